"""Structure: the groups of coordinates solved together, in solving order, from Phi_q's
pattern (block-triangular form), named as the textbooks do."""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from linkwork import examples


def kinds(mech: lw.Mechanism) -> list[tuple[str, tuple[str, ...]]]:
    return [(g.kind, g.bodies) for g in mech.compile().structure().groups]


def test_textbook_mechanisms_decompose_into_an_input_and_assur_dyads() -> None:
    assert kinds(examples.four_bar()) == [("input", ("crank",)), ("dyad RRR", ("coupler", "rocker"))]
    assert [k for k, _ in kinds(examples.slider_crank())] == ["input", "dyad RRP"]
    for six in (examples.six_bar_watt(), examples.six_bar_stephenson()):
        assert [k for k, _ in kinds(six)] == ["input", "dyad RRR", "dyad RRR"]


def test_every_row_and_coordinate_lands_in_exactly_one_group_in_dependency_order() -> None:
    mech = examples.six_bar_stephenson()
    model = mech.compile()
    s = model.structure()
    coords = [c for g in s.groups for c in g.coordinates]
    assert sorted(coords) == sorted(model.columns) and not s.redundant and not s.free
    # a group's constraints touch only bodies of this group or of earlier ones
    known: set[str] = set()
    desc = mech.to_dict()
    bodies_of = {j["name"]: {j["body_a"], j["body_b"]} - {"ground"} for j in desc["joints"]}
    bodies_of |= {d["name"]: {d["body"]} for d in desc["drivers"]}
    for g in s.groups:
        known |= set(g.bodies)
        for name in g.constraints:
            assert bodies_of[name] <= known, (g, name)


def triad_six_bar() -> lw.Mechanism:
    """A class-III six-bar: a crank, and a ternary link T held by three binary links, one
    to the crank's end and two to the ground: T and its three links (four bodies, six
    pins) can only be placed together."""
    m = lw.Mechanism("triad")
    o1, a = (0.0, 0.0), (0.1, 0.05)
    t1, t2, t3 = (0.35, 0.25), (0.55, 0.2), (0.45, 0.4)
    o2, o3 = (0.7, -0.05), (0.8, 0.55)
    crank = m.link("crank", o1, a)
    b1 = m.link("b1", a, t1)
    tern = m.body("ternary", origin=t1)
    b2 = m.link("b2", t2, o2)
    b3 = m.link("b3", t3, o3)
    m.revolute(m.ground, crank, at=o1, name="O1")
    m.revolute(crank, b1, at=a, name="A")
    m.revolute(b1, tern, at=t1, name="T1")
    m.revolute(tern, b2, at=t2, name="T2")
    m.revolute(b2, m.ground, at=o2, name="O2")
    m.revolute(tern, b3, at=t3, name="T3")
    m.revolute(b3, m.ground, at=o3, name="O3")
    m.drive_angle(crank, lw.Linear(math.atan2(a[1], a[0]), 1.0), name="crank_angle")
    return m


def test_a_class_three_mechanism_is_an_input_and_a_triad() -> None:
    assert kinds(triad_six_bar()) == [("input", ("crank",)), ("triad", ("b1", "ternary", "b2", "b3"))]
    # and it sweeps: the structure is read from the model the engine solves
    res = triad_six_bar().compile().sweep(np.linspace(0, 0.5, 6), derivatives=0)
    assert np.all(np.isfinite(res.q))


def test_redundant_rows_and_undriven_freedoms_are_named() -> None:
    # a parallelogram with a third crank: by its pattern the driven parallelogram places
    # the coupler, and the third crank, pinned to the ground and to the coupler, has one
    # row too many; only the special geometry lets it move (mobility's rank)
    m = lw.Mechanism("parallelogram")
    crank = m.link("crank", (0, 0), (0, 1))
    rocker = m.link("rocker", (2, 0), (2, 1))
    cpl = m.link("coupler", (0, 1), (2, 1))
    extra = m.link("extra", (1, 0), (1, 1))
    m.revolute(m.ground, crank, at=(0, 0), name="O2")
    m.revolute(crank, cpl, at=(0, 1), name="A")
    m.revolute(cpl, rocker, at=(2, 1), name="B")
    m.revolute(rocker, m.ground, at=(2, 0), name="O4")
    m.revolute(m.ground, extra, at=(1, 0), name="E0")
    m.revolute(extra, cpl, at=(1, 1), name="E1")
    m.drive_angle(crank, lw.Linear(math.pi / 2, 1.0), name="turn")
    model = m.compile(redundant="solve")
    s = model.structure()
    assert [g.kind for g in s.groups] == ["input", "dyad RRR", "one body"]
    assert s.redundant == ("E1",) and s.free == ()
    assert model.mobility().dof == 1
    # square but structurally singular: a link pinned at both ends (one row too many)
    # beside a link pinned at one end and not driven (its angle free)
    m = lw.Mechanism("square but singular")
    a = m.link("a", (0, 0), (1, 0))
    b = m.link("b", (2, 0), (3, 0))
    m.revolute(m.ground, a, at=(0, 0), name="O")
    m.revolute(m.ground, a, at=(1, 0), name="O_far")
    m.revolute(m.ground, b, at=(2, 0), name="P")
    s = m.compile(redundant="solve").structure()
    assert s.redundant == ("O_far",) and s.free == ("b.theta",)
    assert [g.kind for g in s.groups] == ["one body", "one body"]


