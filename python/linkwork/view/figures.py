"""Figures of a sweep: chosen outputs over time, paths of points in the plane (coupler
curves) over a faint drawing of the mechanism, and the mechanism moving as a GIF or MP4.
``linkwork run --plot``, ``linkwork plot`` and ``--animate`` write them.

Outputs are named as `linkwork.view.series` reads them (a coordinate column, a body's
angle, a named point's ``P.x``); the PNGs of `Results.plot` and `Results.plot_forces`
are drawn here too, and a simulation's energy balance and drift (`Simulation.plot_energy`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .drawing import Geometry, MechanismArtists, Motion, setup_axes
from .series import (
    X_AXES,
    Output,
    XAxis,
    _length_unit,
    default_outputs,
    default_paths,
    output,
    simulation_charts,
    unknown_outputs,
    unknown_paths,
    unknown_x,
    x_axis,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from linkwork import Results, Simulation

    from .targets import Deviation

__all__ = [
    "Output",
    "output",
    "default_outputs",
    "X_AXES",
    "XAxis",
    "x_axis",
    "unknown_x",
    "unknown_outputs",
    "default_paths",
    "unknown_paths",
    "movie_problem",
    "plot_outputs",
    "plot_paths",
    "draw_targets",
    "animate",
    "plot_results",
    "plot_forces",
    "plot_simulation",
]

#: figures need no more points per line than this, whatever the sweep's length
MAX_POINTS = 5000
#: pixels of an animation (width, height); even, as H.264 needs
MOVIE_SIZE = (640, 480)


def _step(n: int) -> int:
    return max(1, -(-n // MAX_POINTS))


def plot_outputs(
    results: Results, path: str, names: Sequence[str] | None = None, x: str = "time"
) -> list[str]:
    """A PNG of the outputs over time (or, with ``x``, against a driver's input: see
    `x_axis`): one column of axes per unit (rad, m, ...), rows for the value, the rate and
    the acceleration (rates are per second whatever the abscissa). Returns the names
    plotted."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = [output(results, n) for n in (names or default_outputs(results))]
    units = list(dict.fromkeys(o.unit for o in chosen))
    rows = [
        ("value", "", lambda o: o.value),
        ("rate", "/s", lambda o: o.rate),
        ("acceleration", "/s^2", lambda o: o.acceleration),
    ]
    rows = [r for r in rows if any(r[2](o) is not None for o in chosen)]
    k = slice(None, None, _step(results.n_steps))
    along = x_axis(results, x)
    t = along.value[k]
    fig, axes = plt.subplots(
        len(rows),
        len(units),
        figsize=(5.5 * len(units) + 1.0, 2.6 * len(rows) + 0.8),
        sharex=True,
        squeeze=False,
        constrained_layout=True,
    )
    for j, unit in enumerate(units):
        for i, (what, suffix, get) in enumerate(rows):
            ax = axes[i, j]
            for o in chosen:
                v = get(o)
                if o.unit == unit and v is not None:
                    ax.plot(t, v[k], label=o.name)
            ax.set_ylabel(f"{what} [{unit}{suffix}]")
            ax.grid(True, alpha=0.3)
            if i == 0:
                ax.legend(fontsize=8, loc="upper right")
        axes[-1, j].set_xlabel(f"{along.label} [{along.unit}]")
    span = f"t = {results.times[0]:g} .. {results.times[-1]:g} s"
    if x != "time":
        span += f", {along.label} = {along.value[0]:.4g} .. {along.value[-1]:.4g} {along.unit}"
    fig.suptitle(f"{results.model.name}: {results.n_steps} steps, {span}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [o.name for o in chosen]


def _labels(labels: object) -> bool:
    from ..errors import InputError

    if not isinstance(labels, bool):
        raise InputError(f"labels must be True or False, not {labels!r}")
    return labels


def draw_targets(ax: Axes, dev: Deviation, size: float, numbers: bool = True) -> None:
    """The targets of ``dev`` on matplotlib axes, as in the SVG: a ring and a cross each,
    its pose's tick, a dashed line to the path's nearest point and (``numbers``) its
    number."""
    from .targets import TARGET_COLOUR, target_marks

    for j, mark in enumerate(target_marks(dev, size)):
        (x, y), r = mark["ring"]
        ax.plot([x], [y], "o", ms=9, mfc="none", mec=TARGET_COLOUR, mew=1.5, zorder=6,
                label="targets" if j == 0 else None)  # fmt: skip
        ax.plot([x], [y], "+", ms=9, color=TARGET_COLOUR, zorder=6)
        if mark["tick"] is not None:
            t = mark["tick"]
            ax.plot(t[:, 0], t[:, 1], "-", color=TARGET_COLOUR, lw=2.0, zorder=6,
                    label="prescribed rotation" if j == 0 else None)  # fmt: skip
        m = mark["miss"]
        if np.all(np.isfinite(m)):
            ax.plot(m[:, 0], m[:, 1], "--", color=TARGET_COLOUR, lw=1.0, zorder=6)
        if numbers:
            ax.annotate(str(j + 1), (x, y), textcoords="offset points", xytext=(6, -12),
                        color=TARGET_COLOUR, fontsize=8, zorder=7)  # fmt: skip


def plot_paths(
    results: Results,
    path: str,
    names: Sequence[str] | None = None,
    labels: bool = False,
    targets: Any = None,
) -> list[str]:
    """A PNG of the paths of points in the plane (equal scales) over the mechanism drawn
    faintly at the first step; ``labels``: the bodies' and joints' names on it;
    ``targets`` (points n x 2, a `linkwork.view.targets.Targets` or a synthesized design):
    marked and numbered, with their poses' ticks, and the path's distance from each
    listed beside the axes (as in `linkwork.view.export.svg`). Returns the names drawn."""
    labels = _labels(labels)
    from .export import target_limits
    from .targets import deviation

    dev = None if targets is None else deviation(results, targets)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    motion = Motion(Geometry.from_model(results.model), results)
    motion.limits = target_limits(motion, dev)
    chosen = list(names) if names is not None else default_paths(results.model)
    if dev is None:
        fig, ax = plt.subplots(figsize=(7.5, 6.0), constrained_layout=True)
    else:
        fig, (ax, side) = plt.subplots(
            1, 2, figsize=(11.0, 6.0), constrained_layout=True, gridspec_kw={"width_ratios": [3.0, 1.6]}
        )
        from .targets import TARGET_COLOUR

        side.axis("off")
        lines = [dev.heading_line()] + [dev.label(j) for j in range(len(dev.targets))]
        side.text(0.0, 1.0, "\n".join(lines), va="top", ha="left", fontsize=8, color=TARGET_COLOUR,
                  wrap=True, transform=side.transAxes)  # fmt: skip
    MechanismArtists(ax, motion, alpha=0.3, traces=False, labels=labels).update(0)
    k = slice(None, None, _step(results.n_steps))
    for name in chosen:
        xy = motion.xy[k, motion.geometry.traceable[name]]
        ax.plot(xy[:, 0], xy[:, 1], lw=1.5, label=name)
    if dev is not None:
        draw_targets(ax, dev, motion.size)
    setup_axes(ax, motion, _length_unit(results))
    if chosen or dev is not None:
        # a fixed place: "best" searches over every line drawn (seconds on a large model)
        ax.legend(fontsize=8, loc="upper right")
    ax.set_title(
        f"{results.model.name}: paths over t = {results.times[0]:g} .. {results.times[-1]:g} s "
        f"(mechanism at t = {results.times[0]:g} s)"
    )
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return chosen


def movie_problem(path: str) -> str | None:
    """Why an animation cannot be written to ``path`` (its type, or ffmpeg missing for
    MP4), or None."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".gif":
        return None
    if ext == ".mp4":
        from matplotlib.animation import FFMpegWriter

        if FFMpegWriter.isAvailable():
            return None
        return f"{path}: writing MP4 needs ffmpeg on the PATH (install ffmpeg, or write a .gif)"
    return f"{path}: an animation is written as .gif or .mp4, not {ext or 'a file without extension'}"


def animate(results: Results, path: str, fps: int = 30, frames: int = 120, labels: bool = False) -> int:
    """Writes the mechanism moving over the sweep as a GIF (Pillow) or an MP4 (ffmpeg),
    ``MOVIE_SIZE`` pixels, with about ``frames`` frames spread evenly over the steps and
    the axis limits fixed over the whole motion; ``labels``: the bodies' and joints' names
    on it. Returns the number of frames written."""
    labels = _labels(labels)
    problem = movie_problem(path)
    if problem:
        raise ValueError(problem)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter, PillowWriter

    motion = Motion(Geometry.from_model(results.model), results)
    dpi = 100
    fig, ax = plt.subplots(figsize=(MOVIE_SIZE[0] / dpi, MOVIE_SIZE[1] / dpi), dpi=dpi)
    artists = MechanismArtists(ax, motion, clock=True, labels=labels)
    setup_axes(ax, motion, _length_unit(results))
    ax.set_title(results.model.name, fontsize=10)
    # laid out once (no layout engine): each frame is then drawn once, on the same axes
    fig.tight_layout()
    rows = motion.frames(frames)
    writer = PillowWriter(fps=fps) if path.lower().endswith(".gif") else FFMpegWriter(fps=fps)
    try:
        with writer.saving(fig, path, dpi):
            for row in rows:
                artists.update(int(row))
                writer.grab_frame()
    finally:
        plt.close(fig)
    return len(rows)


def plot_results(results: Results, path: str, bodies: Sequence[str] | None = None, every: int = 1) -> None:
    """A PNG of every body's angle, angular velocity and acceleration over time, and
    of the paths of the named points (plotting every ``every``-th step): `Results.plot`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(bodies) if bodies is not None else results.model.body_names
    k = slice(None, None, max(1, int(every)))
    t = results.times[k]
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), constrained_layout=True)
    for name in names:
        b = results.body(name)
        for ax, v in ((axes[0, 0], b.theta), (axes[0, 1], b.thetad), (axes[1, 0], b.thetadd)):
            if v is not None:
                ax.plot(t, v[k], label=name)
    for ax, what in zip(axes.flat, ["theta [rad]", "omega [rad/s]", "alpha [rad/s^2]"]):
        ax.set_xlabel("t [s]")
        ax.set_ylabel(what)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    ax = axes[1, 1]
    for pname in results.model.point_names:
        p = results.point(pname).position[k]
        ax.plot(p[:, 0], p[:, 1], label=f"point {pname}")
    for name in names:
        b = results.body(name)
        ax.plot(b.x[k], b.y[k], lw=0.8, ls="--", label=f"{name} origin")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("paths")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.suptitle(f"{results.model.name}: {results.n_steps} steps")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_forces(results: Results, path: str, every: int = 1) -> None:
    """A PNG of every driver's effort (split into inertia, gravity and loads) and of the
    magnitude of every joint's reaction force over the sweep: `Results.plot_forces`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if results.reactions is None:
        raise ValueError("no forces in these results: sweep(..., forces=True) computes them")
    k = slice(None, None, max(1, int(every)))
    t = results.times[k]
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(12, 4.5), constrained_layout=True)
    for name, role, *_ in results.model.constraints:
        if role == "driver":
            ax0.plot(t, results.effort(name)[k], lw=2, label=f"{name} (total)")
            for part, v in results.effort_parts(name).items():
                if np.any(v):
                    ax0.plot(t, v[k], lw=1, ls="--", label=f"{name}: {part}")
        else:
            force = results.reaction(name).force
            ax1.plot(t, np.hypot(force[k, 0], force[k, 1]), label=name)
    u = results.model.units
    ax0.set_ylabel(f"driver effort [{u['torque']} or {u['force']}]")
    ax1.set_ylabel(f"joint force magnitude [{u['force']}]")
    for ax in (ax0, ax1):
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{results.model.name}: inverse dynamics over {results.n_steps} steps")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_simulation(sim: Simulation, path: str, every: int = 1) -> None:
    """A PNG of a simulation over time (every ``every``-th row): its energy (kinetic,
    potential, work of what is not conservative), the balance's error, the constraints'
    drift before projection and the plotted coordinates' rates: `Simulation.plot_energy`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k = slice(None, None, max(1, int(every)))
    t = sim.times[k]
    charts = simulation_charts(sim)
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), constrained_layout=True)
    panels = [[c] for c in charts[:3]] + [charts[3:]]
    for ax, group in zip(axes.flat, panels):
        for c in group:
            for name, v in c.lines.items():
                label = f"{name} [{c.unit}]" if c.title == "rates" else name
                ax.plot(t, v[k], label=label)
        titles = {c.title for c in group}
        units = {c.unit for c in group}
        ax.set_title(", ".join(sorted(titles)) or "rates (none: nothing moves)", fontsize=10)
        if len(units) == 1 and "" not in units:
            ax.set_ylabel(f"[{units.pop()}]")
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
        if group:
            ax.legend(fontsize=8)
    fig.suptitle(f"{sim.model.name}: simulation ({sim.method}), {sim.n_steps} rows")
    fig.savefig(path, dpi=110)
    plt.close(fig)
