"""The engine (through the Python API) against closed forms and the NumPy reference.

Tolerance 1e-10 relative: both solvers stop Newton at a scaled residual and step of
1e-12 on well-conditioned Jacobians (pivot ratios > 1e-2 here), so they agree near
machine precision; a wrong term anywhere is off by orders of magnitude more.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from helpers import rel_err, revolution, wrap
from linkwork import closed_form, examples
from linkwork.reference import ReferenceModel

TOL = 1e-10


@pytest.mark.parametrize("linear", ["dense", "sparse"])
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_four_bar_matches_closed_form(branch, linear):
    dims = dict(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25)
    model = examples.four_bar(**dims, omega=5.0, theta0=0.3, branch=branch).compile(linear=linear)
    assert model.linear == linear
    t = revolution()
    r = model.sweep(t)
    th2 = 0.3 + 5.0 * t
    cf = closed_form.four_bar(**dims, theta2=th2, omega2=5.0, alpha2=0.0, branch=branch)
    for body, k in (("coupler", "3"), ("rocker", "4")):
        b = r.body(body)
        assert np.max(np.abs(wrap(b.theta - cf["theta" + k]))) <= TOL
        assert rel_err(b.thetad, cf["omega" + k]) <= TOL
        assert rel_err(b.thetadd, cf["alpha" + k]) <= TOL
    # coupler point P (mid-coupler) through Results.point against the closed-form angles
    a = 0.20 * np.column_stack([np.cos(th2), np.sin(th2)])
    p = a + 0.175 * np.column_stack([np.cos(cf["theta3"]), np.sin(cf["theta3"])])
    assert rel_err(r.point("P").position, p) <= TOL


def test_offset_slider_crank_matches_closed_form():
    model = examples.slider_crank(crank=0.10, rod=0.35, offset=0.02, omega=5.0, theta0=0.0).compile()
    t = revolution()
    r = model.sweep(t)
    cf = closed_form.slider_crank(0.10, 0.35, 0.02, theta2=5.0 * t, omega2=5.0)
    s = r.body("slider")
    assert rel_err(s.x, cf["x"]) <= TOL
    assert rel_err(s.xd, cf["v"]) <= TOL
    assert rel_err(s.xdd, cf["a"]) <= TOL
    rod = r.body("rod")
    assert np.max(np.abs(wrap(rod.theta - cf["theta3"]))) <= TOL
    assert rel_err(rod.thetad, cf["omega3"]) <= TOL
    assert rel_err(rod.thetadd, cf["alpha3"]) <= TOL


def compare_with_reference(mech: lw.Mechanism, times: np.ndarray, **options) -> lw.Results:
    r = mech.compile(**options).sweep(times)
    ref = ReferenceModel(mech).sweep(times)
    assert r.columns == ReferenceModel(mech).columns
    for key in ("q", "qd", "qdd"):
        got, want = getattr(r, key), ref[key]
        # compare column by column, each relative to its own scale (an angle's rate may
        # be O(100) while a fixed pivot's is 0)
        for j, name in enumerate(r.columns):
            scale = max(np.max(np.abs(want[:, j])), np.max(np.abs(want)) * 1e-6)
            err = np.max(np.abs(got[:, j] - want[:, j])) / scale
            assert err <= TOL, f"{key} {name}: {err:.2e}"
    assert np.all(np.isfinite(r.q)) and np.all(np.isfinite(r.qdd))
    return r


@pytest.mark.parametrize("name", sorted(examples.ALL))
@pytest.mark.parametrize("linear", ["dense", "sparse"])
def test_every_example_matches_the_reference(name, linear):
    r = compare_with_reference(examples.ALL[name](), revolution(n=361), linear=linear)
    assert r.iterations[1:].max() <= 3


def test_point_kinematics_match_the_reference():
    mech = examples.four_bar()
    t = revolution(n=181)
    r = mech.compile().sweep(t)
    ref = ReferenceModel(mech)
    out = ref.sweep(t)
    pos, vel, acc = ref.point("P", out["q"], out["qd"], out["qdd"])
    p = r.point("P")
    assert rel_err(p.position, pos) <= TOL
    assert rel_err(p.velocity, vel) <= TOL
    assert rel_err(p.acceleration, acc) <= TOL
    # the same point through body-frame coordinates
    u = r.point_at("coupler", (0.175, 0.0))
    assert rel_err(u.position, pos) <= TOL


def two_link_arm() -> lw.Mechanism:
    """A serial arm: shoulder driven absolutely (polynomial), elbow relative to the upper
    arm (spline through a table)."""
    m = lw.Mechanism("two-link arm")
    upper = m.link("upper", (0, 0), (0.4, 0.1))
    fore = m.link("fore", (0.4, 0.1), (0.6, 0.35))
    m.revolute(m.ground, upper, at=(0, 0))
    m.revolute(upper, fore, at=(0.4, 0.1))
    m.drive_angle(upper, lw.Polynomial([math.atan2(0.1, 0.4), 0.8, -0.3, 0.05]))
    rel0 = math.atan2(0.25, 0.2) - math.atan2(0.1, 0.4)
    m.drive_relative_angle(upper, fore, lw.Spline([0.0, 0.5, 1.0, 1.5, 2.0], [rel0, 1.2, 0.6, 1.5, 1.0]))
    m.point("tip", fore, (0.6, 0.35))
    return m


def luffing_boom() -> lw.Mechanism:
    """A boom pivoted on the ground and raised by a hydraulic cylinder (distance driver)."""
    m = lw.Mechanism("luffing boom")
    boom = m.link("boom", (0, 0), (1.0, 0.2))
    m.revolute(m.ground, boom, at=(0, 0))
    stroke0 = math.hypot(0.5 - 0.3, 0.1 - (-0.3))
    m.drive_distance(
        m.ground, (0.3, -0.3), boom, (0.5, 0.1), lw.Harmonic(stroke0 + 0.05, 0.05, 2.0, -math.pi / 2)
    )
    return m


def scotch_yoke_by_slide() -> lw.Mechanism:
    """A slider-crank driven backwards: the slider's slide is prescribed (translation
    driver), a bracket is welded to the rod (fixed joint)."""
    m = examples.slider_crank(crank=0.1, rod=0.35, offset=0.0, theta0=0.8)
    d = m.to_dict()
    m.remove("crank_angle")
    bx, by = d["joints"][2]["at"]  # the pin B between rod and slider
    bracket = m.body("bracket", (bx - 0.05, by + 0.03), 0.4)
    m.fixed("rod", bracket)
    m.drive_translation("S", lw.Harmonic(0.0, 0.03, 3.0))
    return m


def pendulum_by_x() -> lw.Mechanism:
    """A pendulum whose tip's x is prescribed (coordinate driver)."""
    m = lw.Mechanism("pendulum")
    bob = m.link("bob", (0, 0), (0.0, -0.5))
    m.revolute(m.ground, bob, at=(0, 0))
    m.drive_coordinate(bob, (0.0, -0.5), "x", lw.Harmonic(0.0, 0.2, 4.0))
    return m


