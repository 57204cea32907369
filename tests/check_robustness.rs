//! Whatever the bytes, `flipcard check` reports and exits 1; it never
//! panics, never floods the terminal.

use std::fs;
use std::path::Path;

use crate::support::Flipcard;

const CONTENT: &str = "[[section]]\nid = \"s\"\ntitle = 'T'\nbody = 'B'\n";

/// Writes `deck` as decks/d.toml (with a valid English content file) and
/// runs the check; returns (exit code, stderr).
fn check_bytes(deck: &[u8], content: &[u8]) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "decks/d.toml", deck);
    write(dir.path(), "content/d/en.toml", content);
    let out = Flipcard::without_data()
        .current_dir(dir.path())
        .args(["check", "decks"])
        .run();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write(root: &Path, rel: &str, bytes: &[u8]) {
    let path = root.join(rel);
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    fs::write(path, bytes).unwrap();
}

/// Exit 1, a positioned error in `file`, no panic, bounded output.
fn assert_reported(name: &str, (code, stderr): (i32, String), file: &str) {
    assert_eq!(code, 1, "{name}: exit code\n{stderr}");
    assert!(!stderr.contains("panicked"), "{name}: {stderr}");
    let head = stderr
        .lines()
        .find(|l| l.starts_with(&format!("{file}:")) && l.contains(": error: "))
        .unwrap_or_else(|| panic!("{name}: no error in {file}\n{stderr}"));
    let mut parts = head.splitn(4, ':');
    parts.next();
    let line: usize = parts.next().unwrap().parse().unwrap();
    let col: usize = parts.next().unwrap().parse().unwrap();
    assert!(line >= 1 && col >= 1, "{name}: {head}");
    assert!(
        stderr.len() < 20_000,
        "{name}: {} bytes of output",
        stderr.len()
    );
}

fn valid_deck() -> String {
    "[deck]\nid = \"d\"\ntitle = 'D'\nlanguages = [\"en\"]\n\n[[card]]\nid = \"c\"\nfront = 'F'\nback = 'B'\n"
        .to_string()
}

/// Deterministic noise.
fn garbage(len: usize) -> Vec<u8> {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 24) as u8
        })
        .collect()
}

#[test]
fn the_valid_base_deck_passes() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "decks/d.toml", valid_deck().as_bytes());
    write(dir.path(), "content/d/en.toml", CONTENT.as_bytes());
    let out = Flipcard::without_data()
        .current_dir(dir.path())
        .args(["check", "decks"])
        .run();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "1 deck, 1 card, 0 prompts, 0 scenes, 1 section: ok\n"
    );
}

#[test]
fn empty_and_whitespace_files() {
    assert_reported(
        "empty",
        check_bytes(b"", CONTENT.as_bytes()),
        "decks/d.toml",
    );
    assert_reported(
        "blank",
        check_bytes(b"\n\n  \t\n", CONTENT.as_bytes()),
        "decks/d.toml",
    );
}

#[test]
fn binary_garbage() {
    for len in [1, 7, 100, 65_536] {
        assert_reported(
            &format!("garbage {len}"),
            check_bytes(&garbage(len), CONTENT.as_bytes()),
            "decks/d.toml",
        );
    }
    let nul = format!("{}\0\0\0", valid_deck());
    assert_reported(
        "nul",
        check_bytes(nul.as_bytes(), CONTENT.as_bytes()),
        "decks/d.toml",
    );
}

#[test]
fn invalid_utf8_is_located() {
    let mut deck = valid_deck().into_bytes();
    let at = deck.len() - 3;
    deck[at] = 0xC3; // a lead byte with no continuation
    let (code, stderr) = check_bytes(&deck, CONTENT.as_bytes());
    assert!(
        stderr.contains("decks/d.toml:9:9: error: not valid UTF-8"),
        "{stderr}"
    );
    assert_reported("utf8", (code, stderr), "decks/d.toml");
}

#[test]
fn garbage_content_file() {
    assert_reported(
        "content garbage",
        check_bytes(valid_deck().as_bytes(), &garbage(4096)),
        "content/d/en.toml",
    );
}

#[test]
fn ten_megabyte_lines() {
    let long = "x".repeat(10 * 1024 * 1024);
    // A long but well-formed string, with a problem after it.
    let deck = format!("{}tags = ['{long}', '']\n", valid_deck());
    assert_reported(
        "long string",
        check_bytes(deck.as_bytes(), CONTENT.as_bytes()),
        "decks/d.toml",
    );
    // A long syntax error.
    let deck = format!("{}oops = {long}\n", valid_deck());
    assert_reported(
        "long junk",
        check_bytes(deck.as_bytes(), CONTENT.as_bytes()),
        "decks/d.toml",
    );
}

#[test]
fn deeply_nested_values() {
    let n = 100_000;
    let closed = format!("a = {}{}\n", "[".repeat(n), "]".repeat(n));
    let open = format!("a = {}\n", "[".repeat(n));
    let tables = format!("a = {}1{}\n", "{b = ".repeat(n), "}".repeat(n));
    let in_card = format!(
        "{}tags = {}{}\n",
        valid_deck(),
        "[".repeat(n),
        "]".repeat(n)
    );
    for (name, deck) in [
        ("closed arrays", closed),
        ("open arrays", open),
        ("inline tables", tables),
        ("in a card", in_card),
    ] {
        assert_reported(
            name,
            check_bytes(deck.as_bytes(), CONTENT.as_bytes()),
            "decks/d.toml",
        );
    }
}

#[test]
fn many_problems_are_all_reported() {
    let mut deck = valid_deck();
    for i in 0..500 {
        deck.push_str(&format!(
            "\n[[card]]\nid = \"c{i}\"\nfront = 'F'\nbak = 'B'\n"
        ));
    }
    let (code, stderr) = check_bytes(deck.as_bytes(), CONTENT.as_bytes());
    assert_eq!(code, 1);
    // Each card: an unknown field and a missing one.
    assert_eq!(stderr.lines().last(), Some("1000 errors, 0 warnings"));
    assert_eq!(stderr.matches("did you mean `back`?").count(), 500);
}
