//! `E` and `A`: a deck file edited where the learner studies, through the
//! real keys, the real check and the real file; the editor is a step the
//! test gives (or a real process, a shell script run as `$VISUAL` would
//! be).

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use crossterm::event::KeyCode::{Char, Enter};

use super::press;
use crate::sched::{Direction, ItemKey};
use crate::tui::edit::NoTerminal;
use crate::tui::edit_run::run_pending;
use crate::tui::screens::Screen;
use crate::tui::services::{EditorRun, Spawn};
use crate::tui::stack::Tui;
use crate::tui::testkit::{render, services};
use crate::tui::theme::Theme;

const DECK: &str = r#"[deck]
id = "mini"
title = { en = 'Mini', hi-Latn = 'Mini' }
languages = ["en", "hi-Latn"]

[[card]]
id = "two"
front = { en = 'What is two plus two?', hi-Latn = 'Do aur do?' }
back = { en = 'Four.', hi-Latn = 'Chaar.' }

[[card]]
id = "unit"
kind = "typed"
front = { en = 'The unit of force?', hi-Latn = 'Force ki unit?' }
back = { en = 'The newton.', hi-Latn = 'Newton.' }
accept = ["newton", "N"]
"#;

/// What the test's editor does to the file, one step per run.
pub(super) type Step = Box<dyn FnMut(&Path) -> Result<(), String>>;

/// An editor that runs the steps given, in order, and remembers where it
/// was opened.
#[derive(Clone, Default)]
pub(super) struct Scripted {
    pub(super) steps: Rc<RefCell<Vec<Step>>>,
    pub(super) opened: Rc<RefCell<Vec<(PathBuf, usize)>>>,
}

impl EditorRun for Scripted {
    fn run(&mut self, file: &Path, line: usize) -> Result<(), String> {
        self.opened.borrow_mut().push((file.to_path_buf(), line));
        let mut steps = self.steps.borrow_mut();
        assert!(
            !steps.is_empty(),
            "the editor ran more often than the test said"
        );
        let mut step = steps.remove(0);
        step(file)
    }
}

pub(super) fn replace(from: &'static str, to: &'static str) -> Step {
    Box::new(move |file: &Path| {
        let text = std::fs::read_to_string(file).unwrap();
        assert!(text.contains(from), "{from:?} not in {}", file.display());
        std::fs::write(file, text.replacen(from, to, 1)).unwrap();
        Ok(())
    })
}

pub(super) struct Fixture {
    pub(super) app: Tui,
    pub(super) editor: Scripted,
    pub(super) file: PathBuf,
    pub(super) _dir: tempfile::TempDir,
}

/// The app on the deck `mini`, a file of a temporary folder, reviewing it.
/// The deck `mini` under `root` (`decks/mini.toml`, empty explanations).
fn write_deck(root: &Path) -> PathBuf {
    let decks = root.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    std::fs::create_dir_all(root.join("content/mini")).unwrap();
    for lang in ["en", "hi-Latn"] {
        std::fs::write(root.join(format!("content/mini/{lang}.toml")), "").unwrap();
    }
    let file = decks.join("mini.toml");
    std::fs::write(&file, DECK).unwrap();
    file
}

pub(super) fn fixture(steps: Vec<Step>) -> Fixture {
    let dir = tempfile::tempdir().unwrap();
    let file = write_deck(dir.path());
    let decks = dir.path().join("decks");
    let loaded = crate::deck::load_paths(std::slice::from_ref(&decks));
    assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
    let mut app = Tui::new(loaded.decks, services(&dir), "en", Theme::PLAIN);
    app.size = (100, 30);
    let editor = Scripted::default();
    editor.steps.borrow_mut().extend(steps);
    app.services.editor = Box::new(editor.clone());
    crate::tui::open_review(&mut app, Some("mini"), false).unwrap();
    Fixture {
        app,
        editor,
        file,
        _dir: dir,
    }
}

