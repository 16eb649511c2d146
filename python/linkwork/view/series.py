"""What a sweep's figures and page show, by name, without drawing: outputs (a coordinate
column, a body's angle, a named point's x or y), the abscissa (time or the input of a
driver), each driver's input over the steps, and the paths drawn by default. The plots
(`figures`), the page (`page`), the SVG (`export`) and the notebook read them.

>>> import numpy as np
>>> from linkwork import examples
>>> res = examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 11))
>>> [output(res, name).name for name in ("rocker", "coupler.x", "P.y")]
['rocker.theta', 'coupler.x', 'P.y']
>>> default_outputs(res)
['crank', 'coupler', 'rocker']
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..kinds import kind as kind_of
from .drawing import Geometry

if TYPE_CHECKING:
    from linkwork import Model, Results, Simulation

__all__ = [
    "Output",
    "output",
    "default_outputs",
    "unknown_outputs",
    "X_AXES",
    "XAxis",
    "x_axis",
    "unknown_x",
    "inputs",
    "default_paths",
    "unknown_paths",
    "Chart",
    "simulation_charts",
]


@dataclass(frozen=True)
class Output:
    """One output over a sweep: its value, rate and acceleration (None where the sweep
    did not solve them), each (n_steps,), and its unit."""

    name: str
    unit: str
    value: np.ndarray
    rate: np.ndarray | None
    acceleration: np.ndarray | None


def _point_names(model: Model) -> list[str]:
    return list(model.point_names)


def _find(model: Model, name: str) -> tuple[str, int] | None:
    """("column", column index) or ("point", axis) for an output name; None if unknown."""
    if name in model.columns:
        return "column", model.columns.index(name)
    if name in model.body_names:
        return "column", model.columns.index(f"{name}.theta")
    point, _, axis = name.rpartition(".")
    if axis in ("x", "y") and point in _point_names(model):
        return "point", "xy".index(axis)
    return None


def unknown_outputs(model: Model, names: Sequence[str]) -> str | None:
    """A message naming the outputs that do not exist and what does, or None."""
    bad = [n for n in names if _find(model, n) is None]
    if not bad:
        return None
    points = ", ".join(f"{p}.x, {p}.y" for p in _point_names(model)) or "none"
    return (
        f"no output named {', '.join(map(repr, bad))}; an output is a column "
        f"({', '.join(model.columns)}), a body (its angle: {', '.join(model.body_names)}) "
        f"or a point's coordinate ({points})"
    )


def _length_unit(results: Results) -> str:
    return results.units(results.columns[0]) if results.columns else "m"


def output(results: Results, name: str) -> Output:
    """The output called ``name`` (a column, a body's angle or ``POINT.x`` / ``POINT.y``)."""
    found = _find(results.model, name)
    if found is None:
        raise KeyError(unknown_outputs(results.model, [name]))
    kind, k = found
    if kind == "column":
        column = results.columns[k]

        def col(a: np.ndarray | None) -> np.ndarray | None:
            return None if a is None else a[:, k]

        assert results.q is not None
        return Output(column, results.units(column), results.q[:, k], col(results.qd), col(results.qdd))
    p = results.point(name.rpartition(".")[0])

    def axis(a: np.ndarray | None) -> np.ndarray | None:
        return None if a is None else a[:, k]

    return Output(name, _length_unit(results), p.position[:, k], axis(p.velocity), axis(p.acceleration))


#: outputs and paths drawn when none are named, at most (a large model has thousands;
#: name them with --outputs / --paths)
MAX_DEFAULT = 12


def default_outputs(results: Results) -> list[str]:
    """The outputs plotted when none are named: the angle of every body that turns, and
    x and y of every body that only translates (a slider), where they change."""
    names: list[str] = []
    tol = 1e-9 * results.model.length_scale
    for body in results.model.body_names:
        b = results.body(body)
        if np.ptp(b.theta) > 1e-9:
            names.append(body)
            continue
        names += [f"{body}.{c}" for c, v in (("x", b.x), ("y", b.y)) if np.ptp(v) > tol]
        if len(names) >= MAX_DEFAULT:
            break
    return (names or list(results.model.body_names))[:MAX_DEFAULT]


#: what the outputs can be plotted against (or a driver's name)
X_AXES = ("time", "input")


@dataclass(frozen=True)
class XAxis:
    """The abscissa of the figures of outputs: its label, unit and value at every step."""

    label: str
    unit: str
    value: np.ndarray


def _input_driver(model: Model, x: str) -> tuple[str | None, str | None]:
    """(the driver plotted against for ``x``, None) or (None, why there is none)."""
    drivers = [d for d in model.description.get("drivers", [])]
    names = [str(d.get("name")) for d in drivers]
    if x in names:
        return x, None
    if x != "input":
        return None, (
            f"--x must be time, input or a driver's name ({', '.join(names) or 'the model has no drivers'}), "
            f"not {x!r}"
        )
    cycle = model.cycle()
    if cycle is not None:
        return cycle.driver, None
    moving = [str(d.get("name")) for d in drivers if d.get("law", {}).get("type") != "constant"]
    if len(moving) == 1:
        return moving[0], None
    return None, (
        f"--x input needs one moving driver; the model has {len(moving)} ({', '.join(moving) or 'none'}): "
        "name one with --x DRIVER"
    )


def unknown_x(model: Model, x: str) -> str | None:
    """Why the outputs cannot be plotted against ``x`` (time, input or a driver's name),
    or None."""
    return None if x == "time" else _input_driver(model, x)[1]


def x_axis(results: Results, x: str = "time") -> XAxis:
    """The abscissa ``x``: "time" (s), or "input", the input of the model's driver (its
    periodic driver, else its only moving one) or of the driver named ``x``: an angle in
    the file's angle unit (deg or rad), a distance in the length unit. A bad ``x`` is an
    `InputError` saying what is allowed."""
    if not isinstance(x, str):
        raise InputError(f"x must be time, input or a driver's name, not {x!r}")
    if x == "time":
        return XAxis("t", "s", np.asarray(results.times))
    driver, problem = _input_driver(results.model, x)
    if problem:
        raise InputError(problem)
    rows = np.arange(results.n_steps)
    found = [d for d in inputs(results, Geometry.from_model(results.model), rows) if d["name"] == driver]
    if not found:
        raise InputError(f"the input of driver {driver!r} cannot be read from the sweep")
    d = found[0]
    value = np.asarray(d["value"], dtype=np.float64)
    unit = d["unit"]
    if d["angle"] and results.model.units.get("input_angle") == "deg":
        value, unit = np.degrees(value), "deg"
    return XAxis(str(driver), unit, value)


def default_paths(model: Model) -> list[str]:
    """The paths drawn when none are named: every named point's, or if the model has
    none, every pin's that is not on the ground."""
    points = _point_names(model)
    if points:
        return points[:MAX_DEFAULT]
    g = Geometry.from_model(model)
    ground = {g.anchors[k].name for k in g.ground_pins}
    return [g.anchors[k].name for k in g.pins if g.anchors[k].name not in ground][:MAX_DEFAULT]


def unknown_paths(model: Model, names: Sequence[str]) -> str | None:
    """A message naming the paths that cannot be drawn and those that can, or None."""
    traceable = Geometry.from_model(model).traceable
    bad = [n for n in names if n not in traceable]
    if not bad:
        return None
    return (
        f"no point or joint named {', '.join(map(repr, bad))}; paths can be drawn of: {', '.join(traceable)}"
    )


def _numbers(a: Any) -> Any:
    """A JSON-ready list of an array, non-finite values as null."""
    a = np.asarray(a, dtype=np.float64)
    out = a.tolist()
    if np.all(np.isfinite(a)):
        return out
    cleaned = a.astype(object)
    cleaned[~np.isfinite(a)] = None
    return cleaned.tolist()


def inputs(results: Results, geometry: Geometry, rows: np.ndarray) -> list[dict[str, Any]]:
    """Each driver's input at the steps ``rows``: name, unit, values and whether it is an
    angle (angle and relative-angle drivers: the angle; distance drivers: the distance
    between their points; coordinate drivers: the coordinate; translation drivers: the
    slide from the drawing). A driver of another type is left out."""
    q = results.q[rows]
    length = results.model.units["length"]
    names = results.model.body_names
    xy = geometry.world(q)

    def theta(body: str) -> np.ndarray:
        return q[:, 3 * names.index(body) + 2] if body in names else np.zeros(len(rows))

    def anchors(name: str) -> list[int]:
        return [k for k, a in enumerate(geometry.anchors) if a.name == name and a.kind == "driver"]

    out = []
    for d in results.model.description.get("drivers", []):
        name = str(d.get("name"))
        driver = kind_of("drivers", d.get("type"))
        law = driver.input if driver else None
        sets = law.input if law else None  # what the driver's law sets
        value: np.ndarray | None = None
        if sets == "angle":
            value = theta(str(d["body"]))
        elif sets == "relative_angle":
            value = theta(str(d["body_b"])) - theta(str(d["body_a"]))
        elif sets == "distance" and len(anchors(name)) == 2:
            a, b = anchors(name)
            value = np.hypot(*(xy[:, b] - xy[:, a]).T)
        elif sets == "coordinate" and len(anchors(name)) == 1:
            value = xy[:, anchors(name)[0], "xy".index(str(d.get("axis", "x")))]
        elif sets == "slide":
            found = [k for k, s in enumerate(geometry.sliders) if s.joint == d.get("joint")]
            if found:
                s = geometry.sliders[found[0]]
                start = geometry.world(geometry._q_start[None, :])[0]
                axis = geometry.axis_world(q, s)
                rel = xy[:, s.block] - xy[:, s.guide] - (start[s.block] - start[s.guide])
                value = np.einsum("ij,ij->i", rel, axis)
        if value is not None and law is not None:
            angle = law.unit == "angle"
            out.append(
                {"name": name, "unit": "rad" if angle else length, "angle": angle, "value": _numbers(value)}
            )
    return out


@dataclass(frozen=True)
class Chart:
    """A plot of a simulation beside its outputs: a title, the unit of its lines, and
    the lines by name, each (n_steps,)."""

    title: str
    unit: str
    lines: dict[str, np.ndarray]


def simulation_charts(sim: Simulation) -> list[Chart]:
    """What a simulation shows beside a sweep's outputs: its energy (kinetic, potential,
    work of what is not conservative), the balance's error, the constraints' drift
    before projection, and the rates of the default outputs' coordinates, grouped by
    unit."""
    e = sim.energy()
    energy = str(sim.model.units["energy"])
    charts = [
        Chart(
            "energy",
            energy,
            {"kinetic": e.kinetic, "potential": e.potential, "work not conservative": e.work},
        ),
        Chart("energy balance error", energy, {"balance": e.balance}),
        Chart(
            "constraint drift before projection",
            "",
            {"drift |Phi| (scaled)": sim.drift, "drift |Phi_q qd - nu|": sim.drift_d},
        ),
    ]
    rates: dict[str, dict[str, np.ndarray]] = {}
    for name in default_outputs(sim):
        o = output(sim, name)
        if o.rate is not None:
            rates.setdefault(f"{o.unit}/s", {})[f"{o.name}_d"] = o.rate
    charts += [Chart("rates", unit, lines) for unit, lines in rates.items()]
    return charts
