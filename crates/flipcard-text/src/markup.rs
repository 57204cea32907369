//! The light markup of explanation section bodies, as a structure the
//! terminal UI styles itself (this module knows nothing of terminals):
//!
//! - paragraphs are separated by blank lines; the lines of a paragraph are
//!   joined with spaces;
//! - a line starting with `- ` starts a list item (following lines continue
//!   it until a blank line or the next item);
//! - `*emphasis*` and `**strong**`; a `*` that opens or closes nothing stays
//!   a `*` (so `a * b` is left alone);
//! - `$...$` math is rendered to Unicode; `$$...$$` display math in a
//!   paragraph becomes a block of its own. A formula that does not parse is
//!   shown as written;
//! - `[text](#section-id)` links its text to another section; brackets that
//!   do not form a link stay as written;
//! - `` `code` `` (a command, a file name) is shown as written, without its
//!   backticks and without markup inside; a backtick that closes nothing
//!   stays a backtick;
//! - a line that is only `{#name}` is an anchor: it is not shown, and it
//!   names the block that follows it, so that a prompt or card can open the
//!   section there (`explain = "section-id#name"`). It ends the paragraph
//!   or item before it.

use super::dollar::{self, Piece};
use super::write_math;

/// A block of a section body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Block {
    Paragraph(Vec<Span>),
    /// A list item (its text, without the `- `).
    Item(Vec<Span>),
    /// Display math, rendered.
    Display(String),
}

/// A run of text in one style.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Span {
    pub text: String,
    pub style: Style,
    /// The section this text links to (`[text](#id)`).
    pub link: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Plain,
    Emphasis,
    Strong,
    /// Rendered math (inside emphasis too).
    Math,
    /// `` `code` ``, as written.
    Code,
}

impl Span {
    pub fn new(text: impl Into<String>, style: Style) -> Span {
        Span {
            text: text.into(),
            style,
            link: None,
        }
    }

    pub fn linked(text: impl Into<String>, style: Style, link: &str) -> Span {
        Span {
            link: Some(link.to_string()),
            ..Span::new(text, style)
        }
    }
}

/// The sections `body` links to inline, in reading order (repeats kept).
pub fn links(body: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for block in parse(body) {
        if let Block::Paragraph(spans) | Block::Item(spans) = block {
            let mut last: Option<&str> = None;
            for s in &spans {
                // Consecutive spans of one link (styles change inside it)
                // are one link.
                if let Some(l) = &s.link
                    && last != Some(l.as_str())
                {
                    out.push(l.clone());
                }
                last = s.link.as_deref();
            }
        }
    }
    out
}

impl Block {
    /// The block's text without styles.
    pub fn text(&self) -> String {
        match self {
            Block::Paragraph(spans) | Block::Item(spans) => {
                spans.iter().map(|s| s.text.as_str()).collect()
            }
            Block::Display(math) => math.clone(),
        }
    }
}

/// The blocks of `body`, in order.
pub fn parse(body: &str) -> Vec<Block> {
    parse_anchored(body).0
}

/// The blocks of `body`, and each anchor (`{#name}` on a line of its own)
/// with the index of the block it names: the first block after it
/// (`blocks.len()` for an anchor after the last block).
pub fn parse_anchored(body: &str) -> (Vec<Block>, Vec<(String, usize)>) {
    let mut blocks = Vec::new();
    let mut anchors = Vec::new();
    for raw in raw_blocks(body) {
        match raw {
            Raw::Anchor(name) => anchors.push((name, blocks.len())),
            Raw::Block(kind, text) => inline(&text, kind, &mut blocks),
        }
    }
    (blocks, anchors)
}

/// The anchor a line declares: the line, trimmed, is `{#name}` with a name
/// of no spaces or braces.
pub fn anchor_of(line: &str) -> Option<&str> {
    let name = line.trim().strip_prefix("{#")?.strip_suffix('}')?;
    let fits = !name.is_empty() && !name.contains(|c: char| c.is_whitespace() || "{}#".contains(c));
    fits.then_some(name)
}

/// The anchors `body` declares, in order (repeats kept), each with the
/// byte offset of its name in `body`.
pub fn anchors(body: &str) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    let mut at = 0;
    for line in body.split_inclusive('\n') {
        if let Some(name) = anchor_of(line) {
            let offset = line.find("{#").map_or(0, |i| i + 2);
            out.push((name.to_string(), at + offset));
        }
        at += line.len();
    }
    out
}

