"""A compiled model: the engine's immutable `Model`, with solve and sweep."""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .. import _args, _core
from ..errors import InputError, ModelError
from ..kinds import kind as kind_of
from .anchors import Anchor, traceable
from .equilibrium import Equilibrium
from .events import Event, MotionLimits
from .initial_rates import complete_rates
from .linkages import AssemblyMode, AssemblyModes, Linkage
from .mobility import Mobility
from .progress import ProgressBar
from .results import Kept, Results, State, Statics
from .simulation import Simulation
from .structure import Structure

__all__ = ["Model", "Cycle", "sweep_batch"]


@dataclass(frozen=True)
class Miss:
    """A joint's pin that missed its drawn point: ``miss`` (the model's length unit; for a
    prismatic joint, across the slide line), the pin ``given`` and the one the drawing
    puts there (``drawn``), both in the body's frame."""

    joint: str
    body: str
    pin: str
    miss: float
    given: tuple[float, float]
    drawn: tuple[float, float]


@dataclass(frozen=True)
class Closing:
    """How the engine closed a drawing that did not close, as asked (``close``): keeping
    the pins ``"given"`` (the bodies ``moved``, as (body, how far its origin moved, how far
    it turned in rad), to the nearest configuration where every joint holds, by least
    squares) or the ``"drawn"`` points (each pin where the drawing puts it)."""

    keep: str
    misses: tuple[Miss, ...]
    moved: tuple[tuple[str, float, float], ...]

    def report(self, length: str = "m", angles: str = "rad") -> str:
        """Lines for ``linkwork check``: what missed, what was kept, what moved."""
        k = math.degrees(1.0) if angles == "deg" else 1.0
        how = (
            "keeping the pins given, the bodies moved by least squares"
            if self.keep == "given"
            else "keeping the drawing's points, the pins given ignored"
        )
        lines = [f'  drawing closed          {how} (close = "{self.keep}")']
        for m in self.misses:
            kept = m.given if self.keep == "given" else m.drawn
            lines.append(
                f"    joint {m.joint!r}: {m.pin} of {m.body!r} missed its drawn point by "
                f"{m.miss:.3e} {length}; {m.pin} = ({kept[0]:.9g}, {kept[1]:.9g}) {length}"
            )
        for body, d, turn in self.moved:
            lines.append(f"    body {body!r} moved {d:.3e} {length} and turned {turn * k:.3e} {angles}")
        return "\n".join(lines)


@dataclass(frozen=True)
class Cycle:
    """One cycle of a model's periodic driver: the driver, the period (s) and how it
    was found ("2 pi / |rate|", "360 / |rate|", "2 pi / |omega|", "its period")."""

    driver: str
    period: float
    how: str

    def __str__(self) -> str:
        return f"one cycle of {self.driver}, {self.how} = {self.period:.6g} s"


