"""More precision points than the exact methods take: `motion_least_squares` and
`path_least_squares`, from the exact dyads of five-point subsets refined by least
squares (SciPy), with bounds on link lengths and the transmission angle."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import SynthesisError
from .designs import FourBarDesign, Synthesis, _merit, _pair_designs
from .dyad import POSITION_TOLERANCE, Dyad, DyadSolutions, _angles, _array, dyads

__all__ = ["motion_least_squares", "path_least_squares"]


def _least_squares() -> Any:
    try:
        from scipy.optimize import least_squares
    except ImportError:  # pragma: no cover - optional dependency
        raise SynthesisError(
            "least-squares synthesis needs scipy: pip install 'linkwork[synthesis]'"
        ) from None
    return least_squares


def _length_range(length_range: tuple[float, float] | None) -> tuple[float, float]:
    lo, hi = length_range if length_range is not None else (0.0, np.inf)
    if not 0.0 <= lo < hi:
        raise SynthesisError(f"length_range must be 0 <= lo < hi, got {length_range}")
    return lo, hi


def _subsets(n: int, count: int, seed: int) -> list[np.ndarray]:
    """Five-point subsets: evenly spread, then random ones."""
    rng = np.random.default_rng(seed)
    chosen = [np.linspace(0, n - 1, 5).round().astype(int)]
    while len(chosen) < count:
        chosen.append(np.sort(rng.choice(n, 5, replace=False)))
    return chosen


def _fit_dyad(
    residual: Callable[[np.ndarray], np.ndarray], z0: np.ndarray, lo: float, hi: float, size: float
) -> Dyad:
    """One dyad (G, M, R) = z by trust-region least squares from z0, R in [lo, hi]."""
    z0 = z0.copy()
    z0[4] = float(np.clip(z0[4], lo, hi if np.isfinite(hi) else None))
    bounds = ([-np.inf] * 4 + [lo], [np.inf] * 4 + [hi])
    fit = _least_squares()(residual, z0, bounds=bounds, x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    res = residual(fit.x)
    return Dyad(
        np.array(fit.x[:2]),
        np.array(fit.x[2:4]),
        np.zeros(2),
        np.zeros(2),
        True,
        False,
        float(np.max(np.abs(res))),
        float(np.sqrt(np.mean(res**2)) / size),
        float(np.linalg.cond(fit.jac)) if fit.jac.size else math.inf,
        0.0,
    )


def _add_new(found: list[Dyad], dyad: Dyad, size: float) -> None:
    if not any(_same_dyad(dyad, e, 1e-5 * size) for e in found):
        found.append(dyad)


def _same_dyad(a: Dyad, b: Dyad, tol: float) -> bool:
    return bool(np.allclose(a.ground, b.ground, atol=tol) and np.allclose(a.moving, b.moving, atol=tol))


def _screened(paired: list[FourBarDesign], size: float, min_transmission: float) -> list[FourBarDesign]:
    """Least-squares designs screened by the engine with the tolerance their fit allows
    (a design meets its positions only as well as its dyads fit them), those whose
    transmission angle comes closer than ``min_transmission`` to 0 or 180 deg dropped."""
    for d in paired:
        d.tolerance = 10.0 * max(x.residual for x in d.dyads) + POSITION_TOLERANCE * size
    return [d for d in paired if d.defects.worst_transmission >= min_transmission]


def _motion_dyads(p: np.ndarray, lo: float, hi: float, subsets: int, seed: int) -> list[Dyad]:
    """Least-squares dyads guiding a body through poses p (n x 3, n > 5), started from
    the real Burmester dyads of five-pose subsets."""
    n = len(p)
    pts = p[:, 0] + 1j * p[:, 1]
    rot = np.exp(1j * (p[:, 2] - p[0, 2]))
    size = float(np.ptp(p[:, :2])) or 1.0

    def residual(z: np.ndarray) -> np.ndarray:
        g, m, r = complex(z[0], z[1]), complex(z[2], z[3]), z[4]
        return np.abs(pts + (m - pts[0]) * rot - g) - r

    found: list[Dyad] = []
    reason = "no five-pose subset has a real Burmester dyad"
    for idx in _subsets(n, subsets, seed):
        try:
            exact = dyads("burmester", poses=p[idx])
        except SynthesisError as e:
            reason = f"the subset of poses {', '.join(str(i + 1) for i in idx)}, numbered 1 to 5 in it: {e}"
            continue
        for d in exact.real:
            # the exact dyad's moving pivot is given at the subset's first pose
            k0 = int(idx[0])
            m1 = pts[0] + (complex(*d.moving) - pts[k0]) / rot[k0]
            g = complex(*d.ground)
            r0 = float(np.median(np.abs(pts + (m1 - pts[0]) * rot - g)))
            z0 = np.array([g.real, g.imag, m1.real, m1.imag, r0])
            _add_new(found, _fit_dyad(residual, z0, lo, hi, size), size)
    if not found:
        raise SynthesisError(f"no dyad to start the least squares from ({reason})")
    return found


def motion_least_squares(
    poses: Any,
    length_range: tuple[float, float] | None = None,
    min_transmission: float = 0.0,
    subsets: int = 12,
    angles: str = "rad",
    seed: int = 0,
) -> Synthesis:
    """Motion generation through more poses than the exact methods take (n > 5): dyads
    minimizing the change of their link length over all poses, then four-bars screened
    by the engine.

    Each dyad (ground pivot G, moving pivot M fixed in the body, length R) minimizes
    sum_j (|M_j - G| - R)^2 by trust-region least squares (scipy), R bounded by
    ``length_range``; the starts are the real Burmester dyads of ``subsets`` five-pose
    subsets (exact, certified), so every local minimum near an exact design of some five
    poses is found. Dyads' ``residual`` is the largest |M_j - G| - R over the poses. Designs
    pair two dyads, are swept by the engine (`Defects`), and those whose transmission
    angle comes closer than ``min_transmission`` (deg) to 0 or 180 are dropped; sorted by
    `MERIT`. Needs scipy (``pip install linkwork[synthesis]``).
    """
    _least_squares()
    p = _array(poses, "poses", 3).copy()
    p[:, 2] = _angles(p[:, 2], angles, "pose angles")
    n = len(p)
    if n <= 5:
        raise SynthesisError(
            f"least squares is for more than 5 poses (got {n}); use motion() for exact synthesis"
        )
    lo, hi = _length_range(length_range)
    size = float(np.ptp(p[:, :2])) or 1.0
    found = _motion_dyads(p, lo, hi, subsets, seed)
    sols = DyadSolutions(found, "least squares")
    designs = _screened(_pair_designs(found, p[:, :2], p[:, 2] - p[0, 2], None), size, min_transmission)
    designs.sort(key=_merit)
    return Synthesis(f"motion generation, {n} poses (least squares)", sols, designs)


def path_least_squares(
    points: Any,
    input_angles: Any,
    length_range: tuple[float, float] | None = None,
    min_transmission: float = 0.0,
    subsets: int = 12,
    angles: str = "rad",
    seed: int = 0,
) -> Synthesis:
    """Path generation with prescribed timing through more points than the exact method
    takes (n > 5): the coupler point through ``points`` while the crank turns by
    ``input_angles`` (from position 1), by least squares, then four-bars screened by the
    engine.

    The input dyad (ground pivot G, crank pin A_1, coupler-side length R = |P - A|)
    minimizes sum_j (|P_j - A_j| - R)^2 with A_j = G + (A_1 - G) e^{i(phi_j - phi_1)}, R
    bounded by ``length_range``; its starts are the real timed dyads of ``subsets``
    five-point subsets (exact, certified). Each fitted input dyad implies the coupler
    rotations theta_j = arg((P_j - A_j) / (P_1 - A_1)); the follower dyads are then the
    least-squares motion dyads of the poses (P_j, theta_j) (as in `motion_least_squares`).
    A design's ``tolerance`` is ten times its dyads' largest residual. Designs whose
    transmission angle comes closer than ``min_transmission`` (deg) to 0 or 180 are
    dropped; sorted by `MERIT`. Needs scipy (``pip install linkwork[synthesis]``).
    """
    _least_squares()
    pts = _array(points, "points", 2)
    a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
    n = len(pts)
    if n <= 5:
        raise SynthesisError(
            f"least squares is for more than 5 points (got {n}); use path() for exact synthesis"
        )
    if len(a) != n:
        raise SynthesisError(f"{n} points need {n} input angles, got {len(a)}")
    lo, hi = _length_range(length_range)
    size = float(np.ptp(pts)) or 1.0
    pc = pts[:, 0] + 1j * pts[:, 1]
    turn = np.exp(1j * (a - a[0]))

    def crank_pins(z: np.ndarray) -> np.ndarray:
        g, a1 = complex(z[0], z[1]), complex(z[2], z[3])
        return g + (a1 - g) * turn

    def residual(z: np.ndarray) -> np.ndarray:
        return np.abs(pc - crank_pins(z)) - z[4]

    inputs: list[Dyad] = []
    reason = "no five-point subset has a real timed dyad"
    for idx in _subsets(n, subsets, seed):
        try:
            exact = dyads("timed", points=pts[idx], input_angles=a[idx] - a[idx[0]])
        except SynthesisError as e:
            reason = f"the subset of points {', '.join(str(i + 1) for i in idx)}, numbered 1 to 5 in it: {e}"
            continue
        for d in exact.real:
            # the exact dyad's crank pin is given at the subset's first point
            g, k0 = complex(*d.ground), int(idx[0])
            a1 = g + (complex(*d.moving) - g) / turn[k0]
            z0 = np.array([g.real, g.imag, a1.real, a1.imag, 0.0])
            z0[4] = float(np.median(np.abs(pc - crank_pins(z0))))
            _add_new(inputs, _fit_dyad(residual, z0, lo, hi, size), size)
    if not inputs:
        raise SynthesisError(f"no input dyad to start the least squares from ({reason})")
    designs: list[FourBarDesign] = []
    followers: list[DyadSolutions] = []
    for d in inputs:
        pins = crank_pins(np.r_[d.ground, d.moving, 0.0])
        theta = np.angle((pc - pins) / (pc[0] - pins[0]))
        found = _motion_dyads(np.column_stack([pts, theta]), lo, hi, subsets, seed)
        others = [b for b in found if not _same_dyad(b, d, 1e-5 * size)]
        followers.append(DyadSolutions(found, "least squares"))
        designs += _screened(_pair_designs(others, pts, theta, a, first=d), size, min_transmission)
    designs.sort(key=_merit)
    return Synthesis(
        f"path generation with prescribed timing, {n} points (least squares)",
        [DyadSolutions(inputs, "least squares"), *followers],
        designs,
    )
