//! End to end, as a person uses it: the release binary in a real terminal
//! (tmux), with a temporary data dir and a fixed clock. Review three cards,
//! undo one, switch to Hinglish, answer the middle-axis prompt and see the
//! verdict, quit, and check through `flipcard export --reviews` that exactly
//! the expected reviews were stored. Also: shrink the terminal to 20×6 and
//! back without a crash, and find the terminal restored after Ctrl-C and
//! SIGTERM.
//!
//! Skipped, with a message, only when tmux is not installed (`.ci/run`
//! installs it).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use flipcard::deck::{Answer, Deck};

const NOW: &str = "2026-03-02T09:00:00Z";
const DECK: &str = "torque-free-rotation";

fn tmux_available() -> bool {
    Command::new("tmux")
        .arg("-V")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The release binary, built once per test run. Cargo locks each profile's
/// output directory separately, so building the release profile from
/// inside `cargo test` (which holds the test profile's lock) cannot
/// deadlock.
fn release_binary() -> &'static Path {
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

/// A tmux server of its own (its own socket), killed on drop.
struct Tmux {
    socket: String,
}

impl Tmux {
    /// Starts `command` in a detached session of `w`×`h` cells. The command
    /// runs under `sh`, which afterwards prints the exit status and whether
    /// the terminal is back in canonical (cooked) mode, then waits.
    fn start(name: &str, env: &[(&str, String)], args: &str, w: u16, h: u16) -> Tmux {
        let socket = format!("flipcard-e2e-{}-{name}", std::process::id());
        let mut exports = String::new();
        for (k, v) in env {
            exports.push_str(&format!("{k}='{v}' "));
        }
        let script = format!(
            "{exports}'{bin}' {args}; echo \"EXIT=$?\"; \
             if stty -a | tr ' ;' '\\n\\n' | grep -qx icanon; then echo TTY=cooked; else echo TTY=raw; fi; \
             sleep 600",
            bin = release_binary().display()
        );
        let t = Tmux { socket };
        t.tmux(&[
            "new-session",
            "-d",
            "-s",
            "e2e",
            "-x",
            &w.to_string(),
            "-y",
            &h.to_string(),
            "sh",
            "-c",
            &script,
        ]);
        t
    }

    fn tmux(&self, args: &[&str]) -> String {
        let out = Command::new("tmux")
            .args(["-L", &self.socket, "-f", "/dev/null"])
            .args(args)
            .output();
        match out {
            Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).into_owned(),
            Ok(o) => panic!(
                "tmux {args:?} failed: {}",
                String::from_utf8_lossy(&o.stderr)
            ),
            Err(e) => panic!("tmux {args:?}: {e}"),
        }
    }

    /// Named keys (`Enter`, `Escape`, `C-c`, `Space`) or single characters.
    fn keys(&self, keys: &[&str]) {
        for k in keys {
            self.tmux(&["send-keys", "-t", "e2e", k]);
            // Two quick Escapes would arrive as one Alt-Escape.
            std::thread::sleep(Duration::from_millis(40));
        }
    }

    fn screen(&self) -> String {
        self.tmux(&["capture-pane", "-p", "-t", "e2e"])
    }

    /// Waits until the screen contains `needle`; returns the screen.
    fn wait_for(&self, needle: &str) -> String {
        self.wait_until(needle, |s| s.contains(needle))
    }

    fn wait_until(&self, what: &str, ok: impl Fn(&str) -> bool) -> String {
        let start = Instant::now();
        loop {
            let s = self.screen();
            if ok(&s) {
                return s;
            }
            if start.elapsed() > Duration::from_secs(30) {
                panic!("timed out waiting for {what:?}; the screen:\n{s}");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn resize(&self, w: u16, h: u16) {
        self.tmux(&[
            "resize-window",
            "-t",
            "e2e",
            "-x",
            &w.to_string(),
            "-y",
            &h.to_string(),
        ]);
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .output();
    }
}

fn bundled_deck() -> Deck {
    let loaded = flipcard::deck::load_dir(&flipcard::cmd::paths::bundled_decks());
    loaded
        .decks
        .into_iter()
        .find(|d| d.id == DECK)
        .unwrap_or_else(|| panic!("bundled deck {DECK} not found"))
}

/// The first words of a text as the screen shows it (math rendered).
fn opening(text: &str, words: usize) -> String {
    flipcard::text::render(text)
        .split_whitespace()
        .take(words)
        .collect::<Vec<_>>()
        .join(" ")
}

struct Env {
    dir: tempfile::TempDir,
}

impl Env {
    fn new() -> Env {
        Env {
            dir: tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}")),
        }
    }

    fn vars(&self) -> Vec<(&'static str, String)> {
        let d = self.dir.path();
        vec![
            ("FLIPCARD_NOW", NOW.to_string()),
            ("FLIPCARD_DATA_DIR", d.join("data").display().to_string()),
            (
                "FLIPCARD_CONFIG",
                d.join("config.toml").display().to_string(),
            ),
            ("TERM", "xterm-256color".to_string()),
        ]
    }

    fn export(&self) -> serde_json::Value {
        let mut cmd = Command::new(release_binary());
        cmd.args(["export", "--reviews", "--format", "json"]);
        for (k, v) in self.vars() {
            cmd.env(k, v);
        }
        let out = cmd.output().unwrap_or_else(|e| panic!("export: {e}"));
        assert!(
            out.status.success(),
            "export failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
            panic!(
                "export is not JSON ({e}): {}",
                String::from_utf8_lossy(&out.stdout)
            )
        })
    }
}

#[test]
fn review_undo_hinglish_prompt_verdict_and_export() {
    if !tmux_available() {
        eprintln!("skipping the terminal end-to-end test: tmux is not installed");
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    let t = Tmux::start("main", &env.vars(), "", 100, 32);
    t.wait_for("last studied");

    // Review: the first three new cards in deck order.
    t.keys(&["Enter"]);
    let cards: Vec<_> = deck.cards.iter().take(3).collect();
    let ratings = ["3", "1", "4"];
    for (card, rating) in cards.iter().zip(ratings) {
        t.wait_for(&opening(card.front.get("en"), 4));
        // Enter reveals a basic card and checks a typed one alike.
        t.keys(&["Enter"]);
        t.wait_for("Again");
        t.keys(&[rating]);
    }
    // Undo the third: it comes back, front first.
    t.keys(&["u"]);
    let third = cards[2];
    let s = t.wait_for("last rating undone");
    assert!(s.contains(&opening(third.front.get("en"), 4)), "{s}");

    // A terminal too small shows a message; growing it back restores the screen.
    t.resize(20, 6);
    t.wait_for("enlarge");
    t.resize(100, 32);
    t.wait_for(&opening(third.front.get("en"), 4));

    // Hinglish: the same card, in Hinglish, and the interface too.
    t.keys(&["l"]);
    let s = t.wait_for(&opening(third.front.get("hi-Latn"), 4));
    assert!(s.contains("naye"), "{s}");

    // The middle-axis prompt: commit to the answer the physics gives.
    let (index, prompt) = deck
        .prompts
        .iter()
        .enumerate()
        .find(|(_, p)| p.id == "middle-axis")
        .unwrap_or_else(|| panic!("no middle-axis prompt"));
    let Answer::Choice { choices, expected } = &prompt.answer else {
        panic!("middle-axis is a choice prompt");
    };
    let choice = choices
        .iter()
        .position(|c| &c.id == expected)
        .unwrap_or_else(|| panic!("expected choice {expected} missing"));
    t.keys(&["Escape"]);
    t.wait_for("pichhli padhai");
    t.keys(&["p"]);
    t.wait_for(&opening(deck.prompts[0].question.get("hi-Latn"), 3));
    for _ in 0..index {
        t.keys(&["j"]);
    }
    t.keys(&["Enter"]);
    t.wait_for(&opening(prompt.question.get("hi-Latn"), 4));
    let number = (choice + 1).to_string();
    t.keys(&[&number, "Enter"]);
    // Speed the run up ×8, then wait for the verdict.
    t.keys(&["+", "+", "+"]);
    let s = t.wait_for("✓ Sahi ✓");
    // What this run showed, with the flip times, and the run's keys.
    assert!(
        s.contains("is 8 s ke run mein: 3 baar palta: 1.49, 4.24 aur 7.00 s par"),
        "{s}"
    );
    assert!(s.contains("n agla prompt"), "{s}");
    // `n`: the next prompt, ready for a new prediction.
    t.keys(&["n"]);
    t.wait_for(&opening(deck.prompts[index + 1].question.get("hi-Latn"), 4));

    // Quit from the prompt: back, back, quit.
    t.keys(&["q"]);
    t.keys(&["q"]);
    t.keys(&["q"]);
    let s = t.wait_for("TTY=");
    assert!(s.contains("EXIT=0"), "{s}");
    assert!(s.contains("TTY=cooked"), "terminal left in raw mode:\n{s}");

    // Exactly three ratings were stored, the third one undone.
    let log = env.export();
    let rows = log
        .as_array()
        .unwrap_or_else(|| panic!("not an array: {log}"));
    let got: Vec<(String, String, u64, String, bool)> = rows
        .iter()
        .map(|r| {
            (
                r["deck"].as_str().unwrap_or("").to_string(),
                r["card"].as_str().unwrap_or("").to_string(),
                r["rating"].as_u64().unwrap_or(0),
                r["reviewed_at"].as_str().unwrap_or("").to_string(),
                r["undone"].as_bool().unwrap_or(false),
            )
        })
        .collect();
    let want: Vec<(String, String, u64, String, bool)> = cards
        .iter()
        .zip([(3, false), (1, false), (4, true)])
        .map(|(c, (rating, undone))| {
            (
                DECK.to_string(),
                c.id.clone(),
                rating,
                "2026-03-02T09:00:00.000Z".to_string(),
                undone,
            )
        })
        .collect();
    assert_eq!(got, want);

    // The language choice was saved for the next run.
    let config = std::fs::read_to_string(env.dir.path().join("config.toml")).unwrap_or_default();
    assert!(config.contains("hi-Latn"), "{config}");
}

#[test]
fn ctrl_c_and_sigterm_restore_the_terminal() {
    if !tmux_available() {
        eprintln!("skipping the terminal end-to-end test: tmux is not installed");
        return;
    }
    let env = Env::new();

    let t = Tmux::start("ctrlc", &env.vars(), "", 80, 24);
    t.wait_for("last studied");
    t.keys(&["Enter"]);
    t.wait_for("Space");
    t.keys(&["C-c"]);
    let s = t.wait_for("TTY=");
    assert!(s.contains("EXIT=0") && s.contains("TTY=cooked"), "{s}");
    assert!(
        !s.contains("last studied"),
        "alternate screen not left:\n{s}"
    );
    drop(t);

    let t = Tmux::start("term", &env.vars(), "", 80, 24);
    t.wait_for("last studied");
    let pid = t.tmux(&["list-panes", "-t", "e2e", "-F", "#{pane_pid}"]);
    // The pane runs sh; the app is its child.
    let child = Command::new("pgrep")
        .args(["-P", pid.trim()])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    assert!(!child.is_empty(), "no app process under the pane's shell");
    let killed = Command::new("kill").args(["-TERM", &child]).status();
    assert!(killed.is_ok_and(|s| s.success()));
    let s = t.wait_for("TTY=");
    assert!(s.contains("EXIT=143") && s.contains("TTY=cooked"), "{s}");
}

/// The process id of the app running in the pane (a child of its shell).
fn app_pid(t: &Tmux) -> String {
    let pid = t.tmux(&["list-panes", "-t", "e2e", "-F", "#{pane_pid}"]);
    let child = Command::new("pgrep")
        .args(["-P", pid.trim()])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    assert!(!child.is_empty(), "no app process under the pane's shell");
    child
}

#[test]
fn outside_sqlite_readers_during_a_review_lose_no_rating() {
    if !tmux_available() {
        eprintln!("skipping the terminal end-to-end test: tmux is not installed");
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    // An existing database, as a learner has after the first day.
    let mut cmd = Command::new(release_binary());
    cmd.args(["db", "rebuild"]);
    for (k, v) in env.vars() {
        cmd.env(k, v);
    }
    assert!(cmd.status().is_ok_and(|s| s.success()));
    let db = env.dir.path().join("data").join("flipcard.db");
    assert!(db.is_file());

    let t = Tmux::start("outside", &env.vars(), &format!("review {DECK}"), 100, 32);
    t.wait_for(&opening(deck.cards[0].front.get("en"), 4));
    let app = app_pid(&t);

    // Another program opens, reads and closes the file again and again.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let reader = {
        let (db, stop) = (db.clone(), std::sync::Arc::clone(&stop));
        std::thread::spawn(move || {
            let mut opens = 0;
            while !stop.load(std::sync::atomic::Ordering::SeqCst) {
                let script = "import sqlite3, sys\nc = sqlite3.connect(sys.argv[1])\n\
                              c.execute('select count(*) from review').fetchall()\nc.close()\n";
                let python = Command::new("python3")
                    .args(["-c", script])
                    .arg(&db)
                    .status();
                if !python.is_ok_and(|s| s.success()) {
                    let conn = rusqlite::Connection::open(&db).unwrap();
                    let _: i64 = conn
                        .query_row("SELECT count(*) FROM review", [], |r| r.get(0))
                        .unwrap();
                }
                opens += 1;
            }
            opens
        })
    };

    for card in deck.cards.iter().take(5) {
        t.wait_for(&opening(card.front.get("en"), 4));
        std::thread::sleep(Duration::from_millis(150));
        t.keys(&["Enter"]);
        t.wait_for("Again");
        std::thread::sleep(Duration::from_millis(150));
        t.keys(&["3"]);
    }
    t.wait_for(&opening(deck.cards[5].front.get("en"), 4));
    stop.store(true, std::sync::atomic::Ordering::SeqCst);
    let opens = reader.join().unwrap();
    assert!(opens >= 5, "only {opens} outside opens");

    // While the app still runs, a third program sees all five.
    let rows = env.export();
    assert_eq!(rows.as_array().map(Vec::len), Some(5), "{rows}");
    // The app still writes into the log that is on disk, not a deleted one.
    let fds = std::fs::read_dir(format!("/proc/{app}/fd"))
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .filter_map(|e| std::fs::read_link(e.path()).ok())
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
        })
        .unwrap_or_default();
    assert!(
        !fds.iter()
            .any(|p| p.contains("flipcard.db") && p.contains("(deleted)")),
        "{fds:?}"
    );

    // Killed without a chance to clean up: still all five.
    assert!(
        Command::new("kill")
            .args(["-KILL", &app])
            .status()
            .is_ok_and(|s| s.success())
    );
    t.wait_for("EXIT=");
    let rows = env.export();
    let cards: Vec<&str> = rows
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["card"].as_str().unwrap_or(""))
        .collect();
    let want: Vec<&str> = deck.cards.iter().take(5).map(|c| c.id.as_str()).collect();
    assert_eq!(cards, want);
}
