"""The NumPy reference against textbook closed forms, finite differences and itself.

Tolerances: Newton stops at a scaled residual and step of 1e-12, and the closed forms are
evaluated in double precision, so agreements to 1e-10 relative leave two orders of margin
without hiding a real error (a wrong term in gamma is off by O(1)). Central differences
with h = 1e-6 carry O(h^2) ~ 1e-12 truncation and O(eps / h) ~ 1e-10 rounding errors, so
they are checked at 1e-8 relative.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from linkwork import closed_form, examples
from linkwork.reference import ConvergenceError, ReferenceModel, motion_law

OMEGA = 5.0
N_STEPS = 361


def revolution(omega: float = OMEGA, n: int = N_STEPS) -> np.ndarray:
    return np.linspace(0.0, 2.0 * math.pi / omega, n)


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angle difference brought into [-pi, pi)."""
    return (np.asarray(angle) + math.pi) % (2.0 * math.pi) - math.pi


def rel_err(got: np.ndarray, want: np.ndarray) -> float:
    """Largest error relative to the quantity's largest magnitude over the cycle."""
    return float(np.max(np.abs(got - want)) / np.max(np.abs(want)))


def col(ref: ReferenceModel, name: str) -> int:
    return ref.columns.index(name)


# --- closed forms over whole revolutions ------------------------------------------------------


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_four_bar_matches_closed_form(branch):
    dims = dict(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25)
    ref = ReferenceModel(examples.four_bar(**dims, omega=OMEGA, theta0=0.3, branch=branch))
    ts = revolution()
    out = ref.sweep(ts)
    theta2 = 0.3 + OMEGA * ts
    cf = closed_form.four_bar(**dims, theta2=theta2, omega2=OMEGA, alpha2=0.0, branch=branch)
    q, qd, qdd = out["q"], out["qd"], out["qdd"]
    # angles are O(1) rad: compare them absolutely, modulo 2 pi
    assert np.max(np.abs(wrap(q[:, col(ref, "crank.theta")] - theta2))) <= 1e-12
    for body, k in (("coupler", "3"), ("rocker", "4")):
        j = col(ref, f"{body}.theta")
        assert np.max(np.abs(wrap(q[:, j] - cf["theta" + k]))) <= 1e-10
        assert rel_err(qd[:, j], cf["omega" + k]) <= 1e-10
        assert rel_err(qdd[:, j], cf["alpha" + k]) <= 1e-10
    assert out["iterations"].max() <= 4  # the q + h qd + h^2/2 qdd prediction is good


def test_four_bar_with_angular_acceleration_matches_closed_form():
    """A polynomial crank law gives alpha2 != 0, so the alpha2 terms are checked too."""
    m = examples.four_bar(theta0=0.0)
    desc = m.to_dict()
    coefficients = [0.0, 2.0, 3.0, -0.5]
    desc["drivers"][0]["law"] = lw.Polynomial(coefficients).to_dict()
    ref = ReferenceModel(desc)
    ts = np.linspace(0.0, 1.5, 241)
    out = ref.sweep(ts)
    c0, c1, c2, c3 = coefficients
    theta2 = c0 + c1 * ts + c2 * ts**2 + c3 * ts**3
    omega2 = c1 + 2 * c2 * ts + 3 * c3 * ts**2
    alpha2 = 2 * c2 + 6 * c3 * ts
    cf = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, theta2, omega2, alpha2)
    for body, k in (("coupler", "3"), ("rocker", "4")):
        j = col(ref, f"{body}.theta")
        assert np.max(np.abs(wrap(out["q"][:, j] - cf["theta" + k]))) <= 1e-10
        assert rel_err(out["qd"][:, j], cf["omega" + k]) <= 1e-10
        assert rel_err(out["qdd"][:, j], cf["alpha" + k]) <= 1e-10


