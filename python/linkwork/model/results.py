"""Results of a sweep (`Results`) or of one solve (`State`) as NumPy arrays.

Array sizes: q, qd, qdd are (n_steps, n_coords), columns named by ``columns``
("<body>.x", "<body>.y", "<body>.theta"); the diagnostics are (n_steps,).
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _args
from .events import Event

if TYPE_CHECKING:
    from linkwork import Model

__all__ = ["Results", "State", "Statics", "BodyMotion", "PointMotion", "Reaction", "Energy"]


@dataclass(frozen=True)
class Kept:
    """What a sweep keeps: model columns (indices, in order), body points (body index, -1
    for the ground; u_x, u_y) and the points' names."""

    coords: list[int]
    points: list[tuple[int, float, float]]
    point_names: list[str]


@dataclass(frozen=True)
class BodyMotion:
    """One body's coordinates and their derivatives, each (n_steps,) (or scalars); the
    derivatives are None where the sweep did not solve them (``derivatives=0`` or 1)."""

    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    xd: np.ndarray | None
    yd: np.ndarray | None
    thetad: np.ndarray | None
    xdd: np.ndarray | None
    ydd: np.ndarray | None
    thetadd: np.ndarray | None


@dataclass(frozen=True)
class PointMotion:
    """A body point's world position, velocity and acceleration, each (n_steps, 2) (or
    (2,)); velocity and acceleration are None where the sweep did not solve them."""

    position: np.ndarray
    velocity: np.ndarray | None
    acceleration: np.ndarray | None


@dataclass(frozen=True)
class Reaction:
    """What a joint or driver transmits to its side b (``body_b``), each (n_steps, ...):
    ``force`` (n, 2) in world axes and ``force_local`` in body b's frame; ``torque`` about
    ``point``, the joint's anchor on b (n, 2) (0 for a pin); ``power`` delivered (0 for a
    joint). The force on side a is the opposite."""

    force: np.ndarray
    force_local: np.ndarray
    torque: np.ndarray
    point: np.ndarray
    power: np.ndarray


@dataclass(frozen=True)
class Energy:
    """Energy bookkeeping, each (n_steps,): ``kinetic`` and ``gravity`` (potential)
    energy from the kinematics and the mass properties alone; ``driver_power`` (sum over
    drivers of effort x rate) and ``load_power`` (springs, dampers, forces, torques) from
    the inverse dynamics; ``kinetic_rate`` = dT/dt from the accelerations; ``balance`` =
    driver_power + load_power - gravity_rate - kinetic_rate, zero up to rounding."""

    kinetic: np.ndarray
    gravity: np.ndarray
    kinetic_rate: np.ndarray
    gravity_rate: np.ndarray
    driver_power: np.ndarray
    load_power: np.ndarray
    balance: np.ndarray


