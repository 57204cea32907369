//! Reading an Anki package (`.apkg`, `.colpkg`): its Basic, Basic-and-
//! reversed and Cloze notes become flipcard decks (TOML text), its review
//! history (revlog) becomes reviews to merge into the log.
//!
//! Both layouts are read: the legacy `collection.anki2` / `collection.anki21`
//! (SQLite, schema 11, note types and decks as JSON in `col`) and the
//! current `collection.anki21b` (the same SQLite compressed with zstd, schema
//! 18, note types and decks in their own tables). A package holding several
//! takes the newest, since the older one is then a stub asking to update.
//!
//! Nothing is trusted: the archive and the collection inside are size
//! limited (a zip bomb is refused before it is unpacked); the collection is
//! opened in memory (no scratch file to leave behind, even when the import
//! is killed), read only, its tables must be plain tables (a view can run
//! for ever), SQLite's work on it is bounded (a progress handler stops a
//! statement past a budget of steps per byte), and it is checked with
//! `PRAGMA quick_check`; a note type that is not one of the three is an
//! error naming it; answers must be dated from 1970 to a day after this
//! machine's clock; field text is converted in one pass (linear time) and
//! may hold at most [`MAX_FIELD_BYTES`] once converted.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::io::Read;
use std::path::{Path, PathBuf};

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use chrono::{DateTime, Utc};
use rusqlite::limits::Limit;
use rusqlite::{Connection, OpenFlags, OptionalExtension};

use crate::deck::cloze::MAX_NUMBER;
use crate::deck::csv::{MAX_FIELD_BYTES, slug, toml_string};
use crate::sched::clock::check_event_time;
use crate::sched::{Direction, ItemKey, Rating};
use crate::store::merge::IncomingReview;

/// The largest collection unpacked (compressed size does not matter).
pub(crate) const MAX_COLLECTION_BYTES: u64 = 512 << 20;

#[derive(Debug, thiserror::Error)]
pub enum AnkiError {
    #[error("cannot read {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path} is not an Anki package (not a zip archive: {detail})")]
    NotZip { path: PathBuf, detail: String },
    #[error(
        "{path} holds no Anki collection (no collection.anki21b, collection.anki21 or collection.anki2)"
    )]
    NoCollection { path: PathBuf },
    #[error(
        "{path}: {entry} unpacks to more than {limit} MiB; refusing it as a likely zip bomb",
        limit = MAX_COLLECTION_BYTES >> 20
    )]
    TooLarge { path: PathBuf, entry: String },
    #[error("{path}: the collection {entry} is damaged: {detail}")]
    Damaged {
        path: PathBuf,
        entry: String,
        detail: String,
    },
    #[error(
        "{path}: note type {name:?} ({fields} fields, {templates} card types) is not Basic, Basic (and reversed card) or Cloze; nothing imported"
    )]
    UnknownNoteType {
        path: PathBuf,
        name: String,
        fields: usize,
        templates: usize,
    },
    #[error("{path}: the collection has no notes to import")]
    Empty { path: PathBuf },
    #[error("{path}: revlog row {id}: the answer time {detail}; nothing imported")]
    BadAnswer {
        path: PathBuf,
        id: i64,
        detail: String,
    },
    #[error(
        "{path}: note {note}: field {field} is {mib} MiB of text; a card's text may be at most {limit} MiB; nothing imported",
        limit = MAX_FIELD_BYTES >> 20
    )]
    FieldTooLarge {
        path: PathBuf,
        note: i64,
        field: usize,
        mib: usize,
    },
}

/// What a note type is to flipcard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Basic,
    Reversed,
    Cloze,
}

/// One deck made from the package.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedDeck {
    pub id: String,
    /// The Anki deck's name (levels joined by `::`).
    pub name: String,
    /// The deck file's text.
    pub toml: String,
    pub cards: usize,
}

/// Everything taken from a package.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AnkiImport {
    /// Which collection file was read.
    pub entry: String,
    pub decks: Vec<ImportedDeck>,
    pub notes: usize,
    /// Media files in the package, and references to them in the notes:
    /// none is imported.
    pub media_files: usize,
    pub media_refs: usize,
    /// Reviews to merge, in time order.
    pub reviews: Vec<IncomingReview>,
    /// Revlog rows left out: manual reschedules, rows of cards that are
    /// gone, and the history of cloze deletions (the log names no cloze
    /// items yet).
    pub reviews_skipped: usize,
    /// Cloze notes left out (read with `with_cloze` false).
    pub cloze_left_out: usize,
}

/// A card of a note, as the review log names it.
struct CardRef {
    deck: String,
    card: String,
    direction: Option<Direction>,
}

