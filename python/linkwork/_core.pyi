# Hand-written stub of the compiled module (checked by mypy.stubtest in the test suite).
from collections.abc import Sequence
from typing import Any, Callable, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "ArmState",
    "Model",
    "SerialArm",
    "__version__",
    "evaluate_law",
    "parse_expression",
    "screw_centres_by_kennedy",
    "screw_centres_from_velocities",
    "screw_join",
    "screw_loop_singularity",
    "screw_meet",
    "screw_normalize",
    "mobility",
    "structure",
    "linkages",
    "assembly_modes",
    "motion_limits",
    "read_model",
    "constraint_roles",
    "write_model",
    "screw_transport",
    "sweep_batch",
    "simulate",
    "load_powers",
    "simulation_rows",
    "equilibrium",
    "sweep_variants",
    "sensitivities",
    "_check_panic_guard",
    "synth_chebyshev",
    "synth_dyads",
    "synth_freudenstein",
    "synth_motion",
    "synth_start_set",
    "synth_alt",
]
__version__: str

def sweep_batch(
    models: list[Model],
    times: npt.NDArray[np.float64],
    threads: int = 0,
    derivatives: int = 2,
    forces: bool = False,
    progress: Callable[[int, int], Any] | None = None,
    every: int = 1,
    on_singular: str = "continue",
    locks: bool = False,
    branches_of: Model | None = None,
    outputs: list[tuple[list[int] | None, list[tuple[int, float, float]] | None]] | None = None,
) -> list[tuple[dict[str, Any], BaseException | None]]: ...
def simulate(
    model: Model,
    times: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64] | None = None,
    qd0: npt.NDArray[np.float64] | None = None,
    method: str = "rk8",
    rtol: float = 1e-8,
    atol: float = 1e-8,
    rho_inf: float = 0.9,
    h0: float | None = None,
    h_max: float | None = None,
    max_steps: int | None = None,
    ic_tol: float = 1e-6,
    progress: Callable[[int, int], Any] | None = None,
    at_travel_end: str = "stop",
) -> tuple[dict[str, Any], BaseException | None]: ...
def simulation_rows(
    model: Model,
    times: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    qd: npt.NDArray[np.float64],
) -> dict[str, npt.NDArray[np.float64]]: ...
def load_powers(
    model: Model,
    times: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    qd: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]: ...
def sensitivities(
    model: Model,
    times: npt.NDArray[np.float64],
    parameters: list[str],
    q_guess: npt.NDArray[np.float64] | None = None,
    points: list[tuple[int, float, float, int]] | None = None,
    progress: Callable[[int, int], Any] | None = None,
    progress_every: int = 0,
    derivatives: int = 2,
    efforts: bool = False,
) -> tuple[dict[str, Any], BaseException | None]: ...
def sweep_variants(
    model: Model,
    parameters: list[str],
    deltas: npt.NDArray[np.float64],
    times: npt.NDArray[np.float64],
    coords: list[int],
    points: list[tuple[int, float, float, int]],
    derivatives: int = 0,
    on_singular: str = "continue",
    threads: int = 0,
    progress: Callable[[int, int], Any] | None = None,
) -> dict[str, Any]: ...
def equilibrium(
    model: Model,
    t: float = 0.0,
    q_guess: npt.NDArray[np.float64] | None = None,
    max_iter: int = 100,
    tol_force: float = 1e-12,
    max_step: float = 0.5,
) -> dict[str, Any]: ...
def parse_expression(text: str, variable: str = "t") -> None: ...
def evaluate_law(
    law_json: str,
    times: npt.NDArray[np.float64],
    python_laws: dict[str, Callable[[float], Any]] | None = None,
) -> npt.NDArray[np.float64]: ...
def linkages(
    model: Model,
    t: float = 0.0,
    q_guess: npt.NDArray[np.float64] | None = None,
    assemble: bool = True,
) -> tuple[npt.NDArray[np.float64], list[dict[str, Any]]]: ...
def assembly_modes(
    model: Model,
    t: float = 0.0,
    q_guess: npt.NDArray[np.float64] | None = None,
    tries: int = 200,
) -> tuple[int, int, list[tuple[npt.NDArray[np.float64], float, float, list[dict[str, Any]]]]]: ...
def mobility(
    model: Model,
    t: float = 0.0,
    q_guess: npt.NDArray[np.float64] | None = None,
    assemble: bool = True,
) -> dict[str, Any]: ...
def structure(model: Model) -> dict[str, Any]: ...
def motion_limits(
    model: Model,
    driver: str,
    t: float = 0.0,
    q_guess: npt.NDArray[np.float64] | None = None,
    range: float | None = None,
    steps: int | None = None,
) -> dict[str, Any]: ...
def read_model(text: str, format: str, file: str) -> tuple[str, list[tuple[str, str, int]]]: ...
def _check_panic_guard() -> None: ...
def write_model(description_json: str, format: str) -> str: ...
def constraint_roles() -> list[dict[str, Any]]: ...

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
        redundant: str = "error",
        solver: str = "auto",
        free: bool = False,
        python_laws: dict[str, Callable[[float], Any]] | None = None,
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
    def dof(self) -> int: ...
    @property
    def nnz(self) -> int: ...
    @property
    def columns(self) -> list[str]: ...
    @property
    def body_names(self) -> list[str]: ...
    @property
    def length_scale(self) -> float: ...
    @property
    def solver(self) -> str: ...
    @property
    def fallback(self) -> str | None: ...
    @property
    def linear(self) -> str: ...
    @property
    def q_start(self) -> npt.NDArray[np.float64]: ...
    @property
    def constraints(self) -> list[tuple[str, str, str, int, int]]: ...
    @property
    def closing(self) -> dict[str, Any] | None: ...
    @property
    def indeterminate(self) -> list[str]: ...
    @property
    def points(self) -> list[tuple[str, int, float, float]]: ...
    def solve(
        self, t: float, q_guess: npt.NDArray[np.float64] | None = None
    ) -> tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        int,
        float,
        float,
        list[dict[str, Any]],
    ]: ...
    def sweep(
        self,
        times: npt.NDArray[np.float64],
        q_guess: npt.NDArray[np.float64] | None = None,
        progress: Callable[[int, int], Any] | None = None,
        progress_every: int = 16384,
        forces: bool = False,
        derivatives: int = 2,
        every: int = 1,
        on_singular: str = "continue",
        locks: bool = False,
        coords: list[int] | None = None,
        points: list[tuple[int, float, float]] | None = None,
    ) -> tuple[dict[str, Any], BaseException | None]: ...
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
    @property
    def units(self) -> list[tuple[str, str]]: ...

