"""Properties of the elliptic Fourier descriptors and the shape objective
(linkwork.synthesis.curve.descriptors), fast and without the engine or the atlas: the raw
coefficients are the Fourier series of the polygon over arc length (against Gauss
quadrature on each side), the normalised ones are the same for a curve moved, turned,
scaled, started elsewhere or run backwards, with the first harmonic on the x axis of
semi-major axis 1, and the pose they report takes the normalised curve back onto the raw
series; the shape error is zero for a moved copy of the curve and not for another shape,
and bad input is refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from linkwork.errors import SynthesisError
from linkwork.synthesis.curve import descriptors as D


def rot(a: float) -> np.ndarray:
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def curve(seed: int, k: int = 60, even: bool = False) -> np.ndarray:
    """A closed curve of k points at uneven phases (``even``: evenly spaced): a first
    harmonic of axes 1 and 0.55 (not a circle) and random second and third harmonics up
    to 0.25 (shapes with even harmonics, so the canonical end is decided)."""
    rng = np.random.default_rng(seed)
    phi = np.sort(rng.uniform(0.0, 2 * math.pi, k))
    if even:
        phi = np.linspace(0.0, 2 * math.pi, k, endpoint=False)
    h = rng.uniform(-0.25, 0.25, (2, 4))
    x = np.cos(phi) + h[0, 0] * np.cos(2 * phi) + h[0, 1] * np.sin(2 * phi) + h[1, 0] * np.cos(3 * phi)
    y = 0.55 * np.sin(phi) + h[0, 2] * np.cos(2 * phi) + h[0, 3] * np.sin(2 * phi) + h[1, 3] * np.sin(3 * phi)
    return np.column_stack([x, y]) @ rot(rng.uniform(-math.pi, math.pi)).T


def quadrature(points: np.ndarray, harmonics: int) -> tuple[np.ndarray, np.ndarray]:
    """The Fourier series of the closed polygon over arc length t (period T):
    a_n = 2/T int x cos(2 pi n t / T) dt, ..., A0 = 1/T int x dt, by 30-point Gauss-Legendre
    on each side (the integrand is smooth there; exact to rounding for these n)."""
    nodes, weights = np.polynomial.legendre.leggauss(30)
    ring = np.vstack([points, points[:1]])
    sides = np.hypot(*np.diff(ring, axis=0).T)
    T = sides.sum()
    t0 = np.concatenate([[0.0], np.cumsum(sides)])[:-1]
    u = (nodes + 1.0) / 2.0  # on [0, 1]
    t = (t0[:, None] + u[None, :] * sides[:, None]).ravel()
    xy = (ring[:-1, None, :] + u[None, :, None] * np.diff(ring, axis=0)[:, None, :]).reshape(-1, 2)
    w = (weights[None, :] / 2.0 * sides[:, None]).ravel()
    out = np.empty((harmonics, 4))
    for n in range(1, harmonics + 1):
        c, s = np.cos(2 * math.pi * n * t / T), np.sin(2 * math.pi * n * t / T)
        out[n - 1] = [2 / T * np.sum(w * xy[:, j] * f) for j in (0, 1) for f in (c, s)]
    return out, (w @ xy) / T


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), k=st.integers(5, 80))
def test_coefficients_are_the_fourier_series_over_arc_length(seed: int, k: int) -> None:
    p = curve(seed, k) * 3.0 + [2.0, -1.0]
    got, locus = D.coefficients(p, 6)
    want, mean = quadrature(p, 6)
    # round-off of sums of k terms of size ~3 (the curve's size)
    np.testing.assert_allclose(got, want, rtol=0.0, atol=1e-12 * 3.0 * k)
    np.testing.assert_allclose(locus, mean, rtol=0.0, atol=1e-13 * 3.0 * k)
    # a repeated vertex is a side of length zero: it adds nothing
    again, at = D.coefficients(np.insert(p, 2, p[2], axis=0), 6)
    np.testing.assert_allclose(again, got, rtol=0.0, atol=1e-13 * 3.0 * k)
    np.testing.assert_allclose(at, locus, rtol=0.0, atol=1e-13 * 3.0 * k)


def test_an_open_curve_is_the_closed_one_run_there_and_back() -> None:
    p = curve(5, 30)[:17]
    there_and_back = np.vstack([p, p[-2:0:-1]])
    for a, b in zip(D.coefficients(p, 8, closed=False), D.coefficients(there_and_back, 8)):
        np.testing.assert_array_equal(a, b)
    ref = D.descriptors(there_and_back)
    got = D.descriptors(p, closed=False)
    np.testing.assert_array_equal(got.coeffs, ref.coeffs)


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    scale=st.floats(1e-3, 1e3),
    angle=st.floats(-math.pi, math.pi),
    offset=st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)),
    shift=st.integers(0, 59),
    backwards=st.booleans(),
)
def test_normalised_descriptors_ignore_pose_scale_start_and_direction(
    seed: int, scale: float, angle: float, offset: tuple[float, float], shift: int, backwards: bool
) -> None:
    p = curve(seed)
    ref = D.descriptors(p, 10)
    q = scale * np.roll(p, shift, axis=0) @ rot(angle).T + np.asarray(offset)
    got = D.descriptors(q[::-1] if backwards else q, 10, reverse=backwards)
    # sums of 60 terms of size 1 (after scaling) in the coefficients and the normalisation
    np.testing.assert_allclose(got.coeffs, ref.coeffs, rtol=0.0, atol=1e-10)
    assert float(got.scale) == pytest.approx(scale * float(ref.scale), rel=1e-11)
    assert math.remainder(float(got.psi - ref.psi) - angle, 2 * math.pi) == pytest.approx(0.0, abs=1e-10)
    size = scale + float(np.hypot(*offset))
    np.testing.assert_allclose(
        got.locus, scale * rot(angle) @ ref.locus + offset, rtol=0.0, atol=1e-12 * size
    )


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), canonical=st.booleans())
def test_the_normalisation_puts_the_first_harmonic_on_the_x_axis_and_reports_its_pose(
    seed: int, canonical: bool
) -> None:
    p = 2.5 * curve(seed, 90) + [1.0, 4.0]
    raw, locus = D.coefficients(p, 12)
    norm = D.normalise(raw, locus, canonical=canonical)
    a1, b1, c1, d1 = norm.coeffs[0]
    # the first harmonic's ellipse: semi-major axis 1 along x, started at its end
    assert a1 == pytest.approx(1.0, abs=1e-13) and abs(b1) < 1e-13 and abs(c1) < 1e-13
    assert 0.0 < abs(d1) < 1.0
    # the scale is that ellipse's semi-major axis in the raw curve: its farthest point
    ellipse = D.reconstruct(raw[:1], n=4000)
    assert float(norm.scale) == pytest.approx(np.hypot(*ellipse.T).max(), rel=1e-6)
    np.testing.assert_array_equal(norm.locus, locus)
    # the reported pose takes the normalised series back onto the raw one, started at theta
    back = norm.locus + float(norm.scale) * D.reconstruct(norm.coeffs, n=64) @ rot(float(norm.psi)).T
    np.testing.assert_allclose(back, D.reconstruct(raw, locus, 64, start=float(norm.theta)), atol=1e-12 * 5)
    even = norm.coeffs[1::2].ravel()
    if canonical:  # the end whose largest even-harmonic coefficient is positive
        assert even[np.argmax(np.abs(even))] > 0.0
    other = D.normalise(raw, locus, canonical=not canonical)
    flipped = np.allclose(other.coeffs, D.flip_even(norm.coeffs), rtol=0.0, atol=1e-13)
    assert flipped or np.allclose(other.coeffs, norm.coeffs, rtol=0.0, atol=1e-13)


@pytest.mark.parametrize("seed", range(8))
def test_the_canonical_end_looks_at_every_even_harmonic(seed: int) -> None:
    """Raw coefficients whose largest even harmonic is the 4th (the 2nd a hundred times
    smaller, a random first harmonic): the canonical end makes the largest even-harmonic
    coefficient positive, which is then one of the 4th's (a start or a rotation changes
    each harmonic's coefficients but not their size)."""
    rng = np.random.default_rng(seed)
    raw = np.zeros((8, 4))
    raw[0] = rng.uniform(-1.0, 1.0, 4)
    raw[1] = rng.uniform(-1e-3, 1e-3, 4)
    raw[2] = rng.uniform(-0.1, 0.1, 4)
    raw[3] = rng.uniform(-0.1, 0.1, 4)
    norm = D.normalise(raw, np.zeros(2))
    even = norm.coeffs[1::2]  # harmonics 2, 4, 6, 8
    at = np.unravel_index(np.argmax(np.abs(even)), even.shape)
    assert at[0] == 1  # the premise: the largest is in the 4th harmonic
    assert even[at] > 0.0