/// Reads a package. With `with_cloze` false, Cloze notes are counted but
/// left out (for decks that have no cloze cards).
/// `now` is this machine's clock: an answer in the revlog dated after it
/// (by more than a day) or before 1970 is refused.
pub fn read_package(
    path: &Path,
    with_cloze: bool,
    now: DateTime<Utc>,
) -> Result<AnkiImport, AnkiError> {
    let file = crate::deck::files::open_regular(path).map_err(|source| AnkiError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut zip = zip::ZipArchive::new(file).map_err(|e| AnkiError::NotZip {
        path: path.to_path_buf(),
        detail: e.to_string(),
    })?;
    let names: Vec<String> = zip
        .file_names()
        .filter_map(|n| n.ok().map(|n| n.into_owned()))
        .collect();
    let entry = [
        "collection.anki21b",
        "collection.anki21",
        "collection.anki2",
    ]
    .into_iter()
    .find(|n| names.iter().any(|x| x == n))
    .ok_or_else(|| AnkiError::NoCollection {
        path: path.to_path_buf(),
    })?;
    let media_files = names
        .iter()
        .filter(|n| !n.starts_with("collection.") && *n != "media" && *n != "meta")
        .count();
    let bytes = {
        let member = zip.by_name(entry).map_err(|e| AnkiError::NotZip {
            path: path.to_path_buf(),
            detail: e.to_string(),
        })?;
        let too_large = || AnkiError::TooLarge {
            path: path.to_path_buf(),
            entry: entry.to_string(),
        };
        if member.size() > MAX_COLLECTION_BYTES {
            return Err(too_large());
        }
        let damaged = |detail: String| AnkiError::Damaged {
            path: path.to_path_buf(),
            entry: entry.to_string(),
            detail,
        };
        let mut raw = Vec::new();
        // The declared size may lie: read one byte past the limit at most.
        member
            .take(MAX_COLLECTION_BYTES + 1)
            .read_to_end(&mut raw)
            .map_err(|e| damaged(e.to_string()))?;
        if raw.len() as u64 > MAX_COLLECTION_BYTES {
            return Err(too_large());
        }
        if entry.ends_with('b') {
            let decoder = zstd::stream::read::Decoder::new(&raw[..])
                .map_err(|e| damaged(format!("not zstd data ({e})")))?;
            let mut out = Vec::new();
            decoder
                .take(MAX_COLLECTION_BYTES + 1)
                .read_to_end(&mut out)
                .map_err(|e| damaged(format!("not zstd data ({e})")))?;
            if out.len() as u64 > MAX_COLLECTION_BYTES {
                return Err(too_large());
            }
            out
        } else {
            raw
        }
    };
    let damaged = |detail: String| AnkiError::Damaged {
        path: path.to_path_buf(),
        entry: entry.to_string(),
        detail,
    };
    if bytes.is_empty() {
        return Err(damaged("the collection is an empty file".to_string()));
    }
    let mut bytes = bytes;
    // A collection saved in WAL mode (Anki's current one) says so in bytes
    // 18 and 19 of its header; a database in memory has no WAL, and reads
    // the same pages in rollback mode.
    if let Some(versions) = bytes.get_mut(18..20)
        && versions == [2, 2]
    {
        versions.copy_from_slice(&[1, 1]);
    }
    let (conn, steps) = open_in_memory(&bytes).map_err(|e| damaged(e.to_string()))?;
    let size = bytes.len() as u64;
    drop(bytes);
    let over_budget = || steps.load(Ordering::Relaxed) > step_budget(size);
    let sql = |e: rusqlite::Error| {
        if over_budget() {
            damaged(format!(
                "reading it took more than {} million SQLite steps, far more than a collection of its size needs; refusing it",
                step_budget(size) * STEPS_PER_CALL as u64 / 1_000_000
            ))
        } else {
            damaged(e.to_string())
        }
    };
    steps.store(0, Ordering::Relaxed);
    check_schema(&conn).map_err(|e| match e {
        ReadError::Sql(e) => sql(e),
        ReadError::Bad(detail) => damaged(detail),
        ReadError::Anki(e) => e,
    })?;
    let check: String = conn
        .query_row("PRAGMA quick_check", [], |r| r.get(0))
        .map_err(sql)?;
    if check != "ok" {
        // One line: SQLite lists every damaged page.
        let first: Vec<&str> = check
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with("***"))
            .take(2)
            .collect();
        return Err(damaged(format!(
            "integrity check failed ({})",
            first.join("; ")
        )));
    }
    let mut out = read_collection(&conn, path, with_cloze, now).map_err(|e| match e {
        ReadError::Sql(e) => sql(e),
        ReadError::Bad(detail) => damaged(detail),
        ReadError::Anki(e) => e,
    })?;
    out.entry = entry.to_string();
    out.media_files = media_files;
    Ok(out)
}

/// How often (in SQLite virtual-machine steps) the work done is counted.
const STEPS_PER_CALL: i32 = 10_000;

/// The counts of [`STEPS_PER_CALL`] steps allowed for reading a collection
/// of `size` bytes: a hundred million steps and twenty per byte, where
/// checking and reading a collection takes under one per byte (about 18
/// million steps for 42 MB of fifty thousand notes and half a million
/// answers), so only a collection built to run on reaches it, and stops
/// within about a second per 5 MB.
fn step_budget(size: u64) -> u64 {
    10_000 + size / 512
}

