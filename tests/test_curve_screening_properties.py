"""Properties of how refined curve designs are screened and told apart, fast (one engine
sweep each): the order defect (crank angles not increasing, or a closed curve's beyond a
turn), the branch defect (a crank that cannot turn through the stretch), the smallest
transmission angle over the traced stretch only (against the exact one of
`constraints.smallest_transmission`: the sweep's 361 steps approach it from above, to
second order in the step of at most 2 pi / 360: within (h / 2)^2 / 2 |mu''| < 1e-4
here), what `ok` means, and which designs `distinct` counts as repeats."""

from __future__ import annotations

import importlib
import math
from types import SimpleNamespace

import numpy as np
import pytest

from linkwork import examples
from linkwork.errors import SolveError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve import constraints as K
from linkwork.synthesis.curve.problem import distinct
from linkwork.synthesis.curve.tracking import coupler_points

F = importlib.import_module("linkwork.synthesis.curve.fit")  # the module, not `fit` the function

X = np.array([2.0, 0.5, 1.8, 1.5, 0.4, 0.3, 0.2, 0.1, -0.2])  # a crank-rocker
TH = np.array([0.4, 1.3, 2.0, 3.9, 5.0])


def _problem(closed: bool = False, circuit: str = "open") -> C.TrackingProblem:
    return C.TrackingProblem(C.target(coupler_points(X, TH, circuit), closed=closed), circuit=circuit)


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_a_crank_rocker_traced_forwards_is_defect_free_with_the_exact_smallest_angle(circuit: str) -> None:
    problem = _problem(circuit=circuit)
    x = np.concatenate([X, TH])
    defects, trans, kind = F._screen(problem, x)
    assert defects == () and kind == "crank-rocker"
    exact = K.smallest_transmission(x, closed=False)[0]
    assert -1e-12 <= trans - exact <= 1e-4


@pytest.mark.parametrize("th", [np.linspace(0.5, 2.5, 5), np.linspace(4.0, 5.5, 5)])
def test_the_smallest_angle_is_over_the_traced_stretch_only(th: np.ndarray) -> None:
    """Stretches from 0.5 to 2.5 rad and from 4.0 to 5.5 rad hold neither 0 nor pi: the
    smallest transmission angle is at an end (on the second, the last: d shrinks towards
    2 pi), larger than the whole turn's (at theta2 = 0), which the sweep passes on its way
    from the drawing to the stretch's start or would reach past the stretch's end."""
    x = np.concatenate([X, th])
    _, trans, _ = F._screen(_problem(), x)
    exact = K.smallest_transmission(x, closed=False)[0]
    turn = K.smallest_transmission(x, closed=True)[0]
    assert turn < exact - 0.05
    assert -1e-12 <= trans - exact <= 1e-4


def test_crank_angles_out_of_order_are_an_order_defect() -> None:
    problem = _problem()
    for th in (TH[::-1], np.array([0.4, 1.3, 1.3, 3.9, 5.0])):  # backwards; a repeated angle
        defects, _, _ = F._screen(problem, np.concatenate([X, th]))
        assert "order" in defects


def test_a_closed_curve_traced_over_more_than_a_turn_is_an_order_defect() -> None:
    """Closed: within one turn is in order (its smallest angle that of the whole turn);
    exactly a turn or beyond is not."""
    problem = _problem(closed=True)
    for th in (TH, TH + 1.0):  # spans of 4.6 rad, ending before and after 2 pi
        x = np.concatenate([X, th])
        defects, trans, _ = F._screen(problem, x)
        assert defects == ()
        assert -1e-12 <= trans - K.smallest_transmission(x, closed=True)[0] <= 1e-4
    for last in (TH[0] + 2 * math.pi, 6.8):
        th = np.append(TH[:-1], last)
        assert F._screen(problem, np.concatenate([X, th]))[0] == ("order",)


def test_a_crank_that_cannot_turn_through_the_stretch_is_a_branch_defect() -> None:
    """r = (2.0, 1.0, 1.2, 1.5): s + l = 3.0 > p + q = 2.7, not Grashof; it assembles at
    theta2 = 0 (d = 1.0) but not at pi (d = 3.0 > r3 + r4): a dead point inside the
    stretch. The design is still reported, with its kind."""
    x = np.concatenate([[2.0, 1.0, 1.2, 1.5], X[4:], TH])
    defects, _, kind = F._screen(_problem(), x)
    assert "branch" in defects and "order" not in defects
    assert kind != "crank-rocker"


