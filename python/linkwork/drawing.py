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

from .mechanism import GROUND

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from .model import Model
    from .results import Results

__all__ = [
    "WORLD_POINTS",
    "GUIDES",
    "CURVES",
    "Anchor",
    "Slider",
    "Curve",
    "Geometry",
    "Motion",
    "MechanismArtists",
    "ground_symbols",
    "colour",
]

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

#: joint types drawn as a block (body_b) sliding on a guide (body_a): the field holding
#: the sliding direction (a world direction at the start, fixed in body_a)
GUIDES: dict[str, str] = {"prismatic": "axis"}

#: joint types whose ``curve`` (world coordinates at the start) is fixed in body_a and
#: drawn with it: a curved slot, a cam profile
CURVES: tuple[str, ...] = ("pin_in_slot", "cam_follower")

#: points drawn along a curve's period
CURVE_SAMPLES = 257


@dataclass(frozen=True)
class Anchor:
    """A point fixed in a body: where a joint or driver acts, or a named point."""

    name: str  # the joint, driver or point
    kind: str  # "joint", "driver", "point" or "origin" (a body with nothing attached)
    type: str  # the joint or driver type ("point", "origin")
    body: str  # the body it is fixed in, or "ground"
    local: tuple[float, float]  # u, in the body's frame


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
    ground) through the points ``local`` (m, 2) of its frame: a slot or a cam profile."""

    joint: str
    body: int
    local: np.ndarray


def _rotate(theta: float, v: tuple[float, float]) -> tuple[float, float]:
    c, s = math.cos(theta), math.sin(theta)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


class Geometry:
    """The anchors of a model's drawing, in body frames, and how to draw them.

    ``anchors``: every attachment point; ``outlines``: per moving body, the indices of its
    distinct anchors in the order its outline goes round; ``pins``: one anchor per
    revolute; ``ground_pins``: the ground's side of revolutes to the ground;
    ``sliders``; ``actuators``: the two anchors of each two-point driver (distance);
    ``points``: the named points; ``traceable``: name -> anchor index of every named
    point, joint and driver that has one (a joint's point on its moving side);
    ``curves``: the slots, cam profiles and rollers, each in the frame of its body.
    """

    def __init__(self, body_names: list[str], q_start: np.ndarray, description: dict[str, Any]) -> None:
        self.body_names = list(body_names)
        self._index = {name: i for i, name in enumerate(self.body_names)}
        self._q_start = np.asarray(q_start, dtype=np.float64)
        self.anchors: list[Anchor] = []
        self.pins: list[int] = []
        self.ground_pins: list[int] = []
        self.sliders: list[Slider] = []
        self.actuators: list[tuple[int, int]] = []
        self.points: list[int] = []
        self.traceable: dict[str, int] = {}
        self.curves: list[Curve] = []

        for kind, group in (("joint", "joints"), ("driver", "drivers")):
            for item in description.get(group, []):
                self._add_constraint(kind, item)
        for p in description.get("points", []):
            k = self._add(str(p["name"]), "point", "point", str(p["body"]), p["at"])
            self.points.append(k)
            self.traceable[str(p["name"])] = k
        # a body with nothing attached is drawn as a dot at its frame origin
        attached = {a.body for a in self.anchors}
        for name in self.body_names:
            if name not in attached:
                self.anchors.append(Anchor(name, "origin", "origin", name, (0.0, 0.0)))
        # coincident anchors (a pin and a slider at one point) count once in an outline
        tol = 1e-9 * max([abs(c) for a in self.anchors for c in a.local] + [1e-300])
        by_body: dict[str, list[int]] = {}
        for k, a in enumerate(self.anchors):
            by_body.setdefault(a.body, []).append(k)
        self.outlines = {name: self._outline(by_body.get(name, []), tol) for name in self.body_names}

    @classmethod
    def from_model(cls, model: Model) -> Geometry:
        """The drawing of a compiled model: its description and starting poses (the
        engine's, in radians whatever units the file used)."""
        return cls(model.body_names, model.q_start, model.description)

    def _pose(self, body: str) -> tuple[float, float, float] | None:
        """(x0, y0, theta0) of a moving body, None for the ground or an unknown body."""
        i = self._index.get(body)
        if i is None:
            return None
        x, y, th = self._q_start[3 * i : 3 * i + 3]
        return float(x), float(y), float(th)

    def _local(self, body: str, world: Any) -> tuple[float, float]:
        px, py = float(world[0]), float(world[1])
        pose = self._pose(body)
        if pose is None:  # the ground's frame is the world's
            return (px, py)
        x0, y0, th0 = pose
        return _rotate(-th0, (px - x0, py - y0))

    def _add(self, name: str, kind: str, type_: str, body: str, world: Any) -> int:
        self.anchors.append(Anchor(name, kind, type_, body, self._local(body, world)))
        return len(self.anchors) - 1

    def _known(self, body: str) -> bool:
        return body == GROUND or body in self._index

    def _add_constraint(self, kind: str, item: dict[str, Any]) -> None:
        type_, name = str(item.get("type")), str(item.get("name"))
        fields = WORLD_POINTS.get(type_)
        if fields is None:
            return  # a type the drawing does not know: not drawn
        added: dict[str, int] = {}  # body field -> anchor index
        for field, body_fields in fields.items():
            if field not in item:
                continue
            for body_field in body_fields:
                body = str(item.get(body_field))
                if self._known(body):
                    added[body_field] = self._add(name, kind, type_, body, item[field])
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
        elif kind == "driver" and len(added) == 2:
            a, b = added.values()
            self.actuators.append((a, b))

    def _add_curve(self, joint: str, body: str, desc: Any) -> None:
        """Samples the joint's curve over one period, in the frame of ``body``. The curve
        comes from the independent reference's evaluator; one it refuses is not drawn
        (compiling the model names the fault)."""
        from .reference.curves import build_curve

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
        # the curves' extent from a few steps spread over the sweep: a whole sweep of a
        # 257-point curve would take n_steps times its memory
        rows = self.frames(64)
        ends = [g.reshape(-1, 2) for g in self.guides]
        ends += [self.curve(c, rows).reshape(-1, 2) for c in geometry.curves]
        allxy = np.concatenate([self.xy.reshape(-1, 2)] + ends)
        margin = 0.08 * self.size
        lo, hi = allxy.min(axis=0) - margin, allxy.max(axis=0) + margin
        lo[1] -= 0.06 * self.size if geometry.ground_pins else 0.0  # room for the ground symbols
        self.limits = ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])))

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
    the colour of their body, distance drivers as dashed lines, and
    named points with their trace so far. ``update(row)`` moves everything to a step."""

    def __init__(
        self, ax: Axes, motion: Motion, alpha: float = 1.0, traces: bool = True, clock: bool = False
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
        # a slot or cam profile in the colour of the body that carries it
        self.curves = [
            ax.plot(
                [],
                [],
                color=_COLOURS[c.body % len(_COLOURS)] if c.body >= 0 else "0.3",
                lw=1.5,
                alpha=alpha,
                zorder=3,
            )[0]
            for c in g.curves
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
        for curve, line in zip(m.geometry.curves, self.curves):
            pts = m.curve(curve, row)
            line.set_data(pts[:, 0], pts[:, 1])
        pins = xy[m.geometry.pins]
        self.pins.set_data(pins[:, 0], pins[:, 1])
        rows = self._trace_rows[self._trace_rows <= row]
        for k, trace, dot, label in self.traces:
            if trace is not None:
                path = m.xy[np.append(rows, row), k]
                trace.set_data(path[:, 0], path[:, 1])
            dot.set_data([xy[k, 0]], [xy[k, 1]])
            label.xy = (float(xy[k, 0]), float(xy[k, 1]))
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
