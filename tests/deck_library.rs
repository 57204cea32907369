//! The deck library through the real binary: sources in order (bundled,
//! library, config `deck_paths`, `--decks`), a deck id found twice named
//! with both files, `decks add` refusing what `check` refuses, `decks
//! remove` keeping the history, and a broken deck hiding nothing else.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::store_support::{at, key, review};
use crate::support::{Flipcard, Output};
use chrono::Duration;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::Store;

const BUNDLED: &str = "torque-free-rotation";

fn flipcard(root: &Path, args: &[&str]) -> Output {
    in_root(root).args(args).run()
}

/// flipcard run in `root`, with its data, config and decks there.
fn in_root(root: &Path) -> Flipcard {
    Flipcard::new(root.join("data"))
        .config(root.join("config.toml"))
        .now("2026-05-10T12:00:00Z")
        .current_dir(root)
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
    assert!(o.status.success(), "{}", o.stderr());
    deck(&root.join("cli2"), "only-cli", &["x"]);

    let o = flipcard(root, &["decks", "--decks", "cli2/decks"]);
    assert!(o.status.success(), "{}", o.stderr());
    let listing = o.stdout();
    let ids: Vec<&str> = listing
        .lines()
        .skip(1)
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let mut expected: Vec<String> = flipcard::bundled::load()
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
    assert!(o.status.success(), "{}", o.stderr());
    let o = flipcard(root, &["--decks", "cli2/decks", "check"]);
    assert!(o.status.success(), "{}", o.stderr());
    let decks = flipcard::bundled::load().decks.len() + 3;
    assert!(
        o.stdout().starts_with(&format!("{decks} decks, ")),
        "{}",
        o.stdout()
    );
}

#[test]
fn hide_bundled_marks_the_bundled_decks_in_the_listing() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    deck(&root.join("cfg"), "mine", &["a"]);
    std::fs::write(
        root.join("config.toml"),
        "deck_paths = ['cfg/decks']
hide_bundled = true
",
    )
    .unwrap();
    let o = flipcard(root, &["decks"]);
    assert!(o.status.success(), "{}", o.stderr());
    let listing = o.stdout();
    assert!(
        row(&listing, BUNDLED).contains(" bundled (hidden) "),
        "{listing}"
    );
    assert!(row(&listing, "mine").contains(" config "), "{listing}");
    assert!(!row(&listing, "mine").contains("hidden"), "{listing}");
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
    let e = o.stderr();
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
        o.stderr()
            .contains(&format!("is also used by decks/{BUNDLED}.toml (bundled)")),
        "{}",
        o.stderr()
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
    let e = o.stderr();
    assert!(e.contains("src/decks/bad.toml:"), "the diagnostics: {e}");
    assert!(e.contains("does not pass `check`"), "{e}");
    assert!(!root.join("data/decks/bad.toml").exists());
    assert!(!root.join("data/content/bad").exists());

    let o = flipcard(root, &["decks", "add", "nowhere"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        o.stderr().contains("nowhere: no such file or directory"),
        "{}",
        o.stderr()
    );
}

