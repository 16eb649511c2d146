"""The one exception hierarchy of linkwork.

::

    LinkworkError
    ├── ModelError          the description cannot be compiled (names the body/joint/driver)
    │   ├── ExpressionError     a text expression that does not parse (``column`` says where)
    │   └── ClosureError        a drawing that does not close: a joint's pins miss its drawn
    │                           point (``joint``, ``miss``); ``close`` asks the engine to close it
    ├── InputError          bad arguments to a solve (time grid, q_guess); also a ValueError
    ├── ScrewError          a screw-theory question without a (unique) answer: coincident
    │                       or collinear joints, parallel lines, a redundant arm; also a ValueError
    ├── SynthesisError      a synthesis problem that is not well posed (point count, coincident
    │                       or collinear points); also a ValueError
    ├── ParameterError      a design parameter that names nothing in the model (the message
    │                       lists what exists); also a ValueError
    ├── StudyError          a design study that cannot be run as asked (a bad study file,
    │   │                   an unknown output); also a ValueError
    │   └── PortabilityError    a model that cannot travel to another process (Python laws)
    ├── DependencyError     an optional package a call needs is not installed (the message
    │                       gives the pip command); also an ImportError
    └── SolveError          a solve could not be completed at some time step
        ├── AssemblyError       no configuration found at the first time
        ├── ConvergenceError    Newton-Raphson did not converge at a later step
        ├── SingularError       Phi_q is singular there (dead point, lock-up, redundancy)
        ├── NonFiniteError      a NaN or infinity appeared
        ├── CancelledError      the sweep was stopped by its progress callback
        ├── FreeModelError      a kinematic solve of a model with free coordinates
        │                       (``compile(free=True)``): simulate it or add drivers
        ├── InitialConditionError   initial positions or rates too far from the
        │                       constraints (projecting them would move them beyond ``ic_tol``)
        ├── MasslessError       no mass on a free coordinate (names the body)
        ├── IntegrationError    a simulation step failed (``partial``: the steps done)
        │   └── StiffnessError      rk8's steps held by stability: a stiff load (named)
        └── EquilibriumError    no rest configuration found (``q``: the last iterate)
    InternalError           a bug in linkwork (an engine panic, caught): please report it
    LinkworkWarning         a warning (a UserWarning): e.g. a model file without units whose
                            numbers look like mm or degrees

Solve errors carry ``step`` and ``time`` (None where not known). A failed sweep's
exception also carries ``partial``: the `Results` of the steps before the failure.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "LinkworkError",
    "ModelError",
    "ExpressionError",
    "ClosureError",
    "InputError",
    "ScrewError",
    "SynthesisError",
    "ParameterError",
    "StudyError",
    "PortabilityError",
    "DependencyError",
    "SolveError",
    "AssemblyError",
    "ConvergenceError",
    "SingularError",
    "NonFiniteError",
    "CancelledError",
    "FreeModelError",
    "InitialConditionError",
    "MasslessError",
    "IntegrationError",
    "StiffnessError",
    "EquilibriumError",
    "InternalError",
    "LinkworkWarning",
]


class LinkworkError(Exception):
    """Base class of every linkwork error."""


class ModelError(LinkworkError, ValueError):
    """The mechanism description cannot be compiled."""


class ExpressionError(ModelError):
    """A text expression that is not one: ``column`` (1-based; 0 when the problem is not
    in the text), ``text`` and ``hint`` (a suggestion, or None) say where and why."""

    column: int = 0
    text: str = ""
    hint: str | None = None


class ClosureError(ModelError):
    """A drawing that does not close: a joint gives both its drawn point and its pins in the
    bodies' frames, and they disagree (or, closed keeping the pins, the joints cannot all
    hold). ``joint`` names the joint that misses most, ``miss`` by how much (the model's
    length unit). ``Mechanism.close = "given"`` or ``"drawn"`` (the model file's ``close``)
    asks the engine to close it."""

    joint: str = ""
    miss: float = 0.0


class InputError(LinkworkError, ValueError):
    """Bad input to a solve: a time grid, a starting guess."""

    step: int | None = None
    time: float | None = None
    partial: Any = None


class ScrewError(LinkworkError, ValueError):
    """Degenerate geometry or bad input in `linkwork.screw`; the message names the joints
    at fault (e.g. "joints 2 and 3 coincide")."""


class SynthesisError(LinkworkError, ValueError):
    """A synthesis problem without a well-posed answer: the wrong number of precision
    points for an exact method, coincident or collinear points, non-finite input; the
    message names the points at fault."""


class ParameterError(LinkworkError, ValueError):
    """A design parameter that is not one: an unknown kind, body, joint, driver or field,
    or a value that is not a finite number; the message names it and lists what exists."""


class StudyError(LinkworkError, ValueError):
    """A design study that cannot be run as asked: a bad study file or design space, an
    unknown output."""


class PortabilityError(StudyError):
    """A model that cannot travel to another process: its Python laws are functions of this
    interpreter, not data (use an expression, spline or other built-in law instead)."""


class DependencyError(LinkworkError, ImportError):
    """An optional package is missing (pandas, pyarrow, ezdxf, ...); the message names
    what needs it and the pip command that installs it."""


class SolveError(LinkworkError):
    """A solve could not be completed; ``step``, ``time`` and ``partial`` say where."""

    step: int | None = None
    time: float | None = None
    partial: Any = None


class AssemblyError(SolveError):
    """No configuration satisfies the constraints at the first time."""


class ConvergenceError(SolveError):
    """Newton-Raphson did not converge at a time step."""


class SingularError(SolveError):
    """Phi_q is singular: a dead point, a lock-up, or redundant constraints."""


class NonFiniteError(SolveError):
    """A NaN or an infinity appeared in a residual, step, velocity or acceleration."""


class CancelledError(SolveError):
    """The sweep was stopped by its progress callback."""


class FreeModelError(SolveError):
    """A kinematic solve (sweep, solve, batch) of a model compiled with free coordinates
    (``compile(free=True)``): simulate it (``Model.simulate``) or add drivers."""


class InitialConditionError(SolveError):
    """Initial positions or rates that the constraints do not hold: projecting them onto
    the constraints would move them by more than the tolerance (the message says how far
    and where)."""


class MasslessError(SolveError):
    """The mass matrix is singular on the motions the constraints allow: a free
    coordinate without mass; the message names the body."""


class IntegrationError(SolveError):
    """A simulation step could not be taken (the step size fell below its floor, Newton
    diverged); ``partial`` holds the steps done."""


class StiffnessError(IntegrationError):
    """The explicit method (``rk8``) is held by stability rather than accuracy: a stiff
    spring or damper for the steps it takes (Hairer's stiffness test of DOP853). The
    message names the stiffest load and suggests ``method="gen-alpha"``; ``partial``
    holds the steps done."""


class EquilibriumError(SolveError):
    """No rest configuration was found (`Model.equilibrium`): the loads do not balance
    near the guess (a constant torque on a free crank), or Newton ran out of iterations.
    ``q`` is the last iterate, ``iterations`` how many were taken, ``force`` the
    unbalanced generalized force left (scaled coordinates) and ``coordinate`` where it is
    largest."""

    q: Any = None
    iterations: int = 0
    force: float = float("nan")
    coordinate: str = ""


class InternalError(LinkworkError):
    """A bug in linkwork: the engine panicked. The message names the operation; please
    report it with the model. A sweep that hits one keeps its good steps (``partial``)."""


class LinkworkWarning(UserWarning):
    """Something probably wrong that does not stop the work (a model file without a units
    header whose numbers look like mm or degrees)."""
