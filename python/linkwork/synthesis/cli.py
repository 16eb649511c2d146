"""``linkwork synth PROBLEM``: read a synthesis problem file, solve it, write every design
as a model file, a report and a figure of the designs through the precision points.

Problem file (TOML; docs/synthesis.md)::

    problem = "motion"        # motion | path | function | chained-six-bar | curve
    angles = "deg"            # units of every angle in the file: "deg" or "rad" (default)
    poses = [[x, y, angle], ...]          # motion: 2 to 5 poses (more: least squares)
    moving = [[x, y], [x, y]]             # motion, 2 or 3 poses: chosen moving pivots
    points = [[x, y], ...]                # path: 5 points (more: least squares)
    length_range = [lo, hi]               # least squares: bounds on the fitted lengths
    min_transmission = 30.0               # least squares: designs kept (deg)
    input_angles = [...]                  # path: crank rotations; function: input angles
    output = [...]                        # function: output angles or slider positions
    kind = "four_bar"                     # function: four_bar | slider_crank
    ground = 1.0                          # function, four_bar: ground length
    input_pivot = [x, y]                  # chained-six-bar: Q (also points,
    output_pivot = [x, y]                 #   input_angles, coupler_angles)
    [torque]                              # chained-six-bar: mass, inertia, gravity, omega
    [curve], [constraints], [fit]         # curve: linkwork.synthesis.curve.problem
    [six_bars]                            # curve: six-bars grown from the best four-bars
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import synthesis as S
from ..errors import LinkworkError, SynthesisError
from ..view.targets import Deviation, Targets, deviation, of_design, sweep_design

if TYPE_CHECKING:
    from ..model.compiled import Model
    from ..model.results import Results

PROBLEMS = ("motion", "path", "function", "chained-six-bar", "curve")


def _read(path: str) -> dict[str, Any]:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python < 3.11
        import tomli as tomllib
    with open(path, "rb") as f:
        try:
            return tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise SynthesisError(f"{path}: not a TOML problem file: {e}") from None


def _need(problem: dict[str, Any], key: str, kind: str) -> Any:
    if key not in problem:
        raise SynthesisError(f"a {kind} problem needs '{key}'")
    return problem[key]


def _angle_column(a: Any, unit: str) -> np.ndarray:
    return np.radians(np.asarray(a, dtype=float)) if unit == "deg" else np.asarray(a, dtype=float)


def _least_squares_options(problem: dict[str, Any]) -> dict[str, Any]:
    """length_range = [lo, hi] and min_transmission (deg) of a least-squares problem."""
    out: dict[str, Any] = {}
    if "length_range" in problem:
        lr = problem["length_range"]
        if not (isinstance(lr, list) and len(lr) == 2):
            raise SynthesisError("length_range must be [lo, hi]")
        out["length_range"] = (float(lr[0]), float(lr[1]))
    if "min_transmission" in problem:
        out["min_transmission"] = float(problem["min_transmission"])
    return out


def solve(problem: dict[str, Any], base: str = ".") -> tuple[str, list[Any], np.ndarray | None]:
    """(report, designs with .model(), precision points to draw) of one problem (files it
    names relative to ``base``)."""
    kind = problem.get("problem")
    unit = problem.get("angles", "rad")
    if unit not in ("rad", "deg"):
        raise SynthesisError(f"angles must be 'rad' or 'deg', not {unit!r}")
    if kind == "motion":
        poses = np.array(_need(problem, "poses", kind), dtype=float)
        if poses.ndim != 2 or poses.shape[1] != 3:
            raise SynthesisError("poses must be rows of [x, y, angle]")
        if len(poses) > 5:
            result = S.motion_least_squares(poses, angles=unit, **_least_squares_options(problem))
        else:
            result = S.motion(
                poses, moving=problem.get("moving"), ground=problem.get("ground_pivots"), angles=unit
            )
        return result.report(), result.designs, poses[:, :2]
    if kind == "path":
        points = np.array(_need(problem, "points", kind), dtype=float)
        input_angles = _need(problem, "input_angles", kind)
        if len(points) > 5:
            options = _least_squares_options(problem)
            result = S.path_least_squares(points, input_angles, angles=unit, **options)
        else:
            result = S.path(points, input_angles, angles=unit)
        return result.report(), result.designs, points
    if kind == "function":
        phi = _angle_column(_need(problem, "input_angles", kind), unit)
        out = np.asarray(_need(problem, "output", kind), dtype=float)
        fk = problem.get("kind", "four_bar")
        if fk == "four_bar":
            out = _angle_column(out, unit)
        design = S.function(phi, out, kind=fk, ground=float(problem.get("ground", 1.0)))
        if fk == "four_bar":
            text = (
                f"function generation (Freudenstein four-bar): crank {design.a:.6g}, coupler {design.b:.6g}, "
                f"rocker {design.c:.6g}, ground {design.d:.6g} (negative: pointing the other way)"
            )
            return text, [design], None
        text = f"function generation (Freudenstein slider-crank): crank {design.a:.6g}, rod {design.b:.6g}, "
        text += f"offset {design.e:.6g}"
        return text, [], None
    if kind == "chained-six-bar":
        return _chained_six_bar(problem, unit)
    if kind == "curve":
        from .curve.problem import solve_curve

        return solve_curve(problem, base)
    raise SynthesisError(f"problem must be one of {', '.join(PROBLEMS)}; got {kind!r}")


def _chained_six_bar(problem: dict[str, Any], unit: str) -> tuple[str, list[Any], np.ndarray]:
    """The chained six-bar from the file's numbers; with a [torque] table, the input
    torque of the first design that is defect-free and turns fully."""
    from . import six_bar as C

    kind = "chained-six-bar"
    keys = ("points", "input_angles", "coupler_angles", "input_pivot", "output_pivot")
    data = {k: _need(problem, k, kind) for k in keys}
    result = C.chained_six_bar(angles=unit, **data)
    text = result.report()
    options = problem.get("torque")
    if options is not None:
        if not isinstance(options, dict) or set(options) - {"mass", "inertia", "gravity", "omega"}:
            raise SynthesisError("torque must be a table of mass, inertia, gravity and omega")
        try:
            options = {k: float(v) for k, v in options.items()}
        except (TypeError, ValueError) as e:
            raise SynthesisError(f"torque: {e}") from None
        full = [d for d in result.designs if d.defects.ok and d.defects.full_turn]
        if full:
            tq = C.torque(full[0], **options)
            text += (
                f"\n  input torque of design {result.designs.index(full[0]) + 1} over a turn: "
                f"phi {np.abs(tq.phi).max():.4g}, theta {np.abs(tq.theta).max():.4g}, "
                f"summed {np.abs(tq.total).max():.4g} N m (peaks); virtual work agrees to "
                f"{np.abs(tq.total - tq.virtual_work).max():.2e} N m"
            )
        else:
            text += "\n  input torque: no design is defect-free and turns fully"
    return text, result.designs, result.points


#: designs (the first in merit order) drawn with their targets: page, SVG and PNG each
MAX_PICTURES = 6


def _targets(design: Any, points: np.ndarray | None) -> Targets | None:
    """A design's targets: its own (positions, poses, precision times) where it has them,
    else the problem's precision points."""
    if hasattr(design, "positions"):
        return of_design(design)
    return None if points is None else Targets(points)


