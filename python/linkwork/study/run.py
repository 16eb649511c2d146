"""One study, three scales: the same designs swept in-process on every core (the
engine's threads, `sweep_batch`), on a local Dask cluster, or on a Dask cluster anywhere
(a scheduler address). Designs are cut into chunks; a chunk is one task: it builds its
designs' models from the model's description, sweeps them in Rust on the worker's
threads (no GIL) and reduces each sweep to the figures asked for, so only they travel
back. A design that fails keeps its error in the results; a chunk lost with its worker
is run again by the scheduler and counted once (results are placed by design index).
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _args
from .._args import requires
from ..errors import LinkworkError, StudyError
from .designs import Designs, listed
from .naming import Parameter, _description, _value, parameters
from .outputs import Output, outputs
from .redraw import apply_many

__all__ = ["Study", "StudyResult", "Job", "run_chunk", "requires"]


@dataclass(frozen=True)
class Job:
    """Everything a task needs, as plain data (it pickles): the model's description and
    compile options, the parameters, the outputs, the times and the sweep's options."""

    description: dict[str, Any]
    options: dict[str, Any]
    parameters: tuple[Parameter, ...]
    outputs: tuple[Output, ...]
    times: np.ndarray = field(repr=False)
    derivatives: int
    forces: bool
    on_singular: str
    #: the designs as variants of the compiled model (`Variants`), or None: each redrawn
    #: and compiled
    variants: Variants | None = None


@dataclass(frozen=True)
class Variants:
    """How a job's designs move the compiled model's own numbers: the engine parameters
    (``names``, as `linkwork.study.sensitivity.engine_directions` gives them) and
    ``weights`` (one row per engine parameter, one column per design parameter: the map
    is affine and exact). Plain data: it pickles."""

    names: tuple[str, ...]
    weights: tuple[tuple[float, ...], ...]


# the outputs the engine keeps itself while it sweeps a design's variant
_KEPT = ("path", "angle", "coordinate", "events", "pivot_min")


def variants_of(
    model: Any, params: Sequence[Parameter], outs: Sequence[Output], forces: bool
) -> Variants | None:
    """The job's designs as variants of ``model``, where every parameter is a direction in
    the engine's numbers and every output is kept by the engine while it sweeps; else
    None (the designs are redrawn and compiled one by one)."""
    from .. import _core
    from ..errors import ParameterError
    from .sensitivity import engine_directions

    if forces or any(o.kind not in _KEPT for o in outs) or _overlapping(params) or any(map(_curved, params)):
        return None
    try:
        directions = [engine_directions(model, p) for p in params]
        names = sorted({k for d in directions for k in d})
        # the engine resolves every name (no design: nothing is swept)
        _core.sweep_variants(model._core, names, np.zeros((0, len(names))), np.zeros(1), [], [])
    except ParameterError:
        return None
    weights = tuple(tuple(d.get(k, 0.0) for d in directions) for k in names)
    return Variants(tuple(names), weights)


def _curved(p: Parameter) -> bool:
    """Whether ``p`` moves the engine's numbers other than affinely: a gear's or belt's
    ratio or radii (its coefficients are r / max(r_a, r_b)). Its exact sensitivity is a
    tangent, but a finite change of it is not one direction: such designs are redrawn."""
    return p.kind == "path" and p.path[0] == "joints" and p.path[-1] in ("ratio", "radius_a", "radius_b")


def _overlapping(params: Sequence[Parameter]) -> bool:
    """Whether two parameters move one pin in one body other than as its x and y. The
    engine's directions add; a redraw sets such a pin from the last of them (a length
    puts it on the link, a pin coordinate on its axis, a joint's place in both bodies), so
    the two would differ: such designs are redrawn."""
    moves: dict[tuple[str, str], list[Parameter]] = {}
    for p in params:
        if p.kind in ("length", "pin"):
            moves.setdefault((p.joint, p.body), []).append(p)
    for ps in moves.values():
        if len(ps) > 1 and not (all(p.kind == "pin" for p in ps) and len({p.axis for p in ps}) == len(ps)):
            return True
    joints = {j for j, _ in moves}
    return any(p.kind == "path" and p.path[0] == "joints" and p.path[1] in joints for p in params)


