//! Collecting the diagnostics of one file while it is read and checked.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::diag::{Diagnostic, LineIndex, Severity};

/// The diagnostics of one source file, positioned by byte span.
#[derive(Debug)]
pub struct FileReport<'s> {
    pub path: PathBuf,
    pub source: &'s str,
    index: LineIndex,
    /// Each diagnostic with the byte offset it points at, for ordering.
    found: Vec<(usize, Diagnostic)>,
}

impl<'s> FileReport<'s> {
    pub fn new(path: &Path, source: &'s str) -> FileReport<'s> {
        FileReport {
            path: path.to_path_buf(),
            source,
            index: LineIndex::new(source),
            found: Vec::new(),
        }
    }

    pub fn error(&mut self, span: Range<usize>, message: impl Into<String>, hint: Option<String>) {
        self.push(Severity::Error, span, message.into(), hint);
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
        let (line, col) = self.index.position(self.source, span.start);
        let width = self.index.width(self.source, &span);
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
        self.index.position(self.source, offset).0
    }

    pub fn has_errors(&self) -> bool {
        self.found.iter().any(|(_, d)| d.is_error())
    }

    /// The diagnostics in file order (same position: in the order found).
    pub fn finish(mut self) -> Vec<Diagnostic> {
        self.found.sort_by_key(|(at, _)| *at);
        self.found.into_iter().map(|(_, d)| d).collect()
    }
}
