"""``linkwork study STUDY``: run a study file and write its dataset and report."""

from __future__ import annotations

import argparse
import os
import sys

from .files import load_study


def study(args: argparse.Namespace) -> int:
    spec = load_study(args.study)
    st = spec.study
    progress = sys.stderr.isatty()
    scale = "in-process" if args.scheduler is None else f"on {args.scheduler}"
    chunk = args.chunk or spec.chunk
    print(f"{st.model!r}: {len(st.times)} steps, t = {st.times[0]:g} .. {st.times[-1]:g}, {scale}")
    run = {"scheduler": args.scheduler, "chunk": chunk, "progress": progress}
    os.makedirs(args.out, exist_ok=True)
    if spec.tolerances is not None:
        tol = st.tolerance(spec.tolerances, n=spec.n, seed=spec.seed, linear=spec.linear, **run)
        print(tol.summary())
        result = tol.monte_carlo
        written = tol.report(args.out, spec.name)
        swept = len(tol.deviations)
    else:
        assert spec.designs is not None
        result = st.run(spec.designs, **run)
        swept = len(result) - result.n_failed
        print(f"{len(result)} designs ({result.designs.kind}): {swept} swept, {result.n_failed} failed")
        for i, design, error in result.failures()[:10]:
            values = ", ".join(f"{k} = {v:.6g}" for k, v in design.items())
            print(f"  design {i} ({values}): {error.splitlines()[0][:120]}")
        if result.n_failed > 10:
            print(f"  ... {result.n_failed - 10} more (all in the dataset's 'error')")
        from .report import study_report

        written = study_report(result, args.out, spec.name)
    per_task = [t[2] / max(1, t[1]) for t in result.tasks]
    print(
        f"  ran {result.where}: {result.seconds:.3g} s, {len(result.tasks)} tasks of up to "
        f"{result.chunk} designs "
        f"({1e3 * sum(per_task) / max(1, len(per_task)):.3g} ms a design in a task)"
    )
    data = result.save(os.path.join(args.out, f"{spec.name}.{args.format}"))
    print(f"wrote {data}, {written[0]} and {len(written) - 1} figures")
    return 0 if swept > 0 else 1
