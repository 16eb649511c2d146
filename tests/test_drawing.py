"""Drawing geometry: local attachment points from the description, their world positions
over a sweep (checked against the joints' own equations), sliders, actuators, unknown
joint types; the artists; the outputs and paths the figures pick."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from linkwork.view import drawing, figures
from linkwork.view.drawing import Geometry, MechanismArtists, Motion

REV = np.linspace(0.0, 2 * math.pi / 5.0, 241)  # one crank revolution of the examples


def sweep(mech: lw.Mechanism, times: np.ndarray = REV) -> tuple[Geometry, lw.Results]:
    model = mech.compile()
    return Geometry.from_model(model), model.sweep(times)


def anchor(g: Geometry, name: str, body: str) -> int:
    (k,) = [k for k, a in enumerate(g.anchors) if a.name == name and a.body == body and a.kind == "joint"]
    return k


def cylinder_lever() -> lw.Mechanism:
    """A lever pinned to the ground at O, swung by a linear actuator (distance driver)
    from the ground point G = (0.3, -0.2) to the lever point (0.4, 0)."""
    m = lw.Mechanism("lever")
    lever = m.link("lever", (0.0, 0.0), (0.5, 0.0))
    m.revolute(m.ground, lever, (0.0, 0.0), name="O")
    m.drive_distance(
        m.ground, (0.3, -0.2), lever, (0.4, 0.0), lw.Linear(math.hypot(0.1, 0.2), 0.05), name="cyl"
    )
    m.point("tip", lever, (0.5, 0.0))
    return m


@pytest.mark.parametrize("name", sorted(lw.examples.ALL))
def test_pins_hold_together_over_a_revolution(name):
    """Both sides of every revolute, each carried by its own body, stay at one point: the
    local vectors and the vectorised transform are right. Tolerance: the solver's scaled
    residual tolerance, 1e-12 of the length scale."""
    g, res = sweep(lw.examples.ALL[name]())
    xy = g.world(res.q)
    assert xy.shape == (len(REV), len(g.anchors), 2)
    revolutes = [j for j in res.model.description["joints"] if j["type"] == "revolute"]
    assert len(g.pins) == len(revolutes)
    for j in revolutes:
        a, b = anchor(g, j["name"], j["body_a"]), anchor(g, j["name"], j["body_b"])
        gap = np.hypot(*(xy[:, a] - xy[:, b]).T).max()
        assert gap <= 1e-12 * res.model.length_scale, (j["name"], gap)
    for k in g.ground_pins:  # the ground's side stands still, at the joint's world point
        assert g.anchors[k].body == "ground" and np.all(xy[:, k] == xy[0, k])


@pytest.mark.parametrize("name", ["four_bar", "six_bar_watt", "six_bar_stephenson"])
def test_named_points_are_where_results_put_them(name):
    g, res = sweep(lw.examples.ALL[name]())
    xy = g.world(res.q)
    for k in g.points:
        want = res.point(g.anchors[k].name).position
        # the same sum in another order: a few units of rounding of the coordinates
        assert np.abs(xy[:, k] - want).max() <= 4 * np.finfo(float).eps * res.model.length_scale


@pytest.mark.parametrize("name", ["slider_crank", "inverted_slider_crank"])
def test_slider_blocks_stay_on_their_guides(name):
    """The block's point minus the guide's point lies along the guide's direction (the
    prismatic joint's rows), to the solver's tolerance."""
    g, res = sweep(lw.examples.ALL[name]())
    (slider,) = g.sliders
    xy = g.world(res.q)
    axis = g.axis_world(res.q, slider)
    assert np.allclose(np.hypot(axis[:, 0], axis[:, 1]), 1.0, rtol=0, atol=1e-15)
    d = xy[:, slider.block] - xy[:, slider.guide]
    across = d[:, 0] * axis[:, 1] - d[:, 1] * axis[:, 0]
    assert np.abs(across).max() <= 1e-12 * res.model.length_scale
    # the guide drawn covers the whole travel
    motion = Motion(g, res)
    (guide,) = motion.guides
    along = np.einsum("ij,ij->i", xy[:, slider.block] - guide[:, 0], axis)
    assert along.min() > 0 and np.all(along < np.hypot(*(guide[:, 1] - guide[:, 0]).T))


def test_actuator_length_is_the_distance_drivers_law():
    g, res = sweep(cylinder_lever(), np.linspace(0.0, 1.0, 101))
    ((a, b),) = g.actuators
    xy = g.world(res.q)
    length = np.hypot(*(xy[:, b] - xy[:, a]).T)
    want = math.hypot(0.1, 0.2) + 0.05 * res.times
    assert np.abs(length - want).max() <= 1e-12 * res.model.length_scale
    assert figures.default_paths(res.model) == ["tip"]


def test_unknown_joint_types_are_skipped_and_bare_bodies_drawn_at_their_origin():
    model = lw.examples.four_bar().compile()
    desc = dict(model.description)
    desc["joints"] = desc["joints"] + [{"type": "gear", "name": "G1", "body_a": "crank", "body_b": "rocker"}]
    g = Geometry(model.body_names + ["flywheel"], np.append(model.q_start, [1.0, 2.0, 0.5]), desc)
    assert not [a for a in g.anchors if a.name == "G1"]
    assert [a for a in g.anchors if a.body == "flywheel"] == [
        drawing.Anchor("flywheel", "origin", "origin", "flywheel", (0.0, 0.0))
    ]


def test_local_vectors_come_from_the_engines_starting_poses():
    """The description's angles may be in a file's units; the drawing reads the
    starting poses from the compiled model (radians), so they do not matter."""
    model = lw.examples.four_bar().compile()
    desc = dict(model.description)
    desc["bodies"] = [dict(b, theta=math.degrees(b["theta"])) for b in desc["bodies"]]
    assert Geometry(model.body_names, model.q_start, desc).anchors == Geometry.from_model(model).anchors


def test_frames_spread_over_the_sweep():
    g, res = sweep(lw.examples.four_bar(), np.linspace(0.0, 1.0, 1001))
    motion = Motion(g, res)
    rows = motion.frames(120)
    assert len(rows) == 120 and rows[0] == 0 and rows[-1] == 1000 and np.all(np.diff(rows) > 0)
    assert list(motion.frames(5000)) == list(range(1001))
    (x0, x1), (y0, y1) = motion.limits
    assert x0 < motion.xy[..., 0].min() and motion.xy[..., 0].max() < x1
    assert y0 < motion.xy[..., 1].min() and motion.xy[..., 1].max() < y1


def test_artists_follow_the_motion_with_fixed_limits():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    g, res = sweep(lw.examples.six_bar_stephenson(), REV[:61])
    motion = Motion(g, res)
    fig, ax = plt.subplots()
    artists = MechanismArtists(ax, motion, clock=True)
    drawing.setup_axes(ax, motion, "m")
    limits = (ax.get_xlim(), ax.get_ylim())
    for row in (0, 30, 60):
        artists.update(row)
        fig.canvas.draw()
        assert np.array_equal(np.column_stack(artists.pins.get_data()), motion.xy[row, g.pins])
        for outline, patch, _ in artists.bodies:
            assert np.array_equal(patch.get_xy()[: len(outline)], motion.xy[row, outline])
        assert (ax.get_xlim(), ax.get_ylim()) == limits
        assert artists.clock is not None and artists.clock.get_text() == f"t = {res.times[row]:.6g} s"
    plt.close(fig)
    # the ternary coupler A-B-C is drawn as a triangle
    assert sorted(g.anchors[k].name for k in g.outlines["coupler"]) == ["A", "B", "C"]


def test_cam_profiles_and_slots_are_drawn_with_their_body():
    """The eccentric cam of the gallery: its circle (radius 50 mm about a centre 20 mm off
    the pivot) is drawn in the cam's frame. At every step the drawn points keep the radius
    about their centre, that centre turns with the cam, and the knife-edge tip the engine
    solved lies on the drawn circle. Tolerances: round-off of a few transforms (1e-15 m),
    and the engine's residual (1e-12 scaled) for the tip."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mech = lw.Mechanism.load(Path(__file__).parent.parent / "examples" / "eccentric_cam.toml")
    g, res = sweep(mech, np.linspace(0.0, 1.0, 73))
    assert [c.joint for c in g.curves] == ["knife_tip", "flat_face"]
    motion = Motion(g, res)
    fig, ax = plt.subplots()
    artists = MechanismArtists(ax, motion)
    theta = res.body("cam").theta
    tip = motion.xy[:, anchor(g, "knife_tip", "knife")]
    for row in range(0, 73, 8):
        artists.update(row)
        drawn = np.column_stack(artists.curves[0].get_data())
        assert np.array_equal(drawn, motion.curve(g.curves[0], row))
        centre = drawn[:-1].mean(axis=0)  # equally spaced over one period, the last repeats the first
        turned = 0.02 * np.array([math.cos(theta[row]), math.sin(theta[row])])
        assert np.abs(centre - turned).max() < 1e-15
        assert np.abs(np.hypot(*(drawn - centre).T) - 0.05).max() < 1e-15
        assert abs(math.hypot(*(tip[row] - centre)) - 0.05) < 1e-12
    plt.close(fig)
    # the limits hold the curve wherever it turns
    (x0, x1), (y0, y1) = motion.limits
    everywhere = motion.curve(g.curves[0], np.arange(73))
    assert x0 < everywhere[..., 0].min() and everywhere[..., 0].max() < x1
    assert y0 < everywhere[..., 1].min() and everywhere[..., 1].max() < y1


