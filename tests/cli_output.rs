//! Every command through the real binary with its output going nowhere: a
//! pipe whose reader has already gone (`| head`) is a normal end, exit
//! status 0 and nothing said; a full device (`> /dev/full`) is one line
//! naming the problem and exit status 1. Neither may ever panic. Also: error
//! chains say their cause once, counts agree with their nouns, `sim --list`
//! reads `--deck`, and clocks outside the supported range are refused.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::Stdio;

use crate::store_support::{at, key, review};
use chrono::Duration;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::Store;

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-05-10T12:00:00Z";
const BUNDLED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/decks");
const FULL: &str =
    "flipcard: error: cannot write to standard output: No space left on device (os error 28)";

/// Where a stream of the command goes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Sink {
    /// A pipe whose read end was closed before the command started.
    ClosedPipe,
    /// `/dev/full`: every write fails with ENOSPC.
    Full,
}

impl Sink {
    fn stdio(self) -> Stdio {
        match self {
            Sink::ClosedPipe => {
                let (reader, writer) = std::io::pipe().expect("pipe");
                drop(reader);
                Stdio::from(writer)
            }
            Sink::Full => Stdio::from(
                File::options()
                    .write(true)
                    .open("/dev/full")
                    .expect("/dev/full"),
            ),
        }
    }
}

/// A data dir with three ratings of deck `mini`, and the deck beside it.
struct Setup {
    _dir: tempfile::TempDir,
    root: PathBuf,
}

impl Setup {
    fn new() -> Setup {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().to_path_buf();
        mini_deck(&root);
        let data = root.join("data");
        let mut store = Store::open(&data).unwrap();
        let t = at("2026-05-09T08:30:00.250Z");
        for (card, rating, state) in [
            ("a", Rating::Good, State::Review),
            ("b", Rating::Again, State::Learning),
        ] {
            let r = review(
                &key("mini", card),
                t,
                rating,
                ReviewKind::Learn,
                state,
                Duration::days(2),
            );
            store.record(&r).unwrap();
        }
        drop(store);
        std::fs::copy(data.join("flipcard.db"), root.join("copy.db")).unwrap();
        std::fs::write(root.join("cards.csv"), "front,back,tags\nQ1,A1,x\nQ2,A2,\n").unwrap();
        Setup { _dir: dir, root }
    }

    fn command(&self, args: &[&str]) -> Flipcard {
        Flipcard::new(self.root.join("data"))
            .decks(self.root.join("decks"))
            .now(NOW)
            .current_dir(&self.root)
            .env_remove("RUST_BACKTRACE")
            .args(args)
    }

    fn run(&self, args: &[&str]) -> Output {
        self.command(args).run()
    }

    fn run_to(&self, args: &[&str], stdout: Sink) -> Output {
        self.command(args).stdout(stdout.stdio()).run()
    }
}

/// Deck `mini` (two cards, one scene) in `root/decks`, with its content.
fn mini_deck(root: &Path) {
    std::fs::create_dir_all(root.join("decks")).unwrap();
    std::fs::create_dir_all(root.join("content/mini")).unwrap();
    std::fs::write(root.join("content/mini/en.toml"), "").unwrap();
    let toml = "[deck]\nid = 'mini'\ntitle = { en = 'Mini' }\nlanguages = ['en']\n\n\
        [[card]]\nid = 'a'\nkind = 'basic'\nfront = { en = 'Front a' }\nback = { en = 'Back a' }\n\n\
        [[card]]\nid = 'b'\nkind = 'basic'\nfront = { en = 'Front b' }\nback = { en = 'Back b' }\n\n\
        [[scene]]\nid = 'spin'\ninertia = [1.0, 2.0, 3.0]\nomega = [0.01, 1.0, 0.01]\n\
        duration = 20.0\nflat = true\nshow = ['omega']\n";
    std::fs::write(root.join("decks/mini.toml"), toml).unwrap();
}

