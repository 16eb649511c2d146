"""A varied description redrawn: `apply` and `apply_many` set parameters (`parameters`)
and, where they move a pin or change a link's length, redraw the mechanism at the
configuration the engine assembles: one closing model per batch (each moved pin held by
two perpendicular slots through its new place, the drivers at their values at the start),
every body keeping every local vector except the ones the parameters move. A varied
mechanism that does not close raises the engine's `AssemblyError`."""

from __future__ import annotations

import json
import math
import pickle
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .. import _core
from ..errors import LinkworkError, ParameterError
from ..kinds import FEATURES
from ..model.compiled import Model
from ..motion import Spline
from .naming import GROUPS, Parameter, _description, _units, _value, parameter

__all__ = ["apply", "apply_many"]


def apply(description: Any, values: Mapping[Any, Any], **options: Any) -> dict[str, Any]:
    """A new description with each parameter set to its value (the given description is
    not changed). Link lengths and pins are applied by redrawing the mechanism (see the
    module's notes; ``options`` are the compile options of that assembly).

    >>> from linkwork import examples
    >>> from linkwork.study import apply, parameter
    >>> desc = examples.four_bar().to_dict()
    >>> varied = apply(desc, {"length crank": 0.21})
    >>> [round(parameter(varied, f"length {b}").nominal, 12) for b in ("crank", "coupler", "rocker")]
    [0.21, 0.35, 0.25]
    """
    desc = _description(description)
    if not isinstance(values, Mapping):
        raise ParameterError(f"values are a dict {{parameter: value}}, not {type(values).__name__}")
    params = [parameter(desc, key) for key in values]
    row = [_value(p, v) for p, v in zip(params, values.values())]
    (out,) = apply_many(desc, params, [row], **options)
    if isinstance(out, Exception):
        raise out
    return out


# paths whose numbers do not change how the mechanism closes: designs varying only these
# and pins share one closing model
_NOT_CLOSING = ("points", "loads", "gravity")


def apply_many(
    description: Any, params: Sequence[Parameter], rows: Any, **options: Any
) -> list[dict[str, Any] | Exception]:
    """`apply` for many designs of the same parameters (``rows``: one value per parameter
    each): a description per design, or the `LinkworkError` that design raises (a value
    out of range, a mechanism that does not close). The designs' redraws share one
    closing model, each solved from the drawing at its own time, so a design's
    description does not depend on the others."""
    desc = _description(description)
    params = [parameter(desc, p) for p in params]
    out: list[dict[str, Any] | Exception] = []
    moves_of: list[dict[tuple[str, str], list[float]]] = []
    for row in rows:
        try:
            values = [_value(p, v) for p, v in zip(params, row)]
            varied = _copy(desc)
            moves: dict[tuple[str, str], list[float]] = {}
            for p, v in zip(params, values):
                if p.kind == "path":
                    _set(varied, p.path, v)
                    continue
                j = _joint(desc, p.joint)
                target = moves.setdefault((p.joint, p.body), list(map(float, j["at"])))
                if p.kind == "pin":
                    target[p.axis] = v
                else:
                    a = _joint(desc, p.anchor)["at"]
                    scale = v / p.nominal
                    target[0] = a[0] + (j["at"][0] - a[0]) * scale
                    target[1] = a[1] + (j["at"][1] - a[1]) * scale
            moves = {k: xy for k, xy in moves.items() if xy != list(map(float, _joint(desc, k[0])["at"]))}
            out.append(varied)
            moves_of.append(moves)
        except LinkworkError as e:
            out.append(e)
            moves_of.append({})
    todo = [i for i, m in enumerate(moves_of) if m and not isinstance(out[i], Exception)]
    if not todo:
        return out
    shared = all(
        p.kind != "path"
        or p.path[0] in _NOT_CLOSING
        or (p.path[0] == "bodies" and p.path[2] in ("mass", "inertia", "com"))
        for p in params
    )
    groups = [todo] if shared else [[i] for i in todo]
    # the closing model carries every pin the parameters can move, whether a design moves it
    # or not: its structure, so each design's redraw, does not depend on the other designs
    sides = sorted({(p.joint, p.body) for p in params if p.kind != "path"})
    for group in groups:
        base = desc if shared else out[group[0]]
        closed = _close(base, sides, [moves_of[i] for i in group], options)  # type: ignore[arg-type]
        for i, poses in zip(group, closed):
            out[i] = poses if isinstance(poses, Exception) else _rewrite(out[i], poses, moves_of[i])  # type: ignore[arg-type]
    return out


