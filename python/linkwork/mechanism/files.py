"""Model files: a mechanism's description read from and written to TOML or JSON
(docs/model-format.md) through the engine's reader and writer, with the file, line and
field of a fault; and the warning for a file whose numbers look like mm or degrees but
that declares no units. Works on descriptions (plain data); `Mechanism.load`, `save`,
`from_toml` and `to_toml` call it."""

from __future__ import annotations

import json
import math
import os
import re
import warnings
from typing import Any

from .. import _core
from ..errors import LinkworkWarning, ModelError
from ..model.compiled import _check_finite

__all__ = ["read_text", "parse", "units_check", "write", "save"]


def read_text(path: str | os.PathLike[str]) -> tuple[str, str]:
    """The text of a model file and its format ("toml" or "json", by its suffix); a file
    that is not UTF-8 is a `ModelError` naming the line and byte."""
    fmt = _format_of(path)
    with open(path, "rb") as f:
        raw = f.read()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        line = raw.count(b"\n", 0, e.start) + 1
        raise ModelError(
            f"{os.fspath(path)}: line {line}, byte {e.start}: the file is not UTF-8 text "
            f"({e.reason}: {raw[e.start : e.start + 4]!r}); model files are UTF-8: save it as UTF-8"
        ) from None
    return text, fmt


def parse(text: str, fmt: str, file: str) -> tuple[dict[str, Any], dict[tuple[str, str], int]]:
    """The description in a model file's text, and the line of each element, keyed by
    (kind, name)."""
    flat, elements = _core.read_model(text, fmt, file)
    return json.loads(flat), {(kind, name): line for kind, name, line in elements}


def units_check(desc: dict[str, Any], text: str, fmt: str, file: str) -> tuple[bool, str | None]:
    """A file without a units header reads as m and rad; when its lengths look like
    mm (a pin or body more than 10 m from the origin) or its angles like degrees (a
    body angle beyond 2 pi), say so, as a `LinkworkWarning`. Returns (units declared,
    the warning or None)."""
    if fmt == "toml":
        # the header is what comes before the first array of tables ([[bodies]] ...):
        # a units key there, or a [model.units] / [units] table (not parsed again: a
        # 10,000-loop file takes seconds to parse)
        head = re.split(r"^\s*\[\[", text, maxsplit=1, flags=re.M)[0]
        declared = bool(re.search(r"^\s*(units\s*=|\[(model\.)?units\])", head, flags=re.M))
    else:
        try:
            doc = json.loads(text)
        except ValueError:
            return True, None
        header = doc.get("model", doc) if isinstance(doc, dict) else {}
        declared = isinstance(header, dict) and "units" in header
    if declared:
        return True, None
    points = [b.get(k, 0.0) for b in desc["bodies"] for k in ("x", "y")]
    points += [c for j in desc["joints"] for c in (j.get("at") or [])]
    points += [c for p in desc["points"] for c in (p.get("at") or [])]
    lengths = max((abs(v) for v in points if isinstance(v, (int, float))), default=0.0)
    angles = max((abs(b.get("theta", 0.0)) for b in desc["bodies"]), default=0.0)
    looks = []
    if lengths > 10.0:
        looks.append(f"lengths up to {lengths:g} look like millimetres")
    if angles > 2 * math.pi + 1e-9:
        looks.append(f"body angles up to {angles:g} look like degrees")
    if looks:
        warning = (
            f"{file}: no units in the model header, so lengths are read in m and angles in rad; "
            f"but its {' and its '.join(looks)}: if so, declare them "
            '(units = { length = "mm", angle = "deg" } in the [model] table)'
        )
        warnings.warn(warning, LinkworkWarning, stacklevel=3)
        return False, warning
    return False, None


def write(desc: dict[str, Any], fmt: str) -> str:
    """The text of a model file ("toml" or "json") holding ``desc``."""
    return _core.write_model(_json(desc), fmt)


def _json(desc: dict[str, Any]) -> str:
    _check_finite(desc)  # names the element: JSON cannot carry NaN to the writer
    return json.dumps(desc)


def save(desc: dict[str, Any], path: str | os.PathLike[str]) -> None:
    """Writes ``desc`` to ``path`` as TOML or JSON by its suffix. A driver or load that
    follows a Python function is a `ModelError`: a file cannot hold one."""
    for kind, item in [("driver", d) for d in desc["drivers"]] + [("load", ld) for ld in desc["loads"]]:
        if _uses_python(item.get("law")):
            raise ModelError(
                f"{kind} {item['name']!r} follows a Python function (PythonLaw), which a model "
                'file cannot hold: write the law as an lw.Expression("...") of t, a lw.Cam, or a '
                "lw.Spline through a table to save it"
            )
    text = _core.write_model(_json(desc), _format_of(path))
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def _format_of(path: str | os.PathLike[str]) -> str:
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in (".toml", ".json"):
        raise ModelError(f"{os.fspath(path)}: a model file ends in .toml or .json, not {ext or 'nothing'!r}")
    return ext[1:]


def _uses_python(law: Any) -> bool:
    """Whether a law's description (a dict) holds a python law, nested ones included."""
    if isinstance(law, dict):
        return law.get("type") == "python" or any(_uses_python(v) for v in law.values())
    if isinstance(law, list):
        return any(_uses_python(v) for v in law)
    return False
