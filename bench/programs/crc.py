#!/usr/bin/env python3
"""Cutter compensation speed programs (issue 20, docs/performance.md).

Usage: python3 bench/programs/crc.py [OUT_DIR]

Writes into OUT_DIR (default: bench/out/):

  contour-100k.nc       a 100,000-block polygon of 1,000 sides per turn round a circle of
                        radius 50 (100 turns), started and left tangentially;
  contour-100k-g42.nc   the same with G42 D1 (radius 5, outside) on and G40 at the end;
  cam-100k.nc           a CAM-style profile: 50 depth passes (0.5 mm each, 25 mm deep) round
                        the outside of a 120 x 90 mm part whose outline mixes free-form edges
                        cut into short G01 segments (0.11-0.12 mm, as CAM linearises a
                        spline), G02/G03 corner and notch arcs given by I/J, chamfers and sharp
                        corners (inside and outside, obtuse), at F1500; per pass an approach,
                        a plunge, a lead-in, the contour, a lead-out and a retract: 2,000
                        blocks a pass, 100,005 in all;
  cam-100k-g41.nc       the very same blocks with G41 D1 on each lead-in and G40 on each
                        lead-out (climb milling, the tool outside the part; the default tool
                        table's radius 5 mm, `fivex run` without --tools: no interference).

Coordinates are printed to 1 um; the free-form edges use math.sin, so a different libm could
in principle move a last digit (the figures in docs/performance.md are from these files as
generated on the benchmark machine).
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


# The CAM profile -------------------------------------------------------------------------

PASSES = 50
DEPTH_STEP = 0.5          # mm per pass
HALF_BOTTOM = 450         # segments of each half of the bottom edge (a parabola)
LEFT_WAVE = 543           # segments of the left edge (two sine waves)
RIGHT_WAVE = 542          # segments of the right edge (one and a half waves)


def f3(v):
    """A coordinate in mm to 1 um, FANUC decimal point style ("12.", "-0.5", "3.142")."""
    s = "%.3f" % v
    if s in ("-0.000",):
        s = "0.000"
    s = s.rstrip("0")
    return s


def contour():
    """The part's outline, travelled clockwise from the bottom's middle (0, -45): a list of
    blocks (text without the pass-dependent parts), tangent-continuous but at its chamfer, its
    notch and one sharp corner (outside corners); the tool is on the left (outside) for G41.
    Where the outline is concave its radius is at least 10 mm (the tool's 5 fit)."""
    out = []

    def bottom(x):
        # y = -40 - 5 cos^2(pi x / 100): -45 at the middle, -40 and level at x = +-50.
        return -40.0 - 5.0 * math.cos(math.pi * x / 100.0) ** 2

    # Bottom edge, left half, from x = 0 to -50.
    for i in range(1, HALF_BOTTOM + 1):
        x = -50.0 * i / HALF_BOTTOM
        out.append("%sX%s Y%s" % ("G01 " if i == 1 else "", f3(x), f3(bottom(x))))
    # Bottom-left corner: clockwise quarter circle R10 about (-50, -30).
    out.append("G02 X-60. Y-30. I0 J10.")
    # Left edge: two outward bumps of 2.5 mm, x = -60 - 2.5 (1 - cos(2 pi (y + 30) / 30)) / 2.
    for i in range(1, LEFT_WAVE + 1):
        y = -30.0 + 60.0 * i / LEFT_WAVE
        x = -60.0 - 1.25 * (1.0 - math.cos(2 * math.pi * (y + 30.0) / 30.0))
        out.append("%sX%s Y%s" % ("G01 " if i == 1 else "", f3(x), f3(y)))
    # Chamfer and top edge up to a semicircular notch R12 (G03 about (-8, 40)), then on.
    out.append("X-50. Y40.")
    out.append("X-20.")
    out.append("G03 X4. Y40. I12. J0")
    out.append("G01 X50.")
    # Top-right corner, then the right edge, one and a half waves of 2 mm, down to (62, -30).
    out.append("G02 X60. Y30. I0 J-10.")
    for i in range(1, RIGHT_WAVE + 1):
        y = 30.0 - 60.0 * i / RIGHT_WAVE
        x = 60.0 + 1.0 * (1.0 - math.cos(3 * math.pi * (30.0 - y) / 60.0))
        out.append("%sX%s Y%s" % ("G01 " if i == 1 else "", f3(x), f3(y)))
    # Straight down to a sharp outside corner at (62, -40), then the bottom edge's right half.
    out.append("Y-40.")
    out.append("X50.")
    for i in range(1, HALF_BOTTOM + 1):
        x = 50.0 - 50.0 * i / HALF_BOTTOM
        out.append("X%s Y%s" % (f3(x), f3(bottom(x))))
    return out


def cam_program(comp):
    ring = contour()
    lines = ["O0020 (CAM PROFILE, %d PASSES)" % PASSES, "G21 G17 G40 G49 G80 G90 G94 G54", "G00 Z5. S8000 M03"]
    for k in range(PASSES):
        z = -DEPTH_STEP * (k + 1)
        # Approach, plunge beside the part, a straight lead-in (the start-up block) and a
        # tangential quarter-circle lead-in arc R10; the same way out.
        lines.append("G00 X10. Y-65.")
        lines.append("G01 Z%s F300." % f3(z))
        lines.append(("G41 D1 " if comp else "") + "G01 Y-55. F1500.")
        lines.append("G03 X0 Y-45. I-10. J0")
        lines.extend(ring)
        lines.append("G03 X-10. Y-55. I0 J-10.")
        lines.append(("G40 " if comp else "") + "G01 Y-65.")
        lines.append("G00 Z5.")
    lines.append("M05")
    lines.append("M30")
    return "\n".join(lines) + "\n"


os.makedirs(OUT, exist_ok=True)
files = [
    ("contour-100k.nc", lambda: program(False)),
    ("contour-100k-g42.nc", lambda: program(True)),
    ("cam-100k.nc", lambda: cam_program(False)),
    ("cam-100k-g41.nc", lambda: cam_program(True)),
]
for name, text in files:
    path = os.path.join(OUT, name)
    with open(path, "w", newline="\n") as f:
        f.write(text())
    print("%-20s %10d bytes  %s" % (name, os.path.getsize(path), path))
