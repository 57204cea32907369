//! The one vocabulary of solver methods: every name the command line
//! (`--method`), the screens and the CSV files use, its help, and which
//! scenes take it (a rigid body, a system of a deck, or both), in one table.
//! The rigid body's families ([`Kind`]), the systems' ([`OdeKind`]) and the
//! app's `--method` argument are views of it: their names, help and the
//! refusal of a method a scene does not take all come from here. Adding a
//! method is one row here, plus its solver.

use crate::rigid::solver::Kind;
use crate::solvers::ode::OdeKind;

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
}

/// One row of the vocabulary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MethodRow {
    pub method: MethodName,
    /// The spelling on the command line, on screen and in the CSV files.
    pub name: &'static str,
    /// What `--help` says of it (none: the name says it all).
    pub help: Option<&'static str>,
    /// The rigid-body family it names, if a rigid body takes it.
    pub rigid: Option<Kind>,
    /// The system family it names, if a system takes it.
    pub system: Option<OdeKind>,
}

/// The table.
pub const METHODS: [MethodRow; 7] = [
    MethodRow {
        method: MethodName::Exact,
        name: "exact",
        help: None,
        rigid: Some(Kind::Exact),
        system: None,
    },
    MethodRow {
        method: MethodName::Adaptive,
        name: "adaptive",
        help: None,
        rigid: Some(Kind::Adaptive),
        system: Some(OdeKind::Adaptive),
    },
    MethodRow {
        method: MethodName::Splitting,
        name: "splitting",
        help: None,
        rigid: Some(Kind::Splitting),
        system: None,
    },
    MethodRow {
        method: MethodName::Splitting4,
        name: "splitting4",
        help: None,
        rigid: Some(Kind::Splitting4),
        system: None,
    },
    MethodRow {
        method: MethodName::Rk4,
        name: "rk4",
        help: None,
        rigid: Some(Kind::Rk4),
        system: Some(OdeKind::Rk4),
    },
    MethodRow {
        method: MethodName::Auto,
        name: "auto",
        help: Some("Systems only: explicit until stiff, then Radau IIA"),
        rigid: None,
        system: Some(OdeKind::Auto),
    },
    MethodRow {
        method: MethodName::Radau,
        name: "radau",
        help: Some("Systems only: Radau IIA of order 5"),
        rigid: None,
        system: Some(OdeKind::Radau),
    },
];

impl MethodName {
    /// Every method, in the table's order.
    pub const ALL: [MethodName; 7] = [
        MethodName::Exact,
        MethodName::Adaptive,
        MethodName::Splitting,
        MethodName::Splitting4,
        MethodName::Rk4,
        MethodName::Auto,
        MethodName::Radau,
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

    /// The rigid-body family, or what a rigid body takes instead.
    pub fn rigid(self) -> Result<Kind, String> {
        self.row().rigid.ok_or_else(|| {
            let names = Kind::ALL.map(|k| k.name());
            format!(
                "only system scenes use it; a rigid body takes {}",
                spoken(&names)
            )
        })
    }

    /// The system family, or what a system takes instead.
    pub fn system(self) -> Result<OdeKind, String> {
        self.row().system.ok_or_else(|| {
            let names = OdeKind::ALL.map(|k| k.name());
            format!("a system takes {}", spoken(&names))
        })
    }
}

impl From<Kind> for MethodName {
    fn from(kind: Kind) -> MethodName {
        named(|r| r.rigid == Some(kind))
    }
}

impl From<OdeKind> for MethodName {
    fn from(kind: OdeKind) -> MethodName {
        named(|r| r.system == Some(kind))
    }
}

/// The method of the row that names a family (every family has one: the
/// tests check it).
fn named(names_it: impl Fn(&MethodRow) -> bool) -> MethodName {
    METHODS
        .iter()
        .find(|r| names_it(r))
        .map_or(MethodName::Exact, |r| r.method)
}

/// Names as a sentence says them: `a, b or c`.
fn spoken(names: &[&str]) -> String {
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
    fn every_family_has_one_row_and_the_views_use_it() {
        for kind in Kind::ALL {
            assert_eq!(MethodName::from(kind).rigid(), Ok(kind));
            assert_eq!(kind.name(), MethodName::from(kind).name());
        }
        for kind in OdeKind::ALL {
            assert_eq!(MethodName::from(kind).system(), Ok(kind));
            assert_eq!(kind.name(), MethodName::from(kind).name());
        }
    }

    #[test]
    fn a_scene_that_does_not_take_a_method_says_what_it_takes() {
        assert_eq!(
            MethodName::Radau.rigid(),
            Err(
                "only system scenes use it; a rigid body takes exact, adaptive, splitting, splitting4 or rk4"
                    .into()
            )
        );
        assert_eq!(
            MethodName::Splitting.system(),
            Err("a system takes auto, adaptive, radau or rk4".into())
        );
    }
}
