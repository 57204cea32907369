//! Editing a deck where the learner studies: `E` opens the learner's
//! editor at the item's line in its deck file (in the reader, at the
//! section's line in the content file of the language read), `A` appends
//! a new card of the current card's kind and opens it the same way. A
//! bundled deck is first copied into the library with its explanations
//! (the copy then replaces it). On return the deck is checked as
//! `flipcard check FILE` checks it (its content files with it); a deck that
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
    /// An explanation section (`id`; `None`: the file from its top, for a
    /// deck with no section yet) in the content file of `lang`.
    Section { id: Option<String>, lang: String },
}

/// An edit under way: the file, what it held before, where the editor
/// opens it.
#[derive(Debug, Clone, PartialEq)]
pub struct Session {
    /// The deck's id (the deck keeps its place in `App::decks`).
    pub deck: String,
    /// The file the editor opens: the deck file, or one of its content
    /// files.
    pub path: PathBuf,
    /// The deck file `flipcard check` checks (with its content files).
    pub deck_file: PathBuf,
    /// Where `r` writes the file back: `path` with the links it went
    /// through when the edit began resolved, so a link or a FIFO put in
    /// its place meanwhile is replaced, never written through.
    pub write_to: PathBuf,
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

/// The first error of a deck's check: one line (`file:line:col: error:
/// …`), the file it is in and its line there.
#[derive(Debug, Clone, PartialEq)]
pub struct Failed {
    pub message: String,
    pub file: PathBuf,
    pub line: usize,
}

/// The first error of `flipcard check FILE` on the deck file `path` (its
/// content files included); or the deck.
pub fn check(path: &std::path::Path) -> Result<Deck, Failed> {
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
        return Err(Failed {
            message: line,
            file: d.path.clone(),
            line: d.line.max(1),
        });
    }
    match loaded.decks.pop() {
        Some(deck) if loaded.decks.is_empty() => Ok(deck),
        _ => Err(Failed {
            message: crate::text::safe::one_line(&format!("{}: not one deck", path.display()))
                .into_owned(),
            file: path.to_path_buf(),
            line: 1,
        }),
    }
}

/// Whether the deck still has the item `key` names.
pub fn item_exists(deck: &Deck, key: &ItemKey) -> bool {
    crate::sched::deck_items(deck).contains(key)
}

/// The file back as it was before the edit, written atomically in place
/// of whatever is at its name now (a link or a FIFO put there while the
/// editor ran is replaced, what a link named is left alone).
pub fn revert(session: &Session) -> Result<(), String> {
    crate::io::replace_atomic(&session.write_to, &session.original, Durability::Synced).map_err(
        |e| crate::text::safe::one_line(&format!("{}: {e}", session.path.display())).into_owned(),
    )
}

/// Where `path` leads through its links now (itself when it is no link).
pub fn resolved(path: &std::path::Path) -> PathBuf {
    let mut current = path.to_path_buf();
    for _ in 0..40 {
        match crate::io::read_link(&current) {
            Ok(next) => {
                current = match current.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                }
            }
            Err(_) => return current,
        }
    }
    current
}
