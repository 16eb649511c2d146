"""Design studies: parameters, the varied models, design spaces, datasets, tolerance
analysis (Monte Carlo against direct sweeps, first order against known sensitivities) and
the same study on a Dask cluster (bit for bit, a worker killed mid-study)."""

from __future__ import annotations

import math
import os
import pickle

import numpy as np
import pytest

import linkwork as lw
from linkwork import study as S

TURN = 2 * math.pi / 5.0  # one crank revolution of the examples' four-bar


def four_bar() -> dict:
    return lw.examples.four_bar().to_dict()


def lengths(desc: dict) -> dict:
    return lw.Model(desc).linkages()[0].lengths


# -- parameters and the varied model ---------------------------------------------------


def test_friendly_names_resolve_to_the_model_numbers():
    desc = four_bar()
    assert S.parameter(desc, "length crank").nominal == pytest.approx(0.2, abs=1e-15)
    assert S.parameter(desc, "length rocker").anchor == "O4"  # the ground pin stays
    assert S.parameter(desc, "pivot O4.x").nominal == 0.35
    assert S.parameter(desc, "point P.y").path == ("points", "P", "at", 1)
    assert S.parameter(desc, "mass crank").path == ("bodies", "crank", "mass")
    assert S.parameter(desc, "law crank_angle.rate").nominal == 5.0
    assert S.parameter(desc, "joints.B.at.0").nominal == desc["joints"][2]["at"][0]
    assert S.parameter(desc, "gravity.1").nominal == 0.0


@pytest.mark.parametrize(
    "name, listed",
    [
        ("length crnk", "the bodies are crank, coupler, rocker"),
        ("joints.Z.at.0", "the joints are O2, A, B, O4"),
        ("point Q.x", "the points are P"),
        ("lenght crank", "the kinds are length, pin"),
        ("pin A@rocker.x", "joins 'crank' and 'coupler'"),
        ("law crank_angle", "(value, rate)"),
        ("bodies.crank.colour", "the fields are name, theta, x, y"),
        ("length coupler:A-Z", "its pins are A, B"),
        ("pivot O4.z", "end it with .x or .y"),
        ("crank", "a path starts with one of"),
    ],
)
def test_bad_parameter_names_list_what_exists(name, listed):
    with pytest.raises(lw.ParameterError, match=".*") as e:
        S.parameter(four_bar(), name)
    assert listed in str(e.value)
    assert name in str(e.value)


def test_a_link_length_changes_that_link_only():
    desc = four_bar()
    before = {k: v for k, v in desc.items()}
    varied = S.apply(desc, {"length crank": 0.21, "length rocker": 0.26, "length coupler": 0.34})
    assert desc == before  # the given description is not changed
    got = lengths(varied)
    assert got["crank"] == pytest.approx(0.21, abs=1e-12)
    assert got["coupler"] == pytest.approx(0.34, abs=1e-12)
    assert got["rocker"] == pytest.approx(0.26, abs=1e-12)
    assert got["ground"] == pytest.approx(0.35, abs=1e-12)

    # the coupler point keeps its place in the coupler: its distances to A are unchanged
    def dist_p_a(d):
        p = next(x for x in d["points"] if x["name"] == "P")["at"]
        a = next(j for j in d["joints"] if j["name"] == "A")["at"]
        return math.dist(p, a)

    assert dist_p_a(varied) == pytest.approx(dist_p_a(desc), abs=1e-12)


def test_a_ground_pivot_moves_in_the_ground_only():
    varied = S.apply(four_bar(), {"pivot O4.x": 0.37, "pivot O4.y": 0.01})
    got = lengths(varied)
    assert got["ground"] == pytest.approx(math.hypot(0.37, 0.01), abs=1e-12)
    assert (got["crank"], got["coupler"], got["rocker"]) == pytest.approx((0.2, 0.35, 0.25), abs=1e-12)
    o4 = next(j for j in varied["joints"] if j["name"] == "O4")["at"]
    assert o4 == pytest.approx([0.37, 0.01], abs=1e-12)


