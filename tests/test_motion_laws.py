"""Expressions, cam laws, sequences, periodic laws and Python laws: the engine against the
independent reference (law by law and on a driven four-bar over a whole crank turn), the
published cam coefficients, and every error path.

Tolerances: the laws themselves are closed forms evaluated two ways in double precision,
so they agree to 1e-12 relative; the sweeps solve to a scaled residual of 1e-12 and are
compared at 1e-10 relative per column, as in test_engine.py.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import linkwork as lw
from helpers import rel_err
from linkwork import _core, examples
from linkwork.reference import ReferenceModel, motion_law
from linkwork.reference.laws import expression as ref_expression

TOL = 1e-10
TURN = 2.0 * math.pi


def driven_four_bar(law: lw.Law) -> lw.Mechanism:
    m = examples.four_bar()
    m.remove("crank_angle")
    m.drive_angle("crank", law, name="crank_angle")
    return m


def compare_with_reference(mech: lw.Mechanism, times: np.ndarray) -> lw.Results:
    r = mech.compile().sweep(times)
    ref = ReferenceModel(mech).sweep(times)
    for key in ("q", "qd", "qdd"):
        got, want = getattr(r, key), ref[key]
        for j, name in enumerate(r.columns):
            scale = max(np.max(np.abs(want[:, j])), np.max(np.abs(want)) * 1e-6)
            err = np.max(np.abs(got[:, j] - want[:, j])) / scale
            assert err <= TOL, f"{key} {name}: {err:.2e}"
    return r


# a quarter turn in 0.4 s, then at rest for 0.6 s: an indexing crank
INDEX = lw.Rise(lift=TURN / 4, duration=0.4, profile="modified_sine")

LAWS = {
    "expression": (lw.Expression("0.3 + 5*t + 0.2*sin(5*t)^2 - 0.1*atan2(t, 1)"), (0.0, 1.4)),
    **{
        f"rise {p}": (lw.Rise(lift=TURN, duration=1.0, t0=0.1, start=0.2, profile=p), (0.0, 1.2))
        for p in lw.PROFILES
    },
    "cam": (
        lw.Cam(
            [
                lw.Cam.rise(0.4, math.pi, "modified_trapezoid"),
                lw.Cam.dwell(0.2),
                lw.Cam.rise(0.3, 1.5 * math.pi, "polynomial_4567"),
                lw.Cam.fall(0.3, math.pi / 2, "cycloidal"),
                lw.Cam.dwell(0.1),
            ],
            start=0.1,
        ),
        (0.0, 1.3),
    ),
    "sequence": (
        # spin up with constant acceleration for 0.5 s, then run at 8 rad/s
        lw.Sequence([0.5], [lw.Polynomial([0.0, 0.0, 8.0]), lw.Linear(-2.0, 8.0)]),
        (0.0, 0.5 + (TURN - 2.0) / 8.0),
    ),
    "periodic": (lw.Periodic(INDEX, period=1.0), (0.0, 4.0)),
}


@pytest.mark.parametrize("name", sorted(LAWS))
def test_engine_laws_match_the_reference(name):
    law, (t0, t1) = LAWS[name]
    times = np.linspace(t0 - 0.5, t1 + 0.5, 2001)
    got = law.evaluate(times)
    want = np.array([motion_law(law.to_dict(), t) for t in times])
    for k in range(3):
        assert rel_err(got[:, k], want[:, k]) <= 1e-12, f"derivative {k}"


@pytest.mark.parametrize("name", sorted(LAWS))
def test_four_bar_driven_by_each_law_matches_the_reference_over_a_turn(name):
    law, (t0, t1) = LAWS[name]
    times = np.linspace(t0, t1, 1201)
    r = compare_with_reference(driven_four_bar(law), times)
    # the crank makes (at least) a whole turn
    crank = r.body("crank").theta
    assert crank.max() - crank.min() >= TURN - 1e-9


@pytest.mark.parametrize(
    "profile, cv, ca",
    [
        ("cycloidal", 2.0, 6.2832),
        ("modified_trapezoid", 2.0, 4.8881),
        ("modified_sine", 1.7596, 5.5280),
        ("polynomial_345", 1.8750, 5.7735),
        ("harmonic", 1.5708, 4.9348),
    ],
)
def test_published_peak_coefficients(profile, cv, ca):
    """Norton, Design of Machinery, tables 8-2 and 8-3 (unit lift over unit time), to the
    digits given, from the engine and from the reference."""
    u = np.linspace(0.0, 1.0, 200_001)
    engine = lw.Rise(lift=1.0, duration=1.0, profile=profile).evaluate(u[:-1])
    reference = np.array(
        [motion_law({"type": "rise", "lift": 1, "duration": 1, "profile": profile}, x) for x in u[::40]]
    )
    for values in (engine, reference):
        assert abs(np.abs(values[:, 1]).max() - cv) <= 0.5e-4
        assert abs(np.abs(values[:, 2]).max() - ca) <= 0.5e-4


def test_the_4567_acceleration_peak_and_the_published_figure():
    """The table's 7.5107 is the largest s'' on u = k / 100; the true peak, at the root
    (5 - sqrt 5) / 10 of s''' = 0, is 7.5132."""
    law = lw.Rise(lift=1.0, duration=1.0, profile="polynomial_4567")
    assert abs(law.evaluate(np.arange(101) / 100)[:, 2].max() - 7.5107) <= 0.5e-4
    u = (5 - math.sqrt(5)) / 10
    peak = law.evaluate(u)[0, 2]
    assert abs(peak - (420 * u**2 - 1680 * u**3 + 2100 * u**4 - 840 * u**5)) <= 1e-12
    assert abs(peak - 7.5132) <= 0.5e-4
    assert abs(np.abs(law.evaluate(np.linspace(0, 1, 20_001))[:, 1]).max() - 2.1875) <= 0.5e-4


def test_a_python_law_gives_the_same_motion_as_its_closed_form():
    times = np.linspace(0.0, TURN / 5, 2001)
    native = driven_four_bar(lw.Harmonic(0.3, 0.2, 5.0, 0.1)).compile().sweep(times)
    calls = []

    def wave(t):
        calls.append(t)
        s, c = math.sin(5 * t + 0.1), math.cos(5 * t + 0.1)
        return 0.3 + 0.2 * s, 1.0 * c, -5.0 * s

    python = driven_four_bar(lw.PythonLaw(wave)).compile().sweep(times)
    for key in ("q", "qd", "qdd"):
        assert np.max(np.abs(getattr(python, key) - getattr(native, key))) <= 1e-13
    # once per time step: Newton, velocity and acceleration reuse the value
    assert len(calls) == len(times)
    # and on worker threads, which take the GIL to call it
    batch = lw.sweep_batch(
        [driven_four_bar(lw.PythonLaw(wave)).compile() for _ in range(3)], times, threads=2
    )
    for r in batch:
        assert np.array_equal(r.qdd, python.qdd)


# --- errors -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, column, message",
    [
        ("0.35 - 0.16*sn(150*t)", 13, "unknown name 'sn' at column 13; did you mean 'sin'?"),
        ("sin(t + 1", 10, "expected ')' (for the '(' at column 4), found the end at column 10"),
        ("t / (1 - 1)", 3, "division by zero at column 3"),
        ("atan2(t)", 1, "atan2 takes 2 arguments, got 1 at column 1"),
        ("2t", 1, "malformed number '2t' at column 1"),
        ("t # 1", 3, "unexpected character '#' at column 3"),
    ],
)
def test_expression_errors_say_what_and_where(text, column, message):
    with pytest.raises(lw.ExpressionError) as info:
        lw.Expression(text)
    assert str(info.value).startswith(message)
    assert info.value.column == column and info.value.text == text
    assert isinstance(info.value, lw.ModelError)


@pytest.mark.parametrize(
    "law, match",
    [
        (
            {
                "type": "sequence",
                "breakpoints": [1.0],
                "laws": [{"type": "constant", "value": 0}, {"type": "constant", "value": 1}],
            },
            r"driver 'crank_angle': sequence breakpoint 0 \(t = 1\): the value jumps from 0 \(law 0\) to 1",
        ),
        ({"type": "rise", "lift": 1, "duration": 1, "profile": "trapezoid"}, "unknown variant `trapezoid`"),
        (
            {"type": "rise", "lift": 1, "duration": 0, "profile": "cycloidal"},
            "rise duration is 0; it must be",
        ),
        ({"type": "cam", "segments": []}, "driver 'crank_angle': cam program has no segments"),
        (
            {"type": "periodic", "period": 1, "law": {"type": "expression", "text": "t +"}},
            r"periodic law: expression 't \+'",
        ),
        ({"type": "python", "name": "f"}, "driver 'crank_angle': python law 'f' has no function"),
    ],
)
def test_bad_laws_are_refused_naming_the_driver(law, match):
    desc = examples.four_bar().to_dict()
    desc["drivers"][0]["law"] = law
    with pytest.raises(lw.ModelError, match=match):
        lw.Model(desc)


@pytest.mark.parametrize(
    "text, step, what",
    [
        ("0.3 + 0.1/(t - 1)", 4, "in the residual of driver 'crank_angle': division by zero at column 10"),
        ("0.3 + sqrt(abs(t - 0.5))", 2, "in nu of driver 'crank_angle': sqrt(0) at column 7"),
        ("0.3 + abs(t - 0.5)^1.5", 2, "in gamma of driver 'crank_angle': the power 0^1.5 at column 19"),
        ("0.3 + ln(1 - t)", 4, "in the residual of driver 'crank_angle': ln(0) at column 7"),
    ],
)
def test_a_law_outside_its_domain_stops_the_sweep_naming_driver_and_step(text, step, what):
    model = driven_four_bar(lw.Expression(text)).compile()
    times = np.linspace(0.0, 2.0, 9)
    with pytest.raises(lw.NonFiniteError) as info:
        model.sweep(times)
    e = info.value
    assert str(e).startswith(f"non-finite value at step {step} (t = {times[step]:g}) {what}"), str(e)
    assert e.step == step and len(e.partial.times) == step
    assert np.all(np.isfinite(e.partial.q)) and np.all(np.isfinite(e.partial.qdd))


def test_a_python_exception_surfaces_with_its_cause_and_the_good_steps():
    def bumpy(t):
        if t > 0.5:
            raise ValueError("no data after 0.5 s")
        return 5 * t, 5.0, 0.0

    model = driven_four_bar(lw.PythonLaw(bumpy)).compile()
    times = np.arange(11) / 10
    with pytest.raises(lw.NonFiniteError) as info:
        model.sweep(times)
    e = info.value
    assert str(e) == (
        "non-finite value at step 6 (t = 0.6) in the residual of driver 'crank_angle': python law 'bumpy' "
        "failed at t = 0.6: ValueError: no data after 0.5 s"
    )
    assert isinstance(e.__cause__, ValueError) and str(e.__cause__) == "no data after 0.5 s"
    assert e.step == 6 and len(e.partial.times) == 6
    # a single solve too
    with pytest.raises(lw.NonFiniteError) as info:
        model.solve(0.9)
    assert isinstance(info.value.__cause__, ValueError)
    # the model is still usable where the function works
    assert model.solve(0.2).q is not None


def test_a_python_law_returning_the_wrong_thing_is_a_type_error_cause():
    model = driven_four_bar(lw.PythonLaw(lambda t: 5 * t, name="flat")).compile()
    with pytest.raises(lw.NonFiniteError, match="python law 'flat' must return 3 numbers") as info:
        model.solve(0.1)
    assert isinstance(info.value.__cause__, TypeError)


def test_an_interrupt_in_a_python_law_is_not_hidden():
    def stop(t):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        driven_four_bar(lw.PythonLaw(stop)).compile().sweep(np.linspace(0.0, 1.0, 5))


def test_a_mechanism_with_a_python_law_cannot_be_saved(tmp_path):
    m = driven_four_bar(lw.Periodic(lw.PythonLaw(lambda t: (t, 1.0, 0.0), name="ramp"), period=1.0))
    with pytest.raises(lw.ModelError, match=r"driver 'crank_angle' follows a Python function.*lw.Expression"):
        m.save(str(tmp_path / "m.json"))
    assert not (tmp_path / "m.json").exists()
    # the same law as an expression saves, loads and runs
    m = driven_four_bar(lw.Periodic(lw.Expression("t"), period=1.0))
    m.save(str(tmp_path / "m.json"))
    r = lw.Mechanism.load(str(tmp_path / "m.json")).compile().sweep(np.linspace(0.0, 2.0, 5))
    assert np.allclose(r.body("crank").theta, np.linspace(0.0, 2.0, 5), rtol=0, atol=1e-12)


def test_two_different_python_laws_need_two_names():
    m = examples.four_bar()
    m.torque("crank", lw.PythonLaw(lambda t: (0.0, 0.0, 0.0), name="f"))
    with pytest.raises(lw.ModelError, match="two different Python laws are named 'f'"):
        m.torque("rocker", lw.PythonLaw(lambda t: (1.0, 0.0, 0.0), name="f"))


def test_laws_serialise_as_plain_data():
    for name, (law, _) in LAWS.items():
        d = law.to_dict()
        assert pickle.loads(pickle.dumps(d)) == d, name
    assert lw.Expression("t^2").to_dict() == {"type": "expression", "text": "t^2"}


# --- the parser against random text ---------------------------------------------------------

ALPHABET = "t0123456789.eE+-*/^(),pi sincoqrtlgxabmhyd_#"


@settings(max_examples=400, deadline=None)
@given(st.text(alphabet=ALPHABET, max_size=60))
def test_random_text_parses_or_fails_with_a_column(text):
    try:
        _core.parse_expression(text, "t")
    except lw.ExpressionError as e:
        assert 1 <= e.column <= len(text) + 1, (text, e.column, str(e))
        assert f"at column {e.column}" in str(e)
        return
    # an accepted text evaluates (finite or not) without raising
    value = lw.Expression(text).evaluate([0.3])
    assert value.shape == (1, 3)


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=200))
def test_any_unicode_text_parses_or_fails_with_a_column(text):
    try:
        _core.parse_expression(text, "t")
    except lw.ExpressionError as e:
        assert 1 <= e.column <= len(text) + 1
        assert e.text == text


def expressions(depth: int = 3) -> st.SearchStrategy[str]:
    """Random well-formed expressions of t that are smooth on t in [0.1, 0.9]."""
    leaves = st.one_of(
        st.just("t"),
        st.floats(0.1, 3.0, allow_nan=False).map(lambda v: f"{v:.3g}"),
        st.sampled_from(["pi", "e"]),
    )

    def grow(inner: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
        return st.one_of(
            st.tuples(inner, st.sampled_from(["+", "-", "*"]), inner).map(
                lambda x: f"({x[0]} {x[1]} {x[2]})"
            ),
            st.tuples(inner, inner).map(lambda x: f"({x[0]}) / (2 + sin({x[1]}))"),
            st.tuples(st.sampled_from(["sin", "cos", "atan", "tanh"]), inner).map(
                lambda x: f"{x[0]}({x[1]} / 10)"
            ),
            inner.map(lambda x: f"exp(sin({x}))"),
            inner.map(lambda x: f"sqrt(1 + ({x})^2)"),
            inner.map(lambda x: f"-{x}"),
            st.tuples(inner, inner).map(lambda x: f"hypot({x[0]}, 1 + ({x[1]})^2)"),
            st.tuples(inner, inner).map(lambda x: f"atan2({x[0]}, 2 + cos({x[1]}))"),
            inner.map(lambda x: f"ln(2 + sin({x}))"),
            inner.map(lambda x: f"(1 + ({x})^2)**0.5"),
        )

    return st.recursive(leaves, grow, max_leaves=2**depth)


@settings(max_examples=150, deadline=None)
@given(expressions())
def test_random_expressions_agree_with_the_reference(text):
    ts = np.linspace(0.1, 0.9, 7)
    got = lw.Expression(text).evaluate(ts)
    want = np.array([ref_expression(text)(t) for t in ts])
    scale = np.maximum(np.abs(want), 1.0)
    assert np.all(np.abs(got - want) <= 1e-11 * scale), (text, got, want)
