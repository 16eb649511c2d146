"""Exports: the mechanism at any time of a sweep, with the paths of its points (coupler
curves), as SVG and as DXF, and the results as a pandas DataFrame.

Drawings are in world coordinates, in the model's length unit, y up: an SVG's numbers
are the model's (its root ``viewBox`` is in model units and its ``width`` and
``height`` in millimetres, so it prints and imports 1:1), a DXF's too (``$INSUNITS`` says
mm or m). What is drawn is what `linkwork.view.drawing` draws with matplotlib: each body as
the polygon through its joints and points, pins, ground pivots, sliders on their guides,
slots and cam profiles, pitch circles of gears, pulleys and pinions with their mesh
points, belts, racks, distance joints' bars, actuators, springs, named points; each
element carries the name of what it draws (``data-name`` in SVG, the ``LINKWORK`` XDATA in DXF).

>>> import numpy as np
>>> from linkwork import examples
>>> res = examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 11))
>>> text = res.to_svg(t=0.25)        # off the grid: solved there, on the sweep's branch
>>> text.startswith("<?xml") and 'data-name="P"' in text
True
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import escape, quoteattr

import numpy as np

from .. import _args
from ..errors import InputError
from .drawing import SPRING_COLOUR, Geometry, Motion, colour, ground_symbols
from .series import default_paths, unknown_paths
from .targets import TARGET_COLOUR, Deviation, deviation, target_marks

if TYPE_CHECKING:
    from linkwork import Model, Results

__all__ = ["configuration", "path_points", "svg", "svg_text", "dxf", "dataframe", "MM_PER"]

#: millimetres per length unit, for an SVG's physical size
MM_PER = {"mm": 1.0, "m": 1000.0}


class _Steps:
    """The part of a `Results` a `Motion` reads: times, q and the model."""

    def __init__(self, model: Model, times: np.ndarray, q: np.ndarray) -> None:
        self.model, self.times, self.q = model, times, q

    @property
    def n_steps(self) -> int:
        return int(self.q.shape[0])


def configuration(results: Results, t: float | None = None) -> tuple[Motion, int]:
    """The sweep's motion and the row drawing time ``t`` (default: the first step). A time
    between steps is solved there (Newton from the nearest step, so on the sweep's
    branch) and added as the last row; a time outside the sweep is an `InputError`, and so
    is a time between a simulation's rows (its motion there is not known)."""
    _args.sweep(results, "results")
    if results.n_steps == 0:
        raise InputError("nothing to draw: the results have no steps")
    geometry = Geometry.from_model(results.model)
    if t is None:
        return Motion(geometry, results), 0
    t = _args.number(t, "t")
    times = results.times
    lo, hi = float(times.min()), float(times.max())
    if not lo <= t <= hi:
        raise InputError(f"t = {t:g} is outside the sweep (t = {lo:g} .. {hi:g})")
    k = int(np.argmin(np.abs(times - t)))
    if times[k] == t:
        return Motion(geometry, results), k
    if results.simulated:
        raise InputError(
            f"t = {t:g} is not a time of the simulation (nearest: t = {times[k]:.10g}, row {k}); "
            "simulate with that time among the times to draw it there"
        )
    state = results.model.solve(t, q_guess=results.q[k])
    steps = _Steps(results.model, np.append(times, t), np.vstack([results.q, state.q]))
    return Motion(geometry, steps), results.n_steps  # type: ignore[arg-type]


def _path_names(model: Model, paths: Sequence[str] | None) -> list[str]:
    if paths is None:
        return default_paths(model)
    names = _args.each(paths, "paths", lambda v, n: _args.of_type(v, n, str, "a point's or joint's name"))
    problem = unknown_paths(model, names)
    if problem:
        raise InputError(problem)
    return names


def path_points(
    motion: Motion, names: Sequence[str], n_steps: int, max_points: int = 5000
) -> dict[str, np.ndarray]:
    """The paths of the named points or joints over the first ``n_steps`` rows of the
    motion, each (m, 2) through at most ``max_points`` steps spread evenly (first and last
    included)."""
    rows = np.unique(np.linspace(0, n_steps - 1, max(2, min(n_steps, max_points))).round().astype(np.intp))
    return {name: motion.xy[rows, motion.geometry.traceable[name]] for name in names}


