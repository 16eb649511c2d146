"""The atlas of four-bar coupler curves: how fast it is built (in-process on the engine's
threads, and on a local Dask cluster of 2 worker processes), how fast it is queried, and
how close its best hit comes to the two shape problems of
../shared/notes/path-synthesis.md (McGarva 1994, Ullah and Kota 1997) against the
literature designs (mean nearest distance from the target points to the traced curve).

    python benches/curve_atlas.py                 # print
    python benches/curve_atlas.py --n 20000       # the atlas built for the rates
    python benches/curve_atlas.py --write         # also add it to the day's log in benches/results/

A hit is scored by `shape_error` (the best similarity transform: descriptors, ICP,
Nelder-Mead on the mean). The literature designs (four-bar-rs test-fb/refer/*.ron, its
vector mapped as rcx = l5 cos g, rcy = l5 sin g, theta0 = a, x0 = p1x, y0 = p1y) are
traced by the engine on each circuit and scored where they stand and after the same
similarity transform.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import time
from pathlib import Path

import numpy as np
import runlog  # benches/, beside this script

import linkwork as lw
from linkwork.synthesis.curve import atlas as A
from linkwork.synthesis.curve import descriptors as D

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(os.environ.get("LINKWORK_PATH_DATA", ROOT.parent.parent / "shared" / "data" / "path-synthesis"))

# ground, crank, coupler, rocker, l5, g, a, p1x, p1y (four-bar-rs test-fb/refer/*.ron)
LITERATURE = {
    "mcgarva_1994": (47.5, 24.3, 48.1, 47.0, 85.6, 0.9599310885968813, 1.95, 54.6, -35.5),
    "ullah_kota_1997": (9.33, 1.41, 7.39, 3.6, 13.57, 0.7452555906015788, 4.9031534676276705, -11.77, 5.38),
}


def traced(design: tuple[float, ...], circuit: str, steps: int = 1440) -> np.ndarray:
    """A literature design's coupler curve in its frame, swept by the engine."""
    r1, r2, r3, r4, l5, g, a, x0, y0 = design
    m = lw.build.four_bar(r1, r2, r3, r4, branch=circuit, coupler_point=(l5 * math.cos(g), l5 * math.sin(g)))
    t = np.linspace(0.0, 2 * math.pi / 5.0, steps, endpoint=False)  # one crank turn at omega 5
    p = m.compile().sweep(t, derivatives=0).point("P").position
    return p @ np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]]) + [x0, y0]