#[test]
fn remove_keeps_the_history_which_returns_with_the_deck() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    deck(&root.join("src"), "mine", &["a", "b"]);
    // Adding the deck file itself works as well as its folder.
    let o = flipcard(root, &["decks", "add", "src/decks/mine.toml"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert!(o.stdout().contains("added mine (2 cards"), "{}", o.stdout());
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
        assert!(o.status.success(), "{}", o.stderr());
        serde_json::from_str::<serde_json::Value>(&o.stdout()).unwrap()
    };
    assert_eq!(stats(root)["orphans"].as_array().unwrap().len(), 0);

    let o = flipcard(root, &["decks", "remove", "mine"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert!(!root.join("data/decks/mine.toml").exists());
    assert!(!root.join("data/content/mine").exists());
    let s = stats(root);
    assert_eq!(s["orphans"][0]["card"], "a", "{s}");

    let o = flipcard(root, &["decks", "add", "src"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert_eq!(stats(root)["orphans"].as_array().unwrap().len(), 0);

    // Only library decks can be removed; unknown ids are named.
    let o = flipcard(root, &["decks", "remove", BUNDLED]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        o.stderr().contains("only library decks can be removed"),
        "{}",
        o.stderr()
    );
    let o = flipcard(root, &["decks", "remove", "nope"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(o.stderr().contains("library decks: mine"), "{}", o.stderr());
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
    assert!(o.status.success(), "{}", o.stderr());
    let listing = o.stdout();
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
    assert!(o.status.success(), "{}", o.stderr());
    assert!(o.stdout().contains(BUNDLED), "{}", o.stdout());
    let o = flipcard(
        root,
        &["--decks", "mixed/decks", "export", "--deck", "good"],
    );
    assert!(o.status.success(), "{}", o.stderr());
    assert!(
        o.stderr().contains("mixed/decks/broken.toml"),
        "named: {}",
        o.stderr()
    );
    assert!(
        o.stderr().contains("flipcard decks"),
        "how to see why: {}",
        o.stderr()
    );
}

/// `flipcard ARGS`, killed and failed if it has not ended in 30 s (a FIFO
/// that is opened blocks forever).
fn flipcard_within(root: &Path, args: &[&str]) -> Output {
    in_root(root).args(args).run_within(30)
}

/// Exit 1 with one line on stderr that contains `what`.
fn refused(o: &Output, what: &str) {
    assert_eq!(o.status.code(), Some(1), "{}", o.stderr());
    let e = o.stderr();
    assert_eq!(e.lines().count(), 1, "one line: {e}");
    assert!(e.contains(what), "{what}: {e}");
}

/// A library with deck `mine`, and beside the data dir a folder `outside`
/// holding `X.toml` and a folder `X` (with a file), and `mine.toml` and a
/// folder `mine` (what a link may lead to).
fn library_and_outside(root: &Path) {
    deck(&root.join("src"), "mine", &["a"]);
    let o = flipcard(root, &["decks", "add", "src"]);
    assert!(o.status.success(), "{}", o.stderr());
    let outside = root.join("outside");
    for name in ["X", "mine"] {
        std::fs::create_dir_all(outside.join(name)).unwrap();
        std::fs::write(outside.join(name).join("en.toml"), "# keep\n").unwrap();
        std::fs::write(outside.join(format!("{name}.toml")), "# keep\n").unwrap();
    }
}

/// Every file under `root/outside` is as `library_and_outside` made it.
fn outside_intact(root: &Path) {
    let outside = root.join("outside");
    for name in ["X", "mine"] {
        for file in [
            outside.join(name).join("en.toml"),
            outside.join(format!("{name}.toml")),
        ] {
            assert_eq!(
                std::fs::read_to_string(&file).ok().as_deref(),
                Some("# keep\n"),
                "{} was touched",
                file.display()
            );
        }
    }
}

#[test]
fn remove_takes_a_deck_id_never_a_path() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    library_and_outside(root);
    let abs = root.join("outside/X").display().to_string();
    for arg in [
        abs.as_str(),
        "../../outside/X",
        "../content/mine",
        "..",
        "",
        "Mine",
        "mine/",
    ] {
        let o = flipcard_within(root, &["decks", "remove", arg]);
        refused(&o, "is not a deck id");
        assert!(o.stderr().contains("nothing removed"), "{}", o.stderr());
        outside_intact(root);
        assert!(root.join("data/decks/mine.toml").is_file(), "{arg}");
        assert!(root.join("data/content/mine/en.toml").is_file(), "{arg}");
    }
    // A bundled deck is not the library's: said so, nothing touched.
    let o = flipcard_within(root, &["decks", "remove", BUNDLED]);
    refused(&o, "is not in the library but in");
    assert!(o.stderr().contains("(bundled)"), "{}", o.stderr());
    // An id that is not installed is named, with what is.
    let o = flipcard_within(root, &["decks", "remove", "nope"]);
    refused(&o, "no deck `nope` in the library; library decks: mine");
    outside_intact(root);
}

#[cfg(unix)]
#[test]
fn remove_never_follows_a_link_out_of_the_library() {
    use std::os::unix::fs::symlink;
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    library_and_outside(root);
    let data = root.join("data");
    // A deck file and a content folder that are links: the links go,
    // what they lead to stays.
    symlink(root.join("outside/X.toml"), data.join("decks/linked.toml")).unwrap();
    symlink(root.join("outside/X"), data.join("content/linked")).unwrap();
    let o = flipcard_within(root, &["decks", "remove", "linked"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert!(std::fs::symlink_metadata(data.join("decks/linked.toml")).is_err());
    assert!(std::fs::symlink_metadata(data.join("content/linked")).is_err());
    outside_intact(root);

    // The content folder of the library a link to a folder outside: the
    // remove is refused before anything moves.
    std::fs::rename(data.join("content"), root.join("content-real")).unwrap();
    std::fs::create_dir_all(root.join("outside2/mine")).unwrap();
    std::fs::write(root.join("outside2/mine/en.toml"), "# keep\n").unwrap();
    symlink(root.join("outside2"), data.join("content")).unwrap();
    let o = flipcard_within(root, &["decks", "remove", "mine"]);
    refused(&o, "is a symbolic link");
    assert!(root.join("outside2/mine/en.toml").is_file());
    assert!(data.join("decks/mine.toml").is_file(), "nothing removed");
    std::fs::remove_file(data.join("content")).unwrap();
    std::fs::rename(root.join("content-real"), data.join("content")).unwrap();

    // So is the library folder itself a link.
    std::fs::rename(data.join("decks"), root.join("decks-real")).unwrap();
    symlink(root.join("decks-real"), data.join("decks")).unwrap();
    let o = flipcard_within(root, &["decks", "remove", "mine"]);
    refused(&o, "is a symbolic link");
    assert!(root.join("decks-real/mine.toml").is_file());
    outside_intact(root);
}

#[cfg(unix)]
#[test]
fn add_never_follows_a_link_or_waits_on_a_fifo_in_the_library() {
    use std::os::unix::fs::symlink;
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    library_and_outside(root);
    let data = root.join("data");
    deck(&root.join("v2"), "mine", &["a", "b"]);

    // Links where the deck's file and content folder are: replaced by
    // the new deck, what they lead to untouched.
    std::fs::remove_file(data.join("decks/mine.toml")).unwrap();
    std::fs::remove_dir_all(data.join("content/mine")).unwrap();
    symlink(root.join("outside/mine.toml"), data.join("decks/mine.toml")).unwrap();
    symlink(root.join("outside/mine"), data.join("content/mine")).unwrap();
    let o = flipcard_within(root, &["decks", "add", "v2"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert!(
        std::fs::symlink_metadata(data.join("decks/mine.toml"))
            .unwrap()
            .is_file()
    );
    assert!(
        std::fs::symlink_metadata(data.join("content/mine"))
            .unwrap()
            .is_dir()
    );
    outside_intact(root);

    // A FIFO where the deck file is: replaced, not opened.
    std::fs::remove_file(data.join("decks/mine.toml")).unwrap();
    mkfifo(&data.join("decks/mine.toml"));
    let o = flipcard_within(root, &["decks", "add", "v2"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert!(data.join("decks/mine.toml").is_file());

    // The library's folders, its lock and its staging folder must be
    // what they are: a link or a FIFO there is refused in one line.
    // (where, a FIFO there rather than a link out of the library)
    let cases = [
        ("content", false),
        ("decks/.staging", false),
        ("decks/.lock", true),
    ];
    for (name, fifo) in cases {
        let path = data.join(name);
        let kept = root.join("kept");
        if std::fs::symlink_metadata(&path).is_ok() {
            std::fs::rename(&path, &kept).unwrap();
        }
        if fifo {
            mkfifo(&path);
        } else {
            symlink(root.join("outside"), &path).unwrap();
        }
        let o = flipcard_within(root, &["decks", "add", "v2"]);
        assert_eq!(o.status.code(), Some(1), "{name}: {}", o.stderr());
        assert_eq!(o.stderr().lines().count(), 1, "{name}: {}", o.stderr());
        outside_intact(root);
        assert!(
            !root.join("outside/deck.toml").exists() && !root.join("outside/new").exists(),
            "{name}: something was written outside"
        );
        std::fs::remove_file(&path).unwrap();
        if kept.exists() {
            std::fs::rename(&kept, &path).unwrap();
        }
    }
    let o = flipcard_within(root, &["decks", "add", "v2"]);
    assert!(o.status.success(), "{}", o.stderr());

    // A folder where the deck file goes is not a deck to replace.
    std::fs::remove_file(data.join("decks/mine.toml")).unwrap();
    std::fs::create_dir(data.join("decks/mine.toml")).unwrap();
    std::fs::write(data.join("decks/mine.toml/notes.txt"), "mine").unwrap();
    let o = flipcard_within(root, &["decks", "add", "v2"]);
    refused(&o, "is a folder, not a deck file");
    assert!(data.join("decks/mine.toml/notes.txt").is_file());
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(status.success());
}

/// Which deck `mine` the library holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Held {
    Nothing,
    /// One card, content `# v1`.
    V1,
    /// Two cards, content `# v2`.
    V2,
}

const KILL_ENV: &str = "FLIPCARD_TEST_LIBRARY_KILL";

/// `flipcard ARGS` made to SIGKILL itself before its `kill_at`th change to
/// the library's files; whether it was killed.
fn killed_at(root: &Path, args: &[&str], kill_at: u32) -> bool {
    use std::os::unix::process::ExitStatusExt;
    let o = in_root(root)
        .env(KILL_ENV, kill_at.to_string())
        .args(args)
        .run();
    match o.status.signal() {
        Some(9) => true,
        _ => {
            assert!(o.status.success(), "{args:?}: {}", o.stderr());
            false
        }
    }
}

/// What the files say, right now: a deck file in the library is always
/// one of the two versions with that version's content beside it. With
/// `settled` (after a run that finished), a deck that is absent has left
/// no content behind and no staging folder remains.
fn held(data: &Path, settled: bool, context: &str) -> Held {
    let file = data.join("decks/mine.toml");
    let content = data.join("content/mine/en.toml");
    let read = |p: &Path| std::fs::read_to_string(p).ok();
    let held = match read(&file) {
        None => {
            assert!(
                std::fs::symlink_metadata(&file).is_err(),
                "{context}: the deck file is there but unreadable"
            );
            Held::Nothing
        }
        Some(text) if text.contains("id = 'b'") => Held::V2,
        Some(_) => Held::V1,
    };
    let want = match held {
        Held::Nothing => None,
        Held::V1 => Some("# v1\n"),
        Held::V2 => Some("# v2\n"),
    };
    if want.is_some() || settled {
        assert_eq!(
            read(&content).as_deref(),
            want,
            "{context}: deck {held:?} with the wrong content"
        );
    }
    if settled {
        assert!(
            !data.join("decks/.staging").exists(),
            "{context}: the staging folder is left"
        );
        if held == Held::Nothing {
            assert!(
                !data.join("content/mine").exists(),
                "{context}: content without a deck"
            );
        }
    }
    held
}

/// The deck as every command sees it: `decks` lists it whole, or not.
fn listed(root: &Path, context: &str) -> Held {
    let o = flipcard(root, &["decks"]);
    assert!(o.status.success(), "{context}: {}", o.stderr());
    assert!(o.stderr().is_empty(), "{context}: {}", o.stderr());
    let listing = o.stdout();
    match listing
        .lines()
        .find(|l| l.split_whitespace().next() == Some("mine"))
    {
        None => Held::Nothing,
        Some(row) => {
            assert!(row.trim_end().ends_with(" ok"), "{context}: {row}");
            if row.contains("2 cards") {
                Held::V2
            } else {
                assert!(row.contains("1 card,"), "{context}: {row}");
                Held::V1
            }
        }
    }
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

/// `decks add` of a new deck, `decks add` replacing the library's copy and
/// `decks remove`, each killed with SIGKILL before every change it makes
/// to the library's files in turn: at every point the library holds the
/// old deck with its content or the new one with its content (never a deck
/// without its content), and the next command finishes the change. For
/// the replacement, that next command is killed at every point too.
#[cfg(unix)]
#[test]
fn a_change_killed_at_any_point_leaves_a_whole_deck_or_none() {
    let sources = tempfile::tempdir().unwrap();
    let src = sources.path();
    for (name, cards, text) in [
        ("v1", &["a"][..], "# v1\n"),
        ("v2", &["a", "b"][..], "# v2\n"),
    ] {
        deck(&src.join(name), "mine", cards);
        std::fs::write(src.join(name).join("content/mine/en.toml"), text).unwrap();
    }
    let v2 = src.join("v2").display().to_string();
    let add: Vec<&str> = vec!["decks", "add", &v2];
    let remove: Vec<&str> = vec!["decks", "remove", "mine"];
    let scenarios: [(&str, Held, &Vec<&str>, Held, bool); 3] = [
        ("add", Held::Nothing, &add, Held::V2, false),
        ("replace", Held::V1, &add, Held::V2, true),
        ("remove", Held::V1, &remove, Held::Nothing, false),
    ];
    for (scenario, before, args, after, kill_recovery) in scenarios {
        let mut kills = 0;
        for n in 1.. {
            let dir = tempfile::tempdir().unwrap();
            let root = dir.path();
            if before == Held::V1 {
                let o = flipcard(
                    root,
                    &["decks", "add", &src.join("v1").display().to_string()],
                );
                assert!(o.status.success(), "{}", o.stderr());
            }
            let context = format!("{scenario}, killed before change {n}");
            if !killed_at(root, args, n) {
                assert_eq!(held(&root.join("data"), true, &context), after, "{context}");
                assert_eq!(listed(root, &context), after, "{context}");
                break;
            }
            kills += 1;
            let now = held(&root.join("data"), false, &context);
            assert!(
                now == before || now == after || now == Held::Nothing,
                "{context}: {now:?}"
            );
            if kill_recovery {
                for m in 1.. {
                    let again = tempfile::tempdir().unwrap();
                    copy_tree(&root.join("data"), &again.path().join("data"));
                    let context = format!("{context}, recovery killed before change {m}");
                    if !killed_at(again.path(), &["decks"], m) {
                        break;
                    }
                    held(&again.path().join("data"), false, &context);
                    let got = listed(again.path(), &context);
                    assert!(got == before || got == after, "{context}: {got:?}");
                    assert_eq!(held(&again.path().join("data"), true, &context), got);
                }
            }
            let got = listed(root, &context);
            assert!(got == before || got == after, "{context}: {got:?}");
            assert_eq!(held(&root.join("data"), true, &context), got, "{context}");
        }
        assert!(kills >= 4, "{scenario}: only {kills} points to kill at");
    }
}
