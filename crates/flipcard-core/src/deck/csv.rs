//! Cards in and out of spreadsheets and other flashcard apps: CSV with the
//! columns front, back, tags.
//!
//! - Export writes a header row `front,back,tags`, texts in the deck's
//!   primary language, tags joined by a space.
//! - Import reads front, back and an optional tags column; a first row naming
//!   the columns (`front`, `back`, `tags`, and optionally `id`) is taken as a
//!   header and may put them in any order. Tags are separated by spaces or
//!   `;`. Card ids come from the `id` column when there is one, else from the
//!   front text (`Why the body frame?` → `why-the-body-frame`), made unique
//!   with `-2`, `-3`…
//! - Texts are checked as `flipcard check` checks them (LaTeX that renders,
//!   no control characters; a tab becomes a space), so the deck written
//!   passes the check. It is written with TOML literal strings, so the
//!   backslashes of LaTeX math survive unchanged.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::io::{Read, Write};

use crate::deck::Deck;
use crate::deck::validate::is_id;

/// The CSV header of an exported deck.
pub(crate) const DECK_COLUMNS: [&str; 3] = ["front", "back", "tags"];

/// Writes a deck's cards as CSV. Returns the number of cards written.
pub fn write_deck_csv(deck: &Deck, out: &mut dyn Write) -> Result<usize, csv::Error> {
    let lang = deck.languages.first().map(String::as_str).unwrap_or("en");
    let mut w = csv::Writer::from_writer(out);
    w.write_record(DECK_COLUMNS)?;
    for card in &deck.cards {
        w.write_record([
            card.front.get(lang),
            card.back.get(lang),
            &card.tags.join(" "),
        ])?;
    }
    w.flush()?;
    Ok(deck.cards.len())
}

/// A card read from CSV, ready to be written as a deck card.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImportedCard {
    pub id: String,
    pub front: String,
    pub back: String,
    pub tags: Vec<String>,
}

/// A problem with one row of the CSV; `line` is the file's line number
/// (1-based) where the row starts.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct RowError {
    pub line: u64,
    pub message: String,
}

#[derive(Debug, Clone, Copy)]
struct Columns {
    front: usize,
    back: usize,
    tags: Option<usize>,
    id: Option<usize>,
    /// Exactly how many fields a row must have.
    width: usize,
}

impl Columns {
    /// No header: front, back and tags (which may be left out).
    const POSITIONAL: Columns = Columns {
        front: 0,
        back: 1,
        tags: Some(2),
        id: None,
        width: 3,
    };

    /// Reads a header row, if `fields` is one.
    fn from_header(fields: &[String]) -> Option<Result<Columns, CardError>> {
        let names: Vec<String> = fields.iter().map(|f| f.trim().to_lowercase()).collect();
        if !names.iter().any(|n| n == "front") || !names.iter().any(|n| n == "back") {
            return None;
        }
        let find = |name: &str| names.iter().position(|n| n == name);
        for (i, n) in names.iter().enumerate() {
            if !["front", "back", "tags", "id"].contains(&n.as_str()) {
                return Some(Err(CardError::UnknownColumn(fields[i].clone())));
            }
            if names[..i].contains(n) {
                return Some(Err(CardError::ColumnTwice(n.clone())));
            }
        }
        Some(Ok(Columns {
            front: find("front")?,
            back: find("back")?,
            tags: find("tags"),
            id: find("id"),
            width: names.len(),
        }))
    }
}

