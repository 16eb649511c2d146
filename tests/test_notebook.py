"""What a notebook shows: the rich-display methods of Mechanism, Model and Results (real
PNGs decoded, tables holding the sweep's numbers), draw() placing the pins where the
engine solved them, and animate()'s inline player with the asked frames."""

from __future__ import annotations

import base64
import io
import math
import re

import numpy as np
import pytest
from PIL import Image

import linkwork as lw

REV = 2 * math.pi / 5.0


def decode(png: bytes) -> Image.Image:
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    image = Image.open(io.BytesIO(png))
    image.load()
    return image


def embedded_pngs(html: str) -> list[Image.Image]:
    return [decode(base64.b64decode(m)) for m in re.findall(r"data:image/png;base64,([A-Za-z0-9+/=]+)", html)]


def pins_on(ax) -> np.ndarray:
    """The pins the drawing put on the axes (the white circles of `MechanismArtists`)."""
    (pins,) = [
        line for line in ax.lines if line.get_marker() == "o" and line.get_markerfacecolor() == "white"
    ]
    return np.column_stack(pins.get_data())


def test_a_mechanism_shows_its_drawing_as_png():
    image = decode(lw.examples.four_bar()._repr_png_())
    assert image.size[0] > 300 and image.size[1] > 200
    # not blank: the bodies' colours are in it
    assert len(np.unique(np.asarray(image.convert("RGB")).reshape(-1, 3), axis=0)) > 50


def test_a_mechanism_being_built_is_drawn_as_described():
    import matplotlib

    matplotlib.use("Agg")
    m = lw.Mechanism("half built")
    crank = m.link("crank", (0.0, 0.0), (0.2, 0.0))
    m.revolute(m.ground, crank, (0.0, 0.0), name="O")
    coupler = m.link("coupler", (0.2, 0.0), (0.4, 0.2))
    m.revolute(crank, coupler, (0.2, 0.0), name="A")
    ax = m.draw()
    assert "as drawn, not assembled" in ax.get_title() and "degree" in ax.get_title()
    assert np.array_equal(pins_on(ax), [[0.0, 0.0], [0.2, 0.0]])
    decode(m._repr_png_())


@pytest.mark.parametrize("t", [0.0, 0.3])
def test_draw_puts_the_pins_where_the_engine_solves_them(t):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mech = lw.examples.four_bar()
    state = mech.compile().solve(t)
    fig, ax = plt.subplots()
    assert mech.draw(ax, t=t) is ax
    pins = pins_on(ax)
    coupler = [state.body("coupler").x, state.body("coupler").y]  # pin A: the coupler's origin
    assert np.hypot(*(pins - coupler).T).min() < 1e-12
    assert f"t = {t:g} s" in ax.get_title()
    plt.close(fig)


def test_results_draw_at_a_time_between_steps_with_paths():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, REV, 25))
    t = 0.5 * (res.times[3] + res.times[4])
    ax = res.draw(t=t)
    exact = res.model.solve(t)
    pins = pins_on(ax)
    assert np.hypot(*(pins - [exact.body("coupler").x, exact.body("coupler").y]).T).min() < 1e-12
    (path,) = [line for line in ax.lines if line.get_label() == "P"]
    assert np.abs(np.column_stack(path.get_data()) - res.point("P").position).max() < 1e-12
    with pytest.raises(lw.InputError, match="outside the sweep"):
        res.draw(t=10.0)
    with pytest.raises(lw.InputError, match="ax must be"):
        res.draw(ax="axes")
    plt.close("all")


def test_a_model_shows_its_counts_and_drawing():
    model = lw.examples.six_bar_watt().compile()
    html = model._repr_html_()
    assert "six-bar (Watt II)" in html and "5 (15 coordinates)" in html
    assert "Gruebler 1, rank 1" in html and "dyad RRR" in html
    (image,) = embedded_pngs(html)
    assert image.size[0] > 300


def test_results_show_a_summary_table_and_plots():
    res = lw.examples.slider_crank().compile().sweep(np.linspace(0.0, REV, 201))
    html = res._repr_html_()
    k = res.columns.index("slider.x")
    row = re.search(r"<tr><td[^>]*>slider\.x</td>(.*?)</tr>", html)
    assert row is not None
    cells = re.findall(r"<td>([^<]*)</td>", row.group(1))
    assert cells[0] == "m"
    assert float(cells[1]) == pytest.approx(res.q[:, k].min(), rel=1e-5)
    assert float(cells[2]) == pytest.approx(res.q[:, k].max(), rel=1e-5)
    assert float(cells[3]) == pytest.approx(np.abs(res.qd[:, k]).max(), rel=1e-5)
    assert "smallest pivot ratio" in html and "events" in html
    (image,) = embedded_pngs(html)
    assert image.size[0] > 600
    assert "no steps" not in html


def test_results_with_events_list_them():
    m = lw.examples.slider_crank(crank=0.1, rod=0.1, offset=0.0, theta0=0.3, omega=1.0)
    res = m.compile().sweep(np.linspace(0.0, 2 * math.pi, 181), locks=True)
    html = res._repr_html_()
    assert html.count("<li>") == len(res.events) == 4 and "bifurcation at t = " in html


def test_animate_gives_an_inline_player_with_the_asked_frames(tmp_path):
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, REV, 301))
    anim = res.animate(frames=12, fps=10)
    assert anim.frames == 12 and repr(anim) == "<linkwork Animation: 12 frames>"
    html = anim._repr_html_()
    assert "<script" in html and "<img" in html
    frames = re.findall(r'frames\[(\d+)\] = "data:image/png;base64,([^"]+)"', html)
    assert [int(i) for i, _ in frames] == list(range(12))
    first, last = (decode(base64.b64decode(f.replace("\\n", ""))) for _, f in (frames[0], frames[-1]))
    assert first.size == last.size and first.tobytes() != last.tobytes()
    anim.save(str(tmp_path / "anim.html"))
    assert (tmp_path / "anim.html").read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_animate_refuses_bad_arguments():
    res = lw.examples.four_bar().compile().sweep(np.linspace(0.0, REV, 11))
    with pytest.raises(lw.InputError, match="frames"):
        res.animate(frames=0)
    with pytest.raises(lw.InputError, match="mode"):
        res.animate(mode="gif")
    with pytest.raises(lw.InputError, match="fps"):
        res.animate(fps=1.5)  # type: ignore[arg-type]
