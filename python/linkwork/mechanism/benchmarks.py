"""Published forward-dynamics benchmark problems as ordinary descriptions.

Each builder returns a `Benchmark`: the `Mechanism` (bodies with their mass properties,
joints, gravity and loads, no driver: its free coordinates move under the forces), the
initial velocities ``qd0`` in the model's column order (3 per body, x, y, theta, bodies in
the order built) and the specified time span. The exact or published references are in
`linkwork.reference.exact`.

- `pendulum` (IFToMM A01): a 1 kg point mass at the tip of a massless 1 m link.
- `n_four_bar` (IFToMM A02): 2N+1 unit bars in a chain of N parallelograms, crossing a
  singular configuration every half turn.
- `andrews_squeezer` (IVP test set, Hairer-Wanner VII.7): seven bodies, a spring, a
  driving torque, no gravity.

>>> b = n_four_bar(2)
>>> b.mechanism.to_dict()["bodies"][0]["name"], b.qd0[:3].tolist()
('crank0', [0.0, 0.0, -1.0])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..motion import Constant
from ..reference.exact import ANDREWS, ANDREWS_ANGLES0
from .builder import Mechanism

__all__ = ["Benchmark", "pendulum", "n_four_bar", "andrews_squeezer", "andrews_angles"]

G = 9.81


@dataclass(frozen=True)
class Benchmark:
    """A benchmark problem: its ``mechanism``, initial velocities ``qd0`` (n_coords,
    column order), the specified end time ``t_end`` and the named point the benchmark
    reports (``point``)."""

    mechanism: Mechanism
    qd0: np.ndarray
    t_end: float
    point: str


def pendulum(length: float = 1.0, mass: float = 1.0, g: float = G) -> Benchmark:
    """IFToMM A01: a point mass ``mass`` at the tip P1 of a massless link of ``length``,
    pinned to the ground at the origin, released at rest from (length, 0) under gravity
    (0, -g); 10 s (the replications' span).

    One body, "bar": frame at the pin, x axis along the bar (theta = 0 at the start), all
    its mass at the tip with no inertia about it, so its own 3 x 3 mass matrix is singular
    (only the motions the pin allows carry inertia). The named point "P1" is the tip."""
    m = Mechanism("IFToMM A01 simple pendulum")
    bar = m.link("bar", (0.0, 0.0), (length, 0.0), mass=mass, inertia=0.0, com=(length, 0.0))
    m.revolute(m.ground, bar, at=(0.0, 0.0), name="O")
    m.point("P1", bar, (length, 0.0))
    m.set_gravity((0.0, -g))
    return Benchmark(m, np.zeros(3), 10.0, "P1")


def n_four_bar(n: int = 40, length: float = 1.0, mass: float = 1.0, g: float = G) -> Benchmark:
    """IFToMM A02, the N-four-bar: N + 1 vertical cranks "crank0".."crankN" pinned to the
    ground at (k L, 0), N horizontal couplers "coupler1".."couplerN" pinned to the tips of
    cranks k-1 and k; uniform bars of ``length`` L and ``mass`` m (inertia m L^2 / 12 about
    the middle), gravity (0, -g), 3N + 1 revolutes, one degree of freedom.

    Initial velocities: every crank turns at -1 rad/s (tip B0 of crank0 moves at +1 m/s
    along x), the couplers translate at (1, 0) m/s. Specified span 20 s (N = 40; the
    replications use N = 2 over 10 s). The named point "B0" is crank0's tip."""
    if int(n) != n or n < 1:
        raise ValueError(f"the N-four-bar needs N >= 1 parallelograms, not {n!r}")
    n = int(n)
    L = float(length)
    m = Mechanism(f"IFToMM A02 N-four-bar, N = {n}")
    cranks = [m.link(f"crank{k}", (k * L, 0.0), (k * L, L), mass=mass) for k in range(n + 1)]
    couplers = [m.link(f"coupler{k}", ((k - 1) * L, L), (k * L, L), mass=mass) for k in range(1, n + 1)]
    for k, crank in enumerate(cranks):
        m.revolute(m.ground, crank, at=(k * L, 0.0), name=f"O{k}")
    for k, coupler in enumerate(couplers, start=1):
        m.revolute(cranks[k - 1], coupler, at=((k - 1) * L, L), name=f"B{k - 1}c{k}")
        m.revolute(coupler, cranks[k], at=(k * L, L), name=f"c{k}B{k}")
    m.point("B0", cranks[0], (0.0, L))
    m.set_gravity((0.0, -g))
    omega = -1.0 / L  # B0 at +1 m/s
    qd0 = np.concatenate([np.tile([0.0, 0.0, omega], n + 1), np.tile([-omega * L, 0.0, 0.0], n)])
    return Benchmark(m, qd0, 20.0, "B0")


def _e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


def _perp(angle: float) -> np.ndarray:
    """The unit vector at angle - 90 degrees: (sin a, -cos a)."""
    return np.array([math.sin(angle), -math.cos(angle)])


def andrews_angles(q: np.ndarray) -> np.ndarray:
    """The test set's seven angles (beta, Theta, gamma, Phi, delta, Omega, epsilon) from
    the absolute angles of ``andrews_squeezer``'s bodies 1..7 (q's theta columns, or q
    itself: n x 21 or 21): body angles beta, beta + Theta, gamma, Phi + delta, delta,
    Omega + epsilon, epsilon."""
    q = np.asarray(q, dtype=float)
    th = q[..., 2::3]
    b1, b2, b3, b4, b5, b6, b7 = (th[..., k] for k in range(7))
    return np.stack([b1, b2 - b1, b3, b4 - b5, b5, b6 - b7, b7], axis=-1)


def andrews_squeezer() -> Benchmark:
    """Andrews' squeezing mechanism (the IVP test set's problem "andrews"; Hairer and
    Wanner, Solving ODEs II, VII.7): seven bodies, no gravity, a driving torque ``mom``
    on body 1, a spring (c0, l0) from point D of body 3 to the ground point C; at rest at
    t = 0 in the test set's initial angles; t from 0 to 0.03.

    Geometry (from the test set's constraints): body 1 turns about O = (0, 0); body 2 is
    pinned to it at P = rr e(beta) and reaches E = P - d e(beta + Theta); E is pinned to
    body 3 (about B = (xb, yb), E = B + ss f(gamma)), to body 4 (E = F + e f(Phi + delta),
    F = A + zt e(delta) on body 5 about A = (xa, ya)) and to body 6 (E = G + zf e(Omega +
    epsilon), G = A + u f(epsilon) on body 7 about A), with e(a) = (cos a, sin a) and
    f(a) = (sin a, -cos a). D = B + sd e(gamma) + sc f(gamma). Centres of mass: body 1 at
    ra from O, body 2 at da from P towards E, body 4 at ea from E towards F, body 6 at fa
    from E towards G; bodies 3, 5 and 7 turn about fixed points and only the distance of
    their centres from them enters the motion (sqrt(sa^2 + sb^2) etc.), placed here at
    (sa, -sb), (ta, tb) and (ua, ub) in their frames. Body k's frame is at its pivot on
    the ground or on the body before it, rotated by its absolute angle (`andrews_angles`
    gives back the test set's relative ones). The named point "E" is the common pin."""
    p = ANDREWS
    beta, theta, gamma, phi, delta, omega, epsilon = ANDREWS_ANGLES0
    a1, a2, a3, a4, a5, a6, a7 = beta, beta + theta, gamma, phi + delta, delta, omega + epsilon, epsilon
    origin = np.zeros(2)
    A = np.array([p["xa"], p["ya"]])
    B = np.array([p["xb"], p["yb"]])
    C = np.array([p["xc"], p["yc"]])
    P = origin + p["rr"] * _e(a1)
    E = P - p["d"] * _e(a2)
    F = A + p["zt"] * _e(a5)
    G = A + p["u"] * _perp(a7)
    D = B + p["sd"] * _e(a3) + p["sc"] * _perp(a3)

    def local(origin: np.ndarray, angle: float, u: tuple[float, float]) -> tuple[float, float]:
        w = origin + u[0] * _e(angle) + u[1] * _e(angle + math.pi / 2)
        return (float(w[0]), float(w[1]))

    mass, inertia = p["m"], p["I"]
    m = Mechanism("Andrews' squeezing mechanism")
    frames = [(origin, a1, (p["ra"], 0.0)), (P, a2, (-p["da"], 0.0)), (B, a3, (p["sa"], -p["sb"]))]
    frames += [(F, a4, (0.0, -(p["e"] - p["ea"]))), (A, a5, (p["ta"], p["tb"]))]
    frames += [(G, a6, (p["zf"] - p["fa"], 0.0)), (A, a7, (p["ua"], p["ub"]))]
    bodies = []
    for k, (frame, angle, u_c) in enumerate(frames):
        bodies.append(
            m.body(
                f"body{k + 1}",
                tuple(frame),
                angle,
                mass=mass[k],
                inertia=inertia[k],
                com=local(frame, angle, u_c),
            )  # fmt: skip
        )
    b1, b2, b3, b4, b5, b6, b7 = bodies
    at = {"O": origin, "P": P, "E": E, "B": B, "A": A, "F": F, "G": G}
    pins = [("O", m.ground, b1), ("P", b1, b2), ("B", m.ground, b3), ("E3", b2, b3)]
    pins += [("A5", m.ground, b5), ("F", b5, b4), ("E4", b2, b4)]
    pins += [("A7", m.ground, b7), ("G", b7, b6), ("E6", b2, b6)]
    for name, body_a, body_b in pins:
        m.revolute(body_a, body_b, at=tuple(at[name[0]]), name=name)
    m.spring(m.ground, tuple(C), b3, tuple(D), stiffness=p["c0"], free_length=p["l0"], name="spring")
    m.torque(b1, Constant(p["mom"]), name="mom")
    m.point("E", b2, tuple(E))
    return Benchmark(m, np.zeros(21), 0.03, "E")
