//! The app's clock, read once from the environment: `FLIPCARD_NOW` (RFC
//! 3339) fixes it for tests, demos and exam planning. The library never
//! reads the environment; the commands and the terminal app hand it this
//! clock, or the time it gives.

use chrono::{DateTime, Utc};

use crate::sched::clock::{self, Clock, ClockError, NOW_VAR};

/// The clock the environment asks for.
///
/// An unparsable `FLIPCARD_NOW` is an error rather than a silent fallback to
/// the system clock: a demo or test that meant to fix the time must not run
/// on the real one.
pub fn from_env() -> Result<Clock, ClockError> {
    if std::env::var_os(NOW_VAR).is_none() {
        return Ok(Clock::System);
    }
    match std::env::var(NOW_VAR) {
        Ok(text) => clock::parse(&text).map(Clock::Fixed),
        // Set, but not Unicode: the system clock's time, fixed (as before).
        Err(_) => Ok(Clock::Fixed(Utc::now())),
    }
}

/// The current time, or the time fixed by `FLIPCARD_NOW`.
pub fn now() -> Result<DateTime<Utc>, ClockError> {
    from_env().map(|c| c.now())
}
