"""Forward dynamics in absolute coordinates, the index-1 way, written for clarity.

The equations of motion of the constrained system are

    M(q) qdd + Phi_q^T lambda = Q(q, qd, t),    Phi(q, t) = 0.

Differentiating the constraints twice gives Phi_q qdd = gamma, so at every state (q, qd)
the accelerations and the multipliers solve one square system,

    [[M,     Phi_q^T],  [qdd   ]   [Q    ]
     [Phi_q, 0      ]]  [lambda] = [gamma].

It has one solution qdd whenever M is positive definite on the motions the constraints
allow (the null space of Phi_q), even where M alone is singular (a point mass on a bar
has no inertia about its centre of mass) and where Phi_q loses rank at a singular
configuration. There lambda is not unique and the least-squares solve gives the
minimum-norm one. M, Q (gravity, quadratic velocity terms, the loads), Phi_q and gamma
are the reference's own (``dynamics``, ``formulation``).

The pair (q, qd) is then an ordinary ODE integrated by ``scipy.integrate.solve_ivp``;
only Phi_q qdd = gamma is imposed, so Phi and Phi_q qd - nu drift with the integration
error. ``simulate`` stops at every output time, measures that drift, and projects q onto
Phi = 0 (Gauss-Newton, minimum-norm steps) and qd onto Phi_q qd = nu (minimum-norm
correction) before going on.

Energy: kinetic 1/2 qd^T M qd, the potential of gravity (-sum m g . r_c) and of the
springs (1/2 k (L - L0)^2, 1/2 k (theta_b - theta_a - free)^2). Applied forces and
torques, the dampers and the joint loads are not in it; their work is what the balance
misses.
"""

from __future__ import annotations

import math
import time as _time
from typing import TYPE_CHECKING, Any

import numpy as np

from . import dynamics

if TYPE_CHECKING:
    from .model import ReferenceModel

__all__ = ["accelerations", "project", "potential_energy", "simulate"]


