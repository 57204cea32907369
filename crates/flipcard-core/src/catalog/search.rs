//! Free text search over every card: the fields of each card (its id, then
//! per language its front and back together), each searched as rendered
//! (`ω₂`) and, when it holds math, as written (`\omega_2`), with a
//! maintained fuzzy matcher (`nucleo-matcher`).
//!
//! Three stages, so that a screen can keep its first frame fast: the texts
//! are gathered from the decks ([`SearchTexts`], a copy into one buffer),
//! the index is built from them ([`SearchIndex`], rendering the math, on
//! any thread), and a [`Search`] matches queries against the index for the
//! items of a catalog.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use chrono::{DateTime, Utc};
use nucleo_matcher::pattern::{AtomKind, CaseMatching, Normalization, Pattern};
use nucleo_matcher::{Matcher, Utf32Str, Utf32String, chars};

use super::{Filter, ItemRow};
use crate::deck::{CardKind, Deck};

/// The least score (per character of the query) a fuzzy match needs: a
/// run of letters scores about 25 a character, letters strewn over a long
/// text far less.
const MIN_SCORE_PER_CHAR: u32 = 10;

/// Below this many candidates a query is matched on the calling thread
/// alone: starting threads would cost more than it saves.
const PARALLEL_FROM: usize = 4096;

/// The texts of every card of some decks, as written, in deck and card
/// order: cheap to gather (one copy into one buffer) and to compare, so a
/// built index can be kept while the texts stay the same.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SearchTexts {
    /// Every piece, one after another.
    text: String,
    /// Where each piece ends in `text`.
    ends: Vec<usize>,
    /// Per card: whether it is a cloze card, and its number of languages
    /// (its pieces are its id, then a front and a back per language).
    cards: Vec<(bool, u32)>,
}

impl SearchTexts {
    pub fn new(decks: &[Deck]) -> SearchTexts {
        let mut t = SearchTexts::default();
        let total: usize = decks
            .iter()
            .map(|d| d.cards.len() + d.derivations.len() + d.prompts.len())
            .sum();
        t.cards.reserve(total);
        t.ends.reserve(total * 5);
        // One allocation for the text (growing it would copy it again).
        let bytes = |x: &crate::deck::Text| x.0.values().map(String::len).sum::<usize>();
        t.text.reserve(
            decks
                .iter()
                .flat_map(|d| &d.cards)
                .map(|c| c.id.len() + bytes(&c.front) + bytes(&c.back))
                .sum(),
        );
        // Each deck's cards, then its derivations (searched by id, title
        // and the steps' math and reasons), then its prompts (by id and
        // question), as `card_of_row` counts them.
        let none = crate::deck::Text::default();
        for deck in decks {
            for c in &deck.cards {
                t.card(&c.id, &c.front, &c.back, c.kind == CardKind::Cloze);
            }
            for x in &deck.derivations {
                t.card(&x.id, &x.title, &derivation_text(x), false);
            }
            for p in &deck.prompts {
                t.card(&p.id, &p.question, &none, false);
            }
        }
        t
    }

    /// Pushes one card's pieces: its id, then a front and a back per
    /// language.
    fn card(&mut self, id: &str, front: &crate::deck::Text, back: &crate::deck::Text, cloze: bool) {
        let t = self;
        {
            t.push(id);
            let mut langs = 0;
            // Front and back keep their languages in order: walk both at
            // once, a language missing on one side giving an empty text.
            let mut front = front.0.iter().peekable();
            let mut back = back.0.iter().peekable();
            loop {
                let (f, b) = match (front.peek(), back.peek()) {
                    (None, None) => break,
                    (Some((fl, _)), Some((bl, _))) if fl == bl => {
                        (front.next().map(|x| x.1), back.next().map(|x| x.1))
                    }
                    (Some((fl, _)), Some((bl, _))) if fl < bl => (front.next().map(|x| x.1), None),
                    (Some(_), None) => (front.next().map(|x| x.1), None),
                    _ => (None, back.next().map(|x| x.1)),
                };
                t.push(f.map_or("", String::as_str));
                t.push(b.map_or("", String::as_str));
                langs += 1;
            }
            t.cards.push((cloze, langs));
        }
    }

