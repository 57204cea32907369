//! A scene as the simulator runs it: the body, its start, the run length,
//! the panels it shows and what it can measure. Decks validate their TOML
//! into these; the simulator needs nothing else from a deck. A system
//! scene's ([`SystemScene`]) is defined beside the systems that compile it,
//! [`crate::system::spec`], and re-exported here; so are the measures, which
//! live with their table in [`crate::scene::vocabulary`].

pub use crate::scene::vocabulary::{Measure, Stat};
pub use crate::system::spec::{Hamiltonian, Mark, SceneAtol, SystemPanel, SystemScene};
use flipcard_text::Text;

/// A panel a scene shows. A scene computes only what its panels need.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Panel {
    /// ω₁, ω₂, ω₃ against time.
    Omega,
    /// The rotating body (needs the orientation q).
    Body,
    /// The polhode on the momentum sphere / energy ellipsoid.
    Polhode,
    /// Invariant drift and error against the exact solution.
    Diagnostics,
}

impl Panel {
    pub const ALL: [Panel; 4] = [
        Panel::Omega,
        Panel::Body,
        Panel::Polhode,
        Panel::Diagnostics,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Panel::Omega => "omega",
            Panel::Body => "body",
            Panel::Polhode => "polhode",
            Panel::Diagnostics => "diagnostics",
        }
    }
    pub fn from_name(name: &str) -> Option<Panel> {
        Panel::ALL.into_iter().find(|p| p.name() == name)
    }
}

/// A torque-free rigid-body simulation declared by a deck.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub id: String,
    pub title: Option<Text>,
    /// Principal moments, in the order the author gave them (kg·m²).
    pub inertia: [f64; 3],
    /// Body-frame angular velocity at t = 0 (rad per time unit).
    pub omega: [f64; 3],
    /// Run length in the scene's time unit.
    pub duration: f64,
    /// Panels shown, in the author's order, without repeats.
    pub show: Vec<Panel>,
    /// Time unit label: `s` by default; `d` (days) for Earth-like scenes.
    pub time_unit: String,
}

impl Scene {
    pub fn shows(&self, panel: Panel) -> bool {
        self.show.contains(&panel)
    }
}
