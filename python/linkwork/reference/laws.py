"""Motion laws f(t) of drivers, with f'(t) and f''(t), read from their description dicts.

Written for clarity, independently of the engine:

- the natural cubic spline solves its (small) system for the knot second derivatives
  with a dense ``np.linalg.solve``;
- expressions are parsed by Python's ``ast`` under a strict whitelist (numbers, the
  variable, ``pi``, ``e``, + - * / ** and unary signs, calls of the listed functions) and
  evaluated on a small `Jet` class (value and three derivatives: motion laws read two,
  curves written as expressions three); nothing is ``eval``-ed;
- the cam profiles built of pieces (modified trapezoid, modified sine) integrate their
  piecewise sine and constant accelerations in closed form, piece by piece, and scale
  the result to a unit rise, rather than using the engine's constants and symmetry.
"""

from __future__ import annotations

import ast
import bisect
import math
from functools import lru_cache
from typing import Any, Callable

import numpy as np

__all__ = ["motion_law", "check_law", "Jet", "expression", "expression3", "profile"]

Triple = tuple[float, float, float]
Quad = tuple[float, float, float, float]


def check_law(law: dict[str, Any]) -> None:
    """Raise ``ValueError`` if ``law`` cannot be evaluated."""
    kind = law.get("type")
    fields = {
        "constant": ["value"],
        "linear": ["value", "rate"],
        "polynomial": ["coefficients"],
        "harmonic": ["mean", "amplitude", "omega"],
        "spline": ["times", "values"],
        "expression": ["text"],
        "rise": ["lift", "duration", "profile"],
        "cam": ["segments"],
        "sequence": ["breakpoints", "laws"],
        "periodic": ["period", "law"],
        "python": ["name"],
        "scaled": ["factor", "law"],
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
    if kind == "expression":
        expression(law["text"])
    if kind == "rise":
        profile(law["profile"])
        if not float(law["duration"]) > 0.0:
            raise ValueError("rise duration must be > 0")
    if kind == "cam":
        _cam_table(law)
    if kind == "sequence":
        _check_sequence(law)
    if kind == "periodic":
        if not float(law["period"]) > 0.0:
            raise ValueError("periodic period must be > 0")
        check_law(law["law"])
    if kind == "scaled":
        check_law(law["law"])
    if kind == "python":
        raise ValueError(
            f"python law {law['name']!r}: the reference reads plain descriptions, "
            "which cannot hold a function"
        )


def motion_law(law: dict[str, Any], t: float) -> Triple:
    """(f, f', f'') of the motion law ``law`` (a description dict) at time ``t``."""
    kind = law.get("type")
    t = float(t)
    if kind == "scaled":  # a law written in degrees, converted (see model._in_radians)
        k = float(law["factor"])
        return tuple(k * v for v in motion_law(law["law"], t))  # type: ignore[return-value]
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
    if kind == "expression":
        return expression(law["text"])(t)
    if kind == "rise":
        return _rise(
            law["profile"],
            float(law.get("start", 0.0)),
            float(law["lift"]),
            float(law["duration"]),
            t - float(law.get("t0", 0.0)),
        )
    if kind == "cam":
        return _cam_eval(law, t)
    if kind == "sequence":
        k = bisect.bisect_right([float(b) for b in law["breakpoints"]], t)
        return motion_law(law["laws"][k], t)
    if kind == "periodic":
        return _periodic_eval(law, t)
    if kind == "python":
        check_law(law)
    raise ValueError(f"unknown motion law type {kind!r}")


# --- natural cubic spline ------------------------------------------------------------------


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


def _spline_eval(times: tuple[float, ...], values: tuple[float, ...], x: float) -> Triple:
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


# --- expressions ---------------------------------------------------------------------------


class Jet:
    """A value with its first, second and third derivative along one variable; arithmetic
    on jets follows the product, quotient and chain rules. Motion laws read the first
    three (`triple`), curves written as expressions all four (`quad`: c''' needs r''')."""

    __slots__ = ("f", "d", "dd", "ddd")

    def __init__(self, f: float, d: float = 0.0, dd: float = 0.0, ddd: float = 0.0) -> None:
        self.f, self.d, self.dd, self.ddd = float(f), float(d), float(dd), float(ddd)

    def triple(self) -> Triple:
        return self.f, self.d, self.dd

    def quad(self) -> Quad:
        return self.f, self.d, self.dd, self.ddd

    def derivative(self) -> Jet:
        """The jet of the first derivative (its own third derivative unknown: NaN)."""
        return Jet(self.d, self.dd, self.ddd, math.nan)

    def __add__(self, o: Jet) -> Jet:
        return Jet(self.f + o.f, self.d + o.d, self.dd + o.dd, self.ddd + o.ddd)

    def __sub__(self, o: Jet) -> Jet:
        return Jet(self.f - o.f, self.d - o.d, self.dd - o.dd, self.ddd - o.ddd)

    def __neg__(self) -> Jet:
        return Jet(-self.f, -self.d, -self.dd, -self.ddd)

    def __mul__(self, o: Jet) -> Jet:
        # Leibniz: (uv)''' = u''' v + 3 u'' v' + 3 u' v'' + u v'''
        return Jet(
            self.f * o.f,
            self.d * o.f + self.f * o.d,
            self.dd * o.f + 2 * self.d * o.d + self.f * o.dd,
            self.ddd * o.f + 3 * self.dd * o.d + 3 * self.d * o.dd + self.f * o.ddd,
        )

    def __truediv__(self, o: Jet) -> Jet:
        # a / b = a * g(b) with g = 1/x: g' = -1/x^2, g'' = 2/x^3, g''' = -6/x^4
        if o.f == 0.0:
            raise ZeroDivisionError("division by zero")
        return self * o.chain(1.0 / o.f, -1.0 / o.f**2, 2.0 / o.f**3, -6.0 / o.f**4)

    def __pow__(self, o: Jet) -> Jet:
        if o.d == 0.0 and o.dd == 0.0 and o.ddd == 0.0:
            n = o.f
            if n == 0.0:
                return Jet(1.0)
            # g = x^n, g^(k) = n (n-1) .. (n-k+1) x^(n-k); a vanishing factor drops its
            # term, where x^(n-k) may not exist (0 to a negative power)
            g = [self.f**n]
            factor = 1.0
            for k in (1, 2, 3):
                factor *= n - (k - 1)
                g.append(0.0 if factor == 0.0 else factor * _power(self.f, n - k))
            return self.chain(*g)
        # a^b = exp(b ln a)
        return exp(o * ln(self))

    def chain(self, g: float, g1: float, g2: float, g3: float) -> Jet:
        """g(self) from g, g', g'', g''' at self.f (Faa di Bruno)."""
        return Jet(
            g,
            g1 * self.d,
            g2 * self.d**2 + g1 * self.dd,
            g3 * self.d**3 + 3 * g2 * self.d * self.dd + g1 * self.ddd,
        )


def _power(x: float, p: float) -> float:
    """x ** p, infinite where Python raises for 0 to a negative power (a derivative that
    does not exist there, as in IEEE arithmetic)."""
    try:
        return x**p
    except ZeroDivisionError:
        return math.inf


def exp(u: Jet) -> Jet:
    e = math.exp(u.f)
    return u.chain(e, e, e, e)


def ln(u: Jet) -> Jet:
    return u.chain(math.log(u.f), 1.0 / u.f, -1.0 / u.f**2, 2.0 / u.f**3)


def _sqrt(u: Jet) -> Jet:
    r = math.sqrt(u.f)
    return u.chain(r, 0.5 / r, -0.25 / r**3, 0.375 / r**5)


def _tan(u: Jet) -> Jet:
    # tan' = sec^2, tan'' = 2 sec^2 tan, tan''' = 4 sec^2 tan^2 + 2 sec^4
    sec2 = 1.0 / math.cos(u.f) ** 2
    t = math.tan(u.f)
    return u.chain(t, sec2, 2.0 * sec2 * t, 4.0 * sec2 * t**2 + 2.0 * sec2**2)


def _asin(u: Jet) -> Jet:
    w = 1.0 - u.f**2
    return u.chain(math.asin(u.f), w**-0.5, u.f * w**-1.5, w**-1.5 + 3.0 * u.f**2 * w**-2.5)


def _acos(u: Jet) -> Jet:
    w = 1.0 - u.f**2
    return u.chain(math.acos(u.f), -(w**-0.5), -u.f * w**-1.5, -(w**-1.5) - 3.0 * u.f**2 * w**-2.5)


def _atan(u: Jet) -> Jet:
    w = 1.0 + u.f**2
    return u.chain(math.atan(u.f), 1.0 / w, -2.0 * u.f / w**2, -2.0 / w**2 + 8.0 * u.f**2 / w**3)


def _tanh(u: Jet) -> Jet:
    th = math.tanh(u.f)
    sech2 = 1.0 - th**2
    return u.chain(th, sech2, -2.0 * th * sech2, -2.0 * sech2**2 + 4.0 * th**2 * sech2)


def _atan2(y: Jet, x: Jet) -> Jet:
    # atan2(y, x)' = (x y' - y x') / (x^2 + y^2), differentiated twice more as a jet
    rate = (x * y.derivative() - y * x.derivative()) / (x * x + y * y)
    return Jet(math.atan2(y.f, x.f), rate.f, rate.d, rate.dd)


def _hypot(a: Jet, b: Jet) -> Jet:
    return _sqrt(a * a + b * b)


_FUNCTIONS: dict[str, tuple[int, Callable[..., Jet]]] = {
    "sin": (1, lambda u: u.chain(math.sin(u.f), math.cos(u.f), -math.sin(u.f), -math.cos(u.f))),
    "cos": (1, lambda u: u.chain(math.cos(u.f), -math.sin(u.f), -math.cos(u.f), math.sin(u.f))),
    "tan": (1, _tan),
    "asin": (1, _asin),
    "acos": (1, _acos),
    "atan": (1, _atan),
    "sinh": (1, lambda u: u.chain(math.sinh(u.f), math.cosh(u.f), math.sinh(u.f), math.cosh(u.f))),
    "cosh": (1, lambda u: u.chain(math.cosh(u.f), math.sinh(u.f), math.cosh(u.f), math.sinh(u.f))),
    "tanh": (1, _tanh),
    "exp": (1, exp),
    "ln": (1, ln),
    "log": (1, ln),
    "log10": (1, lambda u: ln(u) * Jet(1.0 / math.log(10.0))),
    "sqrt": (1, _sqrt),
    "abs": (1, lambda u: u if u.f >= 0.0 else -u),
    "atan2": (2, _atan2),
    "min": (2, lambda a, b: b if b.f < a.f else a),
    "max": (2, lambda a, b: b if b.f > a.f else a),
    "pow": (2, lambda a, b: a**b),
    "hypot": (2, _hypot),
}
_CONSTANTS = {"pi": math.pi, "e": math.e}
_BINARY = {ast.Add: Jet.__add__, ast.Sub: Jet.__sub__, ast.Mult: Jet.__mul__, ast.Div: Jet.__truediv__}


@lru_cache(maxsize=256)
def expression(text: str, variable: str = "t") -> Callable[[float], Triple]:
    """The function x -> (f, f', f'') of an expression written as text (``^`` or ``**``
    for powers); ``ValueError`` if the text uses anything outside the whitelist."""
    jet = expression3(text, variable)

    def f(x: float) -> Triple:
        value, d, dd, _ = jet(x)
        return value, d, dd

    return f


@lru_cache(maxsize=256)
def expression3(text: str, variable: str = "t") -> Callable[[float], Quad]:
    """The function x -> (f, f', f'', f''') of an expression written as text."""
    try:
        tree = ast.parse(text.replace("^", "**").strip(), mode="eval")
    except SyntaxError as e:
        raise ValueError(f"not an expression: {text!r} ({e.msg})") from None
    _whitelist(tree.body, variable, text)

    def f(x: float) -> Quad:
        return _jet(tree.body, Jet(x, 1.0), variable).quad()

    return f


def _whitelist(node: ast.AST, variable: str, text: str) -> None:
    def bad(what: str) -> ValueError:
        return ValueError(f"{what} is not allowed in an expression ({text!r})")

    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise bad(repr(node.value))
    elif isinstance(node, ast.Name):
        if node.id != variable and node.id not in _CONSTANTS:
            raise bad(f"the name {node.id!r}")
    elif isinstance(node, ast.UnaryOp):
        if not isinstance(node.op, (ast.USub, ast.UAdd)):
            raise bad(type(node.op).__name__)
        _whitelist(node.operand, variable, text)
    elif isinstance(node, ast.BinOp):
        if type(node.op) not in _BINARY and not isinstance(node.op, ast.Pow):
            raise bad(type(node.op).__name__)
        _whitelist(node.left, variable, text)
        _whitelist(node.right, variable, text)
    elif isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) or node.func.id not in _FUNCTIONS or node.keywords:
            raise bad("this call")
        arity = _FUNCTIONS[node.func.id][0]
        if len(node.args) != arity:
            raise ValueError(f"{node.func.id} takes {arity} argument(s), got {len(node.args)}")
        for a in node.args:
            _whitelist(a, variable, text)
    else:
        raise bad(type(node).__name__)


