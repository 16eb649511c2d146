"""linkwork: planar mechanism kinematics in absolute coordinates.

Build a `Mechanism` (bodies, joints at world points, drivers with motion laws), compile
it into a `Model`, then ``model.solve(t)`` or ``model.sweep(times)``.
"""

from . import curves, reference, screw, study
from .errors import (
    AssemblyError,
    CancelledError,
    ClosureError,
    ConvergenceError,
    DependencyError,
    EquilibriumError,
    ExpressionError,
    FreeModelError,
    InitialConditionError,
    InputError,
    IntegrationError,
    InternalError,
    LinkworkError,
    LinkworkWarning,
    MasslessError,
    ModelError,
    NonFiniteError,
    ParameterError,
    PortabilityError,
    ScrewError,
    SingularError,
    SolveError,
    StiffnessError,
    StudyError,
)
from .mechanism import examples
from .mechanism import lengths as build
from .mechanism.builder import GROUND, Body, Mechanism
from .model.compiled import Cycle, Model, sweep_batch
from .model.results import BodyMotion, PointMotion, Results, State
from .model.simulation import Simulation
from .motion import (
    PROFILES,
    Cam,
    Constant,
    Expression,
    Harmonic,
    Law,
    Linear,
    Periodic,
    Polynomial,
    PythonLaw,
    Rise,
    Sequence,
    Spline,
)
from .reference import closed_form
from .study import Study, StudyResult

__version__ = "0.1.0"

__all__ = [
    "Cycle",
    "GROUND",
    "PROFILES",
    "AssemblyError",
    "Body",
    "BodyMotion",
    "Cam",
    "CancelledError",
    "InternalError",
    "Constant",
    "ConvergenceError",
    "DependencyError",
    "EquilibriumError",
    "Expression",
    "ClosureError",
    "ExpressionError",
    "FreeModelError",
    "InitialConditionError",
    "IntegrationError",
    "StiffnessError",
    "MasslessError",
    "Harmonic",
    "InputError",
    "Law",
    "Linear",
    "LinkworkError",
    "LinkworkWarning",
    "Mechanism",
    "Model",
    "ModelError",
    "NonFiniteError",
    "ParameterError",
    "PortabilityError",
    "Periodic",
    "PointMotion",
    "Polynomial",
    "PythonLaw",
    "Results",
    "Rise",
    "ScrewError",
    "SingularError",
    "Simulation",
    "Sequence",
    "SolveError",
    "StudyError",
    "Spline",
    "State",
    "Study",
    "StudyResult",
    "build",
    "closed_form",
    "curves",
    "sweep_batch",
    "examples",
    "reference",
    "screw",
    "study",
]
