#!/usr/bin/env python3
"""Outside suite runner (never run by CI): uploads every case of bench/outside/cases.json to
a triaxd, runs the diagnosis with the default options and the preset B scheme
({"scheme": {"preset": "B"}}, as the issue's users did), waits, and prints one table.

  python3 bench/outside/run_suite.py [--url http://127.0.0.1:8080] [--nice 19]
        [--triaxd build/server/triaxd] [--cases plain_dense,seating] [--analytic]
        [--out bench/outside/results.json]

Without --url it starts its own triaxd on 127.0.0.1 (a free port, a temporary data dir)
under nice -n NICE (19) and stops it at the end. Diagnoses run one after another (each uses the
service's default concurrency, 2 engine threads). --analytic adds the analytic stand-in
row (build/bench/diagnose_outside_data case=plain, the bench's own options, not the
service's). Results are appended to --out as they finish, so a long suite can be stopped
and its finished rows kept.
"""
import argparse, json, os, socket, subprocess, sys, tempfile, time, urllib.error, urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def call(url, method="GET", body=None, ctype="application/json"):
    data = None
    if body is not None:
        data = body if isinstance(body, bytes) else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method, headers={"Content-Type": ctype})
    try:
        with urllib.request.urlopen(req, timeout=120) as r:
            return r.status, json.loads(r.read() or b"null")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"null")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_triaxd(binary, nice):
    port = free_port()
    data_dir = tempfile.mkdtemp(prefix="outside_suite_")
    proc = subprocess.Popen(["nice", "-n", str(nice), binary, "--host", "127.0.0.1", "--port", str(port),
                             "--data-dir", data_dir, "--web-dir", os.path.join(ROOT, "web"),
                             "--schema-dir", os.path.join(ROOT, "schema")],
                            stdout=open(os.path.join(data_dir, "triaxd.log"), "w"), stderr=subprocess.STDOUT)
    url = "http://127.0.0.1:%d" % port
    for _ in range(100):
        try:
            call(url + "/presets")
            return proc, url, data_dir
        except Exception:
            time.sleep(0.2)
    proc.terminate()
    raise RuntimeError("triaxd did not start (log in %s)" % data_dir)


def pooled(report, key):
    return report.get(key)


def run_case(url, case, body):
    with open(os.path.join(HERE, case["file"]), "rb") as f:
        st, ds = call(url + "/datasets?name=%s&format=csv" % case["name"], "POST", f.read(), "text/csv")
    if st != 201:
        return {"case": case["name"], "answer": case["answer"], "verdict": "upload refused: %s %s" % (st, ds)}
    t0 = time.time()
    st, dg = call(url + "/datasets/%d/diagnose" % ds["id"], "POST", body)
    if st != 202:
        return {"case": case["name"], "answer": case["answer"], "verdict": "diagnose refused: %s %s" % (st, dg)}
    plan = dg.get("plan") or {}
    print("  %s: dataset %d, diagnosis %d, plan %s runs, %s min" %
          (case["name"], ds["id"], dg["id"], plan.get("model_runs_at_most"), plan.get("minutes_estimate")), flush=True)
    last = -1
    while True:
        time.sleep(10)
        st, d = call(url + "/diagnoses/%d" % dg["id"])
        if d.get("progress_pct") is not None and int(d["progress_pct"]) // 10 != last:
            last = int(d["progress_pct"]) // 10
            print("    %s %.0f %% (%.0f s)" % (d["status"], d["progress_pct"], time.time() - t0), flush=True)
        if d["status"] not in ("queued", "running"):
            break
    wall = time.time() - t0
    rep = d.get("report") or {}
    noise = rep.get("noise_floor") or {}
    return {"case": case["name"], "answer": case["answer"], "status": d["status"],
            "outcome": rep.get("outcome"), "chosen_effect": rep.get("chosen_effect"), "effects": rep.get("effects"),
            "verdict": rep.get("verdict", d.get("error")), "nrmse_before": rep.get("nrmse_before"),
            "nrmse_after": rep.get("nrmse_after"), "tolerance": noise.get("tolerance_nrmse"),
            "runs": rep.get("runs_used"), "failed_runs": rep.get("failed_runs"),
            "unreached_after": rep.get("unreached_after"), "wall_s": wall, "diagnosis_id": dg["id"],
            "parameters": rep.get("parameters"), "plan_runs_at_most": plan.get("model_runs_at_most"),
            "plan_minutes": plan.get("minutes_estimate"), "report": rep}


def analytic_row():
    exe = os.path.join(ROOT, "build", "bench", "diagnose_outside_data")
    if not os.path.exists(exe):
        return {"case": "analytic_plain", "answer": "none", "verdict": "skipped: %s not built" % exe}
    t0 = time.time()
    out = subprocess.run(["nice", "-n", "19", exe, "case=plain"], capture_output=True, text=True)
    return {"case": "analytic_plain", "answer": "none", "verdict": out.stdout.strip().splitlines()[-1:] or out.stderr,
            "wall_s": time.time() - t0}


def pct(x):
    return "-" if x is None else "%.1f" % (100 * x)


def table(rows):
    lines = ["| case | right answer | verdict (chosen effect / outcome) | NRMSE before -> after % | tolerance % | runs | wall s |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        got = r.get("chosen_effect") or "-"
        if r.get("outcome"):
            got = "%s / %s" % (got, r["outcome"])
        else:
            got = str(r.get("verdict"))
        lines.append("| %s | %s | %s | %s -> %s | %s | %s | %s |" % (
            r["case"], r["answer"], got, pct(r.get("nrmse_before")), pct(r.get("nrmse_after")),
            pct(r.get("tolerance")), r.get("runs", "-"), "%.0f" % r["wall_s"] if r.get("wall_s") else "-"))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--url")
    ap.add_argument("--triaxd", default=os.path.join(ROOT, "build", "server", "triaxd"))
    ap.add_argument("--cases", default="")
    ap.add_argument("--analytic", action="store_true")
    ap.add_argument("--out", default=os.path.join(HERE, "results.json"))
    ap.add_argument("--nice", type=int, default=19, help="niceness of the triaxd it starts")
    a = ap.parse_args()
    cases = json.load(open(os.path.join(HERE, "cases.json")))["cases"]
    if a.cases:
        by_name = {c["name"]: c for c in cases}
        cases = [by_name[n] for n in a.cases.split(",") if n in by_name]  # in the order asked
    missing = [{"case": c["name"], "answer": c["answer"], "verdict": "no dataset (%s)" % c.get("note", c.get("what"))}
               for c in cases if not c.get("file")]
    cases = [c for c in cases if c.get("file")]
    proc = None
    url = a.url
    if not url:
        proc, url, data_dir = start_triaxd(a.triaxd, a.nice)
        print("triaxd at %s, data in %s" % (url, data_dir), flush=True)
    body = {"scheme": {"preset": "B"}}
    rows = []
    try:
        for c in cases:
            rows.append(run_case(url, c, body))
            with open(a.out, "a") as f:
                f.write(json.dumps(rows[-1]) + "\n")
            print(table(rows[-1:]).splitlines()[-1], flush=True)
        if a.analytic:
            rows.append(analytic_row())
    finally:
        if proc:
            proc.terminate()
            proc.wait()
    print(table(rows + missing))


if __name__ == "__main__":
    main()
