"""The interactive page: one self-contained HTML file (inline CSS and JavaScript, no
network needed to open it) showing a sweep: the mechanism drawn to scale, a slider over
the sweep's steps (time and the drivers' inputs), play and pause, the paths of points,
live values of the chosen outputs, plots linked to the slider, and the events (limits,
bifurcations, locks, branch jumps, the closest approach to a singular configuration)
marked on the timeline. ``Results.to_html`` and ``linkwork view`` write it. A
simulation's page (``Simulation.to_html``, ``linkwork simulate --page``) adds its energy
balance, constraint drift and rates as plots and live values (``charts`` in its data).

The drawing is the SVG of `linkwork.view.export` at the first frame; every position at every
frame is computed here in Python from the sweep (`linkwork.view.drawing.Motion`, world
coordinates; mesh points and belts' strands too, ``Motion.marks``) and embedded as
JSON; the page's script only moves the SVG's elements to
the positions of the frame the slider shows. Numbers are embedded in shortest round-trip
form, so the page's positions are the sweep's to the last bit.

>>> import numpy as np
>>> from linkwork import examples
>>> res = examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 101))
>>> html = res.to_html()
>>> html.startswith("<!DOCTYPE html>") and "http" not in html.split("<svg", 1)[0]
True
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from .. import _args
from ..errors import InputError
from ..model.events import KINDS
from .drawing import Geometry, Motion
from .export import _output_path, _path_names, path_points, svg_text
from .series import _numbers, default_outputs, inputs, output, simulation_charts, unknown_outputs
from .targets import Deviation, deviation

if TYPE_CHECKING:
    from linkwork import Results, Simulation

__all__ = ["page", "inputs", "MAX_FRAMES"]

#: frames embedded by default (the page's slider has this many positions at most)
MAX_FRAMES = 1000


def _outputs(results: Results, names: Sequence[str] | None, rows: np.ndarray) -> list[dict[str, Any]]:
    if names is None:
        names = default_outputs(results)
    else:
        names = _args.each(names, "outputs", lambda v, n: _args.of_type(v, n, str, "an output's name"))
        problem = unknown_outputs(results.model, names)
        if problem:
            raise InputError(problem)
    out = []
    for name in names:
        o = output(results, name)
        out.append(
            {
                "name": o.name,
                "unit": o.unit,
                "value": _numbers(o.value[rows]),
                "rate": None if o.rate is None else _numbers(o.rate[rows]),
                "acceleration": None if o.acceleration is None else _numbers(o.acceleration[rows]),
            }
        )
    return out


def page(
    results: Results,
    path: str | os.PathLike[str] | None = None,
    outputs: Sequence[str] | None = None,
    paths: Sequence[str] | None = None,
    frames: int = MAX_FRAMES,
    title: str | None = None,
    targets: Any = None,
) -> str:
    """The interactive page of a sweep (see the module's docstring): ``outputs`` plotted
    and shown live (names as for ``linkwork plot``; default: every turning body's angle,
    every slider's travel), ``paths`` drawn (named points or joints; default: every named
    point, or the pins off the ground), ``frames`` steps spread evenly over the sweep
    (first and last included; every step if the sweep has fewer). ``targets`` (points
    n x 2, a `linkwork.view.targets.Targets` or a synthesized design): marked in the drawing as
    in `linkwork.view.export.svg`, listed in a table with the path's distance from each (and
    the traced point's at its precision position), and in the page's data as
    ``targets``. Returns the HTML and writes it to ``path`` if given."""
    _args.sweep(results, "results")
    out = _output_path(path)
    frames = _args.integer(frames, "frames", 2)
    if results.n_steps == 0:
        raise InputError("nothing to show: the results have no steps")
    if title is not None:
        _args.of_type(title, "title", str, "a string")
    model = results.model
    geometry = Geometry.from_model(model)
    motion = Motion(geometry, results)
    rows = motion.frames(frames)
    names = _path_names(model, paths)
    unit = str(model.units.get("length", "m"))
    dev = None if targets is None else deviation(results, targets)
    drawing = svg_text(motion, 0, path_points(motion, names, results.n_steps), model.name, unit, dev)
    drawing = drawing.split("?>", 1)[1].strip()  # no XML declaration inside HTML
    sliders = [
        {
            "guide": _numbers(motion.guides[k][rows].reshape(len(rows), -1)),
            "block": _numbers(np.array([motion.block_polygon(k, int(r)).ravel() for r in rows])),
            "hatch": _numbers(np.array([motion.hatch_polygon(k, int(r)).ravel() for r in rows])),
        }
        for k in range(len(geometry.sliders))
    ]
    curves = [{"body": c.body, "local": _numbers(c.local)} for c in motion.curves]
    marks = [_numbers(m.xy[rows].reshape(len(rows), -1)) for m in motion.marks]
    poses = _numbers(results.q[rows][:, : 3 * model.n_bodies]) if curves else []
    t = results.times
    events = [
        {
            "kind": e.kind,
            "time": e.time,
            "step": e.step,
            "message": str(e),
            "frame": _nearest(t[rows], e.time),
        }
        for e in results.events
    ]
    worst = int(np.argmin(results.pivot_ratio))
    events.append(
        {
            "kind": "closest",
            "time": float(t[worst]),
            "step": worst,
            "message": f"closest approach to a singular configuration: pivot ratio "
            f"{results.pivot_ratio[worst]:.3g} at t = {t[worst]:.10g}",
            "frame": _nearest(t[rows], float(t[worst])),
        }
    )
    data = {
        "name": model.name,
        "unit": unit,
        "times": _numbers(t[rows]),
        "steps": rows.tolist(),
        "xy": _numbers(motion.xy[rows].reshape(len(rows), -1)),
        "sliders": sliders,
        "curves": curves,
        "poses": poses,
        "marks": marks,
        "outputs": _outputs(results, outputs, rows),
        "inputs": inputs(results, geometry, rows),
        "pivot_ratio": _numbers(results.pivot_ratio[rows]),
        "events": events,
        "kinds": {
            **KINDS,
            "closest": "the smallest pivot ratio of Phi_q over the sweep (near 0: near singular)",
        },
        "n_steps": results.n_steps,
        "targets": [] if dev is None else dev.to_json(),
        "charts": _charts(results, rows),
    }
    text = json.dumps(data, allow_nan=False, separators=(",", ":")).replace("</", "<\\/")
    heading = title or f"{model.name}"
    span = f"{results.n_steps} steps, t = {t[0]:.6g} .. {t[-1]:.6g} s, lengths in {unit}"
    if results.simulated:
        sim = cast("Simulation", results)
        span = (
            f"simulation ({sim.method}, {sim.n_steps_taken} integration steps): "
            f"{results.n_steps} rows, t = {t[0]:.6g} .. {t[-1]:.6g} s, lengths in {unit}"
        )
    html = (
        _TEMPLATE.replace("__TITLE__", _escape(heading))
        .replace("__SPAN__", _escape(span))
        .replace("__STYLE__", _STYLE)
        .replace("__SCRIPT__", _SCRIPT)
        .replace("__TARGETS__", "" if dev is None else _targets_table(dev))
        .replace("__SVG__", drawing)
        .replace("__DATA__", text)
    )
    if out is not None:
        with open(out, "w", encoding="utf-8") as f:
            f.write(html)
    return html


def _charts(results: Results, rows: np.ndarray) -> list[dict[str, Any]]:
    """A simulation's own plots (`linkwork.view.series.simulation_charts`) at the frames'
    rows; none for a sweep."""
    if not results.simulated:
        return []
    return [
        {
            "title": c.title,
            "unit": c.unit,
            "lines": [{"name": name, "value": _numbers(v[rows])} for name, v in c.lines.items()],
        }
        for c in simulation_charts(cast("Simulation", results))
    ]


def _targets_table(dev: Deviation) -> str:
    """The targets and their deviations as a table (static: they do not move)."""
    u = _escape(dev.unit)
    at = dev.at_position is not None
    angles = dev.angle_error is not None
    head = f"<th>target</th><th>path's distance [{u}]</th>"
    head += f"<th>at its position [{u}]</th>" if at else ""
    head += "<th>rotation error [rad]</th>" if angles else ""
    rows = []
    for j, item in enumerate(dev.to_json()):
        cells = [_escape(item["name"]), f"{dev.nearest[j]:.3e}"]
        if at:
            cells.append(f"{item['at_position']:.3e}" if item.get("reached") else "not reached")
        if angles:
            cells.append(f"{item['angle_error']:.3e}" if item.get("reached") else "-")
        rows.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    return (
        f'<h2>targets of {_escape(dev.targets.point)}</h2><table id="target-table">'
        f"<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"
    )


def _nearest(times: np.ndarray, t: float) -> int:
    return int(np.argmin(np.abs(times - t))) if math.isfinite(t) else 0


def _escape(text: str) -> str:
    from xml.sax.saxutils import escape

    return escape(text)


_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="linkwork">
<title>__TITLE__</title>
<style>__STYLE__</style>
</head>
<body>
<header><h1>__TITLE__</h1><span class="span">__SPAN__</span></header>
<main>
<section id="drawing" aria-label="the mechanism, drawn to scale">__SVG__
<div id="scale"><div id="scale-bar"></div><span id="scale-text"></span></div></section>
<aside>
<table id="values"><thead><tr><th>output</th><th>value</th><th>rate</th><th>acceleration</th>
</tr></thead><tbody></tbody></table>
__TARGETS__
<h2>events</h2><ul id="events"></ul>
</aside>
</main>
<section id="controls">
<button id="play" type="button" title="play / pause (space)">&#9654; play</button>
<label>speed <select id="speed"><option value="0.1">0.1x</option><option value="0.25">0.25x</option>
<option value="0.5">0.5x</option><option value="1" selected>1x</option><option value="2">2x</option>
</select></label>
<span id="clock"></span>
<div id="track"><input id="lw-slider" type="range" min="0" value="0" step="1"
aria-label="step of the sweep"><div id="timeline"></div></div>
</section>
<section id="plots"></section>
<script id="lw-data" type="application/json">__DATA__</script>
<script>__SCRIPT__</script>
</body>
</html>
"""

_STYLE = """
body { font: 14px/1.4 system-ui, sans-serif; margin: 0 1rem 1rem; color: #222; }
header { display: flex; align-items: baseline; gap: 1rem; }
h1 { font-size: 1.3rem; margin: 0.6rem 0; } h2 { font-size: 1rem; margin: 0.8rem 0 0.3rem; }
.span { color: #666; }
main { display: flex; flex-wrap: wrap; gap: 1rem; align-items: flex-start; }
#drawing { flex: 3 1 30rem; min-width: 0; border: 1px solid #ddd; position: relative; }
#drawing svg { width: 100%; height: auto; max-height: 70vh; display: block; }
#scale { position: absolute; left: 10px; bottom: 8px; font-size: 12px; color: #444; }
#scale-bar { height: 4px; background: #444; margin-bottom: 2px; }
aside { flex: 2 1 30rem; min-width: 0; overflow-x: auto; }
table { border-collapse: collapse; width: 100%; font-variant-numeric: tabular-nums; }
th, td { text-align: right; padding: 2px 4px; border-bottom: 1px solid #eee; white-space: nowrap; }
th:first-child, td:first-child { text-align: left; }
#events { padding-left: 1.2rem; margin: 0; max-height: 12rem; overflow: auto; font-size: 13px; }
#events li { cursor: pointer; } #events li:hover { text-decoration: underline; }
#controls { display: flex; flex-wrap: wrap; align-items: center; gap: 0.8rem; margin: 0.8rem 0; }
#clock { font-variant-numeric: tabular-nums; min-width: 22rem; }
#track { flex-basis: 100%; position: relative; }
#lw-slider { width: 100%; margin: 0; }
#timeline { position: relative; height: 14px; margin: 0 8px; }
.mark { position: absolute; top: 0; width: 3px; height: 14px; margin-left: -1px; cursor: pointer; }
.limit { background: #d62728; } .bifurcation { background: #9467bd; } .lock { background: #ff7f0e; }
.branch_jump { background: #000; } .end_of_travel { background: #8c564b; } .closest { background: #7f7f7f; }
#plots { display: grid; grid-template-columns: repeat(auto-fill, minmax(22rem, 1fr)); gap: 0.6rem; }
.plot { border: 1px solid #ddd; } .plot svg { width: 100%; height: 150px; display: block; cursor: crosshair; }
.plot h3 { font-size: 13px; margin: 2px 6px; font-weight: normal; }
.legend { font-size: 12px; margin: 0 6px 2px; display: flex; flex-wrap: wrap; gap: 0 0.8rem; }
"""

_SCRIPT = r"""
"use strict";
// every position at every frame comes from the sweep, computed in Python (JSON below)
const D = JSON.parse(document.getElementById("lw-data").textContent);
const svg = document.querySelector("#drawing svg");
const slider = document.getElementById("lw-slider");
const n = D.times.length;
slider.max = String(n - 1);

const byAnchor = [...svg.querySelectorAll("[data-anchor]")];
const byAnchors = [...svg.querySelectorAll("[data-anchors]")];
const bySlider = [...svg.querySelectorAll("[data-slider]")];
const byCurve = [...svg.querySelectorAll("[data-curve]")];
const byMark = [...svg.querySelectorAll("[data-mark]")];
const pairs = (a) => a.reduce((s, v, i) => (i % 2 ? s + "," + v : s + (i ? " " : "") + v), "");

function at(f, k) { return [D.xy[f][2 * k], D.xy[f][2 * k + 1]]; }

function fmt(v) {
  if (v === null || v === undefined) return "-";
  const a = Math.abs(v);
  return a !== 0 && (a < 1e-3 || a >= 1e5) ? v.toExponential(4) : v.toPrecision(6);
}

function moveDrawing(f) {
  for (const el of byAnchor) {
    const [x, y] = at(f, +el.dataset.anchor);
    if (el.tagName === "text") {
      el.setAttribute("x", x + +el.dataset.dx);
      el.setAttribute("y", -(y + +el.dataset.dy));
    } else {
      el.setAttribute("cx", x);
      el.setAttribute("cy", y);
    }
  }
  for (const el of byAnchors) {
    const ks = el.dataset.anchors.split(" ").map(Number);
    if (el.tagName === "text") {
      // a body's label, at the middle of its outline (outside the flipped group: -y)
      const ps = ks.map((k) => at(f, k));
      el.setAttribute("x", ps.reduce((s, p) => s + p[0], 0) / ps.length);
      el.setAttribute("y", -ps.reduce((s, p) => s + p[1], 0) / ps.length);
    } else if (el.tagName === "circle") {
      const [x, y] = at(f, ks[0]);
      el.setAttribute("cx", x);
      el.setAttribute("cy", y);
    } else {
      el.setAttribute("points", ks.map((k) => at(f, k).join(",")).join(" "));
    }
  }
  for (const el of bySlider) {
    const s = D.sliders[+el.dataset.slider];
    const cls = el.classList;
    const part = cls.contains("guide") ? s.guide : cls.contains("block") ? s.block : s.hatch;
    el.setAttribute("points", pairs(part[f]));
  }
  for (const el of byCurve) {
    // a slot or cam profile: its points in its body's frame, carried by the body's pose
    const c = D.curves[+el.dataset.curve];
    if (c.body < 0) continue;
    const p = D.poses[f], x = p[3 * c.body], y = p[3 * c.body + 1], th = p[3 * c.body + 2];
    const cs = Math.cos(th), sn = Math.sin(th);
    const world = c.local.map(([u, v]) => (x + cs * u - sn * v) + "," + (y + sn * u + cs * v));
    el.setAttribute("points", world.join(" "));
  }
  for (const el of byMark) {
    // a mesh point or a belt's strand: its world points at this frame (none: not drawn)
    const p = D.marks[+el.dataset.mark][f];
    const ok = p.every((v) => v !== null);
    if (el.tagName === "circle") {
      el.setAttribute("cx", ok ? p[0] : 0);
      el.setAttribute("cy", ok ? p[1] : 0);
      el.style.display = ok ? "" : "none";
    } else {
      el.setAttribute("points", ok ? pairs(p) : "");
    }
  }
}

// live values
const tbody = document.querySelector("#values tbody");
const rows = [];
function addRow(name, cells) {
  const tr = document.createElement("tr");
  tr.innerHTML = "<td></td><td></td><td></td><td></td>";
  tr.children[0].textContent = name;
  tbody.appendChild(tr);
  rows.push([tr, cells]);
}
for (const d of D.inputs) {
  addRow("input " + d.name, (f) => d.angle
    ? [fmt(d.value[f]) + " rad (" + fmt(d.value[f] * 180 / Math.PI) + " deg)", "", ""]
    : [fmt(d.value[f]) + " " + d.unit, "", ""]);
}
for (const o of D.outputs) {
  addRow(o.name, (f) => [fmt(o.value[f]) + " " + o.unit,
    o.rate ? fmt(o.rate[f]) + " " + o.unit + "/s" : "-",
    o.acceleration ? fmt(o.acceleration[f]) + " " + o.unit + "/s^2" : "-"]);
}
addRow("pivot ratio", (f) => [fmt(D.pivot_ratio[f]), "", ""]);
for (const c of D.charts) {
  if (c.title === "rates") continue;  // the outputs' rows show them
  for (const l of c.lines) addRow(l.name, (f) => [fmt(l.value[f]) + (c.unit ? " " + c.unit : ""), "", ""]);
}

// plots of the outputs over time, a cursor at the slider's time
const T0 = D.times[0], T1 = D.times[n - 1], span = T1 - T0 || 1;
const W = 400, H = 150, L = 46, R = 6, TOP = 8, B = 20;
const cursors = [];
const NS = "http://www.w3.org/2000/svg";
function el(tag, attrs) {
  const e = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  return e;
}
const X = (t) => L + (W - L - R) * (t - T0) / span;
const KIND_COLOURS = { limit: "#d62728", bifurcation: "#9467bd", lock: "#ff7f0e", branch_jump: "#000000",
  end_of_travel: "#8c564b", closest: "#7f7f7f" };
// one plot: lines over time (a legend when more than one), events dashed, a cursor
const COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf"];
function addPlot(title, lines) {
  const vals = lines.flatMap((l) => l.value.filter((v) => v !== null));
  let lo = Math.min(...vals), hi = Math.max(...vals);
  if (!vals.length) { lo = 0; hi = 1; }
  if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) { lo -= 1; hi += 1; }
  const Y = (v) => TOP + (H - TOP - B) * (hi - v) / (hi - lo);
  const box = document.createElement("div");
  box.className = "plot";
  box.innerHTML = "<h3></h3>";
  box.firstChild.textContent = title;
  const s = el("svg", { viewBox: `0 0 ${W} ${H}`, preserveAspectRatio: "none" });
  const frame = { x: L, y: TOP, width: W - L - R, height: H - TOP - B, fill: "none", stroke: "#ccc" };
  s.appendChild(el("rect", frame));
  for (const e of D.events) {
    s.appendChild(el("line", { x1: X(e.time), x2: X(e.time), y1: TOP, y2: H - B, stroke: KIND_COLOURS[e.kind],
      "stroke-dasharray": "3 3" }));
  }
  lines.forEach((l, k) => {
    const pts = l.value.map((v, f) => (v === null ? "" : X(D.times[f]) + "," + Y(v))).join(" ");
    const line = el("polyline", { points: pts, fill: "none", stroke: COLOURS[k % COLOURS.length],
      "stroke-width": 1.5, "vector-effect": "non-scaling-stroke" });
    line.dataset.name = l.name;
    s.appendChild(line);
  });
  for (const [v, y] of [[hi, TOP + 10], [lo, H - B - 2]]) {
    const tx = el("text", { x: 2, y: y, "font-size": 10, fill: "#555" });
    tx.textContent = fmt(v);
    s.appendChild(tx);
  }
  for (const [t, anchor] of [[T0, "start"], [T1, "end"]]) {
    const tx = el("text", { x: X(t), y: H - 6, "font-size": 10, fill: "#555", "text-anchor": anchor });
    tx.textContent = fmt(t);
    s.appendChild(tx);
  }
  const cursor = el("line", { y1: TOP, y2: H - B, stroke: "#d62728", "stroke-width": 1.5 });
  s.appendChild(cursor);
  cursors.push(cursor);
  s.addEventListener("click", (ev) => {
    const r = s.getBoundingClientRect();
    const t = T0 + span * (((ev.clientX - r.left) / r.width) * W - L) / (W - L - R);
    show(nearest(t));
  });
  box.appendChild(s);
  if (lines.length > 1) {
    const legend = document.createElement("div");
    legend.className = "legend";
    lines.forEach((l, k) => {
      const item = document.createElement("span");
      item.style.color = COLOURS[k % COLOURS.length];
      item.textContent = "\u2014 " + l.name;
      legend.appendChild(item);
    });
    box.appendChild(legend);
  }
  document.getElementById("plots").appendChild(box);
}
for (const o of D.outputs) addPlot(o.name + " [" + o.unit + "] over t [s]", [o]);
// a simulation's own: energy, the balance's error, the drift, the rates
for (const c of D.charts) addPlot(c.title + (c.unit ? " [" + c.unit + "]" : "") + " over t [s]", c.lines);

function nearest(t) {
  let best = 0;
  for (let f = 1; f < n; f++) if (Math.abs(D.times[f] - t) < Math.abs(D.times[best] - t)) best = f;
  return best;
}

// events on the timeline and in the list
const timeline = document.getElementById("timeline");
const list = document.getElementById("events");
for (const e of D.events) {
  const m = document.createElement("div");
  m.className = "mark " + e.kind;
  m.style.left = (100 * (e.time - T0) / span) + "%";
  m.title = e.message;
  m.addEventListener("click", () => show(e.frame));
  timeline.appendChild(m);
  const li = document.createElement("li");
  li.textContent = e.message;
  li.title = D.kinds[e.kind] || "";
  li.addEventListener("click", () => show(e.frame));
  list.appendChild(li);
}

// a scale bar: a round length about a fifth of the drawing's width
function scaleBar() {
  const vb = svg.viewBox.baseVal, px = svg.getBoundingClientRect().width / vb.width;
  const target = vb.width / 5, p = Math.pow(10, Math.floor(Math.log10(target)));
  const len = [5, 2, 1].map((k) => k * p).find((v) => v <= target) || p;
  document.getElementById("scale-bar").style.width = (len * px) + "px";
  document.getElementById("scale-text").textContent = +len.toPrecision(3) + " " + D.unit;
}

const clock = document.getElementById("clock");
function show(f) {
  f = Math.max(0, Math.min(n - 1, Math.round(f)));
  window.linkwork.frame = f;
  slider.value = String(f);
  moveDrawing(f);
  for (const [tr, cells] of rows) cells(f).forEach((v, i) => { tr.children[i + 1].textContent = v; });
  for (const c of cursors) { c.setAttribute("x1", X(D.times[f])); c.setAttribute("x2", X(D.times[f])); }
  clock.textContent = "t = " + fmt(D.times[f]) + " s   (step " + D.steps[f] + " of " + D.n_steps + ")";
}

// play and pause: the sweep's time runs at the chosen speed, looping at the end
const play = document.getElementById("play");
let playing = false, last = null, tNow = T0;
function tick(ms) {
  if (!playing) return;
  if (last !== null) {
    tNow += ((ms - last) / 1000) * +document.getElementById("speed").value;
    if (tNow > T1) tNow = T0 + ((tNow - T0) % span);
    let f = window.linkwork.frame;
    while (f < n - 1 && D.times[f + 1] <= tNow) f++;
    if (D.times[f] > tNow) f = 0;
    show(f);
  }
  last = ms;
  requestAnimationFrame(tick);
}
function toggle() {
  playing = !playing;
  play.innerHTML = playing ? "&#10073;&#10073; pause" : "&#9654; play";
  last = null;
  tNow = D.times[window.linkwork.frame];
  if (playing) requestAnimationFrame(tick);
}
play.addEventListener("click", toggle);
document.addEventListener("keydown", (ev) => {
  if (ev.code === "Space" && ev.target.tagName !== "BUTTON") { ev.preventDefault(); toggle(); }
});
slider.addEventListener("input", () => show(+slider.value));
window.addEventListener("resize", scaleBar);

window.linkwork = { data: D, frame: 0, show: show, playing: () => playing, toggle: toggle };
scaleBar();
show(0);
"""