/// Reads cards from CSV. Every bad row is reported (not just the first);
/// any bad row means no cards.
pub fn read_cards_csv(input: impl Read) -> Result<Vec<ImportedCard>, Vec<RowError>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(input);
    let mut errors = Vec::new();
    let mut cards = Vec::new();
    let mut columns: Option<Columns> = None;
    let mut ids_taken: HashSet<String> = HashSet::new();
    let mut explicit_ids: HashSet<String> = HashSet::new();
    let mut next_of: HashMap<String, u64> = HashMap::new();

    for (index, result) in reader.records().enumerate() {
        let record = match result {
            Ok(r) => r,
            Err(e) => {
                let line = e.position().map(|p| p.line()).unwrap_or(index as u64 + 1);
                let message = match e.kind() {
                    csv::ErrorKind::Utf8 { .. } => "not valid UTF-8 text".to_string(),
                    _ => e.to_string(),
                };
                let fatal = matches!(e.kind(), csv::ErrorKind::Io(_));
                errors.push(RowError { line, message });
                if fatal {
                    break;
                }
                continue;
            }
        };
        let line = record
            .position()
            .map(|p| p.line())
            .unwrap_or(index as u64 + 1);
        let mut fields: Vec<String> = record.iter().map(str::to_string).collect();
        if index == 0
            && let Some(first) = fields.first_mut()
            && let Some(stripped) = first.strip_prefix('\u{feff}')
        {
            *first = stripped.to_string();
        }
        let cols = match columns {
            Some(c) => c,
            None => {
                match Columns::from_header(&fields) {
                    Some(Ok(c)) => {
                        columns = Some(c);
                        continue;
                    }
                    Some(Err(e)) => {
                        errors.push(RowError {
                            line,
                            message: e.to_string(),
                        });
                        return Err(errors);
                    }
                    None => {}
                }
                columns = Some(Columns::POSITIONAL);
                Columns::POSITIONAL
            }
        };
        match read_row(
            &fields,
            cols,
            &mut ids_taken,
            &mut explicit_ids,
            &mut next_of,
        ) {
            Ok(card) => cards.push(card),
            Err(e) => errors.push(RowError {
                line,
                message: e.to_string(),
            }),
        }
    }
    if cards.is_empty() && errors.is_empty() {
        errors.push(RowError {
            line: 1,
            message: "no cards: expected rows of front, back and optionally tags".into(),
        });
    }
    if errors.is_empty() {
        Ok(cards)
    } else {
        Err(errors)
    }
}

