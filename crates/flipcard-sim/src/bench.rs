//! `flipcard bench [--quick] [--out DIR]`: the work–precision sweep. Every
//! method runs over its tolerances or step sizes on each case of the
//! problem set, with the orientation; each run is timed (minimum of
//! several), its work counted, and its samples compared with the exact
//! solution and with the invariants. Writes `DIR/work_precision.csv` (one
//! row per run) and `DIR/work_precision.svg` (error against time, one panel
//! per case, one curve per method) and prints a table. The generic ODE
//! solvers get their own sweep on three systems ([`systems`]), written to
//! `DIR/work_precision_systems.csv` and to the bottom row of the SVG.

mod cases;
mod plot;
mod systems;

use crate::error::SolveError;
use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::Context;
use nalgebra::Vector3;

pub use cases::{Case, cases, methods};
pub use systems::{Refusal, SysMethod, SystemMeasured, SystemRow, sweep_systems};
pub(crate) use systems::{SystemCase, system_cases, systems_csv};

use crate::rigid::model::{Body, State};
use crate::rigid::reference;
use crate::solvers::budget::Budget;
use crate::solvers::registry::{Options, make_with};
use crate::solvers::{Method, Needs, Work};

/// Points at which every run is compared with the exact solution.
pub const POINTS: usize = 1001;
/// The exact header of the CSV.
pub const CSV_HEADER: &str =
    "case,method,setting,steps,rhs_evals,wall_s,err_omega,err_energy,err_l2,err_lspace,err_qnorm";

/// How long each run may take, in steps, and how often it is repeated.
#[derive(Debug, Clone, Copy)]
pub struct Effort {
    pub budget: Budget,
    /// Repeat a run until this much time is spent (at least twice unless a
    /// single run already takes longer than this)...
    pub time_per_setting: Duration,
    /// ...but no more often than this.
    pub max_repeats: usize,
}

impl Effort {
    pub fn new(quick: bool) -> Effort {
        if quick {
            Effort {
                budget: Budget { max_steps: 200_000 },
                time_per_setting: Duration::from_millis(20),
                max_repeats: 3,
            }
        } else {
            Effort {
                budget: Budget::default(),
                time_per_setting: Duration::from_millis(500),
                max_repeats: 7,
            }
        }
    }
}

/// The errors of one run, each the largest over the sample points.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Errors {
    /// |ω − ω_exact| / |ω_exact|.
    pub omega: f64,
    /// |T − T₀| / T₀.
    pub energy: f64,
    /// ||L|² − |L₀|²| / |L₀|².
    pub l2: f64,
    /// |L_space − L_space(0)| / |L|.
    pub lspace: f64,
    /// ||q| − 1|.
    pub qnorm: f64,
}

/// One row of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub case: &'static str,
    pub method: Method,
    pub outcome: Result<Measured, SolveError>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    pub work: Work,
    /// Minimum wall time over the repeats (s).
    pub wall: f64,
    pub errors: Errors,
}

/// The exact states at the sample times of a case.
pub struct Reference {
    times: Vec<f64>,
    states: Vec<State>,
}

impl Reference {
    pub fn new(case: &Case) -> Result<Reference, SolveError> {
        let times: Vec<f64> = (0..POINTS)
            .map(|k| case.t_end * k as f64 / (POINTS - 1) as f64)
            .collect();
        let mut exact = reference::exact(case.body, case.omega0, Needs { orientation: true })?;
        let states = times
            .iter()
            .map(|&t| exact.advance(t))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Reference { times, states })
    }
}

fn run_once(
    case: &Case,
    method: Method,
    times: &[f64],
    budget: Budget,
) -> Result<(Vec<State>, Work, f64), SolveError> {
    let start = Instant::now();
    let mut solver = make_with(
        method,
        case.body,
        case.omega0,
        Needs { orientation: true },
        Options { budget },
    )?;
    solver.plan(case.t_end)?;
    let mut states = Vec::with_capacity(times.len());
    for &t in times {
        states.push(solver.advance(t)?);
    }
    let wall = start.elapsed().as_secs_f64();
    Ok((states, solver.work(), wall))
}

