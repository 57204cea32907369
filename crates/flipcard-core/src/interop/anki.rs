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

use chrono::{DateTime, Datelike, Utc};
use rusqlite::limits::Limit;
use rusqlite::{Connection, OpenFlags, OptionalExtension};

use crate::deck::cloze::MAX_NUMBER;
use crate::deck::csv::{MAX_FIELD_BYTES, slug, toml_string};
use crate::sched::clock::check_event_time;
use crate::sched::{Direction, ItemKey, Rating, State};
use crate::store::{IncomingReview, KeptState};

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
    #[error("{path}: the collection has no notes to import")]
    Empty { path: PathBuf },
    #[error("{path}: revlog row {id}: the answer time {detail}; nothing imported")]
    BadAnswer {
        path: PathBuf,
        id: i64,
        detail: String,
    },
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
    /// The options (preset) the Anki deck had.
    pub options: Option<DeckOptions>,
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
    /// Every note type used, and what its notes became.
    pub note_types: Vec<MappedType>,
    /// Notes that could not be converted, each with why.
    pub skipped: Vec<SkippedNote>,
    /// Fields whose math flipcard cannot render (kept as text).
    pub math_not_rendered: Vec<UnrenderedMath>,
    /// Suspended, buried, flagged and leech cards, and each card's due
    /// date as Anki had it.
    pub states: KeptStates,
    /// Decks named like a bundled deck, given another id.
    pub renamed: Vec<RenamedDeck>,
}

/// A card of a note, as the review log names it.
struct CardRef {
    deck: String,
    card: String,
    direction: Option<Direction>,
}

