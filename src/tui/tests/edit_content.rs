//! `E` on an explanation (issue 25 §5): the reader opens the learner's
//! editor at the section's line in the content file of the language on
//! screen, through the real keys, the real check (`flipcard check`'s, the
//! deck with its content files) and the real files; a bundled deck's
//! explanations are edited in its library copy; hostile edits (a link or
//! a FIFO put in the file's place, an editor that fails, TOML and markup
//! broken) never write through a link, never hang, and `r` puts the file
//! back byte for byte.

use std::path::{Path, PathBuf};

use crossterm::event::KeyCode::{Enter, Esc, Right};

use super::edit::{Scripted, Step, key, replace, status};
use super::press;
use crate::tui::screens::Screen;
use crate::tui::screens::reader::ReaderState;
use crate::tui::services::Spawn;
use crate::tui::stack::Tui;
use crate::tui::testkit::{render, services};
use crate::tui::theme::Theme;

const DECK: &str = r#"[deck]
id = "mini"
title = { en = 'Mini', hi-Latn = 'Mini' }
languages = ["en", "hi-Latn"]

[[card]]
id = "unit"
kind = "typed"
front = { en = 'The unit of force?', hi-Latn = 'Force ki unit?' }
back = { en = 'The newton.', hi-Latn = 'Newton.' }
accept = ["newton", "N"]
explain = "forces"
"#;

const EN: &str = r#"[[section]]
id = "forces"
title = 'Forces'
body = '''
A force changes motion.
'''

[[section]]
id = "units"
title = 'Units'
body = '''
Force is measured in newtons.
'''
see = ["forces"]
"#;

const HI: &str = r#"[[section]]
id = "forces"
title = 'Force'
body = '''
Force motion ko badalta hai.
'''

[[section]]
id = "units"
title = 'Units'
body = '''
Force newton mein naapte hain.
'''
"#;

struct Fixture {
    app: Tui,
    editor: Scripted,
    en: PathBuf,
    hi: PathBuf,
    dir: tempfile::TempDir,
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// The deck `mini` with two sections in each language, in a temporary
/// folder; the app on its home screen.
fn fixture(steps: Vec<Step>) -> Fixture {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("decks/mini.toml"), DECK);
    let en = dir.path().join("content/mini/en.toml");
    let hi = dir.path().join("content/mini/hi-Latn.toml");
    write(&en, EN);
    write(&hi, HI);
    let loaded = crate::deck::load_paths(&[dir.path().join("decks")]);
    assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
    let mut app = Tui::new(loaded.decks, services(&dir), "en", Theme::PLAIN);
    app.size = (100, 30);
    let editor = Scripted::default();
    editor.steps.borrow_mut().extend(steps);
    app.services.editor = Box::new(editor.clone());
    Fixture {
        app,
        editor,
        en,
        hi,
        dir,
    }
}

fn reader(f: &mut Fixture) {
    f.app.push(Screen::Reader(ReaderState::new(0)));
}

fn section_shown(app: &Tui) -> usize {
    match app.screen() {
        Screen::Reader(r) => r.section,
        _ => panic!("not the reader:\n{}", render(app)),
    }
}

fn check_error(app: &Tui) -> String {
    match app.screen() {
        Screen::EditCheck(c) => c.error.clone(),
        _ => panic!("no check screen:\n{}", render(app)),
    }
}