def _copy(desc: Mapping[str, Any]) -> dict[str, Any]:
    """A deep copy of a description (plain data: a pickle round trip is the fastest)."""
    return pickle.loads(pickle.dumps(desc, -1))


def _joint(desc: Mapping[str, Any], name: str) -> dict[str, Any]:
    return next(j for j in desc["joints"] if j["name"] == name)


def _set(desc: dict[str, Any], path: tuple[Any, ...], value: float) -> None:
    node: Any = desc
    keys = list(path)
    if keys[0] in GROUPS:
        node = next(i for i in desc[keys[0]] if i.get("name") == keys[1])
        keys = keys[2:]
    for k in keys[:-1]:
        node = node[k]
    node[keys[-1]] = value


# which body's frame carries each world point ("p") or direction ("d") of the description:
# the joints' and drivers' from their types' roles
_FEATURES: dict[str, dict[str, tuple[tuple[str, str, str], ...]]] = {
    **FEATURES,
    "points": {"": (("at", "body", "p"),)},
    "loads": {
        "force": (("at", "body", "p"),),
        "spring": (("at_a", "body_a", "p"), ("at_b", "body_b", "p")),
    },
}


def _close(
    desc: dict[str, Any],
    sides: list[tuple[str, str]],
    moves: list[dict[tuple[str, str], list[float]]],
    options: Mapping[str, Any],
) -> list[dict[str, tuple[float, float, float]] | Exception]:
    """The closed configuration (each body's new x, y, theta) of each design, its pins
    moved as ``moves`` say, every other local vector kept, the drivers at their values at
    the start: one closing model for all of them. Each moved pin is cut; on each side that
    moves, two sliders along the world axes of the drawing (fixed in that side's body)
    carry it, their slides driven to the design's offset at the design's time (a spline
    through the designs, exact at its knots), and the two sides are pinned again."""
    temp = _copy(desc)
    # the mechanism's own drivers held at their values at the start
    for d in temp.get("drivers", []):
        value = float(_law_at(d["law"], 0.0))
        d["law"] = {"type": "constant", "value": value}
    cut = {joint for joint, _ in sides}
    temp["joints"] = [j for j in temp["joints"] if j["name"] not in cut]
    n = len(moves)
    knots = list(map(float, range(max(n, 2))))
    carrier: dict[tuple[str, str], str] = {}
    for joint, body in sides:
        j = _joint(desc, joint)
        at = list(map(float, j["at"]))
        last = body
        for k, axis in enumerate(([1.0, 0.0], [0.0, 1.0])):
            helper = f"{joint}~{body}~{k}"
            temp["bodies"].append({"name": helper, "x": at[0], "y": at[1], "theta": 0.0})
            slider = {"type": "prismatic", "name": f"{helper}~p", "body_a": last, "body_b": helper}
            temp["joints"].append({**slider, "at": at, "axis": axis})
            offsets = [m[(joint, body)][k] - at[k] if (joint, body) in m else 0.0 for m in moves]
            offsets += offsets[-1:] * (len(knots) - n)
            law = Spline(knots, offsets)
            if not np.array_equal(law.evaluate(knots)[:, 0], np.asarray(offsets)):
                raise ParameterError("internal: a spline that misses its knots")  # pragma: no cover
            drive = {"type": "translation", "name": f"{helper}~d", "joint": f"{helper}~p"}
            temp["drivers"].append({**drive, "law": law.to_dict()})
            last = helper
        carrier[(joint, body)] = last
    for joint in cut:
        j = _joint(desc, joint)
        a = carrier.get((joint, j["body_a"]), j["body_a"])
        b = carrier.get((joint, j["body_b"]), j["body_b"])
        temp["joints"].append(
            {"type": "revolute", "name": joint, "body_a": a, "body_b": b, "at": list(j["at"])}
        )
    model = Model._checked(temp, dict(options))
    q0 = np.asarray(model.q_start, dtype=np.float64)
    col = model._column_index
    names = [b["name"] for b in desc["bodies"]]
    out: list[dict[str, tuple[float, float, float]] | Exception] = []
    for k, m in enumerate(moves):
        try:
            q = model.solve(float(k), q_guess=q0).q
        except LinkworkError as e:
            # the same kind of error, said of the varied mechanism (not of the closing one)
            moved = ", ".join(f"{jn} in {b} to ({xy[0]:.6g}, {xy[1]:.6g})" for (jn, b), xy in m.items())
            # the closing model's time is the design's place in its batch: not said
            text = re.sub(r"\s*(at )?\(?t = [-+0-9.e]+\)?", "", str(e).split(";")[0])
            out.append(type(e)(f"the mechanism with pin {moved} does not close: {text}"))
            continue
        out.append(
            {
                b: (float(q[col[f"{b}.x"]]), float(q[col[f"{b}.y"]]), float(q[col[f"{b}.theta"]]))
                for b in names
            }
        )
    return out