/// A key, then the edit it asked for, as the event loop carries it out.
pub(super) fn key(app: &mut Tui, c: char) {
    press(app, Char(c));
    run_pending(app, &mut NoTerminal);
}

pub(super) fn status(app: &Tui) -> String {
    app.status
        .as_ref()
        .map(|s| s.text.clone())
        .unwrap_or_default()
}

pub(super) fn shown(app: &Tui) -> Option<ItemKey> {
    match app.screen() {
        Screen::Review(r) => r.current.as_ref().map(|(k, _)| k.clone()),
        _ => None,
    }
}

pub(super) fn item(card: &str) -> ItemKey {
    ItemKey {
        deck: "mini".into(),
        card: card.into(),
        direction: Direction::Forward,
    }
}

#[test]
fn e_opens_the_card_at_its_line_and_a_valid_edit_is_reloaded_in_place() {
    let mut f = fixture(vec![replace(
        "What is two plus two?",
        "What is three plus three?",
    )]);
    assert_eq!(shown(&f.app), Some(item("two")));
    press(&mut f.app, Char(' '));
    key(&mut f.app, 'E');
    // Opened at the card's `id` line, in its own file.
    assert_eq!(*f.editor.opened.borrow(), [(f.file.clone(), 7)]);
    let card = f.app.decks[0].card("two").unwrap();
    assert_eq!(card.front.get("en"), "What is three plus three?");
    // The review goes on at the same card, from its front, as edited.
    assert_eq!(shown(&f.app), Some(item("two")));
    assert!(matches!(f.app.screen(), Screen::Review(_)));
    let screen = render(&f.app);
    assert!(screen.contains("What is three plus three?"), "{screen}");
    assert!(status(&f.app).contains("reloaded"), "{}", status(&f.app));
    // Rated as before: the history is the card id's.
    press(&mut f.app, Char(' '));
    press(&mut f.app, Char('3'));
    assert!(
        f.app
            .services
            .study
            .store
            .state(&item("two"))
            .unwrap()
            .is_some()
    );
}

#[test]
fn an_edit_that_breaks_the_deck_shows_the_error_and_r_puts_the_file_back_byte_for_byte() {
    let mut f = fixture(vec![
        replace("back = { en = 'Four.'", "back = { en = 42"),
        replace("back = { en = 42", "bak = { en = 42"),
    ]);
    let before = std::fs::read(&f.file).unwrap();
    key(&mut f.app, 'E');
    let Screen::EditCheck(check) = f.app.screen() else {
        panic!("no check screen: {}", render(&f.app));
    };
    let at = format!("{}:9:", f.file.display());
    assert!(check.error.starts_with(&at), "{}", check.error);
    let screen = render(&f.app);
    assert!(screen.contains("does not pass its check"), "{screen}");
    // The deck in the app is the one before the edit.
    assert_eq!(f.app.decks[0].card("two").unwrap().back.get("en"), "Four.");
    // `e`: the editor again, at the error's line; still broken.
    key(&mut f.app, 'e');
    assert_eq!(f.editor.opened.borrow()[1].1, 9);
    let Screen::EditCheck(check) = f.app.screen() else {
        panic!("no check screen: {}", render(&f.app));
    };
    assert!(
        check.error.contains("missing the required field `back`"),
        "{}",
        check.error
    );
    // `r`: the file as it was, and the review where it was.
    key(&mut f.app, 'r');
    assert_eq!(std::fs::read(&f.file).unwrap(), before);
    assert!(matches!(f.app.screen(), Screen::Review(_)));
    assert!(
        status(&f.app).contains("back as it was"),
        "{}",
        status(&f.app)
    );
    assert_eq!(shown(&f.app), Some(item("two")));
}

