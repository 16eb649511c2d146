"""Targets in the pictures of a synthesized design: the precision points and poses marked
in its SVG, DXF, page and PNG, and the traced point's distance from each, checked against
an independent closed-form four-bar (numpy only, no engine)."""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from linkwork import synthesis as S
from linkwork.view.targets import Targets, deviation, of_design, sweep_design

EXAMPLES = Path(__file__).parent.parent / "examples" / "synthesis"
SVG = "{http://www.w3.org/2000/svg}"

# the generator of examples/synthesis/motion.toml: ground pivots O2, O4, crank, coupler,
# rocker, and the coupler point in the frame of A -> B; poses at crank angles PHI
O2, O4 = np.array([0.0, 0.0]), np.array([4.0, 0.5])
CRANK, COUPLER, ROCKER = 1.5, 4.0, 3.0
LOCAL = np.array([1.7, 1.1])
PHI = np.array([0.3, 0.7, 1.2, 1.8, 2.3])


def closed_form(phi: np.ndarray, side: float) -> tuple[np.ndarray, np.ndarray]:
    """(P, coupler angle) of the generator at crank angles ``phi``, on the assembly whose
    triangle A, B, O4 turns the way ``side`` says (+1 / -1): two circles intersected."""
    a = O2 + CRANK * np.column_stack([np.cos(phi), np.sin(phi)])
    d = O4 - a
    L = np.hypot(*d.T)
    along = (COUPLER**2 - ROCKER**2 + L**2) / (2 * L)
    h = np.sqrt(COUPLER**2 - along**2)
    u = d / L[:, None]
    n = np.column_stack([-u[:, 1], u[:, 0]])
    b = a + along[:, None] * u + side * h[:, None] * n
    th = np.arctan2(*(b - a).T[::-1])
    c, s = np.cos(th), np.sin(th)
    p = a + np.column_stack([c * LOCAL[0] - s * LOCAL[1], s * LOCAL[0] + c * LOCAL[1]])
    return p, th


@pytest.fixture(scope="module")
def generator():
    """The motion problem's design that is its generator, and the generator's assembly."""
    from linkwork.synthesis.cli import _read

    poses = np.array(_read(str(EXAMPLES / "motion.toml"))["poses"], dtype=float)
    result = S.motion(poses, angles="deg")
    design = next(d for d in result.designs if np.hypot(*d.o2) < 1e-9 and np.hypot(*(d.o4 - O4)) < 1e-9)
    side = next(s for s in (1.0, -1.0) if np.abs(closed_form(PHI, s)[0] - poses[:, :2]).max() < 1e-9)
    return design, side


def test_a_design_from_known_poses_passes_every_target_to_1e_9(generator):
    design, side = generator
    targets = of_design(design)
    assert targets.point == "P" and targets.body == "coupler" and len(targets) == 5
    np.testing.assert_allclose(targets.times, PHI - PHI[0], atol=1e-12)  # the crank's rotation
    res = design.sweep()
    dev = deviation(res, design)
    assert dev.reached is not None and dev.reached.all()
    assert dev.at_position is not None and dev.angle_error is not None and dev.heading is not None
    assert dev.nearest.max() < 1e-9 and dev.at_position.max() < 1e-9
    assert np.abs(dev.angle_error).max() < 1e-9
    # the ticks: the coupler's x axis (A -> B) at each pose, by the closed form
    _, th = closed_form(PHI, side)
    assert np.abs(np.remainder(dev.heading - th + math.pi, 2 * math.pi) - math.pi).max() < 1e-9
    # the convenience method measures the same
    assert np.abs(design.deviation().nearest - dev.nearest).max() < 1e-12


@pytest.mark.parametrize("j", [1, 3])
def test_a_target_moved_by_d_is_reported_d_away(generator, j):
    design, side = generator
    base = of_design(design)
    d = 2e-3
    # along the path's normal there (by the closed form's derivative): the path's nearest
    # point stays the precision point, d away; the point at the precision time is d away
    eps = 1e-6
    p_plus, p_minus = (closed_form(np.array([PHI[j] + s * eps]), side)[0][0] for s in (1, -1))
    tangent = (p_plus - p_minus) / np.hypot(*(p_plus - p_minus))
    normal = np.array([-tangent[1], tangent[0]])
    res = design.sweep()
    for direction in (normal, -normal):
        pts = base.points.copy()
        pts[j] += d * direction
        dev = deviation(res, Targets(pts, base.angles, base.times))
        assert abs(dev.nearest[j] - d) < 1e-10
        assert dev.at_position is not None and abs(dev.at_position[j] - d) < 1e-12
        assert np.abs(np.delete(dev.nearest, j)).max() < 1e-9  # the others unmoved
    # any direction: the point at the precision time is d away; the path is no farther
    pts = base.points.copy()
    pts[j] += d * np.array([math.cos(0.7), math.sin(0.7)])
    dev = deviation(res, Targets(pts, base.angles, base.times))
    assert dev.at_position is not None and abs(dev.at_position[j] - d) < 1e-12
    assert dev.nearest[j] <= d


