//! The expressions instructors write in a system scene: parsed and checked
//! here, with the byte offset of every problem inside the expression (a
//! deck error points at the character that is wrong), into the tree
//! [`super::compile`] turns into a program. The grammar is written
//! mathematics: `-x^2` is −(x²), `a^b^c` is a^(b^c), and numbers may carry
//! an exponent (`1e-3`).
//!
//! A deck is input we did not write, so the parser bounds its work: at most
//! [`MAX_NESTING`] parentheses and calls open at once (checked before it
//! recurses into one more, so 8000 parentheses are an error at the one too
//! many, not a stack overflow), a tree at most [`MAX_DEPTH`] deep, and
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

/// Deepest nesting of an expression's tree: operators and calls inside
/// one another (a sum of k terms nests k − 1 deep, `-(-(x))` 3). Every
/// walk over an expression recurses once per level, so this bounds the
/// stack they use whatever a deck holds; written mathematics stays far
/// below it.
pub const MAX_DEPTH: usize = 200;

/// Most parentheses and calls open at once: the parser recurses into each
/// (sums, products, signs and powers it reads without recursion).
pub(crate) const MAX_NESTING: usize = 64;

/// Most operations (numbers, names, operators, calls) in one expression.
pub(crate) const MAX_NODES: usize = 10_000;

/// The function `name` is most likely a misspelling of: the nearest by
/// edit distance, at most one edit for names up to five characters and two
/// beyond (a one- or two-letter name before `(` is a product, not a typo).
pub(crate) fn misspelt_function(name: &str) -> Option<&'static str> {
    let len = name.chars().count();
    if len < 3 {
        return None;
    }
    let limit = if len <= 5 { 1 } else { 2 };
    FUNCTIONS
        .iter()
        .map(|(f, _)| (strsim::damerau_levenshtein(&name.to_lowercase(), f), *f))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, f)| f)
}

/// The arity of a function name, if it is one.
pub(crate) fn arity(name: &str) -> Option<usize> {
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

/// The name a learner means by a Greek letter typed as itself (`ω` for
/// `omega`, `Ω` for `Omega`, `π` for `pi`): formulas typed as answers only.
fn greek_name(c: char) -> Option<&'static str> {
    const GREEK: &[(char, &str)] = &[
        ('α', "alpha"),
        ('β', "beta"),
        ('γ', "gamma"),
        ('δ', "delta"),
        ('ε', "epsilon"),
        ('ζ', "zeta"),
        ('η', "eta"),
        ('θ', "theta"),
        ('κ', "kappa"),
        ('λ', "lambda"),
        ('μ', "mu"),
        ('ν', "nu"),
        ('ξ', "xi"),
        ('π', "pi"),
        ('ρ', "rho"),
        ('σ', "sigma"),
        ('τ', "tau"),
        ('φ', "phi"),
        ('χ', "chi"),
        ('ψ', "psi"),
        ('ω', "omega"),
        ('Γ', "Gamma"),
        ('Δ', "Delta"),
        ('Θ', "Theta"),
        ('Λ', "Lambda"),
        ('Ξ', "Xi"),
        ('Π', "Pi"),
        ('Σ', "Sigma"),
        ('Φ', "Phi"),
        ('Ψ', "Psi"),
        ('Ω', "Omega"),
    ];
    GREEK.iter().find(|(g, _)| *g == c).map(|(_, n)| *n)
}

/// The digit a subscript digit (₀ … ₉) stands for.
fn subscript_digit(c: char) -> Option<char> {
    let k = (c as u32).checked_sub('₀' as u32)?;
    (k < 10).then(|| char::from_digit(k, 10)).flatten()
}

