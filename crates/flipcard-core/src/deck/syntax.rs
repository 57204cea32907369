//! TOML syntax errors as diagnostics, one per cause.
//!
//! The `toml` crate reports each clash of key definitions as a bare
//! "duplicate key" at the later one and keeps where the first one was to
//! itself, so a stray `card = 5` above twenty `[[card]]` headers gives
//! twenty errors that never name the key. And an array or inline table left
//! open reads the rest of the file as its elements, with an error for
//! nearly every line after it. So when a file has errors it is walked once
//! more with `toml_parser` (the crate's own parser), which gives the full
//! path and role of every key written and where each bracket opens: the
//! clashes with one first definition become one error there, and an
//! unclosed bracket one error at the bracket.

use std::collections::{BTreeMap, HashMap};

use toml::de::DeTable;
use toml_parser::decoder::ScalarKind;
use toml_parser::lexer::TokenKind;
use toml_parser::parser::{Event, EventKind, RecursionGuard};
use toml_parser::{ParseError, Raw, Source};

use super::raw::Span;
use super::report::{FileReport, at_lines};

/// TOML syntax errors shown per file; past this they are mostly echoes of
/// the first ones.
const MAX_SYNTAX_ERRORS: usize = 20;

/// Nesting deeper than this is not followed (the `toml` crate's own limit,
/// which keeps a file of 100 000 `[` from overflowing the stack).
const MAX_DEPTH: u32 = 80;

/// Parses TOML, reporting every syntax error; `None` when there are any
/// (a recovered tree would only add confusing follow-up errors).
pub fn parse<'s>(rep: &mut FileReport, text: &'s str) -> Option<(DeTable<'s>, Span)> {
    let (table, errors) = DeTable::parse_recoverable(text);
    if errors.is_empty() {
        let span = table.span();
        return Some((table.into_inner(), span));
    }
    let mut found: Vec<(Span, String)> = errors
        .iter()
        .map(|e| (e.span().unwrap_or(0..0), e.message().to_string()))
        .collect();
    found.sort_by_key(|(span, _)| span.start);
    found.dedup();

    let outline = Outline::read(text);
    if let Some(open) = &outline.unclosed {
        // Everything the open bracket swallowed is its doing.
        found.retain(|(span, _)| span.start < open.opener.start || span.start > open.swallowed_to);
        rep.error(
            open.opener.clone(),
            format!(
                "TOML: unclosed {}: this `{}` is never closed",
                open.what, open.bracket
            ),
            Some(format!(
                "the rest of the file was read as part of it; add the missing `{}`",
                open.closer
            )),
        );
    }
    let (clashes, mut found): (Vec<_>, Vec<_>) = found.into_iter().partition(|(_, m)| is_clash(m));
    report_clashes(rep, &outline, &clashes);
    let mut hints: Vec<(usize, String)> = Vec::new();
    hints.extend(strings_out_of_step(rep, &outline, &mut found, text));
    hints.extend(text_outside_strings(rep, &outline, &mut found, text));

    // A literal string ended at an apostrophe leaves the rest of its line
    // to be read as TOML, with an error at nearly every word: one error.
    let mut apostrophe_lines: Vec<usize> = Vec::new();
    found.retain(|(span, _)| {
        if apostrophe_hint(text, span.start).is_none() {
            return true;
        }
        let line = rep.line_of(span.start);
        let first = !apostrophe_lines.contains(&line);
        apostrophe_lines.push(line);
        first
    });
    let extra = found.len().saturating_sub(MAX_SYNTAX_ERRORS);
    for (span, message) in found.iter().take(MAX_SYNTAX_ERRORS) {
        let escape = (message.contains("escape") || message.contains("unicode")).then(|| {
            "a backslash in a \"...\" string starts an escape; write LaTeX in a literal string '...' or '''...'''"
                .to_string()
        });
        let hint = hints
            .iter()
            .find(|(at, _)| *at == span.start)
            .map(|(_, hint)| hint.clone())
            .or(escape)
            .or_else(|| apostrophe_hint(text, span.start));
        rep.error(
            span.clone(),
            format!("TOML: {}", escape_list(message)),
            hint,
        );
    }
    if extra > 0 {
        let at = found[MAX_SYNTAX_ERRORS].0.clone();
        rep.error(
            at,
            format!("TOML: {extra} more syntax errors not shown"),
            None,
        );
    }
    None
}

