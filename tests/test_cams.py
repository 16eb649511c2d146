"""Pins in curved slots and cam followers: the reference's rows against finite
differences, closed forms (a pin in a circular slot is a four-bar; an eccentric circular
cam moves its followers by formulas), the engine against the reference over whole
revolutions, model files, and every refusal naming its joint.

Tolerances: 1e-10 relative, as for the other mechanisms (Newton stops at 1e-12 scaled;
the Jacobians are well conditioned away from dead points).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from helpers import eccentric_follower, rel_err, translating_cam, wrap
from linkwork import closed_form
from linkwork.reference import ReferenceModel
from linkwork.reference import curves as ref_curves
from linkwork.reference.formulation import Own, Pose, build_constraints

TOL = 1e-10
TAU = 2.0 * math.pi


# --- mechanisms ----------------------------------------------------------------------------


def profile(phi: float) -> float:
    """A cam profile r(phi) (m): a rise of 12 mm and a ripple, convex all round."""
    return 0.05 + 0.006 * (1.0 - math.cos(phi)) + 0.002 * math.sin(2.0 * phi)


def eccentric_cam(kind: str, e: float = 0.02, R: float = 0.05, rho: float = 0.015) -> lw.Mechanism:
    """A circular cam (radius R, centre e from its pivot at the origin, along +x at the
    start) turning at 10 rad/s from 0.3 rad, and a follower translating along the y axis,
    drawn a little off the profile."""
    return translating_cam(kind, lw.curves.circle((e, 0.0), R), lw.Linear(0.3, 10.0), e, R, rho)


def oscillating_roller(n_rows: int = 36) -> lw.Mechanism:
    """A polar-spline cam (``profile`` tabulated every 360/n_rows degrees) turning once a
    second, and an arm pivoted at O4 whose roller (radius 10 mm, 70 mm from O4) rolls on it."""
    m = lw.Mechanism("polar cam, oscillating roller")
    cam = m.body("cam", angle=0.2)
    phi0, rho, arm_length = math.radians(40.0), 0.010, 0.070
    b = (profile(phi0) + rho) * np.array([math.cos(phi0), math.sin(phi0)])
    # the arm across the radius through the roller: the cam's push turns it
    o4 = b + arm_length * np.array([-math.sin(phi0), math.cos(phi0)])
    arm = m.link("arm", o4, b)
    m.revolute(m.ground, cam, at=(0, 0), name="O")
    m.revolute(m.ground, arm, at=o4, name="O4")
    m.cam_follower(
        cam, arm, b, lw.curves.polar_function((0, 0), profile, n_rows), "roller", radius=rho, name="F"
    )
    m.drive_angle(cam, lw.Linear(0.2, TAU), name="turn")
    return m


def translating_flat() -> lw.Mechanism:
    """The same polar cam under a flat-faced follower translating along a line offset
    from the pivot (its face tilted by 0.1 rad on the follower)."""
    m = lw.Mechanism("polar cam, flat follower")
    cam = m.body("cam")
    top = 0.05 + 0.006 + 0.004
    follower = m.body("follower", (0.01, top), angle=0.1)
    m.revolute(m.ground, cam, at=(0, 0), name="O")
    m.prismatic(m.ground, follower, at=(0.01, top), axis=(0, 1), name="slide")
    m.cam_follower(
        cam,
        follower,
        (0.01, top),
        lw.curves.polar_function((0, 0), profile, 24),
        "flat",
        face=(1, 0),
        name="F",
    )
    m.drive_angle(cam, lw.Linear(0.0, TAU), name="turn")
    return m


def spline_slot() -> lw.Mechanism:
    """A crank (50 mm) whose pin runs in a closed spline slot of a plate pivoted 150 mm
    away: the slot, through 12 points of an ellipse (semi-axes 65 and 20 mm) about the
    crank's pivot, reaches from 85 to 215 mm of the plate's pivot, so the pin (100 to
    200 mm from it) always meets it and the plate rocks."""
    m = lw.Mechanism("spline slot")
    pin = 0.05 * np.array([math.cos(0.26), math.sin(0.26)])
    crank = m.link("crank", (0, 0), pin)
    plate = m.body("plate", (0.15, 0.0))
    m.revolute(m.ground, crank, at=(0, 0), name="O")
    m.revolute(m.ground, plate, at=(0.15, 0.0), name="O4")
    angles = np.linspace(0.0, TAU, 12, endpoint=False)
    slot = lw.curves.spline(np.column_stack([0.065 * np.cos(angles), 0.02 * np.sin(angles)]))
    m.pin_in_slot(plate, crank, at=pin, curve=slot, name="S")
    m.drive_angle(crank, lw.Linear(0.26, TAU), name="turn")
    return m


# --- the reference's rows -----------------------------------------------------------------------


def reference_joints() -> list:
    """One reference joint of each kind on each curve type, between bodies a and b."""
    start = {"ground": (0.0, 0.0, 0.0), "a": (0.1, -0.05, 0.4), "b": (0.3, 0.2, -0.7)}
    curves = [
        lw.curves.circle((0.05, 0.1), 0.3),
        lw.curves.spline([(0.5, 0.0), (0.2, 0.4), (-0.4, 0.3), (-0.5, -0.2), (0.1, -0.45)]),
        lw.curves.polar_function((0.1, 0.0), lambda p: 0.4 + 0.05 * math.cos(p) + 0.03 * math.sin(3 * p), 12),
        lw.curves.polar_expression("0.4 + 0.05*cos(phi) + 0.03*sin(3*phi)*exp(0.2*cos(phi))", (0.1, 0.0)),
    ]
    joints = []
    for k, curve in enumerate(curves):
        for j, (kind, extra) in enumerate(
            [("pin_in_slot", {}), ("knife", {}), ("roller", {"radius": 0.05}), ("flat", {"face": [0.3, 1.0]})]
        ):
            base = {
                "name": f"J{k}{j}",
                "body_a": "a",
                "body_b": "b",
                "at": [0.2, 0.3],
                "curve": curve,
                **extra,
            }
            if kind == "pin_in_slot":
                joints.append({"type": kind, **base})
            else:
                joints.append({"type": "cam_follower", "follower": kind, **base})
    return build_constraints({"joints": joints}, start)


def test_reference_rows_match_finite_differences():
    """Jacobian blocks and d/ds by central differences (h = 1e-6: error ~1e-10); gamma by
    the second difference along q + h qd, s + h sd (h = 1e-4: error ~1e-8)."""
    rng = np.random.default_rng(7)

    def rows(c, qa, qb, s, qda=(0, 0, 0), qdb=(0, 0, 0), sd=0.0):
        pa = Pose(np.array(qa[:2]), qa[2], np.array(qda[:2]), qda[2])
        pb = Pose(np.array(qb[:2]), qb[2], np.array(qdb[:2]), qdb[2])
        return c.evaluate_own(pa, pb, Own(s, sd))

    joints = reference_joints()
    assert len(joints) == 16
    for c in joints:
        for _ in range(5):
            qa, qb = rng.uniform(-0.5, 0.5, 3), rng.uniform(-0.5, 0.5, 3)
            qda, qdb = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
            pa0 = Pose(qa[:2], qa[2], np.zeros(2), 0.0)
            pb0 = Pose(qb[:2], qb[2], np.zeros(2), 0.0)
            s, sd = c.own_start(pa0, pb0) + rng.uniform(-0.5, 0.5), rng.uniform(-2, 2)
            _, jac_a, jac_b, jac_s, gamma = rows(c, qa, qb, s, qda, qdb, sd)
            h = 1e-6
            for k in range(3):
                e = np.zeros(3)
                e[k] = h
                fd_a = (rows(c, qa + e, qb, s)[0] - rows(c, qa - e, qb, s)[0]) / (2 * h)
                fd_b = (rows(c, qa, qb + e, s)[0] - rows(c, qa, qb - e, s)[0]) / (2 * h)
                np.testing.assert_allclose(jac_a[:, k], fd_a, atol=1e-8, err_msg=f"{c.name} d/dq_a[{k}]")
                np.testing.assert_allclose(jac_b[:, k], fd_b, atol=1e-8, err_msg=f"{c.name} d/dq_b[{k}]")
            fd_s = (rows(c, qa, qb, s + h)[0] - rows(c, qa, qb, s - h)[0]) / (2 * h)
            np.testing.assert_allclose(jac_s, fd_s, atol=1e-8, err_msg=f"{c.name} d/ds")
            h = 1e-4
            plus = rows(c, qa + h * qda, qb + h * qdb, s + h * sd)[0]
            zero = rows(c, qa, qb, s)[0]
            minus = rows(c, qa - h * qda, qb - h * qdb, s - h * sd)[0]
            fd_gamma = -(plus - 2 * zero + minus) / h**2
            np.testing.assert_allclose(
                gamma, fd_gamma, atol=1e-5 * (1 + np.max(np.abs(gamma))), err_msg=c.name
            )


def test_reference_periodic_spline_matches_scipy():
    """The reference's periodic spline (a dense solve of the cyclic system) against SciPy's
    CubicSpline(bc_type="periodic"): the same interpolant, so to rounding."""
    interpolate = pytest.importorskip("scipy.interpolate")
    knots = np.array([0.3, 0.9, 1.1, 2.5, 4.0, 5.2, 0.3 + TAU])
    values = np.array([1.0, 0.4, -0.2, 0.8, 1.5, -0.6, 1.0])
    ours = ref_curves.PeriodicSpline(knots, values)
    theirs = interpolate.CubicSpline(knots, values, bc_type="periodic")
    for s in np.linspace(0.3, 0.3 + TAU, 97)[:-1] + 1e-3:
        want = [float(theirs(s, nu=k)) for k in range(4)]
        np.testing.assert_allclose(ours(s), want, rtol=1e-12, atol=1e-12)


# --- closed forms -----------------------------------------------------------------------------


@pytest.mark.parametrize("where", ["ground", "rocker"])
def test_pin_in_a_circular_slot_is_a_four_bar(where):
    """A pin in a circular slot of radius r keeps its distance r from the slot's centre: a
    link pinned at both ends. Slot in the ground about O4, radius = rocker: the pin B of
    the coupler moves as the rocker's tip and s is theta4. Slot in the rocker about B,
    radius = coupler: the crank's pin A stays a coupler's length from B."""
    dims = dict(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25)
    th0, omega = 0.3, 5.0
    t = np.linspace(0.0, TAU / omega, 721)
    cf = closed_form.four_bar(**dims, theta2=th0 + omega * t, omega2=omega, alpha2=0.0)
    # drawn at the closed form's configuration of crank angle 0.1, driven from 0.3
    draw = closed_form.four_bar(**dims, theta2=0.1, omega2=0.0)
    th4 = float(draw["theta4"])
    a = 0.20 * np.array([math.cos(0.1), math.sin(0.1)])
    b = np.array([0.35, 0.0]) + 0.25 * np.array([math.cos(th4), math.sin(th4)])

    m = lw.Mechanism("four-bar with a slot")
    crank = m.link("crank", (0, 0), a)
    m.revolute(m.ground, crank, at=(0, 0))
    if where == "ground":
        coupler = m.link("coupler", a, b)
        m.revolute(crank, coupler, at=a)
        m.pin_in_slot(m.ground, coupler, at=b, curve=lw.curves.circle((0.35, 0.0), 0.25), name="S")
    else:
        rocker = m.link("rocker", (0.35, 0.0), b)
        m.revolute(m.ground, rocker, at=(0.35, 0.0))
        m.pin_in_slot(rocker, crank, at=a, curve=lw.curves.circle(b, 0.35), name="S")
    m.drive_angle(crank, lw.Linear(th0, omega))
    r = m.compile().sweep(t)
    assert r.columns[-1] == "S.s" and r.units("S.s") == "rad" and r.units("S.s_dd") == "rad/s^2"
    s = r.q[:, -1], r.qd[:, -1], r.qdd[:, -1]

    if where == "ground":
        coupler_motion = r.body("coupler")
        assert np.max(np.abs(wrap(coupler_motion.theta - cf["theta3"]))) <= TOL
        assert rel_err(coupler_motion.thetad, cf["omega3"]) <= TOL
        assert rel_err(coupler_motion.thetadd, cf["alpha3"]) <= TOL
        # s is the polar angle of B about O4: the rocker's angle
        want = cf["theta4"], cf["omega4"], cf["alpha4"]
    else:
        rocker_motion = r.body("rocker")
        assert np.max(np.abs(wrap(rocker_motion.theta - cf["theta4"]))) <= TOL
        assert rel_err(rocker_motion.thetad, cf["omega4"]) <= TOL
        assert rel_err(rocker_motion.thetadd, cf["alpha4"]) <= TOL
        # s: the direction B -> A (theta3 + pi) in the rocker, from its drawn x axis
        want = (
            cf["theta3"] + math.pi - (cf["theta4"] - th4),
            cf["omega3"] - cf["omega4"],
            cf["alpha3"] - cf["alpha4"],
        )
    assert np.max(np.abs(wrap(s[0] - want[0]))) <= TOL
    assert rel_err(s[1], want[1]) <= TOL
    assert rel_err(s[2], want[2]) <= TOL


@pytest.mark.parametrize("kind", ["knife", "roller", "flat"])
def test_eccentric_cam_moves_its_follower_by_the_closed_form(kind):
    """y = e sin th + sqrt(R'^2 - e^2 cos^2 th) with R' = R (knife) or R + rho (roller), and
    y = e sin th + R (flat face); rates by the chain rule at constant cam speed. The engine
    and the reference both."""
    e, R, rho, omega = 0.02, 0.05, 0.015, 10.0
    t = np.linspace(0.0, TAU / omega, 361)
    th = 0.3 + omega * t
    y, dy, ddy = eccentric_follower(kind, e, R, rho, th)
    mech = eccentric_cam(kind, e, R, rho)
    r = mech.compile().sweep(t)
    f = r.body("follower")
    assert rel_err(f.y, y) <= TOL
    assert rel_err(f.yd, dy * omega) <= TOL
    assert rel_err(f.ydd, ddy * omega**2) <= TOL
    out = ReferenceModel(mech).sweep(t)
    k = r.columns.index("follower.y")
    assert rel_err(out["q"][:, k], y) <= TOL
    assert rel_err(out["qd"][:, k], dy * omega) <= TOL
    assert rel_err(out["qdd"][:, k], ddy * omega**2) <= TOL


# --- engine against the reference ------------------------------------------------------------------


def compare_with_reference(mech: lw.Mechanism, t: np.ndarray) -> None:
    """Every column of q, qd, qdd to 1e-10 relative to its largest value, but never to
    less than a thousandth of the mechanism's own scale for its unit (L, L W, L W^2 for
    lengths and their rates, 1, W, W^2 for angles; L the length scale, W the fastest
    angular rate), so that columns staying at zero (a pivoted body's x) compare their
    rounding to the motion's size; curve parameters modulo 2 pi."""
    r = mech.compile().sweep(t)
    ref = ReferenceModel(mech)
    out = ref.sweep(t)
    assert r.columns == ref.columns
    q = r.q.copy()
    own = [k for k, c in enumerate(r.columns) if c.endswith(".s")]
    q[:, own] = out["q"][:, own] + wrap(q[:, own] - out["q"][:, own])
    angles = [c.endswith((".theta", ".s")) for c in r.columns]
    L, W = ref.length_scale, float(np.max(np.abs(out["qd"][:, angles])))
    for order, (what, got, want) in enumerate(
        (("position", q, out["q"]), ("velocity", r.qd, out["qd"]), ("acceleration", r.qdd, out["qdd"]))
    ):
        for k, column in enumerate(r.columns):
            unit = (1.0 if angles[k] else L) * W**order
            scale = max(float(np.max(np.abs(want[:, k]))), 1e-3 * unit)
            err = float(np.max(np.abs(got[:, k] - want[:, k]))) / scale
            assert err <= TOL, f"{column} {what}: {err:.2e}"


def test_polar_spline_cam_with_oscillating_roller_matches_the_reference():
    mech = oscillating_roller()
    t = np.linspace(0.0, 1.0, 361)
    compare_with_reference(mech, t)
    # the arm oscillates (it is a follower, not a crank) and the contact goes once round
    r = mech.compile().sweep(t)
    arm = r.body("arm").theta
    assert 0.05 < np.ptp(arm) < 0.5
    s = r.q[:, r.columns.index("F.s")]
    assert abs(s[-1] - s[0] + TAU) < 1e-9  # the cam turned once forwards: s runs once backwards


@pytest.mark.parametrize("build", [translating_flat, spline_slot])
def test_flat_follower_and_spline_slot_match_the_reference(build):
    compare_with_reference(build(), np.linspace(0.0, 1.0, 241))


def test_length_scale_sees_the_curves():
    """L is the diagonal of the box round every described point, the curves' extent
    included: the roller follower's cam circle (centre (0.02, 0), R = 0.05) reaches
    x = -0.03 .. 0.07 and y = -0.05; the follower's point is highest."""
    mech = eccentric_cam("roller")
    y0 = math.sqrt(0.065**2 - 0.02**2) + 0.003
    want = math.hypot(0.07 + 0.03, y0 + 0.05)
    assert mech.compile().length_scale == pytest.approx(want, rel=1e-15)
    assert ReferenceModel(mech).length_scale == pytest.approx(want, rel=1e-15)


def test_model_files_keep_curve_joints():
    mech = oscillating_roller(12)
    text = json.dumps(mech.to_dict())
    again = lw.Mechanism.from_dict(json.loads(text))
    t = np.linspace(0.0, 0.5, 11)
    np.testing.assert_array_equal(mech.compile().sweep(t).q, again.compile().sweep(t).q)


def test_inverse_dynamics_with_a_cam_balances_energy():
    """A follower of 0.4 kg held on the cam by gravity: the driver's power feeds the
    kinetic and potential energy exactly (the curve parameter carries no mass)."""
    mech = eccentric_cam("roller")
    mech.set_mass("follower", 0.4, inertia=1e-4)
    mech.set_mass("cam", 1.0, inertia=2e-3, com=(0.01, 0.0))
    mech.set_gravity((0.0, -9.81))
    r = mech.compile().sweep(np.linspace(0.0, TAU / 10.0, 181), forces=True)
    energy = r.energy()
    scale = np.max(np.abs(energy.driver_power))
    assert scale > 0.1
    assert np.max(np.abs(energy.balance)) <= 1e-9 * scale
    # the contact pushes the follower up, along the common normal through the roller centre
    force = r.reaction("F").force
    assert np.all(force[:, 1] > 0.0)


# --- refusals ----------------------------------------------------------------------------------------


def refusal(mutate, match: str) -> None:
    mech = eccentric_cam("roller")
    desc = mech.to_dict()
    joint = next(j for j in desc["joints"] if j["name"] == "F")
    mutate(joint)
    with pytest.raises(lw.ModelError, match=match):
        lw.Model(desc)


@pytest.mark.parametrize(
    ("mutate", "match"),
    [
        (lambda j: j["curve"].update(radius=0.0), r"joint 'F': curve radius 0(\.0)? must be finite and > 0"),
        (lambda j: j["curve"].update(radius=-0.05), r"joint 'F': curve radius -0.05 must be"),
        (lambda j: j.update(radius=0.0), r"joint 'F': roller radius 0(\.0)? must be finite and > 0"),
        (lambda j: j.update(radius=-0.01), r"joint 'F': roller radius -0.01 must be"),
        (
            lambda j: j.update(curve=lw.curves.spline([(0, 0), (1, 0)])),
            r"joint 'F': .*at least 3 points, got 2",
        ),
        (
            lambda j: j.update(curve=lw.curves.polar((0, 0), [0, 1, 2, 3], [0.05] * 4)),
            r"joint 'F': polar table is not periodic",
        ),
        (
            lambda j: j.update(curve=lw.curves.polar((0, 0), [0, 1, 2, TAU], [0.05, 0.06, 0.07, 0.08])),
            r"joint 'F': polar table is not periodic",
        ),
        (
            lambda j: j.update(curve=lw.curves.polar((0, 0), [0, 1, 2, TAU], [0.05, 0.0, 0.07, 0.05])),
            r"joint 'F': polar table radius 0(\.0)? \(row 1\) must be > 0",
        ),
        (
            lambda j: j.update(curve=lw.curves.polar((0, 0), [0, 1, TAU], [0.05] * 3)),
            r"joint 'F': .*at least 4 rows",
        ),
        (lambda j: j.update(body_a="plate"), r"joint 'F': refers to body 'plate', which is not in the model"),
        (
            lambda j: j.update(body_b="pusher"),
            r"joint 'F': refers to body 'pusher', which is not in the model",
        ),
        (lambda j: j.pop("radius"), r"joint 'F': a roller follower needs a radius"),
        (
            lambda j: j.update(follower="knife"),
            r"joint 'F': gives a radius, which only a roller follower has",
        ),
        (lambda j: j.update(follower="flat"), r"joint 'F': gives a radius"),
        (lambda j: (j.pop("radius"), j.update(follower="flat")), r"joint 'F': a flat-faced follower needs"),
        (
            lambda j: (j.pop("radius"), j.update(follower="flat", face=[0.0, 0.0])),
            r"joint 'F': face direction \[0\.0, 0\.0\] must be finite and non-zero",
        ),
        (lambda j: j["curve"].update(radius=math.nan), r"joint 'F': curve\.radius is nan"),
        (
            lambda j: j.update(follower="mushroom"),
            r"joint 'F': follower must be \"knife\", \"roller\" or \"flat\"",
        ),
    ],
)
def test_bad_curve_joints_are_refused_by_name(mutate, match):
    refusal(mutate, match)


def test_a_roller_too_big_for_a_hollow_of_the_profile_is_refused():
    """A profile with a hollow: a dent 4 mm deep near phi = 0 whose radius of curvature
    there is (r^2 - r r'') / r^3 -> 1 / 146 m, about 7 mm. A 5 mm roller fits, a 20 mm
    roller cannot follow it."""

    def dented(phi: float) -> float:
        return 0.05 - 0.004 * math.exp(-((wrap(phi) / 0.15) ** 2))

    curve = lw.curves.polar_function((0, 0), dented, 180)
    for rho, ok in ((0.005, True), (0.02, False)):
        m = lw.Mechanism()
        cam = m.body("cam")
        follower = m.body("follower", (0.0, 0.05 + rho))
        m.revolute(m.ground, cam, at=(0, 0))
        m.prismatic(m.ground, follower, at=(0.0, 0.05 + rho), axis=(0, 1))
        m.cam_follower(cam, follower, (0.0, 0.05 + rho), curve, "roller", radius=rho, name="roll")
        m.drive_angle(cam, lw.Linear(0.0, 1.0))
        if ok:
            m.compile()
        else:
            with pytest.raises(lw.ModelError, match=r"joint 'roll': roller radius 0.02 exceeds .* hollow"):
                m.compile()


def test_a_flat_face_on_a_profile_with_a_hollow_is_refused():
    def dented(phi: float) -> float:
        return 0.05 - 0.004 * math.exp(-((wrap(phi) / 0.15) ** 2))

    desc = translating_flat().to_dict()
    desc["joints"][-1]["curve"] = lw.curves.polar_function((0, 0), dented, 180)
    with pytest.raises(
        lw.ModelError, match=r"joint 'F': the profile is hollow at s = .* needs a convex profile"
    ):
        lw.Model(desc)


def test_pin_in_slot_refusals_name_the_joint():
    m = lw.Mechanism()
    crank = m.link("crank", (0, 0), (0.05, 0))
    m.revolute(m.ground, crank, at=(0, 0))
    m.pin_in_slot("plate", crank, at=(0.05, 0), curve=lw.curves.circle((0, 0), 0.05), name="S")
    m.drive_angle(crank, lw.Linear(0.0, 1.0))
    with pytest.raises(lw.ModelError, match="joint 'S': refers to body 'plate', which is not in the model"):
        m.compile()
    with pytest.raises(ValueError, match="joint 'S' refers to unknown body 'plate'"):
        ReferenceModel(m)
    points = [(0, 0), (0.1, 0), (0.1, 0), (0, 0.1)]
    desc = spline_slot().to_dict()
    desc["joints"][-1]["curve"] = lw.curves.spline(points)
    with pytest.raises(lw.ModelError, match="joint 'S': spline points 1 and 2 coincide"):
        lw.Model(desc)
    desc["joints"][-1]["curve"] = lw.curves.spline([(0, 0), (0.1, 0), (0, 0.1), (0, 0)])
    with pytest.raises(lw.ModelError, match="joint 'S': the spline's last point repeats its first"):
        lw.Model(desc)


def test_builders_refuse_what_is_not_a_curve_or_a_follower():
    m = lw.Mechanism()
    with pytest.raises(lw.InputError, match="a curve is a dict made by linkwork.curves"):
        m.pin_in_slot(m.ground, "b", at=(0, 0), curve=(0.0, 0.1))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="unknown curve type 'ellipse'"):
        m.pin_in_slot(m.ground, "b", at=(0, 0), curve={"type": "ellipse"})
    with pytest.raises(ValueError, match="kind must be 'knife', 'roller' or 'flat', not 'mushroom'"):
        m.cam_follower(m.ground, "b", (0, 0), lw.curves.circle((0, 0), 1.0), kind="mushroom")


def test_screw_analysis_refuses_curve_joints_by_name():
    state = eccentric_cam("knife").compile().solve(0.1)
    with pytest.raises(lw.ScrewError, match="joint 'F': screw analysis covers revolute, prismatic and fixed"):
        lw.screw.kennedy_centres(state)


def test_the_docs_example_runs():
    text = (Path(__file__).resolve().parent.parent / "docs" / "cams.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    scope: dict = {}
    exec(compile(blocks[0], "docs/cams.md", "exec"), scope)
    swing, s = scope["swing"], scope["s"]
    # 10 mm of lift on a 60 mm arm: a swing of about 0.17 rad, back where it started
    assert 0.12 < np.ptp(swing) < 0.22
    assert abs(swing[-1] - swing[0]) < 1e-9
    # one cam turn counter-clockwise: the contact runs once round the profile backwards
    assert abs(s[-1] - s[0] + TAU) < 1e-9
