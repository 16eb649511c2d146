"""The interactive page: what it embeds (self-contained, the sweep's numbers) and, in a
real headless Chromium driven by Selenium, that it loads without a console error, that
its slider, play button and event marks move the drawing to the sweep's configuration
(positions read from the page's SVG), and a screenshot kept in test-artefacts/.

The browser tests need Chromium and its driver from the system's packages
(``apt-get install chromium chromium-driver``; .ci/run installs them) and skip, saying
so, where there are none."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import time
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw

REV = 2 * math.pi / 5.0
ARTEFACTS = Path(__file__).parent.parent / "test-artefacts"
#: seconds any one browser action may take
TIMEOUT = 30


def four_bar(n: int = 241) -> lw.Results:
    return lw.examples.four_bar().compile().sweep(np.linspace(0.0, REV, n))


def four_bar_joints(q: np.ndarray, res: lw.Results) -> dict[str, np.ndarray]:
    """Pins of the textbook four-bar from its coordinates: each bar's frame is at its first
    pin (O2 crank, A coupler, O4 rocker); B is 0.25 m along the rocker."""
    col = {c: q[k] for k, c in enumerate(res.columns)}
    th = col["rocker.theta"]
    return {
        "O2": np.array([col["crank.x"], col["crank.y"]]),
        "A": np.array([col["coupler.x"], col["coupler.y"]]),
        "O4": np.array([col["rocker.x"], col["rocker.y"]]),
        "B": np.array([col["rocker.x"] + 0.25 * math.cos(th), col["rocker.y"] + 0.25 * math.sin(th)]),
    }


def embedded(html: str) -> dict:
    found = re.search(r'<script id="lw-data" type="application/json">(.*?)</script>', html, re.S)
    assert found is not None
    return json.loads(found.group(1).replace("<\\/", "</"))


# -- the file itself ----------------------------------------------------------------------


def test_the_page_is_self_contained_and_embeds_the_sweep(tmp_path):
    res = four_bar(101)
    html = res.to_html(tmp_path / "fb.html", outputs=["rocker", "P.y"], frames=26)
    assert (tmp_path / "fb.html").read_text(encoding="utf-8") == html
    # nothing fetched from anywhere: no external scripts, styles, images or fonts
    assert not re.search(r"<(script|link|img)[^>]+(src|href)=", html)
    assert set(re.findall(r"https?://[^\s\"'<>]+", html)) == {"http://www.w3.org/2000/svg"}  # a name
    d = embedded(html)
    rows = np.unique(np.linspace(0, 100, 26).round().astype(int))
    assert d["steps"] == rows.tolist() and d["times"] == res.times[rows].tolist()
    assert [o["name"] for o in d["outputs"]] == ["rocker.theta", "P.y"]
    assert d["outputs"][1]["rate"] == res.point("P").velocity[rows, 1].tolist()
    (crank,) = d["inputs"]
    assert crank["name"] == "crank_angle" and crank["angle"] and crank["value"] == res.q[rows, 2].tolist()
    assert d["pivot_ratio"] == res.pivot_ratio[rows].tolist()
    assert d["events"][-1]["kind"] == "closest"


def test_inputs_of_distance_coordinate_and_translation_drivers():
    m = lw.Mechanism("lever")
    lever = m.link("lever", (0.0, 0.0), (0.5, 0.0))
    m.revolute(m.ground, lever, (0.0, 0.0), name="O")
    m.drive_distance(
        m.ground, (0.3, -0.2), lever, (0.4, 0.0), lw.Linear(math.hypot(0.1, 0.2), 0.05), name="cyl"
    )
    res = m.compile().sweep(np.linspace(0.0, 1.0, 11))
    (cyl,) = embedded(res.to_html())["inputs"]
    assert cyl["unit"] == "m" and not cyl["angle"]
    assert np.abs(np.array(cyl["value"]) - (math.hypot(0.1, 0.2) + 0.05 * res.times)).max() < 1e-12
    s = lw.Mechanism("slide")
    block = s.body("block", (0.1, 0.0))
    s.prismatic(s.ground, block, (0.1, 0.0), (1.0, 0.0), name="P1")
    s.drive_translation("P1", lw.Linear(0.0, 0.2), name="push")
    res = s.compile().sweep(np.linspace(0.0, 1.0, 11))
    (push,) = embedded(res.to_html())["inputs"]
    assert np.abs(np.array(push["value"]) - 0.2 * res.times).max() < 1e-12


def test_bad_arguments_are_input_errors():
    res = four_bar(11)
    with pytest.raises(lw.InputError, match="'wheel'"):
        res.to_html(outputs=["wheel"])
    with pytest.raises(lw.InputError, match="frames"):
        res.to_html(frames=1)
    with pytest.raises(lw.InputError, match="outputs"):
        res.to_html(outputs="rocker")  # type: ignore[arg-type]
    with pytest.raises(lw.InputError, match="file name"):
        res.to_html(path=5)  # type: ignore[arg-type]


# -- in the browser -----------------------------------------------------------------------


def _chromium() -> tuple[str, str] | str:
    """(browser, driver) paths, or why there are none."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install selenium, or pip install -e '.[test]')"
    browser = next(
        (shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None
    )
    driver = shutil.which("chromedriver")
    if browser is None or driver is None:
        return "no Chromium and chromedriver on the PATH (apt-get install chromium chromium-driver)"
    return browser, driver


@pytest.fixture(scope="module")
def browser():
    found = _chromium()
    if isinstance(found, str):
        pytest.skip(f"browser test skipped: {found}")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--window-size=1400,1200",
    ):
        options.add_argument(arg)
    options.binary_location = found[0]
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(found[1]), options=options)
    driver.set_page_load_timeout(TIMEOUT)
    driver.set_script_timeout(TIMEOUT)
    yield driver
    driver.quit()


