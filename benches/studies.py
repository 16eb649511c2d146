"""Design-study throughput, side by side in one run: the engine's threads sweeping
pre-built models (`sweep_batch`), the same Monte Carlo tolerance study in-process, and on
a LocalCluster of two worker processes (one thread each). Also the per-task overhead of
the cluster and a scan of task sizes.

    python benches/studies.py [n_designs] [steps] [rounds]       (default 10000 1000 2)

The study: the textbook four-bar (examples/four_bar.toml, mm), three link lengths and the
rocker's pivot toleranced, one crank turn; outputs the coupler path and the rocker angle
(what a tolerance study keeps). The study sets every design up inside it (as a variant
of the compiled model, by the engine; or, with variants=False, redrawn by `apply` and
compiled), so its figure includes that work; sweep_batch's does not.
"""

import math
import os
import sys
import time

import numpy as np
from distributed import Client, LocalCluster

import linkwork as lw
from linkwork import study as S


def phases(res):
    return ", ".join(f"{k} {v:.2f} s" for k, v in res.phases.items())


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 2
    cores = os.cpu_count() or 1
    here = os.path.dirname(os.path.abspath(__file__))
    mechanism = lw.Mechanism.load(os.path.join(here, "..", "examples", "four_bar.toml"))
    times = np.linspace(0.0, 2 * math.pi / 5.0, steps)
    study = lw.Study(mechanism, times, ["path P", "angle rocker"])
    tolerances = {
        "length crank": S.Normal(0.05 / 3),
        "length coupler": S.Normal(0.05 / 3),
        "length rocker": S.Uniform(0.05),
        "pivot O4.x": S.Interval(-0.1, 0.1),
    }
    designs = S.sample(study.nominal(list(tolerances)), tolerances, n, seed=1)
    print(f"{n} four-bars, {steps} steps each, positions only; {cores} cores")

    # the models, built once, outside any clock: what sweep_batch alone sweeps
    start = time.perf_counter()
    job = study.job(designs.names)
    models = [
        lw.Model._checked(desc, job.options)
        for desc in S.apply_many(job.description, job.parameters, designs.values, **job.options)
    ]
    build = time.perf_counter() - start
    print(
        f"  building the {n} models (apply + compile), one thread: {build:.2f} s "
        f"({1e6 * build / n:.0f} us each)"
    )
    # sweep_batch over all the models at once keeps every full result (10,000 x 1000 x 9
    # doubles: 720 MB) and pays for that memory; 256 at a time, results dropped, it does not
    start = time.perf_counter()
    lw.sweep_batch(models, times, derivatives=0, errors="return")
    at_once = time.perf_counter() - start
    print(
        f"  sweep_batch alone, all {n} pre-built models at once ({cores} threads): {at_once:.2f} s, "
        f"{n / at_once:.0f} designs/s"
    )

    os.environ["PYTHONPATH"] = os.pathsep.join(
        [os.path.dirname(os.path.dirname(os.path.abspath(lw.__file__))), os.environ.get("PYTHONPATH", "")]
    )
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            client.wait_for_workers(2)
            # the scheduler's own cost per task: a no-op round trip, many at once
            client.gather(client.map(lambda x: x, range(100), pure=False))
            start = time.perf_counter()
            client.gather(client.map(lambda x: x, range(1000), pure=False))
            noop = (time.perf_counter() - start) / 1000
            print(f"  cluster per-task overhead (no-op tasks, 1000 at once): {1e3 * noop:.2f} ms a task")
            study.run(S.Designs(designs.names, designs.values[:200]), scheduler=client, chunk=100)  # warm up
            # the three side by side in interleaved rounds (the machine is shared: best of the
            # rounds, and the ratios are what to read); the cluster at three task sizes
            best: dict[str, float] = {}
            results: dict[str, object] = {}
            chunks = (50, 250, 1250)
            for _ in range(rounds):
                start = time.perf_counter()
                for k in range(0, n, 256):
                    lw.sweep_batch(models[k : k + 256], times, derivatives=0, errors="return")
                best["alone"] = min(best.get("alone", math.inf), time.perf_counter() - start)
                for key in ("in", "redrawn", *chunks):
                    start = time.perf_counter()
                    if key == "in":
                        res = study.run(designs)
                    elif key == "redrawn":
                        res = study.run(designs, variants=False)
                    else:
                        res = study.run(designs, scheduler=client, chunk=key)
                    t = time.perf_counter() - start
                    if t < best.get(key, math.inf):  # the best round's time, with its tasks' figures
                        best[key], results[key] = t, res
    alone, t_in, inproc = best["alone"], best["in"], results["in"]
    print(
        f"  sweep_batch alone, 256 pre-built models at a time, results dropped ({cores} threads): "
        f"{alone:.2f} s, {n / alone:.0f} designs/s  <- the reference below"
    )
    print(
        f"  study in-process: {t_in:.2f} s, {n / t_in:.0f} designs/s = "
        f"{alone / t_in:.0%} of sweep_batch alone "
        f"({len(inproc.tasks)} chunks of {inproc.chunk}; designs {inproc.built}; {phases(inproc)})"
    )
    redrawn, t_re = results["redrawn"], best["redrawn"]
    same = max(float(np.nanmax(np.abs(redrawn.figures[k] - inproc.figures[k]))) for k in inproc.figures)
    print(
        f"  study in-process, every design redrawn and compiled (variants=False): {t_re:.2f} s, "
        f"{n / t_re:.0f} designs/s = {alone / t_re:.0%} of sweep_batch alone ({phases(redrawn)}); "
        f"largest difference from the variants' figures {same:.1e}"
    )
    for chunk in chunks:
        res, t = results[chunk], best[chunk]
        busy = sum(s for _, _, s in res.tasks)
        same = all(np.array_equal(res.figures[k], inproc.figures[k], equal_nan=True) for k in res.figures)
        print(
            f"  study on LocalCluster (2 workers x 1 thread), chunk {chunk}: {t:.2f} s, "
            f"{n / t:.0f} designs/s = {t_in / t:.0%} of in-process, "
            f"{alone / t:.0%} of sweep_batch alone; "
            f"{len(res.tasks)} tasks, {1e3 * (2 * t - busy) / len(res.tasks):.1f} ms a task "
            f"outside the tasks' work; {phases(res)} (both workers); bit for bit: {same}"
        )
    print(f"  fastest chunk on the cluster: {min(chunks, key=lambda c: best[c])} designs a task")


if __name__ == "__main__":  # worker processes import this file
    main()
