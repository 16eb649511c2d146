"""The classical linkages inside a model (four-bar loops, slider-cranks): Grashof type,
the input's limits of motion in closed form, the circuit, the transmission angle; and
the assembly modes of a mechanism at one input.

Conventions (R. L. Norton, *Design of Machinery*, and `linkwork.closed_form`): the crank
pivot O2, the rocker pivot O4 (or the slide line), the crank the driven ground-pinned
link; "open" and "crossed" circuits as in `closed_form.four_bar` and
`closed_form.slider_crank` (for a slider-crank: open when the slider pin is ahead of the
crank pin along the prismatic joint's axis).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _args

__all__ = ["Linkage", "AssemblyMode", "AssemblyModes"]


@dataclass(frozen=True)
class Linkage:
    """A four-bar loop or a slider-crank of a model, at one configuration.

    ``lengths``: ground, crank, coupler, rocker (four-bar) or crank, rod, offset
    (slider-crank). ``kind_of``: the Grashof type for a four-bar (crank-rocker,
    double-crank, rocker-crank, Grashof double-rocker, non-Grashof triple-rocker, change
    point), "crank turns" / "crank rocks" / "change point" for a slider-crank.
    ``input_limits``: the crank's angle range (its body angle, rad) around the current
    one, from the triangle inequalities; None if it turns fully. ``stroke``: the slider
    pin's travel along the axis from the foot of O2 (slider-crank whose crank turns).
    ``transmission_angle`` (rad): four-bar: the angle at B between coupler and rocker, in
    [0, pi]; slider-crank: between the rod and the normal to the slide, in [0, pi/2];
    best at pi/2.
    """

    kind: str
    name: str
    bodies: tuple[str, str, str]
    joints: tuple[str, str, str, str]
    lengths: dict[str, float]
    kind_of: str
    driven: bool
    input_limits: tuple[float, float] | None
    circuit: str
    transmission_angle: float
    stroke: tuple[float, float] | None = None
    raw: dict[str, Any] = field(default=None, repr=False, compare=False)  # type: ignore[assignment]

    @classmethod
    def from_raw(cls, raw: dict[str, Any], body_names: list[str]) -> Linkage:
        bodies = tuple(body_names[i] for i in raw["bodies"])
        if raw["kind"] == "four-bar":
            lengths = dict(zip(("ground", "crank", "coupler", "rocker"), raw["lengths"]))
            kind_of = str(raw["class"])
        else:
            lengths = dict(zip(("crank", "rod", "offset"), raw["lengths"]))
            kind_of = (
                "change point"
                if raw["change_point"]
                else "crank turns"
                if raw["crank_turns"]
                else "crank rocks"
            )
        limits = raw["input_limits"]
        stroke = raw.get("stroke")
        return cls(
            kind=str(raw["kind"]),
            name=str(raw["name"]),
            bodies=bodies,  # type: ignore[arg-type]
            joints=tuple(raw["joints"]),  # type: ignore[arg-type]
            lengths={k: float(v) for k, v in lengths.items()},
            kind_of=kind_of,
            driven=bool(raw["driven"]),
            input_limits=None if limits is None else (float(limits[0]), float(limits[1])),
            circuit=str(raw["circuit"]),
            transmission_angle=float(raw["transmission_angle"]),
            stroke=None if stroke is None else (float(stroke[0]), float(stroke[1])),
            raw=raw,
        )

    def __str__(self) -> str:
        return self.describe()

    def describe(self, angles: str = "rad") -> str:
        """One line: lengths, type, the crank's limits, circuit, transmission angle and
        stroke; angles in rad (as every angle in Python), or in deg with ``angles="deg"``
        (``linkwork check`` uses the file's angle unit)."""
        _args.choice(angles, "angles", ("rad", "deg"))
        k = math.degrees(1.0) if angles == "deg" else 1.0
        digits = 4 if angles == "deg" else 6
        lengths = ", ".join(f"{k} {v:.6g}" for k, v in self.lengths.items())
        if self.input_limits is None:
            limits = "the crank turns fully"
        else:
            lo, hi = (v * k for v in self.input_limits)
            limits = f"crank angle limits {lo:.{digits}f} .. {hi:.{digits}f} {angles}"
        text = (
            f"{self.kind} {self.name} ({lengths}): {self.kind_of}; {limits}; {self.circuit} circuit; "
            f"transmission angle {self.transmission_angle * k:.{digits - 2}f} {angles}"
        )
        if self.stroke is not None:
            text += f"; stroke {self.stroke[1] - self.stroke[0]:.6g}"
        return text

    def transmission_angle_of(self, results: Any) -> np.ndarray:
        """The transmission angle (rad) at every step of ``results`` (or one state)."""
        raw = self.raw
        crank, coupler, rocker = self.bodies
        if self.kind == "four-bar":
            a = results.point_at(crank, raw["a_on_crank"]).position
            b = results.point_at(rocker, raw["b_on_rocker"]).position
            u, v = a - b, np.asarray(raw["o4"]) - b
            cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
            return np.abs(np.arctan2(cross, np.sum(u * v, axis=-1)))
        a = results.point_at(crank, raw["a_on_crank"]).position
        b = results.point_at(coupler, raw["b_on_rod"]).position
        rod = b - a
        e = np.asarray(raw["axis"])
        # the rod against the slide's normal: pi/2 minus its angle to the axis
        along = np.abs(np.sum(rod * e, axis=-1)) / np.linalg.norm(rod, axis=-1)
        return np.arcsin(np.clip(along, 0.0, 1.0))


@dataclass(frozen=True)
class AssemblyMode:
    """One assembly mode: the configuration ``q``, the sign of det Phi_q, the pivot
    ratio, and each recognised linkage's circuit (name -> "open" / "crossed")."""

    q: np.ndarray = field(repr=False)
    det_sign: float
    pivot_ratio: float
    circuits: dict[str, str]


@dataclass(frozen=True)
class AssemblyModes:
    """The assembly modes found (the first nearest the reference configuration), and how
    many starting guesses were tried and converged."""

    modes: tuple[AssemblyMode, ...]
    tries: int
    converged: int

    def __len__(self) -> int:
        return len(self.modes)

    def __getitem__(self, k: int) -> AssemblyMode:
        return self.modes[k]

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self.modes)

    def find(self, branch: str | dict[str, str]) -> AssemblyMode:
        """The mode whose circuits match ``branch``: "open" or "crossed" (for a mechanism
        with one recognised linkage, or the same for all), or {linkage name: circuit}."""
        for m in self.modes:
            if isinstance(branch, str):
                if m.circuits and all(c == branch for c in m.circuits.values()):
                    return m
            elif all(m.circuits.get(k) == v for k, v in branch.items()):
                return m
        found = [m.circuits for m in self.modes]
        raise ValueError(f"no assembly mode has circuits {branch!r}; the modes found have {found}")
