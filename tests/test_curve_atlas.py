"""Elliptic Fourier descriptors, the shape objective and the atlas of four-bar coupler
curves (linkwork.synthesis.curve.descriptors, .atlas)."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import linkwork as lw
from linkwork.errors import SynthesisError
from linkwork.synthesis.curve import atlas as A
from linkwork.synthesis.curve import descriptors as D


def rot(a):
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def coupler_curve(row, steps, circuit=None):
    """A design's coupler curve by the textbook closed form (independent of the engine)."""
    t = np.linspace(0.0, 2 * math.pi, steps, endpoint=False)
    branch = circuit or A.CIRCUITS[int(row[6])]
    cf = lw.closed_form.four_bar(
        float(row[0]), float(row[1]), float(row[2]), float(row[3]), t, 1.0, 0.0, branch
    )
    return A.coupler_curves(np.asarray(row, dtype=np.float64)[None], cf["theta3"][None], t)[0]


# a coupler curve with a loop (crank-rocker, open circuit): a shape with even harmonics
CURVE = coupler_curve([1.0, 0.35, 1.1, 0.9, 0.8, 0.6, 0], 400)


def moved(points, scale, angle, offset, shift=0):
    return scale * np.roll(points, shift, axis=0) @ rot(angle).T + np.asarray(offset)


@pytest.mark.parametrize(
    "scale, angle, offset, shift", [(3.7, 0.9, (12.0, -5.0), 0), (0.02, -2.5, (0.0, 1e3), 173)]
)
def test_descriptors_invariant_to_similarity_and_start(scale, angle, offset, shift):
    ref = D.descriptors(CURVE)
    got = D.descriptors(moved(CURVE, scale, angle, offset, shift))
    # the same polygon, started at another vertex and moved: equal up to round-off of
    # sums of 400 terms of size 1 (a few 1e-14), far below any shape difference (below)
    assert np.max(np.abs(got.coeffs - ref.coeffs)) < 1e-11
    assert got.scale == pytest.approx(scale * ref.scale, rel=1e-12)
    assert math.remainder(got.psi - ref.psi - angle, 2 * math.pi) == pytest.approx(0.0, abs=1e-11)
    np.testing.assert_allclose(
        got.locus, scale * rot(angle) @ ref.locus + offset, rtol=0, atol=1e-11 * (1 + 1e3)
    )
    # direction: the curve run backwards, asked backwards, is the curve
    back = D.descriptors(moved(CURVE, scale, angle, offset, shift)[::-1], reverse=True)
    assert np.max(np.abs(back.coeffs - ref.coeffs)) < 1e-11
    # and the descriptors do see shape: a shear is not a similarity
    sheared = D.descriptors(CURVE @ np.array([[1.0, 0.3], [0.0, 1.0]]).T)
    assert np.max(np.abs(sheared.coeffs - ref.coeffs)) > 1e-2


def test_descriptors_of_many_curves_at_once():
    many = np.stack([moved(CURVE, 1.0 + i, 0.3 * i, (i, -i), 17 * i) for i in range(4)])
    got = D.descriptors(many)
    for i in range(4):
        one = D.descriptors(many[i])
        np.testing.assert_allclose(got.coeffs[i], one.coeffs, rtol=0, atol=1e-14)
        assert got.scale[i] == pytest.approx(float(one.scale), rel=1e-14)


def test_coefficients_agree_with_pyefd():
    pyefd = pytest.importorskip("pyefd")
    ref = pyefd.elliptic_fourier_descriptors(np.vstack([CURVE, CURVE[:1]]), order=20)
    got, locus = D.coefficients(CURVE, 20)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-13)
    np.testing.assert_allclose(
        locus, pyefd.calculate_dc_coefficients(np.vstack([CURVE, CURVE[:1]])), atol=1e-14
    )


def test_curve_rebuilt_from_its_descriptors():
    raw, locus = D.coefficients(CURVE, 60)
    norm = D.normalise(raw, locus)
    # the normalised curve moved back by its pose is the raw series started at theta
    back = norm.locus + norm.scale * D.reconstruct(norm.coeffs, n=300) @ rot(float(norm.psi)).T
    np.testing.assert_allclose(back, D.reconstruct(raw, locus, 300, start=float(norm.theta)), atol=1e-13)
    # and 60 harmonics of the polygon lie on it: within 1e-3 of a curve 1.3 across (the
    # truncated series of a curve with a loop; 20 harmonics miss by 3e-3)
    size = np.ptp(CURVE, axis=0).max()
    rebuilt = D.reconstruct(raw, locus, 1000)
    assert D.nearest_distances(rebuilt, CURVE).max() < 1e-3 * size
    assert D.nearest_distances(CURVE, rebuilt).max() < 1e-3 * size


