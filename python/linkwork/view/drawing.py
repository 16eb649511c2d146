"""Drawing a mechanism: where each body's joints and points sit in its own frame, their
world positions over a sweep, and matplotlib artists that draw the mechanism at any step.

The geometry comes from the model description (joints, drivers and points at world
points at the start) and the starting poses: a point P of body i has the local vector
u = A(theta0_i)^T (P - R0_i), and at step k it is at R_i(k) + A(theta_i(k)) u, computed
for every step and every point at once.

>>> import numpy as np
>>> from linkwork import examples
>>> model = examples.four_bar().compile()
>>> geometry = Geometry.from_model(model)
>>> [a.name for a in geometry.anchors if a.body == "coupler"]
['A', 'B', 'P']
>>> xy = geometry.world(model.sweep(np.linspace(0.0, 1.0, 11)).q)
>>> xy.shape                                                    # (steps, anchors, 2)
(11, 9, 2)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..kinds import CURVES, GROUND, GUIDES, WHEELS, WORLD_POINTS
from ..model.anchors import Anchor, Frames, _rotate, constraint_anchors

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from linkwork import Model, Results

__all__ = [
    "WORLD_POINTS",
    "GUIDES",
    "CURVES",
    "Anchor",
    "Slider",
    "Curve",
    "Mesh",
    "Belt",
    "Rack",
    "Mark",
    "Geometry",
    "Motion",
    "MechanismArtists",
    "ground_symbols",
    "colour",
]

# from the joint types' roles (`linkwork.kinds`): GUIDES, the types drawn as a block
# (body_b) sliding on a guide (body_a), with the field of the slide's direction (a
# point_on_line is drawn the other way round: its pin, body_a, in the slot of body_b);
# WHEELS, the types drawn as pitch circles with a radial mark that shows their turning

#: teeth drawn along a rack's pitch line at most
RACK_TEETH = 200

#: a curve's kind -> (line width in points, matplotlib line style); the SVG and DXF
#: drawings dash the same kinds
CURVE_STYLES: dict[str, tuple[float, str]] = {
    "curve": (1.5, "-"),
    "pitch": (1.0, "-."),
    "mark": (1.5, "-"),
    "teeth": (1.0, "-"),
}

#: points drawn along a curve's period
CURVE_SAMPLES = 257

#: the colour of springs (spring-damper loads), in every drawing
SPRING_COLOUR = "#8c564b"


@dataclass(frozen=True)
class Slider:
    """A block (``block`` anchor, on body_b) sliding on a guide (``guide`` anchor, on
    body_a) along ``axis``, a unit vector in the guide body's frame."""

    joint: str
    guide: int
    block: int
    axis: tuple[float, float]


@dataclass(frozen=True)
class Curve:
    """A curve fixed in a body (``body``: index among the moving bodies, -1 for the
    ground) through the points ``local`` (m, 2) of its frame. ``kind``: "curve" (a slot,
    a cam profile, a roller), "pitch" (a pitch circle or a rack's pitch line, drawn
    dash-dot), "mark" (a radial line on a wheel, showing its turning) or "teeth" (a
    rack's)."""

    joint: str
    body: int
    local: np.ndarray
    kind: str = "curve"


@dataclass(frozen=True)
class Mesh:
    """Where two pitch circles touch: the point a + t (b - a) on the line through the
    centre anchors ``a`` and ``b`` (t = r_a / (r_a + r_b) for external gears,
    r_a / (r_a - r_b) for internal ones)."""

    joint: str
    a: int
    b: int
    t: float


@dataclass(frozen=True)
class Belt:
    """A belt or chain round two pulleys: centre anchors ``a``, ``b``, pitch radii
    ``r_a``, ``r_b``; ``crossed``: the two strands cross between the pulleys."""

    joint: str
    a: int
    b: int
    r_a: float
    r_b: float
    crossed: bool


@dataclass(frozen=True)
class Rack:
    """A rack (``body``, index among the moving bodies, -1 for the ground) meshing with a
    pinion whose centre is anchor ``centre``, pitch radius ``radius``: the rack's pitch
    line goes through ``base`` along ``axis`` (a unit vector), both in the rack's frame,
    on the side of the pinion's centre that a counter-clockwise turn moves along +axis."""

    joint: str
    body: int
    centre: int
    radius: float
    base: tuple[float, float]
    axis: tuple[float, float]


@dataclass(frozen=True)
class Mark:
    """A drawn element that is fixed in no one body, at every step of a sweep: ``xy``
    (n_steps, m, 2). ``kind``: "mesh" (m = 1: where pitch circles or a rack touch, a
    dot) or "strand" (m = 2: a straight run of a belt, a segment)."""

    joint: str
    kind: str
    xy: np.ndarray


