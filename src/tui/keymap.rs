//! Keys → actions, per screen and mode. One table per context drives both
//! the key handling and the help overlay, so the help is never out of date.

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::sched::Rating;

use super::action::Action;
use super::app::App;

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
    /// Contexts where printable keys are typed into a field.
    pub fn is_text_input(self) -> bool {
        matches!(
            self,
            Context::ReaderSearch | Context::ReviewTyping | Context::PredictNumber
        )
    }
}

/// One line of the help overlay and the keys it stands for.
#[derive(Debug, Clone)]
pub struct Binding {
    /// The keys as the help overlay shows them.
    pub label: &'static str,
    /// What they do, in English and Hinglish.
    pub help: (&'static str, &'static str),
    pub keys: Vec<KeyCode>,
    pub action: Action,
}

impl Binding {
    pub fn help(&self, lang: &str) -> &'static str {
        if lang == super::i18n::HINGLISH {
            self.help.1
        } else {
            self.help.0
        }
    }
}

fn b(
    label: &'static str,
    en: &'static str,
    hi: &'static str,
    keys: &[KeyCode],
    action: Action,
) -> Binding {
    Binding {
        label,
        help: (en, hi),
        keys: keys.to_vec(),
        action,
    }
}

use KeyCode::{
    BackTab, Backspace, Char, Down, End, Enter, Esc, F, Home, Left, PageDown, PageUp, Right, Tab,
    Up,
};

fn explain_binding() -> Binding {
    b(
        "e",
        "open the explanation",
        "samjhaav kholo",
        &[Char('e')],
        Action::Explain,
    )
}

fn undo_binding() -> Binding {
    b(
        "u",
        "undo the last rating",
        "pichhli rating wapas lo",
        &[Char('u')],
        Action::Undo,
    )
}

fn end_session_binding() -> Binding {
    b(
        "Esc q",
        "end the session",
        "session khatam karo",
        &[Esc, Char('q')],
        Action::Back,
    )
}

fn rate_bindings() -> Vec<Binding> {
    vec![
        b(
            "1",
            "Again: forgot it",
            "Phir se: bhool gaye",
            &[Char('1')],
            Action::Rate(Rating::Again),
        ),
        b(
            "2",
            "Hard: recalled with effort",
            "Mushkil: mehnat se yaad aaya",
            &[Char('2')],
            Action::Rate(Rating::Hard),
        ),
        b(
            "3",
            "Good: recalled",
            "Theek: yaad aaya",
            &[Char('3')],
            Action::Rate(Rating::Good),
        ),
        b(
            "4",
            "Easy: instantly",
            "Aasaan: turant",
            &[Char('4')],
            Action::Rate(Rating::Easy),
        ),
    ]
}

fn common(typing: bool) -> Vec<Binding> {
    let mut v = Vec::new();
    if typing {
        v.push(b(
            "F1",
            "this help",
            "yeh madad",
            &[F(1)],
            Action::ToggleHelp,
        ));
    } else {
        v.push(b(
            "? F1",
            "this help",
            "yeh madad",
            &[Char('?'), F(1)],
            Action::ToggleHelp,
        ));
        v.push(b(
            "l",
            "English ⇄ Hinglish",
            "English ⇄ Hinglish",
            &[Char('l')],
            Action::ToggleLanguage,
        ));
    }
    v.push(b(
        "Ctrl-C",
        "quit at once",
        "turant band karo",
        &[],
        Action::Quit,
    ));
    v
}

