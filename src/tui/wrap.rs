//! Word wrapping of styled text to a width, done here rather than by the
//! paragraph widget so that scrolling, `G` and search know exactly which
//! line is where.

use ratatui::style::Style;
use ratatui::text::{Line, Span};
use unicode_width::UnicodeWidthChar;

/// A run of text in one style.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub text: String,
    pub style: Style,
    /// Spaces inside do not break the line (inline math: `I₁ < I₂` stays
    /// on one line unless it is longer than a whole line).
    pub glue: bool,
    /// A mark carried to the lines the run lands on ([`wrap_tagged`]), to
    /// find a link or a match after wrapping.
    pub tag: Option<usize>,
}

impl Run {
    pub fn new(text: impl Into<String>, style: Style) -> Run {
        Run {
            text: text.into(),
            style,
            glue: false,
            tag: None,
        }
    }

    /// A run whose spaces do not break the line.
    pub fn glued(mut self) -> Run {
        self.glue = true;
        self
    }

    pub fn tagged(mut self, tag: Option<usize>) -> Run {
        self.tag = tag;
        self
    }
}

fn width(s: &str) -> usize {
    s.chars().map(|c| c.width().unwrap_or(0)).sum()
}

/// A word: the fragments between two whitespace runs (math followed by a
/// comma stays one word even though the styles differ).
type Word = Vec<Run>;

enum Token {
    Word(Word),
    /// A space, in the style of the run it was written in (a link's
    /// style ends with the link, not at the next word).
    Space(Style),
    Break,
}

fn tokens(runs: &[Run]) -> Vec<Token> {
    let mut out = Vec::new();
    let mut word: Word = Vec::new();
    let flush = |word: &mut Word, out: &mut Vec<Token>| {
        if !word.is_empty() {
            out.push(Token::Word(std::mem::take(word)));
        }
    };
    for run in runs {
        let mut frag = String::new();
        let piece = |frag: String| Run {
            text: frag,
            ..run.clone()
        };
        for c in run.text.chars() {
            if c == '\n' || (c.is_whitespace() && !run.glue) {
                if !frag.is_empty() {
                    word.push(piece(std::mem::take(&mut frag)));
                }
                flush(&mut word, &mut out);
                out.push(if c == '\n' {
                    Token::Break
                } else {
                    Token::Space(run.style)
                });
            } else {
                frag.push(c);
            }
        }
        if !frag.is_empty() {
            word.push(piece(frag));
        }
    }
    flush(&mut word, &mut out);
    glue_units(out)
}

/// Units a number keeps on its line ("1 m", "2.006 s", "9.81 m/s²").
const UNITS: &[&str] = &[
    "s", "ms", "µs", "min", "h", "d", "yr", "m", "cm", "mm", "km", "kg", "g", "N", "J", "W", "Hz",
    "rad", "deg", "°", "K", "%", "AU", "m/s", "m/s²", "rad/s", "rad/s²", "1/s", "km/s", "N·m",
    "kg·m²", "days", "years", "seconds", "din", "saal",
];

/// A number and the unit after it made one word: `Word, Space, Word`
/// where the first ends in a digit and the second is a unit (followed at
/// most by punctuation).
fn glue_units(tokens: Vec<Token>) -> Vec<Token> {
    let text = |w: &Word| w.iter().map(|r| r.text.as_str()).collect::<String>();
    let mut out: Vec<Token> = Vec::with_capacity(tokens.len());
    let mut it = tokens.into_iter().peekable();
    let is_unit = |t: &Token| {
        matches!(t, Token::Word(w)
            if UNITS.contains(&text(w).trim_end_matches([',', '.', ';', ':', ')', '!', '?'])))
    };
    while let Some(token) = it.next() {
        if let Token::Space(style) = token
            && let Some(Token::Word(prev)) = out.last_mut()
            && text(prev).ends_with(|c: char| c.is_ascii_digit())
            && let Some(Token::Word(next)) = it.next_if(is_unit)
        {
            prev.push(Run::new(" ", style));
            prev.extend(next);
            continue;
        }
        out.push(token);
    }
    out
}

struct Builder {
    width: usize,
    first_prefix: Run,
    rest_prefix: Run,
    lines: Vec<Line<'static>>,
    current: Vec<Span<'static>>,
    used: usize,
    pending_space: Option<Style>,
    /// (tag, line) for every tagged run pushed, in order.
    tags: Vec<(usize, usize)>,
}

