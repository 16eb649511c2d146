"""Model files (TOML and JSON): exact round trips, errors that name the file, line and
field, format versions, declared units, and a loader that never crashes."""

from __future__ import annotations

import copy
import csv
import json
import math
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import linkwork as lw
from linkwork import examples

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

ROOT = Path(__file__).resolve().parent.parent
DEG = 180.0 / math.pi


def one_turn(n: int = 721) -> np.ndarray:
    return np.linspace(0.0, 2.0 * math.pi / 5.0, n)


# -- round trips ---------------------------------------------------------------------


def with_loads(m: lw.Mechanism) -> lw.Mechanism:
    """The example with mass, gravity and one of every load, so files carry them too."""
    d = m.to_dict()
    names = [b["name"] for b in d["bodies"]]
    for k, name in enumerate(names):
        m.set_mass(name, 0.5 + 0.1 * k, inertia=0.01 / 3.0, com=(0.1 * k, 0.05))
    m.set_gravity((0.0, -9.81))
    m.force(names[-1], (0.1, 0.2), (1.0, -1.0), lw.Harmonic(1.0, 2.0, 3.0, 0.5))
    m.torque(names[0], lw.Polynomial([0.5, -1.0 / 3.0, 1e-9]))
    m.spring(m.ground, (0.0, 0.3), names[-1], (0.1, 0.1), stiffness=120.0, damping=0.1)
    m.torsion_spring(m.ground, names[0], stiffness=2.0, free_angle=0.1, damping=0.01)
    return m


@pytest.mark.parametrize("suffix", [".toml", ".json"])
@pytest.mark.parametrize("name", sorted(examples.ALL))
def test_every_example_round_trips_exactly(name, suffix, tmp_path):
    m = with_loads(examples.ALL[name]())
    path = tmp_path / f"{name}{suffix}"
    m.save(path)
    back = lw.Mechanism.load(path)
    assert back.to_dict() == m.to_dict()
    # load, save, load: the same description, and the same text
    again = tmp_path / f"again{suffix}"
    back.save(again)
    assert lw.Mechanism.load(again).to_dict() == m.to_dict()
    assert again.read_text() == path.read_text()


def test_floats_are_written_in_shortest_round_trip_form(tmp_path):
    m = examples.four_bar()
    values = [0.1 + 0.2, 1.0 / 3.0, 1e-300, 5e-324, 1.7976931348623157e308, -0.0, 2.5e-7, 1e22]
    m.remove("crank_angle")
    m.drive_angle("crank", lw.Polynomial(values), name="crank_angle")
    text = m.to_toml()
    assert "0.30000000000000004, 0.3333333333333333, 1e-300, 5e-324, 1.7976931348623157e308, -0.0," in text
    for suffix in (".toml", ".json"):
        m.save(tmp_path / f"m{suffix}")
        coefficients = lw.Mechanism.load(tmp_path / f"m{suffix}").to_dict()["drivers"][0]["law"][
            "coefficients"
        ]
        assert [c.hex() for c in coefficients] == [v.hex() for v in values]


def test_toml_reads_well():
    text = examples.slider_crank().to_toml()
    header = text.split("\n[[bodies]]")[0]
    assert header.splitlines()[1:] == [
        "",
        "[model]",
        'name = "slider-crank"',
        "version = 1",
        'units = { length = "m", angle = "rad" }',
        "gravity = [0.0, 0.0]",
    ]
    assert text.count("\n[[bodies]]\n") == 3 and text.count("\n[[joints]]\n") == 4
    assert 'law = { type = "linear", value = 0.0, rate = 5.0 }' in text
    # a long law gets its own table under its driver
    m = examples.four_bar()
    m.remove("crank_angle")
    m.drive_angle("crank", lw.Spline(list(np.linspace(0, 1, 40)), list(np.linspace(0, 6, 40))), name="spline")
    text = m.to_toml()
    assert (
        '\n[[drivers]]\ntype = "angle"\nname = "spline"\nbody = "crank"\n\n[drivers.law]\ntype = "spline"\n'
        in text
    )
    assert max(len(line) for line in text.splitlines()) <= 100
    assert lw.Mechanism.from_toml(text).to_dict() == m.to_dict()


