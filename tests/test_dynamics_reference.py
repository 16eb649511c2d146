"""The reference's forward dynamics (``linkwork.reference.simulate``) against exact and
published solutions, and against the engine's inverse dynamics.

Tolerances (measured values in brackets, each bound a few times above them):
- A01 over 10 s at rtol = atol = 1e-12: DOP853's global error over ~500 steps of a
  smooth problem stays within 1e-10 [4e-12]; the energy (scale 10 J) within 1e-10
  [2e-11]. A wrong mass matrix, force or gamma term is off by O(1).
- A02 on its branch: each passage through a singular configuration (every half turn)
  costs the index-1 integration a phase error along the branch (the cut of the nearly
  dependent rows, ``singular_tol``) that depends on where the steps fall; N = 1 over 10 s
  (10 passages) and N = 2 over 3.3 s (4) stay within 3e-8 of the exact tip [1e-9 to
  6e-9 measured, by output grid], N = 40 over 0.8 s (1) within 5e-10 [5e-11]; the
  cranks share their angle to 1e-12 [1e-13] (off the branch they differ by O(1)), and
  the energy stays within 1e-9 of (N + 1) m g L [2e-10].
- Andrews' squeezer at rtol 1e-12: the published angles to scd >= 9 [9.57].
- Reference against engine, 1e-9 relative, as in test_dynamics: both solve the same
  well-conditioned systems in double precision.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from linkwork.mechanism import benchmarks
from linkwork.reference import ReferenceModel, exact, simulate
from linkwork.reference.forward import accelerations, potential_energy
from test_dynamics import four_bar_massive, luffing_boom

pytest.importorskip("scipy")


def tip(q: np.ndarray, length: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The tip of the first body (a bar along its x axis from its origin)."""
    return q[:, 0] + length * np.cos(q[:, 2]), q[:, 1] + length * np.sin(q[:, 2])


# --- IFToMM A01, the simple pendulum ------------------------------------------------------------


@pytest.fixture(scope="module")
def pendulum_run() -> dict:
    b = benchmarks.pendulum()
    return simulate(b.mechanism, np.linspace(0.0, b.t_end, 101), qd0=b.qd0, rtol=1e-12, atol=1e-12)


def test_exact_pendulum_is_a_pendulum() -> None:
    """The elliptic solution keeps the length, conserves energy and has the textbook
    period 4 K(sin^2(psi0/2)) sqrt(L/g) = 4 K(1/2) / sqrt(g) for psi0 = 90 degrees."""
    from scipy.special import ellipk

    t = np.linspace(0.0, 10.0, 1001)
    x, y, vx, vy = exact.pendulum_tip(t, velocity=True)
    # scipy's ellipj is good to a few 1e-14 [4e-14 measured]
    assert np.max(np.abs(np.hypot(x, y) - 1.0)) < 1e-12
    assert np.max(np.abs(0.5 * (vx**2 + vy**2) + 9.81 * y)) < 1e-11
    period = 4.0 * ellipk(0.5) / math.sqrt(9.81)
    xp, yp = exact.pendulum_tip(np.array([period, period / 2.0]))
    assert abs(xp[0] - 1.0) < 1e-12 and abs(xp[1] + 1.0) < 1e-12 and abs(yp[1]) < 1e-12
    # the velocity is the derivative of the position (central differences, h = 1e-5)
    h = 1e-5
    xa, ya = exact.pendulum_tip(t[1:-1] + h)
    xb, yb = exact.pendulum_tip(t[1:-1] - h)
    assert np.max(np.abs((xa - xb) / (2 * h) - vx[1:-1])) < 1e-8
    assert np.max(np.abs((ya - yb) / (2 * h) - vy[1:-1])) < 1e-8


def test_pendulum_follows_the_elliptic_solution(pendulum_run) -> None:
    x, y = exact.pendulum_tip(pendulum_run["times"])
    xs, ys = tip(pendulum_run["q"])
    assert max(np.max(np.abs(xs - x)), np.max(np.abs(ys - y))) < 1e-10


def test_pendulum_conserves_energy(pendulum_run) -> None:
    energy = pendulum_run["kinetic"] + pendulum_run["gravity"]
    assert np.ptp(energy) < 1e-10
    assert np.max(pendulum_run["drift_position"]) < 1e-12


# --- IFToMM A02, the N-four-bar -------------------------------------------------------------------


@pytest.mark.parametrize("n", [1, 2, 5])
def test_exact_branch_conserves_its_energy(n: int) -> None:
    branch = exact.n_four_bar_branch(n, 20.0)
    t = np.linspace(0.0, 20.0, 401)
    assert np.ptp(branch.energy(t)) < 1e-11 * abs(branch.energy(0.0))
    phi, phid = branch.phi(0.0)
    assert (float(phi), float(phid)) == (math.pi / 2.0, -1.0)


