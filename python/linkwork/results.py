"""Results of a sweep (`Results`) or of one solve (`State`) as NumPy arrays.

Array sizes: q, qd, qdd are (n_steps, n_coords), columns named by ``columns``
("<body>.x", "<body>.y", "<body>.theta"); the diagnostics are (n_steps,).
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .model import Model

__all__ = ["Results", "State", "BodyMotion", "PointMotion"]


@dataclass(frozen=True)
class BodyMotion:
    """One body's coordinates and their derivatives, each (n_steps,) (or scalars)."""

    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    xd: np.ndarray
    yd: np.ndarray
    thetad: np.ndarray
    xdd: np.ndarray
    ydd: np.ndarray
    thetadd: np.ndarray


@dataclass(frozen=True)
class PointMotion:
    """A body point's world position, velocity and acceleration, each (n_steps, 2) (or (2,))."""

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


class _Kinematics:
    """Shared accessors over (q, qd, qdd), for many steps or for one."""

    model: Model
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray

    @property
    def columns(self) -> list[str]:
        return self.model.columns

    def _body_index(self, body: str) -> int:
        try:
            return self.model.body_names.index(body)
        except ValueError:
            raise KeyError(f"no body named {body!r}; bodies: {', '.join(self.model.body_names)}") from None

    def body(self, name: str) -> BodyMotion:
        """x, y, theta of a body and their first and second derivatives."""
        j = 3 * self._body_index(name)
        q, qd, qdd = self.q[..., j : j + 3], self.qd[..., j : j + 3], self.qdd[..., j : j + 3]
        return BodyMotion(
            q[..., 0],
            q[..., 1],
            q[..., 2],
            qd[..., 0],
            qd[..., 1],
            qd[..., 2],
            qdd[..., 0],
            qdd[..., 1],
            qdd[..., 2],
        )

    def point(self, name: str) -> PointMotion:
        """Kinematics of a named point (``Mechanism.point``)."""
        for pname, body, ux, uy in self.model._core.points:
            if pname == name:
                return self._point(body, (ux, uy))
        names = [p[0] for p in self.model._core.points]
        raise KeyError(f"no point named {name!r}; points: {', '.join(names) or 'none'}")

    def point_at(self, body: str, local: Sequence[float]) -> PointMotion:
        """Kinematics of the point with body-frame coordinates ``local`` of ``body``."""
        return self._point(self._body_index(body), (float(local[0]), float(local[1])))

    def _point(self, body: int, u: tuple[float, float]) -> PointMotion:
        if body < 0:  # a point of the ground
            shape = self.q.shape[:-1] + (2,)
            return PointMotion(np.broadcast_to(np.asarray(u), shape).copy(), np.zeros(shape), np.zeros(shape))
        j = 3 * body
        th, w, al = self.q[..., j + 2], self.qd[..., j + 2], self.qdd[..., j + 2]
        c, s = np.cos(th), np.sin(th)
        au = np.stack([c * u[0] - s * u[1], s * u[0] + c * u[1]], axis=-1)  # A u
        bu = np.stack([-au[..., 1], au[..., 0]], axis=-1)  # B u = A u turned +90 deg
        r = self.q[..., j : j + 2] + au
        v = self.qd[..., j : j + 2] + bu * w[..., None]
        a = self.qdd[..., j : j + 2] + bu * al[..., None] - au * (w * w)[..., None]
        return PointMotion(r, v, a)


class State(_Kinematics):
    """Position, velocity and acceleration at one time (1-D arrays of n_coords)."""

    def __init__(
        self, model: Model, t: float, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
        iterations: int, residual: float, pivot_ratio: float,
    ) -> None:  # fmt: skip
        self.model, self.t, self.q, self.qd, self.qdd = model, t, q, qd, qdd
        self.iterations, self.residual, self.pivot_ratio = iterations, residual, pivot_ratio

    def __repr__(self) -> str:
        vals = ", ".join(f"{c}={v:.6g}" for c, v in zip(self.columns, self.q))
        return f"<State t={self.t:g}: {vals}>"