#[test]
fn e_again_with_a_fix_reloads_and_closes_the_check() {
    let mut f = fixture(vec![
        replace("back = { en = 'Four.'", "back = { en = 42"),
        replace("back = { en = 42", "back = { en = 'Vier.'"),
    ]);
    key(&mut f.app, 'E');
    assert!(matches!(f.app.screen(), Screen::EditCheck(_)));
    key(&mut f.app, 'e');
    assert!(matches!(f.app.screen(), Screen::Review(_)));
    assert_eq!(f.app.decks[0].card("two").unwrap().back.get("en"), "Vier.");
}

#[test]
fn a_card_whose_id_changed_leaves_the_review_and_the_learner_is_told_its_history_stays() {
    let mut f = fixture(vec![replace("id = \"two\"", "id = \"two-new\"")]);
    key(&mut f.app, 'E');
    let said = status(&f.app);
    assert!(said.contains("`two` is no longer in the deck"), "{said}");
    assert!(said.contains("history stays with that id"), "{said}");
    assert!(f.app.decks[0].card("two-new").is_some());
    assert_eq!(shown(&f.app), Some(item("unit")));
}

#[test]
fn a_adds_a_card_of_the_current_kind_that_is_then_studied() {
    let mut f = fixture(vec![replace(
        "'''The question.'''",
        "'''The unit of power?'''",
    )]);
    // Past the basic card to the typed one.
    press(&mut f.app, Char(' '));
    press(&mut f.app, Char('3'));
    assert_eq!(shown(&f.app), Some(item("unit")));
    // On a typed card's front `A` is a letter of the answer: on its back
    // it adds a card.
    press(&mut f.app, Enter);
    let lines_before = std::fs::read_to_string(&f.file).unwrap().lines().count();
    key(&mut f.app, 'A');
    let (file, line) = f.editor.opened.borrow()[0].clone();
    assert_eq!(file, f.file);
    let text = std::fs::read_to_string(&f.file).unwrap();
    assert_eq!(text.lines().nth(line - 1), Some("id = \"new-card-1\""));
    assert!(line > lines_before);
    let card = f.app.decks[0].card("new-card-1").expect("the new card");
    assert_eq!(card.kind, crate::deck::CardKind::Typed);
    assert!(
        status(&f.app).contains("card added `new-card-1`"),
        "{}",
        status(&f.app)
    );
    // Shown at once, and studied as any card: typed, checked, rated.
    assert_eq!(shown(&f.app), Some(item("new-card-1")));
    let screen = render(&f.app);
    assert!(screen.contains("The unit of power?"), "{screen}");
    for c in "the answer".chars() {
        press(&mut f.app, Char(c));
    }
    press(&mut f.app, Enter);
    press(&mut f.app, Enter);
    let state = f
        .app
        .services
        .study
        .store
        .state(&item("new-card-1"))
        .unwrap();
    assert!(state.is_some(), "the new card's answer is stored");
}

#[test]
fn a_new_card_left_as_its_template_is_taken_out_again() {
    let mut f = fixture(vec![Box::new(|_: &Path| Ok(()))]);
    let before = std::fs::read(&f.file).unwrap();
    key(&mut f.app, 'A');
    assert_eq!(std::fs::read(&f.file).unwrap(), before);
    assert!(f.app.decks[0].card("new-card-1").is_none());
    assert!(
        status(&f.app).contains("nothing added"),
        "{}",
        status(&f.app)
    );
}

#[test]
fn an_editor_that_cannot_start_is_one_line_and_changes_nothing() {
    let mut f = fixture(Vec::new());
    f.app.services.editor = Box::new(Spawn::from_setting("/nonexistent/flipcard-editor --wait"));
    let before = std::fs::read(&f.file).unwrap();
    for k in ['E', 'A'] {
        key(&mut f.app, k);
        let said = f.app.status.clone().unwrap();
        assert!(said.error);
        assert!(
            said.text
                .starts_with("cannot start the editor `/nonexistent/flipcard-editor`"),
            "{}",
            said.text
        );
        assert!(!said.text.contains('\n'));
        assert_eq!(std::fs::read(&f.file).unwrap(), before);
        assert!(matches!(f.app.screen(), Screen::Review(_)));
    }
}

