//! The measure vocabulary in one table: every measure a prompt, `check`,
//! `sim --scene … --measure` or the verdict can name, with its spelling,
//! its help text, whether it is a rigid-body measure or a statistic of a
//! system's quantity, the closed form it is compared with, and how the
//! verdict reads it. The name lists (deck validation, the JSON schema, the
//! error hints), the one parser of measure text ([`parse`]) and the
//! evaluation dispatch all read [`MEASURES`], so adding a measure is one
//! row here (plus its variant of [`Measure`] below and its evaluation: a reading
//! in `Meter::finish` for a rigid body, an arm of `Tally::stat` for a
//! statistic).

use std::ops::Range;

use crate::system::Name;

/// What a scene's simulation can measure; prompts check against these.
/// Names, help text and parsing come from the one table,
/// [`MEASURES`].
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
        row_of(self).name
    }

    /// The rigid-body measure of this name.
    pub fn from_name(name: &str) -> Option<Measure> {
        match row_named(name)?.kind {
            MeasureKind::Rigid(m) => Some(m),
            MeasureKind::System(_) => None,
        }
    }

    /// A measure as written on the command line: a rigid-body name
    /// (`flips`) or a statistic of a quantity (`period(theta)`).
    pub fn parse(text: &str) -> Result<Measure, MeasureTextError> {
        let text = text.trim();
        let owned = || text.to_string();
        match parse(text) {
            Ok(parsed) => parsed
                .into_measure()
                .map_err(|reason| MeasureTextError::Quantity {
                    text: owned(),
                    reason,
                }),
            Err(ParseError::UnknownName(_)) => Err(MeasureTextError::UnknownName(owned())),
            Err(ParseError::UnknownStat { stat, .. }) => Err(MeasureTextError::UnknownStat {
                stat: stat.to_string(),
                text: owned(),
            }),
            Err(ParseError::NoClose | ParseError::Trailing { .. }) => {
                Err(MeasureTextError::NoClose(owned()))
            }
            Err(ParseError::NoRelation { .. } | ParseError::BadLevel { .. }) => {
                Err(MeasureTextError::Relation(owned()))
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
            Measure::Of(stat, name) => match stat.event() {
                Some(e) => write!(f, "{}({})", stat.name(), e.relation(name.as_str())),
                None => write!(f, "{}({name})", stat.name()),
            },
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
    /// The time average of N over the run (Simpson's rule over each step).
    Mean,
    /// Sign changes of N.
    Crossings,
    /// Mean time between successive upward crossings of the level halfway
    /// between N's minimum and maximum over the run.
    Period,
    /// Largest |N(t) − N(0)| / max(|N(0)|, tiny).
    Drift,
    /// Half the distance between N's maximum and minimum.
    Amplitude,
    /// The period of N's envelope: mean time between successive upward
    /// crossings, by the sequence of N's peaks, of the level halfway between
    /// the lowest and the highest peak (the beat of two close frequencies).
    Beat,
    /// `time_of(N > level)`: the first time the relation holds (0 if it
    /// holds at the start), located on the dense output.
    TimeOf(Event),
    /// `count(N > level)`: how many times the relation starts to hold (the
    /// start counts when it holds there); `count(N = level)`: how many
    /// times N crosses the level.
    Count(Event),
}

/// `N > level`, `N < level` or `N = level`: what `time_of` and `count`
/// watch for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Event {
    pub rel: Rel,
    pub level: Level,
}

/// How N stands to the level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Rel {
    /// N crosses (or touches) the level: written `=` or `==`.
    Crosses,
    /// N above the level: `>`.
    Above,
    /// `>=`.
    AtLeast,
    /// N below the level: `<`.
    Below,
    /// `<=`.
    AtMost,
}

impl Rel {
    pub fn symbol(self) -> &'static str {
        match self {
            Rel::Crosses => "=",
            Rel::Above => ">",
            Rel::AtLeast => ">=",
            Rel::Below => "<",
            Rel::AtMost => "<=",
        }
    }
}

