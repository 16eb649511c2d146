"""Design studies: design parameters named in a model's description, design spaces
(grids, Latin hypercubes, lists), tolerance analysis (Monte Carlo and first-order), each
design swept and reduced where it runs, in-process on all cores or on a Dask cluster.

- `naming`: a number of the model named (`parameters`); `redraw`: `apply`, the varied model redrawn;
- `designs`: grids, Latin hypercubes, listed designs, tolerances and their samples;
- `outputs`: the figures kept of each design (reductions of its sweep);
- `run`: `Study`, the three scales, `StudyResult`;
- `dataset`: the labelled dataset (xarray, pandas), NetCDF and Parquet with units;
- `sensitivity`: exact sensitivities of a sweep to parameters (`Model.sensitivities`);
- `tolerance`: Monte Carlo and first-order tolerance analysis; `report`: its report.
"""

from .dataset import open_dataset
from .designs import Designs, Interval, Normal, Uniform, grid, latin_hypercube, listed, sample
from .naming import KINDS, Parameter, parameter, parameters
from .outputs import NAMES as OUTPUTS
from .outputs import Output
from .redraw import apply, apply_many
from .report import atlas_figure, study_report, tolerance_report
from .run import Job, Study, StudyResult, run_chunk
from .sensitivity import Sensitivities, engine_directions, sensitivities
from .tolerance import Linear, ToleranceResult, central_differences, components, propagate, tolerance_study

__all__ = [
    "KINDS",
    "OUTPUTS",
    "Designs",
    "Interval",
    "Job",
    "Linear",
    "Normal",
    "Output",
    "Parameter",
    "Study",
    "StudyResult",
    "Sensitivities",
    "ToleranceResult",
    "Uniform",
    "apply",
    "apply_many",
    "atlas_figure",
    "central_differences",
    "engine_directions",
    "components",
    "grid",
    "latin_hypercube",
    "listed",
    "open_dataset",
    "parameter",
    "parameters",
    "propagate",
    "run_chunk",
    "sample",
    "sensitivities",
    "study_report",
    "tolerance_report",
    "tolerance_study",
]
