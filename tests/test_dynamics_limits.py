"""Limits of motion in a simulation: a slider's travel given in the model (stopping the run
or reported), a slider-crank's geometric stroke ends, and singular crossings of A02 found
at coarse tolerances, each against a closed form or the exact branch."""

from __future__ import annotations

import math

import numpy as np
import pytest

import linkwork as lw
from linkwork.mechanism import benchmarks
from linkwork.reference import exact

MASS, FORCE = 2.0, 3.0


def pushed_mechanism(travel: tuple[float, float] | None = (-0.1, 0.5)) -> lw.Mechanism:
    """A 2 kg slider on the ground pushed along x by 3 N from rest: x = F t^2 / (2 m)."""
    m = lw.Mechanism("pushed slider")
    s = m.body("slider", mass=MASS, inertia=0.1)
    m.prismatic(m.ground, s, at=(0.0, 0.0), axis=(1.0, 0.0), name="guide", travel=travel)
    m.force(s, (0.0, 0.0), (1.0, 0.0), lw.Constant(FORCE), name="push")
    return m


def pushed_slider(travel: tuple[float, float] | None = (-0.1, 0.5)) -> lw.Model:
    return pushed_mechanism(travel).compile(free=True)


def x_closed(t: np.ndarray | float) -> np.ndarray | float:
    return FORCE * np.square(t) / (2.0 * MASS)


T_MAX = math.sqrt(2.0 * MASS * 0.5 / FORCE)  # x = 0.5, the travel's max


@pytest.mark.parametrize("method", ["rk8", "gen-alpha"])
def test_a_pushed_slider_stops_at_the_end_of_its_travel(method: str) -> None:
    """The run stops where x = 0.5: t* = sqrt(2 m x / F) to 1e-9 s [the root of the slide on
    the interpolant between two steps: ~1e-13 with rk8, whose steps are exact on a
    parabola; gen-alpha, second order, is exact on it too], the rows asked before it kept,
    the event last, its q at the end."""
    model = pushed_slider()
    t = np.linspace(0.0, 2.0, 41)
    sim = model.simulate(t, method=method, rtol=1e-8, atol=1e-8)
    ends = [e for e in sim.events if e.kind == "end_of_travel"]
    assert len(ends) == 1 and sim.events[-1] is ends[0]
    e = ends[0]
    assert abs(e.time - T_MAX) < 1e-9, (e.time, T_MAX)
    assert e.output == "guide" and "max" in e.message and "stops" in e.message
    assert abs(e.q[0] - 0.5) < 1e-9
    kept = t[t <= T_MAX]
    assert np.array_equal(sim.times, kept) and len(kept) < len(t)
    np.testing.assert_allclose(sim.body("slider").x, x_closed(kept), rtol=0, atol=1e-9)
    assert t[e.step - 1] < e.time <= t[e.step]


def test_a_pushed_slider_reported_and_continued_at_its_travel() -> None:
    """at_travel_end="continue": the same event, and the motion goes on as the closed form."""
    model = pushed_slider()
    t = np.linspace(0.0, 2.0, 41)
    sim = model.simulate(t, rtol=1e-10, atol=1e-10, at_travel_end="continue")
    ends = [e for e in sim.events if e.kind == "end_of_travel"]
    assert len(ends) == 1 and abs(ends[0].time - T_MAX) < 1e-9
    assert "goes on" in ends[0].message
    assert len(sim.times) == len(t)
    np.testing.assert_allclose(sim.body("slider").x, x_closed(t), rtol=0, atol=1e-9)
    # pushed the other way it meets the min, -0.1, at sqrt(2 m 0.1 / F)
    m = lw.Mechanism("pulled slider")
    s = m.body("slider", mass=MASS, inertia=0.1)
    m.prismatic(m.ground, s, at=(0.0, 0.0), axis=(1.0, 0.0), name="guide", travel=(-0.1, 0.5))
    m.force(s, (0.0, 0.0), (-1.0, 0.0), lw.Constant(FORCE))
    sim = m.compile(free=True).simulate(t)
    (e,) = sim.events
    assert e.kind == "end_of_travel" and "min" in e.message
    assert abs(e.time - math.sqrt(2.0 * MASS * 0.1 / FORCE)) < 1e-9


