#!/usr/bin/env python3
"""Cutter compensation speed programs (issue 20, docs/performance.md).

Writes into OUT_DIR (default: bench/out/): contour-100k.nc, a 100,000-block polygon of
1,000 sides per turn round a circle of radius 50 (100 turns), started and left tangentially,
and contour-100k-g42.nc, the same with G42 D1 (radius 5, outside) on and G40 at the end.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(HERE, "..", "out"))


def program(comp):
    lines = ["G21 G17 G40 G90 G94", "G10 L12 P1 R5.", "G00 X50. Y-20. Z0."]
    lines.append(("G42 D1 " if comp else "") + "G01 X50. Y0. F3000.")
    for k in range(1, 100001):
        a = 2 * math.pi * k / 1000
        lines.append("X%.4f Y%.4f" % (50 * math.cos(a), 50 * math.sin(a)))
    lines.append(("G40 " if comp else "") + "G01 X50. Y20.")
    lines.append("M30")
    return "\n".join(lines) + "\n"


os.makedirs(OUT, exist_ok=True)
for name, comp in [("contour-100k.nc", False), ("contour-100k-g42.nc", True)]:
    with open(os.path.join(OUT, name), "w") as f:
        f.write(program(comp))
