//! Formula answers, checked as WeBWorK and STACK check them: a learner's
//! typed formula is right when it takes the expected formula's value at
//! random points of the domain the deck declares for each variable.
//!
//! Both formulas are read by the deck's one expression parser in its
//! formula form ([`super::expr::parse_formula`]: juxtaposition multiplies,
//! `^` is a power) and run by the one compiled program
//! ([`super::compile`]), so there is no second evaluator. A name is its
//! spelling without underscores (`I_2` and `I2` are one variable,
//! `omega_2` and `omega2` another), and `w` stands for `omega` where the
//! key has no `w` (`w2` for `omega2`: the letter a keyboard has).
//!
//! The comparison draws points from a fixed seed (a verdict never changes
//! between runs or machines), resamples a point where either side is not
//! finite, within a bounded number of draws, and compares [`POINTS`]
//! points (never fewer than [`MIN_POINTS`]) with relative tolerance
//! [`REL_TOL`]. A wrong answer is told the common slip it makes, when it
//! makes one: the sign, a constant factor, the reciprocal, a variable
//! missing or one the problem does not have.
//!
//! The typed answer is untrusted: at most [`MAX_ANSWER`] bytes, and the
//! parser bounds its nesting, depth and size, so no string can panic,
//! hang or exhaust memory here.

use super::compile::{Program, formula_program};
use super::expr::{self, ExprError, Node};

/// The longest typed answer read (bytes).
pub const MAX_ANSWER: usize = 1000;
/// Points compared when the domain gives them.
pub const POINTS: usize = 12;
/// Fewest points a verdict rests on.
pub const MIN_POINTS: usize = 8;
/// Most points drawn while looking for [`POINTS`] where both sides are
/// finite.
pub const MAX_DRAWS: usize = 400;
/// Two values agree when they differ by at most this times the larger.
pub const REL_TOL: f64 = 1e-9;
/// Values this small against the largest value seen are zero (what is left
/// of a cancellation, `x - x` evaluated as 1e-17).
const ZERO_REL: f64 = 1e-12;
/// The seed of every comparison's points.
const SEED: u64 = 0x5eed_f0c1_a5c0_ffee;

/// One variable of a formula answer and the interval its values are drawn
/// from (`I1 = [1, 3]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    /// The name as the deck writes it.
    pub name: String,
    pub lo: f64,
    pub hi: f64,
}

/// The answer key of a formula card or prompt: the expected formula as the
/// deck writes it, and the domain of each of its variables.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    pub expected: String,
    pub vars: Vec<Domain>,
}

/// A name as the comparison knows it: without underscores (`I_2` is
/// `I2`); a name of underscores only stays as written.
pub fn canonical(name: &str) -> String {
    let s: String = name.chars().filter(|&c| c != '_').collect();
    if s.is_empty() { name.to_string() } else { s }
}

/// What is wrong with a key, found by [`check`]; each is placed by the
/// deck at the expected formula or at one variable (an index of
/// `Key::vars`).
#[derive(Debug, Clone, PartialEq)]
pub enum KeyProblem {
    /// The expected formula does not read, or names something that is not
    /// a variable of `vars` (then `unknown` is set): placed inside it.
    Expected(ExprError),
    /// A variable the expected formula does not use.
    Unused(usize),
    /// A range that is not two finite numbers, low below high.
    Range(usize),
    /// A variable that is another one's name (`I_1` beside `I1`).
    Twice(usize),
    /// `pi` or `e`: the constants.
    Constant(usize),
    /// The expected formula is finite at too few points of the domain
    /// (found, drawn).
    Undefined { found: usize, drawn: usize },
}

/// The common slip a wrong formula makes.
#[derive(Debug, Clone, PartialEq)]
pub enum Slip {
    /// The answer is −expected.
    Sign,
    /// The answer is a constant times expected (the constant, ≠ 1).
    Factor(f64),
    /// The answer is 1/expected.
    Reciprocal,
    /// Variables of the problem the answer leaves out (the deck's
    /// spelling).
    Missing(Vec<String>),
    /// Names in the answer that are no variable of the problem (the
    /// learner's spelling).
    Extra(Vec<String>),
    /// The answer is not finite over most of the domain.
    Undefined,
}

