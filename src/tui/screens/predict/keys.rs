//! The predict-then-check screen's keys, one table per mode.

use crossterm::event::KeyCode::{Backspace, Char, Down, Enter, Esc, F, Left, Right, Tab, Up};

use crate::tui::action::Action;
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;

const BACK: Binding = Binding::new(
    "Esc q",
    Words("back", "wapas"),
    &[(Esc, Action::Back), (Char('q'), Action::Back)],
);

/// Choose one of the prompt's choices.
pub const CHOICE_KEYS: &[Binding] = &[
    Binding::choose(Words("choose", "chuno")),
    Binding::new(
        "1-9",
        Words("choose by number", "number se chuno"),
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
    Binding::new(
        "Enter",
        Words("commit and run", "pakka karo aur chalao"),
        &[(Enter, Action::Submit)],
    ),
    BACK,
];

/// The rows of a typed answer's field (a number's or a formula's).
const DELETE: Binding = Binding::new(
    "Backspace",
    Words("delete a character", "ek akshar mitao"),
    &[(Backspace, Action::Backspace)],
);
const ESC_BACK: Binding = Binding::new("Esc", Words("back", "wapas"), &[(Esc, Action::Back)]);

/// While the answer is typed, `E` and `A` are letters (a unit may be
/// `A`): the function keys edit the prompt and add a card instead, and
/// what is typed stays.
const EDIT_TYPING: Binding = Binding::new(
    "F4",
    Words(
        "edit this prompt in its deck file (what you typed stays)",
        "yeh prompt uski deck file mein badlo (likha hua rehta hai)",
    ),
    &[(F(4), Action::EditItem)],
);
const ADD_TYPING: Binding = Binding::new(
    "F7",
    Words(
        "add a card to the deck, in the editor",
        "deck mein naya card jodo, editor mein",
    ),
    &[(F(7), Action::AddCard)],
);

/// Type a number (with an optional unit).
pub const NUMBER_KEYS: &[Binding] = &[
    Binding::typing(Words(
        "a number, optionally with its unit",
        "ek number, unit ke saath bhi",
    )),
    Binding::new(
        "Enter",
        Words("commit and run", "pakka karo aur chalao"),
        &[(Enter, Action::Submit)],
    ),
    DELETE,
    EDIT_TYPING,
    ADD_TYPING,
    ESC_BACK,
];

/// Type a formula (graded at the commitment, see `predict::formula`).
pub const FORMULA_KEYS: &[Binding] = &[
    Binding::typing(Words(
        "a formula: (I2-I3)*w2*w3/I1, ^ for powers, 2x for 2*x",
        "ek formula: (I2-I3)*w2*w3/I1, power ke liye ^, 2*x ke liye 2x",
    )),
    Binding::new(
        "Enter",
        Words("commit and check", "pakka karo aur jaancho"),
        &[(Enter, Action::Submit)],
    ),
    DELETE,
    EDIT_TYPING,
    ADD_TYPING,
    ESC_BACK,
];

const PAUSE: Binding = Binding::new(
    "Space",
    Words("pause / play", "roko / chalao"),
    &[(Char(' '), Action::TogglePause)],
);
const SPEED: Binding = Binding::new(
    "+ -",
    Words("faster / slower", "tez / dheere"),
    &[
        (Char('+'), Action::Faster),
        (Char('='), Action::Faster),
        (Char('-'), Action::Slower),
    ],
);
const RESTART: Binding = Binding::new(
    "r",
    Words("restart", "phir se shuru"),
    &[(Char('r'), Action::Restart)],
);
const METHOD: Binding = Binding::new(
    "m",
    Words(
        "next method (its name on the status line)",
        "agla method (naam status line pe)",
    ),
    &[(Char('m'), Action::NextMethod)],
);
const STEP: Binding = Binding::new(
    "[ ]",
    Words(
        "smaller / larger step (or tolerance)",
        "chhota / bada step (ya tolerance)",
    ),
    &[
        (Char('['), Action::SmallerStep),
        (Char(']'), Action::LargerStep),
    ],
);

const DIAGNOSTICS: Binding = Binding::new(
    "d",
    Words(
        "solver diagnostics (shown by themselves for another method)",
        "solver diagnostics (doosre method pe khud dikhte hain)",
    ),
    &[(Char('d'), Action::ToggleDiagnostics)],
);

const QUESTION: Binding = Binding::new(
    "w",
    Words(
        "the whole question first, on a small screen (or back)",
        "poora sawaal pehle, chhoti screen pe (ya wapas)",
    ),
    &[(Char('w'), Action::ToggleQuestion)],
);

/// The simulation plays.
pub const RUN_KEYS: &[Binding] = &[
    PAUSE,
    SPEED,
    RESTART,
    METHOD,
    STEP,
    DIAGNOSTICS,
    QUESTION,
    BACK,
];

/// The verdict is shown under the last frame.
pub const VERDICT_KEYS: &[Binding] = &[
    PAUSE,
    SPEED,
    RESTART,
    METHOD,
    STEP,
    DIAGNOSTICS,
    QUESTION,
    Binding::new(
        "j k ↑↓",
        Words(
            "scroll the verdict, on a small screen",
            "verdict scroll karo, chhoti screen pe",
        ),
        &[
            (Down, Action::Down),
            (Up, Action::Up),
            (Char('j'), Action::Down),
            (Char('k'), Action::Up),
        ],
    ),
    Binding::new(
        "e",
        Words("open the explanation", "samjhaav kholo"),
        &[(Char('e'), Action::Explain)],
    ),
    Binding::new(
        "n",
        Words("next prompt", "agla prompt"),
        &[(Char('n'), Action::NextPrompt)],
    ),
    Binding::new(
        "2",
        Words(
            "right but hard: schedule it sooner (Hard, not Good)",
            "sahi par mushkil: jaldi wapas lao (Good nahi, Hard)",
        ),
        &[(Char('2'), Action::Rate(crate::sched::Rating::Hard))],
    ),
    Binding::new(
        "x ← → Tab",
        Words(
            "explore: turn the scene's knobs (when it has some)",
            "explore: scene ke knobs ghumao (agar hain)",
        ),
        &[
            (Char('x'), Action::Explore),
            (Left, Action::KnobDown),
            (Right, Action::KnobUp),
            (Tab, Action::NextKnob),
        ],
    ),
    BACK,
];

/// Exploring the scene: the knobs turn, the run restarts at once.
pub const EXPLORE_KEYS: &[Binding] = &[
    Binding::new(
        "← → h l",
        Words(
            "turn the selected knob one step (the run restarts)",
            "chune hue knob ko ek step ghumao (run phir se shuru)",
        ),
        &[
            (Left, Action::KnobDown),
            (Right, Action::KnobUp),
            (Char('h'), Action::KnobDown),
            (Char('l'), Action::KnobUp),
        ],
    ),
    Binding::new(
        "Tab",
        Words("select the next knob", "agla knob chuno"),
        &[(Tab, Action::NextKnob)],
    ),
    PAUSE,
    SPEED,
    RESTART,
    DIAGNOSTICS,
    Binding::new(
        "L",
        Words("English ⇄ Hinglish", "English ⇄ Hinglish"),
        &[(Char('L'), Action::ToggleLanguage)],
    ),
    BACK,
];
