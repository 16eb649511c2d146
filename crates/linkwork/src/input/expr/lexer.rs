//! Tokens of an expression's text, each with its column.

use super::error::ExprError;

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Tok {
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
pub(super) struct Token {
    pub(super) kind: Tok,
    /// 1-based character column of its first character
    pub(super) col: usize,
}

impl Token {
    pub(super) fn describe(&self) -> String {
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

pub(super) fn tokenize(text: &str) -> Result<Vec<Token>, ExprError> {
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
