//! A scene as the simulator runs it: the body, its start, the run length,
//! the panels it shows and what it can measure. Decks validate their TOML
//! into these; the simulator needs nothing else from a deck.

use crate::text::Text;

/// What a scene's simulation can measure; prompts check against these.
/// Names are the deck format's spelling (`Measure::name`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Measure {
    /// Sign changes of the spin component along the initially dominant axis.
    Flips,
    /// Mean time between successive flips (scene time unit).
    FlipPeriod,
    /// Early exponential growth rate of a perturbation about the middle axis (1/time unit).
    GrowthRate,
    /// 1 / growth rate: the e-folding time of the perturbation.
    EfoldTime,
    /// Angular frequency of the small oscillation about a stable axis (rad/time unit).
    OscillationFreq,
    /// Body-frame precession rate of a symmetric top (rad/time unit, signed).
    PrecessionRate,
    /// 2π / |precession rate| (time unit).
    PrecessionPeriod,
    /// Largest change of any body-frame ω component over the run, relative to |ω₀|.
    OmegaChange,
    /// Largest relative drift of the kinetic energy over the run.
    EnergyDrift,
    /// Largest relative drift of |L|² over the run.
    MomentumDrift,
}

impl Measure {
    pub const ALL: [Measure; 10] = [
        Measure::Flips,
        Measure::FlipPeriod,
        Measure::GrowthRate,
        Measure::EfoldTime,
        Measure::OscillationFreq,
        Measure::PrecessionRate,
        Measure::PrecessionPeriod,
        Measure::OmegaChange,
        Measure::EnergyDrift,
        Measure::MomentumDrift,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Measure::Flips => "flips",
            Measure::FlipPeriod => "flip_period",
            Measure::GrowthRate => "growth_rate",
            Measure::EfoldTime => "efold_time",
            Measure::OscillationFreq => "oscillation_freq",
            Measure::PrecessionRate => "precession_rate",
            Measure::PrecessionPeriod => "precession_period",
            Measure::OmegaChange => "omega_change",
            Measure::EnergyDrift => "energy_drift",
            Measure::MomentumDrift => "momentum_drift",
        }
    }

    pub fn from_name(name: &str) -> Option<Measure> {
        Measure::ALL.into_iter().find(|m| m.name() == name)
    }
}

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
