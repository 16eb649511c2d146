"""Loads that are functions of a joint's coordinate and rate (force laws, motors, laws of
another joint's: a gas force of the crank angle) and joint friction, in forward
dynamics: closed forms, the NumPy reference, the energy balance, equilibrium, model-file
fields (free, initial rates, the drivers a simulation frees) and the errors naming the
load.

Tolerances (measured in brackets):
- A flywheel under a linear motor curve, J w' = T_s (1 - w / w_nl): w = w_nl (1 -
  exp(-t / tau)), tau = J w_nl / T_s, exact; DOP853 at rtol = atol = 1e-12 to 1e-9
  [6e-12]. Generalized-alpha at rtol 1e-8, an order-2 method: 1e-5 [6e-7].
- A pendulum with viscous friction at its pin, released from theta0 = 1e-3 rad: the
  linear solution exp(-sigma t) (cos w_d t + sigma / w_d sin w_d t), sigma = c / (2 I),
  differs from the pendulum's by O(theta0^2) relative (the sin theta ~ theta error,
  theta0^2 / 6 ~ 2e-7, accumulated as a phase over 3 periods): 1e-5 of theta0 [3e-7].
- Engine against reference over 0.3 s, both DOP853 at 1e-11 on the same equations; the
  piston's Coulomb friction, smoothed over 0.05 m/s, turns over sharply at the dead
  centres, and the clipped starter has kinks, where both integrators' errors grow: q to
  1e-7 [4e-9], rates to 3e-6 [1.1e-7].
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from linkwork.cli import main
from linkwork.errors import InitialConditionError, ModelError

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples"))
import engine_startup  # noqa: E402

J, STALL, NO_LOAD = 0.2, 2.0, 30.0


def flywheel(**rates: float) -> lw.Mechanism:
    m = lw.Mechanism("flywheel")
    w = m.body("wheel", mass=5.0, inertia=J)
    m.revolute(m.ground, w, at=(0.0, 0.0), name="A")
    m.motor("A", stall=STALL, no_load_speed=NO_LOAD, name="starter")
    m.free = True
    m.initial_rates = dict(rates)
    return m


def test_flywheel_spins_up_as_the_motor_curve_says() -> None:
    t = np.linspace(0.0, 2.0, 41)
    sim = flywheel().compile().simulate(t, rtol=1e-12, atol=1e-12)
    tau = J * NO_LOAD / STALL
    assert np.max(np.abs(sim.qd[:, 2] - NO_LOAD * (1.0 - np.exp(-t / tau)))) < 1e-9
    # the motor's work is the kinetic energy gained
    assert np.max(np.abs(sim.energy().balance)) < 1e-9
    assert sim.energy().work[-1] > 10.0


def test_flywheel_from_an_initial_rate_in_the_description() -> None:
    """initial_rates of a joint: w(0) = 5, then w_nl - (w_nl - 5) exp(-t / tau)."""
    t = np.linspace(0.0, 1.0, 21)
    model = flywheel(A=5.0).compile()
    sim = model.simulate(t, rtol=1e-12, atol=1e-12)
    tau = J * NO_LOAD / STALL
    assert np.max(np.abs(sim.qd[:, 2] - (NO_LOAD - (NO_LOAD - 5.0) * np.exp(-t / tau)))) < 1e-9
    # the same by column name, and gen-alpha (order 2) to 1e-5 with the same start
    alpha = model.simulate(t, qd0={"wheel.theta": 5.0}, method="gen-alpha", rtol=1e-8, atol=1e-8)
    assert np.max(np.abs(alpha.qd[:, 2] - sim.qd[:, 2])) < 1e-5


def test_pendulum_with_viscous_pin_friction_decays_at_c_over_2I() -> None:
    mass, length, c, g, theta0 = 1.0, 1.0, 0.3, 9.81, 1e-3
    m = lw.Mechanism("damped pendulum")
    m.set_gravity((0.0, -g))
    # the bar hangs from the pin at the origin, a point mass at its end
    bob = m.body("bob", origin=(0.0, 0.0), angle=-math.pi / 2 + theta0, mass=mass, inertia=0.0,
                 com=(length * math.sin(theta0), -length * math.cos(theta0)))  # fmt: skip
    m.revolute(m.ground, bob, at=(0.0, 0.0), name="pin")
    m.friction("pin", viscous=c)
    m.free = True
    t = np.linspace(0.0, 6.0, 121)
    sim = m.compile().simulate(t, rtol=1e-12, atol=1e-12)
    theta = sim.q[:, 2] + math.pi / 2
    inertia = mass * length**2
    sigma, w0 = c / (2 * inertia), math.sqrt(mass * g * length / inertia)
    wd = math.sqrt(w0**2 - sigma**2)
    linear = theta0 * np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    assert np.max(np.abs(theta - linear)) < 1e-5 * theta0
    # friction's work is what the pendulum lost: negative, the balance closed
    energy = sim.energy()
    # (after 6 s exp(-2 sigma t) = 0.17 of the energy is left)
    assert energy.work[-1] < -0.8 * 0.5 * mass * g * length * theta0**2
    # round-off of the potential, ~10 J, against a friction work of 4e-6 J
    assert np.max(np.abs(energy.balance)) < 1e-13


def engine_model() -> lw.Model:
    return engine_startup.engine().compile()


def test_engine_against_the_reference() -> None:
    """The engine's motion (a gas force on the piston of the crank angle, a clipped motor,
    Coulomb and viscous friction at a revolute and a prismatic) against the NumPy
    reference's, from rest over 0.3 s."""
    pytest.importorskip("scipy")
    from linkwork.reference import simulate

    mech = engine_startup.engine()
    model = mech.compile()
    t = np.linspace(0.0, 0.3, 31)
    sim = model.simulate(t, rtol=1e-11, atol=1e-11)
    ref = simulate(mech, t, rtol=1e-11, atol=1e-11)
    order = [list(ref["columns"]).index(c) for c in model.columns]
    assert np.max(np.abs(sim.q - ref["q"][:, order])) < 1e-7
    assert np.max(np.abs(sim.qd - ref["qd"][:, order])) < 1e-7 * NO_LOAD
    assert sim.qd[-1, model.columns.index("crank.theta")] > 10.0  # it did spin up