def test_a_pin_moved_in_both_its_bodies():
    varied = S.apply(four_bar(), {"pin B@rocker.x": 0.48, "pin B@coupler.y": 0.22})
    b = (0.475, 0.2165063509461096)
    got = lengths(varied)
    assert got["rocker"] == pytest.approx(math.dist((0.35, 0.0), (0.48, b[1])), abs=1e-12)
    assert got["coupler"] == pytest.approx(math.dist((0.2, 0.0), (b[0], 0.22)), abs=1e-12)


def test_nominal_values_give_the_very_same_description():
    desc = four_bar()
    names = ["length crank", "pivot O4.x", "point P.x", "law crank_angle.rate"]
    nominal = {n: S.parameter(desc, n).nominal for n in names}
    assert S.apply(desc, nominal) == desc


def test_a_mechanism_in_mm_and_degrees_is_redrawn_in_its_units():
    mech = lw.Mechanism.load(os.path.join(os.path.dirname(__file__), "..", "examples", "four_bar.toml"))
    desc = mech.to_dict()
    p = S.parameter(desc, "length crank")
    assert (p.nominal, p.unit) == (pytest.approx(200.0), "mm")
    varied = S.apply(desc, {"length crank": 201.0})
    got = lw.Model(varied).linkages()[0].lengths
    assert got["crank"] == pytest.approx(201.0, abs=1e-9)
    assert got["coupler"] == pytest.approx(350.0, abs=1e-9)


def test_bad_values_and_unclosable_designs():
    with pytest.raises(lw.ParameterError, match="finite"):
        S.apply(four_bar(), {"length crank": float("nan")})
    with pytest.raises(lw.ParameterError, match="> 0"):
        S.apply(four_bar(), {"length crank": -0.1})
    with pytest.raises(lw.AssemblyError):
        S.apply(four_bar(), {"length crank": 2.0})  # the loop cannot close


# -- pickling: what a task needs -------------------------------------------------------


def test_model_pickles_as_its_description_and_options():
    model = lw.examples.four_bar().compile(solver="general", tol_residual=1e-11)
    back = pickle.loads(pickle.dumps(model))
    assert back.description == model.description and back.options == model.options
    times = np.linspace(0.0, TURN, 500)
    assert np.array_equal(model.sweep(times).q, back.sweep(times).q)


def test_python_laws_cannot_travel():
    m = lw.Mechanism("crank")
    crank = m.link("crank", (0.0, 0.0), (0.2, 0.0))
    m.revolute(m.ground, crank, at=(0.0, 0.0))
    m.drive_angle(crank, lw.PythonLaw(lambda t: (5.0 * t, 5.0, 0.0), name="spin"))
    model = m.compile()
    with pytest.raises(lw.PortabilityError, match="spin"):
        pickle.dumps(model)
    with pytest.raises(lw.PortabilityError, match="spin"):
        lw.Study(model, [0.0, 0.1], ["angle crank"])


def test_every_object_a_task_needs_pickles():
    study = lw.Study(lw.examples.four_bar(), np.linspace(0, TURN, 50), ["path P", "grashof", "events"])
    designs = S.latin_hypercube({"length crank": (0.19, 0.21)}, 5, seed=2)
    job = study.job(designs.names)
    objects = [job, designs, study.model, *job.parameters, *job.outputs, S.Normal(1.0), S.Uniform(1.0)]
    objects += [S.Interval(-1.0, 2.0), study.run(designs)]
    for obj in objects:
        back = pickle.loads(pickle.dumps(obj))
        assert type(back) is type(obj)
    part = pickle.loads(pickle.dumps(S.run_chunk(job, 0, designs.values)))
    direct = S.run_chunk(job, 0, designs.values)
    assert np.array_equal(part["figures"]["path_P"], direct["figures"]["path_P"])


# -- design spaces ---------------------------------------------------------------------


def test_grid_coordinates():
    d = S.grid({"length crank": [0.18, 0.2], "pivot O4.x": [0.3, 0.32, 0.34]})
    assert d.shape == (2, 3) and len(d) == 6
    assert d.values[:, 0].tolist() == [0.18] * 3 + [0.2] * 3
    assert d.values[:, 1].tolist() == [0.3, 0.32, 0.34] * 2


