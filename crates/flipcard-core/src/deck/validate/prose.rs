//! Prose that sends the learner to a section by its title, `(see
//! Applications)`, `see the section on damping`, `(dekho *Applications*)`:
//! the title must be one of the deck's sections in the text's language, or
//! the learner looks for a section that is not there. A warning (the text
//! still reads), with the closest title and how to write a real link.
//!
//! What counts as a reference, after a word `see` (English) or `dekho`,
//! `dekhiye`, `dekhen`, `dekhein` (Hinglish), optionally followed by
//! `also` and by `section` / `the section` (then `on`, `about`, `called`,
//! `titled` or `named`):
//!
//! - an emphasised title, `*Title*` or `**Title**`, starting with a capital
//!   letter and not ending in `:` or `.` (a bold lead-in is no title); a
//!   quoted one, `"Title"` / `“Title”` / `‘Title’`, likewise, but only in
//!   parentheses or after `section` (in running text quotes are more often
//!   what the learner sees on screen);
//! - after `section …`, the words up to the next punctuation, whatever
//!   their case (`see the section on damping`);
//! - inside parentheses right after the `(`, everything up to the `)`, when
//!   it starts with a capital letter and has at most eight words, no number
//!   and no citation word (`(see Applications)`, but not `(see Figure 2)`,
//!   `(see Goldstein 2002)` or `(see below)`).
//!
//! In Hinglish the verb may follow: `(*Applications* dekho)`,
//! `(Applications dekhiye)`. Text in `$…$`, `` `…` `` and `[…](#id)` links is
//! never a reference, and a sentence like `you can see the same` names
//! nothing. A title matches when it equals a section's title, the part of
//! it before its first `:`, or before its first `,` (case, `*`, curly
//! quotes and a leading `the` aside).

use crate::deck::raw::Str;
use crate::deck::report::FileReport;
use crate::deck::suggest;

/// The sections' titles in every language read: (section id, language,
/// title as written). `known` is false when the content could not be read
/// (then nothing is reported: its own errors say why).
#[derive(Debug, Clone, Default)]
pub struct Titles {
    pub of: Vec<(String, String, String)>,
    pub known: bool,
}

/// Where the prose is, which decides how a real link is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// A section's body: `[text](#section-id)`.
    Body,
    /// A card's text: no links; the card's `explain` opens a section.
    Card,
}

/// A title named in prose: where it is in the text (bytes) and as written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reference {
    pub at: usize,
    pub title: String,
}

const SEE: &[&str] = &["see"];
const DEKHO: &[&str] = &["dekho", "dekhiye", "dekhen", "dekhein"];

/// The bytes a verb of [`SEE`] or [`DEKHO`] starts with, in either case,
/// by byte: most bytes of a text start none and are passed at once.
const STARTS_VERB: [bool; 256] = {
    let mut starts = [false; 256];
    let lists: [&[&str]; 2] = [SEE, DEKHO];
    let mut l = 0;
    while l < lists.len() {
        let mut w = 0;
        while w < lists[l].len() {
            let c = lists[l][w].as_bytes()[0];
            starts[c.to_ascii_lowercase() as usize] = true;
            starts[c.to_ascii_uppercase() as usize] = true;
            w += 1;
        }
        l += 1;
    }
    starts
};
const SECTION_WORDS: &[&str] = &["on", "about", "called", "titled", "named"];
/// First words of a parenthesised phrase that name no section.
const CITATION: &[&str] = &[
    "fig",
    "figure",
    "figures",
    "table",
    "eq",
    "eqs",
    "equation",
    "equations",
    "chapter",
    "ch",
    "appendix",
    "ref",
    "refs",
    "page",
    "p",
    "pp",
    "problem",
    "exercise",
    "e.g",
    "eg",
    "i.e",
    "also",
    "above",
    "below",
];
/// Most words a parenthesised phrase may have to be taken for a title.
const MOST_WORDS: usize = 8;
/// Stands for a byte of math, code or a link (never part of a title).
const MASK: u8 = 1;

