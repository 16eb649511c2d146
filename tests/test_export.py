"""Exports: SVG and DXF drawings read back and checked against the sweep (joints, points,
paths, units), DataFrames, CSV and Parquet with named points and units, and the errors
of bad arguments and missing packages."""

from __future__ import annotations

import csv
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw

REV = 2 * math.pi / 5.0  # one crank revolution of the examples (5 rad/s)
EXAMPLES = Path(__file__).parent.parent / "examples"
NS = {"svg": "http://www.w3.org/2000/svg"}


def four_bar(n: int = 121) -> lw.Results:
    return lw.examples.four_bar().compile().sweep(np.linspace(0.0, REV, n))


def pins_of(root: ET.Element) -> dict[str, tuple[float, float]]:
    return {
        c.get("data-name", ""): (float(c.get("cx", "nan")), float(c.get("cy", "nan")))
        for c in root.iterfind(".//svg:circle[@class='pin']", NS)
    }


def four_bar_joints(q: np.ndarray, res: lw.Results) -> dict[str, np.ndarray]:
    """The four-bar's pins from its coordinates: each bar's frame sits at its first pin
    (O2 on the crank, A on the coupler, O4 on the rocker); B is the rocker's end, 0.25 m
    along it."""
    col = {c: q[..., k] for k, c in enumerate(res.columns)}
    th = col["rocker.theta"]
    return {
        "O2": np.stack([col["crank.x"], col["crank.y"]], -1),
        "A": np.stack([col["coupler.x"], col["coupler.y"]], -1),
        "O4": np.stack([col["rocker.x"], col["rocker.y"]], -1),
        "B": np.stack([col["rocker.x"] + 0.25 * np.cos(th), col["rocker.y"] + 0.25 * np.sin(th)], -1),
    }


# -- SVG ----------------------------------------------------------------------------------


@pytest.mark.parametrize("row", [0, 37, 120])
def test_svg_pins_points_and_bodies_sit_where_the_sweep_puts_them(tmp_path, row):
    res = four_bar()
    text = res.to_svg(tmp_path / "fb.svg", t=float(res.times[row]))
    assert (tmp_path / "fb.svg").read_text() == text
    root = ET.fromstring(text.encode())
    assert root.get("data-unit") == "m" and float(root.get("data-time", "nan")) == res.times[row]
    expected = four_bar_joints(res.q[row], res)
    pins = pins_of(root)
    assert set(pins) == set(expected)
    for name, xy in expected.items():
        assert np.abs(np.subtract(pins[name], xy)).max() < 1e-9, name
    (p,) = root.iterfind(".//svg:circle[@class='point']", NS)
    assert p.get("data-name") == "P"
    assert (
        np.abs(
            np.array([float(p.get("cx", "")), float(p.get("cy", ""))]) - res.point("P").position[row]
        ).max()
        < 1e-12
    )
    # the coupler's outline goes through A, B and P
    (coupler,) = root.iterfind(".//svg:polygon[@data-name='coupler']", NS)
    corners = np.array([[float(v) for v in xy.split(",")] for xy in coupler.get("points", "").split()])
    for target in (expected["A"], expected["B"], res.point("P").position[row]):
        assert np.hypot(*(corners - target).T).min() < 1e-9


def test_svg_path_is_the_coupler_curve_and_the_page_is_drawn_to_scale():
    res = four_bar(361)
    root = ET.fromstring(res.to_svg(max_points=100).encode())
    (path,) = root.iterfind(".//svg:polyline[@class='path']", NS)
    assert path.get("data-name") == "P"
    pts = np.array([[float(v) for v in xy.split(",")] for xy in path.get("points", "").split()])
    rows = np.unique(np.linspace(0, 360, 100).round().astype(int))
    assert len(pts) == len(rows) and np.abs(pts - res.point("P").position[rows]).max() < 1e-12
    # y up: the drawing group flips y; the view box holds the whole motion, width in mm at 1:1
    assert root.find("svg:g[@id='world']", NS).get("transform") == "scale(1,-1)"
    x0, y0, w, h = (float(v) for v in root.get("viewBox", "").split())
    assert float(root.get("width", "").removesuffix("mm")) == pytest.approx(1000 * w, rel=1e-5)
    assert float(root.get("height", "").removesuffix("mm")) == pytest.approx(1000 * h, rel=1e-5)
    assert x0 < pts[:, 0].min() and pts[:, 0].max() < x0 + w
    assert -(y0 + h) < pts[:, 1].min() and pts[:, 1].max() < -y0