/// The hint for an error on a line where a literal string `'...'` ends
/// early at an apostrophe (`'Euler's equation'`): the README's advice,
/// with the word as written.
fn apostrophe_hint(text: &str, at: usize) -> Option<String> {
    let at = at.min(text.len());
    let line_start = text[..at].rfind('\n').map_or(0, |n| n + 1);
    let line_end = text[at..].find('\n').map_or(text.len(), |n| at + n);
    let line = &text[line_start..line_end];
    // A value opening a one-line literal string: `= '` but not `= '''`.
    let open = line.find("= '").map(|e| e + 2)?;
    if line[open..].starts_with("'''") {
        return None;
    }
    let body = &line[open + 1..];
    let close = body.find('\'')?;
    let before = body[..close].chars().next_back()?;
    let after = body[close + 1..].chars().next()?;
    if !(before.is_alphanumeric() && after.is_alphanumeric()) {
        return None;
    }
    let word_start = body[..close]
        .rfind(|c: char| !c.is_alphanumeric())
        .map_or(0, |i| i + 1);
    let word_end = body[close + 1..]
        .find(|c: char| !c.is_alphanumeric())
        .map_or(body.len(), |i| close + 1 + i);
    let word = &body[word_start..word_end];
    Some(format!(
        "a literal string '...' cannot hold `'`: it ends at the apostrophe of `{word}`; write the text in '''...''' (or in a basic string \"...\" when it has no backslash)"
    ))
}

/// Every escape TOML allows in a basic string. The parser's own list
/// leaves out `\t`, which is exactly the one a `\theta` turns into.
const VALID_ESCAPES: &str = "`b`, `t`, `n`, `f`, `r`, `e`, `\"`, `\\`, `x`, `u`, `U`";

/// The parser's message, with its list of valid escapes made complete.
fn escape_list(message: &str) -> String {
    const HEAD: &str = "missing escaped value, expected ";
    match message.find(HEAD) {
        Some(at) if message.contains("escape") => {
            let list_start = at + HEAD.len();
            // The list runs to the end of the line.
            let end = message[list_start..]
                .find('\n')
                .map_or(message.len(), |i| list_start + i);
            format!(
                "{}{VALID_ESCAPES}{}",
                &message[..list_start],
                &message[end..]
            )
        }
        _ => message.to_string(),
    }
}

/// A multi-line string running to the end of the file, with other errors
/// before it, means the `'''` (or `"""`) are out of step: one is missing
/// or one too many, every string after pairs the wrong delimiters, and text
/// between them is read as TOML to the end of the file. That is one error:
/// at a string that runs on to the delimiter opening the next one (its own
/// closer is missing), or else at the first error, where the extra or
/// missing delimiter most likely is. The other errors are dropped; the
/// returned hint goes with the first error kept.
fn strings_out_of_step(
    rep: &mut FileReport,
    outline: &Outline,
    found: &mut Vec<(Span, String)>,
    text: &str,
) -> Option<(usize, String)> {
    let open = outline.strings.iter().find(|s| !s.closed)?;
    // The crate reports the string at the end of the file.
    let at_end = |span: &Span| span.start >= text.len().saturating_sub(1);
    if !found.iter().any(|(span, _)| at_end(span)) {
        return None;
    }
    found.retain(|(span, _)| !at_end(span));
    let delim = open.delim;
    let Some(first) = found.first().map(|(span, _)| span.start) else {
        rep.error(
            open.start..open.start + delim.len(),
            format!("TOML: unclosed multi-line string: this `{delim}` is never closed"),
            Some(format!(
                "the rest of the file was read as part of it; add the closing `{delim}`"
            )),
        );
        return None;
    };
    let runaway = outline
        .strings
        .iter()
        .find(|s| s.closed && s.ends_at_opener && s.start < first);
    if let Some(r) = runaway {
        found.retain(|(span, _)| span.start < r.start);
        let line = rep.line_of(r.end.saturating_sub(1));
        rep.error(
            r.start..r.start + r.delim.len(),
            format!(
                "TOML: multi-line string not closed: it runs on to line {line}, where the next string opens"
            ),
            Some(format!(
                "add the closing `{}` where its text ends; every string after it was read out of step",
                r.delim
            )),
        );
        return None;
    }
    let dropped = found.iter().filter(|(span, _)| span.start > first).count();
    found.retain(|(span, _)| span.start <= first);
    Some((
        first,
        format!(
            "a `{delim}` near here is missing or one too many: the multi-line strings after it are out of step to the end of the file ({dropped} more errors not shown)"
        ),
    ))
}

