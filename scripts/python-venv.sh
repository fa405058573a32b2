#!/usr/bin/env bash
# The Python the shop-floor tests run (server/tests/it/shopfloor): a venv in target/venv with
# scripts/requirements-test.txt from PyPI (Debian's python3-venv installed if missing). The tests
# use $FIVEX_TEST_PYTHON, else target/venv/bin/python.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! python3 -c 'import ensurepip' 2>/dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq && $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv >/dev/null
fi
if [ ! -x target/venv/bin/python ]; then
    python3 -m venv target/venv
fi
if ! cmp -s scripts/requirements-test.txt target/venv/requirements-test.txt; then
    target/venv/bin/pip install -q --disable-pip-version-check -r scripts/requirements-test.txt
    cp scripts/requirements-test.txt target/venv/requirements-test.txt
fi