def _n(v: Any) -> str:
    """A number written so that it reads back exactly (shortest round trip)."""
    return repr(float(v))


def _points(a: np.ndarray) -> str:
    return " ".join(f"{_n(x)},{_n(y)}" for x, y in np.asarray(a).reshape(-1, 2))


def _attrs(**kw: Any) -> str:
    return " ".join(f"{k.rstrip('_').replace('_', '-')}={quoteattr(str(v))}" for k, v in kw.items())


def svg_text(
    motion: Motion,
    row: int,
    paths: dict[str, np.ndarray],
    title: str,
    unit: str,
    targets: Deviation | None = None,
) -> str:
    """The SVG of the mechanism at step ``row`` of ``motion`` with ``paths`` (and the
    ``targets`` of a design with their deviations: `linkwork.view.targets`). Every element
    that moves names the anchors it is drawn through (``data-anchor``, ``data-anchors``),
    its slider (``data-slider``), curve (``data-curve``: slots, cam profiles, pitch
    circles and their marks, racks) or mark (``data-mark``: mesh points, belts'
    strands, see `Motion.marks`): the interactive page moves them by these."""
    g = motion.geometry
    xy = motion.xy[row]
    s = motion.size
    lw, r_pin, r_point, h = 0.005 * s, 0.011 * s, 0.007 * s, 0.035 * s
    listing = None if targets is None else target_listing(motion, targets)
    (x0, x1), (y0, y1) = motion.limits if listing is None else listing.limits
    per_mm = MM_PER.get(unit, 1.0)
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{(x1 - x0) * per_mm:.6g}mm" '
        f'height="{(y1 - y0) * per_mm:.6g}mm" viewBox="{_n(x0)} {_n(-y1)} {_n(x1 - x0)} {_n(y1 - y0)}" '
        f'data-unit="{escape(unit)}" data-time="{_n(motion.times[row])}">',
        f"<title>{escape(title)}</title>",
        f'<desc>linkwork drawing: world coordinates in {escape(unit)}, y up (the group "world" '
        "flips the y axis)</desc>",
        f'<defs><pattern id="lw-hatch" patternUnits="userSpaceOnUse" width="{_n(0.4 * h)}" '
        f'height="{_n(0.4 * h)}" patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" '
        f'y2="{_n(0.4 * h)}" stroke="#666666" stroke-width="{_n(0.4 * lw)}"/></pattern></defs>',
        f'<g id="world" transform="scale(1,-1)" stroke-linejoin="round" stroke-linecap="round" '
        f'stroke-width="{_n(lw)}">',
    ]
    out.append('<g id="paths" fill="none">')
    for i, (name, pts) in enumerate(paths.items()):
        a = _attrs(class_="path", data_name=name, stroke=colour(len(g.body_names) + i), points=_points(pts))
        out.append(f'<polyline {a} stroke-width="{_n(0.6 * lw)}"/>')
    out.append("</g>")
    out.append('<g id="ground">')
    for k in g.ground_pins:
        (tri,), (base,), (line,) = ground_symbols(xy[k][None, :], h)
        name = g.anchors[k].name
        out.append(f'<polygon {_attrs(class_="ground-base", data_name=name, points=_points(base))} '
                   'fill="url(#lw-hatch)" stroke="none"/>')  # fmt: skip
        out.append(f'<polygon {_attrs(class_="ground", data_name=name, points=_points(tri))} '
                   'fill="#d9d9d9" stroke="#333333"/>')  # fmt: skip
        out.append(f'<polyline {_attrs(class_="ground-line", data_name=name, points=_points(line))} '
                   'fill="none" stroke="#333333"/>')  # fmt: skip
    out.append("</g>")
    out.append('<g id="guides" fill="none" stroke="#595959">')
    for k, slider in enumerate(g.sliders):
        ends = motion.guides[k][row]
        out.append(f'<polyline {_attrs(class_="guide", data_name=slider.joint, data_slider=k)} '
                   f'points="{_points(ends)}"/>')  # fmt: skip
        if g.body_of(slider.guide) < 0:
            out.append(
                f"<polygon {_attrs(class_='hatch', data_name=slider.joint, data_slider=k)} "
                f'points="{_points(motion.hatch_polygon(k, row))}" fill="url(#lw-hatch)" stroke="none"/>'
            )
    out.append("</g>")
    out.append('<g id="bodies">')
    for i, name in enumerate(g.body_names):
        outline = g.outlines[name]
        c = colour(i)
        a = _attrs(class_="body", data_name=name, data_anchors=" ".join(map(str, outline)))
        if len(outline) == 1:
            (x, y) = xy[outline[0]]
            out.append(f'<circle {a} cx="{_n(x)}" cy="{_n(y)}" r="{_n(1.3 * r_pin)}" fill="{c}"/>')
        else:
            tag = "polygon" if len(outline) > 2 else "polyline"
            out.append(
                f'<{tag} {a} points="{_points(xy[outline])}" fill="{c}" fill-opacity="0.35" stroke="{c}"/>'
            )
    out.append("</g>")
    out.append('<g id="curves" fill="none">')
    for j, curve in enumerate(motion.curves):
        a = _attrs(
            class_="curve" if curve.kind == "curve" else f"curve {curve.kind}",
            data_name=curve.joint,
            data_curve=j,
            stroke=colour(curve.body),
        )
        dash = f' stroke-dasharray="{_n(4 * lw)} {_n(1.5 * lw)} {_n(lw)} {_n(1.5 * lw)}"'
        width = f' stroke-width="{_n(0.5 * lw)}"' if curve.kind in ("pitch", "teeth") else ""
        out.append(
            f'<polyline {a} points="{_points(motion.curve(curve, row))}"'
            f"{dash if curve.kind == 'pitch' else ''}{width}/>"
        )
    out.append("</g>")
    out.append('<g id="rods" stroke="#404040">')
    for a_, b_ in g.rods:
        a = _attrs(class_="rod", data_name=g.anchors[a_].name, data_anchors=f"{a_} {b_}")
        out.append(f'<polyline {a} points="{_points(xy[[a_, b_]])}" stroke-width="{_n(0.8 * lw)}"/>')
    out.append("</g>")
    out.append('<g id="marks" stroke="#333333" fill="#000000">')
    for j, mark in enumerate(motion.marks):
        pts = mark.xy[row]
        a = _attrs(class_=mark.kind, data_name=mark.joint, data_mark=j)
        if mark.kind == "mesh":
            (x, y) = pts[0] if np.all(np.isfinite(pts)) else (0.0, 0.0)
            out.append(f'<circle {a} cx="{_n(x)}" cy="{_n(y)}" r="{_n(0.6 * r_point)}" stroke="none"/>')
        else:
            text = _points(pts) if np.all(np.isfinite(pts)) else ""
            out.append(f'<polyline {a} points="{text}" fill="none" stroke-width="{_n(0.6 * lw)}"/>')
    out.append("</g>")
    out.append('<g id="actuators" stroke="#333333">')
    for a_, b_ in g.actuators:
        a = _attrs(class_="actuator", data_name=g.anchors[a_].name, data_anchors=f"{a_} {b_}")
        out.append(
            f'<polyline {a} points="{_points(xy[[a_, b_]])}" stroke-dasharray="{_n(3 * lw)} {_n(2 * lw)}"/>'
        )
    out.append("</g>")
    out.append(f'<g id="springs" stroke="{SPRING_COLOUR}">')
    for a_, b_ in g.springs:
        a = _attrs(class_="spring", data_name=g.anchors[a_].name, data_anchors=f"{a_} {b_}")
        out.append(
            f'<polyline {a} points="{_points(xy[[a_, b_]])}" stroke-width="{_n(0.6 * lw)}" '
            f'stroke-dasharray="{_n(lw)} {_n(lw)}"/>'
        )
    out.append("</g>")
    out.append('<g id="blocks" fill="#cccccc" stroke="#333333">')
    for k, slider in enumerate(g.sliders):
        a = _attrs(class_="block", data_name=slider.joint, data_slider=k)
        out.append(f'<polygon {a} points="{_points(motion.block_polygon(k, row))}"/>')
    out.append("</g>")
    out.append('<g id="pins" fill="#ffffff" stroke="#000000">')
    for k in g.pins:
        a = _attrs(class_="pin", data_name=g.anchors[k].name, data_anchor=k)
        out.append(f'<circle {a} cx="{_n(xy[k, 0])}" cy="{_n(xy[k, 1])}" r="{_n(r_pin)}"/>')
    out.append("</g>")
    out.append('<g id="points" stroke="none">')
    for n, k in enumerate(g.points):
        a = _attrs(
            class_="point", data_name=g.anchors[k].name, data_anchor=k, fill=colour(len(g.body_names) + n)
        )
        out.append(f'<circle {a} cx="{_n(xy[k, 0])}" cy="{_n(xy[k, 1])}" r="{_n(r_point)}"/>')
    out.append("</g>")
    if targets is not None:
        out += _svg_targets(targets, s, lw)
    out.append("</g>")
    # labels outside the flipped group, so that the text reads upright: y is -y there. The
    # same labels as the figure's (MechanismArtists with labels): each body's name at the
    # middle of its outline, each joint's and named point's name beside its point
    out.append(f'<g id="labels" font-family="sans-serif" font-size="{_n(0.03 * s)}" fill="#333333">')
    for i, name in enumerate(g.body_names):
        outline = g.outlines[name]
        x, y = xy[outline].mean(axis=0)
        a = _attrs(class_="label body-label", data_name=name, data_anchors=" ".join(map(str, outline)))
        out.append(
            f'<text {a} x="{_n(x)}" y="{_n(-y)}" text-anchor="middle" dominant-baseline="middle" '
            f'font-weight="bold" fill="{colour(i)}">{escape(name)}</text>'
        )
    off = 1.5 * r_pin
    named = {g.anchors[k].name for k in g.points}
    joints = [k for name, k in g.traceable.items() if name not in named and g.anchors[k].kind == "joint"]
    for k in g.points + joints:
        x, y = xy[k]
        kind = "point-label" if k in g.points else "joint-label"
        a = _attrs(
            class_=f"label {kind}",
            data_name=g.anchors[k].name,
            data_anchor=k,
            data_dx=_n(off),
            data_dy=_n(off),
        )
        out.append(f'<text {a} x="{_n(x + off)}" y="{_n(-(y + off))}">{escape(g.anchors[k].name)}</text>')
    if targets is not None and listing is not None:
        # each target's number beside it, its distances listed in a column right of the drawing
        for j, (x, y) in enumerate(targets.targets.points):
            a = _attrs(class_="label target-number", data_name=targets.targets.name(j), data_target=j)
            out.append(
                f'<text {a} x="{_n(x + off)}" y="{_n(-(y - off))}" dominant-baseline="hanging" '
                f'fill="{TARGET_COLOUR}">{j + 1}</text>'
            )
        for k, (text, (x, y)) in enumerate(zip(listing.lines, listing.at)):
            a = (
                _attrs(class_="label target-heading")
                if k == 0
                else _attrs(
                    class_="label target-label", data_name=targets.targets.name(k - 1), data_target=k - 1
                )
            )
            out.append(f'<text {a} x="{_n(x)}" y="{_n(-y)}" fill="{TARGET_COLOUR}">{escape(text)}</text>')
    out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


