//! The one clock of the app, as a value: the system clock, or a time fixed
//! by `FLIPCARD_NOW` (RFC 3339) for tests, demos and exam planning. The app
//! reads the environment once and hands the library a [`Clock`] or a time;
//! no library code reads the environment.

use chrono::{DateTime, NaiveDate, Utc};

/// The environment variable that fixes the app's clock (named in
/// [`ClockError`]'s messages; the app reads it).
pub const NOW_VAR: &str = "FLIPCARD_NOW";

/// The longest interval the scheduler gives, in days (py-fsrs's
/// `maximum_interval`). It is here because it bounds the clock: a due date
/// that far after [`latest`] must still be a time the app can write.
pub const MAXIMUM_INTERVAL: i64 = 36_500;

/// The earliest clock accepted: nothing the app stores predates it.
pub(crate) fn earliest() -> DateTime<Utc> {
    DateTime::UNIX_EPOCH
}

/// The latest clock accepted. Every time the app writes out (the clock
/// itself, and a due date up to the longest interval later) must be an RFC
/// 3339 time, whose year has four digits: the bound leaves that interval,
/// and a day to spare for the study day's time zone, before the year 10000.
pub fn latest() -> DateTime<Utc> {
    NaiveDate::from_ymd_opt(9899, 12, 31)
        .and_then(|d| d.and_hms_opt(23, 59, 59))
        .map_or(DateTime::<Utc>::MIN_UTC, |t| t.and_utc())
}

/// Where "now" comes from: the system clock, or a fixed time
/// (`FLIPCARD_NOW`, tests).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Clock {
    #[default]
    System,
    Fixed(DateTime<Utc>),
}

impl Clock {
    pub fn now(&self) -> DateTime<Utc> {
        match self {
            Clock::System => Utc::now(),
            Clock::Fixed(t) => *t,
        }
    }
}

/// A `FLIPCARD_NOW` value: an RFC 3339 time within [`earliest`]..=[`latest`].
pub fn parse(text: &str) -> Result<DateTime<Utc>, ClockError> {
    let t = DateTime::parse_from_rfc3339(text.trim())
        .map(|t| t.with_timezone(&Utc))
        .map_err(|e| ClockError::NotRfc3339 {
            text: text.to_string(),
            reason: e.to_string(),
        })?;
    if t < earliest() || t > latest() {
        return Err(ClockError::OutOfRange {
            text: text.to_string(),
        });
    }
    Ok(t)
}

/// `t` to the millisecond, the precision the log and sync files keep:
/// every choice that shapes a state (the interval fuzz) is made from the
/// time as it is stored, so replaying a synced answer gives the same state.
pub(crate) fn to_millisecond(t: DateTime<Utc>) -> DateTime<Utc> {
    DateTime::from_timestamp_millis(t.timestamp_millis()).unwrap_or(t)
}

/// How far ahead of this machine's clock a time from elsewhere may be: two
/// machines' clocks rarely agree to the second, and a hardware clock kept
/// in local time is off by up to fourteen hours.
pub(crate) const FUTURE_SKEW: chrono::TimeDelta = chrono::TimeDelta::days(1);

/// Checks the time of an answer or event read from a file flipcard did not
/// write (a sync line, a learner's export, an Anki revlog): from 1970 up to
/// [`FUTURE_SKEW`] after `now`, and never past [`latest`], so every time the
/// app stores can be written back as RFC 3339.
pub(crate) fn check_event_time(t: DateTime<Utc>, now: DateTime<Utc>) -> Result<(), EventTimeError> {
    if t < earliest() {
        return Err(EventTimeError::Before1970 { t });
    }
    let bound = (now + FUTURE_SKEW).min(latest());
    if t > bound {
        return Err(EventTimeError::InTheFuture { t, now });
    }
    Ok(())
}

/// Why [`check_event_time`] refused a time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum EventTimeError {
    #[error("{} is before 1970", rfc3339(*t))]
    Before1970 { t: DateTime<Utc> },
    #[error(
        "{} is in the future (this machine's clock says {})",
        rfc3339_or_year(*t),
        rfc3339(*now)
    )]
    InTheFuture {
        t: DateTime<Utc>,
        now: DateTime<Utc>,
    },
}

/// A time for a message: RFC 3339 when it has one (years 0–9999), else
/// its year alone.
fn rfc3339_or_year(t: DateTime<Utc>) -> String {
    use chrono::Datelike;
    if (0..=9999).contains(&t.year()) {
        rfc3339(t)
    } else {
        format!("a time in the year {}", t.year())
    }
}

fn rfc3339(t: DateTime<Utc>) -> String {
    t.to_rfc3339_opts(chrono::SecondsFormat::Secs, true)
}

