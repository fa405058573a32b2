#!/usr/bin/env python3
"""Generate the interpreter benchmark programs (deterministic, stdlib only).

Usage: python3 bench/programs/gen.py [OUT_DIR] [--moves N] [--iters N]

Writes into OUT_DIR (default: bench/out/ next to this script's parent):
  linear-200k.nc   FANUC syntax (fivex): O0001, 200,000 G01 moves, M30
  linear-200k.ngc  the very same moves for LinuxCNC rs274, M2
  macro-200k.nc    FANUC custom macro B WHILE/DO/END loop, 200,000 iterations
  macro-200k.ngc   the equivalent LinuxCNC o-word while loop, ends (debug,#2)
  indexed-5x.nc    FANUC 3+2 shop program for `fivex run` on head-bc: per face an
                   indexing rapid of B/C, a work offset, a pocket of lines and corner
                   arcs, a G81/G83 drilling pattern, tool changes
  tcp-5x.nc        20,000 G43.5 blocks (tip point and tool vector I J K) for `fivex run`
                   on table-ac: a finishing raster over a dome, the tool along its normal
  cutting-5x.nc    the same raster under cutting point control G43.9 (X/Y/Z the cutting
                   point, `,L2` the dome's normal), the tool leaning 10 degrees toward +X
  nano-5x.nc       200,000 G43.4 blocks for `fivex run` on head-bc (tip X Y Z and B C) of
                   0.1 mm over a dome, in nano smoothing (G05.1 Q3 X0 Y0 Z0 B0 C0)
  tcp4-5x.nc       the very same blocks without nano smoothing
  posture-5x.nc    400 G43.5 P1 blocks (tool posture control) for `fivex run` on head-bc:
                   random points and tool directions 15-60 degrees off +Z, each turned on
                   the great circle between its ends
  arcs-200k.nc     200,000 G02/G03 half circles (radii 0.5-20 mm, every third one helical)
                   for `fivex run` on mill3 at F3000: the arc planner's own cost
and prints the expected final value of #2 for the macro programs.

Coordinates are computed with integer arithmetic only (micrometres), so the
output is byte-identical on every machine and Python version.
"""
import argparse
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_OUT = os.path.normpath(os.path.join(HERE, "..", "out"))

ROW_MOVES = 500          # moves per zig-zag row
ROW_LEN_UM = 200_000     # row length: 200 mm
ROW_PITCH_UM = 250       # Y step between rows: 0.25 mm
Y_ROWS = 320             # rows before the raster starts again from Y=0