def target_limits(
    motion: Motion, targets: Deviation | None
) -> tuple[tuple[float, float], tuple[float, float]]:
    """The motion's drawing limits, widened to show every target and its tick."""
    (x0, x1), (y0, y1) = motion.limits
    if targets is None:
        return (x0, x1), (y0, y1)
    m = 0.1 * motion.size
    p = targets.targets.points
    return (
        (min(x0, float(p[:, 0].min()) - m), max(x1, float(p[:, 0].max()) + m)),
        (min(y0, float(p[:, 1].min()) - m), max(y1, float(p[:, 1].max()) + m)),
    )


@dataclass(frozen=True)
class TargetListing:
    """Where the pictures list the targets' distances: ``lines`` (a heading, then
    `Deviation.label` of each target), each at its point ``at`` (world, the text's
    baseline start) in a column right of the drawing, and the drawing's ``limits``
    widened to hold the targets, their ticks and the column."""

    lines: list[str]
    at: list[tuple[float, float]]
    limits: tuple[tuple[float, float], tuple[float, float]]
    height: float


def target_listing(motion: Motion, targets: Deviation) -> TargetListing:
    """The column listing the targets' distances (`TargetListing`), font height 3 % of
    the motion's size like the other labels."""
    (x0, x1), (y0, y1) = target_limits(motion, targets)
    height = 0.03 * motion.size
    step = 1.5 * height
    lines = [targets.heading_line()] + [targets.label(j) for j in range(len(targets.targets))]
    width = 0.56 * height * max(len(t) for t in lines) + 2.0 * height
    y0 = min(y0, y1 - (len(lines) + 1) * step)
    at = [(x1 + height, y1 - (k + 1) * step) for k in range(len(lines))]
    return TargetListing(lines, at, ((x0, x1 + width), (y0, y1)), height)


