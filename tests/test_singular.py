"""Hard cases of mechanism analysis: change points, toggles, dead points, near-singular
grids, units, long chains and unreachable drivers. Each checks geometry, not just that
nothing crashed."""

import numpy as np
import pytest

import linkwork as lw
from linkwork import examples

PI = np.pi


def parallelogram(scale: float = 1.0, theta0: float = 0.5) -> lw.Mechanism:
    """Ground = coupler = 0.3, crank = rocker = 0.1 (times ``scale``), drawn as a
    parallelogram; crank at theta0 + t."""
    r1, r2 = 0.3 * scale, 0.1 * scale
    a = (r2 * np.cos(theta0), r2 * np.sin(theta0))
    m = lw.Mechanism("parallelogram")
    m.body("crank", (0.0, 0.0), theta0)
    m.body("coupler", a, 0.0)
    m.body("rocker", (r1, 0.0), theta0)
    m.revolute("ground", "crank", (0.0, 0.0), name="O2")
    m.revolute("crank", "coupler", a, name="A")
    m.revolute("coupler", "rocker", (r1 + a[0], a[1]), name="B")
    m.revolute("ground", "rocker", (r1, 0.0), name="O4")
    m.drive_angle("crank", lw.Linear(theta0, 1.0), name="crank_angle")
    return m


@pytest.mark.parametrize("offset", [1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 0.0])
@pytest.mark.parametrize("derivatives", [0, 2])
def test_a_parallelogram_stays_one_through_its_change_points(offset, derivatives):
    # a coarse grid with one step placed `offset` after the first change point (crank
    # angle pi): the rates solved there are ill-determined, the next prediction must not
    # follow them onto the antiparallelogram branch
    t_change = PI - 0.5
    times = np.sort(np.r_[np.linspace(0.0, 2 * PI, 13), t_change + offset])
    r = parallelogram().compile().sweep(times, derivatives=derivatives)
    crank, coupler, rocker = r.q[:, 2], r.q[:, 5], r.q[:, 8]
    # the coupler only translates; next to a singular point q is known to about
    # sqrt(eps) times the mechanism's size, elsewhere to round-off
    near = np.abs(r.times - t_change) < 1e-6
    assert np.abs(np.sin(coupler[~near])).max() < 1e-7
    assert np.abs(np.sin(coupler[near])).max(initial=0.0) < 1e-4
    assert np.abs(np.sin(rocker - crank)).max() < 1e-4
    changes = [e.time for e in r.events if e.kind == "bifurcation"]
    assert len(changes) == 2 and len(r.events) == 2
    assert np.allclose(changes, [PI - 0.5, 2 * PI - 0.5], atol=1e-6)


def test_stop_at_a_change_point_keeps_the_good_steps():
    times = np.linspace(0.0, 4.0, 41)
    with pytest.raises(lw.SingularError, match="branches meet") as info:
        parallelogram().compile().sweep(times, on_singular="stop")
    err = info.value
    assert err.step == int(np.searchsorted(times, PI - 0.5))
    assert abs(err.time - (PI - 0.5)) < 1e-6
    assert len(err.partial) == err.step and np.all(np.isfinite(err.partial.qdd))
    assert [e.kind for e in err.partial.events] == ["bifurcation"]
    # the dependency is among the four pins; the driver is not part of it
    assert {n for n, _ in err.partial.events[0].constraints} <= {"O2", "A", "B", "O4"}


