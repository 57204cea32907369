//! The one way a test runs the flipcard binary: [`Flipcard`], a command
//! builder that sets every environment variable the app reads in one
//! place, so that no test inherits a clock, a time zone, a deck folder or
//! a config from the shell that runs `cargo test`, and no test file needs
//! a helper of its own to say so.
//!
//! What the app reads from its environment, and what a run gets unless the
//! test says otherwise:
//!
//! | variable | read by | default here |
//! |---|---|---|
//! | `FLIPCARD_DATA_DIR` | `cmd/args.rs` | the data dir given to [`Flipcard::new`]; unset for [`Flipcard::without_data`] |
//! | `FLIPCARD_CONFIG` | `cmd/args.rs` | `no-config.toml` in the data dir (a file that is not there: the defaults) |
//! | `FLIPCARD_DECKS` | `cmd/args.rs` | unset: the bundled decks only ([`Flipcard::decks`] adds a folder) |
//! | `FLIPCARD_NOW` | `cmd/clock.rs` | unset: the real clock ([`Flipcard::now`] fixes it) |
//! | `TZ` | `chrono::Local` (the study day) | `UTC` ([`Flipcard::tz`]) |
//! | `NO_COLOR` | `tui/theme.rs` | unset |
//! | `FLIPCARD_TEST_LIBRARY_KILL` | `cmd/library.rs` (a test hook) | unset |
//! | `HOME` | `~` in config paths, the platform's folders | inherited |
//!
//! A run's standard input is empty unless [`Flipcard::stdin`] gives it
//! bytes. [`Flipcard::run`] returns an [`Output`] (the process's output,
//! with its text and assertions); [`Flipcard::command`] gives the
//! [`Command`] itself to a test that spawns and kills it; [`Flipcard::shell`]
//! gives the same run as one `sh` line for a test that drives a terminal
//! (tmux).

