"""Design spaces: which values each design gives its parameters.

`grid` (every combination of given values), `latin_hypercube` (n designs, each
parameter's range cut in n strata, one sample per stratum, seeded), `listed` (the user's
own designs) and, for tolerance studies, `sample` (nominal plus deviations drawn from
`Normal`, `Uniform` or `Interval` tolerances, seeded).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import StudyError

__all__ = [
    "Designs",
    "grid",
    "latin_hypercube",
    "listed",
    "sample",
    "Normal",
    "Uniform",
    "Interval",
    "tolerance",
]


@dataclass(frozen=True)
class Designs:
    """Designs of a study: ``names`` of the parameters and ``values`` (n_designs x
    n_params), with how they were made (``kind``; ``shape`` of a grid; ``seed``)."""

    names: tuple[str, ...]
    values: np.ndarray = field(repr=False)
    kind: str = "list"
    shape: tuple[int, ...] | None = None
    seed: int | None = None

    def __len__(self) -> int:
        return int(self.values.shape[0])

    def __repr__(self) -> str:
        extra = (
            f", grid {self.shape}" if self.shape else f", seed {self.seed}" if self.seed is not None else ""
        )
        return f"<Designs: {len(self)} designs ({self.kind}{extra}) of {', '.join(self.names)}>"

    def design(self, i: int) -> dict[str, float]:
        """Design ``i`` as {parameter: value}."""
        return dict(zip(self.names, map(float, self.values[i])))


def _values(values: Any, name: str) -> np.ndarray:
    try:
        a = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise StudyError(f"parameter {name!r}: the values must be numbers, not {values!r}") from None
    if a.ndim != 1 or a.size == 0:
        raise StudyError(f"parameter {name!r}: the values must be a non-empty list of numbers")
    if not np.all(np.isfinite(a)):
        raise StudyError(f"parameter {name!r}: the values must be finite")
    return a


def _mapping(space: Any, what: str) -> Mapping[str, Any]:
    if not isinstance(space, Mapping) or not space:
        raise StudyError(f"{what} is a non-empty dict {{parameter: ...}}, not {space!r}")
    return space


def _seed(seed: Any) -> int | None:
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise StudyError(f"seed must be a non-negative integer, not {seed!r}")
    return int(seed)


def grid(space: Mapping[str, Any]) -> Designs:
    """Every combination of the given values, the last parameter varying fastest.

    >>> d = grid({"length crank": [0.18, 0.2], "point P.x": [0.3, 0.32, 0.34]})
    >>> len(d), d.shape, d.design(1)
    (6, (2, 3), {'length crank': 0.18, 'point P.x': 0.32})
    """
    space = _mapping(space, "a grid")
    axes = [_values(v, k) for k, v in space.items()]
    mesh = np.meshgrid(*axes, indexing="ij")
    values = np.stack([m.ravel() for m in mesh], axis=1)
    return Designs(tuple(space), values, "grid", tuple(len(a) for a in axes))


def latin_hypercube(space: Mapping[str, Any], n: int, seed: int | None = 0) -> Designs:
    """``n`` designs spread over the box {parameter: (low, high)}: each parameter's range
    cut in n equal strata, one uniform sample in each, the strata paired at random."""
    space = _mapping(space, "a Latin hypercube")
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise StudyError(f"n must be a positive integer, not {n!r}")
    seed = _seed(seed)
    rng = np.random.default_rng(seed)
    cols = []
    for name, bounds in space.items():
        lo_hi = _values(bounds, name)
        if lo_hi.size != 2 or not lo_hi[0] < lo_hi[1]:
            raise StudyError(f"parameter {name!r}: a range is (low, high) with low < high, not {bounds!r}")
        u = (rng.permutation(n) + rng.random(n)) / n
        cols.append(lo_hi[0] + u * (lo_hi[1] - lo_hi[0]))
    return Designs(tuple(space), np.stack(cols, axis=1), "latin hypercube", seed=seed)


def listed(designs: Any) -> Designs:
    """The user's designs: a list of {parameter: value} (every one naming the same
    parameters) or {parameter: list of values} (all as long)."""
    if isinstance(designs, Designs):
        return designs
    if isinstance(designs, Mapping):
        cols = [_values(v, k) for k, v in _mapping(designs, "designs").items()]
        if len({len(c) for c in cols}) != 1:
            raise StudyError("designs given as {parameter: values} need as many values for every parameter")
        return Designs(tuple(designs), np.stack(cols, axis=1), "list")
    if isinstance(designs, (str, bytes)) or not isinstance(designs, Sequence) or not designs:
        raise StudyError(f"designs are a non-empty list of {{parameter: value}}, not {designs!r}")
    names = tuple(_mapping(designs[0], "design 0"))
    rows = []
    for i, d in enumerate(designs):
        d = _mapping(d, f"design {i}")
        if tuple(d) != names and set(d) != set(names):
            raise StudyError(f"design {i} names {sorted(d)}; design 0 names {sorted(names)}")
        rows.append([_number(d[k], f"design {i}: {k}") for k in names])
    return Designs(names, np.asarray(rows, dtype=np.float64), "list")


def _number(v: Any, what: str) -> float:
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(float(v)):
        raise StudyError(f"{what} must be a finite number, not {v!r}")
    return float(v)


# -- tolerances ----------------------------------------------------------------------


@dataclass(frozen=True)
class Normal:
    """A normally distributed deviation from nominal: ``sigma`` (and ``mean``, default 0).
    First-order worst case counts it as +-3 sigma."""

    sigma: float
    mean: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.sigma) and self.sigma > 0 and math.isfinite(self.mean)):
            raise StudyError(
                f"Normal(sigma={self.sigma!r}, mean={self.mean!r}): sigma must be > 0, both finite"
            )

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        return self.mean + self.sigma * rng.standard_normal(n)

    @property
    def std(self) -> float:
        return self.sigma

    @property
    def half_width(self) -> float:
        return 3.0 * self.sigma


@dataclass(frozen=True)
class Uniform:
    """A deviation uniform in [-half_width, +half_width] (a symmetric tolerance band)."""

    half_width: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.half_width) and self.half_width > 0):
            raise StudyError(f"Uniform({self.half_width!r}): the half width must be a finite number > 0")

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        return rng.uniform(-self.half_width, self.half_width, n)

    @property
    def std(self) -> float:
        return self.half_width / math.sqrt(3.0)

    @property
    def mean(self) -> float:
        return 0.0


@dataclass(frozen=True)
class Interval:
    """A deviation anywhere in [low, high] (an asymmetric tolerance band, e.g. +0 / -0.1),
    drawn uniformly; first order counts it about its middle."""

    low: float
    high: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise StudyError(f"Interval({self.low!r}, {self.high!r}): need finite low < high")

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        return rng.uniform(self.low, self.high, n)

    @property
    def mean(self) -> float:
        return 0.5 * (self.low + self.high)

    @property
    def half_width(self) -> float:
        return 0.5 * (self.high - self.low)

    @property
    def std(self) -> float:
        return self.half_width / math.sqrt(3.0)


Tolerance = "Normal | Uniform | Interval"


def tolerance(spec: Any, name: str = "") -> Normal | Uniform | Interval:
    """A tolerance from an object or a dict: {"normal": sigma}, {"uniform": half_width},
    {"interval": [low, high]} (the form of study files), or a bare number: +- that, uniform."""
    if isinstance(spec, (Normal, Uniform, Interval)):
        return spec
    if isinstance(spec, numbers.Real) and not isinstance(spec, bool):
        return Uniform(float(spec))
    if isinstance(spec, Mapping) and len(spec) >= 1:
        kind = next(iter(spec))
        try:
            if kind == "normal":
                return Normal(float(spec["normal"]), float(spec.get("mean", 0.0)))
            if kind == "uniform" and len(spec) == 1:
                return Uniform(float(spec["uniform"]))
            if kind == "interval" and len(spec) == 1:
                low, high = spec["interval"]
                return Interval(float(low), float(high))
        except (TypeError, ValueError):
            pass
    raise StudyError(
        f"tolerance of {name!r}: {spec!r} is not one; write Normal(sigma), Uniform(half_width), "
        "Interval(low, high) or, in a study file, {normal = s}, {uniform = h}, {interval = [lo, hi]}"
    )


def sample(
    nominal: Mapping[str, float], tolerances: Mapping[str, Any], n: int, seed: int | None = 0
) -> Designs:
    """``n`` designs: each parameter its nominal value plus a deviation drawn from its
    tolerance (one seeded generator, parameters drawn in the order given)."""
    tolerances = _mapping(tolerances, "tolerances")
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise StudyError(f"n must be a positive integer, not {n!r}")
    seed = _seed(seed)
    rng = np.random.default_rng(seed)
    cols = [nominal[k] + tolerance(t, k).draw(rng, int(n)) for k, t in tolerances.items()]
    return Designs(tuple(tolerances), np.stack(cols, axis=1), "monte carlo", seed=seed)
