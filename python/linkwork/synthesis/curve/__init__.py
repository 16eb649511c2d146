"""Synthesis from a curve: four-bars whose coupler point follows a designer's target
(points, a CSV table or an SVG path), by the tracking error refined with the engine's
exact sensitivities from many starting designs."""

from .fit import CURVE_MERIT, CurveDesign, CurveFit, fit, random_seeds, refine
from .target import TargetCurve, from_csv, from_svg, svg_path_points, target
from .tracking import DESIGN, CircuitError, TrackingProblem, coupler_points

__all__ = [
    "CURVE_MERIT",
    "CurveDesign",
    "CurveFit",
    "fit",
    "random_seeds",
    "refine",
    "TargetCurve",
    "from_csv",
    "from_svg",
    "svg_path_points",
    "target",
    "DESIGN",
    "CircuitError",
    "TrackingProblem",
    "coupler_points",
]
