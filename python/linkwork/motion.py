"""Motion laws for drivers: a value f(t) with exact first and second derivatives.

Each law is a plain description; the engine (Rust) and the reference (NumPy) both
evaluate it. ``to_dict`` gives the model-description form shared with the engine.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Law", "Constant", "Linear", "Polynomial", "Harmonic", "Spline"]


class Law:
    """Base class of the motion laws."""

    def to_dict(self) -> dict[str, Any]:
        raise NotImplementedError


@dataclass(frozen=True)
class Constant(Law):
    """f(t) = value."""

    value: float

    def to_dict(self) -> dict[str, Any]:
        return {"type": "constant", "value": float(self.value)}


@dataclass(frozen=True)
class Linear(Law):
    """f(t) = value + rate * t (constant speed)."""

    value: float
    rate: float

    def to_dict(self) -> dict[str, Any]:
        return {"type": "linear", "value": float(self.value), "rate": float(self.rate)}


@dataclass(frozen=True)
class Polynomial(Law):
    """f(t) = c0 + c1 t + c2 t^2 + ... (coefficients in increasing degree)."""

    coefficients: Sequence[float]

    def to_dict(self) -> dict[str, Any]:
        return {"type": "polynomial", "coefficients": [float(c) for c in self.coefficients]}


@dataclass(frozen=True)
class Harmonic(Law):
    """f(t) = mean + amplitude * sin(omega t + phase)."""

    mean: float
    amplitude: float
    omega: float
    phase: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "harmonic",
            "mean": float(self.mean),
            "amplitude": float(self.amplitude),
            "omega": float(self.omega),
            "phase": float(self.phase),
        }


@dataclass(frozen=True)
class Spline(Law):
    """Natural cubic spline through (times[i], values[i]): C2, so acceleration is continuous.

    Times must be strictly increasing; evaluation outside [times[0], times[-1]] is an error.
    """

    times: Sequence[float] = field(default_factory=list)
    values: Sequence[float] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "spline",
            "times": [float(t) for t in self.times],
            "values": [float(v) for v in self.values],
        }