def timed(f, repeat: int) -> float:
    """Median seconds of ``repeat`` calls."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def build_rates(n: int) -> tuple[list[str], A.Atlas]:
    lines = []
    t = time.perf_counter()
    local = A.build_atlas(n, seed=1)
    s = time.perf_counter() - t
    lines.append(
        f"| in-process (engine threads, {os.cpu_count()} cores) | {n} | {s:.2f} | {n / s:,.0f} | "
        f"{n * A.STEPS / s:,.0f} |"
    )
    try:
        import distributed
    except ImportError:
        lines.append("| LocalCluster | - | - | dask.distributed not installed | - |")
        return lines, local
    t = time.perf_counter()
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
    )
    client = distributed.Client(cluster)
    client.wait_for_workers(2)
    start = time.perf_counter() - t
    try:
        A.build_atlas(min(n, 2048), seed=2, scheduler=client, block=1024)  # workers warmed up
        t = time.perf_counter()
        remote = A.build_atlas(n, seed=1, scheduler=client, block=2048)
        s = time.perf_counter() - t
    finally:
        client.close()
        cluster.close()
    same = all(np.array_equal(getattr(remote, k), getattr(local, k)) for k in ("designs", "descriptors"))
    lines.append(
        f"| LocalCluster, 2 workers x 1 thread (start-up {start:.1f} s not counted) | {n} | {s:.2f} | "
        f"{n / s:,.0f} | {n * A.STEPS / s:,.0f} |"
    )
    lines.append("")
    lines.append(f"The cluster's atlas equals the in-process one: {same}.")
    return lines, local


def query_times(atlas: A.Atlas, targets: dict[str, np.ndarray]) -> list[str]:
    lines = []
    for name, pts in targets.items():
        atlas.query(pts, k=5)
        q = timed(lambda pts=pts: atlas.query(pts, k=5), 200)
        lines.append(f"| {name} ({len(pts)} points) | {len(atlas)} | {q * 1e3:.2f} |")
    vec = atlas.descriptors[0].reshape(-1).astype(np.float64)
    bare = timed(lambda: atlas.tree.query(vec, k=5), 500)
    lines.append(f"| one k-d tree lookup (k = 5) | {len(atlas)} | {bare * 1e3:.3f} |")
    return lines


def shape_rows(atlases: dict[str, A.Atlas], targets: dict[str, np.ndarray]) -> list[str]:
    rows = []
    for name, pts in targets.items():
        for label, atlas in atlases.items():
            t = time.perf_counter()
            hits = atlas.query(pts, k=10)
            fits = [(D.shape_error(pts, h.curve(1440)), h) for h in hits]
            fit, hit = min(fits, key=lambda f: f[0].mean)
            s = time.perf_counter() - t
            rows.append(
                f"| {name} | best of 10 hits, {label} atlas ({len(atlas)}) | {fit.mean:.4g} | "
                f"{fit.largest:.4g} | "
                f"{hit.circuit}, r = {np.round(hit.vector[:4] / hit.vector[0], 3).tolist()} | {s:.2f} |"
            )
        for circuit in A.CIRCUITS:
            curve = traced(LITERATURE[name], circuit)
            placed = D.nearest_distances(pts, curve)
            best = D.shape_error(pts, curve)
            rows.append(
                f"| {name} | literature design, {circuit} circuit: as placed / after similarity | "
                f"{placed.mean():.4g} / {best.mean:.4g} | {placed.max():.4g} / {best.largest:.4g} | | |"
            )
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=20000, help="designs of the atlas built for the rates")
    ap.add_argument("--write", action="store_true", help="add the run to benches/results/")
    args = ap.parse_args()
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    targets = {
        name: np.loadtxt(DATA / f"{name}.csv", delimiter=",", skiprows=1, usecols=(0, 1))
        for name in LITERATURE
    }
    shipped = A.load()
    build, built = build_rates(args.n)
    load = os.getloadavg()
    text = "\n".join(
        [
            f"Measured {stamp} with `python benches/curve_atlas.py --n {args.n}` on "
            f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, load average "
            f"{load[0]:.1f}, Python {platform.python_version()}, linkwork {lw.__version__}.",
            "",
            f"Atlas build ({A.STEPS} crank steps a curve, {shipped.harmonics} harmonics; "
            "design-steps: designs x steps):",
            "",
            "| where | designs | s | designs/s | design-steps/s |",
            "|---|---:|---:|---:|---:|",
            *build,
            "",
            "Query (`Atlas.query(points, k=5)`: the target's descriptors and its mirror image's, both ways "
            "round and from both ends of the major axis, eight k-d tree lookups; median of 200):",
            "",
            "| target | atlas designs | ms |",
            "|---|---:|---:|",
            *query_times(shipped, targets),
            "",
            "Shape problems: mean and largest nearest distance from the target points to the traced curve "
            "(atlas hits after the best similarity transform; s: query, tracing and scoring the 10 hits):",
            "",
            "| problem | design | mean | largest | hit | s |",
            "|---|---|---:|---:|---|---:|",
            *shape_rows({"shipped": shipped, "built": built}, targets),
        ]
    )
    print(text)
    if args.write:
        runlog.append_run("curve_atlas.py", stamp, text)


if __name__ == "__main__":
    main()
