#!/usr/bin/env python3
"""Shape of shear curves written by `triax run` (stress_strain.csv, volumetric.csv).

Usage: bench/shear_shape.py RUN_DIR...

Per run: q (kPa) at 2, 5, 10 and 14 % axial strain and the largest q with its strain; the
softening ratio, the smallest q / running maximum over the readings past 2 % (the paper's
shape: >= 0.95), of the raw readings and of the curve smoothed over +-0.5 % strain (the
full-size curve jumps by +-10 % between readings 0.2 % apart); the volumetric strain's
largest contraction (%, contraction positive) with its strain, and its value at 5 and 14 %.
"""
import os
import sys


def read_csv(path):
    rows = [l.strip().split(",") for l in open(path) if l.strip() and not l.startswith("#")]
    return rows[0], [[float(x) for x in r] for r in rows[1:]]


def value_at(curve, eps):
    """Value of the first reading at or past strain eps (the last one if none)."""
    for e, v in curve:
        if e >= eps:
            return v
    return curve[-1][1]


def softening_ratio(curve):
    running, worst = 0.0, float("inf")
    for e, q in curve:
        running = max(running, q)
        if e > 2.0:
            worst = min(worst, q / running)
    return worst


def smoothed(curve, half_width=0.5):
    return [(e, sum(q for x, q in curve if abs(x - e) <= half_width) /
             sum(1 for x, _ in curve if abs(x - e) <= half_width)) for e, _ in curve]


def main(dirs):
    for d in dirs:
        h, ss = read_csv(os.path.join(d, "stress_strain.csv"))
        _, vv = read_csv(os.path.join(d, "volumetric.csv"))
        qi = h.index("q_kPa")
        q = [(r[0], r[qi]) for r in ss]
        ev = [(r[0], r[1]) for r in vv]
        e_max, q_max = max(q, key=lambda p: p[1])
        e_c, c = max(ev, key=lambda p: p[1])
        print(f"{os.path.basename(os.path.normpath(d)):20s} q2 {value_at(q, 2):5.0f} q5 {value_at(q, 5):5.0f} "
              f"q10 {value_at(q, 10):5.0f} q14 {value_at(q, 14):5.0f} qmax {q_max:5.0f} at {e_max:5.2f} % "
              f"soft {softening_ratio(q):.3f} smoothed {softening_ratio(smoothed(q)):.3f} | "
              f"ev max {c:5.2f} at {e_c:5.2f} %, at 5 % {value_at(ev, 5):5.2f}, at 14 % {value_at(ev, 14):5.2f}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
