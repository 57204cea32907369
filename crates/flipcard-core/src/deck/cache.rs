//! A validated deck kept between runs, so a large collection opens without
//! reading its TOML again.
//!
//! Reading and validating a deck of 50,000 cards (an Anki collection
//! brought over) takes most of a second and a few hundred megabytes: the
//! TOML tree with its spans is large. Yet a deck file that has not changed
//! validates to the same deck every time. So after a deck file loads with
//! no diagnostic at all, the deck is written to the cache folder (in the
//! data folder, `cache/decks/`), under the SHA-256 of what decides the
//! result: the build of flipcard that validated it (`stamp`: its version
//! and the executable's size and time, so any other build validates
//! afresh), the file's name and every byte of it. The next load that finds
//! an entry under that key, with the same bytes in each of the deck's
//! content files, takes the deck from it.
//!
//! What is kept is deliberately narrow: decks of cards only (no prompts,
//! scenes, sections, misconceptions, derivations, declared units, formula
//! cards or links to explanations), which is what a large collection is;
//! a deck with any of them loads from its TOML every time. An entry is
//! untrusted like any file: read only as a regular file (no link, no FIFO),
//! bounded in size, checked against the length and CRC-32 written at its
//! start, and decoded with every length bounded by the bytes present. Any
//! problem with it (missing, damaged, another format, written by another
//! build) is a miss: the deck is read from its TOML as if there were no
//! cache, and the entry written again. A cache that cannot be written (a
//! read-only data folder, a full disk) is skipped without a word: it only
//! ever saves time.
//!
//! `flipcard check` never reads the cache: it validates every deck afresh.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::id::is_id;
use super::model::{Card, CardKind, Deck, Text};

/// The first bytes of an entry; a change of the entry's layout changes it.
const MAGIC: &[u8] = b"flipcard deck cache v2\n";

/// Bytes after [`MAGIC`] before the payload: its length and CRC-32, each
/// little-endian (the key already proves which deck file it is for; the
/// CRC catches an entry damaged on disk).
const HEADER: usize = 12;

/// Deck files smaller than this load fast enough from their TOML.
pub const MIN_CACHED_BYTES: usize = 64 * 1024;

/// An entry larger than this many times its deck file (plus a margin) is
/// not read: a cached deck is never much larger than the file it came from.
const MAX_ENTRY_FACTOR: u64 = 4;

/// Where validated decks are kept, and the build that validated them.
#[derive(Debug, Clone)]
pub struct DeckCache {
    dir: PathBuf,
    stamp: String,
}

/// A SHA-256 digest.
type Digest32 = [u8; 32];

/// Each field borrows the deck when an entry is written (no copy of a
/// large deck is made) and owns it when one is read.
type Map = flipcard_text::LangMap;

#[derive(Serialize, Deserialize)]
struct Entry<'a> {
    /// The SHA-256 of each content file read with the deck, by language.
    content: Vec<(String, Digest32)>,
    id: Cow<'a, str>,
    title: Cow<'a, Map>,
    description: Option<Cow<'a, Map>>,
    languages: Cow<'a, [String]>,
    /// The deck's `parent` and the span of its value in the deck file.
    parent: Option<(Cow<'a, str>, Range<usize>)>,
    /// The cards, laid out for a fast read (see [`Cards`]).
    cards: Cards,
}

/// A deck's cards as three flat lists: every string of every card one
/// after another in one text (checked as UTF-8 once, not string by
/// string), each string's length in bytes, and each card's kind and how
/// many strings each of its fields takes. Reading 50,000 cards is then a
/// copy per string, with nothing decoded twice.
///
/// A card's strings, in order: its id; the front's language and text for
/// each of `front` languages; the back's likewise; each of `accept`
/// answers; for each of `by_lang` languages, the language, then
/// `by_lang_counts`' next number of answers; each of `tags` tags.
#[derive(Serialize, Deserialize, Default)]
struct Cards {
    strings: String,
    lens: Vec<u32>,
    by_lang_counts: Vec<u32>,
    shapes: Vec<Shape>,
}

