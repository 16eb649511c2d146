"""Where the time goes: callgrind's instruction counts (a proxy for time) over one of the
criterion sweeps, summed per source file (inlined code counts where it was written) and
per function.

    python benches/profile.py                   # the four-bar and slider-crank on both paths, the
                                                # floors, the K = 1000 chain; instructions per step
    python benches/profile.py chain/sparse/100      # any criterion benchmark id of benches/sweep.rs

Instructions per step are the inclusive count of the function that runs a benchmark's
sweep (`sweep_observed`) or loop (the floors' `floor_*`, `guarded_*`, `continued_*`,
`general_*`) over its calls and the steps of each (as `benches/sweep.rs` sets them): a
measure of the work a step does that the shared machine's noise does not move, beside
criterion's times.

Needs valgrind. Builds the bench with line tables (in `<target>/callgrind`, so the normal
build is left alone) and runs it for a few seconds of criterion's --profile-time under
callgrind. The model is built inside the benchmark, outside the timed loop, but callgrind
counts it: a few per cent on the largest chains.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import runlog  # benches/, beside this script

ROOT = Path(__file__).resolve().parent.parent
DEFAULT = [
    "four_bar/structured/pva",
    "four_bar/structured/p",
    "slider_crank/structured/pva",
    "slider_crank/structured/p",
    "floor/four_bar/pva",
    "floor/four_bar/p",
    "floor/four_bar/pva_guarded",
    "floor/four_bar/pva_continued",
    "floor/four_bar/p_continued",
    "floor/four_bar/pva_general",
    "floor/slider_crank/pva",
    "floor/slider_crank/p",
    "floor/slider_crank/pva_guarded",
    "four_bar/refactor/pva",
    "four_bar/refactor/p",
    "chain/structured/1000",
    "chain/refactor/1000",
]
# steps per sweep or loop and bodies, as benches/sweep.rs sets them (`mechanisms`, `chains`,
# `floor`)
MECHANISM_STEPS = 10_000
BODIES = {"four_bar": 3, "slider_crank": 3, "six_bar_stephenson": 5}


def per_call(bench: str) -> tuple[str, int, int] | None:
    """The function a benchmark's calls run, its steps per call and the mechanism's bodies;
    None where not known."""
    parts = bench.split("/")
    if parts[0] == "floor" and len(parts) == 3:
        loops = ("guarded", "continued", "general")
        kind = next((k + "_" for k in loops if parts[2].endswith("_" + k)), "floor_")
        return "::" + kind + parts[1], MECHANISM_STEPS, 3
    if parts[0] == "chain" and len(parts) == 3 and parts[2].isdigit():
        loops = int(parts[2])
        return "linkwork::sweep::sweep_observed", max(10_000 // loops, 500), 3 * loops
    if parts[0] in BODIES:
        return "linkwork::sweep::sweep_observed", MECHANISM_STEPS, BODIES[parts[0]]
    return None


def build() -> str:
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "callgrind"
    env = {**os.environ, "CARGO_TARGET_DIR": str(target), "CARGO_PROFILE_BENCH_DEBUG": "line-tables-only"}
    out = subprocess.run(
        ["cargo", "bench", "-p", "linkwork", "--bench", "sweep", "--no-run", "--message-format=json"],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    for line in out.splitlines():
        m = json.loads(line)
        if m.get("reason") == "compiler-artifact" and m["target"]["name"] == "sweep" and m.get("executable"):
            return m["executable"]
    raise SystemExit("no bench executable built")


def parse(path: Path) -> tuple[dict[str, int], dict[str, int], int, dict[str, int], dict[str, int]]:
    """Self cost (Ir) by source file and by function from a callgrind output file, and by
    function its inclusive cost and the calls it received.

    The standard library's code (slices, iterators, f64 methods) inlined into a linkwork
    function counts for the last other file seen in that function (linkwork's own or a
    dependency's, such as faer's, inlined there too): callgrind knows only the innermost
    file of inlined code, and this heuristic puts a loop's iterator overhead where the loop
    was written."""
    names: dict[tuple[str, str], str] = {}
    by_file: dict[str, int] = defaultdict(int)
    by_fn: dict[str, int] = defaultdict(int)
    fl = fi = fn = "?"
    last_own = None
    skip_next = False
    callee = "?"
    inclusive: dict[str, int] = defaultdict(int)
    calls: dict[str, int] = defaultdict(int)

    def name(kind: str, rest: str) -> str:
        m = re.match(r"\((\d+)\)(?: (.*))?", rest)
        if not m:
            return rest
        if m.group(2) is not None:
            names[(kind, m.group(1))] = m.group(2)
        return names.get((kind, m.group(1)), "?")

    for line in path.read_text(errors="replace").splitlines():
        if not line:
            continue
        head = line.split("=", 1)
        if len(head) == 2 and re.fullmatch(r"[a-z]+", head[0]):
            key, rest = head
            if key == "fl":
                fl = fi = name("file", rest)
            elif key in ("fi", "fe"):
                fi = name("file", rest)
            elif key == "fn":
                fn = name("fn", rest)
                fi = fl
                last_own = None
            if key in ("fl", "fi", "fe", "fn") and crate_of(fi) != "std":
                last_own = fi
            elif key in ("cfi", "cfl"):
                name("file", rest)
            elif key == "cfn":
                callee = name("fn", rest)
            elif key == "calls":
                skip_next = True  # the next cost line is the call's inclusive cost
                calls[callee] += int(rest.split()[0])
            continue
        if line[0] in "0123456789+-*":
            if skip_next:
                skip_next = False
                parts = line.split()
                if len(parts) >= 2 and callee != fn:
                    inclusive[fn] += int(parts[1])
                continue
            parts = line.split()
            if len(parts) >= 2:
                cost = int(parts[1])
                own = fn.startswith(("linkwork::", "<linkwork::")) and last_own is not None
                by_file[last_own if own and crate_of(fi) == "std" else fi] += cost
                by_fn[fn] += cost
                inclusive[fn] += cost
    total = sum(by_file.values())
    return by_file, by_fn, total, inclusive, calls


def short(path: str) -> str:
    crate = crate_of(path)
    if "crates/linkwork/src/" in path:
        return "linkwork: " + path.split("crates/linkwork/src/")[-1]
    if "sysdeps/" in path:
        return "libc/libm: " + path.split("sysdeps/")[-1]
    if "/src/" in path:
        return f"{crate}: " + path.split("/src/")[-1]
    return f"{crate}: {path}"


def crate_of(path: str) -> str:
    m = re.search(r"registry/src/[^/]+/([^/]+)/", path)
    if m:
        return m.group(1)
    if "crates/linkwork/" in path:
        return "linkwork"
    if "rustc/" in path or "/library/" in path:
        return "std"
    if "sysdeps" in path or "glibc" in path or path.startswith("./"):
        return "libc/libm"
    return "other"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("filters", nargs="*", default=DEFAULT, help="criterion benchmark ids")
    parser.add_argument("--seconds", type=float, default=3.0, help="criterion --profile-time")
    parser.add_argument("--top", type=int, default=12)
    parser.add_argument("--write", action="store_true", help="add the profile to benches/results/")
    args = parser.parse_args()
    exe = build()
    lines: list[str] = []
    per_step: list[tuple[str, float, float]] = []

    def emit(text: str) -> None:
        print(text)
        sys.stdout.flush()
        lines.append(text)

    with tempfile.TemporaryDirectory() as tmp:
        for bench in args.filters:
            out = Path(tmp) / "callgrind.out"
            # criterion's profile mode refuses a time shorter than its first batch (slow
            # under valgrind for the large chains): longer times until it accepts
            for attempt in range(4):
                run = subprocess.run(
                    [
                        "valgrind",
                        "--tool=callgrind",
                        f"--callgrind-out-file={out}",
                        exe,
                        "--bench",
                        "--profile-time",
                        str(args.seconds * 2**attempt),
                        f"^{re.escape(bench)}$",
                    ],
                    capture_output=True,
                )
                if run.returncode == 0:
                    break
            else:
                raise SystemExit(f"{bench}: {run.stderr.decode(errors='replace')[-2000:]}")
            by_file, by_fn, total, inclusive, calls = parse(out)
            target = per_call(bench)
            if target is not None:
                suffix, steps, bodies = target
                found = [f for f in inclusive if f.endswith(suffix) and calls.get(f)]
                if found:
                    f = found[0]
                    step = inclusive[f] / (calls[f] * steps)
                    per_step.append((bench, step, step / bodies))
            emit(f"== {bench}: {total:,} instructions")
            crates: dict[str, int] = defaultdict(int)
            for f, c in by_file.items():
                crates[crate_of(f)] += c
            shares = [(k, 100 * v / total) for k, v in _top(crates, 5)]
            emit("   by crate: " + ", ".join(f"{k} {p:.1f}%" for k, p in shares if p >= 0.1))
            emit("   by source file (self; inlined code where written):")
            for f, c in _top(by_file, args.top):
                emit(f"     {100 * c / total:5.1f}%  {short(f)}")
            emit("   by function (self; inlined code in its caller):")
            for f, c in _top(by_fn, 6):
                emit(f"     {100 * c / total:5.1f}%  {f[:100]}")
            emit("")
    if per_step:
        table = [
            "Instructions per step (inclusive, over the calls and steps of the sweep or the loop):",
            "",
            "| benchmark | per step | per body per step |",
            "|---|---:|---:|",
        ]
        table += [f"| {b} | {s:,.0f} | {p:,.0f} |" for b, s, p in per_step]
        print("\n".join(table))
    if args.write:
        import platform
        import time

        stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
        body = (
            f"Measured {stamp} on {platform.machine()} "
            f"at `{revision()}` with `python benches/profile.py --write` (callgrind instruction counts)."
            + ("\n\n" + "\n".join(table) if per_step else "")
            + "\n\n```\n"
            + "\n".join(lines).rstrip()
            + "\n```"
        )
        link = runlog.append_run("profile.py", stamp, body)
        runlog.set_latest("profile.py", f"[{stamp}]({link})")
        print(f"wrote {runlog.log_path(stamp)} and {runlog.DOC}", file=sys.stderr)


def revision() -> str:
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True)
        return out.stdout.decode().strip() or "?"
    except OSError:
        return "?"


def _top(d: dict[str, int], n: int) -> list[tuple[str, int]]:
    return sorted(d.items(), key=lambda kv: -kv[1])[:n]


if __name__ == "__main__":
    main()