/// Each command, with the lines it writes to stderr when all goes well.
fn commands() -> Vec<(Vec<&'static str>, &'static [&'static str])> {
    const NONE: &[&str] = &[];
    vec![
        (vec!["check"], NONE),
        (vec!["check", "decks"], NONE),
        (
            vec![
                "sim",
                "--inertia",
                "1,2,3",
                "--omega",
                "0.01,1,0.01",
                "--t-end",
                "10",
            ],
            NONE,
        ),
        (
            vec![
                "sim",
                "--inertia",
                "1,2,3",
                "--omega",
                "0.01,1,0.01",
                "--t-end",
                "10",
                "--format",
                "json",
            ],
            NONE,
        ),
        (vec!["sim", "--scene", "spin"], NONE),
        (
            vec!["sim", "--scene", "middle-axis-spin", "--deck", BUNDLED],
            NONE,
        ),
        (vec!["sim", "--list"], NONE),
        (vec!["sim", "--list", "--deck", "decks/mini.toml"], NONE),
        (vec!["bench", "--quick", "--out", "bench-out"], &["bench"]),
        (vec!["stats"], NONE),
        (vec!["stats", "--json"], NONE),
        (vec!["export", "--reviews"], NONE),
        (vec!["export", "--reviews", "--format", "csv"], NONE),
        (vec!["export", "--deck", "mini"], NONE),
        (vec!["import", "cards.csv", "--deck-id", "imported"], NONE),
        (vec!["db", "rebuild"], NONE),
        (vec!["db", "restore", "copy.db", "--force"], NONE),
        (vec!["--help"], NONE),
        (vec!["sim", "--help"], NONE),
        (vec!["--version"], NONE),
    ]
}

/// The stderr lines not among those the command writes when all goes well.
fn unexpected_stderr<'a>(text: &'a str, expected: &[&str]) -> Vec<&'a str> {
    text.lines()
        .filter(|l| !expected.iter().any(|p| l.starts_with(p)))
        .collect()
}

#[test]
fn every_command_writes_its_output_when_stdout_works() {
    let setup = Setup::new();
    for (args, _) in commands() {
        let out = setup.run(&args);
        assert!(out.status.success(), "{args:?}: {}", out.stderr());
        assert!(!out.stdout.is_empty(), "{args:?} printed nothing");
    }
}

#[test]
fn a_closed_pipe_on_stdout_is_a_quiet_normal_end_for_every_command() {
    let setup = Setup::new();
    for (args, expected) in commands() {
        let out = setup.run_to(&args, Sink::ClosedPipe);
        let err = out.stderr();
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(
            matches!(out.status.code(), Some(0 | 141)),
            "{args:?}: {:?}: {err}",
            out.status
        );
        assert_eq!(
            unexpected_stderr(&err, expected),
            Vec::<&str>::new(),
            "{args:?}"
        );
    }
}

#[test]
fn a_full_device_on_stdout_is_one_line_and_exit_status_1_for_every_command() {
    let setup = Setup::new();
    for (args, expected) in commands() {
        let out = setup.run_to(&args, Sink::Full);
        let err = out.stderr();
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(unexpected_stderr(&err, expected), vec![FULL], "{args:?}");
    }
}

#[test]
fn bench_writes_its_files_even_when_nobody_reads_the_table() {
    let setup = Setup::new();
    let out = setup.run_to(&["bench", "--quick", "--out", "piped"], Sink::ClosedPipe);
    assert_eq!(out.status.code(), Some(0), "{}", out.stderr());
    for file in ["work_precision.csv", "work_precision.svg"] {
        let path = setup.root.join("piped").join(file);
        assert!(path.is_file(), "{} missing", path.display());
    }
}

/// `check` of a deck with an error: the diagnostics go to stderr, the
/// verdict is the exit status, whatever happens to stderr.
#[test]
fn check_keeps_its_verdict_when_stderr_is_closed_or_full() {
    let setup = Setup::new();
    std::fs::write(setup.root.join("bad.toml"), "[deck]\nid = 'bad'\n").unwrap();
    let failed = setup.run(&["check", "bad.toml"]);
    assert_eq!(failed.status.code(), Some(1), "{}", failed.stderr());
    assert!(failed.stderr().contains("error"), "{}", failed.stderr());
    for sink in [Sink::ClosedPipe, Sink::Full] {
        for (path, code) in [("bad.toml", 1), ("decks", 0)] {
            let out = setup.command(&["check", path]).stderr(sink.stdio()).run();
            assert_eq!(out.status.code(), Some(code), "{sink:?} {path}");
            let stdout = String::from_utf8_lossy(&out.stdout);
            if code == 0 {
                assert!(stdout.ends_with(": ok\n"), "{stdout}");
            } else {
                assert_eq!(stdout, "");
            }
        }
    }
}

