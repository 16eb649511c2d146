"""Static equilibrium, stability and modes (`Model.equilibrium`) against closed forms.

- A bar pinned to the ground, held by a torsion spring under gravity: it rests where
  k (theta - theta0) = -m g l cos(theta) and swings at omega^2 = (k - m g l sin theta) / I_O
  (V = m g l sin theta + k (theta - theta0)^2 / 2, V'' / I_O).
- A four-bar whose rocker tip is held by a linear spring to the ground, under gravity:
  its rest crank angle from virtual work, V'(phi) = 0, with the four-bar's closed-form
  position, velocity and acceleration (written here), and its frequency from the one
  degree of freedom's reduced energy: omega^2 = V''(phi) / m*(phi), m* the generalized
  mass of the kinetic energy.
Roots by brentq at xtol 1e-15; agreement to 1e-10.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from linkwork import Constant, EquilibriumError, Linear, MasslessError, Mechanism

G = 9.81


def pendulum(k: float | None, theta0: float = 0.0, gravity: float = G, torque: float | None = None):
    """A bar of mass m, centre of mass a distance arm from its pin, frame origin at the centre of mass."""
    m, arm, jc = 1.3, 0.45, 0.02
    mech = Mechanism("pendulum")
    mech.gravity = (0.0, -gravity)
    bar = mech.body("bar", origin=(arm, 0.0), mass=m, inertia=jc)
    mech.revolute(mech.ground, bar, at=(0.0, 0.0), name="O")
    if k is not None:
        mech.torsion_spring(mech.ground, bar, stiffness=k, free_angle=theta0)
    if torque is not None:
        mech.torque(bar, Constant(torque))
    return mech.compile(free=True), (m, arm, jc)


def test_spring_pendulum_rest_angle_and_frequency_match_the_closed_form():
    k, theta0 = 20.0, 0.7
    model, (m, arm, jc) = pendulum(k, theta0)
    assert k > m * G * arm  # the balance is monotone: one rest angle

    theta = brentq(lambda th: k * (th - theta0) + m * G * arm * math.cos(th), -4.0, 4.0, xtol=1e-15)
    eq = model.equilibrium()
    assert eq.body("bar").theta == pytest.approx(theta, abs=1e-10)
    assert eq.residual < 1e-10 and eq.phi < 1e-12
    assert eq.stable and eq.unstable == [] and eq.neutral == []
    i_o = jc + m * arm * arm
    omega2 = (k - m * G * arm * math.sin(theta)) / i_o
    (mode,) = eq.modes()
    assert mode.omega2 == pytest.approx(omega2, rel=1e-10)
    assert mode.frequency == pytest.approx(math.sqrt(omega2) / (2 * math.pi), rel=1e-10)
    # a turn about the pin, mass-normalised: theta' = 1 / sqrt(I_O)
    assert mode.shape[2] == pytest.approx(1.0 / math.sqrt(i_o), rel=1e-10)
    # the pin carries the weight; the spring's torque balances gravity's moment
    assert eq.reaction("O").force[1] == pytest.approx(m * G, rel=1e-10)


def test_upright_pendulum_is_unstable_and_says_which_coordinate():
    model, (m, arm, jc) = pendulum(None)
    th = 1.35
    eq = model.equilibrium(q_guess=[arm * math.cos(th), arm * math.sin(th), th])
    assert eq.body("bar").theta == pytest.approx(math.pi / 2, abs=1e-12)
    assert not eq.stable and len(eq.unstable) == 1 and eq.unstable[0][1].startswith("bar.")
    assert eq.omega2[0] == pytest.approx(-m * G * arm / (jc + m * arm * arm), rel=1e-10)
    assert eq.frequencies[0] == 0.0


def test_constant_torque_on_a_free_crank_has_no_rest():
    model, _ = pendulum(None, gravity=0.0, torque=2.0)
    with pytest.raises(EquilibriumError, match="no equilibrium found") as info:
        model.equilibrium()
    assert info.value.q.shape == (3,) and np.all(np.isfinite(info.value.q))
    assert info.value.force > 1.0 and info.value.iterations >= 1


# --- the spring-loaded four-bar ----------------------------------------------------------

A, B, C, D = 0.4, 1.0, 0.8, 1.0  # crank, coupler, rocker, ground
MA, MB, MC = 0.5, 1.2, 0.9  # uniform bars
P, K, S0 = np.array([1.6, 1.2]), 60.0, 0.3  # the spring: ground point, stiffness, free length
O4 = np.array([D, 0.0])


def cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def four_bar(phi: float):
    """Closed form: A, B and their first and second derivatives in phi (open branch)."""
    pa = A * np.array([math.cos(phi), math.sin(phi)])
    pa1 = A * np.array([-math.sin(phi), math.cos(phi)])
    pa2 = -pa
    e = O4 - pa
    dist = np.linalg.norm(e)
    e /= dist
    h0 = (B * B - C * C + dist * dist) / (2 * dist)
    pb = pa + h0 * e + math.sqrt(B * B - h0 * h0) * np.array([-e[1], e[0]])
    # |B - A| = b, |B - O4| = c differentiated once and twice
    mat = np.array([pb - pa, pb - O4])
    pb1 = np.linalg.solve(mat, [(pb - pa) @ pa1, 0.0])
    pb2 = np.linalg.solve(mat, [(pb - pa) @ pa2 - (pb1 - pa1) @ (pb1 - pa1), -pb1 @ pb1])
    return pa, pa1, pa2, pb, pb1, pb2


def potential_derivatives(phi: float):
    """V'(phi), V''(phi): gravity on the three centres of mass and the spring at B."""
    pa, pa1, pa2, pb, pb1, pb2 = four_bar(phi)
    y1 = MA * pa1[1] / 2 + MB * (pa1[1] + pb1[1]) / 2 + MC * pb1[1] / 2
    y2 = MA * pa2[1] / 2 + MB * (pa2[1] + pb2[1]) / 2 + MC * pb2[1] / 2
    r = pb - P
    ell = np.linalg.norm(r)
    l1 = r @ pb1 / ell
    l2 = (pb1 @ pb1 + r @ pb2) / ell - (r @ pb1) ** 2 / ell**3
    return G * y1 + K * (ell - S0) * l1, G * y2 + K * (l1 * l1 + (ell - S0) * l2)