def test_a_roller_is_drawn_about_its_centre_on_the_follower():
    mech = lw.Mechanism.load(Path(__file__).parent.parent / "examples" / "cam_rise_dwell_fall.toml")
    d = mech.to_dict()
    (joint,) = [j for j in d["joints"] if j["type"] == "cam_follower"]
    g, res = sweep(mech, np.linspace(0.0, 1.0, 37))
    motion = Motion(g, res)
    profile, roller = [c for c in g.curves if c.joint == joint["name"]]
    assert profile.body == g.body_names.index(joint["body_a"])
    assert roller.body == g.body_names.index(joint["body_b"])
    centre = motion.xy[:, anchor(g, joint["name"], joint["body_b"])]
    circle = motion.curve(roller, np.arange(37))
    distance = np.hypot(*(circle - centre[:, None, :]).transpose(2, 0, 1))
    assert np.abs(distance - joint["radius"]).max() < 1e-15


def test_outputs_by_column_body_and_point():
    _, res = sweep(lw.examples.four_bar(), REV[:50])
    rocker = figures.output(res, "rocker")
    k = res.columns.index("rocker.theta")
    assert rocker.name == "rocker.theta" and rocker.unit == "rad"
    assert np.array_equal(rocker.value, res.q[:, k]) and np.array_equal(rocker.acceleration, res.qdd[:, k])
    py = figures.output(res, "P.y")
    p = res.point("P")
    assert (
        py.unit == "m"
        and np.array_equal(py.value, p.position[:, 1])
        and np.array_equal(py.rate, p.velocity[:, 1])
    )
    with pytest.raises(KeyError, match="'wheel'"):
        figures.output(res, "wheel")


