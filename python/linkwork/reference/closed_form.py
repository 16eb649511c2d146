"""Textbook closed-form kinematics of the four-bar and the offset slider-crank.

Vector-loop solutions in the notation of R. L. Norton, *Design of Machinery*
(chapters 4, 6 and 7): link lengths a (crank), b (coupler), c (rocker), d (ground),
link angles theta2, theta3, theta4 measured counter-clockwise from the +x axis.
They know nothing of the Newton formulation and serve as its independent check.
All functions are vectorised over theta2, omega2 and alpha2 (NumPy broadcasting).
Units: lengths in any one unit, angles in radians, rates in rad/s and rad/s^2.
"""

from __future__ import annotations

import numpy as np

__all__ = ["four_bar", "slider_crank"]


def _branch_sign(branch: str) -> float:
    if branch == "open":
        return -1.0
    if branch == "crossed":
        return 1.0
    raise ValueError(f"branch must be 'open' or 'crossed', not {branch!r}")


def four_bar(
    ground: float,
    crank: float,
    coupler: float,
    rocker: float,
    theta2,
    omega2,
    alpha2=0.0,
    branch: str = "open",
) -> dict[str, np.ndarray]:
    """Pin-jointed four-bar: O2 = (0, 0), O4 = (ground, 0); crank O2->A at theta2,
    coupler A->B at theta3, rocker O4->B at theta4.

    Position (Norton eqs. 4.10 and 4.13, Freudenstein's K1..K5): from the loop
    a e^{i theta2} + b e^{i theta3} - c e^{i theta4} - d = 0,
        theta4 = 2 atan2(-B -+ sqrt(B^2 - 4AC), 2A),
        theta3 = 2 atan2(-E -+ sqrt(E^2 - 4DF), 2D),
    upper sign for the open branch. Velocity (eq. 6.18) and acceleration (eq. 7.12) from
    the loop differentiated once and twice.

    Returns theta3, omega3, alpha3, theta4, omega4, alpha4 (angles in (-2 pi, 2 pi]).
    Raises ``ValueError`` where the linkage cannot be assembled.
    """
    a, b, c, d = float(crank), float(coupler), float(rocker), float(ground)
    theta2, omega2, alpha2 = np.broadcast_arrays(
        np.asarray(theta2, dtype=float), np.asarray(omega2, dtype=float), np.asarray(alpha2, dtype=float)
    )
    sign = _branch_sign(branch)
    c2, s2 = np.cos(theta2), np.sin(theta2)

    # position: Freudenstein's constants
    K1 = d / a
    K2 = d / c
    K3 = (a * a - b * b + c * c + d * d) / (2.0 * a * c)
    K4 = d / b
    K5 = (c * c - d * d - a * a - b * b) / (2.0 * a * b)
    A = c2 - K1 - K2 * c2 + K3
    B = -2.0 * s2
    C = K1 - (K2 + 1.0) * c2 + K3
    D = c2 - K1 + K4 * c2 + K5
    E = -2.0 * s2
    F = K1 + (K4 - 1.0) * c2 + K5
    disc4 = B * B - 4.0 * A * C
    disc3 = E * E - 4.0 * D * F
    if np.any(disc4 < 0.0) or np.any(disc3 < 0.0):
        raise ValueError("the four-bar cannot be assembled at some crank angle (complex roots)")
    theta4 = 2.0 * np.arctan2(-B + sign * np.sqrt(disc4), 2.0 * A)
    theta3 = 2.0 * np.arctan2(-E + sign * np.sqrt(disc3), 2.0 * D)

    # velocity
    omega3 = a * omega2 / b * np.sin(theta4 - theta2) / np.sin(theta3 - theta4)
    omega4 = a * omega2 / c * np.sin(theta2 - theta3) / np.sin(theta4 - theta3)

    # acceleration: A alpha4 - B alpha3 = C and D alpha4 - E alpha3 = F (Norton 7.12)
    c3, s3, c4, s4 = np.cos(theta3), np.sin(theta3), np.cos(theta4), np.sin(theta4)
    Aa = c * s4
    Ba = b * s3
    Ca = a * alpha2 * s2 + a * omega2**2 * c2 + b * omega3**2 * c3 - c * omega4**2 * c4
    Da = c * c4
    Ea = b * c3
    Fa = a * alpha2 * c2 - a * omega2**2 * s2 - b * omega3**2 * s3 + c * omega4**2 * s4
    alpha3 = (Ca * Da - Aa * Fa) / (Aa * Ea - Ba * Da)
    alpha4 = (Ca * Ea - Ba * Fa) / (Aa * Ea - Ba * Da)
    return {
        "theta3": theta3,
        "omega3": omega3,
        "alpha3": alpha3,
        "theta4": theta4,
        "omega4": omega4,
        "alpha4": alpha4,
    }


def slider_crank(
    crank: float,
    rod: float,
    offset: float,
    theta2,
    omega2,
    alpha2=0.0,
    branch: str = "open",
) -> dict[str, np.ndarray]:
    """Offset slider-crank: crank pivot at the origin, crank O2->A at theta2, rod A->B at
    theta3, slider pin B = (x, offset) moving along x.

    Loop a e^{i theta2} + b e^{i theta3} = x + i c (a crank, b rod, c offset):
        y: a sin theta2 + b sin theta3 = c  ->  theta3 = asin((c - a sin theta2) / b)
        (open: slider on the +x side, cos theta3 > 0; crossed: theta3 = pi - that),
        x = a cos theta2 + b cos theta3,
        omega3 = -a omega2 cos theta2 / (b cos theta3), v = -a omega2 sin theta2 - b omega3 sin theta3,
        alpha3 = (a omega2^2 sin theta2 - a alpha2 cos theta2 + b omega3^2 sin theta3) / (b cos theta3),
        a_B = -a alpha2 sin theta2 - a omega2^2 cos theta2 - b alpha3 sin theta3 - b omega3^2 cos theta3.

    Returns theta3, omega3, alpha3, x, v, a. Raises ``ValueError`` where the rod cannot reach.
    """
    ra, rb, c = float(crank), float(rod), float(offset)
    theta2, omega2, alpha2 = np.broadcast_arrays(
        np.asarray(theta2, dtype=float), np.asarray(omega2, dtype=float), np.asarray(alpha2, dtype=float)
    )
    sign = _branch_sign(branch)
    c2, s2 = np.cos(theta2), np.sin(theta2)
    sin3 = (c - ra * s2) / rb
    if np.any(np.abs(sin3) > 1.0):
        raise ValueError("the slider-crank cannot be assembled at some crank angle (rod too short)")
    theta3 = np.arcsin(sin3)
    if sign > 0:  # crossed: slider on the -x side
        theta3 = np.pi - theta3
    c3, s3 = np.cos(theta3), np.sin(theta3)
    x = ra * c2 + rb * c3
    omega3 = -ra * omega2 * c2 / (rb * c3)
    v = -ra * omega2 * s2 - rb * omega3 * s3
    alpha3 = (ra * omega2**2 * s2 - ra * alpha2 * c2 + rb * omega3**2 * s3) / (rb * c3)
    acc = -ra * alpha2 * s2 - ra * omega2**2 * c2 - rb * alpha3 * s3 - rb * omega3**2 * c3
    return {"theta3": theta3, "omega3": omega3, "alpha3": alpha3, "x": x, "v": v, "a": acc}
