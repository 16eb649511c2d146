"""Regenerates the screenshots in docs/ of the interactive page and of the notebook
display, with the real tools: the pages are written by linkwork and photographed by
headless Chromium (Selenium, the system's chromium and chromedriver); the notebook is
executed by a Jupyter kernel (nbclient), converted to HTML by nbconvert and photographed
the same way.

    pip install selenium nbclient nbconvert ipykernel   # and apt-get install chromium chromium-driver
    python scripts/docs_screenshots.py               # every screenshot
    python scripts/docs_screenshots.py --simulation  # only the simulation's page (docs/dynamics.md)
"""

from __future__ import annotations

import math
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

import linkwork as lw

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"


def browser(width: int, height: int):  # type: ignore[no-untyped-def]
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--hide-scrollbars",
        f"--window-size={width},{height}",
    ):
        options.add_argument(arg)
    options.binary_location = shutil.which("chromium") or shutil.which("chromium-browser") or "chromium"
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
    driver.set_page_load_timeout(60)
    return driver


def pages(folder: Path) -> None:
    rev = 2 * math.pi / 5.0
    four_bar = lw.Mechanism.load(ROOT / "examples" / "four_bar.toml").compile()
    four_bar.sweep(np.linspace(0.0, rev, 2001)).to_html(folder / "four_bar.html")
    toggle = lw.examples.slider_crank(crank=0.1, rod=0.1, offset=0.0, theta0=0.3, omega=1.0).compile()
    toggle.sweep(np.linspace(0.0, 2 * math.pi, 721), locks=True).to_html(folder / "toggle.html")
    driver = browser(1300, 1040)
    try:
        for name, frame, out in (("four_bar", 700, "view_four_bar.png"), ("toggle", 250, "view_events.png")):
            driver.get((folder / f"{name}.html").as_uri())
            driver.execute_script(f"window.linkwork.show({frame})")
            driver.save_screenshot(str(DOCS / out))
            print("wrote", DOCS / out)
    finally:
        driver.quit()


def lid() -> lw.Mechanism:
    """The lid on a gas strut of docs/dynamics.md, the strut damped (40 N s/m)."""
    m = lw.Mechanism("lid")
    lid = m.link("lid", (0.0, 0.0), (0.6, 0.0), mass=2.0)
    m.revolute(m.ground, lid, at=(0.0, 0.0), name="hinge")
    m.spring(
        m.ground,
        (0.0, -0.20),
        lid,
        (0.15, 0.0),
        stiffness=800.0,
        free_length=0.40,
        damping=40.0,
        name="strut",
    )
    m.point("edge", lid, (0.6, 0.0))
    m.set_gravity((0.0, -9.81))
    return m


def simulation_page(folder: Path) -> None:
    """The page `linkwork simulate lid.toml --page` writes, at t = 1 s."""
    from linkwork.cli import main

    lid().save(folder / "lid.toml")
    argv = [
        "simulate",
        str(folder / "lid.toml"),
        "--t1",
        "5",
        "--steps",
        "1001",
        "--out",
        str(folder),
        "--page",
    ]
    assert main(argv) == 0
    driver = browser(1300, 1400)
    try:
        driver.get((folder / "lid.html").as_uri())
        driver.execute_script("window.linkwork.show(200)")
        driver.save_screenshot(str(DOCS / "view_simulation.png"))
        print("wrote", DOCS / "view_simulation.png")
    finally:
        driver.quit()


NOTEBOOK = [
    "import numpy as np\nimport linkwork as lw\n\nmech = lw.Mechanism.load('examples/four_bar.toml')\nmech",
    "res = mech.compile().sweep(np.linspace(0.0, 2 * np.pi / 5.0, 721))\nres",
]


def notebook(folder: Path) -> None:
    import nbformat
    from nbclient import NotebookClient
    from nbconvert import HTMLExporter

    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(src) for src in NOTEBOOK])
    NotebookClient(
        nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}
    ).execute()
    html, _ = HTMLExporter(template_name="lab").from_notebook_node(nb)
    (folder / "notebook.html").write_text(html, encoding="utf-8")
    driver = browser(1100, 1300)
    try:
        driver.get((folder / "notebook.html").as_uri())
        driver.save_screenshot(str(DOCS / "notebook_four_bar.png"))
        print("wrote", DOCS / "notebook_four_bar.png")
    finally:
        driver.quit()


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as tmp:
        simulation_page(Path(tmp))
        if "--simulation" in sys.argv[1:]:
            sys.exit(0)
        pages(Path(tmp))
        if "--pages" not in sys.argv[1:]:
            notebook(Path(tmp))