def open_page(driver, path: Path) -> None:
    driver.get(path.as_uri())
    driver.get_log("browser")  # (clears the log of anything before this page)
    driver.refresh()
    deadline = time.monotonic() + TIMEOUT
    while not driver.execute_script("return !!(window.linkwork && window.linkwork.data)"):
        assert time.monotonic() < deadline, "the page did not start"
        time.sleep(0.05)


def problems(driver) -> list[dict]:
    return [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]


def drawn_pins(driver) -> dict[str, np.ndarray]:
    """The pins' centres as the page's SVG has them now."""
    raw = driver.execute_script(
        "return [...document.querySelectorAll('#drawing circle.pin')]"
        ".map(c => [c.dataset.name, c.getAttribute('cx'), c.getAttribute('cy')])"
    )
    return {name: np.array([float(x), float(y)]) for name, x, y in raw}


def drawn_point(driver, name: str) -> np.ndarray:
    x, y = driver.execute_script(
        f"const c = document.querySelector('#drawing circle.point[data-name=\"{name}\"]');"
        "return [c.getAttribute('cx'), c.getAttribute('cy')]"
    )
    return np.array([float(x), float(y)])


def keep(driver, tmp_path: Path, name: str) -> Path:
    """A screenshot in the test's folder, copied to test-artefacts/."""
    shot = tmp_path / name
    assert driver.save_screenshot(str(shot))
    ARTEFACTS.mkdir(exist_ok=True)
    shutil.copy(shot, ARTEFACTS / name)
    return shot


