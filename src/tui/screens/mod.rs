//! One module per screen: its state, how actions change it, how it draws,
//! and its key tables; here, what every screen offers ([`View`]), the
//! screens the stack holds ([`Screen`]) and which table is whose ([`keys`]).

pub mod browser;
pub mod edit_check;
pub mod exam;
pub mod filter;
pub mod formulas;
pub mod home;
pub mod info;
pub mod predict;
pub mod prompts;
pub mod reader;
pub mod review;
pub mod stats;

use ratatui::Frame;
use ratatui::layout::Rect;

use super::action::Action;
use super::app::App;
use super::i18n::Msg;
use super::keymap::{self, Binding, Context};

/// What every screen does: say where the keyboard is (and so which of its
/// key tables applies), carry out actions, draw itself, and name itself in
/// the header. The app reaches a screen only through this.
pub trait View {
    fn context(&self) -> Context;
    fn apply(&mut self, app: &mut App, action: Action) -> Nav;
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App);
    /// What the screen is, for the header ("Review", "Reader").
    fn name(&self) -> Msg;
    /// The deck the screen is about, named in the header beside `name`.
    fn deck(&self) -> Option<usize> {
        None
    }
    /// Whether it plays something, so the event loop must tick.
    fn animating(&self) -> bool {
        false
    }
    /// Whether closing it ends a study session that may have changed the
    /// log (the app then syncs, when `sync_dir` is set).
    fn ends_session(&self) -> bool {
        false
    }
}

pub enum Screen {
    Home(home::HomeState),
    Review(Box<review::ReviewState>),
    Reader(reader::ReaderState),
    Formulas(formulas::FormulaSheet),
    Prompts(prompts::PromptsState),
    Predict(Box<predict::PredictState>),
    Stats(Box<stats::StatsState>),
    Exam(Box<exam::ExamState>),
    Browser(Box<browser::BrowserState>),
    Filter(Box<filter::FilterState>),
    Info(Box<info::InfoState>),
    EditCheck(Box<edit_check::EditCheckState>),
}

impl Screen {
    pub fn view(&self) -> &dyn View {
        match self {
            Screen::Home(s) => s,
            Screen::Review(s) => s.as_ref(),
            Screen::Reader(s) => s,
            Screen::Formulas(s) => s,
            Screen::Prompts(s) => s,
            Screen::Predict(s) => s.as_ref(),
            Screen::Stats(s) => s.as_ref(),
            Screen::Exam(s) => s.as_ref(),
            Screen::Browser(s) => s.as_ref(),
            Screen::Filter(s) => s.as_ref(),
            Screen::Info(s) => s.as_ref(),
            Screen::EditCheck(s) => s.as_ref(),
        }
    }

    pub fn view_mut(&mut self) -> &mut dyn View {
        match self {
            Screen::Home(s) => s,
            Screen::Review(s) => s.as_mut(),
            Screen::Reader(s) => s,
            Screen::Formulas(s) => s,
            Screen::Prompts(s) => s,
            Screen::Predict(s) => s.as_mut(),
            Screen::Stats(s) => s.as_mut(),
            Screen::Exam(s) => s.as_mut(),
            Screen::Browser(s) => s.as_mut(),
            Screen::Filter(s) => s.as_mut(),
            Screen::Info(s) => s.as_mut(),
            Screen::EditCheck(s) => s.as_mut(),
        }
    }

    pub fn context(&self) -> Context {
        self.view().context()
    }
}

/// What a screen's action asks of the screen stack.
pub enum Nav {
    Stay,
    Push(Screen),
    /// Close this screen.
    Pop,
    /// Close this screen and open another in its place.
    Replace(Screen),
}

/// The screen's own rows for a context (its module holds them).
pub fn keys(ctx: Context) -> &'static [Binding] {
    match ctx {
        Context::Home => home::KEYS,
        Context::Reader => reader::KEYS,
        Context::ReaderSearch => reader::SEARCH_KEYS,
        Context::Formulas => formulas::KEYS,
        Context::ReviewFront => review::FRONT_KEYS,
        Context::ReviewTyping => review::TYPING_KEYS,
        Context::ReviewDerive => review::DERIVE_KEYS,
        Context::ReviewBack => review::BACK_KEYS,
        Context::ReviewDone => review::DONE_KEYS,
        Context::Prompts => prompts::KEYS,
        Context::PredictChoice => predict::CHOICE_KEYS,
        Context::PredictNumber => predict::NUMBER_KEYS,
        Context::PredictFormula => predict::FORMULA_KEYS,
        Context::PredictRun => predict::RUN_KEYS,
        Context::PredictVerdict => predict::VERDICT_KEYS,
        Context::PredictExplore => predict::EXPLORE_KEYS,
        Context::Stats => stats::KEYS,
        Context::ExamDate => exam::DATE_KEYS,
        Context::Browser => browser::KEYS,
        Context::BrowserSearch => browser::SEARCH_KEYS,
        Context::Filter => filter::KEYS,
        Context::Info => info::KEYS,
        Context::EditCheck => edit_check::KEYS,
    }
}

/// The rows of a context, in the order the help overlay lists them: the
/// screen's, then those every screen has.
pub fn bindings(ctx: Context) -> Vec<Binding> {
    keymap::with_global(keys(ctx))
}

/// Contexts where printable keys are typed into a field.
pub fn is_text_input(ctx: Context) -> bool {
    keymap::is_text_input(keys(ctx))
}