#[test]
fn e_in_the_reader_edits_the_section_in_the_language_read_and_the_page_shows_it() {
    let mut f = fixture(vec![replace(
        "Force newton mein naapte hain.",
        "Force ko newton (N) mein naapte hain.",
    )]);
    reader(&mut f);
    press(&mut f.app, Right);
    assert_eq!(section_shown(&f.app), 1);
    // Hinglish on screen: the Hinglish file, at the section's id line.
    key(&mut f.app, 'l');
    let en_before = std::fs::read(&f.en).unwrap();
    key(&mut f.app, 'E');
    assert_eq!(*f.editor.opened.borrow(), [(f.hi.clone(), 9)]);
    assert_eq!(section_shown(&f.app), 1);
    let screen = render(&f.app);
    assert!(
        screen.contains("Force ko newton (N) mein naapte hain."),
        "{screen}"
    );
    assert!(
        status(&f.app).contains("explanations check hue aur dobara load hue"),
        "{}",
        status(&f.app)
    );
    assert_eq!(
        f.app.decks[0].section("units").unwrap().body.get("hi-Latn"),
        "Force ko newton (N) mein naapte hain.\n"
    );
    assert_eq!(std::fs::read(&f.en).unwrap(), en_before);
}

/// From the review: the card's `e` opens its explanation, `E` there edits
/// it in English, and back in the review the card is where it was (its
/// back, the answer typed), the deck file untouched.
#[test]
fn an_explanation_opened_from_the_review_is_edited_and_the_review_stays_where_it_was() {
    let mut f = fixture(vec![replace(
        "A force changes motion.",
        "A net force changes motion.",
    )]);
    crate::tui::open_review(&mut f.app, Some("mini"), false).unwrap();
    for c in "newton".chars() {
        key(&mut f.app, c);
    }
    press(&mut f.app, Enter);
    assert!(render(&f.app).contains("3 Good"), "{}", render(&f.app));
    key(&mut f.app, 'e');
    assert_eq!(section_shown(&f.app), 0);
    key(&mut f.app, 'E');
    assert_eq!(*f.editor.opened.borrow(), [(f.en.clone(), 2)]);
    assert!(render(&f.app).contains("A net force changes motion."));
    press(&mut f.app, Esc);
    let screen = render(&f.app);
    assert!(screen.contains("3 Good"), "{screen}");
    assert!(screen.contains("newton"), "{screen}");
}

/// A markup error (a link to no section) and then a TOML error: each
/// shown at the content file's line and column, `e` opening the editor
/// there; `r` puts the file back byte for byte.
#[test]
fn a_content_edit_that_breaks_markup_or_toml_is_shown_at_file_line_col_and_reverted() {
    let mut f = fixture(vec![
        replace(
            "Force is measured in newtons.",
            "Force is measured in [newtons](#nosuch).",
        ),
        replace("title = 'Units'", "title = 'Units"),
    ]);
    reader(&mut f);
    press(&mut f.app, Right);
    let before = std::fs::read(&f.en).unwrap();
    key(&mut f.app, 'E');
    assert_eq!(f.editor.opened.borrow()[0], (f.en.clone(), 9));
    let error = check_error(&f.app);
    let at = format!("{}:12:", f.en.display());
    assert!(error.starts_with(&at), "{error}");
    assert!(error.contains("nosuch"), "{error}");
    let screen = render(&f.app);
    assert!(screen.contains("does not pass its check"), "{screen}");
    // The app keeps the explanations as they were.
    assert_eq!(
        f.app.decks[0].section("units").unwrap().body.get("en"),
        "Force is measured in newtons.\n"
    );
    // `e`: at the error's line; the TOML broken too now.
    key(&mut f.app, 'e');
    assert_eq!(f.editor.opened.borrow()[1], (f.en.clone(), 12));
    let error = check_error(&f.app);
    assert!(
        error.starts_with(&format!("{}:10:", f.en.display())),
        "{error}"
    );
    key(&mut f.app, 'r');
    assert_eq!(std::fs::read(&f.en).unwrap(), before);
    assert_eq!(section_shown(&f.app), 1);
    assert!(
        status(&f.app).contains("back as it was"),
        "{}",
        status(&f.app)
    );
}

