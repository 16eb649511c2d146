"""The joints without coordinates of their own (distance, point on line, gear, rack and
pinion, belt, fixed orientation, parallel, linear coupling): the reference's rows against
finite differences, the engine against the reference and against closed forms over whole
revolutions, model files, and every refusal of bad input.

Tolerances: 1e-10 relative between engine, reference and closed forms (both solvers stop
Newton at a scaled 1e-12 on well-conditioned Jacobians, so they agree near machine
precision; a wrong term is off by orders of magnitude more); central differences with
h = 1e-6 carry O(h^2) truncation and O(eps / h) rounding, so they are checked at 1e-8.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from helpers import rel_err, revolution, wrap
from linkwork import closed_form
from linkwork.reference import ReferenceModel

TOL = 1e-10
H = 1e-6


def compare_with_reference(mech: lw.Mechanism, times: np.ndarray) -> lw.Results:
    """Engine and reference over ``times``: every column of q, qd, qdd to TOL relative to
    its own scale (an angle's rate may be O(10) while a slider's is O(0.1)), or to 1e-3 of
    the largest column for columns that are (nearly) zero, a pivot's x or a planetary
    carrier's acceleration, whose round-off (a few 1e-14 of the largest) is measured against
    the mechanism's scale; absolutely if all are zero (gear trains' accelerations)."""
    r = mech.compile().sweep(times)
    ref = ReferenceModel(mech)
    out = ref.sweep(times)
    assert r.columns == ref.columns
    for key in ("q", "qd", "qdd"):
        got, want = getattr(r, key), out[key]
        for j, name in enumerate(r.columns):
            scale = max(np.max(np.abs(want[:, j])), np.max(np.abs(want)) * 1e-3) or 1.0
            err = np.max(np.abs(got[:, j] - want[:, j])) / scale
            assert err <= TOL, f"{key} {name}: {err:.2e}"
    return r


# --- the reference's rows against finite differences -----------------------------------------

BODIES = {"b1": ((0.3, 0.1), 0.4), "b2": ((-0.2, 0.5), 1.1), "b3": ((0.6, -0.3), -0.7)}


def _distance(m):
    m.distance("b1", (0.2, 0.3), "b2", (-0.1, 0.6), length=0.5)


def _distance_ground(m):
    m.distance("ground", (0.5, 0.5), "b3", (0.7, -0.1))


def _slot(m):
    m.point_on_line("b1", "b2", (0.2, 0.4), (1.0, 0.3))


def _slider_block(m):
    m.point_on_line("b3", "ground", (0.5, -0.2), (0.2, 1.0), through=(0.4, 0.1))


def _gear(m):
    m.gear("b1", "b2", radii=(0.05, 0.12))


def _gear_internal_carrier(m):
    m.gear("b1", "b2", radii=(0.2, 0.07), internal=True, carrier="b3", centres=((0.2, 0.2), (0.0, 0.5)))


def _gear_ground_carrier(m):
    m.gear("ground", "b1", ratio=1.5, carrier="b3")


def _rack(m):
    m.rack_pinion("b1", "b2", 0.04, (1.0, -0.4))


def _rack_ground(m):
    m.rack_pinion("b3", "ground", 0.1, (0.3, 1.0), centre=(0.5, -0.2))


def _belt(m):
    m.belt("b2", "b3", ratio=0.4, crossed=True)


def _belt_carrier(m):
    m.belt("b1", "b2", radii=(0.03, 0.09), carrier="b3")


def _orientation(m):
    m.fixed_orientation("b1", "b3", angle=0.2)


def _parallel(m):
    m.parallel("b2", "b3", (1.0, 0.2), (0.9, 0.5))


def _coupling(m):
    m.linear_coupling("b1", "b2", {"x": 0.5, "theta": -0.3}, {"y": 2.0, "theta": 0.1})


def _coupling_angles(m):
    m.linear_coupling("ground", "b3", None, {"theta": 1.0}, value=0.5)


ITEMS = {
    f.__name__.lstrip("_"): f
    for f in (
        _distance,
        _distance_ground,
        _slot,
        _slider_block,
        _gear,
        _gear_internal_carrier,
        _gear_ground_carrier,
        _rack,
        _rack_ground,
        _belt,
        _belt_carrier,
        _orientation,
        _parallel,
        _coupling,
        _coupling_angles,
    )
}


def one_item(key: str) -> lw.Mechanism:
    m = lw.Mechanism(key)
    for name, (origin, angle) in BODIES.items():
        m.body(name, origin, angle)
    ITEMS[key](m)
    return m


def test_every_new_type_is_covered():
    types = {one_item(k).to_dict()["joints"][0]["type"] for k in ITEMS}
    assert types == {
        "distance",
        "point_on_line",
        "gear",
        "rack_pinion",
        "belt",
        "fixed_orientation",
        "parallel",
        "linear_coupling",
    }


def random_state(ref: ReferenceModel, seed: int):
    rng = np.random.default_rng(seed)
    q = ref.q_start() + rng.normal(scale=0.3, size=ref.n_coords)
    qd = rng.normal(scale=1.0, size=ref.n_coords)
    return q, qd


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("key", sorted(ITEMS))
def test_reference_rows_match_finite_differences(key, seed):
    ref = ReferenceModel(one_item(key))
    q, qd = random_state(ref, seed)
    J = ref.phi_q(q, 0.0)
    J_fd = np.zeros_like(J)
    for k in range(ref.n_coords):
        dq = np.zeros(ref.n_coords)
        dq[k] = H
        J_fd[:, k] = (ref.phi(q + dq, 0.0) - ref.phi(q - dq, 0.0)) / (2 * H)
    assert np.max(np.abs(J - J_fd)) <= 1e-8 * max(1.0, np.max(np.abs(J)))
    assert np.max(np.abs(J)) > 0.01  # not trivially zero

    # gamma: along q + s qd (qdd = 0), d/ds (Phi_q qd) = -gamma
    def rate(s: float) -> np.ndarray:
        return ref.phi_q(q + s * qd, 0.0) @ qd

    gamma_fd = -(rate(H) - rate(-H)) / (2 * H)
    gamma = ref.gamma(q, qd, 0.0)
    assert np.max(np.abs(gamma - gamma_fd)) <= 1e-8 * max(1.0, np.max(np.abs(gamma)))


@pytest.mark.parametrize("key", sorted(ITEMS))
def test_reference_rows_vanish_at_the_drawing_unless_told_otherwise(key):
    """Every joint takes its constant (length, offset, angle, phase of a mesh) from the
    drawing unless the description gives it (or, for parallel lines, draws them apart)."""
    ref = ReferenceModel(one_item(key))
    phi0 = np.max(np.abs(ref.phi(ref.q_start(), 0.0)))
    if key in ("distance", "orientation", "coupling_angles", "parallel"):
        assert phi0 > 1e-3
    else:
        assert phi0 <= 1e-15


# --- mechanisms: engine vs reference vs closed forms ---------------------------------------------


def four_bar_with_distance(theta0: float = 0.3, omega: float = 5.0) -> lw.Mechanism:
    """The textbook four-bar (ground 0.35, crank 0.20, coupler 0.35, rocker 0.25) with
    its coupler replaced by a distance joint: two bodies, six coordinates."""
    cf = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, theta0, omega)
    th4 = float(cf["theta4"])
    a = (0.20 * math.cos(theta0), 0.20 * math.sin(theta0))
    b = (0.35 + 0.25 * math.cos(th4), 0.25 * math.sin(th4))
    m = lw.Mechanism("four-bar, distance coupler")
    crank = m.link("crank", (0.0, 0.0), a)
    rocker = m.link("rocker", (0.35, 0.0), b)
    m.revolute(m.ground, crank, (0.0, 0.0))
    m.revolute(m.ground, rocker, (0.35, 0.0))
    m.distance(crank, a, rocker, b)
    m.drive_angle(crank, lw.Linear(theta0, omega))
    return m


def test_four_bar_with_distance_joint_matches_closed_form_and_reference():
    t = revolution()
    r = compare_with_reference(four_bar_with_distance(), t)
    cf = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, theta2=0.3 + 5.0 * t, omega2=5.0)
    rocker = r.body("rocker")
    assert np.max(np.abs(wrap(rocker.theta - cf["theta4"]))) <= TOL
    assert rel_err(rocker.thetad, cf["omega4"]) <= TOL
    assert rel_err(rocker.thetadd, cf["alpha4"]) <= TOL


def scotch_yoke(r: float = 0.12, omega: float = 4.0) -> lw.Mechanism:
    m = lw.Mechanism("Scotch yoke")
    crank = m.link("crank", (0.0, 0.0), (r, 0.0))
    yoke = m.body("yoke", (r, 0.0))
    m.revolute(m.ground, crank, (0.0, 0.0))
    m.prismatic(m.ground, yoke, (r, 0.0), (1.0, 0.0))
    m.point_on_line(crank, yoke, (r, 0.0), (0.0, 1.0), name="slot")
    m.drive_angle(crank, lw.Linear(0.0, omega))
    return m


def test_scotch_yoke_is_exactly_harmonic():
    t = revolution(omega=4.0)
    r = compare_with_reference(scotch_yoke(), t)
    th = 4.0 * t
    yoke = r.body("yoke")
    assert rel_err(yoke.x, 0.12 * np.cos(th)) <= TOL
    assert rel_err(yoke.xd, -0.12 * 4.0 * np.sin(th)) <= TOL
    assert rel_err(yoke.xdd, -0.12 * 16.0 * np.cos(th)) <= TOL


def offset_pin_slider(e: float, r: float = 0.1, d: float = 0.3, omega: float = 5.0) -> lw.Mechanism:
    """Inverted slider-crank whose slider block, pinned to the crank at A, slides along a
    line of the rocker that passes at distance e from the rocker's pivot O4 = (d, 0)."""
    a = np.array([r, 0.0])
    w = a - [d, 0.0]
    phi = math.atan2(w[1], w[0]) - math.asin(e / math.hypot(*w))
    u = (math.cos(phi), math.sin(phi))
    m = lw.Mechanism("offset pin slider")
    crank = m.link("crank", (0.0, 0.0), a)
    rocker = m.body("rocker", (d, 0.0), phi)
    m.revolute(m.ground, crank, (0.0, 0.0))
    m.revolute(m.ground, rocker, (d, 0.0))
    m.point_on_line(crank, rocker, a, u, through=(d, 0.0), name="block")
    m.drive_angle(crank, lw.Linear(0.0, omega))
    return m


