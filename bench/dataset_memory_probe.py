#!/usr/bin/env python3
"""Memory of triaxd while large datasets are read back (GET /datasets/{id}).

Starts TRIAXD on a free loopback port with a fresh data directory, uploads one CSV of
about SIZE_MB megabytes, then reads it back: once, CONCURRENT times at once, and
SEQUENTIAL times in a row, printing the process's resident memory (VmRSS, MB) after
each step and its peak (VmHWM).

usage: bench/dataset_memory_probe.py TRIAXD [SIZE_MB=15] [CONCURRENT=10] [SEQUENTIAL=53]
"""
import http.client
import os
import re
import subprocess
import sys
import tempfile
import threading


def rss_mb(pid, key="VmRSS"):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def request(port, method, path, body=None, ctype=None):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
    headers = {"Content-Type": ctype} if ctype else {}
    c.request(method, path, body=body, headers=headers)
    r = c.getresponse()
    data = r.read()
    c.close()
    return r.status, data


def main():
    triaxd = sys.argv[1]
    size_mb = float(sys.argv[2]) if len(sys.argv) > 2 else 15
    concurrent = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    sequential = int(sys.argv[4]) if len(sys.argv) > 4 else 53
    rows = ["confining_kPa,axial_strain_pct,q_kPa"]
    size = 0
    i = 0
    while size < size_mb * 1e6:
        i += 1
        rows.append(f"100,{i * 1e-5:.6f},{80 + (i % 977) * 0.137:.4f}")
        size += len(rows[-1]) + 1
    csv = ("\n".join(rows) + "\n").encode()
    with tempfile.TemporaryDirectory() as data:
        p = subprocess.Popen([triaxd, "--port", "0", "--data-dir", data], stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, text=True)
        try:
            line = p.stdout.readline()
            port = int(re.search(r":(\d+)$", line.strip()).group(1))
            print(f"start: {rss_mb(p.pid):.0f} MB")
            status, body = request(port, "POST", "/datasets?format=csv", csv, "text/csv")
            assert status == 201, (status, body[:300])
            ds = re.search(rb'"id":(\d+)', body).group(1).decode()
            print(f"after upload of {len(csv) / 1e6:.1f} MB CSV: {rss_mb(p.pid):.0f} MB")
            status, answer = request(port, "GET", f"/datasets/{ds}")
            assert status == 200
            print(f"after 1 GET ({len(answer) / 1e6:.1f} MB answer): {rss_mb(p.pid):.0f} MB")
            threads = [threading.Thread(target=request, args=(port, "GET", f"/datasets/{ds}"))
                       for _ in range(concurrent)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            print(f"after {concurrent} concurrent GETs: {rss_mb(p.pid):.0f} MB")
            for _ in range(sequential):
                request(port, "GET", f"/datasets/{ds}")
            print(f"after {sequential} more GETs in a row: {rss_mb(p.pid):.0f} MB "
                  f"(peak {rss_mb(p.pid, 'VmHWM'):.0f} MB)")
        finally:
            p.terminate()
            p.wait()


if __name__ == "__main__":
    main()