def test_latin_hypercube_one_sample_per_stratum_and_seeded():
    d = S.latin_hypercube({"a": (0.0, 1.0), "b": (10.0, 20.0)}, 50, seed=7)
    for k, (lo, hi) in enumerate(((0.0, 1.0), (10.0, 20.0))):
        strata = np.floor((d.values[:, k] - lo) / (hi - lo) * 50).astype(int)
        assert sorted(strata.tolist()) == list(range(50))
    assert np.array_equal(
        d.values, S.latin_hypercube({"a": (0.0, 1.0), "b": (10.0, 20.0)}, 50, seed=7).values
    )


def test_bad_designs_are_named():
    with pytest.raises(lw.StudyError, match="design 1"):
        S.listed([{"length crank": 0.2}, {"length rocker": 0.2}])
    with pytest.raises(lw.StudyError, match="low < high"):
        S.latin_hypercube({"length crank": (0.3, 0.2)}, 4)
    with pytest.raises(lw.StudyError, match="unknown output"):
        lw.Study(lw.examples.four_bar(), [0.0, 0.1], ["curvature P"])
    with pytest.raises(lw.StudyError, match="the points are P"):
        lw.Study(lw.examples.four_bar(), [0.0, 0.1], ["path Q"])
    study = lw.Study(lw.examples.four_bar(), [0.0, 0.1], ["path P"])
    with pytest.raises(lw.ParameterError, match="no body 'crnk'"):
        study.run(S.grid({"length crnk": [0.2]}))


def atlas_study():
    times = np.linspace(0.0, TURN, 400)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "transmission_min", "grashof", "events"])
    designs = S.grid({"length crank": [0.1, 0.2, 0.3], "pivot O4.x": [0.3, 0.4]})
    return study, designs, times


def test_atlas_dataset_equals_individual_sweeps():
    study, designs, times = atlas_study()
    res = study.run(designs, chunk=4)
    ds = res.dataset
    assert ds.sizes == {"design": 6, "step": 400, "xy": 2}
    assert ds.length_crank.values.tolist() == designs.values[:, 0].tolist()
    assert ds.path_P.attrs["units"] == "m" and ds.transmission_min.attrs["units"] == "rad"
    for i in range(len(designs)):
        try:
            model = lw.Model(S.apply(four_bar(), designs.design(i)))
            r = model.sweep(times, derivatives=0)
        except lw.LinkworkError as e:
            assert res.errors[i].startswith(type(e).__name__)
            assert np.all(np.isnan(ds.path_P.values[i]))
            continue
        assert res.errors[i] == ""
        assert np.array_equal(ds.path_P.values[i], r.point("P").position)
        assert ds.transmission_min.values[i] == np.min(r.transmission_angle())
        assert ds.grashof.values[i] == model.linkages()[0].kind_of
        assert ds.events.values[i] == len(r.events)
    assert 0 < res.n_failed < len(designs)  # the crank of 0.3 cannot turn fully


@pytest.mark.parametrize("suffix", [".nc", ".parquet"])
def test_saved_datasets_keep_values_and_units(tmp_path, suffix):
    study, designs, _ = atlas_study()
    res = study.run(designs)
    path = res.save(str(tmp_path / f"atlas{suffix}"))
    back = S.open_dataset(path)
    ds = res.dataset
    for name in ("path_P", "transmission_min", "length_crank", "pivot_O4_x", "time"):
        assert np.array_equal(back[name].values, ds[name].values, equal_nan=True), name
        assert back[name].attrs["units"] == ds[name].attrs["units"], name
    assert back.grashof.values.tolist() == ds.grashof.values.tolist()
    assert back.error.values.tolist() == ds.error.values.tolist()
    assert back.path_P.dims == ("design", "step", "xy")


def test_pandas_table_has_the_scalar_figures():
    study, designs, _ = atlas_study()
    frame = study.run(designs).to_pandas()
    assert list(frame.columns) == [
        "length_crank",
        "pivot_O4_x",
        "transmission_min",
        "grashof",
        "events",
        "error",
    ]
    assert frame.attrs["units"]["length_crank"] == "m"


# -- tolerance analysis ----------------------------------------------------------------