#: one design in the overview figure: its number, model, sweep and deviation (None where
#: the sweep failed or the design has no targets)
Drawn = tuple[int, "Model", "Results | None", "Deviation | None"]


def _pictures(
    out: str, stem: str, designs: list[Any], points: np.ndarray | None
) -> tuple[list[Drawn], list[str]]:
    """Each of the first `MAX_PICTURES` designs swept over a turn, with its page, SVG and
    PNG (targets marked) in ``out``; returns each design for the overview figure and the
    report's lines (the deviations, or why a design's pictures are not drawn)."""
    from ..view.figures import plot_paths
    from ..view.page import page
    from .curve.fit import CurveDesign
    from .curve.six_bar_fit import SixBarDesign

    drawn: list[Drawn] = []
    lines = []
    for k, design in enumerate(designs[:MAX_PICTURES], 1):
        targets = _targets(design, points)
        try:
            res = sweep_design(design, targets)
            dev = None if targets is None else deviation(res, targets)
        except LinkworkError as e:
            lines.append(f"design {k}: no pictures, its sweep failed ({e})")
            drawn.append((k, design.model().compile(), None, None))
            continue
        base = os.path.join(out, f"{stem}_design{k}")
        page(res, base + ".html", targets=targets, title=f"{stem}: design {k}")
        res.to_svg(base + ".svg", targets=targets)
        if isinstance(design, (CurveDesign, SixBarDesign)):  # the target against the traced curve
            design.plot(base + ".png")
        else:
            plot_paths(res, base + ".png", targets=targets)
        drawn.append((k, res.model, res, dev))
        if dev is not None:
            lines.append(f"design {k}, {dev.report()}")
    return drawn, lines


