"""ReferenceModel: the whole formulation assembled into dense matrices and solved with
``np.linalg.solve``. Slow and plain on purpose; it exists to check the engine."""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np

from . import curves, dynamics
from .formulation import GROUND, Constraint, CurveJoint, Own, Pose, build_constraints

__all__ = ["ReferenceModel", "ConvergenceError"]


class ConvergenceError(RuntimeError):
    """A solve failed at ``time`` (sweep step ``step``); ``partial`` holds the good steps."""

    def __init__(self, message: str, time: float, step: int | None = None, partial: dict | None = None):
        super().__init__(message)
        self.time = time
        self.step = step
        self.partial = partial


def _description(description: Any) -> dict[str, Any]:
    if hasattr(description, "to_dict"):
        description = description.to_dict()
    if not isinstance(description, dict):
        raise TypeError(f"expected a description dict or a Mechanism, got {type(description).__name__}")
    return _in_radians(copy.deepcopy(description))


def _in_radians(desc: dict[str, Any]) -> dict[str, Any]:
    """The description with its angles in radians, if its units say degrees (lengths
    are used as written). Written here again, independently of the engine's."""
    angle = (desc.get("units") or {}).get("angle", "rad")
    if angle == "rad":
        return desc
    if angle != "deg":
        raise ValueError(f"units.angle must be 'rad' or 'deg', not {angle!r}")
    k = math.pi / 180.0
    for b in desc.get("bodies", []):
        b["theta"] = k * float(b["theta"])
    for d in desc.get("drivers", []):
        if d["type"] in ("angle", "relative_angle"):
            d["law"] = {"type": "scaled", "factor": k, "law": d["law"]}
    for j in desc.get("joints", []):
        if j["type"] == "fixed_orientation" and j.get("angle") is not None:
            j["angle"] = k * float(j["angle"])
        elif j["type"] == "linear_coupling":
            for side in ("coefficients_a", "coefficients_b"):
                c = j.get(side) or {}
                if "theta" in c:
                    c["theta"] = float(c["theta"]) / k  # per degree -> per radian
        elif j["type"] in ("pin_in_slot", "cam_follower") and j["curve"].get("type") == "polar":
            j["curve"]["angles"] = [k * float(a) for a in j["curve"]["angles"]]
    revolutes = {j["name"] for j in desc.get("joints", []) if j["type"] == "revolute"}
    for ld in desc.get("loads", []):
        if ld["type"] == "joint_force" and ld.get("of_joint") in revolutes:
            ld["of_scale"] = 1.0 / k  # the law of another joint's angle, in degrees
        if ld["type"] in ("joint_force", "motor", "friction") and ld.get("joint") in revolutes:
            # x in degrees = x / k: a law of it, a speed, a coefficient per degree/s
            if ld["type"] == "joint_force":
                ld["scale"] = 1.0 / k
            elif ld["type"] == "motor":
                ld["no_load_speed"] = k * float(ld["no_load_speed"])
            else:
                ld["viscous"] = float(ld.get("viscous", 0.0)) / k
                if ld.get("smoothing") is not None:
                    ld["smoothing"] = k * float(ld["smoothing"])
        if ld["type"] == "torsion_spring":
            ld["free_angle"] = k * float(ld["free_angle"])
            ld["stiffness"] = float(ld["stiffness"]) / k
            ld["damping"] = float(ld.get("damping", 0.0)) / k
    desc["units"] = {**desc["units"], "angle": "rad"}
    return desc


