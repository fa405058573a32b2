#!/usr/bin/env bash
# Checks that the OpenAPI document is exact (issue 19): schemathesis, from PyPI, generates
# requests from `/api-docs/openapi.json` and runs every check against the real `fivex serve` on
# a fresh database on loopback — undocumented status codes, answers that break their schema,
# valid requests refused, invalid ones accepted, server errors. Exits non-zero on any finding.
#
#   scripts/schemathesis.sh                      # 100 examples per operation, seed 1
#   MAX_EXAMPLES=20 scripts/schemathesis.sh      # a quicker one while developing
#   SEED=7 scripts/schemathesis.sh               # other requests (the seed makes a run repeatable)
#
# Needs python3 (with venv) and PyPI once: the venv is kept in target/schemathesis-venv, never
# committed. About a minute on 2 cores once built (~5,800 cases); not part of .ci/run: it needs
# PyPI and is long for every run (docs/api.md, "Checking the document").
set -euo pipefail
cd "$(dirname "$0")/.."

SCHEMATHESIS_VERSION=4.32.5
MAX_EXAMPLES="${MAX_EXAMPLES:-100}"
SEED="${SEED:-1}"
VENV=target/schemathesis-venv

if ! "$VENV/bin/schemathesis" --version 2>/dev/null | grep -q "$SCHEMATHESIS_VERSION"; then
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install -q "schemathesis==$SCHEMATHESIS_VERSION"
fi

cargo build -q -p fivex-server --bin fivex
work="$(mktemp -d)"
server=""
cleanup() {
    if [ -n "$server" ]; then
        kill "$server" 2>/dev/null || true
        wait "$server" 2>/dev/null || true
    fi
    rm -rf "$work"
}
trap cleanup EXIT

# Port 0: the service picks a free port and logs it ("listening on http://…").
RUST_LOG=info ./target/debug/fivex serve --db "$work/fivex.db" --addr 127.0.0.1:0 2>"$work/serve.log" &
server=$!
addr=""
for _ in $(seq 1 300); do
    addr="$(sed -n 's|.*listening on http://\([0-9.:]*\).*|\1|p' "$work/serve.log" | head -n 1)"
    [ -n "$addr" ] && break
    kill -0 "$server" 2>/dev/null || { cat "$work/serve.log" >&2; exit 2; }
    sleep 0.1
done
[ -n "$addr" ] || { echo "fivex serve did not announce its address" >&2; cat "$work/serve.log" >&2; exit 2; }
echo "fivex serve on $addr (log: kept on failure in target/schemathesis-serve.log)"

# The address is an IP, so Host is one the service answers to (docs/api.md, "Security").
# The websockets (`…/stream`) are left out: schemathesis speaks HTTP request and answer, and a
# handshake it completes (101) leaves a websocket on its connection pool. Their handshake
# refusals are tested by the black-box tests (server/tests/it/blackbox/limits.rs, streams.rs).
status=0
"$VENV/bin/schemathesis" --config-file scripts/schemathesis.toml run "http://$addr/api-docs/openapi.json" \
    --checks all \
    --exclude-path-regex '/stream$' \
    --max-examples "$MAX_EXAMPLES" \
    --seed "$SEED" \
    --workers 2 \
    --request-timeout 60 \
    --generation-database none \
    --no-color \
    || status=$?

if [ "$status" -ne 0 ]; then
    cp "$work/serve.log" target/schemathesis-serve.log
fi
exit "$status"
