"""Checks of public arguments, in one place: each bad value becomes an `InputError`
naming the argument, its value and what is allowed, before anything reaches the engine
(where it would surface as an OverflowError, TypeError or AttributeError from inside)."""

from __future__ import annotations

import importlib
import math
import numbers
from collections.abc import Callable, Collection, Mapping
from typing import Any

import numpy as np

from .errors import DependencyError, InputError


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def integer(value: Any, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """An integer (a float with an integer value is refused: 1.5 steps is a mistake)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{name} must be an integer, not {_show(value)}")
    v = int(value)
    if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
        lo = "" if minimum is None else f">= {minimum}"
        hi = "" if maximum is None else f"<= {maximum}"
        raise InputError(f"{name} must be an integer {' and '.join(x for x in (lo, hi) if x)}, not {v}")
    return v


def optional_integer(value: Any, name: str, minimum: int | None = None) -> int | None:
    return None if value is None else integer(value, name, minimum)


def number(value: Any, name: str, positive: bool = False) -> float:
    """A finite real number (positive where asked)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a number, not {_show(value)}")
    v = float(value)
    if not math.isfinite(v) or (positive and v <= 0.0):
        raise InputError(f"{name} must be a finite number{' > 0' if positive else ''}, not {v}")
    return v


def optional_number(value: Any, name: str, positive: bool = False) -> float | None:
    return None if value is None else number(value, name, positive)


def flag(value: Any, name: str) -> bool:
    """True or False (numpy's booleans too)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise InputError(f"{name} must be True or False, not {_show(value)}")


def choice(value: Any, name: str, allowed: Collection[str]) -> str:
    if not isinstance(value, str) or value not in allowed:
        options = ", ".join(repr(a) for a in allowed)
        raise InputError(f"{name} must be one of {options}, not {_show(value)}")
    return value


def callback(value: Any, name: str, allow_true: bool = False) -> Any:
    """None, a callable, or (where allowed) True for the built-in progress bar."""
    if value is None or value is False or callable(value) or (allow_true and value is True):
        return value
    allowed = "None, True (a progress bar) or" if allow_true else "None or"
    raise InputError(f"{name} must be {allowed} a function f(done, total), not {_show(value)}")


def vector(value: Any, name: str, length: int | None = None) -> np.ndarray:
    """A 1-D array of float64 (finite is checked by the engine, which names the entry)."""
    try:
        a = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"{name} must be a sequence of numbers, not {_show(value)} ({e})") from None
    if a.ndim != 1:
        raise InputError(f"{name} must be one-dimensional, got shape {a.shape}")
    if length is not None and len(a) != length:
        raise InputError(f"{name} has {len(a)} entries; the model has {length} coordinates")
    return a


def times(value: Any) -> np.ndarray:
    if value is None:
        raise InputError("times must be a sequence of numbers, not None")
    return vector(value, "times")


def optional_vector(value: Any, name: str, length: int | None = None) -> np.ndarray | None:
    return None if value is None else vector(value, name, length)


def mapping(value: Any, name: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InputError(f"{name} must be a dict, not {_show(value)}")
    return value


def of_type(value: Any, name: str, kind: type, what: str) -> Any:
    if not isinstance(value, kind):
        raise InputError(f"{name} must be {what}, not {_show(value)}")
    return value


def is_sweep(value: Any) -> bool:
    """Whether ``value`` is the Results of a sweep, known by what the views read of it (its
    times, coordinates and model), so that a view need not import the class it draws."""
    return all(hasattr(value, a) for a in ("times", "q", "model", "n_steps"))


def sweep(value: Any, name: str) -> Any:
    if not is_sweep(value):
        raise InputError(f"{name} must be the Results of a sweep, not {_show(value)}")
    return value


def each(values: Any, name: str, check: Callable[[Any, str], Any]) -> list[Any]:
    """A list of checked items (``name[i]`` in the messages)."""
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        raise InputError(f"{name} must be a list, not {_show(values)}")
    return [check(v, f"{name}[{i}]") for i, v in enumerate(values)]


def optional_module(module: str, what: str, extra: str) -> Any:
    """Imports an optional dependency, or raises `DependencyError` saying ``what`` needs
    it and how to install it (the package, or linkwork's ``extra``)."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        package = module.partition(".")[0]
        raise DependencyError(
            f"{what} needs {package}: pip install {package} (or pip install 'linkwork[{extra}]')"
        ) from None


def requires(module: str, extra: str = "studies") -> Any:
    """Imports an optional dependency of an extra (default ``studies``), or raises
    `DependencyError` with the pip command."""
    try:
        return importlib.import_module(module)
    except ImportError:
        package = {"distributed": "dask[distributed]", "h5netcdf": "h5netcdf"}.get(
            module, module.split(".")[0]
        )
        raise DependencyError(
            f"this needs {package}, which is not installed: pip install 'linkwork[{extra}]' "
            f"(or pip install '{package}')"
        ) from None
