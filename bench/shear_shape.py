#!/usr/bin/env python3
"""Shape of shear curves written by `triax run` (stress_strain.csv, volumetric.csv).

Usage: bench/shear_shape.py [--mean] RUN_DIR...

Per run: q (kPa) at 2, 5, 10 and 14 % axial strain and the largest q with its strain; the
softening ratio, the smallest q / running maximum over the readings past 2 % (the paper's
shape: >= 0.95), of the raw readings and of the curve smoothed over +-0.5 % strain (the
full-size curve jumps by +-10 % between readings 0.2 % apart); the volumetric strain's
largest contraction (%, contraction positive) with its strain, and its value at 5 and 14 %.
--mean: then the same figures of the runs as mean +- standard deviation, and the softening
ratio and volumetric figures of the mean curve (readings interpolated on a 0.25 % grid).
"""
import statistics
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


def interpolated(curve, eps):
    for (e0, v0), (e1, v1) in zip(curve, curve[1:]):
        if e1 >= eps:
            return v0 + (eps - e0) / max(e1 - e0, 1e-12) * (v1 - v0)
    return curve[-1][1]


def mean_curve(curves, end):
    grid = [0.25 * k for k in range(1, int(end / 0.25) + 1)]
    return [(e, statistics.fmean(interpolated(c, e) for c in curves)) for e in grid]


def spread(values, digits=0):
    sd = statistics.stdev(values) if len(values) > 1 else 0.0
    return f"{statistics.fmean(values):.{digits}f} +- {sd:.{digits}f}"


def main(dirs):
    mean = dirs and dirs[0] == "--mean"
    if mean:
        dirs = dirs[1:]
    qs, evs = [], []
    for d in dirs:
        h, ss = read_csv(os.path.join(d, "stress_strain.csv"))
        _, vv = read_csv(os.path.join(d, "volumetric.csv"))
        qi = h.index("q_kPa")
        q = [(r[0], r[qi]) for r in ss]
        ev = [(r[0], r[1]) for r in vv]
        qs.append(q)
        evs.append(ev)
        e_max, q_max = max(q, key=lambda p: p[1])
        e_c, c = max(ev, key=lambda p: p[1])
        print(f"{os.path.basename(os.path.normpath(d)):20s} q2 {value_at(q, 2):5.0f} q5 {value_at(q, 5):5.0f} "
              f"q10 {value_at(q, 10):5.0f} q14 {value_at(q, 14):5.0f} qmax {q_max:5.0f} at {e_max:5.2f} % "
              f"soft {softening_ratio(q):.3f} smoothed {softening_ratio(smoothed(q)):.3f} | "
              f"ev max {c:5.2f} at {e_c:5.2f} %, at 5 % {value_at(ev, 5):5.2f}, at 14 % {value_at(ev, 14):5.2f}")

    if mean and qs:
        end = min(c[-1][0] for c in qs)
        qm, evm = mean_curve(qs, end), mean_curve(evs, end)
        e_c, c = max(evm, key=lambda p: p[1])
        print(f"mean of {len(qs)}: " + " ".join(f"q{e} {spread([value_at(x, e) for x in qs])}" for e in (2, 5, 10, 14)) +
              f" | mean curve: soft {softening_ratio(qm):.3f}, ev max {c:5.2f} at {e_c:5.2f} %, "
              f"at 14 % {value_at(evm, 14):5.2f} (ev at 14 % per run {spread([value_at(x, 14) for x in evs], 2)})")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
