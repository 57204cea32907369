//! A deck's `parent` key through `flipcard check`: a parent that is not
//! loaded is a warning at the key (the deck is shown at the top), a cycle
//! of parents an error at each deck on it, a deck its own parent an error;
//! a valid tree passes.

use std::path::Path;

use crate::support::Flipcard;

fn deck(dir: &Path, id: &str, parent: Option<&str>) {
    let decks = dir.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    let parent = parent.map_or(String::new(), |p| format!("parent = \"{p}\"\n"));
    std::fs::write(
        decks.join(format!("{id}.toml")),
        format!(
            "[deck]\nid = \"{id}\"\ntitle = {{ en = \"Deck {id}\" }}\nlanguages = [\"en\"]\n{parent}\n[[card]]\nid = \"c1\"\nfront = {{ en = \"F\" }}\nback = {{ en = \"B\" }}\n"
        ),
    )
    .unwrap();
    let content = dir.join("content").join(id);
    std::fs::create_dir_all(&content).unwrap();
    std::fs::write(content.join("en.toml"), "").unwrap();
}

fn check(dir: &Path) -> (bool, String) {
    let o = Flipcard::without_data()
        .args([
            "check",
            "--no-simulate",
            dir.join("decks").to_str().unwrap(),
        ])
        .run();
    (o.status.success(), o.stderr())
}

#[test]
fn a_valid_tree_passes() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), "mech", None);
    deck(dir.path(), "mech-springs", Some("mech"));
    deck(dir.path(), "mech-springs-damped", Some("mech-springs"));
    let (ok, err) = check(dir.path());
    assert!(ok, "{err}");
    assert!(err.is_empty(), "{err}");
}

#[test]
fn an_unknown_parent_is_a_warning_at_the_key() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), "mech", None);
    deck(dir.path(), "springs", Some("mehc"));
    let (ok, err) = check(dir.path());
    assert!(ok, "a warning only: {err}");
    assert!(
        err.contains("springs.toml:5:10: warning: parent deck `mehc` is not among the decks loaded; `springs` is shown at the top level"),
        "{err}"
    );
    assert!(err.contains("mech"), "the hint names the near one: {err}");
}

#[test]
fn cycles_and_a_deck_its_own_parent_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), "a", Some("b"));
    deck(dir.path(), "b", Some("a"));
    deck(dir.path(), "c", Some("c"));
    deck(dir.path(), "d", Some("Not An Id"));
    let (ok, err) = check(dir.path());
    assert!(!ok, "{err}");
    assert!(
        err.contains("a.toml:5:10: error: decks `a` → `b` → `a` go round in a cycle of parents"),
        "{err}"
    );
    assert!(
        err.contains("b.toml:5:10: error: decks `b` → `a` → `b` go round"),
        "{err}"
    );
    assert!(
        err.contains("c.toml:5:10: error: deck `c` cannot be its own parent"),
        "{err}"
    );
    assert!(
        err.contains("d.toml:5:10: error: parent deck id `Not An Id` is not a valid id"),
        "{err}"
    );
}