/// The largest errors of `states` against the exact ones.
pub fn errors(body: &Body, omega0: &Vector3<f64>, states: &[State], exact: &[State]) -> Errors {
    let e0 = body.energy(omega0);
    let l2_0 = body.l2(omega0);
    let l0 = body.momentum(omega0);
    let rel = |x: f64, x0: f64| {
        if x0 != 0.0 {
            (x - x0).abs() / x0.abs()
        } else {
            x.abs()
        }
    };
    let mut err = Errors::default();
    for (s, x) in states.iter().zip(exact) {
        let norm = x.omega.norm();
        let scale = if norm > 0.0 { norm } else { 1.0 };
        err.omega = err.omega.max((s.omega - x.omega).norm() / scale);
        err.energy = err.energy.max(rel(body.energy(&s.omega), e0));
        err.l2 = err.l2.max(rel(body.l2(&s.omega), l2_0));
        let l = body.momentum_in_space(s);
        let lnorm = if l2_0 > 0.0 { l2_0.sqrt() } else { 1.0 };
        err.lspace = err.lspace.max((l - l0).norm() / lnorm);
        err.qnorm = err.qnorm.max((s.q.quaternion().norm() - 1.0).abs());
    }
    err
}

/// Times one method × setting on a case (minimum of several runs) and
/// measures its errors; a refused or failed run gives its reason.
pub fn measure(case: &Case, method: Method, reference: &Reference, effort: &Effort) -> Row {
    let outcome = (|| {
        let (states, work, first) = run_once(case, method, &reference.times, effort.budget)?;
        let mut best = first;
        let mut spent = first;
        let mut runs = 1;
        while runs < effort.max_repeats
            && (runs < 2 || spent < effort.time_per_setting.as_secs_f64())
            && !(runs == 1 && first > effort.time_per_setting.as_secs_f64())
        {
            let (_, _, wall) = run_once(case, method, &reference.times, effort.budget)?;
            best = best.min(wall);
            spent += wall;
            runs += 1;
        }
        Ok::<_, SolveError>(Measured {
            work,
            wall: best,
            errors: errors(&case.body, &case.omega0, &states, &reference.states),
        })
    })();
    Row {
        case: case.id,
        method,
        outcome,
    }
}

/// Runs the whole sweep, reporting progress through `progress`.
pub fn sweep(
    quick: bool,
    mut progress: impl FnMut(&Row, usize, usize),
) -> anyhow::Result<Vec<Row>> {
    let effort = Effort::new(quick);
    let cases = cases(quick);
    let total: usize = cases.iter().map(|c| methods(c, quick).len()).sum();
    let mut rows = Vec::with_capacity(total);
    for case in &cases {
        let reference = Reference::new(case)
            .with_context(|| format!("case {} ({}): exact reference", case.id, case.name))?;
        for method in methods(case, quick) {
            let row = measure(case, method, &reference, &effort);
            progress(&row, rows.len() + 1, total);
            rows.push(row);
        }
    }
    Ok(rows)
}

pub fn sci(x: f64) -> String {
    format!("{x:.3e}")
}