def _jet(node: ast.AST, x: Jet, variable: str) -> Jet:
    if isinstance(node, ast.Constant):
        return Jet(float(node.value))
    if isinstance(node, ast.Name):
        return x if node.id == variable else Jet(_CONSTANTS[node.id])
    if isinstance(node, ast.UnaryOp):
        u = _jet(node.operand, x, variable)
        return -u if isinstance(node.op, ast.USub) else u
    if isinstance(node, ast.BinOp):
        a, b = _jet(node.left, x, variable), _jet(node.right, x, variable)
        return a**b if isinstance(node.op, ast.Pow) else _BINARY[type(node.op)](a, b)
    assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
    return _FUNCTIONS[node.func.id][1](*(_jet(a, x, variable) for a in node.args))


# --- cam profiles --------------------------------------------------------------------------

# acceleration pieces (u_start, u_end, amplitude, omega, phase): a = amplitude sin(omega w
# + phase) with w = u - u_start, or a constant amplitude where omega = 0; unscaled
_PIECES = {
    "modified_trapezoid": [
        (0.0, 0.125, 1.0, 4 * math.pi, 0.0),
        (0.125, 0.375, 1.0, 0.0, 0.0),
        (0.375, 0.625, 1.0, 4 * math.pi, math.pi / 2),
        (0.625, 0.875, -1.0, 0.0, 0.0),
        (0.875, 1.0, 1.0, 4 * math.pi, 3 * math.pi / 2),
    ],
    "modified_sine": [
        (0.0, 0.125, 1.0, 4 * math.pi, 0.0),
        (0.125, 0.875, 1.0, 4 * math.pi / 3, math.pi / 2),
        (0.875, 1.0, 1.0, 4 * math.pi, 3 * math.pi / 2),
    ],
}


