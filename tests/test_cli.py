"""The command line: demo, run (formats, --every, forces), plot, animations, check, model
files, failures, exit statuses and help texts. Each command runs in-process on a built-in
example saved to a file, with small step counts."""

from __future__ import annotations

import csv
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import linkwork as lw
from linkwork.cli import main

REV = 2 * math.pi / 5.0  # one crank revolution of the examples (5 rad/s)


def save(mech: lw.Mechanism, path) -> str:
    mech.save(str(path))
    return str(path)


def massive_four_bar(path) -> str:
    m = lw.Mechanism.from_dict(lw.examples.four_bar().to_dict())
    for body, mass in zip(("crank", "coupler", "rocker"), (1.0, 2.0, 1.5)):
        m.set_mass(body, mass, inertia=0.01 * mass)
    m.set_gravity()
    return save(m, path)


def pulled_slider(path) -> str:
    """A slider-crank driven by its slider, pulled past the crank's reach: the sweep
    fails at step 157 of 301 over t = 0 .. 3."""
    m = lw.examples.slider_crank(crank=0.10, rod=0.35, offset=0.0, theta0=1.0)
    x0 = m.to_dict()["joints"][2]["at"][0]
    m.remove("crank_angle")
    m.drive_coordinate("slider", (x0, 0.0), "x", lw.Linear(x0 - 0.1, 0.1), name="pull")
    return save(m, path)


def read_csv(path) -> tuple[list[str], np.ndarray]:
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=float)


# -- demo and run ------------------------------------------------------------------------


def test_demo_writes_csv_and_png(tmp_path, capsys):
    assert main(["demo", "slider_crank", "--steps", "500", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "worst scaled residual" in out and "smallest pivot ratio" in out and "us per step" in out
    header, table = read_csv(tmp_path / "slider_crank.csv")
    assert header[:3] == ["t [s]", "crank.x [m]", "crank.y [m]"] and table.shape[0] == 500
    assert (tmp_path / "slider_crank.png").stat().st_size > 10_000


def test_run_csv_holds_every_kth_step_of_the_sweep(tmp_path, capsys):
    model = save(lw.examples.slider_crank(), tmp_path / "sc.json")
    assert main(["run", model, "--t1", "1", "--steps", "101", "--every", "10", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    # the summary: range of every output, residual, iterations, pivot ratio, events
    for text in ("slider.x", "worst scaled residual", "Newton iterations", "smallest pivot ratio", "events"):
        assert text in out
    header, table = read_csv(tmp_path / "sc.csv")
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1, 101), every=10)
    assert header[:4] == ["t [s]", "crank.x [m]", "crank.y [m]", "crank.theta [rad]"]
    assert "slider.x_d [m/s]" in header and "rod.theta_dd [rad/s^2]" in header and header[-1] == "pivot_ratio"
    assert table.shape == (11, 1 + 3 * 9 + 3)
    # CSV floats are written in shortest round-trip form: the values come back exactly
    assert np.array_equal(table[:, 0], np.linspace(0, 1, 101)[::10])
    assert np.array_equal(table[:, 1:10], res.q) and np.array_equal(table[:, 19:28], res.qdd)
    assert np.array_equal(table[:, -1], res.pivot_ratio)


def test_run_npz_has_one_array_per_column_with_units(tmp_path):
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    assert main(["run", model, "--t1", "1", "--steps", "51", "--format", "npz", "--out", str(tmp_path)]) == 0
    assert not (tmp_path / "fb.csv").exists()
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1, 51))
    with np.load(tmp_path / "fb.npz", allow_pickle=False) as f:
        units = dict(zip(f["columns"].tolist(), f["units"].tolist()))
        assert np.array_equal(f["time"], res.times)
        for k, c in enumerate(res.columns):
            assert np.array_equal(f[c], res.q[:, k])
            assert np.array_equal(f[c + "_d"], res.qd[:, k])
            assert np.array_equal(f[c + "_dd"], res.qdd[:, k])
        assert np.array_equal(f["iterations"], res.iterations) and np.array_equal(f["residual"], res.residual)
        assert set(f.keys()) == set(units) | {"columns", "units"}
    assert units["time"] == "s" and units["rocker.theta"] == "rad" and units["coupler.x_dd"] == "m/s^2"
    assert units["pivot_ratio"] == ""


