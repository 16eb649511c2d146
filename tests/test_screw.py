"""linkwork.screw: every geometric answer against an algebraic one.

Tolerances: 1e-12 where both sides are the same algebra in a different order (screws,
products, transports); 1e-9 for solves of random arms whose conditioning the test bounds;
1e-7 for central differences with step 1e-6 (truncation ~1e-12, rounding ~1e-10).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from linkwork import screw

RNG = np.random.default_rng(20240607)


def random_arm(n: int) -> screw.SerialArm:
    joints = []
    for i in range(n):
        at = RNG.uniform(-1.0, 1.0, 2)
        if RNG.random() < 0.3:
            t = RNG.uniform(0.0, 2 * np.pi)
            joints.append((f"j{i + 1}", "P", at, (math.cos(t), math.sin(t))))
        else:
            joints.append((f"j{i + 1}", "R", at))
    return screw.SerialArm(joints, end=(*RNG.uniform(-1.0, 1.0, 2), RNG.uniform(-np.pi, np.pi)))


def random_q(arm: screw.SerialArm) -> np.ndarray:
    return np.array([RNG.uniform(-np.pi, np.pi) if k == "R" else RNG.uniform(-0.5, 0.5) for k in arm.kinds])


def fd_twist(arm: screw.SerialArm, q: np.ndarray, dq: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """The end frame's twist from central differences of the forward kinematics."""
    p, m, e = (arm.forward(q + s * dq).end for s in (h, -h, 0.0))
    return screw.body_twist(e, (p - m) / (2 * h))


# -- elements --------------------------------------------------------------------------


def test_element_conventions():
    p = RNG.uniform(-3, 3, (50, 2))
    s = screw.revolute(p)
    np.testing.assert_array_equal(s, np.column_stack([p[:, 1], -p[:, 0], np.ones(50)]))
    np.testing.assert_allclose(screw.velocity_at(s, p), 0.0, atol=1e-15)  # a pivot stays put
    t = RNG.uniform(-np.pi, np.pi, 50)
    ls = screw.line_screw(t, p)
    np.testing.assert_allclose(ls[:, 2], p[:, 0] * np.sin(t) - p[:, 1] * np.cos(t), atol=1e-15)
    # reciprocal product = line . pole, and = f . v for a force at a point
    tw, wr = RNG.normal(size=(50, 3)), RNG.normal(size=(50, 3))
    np.testing.assert_allclose(
        screw.reciprocal(wr, tw), np.sum(screw.line_of(wr) * screw.pole(tw), axis=1), atol=1e-14
    )
    f = RNG.normal(size=(50, 2))
    v = screw.velocity_at(tw, p)
    np.testing.assert_allclose(screw.reciprocal(screw.force(f, p), tw), np.sum(f * v, axis=1), atol=1e-13)
    np.testing.assert_allclose(screw.prismatic((3.0, 4.0)), [0.6, 0.8, 0.0], atol=1e-16)
    with pytest.raises(ValueError):
        screw.prismatic((0.0, 0.0))


def test_join_and_meet():
    for _ in range(50):
        p, q, r = RNG.uniform(-3, 3, (3, 2))
        s = screw.join(p, q)
        assert abs(math.hypot(s[0], s[1]) - 1.0) < 1e-15  # a unit force...
        np.testing.assert_allclose(s[:2], (q - p) / np.linalg.norm(q - p), atol=1e-14)  # ...from p to q
        for x in (p, q):  # with no moment about either point
            assert abs(screw.line_of(s) @ [x[0], x[1], 1.0]) < 1e-13
        k = screw.line_screw(RNG.uniform(-np.pi, np.pi), r)
        x = screw.meet(s, k)
        assert x[2] == 1.0
        for line in (s, k):
            assert abs(screw.line_of(line) @ x) < 1e-9 * (1 + np.abs(x).max())
    # parallel lines meet at infinity, along them
    x = screw.meet(screw.line_screw(0.3, (0, 0)), screw.line_screw(0.3 + np.pi, (0, 1)))
    assert x[2] == 0.0 and abs(abs(x[0] * math.sin(0.3) - x[1] * math.cos(0.3))) < 1e-15
    # a finite point and a direction at infinity: the line through the point along it
    np.testing.assert_allclose(screw.join((1.0, 2.0), (0.0, 1.0, 0.0)), [0.0, 1.0, 1.0], atol=1e-15)
    with pytest.raises(lw.ScrewError, match="points coincide"):
        screw.join((1.0, 2.0), (2.0, 4.0, 2.0))
    with pytest.raises(lw.ScrewError, match="lines coincide"):
        screw.meet(screw.line_screw(0.3, (0, 0)), -2.0 * screw.line_screw(0.3, (0, 0)))
    assert issubclass(lw.ScrewError, lw.LinkworkError) and issubclass(lw.ScrewError, ValueError)


