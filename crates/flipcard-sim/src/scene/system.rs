//! A system scene's run: what it computes (its [`SystemPlan`], from what is
//! shown and measured), the run as the view plays it or a command samples
//! it, and the measures of its variables and observables.
//!
//! Each accepted step is sampled by dense output at [`POINTS_PER_STEP`]
//! points, so the measures follow the solution wherever the solver had to
//! look closely (Van der Pol's fast jumps, Robertson's first second) and
//! never depend on how often a frame is drawn.
//!
//! The panels are scaled to the same continuous solution: the extent of
//! each plotted quantity, of the phase pair and of each sketch coordinate
//! is followed as a measured `max` and `min` are, their extremes between
//! samples located on the dense output ([`SystemRun::sketch_extent`]), and
//! the sketch's trails follow the dense output between samples where a
//! chord would cut a corner ([`trail`]). A run computes them only for the
//! panels it shows ([`SystemPlan::extents`], [`SystemPlan::trail`]).
//!
//! A value that is not finite is never a measurement: a variable, an
//! observable or a sketch expression the run computes that becomes NaN or
//! infinite ends the run with its name, the time and the first operation at
//! fault ([`crate::system::compile::Cause`]), and a solver that gives
//! up at a point where an equation leaves its domain (a root of a negative
//! number, a division by zero) says so instead of "blows up".
//!
//! Work is bounded: each run may take at most [`MAX_RUN_WORK`] operations
//! of its compiled programs, so its step budget is that divided by the cost
//! of a step ([`crate::system::compile::Cost`]), and `flipcard check`
//! refuses a scene one step of which costs more than [`MAX_STEP_WORK`].
//! The app advances a run in [`Slice`]s, so a key is answered within a
//! frame whatever the scene.

use crate::error::SolveError;
use crate::method::MethodError;
use crate::scene::measure::{Measurements, Reading};
use crate::scene::slice::Slice;
use crate::scene::spec::{Mark, Measure, Stat, SystemPanel, SystemScene};
use crate::solvers::ode::{self, OdeKind, OdeMethod, OdeSolver, OdeSystem, Work};
use crate::system::System;
use crate::system::compile::{CompileError, Cost, Fault, POINTS_PER_STEP, Source, time};
use crate::system::spec::SceneAtol;
use flipcard_text::num::Num;
use tally::{Bracket, Edge, InStep, Tally, Watch, brent_max_within};
use trail::Trail;

/// A panel's extent (not a measure's extreme) is located to within the
/// quantity's range so far over this ([`tally::brent_max_within`]): half a
/// Braille dot of a panel 512 cells tall (four dots a cell), below what
/// any panel draws.
pub(crate) const EXTENT_RESOLUTION: f64 = 4096.0;

/// Points kept for each drawn curve against time and the phase portrait
/// (the sketch's trails keep theirs, [`trail::TRAIL_LEN`]).
pub(crate) const TRACE_LEN: usize = 2048;

/// Most operations of a scene's compiled programs one run may take (about a
/// second or two of work): a scene's step budget is this divided by
/// [`Cost::per_step`], below the solvers' own step budget.
pub(crate) const MAX_RUN_WORK: f64 = 1e9;
/// Most operations one step of a scene may take (a few milliseconds), so
/// that the app, which advances a run a step at a time between frames,
/// always answers a key promptly; `flipcard check` refuses a scene beyond
/// it.
pub(crate) const MAX_STEP_WORK: f64 = 2e6;

/// A variable this large when the solver gives up stopped the run by its
/// size (the solvers' cap is 1e150), not by a singularity.
const NEAR_CAP: f64 = 1e140;

/// Why a scene cannot run at all: one step costs too much.
pub fn check_cost(scene: &SystemScene, cost: &Cost) -> Result<(), CostError> {
    if cost.per_step() <= MAX_STEP_WORK {
        return Ok(());
    }
    Err(CostError {
        scene: scene.id.clone(),
        cost: *cost,
    })
}

/// A scene whose step costs more than [`MAX_STEP_WORK`]: its id and what a
/// step of it costs.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.describe())]
pub struct CostError {
    pub scene: String,
    pub cost: Cost,
}

impl CostError {
    fn describe(&self) -> String {
        let cost = &self.cost;
        format!(
            "scene {} needs about {} operations per step, more than the {:e} the app can play: its equations compile to {}, run {} times a step and once per variable ({}) for the Jacobian{}",
            self.scene,
            flipcard_text::num::sig(cost.per_step(), 3),
            MAX_STEP_WORK,
            flipcard_text::plural(cost.rhs, "operation", "operations"),
            crate::system::compile::EVALS_PER_STEP,
            cost.n,
            if cost.observables + cost.marks > 0 {
                format!(
                    "; its observables and sketch compile to {}, run {} times a step",
                    cost.observables + cost.marks,
                    POINTS_PER_STEP
                )
            } else {
                String::new()
            }
        )
    }
}

/// Why a run of a scene cannot start, or (for [`measure_system`]) did not
/// reach its end.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StartError {
    /// The scene's equations do not compile.
    #[error(transparent)]
    Compile(#[from] CompileError),
    #[error(transparent)]
    Cost(#[from] CostError),
    #[error(transparent)]
    Method(#[from] MethodError),
    /// The solver refused to start, or the run stopped early.
    #[error(transparent)]
    Run(#[from] RunError),
    /// A symplectic method on a scene that declares no separable
    /// Hamiltonian, or whose declaration does not split its equations.
    #[error("{method} needs a separable Hamiltonian: {why}")]
    NotHamiltonian { method: &'static str, why: String },
}

/// Why a measure cannot be read from a run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReadingError {
    #[error("{}({name}): the run has no samples", stat.name())]
    NoSamples { stat: Stat, name: String },
    /// `period(name)`: `name` crossed its mid level upwards fewer than
    /// twice (`upward` times).
    #[error("period({name}): {name} crosses the level halfway between its minimum and maximum upwards {} over the run; a period needs two", if *upward == 0 { "never" } else { "once" })]
    NoPeriod { name: String, upward: usize },
    /// `beat(name)`: the envelope through `name`'s peaks crossed its mid
    /// level upwards fewer than twice.
    #[error("beat({name}): the envelope through its {peaks} peaks crosses the level halfway between the lowest and highest peak upwards {} over the run; a beat needs two", if *upward == 0 { "never" } else { "once" })]
    NoBeat {
        name: String,
        peaks: usize,
        upward: usize,
    },
    /// `beat(name)`: the peaks do not vary, so there is no envelope.
    #[error(
        "beat({name}): its peaks are all the same height ({peaks} peaks over the run): there is no envelope to time; for the time between peaks measure period({name})"
    )]
    FlatBeat { name: String, peaks: usize },
    /// `time_of(…)`: the relation never held over the run.
    #[error("{measure}: {what} never holds over the run")]
    Never { measure: String, what: String },
    #[error("`{0}` is a rigid-body measure; this scene is a system")]
    Rigid(Measure),
    #[error("`{name}` is not a variable or observable of scene {scene}")]
    Unknown { name: String, scene: String },
    #[error("{0} was not planned for this run")]
    NotPlanned(Measure),
    #[error("{0} is not a finite number")]
    NotFinite(Measure),
    /// The run (`method`) does not show the measure (`why`), a finer run
    /// of the same scene (`finer`) does: its value there.
    #[error(
        "{measure}: the run at {method} is too coarse for it ({why}); at {finer} it is {}: run at {finer} or finer",
        flipcard_text::num::sig(*value, 4)
    )]
    TooCoarse {
        measure: String,
        why: String,
        method: String,
        finer: String,
        value: f64,
    },
}

impl ReadingError {
    /// The measure needs crossings or an event the run did not show, which
    /// a run too coarse to follow the motion may miss.
    pub fn may_be_too_coarse(&self) -> bool {
        matches!(
            self,
            ReadingError::NoPeriod { .. }
                | ReadingError::NoBeat { .. }
                | ReadingError::Never { .. }
        )
    }
}

