//! A large deck through the real binary: the deck cache (`deck::cache`)
//! gives the same cards as the TOML, follows every change of the deck
//! file and its content files, and survives a damaged entry; the reading
//! in parts (`deck::chunked`) reports an error at the same line as the
//! whole-file reading.

use std::path::{Path, PathBuf};

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-05-10T12:00:00Z";

/// A deck of `n` cards, each with its own front, in `root/decks/big.toml`
/// with its empty content file; returns the deck folder.
fn write_deck(root: &Path, n: usize, front: impl Fn(usize) -> String) -> PathBuf {
    let decks = root.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    std::fs::create_dir_all(root.join("content/big")).unwrap();
    std::fs::write(root.join("content/big/en.toml"), "").unwrap();
    let mut s = String::from("[deck]\nid = \"big\"\ntitle = \"Big\"\nlanguages = [\"en\"]\n\n");
    for i in 0..n {
        let kind = if i % 7 == 0 {
            "kind = \"reversed\"\n"
        } else {
            ""
        };
        s.push_str(&format!(
            "[[card]]\nid = \"c{i}\"\n{kind}tags = [\"t::{}\"]\nfront.en = '''{}'''\nback.en = '''The answer to card {i}, with $x^2$.'''\n\n",
            i % 5,
            front(i)
        ));
    }
    std::fs::write(decks.join("big.toml"), s).unwrap();
    decks
}

fn list(data: &Path, decks: &Path) -> Output {
    Flipcard::new(data)
        .now(NOW)
        .decks(decks)
        .args(["cards", "list", "deck:big", "--format", "csv"])
        .run()
}

fn entries(data: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(data.join("cache/decks"))
        .map(|d| d.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default()
}

#[test]
fn a_cached_deck_lists_the_same_cards_and_follows_every_change() {
    let root = tempfile::tempdir().unwrap();
    let data = root.path().join("data");
    let decks = write_deck(root.path(), 800, |i| format!("What is card {i}?"));

    let first = list(&data, &decks);
    assert!(first.status.success(), "{}", first.stderr());
    assert_eq!(entries(&data).len(), 1, "a clean large deck is cached");
    assert!(first.stdout().contains("What is card 799?"));
    let reversed = (0..800).filter(|i| i % 7 == 0).count();
    assert_eq!(first.stdout().lines().count(), 1 + 800 + reversed);

    // From the cache: the same rows.
    let again = list(&data, &decks);
    assert_eq!(again.stdout(), first.stdout());

    // A changed card is seen, and the old entry replaced.
    write_deck(root.path(), 800, |i| {
        if i == 10 {
            "Edited front".to_string()
        } else {
            format!("What is card {i}?")
        }
    });
    let edited = list(&data, &decks);
    assert!(
        edited.stdout().contains("Edited front"),
        "{}",
        edited.stdout()
    );
    assert!(!edited.stdout().contains("What is card 10?"));
    assert_eq!(entries(&data).len(), 1);

    // A damaged entry is a miss: the deck is read from its TOML again.
    let entry = entries(&data).remove(0);
    let mut bytes = std::fs::read(&entry).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x55;
    std::fs::write(&entry, &bytes).unwrap();
    let damaged = list(&data, &decks);
    assert!(damaged.status.success(), "{}", damaged.stderr());
    assert_eq!(damaged.stdout(), edited.stdout());

    // A content file that gains a section: the deck is read again (and,
    // holding a section now, no longer cached).
    std::fs::write(
        root.path().join("content/big/en.toml"),
        "[[section]]\nid = \"s\"\ntitle = 'S'\nbody = '''Body.'''\n",
    )
    .unwrap();
    for e in entries(&data) {
        std::fs::remove_file(e).unwrap();
    }
    let with_section = list(&data, &decks);
    assert!(with_section.status.success(), "{}", with_section.stderr());
    assert!(entries(&data).is_empty());
}

#[test]
fn a_deck_with_errors_is_never_cached_and_check_never_reads_the_cache() {
    let root = tempfile::tempdir().unwrap();
    let data = root.path().join("data");
    let decks = write_deck(root.path(), 800, |i| format!("Card {i}"));
    assert!(list(&data, &decks).status.success());
    assert_eq!(entries(&data).len(), 1);

    // Card 400 loses its front: `check` reports it at its line although
    // the old deck is in the cache, and nothing new is cached.
    let file = decks.join("big.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let broken = text.replace("front.en = '''Card 400'''\n", "");
    std::fs::write(&file, &broken).unwrap();
    let line = broken.lines().position(|l| l == "id = \"c400\"").unwrap();
    let o = Flipcard::new(&data)
        .now(NOW)
        .args(["check", file.to_str().unwrap()])
        .run();
    assert_eq!(o.status.code(), Some(1), "{}", o.stdout());
    let err = o.stderr();
    assert!(
        err.contains(&format!("big.toml:{}:", line)) && err.contains("front"),
        "{err}"
    );
    let listed = list(&data, &decks);
    assert!(
        !listed.stdout().contains("Card 401"),
        "the deck is left out"
    );
    assert_eq!(entries(&data).len(), 1, "the old entry only");
}

#[test]
fn a_large_file_with_an_error_reports_it_as_a_small_one_does() {
    // Over a megabyte: read in parts; a duplicate key in the last card is
    // one syntax error at its line, as the whole-file reading gives.
    let root = tempfile::tempdir().unwrap();
    let decks = write_deck(root.path(), 9000, |i| format!("Card number {i}"));
    let file = decks.join("big.toml");
    let mut text = std::fs::read_to_string(&file).unwrap();
    assert!(text.len() > 1 << 20);
    text.push_str("[[card]]\nid = \"last\"\nfront.en = 'a'\nfront.en = 'b'\nback.en = 'c'\n");
    std::fs::write(&file, &text).unwrap();
    // The clash is reported at the key's first definition.
    let line = text.lines().count() - 2;
    let o = Flipcard::new(root.path().join("data"))
        .now(NOW)
        .args(["check", file.to_str().unwrap()])
        .run();
    assert_eq!(o.status.code(), Some(1));
    assert!(
        o.stderr().contains(&format!("big.toml:{line}:")),
        "{}",
        o.stderr()
    );
    assert!(o.stderr().contains("1 error,"), "{}", o.stderr());
}
