"""Starting designs for synthesis from a curve, from every direction: the atlas of
normalised coupler curves (its nearest curves placed on the target), Alt's nine-point
problem on nine points sampled along the target (every real four-bar through them), for
a timed target the four-bars of the five-point timed dyads, and random Grashof
crank-rockers. Each is a `Seed` (circuit, x, family) that `fit` takes in
``seeds``; every refined design keeps its seed's ``family``.

A four-bar through given points runs them at crank angles of its own: an atlas seed
takes, for each target point, the crank angle of its curve's nearest point (made
increasing); an Alt seed the crank angles of its nine positions, the others between
them by the same rule.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from ...errors import SynthesisError
from .atlas import Atlas
from .atlas import load as load_atlas
from .target import TargetCurve
from .tracking import TWO_PI, coupler_points

__all__ = [
    "Seed",
    "Seeds",
    "atlas_seeds",
    "alt_seeds",
    "five_along",
    "timed_seeds",
    "crank_angles_along",
    "design_vectors",
    "nine_along",
    "seed_error",
    "make_seeds",
]

# crank angles a seed's curve is sampled at to find each target point's nearest
_DENSE = 720


class Seed(NamedTuple):
    """A starting design: ``circuit`` ("open" or "crossed"), ``x`` (the full design
    vector of `TrackingProblem`) and ``family`` ("atlas", "alt", "timed", "random")."""

    circuit: str
    x: np.ndarray
    family: str


@dataclass
class Seeds:
    """`make_seeds`' answer: ``seeds`` (a list `fit` takes), per family the count kept and the
    wall time spent (``counts``, ``seconds``), and ``notes`` (what was dropped, and why)."""

    seeds: list[Seed]
    counts: dict[str, int]
    seconds: dict[str, float]
    notes: list[str]

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self.seeds)

    def __len__(self) -> int:
        return len(self.seeds)

    def report(self) -> str:
        parts = [f"{k} {self.counts[k]} ({self.seconds[k]:.2f} s)" for k in self.counts]
        return f"{len(self.seeds)} seeds: " + ", ".join(parts)


def crank_angles_along(x: Any, circuit: str, points: Any, closed: bool) -> np.ndarray:
    """For each of ``points`` (n x 2) the crank angle theta2 at which the coupler curve of
    design ``x`` (its first nine entries) comes nearest, made increasing: each step from
    one point to the next is taken as the signed nearest turn, a backward one as none (a
    closed curve's steps then fit one turn when the design runs the points' way)."""
    p = np.asarray(points, dtype=float)
    th = np.linspace(0.0, TWO_PI, _DENSE, endpoint=False)
    c = coupler_points(x, th, circuit)
    ok = np.all(np.isfinite(c), axis=1)
    if not ok.any():
        raise SynthesisError("the design does not assemble at any crank angle")
    th, c = th[ok], c[ok]
    near = th[np.argmin(np.sum((p[:, None, :] - c[None, :, :]) ** 2, axis=-1), axis=1)]
    step = np.remainder(np.diff(near) + math.pi, TWO_PI) - math.pi
    out = near[0] + np.concatenate([[0.0], np.cumsum(np.maximum(step, 0.0))])
    if closed and out[-1] - out[0] >= TWO_PI:
        out = out[0] + (out - out[0]) * (TWO_PI * (len(p) - 1) / len(p)) / (out[-1] - out[0])
    return out


def _with_angles(vector: Any, circuit: str, target: TargetCurve, family: str) -> Seed:
    v = np.asarray(vector, dtype=float)[:9]
    if target.crank_angles is not None:
        th = np.asarray(target.crank_angles, dtype=float)
    else:
        th = crank_angles_along(v, circuit, target.points, target.closed)
    return Seed(circuit, np.concatenate([v, th]), family)


def atlas_seeds(target: TargetCurve, k: int = 8, atlas: Atlas | None = None) -> list[Seed]:
    """The ``k`` atlas designs whose normalised coupler curves are nearest the target's
    (run in the target's direction: the tracking error keeps it), each placed on the
    target by the similarity of the two normalisations, with crank angles from
    `crank_angles_along` (or the target's prescribed ones)."""
    atlas = atlas if atlas is not None else load_atlas()
    hits = atlas.query(target.points, k=k, closed=target.closed, reverse=False)
    return [_with_angles(h.vector, h.circuit, target, "atlas") for h in hits]


def nine_along(target: TargetCurve) -> np.ndarray:
    """Nine points evenly spaced by arc length along the target's polygon (around it,
    for a closed curve; from its first point to its last, for an open one)."""
    p = np.asarray(target.points, dtype=float)
    ring = np.concatenate([p, p[:1]]) if target.closed else p
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(ring, axis=0).T))])
    at = np.linspace(0.0, s[-1], 10)[:-1] if target.closed else np.linspace(0.0, s[-1], 9)
    return np.column_stack([np.interp(at, s, ring[:, 0]), np.interp(at, s, ring[:, 1])])


