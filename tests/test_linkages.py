"""Classical outputs of four-bars and slider-cranks (Grashof type, closed-form limits of
motion, circuits, transmission angle, stroke) and assembly modes, against independent
formulas and the closed forms of `linkwork.closed_form`."""

import math
import re

import numpy as np
import pytest

import linkwork as lw
from linkwork import closed_form, examples


def norton_class(g: float, a: float, b: float, c: float) -> str:
    """Norton's table 2-4, written out for the test."""
    links = {"ground": g, "crank": a, "coupler": b, "rocker": c}
    s = min(links, key=links.get)
    total = g + a + b + c
    sl = min(links.values()) + max(links.values())
    if abs(sl - (total - sl)) <= 1e-9 * total:
        return "change point"
    if sl > total - sl:
        return "non-Grashof triple-rocker"
    return {
        "ground": "double-crank",
        "crank": "crank-rocker",
        "coupler": "Grashof double-rocker",
        "rocker": "rocker-crank",
    }[s]


FOUR_BARS = [
    (0.35, 0.20, 0.35, 0.25, 0.0),  # crank-rocker
    (0.10, 0.30, 0.35, 0.25, 0.0),  # drag link
    (0.35, 0.25, 0.35, 0.20, 0.5),  # rocker-crank
    (0.35, 0.30, 0.20, 0.35, 1.2),  # Grashof double-rocker
    (0.40, 0.30, 0.25, 0.20, 0.8),  # non-Grashof
    (0.30, 0.10, 0.30, 0.10, 0.7),  # parallelogram: change point
]


def assembles(g, a, b, c, th, tol=0.0):
    d = math.hypot(a * math.cos(th) - g, a * math.sin(th))
    return abs(b - c) - tol < d < b + c + tol


@pytest.mark.parametrize("dims", FOUR_BARS)
def test_grashof_type_and_closed_form_limits(dims):
    g, a, b, c, th0 = dims
    (fb,) = examples.four_bar(g, a, b, c, theta0=th0).compile().linkages()
    assert fb.kind_of == norton_class(g, a, b, c)
    assert fb.lengths == pytest.approx({"ground": g, "crank": a, "coupler": b, "rocker": c}, rel=1e-12)
    if fb.input_limits is None:
        # a full turn: every crank angle assembles (a change point's lined-up links only
        # touch: up to round-off)
        assert all(assembles(g, a, b, c, th, 1e-15) for th in np.linspace(0, 2 * np.pi, 721)[:-1])
        return
    lo, hi = fb.input_limits
    assert lo < th0 < hi
    # at the limits A is exactly b + c or |b - c| from O4; just inside it assembles
    for end in (lo, hi):
        d = math.hypot(a * math.cos(end) - g, a * math.sin(end))
        assert min(abs(d - (b + c)), abs(d - abs(b - c))) < 1e-12
    assert assembles(g, a, b, c, lo + 1e-6) and assembles(g, a, b, c, hi - 1e-6)
    assert not assembles(g, a, b, c, lo - 1e-6) and not assembles(g, a, b, c, hi + 1e-6)


def test_closed_form_limits_agree_with_the_numerical_search():
    g, a, b, c, th0 = 0.40, 0.30, 0.25, 0.20, 0.8
    model = examples.four_bar(g, a, b, c, theta0=th0).compile()
    (fb,) = model.linkages()
    numeric = model.motion_limits()
    # the search locates a limit where Newton stops converging: to ~1e-9 in the input
    assert numeric.lower == pytest.approx(fb.input_limits[0], abs=1e-8)
    assert numeric.upper == pytest.approx(fb.input_limits[1], abs=1e-8)


def test_slider_crank_outputs():
    model = examples.slider_crank(crank=0.1, rod=0.35, offset=0.02).compile()
    (sc,) = model.linkages()
    assert sc.kind == "slider-crank" and sc.kind_of == "crank turns" and sc.input_limits is None
    assert sc.lengths["crank"] == pytest.approx(0.1, rel=1e-12)
    assert sc.lengths["rod"] == pytest.approx(0.35, rel=1e-12)
    assert abs(sc.lengths["offset"]) == pytest.approx(0.02, rel=1e-12)
    # the stroke against a sweep of one revolution (its extremes at the toggles)
    res = model.sweep(np.linspace(0, 2 * np.pi / 5, 20001))
    x = res.body("slider").x
    stroke = math.sqrt(0.45**2 - 0.02**2) - math.sqrt(0.25**2 - 0.02**2)
    assert sc.stroke[1] - sc.stroke[0] == pytest.approx(stroke, rel=1e-12)
    assert x.max() - x.min() == pytest.approx(stroke, rel=1e-6)  # grid resolution