def test_engine_energy_balance_counts_the_starter_and_friction() -> None:
    t = np.linspace(0.0, 1.0, 101)
    sim = engine_model().simulate(t, rtol=1e-10, atol=1e-10)
    energy = sim.energy()
    assert np.max(np.abs(energy.balance)) < 1e-7 * np.max(energy.kinetic)
    # without the joint loads' power the balance would miss the whole kinetic energy
    assert energy.work[-1] > 0.9 * energy.kinetic[-1]


def test_engine_cli_from_the_model_file(tmp_path, capsys) -> None:
    path = ROOT / "examples" / "dynamics" / "engine_startup.toml"
    assert lw.Mechanism.load(path).to_dict() == engine_startup.engine().to_dict()
    assert main(["simulate", str(path), "--t1", "0.5", "--steps", "51", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "energy balance within" in out
    assert (tmp_path / "engine_startup.csv").stat().st_size > 0


def test_cli_takes_initial_rates_from_the_file(tmp_path) -> None:
    path = tmp_path / "flywheel.toml"
    flywheel(A=5.0).save(path)
    assert main(["simulate", str(path), "--t1", "0.5", "--steps", "11", "--out", str(tmp_path)]) == 0
    import csv

    with open(tmp_path / "flywheel.csv") as f:
        rows = list(csv.DictReader(row for row in f if not row.startswith("#")))
    tau = J * NO_LOAD / STALL
    for row in rows:
        t = float(row["t [s]"])
        assert (
            abs(float(row["wheel.theta_d [rad/s]"]) - (NO_LOAD - (NO_LOAD - 5.0) * math.exp(-t / tau))) < 1e-6
        )


def test_file_round_trip_of_the_new_fields(tmp_path) -> None:
    m = engine_startup.engine()
    m.initial_rates = {"main": 3.0}
    path = tmp_path / "engine.json"
    m.save(path)
    back = lw.Mechanism.load(path)
    assert back.free and back.initial_rates == {"main": 3.0}
    assert back.to_dict() == m.to_dict()
    sim = back.compile().simulate([0.0, 0.01])
    assert abs(sim.qd[0, back.compile().columns.index("crank.theta")] - 3.0) < 1e-12


def test_degrees_convert_a_revolute_joint_load() -> None:
    """Friction and a motor at a revolute of a model in degrees: per deg/s; the same
    motion as the model in radians."""
    k = math.pi / 180.0
    rad = flywheel()
    rad.friction("A", viscous=0.01, coulomb=0.05, smoothing=0.2)
    deg = lw.Mechanism.from_dict(rad.to_dict())
    deg.units = {"length": "m", "angle": "deg"}
    deg._loads = [dict(ld) for ld in deg._loads]
    deg._loads[0]["no_load_speed"] = NO_LOAD / k
    deg._loads[1].update(viscous=0.01 * k, smoothing=0.2 / k)
    t = np.linspace(0.0, 1.0, 11)
    a = rad.compile().simulate(t, rtol=1e-12, atol=1e-12)
    b = deg.compile().simulate(t, rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(a.qd - b.qd)) < 1e-9
    assert a.qd[-1, 2] < NO_LOAD * (1 - math.exp(-1.0 / (J * NO_LOAD / STALL))) - 0.1  # friction acted


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (lambda m: m.friction("A", viscous=-1.0, name="bad"), ["bad", "viscous", "-1"]),
        (lambda m: m.friction("A", coulomb=1.0, name="bad"), ["bad", "smoothing"]),
        (lambda m: m.friction("A", coulomb=1.0, smoothing=0.0, name="bad"), ["bad", "smoothing"]),
        (lambda m: m.friction("nowhere", viscous=1.0, name="bad"), ["bad", "nowhere", "not a joint"]),
        (lambda m: m.motor("A", stall=1.0, no_load_speed=0.0, name="bad"), ["bad", "no-load speed"]),
        (
            lambda m: m.joint_force("A", lw.Spline([0.0, 1.0, 0.5], [0.0, 1.0, 2.0]), name="bad"),
            ["bad", "must increase strictly"],
        ),
    ],
)
def test_bad_joint_loads_are_named(change, words) -> None:
    m = flywheel()
    try:
        change(m)
    except lw.errors.InputError as e:  # refused by the builder already
        message = str(e)
    else:
        with pytest.raises(ModelError) as err:
            m.compile()
        message = str(err.value)
    for w in words:
        assert w in message, message