/// Reads a package. With `with_cloze` false, Cloze notes are counted but
/// left out (for decks that have no cloze cards). No deck gets an id of
/// `reserved` (the bundled decks'): such a deck is renamed, and said so.
/// `now` is this machine's clock: an answer in the revlog dated after it
/// (by more than a day) or before 1970 is refused.
pub fn read_package(
    path: &Path,
    with_cloze: bool,
    reserved: &HashSet<String>,
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
    let mut out = read_collection(&conn, path, with_cloze, reserved, now).map_err(|e| match e {
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
const TABLES_READ: [&str; 9] = [
    "col",
    "notes",
    "cards",
    "revlog",
    "notetypes",
    "fields",
    "templates",
    "decks",
    "deck_config",
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

/// A note type, as either layout stores it.
#[derive(Debug, Clone, Default)]
struct NoteType {
    name: String,
    cloze: bool,
    /// Field names, in order.
    fields: Vec<String>,
    /// Each card type's question template, in order.
    questions: Vec<String>,
    /// Anki's `originalStockKind` (1 Basic, 2 and reversed, 3 optional
    /// reversed, 4 type in the answer, 5 Cloze, 6 Image Occlusion), kept by
    /// Anki on its stock note types and their copies.
    stock: Option<u64>,
}

/// A deck of the collection: its name (levels joined by `::`) and its
/// options' id.
struct DeckInfo {
    name: String,
    config: Option<i64>,
}

/// Deck options as Anki had them (Anki's "preset").
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DeckOptions {
    /// The preset's name in Anki.
    pub preset: String,
    pub new_per_day: Option<u32>,
    pub reviews_per_day: Option<u32>,
    /// Steps in minutes.
    pub learning_steps: Vec<f64>,
    pub relearning_steps: Vec<f64>,
    pub desired_retention: Option<f64>,
    /// FSRS parameters (the newest set Anki kept: 21 for FSRS-6).
    pub fsrs_parameters: Vec<f64>,
    /// The maximum interval, in days.
    pub maximum_interval: Option<u32>,
}

struct Catalog {
    types: HashMap<i64, NoteType>,
    decks: HashMap<i64, DeckInfo>,
    options: HashMap<i64, DeckOptions>,
    /// The collection's day 0 (seconds): review due dates count from it.
    crt: i64,
}

/// Steps read from Anki (minutes), finite and positive, at most 20.
fn steps(v: impl IntoIterator<Item = f64>) -> Vec<f64> {
    v.into_iter()
        .filter(|m| m.is_finite() && *m > 0.0 && *m < 1e7)
        .take(20)
        .collect()
}

fn per_day(v: Option<i64>) -> Option<u32> {
    v.and_then(|n| u32::try_from(n).ok())
        .filter(|n| *n <= 1_000_000)
}

/// Anki's maximum interval (days), when it is one flipcard can keep.
fn max_interval(v: Option<i64>) -> Option<u32> {
    v.and_then(|n| u32::try_from(n).ok())
        .filter(|n| (1..=crate::sched::preset::MAX_INTERVAL_DAYS).contains(n))
}

fn retention(v: Option<f64>) -> Option<f64> {
    v.filter(|r| r.is_finite() && (0.5..=0.999).contains(r))
}

fn fsrs_params(v: Vec<f64>) -> Vec<f64> {
    if v.len() <= 21 && v.iter().all(|w| w.is_finite()) {
        v
    } else {
        Vec::new()
    }
}

fn catalog_legacy(conn: &Connection) -> Result<Catalog, ReadError> {
    let (models, decks, dconf, crt): (String, String, String, i64) = conn.query_row(
        "SELECT models, decks, coalesce(dconf, '{}'), crt FROM col",
        [],
        |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?)),
    )?;
    let bad = |what: &str, e: serde_json::Error| ReadError::Bad(format!("col.{what}: {e}"));
    let models: serde_json::Value = serde_json::from_str(&models).map_err(|e| bad("models", e))?;
    let decks: serde_json::Value = serde_json::from_str(&decks).map_err(|e| bad("decks", e))?;
    // Options are no reason to refuse the notes: unreadable ones are none.
    let dconf: serde_json::Value = serde_json::from_str(&dconf).unwrap_or_default();
    let mut types = HashMap::new();
    for (id, m) in models.as_object().into_iter().flatten() {
        let id: i64 = id
            .parse()
            .map_err(|_| ReadError::Bad(format!("note type id {id:?}")))?;
        let strings = |list: &str, key: &str| -> Vec<String> {
            m[list]
                .as_array()
                .into_iter()
                .flatten()
                .map(|x| x[key].as_str().unwrap_or("").to_string())
                .collect()
        };
        types.insert(
            id,
            NoteType {
                name: m["name"].as_str().unwrap_or("?").to_string(),
                cloze: m["type"].as_i64() == Some(1),
                fields: strings("flds", "name"),
                questions: strings("tmpls", "qfmt"),
                stock: m["originalStockKind"].as_u64(),
            },
        );
    }
    let mut names = HashMap::new();
    for (id, d) in decks.as_object().into_iter().flatten() {
        if let (Ok(id), Some(name)) = (id.parse::<i64>(), d["name"].as_str()) {
            names.insert(
                id,
                DeckInfo {
                    name: name.to_string(),
                    config: d["conf"].as_i64(),
                },
            );
        }
    }
    let mut options = HashMap::new();
    for (id, c) in dconf.as_object().into_iter().flatten() {
        let Ok(id) = id.parse::<i64>() else { continue };
        let floats = |v: &serde_json::Value| -> Vec<f64> {
            v.as_array()
                .into_iter()
                .flatten()
                .filter_map(serde_json::Value::as_f64)
                .collect()
        };
        let params = ["fsrsParams6", "fsrsParams5", "fsrsWeights"]
            .into_iter()
            .map(|k| floats(&c[k]))
            .find(|v| !v.is_empty())
            .unwrap_or_default();
        options.insert(
            id,
            DeckOptions {
                preset: plain(c["name"].as_str().unwrap_or("")),
                new_per_day: per_day(c["new"]["perDay"].as_i64()),
                reviews_per_day: per_day(c["rev"]["perDay"].as_i64()),
                learning_steps: steps(floats(&c["new"]["delays"])),
                relearning_steps: steps(floats(&c["lapse"]["delays"])),
                desired_retention: retention(c["desiredRetention"].as_f64()),
                fsrs_parameters: fsrs_params(params),
                maximum_interval: max_interval(c["rev"]["maxIvl"].as_i64()),
            },
        );
    }
    Ok(Catalog {
        types,
        decks: names,
        options,
        crt,
    })
}

fn catalog_v18(conn: &Connection) -> Result<Catalog, ReadError> {
    let mut types: HashMap<i64, NoteType> = HashMap::new();
    let mut st = conn.prepare("SELECT id, name, config FROM notetypes")?;
    let mut rows = st.query([])?;
    while let Some(r) = rows.next()? {
        let config: Vec<u8> = r.get(2)?;
        types.insert(
            r.get::<_, i64>(0)?,
            NoteType {
                name: r.get::<_, String>(1)?,
                cloze: proto_varint(&config, 1) == Some(1),
                stock: proto_varint(&config, 9).filter(|k| *k > 0),
                ..NoteType::default()
            },
        );
    }
    let mut st = conn.prepare("SELECT ntid, name FROM fields ORDER BY ntid, ord")?;
    let mut rows = st.query([])?;
    while let Some(r) = rows.next()? {
        if let Some(t) = types.get_mut(&r.get::<_, i64>(0)?) {
            t.fields.push(r.get(1)?);
        }
    }
    let mut st = conn.prepare("SELECT ntid, config FROM templates ORDER BY ntid, ord")?;
    let mut rows = st.query([])?;
    while let Some(r) = rows.next()? {
        let config: Vec<u8> = r.get(1)?;
        if let Some(t) = types.get_mut(&r.get::<_, i64>(0)?) {
            let q = proto_fields(&config)
                .into_iter()
                .find_map(|(f, v)| match (f, v) {
                    (1, Proto::Bytes(b)) => Some(String::from_utf8_lossy(b).into_owned()),
                    _ => None,
                })
                .unwrap_or_default();
            t.questions.push(q);
        }
    }
    let mut names = HashMap::new();
    let mut st = conn.prepare("SELECT id, name, kind FROM decks")?;
    let mut rows = st.query([])?;
    while let Some(r) = rows.next()? {
        let kind: Vec<u8> = r.get::<_, Option<Vec<u8>>>(2)?.unwrap_or_default();
        // DeckKind: field 1 is a normal deck, whose field 1 is its options.
        let config = proto_fields(&kind)
            .into_iter()
            .find_map(|(f, v)| match (f, v) {
                (1, Proto::Bytes(normal)) => proto_varint(normal, 1).map(|c| c as i64),
                _ => None,
            });
        // Levels are joined by U+001F in this schema.
        names.insert(
            r.get(0)?,
            DeckInfo {
                name: r.get::<_, String>(1)?.replace('\u{1f}', "::"),
                config,
            },
        );
    }
    let mut options = HashMap::new();
    if has_table(conn, "deck_config")? {
        let mut st = conn.prepare("SELECT id, name, config FROM deck_config")?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            let config: Vec<u8> = r.get::<_, Option<Vec<u8>>>(2)?.unwrap_or_default();
            let mut o = DeckOptions {
                preset: plain(&r.get::<_, String>(1)?),
                ..DeckOptions::default()
            };
            let (mut p5, mut p6) = (Vec::new(), Vec::new());
            for (f, v) in proto_fields(&config) {
                match (f, v) {
                    (1, v) => o.learning_steps.extend(v.floats()),
                    (2, v) => o.relearning_steps.extend(v.floats()),
                    (5, v) => p5.extend(v.floats()),
                    (6, v) => p6.extend(v.floats()),
                    (9, Proto::Varint(n)) => o.new_per_day = per_day(i64::try_from(n).ok()),
                    (10, Proto::Varint(n)) => o.reviews_per_day = per_day(i64::try_from(n).ok()),
                    (16, Proto::Varint(n)) => {
                        o.maximum_interval = max_interval(i64::try_from(n).ok())
                    }
                    (37, Proto::Fixed32(x)) => {
                        o.desired_retention = retention(Some(f64::from(f32::from_bits(x))))
                    }
                    _ => {}
                }
            }
            o.learning_steps = steps(o.learning_steps);
            o.relearning_steps = steps(o.relearning_steps);
            o.fsrs_parameters = fsrs_params(if p6.is_empty() { p5 } else { p6 });
            options.insert(r.get(0)?, o);
        }
    }
    let crt: i64 = conn.query_row("SELECT crt FROM col", [], |r| r.get(0))?;
    Ok(Catalog {
        types,
        decks: names,
        options,
        crt,
    })
}

/// One top-level value of a protobuf message.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Proto<'a> {
    Varint(u64),
    Fixed64(u64),
    Bytes(&'a [u8]),
    Fixed32(u32),
}

impl Proto<'_> {
    /// The floats this value holds: one (`fixed32`) or a packed list.
    fn floats(self) -> Vec<f64> {
        match self {
            Proto::Fixed32(x) => vec![f64::from(f32::from_bits(x))],
            Proto::Bytes(b) if b.len() % 4 == 0 => b
                .chunks_exact(4)
                .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect(),
            _ => Vec::new(),
        }
    }
}

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