def generalized_mass(phi: float) -> float:
    """m*(phi): T = m* phid^2 / 2, from each bar's centre of mass and rotation rates."""
    pa, pa1, _, pb, pb1, _ = four_bar(phi)
    wb = cross(pb - pa, pb1 - pa1) / B**2
    wc = cross(pb - O4, pb1) / C**2
    t = MA * (pa1 @ pa1) / 4 + MA * A * A / 12
    t += MB * ((pa1 + pb1) @ (pa1 + pb1)) / 4 + MB * B * B / 12 * wb * wb
    t += MC * (pb1 @ pb1) / 4 + MC * C * C / 12 * wc * wc
    return t


def spring_four_bar(phi0: float):
    pa, _, _, pb, _, _ = four_bar(phi0)
    mech = Mechanism("spring four-bar")
    mech.gravity = (0.0, -G)
    tb = math.atan2(*(pb - pa)[::-1])
    tc = math.atan2(*(pb - O4)[::-1])
    crank = mech.body("crank", origin=(0.0, 0.0), angle=phi0, mass=MA, inertia=MA * A * A / 12, com=pa / 2)
    coupler = mech.body("coupler", origin=pa, angle=tb, mass=MB, inertia=MB * B * B / 12, com=(pa + pb) / 2)
    rocker = mech.body("rocker", origin=O4, angle=tc, mass=MC, inertia=MC * C * C / 12, com=(O4 + pb) / 2)
    mech.revolute(mech.ground, crank, at=(0.0, 0.0), name="O2")
    mech.revolute(crank, coupler, at=pa, name="A")
    mech.revolute(coupler, rocker, at=pb, name="B")
    mech.revolute(mech.ground, rocker, at=O4, name="O4")
    mech.spring(mech.ground, P, rocker, pb, stiffness=K, free_length=S0)
    return mech.compile(free=True)


def test_spring_loaded_four_bar_matches_virtual_work_and_the_reduced_energy():
    model = spring_four_bar(1.0)
    eq = model.equilibrium()
    phi_e = eq.body("crank").theta
    # the virtual-work root next to the engine's (brentq in a bracket around it)
    phi = brentq(lambda f: potential_derivatives(f)[0], phi_e - 0.05, phi_e + 0.05, xtol=1e-15)
    assert phi_e == pytest.approx(phi, abs=1e-10)
    # the rest of the configuration is the closed form's at that angle
    _, _, _, pb, _, _ = four_bar(phi)
    assert eq.body("rocker").theta == pytest.approx(math.atan2(pb[1] - O4[1], pb[0] - O4[0]), abs=1e-10)
    v2 = potential_derivatives(phi)[1]
    assert eq.stable == (v2 > 0) and len(eq.eigenvalues) == 1
    omega2 = v2 / generalized_mass(phi)
    assert eq.omega2[0] == pytest.approx(omega2, rel=1e-10)
    # the mode moves the crank by 1 / sqrt(m*) (mass-normalised)
    (mode,) = eq.modes()
    assert abs(mode.shape[2]) == pytest.approx(1.0 / math.sqrt(generalized_mass(phi)), rel=1e-10)


