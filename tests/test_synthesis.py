"""Synthesis against mechanisms that generated the precision points: the generator must be
among the real solutions to 1e-10, every root certified, the homotopy must agree with the
independent elimination, and the engine's screening must pass the generator and flag
designs that cannot make the motion."""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork
from linkwork import synthesis as S
from linkwork.errors import SynthesisError

# generator four-bar: ground pivots O2, O4; crank, coupler, rocker; coupler point P at
# (1.7, 1.1) in the frame of A -> B
O2, O4, CRANK, COUPLER, ROCKER, PC = 0j, 4 + 0.5j, 1.5, 4.0, 3.0, 1.7 + 1.1j
PHIS = np.array([0.3, 0.7, 1.2, 1.8, 2.3])


def at(phi: float) -> tuple[complex, complex, float, complex]:
    a = O2 + CRANK * np.exp(1j * phi)
    d = O4 - a
    dist = abs(d)
    along = (COUPLER**2 - ROCKER**2 + dist**2) / (2 * dist)
    b = a + d / dist * (along + 1j * math.sqrt(COUPLER**2 - along**2))
    angle = float(np.angle(b - a))
    return a, b, angle, a + PC * np.exp(1j * angle)


def poses(phis: np.ndarray) -> np.ndarray:
    return np.array([(at(p)[3].real, at(p)[3].imag, at(p)[2]) for p in phis])


def has(dyads: list[S.Dyad], ground: complex, moving: complex, tol: float = 1e-10) -> S.Dyad | None:
    for d in dyads:
        if abs(complex(*d.ground) - ground) < tol and abs(complex(*d.moving) - moving) < tol:
            return d
    return None


def test_burmester_recovers_the_generator_and_screens_it_defect_free() -> None:
    result = S.motion(poses(PHIS))
    sols = result.dyads
    assert isinstance(sols, S.DyadSolutions)
    assert len(sols) <= 4 and sols.failed == 0 and sols.distinct
    assert all(d.certified for d in sols)
    a1, b1, _, _ = at(PHIS[0])
    for g, m in ((O2, a1), (O4, b1)):
        d = has(sols.real, g, m)
        assert d is not None and d.residual < 1e-12 and d.radius < 1e-9
    # the generator, crank O2 -> A as input, is a design and is defect-free
    gen = [d for d in result.designs if abs(complex(*d.o2) - O2) < 1e-9 and abs(complex(*d.o4) - O4) < 1e-9]
    assert len(gen) == 1
    f = gen[0].defects
    assert f.ok and all(f.reached) and max(f.error) < 1e-9 and f.grashof == "Grashof"
    assert result.designs[0].defects.ok  # defect-free designs sort first
    # the design is a real model: the engine puts P on the precision points
    res = (
        gen[0].model().compile().sweep(gen[0].crank_rotations() * f.direction % (2 * math.pi), derivatives=0)
    )
    assert np.allclose(res.point("P").position, poses(PHIS)[:, :2], atol=1e-10)


def test_homotopy_and_resultant_agree() -> None:
    rng = np.random.default_rng(3)
    for _ in range(10):
        p = np.column_stack([rng.uniform(-2, 2, (5, 2)), rng.uniform(0, 3, 5)])
        h = S.dyads("burmester", poses=p)
        r = S.dyads("burmester", poses=p, method="resultant")
        # the same roots, real and complex, every one certified
        assert len(r.dyads) == len(h.dyads) and len(r.real) == len(h.real)
        assert all(d.certified for d in r.dyads) and r.distinct
        for d in r.dyads:
            size = 1e-8 * (1 + abs(complex(*d.ground)) + abs(complex(*d.moving)))
            assert any(
                np.allclose(
                    np.r_[d.ground, d.moving, d.ground_imag, d.moving_imag],
                    np.r_[e.ground, e.moving, e.ground_imag, e.moving_imag],
                    atol=size,
                    rtol=0,
                )
                for e in h.dyads
            )


