"""Tolerance analysis: how far the outputs stray when the parameters do.

Two answers, side by side:

- **Monte Carlo**: ``n`` mechanisms sampled from the tolerances (seeded), each swept;
  the deviations from the nominal design's outputs, step by step. Samples that do not
  assemble or whose sweep fails are counted and listed, never dropped silently.
- **First order**: with S the sensitivities of the outputs to the parameters, an array
  (n_steps x n_params x n_components), `propagate` gives the worst case
  sum_i |S_i| t_i (t_i the tolerance's half width; 3 sigma for a normal one), the
  root-sum-square sqrt(sum_i (S_i sigma_i)^2) and each parameter's share of the
  variance. S is the engine's **exact** sensitivities (`Model.sensitivities`: the
  implicit function theorem on each step's factorization, no differences) where every
  parameter is one of the engine's (`linkwork.study.sensitivity`), and otherwise
  estimated by **central differences** of sweeps (two designs per parameter, +-h), the
  fallback, labelled with the parameter that needs it; or given (``sensitivities=``).

The components are the per-step outputs' numbers: ``path P`` gives "path_P.x" and
"path_P.y", ``angle rocker`` gives "angle_rocker". Scalar outputs (``transmission_min``,
...) are Monte Carlo only: a minimum over steps has no first-order propagation.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ParameterError, StudyError
from .designs import Designs, sample, tolerance

if TYPE_CHECKING:
    from linkwork.study import Study, StudyResult

__all__ = [
    "propagate",
    "Linear",
    "ToleranceResult",
    "tolerance_study",
    "central_differences",
    "exact_sensitivities",
    "components",
]


@dataclass(frozen=True)
class Linear:
    """First-order propagation: ``worst`` and ``rss`` (n_steps x n_components), ``shift``
    (the mean deviation, from tolerances not centred on nominal), ``share`` (n_steps x
    n_params x n_components: each parameter's fraction of the variance), ``method`` (how S
    was found: "exact (engine)", "central differences (...why...)" or "given")."""

    worst: np.ndarray
    rss: np.ndarray
    shift: np.ndarray
    share: np.ndarray
    sensitivities: np.ndarray = field(repr=False)
    method: str


def propagate(
    sensitivities: Any, half_widths: Any, sigmas: Any, means: Any = None, method: str = "given"
) -> Linear:
    """First-order tolerance propagation from S (n_steps x n_params x n_components):
    worst case sum_i |S_i| half_width_i, root-sum-square sqrt(sum_i (S_i sigma_i)^2),
    mean shift sum_i S_i mean_i, and each parameter's share (S_i sigma_i)^2 / RSS^2.

    >>> S = np.ones((3, 2, 1))                  # two parameters, each moving the output 1:1
    >>> lin = propagate(S, [0.1, 0.2], [0.1, 0.1])
    >>> float(lin.worst[0, 0]), round(float(lin.rss[0, 0]), 12), lin.share[0, :, 0].tolist()
    (0.30000000000000004, 0.141421356237, [0.5, 0.5])
    """
    s = np.asarray(sensitivities, dtype=np.float64)
    if s.ndim != 3:
        raise StudyError(
            f"sensitivities are an (n_steps x n_params x n_components) array, not shape {s.shape}"
        )
    n_params = s.shape[1]
    h = _vector(half_widths, n_params, "half_widths")
    sig = _vector(sigmas, n_params, "sigmas")
    mu = np.zeros(n_params) if means is None else _vector(means, n_params, "means")
    worst = np.einsum("spc,p->sc", np.abs(s), h)
    scaled = s * sig[None, :, None]
    var = np.einsum("spc,spc->sc", scaled, scaled)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(var[:, None, :] > 0, scaled**2 / var[:, None, :], 0.0)
    return Linear(worst, np.sqrt(var), np.einsum("spc,p->sc", s, mu), share, s, method)


def _vector(v: Any, n: int, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64).ravel()
    if a.size != n or not np.all(np.isfinite(a)) or np.any(a < 0):
        raise StudyError(f"{name}: {n} finite non-negative numbers, one per parameter, not {v!r}")
    return a


def components(res_or_study: Any) -> tuple[list[str], list[Any]]:
    """The per-step numbers of a study's outputs: names ("path_P.x", ...) and outputs."""
    names, outs = [], []
    for o in res_or_study.outputs:
        if o.dtype != "float64" or "step" not in o.dims:
            continue
        if "xy" in o.dims:
            names += [f"{o.key}.x", f"{o.key}.y"]
            outs += [o, o]
        else:
            names.append(o.key)
            outs.append(o)
    return names, outs