/// The collection as a read-only database in memory: no scratch file, so
/// nothing is left behind however the import ends (a kill included). The
/// returned counter counts the steps SQLite takes (in [`STEPS_PER_CALL`]),
/// and SQLite stops a statement once they pass [`step_budget`].
fn open_in_memory(bytes: &[u8]) -> rusqlite::Result<(Connection, Arc<AtomicU64>)> {
    let mut conn = Connection::open_in_memory_with_flags(
        OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )?;
    conn.deserialize_read_exact(rusqlite::MAIN_DB, bytes, bytes.len(), true)?;
    // No value read or computed may be larger than the collection itself
    // could hold sensibly (a function in the schema cannot allocate a
    // gigabyte per row).
    conn.set_limit(Limit::SQLITE_LIMIT_LENGTH, MAX_VALUE_BYTES)?;
    // CHECK constraints guard writes; this import only reads, and
    // `quick_check` would otherwise evaluate them on every row.
    conn.pragma_update(None, "ignore_check_constraints", true)?;
    // Anki's own collation for names (schema 18 indexes use it): Unicode
    // case folding, close enough for checking and reading.
    conn.create_collation("unicase", |a: &str, b: &str| {
        a.to_lowercase().cmp(&b.to_lowercase())
    })?;
    let steps = Arc::new(AtomicU64::new(0));
    let counted = Arc::clone(&steps);
    let budget = step_budget(bytes.len() as u64);
    conn.progress_handler(
        STEPS_PER_CALL,
        Some(move || counted.fetch_add(1, Ordering::Relaxed) + 1 > budget),
    )?;
    Ok((conn, steps))
}

/// The largest single value (a note's fields together, the legacy `col`
/// row's JSON) read from a collection.
const MAX_VALUE_BYTES: i32 = 64 << 20;

/// The tables this import reads, in either layout.
const TABLES_READ: [&str; 8] = [
    "col",
    "notes",
    "cards",
    "revlog",
    "notetypes",
    "fields",
    "templates",
    "decks",
];

/// Refuses a collection in which a name this import reads is not a plain
/// table (a view can be made to run for ever, a virtual table needs code
/// the collection does not bring), or a table has a computed column (Anki
/// writes none; it would be computed on every read).
fn check_schema(conn: &Connection) -> Result<(), ReadError> {
    let mut st = conn.prepare(
        "SELECT type, name, coalesce(sql, '') FROM sqlite_schema \
         WHERE name = ?1 COLLATE NOCASE AND type IN ('table', 'view')",
    )?;
    for name in TABLES_READ {
        let mut rows = st.query([name])?;
        while let Some(r) = rows.next()? {
            let (kind, actual, sql): (String, String, String) = (r.get(0)?, r.get(1)?, r.get(2)?);
            let virtual_table = sql
                .trim_start()
                .get(..14)
                .is_some_and(|s| s.eq_ignore_ascii_case("create virtual"));
            if kind != "table" || virtual_table {
                let what = if kind == "table" {
                    "a virtual table"
                } else {
                    "a view"
                };
                return Err(ReadError::Bad(format!(
                    "`{}` is {what}, not a table; refusing it",
                    flipcard_text::safe::one_line(&actual)
                )));
            }
        }
    }
    let computed: Option<(String, String)> = conn
        .query_row(
            "SELECT s.name, x.name FROM sqlite_schema AS s, pragma_table_xinfo(s.name) AS x \
             WHERE s.type = 'table' AND x.hidden IN (2, 3) LIMIT 1",
            [],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .optional()?;
    if let Some((table, column)) = computed {
        return Err(ReadError::Bad(format!(
            "column `{}` of table `{}` is computed (GENERATED), which Anki never writes; refusing it",
            flipcard_text::safe::one_line(&column),
            flipcard_text::safe::one_line(&table)
        )));
    }
    Ok(())
}

enum ReadError {
    Sql(rusqlite::Error),
    Bad(String),
    Anki(AnkiError),
}

impl From<rusqlite::Error> for ReadError {
    fn from(e: rusqlite::Error) -> Self {
        ReadError::Sql(e)
    }
}

fn has_table(conn: &Connection, name: &str) -> rusqlite::Result<bool> {
    conn.query_row(
        "SELECT count(*) FROM sqlite_schema WHERE type = 'table' AND name = ?1",
        [name],
        |r| r.get::<_, i64>(0),
    )
    .map(|n| n > 0)
}

/// (note types by id as (name, kind, fields, templates), deck names by id)
type Catalog = (
    HashMap<i64, (String, bool, usize, usize)>,
    HashMap<i64, String>,
);

fn catalog_legacy(conn: &Connection) -> Result<Catalog, ReadError> {
    let (models, decks): (String, String) =
        conn.query_row("SELECT models, decks FROM col", [], |r| {
            Ok((r.get(0)?, r.get(1)?))
        })?;
    let bad = |what: &str, e: serde_json::Error| ReadError::Bad(format!("col.{what}: {e}"));
    let models: serde_json::Value = serde_json::from_str(&models).map_err(|e| bad("models", e))?;
    let decks: serde_json::Value = serde_json::from_str(&decks).map_err(|e| bad("decks", e))?;
    let mut types = HashMap::new();
    for (id, m) in models.as_object().into_iter().flatten() {
        let id: i64 = id
            .parse()
            .map_err(|_| ReadError::Bad(format!("note type id {id:?}")))?;
        let count = |k: &str| m[k].as_array().map_or(0, Vec::len);
        types.insert(
            id,
            (
                m["name"].as_str().unwrap_or("?").to_string(),
                m["type"].as_i64() == Some(1),
                count("flds"),
                count("tmpls"),
            ),
        );
    }
    let mut names = HashMap::new();
    for (id, d) in decks.as_object().into_iter().flatten() {
        if let (Ok(id), Some(name)) = (id.parse::<i64>(), d["name"].as_str()) {
            names.insert(id, name.to_string());
        }
    }
    Ok((types, names))
}

fn catalog_v18(conn: &Connection) -> Result<Catalog, ReadError> {
    let mut types = HashMap::new();
    let mut st = conn.prepare(
        "SELECT id, name, config, \
           (SELECT count(*) FROM fields f WHERE f.ntid = n.id), \
           (SELECT count(*) FROM templates t WHERE t.ntid = n.id) \
         FROM notetypes n",
    )?;
    let mut rows = st.query([])?;
    while let Some(r) = rows.next()? {
        let config: Vec<u8> = r.get(2)?;
        types.insert(
            r.get::<_, i64>(0)?,
            (
                r.get::<_, String>(1)?,
                proto_varint(&config, 1) == Some(1),
                r.get::<_, i64>(3)? as usize,
                r.get::<_, i64>(4)? as usize,
            ),
        );
    }
    let mut names = HashMap::new();
    let mut st = conn.prepare("SELECT id, name FROM decks")?;
    let mut rows = st.query([])?;
    while let Some(r) = rows.next()? {
        // Levels are joined by U+001F in this schema.
        names.insert(r.get(0)?, r.get::<_, String>(1)?.replace('\u{1f}', "::"));
    }
    Ok((types, names))
}

/// The value of top-level varint field `field` of a protobuf message
/// (`None` when absent, i.e. zero).
fn proto_varint(mut buf: &[u8], field: u64) -> Option<u64> {
    fn varint(buf: &mut &[u8]) -> Option<u64> {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let (&b, rest) = buf.split_first()?;
            *buf = rest;
            v |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Some(v);
            }
        }
        None
    }
    while !buf.is_empty() {
        let key = varint(&mut buf)?;
        let skip = match key & 7 {
            0 => {
                let v = varint(&mut buf)?;
                if key >> 3 == field {
                    return Some(v);
                }
                0
            }
            1 => 8,
            2 => varint(&mut buf)? as usize,
            5 => 4,
            _ => return None,
        };
        buf = buf.get(skip..)?;
    }
    None
}

