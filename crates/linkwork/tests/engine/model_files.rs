//! Model files: TOML and JSON round trips (every element and law kind, floats bit for
//! bit), errors that name the file, line, column and field, versions, units.

use linkwork::files::{read, Format};
use linkwork::motion::CubicSpline;
use linkwork::{Description, DriverDesc, JointDesc, ModelError, MotionLaw, Options};

/// A slider-crank with every joint, driver and load kind and every law kind (drivers
/// beyond the one that moves it make it unsolvable, which files do not mind).
fn every_kind() -> Description {
    let text = r#"{
      "name": "every kind", "units": {"length": "mm", "angle": "deg"}, "gravity": [0.0, -9810.0],
      "bodies": [
        {"name": "crank", "x": 0, "y": 0, "theta": 0, "mass": 0.5, "inertia": 1.5, "com": [50.0, 0.0]},
        {"name": "rod", "x": 100.0, "y": 0.0, "theta": -3.5},
        {"name": "slider", "x": 449.3, "y": -21.25, "theta": 0.0}
      ],
      "joints": [
        {"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
        {"type": "prismatic", "name": "S", "body_a": "ground", "body_b": "slider", "at": [449.3, -21.25],
         "axis": [1.0, 0.0]},
        {"type": "fixed", "name": "W", "body_a": "crank", "body_b": "rod"}
      ],
      "drivers": [
        {"type": "angle", "name": "d1", "body": "crank", "law": {"type": "linear", "value": 0.0, "rate": 286.5}},
        {"type": "relative_angle", "name": "d2", "body_a": "crank", "body_b": "rod",
         "law": {"type": "harmonic", "mean": 1.0, "amplitude": 2.0, "omega": 3.0, "phase": 0.25}},
        {"type": "distance", "name": "d3", "body_a": "ground", "at_a": [0.0, 100.0], "body_b": "rod",
         "at_b": [100.0, 0.0], "law": {"type": "constant", "value": 141.4}},
        {"type": "coordinate", "name": "d4", "body": "slider", "at": [449.3, -21.25], "axis": "x",
         "law": {"type": "polynomial", "coefficients": [449.3, 0.0, -1e-3, 2.5e-7]}},
        {"type": "translation", "name": "d5", "joint": "S",
         "law": {"type": "spline", "times": [0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0, 1.125, 1.25],
                 "values": [0.0, 1.5, 2.75, 3.125, 4.0625, 5.5, 6.25, 7.0, 8.125, 9.5, 10.0]}}
      ],
      "points": [{"name": "P", "body": "rod", "at": [200.0, 10.0]}],
      "loads": [
        {"type": "force", "name": "push", "body": "slider", "at": [449.3, -21.25], "direction": [-1.0, 0.0],
         "law": {"type": "constant", "value": 20.0}},
        {"type": "torque", "name": "brake", "body": "crank", "law": {"type": "linear", "value": 0.0, "rate": -1.0}},
        {"type": "spring", "name": "k", "body_a": "ground", "at_a": [600.0, -21.25], "body_b": "slider",
         "at_b": [449.3, -21.25], "stiffness": 0.5, "free_length": 150.0, "damping": 0.01},
        {"type": "torsion_spring", "name": "kt", "body_a": "ground", "body_b": "crank", "stiffness": 2.0,
         "free_angle": 10.0}
      ]
    }"#;
    Description::from_json(text).expect("the sample reads")
}

#[test]
fn every_kind_round_trips_through_toml_and_json() {
    let d = every_kind();
    assert_eq!(d.joints.len(), 3);
    assert_eq!(d.drivers.len(), 5);
    assert_eq!(d.loads.len(), 4);
    let toml = d.to_toml().unwrap();
    assert_eq!(Description::from_toml(&toml).unwrap(), d);
    assert_eq!(Description::from_json(&d.to_json_file().unwrap()).unwrap(), d);
    assert_eq!(Description::from_json(&d.to_json()).unwrap(), d);
    // the layout: a header, arrays of tables, short laws inline
    assert!(toml.contains(
        "\n[model]\nname = \"every kind\"\nversion = 1\nunits = { length = \"mm\", angle = \"deg\" }\n"
    ));
    assert_eq!(toml.matches("\n[[bodies]]\n").count(), 3);
    assert!(toml.contains("law = { type = \"linear\", value = 0.0, rate = 286.5 }"));
    // a long law gets its own sub-table, under the last [[drivers]]
    assert!(toml.contains("\n[drivers.law]\ntype = \"spline\"\n"));
    // written text reads back as the same text
    assert_eq!(Description::from_toml(&toml).unwrap().to_toml().unwrap(), toml);
}

