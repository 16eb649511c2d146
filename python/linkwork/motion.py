"""Motion laws for drivers: a value f(t) with exact first and second derivatives.

Each law is a plain description; the engine (Rust) and the reference (NumPy) both
evaluate it. ``to_dict`` gives the model-description form shared with the engine, and
``evaluate(times)`` asks the engine for (f, f', f'') at each time.

Besides the closed forms (`Constant`, `Linear`, `Polynomial`, `Harmonic`, `Spline`):

- `Expression`: any formula of t written as text, e.g. ``"0.35 - 0.16*sin(150*t)"``,
  parsed (never ``eval``-ed) and differentiated exactly by the engine;
- cam motion: `Rise` (one rise or fall with a cam profile) and `Cam` (dwells, rises and
  falls in turn), with the profiles of `PROFILES`;
- composition: `Sequence` (laws joined at breakpoints) and `Periodic` (a law repeated);
- `PythonLaw`: a Python function, the slow fallback (it cannot be saved to a file).
"""

from __future__ import annotations

import json
from collections.abc import Sequence as Seq
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from . import _core
from .errors import ModelError

__all__ = [
    "Law",
    "Constant",
    "Linear",
    "Polynomial",
    "Harmonic",
    "Spline",
    "Expression",
    "PROFILES",
    "Rise",
    "Cam",
    "CamSegment",
    "Sequence",
    "Periodic",
    "PythonLaw",
    "period",
]

#: The cam rise profiles s(u), u in [0, 1], by name. With their peak velocity and
#: acceleration for unit lift over unit time (Cv, Ca) and end continuity:
#: cycloidal (2.0000, 6.2832, C2), modified_trapezoid (2.0000, 4.8881, C2),
#: modified_sine (1.7596, 5.5280, C2), polynomial_345 (1.8750, 5.7735, C2),
#: polynomial_4567 (2.1875, 7.5132, C3), harmonic (simple harmonic: 1.5708, 4.9348, C1,
#: the acceleration jumps at both ends).
PROFILES = (
    "cycloidal",
    "modified_trapezoid",
    "modified_sine",
    "polynomial_345",
    "polynomial_4567",
    "harmonic",
)


def _profile(name: str) -> str:
    if name not in PROFILES:
        raise ModelError(f"unknown cam profile {name!r}; the profiles are {', '.join(PROFILES)}")
    return name


class Law:
    """Base class of the motion laws."""

    def to_dict(self) -> dict[str, Any]:
        raise NotImplementedError

    def python_functions(self) -> dict[str, Callable[[float], Any]]:
        """The Python functions this law (or a law inside it) calls, by name."""
        return {}

    def evaluate(self, times: Seq[float] | np.ndarray | float) -> np.ndarray:
        """(f, f', f'') at each time, computed by the engine: an (n, 3) array.

        >>> Linear(1.0, 2.0).evaluate([0.0, 0.5]).tolist()
        [[1.0, 2.0, 0.0], [2.0, 2.0, 0.0]]
        """
        t = np.atleast_1d(np.ascontiguousarray(times, dtype=np.float64))
        return _core.evaluate_law(json.dumps(self.to_dict()), t, self.python_functions() or None)


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

    coefficients: Seq[float]

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

    times: Seq[float] = field(default_factory=list)
    values: Seq[float] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "spline",
            "times": [float(t) for t in self.times],
            "values": [float(v) for v in self.values],
        }


@dataclass(frozen=True)
class Expression(Law):
    """f(t) given as text: numbers (``1e-3``), ``t``, ``pi``, ``e``, ``+ - * /``, ``^`` or
    ``**`` (power), parentheses and the functions sin cos tan asin acos atan atan2(y, x)
    sinh cosh tanh exp ln log (= ln) log10 sqrt abs min max pow(a, b) hypot(a, b).

    The engine parses the text itself (nothing is ``eval``-ed) and differentiates it
    exactly, so f' and f'' are as accurate as f. A text that is not an expression raises
    `ExpressionError` at once, with the column at fault:

    >>> import linkwork as lw
    >>> lw.Expression("0.35 - 0.16*sin(150*t)").evaluate(0.0).round(6).tolist()
    [[0.35, -24.0, 0.0]]
    >>> lw.Expression("0.35 - 0.16*sn(150*t)")
    Traceback (most recent call last):
    ...
    linkwork.errors.ExpressionError: unknown name 'sn' at column 13; did you mean 'sin'?

    Where a function is not defined (``sqrt(t - 1)`` before t = 1, ``1/(t - 1)`` at 1) the
    solve stops with `NonFiniteError` naming the driver, the time step and the operation.
    """

    text: str

    def __post_init__(self) -> None:
        _core.parse_expression(str(self.text), "t")

    def to_dict(self) -> dict[str, Any]:
        return {"type": "expression", "text": str(self.text)}


