"""The picture of a curve design (a four-bar or a six-bar): its target points against the
curve it traces (the engine's sweep over a crank turn, the traced stretch drawn solid),
each point's deviation drawn from the target to the traced point at its crank angle;
beside it the whole linkage at the first target's crank angle (the design's
``linkage_at``)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ...errors import SynthesisError
from .tracking import TWO_PI

# type only, named through the package: fit draws through this module
if TYPE_CHECKING:
    from linkwork.synthesis.curve import CurveDesign, SixBarDesign

__all__ = ["plot_design"]


def _stretch(design: CurveDesign | SixBarDesign, times: np.ndarray) -> np.ndarray:
    """Which sweep times lie on the traced stretch (all of them for a closed curve)."""
    th = design.crank_angles()
    if design.problem.target.closed or th[-1] - th[0] >= TWO_PI:
        return np.ones(times.size, dtype=bool)
    return np.asarray(np.mod(times - th[0], TWO_PI) <= th[-1] - th[0] + 1e-12)


def plot_design(
    design: CurveDesign | SixBarDesign, path: str, title: str | None = None, dpi: int = 110
) -> str:
    """Write the PNG at ``path`` and return it."""
    try:
        import matplotlib
    except ImportError:  # pragma: no cover - optional dependency
        raise SynthesisError("the picture needs matplotlib: pip install matplotlib") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ...view.targets import TARGET_COLOUR

    res = design.sweep()
    times = np.asarray(res.times)
    curve = res.point("P").position
    on = _stretch(design, times)
    target = design.problem.target.points
    r, _ = design.problem.evaluate(design.x)
    at = target + r.reshape(-1, 2)  # the traced point at each target's crank angle

    fig, (ax, whole) = plt.subplots(1, 2, figsize=(12, 5.5), gridspec_kw={"width_ratios": [3, 2]})
    for a in (ax, whole):
        a.plot(curve[:, 0], curve[:, 1], "-", color="0.7", lw=1.0, label="coupler curve (a turn)")
        traced = np.where(on[:, None], curve, np.nan)
        a.plot(traced[:, 0], traced[:, 1], "-", color="C0", lw=1.6, label="traced stretch")
        a.plot(target[:, 0], target[:, 1], "o", mfc="none", mec=TARGET_COLOUR, ms=7, label="target points")
        a.set_aspect("equal", adjustable="datalim")
        a.grid(alpha=0.3)
    for p, q in zip(target, at):
        ax.plot([p[0], q[0]], [p[1], q[1]], "-", color=TARGET_COLOUR, lw=1.2)
    ax.plot(at[:, 0], at[:, 1], ".", color="C0", ms=5, label="traced point at each crank angle")
    for j, p in enumerate(target, 1):
        ax.annotate(str(j), p, textcoords="offset points", xytext=(4, 4), fontsize=7, color=TARGET_COLOUR)
    ax.set_title(
        title or f"target and traced curve: f {design.f:.3g}, largest deviation {design.max_deviation:.3g}",
        fontsize=10,
    )
    ax.legend(fontsize=7, loc="best")
    # the left panel frames the target and the traced stretch (an open curve's turn can be far larger)
    box = np.vstack([target, curve[on], at])
    lo, hi = box.min(axis=0), box.max(axis=0)
    pad = 0.08 * max(float(np.max(hi - lo)), 1e-12)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    # the linkage at the first target's crank angle, from the sweep's nearest step
    k = int(np.argmin(np.abs(np.mod(times - design.crank_angles()[0], TWO_PI))))
    bodies, pivots = design.linkage_at(float(times[k]))
    for body in bodies:
        if len(body) == 2:
            whole.plot(*body.T, "-", color="0.3", lw=2.5)
        else:
            whole.fill(*body.T, color="C1", alpha=0.35, lw=1.5, ec="C1")
    whole.plot(*pivots.T, "^", color="k", ms=9)
    six = getattr(design, "kind", None)
    kind = f"{six} six-bar, " if six else ""
    whole.set_title(
        f"{kind}{design.circuit} circuit, {design.grashof}, smallest transmission "
        f"{math.degrees(design.transmission):.1f} deg",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
