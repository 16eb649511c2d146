#!/usr/bin/env bash
# Mutation check of what a change touches, run before stopping and by CI: cargo mutants
# on the Rust lines changed since BASE (core modules of .cargo/mutants.toml only), then
# scripts/mutate_python.py on the changed Python core modules. Fails if a mutant survives.
#   scripts/mutants-diff.sh [BASE]
# BASE: default the merge-base with main, or HEAD~1 on main itself; with no base (a
# single-commit clone) there is nothing to compare and the check passes, saying so.
# MUTANTS_BUDGET: seconds for each of the two parts (default 270), so that the whole
# check stays under 10 minutes; a mutant not reached in time is reported, not counted.
# MUTANTS_IN_PLACE=1: mutate this tree and reuse its target dir (CI's throwaway clone);
# MUTANTS_PROFILE=dev: build the mutants in that profile (CI: the one its tests just built).
set -euo pipefail
cd "$(dirname "$0")/.."
budget=${MUTANTS_BUDGET:-270}
base=${1:-}
if [ -z "$base" ]; then
    if git rev-parse -q --verify main >/dev/null && [ "$(git rev-parse main)" != "$(git rev-parse HEAD)" ]; then
        base=$(git merge-base main HEAD)
    elif git rev-parse -q --verify HEAD~1 >/dev/null; then
        base=HEAD~1
    else
        echo "mutants-diff: no base commit to compare with: nothing checked"
        exit 0
    fi
fi
out=$(mktemp -d)
status=0

# --- Rust: mutants on the changed lines
git diff "$base" -- '*.rs' >"$out/rust.diff"
if [ -s "$out/rust.diff" ]; then
    # -p: without it cargo mutants parses the whole workspace (minutes, gigabytes)
    # no baseline run: the suite is green before this check (scripts/check.sh); a mutant
    # whose tests run past 5 minutes counts as caught (it hangs)
    args=(--in-diff "$out/rust.diff" -p linkwork -p linkwork-homotopy -o "$out" --no-shuffle --baseline skip --timeout 300)
    [ "${MUTANTS_IN_PLACE:-0}" = 1 ] && args+=(--in-place)
    [ -n "${MUTANTS_PROFILE:-}" ] && args+=(--profile "$MUTANTS_PROFILE")
    if ! command -v cargo-mutants >/dev/null; then
        echo "mutants-diff: cargo-mutants is not installed (cargo install cargo-mutants --locked)" >&2
        exit 1
    fi
    set +e
    timeout "$budget" cargo mutants "${args[@]}"
    rc=$?
    set -e
    missed="$out/mutants.out/missed.txt"
    if [ -s "$missed" ]; then
        echo "mutants-diff: surviving Rust mutants:"
        cat "$missed"
        status=1
    fi
    case $rc in
        0 | 2 | 3) ;; # all caught / some missed (listed above) / some timed out (a hang is caught)
        124) echo "mutants-diff: the Rust budget (${budget} s) ran out; untested mutants are not counted" ;;
        *) echo "mutants-diff: cargo mutants failed (exit $rc)" >&2; status=1 ;;
    esac
else
    echo "mutants-diff: no Rust change since $base"
fi

# --- Python: one-token mutants of the changed lines of the core modules
# synthesis/ holds curve/; the dynamics' results: simulation.py, equilibrium.py
core="python/linkwork/synthesis python/linkwork/model/linkages.py python/linkwork/model/simulation.py python/linkwork/model/equilibrium.py python/linkwork/study"
changed=$(git diff --name-only "$base" -- $core | grep "\.py$" || true)
if [ -n "$changed" ]; then
    set +e
    timeout "$budget" python scripts/mutate_python.py "$base" $changed
    rc=$?
    set -e
    case $rc in
        0) ;;
        124) echo "mutants-diff: the Python budget (${budget} s) ran out; untested mutants are not counted" ;;
        *) status=1 ;;
    esac
else
    echo "mutants-diff: no change to the Python core modules since $base"
fi
exit $status
