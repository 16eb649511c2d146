"""The chained six-bar's synthesis for any data: known mechanisms recovered by the general
call and by `linkwork synth`, the source document's example through its example file,
and the six-bar defects on designs that fail each way."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import linkwork
import linkwork.synthesis as S
from linkwork.errors import SolveError, SynthesisError
from linkwork.motion import Linear, Polynomial
from linkwork.synthesis import six_bar as C

EXAMPLE = Path(__file__).parent.parent / "examples" / "synthesis" / "chained_six_bar.toml"


def _toml(path: Path) -> dict[str, Any]:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python < 3.11
        import tomli as tomllib
    return tomllib.loads(path.read_text())


def _polar(rng: np.random.Generator, lo: float, hi: float) -> np.ndarray:
    r, a = rng.uniform(lo, hi), rng.uniform(0.0, 2.0 * math.pi)
    return np.array([r * math.cos(a), r * math.sin(a)])


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(float(v[1] - u[1]), float(v[0] - u[0]))


def known_six_bar(seed: int, linear: bool = False) -> dict[str, Any]:
    """A chained six-bar of random dimensions (random pivots Q and O, random links), built
    and swept by the engine with QA driven at a random rate and the coupler on a random
    quadratic law (a linear one with ``linear``); its precision data (P, phi, theta at
    five random times) read from the sweep, so they are consistent."""
    rng = np.random.default_rng(seed)
    for _ in range(200):
        q = rng.uniform(-10.0, 10.0, 2)
        a1 = q + _polar(rng, 2.0, 4.0)
        b1 = a1 + _polar(rng, 5.0, 9.0)
        p1 = b1 + _polar(rng, 2.0, 5.0)
        d1 = b1 + _polar(rng, 3.0, 6.0)
        c1 = d1 + _polar(rng, 4.0, 8.0)
        o = c1 + _polar(rng, 5.0, 9.0)
        m = linkwork.Mechanism("known chained six-bar")
        qa = m.body("QA", tuple(q), _angle(q, a1))
        ab = m.body("AB", tuple(a1), _angle(a1, b1))
        coupler = m.body("coupler", tuple(p1), 0.0)
        dc = m.body("DC", tuple(d1), _angle(d1, c1))
        oc = m.body("OC", tuple(o), _angle(o, c1))
        m.revolute(m.ground, qa, tuple(q))
        m.revolute(qa, ab, tuple(a1))
        m.revolute(ab, coupler, tuple(b1))
        m.revolute(coupler, dc, tuple(d1))
        m.revolute(dc, oc, tuple(c1))
        m.revolute(m.ground, oc, tuple(o))
        m.belt(qa, dc, ratio=1.0)
        m.point("P", coupler, tuple(p1))
        sense = rng.choice([-1.0, 1.0])
        m.drive_angle(qa, Linear(_angle(q, a1), sense * rng.uniform(1.5, 2.5)))
        rate = rng.uniform(-0.4, 0.4)
        bend = 0.0 if linear else rng.uniform(-0.3, 0.3)
        m.drive_angle(coupler, Polynomial([0.0, rate, bend]))
        times = np.linspace(0.0, 1.0, 401)
        try:
            res = m.compile().sweep(times, derivatives=0, on_singular="stop")
        except SolveError:
            continue  # this one does not assemble over the motion: draw again
        k = np.sort(rng.choice(np.arange(1, 401), 4, replace=False))
        k = np.concatenate([[0], k])
        phi = res.body("QA").theta[k] - res.body("QA").theta[0]
        theta = res.body("coupler").theta[k]
        return {
            "points": res.point("P").position[k],
            "input_angles": phi,
            "coupler_angles": theta,
            "input_pivot": q,
            "output_pivot": o,
            "truth": (a1, b1, c1, d1),
        }
    raise AssertionError("no random six-bar assembled")


def _recovered(design: Any, truth: tuple[np.ndarray, ...]) -> float:
    return max(float(np.hypot(*(u - v))) for u, v in zip((design.a1, design.b1, design.c1, design.d1), truth))


def _call(data: dict[str, Any], **kw: Any) -> C.ChainedSixBarSynthesis:
    keys = ("points", "input_angles", "coupler_angles", "input_pivot", "output_pivot")
    return S.chained_six_bar(**{k: data[k] for k in keys}, **kw)


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_known_six_bars_are_recovered_by_the_general_call(seed: int) -> None:
    data = known_six_bar(seed)
    result = _call(data)
    assert all(d.certified for s in result.dyads for d in s)
    best = min(result.designs, key=lambda d: _recovered(d, data["truth"]))
    assert _recovered(best, data["truth"]) < 1e-9
    # it is the mechanism that was swept: every position met in order on its assembly
    assert best.defects.ok, best.defects
    assert best.residual < 1e-9 and best.certified
    r1, r2 = C.residuals(
        best.a1,
        best.b1,
        best.c1,
        best.d1,
        data["points"],
        data["input_angles"],
        data["coupler_angles"],
        data["input_pivot"],
        data["output_pivot"],
    )
    assert np.abs(r1).max() < 1e-9 and np.abs(r2).max() < 1e-9
    # the design's pictures' data: positions and coupler rotations, and a model with P
    assert np.allclose(best.positions, data["points"])
    assert np.allclose(best.coupler_angles, data["coupler_angles"] - data["coupler_angles"][0])
    names = [p[0] for p in best.model().compile()._core.points]
    assert "P" in names and "coupler" in best.model().compile().body_names
    # the pictures' targets: the swept P passes every precision point, and is there at the
    # design's time of each with the prescribed coupler rotation
    dev = best.deviation()
    assert dev.reached is not None and dev.reached.all()
    assert dev.at_position is not None and dev.at_position.max() < 1e-9 * max(best.lengths.values())
    assert dev.angle_error is not None and np.abs(dev.angle_error).max() < 1e-9
    assert dev.nearest.max() <= dev.at_position.max() + 1e-12
    # the elimination recovers it too, and every real dyad it finds is one of the homotopy's
    other = _call(data, method="resultant")
    assert min(_recovered(d, data["truth"]) for d in other.designs) < 1e-9
    for mine, theirs in zip(result.dyads, other.dyads):
        for d in theirs.real:
            assert (
                min(np.hypot(*(d.ground - e.ground)) + np.hypot(*(d.moving - e.moving)) for e in mine.real)
                < 1e-9
            )


# here the elimination's R(z) (resultant.rs) has five roots within 0.03 (local units) of
# the generator's x: clustered, its companion eigenvalue is off by ~1e-3 and the candidate
# is dropped as inconsistent
@pytest.mark.xfail(
    strict=True, reason="the elimination drops a real root of dyad 2 in a cluster of R's roots"
)
def test_the_elimination_recovers_every_known_six_bar() -> None:
    data = known_six_bar(2, linear=True)
    assert min(_recovered(d, data["truth"]) for d in _call(data, method="resultant").designs) < 1e-9


def _problem_file(path: Path, data: dict[str, Any]) -> Path:
    rows = lambda a: "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]" for r in a) + "]"  # noqa: E731
    row = lambda a: "[" + ", ".join(repr(float(v)) for v in a) + "]"  # noqa: E731
    path.write_text(
        'problem = "chained-six-bar"\n'
        f"points = {rows(data['points'])}\n"
        f"input_angles = {row(data['input_angles'])}\n"
        f"coupler_angles = {row(data['coupler_angles'])}\n"
        f"input_pivot = {row(data['input_pivot'])}\n"
        f"output_pivot = {row(data['output_pivot'])}\n"
    )
    return path


def _cli_designs(problem: Path, out: Path) -> list[dict[str, np.ndarray]]:
    """Every design `linkwork synth` writes: its pins at position 1, read from the files."""
    from linkwork.cli import main

    main(["synth", str(problem), "--out", str(out)])
    found = []
    for path in sorted(out.glob(f"{problem.stem}_design*.toml")):
        joints = linkwork.Mechanism.load(path).to_dict()["joints"]
        found.append({j["name"]: np.array(j["at"]) for j in joints if "at" in j})
    return found


def test_known_six_bars_are_recovered_by_the_cli_and_a_changed_file_changes_the_answer(
    tmp_path, capsys
) -> None:  # type: ignore[no-untyped-def]
    one, two = known_six_bar(5), known_six_bar(6)
    for k, (data, other) in enumerate(((one, two), (two, one))):
        designs = _cli_designs(_problem_file(tmp_path / f"six_bar_{k}.toml", data), tmp_path / f"out{k}")
        assert designs

        def off(d: dict[str, np.ndarray], truth: tuple[np.ndarray, ...]) -> float:
            return max(float(np.hypot(*(d[n] - t))) for n, t in zip("ABCD", truth))

        assert min(off(d, data["truth"]) for d in designs) < 1e-9
        assert min(off(d, other["truth"]) for d in designs) > 1e-3
        # the input pivot and the output pivot are the file's
        assert all(
            np.allclose(d["Q"], data["input_pivot"]) and np.allclose(d["O"], data["output_pivot"])
            for d in designs
        )
    capsys.readouterr()


def test_cli_names_a_missing_or_ill_shaped_key(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from linkwork.synthesis.cli import solve

    problem = _toml(EXAMPLE)
    for key in ("points", "input_angles", "coupler_angles", "input_pivot", "output_pivot"):
        broken = {k: v for k, v in problem.items() if k != key}
        with pytest.raises(SynthesisError, match=key):
            solve(broken)
    with pytest.raises(SynthesisError, match="output_pivot"):
        solve({**problem, "output_pivot": [1.0, 2.0, 3.0]})
    with pytest.raises(SynthesisError, match="points"):
        solve({**problem, "points": problem["points"][:4]})
    with pytest.raises(SynthesisError, match="torque"):
        solve({**problem, "torque": {"mass": 2.0, "spin": 1.0}})


def test_the_document_example_through_the_general_call() -> None:
    """Today's numbers of docs/synthesis.md from the example file."""
    problem = _toml(EXAMPLE)
    result = _call(problem, angles=problem["angles"])
    one, two = result.dyads
    assert (len(one), len(one.real), len(two), len(two.real)) == (4, 2, 4, 4)
    assert all(d.certified for d in one) and all(d.certified for d in two)
    a1 = sorted(tuple(np.round(d.ground, 4)) for d in one.real)
    assert a1 == [(3.2527, 14.7273), (6.9035, 12.3378)]
    c1 = sorted(tuple(np.round(d.ground, 4)) for d in two.real)
    assert c1 == [(-1.8386, 6.2242), (-1.7833, 2.5939), (4.3551, -0.2606), (41.7196, 14.6947)]
    # the elimination agrees
    r_one, r_two = _call(problem, angles=problem["angles"], method="resultant").dyads
    for s, r in ((one, r_one), (two, r_two)):
        for d in s.real:
            assert (
                min(np.hypot(*(d.ground - e.ground)) + np.hypot(*(d.moving - e.moving)) for e in r.real)
                < 1e-9
            )
    # the torque of the first design that is defect-free and turns fully
    full = [d for d in result.designs if d.defects.ok and d.defects.full_turn]
    assert [tuple(np.round(d.a1, 3)) + tuple(np.round(d.c1, 3)) for d in full[:1]] == [
        (3.253, 14.727, 41.72, 14.695)
    ]
    tq = C.torque(full[0], **problem["torque"])
    peaks = [np.abs(v).max() for v in (tq.phi, tq.theta, tq.total)]
    assert np.allclose(peaks, [277.3, 846.9, 308.9], atol=0.05)
    # inverse dynamics and virtual work agree (multipliers vs energy rate)
    assert np.abs(tq.total - tq.virtual_work).max() < 1e-9 * peaks[2]
    # the mechanism has mobility 2: the engine needs both inputs
    mob = full[0].model().compile().mobility()
    assert (mob.gruebler_dof, mob.dof, mob.dof_driven) == (2, 2, 0)