def test_propagation_of_a_known_sensitivity():
    # S = 1 for the first parameter, 2 for the second, -1 for the third on one output
    s = np.zeros((4, 3, 1))
    s[:, 0, 0], s[:, 1, 0], s[:, 2, 0] = 1.0, 2.0, -1.0
    lin = S.propagate(s, [0.1, 0.05, 0.2], [0.03, 0.01, 0.1])
    assert lin.worst[:, 0] == pytest.approx([0.1 + 0.1 + 0.2] * 4)
    assert lin.rss[:, 0] == pytest.approx([math.sqrt(0.03**2 + 0.02**2 + 0.1**2)] * 4)
    assert lin.share[0, :, 0].sum() == pytest.approx(1.0)
    with pytest.raises(lw.StudyError, match="n_steps x n_params"):
        S.propagate(np.zeros((3, 2)), [1, 1], [1, 1])


def test_a_ground_pivot_moves_the_crank_one_for_one():
    # the crank's frame sits on its ground pivot O2: d(crank.x)/d(pivot O2.x) = 1 exactly
    times = np.linspace(0.0, TURN, 50)
    study = lw.Study(lw.examples.four_bar(), times, ["coordinate crank.x", "coordinate crank.y"])
    s = S.central_differences(study, {"pivot O2.x": 0.0}, {"pivot O2.x": 1e-6})
    assert s.shape == (50, 1, 2)
    assert s[:, 0, 0] == pytest.approx(np.ones(50), abs=1e-6)
    assert s[:, 0, 1] == pytest.approx(np.zeros(50), abs=1e-6)
    tol = study.tolerance({"pivot O2.x": S.Uniform(1e-4)}, n=20, seed=1)
    # the engine's exact sensitivities: d(crank.x)/d(pivot O2.x) = 1 to round-off
    assert tol.linear.worst[:, 0] == pytest.approx(np.full(50, 1e-4), rel=1e-12)
    assert tol.linear.method == "exact (engine)"
    # every sample's crank.x deviation is exactly its pivot's
    dev = tol.deviations[:, :, 0]
    shift = tol.monte_carlo.designs.values[:, 0][:, None]
    assert dev == pytest.approx(np.broadcast_to(shift, dev.shape), abs=1e-12)


def test_monte_carlo_against_direct_sweeps_and_first_order():
    times = np.linspace(0.0, TURN, 200)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "angle rocker"])
    tolerances = {
        "length crank": S.Uniform(5e-5),
        "length coupler": S.Uniform(1e-4),
        "pivot O4.x": S.Interval(-5e-5, 5e-5),
    }
    tol = study.tolerance(tolerances, n=400, seed=11)
    assert tol.n_failed == 0
    assert tol.linear.method == "exact (engine)"
    nominal = lw.Model(four_bar()).sweep(times, derivatives=0).body("rocker").theta
    direct = np.array(
        [
            lw.Model(S.apply(four_bar(), tol.monte_carlo.designs.design(i))).sweep(times, derivatives=0)
            .body("rocker").theta
            for i in range(400)
        ]
    )  # fmt: skip
    stats = tol.monte_carlo_stats()
    k = tol.components.index("angle_rocker")
    # the study's designs are the compiled model's variants, assembled from its drawing;
    # the direct sweeps are redrawn and recompiled: the same closed configurations to
    # round-off (a few ulps of 1 rad), so the spreads (~7e-4 rad) agree to ~1e-12
    assert tol.monte_carlo.built == "variants"
    direct_std = (direct - nominal).std(axis=0, ddof=1)
    assert np.max(np.abs(stats["std"][:, k] - direct_std) / direct_std) < 1e-10
    # small tolerances: first order and Monte Carlo agree (400 samples: ~7 % sampling error)
    ratio = stats["std"] / tol.linear.rss
    assert np.all(np.abs(ratio - 1.0) < 0.2)
    # bounded tolerances: no sample beyond the first-order worst case (but for 2nd order)
    assert np.all(stats["max_abs"] <= tol.linear.worst * 1.001)
    # the same seed gives the same samples
    again = study.tolerance(tolerances, n=400, seed=11, linear=False)
    assert np.array_equal(again.monte_carlo.designs.values, tol.monte_carlo.designs.values)
    assert again.linear is None