def test_default_outputs_and_paths():
    _, res = sweep(lw.examples.slider_crank(), REV[:50])
    assert figures.default_outputs(res) == ["crank", "rod", "slider.x"]  # the slider only slides along x
    assert figures.default_paths(res.model) == ["A", "B"]  # no named points: the moving pins
    assert figures.default_paths(lw.examples.six_bar_watt().compile()) == ["C"]


EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
T = np.linspace(0.0, 1.0, 41)


def example(name: str, times: np.ndarray = T) -> tuple[Geometry, lw.Results]:
    return sweep(lw.Mechanism.load(EXAMPLES / f"{name}.toml"), times)


def test_gears_pitch_circles_turn_about_their_centres_and_touch_at_the_mesh_point():
    """Each gear's pitch circle, at every drawn step, lies at the joint's radius from its
    centre (the body's origin: the sweep's x, y); the mark on it turns with the body; the
    mesh point is on both pitch circles (the carrier's pins hold the centres at r_a +- r_b:
    the solver's tolerance)."""
    g, res = example("gear_train_planetary")
    motion = Motion(g, res)
    scale = res.model.length_scale
    radius = {}
    for j in res.model.description["joints"]:
        if j["type"] == "gear":
            radius[(j["name"], j["body_a"])], radius[(j["name"], j["body_b"])] = j["radius_a"], j["radius_b"]
    pitch = [c for c in motion.curves if c.kind == "pitch"]
    assert len(pitch) == 4 and len([c for c in motion.curves if c.kind == "mark"]) == 4
    rows = np.arange(res.n_steps)
    for c in pitch:
        body = res.model.body_names[c.body]
        pts = motion.curve(c, rows)  # (n_steps, m, 2)
        centre = np.stack([res.body(body).x, res.body(body).y], axis=-1)[:, None, :]
        r = np.hypot(*np.moveaxis(pts - centre, -1, 0))
        assert np.abs(r - radius[(c.joint, body)]).max() <= 1e-12 * scale
    for c in [c for c in motion.curves if c.kind == "mark"]:
        body = res.model.body_names[c.body]
        tip = motion.curve(c, rows)[:, 1] - motion.curve(c, rows)[:, 0]
        turned = np.unwrap(np.arctan2(tip[:, 1], tip[:, 0]))
        assert np.abs((turned - turned[0]) - (res.body(body).theta - res.body(body).theta[0])).max() < 1e-12
    meshes = {m.joint: m for m in motion.marks if m.kind == "mesh"}
    assert sorted(meshes) == ["ring_planet", "sun_planet"]
    for name, m in meshes.items():
        (j,) = [j for j in res.model.description["joints"] if j["name"] == name]
        for body, r in ((j["body_a"], j["radius_a"]), (j["body_b"], j["radius_b"])):
            centre = np.stack([res.body(body).x, res.body(body).y], axis=-1)
            assert np.abs(np.hypot(*(m.xy[:, 0] - centre).T) - r).max() <= 1e-12 * scale, (name, body)


