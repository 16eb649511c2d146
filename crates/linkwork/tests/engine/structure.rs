//! Structure of the shipped examples: groups in solving order, named as the textbooks do,
//! every row and coordinate in exactly one group, each group needing only earlier ones.

use linkwork::analysis::structure::{structure, Structure};
use linkwork::files::read_path;
use linkwork::Model;

fn examples_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn of(name: &str) -> (Model, Structure) {
    let model = read_path(&examples_dir().join(name)).unwrap().compile(Default::default()).unwrap();
    let s = structure(&model);
    (model, s)
}

/// "kind [body, ...]" per group.
fn describe(model: &Model, s: &Structure) -> Vec<String> {
    s.groups
        .iter()
        .map(|g| {
            let bodies: Vec<&str> = g.bodies.iter().map(|&b| model.body_names[b].as_str()).collect();
            format!("{} [{}]", g.kind, bodies.join(", "))
        })
        .collect()
}

#[test]
fn textbook_mechanisms_by_their_assur_groups() {
    let cases: [(&str, &[&str]); 6] = [
        ("four_bar.toml", &["input [crank]", "dyad RRR [coupler, rocker]"]),
        ("slider_crank.toml", &["input [crank]", "dyad RRP [rod, slider]"]),
        ("six_bar_watt.toml", &["input [crank]", "dyad RRR [coupler, rocker]", "dyad RRR [link5, output]"]),
        (
            "six_bar_stephenson.toml",
            &["input [crank]", "dyad RRR [coupler, rocker]", "dyad RRR [link5, output]"],
        ),
        ("five_bar_two_inputs.toml", &["input [crank1]", "input [crank2]", "dyad RRR [link1, link2]"]),
        (
            "quick_return_shaper.toml",
            &["input [crank]", "one body [lever]", "dyad RRP [link, ram]", "one body [tool_post]"],
        ),
    ];
    for (name, want) in cases {
        let (model, s) = of(name);
        assert_eq!(describe(&model, &s), want, "{name}");
    }
}

#[test]
fn every_example_is_partitioned_in_dependency_order() {
    for entry in std::fs::read_dir(examples_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let (model, s) = of(&name);
        assert!(s.redundant_rows.is_empty() && s.free_coords.is_empty(), "{name}: {s:?}");
        let mut rows: Vec<usize> = s.groups.iter().flat_map(|g| g.rows.clone()).collect();
        let mut coords: Vec<usize> = s.groups.iter().flat_map(|g| g.coords.clone()).collect();
        rows.sort_unstable();
        coords.sort_unstable();
        assert_eq!(rows, (0..model.n_rows).collect::<Vec<_>>(), "{name}");
        assert_eq!(coords, (0..model.n_coords).collect::<Vec<_>>(), "{name}");
        // each group's constraints touch only coordinates of this group or earlier ones
        let mut known = vec![false; model.n_coords];
        for g in &s.groups {
            for &c in &g.coords {
                known[c] = true;
            }
            for &k in &g.constraints {
                let c = &model.constraints[k];
                let touched = [c.body_a, c.body_b].into_iter().flatten().flat_map(|b| 3 * b..3 * b + 3);
                for col in touched.chain(c.extra) {
                    assert!(known[col], "{name}: {} needs {} before it is known", c.name, model.columns[col]);
                }
            }
        }
    }
}
