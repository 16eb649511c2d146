//! Expressions written as text, such as `0.35 - 0.16*sin(150*t)`, with exact first,
//! second and third derivatives.
//!
//! A small hand-written parser (nothing is evaluated while parsing, no name outside the
//! fixed list is looked up) turns the text into a tree, folds the constant parts, and
//! emits a flat postfix tape. Evaluation runs the tape on jets with a fixed-size stack
//! (no allocation, no recursion): of second order (value, d/dx, d2/dx2) in `eval`, for
//! motion laws, and of third order (with d3/dx3) in `eval3`, for curves r(phi) whose
//! followers need c'''. Every rule is written once, at third order; the second-order
//! instance never computes the unused slot (the compiler drops it).
//!
//! Grammar (`^` and `**` are both the power, right-associative; unary minus binds less
//! tightly than the power, so `-t^2 = -(t^2)`):
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/') unary)*
//! unary   := ('-' | '+') unary | power
//! power   := primary (('^' | '**') unary)?
//! primary := number | constant | variable | function '(' expr (',' expr)* ')' | '(' expr ')'
//! ```
//!
//! Constants `pi`, `e`; functions `sin cos tan asin acos atan atan2(y, x) sinh cosh tanh
//! exp ln log (= ln) log10 sqrt abs min max pow(a, b) hypot(a, b)`. At a kink (`abs` at
//! 0, `min`/`max` where both arguments are equal) the derivatives are those of one side.

use serde::{Serialize, Serializer};

/// Longest text accepted, in characters.
pub const MAX_LEN: usize = 4096;
/// Evaluation stack slots. Operands are ordered by the Sethi-Ullman rule, so a tape of
/// n leaves needs at most log2(n) + 2 slots: 14 for the longest text.
const STACK: usize = 32;

mod emit;
mod error;
mod lexer;
mod parser;
mod rules;
mod suggest;
mod tape;

use emit::emit;
pub use error::ExprError;
use lexer::{tokenize, Tok};
use parser::Parser;
pub use parser::MAX_DEPTH;
use rules::{Derivs, Fn2, CONSTANTS, FUNCTIONS};
use tape::{step, Op};

/// A parsed expression of one variable, ready to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct Expression {
    text: String,
    variable: String,
    tape: Vec<Op>,
    /// n_tape: the column each instruction comes from (for error messages)
    columns: Vec<u32>,
    /// stack slots the tape needs
    need: usize,
}

impl Serialize for Expression {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.text)
    }
}

impl Expression {
    /// Parses `text` as an expression of `variable` (`t` for a motion law).
    pub fn parse(text: &str, variable: &str) -> Result<Expression, ExprError> {
        check_variable(variable)?;
        let n_chars = text.chars().count();
        if n_chars > MAX_LEN {
            return Err(ExprError::new(
                MAX_LEN + 1,
                format!("expression is longer than {MAX_LEN} characters ({n_chars})"),
            ));
        }
        let tokens = tokenize(text)?;
        let mut parser = Parser { tokens: &tokens, pos: 0, depth: 0, variable };
        let root = parser.expr()?;
        let end = parser.peek();
        if end.kind != Tok::End {
            return Err(match end.kind {
                Tok::RParen => ExprError::new(end.col, "unmatched ')'"),
                Tok::Comma => {
                    ExprError::new(end.col, "unexpected ','").hint("a ',' separates function arguments")
                }
                _ => ExprError::new(
                    end.col,
                    format!("expected an operator (+ - * / ^) before {}", end.describe()),
                )
                .hint("write multiplication with '*', e.g. 2*t"),
            });
        }
        let mut tape = Vec::new();
        let mut columns = Vec::new();
        let need = emit(&root, &mut tape, &mut columns);
        if need > STACK {
            // unreachable within MAX_LEN (see STACK); kept so that no text can overflow it
            return Err(ExprError::new(1, "expression too complex to evaluate"));
        }
        Ok(Expression { text: text.to_string(), variable: variable.to_string(), tape, columns, need })
    }

    /// The text as given.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The variable's name.
    pub fn variable(&self) -> &str {
        &self.variable
    }

    /// Whether the expression does not depend on its variable.
    pub fn is_constant(&self) -> bool {
        matches!(self.tape.as_slice(), [Op::Const(_)])
    }

    /// (f, df/dx, d2f/dx2) at x. Outside the domain of a function (sqrt(-1), ln(0), 1/0)
    /// the result is not finite; `diagnose` says where.
    #[inline]
    pub fn eval(&self, x: f64) -> [f64; 3] {
        // most expressions need a few slots: do not clear the whole stack for them
        if self.need <= 4 {
            self.run::<3, 4>(x)
        } else {
            self.run::<3, STACK>(x)
        }
    }

