"""The exact problems: `motion` (2 to 5 poses, Burmester), `path` (5 timed points),
`function` (Freudenstein, with `chebyshev` spacing) and `nine_points` (Alt's problem)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from ..errors import SynthesisError
from ..mechanism.builder import Mechanism
from ..motion import Linear
from .designs import MERIT, Curves, FourBarDesign, Synthesis, _merit, _pair_designs
from .dyad import Dyad, DyadSolutions, _angles, _array, dyads

__all__ = [
    "motion",
    "path",
    "chebyshev",
    "SliderCrankDesign",
    "function",
    "FunctionFourBar",
    "NinePointResult",
    "nine_points",
]


def motion(
    poses: Any,
    moving: Any = None,
    ground: Any = None,
    along: Sequence[float] = (0.0, 0.0),
    samples: int = 360,
    angles: str = "rad",
) -> Synthesis:
    """Motion generation through 2 to 5 poses (rows x, y, angle; the pose's reference
    point is the coupler point P of the designs).

    5 poses: every Burmester dyad and every four-bar pairing two real ones (either as
    input). 4: `Curves` sampled along ``samples`` rays. 3: give two moving pivots
    (``moving``, 2 x 2, world at pose 1) or two ground pivots (``ground``). 2: two moving
    pivots; ground pivots on their bisectors, ``along`` from the midpoints.
    """
    p = _array(poses, "poses", 3).copy()
    p[:, 2] = _angles(p[:, 2], angles, "pose angles")
    n = len(p)
    positions = p[:, :2]
    rot = p[:, 2] - p[0, 2]
    if n == 5:
        sols = DyadSolutions._from_raw(
            _core.synth_dyads("burmester", "homotopy", p.ravel().tolist()), "homotopy"
        )
        designs = _pair_designs(sols.real, positions, rot, None)
        designs.sort(key=_merit)
        return Synthesis("motion generation, 5 poses (Burmester)", sols, designs)
    if n == 4:
        raw = _core.synth_motion("four_curves", p.ravel().tolist(), [], 0.0, int(samples))
        return Synthesis(
            "motion generation, 4 poses (Burmester curves)",
            DyadSolutions._from_raw(raw, "closed form"),
            [],
            Curves(np.array(raw["moving"]).reshape(-1, 2), np.array(raw["ground"]).reshape(-1, 2)),
        )
    if n in (2, 3):
        if (moving is None) == (ground is None) or (n == 2 and moving is None):
            need = "moving=(2 x 2)" if n == 2 else "moving=(2 x 2) or ground=(2 x 2)"
            raise SynthesisError(f"{n} poses leave free choices: give {need}, one point per dyad")
        chosen = _array(
            moving if moving is not None else ground, "moving" if moving is not None else "ground", 2
        )
        if len(chosen) != 2:
            raise SynthesisError("give exactly two points, one per dyad")
        out = []
        for k in range(2):
            if n == 3:
                kind = "three_ground" if moving is not None else "three_moving"
                raw = _core.synth_motion(kind, p.ravel().tolist(), chosen[k].tolist())
            else:
                raw = _core.synth_motion(
                    "two_ground", p.ravel().tolist(), chosen[k].tolist(), float(along[k])
                )
            out.append(DyadSolutions._from_raw(raw, "closed form").dyads[0])
        sols = DyadSolutions(out, "closed form")
        designs = [
            FourBarDesign(
                out[0].ground,
                out[0].moving,
                out[1].ground,
                out[1].moving,
                positions[0],
                positions,
                rot,
                None,
                (out[0], out[1]),
            )
        ]
        return Synthesis(f"motion generation, {n} poses", sols, designs)
    raise SynthesisError(f"motion generation takes 2 to 5 poses for the exact methods; got {n}")


def path(points: Any, input_angles: Any, angles: str = "rad") -> Synthesis:
    """Path generation with prescribed timing: the coupler point through 5 ``points``
    while the crank turns by ``input_angles`` (from position 1). Every input dyad, each
    completed by the Burmester dyads of the coupler motion it implies."""
    pts = _array(points, "points", 2)
    a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
    first = dyads("timed", points=pts, input_angles=a)
    designs: list[FourBarDesign] = []
    followers = []
    for d in first.real:
        # coupler rotations implied by this input dyad
        g, a1, p1 = complex(*d.ground), complex(*d.moving), complex(*pts[0])
        a_j = g + (a1 - g) * np.exp(1j * (a - a[0]))
        theta = np.angle((pts[:, 0] + 1j * pts[:, 1] - a_j) / (p1 - a1))
        poses = np.column_stack([pts, theta])
        f = dyads("burmester", poses=poses)
        followers.append(f)
        others = [
            b
            for b in f.real
            if not (np.allclose(b.ground, d.ground, atol=1e-7) and np.allclose(b.moving, d.moving, atol=1e-7))
        ]
        designs += _pair_designs(others, pts, theta, a, first=d)
    designs.sort(key=_merit)
    return Synthesis("path generation with prescribed timing, 5 points", [first, *followers], designs)


def chebyshev(lo: float, hi: float, n: int = 3) -> np.ndarray:
    """Chebyshev spacing of ``n`` precision points on [lo, hi]."""
    return np.array(_core.synth_chebyshev(float(lo), float(hi), int(n)))


@dataclass
class SliderCrankDesign:
    """A slider-crank from Freudenstein's equation: crank ``a`` about (0, 0), rod ``b``,
    slider on y = ``e`` (position s along x)."""

    a: float
    b: float
    e: float


def function(input_angles: Any, output: Any, kind: str = "four_bar", ground: float = 1.0) -> Any:
    """Freudenstein function generation through exactly 3 precision pairs.

    ``kind`` "four_bar": ``output`` the rocker angles (rad), ground pivots (0, 0) and
    (``ground``, 0); returns a `FunctionFourBar`. "slider_crank": ``output`` the slider
    positions; returns a `SliderCrankDesign`. Place the pairs with `chebyshev`.
    """
    phi = _array(input_angles, "input_angles", 1)
    out = _array(output, "output", 1)
    if kind == "four_bar":
        a, b, c, d = _core.synth_freudenstein("four_bar", phi.tolist(), out.tolist(), float(ground))
        return FunctionFourBar(a, b, c, d, phi.copy(), out.copy())
    if kind == "slider_crank":
        a, b, e = _core.synth_freudenstein("slider_crank", phi.tolist(), out.tolist(), 0.0)
        return SliderCrankDesign(a, b, e)
    raise SynthesisError(f"kind must be 'four_bar' or 'slider_crank', not {kind!r}")


@dataclass
class FunctionFourBar:
    """A four-bar function generator from Freudenstein's equation: ground pivots (0, 0)
    and (d, 0); signed crank ``a`` and rocker ``c`` (a negative one points the other way
    at the same angle), coupler ``b``; ``pairs_in`` / ``pairs_out``: the precision pairs."""

    a: float
    b: float
    c: float
    d: float
    pairs_in: np.ndarray
    pairs_out: np.ndarray

    def model(self, name: str = "function generator") -> Mechanism:
        """The generator at the first precision pair; driver "crank_angle": the crank's
        input angle phi = t (rad), so a sweep over phi is a sweep over t."""
        phi1, psi1 = float(self.pairs_in[0]), float(self.pairs_out[0])
        a1 = self.a * complex(math.cos(phi1), math.sin(phi1))
        o4 = complex(self.d, 0.0)
        b1 = o4 + self.c * complex(math.cos(psi1), math.sin(psi1))
        m = Mechanism(name)
        crank = m.body("crank", (0.0, 0.0), math.atan2(a1.imag, a1.real))
        coupler = m.body("coupler", (a1.real, a1.imag), math.atan2((b1 - a1).imag, (b1 - a1).real))
        rocker = m.body("rocker", (self.d, 0.0), math.atan2((b1 - o4).imag, (b1 - o4).real))
        m.revolute(m.ground, crank, (0.0, 0.0), name="O2")
        m.revolute(crank, coupler, (a1.real, a1.imag), name="A")
        m.revolute(coupler, rocker, (b1.real, b1.imag), name="B")
        m.revolute(m.ground, rocker, (self.d, 0.0), name="O4")
        m.drive_angle(crank, Linear(math.atan2(a1.imag, a1.real) - phi1, 1.0), name="crank_angle")
        return m

    def output(self, input_angles: Any) -> np.ndarray:
        """The rocker angle psi the generator gives at each input angle (by the engine,
        on the circuit of the first precision pair); raises `SolveError` (with
        ``.partial``) where it cannot follow."""
        phi = _array(input_angles, "input_angles", 1)
        if phi.size > 1 and not np.all(np.diff(phi) > 0):
            raise SynthesisError("input_angles must increase")
        psi1 = float(self.pairs_out[0])
        b1 = self.c * complex(math.cos(psi1), math.sin(psi1))
        # the sweep follows the drawing (the first pair) along the driver to every phi
        r = self.model().compile().sweep(phi, derivatives=0).body("rocker").theta
        return psi1 + np.remainder(r - math.atan2(b1.imag, b1.real) + math.pi, 2.0 * math.pi) - math.pi

    def structural_error(self, input_angles: Any, desired: Any) -> np.ndarray:
        """Desired minus generated output angle at each input angle (rad)."""
        want = _array(desired, "desired", 1)
        return want - self.output(input_angles)


@dataclass(frozen=True)
class NinePointResult:
    """Alt's nine-point problem at one instance: ``classes`` roots found (1442 for
    generic points), of which ``physical_classes`` are real four-bars, each giving three
    Roberts cognates as ``designs`` (screened, sorted by `MERIT`); ``paths``, ``failed``
    (of which ``over_budget``: stopped by the step or time budget of a nearly degenerate
    instance), ``at_infinity``, ``singular``, ``duplicates``: what the 1442 paths did;
    ``certified``: roots passing the alpha test; ``seconds``: the homotopy's wall time."""

    points: np.ndarray
    classes: int
    certified: int
    distinct: bool
    physical_classes: int
    paths: int
    failed: int
    over_budget: int
    at_infinity: int
    singular: int
    duplicates: int
    max_residual: float
    seconds: float
    designs: list[FourBarDesign]

    def report(self) -> str:
        lines = [
            "Alt's nine-point path synthesis:",
            f"  {self.paths} paths in {self.seconds:.2f} s: {self.classes} classes of roots "
            f"({self.certified} certified, distinct: {self.distinct}), {self.failed} failed "
            f"({self.over_budget} over budget), "
            f"{self.at_infinity} at infinity, {self.singular} singular, {self.duplicates} duplicates; "
            f"largest backward error {self.max_residual:.1e}",
            f"  {self.physical_classes} real four-bars (classes), "
            f"{len(self.designs)} designs with their cognates, "
            f"{sum(d.defects.ok for d in self.designs)} defect-free; sorted by: {MERIT}",
        ]
        for i, d in enumerate(self.designs[:10], 1):
            lines.append(f"    {i}. {d}")
        if len(self.designs) > 10:
            lines.append(f"    ... {len(self.designs) - 10} more")
        return "\n".join(lines)


