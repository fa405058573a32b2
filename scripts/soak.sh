#!/usr/bin/env bash
# The soak (issue 18): 1,000 controllers running for 10 minutes on a fresh `fivex serve`, each
# with a position stream, ten fleet stream subscribers and a writer of variables, measured by
# `fivex-load` (server/src/bin/fivex-load.rs): frame lag, frames per subscriber per second, CPU,
# the service's memory every 30 s (flat: it may grow less than 50 MB), and no error (no refused
# request, no stream that ends). Exits as `fivex-load` does: 0 when all of that holds.
#
#   scripts/soak.sh                       # the soak: 1,000 controllers, 600 s
#   CONTROLLERS=100 MEASURE=60 scripts/soak.sh   # a short one while developing
#
# It loads both cores for its whole length: run it while nothing else builds.
set -euo pipefail
cd "$(dirname "$0")/.."

CONTROLLERS="${CONTROLLERS:-1000}"
MEASURE="${MEASURE:-600}"
WARMUP="${WARMUP:-30}"

cargo build --release -q -p fivex-server --bins
exec ./target/release/fivex-load \
    --controllers "$CONTROLLERS" \
    --seconds "$MEASURE" \
    --warmup "$WARMUP" \
    --fleet-subscribers 10 \
    --writes-per-s 20 \
    --sample-every 30 \
    --max-growth-mb 50
