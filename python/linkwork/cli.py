"""The command line.

    linkwork demo [four_bar|slider_crank|...] [--steps N] [--revolutions R] [--out DIR]
    linkwork run MODEL [--t0 T0] [--t1 T1] [--steps N] [--every K] [--format csv|npz|parquet]
                       [--keep NAME,...] [--derivatives 0|1|2] [--points] [--forces] [--plot]
                       [--outputs NAME,...] [--x time|input|DRIVER] [--paths NAME,...]
                       [--angles rad|deg] [--svg] [--dxf] [--at T]
                       [--animate FILE.gif|FILE.mp4] [--fps F] [--frames N] [--out DIR]
    linkwork plot MODEL [--t0 T0] [--t1 T1] [--steps N] [--outputs NAME,...] [--paths NAME,...]
                        [--x time|input|DRIVER] [--svg] [--dxf] [--at T]
                        [--animate FILE.gif|FILE.mp4] [--fps F] [--frames N] [--out DIR]
    linkwork view MODEL [--t0 T0] [--t1 T1] [--steps N] [--outputs NAME,...] [--paths NAME,...]
                        [--frames N] [--out DIR|FILE.html]
    linkwork check MODEL [--t T] [--angles rad|deg]
    linkwork study STUDY [--scheduler ADDRESS|local] [--chunk N] [--format nc|parquet] [--out DIR]

``demo`` sweeps a built-in mechanism: it prints a summary (range of every coordinate, worst
residual, Newton iterations, closest approach to a singular configuration, events, speed)
and writes DIR/<name>.csv and DIR/<name>.png.

``run`` sweeps a model file (anything `Mechanism.load` reads), prints the same summary and
writes DIR/<model>.csv (or .npz, .parquet: every coordinate, its rate and acceleration, the
diagnostics, with units); ``--every K`` keeps steps 0, K, 2K, ... With ``--forces`` it adds
the inverse dynamics (peak efforts and their parts, peak pin forces, the energy balance)
and DIR/<model>_forces.csv. ``--plot`` writes DIR/<model>.png (outputs over time) and
DIR/<model>_paths.png (paths of points over the mechanism at t0), ``--animate FILE`` the
mechanism moving, ``--svg`` / ``--dxf`` the mechanism at ``--at`` (default t0) with the
paths of points as drawings. ``plot`` sweeps and writes the figures only. ``view`` sweeps
and writes the interactive page (one self-contained HTML file).

``check`` reports degrees of freedom, redundant joints and each driver's limits of motion.

``study`` runs a study file (a design space or a tolerance study; docs/studies.md)
in-process or on a Dask cluster and writes its dataset and a report with figures.

Exit status: 0 done; 1 the model file cannot be read or compiled, the sweep failed (the
good steps are written first) or the model has a problem (check); 2 bad usage.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from .errors import LinkworkError, LinkworkWarning
from .mechanism import examples

if TYPE_CHECKING:
    from .model.compiled import Model
    from .model.results import Results

FORMATS = ("csv", "npz", "parquet")


def demo(args: argparse.Namespace) -> int:
    mech = examples.ALL[args.example]()
    model = mech.compile()
    omega = float(mech.to_dict()["drivers"][0]["law"]["rate"])
    t1 = args.revolutions * 2.0 * math.pi / abs(omega)
    times = np.linspace(0.0, t1, args.steps)
    print(f"{model!r}")
    start = time.perf_counter()
    try:
        results = model.sweep(times, progress=sys.stderr.isatty())
    except LinkworkError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    elapsed = time.perf_counter() - start
    print(results.summary())
    print(f"  speed                   {elapsed / args.steps * 1e6:.3f} us per step "
          f"(positions, velocities, accelerations; {args.steps} steps in {elapsed:.3f} s)")  # fmt: skip
    os.makedirs(args.out, exist_ok=True)
    csv_path = os.path.join(args.out, f"{args.example}.csv")
    png_path = os.path.join(args.out, f"{args.example}.png")
    results.to_csv(csv_path)
    results.plot(png_path, every=max(1, args.steps // 2000))  # the plot needs no more points
    print(f"wrote {csv_path} and {png_path}")
    return 0


def _load(path: str) -> Model:
    """The compiled model of a model file; raises _Failed with a message naming the file."""
    from .mechanism.builder import Mechanism

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", LinkworkWarning)
            mechanism = Mechanism.load(path)
        model = mechanism.compile()
    except (OSError, ValueError, TypeError, KeyError, AttributeError, LinkworkError) as e:
        # a model error already names the body, joint or driver at fault (and the file)
        message = str(e)
        raise _Failed(message if message.startswith(os.fspath(path)) else f"{path}: {message}") from None
    units = model.units
    said = "as the file declares" if mechanism.units_declared else "the default: the file declares no units"
    angle = units.get("input_angle", "rad")
    print(f"units: lengths in {units.get('length', 'm')}, angles in {angle} ({said})")
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)
    return model


class _Failed(Exception):
    """A failure reported as ``error: <message>`` with exit status ``status``."""

    def __init__(self, message: str, status: int = 1) -> None:
        super().__init__(message)
        self.status = status


def _check_figures(args: argparse.Namespace, model: Model) -> None:
    """Refuses unknown --outputs and --paths names before sweeping (bad usage)."""
    from .view import figures

    problem = (
        figures.unknown_outputs(model, args.outputs or [])
        or figures.unknown_paths(model, args.paths or [])
        or figures.unknown_x(model, getattr(args, "x", "time"))
    )
    if problem:
        raise _Failed(f"{args.model}: {problem}", status=2)


def _sweep(
    args: argparse.Namespace,
    model: Model,
    forces: bool = False,
    every: int = 1,
    keep: list[str] | None = None,
    derivatives: int = 2,
) -> tuple[Results, int]:
    """Sweeps from t0 to t1, keeping ``keep`` (None: as the model says); a failed sweep
    gives its good steps and status 1."""
    times = np.linspace(args.t0, _t1(args, model), args.steps)
    try:
        results = model.sweep(
            times,
            progress=sys.stderr.isatty(),
            forces=forces,
            every=every,
            outputs=keep,
            derivatives=derivatives,
        )
        return results, 0
    except (KeyboardInterrupt, LinkworkError) as e:
        return _stopped(args, e, "steps")


def _stopped(args: argparse.Namespace, e: BaseException, rows: str) -> tuple[Any, int]:
    """What a sweep or simulation stopped part way kept, and the exit status: 130 after
    Ctrl-C, 1 after a failure (its good ``rows`` are written); with nothing kept, the
    interrupt goes on and the failure is reported."""
    partial = getattr(e, "partial", None)
    if partial is None or len(partial) == 0:
        if isinstance(e, KeyboardInterrupt):
            raise e
        raise _Failed(f"{args.model}: {e}") from None
    if isinstance(e, KeyboardInterrupt):
        last = float(partial.times[-1])
        print(f"interrupted at t = {last:g}: writing the {len(partial)} {rows} done", file=sys.stderr)
        return partial, 130
    print(f"error: {args.model}: {e}", file=sys.stderr)
    print(f"(the {len(partial)} {rows} before the failure are in the output)", file=sys.stderr)
    return partial, 1


def _t1(args: argparse.Namespace, model: Model) -> float:
    """The last time: --t1, else one cycle of the model's periodic driver after t0, else
    t0 + 1 s; says which (once)."""
    if args.t1 is None:
        cycle = model.cycle()
        if cycle is None:
            args.t1 = args.t0 + 1.0
            print(f"t1 = {args.t1:g} s (the default, 1 s: the model has no single periodic driver)")
        else:
            args.t1 = args.t0 + cycle.period
            print(f"t1 = {args.t1:.6g} s ({cycle})")
    return float(args.t1)


def _angles(args: argparse.Namespace, model: Model) -> str:
    """The unit of the angles printed: --angles, else the file's (rad or deg); says it."""
    angles = args.angles or str(model.units.get("input_angle", "rad"))
    said = "--angles" if args.angles else "the file's angle unit; --angles rad|deg for the other"
    print(f"angles printed in {angles} ({said})")
    return angles


