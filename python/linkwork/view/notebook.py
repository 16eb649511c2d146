"""What a notebook shows: a `Mechanism` or `Model` as its drawing (and a model's counts),
`Results` as a summary table with small plots (a `Simulation`'s with its energy balance
and drift), through the standard rich-display methods
(``_repr_png_``, ``_repr_html_``); ``draw`` onto matplotlib axes and ``animate``, an
animation a notebook plays inline (matplotlib's JavaScript animation: no ffmpeg needed).

The drawings are `linkwork.view.drawing`'s (`MechanismArtists`); figures are built without
pyplot's global state, so showing an object never changes the notebook's backend.

>>> import numpy as np
>>> from linkwork import examples
>>> res = examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 21))
>>> "<table" in res._repr_html_()
True
"""

from __future__ import annotations

import base64
import io
import math
import textwrap
from html import escape
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from .. import _args
from ..errors import DependencyError, InputError, LinkworkError
from .drawing import Geometry, MechanismArtists, Motion, setup_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from linkwork import Mechanism, Model, Results, Simulation

__all__ = [
    "draw_results",
    "draw_model",
    "draw_mechanism",
    "Animation",
    "animate",
    "png",
    "model_html",
    "results_html",
]


class _Steps:
    """What `Motion` reads of a `Results`: times, q and the model's length scale."""

    def __init__(self, times: np.ndarray, q: np.ndarray, length_scale: float) -> None:
        self.times, self.q = times, q
        self.model = type("_Scale", (), {"length_scale": length_scale})()

    @property
    def n_steps(self) -> int:
        return int(self.q.shape[0])


def _axes(ax: Any) -> Axes:
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.4, 4.8))
        return ax
    from matplotlib.axes import Axes

    return _args.of_type(ax, "ax", Axes, "matplotlib Axes (or None for a new figure)")


def _figure(width: float, height: float, cols: int = 1) -> tuple[Figure, list[Axes]]:
    """A figure outside pyplot (no backend change, nothing left open)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig, [fig.add_subplot(1, cols, k + 1) for k in range(cols)]


def png(fig: Figure, dpi: int = 90) -> bytes:
    """The figure as PNG bytes."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


def _draw(ax: Axes, motion: Motion, row: int, unit: str, title: str, paths: dict[str, np.ndarray]) -> Axes:
    MechanismArtists(ax, motion, traces=False).update(row)
    for name, xy in paths.items():
        ax.plot(xy[:, 0], xy[:, 1], lw=1.0, alpha=0.8, label=name, zorder=1)
    setup_axes(ax, motion, unit)
    ax.set_title(title, fontsize=10)
    return ax


def draw_results(results: Results, ax: Any = None, t: float | None = None, paths: Any = None) -> Axes:
    """The mechanism at time ``t`` of the sweep (default: its first step) with the paths
    of ``paths`` over the sweep (default: every named point; [] for none)."""
    from .export import _path_names, configuration, path_points

    ax = _axes(ax)
    motion, row = configuration(results, t)
    names = _path_names(results.model, paths)
    unit = str(results.model.units.get("length", "m"))
    title = f"{results.model.name} at t = {motion.times[row]:.6g} s"
    return _draw(ax, motion, row, unit, title, path_points(motion, names, results.n_steps, 2000))


def draw_model(model: Model, ax: Any = None, t: float = 0.0) -> Axes:
    """The model assembled at time ``t`` (on the drawing's branch, as `Model.solve`)."""
    ax = _axes(ax)
    t = _args.number(t, "t")
    state = model.solve(t)
    steps = _Steps(np.array([t]), state.q[None, :], model.length_scale)
    motion = Motion(Geometry.from_model(model), steps)  # type: ignore[arg-type]
    unit = str(model.units.get("length", "m"))
    return _draw(ax, motion, 0, unit, f"{model.name} at t = {t:g} s", {})


def draw_mechanism(mechanism: Mechanism, ax: Any = None, t: float = 0.0) -> Axes:
    """The mechanism assembled at time ``t``; one that cannot be compiled or assembled yet
    (a mechanism still being built) is drawn as described, the title saying why."""
    t = _args.number(t, "t")
    try:
        model = mechanism.compile()
        model.solve(t)
    except LinkworkError as e:
        ax = _axes(ax)
        desc = mechanism.to_dict()
        # pins given only in the bodies' frames have no place in a drawing not assembled
        desc["joints"] = [j for j in desc["joints"] if j.get("type") != "revolute" or "at" in j]
        deg = (desc.get("units") or {}).get("angle") == "deg"
        bodies = [b["name"] for b in desc["bodies"]]
        q = np.array(
            [[b["x"], b["y"], math.radians(b["theta"]) if deg else b["theta"]] for b in desc["bodies"]],
            dtype=np.float64,
        ).reshape(1, -1)
        geometry = Geometry(bodies, q[0], desc)
        # the symbols' size from the extent of what is described (one pin alone has none)
        xy = np.concatenate([geometry.world(q).reshape(-1, 2), q.reshape(-1, 3)[:, :2]])
        extent = float(np.hypot(*np.ptp(xy, axis=0))) if len(xy) else 0.0
        motion = Motion(geometry, _Steps(np.array([t]), q, extent or 1.0))  # type: ignore[arg-type]
        unit = str((desc.get("units") or {}).get("length", "m"))
        reason = textwrap.shorten(str(e), 110, placeholder=" ...")
        title = textwrap.fill(f"{mechanism.name} as drawn, not assembled: {reason}", 64)
        return _draw(ax, motion, 0, unit, title, {})
    return draw_model(model, ax, t)


