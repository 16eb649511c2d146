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

use std::fmt;

use serde::{Serialize, Serializer};

/// Longest text accepted, in characters.
pub const MAX_LEN: usize = 4096;
/// Deepest nesting accepted (parentheses, unary signs, powers, function arguments).
pub const MAX_DEPTH: usize = 64;
/// Evaluation stack slots. Operands are ordered by the Sethi-Ullman rule, so a tape of
/// n leaves needs at most log2(n) + 2 slots: 14 for the longest text.
const STACK: usize = 32;

/// A value and its derivatives with respect to the variable, [f, f', .., f^(N-1)]:
/// N = 3 in `eval`, 4 in `eval3`.
type Derivs<const N: usize> = [f64; N];

/// The jet widened to third order, the derivatives it lacks zero.
#[inline(always)]
fn widen<const N: usize>(u: Derivs<N>) -> [f64; 4] {
    std::array::from_fn(|k| if k < N { u[k] } else { 0.0 })
}

/// The first N slots of a third-order jet (N <= 4).
#[inline(always)]
fn narrow<const N: usize>(v: [f64; 4]) -> Derivs<N> {
    std::array::from_fn(|k| v[k])
}

/// g(u) from g, g', g'', g''' at u[0] (Faa di Bruno): (g o u)' = g' u',
/// (g o u)'' = g'' u'^2 + g' u'', (g o u)''' = g''' u'^3 + 3 g'' u' u'' + g' u'''.
#[inline(always)]
fn chain<const N: usize>(g: [f64; 4], u: Derivs<N>) -> Derivs<N> {
    let [_, u1, u2, u3] = widen(u);
    let [g0, g1, g2, g3] = g;
    narrow([g0, g1 * u1, g2 * u1 * u1 + g1 * u2, g3 * u1 * u1 * u1 + 3.0 * g2 * u1 * u2 + g1 * u3])
}

/// Why a text is not an expression, and where (1-based character column; 0 when the
/// problem is not in the text, e.g. a bad variable name).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExprError {
    pub column: usize,
    pub message: String,
    /// a suggestion ("did you mean 'sin'?"), if there is one
    pub hint: Option<String>,
}

impl ExprError {
    fn new(column: usize, message: impl Into<String>) -> ExprError {
        ExprError { column, message: message.into(), hint: None }
    }
    fn hint(mut self, hint: impl Into<String>) -> ExprError {
        self.hint = Some(hint.into());
        self
    }
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)?;
        if self.column > 0 {
            write!(f, " at column {}", self.column)?;
        }
        if let Some(h) = &self.hint {
            write!(f, "; {h}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ExprError {}

/// Functions of one argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fn1 {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Ln,
    Log10,
    Sqrt,
    Abs,
    Neg,
}

/// Functions of two arguments (the binary operators among them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fn2 {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Atan2,
    Min,
    Max,
    Hypot,
}

/// The names a text may call, with their arity.
const FUNCTIONS: [(&str, Func); 20] = [
    ("sin", Func::One(Fn1::Sin)),
    ("cos", Func::One(Fn1::Cos)),
    ("tan", Func::One(Fn1::Tan)),
    ("asin", Func::One(Fn1::Asin)),
    ("acos", Func::One(Fn1::Acos)),
    ("atan", Func::One(Fn1::Atan)),
    ("sinh", Func::One(Fn1::Sinh)),
    ("cosh", Func::One(Fn1::Cosh)),
    ("tanh", Func::One(Fn1::Tanh)),
    ("exp", Func::One(Fn1::Exp)),
    ("ln", Func::One(Fn1::Ln)),
    ("log", Func::One(Fn1::Ln)),
    ("log10", Func::One(Fn1::Log10)),
    ("sqrt", Func::One(Fn1::Sqrt)),
    ("abs", Func::One(Fn1::Abs)),
    ("atan2", Func::Two(Fn2::Atan2)),
    ("min", Func::Two(Fn2::Min)),
    ("max", Func::Two(Fn2::Max)),
    ("pow", Func::Two(Fn2::Pow)),
    ("hypot", Func::Two(Fn2::Hypot)),
];
const CONSTANTS: [(&str, f64); 2] = [("pi", std::f64::consts::PI), ("e", std::f64::consts::E)];

