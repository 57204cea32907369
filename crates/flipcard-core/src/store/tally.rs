//! Answer tallies: how many answers that count (not undone) each deck has,
//! by kind and rating, kept beside the log so all-time figures need not
//! read it whole. Derived from the log and rebuilt with the card states.

use std::collections::BTreeMap;

use rusqlite::{Connection, Transaction, params};

use crate::sched::ReviewRecord;

/// Adds `delta` (+1 for a new answer, −1 for an undone one).
pub(super) fn count(tx: &Transaction<'_>, r: &ReviewRecord, delta: i64) -> rusqlite::Result<()> {
    tx.prepare_cached(
        "INSERT INTO review_tally (deck, kind, rating, n) VALUES (?1, ?2, ?3, max(?4, 0)) \
         ON CONFLICT (deck, kind, rating) DO UPDATE SET n = max(n + ?4, 0)",
    )?
    .execute(params![r.key.deck, r.kind, r.rating, delta])?;
    Ok(())
}

type Tally = BTreeMap<(String, String, i64), i64>;

fn read(conn: &Connection, sql: &str) -> rusqlite::Result<Tally> {
    let mut st = conn.prepare(sql)?;
    let rows = st.query_map([], |r| Ok(((r.get(0)?, r.get(1)?, r.get(2)?), r.get(3)?)))?;
    rows.collect()
}

const FROM_LOG: &str = "SELECT deck, kind, rating, count(*) FROM review WHERE undone = 0 \
     GROUP BY deck, kind, rating";

/// Recomputes the tallies from the log; true when they were not what the
/// log gives.
pub(super) fn rebuild(tx: &Transaction<'_>) -> rusqlite::Result<bool> {
    let before = read(
        tx,
        "SELECT deck, kind, rating, n FROM review_tally WHERE n > 0",
    )?;
    let after = read(tx, FROM_LOG)?;
    tx.execute("DELETE FROM review_tally", [])?;
    tx.execute(
        &format!("INSERT INTO review_tally (deck, kind, rating, n) {FROM_LOG}"),
        [],
    )?;
    Ok(before != after)
}

/// Review-kind answers that count, and how many of them were not Again,
/// for one deck or all.
pub(super) fn review_answers(
    conn: &Connection,
    deck: Option<&str>,
) -> rusqlite::Result<(u64, u64)> {
    let mut st = conn.prepare_cached(
        "SELECT coalesce(sum(n), 0), coalesce(sum(CASE WHEN rating <> 1 THEN n ELSE 0 END), 0) \
         FROM review_tally WHERE kind = 'review' AND (?1 IS NULL OR deck = ?1)",
    )?;
    st.query_row([deck], |r| {
        Ok((r.get::<_, i64>(0)? as u64, r.get::<_, i64>(1)? as u64))
    })
}