#[derive(Serialize, Deserialize)]
struct Shape {
    kind: CachedKind,
    front: u32,
    back: u32,
    accept: u32,
    by_lang: u32,
    tags: u32,
}

#[derive(Serialize, Deserialize)]
enum CachedKind {
    Basic,
    Reversed,
    Typed,
    Cloze,
}

/// A deck taken from the cache: the deck, where its `parent` value is in
/// its file, and its content files (path and text).
pub(crate) struct Cached {
    pub deck: Deck,
    pub parent_span: Option<Range<usize>>,
    pub content: Vec<(PathBuf, String)>,
}

/// What a deck file's entry is kept under.
struct Key {
    digest: Digest32,
    /// The digest of the file's name alone: every entry of one deck file
    /// starts with it, so writing a new one removes the old ones.
    prefix: String,
}

fn sha256(parts: &[&[u8]]) -> Digest32 {
    let mut h = Sha256::new();
    for p in parts {
        // Each part's length first, so no two lists of parts hash alike.
        h.update((p.len() as u64).to_le_bytes());
        h.update(p);
    }
    h.finalize().into()
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

impl DeckCache {
    /// A cache in `dir` for decks validated by the build `stamp`.
    pub fn new(dir: PathBuf, stamp: String) -> DeckCache {
        DeckCache { dir, stamp }
    }

    /// What every entry of the deck file named `stem` starts with, by
    /// whichever build it was written: a new build's entry replaces the
    /// old build's, so entries do not pile up with each update.
    fn prefix(&self, stem: &str) -> String {
        let name = sha256(&[stem.as_bytes()]);
        hex(&name[..8])
    }

    fn key(&self, stem: &str, text: &str) -> Key {
        Key {
            digest: sha256(&[
                MAGIC,
                self.stamp.as_bytes(),
                stem.as_bytes(),
                text.as_bytes(),
            ]),
            prefix: self.prefix(stem),
        }
    }

    fn path(&self, key: &Key) -> PathBuf {
        self.dir
            .join(format!("{}-{}.bin", key.prefix, hex(&key.digest)))
    }

    /// The deck file `path` (its name `stem`, about `len` bytes) as
    /// `read` reads it (its text, and what else `read` gives), and the
    /// deck kept for it, when there is one for these bytes whose content
    /// files are the ones it was validated with (`content` reads a
    /// language's file: its path and text, `None` when it cannot be read),
    /// with those files. The entry is found by the file's name and decoded
    /// on this thread while another reads the file and computes the key
    /// its bytes give; it is taken only when that is the key it was
    /// written under (and the text is still large enough to be kept).
    pub(crate) fn get<R: Send>(
        &self,
        stem: &str,
        len: u64,
        read: impl FnOnce() -> (Option<String>, R) + Send,
        content: impl Fn(&str) -> Option<(PathBuf, String)>,
        path: &Path,
    ) -> (Option<String>, R, Option<Cached>) {
        let prefix = self.prefix(stem);
        let found = flipcard_io::entries_starting_with(&self.dir, &format!("{prefix}-"));
        let digest = match found.as_slice() {
            [file] => file
                .file_name()
                .and_then(|n| n.to_str())
                .and_then(|n| n.strip_prefix(&format!("{prefix}-")))
                .and_then(|n| n.strip_suffix(".bin"))
                .map(|d| (file, d)),
            _ => None,
        };
        let Some((file, digest)) = digest else {
            let (text, r) = read();
            return (text, r, None);
        };
        let limit = len.saturating_mul(MAX_ENTRY_FACTOR).saturating_add(1 << 20);
        let (text, r, entry) = std::thread::scope(|s| {
            let reader = s.spawn(|| {
                let (text, r) = read();
                let key = text
                    .as_deref()
                    .filter(|t| t.len() >= MIN_CACHED_BYTES)
                    .map(|t| self.key(stem, t));
                (text, r, key)
            });
            let entry = flipcard_io::read_regular_limited(file, limit)
                .ok()
                .and_then(|b| decode(&b));
            let (text, r, key) = match reader.join() {
                Ok(read) => read,
                Err(panic) => std::panic::resume_unwind(panic),
            };
            let entry = entry.filter(|_| key.is_some_and(|k| hex(&k.digest) == digest));
            (text, r, entry)
        });
        let hit = entry.and_then(|entry| take(entry, &content, path));
        (text, r, hit)
    }

    /// Keeps `deck` under `key` (validated with these content files'
    /// texts, by language), replacing what was kept for the same file. A
    /// deck the cache does not hold (see the module) is not written;
    /// nothing here fails loudly.
    pub(crate) fn put(
        &self,
        (stem, text): (&str, &str),
        deck: &Deck,
        parent_span: Option<Range<usize>>,
        content: &[(String, &str)],
    ) {
        let Some(entry) = Entry::of(deck, parent_span, content) else {
            return;
        };
        let key = &self.key(stem, text);
        let Ok(payload) = postcard::to_allocvec(&entry) else {
            return;
        };
        let mut bytes = Vec::with_capacity(MAGIC.len() + HEADER + payload.len());
        bytes.extend_from_slice(MAGIC);
        bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
        bytes.extend_from_slice(&payload);
        let path = self.path(key);
        // Never through a link or onto something that is not a file.
        if let Ok(meta) = flipcard_io::metadata_no_follow(&path)
            && !meta.is_file()
        {
            return;
        }
        if flipcard_io::create_dir_all(&self.dir).is_err() {
            return;
        }
        for old in flipcard_io::entries_starting_with(&self.dir, &key.prefix) {
            if old != path && flipcard_io::metadata_no_follow(&old).is_ok_and(|m| m.is_file()) {
                let _ = flipcard_io::remove_file(&old);
            }
        }
        let _ = flipcard_io::write_atomic(&path, &bytes, flipcard_io::Durability::Whole);
    }
}

/// The deck of an entry whose key matched, when each of its content
/// files still has the bytes it was validated with.
fn take(
    entry: Entry<'static>,
    content: impl Fn(&str) -> Option<(PathBuf, String)>,
    path: &Path,
) -> Option<Cached> {
    let mut texts = Vec::new();
    if entry.content.len() != entry.languages.len() {
        return None;
    }
    for ((lang, digest), declared) in entry.content.iter().zip(entry.languages.iter()) {
        if lang != declared {
            return None;
        }
        let (file, text) = content(lang)?;
        if sha256(&[text.as_bytes()]) != *digest {
            return None;
        }
        texts.push((file, text));
    }
    let parent_span = entry.parent.as_ref().map(|(_, span)| span.clone());
    Some(Cached {
        deck: entry.into_deck(path)?,
        parent_span,
        content: texts,
    })
}

/// An entry's deck, when its bytes are whole and of this format.
fn decode(bytes: &[u8]) -> Option<Entry<'static>> {
    let rest = bytes.strip_prefix(MAGIC)?;
    if rest.len() < HEADER {
        return None;
    }
    let (header, payload) = rest.split_at(HEADER);
    let len = u64::from_le_bytes(header[..8].try_into().ok()?);
    let crc = u32::from_le_bytes(header[8..].try_into().ok()?);
    if len != payload.len() as u64 || crc32fast::hash(payload) != crc {
        return None;
    }
    let (entry, left): (Entry<'static>, &[u8]) = postcard::take_from_bytes(payload).ok()?;
    left.is_empty().then_some(entry)
}

impl<'a> Entry<'a> {
    /// The entry of a deck the cache holds: cards only.
    fn of(
        deck: &'a Deck,
        parent_span: Option<Range<usize>>,
        content: &[(String, &str)],
    ) -> Option<Entry<'a>> {
        let plain = deck.prompts.is_empty()
            && deck.scenes.is_empty()
            && deck.systems.is_empty()
            && deck.sections.is_empty()
            && deck.units.is_empty()
            && deck.misconceptions.is_empty()
            && deck.explore.is_empty()
            && deck.derivations.is_empty();
        if !plain {
            return None;
        }
        let cards = Cards::of(&deck.cards)?;
        let languages = &deck.languages;
        let content: Vec<(String, Digest32)> = content
            .iter()
            .map(|(lang, text)| (lang.clone(), sha256(&[text.as_bytes()])))
            .collect();
        let same_languages = content.len() == languages.len()
            && content.iter().zip(languages).all(|((l, _), d)| l == d);
        if !same_languages {
            return None;
        }
        let parent = match (&deck.parent, parent_span) {
            (Some(p), Some(span)) => Some((Cow::Borrowed(p.as_str()), span)),
            (None, _) => None,
            (Some(_), None) => return None,
        };
        Some(Entry {
            content,
            parent,
            id: Cow::Borrowed(&deck.id),
            title: Cow::Borrowed(&deck.title.0),
            description: deck.description.as_ref().map(|t| Cow::Borrowed(&t.0)),
            languages: Cow::Borrowed(languages),
            cards,
        })
    }

    /// The deck of an entry, `None` when its cards do not read whole.
    fn into_deck(self, path: &Path) -> Option<Deck> {
        if !is_id(&self.id) || self.parent.as_ref().is_some_and(|(p, _)| !is_id(p)) {
            return None;
        }
        let cards = self.cards.read()?;
        Some(Deck {
            id: self.id.into_owned(),
            title: Text(self.title.into_owned()),
            description: self.description.map(|d| Text(d.into_owned())),
            languages: self.languages.into_owned(),
            cards,
            prompts: Vec::new(),
            scenes: Vec::new(),
            systems: Vec::new(),
            sections: Vec::new(),
            units: Vec::new(),
            misconceptions: Vec::new(),
            explore: Vec::new(),
            derivations: Vec::new(),
            parent: self.parent.map(|(p, _)| p.into_owned()),
            path: path.to_path_buf(),
        })
    }
}