def test_the_nearest_point_is_the_paths_not_the_chords():
    """On a coarse sweep, a point of the path between two steps is found on the path
    (Newton on the engine's solution), not at the chord's distance."""
    model = lw.examples.four_bar().compile()
    res = model.sweep(np.linspace(0.0, 1.0, 21))
    p = np.array([model.solve(t).point("P").position for t in (0.125, 0.575)])
    # the chords pass well off these points: a polyline's distance would not do
    path = res.point("P").position
    a, b = path[:-1], path[1:]
    chord = []
    for q in p:
        s = np.clip(np.einsum("ij,ij->i", q - a, b - a) / np.einsum("ij,ij->i", b - a, b - a), 0, 1)
        chord.append(np.hypot(*(a + s[:, None] * (b - a) - q).T).min())
    assert min(chord) > 1e-5
    dev = deviation(res, p)
    assert dev.nearest.max() < 1e-12
    np.testing.assert_allclose(dev.nearest_time, [0.125, 0.575], atol=1e-9)
    assert dev.at_position is None and dev.heading is None  # points only: no times, no poses


def test_a_precision_time_outside_the_sweep_is_not_reached():
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 41))
    p = res.point("P").position[[0, 20]]
    dev = deviation(res, Targets(p, times=[0.0, 5.0]))
    assert dev.reached is not None and dev.reached.tolist() == [True, False]
    assert dev.at_position is not None and dev.at_position[1] == math.inf
    assert "not reached" in dev.label(1) and "not reached" in dev.report()
    assert dev.to_json()[1]["at_position"] is None  # JSON has no infinity
    assert dev.nearest[1] < 1e-12  # the path passes it at t = 0.5 all the same


class _Duck:
    """A design as a six-bar's would be: positions, coupler angles, precision times and
    a model, nothing else; its positions lie before position 1 in time."""

    def __init__(self) -> None:
        self._model = lw.examples.four_bar()
        compiled = self._model.compile()
        self.times = np.array([0.0, -0.4, -0.9])
        states = [compiled.solve(t) for t in self.times]
        self.positions = np.array([s.point("P").position for s in states])
        th = np.array([s.body("coupler").theta for s in states])
        self.coupler_angles = th - th[0]

    def precision_times(self) -> np.ndarray:
        return self.times

    def model(self):
        return self._model


def test_any_design_by_duck_typing_swept_the_way_its_times_go():
    duck = _Duck()
    res = sweep_design(duck)
    assert res.times[-1] < res.times[0]  # backwards: the positions lie at negative times
    dev = deviation(res, duck)
    assert dev.at_position is not None and dev.at_position.max() < 1e-12
    assert dev.angle_error is not None and np.abs(dev.angle_error).max() < 1e-12


# -- the pictures ---------------------------------------------------------------------------


def _svg_targets(root: ET.Element) -> dict[str, list[ET.Element]]:
    out: dict[str, list[ET.Element]] = {}
    for e in root.iter():
        cls = e.get("class", "")
        for c in ("target", "target-pose", "target-miss", "target-cross", "target-label", "target-number"):
            if c in cls.split():
                out.setdefault(c, []).append(e)
    return out


