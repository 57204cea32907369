//! End to end in a real terminal (tmux): `flipcard review --tag intuition`
//! without a deck reviews the tagged card of each bundled deck in one
//! session, each under its own deck's title; an Again comes back at its
//! learning step; then `flipcard export --reviews` has every rating against
//! the right deck.

use std::process::Command;

use crate::tui_e2e::{Tmux, release_binary, tmux_available};

fn vars(dir: &std::path::Path) -> Vec<(&'static str, String)> {
    vec![
        ("FLIPCARD_NOW", "2026-03-02T09:00:00Z".to_string()),
        ("FLIPCARD_DATA_DIR", dir.join("data").display().to_string()),
        (
            "FLIPCARD_CONFIG",
            dir.join("config.toml").display().to_string(),
        ),
        // A deck of its own beside the bundled ones, without the tag.
        (
            "FLIPCARD_DECKS",
            concat!(env!("CARGO_MANIFEST_DIR"), "/tests/decks/study/decks").to_string(),
        ),
        ("TERM", "xterm-256color".to_string()),
    ]
}

/// The tagged card of each bundled deck: (deck, card, deck title, a piece
/// of its front, a piece of its back).
const CARDS: [(&str, &str, &str, &str, &str); 2] = [
    (
        "oscillations",
        "swing-story",
        "Oscillations beyond the small-angle limit",
        "Pushing a child on a swing",
        "Once per swing",
    ),
    (
        "torque-free-rotation",
        "book-story",
        "Torque-free rotation",
        "You toss a book",
        "Flat like a frisbee",
    ),
];

#[test]
fn a_tag_without_a_deck_reviews_both_bundled_decks_and_exports_each_rating_under_its_deck() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let t = Tmux::start(
        "study",
        &vars(dir.path()),
        "review --tag intuition",
        110,
        30,
    );
    let screen = t.wait_for("2 cards · filtered");
    // Deck order is the library's: find which card comes first.
    let first = CARDS
        .iter()
        .position(|c| screen.contains(c.3))
        .unwrap_or_else(|| panic!("neither tagged card is shown:\n{screen}"));
    let (a, b) = (&CARDS[first], &CARDS[1 - first]);
    assert!(screen.contains(a.2), "the card's own deck title:\n{screen}");
    t.keys(&["Space"]);
    t.wait_for(a.4);
    t.keys(&["4"]);
    let screen = t.wait_for(b.3);
    assert!(
        screen.contains(b.2),
        "the second deck's title on its card:\n{screen}"
    );
    t.keys(&["Space"]);
    t.wait_for(b.4);
    t.keys(&["1"]);
    // Again: relearning one minute on, shown again when nothing else is
    // left (within the learn-ahead limit), as in a normal session.
    let screen = t.wait_for("1 learning");
    assert!(screen.contains(b.3), "{screen}");
    t.keys(&["Space"]);
    t.wait_for(b.4);
    t.keys(&["4"]);
    t.wait_for("Session done");
    t.keys(&["Escape"]);
    t.wait_for("Decks");
    t.keys(&["q"]);
    t.wait_for("EXIT=0");

    let mut cmd = Command::new(release_binary());
    cmd.args(["export", "--reviews", "--format", "json"]);
    for (k, v) in vars(dir.path()) {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap_or_else(|e| panic!("export: {e}"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)));
    let got: Vec<(String, String, u64)> = rows
        .as_array()
        .map(|a| {
            a.iter()
                .map(|r| {
                    (
                        r["deck"].as_str().unwrap_or("").to_string(),
                        r["card"].as_str().unwrap_or("").to_string(),
                        r["rating"].as_u64().unwrap_or(0),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    let row =
        |c: &(&str, &str, &str, &str, &str), rating| (c.0.to_string(), c.1.to_string(), rating);
    assert_eq!(got, vec![row(a, 4), row(b, 1), row(b, 4)]);
}
