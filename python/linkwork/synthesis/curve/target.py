"""Target curves for synthesis from a curve: points from arrays, a CSV table (x, y and
optionally the crank angle) or an SVG path as a drawing program writes it; open or
closed; timing prescribed (a crank angle per point) or free.

Bad input raises `SynthesisError` naming what is at fault: too few points for the
method, a non-finite or repeated consecutive point, an SVG without a path, a ``d``
attribute that does not parse.
"""

from __future__ import annotations

import csv
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import SynthesisError

__all__ = ["TargetCurve", "target", "from_csv", "from_svg", "svg_path_points"]


@dataclass(frozen=True)
class TargetCurve:
    """The points a coupler point must follow (``points``, n x 2, in order), whether the
    curve closes on itself (``closed``) and the crank angle at each point (``crank_angles``,
    rad) when the timing is prescribed, None when it is free."""

    points: np.ndarray
    closed: bool = False
    crank_angles: np.ndarray | None = None

    @property
    def timed(self) -> bool:
        return self.crank_angles is not None

    def __len__(self) -> int:
        return len(self.points)

    @property
    def size(self) -> float:
        """The diagonal of the points' bounding box (a length scale)."""
        return float(np.hypot(*np.ptp(self.points, axis=0)))

    def require(self, count: int, method: str) -> None:
        """`SynthesisError` unless there are at least ``count`` points (``method`` needs them)."""
        if len(self) < count:
            raise SynthesisError(f"{method} needs at least {count} target points, the curve has {len(self)}")


