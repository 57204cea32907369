//! The review screen's keys, one table per mode.

use crossterm::event::KeyCode::{Backspace, Char, Down, Enter, Esc, F, Up};

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

const EDIT: Binding = Binding::new(
    "E F4",
    Words(
        "edit this card in its deck file",
        "yeh card uski deck file mein badlo",
    ),
    &[(Char('E'), Action::EditItem), (F(4), Action::EditItem)],
);

const ADD: Binding = Binding::new(
    "A F7",
    Words(
        "add a card of this kind, in the editor",
        "isi kind ka naya card jodo, editor mein",
    ),
    &[(Char('A'), Action::AddCard), (F(7), Action::AddCard)],
);

/// While typing, `E` and `A` are letters: the function keys edit and add
/// (what is typed stays).
pub(crate) const EDIT_TYPING: Binding = Binding::new(
    "F4",
    Words(
        "edit this card in its deck file (your answer so far stays)",
        "yeh card uski deck file mein badlo (ab tak likha jawab rehta hai)",
    ),
    &[(F(4), Action::EditItem)],
);

pub(crate) const ADD_TYPING: Binding = Binding::new(
    "F7",
    Words(
        "add a card of this kind, in the editor",
        "isi kind ka naya card jodo, editor mein",
    ),
    &[(F(7), Action::AddCard)],
);

/// A card taller than the screen scrolls.
const SCROLL: Binding = Binding::new(
    "j k ↑↓",
    Words("scroll the card", "card scroll karo"),
    &[
        (Down, Action::Down),
        (Up, Action::Up),
        (Char('j'), Action::Down),
        (Char('k'), Action::Up),
    ],
);

/// While typing, j and k are letters.
const SCROLL_TYPING: Binding = Binding::new(
    "↑↓",
    Words("scroll the card", "card scroll karo"),
    &[(Down, Action::Down), (Up, Action::Up)],
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
    SCROLL,
    EXPLAIN,
    super::super::info::OPEN,
    SUSPEND,
    BURY,
    EDIT,
    ADD,
    UNDO,
    END_SESSION,
];

/// A derivation walked step by step: on to the next step (or check the
/// faded one), a faded step's choice by its number.
pub const DERIVE_KEYS: &[Binding] = &[
    Binding::new(
        "Space Enter",
        Words(
            "next step; on a faded step, check (or reveal) it",
            "agla step; faded step pe jaancho (ya dikhao)",
        ),
        &[(Char(' '), Action::Reveal), (Enter, Action::Reveal)],
    ),
    Binding::new(
        "1-9",
        Words(
            "choose an answer of a faded step",
            "faded step ka jawab chuno",
        ),
        &[
            (Char('1'), Action::Choose(0)),
            (Char('2'), Action::Choose(1)),
            (Char('3'), Action::Choose(2)),
            (Char('4'), Action::Choose(3)),
            (Char('5'), Action::Choose(4)),
            (Char('6'), Action::Choose(5)),
            (Char('7'), Action::Choose(6)),
            (Char('8'), Action::Choose(7)),
            (Char('9'), Action::Choose(8)),
        ],
    ),
    SCROLL,
    EXPLAIN,
    super::super::info::OPEN,
    SUSPEND,
    BURY,
    EDIT,
    ADD,
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
    SCROLL_TYPING,
    EDIT_TYPING,
    ADD_TYPING,
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
    super::super::info::OPEN,
    SUSPEND,
    BURY,
    EDIT,
    ADD,
    SCROLL,
    UNDO,
    END_SESSION,
];

/// Nothing left to review: the session summary.
pub const DONE_KEYS: &[Binding] = &[
    Binding::new(
        "c",
        Words("cram: review everything now", "cram: sab abhi review karo"),
        &[(Char('c'), Action::OpenCram)],
    ),
    SCROLL,
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