def run_chunk(job: Job, start: int, values: np.ndarray, threads: int | None = None) -> dict[str, Any]:
    """Designs ``start .. start + len(values)`` of a study: each built (`apply_many`),
    compiled, swept (`sweep_batch` on ``threads``) and reduced to the job's outputs; or,
    where the job's designs are variants of the compiled model (``job.variants``), each
    set up, swept and reduced by the engine on its threads. Returns {"start", "figures":
    {key: (k, ...) array}, "error": [message or ""], "seconds", "phases": {"build",
    "sweep", "reduce"} seconds}."""
    if job.variants is not None:
        return _run_variants(job, start, values, threads)
    built = _build(job, start, values)
    return _reduce(job, built, _sweep(job, built, threads))


_MODELS: dict[int, Any] = {}


def _base_model(job: Job) -> Any:
    """The job's compiled model, compiled once per process and job."""
    from ..model.compiled import Model

    key = id(job)
    cached = _MODELS.get(key)
    if cached is None or cached[0] is not job:
        _MODELS.clear()  # one job at a time: its model only
        cached = _MODELS[key] = (job, Model._checked(job.description, job.options))
    return cached[1]


def _run_variants(
    job: Job, start: int, values: np.ndarray, threads: int | None, progress: Any = None
) -> dict[str, Any]:
    """`run_chunk` for designs that are variants of the compiled model: the engine sets
    each design's numbers, sweeps it and keeps its figures on its threads, the GIL
    released; here only the values are checked and the figures placed. ``progress(done,
    total)`` counts the designs swept."""
    from .. import _core
    from ..errors import LinkworkError

    begin = time.perf_counter()
    assert job.variants is not None
    model = _base_model(job)
    values = np.asarray(values, dtype=np.float64).reshape(len(values), len(job.parameters))
    n, n_steps = len(values), len(job.times)
    errors = [""] * n
    ok = np.all(np.isfinite(values), axis=1)
    for j, p in enumerate(job.parameters):
        if p.kind == "length":
            ok &= values[:, j] > 0.0
    for i in np.flatnonzero(~ok):  # the value's own error, as `apply` gives it
        try:
            for p, v in zip(job.parameters, values[i]):
                _value(p, float(v))
        except LinkworkError as e:
            errors[i] = f"{type(e).__name__}: {e}"
    good = [i for i in range(n) if not errors[i]]
    nominal = np.array([p.nominal for p in job.parameters])
    weights = np.array(job.variants.weights, dtype=np.float64).reshape(len(job.variants.names), len(nominal))
    deltas = np.ascontiguousarray((values[good] - nominal) @ weights.T)
    coords: list[int] = []
    points: list[tuple[int, float, float, int]] = []
    named = {name: (k, b, ux, uy) for k, (name, b, ux, uy) in enumerate(model._core.points)}
    slots: dict[str, int] = {}
    for o in job.outputs:
        if o.kind == "path":
            k, b, ux, uy = named[o.target]
            slots[o.key] = len(points)
            points.append((b, ux, uy, k))
        elif o.kind in ("angle", "coordinate"):
            column = f"{o.target}.theta" if o.kind == "angle" else o.target
            slots[o.key] = len(coords)
            coords.append(model._column_index[column])
    times = np.array(job.times, dtype=np.float64)
    build = time.perf_counter() - begin
    begin = time.perf_counter()
    raw = _core.sweep_variants(
        model._core, list(job.variants.names), deltas, times, coords, points,
        job.derivatives, job.on_singular, threads or 0, progress,
    )  # fmt: skip
    sweep = time.perf_counter() - begin
    begin = time.perf_counter()
    for j, e in raw["errors"]:
        errors[good[j]] = f"{type(e).__name__}: {e}"
    swept = np.array([not errors[i] for i in good], dtype=bool)
    rows = np.array(good, dtype=np.intp)[swept]
    figures = {}
    for o in job.outputs:
        if o.kind == "path":
            src = raw["points"][:, :, slots[o.key], :]
        elif o.kind in ("angle", "coordinate"):
            src = raw["q"][:, :, slots[o.key]]
        else:
            src = raw["events"] if o.kind == "events" else raw["pivot_min"]
        if len(rows) == n:  # every design swept: the engine's array as it is (no copy)
            figures[o.key] = src.astype(o.dtype, copy=False)
        else:
            figures[o.key] = o.empty(n, n_steps)
            figures[o.key][rows] = src[swept]
    phases = {"build": build, "sweep": sweep, "reduce": time.perf_counter() - begin}
    return {
        "start": start,
        "figures": figures,
        "error": errors,
        "seconds": sum(phases.values()),
        "phases": phases,
    }