fn read_collection(
    conn: &Connection,
    path: &Path,
    with_cloze: bool,
    now: DateTime<Utc>,
) -> Result<AnkiImport, ReadError> {
    let (types, deck_names) = if has_table(conn, "notetypes")? {
        catalog_v18(conn)?
    } else {
        catalog_legacy(conn)?
    };
    // Every note type in use must be one flipcard knows.
    let mut note_types: HashMap<i64, Kind> = HashMap::new();
    let used: Vec<i64> = {
        let mut st = conn.prepare("SELECT DISTINCT mid FROM notes")?;
        st.query_map([], |r| r.get(0))?
            .collect::<rusqlite::Result<_>>()?
    };
    for mid in used {
        let (name, cloze, fields, templates) = types.get(&mid).cloned().ok_or_else(|| {
            ReadError::Bad(format!("notes use note type {mid}, which is missing"))
        })?;
        let kind = match (cloze, fields, templates) {
            (true, 1..=2, _) => Kind::Cloze,
            (false, 2, 1) => Kind::Basic,
            (false, 2, 2) => Kind::Reversed,
            _ => {
                return Err(ReadError::Anki(AnkiError::UnknownNoteType {
                    path: path.to_path_buf(),
                    name,
                    fields,
                    templates,
                }));
            }
        };
        note_types.insert(mid, kind);
    }

    // A note belongs to the deck of its first card.
    let mut note_deck: HashMap<i64, i64> = HashMap::new();
    {
        let mut st = conn.prepare("SELECT nid, did FROM cards ORDER BY nid, ord")?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            note_deck.entry(r.get(0)?).or_insert(r.get(1)?);
        }
    }

    struct Note {
        id: i64,
        kind: Kind,
        fields: Vec<String>,
        tags: Vec<String>,
    }
    let mut by_deck: BTreeMap<String, Vec<Note>> = BTreeMap::new();
    let mut out = AnkiImport::default();
    {
        let mut st = conn.prepare("SELECT id, mid, flds, tags FROM notes ORDER BY id")?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            let id: i64 = r.get(0)?;
            let mid: i64 = r.get(1)?;
            let flds: String = r.get(2)?;
            let tags: String = r.get(3)?;
            let Some(kind) = note_types.get(&mid).copied() else {
                continue;
            };
            if kind == Kind::Cloze && !with_cloze {
                out.cloze_left_out += 1;
                continue;
            }
            let deck = note_deck
                .get(&id)
                .and_then(|d| deck_names.get(d))
                .cloned()
                .unwrap_or_else(|| "Default".to_string());
            by_deck.entry(deck).or_default().push(Note {
                id,
                kind,
                fields: flds.split('\u{1f}').map(str::to_string).collect(),
                tags: tags
                    .split_whitespace()
                    .map(tag)
                    .filter(|t| !t.is_empty())
                    .collect(),
            });
            out.notes += 1;
        }
    }
    if out.notes == 0 && out.cloze_left_out == 0 {
        return Err(ReadError::Anki(AnkiError::Empty {
            path: path.to_path_buf(),
        }));
    }

    // Deck ids from the names, unique.
    let mut taken = HashSet::new();
    // Where each base's count stopped: many names of one slug take one
    // step each.
    let mut next_of: HashMap<String, u64> = HashMap::new();
    let mut card_of_note: HashMap<i64, (String, String, Kind)> = HashMap::new();
    for (name, notes) in &by_deck {
        let base = slug(&name.replace("::", " "));
        let n = next_of.entry(base.clone()).or_insert(1);
        let mut id = if *n == 1 {
            base.clone()
        } else {
            format!("{base}-{n}")
        };
        while !taken.insert(id.clone()) {
            *n += 1;
            id = format!("{base}-{n}");
        }
        let mut text = String::new();
        text.push_str("# Imported from Anki");
        text.push_str(&format!(" (deck {name:?}).\n[deck]\n"));
        text.push_str(&format!("id = {}\n", toml_string(&id)));
        text.push_str(&format!("title = {}\n", toml_string(&plain(name))));
        text.push_str("languages = [\"en\"]\n");
        for note in notes {
            let card_id = format!("n{}", note.id);
            let field = |i: usize, refs: &mut usize| {
                let (t, media) = html_to_text(note.fields.get(i).map_or("", String::as_str));
                *refs += media;
                if t.len() > MAX_FIELD_BYTES {
                    return Err(ReadError::Anki(AnkiError::FieldTooLarge {
                        path: path.to_path_buf(),
                        note: note.id,
                        field: i + 1,
                        mib: t.len().div_ceil(1 << 20),
                    }));
                }
                Ok(t)
            };
            let mut front = field(0, &mut out.media_refs)?;
            let mut back = field(1, &mut out.media_refs)?;
            text.push_str("\n[[card]]\n");
            text.push_str(&format!("id = {}\n", toml_string(&card_id)));
            match note.kind {
                Kind::Basic => {}
                Kind::Reversed => text.push_str("kind = \"reversed\"\n"),
                Kind::Cloze => text.push_str("kind = \"cloze\"\n"),
            }
            if front.is_empty() {
                front = "(media not imported)".into();
            }
            // A cloze card keeps its deletions in `text`; the others ask `front`.
            let key = if note.kind == Kind::Cloze {
                "text"
            } else {
                "front"
            };
            text.push_str(&format!("{key} = {}\n", toml_string(&front)));
            if note.kind != Kind::Cloze || !back.is_empty() {
                if back.is_empty() {
                    back = "(media not imported)".into();
                }
                text.push_str(&format!("back = {}\n", toml_string(&back)));
            }
            if !note.tags.is_empty() {
                let tags: Vec<String> = note.tags.iter().map(|t| toml_string(t)).collect();
                text.push_str(&format!("tags = [{}]\n", tags.join(", ")));
            }
            card_of_note.insert(note.id, (id.clone(), card_id, note.kind));
        }
        out.decks.push(ImportedDeck {
            id,
            name: name.clone(),
            toml: text,
            cards: notes.len(),
        });
    }

    // Cards (by Anki card id) as the log names them.
    let mut cards: HashMap<i64, CardRef> = HashMap::new();
    {
        let mut st = conn.prepare("SELECT id, nid, ord FROM cards")?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            let (cid, nid, ord): (i64, i64, i64) = (r.get(0)?, r.get(1)?, r.get(2)?);
            let Some((deck, card, kind)) = card_of_note.get(&nid) else {
                continue;
            };
            let direction = match (kind, ord) {
                (Kind::Basic, 0) | (Kind::Reversed, 0) => Some(Direction::Forward),
                (Kind::Reversed, 1) => Some(Direction::Backward),
                // Anki's card `ord` n of a cloze note is deletion c(n+1);
                // a deck numbers its deletions up to c999.
                (Kind::Cloze, n) if (0..i64::from(MAX_NUMBER)).contains(&n) => {
                    Some(Direction::Cloze(n as u16 + 1))
                }
                _ => None,
            };
            cards.insert(
                cid,
                CardRef {
                    deck: deck.clone(),
                    card: card.clone(),
                    direction,
                },
            );
        }
    }
    {
        let mut st = conn.prepare("SELECT id, cid, ease, time, type FROM revlog ORDER BY id")?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            let (at, cid, ease, took, kind): (i64, i64, i64, i64, i64) =
                (r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?);
            // Ease 0 and types 4 and 5 are reschedules by hand, not answers.
            let rating = Rating::from_number(ease).filter(|_| kind <= 3);
            let card = cards.get(&cid);
            match (rating, card.and_then(|c| c.direction.map(|d| (c, d)))) {
                (Some(rating), Some((c, direction))) => {
                    // An answer's id is its time in milliseconds.
                    let when = DateTime::<Utc>::from_timestamp_millis(at)
                        .ok_or_else(|| "its time is out of any calendar's range".to_string())
                        .and_then(|t| {
                            check_event_time(t, now)
                                .map(|()| t)
                                .map_err(|e| e.to_string())
                        })
                        .map_err(|detail| {
                            ReadError::Anki(AnkiError::BadAnswer {
                                path: path.to_path_buf(),
                                id: at,
                                detail,
                            })
                        })?;
                    out.reviews.push(IncomingReview {
                        key: ItemKey {
                            deck: c.deck.clone(),
                            card: c.card.clone(),
                            direction,
                        },
                        reviewed_at: when,
                        rating,
                        cram: false,
                        duration_ms: took.clamp(0, 24 * 3_600_000),
                        undone: false,
                    });
                }
                _ => out.reviews_skipped += 1,
            }
        }
    }
    Ok(out)
}