def _piece(p: tuple[float, ...], s0: float, v0: float, w: float) -> Triple:
    """(s, v, a) a distance w into piece p, from (s0, v0) at its start."""
    _, _, amp, om, ph = p
    if om == 0.0:
        return s0 + v0 * w + amp * w * w / 2, v0 + amp * w, amp
    v = v0 + amp * (math.cos(ph) - math.cos(om * w + ph)) / om
    s = s0 + v0 * w + amp * (w * math.cos(ph) / om - (math.sin(om * w + ph) - math.sin(ph)) / om**2)
    return s, v, amp * math.sin(om * w + ph)


@lru_cache(maxsize=8)
def _piece_starts(name: str) -> tuple[list[tuple[float, float]], float]:
    """(s, v) at the start of each piece, and s(1), all for the unscaled acceleration."""
    starts, s, v = [], 0.0, 0.0
    for p in _PIECES[name]:
        starts.append((s, v))
        s, v, _ = _piece(p, s, v, p[1] - p[0])
    return starts, s


def profile(name: str) -> Callable[[float], Triple]:
    """The normalised rise s(u) of a cam profile as u -> (s, s', s''), u in [0, 1]."""
    if name == "cycloidal":
        return lambda u: (
            u - math.sin(2 * math.pi * u) / (2 * math.pi),
            1 - math.cos(2 * math.pi * u),
            2 * math.pi * math.sin(2 * math.pi * u),
        )
    if name == "harmonic":
        return lambda u: (
            (1 - math.cos(math.pi * u)) / 2,
            math.pi / 2 * math.sin(math.pi * u),
            math.pi**2 / 2 * math.cos(math.pi * u),
        )
    polynomials = {"polynomial_345": [0, 0, 0, 10, -15, 6], "polynomial_4567": [0, 0, 0, 0, 35, -84, 70, -20]}
    if name in polynomials:
        s = np.polynomial.Polynomial(polynomials[name])
        ds, dds = s.deriv(), s.deriv(2)
        return lambda u: (float(s(u)), float(ds(u)), float(dds(u)))
    if name in _PIECES:
        pieces = _PIECES[name]

        def piecewise(u: float) -> Triple:
            starts, total = _piece_starts(name)
            k = max(i for i, p in enumerate(pieces) if p[0] <= u or i == 0)
            s, v, a = _piece(pieces[k], *starts[k], u - pieces[k][0])
            # scaled to a unit rise
            return s / total, v / total, a / total

        return piecewise
    raise ValueError(f"unknown cam profile {name!r}")