def test_joint_load_at_a_weld_is_refused() -> None:
    m = flywheel()
    other = m.body("other", mass=1.0, inertia=0.1)
    m.fixed("wheel", other, name="weld")
    m.friction("weld", viscous=1.0, name="bad")
    with pytest.raises(ModelError, match="bad.*fixed.*revolute or prismatic"):
        m.compile()


def test_initial_rates_that_cannot_be_used_are_named() -> None:
    model = flywheel().compile()
    with pytest.raises(InitialConditionError, match="nothing"):
        model.simulate([0.0, 0.1], qd0={"nothing": 1.0})
    with pytest.raises(InitialConditionError, match="degree"):
        model.simulate([0.0, 0.1], qd0={"A": 1.0, "wheel.theta": 2.0})


def test_equilibrium_under_a_tabulated_joint_torque() -> None:
    """A lid held by a torque table of its hinge angle (a spline through
    f(x) = -5 (x - 1.2) + 0.3 (x - 1.2)^3 every 0.05 rad: the spline's own curve), at rest
    where it balances gravity, f(theta) - m g r cos(theta) = 0 (to 1e-10 N m of the
    spline itself); its stiffness there, -f'(theta) - m g r sin(theta), in the mode's
    frequency, from the exact tangent, to 1e-8 relative."""
    CubicSpline = pytest.importorskip("scipy.interpolate").CubicSpline

    xs = np.arange(0.0, 2.0 + 1e-9, 0.05)
    fs = -5.0 * (xs - 1.2) + 0.3 * (xs - 1.2) ** 3
    m = lw.Mechanism("lid")
    m.set_gravity((0.0, -9.81))
    lid = m.body("lid", origin=(0.2, 0.0), mass=1.0, inertia=0.01)
    m.revolute(m.ground, lid, at=(0.0, 0.0), name="hinge")
    m.joint_force("hinge", lw.Spline(list(xs), list(fs)))
    eq = m.compile(free=True).equilibrium()
    theta = eq.body("lid").theta
    spline = CubicSpline(xs, fs, bc_type="natural")
    assert abs(spline(theta) - 9.81 * 0.2 * math.cos(theta)) < 1e-10
    stiffness = -spline(theta, 1) - 9.81 * 0.2 * math.sin(theta)
    inertia = 0.01 + 1.0 * 0.2**2
    assert eq.stable
    omega = math.sqrt(stiffness / inertia)
    assert eq.omega is not None and abs(eq.omega[0] - omega) < 1e-8 * omega