def test_n_four_bar_description() -> None:
    """2N+1 bars of 1 kg, 3N+1 pins, one degree of freedom, and qd0 satisfies the
    velocity constraints (B0 at +1 m/s)."""
    for n in (1, 2, 7):
        b = benchmarks.n_four_bar(n)
        ref = ReferenceModel(b.mechanism)
        q = ref.q_start()
        assert ref.n_coords == 3 * (2 * n + 1) and ref.n_rows == 2 * (3 * n + 1)
        assert np.linalg.matrix_rank(ref.phi_q(q, 0.0)) == ref.n_rows
        assert np.max(np.abs(ref.phi_q(q, 0.0) @ b.qd0)) < 1e-15
        _, v, _ = ref.point("B0", q, b.qd0, np.zeros_like(q))
        assert np.allclose(v, [1.0, 0.0], atol=1e-15)
    with pytest.raises(ValueError, match="N >= 1"):
        benchmarks.n_four_bar(0)


# (N, span, output times, rtol, singular_tol, bound on the tip's error). N = 40's reference
# costs ~0.3 s per evaluation (243 coordinates, dense, per-joint Python): one passage only.
A02_RUNS = {
    1: (10.0, 101, 1e-12, 1e-5, 3e-8),
    2: (3.3, 34, 1e-12, 1e-6, 3e-8),
    40: (0.8, 5, 1e-9, 0.0, 5e-10),
}


@pytest.fixture(scope="module", params=sorted(A02_RUNS), ids=lambda n: f"N{n}")
def four_bar_run(request) -> tuple[int, dict, exact.FourBarBranch]:
    n = request.param
    span, outputs, rtol, singular_tol, _ = A02_RUNS[n]
    b = benchmarks.n_four_bar(n)
    times = np.linspace(0.0, span, outputs)
    run = simulate(b.mechanism, times, qd0=b.qd0, rtol=rtol, atol=rtol, singular_tol=singular_tol)
    return n, run, exact.n_four_bar_branch(n, span)


def test_n_four_bar_stays_on_its_branch(four_bar_run) -> None:
    n, run, branch = four_bar_run
    phi, _ = branch.phi(run["times"])
    # phi passes a multiple of pi, a singular configuration, every half turn
    passages = int(np.floor(phi[0] / math.pi) - np.floor(phi[-1] / math.pi))
    assert passages >= {1: 10, 2: 4, 40: 1}[n]
    cranks = run["q"][:, 2::3][:, : n + 1]
    assert np.max(np.ptp(cranks, axis=1)) < 1e-12
    x, y, vx, vy = branch.tip(run["times"])
    xs, ys = tip(run["q"])
    assert max(np.max(np.abs(xs - x)), np.max(np.abs(ys - y))) < A02_RUNS[n][-1]


def test_n_four_bar_conserves_energy(four_bar_run) -> None:
    """Within 1e-9 of the energy's scale, (N + 1) m g L [N = 1: 1e-9 measured over 10 s]."""
    n, run, _ = four_bar_run
    assert np.ptp(run["kinetic"] + run["gravity"]) < 1e-9 * (n + 1) * 9.81


# --- Andrews' squeezing mechanism -----------------------------------------------------------------


def test_squeezer_closes_and_starts_as_published() -> None:
    """The drawing closes the three loops at E to rounding, gives back the test set's
    angles, and the accelerations at rest are the test set's consistent initial ones
    (beta'' = 14222.4439199541138705911625887, Theta'' = -10666.8329399655854029433719415)."""
    b = benchmarks.andrews_squeezer()
    ref = ReferenceModel(b.mechanism)
    q = ref.q_start()
    assert np.max(np.abs(ref.phi(q, 0.0))) < 1e-12 * ref.length_scale
    assert np.max(np.abs(benchmarks.andrews_angles(q) - exact.ANDREWS_ANGLES0)) < 1e-15
    qdd, _ = accelerations(ref, q, np.zeros(ref.n_coords), 0.0)
    angles = benchmarks.andrews_angles(qdd)
    want = [14222.4439199541138705911625887, -10666.8329399655854029433719415, 0, 0, 0, 0, 0]
    assert np.max(np.abs(angles - want)) < 1e-9 * 14222.0