def _law_at(law: Mapping[str, Any], t: float) -> float:
    """A law's value at ``t`` as the description writes it (its own units)."""
    return float(_core.evaluate_law(json.dumps(law), np.asarray([t]), None)[0][0])


def _rewrite(
    desc: dict[str, Any],
    new: Mapping[str, tuple[float, float, float]],
    moves: Mapping[tuple[str, str], list[float]],
) -> dict[str, Any]:
    """The description redrawn at the closed configuration ``new`` (every body's x, y,
    theta; angles in radians), each moved pin where its new places meet. Changed in place."""
    _, angle_unit = _units(desc)
    to_rad = math.pi / 180.0 if angle_unit == "deg" else 1.0
    old = {b["name"]: (b["x"], b["y"], b["theta"] * to_rad) for b in desc["bodies"]}

    def carry(body: str, xy: Sequence[float], kind: str) -> list[float]:
        if body == "ground" or body not in old:
            return [float(xy[0]), float(xy[1])]
        x0, y0, t0 = old[body]
        x1, y1, t1 = new[body]
        dx, dy = (xy[0] - x0, xy[1] - y0) if kind == "p" else (xy[0], xy[1])
        c, s = math.cos(t1 - t0), math.sin(t1 - t0)
        rx, ry = c * dx - s * dy, s * dx + c * dy
        return [x1 + rx, y1 + ry] if kind == "p" else [rx, ry]

    places = {}
    for joint, _ in moves:
        j = _joint(desc, joint)
        at = list(map(float, j["at"]))
        places[joint] = (moves.get((joint, j["body_a"]), at), moves.get((joint, j["body_b"]), at))
    for group, table in _FEATURES.items():
        for item in desc.get(group, []):
            for field, side, kind in table.get(item.get("type", ""), ()):
                if field in item and item[field] is not None:
                    item[field] = carry(item[side], item[field], kind)
    for b in desc["bodies"]:
        if b.get("com") is not None:
            b["com"] = carry(b["name"], b["com"], "p")
        x, y, theta = new[b["name"]]
        b["x"], b["y"], b["theta"] = x, y, theta / to_rad
    # a moved pin is where body_a carries its (new) place; body_b's meets it there
    for joint, (place_a, place_b) in places.items():
        j = _joint(desc, joint)
        j["at"] = (
            carry(j["body_a"], place_a, "p") if j["body_a"] != "ground" else carry(j["body_b"], place_b, "p")
        )
    return desc