def test_joint_load_numbers_are_not_design_parameters() -> None:
    from test_dynamics import engine_driven

    model = lw.Model(engine_driven())
    with pytest.raises(lw.ParameterError, match="'bearing' acts at a joint"):
        model.sensitivities(np.linspace(0.0, 0.1, 3), ["loads.bearing.viscous"])


def two_wheels(law: lw.Law, of: str = "coordinate", w0: float = 3.0) -> lw.Mechanism:
    """Two flywheels on their own pins; the first spins freely at w0, the second carries
    a torque of the first one's angle (or rate)."""
    m = lw.Mechanism("two wheels")
    first = m.body("first", origin=(0.0, 0.0), mass=1.0, inertia=0.5)
    second = m.body("second", origin=(1.0, 0.0), mass=1.0, inertia=J)
    m.revolute(m.ground, first, at=(0.0, 0.0), name="A")
    m.revolute(m.ground, second, at=(1.0, 0.0), name="B")
    m.joint_force("B", law, of=of, of_joint="A", name="driven")
    m.free = True
    m.initial_rates = {"A": w0, "B": 0.0}
    return m


def test_torque_of_another_joints_angle_follows_the_closed_form() -> None:
    """tau_B = a sin(theta_A), theta_A = w0 t: J w_B' = a sin(w0 t), so
    w_B = a (1 - cos(w0 t)) / (J w0), theta_B = a (t - sin(w0 t) / w0) / (J w0); the
    first wheel feels nothing (the joint read carries no force). Exact; DOP853 at 1e-12:
    rates to 1e-10 [2e-12], angles to 1e-10 [2e-11]. Its work is W_nc, the second
    wheel's kinetic energy: the balance closes."""
    a, w0 = 4.0, 3.0
    t = np.linspace(0.0, 1.0, 21)
    model = two_wheels(lw.Harmonic(mean=0.0, amplitude=a, omega=1.0), w0=w0).compile()
    sim = model.simulate(t, rtol=1e-12, atol=1e-12)
    col = model.columns.index
    assert np.max(np.abs(sim.qd[:, col("first.theta")] - w0)) < 1e-12
    assert np.max(np.abs(sim.qd[:, col("second.theta")] - a * (1 - np.cos(w0 * t)) / (J * w0))) < 1e-10
    theta = a * (t - np.sin(w0 * t) / w0) / (J * w0)
    assert np.max(np.abs(sim.q[:, col("second.theta")] - theta)) < 1e-10
    energy = sim.energy()
    assert np.max(np.abs(energy.balance)) < 1e-10 * np.max(energy.kinetic)
    gained = 0.5 * J * (a * (1 - np.cos(w0 * t[-1])) / (J * w0)) ** 2
    assert abs(energy.work[-1] - gained) < 1e-10 * gained and gained > 10.0
    # gen-alpha (its tangent couples B's row to A's angle), order 2: to 1e-5
    alpha = model.simulate(t, method="gen-alpha", rtol=1e-9, atol=1e-9)
    assert np.max(np.abs(alpha.q - sim.q)) < 1e-5