impl Cards {
    /// The cards of a deck the cache holds: of the four plain kinds, with
    /// no explanation, prompt or formula; `None` for any other.
    fn of(cards: &[Card]) -> Option<Cards> {
        let mut out = Cards::default();
        for card in cards {
            let kind = match card.kind {
                CardKind::Basic => CachedKind::Basic,
                CardKind::Reversed => CachedKind::Reversed,
                CardKind::Typed => CachedKind::Typed,
                CardKind::Cloze => CachedKind::Cloze,
                CardKind::Formula => return None,
            };
            if card.explain.is_some() || card.prompt.is_some() || card.formula.is_some() {
                return None;
            }
            let count = |n: usize| u32::try_from(n).ok();
            out.shapes.push(Shape {
                kind,
                front: count(card.front.0.len())?,
                back: count(card.back.0.len())?,
                accept: count(card.accept.len())?,
                by_lang: count(card.accept_by_lang.len())?,
                tags: count(card.tags.len())?,
            });
            out.push(&card.id)?;
            for (lang, text) in card.front.0.iter().chain(card.back.0.iter()) {
                out.push(lang)?;
                out.push(text)?;
            }
            for a in &card.accept {
                out.push(a)?;
            }
            for (lang, answers) in &card.accept_by_lang {
                out.push(lang)?;
                out.by_lang_counts.push(count(answers.len())?);
                for a in answers {
                    out.push(a)?;
                }
            }
            for t in &card.tags {
                out.push(t)?;
            }
        }
        Some(out)
    }

