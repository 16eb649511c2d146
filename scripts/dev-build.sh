#!/usr/bin/env bash
# Rebuilds and installs linkwork in editable mode for development: no LTO, and one build
# at a time (concurrent builds would race on the extension module).
set -euo pipefail
cd "$(dirname "$0")/.."
MATURIN_PEP517_ARGS="--profile dev-fast" exec flock /tmp/linkwork-build.lock \
    python -m pip install -q --no-build-isolation -e ".[test]"
