//! The flat postfix tape and one instruction of it on the stack of jets.

use super::rules::{narrow, powc_jet, Derivs, Fn1, Fn2};

/// One instruction of the postfix tape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Op {
    Const(f64),
    Var,
    /// f(top)
    Call1(Fn1),
    /// f(second, top)
    Call2(Fn2),
    /// top ^ n for a constant n
    PowConst(f64),
    /// exchanges the two top slots (an operand evaluated out of order)
    Swap,
}

/// One tape instruction on the stack.
#[inline(always)]
pub(super) fn step<const N: usize>(op: Op, stack: &mut [Derivs<N>], sp: &mut usize, x: f64) {
    match op {
        Op::Const(c) => {
            stack[*sp] = narrow([c, 0.0, 0.0, 0.0]);
            *sp += 1;
        }
        Op::Var => {
            stack[*sp] = narrow([x, 1.0, 0.0, 0.0]);
            *sp += 1;
        }
        Op::Call1(f) => stack[*sp - 1] = f.jet(stack[*sp - 1]),
        Op::PowConst(n) => stack[*sp - 1] = powc_jet(stack[*sp - 1], n),
        Op::Call2(f) => {
            *sp -= 1;
            stack[*sp - 1] = f.jet(stack[*sp - 1], stack[*sp]);
        }
        Op::Swap => stack.swap(*sp - 1, *sp - 2),
    }
}