    fn push(&mut self, piece: &str) {
        self.text.push_str(piece);
        self.ends.push(self.text.len());
    }

    /// The fields of each card (its id, then per language its front and
    /// back together), in order, from card `first` on.
    fn fields(&self, first: usize) -> impl Iterator<Item = Vec<String>> + '_ {
        let first = first.min(self.cards.len());
        let mut piece: usize = self.cards[..first]
            .iter()
            .map(|&(_, langs)| 1 + 2 * langs as usize)
            .sum();
        let mut next = move || {
            let start = if piece == 0 { 0 } else { self.ends[piece - 1] };
            let s = &self.text[start..self.ends[piece]];
            piece += 1;
            s
        };
        self.cards[first..].iter().map(move |&(cloze, langs)| {
            let mut fields = vec![next().to_string()];
            for _ in 0..langs {
                let front = next();
                let back = next();
                let front = if cloze {
                    crate::deck::cloze::revealed(front)
                } else {
                    front.to_string()
                };
                fields.push(format!("{front} {back}"));
            }
            fields
        })
    }

    /// The search index, rendering the math of every card on up to
    /// `threads` threads; `None` when `cancel` was set meanwhile.
    pub fn build(&self, cancel: &AtomicBool, threads: usize) -> Option<SearchIndex> {
        let n = self.cards.len();
        let threads = threads.clamp(1, n.max(1));
        let per = n.div_ceil(threads).max(1);
        let build = |skip: usize| -> Option<(Vec<Hay>, Vec<u32>)> {
            let mut hay = Vec::new();
            let mut renderer = flipcard_text::Renderer::default();
            let mut counts = Vec::with_capacity(per);
            for fields in self.fields(skip).take(per) {
                if cancel.load(Ordering::Relaxed) {
                    return None;
                }
                let before = hay.len();
                for f in &fields {
                    searched(f, &mut hay, &mut renderer);
                }
                counts.push((hay.len() - before) as u32);
            }
            Some((hay, counts))
        };
        let parts: Vec<Option<(Vec<Hay>, Vec<u32>)>> = if threads == 1 {
            vec![build(0)]
        } else {
            std::thread::scope(|s| {
                let others: Vec<_> = (1..threads)
                    .map(|k| {
                        std::thread::Builder::new()
                            .name("search-index".into())
                            .spawn_scoped(s, move || build(k * per))
                    })
                    .collect();
                let mut parts = vec![build(0)];
                for (k, h) in others.into_iter().enumerate() {
                    // A thread that could not start or failed: its share is
                    // built here.
                    let part = h.ok().and_then(|h| h.join().ok());
                    parts.push(part.unwrap_or_else(|| build((k + 1) * per)));
                }
                parts
            })
        };
        let mut index = SearchIndex {
            hay: Vec::new(),
            card_ends: Vec::with_capacity(n),
        };
        for part in parts {
            let (hay, counts) = part?;
            let mut end = index.hay.len() as u32;
            for c in counts {
                end += c;
                index.card_ends.push(end);
            }
            index.hay.extend(hay);
        }
        Some(index)
    }
}

/// A field as searched, pushed to `hay`: rendered (`ω₂`) and, when it holds
/// math, also as written (`\omega_2`), so that `omega2` and `ω₂` both find
/// it. The two are apart: a match lies within one of them (and the written
/// one, plain ASCII in most decks, takes the matcher's fast path).
fn searched(written: &str, hay: &mut Vec<Hay>, renderer: &mut flipcard_text::Renderer) {
    hay.push(Hay::new(&renderer.render(written)));
    if written.contains('$') {
        hay.push(Hay::new(written));
    }
}

/// One text as the matcher reads it, and (when it is not all ASCII) each
/// of its characters as the matcher compares it with a letter of a query
/// in ASCII (lower case, accents taken off; 0xFF for a character no ASCII
/// letter matches): a query whose letters are not all there, in order, is
/// no match, found without running the matcher.
#[derive(Debug)]
struct Hay {
    text: Utf32String,
    folded: Box<[u8]>,
}

