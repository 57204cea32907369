//! Step budgets: a stepping solver refuses, with a reason, a run that would
//! take longer than its budget instead of hanging on a stiff case.

use flipcard_text::num::Num;

/// Default cap on the steps (accepted and rejected) of one run: a few
/// seconds of work for the costliest method.
pub(crate) const DEFAULT_MAX_STEPS: u64 = 5_000_000;

/// How many steps one run may take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    pub max_steps: u64,
}

impl Default for Budget {
    fn default() -> Budget {
        Budget {
            max_steps: DEFAULT_MAX_STEPS,
        }
    }
}

impl Budget {
    /// True when `taken` steps so far plus `more` expected ones exceed the cap.
    pub(crate) fn exceeded(&self, taken: u64, more: f64) -> bool {
        taken as f64 + more > self.max_steps as f64
    }

    /// Why an adaptive run stops: the limiting rate, the steps it would take.
    pub fn stiff(&self, rate: &str, steps: f64) -> String {
        format!(
            "stiff: {rate} needs ~{steps:.0e} steps for this span (budget {:.0e}); use the exact solver",
            self.max_steps as f64
        )
    }

    /// Why a fixed-step run stops.
    pub fn fixed(&self, method: &str, dt: f64, t: f64, steps: f64) -> String {
        format!(
            "{method}: dt = {} needs ~{steps:.0e} steps to reach t = {} (budget {:.0e}); use a larger dt or the exact solver",
            Num(dt),
            Num(t),
            self.max_steps as f64
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_rate_steps_and_way_out() {
        let b = Budget::default();
        assert_eq!(
            b.stiff("nutation at 1.0e9 rad/s", 1.2e10),
            "stiff: nutation at 1.0e9 rad/s needs ~1e10 steps for this span (budget 5e6); use the exact solver"
        );
        assert!(b.exceeded(4_999_999, 2.0));
        assert!(!b.exceeded(4_999_999, 1.0));
    }
}