def test_a_belts_strands_are_tangent_to_both_pulleys():
    """The chain's two strands: each end is on its pulley's pitch circle and the strand
    is tangent there (the radius to it is square to the strand), to rounding."""
    g, res = example("chained_six_bar")
    motion = Motion(g, res)
    (belt,) = g.belts
    strands = [m for m in motion.marks if m.kind == "strand"]
    assert len(strands) == 2
    scale = res.model.length_scale
    for m in strands:
        along = m.xy[:, 1] - m.xy[:, 0]
        along /= np.hypot(*along.T)[:, None]
        for end, anchor_, r in ((0, belt.a, belt.r_a), (1, belt.b, belt.r_b)):
            centre = motion.xy[:, anchor_]
            to = m.xy[:, end] - centre
            assert np.abs(np.hypot(*to.T) - r).max() <= 1e-12 * scale
            assert np.abs(np.einsum("ij,ij->i", to, along)).max() <= 1e-12 * scale
            # the distance of the centre from the strand's line is the radius
            across = np.abs(to[:, 0] * along[:, 1] - to[:, 1] * along[:, 0])
            assert np.abs(across - r).max() <= 1e-12 * scale
    # open belt, equal pulleys: the strands are the pulleys' outer tangents, 2 r apart
    assert belt.r_a == belt.r_b and not belt.crossed
    gap = np.hypot(*(strands[0].xy[:, 0] - strands[1].xy[:, 0]).T)
    assert np.abs(gap - 2 * belt.r_a).max() <= 1e-12 * scale


def test_crossed_belts_strands_cross_between_the_pulleys():
    m = lw.Mechanism("crossed")
    a, b = m.body("a", (0.0, 0.0)), m.body("b", (0.4, 0.0))
    m.revolute(m.ground, a, (0.0, 0.0))
    m.revolute(m.ground, b, (0.4, 0.0))
    m.belt(a, b, radii=(0.1, 0.05), crossed=True)
    m.drive_angle(a, lw.Linear(0.0, 1.0))
    g, res = sweep(m, np.linspace(0.0, 1.0, 5))
    motion = Motion(g, res)
    s1, s2 = [k.xy[0] for k in motion.marks]
    # both strands cross the line of centres at the same point, r_a / (r_a + r_b) along it
    for s in (s1, s2):
        t = -s[0, 1] / (s[1, 1] - s[0, 1])
        assert math.isclose(s[0, 0] + t * (s[1, 0] - s[0, 0]), 0.4 * 0.1 / 0.15, abs_tol=1e-15)
        assert math.isclose(math.hypot(*s[0]), 0.1, abs_tol=1e-15)


def test_distance_joints_are_bars_between_their_points():
    """The steering's tie rods: the bar's ends are the rack's and the arm's points, as
    results.point_at gives them; and the length stays the joint's."""
    g, res = example("steering", np.linspace(0.0, 2.0, 41))
    assert len(g.rods) == 2
    xy = g.world(res.q)
    scale = res.model.length_scale
    for a, b in g.rods:
        for k in (a, b):
            want = res.point_at(g.anchors[k].body, g.anchors[k].local).position
            assert np.abs(xy[:, k] - want).max() <= 4 * np.finfo(float).eps * scale
        length = np.hypot(*(xy[:, b] - xy[:, a]).T)
        assert np.abs(length - length[0]).max() <= 1e-12 * scale


