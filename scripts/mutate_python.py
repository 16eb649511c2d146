"""Mutation check of Python modules, diff-scoped: each one-token mutant of the changed lines
(comparison and arithmetic operators swapped, `and`/`or`, `|=`/`=`, numeric constants
changed, arcsin/arccos and min/max exchanged) is applied alone and the tests that import
the module run against it; a mutant they pass is a survivor. mutmut's trampolines do not
reach a package whose extension is built beside it (python/linkwork/_core), hence this.

    python scripts/mutate_python.py BASE python/linkwork/synthesis/designs.py ...
    python scripts/mutate_python.py --all python/linkwork/model/linkages.py   (every line)
    python scripts/mutate_python.py --all python/linkwork/synthesis/designs.py:1-80   (lines)

The tests run are MUTATE_TESTS (space-separated), else the module's entry in SUITES, else
the files that name the module. A mutant whose tests run longer than MUTATE_TIMEOUT seconds
(default 120: a loop whose counter a mutant turned back) is stopped and counted as caught.

Exit 1 if a mutant survives."""

from __future__ import annotations

import io
import os
import re
import signal
import subprocess
import sys
import time
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SWAPS = {
    "<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "==",
    "+": "-", "-": "+", "*": "/", "/": "*", "and": "or", "or": "and",
    "|=": "=", "&=": "=", "+=": "-=", "-=": "+=", "min": "max", "max": "min",
    "arcsin": "arccos", "arccos": "arcsin", "True": "False", "False": "True",
}  # fmt: skip


def changed_lines(base: str | None, path: str) -> set[int] | None:
    """Line numbers of `path` added or changed since `base` (None: every line)."""
    if base is None:
        return None
    diff = subprocess.run(
        ["git", "diff", "-U0", base, "--", path], cwd=ROOT, capture_output=True, text=True
    ).stdout
    lines: set[int] = set()
    for m in re.finditer(r"^@@ -\d+(?:,\d+)? \+(\d+)(?:,(\d+))? @@", diff, re.M):
        start, count = int(m.group(1)), int(m.group(2) or 1)
        lines.update(range(start, start + count))
    return lines


def mutants(source: str, lines: set[int] | None):
    """(line, description, mutated source) for each token swap on the chosen lines."""
    offsets = [0]
    for line in source.splitlines(keepends=True):
        offsets.append(offsets[-1] + len(line))
    # inside a string nothing is mutated (an f-string's expressions are tokens from 3.12 on);
    # the code around a string on the same line is
    strings: list[tuple[tuple[int, int], tuple[int, int]]] = []
    opened: list[tuple[int, int]] = []
    fstring_start, fstring_end = getattr(tokenize, "FSTRING_START", -1), getattr(tokenize, "FSTRING_END", -1)
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.STRING:
            strings.append((tok.start, tok.end))
        elif tok.type == fstring_start:
            opened.append(tok.start)
        elif tok.type == fstring_end:
            strings.append((opened.pop(), tok.end))
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        row = tok.start[0]
        if lines is not None and row not in lines or any(a <= tok.start < b for a, b in strings):
            continue
        start = offsets[row - 1] + tok.start[1]
        end = offsets[tok.end[0] - 1] + tok.end[1]
        new = None
        if tok.type in (tokenize.OP, tokenize.NAME) and tok.string in SWAPS:
            new = SWAPS[tok.string]
        elif tok.type == tokenize.NUMBER and not tok.string.endswith("j"):
            new = "1" if tok.string in ("0", "0.0") else f"({tok.string} + 1)"
        if new is not None:
            yield row, f"{tok.string} -> {new}", source[:start] + new + source[end:]


# The tests of modules whose names are common words (a search by name would run most of
# the suite for each mutant), the fast property tests first: `-x` stops at the first failure.
_CURVE = "python/linkwork/synthesis/curve/"
SUITES = {
    "python/linkwork/model/simulation.py": "test_dynamics_forward.py test_cli_simulate.py",
    "python/linkwork/model/equilibrium.py": "test_equilibrium.py",
    _CURVE + "constraints.py": "test_curve_constraint_properties.py test_curve_problem_properties.py "
    "test_curve_constraints.py",
    _CURVE + "tracking.py": "test_curve_problem_properties.py test_curve_region_properties.py "
    "test_curve_screening_properties.py test_curve_seed_properties.py test_curve_constraints.py "
    "test_curve_synthesis.py",
    _CURVE + "seeds.py": "test_curve_seed_properties.py test_curve_seeds.py",
    _CURVE + "fit.py": "test_curve_screening_properties.py test_curve_synthesis.py test_curve_budget.py",
    _CURVE + "problem.py": "test_curve_screening_properties.py test_curve_cli.py",
    _CURVE + "descriptors.py": "test_curve_descriptor_properties.py test_curve_atlas.py",
    _CURVE + "shape.py": "test_curve_shape_properties.py test_curve_shape_polish.py "
    "test_curve_shape_rounds.py test_curve_seeds.py",
    _CURVE + "target.py": "test_curve_target_properties.py test_curve_synthesis.py test_curve_cli.py",
    _CURVE + "six_bar_fit.py": "test_curve_six_bar_properties.py test_curve_six_bars.py",
}


def tests_for(module: Path) -> list[str]:
    """Test files of the module: MUTATE_TESTS, its SUITES entry, or those that name it."""
    if os.environ.get("MUTATE_TESTS"):
        return os.environ["MUTATE_TESTS"].split()
    suite = SUITES.get(str(module.resolve().relative_to(ROOT)))
    if suite:
        return [f"tests/{name}" for name in suite.split()]
    tests = sorted((ROOT / "tests").glob("test_*.py"))
    # a package by its name; a module no test names, by its package's (`synthesis.screening`)
    for name in (module.stem, module.parent.name):
        if name in ("__init__", "linkwork"):
            continue
        named = [str(p.relative_to(ROOT)) for p in tests if re.search(rf"\b{name}\b", p.read_text())]
        if named:
            return named
    return []


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__)
        return 2
    # a budget's timeout (SIGTERM) must still restore the module: exit through `finally`
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(124))
    base = None if argv[0] == "--all" else argv[0]
    timeout = float(os.environ.get("MUTATE_TIMEOUT", "120"))
    survivors: list[str] = []
    total = 0
    for arg in argv[1:]:
        arg, _, span = arg.partition(":")
        path = ROOT / arg
        original = path.read_text()
        lines = changed_lines(base, arg)
        if span:
            lo, hi = (int(v) for v in span.split("-"))
            lines = set(range(lo, hi + 1)) & (lines if lines is not None else set(range(lo, hi + 1)))
        tests = tests_for(path)
        if not tests:
            print(f"{arg}: no test imports it")
            survivors.append(f"{arg}: untested module")
            continue
        try:
            for row, what, mutated in mutants(original, lines):
                total += 1
                path.write_text(mutated)
                t0 = time.monotonic()
                try:
                    returncode = subprocess.run(
                        [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", *tests],
                        cwd=ROOT, capture_output=True, text=True, timeout=timeout,
                    ).returncode  # fmt: skip
                    verdict = "survived" if returncode == 0 else "killed"
                except subprocess.TimeoutExpired:
                    returncode, verdict = 1, "killed (timeout)"
                print(f"{arg}:{row}: {what}: {verdict} ({time.monotonic() - t0:.0f} s)", flush=True)
                if returncode == 0:
                    survivors.append(f"{arg}:{row}: {what}")
        finally:
            path.write_text(original)
    print(f"{total} mutants, {total - len(survivors)} killed, {len(survivors)} survived")
    for s in survivors:
        print("  survived:", s)
    return 1 if survivors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
