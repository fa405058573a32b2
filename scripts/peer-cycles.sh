#!/usr/bin/env bash
# Differential test of the canned cycles against LinuxCNC's interpreter `rs274` (optional, not
# part of `cargo test`: rs274 is installed by `scripts/peer-rs274.sh` into .peer/).
#
#   bash scripts/peer-rs274.sh            # once
#   bash scripts/peer-cycles.sh [N] [SEED]   # N random programs (default 200), seed (default 1)
#
# Each program is written twice, for fivex (repeat count K, M30) and for rs274 (L, M2), and the
# sequences of X/Y/Z end points of their moves (fivex `interp` motions, rs274's
# STRAIGHT_TRAVERSE/STRAIGHT_FEED) are compared after dropping repeated points.
#
# The programs avoid what FANUC and LinuxCNC do differently by design (`docs/conventions.md`,
# canned cycles): no G73/G83 (peck clearance), no G85/G89 under G98 (retract), one retract mode
# per program and, under G99, one R level (hole positioning when the tool is below R), the
# tool at the initial level when the cycle starts. Any mismatch is printed with both sequences;
# the exit status is the number of mismatching programs (capped at 100).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PEER="$ROOT/.peer/rs274"
[ -x "$PEER" ] || { echo "peer-cycles: run scripts/peer-rs274.sh first" >&2; exit 2; }
FIVEX="$ROOT/target/debug/fivex"
(cd "$ROOT" && cargo build -q -p fivex-server --bin fivex)

N="${1:-200}"
RANDOM="${2:-1}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

rnd() { echo $((RANDOM % ($2 - $1 + 1) + $1)); }   # integer in [$1, $2]
mm() { echo "$(rnd "$1" "$2")."; }                  # the same with a decimal point (mm, not increments)

# One random program on stdout, in fivex's form (K); rs274's form is derived from it.
program() {
    local init retract cycle incremental r z holes h x y
    init=$(rnd 20 60)
    retract=$((RANDOM % 2 ? 98 : 99))
    case $((RANDOM % 4)) in
        0) cycle="G81" ;;
        1) cycle="G82 P$(rnd 1 500)" ;;
        2) cycle="G86 P1" ;;   # rs274 wants a P with G86; fivex keeps it as cycle data
        *) if [ "$retract" = 99 ]; then cycle="G85"; else cycle="G81"; fi ;;
    esac
    incremental=$((RANDOM % 3 == 0))
    r=$(rnd 1 10)
    z=$(rnd -20 -1)
    echo "G21 G17 G90 G94 G40 G49 G80"
    echo "S1000 M03"
    echo "G00 X0. Y0. Z$init."
    if [ "$incremental" = 1 ]; then
        # G91: R from the initial level, Z from R; K holes in a row.
        echo "G91 G$retract $cycle X$(mm -30 30) Y$(mm -30 30) R-$((init - r)). Z-$(mm 1 20) K$(rnd 1 4) F300."
    else
        echo "G$retract $cycle X$(mm -50 50) Y$(mm -50 50) R$r. Z$z. F300."
        holes=$(rnd 0 4)
        for ((h = 0; h < holes; h++)); do
            x=$(mm -50 50)
            y=$(mm -50 50)
            if [ "$retract" = 98 ] && [ $((RANDOM % 2)) = 0 ]; then
                echo "X$x Y$y R$(mm 1 10) Z$(mm -20 -1)"
            else
                echo "X$x Y$y"
            fi
        done
    fi
    echo "G80 G90 G00 Z$init."
}

# The end points of the moves, one "x y z" line each, repeated points dropped.
fivex_points() {
    "$FIVEX" interp "$1" | jq -r 'select(.type == "motion") | .target | "\(.X) \(.Y) \(.Z)"' |
        awk '{ p = sprintf("%.3f %.3f %.3f", $1, $2, $3); if (p != last) print p; last = p }'
}
rs274_points() {
    PEER_TRACE="$2" "$PEER" "$1" >/dev/null
    sed -nE 's/.*STRAIGHT_(TRAVERSE|FEED)\(([^,]+), ([^,]+), ([^,]+),.*/\2 \3 \4/p' "$2" |
        awk '{ p = sprintf("%.3f %.3f %.3f", $1, $2, $3); if (p != last) print p; last = p }'
}

bad=0
for ((i = 1; i <= N; i++)); do
    program > "$work/p.nc"
    echo "M30" >> "$work/p.nc"
    sed -E 's/ K([0-9]+)/ L\1/; s/^M30$/M2/' "$work/p.nc" > "$work/p.ngc"
    fivex_points "$work/p.nc" > "$work/f.txt"
    rs274_points "$work/p.ngc" "$work/trace.txt" > "$work/r.txt"
    # An empty side (an alarm, a parse failure) is a failure too, never an agreement.
    if [ ! -s "$work/f.txt" ] || [ ! -s "$work/r.txt" ] || ! cmp -s "$work/f.txt" "$work/r.txt"; then
        bad=$((bad + 1))
        echo "=== program $i differs"
        cat "$work/p.nc"
        diff "$work/f.txt" "$work/r.txt" | sed 's/^</fivex/; s/^>/rs274/' || true
    fi
done
echo "peer-cycles: $N programs, $bad differ"
exit $((bad > 100 ? 100 : bad))