def nine_points(points: Any, screen: bool = True, seconds: float = 30.0) -> NinePointResult:
    """Alt's problem: every four-bar whose coupler curve passes through the nine
    ``points`` (9 x 2), by parameter homotopy from the shipped start set of 1442 generic
    classes (docs/synthesis.md says how it was made). Each real four-bar comes with its
    two Roberts cognates; with ``screen``, each design is swept by the engine (is every
    point reached, in order, on one circuit?) and the list sorted by `MERIT`. A generic
    instance takes a few seconds; a nearly degenerate one stops after ``seconds``, its
    unfinished paths counted as failed and ``over_budget``."""
    pts = _array(points, "points", 2)
    if len(pts) != 9:
        raise SynthesisError(f"Alt's problem takes exactly 9 points; got {len(pts)}")
    raw = _core.synth_alt(pts.ravel().tolist(), seconds=float(seconds))
    designs = []
    for k in range(len(raw["class"])):
        a, b = _alt_dyads(raw, k, pts)
        designs.append(
            FourBarDesign(
                a.ground,
                a.moving,
                b.ground,
                b.moving,
                pts[0].copy(),
                pts,
                np.concatenate([[0.0], raw["coupler_angles"][k]]),
                None,
                (a, b),
            )
        )
    if screen:
        designs.sort(key=_merit)
    return NinePointResult(
        pts,
        raw["roots"],
        raw["certified"],
        raw["distinct"],
        raw["physical_classes"],
        raw["paths"],
        raw["failed"],
        raw["over_budget"],
        raw["at_infinity"],
        raw["singular"],
        raw["duplicates"],
        raw["max_residual"],
        raw["seconds"],
        designs,
    )


def _alt_dyads(raw: dict[str, Any], k: int, pts: np.ndarray) -> tuple[Dyad, Dyad]:
    """The two dyads of four-bar k, with their residual: the largest change of the crank
    length over the nine positions (pin at P_j + x theta_j, x = pin - P_0 at position 0)."""
    theta = np.exp(1j * np.concatenate([[0.0], raw["coupler_angles"][k]]))
    p = pts[:, 0] + 1j * pts[:, 1]
    out = []
    for g, m in (("ground_a", "moving_a"), ("ground_b", "moving_b")):
        ground, moving = complex(*raw[g][k]), complex(*raw[m][k])
        lengths = np.abs(p + (moving - p[0]) * theta - ground)
        zero = np.zeros(2)
        out.append(
            Dyad(
                np.array(raw[g][k]),
                np.array(raw[m][k]),
                zero,
                zero,
                True,
                True,
                float(np.ptp(lengths)),
                float(raw["max_residual"]),
                math.nan,
                0.0,
            )
        )
    return out[0], out[1]
