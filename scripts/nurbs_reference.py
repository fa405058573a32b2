#!/usr/bin/env python3
"""An independent NURBS evaluator for fivex's G06.2 tests (SciPy's B-splines).

Reads one JSON object on stdin:
  {"degree": p, "knots": [...], "points": [[x, y, z], ...], "weights": [...],
   "samples": [[x, y, z], ...]}
and prints {"max": d, "ends": [[x, y, z], [x, y, z]]}: the largest distance from a sample to the
rational curve sum(N_i w_i P_i) / sum(N_i w_i) that SciPy evaluates (the nearest point of each
sample found on a dense grid, then refined by a bounded scalar minimisation), and the curve's
two ends. Used by `tests/tests/it/nurbs_scipy.rs` (scripts/test.sh installs python3-scipy).
"""
import json
import sys

import numpy as np
from scipy.interpolate import BSpline
from scipy.optimize import brentq


def main():
    job = json.load(sys.stdin)
    p = job["degree"]
    t = np.array(job["knots"], dtype=float)
    w = np.array(job["weights"], dtype=float)
    pts = np.array(job["points"], dtype=float)
    num = BSpline(t, pts * w[:, None], p)
    den = BSpline(t, w, p)
    lo, hi = t[p], t[-p - 1]

    dnum, dden = num.derivative(), den.derivative()

    def at(u):
        return num(u) / np.expand_dims(den(u), -1)

    def tangent(u):
        d = den(u)
        return (dnum(u) * d - num(u) * dden(u)) / (d * d)

    grid = np.linspace(lo, hi, 20001)
    curve = at(grid)
    worst = 0.0
    for s in np.array(job["samples"], dtype=float):
        # The nearest point: where (C(u) - s) is perpendicular to the curve, bracketed by the
        # grid points either side of the nearest one (or a grid end).
        k = int(np.argmin(np.linalg.norm(curve - s, axis=1)))
        a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
        foot = lambda u: float(np.dot(at(u) - s, tangent(u)))
        candidates = [a, b]
        if foot(a) * foot(b) < 0:
            candidates.append(brentq(foot, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200))
        worst = max(worst, min(float(np.linalg.norm(at(u) - s)) for u in candidates))
    print(json.dumps({"max": worst, "ends": [at(lo).tolist(), at(hi).tolist()]}))


if __name__ == "__main__":
    sys.exit(main())
