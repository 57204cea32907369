//! Reading a large deck file a slice of its cards at a time.
//!
//! The TOML tree of a whole file, every value with its span, takes about
//! ten times the file's size: 160 MB of table nodes alone for a deck of
//! 50,000 cards, all alive at once until the raw stage has read it. Yet
//! each `[[card]]` table stands alone. So a large file is read in parts:
//! the file's `[[card]]` tables are found by their header lines, the rest
//! of the file (the `[deck]` table, prompts, scenes, …) is parsed without
//! them, and the cards are parsed a few megabytes at a time,
//! each part's tree dropped once its cards are read. Every span read is
//! moved to where it is in the file, so every span is the span in
//! the file and a diagnostic points where it would have.
//!
//! The whole file is read at once instead, exactly as before, whenever
//! this reading could differ from it: a small file, a header this scanner
//! does not follow (a quoted key, a `[card]` table), a top-level `card`
//! key outside the headers, or any diagnostic at all from a part (a
//! syntax error, a wrong field): then the whole-file reading gives the
//! diagnostics, in its order and with its wording. A property test holds
//! the two readings equal on generated decks.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeArray, DeTable, DeValue};

use super::raw::{self, RawCard, RawDeckFile};
use super::report::FileReport;
use super::syntax;

/// Files smaller than this are read whole.
pub(crate) const MIN_CHUNKED_BYTES: usize = 1 << 20;

/// About how many bytes of cards are parsed at once.
const PART_BYTES: usize = 2 << 20;

/// The deck file `text` read raw (the TOML syntax checked and the raw
/// stage run), as [`whole`] reads it, with the same diagnostics in `rep`;
/// `None` when it does not parse.
pub(crate) fn read_deck(rep: &mut FileReport, text: &str) -> Option<RawDeckFile> {
    if text.len() >= MIN_CHUNKED_BYTES
        && let Some(file) = in_parts(rep, text, PART_BYTES)
    {
        return Some(file);
    }
    whole(rep, text)
}

/// The whole file parsed at once, then read.
pub(crate) fn whole(rep: &mut FileReport, text: &str) -> Option<RawDeckFile> {
    let (root, span) = syntax::parse(rep, text)?;
    Some(raw::read_deck_file(rep, &root, span))
}

/// The file read in parts of about `part` bytes of cards; `None` when it
/// must be read whole (see the module).
pub(crate) fn in_parts(rep: &FileReport, text: &str, part: usize) -> Option<RawDeckFile> {
    let cards = card_tables(text)?;
    if cards.is_empty() {
        return None;
    }
    let mut scratch = FileReport::new(&rep.path, text);

    // The rest of the file: what lies between the card tables, joined.
    // Each table starts and ends at a line start, so the rest is lines.
    let mut rest = String::with_capacity(text.len() - cards.iter().map(|c| c.len()).sum::<usize>());
    // Where each piece of the rest starts in it and in the file.
    let mut pieces: Vec<(usize, usize)> = Vec::new();
    let mut from = 0;
    for c in cards
        .iter()
        .cloned()
        .chain(std::iter::once(text.len()..text.len()))
    {
        if c.start > from {
            pieces.push((rest.len(), from));
            rest.push_str(&text[from..c.start]);
        }
        from = c.end;
    }
    let to_file = |at: usize| -> usize {
        let i = pieces.partition_point(|&(r, _)| r <= at).saturating_sub(1);
        pieces.get(i).map_or(at, |&(r, f)| f + (at - r))
    };
    let mut file = {
        let (root, span) = syntax::parse(&mut scratch, &rest)?;
        if root.iter().any(|(k, _)| {
            let key: &str = k.get_ref();
            key == "card"
        }) {
            return None;
        }
        // An end is mapped as the byte before it, so a span ending where
        // a card table was taken out ends where the text before it ends.
        let map = |span: Range<usize>| {
            let end = if span.end > span.start {
                to_file(span.end - 1) + 1
            } else {
                to_file(span.end)
            };
            to_file(span.start)..end
        };
        let root = map_table(root, &map);
        raw::read_deck_file(&mut scratch, &root, map(span))
    };
    drop(rest);

    // The cards, part by part: consecutive card tables with nothing
    // between them, parsed alone and their spans moved to the file's.
    let mut parts: Vec<Range<usize>> = Vec::new();
    let mut start = 0;
    while start < cards.len() {
        let mut end = start + 1;
        while end < cards.len()
            && cards[end].start == cards[end - 1].end
            && cards[end].end - cards[start].start <= part
        {
            end += 1;
        }
        parts.push(cards[start].start..cards[end - 1].end);
        start = end;
    }
    if !scratch.is_empty() {
        return None;
    }
    // The parts are independent: with more than one core, each thread
    // reads a run of them, and the runs are joined in file order.
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, MAX_THREADS)
        .min(parts.len());
    let runs = runs(&parts, threads);
    let path = rep.path.as_path();
    let read = |run: &[Range<usize>]| -> Option<Vec<RawCard>> {
        let mut scratch = FileReport::new(path, text);
        let mut out = Vec::new();
        for at in run {
            let (root, _) = syntax::parse(&mut scratch, &text[at.clone()])?;
            let root = map_table(root, &|span: Range<usize>| {
                span.start + at.start..span.end + at.start
            });
            raw::read_cards_into(&mut scratch, &root, &mut out);
        }
        scratch.is_empty().then_some(out)
    };
    let read_runs: Vec<Option<Vec<RawCard>>> = if runs.len() <= 1 {
        runs.iter().map(|r| read(r)).collect()
    } else {
        std::thread::scope(|s| {
            let handles: Vec<_> = runs[1..].iter().map(|r| s.spawn(move || read(r))).collect();
            let mut out = vec![read(runs[0])];
            // A thread that could not finish is a part to read whole.
            out.extend(handles.into_iter().map(|h| h.join().ok().flatten()));
            out
        })
    };
    for cards in read_runs {
        file.cards.extend(cards?);
    }
    Some(file)
}

