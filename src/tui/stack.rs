//! The running terminal app: the [`App`] every screen shares and the stack
//! of screens open over it. The event loop, [`super::apply`] and
//! [`super::view::draw`] work on this; a screen gets the [`App`] alone and
//! asks for another screen by the [`super::screens::Nav`] it returns.

use std::ops::{Deref, DerefMut};

use crate::deck::Deck;

use super::app::App;
use super::i18n;
use super::keymap::Context;
use super::screens::Screen;
use super::screens::home::HomeState;
use super::services::Services;
use super::theme::Theme;

pub struct Tui {
    app: App,
    /// Open screens; the last is shown. Never empty: the home screen is first.
    pub stack: Vec<Screen>,
}

/// The shared state is read and changed through the app as a whole
/// (`app.lang`, `app.info(…)`), as the screens see it.
impl Deref for Tui {
    type Target = App;
    fn deref(&self) -> &App {
        &self.app
    }
}

impl DerefMut for Tui {
    fn deref_mut(&mut self) -> &mut App {
        &mut self.app
    }
}

impl Tui {
    /// The app on its home screen.
    pub fn new(decks: Vec<Deck>, services: Services, lang: &str, theme: Theme) -> Tui {
        let app = App::new(decks, services, lang, theme);
        let home = HomeState::new(&app);
        Tui {
            app,
            stack: vec![Screen::Home(home)],
        }
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
            let mut closed = self.stack.pop();
            // A prompt opened from the review screen hands its rating back.
            if let Some(Screen::Predict(p)) = &mut closed
                && let Some(rated) = p.rated.take()
                && let Some(Screen::Review(r)) = self.stack.last_mut()
            {
                r.answered_elsewhere(&self.app, rated);
            }
            if closed.is_some_and(|c| c.view().ends_session()) {
                self.start_sync();
            }
            if let Screen::Home(_) = self.screen() {
                let fresh = HomeState::new(self);
                if let Screen::Home(h) = self.screen_mut() {
                    h.refresh(fresh);
                }
            }
        } else {
            self.quit = true;
        }
    }

    /// Starts a sync (when `sync_dir` is set) after a session closes; its
    /// end is said on the status line when [`Tui::poll_sync`] finds it.
    fn start_sync(&mut self) {
        let config = self.services.study.config.clone();
        let Some(syncer) = self.services.sync.as_mut() else {
            return;
        };
        syncer.start(&config);
        self.poll_sync();
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
                        i18n::sync::SYNCED.get(&lang),
                        s.written,
                        i18n::sync::SENT.get(&lang),
                        s.merged,
                        i18n::sync::RECEIVED.get(&lang),
                    ));
                }
                if s.merged > 0 && matches!(self.screen(), Screen::Home(_)) {
                    let fresh = HomeState::new(self);
                    if let Screen::Home(h) = self.screen_mut() {
                        h.refresh(fresh);
                    }
                }
            }
            Err(e) => self.error(e),
        }
        true
    }

    /// Calls `f` on each open screen, bottom first, with the shared app
    /// (after an edit, each screen takes the reloaded deck).
    pub fn each_screen(&mut self, mut f: impl FnMut(&App, &mut Screen)) {
        for screen in self.stack.iter_mut() {
            f(&self.app, screen);
        }
    }

    /// Whether a simulation is playing, so the event loop must tick.
    pub fn animating(&self) -> bool {
        self.screen().view().animating()
    }

    /// Where the keyboard is (screen and mode).
    pub fn context(&self) -> Context {
        self.screen().context()
    }
}
