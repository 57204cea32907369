//! Editing a deck where the learner studies: `E` opens the learner's
//! editor at the item's line in its deck file, `A` appends a new card of
//! the current card's kind and opens it the same way. A bundled deck is
//! first copied into the library (the copy then replaces it). On return
//! the file is checked as `flipcard check FILE` checks it; a deck that
//! passes replaces the one in the app (its index unchanged, so every
//! screen keeps its place) and the screens below are told; one that fails
//! opens [`super::screens::edit_check`] with the first error, to edit
//! again or revert the file.
//!
//! A screen asks for an edit with [`request`]; the event loop, which owns
//! the terminal, carries it out with [`run_pending`], leaving the
//! terminal's raw mode and alternate screen while the editor runs.

use std::path::PathBuf;

use crate::deck::places::{ItemTable, item_line};
use crate::deck::{CardKind, Deck};
use crate::io::Durability;
use crate::sched::{Direction, ItemKey};

use super::app::App;
use super::i18n::edit as words;
use super::screens::Screen;
use super::screens::edit_check::EditCheckState;
use super::stack::Tui;

/// What to edit.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// The item's table (a card, a prompt, a derivation).
    Item(ItemKey),
    /// A new card of this kind, appended to the deck file.
    NewCard(CardKind),
}

/// An edit under way: the file, what it held before, where the editor
/// opens it.
#[derive(Debug, Clone, PartialEq)]
pub struct Session {
    /// The deck's id (the deck keeps its place in `App::decks`).
    pub deck: String,
    pub path: PathBuf,
    /// The file before the edit (and before a new card's template): what
    /// `r` writes back.
    pub original: Vec<u8>,
    pub target: Target,
    /// The new card's id (`A`).
    pub new_card: Option<String>,
    /// The file with the new card's template, as the editor first got it.
    pub template: Option<Vec<u8>>,
    /// The line the editor opens at.
    pub line: usize,
    /// The deck was bundled and is now a copy in the library.
    pub copied: bool,
}

/// An edit the event loop is to carry out.
#[derive(Debug, Clone, PartialEq)]
pub enum Pending {
    /// A first edit of the deck at `App::decks[deck]`.
    Start { deck: usize, target: Target },
    /// The same edit again (its check failed).
    Again(Session),
}

/// What a screen below is told after an edit passed its check.
#[derive(Debug, Clone, PartialEq)]
pub struct Edited {
    /// The deck's place in `App::decks`.
    pub deck: usize,
    pub target: Target,
    /// The card added (`A`).
    pub new_card: Option<String>,
}

/// Asks the event loop to edit `target` of deck `deck`.
pub fn request(app: &mut App, deck: usize, target: Target) {
    app.edit = Some(Pending::Start { deck, target });
}

/// What the terminal does around the editor: the real terminal leaves raw
/// mode and the alternate screen; a test's does nothing.
pub trait Suspend {
    fn leave(&mut self);
    fn enter(&mut self);
}

/// No terminal to give up (tests over a `TestBackend`).
pub struct NoTerminal;

impl Suspend for NoTerminal {
    fn leave(&mut self) {}
    fn enter(&mut self) {}
}

/// Carries out the edit a screen asked for, if any: prepares the file
/// (copying a bundled deck, appending a new card), runs the editor with
/// the terminal given up, then checks the file and reloads the deck or
/// shows the first error.
pub fn run_pending(tui: &mut Tui, terminal: &mut dyn Suspend) {
    let Some(pending) = tui.edit.take() else {
        return;
    };
    let session = match pending {
        Pending::Start { deck, target } => match prepare(tui, deck, target) {
            Ok(s) => s,
            Err(e) => {
                tui.error(e);
                return;
            }
        },
        Pending::Again(s) => s,
    };
    let before = match crate::io::read_regular(&session.path) {
        Ok(b) => b,
        Err(e) => {
            tui.error(format!("{}: {e}", session.path.display()));
            return;
        }
    };
    terminal.leave();
    let ran = tui.services.editor.run(&session.path, session.line);
    terminal.enter();
    finish(tui, session, &before, ran);
}

