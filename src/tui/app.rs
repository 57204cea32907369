//! The app's view state: which screens are open, the language, the terminal
//! size. Domain data (decks, schedules, the review log) belongs to the
//! domain modules; screens keep only indices and what the learner typed.

use crate::deck::Deck;

use super::i18n::{self, Msg};
use super::screens::Screen;
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
    /// Open screens; the last is shown. Never empty: the home screen is first.
    pub stack: Vec<Screen>,
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
}

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameTimes {
    pub physics: u64,
    pub draw: u64,
}

impl App {
    pub fn new(decks: Vec<Deck>, services: Services, lang: &str, theme: Theme) -> App {
        let lang = if lang == i18n::HINGLISH {
            i18n::HINGLISH
        } else {
            i18n::ENGLISH
        };
        let mut app = App {
            decks,
            deck_load: DeckLoad::default(),
            lang: lang.to_string(),
            theme,
            stack: Vec::new(),
            help: false,
            help_scroll: 0,
            quit: false,
            size: (80, 24),
            status: None,
            services,
            frame_us: FrameTimes::default(),
        };
        let home = super::screens::home::HomeState::new(&app);
        app.stack.push(Screen::Home(home));
        app
    }

    pub fn tr(&self, msg: Msg) -> &'static str {
        i18n::tr(&self.lang, msg)
    }

    /// `n` with its noun in the interface language: "1 card", "3 cards".
    pub fn count(&self, n: usize, noun: i18n::Noun) -> String {
        i18n::count(&self.lang, n, noun)
    }

    pub fn screen(&self) -> &Screen {
        // The stack is never empty (the home screen is never popped).
        &self.stack[self.stack.len() - 1]
    }

    pub fn screen_mut(&mut self) -> &mut Screen {
        let n = self.stack.len();
        &mut self.stack[n - 1]
    }

    pub fn push(&mut self, screen: Screen) {
        self.status = None;
        self.stack.push(screen);
    }

    /// Closes the top screen; on the home screen, quits.
    pub fn pop(&mut self) {
        self.status = None;
        if self.stack.len() > 1 {
            let closed = self.stack.pop();
            if closed.is_some_and(|c| c.view().ends_session()) {
                self.start_sync();
            }
            if let Screen::Home(_) = self.screen() {
                let fresh = super::screens::home::HomeState::new(self);
                if let Screen::Home(h) = self.screen_mut() {
                    h.refresh(fresh);
                }
            }
        } else {
            self.quit = true;
        }
    }

    /// Starts a sync (when `sync_dir` is set) after a session closes; its
    /// end is said on the status line when [`App::poll_sync`] finds it.
    fn start_sync(&mut self) {
        let config = self.services.study.config.clone();
        let Some(syncer) = self.services.sync.as_mut() else {
            return;
        };
        syncer.start(&config);
        self.poll_sync();
    }

    /// Whether a sync runs in the background (the event loop then ticks).
    pub fn syncing(&self) -> bool {
        self.services.sync.as_ref().is_some_and(|s| s.busy())
    }

    /// Says what a background sync that just ended did, and counts the home
    /// screen's cards again when it brought something. True when the screen
    /// changed.
    pub fn poll_sync(&mut self) -> bool {
        let Some(done) = self.services.sync.as_mut().and_then(|s| s.poll()) else {
            return false;
        };
        match done {
            Ok(s) => {
                if !s.warnings.is_empty() {
                    self.error(s.warnings.join("; "));
                } else if s.written + s.merged > 0 {
                    let lang = self.lang.clone();
                    self.info(format!(
                        "{}: {} {}, {} {}",
                        super::i18n::sync::SYNCED.get(&lang),
                        s.written,
                        super::i18n::sync::SENT.get(&lang),
                        s.merged,
                        super::i18n::sync::RECEIVED.get(&lang),
                    ));
                }
                if s.merged > 0 && matches!(self.screen(), Screen::Home(_)) {
                    let fresh = super::screens::home::HomeState::new(self);
                    if let Screen::Home(h) = self.screen_mut() {
                        h.refresh(fresh);
                    }
                }
            }
            Err(e) => self.error(e),
        }
        true
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

    /// Whether a simulation is playing, so the event loop must tick.
    pub fn animating(&self) -> bool {
        self.screen().view().animating()
    }
}

impl App {
    /// Where the keyboard is (screen and mode).
    pub fn context(&self) -> super::keymap::Context {
        self.screen().context()
    }
}
