//! A system scene as the simulator runs it: its equations, constants,
//! observables and start as written, and what it shows. Decks validate
//! their TOML into it; it is here, below the scenes' runs
//! ([`crate::scene`]), because compiling it is this folder's work.

use flipcard_text::Text;

/// A panel of a system scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SystemPanel {
    /// The `plot` quantities against time.
    Plot,
    /// The `phase` pair, one against the other.
    Phase,
    /// Lines, dots and trails drawn from expressions.
    Sketch,
    /// Method, steps, the stiffness switch, drift of the conserved
    /// observables and the error against a reference run.
    Diagnostics,
}

impl SystemPanel {
    pub const ALL: [SystemPanel; 4] = [
        SystemPanel::Plot,
        SystemPanel::Phase,
        SystemPanel::Sketch,
        SystemPanel::Diagnostics,
    ];
    pub fn name(self) -> &'static str {
        match self {
            SystemPanel::Plot => "plot",
            SystemPanel::Phase => "phase",
            SystemPanel::Sketch => "sketch",
            SystemPanel::Diagnostics => "diagnostics",
        }
    }
    pub fn from_name(name: &str) -> Option<SystemPanel> {
        SystemPanel::ALL.into_iter().find(|p| p.name() == name)
    }
}

/// One element of a sketch; each coordinate is an expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Mark {
    /// A segment from (x1, y1) to (x2, y2).
    Line([String; 4]),
    /// A dot at (x, y), with an optional label drawn beside it.
    Dot([String; 2], Option<Text>),
    /// The path (x, y) has followed so far.
    Trail([String; 2]),
}

impl Mark {
    pub fn key(&self) -> &'static str {
        match self {
            Mark::Line(_) => "line",
            Mark::Dot(..) => "dot",
            Mark::Trail(_) => "trail",
        }
    }
    pub fn exprs(&self) -> &[String] {
        match self {
            Mark::Line(v) => v,
            Mark::Dot(v, _) | Mark::Trail(v) => v,
        }
    }
}

/// A system of ordinary differential equations declared by a deck:
/// d/dt of each variable is its equation, in terms of the variables, the
/// named constants `params`, time `t` and the observables.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemScene {
    pub id: String,
    pub title: Option<Text>,
    /// The state, in the author's order.
    pub variables: Vec<String>,
    pub initial: Vec<f64>,
    /// Named constants, in the author's order.
    pub params: Vec<(String, f64)>,
    /// d/dt of each variable, same order, as written.
    pub equations: Vec<String>,
    /// Named expressions, in the author's order; each may use the ones
    /// before it.
    pub observables: Vec<(String, String)>,
    /// Observables whose drift the diagnostics report.
    pub conserved: Vec<String>,
    pub duration: f64,
    pub show: Vec<SystemPanel>,
    /// Variables or observables plotted against time.
    pub plot: Vec<String>,
    /// The pair drawn in the phase portrait.
    pub phase: Option<[String; 2]>,
    pub sketch: Vec<Mark>,
    pub time_unit: String,
    /// The absolute tolerance the scene declares (`atol`), if any.
    pub atol: Option<SceneAtol>,
    /// The separable Hamiltonian the scene declares (`hamiltonian`), if
    /// any: what the symplectic methods need.
    pub hamiltonian: Option<Hamiltonian>,
    /// How the plots name some variables or observables (`labels`): the
    /// names the question uses (`xc` shown as `A`), in the author's order.
    pub labels: Vec<(String, String)>,
}

/// A separable Hamiltonian H = T(p) + V(q) as a scene declares it
/// (`hamiltonian = { q = ["x", "y"], p = ["vx", "vy"] }`): its positions and
/// momenta by variable name, each variable in one of them, as many of
/// each. The rate of each position must read only momenta, the rate of
/// each momentum only positions ([`crate::system::System::hamiltonian_error`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Hamiltonian {
    pub q: Vec<String>,
    pub p: Vec<String>,
}

/// A scene's absolute tolerance: one for every variable, or some
/// variables' own (the others keep the method's default).
#[derive(Debug, Clone, PartialEq)]
pub enum SceneAtol {
    All(f64),
    Each(Vec<(String, f64)>),
}

impl SceneAtol {
    /// The smallest absolute tolerance a scene or `--atol` may set (below
    /// it no error estimate means anything).
    pub const MIN: f64 = 1e-300;

    /// Whether `a` may be an absolute tolerance: finite and at least
    /// [`SceneAtol::MIN`] (the deck key and `--atol` alike).
    pub fn allowed(a: f64) -> bool {
        a.is_finite() && a >= SceneAtol::MIN
    }

    /// The tolerance of each variable of `scene`, those it does not name at
    /// `default`.
    pub fn per_variable(&self, variables: &[String], default: f64) -> Vec<f64> {
        match self {
            SceneAtol::All(a) => vec![*a; variables.len()],
            SceneAtol::Each(each) => variables
                .iter()
                .map(|v| {
                    each.iter()
                        .find(|(n, _)| n == v)
                        .map_or(default, |(_, a)| *a)
                })
                .collect(),
        }
    }
}

impl SystemScene {
    /// How the plots show `name`: its label when the scene gives one.
    pub fn label(&self, name: &str) -> Option<&str> {
        self.labels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, l)| l.as_str())
    }

    pub fn shows(&self, panel: SystemPanel) -> bool {
        self.show.contains(&panel)
    }

    /// A scene holding one formula and nothing to run: `variables` read from
    /// the state, `params` fixed numbers, the formula its one observable.
    pub(crate) fn one_formula(
        variables: Vec<String>,
        params: Vec<(String, f64)>,
        observable: (String, String),
    ) -> SystemScene {
        SystemScene {
            id: String::new(),
            title: None,
            variables,
            initial: Vec::new(),
            params,
            equations: Vec::new(),
            observables: vec![observable],
            conserved: Vec::new(),
            duration: 1.0,
            show: Vec::new(),
            plot: Vec::new(),
            phase: None,
            sketch: Vec::new(),
            time_unit: String::new(),
            atol: None,
            hamiltonian: None,
            labels: Vec::new(),
        }
    }
}
