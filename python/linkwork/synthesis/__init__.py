"""Synthesis: link dimensions from precision points, every solution, certified, and each
design screened by the engine.

Problems (lengths in any unit, angles in radians unless ``angles="deg"``):

- `motion` (motion generation): a body must take 2 to 5 poses (x, y, angle). Five poses:
  Burmester's dyads, all of them (at most 4), and the four-bars they pair into. Four:
  the circle-point and centre-point curves, sampled (`Curves`). Three: a moving (or
  ground) pivot chosen per dyad, the other by the circumcentre. Two: moving pivots
  chosen, ground pivots on the bisectors.
- `path` (path generation with prescribed timing): a coupler point through 5 points
  while the crank turns by 5 given angles: every input dyad (at most 4), each completed
  by the Burmester dyads of the coupler motion it implies.
- `function` (Freudenstein): a four-bar or slider-crank through 3 precision pairs
  (Chebyshev spacing by `chebyshev`), with its structural error over the range.
- `nine_points` (Alt's problem): every four-bar whose coupler curve passes nine points,
  by parameter homotopy from 1442 shipped generic classes, with the Roberts cognates.
- `motion_least_squares`: more than five poses, by least squares from the exact dyads of
  five-pose subsets, with bounds on link lengths and the transmission angle.
- `path_least_squares`: more than five timed points, the same way (the input dyad from
  the exact timed dyads of five-point subsets, then the follower from the motion it
  implies).
- `chained_six_bar`: the chained Stephenson six-bar (linkwork.synthesis.six_bar): a
  coupler point through 5 points while the input link and the coupler turn by given
  angles, every dyad of both problems and every six-bar they combine into.
- `dyads`: the raw dyad solutions of any of these, by "homotopy" (every root,
  alpha-certified) or "resultant" (the independent elimination, every root too,
  certified the same way; about 20 times faster on these problems).

Every exact solution is a root of a small polynomial system solved by parameter
homotopy (linkwork-homotopy): each comes with ``residual`` (largest change of its link
length over the positions), ``certified`` (Smale's alpha test: a root lies within
``radius``) and ``real`` (certified real). A `FourBarDesign` is a model the engine builds
and sweeps through its precision positions; its `Defects` say whether it reaches every
position in order on one circuit without a dead point. Designs sort by `MERIT`.
"""

from __future__ import annotations

from ..errors import SynthesisError
from .designs import MERIT, Curves, Defects, DyadDesign, FourBarDesign, Synthesis
from .dyad import POSITION_TOLERANCE, Dyad, DyadSolutions, dyads, generic_root_count
from .exact import (
    FunctionFourBar,
    NinePointResult,
    SliderCrankDesign,
    chebyshev,
    function,
    motion,
    nine_points,
    path,
)
from .least_squares import motion_least_squares, path_least_squares
from .six_bar import chained_six_bar

__all__ = [
    "Dyad",
    "DyadSolutions",
    "Defects",
    "DyadDesign",
    "FourBarDesign",
    "SliderCrankDesign",
    "FunctionFourBar",
    "Synthesis",
    "Curves",
    "MERIT",
    "POSITION_TOLERANCE",
    "dyads",
    "motion",
    "path",
    "function",
    "chebyshev",
    "generic_root_count",
    "nine_points",
    "NinePointResult",
    "motion_least_squares",
    "path_least_squares",
    "chained_six_bar",
    "SynthesisError",
]
