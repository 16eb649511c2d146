"""Every joint and driver type is everywhere it must be: in the roles table the engine
exports (`linkwork.kinds`), in the model-file format (a round trip), in the builder (a
`Mechanism` method), in the reference (it builds a constraint of the type), in
docs/joints.md; and the modules that read descriptions by type (drawing, page, design
parameters, the builder's assembly) name only types of the table and keep no table of
types of their own. A failure names the type and the place."""

from __future__ import annotations

import ast
import copy
import importlib
import inspect
import json
import pathlib
from typing import Any

import pytest

from linkwork import Mechanism, _core, kinds
from linkwork.reference.formulation import build_constraints

ROOT = pathlib.Path(__file__).resolve().parents[1]
TYPES = sorted(kinds.KINDS)


def _value(field: Any, k: int = 0) -> Any:
    """A value of the field's role (a `kinds.Field` or a field of the raw table) that the
    engine's reader accepts; ``k`` tells points apart."""
    role = field.role if isinstance(field, kinds.Field) else field["role"]
    choices = field.choices if isinstance(field, kinds.Field) else field["choices"]
    return {
        "name": "e",
        "body": "b",
        "joint": "p",
        "point": [0.25 + 0.125 * k, 0.5],
        "local_point": [0.25, 0.5 + 0.125 * k],
        "direction": [1.0, 0.0],
        "slide": [1.0, 0.0],
        "local_direction": [1.0, 0.0],
        "curve": {"type": "circle", "centre": [0.0, 0.0], "radius": 0.5},
        "pitch": 0.125,
        "length": 0.125,
        "interval": [-0.125, 0.25],
        "angle": 0.75,
        "number": 0.75,
        "ratio": 2.0,
        "coefficients": {"x": 1.0, "y": 0.0, "theta": 0.5},
        "flag": False,
        "choice": choices[0] if choices else None,
        "law": {"type": "linear", "value": 0.0, "rate": 1.0},
    }[role]


def _item(k: kinds.Kind) -> dict[str, Any]:
    return {"type": k.type, **{f.name: _value(f, i) for i, f in enumerate(k.fields)}}


def test_every_engine_type_has_a_description_form() -> None:
    table = _core.constraint_roles()
    engine = {f["kind"] for f in table}
    assert engine == set(kinds.ENGINE_KINDS)
    for label in kinds.ENGINE_KINDS:
        assert any(label in k.engine for k in kinds.KINDS.values()), f"{label!r}: no description form"
    for form in table:
        k = kinds.kind(form["group"], form["type"])
        assert k is not None
        for f in form["fields"]:
            merged = k.field(f["name"])
            assert merged is not None and (merged.role, merged.bodies) == (f["role"], tuple(f["bodies"])), (
                f"{form['type']!r}: field {f['name']!r} has two roles in its forms"
            )


@pytest.mark.parametrize("key", TYPES, ids=lambda k: f"{k[0]}.{k[1]}")
def test_every_type_round_trips_through_the_model_file(key: tuple[str, str]) -> None:
    k = kinds.KINDS[key]
    item = _item(k)
    desc = {"name": "m", "bodies": [{"name": "b", "x": 0.0, "y": 0.0, "theta": 0.0}], k.group: [item]}
    for fmt in ("toml", "json"):
        text = _core.write_model(json.dumps(desc), fmt)
        flat, _ = _core.read_model(text, fmt, f"model.{fmt}")
        back = json.loads(flat)[k.group][0]
        assert back == item, f"{k.type!r}: the {fmt} model file does not give back its fields"
        assert (
            Mechanism.from_toml(Mechanism.from_dict(json.loads(flat)).to_toml()).to_dict()[k.group][0] == item
        ), f"{k.type!r}: Mechanism.from_dict/to_toml does not give back its fields"


@pytest.mark.parametrize("key", TYPES, ids=lambda k: f"{k[0]}.{k[1]}")
def test_every_type_has_a_builder_method(key: tuple[str, str]) -> None:
    group, type_ = key
    method = type_ if group == "joints" else f"drive_{type_}"
    assert hasattr(Mechanism, method), f"{type_!r}: the builder has no method Mechanism.{method}"
    assert f'"{type_}"' in inspect.getsource(getattr(Mechanism, method)), (
        f"{type_!r}: Mechanism.{method} does not write a {type_!r} {group[:-1]}"
    )


FORMS = _core.constraint_roles()