def _svg_targets(targets: Deviation, size: float, lw: float) -> list[str]:
    """The targets' group: each a ring and a cross (``class="target"``, with its
    deviations as ``data-nearest`` and ``data-at-position``), its pose's tick
    (``target-pose``) and the segment to the path's nearest point (``target-miss``)."""
    out = [f'<g id="targets" fill="none" stroke="{TARGET_COLOUR}">']
    for j, mark in enumerate(target_marks(targets, size)):
        (x, y), r = mark["ring"]
        extra: dict[str, Any] = {"data_nearest": _n(targets.nearest[j])}
        if targets.at_position is not None:
            extra["data_at_position"] = _n(targets.at_position[j])
        if targets.targets.angles is not None:
            extra["data_angle"] = _n(targets.targets.angles[j])
        a = _attrs(class_="target", data_name=mark["name"], data_target=j, **extra)
        out.append(f'<circle {a} cx="{_n(x)}" cy="{_n(y)}" r="{_n(r)}" stroke-width="{_n(0.6 * lw)}"/>')
        for seg in mark["cross"]:
            a = _attrs(class_="target-cross", data_name=mark["name"], data_target=j)
            out.append(f'<polyline {a} points="{_points(seg)}" stroke-width="{_n(0.4 * lw)}"/>')
        if mark["tick"] is not None:
            a = _attrs(class_="target-pose", data_name=mark["name"], data_target=j)
            out.append(f'<polyline {a} points="{_points(mark["tick"])}" stroke-width="{_n(0.8 * lw)}"/>')
        a = _attrs(class_="target-miss", data_name=mark["name"], data_target=j)
        out.append(
            f'<polyline {a} points="{_points(mark["miss"])}" stroke-width="{_n(0.4 * lw)}" '
            f'stroke-dasharray="{_n(lw)} {_n(lw)}"/>'
        )
    out.append("</g>")
    return out