def test_transport_keeps_the_power():
    for _ in range(50):
        pose = (*RNG.uniform(-2, 2, 2), RNG.uniform(-np.pi, np.pi))
        t, w = RNG.normal(size=3), RNG.normal(size=3)
        tl, wl = screw.twist_to_local(t, pose), screw.wrench_to_local(w, pose)
        assert abs(screw.reciprocal(wl, tl) - screw.reciprocal(w, t)) < 1e-12
        np.testing.assert_allclose(screw.twist_to_world(tl, pose), t, atol=1e-13)
        np.testing.assert_allclose(screw.wrench_to_world(wl, pose), w, atol=1e-13)
        # the local twist's velocity is the frame origin's, in the frame's axes
        c, s = math.cos(pose[2]), math.sin(pose[2])
        v = np.array([[c, -s], [s, c]]) @ tl[:2]
        np.testing.assert_allclose(v, screw.velocity_at(t, pose[:2]), atol=1e-13)


# -- serial arms -----------------------------------------------------------------------


@pytest.mark.parametrize("n", range(2, 9))
def test_screw_jacobian_is_the_fk_jacobian(n):
    for _ in range(10):
        arm = random_arm(n)
        q = random_q(arm)
        st = arm.forward(q)
        fd = np.column_stack([fd_twist(arm, q, e) for e in np.eye(n)])
        np.testing.assert_allclose(st.jacobian, fd, atol=1e-7 * (1 + np.abs(fd).max()))
        # each column is the screw of its joint: revolute(position) or prismatic(axis)
        for i, k in enumerate(st.kinds):
            want = screw.revolute(st.positions[i]) if k == "R" else screw.prismatic(st.axes[i])
            np.testing.assert_allclose(st.jacobian[:, i], want, atol=1e-15)
        w = RNG.uniform(-2, 2, n)
        np.testing.assert_allclose(st.twist(w), st.jacobian @ w, atol=1e-13)
        np.testing.assert_allclose(st.twist(w), fd_twist(arm, q, w), atol=1e-7 * (1 + np.abs(w).sum()))


@pytest.mark.parametrize("n", range(2, 9))
def test_inverse_velocity_against_a_linear_solve(n):
    done = 0
    for _ in range(30):
        arm = random_arm(n)
        st = arm.forward(random_q(arm))
        J = st.jacobian
        if n == 2:
            w_true = RNG.uniform(-2, 2, 2)
            t = J @ w_true
            if np.linalg.cond(J) > 1e3:
                continue
            np.testing.assert_allclose(st.inverse_velocity(t), w_true, atol=1e-9)
            np.testing.assert_allclose(st.barycentre(t).rates, w_true, atol=1e-9)
            # a twist whose pole is off the line through the two axes is refused
            with pytest.raises(lw.ScrewError, match="cannot produce this twist"):
                st.inverse_velocity(t + 0.5 * screw.revolute(np.array(st.gauge[0]) + (5.0, 3.0)))
            done += 1
            continue
        unknown = [n - 3, n - 2, n - 1]
        if np.linalg.cond(J[:, unknown]) > 1e3:
            continue
        given = {i: RNG.uniform(-2, 2) for i in range(n - 3)}
        t = RNG.normal(size=3)
        rest = t - sum((J[:, i] * v for i, v in given.items()), np.zeros(3))
        x = np.linalg.solve(J[:, unknown], rest)
        w = st.inverse_velocity(t, given)
        b = st.barycentre(t, given)
        scale = 1 + np.abs(x).max()
        np.testing.assert_allclose(w[unknown], x, atol=1e-9 * scale)
        np.testing.assert_allclose(b.rates[unknown], x, atol=1e-9 * scale)
        np.testing.assert_allclose(J @ w, t, atol=1e-9 * scale)
        # each line screw is reciprocal to the other two unknown joints' screws
        S = st.line_screws(unknown)
        R = S @ J[:, unknown]
        np.testing.assert_allclose(R - np.diag(np.diag(R)), 0.0, atol=1e-12)
        done += 1
    assert done >= 15


