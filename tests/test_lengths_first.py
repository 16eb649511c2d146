"""Lengths first: a mechanism given by its joints' pins in the bodies' own frames (and a
branch, or rough poses), drawn by the engine; the same sweep as the drawn one."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

import linkwork as lw
from linkwork import examples

T = np.linspace(0.0, 2.0 * math.pi / 5.0, 721)


def four_bar_by_lengths(
    ground: float, crank: float, coupler: float, rocker: float, branch: str
) -> lw.Mechanism:
    """The four-bar of `examples.four_bar`, given by its lengths: no point of a drawing."""
    m = lw.Mechanism("four-bar")
    c, k, r = m.body("crank"), m.body("coupler"), m.body("rocker")
    m.revolute(m.ground, c, name="O2", pin_a=(0, 0), pin_b=(0, 0))
    m.revolute(c, k, name="A", pin_a=(crank, 0), pin_b=(0, 0))
    m.revolute(k, r, name="B", pin_a=(coupler, 0), pin_b=(rocker, 0))
    m.revolute(m.ground, r, name="O4", pin_a=(ground, 0), pin_b=(0, 0))
    m.drive_angle(c, lw.Linear(0.0, 5.0), name="crank_angle")
    m.branch = branch
    return m


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_a_four_bar_from_its_lengths_sweeps_as_the_drawn_one(branch: str) -> None:
    dims = (0.35, 0.20, 0.35, 0.25)
    by_lengths = four_bar_by_lengths(*dims, branch)
    assert not by_lengths.is_drawn()
    drawn = examples.four_bar(*dims, branch=branch)
    a, b = by_lengths.compile().sweep(T), drawn.compile().sweep(T)
    # the same mechanism, drawn by the engine: the same configuration to round-off
    for x, y in ((a.q, b.q), (a.qd, b.qd), (a.qdd, b.qdd)):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    # the assembled drawing has the pins' lengths exactly
    d = by_lengths.assemble().to_dict()
    at = {j["name"]: np.array(j["at"]) for j in d["joints"]}
    assert abs(np.hypot(*(at["B"] - at["A"])) - 0.35) < 1e-15
    assert abs(np.hypot(*(at["B"] - at["O4"])) - 0.25) < 1e-15
    assert by_lengths.assemble().is_drawn() and "branch" not in d


def test_a_model_file_without_coordinates(tmp_path) -> None:
    text = """
[model]
name = "four-bar"
units = { length = "mm", angle = "deg" }
branch = "open"

[[bodies]]
name = "crank"
[[bodies]]
name = "coupler"
[[bodies]]
name = "rocker"

[[joints]]
type = "revolute"
name = "O2"
body_a = "ground"
body_b = "crank"
pin_a = [0, 0]
pin_b = [0, 0]

[[joints]]
type = "revolute"
name = "A"
body_a = "crank"
body_b = "coupler"
pin_a = [200, 0]
pin_b = [0, 0]

[[joints]]
type = "revolute"
name = "B"
body_a = "coupler"
body_b = "rocker"
pin_a = [350, 0]
pin_b = [250, 0]

[[joints]]
type = "revolute"
name = "O4"
body_a = "ground"
body_b = "rocker"
pin_a = [350, 0]
pin_b = [0, 0]

