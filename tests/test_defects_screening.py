"""The four-bar screening (`FourBarDesign.defects`) on designs built from known four-bars
whose defects are known by construction: precision positions taken from the linkage's
own poses, some from the other assembly (a circuit defect), some out of the order the
input meets them (an order defect), some beyond a dead point of a rocking input (a branch
defect), each at an early and at a late position.

The screening is Python (`synthesis._screen` over an engine sweep): only pytest checks it."""

import math

import numpy as np
import pytest

from linkwork.synthesis import FourBarDesign

# coupler point P in the coupler's frame (x along A -> B)
P_LOCAL = np.array([0.12, 0.07])
CRANK_ROCKER = (0.35, 0.12, 0.30, 0.25)  # ground, crank, coupler, rocker: Grashof, crank turns
TRIPLE_ROCKER = (0.40, 0.30, 0.25, 0.20)  # non-Grashof: the crank rocks within +-1.371 rad


def pose(dims, phi: float, circuit: int):
    """A, B, P and the coupler angle at crank angle phi, by circle intersection; circuit
    +1 / -1 picks B on either side of the line A -> O4."""
    g, a, b, c = dims
    A = a * np.array([math.cos(phi), math.sin(phi)])
    O4 = np.array([g, 0.0])
    d = O4 - A
    L = float(np.hypot(*d))
    assert abs(b - c) < L < b + c, f"no assembly at crank angle {phi}"
    along = (b * b - c * c + L * L) / (2 * L)
    h = math.sqrt(b * b - along * along)
    u = d / L
    B = A + along * u + circuit * h * np.array([-u[1], u[0]])
    th = math.atan2(B[1] - A[1], B[0] - A[0])
    rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    return A, B, A + rot @ P_LOCAL, th


def design(dims, phis, circuits) -> FourBarDesign:
    """The design whose precision positions are the coupler poses at crank angles `phis`
    on `circuits` (position 1 defines the design's circuit)."""
    poses = [pose(dims, p, s) for p, s in zip(phis, circuits)]
    A, B, P, th1 = poses[0]
    return FourBarDesign(
        o2=np.zeros(2),
        a=A,
        o4=np.array([dims[0], 0.0]),
        b=B,
        p=P,
        positions=np.array([q[2] for q in poses]),
        coupler_angles=np.array([q[3] - th1 for q in poses]),
        input_angles=None,
        dyads=(),  # type: ignore[arg-type]
    )


PHIS = [0.0, 0.6, 1.2, 1.8, 2.4]


def test_positions_on_the_drawn_circuit_in_order_are_defect_free():
    f = design(CRANK_ROCKER, PHIS, [1] * 5).defects
    assert f.ok and f.reached == (True,) * 5
    assert max(f.error) < 1e-9


@pytest.mark.parametrize("other", [1, 4])  # an early and the last position
def test_a_position_from_the_other_assembly_is_a_circuit_defect_wherever_it_lies(other):
    circuits = [1] * 5
    circuits[other] = -1
    f = design(CRANK_ROCKER, PHIS, circuits).defects
    assert f.circuit and not f.ok and not f.order and not f.branch
    assert f.reached == tuple(j != other for j in range(5))
    assert "circuit" in str(f)


@pytest.mark.parametrize(
    "phis",
    [
        [0.0, 1.8, 0.6, 2.4, 3.0],  # positions 2 and 3 swapped
        [0.0, 0.6, 1.2, 3.0, 2.4],  # the last two swapped
    ],
)
def test_positions_out_of_the_inputs_order_are_an_order_defect(phis):
    f = design(CRANK_ROCKER, phis, [1] * 5).defects
    assert f.order and not f.ok


@pytest.mark.parametrize(
    ("phis", "reached"),
    [
        # met in order only turning the input back (0, 0.5 -> 2 pi - 0.5, 0.2 -> 2 pi -
        # 0.2), which runs into the dead point at -1.371 before position 2
        ([0.0, 0.5, 0.2], (True, False, False)),
        # turning back meets positions 2 and 3, then the dead point before the last
        ([0.0, -0.2, -0.5, 0.4], (True, True, True, False)),
    ],
)
def test_a_position_beyond_a_dead_point_is_a_branch_defect(phis, reached):
    f = design(TRIPLE_ROCKER, phis, [1] * len(phis)).defects
    assert f.branch and not f.ok and not f.order
    assert f.direction == -1
    assert f.reached == reached
    assert len(f.dead_points) >= 1 and f.dead_points[0] == pytest.approx(-1.371 - 0.0, abs=2e-3)


def law_of_cosines_mu(dims, phi):
    """The angle at B (deg) at crank angle phi, from |A - O4| in the triangle O2-A-O4."""
    g, a, b, c = dims
    d2 = g * g + a * a - 2 * g * a * np.cos(phi)
    return np.degrees(np.arccos((b * b + c * c - d2) / (2 * b * c)))


@pytest.mark.parametrize(
    "dims",
    [CRANK_ROCKER, (0.39, 0.09, 0.25, 0.25)],  # worst near 0 deg; worst near 180 deg
)
def test_transmission_range_over_the_swept_positions_is_the_law_of_cosines(dims):
    # over crank angles 0..3 the angle at B rises with the crank angle (cos falls): its
    # extremes at the first and the last position
    phis = [0.0, 1.0, 2.0, 3.0]
    f = design(dims, phis, [1] * 4).defects
    lo, hi = law_of_cosines_mu(dims, np.array([phis[0], phis[-1]]))
    assert f.transmission == pytest.approx((lo, hi), abs=1e-6)
    assert f.worst_transmission == pytest.approx(min(lo, 180.0 - hi), abs=1e-6)


@pytest.mark.parametrize(
    ("dims", "kind"),
    [(CRANK_ROCKER, "Grashof"), (TRIPLE_ROCKER, "non-Grashof"), ((0.30, 0.10, 0.30, 0.10), "change point")],
)
def test_grashof_type_and_link_ratio_of_a_design(dims, kind):
    f = design(dims, [0.5, 1.0, 1.3], [1] * 3).defects
    assert f.grashof == kind
    assert f.length_ratio == pytest.approx(max(dims) / min(dims), rel=1e-12)
