"""docs/performance.md and the README's speed sentence say what the latest saved benchmark
run measured: their generated parts are exactly the rendering of that run's figures (so a
hand edit or a stale copy fails here), and every link to a run lands on a heading that
exists in its log."""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BENCHES = ROOT / "benches"
LINK = re.compile(r"\]\((\.\./benches/results/[^)#]+)(?:#([^)]+))?\)")


def bench_module(name: str):
    """A script of benches/ as a module (it imports its neighbours, so benches/ goes on the path)."""
    if str(BENCHES) not in sys.path:
        sys.path.insert(0, str(BENCHES))
    spec = importlib.util.spec_from_file_location(f"benches_{name}", BENCHES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def block(text: str, name: str) -> str:
    begin, end = f"<!-- {name} begin -->\n", f"\n<!-- {name} end -->"
    assert begin in text and end in text, f"no {name} block"
    return text[text.index(begin) + len(begin) : text.index(end)]


def test_verdicts_are_the_latest_runs_figures():
    compare, runlog = bench_module("compare"), bench_module("runlog")
    saved = sorted(runlog.RESULTS.glob("compare-*.json"))
    assert saved, "no saved compare.py run in benches/results/"
    m = json.loads(saved[-1].read_text())
    doc = (ROOT / "docs" / "performance.md").read_text()
    assert block(doc, "compare.py") == compare.short_report(m, runlog.link(m["stamp"], "compare.py"))
    readme = (ROOT / "README.md").read_text()
    assert block(readme, "compare.py") == compare.readme_paragraph(m)
    # the run is in its day's log, and the latest-runs list points at it
    assert f"## compare.py, {m['stamp']}\n" in runlog.log_path(m["stamp"]).read_text()
    assert f"- `compare.py`: [{m['stamp']}]({runlog.link(m['stamp'], 'compare.py')})" in doc


PAGES = ["README.md", *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").glob("*.md"))]


@pytest.mark.parametrize("page", PAGES)
def test_links_to_runs_land_on_a_heading(page):
    runlog = bench_module("runlog")
    source = ROOT / page
    links = LINK.findall(source.read_text().replace("](benches/results/", "](../benches/results/"))
    assert links or page != "docs/performance.md"
    for target, anchor in links:
        path = (ROOT / "docs" / target).resolve()
        assert path.exists(), f"{page} links to {target}, which does not exist"
        if anchor:
            headings = {runlog.slug(h) for h in re.findall(r"^#+ (.+)$", path.read_text(), re.M)}
            assert anchor in headings, f"{page} links to #{anchor}, not a heading of {target}"


def test_a_run_is_added_to_its_days_log_and_listed(tmp_path, monkeypatch):
    runlog = bench_module("runlog")
    monkeypatch.setattr(runlog, "RESULTS", tmp_path / "results")
    monkeypatch.setattr(runlog, "DOC", tmp_path / "docs" / "performance.md")
    runlog.DOC.parent.mkdir()
    listed = "- `b.py`: kept\n- `a.py`: old"
    runlog.DOC.write_text(f"a\n<!-- latest runs begin -->\n{listed}\n<!-- latest runs end -->\n")
    first = runlog.append_run("a.py", "2026-01-02 03:04 UTC", "first run")
    second = runlog.append_run("a.py", "2026-01-02 05:06 UTC", "second run")
    runlog.set_latest("a.py", f"[05:06]({second})")
    log = (tmp_path / "results" / "performance-2026-01-02.md").read_text()
    assert log.index("## a.py, 2026-01-02 03:04 UTC\n\nfirst run") < log.index("## a.py, 2026-01-02 05:06")
    assert first == "../results/performance-2026-01-02.md#apy-2026-01-02-0304-utc"
    listed = block(runlog.DOC.read_text(), "latest runs").splitlines()
    newest = "- `a.py`: [05:06](../results/performance-2026-01-02.md#apy-2026-01-02-0506-utc)"
    assert listed == [newest, "- `b.py`: kept"]