class _Kinematics:
    """Shared accessors over (q, qd, qdd), for many steps or for one."""

    model: Model
    q: np.ndarray
    qd: np.ndarray | None
    qdd: np.ndarray | None
    # model column -> column of q, where a sweep kept only some (``outputs``)
    _kept: dict[int, int] | None = None
    #: the points a sweep kept (``outputs``), by name
    points: dict[str, PointMotion] = {}
    _kept_points: dict[tuple[int, float, float], PointMotion] = {}

    @property
    def columns(self) -> list[str]:
        return self.model.columns

    def _col(self, j: int) -> int:
        """The column of q holding the model's column j."""
        if self._kept is None:
            return j
        k = self._kept.get(j)
        if k is None:
            raise KeyError(
                f"{self.model.columns[j]} was not kept by this sweep: it kept "
                f"{', '.join(self.columns) or 'no'} coordinates (sweep(..., outputs=[...]) says what to keep)"
            )
        return k

    def _all_columns(self, what: str) -> None:
        """Refuses ``what`` where the sweep kept only some coordinates."""
        if self._kept is not None and len(self._kept) < len(self.model.columns):
            raise ValueError(
                f"{what} needs every coordinate, and this sweep kept only some (outputs=...): "
                "sweep without outputs for it"
            )

    def _body_index(self, body: str) -> int:
        try:
            return self.model.body_names.index(body)
        except ValueError:
            raise KeyError(f"no body named {body!r}; bodies: {', '.join(self.model.body_names)}") from None

    def body(self, name: str) -> BodyMotion:
        """x, y, theta of a body and their first and second derivatives."""
        j = 3 * self._body_index(name)
        cs = [self._col(j), self._col(j + 1), self._col(j + 2)]

        def cols(a: np.ndarray | None) -> list[np.ndarray | None]:
            return [None] * 3 if a is None else [a[..., c] for c in cs]

        x, y, th = cols(self.q)
        assert x is not None and y is not None and th is not None
        return BodyMotion(x, y, th, *cols(self.qd), *cols(self.qdd))

    def point(self, name: str) -> PointMotion:
        """Kinematics of a named point (``Mechanism.point``), or of a point, joint or
        driver a sweep kept (``outputs``)."""
        if name in self.points:
            return self.points[name]
        for pname, body, ux, uy in self.model._core.points:
            if pname == name:
                return self._point(body, (ux, uy))
        names = [p[0] for p in self.model._core.points]
        raise KeyError(f"no point named {name!r}; points: {', '.join(names) or 'none'}")

    def point_at(self, body: str, local: Sequence[float]) -> PointMotion:
        """Kinematics of the point with body-frame coordinates ``local`` of ``body`` (the
        ground's points stand still)."""
        index = -1 if body == "ground" else self._body_index(body)
        return self._point(index, (float(local[0]), float(local[1])))

    def mechanical_advantage(self, input_body: str, output_body: str) -> np.ndarray:
        """Ideal mechanical advantage, output torque over input torque, by virtual work:
        T_out / T_in = w_in / w_out (a number per step, or a scalar). Infinite where the
        output stops (a toggle position), 0 where the input does."""
        if self.qd is None:
            raise ValueError("the mechanical advantage needs velocities (derivatives >= 1)")
        w_in = self.qd[..., self._col(3 * self._body_index(input_body) + 2)]
        w_out = self.qd[..., self._col(3 * self._body_index(output_body) + 2)]
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(w_in / w_out)

    def transmission_angle(self, linkage: str | None = None) -> np.ndarray:
        """The transmission angle (rad) of a four-bar loop or slider-crank of the model
        (by name, as `Model.linkages` gives it; default: the only one): four-bar, the
        angle between coupler and rocker in [0, pi]; slider-crank, between the rod and
        the slide's normal in [0, pi/2]. Best at pi/2; near 0 (or pi) the output locks."""
        self._all_columns("the transmission angle")
        # the linkages as found at the first state (their geometry does not change)
        t0 = float(np.ravel(getattr(self, "times", getattr(self, "t", 0.0)))[0])
        found = self.model.linkages(t=t0, q_guess=np.reshape(self.q, (-1, self.q.shape[-1]))[0])
        if linkage is None:
            if len(found) != 1:
                names = [f.name for f in found]
                raise ValueError(f"the model has {len(found)} linkages ({names}); name one")
            chosen = found[0]
        else:
            matches = [f for f in found if f.name == linkage]
            if not matches:
                raise ValueError(f"no linkage {linkage!r}; the model has {[f.name for f in found]}")
            chosen = matches[0]
        return chosen.transmission_angle_of(self)

    def _constraint(self, name: str) -> tuple[int, tuple[str, str, str, int, int]]:
        for k, c in enumerate(self.model.constraints):
            if c[0] == name:
                return k, c
        names = ", ".join(c[0] for c in self.model.constraints)
        raise KeyError(f"no joint or driver named {name!r}; there are: {names}")

    def _reaction(self, name: str, table: np.ndarray) -> Reaction:
        """A Reaction from a (..., n_constraints, 4) table of Fx, Fy, torque, power."""
        k, _ = self._constraint(name)
        _, _, _, body_b, ux, uy = self.model._core.anchors[k]
        r = table[..., k, :]
        point = self._point(body_b, (ux, uy)).position
        if body_b >= 0:
            th = self.q[..., self._col(3 * body_b + 2)]
            c, s = np.cos(th), np.sin(th)
        else:
            c, s = np.ones_like(r[..., 0]), np.zeros_like(r[..., 0])
        local = np.stack([c * r[..., 0] + s * r[..., 1], -s * r[..., 0] + c * r[..., 1]], axis=-1)
        return Reaction(r[..., :2], local, r[..., 2], point, r[..., 3])

    def _point(self, body: int, u: tuple[float, float]) -> PointMotion:
        kept = self._kept_points.get((body, float(u[0]), float(u[1])))
        if kept is not None:
            return kept
        if body < 0:  # a point of the ground
            shape = self.q.shape[:-1] + (2,)
            return PointMotion(np.broadcast_to(np.asarray(u), shape).copy(), np.zeros(shape), np.zeros(shape))
        x, y, t = self._col(3 * body), self._col(3 * body + 1), self._col(3 * body + 2)
        th = self.q[..., t]
        c, s = np.cos(th), np.sin(th)
        au = np.stack([c * u[0] - s * u[1], s * u[0] + c * u[1]], axis=-1)  # A u
        bu = np.stack([-au[..., 1], au[..., 0]], axis=-1)  # B u = A u turned +90 deg
        r = self.q[..., [x, y]] + au
        if self.qd is None:
            return PointMotion(r, None, None)
        w = self.qd[..., t]
        v = self.qd[..., [x, y]] + bu * w[..., None]
        if self.qdd is None:
            return PointMotion(r, v, None)
        al = self.qdd[..., t]
        a = self.qdd[..., [x, y]] + bu * al[..., None] - au * (w * w)[..., None]
        return PointMotion(r, v, a)


