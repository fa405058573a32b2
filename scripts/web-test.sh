#!/usr/bin/env bash
# The dashboard's tests: the typed API client matches openapi/openapi.json, TypeScript checks,
# unit tests (vitest), the production build, and the browser tests (Debian's Chromium driven by
# playwright-core against a real `fivex serve`). Installs what a fresh machine lacks: the npm
# packages (from the lockfile) and the chromium package.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ]; then
    echo "== installing Debian's chromium for the browser tests"
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi

cd web
echo "== npm ci"
npm ci --no-audit --no-fund --loglevel=error
echo "== the API client is generated from openapi/openapi.json"
npx openapi-typescript ../openapi/openapi.json -o /tmp/fivex-schema.d.ts >/dev/null 2>&1
diff -q src/api/schema.d.ts /tmp/fivex-schema.d.ts || { echo "web/src/api/schema.d.ts is stale: run 'npm run gen' in web/"; exit 1; }
echo "== tsc, vitest, vite build"
npm run build --silent
npx vitest run
echo "== browser tests"
(cd .. && cargo build -q -p fivex-server --bin fivex)
node tests/e2e.mjs
