//! Deck options in the real app (tmux, the release build): `hide_bundled`
//! leaves the bundled decks off home; a deck under its `parent` is shown
//! indented with the counts of its subtree, each deck within its preset's
//! limits; `Enter` on the parent studies the subtree, and a reversed card's
//! other direction (buried once one is answered) takes no place of the new
//! limit. `flipcard cards list` then shows what the session stored.

use std::path::Path;

use crate::support::Flipcard;
use crate::tui_e2e::{Tmux, tmux_available};

const NOW: &str = "2026-03-02T09:00:00Z";

fn deck(dir: &Path, id: &str, title: &str, parent: Option<&str>, cards: usize) {
    let decks = dir.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    let mut text =
        format!("[deck]\nid = \"{id}\"\ntitle = {{ en = \"{title}\" }}\nlanguages = [\"en\"]\n");
    if let Some(p) = parent {
        text.push_str(&format!("parent = \"{p}\"\n"));
    }
    for i in 0..cards {
        text.push_str(&format!(
            "\n[[card]]\nid = \"c{i}\"\nkind = \"reversed\"\nfront = {{ en = \"{title} front {i}\" }}\nback = {{ en = \"{title} back {i}\" }}\n"
        ));
    }
    std::fs::write(decks.join(format!("{id}.toml")), text).unwrap();
    let content = dir.join("content").join(id);
    std::fs::create_dir_all(&content).unwrap();
    std::fs::write(content.join("en.toml"), "").unwrap();
}

#[test]
fn home_shows_the_tree_with_presets_and_hides_the_bundled_decks() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    deck(d, "mech", "Mechanics", None, 2);
    deck(d, "mech-springs", "Springs", Some("mech"), 6);
    std::fs::write(
        d.join("config.toml"),
        "hide_bundled = true\nnew_per_day = 5\n\n[preset.slow]\nnew_per_day = 2\n\n[deck.mech-springs]\npreset = \"slow\"\n",
    )
    .unwrap();
    let flipcard = || {
        Flipcard::new(d.join("data"))
            .config(d.join("config.toml"))
            .now(NOW)
            .decks(d.join("decks"))
    };
    let t = Tmux::start("deck-options", flipcard(), 100, 24);
    let screen = t.wait_for("Springs");
    // Only the two decks: no bundled one.
    let bundled = flipcard::bundled::load();
    for b in &bundled.decks {
        assert!(
            !screen.contains(b.title.get("en")),
            "{} shown: {screen}",
            b.id
        );
    }
    let row = |title: &str| -> Vec<String> {
        let line = screen
            .lines()
            .find(|l| l.contains(title))
            .unwrap_or_else(|| panic!("{title} in {screen}"));
        line.split_whitespace().map(str::to_string).collect()
    };
    // Mechanics: its 2 cards and 2 of Springs' (Springs' preset: 2 a day),
    // one item a card; Springs alone: 2. Due, learning, new.
    let mech = row("Mechanics");
    assert_eq!(mech[..5], ["›", "Mechanics", "0", "0", "4"], "{screen}");
    let springs_line = screen.lines().find(|l| l.contains("Springs")).unwrap();
    assert!(springs_line.starts_with("    Springs"), "{screen}");
    assert_eq!(row("Springs")[..4], ["Springs", "0", "0", "2"], "{screen}");

    // Enter on Mechanics: four cards, each answered Easy.
    t.keys(&["Enter"]);
    for _ in 0..4 {
        t.wait_for("front");
        t.keys(&["Space"]);
        t.wait_for("back");
        t.keys(&["4"]);
    }
    // After four, the session is done: no fifth card today.
    t.wait_for("Session done");
    t.keys(&["Escape"]);
    // Home again, counted afresh: the day's new cards are used up in both.
    let home = t.wait_for("last studied");
    let zero = |title: &str| {
        let line = home.lines().find(|l| l.contains(title)).unwrap();
        line.split_whitespace().filter(|w| *w == "0").count() >= 3
    };
    assert!(zero("Mechanics") && zero("Springs"), "{home}");
    t.keys(&["q"]);
    t.wait_for("EXIT=0");

    let out = flipcard().args(["cards", "list", "--format", "json"]).run();
    assert!(out.status.success(), "{}", out.stderr());
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut reviewed: Vec<String> = rows
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["state"] != "new")
        .map(|r| {
            format!(
                "{}/{}:{}",
                r["deck"].as_str().unwrap(),
                r["card"].as_str().unwrap(),
                r["direction"].as_str().unwrap()
            )
        })
        .collect();
    reviewed.sort();
    // Two cards of each deck, one direction each (the other is buried).
    assert_eq!(
        reviewed,
        [
            "mech-springs/c0:forward",
            "mech-springs/c1:forward",
            "mech/c0:forward",
            "mech/c1:forward",
        ]
    );
}