def _build(job: Job, start: int, values: np.ndarray) -> dict[str, Any]:
    """The chunk's designs built and compiled (a failure is that design's error)."""
    from ..model.compiled import Model

    begin = time.perf_counter()
    errors = [""] * len(values)
    models: list[Any] = []
    slots: list[int] = []
    for i, desc in enumerate(apply_many(job.description, job.parameters, values, **job.options)):
        try:
            if isinstance(desc, Exception):
                raise desc
            models.append(Model._checked(desc, job.options))
            slots.append(i)
        except LinkworkError as e:
            errors[i] = f"{type(e).__name__}: {e}"
    build = time.perf_counter() - begin
    return {
        "start": start,
        "n": len(values),
        "models": models,
        "slots": slots,
        "errors": errors,
        "build": build,
    }


def _sweep(job: Job, built: dict[str, Any], threads: int | None) -> tuple[list[Any], float]:
    """The built models swept on the engine's threads (the GIL released meanwhile)."""
    from ..model.compiled import sweep_batch

    begin = time.perf_counter()
    # arrays that came through pickle may be read-only views of a misaligned buffer
    times = np.array(job.times, dtype=np.float64)
    swept = sweep_batch(
        built["models"],
        times,
        threads=threads,
        derivatives=job.derivatives,
        forces=job.forces,
        errors="return",
        on_singular=job.on_singular,
        # every design on the branch the study's model is drawn in, never on the one a
        # redraw or Newton from its drawing happened to reach
        branches_of=_base_model(job),
    )
    return swept, time.perf_counter() - begin


def _reduce(job: Job, built: dict[str, Any], swept: tuple[list[Any], float]) -> dict[str, Any]:
    """Each sweep reduced to the job's outputs; failures as the designs' errors."""
    begin = time.perf_counter()
    n_steps = len(job.times)
    figures = {o.key: o.empty(built["n"], n_steps) for o in job.outputs}
    errors = built["errors"]
    for i, model, res in zip(built["slots"], built["models"], swept[0]):
        if isinstance(res, Exception):
            errors[i] = f"{type(res).__name__}: {res}"
            continue
        try:
            for o in job.outputs:
                figures[o.key][i] = o.compute(model, res)
        except (LinkworkError, ValueError, KeyError) as e:
            errors[i] = f"{type(e).__name__}: {e}"
            for o in job.outputs:
                figures[o.key][i] = o.empty(1, n_steps)[0]
    # where the time went: building the designs' models, sweeping, reducing
    phases = {"build": built["build"], "sweep": swept[1], "reduce": time.perf_counter() - begin}
    seconds = sum(phases.values())
    return {
        "start": built["start"],
        "figures": figures,
        "error": errors,
        "seconds": seconds,
        "phases": phases,
    }


def _worker_task(job: Job, start: int, values: np.ndarray) -> dict[str, Any]:
    """A chunk on a Dask worker, on as many engine threads as the worker has."""
    from distributed import get_worker

    try:
        threads = get_worker().state.nthreads
    except (ValueError, AttributeError):
        threads = None
    out = run_chunk(job, start, values, threads)
    out["worker"] = os.getpid()
    return out