def _stem(args: argparse.Namespace) -> str:
    return os.path.join(args.out, os.path.splitext(os.path.basename(args.model))[0])


def _figures(args: argparse.Namespace, results: Results, plots: bool) -> list[str]:
    """Writes the PNGs (if ``plots``) and the animation (if asked); returns their paths."""
    from .view import figures

    written = []
    if plots:
        written.append(_stem(args) + ".png")
        figures.plot_outputs(results, written[-1], args.outputs, x=args.x)
        written.append(_stem(args) + "_paths.png")
        figures.plot_paths(results, written[-1], args.paths)
    for kind in ("svg", "dxf"):
        if getattr(args, kind, False):
            written.append(f"{_stem(args)}.{kind}")
            at = args.t0 if args.at is None else args.at
            getattr(results, f"to_{kind}")(written[-1], t=at, paths=args.paths)
    if args.animate:
        folder = os.path.dirname(args.animate)
        if folder:
            os.makedirs(folder, exist_ok=True)
        n = figures.animate(results, args.animate, fps=args.fps, frames=args.frames)
        written.append(f"{args.animate} ({n} frames)")
    return written


def _kept(args: argparse.Namespace, model: Model) -> list[str] | None:
    """What `run` keeps: --keep, else the model's outputs; every coordinate where the
    figures or the forces need them all."""
    if args.plot or args.animate or args.forces:
        if args.keep:
            problem = "--keep keeps only some coordinates; --plot, --animate and --forces need them all"
            raise _Failed(problem, status=2)
        return list(model.columns)
    if args.keep:
        try:
            model._outputs(args.keep, LinkworkError)
        except LinkworkError as e:
            raise _Failed(f"{args.model}: --keep: {e}", status=2) from None
    return args.keep