fn lex(text: &str, implicit: bool) -> Result<Vec<(Tok, usize, usize)>, ExprError> {
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
                } else if implicit {
                    // `2e` is 2 times e, `2exp(x)` 2 times exp(x).
                } else {
                    return Err(ExprError::new(
                        start,
                        j - start,
                        format!("`{}` is not a number", &text[start..j]),
                    )
                    .hint("an exponent needs digits, as in 1e-3"));
                }
            }
            if !implicit && i < b.len() && (b[i].is_ascii_alphabetic() || b[i] == b'_') {
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
        let greek = match implicit {
            true => text[i..].chars().next().and_then(greek_name),
            false => None,
        };
        if c.is_ascii_alphabetic() || c == b'_' || greek.is_some() {
            let mut name = String::new();
            if let Some(g) = greek {
                name.push_str(g);
                i += text[i..].chars().next().map_or(1, char::len_utf8);
            }
            loop {
                if i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                    name.push(b[i] as char);
                    i += 1;
                    continue;
                }
                // A typed answer may write I₂ for I2.
                match text[i..].chars().next().and_then(subscript_digit) {
                    Some(d) if implicit => {
                        name.push(d);
                        i += '₀'.len_utf8();
                    }
                    _ => break,
                }
            }
            out.push((Tok::Name(name), start, i - start));
            continue;
        }
        // A typed answer may use the signs a keyboard with math symbols
        // gives: × and · multiply, − subtracts.
        if implicit && let Some(ch) = text[i..].chars().next() {
            let op = match ch {
                '×' | '·' => Some('*'),
                '−' => Some('-'),
                _ => None,
            };
            if let Some(op) = op {
                out.push((Tok::Op(op), start, ch.len_utf8()));
                i += ch.len_utf8();
                continue;
            }
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
    /// Parentheses and calls open around the token being parsed (bounded
    /// by [`MAX_NESTING`] before the parser recurses into one more).
    level: usize,
    /// Nodes built so far (bounded by [`MAX_NODES`]).
    nodes: usize,
    /// Juxtaposition multiplies (`2x`, `a b`, `x(y + 1)`), as in a
    /// formula answer ([`parse_formula`]).
    implicit: bool,
}

/// A node with the depth of its tree (a leaf is 1).
type Built = (Node, usize);

/// One element of a power chain: the positions of the minus signs before
/// it, the element, and the position of the `^` after it.
type Link = (Vec<(usize, usize)>, Built, (usize, usize));

/// The parser's error: boxed, so that what each level of a nested
/// expression keeps on the stack stays small.
type PResult<T> = Result<T, Box<ExprError>>;