@pytest.mark.parametrize("n", range(2, 9))
def test_torques_are_virtual_work(n):
    for _ in range(10):
        arm = random_arm(n)
        q = random_q(arm)
        st = arm.forward(q)
        W = screw.force(RNG.uniform(-5, 5, 2), RNG.uniform(-1, 1, 2)) + screw.couple(RNG.uniform(-1, 1))
        tau = st.torques(W)
        np.testing.assert_allclose(tau, st.jacobian.T @ W, atol=1e-13)
        # virtual work of each joint's displacement, by finite differences of the FK
        fd = [screw.reciprocal(W, fd_twist(arm, q, e)) for e in np.eye(n)]
        np.testing.assert_allclose(tau, fd, atol=1e-7 * (1 + np.abs(tau).max()))
        # lever arms: the perpendicular distance from each pivot to the force line
        p = st.lever_arms(W)
        line = screw.line_of(W)
        for i, k in enumerate(st.kinds):
            if k == "R":
                d = (line[:2] @ st.positions[i] + line[2]) / np.hypot(*line[:2])
                assert abs(p[i] - d) < 1e-12 * (1 + abs(d))


@pytest.mark.parametrize("n", range(2, 9))
def test_forward_force_through_torque_centres(n):
    done = 0
    for _ in range(20):
        arm = random_arm(n)
        st = arm.forward(random_q(arm))
        J = st.jacobian
        W = screw.force(RNG.uniform(-5, 5, 2), st.end_point) if n == 2 else RNG.normal(size=3)
        tau = J.T @ W
        if n == 2:
            A = np.vstack([J.T, screw.revolute(st.end_point)])  # and no moment about the end point
        else:
            A = J.T
        if np.linalg.cond(A) > 1e3:
            continue
        got = st.force(tau)
        want = np.linalg.lstsq(A, np.append(tau, 0.0) if n == 2 else tau, rcond=None)[0]
        np.testing.assert_allclose(got, want, atol=1e-9 * (1 + np.abs(want).max()))
        np.testing.assert_allclose(got, W, atol=1e-9 * (1 + np.abs(W).max()))
        # the force line passes through every torque centre
        line = screw.line_of(got)
        for x in st.torque_centres(tau).values():
            assert abs(line @ x) <= 1e-9 * np.linalg.norm(line) * (1 + np.abs(x).max())
        done += 1
    assert done >= 8


def test_torque_centres_are_velocity_centres_of_workless_motions():
    arm = random_arm(5)
    st = arm.forward(random_q(arm))
    W = RNG.normal(size=3)
    tau = st.torques(W)
    for (j, k), x in st.torque_centres(tau).items():
        w = np.zeros(5)
        w[j], w[k] = tau[k], -tau[j]
        np.testing.assert_allclose(st.velocity_centres(w)[(j, k)], x, atol=1e-14)
        assert abs(screw.reciprocal(W, st.twist(w))) < 1e-12


def test_documented_three_link_arm():
    """docs/screw.md: lengths 1.0, 0.8, 0.5 m at 30, 45, -60 degrees, rates 1.0, -0.5, 2.0 rad/s."""
    lengths, q, w = np.array([1.0, 0.8, 0.5]), np.radians([30.0, 45.0, -60.0]), np.array([1.0, -0.5, 2.0])
    st = screw.SerialArm.from_lengths(lengths).forward(q)
    phi, rate = np.cumsum(q), np.cumsum(w)
    pts = np.vstack(
        [[0.0, 0.0], np.cumsum(lengths[:, None] * np.column_stack([np.cos(phi), np.sin(phi)]), 0)]
    )
    np.testing.assert_allclose(st.positions, pts[:3], atol=1e-15)
    np.testing.assert_allclose(st.end, [*pts[3], phi[2]], atol=1e-15)
    v = np.sum(lengths[:, None] * rate[:, None] * np.column_stack([-np.sin(phi), np.cos(phi)]), axis=0)
    np.testing.assert_allclose(st.end_velocity(w), v, atol=1e-14)
    np.testing.assert_allclose(st.joint_velocities(w).sum(axis=0), v, atol=1e-14)
    # the pole is the barycentre of the joints with weights w, and the end point turns about it
    bary = (w[:, None] * pts[:3]).sum(0) / w.sum()
    np.testing.assert_allclose(st.pole(w), [*bary, 1.0], atol=1e-14)
    e = pts[3] - bary
    np.testing.assert_allclose(v, w.sum() * np.array([-e[1], e[0]]), atol=1e-14)
    t = st.twist(w)
    np.testing.assert_allclose(st.inverse_velocity(t), w, atol=1e-13)
    b = st.barycentre(t)
    np.testing.assert_allclose(b.rates, w, atol=1e-13)
    assert b.vertex is not None and b.foot is not None
    # end force (0, -10) N: tau_i = (E - P_i) x F, and back
    F = np.array([0.0, -10.0])
    W = screw.force(F, pts[3])
    d = pts[3] - pts[:3]
    np.testing.assert_allclose(st.torques(W), d[:, 0] * F[1] - d[:, 1] * F[0], atol=1e-13)
    np.testing.assert_allclose(st.lever_arms(W) * 10.0, st.torques(W), atol=1e-13)
    np.testing.assert_allclose(st.force(st.torques(W)), W, atol=1e-12)


