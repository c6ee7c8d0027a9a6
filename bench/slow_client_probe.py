#!/usr/bin/env python3
# Slow-client probe (issue: hostile input): N connections hold unfinished request heads,
# then 20 GET /health are timed.  python3 bench/slow_client_probe.py build/server/triaxd 330
import socket, subprocess, sys, tempfile, time, re, http.client
triaxd = sys.argv[1]; n = int(sys.argv[2])
with tempfile.TemporaryDirectory() as d:
    p = subprocess.Popen([triaxd, "--port", "0", "--data-dir", d], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    port = int(re.search(r":(\d+)$", p.stdout.readline().strip()).group(1))
    socks = []
    for i in range(n):
        s = socket.create_connection(("127.0.0.1", port)); s.sendall(f"GET /health HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Slow: ".encode()); socks.append(s)
    time.sleep(0.5)
    lat = []
    for i in range(20):
        t = time.time(); c = http.client.HTTPConnection("127.0.0.1", port, timeout=15); c.request("GET", "/health"); r = c.getresponse(); r.read(); lat.append(time.time() - t); c.close()
    lat.sort()
    print(f"{n} unfinished heads: /health 20 requests, median {lat[10]*1000:.1f} ms, max {lat[-1]*1000:.1f} ms")
    p.terminate(); p.wait()