def test_four_bar_coupler_point_matches_closed_form():
    ref = ReferenceModel(examples.four_bar())
    ts = revolution()
    out = ref.sweep(ts)
    r, v, a = ref.point("P", out["q"], out["qd"], out["qdd"])
    theta2 = OMEGA * ts
    cf = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, theta2, OMEGA)
    e2, e3 = np.exp(1j * theta2), np.exp(1j * cf["theta3"])
    half = 0.35 / 2
    p = 0.20 * e2 + half * e3
    pv = 0.20 * 1j * OMEGA * e2 + half * 1j * cf["omega3"] * e3
    pa = 0.20 * (-(OMEGA**2)) * e2 + half * (1j * cf["alpha3"] - cf["omega3"] ** 2) * e3
    for got, want in ((r, p), (v, pv), (a, pa)):
        assert got.shape == (N_STEPS, 2)
        assert rel_err(got[:, 0] + 1j * got[:, 1], want) <= 1e-10
    # one state in, one point out
    r1, v1, a1 = ref.point("P", out["q"][7], out["qd"][7], out["qdd"][7])
    assert r1.shape == (2,) and np.allclose(r1, r[7], rtol=0, atol=1e-15)
    assert np.allclose(a1, a[7], rtol=0, atol=1e-12)


@pytest.mark.parametrize("offset", [0.0, 0.02, -0.05])
def test_slider_crank_matches_closed_form(offset):
    ref = ReferenceModel(examples.slider_crank(crank=0.10, rod=0.35, offset=offset, omega=OMEGA, theta0=0.2))
    ts = revolution()
    out = ref.sweep(ts)
    cf = closed_form.slider_crank(0.10, 0.35, offset, 0.2 + OMEGA * ts, OMEGA)
    q, qd, qdd = out["q"], out["qd"], out["qdd"]
    j = col(ref, "rod.theta")
    assert np.max(np.abs(wrap(q[:, j] - cf["theta3"]))) <= 1e-10
    assert rel_err(qd[:, j], cf["omega3"]) <= 1e-10
    assert rel_err(qdd[:, j], cf["alpha3"]) <= 1e-10
    x = col(ref, "slider.x")
    assert rel_err(q[:, x], cf["x"]) <= 1e-10
    assert rel_err(qd[:, x], cf["v"]) <= 1e-10
    assert rel_err(qdd[:, x], cf["a"]) <= 1e-10
    # the slider keeps to its line and does not turn
    assert np.max(np.abs(q[:, col(ref, "slider.y")] - offset)) <= 1e-12
    assert np.max(np.abs(q[:, col(ref, "slider.theta")])) <= 1e-12


def test_inverted_slider_crank_matches_geometry():
    """Rocker angle phi = arg(w), w = A - O4: omega = Im(wd / w), alpha = Im(wdd / w - (wd / w)^2)."""
    ref = ReferenceModel(examples.inverted_slider_crank(ground=0.30, crank=0.10, omega=OMEGA))
    ts = revolution()
    out = ref.sweep(ts)
    th = OMEGA * ts
    w = 0.10 * np.exp(1j * th) - 0.30
    wd = 0.10 * 1j * OMEGA * np.exp(1j * th)
    wdd = -0.10 * OMEGA**2 * np.exp(1j * th)
    j = col(ref, "rocker.theta")
    assert np.max(np.abs(wrap(out["q"][:, j] - np.angle(w)))) <= 1e-10
    assert rel_err(out["qd"][:, j], np.imag(wd / w)) <= 1e-10
    assert rel_err(out["qdd"][:, j], np.imag(wdd / w - (wd / w) ** 2)) <= 1e-10
    # the block rides on the crank pin, turned with the rocker
    assert np.max(np.abs(out["q"][:, col(ref, "block.theta")] - out["q"][:, j])) <= 1e-12
    block = out["q"][:, col(ref, "block.x")] + 1j * out["q"][:, col(ref, "block.y")]
    assert np.max(np.abs(block - (w + 0.30))) <= 1e-12


@pytest.mark.parametrize("scale", [1e-3, 1e3])
def test_tiny_and_huge_units_give_the_same_angles(scale):
    """The tolerance is scale-aware: millimetre and kilometre four-bars solve alike."""
    ts = revolution(n=91)
    base = ReferenceModel(examples.four_bar()).sweep(ts)
    dims = {k: v * scale for k, v in dict(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25).items()}
    ref = ReferenceModel(examples.four_bar(**dims))
    out = ref.sweep(ts)
    assert ref.length_scale == pytest.approx(
        scale * ReferenceModel(examples.four_bar()).length_scale, rel=1e-12
    )
    thetas = [col(ref, f"{b}.theta") for b in ("crank", "coupler", "rocker")]
    assert np.max(np.abs(out["q"][:, thetas] - base["q"][:, thetas])) <= 1e-10
    assert rel_err(out["qdd"][:, thetas], base["qdd"][:, thetas]) <= 1e-10
    assert out["iterations"].max() <= 4