/// This many errors between two multi-line strings that read words as keys
/// are taken for text that a misplaced delimiter left outside its string.
const PROSE_RUN: usize = 2;

/// Text left outside its string by a misplaced `'''` (a swapped or moved
/// line) is read as TOML until the next string, with an error on nearly
/// every line. Between two multi-line strings, a run of errors that read
/// words as keys is one error, at its first; the returned hints go with
/// the errors kept.
fn text_outside_strings(
    rep: &FileReport,
    outline: &Outline,
    found: &mut Vec<(Span, String)>,
    text: &str,
) -> Vec<(usize, String)> {
    // Gaps are counted between strings that are values (`key = '''`): a
    // string that is not one is part of the misplaced text.
    let values: Vec<&MlString> = outline.strings.iter().filter(|s| s.is_value).collect();
    if values.is_empty() {
        return Vec::new();
    }
    let prose = |m: &str| {
        m.starts_with("key with no value")
            || m.starts_with("invalid unquoted key")
            || m.starts_with("unexpected key or value")
    };
    // Errors by the gap between strings they are in, and within it by the
    // last line before them that reads as TOML (a header or `key = `): the
    // misplaced text rarely has one, so an error after one has its own cause.
    let gap = |at: usize| values.partition_point(|s| s.end <= at);
    let mut toml_lines = Vec::new();
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let key_eq = trimmed
            .find('=')
            .is_some_and(|eq| looks_like_key_eq(&trimmed[..=eq]));
        if trimmed.starts_with('[') || key_eq {
            toml_lines.push(line_start);
        }
        line_start += line.len();
    }
    let section = |at: usize| toml_lines.partition_point(|&s| s <= at);
    let mut runs: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (i, (span, _)) in found.iter().enumerate() {
        runs.entry((gap(span.start), section(span.start)))
            .or_default()
            .push(i);
    }
    let mut dropped = vec![false; found.len()];
    let mut hints = Vec::new();
    for members in runs.values() {
        let prose_errors = members.iter().filter(|&&i| prose(&found[i].1)).count();
        if prose_errors < PROSE_RUN {
            continue;
        }
        let (first, last) = (members[0], members[members.len() - 1]);
        for &i in &members[1..] {
            dropped[i] = true;
        }
        hints.push((
            found[first].0.start,
            format!(
                "this looks like text outside its string: a `'''` before it may be missing or misplaced ({} more errors up to line {} not shown)",
                members.len() - 1,
                rep.line_of(found[last].0.start)
            ),
        ));
    }
    let mut kept = dropped.iter();
    found.retain(|_| kept.next() == Some(&false));
    hints
}

/// The `toml` crate's messages for a key defined twice (`duplicate key`,
/// `cannot extend value of type integer with a dotted key`).
fn is_clash(message: &str) -> bool {
    message == "duplicate key" || message.starts_with("cannot extend value of type")
}

/// One error per first definition, naming the key and every later one.
fn report_clashes(rep: &mut FileReport, outline: &Outline, clashes: &[(Span, String)]) {
    let clash_starts: Vec<usize> = clashes.iter().map(|(s, _)| s.start).collect();
    // First definition → the later definitions that clash with it.
    let mut groups: BTreeMap<usize, (&KeyDef, Vec<&KeyDef>)> = BTreeMap::new();
    let mut unplaced: Vec<&(Span, String)> = Vec::new();
    for clash in clashes {
        let Some(later) = outline.def_at(clash.0.start) else {
            unplaced.push(clash);
            continue;
        };
        // Keys inside a key that is itself a clash are its echoes: `[deck]`
        // twice makes every key in it a clash, `[prompt.answer]` above the
        // first [[prompt]] every later `[prompt.answer]`.
        let inside_a_clash = clash_starts.iter().any(|&start| {
            start < later.span.start
                && outline.def_at(start).is_some_and(|outer| {
                    outer.keys().len() < later.keys().len()
                        && later.keys().starts_with(&outer.keys())
                })
        });
        if inside_a_clash {
            continue;
        }
        match outline.first_def(later) {
            Some(first) => groups
                .entry(first.span.start)
                .or_insert_with(|| (first, Vec::new()))
                .1
                .push(later),
            None => unplaced.push(clash),
        }
    }
    for (first, later) in groups.values() {
        let name = later[0].name();
        let mut lines: Vec<usize> = later.iter().map(|d| rep.line_of(d.span.start)).collect();
        lines.dedup();
        let roles_agree = later.iter().all(|d| d.role == later[0].role);
        let then = match lines.split_first() {
            Some((second, rest)) if !roles_agree && !rest.is_empty() => format!(
                "then as {} at line {second} and again at {}",
                later[0].role.describe(),
                at_lines(rest)
            ),
            _ => format!(
                "then as {} at {}",
                later[0].role.describe(),
                at_lines(&lines)
            ),
        };
        let times = match later.len() {
            1 => "twice".to_string(),
            n => format!("{} times", n + 1),
        };
        let message = format!(
            "key `{name}` is defined {times}: first here as {}, {then}",
            first.role.describe(),
        );
        rep.error(
            first.span.clone(),
            message,
            Some("a key is defined once in its table: keep one definition, rename or remove the others".to_string()),
        );
    }
    // Where the walk does not see the clash (it should), the crate's own
    // message is kept, with the key named.
    for (span, message) in unplaced {
        let name = outline
            .defs
            .iter()
            .find(|d| d.span.start == span.start)
            .map(KeyDef::name);
        let message = match name {
            Some(name) => format!("TOML: {message} (`{name}`)"),
            None => format!("TOML: {message}"),
        };
        rep.error(span.clone(), message, None);
    }
}

