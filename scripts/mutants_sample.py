"""A uniform random sample of a package's cargo-mutants mutants, each run against the whole
cargo suite of its package: an estimate of a full run's kill rate where the full run is
too long to make (docs/mutation-testing.md).

    python scripts/mutants_sample.py --seed 20261128 --n 60 --out benches/results/DIR

lists the mutants (`cargo mutants --list -p PACKAGE`, with the repository's config, so the
core's globs apply), sorts the names, draws `--n` of them with
`random.Random(seed).sample` and runs them in the drawn order, one `cargo mutants` call
each (`--in-place`: the tree is mutated and restored; never two runs in one tree). Each
outcome is appended to OUT/sample.jsonl as it comes, so a run stopped (`--until`, or
interrupted) is a prefix of the drawn order, itself a uniform sample, and a second call
with the same seed and OUT resumes it. The summary (counts, the kill rate with its 95 %
Wilson interval) is printed at the end, or alone with `--summary`.

On a machine whose target directory is shared, hold its lock around the whole call.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# the regex crate's metacharacters (its `regex::escape` set): each escaped, nothing else
_META = set("\\.+*?()|[]{}^$#&-~")


def escape(name: str) -> str:
    """`name` as a regex that matches it exactly (anchored)."""
    return "^" + "".join("\\" + c if c in _META else c for c in name) + "$"


def wilson(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """The Wilson score interval of a proportion k / n (95 % by default)."""
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    d = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / d
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, centre - half), min(1.0, centre + half))


def list_mutants(package: str) -> list[str]:
    out = subprocess.run(
        ["cargo", "mutants", "--list", "-p", package],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return sorted(line for line in out.splitlines() if line.strip())


def draw(names: list[str], n: int, seed: int) -> list[str]:
    return random.Random(seed).sample(names, min(n, len(names)))


def run_one(name: str, package: str, profile: str, timeout: int, out: Path) -> tuple[str, float]:
    """Runs one mutant with the package's whole suite; its outcome and wall time (s)."""
    path = name.split(":", 1)[0]
    with tempfile.TemporaryDirectory() as tmp:
        # an empty config: `-f` is then the only glob (the repository's config adds its
        # globs to it); the profile and the timeout are passed here instead
        empty = Path(tmp) / "empty.toml"
        empty.write_text("")
        cmd = [
            "cargo",
            "mutants",
            "--config",
            str(empty),
            "-p",
            package,
            "-f",
            path,
            "--re",
            escape(name),
            "--in-place",
            "--baseline",
            "skip",
            "--timeout",
            str(timeout),
            "--profile",
            profile,
            "-o",
            str(out),
        ]
        start = time.monotonic()
        subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
        seconds = time.monotonic() - start
    found = {}
    for outcome in ("caught", "missed", "timeout", "unviable"):
        f = out / "mutants.out" / f"{outcome}.txt"
        for line in f.read_text().splitlines() if f.exists() else []:
            found[line.strip()] = outcome
    # (a struct field's deletion in the file passes any --re, cargo-mutants 27: those run
    # too, their outcomes not counted)
    if name not in found:
        # the name matched no mutant: the list is not of this tree
        return (f"error ({len(found)} outcomes: {sorted(found.values())})", seconds)
    return (found[name], seconds)


def summary(rows: list[dict]) -> str:
    counts: dict[str, int] = {}
    for r in rows:
        counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
    caught = counts.get("caught", 0) + counts.get("timeout", 0)
    viable = caught + counts.get("missed", 0)
    lines = [f"mutants run: {len(rows)}; " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))]
    if viable:
        lo, hi = wilson(caught, viable)
        lines.append(
            f"kill rate (caught incl. timeouts over viable): {caught}/{viable} = {caught / viable:.3f}, "
            f"95 % Wilson interval [{lo:.3f}, {hi:.3f}]"
        )
    secs = [r["seconds"] for r in rows]
    if secs:
        median = sorted(secs)[len(secs) // 2]
        lines.append(f"time per mutant: median {median:.0f} s, total {sum(secs) / 60:.1f} min")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--n", type=int, default=60, help="sample size (default 60)")
    ap.add_argument("--package", default="linkwork")
    ap.add_argument("--profile", default="dev-fast")
    ap.add_argument("--timeout", type=int, default=120, help="seconds of a mutant's tests (default 120)")
    ap.add_argument("--out", type=Path, required=True, help="folder: list.txt, sample.txt, sample.jsonl")
    ap.add_argument("--until", help="start no mutant after this UTC time (HH:MM)")
    ap.add_argument("--summary", action="store_true", help="print the summary of OUT and stop")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    log = args.out / "sample.jsonl"
    rows = [json.loads(s) for s in log.read_text().splitlines()] if log.exists() else []
    # a row in error (the name not run) is run again
    rows = [r for r in rows if not r["outcome"].startswith("error")]
    if args.summary:
        print(summary(rows))
        return 0
    listed = args.out / "list.txt"
    if listed.exists():
        names = listed.read_text().splitlines()
    else:
        names = list_mutants(args.package)
        listed.write_text("\n".join(names) + "\n")
    sample = draw(names, args.n, args.seed)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout
    (args.out / "sample.txt").write_text(
        f"# {len(names)} mutants listed at {commit.strip()[:12]}; "
        f"random.Random({args.seed}).sample(sorted names, {args.n})\n" + "\n".join(sample) + "\n"
    )
    done = {r["name"] for r in rows}
    for i, name in enumerate(sample):
        if name in done:
            continue
        if args.until and time.strftime("%H:%M", time.gmtime()) >= args.until:
            print(f"stopped at {args.until} UTC before mutant {i}", file=sys.stderr)
            break
        with tempfile.TemporaryDirectory() as tmp:
            outcome, seconds = run_one(name, args.package, args.profile, args.timeout, Path(tmp))
        row = {"i": i, "name": name, "outcome": outcome, "seconds": round(seconds, 1)}
        rows.append(row)
        with log.open("a") as f:
            f.write(json.dumps(row) + "\n")
        print(f"{i:3d} {outcome:8s} {seconds:6.0f} s  {name}", flush=True)
    print(summary(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