/// A finite level, ordered and hashed by its bits so that a measure can be
/// a key.
#[derive(Debug, Clone, Copy)]
pub struct Level(f64);

impl Level {
    /// None unless finite.
    pub fn new(v: f64) -> Option<Level> {
        // −0 and 0 are one level.
        v.is_finite().then_some(Level(v + 0.0))
    }
    pub fn get(self) -> f64 {
        self.0
    }
}

impl PartialEq for Level {
    fn eq(&self, o: &Level) -> bool {
        self.0.to_bits() == o.0.to_bits()
    }
}
impl Eq for Level {}
impl std::hash::Hash for Level {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.0.to_bits().hash(h);
    }
}
impl PartialOrd for Level {
    fn partial_cmp(&self, o: &Level) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Level {
    fn cmp(&self, o: &Level) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

impl Event {
    /// `x > 0.5`: the relation as written, of quantity `name`.
    pub fn relation(&self, name: &str) -> String {
        format!(
            "{name} {} {}",
            self.rel.symbol(),
            flipcard_text::num::Num(self.level.get())
        )
    }

    /// What the vocabulary's table holds for the statistics with a level.
    const ANY: Event = Event {
        rel: Rel::Crosses,
        level: Level(0.0),
    };
}

impl Stat {
    /// The statistic's name, from the vocabulary's table.
    pub fn name(self) -> &'static str {
        row_kind(MeasureKind::System(self)).name
    }

    /// The statistic as its row of the table holds it (any level).
    pub fn base(self) -> Stat {
        match self {
            Stat::TimeOf(_) => Stat::TimeOf(Event::ANY),
            Stat::Count(_) => Stat::Count(Event::ANY),
            s => s,
        }
    }

    /// The relation and level of `time_of` and `count`.
    pub fn event(self) -> Option<Event> {
        match self {
            Stat::TimeOf(e) | Stat::Count(e) => Some(e),
            _ => None,
        }
    }
}

/// What a row names: a rigid-body measure, read from the run's meter, or a
/// statistic a system measure takes of a variable or observable N,
/// written `stat(N)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeasureKind {
    Rigid(Measure),
    System(Stat),
}

/// One measure of the vocabulary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasureRow {
    /// The deck format's and the command line's spelling (`flips`; `period`
    /// of `period(theta)`).
    pub name: &'static str,
    /// What it measures, as the deck format documents it.
    pub help: &'static str,
    pub kind: MeasureKind,
    /// How the closed form it is compared with reads in a verdict ("√k";
    /// empty where none applies).
    pub formula: &'static str,
    /// How the verdict names it, in English and in Hinglish.
    pub words: (&'static str, &'static str),
}

const fn rigid(
    name: &'static str,
    measure: Measure,
    formula: &'static str,
    words: (&'static str, &'static str),
    help: &'static str,
) -> MeasureRow {
    MeasureRow {
        name,
        help,
        kind: MeasureKind::Rigid(measure),
        formula,
        words,
    }
}

const fn stat(
    name: &'static str,
    stat: Stat,
    words: (&'static str, &'static str),
    help: &'static str,
) -> MeasureRow {
    MeasureRow {
        name,
        help,
        kind: MeasureKind::System(stat),
        formula: "",
        words,
    }
}

