"""A simulation's load powers (against a closed form and the NumPy reference, and their
sum against the non-conservative work the engine records), its forces summary, its
notebook view, its figures and its interactive page, in the real headless Chromium of
tests/test_page.py."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson

import linkwork as lw
from linkwork.cli import main
from linkwork.model.simulation import Simulation
from linkwork.reference.dynamics import generalized_forces
from linkwork.reference.model import ReferenceModel
from linkwork.view.drawing import Geometry
from test_page import browser, embedded, open_page, problems  # noqa: F401 (browser: a fixture)

K, C, THETA0 = 5.0, 0.3, 0.4  # torsion spring (N m/rad), its damping (N m s/rad), its free angle
MASS, LENGTH = 1.2, 0.8  # the bar: a uniform rod about one end


def damped_pendulum() -> lw.Mechanism:
    """A bar pinned at one end to the ground, under gravity, held by a torsion
    spring-damper to the ground: I_O theta'' = -m g (l/2) cos theta - K (theta - THETA0) - C w."""
    m = lw.Mechanism("damped pendulum")
    bar = m.link("bar", (0.0, 0.0), (LENGTH, 0.0), mass=MASS)
    m.revolute(m.ground, bar, at=(0.0, 0.0), name="O")
    m.torsion_spring(m.ground, bar, stiffness=K, damping=C, free_angle=THETA0, name="coil")
    m.point("tip", bar, (LENGTH, 0.0))
    m.set_gravity((0.0, -9.81))
    return m


def simulate(mechanism: lw.Mechanism, t1: float = 3.0, rows: int = 601, **kw: float) -> Simulation:
    times = np.linspace(0.0, t1, rows)
    return mechanism.compile(free=True).simulate(times, rtol=1e-11, atol=1e-11, **kw)


# -- load powers ----------------------------------------------------------------------------


def test_a_torsion_spring_dampers_power_is_its_closed_form() -> None:
    sim = simulate(damped_pendulum())
    theta, w = sim.body("bar").theta, sim.body("bar").thetad
    assert np.ptp(theta) > 0.5 and np.abs(w).max() > 1.0  # it swings
    (name, power), *others = sim.load_powers().items()
    assert name == "coil" and others == []
    # -(K (theta - THETA0) + C w) w: the spring's and the damper's parts, to rounding
    exact = -(K * (theta - THETA0) + C * w) * w
    assert np.abs(power - exact).max() < 1e-13 * np.abs(exact).max()
    np.testing.assert_array_equal(sim.load_power, power)


def test_the_loads_power_adds_up_to_the_recorded_work() -> None:
    """What is not conservative in the load power (here the damper's -C w^2; the
    spring's elastic part is the rate of its potential) integrated over time is the work
    the engine integrated along the motion: W_nc(t) = int P dt + V_spring(t) - V_spring(0)."""
    sim = simulate(damped_pendulum(), t1=3.0, rows=3001)
    e = sim.energy()
    theta, w = sim.body("bar").theta, sim.body("bar").thetad
    spring = 0.5 * K * (theta - THETA0) ** 2
    work = cumulative_simpson(sim.load_power, x=sim.times, initial=0.0) + spring - spring[0]
    # measured 2.2e-10 J (Simpson's h^4 error: 1.1e-6 J on 10 ms rows) against 0.62 J
    # dissipated; the engine's own balance error is 3e-10 J
    assert -e.work[-1] > 0.5
    assert np.abs(work - e.work).max() < 1e-9, np.abs(work - e.work).max()
    # and the damper's part alone is -C w^2
    damper = sim.load_power + K * (theta - THETA0) * w
    assert np.abs(damper + C * w * w).max() < 1e-12 * (C * w * w).max()


def test_with_a_driver_the_work_is_the_loads_and_the_drivers_power() -> None:
    """An arm whose shoulder is driven and elbow free (a torsion spring-damper and a
    constant torque on the forearm): W_nc = int (load power + driver power) dt plus the
    spring's potential change, the driver's power from its effort (`Simulation.power`)."""
    m = lw.Mechanism("arm")
    upper = m.link("upper", (0.0, 0.0), (0.5, 0.0), mass=1.0)
    lower = m.link("lower", (0.5, 0.0), (0.9, 0.0), mass=0.5)
    m.revolute(m.ground, upper, at=(0.0, 0.0), name="O")
    m.revolute(upper, lower, at=(0.5, 0.0), name="A")
    m.drive_angle(upper, lw.Harmonic(0.0, 0.5, 3.0), name="shoulder")
    m.torsion_spring(upper, lower, stiffness=3.0, damping=0.2, name="elbow")
    m.torque(lower, lw.Constant(0.4), name="motor")
    m.set_gravity((0.0, -9.81))
    sim = simulate(m, t1=2.0, rows=2001)
    assert sim.model.dof == 1
    turn = sim.body("lower").theta - sim.body("upper").theta
    spring = 0.5 * 3.0 * turn**2
    power = sim.load_power + sim.power("shoulder")
    work = cumulative_simpson(power, x=sim.times, initial=0.0) + spring - spring[0]
    e = sim.energy()
    # measured 4.9e-10 J against 0.73 J of work
    assert abs(e.work[-1]) > 0.5 and np.abs(work - e.work).max() < 2e-9
    # the torque's power is its closed form, torque x the forearm's rate
    np.testing.assert_allclose(sim.load_powers()["motor"], 0.4 * sim.body("lower").thetad, rtol=1e-14, atol=0)
    lines = [line.split()[0] for line in sim.forces_summary().splitlines()[2:]]
    assert lines == ["O", "A", "shoulder", "elbow", "motor", "work", "energy"]


def every_load() -> lw.Mechanism:
    """A double pendulum in mm and deg under gravity with one load of every kind: a force
    of a harmonic magnitude, a torque growing linearly, a spring-damper to the ground and
    a torsion spring-damper between the two bars."""
    m = lw.Mechanism("every load")
    m.units = {"length": "mm", "angle": "deg"}
    upper = m.link("upper", (0.0, 0.0), (300.0, 0.0), mass=1.0)
    lower = m.link("lower", (300.0, 0.0), (300.0, -200.0), mass=0.6)
    m.revolute(m.ground, upper, at=(0.0, 0.0), name="O")
    m.revolute(upper, lower, at=(300.0, 0.0), name="A")
    m.force(lower, (300.0, -150.0), (1.0, 0.5), lw.Harmonic(0.0, 2.0e3, 7.0), name="push")
    m.torque(upper, lw.Linear(1.0e5, -2.0e5), name="motor")
    m.spring(m.ground, (150.0, 150.0), lower, (300.0, -200.0), stiffness=8.0, damping=0.05, name="cord")
    m.torsion_spring(upper, lower, stiffness=2.0e3, damping=40.0, name="knee")
    m.set_gravity((0.0, -9810.0))
    return m


def test_each_loads_power_against_the_numpy_reference() -> None:
    mech = every_load()
    sim = simulate(mech, t1=1.0, rows=101)
    desc = mech.to_dict()
    powers = sim.load_powers()
    assert list(powers) == ["push", "motor", "cord", "knee"]
    for ld in desc["loads"]:
        ref = ReferenceModel(dict(desc, loads=[ld]))
        assert list(ref.columns) == sim.columns
        expected = np.array(
            [generalized_forces(ref, q, qd, t)["loads"] @ qd for t, q, qd in zip(sim.times, sim.q, sim.qd)]
        )
        scale = np.abs(expected).max()
        assert scale > 0.0, ld["name"]
        assert np.abs(powers[ld["name"]] - expected).max() < 1e-12 * scale, ld["name"]
    # every kind of load does work on this motion, and they add up to load_power
    np.testing.assert_allclose(sim.load_power, sum(powers.values()), rtol=0, atol=1e-9 * scale)


def test_a_model_without_loads_has_zero_load_power() -> None:
    from linkwork.mechanism import benchmarks

    sim = benchmarks.pendulum().mechanism.compile(free=True).simulate(np.linspace(0.0, 1.0, 11))
    assert sim.load_powers() == {}
    np.testing.assert_array_equal(sim.load_power, np.zeros(11))


# -- text -----------------------------------------------------------------------------------


def test_forces_summary_gives_the_extremes_and_their_times() -> None:
    sim = simulate(damped_pendulum(), rows=301)
    text = sim.forces_summary()
    lines = {line.split()[0]: line.split() for line in text.splitlines()[2:]}
    force = np.hypot(*sim.reaction("O").force.T)
    power = sim.load_powers()["coil"]
    for key, v, unit in (("O", force, "N"), ("coil", power, "W")):
        row = lines[key]
        i, j = int(np.argmax(v)), int(np.argmin(v))
        assert [float(x) for x in row[2:6]] == pytest.approx(
            [v[i], sim.times[i], v[j], sim.times[j]], rel=1e-5
        ), key
        assert row[6] == unit
    e = sim.energy()
    assert float(lines["work"][3]) == pytest.approx(e.work[-1], rel=1e-5)
    assert f"within {np.abs(e.balance).max():.2e} J" in text
    # a simulation's summary calls its residual the drift, and says the method
    summary = sim.summary()
    assert "worst scaled residual" not in summary
    assert f"largest drift           {sim.drift.max():.2e}" in summary
    assert f"rk8: {sim.n_steps_taken} steps" in summary


# -- notebook and figures -------------------------------------------------------------------


def test_the_notebook_view_has_the_simulations_numbers_and_plots() -> None:
    sim = simulate(damped_pendulum(), rows=201)
    html = sim._repr_html_()
    e = sim.energy()
    assert f"{sim.n_steps_taken} steps ({sim.n_rejected} rejected)" in html
    assert f"within {np.abs(e.balance).max():.2e} J" in html
    assert f"{sim.drift.max():.2e} (positions)" in html
    assert f"{e.work[-1]:.6g} J by t = 3 s" in html
    alts = re.findall(r'<img alt="([^"]*)"', html)
    assert alts == [
        "damped pendulum: outputs over time and paths",
        "damped pendulum: energy, balance error and drift over time",
    ]
    # a sweep's view is unchanged: one picture, no energy
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 21))
    assert len(re.findall("<img", res._repr_html_())) == 1 and "energy" not in res._repr_html_()


def test_plot_energy_writes_a_png(tmp_path) -> None:
    sim = simulate(damped_pendulum(), rows=201)
    sim.plot_energy(str(tmp_path / "e.png"))
    from PIL import Image

    with Image.open(tmp_path / "e.png") as im:
        assert im.size == (1210, 825)
        # not blank: the lines of four panels
        assert len(np.unique(np.asarray(im.convert("L")))) > 50


# -- the page -------------------------------------------------------------------------------


def test_the_page_embeds_the_simulations_energy_drift_and_rates(tmp_path) -> None:
    sim = simulate(damped_pendulum(), rows=241)
    d = embedded(sim.to_html(tmp_path / "p.html"))
    e = sim.energy()
    assert d["steps"] == list(range(241)) and d["times"] == sim.times.tolist()
    charts = {c["title"]: {line["name"]: line["value"] for line in c["lines"]} for c in d["charts"]}
    assert list(charts) == ["energy", "energy balance error", "constraint drift before projection", "rates"]
    assert charts["energy"]["kinetic"] == e.kinetic.tolist()
    assert charts["energy"]["potential"] == e.potential.tolist()
    assert charts["energy"]["work not conservative"] == e.work.tolist()
    assert charts["energy balance error"]["balance"] == e.balance.tolist()
    assert charts["constraint drift before projection"]["drift |Phi| (scaled)"] == sim.drift.tolist()
    assert charts["rates"] == {"bar.theta_d": sim.body("bar").thetad.tolist()}
    assert [o["name"] for o in d["outputs"]] == ["bar.theta"]
    # a sweep's page has none
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, 1.0, 21))
    assert embedded(res.to_html())["charts"] == []


def test_the_page_of_a_simulation_in_the_browser(browser, tmp_path) -> None:  # noqa: F811
    from selenium.webdriver.common.by import By

    sim = simulate(damped_pendulum(), rows=241)
    sim.to_html(tmp_path / "sim.html")
    open_page(browser, tmp_path / "sim.html")
    assert browser.title == "damped pendulum"
    # one animation frame per row of the simulation
    assert browser.find_element(By.ID, "lw-slider").get_attribute("max") == "240"
    assert browser.execute_script("return window.linkwork.data.times.length") == 241
    # the plots: the angle, then energy, balance error, drift and the rate
    titles = [h.text for h in browser.find_elements(By.CSS_SELECTOR, "#plots h3")]
    assert titles == [
        "bar.theta [rad] over t [s]",
        "energy [J] over t [s]",
        "energy balance error [J] over t [s]",
        "constraint drift before projection over t [s]",
        "rates [rad/s] over t [s]",
    ]
    # the energy plot draws the simulation's numbers: its polylines' y at each frame
    # map back to kinetic, potential and work through the plot's own scale
    e = sim.energy()
    drawn = browser.execute_script(
        "const box = [...document.querySelectorAll('#plots .plot')][1];"
        "return [...box.querySelectorAll('polyline')].map(p => [p.dataset.name, p.getAttribute('points')])"
    )
    assert [name for name, _ in drawn] == ["kinetic", "potential", "work not conservative"]
    lo = min(e.kinetic.min(), e.potential.min(), e.work.min())
    hi = max(e.kinetic.max(), e.potential.max(), e.work.max())
    for (name, points), v in zip(drawn, (e.kinetic, e.potential, e.work)):
        xy = np.array([p.split(",") for p in points.split()], dtype=float)
        assert len(xy) == 241, name
        assert np.abs(xy[:, 0] - (46 + 348 * sim.times / sim.times[-1])).max() < 1e-9
        assert np.abs(xy[:, 1] - (8 + 122 * (hi - v) / (hi - lo))).max() < 1e-9, name
    # the live values follow the slider
    browser.execute_script("window.linkwork.show(120)")
    cells = {
        r.find_elements(By.TAG_NAME, "td")[0].text: r.find_elements(By.TAG_NAME, "td")[1].text
        for r in browser.find_elements(By.CSS_SELECTOR, "#values tbody tr")
    }
    assert float(cells["kinetic"].split()[0]) == pytest.approx(e.kinetic[120], rel=1e-5)
    assert float(cells["bar.theta"].split()[0]) == pytest.approx(sim.body("bar").theta[120], rel=1e-5)
    assert "simulation (rk8" in browser.find_element(By.CSS_SELECTOR, ".span").text
    # the drawing moves with the simulated motion
    tip = browser.execute_script(
        "const c = document.querySelector('#drawing circle.point[data-name=\"tip\"]');"
        "return [+c.getAttribute('cx'), +c.getAttribute('cy')]"
    )
    assert np.abs(np.array(tip) - sim.point("tip").position[120]).max() < 1e-12
    assert problems(browser) == []


def lid() -> lw.Mechanism:
    """A lid hinged at the origin, pushed by a damped strut from 0.2 m below the hinge to
    0.15 m along the lid (docs/dynamics.md)."""
    m = lw.Mechanism("lid")
    lid = m.link("lid", (0.0, 0.0), (0.6, 0.0), mass=2.0)
    m.revolute(m.ground, lid, at=(0.0, 0.0), name="hinge")
    m.spring(
        m.ground, (0.0, -0.2), lid, (0.15, 0.0), stiffness=800.0, free_length=0.4, damping=40.0, name="strut"
    )
    m.set_gravity((0.0, -9.81))
    return m


def strut_ends(sim: Simulation) -> np.ndarray:
    """(n, 2, 2): the strut's ends, the ground's and the lid's, over the simulation."""
    on_lid = sim.point_at("lid", (0.15, 0.0)).position
    return np.stack([np.broadcast_to([0.0, -0.2], on_lid.shape), on_lid], axis=1)


def test_springs_are_drawn_between_their_points(tmp_path) -> None:
    sim = simulate(lid(), t1=2.0, rows=201)
    ends = strut_ends(sim)
    assert np.ptp(ends[:, 1, 0]) > 0.2  # the lid's end moves
    # SVG: a polyline through the two ends at the time drawn, named by the load
    found = re.findall(
        r'<polyline class="spring" data-name="strut" data-anchors="\d+ \d+" points="([^"]*)"',
        sim.to_svg(t=1.0),
    )
    (points,) = found
    xy = np.array([p.split(",") for p in points.split()], dtype=float)
    assert np.abs(xy - ends[100]).max() < 1e-12
    # matplotlib: a line of the same two points; the lid's outline leaves the strut out
    ax = sim.draw(t=1.0)
    (line,) = [ln for ln in ax.lines if ln.get_linestyle() == ":"]
    assert np.abs(np.column_stack(line.get_data()) - ends[100]).max() < 1e-12
    g = Geometry.from_model(sim.model)
    assert len(g.springs) == 1 and set(g.springs[0]).isdisjoint(g.outlines["lid"])
    # between two rows the motion is not known: said, not solved kinematically
    between = r"t = 1.005 is not a time of the simulation \(nearest: t = 1, row 100\)"
    with pytest.raises(lw.InputError, match=between):
        sim.to_svg(t=1.005)
    # DXF: a line on the layer SPRINGS
    pytest.importorskip("ezdxf")
    import ezdxf

    sim.to_dxf(str(tmp_path / "lid.dxf"), t=1.0)
    (entity,) = ezdxf.readfile(tmp_path / "lid.dxf").modelspace().query('LINE[layer=="SPRINGS"]')
    drawn = np.array([[entity.dxf.start.x, entity.dxf.start.y], [entity.dxf.end.x, entity.dxf.end.y]])
    assert np.abs(drawn - ends[100]).max() < 1e-12


def test_the_page_moves_the_spring_with_the_motion(browser, tmp_path) -> None:  # noqa: F811
    sim = simulate(lid(), t1=2.0, rows=201)
    ends = strut_ends(sim)
    sim.to_html(tmp_path / "lid.html")
    open_page(browser, tmp_path / "lid.html")
    for row in (0, 57, 200):
        browser.execute_script(f"window.linkwork.show({row})")
        points = browser.execute_script(
            "return document.querySelector('#drawing polyline.spring').getAttribute('points')"
        )
        xy = np.array([p.split(",") for p in points.split()], dtype=float)
        assert np.abs(xy - ends[row]).max() < 1e-12, row
    assert problems(browser) == []


def test_linkwork_simulate_writes_the_page(tmp_path, capsys) -> None:
    damped_pendulum().save(tmp_path / "pend.toml")
    argv = ["simulate", str(tmp_path / "pend.toml"), "--t1", "2", "--steps", "101", "--out", str(tmp_path)]
    assert main([*argv, "--page", "--plot"]) == 0
    out = capsys.readouterr().out
    assert "pend.html (open it in a browser)" in out and "pend_energy.png" in out
    d = embedded((tmp_path / "pend.html").read_text(encoding="utf-8"))
    assert len(d["times"]) == 101 and [c["title"] for c in d["charts"]][0] == "energy"
    # a file name of its own
    assert main([*argv, "--page", str(tmp_path / "pages" / "p.html")]) == 0
    assert (tmp_path / "pages" / "p.html").exists()
    assert math.isclose(embedded((tmp_path / "pages" / "p.html").read_text())["times"][-1], 2.0)