@pytest.mark.parametrize("name", sorted(examples.ALL))
def test_toml_written_is_standard_toml_with_the_json_content(name, tmp_path):
    """An independent TOML 1.0 reader (Python's tomllib) reads the TOML file as the same
    data as the JSON file: both writers agree, and the TOML is not linkwork's dialect."""
    tomllib = pytest.importorskip("tomllib")
    m = with_loads(examples.ALL[name]())
    m.remove(m.to_dict()["drivers"][0]["name"])
    m.drive_angle(m.to_dict()["bodies"][0]["name"], lw.Spline(list(np.linspace(0, 1, 30)), [0.1] * 30))
    m.save(tmp_path / "m.toml")
    m.save(tmp_path / "m.json")
    from_toml = tomllib.loads((tmp_path / "m.toml").read_text())
    assert from_toml == json.loads((tmp_path / "m.json").read_text())


def test_old_json_without_version_or_units_loads_as_metres_and_radians(tmp_path):
    d = examples.four_bar().to_dict()
    path = tmp_path / "old.json"
    path.write_text(json.dumps(d, indent=2))  # what save wrote before model files had versions
    m = lw.Mechanism.load(path)
    assert m.to_dict() == d and m.units is None
    model = m.compile()
    assert model.units["length"] == "m" and model.units["input_angle"] == "rad"
    np.testing.assert_array_equal(
        model.sweep(one_turn(50)).q, examples.four_bar().compile().sweep(one_turn(50)).q
    )


def test_json_files_have_the_toml_layout(tmp_path):
    examples.four_bar().save(tmp_path / "m.json")
    d = json.loads((tmp_path / "m.json").read_text())
    assert list(d) == ["model", "bodies", "joints", "drivers", "points"]  # empty lists left out
    assert d["model"] == {
        "name": "four-bar",
        "version": 1,
        "units": {"length": "m", "angle": "rad"},
        "gravity": [0.0, 0.0],
    }


def test_file_names_must_say_the_format(tmp_path):
    with pytest.raises(lw.ModelError, match=r"m\.yaml: a model file ends in \.toml or \.json"):
        examples.four_bar().save(tmp_path / "m.yaml")
    with pytest.raises(lw.ModelError, match=r"\.toml or \.json"):
        lw.Mechanism.load(tmp_path / "m")


def test_a_description_that_is_not_finite_is_not_saved(tmp_path):
    m = examples.four_bar()
    # refused where it is given (the builder checks its points) ...
    with pytest.raises(lw.InputError, match=r"a point or direction must be finite"):
        m.body("extra", (float("nan"), 0.0))
    # ... and where a description is saved that was not built by the checked builder
    desc = m.to_dict()
    desc["bodies"].append({"name": "extra", "x": float("nan"), "y": 0.0, "theta": 0.0})
    with pytest.raises(lw.ModelError, match=r"body 'extra': x is nan"):
        lw.Mechanism.from_dict(desc).save(tmp_path / "m.toml")


# -- the example file and units ------------------------------------------------------


def test_the_example_file_sweeps_like_the_builtin_four_bar():
    m = lw.Mechanism.load(ROOT / "examples" / "four_bar.toml")
    assert m.units == {"length": "mm", "angle": "deg"}
    model = m.compile()
    ref = examples.four_bar().compile()
    t = one_turn(2001)
    res, res_ref = model.sweep(t), ref.sweep(t)
    for body in ("crank", "coupler", "rocker"):
        # arrays are in radians whatever the file's angle unit
        np.testing.assert_allclose(res.body(body).theta, res_ref.body(body).theta, rtol=0, atol=1e-12)
        np.testing.assert_allclose(res.body(body).thetad, res_ref.body(body).thetad, rtol=1e-10, atol=0)
    # lengths come out in the file's unit: mm
    np.testing.assert_allclose(
        res.point("P").position, 1000.0 * res_ref.point("P").position, rtol=0, atol=1e-9
    )
    assert (
        model.units["length"] == "mm"
        and res.units("coupler.x") == "mm"
        and res.units("coupler.theta") == "rad"
        and res.units("coupler.x_d") == "mm/s"
        and res.units("coupler.theta_dd") == "rad/s^2"
        and res.units("time") == "s"
        and res.units("residual") == ""
    )
    with pytest.raises(KeyError, match="no column 'coupler.z'"):
        res.units("coupler.z")


