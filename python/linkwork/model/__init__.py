"""The compiled model and what it answers: `Model` (solve, sweep, sweep_batch), `Results`
and `State`, events and motion limits, linkages and assembly modes, mobility and the
structure of the equations. Knows nothing of the builder, pictures or studies."""

from .compiled import Cycle, Model, sweep_batch
from .results import BodyMotion, PointMotion, Results, State

__all__ = ["BodyMotion", "Cycle", "Model", "PointMotion", "Results", "State", "sweep_batch"]