/// The verdict on a typed formula.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Equal to the expected formula at every point compared.
    Right,
    /// Not equal; with the slip it makes, when it makes a known one.
    Wrong(Option<Slip>),
    /// The answer does not read as a formula: where and why.
    Unreadable(ExprError),
    /// The key cannot decide (its formula does not read, or is not
    /// finite at enough points): a deck error `check` reports.
    Undecided(String),
}

impl Verdict {
    pub fn is_right(&self) -> bool {
        matches!(self, Verdict::Right)
    }
}

/// A formula read against a key's variables: the tree with each name
/// resolved, the names it uses (indices of the key's variables) and those
/// that are none of them (spelling, offset, length).
struct Read {
    node: Node,
    uses: Vec<usize>,
    unknown: Vec<(String, usize, usize)>,
}

/// The index of the variable `name` means among `canon` (the variables'
/// canonical names), with `w` for `omega` where no variable is `w…`.
fn resolve(name: &str, canon: &[String]) -> Option<usize> {
    let c = canonical(name);
    if let Some(k) = canon.iter().position(|v| *v == c) {
        return Some(k);
    }
    let rest = c.strip_prefix('w')?;
    let omega = format!("omega{rest}");
    canon.iter().position(|v| *v == omega)
}

/// Each name of `node` resolved to the variable's canonical name; what
/// cannot be resolved (and is not `pi` or `e`) is listed. Recursion is
/// bounded by the parser's [`expr::MAX_DEPTH`].
fn rename(node: &mut Node, canon: &[String], read: &mut Read) {
    match node {
        Node::Num(_) => {}
        Node::Name(n, at) => {
            if n == "pi" || n == "e" {
                return;
            }
            match resolve(n, canon) {
                Some(k) => {
                    if !read.uses.contains(&k) {
                        read.uses.push(k);
                    }
                    *n = canon[k].clone();
                }
                None => {
                    if !read.unknown.iter().any(|(u, _, _)| u == n) {
                        read.unknown.push((n.clone(), *at, n.len()));
                    }
                }
            }
        }
        Node::Neg(a) => rename(a, canon, read),
        Node::Bin(_, a, b) => {
            rename(a, canon, read);
            rename(b, canon, read);
        }
        Node::Call(_, args) => args.iter_mut().for_each(|a| rename(a, canon, read)),
    }
}

fn read(text: &str, canon: &[String]) -> Result<Read, ExprError> {
    let node = expr::parse_formula(text)?;
    let mut out = Read {
        node: Node::Num(0.0),
        uses: Vec::new(),
        unknown: Vec::new(),
    };
    let mut node = node;
    rename(&mut node, canon, &mut out);
    out.node = node;
    Ok(out)
}

/// A key's variables made ready to draw: canonical names, the state
/// vector's order (every variable but `t`, which is the time argument)
/// and the domains.
struct Space {
    canon: Vec<String>,
    /// Index into the state vector of each variable; `None` for `t`.
    slot: Vec<Option<usize>>,
    state: Vec<String>,
    domains: Vec<(f64, f64)>,
}

impl Space {
    fn of(key: &Key) -> Space {
        let canon: Vec<String> = key.vars.iter().map(|v| canonical(&v.name)).collect();
        let mut state = Vec::new();
        let slot = canon
            .iter()
            .map(|c| {
                (c != "t").then(|| {
                    state.push(c.clone());
                    state.len() - 1
                })
            })
            .collect();
        Space {
            canon,
            slot,
            state,
            domains: key.vars.iter().map(|v| (v.lo, v.hi)).collect(),
        }
    }

    fn compile(&self, node: &Node) -> Result<Program, String> {
        formula_program(node, &self.state).map_err(|e| e.message)
    }
}

/// SplitMix64: a fixed, portable stream of draws (a verdict is the same on
/// every machine).
struct Draws(u64);