/// Why a run stopped early.
#[derive(Debug, Clone, PartialEq)]
pub enum RunError {
    /// The solver stopped (a blow-up, a refused stiff problem, its step
    /// budget, a bad setting).
    Ode(SolveError),
    /// A quantity left its domain: its name, the time and the cause, and
    /// the expression the operation at fault was written in.
    Domain {
        t: f64,
        message: String,
        at: Option<Source>,
    },
    /// A quantity the scene declares conserved moved from `from` (at the
    /// start) to `to` near `t`, by more than its own size: the run no
    /// longer follows the motion (the guard the rigid body's methods have,
    /// for every system method).
    NotConserved {
        name: String,
        t: f64,
        from: f64,
        to: f64,
    },
    /// A variable grew to `value` near `t`, close to the magnitude past
    /// which no method can go on (1e150: its square would overflow f64).
    TooLarge { t: f64, name: String, value: f64 },
    /// The step size fell to `h` near `t` while the solution stayed
    /// bounded, or (with `grew`) the run grew without bound led by a
    /// variable the tolerance left unchecked: the run cannot meet its
    /// tolerance. `uncontrolled` are the
    /// variables whose typical size over the samples (the median of
    /// |value|) lies below their absolute tolerance: (name, size, atol).
    Inaccurate {
        t: f64,
        h: f64,
        uncontrolled: Vec<(String, f64, f64)>,
        rtol: f64,
        /// The method was already the implicit one.
        radau: bool,
        /// The run did grow without bound, led by this variable and value,
        /// one of those the absolute tolerance did not control: the growth
        /// may be the unchecked error's rather than the equations'.
        grew: Option<(String, f64)>,
        /// Those of `uncontrolled` (with no tolerance of the scene's) whose
        /// typical size lies below the default's floor, or whose tolerance
        /// is held at it
        /// ([`crate::solvers::ode::BySize::NOISE`] of the largest size any
        /// variable reached): sizes that small may be the rounding of the
        /// larger ones' arithmetic, which no tolerance cures.
        at_floor: Vec<String>,
    },
    /// The run took the most work a scene may ([`MAX_RUN_WORK`]).
    Work {
        t: f64,
        steps: u64,
        per_step: f64,
        duration: f64,
    },
}

impl From<SolveError> for RunError {
    fn from(e: SolveError) -> RunError {
        RunError::Ode(e)
    }
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Ode(SolveError::BlowUp { t }) => {
                write!(f, "the solution blows up near t = {}", time(*t))
            }
            RunError::Ode(SolveError::Stiff { t }) => write!(
                f,
                "the problem is stiff from t = {}: adaptive (explicit) refuses it; use --method radau or auto",
                flipcard_text::num::rounded(*t, 4)
            ),
            RunError::Ode(e) => write!(f, "{e}"),
            RunError::Domain { message, .. } => f.write_str(message),
            RunError::NotConserved { name, t, from, to } => write!(
                f,
                "`{name}`, declared conserved, went from {} at the start to {} near t = {}: the run no longer follows the motion (its method or step cannot keep what the equations conserve); tighten the tolerance, take a smaller dt, or use auto",
                flipcard_text::num::sig(*from, 4),
                flipcard_text::num::sig(*to, 4),
                time(*t)
            ),
            RunError::TooLarge { t, name, value } => write!(
                f,
                "`{name}` reached {} near t = {}, where the run stops: past 1e150 its square overflows f64, so no method can go on; the solution grows past what flipcard can compute (if it is meant to be this large, measure it in larger units)",
                flipcard_text::num::sig(*value, 3),
                time(*t)
            ),
            RunError::Inaccurate {
                t,
                h,
                uncontrolled,
                rtol,
                radau,
                grew,
                at_floor,
            } => {
                match grew {
                    Some((name, value)) => write!(
                        f,
                        "the run grows without bound near t = {} (`{name}` reached {}), but it grew from below its absolute tolerance: the growth may be the unchecked error's, not the equations'",
                        time(*t),
                        flipcard_text::num::sig(*value, 2),
                    )?,
                    None => write!(
                        f,
                        "the step size fell to {} near t = {} while no value grew past a million times the size the run started from: not a blow-up, the run cannot meet its tolerance here",
                        flipcard_text::num::sig(*h, 2),
                        time(*t),
                    )?,
                }
                if uncontrolled.is_empty() {
                    return write!(
                        f,
                        "; tighten the tolerance (now rtol {}){}",
                        Num(*rtol),
                        if *radau { "" } else { " or use --method radau" }
                    );
                }
                let one = uncontrolled.len() == 1;
                let named: Vec<String> = (uncontrolled.iter())
                    .map(|(n, size, atol)| {
                        format!(
                            "`{n}` (typically {}, atol {})",
                            flipcard_text::num::sig(*size, 2),
                            flipcard_text::num::sig(*atol, 2)
                        )
                    })
                    .collect();
                // A millionth of each one's typical size, as a power of ten;
                // a size of 0 says only that the value sat below its
                // tolerance everywhere: ten thousand times less, then.
                let suggest: Vec<(String, String)> = (uncontrolled.iter())
                    .map(|(n, size, atol)| {
                        let target = if *size > 0.0 {
                            size * 1e-6
                        } else {
                            atol * 1e-4
                        };
                        let power = 10f64.powf(target.log10().floor());
                        (n.clone(), flipcard_text::num::sig(power, 1))
                    })
                    .collect();
                let each = |sep: &str, eq: &str| {
                    (suggest.iter())
                        .map(|(n, a)| format!("{n}{eq}{a}"))
                        .collect::<Vec<_>>()
                        .join(sep)
                };
                write!(
                    f,
                    ". {} {} below {} absolute tolerance, so {} errors go unchecked; give {} an absolute tolerance of about a millionth of {} size (`atol = {{ {} }}` in the scene, or --atol {})",
                    named.join(", "),
                    if one { "stays" } else { "stay" },
                    if one { "its" } else { "their" },
                    if one { "its" } else { "their" },
                    if one { "it" } else { "them" },
                    if one { "its" } else { "their" },
                    each(", ", " = "),
                    each(",", "="),
                )?;
                if at_floor.is_empty() {
                    return Ok(());
                }
                let quoted: Vec<String> = at_floor.iter().map(|n| format!("`{n}`")).collect();
                write!(
                    f,
                    "; {} fell below 1e-16 of the largest size any variable reached, where the default stops following sizes: values that small may be the rounding of the larger ones' arithmetic, which no tolerance cures (a sum of variables the equations keep fixed is held against it: docs/deck-format.md, \"How far a tolerance goes\"); if they are not, the atol above reaches them",
                    quoted.join(", ")
                )
            }
            RunError::Work {
                t,
                steps,
                per_step,
                duration,
            } => write!(
                f,
                "the run stops at t = {} of {}: {} steps of about {} operations each reach the {:e} a scene may take; shorten the duration, loosen the tolerance or simplify the equations",
                time(*t),
                Num(*duration),
                steps,
                flipcard_text::num::sig(*per_step, 3),
                MAX_RUN_WORK
            ),
        }
    }
}

impl std::error::Error for RunError {}

/// The solver's step budget for a scene of `cost`: its share of
/// [`MAX_RUN_WORK`], within the solvers' own budget; and whether the work
/// is what limits it.
fn step_budget(cost: &Cost, default: u64) -> (u64, bool) {
    let by_work = (MAX_RUN_WORK / cost.per_step().max(1.0)).floor().max(1.0);
    if by_work < default as f64 {
        (by_work as u64, true)
    } else {
        (default, false)
    }
}

/// The absolute tolerance of a run of `scene`: the one the scene declares
/// for a variable, and for the others the method's own, which follows each
/// one's size over the run ([`ode::BySize`]); a reference run
/// (`reference`) keeps the method's where that is tighter. A fixed-step
/// run has none.
fn with_scene_atol(scene: &SystemScene, opts: &mut ode::Options, reference: bool) {
    let (Some(declared), ode::Atol::BySize(by_size)) = (&scene.atol, &mut opts.atol) else {
        return;
    };
    let named = |v: &String| match declared {
        SceneAtol::All(a) => Some(*a),
        SceneAtol::Each(each) => each.iter().find(|(n, _)| n == v).map(|(_, a)| *a),
    };
    let each = (scene.variables.iter()).map(named).collect();
    match reference {
        // The reference follows the sizes too, within what the scene asks.
        true => by_size.cap = each,
        false => by_size.fixed = each,
    }
}

/// How many times the largest size it had before a variable that went
/// below its absolute tolerance must grow to be refused
/// ([`SystemRun::unchecked_rise`]): Van der Pol's v at μ = 1e4 crosses zero
/// after each jump and its next jump peaks a hair (1e-4) above the last;
/// that is the equations', not an error run away.
const RISE: f64 = 10.0;