def test_check_prints_the_structure(capsys) -> None:  # type: ignore[no-untyped-def]
    from pathlib import Path

    from linkwork.cli import main

    path = Path(__file__).parent.parent / "examples" / "six_bar_watt.toml"
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "3 groups in solving order (1 input, 2 dyad RRR)" in out
    assert "2. dyad RRR: coupler, rocker by A (revolute), B (revolute), O4 (revolute)" in out


def test_a_chain_of_loops_is_an_input_and_one_dyad_per_loop() -> None:
    s = examples.chain(1000).compile().structure()
    # loop k + 1's crank is tied to loop k's rocker by a relative-angle driver: an input
    assert s.counts() == {"input": 1000, "dyad RRR": 1000}


def test_each_group_says_how_a_sweep_solves_it_and_general_is_a_choice() -> None:
    model = examples.slider_crank().compile()
    assert model.solver == "structured" and model.fallback is None
    s = model.structure()
    assert [g.method.split(":")[0] for g in s.groups] == ["closed form", "closed form"]
    assert "circle meets the slide's line" in s.groups[1].method
    assert "solver                  structured" in s.report()
    general = examples.slider_crank().compile(solver="general")
    assert general.solver == "general"
    assert general.fallback is not None and "general path was asked for" in general.fallback
    assert "solver                  general" in general.structure().report()
    # both give the same sweep
    t = np.linspace(0.0, 1.0, 201)
    a, b = model.sweep(t), general.sweep(t)
    assert np.abs(a.q - b.q).max() < 1e-12 and np.abs(a.qdd - b.qdd).max() < 1e-9 * np.abs(b.qdd).max()
    with pytest.raises(lw.InputError, match="solver"):
        examples.slider_crank().compile(solver="closed")


def _offset_rpr(ground: float, crank: float, offset: float, theta0: float) -> lw.Mechanism:
    """An inverted slider-crank whose slide line passes `offset` beside both pins, the
    block and rocker frames turned apart (the prismatic's theta0 not 0): the general RPR."""
    a = (crank * math.cos(theta0), crank * math.sin(theta0))
    phi = math.atan2(a[1], a[0] - ground)
    n = (-math.sin(phi), math.cos(phi))
    q = (a[0] + offset * n[0], a[1] + offset * n[1])
    m = lw.Mechanism("offset inverted slider-crank")
    crank_b = m.body("crank", (0.0, 0.0), theta0)
    rocker_b = m.body("rocker", (ground, 0.0), phi + 0.4)
    block_b = m.body("block", a, phi - 0.2)
    m.revolute(m.ground, crank_b, (0.0, 0.0), name="O2")
    m.revolute(crank_b, block_b, a, name="A")
    m.revolute(m.ground, rocker_b, (ground, 0.0), name="O4")
    # the line through q along O4 -> A: offset from A, and from O4 by the same amount
    m.prismatic(rocker_b, block_b, q, (math.cos(phi), math.sin(phi)), name="S")
    m.drive_angle(crank_b, lw.Linear(theta0, 5.0), name="crank_angle")
    return m


@pytest.mark.parametrize(
    "mechanism",
    [
        examples.inverted_slider_crank(),
        examples.inverted_slider_crank(ground=0.12, crank=0.10, theta0=2.0),
        _offset_rpr(0.30, 0.10, 0.03, 0.7),
        _offset_rpr(0.25, 0.12, -0.05, -2.5),
    ],
    ids=["textbook", "short ground", "offset", "offset, negative"],
)
def test_an_rpr_dyad_in_closed_form_is_the_general_path(mechanism: lw.Mechanism) -> None:
    model = mechanism.compile()
    groups = model.structure().groups
    assert [(g.kind, g.method.split(":")[0]) for g in groups] == [
        ("input", "closed form"),
        ("dyad RPR", "closed form"),
    ]
    t = np.linspace(0.0, 2.0 * math.pi / 5.0 * 2, 1601)  # two crank turns
    a, b = model.sweep(t), mechanism.compile(solver="general").sweep(t)
    assert (a.iterations[1:] == 0).all(), "every step after the start by the closed form"
    # both to round-off over the step's conditioning (as crates/linkwork/tests/engine/blocks.rs)
    for x, y, tol in ((a.q, b.q, 1e-12), (a.qd, b.qd, 1e-11), (a.qdd, b.qdd, 1e-10)):
        assert np.abs(x - y).max() <= tol * np.abs(y).max()
    assert np.array_equal(a.det_sign, b.det_sign) and len(a.events) == len(b.events)
    # the textbook inverted slider-crank: the rocker points from O4 at A
    if mechanism.name == "inverted slider-crank":
        ground = model.q_start[3]  # the rocker's pivot x
        crank = math.hypot(*model.q_start[6:8])  # the block's frame sits on A
        th = a.body("crank").theta
        phi = np.arctan2(crank * np.sin(th), crank * np.cos(th) - ground)
        assert np.abs(np.angle(np.exp(1j * (a.body("rocker").theta - phi)))).max() < 1e-12


