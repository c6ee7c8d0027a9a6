#!/usr/bin/env python3
"""Outside suite: turns the YADE curves in bench/outside/raw/ into lab-like datasets in
bench/outside/data/ (the service's plain CSV upload) and writes bench/outside/cases.json,
the manifest of each case's right answer. Seeded: the same raw curves give the same files.

  python3 bench/outside/make_cases.py

Test artefacts are applied here, as post-processing, in forms that differ on purpose from
the product's own (engine/diagnose/test_artefacts.cpp):
  seating: measured strain = soil strain + a closure that the first few kPa of deviator
           close, s (1 - exp(-q_max / q_s)) with q_max the largest deviator so far (the gap
           does not reopen), s = 0.5 %, q_s = 5 kPa, then read on a regular measured-strain
           grid (a flat start of about s);
  membrane: q_measured = q + 4 E_m t_m eps_a / D_c, D_c = D0 sqrt((1 - eps_v) / (1 - eps_a))
           (ASTM D4767 with the specimen's current diameter), E_m = 4 MPa, t_m = 1.5 mm,
           D0 = 100 mm: K_m = 240 kPa, slightly sublinear in eps_a, the same kPa at every sigma3.
Noise (seeded normal): q 0.5 kPa + 0.3 % of the curve's largest q, volumetric strain
0.01 %, creep strain 0.002 %.
"""
import csv, json, math, os, random

HERE = os.path.dirname(os.path.abspath(__file__))
RAW = os.environ.get("OUTSIDE_RAW", os.path.join(HERE, "raw"))
DATA = os.environ.get("OUTSIDE_DATA", os.path.join(HERE, "data"))
SIGMA3 = [50, 100, 200]
STEP_PCT = 0.125  # shear readings every 0.125 % axial strain: 121 per curve to 15 %


def read_raw(name):
    with open(os.path.join(RAW, name)) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def interp(xs, ys, x):
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if xs[i] >= x:
            t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]) if xs[i] > xs[i - 1] else 0.0
            return ys[i - 1] + t * (ys[i] - ys[i - 1])
    return ys[-1]


def monotone(xs, *series):
    """Drops readings whose strain does not increase (the raw strain is monotone in the shear
    but the seating map is only non-decreasing)."""
    out_x, out = [], [[] for _ in series]
    for i, x in enumerate(xs):
        if out_x and x <= out_x[-1]:
            continue
        out_x.append(x)
        for o, s in zip(out, series):
            o.append(s[i])
    return out_x, out


def shear_rows(raw, rng, seating=None, membrane=None, max_pct=15.0):
    e = [r["axial_strain_pct"] for r in raw]
    q = [r["q_kPa"] for r in raw]
    v = [r["volumetric_strain_pct"] for r in raw]
    if membrane:
        em, tm, d0 = membrane
        k = 4.0 * em * tm / d0
        q = [qi + k * (ei / 100) * math.sqrt((1 - vi / 100) / (1 - ei / 100)) ** -1 for qi, ei, vi in zip(q, e, v)]
    if seating:
        s_pct, q_s = seating
        qmax, em_ = 0.0, []
        for ei, qi in zip(e, q):
            qmax = max(qmax, qi)
            em_.append(ei + s_pct * (1 - math.exp(-max(qmax, 0.0) / q_s)))
        e, (q, v) = monotone(em_, q, v)
    qpk = max(q)
    rows = []
    n = int(round(max_pct / STEP_PCT))
    for i in range(n + 1):
        x = i * STEP_PCT
        if x > e[-1] + 1e-9:
            break
        qi = interp(e, q, x) + rng.gauss(0, 0.5 + 0.003 * qpk)
        vi = interp(e, v, x) + rng.gauss(0, 0.01)
        rows.append(("shear", 0, "", None, "", "%.3f" % x, "%.2f" % qi, "%.4f" % vi))
    return rows


def creep_rows(raw, rng, thermal_pct=0.0, period_min=60.0):
    rows = []
    for r in raw:
        t = r["time_min"]
        e = r["axial_strain_pct"] + rng.gauss(0, 0.002)
        if thermal_pct:
            e += thermal_pct * math.sin(2 * math.pi * t / period_min)
        q = r["q_kPa"] + rng.gauss(0, 0.3)
        rows.append(("creep", int(r["stage"]), "%.2f" % r["stress_level"], None, "%.2f" % t, "%.4f" % e, "%.2f" % q, ""))
    return rows


HEADER = "kind,stage,stress_level,confining_kPa,time_min,axial_strain_pct,q_kPa,volumetric_strain_pct"


def write(name, blocks):
    path = os.path.join(DATA, name + ".csv")
    with open(path, "w") as f:
        f.write(HEADER + "\n")
        n = 0
        for s3, rows in blocks:
            for r in rows:
                f.write(",".join([r[0], str(r[1]), r[2], "%g" % s3] + list(r[4:])) + "\n")
                n += 1
    return n


