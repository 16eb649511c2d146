//! The mechanism's structure, read from the pattern of its constraint Jacobian alone: a
//! maximum matching of rows to coordinates, then the strongly connected components of
//! "row r needs the coordinate another row determines" (the block-triangular form of a
//! square, structurally regular Phi_q; Dulmage and Mendelsohn). Each component is a group
//! of coordinates that must be solved together; the groups come in an order in which each
//! needs only earlier ones. Groups are named as the textbooks do: an input (a body with
//! its driver), one body (pinned and slotted, geared...), Assur dyads RRR, RRP, RPR, PRP
//! and RPP (two bodies, three lower pairs, the joints to known bodies outside), triads
//! (a ternary link and three binary links, six lower pairs), and larger groups. The
//! structure is generic: special geometry (a parallelogram with a third crank) can move
//! where the pattern says over-determined, which `mobility` (the rank of Phi_q) tells. Rows left unmatched are
//! structurally redundant; coordinates left unmatched are freedoms no driver takes up.
//!
//! The pattern is the engine's own (each side's three columns and the joint's extra
//! coordinate), so a group is never split finer than the solver could exploit.

use crate::constraints::kinds::ConstraintKind;
use crate::model::Model;

/// One group of coordinates solved together.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// "input" (holds a driver), "one body", "dyad RRR" (RRP, RPR, PRP, RPP), "triad", or
    /// "group"
    pub kind: String,
    /// moving bodies whose coordinates the group determines
    pub bodies: Vec<usize>,
    /// constraints (indices into `model.constraints`) whose rows the group holds
    pub constraints: Vec<usize>,
    /// columns of q the group determines
    pub coords: Vec<usize>,
    /// rows of Phi it holds
    pub rows: Vec<usize>,
}

/// The groups in solving order, and what the matching left over.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Structure {
    pub groups: Vec<Group>,
    /// rows no coordinate is left for: structurally redundant
    pub redundant_rows: Vec<usize>,
    /// coordinates no row determines: freedoms the drivers leave
    pub free_coords: Vec<usize>,
}

/// Columns each row of a constraint touches: both sides' (x, y, theta) and the extra
/// coordinate.
fn columns(model: &Model, k: usize) -> Vec<usize> {
    let c = &model.constraints[k];
    let mut cols: Vec<usize> =
        [c.body_a, c.body_b].into_iter().flatten().flat_map(|b| 3 * b..3 * b + 3).collect();
    cols.extend(c.extra);
    cols.sort_unstable();
    cols.dedup();
    cols
}

/// Maximum matching rows -> columns by augmenting paths (iterative, so that a chain of
/// thousands of loops does not exhaust the stack), after a greedy start that serves the
/// rows with the fewest columns first (a driver, a pin to the ground), so that few rows
/// are left to augment along long paths.
fn matching(n_cols: usize, adj: &[&[usize]]) -> (Vec<Option<usize>>, Vec<Option<usize>>) {
    let n_rows = adj.len();
    let mut row_of: Vec<Option<usize>> = vec![None; n_cols];
    let mut col_of: Vec<Option<usize>> = vec![None; n_rows];
    let mut order: Vec<usize> = (0..n_rows).collect();
    order.sort_by_key(|&r| adj[r].len());
    for r in order {
        if let Some(&c) = adj[r].iter().find(|&&c| row_of[c].is_none()) {
            row_of[c] = Some(r);
            col_of[r] = Some(c);
        }
    }
    let mut seen = vec![usize::MAX; n_cols];
    for start in 0..n_rows {
        if col_of[start].is_some() {
            continue;
        }
        // depth-first search for an augmenting path; stack of (row, next edge index)
        let mut stack: Vec<(usize, usize)> = vec![(start, 0)];
        let mut via: Vec<usize> = Vec::new(); // column taken at each level
        let mut found = None;
        while let Some(&mut (r, ref mut i)) = stack.last_mut() {
            if *i >= adj[r].len() {
                stack.pop();
                via.pop();
                continue;
            }
            let c = adj[r][*i];
            *i += 1;
            if seen[c] == start {
                continue;
            }
            seen[c] = start;
            match row_of[c] {
                None => {
                    via.push(c);
                    found = Some(());
                    break;
                }
                Some(next) => {
                    via.push(c);
                    stack.push((next, 0));
                }
            }
        }
        if found.is_some() {
            // flip the path: row stack[k].0 takes column via[k]
            for (k, &(r, _)) in stack.iter().enumerate() {
                let c = via[k];
                row_of[c] = Some(r);
                col_of[r] = Some(c);
            }
        }
    }
    (col_of, row_of)
}

