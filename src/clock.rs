//! The one clock of the app. `FLIPCARD_NOW` (RFC 3339) replaces the system
//! clock everywhere, for tests, demos and exam planning.

use chrono::{DateTime, Utc};

/// The environment variable that fixes the clock.
pub const NOW_VAR: &str = "FLIPCARD_NOW";

/// The current time, or the time fixed by `FLIPCARD_NOW`.
///
/// An unparsable `FLIPCARD_NOW` is an error rather than a silent fallback to
/// the system clock: a demo or test that meant to fix the time must not run
/// on the real one.
pub fn now() -> Result<DateTime<Utc>, ClockError> {
    match std::env::var(NOW_VAR) {
        Ok(text) => DateTime::parse_from_rfc3339(text.trim())
            .map(|t| t.with_timezone(&Utc))
            .map_err(|e| ClockError {
                text,
                reason: e.to_string(),
            }),
        Err(_) => Ok(Utc::now()),
    }
}

#[derive(Debug, thiserror::Error)]
#[error(
    "{NOW_VAR}={text:?} is not an RFC 3339 time ({reason}); example: 2026-11-22T09:00:00+05:30"
)]
pub struct ClockError {
    pub text: String,
    pub reason: String,
}
