"""`linkwork simulate`: a model file with free coordinates integrated from the command
line, its CSV against the exact solutions of IFToMM A01 and A02, and its refusals."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from linkwork import Constant, Mechanism
from linkwork.cli import main
from linkwork.mechanism import benchmarks, examples
from linkwork.reference import exact


def read(path) -> dict[str, np.ndarray]:  # type: ignore[no-untyped-def]
    with open(path) as f:
        rows = list(csv.reader(f))
    names = [h.split(" [")[0] for h in rows[0]]
    data = np.array(rows[1:], dtype=float)
    return {n: data[:, k] for k, n in enumerate(names)}


def test_the_pendulum_file_is_simulated_to_its_exact_motion(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    benchmarks.pendulum().mechanism.save(tmp_path / "a01.toml")
    argv = [
        "simulate", str(tmp_path / "a01.toml"), "--t1", "10", "--steps", "201",
        "--rtol", "1e-10", "--out", str(tmp_path), "--plot",
    ]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "1 free coordinate" in out and "energy balance within" in out
    table = read(tmp_path / "a01.csv")
    x, y = exact.pendulum_tip(table["t"])
    # rk8 at rtol 1e-10: ~1e-9 over 10 s (tests/test_dynamics_forward.py)
    assert np.abs(table["P1.x"] - x).max() < 1e-8 and np.abs(table["P1.y"] - y).max() < 1e-8
    assert (tmp_path / "a01.png").exists() and (tmp_path / "a01_paths.png").exists()


def test_initial_rates_by_column_name_start_the_n_four_bar(tmp_path) -> None:  # type: ignore[no-untyped-def]
    bench = benchmarks.n_four_bar(1)
    bench.mechanism.save(tmp_path / "a02.toml")
    model = bench.mechanism.compile(free=True)
    rates = [f"{c}={v:g}" for c, v in zip(model.columns, bench.qd0) if v != 0.0]
    argv = [
        "simulate", str(tmp_path / "a02.toml"), "--t1", "3", "--steps", "61",
        "--rtol", "1e-11", "--qd0", ",".join(rates), "--out", str(tmp_path),
    ]  # fmt: skip
    assert main(argv) == 0
    table = read(tmp_path / "a02.csv")
    phi, _ = exact.n_four_bar_branch(1, 3.0).phi(table["t"])
    for k in (0, 1):
        assert np.abs(np.angle(np.exp(1j * (table[f"crank{k}.theta"] - phi)))).max() < 1e-8


def test_a_driven_model_and_a_bad_rate_are_refused(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    examples.four_bar().save(tmp_path / "fb.toml")
    assert main(["simulate", str(tmp_path / "fb.toml"), "--out", str(tmp_path)]) == 1
    assert "nothing to simulate" in capsys.readouterr().err
    benchmarks.pendulum().mechanism.save(tmp_path / "a01.toml")
    argv = ["simulate", str(tmp_path / "a01.toml"), "--qd0", "bar.omega=1", "--out", str(tmp_path)]
    assert main(argv) == 2
    assert "bar.omega" in (err := capsys.readouterr().err) and "bar.theta" in err
    # rates the pin does not allow: refused before any step, nothing written
    argv = ["simulate", str(tmp_path / "a01.toml"), "--qd0", "bar.x=1", "--out", str(tmp_path / "x")]
    assert main(argv) == 1
    assert "inconsistent initial" in capsys.readouterr().err
    assert not (tmp_path / "x" / "a01.csv").exists()


def test_default_span_and_a_run_that_stops_early_writes_what_it_reached(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """Without --t1 the run spans t0 .. t0 + 1; a run out of steps (--max-steps) exits 1
    and writes the times it reached, each on the exact motion."""
    benchmarks.pendulum().mechanism.save(tmp_path / "a01.toml")
    assert (
        main(["simulate", str(tmp_path / "a01.toml"), "--t0", "0.5", "--steps", "11", "--out", str(tmp_path)])
        == 0
    )
    assert read(tmp_path / "a01.csv")["t"] == pytest.approx(np.linspace(0.5, 1.5, 11), abs=1e-15)
    argv = [
        "simulate", str(tmp_path / "a01.toml"), "--t1", "10", "--steps", "101", "--rtol", "1e-10",
        "--max-steps", "40", "--out", str(tmp_path),
    ]  # fmt: skip
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert "times before the failure are in the output" in err
    table = read(tmp_path / "a01.csv")
    assert 1 < len(table["t"]) < 101
    x, y = exact.pendulum_tip(table["t"])
    assert np.abs(table["P1.x"] - x).max() < 1e-8


def test_a_slider_at_the_end_of_its_travel_stops_or_goes_on(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """--at-travel-end: a 2 kg slider pushed by 3 N from rest reaches x = 0.5, its travel's
    max, at t* = sqrt(2 m x / F) = sqrt(2/3) s; "stop" (the default) writes the rows up to
    t* and names the event, "continue" names it and writes every row, on x = F t^2 / (2 m)."""
    m = Mechanism("pushed slider")
    s = m.body("slider", mass=2.0, inertia=0.1)
    m.prismatic(m.ground, s, at=(0.0, 0.0), axis=(1.0, 0.0), name="guide", travel=(-0.1, 0.5))
    m.force(s, (0.0, 0.0), (1.0, 0.0), Constant(3.0), name="push")
    m.save(tmp_path / "pushed.toml")
    t_star = math.sqrt(2.0 * 2.0 * 0.5 / 3.0)
    base = ["simulate", str(tmp_path / "pushed.toml"), "--t1", "2", "--steps", "41", "--rtol", "1e-10"]
    assert main([*base, "--out", str(tmp_path / "stop")]) == 0
    out = capsys.readouterr().out
    assert "1 event(s):" in out and "end_of_travel" in out and f"t = {t_star:.9g} s" in out
    stopped = read(tmp_path / "stop" / "pushed.csv")
    assert np.array_equal(stopped["t"], np.linspace(0.0, 2.0, 41)[np.linspace(0.0, 2.0, 41) <= t_star])
    assert main([*base, "--at-travel-end", "continue", "--out", str(tmp_path / "go")]) == 0
    assert "end_of_travel" in capsys.readouterr().out
    went = read(tmp_path / "go" / "pushed.csv")
    assert len(went["t"]) == 41
    np.testing.assert_allclose(went["slider.x"], 3.0 * went["t"] ** 2 / 4.0, rtol=0, atol=1e-9)
