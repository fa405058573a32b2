#!/usr/bin/env bash
# The cluster under load (docs/performance.md, "A cluster under load"): a PostgreSQL (Debian's,
# initdb into a temporary directory) and a `nats-server -js` of its own on loopback, then
# `fivex-load` once per line of RUNS, each on a fresh database: one process on SQLite, one node,
# three nodes with each stream opened through the hosting node, and three nodes with every
# stream relayed by another node. Prints one JSON report per run. LOGS=DIR keeps every node's log.
#
#   cargo build --release -p fivex-server
#   bash bench/cluster.sh [CONTROLLERS] [SECONDS]      # default 300 controllers, 15 s each
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-300}
SECONDS_EACH=${2:-15}
LOAD=./target/release/fivex-load
[ -x "$LOAD" ] || { echo "build first: cargo build --release -p fivex-server" >&2; exit 2; }
BIN=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
[ -n "$BIN" ] || { echo "PostgreSQL's server binaries not found: apt-get install postgresql" >&2; exit 2; }
NATS=$(command -v nats-server || echo /usr/sbin/nats-server)
WORK=$(mktemp -d)
AS=()
if [ "$(id -u)" -eq 0 ]; then chown postgres "$WORK"; AS=(runuser -u postgres --); fi
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
PG_PORT=$(free_port)
NATS_PORT=$(free_port)
cleanup() {
    "${AS[@]}" "$BIN/pg_ctl" -D "$WORK/data" -m immediate -w stop >/dev/null 2>&1 || true
    [ -n "${NATS_PID:-}" ] && kill "$NATS_PID" 2>/dev/null || true
    rm -rf "$WORK"
}
trap cleanup EXIT
trap "exit 1" INT TERM
"${AS[@]}" "$BIN/initdb" -D "$WORK/data" -A trust -U fivex --no-sync -E UTF8 >/dev/null
"${AS[@]}" "$BIN/pg_ctl" -D "$WORK/data" -o "-p $PG_PORT -h 127.0.0.1 -k $WORK -c max_connections=400" \
    -l "$WORK/pg.log" -w start >/dev/null
mkdir -p "$WORK/nats" && chmod 777 "$WORK/nats"
"$NATS" -js -a 127.0.0.1 -p "$NATS_PORT" -sd "$WORK/nats" >/dev/null 2>&1 &
NATS_PID=$!
sleep 1
# A database of its own per run (called in $(…), a subshell: no counter survives it).
fresh_db() {
    local name="load$(date +%s%N)"
    "${AS[@]}" "$BIN/createdb" -h 127.0.0.1 -p "$PG_PORT" -U fivex "$name" >&2
    echo "postgres://fivex@127.0.0.1:$PG_PORT/$name"
}
common=(--controllers "$N" --seconds "$SECONDS_EACH" --warmup 5 ${LOGS:+--logs "$LOGS"})
echo "== one process, SQLite"
$LOAD "${common[@]}" || true
echo "== one node (PostgreSQL, NATS)"
$LOAD "${common[@]}" --nodes 1 --db "$(fresh_db)" --nats "nats://127.0.0.1:$NATS_PORT" || true
echo "== three nodes, each stream through its controller's node"
$LOAD "${common[@]}" --nodes 3 --db "$(fresh_db)" --nats "nats://127.0.0.1:$NATS_PORT" || true
echo "== three nodes, each stream relayed by another node"
$LOAD "${common[@]}" --nodes 3 --relay --db "$(fresh_db)" --nats "nats://127.0.0.1:$NATS_PORT" || true
