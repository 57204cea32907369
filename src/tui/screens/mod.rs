//! One module per screen: its state, how actions change it, how it draws.

pub mod home;
pub mod predict;
pub mod prompts;

use super::keymap::Context;

pub enum Screen {
    Home(home::HomeState),
    Prompts(prompts::PromptsState),
    Predict(predict::PredictState),
}

impl Screen {
    pub fn context(&self) -> Context {
        match self {
            Screen::Home(_) => Context::Home,
            Screen::Prompts(_) => Context::Prompts,
            Screen::Predict(p) => match &p.phase {
                predict::Phase::Ask { .. } if p.choice => Context::PredictChoice,
                predict::Phase::Ask { .. } => Context::PredictNumber,
                predict::Phase::Play { verdict: None, .. } => Context::PredictRun,
                predict::Phase::Play { .. } => Context::PredictVerdict,
            },
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
