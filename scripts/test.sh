#!/usr/bin/env bash
# The whole test suite: every Rust test (the service's on PostgreSQL too: a server of its own
# per test, from Debian's postgresql, installed if missing; the distributed fleet's on a
# `nats-server -js` of their own, from Debian's nats-server, installed likewise; the cluster of
# docker-compose.yml behind Debian's nginx, installed likewise), the comparisons with LinuxCNC's
# rs274 (ignored by a plain `cargo test`: they need the peer, which scripts/peer-rs274.sh fetches) and of NURBS with
# SciPy (ignored likewise: they need python3-scipy), a build check of the fuzz targets, then the
# dashboard's (scripts/web-test.sh). The service's `/metrics` tests read the scrape with Python's
# prometheus_client parser too (Debian's python3-prometheus-client, installed here if missing: a
# plain `cargo test` without it fails those tests).
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== Python's prometheus_client for the /metrics tests (Debian's python3-prometheus-client, installed if missing)"
if ! /usr/bin/python3 -c 'import prometheus_client.parser' 2>/dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-prometheus-client >/dev/null
fi
echo "== PostgreSQL for the service's tests on it (Debian's postgresql, installed if missing)"
if ! ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 && ! command -v initdb >/dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq postgresql >/dev/null
fi
echo "== NATS for the distributed fleet's tests (Debian's nats-server, installed if missing)"
if ! command -v nats-server >/dev/null && [ ! -x /usr/sbin/nats-server ]; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nats-server >/dev/null
fi
echo "== nginx for the test of docker-compose.yml's cluster behind its proxy (Debian's nginx, installed if missing)"
if [ ! -x /usr/sbin/nginx ] && ! command -v nginx >/dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nginx >/dev/null
fi
echo "== the compose files, validated by Docker Compose itself (Debian's docker-compose, installed if missing; no Docker daemon needed)"
if ! command -v docker-compose >/dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq docker-compose >/dev/null
fi
docker-compose -f docker-compose.yml config -q
docker-compose -f docker-compose.single.yml config -q
echo "== the shop-floor tests' Python clients (asyncua, lxml from PyPI in target/venv)"
scripts/python-venv.sh
echo "== cargo test --workspace"
cargo test --workspace
echo "== cutter compensation against LinuxCNC's rs274 (the peer, fetched from Debian's archive)"
bash scripts/peer-rs274.sh
cargo test -p fivex-e2e --test it peer_crc -- --ignored
echo "== NURBS (G06.2) against SciPy's B-splines (Debian's python3-scipy, installed if missing)"
if ! /usr/bin/python3 -c 'import scipy' 2>/dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-scipy >/dev/null
fi
cargo test -p fivex-e2e --test it nurbs_scipy -- --ignored
echo "== the fuzz targets build (a crate outside the workspace: nothing else compiles them)"
cargo check --manifest-path fuzz/Cargo.toml --bins
scripts/web-test.sh