impl Hay {
    fn new(text: &str) -> Hay {
        let text = utf32(text);
        let folded = match text.slice(..) {
            // Folded as it is compared, in [`Hay::may_match`].
            Utf32Str::Ascii(_) => Box::default(),
            Utf32Str::Unicode(cs) => cs
                .iter()
                .map(|&c| {
                    // ASCII is its own normal form: only its case is folded.
                    if c.is_ascii() {
                        return (c as u8).to_ascii_lowercase();
                    }
                    let f = chars::to_lower_case(chars::normalize(c));
                    if f.is_ascii() { f as u8 } else { 0xFF }
                })
                .collect(),
        };
        Hay { text, folded }
    }

    /// Whether every needle of `ascii` is in the text, its letters in order
    /// (which every kind of match needs).
    fn may_match(&self, ascii: &[&[u8]]) -> bool {
        let (text, fold) = match self.text.slice(..) {
            Utf32Str::Ascii(b) => (b, true),
            Utf32Str::Unicode(_) => (&self.folded[..], false),
        };
        ascii.iter().all(|needle| {
            let mut rest = text;
            needle.iter().all(|b| {
                let at = if fold {
                    rest.iter().position(|x| x.to_ascii_lowercase() == *b)
                } else {
                    rest.iter().position(|x| x == b)
                };
                match at {
                    Some(i) => {
                        rest = &rest[i + 1..];
                        true
                    }
                    None => false,
                }
            })
        })
    }
}

impl Hay {
    /// `pattern.score` of the text, the same score: but the matcher, which
    /// folds every character outside ASCII each time it reads it, reads
    /// from the character before the first one a fuzzy needle's first
    /// letter can match (it needs that one for its bonus) to the last its
    /// last letter can, found in `folded` instead.
    fn score(&self, pattern: &Pattern, matcher: &mut Matcher) -> Option<u32> {
        let full = self.text.slice(..);
        let mut total = 0;
        for atom in &pattern.atoms {
            let narrow = match (full, atom.needle_text()) {
                (Utf32Str::Unicode(_), Utf32Str::Ascii(needle))
                    if atom.kind == AtomKind::Fuzzy && !atom.negative && needle.len() >= 2 =>
                {
                    let first = self.folded.iter().position(|b| *b == needle[0])?;
                    let last = self.folded.iter().rposition(|b| Some(b) == needle.last())?;
                    (last > first).then(|| full.slice(first.saturating_sub(1)..=last))
                }
                _ => None,
            };
            total += u32::from(atom.score(narrow.unwrap_or(full), matcher)?);
        }
        Some(total)
    }
}

/// `Utf32String::from(text)`, the same characters (the first of each
/// grapheme), with only the stretches around characters outside ASCII cut
/// into graphemes: between two ASCII characters (but CR LF) there is
/// always a boundary, so the rest need not be looked at (cutting a whole
/// index into graphemes cost more than rendering its math).
/// A query with its compatibility characters folded as the texts are.
fn compat(query: &str) -> String {
    query.chars().map(flipcard_text::compat_char).collect()
}

fn utf32(text: &str) -> Utf32String {
    if text.is_ascii() {
        return Utf32String::from(text);
    }
    // A text its folding makes ASCII (`ω₂` is not, `x₂` is) is kept as the
    // matcher keeps ASCII.
    let folded = compat(text);
    if folded.is_ascii() {
        return Utf32String::from(folded.as_str());
    }
    let b = text.as_bytes();
    // A boundary is certain before `k` when `k - 1` and `k` are ASCII and
    // not CR LF (or at either end).
    let certain = |k: usize| {
        k == 0
            || k == b.len()
            || (b[k - 1].is_ascii() && b[k].is_ascii() && !(b[k - 1] == b'\r' && b[k] == b'\n'))
    };
    // As many as its characters (graphemes are no more): one allocation.
    let mut out: Vec<char> = Vec::with_capacity(text.chars().count());
    let mut at = 0;
    while at < b.len() {
        // Plain ASCII up to a boundary before the next character outside
        // it (or the end).
        let mut end = at;
        while end < b.len() && b[end].is_ascii() {
            end += 1;
        }
        let mut cut = end;
        while cut > at && !certain(cut) {
            cut -= 1;
        }
        for k in at..cut {
            // CR LF is one grapheme: its CR stands for it.
            if !(b[k] == b'\n' && k > at && b[k - 1] == b'\r') {
                out.push(b[k] as char);
            }
        }
        if cut == b.len() {
            break;
        }
        // From there to the next certain boundary, cut into graphemes.
        let mut next = end.max(cut + 1);
        while !certain(next) {
            next += 1;
        }
        // Compatibility characters folded (the micro sign is the Greek mu).
        out.extend(chars::graphemes(&text[cut..next]).map(flipcard_text::compat_char));
        at = next;
    }
    Utf32String::Unicode(out.into_boxed_slice())
}