def _design(x, circuit="open", size=1.0):
    return SimpleNamespace(
        x=np.asarray(x, dtype=float),
        circuit=circuit,
        problem=SimpleNamespace(target=SimpleNamespace(size=size)),
    )


def test_distinct_drops_repeats_to_a_millionth_of_the_size_and_a_whole_turn() -> None:
    """Repeats: the same circuit, lengths, coupler point and pivot to 1e-6 of the target's
    size (here 2) and theta0 the same modulo a turn; the crank angles do not count."""
    base = np.concatenate([X, TH])
    near = base.copy()
    near[[0, 5, 8]] += 1.9e-6  # within 2e-6
    turned = base.copy()
    turned[6] += 2 * math.pi
    angles = base.copy()
    angles[9:] += 0.3
    far = base.copy()
    far[4] += 2.1e-6  # beyond 2e-6, in the coupler point
    moved = base.copy()
    moved[6] += 1e-3  # theta0 not a whole turn apart
    designs = [_design(v, size=2.0) for v in (base, near, turned, angles, far, moved)]
    designs.append(_design(base, circuit="crossed", size=2.0))
    kept = distinct(designs)
    assert kept == [designs[0], designs[4], designs[5], designs[6]]


def test_ok_means_defect_free_and_within_the_constraints() -> None:
    problem = _problem()
    x = np.concatenate([X, TH])

    def design(defects, violation):
        return F.CurveDesign(problem, x, 0.0, 0.0, 0.5, violation, "crank-rocker", defects, 1, 0.0)

    size = problem.target.size
    assert design((), 0.0).ok and design((), 1e-12 * size).ok  # the bound itself holds
    assert not design((), 1.1e-12 * size).ok
    assert not design(("order",), 0.0).ok and not design(("circuit",), 0.0).ok


def test_an_obtuse_smallest_angle_is_measured_from_180_degrees() -> None:
    """r = (2.0, 0.3, 1.5, 1.2), a crank-rocker whose transmission angle is obtuse over
    2.0 to 2.6 rad (cos mu about -0.25 to -0.4): its distance from 180 degrees counts."""
    x = np.concatenate([[2.0, 0.3, 1.5, 1.2], X[4:], np.linspace(2.0, 2.6, 5)])
    defects, trans, _ = F._screen(_problem(), x)
    exact = K.smallest_transmission(x, closed=False)[0]
    assert defects == () and exact < 1.4  # well below 90 degrees: mu itself is above
    assert -1e-12 <= trans - exact <= 1e-4


def test_a_stretch_the_crank_cannot_reach_has_no_transmission_angle() -> None:
    """r = (2.0, 1.0, 1.2, 1.5) assembles only for cos theta2 >= -0.5725 (theta2 <= 2.18
    rad from the drawing): the sweep stops before a stretch from 3.5 to 5.0 rad."""
    x = np.concatenate([[2.0, 1.0, 1.2, 1.5], X[4:], np.linspace(3.5, 5.0, 5)])
    defects, trans, _ = F._screen(_problem(), x)
    assert "branch" in defects and trans == 0.0


@pytest.mark.parametrize(("off", "defect"), [(0.6e-7, False), (1.4e-7, True)])
def test_a_traced_point_off_its_circuit_by_more_than_1e_7_of_the_scale_is_a_circuit_defect(
    monkeypatch: pytest.MonkeyPatch, off: float, defect: bool
) -> None:
    """The scale is the larger of the target's size (0.71 here) and the longest link (2.0;
    the coupler point, 3.0 away, is no link): the engine's points against a closed form
    moved by off * 2.0 in x are on the circuit below 1e-7 of it, off it above (and
    would be judged otherwise with the size or the coupler point as the scale)."""
    x = np.concatenate([X[:4], [3.0], X[5:], TH])
    problem = C.TrackingProblem(C.target(0.5 * np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])))
    assert problem.target.size < 1.0
    closed_form = F.coupler_points
    monkeypatch.setattr(F, "coupler_points", lambda *a: closed_form(*a) + [off * 2.0, 0.0])
    defects, _, _ = F._screen(problem, x)
    assert ("circuit" in defects) == defect