/// Progress and warnings on stderr: a failing stderr neither stops the
/// command nor costs its output.
#[test]
fn commands_that_talk_on_stderr_finish_when_stderr_is_closed_or_full() {
    let setup = Setup::new();
    for sink in [Sink::ClosedPipe, Sink::Full] {
        let out = setup
            .command(&["import", "cards.csv", "--deck-id", "imported"])
            .stderr(sink.stdio())
            .run();
        assert_eq!(out.status.code(), Some(0), "{sink:?}");
        assert!(String::from_utf8_lossy(&out.stdout).contains("[deck]"));
        let out = setup
            .command(&["bench", "--quick", "--out", "b"])
            .stderr(sink.stdio())
            .run();
        assert_eq!(out.status.code(), Some(0), "{sink:?}");
        assert!(String::from_utf8_lossy(&out.stdout).starts_with("case"));
        // The error message itself has nowhere to go: the status says it.
        let out = setup
            .command(&["stats", "--deck", "nope"])
            .stderr(sink.stdio())
            .run();
        assert_eq!(out.status.code(), Some(1), "{sink:?}");
    }
}

/// Runs a command expected to fail and returns its one error line.
fn error_line(setup: &Setup, args: &[&str]) -> String {
    let out = setup.run(args);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {}", out.stderr());
    let err = out.stderr();
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: {err}");
    assert!(lines[0].starts_with("flipcard: error: "), "{err}");
    lines[0].to_string()
}

#[test]
fn an_error_states_its_cause_once() {
    let setup = Setup::new();
    std::fs::write(setup.root.join("a-file"), "").unwrap();
    let cases: [(&[&str], &str); 6] = [
        (
            &["db", "rebuild", "--data-dir", "a-file"],
            "File exists (os error 17)",
        ),
        (
            &["db", "rebuild", "--data-dir", "a-file/sub"],
            "Not a directory (os error 20)",
        ),
        (
            &["db", "rebuild", "--data-dir", "/proc/x"],
            "No such file or directory (os error 2)",
        ),
        (&["stats", "--data-dir", "a-file"], "Not a directory"),
        (
            &["bench", "--quick", "--out", "a-file"],
            "File exists (os error 17)",
        ),
        (
            &["import", "missing.csv", "--deck-id", "x"],
            "No such file or directory (os error 2)",
        ),
    ];
    for (args, cause) in cases {
        let line = error_line(&setup, args);
        assert_eq!(line.matches(cause).count(), 1, "{line}");
    }
}

#[test]
fn a_database_error_states_its_cause_once() {
    let setup = Setup::new();
    // A flipcard database missing one of its tables: SQLite's own message,
    // once, without its error code's description after it.
    let data = setup.root.join("data");
    rusqlite::Connection::open(data.join("flipcard.db"))
        .and_then(|c| c.execute_batch("DROP TABLE card_state"))
        .unwrap();
    let line = error_line(&setup, &["stats"]);
    assert_eq!(
        line.matches("no such table: card_state").count(),
        1,
        "{line}"
    );
    assert!(!line.contains("Error code"), "{line}");

    std::fs::create_dir_all(setup.root.join("corrupt")).unwrap();
    std::fs::write(setup.root.join("corrupt/flipcard.db"), vec![0x5a; 8192]).unwrap();
    let line = error_line(&setup, &["stats", "--data-dir", "corrupt"]);
    assert_eq!(line.matches("file is not a database").count(), 1, "{line}");
}

#[test]
fn a_config_error_states_its_cause_once() {
    let setup = Setup::new();
    std::fs::create_dir_all(setup.root.join("config-dir")).unwrap();
    let line = error_line(&setup, &["stats", "--config", "config-dir"]);
    assert_eq!(
        line.matches("is a directory, not a regular file").count(),
        1,
        "{line}"
    );
}