def test_slider_crank_whose_crank_rocks_has_closed_form_limits():
    r, length, e = 0.1, 0.08, 0.0
    m = lw.Mechanism("short rod")
    th0 = 0.3
    A = (r * math.cos(th0), r * math.sin(th0))
    B = (A[0] + math.sqrt(length * length - (A[1] - e) ** 2), e)
    crank = m.link("crank", (0, 0), A)
    rod = m.link("rod", A, B)
    slider = m.body("slider", B)
    m.revolute(m.ground, crank, (0, 0))
    m.revolute(crank, rod, A)
    m.revolute(rod, slider, B)
    m.prismatic(m.ground, slider, B, (1, 0))
    m.drive_angle(crank, lw.Linear(th0, 1.0))
    model = m.compile()
    (sc,) = model.linkages()
    assert sc.kind_of == "crank rocks"
    lo, hi = sc.input_limits
    assert lo == pytest.approx(-math.asin(length / r), abs=1e-12)
    assert hi == pytest.approx(math.asin(length / r), abs=1e-12)
    numeric = model.motion_limits()
    assert numeric.lower == pytest.approx(lo, abs=1e-8) and numeric.upper == pytest.approx(hi, abs=1e-8)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_branch_choice_follows_the_closed_form_circuit(branch):
    model = examples.four_bar().compile()
    times = np.linspace(0.0, 2 * np.pi / 5, 2001)
    res = model.sweep(times, branch=branch)
    cf = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, 5.0 * times, 5.0, 0.0, branch)
    assert np.allclose(np.sin(res.body("rocker").theta - cf["theta4"]), 0.0, atol=1e-12)
    assert np.allclose(res.body("rocker").thetad, cf["omega4"], rtol=0, atol=1e-10)
    assert model.linkages(q_guess=res.q[-1], t=times[-1])[0].circuit == branch


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_slider_crank_branch_choice(branch):
    model = examples.slider_crank(offset=0.02).compile()
    times = np.linspace(0.0, 1.0, 501)
    res = model.sweep(times, branch=branch)
    cf = closed_form.slider_crank(0.1, 0.35, 0.02, 5.0 * times, 5.0, 0.0, branch)
    assert np.allclose(res.body("slider").x, cf["x"], rtol=0, atol=1e-12)


def test_transmission_angle_over_a_sweep():
    g, a, b, c = 0.35, 0.20, 0.35, 0.25
    times = np.linspace(0.0, 2 * np.pi / 5, 1001)
    res = examples.four_bar(g, a, b, c).compile().sweep(times)
    mu = res.transmission_angle()
    th = 5.0 * times
    d2 = (a * np.cos(th) - g) ** 2 + (a * np.sin(th)) ** 2
    expected = np.arccos((b * b + c * c - d2) / (2 * b * c))  # law of cosines at B
    assert np.allclose(mu, expected, rtol=0, atol=1e-9)
    # the extremes at the crank angles 0 and pi (Norton eq. 4.32)
    assert mu.min() == pytest.approx(math.acos((b * b + c * c - (g - a) ** 2) / (2 * b * c)), abs=1e-9)
    assert mu.max() == pytest.approx(math.acos((b * b + c * c - (g + a) ** 2) / (2 * b * c)), abs=1e-9)


def dyad_count(kind: str, theta0: float) -> int:
    """The six-bar's assembly modes by circle intersections: each of the first loop's two
    circuits, then the dyad C-D-O6 (0 or 2 solutions)."""
    d = examples._SIX_BAR[kind]
    count = 0
    for br in ("open", "crossed"):
        r = closed_form.four_bar(0.35, 0.1, 0.35, 0.3, theta0, 5.0, 0.0, br)
        A = np.array([0.1 * math.cos(theta0), 0.1 * math.sin(theta0)])
        if kind == "watt":
            ang = float(r["theta4"]) + d["c_angle"]
            C = np.array([0.35, 0.0]) + d["c_arm"] * np.array([math.cos(ang), math.sin(ang)])
        else:
            ang = float(r["theta3"]) + d["c_angle"]
            C = A + d["c_arm"] * np.array([math.cos(ang), math.sin(ang)])
        dist = float(np.linalg.norm(C - np.asarray(d["O6"])))
        count += 2 if abs(d["link5"] - d["output"]) < dist < d["link5"] + d["output"] else 0
    return count