/// The needles of `pattern` that can be checked with [`Hay::may_match`]:
/// those in ASCII that must match (not `!` ones).
fn ascii_needles(pattern: &Pattern) -> Vec<&[u8]> {
    pattern
        .atoms
        .iter()
        .filter(|a| !a.negative)
        .filter_map(|a| match a.needle_text() {
            Utf32Str::Ascii(b) => Some(b),
            Utf32Str::Unicode(_) => None,
        })
        .collect()
}

/// Every card's texts as the matcher reads them: build once, share between
/// searches (and between openings of the browser while the decks stay).
#[derive(Debug, Default)]
pub struct SearchIndex {
    hay: Vec<Hay>,
    /// Where each card's texts end in `hay`.
    card_ends: Vec<u32>,
}

impl SearchIndex {
    fn card(&self, c: u32) -> &[Hay] {
        let c = c as usize;
        let start = if c == 0 {
            0
        } else {
            self.card_ends[c - 1] as usize
        };
        &self.hay[start..self.card_ends[c] as usize]
    }
}

/// Free-text search over many items: every query is a pass of the fuzzy
/// matcher over the cards (an item shares its card's score), split among
/// threads when there are many.
pub struct Search {
    index: Arc<SearchIndex>,
    card_of_row: Vec<u32>,
    /// One matcher a thread (each holds its own scratch memory).
    matchers: Vec<Matcher>,
}

/// What [`Search::matching`] found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Found {
    /// The rows that match well enough, best first.
    pub best: Vec<usize>,
    /// Every row the pattern matches at all, in the order given: a query
    /// that extends this one can only match among these.
    pub any: Vec<usize>,
}

/// Threads worth using for a search on this machine.
pub fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(4))
}

/// Every step of a derivation in one text per language: the math and why
/// of each step, in order.
fn derivation_text(d: &crate::deck::Derivation) -> crate::deck::Text {
    let mut out = crate::deck::Text::default();
    for lang in d.title.0.keys() {
        let mut text = String::new();
        for s in &d.steps {
            for piece in [s.math.get(lang), s.why.get(lang)] {
                text.push_str(piece);
                text.push(' ');
            }
        }
        out.0.insert(lang.clone(), text);
    }
    out
}

/// For each row, the position of its card among every card of `decks`
/// (each deck's derivations counted after its cards, then its prompts).
pub fn card_of_row(decks: &[Deck], rows: &[ItemRow]) -> Vec<u32> {
    let mut first = Vec::with_capacity(decks.len());
    let mut n = 0u32;
    for d in decks {
        first.push(n);
        n += (d.cards.len() + d.derivations.len() + d.prompts.len()) as u32;
    }
    rows.iter()
        .map(|r| {
            let d = &decks[r.deck];
            let within = match r.direction {
                crate::sched::Direction::Derive => d.cards.len() + r.card,
                crate::sched::Direction::Predict => d.cards.len() + d.derivations.len() + r.card,
                _ => r.card,
            };
            first[r.deck] + within as u32
        })
        .collect()
}

impl Search {
    /// Gathers the texts and builds the index here and now.
    pub fn new(decks: &[Deck], rows: &[ItemRow]) -> Search {
        let never = AtomicBool::new(false);
        let index = SearchTexts::new(decks)
            .build(&never, threads())
            .unwrap_or_default();
        Search::with_index(Arc::new(index), card_of_row(decks, rows))
    }

