//! Keys → actions. Each screen owns the tables of its modes (in its own
//! module): one row per help line, listing every key with the action it
//! stands for. The same rows drive the key handling and the help overlay,
//! so the help is never out of date; the rows here are the ones every
//! screen shares.

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use super::action::Action;
use super::app::App;
use super::i18n::Words;
use super::screens;

/// Where the keyboard is: a screen, or a mode of one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Context {
    Home,
    Reader,
    /// Typing a search in the reader.
    ReaderSearch,
    /// A card's front, waiting for the reveal.
    ReviewFront,
    /// A typed card: the answer field has the keyboard.
    ReviewTyping,
    /// The answer is shown: rate it.
    ReviewBack,
    /// Nothing left to review: the session summary.
    ReviewDone,
    Prompts,
    /// Choose one of the prompt's choices.
    PredictChoice,
    /// Type a number (with an optional unit).
    PredictNumber,
    /// The simulation plays.
    PredictRun,
    /// The verdict is shown under the last frame.
    PredictVerdict,
    Stats,
}

impl Context {
    /// The screen's own rows for this context (its module holds them).
    pub fn keys(self) -> &'static [Binding] {
        match self {
            Context::Home => screens::home::KEYS,
            Context::Reader => screens::reader::KEYS,
            Context::ReaderSearch => screens::reader::SEARCH_KEYS,
            Context::ReviewFront => screens::review::FRONT_KEYS,
            Context::ReviewTyping => screens::review::TYPING_KEYS,
            Context::ReviewBack => screens::review::BACK_KEYS,
            Context::ReviewDone => screens::review::DONE_KEYS,
            Context::Prompts => screens::prompts::KEYS,
            Context::PredictChoice => screens::predict::CHOICE_KEYS,
            Context::PredictNumber => screens::predict::NUMBER_KEYS,
            Context::PredictRun => screens::predict::RUN_KEYS,
            Context::PredictVerdict => screens::predict::VERDICT_KEYS,
            Context::Stats => screens::stats::KEYS,
        }
    }

    /// Contexts where printable keys are typed into a field.
    pub fn is_text_input(self) -> bool {
        self.keys().iter().any(|b| matches!(b.keys, Keys::Text))
    }
}

/// What a help line's keys do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Keys {
    /// Each key with the action it stands for.
    Map(&'static [(KeyCode, Action)]),
    /// Printable characters are typed into the screen's field.
    Text,
    /// Keys the event loop handles before any table (Ctrl-C); listed for
    /// the help only.
    Shown,
}

/// One line of the help overlay and the keys it stands for.
const UP_DOWN: &[(KeyCode, Action)] = &[
    (KeyCode::Up, Action::Up),
    (KeyCode::Down, Action::Down),
    (KeyCode::Char('j'), Action::Down),
    (KeyCode::Char('k'), Action::Up),
];

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Binding {
    /// The keys as the help overlay shows them.
    pub label: &'static str,
    /// What they do, in English and Hinglish.
    pub help: Words,
    pub keys: Keys,
}

impl Binding {
    pub const fn new(label: &'static str, help: Words, keys: &'static [(KeyCode, Action)]) -> Self {
        Binding {
            label,
            help,
            keys: Keys::Map(keys),
        }
    }

    /// The row that moves a selection up and down a list (arrows and j k).
    pub const fn choose(help: Words) -> Self {
        Binding::new("↑↓ j k", help, UP_DOWN)
    }

    /// The row of a text field: what typing enters.
    pub const fn typing(help: Words) -> Self {
        Binding {
            label: "type",
            help,
            keys: Keys::Text,
        }
    }

    pub fn help(&self, lang: &str) -> &'static str {
        self.help.get(lang)
    }

    fn action(&self, code: KeyCode) -> Option<Action> {
        match self.keys {
            Keys::Map(keys) => keys.iter().find(|(k, _)| *k == code).map(|(_, a)| *a),
            Keys::Text | Keys::Shown => None,
        }
    }
}

use KeyCode::{Char, F};

/// Rows every screen has. While a field has the keyboard, `?` and `l` are
/// letters to type, so only F1 opens the help there.
const GLOBAL: &[Binding] = &[
    Binding::new(
        "? F1",
        Words("this help", "yeh madad"),
        &[(Char('?'), Action::ToggleHelp), (F(1), Action::ToggleHelp)],
    ),
    Binding::new(
        "l",
        Words("English ⇄ Hinglish", "English ⇄ Hinglish"),
        &[(Char('l'), Action::ToggleLanguage)],
    ),
    QUIT_AT_ONCE,
];

const GLOBAL_TYPING: &[Binding] = &[
    Binding::new(
        "F1",
        Words("this help", "yeh madad"),
        &[(F(1), Action::ToggleHelp)],
    ),
    QUIT_AT_ONCE,
];

const QUIT_AT_ONCE: Binding = Binding {
    label: "Ctrl-C",
    help: Words("quit at once", "turant band karo"),
    keys: Keys::Shown,
};

/// The rows of a context, in the order the help overlay lists them.
pub fn bindings(ctx: Context) -> Vec<Binding> {
    let global = if ctx.is_text_input() {
        GLOBAL_TYPING
    } else {
        GLOBAL
    };
    ctx.keys().iter().chain(global).copied().collect()
}

/// The action a key press stands for in the app's current state.
pub fn key_action(app: &App, key: KeyEvent) -> Option<Action> {
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
    if w < super::view::MIN_WIDTH || h < super::view::MIN_HEIGHT {
        return (key.code == Char('q')).then_some(Action::Quit);
    }
    if app.help {
        return Some(Action::CloseHelp);
    }
    let rows = bindings(app.context());
    if let Some(action) = rows.iter().find_map(|b| b.action(key.code)) {
        return Some(action);
    }
    match key.code {
        Char(c) if rows.iter().any(|b| b.keys == Keys::Text) => Some(Action::Input(c)),
        _ => None,
    }
}