class State(_Kinematics):
    """Position, velocity and acceleration at one time (1-D arrays of n_coords)."""

    def __init__(
        self, model: Model, t: float, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
        iterations: int, residual: float, pivot_ratio: float,
    ) -> None:  # fmt: skip
        self.model, self.t, self.q, self.qd, self.qdd = model, t, q, qd, qdd
        self.iterations, self.residual, self.pivot_ratio = iterations, residual, pivot_ratio
        #: singular configurations crossed on the way from the drawing to ``t`` (`Model.solve`)
        self.events: list[Event] = []

    def __repr__(self) -> str:
        vals = ", ".join(f"{c}={v:.6g}" for c, v in zip(self.columns, self.q))
        return f"<State t={self.t:g}: {vals}>"


class Statics(_Kinematics):
    """Efforts and reactions holding a configuration at rest (``Model.statics``)."""

    def __init__(self, model: Model, t: float, q: np.ndarray, lam: np.ndarray, reactions: np.ndarray) -> None:
        self.model, self.t, self.q = model, t, q
        self.qd = np.zeros_like(q)
        self.qdd = np.zeros_like(q)
        self.multipliers, self.reactions = lam, reactions

    def effort(self, driver: str) -> float:
        """The torque or force the driver must supply to hold the configuration."""
        _, (_, role, _, _, row0) = self._constraint(driver)
        if role != "driver":
            raise KeyError(f"{driver!r} is a joint, not a driver")
        return float(-self.multipliers[row0])

    def reaction(self, name: str) -> Reaction:
        """What joint ``name`` transmits to its side b (arrays of one state)."""
        return self._reaction(name, self.reactions)

    def mechanical_advantage(self, input_body: str, output_body: str) -> np.ndarray:
        """Ideal mechanical advantage T_out / T_in = w_in / w_out at this configuration,
        from the velocities the drivers' rates give at time t."""
        return self.model.solve(self.t, q_guess=self.q).mechanical_advantage(input_body, output_body)