# -- screw theory (crates/linkwork-py/src/screw.rs; public API: linkwork.screw) ---------

_F = npt.NDArray[np.float64]
_V3 = tuple[float, float, float] | list[float]

@final
class SerialArm:
    """A serial planar arm of revolute and prismatic joints (see `linkwork.screw.SerialArm`)."""

    def __new__(
        cls, joints: list[tuple[str, str, tuple[float, float], tuple[float, float]]], end: _V3
    ) -> SerialArm: ...
    @staticmethod
    def from_links(kinds: str, lengths: list[float]) -> SerialArm: ...
    @staticmethod
    def from_description(description_json: str, end_point: str | None = None) -> SerialArm: ...
    @property
    def names(self) -> list[str]: ...
    @property
    def kinds(self) -> str: ...
    @property
    def home_positions(self) -> _F: ...
    @property
    def home_axes(self) -> _F: ...
    @property
    def end_home(self) -> tuple[float, float, float]: ...
    @property
    def end_body(self) -> int | None: ...
    @property
    def gauge(self) -> tuple[tuple[float, float], float]: ...
    def joint_values(self, q: _F, qd: _F) -> tuple[_F, _F]: ...
    def model_end(self, q: _F, qd: _F) -> tuple[tuple[float, float, float], _F]: ...
    def forward(self, q: _F) -> ArmState: ...

@final
class ArmState:
    """An arm at one configuration (see `linkwork.screw.ArmState`)."""

    @property
    def names(self) -> list[str]: ...
    @property
    def kinds(self) -> str: ...
    @property
    def q(self) -> _F: ...
    @property
    def points(self) -> _F: ...
    @property
    def positions(self) -> _F: ...
    @property
    def axes(self) -> _F: ...
    @property
    def end(self) -> tuple[float, float, float]: ...
    @property
    def jacobian(self) -> _F: ...
    @property
    def gauge(self) -> tuple[tuple[float, float], float]: ...
    def twist(self, w: _F) -> list[float]: ...
    def pole(self, w: _F) -> list[float]: ...
    def end_velocity(self, w: _F) -> list[float]: ...
    def velocity_centres(self, w: _F) -> tuple[list[tuple[int, int]], _F]: ...
    def torque_centres(self, tau: _F) -> tuple[list[tuple[int, int]], _F]: ...
    def inverse_velocity(self, twist: _V3, given: list[tuple[int, float]] | None = None) -> _F: ...
    def inverse_velocity_barycentre(
        self, twist: _V3, given: list[tuple[int, float]] | None = None
    ) -> tuple[_F, list[float], int | None, list[float] | None]: ...
    def line_screws(self, unknown: tuple[int, int, int]) -> _F: ...
    def torques(self, wrench: _V3) -> _F: ...
    def lever_arms(self, wrench: _V3) -> _F: ...
    def force(self, tau: _F, through: tuple[float, float] | None = None) -> list[float]: ...
    def dependencies(self) -> list[list[int]]: ...

def screw_join(p: _V3, q: _V3, centre: tuple[float, float] = ..., scale: float = 1.0) -> list[float]: ...
def screw_meet(l: _V3, k: _V3, centre: tuple[float, float] = ..., scale: float = 1.0) -> list[float]: ...
def screw_normalize(p: _V3, centre: tuple[float, float] = ..., scale: float = 1.0) -> list[float]: ...
def screw_transport(kind: str, to: str, pose: _V3, v: _V3) -> list[float]: ...
def screw_centres_from_velocities(description_json: str, q: _F, qd: _F) -> dict[str, Any]: ...
def screw_centres_by_kennedy(description_json: str, q: _F) -> dict[str, Any]: ...
def screw_loop_singularity(description_json: str, q: _F, tol: float = 1e-9) -> dict[str, Any]: ...

# synthesis (linkwork.synthesis)
def synth_dyads(
    problem: str,
    method: str,
    poses_or_points: Sequence[float],
    angles_a: Sequence[float] = ...,
    angles_b: Sequence[float] = ...,
    point: Sequence[float] = ...,
) -> dict[str, Any]: ...
def synth_motion(
    problem: str,
    poses_flat: Sequence[float],
    point: Sequence[float] = ...,
    along: float = 0.0,
    samples: int = 360,
) -> dict[str, Any]: ...
def synth_freudenstein(
    kind: str, input: Sequence[float], output: Sequence[float], ground: float
) -> list[float]: ...
def synth_chebyshev(lo: float, hi: float, n: int) -> list[float]: ...
def synth_start_set() -> tuple[int, int, int]: ...
def synth_alt(
    points: Sequence[float], hatted: Sequence[float] | None = None, seconds: float = 30.0
) -> dict[str, Any]: ...
