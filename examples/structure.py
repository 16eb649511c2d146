"""The structure of a mechanism, drawn: each group of coordinates solved together (in
solving order) in its own colour. The Stephenson III six-bar of the examples: its input
crank, then the Assur dyad coupler-rocker, then the dyad link5-output hung on the coupler.

    python examples/structure.py [output folder]     # writes structure_stephenson.png

Parameters: the Stephenson III six-bar of six_bars (m, rad).
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from linkwork import examples

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

mech = examples.six_bar_stephenson()
structure = mech.compile().structure()
assert [g.kind for g in structure.groups] == ["input", "dyad RRR", "dyad RRR"]
desc = mech.to_dict()
pins = {j["name"]: np.array(j["at"]) for j in desc["joints"]}
# each body's pins, in the order its outline is drawn
pins_of: dict[str, list[str]] = {}
for j in desc["joints"]:
    for side in ("body_a", "body_b"):
        pins_of.setdefault(j[side], []).append(j["name"])

fig, ax = plt.subplots(figsize=(7, 5.5))
colours = ["tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange"]
for k, group in enumerate(structure.groups):
    colour = colours[k % len(colours)]
    for body in group.bodies:
        xy = np.array([pins[p] for p in pins_of[body]])
        if len(xy) > 2:  # a ternary link: a filled triangle
            ax.fill(xy[:, 0], xy[:, 1], color=colour, alpha=0.25, lw=0)
            xy = np.vstack([xy, xy[:1]])
        ax.plot(xy[:, 0], xy[:, 1], "-", color=colour, lw=4, solid_capstyle="round")
    ax.plot([], [], "-", color=colour, lw=4, label=f"{k + 1}. {group.kind}: {', '.join(group.bodies)}")
for name, p in pins.items():
    grounded = "ground" in (j["body_a"] for j in desc["joints"] if j["name"] == name)
    ax.plot(*p, "o", ms=9 if grounded else 7, mfc="white", mec="black", mew=1.5, zorder=5)
    if grounded:
        ax.plot(p[0], p[1] - 0.012, "^", ms=14, color="0.4", zorder=4)
    ax.annotate(name, p, xytext=(6, 6), textcoords="offset points", fontsize=9)
ax.legend(loc="upper left", fontsize=9, title="groups, in solving order", title_fontsize=9)
ax.set_aspect("equal")
ax.set_title(
    f"{desc['name']}: {len(structure.groups)} groups in solving order\n"
    "(each needs only the ones before it: the crank, then one dyad, then the next)",
    fontsize=10,
)
ax.set_xlabel("x (m)")
ax.set_ylabel("y (m)")
ax.set_xlim(-0.05, 0.45)
ax.set_ylim(-0.2, 0.45)
fig.tight_layout()
path = out / "structure_stephenson.png"
fig.savefig(path, dpi=110)
print(f"wrote {path}")
for k, g in enumerate(structure.groups, 1):
    print(f"{k}. {g}")