def design_vectors(o2: Any, a: Any, o4: Any, b: Any, p: Any) -> tuple[str, np.ndarray] | None:
    """The design numbers [r1, r2, r3, r4, rcx, rcy, theta0, x0, y0] and circuit of the
    four-bar drawn with crank O2 -> A, coupler A -> B carrying P, rocker O4 -> B, and the
    crank angle it is drawn at; None if no circuit reproduces the drawing."""
    o2, a, o4, b, p = (np.asarray(v, dtype=float) for v in (o2, a, o4, b, p))
    g = o4 - o2
    th0 = math.atan2(g[1], g[0])
    t3 = math.atan2(b[1] - a[1], b[0] - a[0])
    c3, s3 = math.cos(t3), math.sin(t3)
    rc = np.array([[c3, s3], [-s3, c3]]) @ (p - a)
    r = [float(np.hypot(*v)) for v in (g, a - o2, b - a, b - o4)]
    x = np.array([*r, rc[0], rc[1], th0, o2[0], o2[1]])
    th2 = math.atan2(a[1] - o2[1], a[0] - o2[0]) - th0
    for circuit in ("open", "crossed"):
        c = coupler_points(x, [th2], circuit)[0]
        if np.all(np.isfinite(c)) and np.hypot(*(c - p)) <= 1e-7 * max(r):
            return circuit, np.concatenate([x, [th2]])
    return None


def _crank_rocker(r: np.ndarray) -> bool:
    """The crank (r[1]) the shortest link of a Grashof four-bar: it turns fully."""
    s = np.sort(r[:4])
    return bool(r[1] <= s[0] and s[0] + s[3] <= s[1] + s[2])


def seed_error(seed: Seed, target: TargetCurve) -> float:
    """The tracking error of a seed as it stands (closed form; infinity where it does
    not assemble)."""
    th = seed.x[9:] if target.crank_angles is None else np.asarray(target.crank_angles, dtype=float)
    c = coupler_points(seed.x, th, seed.circuit)
    return float(np.sum((c - target.points) ** 2)) if np.all(np.isfinite(c)) else math.inf


def alt_seeds(
    target: TargetCurve, seconds: float = 10.0, points: Any = None, keep: int | None = None
) -> tuple[list[Seed], dict[str, Any]]:
    """Every real four-bar of Alt's problem on nine points along the target (`nine_along`,
    or the nine ``points`` given), each of its dyads taken as the crank in turn, kept
    where that makes a Grashof crank-rocker; the homotopy stops after ``seconds``. With
    ``keep``, only that many, the smallest tracking error (`seed_error`) first. Also what
    it cost: {"seconds", "four_bars" (real ones found), "crank_rockers", "kept", "failed"}."""
    from ..exact import nine_points

    nine = nine_along(target) if points is None else np.asarray(points, dtype=float)
    t0 = time.perf_counter()
    res = nine_points(nine, screen=False, seconds=seconds)
    out: list[Seed] = []
    for d in res.designs:
        for o2, a, o4, b in ((d.o2, d.a, d.o4, d.b), (d.o4, d.b, d.o2, d.a)):
            mapped = design_vectors(o2, a, o4, b, d.p)
            if mapped is None or not _crank_rocker(mapped[1]):
                continue
            circuit, x = mapped
            if not np.all(np.isfinite(coupler_points(x, np.linspace(0.0, TWO_PI, 73), circuit))):
                continue  # the crank of a crank-rocker drawn on the other circuit's half
            out.append(_with_angles(x, circuit, target, "alt"))
    found = len(out)
    if keep is not None:
        out = sorted(out, key=lambda sd: seed_error(sd, target))[: max(int(keep), 0)]
    info = {
        "seconds": time.perf_counter() - t0,
        "four_bars": len(res.designs),
        "crank_rockers": found,
        "kept": len(out),
        "failed": int(res.failed),
    }
    return out, info


def five_along(target: TargetCurve) -> np.ndarray:
    """The indices of five target points spread evenly by index, first and last included."""
    n = len(target)
    if n < 5:
        raise SynthesisError(f"the timed dyads need five timed points, the target has {n}")
    return np.unique(np.round(np.linspace(0.0, n - 1.0, 5)).astype(int))


