"""Transmission angles of slider-cranks (several offsets, both circuits) and four-bars
against the closed form / the law of cosines at every step and at the extremes.

The per-step arrays (`Results.transmission_angle`, computed in Python by
`Linkage.transmission_angle_of`) are checked only here, by pytest; the Rust summaries
(`Model.linkages`) are checked here at sampled states and by cargo at every step
(crates/linkwork/tests/engine/transmission_angles.rs)."""

import math

import numpy as np
import pytest

from linkwork import examples

CRANK, ROD = 0.1, 0.35


def slider_crank_mu(offset: float, theta: np.ndarray) -> np.ndarray:
    """The angle between the rod and the slide's normal: the rod's component across the
    slide (the pin A's distance from the line y = offset) is |offset - r sin theta|."""
    return np.arccos(np.abs(offset - CRANK * np.sin(theta)) / ROD)


def revolution(offset: float) -> np.ndarray:
    """Crank angles over a turn with the extremes among them: +-pi/2 (worst) and where the
    rod lies along the slide, r sin theta = offset (pi/2, best)."""
    flat = math.asin(offset / CRANK)
    return np.unique(
        np.concatenate(
            [np.linspace(0.0, 2 * np.pi, 721), [np.pi / 2, 1.5 * np.pi, flat % (2 * np.pi), np.pi - flat]]
        )
    )


@pytest.mark.parametrize("offset", [0.0, 0.02, -0.05, 0.08])
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_slider_crank_transmission_angle_is_the_closed_form_at_every_step(offset, branch):
    theta = revolution(offset)
    model = examples.slider_crank(crank=CRANK, rod=ROD, offset=offset, omega=1.0).compile()
    res = model.sweep(theta, branch=branch)
    mu = res.transmission_angle()
    want = slider_crank_mu(offset, theta)
    assert np.allclose(mu, want, rtol=0, atol=1e-9)
    # worst with the crank normal to the slide on the offset's far side; best pi/2
    assert mu.min() == pytest.approx(math.acos((abs(offset) + CRANK) / ROD), abs=1e-9)
    assert mu.max() == pytest.approx(math.pi / 2, abs=1e-9)
    # the Rust summary at the extremes and at a few other states
    for k in [0, 100, 333, int(np.argmin(mu)), int(np.argmax(mu))]:
        (sc,) = model.linkages(q_guess=res.q[k], t=float(theta[k]))
        assert sc.circuit == branch
        assert sc.transmission_angle == pytest.approx(want[k], abs=1e-9)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_four_bar_transmission_angle_is_the_law_of_cosines_at_every_step(branch):
    g, a, b, c = 0.35, 0.20, 0.35, 0.25
    theta = np.linspace(0.0, 2 * np.pi, 721)
    model = examples.four_bar(g, a, b, c, omega=1.0).compile()
    res = model.sweep(theta, branch=branch)
    mu = res.transmission_angle()
    d2 = g * g + a * a - 2 * g * a * np.cos(theta)  # |A - O4|^2 in the triangle O2-A-O4
    want = np.arccos((b * b + c * c - d2) / (2 * b * c))
    assert np.allclose(mu, want, rtol=0, atol=1e-9)
    for k in [0, 180, 360, 500]:  # crank angles 0 and pi are the extremes
        (fb,) = model.linkages(q_guess=res.q[k], t=float(theta[k]))
        assert fb.circuit == branch
        assert fb.transmission_angle == pytest.approx(want[k], abs=1e-9)


@pytest.mark.parametrize("offset", [0.02, -0.05])
def test_slider_crank_transmission_angle_of_one_state_is_the_closed_form(offset):
    model = examples.slider_crank(crank=CRANK, rod=ROD, offset=offset, omega=1.0).compile()
    (sc,) = model.linkages()
    for theta in (0.3, 1.9, 4.4):
        state = model.solve(theta)
        assert float(sc.transmission_angle_of(state)) == pytest.approx(
            float(slider_crank_mu(offset, np.array(theta))), abs=1e-9
        )


def test_four_bar_transmission_angle_of_one_state_is_the_law_of_cosines():
    g, a, b, c = 0.35, 0.20, 0.35, 0.25
    model = examples.four_bar(g, a, b, c, omega=1.0).compile()
    (fb,) = model.linkages()
    for theta in (0.3, 1.9, 4.4):
        d2 = g * g + a * a - 2 * g * a * math.cos(theta)
        want = math.acos((b * b + c * c - d2) / (2 * b * c))
        assert float(fb.transmission_angle_of(model.solve(theta))) == pytest.approx(want, abs=1e-9)
