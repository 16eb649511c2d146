"""Design parameters: any number of a model's description, named.

A parameter is a path into the description dict (`Model.description`,
`Mechanism.to_dict()`): ``joints.B.at.0``, ``bodies.crank.mass``,
``drivers.crank_angle.law.rate``, ``gravity.1`` (items of ``bodies``, ``joints``,
``drivers``, ``points`` and ``loads`` by name, list entries by index). Setting a path sets
that number and nothing else: moving ``joints.B.at`` moves the pin in *both* bodies it
joins (the drawing gives each body's pin positions).

The friendly names are what a designer means:

=========================  ==================================================================
``length crank``           the distance between the two pins of a binary link (``length
                           coupler:A-B`` names them: A stays, B moves along the link; by
                           default a ground pin stays). Every other body keeps its geometry.
``pin A@crank.x``          the x (or ``.y``) of pin A in body crank, as a world coordinate of
                           the drawing; the other body of A keeps its geometry.
``pivot O4.x``             a ground pivot's x (or ``.y``): ``pin O4@ground.x``.
``point P.x``              a named point's drawn x (or ``.y``): world, in the drawing.
``mass crank``             a body's mass (``inertia crank``: its moment of inertia).
``ratio G1``               a gear or belt joint's ratio (``radius_a G1``, ``radius_b G1`` too).
``law crank_angle.rate``   a field of a driver's motion law.
=========================  ==================================================================

Changing a link length or a pin's place in one body changes the mechanism's closed
configuration: `apply` redraws it. The engine assembles the varied mechanism (each moved
pin held by two perpendicular slots through its new place, the drivers at their values at
the start) nearest the old drawing, and the description is rewritten at that
configuration, so every body keeps every local vector except the ones the parameters
move. A varied mechanism that does not close raises the engine's `AssemblyError`.
Values are in the description's units (mm and degrees in a file that declares them).
"""

from __future__ import annotations

import json
import math
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import ParameterError
from ..kinds import CURVES

__all__ = ["Parameter", "parameter", "parameters", "KINDS"]

GROUPS = ("bodies", "joints", "drivers", "points", "loads")
KINDS = ("length", "pin", "pivot", "point", "mass", "inertia", "ratio", "radius_a", "radius_b", "law")


@dataclass(frozen=True)
class Parameter:
    """A named design parameter: ``name`` as the user wrote it, ``kind`` ("path",
    "length" or "pin"), ``path`` (the description's keys, for a path), ``nominal`` (its
    value in the description), ``unit`` and, for lengths and pins, the ``joint`` that
    moves, the ``body`` it moves in, the ``anchor`` pin that stays (lengths) and the
    ``axis`` (0 for x, 1 for y; pins)."""

    name: str
    kind: str
    nominal: float
    unit: str
    path: tuple[Any, ...] = ()
    joint: str = ""
    body: str = ""
    anchor: str = ""
    axis: int = 0

    def __str__(self) -> str:
        return self.name


def _listing(names: Sequence[str]) -> str:
    names = list(names)
    return ", ".join(names[:40]) + (f", ... ({len(names)} in all)" if len(names) > 40 else "") or "none"


def _item(desc: Mapping[str, Any], group: str, name: str, what: str, param: str) -> dict[str, Any]:
    for item in desc.get(group, []):
        if item.get("name") == name:
            return item
    names = [str(i.get("name")) for i in desc.get(group, [])]
    raise ParameterError(f"parameter {param!r}: no {what} {name!r}; the {group} are {_listing(names)}")


def _units(desc: Mapping[str, Any]) -> tuple[str, str]:
    u = desc.get("units") or {}
    return str(u.get("length", "m")), str(u.get("angle", "rad"))


def _pins(desc: Mapping[str, Any], body: str) -> list[dict[str, Any]]:
    return [
        j
        for j in desc.get("joints", [])
        if j.get("type") == "revolute" and body in (j.get("body_a"), j.get("body_b"))
    ]


def _path_unit(desc: Mapping[str, Any], path: tuple[Any, ...]) -> str:
    length, angle = _units(desc)
    last = [p for p in path if isinstance(p, str)][-1]
    if last in ("x", "y", "at", "at_a", "at_b", "through", "centre", "centre_a", "centre_b", "com"):
        return length
    if last in ("radius", "radius_a", "radius_b", "offset", "length", "free_length"):
        return length
    return {"theta": angle, "mass": "kg", "inertia": f"kg {length}^2", "gravity": f"{length}/s^2"}.get(
        last, ""
    )


