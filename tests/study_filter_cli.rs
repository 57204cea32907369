//! `flipcard review [DECK] --tag … --state … --due-within …` without DECK
//! looks through every deck: a tag or state is checked against all of
//! them, and a filter that matches nothing says so in one line before the
//! terminal is touched.

use std::path::Path;
use std::process::{Command, Output};

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flipcard"))
        .args(args)
        .env("FLIPCARD_DATA_DIR", data)
        .env("FLIPCARD_NOW", "2026-05-10T12:00:00Z")
        .env("TZ", "UTC")
        .env("FLIPCARD_CONFIG", data.join("no-such-config.toml"))
        // The fixture deck opens beside the bundled ones.
        .env(
            "FLIPCARD_DECKS",
            concat!(env!("CARGO_MANIFEST_DIR"), "/tests/decks/study/decks"),
        )
        .output()
        .expect("run flipcard")
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn a_filter_without_a_deck_checks_names_against_every_deck() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, says) in [
        // A tag of no deck: named, with the tags of every deck.
        (
            vec!["review", "--tag", "nope"],
            "no card has tag `nope`; tags are ",
        ),
        (
            vec!["review", "--state", "asleep"],
            "unknown state `asleep`; states are new, learning, review, relearning, suspended, leech, buried",
        ),
        // `pendulum` is a tag of the oscillations deck only: unknown there
        // for the study deck, fine across decks (where nothing is due yet).
        (
            vec!["review", "study", "--tag", "pendulum"],
            "no card has tag `pendulum`; tags are euler, frames",
        ),
        (
            vec!["review", "--tag", "pendulum", "--due-within", "3d"],
            "no card of any deck matches the filter (suspended and buried cards are left out)",
        ),
        (
            vec!["review", "--tag", "euler", "--state", "leech"],
            "no card of any deck matches the filter",
        ),
        (
            vec!["review", "--state", "suspended"],
            "add --cram to look through them",
        ),
    ] {
        let o = flipcard(d, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", err(&o));
        assert!(err(&o).contains(says), "{args:?}: {}", err(&o));
        assert_eq!(err(&o).lines().count(), 1, "{args:?}: {}", err(&o));
    }
    // The tags listed come from every deck: the fixture's and the bundled.
    let o = flipcard(d, &["review", "--tag", "nope"]);
    for tag in ["euler", "pendulum", "stability", "frames"] {
        assert!(err(&o).contains(tag), "{tag}: {}", err(&o));
    }
}