use std::collections::BTreeMap;
use std::ffi::{OsStr, OsString};
use std::io::Write as _;
use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Every variable the app reads (see the module's table); each one is set
/// or removed on every run.
const READ_BY_THE_APP: [&str; 7] = [
    "FLIPCARD_DATA_DIR",
    "FLIPCARD_CONFIG",
    "FLIPCARD_DECKS",
    "FLIPCARD_NOW",
    "TZ",
    "NO_COLOR",
    "FLIPCARD_TEST_LIBRARY_KILL",
];

/// One run of the flipcard binary being built; see the module comment.
#[must_use = "a Flipcard does nothing until it is run"]
pub struct Flipcard {
    program: PathBuf,
    /// A program (and its arguments) that runs flipcard: `setpriv …`,
    /// `sh -c 'ulimit …; exec "$0" "$@"'`.
    prefix: Vec<OsString>,
    args: Vec<OsString>,
    /// `None` removes the variable.
    vars: BTreeMap<OsString, Option<OsString>>,
    dir: Option<PathBuf>,
    stdin: Option<Vec<u8>>,
    stdout: Option<Stdio>,
    stderr: Option<Stdio>,
}

impl Flipcard {
    /// flipcard with its data (and the config it looks for) in `data`.
    pub fn new(data: impl AsRef<Path>) -> Flipcard {
        let data = data.as_ref();
        Flipcard::without_data()
            .env("FLIPCARD_DATA_DIR", data)
            .config(data.join("no-config.toml"))
    }

    /// flipcard for a command that keeps no data (`check`, `sim`,
    /// `schema`, `bench`): no data dir is named, and the config is a file
    /// that is not there.
    pub fn without_data() -> Flipcard {
        let mut vars: BTreeMap<OsString, Option<OsString>> = READ_BY_THE_APP
            .iter()
            .map(|k| (OsString::from(k), None))
            .collect();
        vars.insert("TZ".into(), Some("UTC".into()));
        vars.insert(
            "FLIPCARD_CONFIG".into(),
            Some(
                Path::new(env!("CARGO_TARGET_TMPDIR"))
                    .join("no-config.toml")
                    .into(),
            ),
        );
        Flipcard {
            program: test_binary().to_path_buf(),
            prefix: Vec::new(),
            args: Vec::new(),
            vars,
            dir: None,
            stdin: None,
            stdout: None,
            stderr: None,
        }
    }

    /// The release build instead of the test profile's (see
    /// [`release_binary`]).
    pub fn release(self) -> Flipcard {
        self.program(release_binary())
    }

    /// Another flipcard binary (a copy of it, say).
    pub fn program(mut self, path: impl AsRef<Path>) -> Flipcard {
        self.program = path.as_ref().to_path_buf();
        self
    }

    /// Run flipcard through `prefix`: the first word is the program, the
    /// rest its arguments, then flipcard's path and arguments follow.
    pub fn prefix<I, S>(mut self, prefix: I) -> Flipcard
    where
        I: IntoIterator<Item = S>,
        S: AsRef<OsStr>,
    {
        self.prefix = prefix.into_iter().map(|s| s.as_ref().into()).collect();
        self
    }

    /// The clock (`FLIPCARD_NOW`, RFC 3339).
    pub fn now(self, rfc3339: &str) -> Flipcard {
        self.env("FLIPCARD_NOW", rfc3339)
    }

    /// The time zone (`TZ`: `UTC`, `Asia/Kolkata`).
    pub fn tz(self, zone: &str) -> Flipcard {
        self.env("TZ", zone)
    }

    /// The config file (`FLIPCARD_CONFIG`).
    pub fn config(self, path: impl AsRef<Path>) -> Flipcard {
        self.env("FLIPCARD_CONFIG", path.as_ref())
    }

    /// A deck folder opened beside the bundled decks (`FLIPCARD_DECKS`).
    pub fn decks(self, dir: impl AsRef<Path>) -> Flipcard {
        self.env("FLIPCARD_DECKS", dir.as_ref())
    }

    /// Sets any variable (a later call wins).
    pub fn env(mut self, key: impl AsRef<OsStr>, value: impl AsRef<OsStr>) -> Flipcard {
        self.vars
            .insert(key.as_ref().into(), Some(value.as_ref().into()));
        self
    }

    /// Removes a variable from the run's environment.
    pub fn env_remove(mut self, key: impl AsRef<OsStr>) -> Flipcard {
        self.vars.insert(key.as_ref().into(), None);
        self
    }

    /// The working directory.
    pub fn current_dir(mut self, dir: impl AsRef<Path>) -> Flipcard {
        self.dir = Some(dir.as_ref().to_path_buf());
        self
    }

    pub fn arg(mut self, arg: impl AsRef<OsStr>) -> Flipcard {
        self.args.push(arg.as_ref().into());
        self
    }

    pub fn args<I, S>(mut self, args: I) -> Flipcard
    where
        I: IntoIterator<Item = S>,
        S: AsRef<OsStr>,
    {
        self.args
            .extend(args.into_iter().map(|s| s.as_ref().to_os_string()));
        self
    }

    /// Bytes on standard input (empty otherwise).
    pub fn stdin(mut self, bytes: impl Into<Vec<u8>>) -> Flipcard {
        self.stdin = Some(bytes.into());
        self
    }

    /// Where standard output goes instead of being captured (a closed pipe,
    /// `/dev/full`); [`Output::stdout`] is then empty.
    pub fn stdout(mut self, to: Stdio) -> Flipcard {
        self.stdout = Some(to);
        self
    }

    /// Where standard error goes instead of being captured;
    /// [`Output::stderr`] is then empty.
    pub fn stderr(mut self, to: Stdio) -> Flipcard {
        self.stderr = Some(to);
        self
    }

    /// `flipcard ARGS`, for messages.
    fn describe(&self) -> String {
        let mut words = vec!["flipcard".to_string()];
        words.extend(self.args.iter().map(|a| a.to_string_lossy().into_owned()));
        words.join(" ")
    }

    /// The command, ready to spawn: its standard input is empty and its
    /// output inherited unless the test sets them.
    pub fn command(self) -> Command {
        let (command, _) = self.build();
        command
    }

    fn build(self) -> (Command, Option<Vec<u8>>) {
        let mut c = match self.prefix.split_first() {
            Some((program, rest)) => {
                let mut c = Command::new(program);
                c.args(rest).arg(&self.program);
                c
            }
            None => Command::new(&self.program),
        };
        c.args(&self.args);
        for (k, v) in &self.vars {
            match v {
                Some(v) => c.env(k, v),
                None => c.env_remove(k),
            };
        }
        if let Some(dir) = &self.dir {
            c.current_dir(dir);
        }
        c.stdin(if self.stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        });
        // Unset, they are captured by `run` and inherited by `command`.
        if let Some(to) = self.stdout {
            c.stdout(to);
        }
        if let Some(to) = self.stderr {
            c.stderr(to);
        }
        (c, self.stdin)
    }

    /// Runs to the end and returns what it wrote and how it exited.
    pub fn run(self) -> Output {
        let what = self.describe();
        let captured = (self.stdout.is_none(), self.stderr.is_none());
        let (mut command, stdin) = self.build();
        let out = match stdin {
            // `output` captures what the test did not send elsewhere.
            None => command.output(),
            Some(bytes) => {
                if captured.0 {
                    command.stdout(Stdio::piped());
                }
                if captured.1 {
                    command.stderr(Stdio::piped());
                }
                command.spawn().and_then(|mut child| {
                    let mut pipe = child.stdin.take().expect("stdin piped");
                    // A command that stops reading early is not an error here.
                    let _ = pipe.write_all(&bytes);
                    drop(pipe);
                    child.wait_with_output()
                })
            }
        };
        Output {
            out: out.unwrap_or_else(|e| panic!("cannot run {what}: {e}")),
            what,
        }
    }

    /// [`Flipcard::run`], or a panic once it has run `seconds` (the process
    /// is killed first): a command that hangs is a failing test, not a
    /// test run that never ends. The bounds are generous (many times what
    /// the command takes); timing targets live in benchmarks.
    pub fn run_within(self, seconds: u64) -> Output {
        let what = self.describe();
        assert!(
            self.stdin.is_none() && self.stdout.is_none() && self.stderr.is_none(),
            "run_within gives no input and captures the output"
        );
        let mut child = self
            .command()
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot run {what}: {e}"));
        // Read the pipes while waiting: a full pipe would stall the child.
        let mut out = child.stdout.take().expect("stdout piped");
        let mut err = child.stderr.take().expect("stderr piped");
        let read_out = std::thread::spawn(move || {
            let mut v = Vec::new();
            std::io::Read::read_to_end(&mut out, &mut v).map(|_| v)
        });
        let read_err = std::thread::spawn(move || {
            let mut v = Vec::new();
            std::io::Read::read_to_end(&mut err, &mut v).map(|_| v)
        });
        let start = Instant::now();
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            if start.elapsed() > Duration::from_secs(seconds) {
                let _ = child.kill();
                let _ = child.wait();
                panic!("`{what}` took over {seconds} s");
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        Output {
            out: std::process::Output {
                status,
                stdout: read_out.join().unwrap().unwrap(),
                stderr: read_err.join().unwrap().unwrap(),
            },
            what,
        }
    }

    /// The same run as one line of `sh` (variables removed with `unset`,
    /// set for the one command, every word quoted), for a test that starts
    /// flipcard in a terminal.
    pub fn shell(&self) -> String {
        let removed: Vec<String> = self
            .vars
            .iter()
            .filter(|(_, v)| v.is_none())
            .map(|(k, _)| k.to_string_lossy().into_owned())
            .collect();
        let mut line = String::new();
        if let Some(dir) = &self.dir {
            line.push_str(&format!("cd {} && ", quote(dir.as_os_str())));
        }
        if !removed.is_empty() {
            line.push_str(&format!("unset {}; ", removed.join(" ")));
        }
        for (k, v) in &self.vars {
            if let Some(v) = v {
                line.push_str(&format!("{}={} ", k.to_string_lossy(), quote(v)));
            }
        }
        let words: Vec<String> = self
            .prefix
            .iter()
            .map(|w| quote(w))
            .chain([quote(self.program.as_os_str())])
            .chain(self.args.iter().map(|a| quote(a)))
            .collect();
        line.push_str(&words.join(" "));
        line
    }
}

/// `word` in single quotes for `sh`.
fn quote(word: &OsStr) -> String {
    format!("'{}'", word.to_string_lossy().replace('\'', "'\\''"))
}

/// The binary cargo built for these tests (the test profile's).
pub fn test_binary() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_flipcard"))
}

