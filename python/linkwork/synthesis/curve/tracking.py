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
from . import constraints as K
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


class TrackedResiduals:
    """The residuals of a tracking problem and their exact Jacobian, shared by the
    four-bar's (`TrackingProblem`) and the six-bar's problem: each has ``size`` design
    numbers before the crank angles, ``target``, ``complete``, ``constraints`` and
    ``_sweep`` (its engine sweep: times, the index of each target point among them, the
    traced points, their Jacobian in the design numbers, their rate in the crank angle,
    then anything else)."""

    size: int
    target: TargetCurve

    @property
    def n(self) -> int:
        return len(self.target)

    def evaluate_all(self, x: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """`evaluate`'s residuals and Jacobian and `constraints`' values and Jacobian,
        from one sweep."""
        x = self.complete(x)  # type: ignore[attr-defined]
        sweep = self._sweep(x)  # type: ignore[attr-defined]
        r, jac = self._tracking(x, sweep)
        g, dg = self.constraints(x, sweep)  # type: ignore[attr-defined]
        return r, jac, g, dg

    def evaluate(self, x: Any) -> tuple[np.ndarray, np.ndarray]:
        """The residuals P(theta2_i) - P_i (2n: x1, y1, x2, ...) and their exact Jacobian
        with respect to the full vector (2n x (size + n)), from the engine. `CircuitError`
        if the design does not turn fully on its circuit."""
        x = self.complete(x)  # type: ignore[attr-defined]
        return self._tracking(x, self._sweep(x))  # type: ignore[attr-defined]

    def _tracking(self, x: np.ndarray, sweep: Any) -> tuple[np.ndarray, np.ndarray]:
        _, at, p, jd, val = sweep[:5]
        n, m = self.n, self.size
        jac = np.zeros((n, 2, m + n))
        jac[:, :, :m] = jd[at]
        jac[np.arange(n), :, m + np.arange(n)] = val[at]  # d P / d theta2_i: the driver's start
        return (p[at] - self.target.points).reshape(-1), jac.reshape(2 * n, m + n)

    def objective(self, x: Any) -> float:
        """f(x) = sum_i |P(theta2_i) - P_i|^2, from the engine."""
        r, _ = self.evaluate(x)
        return float(r @ r)


@dataclass
class TrackingProblem(TrackedResiduals):
    """The tracking-error problem for a `TargetCurve` on one ``circuit`` ("open" or
    "crossed"). ``lengths``: (lower, upper) for r1..r4 (default 1e-3 to 10 times the
    target's size); ``coupler``: for rcx, rcy (default +-10 sizes); ``pivot``: for x0, y0
    (default the target's box grown by 10 sizes); ``fixed``: {"theta0": v, "x0": v,
    "y0": v} held (Cabrera's timed problem fixes all three at 0); ``ordered``: also require
    r2 <= r3 <= r4 <= r1. The crank turns fully on the circuit.

    The designer's constraints (`linkwork.synthesis.curve.constraints`): ``grashof``
    ("crank-rocker": the crank the shortest link, the default; "double-crank": the ground
    the shortest; "full-turn": either); ``transmission``: the smallest transmission angle
    over the traced stretch ("40 deg", "0.7 rad" or rad); ``links``: {"r1": (lo, hi),
    ...} ranges of single links (bounds); ``ratio``: (lo, hi) of the longest link over
    the shortest; ``regions``: {"O2" | "O4" | "P": a box {"x": (lo, hi), "y": (lo, hi)}
    or a disc {"centre": (x, y), "radius": r}}, P's region holding over the traced
    stretch (at the sweep's steps and the crank angles). Contradictory constraints raise
    `SynthesisError` naming them."""

    target: TargetCurve
    circuit: str = "open"
    lengths: tuple[float, float] | None = None
    coupler: tuple[float, float] | None = None
    pivot: tuple[float, float] | None = None
    fixed: Mapping[str, float] = field(default_factory=dict)
    ordered: bool = False
    grashof: str = "crank-rocker"
    transmission: Any = None
    links: Mapping[str, Any] = field(default_factory=dict)
    ratio: Any = None
    regions: Mapping[str, Any] = field(default_factory=dict)

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
        self._designer_constraints()

    def _designer_constraints(self) -> None:
        """Check and normalise the designer's constraints; contradictions are named."""
        assert self.lengths is not None
        if self.grashof not in K.GRASHOF:
            raise SynthesisError(f"grashof is one of {', '.join(K.GRASHOF)}, not {self.grashof!r}")
        if self.ordered and self.grashof != "crank-rocker":
            raise SynthesisError(
                f"contradictory constraints: ordered (r2 <= r3 <= r4 <= r1) makes the crank the "
                f"shortest link, a crank-rocker, not grashof {self.grashof!r}"
            )
        bound = None
        if self.transmission is not None:
            bound = K.angle("transmission", self.transmission)
            if bound < 0.0 or bound > math.pi / 2:
                raise SynthesisError(
                    f"contradictory transmission bound {self.transmission!r} "
                    f"({math.degrees(bound):.6g} deg): a transmission angle is at most 90 degrees "
                    "from 0 or 180 (state the unit: '40 deg')"
                )
        self.transmission = bound
        links = {}
        for name, value in dict(self.links).items():
            if name not in DESIGN[:4]:
                raise SynthesisError(f"links ranges are for r1, r2, r3, r4, not {name!r}")
            lo, hi = _bounds(f"link {name}", value, self.lengths)
            lo, hi = max(lo, self.lengths[0]), min(hi, self.lengths[1])
            if lo > hi:
                raise SynthesisError(
                    f"contradictory range of link {name}: {list(value)} outside the lengths' "
                    f"bounds {list(self.lengths)}"
                )
            links[name] = (lo, hi)
        self.links = links
        if self.ratio is not None:
            lo, hi = _bounds("ratio (longest / shortest link)", self.ratio, (1.0, math.inf))
            if hi < 1.0:
                raise SynthesisError(
                    f"contradictory ratio: the longest link over the shortest is >= 1, not <= {hi}"
                )
            if lo > self.lengths[1] / self.lengths[0]:
                raise SynthesisError(
                    f"contradictory constraints: ratio >= {lo} with lengths within {list(self.lengths)}"
                )
            self.ratio = (lo, hi)
        regions = {}
        for name, value in dict(self.regions).items():
            if name not in K.PLACES:
                raise SynthesisError(f"regions are for {', '.join(K.PLACES)}, not {name!r}")
            regions[name] = K.region(name, value)
        self.regions = regions
        xlo, xhi = self.lower_upper()
        if np.any(xlo[7:9] > xhi[7:9]):
            raise SynthesisError(
                f"contradictory constraints: the region of O2 ({regions['O2']}) is outside "
                f"the pivot bounds {list(self.pivot or ())}"
            )
        if "O2" in regions and {"x0", "y0"} <= set(self.fixed):
            out, _ = regions["O2"].outside(np.array([self.fixed["x0"], self.fixed["y0"]]))
            if out[0] > 0.0:
                raise SynthesisError(
                    f"contradictory constraints: O2 is fixed outside its region ({regions['O2']})"
                )

    # ---- the design vector ------------------------------------------------------------
    #: how many design numbers come before the crank angles in x
    size = len(DESIGN)

    @property
    def assembly(self) -> str:
        return f"{self.circuit} circuit"

    def lower_upper(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounds on the full vector x (the crank angles: [0, 2 pi) for the first, then
        within the turns their count allows)."""
        assert self.lengths and self.coupler and self.pivot
        lo = [self.lengths[0]] * 4 + [self.coupler[0]] * 2 + [-TWO_PI] + [self.pivot[0]] * 2
        hi = [self.lengths[1]] * 4 + [self.coupler[1]] * 2 + [TWO_PI] + [self.pivot[1]] * 2
        for name, (a, b) in self.links.items():
            k = DESIGN.index(name)
            lo[k], hi[k] = a, b
        box = self.regions.get("O2")
        if box is not None and box.x is not None and box.y is not None:
            # a box for O2 bounds x0 and y0 themselves: held exactly
            for k, (a, b) in ((7, box.x), (8, box.y)):
                lo[k], hi[k] = max(lo[k], a), min(hi[k], b)
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

    def constraint_names(self) -> list[str]:
        """The name of each entry of `constraints`, in order."""
        names = []
        if self.grashof == "crank-rocker":
            names += [f"crank shortest (r2 <= {k})" for k in ("r1", "r3", "r4")]
        elif self.grashof == "double-crank":
            names += [f"ground shortest (r1 <= {k})" for k in ("r2", "r3", "r4")]
        names.append("grashof (s + l <= p + q)")
        if self.ordered:
            names += ["ordered (r3 <= r4)", "ordered (r4 <= r1)"]
        if self.target.closed and not self.target.timed:
            names.append("within one turn")
        if self.ratio is not None:
            names += ["ratio upper", "ratio lower"]
        if self.transmission is not None:
            names.append("transmission")
        names += [f"region {k}" for k in self.regions]
        return names

    def linear_constraints(self) -> np.ndarray:
        """Which entries of `constraints` are linear in x (near the current design: the
        Grashof row's ordering of the links held): the link orderings, Grashof, the one
        turn and the ratio; not the transmission or the regions."""
        names = self.constraint_names()
        nonlinear = {"transmission"} | {f"region {k}" for k in self.regions}
        return np.array([k not in nonlinear for k in names], dtype=bool)

    def grashof_pieces(self, x: Any, band: float) -> tuple[np.ndarray, np.ndarray]:
        """s + l - p - q for every choice of s (the link the Grashof type makes shortest,
        else any within ``band`` of the shortest) and l (any within ``band`` of the
        longest), and their gradients in x: where links tie (a parallelogram) several are
        the Grashof row at once, and each is a wall the crank cannot turn past."""
        x = np.asarray(x, dtype=float)
        r = x[:4]
        shortest = {"crank-rocker": [1], "double-crank": [0]}.get(self.grashof)
        if shortest is None:
            shortest = list(np.flatnonzero(r <= r.min() + band))
        vals, grads = [], []
        for s_ in shortest:
            for l_ in np.flatnonzero(r >= r.max() - band):
                if l_ == s_:
                    continue
                g = -np.ones(x.size)
                g[4:] = 0.0
                g[[s_, l_]] = 1.0
                vals.append(float(g[:4] @ r))
                grads.append(g)
        return np.array(vals), np.array(grads).reshape(len(vals), x.size)

    def constraints(self, x: Any, sweep: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """g(x) <= 0 (`constraint_names`; length units: the transmission's |cos mu| excess
        times the target's size, the one-turn entry in rad) and its exact Jacobian in the
        full x. P's region needs the engine's sweep (``sweep``: `_sweep`'s, else run)."""
        x = np.asarray(x, dtype=float)
        r = x[:4]
        rows: list[tuple[float, np.ndarray]] = []

        def lin(coef: dict[int, float], value: float) -> None:
            g = np.zeros(x.size)
            for k, v in coef.items():
                g[k] += v
            rows.append((value, g))

        short = {"crank-rocker": 1, "double-crank": 0}.get(self.grashof)
        if short is not None:
            for k in (0, 2, 3) if short == 1 else (1, 2, 3):
                lin({short: 1.0, k: -1.0}, float(r[short] - r[k]))
        order = np.argsort(r, kind="stable")
        s_, p_, q_, l_ = order
        lin({s_: 1.0, l_: 1.0, p_: -1.0, q_: -1.0}, float(r[s_] + r[l_] - r[p_] - r[q_]))
        if self.ordered:
            lin({2: 1.0, 3: -1.0}, float(r[2] - r[3]))
            lin({3: 1.0, 0: -1.0}, float(r[3] - r[0]))
        if self.target.closed and not self.target.timed:
            lin({x.size - 1: 1.0, 9: -1.0}, float(x[-1] - x[9] - TWO_PI))
        if self.ratio is not None:
            lo, hi = self.ratio
            if math.isfinite(hi):
                lin({l_: 1.0, s_: -hi}, float(r[l_] - hi * r[s_]))
            else:
                lin({}, -math.inf)
            lin({s_: lo, l_: -1.0}, float(lo * r[s_] - r[l_]))
        if self.transmission is not None:
            mu, dmu = K.smallest_transmission(x, self.target.closed)
            # |cos mu| above cos(bound), in length units: d|cos mu| = -sin mu d mu
            size = self.target.size
            rows.append((size * (math.cos(mu) - math.cos(self.transmission)), -size * math.sin(mu) * dmu))
        for name, reg in self.regions.items():
            if name == "P":
                rows.append(self._coupler_region(x, reg, sweep))
                continue
            r1, th0 = x[0], x[6]
            c, s = math.cos(th0), math.sin(th0)
            pt = np.array([x[7], x[8]]) + (r1 * np.array([c, s]) if name == "O4" else 0.0)
            out, grad = reg.outside(pt)
            g = np.zeros(x.size)
            g[7:9] = grad[0]
            if name == "O4":
                g[0] = grad[0] @ [c, s]
                g[6] = grad[0] @ [-r1 * s, r1 * c]
            rows.append((float(out[0]), g))
        if not rows:
            return np.zeros(0), np.zeros((0, x.size))
        vals = np.array([v for v, _ in rows])
        vals[np.isneginf(vals)] = -1.0  # an unbounded side never binds
        return vals, np.array([g for _, g in rows])

    def _coupler_region(self, x: np.ndarray, reg: K.Region, sweep: Any) -> tuple[float, np.ndarray]:
        """The largest distance of P outside its region over the traced stretch (the
        sweep's steps inside it and the crank angles), with its exact gradient."""
        times, at, p, jd, val = self._sweep(x) if sweep is None else sweep
        th = x[9:]
        inside = np.ones(times.size, dtype=bool)
        if not self.target.closed and th[-1] - th[0] < TWO_PI:
            inside = np.mod(times - th[0], TWO_PI) <= th[-1] - th[0]
        steps = np.flatnonzero(inside)
        out, grad = reg.outside(p[steps])
        k = int(np.argmax(out))
        g = np.zeros(x.size)
        g[:9] = grad[k] @ jd[steps[k]]
        # a crank angle's sample moves with that angle: the driver's start sensitivity
        for i in np.flatnonzero(at == steps[k])[:1]:
            g[9 + i] = grad[k] @ val[steps[k]]
        return float(out[k]), g

    def violation(self, x: Any) -> float:
        """Largest constraint violation (length units; 0 when every constraint holds)."""
        g, _ = self.constraints(self.complete(x))
        return float(max(0.0, g.max())) if g.size else 0.0

    def margins(self, x: Any) -> dict[str, float]:
        """Each stated constraint's margin (>= 0 when it holds; negative: violated by
        that much): "transmission" in rad, "ratio" in the ratio, the Grashof type, the
        ordering, the link ranges and the regions in length units."""
        x = self.complete(x)
        r = x[:4]
        out: dict[str, float] = {}
        s = np.sort(r)
        grashof = float(s[1] + s[2] - s[0] - s[3])
        if self.grashof != "full-turn":
            k = 1 if self.grashof == "crank-rocker" else 0
            grashof = min(grashof, float(np.delete(r, k).min() - r[k]))
        out[f"grashof {self.grashof}"] = grashof
        if self.ordered:
            out["ordered"] = float(min(r[2] - r[1], r[3] - r[2], r[0] - r[3]))
        for name, (lo, hi) in self.links.items():
            v = float(x[DESIGN.index(name)])
            out[f"link {name}"] = min(v - lo, hi - v)
        if self.ratio is not None:
            ratio = float(s[3] / s[0])
            out["ratio"] = min(ratio - self.ratio[0], self.ratio[1] - ratio)
        if self.transmission is not None:
            out["transmission"] = K.smallest_transmission(x, self.target.closed)[0] - self.transmission
        if self.regions:
            g, _ = self.constraints(x)
            names = self.constraint_names()
            for place in self.regions:
                out[f"region {place}"] = -float(g[names.index(f"region {place}")])
        return out

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

    def _sweep(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The engine's sweep of the design over a crank turn (`grid`): the times, the
        step of each crank angle, P at every step (T x 2), d P / d x[:9] (T x 2 x 9) and
        d P / d (the driver's start) (T x 2). `CircuitError` off the circuit."""
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
        S = s.points["P"]  # T x 2 x 10
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
        return times, at, p, np.stack(cols, axis=-1), val
