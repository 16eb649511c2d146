"""The dyad, the unit of every exact problem: the checks of problem data, `Dyad` and
`DyadSolutions` (roots with their certificates), and `dyads`, the raw solutions of a
problem by homotopy or resultant."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from ..errors import SynthesisError

__all__ = ["POSITION_TOLERANCE", "Dyad", "DyadSolutions", "generic_root_count", "dyads"]


#: A precision position counts as reached when the swept pose matches it to this, relative
#: to the design's size (the sweep's own error is ~1e-12).
POSITION_TOLERANCE = 1e-7


def _angles(values: np.ndarray, unit: str, what: str) -> np.ndarray:
    if unit not in ("rad", "deg"):
        raise SynthesisError(f"angles must be 'rad' or 'deg', not {unit!r}")
    if unit == "deg":
        return np.radians(values)
    if values.size and float(np.max(np.abs(values))) > 2.0 * math.pi + 1e-9:
        raise SynthesisError(
            f"{what} reach {float(np.max(np.abs(values))):.4g} rad, more than a turn: they look like "
            "degrees; pass angles='deg' (or give radians)"
        )
    return values


def _array(value: Any, what: str, columns: int) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise SynthesisError(f"{what} must be numbers in rows of {columns}: {e}") from None
    if a.ndim == 1 and columns == 1:
        return a
    if a.ndim != 2 or a.shape[1] != columns:
        raise SynthesisError(f"{what} must be an array of shape (n, {columns}), got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = int(np.argwhere(~np.isfinite(a))[0][0])
        raise SynthesisError(f"{what}: row {bad + 1} is not finite")
    return a


@dataclass(frozen=True)
class Dyad:
    """One RR dyad at position 1: ``ground`` (the fixed pivot, or for a chained problem
    the pivot on the guiding link) and ``moving`` (the pivot on the guided body), in world
    coordinates. A complex solution keeps its imaginary parts in ``*_imag``.
    ``residual``: the largest change of the link length over the positions (length units);
    ``backward_error``, ``condition`` (|Df| |Df^-1|), ``certified``, ``real`` and
    ``radius`` come from the root's certificate. Dyads of `nine_points` designs carry their
    class's largest backward error and ``condition`` NaN (their roots are certified per
    class, in 24 unknowns, not per dyad); least-squares dyads are not certified."""

    ground: np.ndarray
    moving: np.ndarray
    ground_imag: np.ndarray
    moving_imag: np.ndarray
    real: bool
    certified: bool
    residual: float
    backward_error: float
    condition: float
    radius: float

    @property
    def length(self) -> float:
        return float(np.hypot(*(self.moving - self.ground)))


@dataclass(frozen=True)
class DyadSolutions:
    """Every dyad of one problem, and what the paths did: ``paths`` tracked,
    ``at_infinity``, ``failed``, ``singular``; ``distinct``: the certified roots are
    pairwise distinct (disjoint certification balls). For the resultant, ``paths``
    counts the elimination's candidates and ``failed`` those Newton did not take to a
    root (the spurious ones)."""

    dyads: list[Dyad]
    method: str
    paths: int | None = None
    at_infinity: int | None = None
    failed: int | None = None
    singular: int | None = None
    distinct: bool | None = None

    @property
    def real(self) -> list[Dyad]:
        return [d for d in self.dyads if d.real]

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self.dyads)

    def __len__(self) -> int:
        return len(self.dyads)

    def report_lines(
        self, name: str, ground: str = "ground", moving: str = "moving", gap: str = " "
    ) -> list[str]:
        """A report's lines for these roots: a head (counts, what the paths did) and one
        line per root, its pivots labelled ``ground`` and ``moving``, ``gap`` between
        the fields."""
        f = lambda v: f"({v[0]:.6g}, {v[1]:.6g})"  # noqa: E731
        head = f"  {name}: {len(self.dyads)} roots, {len(self.real)} real"
        if self.paths is not None:
            head += f"; {self.paths} paths, {self.at_infinity} at infinity, {self.failed} failed"
            head += f"; distinct: {self.distinct}"
        lines = [head]
        for d in self.dyads:
            kind = "real" if d.real else "complex"
            cert = "certified" if d.certified else "NOT certified"
            lines.append(
                f"    {ground} {f(d.ground)}{gap}{moving} {f(d.moving)}{gap}"
                f"{kind}, {cert}, residual {d.residual:.1e}, radius {d.radius:.1e}"
            )
        return lines

    @classmethod
    def _from_raw(cls, raw: dict[str, Any], method: str) -> DyadSolutions:
        dyads = [
            Dyad(
                np.array(raw["ground"][k]),
                np.array(raw["moving"][k]),
                np.array(raw["ground_imag"][k]),
                np.array(raw["moving_imag"][k]),
                bool(raw["real"][k]),
                bool(raw["certified"][k]),
                float(raw["residual"][k]),
                float(raw["backward_error"][k]),
                float(raw["condition"][k]),
                float(raw["radius"][k]),
            )
            for k in range(len(raw["real"]))
        ]
        return cls(
            dyads,
            method,
            raw.get("paths"),
            raw.get("at_infinity"),
            raw.get("failed"),
            raw.get("singular"),
            raw.get("distinct"),
        )


def generic_root_count() -> int:
    """Roots of the dyad family at generic parameters: the paths every dyad problem tracks."""
    return int(_core.synth_start_set()[0])


def dyads(
    problem: str,
    poses: Any = None,
    points: Any = None,
    input_angles: Any = None,
    coupler_angles: Any = None,
    pivot: Sequence[float] | None = None,
    method: str = "homotopy",
    angles: str = "rad",
) -> DyadSolutions:
    """Every dyad of one exact problem.

    ``problem``: "burmester" (``poses``: 5 x 3), "timed" (``points``: 5 x 2 and
    ``input_angles``), "chain1" / "chain2" (the chained six-bar's dyads: ``points``,
    ``input_angles`` phi_n, ``coupler_angles`` theta_n, and as ``pivot`` the input
    link's pivot Q for "chain1", the output pivot O for "chain2"; `chained_six_bar`
    solves both and assembles the designs). ``method``: "homotopy" (every root,
    certified) or "resultant" (elimination; every root, certified).
    """
    if method not in ("homotopy", "resultant"):
        raise SynthesisError(f"method must be 'homotopy' or 'resultant', not {method!r}")
    if problem == "burmester":
        p = _array(poses, "poses", 3).copy()
        p[:, 2] = _angles(p[:, 2], angles, "pose angles")
        raw = _core.synth_dyads("burmester", method, p.ravel().tolist())
    elif problem == "timed":
        pts = _array(points, "points", 2)
        a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
        raw = _core.synth_dyads("timed", method, pts.ravel().tolist(), a.tolist())
    elif problem in ("chain1", "chain2"):
        pts = _array(points, "points", 2)
        a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
        b = _angles(_array(coupler_angles, "coupler_angles", 1), angles, "coupler angles")
        q = [] if pivot is None else [float(v) for v in pivot]
        if len(q) != 2:
            which = "the input link's pivot Q" if problem == "chain1" else "the output pivot O"
            raise SynthesisError(f"{problem} needs {which} as pivot=(x, y)")
        raw = _core.synth_dyads(problem, method, pts.ravel().tolist(), a.tolist(), b.tolist(), q)
    else:
        raise SynthesisError(f"unknown problem {problem!r}: 'burmester', 'timed', 'chain1' or 'chain2'")
    return DyadSolutions._from_raw(raw, method)
