#!/usr/bin/env bash
# The shop-floor interfaces under load (docs/performance.md, "The shop-floor interfaces under
# load"): `fivex-load` with N controllers running, the MTConnect agent and the OPC UA server on,
# a `/sample` long-poll stream per controller plus a poller of the whole agent (fivex-load's
# own clients) and an OPC UA subscription per controller (bench/opcua_load.py, asyncua in
# target/venv: scripts/python-venv.sh). Three runs, one JSON report each: the interfaces with
# their clients alone (no websocket), the same beside a websocket per controller, and the
# baseline without the interfaces.
#
#   cargo build --release -p fivex-server && scripts/python-venv.sh
#   bash bench/shopfloor.sh [CONTROLLERS] [SECONDS]      # default 200 controllers, 30 s each
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-200}
SECONDS_EACH=${2:-30}
LOAD=./target/release/fivex-load
[ -x "$LOAD" ] || { echo "build first: cargo build --release -p fivex-server" >&2; exit 2; }
[ -x target/venv/bin/python ] || { echo "run scripts/python-venv.sh first" >&2; exit 2; }
CLIENT="target/venv/bin/python bench/opcua_load.py"
set +e
echo "== $N controllers: MTConnect stream and OPC UA subscription each, no websockets"
"$LOAD" --controllers "$N" --seconds "$SECONDS_EACH" --warmup 10 --mtconnect --opcua --opcua-client "$CLIENT" --no-streams
echo "== $N controllers: the same beside a websocket each"
"$LOAD" --controllers "$N" --seconds "$SECONDS_EACH" --warmup 10 --mtconnect --opcua --opcua-client "$CLIENT"
echo "== $N controllers: a websocket each, no shop-floor interface (the baseline)"
"$LOAD" --controllers "$N" --seconds "$SECONDS_EACH" --warmup 10