/// `body` rendered without markup: one line per block, items as `• `.
/// For search and one-line previews.
pub fn plain(body: &str) -> String {
    let mut out = String::with_capacity(body.len());
    for block in parse(body) {
        if !out.is_empty() {
            out.push('\n');
        }
        if matches!(block, Block::Item(_)) {
            out.push_str("• ");
        }
        match block {
            Block::Paragraph(spans) | Block::Item(spans) => {
                spans.iter().for_each(|s| out.push_str(&s.text));
            }
            Block::Display(math) => out.push_str(&math),
        }
    }
    out
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Paragraph,
    Item,
}

/// A block as written, or an anchor between blocks.
enum Raw {
    Block(Kind, String),
    Anchor(String),
}

/// Blocks as trimmed lines joined with `\n` (math may span lines), and
/// the anchors between them.
fn raw_blocks(body: &str) -> Vec<Raw> {
    let mut blocks: Vec<Raw> = Vec::new();
    let mut open = false;
    for line in body.lines() {
        let line = line.trim();
        if line.is_empty() {
            open = false;
            continue;
        }
        if let Some(name) = anchor_of(line) {
            blocks.push(Raw::Anchor(name.to_string()));
            open = false;
            continue;
        }
        let item = line.strip_prefix("- ").or((line == "-").then_some(""));
        match (item, blocks.last_mut()) {
            (Some(rest), _) => blocks.push(Raw::Block(Kind::Item, rest.trim_start().to_string())),
            (None, Some(Raw::Block(_, text))) if open => {
                text.push('\n');
                text.push_str(line);
            }
            (None, _) => blocks.push(Raw::Block(Kind::Paragraph, line.to_string())),
        }
        open = true;
    }
    blocks
}

/// A token of a block's inline content.
#[derive(Debug)]
enum Tok<'a> {
    /// Text as written (newlines become spaces when it is pushed).
    Text(&'a str),
    /// `` `code` ``, its text without the backticks.
    Code(&'a str),
    Math(String),
    Display(String),
    /// `[`, which opens a link when a `](#id)` follows in the block
    /// (`target` is then filled in).
    LinkOpen {
        target: Option<String>,
    },
    /// `](#id)`, closing a link when it was opened.
    LinkClose {
        target: String,
        matched: bool,
    },
    /// A run of `*` (1 or 2 long), with whether it can open or close.
    Stars {
        count: u8,
        open: bool,
        close: bool,
        matched: bool,
    },
}

fn inline(text: &str, kind: Kind, blocks: &mut Vec<Block>) {
    let mut toks = Vec::new();
    for piece in dollar::pieces(text) {
        match piece {
            Piece::Text(s) => code_links_stars_and_text(text, s, &mut toks),
            Piece::Dollar => toks.push(Tok::Text("$")),
            Piece::Math(m) => {
                let mut rendered = String::new();
                if write_math(m.latex, &mut rendered).is_err() {
                    rendered.clear();
                    rendered.push_str(&m.source.replace('\n', " "));
                }
                toks.push(if m.display && kind == Kind::Paragraph {
                    Tok::Display(rendered)
                } else {
                    Tok::Math(rendered)
                });
            }
            Piece::Unclosed { offset, .. } => {
                code_links_stars_and_text(text, &text[offset..], &mut toks)
            }
        }
    }
    match_stars(&mut toks);
    match_links(&mut toks);

    let mut spans: Vec<Span> = Vec::new();
    let (mut emphasis, mut strong) = (0u32, 0u32);
    let mut link: Option<String> = None;
    let finish = |spans: &mut Vec<Span>, blocks: &mut Vec<Block>| {
        trim_spans(spans);
        if !spans.is_empty() {
            let spans = std::mem::take(spans);
            blocks.push(match kind {
                Kind::Paragraph => Block::Paragraph(spans),
                Kind::Item => Block::Item(spans),
            });
        }
    };
    for tok in toks {
        let style = if strong > 0 {
            Style::Strong
        } else if emphasis > 0 {
            Style::Emphasis
        } else {
            Style::Plain
        };
        let to = link.as_deref();
        match tok {
            Tok::Text(s) => push_span(&mut spans, s, style, to),
            Tok::Math(s) => push_span(&mut spans, &s, Style::Math, to),
            Tok::Code(s) => push_span(&mut spans, s, Style::Code, to),
            Tok::Display(s) => {
                finish(&mut spans, blocks);
                blocks.push(Block::Display(s));
            }
            Tok::LinkOpen {
                target: Some(target),
            } => link = Some(target),
            Tok::LinkOpen { target: None } => push_span(&mut spans, "[", style, to),
            Tok::LinkClose { matched: true, .. } => link = None,
            Tok::LinkClose { target, .. } => {
                push_span(&mut spans, &format!("](#{target})"), style, to)
            }
            Tok::Stars {
                count,
                open,
                matched: true,
                ..
            } => {
                let depth = if count == 2 {
                    &mut strong
                } else {
                    &mut emphasis
                };
                if open {
                    *depth += 1;
                } else {
                    *depth = depth.saturating_sub(1);
                }
            }
            Tok::Stars { count, .. } => {
                push_span(&mut spans, if count == 2 { "**" } else { "*" }, style, to);
            }
        }
    }
    finish(&mut spans, blocks);
}

/// Split a text piece at pairs of backticks: what is between two is code,
/// the rest goes through [`links_stars_and_text`]; a backtick left alone
/// stays.
fn code_links_stars_and_text<'a>(whole: &str, piece: &'a str, toks: &mut Vec<Tok<'a>>) {
    let mut rest = piece;
    while let Some(open) = rest.find('`') {
        let Some(len) = rest[open + 1..].find('`') else {
            break;
        };
        if len == 0 {
            // `` `` ``: two backticks, no code.
            links_stars_and_text(whole, &rest[..open + 2], toks);
            rest = &rest[open + 2..];
            continue;
        }
        links_stars_and_text(whole, &rest[..open], toks);
        toks.push(Tok::Code(&rest[open + 1..open + 1 + len]));
        rest = &rest[open + 2 + len..];
    }
    links_stars_and_text(whole, rest, toks);
}