def test_flip_even_starts_the_curve_half_a_period_on_turned_half_a_turn() -> None:
    co = D.descriptors(curve(3), 7).coeffs
    for start in (0.0, 0.7):
        np.testing.assert_allclose(
            D.reconstruct(D.flip_even(co), n=50, start=start),
            -D.reconstruct(co, n=50, start=start + math.pi),
            rtol=0.0,
            atol=1e-14 * 7,
        )
    np.testing.assert_array_equal(D.flip_even(D.flip_even(co)), co)
    np.testing.assert_array_equal(D.flip_even(co)[0::2], co[0::2])


def test_reconstruct_sums_the_series() -> None:
    rng = np.random.default_rng(1)
    co = rng.normal(size=(5, 4))
    locus = np.array([0.3, -2.0])
    start, n = 0.4, 9
    got = D.reconstruct(co, locus, n, start)
    assert got.shape == (n, 2)
    for i in range(n):
        phi = start + 2 * math.pi * i / n
        want = locus.copy()
        for h in range(1, 6):
            a, b, c, d = co[h - 1]
            want += [
                a * math.cos(h * phi) + b * math.sin(h * phi),
                c * math.cos(h * phi) + d * math.sin(h * phi),
            ]
        np.testing.assert_allclose(got[i], want, rtol=0.0, atol=1e-13)