def _rise(name: str, start: float, lift: float, duration: float, tau: float) -> Triple:
    """start + lift s(tau / duration), held before and after (right-continuous)."""
    if tau < 0.0:
        return start, 0.0, 0.0
    if tau >= duration:
        return start + lift, 0.0, 0.0
    s, v, a = profile(name)(min(max(tau / duration, 0.0), 1.0))
    return start + lift * s, lift * v / duration, lift * a / duration**2


def _cam_table(law: dict[str, Any]) -> tuple[list[float], list[float], list[tuple[float, str]]]:
    """Start time and value of each segment (and the end), and each segment's signed
    change and profile."""
    segments = law["segments"]
    if not segments:
        raise ValueError("cam program has no segments")
    t, v = float(law.get("t0", 0.0)), float(law.get("start", 0.0))
    times, values, changes = [], [], []
    for seg in segments:
        duration = float(seg["duration"])
        if not duration > 0.0:
            raise ValueError("cam segment durations must be > 0")
        sign = {"dwell": 0.0, "rise": 1.0, "fall": -1.0}[seg["type"]]
        change = sign * float(seg.get("lift", 0.0))
        name = seg.get("profile", "cycloidal")
        profile(name)
        times.append(t)
        values.append(v)
        changes.append((change, name))
        t, v = t + duration, v + change
    times.append(t)
    values.append(v)
    return times, values, changes