@pytest.mark.parametrize("kind", ["watt", "stephenson"])
@pytest.mark.parametrize("theta0", [0.0, 1.0, 2.5, 4.0, 5.5])
def test_six_bar_assembly_modes_match_the_dyad_count(kind, theta0):
    model = examples.six_bar(kind, theta0=theta0).compile()
    modes = model.assembly_modes()
    assert len(modes) == dyad_count(kind, theta0)
    for mode in modes:
        state = model.solve(0.0, q_guess=mode.q)
        assert np.allclose(state.q, mode.q, rtol=0, atol=1e-12)
    # distinct configurations
    qs = np.array([m.q for m in modes])
    for i in range(len(qs)):
        for j in range(i):
            assert np.max(np.abs(np.sin((qs[i] - qs[j]) / 2))) > 1e-6


def test_four_bar_and_slider_crank_have_two_modes_each():
    for build in (examples.four_bar, examples.slider_crank):
        modes = build().compile().assembly_modes()
        assert len(modes) == 2
        assert sorted(next(iter(m.circuits.values())) for m in modes) == ["crossed", "open"]
        assert {m.det_sign for m in modes} == {-1.0, 1.0}


def test_no_mode_where_the_input_cannot_be_reached():
    # a non-Grashof four-bar (crank limits +-1.371 rad) asked for crank angle 2.5
    m = examples.four_bar(0.40, 0.30, 0.25, 0.20, theta0=0.8, omega=5.0)
    modes = m.compile().assembly_modes(t=(2.5 - 0.8) / 5.0)
    assert len(modes) == 0 and modes.converged == 0


def test_unknown_branch_is_a_clear_error():
    with pytest.raises(ValueError, match="no assembly mode"):
        examples.four_bar().compile().sweep(np.linspace(0, 1, 5), branch="sideways")


def test_describe_in_degrees_gives_the_limits_and_transmission_angle_in_degrees():
    """The crank's limits and the transmission angle read in degrees are the radian
    values times 180/pi (a non-Grashof four-bar, whose crank rocks between its limits)."""
    (fb,) = examples.four_bar(0.40, 0.30, 0.25, 0.20, theta0=0.8).compile().linkages()
    lo, hi = fb.input_limits
    text = fb.describe(angles="deg")
    m = re.search(r"crank angle limits (-?[\d.]+) \.\. (-?[\d.]+) deg", text)
    assert m, text
    assert float(m.group(1)) == pytest.approx(math.degrees(lo), abs=5e-5)
    assert float(m.group(2)) == pytest.approx(math.degrees(hi), abs=5e-5)
    t = re.search(r"transmission angle (-?[\d.]+) deg", text)
    assert float(t.group(1)) == pytest.approx(math.degrees(fb.transmission_angle), abs=5e-3)
    rad = re.search(r"crank angle limits (-?[\d.]+) \.\. (-?[\d.]+) rad", fb.describe())
    assert float(rad.group(1)) == pytest.approx(lo, abs=5e-7)


def test_assembly_mode_found_by_each_linkages_circuit():
    """`find` with {linkage: circuit} returns the one mode with exactly those circuits (a
    Watt six-bar: two recognised linkages, four modes, each pair of circuits once)."""
    model = examples.six_bar("watt", theta0=1.0).compile()
    modes = model.assembly_modes()
    names = sorted(next(iter(modes)).circuits)
    assert len(names) == 2, names
    seen = set()
    for m in modes:
        asked = dict(m.circuits)
        found = modes.find(asked)
        assert found.circuits == asked
        assert np.array_equal(found.q, m.q)
        seen.add(tuple(asked[n] for n in names))
    assert len(seen) == len(modes)
    with pytest.raises(ValueError, match="no assembly mode"):
        modes.find({names[0]: "sideways"})
