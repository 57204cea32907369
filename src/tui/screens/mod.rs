//! One module per screen: its state, how actions change it, how it draws.

pub mod home;
pub mod predict;
pub mod prompts;
pub mod reader;
pub mod review;
pub mod stats;

use super::keymap::Context;

pub enum Screen {
    Home(home::HomeState),
    Review(Box<review::ReviewState>),
    Reader(reader::ReaderState),
    Prompts(prompts::PromptsState),
    Predict(Box<predict::PredictState>),
    Stats(Box<stats::StatsState>),
}

impl Screen {
    pub fn context(&self) -> Context {
        match self {
            Screen::Home(_) => Context::Home,
            Screen::Review(r) => match &r.phase {
                review::Phase::Front { .. } if r.typed => Context::ReviewTyping,
                review::Phase::Front { .. } => Context::ReviewFront,
                review::Phase::Back { .. } => Context::ReviewBack,
                review::Phase::Done => Context::ReviewDone,
            },
            Screen::Reader(r) if r.search.is_some() => Context::ReaderSearch,
            Screen::Reader(_) => Context::Reader,
            Screen::Prompts(_) => Context::Prompts,
            Screen::Predict(p) => match &p.phase {
                predict::Phase::Ask { .. } if p.choice => Context::PredictChoice,
                predict::Phase::Ask { .. } => Context::PredictNumber,
                predict::Phase::Play { verdict: None, .. } => Context::PredictRun,
                predict::Phase::Play { .. } => Context::PredictVerdict,
            },
            Screen::Stats(_) => Context::Stats,
        }
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
