#!/usr/bin/env bash
# The whole test suite: every Rust test, then the dashboard's (scripts/web-test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== cargo test --workspace"
cargo test --workspace
scripts/web-test.sh