    /// A search for `text` among `rows`: the index is built only when
    /// there is free text to look for (a query of filters alone needs
    /// none).
    pub fn for_text(text: &str, decks: &[Deck], rows: &[ItemRow]) -> Search {
        if text.trim().is_empty() {
            Search::with_index(Arc::default(), Vec::new())
        } else {
            Search::new(decks, rows)
        }
    }

    /// A search over a built index; `card_of_row` from [`card_of_row`].
    pub fn with_index(index: Arc<SearchIndex>, card_of_row: Vec<u32>) -> Search {
        Search {
            index,
            card_of_row,
            matchers: (0..threads())
                .map(|_| Matcher::new(nucleo_matcher::Config::DEFAULT))
                .collect(),
        }
    }

    /// The rows among `candidates` whose text matches `text`.
    pub fn matching(&mut self, text: &str, candidates: &[usize]) -> Found {
        if text.trim().is_empty() {
            return Found {
                best: candidates.to_vec(),
                any: candidates.to_vec(),
            };
        }
        let pattern = Pattern::parse(&compat(text), CaseMatching::Ignore, Normalization::Smart);
        let chars = text.chars().filter(|c| !c.is_whitespace()).count() as u32;
        let scan = Scan {
            index: &self.index,
            card_of_row: &self.card_of_row,
            pattern: &pattern,
            ascii: ascii_needles(&pattern),
            least: MIN_SCORE_PER_CHAR * chars,
        };
        let threads = if candidates.len() >= PARALLEL_FROM {
            self.matchers.len()
        } else {
            1
        };
        let per = candidates.len().div_ceil(threads).max(1);
        let mut chunks = candidates.chunks(per);
        let mut matchers = self.matchers.iter_mut();
        let (Some(mine), Some(matcher)) = (chunks.next(), matchers.next()) else {
            return Found::default();
        };
        let parts: Vec<Part> = std::thread::scope(|s| {
            let scan = &scan;
            let others: Vec<_> = chunks
                .zip(matchers)
                .map(|(chunk, m)| {
                    let h = std::thread::Builder::new()
                        .name("search".into())
                        .spawn_scoped(s, move || scan.run(m, chunk));
                    (h, chunk)
                })
                .collect();
            let mut parts = vec![scan.run(matcher, mine)];
            for (h, chunk) in others {
                // A thread that could not start or failed: its share is
                // matched here.
                match h.ok().and_then(|h| h.join().ok()) {
                    Some(p) => parts.push(p),
                    None => {
                        let mut m = Matcher::new(nucleo_matcher::Config::DEFAULT);
                        parts.push(scan.run(&mut m, chunk));
                    }
                }
            }
            parts
        });
        let mut any = Vec::with_capacity(parts.iter().map(|p| p.any.len()).sum());
        let mut scored = Vec::with_capacity(parts.iter().map(|p| p.scored.len()).sum());
        for p in parts {
            any.extend(p.any);
            scored.extend(p.scored);
        }
        scored.sort_unstable_by(|a: &(u32, usize), b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        Found {
            best: scored.into_iter().map(|(_, i)| i).collect(),
            any,
        }
    }
}

/// One query over a share of the candidates.
struct Scan<'a> {
    index: &'a SearchIndex,
    card_of_row: &'a [u32],
    pattern: &'a Pattern,
    ascii: Vec<&'a [u8]>,
    least: u32,
}

struct Part {
    any: Vec<usize>,
    scored: Vec<(u32, usize)>,
}

impl Scan<'_> {
    fn run(&self, matcher: &mut Matcher, candidates: &[usize]) -> Part {
        let mut last: Option<(u32, Option<u32>)> = None;
        let mut part = Part {
            any: Vec::new(),
            scored: Vec::new(),
        };
        for &i in candidates {
            let card = self.card_of_row[i];
            // The items of a card come one after another: score it once.
            let score = match last {
                Some((c, s)) if c == card => s,
                _ => {
                    let s = self
                        .index
                        .card(card)
                        .iter()
                        .filter(|h| h.may_match(&self.ascii))
                        .filter_map(|h| h.score(self.pattern, matcher))
                        .max();
                    last = Some((card, s));
                    s
                }
            };
            if let Some(s) = score {
                part.any.push(i);
                if s >= self.least {
                    part.scored.push((s, i));
                }
            }
        }
        part
    }
}