/// How many times its absolute tolerance a variable must have reached for
/// a fall below that tolerance to arm [`SystemRun::unchecked_rise`]: a
/// size the error control really tracked. Within its tolerance a variable
/// may read as large as the tolerance itself (Van der Pol's v near 7e-6 at
/// μ = 1e5 under an `atol` of 1e-3 was computed near 1e-3 at the start by
/// DOP853, which armed the check and had the first relaxation jump
/// refused as a run-away).
const TRACKED: f64 = 100.0;

/// Sizes of each variable kept for its median (see `SystemRun::sizes`).
const SIZES_KEPT: usize = 1024;

/// What a system scene computes, from what it shows and measures.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemPlan {
    /// Per observable: evaluated at all (plotted, drawn in the phase
    /// portrait, sketched through, measured or conserved in diagnostics).
    pub observables: Vec<bool>,
    /// Quantities (variables, then observables) the meter tracks.
    pub metered: Vec<usize>,
    /// The sketch's expressions are evaluated.
    pub sketch: bool,
    /// A second, tight run for the error in the diagnostics.
    pub reference: bool,
    /// The Jacobian is compiled (implicit methods only).
    pub jacobian: bool,
    /// Quantities whose every sample is kept (for their period).
    pub periods: Vec<usize>,
    /// Quantities whose extremes are located on the dense output (their
    /// `max`, `min`, `amplitude` or `beat` is measured).
    pub extremes: Vec<usize>,
    /// Quantities whose every peak is kept (their `beat` is measured).
    pub peaks: Vec<usize>,
    /// `time_of` and `count` measures, by quantity.
    pub events: Vec<(usize, Stat)>,
    /// Quantities whose extent over the run the shown panels are scaled
    /// to (the plotted ones, the phase pair, and the sketch's coordinates,
    /// numbered after the observables), their extremes between samples
    /// located on the dense output as a measure's are.
    pub extents: Vec<usize>,
    /// The sketch's trails are kept to be drawn (followed on the dense
    /// output where a chord between samples would stray from the curve).
    pub trail: bool,
}

impl SystemPlan {
    pub fn for_scene(scene: &SystemScene, method: OdeMethod, measures: &[Measure]) -> SystemPlan {
        let n = scene.variables.len();
        let index = |name: &str| -> Option<usize> {
            scene.variables.iter().position(|v| v == name).or_else(|| {
                scene
                    .observables
                    .iter()
                    .position(|(o, _)| o == name)
                    .map(|k| n + k)
            })
        };
        let diagnostics = scene.shows(SystemPanel::Diagnostics);
        let mut metered: Vec<usize> = Vec::new();
        let add = |q: Option<usize>, metered: &mut Vec<usize>| {
            if let Some(q) = q
                && !metered.contains(&q)
            {
                metered.push(q);
            }
        };
        let mut periods = Vec::new();
        let mut extremes = Vec::new();
        let mut peaks = Vec::new();
        let mut events = Vec::new();
        for m in measures {
            if let Measure::Of(stat, name) = m {
                add(index(name.as_str()), &mut metered);
                if *stat == Stat::Period {
                    add(index(name.as_str()), &mut periods);
                }
                if matches!(stat, Stat::Max | Stat::Min | Stat::Amplitude | Stat::Beat) {
                    add(index(name.as_str()), &mut extremes);
                }
                if *stat == Stat::Beat {
                    add(index(name.as_str()), &mut peaks);
                }
                if stat.event().is_some()
                    && let Some(q) = index(name.as_str())
                    && !events.contains(&(q, *stat))
                {
                    events.push((q, *stat));
                }
            }
        }
        if diagnostics {
            for c in &scene.conserved {
                add(index(c), &mut metered);
            }
        }
        let mut drawn = metered.clone();
        let mut extents = Vec::new();
        if scene.shows(SystemPanel::Plot) {
            for p in &scene.plot {
                add(index(p), &mut drawn);
                add(index(p), &mut extents);
            }
        }
        if scene.shows(SystemPanel::Phase)
            && let Some(pair) = &scene.phase
        {
            for p in pair {
                add(index(p), &mut drawn);
                add(index(p), &mut extents);
            }
        }
        let sketch = scene.shows(SystemPanel::Sketch) && !scene.sketch.is_empty();
        if sketch {
            let marks = n + scene.observables.len();
            let coordinates: usize = scene.sketch.iter().map(|m| m.exprs().len()).sum();
            extents.extend(marks..marks + coordinates);
        }
        let trail = sketch && scene.sketch.iter().any(|m| matches!(m, Mark::Trail(_)));
        let mut observables = vec![false; scene.observables.len()];
        for q in &drawn {
            if *q >= n {
                observables[q - n] = true;
            }
        }
        SystemPlan {
            observables,
            metered,
            sketch,
            reference: diagnostics,
            jacobian: method.kind.implicit(),
            periods,
            extremes,
            peaks,
            events,
            extents,
            trail,
        }
    }

    /// The plan of a run nobody draws: what `self` measures, without the
    /// panels' extents, trails or reference.
    pub fn headless(self) -> SystemPlan {
        SystemPlan {
            reference: false,
            sketch: false,
            extents: Vec::new(),
            trail: false,
            ..self
        }
    }
}

/// One point of a drawn curve: time and the values of the drawn
/// quantities (or sketch coordinates).
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub t: f64,
    pub values: Vec<f64>,
}

/// A fixed-length record of a run for drawing: every k-th sample, k
/// doubling when full, so it always spans the whole run so far.
#[derive(Debug, Clone, Default)]
pub(crate) struct Trace {
    pub points: Vec<Point>,
    stride: usize,
    seen: usize,
}

impl Trace {
    /// The next sample is kept (the others are passed without building
    /// their point).
    fn wants(&self) -> bool {
        self.seen.is_multiple_of(self.stride.max(1))
    }

    /// Counts a sample not kept.
    fn pass(&mut self) {
        self.seen += 1;
    }

    fn push(&mut self, p: Point) {
        if self.stride == 0 {
            self.stride = 1;
        }
        if self.seen.is_multiple_of(self.stride) {
            self.points.push(p);
            if self.points.len() >= TRACE_LEN {
                let kept: Vec<Point> = self.points.iter().step_by(2).cloned().collect();
                self.points = kept;
                self.stride *= 2;
            }
        }
        self.seen += 1;
    }
}

/// What the diagnostics panel shows.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemDiagnostics {
    /// The solver now stepping.
    pub solver: &'static str,
    pub work: Work,
    /// When auto found the problem stiff and switched to Radau IIA.
    pub stiff_at: Option<f64>,
    /// Drift so far of each conserved observable (name, relative drift).
    pub drift: Vec<(String, f64)>,
    /// Largest error against the reference run so far, relative to the
    /// size of the state (None while no reference runs).
    pub error: Option<f64>,
}

/// How far a quantity declared conserved moved over a run: the largest
/// |value − start| over every sample, and that relative to |start| (none
/// when the start is 0, where no size says what is large).
#[derive(Debug, Clone, PartialEq)]
pub struct ConservedDrift {
    pub name: String,
    pub start: f64,
    pub change: f64,
    pub relative: Option<f64>,
}

/// Evaluations of a run's dense output between its samples (each a state
/// and the quantity or sketch coordinates wanted there), by what asked.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Probes {
    /// Locating extremes (measures' and extents'), events and edges.
    pub searches: u64,
    /// Following the sketch's trails between samples.
    pub trail: u64,
}