/// Reports each title named in `s` that no section of `titles` has in
/// `lang`; `what` says whose text it is ("the body of section `s1`").
pub fn check(
    rep: &mut FileReport,
    s: &Str,
    lang: &str,
    titles: &Titles,
    place: Place,
    what: impl std::fmt::Display,
) {
    if !titles.known {
        return;
    }
    for r in references(&s.value) {
        if resolves(&r.title, lang, titles) {
            continue;
        }
        let span = super::system::span_in(rep, s, r.at, r.title.len());
        let shown = flipcard_text::safe::one_line(&r.title);
        let near = closest(&r.title, lang, titles);
        let hint = match (place, near) {
            (
                Place::Body,
                Some(Near {
                    id,
                    title,
                    link_text,
                }),
            ) => format!(
                "did you mean `{title}`? make it a link the reader opens: [{link_text}](#{id})"
            ),
            (Place::Body, None) => format!(
                "name a section by its title, or link it: [{shown}](#section-id){}",
                none_hint(titles)
            ),
            (Place::Card, Some(Near { id, title, .. })) => format!(
                "did you mean `{title}`? a card's text has no links: name the section by its title, and let `e` open it with explain = \"{id}\""
            ),
            (Place::Card, None) => format!(
                "name a section by its title; a card opens its section with explain = \"section-id\"{}",
                none_hint(titles)
            ),
        };
        rep.warning(
            span,
            format!("{what} refers to a section titled `{shown}`, and no section has that title"),
            Some(hint),
        );
    }
}

fn none_hint(titles: &Titles) -> &'static str {
    if titles.of.is_empty() {
        " (the deck has no sections)"
    } else {
        ""
    }
}

/// Whether some section's title in `lang` is `title`.
fn resolves(title: &str, lang: &str, titles: &Titles) -> bool {
    let want = norm(title);
    titles
        .of
        .iter()
        .filter(|(_, l, _)| l == lang)
        .any(|(_, _, t)| keys(t).contains(&want))
}

/// The section a dangling title most likely means, with its title in
/// `lang` and the text a link to it would show.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Near {
    id: String,
    title: String,
    link_text: String,
}

/// The section `title` most likely means: a close spelling of a title or
/// of its part before `:` or `,` (the link then shows that part, spelt
/// right), else the section whose id the title makes (`Applications` →
/// `applications`), else the one section whose title holds the title's
/// words (`satellites`).
fn closest(title: &str, lang: &str, titles: &Titles) -> Option<Near> {
    let ours: Vec<&(String, String, String)> =
        titles.of.iter().filter(|(_, l, _)| l == lang).collect();
    let want = norm(title);
    let near = |i: usize, link_text: String| {
        let (id, _, t) = ours[i];
        Near {
            id: id.clone(),
            title: flipcard_text::safe::one_line(t).into_owned(),
            link_text,
        }
    };
    let candidates: Vec<(String, usize)> = ours
        .iter()
        .enumerate()
        .flat_map(|(i, (_, _, t))| keys(t).into_iter().map(move |k| (k, i)))
        .collect();
    if let Some((_, i)) = suggest::closest(&want, candidates.iter().map(|(k, _)| k.as_str()))
        .and_then(|k| candidates.iter().find(|(c, _)| c == k))
    {
        let (_, _, t) = ours[*i];
        let short = t.split([':', ',']).next().unwrap_or(t).trim();
        return Some(near(*i, flipcard_text::safe::one_line(short).into_owned()));
    }
    let shown = flipcard_text::safe::one_line(title).into_owned();
    let id = super::slug(title);
    if let Some(i) = ours.iter().position(|(sid, _, _)| *sid == id) {
        return Some(near(i, shown));
    }
    let words = |s: &str| -> Vec<String> {
        norm(s)
            .split(|c: char| !c.is_alphanumeric())
            .filter(|w| !w.is_empty())
            .map(str::to_string)
            .collect()
    };
    let wanted = words(title);
    if wanted.is_empty() {
        return None;
    }
    let holding: Vec<usize> = (0..ours.len())
        .filter(|&i| {
            words(&ours[i].2)
                .windows(wanted.len())
                .any(|w| w == wanted.as_slice())
        })
        .collect();
    match holding.as_slice() {
        [i] => Some(near(*i, shown)),
        _ => None,
    }
}