def test_samples_that_do_not_assemble_are_counted_and_reported(tmp_path):
    times = np.linspace(0.0, TURN, 100)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "angle rocker"])
    tol = study.tolerance({"length crank": S.Uniform(0.1)}, n=60, seed=3, linear=False)
    assert 0 < tol.n_failed < 60
    assert len(tol.deviations) == 60 - tol.n_failed
    crank = tol.monte_carlo.designs.values[:, 0]
    failed = [i for i, _, _ in tol.failures()]
    assert all(crank[i] > 0.2 for i in failed)  # a longer crank stops turning
    assert f"{tol.n_failed} failed" in tol.summary()
    paths = tol.report(str(tmp_path))
    text = open(paths[0]).read()
    assert "## Failed samples" in text and f"{tol.n_failed} failed" in text
    assert all(os.path.exists(p) for p in paths)


def test_tolerance_report_files(tmp_path):
    times = np.linspace(0.0, TURN, 100)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "angle rocker", "transmission_min"])
    tol = study.tolerance({"length crank": S.Normal(1e-4), "length rocker": S.Normal(1e-4)}, n=50, seed=0)
    paths = tol.report(str(tmp_path), stem="fb")
    names = sorted(os.path.basename(p) for p in paths)
    assert names == ["fb.md", "fb_angle_rocker_error.png", "fb_contributions.png", "fb_path_P_envelope.png"]
    assert "exact (engine)" in open(paths[0]).read()


# -- the command line ------------------------------------------------------------------

STUDIES = os.path.join(os.path.dirname(__file__), "..", "examples", "studies")


