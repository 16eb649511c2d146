"""A sweep told what to keep (``outputs``): the kept columns are the full sweep's bit for
bit, kept points are the full sweep's body points, the rest is refused by name."""

from __future__ import annotations

import csv
import gc
import math

import numpy as np
import pytest

import linkwork as lw
from linkwork import examples
from linkwork.cli import main

TIMES = np.linspace(0.0, 2.0 * math.pi / 5.0, 721)


@pytest.fixture(scope="module")
def four_bar() -> lw.Model:
    return examples.four_bar().compile()


@pytest.fixture(scope="module")
def full(four_bar: lw.Model) -> lw.Results:
    return four_bar.sweep(TIMES)


def test_columns_and_points_kept_are_the_full_sweeps(four_bar: lw.Model, full: lw.Results) -> None:
    r = four_bar.sweep(TIMES, outputs=["rocker.theta", "P", "B", ("coupler", (0.1, 0.05)), "crank"])
    assert r.columns == ["rocker.theta", "crank.x", "crank.y", "crank.theta"]
    assert list(r.points) == ["P", "B", "coupler(0.1, 0.05)"]
    # the same solve: the same bits
    for k, c in enumerate(r.columns):
        j = four_bar.columns.index(c)
        for got, want in ((r.q, full.q), (r.qd, full.qd), (r.qdd, full.qdd)):
            assert got is not None and want is not None
            assert np.array_equal(got[:, k], want[:, j])
    # the points from the poses (cos, sin from the pins or from theta: round-off apart)
    anchor = [a for a in four_bar._core.anchors if a[0] == "B"][0]
    for name, want in (
        ("P", full.point("P")),
        ("B", full.point_at(four_bar.body_names[anchor[3]], anchor[4:6])),
        ("coupler(0.1, 0.05)", full.point_at("coupler", (0.1, 0.05))),
    ):
        got = r.points[name]
        assert r.point(name) is got
        for g, w, tol in zip(
            (got.position, got.velocity, got.acceleration),
            (want.position, want.velocity, want.acceleration),
            (1e-15, 1e-14, 1e-12),
        ):
            assert g is not None and w is not None and g.shape == (len(TIMES), 2)
            np.testing.assert_allclose(g, w, rtol=0, atol=tol)
    # a body kept whole answers as before; one not kept is refused by name
    np.testing.assert_array_equal(r.body("crank").theta, full.body("crank").theta)
    with pytest.raises(KeyError, match="rocker.x was not kept"):
        r.body("rocker")
    with pytest.raises(KeyError, match="was not kept"):
        r.point_at("rocker", (0.0, 0.1))
    assert np.array_equal(r.pivot_ratio, full.pivot_ratio) and len(r.events) == len(full.events)


def test_positions_only_path(four_bar: lw.Model, full: lw.Results) -> None:
    r = four_bar.sweep(TIMES, outputs="P", derivatives=0, every=4)
    assert r.q.shape == (len(TIMES[::4]), 0) and r.qd is None
    p = r.points["P"]
    assert p.velocity is None and p.acceleration is None
    np.testing.assert_allclose(p.position, full.point("P").position[::4], rtol=0, atol=1e-15)
    names, units, data = r.table()
    assert names == ["time", "P.x", "P.y", "iterations", "residual", "pivot_ratio"]
    assert units[:3] == ["s", "m", "m"] and data.shape == (len(r), 6)
    assert "P.x" in r.summary()


def test_what_needs_every_coordinate_says_so(four_bar: lw.Model) -> None:
    r = four_bar.sweep(TIMES[:50], outputs=["rocker"])
    with pytest.raises(ValueError, match="needs every coordinate"):
        r.transmission_angle()
    assert four_bar.sweep(TIMES[:50], outputs=list(four_bar.columns)).transmission_angle().shape == (50,)


@pytest.mark.parametrize(
    "bad, match",
    [
        (["nowhere"], "no output named 'nowhere'.*crank.*rocker.theta.*P"),
        ([3], "an output is a name"),
        ([("nobody", (0.0, 0.0))], "no body named 'nobody'"),
        ([("coupler", (0.0,))], "point of 'coupler'"),
    ],
)
def test_bad_outputs_are_named(four_bar: lw.Model, bad: list, match: str) -> None:
    with pytest.raises(lw.InputError, match=match):
        four_bar.sweep(TIMES[:10], outputs=bad)


def test_model_files_say_what_to_keep(tmp_path) -> None:
    mech = examples.four_bar()
    mech.outputs = ["P", "rocker.theta"]
    path = tmp_path / "four_bar.toml"
    mech.save(path)
    assert 'outputs = ["P", "rocker.theta"]' in path.read_text()
    loaded = lw.Mechanism.load(path)
    assert loaded.outputs == ["P", "rocker.theta"]
    r = loaded.compile().sweep(TIMES[:20])
    assert r.columns == ["rocker.theta"] and list(r.points) == ["P"]
    # told otherwise, the sweep keeps what it is told
    told = loaded.compile().sweep(TIMES[:20], outputs=["crank"])
    assert told.columns == ["crank.x", "crank.y", "crank.theta"]
    mech.outputs = ["Q"]
    with pytest.raises(lw.ModelError, match="no output named 'Q'"):
        mech.compile()


def test_cli_run_keeps_a_path(tmp_path, capsys) -> None:
    model = tmp_path / "four_bar.toml"
    examples.four_bar().save(model)
    args = ["run", str(model), "--t1", "1.2566370614359172", "--steps", "200", "--out", str(tmp_path)]
    assert main(args + ["--keep", "P", "--derivatives", "0"]) == 0
    with open(tmp_path / "four_bar.csv") as f:
        header = next(csv.reader(f))
    assert header == ["t [s]", "P.x [m]", "P.y [m]", "iterations", "residual", "pivot_ratio"]
    assert main(args + ["--keep", "Q"]) == 2
    assert "--keep: no output named 'Q'" in capsys.readouterr().err
    assert main(args + ["--keep", "P", "--plot"]) == 2


def test_a_sweeps_arrays_share_one_memory_and_stay_apart(four_bar: lw.Model) -> None:
    # 100,000 steps: outputs of tens of MB, one allocation in huge pages; each array is a
    # view of its own part of it, kept alive by any array still held
    t = np.linspace(0.0, 2.0 * math.pi / 5.0, 100_000)
    r = four_bar.sweep(t)
    q, residual, times = r.q, np.asarray(r.residual), np.asarray(r.times)
    want_q, want_residual = q.copy(), residual.copy()
    assert np.array_equal(times, t)
    assert not np.shares_memory(q, residual) and not np.shares_memory(q, times)
    # writing one array leaves the others as they were
    q[:] = -1.0
    assert np.array_equal(residual, want_residual) and np.array_equal(times, t)
    assert r.qd is not None and np.all(np.isfinite(r.qd))
    q[:] = want_q
    del r
    gc.collect()
    # the arrays held outlive the results they came from, and match a new sweep bit for bit
    again = four_bar.sweep(t)
    assert np.array_equal(q, again.q) and np.array_equal(residual, again.residual)