def test_svg_between_steps_is_solved_there_on_the_sweeps_branch():
    res = four_bar(13)
    t = 0.5 * (res.times[4] + res.times[5])
    root = ET.fromstring(res.to_svg(t=t).encode())
    assert float(root.get("data-time", "nan")) == t
    exact = lw.examples.four_bar().compile().solve(t)
    pins = pins_of(root)
    for name, xy in four_bar_joints(exact.q, res).items():
        assert np.abs(np.subtract(pins[name], xy)).max() < 1e-9, name


def test_svg_draws_sliders_curves_and_millimetres():
    res = lw.Mechanism.load(EXAMPLES / "cam_rise_dwell_fall.toml").compile().sweep(np.linspace(0.0, 1.0, 41))
    root = ET.fromstring(res.to_svg(t=0.5).encode())
    assert root.get("data-unit") == res.model.units["length"]
    curves = list(root.iterfind(".//svg:polyline[@class='curve']", NS))
    assert len(curves) == 2  # the cam's profile and the roller
    assert len(list(root.iterfind(".//svg:polygon[@class='block']", NS))) == 1
    mm = lw.Mechanism.load(EXAMPLES / "four_bar.toml").compile().sweep(np.linspace(0.0, REV, 21))
    root = ET.fromstring(mm.to_svg().encode())
    w = float(root.get("viewBox", "").split()[2])
    assert root.get("data-unit") == "mm" and float(root.get("width", "").removesuffix("mm")) == pytest.approx(
        w
    )
    # the same mechanism in mm: pins 1000 times further out
    pins_m, pins_mm = pins_of(ET.fromstring(four_bar(21).to_svg().encode())), pins_of(root)
    for name in pins_m:
        assert np.abs(1000 * np.array(pins_m[name]) - pins_mm[name]).max() < 1e-9


def test_svg_and_dxf_refuse_bad_arguments(tmp_path):
    res = four_bar(11)
    with pytest.raises(lw.InputError, match="outside the sweep"):
        res.to_svg(t=REV + 1.0)
    with pytest.raises(lw.InputError, match="'wheel'"):
        res.to_svg(paths=["wheel"])
    with pytest.raises(lw.InputError, match="t must be a number"):
        res.to_svg(t="0.1")  # type: ignore[arg-type]
    with pytest.raises(lw.InputError, match="max_points"):
        res.to_svg(max_points=1)
    with pytest.raises(lw.InputError, match="file name"):
        res.to_dxf(3)  # type: ignore[arg-type]
    with pytest.raises(lw.InputError, match="no steps"):
        lw.Results(res.model, _empty(res)).to_svg()


def _empty(res: lw.Results) -> dict:
    raw = {
        k: getattr(res, k)[:0] for k in ("times", "q", "qd", "qdd", "iterations", "residual", "pivot_ratio")
    }
    return raw | {"det_sign": res.det_sign[:0], "events": []}


# -- DXF ----------------------------------------------------------------------------------


def _name(entity) -> str:
    return entity.get_xdata("LINKWORK")[0].value


