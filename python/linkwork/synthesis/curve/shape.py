"""The shape problem of synthesis from a curve: a four-bar whose coupler curve has the
target's shape, its position, rotation, scale and starting point free. The objective is
the mean nearest distance from the target points to the traced curve after the best
similarity transform (`shape_error`, the figure of Ullah and Kota 1997 and four-bar-rs).

It is refined through its least-squares surrogate: the tracking error with the crank
angles free (`fit`), whose design vector already carries position, rotation and scale
(theta0, x0, y0 and the lengths) and whose free crank angles make each residual, at the
optimum, the point's distance normal to the curve. The seeds are the atlas's nearest
curves, the target run either way (the shape has no direction), refined in rounds,
nearest first, until two refined designs agree on the best; each refined design is
then scored by `shape_error` and moved by its similarity onto the target, and, with
``polish``, the mean nearest distance itself is minimised from the best of them over the
nine design numbers and the crank angles, by reweighted least squares on all the points
(each point weighted by 1 / sqrt of its distance, the exact Jacobian, the crank turning
fully), reweighted until the mean stops moving.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import SynthesisError
from .atlas import Atlas
from .atlas import load as load_atlas
from .descriptors import ShapeFit, nearest_distances, shape_error
from .fit import CurveDesign, fit, random_seeds, refine
from .seeds import Seed, crank_angles_along
from .target import TargetCurve
from .target import target as make_target
from .threads import one_blas_thread
from .tracking import TWO_PI, CircuitError, TrackingProblem, coupler_points

__all__ = ["ShapeDesign", "ShapeResult", "shape_fit", "traced", "moved"]

# crank angles the traced curve is sampled at for the nearest distances
_TRACE = 720
# the seeds are refined in rounds of _ROUND, nearest first; after a round in which AGREE
# refined designs come within the fraction _AGREE_TOL of the best mean, the rest are left
# (several starts that fall into the best basin: more seldom find a better one)
_ROUND = 4
AGREE = 2
_AGREE_TOL = 0.01
# the polish reweights after every _POLISH_NFEV evaluations (a reweighting often converges
# faster in time than refining each weighting to its end), more where a round stalls, and
# stops where a round of max_nfev moves the mean nearest distance by less than the
# fraction _POLISH_GAIN
_POLISH_NFEV = 10
_POLISH_GAIN = 1e-5


def traced(x: Any, circuit: str, steps: int = _TRACE) -> np.ndarray:
    """The coupler curve of design ``x`` (its first nine numbers) over a crank turn
    (steps x 2, closed form; NaN where it does not assemble)."""
    return coupler_points(x, np.linspace(0.0, TWO_PI, int(steps), endpoint=False), circuit)


def moved(x: Any, sim: ShapeFit) -> np.ndarray:
    """The design numbers of ``x`` moved by the similarity ``sim`` (a point q of its
    curve to scale R(rotation) q + offset): lengths and coupler point scaled, the ground
    line turned, the pivot O2 carried."""
    x = np.array(x, dtype=float)
    c, s = math.cos(sim.rotation), math.sin(sim.rotation)
    out = x.copy()
    out[:6] = sim.scale * x[:6]
    out[6] = math.remainder(x[6] + sim.rotation, TWO_PI)  # within the refinement's bounds
    out[7:9] = sim.scale * np.array([c * x[7] - s * x[8], s * x[7] + c * x[8]]) + sim.offset
    return out


@dataclass
class ShapeDesign:
    """A design for the shape problem: ``x`` (the nine design numbers, placed on the
    target), ``circuit``, ``mean`` and ``largest`` nearest distance from the target
    points to its traced curve, ``family`` of its seed, ``reverse`` (the target run
    backwards in its tracking refinement), ``tracking`` (that refinement's design)."""

    x: np.ndarray
    circuit: str
    mean: float
    largest: float
    family: str
    reverse: bool
    tracking: CurveDesign | None

    def curve(self, steps: int = _TRACE) -> np.ndarray:
        return traced(self.x, self.circuit, steps)

    def __str__(self) -> str:
        r = ", ".join(f"{k} {v:.6g}" for k, v in zip(("r1", "r2", "r3", "r4", "rcx", "rcy"), self.x[:6]))
        return (
            f"mean nearest distance {self.mean:.4g} (largest {self.largest:.4g}); {r}; "
            f"theta0 {self.x[6]:.6g}, O2 ({self.x[7]:.6g}, {self.x[8]:.6g}); {self.circuit}; "
            f"from {self.family}"
        )


@dataclass
class ShapeResult:
    """`shape_fit`'s answer: ``designs`` by mean nearest distance, ``seconds`` (wall),
    ``unrefined`` (seeds the agreement rule left unrefined)."""

    designs: list[ShapeDesign]
    seconds: float
    unrefined: int = 0

    @property
    def best(self) -> ShapeDesign:
        if not self.designs:
            raise SynthesisError("no starting design could be refined for the shape problem")
        return self.designs[0]

    def report(self, count: int = 5) -> str:
        lines = [f"{len(self.designs)} designs in {self.seconds:.2f} s, by mean nearest distance"]
        if self.unrefined:
            lines[0] += f" ({self.unrefined} seeds left: {AGREE} starts agreed on the best)"
        lines += [f"{k + 1}. {d}" for k, d in enumerate(self.designs[:count])]
        return "\n".join(lines)


def _score(points: np.ndarray, x: np.ndarray, circuit: str) -> tuple[np.ndarray, float, float] | None:
    """The design placed on the points: as it is or moved by the similarity `shape_error`
    finds, whichever leaves the smaller mean nearest distance (a refined design is often
    placed better than a similarity found afresh); its mean and largest nearest distance.
    None if it does not turn fully."""
    c = traced(x, circuit)
    if not np.all(np.isfinite(c)):
        return None
    y = moved(x, shape_error(points, c, polish=False))
    found = []
    for z in (np.asarray(x, dtype=float), y):
        d = nearest_distances(points, traced(z, circuit))
        found.append((float(d.mean()), float(d.max()), z))
    mean, largest, z = min(found, key=lambda f: f[0])
    return z, mean, largest


def _polish(
    points: np.ndarray, design: ShapeDesign, rounds: int, max_nfev: int, problem: dict[str, Any]
) -> np.ndarray | None:
    """The mean nearest distance itself minimised from ``design``, by iteratively
    reweighted least squares on the tracking error over all the points, crank angles
    free: each round weights a point by 1 / sqrt(its distance), so the weighted sum of
    squares is the sum of distances at the round's start (Weiszfeld's device), and
    refines with the exact Jacobian. A round first spends _POLISH_NFEV evaluations; one
    that moves the mean by less than the fraction _POLISH_GAIN of the round before's
    gives the next four times as many (a short round can stall where its trust region
    starts too wide), and at ``max_nfev`` it is the last (converged); at most ``rounds``
    rounds. The nine design numbers of the best round by the mean nearest distance; None
    if no round improves on ``design``."""
    # the points run the way the design runs them: the one its crank angles fit better
    starts = []
    for way in (points, points[::-1]):
        x = np.concatenate([design.x, crank_angles_along(design.x, design.circuit, way, True)])
        c = coupler_points(x, x[9:], design.circuit)
        starts.append((float(np.sum((c - way) ** 2)), way, x))
    _, way, x = min(starts, key=lambda s: s[0])
    tracking = TrackingProblem(make_target(way, closed=True), circuit=design.circuit, **problem)
    best, found, last = design.mean, None, math.inf
    nfev = min(_POLISH_NFEV, int(max_nfev))
    for _ in range(int(rounds)):
        c = coupler_points(x, x[9:], design.circuit)
        d = np.hypot(*(c - way).T)
        # a floor on the distances keeps a point on the curve from taking all the weight
        w = 1.0 / np.sqrt(np.maximum(d, 1e-3 * max(float(d.mean()), 1e-300)))
        try:
            with one_blas_thread():
                x = refine(tracking, x, max_nfev=nfev, weights=w / w.max()).x
        except (CircuitError, SynthesisError):
            break
        scored = _score(points, x[:9], design.circuit)
        if scored is None:
            break
        if scored[1] < best:
            best, found = scored[1], x[:9].copy()
        # (the first round may rise above the start: its weights are the start's)
        if abs(last - scored[1]) < _POLISH_GAIN * last:
            if nfev >= max_nfev:
                break
            nfev = min(4 * nfev, int(max_nfev))
        last = scored[1]
    return found


def shape_fit(
    target: TargetCurve | Any,
    k: int = 12,
    random: int = 0,
    seed: int = 0,
    atlas: Atlas | None = None,
    workers: int | None = None,
    max_nfev: int = 200,
    polish: int = 24,
    refine_points: int = 36,
    agree: int | None = AGREE,
    **problem: Any,
) -> ShapeResult:
    """The shape problem for a closed ``target`` (a `TargetCurve` or an n x 2 array):
    the ``k`` (12) nearest atlas curves (and ``random`` (0) random crank-rockers drawn
    with ``seed`` (0)) as seeds, each refined by the tracking error with free crank
    angles (`fit`, at most ``max_nfev`` (200) evaluations a weight; ``problem``: its
    options, bounds and constraints), scored by the mean nearest distance after the best
    similarity, the best polished by reweighted least squares on all the points, which
    minimise that mean distance itself, until a round moves it by less than 1e-5 of it
    or ``polish`` (24) rounds have run (0: none). The tracking refinement runs on at most
    ``refine_points`` (36; 4 at the least) of the points, every s-th with the smallest
    such s (its cost grows with their count), the scores on all of them. The seeds are
    refined in rounds of 4, nearest first, until ``agree`` refined designs (default 2)
    come within 1 % of the best mean nearest distance (None or 0: every seed)."""
    t0 = time.perf_counter()
    tc = target if isinstance(target, TargetCurve) else make_target(target, closed=True)
    if tc.timed:
        raise SynthesisError("the shape problem has free timing: the target must not prescribe crank angles")
    pts = np.asarray(tc.points, dtype=float)
    step = max(1, math.ceil(len(pts) / max(int(refine_points), 4)))
    sub = pts[::step]
    ways = {False: make_target(sub, closed=tc.closed), True: make_target(sub[::-1], closed=tc.closed)}
    atlas = atlas if atlas is not None else load_atlas()
    seeds: list[tuple[bool, Seed]] = []
    for h in atlas.query(pts, k=k, closed=tc.closed):
        way = ways[h.reverse]
        th = crank_angles_along(h.vector, h.circuit, way.points, way.closed)
        seeds.append((h.reverse, Seed(h.circuit, np.concatenate([h.vector, th]), "atlas")))
    seeds += [(False, Seed(c, x, "random")) for c, x in random_seeds(ways[False], random, seed)]
    designs: list[ShapeDesign] = []
    done = 0
    while done < len(seeds) and not (agree and _agreed(designs, int(agree), tc.size)):
        chunk, done = seeds[done : done + _ROUND], done + _ROUND
        for rev in (False, True):
            group = [sd for r, sd in chunk if r == rev]
            if not group:
                continue
            result = fit(ways[rev], seeds=group, workers=workers, max_nfev=max_nfev, **problem)
            for d in result.designs:
                scored = _score(pts, d.x[:9], d.circuit)
                if scored is not None:
                    y, mean, largest = scored
                    designs.append(ShapeDesign(y, d.circuit, mean, largest, d.family, rev, d))
    designs.sort(key=lambda d: d.mean)
    if polish and designs:
        b = designs[0]
        y = _polish(pts, b, int(polish), max_nfev, problem)
        scored = None if y is None else _score(pts, y, b.circuit)
        if scored is not None and scored[1] < b.mean:
            y, mean, largest = scored
            designs.insert(0, ShapeDesign(y, b.circuit, mean, largest, b.family, b.reverse, None))
    return ShapeResult(designs, time.perf_counter() - t0, max(len(seeds) - done, 0))


def _agreed(designs: list[ShapeDesign], agree: int, size: float) -> bool:
    """``agree`` designs within the fraction _AGREE_TOL of the best mean (or 1e-12
    target sizes of it: a curve a four-bar traces exactly)."""
    if not designs:
        return False
    best = min(d.mean for d in designs)
    return sum(d.mean <= (1.0 + _AGREE_TOL) * best + 1e-12 * size for d in designs) >= agree
