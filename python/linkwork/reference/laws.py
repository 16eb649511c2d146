"""Motion laws f(t) of drivers, with f'(t) and f''(t), read from their description dicts.

Written for clarity: the natural cubic spline solves its (small) system for the knot
second derivatives with a dense ``np.linalg.solve``.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np

__all__ = ["motion_law", "check_law"]


def check_law(law: dict[str, Any]) -> None:
    """Raise ``ValueError`` if ``law`` cannot be evaluated."""
    kind = law.get("type")
    fields = {
        "constant": ["value"],
        "linear": ["value", "rate"],
        "polynomial": ["coefficients"],
        "harmonic": ["mean", "amplitude", "omega"],
        "spline": ["times", "values"],
    }
    if kind not in fields:
        raise ValueError(f"unknown motion law type {kind!r}")
    for key in fields[kind]:
        if key not in law:
            raise ValueError(f"{kind} motion law has no {key!r}")
    if kind == "polynomial" and len(law["coefficients"]) == 0:
        raise ValueError("polynomial motion law has no coefficients")
    if kind == "spline":
        _spline_table(tuple(float(t) for t in law["times"]), tuple(float(v) for v in law["values"]))


def motion_law(law: dict[str, Any], t: float) -> tuple[float, float, float]:
    """(f, f', f'') of the motion law ``law`` (a description dict) at time ``t``."""
    kind = law.get("type")
    t = float(t)
    if kind == "constant":
        return float(law["value"]), 0.0, 0.0
    if kind == "linear":
        return float(law["value"]) + float(law["rate"]) * t, float(law["rate"]), 0.0
    if kind == "polynomial":
        c = [float(x) for x in law["coefficients"]]
        if not c:
            raise ValueError("polynomial motion law has no coefficients")
        f = sum(ck * t**k for k, ck in enumerate(c))
        fd = sum(k * ck * t ** (k - 1) for k, ck in enumerate(c) if k >= 1)
        fdd = sum(k * (k - 1) * ck * t ** (k - 2) for k, ck in enumerate(c) if k >= 2)
        return float(f), float(fd), float(fdd)
    if kind == "harmonic":
        mean, amp, omega = float(law["mean"]), float(law["amplitude"]), float(law["omega"])
        arg = omega * t + float(law.get("phase", 0.0))
        return mean + amp * math.sin(arg), amp * omega * math.cos(arg), -amp * omega**2 * math.sin(arg)
    if kind == "spline":
        times = tuple(float(x) for x in law["times"])
        values = tuple(float(v) for v in law["values"])
        return _spline_eval(times, values, t)
    raise ValueError(f"unknown motion law type {kind!r}")


@lru_cache(maxsize=256)
def _spline_table(times: tuple[float, ...], values: tuple[float, ...]) -> np.ndarray:
    """Second derivatives M at the knots of the natural cubic spline (M[0] = M[-1] = 0).

    Continuity of the first derivative at each interior knot i gives
    h[i-1]/6 M[i-1] + (h[i-1] + h[i])/3 M[i] + h[i]/6 M[i+1]
        = (y[i+1] - y[i])/h[i] - (y[i] - y[i-1])/h[i-1].
    """
    n = len(times)
    if n < 2 or len(values) != n:
        raise ValueError(
            f"spline needs at least 2 times and as many values ({n} times, {len(values)} values)"
        )
    if not all(math.isfinite(v) for v in times + values):
        raise ValueError("spline table holds a value that is not a finite number")
    t = np.array(times)
    y = np.array(values)
    h = np.diff(t)
    if np.any(h <= 0.0):
        raise ValueError("spline times must increase strictly")
    # natural ends: rows 0 and n-1 say M = 0
    K = np.zeros((n, n))
    rhs = np.zeros(n)
    K[0, 0] = K[n - 1, n - 1] = 1.0
    for i in range(1, n - 1):
        K[i, i - 1] = h[i - 1] / 6.0
        K[i, i] = (h[i - 1] + h[i]) / 3.0
        K[i, i + 1] = h[i] / 6.0
        rhs[i] = (y[i + 1] - y[i]) / h[i] - (y[i] - y[i - 1]) / h[i - 1]
    return np.linalg.solve(K, rhs)


def _spline_eval(times: tuple[float, ...], values: tuple[float, ...], x: float) -> tuple[float, float, float]:
    M = _spline_table(times, values)
    if not (times[0] <= x <= times[-1]):
        raise ValueError(f"time {x} is outside the spline's table [{times[0]}, {times[-1]}]")
    # interval k with times[k] <= x <= times[k+1]
    k = int(np.searchsorted(np.array(times), x, side="right")) - 1
    k = min(max(k, 0), len(times) - 2)
    t0, t1 = times[k], times[k + 1]
    y0, y1 = values[k], values[k + 1]
    h = t1 - t0
    a = (t1 - x) / h
    b = (x - t0) / h
    f = a * y0 + b * y1 + ((a**3 - a) * M[k] + (b**3 - b) * M[k + 1]) * h * h / 6.0
    fd = (y1 - y0) / h - (3.0 * a * a - 1.0) / 6.0 * h * M[k] + (3.0 * b * b - 1.0) / 6.0 * h * M[k + 1]
    fdd = a * M[k] + b * M[k + 1]
    return float(f), float(fd), float(fdd)