#[test]
fn floats_round_trip_bit_for_bit() {
    let mut d = every_kind();
    let values = [
        0.1 + 0.2,
        1e-300,
        5e-324,
        f64::MAX,
        -0.0,
        1e22,
        1.0 / 3.0,
        123_456_789.123_456_79,
        2.5e-7,
        0.1 * 3.0,
    ];
    d.drivers[3] = DriverDesc::Coordinate {
        name: "d4".into(),
        body: "slider".into(),
        at: [0.1, 0.7],
        axis: "y".into(),
        law: MotionLaw::Polynomial { coefficients: values.to_vec() },
    };
    for text in [d.to_toml().unwrap(), d.to_json_file().unwrap(), d.to_json()] {
        let back = if text.starts_with('#') {
            Description::from_toml(&text).unwrap()
        } else {
            Description::from_json(&text).unwrap()
        };
        let MotionLaw::Polynomial { coefficients } = back.drivers[3].law() else { panic!("a polynomial") };
        let bits: Vec<u64> = coefficients.iter().map(|c| c.to_bits()).collect();
        assert_eq!(bits, values.iter().map(|c| c.to_bits()).collect::<Vec<_>>(), "{text}");
    }
}

#[test]
fn old_flat_json_reads_as_version_one_in_metres_and_radians() {
    let old = r#"{"name": "p", "bodies": [{"name": "bob", "x": 0.0, "y": -1.0, "theta": -1.5}],
        "joints": [{"type": "revolute", "name": "O", "body_a": "ground", "body_b": "bob", "at": [0.0, 0.0]}],
        "drivers": [{"type": "angle", "name": "d", "body": "bob", "law": {"type": "constant", "value": -1.5}}]}"#;
    let file = read(old, Format::Json, "old.json").unwrap();
    assert!(file.description.units.is_default());
    assert_eq!(file.source.line("joint", "O"), Some(2));
    let model = file.compile(Options::default()).unwrap();
    assert_eq!(model.q_start, vec![0.0, -1.0, -1.5]);
}

const FOUR_BAR: &str = r#"[model]
name = "four-bar"
version = 1
units = { length = "mm", angle = "deg" }

[[bodies]]
name = "crank"
x = 0
y = 0
theta = 0

[[bodies]]
name = "coupler"
x = 200
y = 0
theta = 38.213210701738184

[[bodies]]
name = "rocker"
x = 350
y = 0
theta = 60

[[joints]]
type = "revolute"
name = "O2"
body_a = "ground"
body_b = "crank"
at = [0, 0]

[[joints]]
type = "revolute"
name = "A"
body_a = "crank"
body_b = "coupler"
at = [200, 0]

[[joints]]
type = "revolute"
name = "B"
body_a = "coupler"
body_b = "rocker"
at = [475.0, 216.5063509461096]

[[joints]]
type = "revolute"
name = "O4"
body_a = "rocker"
body_b = "ground"
at = [350, 0]

[[drivers]]
type = "angle"
name = "crank_angle"
body = "crank"
law = { type = "linear", value = 0, rate = 286.4788975654116 }
"#;

/// The line of the first occurrence of `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text[..text.find(needle).expect("the needle is in the text")].matches('\n').count() + 1
}

fn toml_error(text: &str) -> ModelError {
    read(text, Format::Toml, "four_bar.toml").expect_err("the file is refused")
}

fn place(e: &ModelError) -> (usize, usize, String) {
    match e {
        ModelError::File { line, column, field, .. } => (*line, *column, field.clone()),
        other => panic!("not a file error: {other}"),
    }
}

#[test]
fn the_sample_reads_and_compiles() {
    let file = read(FOUR_BAR, Format::Toml, "four_bar.toml").unwrap();
    let model = file.compile(Options::default()).unwrap();
    // degrees, as radians
    assert_eq!(model.q_start[8], 60.0 * (std::f64::consts::PI / 180.0));
    // lengths as written: the engine is scale-aware
    assert_eq!(model.q_start[3], 200.0);
    assert_eq!(
        file.source.line("joint", "B"),
        Some(line_of(FOUR_BAR, "[[joints]]\ntype = \"revolute\"\nname = \"B\""))
    );
}

