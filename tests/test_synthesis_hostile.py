"""Degenerate and hostile input to every synthesis entry point: huge and tiny scales,
near-coincident points and poses, repeated and nearly repeated angles, collinear and
cocircular points. Each call gives dyads and designs that satisfy their own equations
(checked here in world units, independently of the solver) or a named SynthesisError,
within a bounded time; never a panic (InternalError) or another exception."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from linkwork import synthesis as S
from linkwork.errors import SynthesisError

# a five-path problem takes milliseconds and its designs' screening well under a second;
# the bound separates that from a hang
WALL_CLOCK = 10.0
# certified roots: what is left is rounding in the transform to world units
TOL = 1e-7

SETTINGS = settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)


def call(f, *args, **kw):
    """f(*args, **kw), or None for a SynthesisError; any other exception fails the test."""
    start = time.perf_counter()
    try:
        return f(*args, **kw)
    except SynthesisError as e:
        assert str(e), "an error must say what is wrong"
        return None
    finally:
        assert time.perf_counter() - start < WALL_CLOCK, f"{f.__name__} took too long"


def spread(pts: np.ndarray) -> float:
    return float(np.max(np.hypot(*(pts - pts.mean(axis=0)).T)))


def length_change(lengths: np.ndarray, size: float) -> float:
    """Largest change of a link's length, relative to the data's size plus the link."""
    return float(np.ptp(lengths) / (size + np.max(lengths)))


def burmester_error(poses: np.ndarray, d: S.Dyad) -> float:
    """The moving pivot, carried by the body, keeps its distance from the ground pivot."""
    p = poses[:, 0] + 1j * poses[:, 1]
    g, m = complex(*d.ground), complex(*d.moving)
    carried = p + (m - p[0]) * np.exp(1j * (poses[:, 2] - poses[0, 2]))
    return length_change(np.abs(carried - g), spread(poses[:, :2]))


def timed_error(pts: np.ndarray, phi: np.ndarray, d: S.Dyad) -> float:
    """The crank pin, turned by phi about the ground pivot, keeps its distance from P."""
    p = pts[:, 0] + 1j * pts[:, 1]
    g, a1 = complex(*d.ground), complex(*d.moving)
    pins = g + (a1 - g) * np.exp(1j * (phi - phi[0]))
    return length_change(np.abs(p - pins), spread(pts))


def chain_errors(pts, q, o, phi, theta, one, two) -> list[float]:
    """The chained six-bar's two dyad conditions (docs/synthesis.md): |A_n - B_n| and
    |C_n - O| constant."""
    p = pts[:, 0] + 1j * pts[:, 1]
    rot = lambda a: np.exp(1j * (a - a[0]))  # noqa: E731
    out = []
    qc = complex(*q)
    for d in one.real if one else []:
        if d.certified:
            a1, b1 = complex(*d.ground), complex(*d.moving)
            a_n = qc + rot(phi) * (a1 - qc)
            b_n = p + rot(theta) * (b1 - p[0])
            out.append(length_change(np.abs(a_n - b_n), spread(pts)))
    for d in two.real if two else []:
        if d.certified:
            c1, d1 = complex(*d.ground), complex(*d.moving)
            d_n = p + rot(theta) * (d1 - p[0])
            c_n = d_n + rot(phi) * (c1 - d1)
            out.append(length_change(np.abs(c_n - complex(*o)), spread(pts)))
    return out


SHAPES = ("generic", "near-coincident", "collinear", "near-collinear", "cocircular")


@st.composite
def point_sets(draw, n: int = 5) -> np.ndarray:
    """n points of one shape at unit size, then scaled (1e-300 to 1e300, mostly moderate)
    and moved away from the origin by up to ten times their size."""
    shape = draw(st.sampled_from(SHAPES))
    # generic coordinates from a seed: hypothesis' own floats favour 0 and repeats
    u = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).uniform(-1.0, 1.0, (n, 2))
    eps = 10.0 ** draw(st.floats(-14.0, -2.0))
    if shape == "near-coincident":
        u[1] = u[0] + eps * np.array([1.0, 0.3])
    elif shape == "collinear":
        u[:, 1] = 0.5 * u[:, 0] + 0.2
    elif shape == "near-collinear":
        u[:, 1] = 0.5 * u[:, 0] + 0.2 + eps * u[:, 1]
    elif shape == "cocircular":
        u = np.column_stack([np.cos(3.0 * u[:, 0]), np.sin(3.0 * u[:, 0])])
    e = draw(st.one_of(st.floats(-20.0, 20.0), st.floats(-300.0, 300.0)))
    offset = np.array(draw(st.tuples(st.floats(-10.0, 10.0), st.floats(-10.0, 10.0))))
    return (u + offset) * 10.0**e


@st.composite
def angle_sets(draw, n: int = 5) -> np.ndarray:
    """n angles from 0: generic, one repeated, or one repeated to within 1e-14..1e-3."""
    a = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).uniform(-2.0, 2.0, n)
    a[0] = 0.0
    kind = draw(st.sampled_from(("generic", "generic", "repeated", "nearly repeated")))
    if kind == "repeated":
        a[-1] = a[-2]
    elif kind == "nearly repeated":
        a[-1] = a[-2] + 10.0 ** draw(st.floats(-14.0, -3.0))
    return a


def check_designs(result: S.Synthesis | None) -> None:
    """Designs pair real dyads of finite size, each within its equations."""
    if result is None:
        return
    for d in result.designs:
        for x in (d.o2, d.a, d.o4, d.b):
            assert np.all(np.isfinite(x))


@SETTINGS
@given(pts=point_sets(), rot=angle_sets(), method=st.sampled_from(("homotopy", "resultant")))
def test_burmester_dyads_satisfy_their_equations_or_are_refused(pts, rot, method) -> None:
    poses = np.column_stack([pts, rot])
    sols = call(S.dyads, "burmester", poses=poses, method=method)
    for d in sols.real if sols else []:
        if d.certified:
            assert burmester_error(poses, d) < TOL, d


@SETTINGS
@given(pts=point_sets(), phi=angle_sets(), method=st.sampled_from(("homotopy", "resultant")))
def test_timed_dyads_satisfy_their_equations_or_are_refused(pts, phi, method) -> None:
    sols = call(S.dyads, "timed", points=pts, input_angles=phi, method=method)
    for d in sols.real if sols else []:
        if d.certified:
            assert timed_error(pts, phi, d) < TOL, d


@SETTINGS
@given(
    pts=point_sets(),
    phi=angle_sets(),
    theta=angle_sets(),
    q=st.tuples(st.floats(-3, 3), st.floats(-3, 3)),
    o=st.tuples(st.floats(-3, 3), st.floats(-3, 3)),
)
def test_chained_dyads_satisfy_their_equations_or_are_refused(pts, phi, theta, q, o) -> None:
    # the pivots Q and O near the points, at their scale
    size = max(spread(pts), 1e-300)
    q, o = (pts[0] + np.array(v) * size for v in (q, o))
    q, o = (v if np.all(np.isfinite(v)) else pts[0] for v in (q, o))
    one = call(S.dyads, "chain1", points=pts, input_angles=phi, coupler_angles=theta, pivot=q)
    two = call(S.dyads, "chain2", points=pts, input_angles=phi, coupler_angles=theta, pivot=o)
    for err in chain_errors(pts, q, o, phi, theta, one, two):
        assert err < TOL


@settings(SETTINGS, max_examples=10)
@given(pts=point_sets(), phi=angle_sets())
def test_path_designs_satisfy_their_equations_or_are_refused(pts, phi) -> None:
    result = call(S.path, pts, phi)
    check_designs(result)
    for d in result.designs if result else []:
        assert timed_error(pts, phi, d.dyads[0]) < TOL
        poses = np.column_stack([pts, d.coupler_angles])
        assert burmester_error(poses, d.dyads[1]) < TOL


@settings(SETTINGS, max_examples=20)
@given(
    n=st.integers(2, 5),
    pts=point_sets(),
    rot=angle_sets(),
    chosen=st.lists(st.floats(-2.0, 2.0), min_size=4, max_size=4),
)
def test_motion_designs_satisfy_their_equations_or_are_refused(n, pts, rot, chosen) -> None:
    poses = np.column_stack([pts, rot])[:n]
    size = spread(pts) or 1.0
    pick = pts[0] + np.array(chosen).reshape(2, 2) * size
    kw = {"moving": pick} if n in (2, 3) else {}
    result = call(S.motion, poses, **kw)
    check_designs(result)
    if result is None or n == 4:
        return
    for d in result.designs:
        for dyad in d.dyads:
            if dyad.certified:
                assert burmester_error(poses, dyad) < TOL, dyad


@SETTINGS
@given(phi=angle_sets(3), out=st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3), e=st.floats(-300, 300))
def test_function_generators_are_finite_or_refused(phi, out, e) -> None:
    ground = 10.0**e
    fb = call(S.function, phi, out, ground=ground)
    if fb is not None:
        assert all(np.isfinite([fb.a, fb.b, fb.c, fb.d]))
        # Freudenstein's equation at the three pairs, relative to its terms
        k1, k2 = fb.d / fb.a, fb.d / fb.c
        k3 = (fb.a**2 - fb.b**2 + fb.c**2 + fb.d**2) / (2 * fb.a * fb.c)
        psi, ph = np.array(out), np.array(phi)
        size = 1 + abs(k1) + abs(k2) + (fb.a**2 + fb.b**2 + fb.c**2 + fb.d**2) / abs(2 * fb.a * fb.c)
        assert np.all(np.abs(k1 * np.cos(psi) - k2 * np.cos(ph) + k3 - np.cos(ph - psi)) < 1e-8 * size)
    sc = call(S.function, phi, (2.0 + np.array(out)) * ground, kind="slider_crank")
    if sc is not None:
        assert all(np.isfinite([sc.a, sc.b, sc.e]))


@settings(SETTINGS, max_examples=4)
@given(n=st.integers(6, 8), pts=point_sets(8), rot=angle_sets(8))
def test_least_squares_are_finite_or_refused(n, pts, rot) -> None:
    pytest.importorskip("scipy")
    poses = np.column_stack([pts, rot])[:n]
    check_designs(call(S.motion_least_squares, poses, subsets=3))
    check_designs(call(S.path_least_squares, pts[:n], rot[:n], subsets=3))


def test_timed_dyads_at_1e300_are_refused_by_name_and_moderate_scales_solved() -> None:
    """The reported case: 1e300 panicked in the homotopy (InternalError)."""
    unit = np.array([[0.0, 0.0], [1.0, 0.2], [1.8, 1.0], [1.5, 2.1], [0.4, 2.4]])
    phi = np.array([0.0, 0.4, 0.9, 1.5, 2.2])
    for s in (1e300, 1e-300):
        with pytest.raises(SynthesisError, match="cannot be scaled to unit size"):
            S.dyads("timed", points=unit * s, input_angles=phi)
        with pytest.raises(SynthesisError, match="cannot be scaled to unit size"):
            S.path(unit * s, phi)
    reference = S.dyads("timed", points=unit, input_angles=phi)
    for s in (1e100, 1e-100):
        sols = S.dyads("timed", points=unit * s, input_angles=phi)
        assert len(sols.real) == len(reference.real) > 0
        for d, r in zip(sols.real, reference.real):
            assert np.allclose(d.ground / s, r.ground, atol=1e-9)


def test_nine_collinear_points_are_refused_at_once() -> None:
    """They ran for minutes; no four-bar's coupler curve meets a line in 7 points."""
    x = np.linspace(0.0, 8.0, 9)
    start = time.perf_counter()
    with pytest.raises(SynthesisError, match="lie on one line"):
        S.nine_points(np.column_stack([x, 0.5 * x + 1.0]))
    assert time.perf_counter() - start < 0.5
    generic = np.random.default_rng(1).normal(size=(9, 2))
    for s in (1e300, 1e-300):
        with pytest.raises(SynthesisError, match="cannot be scaled"):
            S.nine_points(generic * s)


def test_nine_nearly_collinear_points_end_within_the_budget() -> None:
    """Off a line by 1e-6 of their size: the paths wander (for minutes, unbounded); the
    instance stops within its wall-clock budget (here 2 s) and reports what it found."""
    rng = np.random.default_rng(3)
    x = np.linspace(0.0, 8.0, 9)
    pts = np.column_stack([x, 0.5 * x + 1.0 + 1e-6 * rng.normal(size=9)])
    start = time.perf_counter()
    r = S.nine_points(pts, screen=False, seconds=2.0)
    assert time.perf_counter() - start < 6.0
    assert r.paths == 1442 and r.seconds < 4.0
    assert 0 < r.over_budget <= r.failed
    assert f"{r.failed} failed ({r.over_budget} over budget)" in r.report()
    with pytest.raises(SynthesisError, match="time budget"):
        S.nine_points(pts, seconds=0.0)
