//! The one way anything changes the database:
//! [`Store::write`](crate::store::Store::write) opens an immediate
//! transaction (the write lock is taken at the start, so two writers queue
//! on SQLite's busy timeout instead of failing half-way), hands the work a
//! [`Write`], commits, and maps every SQLite error to a [`StoreError`] that
//! names the file. The session row a rating or a status change is written
//! under is created here, by the first write that needs one, and kept by
//! the store only once that write is on disk.
//!
//! Migrations run before a `Store` exists; they take the same path through
//! [`immediate`].

use std::ops::Deref;
use std::path::Path;

use rusqlite::{Connection, Transaction, TransactionBehavior};

use chrono::{DateTime, Utc};

use super::codec::to_ms;
use super::error::StoreError;
use crate::sched::clock::Clock;

/// Why a write's work stopped: an SQLite error (mapped with the database's
/// path when the write ends) or a store error the work raised itself. Both
/// convert with `?`, so the work reads as plain code.
#[derive(Debug)]
pub(crate) enum Failed {
    Sql(rusqlite::Error),
    Store(StoreError),
}

impl From<rusqlite::Error> for Failed {
    fn from(e: rusqlite::Error) -> Failed {
        Failed::Sql(e)
    }
}

impl From<StoreError> for Failed {
    fn from(e: StoreError) -> Failed {
        Failed::Store(e)
    }
}

/// An open immediate transaction, the session it writes under and the
/// clock a new session starts by.
pub(crate) struct Write<'c> {
    tx: Transaction<'c>,
    session: Option<i64>,
    clock: Clock,
}

impl<'c> Deref for Write<'c> {
    type Target = Transaction<'c>;
    fn deref(&self) -> &Transaction<'c> {
        &self.tx
    }
}

impl Write<'_> {
    /// The store's session, started by this write if none has been.
    pub(crate) fn session(&mut self) -> rusqlite::Result<i64> {
        let started = self.clock.now();
        session_in_at(&self.tx, &mut self.session, started)
    }
}

/// [`Store::write`](crate::store::Store::write) on a bare connection
/// (migrations): the transaction, the commit and the error mapping;
/// returns the work's value and the session after it.
pub(crate) fn immediate<T>(
    conn: &mut Connection,
    path: &Path,
    session: Option<i64>,
    clock: Clock,
    work: impl FnOnce(&mut Write<'_>) -> Result<T, Failed>,
) -> Result<(T, Option<i64>), StoreError> {
    let sql = |e: rusqlite::Error| StoreError::from_sqlite(path, e);
    let tx = conn
        .transaction_with_behavior(TransactionBehavior::Immediate)
        .map_err(sql)?;
    let mut w = Write { tx, session, clock };
    let value = match work(&mut w) {
        Ok(v) => v,
        // Dropping the transaction rolls it back.
        Err(Failed::Sql(e)) => return Err(sql(e)),
        Err(Failed::Store(e)) => return Err(e),
    };
    let Write { tx, session, .. } = w;
    tx.commit().map_err(sql)?;
    Ok((value, session))
}

/// `session`, or a new session row kept in it: merges write under a
/// session of their own that the store does not adopt.
pub(super) fn session_in(w: &Write<'_>, session: &mut Option<i64>) -> rusqlite::Result<i64> {
    session_in_at(&w.tx, session, w.clock.now())
}

fn session_in_at(
    conn: &Connection,
    session: &mut Option<i64>,
    started: DateTime<Utc>,
) -> rusqlite::Result<i64> {
    match *session {
        Some(s) => Ok(s),
        None => Ok(*session.insert(insert_session(conn, started)?)),
    }
}

/// A new session row (the time the session started, by the app's clock).
pub(super) fn insert_session(conn: &Connection, started: DateTime<Utc>) -> rusqlite::Result<i64> {
    conn.execute(
        "INSERT INTO session (started_at) VALUES (?1)",
        [to_ms(started)],
    )?;
    Ok(conn.last_insert_rowid())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::Store;

    fn sessions(store: &Store) -> i64 {
        store
            .conn
            .query_row("SELECT count(*) FROM session", [], |r| r.get(0))
            .unwrap()
    }

    #[test]
    fn a_failed_write_leaves_nothing_and_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let err = store
            .write(|w| {
                w.session()?;
                w.execute("INSERT INTO no_such_table VALUES (1)", [])?;
                Ok(())
            })
            .unwrap_err();
        // The SQLite error is mapped with the database's path, whatever
        // module the work was written in.
        assert!(
            err.to_string().contains(&store.path.display().to_string()),
            "{err}"
        );
        // The session row it started was rolled back and not adopted.
        assert_eq!(sessions(&store), 0);
        assert_eq!(store.session, None);
    }

    #[test]
    fn a_session_is_kept_only_once_its_write_is_on_disk() {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let first = store.write(|w| Ok(w.session()?)).unwrap();
        assert_eq!(store.session, Some(first));
        // A later write reuses it; a merge's own session is not adopted.
        let again = store.write(|w| Ok(w.session()?)).unwrap();
        assert_eq!(again, first);
        let mut own = None;
        let merged = store.write(|w| Ok(session_in(w, &mut own)?)).unwrap();
        assert_ne!(merged, first);
        assert_eq!(store.session, Some(first));
        assert_eq!(sessions(&store), 2);
    }

    #[test]
    fn an_error_the_work_raises_itself_is_returned_as_it_is() {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let err = store
            .write(|w| -> Result<(), Failed> {
                w.session()?;
                Err(StoreError::BadRow {
                    id: 7,
                    detail: "refused".into(),
                }
                .into())
            })
            .unwrap_err();
        assert!(matches!(err, StoreError::BadRow { id: 7, .. }), "{err}");
        assert_eq!(sessions(&store), 0);
    }
}