class Study:
    """A design study of one model: the times every design is swept over and the figures
    kept of each (see `linkwork.study.outputs`).

    ``model``: a `Model` (its options are kept), a `Mechanism` or a description dict.
    ``derivatives``: what the sweeps solve (default: the least the outputs need: 0, or 2
    when an output needs forces). ``options``: compile options for every design (as for
    `Model`), when ``model`` is not already compiled.

    >>> import numpy as np, linkwork as lw
    >>> times = np.linspace(0, 1.2566370614359172, 201)     # one crank turn
    >>> study = lw.Study(lw.examples.four_bar(), times, ["transmission_min"])
    >>> res = study.run(lw.study.grid({"length crank": [0.19, 0.2, 0.21]}))
    >>> np.round(np.degrees(res.figures["transmission_min"]), 2).tolist()
    [24.38, 21.79, 19.07]
    """

    def __init__(
        self,
        model: Any,
        times: Any,
        outputs: Sequence[Any] = ("events",),
        derivatives: int | None = None,
        on_singular: str = "continue",
        **options: Any,
    ) -> None:
        from ..model.compiled import ON_SINGULAR, Model, _options

        if isinstance(model, Model):
            if options:
                raise StudyError("give compile options with a Mechanism or description, not a compiled Model")
            if model._python_laws:
                model.__reduce__()  # raises PortabilityError, naming the laws
            self.model = model
        else:
            options = _options(options)
            if options.get("python_laws"):
                raise StudyError("a study's designs are rebuilt from data: Python laws cannot be used")
            if hasattr(model, "python_laws") and model.python_laws:
                Model(model, **options).__reduce__()
            self.model = Model(_description(model), **options)
        self.times = _args.times(times)
        if len(self.times) < 1:
            raise StudyError("a study needs at least one time")
        self.outputs = tuple(_outputs_of(self.model, outputs))
        self.forces = any(o.forces for o in self.outputs)
        if derivatives is None:
            derivatives = 2 if self.forces else 0
        self.derivatives = _args.integer(derivatives, "derivatives", 0, 2)
        if self.forces and self.derivatives != 2:
            raise StudyError("peak_effort needs accelerations: derivatives=2")
        self.on_singular = _args.choice(on_singular, "on_singular", ON_SINGULAR)

    @property
    def description(self) -> dict[str, Any]:
        return self.model.description

    def nominal(self, names: Sequence[str]) -> dict[str, float]:
        """The nominal value of each parameter (its value in the model)."""
        return {p.name: p.nominal for p in parameters(self.description, names)}

    def job(self, names: Sequence[str], variants: bool = True) -> Job:
        """Everything a task needs to sweep designs of the parameters ``names``. Where
        every parameter is one of the engine's numbers (see
        `linkwork.study.sensitivity`) and every output one the engine keeps (``path``,
        ``angle``, ``coordinate``, ``events``, ``pivot_min``), the designs are variants of
        the compiled model, set up and swept by the engine on its threads; otherwise (or
        with ``variants=False``) each design is redrawn (`apply`) and compiled. The two
        agree to round-off (the same closed configuration, assembled from the drawing or
        redrawn)."""
        params = tuple(parameters(self.description, names))
        return Job(
            self.description,
            self.model.options,
            params,
            self.outputs,
            self.times,
            self.derivatives,
            self.forces,
            self.on_singular,
            variants_of(self.model, params, self.outputs, self.forces) if variants else None,
        )

    def run(
        self,
        designs: Any,
        scheduler: Any = None,
        chunk: int | None = None,
        threads: int | None = None,
        progress: Any = False,
        timeout: float | None = None,
        variants: bool = True,
    ) -> StudyResult:
        """Sweeps every design and keeps its figures: a `StudyResult` (``.dataset``).

        ``designs``: `Designs` (`grid`, `latin_hypercube`, `sample`), a list of
        {parameter: value} or {parameter: values}. ``scheduler``: None (in-process, the
        engine's threads), "local" (a local Dask cluster of processes, one per core, for
        this call), a scheduler address ("tcp://host:8786") or a `distributed.Client`.
        ``chunk``: designs per task (default: see docs/studies.md). ``threads``:
        in-process, the engine threads (default one per core). ``progress``: True for a
        progress bar (tqdm where installed, in notebooks too), or a callable(done, total)
        counting designs. ``timeout``: seconds to wait for a cluster's results.
        ``variants``: False redraws and compiles every design even where the engine could
        set it up as a variant of the compiled model (see `job`).
        """
        designs = listed(designs) if not isinstance(designs, Designs) else designs
        job = self.job(designs.names, variants=_args.flag(variants, "variants"))
        n = len(designs)
        if chunk is not None:
            chunk = _args.integer(chunk, "chunk", 1)
        threads = _args.optional_integer(threads, "threads", 0)
        begin = time.perf_counter()
        if scheduler is None:
            # variants: all at once (no Python work to overlap with the sweeps)
            chunk = chunk or (max(1, n) if job.variants is not None else _default_chunk(n, 1, cluster=False))
            parts = _run_local(job, designs.values, chunk, threads, progress)
            where = "in-process"
        else:
            chunk = chunk or _default_chunk(n, _cluster_threads(scheduler), cluster=True)
            parts, where = _run_dask(job, designs.values, chunk, scheduler, progress, timeout)
        elapsed = time.perf_counter() - begin
        return StudyResult._assemble(self, designs, job, parts, chunk, where, elapsed)

    def tolerance(
        self, tolerances: Mapping[str, Any], n: int = 1000, seed: int | None = 0, **run: Any
    ) -> Any:
        """A tolerance study: see `linkwork.study.tolerance_study`."""
        # declared lazy import, upward: a convenience method of a module above this one
        from .tolerance import tolerance_study

        return tolerance_study(self, tolerances, n=n, seed=seed, **run)