def test_timed_path_recovers_the_input_dyad_and_the_four_bar() -> None:
    pts = poses(PHIS)[:, :2]
    result = S.path(pts, PHIS - PHIS[0])
    first = result.dyads[0]
    a1, b1, _, _ = at(PHIS[0])
    assert has(first.real, O2, a1) is not None
    gen = [d for d in result.designs if abs(complex(*d.o2) - O2) < 1e-9 and abs(complex(*d.o4) - O4) < 1e-9]
    assert len(gen) == 1 and gen[0].defects.ok
    assert abs(complex(*gen[0].b) - b1) < 1e-9
    # the elimination finds the same input dyads
    r = S.dyads("timed", points=pts, input_angles=PHIS - PHIS[0], method="resultant")
    assert len(r.real) == len(first.real)


def test_out_of_order_positions_are_an_order_defect() -> None:
    order = [0, 2, 1, 3, 4]
    result = S.motion(poses(PHIS)[order])
    gen = [d for d in result.designs if abs(complex(*d.o2) - O2) < 1e-9 and abs(complex(*d.o4) - O4) < 1e-9]
    assert len(gen) == 1
    assert gen[0].defects.order and not gen[0].defects.ok
    # out of order, the precision times still reach every position, turning the first way
    t = gen[0].precision_times()
    assert np.all((t >= 0) & (t < 2 * math.pi))
    by_time = np.argsort(t)
    res = gen[0].model().compile().sweep(t[by_time], derivatives=0)
    assert np.allclose(res.point("P").position, poses(PHIS)[order][by_time, :2], atol=1e-10)


def test_three_and_two_poses() -> None:
    p = poses(PHIS[[0, 2, 4]])
    a1, b1, _, _ = at(PHIS[0])
    r = S.motion(p, moving=[(a1.real, a1.imag), (b1.real, b1.imag)])
    (d,) = r.designs
    assert abs(complex(*d.o2) - O2) < 1e-12 and abs(complex(*d.o4) - O4) < 1e-12
    r = S.motion(p, ground=[(O2.real, O2.imag), (O4.real, O4.imag)])
    assert abs(complex(*r.designs[0].a) - a1) < 1e-12
    two = S.motion(poses(PHIS[:2]), moving=[(a1.real, a1.imag), (b1.real, b1.imag)], along=(0.5, -0.5))
    d = two.designs[0]
    for k in range(2):
        g, m = (d.o2, d.a) if k == 0 else (d.o4, d.b)
        assert abs(np.hypot(*(g - m)) - two.dyads.dyads[k].length) < 1e-12


def test_four_pose_curves_are_exact_dyads() -> None:
    p = poses(PHIS[:4])
    r = S.motion(p, samples=360)
    assert r.curves is not None and len(r.curves.circle_points) > 300
    p1 = complex(*p[0, :2])
    for m, g in zip(r.curves.circle_points[::17], r.curves.centre_points[::17]):
        m, g = complex(*m), complex(*g)
        radii = [abs(complex(*q[:2]) + (m - p1) * np.exp(1j * (q[2] - p[0, 2])) - g) for q in p]
        assert np.ptp(radii) < 1e-8 * (1 + radii[0])


def test_freudenstein_four_bar_and_slider_crank() -> None:
    phi = S.chebyshev(0.4, 1.6, 3)
    assert np.allclose(phi, 1.0 - 0.6 * np.cos(np.array([1, 3, 5]) * np.pi / 6))
    # pairs from the generator (crank input, rocker output)
    psi = np.array([np.angle(at(p)[1] - O4) for p in phi])
    # the generator's ground line is not the x axis: rotate into Freudenstein's frame
    tilt = np.angle(O4 - O2)
    fb = S.function(phi - tilt, psi - tilt, ground=abs(O4 - O2))
    assert abs(fb.a - CRANK) < 1e-12 and abs(fb.b - COUPLER) < 1e-12 and abs(fb.c - ROCKER) < 1e-12
    # structural error: zero at the pairs, and the engine follows the generator between them
    grid = np.linspace(0.4, 1.6, 25) - tilt
    want = np.array([np.angle(at(p + tilt)[1] - O4) for p in grid]) - tilt
    err = fb.structural_error(grid, want)
    assert np.max(np.abs(err)) < 1e-9
    # slider-crank
    sc = S.function([0.2, 0.9, 1.7], [1.9, 1.5, 0.8], kind="slider_crank")
    for phi_k, s_k in zip([0.2, 0.9, 1.7], [1.9, 1.5, 0.8]):
        assert (
            abs((s_k - sc.a * math.cos(phi_k)) ** 2 + (sc.e - sc.a * math.sin(phi_k)) ** 2 - sc.b**2) < 1e-12
        )


