//! `flipcard bench [--quick] [--out DIR]`: error against run time for every
//! solver, as a CSV and an SVG in DIR and a table on standard output.

use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;

use crate::cmd::args::{BenchArgs, Cli};
use crate::sim::bench;
use crate::text::plural;

pub fn run(_cli: &Cli, args: &BenchArgs) -> anyhow::Result<ExitCode> {
    let out_dir = &args.out;
    crate::io::create_dir_all(out_dir)
        .with_context(|| format!("cannot create the output folder {}", out_dir.display()))?;
    let started = Instant::now();
    let rows = bench::sweep(args.quick, |row, k, total| {
        let what = match &row.outcome {
            Ok(m) => format!(
                "{} s, error {}",
                bench::sci(m.wall),
                bench::sci(m.errors.omega)
            ),
            Err(reason) => reason.to_string(),
        };
        crate::errln!(
            "bench [{k}/{total}] case {} {} {}: {what}",
            row.case,
            row.method.name(),
            row.method.setting()
        );
    })?;
    let systems = bench::sweep_systems(args.quick, |row, note, k, total| match row {
        None => crate::errln!("bench systems: {note}"),
        Some(row) => {
            let what = match &row.outcome {
                Ok(m) => format!(
                    "{} s, error {}",
                    bench::sci(m.wall),
                    bench::sci(m.err_state)
                ),
                Err(reason) => reason.to_string(),
            };
            crate::errln!(
                "bench systems [{k}/{total}] {} {} {}: {what}",
                row.case,
                row.method.name(),
                row.method.setting(row.setting)
            );
        }
    })
    .map_err(anyhow::Error::msg)?;
    // The files first: they are what the sweep is for, and a reader of the
    // table that stops early (`| head`) must not cost them.
    bench::write(out_dir, &rows, &systems, args.quick)?;
    crate::out!("{}", bench::table(&rows))?;
    crate::errln!(
        "bench: {} in {:.1} s; wrote {}, {} and {}",
        plural(rows.len() + systems.len(), "run", "runs"),
        started.elapsed().as_secs_f64(),
        out_dir.join("work_precision.csv").display(),
        out_dir.join("work_precision_systems.csv").display(),
        out_dir.join("work_precision.svg").display()
    );
    Ok(ExitCode::SUCCESS)
}