impl Builder {
    fn prefix(&self) -> &Run {
        if self.lines.is_empty() {
            &self.first_prefix
        } else {
            &self.rest_prefix
        }
    }
    fn start_line(&mut self) {
        let p = self.prefix().clone();
        self.used = width(&p.text);
        self.current = if p.text.is_empty() {
            Vec::new()
        } else {
            vec![Span::styled(p.text, p.style)]
        };
        self.pending_space = None;
    }
    fn end_line(&mut self) {
        let spans = std::mem::take(&mut self.current);
        self.lines.push(Line::from(spans));
        self.start_line();
    }
    fn available(&self) -> usize {
        self.width.saturating_sub(self.used)
    }
    fn at_line_start(&self) -> bool {
        self.used == width(&self.prefix().text)
    }
    fn push(&mut self, text: String, style: Style, tag: Option<usize>) {
        if let Some(tag) = tag {
            let line = self.lines.len();
            if !self.tags.contains(&(tag, line)) {
                self.tags.push((tag, line));
            }
        }
        self.used += width(&text);
        self.current.push(Span::styled(text, style));
    }
    fn word(&mut self, word: Word) {
        let w: usize = word.iter().map(|r| width(&r.text)).sum();
        let space = usize::from(self.pending_space.is_some() && !self.at_line_start());
        if space + w > self.available() && !self.at_line_start() {
            self.end_line();
        } else if space == 1
            && let Some(style) = self.pending_space
        {
            self.push(" ".into(), style, None);
        }
        self.pending_space = None;
        if w <= self.available() {
            for run in word {
                self.push(run.text, run.style, run.tag);
            }
            return;
        }
        // A formula longer than a whole line: break it where mathematics
        // breaks (beside a top-level operator), else between factors, else
        // inside brackets; never inside a symbol or a number.
        if let Some(pieces) = split_formula(&word, self.available()) {
            let style = word.first().map_or(Style::default(), |r| r.style);
            for (i, piece) in pieces.into_iter().enumerate() {
                if i > 0 {
                    self.pending_space = Some(style);
                }
                self.word(piece);
            }
            return;
        }
        // Longer than a whole line: break it by characters, keeping
        // zero-width combining marks with their base character.
        for run in word {
            let mut chunk = String::new();
            for c in run.text.chars() {
                let cw = c.width().unwrap_or(0);
                if cw > 0 && width(&chunk) + cw > self.available() {
                    if !chunk.is_empty() {
                        self.push(std::mem::take(&mut chunk), run.style, run.tag);
                    }
                    if !self.at_line_start() {
                        self.end_line();
                    }
                    if cw > self.available() {
                        // Not even one character fits: give up on this one.
                        continue;
                    }
                }
                chunk.push(c);
            }
            if !chunk.is_empty() {
                self.push(chunk, run.style, run.tag);
            }
        }
    }
}

/// `word` (a formula, with what sticks to it) cut at its glued spaces
/// ([`crate::text::math_breaks`]) so that its pieces fit in `room`
/// columns, breaking where mathematics breaks: at every top-level
/// operator first, then, only inside a piece still too wide, between
/// top-level factors, and only inside such a piece again, inside brackets,
/// outermost first (so `tan δ = 2ζω₀ω/(ω₀² − ω²)` after a wide `A(ω) = …`
/// keeps its bracket whole, and `√((ω₀² − ω²)² + (2ζω₀ω)²)` breaks at its
/// `+`). `None` when it has no glued space. A piece no break
/// can make fit is left for the caller to break.
fn split_formula(word: &Word, room: usize) -> Option<Vec<Word>> {
    // (run, byte offset of the space, rank), in order.
    let mut spaces = Vec::new();
    for (i, run) in word.iter().enumerate() {
        if run.glue {
            spaces.extend(
                crate::text::math_breaks(&run.text)
                    .into_iter()
                    .map(|(at, rank)| (i, at, rank)),
            );
        }
    }
    if spaces.is_empty() {
        return None;
    }
    // The columns between two positions (run, byte), the space at `from`
    // excluded.
    let columns = |from: (usize, usize), to: (usize, usize)| -> usize {
        let mut w = 0;
        for (i, run) in word.iter().enumerate() {
            if i < from.0 || i > to.0 {
                continue;
            }
            let a = if i == from.0 { from.1 } else { 0 };
            let b = if i == to.0 { to.1 } else { run.text.len() };
            if a < b {
                w += width(&run.text[a..b]);
            }
        }
        w
    };
    let start = (0, 0);
    let end = (
        word.len().saturating_sub(1),
        word.last().map_or(0, |r| r.text.len()),
    );
    // The chosen cuts, refined rank by rank inside the pieces too wide.
    let mut chosen: Vec<(usize, usize)> = Vec::new();
    let deepest = spaces.iter().map(|s| s.2).max().unwrap_or(0);
    for rank in 0..=deepest {
        let mut bounds = vec![start];
        bounds.extend(chosen.iter().map(|&(i, at)| (i, at + 1)));
        let mut ends: Vec<(usize, usize)> = chosen.clone();
        ends.push(end);
        let mut more = Vec::new();
        for (&from, &to) in bounds.iter().zip(ends.iter()) {
            if columns(from, to) <= room {
                continue;
            }
            more.extend(
                spaces
                    .iter()
                    .filter(|s| s.2 == rank && (s.0, s.1) > from && (s.0, s.1) < to)
                    .map(|s| (s.0, s.1)),
            );
        }
        chosen.extend(more);
        chosen.sort_unstable();
        chosen.dedup();
    }
    if chosen.is_empty() {
        return None;
    }
    let mut pieces: Vec<Word> = vec![Vec::new()];
    for (i, run) in word.iter().enumerate() {
        let mut from = 0;
        for &(_, at) in chosen.iter().filter(|c| c.0 == i) {
            if at > from {
                pieces.last_mut()?.push(Run {
                    text: run.text[from..at].to_string(),
                    ..run.clone()
                });
            }
            pieces.push(Vec::new());
            from = at + 1;
        }
        if from < run.text.len() {
            pieces.last_mut()?.push(Run {
                text: run.text[from..].to_string(),
                ..run.clone()
            });
        }
    }
    pieces.retain(|p| !p.is_empty());
    Some(pieces)
}