/// Every measure, rigid-body measures first, each in the order lists and
/// reports show them.
pub(crate) const MEASURES: &[MeasureRow] = &[
    rigid(
        "flips",
        Measure::Flips,
        "count",
        ("flips", "flips"),
        "sign changes of the spin component along the initially dominant axis",
    ),
    rigid(
        "flip_period",
        Measure::FlipPeriod,
        "2K(m)/λ",
        ("flip period", "flip period"),
        "mean time between successive flips",
    ),
    rigid(
        "growth_rate",
        Measure::GrowthRate,
        "√k",
        ("growth rate", "growth rate"),
        "early exponential growth rate of a perturbation about the middle axis (1/time)",
    ),
    rigid(
        "efold_time",
        Measure::EfoldTime,
        "1/√k",
        ("e-folding time", "e-folding time"),
        "1 / growth rate",
    ),
    rigid(
        "oscillation_freq",
        Measure::OscillationFreq,
        "√−k",
        ("oscillation frequency", "oscillation frequency"),
        "angular frequency of the small wobble about a stable axis (rad/time)",
    ),
    rigid(
        "precession_rate",
        Measure::PrecessionRate,
        "(I₃ − I⊥)ω₃/I⊥",
        ("precession rate", "precession rate"),
        "body-frame precession rate of a symmetric top (rad/time, signed)",
    ),
    rigid(
        "precession_period",
        Measure::PrecessionPeriod,
        "2π/|Ω_b|",
        ("precession period", "precession period"),
        "2π / |precession rate|",
    ),
    rigid(
        "omega_change",
        Measure::OmegaChange,
        "steady spin",
        ("largest change of ω", "ω ka sabse bada badlaav"),
        "largest change of any body-frame ω component over the run, relative to |ω₀|",
    ),
    rigid(
        "energy_drift",
        Measure::EnergyDrift,
        "invariant",
        ("energy drift", "energy drift"),
        "largest relative drift of the kinetic energy",
    ),
    rigid(
        "momentum_drift",
        Measure::MomentumDrift,
        "invariant",
        ("|L| drift", "|L| drift"),
        "largest relative drift of |L|²",
    ),
    stat(
        "max",
        Stat::Max,
        ("largest", "sabse bada"),
        "largest value of N over the run",
    ),
    stat(
        "min",
        Stat::Min,
        ("smallest", "sabse chhota"),
        "smallest value of N over the run",
    ),
    stat(
        "final",
        Stat::Final,
        ("final", "aakhri"),
        "N at the end of the run",
    ),
    stat(
        "mean",
        Stat::Mean,
        ("mean", "ausat"),
        "time average of N over the run",
    ),
    stat(
        "amplitude",
        Stat::Amplitude,
        ("amplitude", "amplitude"),
        "half the distance between N's maximum and minimum",
    ),
    stat(
        "crossings",
        Stat::Crossings,
        ("zero crossings", "zero crossings"),
        "sign changes of N",
    ),
    stat(
        "period",
        Stat::Period,
        ("period", "period"),
        "mean time between upward crossings of the level halfway between N's minimum and maximum",
    ),
    stat(
        "beat",
        Stat::Beat,
        ("beat period", "beat period"),
        "period of N's envelope: mean time between upward crossings, by N's peaks, of the level halfway between the lowest and highest peak",
    ),
    stat(
        "time_of",
        Stat::TimeOf(Event::ANY),
        ("time when", "kab"),
        "first time the relation holds (0 if it holds at the start), e.g. time_of(x > 0.5); the relation is N = level (N reaches the level), N > level or N < level",
    ),
    stat(
        "count",
        Stat::Count(Event::ANY),
        ("count of", "ginti"),
        "how many times the relation starts to hold (the start counts), e.g. count(x > 0.5); count(x = 0.5) counts crossings of the level",
    ),
    stat(
        "drift",
        Stat::Drift,
        ("drift", "drift"),
        "largest |N(t) − N(0)| / |N(0)|",
    ),
];

/// The rows of the rigid-body measures, in table order.
pub fn rigid_rows() -> impl Iterator<Item = (&'static MeasureRow, Measure)> {
    MEASURES.iter().filter_map(|r| match r.kind {
        MeasureKind::Rigid(m) => Some((r, m)),
        MeasureKind::System(_) => None,
    })
}

/// The rows of the system statistics, in table order.
pub fn stat_rows() -> impl Iterator<Item = (&'static MeasureRow, Stat)> {
    MEASURES.iter().filter_map(|r| match r.kind {
        MeasureKind::System(s) => Some((r, s)),
        MeasureKind::Rigid(_) => None,
    })
}

