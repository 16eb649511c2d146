"""Shared helpers for the tests."""

from __future__ import annotations

import math
import threading
import time
from typing import Callable

import numpy as np

import linkwork as lw


def revolution(omega: float = 5.0, n: int = 721) -> np.ndarray:
    """Times of one crank revolution at omega rad/s."""
    return np.linspace(0.0, 2.0 * math.pi / omega, n)


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angle difference brought into [-pi, pi)."""
    return (np.asarray(angle) + math.pi) % (2.0 * math.pi) - math.pi


def rel_err(got: np.ndarray, want: np.ndarray) -> float:
    """Largest error relative to the quantity's largest magnitude over the run."""
    scale = float(np.max(np.abs(want)))
    return float(np.max(np.abs(np.asarray(got) - want)) / (scale if scale > 0 else 1.0))


def spins_while(work: Callable[[], object]) -> tuple[int, float]:
    """Runs ``work`` on a thread while this thread counts loop turns: (turns, seconds).
    With the GIL held by ``work`` the count stays near zero; released, it runs freely."""
    done = threading.Event()

    def run() -> None:
        work()
        done.set()

    thread = threading.Thread(target=run)
    ticks, start = 0, time.perf_counter()
    thread.start()
    while not done.is_set():
        ticks += 1
    thread.join()
    return ticks, time.perf_counter() - start


def translating_cam(
    kind: str, curve: dict, law: lw.Law, e: float = 0.02, R: float = 0.05, rho: float = 0.015
) -> lw.Mechanism:
    """A cam pinned at the origin and turned by ``law``, under a follower ("knife",
    "roller" of radius rho, or "flat" facing along x) translating along the y axis, drawn
    3 mm off the circle of radius R whose centre is e from the pivot along +x (the height
    assumes that circle: the cam's curve may be it or another). The joint is "F"."""
    m = lw.Mechanism(f"cam, {kind} follower")
    cam = m.body("cam")
    reach = R + rho if kind == "roller" else R
    y0 = (R if kind == "flat" else math.sqrt(reach**2 - e**2)) + 0.003
    follower = m.body("follower", (0.0, y0))
    m.revolute(m.ground, cam, at=(0, 0), name="O")
    m.prismatic(m.ground, follower, at=(0.0, y0), axis=(0, 1), name="slide")
    extra = {"roller": {"radius": rho}, "flat": {"face": (1.0, 0.0)}}.get(kind, {})
    m.cam_follower(cam, follower, (0.0, y0), curve, kind=kind, name="F", **extra)
    m.drive_angle(cam, law, name="turn")
    return m


def eccentric_follower(kind: str, e: float, R: float, rho: float, b: np.ndarray):
    """Rise y of a follower on a disc of radius R whose centre is e from the cam pivot, at
    cam angle b (the centre's angle from the follower's normal), and dy/db, d2y/db2:
    y = e sin b + sqrt(R'^2 - e^2 cos^2 b) with R' = R (knife) or R + rho (roller), and
    y = e sin b + R for a flat face."""
    if kind == "flat":
        return e * np.sin(b) + R, e * np.cos(b), -e * np.sin(b)
    reach = R + rho if kind == "roller" else R
    root = np.sqrt(reach**2 - e**2 * np.cos(b) ** 2)
    y = e * np.sin(b) + root
    dy = e * np.cos(b) + e**2 * np.sin(2 * b) / (2 * root)
    ddy = -e * np.sin(b) + e**2 * np.cos(2 * b) / root - e**4 * np.sin(2 * b) ** 2 / (4 * root**3)
    return y, dy, ddy