@pytest.mark.parametrize("build", [two_link_arm, luffing_boom, scotch_yoke_by_slide, pendulum_by_x])
def test_every_driver_type_matches_the_reference(build):
    t = np.linspace(0.0, 2.0, 401)
    compare_with_reference(build(), t)


def test_the_same_mechanism_in_metres_and_millimetres_gives_the_same_angles():
    t = revolution(n=181)
    r_m = examples.four_bar().compile().sweep(t)
    r_mm = examples.four_bar(ground=350.0, crank=200.0, coupler=350.0, rocker=250.0).compile().sweep(t)
    for body in ("coupler", "rocker"):
        assert np.max(np.abs(r_m.body(body).theta - r_mm.body(body).theta)) <= TOL
        assert rel_err(r_mm.body(body).thetadd, r_m.body(body).thetadd) <= TOL
    # the scaled problem is the same, so are the diagnostics
    assert np.array_equal(r_m.iterations, r_mm.iterations)
    assert np.allclose(r_m.pivot_ratio, r_mm.pivot_ratio, rtol=1e-9)


def test_solve_at_one_instant_agrees_with_the_sweep():
    model = examples.four_bar().compile()
    t = revolution(n=101)
    r = model.sweep(t)
    s = model.solve(t[37], q_guess=r.q[36])
    assert rel_err(s.q, r.q[37]) <= TOL and rel_err(s.qdd, r.qdd[37]) <= TOL
    assert s.pivot_ratio > 0.01 and s.residual <= 1e-12
    assert s.point("P").position.shape == (2,)


def test_results_are_contiguous_float_arrays_with_names():
    model = examples.six_bar_watt().compile()
    r = model.sweep(np.linspace(0, 1, 50))
    assert r.q.shape == r.qd.shape == r.qdd.shape == (50, model.n_coords)
    assert r.q.dtype == np.float64 and r.q.flags.c_contiguous
    assert len(r.columns) == model.n_coords and r.columns[2] == "crank.theta"
    assert r.iterations.shape == r.residual.shape == r.pivot_ratio.shape == (50,)
    assert len(r) == 50 and "crank.theta" in r.summary()


def test_summary_gives_every_rows_unit_and_angles_in_either_unit():
    r = examples.four_bar().compile().sweep(np.linspace(0, 0.5, 26))
    rows = {line.split()[0]: line.split()[1:] for line in r.summary().splitlines()[2:12]}
    assert r.summary().splitlines()[1].split()[-1] == "unit"
    for c in r.columns:
        assert rows[c][-1] == r.units(c)
    assert rows["crank.x"][-1] == "m" and rows["crank.theta"][-1] == "rad"
    assert float(rows["rocker.theta"][1]) == pytest.approx(r.body("rocker").theta.max(), rel=1e-5)
    deg = {line.split()[0]: line.split()[1:] for line in r.summary(angles="deg").splitlines()[2:12]}
    assert deg["rocker.theta"][-1] == "deg" and deg["rocker.x"] == rows["rocker.x"]
    for k in range(4):
        assert float(deg["rocker.theta"][k]) == pytest.approx(
            math.degrees(float(rows["rocker.theta"][k])), rel=1e-5
        )
    with pytest.raises(lw.InputError, match="angles must be one of 'rad', 'deg', not 'grad'"):
        r.summary(angles="grad")


def test_a_linkage_is_described_in_rad_or_deg():
    linkage = examples.four_bar().compile().linkages()[0]
    mu = linkage.transmission_angle
    assert str(linkage) == linkage.describe("rad") and f"transmission angle {mu:.4f} rad" in str(linkage)
    assert f"transmission angle {math.degrees(mu):.2f} deg" in linkage.describe("deg")
    with pytest.raises(lw.InputError):
        linkage.describe("turns")