# --- finite differences for every joint and driver type ----------------------------------------

# three bodies in general poses; every joint and driver type, with the ground on either side
BODIES = {"b1": ((0.3, 0.1), 0.4), "b2": ((-0.2, 0.5), 1.1), "b3": ((0.6, -0.3), -0.7)}
ITEMS = {
    "revolute-ground-b1": ("revolute", "ground", "b1", {"at": (0.1, 0.2)}),
    "revolute-b1-b2": ("revolute", "b1", "b2", {"at": (0.2, 0.4)}),
    "revolute-b2-ground": ("revolute", "b2", "ground", {"at": (-0.3, 0.1)}),
    "prismatic-b1-b2": ("prismatic", "b1", "b2", {"at": (0.0, 0.3), "axis": (1.0, 0.5)}),
    "prismatic-ground-b3": ("prismatic", "ground", "b3", {"at": (0.5, 0.0), "axis": (0.3, 1.0)}),
    "prismatic-b3-ground": ("prismatic", "b3", "ground", {"at": (0.4, -0.2), "axis": (-1.0, 0.2)}),
    "fixed-b2-b3": ("fixed", "b2", "b3", {}),
    "fixed-ground-b1": ("fixed", "ground", "b1", {}),
    "fixed-b1-ground": ("fixed", "b1", "ground", {}),
    "angle-b2": ("angle", None, "b2", {"law": lw.Harmonic(0.5, 0.3, 2.0, 0.4)}),
    "relative_angle-b1-b3": ("relative_angle", "b1", "b3", {"law": lw.Polynomial([0.1, -0.4, 0.7, 0.2])}),
    "relative_angle-ground-b2": ("relative_angle", "ground", "b2", {"law": lw.Harmonic(0.2, 0.5, 1.5)}),
    "distance-b1-b3": (
        "distance",
        "b1",
        "b3",
        {
            "at_a": (0.2, 0.3),
            "at_b": (0.7, -0.1),
            "law": lw.Spline([0.0, 0.3, 0.5, 1.0], [0.4, 0.5, 0.45, 0.6]),
        },
    ),
    "distance-ground-b2": (
        "distance",
        "ground",
        "b2",
        {"at_a": (0.5, 0.5), "at_b": (-0.1, 0.6), "law": lw.Constant(0.6)},
    ),
    "coordinate-x-b3": (
        "coordinate",
        None,
        "b3",
        {"at": (0.7, -0.2), "axis": "x", "law": lw.Harmonic(0.6, 0.1, 3.0)},
    ),
    "coordinate-y-b2": (
        "coordinate",
        None,
        "b2",
        {"at": (-0.1, 0.7), "axis": "y", "law": lw.Linear(0.7, -0.3)},
    ),
    "translation-b1-b2": ("translation", "b1", "b2", {"law": lw.Polynomial([0.0, 0.2, -0.5])}),
    "translation-ground-b3": ("translation", "ground", "b3", {"law": lw.Harmonic(0.0, 0.05, 4.0, 0.3)}),
    "translation-b3-ground": ("translation", "b3", "ground", {"law": lw.Linear(0.0, 0.3)}),
}


def one_item_model(key: str) -> ReferenceModel:
    kind, a, b, opts = ITEMS[key]
    m = lw.Mechanism(key)
    for name, (origin, angle) in BODIES.items():
        m.body(name, origin, angle)
    opts = dict(opts)
    if kind == "revolute":
        m.revolute(a, b, opts["at"])
    elif kind == "prismatic":
        m.prismatic(a, b, opts["at"], opts["axis"])
    elif kind == "fixed":
        m.fixed(a, b)
    elif kind == "angle":
        m.drive_angle(b, opts["law"])
    elif kind == "relative_angle":
        m.drive_relative_angle(a, b, opts["law"])
    elif kind == "distance":
        m.drive_distance(a, opts["at_a"], b, opts["at_b"], opts["law"])
    elif kind == "coordinate":
        m.drive_coordinate(b, opts["at"], opts["axis"], opts["law"])
    elif kind == "translation":
        joint = m.prismatic(a, b, (0.3, 0.2), (0.6, -0.8))
        m.drive_translation(joint, opts["law"])
    return ReferenceModel(m.to_dict())


