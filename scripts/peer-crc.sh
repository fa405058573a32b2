#!/usr/bin/env bash
# Cutter compensation C against LinuxCNC's rs274 (the peer of docs/performance.md): prints the
# tool centre end points rs274 computes for the shared programs of docs/cutter-compensation.md
# ("Peer"). Needs `bash scripts/peer-rs274.sh` first. fivex's points for the same programs are
# the hand-worked ones of the crc_* fixtures and engine/tests/it/cutter.rs.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
LCNC="$ROOT/.peer/linuxcnc"
[ -x "$LCNC/usr/bin/rs274" ] || { echo "run scripts/peer-rs274.sh first" >&2; exit 1; }
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
# The standalone rs274 reads its tool table in inches: T1 is 10 mm across (radius 5).
printf 'T1 P1 D0.39370078740157477 Z0 ;\n' > "$WORK/tool.tbl"
head='G21 G17 G40 G90 G94
T1 M6'
printf '%s\n' "$head" 'G00 X20. Y20. Z0.' 'G41 D1 G01 Y0. F1000.' X40. Y40. X0. Y0. X20. 'G40 Y20.' M2 > "$WORK/pocket.ngc"
printf '%s\n' "$head" 'G00 X15. Y20. Z0.' 'G41 D1 G01 Y-7. F1000.' X30. Y7. X0. Y-7. X15. 'G40 Y20.' M2 > "$WORK/slot.ngc"
printf '%s\n' "$head" 'G00 X-20. Y0. Z0.' 'G41 D1 G01 X0. F1000.' X30. 'G03 X40. Y10. R10.' 'G01 Y30.' \
    'G02 X50. Y40. R10.' 'G01 X70.' 'G40 X90.' M2 > "$WORK/arcs.ngc"
for p in pocket slot arcs; do
    echo "== $p"
    printf '1\n' | LD_LIBRARY_PATH="$LCNC/usr/lib:$LCNC/usr/lib/linuxcnc" "$LCNC/usr/bin/rs274" \
        -t "$WORK/tool.tbl" "$WORK/$p.ngc" 2>/dev/null | grep -E 'STRAIGHT_FEED|ARC_FEED' |
        sed -E 's/.*(STRAIGHT_FEED|ARC_FEED)\(([^,]*), ([^,]*),.*/\2 \3/'
done