def test_svg_marks_each_target_its_pose_and_its_distance(generator, tmp_path):
    design, _ = generator
    res = design.sweep()
    dev = deviation(res, design)
    text = design.to_svg(tmp_path / "d.svg")
    assert (tmp_path / "d.svg").read_text() == text
    found = _svg_targets(ET.fromstring(text))
    rings = found["target"]
    assert [e.get("data-name") for e in rings] == ["P1", "P2", "P3", "P4", "P5"]
    centres = np.array([[float(e.get("cx")), float(e.get("cy"))] for e in rings])
    assert np.array_equal(centres, design.positions)  # written to round-trip exactly
    assert np.array_equal([float(e.get("data-nearest")) for e in rings], dev.nearest)
    assert np.array_equal([float(e.get("data-at-position")) for e in rings], dev.at_position)
    # each pose's tick starts at its target and points the coupler's prescribed way
    assert dev.heading is not None
    for e, p, h in zip(found["target-pose"], design.positions, dev.heading):
        a, b = (np.array([float(v) for v in xy.split(",")]) for xy in e.get("points").split())
        assert np.array_equal(a, p)
        assert abs(math.remainder(math.atan2(*(b - a)[::-1]) - h, 2 * math.pi)) < 1e-9
    # numbered beside each target; the distances listed in a column right of the drawing
    assert [e.text for e in found["target-number"]] == ["1", "2", "3", "4", "5"]
    labels = [e.text for e in found["target-label"]]
    assert labels == [dev.label(j) for j in range(5)] and labels[0].startswith("1: ")
    path = np.array([[float(v) for v in xy.split(",")] for xy in ET.fromstring(text).find(
        f".//{SVG}polyline[@class='path']").get("points").split()])  # fmt: skip
    assert min(float(e.get("x")) for e in found["target-label"]) > path[:, 0].max()
    assert len(found["target-miss"]) == 5
    # points alone: marked, no ticks; the drawing grows to hold a far target
    far = np.array([[30.0, -20.0]])
    root = ET.fromstring(res.to_svg(targets=far))
    found = _svg_targets(root)
    assert len(found["target"]) == 1 and "target-pose" not in found
    x0, y0, w, h = (float(v) for v in root.get("viewBox").split())
    assert x0 < 30.0 < x0 + w and y0 < 20.0 < y0 + h  # y flipped: -(-20)
    # its label gives the path's distance (two digits); far off, the nearest step's distance
    # is the path's to a few parts in a million
    by_steps = np.hypot(*(res.point("P").position - far[0]).T).min()
    assert deviation(res, far).nearest[0] == pytest.approx(by_steps, rel=1e-5)
    assert float(found["target-label"][0].text.split()[1]) == pytest.approx(by_steps, rel=0.01)
    # no targets: no marks
    assert _svg_targets(ET.fromstring(res.to_svg())) == {}


