"""The README's Python example runs as written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np


def test_readme_python_example_runs():
    text = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "the README has a Python example"
    scope: dict = {}
    exec(compile(blocks[0], "README.md", "exec"), scope)
    res = scope["res"]
    assert res.q.shape == (100_001, 9)
    assert np.all(np.isfinite(res.qdd)) and res.pivot_ratio.min() > 1e-3
