"""How `linkwork run`, `plot` and `check` scale with the model's size: chains of K
four-bar loops written as model files, each command timed once (11 time steps: the
sweep itself is not what is measured here, the work around it is).

    python benches/cli_scaling.py [K ...]      (default: 1000 4000 10000)
"""

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import linkwork as lw

sizes = [int(k) for k in sys.argv[1:]] or [1000, 4000, 10000]
with tempfile.TemporaryDirectory() as tmp:
    print("| loops | coordinates | run [s] | plot [s] | check [s] |")
    print("|---|---|---|---|---|")
    for k in sizes:
        path = Path(tmp) / f"chain{k}.toml"
        lw.examples.chain(k).save(path)
        row = []
        for command in (["run", "--steps", "11"], ["plot", "--steps", "11"], ["check"]):
            start = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "linkwork", command[0], str(path), *command[1:], "--out", tmp]
                if command[0] != "check"
                else [sys.executable, "-m", "linkwork", "check", str(path)],
                check=True,
                capture_output=True,
            )
            row.append(time.perf_counter() - start)
        print(f"| {k} | {9 * k} | " + " | ".join(f"{x:.1f}" for x in row) + " |")
