//! The query language as Anki users type it: terms joined by spaces (all
//! must hold), `or`, `-` for not, parentheses, `"quoted text"`, `*` as a
//! wildcard, and the fields `deck:`, `tag:`, `state:`, `is:`, `due:`,
//! `rated:`, `prop:` and `flag:`. [`parse`] gives an [`Expr`]; an error is
//! one line naming the column of the query where it is.

use chrono::{DateTime, TimeDelta, Utc};

use super::{ItemRow, QueryError, STATES, parse_span};
use crate::deck::Deck;
use crate::sched::State;

/// Parentheses (and negated groups) nested deeper than this are refused:
/// the parser and every walk of an expression recurse once a level.
pub const MAX_DEPTH: usize = 32;

/// The longest query read, in characters.
pub const MAX_QUERY_CHARS: usize = 4096;

/// The most days `rated:N` looks back (a hundred years).
pub const MAX_RATED_DAYS: u32 = 36_500;

/// The largest number `prop:` compares with.
pub const MAX_PROP: f64 = 1e9;

/// The values `is:` accepts: the states, and `due`.
pub const IS: [&str; 8] = [
    "due",
    "new",
    "learning",
    "review",
    "relearning",
    "suspended",
    "leech",
    "buried",
];

/// Anki's flags by number, as an import keeps them: tags.
pub const FLAGS: [&str; 7] = [
    "flag:red",
    "flag:orange",
    "flag:green",
    "flag:blue",
    "flag:pink",
    "flag:turquoise",
    "flag:purple",
];

/// A property `prop:` compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Prop {
    /// Days from the last review to the due date.
    Ivl,
    /// Days from now to the due date (negative: overdue).
    Due,
    Reps,
    Lapses,
    /// Stability (days), difficulty (1–10), retrievability now (0–1).
    S,
    D,
    R,
}

/// The properties `prop:` knows, by name.
pub const PROPS: [(&str, Prop); 7] = [
    ("ivl", Prop::Ivl),
    ("due", Prop::Due),
    ("reps", Prop::Reps),
    ("lapses", Prop::Lapses),
    ("s", Prop::S),
    ("d", Prop::D),
    ("r", Prop::R),
];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cmp {
    Lt,
    Le,
    Eq,
    Ne,
    Ge,
    Gt,
}

impl Cmp {
    fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
            Cmp::Ge => a >= b,
            Cmp::Gt => a > b,
        }
    }
}

/// A parsed query.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// Every one holds (terms side by side, or `and`).
    All(Vec<Expr>),
    /// Any one holds (`or`).
    Any(Vec<Expr>),
    Not(Box<Expr>),
    /// `deck:` a pattern: the deck's id, or its title or an ancestor's
    /// (`Physics` finds `Physics::Rotation`).
    Deck(String),
    /// `tag:` a pattern: a tag, or a parent of one (`physics` finds
    /// `physics::rotation`).
    Tag(String),
    /// `is:` one of [`IS`].
    Is(String),
    /// `state:` one of [`STATES`] (repeated at the top of a query: any of
    /// them).
    State(String),
    /// `due:<3d`.
    DueWithin(TimeDelta),
    /// `rated:N`: answered within the last N days.
    Rated(u32),
    Prop(Prop, Cmp, f64),
    /// `flag:N`: 0 no flag, 1–7 a flag's tag.
    Flag(u8),
    /// Text, matched by the search: fuzzily, or (in quotes or with `*` as
    /// a wildcard) every piece as written, in order.
    Text {
        text: String,
        quoted: bool,
    },
}

/// What a text term is tested with: found once per query by the search,
/// then looked up per row.
pub trait TextHits {
    /// Whether row `row` matches the text term `text` (`exact`: its
    /// pieces between `*`s as written, else fuzzily).
    fn hit(&self, text: &str, exact: bool, row: usize) -> bool;
}

/// No text term to look up (a query without one).
pub struct NoText;

impl TextHits for NoText {
    fn hit(&self, _: &str, _: bool, _: usize) -> bool {
        false
    }
}

/// The deck above a deck: its `parent` key (a deck tree, `deck::tree`).
pub fn parent_deck(deck: &Deck) -> Option<&str> {
    deck.parent.as_deref()
}

/// What an expression is tested against: the rows, their decks, the time.
pub struct Ctx<'a> {
    pub rows: &'a [ItemRow],
    pub decks: &'a [Deck],
    pub now: DateTime<Utc>,
    pub hits: &'a dyn TextHits,
}