/// The top-level fields of a protobuf message, in order; reading stops at
/// the first that cannot be read (a damaged message gives what came before).
fn proto_fields(mut buf: &[u8]) -> Vec<(u64, Proto<'_>)> {
    let mut out = Vec::new();
    while !buf.is_empty() {
        let Some(key) = varint(&mut buf) else { break };
        let value = match key & 7 {
            0 => varint(&mut buf).map(Proto::Varint),
            1 => buf.get(..8).map(|b| {
                let v = u64::from_le_bytes(b.try_into().unwrap_or([0; 8]));
                buf = &buf[8..];
                Proto::Fixed64(v)
            }),
            2 => varint(&mut buf).and_then(|n| {
                let n = usize::try_from(n).ok()?;
                let b = buf.get(..n)?;
                buf = &buf[n..];
                Some(Proto::Bytes(b))
            }),
            5 => buf.get(..4).map(|b| {
                let v = u32::from_le_bytes(b.try_into().unwrap_or([0; 4]));
                buf = &buf[4..];
                Proto::Fixed32(v)
            }),
            _ => None,
        };
        let Some(value) = value else { break };
        out.push((key >> 3, value));
    }
    out
}

/// The value of top-level varint field `field` of a protobuf message
/// (`None` when absent, i.e. zero).
fn proto_varint(buf: &[u8], field: u64) -> Option<u64> {
    proto_fields(buf).into_iter().find_map(|(f, v)| match v {
        Proto::Varint(v) if f == field => Some(v),
        _ => None,
    })
}

/// What a note becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Basic,
    Reversed,
    Cloze,
    Typed,
    /// Reversed when its third field is filled, else basic.
    OptionalReversed,
    /// A note type of its own: the first field its first card type asks is
    /// the front, the others (labelled) the back.
    Custom {
        front: usize,
    },
    /// Image Occlusion: a picture is the card.
    Image,
}

/// The kind of a note type: by Anki's stock kind where kept, else by its
/// name, else by its shape.
fn kind_of(t: &NoteType) -> Kind {
    let (fields, templates) = (t.fields.len(), t.questions.len());
    // A note type made from a stock one keeps its stock kind whatever its
    // fields became: trusted only with the stock shape.
    match (t.stock, t.cloze, fields, templates) {
        (Some(1), false, 2, 1) => return Kind::Basic,
        (Some(2), false, 2, 2) => return Kind::Reversed,
        (Some(3), false, 3, 2) => return Kind::OptionalReversed,
        (Some(4), false, 2, 1) => return Kind::Typed,
        (Some(5), true, _, _) => return Kind::Cloze,
        (Some(6), _, _, _) => return Kind::Image,
        _ => {}
    }
    if t.cloze {
        return Kind::Cloze;
    }
    match (t.name.as_str(), fields, templates) {
        ("Basic", 2, 1) => Kind::Basic,
        ("Basic (and reversed card)", 2, 2) => Kind::Reversed,
        ("Basic (optional reversed card)", 3, 2) => Kind::OptionalReversed,
        ("Basic (type in the answer)", 2, 1) => Kind::Typed,
        (_, 2, 1) if t.questions[0].contains("{{type:") => Kind::Typed,
        (_, 2, 1) if first_asked(t) == 0 => Kind::Basic,
        (_, 2, 2) if first_asked(t) == 0 => Kind::Reversed,
        _ => Kind::Custom {
            front: first_asked(t),
        },
    }
}

/// The index of the first field the first card type's question shows
/// (`{{Name}}`, `{{text:Name}}`, not a `{{#section}}`); the first field when
/// it names none.
fn first_asked(t: &NoteType) -> usize {
    let q = t.questions.first().map_or("", String::as_str);
    let mut rest = q;
    while let Some(i) = rest.find("{{") {
        let after = &rest[i + 2..];
        let Some(j) = after.find("}}") else { break };
        let inner = after[..j].trim();
        rest = &after[j + 2..];
        if inner.starts_with(['#', '^', '/', '!']) {
            continue;
        }
        let name = inner.rsplit(':').next().unwrap_or(inner).trim();
        if let Some(k) = t.fields.iter().position(|f| f == name) {
            return k;
        }
    }
    0
}

/// What a kind of note type is called in the summary.
fn kind_word(kind: Kind, t: &NoteType) -> String {
    match kind {
        Kind::Basic => "basic".into(),
        Kind::Reversed => "reversed".into(),
        Kind::Cloze => "cloze".into(),
        Kind::Typed => "typed".into(),
        Kind::OptionalReversed => {
            "reversed where its Add Reverse field is filled, else basic".into()
        }
        Kind::Custom { front } => format!(
            "basic: front {:?}, the other fields labelled on the back",
            plain(t.fields.get(front).map_or("", String::as_str))
        ),
        Kind::Image => "not imported (image occlusion)".into(),
    }
}

/// A note type as it was mapped, for the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedType {
    /// Its name in Anki.
    pub name: String,
    /// What its notes became.
    pub becomes: String,
    pub notes: usize,
}

/// A note left out, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedNote {
    pub note: i64,
    pub note_type: String,
    pub why: String,
}

/// A field whose math flipcard cannot render, kept as text.
#[derive(Debug, Clone, PartialEq)]
pub struct UnrenderedMath {
    pub deck: String,
    pub card: String,
    pub field: String,
}