@dataclass(frozen=True)
class Rise(Law):
    """One rise by ``lift`` (a fall if negative) over ``duration`` from time ``t0``, with a
    cam ``profile`` (one of `PROFILES`): f = start before t0, start + lift s((t - t0) /
    duration) during, start + lift after.

    >>> Rise(lift=2.0, duration=1.0, profile="cycloidal").evaluate([-1.0, 0.5, 3.0]).round(4).tolist()
    [[0.0, 0.0, 0.0], [1.0, 4.0, 0.0], [2.0, 0.0, 0.0]]
    """

    lift: float
    duration: float
    t0: float = 0.0
    start: float = 0.0
    profile: str = "cycloidal"

    def __post_init__(self) -> None:
        _profile(self.profile)

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "rise",
            "start": float(self.start),
            "lift": float(self.lift),
            "t0": float(self.t0),
            "duration": float(self.duration),
            "profile": self.profile,
        }


@dataclass(frozen=True)
class CamSegment:
    """One segment of a `Cam` program: made by ``Cam.dwell``, ``Cam.rise`` or ``Cam.fall``."""

    kind: str
    duration: float
    lift: float = 0.0
    profile: str = "cycloidal"

    def to_dict(self) -> dict[str, Any]:
        if self.kind == "dwell":
            return {"type": "dwell", "duration": float(self.duration)}
        return {
            "type": self.kind,
            "duration": float(self.duration),
            "lift": float(self.lift),
            "profile": _profile(self.profile),
        }


@dataclass(frozen=True)
class Cam(Law):
    """A cam program: from ``start`` at time ``t0``, each segment in turn (a dwell, a rise
    or a fall), each beginning where the previous one ended, so the motion is continuous
    by construction (and smooth: every profile starts and ends at rest). Before ``t0`` the
    value is ``start``, after the last segment its end value. Repeat it with `Periodic`.

    >>> cam = Cam([Cam.rise(0.3, 0.02), Cam.dwell(0.2), Cam.fall(0.3, 0.02), Cam.dwell(0.2)])
    >>> cam.evaluate([0.0, 0.4, 1.0])[:, 0].round(6).tolist()
    [0.0, 0.02, 0.0]
    """

    segments: Seq[CamSegment]
    start: float = 0.0
    t0: float = 0.0

    @staticmethod
    def dwell(duration: float) -> CamSegment:
        """At rest for ``duration``."""
        return CamSegment("dwell", duration)

    @staticmethod
    def rise(duration: float, lift: float, profile: str = "cycloidal") -> CamSegment:
        """Up by ``lift`` over ``duration`` with a profile of `PROFILES`."""
        return CamSegment("rise", duration, lift, _profile(profile))

    @staticmethod
    def fall(duration: float, lift: float, profile: str = "cycloidal") -> CamSegment:
        """Down by ``lift`` over ``duration`` with a profile of `PROFILES`."""
        return CamSegment("fall", duration, lift, _profile(profile))

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "cam",
            "start": float(self.start),
            "t0": float(self.t0),
            "segments": [s.to_dict() for s in self.segments],
        }


@dataclass(frozen=True)
class Sequence(Law):
    """``laws[0]`` until ``breakpoints[0]``, ``laws[i]`` from ``breakpoints[i-1]`` to
    ``breakpoints[i]``, the last law after the last breakpoint; each law is evaluated at
    the absolute time. The value must be continuous at every breakpoint (a jump is refused,
    naming the breakpoint); velocity and acceleration may jump there.

    >>> ramp = Sequence([1.0], [Polynomial([0.0, 0.0, 1.0]), Linear(-1.0, 2.0)])
    >>> ramp.evaluate([0.5, 2.0]).tolist()
    [[0.25, 1.0, 2.0], [3.0, 2.0, 0.0]]
    """

    breakpoints: Seq[float]
    laws: Seq[Law]

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "sequence",
            "breakpoints": [float(b) for b in self.breakpoints],
            "laws": [law.to_dict() for law in self.laws],
        }

    def python_functions(self) -> dict[str, Callable[[float], Any]]:
        out: dict[str, Callable[[float], Any]] = {}
        for law in self.laws:
            out.update(law.python_functions())
        return out


