"""Degrees of freedom two ways, redundant and near-redundant mechanisms."""

import numpy as np
import pytest

import linkwork as lw
from linkwork import examples


def triple_crank(out_of_parallel: float = 0.0, driven: bool = True, scale: float = 1.0) -> lw.Mechanism:
    """A parallelogram (ground = coupler = 0.3, cranks 0.1) with a third crank between
    them at x = 0.15, turned ``out_of_parallel`` rad from parallel (same length)."""
    th = 0.6
    r = 0.1 * scale
    m = lw.Mechanism("triple crank")
    for name, x0 in (("crank", 0.0), ("middle", 0.15 * scale), ("rocker", 0.3 * scale)):
        m.body(name, (x0, 0.0), th)
    a = np.array([r * np.cos(th), r * np.sin(th)])
    m.body("coupler", tuple(a), 0.0)
    for name, x0 in (("crank", 0.0), ("middle", 0.15 * scale), ("rocker", 0.3 * scale)):
        tip = a + (x0, 0.0)
        pivot = (x0, 0.0)
        if name == "middle":
            # the middle crank turned about its tip: no longer parallel to the others
            d = th + out_of_parallel
            pivot = tuple(tip - r * np.array([np.cos(d), np.sin(d)]))
        m.revolute("ground", name, pivot, name=f"O_{name}")
        m.revolute(name, "coupler", tuple(tip), name=f"T_{name}")
    if driven:
        m.drive_angle("crank", lw.Linear(th, 1.0), name="crank_angle")
    return m


def test_textbook_mechanisms_agree_two_ways():
    textbook = (examples.four_bar, examples.slider_crank, examples.six_bar_watt, examples.six_bar_stephenson)
    for build in textbook:
        mob = build().compile().mobility()
        assert mob.gruebler_dof == mob.dof == 1 and mob.gruebler_dof_driven == mob.dof_driven == 0
        assert not mob.redundant and mob.explanation == ()


def test_a_third_parallel_crank_is_redundant_and_named():
    with pytest.raises(lw.ModelError, match="13 constraint rows for 12 coordinates") as info:
        triple_crank().compile()
    msg = str(info.value)
    assert "redundant" in msg and "O_middle" in msg and "T_middle" in msg
    # without a driver it compiles (12 rows): Gruebler says a structure, the rank says 1
    mob = triple_crank(driven=False).compile().mobility(assemble=False)
    assert (mob.gruebler_dof, mob.dof, mob.rank_joints) == (0, 1, 11)
    ((sigma, who),) = mob.redundancies
    assert sigma < 1e-12 * mob.singular_values[0]
    assert {"O_crank", "O_middle", "O_rocker"} & {n for n, _ in who}
    assert any("Gruebler counts 0" in e for e in mob.explanation)
    # the free motion turns the cranks together
    (motion,) = mob.free_motions
    assert {"crank.theta", "middle.theta", "rocker.theta"} <= {c for c, _ in motion}


def test_a_third_crank_out_of_parallel_is_a_locked_structure():
    with pytest.raises(lw.ModelError, match="locked") as info:
        triple_crank(out_of_parallel=1e-3).compile()
    msg = str(info.value)
    assert "redundant" not in msg
    # its nearest dependency: a singular value of the order of the misfit
    sigma = float(msg.split("singular value ")[1].split(")")[0])
    # scaled by L = 0.36 m: the 1e-3 rad turn of a 0.1 m crank misfits by about 1e-4
    assert 1e-5 < sigma < 1e-3
    mob = triple_crank(out_of_parallel=1e-3, driven=False).compile().mobility(assemble=False)
    assert (mob.gruebler_dof, mob.dof) == (0, 0) and not mob.redundant
    assert mob.nearest is not None and mob.nearest[0] == pytest.approx(mob.singular_values[-1])


def test_a_doubled_pin_is_found():
    m = examples.four_bar()
    at = m.to_dict()["joints"][1]["at"]
    m.revolute("crank", "coupler", at, name="A_again")
    with pytest.raises(lw.ModelError, match="redundant") as info:
        m.compile()
    assert "A_again" in str(info.value) and "'A'" in str(info.value)


def test_mobility_does_not_depend_on_units():
    a = triple_crank(driven=False, scale=1.0).compile().mobility(assemble=False)
    b = triple_crank(driven=False, scale=1000.0).compile().mobility(assemble=False)
    assert (a.rank, a.dof) == (b.rank, b.dof)
    top = a.singular_values[0]
    assert np.allclose(a.singular_values[:-1], b.singular_values[:-1], rtol=1e-10, atol=1e-12 * top)
