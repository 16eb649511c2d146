//! An unknown name's error, with the nearest known names as a hint.

use super::error::ExprError;
use super::rules::{CONSTANTS, FUNCTIONS};

pub(super) fn unknown_name(name: &str, col: usize, variable: &str) -> ExprError {
    let err = ExprError::new(col, format!("unknown name '{name}'"));
    let candidates =
        FUNCTIONS.iter().map(|(n, _)| *n).chain(CONSTANTS.iter().map(|(n, _)| *n)).chain([variable]);
    let best = candidates.map(|c| (edit_distance(name, c), c)).min_by_key(|(d, _)| *d);
    let n = name.chars().count();
    match best {
        // one letter is closer to everything than to anything: point at the variable
        Some((d, c)) if n > 1 && d <= 2 && d < n => err.hint(format!("did you mean '{c}'?")),
        _ => err.hint(format!("the variable is '{variable}'")),
    }
}

/// Levenshtein distance (names are short).
pub(super) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (row[j + 1] + 1).min(row[j] + 1).min(diag + usize::from(ca != *cb));
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}