/// The bindings of a context, in the order the help overlay lists them.
pub fn bindings(ctx: Context) -> Vec<Binding> {
    let mut v = match ctx {
        Context::Home => vec![
            b(
                "↑↓ j k",
                "choose a deck",
                "deck chuno",
                &[Up, Down, Char('j'), Char('k')],
                Action::Down,
            ),
            b(
                "Enter",
                "review the due cards",
                "baaki cards review karo",
                &[Enter],
                Action::OpenReview,
            ),
            b(
                "c",
                "cram: review everything now",
                "cram: sab abhi review karo",
                &[Char('c')],
                Action::OpenCram,
            ),
            b(
                "r",
                "read the explanations",
                "explanations padho",
                &[Char('r')],
                Action::OpenReader,
            ),
            b(
                "p",
                "prompts and simulations",
                "prompts aur simulations",
                &[Char('p')],
                Action::OpenPrompts,
            ),
            b(
                "t",
                "statistics",
                "statistics",
                &[Char('t')],
                Action::OpenStats,
            ),
            b("q", "quit", "band karo", &[Char('q'), Esc], Action::Quit),
        ],
        Context::Reader => vec![
            b(
                "j k ↑↓",
                "scroll",
                "scroll karo",
                &[Down, Up, Char('j'), Char('k')],
                Action::Down,
            ),
            b(
                "PgUp PgDn",
                "scroll a page",
                "ek page scroll",
                &[PageUp, PageDown, Char(' ')],
                Action::PageDown,
            ),
            b(
                "g G",
                "top / bottom",
                "shuru / ant",
                &[Char('g'), Char('G'), Home, End],
                Action::Top,
            ),
            b(
                "← → h",
                "previous / next section",
                "pichhla / agla section",
                &[Left, Right, Char('h')],
                Action::NextSection,
            ),
            b(
                "/",
                "search every section",
                "har section mein khojo",
                &[Char('/')],
                Action::StartSearch,
            ),
            b(
                "n N",
                "next / previous match",
                "agla / pichhla match",
                &[Char('n'), Char('N')],
                Action::NextMatch,
            ),
            b(
                "Tab",
                "choose a linked section",
                "juda section chuno",
                &[Tab, BackTab],
                Action::NextLink,
            ),
            b(
                "Enter",
                "follow the link",
                "link kholo",
                &[Enter],
                Action::FollowLink,
            ),
            b("Esc q", "back", "wapas", &[Esc, Char('q')], Action::Back),
        ],
        Context::ReaderSearch => vec![
            b(
                "type",
                "the words to find",
                "khojne ke shabd",
                &[],
                Action::Input(' '),
            ),
            b("Enter", "find", "khojo", &[Enter], Action::Submit),
            b(
                "Backspace",
                "delete a character",
                "ek akshar mitao",
                &[Backspace],
                Action::Backspace,
            ),
            b("Esc", "cancel", "radd karo", &[Esc], Action::Back),
        ],
        Context::ReviewFront => vec![
            b(
                "Space Enter",
                "show the answer",
                "jawab dikhao",
                &[Char(' '), Enter],
                Action::Reveal,
            ),
            explain_binding(),
            undo_binding(),
            end_session_binding(),
        ],
        Context::ReviewTyping => vec![
            b("type", "your answer", "apna jawab", &[], Action::Input(' ')),
            b(
                "Enter",
                "check the answer",
                "jawab jaancho",
                &[Enter],
                Action::Submit,
            ),
            b(
                "Backspace",
                "delete a character",
                "ek akshar mitao",
                &[Backspace],
                Action::Backspace,
            ),
            b(
                "Esc",
                "end the session",
                "session khatam karo",
                &[Esc],
                Action::Back,
            ),
        ],
        Context::ReviewBack => {
            let mut v = rate_bindings();
            v.extend([
                b(
                    "Space Enter",
                    "Good (or the suggested rating)",
                    "Theek (ya sujhaayi rating)",
                    &[Char(' '), Enter],
                    Action::Submit,
                ),
                explain_binding(),
                b(
                    "p",
                    "try the linked prediction",
                    "judi prediction try karo",
                    &[Char('p')],
                    Action::OpenCardPrompt,
                ),
                undo_binding(),
                end_session_binding(),
            ]);
            v
        }
        Context::ReviewDone => vec![
            undo_binding(),
            b(
                "Esc q Enter",
                "back to the decks",
                "decks par wapas",
                &[Esc, Char('q'), Enter],
                Action::Back,
            ),
        ],
        Context::Prompts => vec![
            b(
                "↑↓ j k",
                "choose a prompt",
                "prompt chuno",
                &[Up, Down, Char('j'), Char('k')],
                Action::Down,
            ),
            b(
                "Enter",
                "predict, then check",
                "andaaza lagao, phir jaancho",
                &[Enter],
                Action::Open,
            ),
            b("Esc q", "back", "wapas", &[Esc, Char('q')], Action::Back),
        ],
        Context::PredictChoice => vec![
            b(
                "↑↓ j k",
                "choose",
                "chuno",
                &[Up, Down, Char('j'), Char('k')],
                Action::Down,
            ),
            b(
                "1-9",
                "choose by number",
                "number se chuno",
                &[],
                Action::Choose(0),
            ),
            b(
                "Enter",
                "commit and run",
                "pakka karo aur chalao",
                &[Enter],
                Action::Submit,
            ),
            b("Esc q", "back", "wapas", &[Esc, Char('q')], Action::Back),
        ],
        Context::PredictNumber => vec![
            b(
                "type",
                "a number, optionally with its unit",
                "ek number, unit ke saath bhi",
                &[],
                Action::Input(' '),
            ),
            b(
                "Enter",
                "commit and run",
                "pakka karo aur chalao",
                &[Enter],
                Action::Submit,
            ),
            b(
                "Backspace",
                "delete a character",
                "ek akshar mitao",
                &[Backspace],
                Action::Backspace,
            ),
            b("Esc", "back", "wapas", &[Esc], Action::Back),
        ],
        Context::PredictRun | Context::PredictVerdict => {
            let mut v = vec![
                b(
                    "Space",
                    "pause / play",
                    "roko / chalao",
                    &[Char(' ')],
                    Action::TogglePause,
                ),
                b(
                    "+ -",
                    "faster / slower",
                    "tez / dheere",
                    &[Char('+'), Char('='), Char('-')],
                    Action::Faster,
                ),
                b(
                    "r",
                    "restart",
                    "phir se shuru",
                    &[Char('r')],
                    Action::Restart,
                ),
                b(
                    "m",
                    "switch method (exact, adaptive, splitting, RK4)",
                    "method badlo (exact, adaptive, splitting, RK4)",
                    &[Char('m')],
                    Action::NextMethod,
                ),
                b(
                    "[ ]",
                    "smaller / larger step",
                    "chhota / bada step",
                    &[Char('['), Char(']')],
                    Action::LargerStep,
                ),
            ];
            if ctx == Context::PredictVerdict {
                v.push(explain_binding());
            }
            v.push(b("Esc q", "back", "wapas", &[Esc, Char('q')], Action::Back));
            v
        }
        Context::Stats => vec![b("Esc q", "back", "wapas", &[Esc, Char('q')], Action::Back)],
    };
    v.extend(common(ctx.is_text_input()));
    v
}