def test_travel_is_checked_and_kept_in_the_model_file(tmp_path) -> None:
    """A travel that is not min < max is a ModelError naming the joint; a start outside it
    an InputError; `travel` survives a save and a load; without it, no event."""
    with pytest.raises(lw.ModelError, match="guide.*travel"):
        pushed_slider(travel=(0.5, -0.1))
    model = pushed_slider()
    with pytest.raises(lw.InputError, match="'guide' starts at slide.*outside its travel"):
        model.simulate([0.0, 1.0], q0=[0.7, 0.0, 0.0])
    with pytest.raises(lw.InputError, match="at_travel_end"):
        model.simulate([0.0, 1.0], at_travel_end="bounce")
    path = tmp_path / "slider.toml"
    pushed_mechanism().save(path)
    assert "travel = [-0.1, 0.5]" in path.read_text()
    again = lw.Mechanism.load(path).compile(free=True)
    assert again.simulate(np.linspace(0.0, 1.0, 5)).events[0].kind == "end_of_travel"
    sim = pushed_slider(travel=None).simulate(np.linspace(0.0, 2.0, 5))
    assert not sim.events


def slider_crank(r: float = 0.05, rod_length: float = 0.2) -> lw.Model:
    """An in-line slider-crank with a heavy free crank spun from its top dead centre (no
    gravity): its stroke ends where the crank angle is 0 or pi (mod 2 pi)."""
    m = lw.Mechanism("slider-crank")
    crank = m.link("crank", (0.0, 0.0), (r, 0.0), mass=1.0, inertia=0.05, com=(0.0, 0.0))
    end = r + rod_length
    rod = m.link("rod", (r, 0.0), (end, 0.0), mass=0.3)
    piston = m.body("piston", origin=(end, 0.0), mass=0.5)
    m.revolute(m.ground, crank, at=(0.0, 0.0), name="main")
    m.revolute(crank, rod, at=(r, 0.0), name="crankpin")
    m.revolute(rod, piston, at=(end, 0.0), name="wristpin")
    m.prismatic(m.ground, piston, at=(end, 0.0), axis=(1.0, 0.0), name="cylinder")
    return m.compile(free=True)