def test_the_slider_moves_the_drawing_to_the_sweeps_configuration(browser, tmp_path):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    res = four_bar(241)
    res.to_html(tmp_path / "four_bar.html")
    open_page(browser, tmp_path / "four_bar.html")
    assert browser.title == "four-bar"
    slider = browser.find_element(By.ID, "lw-slider")
    assert slider.get_attribute("max") == "240"

    def check(step: int) -> None:
        assert browser.execute_script("return window.linkwork.frame") == step
        pins = drawn_pins(browser)
        # the page's numbers are the sweep's (shortest round-trip floats in and out)
        for name, xy in four_bar_joints(res.q[step], res).items():
            assert np.abs(pins[name] - xy).max() < 1e-12, (step, name)
        assert np.abs(drawn_point(browser, "P") - res.point("P").position[step]).max() < 1e-12

    check(0)
    # the keyboard, as a person moves it
    slider.click()
    target = int(slider.get_attribute("value"))
    slider.send_keys(Keys.HOME)
    for _ in range(7):
        slider.send_keys(Keys.ARROW_RIGHT)
    check(7)
    assert target > 0  # the click itself moved it: the drawing followed (checked at 7 after HOME)
    # dragged far: the input event the browser sends while dragging
    browser.execute_script(
        "const s = document.getElementById('lw-slider'); s.value = '180';"
        "s.dispatchEvent(new Event('input', {bubbles: true}))"
    )
    check(180)
    # the live values and the plots' cursors follow
    rocker = [
        r
        for r in browser.find_elements(By.CSS_SELECTOR, "#values tbody tr")
        if r.text.startswith("rocker.theta")
    ]
    value = float(rocker[0].find_elements(By.TAG_NAME, "td")[1].text.split()[0])
    assert value == pytest.approx(res.body("rocker").theta[180], rel=1e-5)
    cursors = browser.execute_script(
        "return [...document.querySelectorAll('#plots line[stroke=\"#d62728\"]')]"
        ".map(l => +l.getAttribute('x1'))"
    )
    assert len(cursors) == 3 and len(set(cursors)) == 1
    assert cursors[0] == pytest.approx(46 + (400 - 52) * res.times[180] / res.times[-1])
    # play runs the sweep's time forward, pause stops it
    browser.execute_script("window.linkwork.show(0)")
    browser.find_element(By.ID, "play").click()
    time.sleep(0.6)
    browser.find_element(By.ID, "play").click()
    frame = browser.execute_script("return window.linkwork.frame")
    assert not browser.execute_script("return window.linkwork.playing()")
    assert 0 < frame < 240
    check(frame)
    time.sleep(0.2)
    assert browser.execute_script("return window.linkwork.frame") == frame
    browser.execute_script("window.linkwork.show(60)")
    shot = keep(browser, tmp_path, "page_four_bar.png")
    assert shot.stat().st_size > 20_000
    assert problems(browser) == []


def test_events_are_marked_and_take_the_drawing_there(browser, tmp_path):
    from selenium.webdriver.common.by import By

    # crank = rod: the slider's pin passes the crank pivot twice (bifurcations) and the
    # slider reverses twice (locks)
    m = lw.examples.slider_crank(crank=0.1, rod=0.1, offset=0.0, theta0=0.3, omega=1.0)
    res = m.compile().sweep(np.linspace(0.0, 2 * math.pi, 361), locks=True)
    kinds = [e.kind for e in res.events]
    assert kinds == ["bifurcation", "lock", "bifurcation", "lock"]
    res.to_html(tmp_path / "toggle.html")
    open_page(browser, tmp_path / "toggle.html")
    marks = browser.find_elements(By.CSS_SELECTOR, "#timeline .mark")
    assert [m.get_attribute("class").split()[1] for m in marks] == kinds + ["closest"]
    assert "lock" in marks[1].get_attribute("title")
    # a mark's left edge at its time along the timeline
    lefts = [float(m.value_of_css_property("left").removesuffix("px")) for m in marks[:4]]
    assert np.all(np.diff(lefts) > 0)
    marks[1].click()
    frame = browser.execute_script("return window.linkwork.frame")
    event = res.events[1]
    assert abs(res.times[frame] - event.time) <= 0.5 * (res.times[1] - res.times[0]) + 1e-12
    # the slider's block at the sweep's slider position (the lock: x = -2 r, its dead centre)
    block = browser.execute_script(
        "return document.querySelector('#drawing polygon.block').getAttribute('points')"
    )
    corners = np.array([[float(v) for v in p.split(",")] for p in block.split()])
    slider = res.body("slider")
    assert np.abs(corners.mean(axis=0) - [slider.x[frame], slider.y[frame]]).max() < 1e-12
    assert abs(slider.x[frame] + 0.2) < 1e-3
    keep(browser, tmp_path, "page_slider_crank_events.png")
    assert problems(browser) == []