[[drivers]]
type = "angle"
name = "crank_angle"
body = "crank"
law = { type = "linear", value = 0, rate = 286.4788975654116 }
"""
    path = tmp_path / "four_bar.toml"
    path.write_text(text)
    mech = lw.Mechanism.load(path)
    assert mech.branch == "open" and not mech.is_drawn()
    a = mech.compile().sweep(T)
    b = examples.four_bar(0.35, 0.20, 0.35, 0.25).compile().sweep(T)
    # mm against m, degrees of the file converted: angles and rates equal
    for x, y in ((a.q[:, 2::3], b.q[:, 2::3]), (a.qd[:, 2::3], b.qd[:, 2::3])):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    np.testing.assert_allclose(a.q[:, 3], 1000.0 * b.q[:, 3], rtol=0, atol=1e-9)
    # saved again it is drawn (in degrees, as the file)
    mech.assemble().save(tmp_path / "drawn.toml")
    again = lw.Mechanism.load(tmp_path / "drawn.toml")
    assert again.is_drawn()
    np.testing.assert_allclose(again.compile().sweep(T).q, a.q, rtol=0, atol=1e-9)


def test_what_cannot_be_drawn_is_named() -> None:
    m = lw.Mechanism()
    with pytest.raises(lw.InputError, match="give its world point `at`, or its pin in each body"):
        m.revolute(m.ground, m.body("a"), pin_a=(0, 0))
    # a loop that cannot close: the rocker is too short to reach
    by_lengths = four_bar_by_lengths(1.0, 0.1, 0.2, 0.2, "open")
    with pytest.raises(lw.LinkworkError):
        by_lengths.compile()
    # a description without `at` or pins is refused by the engine, naming the joint
    desc = examples.four_bar().to_dict()
    del desc["joints"][2]["at"]
    with pytest.raises(lw.ModelError, match="joint 'B'.*needs its position `at`, or its pin in each body"):
        lw.Model(desc)


def test_a_four_bar_in_three_lines() -> None:
    """The issue's three lines: the lengths, a branch, the sweep; the drawn example's sweep
    (bodies placed by the closed form) to 1e-12 of each quantity's largest value."""
    import linkwork as lw

    m = lw.build.four_bar(0.35, 0.20, 0.35, 0.25, branch="crossed", coupler_point=(0.175, 0.0))
    res = m.compile().sweep(T)

    drawn = examples.four_bar(0.35, 0.20, 0.35, 0.25, branch="crossed").compile().sweep(T)
    assert res.columns == drawn.columns
    for x, y in ((res.q, drawn.q), (res.qd, drawn.qd), (res.qdd, drawn.qdd)):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    p, q = res.point("P").position, drawn.point("P").position
    assert np.abs(p - q).max() <= 1e-12 * np.abs(q).max()
    # still a mechanism to extend: a second coupler point, another driver
    m.point("Q", "coupler", (0.1, 0.05))
    m.remove("crank_angle")
    m.drive_angle("crank", lw.Linear(0.5, -2.0))
    assert m.compile().sweep([0.0, 0.1]).point("Q").position.shape == (2, 2)


@pytest.mark.parametrize(
    ("build", "drawn"),
    [
        (lambda: lw.build.slider_crank(0.10, 0.35, 0.02), lambda: examples.slider_crank(0.10, 0.35, 0.02)),
        (
            lambda: lw.build.inverted_slider_crank(0.30, 0.10, theta0=1.0),
            lambda: examples.inverted_slider_crank(0.30, 0.10, theta0=1.0),
        ),
    ],
    ids=["slider_crank", "inverted_slider_crank"],
)
def test_slides_from_their_lengths_sweep_as_the_drawn_ones(build, drawn) -> None:
    by_lengths, drawing = build(), drawn()
    assert not by_lengths.is_drawn()
    a, b = by_lengths.compile().sweep(T), drawing.compile().sweep(T)
    for x, y in ((a.q, b.q), (a.qd, b.qd), (a.qdd, b.qdd)):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    # drawn by the engine, the slide keeps its pins: its slide is still measured from them
    assembled = by_lengths.assemble()
    assert assembled.is_drawn()
    slide = next(j for j in assembled.to_dict()["joints"] if j["type"] == "prismatic")
    assert {"at", "axis", "pin_a", "pin_b"} <= set(slide)
    np.testing.assert_array_equal(assembled.compile().sweep(T).q, a.q)