def in_mm_and_degrees(m: lw.Mechanism) -> lw.Mechanism:
    """The same mechanism written in millimetres and degrees."""
    d = copy.deepcopy(m.to_dict())
    for b in d["bodies"]:
        b["x"], b["y"], b["theta"] = 1000.0 * b["x"], 1000.0 * b["y"], DEG * b["theta"]
    for item in d["joints"] + d["points"]:
        if "at" in item:
            item["at"] = [1000.0 * v for v in item["at"]]
    for drv in d["drivers"]:
        assert drv["type"] == "angle" and drv["law"]["type"] == "linear"
        drv["law"] = {"type": "linear", "value": DEG * drv["law"]["value"], "rate": DEG * drv["law"]["rate"]}
    d["units"] = {"length": "mm", "angle": "deg"}
    return lw.Mechanism.from_dict(d)


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_metres_and_radians_against_millimetres_and_degrees(suffix, tmp_path):
    m = examples.four_bar(theta0=0.3)
    mm = in_mm_and_degrees(m)
    mm.save(tmp_path / f"mm{suffix}")
    mm = lw.Mechanism.load(tmp_path / f"mm{suffix}")
    t = one_turn(1001)
    q_m = m.compile().sweep(t).q
    q_mm = mm.compile().sweep(t).q
    theta = np.arange(q_m.shape[1]) % 3 == 2
    np.testing.assert_allclose(q_mm[:, theta], q_m[:, theta], rtol=0, atol=1e-12)
    # lengths are not converted: the results are the same numbers times 1000 (to round-off)
    np.testing.assert_allclose(q_mm[:, ~theta], 1000.0 * q_m[:, ~theta], rtol=0, atol=1e-12 * 350.0)


def test_results_say_their_units(tmp_path):
    m = in_mm_and_degrees(examples.four_bar())
    for k, name in enumerate(("crank", "coupler", "rocker")):
        m.set_mass(name, 1.0 + k, inertia=1000.0 + k)  # kg and kg mm^2
    m.set_gravity((0.0, -9810.0))  # mm/s^2
    model = m.compile()
    assert model.units == {
        "length": "mm",
        "angle": "rad",
        "input_angle": "deg",
        "time": "s",
        "mass": "kg",
        "inertia": "kg mm^2",
        "force": "mN",
        "torque": "mN mm",
        "power": "uW",
        "energy": "uJ",
        "stiffness": "mN/mm",
    }
    res = model.sweep(one_turn(101), forces=True)
    assert res.effort_unit("crank_angle") == "mN mm"
    res.to_csv(tmp_path / "q.csv")
    res.forces_to_csv(tmp_path / "f.csv")
    with open(tmp_path / "q.csv") as f:
        header = next(csv.reader(f))
    assert "crank.x [mm]" in header and "crank.x_d [mm/s]" in header and "crank.theta_dd [rad/s^2]" in header
    with open(tmp_path / "f.csv") as f:
        header = next(csv.reader(f))
    assert "crank_angle.effort [mN mm]" in header and "crank_angle.power [uW]" in header
    assert "A.Fx [mN]" in header and "A.torque [mN mm]" in header
    # the same mechanism in metres: efforts in N m are the mN mm ones over 1e6
    ref = examples.four_bar()
    for k, name in enumerate(("crank", "coupler", "rocker")):
        ref.set_mass(name, 1.0 + k, inertia=(1000.0 + k) * 1e-6)
    ref.set_gravity((0.0, -9.81))
    effort_m = ref.compile().sweep(one_turn(101), forces=True).effort("crank_angle")
    np.testing.assert_allclose(res.effort("crank_angle"), 1e6 * effort_m, rtol=1e-9, atol=1e-9 * 1e6 * 1e-3)


