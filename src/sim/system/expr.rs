//! The expressions instructors write in a system scene: checked here, with
//! the byte offset of every problem inside the expression, then handed to
//! `exmex` (see [`super::compile`]) in a canonical, fully parenthesised
//! spelling.
//!
//! The check is ours because a deck error must point at the character that
//! is wrong (`exmex` reports no positions), and because `exmex`'s default
//! grammar differs from written mathematics in three places the canonical
//! form settles: `-x^2` is −(x²), `a^b^c` is a^(b^c), and numbers may carry
//! an exponent (`1e-3`).

use std::fmt::Write as _;

/// The functions an expression may call, with their number of arguments.
pub const FUNCTIONS: [(&str, usize); 18] = [
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("asin", 1),
    ("acos", 1),
    ("atan", 1),
    ("atan2", 2),
    ("sinh", 1),
    ("cosh", 1),
    ("tanh", 1),
    ("exp", 1),
    ("ln", 1),
    ("log10", 1),
    ("sqrt", 1),
    ("abs", 1),
    ("sign", 1),
    ("min", 2),
    ("max", 2),
];

/// Names an expression knows without being told: the constants and time.
pub const BUILTINS: [&str; 3] = ["pi", "e", "t"];

/// Longest name of a variable, parameter or observable (so a measure naming
/// one stays a small copyable value, see [`super::Name`]).
pub const MAX_NAME: usize = super::name::CAPACITY;

/// The arity of a function name, if it is one.
pub fn arity(name: &str) -> Option<usize> {
    FUNCTIONS.iter().find(|(f, _)| *f == name).map(|(_, n)| *n)
}

/// A problem in an expression: where (byte offset and length within the
/// expression text), what, and the unknown name when that is the problem
/// (for a did-you-mean).
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    pub at: usize,
    pub len: usize,
    pub message: String,
    pub hint: Option<String>,
    pub unknown: Option<String>,
}

impl ExprError {
    fn new(at: usize, len: usize, message: impl Into<String>) -> ExprError {
        ExprError {
            at,
            len: len.max(1),
            message: message.into(),
            hint: None,
            unknown: None,
        }
    }
    fn hint(mut self, hint: impl Into<String>) -> ExprError {
        self.hint = Some(hint.into());
        self
    }
}

impl std::fmt::Display for ExprError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (at character {})", self.message, self.at + 1)
    }
}

/// Whether `s` is a name an author may give: an ASCII letter or `_`, then
/// letters, digits or `_`.
pub fn is_name(s: &str) -> bool {
    let mut chars = s.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
    Open,
    Close,
    Comma,
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(_) => "a number".into(),
        Tok::Name(n) => format!("`{n}`"),
        Tok::Op(c) => format!("`{c}`"),
        Tok::Open => "`(`".into(),
        Tok::Close => "`)`".into(),
        Tok::Comma => "`,`".into(),
    }
}

fn lex(text: &str) -> Result<Vec<(Tok, usize, usize)>, ExprError> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            if i < b.len() && b[i] == b'.' {
                i += 1;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                let mut j = i + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                if j < b.len() && b[j].is_ascii_digit() {
                    while j < b.len() && b[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                } else {
                    return Err(ExprError::new(
                        start,
                        j - start,
                        format!("`{}` is not a number", &text[start..j]),
                    )
                    .hint("an exponent needs digits, as in 1e-3"));
                }
            }
            if i < b.len() && (b[i].is_ascii_alphabetic() || b[i] == b'_') {
                return Err(ExprError::new(
                    i,
                    1,
                    format!("a name right after the number `{}`", &text[start..i]),
                )
                .hint("write the multiplication: 2*x"));
            }
            let value: f64 = text[start..i].parse().map_err(|_| {
                ExprError::new(
                    start,
                    i - start,
                    format!("`{}` is not a number", &text[start..i]),
                )
            })?;
            if !value.is_finite() {
                return Err(ExprError::new(
                    start,
                    i - start,
                    format!("`{}` is too large for a number", &text[start..i]),
                ));
            }
            out.push((Tok::Num(value), start, i - start));
            continue;
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push((Tok::Name(text[start..i].to_string()), start, i - start));
            continue;
        }
        let tok = match c {
            b'+' | b'-' | b'*' | b'/' | b'^' => Tok::Op(c as char),
            b'(' => Tok::Open,
            b')' => Tok::Close,
            b',' => Tok::Comma,
            _ => {
                let ch = text[i..].chars().next().unwrap_or('?');
                let hint = match ch {
                    '×' | '·' => Some("multiply with *"),
                    '−' => Some("this is a Unicode minus; type -"),
                    '[' | ']' | '{' | '}' => Some("group with ( )"),
                    _ => None,
                };
                let e = ExprError::new(i, ch.len_utf8(), format!("unexpected character `{ch}`"));
                return Err(match hint {
                    Some(h) => e.hint(h),
                    None => e,
                });
            }
        };
        out.push((tok, start, 1));
        i += 1;
    }
    Ok(out)
}

