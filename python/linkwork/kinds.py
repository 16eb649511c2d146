"""The joint and driver types' fields by role, read by the builder (assembly carries each
world point and direction with its body), the model (its traceable points) and the
drawing: which field is a world point fixed in which body, which a world direction,
which a curve. A type not listed here has no such field."""

from __future__ import annotations

__all__ = ["GROUND", "WORLD_POINTS", "WORLD_DIRECTIONS", "CURVES"]

#: the fixed frame's name wherever a body is named
GROUND = "ground"

#: joint or driver type -> {field holding a world point at the start: the fields naming
#: the bodies that point is fixed in}. A new joint type is one line here; a type not
#: listed (an unknown one too) adds nothing to the drawing.
WORLD_POINTS: dict[str, dict[str, tuple[str, ...]]] = {
    "revolute": {"at": ("body_a", "body_b")},
    "prismatic": {"at": ("body_a", "body_b")},
    "fixed": {},
    "angle": {},
    "relative_angle": {},
    "distance": {"at_a": ("body_a",), "at_b": ("body_b",)},
    "coordinate": {"at": ("body",)},
    "translation": {},
    "point_on_line": {"at": ("body_a",), "through": ("body_b",)},
    "gear": {"centre_a": ("body_a",), "centre_b": ("body_b",)},
    "rack_pinion": {"centre": ("body_a",)},
    "belt": {},
    "fixed_orientation": {},
    "parallel": {},
    "linear_coupling": {},
    "pin_in_slot": {"at": ("body_b",)},
    "cam_follower": {"at": ("body_b",)},
}

#: world directions at the start fixed in a body: joint or driver type -> {field: the
#: field naming the body} (a prismatic's axis is turned with its pins, in `assemble`)
WORLD_DIRECTIONS: dict[str, dict[str, str]] = {
    "point_on_line": {"axis": "body_b"},
    "rack_pinion": {"axis": "body_b"},
    "parallel": {"axis_a": "body_a", "axis_b": "body_b"},
    "cam_follower": {"face": "body_b"},
}

#: joint types whose ``curve`` (world coordinates at the start) is fixed in body_a and
#: drawn with it: a curved slot, a cam profile
CURVES: tuple[str, ...] = ("pin_in_slot", "cam_follower")
