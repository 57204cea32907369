//! The terminal app. Owns view state only: decks, schedules, the review log
//! and the simulations come from `deck`, `sched`, `store` and `sim`.
//!
//! Every key becomes an [`Action`] ([`key_action`], through the screens'
//! `keymap` tables) that [`apply`] carries out without a terminal;
//! [`view::draw`] renders the state. The screens share the [`App`]; the
//! [`Tui`] holds it and the stack of open screens. The event loop
//! blocks on input when idle and ticks at about 30 frames per second only
//! while a simulation plays.

pub mod action;
pub mod app;
pub mod derivation;
pub mod edit;
pub mod edit_run;
pub mod geometry;
pub mod i18n;
pub mod keymap;
pub mod layout;
pub mod live;
pub mod logplot;
pub mod memory;
pub mod plots;
pub mod screens;
pub mod services;
pub mod solid;
pub mod stack;
pub mod system_plots;
#[cfg(test)]
mod testkit;
#[cfg(test)]
mod tests;
pub mod theme;
pub mod update;
pub mod view;
pub mod wrap;

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::Context as _;
use crossterm::event::{self, Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use ratatui::DefaultTerminal;

pub use action::Action;
pub use app::App;
pub use stack::Tui;
pub use update::apply;

/// Time between frames while a simulation plays (about 30 per second).
const FRAME: Duration = Duration::from_millis(33);

/// How often the app looks for the end of a sync running in the background.
const SYNC_POLL: Duration = Duration::from_millis(100);

/// Runs the app in the terminal until the learner quits. Everything that
/// can fail with a message (the store, the decks) is done by the caller
/// before this switches the terminal to raw mode, so errors print as
/// ordinary lines.
pub fn run(app: &mut Tui) -> anyhow::Result<()> {
    let busy = Arc::new(Mutex::new(()));
    watch_signals(&busy)?;
    let mut terminal = ratatui::try_init().context("cannot set up the terminal")?;
    let result = event_loop(&mut terminal, app, &busy);
    ratatui::restore();
    result
}

/// Opens the review of a deck at once (`flipcard review [DECK] [--cram]`);
/// the first deck when none is named.
pub fn open_review(app: &mut Tui, deck: Option<&str>, cram: bool) -> anyhow::Result<()> {
    let deck = match deck {
        Some(id) => app.decks.iter().position(|d| d.id == id).ok_or_else(|| {
            let ids: Vec<&str> = app.decks.iter().map(|d| d.id.as_str()).collect();
            anyhow::anyhow!("no deck `{id}`; decks: {}", ids.join(", "))
        })?,
        None if app.decks.is_empty() => anyhow::bail!("no decks to review"),
        None => 0,
    };
    if let screens::Screen::Home(h) = app.screen_mut() {
        h.select_deck(deck);
    }
    let review = screens::review::ReviewState::open(app, deck, cram).map_err(anyhow::Error::msg)?;
    app.push(screens::Screen::Review(Box::new(review)));
    Ok(())
}

/// Opens a review of the cards of `deck` (every deck when none is named)
/// that `filter` chooses; a filter no card passes is an error, said before
/// the terminal switches.
pub fn open_filtered_review(
    app: &mut Tui,
    deck: Option<&str>,
    filter: &crate::catalog::Filter,
    cram: bool,
) -> anyhow::Result<()> {
    let index = match deck {
        Some(id) => Some(app.decks.iter().position(|d| d.id == id).ok_or_else(|| {
            let ids: Vec<&str> = app.decks.iter().map(|d| d.id.as_str()).collect();
            anyhow::anyhow!("no deck `{id}`; decks: {}", ids.join(", "))
        })?),
        None if app.decks.is_empty() => anyhow::bail!("no decks to review"),
        None => None,
    };
    let items =
        screens::review::filtered_items(app, index, filter, cram).map_err(anyhow::Error::msg)?;
    if items.is_empty() {
        let which = match index {
            Some(i) => format!("of deck `{}`", app.decks[i].id),
            None => "of any deck".to_string(),
        };
        anyhow::bail!(
            "no card {which} matches the filter{}",
            if cram {
                ""
            } else {
                " (suspended and buried cards are left out)"
            }
        );
    }
    if let Some(i) = index
        && let screens::Screen::Home(h) = app.screen_mut()
    {
        h.select_deck(i);
    }
    let review = screens::review::ReviewState::open_listed(app, index, items, cram)
        .map_err(anyhow::Error::msg)?;
    app.push(screens::Screen::Review(Box::new(review)));
    Ok(())
}

/// On SIGTERM, SIGHUP, SIGINT or SIGQUIT: wait until the event loop is idle
/// (it holds `busy` while it changes state or draws, so a rating being
/// written finishes first), restore the terminal and exit.
fn watch_signals(busy: &Arc<Mutex<()>>) -> anyhow::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGTERM, SIGHUP, SIGINT, SIGQUIT])
        .context("cannot install signal handlers")?;
    let busy = Arc::clone(busy);
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let _idle = busy.lock();
            ratatui::restore();
            std::process::exit(128 + signal);
        }
    });
    Ok(())
}

