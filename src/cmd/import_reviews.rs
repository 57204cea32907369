//! `flipcard import --reviews FILE [--format json|csv]`: merges a review
//! log written by `flipcard export --reviews` into this one.

use std::process::ExitCode;

use crate::cmd::args::{Cli, ExportFormat, ImportArgs};
use crate::cmd::common::open_store;
use crate::cmd::paths;
use crate::interop::import::{RowError, read_reviews_csv, read_reviews_json};
use crate::sched::{Config, Schedulers};
use crate::text::plural;

pub fn run(cli: &Cli, args: &ImportArgs) -> anyhow::Result<ExitCode> {
    let file = &args.file;
    let format = match args.format {
        Some(f) => f,
        None => match file.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("json") => ExportFormat::Json,
            Some(e) if e.eq_ignore_ascii_case("csv") => ExportFormat::Csv,
            _ => anyhow::bail!(
                "cannot tell the format of {} from its name; pass --format json or --format csv",
                file.display()
            ),
        },
    };
    let bytes = crate::cmd::import_file::read_limited(file, MAX_LOG_BYTES).map_err(|e| {
        anyhow::anyhow!(
            "{}: {}; nothing imported",
            file.display(),
            crate::cmd::import_file::cannot_read(&e)
        )
    })?;
    let Ok(text) = String::from_utf8(bytes) else {
        anyhow::bail!("{} is not UTF-8 text; nothing imported", file.display());
    };
    let now = crate::cmd::clock::now()?;
    let parsed = match format {
        ExportFormat::Json => read_reviews_json(&text, now),
        ExportFormat::Csv => read_reviews_csv(&text, now),
    };
    let rows = match parsed {
        Ok(rows) => rows,
        Err(errors) => return Ok(report_bad_rows(file, &errors)),
    };
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let scheduler = Schedulers::new(&config);
    let mut store = open_store(cli)?;
    let summary = store.merge_reviews(&rows, &scheduler)?;
    crate::outln!(
        "imported {} from {} ({} already present); {} rebuilt",
        plural(summary.added, "review", "reviews"),
        file.display(),
        summary.duplicates,
        plural(summary.items, "card state", "card states"),
    )?;
    if summary.added_undone > 0 {
        crate::outln!("{} came undone and stay undone", summary.added_undone)?;
    }
    if summary.replayed_local > 0 {
        crate::outln!(
            "{} answered here came after imported ones and were replayed after them",
            plural(summary.replayed_local, "review", "reviews")
        )?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The largest review log read (an export of a million answers is about a
/// third of this): the whole file is held in memory while it is checked.
pub const MAX_LOG_BYTES: u64 = 512 << 20;

/// The bad rows as `FILE:LINE: message` (the first few, then how many
/// more), then the verdict.
pub fn report_bad_rows(file: &std::path::Path, errors: &[RowError]) -> ExitCode {
    crate::cmd::import_file::print_bad_rows(
        file,
        errors.iter().map(|e| (e.line as u64, e.message.as_str())),
    );
    crate::errln!(
        "flipcard: error: {} in {}; nothing imported",
        plural(errors.len(), "bad row", "bad rows"),
        file.display()
    );
    ExitCode::FAILURE
}