#[test]
fn file_errors_name_line_column_and_field() {
    // (replace, by, the line holding, column, field, message)
    let b_table = "[[joints]]\ntype = \"revolute\"\nname = \"B\"";
    let cases: [(&str, &str, &str, usize, &str, &str); 9] = [
        // a wrong type: the value
        (
            "at = [475.0, 216.5063509461096]",
            "at = \"B\"",
            "at = \"B\"",
            6,
            "joints[2].at",
            "invalid type: string \"B\", expected an array",
        ),
        // an unknown key: the key
        (
            "at = [475.0, 216.5063509461096]",
            "at = [475.0, 216.5063509461096]\npin = 1",
            "pin = 1",
            1,
            "joints[2].pin",
            "unknown field `pin`",
        ),
        // a missing field: the table that lacks it (a revolute may leave out `at`, given
        // its pins; not the bodies it joins)
        ("body_b = \"rocker\"\n", "", b_table, 1, "joints[2].body_b", "missing field `body_b`"),
        // an unknown joint type lists the known ones
        (
            "type = \"revolute\"\nname = \"B\"",
            "type = \"teleport\"\nname = \"B\"",
            "type = \"teleport\"",
            8,
            "joints[2].type",
            "unknown variant `teleport`, expected one of `revolute`, `prismatic`, `fixed`",
        ),
        // a law's unknown key and unknown type
        (
            "rate = 286.4788975654116",
            "speed = 5",
            "speed = 5",
            37,
            "drivers[0].law.speed",
            "unknown field `speed`",
        ),
        (
            "type = \"linear\"",
            "type = \"cycloid\"",
            "cycloid",
            16,
            "drivers[0].law.type",
            "unknown variant `cycloid`",
        ),
        // units and the header
        (
            "length = \"mm\"",
            "length = \"in\"",
            "length = \"in\"",
            20,
            "model.units.length",
            "unknown variant `in`, expected `m` or `mm`",
        ),
        (
            "version = 1\n",
            "version = 1\nauthor = \"me\"\n",
            "author",
            1,
            "model.author",
            "unknown field `author` in the model header",
        ),
        // a syntax error
        (
            b_table,
            "[[joints]\ntype = \"revolute\"\nname = \"B\"",
            "[[joints]\ntype = \"revolute\"\nname = \"B\"",
            10,
            "",
            "",
        ),
    ];
    for (from, to, at, column, field, message) in cases {
        assert!(FOUR_BAR.contains(from), "{from}");
        let text = FOUR_BAR.replacen(from, to, 1);
        let e = toml_error(&text);
        let line = line_of(&text, at);
        assert_eq!(place(&e), (line, column, field.to_string()), "{e}");
        let shown = e.to_string();
        assert!(shown.starts_with(&format!("four_bar.toml: line {line}, column {column}: ")), "{shown}");
        assert!(shown.contains(message), "{shown}");
    }
}

#[test]
fn json_errors_name_line_column_and_field() {
    let good = every_kind().to_json_file().unwrap();
    let (from, to) = ("\"free_length\": 150.0", "\"free_length\": \"long\"");
    let e = read(&good.replacen(from, to, 1), Format::Json, "m.json").unwrap_err();
    let line = good.lines().position(|l| l.contains(from)).unwrap() + 1;
    assert_eq!(place(&e), (line, 22, "loads[2].free_length".into()), "{e}");
    let e = read("{\"bodies\": [1, 2,]}", Format::Json, "m.json").unwrap_err();
    assert_eq!(place(&e).0, 1, "{e}");
    assert!(e.to_string().contains("comma"), "{e}");
    let e = read("[1, 2]", Format::Json, "m.json").unwrap_err();
    assert!(e.to_string().contains("at the top"), "{e}");
}