/// The CSV: one line per row; a run that could not finish leaves the
/// numbers empty and gives its reason after the setting.
pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(CSV_HEADER);
    out.push('\n');
    for row in rows {
        let setting = row.method.setting();
        let line = match &row.outcome {
            Ok(m) => format!(
                "{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
                row.case,
                row.method.name(),
                setting,
                m.work.steps,
                m.work.rhs_evals,
                m.wall,
                m.errors.omega,
                m.errors.energy,
                m.errors.l2,
                m.errors.lspace,
                m.errors.qnorm
            ),
            Err(reason) => format!(
                "{},{},{},,,,,,,,",
                row.case,
                row.method.name(),
                quote(&format!("{setting} ({reason})"))
            ),
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// A CSV field, quoted when it holds a comma or a quote.
fn quote(field: &str) -> String {
    if field.contains([',', '"', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

/// The table printed at the end.
pub fn table(rows: &[Row]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<4} {:<10} {:<14} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "case",
        "method",
        "setting",
        "steps",
        "rhs_evals",
        "wall_s",
        "err_omega",
        "err_energy",
        "err_l2",
        "err_lspace",
        "err_qnorm"
    );
    for row in rows {
        let _ = match &row.outcome {
            Ok(m) => writeln!(
                out,
                "{:<4} {:<10} {:<14} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
                row.case,
                row.method.name(),
                row.method.setting(),
                m.work.steps,
                m.work.rhs_evals,
                sci(m.wall),
                sci(m.errors.omega),
                sci(m.errors.energy),
                sci(m.errors.l2),
                sci(m.errors.lspace),
                sci(m.errors.qnorm)
            ),
            Err(reason) => writeln!(
                out,
                "{:<4} {:<10} {:<14} {reason}",
                row.case,
                row.method.name(),
                row.method.setting()
            ),
        };
    }
    out
}

/// Writes `work_precision.csv`, `work_precision_systems.csv` and
/// `work_precision.svg` of a sweep into `dir` (which must exist).
pub fn write(dir: &Path, rows: &[Row], systems: &[SystemRow], quick: bool) -> anyhow::Result<()> {
    let csv_path = dir.join("work_precision.csv");
    flipcard_io::write_atomic(
        &csv_path,
        csv(rows).as_bytes(),
        flipcard_io::Durability::Whole,
    )
    .with_context(|| format!("writing {}", csv_path.display()))?;
    let systems_path = dir.join("work_precision_systems.csv");
    flipcard_io::write_atomic(
        &systems_path,
        systems_csv(systems).as_bytes(),
        flipcard_io::Durability::Whole,
    )
    .with_context(|| format!("writing {}", systems_path.display()))?;
    let svg_path = dir.join("work_precision.svg");
    let svg = plot::svg(rows, &cases(quick), systems, &system_cases(quick))
        .context("drawing the work–precision plot")?;
    flipcard_io::write_atomic(&svg_path, svg.as_bytes(), flipcard_io::Durability::Whole)
        .with_context(|| format!("writing {}", svg_path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refused_runs_are_rows_with_their_reason() {
        let case = &cases(true)[0];
        let reference = Reference::new(case).unwrap();
        let effort = Effort {
            budget: Budget { max_steps: 1000 },
            time_per_setting: Duration::ZERO,
            max_repeats: 1,
        };
        let ok = measure(case, Method::Adaptive { tol: 1e-8 }, &reference, &effort);
        let refused = measure(case, Method::Rk4 { dt: 1e-5 }, &reference, &effort);
        let m = ok.outcome.as_ref().unwrap();
        assert!(m.errors.omega > 0.0 && m.errors.omega < 1e-4, "{m:?}");
        assert!(m.work.steps > 0 && m.wall > 0.0);
        let reason = refused.outcome.as_ref().unwrap_err().to_string();
        assert!(reason.contains("budget"), "{reason}");

        let text = csv(&[ok, refused]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], CSV_HEADER);
        assert!(lines[1].starts_with("a,adaptive,tol=1e-8,"), "{}", lines[1]);
        assert_eq!(lines[1].split(',').count(), 11);
        // The reason follows the setting; the numbers are left empty.
        assert!(
            lines[2].starts_with("a,rk4,dt=1.0000e-5 (rk4: dt = "),
            "{}",
            lines[2]
        );
        assert!(lines[2].ends_with("exact solver),,,,,,,,"), "{}", lines[2]);
        // A reason with a comma is quoted, so the row keeps its 11 fields.
        assert_eq!(quote("dt=1 (a, b)"), "\"dt=1 (a, b)\"");
        assert_eq!(quote("say \"x\", y"), "\"say \"\"x\"\", y\"");
        assert!(table(&[refused_row()]).contains("budget"));
    }

    fn refused_row() -> Row {
        Row {
            case: "e",
            method: Method::Rk4 { dt: 1e-3 },
            outcome: Err(SolveError::StepBudget {
                t: 0.0,
                steps: 0,
                reason: "rk4: needs ~2e7 steps (budget 5e6)".into(),
            }),
        }
    }

    #[test]
    fn exact_run_has_no_error_and_keeps_the_invariants() {
        let case = &cases(true)[2];
        let reference = Reference::new(case).unwrap();
        let row = measure(case, Method::Exact, &reference, &Effort::new(true));
        let m = row.outcome.unwrap();
        assert_eq!(m.errors.omega, 0.0);
        assert!(m.errors.energy < 1e-13 && m.errors.l2 < 1e-13, "{m:?}");
        assert!(m.errors.lspace < 1e-12 && m.errors.qnorm < 1e-14, "{m:?}");
    }
}
