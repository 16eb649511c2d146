"""Sweeps every shipped model file and built-in example and writes (or compares) the arrays.

A refactor that moves code must not change a single bit of any result. Run it before the
change with ``--write DIR`` and after it with ``--compare DIR``: the comparison is exact
(``np.array_equal`` with NaN equal to NaN) and names every array that differs.

    python scripts/sweep_bits.py --write /tmp/bits-before
    python scripts/sweep_bits.py --compare /tmp/bits-before
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

import linkwork
from linkwork import examples

ROOT = Path(__file__).resolve().parent.parent
STEPS = 721


def _arrays(results: linkwork.Results) -> dict[str, np.ndarray]:
    """Every array a sweep returns: coordinates, derivatives, diagnostics, forces."""
    out = {"times": results.times, "q": results.q}
    for name in ("qd", "qdd", "iterations", "residual", "pivot_ratio", "det_sign"):
        value = getattr(results, name, None)
        if value is not None:
            out[name] = np.asarray(value)
    for name in ("multipliers", "reactions", "load_power"):
        value = getattr(results, name, None)
        if isinstance(value, np.ndarray):
            out[name] = value
    out["events"] = np.array([repr(e) for e in results.events], dtype=str)
    return out


def _sweep(model: linkwork.Model, times: np.ndarray) -> linkwork.Results:
    """With the inverse dynamics where the model can have them (mass properties given)."""
    try:
        return model.sweep(times, forces=True, on_singular="continue")
    except linkwork.LinkworkError:
        return model.sweep(times, on_singular="continue")


def _cases() -> dict[str, dict[str, np.ndarray]]:
    cases: dict[str, dict[str, np.ndarray]] = {}
    for path in sorted((ROOT / "examples").glob("*.toml")):
        mechanism = linkwork.Mechanism.load(path)
        model = mechanism.compile()
        # One second of motion: every shipped file is drawn at t = 0 and moves within it.
        results = _sweep(model, np.linspace(0.0, 1.0, STEPS))
        cases[f"file-{path.stem}"] = _arrays(results)
    for name in sorted(examples.ALL):
        model = examples.ALL[name]().compile()
        results = _sweep(model, np.linspace(0.0, 2.0 * math.pi / 5.0, STEPS))
        cases[f"example-{name}"] = _arrays(results)
    return cases


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", type=Path, metavar="DIR")
    group.add_argument("--compare", type=Path, metavar="DIR")
    args = parser.parse_args(argv)
    cases = _cases()
    if args.write:
        args.write.mkdir(parents=True, exist_ok=True)
        for name, arrays in cases.items():
            np.savez(args.write / f"{name}.npz", **arrays)
        print(f"wrote {len(cases)} cases to {args.write}")
        return 0
    differ = []
    stored = sorted(p.stem for p in args.compare.glob("*.npz"))
    if stored != sorted(cases):
        differ.append(f"cases differ: stored {stored}, now {sorted(cases)}")
    for name, arrays in cases.items():
        path = args.compare / f"{name}.npz"
        if not path.exists():
            continue
        before = np.load(path)
        for key in sorted(set(before.files) | set(arrays)):
            if key not in before.files or key not in arrays:
                differ.append(f"{name}: array {key} only on one side")
            elif not np.array_equal(before[key], arrays[key], equal_nan=arrays[key].dtype.kind == "f"):
                differ.append(f"{name}: {key} differs")
    for line in differ:
        print(line)
    print(f"{len(cases)} cases, {len(differ)} differences")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
