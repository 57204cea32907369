//! `sync_dir` in the config through the real binary in a real terminal
//! (tmux): a review session's answers reach the sync folder as soon as the
//! session closes, while the app stays open, and what another machine sent
//! meanwhile comes in at the next session's close.

use crate::support::Flipcard;
use crate::tui_e2e::{Tmux, tmux_available};
use std::path::Path;

const NOW: &str = "2026-06-01T12:00:00Z";

/// The release build with its data in `data`, its config `config`.
fn app(data: &Path, config: &Path) -> Flipcard {
    Flipcard::new(data).config(config).now(NOW).release()
}

fn flipcard(data: &Path, config: &Path, args: &[&str]) -> String {
    app(data, config).args(args).run().ok().stdout()
}

fn reviews(data: &Path, config: &Path) -> Vec<serde_json::Value> {
    let text = flipcard(data, config, &["export", "--reviews", "--format", "json"]);
    match serde_json::from_str(&text) {
        Ok(serde_json::Value::Array(rows)) => rows,
        other => panic!("export is not a JSON array: {other:?}\n{text}"),
    }
}

#[test]
fn a_session_syncs_when_it_closes_while_the_app_stays_open() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let folder = dir.path().join("Sync");
    std::fs::create_dir(&folder).unwrap_or_else(|e| panic!("{e}"));
    let config = dir.path().join("config.toml");
    std::fs::write(&config, format!("sync_dir = '{}'\n", folder.display()))
        .unwrap_or_else(|e| panic!("{e}"));
    let (laptop, lab) = (dir.path().join("laptop"), dir.path().join("lab"));

    let t = Tmux::start("sync-after-session", app(&laptop, &config), 100, 30);
    t.wait_for("Torque-free");
    // The first deck's review: one card answered Good, then back home.
    t.keys(&["Enter"]);
    t.wait_for("show answer");
    t.keys(&["Space"]);
    t.wait_for("Good");
    t.keys(&["3"]);
    std::thread::sleep(std::time::Duration::from_millis(300));
    t.keys(&["Escape"]);
    let screen = t.wait_for("Synced: 1 sent, 0 received");

    // The app is still open: the lab machine syncs and sees the answer.
    assert!(!screen.contains("EXIT="), "the app closed:\n{screen}");
    let out = flipcard(&lab, &config, &["sync"]);
    assert!(out.contains("1 review merged"), "{out}");
    let at_lab = reviews(&lab, &config);
    assert_eq!(at_lab.len(), 1, "{at_lab:?}");

    // The lab answers another card of the same deck and syncs.
    let deck = at_lab[0]["deck"].as_str().unwrap_or_default().to_string();
    let card = flipcard(&lab, &config, &["cards", "list", &format!("deck:{deck}")])
        .lines()
        .nth(1)
        .map(|l| l.split(',').nth(1).unwrap_or_default().to_string())
        .unwrap_or_default();
    assert!(!card.is_empty());
    flipcard(&lab, &config, &["cards", "bury", &format!("{deck}/{card}")]);
    let out = flipcard(&lab, &config, &["sync"]);
    assert!(out.contains("status change"), "{out}");

    // The laptop's next session closes and brings the bury in.
    t.keys(&["Enter"]);
    t.wait_for("show answer");
    t.keys(&["Escape"]);
    t.wait_for("Synced: 0 sent, 1 received");
    let listed = flipcard(
        &laptop,
        &config,
        &["cards", "list", "is:buried", "--format", "csv"],
    );
    assert!(listed.contains(&format!("{deck},{card},")), "{listed}");
    t.keys(&["q"]);
    t.wait_for("EXIT=0");
}
