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


def parallelogram(with_middle: bool, masses: bool = False) -> lw.Mechanism:
    """The triple crank with or without its middle crank, for comparisons."""
    m = triple_crank()
    if not with_middle:
        m.remove("O_middle")
        m.remove("T_middle")
        m._bodies = [b for b in m._bodies if b["name"] != "middle"]
    if masses:
        m.set_mass("crank", 0.5, inertia=0.002)
        m.set_mass("coupler", 1.2, inertia=0.01)
        m.set_mass("rocker", 0.5, inertia=0.002)
        m.set_gravity((0.0, -9.81))
    return m


def test_redundant_model_solved_anyway_moves_like_the_parallelogram():
    model = triple_crank().compile(redundant="solve")
    assert model.linear == "least_squares" and model.n_rows == model.n_coords + 1
    # the joints in the dependency are named: their reactions are not unique
    assert {"O_middle", "T_middle"} <= set(model.indeterminate)
    times = np.linspace(0.0, 2 * np.pi, 721)
    res = model.sweep(times)
    # a parallelogram: every crank turns with the driver, the coupler translates. It
    # passes its change points (cranks along the ground line) at theta = 0 and pi, where
    # the rates lose digits as 1 / pivot ratio (velocity) and its square (acceleration), as
    # they do for the plain two-crank parallelogram (measured: error x ratio ~ 7e-14)
    ratio = res.pivot_ratio
    for crank in ("crank", "middle", "rocker"):
        b = res.body(crank)
        assert np.allclose(b.theta, 0.6 + times, rtol=0, atol=1e-12)
        assert np.all(np.abs(b.thetad - 1.0) <= 2e-13 / ratio)
        assert np.all(np.abs(b.thetadd) <= 2e-13 / ratio**2)
    c = res.body("coupler")
    assert np.abs(c.theta).max() < 1e-12 and np.all(np.abs(c.thetad) <= 2e-13 / ratio)
    assert np.allclose(c.x, 0.1 * np.cos(0.6 + times), rtol=0, atol=1e-13)
    assert res.residual.max() <= 1e-12


def test_redundant_driver_effort_is_unique_and_reactions_are_flagged():
    # a massless middle crank adds no load: the crank torque is the parallelogram's
    times = np.linspace(0.0, 2 * np.pi, 181)
    three = parallelogram(True, masses=True).compile(redundant="solve").sweep(times, forces=True)
    two = parallelogram(False, masses=True).compile().sweep(times, forces=True)
    top = np.abs(two.effort("crank_angle")).max()
    assert np.allclose(three.effort("crank_angle"), two.effort("crank_angle"), rtol=0, atol=1e-10 * top)
    # the net force of the three ground pins on the cranks is unique too
    net3 = sum(three.reaction(n).force for n in ("O_crank", "O_middle", "O_rocker"))
    net2 = sum(two.reaction(n).force for n in ("O_crank", "O_rocker"))
    assert np.allclose(net3, net2, rtol=0, atol=1e-10 * np.abs(net2).max())
    assert "not unique" in three.forces_summary()


def test_near_redundant_geometry_is_still_refused_with_solve():
    with pytest.raises(lw.ModelError, match="locked"):
        triple_crank(out_of_parallel=1e-3).compile(redundant="solve")


def test_a_redundant_driver_is_refused_even_with_solve():
    m = examples.four_bar()
    m.drive_angle("rocker", lw.Constant(1.0), name="second")
    with pytest.raises(lw.ModelError):
        m.compile(redundant="solve")


def test_redundant_error_mentions_the_drop_option():
    with pytest.raises(lw.ModelError, match='redundant="solve"'):
        triple_crank().compile()
