"""Drawing geometry: local attachment points from the description, their world positions
over a sweep (checked against the joints' own equations), sliders, actuators, unknown
joint types; the artists; the outputs and paths the figures pick."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from linkwork import figures
from linkwork.drawing import Geometry, MechanismArtists, Motion

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
        lw.drawing.Anchor("flywheel", "origin", "origin", "flywheel", (0.0, 0.0))
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
    lw.drawing.setup_axes(ax, motion, "m")
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
