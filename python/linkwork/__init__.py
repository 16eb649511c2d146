"""linkwork: planar mechanism kinematics in absolute coordinates."""

from .mechanism import GROUND, Body, Mechanism
from .motion import Constant, Harmonic, Law, Linear, Polynomial, Spline

__all__ = ["GROUND", "Body", "Mechanism", "Constant", "Harmonic", "Law", "Linear", "Polynomial", "Spline"]
