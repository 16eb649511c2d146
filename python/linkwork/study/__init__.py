"""Design studies: design parameters named in a model's description, design spaces
(grids, Latin hypercubes, lists), tolerance analysis (Monte Carlo and first-order), each
design swept and reduced where it runs, in-process on all cores or on a Dask cluster.
"""

from .parameters import KINDS, Parameter, apply, parameter, parameters

__all__ = ["KINDS", "Parameter", "apply", "parameter", "parameters"]
