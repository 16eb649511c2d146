"""Study files (TOML): the model, the times, the outputs, and either a design space or
tolerances; read by `load_study` and ``linkwork study FILE``.

::

    [study]
    model = "four_bar.toml"        # a model file, relative to this file
    t1 = 1.2566370614359172        # times: t0 (default 0) to t1 in `steps` steps (default 1000)
    steps = 1000
    outputs = ["path P", "angle rocker", "transmission_min"]
    # derivatives = 0              # default: the least the outputs need
    # chunk = 500                  # designs per task (default: see docs/studies.md)

    # a design space: one of [grid], [latin_hypercube], [designs]
    [grid]                         # every combination
    "length crank" = [180.0, 200.0, 220.0]                 # listed values
    "pivot O4.x" = { from = 300.0, to = 400.0, steps = 5 } # evenly spaced

    [latin_hypercube]
    n = 200
    seed = 1
    ranges = { "length crank" = [180.0, 220.0], "pivot O4.x" = [300.0, 400.0] }

    [designs]                      # the user's own: as many values for every parameter
    "length crank" = [190.0, 200.0, 210.0]

    # or a tolerance study
    [tolerances]
    n = 10000
    seed = 1
    linear = true                  # first order beside Monte Carlo (exact; differences as fallback)
    [tolerances.parameters]
    "length crank" = { normal = 0.05 }         # sigma, in the model's units
    "length coupler" = { uniform = 0.1 }       # +- half width
    "pivot O4.x" = { interval = [-0.1, 0.05] }

Parameter values are in the model file's units (mm in a file declaring mm).
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import LinkworkError, StudyError
from .designs import Designs, grid, latin_hypercube, listed, tolerance

__all__ = ["StudyFile", "load_study"]

SECTIONS = ("study", "grid", "latin_hypercube", "designs", "tolerances")


@dataclass
class StudyFile:
    """A study file read: ``study`` (a `Study`), ``designs`` (a design space) or
    ``tolerances`` with ``n``, ``seed`` and ``linear``; ``chunk``; ``name`` (the file's stem)."""

    path: str
    name: str
    study: Any
    designs: Designs | None
    tolerances: dict[str, Any] | None
    n: int
    seed: int | None
    linear: bool
    chunk: int | None


def _read(path: str) -> dict[str, Any]:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python < 3.11
        import tomli as tomllib
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{path}: not a TOML study file: {e}") from None


def _axis(name: str, spec: Any, where: str) -> Any:
    if isinstance(spec, dict):
        unknown = sorted(set(spec) - {"from", "to", "steps"})
        if unknown or not {"from", "to", "steps"} <= set(spec):
            raise StudyError(f"{where}: {name!r} is a list of values or {{from, to, steps}}, not {spec!r}")
        return np.linspace(float(spec["from"]), float(spec["to"]), int(spec["steps"]))
    return spec


def load_study(path: str) -> StudyFile:
    """Reads a study file: its model (relative to the file), times, outputs and design
    space or tolerances, all checked; `StudyError` (or the model's error) names the file."""
    from ..mechanism.builder import Mechanism
    from .run import Study

    path = os.fspath(path)
    data = _read(path)
    unknown = sorted(set(data) - set(SECTIONS))
    if unknown:
        raise StudyError(f"{path}: unknown section [{unknown[0]}]; the sections are {', '.join(SECTIONS)}")
    head = data.get("study")
    if not isinstance(head, dict):
        raise StudyError(f"{path}: needs a [study] section with model, t1 and outputs")
    allowed = {"model", "t0", "t1", "steps", "outputs", "derivatives", "chunk", "name"}
    extra = sorted(set(head) - allowed)
    if extra:
        raise StudyError(
            f"{path}: [study] has no key {extra[0]!r}; the keys are {', '.join(sorted(allowed))}"
        )
    for key in ("model", "t1", "outputs"):
        if key not in head:
            raise StudyError(f"{path}: [study] needs {key!r}")
    spaces = [s for s in ("grid", "latin_hypercube", "designs", "tolerances") if s in data]
    if len(spaces) != 1:
        raise StudyError(
            f"{path}: give one of [grid], [latin_hypercube], [designs] or [tolerances], "
            f"not {spaces or 'none'}"
        )
    model_path = os.path.join(os.path.dirname(os.path.abspath(path)), str(head["model"]))
    try:
        mechanism = Mechanism.load(model_path)
        steps = int(head.get("steps", 1000))
        if steps < 1:
            raise StudyError("steps must be at least 1")
        times = np.linspace(float(head.get("t0", 0.0)), float(head["t1"]), steps)
        study = Study(mechanism, times, list(head["outputs"]), derivatives=head.get("derivatives"))
        designs, tols, n, seed, linear = None, None, 0, None, True
        space = spaces[0]
        section = data[space]
        if not isinstance(section, dict) or not section:
            raise StudyError(f"[{space}] is empty")
        if space == "grid":
            designs = grid({k: _axis(k, v, "[grid]") for k, v in section.items()})
        elif space == "latin_hypercube":
            extra = sorted(set(section) - {"n", "seed", "ranges"})
            if extra or "n" not in section or "ranges" not in section:
                raise StudyError("[latin_hypercube] has n, seed and ranges = {parameter = [low, high]}")
            designs = latin_hypercube(section["ranges"], section["n"], section.get("seed", 0))
        elif space == "designs":
            designs = listed(section)
        else:
            extra = sorted(set(section) - {"n", "seed", "linear", "parameters"})
            if extra or "parameters" not in section:
                raise StudyError("[tolerances] has n, seed, linear and [tolerances.parameters]")
            tols = {k: tolerance(v, k) for k, v in section["parameters"].items()}
            n, seed, linear = (
                int(section.get("n", 1000)),
                section.get("seed", 0),
                bool(section.get("linear", True)),
            )
            study.nominal(list(tols))  # the parameters exist
        if designs is not None:
            study.job(designs.names)  # the parameters exist
    except LinkworkError as e:
        message = str(e)
        raise type(e)(message if message.startswith(path) else f"{path}: {message}") from None
    except (OSError, TypeError, ValueError, KeyError) as e:
        raise StudyError(f"{path}: {e}") from None
    chunk = head.get("chunk")
    name = str(head.get("name") or os.path.splitext(os.path.basename(path))[0])
    return StudyFile(path, name, study, designs, tols, n, seed, linear, None if chunk is None else int(chunk))