fn precedence(op: char) -> u8 {
    if op == '+' || op == '-' { 1 } else { 2 }
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
    fn expected(&self, what: &str) -> Box<ExprError> {
        let (at, len) = self.at();
        let found = self.peek().map_or("the end".to_string(), describe);
        Box::new(ExprError::new(
            at,
            len,
            format!("expected {what}, found {found}"),
        ))
    }

    /// Counts a new node of depth `depth` made at `at`.
    fn node(&mut self, node: Node, depth: usize, at: (usize, usize)) -> PResult<Built> {
        self.nodes += 1;
        if depth > MAX_DEPTH {
            return Err(Box::new(too_deep(at.0, at.1)));
        }
        if self.nodes > MAX_NODES {
            return Err(Box::new(
                ExprError::new(
                    at.0,
                    at.1,
                    format!(
                        "the expression has more than {MAX_NODES} numbers, names and operations"
                    ),
                )
                .hint("split it into observables"),
            ));
        }
        Ok((node, depth))
    }

    /// A sum of products: `operand (op operand)*` with `*` and `/` before
    /// `+` and `-`, each left to right. Operators wait on a stack of their
    /// own, so a long sum costs no recursion.
    fn expression(&mut self) -> PResult<Built> {
        let mut operands: Vec<Built> = vec![self.operand()?];
        let mut ops: Vec<(char, (usize, usize))> = Vec::new();
        loop {
            let next = match self.peek() {
                Some(Tok::Op(c @ ('+' | '-' | '*' | '/'))) => Some(*c),
                // Juxtaposition: a product, as tight as `*`.
                Some(Tok::Num(_) | Tok::Name(_) | Tok::Open) if self.implicit => Some(' '),
                _ => None,
            };
            // Apply what binds at least as tightly as the next operator
            // (all of it at the end).
            while let Some(&(top, at)) = ops.last() {
                if next.is_some_and(|c| precedence(top) < precedence(c)) {
                    break;
                }
                ops.pop();
                let (b, db) = operands.pop().unwrap_or((Node::Num(0.0), 1));
                let (a, da) = operands.pop().unwrap_or((Node::Num(0.0), 1));
                let built =
                    self.node(Node::Bin(top, Box::new(a), Box::new(b)), 1 + da.max(db), at)?;
                operands.push(built);
            }
            let Some(c) = next else {
                break;
            };
            ops.push((if c == ' ' { '*' } else { c }, self.at()));
            if c != ' ' {
                self.pos += 1;
            }
            operands.push(self.operand()?);
        }
        Ok(operands.pop().unwrap_or((Node::Num(0.0), 1)))
    }

    /// Signs, then a power chain `primary (^ signs primary)*`, read as
    /// written mathematics: `-x^2` is −(x²), `a^b^c` is a^(b^c), `2^-1`
    /// takes its sign into the exponent. No recursion: the chain is
    /// collected, then built from the right.
    fn operand(&mut self) -> PResult<Built> {
        // (the signs before each element: their positions, minus only),
        // each element, and the `^` before it.
        let mut links: Vec<Link> = Vec::new();
        let mut powers = 0usize;
        loop {
            let mut signs = Vec::new();
            let mut count = 0usize;
            while let Some(Tok::Op(c @ ('-' | '+'))) = self.peek() {
                count += 1;
                if count > MAX_DEPTH {
                    let (at, len) = self.at();
                    return Err(Box::new(too_deep(at, len)));
                }
                if *c == '-' {
                    signs.push(self.at());
                }
                self.pos += 1;
            }
            let element = self.primary()?;
            let caret = self.at();
            links.push((signs, element, caret));
            if let Some(Tok::Op('^')) = self.peek() {
                powers += 1;
                if powers > MAX_DEPTH {
                    return Err(Box::new(too_deep(caret.0, caret.1)));
                }
                self.pos += 1;
                continue;
            }
            break;
        }
        // From the right: e = element^e, then that element's signs.
        let mut built: Option<Built> = None;
        while let Some((signs, (node, depth), caret)) = links.pop() {
            let (mut node, mut depth) = match built.take() {
                None => (node, depth),
                Some((e, de)) => self.node(
                    Node::Bin('^', Box::new(node), Box::new(e)),
                    1 + depth.max(de),
                    caret,
                )?,
            };
            for at in signs.into_iter().rev() {
                (node, depth) = self.node(Node::Neg(Box::new(node)), depth + 1, at)?;
            }
            built = Some((node, depth));
        }
        Ok(built.unwrap_or((Node::Num(0.0), 1)))
    }

    /// Opens one more parenthesis or call at the current token, refusing
    /// one beyond [`MAX_NESTING`] before recursing.
    fn enter(&mut self) -> PResult<()> {
        self.level += 1;
        if self.level > MAX_NESTING {
            let (at, len) = self.at();
            return Err(Box::new(
                ExprError::new(
                    at,
                    len,
                    format!("parentheses and calls nest more than {MAX_NESTING} deep"),
                )
                .hint("no formula needs that many: split it into observables"),
            ));
        }
        Ok(())
    }

    /// A number, a name, a call or a parenthesised expression.
    fn primary(&mut self) -> PResult<Built> {
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
                let inner = self.expression()?;
                self.level -= 1;
                match self.peek() {
                    Some(Tok::Close) => {
                        self.pos += 1;
                        Ok(inner)
                    }
                    _ => Err(Box::new(
                        self.expected("`)`")
                            .hint(format!("the `(` at character {} is not closed", at + 1)),
                    )),
                }
            }
            Tok::Name(name) => {
                self.pos += 1;
                let product = self.implicit && arity(&name).is_none();
                if let Some(Tok::Open) = self.peek().filter(|_| !product) {
                    let Some(n) = arity(&name) else {
                        let hint = match misspelt_function(&name) {
                            Some(f) => format!("did you mean `{f}`? (or multiply with *)"),
                            None => "multiply with *, e.g. x*(y + 1)".to_string(),
                        };
                        return Err(Box::new(
                            ExprError::new(at, len, format!("`{name}` is not a function"))
                                .hint(hint),
                        ));
                    };
                    self.enter()?;
                    self.pos += 1;
                    let (first, mut depth) = self.expression()?;
                    let mut args = vec![first];
                    while let Some(Tok::Comma) = self.peek() {
                        self.pos += 1;
                        let (arg, d) = self.expression()?;
                        args.push(arg);
                        depth = depth.max(d);
                    }
                    self.level -= 1;
                    match self.peek() {
                        Some(Tok::Close) => self.pos += 1,
                        _ => return Err(self.expected("`,` or `)`")),
                    }
                    if args.len() != n {
                        return Err(Box::new(ExprError::new(
                            at,
                            len,
                            format!(
                                "`{name}` takes {}, found {}",
                                flipcard_text::plural(n, "argument", "arguments"),
                                args.len()
                            ),
                        )));
                    }
                    self.node(Node::Call(name, args), 1 + depth, (at, len))
                } else if arity(&name).is_some() {
                    Err(Box::new(
                        ExprError::new(at, len, format!("`{name}` is a function"))
                            .hint(format!("call it: {name}(x)")),
                    ))
                } else {
                    self.node(Node::Name(name, at), 1, (at, len))
                }
            }
            other => Err(Box::new(ExprError::new(
                at,
                len,
                format!(
                    "expected a number, a name or `(`, found {}",
                    describe(&other)
                ),
            ))),
        }
    }
}