class Geometry:
    """The anchors of a model's drawing, in body frames, and how to draw them.

    ``anchors``: every attachment point; ``outlines``: per moving body, the indices of its
    distinct anchors in the order its outline goes round; ``pins``: one anchor per
    revolute; ``ground_pins``: the ground's side of revolutes to the ground;
    ``sliders``; ``actuators``: the two anchors of each two-point driver (distance);
    ``rods``: the two anchors of each distance joint (a tie rod, a massless coupler);
    ``springs``: the two anchors of each spring-damper load (kind "load", in no outline);
    ``points``: the named points; ``traceable``: name -> anchor index of every named
    point, joint and driver that has one (a joint's point on its moving side);
    ``curves``: the slots, cam profiles and rollers, pitch circles of gears, pulleys and
    pinions and the marks on them, each in the frame of its body; ``meshes``, ``belts``
    and ``racks``: what is drawn between two bodies (see `Motion.marks`).
    """

    def __init__(self, body_names: list[str], q_start: np.ndarray, description: dict[str, Any]) -> None:
        self.body_names = list(body_names)
        self._index = {name: i for i, name in enumerate(self.body_names)}
        self._q_start = np.asarray(q_start, dtype=np.float64)
        self._frames = Frames(self.body_names, self._q_start)
        self.anchors: list[Anchor] = []
        self.pins: list[int] = []
        self.ground_pins: list[int] = []
        self.sliders: list[Slider] = []
        self.actuators: list[tuple[int, int]] = []
        self.points: list[int] = []
        self.traceable: dict[str, int] = {}
        self.curves: list[Curve] = []
        self.rods: list[tuple[int, int]] = []
        self.springs: list[tuple[int, int]] = []
        self.meshes: list[Mesh] = []
        self.belts: list[Belt] = []
        self.racks: list[Rack] = []

        for kind, group in (("joint", "joints"), ("driver", "drivers")):
            for item in description.get(group, []):
                self._add_constraint(kind, item)
        for p in description.get("points", []):
            k = self._add(str(p["name"]), "point", "point", str(p["body"]), p["at"])
            self.points.append(k)
            self.traceable[str(p["name"])] = k
        for ld in description.get("loads", []):
            ends = [(ld.get("body_a"), ld.get("at_a")), (ld.get("body_b"), ld.get("at_b"))]
            if ld.get("type") == "spring" and all(self._known(str(b)) and at is not None for b, at in ends):
                name = str(ld.get("name"))
                a, b = (self._add(name, "load", "spring", str(body), at) for body, at in ends)
                self.springs.append((a, b))
        # a body with nothing attached is drawn as a dot at its frame origin
        attached = {a.body for a in self.anchors if a.kind != "load"}
        for name in self.body_names:
            if name not in attached:
                self.anchors.append(Anchor(name, "origin", "origin", name, (0.0, 0.0)))
        # coincident anchors (a pin and a slider at one point) count once in an outline
        tol = 1e-9 * max([abs(c) for a in self.anchors for c in a.local] + [1e-300])
        by_body: dict[str, list[int]] = {}
        for k, a in enumerate(self.anchors):
            if a.kind != "load":  # a spring's ends are drawn by the spring, not the body
                by_body.setdefault(a.body, []).append(k)
        self.outlines = {name: self._outline(by_body.get(name, []), tol) for name in self.body_names}

    @classmethod
    def from_model(cls, model: Model) -> Geometry:
        """The drawing of a compiled model: its description and starting poses (the
        engine's, in radians whatever units the file used)."""
        return cls(model.body_names, model.q_start, model.description)

    def _pose(self, body: str) -> tuple[float, float, float] | None:
        return self._frames.pose(body)

    def _local(self, body: str, world: Any) -> tuple[float, float]:
        return self._frames.local(body, world)

    def _add(self, name: str, kind: str, type_: str, body: str, world: Any) -> int:
        self.anchors.append(Anchor(name, kind, type_, body, self._local(body, world)))
        return len(self.anchors) - 1

    def _known(self, body: str) -> bool:
        return self._frames.known(body)

    def _add_constraint(self, kind: str, item: dict[str, Any]) -> None:
        type_, name = str(item.get("type")), str(item.get("name"))
        found = constraint_anchors(self._frames, kind, item)
        if found is None:
            return  # a type the drawing does not know: not drawn
        added: dict[str, int] = {}  # body field -> anchor index
        for body_field, anchor in found:
            self.anchors.append(anchor)
            added[body_field] = len(self.anchors) - 1
        if type_ in CURVES and self._known(str(item.get("body_a"))):
            self._add_curve(name, str(item["body_a"]), item.get("curve"))
        body_b = str(item.get("body_b"))
        if item.get("follower") == "roller" and self._known(body_b) and "at" in item:
            # the roller itself, a circle about its centre on the follower
            radius = float(item.get("radius") or 0.0)
            centre = np.asarray(self._local(body_b, item["at"]))
            s = np.linspace(0.0, 2.0 * math.pi, CURVE_SAMPLES)
            local = centre + radius * np.column_stack([np.cos(s), np.sin(s)])
            if radius > 0.0 and np.all(np.isfinite(local)):
                self.curves.append(Curve(name, self._index.get(body_b, -1), local))
        moving = [k for k in added.values() if self.anchors[k].body != GROUND]
        if moving:
            self.traceable.setdefault(name, moving[-1])
        if type_ == "revolute" and moving:
            self.pins.append(moving[-1])
            if "body_a" in added and "body_b" in added:
                ground = [k for k in added.values() if self.anchors[k].body == GROUND]
                self.ground_pins += ground
        elif type_ in GUIDES and "body_a" in added and "body_b" in added:
            axis = np.asarray(item[GUIDES[type_]], dtype=np.float64)
            norm = float(np.hypot(axis[0], axis[1]))
            if norm > 0.0:
                pose = self._pose(str(item["body_a"]))
                local = _rotate(-pose[2] if pose else 0.0, (axis[0] / norm, axis[1] / norm))
                self.sliders.append(Slider(name, added["body_a"], added["body_b"], local))
        elif type_ == "point_on_line" and "body_a" in added and self._known(str(item.get("body_b"))):
            self._add_slot(name, item, added["body_a"])
        elif kind == "driver" and len(added) == 2:
            a, b = added.values()
            self.actuators.append((a, b))
        if type_ == "distance" and kind == "joint" and len(added) == 2:
            self.rods.append((added["body_a"], added["body_b"]))
        if type_ in WHEELS and kind == "joint":
            self._add_wheels(name, type_, item, added)

    def _add_slot(self, name: str, item: dict[str, Any], pin: int) -> None:
        """A point_on_line: the pin's block in a straight slot of body_b, through
        ``through`` (default the pin's start) moved by ``offset`` across the axis."""
        axis = np.asarray(item.get("axis", (0.0, 0.0)), dtype=np.float64)
        norm = float(np.hypot(axis[0], axis[1]))
        if not norm > 0.0:
            return
        e = axis / norm
        n = np.array([-e[1], e[0]])
        at = np.asarray(item["at"], dtype=np.float64)
        through = np.asarray(item.get("through", at), dtype=np.float64)
        offset = item.get("offset")
        offset = float(np.dot(at - through, n)) if offset is None else float(offset)
        body = str(item["body_b"])
        guide = self._add(name, "joint", "point_on_line", body, through + offset * n)
        pose = self._pose(body)
        local = _rotate(-pose[2] if pose else 0.0, (float(e[0]), float(e[1])))
        self.sliders.append(Slider(name, guide, pin, local))

    def _origin(self, body: str) -> tuple[float, float]:
        pose = self._pose(body)
        return (pose[0], pose[1]) if pose else (0.0, 0.0)

    def _wheel(self, joint: str, body: str, centre: int, radius: float, towards: np.ndarray) -> None:
        """A pitch circle of ``radius`` about anchor ``centre`` and a radial mark on it
        pointing ``towards`` (a world direction at the start), fixed in ``body``."""
        pose = self._pose(body)
        u = np.asarray(self.anchors[centre].local)
        d = np.asarray(_rotate(-pose[2] if pose else 0.0, (float(towards[0]), float(towards[1]))))
        s = np.linspace(0.0, 2.0 * math.pi, CURVE_SAMPLES)
        i = self._index.get(body, -1)
        self.curves.append(Curve(joint, i, u + radius * np.column_stack([np.cos(s), np.sin(s)]), "pitch"))
        self.curves.append(Curve(joint, i, np.array([u, u + radius * d]), "mark"))

    def _add_wheels(self, name: str, type_: str, item: dict[str, Any], added: dict[str, int]) -> None:
        """Pitch circles of a gear pair, of two pulleys and the belt's strands, or of a
        pinion and its rack's pitch line. Centres left out are the bodies' origins; radii
        left out come from the ratio and the centres' distance (gears) or are drawn a
        quarter of that distance for the larger pulley (a belt's length is free)."""
        body_a, body_b = str(item.get("body_a")), str(item.get("body_b"))
        if not (self._known(body_a) and self._known(body_b)):
            return
        if type_ == "rack_pinion":
            self._add_rack(name, item, added, body_a, body_b)
            return
        c_a = np.asarray(item.get("centre_a") or self._origin(body_a), dtype=np.float64)
        c_b = np.asarray(item.get("centre_b") or self._origin(body_b), dtype=np.float64)
        d = float(math.dist(c_a, c_b))
        r_a, r_b, ratio = item.get("radius_a"), item.get("radius_b"), item.get("ratio")
        internal = bool(item.get("internal")) and type_ == "gear"
        if (r_a is None or r_b is None) and ratio is not None and float(ratio) > 0.0:
            ratio = float(ratio)
            if type_ == "gear":
                r_b = d / abs(ratio - 1.0) if internal else d / (1.0 + ratio)
                r_a = ratio * r_b
            else:
                r_a, r_b = (0.25 * d, 0.25 * d / ratio) if ratio >= 1.0 else (0.25 * d * ratio, 0.25 * d)
        if r_a is None or r_b is None:
            return
        r_a, r_b = float(r_a), float(r_b)
        if not (math.isfinite(r_a) and math.isfinite(r_b) and r_a > 0.0 and r_b > 0.0 and d > 0.0):
            return
        a = added.get("body_a", None) if "centre_a" in item else None
        b = added.get("body_b", None) if "centre_b" in item else None
        a = self._add(name, "joint", type_, body_a, c_a) if a is None else a
        b = self._add(name, "joint", type_, body_b, c_b) if b is None else b
        e = (c_b - c_a) / d
        self._wheel(name, body_a, a, r_a, e)
        self._wheel(name, body_b, b, r_b, -e)
        if type_ == "gear":
            self.meshes.append(Mesh(name, a, b, r_a / (r_a - r_b) if internal else r_a / (r_a + r_b)))
        else:
            self.belts.append(Belt(name, a, b, r_a, r_b, bool(item.get("crossed"))))

    def _add_rack(
        self, name: str, item: dict[str, Any], added: dict[str, int], pinion: str, rack: str
    ) -> None:
        radius = float(item.get("radius") or 0.0)
        axis = np.asarray(item.get("axis", (0.0, 0.0)), dtype=np.float64)
        norm = float(np.hypot(axis[0], axis[1]))
        if not (math.isfinite(radius) and radius > 0.0 and norm > 0.0):
            return
        c = np.asarray(item.get("centre") or self._origin(pinion), dtype=np.float64)
        k = added.get("body_a") if "centre" in item else None
        k = self._add(name, "joint", "rack_pinion", pinion, c) if k is None else k
        e = axis / norm
        n = np.array([-e[1], e[0]])
        # a counter-clockwise turn moves the rack along +axis: it touches on the -n side
        self._wheel(name, pinion, k, radius, -n)
        pose = self._pose(rack)
        local_axis = _rotate(-pose[2] if pose else 0.0, (float(e[0]), float(e[1])))
        self.racks.append(
            Rack(name, self._index.get(rack, -1), k, radius, self._local(rack, c - radius * n), local_axis)
        )

    def _add_curve(self, joint: str, body: str, desc: Any) -> None:
        """Samples the joint's curve over one period, in the frame of ``body``. The curve
        comes from the independent reference's evaluator; one it refuses is not drawn
        (compiling the model names the fault)."""
        from ..reference.curves import build_curve

        try:
            curve = build_curve(desc, self._pose(body) or (0.0, 0.0, 0.0), f"joint '{joint}'")
            local = np.array([curve(s)[0] for s in np.linspace(0.0, 2.0 * math.pi, CURVE_SAMPLES)])
        except (ValueError, KeyError, TypeError, ZeroDivisionError, OverflowError):
            return
        if local.shape == (CURVE_SAMPLES, 2) and np.all(np.isfinite(local)):
            self.curves.append(Curve(joint, self._index.get(body, -1), local))

    def _outline(self, anchors: list[int], tol: float) -> list[int]:
        """A body's distinct anchors (given: the indices of its anchors), ordered by angle
        about their centroid, so that the polygon through them does not cross itself."""
        found: list[int] = []
        for k in anchors:
            a = self.anchors[k]
            if all(math.dist(a.local, self.anchors[j].local) > tol for j in found):
                found.append(k)
        if len(found) < 3:
            return found
        u = np.array([self.anchors[k].local for k in found])
        c = u.mean(axis=0)
        order = np.argsort(np.arctan2(u[:, 1] - c[1], u[:, 0] - c[0]), kind="stable")
        return [found[int(i)] for i in order]

    def body_of(self, k: int) -> int:
        """Index of anchor k's body among the moving bodies, -1 for the ground."""
        return self._index.get(self.anchors[k].body, -1)

    def world(
        self, q: np.ndarray, local: np.ndarray | None = None, bodies: np.ndarray | None = None
    ) -> np.ndarray:
        """World positions (n_steps, n_anchors, 2) of every anchor over the rows of ``q``
        (n_steps, n_coords); or of the points ``local`` (m, 2) fixed in ``bodies`` (m,)
        (indices among the moving bodies, -1 for the ground), (n_steps, m, 2)."""
        if local is None or bodies is None:
            local = np.array([a.local for a in self.anchors], dtype=np.float64).reshape(-1, 2)
            bodies = np.array([self.body_of(k) for k in range(len(self.anchors))], dtype=np.intp)
        q = np.asarray(q, dtype=np.float64)
        out = np.broadcast_to(local, (q.shape[0],) + local.shape).copy()
        moving = bodies >= 0
        j = 3 * bodies[moving]
        u = local[moving]
        th = q[:, j + 2]
        c, s = np.cos(th), np.sin(th)
        out[:, moving, 0] = q[:, j] + c * u[:, 0] - s * u[:, 1]
        out[:, moving, 1] = q[:, j + 1] + s * u[:, 0] + c * u[:, 1]
        return out

    def axis_world(self, q: np.ndarray, slider: Slider) -> np.ndarray:
        """The slider's direction in world axes at every row of ``q``, (n_steps, 2)."""
        i = self.body_of(slider.guide)
        if i < 0:
            return np.broadcast_to(np.asarray(slider.axis), (q.shape[0], 2)).copy()
        th = q[:, 3 * i + 2]
        c, s = np.cos(th), np.sin(th)
        ax, ay = slider.axis
        return np.stack([c * ax - s * ay, s * ax + c * ay], axis=-1)