impl Expr {
    /// Whether row `i` of `cx.rows` matches.
    pub fn holds(&self, i: usize, cx: &Ctx) -> bool {
        let row = &cx.rows[i];
        match self {
            Expr::All(xs) => xs.iter().all(|x| x.holds(i, cx)),
            Expr::Any(xs) => xs.iter().any(|x| x.holds(i, cx)),
            Expr::Not(x) => !x.holds(i, cx),
            Expr::Deck(p) => deck_matches(p, cx.decks, row.deck),
            Expr::Tag(p) => row.tags(cx.decks).iter().any(|t| tag_matches(p, t)),
            Expr::Is(s) | Expr::State(s) => state_holds(s, row, cx.now),
            Expr::DueWithin(within) => row.due().is_some_and(|due| due <= cx.now + *within),
            Expr::Rated(days) => row
                .state
                .and_then(|s| s.last_review)
                .is_some_and(|at| at > cx.now - TimeDelta::days(i64::from(*days))),
            Expr::Prop(p, cmp, v) => prop(*p, row, cx.now).is_some_and(|x| cmp.holds(x, *v)),
            Expr::Flag(0) => !row
                .tags(cx.decks)
                .iter()
                .any(|t| FLAGS.iter().any(|f| t.eq_ignore_ascii_case(f))),
            Expr::Flag(n) => {
                let flag = FLAGS[usize::from(*n - 1).min(FLAGS.len() - 1)];
                row.tags(cx.decks)
                    .iter()
                    .any(|t| t.eq_ignore_ascii_case(flag))
            }
            Expr::Text { text, quoted } => cx.hits.hit(text, exact(text, *quoted), i),
        }
    }

    /// The text terms, in order, each once, with whether each is matched
    /// exactly.
    pub fn texts<'a>(&'a self, out: &mut Vec<(&'a str, bool)>) {
        match self {
            Expr::All(xs) | Expr::Any(xs) => xs.iter().for_each(|x| x.texts(out)),
            Expr::Not(x) => x.texts(out),
            Expr::Text { text, quoted } => {
                let t = (text.as_str(), exact(text, *quoted));
                if !out.contains(&t) {
                    out.push(t);
                }
            }
            _ => {}
        }
    }
}

/// Whether a text term is matched as written (its pieces between `*`s in
/// order, as Anki does) rather than fuzzily: when quoted or with a `*`.
pub fn exact(text: &str, quoted: bool) -> bool {
    quoted || text.contains('*')
}

/// Whether the state `s` (one of [`IS`]) holds for `row` at `now`.
pub fn state_holds(s: &str, row: &ItemRow, now: DateTime<Utc>) -> bool {
    match s {
        "suspended" => row.status.suspended,
        "leech" => row.status.leech,
        "buried" => row.buried(now),
        // Waiting to be studied now: not new, due, in the queue.
        "due" => row.due().is_some_and(|d| d <= now) && row.status.studyable(now),
        name => row.state_name() == name,
    }
}

/// The value of `p` for `row` at `now`; `None` when the item has none (a
/// new item has no interval, due date or memory).
pub fn prop(p: Prop, row: &ItemRow, now: DateTime<Utc>) -> Option<f64> {
    let day = 86_400.0;
    let state = row.state.filter(|s| s.state != State::New);
    match p {
        Prop::Reps => Some(f64::from(row.reviews)),
        Prop::Lapses => Some(f64::from(row.lapses)),
        Prop::Ivl => {
            let s = state?;
            let from = s.last_review?;
            Some(((s.due - from).num_seconds() as f64 / day).round())
        }
        Prop::Due => Some(((state?.due - now).num_seconds() as f64 / day).floor()),
        Prop::S => state?.stability,
        Prop::D => state?.difficulty,
        Prop::R => row.retrievability,
    }
}

/// Whether `text` matches `pattern`, `*` standing for any characters
/// (none included), letters compared without case.
pub fn glob(pattern: &str, text: &str) -> bool {
    // Most patterns have no `*`: compared as they stand, nothing copied.
    if !pattern.contains('*') {
        return pattern
            .chars()
            .flat_map(char::to_lowercase)
            .eq(text.chars().flat_map(char::to_lowercase));
    }
    let p: Vec<char> = pattern.chars().collect();
    let t: Vec<char> = text.chars().collect();
    let same = |a: char, b: char| a == b || a.to_lowercase().eq(b.to_lowercase());
    // The classic walk: on a mismatch, go back to the last `*` and let it
    // take one more character (linear but for patterns of many stars).
    let (mut pi, mut ti) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        if pi < p.len() && p[pi] == '*' {
            star = Some((pi, ti));
            pi += 1;
        } else if pi < p.len() && same(p[pi], t[ti]) {
            pi += 1;
            ti += 1;
        } else if let Some((sp, st)) = star {
            pi = sp + 1;
            ti = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == '*')
}

