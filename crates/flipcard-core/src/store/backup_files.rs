//! Where the copies of the database lie, found without opening them: the
//! daily copies in `backups/`, and the newest copy of any kind (daily or
//! made before a migration), which the message of a damaged database names.
//! [`super::backup`] writes the copies; this part is apart so that the
//! errors can point to a copy without depending on the code that makes one.

use std::path::{Path, PathBuf};

use chrono::NaiveDate;

/// The folder of daily copies inside the data dir.
pub fn backups_dir(data_dir: &Path) -> PathBuf {
    data_dir.join("backups")
}

/// The daily copy for `day`.
pub fn daily_path(data_dir: &Path, day: NaiveDate) -> PathBuf {
    backups_dir(data_dir).join(format!("flipcard-{}.db", day.format("%Y-%m-%d")))
}

/// The daily copies present, newest first.
pub fn daily_backups(data_dir: &Path) -> Vec<(NaiveDate, PathBuf)> {
    let Ok(files) = flipcard_io::visible_files(backups_dir(data_dir), "db") else {
        return Vec::new();
    };
    let mut found: Vec<(NaiveDate, PathBuf)> = files
        .into_iter()
        .filter_map(|(path, name)| {
            let date = name.strip_prefix("flipcard-")?.strip_suffix(".db")?;
            let day = NaiveDate::parse_from_str(date, "%Y-%m-%d").ok()?;
            Some((day, path))
        })
        .collect();
    found.sort_by_key(|(day, _)| std::cmp::Reverse(*day));
    found
}

/// The most recently written copy of the database at `db` (daily or
/// pre-migration), to suggest when the database is damaged.
pub fn newest_backup(db: &Path) -> Option<PathBuf> {
    let dir = db.parent()?;
    let db_name = db.file_name()?.to_str()?.to_string();
    let migration_prefix = format!("{db_name}.bak-v");
    let mut candidates: Vec<PathBuf> = daily_backups(dir).into_iter().map(|(_, p)| p).collect();
    candidates.extend(
        flipcard_io::entries_starting_with(dir, &migration_prefix)
            .into_iter()
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| !n.contains(".partial-"))
            }),
    );
    candidates
        .into_iter()
        .filter_map(|p| {
            let modified = flipcard_io::metadata(&p).and_then(|m| m.modified()).ok()?;
            Some((modified, p))
        })
        .max()
        .map(|(_, p)| p)
}