/// Strongly connected components (Tarjan, iterative) of a graph on n nodes, each
/// emitted after every component it reaches: prerequisites first.
fn components(n: usize, succ: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut index = vec![usize::MAX; n];
    let mut low = vec![0; n];
    let mut on_stack = vec![false; n];
    let mut stack = Vec::new();
    let mut out = Vec::new();
    let mut next = 0;
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        let mut call: Vec<(usize, usize)> = vec![(root, 0)];
        index[root] = next;
        low[root] = next;
        next += 1;
        stack.push(root);
        on_stack[root] = true;
        while let Some(&mut (v, ref mut i)) = call.last_mut() {
            if *i < succ[v].len() {
                let w = succ[v][*i];
                *i += 1;
                if index[w] == usize::MAX {
                    index[w] = next;
                    low[w] = next;
                    next += 1;
                    stack.push(w);
                    on_stack[w] = true;
                    call.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            call.pop();
            if let Some(&(parent, _)) = call.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == index[v] {
                let mut comp = Vec::new();
                loop {
                    let w = stack.pop().expect("the component's nodes are on the stack");
                    on_stack[w] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                comp.sort_unstable();
                out.push(comp);
            }
        }
    }
    out
}

/// R or P for a lower pair, None for anything else.
fn pair_letter(kind: &ConstraintKind) -> Option<char> {
    match kind {
        ConstraintKind::Revolute(_) => Some('R'),
        ConstraintKind::Prismatic(_) => Some('P'),
        _ => None,
    }
}

fn classify(model: &Model, bodies: &[usize], constraints: &[usize]) -> String {
    let entries: Vec<_> = constraints.iter().map(|&k| &model.constraints[k]).collect();
    if entries.iter().any(|c| c.role == "driver") {
        return "input".into();
    }
    if bodies.len() == 1 {
        return "one body".into();
    }
    let letters: Option<Vec<char>> = entries.iter().map(|c| pair_letter(&c.kind)).collect();
    let Some(letters) = letters else { return "group".into() };
    let inside = |b: Option<usize>| b.is_some_and(|b| bodies.contains(&b));
    match (bodies.len(), entries.len()) {
        (2, 3) => {
            // the middle pair joins the two bodies; the outer ones join them to what is known
            let middle = entries.iter().position(|c| inside(c.body_a) && inside(c.body_b));
            let Some(m) = middle else { return "group".into() };
            let outer: Vec<char> = (0..3).filter(|&k| k != m).map(|k| letters[k]).collect();
            let s: String = [outer[0], letters[m], outer[1]].iter().collect();
            let r: String = s.chars().rev().collect();
            format!("dyad {}", s.max(r))
        }
        (4, 6) => {
            // a ternary link joined to three binary links, each also joined outside
            let internal = |b: usize| {
                entries
                    .iter()
                    .filter(|c| {
                        inside(c.body_a) && inside(c.body_b) && (c.body_a == Some(b) || c.body_b == Some(b))
                    })
                    .count()
            };
            let mut counts: Vec<usize> = bodies.iter().map(|&b| internal(b)).collect();
            counts.sort_unstable();
            if counts == [1, 1, 1, 3] {
                "triad".into()
            } else {
                "group".into()
            }
        }
        _ => "group".into(),
    }
}

/// The structure of a compiled model.
pub fn structure(model: &Model) -> Structure {
    let n_rows = model.n_rows;
    let n_cols = model.n_coords;
    let mut row_constraint = vec![0; n_rows];
    let mut cols_of: Vec<Vec<usize>> = Vec::with_capacity(model.constraints.len());
    for (k, c) in model.constraints.iter().enumerate() {
        cols_of.push(columns(model, k));
        row_constraint[c.row0..c.row0 + c.n_rows].fill(k);
    }
    let adj: Vec<&[usize]> = (0..n_rows).map(|r| cols_of[row_constraint[r]].as_slice()).collect();
    let (col_of, row_of) = matching(n_cols, &adj);
    // row r needs every column it touches; the row matched to that column determines it
    let matched: Vec<usize> = (0..n_rows).filter(|&r| col_of[r].is_some()).collect();
    let mut node = vec![usize::MAX; n_rows];
    for (i, &r) in matched.iter().enumerate() {
        node[r] = i;
    }
    let succ: Vec<Vec<usize>> = matched
        .iter()
        .map(|&r| {
            adj[r]
                .iter()
                .filter(|&&c| Some(c) != col_of[r])
                .filter_map(|&c| row_of[c].map(|r2| node[r2]))
                .collect()
        })
        .collect();
    let groups = components(matched.len(), &succ)
        .into_iter()
        .map(|comp| {
            let rows: Vec<usize> = comp.iter().map(|&i| matched[i]).collect();
            let mut coords: Vec<usize> = rows.iter().filter_map(|&r| col_of[r]).collect();
            coords.sort_unstable();
            let mut bodies: Vec<usize> =
                coords.iter().filter(|&&c| c < 3 * model.n_bodies).map(|&c| c / 3).collect();
            bodies.dedup();
            let mut constraints: Vec<usize> = rows.iter().map(|&r| row_constraint[r]).collect();
            constraints.sort_unstable();
            constraints.dedup();
            let kind = classify(model, &bodies, &constraints);
            Group { kind, bodies, constraints, coords, rows }
        })
        .collect();
    Structure {
        groups,
        redundant_rows: (0..n_rows).filter(|&r| col_of[r].is_none()).collect(),
        free_coords: (0..n_cols).filter(|&c| row_of[c].is_none()).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_come_prerequisites_first() {
        // 0 -> 1 <-> 2 -> 3: {3} first, then {1, 2}, then {0}
        let succ = vec![vec![1], vec![2], vec![1, 3], vec![]];
        assert_eq!(components(4, &succ), vec![vec![3], vec![1, 2], vec![0]]);
    }

    #[test]
    fn matching_augments_past_a_greedy_choice() {
        // row 0 takes column 0 greedily; row 1 can only use column 0: augment
        let adj: Vec<&[usize]> = vec![&[0, 1], &[0]];
        let (col_of, _) = matching(2, &adj);
        assert_eq!(col_of, vec![Some(1), Some(0)]);
    }
}