class ReferenceModel:
    """A mechanism description solved the textbook way (dense, NumPy only).

    ``columns`` names the coordinates ("<body>.x", "<body>.y", "<body>.theta", bodies in
    description order, then "<joint>.s" for every joint with its own coordinate, a curve
    parameter); ``row_labels`` names the rows of Phi (joints, then drivers).
    """

    def __init__(self, description: Any, tol: float = 1e-12, max_iter: int = 50) -> None:
        self.description = _description(description)
        self.tol = float(tol)
        self.max_iter = int(max_iter)

        bodies = self.description.get("bodies", [])
        self.body_names: list[str] = []
        self._start: dict[str, tuple[float, float, float]] = {GROUND: (0.0, 0.0, 0.0)}
        for b in bodies:
            name = b["name"]
            if name == GROUND:
                raise ValueError("a body cannot be named 'ground': the ground is the fixed frame")
            if name in self._start:
                raise ValueError(f"body {name!r} is described twice")
            self._start[name] = (float(b["x"]), float(b["y"]), float(b["theta"]))
            self.body_names.append(name)
        # first column of each body (x, y, theta follow)
        self._col = {name: 3 * i for i, name in enumerate(self.body_names)}
        self.columns: list[str] = [f"{n}.{c}" for n in self.body_names for c in ("x", "y", "theta")]

        self.constraints: list[Constraint] = build_constraints(self.description, self._start)
        # own coordinates (curve parameters) follow the bodies', in joint order
        self._own_col: dict[str, int] = {}
        for c in self.constraints:
            if c.n_own:
                self._own_col[c.name] = len(self.columns)
                self.columns.append(f"{c.name}.s")
        self.n_coords = len(self.columns)
        self._row: list[int] = []  # first row of each constraint
        self.row_labels: list[str] = []
        length_rows: list[bool] = []
        for c in self.constraints:
            self._row.append(len(self.row_labels))
            self.row_labels += c.row_labels
            length_rows += c.length_rows
        self.n_rows = len(self.row_labels)

        # named points: body and local vector
        self._points: dict[str, tuple[str, np.ndarray]] = {}
        for p in self.description.get("points", []):
            if p["body"] not in self._start:
                raise ValueError(f"point {p['name']!r} is on unknown body {p['body']!r}")
            self._points[p["name"]] = (p["body"], self._local(p["body"], p["at"]))

        # scales for the convergence test: lengths divided by L, angles as they are
        self.length_scale = self._characteristic_length()
        self._row_scale = np.array([1.0 / self.length_scale if is_len else 1.0 for is_len in length_rows])
        self._col_scale = np.concatenate(
            [
                np.tile([1.0 / self.length_scale, 1.0 / self.length_scale, 1.0], len(self.body_names)),
                np.ones(len(self._own_col)),  # curve parameters are angle-like
            ]
        )

        # inverse dynamics: mass properties, gravity, loads (``dynamics``)
        self.mass_properties = dynamics.build_mass_properties(self.description, self._start)
        gravity = self.description.get("gravity", [0.0, 0.0])
        if not dynamics.is_finite(gravity, 2):
            raise ValueError(f"gravity {gravity} is not a finite 2-vector")
        self.gravity = np.asarray(gravity, dtype=float)
        self.loads = dynamics.build_loads(self.description, self._start, self.length_scale, self.constraints)

    # -- setup helpers ----------------------------------------------------------------------
    def _local(self, body: str, p: Any) -> np.ndarray:
        x0, y0, th0 = self._start[body]
        c, s = math.cos(th0), math.sin(th0)
        dx, dy = float(p[0]) - x0, float(p[1]) - y0
        return np.array([c * dx + s * dy, -s * dx + c * dy])

    def _characteristic_length(self) -> float:
        """L: the diagonal of the bounding box of the described world points and body
        origins (within sqrt(2) of the largest distance between two of them); 1 if they
        all coincide."""
        pts = [(x, y) for name, (x, y, _) in self._start.items() if name != GROUND]
        for j in self.description.get("joints", []):
            for key in ("at", "at_a", "at_b", "through", "centre", "centre_a", "centre_b"):
                if j.get(key) is not None:
                    pts.append(tuple(j[key]))
        for d in self.description.get("drivers", []):
            for key in ("at_a", "at_b", "at"):
                if key in d:
                    pts.append(tuple(d[key]))
        for p in self.description.get("points", []):
            pts.append(tuple(p["at"]))
        for j in self.description.get("joints", []):
            if isinstance(j.get("curve"), dict):
                pts += curves.world_points(j["curve"])
        xy = np.array(pts, dtype=float).reshape(-1, 2)
        diagonal = float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0)))) if len(xy) else 0.0
        return diagonal if diagonal > 0.0 else 1.0

    def _pose(self, name: str, q: np.ndarray, qd: np.ndarray | None = None) -> Pose:
        if name == GROUND:
            return Pose(np.zeros(2), 0.0, np.zeros(2), 0.0)
        i = self._col[name]
        rates = (np.zeros(2), 0.0) if qd is None else (np.array(qd[i : i + 2], dtype=float), float(qd[i + 2]))
        return Pose(np.array(q[i : i + 2], dtype=float), float(q[i + 2]), rates[0], rates[1])

    def _own(self, c: Constraint, q: np.ndarray, qd: np.ndarray | None = None) -> dict[str, Own]:
        """The keyword a constraint with its own coordinate takes: own=Own(s, sd) read from
        q and qd; nothing for the others."""
        if not c.n_own:
            return {}
        k = self._own_col[c.name]
        return {"own": Own(float(q[k]), 0.0 if qd is None else float(qd[k]))}

    # -- the formulation ----------------------------------------------------------------------
    def q_start(self) -> np.ndarray:
        """The starting configuration of the description (n_coords): the bodies' starting
        poses, then each own coordinate where the described configuration fits best."""
        q = [v for name in self.body_names for v in self._start[name]]
        for c in self.constraints:
            if isinstance(c, CurveJoint):
                (xa, ya, tha), (xb, yb, thb) = self._start[c.a], self._start[c.b]
                pa = Pose(np.array([xa, ya]), tha, np.zeros(2), 0.0)
                pb = Pose(np.array([xb, yb]), thb, np.zeros(2), 0.0)
                q.append(c.own_start(pa, pb))
        return np.array(q, dtype=float)

    def phi(self, q: np.ndarray, t: float) -> np.ndarray:
        """Phi(q, t) (n_rows)."""
        out = np.zeros(self.n_rows)
        for c, r in zip(self.constraints, self._row):
            out[r : r + c.n_rows] = c.phi(self._pose(c.a, q), self._pose(c.b, q), t, **self._own(c, q))
        return out

    def phi_q(self, q: np.ndarray, t: float) -> np.ndarray:
        """Phi_q (n_rows x n_coords); a joint's own coordinate has a column of its own."""
        J = np.zeros((self.n_rows, self.n_coords))
        for c, r in zip(self.constraints, self._row):
            pa, pb, own = self._pose(c.a, q), self._pose(c.b, q), self._own(c, q)
            jac_a, jac_b = c.jacobian(pa, pb, t, **own)
            for name, block in ((c.a, jac_a), (c.b, jac_b)):
                if name != GROUND:
                    col = self._col[name]
                    J[r : r + c.n_rows, col : col + 3] += block
            if isinstance(c, CurveJoint):
                J[r : r + c.n_rows, self._own_col[c.name]] = c.jacobian_own(pa, pb, t, **own)
        return J

    def nu(self, q: np.ndarray, t: float) -> np.ndarray:
        """nu = -Phi_t (n_rows): f'(t) on driver rows, 0 on joint rows."""
        out = np.zeros(self.n_rows)
        for c, r in zip(self.constraints, self._row):
            out[r : r + c.n_rows] = c.nu(t)
        return out

    def gamma(self, q: np.ndarray, qd: np.ndarray, t: float) -> np.ndarray:
        """gamma = -(Phi_q qd)_q qd - 2 Phi_qt qd - Phi_tt (n_rows)."""
        out = np.zeros(self.n_rows)
        for c, r in zip(self.constraints, self._row):
            pa, pb = self._pose(c.a, q, qd), self._pose(c.b, q, qd)
            out[r : r + c.n_rows] = c.gamma(pa, pb, t, **self._own(c, q, qd))
        return out

    def singular_ratio(self, q: np.ndarray, t: float) -> float:
        """Smallest over largest singular value of Phi_q (0 when singular)."""
        s = np.linalg.svd(self.phi_q(q, t), compute_uv=False)
        return float(s[-1] / s[0]) if s.size and s[0] > 0 else 0.0

    # -- solves -----------------------------------------------------------------------------------
    def _linear_solve(self, J: np.ndarray, rhs: np.ndarray, t: float) -> np.ndarray:
        if J.shape[0] < J.shape[1]:
            raise ConvergenceError(
                f"at t = {t}: {J.shape[1]} coordinates but only {J.shape[0]} rows: "
                f"{J.shape[1] - J.shape[0]} degree(s) of freedom are not driven",
                t,
            )
        try:
            if J.shape[0] == J.shape[1]:
                x = np.linalg.solve(J, rhs)
            else:
                # more rows than coordinates (redundant joints): least squares
                x = np.linalg.lstsq(J, rhs, rcond=None)[0]
        except np.linalg.LinAlgError:
            raise ConvergenceError(f"at t = {t}: the Jacobian Phi_q is singular", t) from None
        if not np.all(np.isfinite(x)):
            raise ConvergenceError(f"at t = {t}: the Jacobian Phi_q is singular", t)
        return x

    def solve_position(self, t: float, q_guess: np.ndarray | None = None) -> tuple[np.ndarray, int]:
        """Newton-Raphson on Phi(q, t) = 0 from ``q_guess`` (default: the starting
        configuration). Returns q and the number of Newton steps taken. Converged when the
        scaled residual and the scaled step are both <= tol (the last step is applied)."""
        q = self.q_start() if q_guess is None else np.array(q_guess, dtype=float)
        residual = math.inf
        for iteration in range(1, self.max_iter + 1):
            r = self.phi(q, t)
            dq = self._linear_solve(self.phi_q(q, t), -r, t)
            q = q + dq
            residual = float(np.max(np.abs(r * self._row_scale), initial=0.0))
            step = float(np.max(np.abs(dq * self._col_scale), initial=0.0))
            if residual <= self.tol and step <= self.tol:
                return q, iteration
            if not (math.isfinite(residual) and math.isfinite(step)):
                break
        raise ConvergenceError(
            f"position analysis did not converge at t = {t} in {self.max_iter} iterations "
            f"(scaled residual {residual:.3e})",
            t,
        )

    def solve(self, t: float, q_guess: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration at time t: (q, qd, qdd)."""
        q, _ = self.solve_position(t, q_guess)
        J = self.phi_q(q, t)
        qd = self._linear_solve(J, self.nu(q, t), t)
        qdd = self._linear_solve(J, self.gamma(q, qd, t), t)
        return q, qd, qdd

    def sweep(self, times: Any) -> dict[str, np.ndarray]:
        """Solve at every time of ``times`` (in the given order). The first step starts from
        the starting configuration, each later one from q + h qd + h^2/2 qdd of the previous.

        Returns "times", "q", "qd", "qdd" (n_steps x n_coords) and "iterations" (n_steps).
        On failure raises ``ConvergenceError`` with the good steps in ``partial``.
        """
        times = np.asarray(times, dtype=float).ravel()
        n = times.size
        out = {
            "times": times.copy(),
            "q": np.zeros((n, self.n_coords)),
            "qd": np.zeros((n, self.n_coords)),
            "qdd": np.zeros((n, self.n_coords)),
            "iterations": np.zeros(n, dtype=int),
        }
        guess = self.q_start()
        for k, t in enumerate(times):
            if k > 0:
                h = t - times[k - 1]
                guess = out["q"][k - 1] + h * out["qd"][k - 1] + 0.5 * h * h * out["qdd"][k - 1]
            try:
                q, iterations = self.solve_position(t, guess)
                J = self.phi_q(q, t)
                qd = self._linear_solve(J, self.nu(q, t), t)
                qdd = self._linear_solve(J, self.gamma(q, qd, t), t)
            except (ConvergenceError, ValueError, ZeroDivisionError) as err:
                partial = {key: value[:k].copy() for key, value in out.items()}
                raise ConvergenceError(f"sweep step {k} (t = {t}): {err}", float(t), k, partial) from err
            out["q"][k], out["qd"][k], out["qdd"][k], out["iterations"][k] = q, qd, qdd, iterations
        return out

    # -- inverse dynamics (see ``dynamics``) -----------------------------------------------------
    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """M(q) (n_coords x n_coords)."""
        return dynamics.mass_matrix(self, q)

    def inverse_dynamics(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, t: float) -> dict[str, Any]:
        """lambda from Phi_q^T lambda = Q - M qdd at one state, with the reactions
        (n_constraints x 4: Fx, Fy on side b, torque about the anchor on b, power), Q, M,
        the drivers' efforts and the loads' power (``dynamics.inverse_dynamics``)."""
        return dynamics.inverse_dynamics(self, q, qd, qdd, t)

    def sweep_forces(self, times: Any) -> dict[str, Any]:
        """``sweep`` plus the inverse dynamics at every step ("lambda", "reactions",
        "efforts", "load_power")."""
        return dynamics.sweep_forces(self, times)

    def statics(self, t: float, q_guess: np.ndarray | None = None) -> dict[str, Any]:
        """The inverse dynamics holding the configuration at time t at rest (qd = qdd = 0)."""
        q, _ = self.solve_position(t, q_guess)
        zero = np.zeros(self.n_coords)
        out = dynamics.inverse_dynamics(self, q, zero, zero, t)
        out["q"] = q
        return out

    def anchor(self, name: str, q: np.ndarray) -> np.ndarray:
        """World position (2) of the point on side b about which constraint ``name``'s
        reaction torque is reported."""
        for c in self.constraints:
            if c.name == name:
                return self._pose(c.b, q).r(dynamics.anchor_b(c))
        raise KeyError(f"no joint or driver named {name!r}")

    def energy(self, q: np.ndarray, qd: np.ndarray) -> tuple[float, float]:
        """(kinetic, gravitational potential) energy at one state."""
        return dynamics.energy(self, q, qd)

    # -- named points -----------------------------------------------------------------------------
    def point(
        self, name: str, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World position, velocity and acceleration of the named point.

        q, qd, qdd are one state (n_coords) -> three arrays (2), or a sweep
        (n_steps x n_coords) -> three arrays (n_steps x 2).
        r = R + A u, v = Rd + A' u thd, a = Rdd + A' u thdd - A u thd^2 (A' = dA/dtheta).
        """
        if name not in self._points:
            raise KeyError(f"no point named {name!r} (points: {sorted(self._points)})")
        body, u = self._points[name]
        q, qd, qdd = (np.asarray(x, dtype=float) for x in (q, qd, qdd))
        single = q.ndim == 1
        q, qd, qdd = (np.atleast_2d(x) for x in (q, qd, qdd))
        n = q.shape[0]
        if body == GROUND:
            r = np.tile(u, (n, 1))
            v = np.zeros((n, 2))
            a = np.zeros((n, 2))
        else:
            i = self._col[body]
            th, thd, thdd = q[:, i + 2], qd[:, i + 2], qdd[:, i + 2]
            c, s = np.cos(th), np.sin(th)
            Au = np.column_stack([c * u[0] - s * u[1], s * u[0] + c * u[1]])  # A u
            Bu = np.column_stack([-Au[:, 1], Au[:, 0]])  # dA/dtheta u
            r = q[:, i : i + 2] + Au
            v = qd[:, i : i + 2] + Bu * thd[:, None]
            a = qdd[:, i : i + 2] + Bu * thdd[:, None] - Au * (thd**2)[:, None]
        if single:
            return r[0], v[0], a[0]
        return r, v, a