def test_nearest_distances_to_the_polygon():
    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    pts = np.array([[1.0, -0.5], [3.0, 3.0], [1.0, 1.0], [0.0, 1.0]])
    np.testing.assert_allclose(D.nearest_distances(pts, square), [0.5, math.sqrt(2), 1.0, 0.0], atol=1e-15)
    # open: no side from the last vertex back to the first
    assert D.nearest_distances(np.array([[-0.5, 1.0]]), square, closed=False)[0] == pytest.approx(
        math.hypot(0.5, 1)
    )


def test_shape_error_finds_the_similarity():
    target = moved(CURVE[::7], 25.0, 2.2, (40.0, -7.0), 9)
    fit = D.shape_error(target, CURVE)
    # every target point is a vertex of the moved curve: distance 0 up to round-off
    assert fit.mean < 1e-9 * 25 and fit.largest < 1e-8 * 25
    assert fit.scale == pytest.approx(25.0, rel=1e-9)
    assert math.remainder(fit.rotation - 2.2, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(fit.apply(np.roll(CURVE[::7], 9, axis=0)), target, atol=1e-7)
    # a different shape is scored as one
    other = coupler_curve([1.0, 0.3, 1.4, 0.7, -0.2, 0.9, 1], 400)
    assert D.shape_error(target, other).mean > 0.01 * 25


def test_bad_curves_get_named_errors():
    with pytest.raises(SynthesisError, match="at least 3 points"):
        D.descriptors([[0, 0], [1, 1]])
    with pytest.raises(SynthesisError, match="non-finite"):
        D.descriptors([[0, 0], [1, np.nan], [2, 0]])
    with pytest.raises(SynthesisError, match="zero length"):
        D.descriptors([[1, 1]] * 5)
    t = np.linspace(0, 2 * math.pi, 50, endpoint=False)
    with pytest.raises(SynthesisError, match="circle"):
        D.descriptors(np.column_stack([np.cos(t), np.sin(t)]))
    with pytest.raises(SynthesisError, match="harmonics"):
        D.coefficients(CURVE, 0)


@pytest.fixture(scope="module")
def small():
    return A.build_atlas(400, seed=3)


def test_sampled_designs_turn_fully_on_both_circuits(small):
    d = small.designs.astype(np.float64)
    assert len(small) == 400 and small.meta["dropped"] == 0
    assert d.dtype == np.float64 and small.descriptors.dtype == np.float32
    links = d[:, :4]
    s, l_ = links.min(axis=1), links.max(axis=1)
    assert np.all(s + l_ < links.sum(axis=1) - s - l_)  # Grashof
    assert np.all((links[:, 1] == s) | (links[:, 0] == s))  # crank-rocker or double-crank
    assert set(np.unique(d[:, 6])) == {0.0, 1.0}
    assert np.any(links[:, 0] == s) and np.any(links[:, 1] == s)


def test_atlas_curves_are_the_engines_on_the_asked_circuit(small):
    times = np.linspace(0.0, 2 * math.pi, A.STEPS, endpoint=False)
    for i in (0, 5, 6, 201):
        row = small.designs[i].astype(np.float64)
        theta, ok = A._theta3(row[None, 1:4], int(row[6]), times)
        assert ok[0]
        curve = A.coupler_curves(row[None], theta, times)[0]
        np.testing.assert_allclose(curve, coupler_curve(row, A.STEPS), atol=1e-12)
        wrong = coupler_curve(row, A.STEPS, A.CIRCUITS[1 - int(row[6])])
        assert np.abs(curve - wrong).max() > 1e-3


@pytest.mark.parametrize("i", [7, 150, 333])
def test_query_returns_the_design_a_curve_was_sampled_from(small, i):
    row = small.designs[i].astype(np.float64)
    scale, angle, offset = 40.0, 1.1 + i, np.array([-3.0, 250.0])
    # traced at another resolution, started elsewhere, moved: the same shape
    target = moved(coupler_curve(row, 240), scale, angle, offset, 31)
    hits = small.query(target, k=3)
    hit = hits[0]
    assert hit.index == i and hit.distance < 1e-3
    assert hits[1].distance > 10 * hit.distance
    # the transform back: as exact as a 180-step polygon's descriptors allow (h^2 ~ 1e-4)
    assert hit.scale == pytest.approx(scale, rel=1e-3)
    assert math.remainder(hit.rotation - angle, 2 * math.pi) == pytest.approx(0.0, abs=1e-3)
    size = np.ptp(target, axis=0).max()
    # the design in the target's frame traces the target (the engine's sweep of .model())
    assert D.nearest_distances(target, hit.curve(720)).max() < 2e-3 * size
    # the design vector of the notes gives the same curve
    r1, r2, r3, r4, rcx, rcy, theta0, x0, y0 = hit.vector
    t = np.linspace(0, 2 * math.pi, 720, endpoint=False)
    th3 = lw.closed_form.four_bar(r1, r2, r3, r4, t, 1.0, 0.0, hit.circuit)["theta3"]
    local = np.column_stack(
        [
            r2 * np.cos(t) + rcx * np.cos(th3) - rcy * np.sin(th3),
            r2 * np.sin(t) + rcx * np.sin(th3) + rcy * np.cos(th3),
        ]
    )
    np.testing.assert_allclose(local @ rot(theta0).T + [x0, y0], hit.curve(720), atol=1e-9 * size)


@pytest.mark.parametrize("i", [7, 150, 333])
def test_query_matches_the_mirror_image_of_an_atlas_design(small, i):
    # the target: the curve of the atlas design's mirror image (y -> -y: its coupler point
    # mirrored, the other circuit), moved; the atlas holds the design, not its mirror
    row = small.designs[i].astype(np.float64)
    mirror = row.copy()
    mirror[5], mirror[6] = -row[5], 1.0 - row[6]
    target = moved(coupler_curve(mirror, 240), 30.0, 0.7 + i, np.array([5.0, -7.0]), 17)
    size = np.ptp(target, axis=0).max()
    hit = small.query(target, k=3)[0]
    assert hit.index == i and hit.mirrored and hit.distance < 1e-3
    np.testing.assert_allclose(hit.design, mirror)
    assert hit.circuit == A.CIRCUITS[int(mirror[6])]
    # the mirrored design in the target's frame traces the target (the engine's sweep)
    assert D.nearest_distances(target, hit.curve(720)).max() < 2e-3 * size
    # without the mirror the atlas's best is another shape, much farther
    plain = small.query(target, k=1, mirror=False)[0]
    assert not plain.mirrored and plain.distance > 10 * hit.distance
    # asked to keep the target's direction, the mirrored hit's crank runs the points in order
    ahead = small.query(target, k=1, reverse=False)[0]
    assert ahead.index == i and ahead.mirrored and not ahead.reverse
    t = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    curve = ahead.curve(720)
    near = np.argmin(np.sum((target[:, None, :] - curve[None, :, :]) ** 2, axis=-1), axis=1)
    assert np.all(np.mod(np.diff(t[near]), 2 * math.pi) < math.pi)


def test_atlas_saves_and_reads(small, tmp_path):
    path = tmp_path / "atlas.npz"
    small.save(path)
    back = A.Atlas.read(path)
    for key in ("designs", "poses", "descriptors"):
        assert np.array_equal(getattr(back, key), getattr(small, key))
    assert back.meta["seed"] == "3"
    with pytest.raises(SynthesisError, match="cannot read an atlas"):
        A.Atlas.read(tmp_path / "missing.npz")


def test_shipped_atlas_is_what_the_code_builds():
    shipped = A.load()
    assert len(shipped) == 5000 and shipped.harmonics == 20
    assert os.path.getsize(A.DEFAULT) < 2_000_000
    rebuilt = A.build_atlas(5000, seed=int(shipped.meta["seed"]))
    assert np.array_equal(rebuilt.designs, shipped.designs)
    # float32 of the same float64 figures; a last-bit difference of another machine's libm
    np.testing.assert_allclose(rebuilt.descriptors, shipped.descriptors, rtol=0, atol=1e-6)
    np.testing.assert_allclose(rebuilt.poses, shipped.poses, rtol=1e-6, atol=1e-6)


def test_bad_atlas_arguments(small):
    with pytest.raises(SynthesisError, match="positive number of designs"):
        A.build_atlas(0)
    with pytest.raises(SynthesisError, match="scheduler"):
        A.build_atlas(8, scheduler=42)
    with pytest.raises(SynthesisError, match="k must be"):
        small.query(CURVE, k=0)


distributed = pytest.importorskip("distributed")


def test_atlas_on_a_local_cluster_equals_the_in_process_one(client, small):
    # 400 designs in blocks of 64: seven tasks over two worker processes
    on_cluster = A.build_atlas(400, seed=3, scheduler=client, block=64)
    for key in ("designs", "poses", "descriptors"):
        assert np.array_equal(getattr(on_cluster, key), getattr(small, key)), key
    assert on_cluster.meta == small.meta