#[derive(Debug, Clone, Copy)]
enum Func {
    One(Fn1),
    Two(Fn2),
}

impl Fn1 {
    fn name(self) -> &'static str {
        match self {
            Fn1::Neg => "unary minus",
            _ => FUNCTIONS
                .iter()
                .find(|(_, f)| matches!(f, Func::One(g) if *g == self))
                .map_or("?", |(n, _)| n),
        }
    }

    /// (g(u), g'(u), g''(u), g'''(u)).
    #[inline(always)]
    fn derivatives(self, u: f64) -> [f64; 4] {
        match self {
            Fn1::Neg => [-u, -1.0, 0.0, 0.0],
            Fn1::Sin => {
                let (s, c) = u.sin_cos();
                [s, c, -s, -c]
            }
            Fn1::Cos => {
                let (s, c) = u.sin_cos();
                [c, -s, -c, s]
            }
            Fn1::Tan => {
                // g' = 1 + g^2, g'' = 2 g g', g''' = 2 g'^2 + 2 g g'' = 2 g' (1 + 3 g^2)
                let g = u.tan();
                let g1 = 1.0 + g * g;
                [g, g1, 2.0 * g * g1, 2.0 * g1 * (1.0 + 3.0 * g * g)]
            }
            Fn1::Asin => {
                // w = 1 - u^2: g' = w^-1/2, g'' = u w^-3/2, g''' = (1 + 2 u^2) w^-5/2
                let w = 1.0 - u * u;
                let r = 1.0 / w.sqrt();
                [u.asin(), r, u * r / w, (1.0 + 2.0 * u * u) * r / (w * w)]
            }
            Fn1::Acos => {
                let w = 1.0 - u * u;
                let r = 1.0 / w.sqrt();
                [u.acos(), -r, -u * r / w, -(1.0 + 2.0 * u * u) * r / (w * w)]
            }
            Fn1::Atan => {
                // r = 1 / (1 + u^2): g' = r, g'' = -2 u r^2, g''' = (6 u^2 - 2) r^3
                let r = 1.0 / (1.0 + u * u);
                [u.atan(), r, -2.0 * u * r * r, (6.0 * u * u - 2.0) * r * r * r]
            }
            Fn1::Sinh => {
                let (sh, ch) = (u.sinh(), u.cosh());
                [sh, ch, sh, ch]
            }
            Fn1::Cosh => {
                let (sh, ch) = (u.sinh(), u.cosh());
                [ch, sh, ch, sh]
            }
            Fn1::Tanh => {
                // g' = 1 - g^2, g'' = -2 g g', g''' = -2 g'^2 - 2 g g'' = -2 g' (1 - 3 g^2)
                let g = u.tanh();
                let g1 = 1.0 - g * g;
                [g, g1, -2.0 * g * g1, -2.0 * g1 * (1.0 - 3.0 * g * g)]
            }
            Fn1::Exp => {
                let g = u.exp();
                [g, g, g, g]
            }
            Fn1::Ln => {
                let r = 1.0 / u;
                [u.ln(), r, -r * r, 2.0 * r * r * r]
            }
            Fn1::Log10 => {
                let r = 1.0 / u;
                let k = std::f64::consts::LOG10_E;
                [u.log10(), k * r, -k * r * r, 2.0 * k * r * r * r]
            }
            Fn1::Sqrt => {
                // g' = u^-1/2 / 2, g'' = -u^-3/2 / 4, g''' = 3 u^-5/2 / 8
                let g = u.sqrt();
                let g1 = 0.5 / g;
                let g2 = -0.5 * g1 / u;
                [g, g1, g2, -1.5 * g2 / u]
            }
            Fn1::Abs => {
                // the right derivative at 0
                let s = if u < 0.0 { -1.0 } else { 1.0 };
                [u.abs(), s, 0.0, 0.0]
            }
        }
    }

    #[inline(always)]
    fn jet<const N: usize>(self, u: Derivs<N>) -> Derivs<N> {
        if let Fn1::Neg = self {
            return u.map(|v| -v);
        }
        chain(self.derivatives(u[0]), u)
    }
}