def _outputs_of(model: Any, names: Sequence[Any]) -> list[Output]:
    return outputs(model, names)


def _default_chunk(n: int, workers: int, cluster: bool) -> int:
    """Designs per task. In-process, for designs redrawn in Python, the next chunk is built
    while the engine's threads sweep one: 256 (small enough to overlap well and pace the
    progress bar); variants go to the engine all at once. On a
    cluster, big enough that a task (~0.3-1 ms a design) dwarfs the scheduler's few ms per
    task, small enough that every worker gets several (load balance, and little to redo
    when a worker is lost)."""
    if not cluster:
        return 256
    return int(max(64, min(1024, math.ceil(n / (4 * max(1, workers))))))


def _cluster_threads(scheduler: Any) -> int:
    if isinstance(scheduler, str) and scheduler == "local":
        return os.cpu_count() or 1
    client = scheduler if hasattr(scheduler, "nthreads") else None
    if client is not None:
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # noqa: BLE001 - an unreachable scheduler is reported by the run
            return 1
    return 4


class _Bar:
    """Counts designs done: tqdm (notebook-aware) where installed, else a line on stderr."""

    def __init__(self, total: int, progress: Any, label: str) -> None:
        self.total, self.done, self.callback, self.bar = total, 0, None, None
        if callable(progress):
            self.callback = progress
        elif progress is True:
            try:
                from tqdm.auto import tqdm

                self.bar = tqdm(total=total, desc=label, unit="design")
            except ImportError:
                self.callback = _text_bar(label)
        elif progress not in (False, None):
            raise StudyError(f"progress must be True, False or a function f(done, total), not {progress!r}")

    def add(self, k: int) -> None:
        self.done += k
        if self.bar is not None:
            self.bar.update(k)
        if self.callback is not None:
            self.callback(self.done, self.total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _text_bar(label: str) -> Any:
    def show(done: int, total: int) -> None:
        width = 30
        filled = width * done // max(total, 1)
        end = "\n" if done >= total else ""
        sys.stderr.write(f"\r  {label} [{'#' * filled}{'.' * (width - filled)}] {done}/{total}{end}")
        sys.stderr.flush()

    return show


def _chunks(n: int, chunk: int) -> list[tuple[int, int]]:
    return [(s, min(n, s + chunk)) for s in range(0, n, chunk)]


def _run_local(
    job: Job, values: np.ndarray, chunk: int, threads: int | None, progress: Any
) -> list[dict[str, Any]]:
    """In-process: variants go to the engine's threads (all at once unless ``chunk`` says
    otherwise); designs redrawn in Python are built a chunk ahead: while the engine's
    threads sweep one (the GIL released), this thread builds the next and reduces the
    last. The results are those of `run_chunk`."""
    from concurrent.futures import ThreadPoolExecutor

    bar = _Bar(len(values), progress, "designs")
    parts = []
    if job.variants is not None:
        try:
            chunks = _chunks(len(values), chunk)

            def count(done: int, _: int) -> None:
                if done > bar.done:
                    bar.add(done - bar.done)

            for s, e in chunks:
                # one chunk (the default): the engine counts the designs as its threads finish them
                parts.append(_run_variants(job, s, values[s:e], threads, count if len(chunks) == 1 else None))
                if e > bar.done:
                    bar.add(e - bar.done)
        finally:
            bar.close()
        return parts
    try:
        with ThreadPoolExecutor(1) as sweeper:
            pending: Any = None
            for s, e in _chunks(len(values), chunk):
                built = _build(job, s, values[s:e])
                if pending is not None:
                    parts.append(_reduce(job, pending[0], pending[1].result()))
                    bar.add(pending[0]["n"])
                pending = (built, sweeper.submit(_sweep, job, built, threads))
            if pending is not None:
                parts.append(_reduce(job, pending[0], pending[1].result()))
                bar.add(pending[0]["n"])
    finally:
        bar.close()
    return parts


def _client(scheduler: Any) -> tuple[Any, Any]:
    """(client, what to close afterwards: [] for the caller's client) for a scheduler."""
    distributed = requires("distributed")
    if isinstance(scheduler, distributed.Client):
        return scheduler, []
    if scheduler == "local":
        cluster = distributed.LocalCluster(
            n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = distributed.Client(cluster)
        return client, [client, cluster]
    if isinstance(scheduler, str) and scheduler:
        try:
            client = distributed.Client(scheduler, timeout="20s", set_as_default=False)
            return client, [client]
        except OSError as e:
            raise StudyError(f"cannot reach the Dask scheduler at {scheduler!r}: {e}") from None
    raise StudyError(
        f"scheduler must be None (in-process), 'local', a scheduler address or a distributed.Client, "
        f"not {scheduler!r}"
    )


@contextmanager
def _script_kept_from_workers(local: bool) -> Iterator[None]:
    """While a local cluster runs: its worker processes start by importing the parent's
    ``__main__`` again (multiprocessing's spawn), which re-runs a script that has no
    ``if __name__ == "__main__":`` guard, study and all, inside each worker ("Nanny failed
    to start"). A study's tasks need nothing of the script (they carry the model as its
    description), so the workers start as from an interactive session, which has no script
    to import: the script's path and module name are hidden from spawn meanwhile."""
    main = sys.modules.get("__main__")
    if not local or main is None:
        yield
        return
    saved = {k: main.__dict__[k] for k in ("__file__", "__spec__") if k in main.__dict__}
    main.__dict__.pop("__file__", None)
    if "__spec__" in saved:
        main.__spec__ = None
    try:
        yield
    finally:
        main.__dict__.update(saved)


def _run_dask(
    job: Job, values: np.ndarray, chunk: int, scheduler: Any, progress: Any, timeout: float | None
) -> tuple[list[dict[str, Any]], str]:
    with _script_kept_from_workers(scheduler == "local"):
        return _run_on_client(job, values, chunk, scheduler, progress, timeout)


def _run_on_client(
    job: Job, values: np.ndarray, chunk: int, scheduler: Any, progress: Any, timeout: float | None
) -> tuple[list[dict[str, Any]], str]:
    distributed = requires("distributed")
    client, owned = _client(scheduler)
    try:
        where = f"dask {client.scheduler.address}" if client.scheduler else "dask"
        futures = [
            client.submit(_worker_task, job, s, values[s:e], pure=False, retries=0)
            for s, e in _chunks(len(values), chunk)
        ]
        if progress is True and "ipykernel" in sys.modules:
            # in a notebook on a cluster: Dask's own progress widget (the tasks, live)
            distributed.progress(futures, notebook=True)
            progress = False
        bar = _Bar(len(values), progress, "designs")
        by_start: dict[int, dict[str, Any]] = {}
        deadline = None if timeout is None else time.monotonic() + timeout
        pending = set(futures)
        try:
            while pending:
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    raise StudyError(f"the cluster did not finish within {timeout} s")
                try:
                    done, pending = distributed.wait(pending, timeout=left, return_when="FIRST_COMPLETED")
                except distributed.TimeoutError:
                    raise StudyError(f"the cluster did not finish within {timeout} s") from None
                # gathered on the client's own loop: a result lost with its worker is
                # recomputed there (the scheduler reschedules it), then gathered again
                for part in client.gather(list(done)):
                    if part["start"] in by_start:  # a chunk is counted once, whatever befell its worker
                        continue
                    by_start[part["start"]] = part
                    bar.add(len(part["error"]))
        finally:
            bar.close()
            for future in pending:
                future.cancel()
        return [by_start[s] for s in sorted(by_start)], where
    finally:
        for thing in owned:
            thing.close()


@dataclass
class StudyResult:
    """The figures of every design of a study.

    ``designs`` (the `Designs`), ``figures`` {key: (n_designs, ...) array}, ``errors``
    (n_designs,) strings ("" where the design swept; else its error, e.g. "AssemblyError:
    ..."), ``outputs``, ``parameters``, ``times``, ``units`` of every figure and parameter,
    ``tasks`` [(first design, designs, seconds)], ``chunk``, ``where`` it ran,
    ``seconds`` in all and ``phases``: the tasks' seconds building the designs' models,
    sweeping and reducing, summed. ``built``: how the designs were built, "variants" (the
    compiled model's numbers set by the engine, see `Study.job`) or "redrawn" (each
    redrawn and compiled). ``dataset`` is the labelled xarray Dataset; `save` writes NetCDF
    or Parquet.
    """

    designs: Designs
    figures: dict[str, np.ndarray]
    errors: np.ndarray
    outputs: tuple[Output, ...]
    parameters: tuple[Parameter, ...]
    times: np.ndarray
    model_name: str
    model_units: dict[str, str]
    tasks: list[tuple[int, int, float]]
    chunk: int
    where: str
    seconds: float
    derivatives: int = 0
    phases: dict[str, float] = field(default_factory=dict)
    built: str = "redrawn"

    @classmethod
    def _assemble(
        cls,
        study: Study,
        designs: Designs,
        job: Job,
        parts: list[dict[str, Any]],
        chunk: int,
        where: str,
        seconds: float,
    ) -> StudyResult:
        n = len(designs)
        starts = [p["start"] for p in parts]
        covered = sum(len(p["error"]) for p in parts)
        if covered != n or len(set(starts)) != len(starts):
            raise StudyError(f"internal: the chunks cover {covered} designs of {n}")  # pragma: no cover
        figures = {o.key: np.concatenate([p["figures"][o.key] for p in parts]) for o in job.outputs}
        errors = np.asarray([e for p in parts for e in p["error"]], dtype=object)
        tasks = [(p["start"], len(p["error"]), float(p["seconds"])) for p in parts]
        return cls(
            designs,
            figures,
            errors,
            job.outputs,
            job.parameters,
            job.times,
            study.model.name,
            study.model.units,
            tasks,
            chunk,
            where,
            seconds,
            job.derivatives,
            {k: sum(p["phases"][k] for p in parts) for k in ("build", "sweep", "reduce")},
            "redrawn" if job.variants is None else "variants",
        )

    def __len__(self) -> int:
        return len(self.designs)

    @property
    def ok(self) -> np.ndarray:
        """(n_designs,) True where the design swept."""
        return np.asarray([e == "" for e in self.errors], dtype=bool)

    @property
    def n_failed(self) -> int:
        return int(np.count_nonzero(~self.ok))

    def failures(self) -> list[tuple[int, dict[str, float], str]]:
        """(index, design, error) of every design that failed."""
        return [(int(i), self.designs.design(int(i)), str(self.errors[i])) for i in np.flatnonzero(~self.ok)]

    def __repr__(self) -> str:
        return (
            f"<StudyResult of {self.model_name!r}: {len(self)} designs ({self.designs.kind}), "
            f"{self.n_failed} failed, {', '.join(o.name for o in self.outputs)}; {self.where}, "
            f"{self.seconds:.3g} s>"
        )

    @property
    def dataset(self) -> Any:
        """The labelled dataset (xarray): dimension ``design`` (with every parameter's
        values as a coordinate), ``step`` (coordinate ``time``) and ``xy``; a variable per
        output and ``error``; units as attributes."""
        # declared lazy import, upward: a convenience method of a module above this one
        from .dataset import to_xarray

        return to_xarray(self)

    def to_pandas(self) -> Any:
        """One row per design: the parameters, every scalar figure and ``error``."""
        # declared lazy import, upward: a convenience method of a module above this one
        from .dataset import to_pandas

        return to_pandas(self)

    def save(self, path: str) -> str:
        """Writes the dataset: ``.nc`` NetCDF (every figure), ``.parquet`` (a row per
        design; per-step figures as fixed-size lists), units in both. Returns the path."""
        # declared lazy import, upward: a convenience method of a module above this one
        from .dataset import save

        return save(self, path)
