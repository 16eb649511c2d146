"""Synthesis side by side: linkwork against pylinkage 1.3 on the same problems.

Five-pose Burmester problems made from random generating four-bars (so the answer is
known): how many of the generator's two dyads each tool recovers (within 1e-6 of the
problem's size), how many real dyads and linkages it reports, and the time per problem;
linkwork both ways (homotopy and elimination, every root certified either way). Then
Alt's nine-point problem on random real points, on published instances and on a random
complex instance: paths, failures, classes, real four-bars, time.

    python benches/synthesis.py            # print
    python benches/synthesis.py --write    # also add it to the day's log in benches/results/

pylinkage is optional (pip install pylinkage==1.3.0): without it its rows say so.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import subprocess
import time
from pathlib import Path

import numpy as np
import runlog  # benches/, beside this script

import linkwork
from linkwork import synthesis as S

try:
    import pylinkage
    from pylinkage import synthesis as PS
except ImportError:  # pragma: no cover - optional
    pylinkage = None

ROOT = Path(__file__).resolve().parent.parent


def generator(rng: np.random.Generator) -> tuple[np.ndarray, tuple[complex, complex, complex, complex]]:
    """Five poses of a random Grashof crank-rocker's coupler and its two dyads."""
    while True:
        o2, o4 = 0j, complex(rng.uniform(2, 4), rng.uniform(-1, 1))
        crank, coupler, rocker = rng.uniform(0.5, 1.2), rng.uniform(2.5, 4.5), rng.uniform(2.0, 4.0)
        pc = complex(rng.uniform(-1, 2), rng.uniform(0.3, 2))
        phis = np.sort(rng.uniform(0, 2 * math.pi, 5))
        poses, ok = [], True
        first = None
        for phi in phis:
            a = o2 + crank * np.exp(1j * phi)
            d = o4 - a
            dist = abs(d)
            along = (coupler**2 - rocker**2 + dist**2) / (2 * dist)
            h2 = coupler**2 - along**2
            if h2 <= 0:
                ok = False
                break
            b = a + d / dist * (along + 1j * math.sqrt(h2))
            ang = float(np.angle(b - a))
            p = a + pc * np.exp(1j * ang)
            poses.append((p.real, p.imag, ang))
            if first is None:
                first = (a, b)
        if ok and first is not None:
            return np.array(poses), (o2, first[0], o4, first[1])


def recovered(
    pairs: list[tuple[complex, complex]], truth: tuple[complex, complex, complex, complex], tol: float
) -> int:
    o2, a1, o4, b1 = truth
    hits = 0
    for g, m in ((o2, a1), (o4, b1)):
        if any(abs(g - pg) < tol and abs(m - pm) < tol for pg, pm in pairs):
            hits += 1
    return hits


def burmester_side_by_side(n: int, seed: int) -> dict[str, dict[str, float]]:
    rng = np.random.default_rng(seed)
    rows: dict[str, dict[str, float]] = {}
    lw = {"found": 0, "real": 0, "designs": 0, "time": 0.0, "error": 0.0}
    el = {"found": 0, "real": 0, "designs": 0, "time": 0.0, "error": 0.0}
    pl = {"found": 0, "real": 0, "designs": 0, "time": 0.0, "error": 0.0}
    for _ in range(n):
        poses, truth = generator(rng)
        size = float(np.ptp(poses[:, :2]))
        t0 = time.perf_counter()
        sols = S.dyads("burmester", poses=poses)
        lw["time"] += time.perf_counter() - t0
        pairs = [(complex(*d.ground), complex(*d.moving)) for d in sols.real]
        lw["found"] += recovered(pairs, truth, 1e-6 * size)
        lw["real"] += len(pairs)
        lw["error"] = max(lw["error"], max((d.residual for d in sols.real), default=0.0))
        designs = sum(1 for d in S.motion(poses).designs if d.defects.ok)
        lw["designs"] += designs
        t0 = time.perf_counter()
        sols = S.dyads("burmester", poses=poses, method="resultant")
        el["time"] += time.perf_counter() - t0
        pairs = [(complex(*d.ground), complex(*d.moving)) for d in sols.real]
        el["found"] += recovered(pairs, truth, 1e-6 * size)
        el["real"] += len(pairs)
        el["error"] = max(el["error"], max((d.residual for d in sols.real), default=0.0))
        el["designs"] += designs  # the same dyads, so the same screened designs
        if pylinkage is not None:
            pposes = [PS.Pose(float(x), float(y), float(a)) for x, y, a in poses]
            t0 = time.perf_counter()
            try:
                curves = PS.compute_circle_point_curve(pposes)
                # complex numbers: (centre point, circle point) pairs
                pdyads = [(complex(c), complex(m)) for m, c in zip(curves.circle_curve, curves.center_curve)]
            except Exception:  # noqa: BLE001 - any failure counts as nothing found
                pdyads = []
            pl["time"] += time.perf_counter() - t0
            try:
                linkages = PS.motion_generation(pposes, require_grashof=False, max_solutions=None).solutions
            except Exception:  # noqa: BLE001
                linkages = []
            pl["found"] += recovered(pdyads, truth, 1e-6 * size)
            pl["real"] += len(pdyads)
            pl["designs"] += len(linkages)
            # the worst change of link length over the poses among its dyads
            for g, m in pdyads:
                p1 = complex(*poses[0, :2])
                lens = [
                    abs(complex(x, y) + (m - p1) * np.exp(1j * (a - poses[0, 2])) - g) for x, y, a in poses
                ]
                pl["error"] = max(pl["error"], float(np.ptp(lens)))
    rows["linkwork (homotopy)"] = lw
    rows["linkwork (elimination)"] = el
    rows["pylinkage"] = pl if pylinkage is not None else {}
    return rows


