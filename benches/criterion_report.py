"""The criterion results of `cargo bench -p linkwork --bench sweep` as Markdown tables.

    cargo bench -p linkwork --bench sweep
    python benches/criterion_report.py            # print the tables
    python benches/criterion_report.py --write    # and add them to the day's log in benches/results/

Reads every `criterion/<group>/<function>/<parameter>/new/` of the Cargo target directory
(`$CARGO_TARGET_DIR`, else `target/`): the median time per sweep and the steps per sweep
(criterion's throughput), so time per step = median / steps.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import sys
import time
from pathlib import Path

import runlog  # benches/, beside this script

ROOT = Path(__file__).resolve().parent.parent
KINDS = ("refactor", "small", "dense", "sparse", "structured")
LABELS = {
    "structured": "structured: groups in order (default)",
    "refactor": "general path, fixed-sequence LU",
    "small": "small LU",
    "dense": "dense LU (faer)",
    "sparse": "sparse LU (faer)",
}


def load(criterion: Path) -> dict[tuple[str, str, str], dict[str, float]]:
    """(group, function, parameter) -> median ns per sweep, elements per sweep, file time."""
    found = {}
    for bench in criterion.glob("*/*/*/new/benchmark.json"):
        meta = json.loads(bench.read_text())
        estimates = json.loads((bench.parent / "estimates.json").read_text())
        elements = (meta.get("throughput") or {}).get("Elements", 1)
        key = (meta["group_id"], meta["function_id"], meta["value_str"])
        found[key] = {
            "ns": estimates["median"]["point_estimate"],
            "elements": float(elements),
            "mtime": bench.stat().st_mtime,
        }
    return found


def us_per_step(entry: dict[str, float] | None) -> float | None:
    return None if entry is None else entry["ns"] / entry["elements"] / 1e3


def cell(value: float | None, digits: int = 3) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def report(found: dict[tuple[str, str, str], dict[str, float]]) -> str:
    when = max(e["mtime"] for e in found.values())
    cpu = platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    lines = [
        f"Measured {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(when))} with "
        f"`cargo bench -p linkwork --bench sweep` on {cpu}, {os.cpu_count()} cores; median time per "
        "sweep divided by its steps (h = one revolution / 100,000), in us per step.",
        "",
        "| mechanism | computes | "
        + " | ".join(LABELS[k] for k in KINDS)
        + " | small / fixed | sparse / fixed | fixed / structured |",
        "|---|---|" + "---:|" * (len(KINDS) + 3),
    ]
    for group in ("four_bar", "slider_crank", "six_bar_stephenson"):
        for what, label in (("pva", "p+v+a"), ("p", "p")):
            us = {k: us_per_step(found.get((group, k, what))) for k in KINDS}
            if all(v is None for v in us.values()):
                continue
            base = us["refactor"]
            ratios = [cell(us[k] / base if us[k] and base else None, 2) for k in ("small", "sparse")]
            st = us["structured"]
            ratios.append(cell(base / st if base and st else None, 2))
            lines.append(
                f"| {group} | {label} | "
                + " | ".join(cell(us[k]) for k in KINDS)
                + " | "
                + " | ".join(ratios)
                + " |"
            )
    mechanisms = ("four_bar", "slider_crank", "six_bar_stephenson")
    paths = [g for g in mechanisms if (g, "structured", "point_path") in found]
    if paths:
        lines += [
            "",
            "One coupler point's path only (`outputs`: that point, positions; nothing else stored) against "
            "the full output (every coordinate, p+v+a), structured path, us per step:",
            "",
            "| mechanism | full output | one point's path | full / path |",
            "|---|---:|---:|---:|",
        ]
        for g in paths:
            full, path = (us_per_step(found.get((g, "structured", w))) for w in ("pva", "point_path"))
            ratio = cell(full / path if full and path else None, 2)
            lines.append(f"| {g} | {cell(full)} | {cell(path)} | {ratio} |")
    chains = sorted({int(p) for g, _, p in found if g == "chain"})
    if chains:
        lines += [
            "",
            "Chain of K four-bar loops (3K bodies), positions + velocities + accelerations:",
            "",
            "| loops K | bodies | steps per sweep | "
            + " | ".join(LABELS[k] for k in KINDS)
            + " | fixed: us per body per step | structured: us per body per step |",
            "|---:|---:|---:|" + "---:|" * (len(KINDS) + 2),
        ]
        for k in chains:
            entries = {kind: found.get(("chain", kind, str(k))) for kind in KINDS}
            steps = next(int(e["elements"]) for e in entries.values() if e)
            per_body = [us_per_step(entries[kind]) for kind in ("refactor", "structured")]
            lines.append(
                f"| {k:,} | {3 * k:,} | {steps:,} | "
                + " | ".join(cell(us_per_step(entries[kind]), 2) for kind in KINDS)
                + " | "
                + " | ".join(cell(v / (3 * k) if v else None) for v in per_body)
                + " |"
            )
    lu = {(f, p): e for (g, f, p), e in found.items() if g == "lu"}
    if lu:
        lines += [
            "",
            "One factorization and three solves of Phi_q at a solved configuration (the work of a time "
            "step's linear algebra), in us:",
            "",
            "| system | fixed-sequence LU (`sparse_lu`) | small LU (`small_lu`) | small / fixed |",
            "|---|---:|---:|---:|",
        ]
        for system in sorted({p for _, p in lu}):
            fixed, small = (lu.get((kind, system)) for kind in ("refactor", "small"))
            us = [None if e is None else e["ns"] / e["elements"] / 1e3 for e in (fixed, small)]
            ratio = cell(us[1] / us[0] if us[0] and us[1] else None, 2)
            lines.append(f"| {system} | {cell(us[0])} | {cell(us[1])} | {ratio} |")
    batch = {int(p): found[("batch", f, p)] for g, f, p in found if g == "batch"}
    if batch:
        lines += [
            "",
            "`sweep_batch`: 8 four-bar designs of 10,000 steps each:",
            "",
            "| threads | ms per batch | us per design-step | speed-up over 1 thread |",
            "|---:|---:|---:|---:|",
        ]
        for threads, e in sorted(batch.items()):
            lines.append(
                f"| {threads} | {e['ns'] / 1e6:.2f} | {e['ns'] / e['elements'] / 1e3:.3f} | "
                f"{batch[1]['ns'] / e['ns'] if 1 in batch else float('nan'):.2f}x |"
            )
    floor = {(f, p): e for (g, f, p), e in found.items() if g == "floor"}
    if floor:
        lines += [
            "",
            "The floor: a hand-written closed-form loop that computes and stores what the sweep stores "
            "(every body's x, y, theta and, for p+v+a, their derivatives; the four-bar's angles by "
            "atan2, the slider-crank's rod by asin), against the engine's two paths, us per step. "
            "The guarded loop (p+v+a) also does by hand what the engine checks and keeps at every "
            "step: the closeness to singular and its trend, the two-way check of every coordinate, "
            "the pins' residuals, and the residual and closeness stored per row. The continued loop "
            "(four-bar) is the guarded loop with its angles continued as the engine continues them "
            "(`turned`, `angle_of`: no sine, cosine or atan2 in most steps), its rates solved for the "
            "check and kept (p+v+a) or not (p): the least a step that keeps the engine's promise costs. "
            "The general loop (four-bar, p+v+a) is the engine's own arithmetic for the two groups (every "
            "origin wherever its pins put it) with the same checks, its values local:",
            "",
            "| mechanism | computes | general path (fixed-sequence LU) | structured (groups in closed form) "
            "| closed-form loop | guarded loop | continued loop | general loop | general path / floor "
            "| structured / floor | structured / guarded | structured / continued "
            "| structured / general loop |",
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for mech in ("four_bar", "slider_crank"):
            for what, label in (("pva", "p+v+a"), ("p", "p")):
                engine = us_per_step(found.get((mech, "refactor", what)))
                structured = us_per_step(found.get((mech, "structured", what)))
                closed = us_per_step(floor.get((mech, what)))
                guarded = us_per_step(floor.get((mech, what + "_guarded")))
                continued = us_per_step(floor.get((mech, what + "_continued")))
                general = us_per_step(floor.get((mech, what + "_general")))
                if closed is None:
                    continue
                r_general = cell(engine / closed if engine else None, 2)
                r_structured = cell(structured / closed if structured else None, 2)
                r_guarded = cell(structured / guarded if structured and guarded else None, 2)
                r_continued = cell(structured / continued if structured and continued else None, 2)
                r_loop = cell(structured / general if structured and general else None, 2)
                lines.append(
                    f"| {mech} | {label} | {cell(engine)} | {cell(structured)} | {cell(closed)} "
                    f"| {cell(guarded)} | {cell(continued)} | {cell(general)} | {r_general} | {r_structured} "
                    f"| {r_guarded} | {r_continued} | {r_loop} |"
                )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="add the tables to benches/results/")
    args = parser.parse_args()
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    found = load(target / "criterion")
    if not found:
        sys.exit(
            f"no criterion results under {target / 'criterion'}: run cargo bench -p linkwork --bench sweep"
        )
    text = report(found)
    print(text)
    if args.write:
        stamp = re.search(r"Measured (\d{4}-\d\d-\d\d \d\d:\d\d UTC)", text)
        if stamp is None:
            sys.exit("the report has no date")
        link = runlog.append_run("criterion", stamp.group(1), text)
        runlog.set_latest("criterion", f"[{stamp.group(1)}]({link})")
        print(f"wrote {runlog.log_path(stamp.group(1))} and {runlog.DOC}", file=sys.stderr)


if __name__ == "__main__":
    main()
