//! End to end in a real terminal (tmux): `E` on the review screen runs
//! `$VISUAL` (a shell script standing in for an editor) on the card's deck
//! file with the terminal handed over in cooked mode, the edit is checked
//! and shown; a broken edit shows its file:line:col and `r` puts the file
//! back byte for byte; the terminal is restored when the app quits.

use std::path::Path;

use crate::support::Flipcard;
use crate::tui_e2e::{Tmux, tmux_available};

const NOW: &str = "2026-03-02T09:00:00Z";

const DECK: &str = r#"[deck]
id = "mini"
title = { en = 'Mini', hi-Latn = 'Mini' }
languages = ["en", "hi-Latn"]

[[card]]
id = "two"
front = { en = 'What is two plus two?', hi-Latn = 'Do aur do?' }
back = { en = 'Four.', hi-Latn = 'Chaar.' }
"#;

/// The editor: what it does is chosen by the file `mode` beside it
/// (`fix`: a valid edit; `break`: a value of the wrong type); it notes its
/// arguments and whether the terminal is in cooked mode.
const EDITOR: &str = r#"#!/bin/sh
here=$(dirname "$0")
printf '%s\n' "$@" >> "$here/args"
if stty -a | tr ' ;' '\n\n' | grep -qx icanon; then echo cooked >> "$here/tty"; else echo raw >> "$here/tty"; fi
case "$(cat "$here/mode")" in
  fix) sed -i "s/'Four\.'/'Four, surely.'/" "$2" ;;
  break) sed -i "s/back = { en = 'Four, surely.'/back = { en = 42/" "$2" ;;
  add) sed -i "s/'''The question.'''/'''Mass of the proton?'''/" "$2" ;;
esac
"#;

fn write(path: &Path, text: &str) {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    }
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

#[test]
fn e_edits_the_card_in_visual_and_a_broken_edit_is_reverted() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let root = dir.path();
    let file = root.join("course/decks/mini.toml");
    write(&file, DECK);
    write(&root.join("course/content/mini/en.toml"), "");
    write(&root.join("course/content/mini/hi-Latn.toml"), "");
    let editor = root.join("bin/editor");
    write(&editor, EDITOR);
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&editor, std::fs::Permissions::from_mode(0o755))
        .unwrap_or_else(|e| panic!("chmod: {e}"));
    write(&root.join("bin/mode"), "fix");
    let app = Flipcard::new(root.join("data"))
        .config(root.join("config.toml"))
        .now(NOW)
        .decks(root.join("course/decks"))
        .env("VISUAL", &editor)
        .env_remove("EDITOR")
        .args(["review", "mini"])
        .release();
    let t = Tmux::start("edit", app, 100, 30);
    t.wait_for("What is two plus two?");
    t.keys(&["Space"]);
    t.wait_for("Four.");
    t.keys(&["E"]);
    let s = t.wait_for("reloaded");
    assert!(s.contains("What is two plus two?"), "{s}");
    let args = std::fs::read_to_string(root.join("bin/args")).unwrap_or_default();
    assert_eq!(args, format!("+7\n{}\n", file.display()));
    t.keys(&["Space"]);
    t.wait_for("Four, surely.");

    // A broken edit: the error at its place, then `r`.
    let before = std::fs::read(&file).unwrap_or_default();
    write(&root.join("bin/mode"), "break");
    t.keys(&["E"]);
    let s = t.wait_for("does not pass its check");
    assert!(s.contains("mini.toml:9:"), "{s}");
    t.keys(&["r"]);
    t.wait_for("back as it was");
    assert_eq!(std::fs::read(&file).unwrap_or_default(), before);
    let tty = std::fs::read_to_string(root.join("bin/tty")).unwrap_or_default();
    assert_eq!(tty, "cooked\ncooked\n", "the editor ran in raw mode");

    // `A`: a new card, written in the editor, studied at once.
    write(&root.join("bin/mode"), "add");
    t.keys(&["A"]);
    t.wait_for("card added `new-card-1`");
    t.wait_for("Mass of the proton?");
    t.keys(&["Space"]);
    t.wait_for("The answer.");
    t.keys(&["3"]);
    t.wait_for("What is two plus two?");

    t.keys(&["q", "q"]);
    let s = t.wait_for("TTY=");
    assert!(s.contains("EXIT=0") && s.contains("TTY=cooked"), "{s}");
    let list = Flipcard::new(root.join("data"))
        .now(NOW)
        .decks(root.join("course/decks"))
        .args(["cards", "list", "deck:mini", "--format", "json"])
        .run();
    let rows: serde_json::Value =
        serde_json::from_str(&list.stdout()).unwrap_or_else(|e| panic!("{e}: {}", list.stdout()));
    let new = rows
        .as_array()
        .and_then(|r| r.iter().find(|r| r["card"] == "new-card-1"))
        .unwrap_or_else(|| panic!("no new-card-1 in {rows}"));
    assert_eq!(new["reviews"], 1, "{new}");
}