/// Whether `tag` matches `pattern`: as a whole, or a parent of it
/// (`physics` matches `physics::rotation`), as Anki reads `tag:`.
pub fn tag_matches(pattern: &str, tag: &str) -> bool {
    hierarchy_matches(pattern, tag)
}

/// `name` or any of its parents (what comes before a `::`) matches.
fn hierarchy_matches(pattern: &str, name: &str) -> bool {
    if glob(pattern, name) {
        return true;
    }
    name.match_indices("::")
        .any(|(at, _)| glob(pattern, &name[..at]))
}

/// Whether deck `d` of `decks` is selected by `deck:pattern`: its id
/// matches, or its title in some language (`Physics` selects the deck
/// titled `Physics::Rotation`), or the same holds for a deck above it
/// ([`parent_deck`]).
pub fn deck_matches(pattern: &str, decks: &[Deck], d: usize) -> bool {
    let mut at = d;
    // A parent chain is at most as long as the list of decks (a cycle
    // ends there).
    for _ in 0..=decks.len() {
        let deck = &decks[at];
        if glob(pattern, &deck.id)
            || deck
                .title
                .0
                .values()
                .any(|t| hierarchy_matches(pattern, t.trim()))
        {
            return true;
        }
        match parent_deck(deck).and_then(|p| decks.iter().position(|x| x.id == p)) {
            Some(up) => at = up,
            None => return false,
        }
    }
    false
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Open,
    Close,
    Minus,
    Word { text: String, quoted: bool },
}

/// Cuts a query into tokens, each with its column (from 1, in characters).
fn tokens(query: &str) -> Result<Vec<(Tok, usize)>, QueryError> {
    let cs: Vec<char> = query.chars().collect();
    if cs.len() > MAX_QUERY_CHARS {
        return Err(QueryError(format!(
            "the query is {} characters long; at most {MAX_QUERY_CHARS} are read",
            cs.len()
        )));
    }
    let mut out = Vec::new();
    let mut i = 0;
    while i < cs.len() {
        let c = cs[i];
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let col = i + 1;
        if c == '(' {
            out.push((Tok::Open, col));
            i += 1;
            continue;
        }
        if c == ')' {
            out.push((Tok::Close, col));
            i += 1;
            continue;
        }
        if c == '-'
            && cs
                .get(i + 1)
                .is_some_and(|n| !n.is_whitespace() && *n != ')')
        {
            out.push((Tok::Minus, col));
            i += 1;
            continue;
        }
        // A word: to a space or a `)` it did not open; quotes keep spaces
        // and parentheses in.
        let mut text = String::new();
        let mut quoted = false;
        let mut inside: Option<usize> = None;
        let mut depth = 0usize;
        while i < cs.len() {
            let c = cs[i];
            if inside.is_some() {
                if c == '"' {
                    inside = None;
                } else {
                    text.push(c);
                }
                i += 1;
                continue;
            }
            if c.is_whitespace() || (c == ')' && depth == 0) {
                break;
            }
            match c {
                '"' => {
                    inside = Some(i + 1);
                    quoted = true;
                }
                '(' => {
                    depth += 1;
                    text.push(c);
                }
                ')' => {
                    depth -= 1;
                    text.push(c);
                }
                _ => text.push(c),
            }
            i += 1;
        }
        if let Some(open) = inside {
            return Err(at(open, "this `\"` is never closed"));
        }
        out.push((Tok::Word { text, quoted }, col));
    }
    Ok(out)
}

fn at(col: usize, message: impl std::fmt::Display) -> QueryError {
    QueryError(format!("at column {col}: {message}"))
}

/// Parses a query into an expression; an empty query is `All([])`.
pub fn parse(query: &str) -> Result<Expr, QueryError> {
    let toks = tokens(query)?;
    let mut p = Parser {
        toks,
        at: 0,
        end: query.chars().count() + 1,
    };
    let e = p.or(0)?;
    if let Some((_, col)) = p.toks.get(p.at) {
        // Only a `)` stops the top level early.
        return Err(at(*col, "this `)` closes no `(`"));
    }
    Ok(e)
}

struct Parser {
    toks: Vec<(Tok, usize)>,
    at: usize,
    /// The column after the last character.
    end: usize,
}

fn is_word(t: &Tok, w: &str) -> bool {
    matches!(t, Tok::Word { text, quoted: false } if text.eq_ignore_ascii_case(w))
}

impl Parser {
    fn peek(&self) -> Option<&(Tok, usize)> {
        self.toks.get(self.at)
    }