def test_a_rack_touches_the_pinions_pitch_circle_on_its_pitch_line():
    g, res = example("steering", np.linspace(0.0, 2.0, 41))
    motion = Motion(g, res)
    (rack,) = g.racks
    (mesh,) = [m for m in motion.marks if m.kind == "mesh"]
    (line,) = [c for c in motion.curves if c.kind == "pitch" and c.joint == rack.joint and len(c.local) == 2]
    (teeth,) = [c for c in motion.curves if c.kind == "teeth"]
    scale = res.model.length_scale
    centre = np.stack([res.body("pinion").x, res.body("pinion").y], axis=-1)
    assert np.abs(np.hypot(*(mesh.xy[:, 0] - centre).T) - rack.radius).max() <= 1e-12 * scale
    ends = motion.curve(line, np.arange(res.n_steps))
    d = ends[:, 1] - ends[:, 0]
    rel = mesh.xy[:, 0] - ends[:, 0]
    assert np.abs(rel[:, 0] * d[:, 1] - rel[:, 1] * d[:, 0]).max() / np.hypot(*d[0]) <= 1e-12 * scale
    # within the line's ends at every step, and the teeth along the same stretch
    t = np.einsum("ij,ij->i", rel, d) / np.einsum("ij,ij->i", d, d)
    assert t.min() > 0.0 and t.max() < 1.0
    assert len(teeth.local) > 10


def test_a_pin_in_a_straight_slot_is_drawn_as_a_block_on_the_slot():
    g, res = example("whitworth")
    (slot,) = [s for s in g.sliders if s.joint == "slot"]
    assert g.anchors[slot.guide].body == "lever" and g.anchors[slot.block].body == "crank"
    xy = g.world(res.q)
    axis = g.axis_world(res.q, slot)
    d = xy[:, slot.block] - xy[:, slot.guide]
    assert np.abs(d[:, 0] * axis[:, 1] - d[:, 1] * axis[:, 0]).max() <= 1e-12 * res.model.length_scale


def test_the_svg_the_dxf_and_the_page_carry_the_new_elements():
    import json
    import re

    g, res = example("gear_train_planetary")
    text = res.to_svg()
    motion = Motion(g, res)
    assert text.count('class="curve pitch"') == 4 and text.count('class="curve mark"') == 4
    for m in [m for m in motion.marks if m.kind == "mesh"]:
        x, y = (float(v) for v in m.xy[0, 0])
        assert f'class="mesh" data-name="{m.joint}"' in text and f'cx="{x!r}" cy="{y!r}"' in text
    html = res.to_html()
    data = json.loads(
        re.search(r'<script id="lw-data" type="application/json">(.*?)</script>', html, re.S).group(1)
    )
    assert len(data["marks"]) == len(motion.marks) == 2
    rows = motion.frames(1000)
    for mark, embedded in zip(motion.marks, data["marks"]):
        assert np.array_equal(np.asarray(embedded), mark.xy[rows].reshape(len(rows), -1))
    assert len(data["curves"]) == len(motion.curves)
    g, res = example("steering", np.linspace(0.0, 2.0, 41))
    text = res.to_svg()
    xy = g.world(res.q)[0]
    for a, b in g.rods:
        pts = " ".join(f"{float(x)!r},{float(y)!r}" for x, y in xy[[a, b]])
        assert f'data-anchors="{a} {b}" points="{pts}"' in text
    assert 'class="curve teeth"' in text


def test_the_dxf_has_the_new_layers(tmp_path):
    pytest.importorskip("ezdxf")
    import ezdxf

    _, res = example("chained_six_bar")
    res.to_dxf(tmp_path / "chain.dxf")
    doc = ezdxf.readfile(tmp_path / "chain.dxf")
    layers = {e.dxf.layer for e in doc.modelspace()}
    assert {"PITCH", "BELTS"} <= layers
    assert doc.layers.get("PITCH").dxf.linetype == "DASHDOT"


def test_labels_name_the_bodies_and_joints_where_they_are(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    g, res = example("steering", np.linspace(0.0, 2.0, 21))
    motion = Motion(g, res)
    fig, ax = plt.subplots()
    artists = MechanismArtists(ax, motion, labels=True)
    artists.update(7)
    texts = {t.get_text(): t for _, t in artists.labels}
    assert set(res.model.body_names) <= set(texts) and {"tie_rod_left", "rack_guide", "column"} <= set(texts)
    rack = g.outlines["rack"]
    assert np.allclose(texts["rack"].get_position(), motion.xy[7, rack].mean(axis=0), rtol=0, atol=1e-15)
    assert texts["tie_rod_left"].xy == tuple(motion.xy[7, g.traceable["tie_rod_left"]])
    plt.close(fig)
    assert figures.plot_paths(res, str(tmp_path / "p.png"), labels=True)
    with pytest.raises(lw.InputError, match="labels must be True or False"):
        figures.plot_paths(res, str(tmp_path / "p.png"), labels="yes")