#[test]
fn versions_newer_than_this_one_are_refused() {
    let v2 = FOUR_BAR.replacen("version = 1", "version = 2", 1);
    let e = toml_error(&v2).to_string();
    assert!(e.contains("line 3, column 11: model.version: this file is model format version 2"), "{e}");
    assert!(e.contains("reads versions up to 1"), "{e}");
    for bad in ["version = 0", "version = \"1\"", "version = 1.0"] {
        let e = toml_error(&FOUR_BAR.replacen("version = 1", bad, 1));
        assert_eq!(place(&e).2, "model.version", "{e}");
    }
    // no version at all: version 1
    assert!(read(&FOUR_BAR.replacen("version = 1\n", "", 1), Format::Toml, "f").is_ok());
}

#[test]
fn numbers_that_are_not_finite_are_refused_where_written() {
    let text = FOUR_BAR.replacen("theta = 38.213210701738184", "theta = nan", 1);
    assert_eq!(place(&toml_error(&text)), (line_of(&text, "theta = nan"), 9, "bodies[1].theta".into()));
    let e = toml_error(&FOUR_BAR.replacen("y = 0\ntheta = 38", "y = inf\ntheta = 38", 1));
    assert_eq!(place(&e).2, "bodies[1].y", "{e}");
}

#[test]
fn compile_errors_name_the_element_and_its_line() {
    let bad = FOUR_BAR.replacen("body_a = \"coupler\"", "body_a = \"coupling\"", 1);
    let file = read(&bad, Format::Toml, "four_bar.toml").unwrap();
    let e = file.compile(Options::default()).unwrap_err().to_string();
    let line = line_of(&bad, "[[joints]]\ntype = \"revolute\"\nname = \"B\"");
    assert!(
        e.starts_with(&format!("four_bar.toml: line {line}: joint 'B': refers to body 'coupling'")),
        "{e}"
    );
    let dup = FOUR_BAR.replacen("name = \"O4\"", "name = \"A\"", 1);
    let e = read(&dup, Format::Toml, "f.toml").unwrap().compile(Options::default()).unwrap_err().to_string();
    let line = line_of(&dup, "[[joints]]\ntype = \"revolute\"\nname = \"A\"\nbody_a = \"rocker\"");
    assert!(e.starts_with(&format!("f.toml: line {line}: duplicate name 'A'")), "{e}");
}

#[test]
fn degrees_and_millimetres_compile_to_the_same_angles() {
    let mm_deg = read(FOUR_BAR, Format::Toml, "f").unwrap().description;
    let mut m_rad = mm_deg.clone();
    m_rad.units = Default::default();
    let k = std::f64::consts::PI / 180.0;
    for b in &mut m_rad.bodies {
        (b.x, b.y, b.theta) = (b.x / 1000.0, b.y / 1000.0, b.theta * k);
    }
    for j in &mut m_rad.joints {
        if let JointDesc::Revolute { at: Some(at), .. } = j {
            *at = [at[0] / 1000.0, at[1] / 1000.0];
        }
    }
    *m_rad.drivers[0].law_mut() = MotionLaw::Linear { value: 0.0, rate: 5.0 };
    let times: Vec<f64> = (0..=400).map(|i| i as f64 * 2.0 * std::f64::consts::PI / 5.0 / 400.0).collect();
    let sweep = |d: Description| {
        let model = linkwork::Model::new(d).unwrap();
        let mut data = linkwork::Data::new(&model);
        let mut out = linkwork::SweepOutput::with_request(&model, &times, Default::default());
        linkwork::sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
        out.q
    };
    let (q_mm, q_m) = (sweep(mm_deg), sweep(m_rad));
    for (k, (a, b)) in q_mm.iter().zip(&q_m).enumerate() {
        if k % 3 == 2 {
            assert!((a - b).abs() <= 1e-12, "angle {k}: {a} vs {b}");
        } else {
            assert!((a - 1000.0 * b).abs() <= 1e-12 * 350.0, "length {k}: {a} vs 1000 x {b}");
        }
    }
}

#[test]
fn a_spline_law_in_a_file_is_prepared_at_compile() {
    let mut d = read(FOUR_BAR, Format::Toml, "f").unwrap().description;
    let spline = CubicSpline { times: vec![0.0, 1.0, 2.0], values: vec![0.0, 90.0, 180.0], second: vec![] };
    *d.drivers[0].law_mut() = MotionLaw::Spline(spline);
    let back = Description::from_toml(&d.to_toml().unwrap()).unwrap();
    assert_eq!(back, d);
    assert!(linkwork::Model::new(back).is_ok());
}