/// A step in a key's full path: a key, or the n-th table of an array of
/// tables (or item of an array).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Seg {
    Key(String),
    Item(usize),
}

/// What writing a key defines.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Role {
    /// `key = value`: "a number", "a string", ...
    Value(&'static str),
    /// The last key of a header, as written: `[deck]`, `[[card]]`.
    Header(String),
    /// A key before the last in a header or a dotted key: it makes a table
    /// for the keys after it ("[x.y]", "the dotted key `x.y`").
    Parent(String),
}

impl Role {
    fn describe(&self) -> String {
        match self {
            Role::Value(what) => what.to_string(),
            Role::Header(header) => header.clone(),
            Role::Parent(by) => format!("a table by {by}"),
        }
    }
}

/// One key as written.
#[derive(Debug, Clone)]
struct KeyDef {
    path: Vec<Seg>,
    span: Span,
    role: Role,
}

impl KeyDef {
    /// The path's keys, without array positions.
    fn keys(&self) -> Vec<&str> {
        self.path
            .iter()
            .filter_map(|s| match s {
                Seg::Key(k) => Some(k.as_str()),
                Seg::Item(_) => None,
            })
            .collect()
    }

    /// The dotted path, without array positions: `deck.id`.
    fn name(&self) -> String {
        let keys: Vec<String> = self
            .path
            .iter()
            .filter_map(|s| match s {
                Seg::Key(k) => Some(shown_key(k)),
                Seg::Item(_) => None,
            })
            .collect();
        keys.join(".")
    }
}

/// A key as it would be written: bare when it can be.
fn shown_key(k: &str) -> String {
    let bare = !k.is_empty()
        && k.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
    if bare {
        k.to_string()
    } else {
        format!("{k:?}")
    }
}

/// An array or inline table that is never closed.
#[derive(Debug, Clone)]
struct Unclosed {
    opener: Span,
    /// The last byte read as part of it.
    swallowed_to: usize,
    what: &'static str,
    bracket: char,
    closer: char,
}

/// What the walk of a file found.
#[derive(Debug, Default)]
struct Outline {
    /// Every key written, in file order.
    defs: Vec<KeyDef>,
    /// The innermost unclosed array or inline table.
    unclosed: Option<Unclosed>,
    /// Every multi-line string, in file order.
    strings: Vec<MlString>,
}

impl Outline {
    fn read(text: &str) -> Outline {
        let source = Source::new(text);
        let tokens = source.lex().into_vec();
        let mut events: Vec<Event> = Vec::new();
        let mut errors: Vec<ParseError> = Vec::new();
        {
            let mut push = |e: Event| events.push(e);
            let mut guard = RecursionGuard::new(&mut push, MAX_DEPTH);
            toml_parser::parser::parse_document(&tokens, &mut guard, &mut errors);
        }
        let unclosed = errors
            .iter()
            .filter_map(|e| {
                let (what, bracket, closer) = match e.description() {
                    "unclosed array" => ("array", '[', ']'),
                    "unclosed inline table" => ("inline table", '{', '}'),
                    _ => return None,
                };
                let opener = e.context()?;
                Some(Unclosed {
                    opener: opener.start()..opener.end(),
                    swallowed_to: e.unexpected().map_or(text.len(), |u| u.end()),
                    what,
                    bracket,
                    closer,
                })
            })
            // An inner bracket left open leaves the ones around it open too;
            // the innermost is the one missing its closer.
            .max_by_key(|u| u.opener.start);
        let strings = tokens
            .iter()
            .filter(|t| {
                matches!(
                    t.kind(),
                    TokenKind::MlBasicString | TokenKind::MlLiteralString
                )
            })
            .map(|t| MlString::new(text, t.span().start()..t.span().end()))
            .collect();
        let mut walk = Walk::new(text);
        for e in &events {
            walk.event(e);
        }
        Outline {
            defs: walk.defs,
            unclosed,
            strings,
        }
    }