def test_the_screened_stretch_starts_at_the_drawing_and_samples_as_stated() -> None:
    """The screening sweep starts at the drawn start (t = 0), reaches the first crank
    angle in 72 equal steps and covers the traced stretch in 360 (a closed curve: one
    turn, a degree a step); angles that do not increase are an order defect."""
    th = np.array([1.0, 1.5, 2.0, 3.0])
    defects, times, first = F.screened_stretch(th, closed=False)
    assert defects == [] and first == 1.0
    assert times[0] == 0.0 and np.all(np.diff(times) > 0.0)
    np.testing.assert_allclose(np.diff(times[:73]), 1.0 / 72, rtol=1e-12)
    np.testing.assert_allclose(np.diff(times[72:]), 2.0 / 360, rtol=1e-12)
    assert len(times) == 73 + 360 and times[-1] == pytest.approx(3.0, abs=1e-15)
    _, times, first = F.screened_stretch(th + 2.0 * np.pi, closed=True)
    assert first == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(np.diff(times[72:]), 2.0 * np.pi / 360, rtol=1e-12)
    assert F.screened_stretch(th[::-1], closed=False)[0] == ["order"]


def test_a_sweep_stopped_right_after_the_drawing_is_a_branch_defect_only() -> None:
    """r4 1e-7 above the toggle at the drawing (r1 - r2 = r3 + r4 at theta2 = 0): the
    sweep's first row is the drawing, on its circuit, and it stops before the next: a
    branch defect, no circuit defect, no angle over the stretch."""
    x = np.concatenate([[2.0, 0.5, 0.8, 0.7 + 1e-7], X[4:], TH])
    assert F._screen(_problem(), x)[:2] == (("branch",), 0.0)


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_a_four_bar_drawn_exactly_at_a_dead_point_is_reported_not_raised(circuit: str) -> None:
    """r1 - r2 = r4 - r3 exactly (2 - 0.5 = 1.75 - 0.25, each a binary fraction): at
    theta2 = 0 the coupler and the
    rocker lie folded along one line, a dead point at the drawing itself, where the
    engine can neither assemble the linkage nor take a step: the screening reports a
    branch defect (and, with no row swept, a circuit defect and no angle), with the type
    from the lengths (s + l = 0.25 + 2 = p + q: a change point), not SingularError."""
    x = np.concatenate([[2.0, 0.5, 0.25, 1.75], X[4:], TH])
    defects, trans, kind = F._screen(_problem(circuit=circuit), x)
    assert defects == ("branch", "circuit") and trans == 0.0 and kind == "change point"


@pytest.mark.parametrize(
    ("lengths", "theta2"),
    [
        ((2.0, 0.5, 1.8, 1.5), 0.3),  # crank-rocker
        ((0.5, 2.0, 1.8, 1.5), 0.3),  # double-crank
        ((2.0, 1.8, 0.5, 1.5), 0.8),  # Grashof double-rocker
        ((2.0, 1.5, 1.8, 0.5), 1.0),  # rocker-crank
        ((2.0, 1.2, 1.9, 1.3), 0.3),  # non-Grashof
        ((2.0, 0.5, 1.0, 1.5), 1.0),  # change point
    ],
)
def test_the_grashof_type_from_the_lengths_is_the_engines(lengths: tuple[float, ...], theta2: float) -> None:
    """`grashof_type` (for a drawing the engine cannot assemble) names what the engine's
    `Linkage.kind_of` names for the same lengths drawn at a crank angle where they close."""
    drawn = examples.four_bar(*lengths, theta0=theta2).compile().linkages()[0]
    assert K.grashof_type(*lengths) == drawn.kind_of


def test_a_sweep_that_gives_no_row_is_a_circuit_defect_without_an_angle(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The design cannot be followed from its drawing at all (the sweep raises before
    its first row, with no partial result): reported as a branch and a circuit defect
    with no transmission angle, not an error."""
    problem = _problem()
    model = problem.model

    class NoRow:
        def __init__(self, compiled: object) -> None:
            self.compiled = compiled

        def linkages(self) -> object:
            return self.compiled.linkages()  # type: ignore[attr-defined]

        def sweep(self, *args: object, **kwargs: object) -> object:
            raise SolveError("no row")

    class Drawn:
        def __init__(self, x: object) -> None:
            self.mech = model(x)

        def compile(self) -> NoRow:
            return NoRow(self.mech.compile())

    monkeypatch.setattr(problem, "model", Drawn)
    assert F._screen(problem, np.concatenate([X, TH]))[:2] == (("branch", "circuit"), 0.0)