@pytest.mark.parametrize("e", [0.0, 0.04, -0.06])
def test_offset_pin_slider_matches_closed_form(e):
    """cross(u, w) = e with u the rocker's direction and w = A - O4: phi = arg(w) -
    asin(e / |w|); differentiating, phid = cross(u, wd) / (u.w) and
    phidd = (cross(u, wdd) - 2 phid u.wd - phid^2 e) / (u.w)."""
    r_, d, om = 0.1, 0.3, 5.0
    t = revolution()
    r = compare_with_reference(offset_pin_slider(e), t)
    th = om * t
    w = np.column_stack([r_ * np.cos(th) - d, r_ * np.sin(th)])
    wd = np.column_stack([-r_ * om * np.sin(th), r_ * om * np.cos(th)])
    wdd = -(om**2) * np.column_stack([r_ * np.cos(th), r_ * np.sin(th)])
    phi = np.arctan2(w[:, 1], w[:, 0]) - np.arcsin(e / np.hypot(w[:, 0], w[:, 1]))
    u = np.column_stack([np.cos(phi), np.sin(phi)])

    def cross(p, q):
        return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]

    uw, uwd = np.sum(u * w, axis=1), np.sum(u * wd, axis=1)
    phid = cross(u, wd) / uw
    phidd = (cross(u, wdd) - 2.0 * phid * uwd - phid**2 * e) / uw
    rocker = r.body("rocker")
    assert np.max(np.abs(wrap(rocker.theta - phi))) <= TOL
    assert rel_err(rocker.thetad, phid) <= TOL
    assert rel_err(rocker.thetadd, phidd) <= TOL


