//! End to end, as a person uses it: the release binary in a real terminal
//! (tmux), with a temporary data dir and a fixed clock. Review three cards,
//! undo one, switch to Hinglish, answer the middle-axis prompt and see the
//! verdict, quit, and check through `flipcard export --reviews` that exactly
//! the expected reviews were stored. Also: the reader's formula sheet in
//! both languages; shrink the terminal to 20×6 and
//! back without a crash, and find the terminal restored after Ctrl-C and
//! SIGTERM.
//!
//! Skipped, with a message, only when tmux is not installed, and never
//! under `CI=true` (`.ci/run` installs tmux; there a missing tmux fails).

use std::process::Command;
use std::time::{Duration, Instant};

use flipcard::deck::{Answer, Deck};

use crate::support::Flipcard;

const NOW: &str = "2026-03-02T09:00:00Z";
const DECK: &str = "torque-free-rotation";

/// Whether the end-to-end tests can run: tmux is there (else skipped with
/// a note, and under `CI=true` failed: `crate::support::require`).
pub(crate) fn tmux_available() -> bool {
    crate::support::require_tool("tmux")
}

/// A tmux server of its own (its own socket), killed on drop.
pub(crate) struct Tmux {
    socket: String,
}

impl Tmux {
    /// Starts `flipcard` (the release build) in a detached session of
    /// `w`×`h` cells. It runs under `sh`, which afterwards prints the exit
    /// status and whether the terminal is back in canonical (cooked) mode,
    /// then waits.
    pub(crate) fn start(name: &str, flipcard: Flipcard, w: u16, h: u16) -> Tmux {
        let socket = format!("flipcard-e2e-{}-{name}", std::process::id());
        let script = format!(
            "{app}; echo \"EXIT=$?\"; \
             if stty -a | tr ' ;' '\\n\\n' | grep -qx icanon; then echo TTY=cooked; else echo TTY=raw; fi; \
             sleep 600",
            app = flipcard.release().env("TERM", "xterm-256color").shell()
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
    pub(crate) fn keys(&self, keys: &[&str]) {
        for k in keys {
            self.tmux(&["send-keys", "-t", "e2e", k]);
            // Two quick Escapes would arrive as one Alt-Escape.
            std::thread::sleep(Duration::from_millis(40));
        }
    }

    pub(crate) fn screen(&self) -> String {
        self.tmux(&["capture-pane", "-p", "-t", "e2e"])
    }

    /// Waits until the screen contains `needle`; returns the screen.
    pub(crate) fn wait_for(&self, needle: &str) -> String {
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
    let loaded = flipcard::bundled::load();
    loaded
        .decks
        .into_iter()
        .find(|d| d.id == DECK)
        .unwrap_or_else(|| panic!("bundled deck {DECK} not found"))
}

/// Moves the home screen's selection down to DECK: the home screen lists
/// the bundled decks in the order they load.
fn select_deck(t: &Tmux) {
    let loaded = flipcard::bundled::load();
    let index = loaded
        .decks
        .iter()
        .position(|d| d.id == DECK)
        .unwrap_or_else(|| panic!("bundled deck {DECK} not found"));
    for _ in 0..index {
        t.keys(&["j"]);
    }
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

    /// The release build with this data dir, config and clock.
    fn flipcard(&self) -> Flipcard {
        let d = self.dir.path();
        Flipcard::new(d.join("data"))
            .config(d.join("config.toml"))
            .now(NOW)
            .release()
    }

    fn export(&self) -> serde_json::Value {
        let out = self
            .flipcard()
            .args(["export", "--reviews", "--format", "json"])
            .run();
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
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    let t = Tmux::start("main", env.flipcard(), 100, 32);
    t.wait_for("last studied");

    // Review: the first three new cards in deck order.
    select_deck(&t);
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
        .position(|c| Some(&c.id) == expected.as_ref())
        .unwrap_or_else(|| panic!("expected choice {expected:?} missing"));
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
    let mut want: Vec<(String, String, u64, String, bool)> = cards
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
    // The prompt, new, was rated by its right verdict: Good, as a review
    // item of its own (direction `predict`).
    want.push((
        DECK.to_string(),
        "middle-axis".to_string(),
        3,
        "2026-03-02T09:00:00.000Z".to_string(),
        false,
    ));
    assert_eq!(got, want);
    assert_eq!(rows[3]["direction"].as_str(), Some("predict"), "{log}");

    // The language choice was saved for the next run.
    let config = std::fs::read_to_string(env.dir.path().join("config.toml")).unwrap_or_default();
    assert!(config.contains("hi-Latn"), "{config}");
}

#[test]
fn ctrl_c_and_sigterm_restore_the_terminal() {
    if !tmux_available() {
        return;
    }
    let env = Env::new();

    let t = Tmux::start("ctrlc", env.flipcard(), 80, 24);
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

    let t = Tmux::start("term", env.flipcard(), 80, 24);
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
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    // An existing database, as a learner has after the first day.
    env.flipcard().args(["db", "rebuild"]).run().ok();
    let db = env.dir.path().join("data").join("flipcard.db");
    assert!(db.is_file());

    let t = Tmux::start("outside", env.flipcard().args(["review", DECK]), 100, 32);
    t.wait_for(&opening(deck.cards[0].front.get("en"), 4));
    let app = app_pid(&t);

    // Another program opens, reads and closes the file again and again.
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::SeqCst};
    let stop = std::sync::Arc::new(AtomicBool::new(false));
    let opens = std::sync::Arc::new(AtomicUsize::new(0));
    // Python's sqlite3 module where there is one (always under CI=true),
    // else rusqlite in this process.
    let python = crate::support::require_python_module("sqlite3");
    let reader = {
        let (db, stop, opens) = (
            db.clone(),
            std::sync::Arc::clone(&stop),
            std::sync::Arc::clone(&opens),
        );
        std::thread::spawn(move || {
            while !stop.load(SeqCst) {
                let script = "import sqlite3, sys\nc = sqlite3.connect(sys.argv[1])\n\
                              c.execute('select count(*) from review').fetchall()\nc.close()\n";
                let read = python
                    && Command::new("python3")
                        .args(["-c", script])
                        .arg(&db)
                        .status()
                        .is_ok_and(|s| s.success());
                if !read {
                    let conn = rusqlite::Connection::open(&db).unwrap();
                    let _: i64 = conn
                        .query_row("SELECT count(*) FROM review", [], |r| r.get(0))
                        .unwrap();
                }
                opens.fetch_add(1, SeqCst);
            }
        })
    };
    // Before each rating, at least one outside open and close has happened
    // since the previous one (however slow the machine), so every rating is
    // written after another client has touched the file.
    let an_open_since = |seen: usize| {
        let deadline = std::time::Instant::now() + Duration::from_secs(60);
        while opens.load(SeqCst) <= seen {
            assert!(
                std::time::Instant::now() < deadline,
                "no outside open within a minute"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        opens.load(SeqCst)
    };

    let mut seen = 0;
    for card in deck.cards.iter().take(5) {
        t.wait_for(&opening(card.front.get("en"), 4));
        seen = an_open_since(seen);
        t.keys(&["Enter"]);
        t.wait_for("Again");
        seen = an_open_since(seen);
        t.keys(&["3"]);
    }
    t.wait_for(&opening(deck.cards[5].front.get("en"), 4));
    stop.store(true, SeqCst);
    reader.join().unwrap();
    let opens = opens.load(SeqCst);
    assert!(opens >= 10, "only {opens} outside opens");

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

/// The texts drawn in reverse video (the reader's chosen link, a list's
/// selection) on a screen captured with its escape sequences.
fn reversed_texts(styled: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut reversed = false;
    let mut current = String::new();
    let mut rest = styled;
    while let Some(c) = rest.chars().next() {
        if let Some(seq) = rest.strip_prefix("\x1b[") {
            let end = seq.find(|ch: char| ch.is_ascii_alphabetic()).unwrap_or(0);
            let params = &seq[..end];
            if seq[end..].starts_with('m') {
                let codes: Vec<&str> = params.split(';').collect();
                let mut now = reversed;
                let mut i = 0;
                while i < codes.len() {
                    match codes[i] {
                        "" | "0" | "27" => now = false,
                        "7" => now = true,
                        // Colours: 38;5;n and 38;2;r;g;b carry numbers
                        // that are no attributes.
                        "38" | "48" | "58" => {
                            i += if codes.get(i + 1) == Some(&"2") { 4 } else { 2 };
                        }
                        _ => {}
                    }
                    i += 1;
                }
                if reversed && !now && !current.trim().is_empty() {
                    out.push(std::mem::take(&mut current).trim().to_string());
                }
                if !now {
                    current.clear();
                }
                reversed = now;
            }
            rest = &seq[end + 1..];
            continue;
        }
        if reversed {
            if c == '\n' {
                current.push(' ');
            } else {
                current.push(c);
            }
        }
        rest = &rest[c.len_utf8()..];
    }
    if reversed && !current.trim().is_empty() {
        out.push(current.trim().to_string());
    }
    out
}

#[test]
fn the_fifth_concept_map_link_opens_where_the_screen_showed_the_choice() {
    if !tmux_available() {
        return;
    }
    let deck = bundled_deck();
    let map = deck
        .section("concept-map")
        .unwrap_or_else(|| panic!("the bundled deck has no concept map"));
    let env = Env::new();
    let t = Tmux::start("links", env.flipcard(), 100, 30);
    t.wait_for("last studied");
    select_deck(&t);
    t.keys(&["r"]);
    t.wait_for("spinning with no torque");
    t.keys(&["Right"]);
    t.wait_for(&opening(map.title.get("en"), 3));
    t.keys(&["Tab", "Tab", "Tab", "Tab", "Tab"]);
    let s = t.wait_until("the fifth link chosen", |s| s.contains(" 5/"));
    let styled = t.tmux(&["capture-pane", "-e", "-p", "-t", "e2e"]);
    // What the screen shows chosen: a phrase of the concept map's text, in
    // reverse video, and the title the status line says it opens.
    let chosen = reversed_texts(&styled);
    let phrase = chosen
        .iter()
        .find(|p| !p.contains(&opening(map.title.get("en"), 3)))
        .unwrap_or_else(|| panic!("no chosen link in reverse video: {chosen:?}\n{s}"));
    let body = flipcard::text::render(map.body.get("en"));
    let first_word = phrase.split_whitespace().next().unwrap_or_default();
    assert!(
        body.contains(first_word),
        "{phrase:?} is not in the concept map"
    );
    let status = s
        .lines()
        .find(|l| l.contains(" 5/") && l.contains('→'))
        .unwrap_or_else(|| panic!("no status line naming the link:\n{s}"));
    let named = status
        .split('→')
        .nth(1)
        .map(|r| r.split("  ").next().unwrap_or_default().trim().to_string())
        .unwrap_or_default();
    // A title too long for the line ends with "…".
    let target = deck
        .sections
        .iter()
        .find(|sec| {
            let title = flipcard::text::render(sec.title.get("en"));
            match named.strip_suffix('…') {
                Some(start) => title.starts_with(start),
                None => title == named,
            }
        })
        .unwrap_or_else(|| panic!("the status line names no section: {named:?}"));
    // The chosen phrase links to that section in the deck's own text.
    let source = map.body.get("en");
    let anchor = format!("](#{})", target.id);
    assert!(
        source.contains(&anchor),
        "{named:?} is not linked from the map"
    );
    let before = &source[..source.find(&anchor).unwrap_or(0)];
    let link_text = before
        .rsplit('[')
        .next()
        .unwrap_or_default()
        .replace("**", "");
    assert_eq!(flipcard::text::render(&link_text), phrase.trim());

    t.keys(&["Enter"]);
    let words = |body: &str, n: usize| {
        flipcard::text::markup::plain(body)
            .split_whitespace()
            .take(n)
            .collect::<Vec<_>>()
            .join(" ")
    };
    let s = t.wait_for(&words(target.body.get("en"), 3));
    let heading = s.lines().nth(1).unwrap_or_default();
    let title = flipcard::text::render(target.title.get("en"));
    assert!(heading.contains(&title), "landed elsewhere:\n{s}");
    // Esc walks back to the concept map.
    t.keys(&["Escape"]);
    t.wait_for(&words(map.body.get("en"), 4));
}

/// `sync_dir` in the config: the other machine's answers are merged before
/// the app opens, and the answers of the session reach the folder when it
/// closes.
#[test]
fn sync_dir_syncs_when_the_app_opens_and_closes() {
    if !tmux_available() {
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    let folder = env.dir.path().join("Sync");
    std::fs::create_dir(&folder).unwrap();
    std::fs::write(env.dir.path().join("config.toml"), "sync_dir = \"Sync\"\n").unwrap();
    // The other machine answered the first card yesterday.
    let other = format!(
        "{{\"event\":\"review\",\"deck\":\"{DECK}\",\"card\":\"{}\",\"direction\":\"forward\",\
         \"reviewed_at\":\"2026-03-01T09:00:00.000Z\",\"rating\":3,\"cram\":false,\
         \"duration_ms\":1200,\"undone\":false}}\n",
        deck.cards[0].id
    );
    std::fs::write(
        folder.join("0123456789abcdef0123456789abcdef.jsonl"),
        &other,
    )
    .unwrap();

    let t = Tmux::start("sync", env.flipcard(), 100, 32);
    t.wait_for("last studied");
    let merged = env.export();
    assert_eq!(
        merged.as_array().map(Vec::len),
        Some(1),
        "merged at open: {merged}"
    );
    // One answer in the app, then quit.
    t.keys(&["Enter"]);
    t.wait_for("show answer");
    t.keys(&["Enter"]);
    t.wait_for("Again");
    t.keys(&["3", "q", "q"]);
    t.wait_for("EXIT=0");
    let id = std::fs::read_to_string(env.dir.path().join("data/machine-id")).unwrap();
    let mine = std::fs::read_to_string(folder.join(format!("{}.jsonl", id.trim()))).unwrap();
    assert_eq!(mine.lines().count(), 1, "{mine}");
    assert!(
        mine.contains("\"reviewed_at\":\"2026-03-02T09:00:00.000Z\""),
        "this session's answer: {mine}"
    );
}

/// A prediction is on disk the moment the learner commits, before its run
/// plays: the app killed with SIGKILL mid-run (no chance to write anything
/// more) leaves the attempt, without a verdict, for `export --attempts`.
#[test]
fn a_prediction_committed_survives_the_app_killed_mid_run() {
    if !tmux_available() {
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    let t = Tmux::start("killed", env.flipcard(), 100, 32);
    t.wait_for("last studied");
    select_deck(&t);
    let index = deck
        .prompts
        .iter()
        .position(|p| p.id == "middle-axis")
        .unwrap_or_else(|| panic!("no middle-axis prompt"));
    t.keys(&["p"]);
    t.wait_for(&opening(deck.prompts[0].question.get("en"), 3));
    for _ in 0..index {
        t.keys(&["j"]);
    }
    t.keys(&["Enter"]);
    t.wait_for(&opening(deck.prompts[index].question.get("en"), 4));
    // "Keeps spinning steadily", committed; the 8 s run starts at ×1.
    t.keys(&["1", "Enter"]);
    t.wait_for(" t = ");
    let child = app_pid(&t);
    let killed = Command::new("kill").args(["-KILL", &child]).status();
    assert!(killed.is_ok_and(|s| s.success()));
    let s = t.wait_for("EXIT=");
    assert!(s.contains("EXIT=137"), "killed by SIGKILL: {s}");
    assert!(
        !s.contains("Sahi") && !s.contains("Right"),
        "no verdict was reached: {s}"
    );
    let out = env
        .flipcard()
        .args(["export", "--attempts", "--format", "json"])
        .run();
    assert!(out.status.success(), "{}", out.stderr());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("not JSON ({e}): {}", out.stdout()));
    let rows = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    assert_eq!(rows.len(), 1, "{v}");
    assert_eq!(rows[0]["prompt"], "middle-axis");
    assert_eq!(rows[0]["prediction"], "stable");
    assert_eq!(rows[0]["attempted_at"], "2026-03-02T09:00:00.000Z");
    assert_eq!(
        rows[0]["correct"],
        serde_json::Value::Null,
        "no verdict: {v}"
    );
    assert_eq!(rows[0]["attempt"], 1);
    assert_eq!(rows[0]["retry"], false);
}

/// Opens prompt `id` of DECK from the home screen (the prompt list, down
/// to it, Enter), in English.
fn open_prompt(t: &Tmux, deck: &Deck, id: &str) {
    let index = deck
        .prompts
        .iter()
        .position(|p| p.id == id)
        .unwrap_or_else(|| panic!("no prompt {id}"));
    t.keys(&["p"]);
    t.wait_for(&opening(deck.prompts[0].question.get("en"), 3));
    for _ in 0..index {
        t.keys(&["j"]);
    }
    t.keys(&["Enter"]);
    t.wait_for(&opening(deck.prompts[index].question.get("en"), 4));
}

/// Issue 27 §2 in the real terminal: a wrong number that is a known slip
/// is told which formula it is and what that means; after a verdict, `e`
/// opens the explanation at the paragraph the prompt's anchor names, not
/// at the top of the section.
#[test]
fn a_known_slip_is_named_and_e_opens_the_anchored_paragraph() {
    if !tmux_available() {
        return;
    }
    let deck = bundled_deck();
    let env = Env::new();
    let t = Tmux::start("slip", env.flipcard(), 100, 32);
    t.wait_for("last studied");
    select_deck(&t);
    open_prompt(&t, &deck, "efold-time");
    t.keys(&["0", ".", "0", "3", "Enter", "+", "+", "+"]);
    let s = t.wait_for("✗ Wrong ✗");
    let prompt = deck.prompt("efold-time").unwrap();
    let Answer::Number { slips, .. } = &prompt.answer else {
        panic!("efold-time is a number prompt");
    };
    let slip = slips
        .iter()
        .find(|s| s.value == "1/k")
        .expect("the 1/k slip");
    assert!(s.contains("your number is 1/k = 0.0300 s:"), "{s}");
    assert!(s.contains(&opening(slip.says.get("en"), 5)), "{s}");

    // Back to the list and home, then a prompt whose explanation has an
    // anchor.
    t.keys(&["Escape", "Escape"]);
    t.wait_for("last studied");
    let id = "wobble-frequency";
    let explain = deck.prompt(id).unwrap().explain.clone().unwrap();
    let anchor = explain.anchor.clone().expect("an anchored explanation");
    open_prompt(&t, &deck, id);
    t.keys(&["1", "0", "Enter", "+", "+", "+"]);
    t.wait_for("✓ Right ✓");
    t.keys(&["e"]);
    let section = deck.section(&explain.section).unwrap();
    let body = section.body.get("en");
    let marker = format!("{{#{anchor}}}");
    let after = body
        .lines()
        .skip_while(|l| l.trim() != marker)
        .nth(1)
        .unwrap_or_else(|| panic!("no {marker} in {}", explain.section));
    let anchored = opening(after, 3).replace('*', "");
    let s = t.wait_for(&anchored);
    // The section's opening paragraph is scrolled away above it.
    let top = opening(body.lines().next().unwrap_or(""), 4);
    assert!(!s.contains(&top), "{top:?} still shown:\n{s}");
    t.keys(&["Escape"]);
    t.wait_for("✓ Right ✓");
    t.keys(&["q"]);
}

/// `F` in the reader opens the deck's formula sheet: the first place that
/// writes a formula is its first heading, with its first formula; `l`
/// turns the sheet into Hinglish, and Esc goes back to the reader.
#[test]
fn f_opens_the_formula_sheet_in_both_languages_and_esc_goes_back() {
    if !tmux_available() {
        return;
    }
    use flipcard::tui::screens::formulas;
    let deck = bundled_deck();
    let (en, hi) = (
        formulas::groups(&deck, "en"),
        formulas::groups(&deck, "hi-Latn"),
    );
    let squash = |s: &str| s.split_whitespace().collect::<String>();
    let env = Env::new();
    let t = Tmux::start("sheet", env.flipcard(), 100, 30);
    t.wait_for("last studied");
    select_deck(&t);
    t.keys(&["r"]);
    t.wait_for("spinning with no torque");
    t.keys(&["F"]);
    let s = t.wait_for("Formula sheet");
    assert!(
        s.contains(&format!("Card · {}", opening(&en[0].heading, 3))),
        "{s}"
    );
    assert!(squash(&s).contains(&squash(&en[0].formulas[0])), "{s}");
    t.keys(&["l"]);
    let s = t.wait_for(&format!("Card · {}", opening(&hi[0].heading, 3)));
    assert!(squash(&s).contains(&squash(&hi[0].formulas[0])), "{s}");
    t.keys(&["Escape"]);
    t.wait_for("Bada picture");
    let s = t.screen();
    assert!(!s.contains("Formula sheet"), "{s}");
    t.keys(&["q", "q"]);
}

/// A derivation as a learner walks it (issue 24 §5), in the release binary:
/// the first day a worked example stepped through with Space and rated; a
/// day later (the app's clock, `FLIPCARD_NOW`) its last step faded, the
/// learner types the formula with the wrong sign, sees the slip named and
/// the math revealed, and takes the suggested rating; `flipcard export`
/// shows both ratings under the direction `derive`.
#[test]
fn a_derivation_is_worked_then_faded_and_checked_in_a_terminal() {
    if !tmux_available() {
        return;
    }
    let data = tempfile::tempdir().unwrap();
    let decks = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/decks/derive/decks");
    let app = |now: &str| {
        Flipcard::new(data.path())
            .now(now)
            .decks(decks)
            .args(["review", "derive"])
    };
    let t = Tmux::start("derive1", app("2026-03-02T09:00:00Z"), 100, 30);
    // The card first, then the derivation, a worked example.
    t.wait_for("Which axis is unstable?");
    t.keys(&["Space"]);
    t.wait_for("Again");
    t.keys(&["3"]);
    let s = t.wait_for("Worked example");
    assert!(s.contains("why: The transport theorem."), "{s}");
    t.keys(&["Space"]);
    t.wait_for("why: Cross product by components.");
    t.keys(&["Space"]);
    let s = t.wait_for("why: Set the torque to zero.");
    assert!(!s.contains("your step"), "{s}");
    t.keys(&["3"]);
    // Both items are learning now (the card comes back within the
    // learn-ahead time).
    t.wait_for("2 learning");
    t.keys(&["q"]);
    std::thread::sleep(Duration::from_millis(300));
    t.keys(&["q"]);
    t.wait_for("EXIT=0");
    drop(t);

    let t = Tmux::start("derive2", app("2026-03-03T09:00:00Z"), 100, 30);
    t.wait_for("Which axis is unstable?");
    t.keys(&["Space"]);
    t.wait_for("Again");
    t.keys(&["3"]);
    t.wait_for("steps to supply: 1 of 3");
    t.keys(&["Space"]);
    let s = t.wait_for("[ your step ]");
    assert!(s.contains("hint: Set the torque to zero."), "{s}");
    assert!(!s.contains("I₁ω̇₁ = (I₂ − I₃)"), "the math is hidden:\n{s}");
    for c in "(I3-I2)*w2*w3/I1".chars() {
        t.keys(&[&c.to_string()]);
    }
    t.keys(&["Enter"]);
    let s = t.wait_for("not quite");
    assert!(s.contains("the sign is wrong"), "{s}");
    assert!(s.contains("I₁ω̇₁ = (I₂ − I₃) ω₂ω₃"), "revealed:\n{s}");
    assert!(s.contains("suggested: Hard"), "{s}");
    t.keys(&["Enter"]);
    // Hard keeps it learning: shown again within the learn-ahead time,
    // now with two steps faded (Good and Hard are two successes).
    t.wait_for("steps to supply: 2 of 3");
    t.keys(&["q"]);
    std::thread::sleep(Duration::from_millis(300));
    t.keys(&["q"]);
    t.wait_for("EXIT=0");
    drop(t);

    let out = Flipcard::new(data.path())
        .now("2026-03-03T10:00:00Z")
        .decks(decks)
        .args(["export", "--reviews", "--format", "csv"])
        .run();
    let text = out.stdout();
    let derive: Vec<&str> = text
        .lines()
        .filter(|l| l.contains(",euler,derive,"))
        .collect();
    assert_eq!(derive.len(), 2, "{text}");
}
