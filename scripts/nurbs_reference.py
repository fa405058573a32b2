#!/usr/bin/env python3
"""An independent NURBS evaluator for fivex's G06.2 tests (SciPy's B-splines).

Reads one JSON object on stdin:
  {"degree": p, "knots": [...], "points": [[x, y, z], ...], "weights": [...],
   "samples": [[x, y, z], ...], "at": [u, ...]}
and prints {"max": d, "ends": [[x, y, z], [x, y, z]], "derivatives": [[C, C', C''], ...]}: the
largest distance from a sample to the rational curve C = sum(N_i w_i P_i) / sum(N_i w_i) that
SciPy evaluates (the nearest point of each sample found on a dense grid, then refined by a
bounded scalar minimisation), the curve's two ends, and at each parameter of "at" the curve's
point and its first and second derivatives (the quotient rule on SciPy's derivatives of the
numerator and the denominator). "samples" and "at" are each optional. Used by
`tests/tests/it/nurbs_scipy.rs` (scripts/test.sh installs python3-scipy).
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

    def derivatives(u):
        # Evaluated piece by piece (nu=2): a spline whose interior knots repeat has no global
        # second derivative SciPy would build, but each piece has one.
        c = at(u)
        d1 = tangent(u)
        d2 = (num(u, nu=2) - 2.0 * dden(u) * d1 - den(u, nu=2) * c) / den(u)
        return [c.tolist(), d1.tolist(), d2.tolist()]

    grid = np.linspace(lo, hi, 20001)
    curve = at(grid)
    worst = 0.0
    for s in np.array(job.get("samples", []), dtype=float):
        # The nearest point: where (C(u) - s) is perpendicular to the curve, bracketed by the
        # grid points either side of the nearest one (or a grid end).
        k = int(np.argmin(np.linalg.norm(curve - s, axis=1)))
        a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
        foot = lambda u: float(np.dot(at(u) - s, tangent(u)))
        candidates = [a, b]
        if foot(a) * foot(b) < 0:
            candidates.append(brentq(foot, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200))
        worst = max(worst, min(float(np.linalg.norm(at(u) - s)) for u in candidates))
    out = {"max": worst, "ends": [at(lo).tolist(), at(hi).tolist()]}
    out["derivatives"] = [derivatives(float(u)) for u in job.get("at", [])]
    print(json.dumps(out))


if __name__ == "__main__":
    sys.exit(main())
