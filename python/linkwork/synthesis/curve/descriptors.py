"""Elliptic Fourier descriptors of closed curves (Kuhl and Giardina, Computer Graphics
and Image Processing 18, 1982) and the shape objective of curve synthesis.

A curve is points (k, 2), or many curves of one length (..., k, 2): every function is
vectorised over the leading axes. The descriptors are the coefficients (a, b, c, d) of
each harmonic n of x(t) = A0 + sum a cos(2 pi n t / T) + b sin(...), y(t) = C0 + sum c
cos + d sin, with t the arc length along the closed polygon (period T, its perimeter),
normalised for starting point, rotation, scale and position as Kuhl and Giardina do (the
first harmonic's ellipse on the x axis, its semi-major axis 1, the start at its end).
Pyslvs (pyslvs/efd.py) and four-bar-rs (the ``efd`` crate) use the same normalisation
with 20 harmonics; here it runs over many curves at once, in NumPy.

`shape_error` scores a traced curve against target points independently of position,
rotation and scale, as the Fourier-descriptor papers report it: the mean and largest
distance from each target point to the traced polygon, after the similarity transform of
the curve onto the target that the descriptors give, polished by ICP (`scipy.spatial`
nearest points, Umeyama's closed-form similarity) and a Nelder-Mead step on the mean.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import SynthesisError

__all__ = [
    "HARMONICS",
    "Normalised",
    "coefficients",
    "normalise",
    "descriptors",
    "flip_even",
    "reconstruct",
    "nearest_distances",
    "ShapeFit",
    "shape_error",
]

#: Harmonics kept by default (four-bar-rs's atlas uses 20).
HARMONICS = 20


def _points(points: Any, what: str = "points", least: int = 3) -> np.ndarray:
    p = np.asarray(points, dtype=np.float64)
    if p.ndim < 2 or p.shape[-1] != 2:
        raise SynthesisError(
            f"{what} must be an array of (x, y) rows, shape (..., k, 2); got shape {p.shape}"
        )
    if p.shape[-2] < least:
        raise SynthesisError(f"{what}: at least {least} points are needed, got {p.shape[-2]}")
    if not np.all(np.isfinite(p)):
        raise SynthesisError(f"{what} hold non-finite values")
    return p


def _closed(p: np.ndarray, closed: bool) -> np.ndarray:
    """An open curve as the closed one that runs it there and back (as the efd crate does)."""
    return p if closed else np.concatenate([p, p[..., -2:0:-1, :]], axis=-2)


def coefficients(
    points: Any, harmonics: int = HARMONICS, closed: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """The raw elliptic Fourier coefficients of the closed polygon through ``points``
    (it closes back to the first point): ``(coeffs, locus)``, coeffs (..., harmonics, 4)
    as (a, b, c, d) and locus (..., 2) = (A0, C0), the arc-length mean of the polygon.
    ``closed=False``: the open curve run there and back."""
    if not isinstance(harmonics, (int, np.integer)) or harmonics < 1:
        raise SynthesisError(f"harmonics must be a positive integer, got {harmonics!r}")
    p = _closed(_points(points), closed)
    d = np.roll(p, -1, axis=-2) - p  # segment i: p[i] -> p[i+1], the last one closing
    dt = np.hypot(d[..., 0], d[..., 1])
    T = dt.sum(axis=-1)
    if np.any(T <= 0.0):
        raise SynthesisError("a curve has zero length (all its points coincide)")
    t = np.concatenate([np.zeros((*dt.shape[:-1], 1)), np.cumsum(dt, axis=-1)], axis=-1)
    # a repeated point is a zero-length segment: it adds nothing (no 0 / 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = np.where(dt[..., None] > 0.0, d / dt[..., None], 0.0)  # (..., k, 2)
    # e^{i n phi} at every vertex by powers of e^{i phi} (a multiply a harmonic, not a
    # cos and a sin): accurate to a few n eps
    unit = np.exp(2j * np.pi * t / T[..., None])
    power = np.ones_like(unit)
    out = np.empty((*dt.shape[:-1], harmonics, 4))
    for n in range(1, harmonics + 1):
        power = power * unit
        step = np.diff(power, axis=-1)
        dcos, dsin = step.real, step.imag
        scale = T / (2.0 * n * n * np.pi**2)
        out[..., n - 1, 0] = scale * np.sum(dcos * slope[..., 0], axis=-1)
        out[..., n - 1, 1] = scale * np.sum(dsin * slope[..., 0], axis=-1)
        out[..., n - 1, 2] = scale * np.sum(dcos * slope[..., 1], axis=-1)
        out[..., n - 1, 3] = scale * np.sum(dsin * slope[..., 1], axis=-1)
    coeffs = out
    # the mean of the polygon over arc length (trapezoids: exact for straight segments)
    mid = 0.5 * (p + np.roll(p, -1, axis=-2))
    locus = np.einsum("...k,...kj->...j", dt, mid) / T[..., None]
    return coeffs, locus


@dataclass(frozen=True)
class Normalised:
    """Normalised descriptors and the normalisation that made them: ``coeffs``
    (..., H, 4); ``locus`` (..., 2) the curve's centre; ``scale`` the first harmonic's
    semi-major axis; ``psi`` its direction (rad); ``theta`` the start-point shift (rad of
    the first harmonic's phase). The curve is locus + scale R(psi) (normalised curve)."""

    coeffs: np.ndarray
    locus: np.ndarray
    scale: np.ndarray
    psi: np.ndarray
    theta: np.ndarray


def normalise(coeffs: np.ndarray, locus: np.ndarray, canonical: bool = True) -> Normalised:
    """Kuhl and Giardina's normalisation of raw coefficients (``coefficients``). The start
    is moved to an end of the first harmonic's major axis, which has two ends: they
    differ by the sign of the even harmonics. ``canonical``: pick the end that makes the
    largest even-harmonic coefficient positive, so a curve has one descriptor whatever its
    start (a query should still try the other end, `flip_even`: the choice jumps where two
    even coefficients tie). Raises `SynthesisError` where the first harmonic is a circle
    or degenerate (no major axis: no normalisation)."""
    co = np.asarray(coeffs, dtype=np.float64)
    a1, b1, c1, d1 = (co[..., 0, j] for j in range(4))
    theta = 0.5 * np.arctan2(2.0 * (a1 * b1 + c1 * d1), a1**2 + c1**2 - b1**2 - d1**2)
    n = np.arange(1, co.shape[-2] + 1, dtype=np.float64)
    ct, st = np.cos(n * theta[..., None]), np.sin(n * theta[..., None])
    a, b, c, d = (co[..., j] for j in range(4))
    # the start moved by theta: each harmonic's phase by n theta
    a2, b2 = a * ct + b * st, -a * st + b * ct
    c2, d2 = c * ct + d * st, -c * st + d * ct
    psi = np.arctan2(c2[..., 0], a2[..., 0])
    scale = np.hypot(a2[..., 0], c2[..., 0])
    minor = np.hypot(b2[..., 0], d2[..., 0])
    if np.any(~(scale > 1e-12 * np.maximum(1.0, minor))) or np.any(np.abs(scale - minor) <= 1e-9 * scale):
        raise SynthesisError(
            "a curve's first harmonic is a circle or a point: its descriptors cannot be normalised"
        )
    cp, sp = (np.cos(psi) / scale)[..., None], (np.sin(psi) / scale)[..., None]
    # rotated by -psi and scaled by 1/scale
    out = np.stack([cp * a2 + sp * c2, cp * b2 + sp * d2, -sp * a2 + cp * c2, -sp * b2 + cp * d2], axis=-1)
    if canonical:
        even = out[..., 1::2, :].reshape(*out.shape[:-2], -1)
        if even.shape[-1]:
            pick = np.take_along_axis(even, np.argmax(np.abs(even), axis=-1)[..., None], axis=-1)[..., 0]
            flip = pick < 0.0
            out = np.where(flip[..., None, None], flip_even(out), out)
            theta = np.where(flip, theta + np.pi, theta)
            psi = np.where(flip, psi + np.pi, psi)
    return Normalised(out, np.asarray(locus, dtype=np.float64), scale, psi, theta)


def flip_even(coeffs: np.ndarray) -> np.ndarray:
    """Normalised descriptors started from the other end of the major axis: the even
    harmonics' signs flipped (the curve is then ``psi + pi`` from its normalised pose)."""
    sign = np.where(np.arange(coeffs.shape[-2]) % 2 == 1, -1.0, 1.0)[:, None]
    return coeffs * sign


def descriptors(
    points: Any, harmonics: int = HARMONICS, closed: bool = True, reverse: bool = False
) -> Normalised:
    """The normalised elliptic Fourier descriptors of a curve or of many curves of one
    length (points (..., k, 2)); ``reverse``: of the curve run the other way."""
    p = _points(points)
    if reverse:
        p = p[..., ::-1, :]
    return normalise(*coefficients(p, harmonics, closed))


def reconstruct(coeffs: Any, locus: Any = (0.0, 0.0), n: int = 256, start: float = 0.0) -> np.ndarray:
    """The curve (..., n, 2) of coefficients (..., H, 4) at ``n`` evenly spaced phases
    over one period from ``start`` (rad of the first harmonic; 0: the curve's start),
    around ``locus``."""
    co = np.asarray(coeffs, dtype=np.float64)
    h = np.arange(1, co.shape[-2] + 1, dtype=np.float64)
    phase = np.outer(start + 2.0 * np.pi * np.arange(n) / n, h)  # (n, H)
    cos, sin = np.cos(phase), np.sin(phase)
    x = cos @ co[..., 0, None] + sin @ co[..., 1, None]
    y = cos @ co[..., 2, None] + sin @ co[..., 3, None]
    return np.concatenate([x, y], axis=-1) + np.asarray(locus, dtype=np.float64)[..., None, :]


def nearest_distances(targets: Any, curve: Any, closed: bool = True) -> np.ndarray:
    """The distance from each target point (m, 2) to the polygon through ``curve``
    (k, 2; closed back to its first point unless ``closed=False``)."""
    q = _points(targets, "target points", 1)
    c = _points(curve, "curve", 2)
    a, b = (c, np.roll(c, -1, axis=0)) if closed else (c[:-1], c[1:])
    ab = b - a
    L2 = np.einsum("kj,kj->k", ab, ab)
    ap = q[:, None, :] - a[None, :, :]
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.clip(np.where(L2 > 0.0, np.einsum("mkj,kj->mk", ap, ab) / L2, 0.0), 0.0, 1.0)
    foot = a[None] + s[..., None] * ab[None]
    return np.sqrt(np.min(np.sum((q[:, None, :] - foot) ** 2, axis=-1), axis=1))


@dataclass(frozen=True)
class ShapeFit:
    """The shape objective of a traced curve against target points: ``mean`` and
    ``largest`` distance from a target point to the transformed curve, and the similarity
    transform (curve -> target frame: x -> ``scale`` R(``rotation``) x + ``offset``)."""

    mean: float
    largest: float
    scale: float
    rotation: float
    offset: np.ndarray

    def apply(self, points: Any) -> np.ndarray:
        """Points of the curve's frame in the target's."""
        c, s = np.cos(self.rotation), np.sin(self.rotation)
        return self.scale * np.asarray(points, dtype=np.float64) @ np.array([[c, s], [-s, c]]) + self.offset


def _similarity(src: np.ndarray, dst: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Umeyama's least-squares similarity src -> dst (no reflection): scale, rotation, offset."""
    ms, md = src.mean(axis=0), dst.mean(axis=0)
    s0, d0 = src - ms, dst - md
    # the complex form of the 2-D Procrustes problem: d = z s with z = scale e^{i rot}
    zs, zd = s0[:, 0] + 1j * s0[:, 1], d0[:, 0] + 1j * d0[:, 1]
    z = np.vdot(zs, zd) / max(np.vdot(zs, zs).real, 1e-300)
    scale, rot = abs(z), float(np.angle(z))
    c, s = np.cos(rot), np.sin(rot)
    offset = md - scale * (np.array([[c, -s], [s, c]]) @ ms)
    return float(scale), rot, offset


def _fit(params: np.ndarray) -> tuple[float, float, np.ndarray]:
    return float(np.exp(params[0])), float(params[1]), params[2:4]


def shape_error(
    targets: Any,
    curve: Any,
    harmonics: int = HARMONICS,
    closed: bool = True,
    polish: bool = True,
    iterations: int = 30,
) -> ShapeFit:
    """The shape objective: the traced ``curve`` (k, 2) moved onto the target points
    (m, 2) by the best similarity transform, and the mean and largest distance from each
    target point to it. The transform starts from the descriptors (both directions and
    both ends of the major axis tried), then ICP (each target's nearest curve point,
    Umeyama's similarity) and, with ``polish``, Nelder-Mead on the mean distance."""
    from scipy.optimize import minimize
    from scipy.spatial import cKDTree

    q = _points(targets, "target points")
    c = _points(curve, "curve")
    # a dense copy of the polygon for the nearest-point steps (ICP)
    ring = np.concatenate([c, c[:1]]) if closed else c
    step = np.linspace(0.0, 1.0, 8, endpoint=False)[None, :, None]
    fine = (ring[:-1, None, :] + step * np.diff(ring, axis=0)[:, None, :]).reshape(-1, 2)
    fine = np.concatenate([fine, ring[-1:]])
    tree = cKDTree(fine)

    def score(scale: float, rot: float, offset: np.ndarray) -> float:
        cc, ss = np.cos(rot), np.sin(rot)
        # targets into the curve's frame: distances there, times the scale
        local = ((q - offset) @ np.array([[cc, -ss], [ss, cc]])) / scale
        return float(scale * np.mean(tree.query(local)[0]))

    starts = []
    tn = descriptors(q, harmonics, closed)
    for rev in (False, True):
        cn = descriptors(c, harmonics, closed, reverse=rev)
        for extra in (0.0, np.pi):
            scale = float(tn.scale / cn.scale)
            rot = float(tn.psi - cn.psi + extra)
            cc, ss = np.cos(rot), np.sin(rot)
            offset = tn.locus - scale * (np.array([[cc, -ss], [ss, cc]]) @ cn.locus)
            starts.append((scale, rot, offset))
    best = None
    for scale, rot, offset in starts:
        for _ in range(iterations):
            cc, ss = np.cos(rot), np.sin(rot)
            local = ((q - offset) @ np.array([[cc, -ss], [ss, cc]])) / scale
            near = fine[tree.query(local)[1]]
            new = _similarity(near, q)
            done = abs(new[0] / scale - 1.0) < 1e-12 and abs(new[1] - rot) < 1e-12
            scale, rot, offset = new
            if done:
                break
        f = score(scale, rot, offset)
        if best is None or f < best[0]:
            best = (f, scale, rot, offset)
    assert best is not None
    _, scale, rot, offset = best
    if polish:
        x0 = np.array([np.log(scale), rot, *offset])
        res = minimize(
            lambda x: score(*_fit(x)),
            x0,
            method="Nelder-Mead",
            options={"xatol": 1e-10, "fatol": 1e-12 * max(1.0, best[0]), "maxiter": 2000},
        )
        if res.fun < best[0]:
            scale, rot, offset = _fit(res.x)

    def exact(scale: float, rot: float, offset: np.ndarray) -> np.ndarray:
        cc, ss = np.cos(rot), np.sin(rot)
        return nearest_distances(q, scale * c @ np.array([[cc, ss], [-ss, cc]]) + offset, closed)

    d = exact(scale, rot, offset)
    if polish:
        # the polish minimises distances to the dense copy's vertices, not to the polygon
        # itself: keep the ICP's transform where the polished one is farther on the polygon
        rough = exact(*best[1:])
        if rough.mean() < d.mean():
            d, (scale, rot, offset) = rough, best[1:]
    return ShapeFit(
        float(d.mean()), float(d.max()), float(scale), float(rot), np.asarray(offset, dtype=np.float64)
    )
