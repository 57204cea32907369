//! A scene as the simulator runs it: the body, its start, the run length,
//! the panels it shows and what it can measure. Decks validate their TOML
//! into these; the simulator needs nothing else from a deck. A system
//! scene's ([`SystemScene`]) is defined beside the systems that compile it,
//! [`crate::system::spec`], and re-exported here.

use crate::scene::vocabulary::{self, MeasureKind, ParseError};
use crate::system::Name;
pub use crate::system::spec::{Mark, SystemPanel, SystemScene};
use flipcard_text::Text;

/// What a scene's simulation can measure; prompts check against these.
/// Names, help text and parsing come from the one table,
/// [`vocabulary::MEASURES`].
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
    /// A statistic of one variable or observable of a system scene over its
    /// run, written `period(theta)`.
    Of(Stat, Name),
}

impl Measure {
    /// The deck format's name of a rigid-body measure, or the statistic's
    /// for a system measure (whose full spelling, `period(theta)`, is its
    /// `Display`), from the vocabulary's table.
    pub fn name(self) -> &'static str {
        vocabulary::row_of(self).name
    }

    /// The rigid-body measure of this name.
    pub fn from_name(name: &str) -> Option<Measure> {
        match vocabulary::row_named(name)?.kind {
            MeasureKind::Rigid(m) => Some(m),
            MeasureKind::System(_) => None,
        }
    }

    /// A measure as written on the command line: a rigid-body name
    /// (`flips`) or a statistic of a quantity (`period(theta)`).
    pub fn parse(text: &str) -> Result<Measure, String> {
        let text = text.trim();
        match vocabulary::parse(text) {
            Ok(parsed) => parsed.into_measure().map_err(|e| format!("`{text}`: {e}")),
            Err(ParseError::UnknownName(_)) => Err(format!(
                "unknown measure `{text}` ({})",
                vocabulary::system_hint()
            )),
            Err(ParseError::UnknownStat { stat, .. }) => {
                Err(format!("unknown measure `{stat}` in `{text}`"))
            }
            Err(ParseError::NoClose | ParseError::Trailing { .. }) => {
                Err(format!("`{text}`: expected `)` at the end"))
            }
        }
    }

    /// Whether the measure applies to system scenes (else to rigid bodies).
    pub fn is_system(self) -> bool {
        matches!(self, Measure::Of(..))
    }
}

impl std::fmt::Display for Measure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Measure::Of(stat, name) => write!(f, "{}({name})", stat.name()),
            m => f.write_str(m.name()),
        }
    }
}

/// What a system measure takes of its quantity N over the run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stat {
    Max,
    Min,
    /// N at the end of the run.
    Final,
    /// The time average of N over the run (trapezoids between samples).
    Mean,
    /// Sign changes of N.
    Crossings,
    /// Mean time between successive upward crossings of the level halfway
    /// between N's minimum and maximum over the run.
    Period,
    /// Largest |N(t) − N(0)| / max(|N(0)|, tiny).
    Drift,
}

impl Stat {
    /// The statistic's name, from the vocabulary's table.
    pub fn name(self) -> &'static str {
        vocabulary::row_kind(MeasureKind::System(self)).name
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