def test_bad_input_is_a_named_error() -> None:
    p = poses(PHIS)
    with pytest.raises(SynthesisError, match="2 to 5 poses"):
        S.motion(np.vstack([p, p[:1] + 1.0]))
    with pytest.raises(SynthesisError, match="degrees"):
        S.motion(np.column_stack([p[:, :2], np.degrees(p[:, 2])]))
    assert len(S.motion(np.column_stack([p[:, :2], np.degrees(p[:, 2])]), angles="deg").dyads.real) == 2
    same = p.copy()
    same[2] = same[1]
    with pytest.raises(SynthesisError, match="poses 2 and 3 coincide"):
        S.motion(same)
    nan = p.copy()
    nan[3, 0] = np.nan
    with pytest.raises(SynthesisError, match="row 4 is not finite"):
        S.motion(nan)
    with pytest.raises(SynthesisError, match="exactly 5 points"):
        S.path(p[:4, :2], PHIS[:4])
    with pytest.raises(SynthesisError, match="leave free choices"):
        S.motion(p[:3])
    with pytest.raises(SynthesisError, match="3 precision pairs"):
        S.function([0.1, 0.2], [0.3, 0.4])
    with pytest.raises(SynthesisError, match="exactly 9 points"):
        S.nine_points(p[:, :2])
    with pytest.raises(SynthesisError, match="points 1 and 2 coincide"):
        S.nine_points(np.vstack([p[:1, :2], p[:1, :2], np.arange(14.0).reshape(7, 2)]))
    assert issubclass(SynthesisError, linkwork.errors.LinkworkError)


def test_generic_root_count() -> None:
    assert S.generic_root_count() == 5