/// The runs of `text` with its formulas rendered and glued (their spaces
/// break a line only when the formula is longer than a line, and then where
/// mathematics breaks), all in `style`.
pub fn math_runs(text: &str, style: Style) -> Vec<Run> {
    crate::text::render_pieces(text)
        .into_iter()
        .map(|(piece, math)| {
            let run = Run::new(piece, style);
            if math { run.glued() } else { run }
        })
        .collect()
}

/// Wraps `runs` to `width` columns. The first line starts with
/// `first_prefix`, the others with `rest_prefix` (a hanging indent for list
/// items). `\n` in the text forces a line break. Always returns at least one
/// line.
pub fn wrap(runs: &[Run], width: usize, first_prefix: Run, rest_prefix: Run) -> Vec<Line<'static>> {
    wrap_tagged(runs, width, first_prefix, rest_prefix).0
}

/// [`wrap`], also returning on which lines each tagged run landed, as
/// (tag, line) pairs in order.
pub fn wrap_tagged(
    runs: &[Run],
    width: usize,
    first_prefix: Run,
    rest_prefix: Run,
) -> (Vec<Line<'static>>, Vec<(usize, usize)>) {
    let mut b = Builder {
        width: width.max(1),
        first_prefix,
        rest_prefix,
        lines: Vec::new(),
        current: Vec::new(),
        used: 0,
        pending_space: None,
        tags: Vec::new(),
    };
    b.start_line();
    for token in tokens(runs) {
        match token {
            Token::Word(word) => b.word(word),
            Token::Space(style) => {
                if !b.at_line_start() {
                    b.pending_space = Some(style);
                }
            }
            Token::Break => b.end_line(),
        }
    }
    if !b.current.is_empty() || b.lines.is_empty() {
        let spans = std::mem::take(&mut b.current);
        b.lines.push(Line::from(spans));
    }
    (b.lines, b.tags)
}

/// `text` cut to `width` columns, ending with "…" when cut.
pub fn ellipsize(text: &str, width: usize) -> String {
    if self::width(text) <= width {
        return text.to_string();
    }
    let mut out = String::new();
    let mut used = 0;
    for c in text.chars() {
        let w = c.width().unwrap_or(0);
        if used + w + 1 > width {
            break;
        }
        used += w;
        out.push(c);
    }
    if width > 0 {
        out.push('…');
    }
    out
}

/// Groups of spans (a key and what it does) laid out in lines of `width`:
/// a group never splits, groups are `gap` columns apart, each line starts
/// with one space.
pub fn pack(groups: Vec<Vec<Span<'static>>>, width: usize, gap: usize) -> Vec<Line<'static>> {
    let group_w = |g: &[Span]| g.iter().map(|s| columns(&s.content)).sum::<usize>();
    let mut lines: Vec<Vec<Span<'static>>> = vec![vec![Span::raw(" ")]];
    let mut used = 1;
    for g in groups {
        let w = group_w(&g);
        if used > 1 && used + gap + w > width {
            lines.push(vec![Span::raw(" ")]);
            used = 1;
        } else if used > 1 {
            if let Some(l) = lines.last_mut() {
                l.push(Span::raw(" ".repeat(gap)));
            }
            used += gap;
        }
        used += w;
        if let Some(l) = lines.last_mut() {
            l.extend(g);
        }
    }
    lines.into_iter().map(Line::from).collect()
}

/// Display width of `text` in columns.
pub fn columns(text: &str) -> usize {
    width(text)
}

/// Wraps plain text in one style.
pub fn wrap_plain(text: &str, style: Style, width: usize) -> Vec<Line<'static>> {
    wrap(
        &[Run::new(text, style)],
        width,
        Run::new("", style),
        Run::new("", style),
    )
}

