//! Collecting the diagnostics of one file while it is read and checked.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::diag::{Diagnostic, LineIndex, Severity};

/// The diagnostics of one source file, positioned by byte span.
#[derive(Debug)]
pub struct FileReport<'s> {
    pub path: PathBuf,
    pub source: &'s str,
    /// The file's line starts, found when the first diagnostic needs them
    /// (a clean 14 MB deck never does).
    index: std::cell::OnceCell<LineIndex>,
    /// Each diagnostic with the byte offset it points at, for ordering.
    found: Vec<(usize, Diagnostic)>,
    /// Errors with one cause met again: the first's index in `found`, and
    /// the lines of the others.
    repeats: HashMap<String, (usize, Vec<usize>)>,
}

impl<'s> FileReport<'s> {
    pub fn new(path: &Path, source: &'s str) -> FileReport<'s> {
        FileReport {
            path: path.to_path_buf(),
            source,
            index: std::cell::OnceCell::new(),
            found: Vec::new(),
            repeats: HashMap::new(),
        }
    }

    fn index(&self) -> &LineIndex {
        self.index.get_or_init(|| LineIndex::new(self.source))
    }

    pub fn error(&mut self, span: Range<usize>, message: impl Into<String>, hint: Option<String>) {
        self.push(Severity::Error, span, message.into(), hint);
    }

    /// An error that may come up again with the same `cause` (a link to a
    /// section that does not exist, from every card that explains with
    /// it): reported once, at the first place, with the others' lines.
    pub(crate) fn error_once(
        &mut self,
        cause: String,
        span: Range<usize>,
        message: impl Into<String>,
        hint: Option<String>,
    ) {
        if self.repeats.contains_key(&cause) {
            let line = self.index().position(self.source, span.start).0;
            if let Some((_, lines)) = self.repeats.get_mut(&cause) {
                lines.push(line);
            }
            return;
        }
        self.repeats.insert(cause, (self.found.len(), Vec::new()));
        self.error(span, message, hint);
    }

    pub fn warning(
        &mut self,
        span: Range<usize>,
        message: impl Into<String>,
        hint: Option<String>,
    ) {
        self.push(Severity::Warning, span, message.into(), hint);
    }

    pub fn push(
        &mut self,
        severity: Severity,
        span: Range<usize>,
        message: String,
        hint: Option<String>,
    ) {
        let (line, col) = self.index().position(self.source, span.start);
        let width = self.index().width(self.source, &span);
        self.found.push((
            span.start,
            Diagnostic {
                path: self.path.clone(),
                line,
                col,
                severity,
                message,
                hint,
                width,
            },
        ));
    }

    /// 1-based line of byte `offset`, for "first defined at line N".
    pub fn line_of(&self, offset: usize) -> usize {
        self.index().position(self.source, offset).0
    }

    /// Nothing found yet, not even a warning.
    pub(crate) fn is_empty(&self) -> bool {
        self.found.is_empty()
    }

    pub(crate) fn has_errors(&self) -> bool {
        self.found.iter().any(|(_, d)| d.is_error())
    }

    /// The diagnostics in file order (same position: in the order found).
    pub fn finish(mut self) -> Vec<Diagnostic> {
        for (first, lines) in self.repeats.values_mut() {
            // Found in checking order (a section's `see`, then its body's
            // links): listed in file order.
            lines.sort_unstable();
            lines.dedup();
            if !lines.is_empty() {
                self.found[*first].1.message += &format!(" (also at {})", at_lines(lines));
            }
        }
        self.found.sort_by_key(|(at, _)| *at);
        self.found.into_iter().map(|(_, d)| d).collect()
    }
}

/// Lines listed before "and N more".
const LINES_LISTED: usize = 3;

/// "line 7", "lines 7 and 9", "lines 7, 9, 12 and 4 more".
pub(crate) fn at_lines(lines: &[usize]) -> String {
    let shown: Vec<String> = lines
        .iter()
        .take(LINES_LISTED)
        .map(usize::to_string)
        .collect();
    let rest = lines.len().saturating_sub(LINES_LISTED);
    match shown.split_last() {
        Some((only, [])) if rest == 0 => format!("line {only}"),
        Some((last, init)) if rest == 0 => format!("lines {} and {last}", init.join(", ")),
        _ => format!("lines {} and {rest} more", shown.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_cause_met_again_is_one_error_listing_the_other_lines() {
        let src = "a\nb\nc\nd\ne\nf\n";
        let mut rep = FileReport::new(Path::new("x.toml"), src);
        for (i, line) in src.lines().enumerate() {
            rep.error_once(
                "x".into(),
                i * 2..i * 2 + 1,
                format!("{line} is wrong"),
                None,
            );
        }
        rep.error_once("y".into(), 2..3, "b alone", None);
        let found: Vec<String> = rep
            .finish()
            .iter()
            .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
            .collect();
        assert_eq!(
            found,
            [
                "1:1: a is wrong (also at lines 2, 3, 4 and 2 more)",
                "2:1: b alone"
            ]
        );
        assert_eq!(at_lines(&[4]), "line 4");
        assert_eq!(at_lines(&[4, 9]), "lines 4 and 9");
        assert_eq!(at_lines(&[4, 9, 12]), "lines 4, 9 and 12");
    }
}
