"""linkwork: planar mechanism kinematics in absolute coordinates.

Build a `Mechanism` (bodies, joints at world points, drivers with motion laws), compile
it into a `Model`, then ``model.solve(t)`` or ``model.sweep(times)``.
"""

from . import closed_form, examples, reference, screw
from .errors import (
    AssemblyError,
    CancelledError,
    ConvergenceError,
    InputError,
    LinkworkError,
    ModelError,
    NonFiniteError,
    ScrewError,
    SingularError,
    SolveError,
)
from .mechanism import GROUND, Body, Mechanism
from .model import Model, sweep_batch
from .motion import Constant, Harmonic, Law, Linear, Polynomial, Spline
from .results import BodyMotion, PointMotion, Results, State

__version__ = "0.1.0"

__all__ = [
    "GROUND",
    "AssemblyError",
    "Body",
    "BodyMotion",
    "CancelledError",
    "Constant",
    "ConvergenceError",
    "Harmonic",
    "InputError",
    "Law",
    "Linear",
    "LinkworkError",
    "Mechanism",
    "Model",
    "ModelError",
    "NonFiniteError",
    "PointMotion",
    "Polynomial",
    "Results",
    "ScrewError",
    "SingularError",
    "SolveError",
    "Spline",
    "State",
    "closed_form",
    "sweep_batch",
    "examples",
    "reference",
    "screw",
]