def test_a_slider_crank_model_file_without_coordinates(tmp_path) -> None:
    text = """
[model]
name = "slider-crank"
units = { length = "mm", angle = "deg" }
branch = "open"

[[bodies]]
name = "crank"
[[bodies]]
name = "rod"
[[bodies]]
name = "slider"

[[joints]]
type = "revolute"
name = "O2"
body_a = "ground"
body_b = "crank"
pin_a = [0, 0]
pin_b = [0, 0]

[[joints]]
type = "revolute"
name = "A"
body_a = "crank"
body_b = "rod"
pin_a = [100, 0]
pin_b = [0, 0]

[[joints]]
type = "revolute"
name = "B"
body_a = "rod"
body_b = "slider"
pin_a = [350, 0]
pin_b = [0, 0]

[[joints]]
type = "prismatic"
name = "S"
body_a = "ground"
body_b = "slider"
pin_a = [0, 20]
axis = [1, 0]
pin_b = [0, 0]

[[drivers]]
type = "angle"
name = "crank_angle"
body = "crank"
law = { type = "linear", value = 0, rate = 286.4788975654116 }
"""
    path = tmp_path / "slider_crank.toml"
    path.write_text(text)
    mech = lw.Mechanism.load(path)
    assert not mech.is_drawn()
    a = mech.compile().sweep(T)
    b = examples.slider_crank(0.10, 0.35, 0.02).compile().sweep(T)
    # angles equal; lengths in mm against m (1e-12 of the largest, in mm)
    for x, y in ((a.q[:, 2::3], b.q[:, 2::3]), (a.qd[:, 2::3], b.qd[:, 2::3])):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    assert np.abs(a.q[:, 6] - 1000.0 * b.q[:, 6]).max() <= 1e-12 * 1000.0 * np.abs(b.q[:, 6]).max()
    # the slide driven instead, from the file's lengths-first slide
    assert mech.to_dict()["joints"][3]["pin_a"] == [0, 20]


def _four_bar_drawn_and_given(shift: float = 1e-3) -> dict:
    """The drawn four-bar whose joint B also gives its pins (the lengths 0.35 and 0.25),
    its drawn point moved by ``shift`` along x: the drawing and the lengths disagree."""
    d = examples.four_bar().to_dict()
    b = d["joints"][2]
    assert b["name"] == "B"
    b.update(pin_a=[0.35, 0.0], pin_b=[0.25, 0.0], at=[b["at"][0] + shift, b["at"][1]])
    return d


def test_a_drawing_that_does_not_close_names_the_joint_and_the_miss() -> None:
    m = lw.Mechanism.from_dict(_four_bar_drawn_and_given(1e-3))
    with pytest.raises(
        lw.ClosureError, match=r"joint 'B' does not close: its pin_a in 'coupler'.*1\.000e-3"
    ) as e:
        m.compile()
    assert e.value.joint == "B" and abs(e.value.miss - 1e-3) < 1e-15
    assert isinstance(e.value, lw.ModelError) and 'close = "given"' in str(e.value)
    # exactly closing: pins and drawing agree to round-off, nothing to say, the same sweep
    # (the pins given, not the drawing's, so to round-off)
    exact = lw.Mechanism.from_dict(_four_bar_drawn_and_given(0.0)).compile()
    assert exact.closing is None
    a, b = exact.sweep(T).q, examples.four_bar().compile().sweep(T).q
    assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()


def test_a_file_that_does_not_close_gives_the_line(tmp_path) -> None:
    path = tmp_path / "not_closed.toml"
    lw.Mechanism.from_dict(_four_bar_drawn_and_given(1e-3)).save(path)
    mech = lw.Mechanism.load(path)
    lines = path.read_text().splitlines()
    # the line of B's table: the [[joints]] above its name (1-based)
    line = max(k for k in range(lines.index('name = "B"')) if lines[k] == "[[joints]]") + 1
    with pytest.raises(
        lw.ClosureError, match=rf"not_closed.toml: line {line}: joint 'B' does not close"
    ) as e:
        mech.compile()
    assert e.value.joint == "B"


