# Hand-written stub of the compiled module (checked by mypy.stubtest in the test suite).
from typing import Any, Callable, final

import numpy as np
import numpy.typing as npt

__all__ = ["Model", "__version__"]
__version__: str

@final
class Model:
    """A compiled mechanism (immutable; every solve gets its own workspace)."""

    def __new__(
        cls,
        description_json: str,
        *,
        tol_residual: float | None = None,
        tol_step: float | None = None,
        max_iter: int | None = None,
        max_iter_assembly: int | None = None,
        singular_tol: float | None = None,
        linear: str = "auto",
        dense_max: int | None = None,
    ) -> Model: ...
    @property
    def name(self) -> str: ...
    @property
    def n_bodies(self) -> int: ...
    @property
    def n_coords(self) -> int: ...
    @property
    def n_rows(self) -> int: ...
    @property
    def nnz(self) -> int: ...
    @property
    def columns(self) -> list[str]: ...
    @property
    def body_names(self) -> list[str]: ...
    @property
    def length_scale(self) -> float: ...
    @property
    def linear(self) -> str: ...
    @property
    def q_start(self) -> npt.NDArray[np.float64]: ...
    @property
    def constraints(self) -> list[tuple[str, str, str, int, int]]: ...
    @property
    def points(self) -> list[tuple[str, int, float, float]]: ...
    def solve(
        self, t: float, q_guess: npt.NDArray[np.float64] | None = None
    ) -> tuple[
        npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64], int, float, float
    ]: ...
    def sweep(
        self,
        times: npt.NDArray[np.float64],
        q_guess: npt.NDArray[np.float64] | None = None,
        progress: Callable[[int, int], Any] | None = None,
        progress_every: int = 16384,
        forces: bool = False,
    ) -> tuple[dict[str, npt.NDArray[Any]], BaseException | None]: ...
    def statics(
        self, t: float, q_guess: npt.NDArray[np.float64] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    @property
    def loads(self) -> list[tuple[str, str, int, int]]: ...
    @property
    def inertias(self) -> list[tuple[float, float, float, float]]: ...
    @property
    def anchors(self) -> list[tuple[str, str, int, int, float, float]]: ...
    @property
    def gravity(self) -> tuple[float, float]: ...
