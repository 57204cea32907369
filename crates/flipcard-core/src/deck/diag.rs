//! Diagnostics: a problem at a file position, and how it is shown.
//!
//! Shown as `path:line:col: error: message`, the source line with a caret
//! under the column, then an optional `  = help: ...` line. Columns count
//! characters (1-based), not bytes, so they match what an editor shows. A
//! problem with the file as a whole (it is a FIFO, a dangling link, cannot
//! be read) has no position and is shown as `path: error: message`.

use std::fmt::Write as _;
use std::ops::Range;
use std::path::PathBuf;

use unicode_width::UnicodeWidthChar;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    Error,
    Warning,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    pub path: PathBuf,
    /// 1-based line; 0 for a problem with the file as a whole.
    pub line: usize,
    /// 1-based column, in characters; 0 with line 0.
    pub col: usize,
    pub severity: Severity,
    pub message: String,
    pub hint: Option<String>,
    /// Characters to underline from `col` on the same line (at least 1).
    pub width: usize,
}

/// The widest stretch of a source line shown; longer lines are cut around
/// the caret so a 10 MB line does not flood the terminal.
const SHOWN_CHARS: usize = 150;

impl Diagnostic {
    /// An error about the file as a whole, which has no line to point at.
    pub(crate) fn whole_file(path: PathBuf, message: String, hint: Option<String>) -> Diagnostic {
        Diagnostic {
            path,
            line: 0,
            col: 0,
            severity: Severity::Error,
            message,
            hint,
            width: 0,
        }
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// Whether the diagnostic points into the file (see [`Diagnostic::whole_file`]).
    pub(crate) fn has_position(&self) -> bool {
        self.line > 0
    }

    /// The one-line head: `path:line:col: error: message`, or
    /// `path: error: message` for the file as a whole.
    pub fn headline(&self) -> String {
        if !self.has_position() {
            return format!(
                "{}: {}: {}",
                self.path.display(),
                self.severity.as_str(),
                self.message
            );
        }
        format!(
            "{}:{}:{}: {}: {}",
            self.path.display(),
            self.line,
            self.col,
            self.severity.as_str(),
            self.message
        )
    }

    /// The full report: headline, source line with caret, help line.
    /// `source` is the whole text of `self.path`.
    pub fn render(&self, source: &str) -> String {
        self.render_line(source.lines().nth(self.line.saturating_sub(1)))
    }

    /// [`Diagnostic::render`] given the text of `self.line` only (`None`:
    /// headline and help alone, e.g. when the file could not be read).
    pub(crate) fn render_line(&self, line_text: Option<&str>) -> String {
        let mut out = self.headline();
        out.push('\n');
        if let Some(text) = line_text.filter(|_| self.has_position()) {
            let (shown, caret_pad, caret_len) = excerpt(text, self.col, self.width);
            let gutter = self.line.to_string();
            let blank = " ".repeat(gutter.len());
            let _ = writeln!(out, " {gutter} | {shown}");
            let _ = writeln!(
                out,
                " {blank} | {}{}",
                " ".repeat(caret_pad),
                "^".repeat(caret_len.max(1))
            );
        }
        if let Some(hint) = &self.hint {
            let _ = writeln!(out, "  = help: {hint}");
        }
        out
    }
}

/// The part of `line` to show, the display width before the caret, and the
/// caret's display width. Control characters are shown as spaces (they would
/// move the cursor) and wide characters are measured so the caret lines up.
fn excerpt(line: &str, col: usize, width: usize) -> (String, usize, usize) {
    let chars: Vec<char> = line.chars().collect();
    let col0 = col.saturating_sub(1).min(chars.len());
    let start = col0
        .saturating_sub(SHOWN_CHARS / 2)
        .min(chars.len().saturating_sub(SHOWN_CHARS));
    let end = (start + SHOWN_CHARS).min(chars.len());
    let shown_char = |c: char| if c.is_control() { ' ' } else { c };
    let cell = |c: char| shown_char(c).width().unwrap_or(0);
    let mut shown = String::new();
    let mut pad = 0;
    if start > 0 {
        shown.push('…');
        pad += 1;
    }
    for &c in &chars[start..end] {
        shown.push(shown_char(c));
    }
    if end < chars.len() {
        shown.push('…');
    }
    pad += chars[start..col0].iter().map(|&c| cell(c)).sum::<usize>();
    let caret_end = (col0 + width.max(1)).min(end);
    let caret = chars[col0.min(caret_end)..caret_end]
        .iter()
        .map(|&c| cell(c).max(1))
        .sum::<usize>();
    (shown, pad, caret.max(1))
}

/// Byte offsets → (line, column) for one source text.
#[derive(Debug, Clone)]
pub(crate) struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    pub fn new(source: &str) -> LineIndex {
        let mut starts = vec![0];
        starts.extend(
            source
                .bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        LineIndex { starts }
    }

    /// 1-based line and character column of byte `offset` (clamped to the
    /// text, and moved back to a character boundary if inside one).
    pub fn position(&self, source: &str, offset: usize) -> (usize, usize) {
        let mut offset = offset.min(source.len());
        while !source.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.starts.partition_point(|&s| s <= offset).max(1);
        let start = self.starts[line - 1];
        let col = source[start..offset].chars().count() + 1;
        (line, col)
    }

    /// The text of 1-based line `n`, without its line break.
    pub fn line<'s>(&self, source: &'s str, n: usize) -> Option<&'s str> {
        let start = *self.starts.get(n.checked_sub(1)?)?;
        let end = self.starts.get(n).map_or(source.len(), |&e| e - 1);
        let text = source.get(start..end.max(start))?;
        Some(text.strip_suffix('\r').unwrap_or(text))
    }

    /// Characters of `span` on its first line (at least 1), for the caret.
    pub fn width(&self, source: &str, span: &Range<usize>) -> usize {
        let end = span.end.min(source.len());
        let start = span.start.min(end);
        source
            .get(start..end)
            .map(|s| s.split('\n').next().unwrap_or("").chars().count())
            .unwrap_or(0)
            .max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diag(line: usize, col: usize, width: usize) -> Diagnostic {
        Diagnostic {
            path: PathBuf::from("decks/x.toml"),
            line,
            col,
            severity: Severity::Error,
            message: "unknown field `fornt`".into(),
            hint: Some("did you mean `front`?".into()),
            width,
        }
    }

    #[test]
    fn positions_count_characters_from_one() {
        let src = "a = 1\nθω = 'x'\n";
        let idx = LineIndex::new(src);
        assert_eq!(idx.position(src, 0), (1, 1));
        assert_eq!(idx.position(src, 4), (1, 5));
        assert_eq!(idx.position(src, 6), (2, 1));
        // `=` after two 2-byte letters and a space: byte 11, character 4.
        assert_eq!(idx.position(src, 11), (2, 4));
        // Inside a character: moved back to its start.
        assert_eq!(idx.position(src, 7), (2, 1));
        // Past the end: clamped.
        assert_eq!(idx.position(src, 999), (3, 1));
    }

    #[test]
    fn lines_by_number() {
        let src = "a\r\nbb\n\nccc";
        let idx = LineIndex::new(src);
        let lines: Vec<_> = (0..=5).map(|n| idx.line(src, n)).collect();
        assert_eq!(
            lines,
            [None, Some("a"), Some("bb"), Some(""), Some("ccc"), None]
        );
    }

    #[test]
    fn render_shows_line_caret_and_help() {
        let src = "[[card]]\nfornt = 'x'\n";
        let out = diag(2, 1, 5).render(src);
        assert_eq!(
            out,
            "decks/x.toml:2:1: error: unknown field `fornt`\n 2 | fornt = 'x'\n   | ^^^^^\n  = help: did you mean `front`?\n"
        );
    }

    #[test]
    fn caret_lines_up_after_wide_and_control_characters() {
        let src = "t = \"\tθ\" # 中文 x";
        let d = Diagnostic {
            col: 16,
            hint: None,
            severity: Severity::Warning,
            ..diag(1, 16, 1)
        };
        let out = d.render(src);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[1], " 1 | t = \" θ\" # 中文 x");
        // 15 characters before the caret, two of them double width.
        assert_eq!(lines[2], format!("   | {}^", " ".repeat(17)));
        assert!(lines[0].contains(": warning: "));
    }

    #[test]
    fn a_whole_file_problem_has_no_position_and_no_source_line() {
        let d = Diagnostic::whole_file(
            PathBuf::from("decks/x.toml"),
            "is a FIFO, not a regular file".into(),
            None,
        );
        assert_eq!(
            d.render("first line\n"),
            "decks/x.toml: error: is a FIFO, not a regular file\n"
        );
    }

    #[test]
    fn long_lines_are_cut_around_the_caret() {
        let src = format!("a = '{}'", "x".repeat(10_000_000));
        let out = diag(1, 5_000_000, 1).render(&src);
        assert!(out.len() < 400, "{} bytes", out.len());
        let lines: Vec<&str> = out.lines().collect();
        assert!(lines[1].contains('…'));
        let caret_at = lines[2].find('^').unwrap();
        // The caret sits under an `x` of the shown part.
        assert_eq!(lines[1].chars().nth(caret_at), Some('x'));
    }
}
