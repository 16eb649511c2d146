//! The layout of Phi_q's values: every Jacobian entry of every constraint gets its slot in
//! the value array the chosen linear algebra factors.

use crate::constraints::MAX_ROWS;
use crate::math::linear::{LinearKind, SymbolicFactor};
use crate::model::ConstraintEntry;

/// The symbolic factor of the constraints' Phi_q (m rows, n coordinates), each entry's
/// slot set in its constraint.
pub(crate) fn symbolic_factor(
    kind: LinearKind,
    m: usize,
    n: usize,
    constraints: &mut [ConstraintEntry],
) -> SymbolicFactor {
    let mut cells = Vec::new();
    for_each_entry(constraints, |row, col| {
        cells.push((row, col));
        0
    });
    let (symbolic, slots) = SymbolicFactor::new(kind, m, n, &cells);
    let mut next = slots.into_iter();
    for_each_entry(constraints, |_, _| next.next().expect("one slot per entry"));
    symbolic
}

/// Calls `slot(row, col)` for every Jacobian block entry of every constraint and stores
/// what it returns as that entry's slot.
fn for_each_entry(constraints: &mut [ConstraintEntry], mut slot: impl FnMut(usize, usize) -> u32) {
    for c in constraints.iter_mut() {
        for i in 0..c.n_rows.min(MAX_ROWS) {
            for j in 0..3 {
                if let Some(b) = c.body_a {
                    c.slots_a[i][j] = slot(c.row0 + i, 3 * b + j);
                }
                if let Some(b) = c.body_b {
                    c.slots_b[i][j] = slot(c.row0 + i, 3 * b + j);
                }
            }
            if let Some(k) = c.extra {
                c.slots_s[i] = slot(c.row0 + i, k);
            }
        }
    }
}