/// The rows each text term of a filter matches (its words in `or`, `-`,
/// parentheses, quotes or with `*`), found by one pass of the search each.
#[derive(Debug, Default)]
pub struct Hits {
    sets: Vec<(String, bool, Vec<bool>)>,
}

impl super::query::TextHits for Hits {
    fn hit(&self, text: &str, exact: bool, row: usize) -> bool {
        self.sets
            .iter()
            .find(|(t, e, _)| t == text && *e == exact)
            .is_some_and(|(_, _, set)| set.get(row).copied().unwrap_or(false))
    }
}

impl Hits {
    /// Matches every text term of `filter` against all `n` rows: a term
    /// in quotes or with `*` by [`Search::glob`], any other fuzzily as the
    /// free text is (its well-scored matches).
    pub fn find(filter: &Filter, search: &mut Search, n: usize) -> Hits {
        let all: Vec<usize> = (0..n).collect();
        let sets = filter
            .text_terms()
            .into_iter()
            .map(|(t, exact)| {
                let rows = if exact {
                    search.glob(t, &all)
                } else {
                    search.matching(t, &all).best
                };
                let mut set = vec![false; n];
                for r in rows {
                    set[r] = true;
                }
                (t.to_string(), exact, set)
            })
            .collect();
        Hits { sets }
    }
}

impl Search {
    /// A search for `filter` among `rows`: the index is built only when
    /// the filter has text (a query of filters alone needs none).
    pub fn for_filter(filter: &Filter, decks: &[Deck], rows: &[ItemRow]) -> Search {
        if filter.needs_index() {
            Search::new(decks, rows)
        } else {
            Search::with_index(Arc::default(), Vec::new())
        }
    }

    /// The rows among `candidates` one of whose texts holds the pieces of
    /// `pattern` between its `*`s, in order, letters compared without case
    /// or accents (Anki's text search with wildcards).
    pub fn glob(&self, pattern: &str, candidates: &[usize]) -> Vec<usize> {
        let pieces: Vec<Vec<char>> = compat(pattern)
            .split('*')
            .filter(|p| !p.is_empty())
            .map(|p| p.chars().map(fold).collect())
            .collect();
        let mut last: Option<(u32, bool)> = None;
        candidates
            .iter()
            .copied()
            .filter(|&i| {
                let Some(&card) = self.card_of_row.get(i) else {
                    return false;
                };
                match last {
                    Some((c, hit)) if c == card => hit,
                    _ => {
                        let hit = (card as usize) < self.index.card_ends.len()
                            && self.index.card(card).iter().any(|h| h.holds(&pieces));
                        last = Some((card, hit));
                        hit
                    }
                }
            })
            .collect()
    }
}

/// A character as [`Search::glob`] compares it: lower case, accents off.
fn fold(c: char) -> char {
    chars::to_lower_case(chars::normalize(c))
}

impl Hay {
    /// Whether the text holds each of `pieces`, in order, folded.
    fn holds(&self, pieces: &[Vec<char>]) -> bool {
        let text: Vec<char> = match self.text.slice(..) {
            Utf32Str::Ascii(b) => b
                .iter()
                .map(|&b| (b as char).to_ascii_lowercase())
                .collect(),
            Utf32Str::Unicode(cs) => cs.iter().map(|&c| fold(c)).collect(),
        };
        let mut rest = &text[..];
        pieces
            .iter()
            .all(|p| match rest.windows(p.len()).position(|w| w == &p[..]) {
                Some(at) => {
                    rest = &rest[at + p.len()..];
                    true
                }
                None => false,
            })
    }
}

