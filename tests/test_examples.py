"""Every script in examples/ runs (each asserts its own check), and every model file in
examples/ passes `linkwork check`, `run` and `plot` as its header comment says to run it."""

from __future__ import annotations

import re
import runpy
import shlex
import sys
from pathlib import Path

import pytest

from linkwork.cli import main

FOLDER = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(FOLDER.glob("*.py"))
MODELS = sorted(FOLDER.glob("*.toml"))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs(path, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", [str(path), str(tmp_path)])
    runpy.run_path(str(path), run_name="__main__")
    assert capsys.readouterr().out.strip()


def test_there_are_examples():
    assert len(EXAMPLES) >= 4
    assert len(MODELS) >= 10


def test_every_example_says_its_parameters_with_units():
    """Each script's docstring has its parameters (with their units) and docs/examples.md
    the same line in its table of parameters."""
    import ast

    table = (FOLDER.parent / "docs" / "examples.md").read_text().split("## Parameters", 1)[1]
    for path in EXAMPLES:
        doc = ast.get_docstring(ast.parse(path.read_text())) or ""
        assert "Parameters: " in doc, path.name
        said = " ".join(doc.split("Parameters: ", 1)[1].split())
        row = re.search(rf"^\| `{path.stem}` \| (.*) \|$", table, re.M)
        assert row is not None, f"docs/examples.md has no parameters of {path.stem}"
        assert said == row.group(1) + ".", path.name
        assert re.search(r"\b(m|mm|rad|deg|rad/s|deg/s|kg|N|rpm)\b", said), path.name


def documented_run(path: Path) -> list[str]:
    """The options of the `linkwork run examples/NAME.toml ...` line in the file's header."""
    found = re.search(rf"^#\s+linkwork run examples/{re.escape(path.name)}(.*)$", path.read_text(), re.M)
    assert found, f"{path.name}: no '#   linkwork run examples/{path.name} ...' line in its header"
    return shlex.split(found.group(1))


def with_steps(options: list[str], steps: int, run: bool = True) -> list[str]:
    """The options with --steps set to ``steps``, without --plot and --animate (tested apart),
    and for `plot` (``run`` False) without the options only `run` has."""
    kept, skip = [], False
    for opt in options:
        if skip:
            skip = False
        elif opt in ("--steps", "--animate"):
            skip = True
        elif opt != "--plot" and (run or opt != "--forces"):
            kept.append(opt)
    return kept + ["--steps", str(steps)]


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_model_file_check_run_plot(path, tmp_path, capsys):
    options = documented_run(path)
    assert main(["check", str(path)]) == 0
    assert main(["run", str(path), *with_steps(options, 301), "--out", str(tmp_path)]) == 0
    assert (tmp_path / f"{path.stem}.csv").stat().st_size > 0
    assert main(["plot", str(path), *with_steps(options, 101, run=False), "--out", str(tmp_path)]) == 0
    assert (tmp_path / f"{path.stem}.png").stat().st_size > 0
    assert (tmp_path / f"{path.stem}_paths.png").stat().st_size > 0
    assert "error" not in capsys.readouterr().err
