"""The rest configuration of a model under its loads (`Model.equilibrium`): q with named
columns, the multipliers and reactions holding it, its stability from the reduced
stiffness and its linearized vibration modes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .results import Statics

if TYPE_CHECKING:
    from linkwork import Model

__all__ = ["Equilibrium", "Mode"]


@dataclass(frozen=True)
class Mode:
    """One linearized vibration mode: ``omega2`` (rad^2/s^2; negative for a motion that
    grows, zero for a neutral one), ``omega`` (rad/s) and ``frequency`` (Hz), both 0 where
    omega2 <= 0; ``shape`` (n_coords,): the motion in q, mass-normalised (shape^T M shape
    = 1) with its largest scaled component positive; ``coordinate``: the column it moves
    most."""

    omega2: float
    omega: float
    frequency: float
    shape: np.ndarray
    coordinate: str


class Equilibrium(Statics):
    """A rest configuration: ``q`` (named columns: ``body(name)``, ``point(name)``), the
    multipliers and reactions holding it (``reaction(joint)``, ``effort(driver)``),
    ``iterations``, ``residual`` (the unbalanced generalized force left along the free
    motions, in the model's energy unit per unit scaled motion: lengths / L, angles in
    rad) and ``phi`` (scaled |Phi|).

    Stability: ``eigenvalues`` of the reduced stiffness K_r = N^T K_t N (ascending, same
    units; N an orthonormal basis of the motions the constraints allow, in scaled
    coordinates), ``directions`` (dof, n_coords): each eigenvalue's motion in q;
    ``stable``: every eigenvalue above ``tol``; ``unstable`` and ``neutral``: the
    (eigenvalue, coordinate moved most) of those below -tol and within tol;
    ``asymmetry``: how far K_r is from symmetric (loads that are not conservative; the
    symmetric part is used). Modes: ``omega2``, ``omega`` (rad/s), ``frequencies`` (Hz),
    ``shapes`` (dof, n_coords), and `modes`.
    """

    def __init__(self, model: Model, t: float, raw: dict[str, Any]) -> None:
        super().__init__(model, t, raw["q"], raw["lambda"], raw["reactions"])
        self.iterations: int = raw["iterations"]
        self.residual: float = raw["force"]
        self.phi: float = raw["phi"]
        self.eigenvalues: np.ndarray = raw["eigenvalues"]
        self.directions: np.ndarray = raw["directions"]
        self.tol: float = raw["tol"]
        self.stable: bool = raw["stable"]
        self.asymmetry: float = raw["asymmetry"]
        names = model.columns
        self._dominant = [names[k] for k in raw["dominant"]]
        self.unstable = [(float(v), c) for v, c in zip(self.eigenvalues, self._dominant) if v < -self.tol]
        self.neutral = [(float(v), c) for v, c in zip(self.eigenvalues, self._dominant) if abs(v) <= self.tol]
        self._modes_error: BaseException | None = raw["modes_error"]
        self.omega2: np.ndarray | None = raw["omega2"]
        self.shapes: np.ndarray | None = raw["shapes"]
        if self.omega2 is None:
            self.omega: np.ndarray | None = None
            self.frequencies: np.ndarray | None = None
        else:
            self.omega = np.sqrt(np.maximum(self.omega2, 0.0))
            self.frequencies = self.omega / (2.0 * math.pi)

    def modes(self) -> list[Mode]:
        """The linearized vibration modes, slowest first; `MasslessError` where a motion
        the constraints allow carries no mass."""
        if self._modes_error is not None:
            raise self._modes_error
        assert self.omega2 is not None and self.shapes is not None
        assert self.omega is not None and self.frequencies is not None
        cols = self.model.columns
        # the coordinate moved most, lengths measured in the model's length scale
        big = self.model._core.length_scale
        scale = np.array([big if c.endswith((".x", ".y")) else 1.0 for c in cols])
        out = []
        for k in range(len(self.omega2)):
            shape = self.shapes[k]
            scaled = shape / scale
            out.append(
                Mode(
                    float(self.omega2[k]),
                    float(self.omega[k]),
                    float(self.frequencies[k]),
                    shape,
                    cols[int(np.argmax(np.abs(scaled)))],
                )
            )
        return out

    def __repr__(self) -> str:
        vals = ", ".join(f"{c}={v:.6g}" for c, v in zip(self.columns, self.q))
        word = "stable" if self.stable else "unstable" if self.unstable else "neutral"
        return f"<Equilibrium t={self.t:g} ({word}, {self.iterations} iterations): {vals}>"