def gear_train(omega: float = 3.0) -> lw.Mechanism:
    """Three gears in a row on fixed pivots, meshes by ratio (0.5 then 1.6, radii from
    the centre distances): the output turns by +0.8 times the input."""
    m = lw.Mechanism("gear train")
    g1, g2, g3 = m.body("g1", (0.0, 0.0), 0.2), m.body("g2", (0.15, 0.0), 0.0), m.body("g3", (0.15, 0.2), 1.0)
    for g, at in ((g1, (0.0, 0.0)), (g2, (0.15, 0.0)), (g3, (0.15, 0.2))):
        m.revolute(m.ground, g, at)
    m.gear(g1, g2, ratio=0.5)
    m.gear(g2, g3, ratio=1.6)
    m.drive_angle(g1, lw.Linear(0.2, omega))
    return m


def test_gear_train_output_is_the_product_of_the_ratios():
    t = revolution(omega=3.0, n=181)
    r = compare_with_reference(gear_train(), t)
    th1 = 3.0 * t
    assert np.max(np.abs(r.body("g2").theta - (-0.5 * th1))) <= 1e-12 * (1.0 + th1.max())
    assert np.max(np.abs(r.body("g3").theta - (1.0 + 0.8 * th1))) <= 1e-12 * (1.0 + th1.max())
    assert np.max(np.abs(r.body("g3").thetad - 0.8 * 3.0)) <= 1e-12 * 3.0
    assert np.max(np.abs(r.body("g3").thetadd)) <= 1e-12


