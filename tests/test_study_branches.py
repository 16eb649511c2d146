"""Every design of a study on the branch it is asked for: the assembly mode of the model
the study varies, never the one Newton from the base's drawing (variants) or a redraw
carried across a toggle (redrawn designs) happens to reach. Checked against each design's
own closed form, across the Grashof limits and far from the nominal design."""

from __future__ import annotations

import numpy as np
import pytest

import linkwork as lw
from linkwork import closed_form as cf
from linkwork import study as S

GROUND, CRANK = 1.0, 0.3
TURN = np.linspace(0.0, 2.0 * np.pi, 181)


def _designs(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    # couplers and rockers from 0.3 to 1.6 with crank 0.3 and ground 1: crank-rockers,
    # triple rockers and designs at the Grashof limit s + l = p + q, most far from the
    # nominal (coupler 1, rocker 0.8); the ones that failed silently before lie here
    rng = np.random.default_rng(seed)
    return rng.uniform(0.3, 1.5, n), rng.uniform(0.3, 1.6, n)


def _rocker(coupler: float, rocker: float, branch: str) -> np.ndarray:
    """The rocker's angle over TURN by the closed form (Norton 4.10), NaN where the
    four-bar has no configuration."""
    a, b, c, d = CRANK, coupler, rocker, GROUND
    c2, s2 = np.cos(TURN), np.sin(TURN)
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2.0 * a * c)
    aa, bb, cc = c2 - k1 - k2 * c2 + k3, -2.0 * s2, k1 - (k2 + 1.0) * c2 + k3
    disc = bb * bb - 4.0 * aa * cc
    root = np.sqrt(np.where(disc >= 0.0, disc, np.nan))
    # the open circuit takes the minus root (the upper sign of Norton 4.10b, as `closed_form`)
    return 2.0 * np.arctan2(-bb + (-1.0 if branch == "open" else 1.0) * root, 2.0 * aa)


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * a)))


@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("variants", [True, False])
def test_every_design_takes_the_asked_circuit_against_its_closed_form(branch: str, variants: bool) -> None:
    """Each design's rocker angle equals its own closed form (Norton's, as
    `closed_form.four_bar`; NaN where it has no configuration) on the asked circuit at every
    step it reached (to 1e-9 rad; the sweep's error is ~1e-14), and no design that the
    closed form can assemble over the turn is lost. With the nominal's drawing (variants)
    or a redraw's continuation (variants=False) as the start and no branch enforced, 9 of
    the 2,000 variants and 2 of the 402 redrawn designs here came out on the other circuit
    with no error."""
    m = lw.build.four_bar(GROUND, CRANK, 1.0, 0.8, branch=branch, coupler_point=(0.5, 0.2), omega=1.0)
    study = lw.Study(m, TURN, ["angle rocker"])
    if variants:
        coupler, rocker = _designs(2000, seed=1)
    else:
        # redrawing compiles each design: every 10th of 4,000, and the two of them that a
        # redraw carried onto the crossed circuit before
        coupler, rocker = _designs(4000, seed=1)
        pick = np.union1d(np.arange(0, 4000, 10), [1799, 3267])
        coupler, rocker = coupler[pick], rocker[pick]
    result = study.run(S.listed({"length coupler": coupler, "length rocker": rocker}), variants=variants)
    angles = result.dataset["angle_rocker"].values
    errors = result.dataset["error"].values
    wrong, lost, checked = [], [], 0
    for i in range(len(coupler)):
        exact = _rocker(coupler[i], rocker[i], branch)
        reached = np.isfinite(angles[i])
        checked += int(reached.sum())
        if reached.any() and _wrapped(angles[i, reached] - exact[reached]).max() > 1e-9:
            wrong.append(i)
        if errors[i] and np.all(np.isfinite(exact)):
            lost.append(i)
    assert wrong == [], f"designs on an unasked branch: {wrong[:10]}"
    assert lost == [], f"designs the closed form assembles, reported failed: {lost[:10]}"
    assert checked > 100 * len(coupler)  # most designs turn fully: the check is not vacuous


def test_a_design_with_no_configuration_on_the_asked_branch_is_its_named_error() -> None:
    """A design whose coupler and rocker cannot reach across at the first time (0.3 + 0.3 <
    |A O4| = 0.7) fails with the engine's AssemblyError naming its dyad's joints, for
    variants and for redrawn designs alike; the good designs beside it are swept."""
    m = lw.build.four_bar(GROUND, CRANK, 1.0, 0.8, branch="open", omega=1.0)
    study = lw.Study(m, TURN, ["angle rocker"])
    designs = S.listed({"length coupler": [1.0, 0.3, 0.9], "length rocker": [0.8, 0.3, 0.85]})
    for variants in (True, False):
        result = study.run(designs, variants=variants)
        errors = list(result.dataset["error"].values)
        assert errors[0] == "" and errors[2] == "", errors
        assert "assemble" in errors[1], errors[1]
        if variants:
            assert "branch its model is drawn in" in errors[1] and "'B'" in errors[1], errors[1]
        assert np.isfinite(result.dataset["angle_rocker"].values[[0, 2]]).all()


def test_sweep_batch_starts_each_model_on_the_branch_of_the_one_given() -> None:
    """`sweep_batch(..., branches_of=base)`: a model drawn on the crossed circuit of a design
    is started on the base's open one; without it, it stays on its own drawing's."""
    base = lw.build.four_bar(GROUND, CRANK, 1.0, 0.8, branch="open", omega=1.0).compile()
    crossed = lw.build.four_bar(GROUND, CRANK, 0.9, 0.85, branch="crossed", omega=1.0).compile()
    own, asked = (lw.sweep_batch([crossed], TURN, derivatives=0, branches_of=b)[0] for b in (None, base))
    for res, branch in ((own, "crossed"), (asked, "open")):
        exact = cf.four_bar(GROUND, CRANK, 0.9, 0.85, TURN, 1.0, branch=branch)["theta4"]
        assert _wrapped(res.body("rocker").theta - exact).max() < 1e-9
    with pytest.raises(lw.InputError, match="branches_of"):
        lw.sweep_batch([crossed], TURN, branches_of="base")