/// A system scene running.
pub struct SystemRun {
    scene: SystemScene,
    system: System,
    plan: SystemPlan,
    method: OdeMethod,
    solver: Box<dyn OdeSolver>,
    reference: Option<Box<dyn OdeSolver>>,
    /// Index into the quantities of each plotted name, phase pair.
    plot: Vec<usize>,
    phase: Option<[usize; 2]>,
    /// Frame time and state.
    t: f64,
    state: Vec<f64>,
    /// Last sampled time (the meter's frontier).
    sampled: f64,
    tallies: Vec<(usize, Tally)>,
    watches: Vec<Watch>,
    /// Each conserved quantity this run computes, with its value at the
    /// start (set by the first sample).
    conserved: Option<Vec<(usize, f64)>>,
    /// Every declared conserved quantity this run computes: its index, its
    /// value at the start and its largest change from it over the samples.
    drift: Vec<(usize, f64, f64)>,
    trace: Trace,
    /// The sketch's coordinates over the run, as its trails are drawn
    /// (when the plan keeps them).
    trail: Option<Trail>,
    error: Option<RunError>,
    ref_error: f64,
    scratch: Vec<f64>,
    /// A state and observables at a time between samples (where an
    /// extreme is searched).
    probe: Vec<f64>,
    probe_obs: Vec<f64>,
    /// Evaluations of the dense output between samples so far: by the
    /// searches for extremes, crossings and edges, and by the trail.
    probes: Probes,
    /// The observables computed at each sample (the plan's, up to the last
    /// of them), and their values at the last sample.
    observables_upto: Option<usize>,
    obs: Vec<f64>,
    marks: Vec<f64>,
    /// The last sample that passed (its time is `sampled`).
    good: Vec<f64>,
    /// |value| of each variable at the samples, each weighted by the time
    /// since the one before, at most [`SIZES_KEPT`] of them (neighbours
    /// merged when full): their weighted median is the typical size of
    /// each over the run's time, which the many short steps before a
    /// failure do not move; with the solver's absolute tolerance of each, to name
    /// the ones it does not control when the run cannot meet its tolerance.
    sizes: Vec<Vec<(f64, f64)>>,
    /// Each variable's largest |value| at the samples so far, and, once it
    /// has sat below its absolute tolerance after having a size, that
    /// size and that tolerance ([`SystemRun::unchecked_rise`]).
    largest: Vec<f64>,
    dipped: Vec<Option<(f64, f64)>>,
    /// Each variable's sign at the last sample where it was at least its
    /// absolute tolerance, before it fell (0 until then).
    sign: Vec<f64>,
    /// Every operation's value at the start and the end of an RK4 step,
    /// and the state at its end (for the domain check).
    step_tapes: [Vec<f64>; 2],
    step_end: Vec<f64>,
    cost: Cost,
    /// The step budget comes from [`MAX_RUN_WORK`].
    work_limited: bool,
    /// The last step taken, [t0, t1] (t1 at most the duration), whose
    /// samples up to `sampled` are done.
    span: Option<(f64, f64)>,
}

/// `the solution blows up near t = 1.0`, `` `lnx` is NaN at t = 1.5: ln of a
/// negative number (ln(-0.5)) ``: why a run stopped, in one line.
pub fn describe(e: &RunError) -> String {
    e.to_string()
}

impl SystemRun {
    /// A run that computes what `scene` shows and what `measures` need.
    pub fn new(
        scene: &SystemScene,
        method: OdeMethod,
        measures: &[Measure],
    ) -> Result<SystemRun, StartError> {
        let plan = SystemPlan::for_scene(scene, method, measures);
        SystemRun::with_plan(scene, method, plan)
    }

    pub fn with_plan(
        scene: &SystemScene,
        method: OdeMethod,
        plan: SystemPlan,
    ) -> Result<SystemRun, StartError> {
        let system = System::compile(scene, plan.jacobian)?;
        if OdeKind::SYMPLECTIC.contains(&method.kind) {
            let why = match &scene.hamiltonian {
                None => Some(format!(
                    "scene {} declares none (`hamiltonian = {{ q = [...], p = [...] }}`, positions and their momenta); use rk4 or auto",
                    scene.id
                )),
                Some(_) => system.hamiltonian_error(scene),
            };
            if let Some(why) = why {
                return Err(StartError::NotHamiltonian {
                    method: method.kind.name(),
                    why,
                });
            }
        }
        let cost = system.cost();
        check_cost(scene, &cost)?;
        let (m, mut opts) = method.solver(scene.duration);
        with_scene_atol(scene, &mut opts, false);
        let (max_steps, work_limited) = step_budget(&cost, opts.max_steps);
        opts.max_steps = max_steps;
        let solver =
            ode::make(m, system.clone(), 0.0, &scene.initial, &opts).map_err(RunError::from)?;
        let reference = if plan.reference {
            let r = OdeMethod::with_setting(OdeKind::Radau, ode::REFERENCE_RTOL)?;
            let (m, mut opts) = r.solver(scene.duration);
            with_scene_atol(scene, &mut opts, true);
            opts.max_steps = step_budget(&cost, opts.max_steps).0;
            let sys = System::compile(scene, true)?;
            Some(ode::make(m, sys, 0.0, &scene.initial, &opts).map_err(RunError::from)?)
        } else {
            None
        };
        let n = scene.variables.len();
        let index = |name: &str| -> usize {
            scene
                .variables
                .iter()
                .position(|v| v == name)
                .or_else(|| {
                    scene
                        .observables
                        .iter()
                        .position(|(o, _)| o == name)
                        .map(|k| n + k)
                })
                .unwrap_or(0)
        };
        let plot = if scene.shows(SystemPanel::Plot) {
            scene.plot.iter().map(|p| index(p)).collect()
        } else {
            Vec::new()
        };
        let phase = scene
            .phase
            .as_ref()
            .filter(|_| scene.shows(SystemPanel::Phase))
            .map(|[a, b]| [index(a), index(b)]);
        // A coordinate of the sketch is numbered after the observables;
        // its extent is followed only when the sketch is computed.
        let marks = n + system.observable_count();
        let mut plan = plan;
        plan.extents.retain(|&q| q < marks || plan.sketch);
        let mut tracked = plan.metered.clone();
        for &q in &plan.extents {
            if !tracked.contains(&q) {
                tracked.push(q);
            }
        }
        let tallies = tracked
            .into_iter()
            .map(|q| {
                let mut tally = if plan.metered.contains(&q) {
                    Tally::new(plan.peaks.contains(&q))
                } else {
                    Tally::extent_only()
                };
                tally.keeps = plan.periods.contains(&q);
                tally.measured = plan.extremes.contains(&q);
                tally.searched = tally.measured || plan.extents.contains(&q);
                (q, tally)
            })
            .collect();
        let trail = (plan.trail && plan.sketch).then(|| Trail::new(&scene.sketch));
        let watches = plan
            .events
            .iter()
            .filter_map(|&(q, stat)| Watch::new(q, stat))
            .collect();
        let observables_upto = plan.observables.iter().rposition(|&o| o);
        let mut run = SystemRun {
            scene: scene.clone(),
            obs: vec![0.0; system.observable_count()],
            probe_obs: vec![0.0; system.observable_count()],
            probes: Probes::default(),
            marks: vec![0.0; system.mark_count()],
            system,
            plan,
            method,
            solver,
            reference,
            plot,
            phase,
            t: 0.0,
            state: scene.initial.clone(),
            sampled: 0.0,
            tallies,
            watches,
            conserved: None,
            drift: Vec::new(),
            trace: Trace::default(),
            trail,
            error: None,
            ref_error: 0.0,
            scratch: vec![0.0; n],
            probe: vec![0.0; n],
            observables_upto,
            good: scene.initial.clone(),
            sizes: vec![Vec::new(); n],
            largest: vec![0.0; n],
            dipped: vec![None; n],
            sign: vec![0.0; n],
            step_tapes: [Vec::new(), Vec::new()],
            step_end: Vec::new(),
            cost,
            work_limited,
            span: None,
        };
        let y0 = scene.initial.clone();
        if let Err(e) = run.sample(0.0, &y0, None) {
            run.error = Some(e);
        }
        Ok(run)
    }

    /// The index of a variable or observable among the quantities.
    pub fn quantity(&self, name: &str) -> Option<usize> {
        let n = self.scene.variables.len();
        self.scene
            .variables
            .iter()
            .position(|v| v == name)
            .or_else(|| {
                self.scene
                    .observables
                    .iter()
                    .position(|(o, _)| o == name)
                    .map(|k| n + k)
            })
    }

    /// Quantity `q` at the sample just computed: a variable, or an
    /// observable of the plan.
    fn value(&self, q: usize, y: &[f64]) -> f64 {
        let n = y.len();
        let marks = n + self.obs.len();
        if q < n {
            y[q]
        } else if q < marks {
            self.obs[q - n]
        } else {
            self.marks[q - marks]
        }
    }

    /// What the run computes at (t, y): the plan's observables and sketch.
    /// A value that is not finite is an error, with its cause.
    fn compute(&mut self, t: f64, y: &[f64]) -> Result<(), RunError> {
        if let Some(k) = self.observables_upto {
            self.system.observables_upto(k, t, y, &mut self.obs);
            let plan = &self.plan.observables;
            if self.obs[..=k]
                .iter()
                .zip(plan)
                .any(|(v, &on)| on && !v.is_finite())
            {
                let fault = self
                    .system
                    .observable_program()
                    .fault(t, y, &|k| plan.get(k).copied().unwrap_or(false));
                return Err(self.domain(t, fault));
            }
        }
        if self.plan.sketch {
            self.system.marks_into(t, y, &mut self.marks);
            if self.marks.iter().any(|v| !v.is_finite()) {
                let fault = self.system.mark_program().fault(t, y, &|_| true);
                return Err(self.domain(t, fault));
            }
        }
        Ok(())
    }