impl Fn2 {
    fn name(self) -> &'static str {
        match self {
            Fn2::Add => "'+'",
            Fn2::Sub => "'-'",
            Fn2::Mul => "'*'",
            Fn2::Div => "'/'",
            Fn2::Pow => "the power",
            Fn2::Atan2 => "atan2",
            Fn2::Min => "min",
            Fn2::Max => "max",
            Fn2::Hypot => "hypot",
        }
    }

    fn commutes(self) -> bool {
        matches!(self, Fn2::Add | Fn2::Mul | Fn2::Min | Fn2::Max | Fn2::Hypot)
    }

    #[inline(always)]
    fn jet<const N: usize>(self, a: Derivs<N>, b: Derivs<N>) -> Derivs<N> {
        match self {
            Fn2::Add => std::array::from_fn(|k| a[k] + b[k]),
            Fn2::Sub => std::array::from_fn(|k| a[k] - b[k]),
            Fn2::Mul => {
                // Leibniz: (a b)^(n) = sum over k of C(n, k) a^(k) b^(n-k)
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (widen(a), widen(b));
                narrow([
                    a0 * b0,
                    a1 * b0 + a0 * b1,
                    a2 * b0 + 2.0 * a1 * b1 + a0 * b2,
                    a3 * b0 + 3.0 * (a2 * b1 + a1 * b2) + a0 * b3,
                ])
            }
            Fn2::Div => {
                // q = a / b from q b = a: q' = (a' - q b') / b, q'' = (a'' - 2 q' b' - q b'') / b,
                // q''' = (a''' - 3 q'' b' - 3 q' b'' - q b''') / b
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (widen(a), widen(b));
                let q = a0 / b0;
                let q1 = (a1 - q * b1) / b0;
                let q2 = (a2 - 2.0 * q1 * b1 - q * b2) / b0;
                narrow([q, q1, q2, (a3 - 3.0 * (q2 * b1 + q1 * b2) - q * b3) / b0])
            }
            Fn2::Pow => pow_jet(a, b),
            Fn2::Atan2 => {
                // theta = atan2(y, x): theta' = n / d with n = x y' - y x', d = x^2 + y^2, so
                // n' = x y'' - y x'', n'' = x' y'' - y' x'' + x y''' - y x''',
                // d' = 2 (x x' + y y'), d'' = 2 (x'^2 + x x'' + y'^2 + y y''); then the
                // quotient rule as for '/'
                let ([y0, y1, y2, y3], [x0, x1, x2, x3]) = (widen(a), widen(b));
                let d = x0 * x0 + y0 * y0;
                let (n0, n1) = (x0 * y1 - y0 * x1, x0 * y2 - y0 * x2);
                let n2 = x1 * y2 - y1 * x2 + x0 * y3 - y0 * x3;
                let (d1, d2) = (2.0 * (x0 * x1 + y0 * y1), 2.0 * (x1 * x1 + x0 * x2 + y1 * y1 + y0 * y2));
                let w1 = n0 / d;
                let w2 = (n1 - w1 * d1) / d;
                narrow([y0.atan2(x0), w1, w2, (n2 - 2.0 * w2 * d1 - w1 * d2) / d])
            }
            Fn2::Min => {
                if b[0] < a[0] {
                    b
                } else {
                    a
                }
            }
            Fn2::Max => {
                if b[0] > a[0] {
                    b
                } else {
                    a
                }
            }
            Fn2::Hypot => {
                // h^2 = a^2 + b^2 differentiated: h h' = a a' + b b',
                // h h'' + h'^2 = a a'' + a'^2 + b b'' + b'^2,
                // h h''' + 3 h' h'' = a a''' + 3 a' a'' + b b''' + 3 b' b''
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (widen(a), widen(b));
                let h = a0.hypot(b0);
                let h1 = (a0 * a1 + b0 * b1) / h;
                let h2 = (a1 * a1 + a0 * a2 + b1 * b1 + b0 * b2 - h1 * h1) / h;
                let h3 = (3.0 * (a1 * a2 + b1 * b2) + a0 * a3 + b0 * b3 - 3.0 * h1 * h2) / h;
                narrow([h, h1, h2, h3])
            }
        }
    }
}

