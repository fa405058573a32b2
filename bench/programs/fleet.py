#!/usr/bin/env python3
"""The fleet benchmark program (docs/performance.md, "Fleet runs"): a 5-axis finishing pass
over a dome with G43.5 tool vectors tilted up to 20 degrees, N blocks, deterministic.

    python3 bench/programs/fleet.py [OUT_DIR] [N]     # writes OUT_DIR/fleet-5x.nc (default bench/out, 3000)
"""
import math
import os
import sys

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "out")
n = int(sys.argv[2]) if len(sys.argv) > 2 else 3000
os.makedirs(out, exist_ok=True)
lines = ["%", "O7000 (FLEET BENCHMARK: G43.5 DOME FINISH)", "G90 G17 G21 G40 G49 G80",
         "G10 L2 P1 X0. Y0. Z0.", "G54 G00 X0. Y0.", "G43.5 H1 X0. Y0. Z60.", "G01 Z30. F3000."]
for k in range(n):
    u = k / n
    phi = math.radians(7.2 * k)
    r = 5.0 + 35.0 * u
    x, y = r * math.cos(phi), r * math.sin(phi)
    z = 30.0 - 10.0 * u * u
    tilt = math.radians(20.0 * u)
    i, j, kk = math.sin(tilt) * math.cos(phi), math.sin(tilt) * math.sin(phi), math.cos(tilt)
    lines.append(f"X{x:.3f} Y{y:.3f} Z{z:.3f} I{i:.4f} J{j:.4f} K{kk:.4f}")
lines += ["G00 Z60.", "G49", "M30", "%"]
with open(os.path.join(out, "fleet-5x.nc"), "w") as f:
    f.write("\n".join(lines) + "\n")