def timed_seeds(target: TargetCurve, keep: int | None = None) -> tuple[list[Seed], dict[str, Any]]:
    """Four-bars from the five-point timed dyads of a timed target: on five of its points
    (`five_along`) every real crank dyad (ground pivot G, pin A) whose pin turns by the
    prescribed crank angles with |P - A| the same at all five (`linkwork.synthesis.dyad`,
    "timed"); its pins give the coupler's rotation at each point, and every real
    Burmester dyad of those five poses is a rocker for it. Each pair is a four-bar through
    the five points at the prescribed crank increments, kept where it is a Grashof
    crank-rocker; its crank angles are the target's (measured from the ground line: the
    four-bar meets them up to one constant, the condition the dyads do not impose). With
    ``keep``, the smallest tracking error (`seed_error`) first. Also what it cost:
    {"seconds", "cranks" (real timed dyads), "four_bars", "kept"}."""
    from ..dyad import dyads

    if not target.timed:
        raise SynthesisError("the timed dyads need a target with prescribed crank angles")
    t0 = time.perf_counter()
    idx = five_along(target)
    p = np.asarray(target.points, dtype=float)[idx]
    turn = np.exp(1j * (np.asarray(target.crank_angles, dtype=float)[idx] - target.crank_angles[idx[0]]))
    pc = p[:, 0] + 1j * p[:, 1]
    out: list[Seed] = []
    cranks = dyads("timed", points=p, input_angles=np.angle(turn)).real
    for crank in cranks:
        g, a1 = complex(*crank.ground), complex(*crank.moving)
        pins = g + (a1 - g) * turn
        theta = np.angle((pc - pins) / (pc[0] - pins[0]))
        try:
            rockers = dyads("burmester", poses=np.column_stack([p, theta])).real
        except SynthesisError:
            continue
        for rocker in rockers:
            if np.allclose(rocker.ground, crank.ground, atol=1e-9) and np.allclose(
                rocker.moving, crank.moving, atol=1e-9
            ):
                continue  # the crank dyad itself solves the poses
            mapped = design_vectors(crank.ground, crank.moving, rocker.ground, rocker.moving, p[0])
            if mapped is None or not _crank_rocker(mapped[1]):
                continue
            circuit, x = mapped
            if not np.all(np.isfinite(coupler_points(x, np.linspace(0.0, TWO_PI, 73), circuit))):
                continue
            out.append(_with_angles(x, circuit, target, "timed"))
    found = len(out)
    if keep is not None:
        out = sorted(out, key=lambda sd: seed_error(sd, target))[: max(int(keep), 0)]
    info = {"seconds": time.perf_counter() - t0, "cranks": len(cranks), "four_bars": found, "kept": len(out)}
    return out, info


def make_seeds(
    target: TargetCurve,
    atlas: int = 8,
    alt: int = 16,
    random: int = 8,
    seed: int = 0,
    seconds: float = 10.0,
    atlas_data: Atlas | None = None,
    timed: int = 16,
) -> Seeds:
    """Starting designs from every direction: ``atlas`` atlas seeds, ``alt`` of Alt's
    crank-rockers through nine points of the target (the smallest tracking error as seeds
    first; its homotopy bounded by ``seconds``), for a timed target ``timed`` four-bars
    of the five-point timed dyads (`timed_seeds`, the smallest tracking error first) and
    ``random`` random crank-rockers (`random_seeds`, ``seed``)."""
    from .fit import random_seeds

    out: list[Seed] = []
    counts: dict[str, int] = {}
    spent: dict[str, float] = {}
    notes: list[str] = []
    if atlas:
        t0 = time.perf_counter()
        got = atlas_seeds(target, atlas, atlas_data)
        out += got
        counts["atlas"], spent["atlas"] = len(got), time.perf_counter() - t0

    def exact(family: str, label: str, make: Any, line: str) -> None:
        # an exact family: its seeds, or why there are none, in the notes
        t0 = time.perf_counter()
        try:
            got, info = make()
            notes.append(f"{label}: " + line.format(**info))
        except SynthesisError as e:
            got = []
            notes.append(f"{label}: {e}")
        out.extend(got)
        counts[family], spent[family] = len(got), time.perf_counter() - t0

    if alt:
        exact(
            "alt",
            "Alt",
            lambda: alt_seeds(target, seconds, keep=alt),
            "{four_bars} real four-bars (with cognates), {crank_rockers} crank-rocker seeds, "
            "{kept} kept, {failed} paths failed, {seconds:.2f} s",
        )
    if timed and target.timed:
        exact(
            "timed",
            "timed dyads",
            lambda: timed_seeds(target, keep=timed),
            "{cranks} real cranks, {four_bars} crank-rockers, {kept} kept, {seconds:.2f} s",
        )
    if random:
        t0 = time.perf_counter()
        got = [Seed(c, x, "random") for c, x in random_seeds(target, random, seed)]
        out += got
        counts["random"], spent["random"] = len(got), time.perf_counter() - t0
    return Seeds(out, counts, spent, notes)
