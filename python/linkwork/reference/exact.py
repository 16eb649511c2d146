"""Exact and published solutions of the forward-dynamics benchmarks
(`linkwork.mechanism.benchmarks` builds the problems).

- IFToMM A01, the simple pendulum released at rest from (L, 0): in Jacobi elliptic
  functions of parameter m = 1/2, u = sqrt(g/L) t + K(1/2),
  x = sqrt(2) L sn(u) dn(u), y = -L cn(u)^2 (energy: v^2 = -2 g y, and the angle from the
  downward vertical obeys sin(psi/2) = sn(u) / sqrt(2)).
- IFToMM A02, the N-four-bar: on its branch every crank keeps the angle phi of crank 0
  and the couplers translate, so T = 1/2 (N + 1) (m L^2 / 3) phid^2 + 1/2 N m L^2 phid^2
  and V = (N + 1) m g (L/2) sin phi + N m g L sin phi; Lagrange's equation is
  phidd = -c (g / L) cos phi with c = 1.5 (3N + 1) / (4N + 1). That scalar ODE is
  integrated with DOP853 at rtol 1e-13 (and its dense output kept).
- Andrews' squeezer: the test set's parameters, initial angles, the published angles at
  t = 0.03 (PSIDE, rtol = atol = 1e-14) and its accuracy measure scd.

Sources: the IFToMM multibody benchmark library (A01, A02); the Bari/CWI IVP test set,
problem "andrews"; E. Hairer, G. Wanner, Solving ODEs II, VII.7.

>>> x, y = pendulum_tip([0.0, 1.0])
>>> [round(float(v), 12) + 0.0 for v in (x[0], y[0], np.hypot(x[1], y[1]))]
[1.0, 0.0, 1.0]
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = [
    "pendulum_tip",
    "FourBarBranch",
    "n_four_bar_branch",
    "ANDREWS",
    "ANDREWS_ANGLES0",
    "ANDREWS_REFERENCE",
    "ANDREWS_T_END",
    "scd",
]

G = 9.81


def pendulum_tip(
    t: Any, length: float = 1.0, g: float = G, velocity: bool = False
) -> tuple[np.ndarray, np.ndarray] | tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """IFToMM A01's tip (x, y) at times ``t``, released at rest from (length, 0) under
    gravity (0, -g); with ``velocity``, also (vx, vy) (from d sn/du = cn dn,
    d cn/du = -sn dn, d dn/du = -m sn cn)."""
    from scipy.special import ellipj, ellipk

    t = np.asarray(t, dtype=float)
    w = math.sqrt(g / length)
    u = w * t + ellipk(0.5)
    sn, cn, dn, _ = ellipj(u, 0.5)
    x = math.sqrt(2.0) * length * sn * dn
    y = -length * cn**2
    if not velocity:
        return x, y
    vx = math.sqrt(2.0) * length * w * (cn * dn * dn - 0.5 * sn * sn * cn)
    vy = 2.0 * length * w * cn * sn * dn
    return x, y, vx, vy


class FourBarBranch:
    """IFToMM A02's exact branch: phi(t) of every crank, from phi(0) = pi/2,
    phid(0) = -omega0 (default 1 rad/s clockwise), integrated once over [0, t_end] with
    DOP853 at ``rtol`` (atol ``rtol`` x 1e-2), dense output kept.

    ``phi(t)`` -> (phi, phid); ``tip(t)`` -> B0's (x, y, vx, vy) = L (cos phi, sin phi,
    -sin phi phid, cos phi phid); ``energy`` the invariant 1/2 phid^2 + c (g/L) sin phi."""

    def __init__(
        self,
        n: int,
        t_end: float = 20.0,
        length: float = 1.0,
        g: float = G,
        omega0: float = 1.0,
        rtol: float = 1e-13,
    ) -> None:
        from scipy.integrate import solve_ivp

        self.n, self.length, self.g = int(n), float(length), float(g)
        self.c = 1.5 * (3 * n + 1) / (4 * n + 1)
        k = self.c * g / length

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            return np.array([y[1], -k * math.cos(y[0])])

        y0 = np.array([math.pi / 2.0, -float(omega0)])
        self._solution = solve_ivp(
            rhs, (0.0, float(t_end)), y0, method="DOP853", rtol=rtol, atol=rtol * 1e-2, dense_output=True
        )
        if not self._solution.success:
            raise RuntimeError(f"the A02 branch ODE failed: {self._solution.message}")
        self.t_end = float(t_end)
        self._k = k

    def phi(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """(phi, phid) at times ``t`` (within [0, t_end])."""
        t = np.asarray(t, dtype=float)
        if np.any(t < 0.0) or np.any(t > self.t_end):
            raise ValueError(f"times must lie in [0, {self.t_end}]")
        y = self._solution.sol(t)
        return y[0], y[1]

    def tip(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """B0 (the tip of crank 0): x, y, vx, vy at times ``t``."""
        phi, phid = self.phi(t)
        L = self.length
        return L * np.cos(phi), L * np.sin(phi), -L * np.sin(phi) * phid, L * np.cos(phi) * phid

    def energy(self, t: Any) -> np.ndarray:
        """1/2 phid^2 + c (g/L) sin phi, constant on the exact solution."""
        phi, phid = self.phi(t)
        return 0.5 * phid**2 + self._k * np.sin(phi)


def n_four_bar_branch(n: int, t_end: float = 20.0, **options: Any) -> FourBarBranch:
    """The exact branch of the N-four-bar (`FourBarBranch`)."""
    return FourBarBranch(n, t_end, **options)


# --- Andrews' squeezing mechanism -----------------------------------------------------------

#: the test set's parameters (SI units; no gravity)
ANDREWS: dict[str, Any] = {
    "m": [0.04325, 0.00365, 0.02373, 0.00706, 0.0705, 0.00706, 0.05498],
    "I": [2.194e-06, 4.41e-07, 5.255e-06, 5.667e-07, 1.169e-05, 5.667e-07, 1.912e-05],
    "xa": -0.06934, "ya": -0.00227, "xb": -0.03635, "yb": 0.03273, "xc": 0.014, "yc": 0.072,
    "d": 0.028, "da": 0.0115, "e": 0.02, "ea": 0.01421, "rr": 0.007, "ra": 0.00092,
    "ss": 0.035, "sa": 0.01874, "sb": 0.01043, "sc": 0.018, "sd": 0.02, "ta": 0.02308,
    "tb": 0.00916, "u": 0.04, "ua": 0.01228, "ub": 0.00449, "zf": 0.02, "zt": 0.04,
    "fa": 0.01421, "mom": 0.033, "c0": 4530.0, "l0": 0.07785,
}  # fmt: skip

#: the test set's initial angles (beta, Theta, gamma, Phi, delta, Omega, epsilon); at rest
ANDREWS_ANGLES0 = (
    -0.0617138900142764496358948458001,
    0.0,
    0.455279819163070380255912382449,
    0.222668390165885884674473185609,
    0.487364979543842550225598953530,
    -0.222668390165885884674473185609,
    1.23054744454982119249735015568,
)

ANDREWS_T_END = 0.03

#: the published angles at t = 0.03 (PSIDE, rtol = atol = 1e-14)
ANDREWS_REFERENCE = np.array(
    [
        15.81077119629904,
        -15.75637105984298,
        0.04082224013073101,
        -0.5347301163226948,
        0.5244099658805303,
        0.5347301163226948,
        1.048080741042263,
    ]
)


def scd(angles: Any, reference: Any = ANDREWS_REFERENCE) -> float:
    """The test set's accuracy: -log10 of the largest relative error over the components
    (the number of correct significant digits of the worst one)."""
    angles, reference = np.asarray(angles, dtype=float), np.asarray(reference, dtype=float)
    error = float(np.max(np.abs((angles - reference) / reference)))
    return math.inf if error == 0.0 else -math.log10(error)
