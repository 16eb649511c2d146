//! Recursive descent into a tree, constants folded as they are met.

use super::error::ExprError;
use super::lexer::{Tok, Token};
use super::rules::{Fn1, Fn2, Func, CONSTANTS, FUNCTIONS};
use super::suggest::unknown_name;

/// Deepest nesting accepted (parentheses, unary signs, powers, function arguments).
pub const MAX_DEPTH: usize = 64;

// --- parsing into a folded tree ------------------------------------------------------------

#[derive(Debug)]
pub(super) enum Node {
    Num(f64),
    Var,
    Call1 { f: Fn1, arg: Box<Node>, col: usize },
    Call2 { f: Fn2, a: Box<Node>, b: Box<Node>, col: usize },
}

pub(super) struct Parser<'a> {
    pub(super) tokens: &'a [Token],
    pub(super) pos: usize,
    pub(super) depth: usize,
    pub(super) variable: &'a str,
}

impl Parser<'_> {
    pub(super) fn peek(&self) -> &Token {
        &self.tokens[self.pos]
    }

    pub(super) fn next(&mut self) -> Token {
        let t = self.tokens[self.pos].clone();
        if t.kind != Tok::End {
            self.pos += 1;
        }
        t
    }

    pub(super) fn expr(&mut self) -> Result<Node, ExprError> {
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

    pub(super) fn term(&mut self) -> Result<Node, ExprError> {
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
    pub(super) fn unary(&mut self) -> Result<Node, ExprError> {
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

    pub(super) fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.primary()?;
        if self.peek().kind == Tok::Caret {
            let col = self.next().col;
            let exponent = self.unary()?;
            return call2(Fn2::Pow, base, exponent, col);
        }
        Ok(base)
    }

    pub(super) fn primary(&mut self) -> Result<Node, ExprError> {
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

    pub(super) fn expect_close(&mut self, open_col: usize) -> Result<(), ExprError> {
        let t = self.next();
        if t.kind == Tok::RParen {
            return Ok(());
        }
        Err(ExprError::new(
            t.col,
            format!("expected ')' (for the '(' at column {open_col}), found {}", t.describe()),
        ))
    }

    pub(super) fn name(&mut self, name: &str, col: usize) -> Result<Node, ExprError> {
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

/// f(arg), folded when arg is a constant.
pub(super) fn call1(f: Fn1, arg: Node, col: usize) -> Result<Node, ExprError> {
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
pub(super) fn call2(f: Fn2, a: Node, b: Node, col: usize) -> Result<Node, ExprError> {
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