def fmt(um):
    """Micrometres -> decimal-point millimetres, always 3 decimals."""
    sign = "-" if um < 0 else ""
    um = abs(um)
    return "%s%d.%03d" % (sign, um // 1000, um % 1000)


def moves(n):
    """Deterministic zig-zag raster with a wobble in Y and a varying depth.

    Yields (N word or None, x_um, y_um, z_um).  Every 10th block gets a
    sequence number N10, N20, ... wrapping after N99990 (5 digits).
    """
    state = 12345
    for i in range(n):
        row, k = divmod(i, ROW_MOVES)
        step = (k + 1) * ROW_LEN_UM // ROW_MOVES
        x = step if row % 2 == 0 else ROW_LEN_UM - step
        x -= ROW_LEN_UM // 2                     # centre on X0
        state = (state * 1103515245 + 12345) & 0x7FFFFFFF   # LCG
        wobble = (state >> 8) % 201 - 100        # -0.100 .. +0.100 mm
        y = (row % Y_ROWS) * ROW_PITCH_UM - 40_000 + wobble
        z = -500 - ((state >> 16) % 1501)        # -0.500 .. -2.000 mm
        nword = None
        if (i + 1) % 10 == 0:
            nword = ((i + 1) // 10 - 1) % 9999 * 10 + 10
        yield nword, x, y, z


def write_linear(path, n, fanuc):
    with open(path, "w", newline="\n") as f:
        if fanuc:
            f.write("O0001\n")
        f.write("G21 G90 G17 G94 G54\n")
        f.write("G00 X0 Y0 Z5.\n")
        f.write("G01 Z0 F1000.\n")
        for nword, x, y, z in moves(n):
            pre = "N%d " % nword if nword is not None else ""
            f.write("%sG01 X%s Y%s Z%s\n" % (pre, fmt(x), fmt(y), fmt(z)))
        f.write("G00 Z5.\n")
        f.write("M30\n" if fanuc else "M2\n")


def write_macro_fanuc(path, iters):
    with open(path, "w", newline="\n") as f:
        f.write("O0002\n")
        f.write("#1=0\n")
        f.write("#2=0\n")
        f.write("WHILE [#1 LT %d] DO 1\n" % iters)
        f.write("#2 = #2 + SIN[#1] + SQRT[ABS[#1]] + ABS[#1 - 100]\n")
        f.write("#1 = #1 + 1\n")
        f.write("END 1\n")
        f.write("#100 = #2\n")
        f.write("M30\n")


def write_macro_ngc(path, iters):
    # LinuxCNC wants a bracketed expression on the right of '=' and
    # evaluates sin[] in degrees, as FANUC SIN[] does.
    with open(path, "w", newline="\n") as f:
        f.write("#1=0\n")
        f.write("#2=0\n")
        f.write("o100 while [#1 lt %d]\n" % iters)
        f.write("#2 = [#2 + sin[#1] + sqrt[abs[#1]] + abs[#1 - 100]]\n")
        f.write("#1 = [#1 + 1]\n")
        f.write("o100 endwhile\n")
        f.write("#100 = #2\n")
        f.write("(debug,#2)\n")
        f.write("M2\n")


def write_indexed(path, faces):
    """A long indexed (3+2) program: `faces` faces, each a rectangular pocket with corner
    arcs in 8 passes and a 5x4 hole pattern (G81 spot, G83 peck). Integer micrometres."""
    with open(path, "w", newline="\n") as f:
        f.write("O0003 (INDEXED 3+2)\n")
        f.write("G21 G17 G40 G49 G80 G90 G94\n")
        for w, (x, y) in enumerate([(0, 0), (5_000, 0), (0, 5_000), (-5_000, 0), (0, -5_000), (5_000, 5_000)]):
            f.write("G10 L2 P%d X%s Y%s Z0.\n" % (w + 1, fmt(x), fmt(y)))
        for face in range(faces):
            tool = face % 3 + 1
            b = [-30_000, 0, 30_000, 45_000, -45_000, 15_000][face % 6]
            c = (face * 37_000) % 360_000
            f.write("N%d T%d M06\n" % (face % 9000 + 1, tool))
            f.write("G%d G43 H%d S8000 M03\n" % (54 + face % 6, tool))
            f.write("G00 B%s C%s\n" % (fmt(b), fmt(c)))
            f.write("G00 X0. Y0. Z50.\n")
            # Pocket: concentric rounded rectangles, 2 mm deep steps.
            for depth in range(1, 3):
                f.write("G00 X0. Y0. Z2.\n")
                f.write("G01 Z-%d. F400.\n" % (2 * depth))
                for k in range(1, 9):
                    hx, hy, r = 5_000 * k, 3_500 * k, 1_000 * k
                    f.write("G01 X%s Y%s F2400.\n" % (fmt(hx - r), fmt(-hy)))
                    f.write("G03 X%s Y%s R%s\n" % (fmt(hx), fmt(-hy + r), fmt(r)))
                    f.write("G01 Y%s\n" % fmt(hy - r))
                    f.write("G03 X%s Y%s R%s\n" % (fmt(hx - r), fmt(hy), fmt(r)))
                    f.write("G01 X%s\n" % fmt(-hx + r))
                    f.write("G03 X%s Y%s R%s\n" % (fmt(-hx), fmt(hy - r), fmt(r)))
                    f.write("G01 Y%s\n" % fmt(-hy + r))
                    f.write("G03 X%s Y%s R%s\n" % (fmt(-hx + r), fmt(-hy), fmt(r)))
                    f.write("G01 X0.\n")
                f.write("G00 Z50.\n")
            # Holes: spot then peck, G99 between holes, G98 at the last.
            for cycle in ("G81 G99 R2. Z-3. F300.", "G83 G99 R2. Z-20. Q4. F250."):
                first = True
                for i in range(5):
                    for j in range(4):
                        x, y = -48_000 + 24_000 * i, -36_000 + 24_000 * j
                        if first:
                            f.write("%s X%s Y%s\n" % (cycle, fmt(x), fmt(y)))
                            first = False
                        else:
                            f.write("X%s Y%s\n" % (fmt(x), fmt(y)))
                f.write("G80\n")
            f.write("G00 Z50. M05\n")
        f.write("G49 G00 B0. C0.\n")
        f.write("M30\n")


DOME_R_UM = 100_000


def dome_raster(blocks):
    """The finishing raster over a paraboloid dome z = -(x^2 + y^2) / 2R (R = 100 mm): rows of
    0.5 mm moves along X, 1 mm apart, `blocks` points (x, y, z) in micrometres."""
    step_um, half_um, pitch_um = 500, 60_000, 1_000
    per_row = 2 * half_um // step_um
    rows = (blocks + per_row - 1) // per_row
    n = 0
    for row in range(rows):
        y = (row - rows // 2) * pitch_um
        for k in range(per_row + 1):
            if n == blocks:
                return
            x = -half_um + k * step_um if row % 2 == 0 else half_um - k * step_um
            yield x, y, -(x * x + y * y) // (2 * DOME_R_UM)
            n += 1


def write_tcp5x(path, blocks):
    """A 5-axis finishing pass for `fivex run` on table-ac: G43.5 over `dome_raster` with the
    tool along the dome's normal, the vector I J K = (x, y, R) unnormalised (the control
    normalises it)."""
    with open(path, "w", newline="\n") as f:
        f.write("O0005\nG90 G54 G00 A0 C0\nG43.5 H1\n")
        for n, (x, y, z) in enumerate(dome_raster(blocks)):
            head, feed = ("G01 ", " F2000.") if n == 0 else ("", "")
            f.write("%sX%s Y%s Z%s I%s J%s K%s%s\n" % (head, fmt(x), fmt(y), fmt(z), fmt(x), fmt(y), fmt(DOME_R_UM), feed))
        f.write("G49\nM30\n")


def write_cutting5x(path, blocks):
    """`write_tcp5x`'s raster under cutting point control: G43.9 H1 D1, X/Y/Z the point where
    the tool touches the dome, `,L2 I J K` its normal (x, y, R), the tool I J K leaning about 10
    degrees from it toward +X: (x + 17.633, y, R) unnormalised (tan 10 deg = 0.17633)."""
    lead_um = 17_633
    with open(path, "w", newline="\n") as f:
        # (The start block's normal is the first point's: with the tool along +Z and the normal
        # +Z a square end mill would start in its singular posture and leave it, PS5464.)
        f.write("O0006\nG90 G54 G00 A0 C0\nG43.9 H1 D1 ,L2 I-60. J-42. K100.\n")
        for n, (x, y, z) in enumerate(dome_raster(blocks)):
            head, feed = ("G01 ", " F2000.") if n == 0 else ("", "")
            f.write(
                "%sX%s Y%s Z%s I%s J%s K%s%s ,L2 I%s J%s K%s\n"
                % (head, fmt(x), fmt(y), fmt(z), fmt(x + lead_um), fmt(y), fmt(DOME_R_UM), feed, fmt(x), fmt(y), fmt(DOME_R_UM))
            )
        f.write("G49\nM30\n")


def write_posture5x(path, blocks):
    """Tool posture control for `fivex run` on head-bc: G43.5 H1 P1 blocks to random points
    (a fixed seed) with random tool directions 15 to 60 degrees off +Z, clear of the singular
    posture (the planner's grid is finest where the axes' way bends: `Grid::fine`)."""
    rnd = random.Random(7)
    with open(path, "w", newline="\n") as f:
        f.write("O0007\nG90 G54 G00 X0 Y0 Z100. B30. C0\nG43.5 H1 P1\nG00 X0 Y0 Z50.\nG01 F3000.\n")
        for _ in range(blocks):
            tilt, azimuth = math.radians(rnd.uniform(15, 60)), math.radians(rnd.uniform(-170, 170))
            i, j, k = math.sin(tilt) * math.cos(azimuth), math.sin(tilt) * math.sin(azimuth), math.cos(tilt)
            x, y, z = rnd.uniform(-40, 40), rnd.uniform(-40, 40), rnd.uniform(20, 50)
            f.write("X%.3f Y%.3f Z%.3f I%.6f J%.6f K%.6f\n" % (x, y, z, i, j, k))
        f.write("G49\nM30\n")


def write_nano5x(path, blocks, smoothing):
    """A 5-axis finishing pass for `fivex run` on head-bc: G43.4 over a dome z = -(x^2 +
    y^2) / 2R in rows of 0.1 mm moves along X, 0.5 mm apart from Y5 on (so the tool never
    stands vertical: C is continuous along a row), the tool along (x + 36.4, y, R) — the
    normal leaning 20 degrees toward +X — as B C angles (B = its angle from Z, C its azimuth),
    with or without nano smoothing. Angles to 4 decimals."""
    step_um, half_um, pitch_um = 100, 60_000, 500
    per_row = 2 * half_um // step_um
    with open(path, "w", newline="\n") as f:
        f.write("O0007\nG90 G54 G00 B0 C0\nG43.4 H1\n")
        n = 0
        row = 0
        while n < blocks:
            y = 5_000 + row * pitch_um
            for k in range(per_row + 1):
                if n == blocks:
                    break
                x = -half_um + k * step_um if row % 2 == 0 else half_um - k * step_um
                z = -(x * x + y * y) // (2 * DOME_R_UM)
                tx, ty, tz = x + 36_400, y, DOME_R_UM
                b = math.degrees(math.atan2(math.hypot(tx, ty), tz))
                c = math.degrees(math.atan2(ty, tx))
                head = "G01 " if n == 0 else ""
                feed = " F2000." if n == 0 else ""
                f.write("%sX%s Y%s Z%s B%.4f C%.4f%s\n" % (head, fmt(x), fmt(y), fmt(z), b, c, feed))
                if n == 0 and smoothing:
                    f.write("G05.1 Q3 X0 Y0 Z0 B0 C0\n")
                n += 1
            row += 1
        if smoothing:
            f.write("G05.1 Q0\n")
        f.write("G49\nM30\n")


def write_arcs(path, arcs):
    """Half circles along X, alternately G02 and G03 (tangent where they meet), turning back
    at X +-100; radii cycle through 0.5-20 mm; every third one also moves Z 0.5 mm (a helix)."""
    radii_um = [1_000, 2_000, 5_000, 10_000, 20_000, 3_000, 500]
    with open(path, "w", newline="\n") as f:
        f.write("O0008\nG90 G17 G54 G00 X-100. Y0 Z5.\nG01 Z-1. F3000.\n")
        x, z, heading = -100_000, -1_000, 1
        for n in range(arcs):
            r = radii_um[n % len(radii_um)]
            if not -100_000 <= x + heading * 2 * r <= 100_000:
                heading = -heading
            x += heading * 2 * r
            word = "G02" if n % 2 == 0 else "G03"
            helix = ""
            if n % 3 == 0:
                z = -1_500 if z == -1_000 else -1_000
                helix = " Z" + fmt(z)
            f.write("%s X%s Y0%s R%s\n" % (word, fmt(x), helix, fmt(r)))
        f.write("G00 Z5.\nM30\n")


def expected_macro(iters):
    acc = 0.0
    for i in range(iters):
        x = float(i)
        acc = acc + math.sin(math.radians(x)) + math.sqrt(abs(x)) + abs(x - 100)
    return acc


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default=DEFAULT_OUT)
    ap.add_argument("--moves", type=int, default=200_000)
    ap.add_argument("--iters", type=int, default=200_000)
    ap.add_argument("--faces", type=int, default=300)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    files = {
        "linear-200k.nc": lambda p: write_linear(p, a.moves, True),
        "linear-200k.ngc": lambda p: write_linear(p, a.moves, False),
        "macro-200k.nc": lambda p: write_macro_fanuc(p, a.iters),
        "macro-200k.ngc": lambda p: write_macro_ngc(p, a.iters),
        "indexed-5x.nc": lambda p: write_indexed(p, a.faces),
        "tcp-5x.nc": lambda p: write_tcp5x(p, 20_000),
        "cutting-5x.nc": lambda p: write_cutting5x(p, 20_000),
        "nano-5x.nc": lambda p: write_nano5x(p, 200_000, True),
        "tcp4-5x.nc": lambda p: write_nano5x(p, 200_000, False),
        "posture-5x.nc": lambda p: write_posture5x(p, 400),
        "arcs-200k.nc": lambda p: write_arcs(p, 200_000),
    }
    for name, writer in files.items():
        path = os.path.join(a.out, name)
        writer(path)
        print("%-16s %10d bytes  %s" % (name, os.path.getsize(path), path))
    print("expected final #2 (macro): %.6f" % expected_macro(a.iters))
    return 0


if __name__ == "__main__":
    sys.exit(main())
