"""Synthesis from a curve: four-bars whose coupler point follows a designer's target
(points, a CSV table or an SVG path), by the tracking error refined with the engine's
exact sensitivities from many starting designs (random, the atlas's nearest curves, Alt's
four-bars through nine points of the target); the shape problem (position, rotation,
scale and start free); the shape of a curve (elliptic Fourier
descriptors, the shape error) and an atlas of normalised four-bar coupler curves to start
from; Watt and Stephenson six-bars grown from the best four-bars where a four-bar cannot
follow the curve."""

from .atlas import Atlas, AtlasHit, build_atlas
from .atlas import load as load_atlas
from .descriptors import ShapeFit, shape_error
from .fit import CURVE_MERIT, USABLE_TRANSMISSION, CurveDesign, CurveFit, fit, random_seeds, refine
from .seeds import Seed, Seeds, alt_seeds, atlas_seeds, make_seeds
from .shape import ShapeDesign, ShapeResult, shape_fit
from .six_bar_fit import SixBarDesign, SixBarFit, dyad_seeds, fit_six_bars, refine_six_bar
from .six_bars import SixBarProblem
from .target import TargetCurve, from_csv, from_svg, svg_path_points, target
from .tracking import DESIGN, CircuitError, TrackingProblem, coupler_points

__all__ = [
    "Atlas",
    "AtlasHit",
    "build_atlas",
    "load_atlas",
    "ShapeFit",
    "shape_error",
    "CURVE_MERIT",
    "USABLE_TRANSMISSION",
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
    "Seed",
    "Seeds",
    "alt_seeds",
    "atlas_seeds",
    "make_seeds",
    "ShapeDesign",
    "ShapeResult",
    "shape_fit",
    "SixBarDesign",
    "SixBarFit",
    "SixBarProblem",
    "dyad_seeds",
    "fit_six_bars",
    "refine_six_bar",
]