    /// Terms joined by `or`.
    fn or(&mut self, depth: usize) -> Result<Expr, QueryError> {
        let mut any = vec![self.and(depth)?];
        while let Some((t, col)) = self.peek() {
            if !is_word(t, "or") {
                break;
            }
            let col = *col;
            self.at += 1;
            let next = self.and(depth)?;
            if next == Expr::All(Vec::new()) {
                return Err(at(col, "`or` needs a term after it"));
            }
            any.push(next);
        }
        if any.len() > 1 && any[0] == Expr::All(Vec::new()) {
            return Err(at(
                self.toks
                    .iter()
                    .find(|(t, _)| is_word(t, "or"))
                    .map_or(1, |x| x.1),
                "`or` needs a term before it",
            ));
        }
        Ok(if any.len() == 1 {
            any.pop().unwrap_or(Expr::All(Vec::new()))
        } else {
            Expr::Any(any)
        })
    }

    /// Terms side by side (or joined by `and`), up to an `or`, a `)` or
    /// the end.
    fn and(&mut self, depth: usize) -> Result<Expr, QueryError> {
        let mut all = Vec::new();
        while let Some((t, col)) = self.peek() {
            let col = *col;
            if *t == Tok::Close || is_word(t, "or") {
                break;
            }
            if is_word(t, "and") {
                self.at += 1;
                let next_ok = self.peek().is_some_and(|(t, _)| {
                    *t != Tok::Close && !is_word(t, "or") && !is_word(t, "and")
                });
                if all.is_empty() || !next_ok {
                    return Err(at(col, "`and` needs a term on both sides"));
                }
                continue;
            }
            all.push(self.unary(depth)?);
        }
        Ok(if all.len() == 1 {
            all.pop().unwrap_or(Expr::All(Vec::new()))
        } else {
            Expr::All(all)
        })
    }

    /// A term with any number of `-` before it.
    fn unary(&mut self, depth: usize) -> Result<Expr, QueryError> {
        let mut negate = false;
        while let Some((Tok::Minus, _)) = self.peek() {
            negate = !negate;
            self.at += 1;
        }
        let e = self.atom(depth)?;
        Ok(if negate { Expr::Not(Box::new(e)) } else { e })
    }

    fn atom(&mut self, depth: usize) -> Result<Expr, QueryError> {
        let Some((tok, col)) = self.peek().cloned() else {
            return Err(at(self.end, "a term is missing at the end"));
        };
        self.at += 1;
        match tok {
            Tok::Open => {
                if depth + 1 > MAX_DEPTH {
                    return Err(at(
                        col,
                        format!("parentheses nested deeper than {MAX_DEPTH} levels"),
                    ));
                }
                let e = self.or(depth + 1)?;
                match self.peek() {
                    Some((Tok::Close, _)) => self.at += 1,
                    _ => return Err(at(col, "this `(` is never closed")),
                }
                if e == Expr::All(Vec::new()) {
                    return Err(at(col, "nothing between `(` and `)`"));
                }
                Ok(e)
            }
            Tok::Close => Err(at(col, "this `)` closes no `(`")),
            Tok::Minus => Err(at(col, "a term is missing after `-`")),
            Tok::Word { text, quoted } => word(&text, quoted, col),
        }
    }
}

/// The filter fields of the query language.
pub const FIELDS: [&str; 8] = [
    "deck:", "tag:", "state:", "due:", "is:", "rated:", "prop:", "flag:",
];