@pytest.mark.parametrize("example, unit, insunits", [("four_bar", "m", 6), ("four_bar.toml", "mm", 4)])
def test_dxf_reads_back_with_pins_bodies_and_paths_on_their_layers(tmp_path, example, unit, insunits):
    ezdxf = pytest.importorskip("ezdxf")
    mech = lw.Mechanism.load(EXAMPLES / example) if example.endswith(".toml") else lw.examples.four_bar()
    res = mech.compile().sweep(np.linspace(0.0, REV, 181))
    scale = 1000.0 if unit == "mm" else 1.0
    row = 50
    res.to_dxf(tmp_path / "fb.dxf", t=float(res.times[row]), max_points=181)
    doc = ezdxf.readfile(tmp_path / "fb.dxf")
    assert doc.header["$INSUNITS"] == insunits and doc.header["$MEASUREMENT"] == 1
    msp = doc.modelspace()
    assert {e.dxf.layer for e in msp} >= {"BODIES", "PINS", "GROUND", "POINTS", "PATHS", "LABELS"}
    metres = four_bar(181)
    expected = {k: scale * v for k, v in four_bar_joints(metres.q[row], metres).items()}
    pins = {_name(c): np.array(c.dxf.center)[:2] for c in msp.query("CIRCLE[layer=='PINS']")}
    assert set(pins) == set(expected)
    for name, xy in expected.items():
        assert np.abs(pins[name] - xy).max() < 1e-9 * scale, name
    (p,) = msp.query("POINT[layer=='POINTS']")
    assert _name(p) == "P"
    assert np.abs(np.array(p.dxf.location)[:2] - res.point("P").position[row]).max() < 1e-12 * scale
    (path,) = msp.query("LWPOLYLINE[layer=='PATHS']")
    assert _name(path) == "P"
    assert np.abs(np.array(path.get_points("xy")) - res.point("P").position).max() < 1e-12 * scale
    bodies = {_name(e): e for e in msp.query("*[layer=='BODIES']")}
    assert set(bodies) == {"crank", "coupler", "rocker"}
    assert bodies["coupler"].closed and bodies["crank"].dxftype() == "LWPOLYLINE"  # a bar: two points
    crank = np.array(bodies["crank"].get_points("xy"))
    assert sorted(np.hypot(*(crank - expected["O2"]).T).round(9)) == [0.0, round(0.2 * scale, 9)]


def test_dxf_draws_sliders_and_curves(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    res = lw.Mechanism.load(EXAMPLES / "cam_rise_dwell_fall.toml").compile().sweep(np.linspace(0.0, 1.0, 41))
    res.to_dxf(tmp_path / "cam.dxf", t=0.25)
    msp = ezdxf.readfile(tmp_path / "cam.dxf").modelspace()
    assert len(msp.query("LWPOLYLINE[layer=='CURVES']")) == 2
    (block,) = msp.query("LWPOLYLINE[layer=='SLIDERS']")
    assert block.closed and len(block) == 4


# -- tables -------------------------------------------------------------------------------


def test_dataframe_holds_the_table_with_points_and_units():
    pytest.importorskip("pandas")
    res = four_bar(31)
    df = res.to_dataframe(points=True)
    names, units, data = res.table(points=True)
    assert list(df.columns) == names and df.shape == data.shape
    assert df["iterations"].dtype == np.int64 and np.array_equal(df["iterations"], res.iterations)
    assert np.array_equal(df["P.x"], res.point("P").position[:, 0])
    assert np.array_equal(df["P.y_dd"], res.point("P").acceleration[:, 1])
    assert np.array_equal(df["rocker.theta_d"], res.qd[:, res.columns.index("rocker.theta")])
    assert df.attrs["units"] == dict(zip(names, units)) and df.attrs["model"] == "four-bar"
    assert (df.attrs["units"]["P.x"], df.attrs["units"]["P.y_d"], df.attrs["units"]["time"]) == (
        "m",
        "m/s",
        "s",
    )
    assert "P.x" not in res.to_dataframe().columns
    with pytest.raises(lw.InputError, match="points"):
        res.to_dataframe(points="yes")  # type: ignore[arg-type]


def test_positions_only_tables_have_no_rate_columns():
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 5), derivatives=0)
    names, units, data = res.table(points=True)
    assert names == ["time"] + res.columns + ["P.x", "P.y", "iterations", "residual", "pivot_ratio"]
    assert data.shape == (5, len(names)) and units[-4] == "m"