/// An Anki tag as a flipcard tag (`::` levels kept as written).
fn tag(t: &str) -> String {
    t.chars().filter(|c| !c.is_control()).collect()
}

/// Text without control characters, for titles.
fn plain(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .trim()
        .to_string()
}

/// A field's HTML as flipcard text: tags dropped (line breaks where blocks
/// and `<br>` were), entities decoded, MathJax `\(…\)` and `\[…\]` as `$…$`
/// and `$$…$$`, other dollars escaped. Images and sounds are dropped; the
/// count of them is returned beside the text. Math that flipcard cannot
/// render is kept as plain text.
pub(crate) fn html_to_text(html: &str) -> (String, usize) {
    let mut media = html.matches("[sound:").count();
    let mut text = String::new();
    let mut rest = html;
    while let Some(i) = rest.find('<') {
        text.push_str(&rest[..i]);
        let Some(end) = rest[i..].find('>') else {
            text.push_str(&rest[i..]);
            rest = "";
            break;
        };
        let tag = rest[i + 1..i + end].trim().to_ascii_lowercase();
        let name: String = tag
            .trim_start_matches('/')
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect();
        match name.as_str() {
            "br" => text.push('\n'),
            "div" | "p" | "li" | "tr" | "h1" | "h2" | "h3" | "h4" if tag.starts_with('/') => {
                text.push('\n')
            }
            "img" | "audio" | "video" => media += 1,
            _ => {}
        }
        rest = &rest[i + end + 1..];
    }
    text.push_str(rest);
    let mut sound_free = String::new();
    let mut r = text.as_str();
    while let Some(i) = r.find("[sound:") {
        sound_free.push_str(&r[..i]);
        r = r[i..].find(']').map_or("", |j| &r[i + j + 1..]);
    }
    sound_free.push_str(r);
    let decoded = decode_entities(&sound_free);
    // Anki's blocks are lines; empty ones (a block that held only an image)
    // are dropped.
    let lines: Vec<String> = decoded
        .replace('\u{a0}', " ")
        .lines()
        .map(|l| {
            l.split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
                .chars()
                .filter(|c| !c.is_control())
                .collect::<String>()
        })
        .filter(|l| !l.is_empty())
        .collect();
    let joined = lines.join("\n");
    let with_math = convert_math(&joined, true);
    let t = if flipcard_text::check(&with_math).is_empty() {
        with_math
    } else {
        convert_math(&joined, false)
    };
    (t, media)
}

