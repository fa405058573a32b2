#!/usr/bin/env bash
# Seed the corpora from tests/fixtures and run each fuzz target for SECONDS (default 600).
# Needs a nightly toolchain (`rustup toolchain list`) and `cargo install cargo-fuzz`.
set -euo pipefail
cd "$(dirname "$0")"
SECONDS_PER_TARGET="${1:-600}"
TARGETS="${TARGETS:-parse interp}"
cargo +nightly fuzz build -O
for t in $TARGETS; do
  mkdir -p "corpus/$t"
  cp ../tests/fixtures/*.nc "corpus/$t/" 2>/dev/null || true
  cargo +nightly fuzz run -O "$t" "corpus/$t" -- \
    -dict=nc.dict -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -max_total_time="$SECONDS_PER_TARGET" -print_final_stats=1 2>&1 | tee "fuzz-$t.log" | grep -E "^#|stat::|ERROR|SUMMARY|Test unit written|panicked" | tail -40 || true
done