    fn def_at(&self, start: usize) -> Option<&KeyDef> {
        self.defs.iter().find(|d| d.span.start == start)
    }

    /// The earliest definition of the same key as `later`.
    fn first_def(&self, later: &KeyDef) -> Option<&KeyDef> {
        self.defs
            .iter()
            .take_while(|d| d.span.start < later.span.start)
            .find(|d| d.path == later.path)
    }
}

/// A multi-line string token.
#[derive(Debug, Clone)]
struct MlString {
    start: usize,
    end: usize,
    delim: &'static str,
    /// Ends with its own delimiter (else it runs to the end of the file).
    closed: bool,
    /// Its closing delimiter follows `key =` on its line: it is the next
    /// string's opener, and this string's own closer is missing.
    ends_at_opener: bool,
    /// It follows `key =` on its line.
    is_value: bool,
}

impl MlString {
    fn new(text: &str, span: Span) -> MlString {
        let token = text.get(span.clone()).unwrap_or("");
        let delim = if token.starts_with('"') {
            "\"\"\""
        } else {
            "'''"
        };
        let closed = token.len() >= 6 && token.ends_with(delim);
        let close = span.end.saturating_sub(delim.len());
        let spans_lines = token
            .get(..token.len().saturating_sub(delim.len()))
            .is_some_and(|t| t.contains('\n'));
        MlString {
            start: span.start,
            end: span.end,
            delim,
            closed,
            ends_at_opener: closed && spans_lines && looks_like_key_eq(line_before(text, close)),
            is_value: looks_like_key_eq(line_before(text, span.start)),
        }
    }
}

/// The text from the start of the line of byte `at` up to it.
fn line_before(text: &str, at: usize) -> &str {
    let before = text.get(..at).unwrap_or("");
    &before[before.rfind('\n').map_or(0, |i| i + 1)..]
}

/// `body = ` (a key and `=`, nothing else).
fn looks_like_key_eq(s: &str) -> bool {
    let Some(key) = s.trim_end().strip_suffix('=') else {
        return false;
    };
    let key = key.trim();
    !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | ' ' | '"' | '\''))
}

/// Where the walk is: a table (the root, a header's, an inline table)
/// taking keys, or an array taking items.
#[derive(Debug, Clone)]
enum Frame {
    Table(Vec<Seg>),
    Array(Vec<Seg>, usize),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Reading the keys of a key-value pair (or between pairs).
    Keys,
    /// Reading a header's keys.
    Header { array: bool },
    /// After `=`: the next value belongs to the keys read.
    Value,
}

/// Follows the parser's events, keeping every key's full path the way the
/// `toml` crate builds its tables (arrays of tables by their last table).
struct Walk<'s> {
    text: &'s str,
    defs: Vec<KeyDef>,
    /// How many tables each array of tables has so far.
    tables_in: HashMap<Vec<Seg>, usize>,
    frames: Vec<Frame>,
    keys: Vec<(String, Span)>,
    mode: Mode,
    after_key_sep: bool,
}

