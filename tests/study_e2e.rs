//! End to end in a real terminal (tmux): `flipcard review --tag intuition`
//! without a deck reviews the tagged card of each bundled deck in one
//! session, each under its own deck's title; an Again comes back at its
//! learning step; then `flipcard export --reviews` has every rating against
//! the right deck.

use crate::support::Flipcard;
use crate::tui_e2e::{Tmux, tmux_available};

fn flipcard(dir: &std::path::Path) -> Flipcard {
    Flipcard::new(dir.join("data"))
        .config(dir.join("config.toml"))
        .now("2026-03-02T09:00:00Z")
        // A deck of its own beside the bundled ones, without the tag.
        .decks(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/decks/study/decks"
        ))
        .release()
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
        flipcard(dir.path()).args(["review", "--tag", "intuition"]),
        110,
        30,
    );
    let screen = t.wait_for("2 cards left in this filter");
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

    let out = flipcard(dir.path())
        .args(["export", "--reviews", "--format", "json"])
        .run();
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