class Motion:
    """A mechanism's geometry in motion over a sweep: world positions of every anchor at
    every step, each slider's guide and direction, and what stays fixed while drawing it
    (``limits`` over the whole motion; ``size``, the diagonal of the motion's bounding
    box, which sizes the symbols)."""

    def __init__(self, geometry: Geometry, results: Results) -> None:
        if results.n_steps == 0:
            raise ValueError("nothing to draw: the results have no steps")
        self.geometry = geometry
        self.times = results.times
        self.xy = geometry.world(results.q)  # (n_steps, n_anchors, 2)
        lo = self.xy.reshape(-1, 2).min(axis=0)
        hi = self.xy.reshape(-1, 2).max(axis=0)
        diagonal = float(np.hypot(*(hi - lo)))
        self.size = diagonal if diagonal > 0.0 else results.model.length_scale
        self.axes = [geometry.axis_world(results.q, s) for s in geometry.sliders]  # each (n_steps, 2)
        self.guides = [self._guide(results.q, s, a) for s, a in zip(geometry.sliders, self.axes)]
        self.q = results.q
        #: the geometry's curves, then each rack's pitch line and teeth (over its travel)
        self.curves = list(geometry.curves)
        #: what is fixed in no one body: mesh points, belts' strands
        self.marks: list[Mark] = []
        for m in geometry.meshes:
            a, b = self.xy[:, m.a], self.xy[:, m.b]
            self.marks.append(Mark(m.joint, "mesh", (a + m.t * (b - a))[:, None, :]))
        for belt in geometry.belts:
            self.marks += [Mark(belt.joint, "strand", xy) for xy in self._strands(belt)]
        for rack in geometry.racks:
            self._rack(rack)
        # the curves' extent from a few steps spread over the sweep: a whole sweep of a
        # 257-point curve would take n_steps times its memory
        rows = self.frames(64)
        ends = [g.reshape(-1, 2) for g in self.guides]
        ends += [self.curve(c, rows).reshape(-1, 2) for c in self.curves]
        ends += [m.xy[np.isfinite(m.xy).all(axis=-1)] for m in self.marks]
        allxy = np.concatenate([self.xy.reshape(-1, 2)] + ends)
        margin = 0.08 * self.size
        lo, hi = allxy.min(axis=0) - margin, allxy.max(axis=0) + margin
        lo[1] -= 0.06 * self.size if geometry.ground_pins else 0.0  # room for the ground symbols
        self.limits = ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])))

    def _strands(self, belt: Belt) -> tuple[np.ndarray, np.ndarray]:
        """The belt's two straight runs at every step, each (n_steps, 2, 2): the common
        tangents of the pitch circles, outer ones for an open belt, crossing ones for a
        crossed belt (NaN where the circles overlap and there is none)."""
        c_a, c_b = self.xy[:, belt.a], self.xy[:, belt.b]
        d = c_b - c_a
        length = np.hypot(d[:, 0], d[:, 1])[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            e = d / length
            n = np.stack([-e[:, 1], e[:, 0]], axis=-1)
            # the unit normal m of a tangent line has m.d = r_b s_b - r_a, s_b = +-1
            s_b = -1.0 if belt.crossed else 1.0
            cos = (s_b * belt.r_b - belt.r_a) / length
            sin = np.sqrt(1.0 - cos**2)
        out = []
        for side in (1.0, -1.0):
            m = cos * e + side * sin * n
            out.append(np.stack([c_a - belt.r_a * m, c_b - s_b * belt.r_b * m], axis=1))
        return out[0], out[1]

    def _rack(self, rack: Rack) -> None:
        """A rack's pitch line and teeth, fixed in its body, covering where the pinion
        touches it over the whole sweep; and the touching point at every step."""
        g = self.geometry
        c = self.xy[:, rack.centre]
        if rack.body >= 0:
            j = 3 * rack.body
            th = self.q[:, j + 2]
            cs, sn = np.cos(th), np.sin(th)
            rel = c - self.q[:, j : j + 2]
            local = np.stack([cs * rel[:, 0] + sn * rel[:, 1], -sn * rel[:, 0] + cs * rel[:, 1]], axis=-1)
        else:
            local = c
        e = np.asarray(rack.axis)
        n = np.array([-e[1], e[0]])
        base = np.asarray(rack.base)
        along = (local - base) @ e
        lo, hi = float(along.min()) - 3.0 * rack.radius, float(along.max()) + 3.0 * rack.radius
        pitch = max(2.0 * math.pi * rack.radius / 16.0, (hi - lo) / RACK_TEETH)
        s = lo + 0.5 * pitch * np.arange(int((hi - lo) / (0.5 * pitch)) + 1)
        h = 0.3 * pitch * np.where(np.arange(len(s)) % 2 == 0, -1.0, 1.0)
        self.curves.append(Curve(rack.joint, rack.body, base + np.outer([lo, hi], e), "pitch"))
        self.curves.append(Curve(rack.joint, rack.body, base + np.outer(s, e) + np.outer(h, n), "teeth"))
        # the touching point: the pinion's centre moved by its radius towards the rack
        bodies = np.array([rack.body], dtype=np.intp)
        axis = g.world(self.q, np.array([e]), bodies)[:, 0] - g.world(self.q, np.zeros((1, 2)), bodies)[:, 0]
        normal = np.stack([-axis[:, 1], axis[:, 0]], axis=-1)
        self.marks.append(Mark(rack.joint, "mesh", (c - rack.radius * normal)[:, None, :]))

    def curve(self, curve: Curve, rows: Any) -> np.ndarray:
        """World points of a curve at the steps ``rows`` (an index or an array of them),
        (len(rows), m, 2) or (m, 2)."""
        q = self.q[rows]
        one = q.ndim == 1
        bodies = np.full(len(curve.local), curve.body, dtype=np.intp)
        xy = self.geometry.world(np.atleast_2d(q), curve.local, bodies)
        return xy[0] if one else xy

    @property
    def block(self) -> tuple[float, float]:
        """Half length and half height of a slider block."""
        return 0.045 * self.size, 0.025 * self.size

    def _guide(self, q: np.ndarray, slider: Slider, axis: np.ndarray) -> np.ndarray:
        """The ends of a slider's guide at every step, (n_steps, 2, 2): a segment of the
        guide body along the axis covering the block's whole travel."""
        travel = np.einsum("ij,ij->i", self.xy[:, slider.block] - self.xy[:, slider.guide], axis)
        half = self.block[0]
        g = self.geometry
        base = np.asarray(g.anchors[slider.guide].local)
        ends = np.array(
            [
                base + (travel.min() - 1.5 * half) * np.asarray(slider.axis),
                base + (travel.max() + 1.5 * half) * np.asarray(slider.axis),
            ]
        )
        body = g.body_of(slider.guide)
        return g.world(q, ends, np.array([body, body], dtype=np.intp))

    def block_polygon(self, k: int, row: int) -> np.ndarray:
        """The corners (4, 2) of slider k's block at step ``row``: a rectangle about the
        block's anchor, its long side along the guide."""
        a = self.axes[k][row]
        n = np.array([-a[1], a[0]])
        c = self.xy[row, self.geometry.sliders[k].block]
        half_l, half_h = self.block
        return np.array(
            [c - half_l * a - half_h * n, c + half_l * a - half_h * n, c + half_l * a + half_h * n,
             c - half_l * a + half_h * n]
        )  # fmt: skip

    def hatch_polygon(self, k: int, row: int) -> np.ndarray:
        """The strip (4, 2) hatched beside slider k's guide at step ``row``, on the side
        away from the block (drawn for guides on the ground)."""
        a = self.axes[k][row]
        n = np.array([-a[1], a[0]])
        ends = self.guides[k][row]
        side = -1.0 if np.dot(self.xy[row, self.geometry.sliders[k].block] - ends[0], n) >= 0.0 else 1.0
        off = side * n * self.block[1]
        return np.array([ends[0] + off * 0.5, ends[1] + off * 0.5, ends[1] + off * 1.5, ends[0] + off * 1.5])

    def frames(self, n_frames: int) -> np.ndarray:
        """Indices of about ``n_frames`` steps spread evenly over the sweep, first and last
        included (every step if there are fewer)."""
        n = len(self.times)
        return np.unique(np.linspace(0, n - 1, max(1, min(int(n_frames), n))).round().astype(np.intp))


_COLOURS = [f"tab:{c}" for c in ("blue", "orange", "green", "red", "purple", "brown", "pink", "olive")]


class MechanismArtists:
    """Matplotlib artists drawing a mechanism on ``ax``: each body as the polygon (or
    segment) through its anchors, pins as small circles, ground pivots as hatched
    triangles, sliders as blocks on their guides, slots and cam profiles as curves in
    the colour of their body, pitch circles (dash-dot, with a radial mark) of gears,
    pulleys and pinions, racks, belts' strands, mesh points as dots, distance joints as
    solid bars, distance drivers as dashed lines, springs as thin dotted lines, and
    named points with their trace so far; with ``labels``, the names of the bodies and
    joints too. ``update(row)`` moves everything to a step."""

    def __init__(
        self,
        ax: Axes,
        motion: Motion,
        alpha: float = 1.0,
        traces: bool = True,
        clock: bool = False,
        labels: bool = False,
    ) -> None:
        from matplotlib.lines import Line2D
        from matplotlib.patches import Polygon

        self.motion, self.ax = motion, ax
        g = motion.geometry
        s = motion.size
        lw = 2.5
        self.bodies = []
        for i, name in enumerate(g.body_names):
            colour = _COLOURS[i % len(_COLOURS)]
            patch = Polygon(
                np.zeros((1, 2)),
                closed=True,
                facecolor=colour,
                edgecolor="none",
                alpha=0.35 * alpha,
                zorder=2,
            )
            edge = Polygon(
                np.zeros((1, 2)), closed=True, fill=False, edgecolor=colour, lw=lw, alpha=alpha, zorder=3
            )
            ax.add_patch(patch)
            ax.add_patch(edge)
            self.bodies.append((g.outlines[name], patch, edge))
        self._ground_symbols(ax, [motion.xy[0, k] for k in g.ground_pins], 0.035 * s, alpha)
        self.guides = []
        for slider in g.sliders:
            (line,) = ax.plot([], [], color="0.35", lw=1.5, alpha=alpha, zorder=1)
            hatch = None
            if g.body_of(slider.guide) < 0:
                hatch = Polygon(
                    np.zeros((4, 2)),
                    closed=True,
                    fill=False,
                    hatch="////",
                    lw=0,
                    alpha=alpha,
                    edgecolor="0.45",
                    zorder=1,
                )
                ax.add_patch(hatch)
            block = Polygon(
                np.zeros((4, 2)), closed=True, facecolor="0.8", edgecolor="0.2", lw=1.5, alpha=alpha, zorder=4
            )
            ax.add_patch(block)
            self.guides.append((line, hatch, block))
        self.actuators = [
            ax.plot([], [], color="0.2", lw=1.5, ls="--", alpha=alpha, zorder=3)[0] for _ in g.actuators
        ]
        # a slot, cam profile, pitch circle or rack in the colour of the body that carries it
        self.curves = [
            ax.plot(
                [],
                [],
                color=_COLOURS[c.body % len(_COLOURS)] if c.body >= 0 else "0.3",
                lw=CURVE_STYLES[c.kind][0],
                ls=CURVE_STYLES[c.kind][1],
                alpha=alpha,
                zorder=3,
            )[0]
            for c in motion.curves
        ]
        # tie rods and couplers of distance joints: thin solid bars
        self.rods = [ax.plot([], [], color="0.25", lw=2.0, alpha=alpha, zorder=3)[0] for _ in g.rods]
        self.springs = [
            ax.plot([], [], color=SPRING_COLOUR, lw=1.2, ls=":", alpha=alpha, zorder=3)[0] for _ in g.springs
        ]
        # mesh points and belts' strands
        self.marks = [
            ax.plot([], [], ls="none", marker="o", ms=4, color="black", alpha=alpha, zorder=6)[0]
            if m.kind == "mesh"
            else ax.plot([], [], color="0.2", lw=1.5, alpha=alpha, zorder=3)[0]
            for m in motion.marks
        ]
        self.pins = Line2D(
            [], [], ls="none", marker="o", ms=6, mfc="white", mec="black", mew=1.5, alpha=alpha, zorder=5
        )
        ax.add_line(self.pins)
        self.traces = []
        for n, k in enumerate(g.points):
            colour = _COLOURS[(len(g.body_names) + n) % len(_COLOURS)]
            trace = ax.plot([], [], color=colour, lw=1.0, alpha=alpha, zorder=1)[0] if traces else None
            (dot,) = ax.plot([], [], ls="none", marker="o", ms=4, color=colour, alpha=alpha, zorder=6)
            label = ax.annotate(
                g.anchors[k].name,
                (0.0, 0.0),
                xytext=(4, 4),
                textcoords="offset points",
                fontsize=8,
                color=colour,
                alpha=alpha,
                zorder=6,
            )
            self.traces.append((k, trace, dot, label))
        # with labels: each body's name at the middle of its outline, each joint's at its point
        self.labels: list[tuple[list[int], Any]] = []
        if labels:
            for i, name in enumerate(g.body_names):
                text = ax.text(0.0, 0.0, name, fontsize=8, ha="center", va="center", alpha=alpha, zorder=7,
                               color=_COLOURS[i % len(_COLOURS)], fontweight="bold")  # fmt: skip
                self.labels.append((g.outlines[name], text))
            named = {g.anchors[k].name for k in g.points}
            for name, k in g.traceable.items():
                if name not in named and g.anchors[k].kind == "joint":
                    text = ax.annotate(name, (0.0, 0.0), xytext=(4, -10), textcoords="offset points",
                                       fontsize=7, color="0.25", alpha=alpha, zorder=7)  # fmt: skip
                    self.labels.append(([k], text))
        # the traces are drawn through at most this many steps, whatever the sweep's length
        self._trace_rows = np.unique(np.linspace(0, len(motion.times) - 1, 2000).round().astype(np.intp))
        self.clock = ax.text(0.02, 0.96, "", transform=ax.transAxes, va="top", fontsize=9) if clock else None

    @staticmethod
    def _ground_symbols(ax: Axes, pins: list[np.ndarray], h: float, alpha: float) -> None:
        """The usual ground pivot under each pin: a triangle on a hatched base (three
        collections for all of them: a large model has thousands)."""
        from matplotlib.collections import LineCollection, PolyCollection

        if not pins:
            return
        triangles, bases, lines = ground_symbols(np.asarray(pins, dtype=np.float64), h)
        ax.add_collection(
            PolyCollection(
                triangles, facecolors="0.85", edgecolors="0.2", linewidths=1.2, alpha=alpha, zorder=1
            )
        )
        ax.add_collection(
            PolyCollection(
                bases, facecolors="none", edgecolors="0.4", linewidths=0, hatch="////", alpha=alpha, zorder=1
            )
        )
        ax.add_collection(LineCollection(lines, colors="0.2", linewidths=1.2, alpha=alpha, zorder=1))

    def update(self, row: int) -> None:
        """Moves every artist to step ``row`` of the sweep."""
        m = self.motion
        xy = m.xy[row]
        for outline, patch, edge in self.bodies:
            pts = xy[outline]
            patch.set_xy(pts)
            edge.set_xy(pts)
        for k, (line, hatch, block) in enumerate(self.guides):
            ends = m.guides[k][row]
            line.set_data(ends[:, 0], ends[:, 1])
            if hatch is not None:  # a ground guide: hatching on the side away from the block
                hatch.set_xy(m.hatch_polygon(k, row))
            block.set_xy(m.block_polygon(k, row))
        for (a, b), line in zip(m.geometry.actuators, self.actuators):
            line.set_data([xy[a, 0], xy[b, 0]], [xy[a, 1], xy[b, 1]])
        for curve, line in zip(m.curves, self.curves):
            pts = m.curve(curve, row)
            line.set_data(pts[:, 0], pts[:, 1])
        for (a, b), line in zip(m.geometry.rods, self.rods):
            line.set_data([xy[a, 0], xy[b, 0]], [xy[a, 1], xy[b, 1]])
        for (a, b), line in zip(m.geometry.springs, self.springs):
            line.set_data([xy[a, 0], xy[b, 0]], [xy[a, 1], xy[b, 1]])
        for mark, line in zip(m.marks, self.marks):
            line.set_data(mark.xy[row, :, 0], mark.xy[row, :, 1])
        pins = xy[m.geometry.pins]
        self.pins.set_data(pins[:, 0], pins[:, 1])
        rows = self._trace_rows[self._trace_rows <= row]
        for k, trace, dot, label in self.traces:
            if trace is not None:
                path = m.xy[np.append(rows, row), k]
                trace.set_data(path[:, 0], path[:, 1])
            dot.set_data([xy[k, 0]], [xy[k, 1]])
            label.xy = (float(xy[k, 0]), float(xy[k, 1]))
        for ks, text in self.labels:
            x, y = xy[ks].mean(axis=0)
            if len(ks) > 1:
                text.set_position((float(x), float(y)))
            else:
                text.xy = (float(x), float(y))
        if self.clock is not None:
            self.clock.set_text(f"t = {m.times[row]:.6g} s")


def setup_axes(ax: Axes, motion: Motion, unit: str) -> None:
    """Equal scales on both axes and limits fixed over the whole motion."""
    (x0, x1), (y0, y1) = motion.limits
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.grid(True, alpha=0.25)


def ground_symbols(pins: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The usual ground pivot under each of the points ``pins`` (m, 2), ``h`` its size:
    the triangles (m, 3, 2), the hatched bases under them (m, 4, 2) and the base lines
    (m, 2, 2)."""
    p = np.asarray(pins, dtype=np.float64).reshape(-1, 2)
    x, y = p[:, 0], p[:, 1]
    triangles = np.stack(
        [np.stack([x, y], -1), np.stack([x - h, y - 1.6 * h], -1), np.stack([x + h, y - 1.6 * h], -1)], 1
    )
    bases = np.stack(
        [
            np.stack([x - 1.5 * h, y - 2.2 * h], -1),
            np.stack([x + 1.5 * h, y - 2.2 * h], -1),
            np.stack([x + 1.5 * h, y - 1.6 * h], -1),
            np.stack([x - 1.5 * h, y - 1.6 * h], -1),
        ],
        1,
    )
    lines = np.stack([np.stack([x - 1.5 * h, y - 1.6 * h], -1), np.stack([x + 1.5 * h, y - 1.6 * h], -1)], 1)
    return triangles, bases, lines


def colour(i: int) -> str:
    """The colour of moving body i (and of what it carries) as "#rrggbb"; -1, the ground, is grey."""
    from matplotlib.colors import to_hex

    return "#4d4d4d" if i < 0 else str(to_hex(_COLOURS[i % len(_COLOURS)]))