    /// RK4 takes its steps whatever the equations do between them: a step
    /// across a zero of a divisor (x' = −1/x past t = 0.5, where
    /// x = √(1 − 2t) ends) lands on finite numbers that belong to no
    /// solution, and the run would go on printing them. So after each RK4
    /// step the divisors at its two ends are compared (the adaptive
    /// methods' steps collapse there instead, and `solver_error` names the
    /// cause).
    fn fixed_step_left_the_domain(&mut self, t0: f64, t1: f64) -> Option<RunError> {
        if !self.method.kind.fixed_step() {
            return None;
        }
        // The tape at the step's start is the previous step's end.
        let equations = self.system.equations();
        if self.step_tapes[0].is_empty() {
            equations.tape(t0, &self.scene.initial, &mut self.step_tapes[0]);
        }
        self.step_end.resize(self.good.len(), 0.0);
        self.solver.dense(t1, &mut self.step_end).ok()?;
        let [start, end] = &mut self.step_tapes;
        equations.tape(t1, &self.step_end, end);
        let fault = equations.crossing(start, end);
        self.step_tapes.swap(0, 1);
        Some(self.domain(t1, Some(fault?)))
    }

    fn domain(&self, t: f64, fault: Option<Fault>) -> RunError {
        RunError::Domain {
            t,
            at: fault.as_ref().map(|f| f.written_in),
            message: match fault {
                Some(f) => f.describe(&self.scene, t),
                None => format!("a value is not finite at t = {}", time(t)),
            },
        }
    }

    fn sample(&mut self, t: f64, y: &[f64], at: Option<InStep>) -> Result<(), RunError> {
        self.compute(t, y)?;
        self.check_conserved(t, y)?;
        self.unchecked_rise(t, y)?;
        for k in 0..self.tallies.len() {
            let q = self.tallies[k].0;
            let v = self.value(q, y);
            let keep = self.tallies[k].1.keeps;
            self.tallies[k].1.add(t, v, keep, at);
        }
        for k in 0..self.watches.len() {
            let v = self.value(self.watches[k].q, y);
            self.watches[k].add(t, v);
        }
        if (!self.plot.is_empty() || self.phase.is_some()) && self.trace.wants() {
            let phase = self.phase.iter().flatten();
            let values = (self.plot.iter().chain(phase))
                .map(|&q| self.value(q, y))
                .collect();
            self.trace.push(Point { t, values });
        } else {
            self.trace.pass();
        }
        if let Some(trail) = &mut self.trail {
            let span = trail.span(|q| {
                let q = y.len() + self.obs.len() + q;
                let (_, tally) = self.tallies.iter().find(|(k, _)| *k == q)?;
                tally.extent()
            });
            // Between the last sample and this one the step's dense output
            // is at hand (every sample but the run's first).
            let (solver, system, probe) = (&mut self.solver, &self.system, &mut self.probe);
            let count = &mut self.probes.trail;
            let between = |tm: f64| {
                *count += 1;
                if at.is_none() || solver.dense(tm, probe).is_err() {
                    return None;
                }
                let mut out = vec![0.0; system.mark_count()];
                system.marks_into(tm, probe, &mut out);
                out.iter().all(|v| v.is_finite()).then_some(out)
            };
            let p = trail.point(t, &self.marks);
            trail.add(p, span, between);
        }
        let weight = (t - self.sampled).max(0.0);
        for (kept, v) in self.sizes.iter_mut().zip(y) {
            kept.push((v.abs(), weight));
            if kept.len() >= SIZES_KEPT {
                *kept = kept
                    .chunks(2)
                    .map(|p| (p[0].0, p.iter().map(|q| q.1).sum()))
                    .collect();
            }
        }
        self.sampled = t;
        self.good.copy_from_slice(y);
        Ok(())
    }

    /// Refuses a sample where a quantity the scene declares conserved has
    /// moved by more than its own size from the start (none whose start is
    /// 0, where no size says what "more" is; an observable only when this
    /// run computes it).
    fn check_conserved(&mut self, t: f64, y: &[f64]) -> Result<(), RunError> {
        let n = y.len();
        let computed = |q: usize, plan: &SystemPlan| {
            q < n || plan.observables.get(q - n).copied().unwrap_or(false)
        };
        if self.conserved.is_none() {
            let all: Vec<(usize, f64)> = (self.scene.conserved.iter())
                .filter_map(|c| self.quantity(c))
                .filter(|&q| computed(q, &self.plan))
                .map(|q| (q, self.value(q, y)))
                .filter(|(_, v)| v.is_finite())
                .collect();
            self.drift = all.iter().map(|&(q, v)| (q, v, 0.0)).collect();
            let list = all
                .into_iter()
                .filter(|(_, v)| v.abs() >= tally::TINY)
                .collect();
            self.conserved = Some(list);
            return Ok(());
        }
        for k in 0..self.drift.len() {
            let (q, from, _) = self.drift[k];
            let change = (self.value(q, y) - from).abs();
            let largest = &mut self.drift[k].2;
            // NaN (a value that is not finite) counts as the largest.
            if change > *largest || change.is_nan() {
                *largest = change;
            }
        }
        for &(q, from) in self.conserved.as_deref().unwrap_or(&[]) {
            let to = self.value(q, y);
            if (to - from).abs() > from.abs() {
                let mut names = self
                    .scene
                    .variables
                    .iter()
                    .map(String::as_str)
                    .chain(self.scene.observables.iter().map(|(o, _)| o.as_str()));
                return Err(RunError::NotConserved {
                    name: names.nth(q).unwrap_or_default().to_string(),
                    t,
                    from,
                    to,
                });
            }
        }
        Ok(())
    }

