//! Writing an Anki package (`flipcard export --apkg FILE`): decks as notes
//! of Anki's stock note types (Basic, Basic (and reversed card), Basic
//! (type in the answer), Cloze), their tags, each item's state as its
//! card's type, queue, due date and interval (suspended and buried kept),
//! and the review log as revlog rows.
//!
//! The package is the legacy layout every Anki since 2.1 imports: a zip of
//! `collection.anki21` (SQLite, schema 11, note types and decks as JSON in
//! `col`) and an empty `media` map. The collection's day 0 (`crt`) is the
//! start of the day the export is made (04:00 UTC, Anki's default
//! rollover), so a due date is a day number Anki reads back as the same
//! date.
//!
//! Text: `$…$` becomes MathJax `\(…\)`, `$$…$$` `\[…\]`, `\$` a dollar;
//! `<`, `>` and `&` are escaped; line breaks are `<br>`; `**strong**` and
//! `*emphasis*` (the reader's markup, what an import made of Anki's bold
//! and italic) are `<b>` and `<i>`, a `*` that opens or closes nothing
//! staying a `*`; cloze deletions are kept as written (inside math too:
//! Anki's MathJax reads them there).

use std::collections::{HashMap, HashSet};
use std::io::Write as _;

use chrono::{DateTime, TimeDelta, Utc};
use rusqlite::{Connection, params};

use crate::deck::model::{Card, CardKind, Deck};
use crate::sched::{Direction, ItemKey, ReviewKind, State};
use crate::store::{Store, StoreError};

/// The stock note types, as Anki's legacy JSON (ids fixed).
const MODELS: &str = include_str!("anki_models.json");
/// The collection's `conf`, and the JSON of a deck and of its options.
const COLLECTION: &str = include_str!("anki_collection.json");

const BASIC: i64 = 1_700_000_000_001;
const REVERSED: i64 = 1_700_000_000_002;
const TYPED: i64 = 1_700_000_000_003;
const CLOZE: i64 = 1_700_000_000_004;