def test_torsion_springs_in_degrees():
    """Free angle in degrees, stiffness and damping per degree: the same torques."""
    m = examples.four_bar()
    m.torsion_spring(m.ground, "rocker", stiffness=3.0, free_angle=1.0, damping=0.2, name="kt")
    deg = in_mm_and_degrees(examples.four_bar())
    deg.torsion_spring(
        deg.ground, "rocker", stiffness=3.0 / DEG, free_angle=DEG, damping=0.2 / DEG, name="kt"
    )
    # torques: N m per rad -> mN mm per degree is 1e6 / DEG
    deg_d = deg.to_dict()
    deg_d["loads"][0].update(stiffness=3.0 * 1e6 / DEG, damping=0.2 * 1e6 / DEG)
    deg = lw.Mechanism.from_dict(deg_d)
    t = one_turn(101)
    e_m = m.compile().sweep(t, forces=True).effort("crank_angle")
    e_mm = deg.compile().sweep(t, forces=True).effort("crank_angle")
    np.testing.assert_allclose(e_mm, 1e6 * e_m, rtol=1e-9, atol=1e-9 * 1e6 * np.abs(e_m).max())


# -- bad files -------------------------------------------------------------------------

FOUR_BAR_TOML = (ROOT / "examples" / "four_bar.toml").read_text()


def line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def load_text(tmp_path: Path, text: str, name: str = "bad.toml") -> lw.Mechanism:
    path = tmp_path / name
    path.write_text(text)
    return lw.Mechanism.load(path)


@pytest.mark.parametrize(
    "old, new, at, field, message",
    [
        # a wrong type: the line of the value
        (
            "at = [475.0, 216.5063509461096]",
            'at = "B"',
            'at = "B"',
            "joints[2].at",
            r'invalid type: string "B", expected an array',
        ),
        # a missing field: the line of the table that lacks it (a revolute may leave out
        # `at`, given its pins; not the bodies it joins)
        (
            'body_b = "rocker"\n',
            "",
            '[[joints]]\ntype = "revolute"\nname = "B"',
            "joints[2].body_b",
            "missing field `body_b`",
        ),
        # an unknown key is an error, not ignored: the line of the key
        (
            'body_b = "rocker"\nat = [475.0',
            'body_b = "rocker"\npin = true\nat = [475.0',
            "pin = true",
            "joints[2].pin",
            r"unknown field `pin`, expected one of `name`, `body_a`, `body_b`, `at`",
        ),
        # an unknown joint type lists the known ones
        (
            'type = "revolute"\nname = "B"',
            'type = "teleport"\nname = "B"',
            'type = "teleport"',
            "joints[2].type",
            r"unknown variant `teleport`, expected one of `revolute`, `prismatic`, `fixed`",
        ),
        (
            "rate = 286.4788975654116",
            "rat = 286.4788975654116",
            "rat = ",
            "drivers[0].law.rat",
            "unknown field `rat`",
        ),
        (
            'length = "mm"',
            'length = "inch"',
            "units = ",
            "model.units.length",
            r"unknown variant `inch`, expected `m` or `mm`",
        ),
        ("gravity = [0.0, 0.0]", "gravity = [0.0, 0.0, 0.0]", "gravity", "model.gravity", "invalid length 3"),
        ("theta = 60.0", "theta = nan", "theta = nan", "bodies[2].theta", "NaN is not a finite number"),
        (
            "version = 1",
            "version = 7",
            "version = 7",
            "model.version",
            r"this file is model format version 7; this linkwork reads versions up to 1",
        ),
    ],
)
def test_bad_files_name_the_line_and_field(old, new, at, field, message, tmp_path):
    assert old in FOUR_BAR_TOML
    text = FOUR_BAR_TOML.replace(old, new, 1)
    with pytest.raises(lw.ModelError) as info:
        load_text(tmp_path, text)
    msg = str(info.value)
    m = re.match(r"(.*bad\.toml): line (\d+), column (\d+): (\S+): (.*)", msg)
    assert m, msg
    assert m.group(4) == field and re.search(message, m.group(5)), msg
    assert int(m.group(2)) == line_of(text, at), msg