/// The text of a line without styles.
pub fn line_text(line: &Line<'_>) -> String {
    line.spans.iter().map(|s| s.content.as_ref()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(lines: &[Line<'_>]) -> Vec<String> {
        lines.iter().map(line_text).collect()
    }

    #[test]
    fn wraps_at_word_boundaries() {
        let lines = wrap_plain("the quick brown fox jumps over", Style::new(), 10);
        assert_eq!(texts(&lines), ["the quick", "brown fox", "jumps over"]);
    }

    #[test]
    fn breaks_words_longer_than_the_width() {
        let lines = wrap_plain("abcdefghij xy", Style::new(), 4);
        assert_eq!(texts(&lines), ["abcd", "efgh", "ij", "xy"]);
    }

    #[test]
    fn keeps_a_styled_word_with_its_punctuation() {
        let bold = Style::new().add_modifier(ratatui::style::Modifier::BOLD);
        let runs = [
            Run::new("see ", Style::new()),
            Run::new("ω₂", bold),
            Run::new(", then", Style::new()),
        ];
        let lines = wrap(
            &runs,
            6,
            Run::new("", Style::new()),
            Run::new("", Style::new()),
        );
        assert_eq!(texts(&lines), ["see", "ω₂,", "then"]);
    }

    #[test]
    fn hanging_indent_for_items() {
        let lines = wrap(
            &[Run::new("one two three four", Style::new())],
            9,
            Run::new("• ", Style::new()),
            Run::new("  ", Style::new()),
        );
        assert_eq!(texts(&lines), ["• one two", "  three", "  four"]);
    }

    #[test]
    fn combining_marks_do_not_count_and_stay_attached() {
        // ω̇ is ω followed by U+0307 (combining dot above): one column.
        let lines = wrap_plain("ω\u{307}ω\u{307}ω\u{307}", Style::new(), 2);
        assert_eq!(texts(&lines), ["ω\u{307}ω\u{307}", "ω\u{307}"]);
    }

    #[test]
    fn explicit_newlines_break_lines_and_empty_text_gives_one_line() {
        assert_eq!(texts(&wrap_plain("a\nb", Style::new(), 10)), ["a", "b"]);
        assert_eq!(texts(&wrap_plain("", Style::new(), 10)), [""]);
    }

    #[test]
    fn glued_runs_keep_their_spaces_and_tags_find_lines() {
        let runs = [
            Run::new("so that ", Style::new()),
            Run::new("I₁ < I₂ < I₃", Style::new())
                .glued()
                .tagged(Some(7)),
            Run::new(" holds", Style::new()),
        ];
        let (lines, tags) = wrap_tagged(
            &runs,
            14,
            Run::new("", Style::new()),
            Run::new("", Style::new()),
        );
        assert_eq!(texts(&lines), ["so that", "I₁ < I₂ < I₃", "holds"]);
        assert_eq!(tags, [(7, 1)]);
    }

    #[test]
    fn a_space_after_a_styled_word_keeps_the_plain_style() {
        let link = Style::new().add_modifier(ratatui::style::Modifier::REVERSED);
        let runs = [
            Run::new("a link", link),
            Run::new(" and more", Style::new()),
        ];
        let lines = wrap(
            &runs,
            40,
            Run::new("", Style::new()),
            Run::new("", Style::new()),
        );
        let styled: Vec<(&str, Style)> = lines[0]
            .spans
            .iter()
            .map(|s| (s.content.as_ref(), s.style))
            .collect();
        assert_eq!(
            styled,
            [
                ("a", link),
                (" ", link),
                ("link", link),
                (" ", Style::new()),
                ("and", Style::new()),
                (" ", Style::new()),
                ("more", Style::new()),
            ]
        );
    }

    #[test]
    fn ellipsize_marks_the_cut() {
        assert_eq!(ellipsize("Concept map", 20), "Concept map");
        assert_eq!(ellipsize("Concept map", 8), "Concept…");
        assert_eq!(columns(&ellipsize("ωωωωω", 3)), 3);
    }

    #[test]
    fn zero_width_does_not_hang() {
        let lines = wrap_plain("abc", Style::new(), 0);
        assert!(!lines.is_empty());
    }
}