def target(points: Any, closed: bool = False, crank_angles: Any = None, minimum: int = 3) -> TargetCurve:
    """A `TargetCurve` from an n x 2 array of points (and n crank angles, rad, if timed),
    checked: at least ``minimum`` points, all finite, no point equal to the one before it
    (or, closed, the last equal to the first)."""
    p = np.array(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise SynthesisError(f"target points are an n x 2 array (x, y), not shape {p.shape}")
    if len(p) < minimum:
        raise SynthesisError(f"a target curve needs at least {minimum} points, got {len(p)}")
    bad = np.flatnonzero(~np.all(np.isfinite(p), axis=1))
    if bad.size:
        raise SynthesisError(f"target point {bad[0] + 1} is not finite: {p[bad[0]].tolist()}")
    step = np.hypot(*np.diff(p, axis=0).T)
    scale = max(float(np.hypot(*np.ptp(p, axis=0))), 1e-300)
    same = np.flatnonzero(step <= 1e-12 * scale)
    if same.size:
        raise SynthesisError(f"target points {same[0] + 1} and {same[0] + 2} coincide: {p[same[0]].tolist()}")
    if closed and math.hypot(*(p[-1] - p[0])) <= 1e-12 * scale:
        raise SynthesisError("a closed target repeats its first point at the end: give each point once")
    angles = None
    if crank_angles is not None:
        angles = np.array(crank_angles, dtype=float).reshape(-1)
        if angles.shape != (len(p),):
            raise SynthesisError(f"{len(angles)} crank angles for {len(p)} target points")
        if not np.all(np.isfinite(angles)):
            raise SynthesisError("a prescribed crank angle is not finite")
        if np.any(np.diff(angles) == 0.0):
            k = int(np.flatnonzero(np.diff(angles) == 0.0)[0])
            raise SynthesisError(f"target points {k + 1} and {k + 2} have the same crank angle")
    return TargetCurve(p, bool(closed), angles)


def from_csv(path: str | Path, closed: bool = False, minimum: int = 3) -> TargetCurve:
    """A target from a CSV file: a header row naming x, y and optionally a third column,
    the crank angle (rad) at each point, which makes the timing prescribed."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and any(c.strip() for c in r)]
    if not rows:
        raise SynthesisError(f"{path}: no rows")
    try:
        float(rows[0][0])
    except ValueError:
        rows = rows[1:]  # a header
    try:
        data = [[float(c) for c in r] for r in rows]
    except ValueError as e:
        raise SynthesisError(f"{path}: a cell is not a number ({e})") from None
    widths = {len(r) for r in data}
    if not widths or widths - {2, 3} or len(widths) > 1:
        raise SynthesisError(
            f"{path}: every row is x, y or x, y, crank angle (found {sorted(widths)} columns)"
        )
    a = np.array(data, dtype=float).reshape(len(data), -1)
    angles = a[:, 2] if a.shape[1] == 3 else None
    return target(a[:, :2], closed=closed, crank_angles=angles, minimum=minimum)


_TOKEN = re.compile(r"[MmLlHhVvCcSsQqTtZz]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_ARITY = {"M": 2, "L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "T": 2, "Z": 0}


def _segments(d: str) -> tuple[list[tuple[str, np.ndarray]], bool]:
    """The path as absolute segments: ("L", [p0, p1]), ("C", [p0, c1, c2, p1]),
    ("Q", [p0, c, p1]); and whether it closes (a Z). One subpath."""
    tokens = _TOKEN.findall(d)
    if re.sub(r"[\s,]", "", _TOKEN.sub(" ", d)):
        raise SynthesisError(f"SVG path data does not parse (only M, L, H, V, C, S, Q, T, Z): {d[:60]!r}")
    segs: list[tuple[str, np.ndarray]] = []
    cur = np.zeros(2)
    start = np.zeros(2)
    last_ctrl: np.ndarray | None = None
    closed = False
    k = 0
    cmd = ""
    while k < len(tokens):
        if tokens[k].isalpha():
            cmd = tokens[k]
            k += 1
            if cmd in "Zz":
                if segs and segs[-1][0] != "M":
                    closed = True
                cur = start.copy()
                continue
        elif not cmd:
            raise SynthesisError(f"SVG path data starts with a number, not a command: {d[:60]!r}")
        up = cmd.upper()
        n = _ARITY[up]
        nums = tokens[k : k + n]
        if len(nums) < n or any(t.isalpha() for t in nums):
            raise SynthesisError(f"SVG path command {cmd!r} needs {n} numbers: {d[:60]!r}")
        v = np.array([float(t) for t in nums])
        k += n
        rel = cmd.islower()
        base = cur if rel else np.zeros(2)
        if up == "M":
            if segs or closed:
                raise SynthesisError("the SVG path has more than one subpath: give the curve as one")
            cur = start = base + v
            cmd = "l" if rel else "L"  # further pairs are line-tos
            last_ctrl = None
            continue
        if up in "HV":
            p1 = cur.copy()
            i = 0 if up == "H" else 1
            p1[i] = (cur[i] if rel else 0.0) + v[0]
            segs.append(("L", np.array([cur, p1])))
            cur, last_ctrl = p1, None
        elif up == "L":
            p1 = base + v
            segs.append(("L", np.array([cur, p1])))
            cur, last_ctrl = p1, None
        elif up in "CS":
            if up == "C":
                c1, c2, p1 = base + v[0:2], base + v[2:4], base + v[4:6]
            else:
                c1 = 2 * cur - last_ctrl if last_ctrl is not None and segs[-1][0] == "C" else cur.copy()
                c2, p1 = base + v[0:2], base + v[2:4]
            segs.append(("C", np.array([cur, c1, c2, p1])))
            cur, last_ctrl = p1, c2
        else:  # Q, T
            if up == "Q":
                c, p1 = base + v[0:2], base + v[2:4]
            else:
                c = 2 * cur - last_ctrl if last_ctrl is not None and segs[-1][0] == "Q" else cur.copy()
                p1 = base + v[0:2]
            segs.append(("Q", np.array([cur, c, p1])))
            cur, last_ctrl = p1, c
    if not segs:
        raise SynthesisError(f"the SVG path draws nothing: {d[:60]!r}")
    if closed and np.hypot(*(cur - segs[-1][1][-1])) > 0.0:
        segs.append(("L", np.array([segs[-1][1][-1], cur])))
    return segs, closed


def _bezier(ctrl: np.ndarray, t: np.ndarray) -> np.ndarray:
    n = len(ctrl) - 1
    t = t[:, None]
    return sum(math.comb(n, k) * (1 - t) ** (n - k) * t**k * ctrl[k] for k in range(n + 1))  # type: ignore[return-value]


def svg_path_points(d: str, samples: int = 64) -> tuple[np.ndarray, bool]:
    """``samples`` points evenly spaced by arc length along an SVG path's ``d`` (M, L, H,
    V, C, S, Q, T, Z, absolute and relative; one subpath), and whether it closes. A
    closed path's last sample is not a repeat of its first. SVG's y axis points down: the
    points are returned as drawn (y down); `from_svg` flips them."""
    segs, closed = _segments(d)
    # a dense polyline, then resampled at equal arc length
    dense = [segs[0][1][0][None, :]]
    for kind, ctrl in segs:
        t = np.linspace(0.0, 1.0, 2 if kind == "L" else 257)[1:]
        dense.append(_bezier(ctrl, t))
    poly = np.vstack(dense)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(poly, axis=0).T))])
    if s[-1] <= 0.0:
        raise SynthesisError("the SVG path has zero length")
    keep = np.concatenate([[True], np.diff(s) > 0.0])
    poly, s = poly[keep], s[keep]
    u = np.linspace(0.0, s[-1], samples, endpoint=not closed)
    return np.column_stack([np.interp(u, s, poly[:, 0]), np.interp(u, s, poly[:, 1])]), closed


def from_svg(
    source: str | Path, samples: int = 64, closed: bool | None = None, minimum: int = 3
) -> TargetCurve:
    """A target from an SVG file (or its text): the first ``<path>``'s ``d``, sampled at
    ``samples`` points evenly along it (`svg_path_points`), y flipped up. ``closed``:
    default, closed when the path ends with Z. Transforms are not applied."""
    text = str(source)
    if not text.lstrip().startswith("<"):
        text = Path(source).read_text()
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise SynthesisError(f"the SVG is not well-formed XML: {e}") from None
    path = next((el for el in root.iter() if el.tag.rsplit("}", 1)[-1] == "path" and el.get("d")), None)
    if path is None:
        raise SynthesisError("the SVG has no <path> with a d attribute")
    pts, is_closed = svg_path_points(path.get("d", ""), samples)
    pts[:, 1] = -pts[:, 1]
    return target(pts, closed=is_closed if closed is None else closed, minimum=minimum)