def test_dxf_has_the_targets_on_their_layer(generator, tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    design, _ = generator
    dev = design.deviation()
    design.to_dxf(tmp_path / "d.dxf")
    msp = ezdxf.readfile(tmp_path / "d.dxf").modelspace()

    def name(e) -> str:
        return e.get_xdata("LINKWORK")[0].value

    points = msp.query("POINT[layer=='TARGETS']")
    assert [name(p) for p in points] == ["P1", "P2", "P3", "P4", "P5"]
    assert np.array_equal(np.array([p.dxf.location for p in points])[:, :2], design.positions)
    assert len(msp.query("CIRCLE[layer=='TARGETS']")) == 5
    # each target's number beside it; the heading and each target's distances in a column
    # right of everything else drawn
    texts = [(name(t), t.dxf.text, t.dxf.insert[0]) for t in msp.query("TEXT[layer=='TARGETS']")]
    numbers = [(n, t) for n, t, _ in texts if t.isdigit()]
    assert numbers == [(f"P{j}", str(j)) for j in range(1, 6)]
    listed = [(n, t) for n, t, _ in texts if not t.isdigit()]
    assert listed == [("targets", dev.heading_line())] + [(f"P{j + 1}", dev.label(j)) for j in range(5)]
    column = min(x for _, t, x in texts if not t.isdigit())
    others = [e for e in msp if e.dxf.layer != "TARGETS" and e.dxftype() == "LWPOLYLINE"]
    assert column > max(np.array(e.get_points("xy"))[:, 0].max() for e in others)
    # per target: the cross (2 lines), the pose's tick and the line to the path
    lines = msp.query("LINE[layer=='TARGETS']")
    assert sorted(name(e) for e in lines) == sorted([f"P{j}" for j in range(1, 6)] * 4)


def _embedded(html: str) -> dict:
    found = re.search(r'<script id="lw-data" type="application/json">(.*?)</script>', html, re.S)
    assert found is not None
    return json.loads(found.group(1).replace("<\\/", "</"))


def test_the_page_marks_and_lists_the_targets(generator, tmp_path):
    design, _ = generator
    dev = design.deviation()
    html = design.to_html(tmp_path / "d.html", frames=50)
    data = _embedded(html)["targets"]
    assert [t["name"] for t in data] == ["P1", "P2", "P3", "P4", "P5"]
    assert np.array_equal([[t["x"], t["y"]] for t in data], design.positions)
    assert np.array_equal([t["nearest"] for t in data], dev.nearest)
    assert all(t["reached"] for t in data) and max(t["at_position"] for t in data) < 1e-9
    assert np.array_equal([t["angle"] for t in data], design.coupler_angles)
    assert 'id="target-table"' in html and html.count('class="target"') == 5
    table = html.split('id="target-table"', 1)[1].split("</table>", 1)[0]
    assert table.count("<tr>") == 6  # the head and one row a target
    # the page without targets is as it was
    plain = design.sweep().to_html(frames=50)
    assert _embedded(plain)["targets"] == [] and "target-table" not in plain and 'class="target"' not in plain


def test_the_png_is_written_with_the_targets(generator, tmp_path):
    design, _ = generator
    assert design.plot(str(tmp_path / "d.png")) == ["P"]
    assert (tmp_path / "d.png").stat().st_size > 20_000


def test_linkwork_synth_writes_each_designs_pictures_with_its_targets(tmp_path, capsys):
    from linkwork.cli import main

    assert main(["synth", str(EXAMPLES / "motion.toml"), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "design 1, targets of P" in out
    report = (tmp_path / "motion_report.txt").read_text()
    assert "targets of P" in report and "  P5 (" in report
    designs = sorted(tmp_path.glob("motion_design*.toml"))
    for k in range(1, len(designs) + 1):
        for ext in ("html", "svg", "png"):
            assert (tmp_path / f"motion_design{k}.{ext}").stat().st_size > 5_000
        found = _svg_targets(ET.parse(tmp_path / f"motion_design{k}.svg").getroot())
        assert len(found["target"]) == 5 and len(found["target-pose"]) == 5
        assert len(_embedded((tmp_path / f"motion_design{k}.html").read_text())["targets"]) == 5


# -- bad input ------------------------------------------------------------------------------


def test_bad_targets_are_named_input_errors():
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 11))
    cases = [
        (lambda: Targets(np.zeros((3, 3))), "points must be n x 2"),
        (lambda: Targets([[0.0, math.nan]]), r"points must be finite; entry \(0, 1\)"),
        (lambda: Targets([[0.0, 0.0], [1.0, math.inf]]), "finite"),
        (lambda: Targets(np.zeros((0, 2))), "empty"),
        (lambda: Targets([[0.0, 0.0], [1.0, 1.0]], angles=[0.0]), "angles has 1 entries for 2 points"),
        (lambda: Targets([[0.0, 0.0]], times=[[0.0]]), "times must be n"),
        (lambda: Targets([[0.0, 0.0]], angles=[math.nan]), "angles must be finite"),
        (lambda: Targets([[0.0, 0.0]], point=3), "point must be a name"),  # type: ignore[arg-type]
        (lambda: Targets("abc"), "points must be numbers"),
        (lambda: of_design(object()), "no .positions"),
        (lambda: res.to_svg(targets=[[1.0, 2.0, 3.0]]), "points must be n x 2"),
        (lambda: res.to_html(targets=[[math.inf, 0.0]]), "finite"),
        (lambda: res.to_dxf("x.dxf", targets=[1.0, 2.0]), "points must be n x 2"),
        (lambda: deviation(res, Targets([[0.0, 0.0]], point="Q")), "no point named 'Q'"),
        (lambda: deviation(res, Targets([[0.0, 0.0]], angles=[0.0], body="arm")), "no body named 'arm'"),
        (lambda: deviation(res, None), "must be given"),
        (lambda: deviation(res.model.sweep([0.0, 0.5], outputs=["P"]), [[0.0, 0.0]]), "every coordinate"),
    ]
    for call, message in cases:
        with pytest.raises(lw.InputError, match=message) as e:
            call()
        assert isinstance(e.value, lw.LinkworkError)


def test_linkwork_synth_draws_what_it_can_and_says_why_not(tmp_path):
    """A function generator has no precision points to mark; a design whose sweep fails
    still appears in the overview figure, and the report says why it has no pictures."""
    from linkwork.cli import main

    problem = tmp_path / "fn.toml"
    problem.write_text(
        'problem = "function"\nangles = "deg"\ninput_angles = [15, 45, 75]\noutput = [30, 50, 80]\n'
    )
    assert main(["synth", str(problem), "--out", str(tmp_path)]) == 0
    report = (tmp_path / "fn_report.txt").read_text()
    assert (tmp_path / "fn.png").stat().st_size > 10_000
    assert "targets of" not in report
    assert (tmp_path / "fn_design1.svg").exists() or "design 1: no pictures, its sweep failed" in report
