//! The review screen's keys, one table per mode.

use crossterm::event::KeyCode::{Backspace, Char, Enter, Esc};

use crate::sched::Rating;
use crate::tui::action::Action;
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;

const EXPLAIN: Binding = Binding::new(
    "e",
    Words("open the explanation", "samjhaav kholo"),
    &[(Char('e'), Action::Explain)],
);

const UNDO: Binding = Binding::new(
    "u",
    Words(
        "undo the last rating, suspend or bury",
        "pichhli rating, suspend ya bury wapas lo",
    ),
    &[(Char('u'), Action::Undo)],
);

const SUSPEND: Binding = Binding::new(
    "s",
    Words(
        "suspend this card (out of every queue)",
        "yeh card suspend karo (har queue se bahar)",
    ),
    &[(Char('s'), Action::Suspend)],
);

const BURY: Binding = Binding::new(
    "b",
    Words("bury this card until tomorrow", "yeh card kal tak hatao"),
    &[(Char('b'), Action::Bury)],
);

const END_SESSION: Binding = Binding::new(
    "Esc q",
    Words("end the session", "session khatam karo"),
    &[(Esc, Action::Back), (Char('q'), Action::Back)],
);

/// A card's front, waiting for the reveal.
pub const FRONT_KEYS: &[Binding] = &[
    Binding::new(
        "Space Enter",
        Words("show the answer", "jawab dikhao"),
        &[(Char(' '), Action::Reveal), (Enter, Action::Reveal)],
    ),
    EXPLAIN,
    SUSPEND,
    BURY,
    UNDO,
    END_SESSION,
];

/// A typed card: the answer field has the keyboard.
pub const TYPING_KEYS: &[Binding] = &[
    Binding::typing(Words("your answer", "apna jawab")),
    Binding::new(
        "Enter",
        Words("check the answer", "jawab jaancho"),
        &[(Enter, Action::Submit)],
    ),
    Binding::new(
        "Backspace",
        Words("delete a character", "ek akshar mitao"),
        &[(Backspace, Action::Backspace)],
    ),
    Binding::new(
        "Esc",
        Words("end the session", "session khatam karo"),
        &[(Esc, Action::Back)],
    ),
];

/// The answer is shown: rate it.
pub const BACK_KEYS: &[Binding] = &[
    Binding::new(
        "1",
        Words("Again: forgot it", "Phir se: bhool gaye"),
        &[(Char('1'), Action::Rate(Rating::Again))],
    ),
    Binding::new(
        "2",
        Words("Hard: recalled with effort", "Mushkil: mehnat se yaad aaya"),
        &[(Char('2'), Action::Rate(Rating::Hard))],
    ),
    Binding::new(
        "3",
        Words("Good: recalled", "Theek: yaad aaya"),
        &[(Char('3'), Action::Rate(Rating::Good))],
    ),
    Binding::new(
        "4",
        Words("Easy: instantly", "Aasaan: turant"),
        &[(Char('4'), Action::Rate(Rating::Easy))],
    ),
    Binding::new(
        "Space Enter",
        Words(
            "Good (or the suggested rating)",
            "Theek (ya sujhaayi rating)",
        ),
        &[(Char(' '), Action::Submit), (Enter, Action::Submit)],
    ),
    EXPLAIN,
    Binding::new(
        "p",
        Words("try the linked prediction", "judi prediction try karo"),
        &[(Char('p'), Action::OpenCardPrompt)],
    ),
    SUSPEND,
    BURY,
    UNDO,
    END_SESSION,
];

/// Nothing left to review: the session summary.
pub const DONE_KEYS: &[Binding] = &[
    UNDO,
    Binding::new(
        "Esc q Enter",
        Words("back to the decks", "decks par wapas"),
        &[
            (Esc, Action::Back),
            (Char('q'), Action::Back),
            (Enter, Action::Back),
        ],
    ),
];
