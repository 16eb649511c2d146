"""The command line: demo, run (with and without forces), model files, failures."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import linkwork as lw
from linkwork.cli import main


def massive_four_bar(path) -> str:
    m = lw.Mechanism.from_dict(lw.examples.four_bar().to_dict())
    for body, mass in zip(("crank", "coupler", "rocker"), (1.0, 2.0, 1.5)):
        m.set_mass(body, mass, inertia=0.01 * mass)
    m.set_gravity()
    m.save(str(path))
    return str(path)


def test_demo_writes_csv_and_png(tmp_path, capsys):
    assert main(["demo", "slider_crank", "--steps", "500", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "worst scaled residual" in out and "smallest pivot ratio" in out and "us per step" in out
    with open(tmp_path / "slider_crank.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0][:3] == ["t [s]", "crank.x [m]", "crank.y [m]"] and len(rows) == 501
    assert (tmp_path / "slider_crank.png").stat().st_size > 10_000


def test_run_with_forces_writes_efforts_and_reactions(tmp_path, capsys):
    model = massive_four_bar(tmp_path / "fb.json")
    code = main(
        ["run", model, "--t1", "1.2566", "--steps", "400", "--forces", "--plot", "--out", str(tmp_path)]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "crank_angle" in out and "energy balance" in out
    with open(tmp_path / "fb_forces.csv") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert "crank_angle.effort [N m]" in header and "O2.Fx [N]" in header and "B.torque [N m]" in header
    table = np.array(rows[1:], dtype=float)
    # the CSV holds what the API computes
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1.2566, 400), forces=True)
    assert np.allclose(
        table[:, header.index("crank_angle.effort [N m]")], res.effort("crank_angle"), rtol=1e-12
    )
    for name in ("fb.png", "fb_forces.png"):
        assert (tmp_path / name).stat().st_size > 10_000


def test_model_files_round_trip(tmp_path):
    m = lw.examples.six_bar_watt()
    m.set_gravity((0.0, -9.81))
    m.save(str(tmp_path / "m.json"))
    back = lw.Mechanism.load(str(tmp_path / "m.json"))
    assert back.to_dict() == json.loads(json.dumps(m.to_dict()))
    t = np.linspace(0, 0.5, 50)
    assert np.array_equal(back.compile().sweep(t).q, m.compile().sweep(t).q)


def test_run_reports_a_bad_model_file(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    d = lw.examples.four_bar().to_dict()
    d["joints"][1]["body_b"] = "nobody"
    bad.write_text(json.dumps(d))
    assert main(["run", str(bad), "--out", str(tmp_path)]) == 1
    assert "joint 'A'" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "missing.json"), "--out", str(tmp_path)]) == 1


def test_run_keeps_the_good_steps_of_a_failed_sweep(tmp_path, capsys):
    m = lw.examples.slider_crank(crank=0.10, rod=0.35, offset=0.0, theta0=1.0)
    x0 = m.to_dict()["joints"][2]["at"][0]
    m.remove("crank_angle")
    m.drive_coordinate("slider", (x0, 0.0), "x", lw.Linear(x0 - 0.1, 0.1), name="pull")
    m.save(str(tmp_path / "pull.json"))
    assert (
        main(["run", str(tmp_path / "pull.json"), "--t1", "3", "--steps", "301", "--out", str(tmp_path)]) == 1
    )
    err = capsys.readouterr().err
    assert "step 157" in err and "157 steps before the failure" in err
    with open(tmp_path / "pull.csv") as f:
        assert len(list(csv.reader(f))) == 158


def test_steps_must_be_at_least_two(tmp_path):
    with pytest.raises(SystemExit):
        main(["demo", "--steps", "1", "--out", str(tmp_path)])


def test_check_reports_dof_and_limits(tmp_path, capsys):
    path = tmp_path / "rocking.json"
    lw.examples.four_bar(ground=0.40, crank=0.30, coupler=0.25, rocker=0.20).save(str(path))
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "Gruebler 1, rank 1" in out and "Gruebler 0, rank 0" in out
    limit = np.arccos((0.40**2 + 0.30**2 - 0.45**2) / (2 * 0.40 * 0.30))
    assert f"{limit:.6f}" in out and "ok" in out


def test_check_names_redundant_joints(tmp_path, capsys):
    m = lw.examples.four_bar()
    m.revolute("crank", "coupler", m.to_dict()["joints"][1]["at"], name="A_again")
    path = tmp_path / "doubled.json"
    m.save(str(path))
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert "redundant" in err and "A_again" in err