/// The rows a query selects, best match first when it has free text.
pub fn select(
    decks: &[Deck],
    rows: &[ItemRow],
    search: &mut Search,
    filter: &Filter,
    now: DateTime<Utc>,
) -> Vec<usize> {
    let hits = Hits::find(filter, search, rows.len());
    let kept: Vec<usize> = (0..rows.len())
        .filter(|&i| filter.keeps(i, rows, decks, now, &hits))
        .collect();
    search.matching(&filter.text, &kept).best
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn formulas_rendered_once_read_as_rendered_each_time() {
        let mut r = flipcard_text::Renderer::default();
        for text in [
            r"$\omega_2$ and $\omega_2$ again, $\vec L$",
            r"$$\dot\omega = \tau$$ then text $\omega_2$",
            r"a bad one $\frac{a$ and $x^2$",
            r"a bad one $\frac{a$ twice, and one never closed $x",
            "no math at all",
        ] {
            assert_eq!(r.render(text), flipcard_text::render(text), "{text}");
        }
    }

    #[test]
    fn compatibility_characters_in_texts_and_queries_find_each_other() {
        // The micro sign and the Greek mu; a subscript typed as one (the
        // matcher read a text's `₂` as `2` but a query's as `₂`: `ω₂`
        // found nothing).
        let mut matcher = Matcher::new(nucleo_matcher::Config::DEFAULT);
        for (text, query) in [
            ("decays in 2.2 \u{b5}s", "\u{3bc}s"),
            ("decays in 2.2 \u{3bc}s", "\u{b5}s"),
            ("the spin \u{3c9}\u{2082} grows", "\u{3c9}\u{2082}"),
            ("the spin \u{3c9}\u{2082} grows", "'\u{3c9}\u{2082}"),
        ] {
            let hay = Hay::new(text);
            let pattern =
                Pattern::parse(&compat(query), CaseMatching::Ignore, Normalization::Smart);
            assert!(
                hay.score(&pattern, &mut matcher).is_some(),
                "{query:?} in {text:?}"
            );
        }
    }

    proptest! {
        /// Reading only the stretch a fuzzy needle can match gives the
        /// score of the whole text.
        #[test]
        fn the_stretch_read_scores_as_the_whole_text(
            text in "[a-dA-D ωΩ₂é/:_]{0,40}",
            query in "[!^']?[a-dA-Dé ω/_]{1,6}[$]?( [a-d]{1,3})?",
        ) {
            let hay = Hay::new(&text);
            let pattern = Pattern::parse(&compat(&query), CaseMatching::Ignore, Normalization::Smart);
            let mut matcher = Matcher::new(nucleo_matcher::Config::DEFAULT);
            let whole = pattern.score(hay.text.slice(..), &mut matcher);
            prop_assert_eq!(hay.score(&pattern, &mut matcher), whole, "{:?} in {:?}", query, text);
        }

        /// Cutting into graphemes only around what is not ASCII gives the
        /// matcher's own characters: combining marks after ASCII letters,
        /// CR LF, joiners, flags, Hangul, prepended marks.
        #[test]
        fn texts_convert_as_the_matcher_converts_them(
            text in "[a-zA-Z \r\n\u{301}\u{20D7}\u{200D}\u{1F1EE}\u{1F1F3}\u{1100}\u{1161}\u{600}\u{1F600}ω₂é]{0,30}",
        ) {
            // As the matcher converts it, compatibility characters folded.
            prop_assert_eq!(utf32(&text), Utf32String::from(compat(&text).as_str()));
        }

        /// The check before the matcher never turns away a text the
        /// matcher would match: accents, Greek, capitals, the Kelvin sign,
        /// subscripts, and queries with `!`, `^`, `'` and `$`.
        #[test]
        fn the_check_before_the_matcher_loses_no_match(
            text in "[a-zA-Zé ωΩ₂K2_{}$\\\\]{0,40}",
            query in "[!^'$]?[a-zA-Zé ωΩ₂K2_{}]{1,6}[$]?",
        ) {
            let hay = Hay::new(&text);
            let pattern = Pattern::parse(&compat(&query), CaseMatching::Ignore, Normalization::Smart);
            let mut matcher = Matcher::new(nucleo_matcher::Config::DEFAULT);
            if pattern.score(hay.text.slice(..), &mut matcher).is_some() {
                prop_assert!(hay.may_match(&ascii_needles(&pattern)), "{query:?} in {text:?}");
            }
        }
    }
}
