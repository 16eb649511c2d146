"""Exact sensitivities (`Model.sensitivities`) of the four-bar against differences of
whole sweeps, the parameters named as a study names them (description paths and the
friendly names, the redrawn link lengths among them); the driver efforts' (``efforts=True``)
with masses, gravity and loads; gear trains' ratios and radii; the linear tolerance
analysis from them against Monte Carlo; and the parameters the engine does not
differentiate, refused by name (a study then falls back to labelled central differences).

The differences are fourth-order central ones, (f(-2h) - 8 f(-h) + 8 f(h) - f(2h)) / 12h,
with h = 1e-4: truncation ~h^4 |f^(5)| / 30 ~ 1e-14 and round-off ~eps |q| / h ~ 1e-12 on
this mechanism (lengths ~0.3, sweeps converged to ~1e-15), so 1e-8 relative to each
array's largest entry leaves a wide margin while a wrong term would be off by far more.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from linkwork.study import apply
from linkwork.study import tolerance as T

TURN = 2 * np.pi / 5.0
PARAMS = [
    "joints.B.at.0",
    "joints.O4.at.1",
    "drivers.crank_angle.law.rate",
    "drivers.crank_angle.law.value",
    "pin A@crank.y",
    "pin B@rocker.x",
    "length coupler",
    "length rocker",
    "pivot O2.x",
    "point P.x",
]


def four_bar() -> dict:
    return lw.examples.four_bar().to_dict()


def differences(desc: dict, name: str, nominal: float, times: np.ndarray, h: float = 1e-4):
    runs = [lw.Model(apply(desc, {name: nominal + k * h})).sweep(times) for k in (-2, -1, 1, 2)]

    def d(get):
        f = [get(r) for r in runs]
        return (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / (12 * h)

    return {
        "dq": d(lambda r: r.q),
        "dqd": d(lambda r: r.qd),
        "dqdd": d(lambda r: r.qdd),
        "P": d(lambda r: r.point("P").position),
        "P_d": d(lambda r: r.point("P").velocity),
        "P_dd": d(lambda r: r.point("P").acceleration),
    }


def test_four_bar_sensitivities_match_differences_of_whole_sweeps():
    desc = four_bar()
    times = np.linspace(0.0, TURN, 61)
    s = lw.Model(desc).sensitivities(times, PARAMS)
    assert s.dq.shape == (61, 9, len(PARAMS)) and list(s.points) == ["P"]
    assert s.names == PARAMS
    for j, name in enumerate(PARAMS):
        fd = differences(desc, name, s.nominal[j], times)
        got = {
            "dq": s.dq[:, :, j],
            "dqd": s.dqd[:, :, j],
            "dqdd": s.dqdd[:, :, j],
            "P": s.points["P"][:, :, j],
            "P_d": s.points_d["P"][:, :, j],
            "P_dd": s.points_dd["P"][:, :, j],
        }
        for key, want in fd.items():
            scale = np.abs(want).max()
            err = np.abs(got[key] - want).max()
            assert err <= 1e-8 * scale + 1e-10, f"{name} {key}: error {err:.3g} of {scale:.3g}"


def test_the_sweep_comes_with_them_and_a_column_reads_one_coordinate():
    times = np.linspace(0.0, TURN, 21)
    m = lw.Model(four_bar())
    s = m.sensitivities(times, ["length crank", "mass coupler"])
    plain = m.sweep(times)
    assert np.array_equal(s.results.q, plain.q)
    assert s.column("rocker.theta").shape == (21, 2)
    # the kinematics does not depend on a mass: exactly zero
    assert np.all(s.dq[:, :, 1] == 0.0)
    with pytest.raises(lw.ParameterError, match="no coordinate 'rocker.phi'"):
        s.column("rocker.phi")


def test_positions_alone_take_the_structured_path_and_agree():
    # dq/dp alone of a crank and a dyad: each group's closed form differentiated, against
    # the general path (every derivative, checked against differences above) at the same
    # steps; both solve the same equations, so they agree to round-off (1e-12 of each
    # parameter's largest entry)
    times = np.linspace(0.0, TURN, 41)
    m = lw.Model(four_bar())
    s0 = m.sensitivities(times, PARAMS, derivatives=0)
    s2 = m.sensitivities(times, PARAMS)
    assert (s0.path, s0.general_steps, s0.derivatives) == ("structured", 0, 0), s0.path_reason
    assert (s2.path, s2.derivatives) == ("general", 2) and "dqd/dp" in s2.path_reason
    assert s0.dqd is None and s0.dqdd is None and s0.points_d == {} and s0.results.qd is None
    assert np.array_equal(s0.results.q, s2.results.q)
    for got, want in [(s0.dq, s2.dq), (s0.points["P"], s2.points["P"])]:
        scale = np.maximum(np.abs(want).max(axis=(0, 1)), 1e-3 * np.abs(want).max())
        assert np.all(np.abs(got - want).max(axis=(0, 1)) <= 1e-12 * scale)
    with pytest.raises(lw.ParameterError, match="derivatives=0"):
        s0.column("rocker.theta", derivative=1)
    with pytest.raises(lw.InputError, match="derivatives"):
        m.sensitivities(times, PARAMS, derivatives=3)


@pytest.mark.parametrize(
    "name, says",
    [
        ("bodies.crank.x", "'x' of a body is not an engine parameter"),
        ("joints.Z.at.0", "no joint 'Z'"),
        ("drivers.crank_angle.law.omega", "no field 'omega'"),
    ],
)
def test_parameters_the_engine_does_not_differentiate_are_refused_by_name(name, says):
    with pytest.raises(lw.ParameterError, match=says) as e:
        lw.Model(four_bar()).sensitivities(np.linspace(0.0, 0.1, 3), [name])
    assert name in str(e.value)


def test_linear_tolerance_from_exact_sensitivities_agrees_with_monte_carlo():
    times = np.linspace(0.0, TURN, 100)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "angle rocker"])
    tolerances = {
        "length crank": lw.study.Normal(2e-5),
        "pin B@coupler.y": lw.study.Normal(2e-5),
        "pivot O4.x": lw.study.Normal(3e-5),
        "drivers.crank_angle.law.value": lw.study.Normal(1e-4),
    }
    tol = study.tolerance(tolerances, n=1000, seed=4)
    assert tol.linear.method == "exact (engine)" and tol.n_failed == 0
    # the exact S against the labelled central differences of the fallback
    names = list(tolerances)
    exact = T.exact_sensitivities(study, names)
    nominal = study.nominal(names)
    fd = T.central_differences(study, nominal, {k: 1e-6 for k in names})
    assert np.abs(exact - fd).max() <= 1e-6 * np.abs(fd).max()
    # small normal tolerances: the Monte Carlo standard deviation is the first-order RSS
    # to within the sampling error (1000 samples: ~2.2 % standard error on a std)
    ratio = tol.monte_carlo_stats()["std"] / tol.linear.rss
    assert np.all(np.abs(ratio - 1.0) < 0.1)
    assert abs(np.median(ratio) - 1.0) < 0.05


def test_tolerance_falls_back_to_labelled_differences():
    times = np.linspace(0.0, TURN, 30)
    study = lw.Study(lw.examples.four_bar(), times, ["angle rocker"])
    tol = study.tolerance({"bodies.coupler.theta": lw.study.Normal(1e-3)}, n=10, seed=0)
    assert tol.linear.method.startswith("central differences (parameter 'bodies.coupler.theta'")
    assert "central differences" in tol.summary()


# --- the driver efforts' sensitivities (inverse dynamics) ---------------------------------
#
# Against the same fourth-order differences of whole sweeps, now with forces; h scaled to
# each number (1e-4 of it, or of 0.1 for a zero): truncation ~h^4 |f^(5)| / 30 and
# round-off ~|effort| eps / h. Measured agreement on these mechanisms (lengths ~0.3 m,
# efforts ~1-100 N m), the gear trains' kinematics included: 9e-11 relative at worst, so
# 1e-8 leaves a margin of 100 while a missing term (a velocity term, the (dPhi_q/dp)^T
# lambda part, a unit factor) is off by 1e-3 or more.

HERE = Path(__file__).resolve().parent.parent


def effort_differences(desc: dict, name: str, nominal: float, times: np.ndarray, driver: str) -> np.ndarray:
    h = 1e-4 * max(abs(nominal), 0.1)
    runs = [lw.Model(apply(desc, {name: nominal + k * h})).sweep(times, forces=True) for k in (-2, -1, 1, 2)]
    f = [r.effort(driver) for r in runs]
    return (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / (12 * h)


def check_efforts(desc: dict, names: list[str], times: np.ndarray, driver: str, kinematic_zero: set[str]):
    s = lw.Model(desc).sensitivities(times, names, efforts=True)
    n_rows = len(s.results.multipliers[0])
    assert s.dlambda is not None and s.dlambda.shape == (len(times), n_rows, len(names))
    # the sweep with forces comes with them: the efforts they differentiate
    assert np.array_equal(s.results.effort(driver), lw.Model(desc).sweep(times, forces=True).effort(driver))
    for j, name in enumerate(names):
        want = effort_differences(desc, name, s.nominal[j], times, driver)
        got = s.effort(driver)[:, j]
        scale = np.abs(want).max()
        err = np.abs(got - want).max()
        assert err <= 1e-8 * scale + 1e-9, f"{name}: error {err:.3g} of {scale:.3g}"
        if name in kinematic_zero:
            assert np.all(s.dq[:, :, j] == 0.0) and np.all(s.dqdd[:, :, j] == 0.0), name


def test_effort_sensitivities_of_a_four_bar_with_masses_and_gravity_match_differences():
    m = lw.examples.four_bar()
    m.set_mass("crank", 0.8, 0.003, (0.1, 0.01))
    m.set_mass("coupler", 2.0, 0.02, (0.3, 0.15))
    m.set_mass("rocker", 1.4, 0.008, (0.4, 0.1))
    m.set_gravity((0.0, -9.81))
    desc = m.to_dict()
    dynamic = ["mass coupler", "inertia rocker", "bodies.coupler.com.0", "bodies.rocker.com.1", "gravity.1"]
    kinematic = ["length crank", "pin B@rocker.x", "pivot O4.y", "drivers.crank_angle.law.rate"]
    check_efforts(desc, dynamic + kinematic, np.linspace(0.0, TURN, 31), "crank_angle", set(dynamic))


def test_effort_sensitivities_of_a_slider_crank_match_differences():
    m = lw.examples.slider_crank()
    m.set_mass("crank", 0.5, 0.001, (0.04, 0.01))
    m.set_mass("rod", 1.1, 0.011, (0.2, 0.03))
    m.set_mass("slider", 2.5, 0.002)
    m.set_gravity((0.0, -9.81))
    desc = m.to_dict()
    dynamic = ["mass slider", "inertia rod", "bodies.rod.com.1", "gravity.1"]
    kinematic = ["length crank", "length rod", "joints.S.at.1", "drivers.crank_angle.law.value"]
    check_efforts(desc, dynamic + kinematic, np.linspace(0.0, TURN, 31), "crank_angle", set(dynamic))


def test_loads_with_any_law_are_differentiated_and_their_law_numbers_refused_by_name():
    # an expression-law force and a spring: their generalized forces move with the motion
    m = lw.examples.four_bar()
    m.set_mass("coupler", 2.0, 0.02, (0.3, 0.15))
    desc = m.to_dict()
    desc["loads"] = [
        {
            "type": "force",
            "name": "push",
            "body": "coupler",
            "at": [0.35, 0.12],
            "direction": [0.0, -1.0],
            "law": {"type": "expression", "text": "20 + 5*sin(3*t)"},
        },
        {
            "type": "spring",
            "name": "S",
            "body_a": "ground",
            "at_a": [0.1, 0.3],
            "body_b": "rocker",
            "at_b": [0.4, 0.15],
            "stiffness": 200.0,
            "free_length": 0.1,
            "damping": 2.0,
        },
    ]
    names = ["length crank", "pin B@coupler.y", "loads.S.stiffness", "loads.push.at.0"]
    times = np.linspace(0.0, TURN, 21)
    check_efforts(desc, names, times, "crank_angle", {"loads.S.stiffness", "loads.push.at.0"})
    desc["loads"][0]["law"] = {"type": "spline", "times": [0.0, 1.0, 2.0], "values": [20.0, 25.0, 20.0]}
    with pytest.raises(lw.ParameterError, match="load 'push' follows a law whose numbers") as e:
        lw.Model(desc).sensitivities(np.linspace(0.0, 0.1, 3), ["loads.push.law.values.1"], efforts=True)
    assert "loads.push.law.values.1" in str(e.value)


def test_a_torsion_spring_in_degrees_is_differentiated_per_degree():
    # the engine keeps the spring per radian; the description's numbers are per degree
    m = lw.examples.four_bar()
    m.set_mass("coupler", 2.0, 0.02, (0.3, 0.15))
    desc = m.to_dict()
    k = 180.0 / np.pi
    desc["units"] = {"length": "m", "angle": "deg"}
    for b in desc["bodies"]:
        b["theta"] *= k
    law = desc["drivers"][0]["law"]
    law["value"], law["rate"] = law["value"] * k, law["rate"] * k
    desc["loads"] = [
        {
            "type": "torsion_spring",
            "name": "TS",
            "body_a": "crank",
            "body_b": "coupler",
            "stiffness": 0.05,
            "free_angle": 30.0,
            "damping": 0.01,
        }
    ]
    names = ["loads.TS.stiffness", "loads.TS.free_angle", "loads.TS.damping", "mass coupler"]
    check_efforts(desc, names, np.linspace(0.0, TURN, 21), "crank_angle", set(names))


def test_efforts_need_asking_for():
    s = lw.Model(four_bar()).sensitivities(np.linspace(0.0, 0.1, 3), ["length crank"])
    assert s.dlambda is None and s.efforts == {}
    with pytest.raises(lw.ParameterError, match="efforts=True"):
        s.effort("crank_angle")


# --- gear and belt ratios and radii ---------------------------------------------------------


def kinematic_check(desc: dict, names: list[str], times: np.ndarray, h_rel: float = 1e-4) -> None:
    s = lw.Model(desc).sensitivities(times, names)
    for j, name in enumerate(names):
        h = h_rel * abs(s.nominal[j])
        runs = [lw.Model(apply(desc, {name: s.nominal[j] + k * h})).sweep(times) for k in (-2, -1, 1, 2)]
        for key, got in (("q", s.dq), ("qd", s.dqd), ("qdd", s.dqdd)):
            f = [getattr(r, key) for r in runs]
            want = (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / (12 * h)
            scale = np.abs(want).max()
            err = np.abs(got[:, :, j] - want).max()
            assert err <= 1e-8 * scale + 1e-10, f"{name} d{key}: error {err:.3g} of {scale:.3g}"


def test_gear_train_radii_match_differences_of_whole_sweeps():
    # the compound train in mm and degrees: the radii's sensitivities, per mm
    desc = lw.Mechanism.load(HERE / "examples" / "gear_train_compound.toml").to_dict()
    names = ["radius_a mesh12", "radius_b mesh12", "radius_a mesh34", "radius_b mesh34"]
    kinematic_check(desc, names, np.linspace(0.0, 1.0, 25))
    # the planetary differential: gears on a carrier, an internal one
    desc = lw.Mechanism.load(HERE / "examples" / "gear_train_planetary.toml").to_dict()
    desc["bodies"][2]["theta"] = 0.4  # the arm (and the planet on it) drawn turned
    desc["bodies"][3].update(x=0.08 * np.cos(0.4), y=0.08 * np.sin(0.4), theta=0.9)
    desc["joints"][3]["at"] = [0.08 * np.cos(0.4), 0.08 * np.sin(0.4)]
    names = ["radius_a sun_planet", "radius_b sun_planet", "radius_a ring_planet", "radius_b ring_planet"]
    kinematic_check(desc, names, np.linspace(0.0, 1.0, 25))


def gear_pair(ratio: float) -> dict:
    return {
        "bodies": [
            {"name": "pinion", "x": 0.0, "y": 0.0, "theta": 0.4},
            {"name": "wheel", "x": 0.2, "y": 0.0, "theta": -1.3, "inertia": 0.02},
        ],
        "joints": [
            {"type": "revolute", "name": "Oa", "body_a": "ground", "body_b": "pinion", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "Ob", "body_a": "ground", "body_b": "wheel", "at": [0.2, 0.0]},
            {"type": "gear", "name": "G1", "body_a": "pinion", "body_b": "wheel", "ratio": ratio},
        ],
        "drivers": [
            {
                "type": "angle",
                "name": "input",
                "body": "pinion",
                "law": {"type": "polynomial", "coefficients": [0.4, 3.0, 2.0]},
            }
        ],
    }


def test_a_gear_ratio_on_both_sides_of_one_and_its_effort():
    for ratio in (0.6, 1.7):
        kinematic_check(gear_pair(ratio), ["ratio G1"], np.linspace(0.0, 0.5, 11))
        # the wheel's inertia seen at the pinion: J (r_a / r_b)^2 alpha_a, differentiated
        times = np.linspace(0.0, 0.5, 11)
        check_efforts(gear_pair(ratio), ["ratio G1", "inertia wheel"], times, "input", set())


def test_equal_radii_are_refused_where_the_derivative_is_one_sided():
    with pytest.raises(lw.ParameterError, match="two radii are equal.*one-sided") as e:
        lw.Model(gear_pair(1.0)).sensitivities(np.linspace(0.0, 0.1, 3), ["ratio G1"])
    assert "ratio G1" in str(e.value)