def _resolve_path(desc: Mapping[str, Any], name: str, keys: Sequence[str]) -> Parameter:
    """A raw path: group and item name, then keys and indices."""
    node: Any = desc
    path: list[Any] = []
    for k, key in enumerate(keys):
        if k == 1 and keys[0] in GROUPS:
            node = _item(desc, keys[0], key, "body" if keys[0] == "bodies" else keys[0][:-1], name)
            path.append(key)
            continue
        if isinstance(node, Mapping):
            if key not in node:
                have = ", ".join(sorted(str(x) for x in node)) or "none"
                raise ParameterError(f"parameter {name!r}: no field {key!r} there; the fields are {have}")
            node = node[key]
        elif isinstance(node, list):
            try:
                i = int(key)
                node = node[i]
            except (ValueError, IndexError):
                raise ParameterError(
                    f"parameter {name!r}: {key!r} is not an index of a list of {len(node)}"
                ) from None
            path.append(i)
            continue
        else:
            raise ParameterError(f"parameter {name!r}: {'.'.join(keys[:k])} is a number, it has no {key!r}")
        path.append(key)
    if isinstance(node, bool) or not isinstance(node, numbers.Real):
        raise ParameterError(
            f"parameter {name!r} is not a number of the model but {json.dumps(node)[:60]}; "
            "name one of its numbers"
        )
    return Parameter(name, "path", float(node), _path_unit(desc, tuple(path)), path=tuple(path))


def parameter(description: Mapping[str, Any], name: str) -> Parameter:
    """The parameter ``name`` of a model description (a dict, or anything with
    ``to_dict()`` or ``description``), checked; `ParameterError` lists what exists.

    >>> from linkwork import examples
    >>> from linkwork.study import parameter
    >>> desc = examples.four_bar().to_dict()
    >>> p = parameter(desc, "length crank")
    >>> (p.kind, p.joint, p.anchor, round(p.nominal, 6))
    ('length', 'A', 'O2', 0.2)
    """
    desc = _description(description)
    if isinstance(name, Parameter):
        return name
    if not isinstance(name, str) or not name.strip():
        raise ParameterError(f"a parameter is named by a string, not {name!r}")
    text = name.strip()
    length_unit, _ = _units(desc)
    if " " not in text:
        keys = text.split(".")
        if keys[0] not in (*GROUPS, "gravity"):
            raise ParameterError(
                f"parameter {name!r}: a path starts with one of {', '.join((*GROUPS, 'gravity'))}, "
                f"or a name is '<kind> <what>' with kind one of {', '.join(KINDS)}"
            )
        return _resolve_path(desc, name, keys)
    kind, what = text.split(None, 1)
    if kind not in KINDS:
        raise ParameterError(f"parameter {name!r}: unknown kind {kind!r}; the kinds are {', '.join(KINDS)}")
    if kind in ("mass", "inertia"):
        body = _item(desc, "bodies", what, "body", name)
        return Parameter(
            name, "path", float(body.get(kind, 0.0)), _path_unit(desc, (kind,)), ("bodies", what, kind)
        )
    if kind in ("ratio", "radius_a", "radius_b"):
        joint = _item(desc, "joints", what, "joint", name)
        if kind not in joint:
            have = [j["name"] for j in desc.get("joints", []) if kind in j]
            raise ParameterError(
                f"parameter {name!r}: joint {what!r} ({joint.get('type')}) has no {kind}; "
                f"the joints with one are {_listing(have)}"
            )
        return _resolve_path(desc, name, ["joints", what, kind])
    if kind == "law":
        driver, _, field = what.partition(".")
        law = _item(desc, "drivers", driver, "driver", name)["law"]
        if not field:
            fields = ", ".join(k for k, v in law.items() if isinstance(v, (int, float, list)))
            raise ParameterError(
                f"parameter {name!r}: name the law's field ({fields}), e.g. 'law {driver}.rate'"
            )
        return _resolve_path(desc, name, ["drivers", driver, "law", *field.split(".")])
    if kind == "point":
        point, axis = _axis(name, what)
        p = _item(desc, "points", point, "point", name)
        return Parameter(name, "path", float(p["at"][axis]), length_unit, ("points", point, "at", axis))
    if kind in ("pin", "pivot"):
        joint_body, axis = _axis(name, what)
        joint, _, body = joint_body.partition("@")
        if kind == "pivot":
            if body:
                raise ParameterError(f"parameter {name!r}: a pivot is on the ground; write 'pivot {joint}.x'")
            body = "ground"
        j = _item(desc, "joints", joint, "joint", name)
        _check_pin(desc, name, j, body)
        return Parameter(name, "pin", float(j["at"][axis]), length_unit, joint=joint, body=body, axis=axis)
    # a link length
    body, _, pins = what.partition(":")
    if body != "ground":
        _item(desc, "bodies", body, "body", name)
    on_body = _pins(desc, body)
    if pins:
        anchor, _, moved = pins.partition("-")
        for pin in (anchor, moved):
            if pin not in [j["name"] for j in on_body]:
                raise ParameterError(
                    f"parameter {name!r}: {pin!r} is not a pin of {body!r}; its pins are "
                    f"{_listing([j['name'] for j in on_body])}"
                )
        if anchor == moved:
            raise ParameterError(f"parameter {name!r}: a length is between two different pins")
    else:
        if len(on_body) != 2:
            raise ParameterError(
                f"parameter {name!r}: body {body!r} has {len(on_body)} pins "
                f"({_listing([j['name'] for j in on_body])}); name two: 'length {body}:A-B' "
                "(A stays, B moves)"
            )
        grounded = [j for j in on_body if "ground" in (j["body_a"], j["body_b"])]
        first = grounded[0] if len(grounded) == 1 else on_body[0]
        anchor, moved = first["name"], next(j["name"] for j in on_body if j is not first)
    ja = _item(desc, "joints", anchor, "joint", name)
    jm = _item(desc, "joints", moved, "joint", name)
    _check_pin(desc, name, jm, body)
    nominal = math.dist(ja["at"], jm["at"])
    if nominal == 0.0:
        raise ParameterError(
            f"parameter {name!r}: pins {anchor!r} and {moved!r} coincide; a length needs a line"
        )
    return Parameter(name, "length", nominal, length_unit, joint=moved, body=body, anchor=anchor)