/// One word: a field and its value, or text.
fn word(w: &str, quoted: bool, col: usize) -> Result<Expr, QueryError> {
    let text = || Expr::Text {
        text: w.to_string(),
        quoted,
    };
    let Some((field, value)) = w.split_once(':') else {
        return Ok(text());
    };
    // A colon after something that is not a field name is text (`L_z:1`).
    if field.is_empty() || !field.chars().all(|c| c.is_ascii_alphabetic()) {
        return Ok(text());
    }
    let vcol = col + field.chars().count() + 1;
    let need = |what: &str| {
        if value.is_empty() {
            Err(at(col, format!("`{field}:` needs {what}")))
        } else {
            Ok(value.to_string())
        }
    };
    let field_lower = field.to_ascii_lowercase();
    match field_lower.as_str() {
        "deck" => Ok(Expr::Deck(need("a deck id")?)),
        "tag" => Ok(Expr::Tag(need("a tag")?)),
        "state" => {
            let v = need("a state")?;
            if !STATES.contains(&v.as_str()) {
                return Err(at(
                    vcol,
                    format!("unknown state `{v}`; states are {}", STATES.join(", ")),
                ));
            }
            Ok(Expr::State(v))
        }
        "is" => {
            let v = need("a state")?;
            if !IS.contains(&v.as_str()) {
                return Err(at(
                    vcol,
                    format!(
                        "unknown state `{v}`; states are {} (is: also takes due)",
                        STATES.join(", ")
                    ),
                ));
            }
            Ok(Expr::Is(v))
        }
        "due" => {
            let span = value.strip_prefix('<').ok_or_else(|| {
                at(
                    vcol,
                    format!("`due:{value}`: write due:<3d for items due within three days"),
                )
            })?;
            Ok(Expr::DueWithin(
                parse_span(span).map_err(|e| at(vcol + 1, e.0))?,
            ))
        }
        "rated" => {
            let v = need("a number of days")?;
            match v.parse::<u32>() {
                Ok(n) if (1..=MAX_RATED_DAYS).contains(&n) => Ok(Expr::Rated(n)),
                _ => Err(at(
                    vcol,
                    format!(
                        "`rated:{v}`: write a whole number of days from 1 to {MAX_RATED_DAYS}, as rated:7"
                    ),
                )),
            }
        }
        "flag" => {
            let v = need("a flag number")?;
            match v.parse::<u8>() {
                Ok(n) if n <= 7 => Ok(Expr::Flag(n)),
                _ => Err(at(
                    vcol,
                    format!(
                        "`flag:{v}`: flags are 0 (none), 1 red, 2 orange, 3 green, 4 blue, 5 pink, 6 turquoise, 7 purple"
                    ),
                )),
            }
        }
        "prop" => {
            let v = need("a comparison, as prop:ivl>30")?;
            prop_term(&v, vcol)
        }
        other => Err(at(
            col,
            format!(
                "unknown filter `{other}:`; filters are {}",
                FIELDS.join(" ")
            ),
        )),
    }
}