def test_a_slider_crank_reports_each_stroke_end_at_the_dead_centres() -> None:
    """Spun at 20 rad/s (the rod and piston make its speed vary), the piston stops and
    reverses at every dead centre: one "lock" of the cylinder each half turn, where the
    crank angle is k pi to 1e-6 rad [3.2e-7 measured: the rate's zero on the interpolant
    between steps] and the slide is the closed form's extreme (0 at the outer, -2 r at the
    inner dead centre) to 1e-9; no event otherwise."""
    r, rod = 0.05, 0.2
    model = slider_crank(r, rod)
    t = np.linspace(0.0, 1.0, 101)
    sim = model.simulate(t, rtol=1e-10, atol=1e-10, qd0={"main": 20.0})
    theta = np.unwrap(sim.body("crank").theta)
    half_turns = int(theta[-1] // math.pi)
    assert half_turns >= 5
    locks = [e for e in sim.events if e.kind == "lock"]
    assert len(locks) == len(sim.events) == half_turns
    col = model.columns.index("crank.theta")
    for k, e in enumerate(locks, start=1):
        assert e.output == "cylinder" and "end of its stroke" in e.message
        assert abs(e.q[col] - k * math.pi) < 1e-6, (k, e.q[col] - k * math.pi)
        x = r * math.cos(e.q[col]) + math.sqrt(rod**2 - (r * math.sin(e.q[col])) ** 2) - (r + rod)
        slide = float(e.message.split("slide ")[1].split(")")[0])
        assert abs(slide - x) < 1e-9 and abs(x - (0.0 if k % 2 == 0 else -2 * r)) < 1e-9


def test_a_slider_turned_by_its_spring_is_not_a_stroke_end() -> None:
    """A slider on a spring beside a free wheel that spins on: the slider reverses under its
    spring where the joints would let it go on, so no lock is reported (nor a whole-motion
    lock: the wheel never stops)."""
    m = lw.Mechanism("spring slider and wheel")
    s = m.body("slider", origin=(0.0, 0.0), mass=1.0, inertia=0.1)
    w = m.body("wheel", origin=(1.0, 0.0), mass=1.0, inertia=0.1)
    m.prismatic(m.ground, s, at=(0.0, 0.0), axis=(1.0, 0.0), name="guide")
    m.revolute(m.ground, w, at=(1.0, 0.0), name="axle")
    m.spring(m.ground, (-1.0, 0.0), s, (0.0, 0.0), stiffness=100.0, free_length=1.1)
    model = m.compile(free=True)
    sim = model.simulate(np.linspace(0.0, 2.0, 21), qd0={"axle": 3.0, "guide": 0.0})
    x = sim.body("slider").x
    assert np.count_nonzero(np.diff(np.sign(np.diff(x)))) >= 4  # it does reverse
    assert not sim.events


def _a02_crossings() -> np.ndarray:
    """The exact N = 2 branch's singular configurations in 10 s (the cranks horizontal)."""
    from scipy.optimize import brentq

    branch = exact.n_four_bar_branch(2, 10.0)
    grid = np.linspace(0.0, 10.0, 4001)
    s = np.sin(branch.phi(grid)[0])
    return np.array(
        [
            brentq(lambda x: np.sin(branch.phi(x)[0]), grid[i], grid[i + 1], xtol=1e-14)
            for i in np.nonzero(np.diff(np.sign(s)))[0]
        ]
    )


@pytest.mark.parametrize("rtol", [1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6, 1e-7])
def test_a02_coarse_tolerances_report_every_crossing(rtol: float) -> None:
    """N = 2 over 10 s: at coarse tolerances too all ten crossings are reported, each
    within 1e3 rtol of the exact branch's [below 50 rtol measured], and nothing else."""
    bench = benchmarks.n_four_bar(2)
    model = bench.mechanism.compile(free=True)
    sim = model.simulate(np.linspace(0.0, 10.0, 201), rtol=rtol, atol=rtol, qd0=bench.qd0)
    crossings = _a02_crossings()
    assert len(crossings) == 10
    events = [e for e in sim.events if e.kind == "bifurcation"]
    assert len(events) == len(sim.events)
    assert len(events) == 10
    for e in events:
        assert np.abs(crossings - e.time).min() <= 1e3 * rtol, (rtol, e.time)


def test_a02_a_row_at_a_crossing_is_projected_onto_the_constraints() -> None:
    """rtol 3e-3, a row every 0.01 s: the one at t = 8.99 is interpolated 9e-4 off the
    constraints within 1e-3 s of the run's crossing (8.9903 s; the exact branch's 8.9982),
    where the regularised projection stalls; it is still brought onto the constraints,
    and the run goes on (every crossing reported, the cranks together)."""
    bench = benchmarks.n_four_bar(2)
    model = bench.mechanism.compile(free=True)
    sim = model.simulate(np.linspace(0.0, 10.0, 1001), rtol=3e-3, atol=3e-3, qd0=bench.qd0)
    q = sim.q
    assert len(q) == 1001
    # the pins, from the coordinates: crank j about (j, 0) (its frame there), coupler k's
    # frame at its left pin, its right pin one unit along it
    crank = [q[:, 3 * j : 3 * j + 3] for j in range(3)]
    coupler = [q[:, 9 + 3 * k : 12 + 3 * k] for k in range(2)]
    tip = [np.column_stack([j + np.cos(c[:, 2]), np.sin(c[:, 2])]) for j, c in enumerate(crank)]
    gaps = [np.abs(c[:, :2] - [j, 0.0]) for j, c in enumerate(crank)]
    for k, c in enumerate(coupler):
        gaps.append(np.abs(c[:, :2] - tip[k]))
        gaps.append(np.abs(c[:, :2] + np.column_stack([np.cos(c[:, 2]), np.sin(c[:, 2])]) - tip[k + 1]))
    # tol_residual 1e-12 (scaled, L = 1) and the round-off of the check's own sums
    assert max(g.max() for g in gaps) <= 2e-12
    assert sim.drift[899] > 1e-4  # the row did start off the constraints
    assert np.ptp(q[:, 2:9:3], axis=1).max() < 1e-6  # on the branch
    crossings = _a02_crossings()
    events = [e for e in sim.events if e.kind == "bifurcation"]
    assert len(events) == 10
    for e in events:
        assert np.abs(crossings - e.time).min() <= 10 * 3e-3, e.time  # 4.4 rtol measured


def spinning_parallelogram() -> lw.Model:
    """Crank 0.1 and rocker pinned 0.3 apart, a coupler of 0.3: a parallelogram, free, whose
    bars all lie on the ground line (a change point) at crank angles k pi."""
    th = 0.5
    a = [0.1 * math.cos(th), 0.1 * math.sin(th)]
    d = {
        "name": "parallelogram",
        "gravity": [0.0, -9.81],
        "bodies": [
            {"name": "crank", "x": 0.0, "y": 0.0, "theta": th, "mass": 0.4, "inertia": 0.002},
            {"name": "coupler", "x": a[0], "y": a[1], "theta": 0.0, "mass": 1.1, "inertia": 0.01},
            {"name": "rocker", "x": 0.3, "y": 0.0, "theta": th, "mass": 0.7, "inertia": 0.003},
        ],
        "joints": [
            {"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler", "at": a},
            {
                "type": "revolute",
                "name": "B",
                "body_a": "coupler",
                "body_b": "rocker",
                "at": [a[0] + 0.3, a[1]],
            },
            {"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.3, 0.0]},
        ],
    }
    return lw.Model(d, free=True)


@pytest.mark.parametrize(
    ("method", "w", "th", "rtol", "dt"),
    [
        # rk8's steps turn the crank 0.5 to 3 rad: crossings inside a step whose ends are
        # far from them, several to a step, and one just before the run's end
        ("rk8", 25.0, 0.5, 1e-8, 0.005),
        ("rk8", 38.8, 0.5, 7.7e-4, 0.1),
        ("rk8", 90.0, 1.0, 1e-4, 0.1),
        ("rk8", 65.4, 0.355, 8e-7, 0.005),
        ("rk8", 113.3, 2.716, 1e-5, 0.02),
        ("gen-alpha", 60.0, 1.0, 1e-5, 0.02),
    ],
)
def test_a_spinning_parallelogram_reports_every_change_point(
    method: str, w: float, th: float, rtol: float, dt: float
) -> None:
    """Spun fast (17 rad/s carries it over the top), the parallelogram passes a change point
    every half turn; every one the crank passes in the second is reported, at crank angle
    k pi within 100 rtol + 1e-5 rad (the events are located on a quintic interpolant between
    the watch's samples; 74 rtol at most measured over 400 random runs), and nothing else.
    Before the watch sampled long steps inside, 183 of 381 such random runs missed some,
    one all 22 (benches/results/dynamics-2026-11-28i.md)."""
    model = spinning_parallelogram()
    q0 = [0.0, 0.0, th, 0.1 * math.cos(th), 0.1 * math.sin(th), 0.0, 0.3, 0.0, th]
    qd0 = [0.0, 0.0, w, -0.1 * w * math.sin(th), 0.1 * w * math.cos(th), 0.0, 0.0, 0.0, w]
    times = np.arange(0.0, 1.0 + 0.5 * dt, dt)
    sim = model.simulate(times, q0=q0, qd0=qd0, rtol=rtol, atol=rtol, method=method)
    crank = sim.q[:, 2]
    passed = list(range(math.floor(th / math.pi) + 1, math.floor(crank[-1] / math.pi) + 1))
    assert len(passed) >= 6
    assert [e.kind for e in sim.events] == ["bifurcation"] * len(passed)
    for k, e in zip(passed, sim.events):
        assert abs(e.q[2] - k * math.pi) < 100 * rtol + 1e-5, (k, e.q[2] - k * math.pi)
        # the rows either side of it bracket the crossing
        assert crank[e.step - 1] <= k * math.pi <= crank[e.step]