/// Threads that read parts at most.
const MAX_THREADS: usize = 4;

/// `parts` cut into at most `n` runs of consecutive parts with about as
/// many bytes each.
fn runs(parts: &[Range<usize>], n: usize) -> Vec<&[Range<usize>]> {
    let total: usize = parts.iter().map(|p| p.len()).sum();
    let mut out = Vec::new();
    let mut from = 0;
    let mut bytes = 0;
    for (i, p) in parts.iter().enumerate() {
        bytes += p.len();
        // Cut after this part once this run holds its share.
        if out.len() + 1 < n && bytes * n >= total * (out.len() + 1) {
            out.push(&parts[from..=i]);
            from = i + 1;
        }
    }
    if from < parts.len() {
        out.push(&parts[from..]);
    }
    out
}

/// `table` with every span (of keys and values, all the way down) moved
/// by `map` to where it is in the file.
fn map_table<'i>(table: DeTable<'i>, map: &dyn Fn(Range<usize>) -> Range<usize>) -> DeTable<'i> {
    let mut out = DeTable::new();
    for (k, v) in table {
        let span = map(k.span());
        out.insert(Spanned::new(span, k.into_inner()), map_value(v, map));
    }
    out
}

fn map_value<'i>(
    v: Spanned<DeValue<'i>>,
    map: &dyn Fn(Range<usize>) -> Range<usize>,
) -> Spanned<DeValue<'i>> {
    let span = map(v.span());
    let value = match v.into_inner() {
        DeValue::Table(t) => DeValue::Table(map_table(t, map)),
        DeValue::Array(a) => {
            let mut out = DeArray::new();
            for x in a {
                out.push(map_value(x, map));
            }
            DeValue::Array(out)
        }
        other => other,
    };
    Spanned::new(span, value)
}

/// What a table header names.
#[derive(Debug, PartialEq, Eq)]
enum Header {
    /// `[[card]]`: a card starts.
    Card,
    /// `[card.x]` or `[[card.x]]`: part of the card above.
    OfCard,
    /// Any other table.
    Other,
}

/// The byte ranges of the `[[card]]` tables, each from the start of its
/// header's line to the start of the next header's line that is not part
/// of it; `None` when a header is one this scanner does not follow.
fn card_tables(text: &str) -> Option<Vec<Range<usize>>> {
    let mut out = Vec::new();
    let mut open: Option<usize> = None;
    for (line, header) in headers(text)? {
        match classify(header)? {
            Header::Card => {
                if let Some(s) = open.replace(line) {
                    out.push(s..line);
                }
            }
            Header::OfCard => open.map(|_| ())?,
            Header::Other => {
                if let Some(s) = open.take() {
                    out.push(s..line);
                }
            }
        }
    }
    if let Some(s) = open {
        out.push(s..text.len());
    }
    Some(out)
}