@pytest.mark.parametrize("name", ["motion", "path", "path_least_squares", "chained_six_bar"])
def test_cli_synth_writes_designs_report_and_figure(name: str, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from pathlib import Path

    from linkwork.cli import main

    problem = Path(__file__).parent.parent / "examples" / "synthesis" / f"{name}.toml"
    assert main(["synth", str(problem), "--out", str(tmp_path)]) == 0
    stem = name
    assert (tmp_path / f"{stem}_report.txt").read_text().strip()
    assert (tmp_path / f"{stem}.png").stat().st_size > 10_000
    models = sorted(tmp_path.glob(f"{stem}_design*.toml"))
    assert models
    # every written design is a model file the engine reads and sweeps (a defective
    # design as far as its limit of motion)
    for path in models:
        m = linkwork.Mechanism.load(path).compile()
        try:
            res = m.sweep(np.linspace(0.0, 0.5, 6), derivatives=0)
        except linkwork.errors.SingularError as e:
            res = e.partial  # type: ignore[attr-defined]
        assert len(res.times) and np.all(np.isfinite(res.q))
    assert "designs" in capsys.readouterr().out or name == "chained_six_bar"


def test_cli_synth_bad_problem_file(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from linkwork.cli import main

    bad = tmp_path / "bad.toml"
    bad.write_text('problem = "motion"\nposes = [[0, 0, 0], [1, 0, 0.1]]\n')
    assert main(["synth", str(bad), "--out", str(tmp_path)]) == 1
    assert "leave free choices" in capsys.readouterr().err
    bad.write_text('problem = "gears"\n')
    assert main(["synth", str(bad), "--out", str(tmp_path)]) == 1
    assert "problem must be one of" in capsys.readouterr().err


WMS3 = [
    (0.25, 0.00), (0.52, 0.10), (0.80, 0.70), (1.20, 1.00), (1.40, 1.30),
    (1.10, 1.48), (0.70, 1.40), (0.20, 1.00), (0.02, 0.40),
]  # fmt: skip


def test_alt_nine_points_published_count_and_a_real_four_bar_through_all_nine() -> None:
    # Wampler, Morgan and Sommese's Problem 3: 64 of the 1442 four-bars are real
    # (certified by Hauenstein and Sottile with alphaCertified)
    r = S.nine_points(np.array(WMS3), screen=False)
    assert r.paths == 1442
    assert r.physical_classes == 64
    assert len(r.designs) == 3 * 64  # each with its two Roberts cognates
    assert r.certified >= 1400 and r.max_residual < 1e-12
    # every real four-bar passes the nine points: its crank length is constant over them
    assert max(d.residual for design in r.designs for d in design.dyads) < 1e-8
    # and the engine, driving the crank of one of them, puts P on the points it reaches
    design = r.designs[0]
    model = design.model().compile()
    turns = np.sort(np.mod(design.crank_rotations(), 2 * np.pi))
    try:
        res = model.sweep(np.union1d(np.linspace(0, 2 * np.pi, 721), turns), derivatives=0)
        path = res.point("P").position
    except linkwork.errors.SolveError as e:
        path = e.partial.point("P").position  # type: ignore[attr-defined]
    near = [np.min(np.hypot(*(path - p).T)) for p in np.array(WMS3)]
    assert min(near) < 1e-9  # at least the drawing's own point; the rest by the defects report
    assert design.defects.reached[0]


def test_least_squares_motion_through_nine_poses() -> None:
    phis = np.linspace(0.2, 2.6, 9)
    p = poses(phis)
    a1, b1, _, _ = at(phis[0])
    # exact poses: the generator's dyads are zero-residual minima and are found
    r = S.motion_least_squares(p, length_range=(0.5, 10.0))
    for g, m in ((O2, a1), (O4, b1)):
        d = has(r.dyads.dyads, g, m, 1e-8)  # type: ignore[union-attr]
        assert d is not None and d.residual < 1e-10
    gen = [d for d in r.designs if abs(complex(*d.o2) - O2) < 1e-8 and abs(complex(*d.o4) - O4) < 1e-8]
    assert len(gen) == 1 and gen[0].defects.ok
    # bounds hold: the fitted length is in range, so the length at pose 1 is within the
    # dyad's residual of it
    assert all(0.5 - d.residual - 1e-12 <= d.length <= 10.0 + d.residual + 1e-12 for d in r.dyads)
    # noisy poses (1e-4): the generator's neighbourhood, residual at the noise level
    rng = np.random.default_rng(0)
    noisy = p + np.column_stack([rng.normal(0, 1e-4, (9, 2)), rng.normal(0, 1e-4, 9)])
    r = S.motion_least_squares(noisy, min_transmission=30.0)
    best = min(r.dyads, key=lambda d: abs(complex(*d.ground) - O2))
    assert abs(complex(*best.ground) - O2) < 1e-2 and best.residual < 1e-3
    assert all(d.defects.worst_transmission >= 30.0 for d in r.designs)
    with pytest.raises(SynthesisError, match="more than 5 poses"):
        S.motion_least_squares(p[:5])


def test_alt_random_complex_instance_every_class_finite_and_certified() -> None:
    # Alt's problem at random complex parameters (the points' conjugates replaced by
    # independent complex numbers): every one of the 1442 classes ends at a finite root,
    # each alpha-certified, the roots in pairwise different orbits of the group
    rng = np.random.default_rng(5)
    pts, hat = rng.normal(size=(9, 2)), rng.normal(size=(9, 2))
    r = linkwork._core.synth_alt(pts.ravel().tolist(), hat.ravel().tolist())
    assert r["paths"] == r["roots"] == r["certified"] == 1442 and r["distinct"]
    assert r["failed"] == r["at_infinity"] == r["singular"] == 0
    assert r["max_residual"] < 1e-12 and r["physical_classes"] == 0


def test_least_squares_path_through_nine_timed_points() -> None:
    phis = np.linspace(0.2, 2.6, 9)
    pts = poses(phis)[:, :2]
    a1, b1, _, _ = at(phis[0])
    # exact points: the generator's crank and follower are zero-residual minima
    r = S.path_least_squares(pts, phis - phis[0], length_range=(0.5, 10.0))
    crank = has(r.dyads[0].dyads, O2, a1, 1e-8)  # type: ignore[index]
    assert crank is not None and crank.residual < 1e-10
    gen = [d for d in r.designs if abs(complex(*d.o2) - O2) < 1e-8 and abs(complex(*d.o4) - O4) < 1e-8]
    assert len(gen) == 1 and gen[0].defects.ok
    assert abs(complex(*gen[0].b) - b1) < 1e-8
    # noisy points (1e-5): a defect-free design near the generator with residuals at the
    # noise level; the pivots move about 1000 times the noise (the fit's condition number
    # is about 400 here: timing fixes the crank less firmly than poses fix a body)
    rng = np.random.default_rng(1)
    r = S.path_least_squares(pts + rng.normal(0, 1e-5, (9, 2)), phis - phis[0], min_transmission=30.0)
    best = min(r.designs, key=lambda d: abs(complex(*d.o2) - O2) + abs(complex(*d.o4) - O4))
    assert abs(complex(*best.o2) - O2) < 2e-2 and abs(complex(*best.o4) - O4) < 2e-2
    assert max(d.residual for d in best.dyads) < 1e-4 and best.defects.ok
    assert all(d.defects.worst_transmission >= 30.0 for d in r.designs)
    with pytest.raises(SynthesisError, match="more than 5 points"):
        S.path_least_squares(pts[:5], phis[:5])
    with pytest.raises(SynthesisError, match="input angles"):
        S.path_least_squares(pts, phis[:8])
    # degenerate input: a named error with the reason, not an empty answer
    with pytest.raises(SynthesisError, match="no input dyad.*coincide"):
        S.path_least_squares(np.zeros((7, 2)), np.linspace(0, 1, 7))
    with pytest.raises(SynthesisError, match="no dyad.*coincide"):
        S.motion_least_squares(np.zeros((7, 3)))


def test_crank_rotations_and_precision_times_away_from_the_origin() -> None:
    """Moved off the origin (O2 != 0) and turned the other way round, the generator's crank
    rotations are recovered from the coupler poses alone, and the design's model, swept at
    its `precision_times`, puts P on every precision point with the coupler at its angle."""
    shift = np.array([0.7, -1.3, 0.0])
    for phis in (PHIS, PHIS[::-1], np.array([0.3, 1.4, 2.6, 3.7, 4.6])):
        result = S.motion(poses(phis) + shift)
        o2, o4 = O2 + complex(*shift[:2]), O4 + complex(*shift[:2])
        near = [d for d in result.designs if abs(complex(*d.o2) - o2) < 1e-9]
        (gen,) = [d for d in near if abs(complex(*d.o4) - o4) < 1e-9]
        turned = np.angle(np.exp(1j * (phis - phis[0])))
        assert np.allclose(np.angle(np.exp(1j * gen.crank_rotations())), turned, atol=1e-10)
        t = gen.precision_times()
        assert t[0] == 0.0 and np.all(np.abs(t) < 2 * math.pi)
        assert np.all(np.diff(np.sign(phis[-1] - phis[0]) * t) > 0), t
        res = gen.model().compile().sweep(t, derivatives=0)
        assert np.allclose(res.point("P").position, poses(phis)[:, :2] + shift[:2], atol=1e-10)
    # timed: the rotations are the prescribed input angles from the first
    result = S.path(poses(PHIS)[:, :2], PHIS)
    near = [d for d in result.designs if abs(complex(*d.o2) - O2) < 1e-9]
    (gen,) = [d for d in near if abs(complex(*d.o4) - O4) < 1e-9]
    assert np.allclose(gen.crank_rotations(), PHIS - PHIS[0], atol=1e-12)