class Results(_Kinematics):
    """A sweep's results: q, qd, qdd (n_steps, n_coords) and per-step diagnostics.

    Diagnostics, each (n_steps,): ``iterations`` (Newton iterations, each one
    factorization of Phi_q), ``residual`` (inf-norm of the residual at the last Newton
    evaluation, length rows divided by the model's length scale), ``pivot_ratio``
    (smallest over largest LU pivot of the scaled Phi_q: near 0 means near singular; at
    the start, Phi_q factored at the solved configuration with its pivots chosen there; on
    steps the closed forms solved, the groups' closeness, docs/analysis.md).
    """

    #: True for a `Simulation` (forward dynamics): its views add its energy and drift
    simulated = False

    def __init__(self, model: Model, raw: dict[str, Any], kept: Kept | None = None) -> None:
        self.model = model
        if kept is not None:
            self._kept = {j: k for k, j in enumerate(kept.coords)}
            self._columns = [model.columns[j] for j in kept.coords]
            rows = [raw.get(k) for k in ("points", "points_d", "points_dd")]
            self.points = {
                name: PointMotion(*(None if a is None else a[:, i] for a in rows))
                for i, name in enumerate(kept.point_names)
            }
            self._kept_points = {p: self.points[n] for p, n in zip(kept.points, kept.point_names)}
        self.times: np.ndarray = raw["times"]
        self.q: np.ndarray = raw["q"]
        self.qd: np.ndarray | None = raw["qd"]  # None with derivatives=0
        self.qdd: np.ndarray | None = raw["qdd"]  # None with derivatives < 2
        self.iterations: np.ndarray = raw["iterations"]
        self.residual: np.ndarray = raw["residual"]
        self.pivot_ratio: np.ndarray = raw["pivot_ratio"]
        # sign of det Phi_q at each step: it flips where a singular configuration is crossed
        self.det_sign: np.ndarray = raw["det_sign"]
        #: the located events: limits of motion, bifurcations, locks, branch jumps
        self.events: list[Event] = [Event.from_raw(e) for e in raw["events"]]
        # inverse dynamics (sweep(..., forces=True)); None otherwise
        self.multipliers: np.ndarray | None = raw.get("lambda")  # (n_steps, n_rows)
        self.reactions: np.ndarray | None = raw.get("reactions")  # (n_steps, n_constraints, 4)
        self.load_power: np.ndarray | None = raw.get("load_power")  # (n_steps,)
        self._parts = {p: raw.get("lambda_" + p) for p in ("inertia", "gravity", "loads")}

    @property
    def columns(self) -> list[str]:
        """The coordinates kept: every one of the model's unless the sweep said (``outputs``)."""
        return getattr(self, "_columns", self.model.columns)

    def _forces(self) -> np.ndarray:
        if self.reactions is None:
            raise ValueError("no forces in these results: sweep(..., forces=True) computes them")
        return self.reactions

    def _driver_row(self, driver: str) -> int:
        _, (_, role, _, _, row0) = self._constraint(driver)
        if role != "driver":
            raise KeyError(f"{driver!r} is a joint, not a driver; its forces are reaction({driver!r})")
        return row0

    def effort(self, driver: str) -> np.ndarray:
        """The torque (angle drivers) or force (distance, coordinate, translation drivers)
        the driver exerts on its body, (n_steps,)."""
        self._forces()
        assert self.multipliers is not None
        return -self.multipliers[:, self._driver_row(driver)]

    def effort_parts(self, driver: str) -> dict[str, np.ndarray]:
        """The driver's effort split by cause: ``inertia`` (accelerating the masses),
        ``gravity`` and ``loads`` (springs, dampers, applied forces); they add up to
        ``effort``."""
        self._forces()
        row = self._driver_row(driver)
        return {p: -a[:, row] for p, a in self._parts.items() if a is not None}

    def power(self, driver: str) -> np.ndarray:
        """Power the driver delivers (effort times the rate of what it drives), (n_steps,)."""
        self._driver_row(driver)
        return self.reaction(driver).power

    def reaction(self, name: str) -> Reaction:
        """What joint (or driver) ``name`` transmits to its side b, over the sweep.

        For a joint in ``model.indeterminate`` (a model compiled with redundant rows set
        aside) this is one of infinitely many distributions of the load."""
        return self._reaction(name, self._forces())

    def energy(self) -> Energy:
        """Kinetic and gravitational energy from the kinematics, the power of drivers and
        loads from the inverse dynamics, and their balance (zero up to rounding)."""
        table = self._forces()
        self._all_columns("the energy balance")
        assert self.load_power is not None
        g = np.asarray(self.model._core.gravity)
        kinetic = np.zeros(self.n_steps)
        kinetic_rate = np.zeros(self.n_steps)
        gravity = np.zeros(self.n_steps)
        gravity_rate = np.zeros(self.n_steps)
        for i, (mass, inertia, cx, cy) in enumerate(self.model._core.inertias):
            c = self._point(i, (cx, cy))
            assert self.qd is not None and self.qdd is not None  # forces imply derivatives=2
            w, a = self.qd[:, self._col(3 * i + 2)], self.qdd[:, self._col(3 * i + 2)]
            kinetic += 0.5 * mass * np.sum(c.velocity**2, axis=1) + 0.5 * inertia * w * w
            kinetic_rate += mass * np.sum(c.velocity * c.acceleration, axis=1) + inertia * w * a
            gravity -= mass * c.position @ g
            gravity_rate -= mass * c.velocity @ g
        drivers = [k for k, c in enumerate(self.model.constraints) if c[1] == "driver"]
        driver_power = table[:, drivers, 3].sum(axis=1)
        balance = driver_power + self.load_power - gravity_rate - kinetic_rate
        return Energy(kinetic, gravity, kinetic_rate, gravity_rate, driver_power, self.load_power, balance)

    def effort_unit(self, driver: str) -> str:
        """The unit of a driver's effort: the model's torque unit for drivers of angles
        (N m, or mN mm for millimetres), its force unit for drivers of lengths (N or mN)."""
        kind = self._constraint(driver)[1][2]
        u = self.model.units
        return u["torque"] if "angle" in kind else u["force"]

    def forces_to_csv(self, path: str) -> None:
        """Writes t, every driver's effort (total and parts) and power, and every
        joint's reaction on its side b (Fx, Fy world; torque about its anchor)."""
        table = self._forces()
        header, cols = ["t [s]"], [self.times]
        u = self.model.units
        for k, (name, role, *_) in enumerate(self.model.constraints):
            if role == "driver":
                unit = self.effort_unit(name)
                header.append(f"{name}.effort [{unit}]")
                cols.append(self.effort(name))
                for part, v in self.effort_parts(name).items():
                    header.append(f"{name}.effort_{part} [{unit}]")
                    cols.append(v)
                header.append(f"{name}.power [{u['power']}]")
                cols.append(table[:, k, 3])
            else:
                header += [f"{name}.Fx [{u['force']}]", f"{name}.Fy [{u['force']}]"]
                header.append(f"{name}.torque [{u['torque']}]")
                cols += [table[:, k, 0], table[:, k, 1], table[:, k, 2]]
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            w.writerows(np.column_stack(cols).tolist())

    def forces_summary(self) -> str:
        """Peak efforts (with their parts) and peak joint forces, as text."""
        table = self._forces()
        lines = [
            f"  {'driver or joint':<22}{'peak':>13}  unit   (parts at the peak: inertia / gravity / loads)"
        ]
        for k, (name, role, *_) in enumerate(self.model.constraints):
            if role == "driver":
                e = self.effort(name)
                i = int(np.argmax(np.abs(e)))
                parts = " / ".join(f"{v[i]:.4g}" for v in self.effort_parts(name).values())
                unit = self.effort_unit(name)
                lines.append(f"  {name:<22}{e[i]:>13.6g}  {unit:<5}  ({parts}) at t = {self.times[i]:g}")
            else:
                f = np.hypot(table[:, k, 0], table[:, k, 1])
                unique = name not in self.model.indeterminate
                note = "largest force magnitude" if unique else "not unique: redundant rows"
                lines.append(f"  {name:<22}{f.max():>13.6g}  {self.model.units['force']:<5}  ({note})")
        e = self.energy()
        scale = max(float(np.abs(e.driver_power).max()), float(np.abs(e.kinetic_rate).max()), 1e-300)
        lines.append(f"  energy balance          {np.abs(e.balance).max() / scale:.1e} of the largest power")
        return "\n".join(lines)

    def plot_forces(self, path: str, every: int = 1) -> None:
        """A PNG of every driver's effort (split into inertia, gravity and loads) and of the
        magnitude of every joint's reaction force over the sweep (`linkwork.view.figures.plot_forces`)."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.figures import plot_forces

        plot_forces(self, path, every)

    @property
    def n_steps(self) -> int:
        return int(self.q.shape[0])

    def __len__(self) -> int:
        return self.n_steps

    def __repr__(self) -> str:
        return f"<Results of '{self.model.name}': {self.n_steps} steps x {len(self.columns)} coordinates>"

    def summary(self, angles: str = "rad") -> str:
        """A plain-text summary: range of every coordinate with its unit (the value's; the
        rate's and acceleration's are per s and per s^2), worst residual, Newton
        iterations, closest approach to a singular configuration. Angles in rad (the
        results' unit), or in deg with ``angles="deg"``."""
        _args.choice(angles, "angles", ("rad", "deg"))
        if self.n_steps == 0:
            return f"{self.model.name}: no steps"
        lines = [
            f"{self.model.name}: {self.n_steps} steps, t = {self.times[0]:g} .. {self.times[-1]:g} s",
            f"  {'coordinate':<22}{'min':>13}{'max':>13}{'max |rate|':>13}{'max |accel|':>13}  unit",
        ]

        def peak(a: np.ndarray | None, k: int) -> str:
            return f"{'-':>13}" if a is None else f"{np.abs(a[:, k]).max() * scale:>13.6g}"

        for k, c in enumerate(self.columns):
            unit = self.units(c)
            scale = 180.0 / np.pi if unit == "rad" and angles == "deg" else 1.0
            unit = angles if unit == "rad" else unit
            q = self.q[:, k] * scale
            lines.append(
                f"  {c:<22}{q.min():>13.6g}{q.max():>13.6g}{peak(self.qd, k)}{peak(self.qdd, k)}  {unit}"
            )
        scale, length = 1.0, self.model.units["length"]
        for name, p in self.points.items():
            for i, a in enumerate("xy"):
                motion = (p.position, p.velocity, p.acceleration)
                r, v, acc = (x if x is None else x[:, i : i + 1] for x in motion)
                assert r is not None
                c = f"{name}.{a}"
                lines.append(f"  {c:<22}{r.min():>13.6g}{r.max():>13.6g}{peak(v, 0)}{peak(acc, 0)}  {length}")
        worst = int(np.argmin(self.pivot_ratio))
        lines += [
            f"  worst scaled residual   {self.residual.max():.2e}",
            f"  Newton iterations       mean {self.iterations.mean():.2f}, max {self.iterations.max()}",
            f"  smallest pivot ratio    {self.pivot_ratio[worst]:.2e} at t = {self.times[worst]:g}"
            " (near 0: near a singular configuration)",
        ]
        lines.append(f"  events                  {len(self.events) or 'none'}")
        lines += [f"    {e}" for e in self.events]
        return "\n".join(lines)

    def units(self, column: str) -> str:
        """The unit of a column of `table`: the model's length unit ("m" or "mm") for x
        and y (of a body or of a named point: ``P.x``), "rad" for theta (whatever angle
        unit the description was written in) and for a curve parameter ``<joint>.s`` (an
        angle-like parameter of period 2 pi), over "s" or "s^2" for a rate ``<column>_d``
        or an acceleration ``<column>_dd``; "s" for ``time``, "" for the diagnostics. An
        unknown column is a KeyError naming it."""
        if column == "time":
            return "s"
        if column in ("iterations", "residual", "pivot_ratio"):
            return ""
        index = self.model._column_index
        for suffix, per in (("_dd", "/s^2"), ("_d", "/s")):
            base = column.removesuffix(suffix)
            if base != column and (base in index or base in self._point_columns()):
                return self.units(base) + per
        point, _, axis = column.rpartition(".")
        if (
            column not in index
            and axis in ("x", "y")
            and (point in self.points or column in self._point_columns())
        ):
            return str(self.model.units["length"])
        if column not in index:
            raise KeyError(f"no column {column!r}; the coordinates are {', '.join(self.columns)}")
        return "rad" if column.endswith((".theta", ".s")) else self.model.units["length"]

    def _point_names(self) -> list[str]:
        """The named points whose columns ``P.x``, ``P.y`` do not clash with a coordinate."""
        index = self.model._column_index
        return [
            p[0] for p in self.model._core.points if f"{p[0]}.x" not in index and f"{p[0]}.y" not in index
        ]

    def _point_columns(self) -> list[str]:
        return [f"{name}.{axis}" for name in self._point_names() for axis in "xy"]

    def table(self, points: bool = False) -> tuple[list[str], list[str], np.ndarray]:
        """Every output as one table: column names, their units and the data (n_steps x
        n_columns). Columns: ``time``, every coordinate kept, the kept points' ``<point>.x``
        and ``.y`` (`outputs`; with ``points``, also every other named point's), their rates
        (``<column>_d``) and accelerations (``<column>_dd``) where solved, then the
        diagnostics ``iterations``, ``residual`` and ``pivot_ratio`` (unit ""). The CSV, NPZ,
        Parquet and DataFrame writers share it.
        """
        # the points: those the sweep kept, then (points=True) the other named ones
        shown = dict(self.points)
        if points:
            shown.update({name: self.point(name) for name in self._point_names() if name not in shown})
        columns = list(self.columns) + [f"{name}.{a}" for name in shown for a in "xy"]
        # a unit per coordinate, then the points' x and y (in the length unit)
        base = [self.units(c) for c in self.columns] + [str(self.model.units["length"])] * 2 * len(shown)
        n = len(self.times)

        def with_points(a: np.ndarray | None, i: int) -> np.ndarray | None:
            ps = [getattr(p, ("position", "velocity", "acceleration")[i]) for p in shown.values()]
            if a is None or any(p is None for p in ps):
                return None
            return np.column_stack([a] + [p.reshape(n, 2) for p in ps])

        q, qd, qdd = (with_points(a, i) for i, a in enumerate((self.q, self.qd, self.qdd)))
        assert q is not None
        names, units, parts = ["time"] + columns, ["s"] + base, [self.times, q]
        for a, suffix, per in ((qd, "_d", "/s"), (qdd, "_dd", "/s^2")):
            if a is not None:
                names += [f"{c}{suffix}" for c in columns]
                units += [u + per for u in base]
                parts.append(a)
        names += ["iterations", "residual", "pivot_ratio"]
        units += ["", "", ""]
        return names, units, np.column_stack(parts + [self.iterations, self.residual, self.pivot_ratio])

    def to_csv(self, path: str, points: bool = False) -> None:
        """Writes t, every coordinate with its derivatives (with ``points``, the named
        points' too), and the diagnostics; each header names its unit."""
        names, units, data = self.table(points=points)
        names[0] = "t"  # the CSV's time column has always been "t [s]"
        header = [f"{n} [{u}]" if u else n for n, u in zip(names, units)]
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            w.writerows(data.tolist())

    def to_npz(self, path: str, points: bool = False) -> None:
        """Writes a NumPy ``.npz``: one array per column of `table` (``time``, ``crank.x``,
        ``crank.x_d``, ..., ``pivot_ratio``), and ``columns`` and ``units``, the column
        names in order and their units (string arrays, loadable without pickle)."""
        names, units, data = self.table(points=points)
        arrays: dict[str, Any] = {name: np.ascontiguousarray(data[:, k]) for k, name in enumerate(names)}
        np.savez(path, **arrays, columns=np.array(names), units=np.array(units))

    def to_parquet(self, path: str, points: bool = False) -> None:
        """Writes a Parquet file (needs pyarrow): the columns of `table`, each field's unit
        in its metadata (``unit``), the model's name in the schema's (``model``)."""
        pa = _args.optional_module("pyarrow", "writing Parquet", "export")
        pq = _args.optional_module("pyarrow.parquet", "writing Parquet", "export")
        names, units, data = self.table(points=points)
        schema = pa.schema(
            [pa.field(n, pa.float64(), metadata={"unit": u}) for n, u in zip(names, units)],
            metadata={"model": self.model.name},
        )
        pq.write_table(pa.Table.from_arrays([data[:, k] for k in range(len(names))], schema=schema), path)

    def to_dataframe(self, points: bool = False) -> Any:
        """The columns of `table` as a pandas DataFrame (needs pandas): one row per step,
        ``iterations`` as integers, every other column float64; ``df.attrs["units"]``
        maps each column to its unit and ``df.attrs["model"]`` names the model.

        >>> import numpy as np
        >>> from linkwork import examples
        >>> df = examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 5)).to_dataframe(points=True)
        >>> df.shape, df.attrs["units"]["P.x_d"], df.attrs["units"]["rocker.theta_dd"]
        ((5, 37), 'm/s', 'rad/s^2')
        """
        # declared lazy import, upward: a convenience method of the view
        from ..view.export import dataframe

        return dataframe(self, points=_args.flag(points, "points"))

    def to_svg(
        self,
        path: str | None = None,
        t: float | None = None,
        paths: Sequence[str] | None = None,
        max_points: int = 5000,
        targets: Any = None,
    ) -> str:
        """The mechanism at time ``t`` (default: the first step) with the paths of points
        over the sweep, as SVG in world coordinates (the model's length unit, y up, drawn
        1:1), and ``targets`` marked with the path's distance from each (points n x 2, a
        `linkwork.view.targets.Targets` or a synthesized design); written to ``path`` if given,
        and returned. See `linkwork.view.export.svg`."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.export import svg

        return svg(self, path, t=t, paths=paths, max_points=max_points, targets=targets)

    def to_html(
        self,
        path: str | None = None,
        outputs: Sequence[str] | None = None,
        paths: Sequence[str] | None = None,
        frames: int = 1000,
        targets: Any = None,
    ) -> str:
        """The interactive page of the sweep: one self-contained HTML file (no network
        needed) with the mechanism drawn to scale, a slider over the steps, play and pause,
        the paths of points, live values and plots of ``outputs``, the events on the
        timeline and ``targets`` marked, with a table of their distances (as for
        `to_svg`); written to ``path`` if given, and returned. See `linkwork.view.page`."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.page import page

        return page(self, path, outputs=outputs, paths=paths, frames=frames, targets=targets)

    def draw(self, ax: Any = None, t: float | None = None, paths: Sequence[str] | None = None) -> Any:
        """Draws the mechanism at time ``t`` of the sweep (default: the first step; a time
        between steps is solved there) with the paths of ``paths`` (default: every named
        point) on matplotlib axes ``ax`` (default: a new figure); returns the axes."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import draw_results

        return draw_results(self, ax, t, paths)

    def animate(self, frames: int = 60, fps: int = 20, mode: str = "jshtml") -> Any:
        """The mechanism moving, as an animation a notebook plays inline (an `Animation`:
        matplotlib's JavaScript player by default, ``mode="html5"`` for a video, which
        needs ffmpeg); ``frames`` frames spread evenly over the sweep."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import animate

        return animate(self, frames=frames, fps=fps, mode=mode)

    def _repr_html_(self) -> str:
        """What a notebook shows: a summary table and small plots."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import results_html

        return results_html(self)

    def to_dxf(
        self,
        path: str,
        t: float | None = None,
        paths: Sequence[str] | None = None,
        max_points: int = 5000,
        targets: Any = None,
    ) -> None:
        """The mechanism at time ``t`` and the paths of points as a DXF drawing (needs
        ezdxf), one layer per kind of thing, ``targets`` on layer TARGETS (as for
        `to_svg`). See `linkwork.view.export.dxf`."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.export import dxf

        dxf(self, path, t=t, paths=paths, max_points=max_points, targets=targets)

    def plot(self, path: str, bodies: Sequence[str] | None = None, every: int = 1) -> None:
        """A PNG of every body's angle, angular velocity and acceleration over time, and
        of the paths of the named points, every ``every``-th step (`linkwork.view.figures.plot_results`)."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.figures import plot_results

        plot_results(self, path, bodies, every)
