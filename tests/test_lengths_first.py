"""Lengths first: a mechanism given by its joints' pins in the bodies' own frames (and a
branch, or rough poses), drawn by the engine; the same sweep as the drawn one."""

from __future__ import annotations

import math

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