def _stack(res: StudyResult) -> np.ndarray:
    """(n_designs, n_steps, n_components) of a result's per-step outputs."""
    parts = []
    for o in res.outputs:
        if o.dtype != "float64" or "step" not in o.dims:
            continue
        v = res.figures[o.key]
        parts.append(v if v.ndim == 3 else v[:, :, None])
    if not parts:
        raise StudyError(
            "a tolerance study needs a per-step output: 'path P', 'angle BODY' or 'coordinate NAME'"
        )
    return np.concatenate(parts, axis=2)


def central_differences(
    study: Study, nominal: Mapping[str, float], steps: Mapping[str, float], **run: Any
) -> np.ndarray:
    """S (n_steps x n_params x n_components) by central differences: for each parameter,
    the two designs nominal +- h (``steps``), (y+ - y-) / 2h. Raises `StudyError` naming
    the parameter whose +-h designs do not sweep."""
    names = list(nominal)
    rows = []
    for k, name in enumerate(names):
        for sign in (1.0, -1.0):
            row = [nominal[m] for m in names]
            row[k] += sign * steps[name]
            rows.append(row)
    res = study.run(Designs(tuple(names), np.asarray(rows, dtype=np.float64), "central differences"), **run)
    if res.n_failed:
        i, _, error = res.failures()[0]
        raise StudyError(f"central differences of {names[i // 2]!r} (+-{steps[names[i // 2]]:g}): {error}")
    y = _stack(res)
    h = np.asarray([steps[m] for m in names])
    return np.transpose((y[0::2] - y[1::2]) / (2.0 * h[:, None, None]), (1, 0, 2))


def exact_sensitivities(study: Study, names: Sequence[str]) -> np.ndarray:
    """S (n_steps x n_params x n_components) of the study's per-step outputs from the
    engine's exact sensitivities of the nominal design (`Model.sensitivities`). Raises
    `ParameterError` for a parameter that is not one of the engine's, `StudyError` for an
    output without a per-step first order."""
    paths = [o.target for o in study.outputs if o.kind == "path"]
    # positions' sensitivities alone: the structured path where the mechanism allows it
    sens = study.model.sensitivities(study.times, list(names), points=paths, derivatives=0)
    parts = []
    for o in study.outputs:
        if o.dtype != "float64" or "step" not in o.dims:
            continue
        if o.kind == "path":
            parts += [sens.points[o.target][:, 0, :], sens.points[o.target][:, 1, :]]
        elif o.kind == "angle":
            parts.append(sens.column(f"{o.target}.theta"))
        elif o.kind == "coordinate":
            parts.append(sens.column(o.target))
        else:
            raise StudyError(f"output {o.name!r} has no exact first order")
    if not parts:
        raise StudyError(
            "a tolerance study needs a per-step output: 'path P', 'angle BODY' or 'coordinate NAME'"
        )
    return np.stack(parts, axis=2)


@dataclass
class ToleranceResult:
    """A tolerance study: ``nominal`` (the nominal design's `StudyResult`), ``monte_carlo``
    (the samples' `StudyResult`), ``deviations`` (n_ok x n_steps x n_components, the
    swept samples' outputs minus nominal), ``components``, ``linear`` (`Linear`),
    ``tolerances``, ``parameters``, ``n``, ``seed``; `summary` and `report`."""

    nominal: StudyResult
    monte_carlo: StudyResult
    deviations: np.ndarray = field(repr=False)
    components: list[str]
    linear: Linear | None
    tolerances: dict[str, Any]
    n: int
    seed: int | None

    @property
    def n_failed(self) -> int:
        """Samples that did not assemble or whose sweep failed (listed in `failures`)."""
        return self.monte_carlo.n_failed

    def failures(self) -> list[tuple[int, dict[str, float], str]]:
        return self.monte_carlo.failures()

    def monte_carlo_stats(self) -> dict[str, np.ndarray]:
        """Per step and component: ``mean``, ``std`` (ddof 1) and ``max_abs`` deviation of
        the swept samples."""
        d = self.deviations
        if len(d) == 0:
            nan = np.full(d.shape[1:], np.nan)
            return {"mean": nan, "std": nan, "max_abs": nan}
        return {
            "mean": d.mean(axis=0),
            "std": d.std(axis=0, ddof=1) if len(d) > 1 else np.zeros(d.shape[1:]),
            "max_abs": np.abs(d).max(axis=0),
        }

    def comparison(self) -> list[dict[str, Any]]:
        """Per component, the largest over the steps of: the Monte Carlo standard
        deviation and largest deviation, the first-order RSS and worst case, and the
        parameter contributing most (largest mean share of the variance)."""
        stats = self.monte_carlo_stats()
        if len(self.deviations) == 0:
            stats = {k: np.zeros_like(v) for k, v in stats.items()}
        rows = []
        names = list(self.tolerances)
        for c, name in enumerate(self.components):
            row: dict[str, Any] = {
                "component": name,
                "unit": _unit(self.monte_carlo, name),
                "mc_std": float(np.nanmax(stats["std"][:, c])),
                "mc_max_abs": float(np.nanmax(stats["max_abs"][:, c])),
            }
            if self.linear is not None:
                row["linear_rss"] = float(np.max(self.linear.rss[:, c]))
                row["linear_worst"] = float(np.max(self.linear.worst[:, c]))
                share = self.linear.share[:, :, c].mean(axis=0)
                row["top_parameter"] = names[int(np.argmax(share))]
                row["top_share"] = float(np.max(share))
            rows.append(row)
        return rows

    def summary(self) -> str:
        method = self.linear.method if self.linear is not None else "none"
        lines = [
            f"tolerance study of {self.nominal.model_name!r}: {self.n} samples (seed {self.seed}), "
            f"{self.n - self.n_failed} swept, {self.n_failed} failed (not assembled or not swept)",
            f"  first order: {method}",
            f"  {'component':<22} {'unit':>5} {'MC std':>11} {'RSS':>11} {'MC max|d|':>11} "
            f"{'worst':>11}  top",
        ]
        for r in self.comparison():
            lines.append(
                f"  {r['component']:<22} {r['unit']:>5} {r['mc_std']:11.4g} "
                f"{r.get('linear_rss', math.nan):11.4g} "
                f"{r['mc_max_abs']:11.4g} {r.get('linear_worst', math.nan):11.4g}  "
                f"{r.get('top_parameter', '')} ({100 * r.get('top_share', math.nan):.0f} %)"
            )
        for i, _, error in self.failures()[:5]:
            lines.append(f"  failed sample {i}: {error.splitlines()[0][:100]}")
        if self.n_failed > 5:
            lines.append(f"  ... {self.n_failed - 5} more failed samples")
        return "\n".join(lines)

    def report(self, directory: str, stem: str = "tolerance") -> list[str]:
        """Writes the report (markdown) and its figures to ``directory``; returns the paths."""
        # declared lazy import, upward: a convenience method of the report
        from .report import tolerance_report

        return tolerance_report(self, directory, stem)