/// The file to edit and where: a bundled deck copied into the library
/// first, a new card's template appended.
fn prepare(app: &mut App, deck: usize, target: Target) -> Result<Session, String> {
    let d = app.decks.get(deck).ok_or("no such deck")?;
    let id = d.id.clone();
    let bundled = app
        .services
        .library
        .as_ref()
        .is_some_and(|l| l.is_bundled(&id));
    let (path, copied) = if bundled {
        let not_a_file = app_words(app, words::NOT_A_FILE);
        let library = app.services.library.as_mut().ok_or(not_a_file)?;
        (library.copy_bundled(&id)?, true)
    } else {
        (d.path.clone(), false)
    };
    if path.extension().is_none_or(|e| e != "toml") {
        return Err(app_words(app, words::NOT_A_FILE));
    }
    let original =
        crate::io::read_regular(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = String::from_utf8_lossy(&original).into_owned();
    let mut session = Session {
        deck: id,
        path,
        original: original.clone(),
        target: target.clone(),
        new_card: None,
        template: None,
        line: 1,
        copied,
    };
    match &target {
        Target::Item(key) => {
            let table = match key.direction {
                Direction::Predict => ItemTable::Prompt,
                Direction::Derive => ItemTable::Derivation,
                _ => ItemTable::Card,
            };
            session.line = item_line(&session.path, &text, table, &key.card).unwrap_or(1);
        }
        Target::NewCard(kind) => {
            let d = &app.decks[deck];
            let states = app
                .services
                .study
                .store
                .states(&d.id)
                .map_err(|e| e.to_string())?;
            let taken = |card: &str| states.keys().any(|k| k.card == card);
            let new_id = crate::deck::template::fresh_card_id(d, &taken);
            let mut with = text.clone();
            if !with.is_empty() && !with.ends_with('\n') {
                with.push('\n');
            }
            with.push_str(&crate::deck::template::card_table(
                *kind,
                &new_id,
                &d.languages,
            ));
            let id_line = format!("\nid = \"{new_id}\"\n");
            session.line = with
                .rfind(&id_line)
                .map_or(1, |at| with[..at].matches('\n').count() + 2);
            crate::io::write_atomic(&session.path, with.as_bytes(), Durability::Synced)
                .map_err(|e| format!("{}: {e}", session.path.display()))?;
            session.new_card = Some(new_id);
            session.template = Some(with.into_bytes());
        }
    }
    Ok(session)
}

fn app_words(app: &App, w: super::i18n::Words) -> String {
    w.get(&app.lang).to_string()
}

/// The first error of `flipcard check FILE` on the deck file `path`, as
/// one line (`file:line:col: error: …`), with its line; or the deck.
pub fn check(path: &std::path::Path) -> Result<Deck, (String, usize)> {
    let mut loaded = crate::deck::load_paths(&[path.to_path_buf()]);
    if loaded.errors() == 0 {
        let judged = crate::predict::audit::check_loaded(&loaded);
        loaded.diagnostics.extend(judged);
    }
    if let Some(d) = loaded.diagnostics.iter().find(|d| d.is_error()) {
        let mut line = crate::text::safe::one_line(&d.headline()).into_owned();
        if let Some(hint) = &d.hint {
            line.push_str(" (");
            line.push_str(&crate::text::safe::one_line(hint));
            line.push(')');
        }
        return Err((line, d.line.max(1)));
    }
    match loaded.decks.pop() {
        Some(deck) if loaded.decks.is_empty() => Ok(deck),
        _ => Err((format!("{}: not one deck", path.display()), 1)),
    }
}

/// After the editor: reload the deck or show the first error.
fn finish(tui: &mut Tui, mut session: Session, before: &[u8], ran: Result<(), String>) {
    let now = match crate::io::read_regular(&session.path) {
        Ok(b) => b,
        Err(e) => {
            tui.error(format!("{}: {e}", session.path.display()));
            return;
        }
    };
    if let Err(e) = &ran
        && now == before
    {
        // Nothing was edited: a template appended for it goes again.
        let mut said = e.clone();
        if session.template.is_some()
            && !matches!(tui.screen(), Screen::EditCheck(_))
            && let Err(e) = revert(&session)
        {
            said = format!("{said}; {e}");
        }
        tui.error(said);
        return;
    }
    // A new card left as its template is no card.
    if session.template.as_deref() == Some(&now[..]) {
        close_check(tui);
        match revert(&session) {
            Ok(()) => {
                let said = app_words(tui, words::NOTHING_ADDED);
                tui.info(said)
            }
            Err(e) => tui.error(e),
        }
        return;
    }
    let deck = match check(&session.path) {
        Ok(d) => d,
        Err((message, line)) => {
            session.line = line;
            let state = EditCheckState::new(session, message);
            close_check(tui);
            tui.push(Screen::EditCheck(Box::new(state)));
            return;
        }
    };
    close_check(tui);
    let Some(index) = tui.decks.iter().position(|d| d.id == session.deck) else {
        return;
    };
    tui.decks[index] = deck;
    let edited = Edited {
        deck: index,
        target: session.target.clone(),
        new_card: session.new_card.clone(),
    };
    tui.each_screen(|app, screen| match screen {
        Screen::Review(r) => r.deck_edited(app, &edited),
        Screen::Browser(b) => b.deck_edited(app, &edited),
        _ => {}
    });
    let mut said = vec![if now == session.original {
        app_words(tui, words::UNCHANGED)
    } else {
        app_words(tui, words::SAVED)
    }];
    if session.copied {
        said.push(format!(
            "{}: {}",
            app_words(tui, words::COPIED),
            session.path.display()
        ));
    }
    let d = &tui.decks[index];
    match (&session.target, &session.new_card) {
        (_, Some(id)) if d.card(id).is_some() => {
            said.push(format!("{} `{id}`", app_words(tui, words::ADDED)));
        }
        (Target::Item(key), _) if !item_exists(d, key) => {
            let id = crate::text::safe::one_line(&key.card).into_owned();
            let gone = app_words(tui, words::ID_CHANGED);
            tui.error(format!("{}; `{id}` {gone}", said.join("; ")));
            return;
        }
        _ => {}
    }
    tui.info(said.join("; "));
}

/// Whether the deck still has the item `key` names.
pub fn item_exists(deck: &Deck, key: &ItemKey) -> bool {
    crate::sched::deck_items(deck).contains(key)
}

/// The file back as it was before the edit, written atomically.
pub fn revert(session: &Session) -> Result<(), String> {
    crate::io::write_atomic(&session.path, &session.original, Durability::Synced)
        .map_err(|e| format!("{}: {e}", session.path.display()))
}

/// Closes the check screen of an earlier try, if it is on top.
fn close_check(tui: &mut Tui) {
    if matches!(tui.screen(), Screen::EditCheck(_)) {
        tui.stack.pop();
    }
}
