"""A simulation's initial rates from the rates of a few coordinates or joints: the model
driven by them (an angle or coordinate driver per named column, a relative-angle or
translation driver per named revolute or prismatic joint, each at its rate through the
drawing) solved once for its velocities, so that every other rate follows from the
joints. As many independent rates as the model has degrees of freedom are needed."""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import InitialConditionError, LinkworkError

__all__ = ["complete_rates"]


def complete_rates(model: Any, given: Mapping[str, float], t0: float) -> np.ndarray:
    """qd of ``model`` (a compiled `Model`) at time ``t0`` and the drawing from ``given``
    ({column or joint name: rate}, in the model's units: deg/s for the angles of a model
    in degrees); an `InitialConditionError` names what cannot be used."""
    desc = copy.deepcopy(model.description)
    desc["free"] = False
    desc.pop("initial_rates", None)
    k = 180.0 / math.pi if (desc.get("units") or {}).get("angle") == "deg" else 1.0
    q0 = np.asarray(model.q_start, dtype=float)
    columns = list(model.columns)
    joints = {j["name"]: j for j in desc.get("joints", [])}

    def theta(body: str) -> float:
        return 0.0 if body == "ground" else float(q0[columns.index(f"{body}.theta")])

    def law(value: float, rate: float) -> dict[str, object]:
        return {"type": "linear", "value": value - rate * t0, "rate": rate}

    drivers = desc.setdefault("drivers", [])
    for key, rate in given.items():
        name = f"initial rate of {key}"
        body, _, what = key.rpartition(".")
        if key in columns and what == "theta":
            drivers.append({"type": "angle", "name": name, "body": body, "law": law(k * theta(body), rate)})
        elif key in columns and what in ("x", "y"):
            i = columns.index(f"{body}.x")
            at = [float(q0[i]), float(q0[i + 1])]
            value = at[0] if what == "x" else at[1]
            drivers.append(
                {
                    "type": "coordinate",
                    "name": name,
                    "body": body,
                    "at": at,
                    "axis": what,
                    "law": law(value, rate),
                }
            )
        elif joints.get(key, {}).get("type") == "revolute":
            j = joints[key]
            turn = k * (theta(j["body_b"]) - theta(j["body_a"]))
            drivers.append(
                {"type": "relative_angle", "name": name, "body_a": j["body_a"], "body_b": j["body_b"],
                 "law": law(turn, rate)}
            )  # fmt: skip
        elif joints.get(key, {}).get("type") == "prismatic":
            drivers.append({"type": "translation", "name": name, "joint": key, "law": law(0.0, rate)})
        else:
            raise InitialConditionError(
                f"initial rate of {key!r}: not a body's x, y or theta column nor a revolute or "
                f"prismatic joint of the model; the columns are {', '.join(columns)}"
            )
    try:
        driven = type(model)(desc, python_laws=model._python_laws or None)
        if driven.dof != 0:
            raise InitialConditionError(f"{driven.dof} more are needed")
        state = driven.solve(t0, q_guess=q0)
    except LinkworkError as e:
        raise InitialConditionError(
            f"initial rates of {', '.join(map(repr, given))}: the model has {model.dof} degree(s) of "
            f"freedom; give as many independent rates ({e})"
        ) from None
    return np.asarray(state.qd, dtype=float)