def test_syntax_errors_name_the_line(tmp_path):
    text = FOUR_BAR_TOML.replace('name = "A"', 'name = "A', 1)
    line = line_of(text, 'name = "A')
    with pytest.raises(lw.ModelError, match=rf"bad\.toml: line {line}, column \d+: "):
        load_text(tmp_path, text)
    with pytest.raises(lw.ModelError, match=r"bad\.json: line 3, column \d+: .*comma"):
        load_text(tmp_path, '{\n"bodies": [],\n"joints": [],}', "bad.json")


def test_json_errors_name_the_line_and_field(tmp_path):
    examples.slider_crank().save(tmp_path / "m.json")
    text = (tmp_path / "m.json").read_text().replace('"axis": [', '"axle": [', 1)
    with pytest.raises(lw.ModelError) as info:
        load_text(tmp_path, text, "bad.json")
    assert re.match(
        rf"\S+bad\.json: line {line_of(text, 'axle')}, column 7: joints\[3\]\.axle: unknown field",
        str(info.value),
    )


@pytest.mark.parametrize(
    "old, new, element, message",
    [
        (
            'body_b = "rocker"\nat = [475.0',
            'body_b = "rockr"\nat = [475.0',
            '[[joints]]\ntype = "revolute"\nname = "B"',
            r"joint 'B': refers to body 'rockr', which is not in the model",
        ),
        (
            "y = 0.0\ntheta = 60.0",
            "y = 0.0\ntheta = 60.0\nmass = -1.0",
            '[[bodies]]\nname = "rocker"',
            r"body 'rocker': mass -1 must be finite and >= 0",
        ),
        (
            'law = { type = "linear", value = 0.0, rate = 286.4788975654116 }',
            'law = { type = "spline", times = [0.0, 2.0, 1.0], values = [0.0, 1.0, 2.0] }',
            "[[drivers]]",
            r"driver 'crank_angle': spline times must increase strictly",
        ),
        (
            'name = "P"\nbody = "coupler"',
            'name = "P"\nbody = "couple"',
            "[[points]]",
            r"point 'P': refers to body",
        ),
        (
            'name = "O4"',
            'name = "A"',
            '[[joints]]\ntype = "revolute"\nname = "A"\nbody_a = "ground"',
            r"duplicate name 'A': used by a joint and by a joint",
        ),
    ],
)
def test_compile_errors_name_the_element_and_its_line(old, new, element, message, tmp_path):
    assert old in FOUR_BAR_TOML
    text = FOUR_BAR_TOML.replace(old, new, 1)
    m = load_text(tmp_path, text)
    with pytest.raises(lw.ModelError) as info:
        m.compile()
    line = line_of(text, element)
    assert re.match(rf"\S*bad\.toml: line {line}: {message}", str(info.value)), str(info.value)


def test_from_toml_and_to_toml():
    m = lw.Mechanism.from_toml(FOUR_BAR_TOML, "four_bar.toml")
    assert m.name == "four-bar" and m.units == {"length": "mm", "angle": "deg"}
    assert lw.Mechanism.from_toml(m.to_toml()).to_dict() == m.to_dict()
    with pytest.raises(lw.ModelError, match=r"^four_bar\.toml: line 1, column \d+"):
        lw.Mechanism.from_toml("[model\n", "four_bar.toml")


# -- the loader never crashes ---------------------------------------------------------

SEEDS = {
    "toml": FOUR_BAR_TOML,
    "json": json.dumps(json.loads(json.dumps(examples.slider_crank().to_dict())), indent=1),
}
PIECES = list('[]{}=",.:-+#\n 0123456789eaxyz') + ["[[joints]]", "type", "nan", "true", "1e999", '"\\u']


@st.composite
def mutated(draw):
    fmt = draw(st.sampled_from(sorted(SEEDS)))
    text = SEEDS[fmt]
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(text)))
        j = draw(st.integers(i, min(len(text), i + 40)))
        piece = draw(st.one_of(st.sampled_from(PIECES), st.text(max_size=8)))
        text = text[:i] + piece + text[j:]
    return fmt, text