Z_SUN, Z_PLANET = 0.05, 0.03
Z_RING = Z_SUN + 2 * Z_PLANET


def planetary(w_sun: float, w_ring: float | None) -> lw.Mechanism:
    """Sun, carrier arm and ring about the origin; a planet pinned to the arm; meshes
    relative to the arm. ``w_ring`` None holds the ring in the ground."""
    m = lw.Mechanism("planetary train")
    sun = m.body("sun", (0.0, 0.0), 0.1)
    arm = m.body("arm", (0.0, 0.0), 0.0)
    planet = m.body("planet", (Z_SUN + Z_PLANET, 0.0), 0.5)
    m.revolute(m.ground, sun, (0.0, 0.0))
    m.revolute(m.ground, arm, (0.0, 0.0))
    m.revolute(arm, planet, (Z_SUN + Z_PLANET, 0.0))
    ring = m.ground if w_ring is None else m.body("ring", (0.0, 0.0), -0.3)
    if w_ring is not None:
        m.revolute(m.ground, ring, (0.0, 0.0))
        m.drive_angle(ring, lw.Linear(-0.3, w_ring), name="ring_input")
    m.gear(sun, planet, radii=(Z_SUN, Z_PLANET), carrier=arm, name="sun_planet")
    m.gear(ring, planet, radii=(Z_RING, Z_PLANET), internal=True, carrier=arm, name="planet_ring")
    m.drive_angle(sun, lw.Linear(0.1, w_sun), name="sun_input")
    return m


