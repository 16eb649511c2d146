"""Exact sensitivities (`Model.sensitivities`) of the four-bar against differences of
whole sweeps, the parameters named as a study names them (description paths and the
friendly names, the redrawn link lengths among them); the linear tolerance analysis from
them against Monte Carlo; and the parameters the engine does not differentiate, refused
by name (a study then falls back to labelled central differences).

The differences are fourth-order central ones, (f(-2h) - 8 f(-h) + 8 f(h) - f(2h)) / 12h,
with h = 1e-4: truncation ~h^4 |f^(5)| / 30 ~ 1e-14 and round-off ~eps |q| / h ~ 1e-12 on
this mechanism (lengths ~0.3, sweeps converged to ~1e-15), so 1e-8 relative to each
array's largest entry leaves a wide margin while a wrong term would be off by far more.
"""

from __future__ import annotations

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
        ("bodies.crank.x", "not an engine parameter"),
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
