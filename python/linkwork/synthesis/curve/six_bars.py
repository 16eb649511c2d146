"""Six-bars for synthesis from a curve, where a four-bar cannot follow it (a straight
stretch, a corner): the four-bar of `TrackingProblem` (crank O2-A, coupler A-B carrying
the point C, rocker O4-B) with a dyad C-D-F whose link C-D ("link5") carries the tracer
P, D joined to F by "link6":

- ``"stephenson"`` (Stephenson III): F a third ground pivot O6; the ground (O2, O4, O6)
  and the coupler (A, B, C) are the ternary links;
- ``"watt"`` (Watt I): F a pin E on the rocker; the coupler (A, B, C) and the rocker
  (O4, B, E), joined at B, are the ternary links, the ground binary.

The design vector extends the four-bar's,

    y = [r1, r2, r3, r4, rcx, rcy, theta0, x0, y0, r5, r6, fx, fy, px, py, theta2_1 .. theta2_n],

r5 = |C D|, r6 = |D F|, (fx, fy) O6 in the world (Stephenson) or E in the rocker's frame
(origin O4, x along O4 -> B; Watt), (px, py) P in link5's frame (origin C, x along
C -> D); D on the ``side`` ("left" or "right") of the line C -> F. The objective is the
tracking error of P. As for the four-bar, every evaluation builds the six-bar as a
linkwork model and sweeps it over a crank turn; the Jacobian is the engine's exact
sensitivities of P to every pin's place in every body (`Model.sensitivities`, ``pin
J@body``, ``pivot J``, ``point P``, the driver's start) carried to y by the chain rule.
The crank turns fully (the four-bar's constraints hold) and the dyad assembles over the
whole turn on its side, or the design raises `CircuitError`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...errors import InputError, ModelError, SolveError, SynthesisError
from ...mechanism.builder import Mechanism
from ...model.compiled import Model
from .target import TargetCurve
from .tracking import DESIGN as FOUR_BAR
from .tracking import CircuitError, TrackedResiduals, TrackingProblem

__all__ = ["SIX_BAR", "KINDS", "SIDES", "SixBarProblem", "six_bar_points"]

#: The design numbers of the six-bar before the crank angles, in the order of y.
SIX_BAR = (*FOUR_BAR, "r5", "r6", "fx", "fy", "px", "py")
#: The six-bars: the dyad's far pin on the ground or on the rocker.
KINDS = ("stephenson", "watt")
#: Which side of C -> F the pin D is on.
SIDES = ("left", "right")
_STEPS = 72
# the points a sweep reads the dyad's transmission angle from, each at its body's frame
# origin (so fixed there whatever y): (name, body, joint)
_PROBES = [("C5", "link5", "C"), ("F6", "link6", "F")]


def six_bar_points(y: Any, theta2: Any, kind: str, circuit: str, side: str) -> dict[str, np.ndarray]:
    """The joints and P of the six-bar ``y`` at crank angles ``theta2``, in closed form
    (each m x 2; NaN where it does not assemble): "O2", "A", "B", "O4", "C", "F", "D",
    "P"."""
    y = np.asarray(y, dtype=float)
    r1, r2, r3, r4, rcx, rcy, th0, x0, y0, r5, r6, fx, fy, px, py = (float(v) for v in y[:15])
    th = np.atleast_1d(np.asarray(theta2, dtype=float))
    c0, s0 = math.cos(th0), math.sin(th0)

    def world(lx: np.ndarray, ly: np.ndarray) -> np.ndarray:
        return np.column_stack([x0 + c0 * lx - s0 * ly, y0 + s0 * lx + c0 * ly])

    ax, ay = r2 * np.cos(th), r2 * np.sin(th)
    dx, dy = r1 - ax, -ay
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        alpha = np.arccos((r3 * r3 + d * d - r4 * r4) / (2.0 * r3 * d))
    t3 = np.arctan2(dy, dx) + (1.0 if circuit == "open" else -1.0) * alpha
    bx, by = ax + r3 * np.cos(t3), ay + r3 * np.sin(t3)
    cx = ax + rcx * np.cos(t3) - rcy * np.sin(t3)
    cy = ay + rcx * np.sin(t3) + rcy * np.cos(t3)
    zero = np.zeros_like(th)
    out = {
        "O2": world(zero, zero),
        "A": world(ax, ay),
        "B": world(bx, by),
        "O4": world(zero + r1, zero),
        "C": world(cx, cy),
    }
    if kind == "stephenson":
        out["F"] = np.column_stack([zero + fx, zero + fy])
    else:
        t4 = np.arctan2(by, bx - r1)
        ex = r1 + fx * np.cos(t4) - fy * np.sin(t4)
        ey = fx * np.sin(t4) + fy * np.cos(t4)
        out["F"] = world(ex, ey)
    c, f = out["C"], out["F"]
    v = f - c
    dist = np.hypot(v[:, 0], v[:, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        along = (r5 * r5 - r6 * r6 + dist * dist) / (2.0 * dist)
        across = np.sqrt(r5 * r5 - along * along) * (1.0 if side == "left" else -1.0)
        e = v / dist[:, None]
    dd = c + along[:, None] * e + across[:, None] * np.column_stack([-e[:, 1], e[:, 0]])
    out["D"] = dd
    t5 = np.arctan2(dd[:, 1] - c[:, 1], dd[:, 0] - c[:, 0])
    out["P"] = c + np.column_stack([px * np.cos(t5) - py * np.sin(t5), px * np.sin(t5) + py * np.cos(t5)])
    return out


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(float(v[1] - u[1]), float(v[0] - u[0]))


class SixBarProblem(TrackedResiduals):
    """The tracking-error problem of a `TargetCurve` for a six-bar of ``kind`` ("watt" or
    "stephenson"), its four-bar on ``circuit`` ("open" or "crossed") and D on ``side``
    ("left" or "right" of C -> F). ``options``: those of `TrackingProblem`, which hold on
    the four-bar (its Grashof type, lengths, transmission angle at B, ratio, regions for
    O2 and O4); ``transmission`` holds at D too, over the traced stretch (at the sweep's
    steps and the crank angles). The dyad's lengths r5, r6 take the length bounds, P's
    place in link5 and E's in the rocker the coupler point's, O6 the pivot's. A region
    for P is not taken here (`SynthesisError`)."""

    size = len(SIX_BAR)

    def __init__(
        self,
        target: TargetCurve,
        kind: str = "stephenson",
        circuit: str = "open",
        side: str = "left",
        **options: Any,
    ) -> None:
        if kind not in KINDS:
            raise SynthesisError(f"a six-bar is one of {', '.join(KINDS)}, not {kind!r}")
        if side not in SIDES:
            raise SynthesisError(f"the dyad's side is 'left' or 'right', not {side!r}")
        if "P" in dict(options.get("regions") or {}):
            raise SynthesisError("a region for P is not taken by the six-bar problem (O2 and O4 are)")
        self.four = TrackingProblem(target, circuit=circuit, **options)
        self.target = target
        self.kind = kind
        self.circuit = circuit
        self.side = side

    @property
    def transmission(self) -> float | None:
        """The stated transmission bound (rad; None: none), held at B and at D."""
        return self.four.transmission

    @property
    def assembly(self) -> str:
        return f"{self.circuit} circuit with D on the {self.side}"

    # ---- the design vector ------------------------------------------------------------
    def four_bar(self, y: Any) -> np.ndarray:
        """The four-bar's design vector of y (its nine numbers and the crank angles)."""
        y = np.asarray(y, dtype=float)
        return np.concatenate([y[:9], y[self.size :]])

    def lower_upper(self) -> tuple[np.ndarray, np.ndarray]:
        lo4, hi4 = self.four.lower_upper()
        assert self.four.lengths and self.four.coupler and self.four.pivot
        far = self.four.pivot if self.kind == "stephenson" else self.four.coupler
        lo = [self.four.lengths[0]] * 2 + [far[0]] * 2 + [self.four.coupler[0]] * 2
        hi = [self.four.lengths[1]] * 2 + [far[1]] * 2 + [self.four.coupler[1]] * 2
        return np.concatenate([lo4[:9], lo, lo4[9:]]), np.concatenate([hi4[:9], hi, hi4[9:]])

    def free(self) -> np.ndarray:
        f4 = self.four.free()
        return np.concatenate([f4[:9], np.ones(6, dtype=bool), f4[9:]])

    def complete(self, y: Any) -> np.ndarray:
        y = np.array(y, dtype=float).reshape(-1)
        if y.shape != (self.size + self.n,):
            raise SynthesisError(
                f"a six-bar design vector here has {self.size + self.n} entries, not {y.size}"
            )
        four = self.four.complete(self.four_bar(y))
        y[:9], y[self.size :] = four[:9], four[9:]
        return y

    def constraint_names(self) -> list[str]:
        dyad = ["transmission at D"] if self.four.transmission is not None else []
        return self.four.constraint_names() + dyad

    def linear_constraints(self) -> np.ndarray:
        """Which entries of `constraints` are linear in y (the four-bar's; not the dyad's)."""
        dyad = len(self.constraint_names()) - len(self.four.constraint_names())
        return np.append(self.four.linear_constraints(), np.zeros(dyad, dtype=bool))

    def constraints(self, y: Any, sweep: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """The four-bar's constraints (`TrackingProblem.constraints`) in y and, with a
        transmission bound, the dyad's at D (|cos mu| over cos(bound), times the
        target's size) with its exact gradient (``sweep``: `_sweep`'s, else run)."""
        y = np.asarray(y, dtype=float)
        g, dg = self.four.constraints(self.four_bar(y))
        dg = np.insert(dg, [9] * 6, 0.0, axis=1) if dg.size else np.zeros((0, self.size + self.n))
        if self.four.transmission is None:
            return g, dg
        value, grad = self._dyad_transmission(y, sweep if sweep is not None else self._sweep(y))
        return np.append(g, value), np.vstack([dg, grad])

    def _dyad_transmission(self, y: np.ndarray, sweep: Any) -> tuple[float, np.ndarray]:
        """The largest |cos mu| at D over the traced stretch above cos(bound), in length
        units, and its exact gradient in y: cos mu = (r5^2 + r6^2 - |C - F|^2) / (2 r5 r6)."""
        assert self.four.transmission is not None
        times, at, _, _, _, probes = sweep
        th = y[self.size :]
        inside = np.ones(times.size, dtype=bool)
        if not self.target.closed and th[-1] - th[0] < 2.0 * math.pi:
            inside = np.mod(times - th[0], 2.0 * math.pi) <= th[-1] - th[0]
        steps = np.flatnonzero(inside)
        (c, dc, vc), (f, df, vf) = probes["C5"], probes["F6"]
        r5, r6 = float(y[9]), float(y[10])
        w = c - f
        cos = (r5 * r5 + r6 * r6 - np.sum(w * w, axis=1)) / (2.0 * r5 * r6)
        k = int(steps[np.argmax(np.abs(cos[steps]))])
        sign = math.copysign(1.0, float(cos[k]))
        # d cos = (r5 dr5 + r6 dr6 - w.(dC - dF)) / (r5 r6) - cos (dr5 / r5 + dr6 / r6)
        grad = np.zeros(y.size)
        grad[: self.size] = -(w[k] @ (dc[k] - df[k])) / (r5 * r6)
        grad[9] += 1.0 / r6 - cos[k] / r5
        grad[10] += 1.0 / r5 - cos[k] / r6
        for i in np.flatnonzero(at == k)[:1]:
            grad[self.size + i] = -(w[k] @ (vc[k] - vf[k])) / (r5 * r6)
        size = self.target.size
        return size * (abs(float(cos[k])) - math.cos(self.four.transmission)), size * sign * grad

    def violation(self, y: Any) -> float:
        g, _ = self.constraints(self.complete(y))
        return float(max(0.0, g.max())) if g.size else 0.0

    def margins(self, y: Any) -> dict[str, float]:
        """The four-bar's margins (`TrackingProblem.margins`) and, with a transmission
        bound, "transmission at D" (rad)."""
        y = self.complete(y)
        out = self.four.margins(self.four_bar(y))
        if self.four.transmission is not None:
            value, _ = self._dyad_transmission(y, self._sweep(y))
            cos = value / self.target.size + math.cos(self.four.transmission)
            out["transmission at D"] = math.acos(min(cos, 1.0)) - self.four.transmission
        return out

    # ---- the model ----------------------------------------------------------------------
    def points(self, y: Any, theta2: Any) -> dict[str, np.ndarray]:
        """`six_bar_points` of this problem's six-bar."""
        return six_bar_points(y, theta2, self.kind, self.circuit, self.side)

    def description(self, y: Any, name: str = "six-bar design", probes: bool = False) -> dict[str, Any]:
        """The design as a model description drawn at theta2 = 0 (closed form): bodies
        crank, coupler, rocker, link5, link6, each framed at its first pin with its x axis
        to the next (link6 at F, towards D); revolutes O2, A, B, O4, C, D and O6
        (Stephenson) or E (Watt); point P on link5; driver crank_angle = theta0 + t, so
        time is theta2. ``probes``: also the points C5 (on link5 at C) and F6 (on link6 at
        F) the dyad's transmission angle is read from. `CircuitError` if it
        does not assemble there."""
        y = self.complete(y)
        pts = {k: v[0] for k, v in self.points(y, [0.0]).items()}
        if not all(np.all(np.isfinite(v)) for v in pts.values()):
            raise CircuitError("the six-bar does not assemble at theta2 = 0")
        far = "O6" if self.kind == "stephenson" else "E"
        frames = {
            "crank": ("O2", "A"),
            "coupler": ("A", "B"),
            "rocker": ("O4", "B"),
            "link5": ("C", "D"),
            "link6": ("F", "D"),
        }
        bodies = [
            {"name": b, "x": float(pts[u][0]), "y": float(pts[u][1]), "theta": _angle(pts[u], pts[v])}
            for b, (u, v) in frames.items()
        ]
        pairs = [
            ("O2", "ground", "crank", "O2"),
            ("A", "crank", "coupler", "A"),
            ("B", "coupler", "rocker", "B"),
            ("O4", "ground", "rocker", "O4"),
            ("C", "coupler", "link5", "C"),
            ("D", "link5", "link6", "D"),
            (far, "ground" if far == "O6" else "rocker", "link6", "F"),
        ]
        joints = [
            {"type": "revolute", "name": n, "body_a": a, "body_b": b, "at": [float(v) for v in pts[at]]}
            for n, a, b, at in pairs
        ]
        return {
            "name": name,
            "bodies": bodies,
            "joints": joints,
            "drivers": [
                {
                    "type": "angle",
                    "name": "crank_angle",
                    "body": "crank",
                    "law": {"type": "linear", "value": float(y[6]), "rate": 1.0},
                }
            ],
            "points": [
                {"name": n, "body": b, "at": [float(v) for v in pts[at]]}
                for n, b, at in [("P", "link5", "P")] + (_PROBES if probes else [])
            ],
        }

    def model(self, y: Any, name: str = "six-bar design") -> Mechanism:
        """The design as a linkwork mechanism (`description`): time is the crank angle theta2."""
        return Mechanism.from_dict(self.description(y, name))

    def grid(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The sweep's times (a crank turn and the crank angles modulo a turn) and the
        step of each crank angle in it."""
        th = np.mod(y[self.size :], 2.0 * math.pi)
        times = np.union1d(np.linspace(0.0, 2.0 * math.pi, _STEPS + 1), th)
        return times, np.searchsorted(times, th)

    def _locals(self, y: np.ndarray) -> list[tuple[str, str, dict[int, tuple[float, float]]]]:
        """Each pin's place in each body that depends on y: (the parameter's name
        without its axis, the body whose frame it is in, {index of y: d local / d y})."""
        r1, th0 = float(y[0]), float(y[6])
        c0, s0 = math.cos(th0), math.sin(th0)
        far = "pivot O6" if self.kind == "stephenson" else "pin E@rocker"
        return [
            ("pivot O2", "ground", {7: (1.0, 0.0), 8: (0.0, 1.0)}),
            ("pivot O4", "ground", {0: (c0, s0), 6: (-r1 * s0, r1 * c0), 7: (1.0, 0.0), 8: (0.0, 1.0)}),
            ("pin A@crank", "crank", {1: (1.0, 0.0)}),
            ("pin B@coupler", "coupler", {2: (1.0, 0.0)}),
            ("pin B@rocker", "rocker", {3: (1.0, 0.0)}),
            ("pin C@coupler", "coupler", {4: (1.0, 0.0), 5: (0.0, 1.0)}),
            ("pin D@link5", "link5", {9: (1.0, 0.0)}),
            ("pin D@link6", "link6", {10: (1.0, 0.0)}),
            (far, "ground" if self.kind == "stephenson" else "rocker", {11: (1.0, 0.0), 12: (0.0, 1.0)}),
            ("point P", "link5", {13: (1.0, 0.0), 14: (0.0, 1.0)}),
        ]

    def _sweep(self, y: np.ndarray) -> tuple[Any, ...]:
        """The engine's sweep over a crank turn (`grid`): the times, the step of each crank
        angle, P at every step (T x 2), d P / d y[:15] (T x 2 x 15), d P / d (the
        driver's start) (T x 2), and with a transmission bound the same three for the
        probes C5, F6 ({name: (position, d / d y[:15], d / d start)}). `CircuitError`
        if it does not assemble or leaves its assembly."""
        pins = self._locals(y)
        names = [f"{p}.{a}" for p, _, _ in pins for a in ("x", "y")] + ["law crank_angle.value"]
        probes = self.four.transmission is not None
        points = ["P"] + ([n for n, _, _ in _PROBES] if probes else [])
        try:
            model = Model(self.description(y, probes=probes))
            times, at = self.grid(y)
            s = model.sensitivities(times, names, points=points, derivatives=0)
        except (SolveError, InputError, ModelError) as e:
            raise CircuitError(f"the six-bar does not assemble over a crank turn: {e}") from None
        p = s.results.point("P").position
        ref = self.points(y, times)["P"]
        scale = max(self.target.size, float(np.max(np.abs(y[: self.size]))))
        miss = float(np.nanmax(np.hypot(*(p - ref).T))) if np.all(np.isfinite(ref)) else math.inf
        if not miss <= 1e-7 * scale:
            raise CircuitError(f"the sweep leaves the six-bar's {self.assembly} (by {miss:.3g})")
        # a pin's world place in the drawing moves its local place by A(theta)^T
        turns = []
        for _, body, _ in pins:
            t = 0.0 if body == "ground" else float(model.q_start[model.columns.index(f"{body}.theta")])
            turns.append((math.cos(t), math.sin(t)))

        def chain(S: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            jd = np.zeros((len(times), 2, self.size))
            for k, ((_, _, grads), (c, sn)) in enumerate(zip(pins, turns)):
                sx, sy = S[:, :, 2 * k], S[:, :, 2 * k + 1]
                du_x, du_y = sx * c + sy * sn, -sx * sn + sy * c
                for i, (gx, gy) in grads.items():
                    jd[:, :, i] += du_x * gx + du_y * gy
            val = S[:, :, -1]
            jd[:, :, 6] += val  # theta0 is the driver's start too
            return jd, val

        jd, val = chain(s.points["P"])
        extra = {}
        for name in points[1:]:
            extra[name] = (s.results.point(name).position, *chain(s.points[name]))
        return times, at, p, jd, val, extra
