#!/usr/bin/env bash
# The whole test suite: every Rust test, a build check of the fuzz targets, then the dashboard's
# (scripts/web-test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== cargo test --workspace"
cargo test --workspace
echo "== the fuzz targets build (a crate outside the workspace: nothing else compiles them)"
cargo check --manifest-path fuzz/Cargo.toml --bins
scripts/web-test.sh
