//! Deck and content paths that are not regular files: FIFOs, sockets,
//! devices, directories, dangling links and link loops are reported by what
//! they are (never opened, never skipped), through the binary and through
//! the library the app uses.

#![cfg(unix)]

use std::fs;
use std::os::unix::fs::{PermissionsExt, symlink};
use std::os::unix::net::UnixListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use crate::support::Flipcard;

/// Long enough for a loaded machine; a FIFO that is opened blocks forever.
const TIMEOUT: Duration = Duration::from_secs(30);

const DECK: &str = "[deck]
id = \"d\"
title = { en = 'D', hi-Latn = 'D' }
languages = [\"en\", \"hi-Latn\"]

[[card]]
id = \"c\"
front = { en = 'F', hi-Latn = 'F' }
back = { en = 'B', hi-Latn = 'B' }
explain = \"s\"
";
const DECK_EN: &str = "[deck]\nid = \"e\"\ntitle = 'E'\nlanguages = [\"en\"]\n\n[[card]]\nid = \"c\"\nfront = 'F'\nback = 'B'\n";
const EN: &str = "[[section]]\nid = \"s\"\ntitle = 'T'\nbody = 'B'\n";
const HI: &str = "[[section]]\nid = \"s\"\ntitle = 'T'\nbody = 'B'\n";

fn write(root: &Path, rel: &str, text: &str) {
    let path = root.join(rel);
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    fs::write(path, text).unwrap();
}

/// A course with deck `d` (two languages) and deck `e` (English only).
fn course() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "decks/d.toml", DECK);
    write(dir.path(), "content/d/en.toml", EN);
    write(dir.path(), "content/d/hi-Latn.toml", HI);
    write(dir.path(), "decks/e.toml", DECK_EN);
    write(dir.path(), "content/e/en.toml", "");
    dir
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(status.success());
}

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

/// `flipcard check ARGS` in `dir`, killed (and failed) if it does not end.
fn check(dir: &Path, args: &[&str]) -> Run {
    let mut all = vec!["check"];
    all.extend_from_slice(args);
    flipcard(dir, &all)
}

/// `flipcard ARGS` in `dir` with its data and config there, killed (and
/// failed) if it does not end.
fn flipcard(dir: &Path, args: &[&str]) -> Run {
    run(in_dir(dir).args(args))
}

/// flipcard run in `dir`, with its data and config there.
fn in_dir(dir: &Path) -> Flipcard {
    Flipcard::new(dir.join("data"))
        .config(dir.join("config.toml"))
        .current_dir(dir)
}

/// A run killed (and failed) if it does not end.
fn run(flipcard: Flipcard) -> Run {
    let out = flipcard.run_within(TIMEOUT.as_secs());
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: out.stdout(),
        stderr: out.stderr(),
    }
}

/// The headlines of a run (lines naming an error or warning).
fn headlines(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.contains(": error: ") || l.contains(": warning: "))
        .collect()
}