def test_closing_keeps_the_pins_given() -> None:
    """A drawing rounded to 4 decimals, with the pins (the lengths) exact: closing keeping
    the pins moves the bodies by least squares, and the sweep is the exact four-bar's."""
    d = examples.four_bar().to_dict()
    for body in d["bodies"]:
        body.update({k: round(body[k], 4) for k in ("x", "y", "theta")})
    pins = {
        "O2": ([0, 0], [0, 0]),
        "A": ([0.2, 0], [0, 0]),
        "B": ([0.35, 0], [0.25, 0]),
        "O4": ([0.35, 0], [0, 0]),
    }
    for j in d["joints"]:
        j.update(at=[round(v, 4) for v in j["at"]], pin_a=pins[j["name"]][0], pin_b=pins[j["name"]][1])
    m = lw.Mechanism.from_dict(d)
    with pytest.raises(lw.ClosureError) as e:
        m.compile()
    assert 1e-6 < e.value.miss < 1e-4
    m.close = "given"
    model = m.compile()
    closing = model.closing
    assert closing.keep == "given" and {x.joint for x in closing.misses} <= {"A", "B"}
    assert closing.moved and max(d for _, d, _ in closing.moved) < 1e-4
    assert "keeping the pins given" in closing.report()
    exact = examples.four_bar().compile().sweep(T)
    res = model.sweep(T)
    for x, y in ((res.q, exact.q), (res.qd, exact.qd), (res.qdd, exact.qdd)):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()


def test_closing_keeps_the_drawing() -> None:
    m = lw.Mechanism.from_dict(_four_bar_drawn_and_given(1e-3))
    m.close = "drawn"
    model = m.compile()
    closing = model.closing
    assert closing.keep == "drawn" and not closing.moved
    assert [(x.joint, x.body, x.pin) for x in closing.misses] == [
        ("B", "coupler", "pin_a"),
        ("B", "rocker", "pin_b"),
    ]
    # the drawing's pins: the same sweep as the drawing without any pins
    d = _four_bar_drawn_and_given(1e-3)
    del d["joints"][2]["pin_a"], d["joints"][2]["pin_b"]
    np.testing.assert_array_equal(model.sweep(T).q, lw.Mechanism.from_dict(d).compile().sweep(T).q)
    # the coupler's length is the drawing's: 1e-3 along x changes it by 0.35 -> |B' - A|
    res = model.sweep(T[:1])
    length = np.hypot(
        *(
            res.point_at("coupler", closing.misses[0].drawn).position[0]
            - res.point_at("coupler", (0, 0)).position[0]
        )
    )
    assert abs(length - 0.35) > 5e-4
    with pytest.raises(lw.ModelError, match='close must be "given"'):
        lw.Model({**d, "close": "nearest"})


def test_pins_that_cannot_close_are_named_after_least_squares() -> None:
    d = _four_bar_drawn_and_given(0.0)
    # a rocker longer than ground, crank and coupler together: no configuration closes
    d["joints"][2]["pin_b"] = [2.0, 0.0]
    m = lw.Mechanism.from_dict(d)
    m.close = "given"
    with pytest.raises(lw.ClosureError, match="cannot all hold.*least squares"):
        m.compile()


def test_check_states_how_the_drawing_was_closed(tmp_path) -> None:
    from linkwork import cli

    m = lw.Mechanism.from_dict(_four_bar_drawn_and_given(1e-3))
    m.close = "drawn"
    m.save(tmp_path / "closed.toml")
    assert 'close = "drawn"' in (tmp_path / "closed.toml").read_text()
    out = subprocess.run(
        [sys.executable, "-m", "linkwork", "check", str(tmp_path / "closed.toml")],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "drawing closed          keeping the drawing's points" in out.stdout
    assert "joint 'B': pin_a of 'coupler' missed its drawn point by 1.000e-03 m" in out.stdout
    m.close = None
    m.save(tmp_path / "open.toml")
    out = subprocess.run(
        [sys.executable, "-m", "linkwork", "check", str(tmp_path / "open.toml")],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert out.returncode != 0 and "joint 'B' does not close" in out.stderr
    assert cli is not None
