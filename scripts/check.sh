#!/usr/bin/env bash
# Every house check, in the order a failure is cheapest to see. CI (.ci/run), the README
# and the pre-commit hook all call this. Expects linkwork installed: pip install -e ".[test]"
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== rustfmt";  cargo fmt --all -- --check
echo "== clippy";   cargo clippy --workspace --all-targets --quiet -- -D warnings
echo "== cargo test"; cargo test -p linkwork -p linkwork-homotopy --quiet
echo "== ruff";     ruff check python tests benches examples
ruff format --check python tests benches examples
echo "== import layers"; lint-imports
echo "== stubtest"; python -m mypy.stubtest linkwork._core
echo "== pytest";   python -m pytest -q