/// `\(…\)` → `$…$`, `\[…\]` → `$$…$$` (or left as written when `math` is
/// false), every other `$` escaped. One pass from left to right: each
/// opener is found once and the search for its closer starts after it, so
/// the work is linear in the text (a field of many openers once searched
/// the rest of the text for each).
fn convert_math(s: &str, math: bool) -> String {
    let mut out = String::with_capacity(s.len() + s.len() / 8);
    let mut rest = s;
    loop {
        let Some((i, c, d)) = next_opener(rest) else {
            push_escaped(&mut out, rest);
            return out;
        };
        let o = 2;
        let Some(j) = rest[i + o..].find(c) else {
            push_escaped(&mut out, rest);
            return out;
        };
        push_escaped(&mut out, &rest[..i]);
        let inner = &rest[i + o..i + o + j];
        if math && !inner.contains('$') {
            out.push_str(d);
            out.push_str(inner.trim());
            out.push_str(d);
        } else {
            push_escaped(&mut out, &rest[i..i + o + j + c.len()]);
        }
        rest = &rest[i + o + j + c.len()..];
    }
}

/// The first MathJax opener of `s`, `\(` or `\[`: where it is, its closer
/// and the flipcard delimiter.
fn next_opener(s: &str) -> Option<(usize, &'static str, &'static str)> {
    let b = s.as_bytes();
    b.windows(2).enumerate().find_map(|(i, w)| match w {
        [b'\\', b'('] => Some((i, "\\)", "$")),
        [b'\\', b'['] => Some((i, "\\]", "$$")),
        _ => None,
    })
}