#[test]
fn counts_of_one_are_singular() {
    let setup = Setup::new();
    let out = setup.run(&["check", "decks"]);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1 deck, 2 cards, 0 prompts, 1 scene, 0 sections: ok\n"
    );

    // A file with no [deck] table: one error, no warning.
    std::fs::write(setup.root.join("empty.toml"), "").unwrap();
    let out = setup.run(&["check", "empty.toml"]);
    assert_eq!(out.stderr().lines().last(), Some("1 error, 0 warnings"));

    std::fs::write(setup.root.join("one-bad.csv"), "front,back,tags\nQ,,\n").unwrap();
    let out = setup.run(&["import", "one-bad.csv", "--deck-id", "x"]);
    let err = out.stderr();
    assert!(err.contains("error: 1 bad row in one-bad.csv"), "{err}");

    std::fs::write(setup.root.join("one.csv"), "front,back,tags\nQ,A,\n").unwrap();
    let out = setup.run(&["import", "one.csv", "--deck-id", "x"]);
    assert!(
        out.stderr().starts_with("flipcard: 1 card. "),
        "{}",
        out.stderr()
    );

    let out = setup.run(&["db", "rebuild"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("rebuilt 2 card states from 2 log rows in "),
        "{text}"
    );

    // Card `b` leaves the deck: one orphan, with one review.
    let deck = setup.root.join("decks/mini.toml");
    let toml = std::fs::read_to_string(&deck).unwrap();
    let without_b = toml.replace("[[card]]\nid = 'b'", "[[card]]\nid = 'c'");
    std::fs::write(&deck, without_b).unwrap();
    let out = setup.run(&["stats"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Orphans: 1 item with history"), "{text}");
    assert!(text.contains("  mini/b forward: 1 review\n"), "{text}");

    let out = setup.run(&["sim", "--list", "--deck", "empty.toml"]);
    assert!(out.stderr().contains("(1 error; run"), "{}", out.stderr());
}

#[test]
fn sim_list_reads_the_deck_it_is_given() {
    let setup = Setup::new();
    for path in ["decks/mini.toml", "decks"] {
        let out = setup
            .command(&["sim", "--list", "--deck", path])
            .env_remove("FLIPCARD_DECKS")
            .run();
        assert!(out.status.success(), "{}", out.stderr());
        let text = String::from_utf8_lossy(&out.stdout);
        let ids: Vec<&str> = text
            .lines()
            .map(|l| l.split('\t').next().unwrap())
            .collect();
        assert_eq!(ids, ["spin"], "{text}");
        assert!(text.starts_with("spin\tmini\tinertia=1,2,3\t"), "{text}");
    }
    let line = error_line(&setup, &["sim", "--list", "--deck", "nowhere.toml"]);
    assert!(
        line.contains("nowhere.toml: no such file or directory"),
        "{line}"
    );
    // Without --scene or --list, --deck means nothing: a usage error.
    let out = setup.run(&["sim", "--deck", "decks", "--inertia", "1,2,3"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("--list"), "{}", out.stderr());
}

#[test]
fn clocks_beyond_the_supported_range_are_refused() {
    let setup = Setup::new();
    for now in [
        "9999-12-31T23:00:00-05:00",
        "9999-12-31T00:00:00Z",
        "9900-01-01T00:00:00Z",
        "1969-12-31T23:59:59Z",
    ] {
        for args in [
            &["stats"][..],
            &["stats", "--json"],
            &["export", "--reviews"],
        ] {
            let out = setup.command(args).now(now).run();
            assert_eq!(out.status.code(), Some(1), "{now} {args:?}");
            assert!(out.stdout.is_empty(), "{now} {args:?}");
            let err = out.stderr();
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(
                err.contains(
                    "outside the supported range 1970-01-01T00:00:00Z to 9899-12-31T23:59:59Z"
                ),
                "{err}"
            );
        }
    }
    // The last second accepted: every time written is still RFC 3339.
    let out = setup
        .command(&["stats", "--json"])
        .now("9899-12-31T23:59:59Z")
        .run();
    assert!(out.status.success(), "{}", out.stderr());
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(stats["now"], "9899-12-31T23:59:59Z");
    let out = setup
        .command(&["export", "--reviews"])
        .now("9899-12-31T23:59:59Z")
        .run();
    assert!(out.status.success(), "{}", out.stderr());
}

#[test]
fn import_of_a_folder_says_what_it_is() {
    let setup = Setup::new();
    let line = error_line(&setup, &["import", "decks", "--deck-id", "x"]);
    assert_eq!(
        line,
        "flipcard: error: cannot read decks: is a directory, not a regular file"
    );
}