def _output_path(path: Any, name: str = "path") -> str | None:
    if path is None:
        return None
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"{name} must be a file name, not {path!r}")
    return os.fspath(path)


def svg(
    results: Results,
    path: str | os.PathLike[str] | None = None,
    t: float | None = None,
    paths: Sequence[str] | None = None,
    max_points: int = 5000,
    targets: Any = None,
) -> str:
    """The mechanism at time ``t`` of the sweep (default: its first step; a time between
    steps is solved there) and the paths over the whole sweep of ``paths`` (named points
    or joints; default: every named point, or the pins off the ground), each through at
    most ``max_points`` steps; ``targets`` (points n x 2, a `linkwork.view.targets.Targets` or a
    synthesized design): each marked (``class="target"``), with its pose's tick and the
    distance of the path from it, labelled. Returns the SVG text and writes it to ``path``
    if given."""
    out = _output_path(path)
    max_points = _args.integer(max_points, "max_points", 2)
    dev = None if targets is None else deviation(results, targets)
    motion, row = configuration(results, t)
    names = _path_names(results.model, paths)
    title = f"{results.model.name} at t = {motion.times[row]:.6g} s"
    drawn = path_points(motion, names, results.n_steps, max_points)
    text = svg_text(motion, row, drawn, title, _length_unit(results), dev)
    if out is not None:
        with open(out, "w", encoding="utf-8") as f:
            f.write(text)
    return text


