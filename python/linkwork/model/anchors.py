"""Where each joint's and driver's points and each named point sit in their bodies' frames:
u = A(theta0)^T (P - R0) from the description's world points at the start and the bodies'
starting poses, read through the joint types' roles (`linkwork.kinds`). A sweep traces any
of them by name (`Model.sweep(outputs=...)`); the drawing draws them."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..kinds import GROUND, WORLD_POINTS

__all__ = ["Anchor", "Frames", "constraint_anchors", "traceable"]


@dataclass(frozen=True)
class Anchor:
    """A point fixed in a body: where a joint or driver acts, or a named point."""

    name: str  # the joint, driver or point
    kind: str  # "joint", "driver", "point" or "origin" (a body with nothing attached)
    type: str  # the joint or driver type ("point", "origin")
    body: str  # the body it is fixed in, or "ground"
    local: tuple[float, float]  # u, in the body's frame


def _rotate(theta: float, v: tuple[float, float]) -> tuple[float, float]:
    c, s = math.cos(theta), math.sin(theta)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


class Frames:
    """The moving bodies' frames at the start (``q_start``); the ground's is the world's."""

    def __init__(self, body_names: Sequence[str], q_start: np.ndarray) -> None:
        self._index = {name: i for i, name in enumerate(body_names)}
        self._q_start = np.asarray(q_start, dtype=np.float64)

    def pose(self, body: str) -> tuple[float, float, float] | None:
        """(x0, y0, theta0) of a moving body, None for the ground or an unknown body."""
        i = self._index.get(body)
        if i is None:
            return None
        x, y, th = self._q_start[3 * i : 3 * i + 3]
        return float(x), float(y), float(th)

    def local(self, body: str, world: Any) -> tuple[float, float]:
        """A world point at the start in ``body``'s frame."""
        px, py = float(world[0]), float(world[1])
        pose = self.pose(body)
        if pose is None:  # the ground's frame is the world's
            return (px, py)
        x0, y0, th0 = pose
        return _rotate(-th0, (px - x0, py - y0))

    def known(self, body: str) -> bool:
        return body == GROUND or body in self._index


def constraint_anchors(frames: Frames, kind: str, item: dict[str, Any]) -> list[tuple[str, Anchor]] | None:
    """The anchors of a joint or driver (``kind``), each with the field naming its body,
    in the order of its type's roles; None for a type with no roles listed."""
    type_, name = str(item.get("type")), str(item.get("name"))
    fields = WORLD_POINTS.get(type_)
    if fields is None:
        return None
    found = []
    for field, body_fields in fields.items():
        if field not in item:
            continue
        for body_field in body_fields:
            body = str(item.get(body_field))
            if frames.known(body):
                found.append((body_field, Anchor(name, kind, type_, body, frames.local(body, item[field]))))
    return found


def traceable(
    body_names: Sequence[str], q_start: np.ndarray, description: dict[str, Any]
) -> dict[str, Anchor]:
    """Every named point, joint and driver that has a point, by name: a joint's or
    driver's point on its moving side (the last of its type's roles), a named point
    itself (a point named like a joint wins)."""
    frames = Frames(body_names, q_start)
    out: dict[str, Anchor] = {}
    for kind, group in (("joint", "joints"), ("driver", "drivers")):
        for item in description.get(group, []):
            added = dict(constraint_anchors(frames, kind, item) or [])
            moving = [a for a in added.values() if a.body != GROUND]
            if moving:
                out.setdefault(str(item.get("name")), moving[-1])
    for p in description.get("points", []):
        name, body = str(p["name"]), str(p["body"])
        out[name] = Anchor(name, "point", "point", body, frames.local(body, p["at"]))
    return out