@pytest.mark.parametrize("gap", [1e-4, 1e-5, 1e-6])
@pytest.mark.parametrize("steps_per_rev", [8, 10, 25])
def test_branches_that_pass_close_are_not_confused(gap, steps_per_rev):
    # a Grashof crank-rocker next to a change point (rocker = crank + gap): its open and
    # crossed branches pass within about sqrt(gap) of each other once a turn; coarse
    # grids must still follow the branch a fine grid follows
    model = examples.four_bar(ground=0.3, crank=0.1, coupler=0.3, rocker=0.1 + gap, theta0=0.5, omega=1.0)
    model = model.compile()
    fine = model.sweep(np.linspace(0.0, 4 * PI, 200_001), derivatives=0)
    n = 2 * steps_per_rev
    coarse = model.sweep(np.linspace(0.0, 4 * PI, n + 1))
    rows = np.arange(n + 1) * (200_000 // n)
    assert np.abs(np.sin(coarse.q - fine.q[rows])).max() < 1e-10
    assert coarse.events == [] and fine.events == []


def test_slider_crank_with_crank_equal_to_rod_passes_its_toggle():
    # crank = rod, no offset: at crank angles pi/2 and 3 pi/2 the slider pin reaches the
    # crank pivot, where the branch x = 2 r cos(theta) meets the branch x = 0
    r = 0.1
    m = examples.slider_crank(crank=r, rod=r, offset=0.0, theta0=0.3, omega=1.0)
    res = m.compile().sweep(np.linspace(0.0, 2 * PI, 181), locks=True)
    theta = 0.3 + res.times
    x = res.body("slider").x
    near = np.abs(np.cos(theta)) < 1e-6
    assert np.abs(x - 2 * r * np.cos(theta))[~near].max() < 1e-12
    toggles = [e.time + 0.3 for e in res.events if e.kind == "bifurcation"]
    assert np.allclose(toggles, [PI / 2, 3 * PI / 2], atol=1e-6)
    # the slider's dead centres, crank along the slide (x = -2r, then 2r)
    locks = [e.time + 0.3 for e in res.events if e.kind == "lock"]
    assert np.allclose(locks, [PI, 2 * PI], atol=1e-10)


def test_a_slider_driven_past_its_dead_centre_stops_with_the_limit_located():
    # drive the slider of a slider-crank outwards: at x = crank + rod the crank and rod
    # are stretched and the slider cannot go further
    m = examples.slider_crank(crank=0.10, rod=0.35, offset=0.0, theta0=1.0)
    x0 = m.to_dict()["joints"][2]["at"][0]
    m.remove("crank_angle")
    m.drive_coordinate("slider", (x0, 0.0), "x", lw.Harmonic(x0, 0.2, 1.0), name="piston")
    times = np.linspace(0.0, 3.0, 301)
    with pytest.raises(lw.SingularError, match="limit of motion") as info:
        m.compile().sweep(times)
    err = info.value
    t_limit = np.arcsin((0.45 - x0) / 0.2)
    assert abs(err.time - t_limit) < 1e-9
    assert np.all(np.isfinite(err.partial.q)) and np.all(np.isfinite(err.partial.qdd))
    assert err.partial.events[-1].kind == "limit"
    assert abs(err.partial.events[-1].driver("piston") - 0.45) < 1e-9


@pytest.mark.parametrize(
    "lengths, expected",
    [
        # non-Grashof: the input rocks between the angles where the diagonal reaches
        # coupler + rocker
        ((0.40, 0.30, 0.25, 0.20), "rocks"),
        ((0.35, 0.20, 0.35, 0.25), "turns"),
    ],
)
def test_motion_limits_of_a_crank(lengths, expected):
    ground, crank, coupler, rocker = lengths
    model = examples.four_bar(ground=ground, crank=crank, coupler=coupler, rocker=rocker, omega=1.0).compile()
    lim = model.motion_limits()
    if expected == "turns":
        assert lim.full_rotation and lim.lower is None and lim.upper is None
        return
    limit = np.arccos((ground**2 + crank**2 - (coupler + rocker) ** 2) / (2 * ground * crank))
    assert not lim.full_rotation
    assert abs(lim.upper - limit) < 1e-9 and abs(lim.lower + limit) < 1e-9
    assert "rad" in str(lim)


def test_motion_limits_of_a_slider_match_the_triangle_inequalities():
    crank, rod, offset = 0.10, 0.35, 0.05
    m = examples.slider_crank(crank=crank, rod=rod, offset=offset, theta0=1.0)
    x0 = m.to_dict()["joints"][2]["at"][0]
    m.remove("crank_angle")
    m.drive_coordinate("slider", (x0, offset), "x", lw.Constant(x0), name="piston")
    lim = m.compile().motion_limits()
    lo = np.sqrt((rod - crank) ** 2 - offset**2)
    hi = np.sqrt((rod + crank) ** 2 - offset**2)
    assert abs(lim.lower - lo) < 1e-9 and abs(lim.upper - hi) < 1e-9


def test_units_do_not_change_the_events():
    times = np.linspace(0.0, 2 * PI, 90)
    metres = parallelogram(1.0).compile().sweep(times)
    millimetres = parallelogram(1000.0).compile().sweep(times)
    assert [e.kind for e in metres.events] == [e.kind for e in millimetres.events]
    assert np.allclose([e.time for e in metres.events], [e.time for e in millimetres.events], atol=1e-7)
    angles = [3 * i + 2 for i in range(3)]
    assert np.abs(metres.q[:, angles] - millimetres.q[:, angles]).max() < 1e-10
    assert np.array_equal(metres.det_sign, millimetres.det_sign)


def test_a_long_chain_sweeps_without_events():
    model = examples.chain(200).compile()
    res = model.sweep(np.linspace(0.0, 0.5, 51))
    assert res.events == [] and np.all(res.det_sign == res.det_sign[0])
    assert res.residual.max() < 1e-12


def test_a_driver_asking_for_an_unreachable_start_names_it():
    m = examples.slider_crank(crank=0.10, rod=0.35, offset=0.0, theta0=1.0)
    x0 = m.to_dict()["joints"][2]["at"][0]
    m.remove("crank_angle")
    m.drive_coordinate("slider", (x0, 0.0), "x", lw.Constant(0.6), name="piston")
    with pytest.raises(lw.AssemblyError, match="t = 0") as info:
        m.compile().sweep(np.linspace(0.0, 1.0, 11))
    assert info.value.step == 0 and len(info.value.partial) == 0


def test_bad_on_singular_is_an_input_error():
    with pytest.raises(lw.InputError, match="on_singular"):
        examples.four_bar().compile().sweep([0.0, 0.1], on_singular="ignore")
