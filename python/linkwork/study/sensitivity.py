"""Exact sensitivities of a sweep to design parameters: dq/dp, dqd/dp, dqdd/dp per step,
and of named points, from the engine (the implicit function theorem on the sweep's
factorization of Phi_q, each joint's rows differentiated exactly; no differences); with
``efforts=True``, of the inverse dynamics' multipliers too (dlambda/dp, hence each
driver's effort), from Phi_q^T dlambda/dp = dQ/dp - (dPhi_q/dp)^T lambda.

Parameters are named as in `linkwork.study.naming`:

- description paths the engine maps exactly onto its numbers: a revolute's ``at`` (or
  ``pin_a``/``pin_b``), a distance joint's ``at_a``/``at_b``/``length``, a prismatic
  joint's ``at`` (its translation drivers too), a point-on-line's ``at``/``through``/
  ``offset``, a rack's ``radius``, a gear's or belt's ``ratio``, ``radius_a`` and
  ``radius_b`` (its coefficients and the drawing's row constant move; refused where the
  two radii are equal, where the derivative is one-sided), a cam follower's ``at`` and
  roller ``radius``, a distance or coordinate driver's points, a driver's closed-form law
  fields (``drivers.D.law.rate``: constant, linear, polynomial, harmonic), a named point's
  ``points.P.at.0``; and the engine's own numbers, ``constraints.<joint>.<number>``;
- the friendly names that are one direction in those numbers: ``pin J@body.x`` (the pin's
  place in that body only), ``pivot J.x``, ``point P.x``, ``law D.field``, ``ratio G``,
  ``radius_a G``, ``radius_b G`` and ``length body`` (the moved pin's place in the body
  along the link, exactly what `apply`'s redraw does to first order);
- the inverse dynamics' numbers: a body's ``mass``, ``inertia`` and ``com`` (``mass
  crank``, ``bodies.crank.com.0``), ``gravity.0``/``gravity.1``, and a load's numbers (a
  force's ``at``, ``direction`` and closed-form law fields, a torque's law fields, a
  spring's ``at_a``, ``at_b``, ``stiffness``, ``free_length``, ``damping``, a torsion
  spring's ``stiffness``, ``free_angle``, ``damping``). The kinematics does not depend on
  them: their dq/dp are exactly zero, their effort sensitivities are not.

Anything else (a body's drawn pose, a table, expression or Python law, a load following
one) raises `ParameterError` naming it: vary it by differences of whole sweeps
(`linkwork.study.central_differences`). Every load is differentiated along the motion
whatever its law (a law is of time alone); only a number inside a law the engine cannot
differentiate is refused.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _args, _core
from ..errors import ParameterError
from ..model.progress import ProgressBar
from ..model.results import Results
from .naming import Parameter, parameters

if TYPE_CHECKING:
    from linkwork import Model

__all__ = ["Sensitivities", "sensitivities", "engine_directions"]


@dataclass(frozen=True)
class Sensitivities:
    """A sweep's exact sensitivities: ``names`` (the parameters, as given), ``nominal``,
    ``columns`` (the model's coordinates), ``times``, ``dq``, ``dqd``, ``dqdd`` (n_steps x
    n_coords x n_params; ``dqd`` and ``dqdd`` None unless ``derivatives`` asked for them),
    ``points`` (name -> n_steps x 2 x n_params, the world position's; ``points_d`` and
    ``points_dd`` the velocity's and acceleration's, empty unless asked for), ``results``
    (the sweep itself), ``derivatives`` (0, 1 or 2), and how they were solved: ``path``
    ("structured": each group of the mechanism's closed form differentiated, for dq/dp of
    cranks and dyads; "general": Phi_q factored at every step), ``path_reason``, and
    ``general_steps`` (on the structured path, the steps next to a singular configuration
    the general path solved). With ``efforts=True``: ``dlambda`` (n_steps x n_rows x
    n_params, the multipliers') and ``efforts`` (driver name -> n_steps x n_params, d
    `Results.effort` / dp), and ``results`` has its forces; otherwise None and empty."""

    names: list[str]
    nominal: list[float]
    columns: list[str]
    times: np.ndarray
    dq: np.ndarray = field(repr=False)
    dqd: np.ndarray | None = field(repr=False)
    dqdd: np.ndarray | None = field(repr=False)
    points: dict[str, np.ndarray] = field(repr=False)
    points_d: dict[str, np.ndarray] = field(repr=False)
    points_dd: dict[str, np.ndarray] = field(repr=False)
    results: Results = field(repr=False)
    dlambda: np.ndarray | None = field(default=None, repr=False)
    efforts: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    derivatives: int = 2
    path: str = "general"
    path_reason: str = ""
    general_steps: int = 0

    def column(self, name: str, derivative: int = 0) -> np.ndarray:
        """n_steps x n_params: the sensitivities of one coordinate ("rocker.theta"), of
        its rate (``derivative=1``) or its acceleration (2)."""
        if name not in self.columns:
            raise ParameterError(f"no coordinate {name!r}; the coordinates are {', '.join(self.columns)}")
        a = (self.dq, self.dqd, self.dqdd)[derivative]
        if a is None:
            solved = f"derivatives={self.derivatives}"
            raise ParameterError(f"derivative {derivative} of the sensitivities was not solved ({solved})")
        return a[:, self.columns.index(name), :]

    def effort(self, driver: str) -> np.ndarray:
        """n_steps x n_params: the sensitivities of a driver's effort (the torque or force
        of `Results.effort`)."""
        if self.dlambda is None:
            raise ParameterError(
                "no effort sensitivities here: Model.sensitivities(..., efforts=True) solves them"
            )
        if driver not in self.efforts:
            raise ParameterError(f"no driver {driver!r}; the drivers are {', '.join(self.efforts) or 'none'}")
        return self.efforts[driver]


def _theta0(model: Model, body: str) -> float:
    return 0.0 if body == "ground" else float(model.q_start[model._column_index[f"{body}.theta"]])


def engine_directions(model: Model, p: Parameter) -> dict[str, float]:
    """The engine parameters (names) and weights whose combination is ``p``: one path
    with weight 1 (a torsion spring's numbers per degree in a file in degrees: the
    engine's are per radian), or a pin's local coordinates in one body. Raises
    `ParameterError` for a parameter that is not one direction in the engine's numbers."""
    if p.kind == "path":
        return {".".join(str(k) for k in p.path): _per_engine_unit(model, p.path)}
    joint = next(j for j in model.description["joints"] if j["name"] == p.joint)
    side = "u_a" if joint["body_a"] == p.body else "u_b"
    if p.kind == "pin":
        world = [0.0, 0.0]
        world[p.axis] = 1.0
    else:
        # a length: the moved pin slides along the link, away from the anchor
        anchor = next(j for j in model.description["joints"] if j["name"] == p.anchor)
        d = [joint["at"][0] - anchor["at"][0], joint["at"][1] - anchor["at"][1]]
        norm = math.hypot(d[0], d[1])
        world = [d[0] / norm, d[1] / norm]
    # d local / d world = A(theta_0)^T in the body's drawn frame (theta in rad)
    c, s = math.cos(_theta0(model, p.body)), math.sin(_theta0(model, p.body))
    local = [c * world[0] + s * world[1], -s * world[0] + c * world[1]]
    out = {f"constraints.{p.joint}.{side}.x": local[0], f"constraints.{p.joint}.{side}.y": local[1]}
    return {k: v for k, v in out.items() if v != 0.0}


def _per_engine_unit(model: Model, path: tuple[Any, ...]) -> float:
    """d engine number / d description number: 1 but for a torsion spring's numbers in a
    description in degrees, which the engine keeps per radian."""
    if path[0] != "loads" or str((model.description.get("units") or {}).get("angle", "rad")) != "deg":
        return 1.0
    load = next(item for item in model.description["loads"] if item.get("name") == path[1])
    if load.get("type") != "torsion_spring":
        return 1.0
    to_rad = math.pi / 180.0
    return {"free_angle": to_rad, "stiffness": 1.0 / to_rad, "damping": 1.0 / to_rad}.get(str(path[2]), 1.0)


def sensitivities(
    model: Model,
    times: Any,
    names: Sequence[Any],
    points: Sequence[str] | None = None,
    q_guess: Any = None,
    progress: Callable[[int, int], Any] | bool | None = None,
    derivatives: int = 2,
    efforts: bool = False,
) -> Sensitivities:
    """See `Model.sensitivities`."""
    t = _args.times(times)
    derivatives = _args.integer(derivatives, "derivatives", 0, 2)
    params = parameters(model.description, names)
    directions = [engine_directions(model, p) for p in params]
    engine = sorted({k for d in directions for k in d})
    named = {n: (k, b, ux, uy) for k, (n, b, ux, uy) in enumerate(model._core.points)}
    wanted = list(points) if points is not None else list(named)
    requests = []
    for name in wanted:
        if name not in named:
            raise ParameterError(f"no named point {name!r}; the points are {', '.join(named) or 'none'}")
        k, b, ux, uy = named[name]
        requests.append((b, ux, uy, k))
    progress = _args.callback(progress, "progress", allow_true=True)
    callback = ProgressBar() if progress is True else (progress or None)
    check = max(1, min(16384, 1_000_000 // max(1, model.n_coords)))
    try:
        raw, error = _core.sensitivities(
            model._core,
            t,
            engine,
            model._guess(q_guess),
            requests,
            callback,
            check if callback else 0,
            derivatives,
            bool(efforts),
        )
    except ParameterError as e:
        # the engine names its own path: say which of the user's parameters it came from
        bad = next((p.name for p, d in zip(params, directions) if any(k in str(e) for k in d)), None)
        raise ParameterError(f"parameter {bad!r}: {e}" if bad and bad not in str(e) else str(e)) from None
    # the user's parameters: combinations of the engine's (exact: the map is linear)
    weights = np.zeros((len(engine), len(params)))
    for j, d in enumerate(directions):
        for path, w in d.items():
            weights[engine.index(path), j] = w

    def combine(a: np.ndarray | None) -> np.ndarray | None:
        # a derivative not asked for: None
        return None if a is None else np.asarray(a @ weights)

    dq, dqd, dqdd = (combine(raw[k]) for k in ("dq", "dqd", "dqdd"))
    pts = [combine(raw[k]) for k in ("sens_points", "sens_points_d", "sens_points_dd")]

    def per_point(a: np.ndarray | None) -> dict[str, np.ndarray]:
        return {} if a is None else {n: a[:, i] for i, n in enumerate(wanted)}

    results = Results(model, raw, None)
    assert dq is not None  # the positions' are always solved
    dlambda = combine(raw["dlambda"]) if efforts else None
    drivers: dict[str, np.ndarray] = {}
    if dlambda is not None:
        # a driver's effort is -lambda of its row, as `Results.effort` reads it
        drivers = {c[0]: -dlambda[:, c[4], :] for c in model.constraints if c[1] == "driver"}
    out = Sensitivities(
        [p.name for p in params],
        [p.nominal for p in params],
        list(model.columns),
        np.asarray(raw["times"]),
        dq,
        dqd,
        dqdd,
        per_point(pts[0]),
        per_point(pts[1]),
        per_point(pts[2]),
        results,
        dlambda,
        drivers,
        int(raw["derivatives"]),
        str(raw["path"]),
        str(raw["path_reason"]),
        int(raw["general_steps"]),
    )
    if error is not None:
        setattr(error, "partial", out)  # noqa: B010 (raised from the engine's tuple)
        raise error
    return out