    fn push(&mut self, s: &str) -> Option<()> {
        self.lens.push(u32::try_from(s.len()).ok()?);
        self.strings.push_str(s);
        Some(())
    }

    /// The cards, when every count and length fits what is there and
    /// nothing is left over (anything else is a damaged entry).
    fn read(self) -> Option<Vec<Card>> {
        let mut r = Strings {
            text: &self.strings,
            at: 0,
            lens: self.lens.iter(),
        };
        let mut counts = self.by_lang_counts.iter();
        let mut cards = Vec::with_capacity(self.shapes.len());
        for shape in &self.shapes {
            // An entry is a file like any other: its ids are the deck
            // format's (the key proves the deck file, not the entry).
            let id = r.next().filter(|id| is_id(id))?;
            let front = r.texts(shape.front)?;
            let back = r.texts(shape.back)?;
            let accept = r.list(shape.accept)?;
            let mut accept_by_lang = BTreeMap::new();
            for _ in 0..shape.by_lang {
                let lang = r.next()?;
                let answers = r.list(*counts.next()?)?;
                accept_by_lang.insert(lang, answers);
            }
            let tags = r.list(shape.tags)?;
            cards.push(Card {
                id,
                kind: match shape.kind {
                    CachedKind::Basic => CardKind::Basic,
                    CachedKind::Reversed => CardKind::Reversed,
                    CachedKind::Typed => CardKind::Typed,
                    CachedKind::Cloze => CardKind::Cloze,
                },
                front: Text(front),
                back: Text(back),
                accept,
                accept_by_lang,
                explain: None,
                prompt: None,
                tags,
                formula: None,
            });
        }
        let whole = r.at == r.text.len() && r.lens.len() == 0 && counts.len() == 0;
        whole.then_some(cards)
    }
}

