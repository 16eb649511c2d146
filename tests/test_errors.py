"""Every error path: the message names the body, joint, driver or time step at fault;
a failed sweep keeps its good steps; nothing crosses as a panic or comes back as NaN."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import linkwork as lw
from helpers import spins_while
from linkwork import _core, examples


def four_bar_dict() -> dict:
    return examples.four_bar().to_dict()


def compile_dict(d: dict) -> lw.Model:
    return lw.Model(d)


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda d: d["joints"][1].update(body_b="nobody"), r"joint 'A'.*body 'nobody'"),
        (lambda d: d["bodies"].append(dict(d["bodies"][0])), r"duplicate name 'crank'"),
        (lambda d: d["joints"][2].update(name="A"), r"duplicate name 'A'.*joint"),
        (lambda d: d["drivers"][0].update(name="O4"), r"duplicate name 'O4'"),
        (
            lambda d: d["bodies"].append({"name": "ground", "x": 0, "y": 0, "theta": 0}),
            "duplicate name 'ground'",
        ),
        (
            lambda d: d["joints"][1].update(at=[float("nan"), 0.0]),
            r"joint 'A': at\[0\] is nan, not a finite number",
        ),
        (lambda d: d["bodies"][1].update(theta=float("inf")), r"body 'coupler': theta is inf"),
        (lambda d: d["joints"][1].update(body_b="crank"), r"joint 'A'.*itself"),
        (
            lambda d: d["drivers"].clear(),
            r"8 constraint rows for 9 coordinates.*1 degree\(s\) of freedom left",
        ),
        (
            lambda d: d["drivers"].append({**d["drivers"][0], "name": "extra"}),
            r"10 constraint rows for 9 coordinates.*1 degree\(s\) of freedom for 2 driver row",
        ),
        (
            lambda d: d["drivers"][0].update(law={"type": "spline", "times": [0, 1], "values": [0]}),
            r"driver 'crank_angle'.*2 times, 1 values",
        ),
        (
            lambda d: d["drivers"][0]["law"].update(slope=1.0),
            r"line 1, column \d+: drivers\[0\]\.law\.slope: unknown field `slope`",
        ),
        (
            lambda d: d["drivers"][0].update(law={"type": "spline", "times": [0, 2, 1], "values": [0, 1, 2]}),
            r"driver 'crank_angle'.*increase strictly",
        ),
        (lambda d: d["drivers"][0].update(law={"type": "polynomial", "coefficients": []}), "no coefficients"),
        (lambda d: d["drivers"][0].update(body="ground"), r"driver 'crank_angle'.*ground"),
        (lambda d: d["points"].append({"name": "Q", "body": "nobody", "at": [0, 0]}), r"point 'Q'.*nobody"),
        (lambda d: d["joints"][1].update(extra=1), r"unknown field `extra`"),
        (lambda d: d["joints"][1].update(type="teleport"), r"unknown variant `teleport`"),
        (lambda d: d.update(bodies=[], joints=[], drivers=[], points=[]), "no moving body"),
    ],
)
def test_bad_descriptions_are_refused_with_names(edit, match):
    d = four_bar_dict()
    edit(d)
    with pytest.raises(lw.ModelError, match=match):
        compile_dict(d)


def test_zero_length_prismatic_axis_is_refused():
    d = examples.slider_crank().to_dict()
    d["joints"][3]["axis"] = [0.0, 0.0]
    with pytest.raises(lw.ModelError, match=r"joint 'S'.*zero-length axis"):
        compile_dict(d)


def test_translation_driver_needs_a_prismatic_joint():
    d = examples.slider_crank().to_dict()
    d["drivers"][0] = {
        "type": "translation",
        "name": "push",
        "joint": "A",
        "law": {"type": "constant", "value": 0},
    }
    with pytest.raises(lw.ModelError, match=r"driver 'push'.*'A'.*not a prismatic"):
        compile_dict(d)


def test_coordinate_driver_axis_and_distance_driver_points_are_checked():
    m = lw.Mechanism()
    b = m.link("bob", (0, 0), (0, -1))
    m.revolute(m.ground, b, at=(0, 0))
    m.drive_coordinate(b, (0, -1), "z", lw.Constant(0.0), name="dx")
    with pytest.raises(lw.ModelError, match=r"driver 'dx'.*\"x\" or \"y\""):
        m.compile()
    m = lw.Mechanism()
    b = m.link("bob", (0, 0), (0, -1))
    m.revolute(m.ground, b, at=(0, 0))
    m.drive_distance(m.ground, (0, -1), b, (0, -1), lw.Constant(0.5), name="cyl")
    with pytest.raises(lw.ModelError, match=r"driver 'cyl'.*coincide"):
        m.compile()


def test_description_syntax_errors_name_the_line():
    with pytest.raises(lw.ModelError, match="line 1"):
        _core.Model('{"bodies": [}')


def test_solver_options_are_checked():
    # bad options are bad arguments: InputError naming the option, its value, what is allowed
    with pytest.raises(lw.InputError, match=r"tol_residual must be a finite number > 0, not -1.0"):
        examples.four_bar().compile(tol_residual=-1.0)
    with pytest.raises(lw.InputError, match="linear must be one of 'auto'.*not 'cholesky'"):
        examples.four_bar().compile(linear="cholesky")
    with pytest.raises(lw.InputError, match="unknown option 'lienar'"):
        examples.four_bar().compile(lienar="dense")


def test_unreachable_start_is_an_assembly_error():
    # the slider cannot be 1 m from the crank pivot when crank + rod = 0.45 m
    m = examples.slider_crank()
    m.remove("crank_angle")
    m.drive_coordinate("slider", m.to_dict()["joints"][2]["at"], "x", lw.Constant(1.0), name="reach")
    with pytest.raises(lw.AssemblyError, match=r"t = 0.*largest in") as info:
        m.compile().sweep(np.linspace(0, 1, 10))
    assert info.value.step == 0 and info.value.time == 0.0
    assert info.value.partial is not None and len(info.value.partial) == 0


def test_sweep_past_the_reach_fails_at_that_step_and_keeps_the_good_ones():
    # pull the slider out along x at constant speed until crank + rod cannot reach it
    m = examples.slider_crank(crank=0.10, rod=0.35, offset=0.0, theta0=1.0)
    x0 = m.to_dict()["joints"][2]["at"][0]
    m.remove("crank_angle")
    m.drive_coordinate("slider", (x0, 0.0), "x", lw.Linear(x0 - 0.1, 0.1), name="pull")
    times = np.linspace(0.0, 3.0, 301)
    t_reach = (0.45 - (x0 - 0.1)) / 0.1  # crank + rod fully stretched
    k_reach = int(np.searchsorted(times, t_reach))
    with pytest.raises(lw.SolveError) as info:
        m.compile().sweep(times)
    err = info.value
    k = err.step
    # a limit of motion, located between the last good step and the first bad one
    assert isinstance(err, lw.SingularError) and "limit of motion" in str(err)
    assert k == k_reach and f"step {k}" in str(err)
    assert times[k - 1] < err.time <= times[k]
    assert abs(err.time - t_reach) < 1e-9
    good = err.partial
    assert [e.kind for e in good.events] == ["limit"]
    assert len(good) == k and good.q.shape == (k, 9)
    assert np.all(np.isfinite(good.q)) and np.all(np.isfinite(good.qdd))
    assert np.allclose(good.body("slider").x, x0 - 0.1 + 0.1 * times[:k], atol=1e-12)


def test_driving_a_rocker_through_its_limit_reports_a_singular_configuration():
    # the crank-rocker four-bar driven by its rocker: the crank locks where it lines up
    # with the coupler (a dead point of rocker-driven motion)
    m = examples.four_bar()
    m.remove("crank_angle")
    th4 = m.to_dict()["bodies"][2]["theta"]
    m.drive_angle("rocker", lw.Linear(th4, 1.0), name="rocker_angle")
    times = np.linspace(0.0, 3.0, 3001)
    with pytest.raises(lw.SolveError) as info:
        m.compile().sweep(times)
    err = info.value
    assert err.step is not None and err.step > 0 and len(err.partial) == err.step
    assert np.all(np.isfinite(err.partial.qd))
    # the pivot ratio falls towards the dead point
    assert err.partial.pivot_ratio[-1] < err.partial.pivot_ratio[0] / 10
    # located where crank and coupler line up: |O2 B| = crank + coupler (0.55 m)
    (event,) = err.partial.events
    assert event.kind == "limit" and "rocker_angle" in dict(event.constraints)
    crank, coupler = event.q[2], event.q[5]
    # near a fold q moves like sqrt(t* - t): 1e-10 in time is 1e-5 in angle
    assert abs(np.sin(coupler - crank)) < 1e-4


@pytest.mark.parametrize(
    "times, match",
    [
        (np.array([0.0, 0.1, 0.1]), r"step 2.*strictly monotone"),
        (np.array([0.0, 0.2, 0.1]), r"step 2.*strictly monotone"),
        (np.array([0.0, np.nan]), r"step 1.*not finite"),
        # inside every driver's (unbounded) domain, but not a time
        (np.array([0.0, np.inf]), r"step 1.*not finite"),
        (np.array([-np.inf, 0.0]), r"step 0.*not finite"),
        (np.array([]), "no times"),
    ],
)
def test_bad_time_grids_are_input_errors(times, match):
    with pytest.raises(lw.InputError, match=match):
        examples.four_bar().compile().sweep(times)


def test_times_outside_a_spline_table_name_the_driver():
    m = examples.four_bar()
    m.remove("crank_angle")
    m.drive_angle("crank", lw.Spline([0.0, 1.0, 2.0], [0.0, 1.0, 3.0]), name="table")
    with pytest.raises(lw.InputError, match=r"driver 'table': t = 2.25 is outside its spline table \[0, 2\]"):
        m.compile().sweep(np.linspace(0.0, 2.5, 11))


def test_bad_starting_guess_is_an_input_error():
    model = examples.four_bar().compile()
    with pytest.raises(lw.InputError, match="3 entries; the model has 9"):
        model.solve(0.0, q_guess=[0.0, 0.0, 0.0])
    q = model.q_start.copy()
    q[4] = np.nan
    with pytest.raises(lw.InputError, match=r"q_guess\[4\] \(coupler.y\)"):
        model.sweep([0.0, 0.1], q_guess=q)


def test_the_exception_hierarchy_has_one_base():
    for exc in (lw.ModelError, lw.InputError, lw.AssemblyError, lw.ConvergenceError, lw.SingularError,
                lw.NonFiniteError, lw.CancelledError):  # fmt: skip
        assert issubclass(exc, lw.LinkworkError)
    assert issubclass(lw.ModelError, ValueError) and issubclass(lw.SingularError, lw.SolveError)


def test_progress_is_reported_and_can_stop_the_sweep():
    model = examples.four_bar().compile()
    times = np.linspace(0.0, 10.0, 20_000)
    calls: list[tuple[int, int]] = []
    model.sweep(times, progress=lambda done, total: calls.append((done, total)))
    assert calls[-1] == (20_000, 20_000) and len(calls) > 5
    assert all(a <= b for (a, _), (b, _) in zip(calls, calls[1:]))

    def stop(done: int, total: int) -> None:
        if done >= 5_000:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough") as info:
        model.sweep(times, progress=stop)
    assert 5_000 <= len(info.value.partial) < 20_000


def test_the_gil_is_released_during_a_sweep():
    model = examples.four_bar().compile()
    times = np.linspace(0.0, 100.0, 1_000_000)
    ticks, elapsed = spins_while(lambda: model.sweep(times))
    # with the GIL held for the whole sweep this loop could only run at the rare points
    # where the sweep checks for signals; released, it spins freely all along
    assert ticks > 20_000 * elapsed, (ticks, elapsed)


def test_no_nan_comes_back_from_a_good_sweep():
    r = examples.six_bar_stephenson().compile().sweep(np.linspace(0, 2 * math.pi / 5, 2001))
    for a in (r.q, r.qd, r.qdd, r.residual, r.pivot_ratio):
        assert np.all(np.isfinite(a))


def test_description_round_trips_through_json():
    d = examples.six_bar_watt().to_dict()
    assert json.loads(json.dumps(d)) == d
    assert lw.Model(json.loads(json.dumps(d))).n_coords == 15


def test_engine_panic_arrives_as_internal_error() -> None:
    # every engine call from Python runs inside the same guard; a panic there is a bug,
    # and must reach Python as an ordinary linkwork exception naming the operation
    with pytest.raises(lw.InternalError, match=r"while checking the panic guard: deliberate panic.*report"):
        _core._check_panic_guard()
    assert issubclass(lw.InternalError, Exception) and issubclass(lw.InternalError, lw.LinkworkError)


def test_a_sweep_too_large_for_memory_is_refused_before_it_starts():
    # 5,000,000 steps of a 200-loop chain with rates: far more than this machine has.
    # Refused with what it needs and how to ask for less, instead of the allocation
    # failure aborting the interpreter; the same sweep asking for less runs
    import time

    model = lw.examples.chain(200).compile()
    times = np.linspace(0.0, 1.0, 5_000_000)
    start = time.perf_counter()
    with pytest.raises(lw.InputError, match=r"outputs need [0-9.]+ GB .*every=k") as info:
        model.sweep(times)
    assert time.perf_counter() - start < 10.0, "refused before any work"
    assert info.value.step is None
    with pytest.raises(lw.InputError, match="for 3 models"):
        lw.sweep_batch([model] * 3, times)
    few = model.sweep(times[:2001], derivatives=0, every=1000)
    assert few.n_steps == 3