def accelerations(
    ref: ReferenceModel, q: np.ndarray, qd: np.ndarray, t: float, singular_tol: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """qdd (n_coords) and lambda (n_rows) from the augmented system at one state.

    With ``singular_tol`` = 0, LU, and where that fails (Phi_q rank deficient at a
    singular configuration) the least-squares minimum-norm solution, whose qdd is still
    the unique one when M is positive definite on the null space of Phi_q.

    With ``singular_tol`` > 0, Phi_q = U S V^T is first cut to its singular values above
    ``singular_tol`` times the largest: near a singular configuration a state a little
    off the constraints (integration error) asks the nearly dependent rows for
    accelerations of order (error) / s_min, which the motion does not have; the cut
    drops those rows while s_min < singular_tol s_max (their multipliers are set to 0,
    the minimum-norm choice) and the projection at the output times restores them."""
    n = ref.n_coords
    J = ref.phi_q(q, t)
    gamma = ref.gamma(q, qd, t)
    parts = dynamics.generalized_forces(ref, q, qd, t)
    Q = parts["velocity"] + parts["gravity"] + parts["loads"]
    U = None
    if singular_tol > 0.0:
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        keep = s > singular_tol * s[0]
        U = U[:, keep]
        J, gamma = s[keep, None] * Vt[keep], U.T @ gamma
    m = J.shape[0]
    K = np.block([[dynamics.mass_matrix(ref, q), J.T], [J, np.zeros((m, m))]])
    rhs = np.concatenate([Q, gamma])
    try:
        x = np.linalg.solve(K, rhs)
    except np.linalg.LinAlgError:
        x = np.full(rhs.shape, np.nan)
    if not np.all(np.isfinite(x)):
        x = np.linalg.lstsq(K, rhs, rcond=None)[0]
    lam = x[n:] if U is None else U @ x[n:]
    return x[:n], lam


def project(
    ref: ReferenceModel, q: np.ndarray, qd: np.ndarray, t: float, tol: float = 1e-14, max_iter: int = 50
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(q, qd) moved onto the constraints: q onto Phi(q, t) = 0 by Gauss-Newton with
    minimum-norm steps (until the step is below ``tol`` times the model's length scale),
    then qd onto Phi_q qd = nu by the minimum-norm correction. Returns the projected q and
    qd and the sizes (inf-norms) of the two corrections. ``ValueError`` if the positions
    do not converge."""
    q0 = np.array(q, dtype=float)
    q = q0.copy()
    scale = ref.length_scale
    for _ in range(max_iter):
        residual = ref.phi(q, t)
        if float(np.max(np.abs(residual), initial=0.0)) <= tol * scale:
            break
        dq = np.linalg.lstsq(ref.phi_q(q, t), -residual, rcond=None)[0]
        q = q + dq
        if float(np.max(np.abs(dq), initial=0.0)) <= tol * scale:
            break
    else:
        raise ValueError(f"at t = {t}: the positions did not reach the constraints in {max_iter} steps")
    J = ref.phi_q(q, t)
    dqd = np.linalg.lstsq(J, ref.nu(q, t) - J @ qd, rcond=None)[0]
    return (
        q,
        np.asarray(qd, dtype=float) + dqd,
        float(np.max(np.abs(q - q0), initial=0.0)),
        float(np.max(np.abs(dqd), initial=0.0)),
    )


def potential_energy(ref: ReferenceModel, q: np.ndarray) -> dict[str, float]:
    """The potential energy at q: "gravity" (-sum m g . r_c) and "springs" (linear and
    torsional springs, 1/2 k stretch^2)."""
    q = np.asarray(q, dtype=float)
    _, gravity = dynamics.energy(ref, q, np.zeros_like(q))
    springs = 0.0
    for load in ref.loads:
        pa, pb = ref._pose(load.a, q), ref._pose(load.b, q)
        if load.kind == "spring":
            assert load.u_a is not None and load.u_b is not None
            d = pb.r(load.u_b) - pa.r(load.u_a)
            springs += 0.5 * load.stiffness * (math.hypot(d[0], d[1]) - load.free_length) ** 2
        elif load.kind == "torsion_spring":
            springs += 0.5 * load.stiffness * (pb.theta - pa.theta - load.free_angle) ** 2
    return {"gravity": float(gravity), "springs": float(springs)}


def _reference(description: Any) -> ReferenceModel:
    from .model import ReferenceModel

    return description if isinstance(description, ReferenceModel) else ReferenceModel(description)


def simulate(
    description: Any,
    times: Any,
    q0: Any = None,
    qd0: Any = None,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-10,
    project_outputs: bool = True,
    singular_tol: float = 0.0,
) -> dict[str, Any]:
    """Integrates the equations of motion of a description (a ``Mechanism``, its dict or
    a ``ReferenceModel``) with ``scipy.integrate.solve_ivp`` (``method``: "DOP853",
    "Radau", ...; ``rtol``, ``atol`` its tolerances on (q, qd)) and returns the state at
    every time of ``times`` (increasing, the first the start).

    ``q0`` (default: the description's starting configuration) and ``qd0`` (default: at
    rest), in the reference's column order, are projected onto the constraints first.
    With ``project_outputs``, the integration stops at every output time and goes on
    from the state projected there; without, it runs in one piece and only measures the
    drift. ``singular_tol`` cuts the nearly dependent rows near singular configurations
    (``accelerations``); 1e-6 to 1e-5 carries the N-four-bar through its crossings, 0
    (the default) solves the full system everywhere.

    Returns "times", "q", "qd", "qdd" (n_times x n_coords), "lambda" (n_times x n_rows),
    "kinetic", "gravity", "springs" (energies, n_times), "drift_position" (inf-norm of
    Phi before projection) and "drift_velocity" (of Phi_q qd - nu), "nfev" (right-hand
    side evaluations), "initial_correction" (the inf-norms of the corrections made to q0
    and qd0), "columns" and "wall" (seconds)."""
    # scipy is an optional dependency of the package; only the integration needs it
    from scipy.integrate import solve_ivp

    ref = _reference(description)
    times = np.asarray(times, dtype=float).ravel()
    if times.size < 1 or np.any(np.diff(times) <= 0.0) or not np.all(np.isfinite(times)):
        raise ValueError("times must be finite and strictly increasing")
    n, m = ref.n_coords, ref.n_rows
    q = ref.q_start() if q0 is None else np.array(q0, dtype=float)
    qd = np.zeros(n) if qd0 is None else np.array(qd0, dtype=float)
    if q.shape != (n,) or qd.shape != (n,):
        raise ValueError(f"q0 and qd0 must have {n} entries (columns {ref.columns})")
    start = _time.perf_counter()
    q, qd, dq0, dqd0 = project(ref, q, qd, float(times[0]))
    out: dict[str, Any] = {
        "times": times.copy(),
        "q": np.zeros((times.size, n)),
        "qd": np.zeros((times.size, n)),
        "qdd": np.zeros((times.size, n)),
        "lambda": np.zeros((times.size, m)),
        "kinetic": np.zeros(times.size),
        "gravity": np.zeros(times.size),
        "springs": np.zeros(times.size),
        "drift_position": np.zeros(times.size),
        "drift_velocity": np.zeros(times.size),
        "initial_correction": (dq0, dqd0),
        "columns": list(ref.columns),
    }

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([y[n:], accelerations(ref, y[:n], y[n:], t, singular_tol)[0]])

    def record(k: int, q: np.ndarray, qd: np.ndarray) -> None:
        t = float(times[k])
        out["drift_position"][k] = float(np.max(np.abs(ref.phi(q, t)), initial=0.0))
        out["drift_velocity"][k] = float(np.max(np.abs(ref.phi_q(q, t) @ qd - ref.nu(q, t)), initial=0.0))
        if project_outputs:
            q, qd, _, _ = project(ref, q, qd, t)
        qdd, lam = accelerations(ref, q, qd, t)
        out["q"][k], out["qd"][k], out["qdd"][k], out["lambda"][k] = q, qd, qdd, lam
        out["kinetic"][k] = 0.5 * float(qd @ dynamics.mass_matrix(ref, q) @ qd)
        potential = potential_energy(ref, q)
        out["gravity"][k], out["springs"][k] = potential["gravity"], potential["springs"]

    nfev = 0
    record(0, q, qd)
    if project_outputs:
        for k in range(1, times.size):
            y = np.concatenate([out["q"][k - 1], out["qd"][k - 1]])
            sol = solve_ivp(rhs, (times[k - 1], times[k]), y, method=method, rtol=rtol, atol=atol)
            nfev += sol.nfev
            if not sol.success:
                raise ValueError(f"integration failed from t = {times[k - 1]} to {times[k]}: {sol.message}")
            record(k, sol.y[:n, -1], sol.y[n:, -1])
    elif times.size > 1:
        y = np.concatenate([q, qd])
        sol = solve_ivp(rhs, (times[0], times[-1]), y, method=method, rtol=rtol, atol=atol, t_eval=times)
        nfev += sol.nfev
        if not sol.success:
            raise ValueError(f"integration failed: {sol.message}")
        for k in range(1, times.size):
            record(k, sol.y[:n, k], sol.y[n:, k])
    out["nfev"] = nfev
    out["wall"] = _time.perf_counter() - start
    return out