/// Card states kept: the items to mark (applied by the caller through the
/// store), and how many cards were flagged (their flags are tags).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct KeptStates {
    pub suspended: Vec<ItemKey>,
    pub buried: Vec<ItemKey>,
    pub leeches: Vec<ItemKey>,
    pub flagged: usize,
    /// Due date, interval and memory state of every item with a history.
    pub due: HashMap<ItemKey, KeptState>,
}

/// A deck whose id would have been a bundled deck's.
#[derive(Debug, Clone, PartialEq)]
pub struct RenamedDeck {
    pub name: String,
    pub wanted: String,
    pub id: String,
}

/// Anki's flag numbers as tags: the tags `flag:N` searches for.
use crate::catalog::query::FLAGS;

/// One card of the collection, as read.
struct CardRow {
    id: i64,
    nid: i64,
    ord: i64,
    deck: i64,
    kind: i64,
    queue: i64,
    due: i64,
    flags: i64,
    data: String,
    /// The interval in days (review cards).
    ivl: i64,
}

/// The due date Anki gives a card: a day number from the collection's day
/// 0 for review cards (and learning cards across days), a time in seconds
/// for learning cards within a day. `None` for a new card or a date out of
/// range.
fn anki_due(c: &CardRow, crt: i64) -> Option<DateTime<Utc>> {
    let secs = match c.kind {
        2 => crt.checked_add(c.due.checked_mul(86_400)?)?,
        1 | 3 if c.due > 1_000_000_000 => c.due,
        1 | 3 => crt.checked_add(c.due.checked_mul(86_400)?)?,
        _ => return None,
    };
    DateTime::<Utc>::from_timestamp(secs, 0).filter(|t| (1970..=9999).contains(&t.year()))
}

/// The FSRS memory state Anki keeps in a card's `data` (`s`, `d`).
fn memory_state(data: &str) -> (Option<f64>, Option<f64>) {
    let v: serde_json::Value = serde_json::from_str(data).unwrap_or_default();
    (v["s"].as_f64(), v["d"].as_f64())
}

/// What Anki had of a card with a schedule, as the state flipcard keeps:
/// its state by Anki's card type, its due date, memory state, and when it
/// was last reviewed (Anki's `lrt` in the card's data; else its due date
/// less its interval). Without an FSRS memory state, a review card's
/// stability is its interval (the interval at which recall is at the
/// desired retention). The state holds from that last review (at most
/// `now`); the caller moves it to the card's last answer when the review
/// history has some.
fn kept_state(c: &CardRow, due: DateTime<Utc>, now: DateTime<Utc>) -> Option<KeptState> {
    let state = match c.kind {
        1 => State::Learning,
        2 => State::Review,
        3 => State::Relearning,
        _ => return None,
    };
    let (s, difficulty) = memory_state(&c.data);
    let v: serde_json::Value = serde_json::from_str(&c.data).unwrap_or_default();
    let ivl = c.ivl.clamp(0, 36_500);
    let last_review = v["lrt"]
        .as_i64()
        .and_then(|t| DateTime::<Utc>::from_timestamp(t, 0))
        .or_else(|| (state == State::Review).then(|| due - chrono::TimeDelta::days(ivl)))
        .filter(|t| t.year() >= 1970 && *t <= now);
    let stability = s.or_else(|| (state == State::Review && ivl > 0).then_some(ivl as f64));
    Some(KeptState {
        at: last_review.unwrap_or(now),
        state,
        due,
        stability,
        difficulty,
        last_review,
    })
}