impl Draws {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The values of the programs at the points of the domain where every one
/// is finite (at most [`POINTS`], from at most [`MAX_DRAWS`] draws), and
/// how many draws gave a finite value of the first.
fn sample(space: &Space, progs: &[&Program]) -> (Vec<Vec<f64>>, usize) {
    let mut draws = Draws(SEED);
    let mut y = vec![0.0; space.state.len()];
    let mut rows = Vec::new();
    let mut first_finite = 0;
    for _ in 0..MAX_DRAWS {
        let mut t = 0.0;
        for (k, &(lo, hi)) in space.domains.iter().enumerate() {
            let v = lo + (hi - lo) * draws.next();
            match space.slot[k] {
                Some(i) => y[i] = v,
                None => t = v,
            }
        }
        let row: Vec<f64> = progs.iter().map(|p| p.eval_one(0, t, &y)).collect();
        if row.first().is_some_and(|v| v.is_finite()) {
            first_finite += 1;
        }
        if row.iter().all(|v| v.is_finite()) {
            rows.push(row);
            if rows.len() == POINTS {
                break;
            }
        }
    }
    (rows, first_finite)
}

/// Whether `a` and `b` agree: within [`REL_TOL`] of the larger, or both
/// below `zero`.
fn close(a: f64, b: f64, zero: f64) -> bool {
    let big = a.abs().max(b.abs());
    (a - b).abs() <= REL_TOL * big || big <= zero
}

/// Every problem of `key`: the expected formula read against its
/// variables, each variable used and its range sound, and the formula
/// finite at enough points of the domain.
pub fn check(key: &Key) -> Vec<KeyProblem> {
    let mut out = Vec::new();
    let space = Space::of(key);
    for (k, v) in key.vars.iter().enumerate() {
        if !(v.lo.is_finite() && v.hi.is_finite() && v.lo < v.hi) {
            out.push(KeyProblem::Range(k));
        }
        let c = &space.canon[k];
        if c == "pi" || c == "e" {
            out.push(KeyProblem::Constant(k));
        } else if space.canon[..k].contains(c) {
            out.push(KeyProblem::Twice(k));
        }
    }
    let read = match read(&key.expected, &space.canon) {
        Ok(r) => r,
        Err(e) => {
            out.push(KeyProblem::Expected(e));
            return out;
        }
    };
    if let Some((name, at, len)) = read.unknown.first() {
        out.push(KeyProblem::Expected(ExprError {
            at: *at,
            len: *len,
            message: format!("`{name}` is not a variable of `vars`"),
            hint: None,
            unknown: Some(name.clone()),
        }));
    }
    for k in 0..key.vars.len() {
        if !read.uses.contains(&k) && !space.canon[..k].contains(&space.canon[k]) {
            out.push(KeyProblem::Unused(k));
        }
    }
    if !out.is_empty() {
        return out;
    }
    let prog = match space.compile(&read.node) {
        Ok(p) => p,
        Err(message) => {
            out.push(KeyProblem::Expected(ExprError {
                at: 0,
                len: key.expected.len().max(1),
                message,
                hint: None,
                unknown: None,
            }));
            return out;
        }
    };
    let (rows, _) = sample(&space, &[&prog]);
    if rows.len() < MIN_POINTS {
        out.push(KeyProblem::Undefined {
            found: rows.len(),
            drawn: MAX_DRAWS,
        });
    }
    out
}

/// The verdict on `answer` (typed by a learner: untrusted) against `key`.
pub fn grade(key: &Key, answer: &str) -> Verdict {
    let space = Space::of(key);
    let expected = match read(&key.expected, &space.canon)
        .map_err(|e| e.message)
        .and_then(|r| {
            if let Some((n, _, _)) = r.unknown.first() {
                return Err(format!("`{n}` is not a variable of `vars`"));
            }
            Ok(r)
        })
        .and_then(|r| space.compile(&r.node).map(|p| (r, p)))
    {
        Ok(e) => e,
        Err(why) => return Verdict::Undecided(format!("the expected formula: {why}")),
    };
    if answer.len() > MAX_ANSWER {
        return Verdict::Unreadable(ExprError {
            at: 0,
            len: 1,
            message: format!(
                "the formula is {} bytes long; an answer may be at most {MAX_ANSWER}",
                answer.len()
            ),
            hint: None,
            unknown: None,
        });
    }
    let given = match read(answer, &space.canon) {
        Ok(r) => r,
        // Where, in characters of what was typed (it may hold ω or I₂),
        // as the error's "at character" says.
        Err(mut e) => {
            let chars = |bytes: usize| answer.get(..bytes).map_or(bytes, |s| s.chars().count());
            let end = chars(e.at + e.len);
            e.at = chars(e.at);
            e.len = end.saturating_sub(e.at).max(1);
            return Verdict::Unreadable(e);
        }
    };
    if !given.unknown.is_empty() {
        let names = given.unknown.into_iter().map(|(n, _, _)| n).collect();
        return Verdict::Wrong(Some(Slip::Extra(names)));
    }
    let prog = match space.compile(&given.node) {
        Ok(p) => p,
        Err(message) => {
            return Verdict::Unreadable(ExprError {
                at: 0,
                len: answer.len().max(1),
                message,
                hint: None,
                unknown: None,
            });
        }
    };
    let (rows, defined) = sample(&space, &[&expected.1, &prog]);
    if defined < MIN_POINTS {
        return Verdict::Undecided(format!(
            "the expected formula is finite at {defined} of {MAX_DRAWS} points of the domain; a verdict needs {MIN_POINTS}"
        ));
    }
    if rows.len() < MIN_POINTS {
        return Verdict::Wrong(Some(Slip::Undefined));
    }
    let pairs: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
    let zero = ZERO_REL
        * pairs
            .iter()
            .map(|(e, a)| e.abs().max(a.abs()))
            .fold(0.0, f64::max);
    let all = |f: &dyn Fn(f64, f64) -> bool| pairs.iter().all(|&(e, a)| f(e, a));
    if all(&|e, a| close(a, e, zero)) {
        return Verdict::Right;
    }
    let missing: Vec<String> = expected
        .0
        .uses
        .iter()
        .filter(|k| !given.uses.contains(k))
        .map(|&k| key.vars[k].name.clone())
        .collect();
    let slip = if all(&|e, a| close(a, -e, zero)) {
        Some(Slip::Sign)
    } else if let Some(c) = factor(&pairs, zero) {
        Some(Slip::Factor(c))
    } else if all(&|e, a| e != 0.0 && close(a, 1.0 / e, 0.0)) {
        Some(Slip::Reciprocal)
    } else if !missing.is_empty() {
        Some(Slip::Missing(missing))
    } else {
        None
    };
    Verdict::Wrong(slip)
}

/// The constant `c` ≠ 1 (and ≠ 0) with answer = c · expected at every
/// point, if there is one.
fn factor(pairs: &[(f64, f64)], zero: f64) -> Option<f64> {
    let &(e0, a0) = pairs.iter().find(|(e, _)| e.abs() > zero)?;
    let c = a0 / e0;
    let ok = c.is_finite()
        && c != 0.0
        && !close(c, 1.0, 0.0)
        && pairs.iter().all(|&(e, a)| close(a, c * e, zero));
    ok.then_some(c)
}

/// Whether `a` and `b` are the same function over `vars` (the relation
/// [`grade`] decides, with neither side the key): both read, neither
/// names another variable, and they agree at every point compared. For
/// tests of its symmetry and reflexivity.
pub fn equivalent(a: &str, b: &str, vars: &[Domain]) -> Option<bool> {
    let key = Key {
        expected: a.to_string(),
        vars: vars.to_vec(),
    };
    match grade(&key, b) {
        Verdict::Right => Some(true),
        Verdict::Wrong(_) => Some(false),
        Verdict::Unreadable(_) | Verdict::Undecided(_) => None,
    }
}

#[cfg(test)]
mod tests;

/// A formula written in the deck's expression language, as LaTeX for the
/// math renderer (`(I_3 - I_2)(I_2 - I_1) Omega^2 / (I_1 I_3)` →
/// `\left(I_{3} - I_{2}\right)…`), so a verdict shows the deck's answer as
/// the reader shows math: Greek names as letters, trailing digits as
/// subscripts, powers raised. `None` when it does not read.
pub fn latex(formula: &str) -> Option<String> {
    let node = expr::parse_formula(formula).ok()?;
    let mut out = String::new();
    tex(&node, &mut out);
    Some(out)
}

/// Binding strength of a node, for parentheses: sums 1, products 2,
/// unary minus 3, powers 4, atoms 5.
fn strength(n: &Node) -> u8 {
    match n {
        Node::Bin('+' | '-', ..) => 1,
        Node::Bin('*' | '/', ..) => 2,
        Node::Neg(_) => 3,
        Node::Bin(..) => 4,
        Node::Num(v) if *v < 0.0 => 3,
        _ => 5,
    }
}

fn tex_in(n: &Node, at_least: u8, out: &mut String) {
    if strength(n) < at_least {
        out.push('(');
        tex(n, out);
        out.push(')');
    } else {
        tex(n, out);
    }
}

fn tex(n: &Node, out: &mut String) {
    match n {
        Node::Num(v) => out.push_str(&flipcard_text::num::show(*v)),
        Node::Name(name, _) => out.push_str(&tex_name(name)),
        Node::Neg(a) => {
            out.push('-');
            tex_in(a, 3, out);
        }
        Node::Bin('+', a, b) => {
            tex(a, out);
            out.push_str(" + ");
            tex_in(b, 1, out);
        }
        Node::Bin('-', a, b) => {
            tex(a, out);
            out.push_str(" - ");
            tex_in(b, 2, out);
        }
        Node::Bin('*', a, b) => {
            tex_in(a, 2, out);
            // Side by side, as written by hand, unless two numbers meet.
            let numbers = matches!(**b, Node::Num(_))
                || matches!(**a, Node::Num(_)) && matches!(**b, Node::Neg(_));
            out.push_str(if numbers { " \\cdot " } else { " " });
            tex_in(b, 3, out);
        }
        Node::Bin('/', a, b) => {
            tex_in(a, 2, out);
            out.push_str(" / ");
            tex_in(b, 3, out);
        }
        Node::Bin(_, a, b) => {
            tex_in(a, 5, out);
            out.push_str("^{");
            tex(b, out);
            out.push('}');
        }
        Node::Call(f, args) if f == "sqrt" && args.len() == 1 => {
            out.push_str("\\sqrt{");
            tex(&args[0], out);
            out.push('}');
        }
        Node::Call(f, args) => {
            match f.as_str() {
                "sin" | "cos" | "tan" | "exp" | "ln" | "sinh" | "cosh" | "tanh" => {
                    out.push('\\');
                    out.push_str(f);
                }
                _ => {
                    out.push_str("\\mathrm{");
                    out.push_str(f);
                    out.push('}');
                }
            }
            out.push('(');
            for (k, a) in args.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                tex(a, out);
            }
            out.push(')');
        }
    }
}

/// `omega_2` and `omega2` as `\omega_{2}`, `I_2` as `I_{2}`, `Omega` as
/// `\Omega`, `pi` as `\pi`; any other name as written.
fn tex_name(name: &str) -> String {
    const GREEK: &[&str] = &[
        "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "kappa", "lambda",
        "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "phi", "chi", "psi", "omega", "Gamma",
        "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Phi", "Psi", "Omega",
    ];
    let (stem, digits) = match name.trim_end_matches(|c: char| c.is_ascii_digit()) {
        s if s.len() < name.len() && !s.is_empty() => (s.trim_end_matches('_'), &name[s.len()..]),
        _ => match name.split_once('_') {
            Some((s, sub)) if !s.is_empty() && !sub.is_empty() && !sub.contains('_') => (s, sub),
            _ => (name, ""),
        },
    };
    let stem = match GREEK.contains(&stem) {
        true => format!("\\{stem}"),
        false => stem.to_string(),
    };
    match digits {
        "" => stem,
        d => format!("{stem}_{{{d}}}"),
    }
}
