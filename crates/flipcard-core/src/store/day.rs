//! Learning days: a day starts at a fixed local time (04:00 by default), so
//! a late-night session still counts for the evening it belongs to.

use chrono::{DateTime, Duration, LocalResult, NaiveDate, NaiveTime, TimeZone, Utc};

#[derive(Debug, Clone)]
pub struct DayGrid<Tz: TimeZone> {
    tz: Tz,
    starts_at: NaiveTime,
}

impl<Tz: TimeZone> DayGrid<Tz> {
    pub fn new(tz: Tz, starts_at: NaiveTime) -> Self {
        DayGrid { tz, starts_at }
    }

    /// The learning day `t` falls in, named by its calendar date.
    pub fn day_of(&self, t: DateTime<Utc>) -> NaiveDate {
        let local = t.with_timezone(&self.tz).naive_local();
        if local.time() < self.starts_at {
            local.date() - Duration::days(1)
        } else {
            local.date()
        }
    }

    /// When `day` starts. In a daylight-saving gap the start moves to the
    /// first local time that exists.
    pub fn start_of(&self, day: NaiveDate) -> DateTime<Utc> {
        let mut local = day.and_time(self.starts_at);
        for _ in 0..4 {
            match self.tz.from_local_datetime(&local) {
                LocalResult::Single(t) => return t.with_timezone(&Utc),
                LocalResult::Ambiguous(early, _) => return early.with_timezone(&Utc),
                LocalResult::None => local += Duration::minutes(30),
            }
        }
        // No time zone has a gap this long; read the time as UTC.
        Utc.from_utc_datetime(&local)
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