/// `system measures: max(N), min(N), …`: the hint an unknown measure gets.
pub fn system_hint() -> String {
    let calls: Vec<String> = stat_rows().map(|(r, s)| call(r.name, s)).collect();
    format!("system measures: {}", calls.join(", "))
}

/// How a statistic is written: `max(N)`, `time_of(N > level)`.
pub fn call(name: &str, stat: Stat) -> String {
    if stat.event().is_some() {
        format!("{name}(N > level)")
    } else {
        format!("{name}(N)")
    }
}

/// `rigid-body measures: flips, flip_period, …`.
pub fn rigid_hint() -> String {
    let names: Vec<&str> = rigid_rows().map(|(r, _)| r.name).collect();
    format!("rigid-body measures: {}", names.join(", "))
}

/// The row of a rigid-body measure's name or a statistic's name.
pub(crate) fn row_named(name: &str) -> Option<&'static MeasureRow> {
    MEASURES.iter().find(|r| r.name == name)
}

/// The row of a measure (the statistic's row for `stat(N)`).
pub fn row_of(measure: Measure) -> &'static MeasureRow {
    row_kind(match measure {
        Measure::Of(s, _) => MeasureKind::System(s),
        m => MeasureKind::Rigid(m),
    })
}

/// The row of a rigid-body measure or a statistic (at any level).
pub fn row_kind(kind: MeasureKind) -> &'static MeasureRow {
    let kind = match kind {
        MeasureKind::System(s) => MeasureKind::System(s.base()),
        k => k,
    };
    MEASURES.iter().find(|r| r.kind == kind).unwrap_or(&MISSING)
}

/// What [`row_of`] gives a variant left out of the table (the test
/// `every_measure_has_one_row` keeps that from happening).
const MISSING: MeasureRow = MeasureRow {
    name: "?",
    help: "",
    kind: MeasureKind::Rigid(Measure::Flips),
    formula: "",
    words: ("?", "?"),
};

/// Measure text as written, split but not yet checked against a scene:
/// a rigid-body measure, or a statistic of the quantity at `quantity`
/// (byte offsets into the trimmed text).
#[derive(Debug, Clone, PartialEq)]
pub enum Parsed<'a> {
    Rigid(Measure),
    Of {
        stat: Stat,
        quantity: &'a str,
        /// Where the quantity sits in the trimmed text.
        at: Range<usize>,
    },
}