def test_bodies_fixed_by_an_angle_row_and_a_pin_are_substitutions() -> None:
    # a four-bar carrying: a plate welded to the coupler, a car hung on the coupler and
    # kept level, a wheel on the ground whose angle a linear coupling ties to the rocker's
    mech = examples.four_bar()
    s = mech.compile().q_start
    coupler_at = (float(s[3]) + 0.05, float(s[4]) + 0.02)
    plate = mech.body("plate", coupler_at, 0.3)
    mech.fixed("coupler", plate, name="weld")
    car = mech.body("car", coupler_at, 0.0)
    mech.revolute("coupler", car, coupler_at, name="hanger")
    mech.fixed_orientation(mech.ground, car, name="level")
    wheel = mech.body("wheel", (0.5, 0.3), 0.1)
    mech.revolute(mech.ground, wheel, (0.5, 0.3), name="axle")
    mech.linear_coupling("rocker", wheel, {"theta": 2.0}, {"theta": 1.0}, name="tie")
    model = mech.compile()
    methods = {g.bodies: g.method for g in model.structure().groups}
    for body in ("plate", "car", "wheel"):
        assert methods[(body,)].startswith("closed form: the angles from rows affine in them"), methods
    t = np.linspace(0.0, 2.0 * math.pi / 5.0, 801)
    a, b = model.sweep(t, forces=False), mech.compile(solver="general").sweep(t)
    assert (a.iterations[1:] == 0).all()
    for x, y, tol in ((a.q, b.q, 1e-12), (a.qd, b.qd, 1e-11), (a.qdd, b.qdd, 1e-10)):
        assert np.abs(x - y).max() <= tol * np.abs(y).max()
    # what each substitution says, exactly
    assert np.abs(a.body("car").theta).max() == 0.0
    np.testing.assert_allclose(a.body("plate").theta - a.body("coupler").theta, 0.3 - float(s[5]), atol=1e-15)
    tie = 2.0 * a.body("rocker").theta + a.body("wheel").theta
    np.testing.assert_allclose(tie, tie[0], atol=1e-14)
    np.testing.assert_allclose(2.0 * a.body("rocker").thetadd + a.body("wheel").thetadd, 0.0, atol=1e-12)


def _prp() -> lw.Mechanism:
    """A slider on the ground's x guide pinned to a slider on the crank's radial guide."""
    m = lw.Mechanism("PRP")
    th = 0.6
    crank = m.body("crank", (0.0, 0.0), th)
    m.revolute(m.ground, crank, (0.0, 0.0), name="O")
    m.drive_angle(crank, lw.Linear(th, 2.0), name="drive")
    b = (0.1 / math.tan(th), 0.1)  # where the radial line meets the guide y = 0.1
    s1, s2 = m.body("s1", b, 0.0), m.body("s2", b, th)
    m.prismatic(m.ground, s1, b, (1.0, 0.0), name="guide")
    m.prismatic(crank, s2, b, (math.cos(th), math.sin(th)), name="radial")
    m.revolute(s1, s2, b, name="B")
    return m


def _rpp() -> lw.Mechanism:
    """A rocker pinned at O4 whose line and the crank's radial line meet at one slider."""
    m = lw.Mechanism("RPP")
    th = 0.6
    crank = m.body("crank", (0.0, 0.0), th)
    m.revolute(m.ground, crank, (0.0, 0.0), name="O")
    m.drive_angle(crank, lw.Linear(th, 2.0), name="drive")
    p, o4 = (0.2 * math.cos(th), 0.2 * math.sin(th)), (0.5, -0.1)
    phi = math.atan2(p[1] - o4[1], p[0] - o4[0])
    rocker = m.body("rocker", o4, phi)
    m.revolute(m.ground, rocker, o4, name="O4")
    s = m.body("s", p, th)
    m.prismatic(crank, s, p, (math.cos(th), math.sin(th)), name="radial")
    m.prismatic(rocker, s, p, (math.cos(phi), math.sin(phi)), name="along")
    return m


@pytest.mark.parametrize("make, kind", [(_prp, "dyad PRP"), (_rpp, "dyad RPP")])
def test_prp_and_rpp_dyads_are_substitutions(make, kind) -> None:  # type: ignore[no-untyped-def]
    mech = make()
    model = mech.compile()
    groups = model.structure().groups
    assert groups[1].kind == kind and groups[1].method.startswith("closed form: the angles from rows")
    t = np.linspace(0.0, 1.0, 401)
    a, b = model.sweep(t), mech.compile(solver="general").sweep(t)
    assert (a.iterations[1:] == 0).all()
    for x, y, tol in ((a.q, b.q, 1e-12), (a.qd, b.qd, 1e-11), (a.qdd, b.qdd, 1e-10)):
        assert np.abs(x - y).max() <= tol * np.abs(y).max()
    assert np.array_equal(a.det_sign, b.det_sign)