#: Alt's problem instances: the HomotopyContinuation.jl example points, and Wampler,
#: Morgan and Sommese's Problem 3 (64 real four-bars, certified by Hauenstein and Sottile).
HCJL = [
    (0.8961867, -0.09802917), (1.2156535, -1.18749100), (1.5151435, -0.85449808),
    (1.6754775, -0.48768058), (1.7138690, -0.30099232), (1.7215236, 0.03269953),
    (1.6642029, 0.33241088), (1.4984171, 0.74435576), (1.3011834, 0.92153806),
]  # fmt: skip
WMS3 = [
    (0.25, 0.00), (0.52, 0.10), (0.80, 0.70), (1.20, 1.00), (1.40, 1.30),
    (1.10, 1.48), (0.70, 1.40), (0.20, 1.00), (0.02, 0.40),
]  # fmt: skip


def alt_runs() -> list[tuple[str, dict[str, float]]]:
    rng = np.random.default_rng(7)
    random_points = rng.uniform(-1, 1, (9, 2))
    out: list[tuple[str, dict[str, float]]] = []
    for name, pts in (("random points", random_points), ("HC.jl example", HCJL), ("WMS Problem 3", WMS3)):
        r = S.nine_points(np.array(pts), screen=False)
        out.append((name, {k: getattr(r, k) for k in FIELDS} | {"real": r.physical_classes}))
    # complex parameters: the points' conjugates replaced by independent complex numbers
    rng = np.random.default_rng(5)
    pts, hat = rng.normal(size=(9, 2)), rng.normal(size=(9, 2))
    raw = linkwork._core.synth_alt(pts.ravel().tolist(), hat.ravel().tolist())
    out.append(("random complex", {k: raw["roots" if k == "classes" else k] for k in FIELDS} | {"real": "-"}))
    return out


FIELDS = ("paths", "seconds", "failed", "at_infinity", "singular", "classes", "certified", "distinct")


def table(n: int, seed: int) -> str:
    rows = burmester_side_by_side(n, seed)
    lines = [
        f"Measured {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC with "
        f"`python benches/synthesis.py --write` on {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores; linkwork at `{_commit()}`"
        + (
            f", pylinkage {pylinkage.__version__}"
            if pylinkage is not None and hasattr(pylinkage, "__version__")
            else ""
        ),
        "",
        f"**Five-pose Burmester**, {n} problems from random crank-rockers (seed {seed}); a generator dyad "
        "counts as recovered within 1e-6 of the problem's size.",
        "",
        "| tool | generator dyads recovered | real dyads reported | defect-free linkages "
        "| worst link-length change | time per problem |",
        "|---|---|---|---|---|---|",
    ]
    for tool, r in rows.items():
        if not r:
            lines.append(f"| {tool} | not installed | | | | |")
            continue
        lines.append(
            f"| {tool} | {r['found']} of {2 * n} | {r['real']} | {r['designs']} | {r['error']:.1e} | "
            f"{1e3 * r['time'] / n:.2f} ms |"
        )
    lines += [
        "",
        "pylinkage's linkages are counted as it reports them (`motion_generation`, Grashof not required); "
        "linkwork's are the designs its engine screening finds defect-free.",
        "",
        "**Alt's nine-point problem** (parameter homotopy from the 1442 shipped classes):",
        "",
        "| instance | paths | time | failed | at infinity | singular | classes (certified) "
        "| in distinct orbits | real four-bars |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, r in alt_runs():
        lines.append(
            f"| {name} | {r['paths']} | {r['seconds']:.2f} s ({r['paths'] / r['seconds']:.0f} paths/s) "
            f"| {r['failed']} | {r['at_infinity']} | {r['singular']} | {r['classes']} ({r['certified']}) "
            f"| {'yes' if r['distinct'] else 'no'} | {r['real']} |"
        )
    return "\n".join(lines)


def _commit() -> str:
    try:
        return subprocess.check_output(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True).strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problems", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--write", action="store_true", help="add the run to benches/results/")
    args = ap.parse_args()
    text = table(args.problems, args.seed)
    print(text)
    if args.write:
        stamp = text.split(" with ", 1)[0].removeprefix("Measured ")
        link = runlog.append_run("synthesis.py", stamp, text)
        runlog.set_latest("synthesis.py", f"[{stamp}]({link})")


if __name__ == "__main__":
    main()