def test_the_document_example_changed_changes_the_answer() -> None:
    problem = _toml(EXAMPLE)
    base = _call(problem, angles=problem["angles"])
    moved = dict(
        problem, input_pivot=[-8.7, 12.9], points=[*problem["points"][:3], [-8.3, -6.7], problem["points"][4]]
    )
    changed = _call(moved, angles=problem["angles"])
    a_base = {tuple(np.round(d.ground, 6)) for d in base.dyads[0].real}
    a_moved = {tuple(np.round(d.ground, 6)) for d in changed.dyads[0].real}
    assert a_base.isdisjoint(a_moved)
    assert base.report() != changed.report()


def test_six_bar_defects_each_way() -> None:
    """On the document's designs: a branch defect (a limit before position 2), circuit
    defects (positions met on the other assembly), designs that stop at a limit only after
    the last position (defect-free, not turning fully) and ones that turn fully."""
    problem = _toml(EXAMPLE)
    designs = _call(problem, angles=problem["angles"]).designs
    stroke = math.radians(210.0)
    branch = [d for d in designs if d.defects.branch]
    circuit = [d for d in designs if d.defects.circuit]
    after = [d for d in designs if d.defects.ok and not d.defects.full_turn]
    full = [d for d in designs if d.defects.ok and d.defects.full_turn]
    assert (len(branch), len(circuit), len(after), len(full)) == (1, 3, 2, 2)
    assert not any(d.defects.order for d in designs)
    f = branch[0].defects
    assert f.reached == (True, False, False, False, False) and f.stopped is not None and f.stopped < stroke
    assert f.events[0][0] == "limit" and "branch: limit at input rotation" in f.where()
    for d in circuit:
        g = d.defects
        assert not g.branch and not all(g.reached)
        wrong = [e for e, r in zip(g.error, g.reached) if not r]
        assert min(wrong) > 1.0 and "circuit: met on the other assembly at P" in g.where()
    for d in after:
        g = d.defects
        assert all(g.reached) and max(g.error) < 1e-12
        assert g.stopped is not None and stroke < g.stopped < 2.0 * math.pi
        assert "does not turn fully" in str(g) and str(g).startswith("defect-free")
    for d in full:
        assert d.defects.stopped is None and not d.defects.events and "turns fully" in str(d.defects)
    # the report says which property fails and where, for every combination, by role
    report = _call(problem, angles=problem["angles"]).report()
    assert report.count("circuit: met on the other assembly") == 3 and "ground" not in report
    for pin in ("A1 (on QA)", "B1 (on the coupler)", "C1 (on DC)", "D1 (on the coupler)"):
        assert pin in report


