"""Shared helpers for the tests."""

from __future__ import annotations

import math
import threading
import time
from typing import Callable

import numpy as np


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