def test_cli_atlas_study_writes_dataset_and_report(tmp_path, capsys):
    from linkwork.cli import main

    assert main(["study", os.path.join(STUDIES, "four_bar_atlas.toml"), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    ds = S.open_dataset(str(tmp_path / "four_bar_atlas.nc"))
    failed = int(sum(e != "" for e in ds.error.values))
    assert f"36 designs (grid): {36 - failed} swept, {failed} failed" in out
    assert ds.sizes["design"] == 36 and ds.length_crank.attrs["units"] == "mm"
    assert ds.path_P.attrs["units"] == "mm"
    assert (tmp_path / "four_bar_atlas_path_P_atlas.png").stat().st_size > 0
    assert ("## Failed designs" in (tmp_path / "four_bar_atlas.md").read_text()) == (failed > 0)


def test_cli_tolerance_study_as_parquet(tmp_path, capsys):
    from linkwork.cli import main

    path = tmp_path / "tol.toml"
    text = open(os.path.join(STUDIES, "four_bar_tolerance.toml")).read()
    text = text.replace(
        'model = "../four_bar.toml"', f'model = "{os.path.abspath(STUDIES)}/../four_bar.toml"'
    )
    path.write_text(text.replace("n = 2000", "n = 60").replace("steps = 1000", "steps = 200"))
    assert main(["study", str(path), "--out", str(tmp_path), "--format", "parquet", "--chunk", "16"]) == 0
    out = capsys.readouterr().out
    assert "60 samples (seed 1), 60 swept, 0 failed" in out and "exact (engine)" in out
    ds = S.open_dataset(str(tmp_path / "tol.parquet"))
    assert ds.sizes["design"] == 60 and ds.pivot_O4_x.attrs["units"] == "mm"
    assert {"tol.md", "tol_contributions.png"} <= set(os.listdir(tmp_path))


HEAD = '[study]\nmodel = "M"\nt1 = 1.0\noutputs = ["path P"]\n'


@pytest.mark.parametrize(
    "text, message",
    [
        ('[study]\nmodel = "x.toml"\n', "needs 't1'"),
        ('[study]\nmodel = "M"\nt1 = 1.0\noutputs = ["path P"]\n', "give one of [grid]"),
        ('[study]\nmodel = "M"\nt1 = 1.0\noutputs = ["path P"]\n[grid]\n"length crnk" = [1.0]\n', "no body"),
        (
            '[study]\nmodel = "M"\nt1 = 1.0\noutputs = ["path Q"]\n[grid]\n"length crank" = [1.0]\n',
            "no point",
        ),
        (
            HEAD + '[tolerances.parameters]\n"length crank" = 0\n',
            "half",
        ),
        ('[stduy]\nmodel = "M"\n', "unknown section [stduy]"),
    ],
)
def test_cli_bad_study_files_are_named(tmp_path, capsys, text, message):
    from linkwork.cli import main

    model = os.path.abspath(os.path.join(STUDIES, "..", "four_bar.toml"))
    path = tmp_path / "bad.toml"
    path.write_text(text.replace('"M"', f'"{model}"'))
    assert main(["study", str(path), "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert message in err and str(path) in err


def test_missing_packages_and_bad_schedulers_are_named():
    from linkwork.study.run import requires

    with pytest.raises(lw.DependencyError, match=r"pip install 'linkwork\[studies\]'"):
        requires("a_package_that_is_not_there")
    study = lw.Study(lw.examples.four_bar(), [0.0, 0.1], ["angle rocker"])
    with pytest.raises(lw.StudyError, match="scheduler must be"):
        study.run(S.grid({"length crank": [0.2]}), scheduler=42)
    with pytest.raises(lw.StudyError, match="progress must be"):
        study.run(S.grid({"length crank": [0.2]}), progress="yes")


def test_progress_counts_every_design():
    study = lw.Study(lw.examples.four_bar(), np.linspace(0.0, TURN, 20), ["angle rocker"])
    seen = []
    study.run(
        S.grid({"length crank": np.linspace(0.19, 0.21, 7)}),
        chunk=3,
        progress=lambda d, t: seen.append((d, t)),
    )
    assert seen == [(3, 7), (6, 7), (7, 7)]


def test_peak_effort_and_other_reductions_against_a_direct_sweep():
    m = lw.examples.four_bar()
    for body, mass in (("crank", 0.8), ("coupler", 1.4), ("rocker", 1.0)):
        m.set_mass(body, mass, inertia=0.01 * mass)
    m.set_gravity((0.0, -9.81))
    times = np.linspace(0.0, TURN, 200)
    outputs = ["peak_effort crank_angle", "pivot_min", "coordinate rocker.theta", "events"]
    study = lw.Study(m, times, outputs)
    assert study.derivatives == 2 and study.forces
    res = study.run(S.grid({"mass coupler": [1.4, 2.0]}))
    assert res.dataset.peak_effort_crank_angle.attrs["units"] == "N m"
    for i, mass in enumerate((1.4, 2.0)):
        direct = lw.Model(S.apply(m, {"mass coupler": mass})).sweep(times, forces=True)
        assert res.figures["peak_effort_crank_angle"][i] == np.max(np.abs(direct.effort("crank_angle")))
        assert res.figures["pivot_min"][i] == np.min(direct.pivot_ratio)
        assert np.array_equal(res.figures["q_rocker_theta"][i], direct.body("rocker").theta)
    assert res.figures["peak_effort_crank_angle"][1] > res.figures["peak_effort_crank_angle"][0]
    with pytest.raises(lw.StudyError, match="the drivers are crank_angle"):
        lw.Study(m, times, ["peak_effort D1"])


def test_a_design_is_redrawn_the_same_whatever_shares_its_batch():
    # a batch where the crank keeps its length everywhere and one where it does not: the
    # closing model carries every pin the parameters can move, so each design's redraw is
    # its own (found on a change-point design, where Newton's last digits follow the model)
    desc = lw.Mechanism.load(
        os.path.join(os.path.dirname(__file__), "..", "examples", "four_bar.toml")
    ).to_dict()
    params = S.parameters(desc, ["length crank", "length rocker"])
    designs = S.grid({"length crank": [60.0, 200.0], "length rocker": [200.0, 360.0, 400.0]}).values
    together = S.apply_many(desc, params, designs)
    for i, row in enumerate(designs):
        alone = S.apply_many(desc, params, [row])[0]
        assert alone == together[i], i
        assert S.apply(desc, dict(zip(["length crank", "length rocker"], row))) == together[i]
    assert S.apply_many(desc, params, designs[3:]) == together[3:]


def test_a_slider_crank_keeps_its_rod_and_offset():
    desc = lw.examples.slider_crank().to_dict()
    before = lw.Model(desc).linkages()[0].lengths
    varied = S.apply(desc, {"length crank": before["crank"] * 1.1})
    after = lw.Model(varied).linkages()[0].lengths
    assert after["crank"] == pytest.approx(before["crank"] * 1.1, rel=1e-12)
    assert after["rod"] == pytest.approx(before["rod"], rel=1e-12)
    assert after["offset"] == pytest.approx(before["offset"], abs=1e-12 * before["rod"])


# -- designs as variants of the compiled model -------------------------------------------


def test_variants_agree_with_redrawn_and_recompiled_designs():
    # every kind of parameter the engine maps: a link length, a pin in one body, a ground
    # pivot, a pin in both bodies (the length's anchor), a named point, a driver's law;
    # designs that sweep and designs that stop at a limit of motion
    times = np.linspace(0.0, TURN, 200)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "angle rocker", "events", "pivot_min"])
    designs = S.grid(
        {
            "length crank": [0.15, 0.2, 0.26],
            "pin B@coupler.y": [0.2165, 0.23],
            "pivot O4.x": [0.35, 0.37],
            "joints.O2.at.1": [0.0, 0.01],
            "point P.x": [0.3375, 0.3],
            "drivers.crank_angle.law.rate": [5.0, 6.0],
        }
    )
    variants = study.run(designs)
    redrawn = S.run_chunk(study.job(designs.names, variants=False), 0, designs.values)
    assert variants.built == "variants" and study.job(designs.names).variants is not None
    kinds = [e.partition(":")[0] for e in variants.errors]
    assert kinds == [e.partition(":")[0] for e in redrawn["error"]]
    assert {"", "SingularError"} <= set(kinds)
    # the same closed configurations, assembled from the drawing or redrawn: round-off
    # (paths of ~0.5 m to a few ulps, angles of a few rad likewise)
    ok = variants.ok
    assert np.max(np.abs(variants.figures["path_P"][ok] - redrawn["figures"]["path_P"][ok])) < 1e-13
    assert (
        np.max(np.abs(variants.figures["angle_rocker"][ok] - redrawn["figures"]["angle_rocker"][ok])) < 1e-12
    )
    assert np.array_equal(variants.figures["events"], redrawn["figures"]["events"])
    assert np.all(np.isnan(variants.figures["path_P"][~ok]))
    # the pivot ratio of the assembled start measures lengths in the drawing's size L: a
    # variant keeps the model's, a redrawn design has its own (so they differ, by up to
    # ~10 % here); where L is one, so are the pivot ratios, to round-off
    pivots = variants.figures["pivot_min"][ok], redrawn["figures"]["pivot_min"][ok]
    assert np.max(np.abs(pivots[0] - pivots[1]) / pivots[1]) < 0.15
    rates = S.grid({"drivers.crank_angle.law.rate": [4.0, 5.0, 6.5]})
    pivots = (
        study.run(rates).figures["pivot_min"],
        S.run_chunk(study.job(rates.names, False), 0, rates.values),
    )
    assert np.max(np.abs(pivots[0] - pivots[1]["figures"]["pivot_min"])) < 1e-14


def test_a_designs_pivot_min_is_its_own_sweeps_whatever_path_and_threads_take_it():
    # a study sweeps a four-bar's designs eight at a time in lanes (each started from its
    # closed forms, in a workspace reused from design to design) or one by one (a chunk of
    # fewer than eight; a lane that meets a limit); each design's pivot_min is its sweep
    # alone's, whichever: the start's is Phi_q's LU with its pivots chosen at the solved
    # start, not on what the workspace factored before
    times = np.linspace(0.0, TURN, 60)
    study = lw.Study(lw.examples.four_bar(), times, ["path P", "events", "pivot_min"])
    designs = S.grid(
        {
            "length crank": list(np.linspace(0.08, 0.3, 12)),
            "pivot O4.x": [0.3, 0.35, 0.42],
            "point P.x": [0.3375, 0.2],
        }
    )
    job, n = study.job(designs.names), len(designs.values)
    alone = [S.run_chunk(job, i, designs.values[i : i + 1], 1)["figures"] for i in range(n)]
    pivots = np.array([a["pivot_min"][0] for a in alone])
    paths = np.array([a["path_P"][0] for a in alone])
    swept = np.isfinite(pivots)
    assert 0 < np.sum(swept) < n and np.all(np.isfinite(pivots[swept]))
    for threads in (1, 2):
        # all in one chunk, then shifted by three: other designs share a lane's eight
        for start in (0, 3):
            runs = [S.run_chunk(job, start, designs.values[start:], threads)["figures"] for _ in range(3)]
            # the same bits whatever the threads took first
            for run in runs[1:]:
                assert np.array_equal(run["pivot_min"], runs[0]["pivot_min"], equal_nan=True)
            got, path = runs[0]["pivot_min"], runs[0]["path_P"]
            # the lanes' start is the closed form, the sweep alone's Newton's solution: the
            # same configuration to round-off (paths 1e-13 m apart at most), so two LUs
            # with the same pivots chosen there agree to a few ulps (1.5e-15 measured)
            ok = swept[start:]
            assert np.allclose(got[ok], pivots[start:][ok], rtol=1e-12, atol=0.0)
            assert np.all(np.isnan(got[~ok]))
            apart = np.abs(path[ok] - paths[start:][ok])
            assert np.max(apart) < 1e-13
            # some designs took the lanes (their start a round-off off Newton's)
            assert np.any(apart > 0.0)
    res = study.run(designs, threads=2)
    assert np.allclose(res.figures["pivot_min"][swept], pivots[swept], rtol=1e-12, atol=0.0)


def test_variants_name_bad_values_as_apply_does():
    study = lw.Study(lw.examples.four_bar(), np.linspace(0.0, TURN, 20), ["path P"])
    res = study.run(S.listed([{"length crank": v} for v in (0.2, -0.1, 0.21)]))
    assert res.built == "variants"
    assert res.errors[0] == res.errors[2] == ""
    assert res.errors[1] == "ParameterError: parameter 'length crank': a length must be > 0, not -0.1"
    # a task's values straight from elsewhere (designs check theirs when made)
    part = S.run_chunk(study.job(["length crank"]), 0, np.array([[np.nan], [0.2]]))
    assert part["error"][0].startswith("ParameterError: parameter 'length crank': the value must be a finite")
    assert part["error"][1] == "" and np.all(np.isnan(part["figures"]["path_P"][0]))
    with pytest.raises(lw.InputError, match="variants must be True or False"):
        study.run(S.grid({"length crank": [0.2]}), variants="no")


def test_designs_are_redrawn_where_the_engine_cannot_vary_them():
    times = np.linspace(0.0, TURN, 20)
    # an output that needs every coordinate, or forces
    for outputs in (["path P", "transmission_min"], ["grashof"]):
        res = lw.Study(lw.examples.four_bar(), times, outputs).run(S.grid({"length crank": [0.2]}))
        assert res.built == "redrawn"
    m = lw.examples.four_bar()
    m.set_mass("coupler", 1.0, inertia=0.01)
    res = lw.Study(m, times, ["peak_effort crank_angle"]).run(S.grid({"mass coupler": [1.0]}))
    assert res.built == "redrawn"
    # a parameter that is not one of the engine's numbers (a body's drawn pose)
    study = lw.Study(lw.examples.four_bar(), times, ["path P"])
    assert study.job(["bodies.coupler.theta"]).variants is None
    # a gear's radius: its exact sensitivity is a tangent, a finite change not one direction
    gears = lw.Mechanism.load(
        os.path.join(os.path.dirname(__file__), "..", "examples", "gear_train_compound.toml")
    )
    first = gears.to_dict()["bodies"][0]["name"]
    assert lw.Study(gears, times, [f"angle {first}"]).job(["radius_a mesh12"]).variants is None
    # two parameters that move one pin in one body (the redraw keeps the last; the
    # engine's directions would add)
    assert study.job(["length crank", "joints.A.at.1"]).variants is None
    assert study.job(["length crank", "pin A@crank.y"]).variants is None
    assert study.job(["pin A@crank.x", "pin A@crank.y"]).variants is not None