/// A real editor process: a shell script given as `$VISUAL` would give
/// it (with an argument), run without a shell on a path with spaces,
/// quotes and `$(…)` in it, which must reach it as one argument.
#[test]
fn the_editor_runs_without_a_shell_with_the_line_then_the_file() {
    let mut f = fixture(Vec::new());
    let odd = f._dir.path().join("it's a $(touch pwned) dir");
    let file = write_deck(&odd);
    let loaded = crate::deck::load_paths(&[odd.join("decks")]);
    f.app.decks = loaded.decks;
    let script = f._dir.path().join("fake-editor");
    let log = f._dir.path().join("args");
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\nprintf '%s\\n' \"$@\" > '{}'\nsed -i 's/Four\\./Four, of course./' \"$3\"\n",
            log.display()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    f.app.services.editor = Box::new(Spawn::from_setting(&format!("{} --flag", script.display())));
    key(&mut f.app, 'E');
    let args = std::fs::read_to_string(&log).unwrap();
    assert_eq!(args, format!("--flag\n+7\n{}\n", file.display()));
    assert!(!f._dir.path().join("pwned").exists());
    assert_eq!(
        f.app.decks[0].card("two").unwrap().back.get("en"),
        "Four, of course."
    );
}

#[test]
fn e_in_the_browser_edits_the_selected_item_and_the_list_shows_the_edit() {
    let mut f = fixture(vec![replace("The unit of force?", "The SI unit of force?")]);
    let browser = crate::tui::screens::browser::BrowserState::open(&f.app).unwrap();
    f.app.push(Screen::Browser(Box::new(browser)));
    press(&mut f.app, Char('j'));
    key(&mut f.app, 'E');
    assert_eq!(f.editor.opened.borrow()[0].1, 12);
    let Screen::Browser(b) = f.app.screen() else {
        panic!("not the browser");
    };
    assert_eq!(b.current().map(|r| r.key(&f.app.decks)), Some(item("unit")));
    let screen = render(&f.app);
    assert!(screen.contains("The SI unit of force?"), "{screen}");
}

/// `E` in card info edits the item it shows; the info screen then shows
/// the edited text (issue 25 §5: review, browser or card info).
#[test]
fn e_in_card_info_edits_its_item_and_the_info_shows_the_edit() {
    let mut f = fixture(vec![replace("The unit of force?", "The SI unit of force?")]);
    let browser = crate::tui::screens::browser::BrowserState::open(&f.app).unwrap();
    f.app.push(Screen::Browser(Box::new(browser)));
    press(&mut f.app, Char('j'));
    key(&mut f.app, 'i');
    assert!(matches!(f.app.screen(), Screen::Info(_)), "card info open");
    key(&mut f.app, 'E');
    assert_eq!(f.editor.opened.borrow()[0].1, 12);
    let Screen::Info(i) = f.app.screen() else {
        panic!("card info closed");
    };
    assert_eq!(i.key, item("unit"));
    let screen = render(&f.app);
    assert!(screen.contains("The SI unit of force?"), "{screen}");
}

