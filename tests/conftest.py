"""Fixtures shared by the test modules."""

from __future__ import annotations

import os

import pytest

import linkwork as lw


@pytest.fixture(scope="session")
def client():
    """A real Dask LocalCluster of two worker processes (one for the whole run: starting one
    takes seconds), whose workers import linkwork from where this process does."""
    distributed = pytest.importorskip("distributed")
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(lw.__file__)))
    paths = [package_root, *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    old = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths))
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
    )
    c = distributed.Client(cluster, timeout="60s")
    try:
        c.wait_for_workers(2, timeout=60)
        yield c
    finally:
        c.close()
        cluster.close()
        if old is None:
            os.environ.pop("PYTHONPATH", None)
        else:
            os.environ["PYTHONPATH"] = old
