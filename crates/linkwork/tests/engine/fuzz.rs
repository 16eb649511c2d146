//! Fuzzing the two text front doors, the model-file reader and the expression parser:
//! any text either reads (and compiles or is refused with a model error) or is a named
//! error, never a panic, a hang or a NaN taken for a number. Bounded (a few hundred cases
//! each, seconds); `PROPTEST_CASES` raises it.

use linkwork::{Expression, Format, Model};
use proptest::prelude::*;

const FOUR_BAR: &str = include_str!("../../../../examples/four_bar.toml");

/// The shipped four-bar with one byte range replaced by arbitrary text: mostly near-valid
/// files, which reach deep into the reader and the compiler.
fn mutated() -> impl Strategy<Value = String> {
    (0..FOUR_BAR.len(), 0usize..40, "[ -~\n\t\u{e9}\u{3c0}]{0,40}").prop_map(|(at, len, insert)| {
        let mut at = at;
        while !FOUR_BAR.is_char_boundary(at) {
            at -= 1;
        }
        let mut end = (at + len).min(FOUR_BAR.len());
        while !FOUR_BAR.is_char_boundary(end) {
            end -= 1;
        }
        format!("{}{}{}", &FOUR_BAR[..at], insert, &FOUR_BAR[end..])
    })
}

fn read_and_compile(text: &str, format: Format) {
    let start = std::time::Instant::now();
    if let Ok(file) = linkwork::files::read(text, format, "fuzz.toml") {
        if let Ok(model) = Model::new(file.description) {
            assert!(model.q_start.iter().all(|v| v.is_finite()), "a compiled model starts finite");
        }
    }
    assert!(start.elapsed().as_secs_f64() < 5.0, "reading one file must not hang");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_model_files_read_or_are_named_errors(text in mutated()) {
        read_and_compile(&text, Format::Toml);
    }

    #[test]
    fn arbitrary_text_as_a_model_file_is_a_named_error(text in "[ -~\n]{0,200}") {
        read_and_compile(&text, Format::Toml);
        read_and_compile(&text, Format::Json);
    }

    #[test]
    fn expressions_parse_or_are_named_errors(text in "[-+*/^(), .0-9a-z_tpiesqrcn]{0,40}", x in -10.0f64..10.0) {
        match Expression::parse(&text, "t") {
            Ok(e) => {
                // the property is that evaluating does not panic (proptest fails on a
                // panic); a value that is not finite there is named by the engine when a
                // law uses it (tests/parse_errors: run_time_domain_errors...)
                let _ = e.eval(x);
                let _ = e.eval3(x);
            }
            Err(err) => prop_assert!(!err.to_string().is_empty()),
        }
    }
}