fn classify(header: &str) -> Option<Header> {
    let (inner, array) = match header.strip_prefix("[[") {
        Some(h) => (h.strip_suffix("]]")?, true),
        None => (header.strip_prefix('[')?.strip_suffix(']')?, false),
    };
    if inner.contains(['"', '\'', '[', ']']) {
        return None;
    }
    let mut parts = inner.split('.').map(str::trim);
    if parts.next()? != "card" {
        return Some(Header::Other);
    }
    match (parts.next(), array) {
        (None, true) => Some(Header::Card),
        (None, false) => None,
        (Some(_), _) => Some(Header::OfCard),
    }
}

/// Every table header of `text`: the start of its line and its text from
/// `[` to its last `]`. `None` when the text cannot be scanned with
/// certainty (a string left open at a line's end, a header not closed on
/// its line).
fn headers(text: &str) -> Option<Vec<(usize, &str)>> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    // Brackets and braces open in a value.
    let mut depth: usize = 0;
    let mut line = 0;
    let mut blank = true;
    while i < b.len() {
        match b[i] {
            b'\n' => {
                i += 1;
                line = i;
                blank = true;
            }
            b' ' | b'\t' | b'\r' => i += 1,
            b'#' => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'"' | b'\'' => {
                i = string_end(b, i)?;
                blank = false;
            }
            b'[' if blank && depth == 0 => {
                let close = b[i..]
                    .iter()
                    .position(|&c| c == b'\n')
                    .map_or(b.len(), |p| i + p);
                let close = line_header_end(b, i, close)?;
                out.push((line, &text[i..close]));
                i = close;
                blank = false;
            }
            b'[' | b'{' => {
                depth += 1;
                i += 1;
                blank = false;
            }
            b']' | b'}' => {
                depth = depth.checked_sub(1)?;
                i += 1;
                blank = false;
            }
            _ => {
                i += 1;
                blank = false;
            }
        }
    }
    Some(out)
}

/// The end of a header starting at `start` on a line ending at `eol`:
/// after its last `]`, with only a comment or spaces after it.
fn line_header_end(b: &[u8], start: usize, eol: usize) -> Option<usize> {
    let line = &b[start..eol];
    let comment = line.iter().position(|&c| c == b'#').unwrap_or(line.len());
    let body = &line[..comment];
    let last = body.iter().rposition(|&c| c == b']')?;
    body[last + 1..]
        .iter()
        .all(|c| c.is_ascii_whitespace())
        .then_some(start + last + 1)
}