/// a^b on jets: the power rule when b is constant (any sign of a), exp(b ln a) otherwise.
#[inline(always)]
fn pow_jet<const N: usize>(a: Derivs<N>, b: Derivs<N>) -> Derivs<N> {
    if b[1..].iter().all(|v| *v == 0.0) {
        return powc_jet(a, b[0]);
    }
    // f = exp(l), l = b ln a: f' = f l', f'' = f (l'^2 + l''), f''' = f (l'^3 + 3 l' l'' + l''')
    let [_, l1, l2, l3] = widen(Fn2::Mul.jet(b, Fn1::Ln.jet(a)));
    let f = a[0].powf(b[0]);
    narrow([f, f * l1, f * (l1 * l1 + l2), f * (l1 * l1 * l1 + 3.0 * l1 * l2 + l3)])
}

/// a^n for a constant n: g = a^n has g^(k) = n (n - 1) .. (n - k + 1) a^(n-k).
#[inline(always)]
fn powc_jet<const N: usize>(a: Derivs<N>, n: f64) -> Derivs<N> {
    if n == 0.0 {
        return narrow([1.0, 0.0, 0.0, 0.0]);
    }
    let (p0, p1, p2, p3) = if n == n.trunc() && n.abs() < 1024.0 {
        let k = n as i32;
        (a[0].powi(k), a[0].powi(k - 1), a[0].powi(k - 2), a[0].powi(k - 3))
    } else {
        (a[0].powf(n), a[0].powf(n - 1.0), a[0].powf(n - 2.0), a[0].powf(n - 3.0))
    };
    // a factor n (n - 1) .. that vanishes (n = 1, 2) drops its term: at a = 0 its power of
    // a is infinite, and 0 * inf must not become NaN
    let (c2, c3) = (n * (n - 1.0), n * (n - 1.0) * (n - 2.0));
    let g2 = if c2 == 0.0 { 0.0 } else { c2 * p2 };
    let g3 = if c3 == 0.0 { 0.0 } else { c3 * p3 };
    chain([p0, n * p1, g2, g3], a)
}

/// One instruction of the postfix tape.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
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

/// One tape instruction on the stack.
#[inline(always)]
fn step<const N: usize>(op: Op, stack: &mut [Derivs<N>], sp: &mut usize, x: f64) {
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

// --- tokens -----------------------------------------------------------------------------

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    Comma,
    End,
}

#[derive(Debug, Clone)]
struct Token {
    kind: Tok,
    /// 1-based character column of its first character
    col: usize,
}

impl Token {
    fn describe(&self) -> String {
        match &self.kind {
            Tok::Num(_) => "a number".into(),
            Tok::Name(n) => format!("'{n}'"),
            Tok::Plus => "'+'".into(),
            Tok::Minus => "'-'".into(),
            Tok::Star => "'*'".into(),
            Tok::Slash => "'/'".into(),
            Tok::Caret => "'^'".into(),
            Tok::LParen => "'('".into(),
            Tok::RParen => "')'".into(),
            Tok::Comma => "','".into(),
            Tok::End => "the end".into(),
        }
    }
}