/// What a title is compared as: lower case, straight quotes, no `*`, one
/// space between words, no end punctuation or leading `the`.
fn norm(s: &str) -> String {
    let s: String = s
        .chars()
        .filter(|&c| c != '*')
        .map(|c| match c {
            '’' | '‘' => '\'',
            '“' | '”' => '"',
            c => c,
        })
        .flat_map(char::to_lowercase)
        .collect();
    let s = s.split_whitespace().collect::<Vec<_>>().join(" ");
    let s = s.trim_matches(|c: char| ".,;:\"".contains(c)).trim();
    s.strip_prefix("the ").unwrap_or(s).to_string()
}

/// The forms of a title a reference may use: whole, before its first `:`,
/// before its first `,` (each as written and with its math rendered).
fn keys(title: &str) -> Vec<String> {
    let mut out = Vec::new();
    for t in [title.to_string(), flipcard_text::render(title)] {
        for k in [
            t.as_str(),
            t.split(':').next().unwrap_or(""),
            t.split(',').next().unwrap_or(""),
        ] {
            let k = norm(k);
            if !k.is_empty() && !out.contains(&k) {
                out.push(k);
            }
        }
    }
    out
}

/// `text` with math, code and links turned into [`MASK`] bytes (same
/// length, so offsets hold).
fn mask(text: &str) -> Vec<u8> {
    let mut b = text.as_bytes().to_vec();
    let blank = |b: &mut Vec<u8>, from: usize, to: usize| {
        for x in &mut b[from..to] {
            *x = MASK;
        }
    };
    let src = text.as_bytes();
    let mut i = 0;
    while i < src.len() {
        match src[i] {
            b'\\' => i += 2,
            b'$' => {
                let double = src.get(i + 1) == Some(&b'$');
                let delim: &[u8] = if double { b"$$" } else { b"$" };
                let from = i + delim.len();
                let end = find(src, from, delim).unwrap_or(src.len());
                let to = (end + delim.len()).min(src.len());
                blank(&mut b, i, to);
                i = to;
            }
            b'`' => {
                let end = find(src, i + 1, b"`").map_or(i + 1, |e| e + 1);
                blank(&mut b, i, end);
                i = end;
            }
            b'[' => {
                // `[text](#id)`: up to the `)` after `](#`.
                let close = find(src, i + 1, b"](#");
                let end = close.and_then(|c| find(src, c + 3, b")"));
                match end {
                    Some(e) if !src[i..e].contains(&b'\n') => {
                        blank(&mut b, i, e + 1);
                        i = e + 1;
                    }
                    _ => i += 1,
                }
            }
            _ => i += 1,
        }
    }
    b
}

fn find(hay: &[u8], from: usize, needle: &[u8]) -> Option<usize> {
    if from > hay.len() {
        return None;
    }
    hay[from..]
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|p| from + p)
}

fn is_word_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b >= 0x80
}

/// The word at `i` (ASCII letters, case-insensitively) if it is one of
/// `words`, as its end.
fn word_at(b: &[u8], i: usize, words: &[&str]) -> Option<usize> {
    if i > 0 && is_word_byte(b[i - 1]) {
        return None;
    }
    words.iter().find_map(|w| {
        let end = i + w.len();
        let fits = end <= b.len() && b[i..end].eq_ignore_ascii_case(w.as_bytes());
        (fits && b.get(end).is_none_or(|&c| !is_word_byte(c))).then_some(end)
    })
}

fn skip_spaces(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && (b[i] == b' ' || b[i] == b'\n' || b[i] == b'\t') {
        i += 1;
    }
    i
}

/// The titles `text` names in prose, in order (see the module's rules).
pub fn references(text: &str) -> Vec<Reference> {
    // A text that holds no verb anywhere (in any case, word or not) names
    // nothing; masking only ever removes words, so it is not needed then.
    if !has_verb(text.as_bytes()) {
        return Vec::new();
    }
    scan(text)
}