def test_torque_of_another_joints_rate_and_its_unit_in_degrees() -> None:
    """tau_B = c0 + c1 w_A (w_A = w0, constant): w_B = (c0 + c1 w0) t / J; in a model in
    degrees the law reads w_A in deg/s."""
    c0, c1, w0 = 0.5, 0.2, 3.0
    t = np.linspace(0.0, 1.0, 11)
    rad = two_wheels(lw.Polynomial([c0, c1]), of="rate", w0=w0)
    sim = rad.compile().simulate(t, rtol=1e-12, atol=1e-12)
    col = rad.compile().columns.index("second.theta")
    assert np.max(np.abs(sim.qd[:, col] - (c0 + c1 * w0) * t / J)) < 1e-12
    deg = lw.Mechanism.from_dict(rad.to_dict())
    deg.units = {"length": "m", "angle": "deg"}
    deg._loads = [dict(deg._loads[0], law=lw.Polynomial([c0, c1 * math.pi / 180.0]).to_dict())]
    deg.initial_rates = {"A": math.degrees(w0), "B": 0.0}
    again = deg.compile().simulate(t, rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(again.qd - sim.qd)) < 1e-11


def test_equilibrium_with_a_torque_of_another_joints_angle() -> None:
    """Two wheels on torsion springs k1, k2 (free at their drawn angles 0); a constant
    torque T on the first, and on the second c theta_1: at rest theta_1 = T / k1,
    theta_2 = c theta_1 / k2 (to 1e-12). The stiffness is not symmetric (the second's
    torque moves with the first's angle, not the other way): `asymmetry` says so."""
    k1, k2, torque, c = 4.0, 2.5, 0.8, 1.5
    m = two_wheels(lw.Linear(value=0.0, rate=c))
    m.initial_rates = {}
    m.torsion_spring(m.ground, "first", stiffness=k1, free_angle=0.0)
    m.torsion_spring(m.ground, "second", stiffness=k2, free_angle=0.0)
    m.torque("first", lw.Constant(torque))
    eq = m.compile().equilibrium()
    assert abs(eq.body("first").theta - torque / k1) < 1e-12
    assert abs(eq.body("second").theta - c * torque / (k1 * k2)) < 1e-12
    assert eq.stable and eq.asymmetry > 0.1


def test_a_joint_force_of_an_unknown_or_welded_joint_is_named() -> None:
    m = two_wheels(lw.Constant(1.0))
    m._loads[0]["of_joint"] = "nowhere"
    with pytest.raises(ModelError, match="driven.*reads the coordinate of 'nowhere'.*not a joint"):
        m.compile()
    m = two_wheels(lw.Constant(1.0))
    m.fixed("first", m.body("third", mass=1.0, inertia=0.1), name="weld")
    m._loads[0]["of_joint"] = "weld"
    with pytest.raises(ModelError, match="driven.*reads the coordinate of 'weld', a fixed joint"):
        m.compile()


def test_the_joint_read_travels_through_model_files(tmp_path) -> None:
    m = engine_startup.engine()
    for name in ("engine.toml", "engine.json"):
        m.save(tmp_path / name)
        back = lw.Mechanism.load(tmp_path / name)
        gas = next(ld for ld in back.to_dict()["loads"] if ld["name"] == "gas")
        starter = next(ld for ld in back.to_dict()["loads"] if ld["name"] == "starter")
        assert gas["of_joint"] == "main" and starter["clip"] is True
        assert back.to_dict() == lw.Mechanism.from_dict(m.to_dict()).to_dict()


