//! A cloze deletion inside math is a review item through the real binary:
//! `check` is green and `cards list` has its `cN`, where before the marker
//! inside `$...$` was dropped without a word (issue 23, section 5).

use crate::support::Flipcard;

const NOW: &str = "2026-05-10T12:00:00Z";

#[test]
fn every_deletion_inside_math_is_an_item() {
    let case = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/decks/valid/cloze-in-math"
    );
    let data = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let out = Flipcard::new(data.path())
        .now(NOW)
        .decks(format!("{case}/decks"))
        .args(["cards", "list", "deck:d"])
        .run();
    assert!(out.status.success(), "{}", out.stderr());
    let text = out.stdout();
    let items: Vec<&str> = text
        .lines()
        .skip(1)
        .filter_map(|l| {
            let mut f = l.split(',');
            (f.next() == Some("d") && f.next() == Some("euler")).then(|| f.next())?
        })
        .collect();
    // c1 and c4 sit inside formulas, c2 around one, c3 in prose.
    assert_eq!(items, ["c1", "c2", "c3", "c4"], "{text}");
}