@pytest.mark.parametrize("w_ring", [None, 0.0, -2.0, 3.5])
def test_planetary_train_obeys_willis_and_matches_the_reference(w_ring):
    """Willis: (w_s - w_c) / (w_r - w_c) = -z_r / z_s. The reference writes each mesh from
    the line of centres instead of the carrier's angle: an independent formulation."""
    w_s = 6.0
    t = revolution(omega=w_s, n=361)
    r = compare_with_reference(planetary(w_s, w_ring), t)
    w_r = 0.0 if w_ring is None else w_ring
    w_c = r.body("arm").thetad
    assert np.max(np.abs((w_s - w_c) / (w_r - w_c) + Z_RING / Z_SUN)) <= TOL
    want = (Z_SUN * w_s + Z_RING * w_r) / (Z_SUN + Z_RING)
    assert np.max(np.abs(r.body("arm").theta - want * t)) <= 1e-12 * (1.0 + abs(want) * t.max())
    assert np.max(np.abs(w_c - want)) <= 1e-12 * w_s


def chained_six_bar(ratio: float = 1.0, crossed: bool = False, omega: float = 4.0) -> lw.Mechanism:
    """A geared (chained) five-bar: two cranks on the ground, O1 = (0, 0) and
    O2 = (0.2, 0), joined by two links meeting at P; a chain couples the cranks, so one
    driver moves it all."""
    r1, r2, l3, l4 = 0.1, 0.08, 0.3, 0.28
    th1, th2 = 0.0, 1.0
    a = np.array([r1 * math.cos(th1), r1 * math.sin(th1)])
    b = np.array([0.2 + r2 * math.cos(th2), r2 * math.sin(th2)])
    p = _circles(a, l3, b, l4)
    m = lw.Mechanism("chained six-bar")
    c1, c2 = m.link("crank1", (0.0, 0.0), a), m.link("crank2", (0.2, 0.0), b)
    link3, link4 = m.link("link3", a, p), m.link("link4", b, p)
    m.revolute(m.ground, c1, (0.0, 0.0))
    m.revolute(m.ground, c2, (0.2, 0.0))
    m.revolute(c1, link3, a)
    m.revolute(c2, link4, b)
    m.revolute(link3, link4, p)
    m.belt(c1, c2, ratio=ratio, crossed=crossed, name="chain")
    m.drive_angle(c1, lw.Linear(th1, omega))
    m.point("P", link3, p)
    return m