    /// Where the first bad value appears between the last good sample and
    /// (t, y) of the same step, to the resolution of f64 (the failure
    /// path): the time reported is where the quantity leaves its domain,
    /// not the next sample's.
    fn first_bad(&mut self, t_bad: f64) -> (f64, Vec<f64>) {
        let n = self.good.len();
        let (mut lo, mut hi) = (self.sampled, t_bad);
        let mut y_hi = vec![0.0; n];
        if self.solver.dense(hi, &mut y_hi).is_err() {
            return (hi, y_hi);
        }
        let mut y = vec![0.0; n];
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi || self.solver.dense(mid, &mut y).is_err() {
                break;
            }
            if self.compute(mid, &y).is_ok() {
                lo = mid;
            } else {
                hi = mid;
                y_hi.copy_from_slice(&y);
            }
        }
        (hi, y_hi)
    }

    /// Why the solver stopped: at a point where an equation leaves its
    /// domain (NaN just ahead of the last good state, or a divisor that
    /// crosses zero there), that cause; else what the solver said.
    fn solver_error(&self, e: SolveError) -> RunError {
        let (y, t0) = (&self.good, self.sampled);
        // Near the magnitude cap (a blow-up, or a budget spent on steps
        // refused for their size): the run stops because the numbers grow
        // past what f64 arithmetic can carry, which is not the same as a
        // solution going to infinity at a finite time.
        if let Some((k, v)) = y
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .filter(|(_, v)| v.abs() >= NEAR_CAP)
        {
            return RunError::TooLarge {
                t: t0,
                name: self.scene.variables.get(k).cloned().unwrap_or_default(),
                value: *v,
            };
        }
        let (SolveError::BlowUp { t } | SolveError::StepSize { t, .. }) = e else {
            if let SolveError::StepBudget { t, steps, .. } = e
                && self.work_limited
            {
                return RunError::Work {
                    t,
                    steps,
                    per_step: self.cost.per_step(),
                    duration: self.scene.duration,
                };
            }
            return RunError::Ode(e);
        };
        if let Some(f) = self.system.rhs_fault(t0, y)
            && f.cause.is_domain()
        {
            return self.domain(t0, Some(f));
        }
        let n = y.len();
        let mut f = vec![0.0; n];
        self.system.rhs(t0, y, &mut f);
        if f.iter().any(|v| !v.is_finite()) {
            return RunError::Ode(e);
        }
        // Along the tangent, from the resolution of t up to a millionth of
        // the run: the solver gave up because every step into that stretch
        // failed.
        let reach = 1e-6 * t0.abs().max(self.scene.duration);
        let mut h = (f64::EPSILON * t0.abs()).max(f64::MIN_POSITIVE);
        let mut yp = vec![0.0; n];
        while h <= reach {
            for i in 0..n {
                yp[i] = y[i] + h * f[i];
            }
            if yp.iter().any(|v| !v.is_finite()) {
                break;
            }
            let tp = t0 + h;
            if let Some(fault) = self.system.rhs_fault(tp, &yp) {
                if fault.cause.is_domain() {
                    return self.domain(tp, Some(fault));
                }
                break;
            }
            if let Some(fault) = self.system.equations().divisor_crossing(t0, y, tp, &yp) {
                return self.domain(tp, Some(fault));
            }
            h *= 2.0;
        }
        match e {
            SolveError::StepSize { t, h } => self.inaccurate(t, h, None),
            _ => self.unchecked_growth(t, y),
        }
    }

    /// Refuses a sample where a variable that sat below its absolute
    /// tolerance (after having a size: its error then went unchecked) has
    /// since grown past a million times that tolerance and past [`RISE`]
    /// times the largest size it had before, with the other sign than it
    /// had before it fell: that growth is the unchecked error's, not the
    /// equations'. Robertson to t = 1e11 at rtol 1e-3 lets
    /// y1 (size 1) fall below a tolerance of 1e-5 near t = 1e8, go negative
    /// and run
    /// away linearly to −4.5e7 with no blow-up for the solver to see (with
    /// the tolerance the default gave then; the default now follows y1
    /// down). A variable that falls and rises again to no more than [`RISE`]
    /// times what it was (a population's trough) is left alone; so is one
    /// that starts at 0, and one that rises with the sign it had: the
    /// Oregonator's y2 falls to 0.003 between its spikes and its first
    /// spike reaches 1,500 (auto at rtol 1e-3 with `atol` 1e-3 computed it
    /// below the tolerance there and had the spike refused).
    fn unchecked_rise(&mut self, t: f64, y: &[f64]) -> Result<(), RunError> {
        let Some(atol) = self.solver.atol() else {
            return Ok(());
        };
        // Only a size well above rounding arms the check: a variable that
        // rises from 0 wobbles at the noise floor first (E5's y4 near 1e-17
        // before its rise to 1e-11), which is no size it had: 1e-8 of the
        // largest size any variable reached.
        let top = self.largest.iter().fold(0.0f64, |m, v| m.max(*v));
        let real = 1e-8 * top;
        let mut rose = None;
        for (k, &v) in y.iter().enumerate() {
            let (Some(&a), Some(largest)) = (atol.get(k), self.largest.get_mut(k)) else {
                continue;
            };
            if !v.is_finite() {
                continue;
            }
            let size = v.abs();
            match self.dipped[k] {
                None if size < a && *largest > TRACKED * a && *largest >= real => {
                    self.dipped[k] = Some((*largest, a));
                }
                Some((before, a0))
                    if size > 1e6 * a0
                        && size > RISE * before
                        && v.signum() != self.sign[k]
                        && rose.is_none() =>
                {
                    rose = Some((k, v));
                }
                _ => {}
            }
            if self.dipped[k].is_none() && size >= a {
                self.sign[k] = v.signum();
            }
            *largest = largest.max(size);
        }
        let Some((k, v)) = rose else {
            return Ok(());
        };
        let name = self.scene.variables[k].clone();
        let mut e = self.inaccurate(t, f64::NAN, Some((name.clone(), v)));
        // The variable that ran away is named with its cure, by the size it
        // had before it went unchecked (its median may be the runaway's own).
        if let RunError::Inaccurate { uncontrolled, .. } = &mut e
            && let Some((before, a0)) = self.dipped[k]
            && !uncontrolled.iter().any(|(n, _, _)| *n == name)
        {
            uncontrolled.push((name, before, a0));
            let order = |n: &String| self.scene.variables.iter().position(|v| v == n);
            uncontrolled.sort_by_key(|(n, _, _)| order(n));
        }
        Err(e)
    }

    /// A blow-up led by a variable that sat below its absolute tolerance
    /// (so its error went unchecked) and has grown past a million times
    /// that tolerance is not called one: E5 at the default tolerance lets
    /// y2…y4 (~1e-11 under an atol of 1e-5) wander below zero, where the
    /// equations do run away. Any other blow-up stays one.
    fn unchecked_growth(&self, t: f64, y: &[f64]) -> RunError {
        let RunError::Inaccurate { uncontrolled, .. } = self.inaccurate(t, f64::NAN, None) else {
            return RunError::Ode(SolveError::BlowUp { t });
        };
        let led = (uncontrolled.iter())
            // A size of 0 is a variable sampled only at its start (or never
            // off zero): no evidence that it ever sat below its tolerance.
            .filter(|(_, size, _)| *size > 0.0)
            .filter_map(|(name, _, atol)| {
                let k = self.scene.variables.iter().position(|v| v == name)?;
                let v = *y.get(k)?;
                (v.is_finite() && v.abs() > 1e6 * atol).then(|| (name.clone(), v))
            })
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
        match led {
            Some(grew) => self.inaccurate(t, f64::NAN, Some(grew)),
            None => RunError::Ode(SolveError::BlowUp { t }),
        }
    }

    /// The step size collapsed while the solution stayed bounded: which
    /// variables the absolute tolerance does not control (their largest
    /// size over the run below it), with an `atol` that would.
    fn inaccurate(&self, t: f64, h: f64, grew: Option<(String, f64)>) -> RunError {
        let typical = |kept: &Vec<(f64, f64)>| {
            let mut v = kept.clone();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            let total: f64 = v.iter().map(|p| p.1).sum();
            if total <= 0.0 {
                // No stretch of the run sampled yet: nothing is known of
                // the variable's size, so it is not called uncontrolled.
                return None;
            }
            let mut acc = 0.0;
            for (size, w) in &v {
                acc += w;
                if acc >= 0.5 * total {
                    return Some(*size);
                }
            }
            v.last().map(|p| p.0)
        };
        // The tolerances the solver holds now (they follow the sizes).
        let atol = self.solver.atol().unwrap_or(&[]);
        let uncontrolled: Vec<(String, f64, f64)> = (self.sizes.iter().zip(atol).enumerate())
            .filter_map(|(k, (kept, a))| Some((k, typical(kept)?, *a)))
            .filter(|(_, size, a)| size < a)
            .map(|(k, size, a)| (self.scene.variables[k].clone(), size, a))
            .collect();
        // The variables typically below the default's floor (from the
        // largest size sampled), or held at it (a run stopped before its
        // first sample past the start has no typical size), unless the
        // scene gives them a tolerance.
        let top = self.largest.iter().fold(0.0f64, |m, v| m.max(*v));
        let floor = crate::solvers::ode::BySize::NOISE * top;
        let declared = |name: &String| match &self.scene.atol {
            None => false,
            Some(SceneAtol::All(_)) => true,
            Some(SceneAtol::Each(each)) => each.iter().any(|(n, _)| n == name),
        };
        let at_floor = (uncontrolled.iter())
            .filter(|(name, size, a)| {
                let below = (*size > 0.0 && *size < floor) || *a <= 2.0 * floor;
                floor > 0.0 && below && !declared(name)
            })
            .map(|(name, _, _)| name.clone())
            .collect();
        RunError::Inaccurate {
            t,
            h,
            uncontrolled,
            rtol: self.method.setting,
            radau: self.method.kind == OdeKind::Radau,
            grew,
            at_floor,
        }
    }

    /// Samples every step up to `target`, then sets the frame there.
    pub fn advance_to(&mut self, target: f64) {
        self.advance_within(target, Slice::WHOLE);
    }

    /// As [`SystemRun::advance_to`], stopping at the first step boundary
    /// after `slice` ends (at least one step is taken); the next call goes
    /// on from there. Returns whether the run reached `target` (or
    /// stopped for good).
    pub fn advance_within(&mut self, target: f64, slice: Slice) -> bool {
        if self.error.is_some() {
            return true;
        }
        let target = target.min(self.scene.duration);
        if target <= self.t {
            return true;
        }
        let per_step = if self.method.kind.fixed_step() {
            1
        } else {
            POINTS_PER_STEP
        };
        let mut stepped = false;
        loop {
            // The samples of the last step, up to the target: a step may
            // reach past it, and what lies beyond is checked when the run
            // gets there.
            if let Some((t0, end)) = self.span {
                let mut y = std::mem::take(&mut self.scratch);
                for k in 1..=per_step {
                    let t = if k == per_step {
                        end
                    } else {
                        t0 + (end - t0) * k as f64 / per_step as f64
                    };
                    if t <= self.sampled {
                        continue;
                    }
                    if t > target {
                        break;
                    }
                    if let Err(e) = self.solver.dense(t, &mut y) {
                        self.scratch = y;
                        self.stop(self.solver_error(e));
                        return true;
                    }
                    let at = InStep { k, per_step, t0 };
                    if let Err(e) = self.sample(t, &y, Some(at)) {
                        let e = match e {
                            RunError::Domain { .. } => {
                                let (tb, yb) = self.first_bad(t);
                                self.compute(tb, &yb).err().unwrap_or(e)
                            }
                            e => e,
                        };
                        self.scratch = y;
                        self.stop(e);
                        return true;
                    }
                    self.locate(at);
                    self.locate_events();
                }
                self.scratch = y;
            }
            if self.solver.t() >= target {
                break;
            }
            if stepped && slice.over() {
                // Shown where the samples reached (the last step's end);
                // the rest next time.
                self.t = self.sampled;
                self.state = self.good.clone();
                self.follow_reference(slice);
                return false;
            }
            match self.solver.step() {
                Ok((t0, t1)) => {
                    self.span = Some((t0, t1.min(self.scene.duration)));
                    if let Some(e) = self.fixed_step_left_the_domain(t0, t1) {
                        self.stop(e);
                        return true;
                    }
                }
                Err(e) => {
                    self.stop(self.solver_error(e));
                    return true;
                }
            }
            stepped = true;
        }
        let mut y = vec![0.0; self.state.len()];
        match self.solver.dense(target, &mut y) {
            Ok(()) => {
                self.state = y;
                self.t = target;
            }
            Err(e) => {
                let e = self.solver_error(e);
                self.stop(e);
                return true;
            }
        }
        self.follow_reference(slice);
        true
    }

    /// Searches the dense output of the current step for the extremes the
    /// samples so far point at ([`Tally::brackets`]).
    fn locate(&mut self, at: InStep) {
        let step_end = at.k == at.per_step;
        for i in 0..self.tallies.len() {
            let q = self.tallies[i].0;
            let measured = self.tallies[i].1.measured;
            if !self.tallies[i].1.searched || self.tallies[i].1.quiet() {
                continue;
            }
            let brackets = self.tallies[i].1.brackets(at.t0, step_end);
            if brackets.is_empty() {
                continue;
            }
            // A panel's extent to what the panel shows; a measure's extreme
            // to the full resolution.
            let within = match self.tallies[i].1.extent() {
                Some((lo, hi)) if !measured && hi - lo > 0.0 && (hi - lo).is_finite() => {
                    (hi - lo) / EXTENT_RESOLUTION
                }
                _ => 0.0,
            };
            for br in brackets {
                let s = if br.max { 1.0 } else { -1.0 };
                if !measured && self.at_its_edge(q, br) {
                    continue;
                }
                if let Some((t, v)) = brent_max_within(br.a, br.b, within, |t| {
                    self.quantity_at(q, t).map(|v| s * v)
                }) {
                    self.tallies[i].1.found(br, t, s * v);
                }
            }
        }
    }

    /// An extent (not a measure) needs no search of a bracket at a step's
    /// edge where the quantity moves away from the edge's sample: rising
    /// into the step's end as steadily as before (by the samples), or by
    /// the dense output just inside the edge. Its extreme there is that
    /// sample, already counted (two turns within one sample interval are
    /// beyond what a drawing resolves); a quantity that keeps rising over
    /// the run would otherwise be searched at every step.
    fn at_its_edge(&mut self, q: usize, br: Bracket) -> bool {
        let (edge, toward) = match br.edge {
            Edge::Inside => return false,
            _ if br.steady => return true,
            Edge::Start => (br.a, br.b),
            Edge::End => (br.b, br.a),
        };
        let near = edge + (toward - edge) * 2f64.powi(-20);
        let s = if br.max { 1.0 } else { -1.0 };
        self.quantity_at(q, near)
            .is_some_and(|n| s * n < s * br.at_edge)
    }

    /// Locates on the current step's dense output the first time a
    /// watched relation held, between the last two samples.
    fn locate_events(&mut self) {
        for k in 0..self.watches.len() {
            if self.watches[k].pending.is_none() {
                continue;
            }
            let q = self.watches[k].q;
            let mut w = self.watches[k].clone();
            w.locate(|t| self.quantity_at(q, t));
            self.watches[k] = w;
        }
    }

    /// Quantity `q` at time `t` of the current step, from the dense output
    /// (None if it cannot be evaluated or is not finite).
    fn quantity_at(&mut self, q: usize, t: f64) -> Option<f64> {
        self.probes.searches += 1;
        let mut y = std::mem::take(&mut self.probe);
        let n = y.len();
        let marks = n + self.probe_obs.len();
        let v = if self.solver.dense(t, &mut y).is_err() {
            None
        } else if q < n {
            Some(y[q])
        } else if q >= marks {
            Some(self.system.mark(q - marks, t, &y))
        } else {
            self.system
                .observables_upto(q - n, t, &y, &mut self.probe_obs);
            Some(self.probe_obs[q - n])
        };
        self.probe = y;
        v.filter(|v| v.is_finite())
    }

    /// Ends the run with `e`, the frame at the last good sample.
    fn stop(&mut self, e: RunError) {
        self.t = self.sampled;
        self.state = self.good.clone();
        self.error = Some(e);
    }

    /// Brings the reference run up to the frame time (within the slice)
    /// and compares the states there.
    fn follow_reference(&mut self, slice: Slice) {
        let Some(r) = &mut self.reference else {
            return;
        };
        while r.t() < self.t {
            if slice.over() {
                return;
            }
            if r.step().is_err() {
                self.reference = None;
                return;
            }
        }
        let mut yr = vec![0.0; self.state.len()];
        if r.dense(self.t, &mut yr).is_err() {
            self.reference = None;
            return;
        }
        let scale = yr.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        let err = yr
            .iter()
            .zip(&self.state)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale;
        self.ref_error = self.ref_error.max(err);
    }

    /// Runs to the end (or the first error).
    pub fn run_to_end(&mut self) -> Result<(), RunError> {
        self.advance_to(self.scene.duration);
        match &self.error {
            Some(e) => Err(e.clone()),
            None => Ok(()),
        }
    }

    pub fn scene(&self) -> &SystemScene {
        &self.scene
    }
    pub fn plan(&self) -> &SystemPlan {
        &self.plan
    }
    pub fn method(&self) -> OdeMethod {
        self.method
    }
    pub fn t(&self) -> f64 {
        self.t
    }
    pub fn state(&self) -> &[f64] {
        &self.state
    }
    pub fn finished(&self) -> bool {
        self.error.is_some() || self.t >= self.scene.duration
    }
    pub fn error(&self) -> Option<&RunError> {
        self.error.as_ref()
    }
    /// The last step the solver took, [t0, t1].
    pub fn last_step(&self) -> Option<(f64, f64)> {
        self.span
    }
    /// What a step of this scene costs.
    pub fn cost(&self) -> Cost {
        self.cost
    }
    #[cfg(test)]
    pub(crate) fn has_reference(&self) -> bool {
        self.reference.is_some()
    }
    /// The plotted quantities, then the phase pair, over the run so far.
    pub fn trace(&self) -> &[Point] {
        &self.trace.points
    }
    /// The sketch's coordinates over the run so far, as its trails are
    /// drawn: through the samples, and between two of them along the dense
    /// output where the chord would stray from the curve by more than the
    /// sketch's extent over [`trail::RESOLUTION`]; thinned where straight
    /// (empty when the plan keeps no trail).
    pub fn trail(&self) -> &[Point] {
        self.trail.as_ref().map_or(&[], Trail::points)
    }

    /// How often the run evaluated its dense output between samples.
    pub fn probes(&self) -> Probes {
        self.probes
    }

    /// The smallest and largest value of quantity `q` over the run so far,
    /// when the plan follows its extent: every sample's, and the extremes
    /// between samples located on the dense output.
    fn extent(&self, q: usize) -> Option<(f64, f64)> {
        if !self.plan.extents.contains(&q) {
            return None;
        }
        let (_, tally) = self.tallies.iter().find(|(k, _)| *k == q)?;
        tally.extent()
    }

    /// The extent over the run so far of the plotted quantities together
    /// (None when the plot is not shown).
    pub fn plot_extent(&self) -> Option<(f64, f64)> {
        join(self.plot.iter().filter_map(|&q| self.extent(q)))
    }

    /// The extent over the run so far of each of the phase pair.
    pub fn phase_extent(&self) -> Option<[(f64, f64); 2]> {
        let [a, b] = self.phase?;
        Some([self.extent(a)?, self.extent(b)?])
    }

    /// The extent over the run so far of the sketch's x coordinates (the
    /// first of each pair, every mark's) and of its y coordinates; the
    /// frame's own coordinates ([`SystemRun::marks_now`]) are not in it.
    pub fn sketch_extent(&self) -> Option<[(f64, f64); 2]> {
        let marks = self.state.len() + self.obs.len();
        let axis = |parity: usize| {
            join(
                (0..self.marks.len())
                    .filter(|j| j % 2 == parity)
                    .filter_map(|j| self.extent(marks + j)),
            )
        };
        Some([axis(0)?, axis(1)?])
    }
    /// How many plotted quantities lead each trace point.
    pub fn plot_count(&self) -> usize {
        self.plot.len()
    }
    /// The sketch's coordinates at the frame.
    pub fn marks_now(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.system.mark_count()];
        self.system.marks_into(self.t, &self.state, &mut out);
        out
    }
    pub fn work(&self) -> Work {
        self.solver.work()
    }

    pub fn diagnostics(&self) -> SystemDiagnostics {
        let drift = self
            .scene
            .conserved
            .iter()
            .filter_map(|c| {
                let q = self.quantity(c)?;
                let (_, tally) = self.tallies.iter().find(|(k, _)| *k == q)?;
                Some((c.clone(), tally.stat(Stat::Drift, c).ok()?))
            })
            .collect();
        SystemDiagnostics {
            solver: self.solver.name(),
            work: self.solver.work(),
            stiff_at: self.solver.stiffness(),
            drift,
            error: self.reference.as_ref().map(|_| self.ref_error),
        }
    }

    /// How far each quantity the scene declares conserved has moved so
    /// far (those this run computes), in the scene's order of `conserved`.
    pub fn conserved_drift(&self) -> Vec<ConservedDrift> {
        let n = self.scene.variables.len();
        let name = |q: usize| match q < n {
            true => self.scene.variables[q].clone(),
            false => self.scene.observables[q - n].0.clone(),
        };
        self.drift
            .iter()
            .map(|&(q, start, change)| ConservedDrift {
                name: name(q),
                start,
                change,
                relative: (start.abs() >= tally::TINY).then(|| change / start.abs()),
            })
            .collect()
    }

    /// One measure of the run so far, or why it cannot be made.
    pub fn measure(&self, m: Measure) -> Result<f64, ReadingError> {
        let Measure::Of(stat, name) = m else {
            return Err(ReadingError::Rigid(m));
        };
        let q = self
            .quantity(name.as_str())
            .ok_or_else(|| ReadingError::Unknown {
                name: name.as_str().to_string(),
                scene: self.scene.id.clone(),
            })?;
        if stat.event().is_some() {
            let w = self
                .watches
                .iter()
                .find(|w| w.q == q && w.stat == stat)
                .ok_or(ReadingError::NotPlanned(m))?;
            return w.value(m);
        }
        let (_, tally) = self
            .tallies
            .iter()
            .find(|(k, _)| *k == q && self.plan.metered.contains(k))
            .ok_or(ReadingError::NotPlanned(m))?;
        let v = tally.stat(stat, name.as_str())?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(ReadingError::NotFinite(m))
        }
    }

    /// What a reader of measure `m` should know about its value: `period`
    /// on a quantity whose upward crossings are not evenly spaced (not
    /// periodic at one frequency: two close frequencies beat, or a peak
    /// grazes the mid level).
    pub fn caveat(&self, m: Measure) -> Option<String> {
        let Measure::Of(Stat::Period, name) = m else {
            return None;
        };
        let q = self.quantity(name.as_str())?;
        let (_, tally) = self.tallies.iter().find(|(k, _)| *k == q)?;
        let (lo, hi, _) = tally.period_spread()?;
        Some(format!(
            "{m}: the upward crossings of its mid level are not evenly spaced (from {} to {} {} apart): {name} is not periodic at one frequency; for the period of its envelope (a beat) measure beat({name})",
            flipcard_text::num::sig(lo, 3),
            flipcard_text::num::sig(hi, 3),
            self.scene.time_unit
        ))
    }

    /// The readings of `measures` the run could make.
    pub fn measurements(&self, measures: &[Measure]) -> Measurements {
        let readings = measures
            .iter()
            .filter_map(|&m| {
                self.measure(m).ok().map(|value| Reading {
                    measure: m,
                    value,
                    formula: None,
                })
            })
            .collect();
        Measurements::from_readings(readings).over(self.t())
    }
}

