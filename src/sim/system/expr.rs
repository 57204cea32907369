//! The expressions instructors write in a system scene: parsed and checked
//! here, with the byte offset of every problem inside the expression (a
//! deck error points at the character that is wrong), into the tree
//! [`super::compile`] turns into a program. The grammar is written
//! mathematics: `-x^2` is −(x²), `a^b^c` is a^(b^c), and numbers may carry
//! an exponent (`1e-3`).
//!
//! A deck is input we did not write, so the parser bounds its work: at most
//! [`MAX_DEPTH`] levels of nesting (checked before it recurses, so 8000
//! parentheses are an error at the one too many, not a stack overflow) and
//! [`MAX_NODES`] numbers, names and operations per expression.

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

/// Deepest nesting of an expression: parentheses, operators and calls
/// inside one another (a sum of k terms nests k − 1 deep). Every walk over
/// an expression recurses once per level, so this bounds the stack they
/// use whatever a deck holds; written mathematics stays far below it.
pub const MAX_DEPTH: usize = 200;

/// Most operations (numbers, names, operators, calls) in one expression.
pub const MAX_NODES: usize = 10_000;

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
    /// Nesting of the rule being parsed (bounded by [`MAX_DEPTH`] before
    /// the parser recurses further).
    level: usize,
    /// Nodes built so far (bounded by [`MAX_NODES`]).
    nodes: usize,
}

/// A node with the depth of its tree (a leaf is 1).
type Built = (Node, usize);

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

    /// Enters one more level of nesting at the current token, refusing
    /// one beyond [`MAX_DEPTH`] before recursing.
    fn enter(&mut self) -> Result<(), ExprError> {
        self.level += 1;
        if self.level > MAX_DEPTH {
            let (at, len) = self.at();
            return Err(too_deep(at, len));
        }
        Ok(())
    }

    fn leave(&mut self) {
        self.level -= 1;
    }

    /// Counts a new node of depth `depth` made at `at`.
    fn node(&mut self, node: Node, depth: usize, at: (usize, usize)) -> Result<Built, ExprError> {
        self.nodes += 1;
        if depth > MAX_DEPTH {
            return Err(too_deep(at.0, at.1));
        }
        if self.nodes > MAX_NODES {
            return Err(ExprError::new(
                at.0,
                at.1,
                format!("the expression has more than {MAX_NODES} numbers, names and operations"),
            )
            .hint("split it into observables"));
        }
        Ok((node, depth))
    }

    fn sum(&mut self) -> Result<Built, ExprError> {
        let (mut left, mut depth) = self.product()?;
        while let Some(Tok::Op(c @ ('+' | '-'))) = self.peek() {
            let c = *c;
            let at = self.at();
            self.pos += 1;
            let (right, d) = self.product()?;
            (left, depth) = self.node(
                Node::Bin(c, Box::new(left), Box::new(right)),
                1 + depth.max(d),
                at,
            )?;
        }
        Ok((left, depth))
    }

    fn product(&mut self) -> Result<Built, ExprError> {
        let (mut left, mut depth) = self.unary()?;
        while let Some(Tok::Op(c @ ('*' | '/'))) = self.peek() {
            let c = *c;
            let at = self.at();
            self.pos += 1;
            let (right, d) = self.unary()?;
            (left, depth) = self.node(
                Node::Bin(c, Box::new(left), Box::new(right)),
                1 + depth.max(d),
                at,
            )?;
        }
        Ok((left, depth))
    }

    fn unary(&mut self) -> Result<Built, ExprError> {
        match self.peek() {
            Some(Tok::Op('-')) => {
                let at = self.at();
                self.enter()?;
                self.pos += 1;
                let (inner, d) = self.unary()?;
                self.leave();
                self.node(Node::Neg(Box::new(inner)), 1 + d, at)
            }
            Some(Tok::Op('+')) => {
                self.enter()?;
                self.pos += 1;
                let inner = self.unary()?;
                self.leave();
                Ok(inner)
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Built, ExprError> {
        let (base, db) = self.atom()?;
        if let Some(Tok::Op('^')) = self.peek() {
            let at = self.at();
            self.enter()?;
            self.pos += 1;
            // Right-associative, and the exponent may carry a sign: 2^-1.
            let (exp, de) = self.unary()?;
            self.leave();
            return self.node(
                Node::Bin('^', Box::new(base), Box::new(exp)),
                1 + db.max(de),
                at,
            );
        }
        Ok((base, db))
    }

    fn atom(&mut self) -> Result<Built, ExprError> {
        let Some((tok, at, len)) = self.toks.get(self.pos).cloned() else {
            return Err(self.expected("a number, a name or `(`"));
        };
        match tok {
            Tok::Num(v) => {
                self.pos += 1;
                self.node(Node::Num(v), 1, (at, len))
            }
            Tok::Open => {
                self.enter()?;
                self.pos += 1;
                let inner = self.sum()?;
                self.leave();
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
                    self.enter()?;
                    self.pos += 1;
                    let (first, mut depth) = self.sum()?;
                    let mut args = vec![first];
                    while let Some(Tok::Comma) = self.peek() {
                        self.pos += 1;
                        let (arg, d) = self.sum()?;
                        args.push(arg);
                        depth = depth.max(d);
                    }
                    self.leave();
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
                    self.node(Node::Call(name, args), 1 + depth, (at, len))
                } else if arity(&name).is_some() {
                    Err(ExprError::new(at, len, format!("`{name}` is a function"))
                        .hint(format!("call it: {name}(x)")))
                } else {
                    self.node(Node::Name(name, at), 1, (at, len))
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

fn too_deep(at: usize, len: usize) -> ExprError {
    ExprError::new(
        at,
        len,
        format!("the expression nests more than {MAX_DEPTH} levels deep"),
    )
    .hint("parentheses, operators and calls inside one another each count a level (a sum of k terms, k − 1): split it into observables")
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
        level: 0,
        nodes: 0,
    };
    let (node, _) = p.sum()?;
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
}
