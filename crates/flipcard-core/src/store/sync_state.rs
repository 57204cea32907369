//! What the last sync through a folder saw, kept in the database: a
//! fingerprint of the folder's files and of the log (a sync that finds the
//! same one has nothing to do), and for each file the line up to which its
//! problems were reported (a line, once written, never changes, so a
//! problem is said once, not at every sync).

use std::collections::HashMap;

use rusqlite::{OptionalExtension, params};

use super::db::Store;
use super::error::StoreError;

impl Store {
    /// What changes when the log does: its newest rows and how many are
    /// undone (an undo marks a row, it adds none).
    pub(crate) fn log_fingerprint(&self) -> Result<String, StoreError> {
        self.conn
            .query_row(
                "SELECT * FROM \
                   (SELECT coalesce(max(id), 0), coalesce(sum(undone), 0), count(origin) \
                    FROM review), \
                   (SELECT coalesce(max(id), 0), coalesce(sum(undone), 0), count(origin) \
                    FROM status_event)",
                [],
                |r| {
                    Ok(format!(
                        "{}:{}:{}:{}:{}:{}",
                        r.get::<_, i64>(0)?,
                        r.get::<_, i64>(1)?,
                        r.get::<_, i64>(2)?,
                        r.get::<_, i64>(3)?,
                        r.get::<_, i64>(4)?,
                        r.get::<_, i64>(5)?
                    ))
                },
            )
            .map_err(|e| self.err(e))
    }

    /// The fingerprint the last complete sync through `dir` left.
    pub(crate) fn sync_fingerprint(&self, dir: &str) -> Result<Option<String>, StoreError> {
        self.conn
            .query_row(
                "SELECT fingerprint FROM sync_folder WHERE dir = ?1",
                [dir],
                |r| r.get(0),
            )
            .optional()
            .map_err(|e| self.err(e))
    }

    /// Keeps `fingerprint` for `dir` (`None`: forget it, so the next sync
    /// reads everything).
    pub(crate) fn set_sync_fingerprint(
        &mut self,
        dir: &str,
        fingerprint: Option<&str>,
    ) -> Result<(), StoreError> {
        match fingerprint {
            Some(f) => self.conn.execute(
                "INSERT INTO sync_folder (dir, fingerprint) VALUES (?1, ?2) \
                 ON CONFLICT (dir) DO UPDATE SET fingerprint = excluded.fingerprint",
                params![dir, f],
            ),
            None => self
                .conn
                .execute("DELETE FROM sync_folder WHERE dir = ?1", [dir]),
        }
        .map(|_| ())
        .map_err(|e| self.err(e))
    }

    /// The ids this data folder synced under before its current one.
    pub(crate) fn previous_machine_ids(&self) -> Result<Vec<String>, StoreError> {
        let mut st = self
            .conn
            .prepare_cached("SELECT id FROM machine_history ORDER BY id")
            .map_err(|e| self.err(e))?;
        let rows = st.query_map([], |r| r.get(0)).map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    /// Notes that this data folder synced under `id` before.
    pub(crate) fn add_previous_machine_id(&mut self, id: &str) -> Result<(), StoreError> {
        self.conn
            .execute(
                "INSERT INTO machine_history (id) VALUES (?1) ON CONFLICT DO NOTHING",
                [id],
            )
            .map(|_| ())
            .map_err(|e| self.err(e))
    }

    /// For each file of `dir`, the line up to which its problems were said.
    pub(crate) fn reported_through(&self, dir: &str) -> Result<HashMap<String, usize>, StoreError> {
        let mut st = self
            .conn
            .prepare_cached("SELECT name, reported_through FROM sync_file WHERE dir = ?1")
            .map_err(|e| self.err(e))?;
        let rows = st
            .query_map([dir], |r| {
                Ok((r.get::<_, String>(0)?, r.get::<_, i64>(1)?.max(0) as usize))
            })
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    /// Notes that the problems of `name` up to `line` were said.
    pub(crate) fn set_reported_through(
        &mut self,
        dir: &str,
        name: &str,
        line: usize,
    ) -> Result<(), StoreError> {
        self.conn
            .execute(
                "INSERT INTO sync_file (dir, name, reported_through) VALUES (?1, ?2, ?3) \
                 ON CONFLICT (dir, name) DO UPDATE SET reported_through = excluded.reported_through",
                params![dir, name, line as i64],
            )
            .map(|_| ())
            .map_err(|e| self.err(e))
    }
}
