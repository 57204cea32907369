//! The one way the commands print. Standard output is the product a script
//! or pipe consumes, so a failed write is an error the handler propagates
//! with `?`; the failure is also noted here, because by the time it reaches
//! `main` it may be wrapped in a CSV, JSON or store error. `main` then ends
//! quietly when the reader went away (`| head`) and reports any other
//! failure (a full disk) in one line. Standard error is where failures are
//! reported, so a failure to write there has nowhere to go: it is ignored,
//! never a panic as with `eprintln!`.

use std::fmt;
use std::io::{self, BufWriter, Write};
use std::sync::Mutex;

use crate::text::safe::{self, Escaper};

/// The first failed write to standard output: its kind, and its text.
static STDOUT_FAILURE: Mutex<Option<(io::ErrorKind, String)>> = Mutex::new(None);

fn note_stdout_failure(err: &io::Error) {
    // `write_all` retries an interrupted write itself; it is no failure.
    if err.kind() == io::ErrorKind::Interrupted {
        return;
    }
    let mut failure = STDOUT_FAILURE.lock().unwrap_or_else(|e| e.into_inner());
    if failure.is_none() {
        *failure = Some((err.kind(), err.to_string()));
    }
}

/// Standard output, noting its first failure. Every writer to stdout sits
/// on this, so even the flush a `BufWriter` does (and swallows) when
/// dropped is noted. It is the output edge: control characters are escaped
/// here ([`text::safe`](crate::text::safe)), whatever printed them.
pub struct Stdout {
    lock: io::StdoutLock<'static>,
    escaper: Escaper,
}

impl Stdout {
    fn new() -> Stdout {
        Stdout {
            lock: io::stdout().lock(),
            escaper: Escaper::default(),
        }
    }
}

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let escaped = self.escaper.feed(buf);
        self.lock
            .write_all(&escaped)
            .inspect_err(note_stdout_failure)?;
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        let held = self.escaper.finish();
        self.lock
            .write_all(&held)
            .inspect_err(note_stdout_failure)?;
        self.lock.flush().inspect_err(note_stdout_failure)
    }
}

impl Drop for Stdout {
    fn drop(&mut self) {
        let held = self.escaper.finish();
        if !held.is_empty() {
            let _ = self.lock.write_all(&held).inspect_err(note_stdout_failure);
        }
    }
}

/// Buffered standard output for long outputs; flush it before returning.
pub fn stdout() -> BufWriter<Stdout> {
    BufWriter::new(Stdout::new())
}

/// Writes to standard output (see [`out!`](crate::out) and
/// [`outln!`](crate::outln)).
pub fn write_stdout(args: fmt::Arguments) -> io::Result<()> {
    let text = args.to_string();
    Stdout::new().write_all(safe::escape(&text).as_bytes())
}

/// Writes to standard error, best effort (see [`errln!`](crate::errln)),
/// control characters escaped: errors and warnings quote input.
pub fn write_stderr(args: fmt::Arguments) {
    let text = args.to_string();
    let _ = io::stderr()
        .lock()
        .write_all(safe::escape(&text).as_bytes());
}

/// Flushes what the standard library still buffers (a last line without
/// its newline), noting a failure.
pub fn flush_stdout() {
    let _ = Stdout::new().flush();
}

/// How standard output fared.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StdoutStatus {
    Written,
    /// The reader went away: the output was not wanted any further.
    Closed,
    /// Any other failure, with its text (e.g. "No space left on device").
    Failed(String),
}

/// Flushes standard output and says how writing to it went.
pub fn stdout_status() -> StdoutStatus {
    flush_stdout();
    let failure = STDOUT_FAILURE.lock().unwrap_or_else(|e| e.into_inner());
    match &*failure {
        None => StdoutStatus::Written,
        Some((io::ErrorKind::BrokenPipe, _)) => StdoutStatus::Closed,
        Some((_, text)) => StdoutStatus::Failed(text.clone()),
    }
}

/// Like `print!`, but returns the write's `io::Result` instead of panicking.
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cmd::output::write_stdout(format_args!($($arg)*))
    };
}

/// Like `println!`, but returns the write's `io::Result` instead of
/// panicking.
#[macro_export]
macro_rules! outln {
    () => {
        $crate::cmd::output::write_stdout(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cmd::output::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// Like `eprintln!`, but a failed write is ignored instead of panicking.
#[macro_export]
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::cmd::output::write_stderr(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// Writes `error` as one line: each layer of its chain once, dropping a
/// layer whose text an outer one already includes (errors here usually
/// spell out their cause, which is also their source).
pub fn chain_text(error: &anyhow::Error) -> String {
    let mut said: Vec<String> = Vec::new();
    for layer in error.chain() {
        let text = layer.to_string();
        let text = text.trim();
        if text.is_empty() || said.iter().any(|s| s.contains(text)) {
            continue;
        }
        said.push(text.to_string());
    }
    said.join(": ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug)]
    struct Spelled {
        text: &'static str,
        source: Option<Box<Spelled>>,
    }

    impl fmt::Display for Spelled {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str(self.text)
        }
    }

    impl std::error::Error for Spelled {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            self.source.as_deref().map(|s| s as _)
        }
    }

    #[test]
    fn a_cause_an_outer_layer_spells_out_is_said_once() {
        let os = "File exists (os error 17)";
        let inner = Spelled {
            text: os,
            source: None,
        };
        let outer = Spelled {
            text: "cannot use data dir d: File exists (os error 17); pass --data-dir",
            source: Some(Box::new(inner)),
        };
        let err = anyhow::Error::new(outer).context("stats");
        let text = chain_text(&err);
        assert_eq!(text.matches(os).count(), 1, "{text}");
        assert_eq!(
            text,
            "stats: cannot use data dir d: File exists (os error 17); pass --data-dir"
        );
    }

    #[test]
    fn layers_that_add_something_are_all_kept() {
        let err = anyhow::anyhow!("No such file or directory (os error 2)")
            .context("cannot read x.csv")
            .context("import");
        assert_eq!(
            chain_text(&err),
            "import: cannot read x.csv: No such file or directory (os error 2)"
        );
    }
}