def rrr_mechanism() -> lw.Mechanism:
    """The three-link arm as a linkwork mechanism, every joint driven by a relative angle."""
    m = lw.Mechanism("rrr")
    lengths, q0 = [1.0, 0.8, 0.5], np.radians([30.0, 45.0, -60.0])
    p, phi, prev = np.zeros(2), 0.0, m.ground
    for i, (length, qi) in enumerate(zip(lengths, q0)):
        phi += qi
        end = p + length * np.array([math.cos(phi), math.sin(phi)])
        b = m.link(f"link{i + 1}", p, end)
        m.revolute(prev, b, at=p, name=f"J{i + 1}")
        m.drive_relative_angle(prev, b, lw.Harmonic(qi, 0.4 * (i + 1), 1.0 + i, 0.3))
        p, prev = end, b
    m.point("E", prev, p)
    return m


def test_arm_from_a_model_matches_the_engine():
    model = rrr_mechanism().compile()
    arm = screw.SerialArm.from_model(model, end_point="E")
    assert arm.names == ["J1", "J2", "J3"] and arm.kinds == "RRR"
    res = model.sweep(np.linspace(0.0, 2.0, 41))
    for k in range(0, 41, 5):
        q, w = arm.joint_values(res, step=k)
        st = arm.forward(q)  # q: joint values since the drawing (the home configuration)
        pose, twist = arm.model_end(res, step=k)
        np.testing.assert_allclose(st.end, pose, atol=1e-12)
        np.testing.assert_allclose(st.twist(w), twist, atol=1e-12)
        # the engine's own point velocity of E
        np.testing.assert_allclose(st.end_velocity(w), res.point("E").velocity[k], atol=1e-12)
    with pytest.raises(ValueError, match="step="):
        arm.joint_values(res)


# -- closed mechanisms -----------------------------------------------------------------


@pytest.mark.parametrize("build", [lw.examples.four_bar, lw.examples.slider_crank, lw.examples.six_bar_watt])
def test_instant_centres_from_velocities_match_kennedy(build):
    model = build().compile()
    res = model.sweep(np.linspace(0.013, 0.013 + 2 * np.pi / 5.0, 19))
    for k in range(res.n_steps):
        vel = screw.instant_centres(res, step=k)
        geo = screw.kennedy_centres(res, step=k)
        assert vel.kennedy is not None and vel.kennedy[0] < 1e-12  # Kennedy's theorem holds
        for pair, p in vel.points.items():
            g = geo.points[pair]
            assert p is not None and g is not None, pair
            # the same homogeneous point: both normalised the same way
            if p[2] == 0.0:
                assert g[2] == 0.0 and abs(p[0] * g[1] - p[1] * g[0]) < 1e-9, pair
            else:
                np.testing.assert_allclose(p, g, atol=1e-9, err_msg=str(pair))


def test_slider_crank_centres_at_infinity():
    st = lw.examples.slider_crank().compile().solve(0.05)
    c = screw.instant_centres(st)
    s = c.centre("ground", "slider")
    assert s[2] == 0.0 and abs(abs(s[1]) - 1.0) < 1e-12  # across the horizontal slide
    np.testing.assert_allclose(c.centre("ground", "crank"), [0.0, 0.0, 1.0], atol=1e-12)
    assert "at infinity" in c.table()


