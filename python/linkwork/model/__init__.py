"""The compiled model and what it answers: `Model` (solve, sweep, sweep_batch), `Results`
and `State`, the points a sweep traces (`anchors`), events and motion limits, linkages
and assembly modes, mobility and the structure of the equations. Imports nothing of the
builder, the views or the studies, but for the declared lazy imports of convenience
methods (`draw`, `to_html`, `to_svg`, `plot`, `sensitivities`, ...)."""

from .compiled import Cycle, Model, sweep_batch
from .results import BodyMotion, PointMotion, Results, State

__all__ = ["BodyMotion", "Cycle", "Model", "PointMotion", "Results", "State", "sweep_batch"]