fn too_deep(at: usize, len: usize) -> ExprError {
    ExprError::new(
        at,
        len,
        format!("the expression nests more than {MAX_DEPTH} levels deep"),
    )
    .hint("operators and calls inside one another each count a level (a sum of k terms, k − 1): split it into observables")
}

/// Parses `text` (syntax and arity only; names are checked by
/// [`check_names`]).
pub fn parse(text: &str) -> Result<Node, ExprError> {
    parse_with(text, false)
}

/// Parses a formula as a learner types it: [`parse`]'s grammar, where
/// juxtaposition also multiplies, as tightly as `*` and left to right
/// (`2x`, `(I_2 - I_3) omega_2 omega_3 / I_1`, `x(y + 1)`, `2 pi r`), so
/// `1/2x` is (1/2)·x. A name before `(` is a call only when it is a
/// function.
pub fn parse_formula(text: &str) -> Result<Node, ExprError> {
    parse_with(text, true)
}

fn parse_with(text: &str, implicit: bool) -> Result<Node, ExprError> {
    let toks = lex(text, implicit)?;
    if toks.is_empty() {
        return Err(ExprError::new(0, 1, "the expression is empty"));
    }
    let mut p = Parser {
        toks: &toks,
        pos: 0,
        end: text.len(),
        level: 0,
        nodes: 0,
        implicit,
    };
    let (node, _) = p.expression().map_err(|e| *e)?;
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
        assert!(e.hint.unwrap().contains("multiply with *"));
    }

    #[test]
    fn a_misspelt_function_gets_the_function_it_was_meant_to_be() {
        let e = err("-g/L*sinn(theta)");
        assert_eq!((e.at, e.len), (5, 4));
        assert_eq!(e.message, "`sinn` is not a function");
        assert_eq!(
            e.hint.as_deref(),
            Some("did you mean `sin`? (or multiply with *)")
        );
        for (typo, meant) in [
            ("cso", "cos"),
            ("sqr", "sqrt"),
            ("Exp", "exp"),
            ("sqtr", "sqrt"),
        ] {
            assert_eq!(misspelt_function(typo), Some(meant), "{typo}");
        }
        // Names too far from any function, or too short to be one, are
        // products: `k(x + 1)`, `omega(t)`.
        for name in ["k", "om", "omega", "theta", "mass"] {
            assert_eq!(misspelt_function(name), None, "{name}");
        }
    }

    #[test]
    fn unknown_names_are_reported_at_the_first() {
        let node = parse("omega + 2*thta").unwrap();
        let e = check_names(&node, &|n| n == "omega").unwrap_err();
        assert_eq!((e.at, e.unknown.as_deref()), (10, Some("thta")));
    }
}