fn tokenize(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && chars[i].is_ascii_digit() {
                i += 1;
            }
            if i < chars.len() && chars[i] == '.' {
                i += 1;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            let mantissa_digits = chars[start..i].iter().any(|c| c.is_ascii_digit());
            let mut ok = mantissa_digits;
            if ok && i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                // an exponent needs digits: "2e" is not a number (write 2*e)
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                let digits = j;
                while j < chars.len() && chars[j].is_ascii_digit() {
                    j += 1;
                }
                ok = j > digits;
                i = j;
            }
            // a number runs into no letter, digit or point
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '.' || chars[i] == '_')
            {
                ok = false;
                i += 1;
            }
            let s: String = chars[start..i].iter().collect();
            if !ok {
                return Err(ExprError::new(col, format!("malformed number '{s}'"))
                    .hint("numbers look like 2, 0.5, .5 or 1e-3; multiply with '*'"));
            }
            let v: f64 = s.parse().map_err(|_| ExprError::new(col, format!("malformed number '{s}'")))?;
            if !v.is_finite() {
                return Err(ExprError::new(col, format!("number '{s}' is too large")));
            }
            out.push(Token { kind: Tok::Num(v), col });
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Token { kind: Tok::Name(chars[start..i].iter().collect()), col });
            continue;
        }
        let kind = match c {
            '+' => Tok::Plus,
            '-' => Tok::Minus,
            '*' if chars.get(i + 1) == Some(&'*') => {
                i += 1;
                Tok::Caret
            }
            '*' => Tok::Star,
            '/' => Tok::Slash,
            '^' => Tok::Caret,
            '(' => Tok::LParen,
            ')' => Tok::RParen,
            ',' => Tok::Comma,
            _ => {
                let hint = match c {
                    '[' | ']' | '{' | '}' => "group with '(' and ')'",
                    _ => "expressions use numbers, names, + - * / ^ ** ( ) and ','",
                };
                return Err(ExprError::new(col, format!("unexpected character {c:?}")).hint(hint));
            }
        };
        out.push(Token { kind, col });
        i += 1;
    }
    out.push(Token { kind: Tok::End, col: chars.len() + 1 });
    Ok(out)
}

// --- parsing into a folded tree ------------------------------------------------------------

#[derive(Debug)]
enum Node {
    Num(f64),
    Var,
    Call1 { f: Fn1, arg: Box<Node>, col: usize },
    Call2 { f: Fn2, a: Box<Node>, b: Box<Node>, col: usize },
}

struct Parser<'a> {
    tokens: &'a [Token],
    pos: usize,
    depth: usize,
    variable: &'a str,
}

