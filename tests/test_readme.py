"""The README's Python example runs as written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest


def test_readme_python_example_runs():
    text = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "the README has a Python example"
    scope: dict = {}
    exec(compile(blocks[0], "README.md", "exec"), scope)
    res = scope["res"]
    assert res.q.shape == (100_001, 9)
    assert np.all(np.isfinite(res.qdd)) and res.pivot_ratio.min() > 1e-3


def test_readme_three_lines_sweep_as_the_drawn_four_bar():
    """The README's three lines (its second Python block) sweep as the drawn example."""
    import linkwork as lw

    text = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    block = re.findall(r"```python\n(.*?)```", text, flags=re.S)[1]
    assert len(block.strip().splitlines()) == 3 and "lw.build.four_bar" in block
    scope: dict = {"np": np}
    exec(compile(block, "README.md", "exec"), scope)
    drawn = lw.examples.four_bar().compile().sweep(np.linspace(0.0, 2 * np.pi / 5.0, 721))
    res = scope["res"]
    for x, y in ((res.q, drawn.q), (res.qd, drawn.qd), (res.qdd, drawn.qdd)):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    p, q = res.point("P").position, drawn.point("P").position
    assert np.abs(p - q).max() <= 1e-12 * np.abs(q).max()


def test_designers_tour_examples_run(tmp_path, monkeypatch):
    """docs/designers-tour.md's Python runs as written (its files written in a scratch folder)."""
    pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    pytest.importorskip("ezdxf")
    root = Path(__file__).resolve().parent.parent
    text = (root / "docs" / "designers-tour.md").read_text()
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    for block in re.findall(r"```python\n(.*?)```", text, flags=re.S):
        exec(compile(block.replace('"examples/', f'"{root}/examples/'), "designers-tour.md", "exec"), scope)
    assert scope["df"].attrs["units"]["P.x_d"] == "mm/s"
    assert scope["cycle"].driver == "crank_angle" and scope["cycle"].how == "360 / |rate|"
    assert scope["drawn"].is_drawn() and abs(scope["drawn"].to_dict()["joints"][2]["at"][0] - 0.475) < 1e-15
    assert {p.name for p in tmp_path.iterdir()} == {
        "four_bar_input.png",
        "four_bar.svg",
        "four_bar.dxf",
        "four_bar.csv",
        "four_bar.parquet",
    }