def _img(data: bytes, alt: str) -> str:
    return f'<img alt="{escape(alt)}" src="data:image/png;base64,{base64.b64encode(data).decode()}"/>'


def mechanism_png(mechanism: Mechanism) -> bytes:
    fig, (ax,) = _figure(5.6, 4.2)
    draw_mechanism(mechanism, ax)
    return png(fig)


def model_html(model: Model) -> str:
    """A model's counts, units, drivers and structure, beside its drawing at t = 0."""
    rows = [
        ("moving bodies", f"{model.n_bodies} ({model.n_coords} coordinates)"),
        ("rows", f"{model.n_rows}"),
        ("units", f"lengths in {model.units['length']}, angles in rad, time in s"),
        ("drivers", ", ".join(c[0] for c in model.constraints if c[1] == "driver") or "none"),
        ("solver", f"{model.solver}, {model.linear} LU"),
    ]
    try:
        mob = model.mobility()
        rows.insert(2, ("degrees of freedom", f"Gruebler {mob.gruebler_dof}, rank {mob.dof}"))
        rows.append(("structure", ", ".join(g.kind for g in model.structure().groups)))
    except LinkworkError as e:
        rows.append(("assembly", f"fails at t = 0: {e}"))
    table = "".join(
        f"<tr><th style='text-align:left'>{escape(k)}</th><td>{escape(v)}</td></tr>" for k, v in rows
    )
    try:
        fig, (ax,) = _figure(5.6, 4.2)
        draw_model(model, ax)
        picture = _img(png(fig), f"{model.name} at t = 0")
    except LinkworkError as e:
        picture = f"<p>not drawn: {escape(str(e))}</p>"
    return (
        f"<div><strong>{escape(repr(model))}</strong>"
        "<div style='display:flex;gap:1em;align-items:flex-start'>"
        f"<table>{table}</table>{picture}</div></div>"
    )