/// The strings of [`Cards`], taken one at a time.
struct Strings<'a> {
    text: &'a str,
    at: usize,
    lens: std::slice::Iter<'a, u32>,
}

impl Strings<'_> {
    /// The next string; `None` past the last, or where a length would cut
    /// the text outside it or inside a character.
    fn next(&mut self) -> Option<String> {
        let len = usize::try_from(*self.lens.next()?).ok()?;
        let end = self.at.checked_add(len)?;
        let s = self.text.get(self.at..end)?;
        self.at = end;
        Some(s.to_owned())
    }

    /// The next `n` strings. Each takes a length, so a count larger than
    /// the lengths left ends at the first missing one.
    fn list(&mut self, n: u32) -> Option<Vec<String>> {
        let mut v = Vec::with_capacity((n as usize).min(self.lens.len()));
        for _ in 0..n {
            v.push(self.next()?);
        }
        Some(v)
    }

    /// A text of `n` languages: language and string, `n` times.
    fn texts(&mut self, n: u32) -> Option<Map> {
        let mut v = Vec::with_capacity((n as usize).min(self.lens.len()));
        for _ in 0..n {
            v.push((self.next()?, self.next()?));
        }
        Some(v.into_iter().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deck() -> Deck {
        let toml = "[deck]\nid = \"big\"\ntitle = \"Big\"\nlanguages = [\"en\"]\n\n[[card]]\nid = \"c1\"\nfront = 'F'\nback = 'B'\n";
        let tree = crate::deck::files::Memory::new([
            (PathBuf::from("d/decks/big.toml"), toml.as_bytes()),
            (PathBuf::from("d/content/big/en.toml"), b"".as_slice()),
        ]);
        let loaded = crate::deck::load::load_tree(&tree, &[PathBuf::from("d/decks")]);
        assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
        loaded.decks.into_iter().next().expect("the deck loads")
    }

    /// An entry of another build is never taken, and the next build's entry
    /// replaces it instead of piling up beside it.
    #[test]
    fn a_new_builds_entry_replaces_the_old_builds() {
        let dir = tempfile::tempdir().unwrap();
        let deck = deck();
        let text = &"the deck file's bytes ".repeat(MIN_CACHED_BYTES / 16);
        let cache = |stamp: &str| DeckCache::new(dir.path().to_path_buf(), stamp.to_string());
        let get = |c: &DeckCache| {
            let read = || (Some(text.clone()), ());
            let content = |_: &str| Some((PathBuf::from("en.toml"), String::new()));
            let (got, (), hit) = c.get(
                "big",
                text.len() as u64,
                read,
                content,
                Path::new("big.toml"),
            );
            assert_eq!(got.as_ref(), Some(text), "the file's text, hit or miss");
            hit
        };
        cache("build 1").put(("big", text), &deck, None, &[("en".to_string(), "")]);
        assert!(get(&cache("build 1")).is_some_and(|c| c.deck.cards == deck.cards));
        assert!(get(&cache("build 2")).is_none(), "another build's entry");
        cache("build 2").put(("big", text), &deck, None, &[("en".to_string(), "")]);
        assert_eq!(flipcard_io::entries(dir.path()).unwrap().len(), 1);
        assert!(get(&cache("build 2")).is_some());
        assert!(get(&cache("build 1")).is_none());
    }

    fn card() -> impl proptest::strategy::Strategy<Value = Card> {
        use proptest::prelude::*;
        let lang = prop_oneof![Just("en"), Just("hi-Latn"), Just("de")].prop_map(String::from);
        let text = proptest::collection::vec((lang.clone(), ".{0,12}"), 0..3)
            .prop_map(|v| Text(v.into_iter().collect()));
        let kind = prop_oneof![
            Just(CardKind::Basic),
            Just(CardKind::Reversed),
            Just(CardKind::Typed),
            Just(CardKind::Cloze),
        ];
        let list = proptest::collection::vec(".{0,6}", 0..3);
        (
            "[a-z0-9]{1,4}(-[a-z0-9]{1,4})?",
            kind,
            text.clone(),
            text,
            list.clone(),
            proptest::collection::btree_map(lang, list.clone(), 0..2),
            list,
        )
            .prop_map(
                |(id, kind, front, back, accept, accept_by_lang, tags)| Card {
                    id,
                    kind,
                    front,
                    back,
                    accept,
                    accept_by_lang,
                    explain: None,
                    prompt: None,
                    tags,
                    formula: None,
                },
            )
    }

    fn through_bytes(cards: &Cards) -> Cards {
        postcard::from_bytes(&postcard::to_allocvec(cards).unwrap()).unwrap()
    }

    proptest::proptest! {
        /// Cards written to the flat layout read back as they were, any
        /// text (multi-byte characters included) in any field.
        #[test]
        fn cards_read_back_as_written(cards in proptest::collection::vec(card(), 0..12)) {
            let flat = Cards::of(&cards).expect("plain cards are kept");
            proptest::prop_assert_eq!(through_bytes(&flat).read(), Some(cards));
        }

        /// A layout whose lengths or counts do not add up (one length
        /// longer, or one card claiming one string more) is refused, never
        /// read as some other deck.
        #[test]
        fn a_layout_that_does_not_add_up_is_refused(
            cards in proptest::collection::vec(card(), 1..8),
            at in proptest::sample::select(vec![0usize, 1, 2, 3, 4]),
            which in 0usize..64,
        ) {
            let mut flat = through_bytes(&Cards::of(&cards).unwrap());
            match at {
                0 if !flat.lens.is_empty() => {
                    let i = which % flat.lens.len();
                    flat.lens[i] += 1;
                }
                1 => flat.shapes[which % cards.len()].tags += 1,
                2 if which % 2 == 0 => {
                    // A card id the deck format refuses, of the same length.
                    let first = flat.lens[0] as usize;
                    flat.strings.replace_range(..first, &"/".repeat(first));
                }
                2 => flat.shapes[which % cards.len()].front += 1,
                3 => flat.lens.push(0),
                _ => flat.strings.push('x'),
            }
            proptest::prop_assert_eq!(flat.read(), None);
        }
    }
}