def _unit(res: StudyResult, component: str) -> str:
    key = component.split(".")[0]
    return next((o.unit for o in res.outputs if o.key == key), "")


def tolerance_study(
    study: Study,
    tolerances: Mapping[str, Any],
    n: int = 1000,
    seed: int | None = 0,
    sensitivities: Any = None,
    linear: bool = True,
    **run: Any,
) -> ToleranceResult:
    """Monte Carlo over ``n`` mechanisms sampled from ``tolerances`` {parameter: Normal,
    Uniform, Interval or a study file's dict}, beside first-order propagation from
    ``sensitivities`` (n_steps x n_params x n_components, in the order of ``tolerances``)
    or, by default, from the engine's exact sensitivities (`exact_sensitivities`), or where
    a parameter is not one of the engine's, from central differences of sweeps (the
    method, ``linear.method``, says which, and why). ``run``: as for `Study.run`
    (``scheduler``, ``chunk``, ``progress``, ...); the nominal and the differences run
    in-process.
    """
    if not isinstance(tolerances, Mapping) or not tolerances:
        raise StudyError("tolerances are a non-empty dict {parameter: tolerance}")
    tols = {k: tolerance(v, k) for k, v in tolerances.items()}
    names = list(tols)
    nominal = study.nominal(names)
    base = study.run(Designs(tuple(names), np.asarray([[nominal[k] for k in names]]), "nominal"))
    if base.n_failed:
        raise StudyError(f"the nominal design does not sweep: {base.errors[0]}")
    mc = study.run(sample(nominal, tols, n, seed), **run)
    y0 = _stack(base)[0]
    ok = mc.ok
    deviations = _stack(mc)[ok] - y0[None]
    comps, _ = components(study)
    half = [t.half_width for t in tols.values()]
    sig = [t.std for t in tols.values()]
    means = [t.mean for t in tols.values()]
    lin = None
    if sensitivities is not None:
        lin = propagate(sensitivities, half, sig, means, method="given")
        if lin.worst.shape != y0.shape:
            raise StudyError(
                f"sensitivities give {lin.worst.shape} (steps x components); the outputs are {y0.shape}"
            )
    elif linear:
        try:
            lin = propagate(exact_sensitivities(study, names), half, sig, means, method="exact (engine)")
        except ParameterError as e:
            # a step small against the tolerance (truncation ~h^2) and large against the
            # solver's round-off (~1e-12 of the mechanism's size)
            steps = {k: 1e-2 * t.std for k, t in tols.items()}
            local = {k: v for k, v in run.items() if k in ("threads",)}
            s = central_differences(study, nominal, steps, **local)
            why = str(e).split(";")[0]
            lin = propagate(s, half, sig, means, method=f"central differences ({why})")
    return ToleranceResult(base, mc, deviations, comps, lin, tols, int(n), seed)