/// The index after the string starting at `i` (a quote); `None` when a
/// one-line string meets the end of its line or the file ends inside one.
fn string_end(b: &[u8], i: usize) -> Option<usize> {
    let q = b[i];
    let basic = q == b'"';
    if b[i..].starts_with(&[q, q, q]) {
        let mut j = i + 3;
        loop {
            match b.get(j)? {
                b'\\' if basic => j += 2,
                &c if c == q && b[j..].starts_with(&[q, q, q]) => {
                    j += 3;
                    // Up to two quotes more belong to the string.
                    let mut extra = 0;
                    while extra < 2 && b.get(j) == Some(&q) {
                        j += 1;
                        extra += 1;
                    }
                    return Some(j);
                }
                _ => j += 1,
            }
        }
    }
    let mut j = i + 1;
    loop {
        match b.get(j)? {
            b'\\' if basic => j += 2,
            b'\n' => return None,
            &c if c == q => return Some(j + 1),
            _ => j += 1,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use proptest::prelude::*;

    use super::*;

    fn both(text: &str, part: usize) -> (Option<RawDeckFile>, Option<RawDeckFile>) {
        let rep = FileReport::new(Path::new("d.toml"), text);
        let parts = in_parts(&rep, text, part);
        let mut rep = FileReport::new(Path::new("d.toml"), text);
        (parts, whole(&mut rep, text))
    }

    const HEAD: &str = "[deck]\nid = \"d\"\ntitle = \"D\"\nlanguages = [\"en\"]\n\n";

    #[test]
    fn cards_read_in_parts_are_the_cards_read_whole() {
        // The [deck] table between cards: the rest is read in pieces.
        let mut text = String::new();
        for i in 0..40 {
            text.push_str(&format!(
                "[[card]] # {i}\nid = \"c{i}\"\ntags = [\n  \"a\",\n  \"[b]\", # ]\n]\nfront.en = '''[[card]] inside\n[deck]'''\nback = \"x \\\" ]\"\n\n"
            ));
            if i == 20 {
                text.push_str(HEAD);
            }
        }
        let (parts, whole) = both(&text, 300);
        let parts = parts.expect("read in parts");
        assert_eq!(parts.cards.len(), 40);
        assert_eq!(Some(parts), whole);
    }

    #[test]
    fn a_bracket_starting_a_line_inside_a_value_is_no_header() {
        let text =
            "[[card]]\nx = [\n  [1, 2],\n  { a = [3] },\n]\ny = '''\n[[card]]'''\n[[card]] # two\n";
        let found: Vec<&str> = headers(text).unwrap().into_iter().map(|(_, h)| h).collect();
        assert_eq!(found, ["[[card]]", "[[card]]"]);
        assert_eq!(card_tables(text).unwrap(), [0..62, 62..text.len()]);
    }

    #[test]
    fn what_the_scanner_does_not_follow_is_read_whole() {
        for odd in [
            "[\"card\"]\nid = \"x\"\n",
            "[card]\nid = \"x\"\n",
            "card = 5\n",
            "[[card]]\nid = 'open\n",
        ] {
            let text = format!("{odd}{HEAD}[[card]]\nid = \"c\"\n");
            let rep = FileReport::new(Path::new("d.toml"), &text);
            assert_eq!(in_parts(&rep, &text, 10), None, "{odd}");
        }
    }

    #[test]
    fn a_card_with_an_error_is_read_whole_to_report_it() {
        let text = format!("{HEAD}[[card]]\nid = \"a\"\n\n[[card]]\nid = \"b\"\nfrnt = 1\n");
        let rep = FileReport::new(Path::new("d.toml"), &text);
        assert_eq!(in_parts(&rep, &text, 10), None);
    }

    /// A valid card table whose strings and comments hold brackets,
    /// quotes and header-like lines, written in one of three ways.
    fn card() -> impl Strategy<Value = String> {
        let text = "[a-z \\[\\]{}#.=\n]{0,16}";
        (0u32..1000, text, text, 0..3u8, proptest::bool::ANY).prop_map(
            |(i, front, back, style, comment)| {
                let comment = if comment { " # [[card]] ]" } else { "" };
                let back_line = format!("back = {:?}\n", back.replace('\n', " "));
                match style {
                    0 => format!("[[card]]{comment}\nid = \"c{i}\"\nfront.en = \'\'\'{front}\'\'\'\n{back_line}\n"),
                    1 => format!("[[card]]\nid = \"c{i}\"\ntags = [\n  \"a]\", # ]\n  \"[b\",\n]\n{back_line}[card.front]{comment}\nen = \'\'\'{front}\'\'\'\n"),
                    _ => format!("  [[ card ]]\nid = \"c{i}\"\nfront = {{ en = {:?} }}\n{back_line}", front.replace('\n', " ")),
                }
            },
        )
    }

    proptest! {
        /// The runs the threads read cover every part once, in order, as at
        /// most `n` non-empty runs of about equal bytes.
        #[test]
        fn runs_cover_every_part_in_order(
            lens in proptest::collection::vec(1usize..5000, 1..60),
            n in 1usize..6,
        ) {
            let mut parts = Vec::new();
            let mut at = 0;
            for l in &lens {
                parts.push(at..at + l);
                at += l;
            }
            let runs = runs(&parts, n);
            prop_assert!(!runs.is_empty() && runs.len() <= n);
            prop_assert!(runs.iter().all(|r| !r.is_empty()));
            let joined: Vec<Range<usize>> = runs.concat();
            prop_assert_eq!(&joined, &parts);
            // No run but the last holds more than its share and a part.
            let total: usize = lens.iter().sum();
            let most = lens.iter().max().copied().unwrap_or(0);
            for r in &runs[..runs.len() - 1] {
                let bytes: usize = r.iter().map(|p| p.len()).sum();
                prop_assert!(bytes <= total / runs.len() + most);
            }
        }
    }

    proptest! {
        /// A file of valid cards is read in parts, and reads as it does
        /// whole, wherever the parts are cut.
        #[test]
        fn parts_never_differ_from_the_whole(
            before in proptest::collection::vec(card(), 0..20),
            after in proptest::collection::vec(card(), 1..20),
            part in 1usize..400,
        ) {
            let text = format!("{}{HEAD}{}", before.concat(), after.concat());
            let (parts, whole) = both(&text, part);
            prop_assert!(parts.is_some(), "not read in parts:\n{text}");
            prop_assert_eq!(parts, whole);
        }
    }
}
