"""Screw analysis of a three-link planar arm (docs/screw.md): forward and inverse velocity,
inverse and forward force, each answered geometrically and checked against linear algebra.
Draws the arm with its end-point velocity, the barycentre construction, and the force line
through the torque centres.

    python examples/screw_three_link.py [output folder]

The arm is a representative example chosen for linkwork's documentation (links 1.0, 0.8,
0.5 m; joint angles 30, 45, -60 degrees; rates 1.0, -0.5, 2.0 rad/s); no published values
are reproduced.

Parameters: links 1.0, 0.8, 0.5 m; relative joint angles 30, 45, -60 deg; joint rates
1.0, -0.5, 2.0 rad/s; end force (0, -10) N; joint torques 4.0, 1.5, 0.5 N m.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from linkwork import screw

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

LENGTHS = [1.0, 0.8, 0.5]  # m
Q = np.radians([30.0, 45.0, -60.0])  # relative joint angles
W = np.array([1.0, -0.5, 2.0])  # joint rates, rad/s
F_END = np.array([0.0, -10.0])  # N, applied by the end point (inverse force)
TAU = np.array([4.0, 1.5, 0.5])  # N m, joint torques (forward force)

arm = screw.SerialArm.from_lengths(LENGTHS)
st = arm.forward(Q)
P, E = st.positions, st.end_point
J = st.jacobian
fmt = lambda v: "(" + ", ".join(f"{x + 0.0:+.4f}" for x in np.ravel(v)) + ")"  # noqa: E731

print("three-link arm: links", LENGTHS, "m, joint angles 30, 45, -60 deg")
for i, p in enumerate(P):
    print(f"  joint {i + 1} at {fmt(p)}   axis screw $_{i + 1} = (y, -x; 1) = {fmt(J[:, i])}")
print(f"  end point {fmt(E)}, end link at {np.degrees(st.end[2]):.1f} deg")

# -- forward velocity: T = J w; the pole is the barycentre of the joints, weights w ----------
T = st.twist(W)
v_end = st.end_velocity(W)
shares = st.joint_velocities(W)
pole = st.pole(W)
bary = (W[:, None] * P).sum(axis=0) / W.sum()
print("\nforward velocity, rates", W.tolist(), "rad/s")
print(f"  twist T = J w = {fmt(T)} (velocity of the point at the origin; rate)")
for i, s in enumerate(shares):
    print(f"  joint {i + 1} moves the end point at {fmt(s)} m/s  (w_{i + 1} k x (E - P_{i + 1}))")
print(f"  end-point velocity {fmt(v_end)} m/s = sum of the shares {fmt(shares.sum(0))}")
print(f"  pole {fmt(pole[:2])} = barycentre sum w_i P_i / sum w_i {fmt(bary)}")
turn = W.sum() * np.array([-(E - bary)[1], (E - bary)[0]])
print(f"  end point turns about the pole at {W.sum():g} rad/s: {fmt(turn)} m/s")
assert np.allclose(turn, v_end, atol=1e-12) and np.allclose(shares.sum(0), v_end, atol=1e-12)

# -- inverse velocity: line screws through the other two joints; the barycentre construction --
S = st.line_screws()
w_lines = st.inverse_velocity(T)
b = st.barycentre(T)
w_solve = np.linalg.solve(J, T)
print("\ninverse velocity of T")
for i, s in enumerate(S):
    j, k = [m + 1 for m in range(3) if m != i]
    print(
        f"  S_{j}{k} (line through joints {j}, {k}) = {fmt(s)}: "
        f"w_{i + 1} = S.T / S.$_{i + 1} = {s @ T:+.4f} / {s @ J[:, i]:+.4f} = {w_lines[i]:+.6f}"
    )
a = b.vertex
foot = b.foot[:2] / b.foot[2]
print(
    f"  barycentre: the line from joint {a + 1} through the pole meets the opposite side at {fmt(foot)};"
    f" rates {fmt(b.rates)}"
)
print(f"  linear solve J w = T: {fmt(w_solve)}; largest difference {np.abs(w_lines - w_solve).max():.1e}")
assert np.allclose(w_lines, W, atol=1e-12) and np.allclose(b.rates, W, atol=1e-12)

# -- inverse force: tau = J^T W, the perpendicular distances times the force ----------------
W_end = screw.force(F_END, E)
tau_end = st.torques(W_end)
p = st.lever_arms(W_end)
print(f"\ninverse force: end force {fmt(F_END)} N at the end point")
for i in range(3):
    print(
        f"  joint {i + 1}: distance to the force line p = {p[i]:+.4f} m, "
        f"tau = |F| p = {np.hypot(*F_END) * p[i]:+.4f} N m"
    )
print(f"  J^T W = {fmt(J.T @ W_end)} N m")
assert np.allclose(tau_end, J.T @ W_end, atol=1e-12)

# -- forward force: the force line passes through the torque centres of joint pairs ----------
centres = st.torque_centres(TAU)
W_f = st.force(TAU)
line = screw.line_of(W_f)
print(f"\nforward force: joint torques {TAU.tolist()} N m")
for (j, k), x in centres.items():
    xy = x[:2] / x[2]
    print(
        f"  torque centre of joints {j + 1}, {k + 1}: {fmt(xy)} "
        f"(= velocity centre of rates ({TAU[k]:+g}, {-TAU[j]:+g}) on joints {j + 1}, {k + 1}; "
        f"moment of the force about it {line @ x / x[2]:+.1e})"
    )
print(f"  end wrench W = {fmt(W_f)}: force {fmt(W_f[:2])} N, moment about the origin {W_f[2]:+.4f} N m")
print(f"  check J^T W = {fmt(J.T @ W_f)} N m; linear solve of J^T W = tau: {fmt(np.linalg.solve(J.T, TAU))}")
assert np.allclose(J.T @ W_f, TAU, atol=1e-12)
for (j, k), x in centres.items():
    rates = np.zeros(3)
    rates[j], rates[k] = TAU[k], -TAU[j]
    assert np.allclose(st.velocity_centres(rates)[(j, k)], x, atol=1e-14)
    assert abs(screw.reciprocal(W_f, st.twist(rates))) < 1e-12  # that motion does no work

# -- figure --------------------------------------------------------------------------------
fig, axes = plt.subplots(1, 3, figsize=(17, 6.2), constrained_layout=True)
chain = np.vstack([P, E])


def draw_arm(ax, title):
    ax.plot(chain[:, 0], chain[:, 1], "-", color="0.25", lw=4, solid_capstyle="round", zorder=2)
    ax.plot(P[:, 0], P[:, 1], "o", ms=9, mfc="white", mec="0.1", mew=2, zorder=4)
    ax.plot(*E, "s", ms=7, color="0.1", zorder=4)
    for i, pt in enumerate(P):
        ax.annotate(f"$P_{i + 1}$", pt, xytext=(-16, 8), textcoords="offset points", fontsize=11)
    ax.annotate("$E$", E, xytext=(8, 6), textcoords="offset points", fontsize=11)
    ax.plot([-0.15, 0.15], [-0.04, -0.04], color="0.1", lw=2)
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.25)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title, fontsize=11)


# (a) end-point velocity: the joints' shares and their sum, perpendicular to pole-E
ax = axes[0]
draw_arm(ax, "forward velocity: $v_E = \\sum w_i\\, k \\times (E - P_i)$")
k = 0.5  # m per (m/s)
colors = ["tab:blue", "tab:orange", "tab:green"]
start = E.copy()
for i, s in enumerate(shares):
    ax.annotate("", start + k * s, start, arrowprops=dict(arrowstyle="->", color=colors[i], lw=1.8))
    ax.text(*(start + 0.5 * k * s + [0.03, 0.0]), f"joint {i + 1}", color=colors[i], fontsize=9)
    start = start + k * s
ax.annotate("", E + k * v_end, E, arrowprops=dict(arrowstyle="-|>", color="crimson", lw=2.4))
ax.text(*(E + k * v_end + [0.04, -0.02]), "$v_E$", color="crimson", fontsize=12)
ax.plot(*pole[:2], "*", ms=15, color="crimson", zorder=5)
ax.annotate("pole", pole[:2], xytext=(8, -14), textcoords="offset points", color="crimson")
ax.plot([pole[0], E[0]], [pole[1], E[1]], ":", color="crimson", lw=1.2)
ax.update_datalim(np.vstack([E + k * np.cumsum(shares, axis=0), E + k * v_end + [0.25, 0.0]]))
ax.autoscale_view()
ax.text(0.02, 0.02, f"arrows: {k} m per m/s", transform=ax.transAxes, fontsize=8, color="0.3")

# (b) barycentre construction: pole = sum w_i P_i / sum w_i on the joint triangle
ax = axes[1]
draw_arm(ax, "inverse velocity: barycentre of the joints, weights $w_i$")
tri = np.vstack([P, P[:1]])
ax.plot(tri[:, 0], tri[:, 1], "--", color="0.55", lw=1)
others = [m for m in range(3) if m != a]
side = P[others]
d = side[1] - side[0]
ext = np.vstack([side[0] - 0.2 * d, side[1] + 0.2 * d])
ax.plot(ext[:, 0], ext[:, 1], "-", color="tab:purple", lw=1, alpha=0.6)
ax.plot([P[a][0], foot[0]], [P[a][1], foot[1]], "-", color="tab:purple", lw=1.5)
ax.plot(*foot, "D", color="tab:purple", ms=7, zorder=5)
ax.annotate("foot $D$", foot, xytext=(8, -12), textcoords="offset points", color="tab:purple")
ax.plot(*pole[:2], "*", ms=15, color="crimson", zorder=5)
ax.annotate("pole", pole[:2], xytext=(8, 6), textcoords="offset points", color="crimson")
for i, pt in enumerate(P):
    ax.annotate(f"$w_{i + 1}$ = {W[i]:+g}", pt, xytext=(8, -16), textcoords="offset points", fontsize=9)
for i, s in enumerate(S):  # the line screws S_jk, drawn from the screws themselves
    f, r = s[:2], s[2] * np.array([s[1], -s[0]])  # unit force; its line's point nearest the origin
    t = (P[[m for m in range(3) if m != i]] - r) @ f
    seg = r + np.outer([t.min() - 0.3, t.max() + 0.3], f)
    ax.plot(seg[:, 0], seg[:, 1], "-", color="0.7", lw=0.8, zorder=1)
ax.text(
    0.02,
    0.02,
    f"pole divides $P_{a + 1}D$, and $D$ divides the opposite side,\nin the inverse ratio of the rates",
    transform=ax.transAxes,
    fontsize=8,
    color="0.3",
)

# (c) forward force: the lines through joint pairs, the torque centres, the force line
ax = axes[2]
draw_arm(ax, f"forward force: torques {TAU.tolist()} N m")
pts = []
for (j, kk), x in centres.items():
    xy = x[:2] / x[2]
    pts.append(xy)
    seg = np.vstack([P[j], xy, P[kk]])
    ax.plot(seg[:, 0], seg[:, 1], "--", color="0.6", lw=0.9)
    ax.plot(*xy, "o", ms=7, color="tab:green", zorder=5)
    ax.annotate(f"$X_{{{j + 1}{kk + 1}}}$", xy, xytext=(8, 2), textcoords="offset points", color="tab:green")
pts = np.array(pts)
u = W_f[:2] / np.hypot(*W_f[:2])
base = pts.mean(axis=0)
span = np.ptp(pts @ u) / 2 + 1.2
fline = np.vstack([base - span * u, base + span * u])
ax.plot(*fline.T, "-", color="tab:green", lw=1.8, label=f"force line, |F| = {np.hypot(*W_f[:2]):.2f} N")
tail = base - 0.8 * span * u
ax.annotate("", tail + 0.5 * u, tail, arrowprops=dict(arrowstyle="-|>", color="tab:green", lw=2.4))
ax.annotate(
    "$F$", tail + 0.25 * u, xytext=(10, 0), textcoords="offset points", color="tab:green", fontsize=12
)
ax.legend(loc="lower right", fontsize=9)
for ax in axes:
    ax.margins(0.12)

fig.suptitle("three-link arm (links 1.0, 0.8, 0.5 m at 30, 45, -60 deg): screw analysis", fontsize=13)
path = out / "screw_three_link.png"
fig.savefig(path, dpi=120)
plt.close(fig)
print(f"\nwrote {path}")