/// The content file swapped for a link to a file elsewhere while the
/// editor runs: the check reads it as the loader would (a link to a
/// regular file), reports what is wrong there, and `r` puts a regular
/// file back at the name: the file the link named is never written.
#[test]
fn a_content_file_replaced_by_a_link_while_the_editor_runs_is_never_written_through() {
    let mut f = fixture(Vec::new());
    let outside = f.dir.path().join("outside.txt");
    std::fs::write(&outside, "precious = [not toml\n").unwrap();
    let link_to = outside.clone();
    f.editor
        .steps
        .borrow_mut()
        .push(Box::new(move |file: &Path| {
            std::fs::remove_file(file).unwrap();
            std::os::unix::fs::symlink(&link_to, file).unwrap();
            Ok(())
        }));
    reader(&mut f);
    let before = std::fs::read(&f.en).unwrap();
    key(&mut f.app, 'E');
    let error = check_error(&f.app);
    assert!(
        error.starts_with(&format!("{}:1:", f.en.display())),
        "{error}"
    );
    key(&mut f.app, 'r');
    let meta = std::fs::symlink_metadata(&f.en).unwrap();
    assert!(meta.file_type().is_file(), "{meta:?}");
    assert_eq!(std::fs::read(&f.en).unwrap(), before);
    assert_eq!(
        std::fs::read_to_string(&outside).unwrap(),
        "precious = [not toml\n"
    );
}

/// A FIFO in the file's place: never opened to wait on, said on the check
/// screen, and `r` puts the file back.
#[test]
fn a_content_file_replaced_by_a_fifo_while_the_editor_runs_does_not_hang_and_is_reverted() {
    let mut f = fixture(vec![Box::new(|file: &Path| {
        std::fs::remove_file(file).unwrap();
        nix::unistd::mkfifo(file, nix::sys::stat::Mode::S_IRWXU).unwrap();
        Ok(())
    })]);
    reader(&mut f);
    let before = std::fs::read(&f.en).unwrap();
    key(&mut f.app, 'E');
    let error = check_error(&f.app);
    assert!(error.contains("FIFO"), "{error}");
    assert!(error.starts_with(&f.en.display().to_string()), "{error}");
    key(&mut f.app, 'r');
    assert!(std::fs::symlink_metadata(&f.en).unwrap().is_file());
    assert_eq!(std::fs::read(&f.en).unwrap(), before);
    assert_eq!(section_shown(&f.app), 0);
}

/// A real editor process that exits non-zero without writing: one line
/// on the status line, the file as it was, the reader where it was.
#[test]
fn an_editor_that_exits_non_zero_leaves_the_content_file_as_it_was() {
    let mut f = fixture(Vec::new());
    f.app.services.editor = Box::new(Spawn::from_setting("false"));
    reader(&mut f);
    let before = std::fs::read(&f.en).unwrap();
    key(&mut f.app, 'E');
    let said = f.app.status.clone().unwrap();
    assert!(said.error);
    assert!(
        said.text.starts_with("the editor `false` failed"),
        "{}",
        said.text
    );
    assert_eq!(std::fs::read(&f.en).unwrap(), before);
    assert_eq!(section_shown(&f.app), 0);
}

/// A bundled deck's explanation: the deck is copied into the library with
/// its explanations (the one journaled install `decks add` uses) and the
/// copy's content file edited; loaded again, the library's copy with its
/// explanations stands in for the bundled deck.
#[test]
fn a_bundled_decks_explanation_is_edited_in_its_library_copy() {
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
        "title = 'The big picture: where the textbook oscillator stops'",
        "title = 'The big picture, edited'",
    ));
    app.services.editor = Box::new(editor.clone());
    app.services.library = Some(Box::new(EditLibrary::new(
        dir.path().to_path_buf(),
        &library,
    )));
    let i = app
        .decks
        .iter()
        .position(|d| d.id == "oscillations")
        .unwrap();
    app.push(Screen::Reader(ReaderState::new(i)));
    key(&mut app, 'E');
    let copy = dir.path().join("content/oscillations/en.toml");
    assert_eq!(*editor.opened.borrow(), [(copy.clone(), 9)]);
    let said = status(&app);
    assert!(said.contains("explanations checked and reloaded"), "{said}");
    assert!(
        said.contains("bundled deck copied into your library"),
        "{said}"
    );
    assert_eq!(app.decks[i].path, lib.join("oscillations.toml"));
    assert!(render(&app).contains("The big picture, edited"));
    // Loaded again: the library's copy, with the edited explanation.
    let again = load_with(sources());
    assert_eq!(again.loaded.errors(), 0, "{}", again.loaded.render_all());
    let d = again
        .loaded
        .decks
        .iter()
        .find(|d| d.id == "oscillations")
        .unwrap();
    assert_eq!(d.path, lib.join("oscillations.toml"));
    assert_eq!(
        d.section("big-picture").unwrap().title.get("en"),
        "The big picture, edited"
    );
}

