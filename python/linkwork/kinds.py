"""The joint and driver types, read once from the engine's kind list: each description
type's fields and their roles (a world point fixed in which bodies, a direction, a curve,
a pitch radius, a length, ...). The drawing, the design parameters and the builder's
assembly read these instead of keeping tables of their own, so a new joint type declares
its fields once, in its Rust file.

A field's ``bodies`` are the fields naming the bodies it is fixed in (``("body_a",)``);
roles: ``name``, ``body``, ``joint``, ``point`` (a world point at the start, fixed in each
of its bodies), ``local_point``, ``direction`` (a world direction at the start),
``slide`` (a slide's direction, fixed in the guide), ``local_direction``, ``curve``,
``pitch`` (a wheel's pitch radius), ``coefficients``, ``length``, ``interval`` (a range
[min, max] of lengths), ``angle``, ``ratio``,
``number``, ``flag``, ``choice`` (one of ``choices``) and ``law`` (a driver's motion law;
``input`` says what it sets: ``angle``, ``relative_angle``, ``distance``, ``coordinate``
or ``slide``). ``unit`` is "length", "angle" or None.

The views below (`WORLD_POINTS`, `WORLD_DIRECTIONS`, `CURVES`, `GUIDES`, `WHEELS`,
`PINNED`, `FEATURES`) are what the drawing, the assembly and the redraw of design parameters read.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from . import _core

__all__ = [
    "GROUND",
    "Field",
    "Kind",
    "ENGINE_KINDS",
    "KINDS",
    "kind",
    "WORLD_POINTS",
    "WORLD_DIRECTIONS",
    "CURVES",
    "GUIDES",
    "WHEELS",
    "PINNED",
    "FEATURES",
]

#: the fixed frame's name wherever a body is named
GROUND = "ground"


@dataclass(frozen=True)
class Field:
    """One field of a description type and its role."""

    name: str
    role: str
    bodies: tuple[str, ...] = ()
    choices: tuple[str, ...] = ()
    input: str | None = None
    unit: str | None = None


@dataclass(frozen=True)
class Kind:
    """A description type (``group`` "joints" or "drivers", ``type`` as in a model file),
    the engine types it compiles to and its fields in the description's order (a type
    that compiles to several engine types, a cam follower's, has the fields of all)."""

    group: str
    type: str
    engine: tuple[str, ...]
    fields: tuple[Field, ...]

    def field(self, name: str) -> Field | None:
        return next((f for f in self.fields if f.name == name), None)

    def of_role(self, *roles: str) -> dict[str, Field]:
        """The fields of these roles, {name: Field}, in the description's order."""
        return {f.name: f for f in self.fields if f.role in roles}

    @property
    def input(self) -> Field | None:
        """A driver's law (its ``input``: what it sets, its ``unit``), or None."""
        return next((f for f in self.fields if f.role == "law"), None)


def _read(table: list[dict[str, Any]]) -> tuple[tuple[str, ...], dict[tuple[str, str], Kind]]:
    engine: list[str] = []
    kinds: dict[tuple[str, str], Kind] = {}
    for form in table:
        if form["kind"] not in engine:
            engine.append(form["kind"])
        key = (form["group"], form["type"])
        old = kinds.get(key)
        fields = list(old.fields) if old else []
        for f in form["fields"]:
            new = Field(f["name"], f["role"], tuple(f["bodies"]), tuple(f["choices"]), f["input"], f["unit"])
            k = next((i for i, g in enumerate(fields) if g.name == new.name), None)
            if k is None:
                fields.append(new)
            else:  # one field in several forms: its choices joined
                choices = fields[k].choices + tuple(c for c in new.choices if c not in fields[k].choices)
                fields[k] = Field(**{**fields[k].__dict__, "choices": choices})
        engine_of = (*old.engine, form["kind"]) if old else (form["kind"],)
        kinds[key] = Kind(key[0], key[1], engine_of, tuple(fields))
    return tuple(engine), kinds


#: the engine's joint and driver types (labels, in its kind list's order) and every
#: description type {(group, type): Kind}
ENGINE_KINDS, KINDS = _read(_core.constraint_roles())


def kind(group: str, type_: Any) -> Kind | None:
    """The description type ``type_`` of ``group`` ("joints" or "drivers"; "joint" and
    "driver" too), or None for a type the engine does not know."""
    return KINDS.get((group if group.endswith("s") else group + "s", str(type_)))


def _by_type(view: Any) -> dict[str, Any]:
    """{type: view(kind)} over joints and drivers (a joint and a driver of the same type
    name, `distance`, have the same such fields)."""
    return {t: view(k) for (_, t), k in KINDS.items()}


#: type -> {field holding a world point at the start: the fields naming the bodies that
#: point is fixed in}; every type is listed
WORLD_POINTS: dict[str, dict[str, tuple[str, ...]]] = _by_type(
    lambda k: {n: f.bodies for n, f in k.of_role("point").items()}
)

#: type -> {field holding a world direction at the start: the field naming the body it
#: is fixed in} (a slide's direction too)
WORLD_DIRECTIONS: dict[str, dict[str, str]] = {
    t: v
    for t, v in _by_type(
        lambda k: {n: f.bodies[0] for n, f in k.of_role("direction", "slide").items()}
    ).items()
    if v
}

#: types with a curve (world coordinates at the start) fixed in a body
CURVES: tuple[str, ...] = tuple(t for t, k in _by_type(lambda k: k.of_role("curve")).items() if k)

#: types drawn as a block (body_b) sliding on a guide (body_a): the field of the slide's
#: direction, fixed in body_a
GUIDES: dict[str, str] = {
    t: n for (_, t), k in KINDS.items() for n, f in k.of_role("slide").items() if f.bodies == ("body_a",)
}

#: types with pitch circles (a gear's, a pulley's, a pinion's)
WHEELS: tuple[str, ...] = tuple(t for t, k in _by_type(lambda k: k.of_role("pitch")).items() if k)

#: types a description may give by points in the bodies' own frames (pins), which
#: `Mechanism.assemble` draws
PINNED: tuple[str, ...] = tuple(t for t, k in _by_type(lambda k: k.of_role("local_point")).items() if k)

#: group -> type -> (field, the field naming the body whose frame carries it, "p" for a
#: world point or "d" for a direction), for each type with such fields; a point of two
#: bodies is carried by the first
FEATURES: dict[str, dict[str, tuple[tuple[str, str, str], ...]]] = {
    group: {
        t: tuple((n, f.bodies[0], "p" if f.role == "point" else "d") for n, f in fs.items())
        for (g, t), k in KINDS.items()
        if g == group and (fs := k.of_role("point", "direction", "slide"))
    }
    for group in ("joints", "drivers")
}
