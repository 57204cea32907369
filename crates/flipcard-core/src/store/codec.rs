//! How the scheduler's vocabulary is spelled in the database: states, kinds
//! and directions as readable words, ratings as 1–4, times as UTC
//! milliseconds. Each type reads and writes itself (`FromSql` / `ToSql`), so
//! a row decodes with `row.get` and a value this build does not know is an
//! error naming it.

use chrono::{DateTime, Utc};
use rusqlite::types::{FromSql, FromSqlError, FromSqlResult, ToSql, ToSqlOutput, ValueRef};

use crate::sched::{CardState, Direction, Rating, ReviewKind, State};

/// A card's state from six columns of a row, at the positions given in the
/// order state, step, stability, difficulty, due, last review (the log and
/// the cache keep them in different orders).
pub fn card_state(row: &rusqlite::Row<'_>, at: [usize; 6]) -> rusqlite::Result<CardState> {
    Ok(CardState {
        state: row.get(at[0])?,
        step: row.get::<_, Option<Count>>(at[1])?.map(|c| c.0),
        stability: row.get(at[2])?,
        difficulty: row.get(at[3])?,
        due: row.get::<_, Ms>(at[4])?.0,
        last_review: row.get::<_, Option<Ms>>(at[5])?.map(|m| m.0),
    })
}

pub(crate) fn state_str(s: State) -> &'static str {
    match s {
        State::New => "new",
        State::Learning => "learning",
        State::Review => "review",
        State::Relearning => "relearning",
    }
}

const STATES: [State; 4] = [
    State::New,
    State::Learning,
    State::Review,
    State::Relearning,
];

const KINDS: [ReviewKind; 4] = [
    ReviewKind::Learn,
    ReviewKind::Review,
    ReviewKind::Relearn,
    ReviewKind::Cram,
];

fn parse_kind(s: &str) -> Option<ReviewKind> {
    KINDS.into_iter().find(|k| k.as_str() == s)
}

/// A word column read as one of `T`'s values.
fn word<T>(value: ValueRef<'_>, what: &str, parse: impl Fn(&str) -> Option<T>) -> FromSqlResult<T> {
    let text = value.as_str()?;
    parse(text).ok_or_else(|| FromSqlError::Other(format!("unknown {what} {text:?}").into()))
}

impl ToSql for State {
    fn to_sql(&self) -> rusqlite::Result<ToSqlOutput<'_>> {
        Ok(state_str(*self).into())
    }
}

impl FromSql for State {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        word(value, "state", |s| {
            STATES.into_iter().find(|st| state_str(*st) == s)
        })
    }
}

impl ToSql for ReviewKind {
    fn to_sql(&self) -> rusqlite::Result<ToSqlOutput<'_>> {
        Ok(self.as_str().into())
    }
}

impl FromSql for ReviewKind {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        word(value, "kind", parse_kind)
    }
}

impl ToSql for Direction {
    fn to_sql(&self) -> rusqlite::Result<ToSqlOutput<'_>> {
        Ok(ToSqlOutput::from(self.as_str().into_owned()))
    }
}

impl FromSql for Direction {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        word(value, "direction", Direction::parse)
    }
}

impl ToSql for Rating {
    fn to_sql(&self) -> rusqlite::Result<ToSqlOutput<'_>> {
        Ok((*self as i64).into())
    }
}

impl FromSql for Rating {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        let n = value.as_i64()?;
        Rating::from_number(n)
            .ok_or_else(|| FromSqlError::Other(format!("rating {n} is not 1–4").into()))
    }
}

/// A time as stored: whole UTC milliseconds (sub-millisecond parts are
/// dropped, so a stored time reads back equal to its truncation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ms(pub DateTime<Utc>);

impl ToSql for Ms {
    fn to_sql(&self) -> rusqlite::Result<ToSqlOutput<'_>> {
        Ok(to_ms(self.0).into())
    }
}

impl FromSql for Ms {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        let ms = value.as_i64()?;
        from_ms(ms)
            .map(Ms)
            .ok_or_else(|| FromSqlError::Other(format!("time {ms} ms is out of range").into()))
    }
}

/// A count or step stored as an integer that must fit `u32`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Count(pub u32);

impl FromSql for Count {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        let n = value.as_i64()?;
        u32::try_from(n)
            .map(Count)
            .map_err(|_| FromSqlError::Other(format!("{n} is out of range").into()))
    }
}

/// The interval the load balancer chose for an answer, as stored: whole
/// days from 1 to the longest interval (`review.balanced_days`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct BalancedDays(pub i64);

impl FromSql for BalancedDays {
    fn column_result(value: ValueRef<'_>) -> FromSqlResult<Self> {
        let n = value.as_i64()?;
        if (1..=crate::sched::scheduler::MAXIMUM_INTERVAL).contains(&n) {
            Ok(BalancedDays(n))
        } else {
            Err(FromSqlError::Other(
                format!("balanced interval {n} days is out of range").into(),
            ))
        }
    }
}

pub(crate) fn to_ms(t: DateTime<Utc>) -> i64 {
    t.timestamp_millis()
}

pub(crate) fn from_ms(ms: i64) -> Option<DateTime<Utc>> {
    DateTime::from_timestamp_millis(ms)
}

/// A decoding failure of one row: SQLite's own errors stay SQLite errors,
/// a value this build cannot interpret becomes the row's own problem.
pub(crate) fn bad_value(err: rusqlite::Error) -> Result<String, rusqlite::Error> {
    match err {
        rusqlite::Error::FromSqlConversionFailure(_, _, cause) => Ok(cause.to_string()),
        rusqlite::Error::IntegralValueOutOfRange(_, n) => Ok(format!("{n} is out of range")),
        other => Err(other),
    }
}