def test_every_joint_and_driver_type_is_covered():
    desc_types = {ITEMS[k][0] for k in ITEMS}
    assert desc_types == {
        "revolute",
        "prismatic",
        "fixed",
        "angle",
        "relative_angle",
        "distance",
        "coordinate",
        "translation",
    }


def random_state(ref: ReferenceModel, seed: int):
    rng = np.random.default_rng(seed)
    q = ref.q_start() + rng.normal(scale=0.3, size=ref.n_coords)  # away from the start
    qd = rng.normal(scale=1.0, size=ref.n_coords)
    t = float(rng.uniform(0.05, 0.95))
    return q, qd, t


H = 1e-6


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("key", sorted(ITEMS))
def test_phi_q_and_nu_match_finite_differences(key, seed):
    ref = one_item_model(key)
    q, _, t = random_state(ref, seed)
    J = ref.phi_q(q, t)
    J_fd = np.zeros_like(J)
    for k in range(ref.n_coords):
        dq = np.zeros(ref.n_coords)
        dq[k] = H
        J_fd[:, k] = (ref.phi(q + dq, t) - ref.phi(q - dq, t)) / (2 * H)
    assert np.max(np.abs(J - J_fd)) <= 1e-8 * max(1.0, np.max(np.abs(J)))
    assert np.max(np.abs(J)) > 0.1  # not trivially zero
    # nu = -Phi_t
    phi_t = (ref.phi(q, t + H) - ref.phi(q, t - H)) / (2 * H)
    assert np.max(np.abs(ref.nu(q, t) + phi_t)) <= 1e-8 * max(1.0, np.max(np.abs(phi_t)))


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("key", sorted(ITEMS))
def test_gamma_matches_finite_differences(key, seed):
    """Along q(s) = q + s qd, t(s) = t + s (so qdd = 0), d/ds [Phi_q qd + Phi_t] is
    (Phi_q qd)_q qd + 2 Phi_qt qd + Phi_tt = -gamma."""
    ref = one_item_model(key)
    q, qd, t = random_state(ref, seed)

    def rate(s: float) -> np.ndarray:
        return ref.phi_q(q + s * qd, t + s) @ qd - ref.nu(q + s * qd, t + s)

    gamma_fd = -(rate(H) - rate(-H)) / (2 * H)
    gamma = ref.gamma(q, qd, t)
    assert np.max(np.abs(gamma - gamma_fd)) <= 1e-8 * max(1.0, np.max(np.abs(gamma)))
    if key != "fixed-ground-b1":  # a weld to the ground has gamma = 0 exactly
        assert np.max(np.abs(gamma)) > 1e-3  # the check is not comparing zeros


def test_gamma_with_all_items_together():
    """The assembled model (every item at once) agrees with finite differences too."""
    m = lw.Mechanism("zoo")
    for name, (origin, angle) in BODIES.items():
        m.body(name, origin, angle)
    m.revolute("ground", "b1", (0.1, 0.2))
    p = m.prismatic("b1", "b2", (0.0, 0.3), (1.0, 0.5))
    m.fixed("b2", "b3")
    m.drive_translation(p, lw.Linear(0.0, 0.4))
    m.drive_distance("ground", (0.5, 0.5), "b3", (0.7, -0.1), lw.Harmonic(0.6, 0.05, 2.0))
    ref = ReferenceModel(m)
    assert ref.n_rows == 9 == ref.n_coords
    q, qd, t = random_state(ref, 7)
    rate = lambda s: ref.phi_q(q + s * qd, t + s) @ qd - ref.nu(q + s * qd, t + s)  # noqa: E731
    gamma_fd = -(rate(H) - rate(-H)) / (2 * H)
    assert np.max(np.abs(ref.gamma(q, qd, t) - gamma_fd)) <= 1e-8 * max(1.0, np.max(np.abs(gamma_fd)))
    # and the solves hold the model together along a short sweep
    out = ref.sweep(np.linspace(0.0, 0.5, 11))
    for k, tk in enumerate(out["times"]):
        assert np.max(np.abs(ref.phi(out["q"][k], tk))) <= 1e-12
        J = ref.phi_q(out["q"][k], tk)
        assert np.allclose(J @ out["qd"][k], ref.nu(out["q"][k], tk), rtol=0, atol=1e-12)
        assert np.allclose(J @ out["qdd"][k], ref.gamma(out["q"][k], out["qd"][k], tk), rtol=0, atol=1e-11)