/// Split a text piece (a slice of `whole`) at link brackets (`[` and
/// `](#id)`), the rest going through [`stars_and_text`].
fn links_stars_and_text<'a>(whole: &str, piece: &'a str, toks: &mut Vec<Tok<'a>>) {
    let mut start = 0;
    let mut i = 0;
    while i < piece.len() {
        let rest = &piece[i..];
        if rest.starts_with('[') {
            stars_and_text(whole, &piece[start..i], toks);
            toks.push(Tok::LinkOpen { target: None });
            i += 1;
            start = i;
            continue;
        }
        if let Some(after) = rest.strip_prefix("](#") {
            let len = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-' || c == '_'))
                .unwrap_or(after.len());
            if len > 0 && after[len..].starts_with(')') {
                stars_and_text(whole, &piece[start..i], toks);
                toks.push(Tok::LinkClose {
                    target: after[..len].to_string(),
                    matched: false,
                });
                i += 3 + len + 1;
                start = i;
                continue;
            }
        }
        i += rest.chars().next().map_or(1, char::len_utf8);
    }
    stars_and_text(whole, &piece[start..], toks);
}

/// Pair link brackets: a `](#id)` closes the nearest `[` before it; links
/// do not nest, and whatever is left unpaired stays literal.
fn match_links(toks: &mut [Tok<'_>]) {
    let mut open: Option<usize> = None;
    for i in 0..toks.len() {
        match &toks[i] {
            Tok::LinkOpen { .. } => open = Some(i),
            Tok::LinkClose { target, .. } => {
                if let Some(j) = open.take() {
                    let target = target.clone();
                    if let Tok::LinkOpen { target: t } = &mut toks[j] {
                        *t = Some(target);
                    }
                    if let Tok::LinkClose { matched, .. } = &mut toks[i] {
                        *matched = true;
                    }
                }
            }
            _ => {}
        }
    }
}

/// Split a text piece (a slice of `whole`) into text and `*` runs, newlines
/// becoming spaces. Whether a run can open or close depends on the
/// characters around it in `whole`, math included.
fn stars_and_text<'a>(whole: &str, piece: &'a str, toks: &mut Vec<Tok<'a>>) {
    let base = piece.as_ptr() as usize - whole.as_ptr() as usize;
    let mut rest_start = 0;
    let bytes = piece.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != b'*' {
            i += 1;
            continue;
        }
        let run = bytes[i..].iter().take_while(|&&b| b == b'*').count();
        push_text(toks, &piece[rest_start..i]);
        let before = whole[..base + i].chars().next_back();
        let after = whole[base + i + run..].chars().next();
        let open = after.is_some_and(|c| !c.is_whitespace());
        let close = before.is_some_and(|c| !c.is_whitespace());
        let star = |count, open, close| Tok::Stars {
            count,
            open,
            close,
            matched: false,
        };
        match run {
            1 | 2 => toks.push(star(run as u8, open, close)),
            // `***a***`: strong around emphasis.
            3 if open => {
                toks.push(star(2, open, close));
                toks.push(star(1, open, close));
            }
            3 => {
                toks.push(star(1, open, close));
                toks.push(star(2, open, close));
            }
            _ => push_text(toks, &piece[i..i + run]),
        }
        i += run;
        rest_start = i;
    }
    push_text(toks, &piece[rest_start..]);
}

