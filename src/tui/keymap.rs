//! Keys → actions: the words of the key tables. Each screen owns the tables
//! of its modes (in its own module, found by [`super::screens::keys`]): one
//! row per help line, listing every key with the action it stands for. The
//! same rows drive the key handling ([`super::key_action`]) and the help
//! overlay, so the help is never out of date; the rows here are the ones
//! every screen shares.

use crossterm::event::KeyCode;

use super::action::Action;
use super::i18n::Words;

/// Where the keyboard is: a screen, or a mode of one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Context {
    Home,
    Reader,
    /// Typing a search in the reader.
    ReaderSearch,
    /// The formula sheet of the reader's deck.
    Formulas,
    /// A card's front, waiting for the reveal.
    ReviewFront,
    /// A typed card: the answer field has the keyboard.
    ReviewTyping,
    /// A derivation walked step by step (a faded step's choice by digit).
    ReviewDerive,
    /// The answer is shown: rate it.
    ReviewBack,
    /// Nothing left to review: the session summary.
    ReviewDone,
    Prompts,
    /// Choose one of the prompt's choices.
    PredictChoice,
    /// Type a number (with an optional unit).
    PredictNumber,
    /// Type a formula.
    PredictFormula,
    /// The simulation plays.
    PredictRun,
    /// The verdict is shown under the last frame.
    PredictVerdict,
    /// Exploring the scene with its knobs.
    PredictExplore,
    Stats,
    /// Typing the exam date.
    ExamDate,
    /// The card browser's table.
    Browser,
    /// Typing the browser's query.
    BrowserSearch,
    /// The study filter's form.
    Filter,
    /// Card info: an item's review history.
    Info,
    /// An edited deck failed its check: edit again or revert.
    EditCheck,
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

    /// The three rows of a page of text that scrolls (the reader, the
    /// formula sheet): lines, pages, the ends.
    pub const SCROLL: [Binding; 3] = [
        Binding::new(
            "j k ↑↓",
            Words("scroll", "scroll karo"),
            &[
                (KeyCode::Down, Action::Down),
                (KeyCode::Up, Action::Up),
                (KeyCode::Char('j'), Action::Down),
                (KeyCode::Char('k'), Action::Up),
            ],
        ),
        Binding::new(
            "PgUp PgDn",
            Words("scroll a page", "ek page scroll"),
            &[
                (KeyCode::PageUp, Action::PageUp),
                (KeyCode::PageDown, Action::PageDown),
                (KeyCode::Char(' '), Action::PageDown),
            ],
        ),
        Binding::new(
            "g G",
            Words("top / bottom", "shuru / ant"),
            &[
                (KeyCode::Char('g'), Action::Top),
                (KeyCode::Char('G'), Action::Bottom),
                (KeyCode::Home, Action::Top),
                (KeyCode::End, Action::Bottom),
            ],
        ),
    ];

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

    /// The action `code` stands for in this row, if any.
    pub fn action(&self, code: KeyCode) -> Option<Action> {
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

/// Whether printable keys are typed into a field where `rows` apply.
pub fn is_text_input(rows: &[Binding]) -> bool {
    rows.iter().any(|b| matches!(b.keys, Keys::Text))
}

/// A screen's `rows`, then the rows every screen has, in the order the
/// help overlay lists them.
pub fn with_global(rows: &'static [Binding]) -> Vec<Binding> {
    let global = if is_text_input(rows) {
        GLOBAL_TYPING
    } else {
        GLOBAL
    };
    // A row of the screen's wins over a shared row on the same keys (the
    // explore view's `l` turns a knob): the help lists only what a key does.
    let taken = |code: KeyCode| rows.iter().any(|b| b.action(code).is_some());
    let shadowed = |b: &Binding| match b.keys {
        Keys::Map(keys) => keys.iter().all(|(k, _)| taken(*k)),
        Keys::Text | Keys::Shown => false,
    };
    rows.iter()
        .chain(global.iter().filter(|b| !shadowed(b)))
        .copied()
        .collect()
}