/// A parsed expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    Num(f64),
    /// A name with its byte offset in the text.
    Name(String, usize),
    Neg(Box<Node>),
    Bin(char, Box<Node>, Box<Node>),
    Call(String, Vec<Node>),
}

struct Parser<'a> {
    toks: &'a [(Tok, usize, usize)],
    pos: usize,
    end: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|t| &t.0)
    }
    fn at(&self) -> (usize, usize) {
        self.toks
            .get(self.pos)
            .map_or((self.end, 1), |t| (t.1, t.2))
    }
    fn expected(&self, what: &str) -> ExprError {
        let (at, len) = self.at();
        let found = self.peek().map_or("the end".to_string(), describe);
        ExprError::new(at, len, format!("expected {what}, found {found}"))
    }

    fn sum(&mut self) -> Result<Node, ExprError> {
        let mut left = self.product()?;
        while let Some(Tok::Op(c @ ('+' | '-'))) = self.peek() {
            let c = *c;
            self.pos += 1;
            let right = self.product()?;
            left = Node::Bin(c, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn product(&mut self) -> Result<Node, ExprError> {
        let mut left = self.unary()?;
        while let Some(Tok::Op(c @ ('*' | '/'))) = self.peek() {
            let c = *c;
            self.pos += 1;
            let right = self.unary()?;
            left = Node::Bin(c, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        match self.peek() {
            Some(Tok::Op('-')) => {
                self.pos += 1;
                Ok(Node::Neg(Box::new(self.unary()?)))
            }
            Some(Tok::Op('+')) => {
                self.pos += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.atom()?;
        if let Some(Tok::Op('^')) = self.peek() {
            self.pos += 1;
            // Right-associative, and the exponent may carry a sign: 2^-1.
            let exp = self.unary()?;
            return Ok(Node::Bin('^', Box::new(base), Box::new(exp)));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Node, ExprError> {
        let Some((tok, at, len)) = self.toks.get(self.pos).cloned() else {
            return Err(self.expected("a number, a name or `(`"));
        };
        match tok {
            Tok::Num(v) => {
                self.pos += 1;
                Ok(Node::Num(v))
            }
            Tok::Open => {
                self.pos += 1;
                let inner = self.sum()?;
                match self.peek() {
                    Some(Tok::Close) => {
                        self.pos += 1;
                        Ok(inner)
                    }
                    _ => Err(self
                        .expected("`)`")
                        .hint(format!("the `(` at character {} is not closed", at + 1))),
                }
            }
            Tok::Name(name) => {
                self.pos += 1;
                if let Some(Tok::Open) = self.peek() {
                    let Some(n) = arity(&name) else {
                        return Err(
                            ExprError::new(at, len, format!("`{name}` is not a function"))
                                .hint("multiply with *, e.g. x*(y + 1)"),
                        );
                    };
                    self.pos += 1;
                    let mut args = vec![self.sum()?];
                    while let Some(Tok::Comma) = self.peek() {
                        self.pos += 1;
                        args.push(self.sum()?);
                    }
                    match self.peek() {
                        Some(Tok::Close) => self.pos += 1,
                        _ => return Err(self.expected("`,` or `)`")),
                    }
                    if args.len() != n {
                        return Err(ExprError::new(
                            at,
                            len,
                            format!(
                                "`{name}` takes {}, found {}",
                                crate::text::plural(n, "argument", "arguments"),
                                args.len()
                            ),
                        ));
                    }
                    Ok(Node::Call(name, args))
                } else if arity(&name).is_some() {
                    Err(ExprError::new(at, len, format!("`{name}` is a function"))
                        .hint(format!("call it: {name}(x)")))
                } else {
                    Ok(Node::Name(name, at))
                }
            }
            other => Err(ExprError::new(
                at,
                len,
                format!(
                    "expected a number, a name or `(`, found {}",
                    describe(&other)
                ),
            )),
        }
    }
}

/// Parses `text` (syntax and arity only; names are checked by
/// [`check_names`]).
pub fn parse(text: &str) -> Result<Node, ExprError> {
    let toks = lex(text)?;
    if toks.is_empty() {
        return Err(ExprError::new(0, 1, "the expression is empty"));
    }
    let mut p = Parser {
        toks: &toks,
        pos: 0,
        end: text.len(),
    };
    let node = p.sum()?;
    if p.pos < toks.len() {
        let (tok, at, len) = &toks[p.pos];
        let e = ExprError::new(*at, *len, format!("unexpected {}", describe(tok)));
        return Err(match tok {
            Tok::Close => e.hint("this `)` has no `(`"),
            Tok::Name(_) | Tok::Num(_) | Tok::Open => e.hint("an operator is missing before it"),
            Tok::Comma => e.hint("only atan2, min and max take two arguments"),
            Tok::Op(_) => e,
        });
    }
    Ok(node)
}

/// Each name the expression uses that `known` does not accept, reported at
/// the first one.
pub fn check_names(node: &Node, known: &dyn Fn(&str) -> bool) -> Result<(), ExprError> {
    match node {
        Node::Num(_) => Ok(()),
        Node::Name(n, at) => {
            if known(n) {
                Ok(())
            } else {
                let mut e = ExprError::new(*at, n.len(), format!("unknown name `{n}`"));
                e.unknown = Some(n.clone());
                Err(e)
            }
        }
        Node::Neg(a) => check_names(a, known),
        Node::Bin(_, a, b) => {
            check_names(a, known)?;
            check_names(b, known)
        }
        Node::Call(_, args) => args.iter().try_for_each(|a| check_names(a, known)),
    }
}

/// Every name the expression uses, in order of first use.
pub fn names(node: &Node, out: &mut Vec<String>) {
    match node {
        Node::Num(_) => {}
        Node::Name(n, _) => {
            if !out.contains(n) {
                out.push(n.clone());
            }
        }
        Node::Neg(a) => names(a, out),
        Node::Bin(_, a, b) => {
            names(a, out);
            names(b, out);
        }
        Node::Call(_, args) => args.iter().for_each(|a| names(a, out)),
    }
}

/// What a name stands for in the canonical text.
pub enum Subst<'a> {
    /// Kept as a variable of the compiled expression.
    Var,
    /// A named constant, written in as its value.
    Value(f64),
    /// An observable, written in as its own canonical text.
    Text(&'a str),
}

/// The canonical text `exmex` compiles: every operation parenthesised,
/// variables in braces, constants written in, observables expanded.
pub fn canonical<'a>(node: &Node, subst: &dyn Fn(&str) -> Subst<'a>) -> String {
    let mut s = String::new();
    emit(node, subst, &mut s);
    s
}

fn number(v: f64, out: &mut String) {
    // `{:e}` is the shortest round-trip spelling with an exponent, which
    // the literal matcher of `compile` reads back exactly.
    if v < 0.0 || (v == 0.0 && v.is_sign_negative()) {
        let _ = write!(out, "(-{:e})", -v);
    } else {
        let _ = write!(out, "{v:e}");
    }
}

fn emit<'a>(node: &Node, subst: &dyn Fn(&str) -> Subst<'a>, out: &mut String) {
    match node {
        Node::Num(v) => number(*v, out),
        Node::Name(n, _) => match n.as_str() {
            "pi" => number(std::f64::consts::PI, out),
            "e" => number(std::f64::consts::E, out),
            _ => match subst(n) {
                Subst::Var => {
                    let _ = write!(out, "{{{n}}}");
                }
                Subst::Value(v) => number(v, out),
                Subst::Text(t) => {
                    let _ = write!(out, "({t})");
                }
            },
        },
        Node::Neg(a) => {
            out.push_str("(-(");
            emit(a, subst, out);
            out.push_str("))");
        }
        Node::Bin(op, a, b) => {
            out.push_str("((");
            emit(a, subst, out);
            let _ = write!(out, "){op}(");
            emit(b, subst, out);
            out.push_str("))");
        }
        Node::Call(f, args) => {
            let _ = write!(out, "{f}(");
            for (k, a) in args.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                out.push('(');
                emit(a, subst, out);
                out.push(')');
            }
            out.push(')');
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> ExprError {
        parse(text).unwrap_err()
    }

    #[test]
    fn syntax_errors_point_at_the_character() {
        let e = err("omega +* 2");
        assert_eq!(
            (e.at, e.message.as_str()),
            (7, "expected a number, a name or `(`, found `*`")
        );
        let e = err("sin(theta");
        assert_eq!(e.at, 9, "{e:?}");
        let e = err("2 theta");
        assert_eq!(e.at, 2);
        assert_eq!(e.hint.as_deref(), Some("an operator is missing before it"));
        let e = err("2theta");
        assert_eq!(e.at, 1);
        let e = err("atan2(y)");
        assert_eq!(
            (e.at, e.message.as_str()),
            (0, "`atan2` takes 2 arguments, found 1")
        );
        let e = err("x + sin");
        assert_eq!((e.at, e.len), (4, 3));
        let e = err("1e+");
        assert_eq!(e.at, 0);
        let e = err("x − 1");
        assert_eq!(e.at, 2);
        assert!(e.hint.unwrap().contains("minus"));
        assert_eq!(err("  ").message, "the expression is empty");
        let e = err("theta(2)");
        assert_eq!(e.message, "`theta` is not a function");
    }

    #[test]
    fn unknown_names_are_reported_at_the_first() {
        let node = parse("omega + 2*thta").unwrap();
        let e = check_names(&node, &|n| n == "omega").unwrap_err();
        assert_eq!((e.at, e.unknown.as_deref()), (10, Some("thta")));
    }

    #[test]
    fn canonical_form_follows_written_mathematics() {
        let c = |s: &str| canonical(&parse(s).unwrap(), &|_| Subst::Var);
        assert_eq!(c("-x^2"), "(-((({x})^(2e0))))");
        assert_eq!(c("a^b^c"), "(({a})^((({b})^({c}))))");
        assert_eq!(c("1.5e-3"), "1.5e-3");
        assert_eq!(c("atan2(y, x)"), "atan2(({y}), ({x}))");
    }
}