#[derive(Debug, thiserror::Error)]
pub enum ApkgError {
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("cannot build the Anki collection: {0}")]
    Sql(#[from] rusqlite::Error),
    #[error("cannot build the Anki package: {0}")]
    Zip(#[from] zip::result::ZipError),
    #[error("cannot build the Anki package: {0}")]
    Io(#[from] std::io::Error),
}

/// What a package holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ApkgSummary {
    pub decks: usize,
    pub notes: usize,
    pub cards: usize,
    pub reviews: usize,
}

/// The package of `decks` with their states and review history from
/// `store`, as the bytes of the `.apkg` file. `lang` is the language whose
/// text the notes take.
pub fn write_apkg(
    decks: &[&Deck],
    store: &Store,
    lang: &str,
    now: DateTime<Utc>,
) -> Result<(Vec<u8>, ApkgSummary), ApkgError> {
    let mut summary = ApkgSummary::default();
    let crt = day_start(now);
    let mut conn = Connection::open_in_memory()?;
    conn.execute_batch(SCHEMA_11)?;
    let collection: serde_json::Value =
        serde_json::from_str(COLLECTION).expect("anki_collection.json is JSON");
    let models: serde_json::Value = serde_json::from_str(MODELS).expect("anki_models.json is JSON");

    // Ids: Anki's are times in milliseconds; these count up from now, one
    // per object, so they are unique within the package.
    let mut next = now.timestamp_millis();
    let mut id = || {
        next += 1;
        next
    };
    let mut deck_json = serde_json::Map::new();
    deck_json.insert("1".into(), collection["deck"].clone());
    let statuses = store.statuses()?;
    let states: HashMap<ItemKey, crate::store::CachedState> = store
        .cached_states()?
        .into_iter()
        .map(|s| (s.key.clone(), s))
        .collect();
    let mut revlog_ids: HashSet<i64> = HashSet::new();
    let mut new_position = 0i64;
    for deck in decks {
        summary.decks += 1;
        let did = id();
        let mut d = collection["deck"].clone();
        d["id"] = did.into();
        d["name"] = deck.title.get(lang).replace('\u{1f}', " ").into();
        deck_json.insert(did.to_string(), d);
        for card in &deck.cards {
            let nid = id();
            summary.notes += 1;
            let (mid, fields) = note_fields(card, lang);
            let sort = fields.first().cloned().unwrap_or_default();
            let flds = fields.join("\u{1f}");
            let tags = if card.tags.is_empty() {
                String::new()
            } else {
                format!(" {} ", card.tags.join(" "))
            };
            conn.execute(
                "INSERT INTO notes (id, guid, mid, mod, usn, tags, flds, sfld, csum, flags, data) \
                 VALUES (?1, ?2, ?3, ?4, -1, ?5, ?6, ?7, ?8, 0, '')",
                params![
                    nid,
                    format!("flipcard/{}/{}", deck.id, card.id),
                    mid,
                    now.timestamp(),
                    tags,
                    flds,
                    sort,
                    checksum(&sort),
                ],
            )?;
            for (ord, direction) in card_directions(card) {
                let cid = id();
                summary.cards += 1;
                let key = ItemKey {
                    deck: deck.id.clone(),
                    card: card.id.clone(),
                    direction,
                };
                let status = statuses.get(&key).copied().unwrap_or_default();
                let state = states.get(&key);
                let sched = match state {
                    Some(s) if s.state.state != State::New => schedule(s, crt),
                    _ => {
                        new_position += 1;
                        Schedule {
                            kind: 0,
                            due: new_position,
                            ivl: 0,
                            data: "{}".into(),
                        }
                    }
                };
                let queue = if status.suspended {
                    -1
                } else if status.buried(now) {
                    -3
                } else {
                    match sched.kind {
                        3 => 1,
                        k => k,
                    }
                };
                // A learning card stays in the learning queue with its due
                // time in seconds, however far off (Anki shows it then).
                let due = sched.due;
                let (reps, lapses) = state.map_or((0, 0), |s| (s.reps, s.lapses));
                conn.execute(
                    "INSERT INTO cards (id, nid, did, ord, mod, usn, type, queue, due, ivl, factor, \
                     reps, lapses, left, odue, odid, flags, data) \
                     VALUES (?1, ?2, ?3, ?4, ?5, -1, ?6, ?7, ?8, ?9, ?10, ?11, ?12, 0, 0, 0, 0, ?13)",
                    params![
                        cid,
                        nid,
                        did,
                        ord,
                        now.timestamp(),
                        sched.kind,
                        queue,
                        due,
                        sched.ivl,
                        if sched.kind == 0 { 0 } else { 2500 },
                        reps,
                        lapses,
                        sched.data,
                    ],
                )?;
                // The answers, live ones, in time order.
                let mut last_ivl = 0i64;
                for l in store.history(&key)? {
                    if l.undone {
                        continue;
                    }
                    let r = &l.record;
                    let mut rid = r.reviewed_at.timestamp_millis();
                    while !revlog_ids.insert(rid) {
                        rid += 1;
                    }
                    let ivl = if r.after.state == State::Review {
                        r.scheduled_days.max(1)
                    } else {
                        // Seconds, negative: a learning step.
                        -(r.after.due - r.reviewed_at)
                            .num_seconds()
                            .clamp(1, 86_400 * 365)
                    };
                    let kind = match r.kind {
                        ReviewKind::Learn => 0,
                        ReviewKind::Review => 1,
                        ReviewKind::Relearn => 2,
                        ReviewKind::Cram => 3,
                    };
                    conn.execute(
                        "INSERT INTO revlog (id, cid, usn, ease, ivl, lastIvl, factor, time, type) \
                         VALUES (?1, ?2, -1, ?3, ?4, ?5, ?6, ?7, ?8)",
                        params![
                            rid,
                            cid,
                            r.rating as i64,
                            ivl,
                            last_ivl,
                            r.after
                                .difficulty
                                .map_or(0, |d| (d * 100.0).round() as i64 + 100),
                            r.duration_ms.clamp(0, 3_600_000),
                            kind,
                        ],
                    )?;
                    if kind != 3 {
                        last_ivl = ivl;
                    }
                    summary.reviews += 1;
                }
            }
        }
    }
    let mut dconf = serde_json::Map::new();
    dconf.insert("1".into(), collection["dconf"].clone());
    conn.execute(
        "INSERT INTO col (id, crt, mod, scm, ver, dty, usn, ls, conf, models, decks, dconf, tags) \
         VALUES (1, ?1, ?2, ?2, 11, 0, 0, 0, ?3, ?4, ?5, ?6, '{}')",
        params![
            crt,
            now.timestamp_millis(),
            collection["conf"].to_string(),
            models.to_string(),
            serde_json::Value::Object(deck_json).to_string(),
            serde_json::Value::Object(dconf).to_string(),
        ],
    )?;
    let db = conn.serialize(rusqlite::MAIN_DB)?.to_vec();
    drop(conn);

    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    zip.start_file("collection.anki21", options)?;
    zip.write_all(&db)?;
    zip.start_file("media", options)?;
    zip.write_all(b"{}")?;
    let bytes = zip.finish()?.into_inner();
    Ok((bytes, summary))
}

/// A card's schedule in Anki's terms.
struct Schedule {
    /// 0 new, 1 learning, 2 review, 3 relearning.
    kind: i64,
    /// Review: a day number from `crt`; learning: seconds; new: position.
    due: i64,
    ivl: i64,
    /// The FSRS memory state, as Anki keeps it in `cards.data`.
    data: String,
}

fn schedule(s: &crate::store::CachedState, crt: i64) -> Schedule {
    let st = &s.state;
    let due_secs = st.due.timestamp();
    let kind = match st.state {
        State::New => 0,
        State::Learning => 1,
        State::Review => 2,
        State::Relearning => 3,
    };
    let ivl = st
        .last_review
        .map_or(0, |l| {
            ((st.due - l).num_seconds() as f64 / 86_400.0).round() as i64
        })
        .max(i64::from(kind == 2));
    let due = if kind == 2 {
        (due_secs - crt).div_euclid(86_400)
    } else {
        due_secs
    };
    let mut data = serde_json::Map::new();
    if let (Some(sv), Some(dv)) = (st.stability, st.difficulty) {
        data.insert("s".into(), round4(sv).into());
        data.insert("d".into(), round4(dv).into());
    }
    if let Some(l) = st.last_review {
        data.insert("lrt".into(), l.timestamp().into());
    }
    Schedule {
        kind,
        due,
        ivl,
        data: serde_json::Value::Object(data).to_string(),
    }
}

fn round4(x: f64) -> f64 {
    (x * 10_000.0).round() / 10_000.0
}

/// The start of the day of `now` as Anki counts days by default: 04:00
/// UTC, in seconds.
fn day_start(now: DateTime<Utc>) -> i64 {
    let shifted = now - TimeDelta::hours(4);
    shifted.timestamp().div_euclid(86_400) * 86_400 + 4 * 3_600
}

/// A card's note type and fields (HTML).
fn note_fields(card: &Card, lang: &str) -> (i64, Vec<String>) {
    let front = to_html(card.front.get(lang));
    let back = to_html(card.back.get(lang));
    match card.kind {
        CardKind::Reversed => (REVERSED, vec![front, back]),
        CardKind::Typed => (TYPED, vec![front, back]),
        CardKind::Cloze => (CLOZE, vec![front, back]),
        CardKind::Basic | CardKind::Formula => (BASIC, vec![front, back]),
    }
}

/// Each card of a note: its `ord` and the item it is.
fn card_directions(card: &Card) -> Vec<(i64, Direction)> {
    match card.kind {
        CardKind::Reversed => vec![(0, Direction::Forward), (1, Direction::Backward)],
        CardKind::Cloze => card
            .cloze_numbers()
            .into_iter()
            .map(|n| (i64::from(n) - 1, Direction::Cloze(n)))
            .collect(),
        _ => vec![(0, Direction::Forward)],
    }
}

/// flipcard text as Anki HTML: math as MathJax, `<>&` escaped, lines as
/// `<br>`, bold and italic as `<b>` and `<i>`.
pub(crate) fn to_html(text: &str) -> String {
    emphasis(&html_pieces(text))
}

/// What [`to_html`] writes, before bold and italic: the HTML of each run
/// of text outside math (`Ok`) and of each formula with its delimiters
/// (`Err`), in order.
fn html_pieces(text: &str) -> Vec<Result<String, String>> {
    let mut pieces: Vec<Result<String, String>> = Vec::new();
    let mut out = String::with_capacity(text.len() + 16);
    let b = text.as_bytes();
    let mut i = 0;
    // Open math: its closer.
    let mut math: Option<&str> = None;
    let mut plain_from = 0;
    let flush = |out: &mut String, s: &str| {
        for c in s.chars() {
            match c {
                '<' => out.push_str("&lt;"),
                '>' => out.push_str("&gt;"),
                '&' => out.push_str("&amp;"),
                '\n' => out.push_str("<br>"),
                c => out.push(c),
            }
        }
    };
    while i < b.len() {
        match b[i] {
            b'\\' if b.get(i + 1) == Some(&b'$') => {
                flush(&mut out, &text[plain_from..i]);
                out.push('$');
                i += 2;
                plain_from = i;
            }
            b'\\' => i += 2,
            b'$' => {
                flush(&mut out, &text[plain_from..i]);
                let display = b.get(i + 1) == Some(&b'$');
                match math {
                    None => {
                        pieces.push(Ok(std::mem::take(&mut out)));
                        out.push_str(if display { "\\[" } else { "\\(" });
                        math = Some(if display { "\\]" } else { "\\)" });
                    }
                    Some(close) => {
                        out.push_str(close);
                        pieces.push(Err(std::mem::take(&mut out)));
                        math = None;
                    }
                }
                i += if display { 2 } else { 1 };
                plain_from = i;
            }
            _ => i += 1,
        }
    }
    flush(&mut out, &text[plain_from.min(text.len())..]);
    match math {
        Some(close) => {
            out.push_str(close);
            pieces.push(Err(out));
        }
        None => pieces.push(Ok(out)),
    }
    pieces
}

/// The pieces of [`html_pieces`] joined, `**…**` as `<b>…</b>` and `*…*`
/// as `<i>…</i>` across the text outside math (a formula may sit inside
/// them), as the reader's markup pairs them: a run of stars opens when a
/// character that is not a space follows it, closes when one precedes it,
/// and closes the nearest open run of its length (a run of three is strong
/// and emphasis); a star that opens or closes nothing is written as it is.
fn emphasis(pieces: &[Result<String, String>]) -> String {
    // The stars of the text outside math: (piece, byte, length), each
    // with whether it may open and close.
    struct Run {
        piece: usize,
        at: usize,
        len: usize,
        open: bool,
        close: bool,
    }
    let mut runs: Vec<Run> = Vec::new();
    let char_at = |p: usize, at: usize, before: bool| -> Option<char> {
        let Ok(s) = &pieces[p] else { return None };
        if before {
            s[..at].chars().next_back()
        } else {
            s[at..].chars().next()
        }
    };
    for (p, piece) in pieces.iter().enumerate() {
        let Ok(s) = piece else { continue };
        let b = s.as_bytes();
        let mut i = 0;
        while i < b.len() {
            if b[i] != b'*' {
                i += 1;
                continue;
            }
            let start = i;
            while i < b.len() && b[i] == b'*' {
                i += 1;
            }
            // Beside math, the formula is the neighbour: not a space.
            let before = if start == 0 && p > 0 {
                Some('x')
            } else {
                char_at(p, start, true)
            };
            let after = if i == b.len() && p + 1 < pieces.len() {
                Some('x')
            } else {
                char_at(p, i, false)
            };
            let len = i - start;
            if len <= 3 {
                runs.push(Run {
                    piece: p,
                    at: start,
                    len,
                    open: after.is_some_and(|c| !c.is_whitespace()),
                    close: before.is_some_and(|c| !c.is_whitespace()),
                });
            }
        }
    }
    // Each closer takes the nearest opener of its length; what lies
    // between stays open or not as it was paired.
    let mut pair: Vec<Option<(usize, bool)>> = vec![None; runs.len()];
    let mut open: Vec<usize> = Vec::new();
    for r in 0..runs.len() {
        if runs[r].close
            && let Some(k) = open.iter().rposition(|&o| runs[o].len == runs[r].len)
        {
            let o = open[k];
            open.truncate(k);
            pair[o] = Some((r, true));
            pair[r] = Some((o, false));
            continue;
        }
        if runs[r].open {
            open.push(r);
        }
    }
    let tag = |len: usize, opening: bool| -> &'static str {
        match (len, opening) {
            (1, true) => "<i>",
            (1, false) => "</i>",
            (2, true) => "<b>",
            (2, false) => "</b>",
            (_, true) => "<b><i>",
            (_, false) => "</i></b>",
        }
    };
    let mut out = String::new();
    let mut next = runs.iter().zip(&pair).peekable();
    for (p, piece) in pieces.iter().enumerate() {
        let s = match piece {
            Ok(s) | Err(s) => s,
        };
        let mut from = 0;
        while let Some((run, paired)) = next.peek().filter(|(r, _)| r.piece == p) {
            out.push_str(&s[from..run.at]);
            match paired {
                Some((_, opening)) => out.push_str(tag(run.len, *opening)),
                None => out.push_str(&s[run.at..run.at + run.len]),
            }
            from = run.at + run.len;
            next.next();
        }
        out.push_str(&s[from..]);
    }
    out
}