def test_order_defect_when_the_positions_are_swapped() -> None:
    """Positions 2 and 3 exchanged: the same dyads solve the equations (their rows are
    the same), but the input meets the positions out of order turning either way."""
    data = known_six_bar(1)
    swapped = dict(data)
    for key in ("points", "input_angles", "coupler_angles"):
        v = np.array(data[key], dtype=float)
        v[[1, 2]] = v[[2, 1]]
        swapped[key] = v
    result = _call(swapped)
    best = min(result.designs, key=lambda d: _recovered(d, data["truth"]))
    assert _recovered(best, data["truth"]) < 1e-9
    assert best.defects.order and not best.defects.ok and "order:" in best.defects.where()
    assert _call(data).designs[0].defects.ok


def test_a_singular_event_within_the_stroke_is_a_branch_defect(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """A bifurcation the sweep passes on its branch (every position still met) makes the
    stroke defective when it comes before the last position, not when it comes after."""
    from linkwork.model.compiled import Model
    from linkwork.model.events import Event

    problem = _toml(EXAMPLE)
    design = next(d for d in _call(problem, angles=problem["angles"]).designs if d.defects.full_turn)
    assert design.defects.ok
    sweep = Model.sweep

    for at, defective in ((1.0, True), (5.0, False)):

        def with_event(self, *args, at=at, **kw):  # type: ignore[no-untyped-def]
            res = sweep(self, *args, **kw)
            res.events.append(
                Event("bifurcation", 1, at, np.zeros(1), 0.0, (), (), None, (), "assembly branches meet")
            )
            return res

        monkeypatch.setattr(Model, "sweep", with_event)
        design._defects = None
        f = design.defects
        assert all(f.reached) and max(f.error) < 1e-12
        assert f.branch is defective and f.ok is not defective and not f.full_turn
        assert ("branch: bifurcation at input rotation 57.3 deg before position 3" in f.where()) is defective
        monkeypatch.setattr(Model, "sweep", sweep)


def test_bad_input_is_named() -> None:
    problem = _toml(EXAMPLE)
    with pytest.raises(SynthesisError, match="output_pivot"):
        _call({**problem, "output_pivot": [0.0, math.nan]}, angles="deg")
    with pytest.raises(SynthesisError, match="5 points"):
        _call({**problem, "points": problem["points"][:4]}, angles="deg")
    with pytest.raises(SynthesisError, match="input angles 4 and 5"):
        _call({**problem, "input_angles": [0.0, -45.0, -90.0, -150.0, 210.0]}, angles="deg")
    with pytest.raises(SynthesisError, match="output pivot O"):
        S.dyads("chain2", points=problem["points"], input_angles=[0, 1, 2, 3, 4], coupler_angles=[0] * 5)
    # data no frame brings to unit size: refused by name, not solved in overflowing units
    huge = {**problem, "points": (np.array(problem["points"]) * 1e300).tolist()}
    with pytest.raises(SynthesisError, match="cannot be scaled"):
        _call({**huge, "input_pivot": [-3.7e300, 12.9e300]}, angles="deg")


def test_a_design_is_as_uncertain_as_its_worse_dyad() -> None:
    """`residual` is the larger dyad residual and `certified` needs both dyads certified
    and real (a pytest-only property of `synthesis.DyadDesign`, the four-bar's and the
    six-bar's alike)."""
    import dataclasses

    problem = _toml(EXAMPLE)
    design = _call(problem, angles="deg").designs[0]
    one, two = design.dyads
    assert design.certified and design.residual == max(one.residual, two.residual)
    worse = dataclasses.replace(two, residual=1e-3)
    assert dataclasses.replace(design, dyads=(one, worse)).residual == 1e-3
    assert dataclasses.replace(design, dyads=(worse, one)).residual == 1e-3
    for bad in (dataclasses.replace(two, real=False), dataclasses.replace(two, certified=False)):
        assert not dataclasses.replace(design, dyads=(one, bad)).certified
        assert not dataclasses.replace(design, dyads=(bad, one)).certified