class Model:
    """A mechanism compiled by the engine (validated; immutable).

    Options: ``tol_residual`` and ``tol_step`` (Newton tolerances on the scaled residual
    and step, default 1e-12), ``max_iter`` (25 per step), ``max_iter_assembly`` (100),
    ``singular_tol`` (pivot ratio under which Phi_q counts as singular, 1e-12),
    ``linear`` ("auto", "dense" or "sparse" LU), ``dense_max`` (largest model solved
    densely by "auto", in coordinates) and ``redundant``: "error" (default) refuses a
    model whose joint rows are dependent (a third parallel crank, a doubled pin), naming
    them; "solve" solves it anyway, all rows in the least-squares sense (dense QR; exact
    while the rows stay consistent, and which rows are independent may change along the
    motion). Positions, velocities and accelerations are then still unique; the
    reactions of the joints in ``indeterminate`` are not (the minimum-norm set is given),
    and ``det_sign`` is not defined (reported as +1).
    ``solver``: "auto" (default) solves a sweep's steps group by group where the
    mechanism's structure allows (closed-form dyads, small Newton blocks; ``structure()``
    shows how), the general sparse Newton otherwise and at every step near a singular
    configuration; "general" always the general path.
    ``free``: True keeps degrees of freedom free: a model with fewer rows than
    coordinates compiles, its motion following from forces (`simulate`); every kinematic
    solve refuses it (`FreeModelError`).
    ``python_laws``: name -> function for the description's ``{"type": "python"}`` laws
    (a `Mechanism` passes its own).
    """

    def __init__(self, mechanism: Any, **options: Any) -> None:
        if not hasattr(mechanism, "to_dict"):
            _args.mapping(mechanism, "mechanism")
        options = _options(options)
        if hasattr(mechanism, "assemble"):
            mechanism = mechanism.assemble()  # a mechanism given by its pins, drawn first
        desc = mechanism.to_dict() if hasattr(mechanism, "to_dict") else dict(mechanism)
        _check_finite(desc)
        self.description: dict[str, Any] = desc
        # the functions of PythonLaw laws travel beside the JSON (a dict may pass them too)
        python_laws = {**getattr(mechanism, "python_laws", {}), **(options.pop("python_laws", None) or {})}
        # kept to rebuild the model elsewhere (pickling: the description plus its options)
        self._options: dict[str, Any] = options
        self._python_laws = python_laws
        self._core = _core.Model(json.dumps(desc), python_laws=python_laws or None, **options)
        # immutable: asked once (each ask builds a new list in the engine; results ask per column)
        self._columns: list[str] = list(self._core.columns)
        self._body_names: list[str] = list(self._core.body_names)
        self._column_index = {c: i for i, c in enumerate(self._columns)}
        # what a sweep keeps unless told otherwise: the description's outputs, or everything
        said = desc.get("outputs")
        self._default_outputs = self._outputs(said, ModelError) if said else None

    @classmethod
    def _checked(cls, desc: dict[str, Any], options: dict[str, Any]) -> Model:
        """The model of a description already known finite and options already checked
        (design studies build thousands): the same model as ``Model(desc, **options)``."""
        self = cls.__new__(cls)
        self.description = desc
        self._options, self._python_laws = dict(options), {}
        self._core = _core.Model(json.dumps(desc), python_laws=None, **options)
        self._columns = list(self._core.columns)
        self._body_names = list(self._core.body_names)
        self._column_index = {c: i for i, c in enumerate(self._columns)}
        return self

    name = property(lambda self: self._core.name, doc="The mechanism's name.")
    n_bodies = property(lambda self: self._core.n_bodies, doc="Moving bodies.")
    n_coords = property(
        lambda self: self._core.n_coords,
        doc="Coordinates: 3 per moving body, then one per joint with its own (a curve parameter).",
    )
    n_rows = property(lambda self: self._core.n_rows, doc="Constraint rows (joints and drivers).")
    dof = property(
        lambda self: self._core.dof,
        doc="Degrees of freedom left free (a model compiled with ``free=True``; 0 otherwise).",
    )
    columns = property(lambda self: self._columns, doc="Names of the coordinates (do not modify).")
    body_names = property(lambda self: self._body_names, doc="Names of the moving bodies (do not modify).")
    linear = property(lambda self: self._core.linear, doc="'dense' or 'sparse' LU.")
    solver = property(
        lambda self: self._core.solver,
        doc="'structured' (the groups one after another) or 'general' (one sparse system).",
    )
    fallback = property(
        lambda self: self._core.fallback,
        doc="Why the general path solves the whole model (None when it is structured).",
    )
    length_scale = property(lambda self: self._core.length_scale, doc="L: lengths are measured in L.")
    q_start = property(lambda self: self._core.q_start, doc="The starting configuration as described.")
    indeterminate = property(
        lambda self: self._core.indeterminate,
        doc="Joints whose reactions kinematics does not determine (their rows are dependent).",
    )

    @property
    def closing(self) -> Closing | None:
        """How a drawing that did not close was closed (`Mechanism.close`, the model file's
        ``close``), or None where it closed as drawn (or nothing was given twice)."""
        raw = self._core.closing
        if raw is None:
            return None
        misses = tuple(Miss(j, b, p, float(m), tuple(g), tuple(d)) for j, b, p, m, g, d in raw["misses"])  # type: ignore[arg-type]
        moved = tuple((str(b), float(d), float(t)) for b, d, t in raw["moved"])
        return Closing(str(raw["keep"]), misses, moved)

    @property
    def units(self) -> dict[str, str]:
        """The unit of every quantity in and out of the model: ``length`` as declared ("m"
        or "mm"), ``angle`` "rad" (results are always in radians; ``input_angle`` is the
        declared unit of the description's angles), ``time`` s, ``mass`` kg, and the
        derived ``force``, ``torque``, ``power``, ``energy``, ``stiffness``, ``inertia``.

        >>> from linkwork import examples
        >>> u = examples.four_bar().compile().units
        >>> (u["length"], u["angle"], u["force"], u["torque"])
        ('m', 'rad', 'N', 'N m')
        """
        return dict(self._core.units)

    @property
    def constraints(self) -> list[tuple[str, str, str, int, int]]:
        """(name, role, type, n_rows, first row) of every joint and driver."""
        return self._core.constraints

    def __repr__(self) -> str:
        return repr(self._core)

    @property
    def options(self) -> dict[str, Any]:
        """The compile options the model was built with (a copy)."""
        return dict(self._options)

    def __reduce__(self) -> tuple[Any, ...]:
        """A model pickles as its description and options (the engine's compiled form is
        rebuilt on the other side, identically). A model with Python laws cannot travel:
        `PortabilityError` names them."""
        if self._python_laws:
            from ..errors import PortabilityError

            names = ", ".join(sorted(self._python_laws))
            raise PortabilityError(
                f"model {self.name!r} cannot be pickled or sent to another process: its Python laws "
                f"({names}) are functions of this interpreter, not data; describe them with a built-in "
                "law (expression, spline, polynomial, ...) instead"
            )
        return (_rebuild, (self.description, self._options))

    def draw(self, ax: Any = None, t: float = 0.0) -> Any:
        """Draws the model assembled at time ``t`` (on the drawing's branch, as `solve`) on
        matplotlib axes ``ax`` (default: a new figure); returns the axes."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import draw_model

        return draw_model(self, ax, t)

    def _repr_html_(self) -> str:
        """What a notebook shows: counts, units, degrees of freedom, structure and the drawing."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import model_html

        return model_html(self)

    def solve(
        self,
        t: float = 0.0,
        q_guess: Sequence[float] | np.ndarray | None = None,
        branch: str | dict[str, str] | None = None,
    ) -> State:
        """Position, velocity and acceleration at time ``t``.

        By default on the drawing's branch: the drawing is assembled at its time (0, or
        the nearest time the drivers are defined at) and followed along the drivers to
        ``t`` in certified steps, so a time far from the drawing (``solve(100.0)``) gets
        the drawing's configuration continued; singular configurations crossed on the way
        are in the state's ``events``. With ``q_guess``, assembled at ``t`` from it; with
        ``branch``, on the assembly mode it names: "open" / "crossed", or {linkage: circuit}
        (see `assembly_modes`).

        >>> import numpy as np
        >>> from linkwork import examples
        >>> model = examples.four_bar().compile()
        >>> far = model.solve(100.0)
        >>> bool(np.allclose(far.q, model.sweep(np.linspace(0.0, 100.0, 20001)).q[-1], atol=1e-9))
        True
        """
        t = _args.number(t, "t")
        if branch is not None:
            q_guess = self._branch_guess(t, branch)
        g = self._guess(q_guess)
        q, qd, qdd, it, res, piv, events = self._core.solve(t, g)
        state = State(self, float(t), q, qd, qdd, it, res, piv)
        state.events = [Event.from_raw(e) for e in events]
        return state

    def statics(self, t: float = 0.0, q_guess: Sequence[float] | np.ndarray | None = None) -> Statics:
        """The driver efforts and joint reactions that hold the mechanism at rest at time
        ``t`` against gravity and the loads (velocities and accelerations set to zero)."""
        t, g = _args.number(t, "t"), self._guess(q_guess)
        q, lam, reactions = self._core.statics(t, g)
        return Statics(self, float(t), q, lam, reactions)

    def mobility(
        self, t: float = 0.0, q_guess: Sequence[float] | np.ndarray | None = None, assemble: bool = True
    ) -> Mobility:
        """Degrees of freedom by Gruebler's count and by the rank of Phi_q, redundant
        rows mapped to their joints, and the motions left free, at the configuration
        assembled at time ``t`` from ``q_guess`` (default: as described).

        >>> from linkwork import examples
        >>> m = examples.four_bar().compile().mobility()
        >>> (m.gruebler_dof, m.dof, m.dof_driven)
        (1, 1, 0)
        """
        t, g = _args.number(t, "t"), self._guess(q_guess)
        return Mobility.from_raw(_core.mobility(self._core, t, g, _args.flag(assemble, "assemble")))

    def structure(self) -> Structure:
        """The mechanism's structure, from the pattern of Phi_q alone: the groups of
        coordinates that must be solved together, in an order where each needs only the
        earlier ones (block-triangular form), named as the textbooks do ("input",
        "one body", "dyad RRR" / "RRP" / "RPR" / "PRP" / "RPP", "triad", "group"); rows no
        coordinate is left for (structurally redundant) and coordinates no row
        determines.

        >>> from linkwork import examples
        >>> [g.kind for g in examples.four_bar().compile().structure().groups]
        ['input', 'dyad RRR']
        """
        return Structure.from_raw(_core.structure(self._core))

    def linkages(self, t: float = 0.0, q_guess: Sequence[float] | np.ndarray | None = None) -> list[Linkage]:
        """The four-bar loops and slider-cranks of the mechanism (found from its pins and
        sliders, six-bars included), with their Grashof type, the input's limits of motion
        in closed form, circuit and transmission angle, at the configuration assembled at
        ``t`` from ``q_guess`` (default: as described).

        >>> from linkwork import examples
        >>> (fb,) = examples.four_bar().compile().linkages()
        >>> fb.kind_of, fb.input_limits, fb.circuit
        ('crank-rocker', None, 'open')
        """
        t, g = _args.number(t, "t"), self._guess(q_guess)
        _, raw = _core.linkages(self._core, t, g)
        return [Linkage.from_raw(r, self.body_names) for r in raw]

    def assembly_modes(
        self, t: float = 0.0, q_guess: Sequence[float] | np.ndarray | None = None, tries: int = 200
    ) -> AssemblyModes:
        """Every assembly mode at time ``t`` (the drivers at their values then): the
        configurations that close the mechanism, e.g. a four-bar's open and crossed
        circuits, a six-bar's four. A search from ``tries`` seeded guesses around
        ``q_guess`` (default: as described; its own mode comes first). Sweep on a mode with
        ``model.sweep(times, q_guess=mode.q)`` or ``branch=...``.

        >>> from linkwork import examples
        >>> modes = examples.four_bar().compile().assembly_modes()
        >>> sorted(m.circuits["crank/coupler/rocker"] for m in modes)
        ['crossed', 'open']
        """
        t, g = _args.number(t, "t"), self._guess(q_guess)
        tries = _args.integer(tries, "tries", 1, 1_000_000)
        tried, converged, raw = _core.assembly_modes(self._core, t, g, tries)
        modes = tuple(
            AssemblyMode(q, float(det), float(ratio), {str(r["name"]): str(r["circuit"]) for r in loops})
            for q, det, ratio, loops in raw
        )
        return AssemblyModes(modes, int(tried), int(converged))

    @property
    def point_names(self) -> list[str]:
        """The named points, in the description's order."""
        return [p[0] for p in self._core.points]

    def _outputs(self, outputs: Any, error: type[Exception]) -> Kept:
        """What ``outputs`` asks a sweep to keep; ``error`` names what does not exist."""
        if isinstance(outputs, (str, tuple)):
            outputs = [outputs]
        items = _args.each(outputs, "outputs", lambda item, name: item)
        coords: list[int] = []
        points: dict[str, tuple[int, float, float]] = {}
        named = {p: (b, ux, uy) for p, b, ux, uy in self._core.points}
        traced: dict[str, Anchor] | None = None
        for item in items:
            if isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str):
                body, local = item
                index = -1 if body == "ground" else self._body_index(body, error)
                u = [float(x) for x in _args.vector(local, f"the point of {body!r}", 2)]
                points[f"{body}({u[0]:g}, {u[1]:g})"] = (index, u[0], u[1])
            elif not isinstance(item, str):
                raise error(f"an output is a name or (body, (u_x, u_y)), not {item!r}")
            elif item in self._column_index:
                coords.append(self._column_index[item])
            elif item in self._body_names:
                j = 3 * self._body_names.index(item)
                coords += [j, j + 1, j + 2]
            elif item in named:
                points[item] = named[item]
            else:
                traced = (
                    traced
                    if traced is not None
                    else traceable(self.body_names, self.q_start, self.description)
                )
                anchor = traced.get(item)
                if anchor is None:
                    raise error(
                        f"no output named {item!r}; an output is a body ({', '.join(self._body_names)}), "
                        f"a column ({', '.join(self._columns)}), or a point, joint or driver with a point "
                        f"({', '.join(traced) or 'none'})"
                    )
                index = -1 if anchor.body == "ground" else self._body_names.index(anchor.body)
                points[item] = (index, float(anchor.local[0]), float(anchor.local[1]))
        return Kept(list(dict.fromkeys(coords)), list(points.values()), list(points))

    def _body_index(self, body: str, error: type[Exception]) -> int:
        if body not in self._body_names:
            raise error(f"no body named {body!r}; bodies: {', '.join(self._body_names)} (or 'ground')")
        return self._body_names.index(body)

    def _guess(self, q_guess: Any) -> np.ndarray | None:
        return _args.optional_vector(q_guess, "q_guess", self.n_coords)

    def _branch_guess(self, t: float, branch: str | dict[str, str]) -> np.ndarray:
        mode: AssemblyMode = self.assembly_modes(t).find(branch)
        return mode.q

    def motion_limits(
        self,
        driver: str | None = None,
        t: float = 0.0,
        q_guess: Sequence[float] | np.ndarray | None = None,
        range: float | None = None,
        steps: int | None = None,
    ) -> MotionLimits:
        """The range of ``driver``'s input (default: the only driver) over which the
        mechanism assembles, on the branch of ``q_guess`` at time ``t``: the input is swept
        from its value at ``t`` both ways until a limit of motion (located to round-off),
        a whole turn (angles) or ``range`` (default 4 L for lengths) is reached.

        >>> from linkwork import examples
        >>> examples.four_bar().compile().motion_limits().full_rotation
        True
        """
        t, g = _args.number(t, "t"), self._guess(q_guess)
        range = _args.optional_number(range, "range", positive=True)
        steps = _args.optional_integer(steps, "steps", 2)
        if driver is not None and not isinstance(driver, str):
            raise InputError(f"driver must be a driver's name, not {driver!r}")
        if driver is None:
            drivers = [c[0] for c in self.constraints if c[1] == "driver"]
            if len(drivers) != 1:
                raise InputError(f"name the driver: this model has {len(drivers)} ({', '.join(drivers)})")
            driver = drivers[0]
        raw = _core.motion_limits(self._core, driver, t, g, range, steps)
        return MotionLimits.from_raw(raw)

    def cycle(self) -> Cycle | None:
        """One cycle of the model's periodic driver, when it has exactly one and every
        other driver holds still: a crank at a constant rate (one turn, 2 pi / |rate| in
        the file's angle unit), a harmonic law (2 pi / |omega|) or a periodic law (its
        period); None otherwise. ``linkwork run`` sweeps one cycle by default.

        >>> from linkwork import examples
        >>> print(examples.four_bar(omega=5.0).compile().cycle())
        one cycle of crank_angle, 2 pi / |rate| = 1.25664 s
        """
        from ..motion import period

        turn = 360.0 if self.units.get("input_angle") == "deg" else 2 * math.pi
        found, moving = [], 0
        for d in self.description.get("drivers", []):
            law = d.get("law", {})
            driver = kind_of("drivers", d.get("type"))
            angle = driver is not None and driver.input is not None and driver.input.unit == "angle"
            p = period(law, full_turn=turn if angle else None)
            moving += law.get("type") != "constant"
            if p is not None:
                found.append(Cycle(str(d.get("name")), p[0], p[1]))
        return found[0] if len(found) == 1 and moving == 1 else None

    def sweep(
        self,
        times: Sequence[float] | np.ndarray,
        q_guess: Sequence[float] | np.ndarray | None = None,
        progress: Callable[[int, int], Any] | bool | None = None,
        forces: bool = False,
        derivatives: int = 2,
        every: int = 1,
        on_singular: str = "continue",
        locks: bool = False,
        branch: str | dict[str, str] | None = None,
        outputs: Sequence[Any] | None = None,
    ) -> Results:
        """Solves position, velocity and acceleration at every time (strictly monotone),
        each step predicted from the previous one. The GIL is released meanwhile.

        ``progress``: True for a progress bar on stderr, or a callable(done, total).
        ``forces``: also solve the inverse dynamics (driver efforts, joint reactions) from
        the bodies' mass properties, gravity and the loads.
        ``derivatives``: 0 solves positions only, 1 adds velocities, 2 (default) also
        accelerations; what is not solved costs nothing and is None in the results.
        ``every``: keep every ``every``-th step only (all are solved; each kept row's
        diagnostics are the worst since the previous kept row).
        ``on_singular``: at a limit of motion, a bifurcation or a branch jump, "continue"
        (default: report it in ``results.events`` and go on along the same branch, its
        analytic continuation, where one exists), "switch" (at a bifurcation, go on along
        the other branch through it: a parallelogram becomes an antiparallelogram at its
        change point) or "stop" (raise `SingularError` there).
        ``locks``: also locate where each output (a link pinned to the ground, a slider)
        stops and reverses (needs velocities; solved even if ``derivatives=0``).
        Each step is checked against its prediction: a step that fails or would jump to
        another assembly branch is redone in sub-steps, so nothing changes branch silently.
        If step k fails, the exception carries ``.partial``: the k good steps, with the
        events found so far. ``branch``: start on the assembly mode it names instead of
        the one nearest ``q_guess``: "open" or "crossed" (every recognised four-bar loop or
        slider-crank), or {linkage name: circuit}; see `assembly_modes` and `linkages`.
        ``outputs``: keep only these (default: the model's ``outputs``, else every
        coordinate): a body's name (its x, y, theta), a column ("rocker.theta"), a named
        point, joint or driver (its world path: ``results.points[name]``), or
        (body, (u_x, u_y)) for any body point. What is not kept is neither stored nor
        allocated; the diagnostics and events are always kept. With ``derivatives=0``, one
        coupler point's path costs a fraction of the full sweep.
        """
        t = _args.times(times)
        forces, locks = _args.flag(forces, "forces"), _args.flag(locks, "locks")
        derivatives = _args.integer(derivatives, "derivatives", 0, 2)
        every = _args.integer(every, "every", 1)
        on_singular = _args.choice(on_singular, "on_singular", ON_SINGULAR)
        progress = _args.callback(progress, "progress", allow_true=True)
        if branch is not None and len(t):
            q_guess = self._branch_guess(float(t[0]), branch)
        g = self._guess(q_guess)
        callback = ProgressBar() if progress is True else (progress or None)
        # Ctrl-C (and the progress bar) are looked at every `check` steps: about every
        # 0.1 s whatever the model's size (a step costs ~0.1 us per coordinate)
        check = max(1, min(16384, 1_000_000 // max(1, self.n_coords)))
        if callback is not None:
            check = min(check, max(1024, len(t) // 100))
        kept = self._default_outputs if outputs is None else self._outputs(outputs, InputError)
        coords, points = (None, None) if kept is None else (kept.coords, kept.points)
        raw, error = self._core.sweep(
            t, g, callback, check, forces, derivatives, every, on_singular, locks, coords, points
        )
        results = Results(self, raw, kept)
        if error is not None:
            error.partial = results
            raise error
        return results

    def simulate(
        self,
        times: Sequence[float] | np.ndarray,
        *,
        method: str = "rk8",
        rtol: float = 1e-8,
        atol: float = 1e-8,
        q0: Sequence[float] | np.ndarray | None = None,
        qd0: Sequence[float] | np.ndarray | Mapping[str, float] | None = None,
        rho_inf: float = 0.9,
        h0: float | None = None,
        h_max: float | None = None,
        max_steps: int | None = None,
        ic_tol: float = 1e-6,
        progress: Callable[[int, int], Any] | bool | None = None,
        free_drivers: Iterable[str] | bool = False,
        at_travel_end: str = "stop",
    ) -> Simulation:
        """Forward dynamics: the motion under gravity, the loads and the drivers of a
        model compiled with free coordinates (``compile(free=True)``), from ``q0``, ``qd0``
        (default: the drawing, at rest, or the description's ``initial_rates``) at
        ``times[0]``, reported at every one of ``times`` (strictly increasing). The GIL is
        released meanwhile. ``qd0`` may be a dict of the rates of as many columns
        ("crank.theta") or revolute and prismatic joints as the model has degrees of
        freedom: the other rates follow from the joints (at the drawing).

        The initial conditions are projected onto the constraints first (the smallest
        change in the mass metric; ``moved_q``, ``moved_qd`` say how far): those given
        beyond ``ic_tol`` (scaled: lengths / L) raise `InitialConditionError`; the defaults
        are made consistent with the drivers whatever it takes. A free coordinate
        without mass raises `MasslessError` naming its body.
        ``method``: "rk8" (default; DOP853, the 8th-order Runge-Kutta with error control,
        on the index-1 equations, q and qd projected onto the constraints after every
        step; the times come from its dense output) or "gen-alpha" (implicit index-3
        generalized-alpha with spectral radius ``rho_inf``, steps adapted to a local error
        estimate and cut to land on the times). ``rtol``, ``atol``: the local error
        allowed per step, atol in the model's length unit for lengths (rad for angles),
        rtol relative to each value (an angle's counted up to a half-turn).
        ``h0``, ``h_max``, ``max_steps``: the first and largest step, the most steps.
        A failed step raises `IntegrationError` with ``partial``: the times reached.
        ``free_drivers``: drivers to free for this simulation, by name (True: all), their
        coordinates then following the forces; the others are kept. The model is compiled
        again without them, free (the simulation's ``model``); a name that is not a
        driver of the model raises `InputError`.
        ``at_travel_end``: where a slider reaches an end of the ``travel`` its prismatic
        joint is given (an "end_of_travel" event), "stop" ends the simulation there (the
        rows asked before it kept, the event last in ``events``) and "continue" reports
        it and goes on (no stop is modelled: the slider passes the end).
        """
        if free_drivers is not False:
            return self.freed(free_drivers).simulate(
                times, method=method, rtol=rtol, atol=atol, q0=q0, qd0=qd0, rho_inf=rho_inf, h0=h0,
                h_max=h_max, max_steps=max_steps, ic_tol=ic_tol, progress=progress,
                at_travel_end=at_travel_end,
            )  # fmt: skip
        t = _args.times(times)
        method = _args.choice(method, "method", ("rk8", "gen-alpha"))
        at_travel_end = _args.choice(at_travel_end, "at_travel_end", ("stop", "continue"))
        rtol = _args.number(rtol, "rtol", positive=True)
        atol = _args.number(atol, "atol", positive=True)
        rho_inf = _args.number(rho_inf, "rho_inf")
        h0 = _args.optional_number(h0, "h0", positive=True)
        h_max = _args.optional_number(h_max, "h_max", positive=True)
        max_steps = _args.optional_integer(max_steps, "max_steps", 1)
        ic_tol = _args.number(ic_tol, "ic_tol")
        progress = _args.callback(progress, "progress", allow_true=True)
        callback = ProgressBar() if progress is True else (progress or None)
        q0a = _args.optional_vector(q0, "q0", self.n_coords)
        if qd0 is None and self.description.get("initial_rates"):
            qd0 = dict(self.description["initial_rates"])
        if isinstance(qd0, Mapping):
            given = {str(k): _args.number(v, f"qd0[{k!r}]") for k, v in qd0.items()}
            qd0 = complete_rates(self, given, float(t[0]))
        qd0a = _args.optional_vector(qd0, "qd0", self.n_coords)
        raw, error = _core.simulate(
            self._core,
            t,
            q0a,
            qd0a,
            method=method,
            rtol=rtol,
            atol=atol,
            rho_inf=rho_inf,
            h0=h0,
            h_max=h_max,
            max_steps=max_steps,
            ic_tol=ic_tol,
            progress=callback,
            at_travel_end=at_travel_end,
        )
        results = Simulation(self, raw, method)
        if error is not None:
            error.partial = results
            raise error
        return results

    def freed(self, drivers: Iterable[str] | bool) -> Model:
        """This model compiled free without the named drivers (True: all of them)."""
        have = [d["name"] for d in self.description.get("drivers", [])]
        if drivers is True:
            names = set(have)
        elif isinstance(drivers, str) or not isinstance(drivers, Iterable):
            raise InputError(f"free_drivers must be driver names or True, not {drivers!r}")
        else:
            names = {str(d) for d in drivers}
            unknown = sorted(names - set(have))
            if unknown:
                raise InputError(
                    f"free_drivers: {unknown[0]!r} is not a driver of {self.name!r}; its drivers are "
                    + (", ".join(repr(d) for d in have) or "none")
                )
        desc = dict(self.description)
        desc["drivers"] = [d for d in self.description.get("drivers", []) if d["name"] not in names]
        return Model(desc, **{**self._options, "free": True, "python_laws": self._python_laws or None})

    def equilibrium(
        self,
        t: float = 0.0,
        q_guess: Sequence[float] | np.ndarray | None = None,
        *,
        max_iter: int = 100,
        tol_force: float = 1e-12,
        max_step: float = 0.5,
    ) -> Equilibrium:
        """The rest configuration under gravity, the springs and the applied loads at time
        ``t`` (drivers hold their coordinates), from ``q_guess`` (default: the drawing):
        Q_A(q, 0, t) = Phi_q^T lambda, Phi(q, t) = 0, by Newton with the exact tangent
        stiffness (the loads' and the constraint forces' own), globalized by a line search
        on the residual. Converged when the unbalanced force along the free motions is
        below ``tol_force`` times the largest applied one and |Phi| below ``tol_residual``;
        ``max_step`` bounds one iteration's scaled move. Newton finds the rest position
        nearest the guess, stable or not: ``stable`` says which. Its stability, and the
        linearized vibration modes about it, come with the result (`Equilibrium`).
        No rest found raises `EquilibriumError` with the last iterate (``q``).

        >>> import math
        >>> from linkwork import Mechanism
        >>> m = Mechanism("lid")
        >>> m.gravity = (0.0, -9.81)
        >>> lid = m.body("lid", origin=(0.2, 0.0), mass=1.0, inertia=0.01)
        >>> _ = m.revolute(m.ground, lid, at=(0.0, 0.0))
        >>> _ = m.torsion_spring(m.ground, lid, stiffness=5.0, free_angle=1.2)
        >>> eq = m.compile(free=True).equilibrium()
        >>> theta = eq.body("lid").theta
        >>> bool(abs(5.0 * (theta - 1.2) + 1.0 * 9.81 * 0.2 * math.cos(theta)) < 1e-12), eq.stable
        (True, True)
        """
        t = _args.number(t, "t")
        g = self._guess(q_guess)
        max_iter = _args.integer(max_iter, "max_iter", 1)
        tol_force = _args.number(tol_force, "tol_force", positive=True)
        max_step = _args.number(max_step, "max_step", positive=True)
        raw = _core.equilibrium(self._core, t, g, max_iter=max_iter, tol_force=tol_force, max_step=max_step)
        return Equilibrium(self, float(t), raw)

    def sensitivities(
        self,
        times: Sequence[float] | np.ndarray,
        parameters: Sequence[str],
        points: Sequence[str] | None = None,
        q_guess: Sequence[float] | np.ndarray | None = None,
        progress: Callable[[int, int], Any] | bool | None = None,
        derivatives: int = 2,
        efforts: bool = False,
    ) -> Any:
        """A sweep over ``times`` and, at every step, the exact sensitivities of the
        coordinates, their rates and accelerations (dq/dp, dqd/dp, dqdd/dp: n_steps x
        n_coords x n_params) and of the named ``points`` (default: all) to the design
        ``parameters``, named as in `linkwork.study.naming` (``joints.B.at.0``,
        ``drivers.crank_angle.law.rate``, ``pin A@crank.x``, ``length crank``, ``ratio
        G1``, ``mass coupler``, ...). ``derivatives``: 0 for dq/dp alone (and the sweep's
        positions), 1 with dqd/dp, 2 (the default) with dqdd/dp too. The implicit function
        theorem, every joint's rows differentiated exactly: no differences. dq/dp alone of
        a mechanism of cranks and dyads is solved group by group, each closed form
        differentiated (``path`` "structured"); otherwise on the factorization of Phi_q at
        each solved step ("general"). With ``efforts=True`` (and derivatives 2) the sweep
        solves the inverse dynamics too (its ``results`` has the forces) and the
        multipliers' sensitivities follow, dlambda/dp (n_steps x n_rows x n_params), and
        each driver's effort's (``.effort(driver)``); masses, inertias, centres of mass,
        gravity and the loads' numbers move those alone. The GIL is released meanwhile. A
        parameter that is not one of the engine's numbers (see
        `linkwork.study.sensitivity`) raises `ParameterError` naming it. Returns a
        `linkwork.study.Sensitivities` (its ``results`` is the sweep).
        """
        # declared lazy import, upward: a convenience method of the study layer
        from ..study.sensitivity import sensitivities

        return sensitivities(self, times, parameters, points, q_guess, progress, derivatives, efforts)


def sweep_batch(
    models: Sequence[Model],
    times: Sequence[float] | np.ndarray,
    threads: int | None = None,
    derivatives: int = 2,
    forces: bool = False,
    progress: Callable[[int, int], Any] | None = None,
    errors: str = "raise",
    every: int = 1,
    on_singular: str = "continue",
    locks: bool = False,
    branches_of: Model | None = None,
    outputs: Sequence[Any] | None = None,
) -> list[Any]:
    """Sweeps many models (a design study) over the same times on worker threads, with
    the GIL released: one `Results` per model, in order.

    ``outputs``: what each model's results keep, as for `Model.sweep` (a body, a column, a
    named point, joint or driver, or (body, (u_x, u_y))), named in each model (default: every
    coordinate of each); what is not kept is neither stored nor allocated. With
    ``derivatives=0`` and one coupler point, an atlas of coupler curves keeps two numbers a
    step.

    ``branches_of``: a model of the same mechanism (a study's base) whose assembly mode at
    the first time every model is started on, by its own closed forms (each dyad on the
    base's side, each Newton block with the base's det sign), not wherever Newton from its
    own drawing lands; a model that has no configuration there fails with `AssemblyError`
    naming the group. A model whose groups differ from the base's starts from its drawing.

    ``derivatives``, ``forces``, ``every``, ``on_singular`` and ``locks`` are as for
    `Model.sweep`.
    ``threads``: worker threads (default: one per core). ``progress(done, total)`` counts
    finished models; Ctrl-C stops every running sweep. ``errors="raise"`` raises the first
    model's failure (with ``.index`` and ``.partial``); ``errors="return"`` puts the
    exception, with its ``.partial``, in that model's place instead.
    """
    errors = _args.choice(errors, "errors", ("raise", "return"))
    t = _args.times(times)
    models = _args.each(models, "models", lambda m, name: _args.of_type(m, name, Model, "a compiled Model"))
    threads = _args.optional_integer(threads, "threads", 0) or 0
    derivatives = _args.integer(derivatives, "derivatives", 0, 2)
    every = _args.integer(every, "every", 1)
    on_singular = _args.choice(on_singular, "on_singular", ON_SINGULAR)
    progress = _args.callback(progress, "progress")
    forces, locks = _args.flag(forces, "forces"), _args.flag(locks, "locks")
    if branches_of is not None:
        branches_of = _args.of_type(branches_of, "branches_of", Model, "a compiled Model")
    kept = [None if outputs is None else m._outputs(outputs, InputError) for m in models]
    asked = None
    if any(k is not None for k in kept):
        asked = [(None, None) if k is None else (k.coords, k.points) for k in kept]
    cores = [m._core for m in models]
    items = _core.sweep_batch(
        cores,
        t,
        threads,
        derivatives,
        forces,
        progress or None,
        every,
        on_singular,
        locks,
        None if branches_of is None else branches_of._core,
        asked,
    )
    out: list[Any] = []
    for i, (model, (raw, error)) in enumerate(zip(models, items)):
        results = Results(model, raw, kept[i])
        if error is None:
            out.append(results)
            continue
        error.partial, error.index = results, i
        if errors == "raise":
            raise error
        out.append(error)
    return out


def _rebuild(description: dict[str, Any], options: dict[str, Any]) -> Model:
    """The model of a description and options (unpickling)."""
    return Model(description, **options)


ON_SINGULAR = ("continue", "stop", "switch")
LINEAR = ("auto", "refactor", "small", "dense", "sparse")


def _options(options: dict[str, Any]) -> dict[str, Any]:
    """The compile options checked (names, types, ranges)."""
    checks: dict[str, Callable[[Any, str], Any]] = {
        "tol_residual": lambda v, n: _args.optional_number(v, n, positive=True),
        "tol_step": lambda v, n: _args.optional_number(v, n, positive=True),
        "singular_tol": lambda v, n: _args.optional_number(v, n, positive=True),
        "max_iter": lambda v, n: _args.optional_integer(v, n, 1),
        "max_iter_assembly": lambda v, n: _args.optional_integer(v, n, 1),
        "dense_max": lambda v, n: _args.optional_integer(v, n, 0),
        "linear": lambda v, n: _args.choice(v, n, LINEAR),
        "redundant": lambda v, n: _args.choice(v, n, ("error", "solve")),
        "solver": lambda v, n: _args.choice(v, n, ("auto", "general")),
        "free": lambda v, n: _args.flag(v, n),
        "python_laws": lambda v, n: v if v is None else dict(_args.mapping(v, n)),
    }
    unknown = sorted(set(options) - set(checks))
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r}; the options are {', '.join(sorted(checks))}")
    return {k: checks[k](v, k) for k, v in options.items()}


_KINDS = {"bodies": "body", "joints": "joint", "drivers": "driver", "points": "point", "loads": "load"}


def _check_finite(desc: dict[str, Any]) -> None:
    """Refuses NaN and infinities, naming the item and field (JSON cannot carry them
    to the engine, which would otherwise only see a syntax error)."""

    def walk(value: Any, path: str) -> str | None:
        if isinstance(value, float) and not math.isfinite(value):
            return f"{path} is {value}, not a finite number"
        if isinstance(value, dict):
            items: Any = value.items()
        elif isinstance(value, (list, tuple)):
            items = ((f"[{i}]", v) for i, v in enumerate(value))
        else:
            return None
        for key, v in items:
            found = walk(v, f"{path}.{key}" if isinstance(value, dict) else f"{path}{key}")
            if found:
                return found
        return None

    gravity = desc.get("gravity", [0.0, 0.0])
    if not all(math.isfinite(float(g)) for g in gravity):
        raise ModelError(f"gravity {list(gravity)} is not finite")
    for group, kind in _KINDS.items():
        for item in desc.get(group, []):
            problem = walk(item, "")
            if problem:
                raise ModelError(f"{kind} {item.get('name')!r}: {problem.lstrip('.')}")