def test_csv_and_parquet_with_points_keep_values_and_units(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    pd = pytest.importorskip("pandas")
    res = lw.Mechanism.load(EXAMPLES / "four_bar.toml").compile().sweep(np.linspace(0.0, REV, 41))
    res.to_csv(tmp_path / "fb.csv", points=True)
    with open(tmp_path / "fb.csv") as f:
        rows = list(csv.reader(f))
    assert "P.x [mm]" in rows[0] and "P.y_dd [mm/s^2]" in rows[0]
    k = rows[0].index("P.y [mm]")
    assert np.array_equal(np.array([float(r[k]) for r in rows[1:]]), res.point("P").position[:, 1])
    res.to_parquet(tmp_path / "fb.parquet", points=True)
    table = pq.read_table(tmp_path / "fb.parquet")
    assert table.schema.field("P.x_d").metadata == {b"unit": b"mm/s"}
    assert table.schema.field("rocker.theta").metadata == {b"unit": b"rad"}
    df = pd.read_parquet(tmp_path / "fb.parquet")
    assert np.array_equal(df["P.x"].to_numpy(), res.point("P").position[:, 0])
    assert np.array_equal(df["time"].to_numpy(), res.times)


@pytest.mark.parametrize(
    "module, call",
    [
        ("pandas", lambda res, path: res.to_dataframe()),
        ("pyarrow", lambda res, path: res.to_parquet(path / "x.parquet")),
        ("ezdxf", lambda res, path: res.to_dxf(path / "x.dxf")),
    ],
)
def test_a_missing_package_is_named_with_its_pip_command(tmp_path, monkeypatch, module, call):
    res = four_bar(5)
    monkeypatch.setitem(sys.modules, module, None)  # importing it now raises ImportError
    with pytest.raises(lw.DependencyError, match=f"pip install {module}") as e:
        call(res, tmp_path)
    assert isinstance(e.value, ImportError) and "linkwork[export]" in str(e.value)


def test_svg_labels_name_bodies_joints_and_points_as_the_figure_does():
    """The SVG's labels are the static figure's (MechanismArtists with labels): every body
    at the middle of its outline, every joint and named point beside its point."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from linkwork.view.drawing import Geometry, MechanismArtists, Motion

    res = four_bar()
    row = 37
    root = ET.fromstring(res.to_svg(t=float(res.times[row])).encode())
    labels = {t.text: t for t in root.iterfind(".//svg:g[@id='labels']/svg:text", NS)}
    bodies = {t.text: t for t in root.iterfind(".//svg:text[@class='label body-label']", NS)}
    assert set(bodies) == {"crank", "coupler", "rocker"}
    expected = four_bar_joints(res.q[row], res)
    outlines = {
        "crank": [expected["O2"], expected["A"]],
        "rocker": [expected["O4"], expected["B"]],
        "coupler": [expected["A"], expected["B"], res.point("P").position[row]],
    }
    for name, corners in outlines.items():
        # upright text outside the flipped group: y is -y there
        x, y = float(bodies[name].get("x", "nan")), -float(bodies[name].get("y", "nan"))
        assert np.abs(np.array([x, y]) - np.mean(corners, axis=0)).max() < 1e-9, name
    # the figure labels the same names
    fig, ax = plt.subplots()
    g = Geometry.from_model(res.model)
    artists = MechanismArtists(ax, Motion(g, res), labels=True)
    figure = {t.get_text() for _, t in artists.labels} | {"P"}
    plt.close(fig)
    assert set(labels) == figure == {"crank", "coupler", "rocker", "O2", "A", "B", "O4", "P"}
