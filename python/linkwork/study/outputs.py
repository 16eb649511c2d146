"""The figures a study keeps of each design: reductions of its sweep, computed where the
sweep runs (on the worker), so only they travel back.

=============================  =================  ==============================================
name                           shape              what
=============================  =================  ==============================================
``path P``                     (steps, 2)         the path of point P (a coupler curve), L
``angle rocker``               (steps,)           a body's angle, rad
``coordinate rocker.theta``    (steps,)           any coordinate of the model (its unit)
``transmission_min``           ()                 the smallest transmission angle over the
                                                  sweep, rad (``transmission_min NAME``: of
                                                  one linkage of several)
``grashof``                    () text            the Grashof type of the four-bar loop
                                                  (``grashof NAME``: of one of several)
``peak_effort D1``             ()                 the largest absolute effort of a driver
                                                  over the sweep (torque or force; solves the
                                                  inverse dynamics)
``events``                     () integer         singular configurations met: limits of
                                                  motion, bifurcations, branch jumps (defects);
                                                  and crossings of a slider's travel ends
``pivot_min``                  ()                 the closest approach to a singular
                                                  configuration: the smallest of the sweep's
                                                  ``pivot_ratio`` (0 = singular)
=============================  =================  ==============================================

A design whose sweep fails has NaN (or "" and -1) in every figure and its error in the
study's ``error`` variable.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import StudyError

if TYPE_CHECKING:
    from ..model.compiled import Model
    from ..model.results import Results

__all__ = ["Output", "output", "outputs", "NAMES"]

NAMES = (
    "path",
    "angle",
    "coordinate",
    "transmission_min",
    "grashof",
    "peak_effort",
    "events",
    "pivot_min",
)


@dataclass(frozen=True)
class Output:
    """A figure of each design: ``name`` as asked, ``kind``, ``target`` (the point, body,
    coordinate, linkage or driver it is of), ``key`` (its variable in the dataset),
    ``dims`` after the design's ("step", "xy"), ``unit`` and ``dtype``."""

    name: str
    kind: str
    target: str
    key: str
    dims: tuple[str, ...]
    unit: str
    dtype: str = "float64"

    @property
    def forces(self) -> bool:
        return self.kind == "peak_effort"

    def shape(self, n_steps: int) -> tuple[int, ...]:
        return tuple(n_steps if d == "step" else 2 for d in self.dims)

    def empty(self, n: int, n_steps: int) -> np.ndarray:
        fill: Any = {"float64": np.nan, "int64": -1}.get(self.dtype, "")
        dtype = object if self.dtype == "str" else self.dtype
        return np.full((n, *self.shape(n_steps)), fill, dtype=dtype)

    def compute(self, model: Model, results: Results) -> Any:
        """This figure of one design's sweep."""
        if self.kind == "path":
            return results.point(self.target).position
        if self.kind == "angle":
            return results.body(self.target).theta
        if self.kind == "coordinate":
            return results.q[:, model._column_index[self.target]]
        if self.kind == "transmission_min":
            return float(np.min(results.transmission_angle(self.target or None)))
        if self.kind == "grashof":
            found = model.linkages(float(results.times[0]), results.q[0])
            four_bars = [
                f for f in found if f.kind == "four-bar" and (not self.target or f.name == self.target)
            ]
            if len(four_bars) != 1:
                names = [f.name for f in found if f.kind == "four-bar"]
                raise StudyError(f"output {self.name!r}: the design has four-bar loops {names}; name one")
            return four_bars[0].kind_of
        if self.kind == "peak_effort":
            return float(np.max(np.abs(results.effort(self.target))))
        if self.kind == "events":
            return len(results.events)
        return float(np.min(results.pivot_ratio))


def _key(text: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in text).strip("_")


def output(model: Model, name: str) -> Output:
    """The output ``name`` for ``model``, checked (its point, body, coordinate or driver
    exists); `StudyError` says what exists."""
    if isinstance(name, Output):
        return name
    if not isinstance(name, str) or not name.strip():
        raise StudyError(f"an output is named by a string, not {name!r}")
    kind, _, target = name.strip().partition(" ")
    target = target.strip()
    units = model.units
    if kind not in NAMES:
        raise StudyError(
            f"unknown output {name!r}; the outputs are {', '.join(NAMES)} (see linkwork.study.outputs)"
        )
    if kind == "path":
        points = [p["name"] for p in model.description.get("points", [])]
        if target not in points:
            raise StudyError(
                f"output {name!r}: no point {target!r}; the points are {', '.join(points) or 'none'}"
            )
        return Output(name, kind, target, f"path_{_key(target)}", ("step", "xy"), units["length"])
    if kind == "angle":
        if target not in model.body_names:
            raise StudyError(
                f"output {name!r}: no body {target!r}; the bodies are {', '.join(model.body_names)}"
            )
        return Output(name, kind, target, f"angle_{_key(target)}", ("step",), "rad")
    if kind == "coordinate":
        if target not in model.columns:
            raise StudyError(
                f"output {name!r}: no coordinate {target!r}; the coordinates are {', '.join(model.columns)}"
            )
        unit = "rad" if target.endswith(".theta") else units["length"]
        return Output(name, kind, target, f"q_{_key(target)}", ("step",), unit)
    if kind == "peak_effort":
        drivers = [c[0] for c in model.constraints if c[1] == "driver"]
        if target not in drivers:
            raise StudyError(f"output {name!r}: no driver {target!r}; the drivers are {', '.join(drivers)}")
        kinds = {c[0]: c[2] for c in model.constraints}
        unit = units["torque"] if "angle" in kinds[target] else units["force"]
        return Output(name, kind, target, f"peak_effort_{_key(target)}", (), unit)
    if kind == "grashof":
        return Output(name, kind, target, _key(name), (), "", "str")
    if kind == "events":
        return Output(name, kind, "", "events", (), "", "int64")
    if kind == "transmission_min":
        return Output(name, kind, target, _key(name), (), "rad")
    return Output(name, kind, "", "pivot_min", (), "")


def outputs(model: Model, names: Sequence[Any]) -> list[Output]:
    """Each output checked; the same one twice is a `StudyError`."""
    if isinstance(names, str):
        names = [names]
    out = [output(model, n) for n in names]
    if not out:
        raise StudyError("a study needs at least one output (e.g. 'path P', 'transmission_min')")
    keys = [o.key for o in out]
    twice = sorted({k for k in keys if keys.count(k) > 1})
    if twice:
        raise StudyError(f"output {twice[0]!r} is asked for twice")
    return out
