# Prints the triax and YADE curves of bench/cross_engine side by side (q and ev against the
# axial strain, both sampled at the same axial strains) and the largest difference in q
# between 1 % and 10 % axial strain, relative to the YADE q at that strain.
#   python3 bench/cross_engine/compare.py OUT_DIR
import csv, sys

def read(path):
    with open(path) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]

def at(rows, ea, key):
    for a, b in zip(rows, rows[1:]):
        if a["axial_strain_pct"] <= ea <= b["axial_strain_pct"]:
            t = (ea - a["axial_strain_pct"]) / max(b["axial_strain_pct"] - a["axial_strain_pct"], 1e-12)
            return a[key] + t * (b[key] - a[key])
    return None

d = sys.argv[1]
tx, yd = read(d + "/triax_curve.csv"), read(d + "/yade_curve.csv")
print("%8s %12s %12s %10s %10s" % ("ea_pct", "q_triax_kPa", "q_yade_kPa", "ev_triax", "ev_yade"))
worst, worst_at = 0.0, None
ea = 0.0
while ea <= 10.0 + 1e-9:
    qt, qy = at(tx, ea, "q_kPa"), at(yd, ea, "q_kPa")
    et, ey = at(tx, ea, "volumetric_strain_pct"), at(yd, ea, "volumetric_strain_pct")
    if None not in (qt, qy, et, ey):
        print("%8.2f %12.2f %12.2f %10.3f %10.3f" % (ea, qt, qy, et, ey))
        if ea >= 1.0 - 1e-9 and abs(qy) > 0:
            rel = abs(qt - qy) / abs(qy)
            if rel > worst:
                worst, worst_at = rel, ea
    ea += 0.5
if worst_at is None:
    print("no common range between 1 % and 10 % axial strain")
else:
    print("largest q difference between 1 %% and 10 %%: %.1f %% of YADE's q (at ea = %.1f %%)" % (100 * worst, worst_at))