def dead_four_bar() -> lw.Mechanism:
    """A four-bar drawn at a dead point: B on the line from A to O4."""
    a = 0.2 * np.array([math.cos(1.1), math.sin(1.1)])
    o4 = np.array([0.35, 0.0])
    b = a + 0.6 * (o4 - a)
    m = lw.Mechanism("dead four-bar")
    crank, coupler, rocker = m.link("crank", (0, 0), a), m.link("coupler", a, b), m.link("rocker", o4, b)
    m.revolute(m.ground, crank, (0, 0), name="O2")
    m.revolute(crank, coupler, a, name="A")
    m.revolute(coupler, rocker, b, name="B")
    m.revolute(m.ground, rocker, o4, name="O4")
    m.drive_angle(crank, lw.Linear(1.1, 1.0))
    return m


def test_a_dead_point_collapses_the_loop_screws():
    ok = screw.loop_singularity(lw.examples.four_bar().compile().solve(0.0))
    assert not ok.singular and ok.rank == 3 and ok.loops == [["O2", "A", "B", "O4"]]
    model = dead_four_bar().compile()
    # the engine says Phi_q is singular there...
    with pytest.raises(lw.SingularError):
        model.solve(0.0)

    # ...and, as drawn, the screws of the passive joints A, B, O4 have become dependent
    s = screw.loop_singularity(model)
    assert s.singular and s.rank == 2
    assert s.involved == ["A", "B", "O4"] and s.dependent == [["A", "B", "O4"]]
    assert s.singular_values[-1] < 1e-12 * s.singular_values[0]


def test_degenerate_input_gets_clear_errors():
    st = screw.SerialArm.from_lengths([1.0, 0.0, 0.5]).forward([0.3, 0.2, 0.1])
    with pytest.raises(lw.ScrewError, match="^joints 2 and 3 coincide$"):
        st.inverse_velocity([0.1, 0.2, 0.3])
    assert st.dependencies() == [("2", "3")]
    st = screw.SerialArm.from_lengths([1.0, 0.8, 0.5]).forward([0.4, 0.0, 0.0])
    with pytest.raises(lw.ScrewError, match="^joints 1, 2 and 3 are collinear$"):
        st.barycentre([0.1, 0.2, 0.3])
    # a wrench through every joint needs no torque, and torques cannot fix it
    np.testing.assert_allclose(st.torques(7.0 * screw.line_screw(0.4, (0.0, 0.0))), 0.0, atol=1e-14)
    with pytest.raises(lw.ScrewError, match="dependent axes"):
        st.force([0.0, 0.0, 0.0])
    with pytest.raises(lw.ScrewError, match="pure couple"):
        st.lever_arms(screw.couple(1.0))
    four = screw.SerialArm.from_lengths([1.0, 0.8, 0.5, 0.3]).forward([0.1, 0.2, 0.3, 0.4])
    with pytest.raises(lw.ScrewError, match="4 unknown joint rates"):
        four.inverse_velocity([1.0, 0.0, 0.0])
    with pytest.raises(lw.ScrewError, match="no end wrench"):
        four.force(four.torques([1.0, 2.0, 0.3]) + [0, 0, 0, 0.5])
    with pytest.raises(lw.ScrewError, match="3 entries; the arm has 4"):
        four.twist([1.0, 2.0, 3.0])
    with pytest.raises(lw.ScrewError, match="kind must be 'R' or 'P'"):
        screw.SerialArm([("a", "X", (0, 0))], end=(1, 0, 0))
    with pytest.raises(lw.ScrewError, match="closes a loop|has joints"):
        screw.SerialArm.from_model(lw.examples.four_bar())
    with pytest.raises(lw.ScrewError, match="driver 'x'"):
        m = lw.examples.four_bar()
        m.remove("crank_angle")
        m.drive_coordinate("coupler", (0.1, 0.1), "x", lw.Constant(0.1), name="x")
        screw.loop_singularity(m.compile().solve(0.0))


def test_the_docs_page_example_runs():
    """The Python block of docs/screw.md, and the claims in its comments."""
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "docs" / "screw.md").read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    env: dict = {}
    exec(compile(code, "docs/screw.md", "exec"), env)
    st, T = env["st"], env["T"]
    np.testing.assert_allclose(st.inverse_velocity(T), [1.0, -0.5, 2.0], atol=1e-12)
    np.testing.assert_allclose(st.barycentre(T).rates, [1.0, -0.5, 2.0], atol=1e-12)
