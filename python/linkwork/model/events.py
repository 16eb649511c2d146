"""Events of a sweep (limits of motion, bifurcations, locks, branch jumps, ends of a
slider's travel) and limits of motion of a driven input. See docs/analysis.md for what
each means and what to do.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["KINDS", "Event", "MotionLimits"]

#: what each event kind means, in a sentence
KINDS = {
    "limit": "a driver reaches a limit of motion: beyond it the mechanism cannot be assembled "
    "unless the driver reverses",
    "bifurcation": "assembly branches meet: the joints' rows become dependent; the sweep follows "
    "the branch it was on",
    "lock": "an output stops and reverses while the input moves (a dead point if driven from that output); "
    "in a simulation, the whole motion stops and reverses, or a slider reaches the end of its stroke",
    "branch_jump": "the solution left the branch it was on and halving the step did not bring it back",
    "end_of_travel": "a slider crosses an end of the travel its prismatic joint is given: a simulation "
    "stops there or goes on, a sweep goes on through it (kinematics models no stop) and also reports "
    "where the slider comes back inside",
}


@dataclass(frozen=True)
class Event:
    """A located event of a sweep or a simulation.

    ``kind``: "limit", "bifurcation", "lock", "branch_jump" or "end_of_travel" (see `KINDS`); ``step``:
    it lies between times[step - 1] and times[step]; ``time``: where it was located;
    ``q``: the configuration there; ``sigma_min``: smallest singular value of the scaled
    Phi_q there; ``constraints`` / ``coordinates``: the (name, share) of the joints and
    drivers in the dependency and of the coordinates in the free motion; ``output``: the
    output that locks; ``drivers``: (name, value) of each driver there; ``pivot_ratio``:
    of the sweep's Phi_q there, or the smallest of the augmented matrix a simulation's
    solves met around it. A simulation's lock is the whole motion stopping and reversing
    (``sigma_min`` NaN, ``output`` the coordinate that turns back), or a slider at the end
    of its stroke (``output`` its prismatic joint); an "end_of_travel" names the joint
    (``output``), the end and its time.
    """

    kind: str
    step: int
    time: float
    q: np.ndarray = field(repr=False)
    sigma_min: float
    constraints: tuple[tuple[str, float], ...]
    coordinates: tuple[tuple[str, float], ...]
    output: str | None
    drivers: tuple[tuple[str, float], ...]
    message: str
    pivot_ratio: float = float("nan")

    @classmethod
    def from_raw(cls, raw: dict[str, Any]) -> Event:
        return cls(
            kind=raw["kind"],
            step=int(raw["step"]),
            time=float(raw["time"]),
            q=np.asarray(raw["q"]),
            sigma_min=float(raw["sigma_min"]),
            constraints=tuple((str(n), float(s)) for n, s in raw["constraints"]),
            coordinates=tuple((str(n), float(s)) for n, s in raw["coordinates"]),
            output=raw["output"],
            drivers=tuple((str(n), float(v)) for n, v in raw["drivers"]),
            message=raw["message"],
            pivot_ratio=float(raw.get("pivot_ratio", float("nan"))),
        )

    def driver(self, name: str | None = None) -> float:
        """The value of driver ``name`` (default: the only or first driver) at the event."""
        for n, v in self.drivers:
            if name is None or n == name:
                return v
        raise KeyError(f"no driver {name!r} at this event; drivers: {[n for n, _ in self.drivers]}")

    def __str__(self) -> str:
        joints = ", ".join(f"{n} ({s:.2f})" for n, s in self.constraints[:6])
        extra = f"; involves {joints}" if joints and self.kind != "lock" else ""
        return f"{self.kind} at t = {self.time:.10g} (step {self.step}): {self.message}{extra}"


@dataclass(frozen=True)
class MotionLimits:
    """The range of a driver's input over which the mechanism assembles, on one branch.

    ``lower`` / ``upper``: the limits (None: no limit within ``range`` of ``start``);
    ``full_rotation``: an angle input that turns a whole revolution both ways.
    """

    driver: str
    angle: bool
    start: float
    lower: float | None
    upper: float | None
    full_rotation: bool
    range: float
    events: tuple[Event, ...]

    @classmethod
    def from_raw(cls, raw: dict[str, Any]) -> MotionLimits:
        return cls(
            driver=raw["driver"],
            angle=bool(raw["angle"]),
            start=float(raw["start"]),
            lower=raw["lower"],
            upper=raw["upper"],
            full_rotation=bool(raw["full_rotation"]),
            range=float(raw["range"]),
            events=tuple(Event.from_raw(e) for e in raw["events"]),
        )

    def __str__(self) -> str:
        return self.describe()

    def describe(self, angles: str = "rad", length: str = "m") -> str:
        """One line: the limits either way and the start; an angle input in rad (with
        degrees beside), or in deg with ``angles="deg"``; a distance in ``length``."""
        if angles not in ("rad", "deg"):
            raise ValueError(f"angles must be 'rad' or 'deg', not {angles!r}")
        unit = angles if self.angle else length
        k = np.degrees(1.0) if self.angle and angles == "deg" else 1.0
        if self.full_rotation:
            return f"{self.driver}: turns fully (no limit within a revolution either way)"

        def fmt(v: float | None, way: str) -> str:
            if v is None:
                return f"none within {self.range * k:g} {unit} {way}"
            deg = f" ({np.degrees(v):.6g} deg)" if self.angle and angles == "rad" else ""
            return f"{v * k:.12g} {unit}{deg}"

        return (
            f"{self.driver}: from {fmt(self.lower, 'below')} to {fmt(self.upper, 'above')} "
            f"(start {self.start * k:.6g} {unit})"
        )
