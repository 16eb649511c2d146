"""The tracking-error problem of path synthesis (Cabrera, Simon and Prado 2002): a
four-bar's coupler point C must pass the target points P_i at crank angles theta2_i,

    x = [r1, r2, r3, r4, rcx, rcy, theta0, x0, y0, theta2_1 .. theta2_n],
    C(theta2) = R(theta0) [r2 cos theta2 + rcx cos theta3 - rcy sin theta3,
                           r2 sin theta2 + rcx sin theta3 + rcy cos theta3] + [x0, y0],
    f(x) = sum_i |C(theta2_i) - P_i|^2,

r1 the ground O2 -> O4, r2 the crank O2 -> A, r3 the coupler A -> B, r4 the rocker
O4 -> B, (rcx, rcy) the coupler point in the coupler's frame (x along A -> B), theta3 on
one circuit ("open": theta3 = angle(O4 - A) + acos(...), the builder's "open"; "crossed":
minus). With timing prescribed the theta2_i are given; free, they are unknowns,
increasing from the first (within one turn for a closed curve).

Every evaluation builds the design as a linkwork model whose numbers are named parameters
and sweeps it through a whole crank turn: the residuals are the engine's coupler point,
the Jacobian the engine's exact sensitivities (`Model.sensitivities`) carried to x by the
chain rule. The sweep's time is theta2 (the driver turns the crank at unit rate from the
ground line), so dC/dtheta2_i is the point's sensitivity to the driver's start angle. A
design that does not assemble at every crank angle, or whose sweep leaves its circuit,
raises `CircuitError`: the crank of a crank-rocker turns fully on one circuit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import InputError, ModelError, SolveError, SynthesisError
from ...mechanism.builder import Mechanism
from ...model.compiled import Model
from .target import TargetCurve

__all__ = ["CircuitError", "TrackingProblem", "DESIGN", "coupler_points"]

#: The design numbers before the crank angles, in the order of the vector x.
DESIGN = ("r1", "r2", "r3", "r4", "rcx", "rcy", "theta0", "x0", "y0")
TWO_PI = 2.0 * math.pi
# the model's parameters, named as in linkwork.study.naming
_ENGINE = (
    "pivot O2.x",
    "pivot O2.y",
    "pivot O4.x",
    "pivot O4.y",
    "length crank",
    "length coupler",
    "length rocker",
    "point P.x",
    "point P.y",
    "law crank_angle.value",
)
# sweep steps per crank turn: small enough for the engine to keep its circuit
_STEPS = 72


class CircuitError(SynthesisError):
    """A four-bar design that cannot be scored: its sweep over a crank turn does not
    assemble, meets a dead point or leaves its circuit."""


def coupler_points(x: Any, theta2: Any, circuit: str = "open") -> np.ndarray:
    """The closed form C(theta2) of the module docstring (n x 2; NaN where the four-bar
    does not assemble)."""
    r1, r2, r3, r4, rcx, rcy, th0, x0, y0 = (float(v) for v in np.asarray(x, dtype=float)[:9])
    th = np.asarray(theta2, dtype=float)
    ax, ay = r2 * np.cos(th), r2 * np.sin(th)
    dx, dy = r1 - ax, -ay
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        alpha = np.arccos((r3 * r3 + d * d - r4 * r4) / (2.0 * r3 * d))
    t3 = np.arctan2(dy, dx) + (1.0 if circuit == "open" else -1.0) * alpha
    cx = ax + rcx * np.cos(t3) - rcy * np.sin(t3)
    cy = ay + rcx * np.sin(t3) + rcy * np.cos(t3)
    c, s = math.cos(th0), math.sin(th0)
    return np.column_stack([x0 + c * cx - s * cy, y0 + s * cx + c * cy])


def _bounds(name: str, value: Any, default: tuple[float, float]) -> tuple[float, float]:
    try:
        lo, hi = default if value is None else (float(value[0]), float(value[1]))
    except (TypeError, ValueError, IndexError):
        raise SynthesisError(f"{name} bounds are (lower, upper) numbers, not {value!r}") from None
    if math.isnan(lo) or math.isnan(hi):
        raise SynthesisError(f"{name} bounds must be numbers, got {value!r}")
    if lo > hi:
        raise SynthesisError(f"contradictory {name} bounds: lower {lo} > upper {hi}")
    return lo, hi


@dataclass
class TrackingProblem:
    """The tracking-error problem for a `TargetCurve` on one ``circuit`` ("open" or
    "crossed"). ``lengths``: (lower, upper) for r1..r4 (default 1e-3 to 10 times the
    target's size); ``coupler``: for rcx, rcy (default +-10 sizes); ``pivot``: for x0, y0
    (default the target's box grown by 10 sizes); ``fixed``: {"theta0": v, "x0": v,
    "y0": v} held (Cabrera's timed problem fixes all three at 0); ``ordered``: also require
    r2 <= r3 <= r4 <= r1. The crank is always the shortest link and turns fully on the
    circuit (a Grashof crank-rocker)."""

    target: TargetCurve
    circuit: str = "open"
    lengths: tuple[float, float] | None = None
    coupler: tuple[float, float] | None = None
    pivot: tuple[float, float] | None = None
    fixed: Mapping[str, float] = field(default_factory=dict)
    ordered: bool = False

    def __post_init__(self) -> None:
        if self.circuit not in ("open", "crossed"):
            raise SynthesisError(f"circuit is 'open' or 'crossed', not {self.circuit!r}")
        self.target.require(3 if self.target.timed else 4, "the tracking-error problem")
        size = self.target.size
        self.lengths = _bounds("length", self.lengths, (1e-3 * size, 10.0 * size))
        if self.lengths[0] <= 0.0:
            raise SynthesisError(f"link lengths must be > 0: lower bound {self.lengths[0]}")
        self.coupler = _bounds("coupler point", self.coupler, (-10.0 * size, 10.0 * size))
        lo = float(self.target.points.min()) - 10.0 * size
        hi = float(self.target.points.max()) + 10.0 * size
        self.pivot = _bounds("pivot", self.pivot, (lo, hi))
        bad = set(self.fixed) - {"theta0", "x0", "y0"}
        if bad:
            raise SynthesisError(f"only theta0, x0, y0 can be fixed, not {', '.join(sorted(bad))}")
        self.fixed = {k: float(v) for k, v in self.fixed.items()}

    # ---- the design vector ------------------------------------------------------------
    @property
    def n(self) -> int:
        return len(self.target)

    def lower_upper(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounds on the full vector x (the crank angles: [0, 2 pi) for the first, then
        within the turns their count allows)."""
        assert self.lengths and self.coupler and self.pivot
        lo = [self.lengths[0]] * 4 + [self.coupler[0]] * 2 + [-TWO_PI] + [self.pivot[0]] * 2
        hi = [self.lengths[1]] * 4 + [self.coupler[1]] * 2 + [TWO_PI] + [self.pivot[1]] * 2
        return np.array(lo + [-np.inf] * self.n), np.array(hi + [np.inf] * self.n)

    def free(self) -> np.ndarray:
        """Which entries of x the refinement moves."""
        mask = np.ones(9 + self.n, dtype=bool)
        for k in self.fixed:
            mask[DESIGN.index(k)] = False
        if self.target.timed:
            mask[9:] = False
        return mask

    def complete(self, x: Any) -> np.ndarray:
        """x with the fixed entries (and prescribed crank angles) set."""
        x = np.array(x, dtype=float).reshape(-1)
        if x.shape != (9 + self.n,):
            raise SynthesisError(f"a design vector here has {9 + self.n} entries, not {x.size}")
        for k, v in self.fixed.items():
            x[DESIGN.index(k)] = v
        if self.target.crank_angles is not None:
            x[9:] = self.target.crank_angles
        return x

    def constraints(self, x: np.ndarray) -> np.ndarray:
        """g(x) <= 0: the crank the shortest link (and, ``ordered``, r3 <= r4 <= r1); for a
        closed curve the crank angles within one turn."""
        r1, r2, r3, r4 = x[:4]
        g = [r2 - r1, r2 - r3, r2 - r4]
        if self.ordered:
            g += [r3 - r4, r4 - r1]
        if self.target.closed and not self.target.timed:
            g.append(x[-1] - x[9] - TWO_PI)
        return np.array(g)

    def violation(self, x: Any) -> float:
        """Largest constraint violation (length units; 0 when every constraint holds)."""
        return float(max(0.0, self.constraints(self.complete(x)).max()))

    # ---- the model ----------------------------------------------------------------------
    def description(self, x: Any, name: str = "four-bar design") -> dict[str, Any]:
        """The design as a model description drawn at theta2 = 0 on its circuit (the
        closed form places the bodies, so the engine need not assemble it): bodies crank,
        coupler, rocker, each framed at its first pin with its x axis to the next;
        revolutes O2, A, B, O4; point P; driver crank_angle = theta0 + t, so time is
        theta2. `CircuitError` if it does not assemble there."""
        x = self.complete(x)
        r1, r2, r3, r4, rcx, rcy, th0, x0, y0 = (float(v) for v in x[:9])
        c0, s0 = math.cos(th0), math.sin(th0)
        o2, o4 = (x0, y0), (x0 + r1 * c0, y0 + r1 * s0)
        a = (x0 + r2 * c0, y0 + r2 * s0)
        # the coupler's world angle from two coupler points in closed form: A and A + r3 e3
        probe = np.array(x[:9], dtype=float)
        probe[4:6] = (r3, 0.0)
        b = coupler_points(probe, [0.0], self.circuit)[0]
        p = coupler_points(x, [0.0], self.circuit)[0]
        if not (np.all(np.isfinite(b)) and np.all(np.isfinite(p))):
            raise CircuitError("the design does not assemble at theta2 = 0")
        t3 = math.atan2(b[1] - a[1], b[0] - a[0])
        t4 = math.atan2(b[1] - o4[1], b[0] - o4[0])
        rev = lambda n, u, v, at: {"type": "revolute", "name": n, "body_a": u, "body_b": v, "at": list(at)}  # noqa: E731
        return {
            "name": name,
            "bodies": [
                {"name": "crank", "x": o2[0], "y": o2[1], "theta": th0},
                {"name": "coupler", "x": a[0], "y": a[1], "theta": t3},
                {"name": "rocker", "x": o4[0], "y": o4[1], "theta": t4},
            ],
            "joints": [
                rev("O2", "ground", "crank", o2),
                rev("A", "crank", "coupler", a),
                rev("B", "coupler", "rocker", (float(b[0]), float(b[1]))),
                rev("O4", "ground", "rocker", o4),
            ],
            "drivers": [
                {
                    "type": "angle",
                    "name": "crank_angle",
                    "body": "crank",
                    "law": {"type": "linear", "value": th0, "rate": 1.0},
                }
            ],
            "points": [{"name": "P", "body": "coupler", "at": [float(p[0]), float(p[1])]}],
        }

    def model(self, x: Any, name: str = "four-bar design") -> Mechanism:
        """The design as a linkwork mechanism (`description`): time is the crank angle theta2."""
        return Mechanism.from_dict(self.description(x, name))

    def grid(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The sweep's times (a whole crank turn and the crank angles, taken modulo a
        turn: C is periodic in theta2) and the step of each crank angle in it."""
        th = np.mod(x[9:], TWO_PI)
        times = np.union1d(np.linspace(0.0, TWO_PI, _STEPS + 1), th)
        return times, np.searchsorted(times, th)

    def evaluate(self, x: Any) -> tuple[np.ndarray, np.ndarray]:
        """The residuals C(theta2_i) - P_i (2n: x1, y1, x2, ...) and their exact Jacobian
        with respect to the full x (2n x (9 + n)), from the engine. `CircuitError` if the
        design does not turn fully on its circuit."""
        x = self.complete(x)
        r1, th0 = x[0], x[6]
        try:
            model = Model(self.description(x))
            times, at = self.grid(x)
            s = model.sensitivities(times, _ENGINE, points=["P"], derivatives=0)
        except (SolveError, InputError, ModelError) as e:
            # the builder's assembly refuses a design with no configuration on the circuit
            raise CircuitError(f"the design does not assemble over a crank turn: {e}") from None
        p = s.results.point("P").position
        # the engine's branch tracking must have stayed on the circuit asked
        ref = coupler_points(x, times, self.circuit)
        miss = float(np.nanmax(np.hypot(*(p - ref).T))) if np.all(np.isfinite(ref)) else math.inf
        if not miss <= 1e-7 * max(self.target.size, float(np.max(x[:4]))):
            raise CircuitError(f"the sweep leaves the {self.circuit} circuit (by {miss:.3g})")
        S = s.points["P"][at]  # n x 2 x 10
        o2x, o2y, o4x, o4y, lc, lk, lr, px, py, val = (S[:, :, k] for k in range(10))
        # "point P.x" moves P in world coordinates of the drawing: rotate to the coupler's frame
        t3 = float(model.q_start[model.columns.index("coupler.theta")])
        c3, s3 = math.cos(t3), math.sin(t3)
        c0, s0 = math.cos(th0), math.sin(th0)
        cols = [
            o4x * c0 + o4y * s0,  # r1: O4 = O2 + r1 (cos theta0, sin theta0)
            lc,
            lk,
            lr,
            px * c3 + py * s3,
            -px * s3 + py * c3,
            val + r1 * (-o4x * s0 + o4y * c0),  # theta0 turns the crank's start and O4
            o2x + o4x,
            o2y + o4y,
        ]
        n = self.n
        jac = np.zeros((n, 2, 9 + n))
        for k, col in enumerate(cols):
            jac[:, :, k] = col
        jac[np.arange(n), :, 9 + np.arange(n)] = val  # d C / d theta2_i: the driver's start
        return (p[at] - self.target.points).reshape(-1), jac.reshape(2 * n, 9 + n)

    def objective(self, x: Any) -> float:
        """f(x) = sum_i |C(theta2_i) - P_i|^2, from the engine."""
        r, _ = self.evaluate(x)
        return float(r @ r)
