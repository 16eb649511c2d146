"""The joint and driver types, read once from the engine's kind list: each description
type's fields and their roles (a world point fixed in which bodies, a direction, a curve,
a pitch radius, a length, ...). The drawing, the design parameters and the builder's
assembly read these instead of keeping tables of their own, so a new joint type declares
its fields once, in its Rust file.

A field's ``bodies`` are the fields naming the bodies it is fixed in (``("body_a",)``);
roles: ``name``, ``body``, ``joint``, ``point`` (a world point at the start, fixed in each
of its bodies), ``local_point``, ``direction`` (a world direction at the start),
``slide`` (a slide's direction, fixed in the guide), ``local_direction``, ``curve``,
``pitch`` (a wheel's pitch radius), ``coefficients``, ``length``, ``angle``, ``ratio``,
``number``, ``flag``, ``choice`` (one of ``choices``) and ``law`` (a driver's motion law;
``input`` says what it sets: ``angle``, ``relative_angle``, ``distance``, ``coordinate``
or ``slide``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from . import _core

__all__ = ["Field", "Kind", "ENGINE_KINDS", "KINDS", "kind", "of_role"]


@dataclass(frozen=True)
class Field:
    """One field of a description type and its role."""

    name: str
    role: str
    bodies: tuple[str, ...] = ()
    choices: tuple[str, ...] = ()
    input: str | None = None


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
            new = Field(f["name"], f["role"], tuple(f["bodies"]), tuple(f["choices"]), f["input"])
            k = next((i for i, g in enumerate(fields) if g.name == new.name), None)
            if k is None:
                fields.append(new)
            else:  # one field in several forms: its choices joined
                choices = fields[k].choices + tuple(c for c in new.choices if c not in fields[k].choices)
                fields[k] = Field(new.name, fields[k].role, fields[k].bodies, choices, fields[k].input)
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


def of_role(group: str, *roles: str) -> dict[str, dict[str, Field]]:
    """For each type of ``group`` that has fields of these roles: {type: {field name:
    Field}}, fields in the description's order."""
    out: dict[str, dict[str, Field]] = {}
    for (g, type_), k in KINDS.items():
        if g == group:
            found = {f.name: f for f in k.fields if f.role in roles}
            if found:
                out[type_] = found
    return out