fn event_loop(
    terminal: &mut DefaultTerminal,
    app: &mut Tui,
    busy: &Mutex<()>,
) -> anyhow::Result<()> {
    let size = terminal.size()?;
    app.size = (size.width, size.height);
    let mut dirty = true;
    let mut last_tick: Option<Instant> = None;
    loop {
        let guard = busy.lock().unwrap_or_else(|e| e.into_inner());
        if app.animating() {
            let now = Instant::now();
            match last_tick {
                None => last_tick = Some(now),
                Some(t) if now.duration_since(t) >= FRAME => {
                    let t0 = Instant::now();
                    apply(app, Action::Tick(now.duration_since(t)));
                    app.frame_us.physics = t0.elapsed().as_micros() as u64;
                    last_tick = Some(now);
                    dirty = true;
                }
                Some(_) => {}
            }
        } else {
            last_tick = None;
        }
        if app.quit {
            return Ok(());
        }
        if dirty {
            let t0 = Instant::now();
            terminal.draw(|frame| view::draw(frame, app))?;
            app.frame_us.draw = t0.elapsed().as_micros() as u64;
            dirty = false;
        }
        drop(guard);

        let event = match last_tick {
            Some(t) if app.animating() => {
                let wait = (t + FRAME).saturating_duration_since(Instant::now());
                if event::poll(wait)? {
                    Some(event::read()?)
                } else {
                    None
                }
            }
            // A sync runs in the background: look for its end now and then.
            _ if app.syncing() => {
                if event::poll(SYNC_POLL)? {
                    Some(event::read()?)
                } else {
                    None
                }
            }
            // Idle: block until something happens.
            _ => Some(event::read()?),
        };
        let _guard = busy.lock().unwrap_or_else(|e| e.into_inner());
        if app.poll_sync() {
            dirty = true;
        }
        if let Some(event) = event
            && let Some(action) = event_action(app, event)
        {
            apply(app, action);
            if app.edit.is_some() {
                edit_run::run_pending(app, &mut GivenUp(terminal));
            }
            dirty = true;
        }
    }
}

/// The terminal handed to the learner's editor and taken back: cooked
/// mode and the main screen while the editor runs, then raw mode, the
/// alternate screen and a full redraw.
struct GivenUp<'a>(&'a mut DefaultTerminal);

impl edit::Suspend for GivenUp<'_> {
    fn leave(&mut self) {
        ratatui::restore();
    }
    fn enter(&mut self) {
        let _ = crossterm::terminal::enable_raw_mode();
        let _ = crossterm::execute!(std::io::stdout(), crossterm::terminal::EnterAlternateScreen);
        let _ = self.0.clear();
    }
}

fn event_action(app: &Tui, event: Event) -> Option<Action> {
    match event {
        Event::Key(key) => key_action(app, key),
        Event::Resize(w, h) => Some(Action::Resize(w, h)),
        _ => None,
    }
}

/// The action a key press stands for in the app's current state: the top
/// screen's table for where the keyboard is, then the rows every screen has.
pub fn key_action(app: &Tui, key: KeyEvent) -> Option<Action> {
    use KeyCode::Char;
    if key.kind == KeyEventKind::Release {
        return None;
    }
    if key.modifiers.contains(KeyModifiers::CONTROL) {
        return match key.code {
            Char('c') | Char('d') => Some(Action::Quit),
            _ => None,
        };
    }
    // While the "please enlarge" message stands in for the screen, keys
    // would act on something the learner cannot see (a rating, a commit);
    // only `q`, which the message offers, quits.
    let (w, h) = app.size;
    if w < layout::MIN_WIDTH || h < layout::MIN_HEIGHT {
        return (key.code == Char('q')).then_some(Action::Quit);
    }
    if app.help {
        // A help taller than the screen scrolls; any other key closes it.
        let scrolls = view::help_scroll_max(app) > 0;
        return Some(match key.code {
            KeyCode::Down | Char('j') if scrolls => Action::HelpDown,
            KeyCode::Up | Char('k') if scrolls => Action::HelpUp,
            _ => Action::CloseHelp,
        });
    }
    let rows = screens::bindings(app.context());
    if let Some(action) = rows.iter().find_map(|b| b.action(key.code)) {
        return Some(action);
    }
    match key.code {
        Char(c) if rows.iter().any(|b| b.keys == keymap::Keys::Text) => Some(Action::Input(c)),
        _ => None,
    }
}