def _cam_eval(law: dict[str, Any], t: float) -> Triple:
    times, values, changes = _cam_table(law)
    k = bisect.bisect_right(times, t) - 1
    if k < 0:
        return values[0], 0.0, 0.0
    if k >= len(changes):
        return values[-1], 0.0, 0.0
    change, name = changes[k]
    return _rise(name, values[k], change, times[k + 1] - times[k], t - times[k])


def _check_sequence(law: dict[str, Any]) -> None:
    b = [float(x) for x in law["breakpoints"]]
    laws = law["laws"]
    if len(laws) != len(b) + 1:
        raise ValueError(f"sequence needs one law more than breakpoints ({len(b)}, {len(laws)})")
    if any(b2 <= b1 for b1, b2 in zip(b, b[1:])):
        raise ValueError("sequence breakpoints must increase strictly")
    for sub in laws:
        check_law(sub)
    for i, t in enumerate(b):
        left, right = motion_law(laws[i], t)[0], motion_law(laws[i + 1], t)[0]
        if abs(left - right) > 1e-9 * max(1.0, abs(left), abs(right)):
            raise ValueError(f"sequence breakpoint {i} (t = {t}): the value jumps from {left} to {right}")


def _periodic_eval(law: dict[str, Any], t: float) -> Triple:
    period, t0 = float(law["period"]), float(law.get("t0", 0.0))
    k = math.floor((t - t0) / period)
    tau = (t - t0) - k * period
    if tau < 0.0:
        tau, k = tau + period, k - 1
    elif tau >= period:
        tau, k = tau - period, k + 1
    inner = law["law"]
    advance = motion_law(inner, t0 + period)[0] - motion_law(inner, t0)[0]
    f, fd, fdd = motion_law(inner, t0 + max(tau, 0.0))
    return f + k * advance, fd, fdd