def test_a_page_of_fewer_frames_than_steps_and_a_cam(browser, tmp_path):
    path = Path(__file__).parent.parent / "examples" / "cam_rise_dwell_fall.toml"
    res = lw.Mechanism.load(path).compile().sweep(np.linspace(0.0, 1.0, 401))
    res.to_html(tmp_path / "cam.html", frames=41)
    open_page(browser, tmp_path / "cam.html")
    browser.execute_script("window.linkwork.show(20)")
    assert browser.execute_script("return window.linkwork.data.steps[20]") == 200
    # the cam's profile turns with the cam: the page's points are the Python drawing's
    from linkwork.view.drawing import Geometry, Motion

    motion = Motion(Geometry.from_model(res.model), res)
    curves = browser.execute_script(
        "return [...document.querySelectorAll('#drawing polyline.curve')].map(c => c.getAttribute('points'))"
    )
    for curve, text in zip(motion.geometry.curves, curves):
        pts = np.array([[float(v) for v in p.split(",")] for p in text.split()])
        assert np.abs(pts - motion.curve(curve, 200)).max() < 1e-12 * res.model.length_scale
    keep(browser, tmp_path, "page_cam.png")
    assert problems(browser) == []
    assert os.path.getsize(tmp_path / "cam.html") < 2_000_000


def test_the_page_labels_the_bodies_and_moves_them_with_the_drawing(browser, tmp_path):
    """The page's labels (the SVG export's, the figure's): read from its DOM at a step of
    the slider, each body's name at the middle of its outline, from the sweep."""
    res = four_bar(61)
    res.to_html(tmp_path / "labels.html")
    open_page(browser, tmp_path / "labels.html")
    browser.execute_script("window.linkwork.show(40)")
    raw = browser.execute_script(
        "return [...document.querySelectorAll('#drawing text.body-label')]"
        ".map(t => [t.textContent, t.getAttribute('x'), t.getAttribute('y')])"
    )
    labels = {name: np.array([float(x), -float(y)]) for name, x, y in raw}
    assert set(labels) == {"crank", "coupler", "rocker"}
    pins = four_bar_joints(res.q[40], res)
    p = res.point("P").position[40]
    middles = {
        "crank": (pins["O2"] + pins["A"]) / 2,
        "rocker": (pins["O4"] + pins["B"]) / 2,
        "coupler": (pins["A"] + pins["B"] + p) / 3,
    }
    for name, xy in middles.items():
        assert np.abs(labels[name] - xy).max() < 1e-12, name
    joints = browser.execute_script(
        "return [...document.querySelectorAll('#drawing text.joint-label')].map(t => t.textContent)"
    )
    assert sorted(joints) == ["A", "B", "O2", "O4"]
    assert problems(browser) == []


def test_a_synthesized_designs_page_shows_its_targets_where_they_are(browser, tmp_path):
    """The targets of a design (linkwork.targets) are drawn in the page and stay put while
    the slider moves the mechanism; their table lists one row a target."""
    from selenium.webdriver.common.by import By

    from linkwork import synthesis as S

    # five poses of the example four-bar's coupler
    drawn = lw.examples.four_bar().compile()
    states = [drawn.solve(t) for t in (0.0, 0.2, 0.45, 0.7, 1.0)]
    poses = [(*s.point("P").position, s.body("coupler").theta) for s in states]
    design = S.motion(poses).designs[0]
    design.to_html(tmp_path / "design.html", frames=60)
    open_page(browser, tmp_path / "design.html")

    def rings() -> np.ndarray:
        raw = browser.execute_script(
            "return [...document.querySelectorAll('#drawing circle.target')]"
            ".map(c => [c.getAttribute('cx'), c.getAttribute('cy')])"
        )
        return np.array(raw, dtype=float)

    assert np.array_equal(rings(), design.positions)
    browser.execute_script("window.linkwork.show(40)")
    assert np.array_equal(rings(), design.positions)
    assert len(browser.find_elements(By.CSS_SELECTOR, "#target-table tbody tr")) == 5
    assert browser.execute_script("return window.linkwork.data.targets.length") == 5
    keep(browser, tmp_path, "page_design_targets.png")
    assert problems(browser) == []
