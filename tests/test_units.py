"""Model files and units with the whole joint library: every joint type round-trips
through TOML and JSON, and a mechanism written in degrees solves exactly like the same
mechanism in radians, in the engine and in the reference."""

import copy
import math

import numpy as np
import pytest

import linkwork as lw
import test_cams
import test_joints
from linkwork.reference import ReferenceModel

K = math.pi / 180.0


def geared_trio() -> lw.Mechanism:
    """Three cranks on the ground: the first driven, the second tied to it by a linear
    coupling of angles, the third held at a fixed angle to the second."""
    m = lw.Mechanism("geared trio")
    a = m.link("a", (0.0, 0.0), (0.1, 0.0))
    b = m.link("b", (0.3, 0.0), (0.3, 0.1))
    c = m.link("c", (0.6, 0.0), (0.7, 0.05))
    for body, x in ((a, 0.0), (b, 0.3), (c, 0.6)):
        m.revolute(m.ground, body, at=(x, 0.0))
    m.linear_coupling(a, b, coefficients_a={"theta": 0.5}, coefficients_b={"theta": 1.0})
    m.fixed_orientation(b, c, angle=0.3)
    m.drive_angle(a, lw.Harmonic(0.2, 0.8, 3.0))
    return m


MECHANISMS = {
    "geared_trio": geared_trio,
    "gear_train": test_joints.gear_train,
    "planetary": lambda: test_joints.planetary(2.0, None),
    "chained_six_bar": test_joints.chained_six_bar,
    "rack_and_pinion": test_joints.rack_and_pinion,
    "scotch_yoke": test_joints.scotch_yoke,
    "four_bar_with_distance": test_joints.four_bar_with_distance,
    "oscillating_roller": test_cams.oscillating_roller,
    "spline_slot": test_cams.spline_slot,
    "eccentric_flat": lambda: test_cams.eccentric_cam("flat"),
}


def in_degrees(desc: dict) -> dict:
    """The same mechanism written in degrees (every angle field of the format)."""
    d = copy.deepcopy(desc)
    d["units"] = {"length": "m", "angle": "deg"}
    for b in d["bodies"]:
        b["theta"] = b["theta"] / K
    for dr in d["drivers"]:
        if dr["type"] in ("angle", "relative_angle"):
            law = dr["law"]
            assert law["type"] in ("linear", "harmonic", "constant"), law
            for key in ("value", "rate", "mean", "amplitude"):
                if key in law:
                    law[key] = law[key] / K
    for j in d["joints"]:
        if j["type"] == "fixed_orientation" and "angle" in j:
            j["angle"] = j["angle"] / K
        if j["type"] == "linear_coupling":
            for side in ("coefficients_a", "coefficients_b"):
                if "theta" in j.get(side, {}):
                    j[side]["theta"] = j[side]["theta"] * K
        if j["type"] in ("pin_in_slot", "cam_follower") and j["curve"]["type"] == "polar":
            j["curve"]["angles"] = [a / K for a in j["curve"]["angles"]]
    return d


@pytest.mark.parametrize("key", sorted(test_joints.ITEMS))
@pytest.mark.parametrize("ext", ["toml", "json"])
def test_every_joint_type_round_trips(tmp_path, key, ext):
    m = test_joints.one_item(key)
    path = tmp_path / f"{key}.{ext}"
    m.save(str(path))
    back = lw.Mechanism.load(str(path))
    assert back.to_dict() == m.to_dict()
    path2 = tmp_path / f"again.{ext}"
    back.save(str(path2))
    assert path2.read_text() == path.read_text()


@pytest.mark.parametrize("key", sorted(MECHANISMS))
@pytest.mark.parametrize("ext", ["toml", "json"])
def test_mechanisms_round_trip(tmp_path, key, ext):
    m = MECHANISMS[key]()
    path = tmp_path / f"{key}.{ext}"
    m.save(str(path))
    assert lw.Mechanism.load(str(path)).to_dict() == m.to_dict()


@pytest.mark.parametrize("key", sorted(MECHANISMS))
def test_degrees_solve_like_radians(tmp_path, key):
    rad = MECHANISMS[key]()
    deg = lw.Mechanism.from_dict(in_degrees(rad.to_dict()))
    path = tmp_path / "deg.toml"
    deg.save(str(path))
    deg = lw.Mechanism.load(str(path))
    times = np.linspace(0.0, 1.0, 201)
    a = rad.compile().sweep(times)
    b = deg.compile().sweep(times)
    # the same numbers up to the rounding of the conversion (a few ulp of each angle)
    for x, y in ((a.q, b.q), (a.qd, b.qd), (a.qdd, b.qdd)):
        assert np.allclose(x, y, rtol=0, atol=1e-11 * max(1.0, np.abs(x).max()))
    # the reference converts independently and agrees
    ref = ReferenceModel(deg)
    k = len(times) // 2
    q, qd, qdd = ref.solve(times[k], q_guess=b.q[k])
    assert np.allclose(q, b.q[k], rtol=0, atol=1e-11)
    assert np.allclose(qd, b.qd[k], rtol=0, atol=1e-10 * max(1.0, np.abs(b.qd[k]).max()))
    assert np.allclose(qdd, b.qdd[k], rtol=0, atol=1e-9 * max(1.0, np.abs(b.qdd[k]).max()))
