//! What every screen shares: the decks, the language, the services, the
//! status line, the terminal size, the help overlay. Domain data (decks,
//! schedules, the review log) belongs to the domain modules; screens keep
//! only indices and what the learner typed. The screens themselves are
//! open on the stack of [`super::stack::Tui`], over this.

use crate::deck::Deck;

use super::i18n::{self, Msg};
use super::services::Services;
use super::theme::Theme;

/// A one-line message at the bottom of the screen.
#[derive(Debug, Clone, PartialEq)]
pub struct Status {
    pub text: String,
    pub error: bool,
}

/// How loading the decks went, for the home screen to explain what is
/// missing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeckLoad {
    /// The folder (or file) the decks came from.
    pub from: Option<std::path::PathBuf>,
    /// Errors reported in all.
    pub errors: usize,
    /// Files with at least one error (their decks are left out).
    pub failed_files: usize,
    /// Those deck files, as the sources name them.
    pub failed: Vec<String>,
}

pub struct App {
    pub decks: Vec<Deck>,
    /// What loading the decks went through (shown on the home screen).
    pub deck_load: DeckLoad,
    pub lang: String,
    pub theme: Theme,
    pub help: bool,
    /// First line of the help overlay shown, when it is taller than the screen.
    pub help_scroll: usize,
    pub quit: bool,
    /// Terminal size in cells (width, height).
    pub size: (u16, u16),
    pub status: Option<Status>,
    pub services: Services,
    /// Time the last simulation step and the last frame took (µs), measured
    /// by the event loop; shown in the diagnostics line.
    pub frame_us: FrameTimes,
    /// An edit a screen asked for (`E`, `A`), carried out by the event
    /// loop, which owns the terminal ([`super::edit_run::run_pending`]).
    pub edit: Option<super::edit::Pending>,
    /// What the check screen of an edit says once it has closed (closing
    /// a screen clears the status line).
    pub edit_said: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameTimes {
    pub physics: u64,
    pub draw: u64,
}

impl App {
    /// The shared state alone; [`super::stack::Tui::new`] opens the home
    /// screen over it.
    pub fn new(decks: Vec<Deck>, services: Services, lang: &str, theme: Theme) -> App {
        let lang = if lang == i18n::HINGLISH {
            i18n::HINGLISH
        } else {
            i18n::ENGLISH
        };
        App {
            decks,
            deck_load: DeckLoad::default(),
            lang: lang.to_string(),
            theme,
            help: false,
            help_scroll: 0,
            quit: false,
            size: (80, 24),
            status: None,
            services,
            frame_us: FrameTimes::default(),
            edit: None,
            edit_said: None,
        }
    }

    pub fn tr(&self, msg: Msg) -> &'static str {
        i18n::tr(&self.lang, msg)
    }

    /// `n` with its noun in the interface language: "1 card", "3 cards".
    pub fn count(&self, n: usize, noun: i18n::Noun) -> String {
        i18n::count(&self.lang, n, noun)
    }

    /// Whether a sync runs in the background (the event loop then ticks).
    pub fn syncing(&self) -> bool {
        self.services.sync.as_ref().is_some_and(|s| s.busy())
    }

    /// Asks the event loop to edit `target` of deck `deck` (`E`, `A`).
    pub fn request_edit(&mut self, deck: usize, target: super::edit::Target) {
        self.edit = Some(super::edit::Pending::Start { deck, target });
    }

    pub fn info(&mut self, text: impl Into<String>) {
        self.status = Some(Status {
            text: text.into(),
            error: false,
        });
    }

    pub fn error(&mut self, text: impl Into<String>) {
        self.status = Some(Status {
            text: text.into(),
            error: true,
        });
    }
}
