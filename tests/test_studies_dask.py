"""Design studies on a real Dask cluster (two worker processes on this machine): the
results equal the in-process ones bit for bit, and a worker killed mid-study loses and
doubles nothing."""

from __future__ import annotations

import math
import os
import signal

import numpy as np
import pytest

import linkwork as lw
from linkwork import study as S

distributed = pytest.importorskip("distributed")

TURN = 2 * math.pi / 5.0


def study():
    times = np.linspace(0.0, TURN, 300)
    return lw.Study(lw.examples.four_bar(), times, ["path P", "angle rocker", "transmission_min", "grashof"])


def same(a, b):
    assert a.errors.tolist() == b.errors.tolist()
    assert np.array_equal(a.designs.values, b.designs.values)
    for key in a.figures:
        x, y = a.figures[key], b.figures[key]
        if x.dtype == object:
            assert x.tolist() == y.tolist(), key
        else:
            assert np.array_equal(x, y, equal_nan=True), key


def test_cluster_results_equal_in_process_bit_for_bit(client):
    st = study()
    designs = S.latin_hypercube({"length crank": (0.15, 0.26), "pivot O4.x": (0.3, 0.4)}, 200, seed=5)
    here = st.run(designs)
    there = st.run(designs, scheduler=client, chunk=30, timeout=120)
    assert there.where.startswith("dask")
    assert len(there.tasks) == 7
    assert 0 < here.n_failed < 200  # failures travel as the designs' errors
    same(here, there)


def test_scheduler_address_reaches_the_same_cluster(client):
    st = study()
    designs = S.grid({"length crank": [0.19, 0.2, 0.21], "length rocker": [0.24, 0.25]})
    there = st.run(designs, scheduler=client.scheduler.address, chunk=2, timeout=120)
    same(st.run(designs), there)


def test_a_worker_killed_mid_study_loses_nothing_and_counts_nothing_twice(client):
    st = study()
    designs = S.sample(
        st.nominal(["length crank", "length coupler"]),
        {"length crank": S.Normal(1e-4), "length coupler": S.Normal(1e-4)},
        1200,
        seed=9,
    )
    pids_before = set(client.run(os.getpid).values())
    killed = []

    def kill_one(done, total):
        if not killed and done < total:
            pid = sorted(client.run(os.getpid).values())[0]
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    there = st.run(designs, scheduler=client, chunk=40, progress=kill_one, timeout=120)
    assert killed and killed[0] in pids_before
    starts = [t[0] for t in there.tasks]
    assert starts == list(range(0, 1200, 40))  # every chunk once
    assert sum(t[1] for t in there.tasks) == 1200
    assert there.n_failed == 0
    same(st.run(designs), there)
    client.wait_for_workers(2, timeout=60)  # the nanny brought a worker back
    assert set(client.run(os.getpid).values()) != pids_before


def test_tolerance_study_on_the_cluster(client):
    st = study()
    tolerances = {"length crank": S.Normal(1e-4), "pivot O4.x": S.Uniform(1e-4)}
    here = st.tolerance(tolerances, n=100, seed=4)
    there = st.tolerance(tolerances, n=100, seed=4, scheduler=client, chunk=25, timeout=120)
    assert np.array_equal(here.deviations, there.deviations)
    assert np.array_equal(here.linear.rss, there.linear.rss)


def test_cli_study_on_the_cluster(client, tmp_path, capsys):
    from linkwork.cli import main

    folder = os.path.join(os.path.dirname(__file__), "..", "examples", "studies")
    args = ["study", os.path.join(folder, "four_bar_atlas.toml"), "--out", str(tmp_path)]
    assert main([*args, "--scheduler", client.scheduler.address, "--chunk", "5"]) == 0
    there = capsys.readouterr().out
    assert f"on {client.scheduler.address}" in there and "8 tasks of up to 5 designs" in there
    remote = S.open_dataset(str(tmp_path / "four_bar_atlas.nc"))
    assert main([*args]) == 0
    local = S.open_dataset(str(tmp_path / "four_bar_atlas.nc"))
    assert np.array_equal(remote.path_P.values, local.path_P.values, equal_nan=True)
    assert remote.error.values.tolist() == local.error.values.tolist()


def test_a_script_without_a_main_guard_runs_a_local_cluster_study(tmp_path) -> None:
    """`study.run(designs, scheduler="local")` at a script's top level, with no
    `if __name__ == "__main__":` guard: the worker processes do not run the script again
    (which made each fail, and the study raise "Nanny failed to start"); the study's
    figures equal the in-process ones. A real LocalCluster in a child interpreter."""
    import subprocess
    import sys

    script = tmp_path / "study_script.py"
    script.write_text(
        "import numpy as np\n"
        "import linkwork as lw\n"
        "from linkwork import study as S\n"
        "m = lw.build.four_bar(1.0, 0.3, 1.0, 0.8, omega=1.0)\n"
        "study = lw.Study(m, np.linspace(0.0, 6.0, 40), ['angle rocker'])\n"
        "designs = S.listed({'length coupler': [1.0, 0.9, 0.3]})\n"
        "here = study.run(designs)\n"
        "there = study.run(designs, scheduler='local', progress=False)\n"
        "a, b = here.dataset['angle_rocker'].values, there.dataset['angle_rocker'].values\n"
        "assert np.array_equal(a, b, equal_nan=True), 'figures differ'\n"
        "assert list(there.dataset['error'].values) == list(here.dataset['error'].values)\n"
        "print('study ran on', there.where)\n"
    )
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(lw.__file__)))
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join(filter(None, [package_root, os.environ.get("PYTHONPATH")]))
    )
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=240, cwd=tmp_path, env=env
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "study ran on dask" in done.stdout
    assert "Nanny failed" not in done.stderr
