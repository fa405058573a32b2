#!/bin/bash
# Fleet benchmark (docs/performance.md, "Fleet runs"): 40 machines (4 presets and 16 library
# machines, twice) running bench/out/fleet-5x.nc, as one `fivex fleet` or as 40 `fivex run`
# one after another.
#   python3 bench/programs/fleet.py bench/out 20000
#   bench/fleet.sh fleet|fleet1|serial      (F=path/to/fivex, default target/release/fivex)
set -e
here=$(cd "$(dirname "$0")/.." && pwd)
F=${F:-$here/target/release/fivex}
P=${P:-$here/bench/out/fleet-5x.nc}
M=$here/machines
LIB="cradle-bc-110 hmc-trunnion-ab horizontal-mixed-ab mixed-ac-swivel mixed-bc-200 mixed-nutating-b45
     nutating-head-b45 nutating-table-b45 trunnion-ac-120 trunnion-ac-compact trunnion-ac-offset-c
     mixed-bc-singular-5deg mixed-bc-one-side fork-head-bc head-bc-offset-pivot gantry-head-ac"
PRESETS="head-bc table-ac table-bc mixed-bc"
args=()
for _ in 1 2; do
  for p in $PRESETS; do args+=(--preset "$p"); done
  for m in $LIB; do args+=(--machine "$M/$m.json"); done
done
# A parameter list runs in its own dialect in the fleet; `fivex run` is told so.
dialect() { grep -q '"dialect": "syntec"' "$1" && echo syntec || echo fanuc; }
case "$1" in
  serial)
    for _ in 1 2; do
      for p in $PRESETS; do "$F" run "$P" --preset "$p" > /dev/null || true; done
      for m in $LIB; do "$F" run "$P" --machine "$M/$m.json" --dialect "$(dialect "$M/$m.json")" > /dev/null || true; done
    done ;;
  fleet) "$F" fleet "$P" "${args[@]}" -q > /dev/null || true ;;
  fleet1) "$F" fleet "$P" "${args[@]}" -q --jobs 1 > /dev/null || true ;;
  *) echo "usage: $0 fleet|fleet1|serial" >&2; exit 2 ;;
esac
