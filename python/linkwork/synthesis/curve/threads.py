"""The multistarts' thread pool, with the BLAS library kept to one thread inside it.

Each refinement solves small dense systems (a trust-region step is an SVD of a few dozen
columns); a threaded BLAS splits each into threads that wait on one another, and on a
loaded machine every such wait costs a time slice: one refinement ran 12 times slower
with OpenBLAS's default threads than with one. The starts themselves fill the cores.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor
from typing import Any, TypeVar

__all__ = ["one_blas_thread", "map_starts"]

T = TypeVar("T")


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """BLAS and LAPACK on one thread within the block (threadpoolctl; without it, as is)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - optional dependency
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def map_starts(run: Callable[[Any], T], jobs: Iterable[Any], workers: int | None) -> list[T]:
    """``run`` over ``jobs`` on ``workers`` threads (default: every core), in order, BLAS
    on one thread meanwhile."""
    with one_blas_thread(), ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
        return list(pool.map(run, jobs))