fn read_collection(
    conn: &Connection,
    path: &Path,
    with_cloze: bool,
    reserved: &HashSet<String>,
    now: DateTime<Utc>,
) -> Result<AnkiImport, ReadError> {
    let catalog = if has_table(conn, "notetypes")? {
        catalog_v18(conn)?
    } else {
        catalog_legacy(conn)?
    };
    let mut out = AnkiImport::default();

    // Cards by note, in card order; a card in a filtered deck belongs to
    // its home deck, with its due date there.
    let mut cards_of: HashMap<i64, Vec<CardRow>> = HashMap::new();
    {
        let mut st = conn.prepare(
            "SELECT id, nid, ord, CASE WHEN odid <> 0 THEN odid ELSE did END, type, queue, \
             CASE WHEN odid <> 0 AND odue <> 0 THEN odue ELSE due END, flags, coalesce(data, ''), \
             ivl FROM cards ORDER BY nid, ord",
        )?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            let c = CardRow {
                id: r.get(0)?,
                nid: r.get(1)?,
                ord: r.get(2)?,
                deck: r.get(3)?,
                kind: r.get(4)?,
                queue: r.get(5)?,
                due: r.get(6)?,
                flags: r.get(7)?,
                data: r.get(8)?,
                ivl: r.get(9)?,
            };
            cards_of.entry(c.nid).or_default().push(c);
        }
    }

    struct Note {
        id: i64,
        kind: Kind,
        /// The note type's fields, converted.
        fields: Vec<(String, bool)>,
        tags: Vec<String>,
        leech: bool,
        /// The note type's field names (a custom type labels its back).
        labels: Vec<String>,
    }
    let mut by_deck: BTreeMap<String, Vec<Note>> = BTreeMap::new();
    let mut mapped: BTreeMap<i64, (usize, BTreeMap<&'static str, usize>)> = BTreeMap::new();
    let mut seen_any = false;
    {
        let mut st = conn.prepare("SELECT id, mid, flds, tags FROM notes ORDER BY id")?;
        let mut rows = st.query([])?;
        while let Some(r) = rows.next()? {
            seen_any = true;
            let id: i64 = r.get(0)?;
            let mid: i64 = r.get(1)?;
            let flds: String = r.get(2)?;
            let tags: String = r.get(3)?;
            let Some(t) = catalog.types.get(&mid) else {
                out.skipped.push(SkippedNote {
                    note: id,
                    note_type: format!("#{mid}"),
                    why: "its note type is missing from the collection".into(),
                });
                continue;
            };
            let kind = kind_of(t);
            let skip = |why: String| SkippedNote {
                note: id,
                note_type: plain(&t.name),
                why,
            };
            if kind == Kind::Image {
                out.skipped.push(skip(
                    "an image occlusion note is a picture, which flipcard cannot show".into(),
                ));
                mapped.entry(mid).or_default().0 += 1;
                continue;
            }
            if kind == Kind::Cloze && !with_cloze {
                out.cloze_left_out += 1;
                continue;
            }
            let mut fields = Vec::new();
            let mut too_large = None;
            for (i, html) in flds.split('\u{1f}').enumerate() {
                let (text, media, rendered) = html_to_text(html, kind == Kind::Cloze);
                out.media_refs += media;
                if text.len() > MAX_FIELD_BYTES {
                    too_large = Some((i, text.len()));
                }
                fields.push((text, rendered));
            }
            if let Some((i, len)) = too_large {
                out.skipped.push(skip(format!(
                    "field {} is {} MiB of text; a card's text may be at most {} MiB",
                    i + 1,
                    len.div_ceil(1 << 20),
                    MAX_FIELD_BYTES >> 20
                )));
                continue;
            }
            let text = |i: usize| fields.get(i).map_or("", |f| f.0.as_str());
            let kind = match kind {
                Kind::OptionalReversed if text(2).is_empty() => Kind::Basic,
                Kind::OptionalReversed => Kind::Reversed,
                Kind::Typed if text(1).is_empty() => Kind::Basic,
                k => k,
            };
            let front = match kind {
                Kind::Custom { front } => front,
                _ => 0,
            };
            if text(front).is_empty() {
                let why = if flds
                    .split('\u{1f}')
                    .nth(front)
                    .unwrap_or("")
                    .trim()
                    .is_empty()
                {
                    "its front is empty"
                } else {
                    "its front is only media, which is not imported"
                };
                out.skipped.push(skip(why.into()));
                continue;
            }
            if kind == Kind::Cloze {
                match crate::deck::cloze::parse(text(0)) {
                    Err(e) => {
                        out.skipped.push(skip(format!(
                            "its cloze text cannot be read ({})",
                            flipcard_text::safe::one_line(&e.message)
                        )));
                        continue;
                    }
                    Ok(pieces)
                        if !pieces
                            .iter()
                            .any(|p| matches!(p, crate::deck::cloze::Piece::Deletion { .. })) =>
                    {
                        out.skipped
                            .push(skip("its text has no cloze deletion".into()));
                        continue;
                    }
                    Ok(_) => {}
                }
            }
            let entry = mapped.entry(mid).or_default();
            entry.0 += 1;
            *entry
                .1
                .entry(match kind {
                    Kind::Basic | Kind::Custom { .. } => "basic",
                    Kind::Reversed => "reversed",
                    Kind::Cloze => "cloze",
                    _ => "typed",
                })
                .or_default() += 1;
            let cards = cards_of.get(&id).map_or(&[][..], Vec::as_slice);
            let deck = cards
                .first()
                .and_then(|c| catalog.decks.get(&c.deck))
                .map(|d| d.name.clone())
                .unwrap_or_else(|| "Default".to_string());
            let mut tags: Vec<String> = tags
                .split_whitespace()
                .map(tag)
                .filter(|t| !t.is_empty())
                .collect();
            let leech = tags.iter().any(|t| t.eq_ignore_ascii_case("leech"));
            tags.retain(|t| !t.eq_ignore_ascii_case("leech"));
            for c in cards {
                if let Some(flag) = usize::try_from(c.flags & 7)
                    .ok()
                    .and_then(|f| f.checked_sub(1))
                    .and_then(|f| FLAGS.get(f))
                {
                    out.states.flagged += 1;
                    if !tags.iter().any(|t| t == flag) {
                        tags.push(flag.to_string());
                    }
                }
            }
            by_deck.entry(deck).or_default().push(Note {
                id,
                kind,
                fields,
                tags,
                leech,
                labels: t.fields.clone(),
            });
            out.notes += 1;
        }
    }
    if !seen_any {
        return Err(ReadError::Anki(AnkiError::Empty {
            path: path.to_path_buf(),
        }));
    }
    for (mid, (notes, kinds)) in &mapped {
        let t = &catalog.types[mid];
        let kind = kind_of(t);
        let becomes = if kind == Kind::OptionalReversed {
            kinds
                .iter()
                .map(|(k, n)| format!("{k} ({n})"))
                .collect::<Vec<_>>()
                .join(", ")
                + " by its Add Reverse field"
        } else {
            kind_word(kind, t)
        };
        out.note_types.push(MappedType {
            name: plain(&t.name),
            becomes,
            notes: *notes,
        });
    }

    // Deck ids from the names, unique, none a bundled deck's.
    let mut taken: HashSet<String> = reserved.clone();
    // Where each base's count stopped: many names of one slug take one
    // step each.
    let mut next_of: HashMap<String, u64> = HashMap::new();
    let mut card_of_note: HashMap<i64, (String, String, Kind)> = HashMap::new();
    let deck_options: HashMap<&str, &DeckOptions> = catalog
        .decks
        .values()
        .filter_map(|d| Some((d.name.as_str(), catalog.options.get(&d.config?)?)))
        .collect();
    let mut leech_notes = HashSet::new();
    // A deck `A::B` sits under `A`: a level with no notes of its own is
    // made a deck too (empty), so the tree stays whole.
    let levels: Vec<String> = by_deck
        .keys()
        .flat_map(|name| {
            let parts: Vec<&str> = name.split("::").collect();
            (1..parts.len())
                .map(|n| parts[..n].join("::"))
                .collect::<Vec<_>>()
        })
        .collect();
    for level in levels {
        by_deck.entry(level).or_default();
    }
    let mut id_of_name: HashMap<String, String> = HashMap::new();
    for (name, notes) in &by_deck {
        let wanted = slug(&name.replace("::", " "));
        let base = if reserved.contains(&wanted) {
            format!("{wanted}-anki")
        } else {
            wanted.clone()
        };
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
        if reserved.contains(&wanted) {
            out.renamed.push(RenamedDeck {
                name: plain(name),
                wanted,
                id: id.clone(),
            });
        }
        let mut text = String::new();
        text.push_str("# Imported from Anki");
        text.push_str(&format!(" (deck {name:?}).\n[deck]\n"));
        text.push_str(&format!("id = {}\n", toml_string(&id)));
        // Names sort parents first: `A` before `A::B`. A subdeck is titled
        // by its own name (`B`), as Anki's deck list shows it, when it sits
        // under its parent; else by its whole name.
        let parent = name
            .rsplit_once("::")
            .and_then(|(up, own)| Some((id_of_name.get(up)?, own)));
        let title = match parent {
            Some((_, own)) if !plain(own).trim().is_empty() => plain(own),
            _ => plain(name),
        };
        text.push_str(&format!("title = {}\n", toml_string(&title)));
        if let Some((parent, _)) = parent {
            text.push_str(&format!("parent = {}\n", toml_string(parent)));
        }
        id_of_name.insert(name.clone(), id.clone());
        text.push_str("languages = [\"en\"]\n");
        for note in notes {
            let card_id = format!("n{}", note.id);
            let t = |i: usize| note.fields.get(i).map_or("", |f| f.0.as_str());
            let (front_i, back): (usize, String) = match note.kind {
                Kind::Custom { front } => {
                    let names = &note.labels;
                    let back = note
                        .fields
                        .iter()
                        .enumerate()
                        .filter(|(i, f)| *i != front && !f.0.is_empty())
                        .map(|(i, f)| {
                            let label = names
                                .get(i)
                                .map_or_else(|| format!("Field {}", i + 1), |n| plain(n));
                            format!("{label}: {}", f.0)
                        })
                        .collect::<Vec<_>>()
                        .join("\n");
                    (front, back)
                }
                _ => (0, t(1).to_string()),
            };
            for (i, f) in note.fields.iter().enumerate() {
                let used = i == front_i || matches!(note.kind, Kind::Custom { .. }) || i == 1;
                if used && !f.1 {
                    out.math_not_rendered.push(UnrenderedMath {
                        deck: id.clone(),
                        card: card_id.clone(),
                        field: note
                            .labels
                            .get(i)
                            .map_or_else(|| format!("field {}", i + 1), |n| plain(n)),
                    });
                }
            }
            text.push_str("\n[[card]]\n");
            text.push_str(&format!("id = {}\n", toml_string(&card_id)));
            match note.kind {
                Kind::Reversed => text.push_str("kind = \"reversed\"\n"),
                Kind::Cloze => text.push_str("kind = \"cloze\"\n"),
                Kind::Typed => text.push_str("kind = \"typed\"\n"),
                _ => {}
            }
            // A cloze card keeps its deletions in `text`; the others ask `front`.
            let key = if note.kind == Kind::Cloze {
                "text"
            } else {
                "front"
            };
            text.push_str(&format!("{key} = {}\n", toml_string(t(front_i))));
            // An empty field stays empty (`back = ''`).
            if note.kind != Kind::Cloze || !back.is_empty() {
                text.push_str(&format!("back = {}\n", toml_string(&back)));
            }
            if note.kind == Kind::Typed {
                text.push_str(&format!("accept = [{}]\n", toml_string(&back)));
            }
            if !note.tags.is_empty() {
                let tags: Vec<String> = note.tags.iter().map(|t| toml_string(t)).collect();
                text.push_str(&format!("tags = [{}]\n", tags.join(", ")));
            }
            if note.leech {
                leech_notes.insert(note.id);
            }
            card_of_note.insert(note.id, (id.clone(), card_id, note.kind));
        }
        out.decks.push(ImportedDeck {
            id,
            name: name.clone(),
            toml: text,
            cards: notes.len(),
            options: deck_options.get(name.as_str()).map(|o| (*o).clone()),
        });
    }

    // Cards (by Anki card id) as the log names them, and their states.
    let mut cards: HashMap<i64, CardRef> = HashMap::new();
    for c in cards_of.values().flatten() {
        let Some((deck, card, kind)) = card_of_note.get(&c.nid) else {
            continue;
        };
        let direction = match (kind, c.ord) {
            (Kind::Reversed, 1) => Some(Direction::Backward),
            // Anki's card `ord` n of a cloze note is deletion c(n+1);
            // a deck numbers its deletions up to c999.
            (Kind::Cloze, n) if (0..i64::from(MAX_NUMBER)).contains(&n) => {
                Some(Direction::Cloze(n as u16 + 1))
            }
            (Kind::Cloze, _) => None,
            (_, 0) => Some(Direction::Forward),
            _ => None,
        };
        if let Some(direction) = direction {
            let key = ItemKey {
                deck: deck.clone(),
                card: card.clone(),
                direction,
            };
            match c.queue {
                -1 => out.states.suspended.push(key.clone()),
                -2 | -3 => out.states.buried.push(key.clone()),
                _ => {}
            }
            if leech_notes.contains(&c.nid) {
                out.states.leeches.push(key.clone());
            }
            // Anki's longest interval is 36,500 days: a due date further
            // off than that from now is not one Anki gave.
            let bound = now + chrono::TimeDelta::days(36_600);
            if let Some(kept) = anki_due(c, catalog.crt)
                .filter(|d| *d <= bound)
                .and_then(|due| kept_state(c, due, now))
            {
                out.states.due.insert(key, kept);
            }
        }
        cards.insert(
            c.id,
            CardRef {
                deck: deck.clone(),
                card: card.clone(),
                direction,
            },
        );
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
                        balanced_days: None,
                    });
                }
                _ => out.reviews_skipped += 1,
            }
        }
    }
    // A kept state holds from the card's last answer Anki had, when the
    // review history has it (the answers are in time order).
    for r in &out.reviews {
        if let Some(k) = out.states.due.get_mut(&r.key) {
            k.at = r.reviewed_at;
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
/// and `<br>` were; list items as `- ` lines; table cells apart, ` | `
/// between them), bold as `**…**` and italic as `*…*` (the reader's
/// markup), `<sup>`/`<sub>` as Unicode super- and subscripts (`^(…)` and
/// `_(…)` where a character has none), entities decoded, MathJax `\(…\)`
/// and `\[…\]` as `$…$` and `$$…$$`, other dollars escaped. Images and
/// sounds are dropped; the count of them is returned beside the text, and
/// whether its math (if any) renders. Math that flipcard cannot render is
/// kept as plain text. With `cloze`, deletions inside math (`\(F =
/// {{c1::k}} x\)`) stay inside it: the math is checked as revealed.
pub(crate) fn html_to_text(html: &str, cloze: bool) -> (String, usize, bool) {
    let (text, media) = strip_tags(html);
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
        .filter(|l| !l.is_empty() && l != "-" && l != "|")
        .collect();
    let joined = lines.join("\n");
    let with_math = convert_math(&joined, true);
    if renders(&with_math, cloze) {
        (with_math, media, true)
    } else {
        (convert_math(&joined, false), media, false)
    }
}

/// Whether the math of `text` renders; a cloze text's as revealed (each
/// deletion replaced by its answer).
fn renders(text: &str, cloze: bool) -> bool {
    if cloze && let Ok(pieces) = crate::deck::cloze::parse(text) {
        let revealed: String = pieces
            .iter()
            .map(|p| match p {
                crate::deck::cloze::Piece::Text(t) => *t,
                crate::deck::cloze::Piece::Deletion { answer, .. } => answer,
            })
            .collect();
        return flipcard_text::check(&revealed).is_empty();
    }
    flipcard_text::check(text).is_empty()
}

/// The structure of a field's HTML as text (entities not yet decoded), and
/// the count of images, sounds and videos. Linear in the text: the closing
/// tag of a `<sup>` or `<sub>` is searched for once from where the last
/// search ended (remembered per name), and a script's own text is read once
/// more, its tags dropped.
fn strip_tags(html: &str) -> (String, usize) {
    strip(html, true)
}

fn strip(html: &str, scripts: bool) -> (String, usize) {
    let mut media = html.matches("[sound:").count();
    let mut text = String::new();
    let mut rest = html;
    // Whether a cell of the current table row was written.
    let mut cell = false;
    // The next `</sup` and `</sub` at or after where each was last looked
    // for (`None`: there is none after it).
    let mut closers: [Option<Option<usize>>; 2] = [None, None];
    while let Some(i) = rest.find('<') {
        text.push_str(&rest[..i]);
        let Some(end) = rest[i..].find('>') else {
            text.push_str(&rest[i..]);
            rest = "";
            break;
        };
        let tag = rest[i + 1..i + end].trim().to_ascii_lowercase();
        let closing = tag.starts_with('/');
        let name: String = tag
            .trim_start_matches('/')
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect();
        rest = &rest[i + end + 1..];
        match name.as_str() {
            "br" => text.push('\n'),
            "sup" | "sub" if scripts && !closing => {
                // The script's text runs to its closing tag (tags inside it
                // are dropped); the rest goes on after it.
                let at = html.len() - rest.len();
                let slot = &mut closers[usize::from(name == "sub")];
                let close = match *slot {
                    Some(Some(c)) if c >= at => Some(c),
                    Some(None) => None,
                    _ => find_ascii_ci(html, at, if name == "sup" { "</sup" } else { "</sub" }),
                };
                *slot = Some(close);
                let Some(c) = close else { continue };
                let (inner, m) = strip(&html[at..c], false);
                media += m;
                let after = &html[c..];
                rest = after.find('>').map_or("", |k| &after[k + 1..]);
                let inner = inner.trim();
                match script(&decode_entities(inner), name == "sup") {
                    Some(s) => text.push_str(&s),
                    None if inner.is_empty() => {}
                    None => {
                        text.push(if name == "sup" { '^' } else { '_' });
                        text.push('(');
                        text.push_str(inner);
                        text.push(')');
                    }
                }
            }
            "b" | "strong" => text.push_str("**"),
            "i" | "em" => text.push('*'),
            "li" if !closing => text.push_str("\n- "),
            "tr" => {
                cell = false;
                text.push('\n');
            }
            "td" | "th" if !closing => {
                if cell {
                    text.push_str(" | ");
                }
                cell = true;
            }
            "div" | "p" | "li" | "ul" | "ol" | "table" | "h1" | "h2" | "h3" | "h4" if closing => {
                text.push('\n')
            }
            "img" | "audio" | "video" => media += 1,
            _ => {}
        }
    }
    text.push_str(rest);
    (text, media)
}

/// The first `needle` (ASCII, lower case) in `hay` at or after `from`,
/// ignoring ASCII case.
fn find_ascii_ci(hay: &str, from: usize, needle: &str) -> Option<usize> {
    let h = hay.as_bytes();
    let n = needle.as_bytes();
    (from..h.len().saturating_sub(n.len() - 1)).find(|&i| h[i..i + n.len()].eq_ignore_ascii_case(n))
}

/// `s` as Unicode superscript (or subscript) characters, when every
/// character has one.
fn script(s: &str, sup: bool) -> Option<String> {
    const SUP: &str = "0⁰1¹2²3³4⁴5⁵6⁶7⁷8⁸9⁹+⁺-⁻−⁻=⁼(⁽)⁾nⁿiⁱ";
    const SUB: &str = "0₀1₁2₂3₃4₄5₅6₆7₇8₈9₉+₊-₋−₋=₌(₍)₎aₐeₑoₒxₓhₕkₖlₗmₘnₙpₚsₛtₜiᵢrᵣuᵤvᵥjⱼ";
    let table: Vec<char> = (if sup { SUP } else { SUB }).chars().collect();
    if s.is_empty() {
        return None;
    }
    s.chars()
        .map(|c| table.chunks_exact(2).find(|p| p[0] == c).map(|p| p[1]))
        .collect()
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
        let (t, media, rendered) = html_to_text(
            "<div>Torque &amp; spin:&nbsp;\\(\\tau = I\\alpha\\)</div><div><img src=\"a.png\"></div>costs $5<br>\\[E = mc^2\\][sound:x.mp3]",
            false,
        );
        assert!(rendered);
        assert_eq!(
            t,
            "Torque & spin: $\\tau = I\\alpha$\ncosts \\$5\n$$E = mc^2$$"
        );
        assert_eq!(media, 2);
        assert_eq!(
            html_to_text("L = I&omega; &amp;c &bogus; &#8594;", false).0,
            "L = Iω &c &bogus; →"
        );
        assert!(flipcard_text::check(&t).is_empty());
        // Math flipcard cannot render stays as written, dollars escaped.
        let (t, _, rendered) = html_to_text("\\(\\unknowncommand x\\) for $1", false);
        assert!(!rendered);
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
        let (t, _, _) = html_to_text(&"&".repeat(2_000_000), false);
        assert_eq!(t.len(), 2_000_000);
        assert!(t.bytes().all(|b| b == b'&'));
        let (t, _, _) = html_to_text(&"\\(x^2\\)".repeat(250_000), false);
        assert_eq!(t, "$x^2$".repeat(250_000));
        // Scripts without a closing tag, and nested ones: each closer is
        // searched for once.
        let (t, _, _) = html_to_text(&"<sup>2".repeat(400_000), false);
        assert_eq!(t, "2".repeat(400_000));
        let nested = format!("{}x{}", "<sub>".repeat(200_000), "</sub>".repeat(200_000));
        assert_eq!(html_to_text(&nested, false).0, "ₓ");
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

    /// A varint as protobuf writes it.
    fn encode_varint(mut v: u64, out: &mut Vec<u8>) {
        loop {
            let b = (v & 0x7f) as u8;
            v >>= 7;
            if v == 0 {
                out.push(b);
                return;
            }
            out.push(b | 0x80);
        }
    }

    proptest::proptest! {
        /// Any bytes: read without a panic, and never past the message.
        #[test]
        fn protobuf_fields_of_any_bytes_are_read_without_panic(
            bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..64),
        ) {
            let _ = proto_fields(&bytes);
            let _ = proto_varint(&bytes, 1);
        }

        /// Fields written are read back, in order: varints, strings, packed
        /// floats and fixed32 floats.
        #[test]
        fn protobuf_fields_written_are_read_back(
            fields in proptest::collection::vec(
                (1u64..300, proptest::prelude::any::<u64>(), proptest::collection::vec(-1e6f32..1e6, 0..5), 0u8..3),
                0..8,
            ),
        ) {
            let mut buf = Vec::new();
            for (field, v, floats, wire) in &fields {
                match wire {
                    0 => {
                        encode_varint(field << 3, &mut buf);
                        encode_varint(*v, &mut buf);
                    }
                    1 => {
                        encode_varint((field << 3) | 2, &mut buf);
                        encode_varint(floats.len() as u64 * 4, &mut buf);
                        for f in floats {
                            buf.extend(f.to_le_bytes());
                        }
                    }
                    _ => {
                        encode_varint((field << 3) | 5, &mut buf);
                        buf.extend((*v as u32).to_le_bytes());
                    }
                }
            }
            let read = proto_fields(&buf);
            proptest::prop_assert_eq!(read.len(), fields.len());
            for ((field, v, floats, wire), (f, got)) in fields.iter().zip(read) {
                proptest::prop_assert_eq!(f, *field);
                match wire {
                    0 => proptest::prop_assert_eq!(got, Proto::Varint(*v)),
                    1 => proptest::prop_assert_eq!(
                        got.floats(),
                        floats.iter().map(|x| f64::from(*x)).collect::<Vec<_>>()
                    ),
                    _ => proptest::prop_assert_eq!(got, Proto::Fixed32(*v as u32)),
                }
            }
        }

        /// flipcard text written as Anki HTML (`export --apkg`) reads back
        /// as the same text (`import`): math, escaped dollars, `<`, `&`,
        /// line breaks, cloze deletions inside math.
        #[test]
        fn text_written_as_anki_html_reads_back_the_same(
            lines in proptest::collection::vec(
                proptest::collection::vec(
                    proptest::sample::select(vec![
                        "force", "a", "<", "&", "a&b", "\\$5", "$x^2$", "$\\omega_1$",
                        "$$E = mc^2$$", "×", "θ", "$F = -{{c1::k}} x$", "{{c2::mass}}",
                    ]),
                    1..6,
                ),
                1..4,
            ),
        ) {
            let text = lines
                .iter()
                .map(|words| words.join(" "))
                .collect::<Vec<_>>()
                .join("\n");
            let html = crate::interop::apkg::to_html(&text);
            let (back, media, rendered) = html_to_text(&html, true);
            proptest::prop_assert!(rendered);
            proptest::prop_assert_eq!(media, 0);
            proptest::prop_assert_eq!(back, text);
        }

        /// Any HTML: converted without a panic, no tag left, no control
        /// character.
        #[test]
        fn any_html_converts_without_panic_or_tags(
            s in "(<sup>|</sup>|<sub>|</sub>|<b>|</b>|<i>|<li>|</li>|<td>|</tr>|<br>|[a-z0-9 ]|&minus;|−|é|\\\\\\(|\\\\\\)){0,40}",
        ) {
            let (t, _, _) = html_to_text(&s, false);
            proptest::prop_assert!(!t.contains("<sup") && !t.contains("<b>") && !t.contains("<br"));
            proptest::prop_assert!(!t.chars().any(|c| c.is_control() && c != '\n'));
        }
    }

    #[test]
    fn scripts_become_unicode_or_stay_readable() {
        assert_eq!(html_to_text("10<sup>−10</sup> m", false).0, "10⁻¹⁰ m");
        assert_eq!(html_to_text("10<SUP>&minus;3</SUP>", false).0, "10⁻³");
        assert_eq!(html_to_text("v<sub>max</sub>", false).0, "vₘₐₓ");
        assert_eq!(html_to_text("x<sub>Q</sub>", false).0, "x_(Q)");
        assert_eq!(
            html_to_text("<b>F</b> = m<i>a</i>", false).0,
            "**F** = m*a*"
        );
        assert_eq!(
            html_to_text("<ul><li>one</li><li>two</li></ul>", false).0,
            "- one\n- two"
        );
        assert_eq!(
            html_to_text(
                "<table><tr><td>a</td><td>b</td></tr><tr><td>c</td><td>d</td></tr></table>",
                false
            )
            .0,
            "a | b\nc | d"
        );
        assert_eq!(html_to_text("", false).0, "");
    }

    #[test]
    fn protobuf_kind_is_found_past_other_fields() {
        // field 3 (string "ab"), then field 1 = 1 (cloze)
        assert_eq!(proto_varint(&[0x1a, 2, b'a', b'b', 0x08, 1], 1), Some(1));
        assert_eq!(proto_varint(&[0x10, 5], 1), None);
        assert_eq!(proto_varint(&[0x1a, 9, 1], 1), None, "truncated");
    }
}