#[derive(Debug, thiserror::Error)]
pub enum ClockError {
    #[error(
        "{NOW_VAR}={text:?} is not an RFC 3339 time ({reason}); example: 2026-11-22T09:00:00+05:30"
    )]
    NotRfc3339 { text: String, reason: String },
    #[error(
        "{NOW_VAR}={text:?} is outside the supported range {} to {} (a due date up to {MAXIMUM_INTERVAL} days later must still fall before the year 10000)",
        rfc3339(earliest()),
        rfc3339(latest())
    )]
    OutOfRange { text: String },
}

#[cfg(test)]
mod tests {
    use chrono::TimeDelta;

    use super::*;

    #[test]
    fn event_times_are_bounded_by_1970_and_now_plus_a_day() {
        let now = parse("2026-11-22T09:00:00Z").unwrap();
        assert!(check_event_time(now, now).is_ok());
        assert!(check_event_time(earliest(), now).is_ok());
        assert!(check_event_time(now + TimeDelta::hours(23), now).is_ok());
        let err = check_event_time(now + TimeDelta::hours(25), now)
            .unwrap_err()
            .to_string();
        assert!(err.contains("in the future"), "{err}");
        let err = check_event_time(earliest() - TimeDelta::milliseconds(1), now)
            .unwrap_err()
            .to_string();
        assert!(err.contains("before 1970"), "{err}");
        let far = DateTime::parse_from_rfc3339("9999-12-31T23:59:59.999-23:59")
            .unwrap()
            .with_timezone(&Utc);
        let err = check_event_time(far, latest()).unwrap_err().to_string();
        assert!(err.contains("year 10000"), "{err}");
    }

    #[test]
    fn clocks_in_range_parse_in_any_offset() {
        let t = parse("2026-11-22T09:00:00+05:30").unwrap();
        assert_eq!(rfc3339(t), "2026-11-22T03:30:00Z");
        assert_eq!(parse("1970-01-01T00:00:00Z").unwrap(), earliest());
        assert_eq!(parse(&rfc3339(latest())).unwrap(), latest());
    }

    #[test]
    fn the_latest_clock_leaves_room_for_the_longest_interval() {
        let due = latest() + TimeDelta::days(MAXIMUM_INTERVAL);
        // A day later still, for a study day east of UTC.
        let text = rfc3339(due + TimeDelta::days(1));
        assert!(text.starts_with("9999-"), "{text}");
        assert_eq!(
            DateTime::parse_from_rfc3339(&text).unwrap(),
            due + TimeDelta::days(1)
        );
        assert_eq!(rfc3339(latest()), "9899-12-31T23:59:59Z");
    }

    #[test]
    fn the_longest_interval_scheduled_at_the_latest_clock_is_rfc_3339() {
        use crate::sched::{CardState, Config, Direction, ItemKey, Rating, Scheduler, State};
        let scheduler = Scheduler::new(&Config {
            fuzz: false,
            ..Config::default()
        });
        let key = ItemKey {
            deck: "d".into(),
            card: "c".into(),
            direction: Direction::Forward,
        };
        let now = latest();
        // Remembered for a very long time already: the next interval is the
        // longest there is.
        let card = CardState {
            state: State::Review,
            step: None,
            stability: Some(1e9),
            difficulty: Some(1.0),
            due: now,
            last_review: Some(now - TimeDelta::days(MAXIMUM_INTERVAL)),
        };
        let record = scheduler.review(&key, Some(&card), Rating::Easy, now, 0);
        assert_eq!(record.scheduled_days, MAXIMUM_INTERVAL);
        let due = rfc3339(record.after.due);
        assert!(due.starts_with("9999-"), "{due}");
    }

    #[test]
    fn clocks_outside_the_range_are_refused_in_one_line() {
        for text in [
            "9999-12-31T23:00:00-05:00",
            "9999-12-31T00:00:00Z",
            "9950-01-01T00:00:00Z",
            "1969-12-31T23:59:59Z",
            "0000-01-01T00:00:00Z",
        ] {
            let err = parse(text).unwrap_err();
            assert!(
                matches!(err, ClockError::OutOfRange { .. }),
                "{text}: {err}"
            );
            let msg = err.to_string();
            assert!(!msg.contains('\n'), "{msg}");
            assert!(
                msg.contains("1970-01-01T00:00:00Z to 9899-12-31T23:59:59Z"),
                "{msg}"
            );
            assert!(msg.contains("36500 days"), "{msg}");
        }
        let just_after = rfc3339(latest() + TimeDelta::seconds(1));
        assert!(parse(&just_after).is_err(), "{just_after}");
    }

    #[test]
    fn a_time_that_is_not_rfc_3339_says_so() {
        for text in ["garbage", "+10000-01-01T00:00:00Z", "2026-13-01T00:00:00Z"] {
            let err = parse(text).unwrap_err();
            assert!(
                matches!(err, ClockError::NotRfc3339 { .. }),
                "{text}: {err}"
            );
        }
    }
}