/// A large deck of cards is kept in the deck cache with the hashes of its
/// content files; an explanation written through `E` changes them, so the
/// next load validates the deck afresh and has the new section (a cache
/// that missed the content files would give the deck without it).
#[test]
fn a_content_edit_is_seen_through_the_deck_cache() {
    use crate::deck::DeckCache;
    use crate::deck::files::{Disk, Tree};
    let dir = tempfile::tempdir().unwrap();
    let mut deck = String::from(
        "[deck]\nid = \"big\"\ntitle = { en = 'Big', hi-Latn = 'Big' }\nlanguages = [\"en\", \"hi-Latn\"]\n",
    );
    for i in 0..400 {
        deck.push_str(&format!(
            "\n[[card]]\nid = \"c{i}\"\nfront = {{ en = 'Question number {i} about a body spinning freely in space', hi-Latn = 'Sawaal {i}' }}\nback = {{ en = 'Answer number {i}: the angular momentum stays fixed', hi-Latn = 'Jawab {i}' }}\n"
        ));
    }
    assert!(deck.len() >= crate::deck::cache::MIN_CACHED_BYTES);
    let decks = dir.path().join("decks");
    write(&decks.join("big.toml"), &deck);
    let en = dir.path().join("content/big/en.toml");
    write(&en, "");
    write(&dir.path().join("content/big/hi-Latn.toml"), "");
    let cache_dir = dir.path().join("cache");
    let cache = DeckCache::new(cache_dir.clone(), "test build".into());
    let load = || {
        let sources: Vec<(&dyn Tree, PathBuf)> = vec![(&Disk, decks.clone())];
        crate::deck::load_sources_cached(&sources, Some(&cache)).0
    };
    let first = load();
    assert_eq!(first.errors(), 0, "{}", first.render_all());
    assert!(
        std::fs::read_dir(&cache_dir).unwrap().count() > 0,
        "the deck is kept in the cache"
    );
    let mut app = Tui::new(first.decks, services(&dir), "en", Theme::PLAIN);
    app.size = (100, 30);
    let editor = Scripted::default();
    // The learner writes the first section, in both languages' files.
    editor.steps.borrow_mut().push(Box::new(|file: &Path| {
        let section = |title: &str| {
            format!("[[section]]\nid = \"spin\"\ntitle = '{title}'\nbody = '''\nFree spin.\n'''\n")
        };
        std::fs::write(file, section("Spin")).unwrap();
        std::fs::write(
            file.with_file_name("hi-Latn.toml"),
            section("Spin (Hinglish)"),
        )
        .unwrap();
        Ok(())
    }));
    app.services.editor = Box::new(editor.clone());
    app.push(Screen::Reader(ReaderState::new(0)));
    key(&mut app, 'E');
    // No section yet: the file from its top.
    assert_eq!(*editor.opened.borrow(), [(en.clone(), 1)]);
    assert_eq!(app.decks[0].sections.len(), 1, "{}", status(&app));
    assert!(render(&app).contains("Free spin."));
    let again = load();
    assert_eq!(again.errors(), 0, "{}", again.render_all());
    assert_eq!(again.decks[0].sections.len(), 1);
    assert_eq!(again.decks[0].cards.len(), 400);
}