def test_a_curves_descriptors_unless_asked_have_the_shipped_atlas_harmonics() -> None:
    """A query compares a curve's default descriptors with the shipped atlas's."""
    from linkwork.synthesis.curve.atlas import load

    shipped = load().descriptors.shape[1:]
    assert D.descriptors(curve(4)).coeffs.shape == shipped and D.coefficients(curve(4))[0].shape == shipped


def test_many_curves_at_once_are_each_alone() -> None:
    """Each curve of a batch gets its own descriptors, its own canonical end included
    (twelve curves: both ends are picked in the batch's last axis), and its own curve
    back from them."""
    many = np.stack([curve(s, 40) for s in range(12)]).reshape(3, 4, 40, 2)
    got = D.descriptors(many, 6)
    assert got.coeffs.shape == (3, 4, 6, 4)
    curves = D.reconstruct(got.coeffs, n=32)
    assert curves.shape == (3, 4, 32, 2)
    for i in range(3):
        for j in range(4):
            one = D.descriptors(many[i, j], 6)
            np.testing.assert_allclose(got.coeffs[i, j], one.coeffs, rtol=0.0, atol=1e-14)
            np.testing.assert_allclose(curves[i, j], D.reconstruct(one.coeffs, n=32), rtol=0.0, atol=1e-14)
            assert float(got.theta[i, j]) == pytest.approx(float(one.theta), abs=1e-14)
            assert float(got.psi[i, j]) == pytest.approx(float(one.psi), abs=1e-14)


def _segment_distance(q: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab, aq = b - a, q - a
    L2 = float(ab @ ab)
    s = 0.0 if L2 == 0.0 else min(max(float(aq @ ab) / L2, 0.0), 1.0)
    return float(np.hypot(*(q - a - s * ab)))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), closed=st.booleans())
def test_nearest_distances_are_to_the_sides_of_the_polygon(seed: int, closed: bool) -> None:
    rng = np.random.default_rng(seed)
    c = rng.uniform(-2.0, 2.0, (int(rng.integers(2, 8)), 2))
    q = rng.uniform(-3.0, 3.0, (7, 2))
    q[0] = c[0] + 0.3 * (c[1] - c[0])  # one on a side
    sides = [(c[i], c[(i + 1) % len(c)]) for i in range(len(c) if closed else len(c) - 1)]
    want = [min(_segment_distance(p, a, b) for a, b in sides) for p in q]
    np.testing.assert_allclose(D.nearest_distances(q, c, closed=closed), want, rtol=0.0, atol=1e-14)
    # a repeated vertex (a side of zero length) is a point of the polygon already
    twice = np.insert(c, 1, c[1], axis=0)
    np.testing.assert_allclose(D.nearest_distances(q, twice, closed=closed), want, rtol=0.0, atol=1e-14)


@pytest.mark.parametrize("size", [1e-3, 1.0, 1e3])
def test_the_similarity_of_two_similar_point_sets_is_exact(size: float) -> None:
    src = size * curve(9, 20)
    dst = 3.5 * src @ rot(2.9).T + [4.0, -1.0]
    scale, angle, offset = D._similarity(src, dst)
    assert scale == pytest.approx(3.5, rel=1e-13)
    assert math.remainder(angle - 2.9, 2 * math.pi) == pytest.approx(0.0, abs=1e-13)
    np.testing.assert_allclose(offset, [4.0, -1.0], atol=1e-13 * (1 + size))
    fit = D.ShapeFit(0.0, 0.0, scale, angle, offset)
    np.testing.assert_allclose(fit.apply(src), dst, atol=1e-13 * (1 + size))