# --- motion laws ---------------------------------------------------------------------------------

LAWS = {
    "constant": lw.Constant(1.3),
    "linear": lw.Linear(0.5, -2.0),
    "polynomial": lw.Polynomial([0.3, -1.0, 0.5, 2.0, -0.7]),
    "harmonic": lw.Harmonic(0.2, 1.5, 3.0, 0.4),
    "spline": lw.Spline([0.0, 0.2, 0.5, 0.6, 1.0, 1.4], [0.0, 0.3, -0.1, 0.2, 0.8, 0.5]),
}


@pytest.mark.parametrize("name", sorted(LAWS))
def test_motion_law_derivatives_match_finite_differences(name):
    law = LAWS[name].to_dict()
    h = 1e-6
    for t in (0.07, 0.33, 0.55, 0.81, 1.27):
        f, fd, fdd = motion_law(law, t)
        fp, fdp, _ = motion_law(law, t + h)
        fm, fdm, _ = motion_law(law, t - h)
        assert abs(fd - (fp - fm) / (2 * h)) <= 1e-8 * max(1.0, abs(fd))
        assert abs(fdd - (fdp - fdm) / (2 * h)) <= 1e-8 * max(1.0, abs(fdd))


def test_motion_law_values():
    assert motion_law(LAWS["linear"].to_dict(), 2.0) == (0.5 - 4.0, -2.0, 0.0)
    f, fd, fdd = motion_law(lw.Polynomial([1.0, 2.0, 3.0]).to_dict(), 2.0)
    assert (f, fd, fdd) == (1 + 4 + 12, 2 + 12, 6)
    f, fd, fdd = motion_law(lw.Harmonic(1.0, 2.0, 3.0, 0.5).to_dict(), 0.25)
    assert f == pytest.approx(1 + 2 * math.sin(1.25), rel=1e-15)
    assert fdd == pytest.approx(-18 * math.sin(1.25), rel=1e-15)


def test_spline_interpolates_is_c2_and_natural():
    law = LAWS["spline"].to_dict()
    times, values = law["times"], law["values"]
    for tk, yk in zip(times, values):
        assert motion_law(law, tk)[0] == pytest.approx(yk, abs=1e-14)
    # at each interior knot the cubic on the left and the one on the right agree (C2)
    for tk in times[1:-1]:
        left = np.array(motion_law(law, np.nextafter(tk, -np.inf)))
        right = np.array(motion_law(law, tk))
        assert np.max(np.abs(left - right)) <= 1e-12
    # natural ends: zero second derivative
    assert abs(motion_law(law, times[0])[2]) <= 1e-12
    assert abs(motion_law(law, times[-1])[2]) <= 1e-12
    # the third derivative does jump at knots (it is a real cubic spline, not one cubic)
    thirds = []
    for k in range(len(times) - 1):
        a, b = times[k] + 1e-3, times[k + 1] - 1e-3
        thirds.append((motion_law(law, b)[2] - motion_law(law, a)[2]) / (b - a))
    assert np.ptp(thirds) > 1.0


def test_spline_reproduces_straight_lines_and_refuses_outside_times():
    law = lw.Spline([0.0, 0.5, 2.0, 2.5], [1.0, 2.0, 5.0, 6.0]).to_dict()  # y = 1 + 2 t
    for t in (0.0, 0.3, 1.7, 2.5):
        f, fd, fdd = motion_law(law, t)
        assert f == pytest.approx(1 + 2 * t, abs=1e-14)
        assert fd == pytest.approx(2.0, abs=1e-13)
        assert fdd == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(ValueError, match="outside"):
        motion_law(law, 2.5000001)
    with pytest.raises(ValueError, match="outside"):
        motion_law(law, -1e-9)
    with pytest.raises(ValueError, match="increase"):
        motion_law(lw.Spline([0.0, 0.0, 1.0], [1.0, 2.0, 3.0]).to_dict(), 0.5)


