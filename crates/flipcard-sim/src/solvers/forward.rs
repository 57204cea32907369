//! The one rule every stepping solver shares: a run's times only go
//! forward. A solver keeps its step sequence between calls, so a time
//! before the previous one cannot be served from it (and a NaN never can).

use crate::error::SolveError;
use flipcard_text::num::Num;

#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Forward {
    last: f64,
}

impl Forward {
    /// Accepts `t` and remembers it, or refuses a time before the last one.
    pub(crate) fn accept(&mut self, t: f64) -> Result<(), SolveError> {
        if !t.is_finite() || t < self.last {
            return Err(SolveError::Invalid(format!(
                "time {} is before the previous sample {} (runs only go forward)",
                Num(t),
                Num(self.last)
            )));
        }
        self.last = t;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_and_later_times_pass_earlier_and_nan_do_not() {
        let mut f = Forward::default();
        assert!(f.accept(0.0).is_ok());
        assert!(f.accept(1.5).is_ok());
        assert!(f.accept(1.5).is_ok());
        let err = f.accept(1.0).unwrap_err().to_string();
        assert!(err.contains("before the previous sample 1.5"), "{err}");
        assert!(f.accept(f64::NAN).is_err());
        assert!(f.accept(2.0).is_ok());
    }
}
