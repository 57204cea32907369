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
//! A screen asks for an edit with `App::request_edit`; the event loop,
//! which owns the terminal, carries it out with
//! [`super::edit_run::run_pending`], leaving the terminal's raw mode and
//! alternate screen while the editor runs. Here, what the screens and the
//! run share: what is edited, the session, the check of the file.

use std::path::PathBuf;

use crate::deck::{CardKind, Deck};
use crate::io::Durability;
use crate::sched::ItemKey;

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

/// Whether the deck still has the item `key` names.
pub fn item_exists(deck: &Deck, key: &ItemKey) -> bool {
    crate::sched::deck_items(deck).contains(key)
}

/// The file back as it was before the edit, written atomically.
pub fn revert(session: &Session) -> Result<(), String> {
    crate::io::write_atomic(&session.path, &session.original, Durability::Synced)
        .map_err(|e| format!("{}: {e}", session.path.display()))
}