/// A bundled deck is copied into the library (with its explanations) and
/// the copy edited; the next load takes the copy in place of the bundled
/// deck, with no clash of ids.
#[test]
fn a_bundled_deck_is_copied_into_the_library_and_the_copy_edited() {
    use crate::cmd::library::{EditLibrary, Origin, Source, library_dir, load_with};
    let dir = tempfile::tempdir().unwrap();
    let lib = library_dir(dir.path());
    std::fs::create_dir_all(&lib).unwrap();
    let sources = || {
        vec![
            Source {
                origin: Origin::Bundled,
                path: PathBuf::from(crate::bundled::DECKS),
            },
            Source {
                origin: Origin::Library,
                path: lib.clone(),
            },
        ]
    };
    let library = load_with(sources());
    let mut app = Tui::new(
        library.loaded.decks.clone(),
        services(&dir),
        "en",
        Theme::PLAIN,
    );
    app.size = (100, 30);
    let editor = Scripted::default();
    editor.steps.borrow_mut().push(replace(
        "front.en = '''What is the exact equation",
        "front.en = '''Edited: what is the exact equation",
    ));
    app.services.editor = Box::new(editor.clone());
    app.services.library = Some(Box::new(EditLibrary::new(
        dir.path().to_path_buf(),
        &library,
    )));
    crate::tui::open_review(&mut app, Some("oscillations"), false).unwrap();
    let first = shown(&app).unwrap();
    assert_eq!(first.card, "pendulum-equation");
    key(&mut app, 'E');
    let copy = lib.join("oscillations.toml");
    assert_eq!(*editor.opened.borrow(), [(copy.clone(), 28)]);
    let said = status(&app);
    assert!(
        said.contains("bundled deck copied into your library"),
        "{said}"
    );
    assert!(said.contains(&copy.display().to_string()), "{said}");
    for lang in ["en", "hi-Latn"] {
        let content = dir.path().join(format!("content/oscillations/{lang}.toml"));
        assert!(content.is_file(), "{}", content.display());
    }
    let i = app
        .decks
        .iter()
        .position(|d| d.id == "oscillations")
        .unwrap();
    assert_eq!(app.decks[i].path, copy);
    assert!(
        app.decks[i]
            .card("pendulum-equation")
            .unwrap()
            .front
            .get("en")
            .starts_with("Edited: ")
    );
    assert_eq!(shown(&app), Some(first));
    // Loaded again, the copy stands in for the bundled deck.
    let again = load_with(sources());
    assert_eq!(again.loaded.errors(), 0, "{}", again.loaded.render_all());
    let from: Vec<_> = again
        .files
        .iter()
        .filter(|f| {
            f.deck
                .is_some_and(|d| again.loaded.decks[d].id == "oscillations")
        })
        .map(|f| again.source_of(f).origin)
        .collect();
    assert_eq!(from, [Origin::Library]);
}

#[test]
fn esc_on_the_check_keeps_the_broken_file_and_says_the_deck_is_left_out() {
    let mut f = fixture(vec![replace("back = { en = 'Four.'", "back = { en = 42")]);
    key(&mut f.app, 'E');
    assert!(matches!(f.app.screen(), Screen::EditCheck(_)));
    press(&mut f.app, crossterm::event::KeyCode::Esc);
    assert!(matches!(f.app.screen(), Screen::Review(_)));
    assert!(
        std::fs::read_to_string(&f.file)
            .unwrap()
            .contains("en = 42")
    );
    assert!(status(&f.app).contains("left out"), "{}", status(&f.app));
    // The app goes on with the deck as it was loaded.
    assert_eq!(f.app.decks[0].card("two").unwrap().back.get("en"), "Four.");
}

#[test]
fn a_in_the_browser_adds_a_card_of_the_selected_kind_and_selects_it() {
    let mut f = fixture(vec![replace(
        "'''The question.'''",
        "'''Mass of the proton?'''",
    )]);
    let browser = crate::tui::screens::browser::BrowserState::open(&f.app).unwrap();
    f.app.push(Screen::Browser(Box::new(browser)));
    key(&mut f.app, 'A');
    let card = f.app.decks[0].card("new-card-1").expect("the new card");
    assert_eq!(card.kind, crate::deck::CardKind::Basic);
    let Screen::Browser(b) = f.app.screen() else {
        panic!("not the browser");
    };
    assert_eq!(
        b.current().map(|r| r.key(&f.app.decks)),
        Some(item("new-card-1"))
    );
    let screen = render(&f.app);
    assert!(screen.contains("Mass of the proton?"), "{screen}");
}
