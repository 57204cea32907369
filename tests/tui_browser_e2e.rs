//! End to end in a real terminal (tmux): open the card browser from home,
//! search, suspend the item found, leave, and check through `flipcard cards
//! list` that exactly that item is suspended; then a filtered session of a
//! cloze card shows the blank and records its rating under `c1`.

use crate::support::Flipcard;
use crate::tui_e2e::{Tmux, tmux_available};

const NOW: &str = "2026-03-02T09:00:00Z";

fn decks() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/tests/decks/study/decks").to_string()
}

/// The release build with its data and config in `dir`, the fixture deck
/// beside the bundled ones.
fn app(dir: &std::path::Path) -> Flipcard {
    Flipcard::new(dir.join("data"))
        .config(dir.join("config.toml"))
        .now(NOW)
        .decks(decks())
        .release()
}

fn flipcard(dir: &std::path::Path, args: &[&str]) -> (bool, String, String) {
    let out = app(dir).args(args).run();
    (out.status.success(), out.stdout(), out.stderr())
}

#[test]
fn browse_search_suspend_then_cards_list_shows_it() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let t = Tmux::start("browser", app(dir.path()), 110, 30);
    t.wait_for("Study");
    t.keys(&["b"]);
    t.wait_for("Card browser");
    t.wait_for(" items");
    t.keys(&["/"]);
    // The bundled decks are in the browser too: the fixture deck alone has
    // six items, and the search looks only there.
    for c in "deck:study stable spin".chars() {
        let k = if c == ' ' {
            "Space".to_string()
        } else {
            c.to_string()
        };
        t.keys(&[&k]);
    }
    let screen = t.wait_for("deck:study stable spin");
    assert!(screen.contains("spin-axis"), "{screen}");
    t.keys(&["Enter", "s"]);
    t.wait_for("card suspended");
    t.keys(&["Escape"]);
    t.wait_for("Decks");
    t.keys(&["q"]);
    t.wait_for("EXIT=0");

    let (ok, out, err) = flipcard(dir.path(), &["cards", "list", "is:suspended"]);
    assert!(ok, "{err}");
    let rows: Vec<&str> = out.lines().collect();
    assert_eq!(
        rows[0],
        "deck,card,direction,state,due,stability,difficulty,retrievability,reviews,lapses,suspended,buried,leech,tags,front"
    );
    assert_eq!(rows.len(), 2, "exactly one item is suspended: {out}");
    assert!(
        rows[1].starts_with("study,spin-axis,forward,new,")
            && rows[1].contains(",true,false,false,"),
        "{}",
        rows[1]
    );
    // The rebuild replays the status log to the same marks.
    let (ok, _, err) = flipcard(dir.path(), &["db", "rebuild"]);
    assert!(ok, "{err}");
    let (_, again, _) = flipcard(dir.path(), &["cards", "list", "is:suspended"]);
    assert_eq!(again, out);
}

#[test]
fn a_filtered_cloze_session_blanks_one_number_and_records_it() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let t = Tmux::start(
        "cloze",
        app(dir.path()).args(["review", "study", "--tag", "euler"]),
        110,
        30,
    );
    let front = t.wait_for("[…]");
    assert!(front.contains("is the rate of change of"), "{front}");
    t.keys(&["Space"]);
    t.wait_for("From Euler.");
    t.keys(&["3"]);
    // c2 is buried as c1's sibling: the plain card tagged euler comes next.
    t.wait_for("Middle axis spin?");
    t.keys(&["Escape"]);
    t.wait_for("Decks");
    t.keys(&["q"]);
    t.wait_for("EXIT=0");
    let (ok, out, err) = flipcard(
        dir.path(),
        &["cards", "list", "deck:study", "--format", "json"],
    );
    assert!(ok, "{err}");
    let rows: serde_json::Value =
        serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"));
    let row = |dir: &str| {
        rows.as_array()
            .and_then(|a| {
                a.iter()
                    .find(|r| r["card"] == "torque-rate" && r["direction"] == dir)
                    .cloned()
            })
            .unwrap_or_else(|| panic!("no torque-rate/{dir}: {out}"))
    };
    assert_eq!(row("c1")["reviews"], 1);
    assert_eq!(row("c1")["state"], "learning");
    assert_eq!(row("c2")["buried"], true);
    assert_eq!(row("c3")["buried"], true);
    assert_eq!(row("c2")["reviews"], 0);

    // Bad input is one clear line and exit 1, before the terminal switches.
    let (ok, _, err) = flipcard(dir.path(), &["review", "study", "--state", "sleeping"]);
    assert!(!ok && err.contains("unknown state `sleeping`"), "{err}");
    let (ok, _, err) = flipcard(dir.path(), &["cards", "suspend", "study/torque-rate/c9"]);
    assert!(
        !ok && err.contains("unknown item `study/torque-rate/c9`"),
        "{err}"
    );
}
