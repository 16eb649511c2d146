"""Results of a forward-dynamics simulation (`Model.simulate`): a sweep's `Results` (q,
qd, qdd, points, reactions, efforts) with the simulation's own diagnostics: the
constraints' drift, the energy balance and the steps taken.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .results import Results

if TYPE_CHECKING:
    from linkwork import Model

__all__ = ["Simulation", "SimulationEnergy"]


@dataclass(frozen=True)
class SimulationEnergy:
    """Energy of a simulation at each kept time, each (n,): ``kinetic``, ``potential``
    (gravity and springs), ``work`` done since the start by what is not conservative
    (dampers, applied forces and torques, driven constraints) and ``balance`` = kinetic +
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
    """

    def __init__(self, model: Model, raw: dict[str, Any], method: str) -> None:
        n = len(raw["times"])
        sweep_raw = dict(raw)
        sweep_raw.update(
            residual=raw["drift"],
            det_sign=np.ones(n),
            events=raw.get("events", []),
            load_power=np.full(n, np.nan),
        )
        super().__init__(model, sweep_raw)
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

    def energy(self) -> SimulationEnergy:  # type: ignore[override]
        """Kinetic and potential energy, the work of what is not conservative, and the
        balance (zero but for the integration error)."""
        kinetic, potential, work = self._energy
        total = kinetic + potential - work
        balance = total - total[0] if len(total) else total
        return SimulationEnergy(kinetic, potential, work, balance)

    def __repr__(self) -> str:
        return (
            f"<Simulation of '{self.model.name}' ({self.method}): {self.n_steps} times x "
            f"{len(self.columns)} coordinates, {self.n_steps_taken} steps>"
        )