CASES = [
    {"name": "plain_dense", "answer": "none", "runs": "dense",
     "what": "frictional spheres (mu 0.5) consolidated frictionless (dense), no artefact"},
    {"name": "plain_loose", "answer": "none", "runs": "loose",
     "what": "the same spheres consolidated at mu 0.5 (loose), no artefact"},
    {"name": "rolling_weak", "answer": "rolling_resistance", "runs": "roll_weak",
     "what": "CohFrictMat rolling resistance etaRoll 0.05, alphaKr 2 (YADE mechanism)"},
    {"name": "rolling_strong", "answer": "rolling_resistance", "runs": "roll_strong",
     "what": "CohFrictMat rolling resistance etaRoll 0.2, alphaKr 2 (YADE mechanism)"},
    {"name": "seating", "answer": "seating_error", "runs": "dense",
     "what": "plain dense + closure 0.5 % (1 - exp(-q_max / 5 kPa)) added to the strain readings",
     "seating": [0.5, 5.0]},
    {"name": "membrane", "answer": "membrane_compliance", "runs": "dense",
     "what": "plain dense + 4 E_m t_m eps_a / D_c on q (E_m 4 MPa, t_m 1.5 mm, D0 100 mm: 240 kPa per unit strain)",
     "membrane": [4000.0, 1.5, 100.0]},
    {"name": "creep_slow", "answer": "contact_creep_viscosity", "runs": "creep_slow", "creep": True,
     "what": "plain dense shear at 100 kPa + 4 one-day creep stages (S 0.1/0.4/0.6/0.8), friction decay c = 0.01 per decade"},
    {"name": "creep_fast", "answer": "contact_creep_viscosity", "runs": "creep_fast", "creep": True,
     "what": "as creep_slow with c = 0.02 per decade"},
    {"name": "creep_thermal", "answer": "unexplained", "runs": "creep_fast", "creep": True,
     "what": "creep_fast + an hourly sinusoid of 0.03 % on every creep strain reading (outside the catalogue)",
     "thermal_pct": 0.03},
]


def main():
    os.makedirs(DATA, exist_ok=True)
    manifest = []
    for i, c in enumerate(CASES):
        rng = random.Random(1000 + i)
        blocks = []
        if c.get("creep"):
            if not all(os.path.exists(os.path.join(RAW, f)) for f in
                       ("dense_100kPa_shear.csv", c["runs"] + "_100kPa_creep.csv")):
                blocks = None
        if blocks is not None and c.get("creep"):
            blocks.append((100, shear_rows(read_raw("dense_100kPa_shear.csv"), rng)))
            blocks.append((100, creep_rows(read_raw(c["runs"] + "_100kPa_creep.csv"), rng, c.get("thermal_pct", 0.0))))
        elif not c.get("creep"):
            # Every confining pressure whose YADE curve exists (all three when the runs are done).
            for s3 in SIGMA3:
                raw = "%s_%dkPa_shear.csv" % (c["runs"], s3)
                if os.path.exists(os.path.join(RAW, raw)):
                    blocks.append((s3, shear_rows(read_raw(raw), rng, c.get("seating"), c.get("membrane"))))
        if not blocks:
            print("skip", c["name"], "(raw curves missing)")
            entry = {k: v for k, v in c.items() if k not in ("creep",)}
            entry["file"] = None
            entry["note"] = "not generated: its YADE runs are missing from raw/"
            manifest.append(entry)
            continue
        n = write(c["name"], blocks)
        entry = {k: v for k, v in c.items() if k not in ("creep",)}
        entry["file"] = "data/%s.csv" % c["name"]
        entry["rows"] = n
        entry["sigma3_kPa"] = sorted(set(b[0] for b in blocks))
        manifest.append(entry)
        print(c["name"], n, "rows")
    manifest.append({"name": "grain_crushing", "answer": "bond_degradation", "file": None,
                     "what": "missing: grain crushing is not cheap in YADE (clump or sphere replacement); not built"})
    with open(os.path.join(HERE, "cases.json"), "w") as f:
        json.dump({"cases": manifest}, f, indent=1)
        f.write("\n")


def runs_table():
    """The YADE runs' checks (raw/*.json) as a markdown table, for the README."""
    print("| run | sigma3 kPa | porosity | consolidation + relax steps | shear/creep steps | q peak kPa | unbalanced mean / max | lateral kPa min-max | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in sorted(os.listdir(RAW)):
        if not name.endswith(".json"):
            continue
        j = json.load(open(os.path.join(RAW, name)))
        c, cons = j["cfg"], j.get("consolidation", {})
        steps = j.get("steps", 0) - cons.get("consolidation_steps", 0) - cons.get("relax_steps", 0)
        if c["mode"] == "creep":
            steps = j.get("steps", 0)  # counted from the loaded state's iteration
        print("| %s | %g | %.3f | %s + %s | %s | %s | %s | %s | %.0f |" % (
            name[:-5], c["sigma3_kPa"], cons.get("porosity", float("nan")), cons.get("consolidation_steps", "-"),
            cons.get("relax_steps", "-"), steps, "%.1f" % j["q_peak_kPa"] if "q_peak_kPa" in j else "-",
            "%.3f / %.3f" % (j["unbalanced_mean"], j["unbalanced_max"]) if "unbalanced_mean" in j else "-",
            "%.1f-%.1f" % (j["lateral_kPa_min"], j["lateral_kPa_max"]) if "lateral_kPa_min" in j else "-",
            j.get("wall_s", float("nan"))))


if __name__ == "__main__":
    import sys
    if sys.argv[1:] == ["runs"]:
        runs_table()
    else:
        main()