#[test]
fn the_course_is_valid_to_start_with() {
    let dir = course();
    let run = check(dir.path(), &["decks"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "2 decks, 2 cards, 0 prompts, 0 scenes, 1 section: ok\n"
    );
}

#[test]
fn a_fifo_named_on_the_command_line_is_reported_not_opened() {
    let dir = course();
    mkfifo(&dir.path().join("x.toml"));
    let run = check(dir.path(), &["x.toml"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(
        headlines(&run.stderr),
        ["x.toml: error: is a FIFO, not a regular file"]
    );
    assert!(run.stdout.is_empty());
}

#[test]
fn a_dangling_link_named_on_the_command_line_says_where_it_points() {
    let dir = course();
    symlink("gone/x.toml", dir.path().join("x.toml")).unwrap();
    let run = check(dir.path(), &["x.toml"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(
        headlines(&run.stderr),
        ["x.toml: error: dangling symbolic link to gone/x.toml"]
    );
}

#[test]
fn every_deck_entry_that_is_not_a_file_is_an_error() {
    let dir = course();
    let decks = dir.path().join("decks");
    mkfifo(&decks.join("a-fifo.toml"));
    symlink("../elsewhere/gone.toml", decks.join("b-dangling.toml")).unwrap();
    symlink("c-loop.toml", decks.join("c-loop.toml")).unwrap();
    symlink("d2-loop.toml", decks.join("d1-loop.toml")).unwrap();
    symlink("d1-loop.toml", decks.join("d2-loop.toml")).unwrap();
    fs::create_dir(decks.join("f-dir.toml")).unwrap();
    symlink("/dev/null", decks.join("g-null.toml")).unwrap();
    let _socket = UnixListener::bind(decks.join("h-socket.toml")).unwrap();
    // Not deck files at all: ignored as before; hidden names too (an
    // editor's lock file is a dangling link while the deck is open).
    mkfifo(&decks.join("notes.txt"));
    symlink("learner@host.1234:1700000000", decks.join(".#deck.toml")).unwrap();
    fs::create_dir(decks.join("drafts")).unwrap();

    let run = check(dir.path(), &["decks"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(
        headlines(&run.stderr),
        [
            "decks/a-fifo.toml: error: is a FIFO, not a regular file",
            "decks/b-dangling.toml: error: dangling symbolic link to ../elsewhere/gone.toml",
            "decks/c-loop.toml: error: symbolic link loop",
            "decks/d1-loop.toml: error: symbolic link loop",
            "decks/d2-loop.toml: error: symbolic link loop",
            "decks/f-dir.toml: error: is a directory, not a regular file",
            "decks/g-null.toml: error: is a symbolic link to a character device (/dev/null), not a regular file",
            "decks/h-socket.toml: error: is a socket, not a regular file",
        ],
        "{}",
        run.stderr
    );
    assert_eq!(run.stderr.lines().last(), Some("8 errors, 0 warnings"));
    assert!(run.stdout.is_empty());
}

#[test]
fn a_link_to_a_good_deck_file_is_fine() {
    let dir = course();
    let decks = dir.path().join("decks");
    fs::create_dir(dir.path().join("shared")).unwrap();
    fs::rename(decks.join("e.toml"), dir.path().join("shared/e.toml")).unwrap();
    symlink("../shared/e.toml", decks.join("e.toml")).unwrap();
    let run = check(dir.path(), &["decks"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "2 decks, 2 cards, 0 prompts, 0 scenes, 1 section: ok\n"
    );
}

#[test]
fn content_files_that_are_not_files_say_what_they_are() {
    type Make = fn(&Path);
    let cases: [(&str, Make, &str); 5] = [
        (
            "directory",
            |p| fs::create_dir(p).unwrap(),
            "is a directory, not a regular file",
        ),
        ("fifo", |p| mkfifo(p), "is a FIFO, not a regular file"),
        (
            "loop",
            |p| symlink("hi-Latn.toml", p).unwrap(),
            "symbolic link loop",
        ),
        (
            "dangling",
            |p| symlink("../../old/hi-Latn.toml", p).unwrap(),
            "dangling symbolic link to ../../old/hi-Latn.toml",
        ),
        (
            "socket",
            |p| drop(UnixListener::bind(p).unwrap()),
            "is a socket, not a regular file",
        ),
    ];
    for (name, make, what) in cases {
        let dir = course();
        let file = dir.path().join("content/d/hi-Latn.toml");
        fs::remove_file(&file).unwrap();
        make(&file);
        let run = check(dir.path(), &["decks"]);
        assert_eq!(run.code, 1, "{name}: {}", run.stderr);
        // Only what the file is: no "no content file", and the card's link
        // to a section is not reported as unresolved.
        assert_eq!(
            headlines(&run.stderr),
            [format!("content/d/hi-Latn.toml: error: {what}")],
            "{name}"
        );
    }
}

/// Permissions stop a user without privileges only: where this test runs
/// as root (as in CI) the check runs as `nobody`, through `setpriv`.
#[test]
fn an_unreadable_content_file_says_so() {
    let dir = course();
    let file = dir.path().join("content/d/hi-Latn.toml");
    fs::set_permissions(&file, fs::Permissions::from_mode(0o000)).unwrap();
    let run = if fs::read(&file).is_err() {
        check(dir.path(), &["decks"])
    } else {
        let Some(run) = as_nobody(dir.path(), &["check", "decks"]) else {
            return;
        };
        run
    };
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(
        headlines(&run.stderr),
        ["content/d/hi-Latn.toml: error: cannot be read: permission denied"]
    );
}

/// `flipcard ARGS` in `dir` as the unprivileged user `nobody` (uid and
/// gid 65534, no groups): `dir` is opened to every user and the binary
/// copied there if `nobody` cannot run it where it is. `None` (skipped, a
/// failure under `CI=true`) without `setpriv`.
fn as_nobody(dir: &Path, args: &[&str]) -> Option<Run> {
    if !crate::support::require_tool("setpriv") {
        return None;
    }
    const NOBODY: [&str; 3] = ["--reuid=65534", "--regid=65534", "--clear-groups"];
    fs::set_permissions(dir, fs::Permissions::from_mode(0o755)).unwrap();
    let can_run = |bin: &Path| {
        Command::new("setpriv")
            .args(NOBODY)
            .arg(bin)
            .arg("--version")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    let mut bin = crate::support::test_binary().to_path_buf();
    if !can_run(&bin) {
        let copy = dir.join("flipcard-bin");
        fs::copy(&bin, &copy).unwrap();
        fs::set_permissions(&copy, fs::Permissions::from_mode(0o755)).unwrap();
        bin = copy;
        assert!(can_run(&bin), "nobody cannot run {}", bin.display());
    }
    // Nobody must not read the file, or the test proves nothing.
    assert!(
        !Command::new("setpriv")
            .args(NOBODY)
            .args(["cat", "content/d/hi-Latn.toml"])
            .current_dir(dir)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap()
            .success(),
        "nobody can read the unreadable file"
    );
    let nobody = in_dir(dir)
        .prefix(["setpriv"].into_iter().chain(NOBODY))
        .program(&bin)
        .args(args);
    Some(run(nobody))
}

#[test]
fn a_content_folder_that_is_a_file_is_not_missing_content() {
    let dir = course();
    fs::remove_dir_all(dir.path().join("content/d")).unwrap();
    write(dir.path(), "content/d", "");
    let run = check(dir.path(), &["decks"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let heads = headlines(&run.stderr);
    assert_eq!(heads.len(), 2, "{}", run.stderr);
    for (head, lang) in heads.iter().zip(["en", "hi-Latn"]) {
        assert!(
            head.starts_with(&format!("content/d/{lang}.toml: error: cannot be read: ")),
            "{head}"
        );
    }
}

/// Runs `f` on another thread, failing if it does not return in time.
fn within_timeout<T: Send + 'static>(what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(TIMEOUT)
        .unwrap_or_else(|_| panic!("{what} hung"))
}

#[test]
fn the_library_loader_never_opens_a_fifo() {
    let dir = course();
    let decks = dir.path().join("decks");
    mkfifo(&decks.join("x.toml"));
    fs::remove_file(dir.path().join("content/e/en.toml")).unwrap();
    mkfifo(&dir.path().join("content/e/en.toml"));

    let loaded = within_timeout("load_dir", {
        let decks = decks.clone();
        move || flipcard::deck::load_dir(&decks)
    });
    let heads: Vec<String> = loaded.diagnostics.iter().map(|d| d.headline()).collect();
    let x = decks.join("x.toml");
    let en = dir.path().join("content/e/en.toml");
    assert_eq!(
        heads,
        [
            format!("{}: error: is a FIFO, not a regular file", en.display()),
            format!("{}: error: is a FIFO, not a regular file", x.display()),
        ]
    );
    // The good deck is still there for the app.
    let ids: Vec<&str> = loaded.decks.iter().map(|d| d.id.as_str()).collect();
    assert_eq!(ids, ["d"]);

    let loaded = within_timeout("load_paths", {
        let x: PathBuf = x.clone();
        move || flipcard::deck::load_paths(&[x])
    });
    assert_eq!(loaded.errors(), 1);
    assert!(loaded.decks.is_empty());
}

/// Files the commands read whole (a learner's export, a review log, a CSV
/// of cards, an Anki package, the config): a FIFO there is refused by name
/// at once, and nothing is written.
#[test]
fn a_fifo_given_as_an_input_file_is_refused_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in ["export.csv", "log.json", "cards.csv", "deck.apkg"] {
        mkfifo(&d.join(name));
    }
    let cases: [(&[&str], &str); 4] = [
        (
            &["report", "export.csv", "--out", "out"],
            "export.csv: is a FIFO",
        ),
        (&["import", "--reviews", "log.json"], "log.json: is a FIFO"),
        (
            &["import", "cards.csv", "--deck-id", "x"],
            "cards.csv: is a FIFO",
        ),
        (&["import", "deck.apkg"], "deck.apkg: is a FIFO"),
    ];
    for (args, said) in cases {
        let run = flipcard(d, args);
        assert_eq!(run.code, 1, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(said), "{args:?}: {}", run.stderr);
    }
    assert!(!d.join("data").join("flipcard.db").exists());
    mkfifo(&d.join("config.toml"));
    let run = flipcard(d, &["stats"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("config.toml: is a FIFO, not a regular file"),
        "{}",
        run.stderr
    );
}