impl<'s> Walk<'s> {
    fn new(text: &'s str) -> Walk<'s> {
        Walk {
            text,
            defs: Vec::new(),
            tables_in: HashMap::new(),
            frames: vec![Frame::Table(Vec::new())],
            keys: Vec::new(),
            mode: Mode::Keys,
            after_key_sep: false,
        }
    }

    fn event(&mut self, e: &Event) {
        let span = e.span().start()..e.span().end();
        let after_key_sep = std::mem::take(&mut self.after_key_sep);
        match e.kind() {
            EventKind::Whitespace | EventKind::Comment | EventKind::Error => {
                self.after_key_sep = after_key_sep;
            }
            EventKind::StdTableOpen | EventKind::ArrayTableOpen => {
                self.frames.truncate(1);
                self.keys.clear();
                self.mode = Mode::Header {
                    array: e.kind() == EventKind::ArrayTableOpen,
                };
            }
            EventKind::StdTableClose | EventKind::ArrayTableClose => self.end_header(),
            EventKind::Newline => {
                // A header's `]` may be missing; the line ends it anyway.
                self.end_header();
            }
            EventKind::SimpleKey => {
                let name = self.decode_key(e, &span);
                match self.mode {
                    Mode::Header { .. } if after_key_sep || self.keys.is_empty() => {
                        self.keys.push((name, span));
                    }
                    Mode::Header { .. } => {}
                    Mode::Keys if after_key_sep => self.keys.push((name, span)),
                    Mode::Keys | Mode::Value => {
                        self.mode = Mode::Keys;
                        self.keys = vec![(name, span)];
                    }
                }
            }
            EventKind::KeySep => self.after_key_sep = true,
            EventKind::KeyValSep => {
                if self.mode == Mode::Keys && !self.keys.is_empty() {
                    self.mode = Mode::Value;
                }
            }
            EventKind::Scalar => {
                if self.mode == Mode::Value {
                    let what = self.scalar_kind(e, &span);
                    self.define_value(what);
                }
            }
            EventKind::ArrayOpen => {
                if let Some(path) = self.value_path("an array") {
                    self.frames.push(Frame::Array(path, 0));
                }
            }
            EventKind::InlineTableOpen => {
                if let Some(path) = self.value_path("an inline table") {
                    self.frames.push(Frame::Table(path));
                }
            }
            EventKind::ArrayClose => {
                if matches!(self.frames.last(), Some(Frame::Array(..))) {
                    self.frames.pop();
                }
            }
            EventKind::InlineTableClose => {
                if self.frames.len() > 1 && matches!(self.frames.last(), Some(Frame::Table(_))) {
                    self.frames.pop();
                }
                self.keys.clear();
                self.mode = Mode::Keys;
            }
            EventKind::ValueSep => match self.frames.last_mut() {
                Some(Frame::Array(_, item)) => *item += 1,
                _ => {
                    self.keys.clear();
                    self.mode = Mode::Keys;
                }
            },
        }
    }

    fn decode_key(&self, e: &Event, span: &Span) -> String {
        let Some(raw) = self.text.get(span.clone()) else {
            return String::new();
        };
        let raw = Raw::new_unchecked(raw, e.encoding(), e.span());
        let mut name = String::new();
        raw.decode_key(&mut name, &mut ());
        name
    }

    fn scalar_kind(&self, e: &Event, span: &Span) -> &'static str {
        let Some(raw) = self.text.get(span.clone()) else {
            return "a value";
        };
        let raw = Raw::new_unchecked(raw, e.encoding(), e.span());
        match raw.decode_scalar(&mut (), &mut ()) {
            ScalarKind::String => "a string",
            ScalarKind::Boolean(_) => "a boolean",
            ScalarKind::DateTime => "a date-time",
            ScalarKind::Float | ScalarKind::Integer(_) => "a number",
        }
    }

    /// The path of the value that opens here: the keys before `=`, or the
    /// next item of the array being read.
    fn value_path(&mut self, what: &'static str) -> Option<Vec<Seg>> {
        if self.mode == Mode::Value {
            return self.define_value(what);
        }
        match self.frames.last() {
            Some(Frame::Array(base, item)) => {
                let mut path = base.clone();
                path.push(Seg::Item(*item));
                Some(path)
            }
            // An array or table where no value can start: its keys, if
            // any, are put where nothing else is.
            _ => Some(vec![Seg::Item(usize::MAX)]),
        }
    }

    /// Records `keys = value` in the current table; the value's path.
    fn define_value(&mut self, what: &'static str) -> Option<Vec<Seg>> {
        self.mode = Mode::Keys;
        let keys = std::mem::take(&mut self.keys);
        let Some(Frame::Table(base)) = self.frames.last() else {
            return None;
        };
        let dotted = format!(
            "the dotted key `{}`",
            keys.iter()
                .map(|(k, _)| shown_key(k))
                .collect::<Vec<_>>()
                .join(".")
        );
        let inline = self.frames.len() > 1;
        let path = self.define(base.clone(), &keys, Role::Value(what), &dotted, inline);
        Some(path)
    }

