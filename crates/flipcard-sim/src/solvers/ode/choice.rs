//! The methods a system scene can run with, as the learner and the command
//! line name them, with their one setting (a tolerance, or RK4's step).

use super::{Atol, BySize, Method, Options, StiffnessMode};
use crate::method::{MethodError, MethodName};

/// Default relative tolerance of the adaptive methods on a scene; the
/// absolute one of each variable is this times [`ATOL_FACTOR`] times the
/// variable's recent size ([`super::BySize`]).
pub(crate) const DEFAULT_RTOL: f64 = 1e-8;
pub(crate) const ATOL_FACTOR: f64 = 1e-2;
/// RK4's default step: this many steps over the run.
pub(crate) const DEFAULT_RK4_STEPS: f64 = 20_000.0;
/// The reference run of the diagnostics.
pub(crate) const REFERENCE_RTOL: f64 = 1e-11;

/// A method family for systems.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OdeKind {
    /// DOP853 until it finds the problem stiff, then Radau IIA.
    Auto,
    /// DOP853, refusing a stiff problem.
    Adaptive,
    /// Radau IIA of order 5.
    Radau,
    /// Classical RK4 with a fixed step.
    Rk4,
    /// Störmer–Verlet, symplectic, fixed step: a scene that declares a
    /// separable Hamiltonian only.
    Verlet,
    /// Its fourth-order triple jump (Yoshida).
    Verlet4,
}

impl OdeKind {
    pub const ALL: [OdeKind; 4] = [
        OdeKind::Auto,
        OdeKind::Adaptive,
        OdeKind::Radau,
        OdeKind::Rk4,
    ];

    /// The symplectic methods, which only a scene declaring a separable
    /// Hamiltonian takes (so not among [`OdeKind::ALL`], which every
    /// system takes).
    pub const SYMPLECTIC: [OdeKind; 2] = [OdeKind::Verlet, OdeKind::Verlet4];

    /// Whether the method steps by a fixed `dt` (its setting).
    pub fn fixed_step(self) -> bool {
        matches!(self, OdeKind::Rk4 | OdeKind::Verlet | OdeKind::Verlet4)
    }

    /// Whether the method holds the sums the equations keep fixed against
    /// rounding ([`super::fixed`]): the error-controlled ones, whose
    /// error weights say where a correction has room.
    pub fn holds_fixed_sums(self) -> bool {
        !self.fixed_step()
    }

    /// Its name in the one vocabulary ([`crate::method`]).
    pub fn method(self) -> MethodName {
        match self {
            OdeKind::Auto => MethodName::Auto,
            OdeKind::Adaptive => MethodName::Adaptive,
            OdeKind::Radau => MethodName::Radau,
            OdeKind::Rk4 => MethodName::Rk4,
            OdeKind::Verlet => MethodName::Verlet,
            OdeKind::Verlet4 => MethodName::Verlet4,
        }
    }

    /// The command line's spelling.
    pub fn name(self) -> &'static str {
        self.method().name()
    }

    /// The family a method names, or what a system takes instead.
    pub fn from_method(m: MethodName) -> Result<OdeKind, MethodError> {
        let kinds = OdeKind::ALL.into_iter().chain(OdeKind::SYMPLECTIC);
        kinds
            .clone()
            .find(|k| k.method() == m)
            .ok_or_else(|| MethodError::NotSystem {
                method: m,
                takes: kinds.map(OdeKind::name).collect(),
            })
    }

    /// Whether the method solves with the Jacobian (so it is compiled).
    pub(crate) fn implicit(self) -> bool {
        matches!(self, OdeKind::Radau | OdeKind::Auto)
    }
}

/// A method with its setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdeMethod {
    pub kind: OdeKind,
    /// Relative tolerance (adaptive kinds) or step (RK4).
    pub setting: f64,
}

impl OdeMethod {
    /// The kind with its default setting for a run of `duration`.
    pub fn default_for(kind: OdeKind, duration: f64) -> OdeMethod {
        let setting = match kind.fixed_step() {
            true => duration / DEFAULT_RK4_STEPS,
            false => DEFAULT_RTOL,
        };
        OdeMethod { kind, setting }
    }

    /// The kind with `tol` (a tolerance, or RK4's step), checked.
    pub fn with_setting(kind: OdeKind, setting: f64) -> Result<OdeMethod, MethodError> {
        let ok = match kind.fixed_step() {
            true => setting.is_finite() && setting > 0.0,
            false => setting.is_finite() && setting > 1e-14 && setting < 1.0,
        };
        if !ok {
            return Err(match kind {
                k if k.fixed_step() => MethodError::Step(setting),
                _ => MethodError::Tolerance {
                    method: kind.method(),
                    setting,
                },
            });
        }
        Ok(OdeMethod { kind, setting })
    }

    /// `radau rtol 1e-8`, `rk4 dt 0.001`.
    pub fn label(&self) -> String {
        let what = if self.kind.fixed_step() { "dt" } else { "rtol" };
        format!(
            "{} {what} {}",
            self.kind.name(),
            flipcard_text::num::show(self.setting)
        )
    }

    /// The tolerance tightened or loosened tenfold (the step halved or
    /// doubled for RK4), within the allowed range.
    pub fn finer(&self, finer: bool) -> OdeMethod {
        let setting = match (self.kind.fixed_step(), finer) {
            (true, true) => self.setting / 2.0,
            (true, false) => self.setting * 2.0,
            (_, true) => (self.setting / 10.0).max(1e-13),
            (_, false) => (self.setting * 10.0).min(1e-2),
        };
        OdeMethod { setting, ..*self }
    }

    /// The solver and its options for a run ending at `t_end`.
    pub fn solver(&self, t_end: f64) -> (Method, Options) {
        let mut opts = Options {
            rtol: self.setting,
            atol: Atol::BySize(BySize::new(self.setting * ATOL_FACTOR)),
            t_stop: Some(t_end),
            ..Options::default()
        };
        let method = match self.kind {
            OdeKind::Auto => Method::Auto,
            OdeKind::Adaptive => Method::Dop853 {
                stiffness: StiffnessMode::Refuse,
            },
            OdeKind::Radau => Method::Radau5,
            OdeKind::Rk4 => {
                opts = Options {
                    t_stop: Some(t_end),
                    ..Options::default()
                };
                Method::Rk4 { dt: self.setting }
            }
            OdeKind::Verlet | OdeKind::Verlet4 => {
                opts = Options {
                    t_stop: Some(t_end),
                    ..Options::default()
                };
                let order = if self.kind == OdeKind::Verlet4 { 4 } else { 2 };
                Method::Verlet {
                    dt: self.setting,
                    order,
                }
            }
        };
        (method, opts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::METHODS;

    /// The vocabulary's `system` column and the families agree.
    #[test]
    fn the_families_are_the_methods_a_system_takes() {
        for row in METHODS {
            assert_eq!(
                OdeKind::from_method(row.method).is_ok(),
                row.system,
                "{}",
                row.name
            );
        }
        assert_eq!(
            OdeKind::from_method(MethodName::Exact).map_err(|e| e.to_string()),
            Err("a system takes auto, adaptive, radau, rk4, verlet or verlet4".into())
        );
    }
}