    /// (f, df/dx, d2f/dx2, d3f/dx3) at x, exactly as `eval` gives the first three (the
    /// same rules, one order further). Not finite outside a function's domain, or where
    /// only the third derivative is infinite (sqrt(x)^3 at 0); `diagnose3` says where.
    #[inline]
    pub fn eval3(&self, x: f64) -> [f64; 4] {
        if self.need <= 4 {
            self.run::<4, 4>(x)
        } else {
            self.run::<4, STACK>(x)
        }
    }

    /// The tape on jets of N slots with a stack of S.
    #[inline(always)]
    fn run<const N: usize, const S: usize>(&self, x: f64) -> Derivs<N> {
        let mut stack = [[0.0; N]; S];
        let mut sp = 0;
        for op in &self.tape {
            step(*op, &mut stack, &mut sp, x);
        }
        stack[0]
    }

    /// Why the value at x is not finite: the first operation that turns finite
    /// arguments into a non-finite result, with its column. None if all is finite.
    pub fn diagnose(&self, x: f64) -> Option<String> {
        self.diagnose_jets::<3>(x)
    }

    /// `diagnose` for `eval3`: the third derivative included.
    pub fn diagnose3(&self, x: f64) -> Option<String> {
        self.diagnose_jets::<4>(x)
    }

    fn diagnose_jets<const N: usize>(&self, x: f64) -> Option<String> {
        let mut stack = [[0.0; N]; STACK];
        let mut sp = 0;
        let finite = |j: &Derivs<N>| j.iter().all(|v| v.is_finite());
        for (op, &col) in self.tape.iter().zip(&self.columns) {
            let args: Vec<Derivs<N>> = match op {
                Op::Call1(_) | Op::PowConst(_) => vec![stack[sp - 1]],
                Op::Call2(_) => vec![stack[sp - 2], stack[sp - 1]],
                _ => Vec::new(),
            };
            step(*op, &mut stack, &mut sp, x);
            let out = stack[sp - 1];
            if !finite(&out) && args.iter().all(finite) {
                let values: Vec<String> = args.iter().map(|a| format!("{}", a[0])).collect();
                let what = match op {
                    Op::Call2(Fn2::Div) if args[1][0] == 0.0 => "division by zero".to_string(),
                    Op::Call1(f) => format!("{}({})", f.name(), values.join(", ")),
                    Op::Call2(f) if matches!(f, Fn2::Atan2 | Fn2::Min | Fn2::Max | Fn2::Hypot) => {
                        format!("{}({})", f.name(), values.join(", "))
                    }
                    Op::Call2(f) => format!("{} of {}", f.name(), values.join(" and ")),
                    Op::PowConst(n) => format!("the power {}^{}", values[0], n),
                    _ => "a constant".to_string(),
                };
                let part = if out[0].is_finite() { "its derivatives are" } else { "the value is" };
                let shown: Vec<String> = out.iter().map(|v| v.to_string()).collect();
                return Some(format!(
                    "{what} at column {col} of '{}': {part} not finite ({}) at {} = {x}",
                    self.text,
                    shown.join(", "),
                    self.variable
                ));
            }
        }
        None
    }
}

fn check_variable(variable: &str) -> Result<(), ExprError> {
    let mut chars = variable.chars();
    let ident = matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ident {
        return Err(ExprError::new(
            0,
            format!("variable name {variable:?} is not a name (letters, digits, _)"),
        ));
    }
    if FUNCTIONS.iter().any(|(n, _)| *n == variable) || CONSTANTS.iter().any(|(n, _)| *n == variable) {
        return Err(ExprError::new(
            0,
            format!("variable name '{variable}' is taken by a function or constant"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_constants_and_keeps_the_text() {
        let e = Expression::parse("2*pi + 3^2", "t").unwrap();
        assert!(e.is_constant());
        assert_eq!(e.eval(0.3), [2.0 * std::f64::consts::PI + 9.0, 0.0, 0.0]);
        assert_eq!(e.text(), "2*pi + 3^2");
    }

    #[test]
    fn stack_need_stays_small_on_right_nested_chains() {
        let text = "t+(".repeat(60) + "t" + &")".repeat(60);
        let e = Expression::parse(&text, "t").unwrap();
        assert_eq!(e.eval(1.0), [61.0, 61.0, 0.0]);
        assert!(need_of(&e) <= 3);
    }

    fn need_of(e: &Expression) -> usize {
        let (mut sp, mut most) = (0usize, 0usize);
        for op in &e.tape {
            match op {
                Op::Const(_) | Op::Var => sp += 1,
                Op::Call2(_) => sp -= 1,
                _ => {}
            }
            most = most.max(sp);
        }
        most
    }
}