class Results(_Kinematics):
    """A sweep's results: q, qd, qdd (n_steps, n_coords) and per-step diagnostics.

    Diagnostics, each (n_steps,): ``iterations`` (Newton iterations, each one
    factorization of Phi_q), ``residual`` (inf-norm of the residual at the last Newton
    evaluation, length rows divided by the model's length scale), ``pivot_ratio``
    (smallest over largest LU pivot of the scaled Phi_q: near 0 means near singular).
    """

    def __init__(self, model: Model, raw: dict[str, np.ndarray]) -> None:
        self.model = model
        self.times: np.ndarray = raw["times"]
        self.q: np.ndarray = raw["q"]
        self.qd: np.ndarray = raw["qd"]
        self.qdd: np.ndarray = raw["qdd"]
        self.iterations: np.ndarray = raw["iterations"]
        self.residual: np.ndarray = raw["residual"]
        self.pivot_ratio: np.ndarray = raw["pivot_ratio"]

    @property
    def n_steps(self) -> int:
        return int(self.q.shape[0])

    def __len__(self) -> int:
        return self.n_steps

    def __repr__(self) -> str:
        return f"<Results of '{self.model.name}': {self.n_steps} steps x {len(self.columns)} coordinates>"

    def summary(self) -> str:
        """A plain-text summary: range of every coordinate, worst residual, Newton
        iterations, closest approach to a singular configuration."""
        if self.n_steps == 0:
            return f"{self.model.name}: no steps"
        lines = [
            f"{self.model.name}: {self.n_steps} steps, t = {self.times[0]:g} .. {self.times[-1]:g}",
            f"  {'coordinate':<22}{'min':>13}{'max':>13}{'max |rate|':>13}{'max |accel|':>13}",
        ]
        for k, c in enumerate(self.columns):
            q = self.q[:, k]
            lines.append(
                f"  {c:<22}{q.min():>13.6g}{q.max():>13.6g}"
                f"{np.abs(self.qd[:, k]).max():>13.6g}{np.abs(self.qdd[:, k]).max():>13.6g}"
            )
        worst = int(np.argmin(self.pivot_ratio))
        lines += [
            f"  worst scaled residual   {self.residual.max():.2e}",
            f"  Newton iterations       mean {self.iterations.mean():.2f}, max {self.iterations.max()}",
            f"  smallest pivot ratio    {self.pivot_ratio[worst]:.2e} at t = {self.times[worst]:g}"
            " (near 0: near a singular configuration)",
        ]
        return "\n".join(lines)

    def to_csv(self, path: str) -> None:
        """Writes t, every coordinate with its derivatives, and the diagnostics."""
        header = ["t"] + self.columns + [c + "_d" for c in self.columns] + [c + "_dd" for c in self.columns]
        header += ["iterations", "residual", "pivot_ratio"]
        table = np.column_stack(
            [self.times, self.q, self.qd, self.qdd, self.iterations, self.residual, self.pivot_ratio]
        )
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            w.writerows(table.tolist())

    def plot(self, path: str, bodies: Sequence[str] | None = None, every: int = 1) -> None:
        """A PNG of every body's angle, angular velocity and acceleration over time, and
        of the paths of the named points (plotting every ``every``-th step)."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        names = list(bodies) if bodies is not None else self.model.body_names
        k = slice(None, None, max(1, int(every)))
        t = self.times[k]
        fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), constrained_layout=True)
        for name in names:
            b = self.body(name)
            axes[0, 0].plot(t, b.theta[k], label=name)
            axes[0, 1].plot(t, b.thetad[k], label=name)
            axes[1, 0].plot(t, b.thetadd[k], label=name)
        for ax, what in zip(axes.flat, ["theta [rad]", "omega [rad/s]", "alpha [rad/s^2]"]):
            ax.set_xlabel("t [s]")
            ax.set_ylabel(what)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=8)
        ax = axes[1, 1]
        for pname, *_ in self.model._core.points:
            p = self.point(pname).position[k]
            ax.plot(p[:, 0], p[:, 1], label=f"point {pname}")
        for name in names:
            b = self.body(name)
            ax.plot(b.x[k], b.y[k], lw=0.8, ls="--", label=f"{name} origin")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title("paths")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.suptitle(f"{self.model.name}: {self.n_steps} steps")
        fig.savefig(path, dpi=110)
        plt.close(fig)