/// The release binary, built once per test run. Cargo locks each profile's
/// output directory separately, so building the release profile from
/// inside `cargo test` (which holds the test profile's lock) cannot
/// deadlock.
pub fn release_binary() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        let manifest = env!("CARGO_MANIFEST_DIR");
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = Command::new(cargo)
            .args(["build", "--release", "--quiet", "--bin", "flipcard"])
            .current_dir(manifest)
            .status();
        match status {
            Ok(s) if s.success() => {}
            other => panic!("cargo build --release failed: {other:?}"),
        }
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| Path::new(manifest).join("target"));
        target.join("release").join("flipcard")
    })
}

/// What a run wrote and how it ended. It derefs to the process's
/// [`std::process::Output`] (`status`, `stdout`, `stderr` as bytes).
pub struct Output {
    out: std::process::Output,
    /// `flipcard ARGS`, for messages.
    what: String,
}

impl Deref for Output {
    type Target = std::process::Output;

    fn deref(&self) -> &std::process::Output {
        &self.out
    }
}

impl Output {
    /// Standard output as text (invalid UTF-8 replaced).
    pub fn stdout(&self) -> String {
        String::from_utf8_lossy(&self.out.stdout).into_owned()
    }

    /// Standard error as text (invalid UTF-8 replaced).
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.out.stderr).into_owned()
    }

    /// The exit code (`None` when a signal ended the process).
    pub fn code(&self) -> Option<i32> {
        self.out.status.code()
    }

    /// Asserts that the run succeeded (its stderr in the message).
    #[track_caller]
    pub fn ok(self) -> Output {
        assert!(
            self.out.status.success(),
            "`{}` failed ({}): {}",
            self.what,
            self.out.status,
            self.stderr()
        );
        self
    }

    /// Asserts that the run failed as the app fails: exit status 1.
    #[track_caller]
    pub fn fails(self) -> Output {
        assert_eq!(
            self.code(),
            Some(1),
            "`{}` should exit 1: {}{}",
            self.what,
            self.stdout(),
            self.stderr()
        );
        self
    }

    /// The process's output itself.
    pub fn into_inner(self) -> std::process::Output {
        self.out
    }
}