def _axis(name: str, what: str) -> tuple[str, int]:
    base, _, axis = what.rpartition(".")
    if axis not in ("x", "y") or not base:
        raise ParameterError(f"parameter {name!r}: end it with .x or .y (which coordinate)")
    return base, 0 if axis == "x" else 1


def _check_pin(desc: Mapping[str, Any], name: str, joint: Mapping[str, Any], body: str) -> None:
    if joint.get("type") != "revolute":
        raise ParameterError(
            f"parameter {name!r}: joint {joint.get('name')!r} is a {joint.get('type')} joint; "
            "pins and lengths move revolute joints (name the number by its path, e.g. joints.NAME.at.0)"
        )
    if body not in (joint["body_a"], joint["body_b"]):
        raise ParameterError(
            f"parameter {name!r}: pin {joint['name']!r} joins {joint['body_a']!r} and {joint['body_b']!r}, "
            f"not {body!r}"
        )
    curved = [j["name"] for j in desc.get("joints", []) if j.get("type") in CURVES]
    if curved:
        raise ParameterError(
            f"parameter {name!r}: the mechanism has curve joints ({_listing(curved)}), which a redraw "
            "would not carry; vary the pin by its path (joints.NAME.at.0) instead"
        )


def parameters(description: Any, names: Sequence[Any]) -> list[Parameter]:
    """Each name checked (`parameter`); the same name twice is a `ParameterError`."""
    desc = _description(description)
    if isinstance(names, str):
        raise ParameterError(f"parameters are a list of names, not the string {names!r}")
    out = [parameter(desc, n) for n in names]
    seen: set[str] = set()
    for p in out:
        if p.name in seen:
            raise ParameterError(f"parameter {p.name!r} is given twice")
        seen.add(p.name)
    return out


def _description(description: Any) -> dict[str, Any]:
    if hasattr(description, "description") and isinstance(description.description, dict):
        return description.description
    if hasattr(description, "assemble"):
        return description.assemble().to_dict()  # a mechanism given by its pins, drawn
    if hasattr(description, "to_dict"):
        return description.to_dict()
    if isinstance(description, Mapping):
        return description  # type: ignore[return-value]
    raise ParameterError(
        f"a model description is a dict, a Mechanism or a Model, not {type(description).__name__}"
    )


def _value(p: Parameter, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise ParameterError(f"parameter {p.name!r}: the value must be a finite number, not {value!r}")
    v = float(value)
    if p.kind == "length" and v <= 0.0:
        raise ParameterError(f"parameter {p.name!r}: a length must be > 0, not {v}")
    return v