    fn end_header(&mut self) {
        let Mode::Header { array } = self.mode else {
            return;
        };
        self.mode = Mode::Keys;
        let keys = std::mem::take(&mut self.keys);
        if keys.is_empty() {
            // `[]`: its keys belong to no table.
            self.frames = vec![Frame::Table(vec![Seg::Item(usize::MAX)])];
            return;
        }
        let written = keys
            .iter()
            .map(|(k, _)| shown_key(k))
            .collect::<Vec<_>>()
            .join(".");
        let header = if array {
            format!("[[{written}]]")
        } else {
            format!("[{written}]")
        };
        let mut path = self.define(
            Vec::new(),
            &keys,
            Role::Header(header.clone()),
            &header,
            false,
        );
        if array {
            let count = self.tables_in.entry(path.clone()).or_insert(0);
            *count += 1;
            path.push(Seg::Item(*count - 1));
        }
        self.frames = vec![Frame::Table(path)];
    }

    /// Records each of `keys` under `base`: the last with `role`, the ones
    /// before it as the tables it goes through. Outside inline tables an
    /// array of tables is entered at its last table, as the crate does.
    fn define(
        &mut self,
        base: Vec<Seg>,
        keys: &[(String, Span)],
        role: Role,
        by: &str,
        inline: bool,
    ) -> Vec<Seg> {
        let mut path = base;
        for (i, (name, span)) in keys.iter().enumerate() {
            path.push(Seg::Key(name.clone()));
            let last = i + 1 == keys.len();
            self.defs.push(KeyDef {
                path: path.clone(),
                span: span.clone(),
                role: if last {
                    role.clone()
                } else {
                    Role::Parent(by.to_string())
                },
            });
            if !last
                && !inline
                && let Some(&n) = self.tables_in.get(&path)
            {
                path.push(Seg::Item(n.saturating_sub(1)));
            }
        }
        path
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// `line:col: message` of every error for `text`.
    fn errors(text: &str) -> Vec<String> {
        let mut rep = FileReport::new(Path::new("x.toml"), text);
        assert!(parse(&mut rep, text).is_none(), "no errors in {text:?}");
        rep.finish()
            .into_iter()
            .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
            .collect()
    }

    #[test]
    fn a_value_then_an_array_of_tables_is_one_error_at_the_value() {
        let text = "card = 5\n[[card]]\nid = 1\n[[card]]\nid = 2\n[[card]]\n";
        assert_eq!(
            errors(text),
            [
                "1:1: key `card` is defined 4 times: first here as a number, then as [[card]] at lines 2, 4 and 6"
            ]
        );
    }

    #[test]
    fn a_repeated_key_names_both_places() {
        assert_eq!(
            errors("[deck]\nid = 'a'\ntitle = 'T'\nid = 'b'\n"),
            [
                "2:1: key `deck.id` is defined twice: first here as a string, then as a string at line 4"
            ]
        );
        assert_eq!(
            errors("a = { x = 1, x = [2] }\n"),
            ["1:7: key `a.x` is defined twice: first here as a number, then as an array at line 1"]
        );
    }

    #[test]
    fn a_table_written_twice_is_one_error_not_one_per_key() {
        let text = "[deck]\nid = 1\n[deck]\nid = 2\n[deck]\nid = 3\n";
        assert_eq!(
            errors(text),
            [
                "1:2: key `deck` is defined 3 times: first here as [deck], then as [deck] at lines 3 and 5"
            ]
        );
    }

    #[test]
    fn extending_a_value_names_how() {
        assert_eq!(
            errors("x = 1\n[x.y]\nz = 1\n[x.w]\n"),
            [
                "1:1: key `x` is defined 3 times: first here as a number, then as a table by [x.y] at line 2 and again at line 4"
            ]
        );
        assert_eq!(
            errors("a = { b = 1 }\na.c = 2\n"),
            [
                "1:1: key `a` is defined twice: first here as an inline table, then as a table by the dotted key `a.c` at line 2"
            ]
        );
    }

    #[test]
    fn tables_of_an_array_are_told_apart() {
        // The same key in two [[card]] tables is fine; twice in one is not.
        let text = "[[card]]\nid = 1\n[[card]]\nid = 2\n[card.answer]\n[[card]]\n[card.answer]\nk = 1\n[card.answer]\n";
        assert_eq!(
            errors(text),
            [
                "7:7: key `card.answer` is defined twice: first here as [card.answer], then as [card.answer] at line 9"
            ]
        );
        // Quoted keys are the same keys.
        assert_eq!(
            errors("\"a b\" = 1\n'a b' = 2\n"),
            [
                "1:1: key `\"a b\"` is defined twice: first here as a number, then as a number at line 2"
            ]
        );
    }

    #[test]
    fn an_unclosed_array_is_one_error_at_its_bracket() {
        let text = "a = 1\nb = [1, 2\nc = 3\n[x]\ny = 'z'\n";
        let errs = errors(text);
        assert_eq!(
            errs,
            ["2:5: TOML: unclosed array: this `[` is never closed"]
        );
        let text = "a = 1 1\nb = { c = 1,\nd = 2\n";
        let errs = errors(text);
        assert_eq!(errs.len(), 2, "{errs:?}");
        assert_eq!(
            errs[1],
            "2:5: TOML: unclosed inline table: this `{` is never closed"
        );
        // An inline table left open inside an array leaves the array open
        // too; the table is the one missing its `}`.
        let text = "a = [\n  { b = 1 },\n  { b = 2,\n]\nc = 3\n";
        assert_eq!(
            errors(text),
            ["3:3: TOML: unclosed inline table: this `{` is never closed"]
        );
    }

    #[test]
    fn a_table_above_its_array_of_tables_is_one_error() {
        let text = "[p.a]\nk = 1\n[[p]]\n[p.a]\nk = 2\n[[p]]\n[p.a]\n";
        assert_eq!(
            errors(text),
            [
                "1:2: key `p` is defined 3 times: first here as a table by [p.a], then as [[p]] at lines 3 and 6"
            ]
        );
    }

    #[test]
    fn strings_out_of_step_are_one_error() {
        // The first body's closer is missing: it runs on to the second's
        // opener, and the second body's text is read as TOML.
        let text = "a = '''\none\n\nb = '''\ntwo words\n'''\nc = 1\n";
        assert_eq!(
            errors(text),
            [
                "1:5: TOML: multi-line string not closed: it runs on to line 4, where the next string opens"
            ]
        );
        // A stray delimiter ends the first string early.
        let text = "a = '''\none ''' two\n'''\nb = '''\nthree four\n'''\n";
        let mut rep = FileReport::new(Path::new("x.toml"), text);
        assert!(parse(&mut rep, text).is_none());
        let found = rep.finish();
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].line, found[0].col), (2, 9));
        assert!(
            found[0]
                .hint
                .as_deref()
                .is_some_and(|h| h.starts_with("a `'''` near here is missing or one too many")),
            "{found:?}"
        );
    }

    #[test]
    fn text_left_outside_its_string_is_one_error() {
        let text =
            "a = '''\none\n'''\ntwo words\nthree words\n'''\nfour\n'''\nb = 'x'\n[t\nc = 1\n";
        let mut rep = FileReport::new(Path::new("x.toml"), text);
        assert!(parse(&mut rep, text).is_none());
        let found: Vec<(usize, Option<String>)> =
            rep.finish().into_iter().map(|d| (d.line, d.hint)).collect();
        // The run of text from line 4 is one error; the error on a line of
        // TOML after it is its own.
        assert_eq!(found.len(), 2, "{found:?}");
        assert_eq!(found[0].0, 4);
        assert!(
            found[0]
                .1
                .as_deref()
                .is_some_and(|h| h.starts_with("this looks like text outside its string")),
            "{found:?}"
        );
        assert_eq!(found[1], (10, None));
    }

    #[test]
    fn an_apostrophe_in_a_literal_string_gets_the_readme_hint() {
        let text = "[[card]]\nid = \"euler\"\nfront.en = 'Euler's equation for $\\omega$?'\n";
        let mut rep = FileReport::new(Path::new("x.toml"), text);
        assert!(parse(&mut rep, text).is_none());
        let found = rep.finish();
        assert!(!found.is_empty());
        assert_eq!(found[0].line, 3, "{found:?}");
        let hint = found[0].hint.as_deref().unwrap_or("");
        assert!(hint.contains("cannot hold `'`"), "{found:?}");
        assert!(hint.contains("`Euler's`"), "{found:?}");
        // A quote that is not an apostrophe inside a word gets no such hint.
        let text = "a = 'x' y\n";
        let mut rep = FileReport::new(Path::new("x.toml"), text);
        assert!(parse(&mut rep, text).is_none());
        let found = rep.finish();
        assert!(
            found
                .iter()
                .all(|d| !d.hint.as_deref().unwrap_or("").contains("apostrophe")),
            "{found:?}"
        );
    }

    #[test]
    fn an_unclosed_multiline_string_points_at_its_start() {
        let text = "a = 1\nb = '''\ntext\n\nc = 2\n";
        assert_eq!(
            errors(text),
            ["2:5: TOML: unclosed multi-line string: this `'''` is never closed"]
        );
    }
}
