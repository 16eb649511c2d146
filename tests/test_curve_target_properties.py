"""Properties of the target curves of synthesis from a curve (linkwork.synthesis.curve
.target), fast and without the engine: each bad input is refused with a SynthesisError
naming what is at fault (and the input just inside each check is accepted), a CSV table
gives back the numbers written to it, and an SVG path is sampled on the curve it draws,
evenly by arc length, the same whether drawn with absolute or relative commands, its
smooth segments (S, T) the explicit ones with the reflected control point."""

from __future__ import annotations

import importlib
import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork.errors import SynthesisError

# the module (the package's name `target` is its function)
T = importlib.import_module("linkwork.synthesis.curve.target")

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
SVG = '<svg xmlns="http://www.w3.org/2000/svg">{}</svg>'


def _polyline(seed: int, n: int) -> np.ndarray:
    """n points, each step at least 0.5 long (no coincident neighbours)."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.0, 2 * math.pi, n - 1)
    steps = rng.uniform(0.5, 2.0, n - 1)[:, None] * np.column_stack([np.cos(a), np.sin(a)])
    start = rng.uniform(-5.0, 5.0, 2)
    return np.vstack([start, start + np.cumsum(steps, axis=0)])


# ---- target(): what it keeps and what it refuses -------------------------------------------
def test_a_target_keeps_its_points_closure_and_angles() -> None:
    t = T.target(SQUARE.tolist(), closed=1, crank_angles=[[0.1], [0.2], [0.4], [0.3]])
    assert isinstance(t.points, np.ndarray) and np.array_equal(t.points, SQUARE)
    assert t.closed is True and t.timed and len(t) == 4
    assert np.array_equal(t.crank_angles, [0.1, 0.2, 0.4, 0.3])  # any order but no repeat
    free = T.target(SQUARE)
    assert free.closed is False and not free.timed and free.crank_angles is None
    direct = T.TargetCurve(SQUARE)  # built without the checks: open and untimed
    assert direct.closed is False and not direct.timed
    # the size is the bounding box's diagonal, wherever the box is
    assert T.target(SQUARE + [7.0, -9.0]).size == pytest.approx(5.0, rel=1e-15)


def test_require_counts_the_points() -> None:
    t = T.target(SQUARE)
    t.require(4, "the method")
    with pytest.raises(SynthesisError, match="the method needs at least 5 target points, the curve has 4"):
        t.require(5, "the method")


@pytest.mark.parametrize("shape", [(6,), (3, 3), (2, 3, 2), (3, 1)])
def test_points_not_n_by_2_are_named(shape: tuple[int, ...]) -> None:
    with pytest.raises(SynthesisError, match=rf"n x 2 array.*{re.escape(str(shape))}"):
        T.target(np.ones(shape))


@pytest.mark.parametrize("minimum", [1, 3, 5])
def test_the_least_number_of_points_is_the_asked_minimum(minimum: int) -> None:
    p = _polyline(1, minimum)
    assert len(T.target(p, minimum=minimum)) == minimum
    with pytest.raises(SynthesisError, match=f"at least {minimum + 1} points, got {minimum}"):
        T.target(p, minimum=minimum + 1)


@settings(max_examples=25, deadline=None)
@given(n=st.integers(3, 9), data=st.data())
def test_the_first_non_finite_point_is_named(n: int, data: st.DataObject) -> None:
    p = _polyline(n, n)
    k = data.draw(st.integers(0, n - 1))
    p[k, data.draw(st.integers(0, 1))] = data.draw(st.sampled_from([math.nan, math.inf, -math.inf]))
    if k + 1 < n:
        p[k + 1, 0] = math.nan  # a later one is not the one named
    with pytest.raises(SynthesisError, match=rf"target point {k + 1} is not finite"):
        T.target(p)


@settings(max_examples=25, deadline=None)
@given(n=st.integers(3, 9), size=st.sampled_from([1e-6, 1.0, 1e6]), data=st.data())
def test_coincident_neighbours_are_named_at_1e_12_of_the_size(
    n: int, size: float, data: st.DataObject
) -> None:
    """Neighbours closer than 1e-12 of the bounding box's diagonal are one point twice
    (named by their numbers); 3e-12 apart they are two points, whatever the size."""
    p = size * _polyline(n + 10, n)
    k = data.draw(st.integers(0, n - 2))
    q = p.copy()
    q[k + 1] = q[k]
    scale = float(np.hypot(*np.ptp(q, axis=0)))  # the box without the moved point
    q[k + 1] = q[k] + [0.5e-12 * scale, 0.0]
    with pytest.raises(SynthesisError, match=rf"target points {k + 1} and {k + 2} coincide"):
        T.target(q)
    q[k + 1] = q[k] + [0.0, 3e-12 * scale]
    assert np.array_equal(T.target(q).points, q)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (3.0, -2.0)])
def test_a_closed_target_that_repeats_its_first_point_is_named(offset: tuple[float, float]) -> None:
    square, scale = SQUARE + offset, 5.0
    with pytest.raises(SynthesisError, match="repeats its first point"):
        T.target(np.vstack([square, square[:1]]), closed=True)
    with pytest.raises(SynthesisError, match="repeats its first point"):
        T.target(np.vstack([square, square[0] + [0.5e-12 * scale, 0.0]]), closed=True)
    # a last point near the first, but not on it, is a point; an open curve may end at its start
    assert len(T.target(np.vstack([square, square[0] + [0.0, 3e-12 * scale]]), closed=True)) == 5
    assert len(T.target(np.vstack([square, square[:1]]), closed=False)) == 5


def test_bad_crank_angles_are_named() -> None:
    with pytest.raises(SynthesisError, match="3 crank angles for 4 target points"):
        T.target(SQUARE, crank_angles=[0.0, 1.0, 2.0])
    with pytest.raises(SynthesisError, match="5 crank angles for 4 target points"):
        T.target(SQUARE, crank_angles=np.arange(5.0))
    for bad in (math.nan, math.inf):
        with pytest.raises(SynthesisError, match="crank angle is not finite"):
            T.target(SQUARE, crank_angles=[0.0, bad, 2.0, 3.0])
    for k in range(3):
        angles = [0.0, 1.0, 2.0, 3.0]
        angles[k + 1] = angles[k]
        with pytest.raises(
            SynthesisError, match=f"target points {k + 1} and {k + 2} have the same crank angle"
        ):
            T.target(SQUARE, crank_angles=angles)
    # equal angles that are not neighbours are allowed (a curve traced over two turns)
    assert T.target(SQUARE, crank_angles=[0.0, 1.0, 0.0, 1.0]).timed


# ---- CSV --------------------------------------------------------------------------------------
@settings(max_examples=20, deadline=None)
@given(n=st.integers(3, 8), header=st.booleans(), timed=st.booleans(), closed=st.booleans())
def test_csv_gives_back_the_numbers_written(
    tmp_path_factory, n: int, header: bool, timed: bool, closed: bool
) -> None:
    p = _polyline(n, n)
    angles = np.cumsum(np.linspace(0.1, 0.5, n))
    cols = np.column_stack([p, angles]) if timed else p
    text = ("x,y,theta2\n" if header else "") + "\n".join(",".join(repr(float(v)) for v in r) for r in cols)
    f = tmp_path_factory.mktemp("csv") / "t.csv"
    f.write_text("\n" + text + "\n\n , \n")  # blank rows and a row of blanks are skipped
    t = T.from_csv(f, closed=closed)
    assert np.array_equal(t.points, p) and t.closed == closed
    assert t.timed == timed and (not timed or np.array_equal(t.crank_angles, angles))


def test_bad_csv_is_named(tmp_path: Path) -> None:
    cases = {
        "": "no rows",
        "x,y\n1,2\n3,x\n": "a cell is not a number",
        "x,y\n1,2\n3,4,5\n6,7\n": r"every row is x, y or x, y, crank angle \(found \[2, 3\] columns\)",
        "x\n1\n2\n3\n": r"found \[1\] columns",
        "1,2,3,4\n5,6,7,8\n9,1,2,3\n": r"found \[4\] columns",
        "x,y\n": r"found \[\] columns",
        "0,0\n1,0\n": "at least 3 points",
    }
    for k, (text, match) in enumerate(cases.items()):
        f = tmp_path / f"bad{k}.csv"
        f.write_text(text)
        with pytest.raises(SynthesisError, match=match):
            T.from_csv(f)
    f = tmp_path / "two.csv"
    f.write_text("0,0\n1,0\n")
    assert len(T.from_csv(f, minimum=2)) == 2
    assert not T.from_csv(f, minimum=2).closed  # open unless asked


# ---- SVG ---------------------------------------------------------------------------------------
def _arc_steps(p: np.ndarray, closed: bool) -> np.ndarray:
    ring = np.vstack([p, p[:1]]) if closed else p
    return np.hypot(*np.diff(ring, axis=0).T)


@settings(max_examples=30, deadline=None)
@given(n=st.integers(2, 6), seed=st.integers(0, 10_000), closed=st.booleans(), samples=st.integers(5, 40))
def test_a_polyline_is_sampled_on_itself_evenly_absolute_or_relative(
    n: int, seed: int, closed: bool, samples: int
) -> None:
    """M, L (and H, V where a step is level) and their relative forms draw the same
    polyline; the samples lie on it, at equal arc length apart (closed: around it, the
    closing side included, the start not repeated)."""
    p = _polyline(seed, n + 1)
    p[2, 1] = p[1, 1]  # one level step (p1 -> p2): drawn with H / h
    p, d = p.tolist(), np.diff(p, axis=0).tolist()  # floats, whose repr parses back exactly
    absolute = f"M{p[0][0]!r},{p[0][1]!r} " + " ".join(
        f"H{b[0]!r}" if k == 2 else f"L{b[0]!r},{b[1]!r}" for k, b in enumerate(p[1:], 1)
    )
    relative = f"m{p[0][0]!r} {p[0][1]!r} " + " ".join(
        f"h{v[0]!r}" if k == 2 else f"l{v[0]!r} {v[1]!r}" for k, v in enumerate(d, 1)
    )
    p = np.array(p)
    tail = " Z" if closed else ""
    a, ca = T.svg_path_points(absolute + tail, samples)
    b, cb = T.svg_path_points(relative + tail.lower(), samples)
    assert ca == cb == closed and a.shape == (samples, 2)
    size = float(np.ptp(p, axis=0).max())
    np.testing.assert_allclose(b, a, rtol=0.0, atol=1e-12 * size)
    # on the polyline (closed: with its closing side)
    from linkwork.synthesis.curve.descriptors import nearest_distances

    assert nearest_distances(a, p, closed=closed).max() <= 1e-12 * size
    np.testing.assert_allclose(a[0], p[0], atol=1e-12 * size)
    # the k-th sample is k equal steps of arc length along the polyline, walked here
    ring = np.vstack([p, p[:1]]) if closed else p
    sides = _arc_steps(p, closed)
    cum = np.concatenate([[0.0], np.cumsum(sides)])
    step = cum[-1] / (samples if closed else samples - 1)
    for k, got in enumerate(a):
        u = k * step
        i = min(int(np.searchsorted(cum, u, side="right")) - 1, len(sides) - 1)
        while sides[i] == 0.0:
            i -= 1
        want = ring[i] + (u - cum[i]) / sides[i] * (ring[i + 1] - ring[i])
        np.testing.assert_allclose(got, want, rtol=0.0, atol=1e-11 * size)


def test_a_square_is_sampled_at_equal_arc_length_with_vertical_and_horizontal_moves() -> None:
    pts, closed = T.svg_path_points("M0 0 H4 V3 H0 Z", samples=14)
    assert closed
    # perimeter 14: a sample each unit of arc length, corners included, the start once
    expected = [[x, 0] for x in range(4)] + [[4, y] for y in range(3)]
    expected += [[4 - x, 3] for x in range(4)] + [[0, 3 - y] for y in range(3)]
    np.testing.assert_allclose(pts, expected, atol=1e-12)
    rel, _ = T.svg_path_points("m0 0 h4 v3 h-4 z", samples=14)
    np.testing.assert_allclose(rel, pts, atol=1e-12)
    # a path ending where it starts without Z is open: its last sample is the start
    pts, closed = T.svg_path_points("M0 0 H4 V3 H0 V0", samples=15)
    assert not closed and np.allclose(pts[-1], [0, 0], atol=1e-12) and np.allclose(pts[1], [1, 0])


def test_a_closing_z_adds_the_closing_side() -> None:
    """Z draws the side back to the start: the samples go round a triangle of
    perimeter 12 (3, 4, 5), every unit of arc length."""
    pts, closed = T.svg_path_points("M0,0 L4,0 L4,3 Z", samples=12)
    assert closed
    along = np.array([[4 - 0.8 * k, 3 - 0.6 * k] for k in range(1, 5)])
    expected = np.vstack([[[x, 0] for x in range(4)], [[4, y] for y in range(3)], [[4, 3]], along])
    np.testing.assert_allclose(pts, expected, atol=1e-12)


def test_cubic_and_quadratic_segments_are_their_bezier_curves() -> None:
    """The Bernstein form against de Casteljau's construction at the samples' own
    parameters, for C and Q, absolute and relative."""
    ctrl = np.array([[0.0, 0.0], [1.0, 3.0], [4.0, 3.0], [5.0, 0.0]])
    t = np.linspace(0.0, 1.0, 11)
    got = T._bezier(ctrl, t)
    for k, tk in enumerate(t):
        pts = ctrl.copy()
        while len(pts) > 1:
            pts = (1 - tk) * pts[:-1] + tk * pts[1:]
        np.testing.assert_allclose(got[k], pts[0], atol=1e-14)
    # a cubic sampled from its path data lies on its Bernstein curve
    pts, _ = T.svg_path_points("M0,0 C1,3 4,3 5,0", samples=21)
    dense = T._bezier(ctrl, np.linspace(0.0, 1.0, 20001))
    from linkwork.synthesis.curve.descriptors import nearest_distances

    # the samples lie on chords of 1/256 of the segment's parameter: off the curve by at
    # most the sagitta h^2 kappa / 8 (largest chord h, curvature kappa): 8.5e-5 for this
    # cubic (h 0.037, kappa 0.5), 1.2e-4 for the parabola below (h 0.033, kappa 0.88)
    assert nearest_distances(pts, dense, closed=False).max() < 8.6e-5
    rel, _ = T.svg_path_points("m0,0 c1,3 4,3 5,0", samples=21)
    np.testing.assert_allclose(rel, pts, atol=1e-12)
    qa, _ = T.svg_path_points("M1,1 Q2,4 5,1", samples=9)
    qr, _ = T.svg_path_points("m1,1 q1,3 4,0", samples=9)
    np.testing.assert_allclose(qr, qa, atol=1e-12)
    parabola = T._bezier(np.array([[1.0, 1.0], [2.0, 4.0], [5.0, 1.0]]), np.linspace(0.0, 1.0, 20001))
    assert nearest_distances(qa, parabola, closed=False).max() < 1.2e-4


def test_smooth_segments_reflect_the_last_control_point() -> None:
    """S (T) is C (Q) with the first control point the previous segment's last one
    reflected through the current point; after a segment of another kind, the current
    point itself."""
    pairs = [
        ("M0,0 C1,2 3,2 4,0 S7,-2 8,0", "M0,0 C1,2 3,2 4,0 C5,-2 7,-2 8,0"),
        ("M0,0 C1,2 3,2 4,0 s3,-2 4,0", "M0,0 C1,2 3,2 4,0 C5,-2 7,-2 8,0"),
        ("M0,0 L4,0 S7,-2 8,0", "M0,0 L4,0 C4,0 7,-2 8,0"),
        ("M0,0 Q2,3 4,0 T8,0", "M0,0 Q2,3 4,0 Q6,-3 8,0"),
        ("M0,0 Q2,3 4,0 t4,0", "M0,0 Q2,3 4,0 Q6,-3 8,0"),
        ("M0,0 C1,2 3,2 4,0 T8,0", "M0,0 C1,2 3,2 4,0 Q4,0 8,0"),
        ("M0,0 Q2,3 4,0 S7,-2 8,0", "M0,0 Q2,3 4,0 C4,0 7,-2 8,0"),
    ]
    for smooth, explicit in pairs:
        a, _ = T.svg_path_points(smooth, 17)
        b, _ = T.svg_path_points(explicit, 17)
        np.testing.assert_allclose(a, b, atol=1e-12, err_msg=smooth)


def test_moveto_pairs_after_the_first_are_line_tos() -> None:
    a, _ = T.svg_path_points("M0,0 3,0 3,4", 8)
    b, _ = T.svg_path_points("M0,0 L3,0 L3,4", 8)
    np.testing.assert_allclose(a, b, atol=1e-12)
    a, _ = T.svg_path_points("m1,1 3,0 0,4", 8)
    b, _ = T.svg_path_points("M1,1 L4,1 L4,5", 8)
    np.testing.assert_allclose(a, b, atol=1e-12)
    # a vertical move: relative to the current y, absolute to the origin's
    a, _ = T.svg_path_points("M1,1 v3 V2 h-1", 7)
    b, _ = T.svg_path_points("M1,1 L1,4 L1,2 L0,2", 7)
    np.testing.assert_allclose(a, b, atol=1e-12)


@pytest.mark.parametrize(
    "d",
    [
        "M0,0 L0.5,0",  # one side: there and back
        "M0.1,0 L0.4,0 L0.1,0 L0.1,0.3",  # the last side starts at the start
        "M0,0 L0.4,0 C0,0 0.2,0.3 0.2,0.3",  # the last segment's first control point at the start
        "M0,0 Q0.5,0.5 0.6,0 T0.9,0.2",
    ],
)
def test_z_draws_the_side_back_to_the_start(d: str) -> None:
    """Z is a last line to the start (short sides included): the same samples as the
    path closed by that line drawn explicitly, and the start not repeated."""
    start = d.split()[0][1:]
    implicit, closed = T.svg_path_points(d + " Z", 24)
    explicit, _ = T.svg_path_points(f"{d} L{start} Z", 24)
    assert closed
    np.testing.assert_allclose(implicit, explicit, atol=1e-12)
    assert np.hypot(*(implicit[-1] - implicit[0])) > 1e-3


def test_defaults_and_the_shortest_paths() -> None:
    """64 samples unless asked (an SVG's too); three samples pass the default minimum; a
    single line, and one after a zero-length first side, are paths."""
    assert T.svg_path_points("M0,0 L1,0")[0].shape == (64, 2)
    pts, _ = T.svg_path_points("M0,0 L1,0", 3)
    np.testing.assert_allclose(pts, [[0, 0], [0.5, 0], [1, 0]], atol=1e-15)
    pts, _ = T.svg_path_points("M0,0 L0,0 L1,0", 3)
    np.testing.assert_allclose(pts, [[0, 0], [0.5, 0], [1, 0]], atol=1e-15)
    line = SVG.format('<path d="M0,0 L4,0 L4,3"/>')
    assert len(T.from_svg(line)) == 64 and len(T.from_svg(line, samples=3)) == 3


def test_a_path_without_a_first_moveto_starts_at_the_origin() -> None:
    for d in ("L4,0 L4,3 Z", "l4,0 l0,3 z"):
        a, closed = T.svg_path_points(d, 12)
        b, _ = T.svg_path_points("M0,0 L4,0 L4,3 Z", 12)
        assert closed
        np.testing.assert_allclose(a, b, atol=1e-12)


def test_bad_path_data_is_named() -> None:
    cases = {
        "M 0 0 A 1 1 0 0 1 2 2": "does not parse",
        "M0,0 L1,1 # ": "does not parse",
        "0,0 L1,1": "starts with a number",
        "M0,0 L1": r"command 'L' needs 2 numbers",
        "M0,0 C1,1 2,2 L3,3": r"command 'C' needs 6 numbers",
        "M0,0 L1,0 M2,2 L3,3": "more than one subpath",
        "M0,0 L1,0 Z M2,2": "more than one subpath",
        "M0,0": "draws nothing",
        "M1,1 Z": "draws nothing",
        "M1,1 L1,1 L1,1": "zero length",
    }
    for d, match in cases.items():
        with pytest.raises(SynthesisError, match=match):
            T.svg_path_points(d)


def test_from_svg_flips_y_and_names_bad_files(tmp_path: Path) -> None:
    f = tmp_path / "t.svg"
    f.write_text(SVG.format('<g><rect/><path d=""/><path d="M0,0 H4 V3 H0 Z"/></g>'))
    t = T.from_svg(f, samples=14)  # the first path with data, read from a file
    pts, _ = T.svg_path_points("M0,0 H4 V3 H0 Z", 14)
    assert t.closed and np.array_equal(t.points, pts * [1.0, -1.0])
    assert not T.from_svg(f, samples=14, closed=False).closed
    assert T.from_svg(SVG.format('<path d="M0,0 L4,0 L4,3"/>'), samples=5, closed=True).closed
    with pytest.raises(SynthesisError, match="at least 9 points, got 8"):
        T.from_svg(f, samples=8, minimum=9)
    with pytest.raises(SynthesisError, match="not well-formed XML"):
        T.from_svg("<svg><path d='M0 0 L1 1'></svg>")
    with pytest.raises(SynthesisError, match="no <path> with a d attribute"):
        T.from_svg(SVG.format('<path d=""/><circle r="1"/>'))