@settings(max_examples=12, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    scale=st.floats(0.05, 50.0),
    angle=st.floats(-math.pi, math.pi),
    shift=st.integers(0, 89),
    backwards=st.booleans(),
    polish=st.booleans(),
)
def test_shape_error_is_zero_for_a_moved_copy(
    seed: int, scale: float, angle: float, shift: int, backwards: bool, polish: bool
) -> None:
    """Targets that are vertices of the curve moved by a similarity (any start, either
    direction): found at distance zero, up to round-off, with that similarity (a curve
    sampled evenly in phase; see the next test for an uneven one)."""
    c = curve(seed, 90, even=True)
    q = scale * np.roll(c, shift, axis=0)[::3] @ rot(angle).T + [7.0, -3.0]
    q = q[::-1] if backwards else q
    fit = D.shape_error(q, c, polish=polish)
    assert fit.mean <= 1e-9 * scale and fit.largest <= 1e-8 * scale
    assert fit.scale == pytest.approx(scale, rel=1e-8)
    assert math.remainder(fit.rotation - angle, 2 * math.pi) == pytest.approx(0.0, abs=1e-8)
    np.testing.assert_allclose(fit.offset, [7.0, -3.0], atol=1e-7 * (1 + scale))


@settings(max_examples=12, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    scale=st.floats(0.05, 50.0),
    angle=st.floats(-math.pi, math.pi),
    shift=st.integers(0, 59),
    backwards=st.booleans(),
)
def test_the_descriptors_starts_alone_place_the_curve_moved_whole(
    seed: int, scale: float, angle: float, shift: int, backwards: bool
) -> None:
    """Targets that are the whole polygon moved by a similarity (any start, either
    direction): the similarity of the two normalisations (scale, turn and centre), with
    no ICP step and no polish, is that similarity, at distance zero up to round-off."""
    c = curve(seed, 60)
    q = scale * np.roll(c, shift, axis=0) @ rot(angle).T + [7.0, -3.0]
    q = q[::-1] if backwards else q
    fit = D.shape_error(q, c, polish=False, iterations=0)
    assert fit.largest <= 1e-12 * scale
    assert fit.scale == pytest.approx(scale, rel=1e-12)
    assert math.remainder(fit.rotation - angle, 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(fit.offset, [7.0, -3.0], rtol=0.0, atol=1e-12 * (10 + scale))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_icp_finds_a_similarity_onto_the_midpoints_of_the_sides(seed: int) -> None:
    """Targets at the midpoints of every other side (the closing one included), moved by
    a similarity: ICP alone (no polish) finds it, at distance zero up to round-off."""
    c = curve(seed, 60, even=True)
    middles = 0.5 * (c + np.roll(c, -1, axis=0))[1::2]
    fit = D.shape_error(2.5 * middles @ rot(0.7).T + [3.0, 1.0], c, polish=False)
    assert fit.largest < 1e-12 * 2.5


@pytest.mark.xfail(strict=True, reason="ICP from the descriptors' starts ends in a local minimum")
@pytest.mark.parametrize(
    "seed, polish", [(9, False), (24, False), (40, False), (188, False), (378, False), (378, True)]
)
def test_shape_error_of_a_moved_copy_of_an_unevenly_sampled_curve(seed: int, polish: bool) -> None:
    """Known limitation: for 5 of the first 400 shapes of `curve` (uneven phases), the
    targets every third vertex of the curve itself are scored 1e-3 to 3e-3 away (of a
    curve 2 across) without the polish, and one of them (378) with it; evenly sampled,
    none of 300."""
    c = curve(seed, 90)
    assert D.shape_error(c[::3], c, polish=polish).mean <= 1e-9


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10_000), shear=st.floats(0.3, 1.0))
# the polish, on the dense copy's vertices, ended 1e-4 farther on the polygon than ICP here
@example(seed=6774, shear=0.3)
@example(seed=6774, shear=0.3125)
def test_shape_error_of_another_shape_is_its_distance_after_the_best_similarity(
    seed: int, shear: float
) -> None:
    """A sheared curve is not similar to the curve: a positive error, which is the mean
    and largest distance to the curve moved by the similarity reported, and no larger
    than that of the descriptors' own similarity (the polish only improves it)."""
    c = curve(seed, 90)
    q = 4.0 * (c @ np.array([[1.0, shear], [0.0, 1.0]]).T)[::2]
    fit = D.shape_error(q, c)
    d = D.nearest_distances(q, fit.apply(c))
    assert fit.mean == pytest.approx(float(d.mean()), rel=1e-12)
    assert fit.largest == pytest.approx(float(d.max()), rel=1e-12)
    # a shear of 0.3 moves the points by about 0.1 of the curve's size 4 (a few 0.1 at 1.0)
    assert 0.01 * 4.0 < fit.mean <= fit.largest
    rough = D.shape_error(q, c, polish=False)
    assert fit.mean <= rough.mean * (1.0 + 1e-12)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_polish_lowers_the_mean_distance_below_icps(seed: int) -> None:
    """ICP matches nearest points (a least-squares fit); the polish, on by default,
    minimises the mean distance itself: lower by 5 to 11 % on these sheared curves,
    whatever the curve's own size (drawn 1000 times larger, its similarity's scale far
    below the distances: the same mean to 2 %, measured 1.3 % at most, the polish ending
    in a nearby minimum)."""
    c = curve(seed, 90)
    q = 4.0 * (c @ np.array([[1.0, 0.5], [0.0, 1.0]]).T)[::2]
    fit = D.shape_error(q, c)
    assert fit.mean < 0.97 * D.shape_error(q, c, polish=False).mean
    assert D.shape_error(q, 1000.0 * c).mean == pytest.approx(fit.mean, rel=0.02)