impl Parser<'_> {
    fn peek(&self) -> &Token {
        &self.tokens[self.pos]
    }

    fn next(&mut self) -> Token {
        let t = self.tokens[self.pos].clone();
        if t.kind != Tok::End {
            self.pos += 1;
        }
        t
    }

    fn expr(&mut self) -> Result<Node, ExprError> {
        let mut lhs = self.term()?;
        loop {
            let f = match self.peek().kind {
                Tok::Plus => Fn2::Add,
                Tok::Minus => Fn2::Sub,
                _ => return Ok(lhs),
            };
            let col = self.next().col;
            let rhs = self.term()?;
            lhs = call2(f, lhs, rhs, col)?;
        }
    }

    fn term(&mut self) -> Result<Node, ExprError> {
        let mut lhs = self.unary()?;
        loop {
            let f = match self.peek().kind {
                Tok::Star => Fn2::Mul,
                Tok::Slash => Fn2::Div,
                _ => return Ok(lhs),
            };
            let col = self.next().col;
            let rhs = self.unary()?;
            lhs = call2(f, lhs, rhs, col)?;
        }
    }

    /// Every nesting passes through here (parentheses, arguments, signs, exponents):
    /// the depth count bounds the recursion whatever the text.
    fn unary(&mut self) -> Result<Node, ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(ExprError::new(
                self.peek().col,
                format!("expression nested deeper than {MAX_DEPTH} levels"),
            ));
        }
        let node = match self.peek().kind {
            Tok::Minus => {
                let col = self.next().col;
                let arg = self.unary()?;
                call1(Fn1::Neg, arg, col)?
            }
            Tok::Plus => {
                self.next();
                self.unary()?
            }
            _ => self.power()?,
        };
        self.depth -= 1;
        Ok(node)
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.primary()?;
        if self.peek().kind == Tok::Caret {
            let col = self.next().col;
            let exponent = self.unary()?;
            return call2(Fn2::Pow, base, exponent, col);
        }
        Ok(base)
    }

    fn primary(&mut self) -> Result<Node, ExprError> {
        let tok = self.next();
        match tok.kind {
            Tok::Num(v) => Ok(Node::Num(v)),
            Tok::LParen => {
                let inner = self.expr()?;
                self.expect_close(tok.col)?;
                Ok(inner)
            }
            Tok::Name(name) => self.name(&name, tok.col),
            Tok::End => Err(ExprError::new(tok.col, "unexpected end of the expression")
                .hint("expected a number, a name or '('")),
            _ => Err(ExprError::new(tok.col, format!("unexpected {}", tok.describe()))
                .hint("expected a number, a name or '('")),
        }
    }

    fn expect_close(&mut self, open_col: usize) -> Result<(), ExprError> {
        let t = self.next();
        if t.kind == Tok::RParen {
            return Ok(());
        }
        Err(ExprError::new(
            t.col,
            format!("expected ')' (for the '(' at column {open_col}), found {}", t.describe()),
        ))
    }

    fn name(&mut self, name: &str, col: usize) -> Result<Node, ExprError> {
        let called = self.peek().kind == Tok::LParen;
        if let Some((_, f)) = FUNCTIONS.iter().find(|(n, _)| *n == name) {
            if !called {
                return Err(ExprError::new(
                    col,
                    format!("function '{name}' needs its arguments in parentheses"),
                )
                .hint(format!("write {name}(...)")));
            }
            let open = self.next().col;
            let mut args = vec![self.expr()?];
            while self.peek().kind == Tok::Comma {
                self.next();
                args.push(self.expr()?);
            }
            self.expect_close(open)?;
            let want = match f {
                Func::One(_) => 1,
                Func::Two(_) => 2,
            };
            if args.len() != want {
                let s = if want == 1 { "" } else { "s" };
                return Err(ExprError::new(
                    col,
                    format!("{name} takes {want} argument{s}, got {}", args.len()),
                ));
            }
            return match *f {
                Func::One(g) => call1(g, args.pop().expect("one argument"), col),
                Func::Two(g) => {
                    let b = args.pop().expect("two arguments");
                    let a = args.pop().expect("two arguments");
                    call2(g, a, b, col)
                }
            };
        }
        let node = if name == self.variable {
            Node::Var
        } else if let Some((_, v)) = CONSTANTS.iter().find(|(n, _)| *n == name) {
            Node::Num(*v)
        } else {
            return Err(unknown_name(name, col, self.variable));
        };
        if called {
            return Err(ExprError::new(col, format!("'{name}' is not a function")).hint("multiply with '*'"));
        }
        Ok(node)
    }
}

fn unknown_name(name: &str, col: usize, variable: &str) -> ExprError {
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
fn edit_distance(a: &str, b: &str) -> usize {
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

/// f(arg), folded when arg is a constant.
fn call1(f: Fn1, arg: Node, col: usize) -> Result<Node, ExprError> {
    if let Node::Num(u) = arg {
        let v = f.derivatives(u)[0];
        if !v.is_finite() {
            return Err(ExprError::new(col, format!("{}({u}) is not a finite real number", f.name())));
        }
        return Ok(Node::Num(v));
    }
    Ok(Node::Call1 { f, arg: Box::new(arg), col })
}

/// f(a, b), folded when both are constants; a constant zero divisor is refused.
fn call2(f: Fn2, a: Node, b: Node, col: usize) -> Result<Node, ExprError> {
    if f == Fn2::Div && matches!(b, Node::Num(v) if v == 0.0) {
        return Err(ExprError::new(col, "division by zero"));
    }
    if let (Node::Num(x), Node::Num(y)) = (&a, &b) {
        let v = f.jet([*x, 0.0, 0.0], [*y, 0.0, 0.0])[0];
        if !v.is_finite() {
            return Err(ExprError::new(
                col,
                format!("{} of {x} and {y} is not a finite real number", f.name()),
            ));
        }
        return Ok(Node::Num(v));
    }
    Ok(Node::Call2 { f, a: Box::new(a), b: Box::new(b), col })
}

/// Appends the postfix code of `node`; returns the stack slots it needs. The operand
/// needing more slots goes first (Sethi-Ullman), swapped back for ordered operators.
fn emit(node: &Node, tape: &mut Vec<Op>, columns: &mut Vec<u32>) -> usize {
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
fn need(node: &Node) -> usize {
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
