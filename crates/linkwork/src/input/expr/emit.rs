//! The tree emitted as a postfix tape, operands in Sethi-Ullman order.

use super::parser::Node;
use super::rules::Fn2;
use super::tape::Op;

/// Appends the postfix code of `node`; returns the stack slots it needs. The operand
/// needing more slots goes first (Sethi-Ullman), swapped back for ordered operators.
pub(super) fn emit(node: &Node, tape: &mut Vec<Op>, columns: &mut Vec<u32>) -> usize {
    let push = |tape: &mut Vec<Op>, columns: &mut Vec<u32>, op: Op, col: usize| {
        tape.push(op);
        columns.push(col as u32);
    };
    match node {
        Node::Num(v) => {
            push(tape, columns, Op::Const(*v), 0);
            1
        }
        Node::Var => {
            push(tape, columns, Op::Var, 0);
            1
        }
        Node::Call1 { f, arg, col } => {
            let need = emit(arg, tape, columns);
            push(tape, columns, Op::Call1(*f), *col);
            need
        }
        Node::Call2 { f: Fn2::Pow, a, b: exponent, col } if matches!(**exponent, Node::Num(_)) => {
            let Node::Num(n) = **exponent else { unreachable!("matched a number") };
            let need = emit(a, tape, columns);
            push(tape, columns, Op::PowConst(n), *col);
            need
        }
        Node::Call2 { f, a, b, col } => {
            let (na, nb) = (need(a), need(b));
            if nb > na {
                emit(b, tape, columns);
                emit(a, tape, columns);
                if !f.commutes() {
                    push(tape, columns, Op::Swap, *col);
                }
            } else {
                emit(a, tape, columns);
                emit(b, tape, columns);
            }
            push(tape, columns, Op::Call2(*f), *col);
            if na == nb {
                na + 1
            } else {
                na.max(nb)
            }
        }
    }
}

/// The stack slots `node` needs (what `emit` returns, without emitting).
pub(super) fn need(node: &Node) -> usize {
    match node {
        Node::Num(_) | Node::Var => 1,
        Node::Call1 { arg, .. } => need(arg),
        Node::Call2 { f: Fn2::Pow, a, b, .. } if matches!(**b, Node::Num(_)) => need(a),
        Node::Call2 { a, b, .. } => {
            let (na, nb) = (need(a), need(b));
            if na == nb {
                na + 1
            } else {
                na.max(nb)
            }
        }
    }
}