def test_run_parquet_has_the_columns_and_their_units(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    args = ["run", model, "--t1", "1", "--steps", "41", "--every", "4", "--format", "parquet"]
    assert main(args + ["--out", str(tmp_path)]) == 0
    table = pq.read_table(tmp_path / "fb.parquet")
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1, 41), every=4)
    names, units, data = res.table()
    assert table.column_names == names and table.num_rows == 11
    for k, name in enumerate(names):
        assert np.array_equal(table.column(name).to_numpy(), data[:, k])
        assert table.schema.field(name).metadata == {b"unit": units[k].encode()}
    assert table.schema.metadata[b"model"] == b"four-bar"


def test_parquet_without_pyarrow_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow now raises ImportError
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    with pytest.raises(SystemExit) as e:
        main(["run", model, "--format", "parquet", "--out", str(tmp_path)])
    assert e.value.code == 2 and "pip install pyarrow" in capsys.readouterr().err
    assert not list(tmp_path.glob("fb.*parquet"))


def test_run_with_forces_writes_efforts_and_reactions(tmp_path, capsys):
    model = massive_four_bar(tmp_path / "fb.json")
    code = main(
        ["run", model, "--t1", "1.2566", "--steps", "400", "--forces", "--plot", "--out", str(tmp_path)]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "crank_angle" in out and "energy balance" in out
    header, table = read_csv(tmp_path / "fb_forces.csv")
    assert "crank_angle.effort [N m]" in header and "O2.Fx [N]" in header and "B.torque [N m]" in header
    # the CSV holds what the API computes
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1.2566, 400), forces=True)
    assert np.allclose(
        table[:, header.index("crank_angle.effort [N m]")], res.effort("crank_angle"), rtol=1e-12
    )
    for name in ("fb.png", "fb_paths.png", "fb_forces.png"):
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
    err = capsys.readouterr().err
    assert "joint 'A'" in err and str(bad) in err
    missing = str(tmp_path / "missing.json")
    assert main(["run", missing, "--out", str(tmp_path)]) == 1
    assert missing in capsys.readouterr().err


@pytest.mark.parametrize("fmt", ["csv", "npz"])
def test_run_keeps_the_good_steps_of_a_failed_sweep(tmp_path, capsys, fmt):
    model = pulled_slider(tmp_path / "pull.json")
    args = ["run", model, "--t1", "3", "--steps", "301", "--format", fmt, "--out", str(tmp_path)]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert "step 157" in err and "157 steps before the failure" in err and model in err
    if fmt == "csv":
        assert read_csv(tmp_path / "pull.csv")[1].shape[0] == 157
    else:
        with pytest.raises(lw.SolveError) as e:
            lw.Mechanism.load(model).compile().sweep(np.linspace(0, 3, 301))
        with np.load(tmp_path / "pull.npz") as f:
            assert np.array_equal(f["slider.x"], e.value.partial.body("slider").x) and len(f["time"]) == 157


def test_failed_sweep_with_every_keeps_the_kept_good_steps(tmp_path, capsys):
    model = pulled_slider(tmp_path / "pull.json")
    args = ["run", model, "--t1", "3", "--steps", "301", "--every", "10", "--out", str(tmp_path)]
    assert main(args) == 1
    _, table = read_csv(tmp_path / "pull.csv")
    assert np.array_equal(table[:, 0], np.linspace(0, 3, 301)[:157:10])  # steps 0, 10, ..., 150
    capsys.readouterr()


@pytest.mark.parametrize(
    "args",
    [
        ["demo", "--steps", "1"],
        ["run", "M.json", "--steps", "1"],
        ["run", "M.json", "--every", "0"],
        ["run", "M.json", "--format", "xlsx"],
        ["plot", "M.json", "--frames", "0"],
        ["plot", "M.json", "--fps", "-3"],
        ["plot", "M.json", "--animate", "movie.avi"],
        ["view", "M.json", "--frames", "1"],
        ["run", "M.json", "--at", "noon"],
        ["run", "M.json", "--angles", "grad"],
        ["check", "M.json", "--angles", "turns"],
        ["frobnicate"],
    ],
)
def test_bad_usage_exits_with_status_2(tmp_path, capsys, args):
    with pytest.raises(SystemExit) as e:
        main(args + ["--out", str(tmp_path)] if args[0] != "frobnicate" else args)
    assert e.value.code == 2
    assert "error" in capsys.readouterr().err


# -- plot and animations -------------------------------------------------------------------