@dataclass(frozen=True)
class Periodic(Law):
    """``law`` repeated every ``period`` from ``t0`` (and before it): f(t) = law(t0 + tau)
    + k (law(t0 + period) - law(t0)) for t = t0 + k period + tau. The net change per period
    is carried over, so an indexing motion keeps advancing, and a rise-dwell-fall repeats
    exactly. Velocity and acceleration jump at the seams unless the law's own match.

    >>> index = Periodic(Rise(lift=0.25, duration=0.4, profile="modified_sine"), period=1.0)
    >>> index.evaluate([0.5, 1.5, 10.5])[:, 0].tolist()
    [0.25, 0.5, 2.75]
    """

    law: Law
    period: float
    t0: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "periodic",
            "period": float(self.period),
            "t0": float(self.t0),
            "law": self.law.to_dict(),
        }

    def python_functions(self) -> dict[str, Callable[[float], Any]]:
        return self.law.python_functions()


@dataclass(frozen=True, eq=False)
class PythonLaw(Law):
    """A law given by a Python function ``func(t) -> (f, f', f'')``: the fallback for what
    an `Expression`, a `Cam` or a `Spline` cannot say.

    It is slower: the engine takes the GIL back to call it once per time step (its value
    serves the Newton iterations, the velocity and the acceleration of that step). On
    ``examples.four_bar()`` swept over 100,001 steps, the crank motion 5 t + 0.2 sin(5 t)
    as a Python function took 0.162 s, as an `Expression` 0.135 s: 1.2 times slower, about
    0.3 us more per step (best of 15, a shared 2-core machine; docs/motion_laws.md has the
    script). A function doing more work costs more, and every sweep of it holds the GIL
    for each call, so threads (``sweep_batch``) take turns in it.

    An exception raised by ``func`` stops the solve with `NonFiniteError` naming the
    driver and the time step, the exception chained as ``__cause__`` (and the good steps
    kept in ``.partial``). ``name`` (default: the function's ``__name__``) identifies it in
    the description; a mechanism holding one cannot be saved to a file.

    >>> import math
    >>> law = PythonLaw(lambda t: (math.sin(t), math.cos(t), -math.sin(t)), name="wave")
    >>> law.evaluate([0.0]).tolist()
    [[0.0, 1.0, -0.0]]
    """

    func: Callable[[float], Any]
    name: str = ""

    def __post_init__(self) -> None:
        if not callable(self.func):
            raise TypeError(f"PythonLaw needs a callable, got {type(self.func).__name__}")
        if not self.name:
            object.__setattr__(self, "name", getattr(self.func, "__name__", "law"))

    def to_dict(self) -> dict[str, Any]:
        return {"type": "python", "name": self.name}

    def python_functions(self) -> dict[str, Callable[[float], Any]]:
        return {self.name: self.func}


def period(law: dict[str, Any], full_turn: float | None = None) -> tuple[float, str] | None:
    """The period of a law description and how it was found, or None if it has none: a
    harmonic law's 2 pi / |omega|, a periodic law's period, and, for an angle (give
    ``full_turn``, 2 pi or 360 in the driver's unit), a constant rate's full_turn / |rate|
    (one turn of a crank).

    >>> period(Linear(0.0, 5.0).to_dict(), full_turn=2 * np.pi)
    (1.2566370614359172, '2 pi / |rate|')
    >>> period(Linear(0.0, 5.0).to_dict()) is None  # a distance growing at a constant rate
    True
    """
    kind = law.get("type")
    if kind == "linear" and full_turn is not None and float(law.get("rate", 0.0)) != 0.0:
        turn = "2 pi" if full_turn == 2 * np.pi else f"{full_turn:g}"
        return full_turn / abs(float(law["rate"])), f"{turn} / |rate|"
    if kind == "harmonic" and float(law.get("omega", 0.0)) != 0.0 and float(law.get("amplitude", 0.0)) != 0.0:
        return 2 * np.pi / abs(float(law["omega"])), "2 pi / |omega|"
    if kind == "periodic" and float(law.get("period", 0.0)) > 0.0:
        return float(law["period"]), "its period"
    return None