def never_crashes(fmt: str, text: str) -> None:
    try:
        m = lw.Mechanism._read(text, fmt, f"fuzz.{fmt}")
        m.compile()
    except lw.ModelError as e:
        assert str(e).strip()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_mutated_files_give_model_errors_never_crashes(case):
    never_crashes(*case)


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(["toml", "json"]), st.text(max_size=200))
def test_random_text_gives_model_errors_never_crashes(fmt, text):
    never_crashes(fmt, text)


def test_deep_nesting_is_refused_cleanly():
    for fmt, text in (("json", "[" * 100_000), ("toml", "a = " + "[" * 100_000)):
        with pytest.raises(lw.ModelError):
            lw.Mechanism._read(text, fmt, "deep")


def test_the_format_reference_lists_every_joint_and_driver_type():
    """docs/model-format.md has a row for every type the engine reads (the engine's own
    list, from its error for an unknown type)."""
    import re
    from pathlib import Path

    text = (Path(__file__).parent.parent / "docs" / "model-format.md").read_text()
    for group in ("joints", "drivers"):
        d = examples.four_bar().to_dict()
        d[group][0]["type"] = "no_such_type"
        with pytest.raises(lw.ModelError) as info:
            lw.Model(d)
        known = re.findall(r"`(\w+)`", str(info.value).split("expected one of", 1)[1])
        section = text.split(f"### `[[{group}]]`", 1)[1].split("###", 1)[0]
        documented = re.findall(r'^\| `"(\w+)"`', section, flags=re.M)
        assert len(known) > 4 and sorted(documented) == sorted(known), group


def test_a_file_that_is_not_utf8_is_a_model_error_naming_the_place(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(b'[model]\nname = "Kurbelschwinge \xfcber"\nversion = 1\n')
    with pytest.raises(lw.ModelError, match=r"latin1.toml: line 2, byte 31: the file is not UTF-8"):
        lw.Mechanism.load(path)


def test_a_file_without_units_that_looks_like_mm_and_deg_is_warned_about(tmp_path):
    # the shipped four-bar is in mm and deg; without its units line it would be read in m
    # and rad, 1000x and 57x off: said, as a LinkworkWarning, and by the CLI
    text = (EXAMPLES / "four_bar.toml").read_text(encoding="utf-8")
    path = tmp_path / "no_units.toml"
    path.write_text("\n".join(line for line in text.splitlines() if not line.startswith("units =")))
    with pytest.warns(lw.LinkworkWarning, match=r"no units .* look like millimetres .* look like degrees"):
        m = lw.Mechanism.load(path)
    assert not m.units_declared
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        declared = lw.Mechanism.load(EXAMPLES / "four_bar.toml")
    assert declared.units_declared and declared.units_warning is None
    run = subprocess.run(
        [sys.executable, "-m", "linkwork", "check", str(path)], capture_output=True, text=True, timeout=120
    )
    assert "units: lengths in m, angles in rad (the default: the file declares no units)" in run.stdout
    assert "warning:" in run.stderr and "millimetres" in run.stderr


def test_the_law_table_names_every_law_the_engine_accepts():
    """docs/model-format.md's table of motion laws against the engine's own list (the
    one its reader gives for an unknown type), so neither can drift from the other."""
    doc = (Path(__file__).resolve().parent.parent / "docs" / "model-format.md").read_text()
    section = doc.split("### Motion laws", 1)[1].split("\n### ", 1)[0]
    documented = re.findall(r'^\| `"(\w+)"` \|', section, flags=re.M)
    with pytest.raises(lw.ModelError, match="unknown variant") as e:
        lw.Mechanism.from_toml(
            '[model]\nname = "x"\n[[bodies]]\nname = "a"\n[[drivers]]\ntype = "angle"\n'
            'name = "d"\nbody = "a"\nlaw = { type = "no_such_law" }\n'
        )
    accepted = re.findall(r"`(\w+)`", str(e.value).split("expected one of", 1)[1])
    assert len(accepted) >= 11 and documented == accepted