def run(args: argparse.Namespace) -> int:
    model = _load(args.model)
    _check_figures(args, model)
    keep = _kept(args, model)
    if args.derivatives < 2 and (args.forces or args.plot or args.animate):
        raise _Failed("--plot, --animate and --forces need --derivatives 2", 2)
    print(f"{model!r}")
    results, status = _sweep(
        args, model, forces=args.forces, every=args.every, keep=keep, derivatives=args.derivatives
    )
    print(results.summary(angles=_angles(args, model)))
    os.makedirs(args.out, exist_ok=True)
    written = [f"{_stem(args)}.{args.format}"]
    writer = {"csv": results.to_csv, "npz": results.to_npz, "parquet": results.to_parquet}[args.format]
    writer(written[0], points=args.points)
    if args.forces and results.reactions is not None:
        print(results.forces_summary())
        written.append(_stem(args) + "_forces.csv")
        results.forces_to_csv(written[-1])
        if args.plot:
            written.append(_stem(args) + "_forces.png")
            results.plot_forces(written[-1], every=max(1, len(results) // 2000))
    written += _figures(args, results, plots=args.plot)
    print("wrote " + ", ".join(written))
    return status


def simulate(args: argparse.Namespace) -> int:
    """Forward dynamics of a model file whose free coordinates follow from its forces."""
    from .mechanism.builder import Mechanism

    try:
        model = Mechanism.load(args.model).compile(free=True)
        if args.free_drivers:
            freed = True if args.free_drivers == ["all"] else args.free_drivers
            model = model.freed(freed)
    except (OSError, ValueError, TypeError, KeyError, AttributeError, LinkworkError) as e:
        raise _Failed(f"{args.model}: {e}") from None
    if model.dof == 0:
        raise _Failed(f"{args.model}: every coordinate is driven: nothing to simulate (use linkwork run)")
    qd0 = None
    if args.qd0:
        qd0 = np.zeros(len(model.columns))
        for item in args.qd0:
            name, _, value = item.partition("=")
            if name not in model.columns or not value:
                raise _Failed(
                    f"--qd0 {item!r}: give COLUMN=VALUE, a column of the model: {', '.join(model.columns)}",
                    2,
                )
            qd0[model.columns.index(name)] = float(value)
    t1 = args.t0 + 1.0 if args.t1 is None else args.t1
    times = np.linspace(args.t0, t1, args.steps)
    print(f"{model!r}: {model.dof} free coordinate(s), {args.method}, rtol {args.rtol:g}")
    try:
        sim = model.simulate(
            times,
            method=args.method,
            rtol=args.rtol,
            atol=args.rtol,
            qd0=qd0,
            max_steps=args.max_steps,
            progress=sys.stderr.isatty(),
            at_travel_end=args.at_travel_end,
        )
        status = 0
    except (KeyboardInterrupt, LinkworkError) as e:
        sim, status = _stopped(args, e, "times")
    energy = sim.energy()
    print(
        f"{sim.n_steps_taken} steps ({sim.n_rejected} rejected), {sim.n_evaluations} evaluations; "
        f"largest drift before projection {float(np.max(sim.drift)):.2e} (positions), "
        f"{float(np.max(sim.drift_d)):.2e} (rates); energy balance within "
        f"{float(np.max(np.abs(energy.balance))):.2e}"
    )
    _print_events(sim.events)
    os.makedirs(args.out, exist_ok=True)
    path = f"{_stem(args)}.csv"
    sim.to_csv(path, points=True)
    written = [path]
    if args.plot:
        written += _figures(args, sim, plots=True)
        written.append(f"{_stem(args)}_energy.png")
        sim.plot_energy(written[-1], every=max(1, len(sim) // 2000))
    if args.page is not None and len(sim):
        page = args.page or f"{_stem(args)}.html"
        folder = os.path.dirname(page)
        if folder:
            os.makedirs(folder, exist_ok=True)
        sim.to_html(page, outputs=args.outputs, paths=args.paths)
        written.append(f"{page} (open it in a browser)")
    print("wrote " + ", ".join(written))
    return status


def _print_events(events: list[Any], most: int = 20) -> None:
    """One line per located event (the first ``most``): where a simulation crossed a
    singular configuration, locked, or met the end of a slider's travel."""
    if not events:
        return
    print(f"{len(events)} event(s):")
    for e in events[:most]:
        print(f"  t = {e.time:.9g} s, {e.kind}: {e.message}")
    if len(events) > most:
        print(f"  ... and {len(events) - most} more (the page and Simulation.events have all)")


def plot(args: argparse.Namespace) -> int:
    model = _load(args.model)
    _check_figures(args, model)
    print(f"{model!r}")
    results, status = _sweep(args, model, keep=list(model.columns))
    os.makedirs(args.out, exist_ok=True)
    print("wrote " + ", ".join(_figures(args, results, plots=True)))
    return status


def view(args: argparse.Namespace) -> int:
    """Sweeps and writes the interactive page: DIR/MODEL.html, or FILE.html."""
    model = _load(args.model)
    _check_figures(args, model)
    print(f"{model!r}")
    results, status = _sweep(args, model)
    if args.out.lower().endswith((".html", ".htm")):
        path = args.out
    else:
        path = _stem(args) + ".html"
    folder = os.path.dirname(path)
    if folder:
        os.makedirs(folder, exist_ok=True)
    results.to_html(path, outputs=args.outputs, paths=args.paths, frames=args.frames)
    n = min(args.frames, len(results))
    events = len(results.events)
    print(f"wrote {path} ({n} frames of {len(results)} steps, {events} events; open it in a browser)")
    return status


def check(args: argparse.Namespace) -> int:
    """Counts bodies, rows and degrees of freedom, finds redundant rows, the structure
    (groups solved together, in order: inputs, Assur dyads, triads), each driver's
    limits of motion, the four-bar loops and slider-cranks (Grashof type, closed-form
    limits, circuit) and the assembly modes, without sweeping; exit status 1 if the model
    has a problem."""
    model = _load(args.model)
    angles = _angles(args, model)
    print(f"{model!r}")
    closing = model.closing
    if closing is not None:
        print(closing.report(model.units["length"], angles))
    try:
        mob = model.mobility(t=args.t)
    except LinkworkError as e:
        raise _Failed(f"{args.model}: cannot assemble at t = {args.t}: {e}") from None
    print(mob.report())
    # the groups of coordinates solved together, in solving order (from Phi_q's pattern)
    print(model.structure().report(limit=MAX_LISTED))
    problem = mob.redundant or mob.dof_driven > 0
    drivers = [c[0] for c in model.constraints if c[1] == "driver"]
    # each search sweeps the whole model over a turn: a few drivers of a large model
    listed = MAX_LISTED if model.n_coords <= LARGE_MODEL else 2
    if len(drivers) > listed:
        print(f"  limits of motion        of the first {listed} of {len(drivers)} drivers "
              "(linkwork.Model.motion_limits gives any)")  # fmt: skip
    for name in drivers[:listed]:
        try:
            limits = model.motion_limits(name, t=args.t, q_guess=mob.q)
            print(f"  limits of motion        {limits.describe(angles, model.units['length'])}")
        except LinkworkError as e:
            print(f"  limits of motion        {name}: not found ({e})")
    # the four-bar loops and slider-cranks inside it: Grashof type, closed-form limits
    linkages = model.linkages(t=args.t, q_guess=mob.q)
    for linkage in linkages[:MAX_LISTED]:
        print(f"  {linkage.describe(angles)}")
    if len(linkages) > MAX_LISTED:
        print(
            f"  ... and {len(linkages) - MAX_LISTED} more linkages (linkwork.Model.linkages lists them all)"
        )
    if len(linkages) > MAX_MODE_LOOPS:
        # 2 circuits a loop: 2^n modes, which no search of seeded starts can list
        n = len(linkages)
        print(f"  assembly modes at t = {args.t:g}: not searched ({n} loops, up to 2^{n})")
        print("problems found" if problem else "ok")
        return 1 if problem else 0
    modes = model.assembly_modes(t=args.t, q_guess=mob.q)
    circuits = "; ".join(
        ", ".join([f"{k} {v}" for k, v in m.circuits.items()] + [f"det {m.det_sign:+.0f}"]) for m in modes
    )
    print(f"  assembly modes at t = {args.t:g}: {len(modes)} ({circuits}; {modes.tries} starts searched)")
    print("problems found" if problem else "ok")
    return 1 if problem else 0


#: linkages listed by ``check`` (a large model has thousands)
MAX_LISTED = 20
#: coordinates above which ``check`` searches the limits of motion of two drivers only
LARGE_MODEL = 3000
#: above this many loops ``check`` does not search the assembly modes (2 circuits a loop)
MAX_MODE_LOOPS = 6


def _names(text: str) -> list[str]:
    return [n.strip() for n in text.split(",") if n.strip()]


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {value}")
    return value


_OUTPUTS_HELP = (
    "outputs plotted over time, comma-separated: a column (rocker.theta, slider.x), a body (its "
    "angle) or a named point's coordinate (P.x, P.y); default: the angle of every body that "
    "turns, x and y of every body that only slides"
)
_PATHS_HELP = (
    "points whose paths are drawn in the plane, comma-separated: named points or joints; "
    "default: every named point (every pin off the ground if there are none)"
)


def _sweep_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("model", help="model file (as written by Mechanism.save)")
    p.add_argument("--t0", type=float, default=0.0, help="first time [s] (default 0)")
    p.add_argument(
        "--t1",
        type=float,
        default=None,
        help="last time [s] (default: one cycle of the model's driver after t0 when it has exactly "
        "one periodic driver (a crank at a constant rate: 2 pi / |rate|; a harmonic or periodic law), "
        "else t0 + 1)",
    )
    p.add_argument(
        "--steps", type=int, default=1001, metavar="N", help="time steps from t0 to t1 (default 1001)"
    )


def _angles_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--angles",
        choices=("rad", "deg"),
        default=None,
        help="unit of the angles printed (default: the file's angle unit)",
    )


def _figure_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--outputs", type=_names, metavar="NAME,...", help=_OUTPUTS_HELP)
    p.add_argument(
        "--x",
        default="time",
        metavar="time|input|DRIVER",
        help="plot the outputs against time (default) or the driver's input: its periodic driver, else "
        "its only moving one, or the driver named (an angle in the file's angle unit, or a distance)",
    )
    p.add_argument("--paths", type=_names, metavar="NAME,...", help=_PATHS_HELP)
    p.add_argument(
        "--animate",
        metavar="FILE",
        help="write the mechanism moving to FILE.gif (Pillow) or FILE.mp4 (ffmpeg)",
    )
    p.add_argument(
        "--fps", type=_positive_int, default=30, metavar="F", help="animation frames per second (default 30)"
    )
    p.add_argument(
        "--frames",
        type=_positive_int,
        metavar="N",
        default=120,
        help="animation frames, spread evenly over the sweep (default 120)",
    )
    p.add_argument(
        "--svg", action="store_true", help="also write DIR/MODEL.svg: the mechanism at --at, paths"
    )
    p.add_argument(
        "--dxf", action="store_true", help="also write DIR/MODEL.dxf: the same drawing as DXF (needs ezdxf)"
    )
    p.add_argument(
        "--at", type=float, metavar="T", help="time of the mechanism in --svg and --dxf [s] (default t0)"
    )
    p.add_argument(
        "--out", default="linkwork-out", metavar="DIR", help="output folder (default linkwork-out)"
    )


def _parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    fmt = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(
        prog="linkwork",
        description="Planar mechanism kinematics: sweep a model file over time, write its "
        "results (CSV, NPZ, Parquet), plots (PNG), animations (GIF, MP4), drawings (SVG, DXF) "
        "and an interactive page (HTML).",
        epilog="Exit status: 0 done, 1 a model or sweep failed (good steps are written), 2 bad usage. "
        "See docs/cli.md.",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser(
        "demo",
        help="sweep a built-in mechanism, print a summary, write CSV and PNG",
        description="Sweeps a built-in mechanism over whole crank revolutions, prints a summary and "
        "the speed, and writes DIR/NAME.csv (every coordinate, rate, acceleration, diagnostics) and "
        "DIR/NAME.png (angles, rates, accelerations and paths).",
    )
    d.add_argument("example", nargs="?", default="four_bar", choices=sorted(examples.ALL))
    d.add_argument("--steps", type=int, default=100_000, help="time steps (default 100000)")
    d.add_argument("--revolutions", type=float, default=1.0, help="crank revolutions (default 1)")
    d.add_argument(
        "--out", default="linkwork-out", metavar="DIR", help="output folder (default linkwork-out)"
    )

    r = sub.add_parser(
        "run",
        formatter_class=fmt,
        help="sweep a model file; write its results (CSV, NPZ or Parquet), with --plot PNGs",
        description="""Sweeps a model file from t0 to t1, prints a summary (range of every coordinate,
worst residual, Newton iterations, smallest pivot ratio, located events) and writes:
  DIR/MODEL.csv|.npz|.parquet  time, every coordinate (or what --keep or the model's outputs
                               keep: coordinates, point paths P.x, P.y), its rate (_d) and
                               acceleration (_dd), iterations, residual, pivot_ratio; units in
                               the CSV headers, in an array 'units' (NPZ) or in each field's
                               metadata (Parquet)
  DIR/MODEL_forces.csv         with --forces: driver efforts (and parts), power, joint reactions
  DIR/MODEL.png                with --plot: outputs over time (value, rate, acceleration)
  DIR/MODEL_paths.png          with --plot: paths of points over the mechanism at t0
  DIR/MODEL_forces.png         with --plot --forces
  FILE.gif|FILE.mp4            with --animate FILE: the mechanism moving
  DIR/MODEL.svg, DIR/MODEL.dxf with --svg, --dxf: the mechanism at --at (default t0) and
                               the paths of points, in world coordinates (1:1)
A sweep that fails at step k writes its k good steps and exits with status 1.""",
    )
    _sweep_arguments(r)
    r.add_argument(
        "--every",
        type=_positive_int,
        default=1,
        metavar="K",
        help="keep steps 0, K, 2K, ... (default 1: all)",
    )
    r.add_argument(
        "--format",
        choices=FORMATS,
        default="csv",
        help="results file: csv (default), npz (NumPy) or parquet (needs pyarrow)",
    )
    r.add_argument(
        "--keep",
        type=_names,
        metavar="NAME,...",
        help="keep only these, comma-separated: bodies, columns (rocker.theta), named points, joints "
        "(their paths); default: the model's outputs, else every coordinate",
    )
    r.add_argument(
        "--derivatives",
        type=int,
        choices=(0, 1, 2),
        default=2,
        help="0: positions only; 1: and velocities; 2 (default): and accelerations",
    )
    r.add_argument(
        "--points", action="store_true", help="named points' x, y and their rates in the results file too"
    )
    r.add_argument("--forces", action="store_true", help="inverse dynamics: driver efforts, joint reactions")
    r.add_argument("--plot", action="store_true", help="also write the PNGs of outputs and paths")
    _angles_argument(r)
    _figure_arguments(r)

    p = sub.add_parser(
        "plot",
        formatter_class=fmt,
        help="sweep a model file; write PNGs of outputs over time and of paths (and an animation)",
        description="""Sweeps a model file from t0 to t1 and writes:
  DIR/MODEL.png        the chosen outputs over time: value, rate and acceleration,
                       one column of plots per unit
  DIR/MODEL_paths.png  the paths of points in the plane (equal scales) over the
                       mechanism drawn at t0
  FILE.gif|FILE.mp4    with --animate FILE: the mechanism moving (640 x 480 pixels),
                       axis limits fixed over the whole motion
  DIR/MODEL.svg|.dxf   with --svg, --dxf: the mechanism at --at (default t0) and the
                       paths of points, in world coordinates (1:1)""",
    )
    _sweep_arguments(p)
    _figure_arguments(p)

    v = sub.add_parser(
        "view",
        formatter_class=fmt,
        help="sweep a model file; write the interactive page (one self-contained HTML file)",
        description="""Sweeps a model file from t0 to t1 and writes one HTML file that opens in any
browser without a network: the mechanism drawn to scale, a slider over the steps (time
and the drivers' inputs), play and pause, the paths of points, live values of the
outputs, plots linked to the slider, and the events (limits, bifurcations, locks, branch
jumps, the closest approach to a singular configuration) marked on the timeline.
  DIR/MODEL.html       or FILE.html if --out ends in .html""",
    )
    _sweep_arguments(v)
    v.add_argument("--outputs", type=_names, metavar="NAME,...", help=_OUTPUTS_HELP)
    v.add_argument("--paths", type=_names, metavar="NAME,...", help=_PATHS_HELP)
    v.add_argument(
        "--frames",
        type=_positive_int,
        default=1000,
        metavar="N",
        help="slider positions, spread evenly over the steps (default 1000; every step if fewer)",
    )
    v.add_argument(
        "--out",
        default="linkwork-out",
        metavar="DIR|FILE.html",
        help="output folder (default linkwork-out), or the page's file name if it ends in .html",
    )

    sim = sub.add_parser(
        "simulate",
        formatter_class=fmt,
        help="forward dynamics: the motion a model's forces produce (its free coordinates)",
        description="""Compiles a model file keeping its undriven coordinates free and integrates its
equations of motion from the drawing (at rest, the file's initial_rates, or --qd0) under
gravity, springs, dampers, applied loads, joint forces, motors and friction
(docs/dynamics.md), and writes:
  DIR/MODEL.csv     time, every coordinate with its rate and acceleration, the named
                    points, and per row the constraints' drift before projection
                    (residual) and the augmented matrix's pivot ratio
  DIR/MODEL.png     with --plot: coordinates over time; DIR/MODEL_paths.png the paths;
                    DIR/MODEL_energy.png the energy balance, the drift and the rates
  DIR/MODEL.html    with --page (or --page FILE.html): the interactive page of
                    `linkwork view`, the mechanism moving over the simulated times,
                    with the energy balance, the drift and the rates plotted
A run that fails part way writes the times it reached and exits with status 1.""",
    )
    _sweep_arguments(sim)
    sim.add_argument("--method", choices=("rk8", "gen-alpha"), default="rk8", help="integrator (default rk8)")
    sim.add_argument(
        "--rtol", type=float, default=1e-8, help="relative and absolute tolerance (default 1e-8)"
    )
    sim.add_argument(
        "--qd0",
        type=_names,
        metavar="COLUMN=VALUE,...",
        help="initial rates of coordinates (crank.theta=-1,...; the rest 0); they must be consistent "
        "with the joints (default: the file's initial_rates, the other rates following from the joints)",
    )
    sim.add_argument(
        "--free-drivers",
        type=_names,
        metavar="DRIVER,...|all",
        help="drivers to free for this run (their coordinates follow the forces; the others are kept)",
    )
    sim.add_argument(
        "--at-travel-end",
        choices=("stop", "continue"),
        default="stop",
        help="where a slider reaches an end of its joint's travel: stop the run there (the rows before "
        "it written, exit status 0) or report it and go on (default stop)",
    )
    sim.add_argument(
        "--max-steps", type=_positive_int, default=None, metavar="N", help="stop after N integration steps"
    )
    sim.add_argument(
        "--plot", action="store_true", help="also write the PNGs of coordinates, paths and energy"
    )
    sim.add_argument(
        "--page",
        nargs="?",
        const="",
        default=None,
        metavar="FILE.html",
        help="also write the interactive page (default DIR/MODEL.html)",
    )
    _figure_arguments(sim)

    c = sub.add_parser(
        "check",
        help="count bodies, rows, degrees of freedom; find redundancy and limits",
        description="Reports the degrees of freedom (Gruebler's count and the rank of Phi_q), redundant "
        "joints and each driver's limits of motion, without sweeping; writes nothing. Exit status 1 "
        "if the model has a problem.",
    )
    c.add_argument("model", help="model file (as written by Mechanism.save)")
    c.add_argument("--t", type=float, default=0.0, help="time of the configuration checked (default 0)")
    _angles_argument(c)

    s = sub.add_parser(
        "synth",
        formatter_class=fmt,
        help="design mechanisms from precision points: every solution, screened, as model files",
        description="""Reads a synthesis problem file (TOML: problem = motion | path | function |
chained-six-bar, with its poses, points or angles, or curve, with a target curve;
docs/synthesis.md), finds every exact solution (certified; for a curve, the designs
refined from many starts, ranked), assembles and screens the designs with the engine, and writes:
  DIR/PROBLEM_designK.toml   each design as a model file (linkwork run can sweep it)
  DIR/PROBLEM_report.txt     the solutions, their certificates, defects and merit order
  DIR/PROBLEM.png            the designs at position 1 and their coupler paths through
                             the precision points
  DIR/PROBLEM_designK.html   the first six designs' pages, drawings and figures with the
       .svg, .png            precision points and poses marked and the path's distance
                             from each (the numbers are in the report)
Exit status 1 if no design results.""",
    )
    s.add_argument("problem", help="problem file (TOML)")
    s.add_argument(
        "--out", default="linkwork-out", metavar="DIR", help="output folder (default linkwork-out)"
    )
    st = sub.add_parser(
        "study",
        formatter_class=fmt,
        help="a design study or tolerance study from a study file: dataset and report",
        description="""Reads a study file (TOML: the model, times, outputs, and a [grid],
[latin_hypercube], [designs] or [tolerances] section; docs/studies.md), sweeps every
design in-process on all cores or on a Dask cluster (--scheduler), and writes:
  DIR/STUDY.nc|.parquet     the dataset: a row per design, its parameters, the figures
                            asked for and its error if it failed; units with every column
  DIR/STUDY.md + PNGs       the report: an atlas of coupler curves and the figures against
                            the parameters, or (tolerances) the path envelopes, the
                            histogram of output errors, Monte Carlo beside first order and
                            which parameter contributes most
Designs that fail are listed, not dropped; exit status 1 when every design failed.""",
    )
    st.add_argument("study", help="study file (TOML)")
    st.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="a Dask scheduler address (tcp://host:8786), or 'local' for a local cluster of one "
        "process per core (default: in-process, the engine's threads)",
    )
    st.add_argument("--chunk", type=_positive_int, default=None, metavar="N", help="designs per task")
    st.add_argument("--format", choices=("nc", "parquet"), default="nc", help="dataset file (default nc)")
    st.add_argument(
        "--out", default="linkwork-out", metavar="DIR", help="output folder (default linkwork-out)"
    )
    commands = {"demo": d, "run": r, "plot": p, "check": c, "synth": s, "study": st, "view": v}
    return parser, {**commands, "simulate": sim}


def _usage_problem(args: argparse.Namespace) -> str | None:
    """What is wrong with the arguments before any model is read, or None."""
    if args.command in ("check", "synth", "study"):
        return None
    if args.steps < 2:
        return "--steps must be at least 2"
    if getattr(args, "format", "csv") == "parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            return "--format parquet needs pyarrow: pip install pyarrow"
    if getattr(args, "dxf", False):
        try:
            import ezdxf  # noqa: F401
        except ImportError:
            return "--dxf needs ezdxf: pip install ezdxf"
    if getattr(args, "frames", 2) < 2 and args.command == "view":
        return "--frames must be at least 2"
    if getattr(args, "animate", None):
        from .view.figures import movie_problem

        return movie_problem(args.animate)
    return None


def _synth(args: argparse.Namespace) -> int:
    from .synthesis.cli import synth

    return synth(args)


def _study(args: argparse.Namespace) -> int:
    from .study.cli import study

    return study(args)


def main(argv: list[str] | None = None) -> int:
    parser, commands = _parser()
    args = parser.parse_args(argv)
    problem = _usage_problem(args)
    if problem:
        commands[args.command].error(problem)  # exits with status 2
    do: dict[str, Any] = {
        "demo": demo,
        "run": run,
        "plot": plot,
        "check": check,
        "synth": _synth,
        "study": _study,
        "view": view,
        "simulate": simulate,
    }
    try:
        return int(do[args.command](args))
    except LinkworkError as e:  # a synthesis problem that is not well posed
        print(f"error: {e}", file=sys.stderr)
        return 1
    except _Failed as e:
        print(f"error: {e}", file=sys.stderr)
        return e.status
    except OSError as e:  # an output that cannot be written
        print(f"error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