/// The action of a key in a context. Keys that share a help line map to
/// different actions (↑ and ↓ both sit on "choose"), so the exact action is
/// decided here.
fn action_for(ctx: Context, code: KeyCode) -> Option<Action> {
    let a = match (ctx, code) {
        (_, Up | Char('k')) if !ctx.is_text_input() => Action::Up,
        (_, Down | Char('j')) if !ctx.is_text_input() => Action::Down,
        (Context::Reader, PageUp) => Action::PageUp,
        (Context::Reader, PageDown | Char(' ')) => Action::PageDown,
        (Context::Reader, Char('g') | Home) => Action::Top,
        (Context::Reader, Char('G') | End) => Action::Bottom,
        (Context::Reader, Left | Char('h')) => Action::PrevSection,
        (Context::Reader, Right) => Action::NextSection,
        (Context::Reader, Char('n')) => Action::NextMatch,
        (Context::Reader, Char('N')) => Action::PrevMatch,
        (Context::Reader, Tab | BackTab) => Action::NextLink,
        (Context::PredictChoice, Char(c @ '1'..='9')) => Action::Choose(c as usize - '1' as usize),
        (Context::PredictRun | Context::PredictVerdict, Char('+') | Char('=')) => Action::Faster,
        (Context::PredictRun | Context::PredictVerdict, Char('-')) => Action::Slower,
        (Context::PredictRun | Context::PredictVerdict, Char('[')) => Action::SmallerStep,
        (Context::PredictRun | Context::PredictVerdict, Char(']')) => Action::LargerStep,
        _ => {
            return bindings(ctx)
                .into_iter()
                .find(|bind| bind.keys.contains(&code))
                .map(|bind| bind.action);
        }
    };
    Some(a)
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
    let ctx = app.context();
    if let Some(action) = action_for(ctx, key.code) {
        return Some(action);
    }
    match key.code {
        Char(c) if ctx.is_text_input() => Some(Action::Input(c)),
        _ => None,
    }
}