/// Why measure text does not parse. Ranges are byte offsets into the
/// trimmed text.
#[derive(Debug, Clone, PartialEq)]
pub enum ParseError<'a> {
    /// A name with no `(…)` that is no rigid-body measure.
    UnknownName(&'a str),
    /// `stat(…)` with an unknown statistic, which sits at `at`.
    UnknownStat { stat: &'a str, at: Range<usize> },
    /// `stat(…` with no closing `)`.
    NoClose,
    /// Text after the closing `)`, which sits at `close`.
    Trailing { close: usize },
    /// `time_of(x)` or `count(x)` without `> level`; the inside sits at
    /// `at`.
    NoRelation { at: Range<usize> },
    /// The level is not a finite number; it sits at `at`.
    BadLevel { at: Range<usize> },
}

/// The one parser of measure text: `flips`, or `period(theta)` (spaces
/// allowed around the parts). Whether the quantity names something is left
/// to the caller ([`Parsed::into_measure`] checks that it is a name at all).
pub fn parse(text: &str) -> Result<Parsed<'_>, ParseError<'_>> {
    let Some(open) = text.find('(') else {
        return match row_named(text).map(|r| r.kind) {
            Some(MeasureKind::Rigid(m)) => Ok(Parsed::Rigid(m)),
            _ => Err(ParseError::UnknownName(text)),
        };
    };
    let stat_name = text[..open].trim();
    let Some(MeasureKind::System(stat)) = row_named(stat_name).map(|r| r.kind) else {
        return Err(ParseError::UnknownStat {
            stat: stat_name,
            at: 0..open,
        });
    };
    let Some(close) = text.rfind(')').filter(|&c| c > open) else {
        return Err(ParseError::NoClose);
    };
    if close + 1 != text.len() {
        return Err(ParseError::Trailing { close });
    }
    let inner = &text[open + 1..close];
    let lead = inner.len() - inner.trim_start().len();
    let start = open + 1 + lead;
    if stat.event().is_none() {
        let quantity = inner.trim();
        return Ok(Parsed::Of {
            stat,
            quantity,
            at: start..start + quantity.len(),
        });
    }
    // `quantity rel level`.
    let body = inner.trim();
    let Some(op_at) = body.find(['=', '<', '>']) else {
        return Err(ParseError::NoRelation {
            at: start..start + body.len(),
        });
    };
    let quantity = body[..op_at].trim_end();
    let rest = &body[op_at..];
    let (rel, len) = [
        ("==", Rel::Crosses),
        (">=", Rel::AtLeast),
        ("<=", Rel::AtMost),
        ("=", Rel::Crosses),
        (">", Rel::Above),
        ("<", Rel::Below),
    ]
    .into_iter()
    .find(|(o, _)| rest.starts_with(o))
    .map(|(o, r)| (r, o.len()))
    .unwrap_or((Rel::Crosses, 1));
    let level_text = rest[len..].trim();
    let level_at = start + op_at + len + (rest[len..].len() - rest[len..].trim_start().len());
    let level =
        level_text
            .parse::<f64>()
            .ok()
            .and_then(Level::new)
            .ok_or(ParseError::BadLevel {
                at: level_at..level_at + level_text.len(),
            })?;
    let event = Event { rel, level };
    let stat = match stat {
        Stat::TimeOf(_) => Stat::TimeOf(event),
        _ => Stat::Count(event),
    };
    Ok(Parsed::Of {
        stat,
        quantity,
        at: start..start + quantity.len(),
    })
}

impl Parsed<'_> {
    /// The measure, once the quantity is a variable or observable name.
    pub(crate) fn into_measure(self) -> Result<Measure, QuantityError> {
        match self {
            Parsed::Rigid(m) => Ok(m),
            Parsed::Of { stat, quantity, .. } => {
                if !crate::system::expr::is_name(quantity) {
                    return Err(QuantityError::NotAName(quantity.to_string()));
                }
                let name = Name::new(quantity)
                    .ok_or_else(|| QuantityError::TooLong(quantity.to_string()))?;
                Ok(Measure::Of(stat, name))
            }
        }
    }
}

/// Why measure text written on the command line names no measure.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MeasureTextError {
    /// `stat(q)` where `q` is no usable name.
    #[error("`{text}`: {reason}")]
    Quantity { text: String, reason: QuantityError },
    /// Neither a rigid-body measure nor `stat(…)`.
    #[error("unknown measure `{0}` ({hint})", hint = system_hint())]
    UnknownName(String),
    /// `stat(…)` with an unknown statistic.
    #[error("unknown measure `{stat}` in `{text}`")]
    UnknownStat { stat: String, text: String },
    /// `stat(…` with no `)` at the end.
    #[error("`{0}`: expected `)` at the end")]
    NoClose(String),
    /// `time_of(…)`, `count(…)` without `N > level` (a finite level).
    #[error("`{0}`: write the quantity, a relation and a finite level, e.g. time_of(x > 0.5)")]
    Relation(String),
}