def test_modes_of_a_massless_free_motion_are_refused_by_name():
    """A massless flap on a spring at the bar's tip: at rest and stable (the spring holds
    it), but its motion carries no mass, so there is no frequency to give."""
    mech = Mechanism("flap")
    mech.gravity = (0.0, -G)
    bar = mech.body("bar", origin=(0.3, 0.0), mass=1.0, inertia=0.01)
    flap = mech.body("flap", origin=(0.6, 0.0))
    mech.revolute(mech.ground, bar, at=(0.0, 0.0))
    mech.revolute(bar, flap, at=(0.6, 0.0))
    mech.torsion_spring(mech.ground, bar, stiffness=30.0, free_angle=0.5)
    mech.torsion_spring(bar, flap, stiffness=2.0, free_angle=0.3)
    eq = mech.compile(free=True).equilibrium()
    assert eq.stable and len(eq.eigenvalues) == 2
    # the flap rests at its spring's free angle to the bar
    assert eq.body("flap").theta - eq.body("bar").theta == pytest.approx(0.3, abs=1e-12)
    assert eq.omega2 is None
    with pytest.raises(MasslessError, match="flap"):
        eq.modes()


def test_a_driver_holds_its_coordinate_at_the_time_asked():
    """A driven arm (angle 0.2 + 0.5 t) carrying a free pendulum: at t = 1 the arm is at
    0.7 rad, the pendulum hangs straight down from its tip and swings as a compound
    pendulum about it; the driver supplies the torque of both weights about the ground pin."""
    m1, m2, arm, reach, jc = 0.8, 1.1, 0.25, 0.5, 0.015
    mech = Mechanism("driven arm")
    mech.gravity = (0.0, -G)
    upper = mech.body("upper", origin=(0.0, 0.0), mass=m1, inertia=0.02, com=(arm, 0.0))
    lower = mech.body("lower", origin=(reach + 0.3, 0.0), mass=m2, inertia=jc)
    mech.revolute(mech.ground, upper, at=(0.0, 0.0))
    mech.revolute(upper, lower, at=(reach, 0.0))
    mech.drive_angle(upper, Linear(0.2, 0.5), name="hold")
    eq = mech.compile(free=True).equilibrium(t=1.0)
    assert eq.body("upper").theta == pytest.approx(0.7, abs=1e-14)
    assert eq.body("lower").theta == pytest.approx(-math.pi / 2, abs=1e-10)
    assert eq.stable and len(eq.eigenvalues) == 1
    assert eq.omega2[0] == pytest.approx(m2 * G * 0.3 / (jc + m2 * 0.3**2), rel=1e-10)
    torque = (m1 * arm + m2 * reach) * G * math.cos(0.7)
    assert eq.effort("hold") == pytest.approx(torque, rel=1e-10)


def test_a_motion_without_stiffness_is_neutral_not_unstable():
    """A wheel pinned at its centre of mass beside the spring pendulum: gravity does no
    work on its turning, so its eigenvalue is zero (within the tolerance the pendulum's
    stiffness sets): listed neutral, never unstable; the pendulum's stays stable. With no
    load at all (a bare free crank, tolerance zero) the zero eigenvalue is neutral too."""
    mech = Mechanism("pendulum and wheel")
    mech.gravity = (0.0, -G)
    bar = mech.body("bar", origin=(0.45, 0.0), mass=1.3, inertia=0.02)
    mech.revolute(mech.ground, bar, at=(0.0, 0.0))
    mech.torsion_spring(mech.ground, bar, stiffness=20.0, free_angle=0.7)
    wheel = mech.body("wheel", origin=(2.0, 0.0), mass=0.5, inertia=0.03)
    mech.revolute(mech.ground, wheel, at=(2.0, 0.0))
    eq = mech.compile(free=True).equilibrium()
    assert eq.tol > 0.0 and len(eq.eigenvalues) == 2
    assert eq.unstable == [] and [c for _, c in eq.neutral] == ["wheel.theta"]
    assert not eq.stable and "neutral" in repr(eq)

    bare, _ = pendulum(None, gravity=0.0)
    eq = bare.equilibrium()
    assert eq.tol == 0.0 and eq.eigenvalues[0] == 0.0
    assert eq.unstable == [] and len(eq.neutral) == 1 and not eq.stable


def test_the_coordinate_a_mode_moves_most_does_not_depend_on_the_length_unit():
    """The spring pendulum built in metres and in millimetres (lengths x1000, inertia
    x1e6, stiffness and gravity scaled to keep the same rest angle and frequency): the
    mode's dominant coordinate is the same, lengths being compared in the model's length
    scale (in raw numbers the millimetre model's translations would win)."""

    def scaled(s: float) -> str:
        m, arm = 1.3, 0.45 * s
        mech = Mechanism("pendulum")
        mech.gravity = (0.0, -G * s)
        bar = mech.body("bar", origin=(arm, 0.0), mass=m, inertia=0.02 * s * s)
        mech.revolute(mech.ground, bar, at=(0.0, 0.0))
        mech.torsion_spring(mech.ground, bar, stiffness=20.0 * s * s, free_angle=0.7)
        (mode,) = mech.compile(free=True).equilibrium().modes()
        return mode.coordinate

    assert scaled(1.0) == scaled(1000.0) == scaled(0.001) == "bar.theta"