const TYPED_DECK: &str = r#"[deck]
id = "typed"
title = { en = 'Typed', hi-Latn = 'Typed' }
languages = ["en", "hi-Latn"]

[[card]]
id = "unit"
kind = "typed"
front = { en = 'The unit of force?', hi-Latn = 'Force ki unit?' }
back = { en = 'The newton.', hi-Latn = 'Newton.' }
accept = ["newton"]
explain = "forces"
"#;

const TYPED_EN: &str = r#"[[section]]
id = "forces"
title = 'Forces'
body = '''
A force changes motion.
'''
"#;

const TYPED_HI: &str = r#"[[section]]
id = "forces"
title = 'Force'
body = '''
Force motion ko badalta hai.
'''
"#;

/// The editor of the second test: `card` edits the card's front, `content`
/// the explanation's body (in whichever file it is given).
const TYPED_EDITOR: &str = r#"#!/bin/sh
here=$(dirname "$0")
printf '%s\n' "$@" >> "$here/args"
case "$(cat "$here/mode")" in
  card) sed -i "s/'The unit of force?'/'The SI unit of force?'/" "$2" ;;
  content) sed -i "s/A force changes motion\./A net force changes motion./" "$2" ;;
esac
"#;

/// F4 in a real terminal while the answer is typed (tmux delivers the
/// function key as the app reads it): the card is edited and the answer
/// typed so far is still there; then the card's explanation is edited
/// from the reader with `E`, in its content file.
#[test]
fn f4_while_typing_keeps_the_answer_and_e_in_the_reader_edits_the_explanation() {
    if !tmux_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let root = dir.path();
    let file = root.join("course/decks/typed.toml");
    write(&file, TYPED_DECK);
    let en = root.join("course/content/typed/en.toml");
    write(&en, TYPED_EN);
    write(&root.join("course/content/typed/hi-Latn.toml"), TYPED_HI);
    let editor = root.join("bin/editor");
    write(&editor, TYPED_EDITOR);
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&editor, std::fs::Permissions::from_mode(0o755))
        .unwrap_or_else(|e| panic!("chmod: {e}"));
    write(&root.join("bin/mode"), "card");
    let app = Flipcard::new(root.join("data"))
        .config(root.join("config.toml"))
        .now(NOW)
        .decks(root.join("course/decks"))
        .env("VISUAL", &editor)
        .env_remove("EDITOR")
        .args(["review", "typed"])
        .release();
    let t = Tmux::start("edit-typed", app, 100, 30);
    t.wait_for("The unit of force?");
    let s = t.wait_for("F4 edit");
    assert!(s.contains("F7 add card"), "{s}");
    // `E` is a letter of the answer here; F4 edits.
    t.keys(&["n", "E", "BSpace", "e", "w", "t"]);
    t.wait_for("newt");
    t.keys(&["F4"]);
    let s = t.wait_for("reloaded");
    assert!(s.contains("The SI unit of force?"), "{s}");
    assert!(s.contains("newt"), "the answer typed is kept:\n{s}");
    let args = std::fs::read_to_string(root.join("bin/args")).unwrap_or_default();
    assert_eq!(args, format!("+7\n{}\n", file.display()));
    t.keys(&["o", "n", "Enter"]);
    t.wait_for("3 Good");
    // The explanation, from the card's back: `e`, then `E` in the reader.
    write(&root.join("bin/mode"), "content");
    t.keys(&["e"]);
    t.wait_for("A force changes motion.");
    t.keys(&["E"]);
    t.wait_for("explanations checked and reloaded");
    t.wait_for("A net force changes motion.");
    let args = std::fs::read_to_string(root.join("bin/args")).unwrap_or_default();
    assert!(args.ends_with(&format!("+2\n{}\n", en.display())), "{args}");
    t.keys(&["Escape"]);
    t.wait_for("3 Good");
    // Rated; the learning card comes back at once (nothing else is due),
    // its field empty: Esc ends the session there (`q` is a letter).
    t.keys(&["3"]);
    t.wait_for("> ▏");
    t.keys(&["Escape"]);
    t.wait_for("q quit");
    t.keys(&["q"]);
    let s = t.wait_for("TTY=");
    assert!(s.contains("EXIT=0") && s.contains("TTY=cooked"), "{s}");
}
