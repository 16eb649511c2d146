"""Assembly from pins: a mechanism given by its joints' pins in the bodies' own frames
drawn at the configuration the engine assembles, every world point and direction carried
with its body (`Mechanism.assemble`). Works on descriptions (plain data)."""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import AssemblyError, InputError
from ..kinds import CURVES, GROUND, PINNED, WORLD_DIRECTIONS, WORLD_POINTS
from ..model.compiled import Model

__all__ = ["drawn"]


def drawn(
    desc: dict[str, Any], python_laws: dict[str, Any], t: float, branch: str | dict[str, str] | None
) -> dict[str, Any]:
    """The description ``desc`` drawn: its bodies at the configuration the engine
    assembles at time ``t`` from the joints' pins (on ``branch``'s assembly mode, else the
    one nearest the bodies' rough poses), each revolute at its world point, each slide
    through its ``pin_b``, every named point and joint point carried with its body
    (`Mechanism.assemble`). A joint that cannot close is an `AssemblyError` naming it."""
    model = Model(desc, python_laws=python_laws)
    q = model._branch_guess(t, branch) if branch is not None else model.solve(t).q
    desc = copy.deepcopy(desc)
    # poses in the description's own angle unit (the engine's are radians)
    per_rad = 180.0 / math.pi if (desc.get("units") or {}).get("angle") == "deg" else 1.0
    rough = {
        b["name"]: (b.get("x", 0.0), b.get("y", 0.0), b.get("theta", 0.0) / per_rad) for b in desc["bodies"]
    }
    poses = {name: q[3 * i : 3 * i + 3] for i, name in enumerate(model.body_names)}
    for b in desc["bodies"]:
        x, y, theta = poses[b["name"]]
        b.update(x=float(x), y=float(y), theta=float(theta) * per_rad)

    def world(body: str, u: Sequence[float]) -> np.ndarray:
        if body == GROUND:
            return np.asarray(u, dtype=float)
        x, y, theta = poses[body]
        c, s = math.cos(theta), math.sin(theta)
        return np.array([x + c * u[0] - s * u[1], y + s * u[0] + c * u[1]])

    def turn(body: str, v: Sequence[float]) -> np.ndarray:
        if body == GROUND:
            return np.asarray(v, dtype=float)
        c, s = math.cos(poses[body][2]), math.sin(poses[body][2])
        return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])

    _carry_world_points(desc, rough, poses)
    for j in desc["joints"]:
        if j.get("type") not in PINNED or "at" in j:
            continue
        a, b = world(j["body_a"], j["pin_a"]), world(j["body_b"], j["pin_b"])
        miss = float(np.hypot(*(a - b)))
        if j["type"] == "prismatic":
            # the slide: pin_b on the line through pin_a; drawn through pin_b, the pins
            # kept so that the slide is still 0 where pin_b is at pin_a
            e = turn(j["body_a"], j["axis_a"]) if "axis_a" in j else np.asarray(j["axis"], dtype=float)
            e = e / np.hypot(*e)
            miss = abs(float(e[0] * (b - a)[1] - e[1] * (b - a)[0]))
            j["at"], j["axis"] = [float(b[0]), float(b[1])], [float(e[0]), float(e[1])]
            j.pop("axis_a", None)
            j.setdefault("angle", 0.0)
        if miss > 1e-9 * model.length_scale:
            raise AssemblyError(
                f"joint {j['name']!r} does not close: its pins are {miss:.6g} apart at t = {t:g}"
            )
        if j["type"] == "revolute":
            j["at"] = [float(a[0]), float(a[1])]
            del j["pin_a"], j["pin_b"]
    desc.pop("branch", None)
    return desc


def _carry_world_points(
    desc: dict[str, Any], rough: dict[str, tuple[float, float, float]], poses: dict[str, np.ndarray]
) -> None:
    """Carries every world point and direction of ``desc`` fixed in one body from the
    body's rough pose to its assembled one (as the engine reads them: the point in the
    body's frame is u = A(theta_rough)^T (p - R_rough)), so a named point or a joint's
    point given beside the pins stays where it is on its body."""

    def moved(body: str) -> bool:
        return body != GROUND and any(abs(a - b) > 0.0 for a, b in zip(rough[body], poses[body]))

    def carry(body: str, p: Sequence[float], direction: bool = False) -> list[float]:
        if body == GROUND:
            return [float(p[0]), float(p[1])]
        x0, y0, th0 = rough[body]
        x, y, th = (float(v) for v in poses[body])
        d = (p[0], p[1]) if direction else (p[0] - x0, p[1] - y0)
        c0, s0 = math.cos(th0), math.sin(th0)
        u = (c0 * d[0] + s0 * d[1], -s0 * d[0] + c0 * d[1])
        c, s = math.cos(th), math.sin(th)
        w = (c * u[0] - s * u[1], s * u[0] + c * u[1])
        return [w[0], w[1]] if direction else [x + w[0], y + w[1]]

    for item in desc["joints"] + desc["drivers"]:
        kind = item.get("type")
        for key, sides in WORLD_POINTS.get(kind, {}).items():
            if key in item:
                # a drawn point of two bodies goes with either (they agree once assembled)
                bodies = [item[side] for side in sides]
                item[key] = carry(next((b for b in bodies if b != GROUND), bodies[-1]), item[key])
        for key, side in WORLD_DIRECTIONS.get(kind, {}).items():
            if key in item:
                item[key] = carry(item[side], item[key], direction=True)
        if kind in CURVES and moved(item["body_a"]):
            raise InputError(
                f"joint {item['name']!r}: its curve is fixed in {item['body_a']!r}, which assembling "
                "moves from its pose; give that body its drawn pose (a curve is drawn in world terms)"
            )
    for p in desc["points"]:
        p["at"] = carry(p["body"], p["at"])
    for ld in desc["loads"]:
        for key, side in (("at", "body"), ("at_a", "body_a"), ("at_b", "body_b")):
            if key in ld and side in ld:
                ld[key] = carry(ld[side], ld[key])
    for b in desc["bodies"]:
        if "com" in b:
            b["com"] = carry(b["name"], b["com"])