def test_engine_gen_alpha_agrees_with_rk8() -> None:
    """The engine's gas force of the crank angle in the implicit integrator's tangent:
    gen-alpha (order 2, rtol 1e-8) against DOP853 (1e-10) over 0.5 s, to 1e-4 rad
    [5e-6] in the crank angle."""
    t = np.linspace(0.0, 0.5, 11)
    model = engine_model()
    rk = model.simulate(t, rtol=1e-10, atol=1e-10)
    alpha = model.simulate(t, method="gen-alpha", rtol=1e-8, atol=1e-8)
    col = model.columns.index("crank.theta")
    assert np.max(np.abs(alpha.q[:, col] - rk.q[:, col])) < 1e-4


@pytest.mark.parametrize("w0", [55.0, -5.0])
def test_a_clipped_motor_holds_between_zero_and_stall(w0: float) -> None:
    """Clipped, the starter gives nothing beyond its no-load speed (a flywheel at 55 rad/s
    keeps it; unclipped it brakes towards 30) and stall torque against it (from -5 rad/s:
    w = -5 + T_s t / J until w = 0, then w_nl (1 - exp(-(t - t0) / tau))), to 1e-8 past
    the kinks [7e-12]. The NumPy reference clips the same way."""
    pytest.importorskip("scipy")
    from linkwork.reference import simulate

    m = flywheel(A=w0)
    m._loads[0]["clip"] = True
    t = np.linspace(0.0, 1.0, 21)
    sim = m.compile().simulate(t, rtol=1e-12, atol=1e-12)
    tau = J * NO_LOAD / STALL
    if w0 > NO_LOAD:
        want = np.full_like(t, w0)
        free = flywheel(A=w0).compile().simulate(t, rtol=1e-12, atol=1e-12)
        assert free.qd[-1, 2] < w0 - 5.0  # the line brakes
    else:
        t0 = -w0 * J / STALL
        want = np.where(t < t0, w0 + STALL * t / J, NO_LOAD * (1 - np.exp(-(t - t0) / tau)))
    assert np.max(np.abs(sim.qd[:, 2] - want)) < 1e-8
    ref = simulate(m, t, qd0=sim.qd[0], rtol=1e-11, atol=1e-11)  # one body: the same columns
    assert np.max(np.abs(ref["qd"][:, 2] - want)) < 1e-7


def driven_wheel() -> lw.Mechanism:
    """A flywheel driven at 2 rad/s, a motor at its pin, in a file that says free."""
    m = flywheel()
    m.drive_angle("wheel", lw.Linear(value=0.0, rate=2.0), name="drive")
    return m


def test_simulate_chooses_the_drivers_it_frees() -> None:
    model = driven_wheel().compile()
    t = np.linspace(0.0, 1.0, 11)
    kept = model.simulate(t)
    assert np.max(np.abs(kept.qd[:, 2] - 2.0)) < 1e-9  # the driver holds the rate
    freed = model.simulate(t, rtol=1e-12, atol=1e-12, free_drivers=["drive"])
    tau = J * NO_LOAD / STALL
    assert np.max(np.abs(freed.qd[:, 2] - NO_LOAD * (1 - np.exp(-t / tau)))) < 1e-9
    assert freed.model.dof == 1 and model.dof == 0
    every = model.simulate(t, rtol=1e-12, atol=1e-12, free_drivers=True)
    assert np.max(np.abs(every.qd - freed.qd)) < 1e-12
    with pytest.raises(lw.errors.InputError, match="'nothing' is not a driver.*'drive'"):
        model.simulate(t, free_drivers=["nothing"])
    with pytest.raises(lw.errors.InputError, match="free_drivers must be"):
        model.simulate(t, free_drivers="drive")


def test_cli_frees_drivers(tmp_path, capsys) -> None:
    path = tmp_path / "wheel.toml"
    driven_wheel().save(path)
    args = ["simulate", str(path), "--t1", "0.5", "--steps", "6", "--out", str(tmp_path)]
    assert main(args) == 1  # every coordinate is driven
    assert "every coordinate is driven" in capsys.readouterr().err
    assert main([*args, "--free-drivers", "drive"]) == 0
    assert main([*args, "--free-drivers", "all"]) == 0
    assert main([*args, "--free-drivers", "nothing"]) != 0
    assert "'nothing' is not a driver" in capsys.readouterr().err
