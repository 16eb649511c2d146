"""Results of a forward-dynamics simulation (`Model.simulate`): a sweep's `Results` (q,
qd, qdd, points, reactions, efforts; its page, notebook view and figures) with the
simulation's own diagnostics: the constraints' drift, the energy balance, the power of
every load and the steps taken.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _core
from .events import Event
from .results import Results

if TYPE_CHECKING:
    from linkwork import Model

__all__ = ["Simulation", "SimulationEnergy"]


@dataclass(frozen=True)
class SimulationEnergy:
    """Energy of a simulation at each kept time, each (n,): ``kinetic``, ``potential``
    (gravity and springs), ``work`` done since the start by what is not conservative
    (dampers, applied forces and torques, joint forces, motors and friction, driven
    constraints) and ``balance`` = kinetic +
    potential - work minus its initial value: zero but for the integration error."""

    kinetic: np.ndarray
    potential: np.ndarray
    work: np.ndarray
    balance: np.ndarray


class Simulation(Results):
    """A simulation's results at the asked times: q, qd, qdd (n, n_coords), the
    multipliers and reactions (``reaction(name)``, ``effort(driver)``), and:

    ``drift`` and ``drift_d`` (n,): |Phi| (length rows / L) and |Phi_q qd - nu| of the
    integrated state before it was projected onto the constraints (the kept q and qd are
    projected); ``step`` (n,): the size of the step that reached each time;
    ``iterations``: its Newton (or projection) iterations; ``pivot_ratio``: of the
    augmented matrix (near 0 at a singular configuration of the constraints);
    ``n_steps_taken``, ``n_rejected``, ``n_evaluations``; ``moved_q`` and ``moved_qd``: how
    far the initial conditions were moved onto the constraints (scaled); ``method``;
    ``events``: as a sweep's (`Event`), the singular configurations the motion passed
    ("bifurcation", or "limit" with a driver row in the dependency) and the locks (the
    whole motion stopping and reversing), each located between the steps with its time,
    the joints and coordinates involved and the smallest pivot ratio met.
    ``load_power`` (n,): the power of all the loads (`load_powers` one by one).

    Views as for a sweep (`to_html`, `_repr_html_`, `draw`, `animate`, `plot`), with the
    energy balance and the drift added to the page and the notebook's view, and
    `plot_energy` for a PNG of them.
    """

    simulated = True

    def __init__(self, model: Model, raw: dict[str, Any], method: str) -> None:
        n = len(raw["times"])
        # solved when first read (`_solved`): qdd, the multipliers, the reactions, the
        # pivot ratios and the loads' powers
        self._lazy: dict[str, Any] = {}
        sweep_raw = dict(raw)
        sweep_raw.update(
            residual=raw["drift"],
            det_sign=np.ones(n),
            events=[],  # made `Event`s when first read (`events`)
            qdd=None,
            pivot_ratio=None,
            load_power=None,
        )
        super().__init__(model, sweep_raw)
        self._raw_events: list[dict[str, Any]] = raw.get("events", [])
        self._events: list[Event] | None = None
        self.method = method
        self.drift: np.ndarray = raw["drift"]
        self.drift_d: np.ndarray = raw["drift_d"]
        self.step: np.ndarray = raw["step"]
        self.n_steps_taken: int = raw["n_steps"]
        self.n_rejected: int = raw["n_rejected"]
        self.n_evaluations: int = raw["n_evaluations"]
        self.moved_q: float = raw["moved_q"]
        self.moved_qd: float = raw["moved_qd"]
        self._energy = (raw["kinetic"], raw["potential"], raw["work"])

    def _solved(self, name: str) -> Any:
        """One of the quantities solved at every row on first use: the index-1 solve (qdd,
        multipliers, reactions, pivot ratios) at the kept q and qd, the loads' powers."""
        if self._lazy.get(name) is None:
            assert self.qd is not None  # a simulation keeps its rates
            if name == "load_powers":
                self._lazy[name] = _core.load_powers(self.model._core, self.times, self.q, self.qd)
            else:
                rows = _core.simulation_rows(self.model._core, self.times, self.q, self.qd)
                self._lazy.update(
                    qdd=rows["qdd"],
                    multipliers=rows["lambda"],
                    reactions=rows["reactions"],
                    pivot_ratio=rows["pivot_ratio"],
                )
        return self._lazy[name]

    @property  # type: ignore[override]
    def events(self) -> list[Event]:
        """The singular configurations passed and the locks met, in time order."""
        if self._events is None:
            self._events = [Event.from_raw(e) for e in self._raw_events]
        return self._events

    @events.setter
    def events(self, value: list[Event]) -> None:
        self._events = value

    @property  # type: ignore[override]
    def qdd(self) -> np.ndarray:
        """(n, n_coords): the accelerations at the kept q and qd."""
        return self._solved("qdd")

    @qdd.setter
    def qdd(self, value: np.ndarray | None) -> None:
        self._lazy["qdd"] = value

    @property  # type: ignore[override]
    def multipliers(self) -> np.ndarray:
        """(n, n_rows): the multipliers of M qdd + Phi_q^T lambda = Q_A."""
        return self._solved("multipliers")

    @multipliers.setter
    def multipliers(self, value: np.ndarray | None) -> None:
        self._lazy["multipliers"] = value

    @property  # type: ignore[override]
    def reactions(self) -> np.ndarray:
        """(n, n_constraints, 4): each constraint's reaction on its side b (Fx, Fy, torque
        about its anchor, power)."""
        return self._solved("reactions")

    @reactions.setter
    def reactions(self, value: np.ndarray | None) -> None:
        self._lazy["reactions"] = value

    @property  # type: ignore[override]
    def pivot_ratio(self) -> np.ndarray:
        """(n,): the pivot ratio of the augmented matrix at each kept state."""
        return self._solved("pivot_ratio")

    @pivot_ratio.setter
    def pivot_ratio(self, value: np.ndarray | None) -> None:
        self._lazy["pivot_ratio"] = value

    @property  # type: ignore[override]
    def load_power(self) -> np.ndarray:
        """(n,): the power of all the loads (`load_powers` one by one)."""
        return self._solved("load_powers").sum(axis=1)

    @load_power.setter
    def load_power(self, value: np.ndarray | None) -> None:
        pass  # always the sum of `load_powers`

    def load_powers(self) -> dict[str, np.ndarray]:
        """The power of each load (by name, in the order of the model's loads), each (n,):
        F . v of a force's point, torque x rate, -tension x elongation rate of a spring
        (-torque x relative rate of a torsion spring), its damping included; negative
        where the load takes energy out. A spring's elastic part is the rate of its
        potential energy (in ``energy().potential``); the rest is in ``energy().work``."""
        names = [load[0] for load in self.model._core.loads]
        powers = self._solved("load_powers")
        return {name: powers[:, k] for k, name in enumerate(names)}

    def energy(self) -> SimulationEnergy:  # type: ignore[override]
        """Kinetic and potential energy, the work of what is not conservative, and the
        balance (zero but for the integration error)."""
        kinetic, potential, work = self._energy
        total = kinetic + potential - work
        balance = total - total[0] if len(total) else total
        return SimulationEnergy(kinetic, potential, work, balance)

    def summary(self, angles: str = "rad") -> str:
        """A sweep's summary (`Results.summary`) with the simulation's own lines: the
        method and steps, the largest drift before projection and the energy balance."""
        lines = super().summary(angles).splitlines()
        if self.n_steps == 0:
            return "\n".join(lines)
        # a simulation's residual is the drift before projection: said as such below
        lines = [line for line in lines if not line.startswith("  worst scaled residual")]
        e = self.energy()
        unit = self.model.units["energy"]
        lines += [
            f"  method                  {self.method}: {self.n_steps_taken} steps "
            f"({self.n_rejected} rejected), {self.n_evaluations} evaluations",
            f"  largest drift           {self.drift.max():.2e} (positions, scaled), "
            f"{self.drift_d.max():.2e} (rates), before projection",
            f"  energy balance          within {np.abs(e.balance).max():.2e} {unit} "
            f"({_relative(e):.1e} of the largest energy)",
        ]
        return "\n".join(lines)

    def forces_summary(self) -> str:
        """Over the simulation, as text: every joint's force magnitude (its reaction on
        side b), every driver's effort and every load's power, each with its largest and
        smallest value and the time of each; the work done by what is not conservative
        and the energy balance."""
        table = self._forces()
        u = self.model.units
        lines = [
            f"{self.model.name}: {self.n_steps} rows, t = {self.times[0]:g} .. {self.times[-1]:g} s"
            if self.n_steps
            else f"{self.model.name}: no rows",
            f"  {'joint, driver or load':<26}{'max':>13}{'at t':>11}{'min':>13}{'at t':>11}  unit",
        ]
        if self.n_steps == 0:
            return "\n".join(lines)

        def row(label: str, v: np.ndarray, unit: str, note: str = "") -> str:
            i, j = int(np.argmax(v)), int(np.argmin(v))
            return (
                f"  {label:<26}{v[i]:>13.6g}{self.times[i]:>11.6g}{v[j]:>13.6g}{self.times[j]:>11.6g}"
                f"  {unit}{note}"
            )

        for k, (name, role, *_) in enumerate(self.model.constraints):
            if role == "driver":
                lines.append(row(f"{name} effort", self.effort(name), self.effort_unit(name)))
            else:
                note = "" if name not in self.model.indeterminate else "  (not unique: redundant rows)"
                force = np.hypot(table[:, k, 0], table[:, k, 1])
                lines.append(row(f"{name} |force|", force, u["force"], note))
        for name, power in self.load_powers().items():
            lines.append(row(f"{name} power", power, u["power"]))
        e = self.energy()
        lines += [
            f"  work not conservative     {e.work[-1]:.6g} {u['energy']} by t = {self.times[-1]:g} s "
            "(dampers, applied loads, drivers)",
            f"  energy balance            within {np.abs(e.balance).max():.2e} {u['energy']} "
            f"({_relative(e):.1e} of the largest energy)",
        ]
        return "\n".join(lines)

    def plot_energy(self, path: str, every: int = 1) -> None:
        """A PNG of the energy balance (kinetic, potential, work of what is not
        conservative, and the balance's error), the constraints' drift before projection,
        and the plotted coordinates' rates, over time (`linkwork.view.figures.plot_simulation`)."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.figures import plot_simulation

        plot_simulation(self, path, every)

    def __repr__(self) -> str:
        return (
            f"<Simulation of '{self.model.name}' ({self.method}): {self.n_steps} times x "
            f"{len(self.columns)} coordinates, {self.n_steps_taken} steps>"
        )


def _relative(e: SimulationEnergy) -> float:
    """The balance's largest error over the largest energy term (0 where all are 0)."""
    scale = max(float(np.abs(a).max()) for a in (e.kinetic, e.potential, e.work))
    return float(np.abs(e.balance).max()) / scale if scale > 0 else 0.0
