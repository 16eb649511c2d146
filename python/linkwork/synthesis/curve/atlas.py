"""An atlas of normalised four-bar coupler curves: seeds for synthesis from a curve.

Each design is a four-bar with ground 1 (O2 = (0, 0), O4 = (1, 0)), crank, coupler and
rocker ratios and a coupler point (rcx, rcy) in the coupler's frame (at A, x towards B),
on one circuit ("open" or "crossed", as `linkwork.build.four_bar`), of a Grashof type
whose crank turns fully (crank-rocker or double-crank). The lengths are sampled
log-uniformly in [1/6, 6] (the range four-bar-rs samples), the coupler point at a
distance log-uniform in [1/6, 6] coupler lengths from A in a uniform direction. The
engine sweeps every linkage over one crank turn on its circuit (`linkwork.sweep_batch`
on its threads, every model started on the circuit asked; blocks of designs as tasks of a
Dask cluster), keeping the coupler's angle theta3; the coupler points of a linkage follow from it,
C = A + R(theta3) (rcx, rcy), and each curve is reduced to its normalised elliptic Fourier
descriptors (`descriptors`). A query finds the nearest descriptors (`scipy.spatial.cKDTree`)
and maps each hit back to a design in the target's frame (the similarity transform the
two normalisations give).

The shipped atlas (`load()`) is small; `build_atlas(n, seed)` builds a larger one
(in-process, or on a Dask cluster with ``scheduler``), `Atlas.save` keeps it.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..._args import requires
from ...errors import SynthesisError
from .descriptors import HARMONICS, coefficients, descriptors, flip_even, normalise

__all__ = [
    "STEPS",
    "RATIO",
    "DEFAULT",
    "Atlas",
    "AtlasHit",
    "sample_designs",
    "coupler_curves",
    "trace_block",
    "build_atlas",
    "load",
]

#: Crank angles a coupler curve is traced at (one turn).
STEPS = 180
#: Link ratios and coupler-point distances are sampled in [1 / RATIO, RATIO].
RATIO = 6.0
#: Coupler points drawn on each swept linkage (they share its sweep).
POINTS_PER_LINKAGE = 4
#: The shipped atlas.
DEFAULT = Path(__file__).with_name("data") / "four_bar_atlas.npz"
CIRCUITS = ("open", "crossed")


def _full_turn(r2: np.ndarray, r3: np.ndarray, r4: np.ndarray) -> np.ndarray:
    """Whether a four-bar of ground 1 has a crank that turns fully: Grashof (s + l < p +
    q, strictly: no change point) with the crank or the ground shortest."""
    links = np.stack([np.ones_like(r2), r2, r3, r4], axis=-1)
    s, l_ = links.min(axis=-1), links.max(axis=-1)
    grashof = s + l_ < links.sum(axis=-1) - s - l_ - 1e-9
    return grashof & ((r2 == s) | (s == 1.0))


def sample_designs(n: int, seed: int | None = 0, points_per_linkage: int = POINTS_PER_LINKAGE) -> np.ndarray:
    """``n`` normalised designs (n, 7): [r1 = 1, r2, r3, r4, rcx, rcy, circuit] (circuit 0
    "open", 1 "crossed"), ``points_per_linkage`` consecutive rows sharing one linkage,
    half of the linkages on each circuit. Reproducible with ``seed``."""
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise SynthesisError(f"an atlas needs a positive number of designs, got {n!r}")
    k = int(points_per_linkage)
    rng = np.random.default_rng(seed)
    m = -(-n // k)
    found: list[np.ndarray] = []
    count = 0
    lo, hi = math.log(1.0 / RATIO), math.log(RATIO)
    while count < m:
        r = np.exp(rng.uniform(lo, hi, (2 * m + 16, 3)))
        ok = r[_full_turn(r[:, 0], r[:, 1], r[:, 2])]
        found.append(ok)
        count += len(ok)
    links = np.concatenate(found)[:m]
    circuit = np.arange(m) % 2
    dist = np.exp(rng.uniform(lo, hi, (m, k))) * links[:, 1:2]
    angle = rng.uniform(0.0, 2.0 * math.pi, (m, k))
    rows = np.column_stack(
        [
            np.ones(m * k),
            np.repeat(links, k, axis=0),
            (dist * np.cos(angle)).ravel(),
            (dist * np.sin(angle)).ravel(),
            np.repeat(circuit, k),
        ]
    )
    return rows[:n]


def _models(links: np.ndarray, circuit: int) -> tuple[list[Any], Any]:
    """A compiled model of each linkage (r2, r3, r4) of ground 1, its pins given in its
    bodies' frames and drawn at crank angle 0 on ``circuit`` (the closed form's
    configuration there, so the drawing is not singular); and the base model whose
    assembly mode every sweep starts on (`sweep_batch`'s ``branches_of``)."""
    from ...mechanism.lengths import four_bar
    from ...model.compiled import Model
    from ...reference import closed_form

    branch = CIRCUITS[circuit]
    mech = four_bar(ground=1.0, crank=0.3, coupler=1.0, rocker=1.0, branch=branch, omega=1.0)
    base = mech.compile()
    template = mech.to_dict()
    models = []
    for r2, r3, r4 in links.tolist():
        start = closed_form.four_bar(1.0, r2, r3, r4, 0.0, 1.0, 0.0, branch)
        d = copy.deepcopy(template)
        joints = {j["name"]: j for j in d["joints"]}
        joints["A"]["pin_a"] = [r2, 0.0]
        joints["B"]["pin_a"], joints["B"]["pin_b"] = [r3, 0.0], [r4, 0.0]
        bodies = {b["name"]: b for b in d["bodies"]}
        bodies["coupler"].update(x=r2, y=0.0, theta=float(start["theta3"]))
        bodies["rocker"].update(x=1.0, y=0.0, theta=float(start["theta4"]))
        models.append(Model(d))
    return models, base


def _theta3(
    links: np.ndarray, circuit: int, times: np.ndarray, threads: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The coupler angle of each linkage (r2, r3, r4) over ``times`` on ``circuit``,
    swept by the engine (`sweep_batch`, its threads); and whether its sweep succeeded."""
    from ...model.compiled import sweep_batch

    models, base = _models(links, circuit)
    swept = sweep_batch(models, times, threads=threads, derivatives=0, errors="return", branches_of=base)
    theta = np.full((len(links), len(times)), np.nan)
    ok = np.zeros(len(links), dtype=bool)
    for i, res in enumerate(swept):
        if not isinstance(res, Exception):
            theta[i], ok[i] = res.body("coupler").theta, True
    return theta, ok & np.all(np.isfinite(theta), axis=1)


def trace_block(
    designs: np.ndarray, steps: int, harmonics: int, threads: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """One task of an atlas build: the normalised descriptors (n, H, 4) and poses (n, 4)
    of a block of designs (rows of `sample_designs`, whole linkages), float32; NaN where
    a sweep failed or a curve cannot be normalised. ``threads``: the engine's (default one
    a core)."""
    designs = np.asarray(designs, dtype=np.float64)
    times = np.linspace(0.0, 2.0 * math.pi, int(steps), endpoint=False)
    k = POINTS_PER_LINKAGE
    desc = np.full((len(designs), harmonics, 4), np.nan)
    pose = np.full((len(designs), 4), np.nan)
    first = np.arange(0, len(designs), k)
    for c in (0, 1):
        heads = first[designs[first, 6] == c]
        if not len(heads):
            continue
        theta, ok = _theta3(designs[heads, 1:4], c, times, threads)
        rows = (heads[:, None] + np.arange(k)).ravel()
        th = np.repeat(theta, k, axis=0)
        good = np.repeat(ok, k) & (rows < len(designs))
        rows, th = rows[good], th[good]
        desc[rows], pose[rows] = _reduce(coupler_curves(designs[rows], th, times), harmonics)
    return desc.astype(np.float32), pose.astype(np.float32)


def coupler_curves(designs: np.ndarray, theta3: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Coupler curves (n, steps, 2) of designs [r1, r2, r3, r4, rcx, rcy, ...] from their
    coupler angles (n, steps) at crank angles ``times``: C = A + R(theta3) (rcx, rcy)."""
    r2, rcx, rcy = designs[:, 1:2], designs[:, 4:5], designs[:, 5:6]
    c, s = np.cos(theta3), np.sin(theta3)
    x = r2 * np.cos(times) + rcx * c - rcy * s
    y = r2 * np.sin(times) + rcx * s + rcy * c
    return np.stack([x, y], axis=-1)


def _reduce(curves: np.ndarray, harmonics: int, block: int = 512) -> tuple[np.ndarray, np.ndarray]:
    """Normalised descriptors (n, H, 4) and poses (n, 4) [locus x, y, scale, psi] of the
    curves, a block at a time (bounded memory); a curve that cannot be normalised (its
    first harmonic a circle) gets NaN."""
    n = len(curves)
    desc = np.full((n, harmonics, 4), np.nan)
    pose = np.full((n, 4), np.nan)
    for s in range(0, n, block):
        co, locus = coefficients(curves[s : s + block], harmonics)
        try:
            nd = normalise(co, locus)
            desc[s : s + block], pose[s : s + block] = nd.coeffs, np.column_stack([locus, nd.scale, nd.psi])
        except SynthesisError:  # one circle in the block: the block one curve at a time
            for i in range(len(co)):
                try:
                    nd = normalise(co[i], locus[i])
                except SynthesisError:
                    continue
                desc[s + i], pose[s + i] = nd.coeffs, [*locus[i], nd.scale, nd.psi]
    return desc, pose


def build_atlas(
    n: int,
    seed: int | None = 0,
    scheduler: Any = None,
    harmonics: int = HARMONICS,
    steps: int = STEPS,
    block: int = 8192,
) -> Atlas:
    """An atlas of ``n`` sampled designs (`sample_designs`), traced by the engine and
    reduced to ``harmonics`` descriptors, ``block`` designs a task (`trace_block`: only
    descriptors travel back, and memory stays bounded). ``scheduler``: None (in-process,
    the engine's threads), "local" (a local Dask cluster for the call, a worker a core),
    a scheduler address or a `distributed.Client`. Designs whose sweep fails (none should:
    each has a crank that turns fully) or whose curve cannot be normalised are left out;
    ``meta["dropped"]`` counts them. The same ``n`` and ``seed`` give the same atlas
    in-process and on any cluster."""
    designs = sample_designs(n, seed)
    harmonics = int(harmonics)
    k = POINTS_PER_LINKAGE
    size = max(k, int(block) // k * k)
    parts = [designs[s : s + size] for s in range(0, len(designs), size)]
    if scheduler is None:
        done = [trace_block(p, steps, harmonics) for p in parts]
    else:
        done = _on_dask(parts, steps, harmonics, scheduler)
    desc = np.concatenate([d for d, _ in done])
    pose = np.concatenate([p for _, p in done])
    keep = np.all(np.isfinite(pose), axis=1) & np.all(np.isfinite(desc), axis=(1, 2))
    meta = {
        "seed": -1 if seed is None else int(seed),
        "steps": int(steps),
        "ratio": RATIO,
        "points_per_linkage": k,
        "dropped": int(np.count_nonzero(~keep)),
    }
    return Atlas(designs[keep].astype(np.float32), pose[keep], desc[keep], meta)


def _on_dask(parts: list[np.ndarray], steps: int, harmonics: int, scheduler: Any) -> list[Any]:
    """The blocks traced as tasks of a Dask cluster, in order."""
    distributed = requires("distributed")
    close: list[Any] = []
    if isinstance(scheduler, distributed.Client):
        client = scheduler
    elif scheduler == "local":
        cluster = distributed.LocalCluster(threads_per_worker=1, processes=True, dashboard_address=None)
        client = distributed.Client(cluster)
        close = [client, cluster]
    elif isinstance(scheduler, str) and scheduler:
        client = distributed.Client(scheduler, timeout="20s", set_as_default=False)
        close = [client]
    else:
        raise SynthesisError(
            f"scheduler must be None (in-process), 'local', a scheduler address or a distributed.Client, "
            f"not {scheduler!r}"
        )
    try:
        futures = client.map(_worker_task, parts, steps=steps, harmonics=harmonics, pure=False)
        return list(client.gather(futures))
    finally:
        for c in close:
            c.close()


def _worker_task(designs: np.ndarray, steps: int, harmonics: int) -> tuple[np.ndarray, np.ndarray]:
    """A block on a Dask worker, on as many engine threads as the worker has."""
    from distributed import get_worker

    try:
        threads = get_worker().state.nthreads
    except (ValueError, AttributeError):
        threads = None
    return trace_block(designs, steps, harmonics, threads)


@dataclass(frozen=True)
class AtlasHit:
    """An atlas design matched to a target: ``index`` in the atlas, ``distance`` between
    descriptors, ``design`` its normalised row [r1, r2, r3, r4, rcx, rcy, circuit] (for
    a mirrored hit, the mirror image of the atlas's: rcy negated, the other circuit),
    ``circuit`` ("open" or "crossed"), ``reverse`` (the target matched run backwards),
    the similarity transform onto the target (``scale``, ``rotation``, ``offset``) and
    ``mirrored`` (the atlas design's mirror image is the one that matched)."""

    index: int
    distance: float
    design: np.ndarray
    circuit: str
    reverse: bool
    scale: float
    rotation: float
    offset: np.ndarray
    mirrored: bool = False

    @property
    def vector(self) -> np.ndarray:
        """The design in the target's frame: [r1, r2, r3, r4, rcx, rcy, theta0, x0, y0]
        (the coupler point C(theta2) = R(theta0) [r2 cos theta2 + rcx cos theta3 - rcy sin
        theta3, r2 sin theta2 + rcx sin theta3 + rcy cos theta3] + [x0, y0])."""
        r = self.scale * np.asarray(self.design[:6], dtype=np.float64)
        return np.array([*r, self.rotation, *self.offset])

    def model(self, omega: float = 1.0) -> Any:
        """The design as a compiled model in its own frame (O2 at the origin, O4 on +x,
        lengths scaled to the target; the coupler point "P"); ``vector`` places it."""
        from ...mechanism.lengths import four_bar

        r1, r2, r3, r4, rcx, rcy = (float(v) for v in self.vector[:6])
        return four_bar(r1, r2, r3, r4, branch=self.circuit, coupler_point=(rcx, rcy), omega=omega).compile()

    def curve(self, steps: int = 360) -> np.ndarray:
        """The coupler curve (steps, 2) over one crank turn, traced by the engine, in the
        target's frame."""
        times = np.linspace(0.0, 2.0 * math.pi, int(steps), endpoint=False)
        p = self.model().sweep(times, derivatives=0).point("P").position
        c, s = math.cos(self.rotation), math.sin(self.rotation)
        return p @ np.array([[c, s], [-s, c]]) + self.offset


class Atlas:
    """Designs (n, 7) [r1, r2, r3, r4, rcx, rcy, circuit], their curves' poses (n, 4)
    [locus x, y, scale, psi] and normalised descriptors (n, H, 4), float32, with a
    k-d tree on the descriptors. ``meta``: how it was built."""

    def __init__(self, designs: np.ndarray, poses: np.ndarray, descriptors: np.ndarray, meta: dict[str, Any]):
        from scipy.spatial import cKDTree

        self.designs, self.poses, self.descriptors, self.meta = designs, poses, descriptors, dict(meta)
        if len(designs) == 0:
            raise SynthesisError("an atlas needs at least one design")
        self.harmonics = int(descriptors.shape[1])
        self.tree = cKDTree(descriptors.reshape(len(descriptors), -1).astype(np.float64))

    def __len__(self) -> int:
        return len(self.designs)

    def __repr__(self) -> str:
        return f"<Atlas: {len(self)} four-bar designs, {self.harmonics} harmonics>"

    def save(self, path: str | Path) -> None:
        """Writes the atlas as a compressed .npz."""
        meta = np.array([[k, str(v)] for k, v in self.meta.items()])
        np.savez_compressed(
            path, designs=self.designs, poses=self.poses, descriptors=self.descriptors, meta=meta
        )

    @classmethod
    def read(cls, path: str | Path) -> Atlas:
        """An atlas saved by `save`."""
        try:
            with np.load(path, allow_pickle=False) as f:
                meta = {str(k): str(v) for k, v in f["meta"]}
                return cls(f["designs"], f["poses"], f["descriptors"], meta)
        except (OSError, KeyError, ValueError) as e:
            raise SynthesisError(f"cannot read an atlas from {path}: {e}") from e

    def query(
        self, points: Any, k: int = 5, closed: bool = True, reverse: bool | None = None, mirror: bool = True
    ) -> list[AtlasHit]:
        """The ``k`` designs whose normalised coupler curves are nearest the curve through
        ``points`` (m, 2), best first, each mapped onto the target. ``reverse``: None tries
        the target both ways (the shape objective ignores direction), False or True one.
        ``mirror``: also match the target's mirror image, each such hit the mirror image
        of its atlas design (a mirrored four-bar traces the mirrored curve), which
        doubles the atlas at the cost of a second set of lookups."""
        if not isinstance(k, (int, np.integer)) or k < 1:
            raise SynthesisError(f"k must be a positive integer, got {k!r}")
        k = min(int(k), len(self))
        ways = (False, True) if reverse is None else (bool(reverse),)
        found: dict[tuple[int, bool], AtlasHit] = {}
        pts = np.asarray(points, dtype=np.float64)
        for mirrored in (False, True) if mirror else (False,):
            for rev in ways:
                # a mirrored four-bar turning its crank forwards runs the mirrored curve
                # backwards: the direction asked is the other one on the mirror image
                seen = pts * [1.0, -1.0] if mirrored else pts
                t = descriptors(seen, self.harmonics, closed, reverse=rev != mirrored)
                for flipped in (False, True):
                    q = flip_even(t.coeffs) if flipped else t.coeffs
                    dist, idx = self.tree.query(q.reshape(-1), k=k)
                    for d, i in zip(np.atleast_1d(dist), np.atleast_1d(idx)):
                        key = (int(i), mirrored)
                        if key not in found or d < found[key].distance:
                            found[key] = self._hit(int(i), float(d), t, flipped, rev, mirrored)
        return sorted(found.values(), key=lambda h: (h.distance, h.mirrored))[:k]

    def _hit(
        self, i: int, dist: float, target: Any, flipped: bool, reverse: bool, mirrored: bool = False
    ) -> AtlasHit:
        lx, ly, scale_d, psi_d = (float(v) for v in self.poses[i])
        scale = float(target.scale) / scale_d
        rot = math.remainder(float(target.psi) + (math.pi if flipped else 0.0) - psi_d, 2.0 * math.pi)
        c, s = math.cos(rot), math.sin(rot)
        offset = np.asarray(target.locus, dtype=np.float64) - scale * np.array(
            [c * lx - s * ly, s * lx + c * ly]
        )
        row = np.array(self.designs[i], dtype=np.float64)
        if mirrored:
            # the mirror M (y -> -y) of the design and of the similarity S: M S M is
            # s R(-a) q + M t; the design's coupler point mirrored, its circuit the other
            row[5], row[6] = -row[5], 1.0 - row[6]
            rot, offset = -rot, offset * [1.0, -1.0]
        return AtlasHit(i, dist, row, CIRCUITS[int(row[6])], reverse, scale, rot, offset, mirrored)


_LOADED: dict[str, Atlas] = {}


def load(path: str | Path | None = None) -> Atlas:
    """The shipped atlas (read once), or the one saved at ``path``."""
    key = str(DEFAULT if path is None else path)
    if key not in _LOADED:
        _LOADED[key] = Atlas.read(key)
    return _LOADED[key]
