//! The one vocabulary of solver methods: every name the command line
//! (`--method`), the screens and the CSV files use, its help, and which
//! scenes take it (a rigid body, a system of a deck, or both), in one table.
//! The rigid body's families (`rigid::solver::Kind`), the systems'
//! (`solvers::ode::OdeKind`) and the app's `--method` argument are views of
//! it: their names, help and the refusal of a method a scene does not take
//! all come from here. It sits below both stacks and uses neither. Adding a
//! method is one row here, plus its solver.

/// Every method a run can name, in the order `--help` lists them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MethodName {
    Exact,
    Adaptive,
    Splitting,
    Splitting4,
    Rk4,
    Auto,
    Radau,
    Verlet,
    Verlet4,
}

/// One row of the vocabulary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MethodRow {
    pub method: MethodName,
    /// The spelling on the command line, on screen and in the CSV files.
    pub name: &'static str,
    /// What `--help` says of it (none: the name says it all).
    pub help: Option<&'static str>,
    /// Whether a rigid body takes it.
    pub rigid: bool,
    /// Whether a system of a deck takes it.
    pub system: bool,
}

/// The table.
pub(crate) const METHODS: [MethodRow; 9] = [
    MethodRow {
        method: MethodName::Exact,
        name: "exact",
        help: None,
        rigid: true,
        system: false,
    },
    MethodRow {
        method: MethodName::Adaptive,
        name: "adaptive",
        help: None,
        rigid: true,
        system: true,
    },
    MethodRow {
        method: MethodName::Splitting,
        name: "splitting",
        help: None,
        rigid: true,
        system: false,
    },
    MethodRow {
        method: MethodName::Splitting4,
        name: "splitting4",
        help: None,
        rigid: true,
        system: false,
    },
    MethodRow {
        method: MethodName::Rk4,
        name: "rk4",
        help: None,
        rigid: true,
        system: true,
    },
    MethodRow {
        method: MethodName::Auto,
        name: "auto",
        help: Some("Systems only: explicit until stiff, then Radau IIA"),
        rigid: false,
        system: true,
    },
    MethodRow {
        method: MethodName::Radau,
        name: "radau",
        help: Some("Systems only: Radau IIA of order 5"),
        rigid: false,
        system: true,
    },
    MethodRow {
        method: MethodName::Verlet,
        name: "verlet",
        help: Some(
            "Systems declaring a separable `hamiltonian` only: Störmer–Verlet, symplectic, fixed step (--dt)",
        ),
        rigid: false,
        system: true,
    },
    MethodRow {
        method: MethodName::Verlet4,
        name: "verlet4",
        help: Some("As verlet, of order 4 (Yoshida's triple jump)"),
        rigid: false,
        system: true,
    },
];

impl MethodName {
    /// Every method, in the table's order.
    pub const ALL: [MethodName; 9] = [
        MethodName::Exact,
        MethodName::Adaptive,
        MethodName::Splitting,
        MethodName::Splitting4,
        MethodName::Rk4,
        MethodName::Auto,
        MethodName::Radau,
        MethodName::Verlet,
        MethodName::Verlet4,
    ];

    pub fn row(self) -> &'static MethodRow {
        &METHODS[self as usize]
    }

    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// The method spelled `s` exactly (the command line's spelling).
    pub fn parse(s: &str) -> Option<MethodName> {
        METHODS.iter().find(|r| r.name == s).map(|r| r.method)
    }
}

/// Why a scene refuses a method, or a method its setting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MethodError {
    /// A rigid body refuses a method for systems only.
    #[error("only system scenes use it; a rigid body takes {}", spoken(&rigid_names()))]
    NotRigid(MethodName),
    /// A system refuses a method; `takes` lists what it takes instead.
    #[error("a system takes {}", spoken(takes))]
    NotSystem {
        method: MethodName,
        takes: Vec<&'static str>,
    },
    /// A fixed step (RK4's, Verlet's) is not positive and finite.
    #[error("the step (--dt) must be positive and finite, not {0}")]
    Step(f64),
    /// An adaptive method's tolerance is outside (1e-14, 1).
    #[error("the tolerance of {} must lie between 1e-14 and 1, not {setting}", method.name())]
    Tolerance { method: MethodName, setting: f64 },
}

/// The methods a rigid body takes, in the table's order.
fn rigid_names() -> Vec<&'static str> {
    METHODS.iter().filter(|r| r.rigid).map(|r| r.name).collect()
}

/// Names as a sentence says them: `a, b or c`.
pub(crate) fn spoken(names: &[&str]) -> String {
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_in_the_order_of_the_names() {
        for (i, m) in MethodName::ALL.iter().enumerate() {
            assert_eq!(METHODS[i].method, *m);
            assert_eq!(MethodName::parse(m.name()), Some(*m));
        }
        assert_eq!(MethodName::parse("Exact"), None);
    }

    #[test]
    fn a_rigid_body_says_what_it_takes() {
        assert_eq!(
            MethodError::NotRigid(MethodName::Radau).to_string(),
            "only system scenes use it; a rigid body takes exact, adaptive, splitting, splitting4 or rk4"
        );
        assert_eq!(spoken(&["a"]), "a");
    }
}
