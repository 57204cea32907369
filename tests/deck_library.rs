//! The deck library through the real binary: sources in order (bundled,
//! library, config `deck_paths`, `--decks`), a deck id found twice named
//! with both files, `decks add` refusing what `check` refuses, `decks
//! remove` keeping the history, and a broken deck hiding nothing else.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::store_support::{at, key, review};
use chrono::Duration;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::Store;

const BUNDLED: &str = "torque-free-rotation";

fn flipcard(root: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flipcard"))
        .args(args)
        .current_dir(root)
        .env("FLIPCARD_DATA_DIR", root.join("data"))
        .env("FLIPCARD_CONFIG", root.join("config.toml"))
        .env("FLIPCARD_NOW", "2026-05-10T12:00:00Z")
        .env("TZ", "UTC")
        .env_remove("FLIPCARD_DECKS")
        .output()
        .expect("run flipcard")
}

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A deck folder `root/decks/ID.toml` with `content/ID/en.toml`.
fn deck(root: &Path, id: &str, cards: &[&str]) -> PathBuf {
    let decks = root.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    std::fs::create_dir_all(root.join("content").join(id)).unwrap();
    std::fs::write(root.join("content").join(id).join("en.toml"), "").unwrap();
    let mut toml =
        format!("[deck]\nid = '{id}'\ntitle = {{ en = 'Deck {id}' }}\nlanguages = ['en']\n");
    for c in cards {
        toml.push_str(&format!(
            "\n[[card]]\nid = '{c}'\nkind = 'basic'\nfront = {{ en = 'Front {c}' }}\nback = {{ en = 'Back {c}' }}\ntags = ['t-{id}']\n"
        ));
    }
    let file = decks.join(format!("{id}.toml"));
    std::fs::write(&file, toml).unwrap();
    file
}

/// The `decks` row of deck `id`.
fn row(listing: &str, id: &str) -> String {
    listing
        .lines()
        .find(|l| l.split_whitespace().next() == Some(id))
        .unwrap_or_else(|| panic!("no row for {id} in\n{listing}"))
        .to_string()
}

#[test]
fn every_source_is_listed_in_order_with_counts_and_status() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    deck(&root.join("cfg"), "from-config", &["a", "b"]);
    deck(&root.join("cli"), "from-cli", &["a"]);
    std::fs::write(root.join("config.toml"), "deck_paths = ['cfg/decks']\n").unwrap();
    let o = flipcard(root, &["decks", "add", "cli"]);
    assert!(o.status.success(), "{}", err(&o));
    deck(&root.join("cli2"), "only-cli", &["x"]);

    let o = flipcard(root, &["decks", "--decks", "cli2/decks"]);
    assert!(o.status.success(), "{}", err(&o));
    let listing = out(&o);
    let ids: Vec<&str> = listing
        .lines()
        .skip(1)
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let mut expected: Vec<String> = flipcard::deck::bundled::load()
        .decks
        .iter()
        .map(|d| d.id.clone())
        .collect();
    expected.extend(["from-cli", "from-config", "only-cli"].map(String::from));
    assert_eq!(ids, expected, "{listing}");
    assert!(row(&listing, BUNDLED).contains(" bundled "), "{listing}");
    assert!(row(&listing, "from-cli").contains(" library "), "{listing}");
    assert!(
        row(&listing, "from-config").contains(" config "),
        "{listing}"
    );
    assert!(
        row(&listing, "from-config").contains("2 cards, 0 prompts"),
        "{listing}"
    );
    assert!(row(&listing, "only-cli").contains(" --decks "), "{listing}");
    assert!(
        row(&listing, "only-cli").trim_end().ends_with("ok"),
        "{listing}"
    );

    // Every command sees the same decks.
    let o = flipcard(
        root,
        &["--decks", "cli2/decks", "export", "--deck", "from-config"],
    );
    assert!(o.status.success(), "{}", err(&o));
    let o = flipcard(root, &["--decks", "cli2/decks", "check"]);
    assert!(o.status.success(), "{}", err(&o));
    let decks = flipcard::deck::bundled::load().decks.len() + 3;
    assert!(
        out(&o).starts_with(&format!("{decks} decks, ")),
        "{}",
        out(&o)
    );
}

#[test]
fn a_deck_id_found_twice_names_both_files() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let first = deck(&root.join("one"), "twin", &["a"]);
    let second = deck(&root.join("two"), "twin", &["b"]);
    let o = flipcard(
        root,
        &["--decks", "one/decks", "--decks", "two/decks", "check"],
    );
    assert_eq!(o.status.code(), Some(1));
    let e = err(&o);
    let line = e
        .lines()
        .find(|l| l.contains("deck id `twin` is also used by"))
        .unwrap_or_else(|| panic!("{e}"));
    let rel = |p: &Path| p.strip_prefix(root).unwrap().display().to_string();
    assert!(line.starts_with(&format!("{}:", rel(&second))), "{line}");
    assert!(line.ends_with(&rel(&first)), "{line}");

    // A deck with a bundled id is refused by `decks add`, naming both.
    deck(&root.join("clash"), BUNDLED, &["a"]);
    let o = flipcard(root, &["decks", "add", "clash"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err(&o).contains(&format!("is also used by decks/{BUNDLED}.toml (bundled)")),
        "{}",
        err(&o)
    );
    assert!(
        !root
            .join("data/decks")
            .join(format!("{BUNDLED}.toml"))
            .exists()
    );
}