/// Anki's note checksum: the first 8 hex digits of the SHA-1 of the sort
/// field's text (without HTML), as a number. Anki recomputes it on import;
/// this one only has to be a number.
fn checksum(sort: &str) -> i64 {
    // FNV-1a, 32 bits: Anki uses the field only to find duplicates fast.
    let mut h: u32 = 0x811c_9dc5;
    for b in sort.bytes() {
        h ^= u32::from(b);
        h = h.wrapping_mul(0x0100_0193);
    }
    i64::from(h)
}

/// The legacy collection's tables (schema 11), as Anki writes them.
const SCHEMA_11: &str = "
CREATE TABLE col (id integer PRIMARY KEY, crt integer NOT NULL, mod integer NOT NULL,
  scm integer NOT NULL, ver integer NOT NULL, dty integer NOT NULL, usn integer NOT NULL,
  ls integer NOT NULL, conf text NOT NULL, models text NOT NULL, decks text NOT NULL,
  dconf text NOT NULL, tags text NOT NULL);
CREATE TABLE notes (id integer PRIMARY KEY, guid text NOT NULL, mid integer NOT NULL,
  mod integer NOT NULL, usn integer NOT NULL, tags text NOT NULL, flds text NOT NULL,
  sfld integer NOT NULL, csum integer NOT NULL, flags integer NOT NULL, data text NOT NULL);