fn read_row(
    fields: &[String],
    cols: Columns,
    ids_taken: &mut HashSet<String>,
    explicit_ids: &mut HashSet<String>,
    next_of: &mut HashMap<String, u64>,
) -> Result<ImportedCard, CardError> {
    let accepts_two = cols.tags == Some(2) && cols.width == 3 && cols.id.is_none();
    if fields.len() != cols.width && !(accepts_two && fields.len() == 2) {
        return Err(CardError::Columns {
            width: cols.width,
            names: describe(cols),
            found: fields.len(),
        });
    }
    let front = text(fields, cols.front, "front")?;
    let back = text(fields, cols.back, "back")?;
    let tags: Vec<String> = cols
        .tags
        .and_then(|i| fields.get(i))
        .map(|t| {
            t.split(|c: char| c.is_whitespace() || c == ';')
                .filter(|t| !t.is_empty())
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default();
    let id = match cols.id.and_then(|i| fields.get(i)).map(|s| s.trim()) {
        Some(id) if !id.is_empty() => {
            if !is_id(id) {
                return Err(CardError::NotAnId(id.to_string()));
            }
            if !explicit_ids.insert(id.to_string()) {
                return Err(CardError::IdUsed(id.to_string()));
            }
            if !ids_taken.insert(id.to_string()) {
                return Err(CardError::IdTaken(id.to_string()));
            }
            id.to_string()
        }
        _ => unique(slug(&front), ids_taken, next_of),
    };
    Ok(ImportedCard {
        id,
        front,
        back,
        tags,
    })
}

fn describe(cols: Columns) -> String {
    let mut names = vec![""; cols.width];
    names[cols.front] = "front";
    names[cols.back] = "back";
    if let Some(t) = cols.tags {
        names[t] = "tags";
    }
    if let Some(i) = cols.id {
        names[i] = "id";
    }
    names.join(", ")
}

/// The longest text of a card field, in bytes: a card is read on one
/// screen, and every step after the import (the check, the search index,
/// the app) handles each text whole.
pub(crate) const MAX_FIELD_BYTES: usize = 4 << 20;

/// Why a row of the CSV gives no card.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum CardError {
    #[error("unknown column {0:?} in the header (known: front, back, tags, id)")]
    UnknownColumn(String),
    #[error("column {0:?} appears twice in the header")]
    ColumnTwice(String),
    #[error("expected {width} columns ({names}), found {found}")]
    Columns {
        width: usize,
        names: String,
        found: usize,
    },
    #[error("card id {0:?} is not lowercase a-z/0-9 words joined by '-'")]
    NotAnId(String),
    #[error("card id {0:?} is used by an earlier row")]
    IdUsed(String),
    #[error(
        "card id {0:?} was already given to an earlier card made from its front text; give that row an id too"
    )]
    IdTaken(String),
    #[error("{name} is {mib} MiB long; a card's text may be at most {} MiB", MAX_FIELD_BYTES >> 20)]
    TooLong { name: &'static str, mib: usize },
    #[error("{0} is empty")]
    Empty(&'static str),
    #[error("{name} holds the control character U+{code:04X}")]
    Control { name: &'static str, code: u32 },
    #[error("{name}: LaTeX: {message} (at character {at})")]
    Latex {
        name: &'static str,
        message: String,
        at: usize,
    },
}

fn text(fields: &[String], i: usize, name: &'static str) -> Result<String, CardError> {
    if let Some(f) = fields.get(i).filter(|f| f.len() > MAX_FIELD_BYTES) {
        return Err(CardError::TooLong {
            name,
            mib: f.len().div_ceil(1 << 20),
        });
    }
    let t = fields
        .get(i)
        .map(|s| s.replace("\r\n", "\n").replace('\t', " "))
        .unwrap_or_default();
    let t = t.trim().to_string();
    if t.is_empty() {
        return Err(CardError::Empty(name));
    }
    if let Some(c) = t.chars().find(|c| c.is_control() && *c != '\n') {
        return Err(CardError::Control {
            name,
            code: c as u32,
        });
    }
    if let Some(e) = flipcard_text::check(&t).first() {
        let at = t.get(..e.offset).map_or(0, |s| s.chars().count()) + 1;
        return Err(CardError::Latex {
            name,
            message: e.message.to_string(),
            at,
        });
    }
    Ok(t)
}

/// An id from a text: its first few ASCII words, lowercased.
pub fn slug(text: &str) -> String {
    const MAX_LEN: usize = 40;
    let mut out = String::new();
    for word in text
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
    {
        let word = word.to_ascii_lowercase();
        if !out.is_empty() && out.len() + 1 + word.len() > MAX_LEN {
            break;
        }
        if !out.is_empty() {
            out.push('-');
        }
        out.push_str(&word[..word.len().min(MAX_LEN)]);
    }
    if out.is_empty() {
        "card".to_string()
    } else {
        out
    }
}

/// `base`, or `base-2`, `base-3`… when taken. `next` remembers where each
/// base's count stopped, so ten thousand rows of the same front take ten
/// thousand steps, not fifty million.
fn unique(base: String, taken: &mut HashSet<String>, next: &mut HashMap<String, u64>) -> String {
    let n = next.entry(base.clone()).or_insert(1);
    let mut id = if *n == 1 {
        base.clone()
    } else {
        format!("{base}-{n}")
    };
    while taken.contains(&id) {
        *n += 1;
        id = format!("{base}-{n}");
    }
    taken.insert(id.clone());
    id
}

/// A TOML string that reads back as exactly `s`: a literal string when
/// possible (backslashes stay as typed), a plain basic string for a text
/// with an apostrophe and nothing to escape, else a basic string with escapes.
pub(crate) fn toml_string(s: &str) -> String {
    let plain = |c: char| !c.is_control();
    let multiline = s.contains('\n');
    if !s.contains('\'') && s.chars().all(plain) {
        return format!("'{s}'");
    }
    if !multiline && !s.contains(['\\', '"']) && s.chars().all(plain) {
        return format!("\"{s}\"");
    }
    if !s.contains("'''") && s.chars().all(|c| plain(c) || c == '\n') {
        // The newline right after the opening quotes is not part of the text.
        return format!("'''\n{s}'''");
    }
    // A basic string. Line breaks stay real line breaks (in a multi-line
    // string): `flipcard check` refuses an escaped `\n` in a text.
    let mut out = String::from(if multiline { "\"\"\"\n" } else { "\"" });
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' if multiline => out.push('\n'),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push_str(if multiline { "\"\"\"" } else { "\"" });
    out
}

/// A TOML key: bare when it can be.
fn toml_key(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        s.to_string()
    } else {
        toml_string(s)
    }
}

/// What goes into the deck file besides the cards.
#[derive(Debug, Clone)]
pub struct DeckHeader {
    pub id: String,
    pub title: String,
    /// The one language the texts are in.
    pub lang: String,
    /// Where the cards came from, for a comment at the top.
    pub source: String,
}

/// The deck file for `cards`.
pub fn deck_toml(header: &DeckHeader, cards: &[ImportedCard]) -> String {
    let lang = toml_key(&header.lang);
    let text = |s: &str| format!("{{ {lang} = {} }}", toml_string(s));
    let mut out = String::new();
    let source = header.source.replace(['\n', '\r'], " ");
    let _ = writeln!(out, "# Made by `flipcard import` from {source}.");
    out.push_str("\n[deck]\n");
    let _ = writeln!(out, "id = {}", toml_string(&header.id));
    let _ = writeln!(out, "title = {}", text(&header.title));
    let _ = writeln!(out, "languages = [{}]", toml_string(&header.lang));
    for card in cards {
        out.push_str("\n[[card]]\n");
        let _ = writeln!(out, "id = {}", toml_string(&card.id));
        let _ = writeln!(out, "front = {}", text(&card.front));
        let _ = writeln!(out, "back = {}", text(&card.back));
        if !card.tags.is_empty() {
            let tags: Vec<String> = card.tags.iter().map(|t| toml_string(t)).collect();
            let _ = writeln!(out, "tags = [{}]", tags.join(", "));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(csv: &str) -> Result<Vec<ImportedCard>, Vec<RowError>> {
        read_cards_csv(csv.as_bytes())
    }

    #[test]
    fn toml_strings_read_back_exactly() {
        let samples = [
            r"plain",
            r"$I_1\dot\omega_1 = (I_2-I_3)\,\omega_2\omega_3$",
            "it's a \\frac{1}{2}",
            "two\nlines with \\theta",
            "ends with a quote'",
            "ends with two quotes''",
            "has ''' three quotes\nand \\n a newline",
            "quote \" and 'single' \\ back",
            "\nstarts with a newline",
            "tab\tinside, with 'quotes' and '''",
        ];
        for s in samples {
            let doc = format!("x = {}\n", toml_string(s));
            let v: toml::Table = toml::from_str(&doc).unwrap_or_else(|e| panic!("{doc}: {e}"));
            assert_eq!(v["x"].as_str(), Some(s), "{doc}");
        }
        assert_eq!(toml_string(r"\omega"), r"'\omega'");
        assert_eq!(toml_string("it's"), "\"it's\"");
    }

    #[test]
    fn positional_rows_without_header() {
        let cards = read("What is $\\omega$?,Angular velocity,kinematics basics\nQ2,A2\n").unwrap();
        assert_eq!(cards.len(), 2);
        assert_eq!(cards[0].front, "What is $\\omega$?");
        assert_eq!(cards[0].id, "what-is-omega");
        assert_eq!(cards[0].tags, ["kinematics", "basics"]);
        assert_eq!(cards[1].id, "q2");
        assert!(cards[1].tags.is_empty());
    }

    #[test]
    fn header_may_reorder_columns_and_give_ids() {
        let cards = read("Tags,ID,Back,Front\na;b,my-card,the back,the front\n").unwrap();
        assert_eq!(
            cards,
            [ImportedCard {
                id: "my-card".into(),
                front: "the front".into(),
                back: "the back".into(),
                tags: vec!["a".into(), "b".into()],
            }]
        );
    }

    #[test]
    fn tabs_become_spaces_and_crlf_line_breaks_newlines() {
        let cards = read("\"a\tb\",\"one\r\ntwo\"\r\n").unwrap();
        assert_eq!(cards[0].front, "a b");
        assert_eq!(cards[0].back, "one\ntwo");
    }

    #[test]
    fn same_front_gets_distinct_ids() {
        let cards = read("Same?,one\nSame?,two\nSame?,three\n").unwrap();
        let ids: Vec<&str> = cards.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["same", "same-2", "same-3"]);
    }

    #[test]
    fn every_bad_row_is_reported_with_its_line() {
        let csv = "front,back,tags\n\
                   ok,fine,\n\
                   ,missing front,\n\
                   only one field\n\
                   a,b,c,d\n\
                   \"multi\nline\",\"\",x\n";
        let errors = read(csv).unwrap_err();
        let got: Vec<(u64, &str)> = errors
            .iter()
            .map(|e| (e.line, e.message.as_str()))
            .collect();
        assert_eq!(
            got,
            [
                (3, "front is empty"),
                (4, "expected 3 columns (front, back, tags), found 1"),
                (5, "expected 3 columns (front, back, tags), found 4"),
                (6, "back is empty"),
            ]
        );
        assert_eq!(errors[0].to_string(), "line 3: front is empty");
    }

    #[test]
    fn bad_ids_and_headers_are_refused() {
        let e = read("front,back,id\na,b,Bad Id\nc,d,x\ne,f,x\n").unwrap_err();
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].line, 2);
        assert!(e[0].message.contains("\"Bad Id\""), "{}", e[0].message);
        assert_eq!(e[1].line, 4);
        assert!(e[1].message.contains("earlier row"), "{}", e[1].message);

        let e = read("front,back,notes\n").unwrap_err();
        assert!(e[0].message.contains("unknown column"), "{}", e[0].message);

        let e = read("").unwrap_err();
        assert!(e[0].message.contains("no cards"));

        let e = read_cards_csv(&b"ok,fine\n\xff\xfe,bad\n"[..]).unwrap_err();
        assert_eq!(e[0].line, 2);
        assert!(e[0].message.contains("UTF-8"), "{}", e[0].message);

        let e = read("fine,ok\nCosts $5,ok\n").unwrap_err();
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].line, 2);
        assert!(
            e[0].message.starts_with("front: LaTeX:"),
            "{}",
            e[0].message
        );
        assert!(
            e[0].message.ends_with("(at character 7)"),
            "{}",
            e[0].message
        );
        assert!(read("Costs \\$5,ok\n").is_ok(), "an escaped dollar is text");

        let e = read("a\u{7}b,c\n").unwrap_err();
        assert!(e[0].message.contains("U+0007"), "{}", e[0].message);
    }

    #[test]
    fn ids_follow_the_deck_format() {
        assert!(is_id("middle-axis"));
        assert!(is_id("a1"));
        for bad in ["", "-a", "a-", "a--b", "A", "a_b", "é"] {
            assert!(!is_id(bad), "{bad}");
        }
        assert_eq!(slug("Why the body frame?"), "why-the-body-frame");
        assert_eq!(slug("$$\\,$$"), "card");
        assert!(slug(&"word ".repeat(30)).len() <= 40);
        assert!(is_id(&slug(
            "A very long front text with many words in it, beyond forty"
        )));
    }

    #[test]
    fn deck_toml_parses_and_keeps_texts() {
        let cards = read("front,back,tags\n\"It's $\\frac{1}{2}$\",\"two\nlines\",a b\n").unwrap();
        let header = DeckHeader {
            id: "imported".into(),
            title: "My 'cards'".into(),
            lang: "hi-Latn".into(),
            source: "cards.csv".into(),
        };
        let doc = deck_toml(&header, &cards);
        let v: toml::Table = toml::from_str(&doc).unwrap();
        assert_eq!(v["deck"]["id"].as_str(), Some("imported"));
        assert_eq!(v["deck"]["title"]["hi-Latn"].as_str(), Some("My 'cards'"));
        let card = &v["card"][0];
        assert_eq!(
            card["front"]["hi-Latn"].as_str(),
            Some("It's $\\frac{1}{2}$")
        );
        assert_eq!(card["back"]["hi-Latn"].as_str(), Some("two\nlines"));
        assert_eq!(card["tags"][1].as_str(), Some("b"));
    }
}