def _length_unit(results: Results) -> str:
    return str(results.model.units.get("length", "m"))


#: DXF layers: name -> AutoCAD colour index
LAYERS = {
    "BODIES": 7,
    "PINS": 7,
    "GROUND": 8,
    "GUIDES": 8,
    "SLIDERS": 7,
    "CURVES": 5,
    "PITCH": 5,
    "RODS": 7,
    "MESHES": 1,
    "BELTS": 8,
    "ACTUATORS": 7,
    "SPRINGS": 7,
    "POINTS": 1,
    "PATHS": 1,
    "LABELS": 7,
    "TARGETS": 1,
}


def dxf(
    results: Results,
    path: str | os.PathLike[str],
    t: float | None = None,
    paths: Sequence[str] | None = None,
    max_points: int = 5000,
    targets: Any = None,
) -> None:
    """Writes the mechanism at time ``t`` and the paths of ``paths`` over the sweep (and
    ``targets``, as for `svg`) as a DXF drawing (R2010, needs ezdxf), in the model's length
    unit. Layers: BODIES (closed polylines through each body's joints and points, a line
    for a bar), PINS (circles about the pins), GROUND (pivot symbols), GUIDES and SLIDERS
    (guides and blocks), CURVES (slots, cam profiles, rollers, marks on wheels, racks'
    teeth), PITCH (pitch circles, racks' pitch lines; dash-dot), RODS (distance joints),
    MESHES (mesh points: a POINT entity each), BELTS (belts' strands), ACTUATORS, SPRINGS
    (spring-dampers; dotted), POINTS
    (named points: a POINT entity each), PATHS (the coupler curves, polylines), LABELS and
    TARGETS (each target a POINT, a circle and a cross, its pose's tick, a line to the
    path's nearest point and its number; a column of text right of the drawing lists the
    distances). Each entity's XDATA ``LINKWORK`` holds the name of the body, joint, point
    or target ("P1") it draws."""
    out = _output_path(path)
    if out is None:
        raise InputError("path must be a file name, not None")
    max_points = _args.integer(max_points, "max_points", 2)
    dev = None if targets is None else deviation(results, targets)
    ezdxf = _args.optional_module("ezdxf", "writing DXF", "export")
    from ezdxf import colors, units

    motion, row = configuration(results, t)
    names = _path_names(results.model, paths)
    g, xy, s = motion.geometry, motion.xy[row], motion.size
    unit = _length_unit(results)
    doc = ezdxf.new("R2010", setup=True)
    doc.units = units.MM if unit == "mm" else units.M
    doc.header["$MEASUREMENT"] = 1  # metric
    doc.appids.add("LINKWORK")
    for layer, aci in LAYERS.items():
        doc.layers.add(layer, color=aci, linetype="DASHDOT" if layer == "PITCH" else "Continuous")
    msp = doc.modelspace()

    def named(entity: Any, name: str, rgb: str | None = None) -> None:
        entity.set_xdata("LINKWORK", [(1000, name)])
        if rgb is not None:
            entity.rgb = colors.RGB.from_hex(rgb)

    def poly(points: np.ndarray, layer: str, name: str, closed: bool = False, rgb: str | None = None) -> None:
        pts = [(float(x), float(y)) for x, y in np.asarray(points).reshape(-1, 2)]
        named(msp.add_lwpolyline(pts, close=closed, dxfattribs={"layer": layer}), name, rgb)

    r_pin = 0.011 * s
    for i, name in enumerate(g.body_names):
        outline = g.outlines[name]
        if len(outline) == 1:
            x, y = xy[outline[0]]
            named(
                msp.add_circle((float(x), float(y)), 1.3 * r_pin, dxfattribs={"layer": "BODIES"}),
                name,
                colour(i),
            )
        else:
            poly(xy[outline], "BODIES", name, closed=len(outline) > 2, rgb=colour(i))
    for k in g.pins:
        x, y = xy[k]
        named(msp.add_circle((float(x), float(y)), r_pin, dxfattribs={"layer": "PINS"}), g.anchors[k].name)
    if g.ground_pins:
        triangles, bases, lines = ground_symbols(xy[g.ground_pins], 0.035 * s)
        for k, tri, line in zip(g.ground_pins, triangles, lines):
            poly(tri, "GROUND", g.anchors[k].name, closed=True)
            poly(line, "GROUND", g.anchors[k].name)
    for k, slider in enumerate(g.sliders):
        poly(motion.guides[k][row], "GUIDES", slider.joint)
        poly(motion.block_polygon(k, row), "SLIDERS", slider.joint, closed=True)
    for curve in motion.curves:
        layer = "PITCH" if curve.kind == "pitch" else "CURVES"
        poly(motion.curve(curve, row), layer, curve.joint, rgb=colour(curve.body))
    for a, b in g.rods:
        named(msp.add_line(tuple(xy[a]), tuple(xy[b]), dxfattribs={"layer": "RODS"}), g.anchors[a].name)
    for mark in motion.marks:
        pts = mark.xy[row]
        if not np.all(np.isfinite(pts)):
            continue
        if mark.kind == "mesh":
            x, y = pts[0]
            named(msp.add_point((float(x), float(y)), dxfattribs={"layer": "MESHES"}), mark.joint)
        else:
            poly(pts, "BELTS", mark.joint)
    for a, b in g.springs:
        line = msp.add_line(tuple(xy[a]), tuple(xy[b]), dxfattribs={"layer": "SPRINGS", "linetype": "DOT"})
        named(line, g.anchors[a].name)
    for a, b in g.actuators:
        line = msp.add_line(
            tuple(xy[a]), tuple(xy[b]), dxfattribs={"layer": "ACTUATORS", "linetype": "DASHED"}
        )
        named(line, g.anchors[a].name)
    for k in g.points:
        x, y = xy[k]
        named(msp.add_point((float(x), float(y)), dxfattribs={"layer": "POINTS"}), g.anchors[k].name)
    for i, (name, pts) in enumerate(path_points(motion, names, results.n_steps, max_points).items()):
        poly(pts, "PATHS", name, rgb=colour(len(g.body_names) + i))
    for k in g.points + [k for k in g.pins if k not in g.ground_pins]:
        x, y = xy[k]
        text = msp.add_text(g.anchors[k].name, height=0.03 * s, dxfattribs={"layer": "LABELS"})
        text.set_placement((float(x + 1.5 * r_pin), float(y + 1.5 * r_pin)))
        named(text, g.anchors[k].name)
    if dev is not None:
        on = {"layer": "TARGETS"}
        for j, tm in enumerate(target_marks(dev, s)):
            name = tm["name"]
            (x, y), r = tm["ring"]
            named(msp.add_point((x, y), dxfattribs=on), name)
            named(msp.add_circle((x, y), r, dxfattribs=on), name)
            for seg in tm["cross"] + ([tm["tick"]] if tm["tick"] is not None else []):
                named(msp.add_line(tuple(seg[0]), tuple(seg[1]), dxfattribs=on), name)
            if np.all(np.isfinite(tm["miss"])):
                named(msp.add_line(tuple(tm["miss"][0]), tuple(tm["miss"][1]), dxfattribs=on), name)
            text = msp.add_text(str(j + 1), height=0.03 * s, dxfattribs=on)
            text.set_placement((x + 1.5 * r_pin, y - 1.5 * r_pin - 0.03 * s))
            named(text, name)
        listing = target_listing(motion, dev)
        for k, (line, at) in enumerate(zip(listing.lines, listing.at)):
            text = msp.add_text(line, height=listing.height, dxfattribs=on)
            text.set_placement(at)
            named(text, dev.targets.name(k - 1) if k else "targets")
    doc.saveas(out)


def dataframe(results: Results, points: bool = False) -> Any:
    """`Results.table` as a pandas DataFrame, units in ``attrs`` (see `Results.to_dataframe`)."""
    pd = _args.optional_module("pandas", "Results.to_dataframe", "export")
    names, units, data = results.table(points=points)
    df = pd.DataFrame(data, columns=names)
    df["iterations"] = df["iterations"].astype(np.int64)
    df.attrs["units"] = dict(zip(names, units))
    df.attrs["model"] = results.model.name
    return df