/// [`references`] without the shortcut for texts with no verb.
fn scan(text: &str) -> Vec<Reference> {
    let b = mask(text);
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if !STARTS_VERB[usize::from(b[i])] {
            i += 1;
            continue;
        }
        if let Some(end) = word_at(&b, i, SEE).or_else(|| word_at(&b, i, DEKHO)) {
            let hinglish = word_at(&b, i, DEKHO).is_some();
            if let Some(r) = after(text, &b, i, end) {
                out.push(r);
            } else if hinglish && let Some(r) = before(text, &b, i, end) {
                out.push(r);
            }
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

/// Whether `b` holds any verb of [`SEE`] or [`DEKHO`], ignoring case and
/// word boundaries.
fn has_verb(b: &[u8]) -> bool {
    (0..b.len()).any(|i| {
        STARTS_VERB[usize::from(b[i])]
            && SEE.iter().chain(DEKHO).any(|w| {
                b.get(i..i + w.len())
                    .is_some_and(|s| s.eq_ignore_ascii_case(w.as_bytes()))
            })
    })
}

/// A title after the verb that starts at `start` and ends at `end`.
fn after(text: &str, b: &[u8], start: usize, end: usize) -> Option<Reference> {
    let in_paren = text[..start].trim_end().ends_with('(');
    let mut p = skip_spaces(b, end);
    if let Some(e) = word_at(b, p, &["also"]) {
        p = skip_spaces(b, e);
    }
    let mut explicit = false;
    let q = word_at(b, p, &["the"]).map_or(p, |e| skip_spaces(b, e));
    if let Some(e) = word_at(b, q, &["section"]) {
        explicit = true;
        p = skip_spaces(b, e);
        if let Some(e) = word_at(b, p, SECTION_WORDS) {
            p = skip_spaces(b, e);
        }
    }
    if let Some(r) = marked(text, b, p) {
        // Quotes in running text are more often what is seen (`you see
        // "Wrong"`) than a title.
        let quoted = !text[p..].starts_with('*');
        let titled = !quoted || in_paren || explicit;
        return (titled && is_title(&r.title)).then_some(r);
    }
    if explicit {
        let stop = (p..b.len())
            .find(|&k| b".,;:!?()\n".contains(&b[k]))
            .unwrap_or(b.len());
        return bare(text, b, p, stop, false);
    }
    if in_paren {
        let close = (p..b.len()).find(|&k| b"()\n".contains(&b[k]))?;
        if b[close] != b')' {
            return None;
        }
        return bare(text, b, p, close, true);
    }
    None
}

/// A Hinglish title before the verb at `start`: marked, or the whole of a
/// parenthesis that the verb ends.
fn before(text: &str, b: &[u8], start: usize, end: usize) -> Option<Reference> {
    let head = text[..start].trim_end();
    let last = head.chars().next_back()?;
    if "*\"”’".contains(last) {
        let close = head.len() - last.len_utf8();
        let (open, delim_len) = match last {
            '*' => {
                let n = head.len() - head.trim_end_matches('*').len();
                let delim = &head[head.len() - n..];
                let inner_end = head.len() - n;
                (head[..inner_end].rfind(delim)?, n)
            }
            '”' => (head[..close].rfind('“')?, '“'.len_utf8()),
            '’' => (head[..close].rfind('‘')?, '‘'.len_utf8()),
            _ => (head[..close].rfind('"')?, 1),
        };
        let from = open + delim_len;
        let to = if last == '*' {
            head.len() - (head.len() - head.trim_end_matches('*').len())
        } else {
            close
        };
        if from >= to || b[from..to].contains(&MASK) || text[from..to].contains("\n\n") {
            return None;
        }
        let title = text[from..to].to_string();
        return is_title(&title).then_some(Reference { at: from, title });
    }
    // `(Applications dekhiye)`
    let after_verb = skip_spaces(b, end);
    if b.get(after_verb) != Some(&b')') {
        return None;
    }
    let open = head.rfind(['(', ')', '\n'])?;
    if !head[open..].starts_with('(') {
        return None;
    }
    let from = skip_spaces(b, open + 1);
    bare(text, b, from, head.len(), true)
}

/// An emphasised or quoted title starting at `p`.
fn marked(text: &str, b: &[u8], p: usize) -> Option<Reference> {
    let rest = text.get(p..)?;
    let (open_len, close): (usize, &str) = if rest.starts_with('*') {
        let n = rest.len() - rest.trim_start_matches('*').len();
        (n, &rest[..n])
    } else if rest.starts_with('"') {
        (1, "\"")
    } else if rest.starts_with('“') {
        ('“'.len_utf8(), "”")
    } else if rest.starts_with('‘') {
        ('‘'.len_utf8(), "’")
    } else {
        return None;
    };
    let from = p + open_len;
    let to = from + text[from..].find(close)?;
    if from >= to || b[from..to].contains(&MASK) || text[from..to].contains("\n\n") {
        return None;
    }
    Some(Reference {
        at: from,
        title: text[from..to].to_string(),
    })
}

/// The plain words from `from` to `to` as a title; `strict` (a
/// parenthesis) asks for a capital, few words, no number or citation.
fn bare(text: &str, b: &[u8], from: usize, to: usize, strict: bool) -> Option<Reference> {
    if from >= to || b[from..to].contains(&MASK) {
        return None;
    }
    let title = text[from..to].trim_end();
    if title.is_empty() {
        return None;
    }
    if strict {
        let words: Vec<&str> = title.split_whitespace().collect();
        let first = words.first()?.to_lowercase();
        let first = first.trim_end_matches('.');
        if !capitalised(title)
            || words.len() > MOST_WORDS
            || CITATION.contains(&first)
            || title.contains(|c: char| c.is_ascii_digit() || c == '§')
            || title.contains("et al")
        {
            return None;
        }
    }
    Some(Reference {
        at: from,
        title: title.to_string(),
    })
}

/// Whether marked words read as a title: a capital first, and no lead-in
/// label (`**Experiment:** dekho ki …`, `*Note.*`).
fn is_title(title: &str) -> bool {
    capitalised(title) && !title.trim_end().ends_with([':', '.'])
}

/// Whether a title starts with a capital letter (a title, not prose).
fn capitalised(title: &str) -> bool {
    title
        .trim_start()
        .chars()
        .next()
        .is_some_and(char::is_uppercase)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn titles_of(text: &str) -> Vec<String> {
        references(text).into_iter().map(|r| r.title).collect()
    }

    proptest::proptest! {
        /// The shortcut for texts without a verb never changes what is found.
        #[test]
        fn the_shortcut_finds_what_the_scan_finds(
            parts in proptest::collection::vec(
                proptest::sample::select(vec![
                    "see", "See ", "SEE", "dekho", "Dekhiye", "dekh", "se", "e", " ",
                    "(", ")", "*", "`", "$", "\\", "\"", "Applications", "section",
                    "the", "also", "x", ".", "\n", "“", "”", "é",
                ]),
                0..16,
            )
        ) {
            let text: String = parts.concat();
            proptest::prop_assert_eq!(references(&text), scan(&text));
        }
    }

    #[test]
    fn references_are_a_verb_and_a_title() {
        let cases: &[(&str, &[&str])] = &[
            ("stable (see Applications).", &["Applications"]),
            ("stable (See also Applications)", &["Applications"]),
            ("stable (see *Applications*)", &["Applications"]),
            (
                "stable, see **Earth's free wobble** for more",
                &["Earth's free wobble"],
            ),
            (
                "(see “Why we work in the body frame”).",
                &["Why we work in the body frame"],
            ),
            ("see the section on damping, which", &["damping"]),
            ("See section Damping.", &["Damping"]),
            ("(dekho *Applications*)", &["Applications"]),
            ("(dekhiye Applications)", &["Applications"]),
            ("(*Applications* dekho)", &["Applications"]),
            ("(Applications dekhiye)", &["Applications"]),
            // Prose, citations and links name nothing.
            ("You can see the same with a phone", &[]),
            ("see *why* it flips", &[]),
            ("(see below)", &[]),
            ("(see Figure 2)", &[]),
            ("(see Goldstein 2002)", &[]),
            ("(see e.g. Landau)", &[]),
            ("see Applications for more", &[]),
            ("(see [Applications](#applications))", &[]),
            ("(see $\\omega$)", &[]),
            ("axis 3 ki tip se dekho to counter-clockwise", &[]),
            ("see the section \"Damping\".", &["Damping"]),
            ("**Experiment:** dekho ki kya hota hai", &[]),
            ("*Note.* See *why* below", &[]),
            ("press Enter and see \"Wrong\" on the screen", &[]),
            ("body se dekho to $\\vec\\omega$", &[]),
            ("a (long aside that goes on) and see", &[]),
            (
                "(see A very long phrase that has far too many words to be a title)",
                &[],
            ),
        ];
        for (text, want) in cases {
            assert_eq!(titles_of(text), *want, "{text}");
        }
    }

    #[test]
    fn the_offset_is_the_titles() {
        let text = "x (see *Applications*)";
        let r = &references(text)[0];
        assert_eq!(&text[r.at..r.at + r.title.len()], "Applications");
        let text = "x (*Stability* dekho)";
        let r = &references(text)[0];
        assert_eq!(&text[r.at..r.at + r.title.len()], "Stability");
    }

    fn titles() -> Titles {
        let t = |id: &str, lang: &str, title: &str| (id.into(), lang.into(), title.into());
        Titles {
            of: vec![
                t(
                    "ellipsoids",
                    "en",
                    "Energy and momentum ellipsoids, and polhodes",
                ),
                t(
                    "earth-wobble",
                    "en",
                    "Earth’s free wobble: 305 days on paper",
                ),
                t("applications", "en", "Where it matters: satellites, Earth"),
                t("applications", "hi-Latn", "Kahan kaam aata hai: satellites"),
                t("damping", "en", "Damping: underdamped, critical"),
                t("chandler", "en", "The Chandler wobble"),
            ],
            known: true,
        }
    }

    #[test]
    fn a_title_resolves_whole_or_before_its_colon_or_comma() {
        let t = titles();
        for ok in [
            "Energy and momentum ellipsoids, and polhodes",
            "Energy and momentum ellipsoids",
            "Earth's free wobble",
            "damping",
            "the Damping",
            "*Where it matters*",
        ] {
            assert!(resolves(ok, "en", &t), "{ok}");
        }
        for dangling in ["Applications", "Polhodes", "Earth"] {
            assert!(!resolves(dangling, "en", &t), "{dangling}");
        }
        // A title is looked up in the text's own language.
        assert!(!resolves("Where it matters", "hi-Latn", &t));
    }

    #[test]
    fn the_hint_names_the_closest_title_or_the_id_it_makes() {
        let t = titles();
        assert_eq!(
            closest("Applications", "en", &t),
            Some(Near {
                id: "applications".into(),
                title: "Where it matters: satellites, Earth".into(),
                link_text: "Applications".into(),
            })
        );
        // A misspelt title is linked spelt right.
        let damping = closest("Dampnig", "en", &t).unwrap();
        assert_eq!((&*damping.id, &*damping.link_text), ("damping", "Damping"));
        assert_eq!(
            closest("Applications", "hi-Latn", &t).map(|n| n.title),
            Some("Kahan kaam aata hai: satellites".into())
        );
        // Words of one title only.
        assert_eq!(
            closest("satellites", "en", &t).map(|n| n.id),
            Some("applications".into())
        );
        // The start of a title.
        assert_eq!(
            closest("Earth", "en", &t).map(|n| n.id),
            Some("earth-wobble".into())
        );
        // Words of two titles, or of none, name no section.
        assert_eq!(closest("Wobble", "en", &t), None);
        assert_eq!(closest("Gyroscopes", "en", &t), None);
    }

    /// Pieces of prose a reference is made of, and of the marks around it.
    const PIECES: &[&str] = &[
        "see",
        "See",
        "dekho",
        "dekhiye",
        "also",
        "the",
        "section",
        "on",
        "(",
        ")",
        "*",
        "**",
        "\"",
        "“",
        "”",
        "‘",
        "’",
        "$",
        "`",
        "[",
        "](#a)",
        "é",
        "ω₂",
        ":",
        ",",
        ".",
        "\n",
        "Applications",
        "Damping",
        "why",
        "Figure",
        "2",
        "(see ",
        "see *",
        "(dekho *",
        "* dekho)",
        " dekhiye)",
        "see the section on ",
        "(see “",
        "”)",
        "Earth’s free wobble",
    ];

    proptest::proptest! {
        /// Any text, however its marks, parentheses, quotes, `$` and
        /// non-ASCII letters fall: no panic, and each reference is the text
        /// at its offset.
        #[test]
        fn any_text_gives_references_at_their_place(
            pieces in proptest::collection::vec(
                (proptest::sample::select(PIECES), proptest::bool::ANY),
                0..24,
            )
        ) {
            let text: String = pieces
                .iter()
                .map(|(p, space)| if *space { format!("{p} ") } else { p.to_string() })
                .collect();
            for r in references(&text) {
                proptest::prop_assert_eq!(
                    text.get(r.at..r.at + r.title.len()),
                    Some(r.title.as_str())
                );
            }
        }
    }
}