def _figure(path: str, drawn: list[Drawn], points: np.ndarray | None, title: str) -> None:
    """The designs at position 1 and the paths of their point P through the precision
    points, each design's farthest distance from a target in the legend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 6))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, compiled, res, dev in drawn:
        color = colors[(k - 1) % len(colors)]
        names = [p[0] for p in compiled._core.points]
        if res is not None and res.n_steps and "P" in names:
            p = res.point("P").position
            label = f"design {k}: path of P"
            if dev is not None:
                label += f" (farthest from a target: {dev.worst():.2g})"
            ax.plot(p[:, 0], p[:, 1], "-", color=color, lw=1.2, label=label)
        # the linkage at position 1: its joints joined body by body
        joints = {}
        for name, b1, b2, x, y in _joint_points(compiled):
            joints[name] = (x, y, b1, b2)
        marks = {p["body"]: tuple(p["at"]) for p in compiled.description.get("points", [])}
        for body in compiled.body_names:
            pts = [(x, y) for (x, y, b1, b2) in joints.values() if body in (b1, b2)]
            if body in marks:
                pts.append(marks[body])
            if len(pts) >= 2:
                xs, ys = zip(*pts, pts[0])
                ax.plot(xs, ys, "-", color=color, lw=2.5, alpha=0.6)
        ground = [(x, y) for (x, y, b1, b2) in joints.values() if "ground" in (b1, b2)]
        if ground:
            gx, gy = zip(*ground)
            ax.plot(gx, gy, "^", color=color, ms=9)
    if points is not None:
        ax.plot(points[:, 0], points[:, 1], "ko", ms=7, label="precision points", zorder=5)
        for j, (x, y) in enumerate(points, 1):
            ax.annotate(str(j), (x, y), textcoords="offset points", xytext=(5, 5))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _joint_points(compiled: Any) -> list[tuple[str, str, str, float, float]]:
    """(name, body a, body b, x, y) of each revolute at the drawing."""
    out = []
    for j in compiled.description.get("joints", []):
        if j.get("type") == "revolute" and "at" in j:
            out.append((j["name"], j.get("body_a", "ground"), j.get("body_b", "ground"), *j["at"]))
    return out


def synth(args: Any) -> int:
    """The ``synth`` command: status 0 done, 1 no design (report still written)."""
    problem = _read(args.problem)
    report, designs, points = solve(problem, os.path.dirname(os.path.abspath(args.problem)))
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.problem))[0]
    written = []
    for k, design in enumerate(designs, 1):
        if hasattr(design, "model"):
            path = os.path.join(args.out, f"{stem}_design{k}.toml")
            design.model().save(path)
            written.append(path)
    drawn, lines = _pictures(args.out, stem, [d for d in designs if hasattr(d, "model")], points)
    if lines:
        report += "\n" + "\n".join(lines)
    with open(os.path.join(args.out, f"{stem}_report.txt"), "w", encoding="utf-8") as f:
        f.write(report + "\n")
    figure = os.path.join(args.out, f"{stem}.png")
    if designs or points is not None:
        _figure(figure, drawn, points, f"{stem}: {problem.get('problem')}")
    print(report)
    swept = sum(res is not None for _, _, res, _ in drawn)
    pictures = f", {stem}_designK.html, .svg and .png of {swept}" if swept else ""
    print(
        f"wrote {len(written)} design model file(s){pictures}, {stem}_report.txt and {stem}.png in {args.out}"
    )
    return 0 if designs else 1


__all__ = ["synth", "solve", "PROBLEMS", "LinkworkError"]