def test_spline_matches_scipy_natural_spline():
    interpolate = pytest.importorskip("scipy.interpolate")
    law = LAWS["spline"].to_dict()
    cs = interpolate.CubicSpline(law["times"], law["values"], bc_type="natural")
    for t in np.linspace(0.0, 1.4, 29):
        got = motion_law(law, t)
        assert got == pytest.approx((float(cs(t)), float(cs(t, 1)), float(cs(t, 2))), abs=1e-12)


# --- the built-in examples -----------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(examples.ALL))
def test_example_sweeps_a_full_revolution(name):
    m = examples.ALL[name]()
    assert isinstance(m, lw.Mechanism)
    ref = ReferenceModel(m)
    assert ref.n_rows == ref.n_coords
    # assembled exactly at t = 0: one Newton step, nothing moves
    q0, iterations = ref.solve_position(0.0)
    assert iterations == 1 and np.max(np.abs(q0 - ref.q_start())) <= 1e-12
    ts = revolution()
    out = ref.sweep(ts)
    assert out["q"].shape == out["qd"].shape == out["qdd"].shape == (N_STEPS, ref.n_coords)
    assert out["iterations"].max() <= 4
    for k in range(0, N_STEPS, 6):
        assert np.max(np.abs(ref.phi(out["q"][k], ts[k]))) <= 1e-12 * ref.length_scale * 10
        assert ref.singular_ratio(out["q"][k], ts[k]) > 1e-3  # far from any singular position
    # after one revolution everything is back where it started
    dq = out["q"][-1] - out["q"][0]
    dq[2::3] = wrap(dq[2::3])
    assert np.max(np.abs(dq)) <= 1e-10
    assert np.max(np.abs(out["qd"][-1] - out["qd"][0])) <= 1e-9 * np.max(np.abs(out["qd"]))


def test_examples_have_the_documented_names():
    fb = ReferenceModel(examples.four_bar())
    assert fb.body_names == ["crank", "coupler", "rocker"]
    assert fb.columns[:3] == ["crank.x", "crank.y", "crank.theta"]
    joints = [j["name"] for j in examples.four_bar().to_dict()["joints"]]
    assert joints == ["O2", "A", "B", "O4"]
    for name, build in examples.ALL.items():
        desc = build().to_dict()
        assert [d["name"] for d in desc["drivers"]] == ["crank_angle"], name


# --- API behaviour and errors -------------------------------------------------------------------


def test_accepts_mechanism_or_dict():
    m = examples.slider_crank()
    a, b = ReferenceModel(m), ReferenceModel(m.to_dict())
    assert a.columns == b.columns and np.array_equal(a.q_start(), b.q_start())
    q, qd, qdd = a.solve(0.1)
    assert q.shape == qd.shape == qdd.shape == (a.n_coords,)


def _unreachable() -> lw.Mechanism:
    m = lw.Mechanism("reach")
    bar = m.body("bar", (0.0, 0.0), 1.0)
    m.revolute(m.ground, bar, (0.0, 0.0))
    # tip at 0.2 from the pivot, pulled from (0.5, 0): reachable for distances in [0.3, 0.7]
    tip = (0.2 * math.cos(1.0), 0.2 * math.sin(1.0))
    m.drive_distance(m.ground, (0.5, 0.0), bar, tip, lw.Linear(0.5, 1.0))
    return m


def test_failure_names_the_time_and_keeps_good_steps():
    ref = ReferenceModel(_unreachable())
    with pytest.raises(RuntimeError, match=r"t = 0\.6"):
        ref.solve_position(0.6)
    with pytest.raises(ConvergenceError) as info:
        ref.sweep([0.0, 0.1, 0.6, 0.7])
    assert info.value.step == 2 and info.value.time == 0.6
    assert info.value.partial["q"].shape == (2, ref.n_coords)


def test_bad_descriptions_are_refused_with_names():
    m = lw.Mechanism()
    m.body("b", (0, 0), 0)
    m.revolute(m.ground, "nobody", (0, 0), name="J")
    with pytest.raises(ValueError, match="nobody"):
        ReferenceModel(m)
    m = lw.Mechanism()
    b = m.body("b", (0, 0), 0)
    j = m.revolute(m.ground, b, (0, 0))
    m.drive_translation(j, lw.Linear(0, 1))
    with pytest.raises(ValueError, match="not a prismatic"):
        ReferenceModel(m)