/// `ivl>30`, `s<=2.5`, `lapses!=0`.
fn prop_term(v: &str, col: usize) -> Result<Expr, QueryError> {
    let names: Vec<&str> = PROPS.iter().map(|p| p.0).collect();
    let split = v
        .find(|c: char| !c.is_ascii_alphabetic())
        .unwrap_or(v.len());
    let (name, rest) = v.split_at(split);
    let Some(&(_, p)) = PROPS.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)) else {
        return Err(at(
            col,
            format!(
                "unknown property `{name}`; prop: takes {}",
                names.join(", ")
            ),
        ));
    };
    let ocol = col + name.chars().count();
    let (cmp, number) = [
        (">=", Cmp::Ge),
        ("<=", Cmp::Le),
        ("!=", Cmp::Ne),
        (">", Cmp::Gt),
        ("<", Cmp::Lt),
        ("=", Cmp::Eq),
    ]
    .into_iter()
    .find_map(|(op, c)| rest.strip_prefix(op).map(|n| (c, n)))
    .ok_or_else(|| {
        at(
            ocol,
            format!("`prop:{v}` needs a comparison: <, <=, =, !=, >= or > and a number"),
        )
    })?;
    let ncol = ocol + rest.chars().count() - number.chars().count();
    if number.is_empty() {
        return Err(at(ncol, format!("a number is missing after `prop:{v}`")));
    }
    match number.parse::<f64>() {
        Ok(x) if x.is_finite() && x.abs() <= MAX_PROP && !number.starts_with('+') => {
            Ok(Expr::Prop(p, cmp, x))
        }
        _ => Err(at(
            ncol,
            format!("`{number}` is not a number (in prop:{v})"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn globs_and_hierarchies() {
        assert!(glob("phys*", "physics"));
        assert!(glob("*ics", "Physics"));
        assert!(glob("p*s*s", "physics"));
        assert!(!glob("phys", "physics"));
        assert!(glob("*", ""));
        assert!(tag_matches("physics", "physics::rotation"));
        assert!(tag_matches("physics", "Physics"));
        assert!(tag_matches("rot*", "rotation::euler"));
        assert!(!tag_matches("rotation", "physics::rotation"));
        assert!(tag_matches("*rotation", "physics::rotation"));
        assert!(!tag_matches("phys", "physics::rotation"));
    }

    #[test]
    fn the_grammar_groups_as_anki_does() {
        let t = |s: &str| Expr::Text {
            text: s.into(),
            quoted: false,
        };
        assert_eq!(
            parse("a b or c").unwrap(),
            Expr::Any(vec![Expr::All(vec![t("a"), t("b")]), t("c")])
        );
        assert_eq!(
            parse("-(a or b) c").unwrap(),
            Expr::All(vec![
                Expr::Not(Box::new(Expr::Any(vec![t("a"), t("b")]))),
                t("c")
            ])
        );
        assert_eq!(parse("--a").unwrap(), t("a"));
        assert_eq!(parse("sin(x)").unwrap(), t("sin(x)"));
        assert_eq!(
            parse("\"or\" and \"a b\"").unwrap(),
            Expr::All(vec![
                Expr::Text {
                    text: "or".into(),
                    quoted: true
                },
                Expr::Text {
                    text: "a b".into(),
                    quoted: true
                }
            ])
        );
        assert_eq!(
            parse("prop:ivl>=30 prop:s<2.5 rated:7 flag:1 is:due").unwrap(),
            Expr::All(vec![
                Expr::Prop(Prop::Ivl, Cmp::Ge, 30.0),
                Expr::Prop(Prop::S, Cmp::Lt, 2.5),
                Expr::Rated(7),
                Expr::Flag(1),
                Expr::Is("due".into()),
            ])
        );
    }

    #[test]
    fn errors_name_the_column() {
        for (q, says) in [
            ("(a or b", "at column 1: this `(` is never closed"),
            ("a b)", "at column 4: this `)` closes no `(`"),
            ("is:sleepy", "at column 4: unknown state `sleepy`"),
            ("prop:ease>2", "at column 6: unknown property `ease`"),
            ("prop:ivl>x", "at column 10: `x` is not a number"),
            ("prop:ivl~3", "at column 9: `prop:ivl~3` needs a comparison"),
            ("rated:0", "at column 7: `rated:0`"),
            ("rated:99999999", "at column 7"),
            ("flag:9", "at column 6: `flag:9`"),
            ("a or", "at column 3: `or` needs a term after it"),
            ("or a", "at column 1: `or` needs a term before it"),
            ("()", "at column 1: nothing between"),
            ("\"abc", "at column 1: this `\"` is never closed"),
            ("x colour:red", "at column 3: unknown filter `colour:`"),
        ] {
            let e = parse(q).unwrap_err();
            assert!(e.0.contains(says), "{q}: {e}");
        }
        let deep = format!(
            "{}a{}",
            "(".repeat(MAX_DEPTH + 1),
            ")".repeat(MAX_DEPTH + 1)
        );
        assert!(parse(&deep).unwrap_err().0.contains("nested deeper"));
        let ok = format!("{}a{}", "(".repeat(MAX_DEPTH), ")".repeat(MAX_DEPTH));
        assert!(parse(&ok).is_ok());
    }
}

#[cfg(test)]
mod props {
    //! `a or b` is the union, `-a` the complement, `a b` (of terms that are
    //! not text) the intersection, on generated catalogs, through the path
    //! every list takes (`Filter::parse`, then `search::select`); and no
    //! input makes the parser panic or recurse without bound.

    use std::collections::BTreeSet;
    use std::path::PathBuf;

    use chrono::{TimeZone, Utc};
    use proptest::prelude::*;

    use super::*;
    use crate::catalog::search::{Search, select};
    use crate::catalog::{Filter, ItemRow};
    use crate::sched::{CardState, Direction};
    use crate::store::status::ItemStatus;

    const TAGS: [&str; 7] = [
        "physics",
        "physics::rotation",
        "physics::rotation::euler",
        "waves",
        "flag:red",
        "flag:blue",
        "leech",
    ];
    const WORDS: [&str; 6] = ["torque", "spin", "omega", "wave", "axis", "energy"];

    /// A deck of `cards` (each: tags by index, two words of its front)
    /// loaded as every deck is.
    fn deck(id: &str, title: &str, cards: &[(Vec<usize>, usize, usize)]) -> Deck {
        let mut toml =
            format!("[deck]\nid = \"{id}\"\ntitle = {{ en = '{title}' }}\nlanguages = [\"en\"]\n");
        for (i, (tags, a, b)) in cards.iter().enumerate() {
            let tags: Vec<String> = tags.iter().map(|t| format!("\"{}\"", TAGS[*t])).collect();
            toml.push_str(&format!(
                "\n[[card]]\nid = \"c{i}\"\ntags = [{}]\nfront = {{ en = 'the {} of the {}' }}\nback = {{ en = 'x' }}\n",
                tags.join(", "),
                WORDS[*a],
                WORDS[*b]
            ));
        }
        let leak = |s: String| -> &'static [u8] { Box::leak(s.into_bytes().into_boxed_slice()) };
        let tree = crate::deck::files::Memory::new([
            (PathBuf::from(format!("d/decks/{id}.toml")), leak(toml)),
            (
                PathBuf::from(format!("d/content/{id}/en.toml")),
                leak(String::new()),
            ),
        ]);
        let loaded = crate::deck::load::load_tree(&tree, &[PathBuf::from("d/decks")]);
        assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
        loaded.decks.into_iter().next().expect("the deck loads")
    }

    /// `deck:ID` takes the deck's subdecks by their `parent` key, as
    /// `deck:parent` in Anki takes its children (a deck tree's ids have no
    /// `::`); a parent is not taken by its child's id.
    #[test]
    fn a_deck_query_takes_the_subdecks_by_their_parent() {
        let mut decks = vec![
            deck("mech", "Mechanics", &[]),
            deck("springs", "Springs", &[]),
            deck("coils", "Coils", &[]),
            deck("optics", "Optics", &[]),
        ];
        decks[1].parent = Some("mech".into());
        decks[2].parent = Some("springs".into());
        let taken = |decks: &[Deck], q: &str| -> Vec<usize> {
            (0..decks.len())
                .filter(|&d| deck_matches(q, decks, d))
                .collect()
        };
        assert_eq!(taken(&decks, "mech"), [0, 1, 2]);
        assert_eq!(taken(&decks, "springs"), [1, 2]);
        assert_eq!(taken(&decks, "coils"), [2]);
        assert_eq!(taken(&decks, "Mechanics"), [0, 1, 2], "by title too");
        assert_eq!(taken(&decks, "opt*"), [3]);
        // A cycle (refused by the loader) still ends.
        decks[0].parent = Some("coils".into());
        assert_eq!(taken(&decks, "optics"), [3]);
        assert_eq!(taken(&decks, "coils"), [0, 1, 2]);
    }

    fn catalog() -> impl Strategy<Value = (Vec<Deck>, Vec<ItemRow>)> {
        let card = (
            proptest::collection::vec(0..TAGS.len(), 0..3),
            0..WORDS.len(),
            0..WORDS.len(),
        );
        let state =
            proptest::option::of((0..3u8, -40i64..60, 0i64..80, 0.5f64..90.0, 1.0f64..10.0));
        let status = (any::<bool>(), any::<bool>(), any::<bool>());
        (
            proptest::collection::vec(card.clone(), 1..6),
            proptest::collection::vec(card, 1..6),
            proptest::collection::vec((state, status, 0u32..6, 0u32..3), 12),
        )
            .prop_map(|(a, b, states)| {
                let decks = vec![
                    deck("mech", "Physics::Mechanics", &a),
                    deck("optics", "Optics", &b),
                ];
                let now = Utc.with_ymd_and_hms(2026, 6, 1, 12, 0, 0).unwrap();
                let mut rows = Vec::new();
                for (d, deck) in decks.iter().enumerate() {
                    for c in 0..deck.cards.len() {
                        rows.push((d, c));
                    }
                }
                let rows = rows
                    .into_iter()
                    .zip(states.into_iter().cycle())
                    .map(|((deck, card), (st, (sus, bur, lee), reps, lapses))| {
                        let state = st.map(|(k, due, ago, s, d)| CardState {
                            state: [State::Learning, State::Review, State::Relearning]
                                [usize::from(k)],
                            step: None,
                            stability: Some(s),
                            difficulty: Some(d),
                            due: now + TimeDelta::days(due),
                            last_review: Some(now - TimeDelta::days(ago)),
                        });
                        ItemRow {
                            deck,
                            card,
                            direction: Direction::Forward,
                            retrievability: state.map(|s| 0.5 + s.stability.unwrap_or(1.0) / 200.0),
                            state,
                            reviews: reps,
                            lapses,
                            status: ItemStatus {
                                suspended: sus,
                                buried_until: bur.then(|| now + TimeDelta::hours(3)),
                                leech: lee,
                            },
                        }
                    })
                    .collect();
                (decks, rows)
            })
    }

    const FIELD_TERMS: [&str; 29] = [
        "deck:mech",
        "deck:physics",
        "deck:opt*",
        "deck:*",
        "tag:physics",
        "tag:physics::rotation",
        "tag:wav*",
        "tag:*euler",
        "is:due",
        "is:new",
        "is:suspended",
        "is:buried",
        "is:leech",
        "is:review",
        "state:learning",
        "rated:3",
        "rated:30",
        "prop:ivl>30",
        "prop:ivl<=10",
        "prop:due<0",
        "prop:reps>=2",
        "prop:lapses!=0",
        "prop:s>20",
        "prop:d<5",
        "prop:r=0.7",
        "flag:0",
        "flag:1",
        "flag:4",
        "due:<3d",
    ];
    const TEXT_TERMS: [&str; 5] = ["torque", "omega", "spn", "ax*s", "*ener*"];

    fn grouped(leaf: BoxedStrategy<String>) -> impl Strategy<Value = String> {
        leaf.prop_recursive(3, 12, 2, |inner| {
            prop_oneof![
                (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} or {b})")),
                inner.clone().prop_map(|a| format!("-{a}")),
                inner.prop_map(|a| format!("-({a})")),
            ]
        })
    }

    /// A term: a field, a word (fuzzy or with `*`), or a group of them.
    fn term() -> impl Strategy<Value = String> {
        let all: Vec<&str> = FIELD_TERMS.iter().chain(&TEXT_TERMS).copied().collect();
        grouped(
            proptest::sample::select(all)
                .prop_map(str::to_string)
                .boxed(),
        )
    }

    /// A term without text.
    fn fields() -> impl Strategy<Value = String> {
        grouped(
            proptest::sample::select(FIELD_TERMS.to_vec())
                .prop_map(str::to_string)
                .boxed(),
        )
    }

    fn rows_of(q: &str, decks: &[Deck], rows: &[ItemRow]) -> BTreeSet<usize> {
        let now = Utc.with_ymd_and_hms(2026, 6, 1, 12, 0, 0).unwrap();
        let f = Filter::parse(q).unwrap_or_else(|e| panic!("{q}: {e}"));
        let mut search = Search::for_filter(&f, decks, rows);
        select(decks, rows, &mut search, &f, now)
            .into_iter()
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(96))]

        #[test]
        fn or_is_the_union_and_minus_the_complement(
            (decks, rows) in catalog(),
            a in term(),
            b in term(),
            f in fields(),
        ) {
            let all: BTreeSet<usize> = (0..rows.len()).collect();
            let ra = rows_of(&a, &decks, &rows);
            let rb = rows_of(&b, &decks, &rows);
            let union: BTreeSet<usize> = ra.union(&rb).copied().collect();
            prop_assert_eq!(rows_of(&format!("{a} or {b}"), &decks, &rows), union, "{} or {}", a, b);
            let rest: BTreeSet<usize> = all.difference(&ra).copied().collect();
            prop_assert_eq!(rows_of(&format!("-{a}"), &decks, &rows), rest.clone(), "-{}", a);
            prop_assert_eq!(rows_of(&format!("-({a})"), &decks, &rows), rest, "-({})", a);
            prop_assert_eq!(rows_of(&format!("--{a}"), &decks, &rows), ra.clone(), "--{}", a);
            // Side by side with terms without text: both hold; but two
            // `deck:` or two `state:` terms at the top level take any of
            // them (README, "repeated: any of them", as `--deck a --deck
            // b`), however they are wrapped (`--(deck:mech) deck:opt*`).
            let rf = rows_of(&f, &decks, &rows);
            let side = Filter::parse(&format!("{a} {f}")).unwrap();
            let either = side.decks.len() > 1 || side.states.len() > 1;
            let both: BTreeSet<usize> = if either {
                ra.union(&rf).copied().collect()
            } else {
                ra.intersection(&rf).copied().collect()
            };
            prop_assert_eq!(rows_of(&format!("{a} {f}"), &decks, &rows), both.clone(), "{} {}", a, f);
            prop_assert_eq!(rows_of(&format!("{f} and {a}"), &decks, &rows), both, "{} and {}", f, a);
        }

        /// No input makes the parser panic; every error is one line that
        /// names a column within the query (or its length).
        #[test]
        fn the_parser_never_panics(q in "[-()\" a-z:*<>=!0-9.]{0,60}|\\PC{0,40}") {
            if let Err(e) = parse(&q) {
                prop_assert!(!e.0.contains('\n'), "{}", e);
                if let Some(rest) = e.0.strip_prefix("at column ") {
                    let col: usize = rest.split(':').next().unwrap_or("").parse().unwrap_or(0);
                    prop_assert!(col >= 1 && col <= q.chars().count() + 1, "{} in {:?}", e, q);
                }
            }
            let _ = Filter::parse(&q);
        }

        /// Parentheses nested past the bound are refused, not a stack
        /// overflow, however deep.
        #[test]
        fn deep_nesting_is_refused(depth in 0usize..3_000, minus in any::<bool>()) {
            let open = if minus { "-(" } else { "(" };
            let q = format!("{}a{}", open.repeat(depth), ")".repeat(depth));
            match parse(&q) {
                Ok(_) => prop_assert!(depth <= MAX_DEPTH),
                Err(e) => {
                    prop_assert!(depth > MAX_DEPTH);
                    prop_assert!(
                        e.0.contains("nested deeper") || e.0.contains("at most 4096"),
                        "{}",
                        e
                    );
                }
            }
        }
    }
}