def _circles(a: np.ndarray, ra: float, b: np.ndarray, rb: float) -> np.ndarray:
    """The intersection of circles (a, ra) and (b, rb) left of a -> b (vectorised over rows)."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    d = b - a
    dist = np.hypot(d[:, 0], d[:, 1])
    along = (ra**2 - rb**2 + dist**2) / (2 * dist)
    across = np.sqrt(ra**2 - along**2)
    e = d / dist[:, None]
    p = a + along[:, None] * e + across[:, None] * np.column_stack([-e[:, 1], e[:, 0]])
    return p[0] if p.shape[0] == 1 else p


@pytest.mark.parametrize("ratio, crossed", [(1.0, False), (0.5, True)])
def test_chained_six_bar_matches_geometry_and_reference(ratio, crossed):
    t = revolution(omega=4.0, n=361)
    r = compare_with_reference(chained_six_bar(ratio, crossed), t)
    th1 = 4.0 * t
    th2 = 1.0 + (-1.0 if crossed else 1.0) * ratio * th1
    assert np.max(np.abs(r.body("crank2").theta - th2)) <= 1e-12 * (1.0 + np.abs(th2).max())
    a = 0.1 * np.column_stack([np.cos(th1), np.sin(th1)])
    b = np.column_stack([0.2 + 0.08 * np.cos(th2), 0.08 * np.sin(th2)])
    assert rel_err(r.point("P").position, _circles(a, 0.3, b, 0.28)) <= TOL


def rack_and_pinion(radius: float = 0.04, omega: float = 2.0) -> lw.Mechanism:
    m = lw.Mechanism("rack and pinion")
    pinion = m.body("pinion", (0.0, 0.0), 0.3)
    rack = m.body("rack", (0.1, -radius))
    m.revolute(m.ground, pinion, (0.0, 0.0))
    m.prismatic(m.ground, rack, (0.1, -radius), (1.0, 0.0))
    m.rack_pinion(pinion, rack, radius, (1.0, 0.0))
    m.drive_angle(pinion, lw.Linear(0.3, omega))
    return m


def test_rack_travel_is_radius_times_turn():
    t = revolution(omega=2.0, n=181)
    r = compare_with_reference(rack_and_pinion(), t)
    rack = r.body("rack")
    assert np.max(np.abs(rack.x - (0.1 + 0.04 * 2.0 * t))) <= 1e-12 * 0.6
    assert np.max(np.abs(rack.xd - 0.08)) <= 1e-12 and np.max(np.abs(rack.xdd)) <= 1e-12


def test_rolling_wheel_traces_a_cycloid():
    """A wheel rolling on the ground (the rack) with its centre on the line y = r: a rim
    point that starts at the contact traces x = x0 - r (th - sin th), y = r (1 - cos th)
    (rolling to the left for a counter-clockwise turn th)."""
    r_, x0, om = 0.05, 0.3, 3.0
    m = lw.Mechanism("rolling wheel")
    wheel = m.body("wheel", (x0, r_))
    m.point_on_line(wheel, m.ground, (x0, r_), (1.0, 0.0))
    m.rack_pinion(wheel, m.ground, r_, (1.0, 0.0))
    m.drive_angle(wheel, lw.Linear(0.0, om))
    m.point("rim", wheel, (x0, 0.0))
    t = revolution(omega=om, n=181)
    r = compare_with_reference(m, t)
    th = om * t
    rim = r.point("rim")
    want = np.column_stack([x0 - r_ * (th - np.sin(th)), r_ * (1.0 - np.cos(th))])
    assert rel_err(rim.position, want) <= TOL
    want_v = r_ * om * np.column_stack([-(1.0 - np.cos(th)), np.sin(th)])
    assert rel_err(rim.velocity, want_v) <= TOL
    want_a = r_ * om**2 * np.column_stack([-np.sin(th), np.cos(th)])
    assert rel_err(rim.acceleration, want_a) <= TOL


@pytest.mark.parametrize("keep", ["fixed_orientation", "parallel"])
def test_translating_plate_keeps_its_angle(keep):
    r_, om, th0, phi = 0.1, 4.0, 0.5, 0.35
    a = (r_ * math.cos(th0), r_ * math.sin(th0))
    m = lw.Mechanism("translating plate")
    crank = m.link("crank", (0.0, 0.0), a)
    plate = m.body("plate", (a[0] + 0.2, a[1]), phi)
    m.revolute(m.ground, crank, (0.0, 0.0))
    m.revolute(crank, plate, a)
    if keep == "parallel":
        m.parallel(m.ground, plate, (math.cos(phi), math.sin(phi)), (math.cos(phi), math.sin(phi)))
    else:
        m.fixed_orientation(m.ground, plate)
    m.drive_angle(crank, lw.Linear(th0, om))
    t = revolution(omega=om, n=181)
    r = compare_with_reference(m, t)
    th = th0 + om * t
    p = r.body("plate")
    assert np.max(np.abs(p.theta - phi)) <= 1e-13
    assert rel_err(p.x, r_ * np.cos(th) + 0.2) <= TOL
    assert rel_err(p.ydd, -r_ * om**2 * np.sin(th)) <= TOL


def test_linear_coupling_of_two_cranks_and_a_slider():
    """theta_b = -2 theta_a + const by a coupling of angles, and a slider's x tied to
    theta_b: x - 0.02 theta_b = const."""
    m = lw.Mechanism("couplings")
    a, b = m.body("a", (0.0, 0.0), 0.1), m.body("b", (0.3, 0.0), 0.4)
    s = m.body("s", (0.0, 0.3))
    m.revolute(m.ground, a, (0.0, 0.0))
    m.revolute(m.ground, b, (0.3, 0.0))
    m.prismatic(m.ground, s, (0.0, 0.3), (1.0, 0.0))
    m.linear_coupling(a, b, {"theta": 2.0}, {"theta": 1.0})
    m.linear_coupling(b, s, {"theta": -0.02}, {"x": 1.0})
    m.drive_angle(a, lw.Linear(0.1, 2.0))
    t = revolution(omega=2.0, n=91)
    r = compare_with_reference(m, t)
    assert np.max(np.abs(r.body("b").theta - (0.4 - 4.0 * t))) <= 1e-12 * 13.0
    assert np.max(np.abs(r.body("s").x - (0.02 * (-4.0 * t)))) <= 1e-13
    assert np.max(np.abs(r.body("s").xd + 0.08)) <= 1e-13


# --- engine details ----------------------------------------------------------------------------


def test_model_files_round_trip(tmp_path):
    mechs = [four_bar_with_distance(), offset_pin_slider(0.04), planetary(6.0, -2.0), chained_six_bar()]
    mechs.append(rack_and_pinion())
    t = np.linspace(0.0, 0.5, 11)
    for m in mechs:
        path = tmp_path / "model.json"
        m.save(str(path))
        again = lw.Mechanism.load(str(path))
        assert again.to_dict() == m.to_dict()
        assert np.array_equal(again.compile().sweep(t).q, m.compile().sweep(t).q)


def test_constraint_types_and_mobility():
    model = planetary(6.0, None).compile()
    types = {name: kind for name, _, kind, _, _ in model.constraints}
    assert types["sun_planet"] == "gear" and types["planet_ring"] == "gear"
    mob = model.mobility()
    assert (mob.dof, mob.gruebler_dof, mob.dof_driven, mob.gruebler_dof_driven) == (1, 1, 0, 0)
    assert mob.redundancies == ()
    assert chained_six_bar().compile().constraints[5][2] == "belt"


def test_gear_pair_torques_balance_power():
    """Massless gears: the driver's torque on the pinion against a load torque T on the
    gear is ratio * T for external gears (the power in equals the power out)."""
    m = lw.Mechanism("gear statics")
    a, b = m.body("a", (0.0, 0.0)), m.body("b", (0.2, 0.0))
    m.revolute(m.ground, a, (0.0, 0.0))
    m.revolute(m.ground, b, (0.2, 0.0))
    m.gear(a, b, ratio=0.6)
    m.drive_angle(a, lw.Linear(0.0, 1.0), name="input")
    m.torque(b, lw.Constant(2.0))
    st = m.compile().statics(0.3)
    # power: tau_a w_a + T w_b = 0 with w_b = -0.6 w_a
    assert st.effort("input") == pytest.approx(2.0 * 0.6, rel=1e-12)


def test_screw_analysis_refuses_library_joints_by_name():
    model = gear_train().compile()
    state = model.solve(0.0)
    with pytest.raises(lw.ScrewError, match="joint 'G1' is a gear joint; screw analysis covers revolute"):
        lw.screw.instant_centres(state)


# --- bad input --------------------------------------------------------------------------------------


def _two_bodies() -> lw.Mechanism:
    m = lw.Mechanism("bad")
    m.body("a", (0.0, 0.0))
    m.body("b", (0.3, 0.0))
    m.body("c", (0.1, 0.1))
    return m


BAD = {
    "distance unknown body": (lambda m: m.distance("a", (0, 0), "nobody", (0.3, 0), name="J"), "nobody"),
    "distance coincident points": (lambda m: m.distance("a", (0.1, 0), "b", (0.1, 0), name="J"), "coincide"),
    "distance zero length": (
        lambda m: m.distance("a", (0, 0), "b", (0.3, 0), length=0.0, name="J"),
        "length 0",
    ),
    "slot zero axis": (lambda m: m.point_on_line("a", "b", (0, 0), (0, 0), name="J"), "axis"),
    "slot infinite offset": (
        lambda m: m.point_on_line("a", "b", (0, 0), (1, 0), offset=math.inf, name="J"),
        "offset is inf",
    ),
    "gear zero radius": (lambda m: m.gear("a", "b", radii=(0.1, 0.0), name="J"), "radius_b 0"),
    "gear negative ratio": (lambda m: m.gear("a", "b", ratio=-1.0, name="J"), "ratio -1"),
    "gear radii and ratio": (lambda m: m.gear("a", "b", radii=(0.1, 0.2), ratio=0.5, name="J"), "not both"),
    "gear nothing": (lambda m: m.gear("a", "b", name="J"), "either radius_a and radius_b, or ratio"),
    "gear carrier is a gear": (lambda m: m.gear("a", "b", ratio=2.0, carrier="a", name="J"), "carrier 'a'"),
    "gear unknown carrier": (lambda m: m.gear("a", "b", ratio=2.0, carrier="arm", name="J"), "'arm'"),
    "gear internal ratio 1": (lambda m: m.gear("a", "b", ratio=1.0, internal=True, name="J"), "ratio 1"),
    "gear coincident centres": (
        lambda m: m.gear("a", "b", ratio=2.0, centres=((0, 0), (0, 0)), name="J"),
        "centres coincide",
    ),
    "rack zero radius": (lambda m: m.rack_pinion("a", "b", 0.0, (1, 0), name="J"), "radius 0"),
    "rack ground pinion": (lambda m: m.rack_pinion("ground", "b", 0.1, (1, 0), name="J"), "ground"),
    "rack zero axis": (lambda m: m.rack_pinion("a", "b", 0.1, (0, 0), name="J"), "axis"),
    "belt negative radius": (lambda m: m.belt("a", "b", radii=(-0.1, 0.1), name="J"), "radius_a -0.1"),
    "belt carrier is a pulley": (lambda m: m.belt("a", "b", ratio=2.0, carrier="b", name="J"), "carrier 'b'"),
    "orientation unknown body": (lambda m: m.fixed_orientation("a", "ghost", name="J"), "ghost"),
    "orientation same body": (lambda m: m.fixed_orientation("a", "a", name="J"), "itself"),
    "parallel perpendicular": (lambda m: m.parallel("a", "b", (1, 0), (0, 1), name="J"), "perpendicular"),
    "parallel zero axis": (lambda m: m.parallel("a", "b", (0, 0), (1, 0), name="J"), "axis_a"),
    "coupling no coefficient": (lambda m: m.linear_coupling("a", "b", name="J"), "no non-zero coefficient"),
    "coupling on the ground": (
        lambda m: m.linear_coupling("a", "ground", {"x": 1.0}, {"theta": 1.0}, name="J"),
        "coefficients_b on the ground",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_joints_are_refused_by_name(case):
    add, fragment = BAD[case]
    m = _two_bodies()
    add(m)
    with pytest.raises(lw.ModelError, match=r"joint 'J'") as err:
        m.compile()
    assert fragment in str(err.value)
    # the reference refuses them too (non-finite numbers are the Python model's check)
    if case != "slot infinite offset":
        with pytest.raises(ValueError, match="'J'"):
            ReferenceModel(m)


def test_unknown_coupling_coordinates_are_refused_by_the_builder():
    with pytest.raises(ValueError, match=r"coefficients_a may name 'x', 'y' and 'theta', not \['phi'\]"):
        _two_bodies().linear_coupling("a", "b", {"phi": 1.0})


def test_docs_example_runs():
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "docs" / "joints.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1
    scope: dict = {}
    exec(compile(blocks[0], "docs/joints.md", "exec"), scope)
    assert scope["res"].q.shape == (101, 9)