/// Why the quantity of `stat(q)` is not a name a measure can hold.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum QuantityError {
    #[error("`{0}` is not a variable or observable name")]
    NotAName(String),
    #[error("the name `{0}` is too long")]
    TooLong(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_measure_has_one_row() {
        for (i, r) in MEASURES.iter().enumerate() {
            assert!(
                MEASURES[..i]
                    .iter()
                    .all(|o| o.name != r.name && o.kind != r.kind),
                "{} twice",
                r.name
            );
            let m = match r.kind {
                MeasureKind::Rigid(m) => m,
                MeasureKind::System(s) => Measure::Of(s, Name::new("x").unwrap()),
            };
            assert_eq!(row_of(m), r);
            assert_eq!(m.name(), r.name);
        }
        // Every variant, spelled out once here so that the compiler points
        // at this test when one is added without a row.
        let check = |m: Measure| assert_ne!(row_of(m).name, "?", "{m:?} has no row");
        let x = || Name::new("x").unwrap();
        for m in [
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
            Measure::Of(Stat::Max, x()),
            Measure::Of(Stat::Min, x()),
            Measure::Of(Stat::Final, x()),
            Measure::Of(Stat::Mean, x()),
            Measure::Of(Stat::Crossings, x()),
            Measure::Of(Stat::Period, x()),
            Measure::Of(Stat::Drift, x()),
            Measure::Of(Stat::Amplitude, x()),
            Measure::Of(Stat::Beat, x()),
            Measure::Of(Stat::TimeOf(Event::ANY), x()),
            Measure::Of(Stat::Count(Event::ANY), x()),
        ] {
            match m {
                Measure::Flips
                | Measure::FlipPeriod
                | Measure::GrowthRate
                | Measure::EfoldTime
                | Measure::OscillationFreq
                | Measure::PrecessionRate
                | Measure::PrecessionPeriod
                | Measure::OmegaChange
                | Measure::EnergyDrift
                | Measure::MomentumDrift => (),
                Measure::Of(
                    Stat::Max
                    | Stat::Min
                    | Stat::Final
                    | Stat::Mean
                    | Stat::Crossings
                    | Stat::Period
                    | Stat::Drift
                    | Stat::Amplitude
                    | Stat::Beat
                    | Stat::TimeOf(_)
                    | Stat::Count(_),
                    _,
                ) => (),
            }
            check(m);
        }
    }

    #[test]
    fn hints_keep_their_spelling() {
        assert_eq!(
            system_hint(),
            "system measures: max(N), min(N), final(N), mean(N), amplitude(N), crossings(N), period(N), beat(N), time_of(N > level), count(N > level), drift(N)"
        );
    }

    #[test]
    fn parses_both_kinds() {
        assert_eq!(parse("flips"), Ok(Parsed::Rigid(Measure::Flips)));
        assert_eq!(
            parse("period( theta )"),
            Ok(Parsed::Of {
                stat: Stat::Period,
                quantity: "theta",
                at: 8..13
            })
        );
        assert_eq!(parse("flip"), Err(ParseError::UnknownName("flip")));
        assert_eq!(parse("max"), Err(ParseError::UnknownName("max")));
        assert_eq!(
            parse("flips(x)"),
            Err(ParseError::UnknownStat {
                stat: "flips",
                at: 0..5
            })
        );
        assert_eq!(parse("max(x"), Err(ParseError::NoClose));
        assert_eq!(parse("max(x)y"), Err(ParseError::Trailing { close: 5 }));
    }

    #[test]
    fn a_relation_and_its_level_are_part_of_the_measure() {
        let x = Name::new("x").unwrap();
        let m = Measure::parse("time_of( x >= 0.5 )").unwrap();
        let e = Event {
            rel: Rel::AtLeast,
            level: Level::new(0.5).unwrap(),
        };
        assert_eq!(m, Measure::Of(Stat::TimeOf(e), x));
        assert_eq!(m.to_string(), "time_of(x >= 0.5)");
        assert_eq!(Measure::parse(&m.to_string()), Ok(m));
        let c = Measure::parse("count(x == -1e-3)").unwrap();
        assert_eq!(c.to_string(), "count(x = -0.001)");
        assert_eq!(c.name(), "count");
        assert!(matches!(
            Measure::parse("time_of(x)"),
            Err(MeasureTextError::Relation(_))
        ));
        assert!(matches!(
            Measure::parse("count(x > inf)"),
            Err(MeasureTextError::Relation(_))
        ));
        assert_eq!(
            parse("time_of(x > y)"),
            Err(ParseError::BadLevel { at: 12..13 })
        );
    }
}
