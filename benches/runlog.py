"""Where the benchmarks write what they measured.

Each run with ``--write`` adds its full report to the day's log,
``benches/results/performance-<YYYY-MM-DD>.md`` (one section a run, newest last: the logs
are history and are never rewritten), and points docs/performance.md, the short report,
at it. The short report's generated parts sit between ``<!-- NAME begin -->`` and
``<!-- NAME end -->`` lines; the prose around them holds no figures, so it cannot drift.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benches" / "results"
DOC = ROOT / "docs" / "performance.md"
LOG_HEADER = """# Performance runs of {day}

Each section is one run, as its command wrote it; the figures are as measured then.
"""


def log_path(stamp: str) -> Path:
    """The log of the day of ``stamp`` ("YYYY-MM-DD HH:MM UTC")."""
    return RESULTS / f"performance-{stamp[:10]}.md"


def slug(heading: str) -> str:
    """The anchor GitHub gives a Markdown heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def link(stamp: str, name: str) -> str:
    """The link from docs/performance.md to the run ``name, stamp`` in its day's log."""
    return f"{Path(os.path.relpath(log_path(stamp), DOC.parent)).as_posix()}#{slug(f'{name}, {stamp}')}"


def append_run(name: str, stamp: str, body: str) -> str:
    """Add one run to its day's log; returns the link to it from docs/performance.md."""
    path = log_path(stamp)
    text = path.read_text() if path.exists() else LOG_HEADER.format(day=stamp[:10])
    heading = f"{name}, {stamp}"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text.rstrip("\n") + f"\n\n## {heading}\n\n{body.strip()}\n")
    return link(stamp, name)


def replace_block(name: str, body: str, path: Path | None = None) -> None:
    """Put ``body`` between the ``name`` markers of ``path`` (appended if it has none)."""
    path = path or DOC
    begin, end = f"<!-- {name} begin -->", f"<!-- {name} end -->"
    text = path.read_text() if path.exists() else ""
    block = f"{begin}\n{body.strip()}\n{end}"
    if begin in text:
        text = text[: text.index(begin)] + block + text[text.index(end) + len(end) :]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    path.write_text(text)


def set_latest(name: str, line: str, path: Path | None = None) -> None:
    """Point the short report's list of latest runs at this run: one line per command."""
    path = path or DOC
    begin, end = "<!-- latest runs begin -->", "<!-- latest runs end -->"
    text = path.read_text()
    head, rest = text.split(begin, 1)
    lines, tail = rest.split(end, 1)
    kept = [ln for ln in lines.strip("\n").splitlines() if ln and not ln.startswith(f"- `{name}`")]
    kept.append(f"- `{name}`: {line}")
    path.write_text(head + begin + "\n" + "\n".join(sorted(kept)) + "\n" + end + tail)