/// `s` with every `$` escaped, appended to `out`.
fn push_escaped(out: &mut String, s: &str) {
    for (k, part) in s.split('$').enumerate() {
        if k > 0 {
            out.push_str("\\$");
        }
        out.push_str(part);
    }
}

fn decode_entities(s: &str) -> String {
    let mut out = String::new();
    let mut rest = s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        // A name is at most ten bytes: only those are searched for its `;`
        // (a text of many `&` once searched the whole rest for each).
        let end = after.as_bytes().iter().take(11).position(|&b| b == b';');
        let decoded = end.and_then(|e| Some((decode_entity(&after[..e])?, e)));
        match decoded {
            Some((c, e)) => {
                out.push(c);
                rest = &after[e + 1..];
            }
            None => {
                out.push('&');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The character an entity `&name;` stands for.
fn decode_entity(name: &str) -> Option<char> {
    match name {
        "amp" => Some('&'),
        "lt" => Some('<'),
        "gt" => Some('>'),
        "quot" => Some('"'),
        "apos" | "#39" => Some('\''),
        "nbsp" => Some(' '),
        _ => named_entity(name).or_else(|| {
            name.strip_prefix("#x")
                .or_else(|| name.strip_prefix("#X"))
                .and_then(|h| u32::from_str_radix(h, 16).ok())
                .or_else(|| name.strip_prefix('#').and_then(|d| d.parse().ok()))
                .and_then(char::from_u32)
        }),
    }
}

/// The named HTML entities a science note is likely to hold.
fn named_entity(name: &str) -> Option<char> {
    static TABLE: std::sync::LazyLock<HashMap<&'static str, char>> = std::sync::LazyLock::new(
        || {
            const NAMES: &str = "alpha α beta β gamma γ delta δ epsilon ε zeta ζ eta η theta θ iota ι \
                kappa κ lambda λ mu μ nu ν xi ξ omicron ο pi π rho ρ sigma σ tau τ upsilon υ phi φ \
                chi χ psi ψ omega ω Gamma Γ Delta Δ Theta Θ Lambda Λ Xi Ξ Pi Π Sigma Σ Phi Φ Psi Ψ \
                Omega Ω hellip … mdash — ndash – times × divide ÷ deg ° middot · plusmn ± le ≤ ge ≥ \
                ne ≠ asymp ≈ rarr → larr ← harr ↔ rArr ⇒ infin ∞ part ∂ nabla ∇ sum ∑ int ∫ radic √ \
                prop ∝ micro µ sup2 ² sup3 ³ frac12 ½ lsquo ‘ rsquo ’ ldquo “ rdquo ” bull • minus −";
            let words: Vec<&str> = NAMES.split_whitespace().collect();
            words
                .chunks_exact(2)
                .filter_map(|kv| Some((kv[0], kv[1].chars().next()?)))
                .collect()
        },
    );
    TABLE.get(name).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn html_becomes_text_with_math_and_media_counted() {
        let (t, media) = html_to_text(
            "<div>Torque &amp; spin:&nbsp;\\(\\tau = I\\alpha\\)</div><div><img src=\"a.png\"></div>costs $5<br>\\[E = mc^2\\][sound:x.mp3]",
        );
        assert_eq!(
            t,
            "Torque & spin: $\\tau = I\\alpha$\ncosts \\$5\n$$E = mc^2$$"
        );
        assert_eq!(media, 2);
        assert_eq!(
            html_to_text("L = I&omega; &amp;c &bogus; &#8594;").0,
            "L = Iω &c &bogus; →"
        );
        assert!(flipcard_text::check(&t).is_empty());
        // Math flipcard cannot render stays as written, dollars escaped.
        let (t, _) = html_to_text("\\(\\unknowncommand x\\) for $1");
        assert_eq!(t, "\\(\\unknowncommand x\\) for \\$1");
        assert!(flipcard_text::check(&t).is_empty());
    }

    /// The conversions as they were before they were made linear: the
    /// reference their output must equal.
    fn reference_convert_math(s: &str, math: bool) -> String {
        let mut out = String::new();
        let mut rest = s;
        loop {
            let open = [("\\(", "\\)", "$"), ("\\[", "\\]", "$$")]
                .into_iter()
                .filter_map(|(o, c, d)| rest.find(o).map(|i| (i, o, c, d)))
                .min_by_key(|x| x.0);
            let Some((i, o, c, d)) = open else {
                out.push_str(&rest.replace('$', "\\$"));
                return out;
            };
            let Some(j) = rest[i + o.len()..].find(c) else {
                out.push_str(&rest.replace('$', "\\$"));
                return out;
            };
            out.push_str(&rest[..i].replace('$', "\\$"));
            let inner = &rest[i + o.len()..i + o.len() + j];
            if math && !inner.contains('$') {
                out.push_str(d);
                out.push_str(inner.trim());
                out.push_str(d);
            } else {
                out.push_str(&rest[i..i + o.len() + j + c.len()].replace('$', "\\$"));
            }
            rest = &rest[i + o.len() + j + c.len()..];
        }
    }

    fn reference_decode_entities(s: &str) -> String {
        let mut out = String::new();
        let mut rest = s;
        while let Some(i) = rest.find('&') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let end = after.find(';').filter(|e| *e <= 10);
            match end.and_then(|e| Some((decode_entity(&after[..e])?, e))) {
                Some((c, e)) => {
                    out.push(c);
                    rest = &after[e + 1..];
                }
                None => {
                    out.push('&');
                    rest = after;
                }
            }
        }
        out.push_str(rest);
        out
    }

    proptest::proptest! {
        /// Run longer with `PROPTEST_CASES=100000 cargo test --lib interop::anki`.
        #[test]
        fn the_linear_conversions_equal_the_reference(
            s in "([\\\\()\\[\\]$&;#x0-9a-z ]|amp;|\\\\\\(|\\\\\\[|\\\\\\)|\\\\\\]|é){0,40}",
            math: bool,
        ) {
            proptest::prop_assert_eq!(convert_math(&s, math), reference_convert_math(&s, math));
            proptest::prop_assert_eq!(decode_entities(&s), reference_decode_entities(&s));
        }
    }

    #[test]
    fn field_text_is_converted_in_linear_time() {
        // 2 MB of `&` and 1.8 MB of `\(x^2\)` took minutes when each `&`
        // searched the rest for a `;` and each opener the rest for the other
        // opener; counted in steps, not seconds: the output is exact.
        let (t, _) = html_to_text(&"&".repeat(2_000_000));
        assert_eq!(t.len(), 2_000_000);
        assert!(t.bytes().all(|b| b == b'&'));
        let (t, _) = html_to_text(&"\\(x^2\\)".repeat(250_000));
        assert_eq!(t, "$x^2$".repeat(250_000));
    }

    #[test]
    fn a_statement_that_runs_on_is_stopped_by_the_step_budget() {
        let mut made = Connection::open_in_memory().unwrap();
        made.execute_batch(
            "CREATE TABLE notes (id INTEGER PRIMARY KEY, flds TEXT); \
             INSERT INTO notes VALUES (1, 'a');",
        )
        .unwrap();
        let bytes = made.serialize(rusqlite::MAIN_DB).unwrap().to_vec();
        let (conn, steps) = open_in_memory(&bytes).unwrap();
        // Read-only, and a normal query well within the budget.
        assert!(conn.execute("DELETE FROM notes", []).is_err());
        let n: i64 = conn
            .query_row("SELECT count(*) FROM notes", [], |r| r.get(0))
            .unwrap();
        assert_eq!(n, 1);
        // A query that never ends is interrupted once past the budget.
        let endless = conn.query_row(
            "WITH RECURSIVE r(n) AS (SELECT 1 UNION ALL SELECT n + 1 FROM r) \
             SELECT count(*) FROM r",
            [],
            |r| r.get::<_, i64>(0),
        );
        assert!(endless.is_err(), "{endless:?}");
        assert!(steps.load(Ordering::Relaxed) > step_budget(bytes.len() as u64));
    }

    #[test]
    fn views_and_computed_columns_are_refused() {
        for (sql, says) in [
            (
                "CREATE VIEW Notes AS SELECT 1 AS id",
                "`Notes` is a view, not a table",
            ),
            (
                "CREATE TABLE revlog (id INTEGER, g INTEGER AS (id * 2))",
                "column `g` of table `revlog` is computed",
            ),
            (
                "CREATE TABLE other (id INTEGER, g TEXT AS (hex(zeroblob(1000000))) STORED)",
                "column `g` of table `other` is computed",
            ),
        ] {
            let mut made = Connection::open_in_memory().unwrap();
            made.execute_batch(sql).unwrap();
            let bytes = made.serialize(rusqlite::MAIN_DB).unwrap().to_vec();
            let (conn, _) = open_in_memory(&bytes).unwrap();
            match check_schema(&conn) {
                Err(ReadError::Bad(e)) => assert!(e.contains(says), "{e}"),
                _ => panic!("{sql}: not refused"),
            }
        }
    }

    #[test]
    fn protobuf_kind_is_found_past_other_fields() {
        // field 3 (string "ab"), then field 1 = 1 (cloze)
        assert_eq!(proto_varint(&[0x1a, 2, b'a', b'b', 0x08, 1], 1), Some(1));
        assert_eq!(proto_varint(&[0x10, 5], 1), None);
        assert_eq!(proto_varint(&[0x1a, 9, 1], 1), None, "truncated");
    }
}
