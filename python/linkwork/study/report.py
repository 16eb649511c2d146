"""Reports of studies: a markdown page with figures (matplotlib, Agg).

A tolerance report has the envelope of each coupler path (the samples' spread across the
path, Monte Carlo and first order), the histogram of each output angle's error, and the
share of each parameter in the variance. A design-space report has the coupler curves
of the designs (an atlas) and the scalar figures against the parameters.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from linkwork.study import StudyResult, ToleranceResult

__all__ = ["tolerance_report", "study_report", "atlas_figure"]


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: str, title: str, written: list[str], figures: list[tuple[str, str]]) -> None:
    """Writes a report's figure and lists it (the files written; the report's sections)."""
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    written.append(path)
    figures.append((title, path))


def _normals(path: np.ndarray) -> np.ndarray:
    """Unit normals (left of the direction of travel) along a path (n_steps x 2)."""
    tangent = np.gradient(path, axis=0)
    norm = np.hypot(tangent[:, 0], tangent[:, 1])
    norm[norm == 0] = 1.0
    return np.stack([-tangent[:, 1], tangent[:, 0]], axis=1) / norm[:, None]


def tolerance_report(tol: ToleranceResult, directory: str, stem: str = "tolerance") -> list[str]:
    """Writes ``stem``.md and its PNGs to ``directory``; returns the paths written."""
    plt = _plt()
    os.makedirs(directory, exist_ok=True)
    written: list[str] = []
    comps = tol.components
    times = tol.nominal.times
    dev = tol.deviations
    lin = tol.linear
    stats = tol.monte_carlo_stats()
    figures: list[tuple[str, str]] = []
    for o in tol.nominal.outputs:
        if o.kind == "path":
            cx, cy = comps.index(f"{o.key}.x"), comps.index(f"{o.key}.y")
            nominal = tol.nominal.figures[o.key][0]
            n = _normals(nominal)
            across = dev[:, :, cx] * n[None, :, 0] + dev[:, :, cy] * n[None, :, 1]
            fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
            ax1.plot(nominal[:, 0], nominal[:, 1], "k-", lw=1, label="nominal")
            if len(across):
                scale = 0.05 * np.ptp(nominal, axis=0).max() / max(np.abs(across).max(), 1e-300)
                hi, lo = across.max(axis=0), across.min(axis=0)
                for edge, label in ((hi, "Monte Carlo envelope"), (lo, None)):
                    ax1.plot(*(nominal + scale * edge[:, None] * n).T, "C0-", lw=0.8, label=label)
                ax1.set_title(f"{o.name}: envelope across the path, deviations x {scale:.3g}")
            ax1.set_aspect("equal")
            ax1.legend(loc="best", fontsize=8)
            ax1.set_xlabel(f"x ({o.unit})")
            ax1.set_ylabel(f"y ({o.unit})")
            steps = np.arange(len(times))
            if len(across):
                ax2.fill_between(steps, across.min(axis=0), across.max(axis=0), color="C0", alpha=0.25,
                                 label="Monte Carlo min..max")  # fmt: skip
                sd = across.std(axis=0, ddof=1) if len(across) > 1 else np.zeros(len(steps))
                ax2.plot(steps, 3 * sd, "C0--", lw=1, label="Monte Carlo 3 std")
                ax2.plot(steps, -3 * sd, "C0--", lw=1)
            if lin is not None:
                s_n = (
                    lin.sensitivities[:, :, cx] * n[:, None, 0] + lin.sensitivities[:, :, cy] * n[:, None, 1]
                )
                half = np.asarray([t.half_width for t in tol.tolerances.values()])
                sig = np.asarray([t.std for t in tol.tolerances.values()])
                worst = np.abs(s_n) @ half
                rss = np.sqrt((s_n * sig) ** 2 @ np.ones(len(sig)))
                ax2.plot(steps, worst, "C3-", lw=1, label=f"first order worst case ({lin.method})")
                ax2.plot(steps, -worst, "C3-", lw=1)
                ax2.plot(steps, 3 * rss, "C1:", lw=1.5, label="first order 3 RSS")
                ax2.plot(steps, -3 * rss, "C1:", lw=1.5)
            ax2.set_xlabel("step")
            ax2.set_ylabel(f"deviation across the path ({o.unit})")
            ax2.legend(loc="best", fontsize=8)
            _save(
                fig,
                os.path.join(directory, f"{stem}_{o.key}_envelope.png"),
                f"Envelope of {o.name}",
                written,
                figures,
            )
        elif o.kind in ("angle", "coordinate"):
            c = comps.index(o.key)
            fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
            err = np.abs(dev[:, :, c]).max(axis=1) if len(dev) else np.zeros(0)
            factor, unit = (np.degrees(1.0), "deg") if o.unit == "rad" else (1.0, o.unit)
            ax1.hist(err * factor, bins=50, color="C0", alpha=0.8)
            if lin is not None:
                ax1.axvline(lin.worst[:, c].max() * factor, color="C3", label=f"worst case ({lin.method})")
                ax1.axvline(3 * lin.rss[:, c].max() * factor, color="C1", ls=":", label="3 RSS")
                ax1.legend(fontsize=8)
            ax1.set_xlabel(f"largest |error| over the cycle ({unit})")
            ax1.set_ylabel("samples")
            ax1.set_title(f"{o.name}: error of each sample")
            k = int(np.argmax(stats["std"][:, c])) if len(dev) > 1 else 0
            at_k = dev[:, k, c] * factor if len(dev) else np.zeros(0)
            ax2.hist(at_k, bins=50, density=True, color="C0", alpha=0.8, label="Monte Carlo")
            if lin is not None and lin.rss[k, c] > 0:
                s = lin.rss[k, c] * factor
                x = np.linspace(-4 * s, 4 * s, 200) + lin.shift[k, c] * factor
                pdf = np.exp(-0.5 * ((x - lin.shift[k, c] * factor) / s) ** 2) / (s * np.sqrt(2 * np.pi))
                ax2.plot(x, pdf, "C1-", label="first order (normal, RSS)")
            ax2.set_xlabel(f"error at step {k}, t = {times[k]:.4g} s ({unit})")
            ax2.set_ylabel("density")
            ax2.legend(fontsize=8)
            _save(
                fig,
                os.path.join(directory, f"{stem}_{o.key}_error.png"),
                f"Error of {o.name}",
                written,
                figures,
            )
    if lin is not None:
        names = list(tol.tolerances)
        share = lin.share.mean(axis=0)  # (n_params, n_components)
        fig, ax = plt.subplots(figsize=(max(6, 1.2 * len(comps) + 3), 4))
        width = 0.8 / max(1, len(names))
        for i, name in enumerate(names):
            ax.bar(np.arange(len(comps)) + i * width, 100 * share[i], width, label=name)
        ax.set_xticks(np.arange(len(comps)) + 0.4 - width / 2)
        ax.set_xticklabels(comps, rotation=20)
        ax.set_ylabel("share of the variance (%, mean over the cycle)")
        ax.set_title(f"Which parameter contributes most ({lin.method})")
        ax.legend(fontsize=8)
        _save(fig, os.path.join(directory, f"{stem}_contributions.png"), "Contributions", written, figures)
    md = os.path.join(directory, f"{stem}.md")
    with open(md, "w", encoding="utf-8") as f:
        f.write(f"# Tolerance study of {tol.nominal.model_name}\n\n")
        f.write(f"{tol.n} samples (seed {tol.seed}): {tol.n - tol.n_failed} swept, {tol.n_failed} failed")
        f.write(" (did not assemble or their sweep failed; listed below).\n\n" if tol.n_failed else ".\n\n")
        f.write("| parameter | nominal | unit | tolerance (deviation from nominal) |\n|---|---|---|---|\n")
        for p, (name, t) in zip(tol.nominal.parameters, tol.tolerances.items()):
            f.write(f"| {name} | {p.nominal:.6g} | {p.unit} | {t} |\n")
        method = lin.method if lin is not None else "none"
        f.write(f"\nFirst order from sensitivities by **{method}**. Largest over the cycle:\n\n")
        f.write(
            "| output | unit | MC std | first-order RSS | MC max abs | first-order worst | top parameter |\n"
        )
        f.write("|---|---|---|---|---|---|---|\n")
        for r in tol.comparison():
            f.write(
                f"| {r['component']} | {r['unit']} | {r['mc_std']:.4g} | "
                f"{r.get('linear_rss', float('nan')):.4g} | "
                f"{r['mc_max_abs']:.4g} | {r.get('linear_worst', float('nan')):.4g} | "
                f"{r.get('top_parameter', '')} ({100 * r.get('top_share', float('nan')):.0f} %) |\n"
            )
        for title, path in figures:
            f.write(f"\n## {title}\n\n![{title}]({os.path.basename(path)})\n")
        if tol.n_failed:
            f.write("\n## Failed samples\n\n| sample | error |\n|---|---|\n")
            for i, _, error in tol.failures()[:50]:
                f.write(f"| {i} | {error.splitlines()[0][:160]} |\n")
    written.insert(0, md)
    return written


def atlas_figure(res: StudyResult, path: str, output: str | None = None, columns: int | None = None) -> str:
    """The coupler curves of a design space, one small panel per design (a grid's
    parameters along the panels' rows and columns); failed designs are marked."""
    plt = _plt()
    key = output or next(o.key for o in res.outputs if o.kind == "path")
    n = len(res)
    if columns is None:
        columns = (
            res.designs.shape[-1]
            if res.designs.shape and len(res.designs.shape) == 2
            else int(np.ceil(np.sqrt(n)))
        )
    rows = int(np.ceil(n / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(1.7 * columns, 1.7 * rows), squeeze=False)
    for i, ax in enumerate(axes.ravel()):
        ax.set_xticks([])
        ax.set_yticks([])
        if i >= n:
            ax.axis("off")
            continue
        curve = res.figures[key][i]
        if res.ok[i]:
            ax.plot(curve[:, 0], curve[:, 1], "C0-", lw=0.9)
            ax.set_aspect("equal", adjustable="datalim")
        else:
            ax.text(0.5, 0.5, res.errors[i].split(":")[0], ha="center", va="center", fontsize=6, color="C3",
                    transform=ax.transAxes)  # fmt: skip
        label = ", ".join(f"{v:.3g}" for v in res.designs.values[i])
        ax.set_title(label, fontsize=6)
    fig.suptitle(f"{res.model_name}: {key} by {', '.join(p.name for p in res.parameters)}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def study_report(res: StudyResult, directory: str, stem: str = "study") -> list[str]:
    """A design-space report: ``stem``.md, the atlas of coupler curves (if a path was
    asked for) and each scalar figure against each parameter."""
    plt = _plt()
    os.makedirs(directory, exist_ok=True)
    written: list[str] = []
    figures: list[tuple[str, str]] = []
    if any(o.kind == "path" for o in res.outputs):
        for o in res.outputs:
            if o.kind == "path":
                path = atlas_figure(res, os.path.join(directory, f"{stem}_{o.key}_atlas.png"), o.key)
                written.append(path)
                figures.append((f"Atlas of {o.name}", path))
    scalars = [o for o in res.outputs if not o.dims and o.dtype == "float64"]
    if scalars:
        p = len(res.parameters)
        fig, axes = plt.subplots(len(scalars), p, figsize=(4 * p, 3 * len(scalars)), squeeze=False)
        for r, o in enumerate(scalars):
            y = res.figures[o.key]
            factor, unit = (np.degrees(1.0), "deg") if o.unit == "rad" else (1.0, o.unit)
            for c, par in enumerate(res.parameters):
                ax = axes[r, c]
                ax.plot(res.designs.values[:, c], y * factor, ".", ms=3)
                ax.set_xlabel(f"{par.name} ({par.unit})")
                ax.set_ylabel(f"{o.name} ({unit})" if unit else o.name)
        _save(
            fig,
            os.path.join(directory, f"{stem}_figures.png"),
            "Figures against parameters",
            written,
            figures,
        )
    md = os.path.join(directory, f"{stem}.md")
    with open(md, "w", encoding="utf-8") as f:
        f.write(f"# Design study of {res.model_name}\n\n")
        f.write(f"{len(res)} designs ({res.designs.kind}) of {', '.join(p.name for p in res.parameters)}: ")
        f.write(
            f"{len(res) - res.n_failed} swept, {res.n_failed} failed; ran {res.where} in {res.seconds:.3g} s "
        )
        f.write(f"({len(res.tasks)} tasks of up to {res.chunk} designs).\n")
        for title, path in figures:
            f.write(f"\n## {title}\n\n![{title}]({os.path.basename(path)})\n")
        if res.n_failed:
            f.write("\n## Failed designs\n\n| design | values | error |\n|---|---|---|\n")
            for i, design, error in res.failures()[:50]:
                values = ", ".join(f"{k} = {v:.6g}" for k, v in design.items())
                f.write(f"| {i} | {values} | {error.splitlines()[0][:160]} |\n")
    written.insert(0, md)
    return written