CREATE TABLE cards (id integer PRIMARY KEY, nid integer NOT NULL, did integer NOT NULL,
  ord integer NOT NULL, mod integer NOT NULL, usn integer NOT NULL, type integer NOT NULL,
  queue integer NOT NULL, due integer NOT NULL, ivl integer NOT NULL, factor integer NOT NULL,
  reps integer NOT NULL, lapses integer NOT NULL, left integer NOT NULL, odue integer NOT NULL,
  odid integer NOT NULL, flags integer NOT NULL, data text NOT NULL);
CREATE TABLE revlog (id integer PRIMARY KEY, cid integer NOT NULL, usn integer NOT NULL,
  ease integer NOT NULL, ivl integer NOT NULL, lastIvl integer NOT NULL,
  factor integer NOT NULL, time integer NOT NULL, type integer NOT NULL);
CREATE TABLE graves (usn integer NOT NULL, oid integer NOT NULL, type integer NOT NULL);
CREATE INDEX ix_notes_usn ON notes (usn);
CREATE INDEX ix_cards_usn ON cards (usn);
CREATE INDEX ix_revlog_usn ON revlog (usn);
CREATE INDEX ix_cards_nid ON cards (nid);
CREATE INDEX ix_cards_sched ON cards (did, queue, due);
CREATE INDEX ix_revlog_cid ON revlog (cid);
CREATE INDEX ix_notes_csum ON notes (csum);
";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_becomes_anki_html() {
        assert_eq!(
            to_html("a < b & $x^2$ costs \\$5\n$$E = mc^2$$"),
            "a &lt; b &amp; \\(x^2\\) costs $5<br>\\[E = mc^2\\]"
        );
        assert_eq!(to_html("$F = -{{c1::k}} x$"), "\\(F = -{{c1::k}} x\\)");
    }

    #[test]
    fn bold_and_italic_become_anki_html() {
        assert_eq!(
            to_html("**c** = 3 and *half* an *ångström*"),
            "<b>c</b> = 3 and <i>half</i> an <i>ångström</i>"
        );
        // Around math, and math left alone inside.
        assert_eq!(
            to_html("**$x^2$ grows** but $a*b*c$"),
            "<b>\\(x^2\\) grows</b> but \\(a*b*c\\)"
        );
        assert_eq!(to_html("***both***"), "<b><i>both</i></b>");
        // A star that opens or closes nothing stays a star.
        for plain in ["a * b", "2*", "**a*", "* x *", "*"] {
            assert!(!to_html(plain).contains('<'), "{plain}: {}", to_html(plain));
        }
        assert_eq!(to_html("**a < b**"), "<b>a &lt; b</b>");
        assert_eq!(to_html("*a\nb*"), "<i>a<br>b</i>");
    }

    proptest::proptest! {
        /// Any text: every tag written is closed, in order, and with the
        /// tags taken out the text is the one without the markup's pairs
        /// (no character is lost or added).
        #[test]
        fn emphasis_tags_nest_and_lose_nothing(
            s in "([a-z ]|\\*|\\*\\*|\\$|<|\n){0,40}",
        ) {
            let html = to_html(&s);
            let mut stack = Vec::new();
            let mut rest = html.as_str();
            while let Some(i) = rest.find(['<']) {
                rest = &rest[i..];
                let tag = ["<b>", "</b>", "<i>", "</i>", "<br>"]
                    .into_iter()
                    .find(|t| rest.starts_with(t));
                let Some(tag) = tag else {
                    proptest::prop_assert!(false, "{:?} in {:?}", rest, html);
                    break;
                };
                match tag {
                    "<b>" | "<i>" => stack.push(tag),
                    "</b>" => proptest::prop_assert_eq!(stack.pop(), Some("<b>")),
                    "</i>" => proptest::prop_assert_eq!(stack.pop(), Some("<i>")),
                    _ => {}
                }
                rest = &rest[tag.len()..];
            }
            proptest::prop_assert!(stack.is_empty(), "{:?}", html);
            let stars = |t: &str| t.matches('*').count();
            let tags = html.matches("<b>").count() * 4 + html.matches("<i>").count() * 2;
            proptest::prop_assert_eq!(stars(&html) + tags, stars(&s), "{:?}", html);
        }
    }

    #[test]
    fn the_day_starts_at_four_utc() {
        let t = |s: &str| s.parse::<DateTime<Utc>>().unwrap();
        assert_eq!(day_start(t("2026-01-05T12:00:00Z")), 1_767_585_600);
        assert_eq!(day_start(t("2026-01-06T03:59:59Z")), 1_767_585_600);
        assert_eq!(day_start(t("2026-01-06T04:00:00Z")), 1_767_585_600 + 86_400);
    }
}