def test_plot_writes_outputs_and_paths(tmp_path, capsys):
    model = save(lw.examples.six_bar_watt(), tmp_path / "watt.json")
    args = [
        "plot",
        model,
        "--t1",
        str(REV),
        "--steps",
        "201",
        "--outputs",
        "output,link5.x,C.y",
        "--paths",
        "C,D",
    ]
    assert main(args + ["--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "watt.png" in out and "watt_paths.png" in out and not (tmp_path / "watt.csv").exists()
    for name in ("watt.png", "watt_paths.png"):
        with Image.open(tmp_path / name) as im:
            assert im.format == "PNG" and im.size[0] > 500 and im.size[1] > 400


def test_run_plot_uses_the_default_outputs_and_paths(tmp_path, capsys):
    model = save(lw.examples.slider_crank(), tmp_path / "sc.json")
    assert main(["run", model, "--t1", "0.5", "--steps", "51", "--plot", "--out", str(tmp_path)]) == 0
    for name in ("sc.csv", "sc.png", "sc_paths.png"):
        assert (tmp_path / name).stat().st_size > 1000
    capsys.readouterr()


def test_plot_refuses_unknown_outputs_and_paths_before_sweeping(tmp_path, capsys):
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    assert main(["plot", model, "--outputs", "rocker.theta,wheel", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "'wheel'" in err and "rocker.theta" in err and "P.x" in err and model in err
    assert main(["run", model, "--paths", "Q", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "'Q'" in err and "P" in err and not (tmp_path / "out").exists()


def test_animate_writes_a_gif_of_the_asked_frames(tmp_path, capsys):
    model = save(lw.examples.slider_crank(), tmp_path / "sc.json")
    gif = tmp_path / "movies" / "sc.gif"
    args = ["plot", model, "--t1", str(REV), "--steps", "301", "--animate", str(gif), "--frames", "6"]
    assert main(args + ["--fps", "20", "--out", str(tmp_path)]) == 0
    assert f"{gif} (6 frames)" in capsys.readouterr().out
    with Image.open(gif) as im:
        assert im.format == "GIF" and im.n_frames == 6 and im.size == (640, 480)
        assert im.info["duration"] == 50  # ms per frame at 20 fps
        im.seek(3)  # frames differ: the mechanism moves
        middle = np.asarray(im.convert("RGB"))
        im.seek(0)
        assert np.abs(middle.astype(int) - np.asarray(im.convert("RGB")).astype(int)).sum() > 0


def test_run_animates_only_the_steps_there_are(tmp_path, capsys):
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    gif = str(tmp_path / "fb.gif")
    assert main(["run", model, "--t1", "1", "--steps", "9", "--every", "2", "--animate", gif]) == 0
    with Image.open(gif) as im:
        assert im.n_frames == 5  # 9 steps, every 2nd kept: fewer than the 120 frames asked
    capsys.readouterr()


def test_plot_of_a_failed_sweep_draws_the_good_steps_and_exits_1(tmp_path, capsys):
    model = pulled_slider(tmp_path / "pull.json")
    gif = str(tmp_path / "pull.gif")
    args = ["plot", model, "--t1", "3", "--steps", "301", "--animate", gif, "--frames", "4"]
    assert main(args + ["--out", str(tmp_path)]) == 1
    assert "157 steps before the failure" in capsys.readouterr().err
    with Image.open(gif) as im:
        assert im.n_frames == 4
    assert (tmp_path / "pull_paths.png").exists()


def test_mp4_without_ffmpeg_is_a_clear_usage_error(tmp_path, capsys, monkeypatch):
    from matplotlib.animation import FFMpegWriter

    monkeypatch.setattr(FFMpegWriter, "isAvailable", classmethod(lambda cls: False))
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    with pytest.raises(SystemExit) as e:
        main(["plot", model, "--animate", str(tmp_path / "fb.mp4"), "--out", str(tmp_path)])
    assert e.value.code == 2 and "ffmpeg" in capsys.readouterr().err
    assert not (tmp_path / "fb.png").exists()


def test_mp4_with_ffmpeg(tmp_path, capsys):
    from matplotlib.animation import FFMpegWriter

    if not FFMpegWriter.isAvailable():
        pytest.skip("ffmpeg is not on the PATH")
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    mp4 = tmp_path / "fb.mp4"
    assert (
        main(["plot", model, "--steps", "51", "--animate", str(mp4), "--frames", "5", "--out", str(tmp_path)])
        == 0
    )
    assert mp4.read_bytes()[4:8] == b"ftyp"  # an MP4 container
    if shutil.which("ffprobe"):
        probe = subprocess.run(
            ["ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=width,height,nb_read_frames",
             "-of", "csv=p=0", str(mp4)],
            capture_output=True, text=True, check=True,
        )  # fmt: skip
        assert probe.stdout.split() == ["640,480,5"]
    capsys.readouterr()


# -- check ---------------------------------------------------------------------------------


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


@pytest.mark.parametrize("content", ['{"bodies": [', "[1, 2]", None])
def test_check_of_a_bad_model_file_names_the_file(tmp_path, capsys, content):
    path = tmp_path / "broken.json"
    if content is not None:
        path.write_text(content)
    assert main(["check", str(path)]) == 1
    captured = capsys.readouterr()
    assert captured.err.startswith(f"error: {path}: ") and captured.out == ""


# -- help ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "command, says",
    [
        ([], ["run", "plot", "view", "check", "demo", "CSV", "GIF", "SVG, DXF", "HTML", "Exit status"]),
        (["run"], ["MODEL.csv", ".npz", ".parquet", "MODEL_paths.png", "--every", "--animate", "status 1"]),
        (["plot"], ["MODEL.png", "MODEL_paths.png", "FILE.gif", "--outputs", "--paths", "--frames"]),
        (["check"], ["degrees of freedom", "writes nothing"]),
        (["view"], ["MODEL.html", "FILE.html", "slider", "events", "without a network", "--frames"]),
        (["run"], ["MODEL.svg", "MODEL.dxf", "--at", "--points"]),
        (["demo"], ["NAME.csv", "NAME.png"]),
    ],
)
def test_help_says_what_each_command_writes(capsys, command, says):
    with pytest.raises(SystemExit) as e:
        main(command + ["--help"])
    assert e.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    for text in says:
        assert text in out, text


def test_check_reports_grashof_type_limits_and_assembly_modes(tmp_path, capsys):
    path = tmp_path / "rocking.toml"
    lw.examples.four_bar(ground=0.40, crank=0.30, coupler=0.25, rocker=0.20, theta0=0.8).save(str(path))
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    # the file is in rad: its angles are printed in rad, and in deg when asked
    assert "non-Grashof triple-rocker" in out and "crank angle limits -1.371564 .. 1.371564 rad" in out
    assert "angles printed in rad (the file's angle unit" in out
    assert "assembly modes at t = 0: 2" in out and "open" in out and "crossed" in out
    assert main(["check", str(path), "--angles", "deg"]) == 0
    out = capsys.readouterr().out
    assert "crank angle limits -78.5848 .. 78.5848 deg" in out and "from -78.5848" in out
    assert "rad" not in out.split("limits of motion")[1]


def test_run_summary_carries_units_in_the_files_angle_unit(tmp_path, capsys):
    model = os.path.join(os.path.dirname(__file__), "..", "examples", "four_bar.toml")
    assert main(["run", model, "--steps", "101", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "units: lengths in mm, angles in deg (as the file declares)" in out
    rows = {line.split()[0]: line.split()[1:] for line in out.splitlines() if line.startswith("  crank.")}
    assert rows["crank.theta"][-1] == "deg" and float(rows["crank.theta"][1]) == pytest.approx(360.0)
    assert float(rows["crank.theta"][2]) == pytest.approx(286.4788975654116)  # deg/s
    assert rows["crank.x"][-1] == "mm"
    assert main(["run", model, "--steps", "101", "--angles", "rad", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    theta = next(line.split() for line in out.splitlines() if line.startswith("  crank.theta"))
    assert theta[-1] == "rad" and float(theta[2]) == pytest.approx(2 * math.pi)


def test_check_works_on_a_model_beyond_the_dense_limit(tmp_path, capsys):
    # 400 loops, 3600 coordinates: mobility by the sparse LU (the dense SVD stops at
    # 3000), a few drivers' limits, the linkages listed in part, no mode search
    path = tmp_path / "chain400.toml"
    lw.examples.chain(400).save(path)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "3600 coordinates" in out or "3600" in out
    assert "assembly modes at t = 0: not searched (400 loops" in out
    assert "more linkages" in out
    assert out.strip().endswith("ok")


def test_ctrl_c_in_run_stops_cleanly_and_writes_the_steps_done(tmp_path):
    import signal
    import time

    model = tmp_path / "chain30.toml"
    lw.examples.chain(30).save(model)
    out = tmp_path / "out"
    proc = subprocess.Popen(
        [sys.executable, "-m", "linkwork", "run", str(model), "--steps", "20000000", "--every", "1000",
         "--format", "npz", "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
        # Ctrl-C's default disposition, whatever this process inherited: a shell's
        # background job starts with SIGINT ignored, and Python then leaves it ignored
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    # the model line is printed once it is compiled, just before the sweep (minutes for
    # the whole grid) starts
    assert proc.stdout is not None
    while "<linkwork Model" not in proc.stdout.readline():
        assert proc.poll() is None, proc.stderr.read() if proc.stderr else ""
    # the grid (20 million times) and the outputs are set up before the first step: on a
    # loaded machine that takes over a second, and a Ctrl-C then has no steps to write
    time.sleep(3.0)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    assert "interrupted at t = " in stderr and "steps done" in stderr
    data = np.load(out / "chain30.npz")
    n = len(data["time"])
    assert 0 < n < 20000
    assert np.isfinite(data["crank1.theta"] if "crank1.theta" in data else data[data["columns"][1]]).all()


# -- the interactive page and drawings --------------------------------------------------


def test_view_writes_the_page_of_the_sweep(tmp_path, capsys):
    model = save(lw.examples.slider_crank(), tmp_path / "sc.json")
    args = ["view", model, "--t1", "1", "--steps", "101", "--frames", "51", "--outputs", "slider.x,rod"]
    assert main(args + ["--out", str(tmp_path / "pages")]) == 0
    assert (
        "wrote " + str(tmp_path / "pages" / "sc.html") + " (51 frames of 101 steps, 0 events"
        in capsys.readouterr().out
    )
    html = (tmp_path / "pages" / "sc.html").read_text(encoding="utf-8")
    data = json.loads(html.split('type="application/json">', 1)[1].split("</script>", 1)[0])
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1, 101))
    assert data["steps"] == list(range(0, 101, 2)) and data["times"] == res.times[::2].tolist()
    assert [o["name"] for o in data["outputs"]] == ["slider.x", "rod.theta"]
    assert data["outputs"][0]["value"] == res.body("slider").x[::2].tolist()
    # --out FILE.html names the page itself
    assert main(["view", model, "--steps", "11", "--out", str(tmp_path / "page.html")]) == 0
    assert (tmp_path / "page.html").read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_view_refuses_unknown_outputs_before_sweeping(tmp_path, capsys):
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    assert main(["view", model, "--outputs", "wheel", "--out", str(tmp_path)]) == 2
    assert "no output named 'wheel'" in capsys.readouterr().err
    assert not list(tmp_path.glob("*.html"))


def test_run_writes_svg_dxf_and_points(tmp_path, capsys):
    ezdxf = pytest.importorskip("ezdxf")
    import xml.etree.ElementTree as ET

    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    args = ["run", model, "--t1", "1", "--steps", "101", "--svg", "--dxf", "--at", "0.25", "--points"]
    assert main(args + ["--out", str(tmp_path)]) == 0
    assert "fb.svg" in capsys.readouterr().out
    exact = lw.Mechanism.load(model).compile().solve(0.25)
    coupler = np.array([exact.body("coupler").x, exact.body("coupler").y])  # pin A: the coupler's origin
    root = ET.parse(tmp_path / "fb.svg").getroot()
    (a,) = [c for c in root.iter("{http://www.w3.org/2000/svg}circle") if c.get("data-name") == "A"]
    assert np.abs(np.array([float(a.get("cx")), float(a.get("cy"))]) - coupler).max() < 1e-9
    pins = {
        e.get_xdata("LINKWORK")[0].value: e
        for e in ezdxf.readfile(tmp_path / "fb.dxf").query("CIRCLE[layer=='PINS']")
    }
    assert np.abs(np.array(pins["A"].dxf.center)[:2] - coupler).max() < 1e-9
    header, table = read_csv(tmp_path / "fb.csv")
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0, 1, 101))
    assert np.array_equal(table[:, header.index("P.x [m]")], res.point("P").position[:, 0])
    assert "P.y_dd [m/s^2]" in header


def test_dxf_without_ezdxf_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ezdxf", None)
    model = save(lw.examples.four_bar(), tmp_path / "fb.json")
    with pytest.raises(SystemExit) as e:
        main(["plot", model, "--dxf", "--out", str(tmp_path)])
    assert e.value.code == 2 and "pip install ezdxf" in capsys.readouterr().err


# -- the sweep's span and the figures' abscissa --------------------------------------------


def test_t1_defaults_to_one_cycle_of_the_periodic_driver(tmp_path, capsys):
    # the shipped four-bar is in deg: one turn is 360 / |rate| there
    model = os.path.join(os.path.dirname(__file__), "..", "examples", "four_bar.toml")
    assert main(["run", model, "--steps", "11", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    rate = lw.Mechanism.load(model).to_dict()["drivers"][0]["law"]["rate"]
    assert "one cycle of crank_angle, 360 / |rate|" in out
    header, rows = read_csv(tmp_path / "four_bar.csv")
    assert abs(rows[-1, header.index("t [s]")] - 360.0 / abs(rate)) < 1e-12
    theta = rows[:, header.index("crank.theta [rad]")]
    assert abs(theta[-1] - theta[0] - 2 * math.pi) < 1e-9


def test_t1_of_a_harmonic_driver_and_the_default_without_one(tmp_path, capsys):
    m = lw.examples.four_bar()
    m.remove("crank_angle")
    m.drive_angle("crank", lw.Harmonic(0.3, 0.2, 4.0), name="wobble")
    assert (
        main(["run", save(m, tmp_path / "h.json"), "--t0", "0.5", "--steps", "5", "--out", str(tmp_path)])
        == 0
    )
    header, rows = read_csv(tmp_path / "h.csv")
    assert abs(rows[-1, 0] - (0.5 + 2 * math.pi / 4.0)) < 1e-12
    assert "one cycle of wobble, 2 pi / |omega|" in capsys.readouterr().out
    # two cranks turning: no single cycle, t1 = t0 + 1 s, and the output says so
    two = os.path.join(os.path.dirname(__file__), "..", "examples", "five_bar_two_inputs.toml")
    assert main(["run", two, "--steps", "5", "--out", str(tmp_path)]) == 0
    assert "t1 = 1 s (the default" in capsys.readouterr().out
    header, rows = read_csv(tmp_path / "five_bar_two_inputs.csv")
    assert rows[-1, 0] == 1.0


def test_plot_against_the_input_angle_in_the_files_unit(tmp_path, capsys, monkeypatch):
    import matplotlib.figure

    saved = []
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", lambda fig, *a, **k: saved.append(fig))
    model = os.path.join(os.path.dirname(__file__), "..", "examples", "four_bar.toml")
    args = ["plot", model, "--steps", "37", "--x", "input", "--outputs", "rocker", "--out", str(tmp_path)]
    assert main(args) == 0
    ax = saved[0].axes[0]
    assert saved[0].axes[-1].get_xlabel() == "crank_angle [deg]"
    rate = lw.Mechanism.load(model).to_dict()["drivers"][0]["law"]["rate"]
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0.0, 360.0 / rate, 37))
    x, y = ax.lines[0].get_data()
    crank = res.body("crank").theta
    assert np.max(np.abs(x - np.degrees(crank - crank[0]) - x[0])) < 1e-9 and abs(x[-1] - x[0] - 360) < 1e-9
    assert np.max(np.abs(y - res.body("rocker").theta)) < 1e-9
    capsys.readouterr()


def test_x_axis_of_a_distance_driver_and_bad_choices(tmp_path, capsys):
    from linkwork.view import figures

    model = pulled_slider(tmp_path / "pull.json")
    res = lw.Mechanism.load(model).compile().sweep(np.linspace(0.0, 1.0, 11))
    along = figures.x_axis(res, "input")
    assert along.label == "pull" and along.unit == "m"
    assert (
        np.max(np.abs(along.value - res.body("slider").x - (along.value[0] - res.body("slider").x[0])))
        < 1e-12
    )
    assert np.all(figures.x_axis(res, "time").value == res.times)
    with pytest.raises(lw.InputError, match="driver's name"):
        figures.x_axis(res, "angle")
    two = os.path.join(os.path.dirname(__file__), "..", "examples", "five_bar_two_inputs.toml")
    assert main(["plot", two, "--x", "input", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--x input needs one moving driver" in err and "crank1_angle, crank2_angle" in err
    assert main(["run", two, "--plot", "--x", "crank3", "--out", str(tmp_path / "o")]) == 2
    assert "not 'crank3'" in capsys.readouterr().err and not (tmp_path / "o").exists()