#[test]
fn add_refuses_what_check_refuses_and_copies_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let file = deck(&root.join("src"), "bad", &["a"]);
    let broken = std::fs::read_to_string(&file)
        .unwrap()
        .replace("kind = 'basic'", "kind = 'basik'");
    std::fs::write(&file, broken).unwrap();
    let o = flipcard(root, &["decks", "add", "src"]);
    assert_eq!(o.status.code(), Some(1));
    let e = err(&o);
    assert!(e.contains("src/decks/bad.toml:"), "the diagnostics: {e}");
    assert!(e.contains("does not pass `check`"), "{e}");
    assert!(!root.join("data/decks/bad.toml").exists());
    assert!(!root.join("data/content/bad").exists());

    let o = flipcard(root, &["decks", "add", "nowhere"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err(&o).contains("nowhere: no such file or directory"),
        "{}",
        err(&o)
    );
}

#[test]
fn remove_keeps_the_history_which_returns_with_the_deck() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    deck(&root.join("src"), "mine", &["a", "b"]);
    // Adding the deck file itself works as well as its folder.
    let o = flipcard(root, &["decks", "add", "src/decks/mine.toml"]);
    assert!(o.status.success(), "{}", err(&o));
    assert!(out(&o).contains("added mine (2 cards"), "{}", out(&o));
    assert!(root.join("data/content/mine/en.toml").is_file());
    {
        let mut store = Store::open(&root.join("data")).unwrap();
        store
            .record(&review(
                &key("mine", "a"),
                at("2026-05-09T08:00:00Z"),
                Rating::Good,
                ReviewKind::Learn,
                State::Review,
                Duration::days(3),
            ))
            .unwrap();
    }
    let stats = |root: &Path| {
        let o = flipcard(root, &["stats", "--json"]);
        assert!(o.status.success(), "{}", err(&o));
        serde_json::from_str::<serde_json::Value>(&out(&o)).unwrap()
    };
    assert_eq!(stats(root)["orphans"].as_array().unwrap().len(), 0);

    let o = flipcard(root, &["decks", "remove", "mine"]);
    assert!(o.status.success(), "{}", err(&o));
    assert!(!root.join("data/decks/mine.toml").exists());
    assert!(!root.join("data/content/mine").exists());
    let s = stats(root);
    assert_eq!(s["orphans"][0]["card"], "a", "{s}");

    let o = flipcard(root, &["decks", "add", "src"]);
    assert!(o.status.success(), "{}", err(&o));
    assert_eq!(stats(root)["orphans"].as_array().unwrap().len(), 0);

    // Only library decks can be removed; unknown ids are named.
    let o = flipcard(root, &["decks", "remove", BUNDLED]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err(&o).contains("only library decks can be removed"),
        "{}",
        err(&o)
    );
    let o = flipcard(root, &["decks", "remove", "nope"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(err(&o).contains("library decks: mine"), "{}", err(&o));
}

#[test]
fn a_broken_deck_hides_no_other() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    deck(&root.join("mixed"), "good", &["a"]);
    std::fs::write(
        root.join("mixed/decks/broken.toml"),
        "[deck\nid = 'broken'\n",
    )
    .unwrap();
    let o = flipcard(root, &["--decks", "mixed/decks", "decks"]);
    assert!(o.status.success(), "{}", err(&o));
    let listing = out(&o);
    assert!(
        row(&listing, "good").trim_end().ends_with("ok"),
        "{listing}"
    );
    assert!(
        row(&listing, BUNDLED).trim_end().ends_with("ok"),
        "{listing}"
    );
    assert!(
        row(&listing, "broken").contains("run `flipcard check mixed/decks/broken.toml`"),
        "{listing}"
    );
    let o = flipcard(root, &["--decks", "mixed/decks", "sim", "--list"]);
    assert!(o.status.success(), "{}", err(&o));
    assert!(out(&o).contains(BUNDLED), "{}", out(&o));
    let o = flipcard(
        root,
        &["--decks", "mixed/decks", "export", "--deck", "good"],
    );
    assert!(o.status.success(), "{}", err(&o));
    assert!(
        err(&o).contains("mixed/decks/broken.toml"),
        "named: {}",
        err(&o)
    );
    assert!(
        err(&o).contains("flipcard decks"),
        "how to see why: {}",
        err(&o)
    );
}
