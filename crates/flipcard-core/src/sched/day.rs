//! Learning days: a day starts at a fixed local time (04:00 by default), so
//! a late-night session still counts for the evening it belongs to. This is
//! the one place that turns a wall-clock start into instants (with the
//! daylight-saving probe): the queue's study day, the bury that ends with
//! it, and every per-day statistic read it from a [`DayGrid`].

use chrono::{DateTime, Duration, LocalResult, NaiveDate, NaiveTime, TimeZone, Utc};

/// Learning days in one time zone, starting at `starts_at` local time.
#[derive(Debug, Clone)]
pub struct DayGrid<Tz: TimeZone> {
    tz: Tz,
    starts_at: NaiveTime,
}

impl<Tz: TimeZone> DayGrid<Tz> {
    pub fn new(tz: Tz, starts_at: NaiveTime) -> Self {
        DayGrid { tz, starts_at }
    }

    /// The learning day `t` falls in, named by the calendar date it starts
    /// on: the day has begun once its start instant has passed.
    pub fn day_of(&self, t: DateTime<Utc>) -> NaiveDate {
        let date = t.with_timezone(&self.tz).date_naive();
        if self.start_of(date) > t {
            date - Duration::days(1)
        } else {
            date
        }
    }

    /// When `day` starts: the earlier instant when the clock is set back
    /// over the start time, the first instant after the gap when it jumps
    /// forward over it.
    pub(crate) fn start_of(&self, day: NaiveDate) -> DateTime<Utc> {
        let local = day.and_time(self.starts_at);
        let mut probe = local;
        for _ in 0..4 {
            match self.tz.from_local_datetime(&probe) {
                LocalResult::Single(t) => return t.with_timezone(&Utc),
                LocalResult::Ambiguous(a, b) => return a.min(b).with_timezone(&Utc),
                LocalResult::None => probe += Duration::minutes(30),
            }
        }
        // No time zone has a gap this long; read the time as UTC.
        local.and_utc()
    }

    /// The learning day containing `now`: (start, end). The end is never in
    /// the past, even around a daylight-saving jump.
    pub fn bounds(&self, now: DateTime<Utc>) -> (DateTime<Utc>, DateTime<Utc>) {
        let day = self.day_of(now);
        let start = self.start_of(day);
        let mut end = self.start_of(day + Duration::days(1));
        if end <= now {
            end = self.start_of(day + Duration::days(2));
        }
        (start, end)
    }
}

/// Which clock draws the line between study days.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DayZone {
    /// The machine's local time zone (the app and every command).
    Local,
    /// For tests: the same day boundary on every machine.
    Utc,
}

/// Learning days as the queries that count per day need them, whatever
/// the zone: a [`DayGrid`] of any zone, or [`Days`] chosen by a
/// [`DayZone`] at run time.
pub trait DayOf {
    /// The learning day `t` falls in.
    fn day_of(&self, t: DateTime<Utc>) -> NaiveDate;
    /// When `day` starts.
    fn start_of(&self, day: NaiveDate) -> DateTime<Utc>;
}

impl<Tz: TimeZone> DayOf for DayGrid<Tz> {
    fn day_of(&self, t: DateTime<Utc>) -> NaiveDate {
        DayGrid::day_of(self, t)
    }
    fn start_of(&self, day: NaiveDate) -> DateTime<Utc> {
        DayGrid::start_of(self, day)
    }
}

/// The learning days of a [`DayZone`].
#[derive(Debug, Clone)]
pub enum Days {
    Local(DayGrid<chrono::Local>),
    Utc(DayGrid<Utc>),
}

impl Days {
    pub fn new(zone: DayZone, starts_at: NaiveTime) -> Days {
        match zone {
            DayZone::Local => Days::Local(DayGrid::new(chrono::Local, starts_at)),
            DayZone::Utc => Days::Utc(DayGrid::new(Utc, starts_at)),
        }
    }

    /// The learning day containing `now`: (start, end).
    pub fn bounds(&self, now: DateTime<Utc>) -> (DateTime<Utc>, DateTime<Utc>) {
        match self {
            Days::Local(g) => g.bounds(now),
            Days::Utc(g) => g.bounds(now),
        }
    }
}

impl DayOf for Days {
    fn day_of(&self, t: DateTime<Utc>) -> NaiveDate {
        match self {
            Days::Local(g) => g.day_of(t),
            Days::Utc(g) => g.day_of(t),
        }
    }
    fn start_of(&self, day: NaiveDate) -> DateTime<Utc> {
        match self {
            Days::Local(g) => g.start_of(day),
            Days::Utc(g) => g.start_of(day),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono::FixedOffset;

    fn t(s: &str) -> DateTime<Utc> {
        DateTime::parse_from_rfc3339(s).unwrap().with_timezone(&Utc)
    }

    #[test]
    fn day_turns_at_the_local_start_time() {
        let ist = FixedOffset::east_opt(5 * 3600 + 1800).unwrap();
        let grid = DayGrid::new(ist, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
        let d = |s: &str| NaiveDate::parse_from_str(s, "%Y-%m-%d").unwrap();
        assert_eq!(grid.day_of(t("2026-11-22T03:59:59+05:30")), d("2026-11-21"));
        assert_eq!(grid.day_of(t("2026-11-22T04:00:00+05:30")), d("2026-11-22"));
        assert_eq!(
            grid.start_of(d("2026-11-22")),
            t("2026-11-22T04:00:00+05:30")
        );
    }
}

#[cfg(test)]
mod agree {
    use super::*;
    use chrono::FixedOffset;
    use proptest::prelude::*;

    proptest! {
        /// The day an instant falls in is the day whose bounds hold it, in
        /// any zone and for any start time: the queue (`bounds`) and the
        /// statistics (`day_of`) never disagree about a day.
        #[test]
        fn day_of_and_bounds_agree(
            secs in 0i64..4_102_444_800,
            offset_min in -14 * 60i32..=14 * 60,
            start_min in 0u32..24 * 60,
        ) {
            let tz = FixedOffset::east_opt(offset_min * 60).unwrap();
            let starts = NaiveTime::from_hms_opt(start_min / 60, start_min % 60, 0).unwrap();
            let grid = DayGrid::new(tz, starts);
            let t = DateTime::from_timestamp(secs, 0).unwrap();
            let (start, end) = grid.bounds(t);
            prop_assert!(start <= t && t < end);
            prop_assert_eq!(start, grid.start_of(grid.day_of(t)));
            prop_assert_eq!(grid.day_of(start), grid.day_of(t));
        }
    }
}