#: rows of the coordinates' table a notebook shows (a large model has thousands)
MAX_ROWS = 24


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def results_html(results: Results) -> str:
    """A summary table (range, peak rate and acceleration of every coordinate; residual,
    iterations, closest approach to a singular configuration; events) and two small plots:
    the default outputs over time and the paths over the mechanism at the first step."""
    from .series import default_outputs, output

    r = results
    head = f"<strong>{escape(r.model.name)}</strong>: {r.n_steps} steps"
    if r.n_steps == 0:
        return f"<div>{head}</div>"
    head += f", t = {r.times[0]:.6g} .. {r.times[-1]:.6g} s"
    cells = "".join(
        f"<th>{h}</th>" for h in ("coordinate", "unit", "min", "max", "max |rate|", "max |accel|")
    )
    body = []
    for k, c in enumerate(r.columns[:MAX_ROWS]):
        q = r.q[:, k]
        rate = "-" if r.qd is None else _fmt(np.abs(r.qd[:, k]).max())
        acc = "-" if r.qdd is None else _fmt(np.abs(r.qdd[:, k]).max())
        body.append(
            f"<tr><td style='text-align:left'>{escape(c)}</td><td>{escape(r.units(c))}</td>"
            f"<td>{_fmt(q.min())}</td><td>{_fmt(q.max())}</td><td>{rate}</td><td>{acc}</td></tr>"
        )
    if len(r.columns) > MAX_ROWS:
        body.append(
            f"<tr><td colspan='6'>... and {len(r.columns) - MAX_ROWS} more (results.summary())</td></tr>"
        )
    worst = int(np.argmin(r.pivot_ratio))
    pivot = f"{r.pivot_ratio[worst]:.2e} at t = {r.times[worst]:g} (near 0: near singular)"
    if r.simulated:
        sim = cast("Simulation", r)
        e = sim.energy()
        energy = r.model.units["energy"]
        diag = [
            ("method", f"{sim.method}: {sim.n_steps_taken} steps ({sim.n_rejected} rejected)"),
            ("largest drift", f"{sim.drift.max():.2e} (positions), {sim.drift_d.max():.2e} (rates)"),
            ("energy balance", f"within {np.abs(e.balance).max():.2e} {energy}"),
            ("work not conservative", f"{e.work[-1]:.6g} {energy} by t = {r.times[-1]:g} s"),
            ("smallest pivot ratio", pivot),
        ]
    else:
        diag = [
            ("worst scaled residual", f"{r.residual.max():.2e}"),
            ("Newton iterations", f"mean {r.iterations.mean():.2f}, max {r.iterations.max()}"),
            ("smallest pivot ratio", pivot),
            ("events", str(len(r.events) or "none")),
        ]
    diag_rows = "".join(
        f"<tr><th style='text-align:left'>{k}</th><td style='text-align:left'>{escape(v)}</td></tr>"
        for k, v in diag
    )
    events = "".join(f"<li>{escape(str(e))}</li>" for e in r.events[:MAX_ROWS])
    fig, (ax0, ax1) = _figure(9.0, 3.2, cols=2)
    rows = slice(None, None, max(1, r.n_steps // 2000))
    for name in default_outputs(r)[:6]:
        o = output(r, name)
        ax0.plot(r.times[rows], o.value[rows], label=f"{o.name} [{o.unit}]")
    ax0.set_xlabel("t [s]")
    ax0.grid(True, alpha=0.3)
    ax0.legend(fontsize=7)
    draw_results(r, ax1)
    ax1.title.set_fontsize(9)
    picture = _img(png(fig), f"{r.model.name}: outputs over time and paths")
    if r.simulated:
        picture += _simulation_picture(cast("Simulation", r), rows)
    return (
        f"<div><p>{head}</p><div style='display:flex;gap:1.5em;align-items:flex-start;flex-wrap:wrap'>"
        f"<table><thead><tr>{cells}</tr></thead><tbody>{''.join(body)}</tbody></table>"
        f"<div><table>{diag_rows}</table>{f'<ul>{events}</ul>' if events else ''}</div></div>{picture}</div>"
    )


def _simulation_picture(sim: Simulation, rows: slice) -> str:
    """A simulation's energy, balance error and drift over time, as one small figure."""
    from .series import simulation_charts

    charts = [c for c in simulation_charts(sim) if c.title != "rates"]
    fig, axes = _figure(13.5, 3.0, cols=len(charts))
    for ax, c in zip(axes, charts):
        for name, v in c.lines.items():
            ax.plot(sim.times[rows], v[rows], label=name)
        ax.set_title(c.title, fontsize=9)
        ax.set_xlabel("t [s]")
        if c.unit:
            ax.set_ylabel(c.unit)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    return _img(png(fig), f"{sim.model.name}: energy, balance error and drift over time")


class Animation:
    """An animation of a sweep a notebook plays inline (``_repr_html_``); ``html`` is
    the markup, ``save(path)`` writes it as a page, ``frames`` counts its frames."""

    def __init__(self, html: str, frames: int) -> None:
        self.html, self.frames = html, frames

    def _repr_html_(self) -> str:
        return self.html

    def save(self, path: str) -> None:
        with open(path, "w", encoding="utf-8") as f:
            f.write(
                f"<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>{self.html}</body></html>"
            )

    def __repr__(self) -> str:
        return f"<linkwork Animation: {self.frames} frames>"


def animate(results: Results, frames: int = 60, fps: int = 20, mode: str = "jshtml") -> Animation:
    """The mechanism moving over the sweep, ``frames`` frames spread evenly over the steps,
    each point's trace so far, the time in a corner: ``mode="jshtml"`` (matplotlib's
    JavaScript player with its own controls, frames embedded as PNG; nothing else needed)
    or ``"html5"`` (an H.264 video; needs ffmpeg)."""
    from matplotlib.animation import FFMpegWriter, FuncAnimation

    frames = _args.integer(frames, "frames", 1, 2000)
    fps = _args.integer(fps, "fps", 1, 240)
    mode = _args.choice(mode, "mode", ("jshtml", "html5"))
    if mode == "html5" and not FFMpegWriter.isAvailable():
        raise DependencyError("animate(mode='html5') needs ffmpeg on the PATH; mode='jshtml' needs nothing")
    if results.n_steps == 0:
        raise InputError("nothing to animate: the results have no steps")
    motion = Motion(Geometry.from_model(results.model), results)
    fig, (ax,) = _figure(6.4, 4.8)
    fig.set_layout_engine("none")
    artists = MechanismArtists(ax, motion, clock=True)
    setup_axes(ax, motion, str(results.model.units.get("length", "m")))
    ax.set_title(results.model.name, fontsize=10)
    fig.tight_layout()
    rows = motion.frames(frames)
    anim = FuncAnimation(
        fig, lambda row: artists.update(int(row)), frames=rows, interval=1000.0 / fps, blit=False
    )
    html = anim.to_jshtml(fps=fps, default_mode="loop") if mode == "jshtml" else anim.to_html5_video()
    return Animation(html, len(rows))
