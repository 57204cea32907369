//! Carrying out an edit a screen asked for (`E`, `A`; see
//! [`super::edit`]): the file prepared (a bundled deck copied into the
//! library, a new card's template appended), the editor run with the
//! terminal given up, then the file checked, the deck reloaded in place and
//! the screens told, or the first error shown on
//! [`super::screens::edit_check`].

use crate::deck::places::{ItemTable, item_line, section_line};
use crate::io::Durability;
use crate::sched::Direction;

use super::app::App;
use super::edit::{Edited, Pending, Session, Suspend, Target, check, item_exists, revert};
use super::i18n::edit as words;
use super::screens::Screen;
use super::screens::edit_check::EditCheckState;
use super::stack::Tui;

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
            tui.error(
                crate::text::safe::one_line(&format!("{}: {e}", session.path.display()))
                    .into_owned(),
            );
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
    let (deck_file, copied) = if bundled {
        let not_a_file = app_words(app, words::NOT_A_FILE);
        let library = app.services.library.as_mut().ok_or(not_a_file)?;
        (library.copy_bundled(&id)?, true)
    } else {
        (d.path.clone(), false)
    };
    if deck_file.extension().is_none_or(|e| e != "toml") {
        return Err(app_words(app, words::NOT_A_FILE));
    }
    // An explanation is edited in its language's content file, found
    // beside the deck file as the loader finds it (the library's copy of
    // a bundled deck has its own).
    let path = match &target {
        Target::Section { lang, .. } => {
            crate::deck::content_dir(&deck_file, &id).join(format!("{lang}.toml"))
        }
        _ => deck_file.clone(),
    };
    let original = crate::io::read_regular(&path).map_err(|e| {
        crate::text::safe::one_line(&format!("{}: {e}", path.display())).into_owned()
    })?;
    let text = String::from_utf8_lossy(&original).into_owned();
    let mut session = Session {
        deck: id,
        write_to: super::edit::resolved(&path),
        path,
        deck_file,
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
        Target::Section { id, .. } => {
            session.line = id
                .as_deref()
                .and_then(|id| section_line(&session.path, &text, id))
                .unwrap_or(1);
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

/// After the editor: reload the deck or show the first error.
fn finish(tui: &mut Tui, mut session: Session, before: &[u8], ran: Result<(), String>) {
    let now = match crate::io::read_regular(&session.path) {
        Ok(b) => b,
        Err(e) => {
            // Something else than a file where the file was (a FIFO, a
            // link to one): never read, and `r` puts the file back.
            let message = crate::text::safe::one_line(&format!("{}: {e}", session.path.display()))
                .into_owned();
            let state = EditCheckState::new(session, message);
            close_check(tui);
            tui.push(Screen::EditCheck(Box::new(state)));
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
    let deck = match check(&session.deck_file) {
        Ok(d) => d,
        Err(failed) => {
            // Edited again at the error when it is in the file edited
            // (an error the edit caused in the deck file, a link to an
            // anchor taken out, is shown with its own file:line:col).
            if same_file(&failed.file, &session.path) {
                session.line = failed.line;
            }
            let state = EditCheckState::new(session, failed.message);
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
    let top = tui.stack.len() - 1;
    let mut at = 0;
    tui.each_screen(|app, screen| {
        let on_top = at == top;
        at += 1;
        match screen {
            Screen::Review(r) => r.deck_edited(app, &edited, on_top),
            Screen::Browser(b) => b.deck_edited(app, &edited),
            Screen::Info(i) => i.deck_edited(app, &edited),
            Screen::Reader(r) => r.deck_edited(app, &edited),
            Screen::Predict(p) => p.deck_edited(app, &edited),
            _ => {}
        }
    });
    let explanations = matches!(session.target, Target::Section { .. });
    let mut said = vec![match (now == session.original, explanations) {
        (true, false) => app_words(tui, words::UNCHANGED),
        (false, false) => app_words(tui, words::SAVED),
        (true, true) => app_words(tui, words::CONTENT_UNCHANGED),
        (false, true) => app_words(tui, words::CONTENT_SAVED),
    }];
    if session.copied {
        let path = session.path.display().to_string();
        said.push(format!(
            "{}: {}",
            app_words(tui, words::COPIED),
            crate::text::safe::one_line(&path)
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

/// Whether two paths name one file (a relative and an absolute name, or
/// one through a link).
fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    a == b || crate::io::canonical(a) == crate::io::canonical(b)
}

/// Closes the check screen of an earlier try, if it is on top.
fn close_check(tui: &mut Tui) {
    if matches!(tui.screen(), Screen::EditCheck(_)) {
        tui.stack.pop();
    }
}