fn push_text<'a>(toks: &mut Vec<Tok<'a>>, s: &'a str) {
    if !s.is_empty() {
        toks.push(Tok::Text(s));
    }
}

/// Pair `*` runs: a closer takes the nearest open run of the same length,
/// and open runs of the other length inside the pair stay literal; runs
/// left unpaired stay literal too. One stack per length keeps this linear.
fn match_stars(toks: &mut [Tok<'_>]) {
    let mut openers: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
    for i in 0..toks.len() {
        let Tok::Stars {
            count, open, close, ..
        } = toks[i]
        else {
            continue;
        };
        let (same, other) = if count == 2 { (1, 0) } else { (0, 1) };
        if let (true, Some(j)) = (close, openers[same].pop()) {
            while openers[other].last().is_some_and(|&k| k > j) {
                openers[other].pop();
            }
            set_matched(&mut toks[j], true);
            set_matched(&mut toks[i], false);
            continue;
        }
        if open {
            openers[same].push(i);
        }
    }
}

fn set_matched(tok: &mut Tok<'_>, as_opener: bool) {
    if let Tok::Stars { open, matched, .. } = tok {
        *open = as_opener;
        *matched = true;
    }
}

/// Append `text` (newlines as spaces) to the last span if it has the same
/// style, else as a new span.
fn push_span(spans: &mut Vec<Span>, text: &str, style: Style, link: Option<&str>) {
    if text.is_empty() {
        return;
    }
    let span = match spans.last_mut() {
        Some(last) if last.style == style && last.link.as_deref() == link => last,
        _ => {
            spans.push(Span {
                link: link.map(str::to_string),
                ..Span::new(String::with_capacity(text.len()), style)
            });
            let Some(last) = spans.last_mut() else {
                return;
            };
            last
        }
    };
    let mut parts = text.split('\n');
    if let Some(first) = parts.next() {
        span.text.push_str(first);
    }
    for part in parts {
        span.text.push(' ');
        span.text.push_str(part);
    }
}

/// Drop the spaces a display block or the block edges leave behind.
fn trim_spans(spans: &mut Vec<Span>) {
    if let Some(first) = spans.first_mut() {
        let trimmed = first.text.trim_start().len();
        first.text.drain(..first.text.len() - trimmed);
    }
    if let Some(last) = spans.last_mut() {
        let trimmed = last.text.trim_end().len();
        last.text.truncate(trimmed);
    }
    spans.retain(|s| !s.text.is_empty());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_is_shown_as_written_without_its_backticks() {
        let blocks = parse("Run `flipcard sim --scene a*b*c` *now*; a lone ` stays.");
        let Block::Paragraph(spans) = &blocks[0] else {
            panic!("{blocks:?}");
        };
        assert_eq!(spans[0], Span::new("Run ", Style::Plain));
        assert_eq!(
            spans[1],
            Span::new("flipcard sim --scene a*b*c", Style::Code)
        );
        assert!(
            spans.contains(&Span::new("now", Style::Emphasis)),
            "{spans:?}"
        );
        assert!(
            blocks[0].text().ends_with("a lone ` stays."),
            "{}",
            blocks[0].text()
        );
        // Two backticks together are not code; math keeps its own rules.
        assert_eq!(plain("a `` b and $x$ `y`"), "a `` b and x y");
    }

    fn plain_span(s: &str) -> Span {
        Span::new(s, Style::Plain)
    }

    #[test]
    fn paragraphs_are_separated_by_blank_lines_and_lines_joined() {
        assert_eq!(
            parse("First line\nsecond line.\n\n  \nNext one."),
            vec![
                Block::Paragraph(vec![plain_span("First line second line.")]),
                Block::Paragraph(vec![plain_span("Next one.")]),
            ]
        );
    }

    #[test]
    fn items_start_with_dash_and_continue_on_following_lines() {
        assert_eq!(
            parse("Intro:\n- one\n- two\n  continued\n\nAfter."),
            vec![
                Block::Paragraph(vec![plain_span("Intro:")]),
                Block::Item(vec![plain_span("one")]),
                Block::Item(vec![plain_span("two continued")]),
                Block::Paragraph(vec![plain_span("After.")]),
            ]
        );
    }

    #[test]
    fn emphasis_and_strong() {
        assert_eq!(
            parse("a *b* and **c d** e"),
            vec![Block::Paragraph(vec![
                plain_span("a "),
                Span::new("b", Style::Emphasis),
                plain_span(" and "),
                Span::new("c d", Style::Strong),
                plain_span(" e"),
            ])]
        );
    }

    #[test]
    fn links_name_a_section_and_keep_their_styles() {
        assert_eq!(
            parse("see [the **body** frame](#body-frame), or [x](#)"),
            vec![Block::Paragraph(vec![
                plain_span("see "),
                Span::linked("the ", Style::Plain, "body-frame"),
                Span::linked("body", Style::Strong, "body-frame"),
                Span::linked(" frame", Style::Plain, "body-frame"),
                plain_span(", or [x](#)"),
            ])]
        );
        assert_eq!(
            links("- [a $x$](#one) and [b](#two)\n- [c](#one)"),
            ["one", "two", "one"]
        );
        // Brackets that are no link stay as written.
        assert_eq!(
            parse("[a, b] and f(x)](#not a link)"),
            vec![Block::Paragraph(vec![plain_span(
                "[a, b] and f(x)](#not a link)"
            )])]
        );
    }

    #[test]
    fn triple_star_is_strong() {
        assert_eq!(
            parse("***x***"),
            vec![Block::Paragraph(vec![Span::new("x", Style::Strong)])]
        );
    }

    #[test]
    fn lone_stars_stay_literal() {
        assert_eq!(
            parse("a * b and *c"),
            vec![Block::Paragraph(vec![plain_span("a * b and *c")])]
        );
        assert_eq!(
            parse("**a*"),
            vec![Block::Paragraph(vec![plain_span("**a*")])]
        );
    }

    #[test]
    fn unmatched_inner_run_stays_literal() {
        assert_eq!(
            parse("*a **b c*"),
            vec![Block::Paragraph(vec![Span::new(
                "a **b c",
                Style::Emphasis
            )])]
        );
    }

    #[test]
    fn many_unpaired_runs_stay_fast_and_literal() {
        let body = "**a ".repeat(20_000) + &"b* ".repeat(20_000);
        let blocks = parse(&body);
        assert_eq!(blocks.len(), 1);
        assert_eq!(blocks[0].text().matches('*').count(), 60_000);
    }

    #[test]
    fn math_is_rendered_inside_emphasis() {
        assert_eq!(
            parse(r"*spin $\omega_3$ axis*"),
            vec![Block::Paragraph(vec![
                Span::new("spin ", Style::Emphasis),
                Span::new("ω₃", Style::Math),
                Span::new(" axis", Style::Emphasis),
            ])]
        );
    }

    #[test]
    fn star_inside_math_is_not_emphasis() {
        assert_eq!(
            parse(r"$a^*$ and $b^*$"),
            vec![Block::Paragraph(vec![
                Span::new("a^∗", Style::Math),
                plain_span(" and "),
                Span::new("b^∗", Style::Math),
            ])]
        );
    }

    #[test]
    fn display_math_in_a_paragraph_is_its_own_block() {
        assert_eq!(
            parse("Euler:\n$$I_1\\dot\\omega_1 = 0$$\nso it holds."),
            vec![
                Block::Paragraph(vec![plain_span("Euler:")]),
                Block::Display("I₁ω̇₁ = 0".to_string()),
                Block::Paragraph(vec![plain_span("so it holds.")]),
            ]
        );
    }

    #[test]
    fn display_math_may_span_lines() {
        assert_eq!(
            parse("$$\na =\nb\n$$"),
            vec![Block::Display("a = b".to_string())]
        );
    }

    #[test]
    fn display_math_in_an_item_stays_inline() {
        assert_eq!(
            parse("- so $$x$$"),
            vec![Block::Item(vec![
                plain_span("so "),
                Span::new("x", Style::Math)
            ])]
        );
    }

    #[test]
    fn bad_math_is_shown_as_written() {
        assert_eq!(
            parse(r"see $\nope$"),
            vec![Block::Paragraph(vec![
                plain_span("see "),
                Span::new(r"$\nope$", Style::Math),
            ])]
        );
        assert_eq!(
            parse("costs $5"),
            vec![Block::Paragraph(vec![plain_span("costs $5")])]
        );
    }

    #[test]
    fn escaped_dollar() {
        assert_eq!(
            parse(r"\$5 *off*"),
            vec![Block::Paragraph(vec![
                plain_span("$5 "),
                Span::new("off", Style::Emphasis)
            ])]
        );
    }

    #[test]
    fn plain_drops_markup() {
        let body = "The **middle** axis is *unstable*:\n\n- spin $\\omega_2$\n- flip\n\n$$k > 0$$";
        assert_eq!(
            plain(body),
            "The middle axis is unstable:\n• spin ω₂\n• flip\nk > 0"
        );
    }

    #[test]
    fn empty_body_has_no_blocks() {
        assert!(parse("").is_empty());
        assert!(parse("\n  \n\n").is_empty());
        assert_eq!(plain(""), "");
    }

    #[test]
    fn an_anchor_line_names_the_block_after_it_and_is_not_shown() {
        let body = "First paragraph\nstill first.\n{#second}\nSecond paragraph.\n\n- an item\n  {#after-item}\n\n$$x^2$$\n{#end}\n";
        let (blocks, anchors) = parse_anchored(body);
        assert_eq!(blocks.len(), 4, "{blocks:?}");
        assert_eq!(blocks[0].text(), "First paragraph still first.");
        assert_eq!(blocks[1].text(), "Second paragraph.");
        assert_eq!(
            anchors,
            vec![
                ("second".to_string(), 1),
                ("after-item".to_string(), 3),
                ("end".to_string(), 4)
            ]
        );
        assert!(!plain(body).contains("{#"), "{}", plain(body));
        let found = super::anchors(body);
        let names: Vec<&str> = found.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["second", "after-item", "end"]);
        for (name, at) in &found {
            assert_eq!(&body[*at..*at + name.len()], name.as_str());
        }
        // Not an anchor: braces inside text, a space, an empty name.
        for line in ["see {#a} here", "{# a}", "{#}", "{#a b}", "{#a}}"] {
            assert_eq!(anchor_of(line), None, "{line}");
        }
    }

    proptest::proptest! {
        /// Any body: the anchors the reader places are the ones `check`
        /// finds, in order, each naming a block that exists (or the end),
        /// and every other line's text is still shown.
        #[test]
        fn anchors_are_found_alike_and_name_blocks_in_order(
            lines in proptest::collection::vec(
                proptest::prop_oneof![
                    "[a-z]{1,6}( [a-z]{1,6}){0,3}",
                    "- [a-z]{1,6}",
                    "\\{#[a-z0-9-]{1,8}\\}",
                    " *",
                    "[{}#a ]{0,6}",
                ],
                0..24,
            )
        ) {
            let body = lines.join("\n");
            let (blocks, anchors) = parse_anchored(&body);
            let found = super::anchors(&body);
            let names: Vec<&String> = anchors.iter().map(|(n, _)| n).collect();
            let found_names: Vec<&String> = found.iter().map(|(n, _)| n).collect();
            proptest::prop_assert_eq!(names, found_names);
            let mut last = 0;
            for (_, i) in &anchors {
                proptest::prop_assert!(*i >= last && *i <= blocks.len());
                last = *i;
            }
            let shown: String = blocks.iter().map(Block::text).collect::<Vec<_>>().join(" ");
            for line in &lines {
                let word = line.trim().trim_start_matches("- ");
                if anchor_of(line).is_none() && !word.is_empty() && !word.contains(['{', '}', '#', '*', '-']) {
                    proptest::prop_assert!(shown.contains(word), "{word:?} not in {shown:?}");
                }
            }
        }
    }
}