def test_bad_curves_get_named_errors() -> None:
    good = curve(1, 10)
    with pytest.raises(SynthesisError, match=r"points must be an array of \(x, y\) rows.*\(10,\)"):
        D.descriptors(good[:, 0])
    with pytest.raises(SynthesisError, match=r"shape \(10, 3\)"):
        D.descriptors(np.ones((10, 3)))
    with pytest.raises(SynthesisError, match="at least 3 points are needed, got 2"):
        D.descriptors(good[:2])
    with pytest.raises(SynthesisError, match="target points: at least 3 points are needed, got 2"):
        D.shape_error(good[:2], good)
    with pytest.raises(SynthesisError, match="curve: at least 3 points"):
        D.shape_error(good, good[:2])
    with pytest.raises(SynthesisError, match="target points hold non-finite values"):
        D.nearest_distances([[0.0, math.inf]], good)
    with pytest.raises(SynthesisError, match="curve: at least 2 points are needed, got 1"):
        D.nearest_distances(good, good[:1])
    assert D.nearest_distances(good[:1], good[:2])[0] == 0.0  # one target, one side: enough
    for bad in (0, -3, 2.0, "4"):
        with pytest.raises(SynthesisError, match="harmonics must be a positive integer"):
            D.coefficients(good, bad)
    assert D.coefficients(good, np.int64(1))[0].shape == (1, 4)
    with pytest.raises(SynthesisError, match="zero length"):
        D.coefficients(np.stack([good, np.ones((10, 2))]))
    with pytest.raises(SynthesisError, match="non-finite"):
        D.descriptors(np.where(np.arange(10)[:, None] == 4, math.nan, good))


def test_a_circle_or_a_point_has_no_normalisation() -> None:
    """A regular polygon's first harmonic is a circle (no major axis); a circle run twice
    has no first harmonic. A first harmonic 1e-6 from a circle (at any size), and a small
    curve, are normalised."""
    t = np.linspace(0.0, 2 * math.pi, 40, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    with pytest.raises(SynthesisError, match="circle or a point"):
        D.descriptors(circle)
    twice = np.column_stack([np.cos(2 * t), np.sin(2 * t)])
    with pytest.raises(SynthesisError, match="circle or a point"):
        D.descriptors(twice + 0.1 * np.column_stack([np.cos(4 * t), np.zeros_like(t)]))
    for size in (1e-3, 1.0, 1e3):  # at any size
        near = D.descriptors(size * circle * [1.0 + 1e-6, 1.0])
        assert 1.0 - 1e-5 < abs(near.coeffs[0, 3]) < 1.0
    tiny = D.descriptors(1e-4 * curve(2))
    np.testing.assert_allclose(tiny.coeffs, D.descriptors(curve(2)).coeffs, rtol=0.0, atol=1e-10)
