"""Targets of a synthesized design: the precision points (and poses) it was asked to pass,
marked in its pictures (the page, SVG, DXF and PNG), and how far its traced point passes
from each, measured on an engine sweep.

A `Targets` holds the points (n x 2), optionally the rotation of the body carrying the
traced point from position 1 at each (rad: a pose), and optionally the model's time at
each precision position. `of_design` reads them from any design by duck typing:
``.positions`` (n x 2), ``.coupler_angles`` (or None) and ``.precision_times()`` if it
has one. `deviation` measures, on a sweep's `Results`:

- ``nearest``: the distance from each target to the nearest point of the traced path
  (the polyline's nearest point, refined by Newton's method on the engine's solution
  between its steps, so it is the path's, not the chord's);
- ``at_position``: the distance from each target to the traced point at its precision
  time (solved there, on the sweep's branch; inf where the sweep does not reach that
  time or the solve fails), and ``angle_error``, the body's rotation there minus the
  prescribed one (rad).

>>> import numpy as np
>>> from linkwork import examples
>>> res = examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 101))
>>> p = res.point("P").position
>>> dev = deviation(res, Targets(p[[10, 50]] + [0.0, 0.001]))
>>> bool(np.all(dev.nearest <= 0.001))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _args
from ..errors import InputError, SolveError

if TYPE_CHECKING:
    from linkwork import Results

__all__ = [
    "Targets",
    "Deviation",
    "of_design",
    "as_targets",
    "deviation",
    "sweep_design",
    "target_marks",
    "TARGET_COLOUR",
]

#: the colour of the targets and their deviations in every picture
TARGET_COLOUR = "#d62728"


def _array(value: Any, name: str, shape: tuple[int | None, ...]) -> np.ndarray:
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"targets: {name} must be numbers, not {value!r:.60} ({e})") from None
    ok = a.ndim == len(shape) and all(s is None or a.shape[i] == s for i, s in enumerate(shape))
    if not ok:
        want = " x ".join("n" if s is None else str(s) for s in shape)
        raise InputError(f"targets: {name} must be {want}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = np.argwhere(~np.isfinite(a))[0]
        where = tuple(int(i) for i in bad)
        raise InputError(f"targets: {name} must be finite; entry {where} is {a[where]}")
    return a


@dataclass(frozen=True)
class Targets:
    """What a design was asked to do: the traced point ``point`` (default "P") through
    ``points`` (n x 2, the model's length unit); ``angles`` (n, rad, or None): the rotation
    of ``body`` (default "coupler") from position 1 at each (a pose); ``times`` (n, or
    None): the model's time at each precision position. Bad input is an `InputError`."""

    points: np.ndarray
    angles: np.ndarray | None = None
    times: np.ndarray | None = None
    point: str = "P"
    body: str = "coupler"

    def __post_init__(self) -> None:
        pts = _array(self.points, "points", (None, 2))
        if len(pts) == 0:
            raise InputError("targets: points is empty (give at least one point, n x 2)")
        object.__setattr__(self, "points", pts)
        for name in ("angles", "times"):
            value = getattr(self, name)
            if value is not None:
                a = _array(value, name, (None,))
                if len(a) != len(pts):
                    raise InputError(f"targets: {name} has {len(a)} entries for {len(pts)} points")
                object.__setattr__(self, name, a)
        for name in ("point", "body"):
            if not isinstance(getattr(self, name), str):
                raise InputError(f"targets: {name} must be a name (str), not {getattr(self, name)!r}")

    def __len__(self) -> int:
        return len(self.points)

    def name(self, j: int) -> str:
        """The name of target j (0-based): the point's name and its position's number, "P1"."""
        return f"{self.point}{j + 1}"


def of_design(design: Any, point: str = "P", body: str = "coupler") -> Targets:
    """The targets of a synthesized design: ``design.positions`` (n x 2),
    ``design.coupler_angles`` (n, or None) and ``design.precision_times()`` (the model's
    time at each precision position) where the design has it."""
    positions = getattr(design, "positions", None)
    if positions is None:
        raise InputError(
            f"targets: {type(design).__name__} has no .positions (n x 2 precision points); "
            "give the targets as points (n x 2) or a Targets"
        )
    times = getattr(design, "precision_times", None)
    if callable(times):
        times = times()
    return Targets(positions, getattr(design, "coupler_angles", None), times, point, body)


def as_targets(value: Any) -> Targets | None:
    """``targets=`` as the pictures take it: None, a `Targets`, a design (see
    `of_design`) or the points (n x 2)."""
    if value is None or isinstance(value, Targets):
        return value
    if hasattr(value, "positions"):
        return of_design(value)
    if hasattr(value, "model") and not isinstance(value, (list, tuple, np.ndarray)):
        return of_design(value)  # a design without positions: of_design says so
    return Targets(value)


@dataclass(frozen=True)
class Deviation:
    """How far a sweep's traced point passes from each target (see the module's
    docstring). Arrays are (n,) or (n, 2), one row per target; ``at_position``,
    ``position_xy``, ``reached`` and ``angle_error`` are None without the targets'
    times (``position_xy`` is NaN where not reached), ``angle_error`` and ``heading``
    None without their angles. ``heading``: the world direction (rad) the body's x axis
    is prescribed at each target (its direction at position 1 plus the rotation); the
    pictures draw it as a tick."""

    targets: Targets
    unit: str
    nearest: np.ndarray
    nearest_xy: np.ndarray
    nearest_time: np.ndarray
    at_position: np.ndarray | None
    position_xy: np.ndarray | None
    reached: np.ndarray | None
    angle_error: np.ndarray | None
    heading: np.ndarray | None

    def label(self, j: int) -> str:
        """The label of target j in the pictures: its number and the distance of the path
        (and of the traced point at its position, where known and different)."""
        text = f"{j + 1}: {self.nearest[j]:.2g} {self.unit}"
        if self.at_position is not None and self.reached is not None:
            if not self.reached[j]:
                text += " (position not reached)"
            elif self.at_position[j] > 1.01 * self.nearest[j] + 1e-15 * _size(self):
                text += f" (at its position {self.at_position[j]:.2g})"
        return text

    def heading_line(self) -> str:
        """The heading of the pictures' list of `label`s."""
        t = self.targets
        text = f"distance of {t.point}'s path from each target"
        return text + (f" (and of {t.point} at its position)" if self.at_position is not None else "")

    def worst(self) -> float:
        """The largest distance of the path from a target."""
        return float(self.nearest.max())

    def report(self) -> str:
        """The numbers, one line per target."""
        t, u = self.targets, self.unit
        head = f"targets of {t.point}: distance to the nearest point of its path"
        if self.at_position is not None:
            head += "; at the precision position: the distance"
            head += f", and the error of {t.body}'s rotation" if self.angle_error is not None else ""
        lines = [head]
        for j, (x, y) in enumerate(t.points):
            line = f"  {t.name(j)} ({x:.6g}, {y:.6g}): path {self.nearest[j]:.3e} {u}"
            line += f" at t = {self.nearest_time[j]:.6g}"
            if self.at_position is not None and self.reached is not None:
                if self.reached[j]:
                    assert t.times is not None
                    line += f"; at t = {t.times[j]:.6g}: {self.at_position[j]:.3e} {u}"
                    if self.angle_error is not None:
                        line += f", rotation error {self.angle_error[j]:.3e} rad"
                else:
                    assert t.times is not None
                    line += f"; position at t = {t.times[j]:.6g} not reached by the sweep"
            lines.append(line)
        return "\n".join(lines)

    def to_json(self) -> list[dict[str, Any]]:
        """One dict per target, for the interactive page (non-finite numbers as None)."""

        def num(v: Any) -> Any:
            v = float(v)
            return v if math.isfinite(v) else None

        out = []
        for j, (x, y) in enumerate(self.targets.points):
            item: dict[str, Any] = {
                "name": self.targets.name(j),
                "x": num(x),
                "y": num(y),
                "nearest": num(self.nearest[j]),
                "nearest_xy": [num(v) for v in self.nearest_xy[j]],
                "nearest_time": num(self.nearest_time[j]),
                "label": self.label(j),
            }
            if self.targets.angles is not None:
                item["angle"] = num(self.targets.angles[j])
            if self.heading is not None:
                item["heading"] = num(self.heading[j])
            if self.at_position is not None and self.reached is not None and self.targets.times is not None:
                item["time"] = num(self.targets.times[j])
                item["reached"] = bool(self.reached[j])
                item["at_position"] = num(self.at_position[j])
            if self.angle_error is not None:
                item["angle_error"] = num(self.angle_error[j])
            out.append(item)
        return out


def _size(dev: Deviation) -> float:
    return float(np.ptp(dev.targets.points)) or 1.0


def _point_names(results: Results) -> list[str]:
    return list(results.model.point_names)


def _refine(
    results: Results, name: str, target: np.ndarray, t0: float, q0: np.ndarray, lo: float, hi: float
) -> tuple[float, float, np.ndarray] | None:
    """(distance, time, point) of the traced point nearest ``target`` for t in [lo, hi]:
    Newton's method on (P(t) - T) . P'(t) = 0 from t0, each P solved by the engine from the
    previous configuration (so on the sweep's branch). None if no solve succeeded."""
    model = results.model
    best: tuple[float, float, np.ndarray] | None = None
    t, q = t0, q0
    for _ in range(30):
        try:
            state = model.solve(t, q_guess=q)
        except SolveError:
            break
        p = state.point(name)
        assert p.velocity is not None and p.acceleration is not None
        d = p.position - target
        dist = float(np.hypot(*d))
        if best is None or dist < best[0]:
            best = (dist, t, np.array(p.position, dtype=float))
        g = float(d @ p.velocity)
        gp = float(p.velocity @ p.velocity + d @ p.acceleration)
        if not gp > 0.0:
            break
        t_next = min(max(t - g / gp, lo), hi)
        if abs(t_next - t) <= 4e-16 * max(1.0, abs(t)):
            break
        t, q = t_next, state.q
    return best


def deviation(results: Results, targets: Any) -> Deviation:
    """How far the sweep's traced point (``targets.point``) passes from each target: the
    distance to the nearest point of its path over the sweep, and (with the targets'
    times) to the point at each precision position, with the rotation error of
    ``targets.body`` there (with their angles). ``targets``: as `as_targets` takes."""
    if not _args.is_sweep(results):
        raise InputError(f"deviation needs the Results of a sweep, not {type(results).__name__}")
    found = as_targets(targets)
    if found is None:
        raise InputError("targets must be given (points n x 2, a Targets or a design), not None")
    tg = found
    if tg.point not in _point_names(results):
        names = ", ".join(_point_names(results)) or "none"
        raise InputError(f"targets: the model has no point named {tg.point!r} to trace (points: {names})")
    needs_body = tg.angles is not None
    if needs_body and tg.body not in results.model.body_names:
        raise InputError(
            f"targets: the model has no body named {tg.body!r} for the poses' rotations "
            f"(bodies: {', '.join(results.model.body_names)})"
        )
    if results.n_steps == 0:
        raise InputError("targets: the results have no steps")
    if results._kept is not None and len(results._kept) < len(results.model.columns):
        # the distances are refined by solving the model from the sweep's configurations
        raise InputError("targets need a sweep that kept every coordinate (sweep without outputs=...)")
    path = np.asarray(results.point(tg.point).position, dtype=float)
    times = np.asarray(results.times, dtype=float)
    ok = np.all(np.isfinite(path), axis=1)
    rows = np.flatnonzero(ok)
    if len(rows) == 0:
        raise InputError(f"targets: the sweep has no finite position of {tg.point}")
    n = len(tg)
    nearest = np.empty(n)
    nearest_xy = np.empty((n, 2))
    nearest_time = np.empty(n)
    pts = path[rows]
    a, b = pts[:-1], pts[1:]
    ab = b - a
    ab2 = np.einsum("ij,ij->i", ab, ab)
    unit = str(results.model.units.get("length", "m"))
    for j, target in enumerate(tg.points):
        if len(pts) == 1:
            k, s = 0, 0.0
            dist = float(np.hypot(*(pts[0] - target)))
        else:
            s_all = np.clip(np.einsum("ij,ij->i", target - a, ab) / np.where(ab2 > 0, ab2, 1.0), 0.0, 1.0)
            foot = a + s_all[:, None] * ab
            d_all = np.hypot(*(foot - target).T)
            k = int(np.argmin(d_all))
            s, dist = float(s_all[k]), float(d_all[k])
        r0 = rows[k]
        r1 = rows[min(k + 1, len(rows) - 1)]
        t_guess = float(times[r0] + s * (times[r1] - times[r0]))
        xy = pts[k] + s * (pts[min(k + 1, len(pts) - 1)] - pts[k])
        best_t = t_guess
        span = times[rows[max(k - 1, 0)]], times[rows[min(k + 2, len(rows) - 1)]]
        lo, hi = min(span), max(span)
        refined = _refine(results, tg.point, target, t_guess, results.q[r0], lo, hi)
        if refined is not None:  # a point of the path (a chord may pass closer, off it)
            dist, best_t, xy = refined
        nearest[j], nearest_xy[j], nearest_time[j] = dist, xy, best_t
    at_position = position_xy = reached = angle_error = heading = None
    theta_1: float | None = None
    if tg.times is not None:
        at_position = np.full(n, math.inf)
        position_xy = np.full((n, 2), math.nan)
        reached = np.zeros(n, dtype=bool)
        thetas = np.full(n, math.nan)
        t_lo, t_hi = float(times[rows].min()), float(times[rows].max())
        slack = 1e-12 * max(1.0, abs(t_lo), abs(t_hi))
        for j, tj in enumerate(tg.times):
            if not t_lo - slack <= tj <= t_hi + slack:
                continue
            k = int(rows[np.argmin(np.abs(times[rows] - tj))])
            try:
                state = results.model.solve(float(tj), q_guess=results.q[k])
            except SolveError:
                continue
            p = np.asarray(state.point(tg.point).position, dtype=float)
            reached[j] = True
            position_xy[j] = p
            at_position[j] = float(np.hypot(*(p - tg.points[j])))
            if needs_body:
                thetas[j] = float(state.body(tg.body).theta)
            # the traced point at its position is a point of the path too
            if at_position[j] < nearest[j]:
                nearest[j], nearest_xy[j], nearest_time[j] = at_position[j], p, tj
        if needs_body and reached[0]:
            theta_1 = float(thetas[0])
            assert tg.angles is not None
            angle_error = np.array(
                [
                    math.remainder(th - theta_1 - aj, 2.0 * math.pi) if r else math.inf
                    for th, aj, r in zip(thetas, tg.angles, reached)
                ]
            )
    if needs_body:
        assert tg.angles is not None
        if theta_1 is None:
            # position 1 not known by time: the body's direction where the path passes
            # nearest target 1
            k = int(np.argmin(np.abs(times - nearest_time[0])))
            try:
                state = results.model.solve(float(nearest_time[0]), q_guess=results.q[k])
                theta_1 = float(state.body(tg.body).theta)
            except SolveError:
                theta_1 = float(results.body(tg.body).theta[k])
        heading = theta_1 + tg.angles
    return Deviation(
        tg, unit, nearest, nearest_xy, nearest_time, at_position, position_xy, reached, angle_error, heading
    )


def target_marks(targets: Deviation, size: float) -> list[dict[str, Any]]:
    """What marks each target, in world coordinates, the same in every picture: ``ring``
    (centre and radius), ``cross`` (two segments), ``tick`` (the prescribed direction of
    the body's x axis, a segment from the target; None without angles) and ``miss`` (the
    segment from the target to the nearest point of the path)."""
    r = 0.014 * size
    out = []
    for j, (x, y) in enumerate(targets.targets.points):
        tick = None
        if targets.heading is not None:
            h = float(targets.heading[j])
            tick = np.array([[x, y], [x + 0.07 * size * np.cos(h), y + 0.07 * size * np.sin(h)]])
        out.append(
            {
                "name": targets.targets.name(j),
                "ring": ((float(x), float(y)), r),
                "cross": [np.array([[x - r, y], [x + r, y]]), np.array([[x, y - r], [x, y + r]])],
                "tick": tick,
                "miss": np.array([[x, y], targets.nearest_xy[j]]),
            }
        )
    return out


def sweep_design(design: Any, targets: Any = None, steps: int = 721) -> Results:
    """The sweep a design's pictures are drawn from: ``design.model()`` over one cycle of
    its periodic driver (one turn of the crank; 2 pi of time if the model has no single
    periodic driver) in ``steps`` steps plus the targets' times (``targets``: default the
    design's own, `of_design`, where it has positions), turning the way its precision
    times go (backwards if they all lie before position 1). A sweep that stops at a limit
    of the motion gives the steps before it."""
    steps = _args.integer(steps, "steps", 2)
    tg = as_targets(targets) if targets is not None else None
    if tg is None and hasattr(design, "positions"):
        tg = of_design(design)
    model = design.model().compile()
    cycle = model.cycle()
    span = cycle.period if cycle is not None else 2.0 * math.pi
    sign = 1.0
    grid = np.linspace(0.0, span, steps)
    if tg is not None and tg.times is not None:
        if np.all(tg.times <= 0.0) and np.any(tg.times < 0.0):
            sign = -1.0
        inside = sign * tg.times
        grid = np.union1d(grid, inside[(inside >= 0.0) & (inside <= span)])
    try:
        return model.sweep(sign * grid)
    except SolveError as e:
        partial = getattr(e, "partial", None)
        if partial is None or partial.n_steps < 2:
            raise
        return partial  # type: ignore[no-any-return]