@pytest.mark.parametrize("form", FORMS, ids=lambda f: f"{f['kind']}.{f['type']}")
def test_every_engine_type_has_a_reference_class(form: dict[str, Any]) -> None:
    """The reference builds a constraint of each description form of each engine type
    (a cam follower's three): bodies b, c (a's side, not the ground: a pinion, a coupled
    body) and d (a carrier), and a prismatic joint p for a translation driver."""
    item = {"type": form["type"], **{f["name"]: _value(f, i) for i, f in enumerate(form["fields"])}}
    item.update({key: v for key, v in (("body_a", "c"), ("carrier", "d")) if key in item})
    if "ratio" in item and "radius_a" in item:
        del item["ratio"]  # radii or a ratio, not both
    bodies = [
        {"name": n, "x": x, "y": y, "theta": 0.0}
        for n, x, y in (("b", 0.5, 0.0), ("c", 0.0, 0.0), ("d", 0.0, 0.25))
    ]
    desc: dict[str, Any] = {"name": "m", "bodies": bodies, "joints": [], "drivers": []}
    if form["group"] == "drivers":
        desc["joints"].append(
            {
                "type": "prismatic",
                "name": "p",
                "body_a": "ground",
                "body_b": "b",
                "at": [0.5, 0.0],
                "axis": [1.0, 0.0],
            }
        )
    desc[form["group"]].append(item)
    start = {b["name"]: (b["x"], b["y"], b["theta"]) for b in bodies} | {"ground": (0.0, 0.0, 0.0)}
    try:
        built = build_constraints(copy.deepcopy(desc), start)
    except ValueError as e:
        pytest.fail(f"{form['kind']!r} ({form['type']}): the reference does not build it: {e}")
    assert len(built) == len(desc["joints"]) + len(desc["drivers"])


DOCS = (ROOT / "docs" / "joints.md").read_text()


@pytest.mark.parametrize("key", TYPES, ids=lambda k: f"{k[0]}.{k[1]}")
def test_every_type_is_in_the_joints_page(key: tuple[str, str]) -> None:
    assert f"`{key[1]}`" in DOCS, f"{key[1]!r}: not in docs/joints.md"


# the modules that read descriptions by type
READERS = {
    "drawing": "linkwork.view.drawing",
    "traced points": "linkwork.model.anchors",
    "page": "linkwork.view.page",
    "page inputs": "linkwork.view.series",
    "parameters": "linkwork.study.naming",
    "redraw": "linkwork.study.redraw",
    "builder": "linkwork.mechanism.builder",
    "assembly": "linkwork.mechanism.assembly",
    "model": "linkwork.model.compiled",
}


def _source(name: str) -> tuple[str, ast.Module]:
    path = inspect.getsourcefile(importlib.import_module(name))
    assert path is not None
    return name, ast.parse(pathlib.Path(path).read_text())


def _is_type_read(node: ast.expr, names: set[str]) -> bool:
    """`x.get("type")`, `x["type"]` (in `str(...)` or not), or a name assigned one."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "str" and node.args:
        node = node.args[0]
    if isinstance(node, ast.Name):
        return node.id in names
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get":
        key, of = (node.args[0] if node.args else None), node.func.value
    elif isinstance(node, ast.Subscript):
        key, of = node.slice, node.value
    else:
        return False
    # a law's type (`law.get("type")`, `d.get("law", {}).get("type")`) is not an element's
    return isinstance(key, ast.Constant) and key.value == "type" and "law" not in ast.unparse(of)


def _type_names(fn: ast.AST) -> set[str]:
    """The names a function assigns a type to (``kind = item.get("type")``)."""
    names: set[str] = set()
    for node in ast.walk(fn):
        if isinstance(node, ast.Assign):
            for target in node.targets:
                pairs = (
                    zip(target.elts, node.value.elts)
                    if isinstance(target, ast.Tuple) and isinstance(node.value, ast.Tuple)
                    else [(target, node.value)]
                )
                names |= {t.id for t, v in pairs if isinstance(t, ast.Name) and _is_type_read(v, set())}
    return names


def _strings(node: ast.expr) -> list[str]:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [s for e in node.elts for s in _strings(e)]
    return []


ALL_TYPES = {t for _, t in kinds.KINDS}
# the loads' types
LOADS = {"force", "torque", "spring", "torsion_spring"}


@pytest.mark.parametrize("reader", sorted(READERS))
def test_readers_name_only_types_of_the_table(reader: str) -> None:
    """A type a reader compares with is a joint, driver or load type."""
    name, tree = _source(READERS[reader])
    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.Lambda)):
            continue
        names = _type_names(fn)
        for node in ast.walk(fn):
            if isinstance(node, ast.Compare) and _is_type_read(node.left, names):
                for right in node.comparators:
                    for s in _strings(right):
                        assert s in ALL_TYPES | LOADS, (
                            f"{name}, line {node.lineno}: {s!r} is no joint or driver type"
                        )


@pytest.mark.parametrize("reader", sorted(READERS))
def test_readers_keep_no_table_of_types(reader: str) -> None:
    """A dict keyed by, or a tuple of, two or more types is a table of the module's own,
    which would silently skip a type it does not list."""
    name, tree = _source(READERS[reader])
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            keys = [k.value for k in node.keys if isinstance(k, ast.Constant) and isinstance(k.value, str)]
        elif isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            keys = _strings(node)
        else:
            continue
        found = sorted(set(keys) & ALL_TYPES)
        assert len(found) < 2, (
            f"{name}, line {node.lineno}: a table of types {found}; read linkwork.kinds instead"
        )