/// Runs a scene to its end for `measures`; each value, or why it cannot be
/// made. A failed run is an error for all.
pub fn measure_system(
    scene: &SystemScene,
    method: OdeMethod,
    measures: &[Measure],
) -> Result<Vec<Result<f64, ReadingError>>, StartError> {
    Ok(measure_system_noting(scene, method, measures)?
        .into_iter()
        .map(|(value, _)| value)
        .collect())
}

/// A measure's value (or why there is none) and its caveat.
pub type Noted = (Result<f64, ReadingError>, Option<String>);

/// As [`measure_system`], with each measure's caveat ([`SystemRun::caveat`]).
pub fn measure_system_noting(
    scene: &SystemScene,
    method: OdeMethod,
    measures: &[Measure],
) -> Result<Vec<Noted>, StartError> {
    let plan = SystemPlan::for_scene(scene, method, measures).headless();
    let mut run = SystemRun::with_plan(scene, method, plan)?;
    run.run_to_end()?;
    let mut noted: Vec<Noted> = measures
        .iter()
        .map(|&m| (run.measure(m), run.caveat(m)))
        .collect();
    // A crossing or an event the run never shows may be the run's fault
    // (a pendulum released at 179.9° that a loose tolerance tips over the
    // top never swings back): the same scene, a hundred, ten thousand and
    // a million times finer (as far as the setting goes), says whether the
    // measure exists, and how fine a run must be to show it (from rtol
    // 1e-2 that pendulum needs 1e-8: two tries stopped at 1e-6 and called
    // the period missing).
    let missing: Vec<usize> = (noted.iter().enumerate())
        .filter(|(_, (v, _))| matches!(v, Err(e) if e.may_be_too_coarse()))
        .map(|(k, _)| k)
        .collect();
    let mut finer = method;
    for _ in 0..3 {
        if missing.iter().all(|&k| noted[k].0.is_ok()) {
            break;
        }
        let next = finer.finer(true).finer(true);
        if next == finer {
            break;
        }
        // Two tenfold steps leave 1.0000000000000002e-7: the setting
        // rounded to three digits, as a person would write it.
        let next = OdeMethod {
            setting: format!("{:.2e}", next.setting)
                .parse()
                .unwrap_or(next.setting),
            ..next
        };
        finer = next;
        let plan = SystemPlan::for_scene(scene, finer, measures).headless();
        let Ok(mut run) = SystemRun::with_plan(scene, finer, plan) else {
            break;
        };
        if run.run_to_end().is_err() {
            break;
        }
        for &k in &missing {
            if let (Err(e), Ok(value)) = (&noted[k].0, run.measure(measures[k])) {
                // The reason without the measure's name it starts with.
                let measure = measures[k].to_string();
                let text = e.to_string();
                let why = text
                    .strip_prefix(&format!("{measure}: "))
                    .unwrap_or(&text)
                    .to_string();
                noted[k].0 = Err(ReadingError::TooCoarse {
                    measure,
                    why,
                    method: method.label(),
                    finer: finer.label(),
                    value,
                });
            }
        }
    }
    Ok(noted)
}

/// The smallest and largest of `extents` together.
fn join(extents: impl Iterator<Item = (f64, f64)>) -> Option<(f64, f64)> {
    extents.reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

mod tally;
#[cfg(test)]
mod tests;
pub mod trail;
