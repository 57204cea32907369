//! Where things live: bundled decks, data dir, config file.

use std::path::PathBuf;

/// The data dir: explicit override (`--data-dir` / `FLIPCARD_DATA_DIR`), else
/// the platform's (XDG on Linux).
pub fn data_dir(explicit: Option<PathBuf>) -> anyhow::Result<PathBuf> {
    if let Some(dir) = explicit {
        return Ok(dir);
    }
    project_dirs()
        .map(|d| d.data_dir().to_path_buf())
        .ok_or_else(|| {
            anyhow::anyhow!("no home directory found; pass --data-dir or set FLIPCARD_DATA_DIR")
        })
}

/// The config file: explicit override (`--config` / `FLIPCARD_CONFIG`), else
/// `config.toml` in the platform's config dir.
pub fn config_file(explicit: Option<PathBuf>) -> Option<PathBuf> {
    explicit.or_else(|| project_dirs().map(|d| d.config_dir().join("config.toml")))
}

fn project_dirs() -> Option<directories::ProjectDirs> {
    directories::ProjectDirs::from("", "", "flipcard")
}

/// The work–precision table the stats screen shows: the learner's own
/// `flipcard bench` run (`bench-out/` in the working directory) first, else
/// the report that ships with flipcard (`docs/`).
pub fn bench_csv() -> Option<PathBuf> {
    let file = "work_precision.csv";
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    [
        std::path::Path::new("bench-out").join(file),
        root.join("bench-out").join(file),
        root.join("docs").join(file),
    ]
    .into_iter()
    .find(|p| p.is_file())
}