def test_squeezer_reaches_the_published_angles() -> None:
    b = benchmarks.andrews_squeezer()
    run = simulate(b.mechanism, [0.0, 0.01, 0.02, exact.ANDREWS_T_END], rtol=1e-12, atol=1e-14)
    assert exact.scd(benchmarks.andrews_angles(run["q"][-1])) >= 9.0
    # energy: the torque's work mom * (beta - beta0) goes into motion and the spring
    ref = ReferenceModel(b.mechanism)
    work = exact.ANDREWS["mom"] * (run["q"][:, 2] - run["q"][0, 2])
    balance = run["kinetic"] + run["springs"] - work
    assert np.ptp(balance) < 1e-9 * max(np.max(run["kinetic"]), 1.0)
    assert potential_energy(ref, run["q"][0])["springs"] == pytest.approx(run["springs"][0], rel=1e-15)


def test_drift_without_projection_is_measured_and_bad_input_named() -> None:
    """Without projection the constraints drift by about the integration error and the
    run says by how much; with it the outputs sit on them to rounding."""
    b = benchmarks.n_four_bar(1)
    times = np.linspace(0.0, 0.6, 7)
    free = simulate(b.mechanism, times, qd0=b.qd0, rtol=1e-6, atol=1e-6, project_outputs=False)
    kept = simulate(b.mechanism, times, qd0=b.qd0, rtol=1e-6, atol=1e-6)
    ref = ReferenceModel(b.mechanism)
    assert 1e-12 < np.max(free["drift_position"]) < 1e-4
    assert max(np.max(np.abs(ref.phi(q, 0.0))) for q in kept["q"]) < 1e-14
    with pytest.raises(ValueError, match="strictly increasing"):
        simulate(b.mechanism, [0.0, 0.0])
    with pytest.raises(ValueError, match="9 entries"):
        simulate(b.mechanism, [0.0, 0.1], qd0=[1.0])


def test_scd_is_digits_of_the_worst_component() -> None:
    ref = exact.ANDREWS_REFERENCE
    assert exact.scd(ref) == math.inf
    assert exact.scd(ref * (1 + 1e-7)) == pytest.approx(7.0, abs=1e-6)


# --- against the engine ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "make", [four_bar_massive, lambda: luffing_boom().to_dict()], ids=["four_bar", "boom"]
)
def test_augmented_system_matches_the_engines_inverse_dynamics(make) -> None:
    """On a driven model (no free coordinate) the augmented system's qdd is the
    kinematics' and its lambda the engine's inverse dynamics, M qdd + Phi_q^T lambda = Q:
    one check of the reference's M, Q, Phi_q and gamma together against the engine."""
    desc = make()
    times = np.linspace(0.0, 1.0, 7)
    res = lw.Model(desc).sweep(times, forces=True)
    ref = ReferenceModel(desc)
    for k, t in enumerate(times):
        qdd, lam = accelerations(ref, res.q[k], res.qd[k], float(t))
        assert np.max(np.abs(qdd - res.qdd[k])) <= 1e-9 * np.max(np.abs(res.qdd[k]))
        assert np.max(np.abs(lam - res.multipliers[k])) <= 1e-9 * np.max(np.abs(res.multipliers[k]))


FREE_MOTIONS = {
    "A01": (benchmarks.pendulum, "bar", 0.7),
    "A02": (lambda: benchmarks.n_four_bar(2), "crank0", 0.4),
    "andrews": (benchmarks.andrews_squeezer, "body1", 0.01),
}


@pytest.mark.parametrize("problem", sorted(FREE_MOTIONS))
def test_free_motion_needs_no_driver_effort(problem: str) -> None:
    """A benchmark simulated by the reference to t0, then driven by the engine along the
    same motion (its first body's angle, a quadratic in t matching theta, thetad and
    thetadd at t0): the engine's driver effort vanishes and its joint multipliers are the
    reference's. The engine reads the same description (a singular body mass matrix in
    A01, the spring and the torque in Andrews')."""
    make, body, t0 = FREE_MOTIONS[problem]
    b = make()
    run = simulate(b.mechanism, [0.0, t0], qd0=b.qd0, rtol=1e-12, atol=1e-12)
    q, qd, qdd, lam = (run[key][-1] for key in ("q", "qd", "qdd", "lambda"))
    th, w, a = q[2], qd[2], qdd[2]
    m = b.mechanism
    m.drive_angle(body, lw.Polynomial([th - w * t0 + 0.5 * a * t0**2, w - a * t0, 0.5 * a]), name="motor")
    res = m.compile().sweep([t0], q_guess=q, forces=True)
    scale = np.max(np.abs(lam))
    assert np.max(np.abs(res.q[0] - q)) < 1e-12 * ReferenceModel(m).length_scale
    assert np.max(np.abs(res.qdd[0] - qdd)) < 1e-9 * np.max(np.abs(qdd))
    assert abs(res.effort("motor")[0]) < 1e-9 * scale * ReferenceModel(m).length_scale
    assert np.max(np.abs(res.multipliers[0, : len(lam)] - lam)) < 1e-9 * scale
