//! `flipcard sim --scene ID` on a system scene: the run sampled
//! (`--samples N`, CSV or JSON, columns `t`, the variables, then the
//! observables), chosen measures (`--measure 'period(theta)'`), or every
//! measurement its prompts use with their verdicts (exit 1 when the run
//! contradicts a prompt's answer, as `check` says).

use std::fmt::Write as _;
use std::io::Write;
use std::process::ExitCode;

use anyhow::{anyhow, bail};

use crate::cmd::args::{MethodArg, SimArgs, SimFormat};
use crate::cmd::sim_samples::{Conserved, Stats};
use crate::deck::{Deck, Measure, Prompt, SystemScene};
use crate::predict::audit::{Run, audit_run, audit_slips};
use crate::sim::error::SolveError;
use crate::sim::scene::spec::SceneAtol;
use crate::sim::scene::system::{RunError, SystemPlan, SystemRun, describe, measure_system_noting};
use crate::sim::solvers::ode::{OdeKind, OdeMethod, OdeSystem};
use crate::sim::system::System;
use crate::text::num::{self, Num};

/// The method for a system from the arguments (default auto).
pub fn method(args: &SimArgs, scene: &SystemScene) -> anyhow::Result<OdeMethod> {
    let kind = match args.method.unwrap_or(MethodArg::Auto) {
        MethodArg::Auto => OdeKind::Auto,
        MethodArg::Adaptive => OdeKind::Adaptive,
        MethodArg::Radau => OdeKind::Radau,
        MethodArg::Rk4 => OdeKind::Rk4,
        MethodArg::Verlet => OdeKind::Verlet,
        MethodArg::Verlet4 => OdeKind::Verlet4,
        m @ (MethodArg::Exact | MethodArg::Splitting | MethodArg::Splitting4) => bail!(
            "--method {}: scene {} is a system, which takes auto, adaptive, radau or rk4",
            m.name(),
            scene.id
        ),
    };
    let setting = match (kind.fixed_step(), args.tol, args.dt) {
        (true, Some(_), _) => bail!(
            "--tol: {} takes a step (--dt), not a tolerance",
            kind.name()
        ),
        (true, None, dt) => dt,
        (_, _, Some(_)) => bail!(
            "--dt: only rk4, verlet and verlet4 take a step; {} takes --tol",
            kind.name()
        ),
        (_, tol, None) => tol,
    };
    match setting {
        None => Ok(OdeMethod::default_for(kind, scene.duration)),
        Some(s) => OdeMethod::with_setting(kind, s).map_err(|e| anyhow!("{e}")),
    }
}

/// The scene with `--atol` in place of its own `atol`: one number, or
/// `NAME=VALUE` pairs naming variables, each value positive and finite.
pub fn with_atol(args: &SimArgs, scene: &SystemScene) -> anyhow::Result<SystemScene> {
    let mut scene = scene.clone();
    let Some(text) = &args.atol else {
        return Ok(scene);
    };
    let value = |v: &str| -> anyhow::Result<f64> {
        match v.trim().parse::<f64>() {
            Ok(a) if SceneAtol::allowed(a) => Ok(a),
            _ => bail!(
                "--atol: `{}` is not an absolute tolerance (a positive, finite number of at least 1e-300)",
                crate::text::safe::one_line(v)
            ),
        }
    };
    if !text.contains('=') {
        scene.atol = Some(SceneAtol::All(value(text)?));
        return Ok(scene);
    }
    let mut each: Vec<(String, f64)> = match scene.atol.take() {
        Some(SceneAtol::Each(each)) => each,
        _ => Vec::new(),
    };
    for pair in text.split(',') {
        let Some((name, v)) = pair.split_once('=') else {
            bail!(
                "--atol: `{}` is not NAME=VALUE (write y2=1e-20,y3=1e-20, or one number for every variable)",
                crate::text::safe::one_line(pair)
            );
        };
        let name = name.trim();
        if !scene.variables.iter().any(|x| x == name) {
            bail!(
                "--atol: `{}` is not a variable of scene {} (its variables: {})",
                crate::text::safe::one_line(name),
                scene.id,
                scene.variables.join(", ")
            );
        }
        let v = value(v)?;
        each.retain(|(n, _)| n != name);
        each.push((name.to_string(), v));
    }
    scene.atol = Some(SceneAtol::Each(each));
    Ok(scene)
}

pub fn run(args: &SimArgs, deck: &Deck, scene: &SystemScene) -> anyhow::Result<ExitCode> {
    let method = method(args, scene)?;
    if let Some(samples) = args.samples {
        let samples = crate::cmd::sim_samples::check_samples(samples, scene.duration)?;
        return write_samples(scene, method, samples, args.format, args.stats);
    }
    if !args.measure.is_empty() {
        return measures(scene, method, &args.measure);
    }
    let (text, wrong) = report(deck, scene, method)?;
    crate::out!("{text}")?;
    // An answer the run contradicts is an error in the deck, as `check`
    // reports it.
    Ok(if wrong {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// `--measure` on a system: each value on its own line, nothing else.
fn measures(
    scene: &SystemScene,
    method: OdeMethod,
    written: &[String],
) -> anyhow::Result<ExitCode> {
    let mut list = Vec::new();
    for text in written {
        let m = Measure::parse(text).map_err(|e| anyhow!("--measure {e}"))?;
        let Measure::Of(_, name) = m else {
            bail!(
                "--measure `{m}` is a rigid-body measure; scene {} is a system",
                scene.id
            );
        };
        let known = scene.variables.iter().any(|v| v == name.as_str())
            || scene.observables.iter().any(|(o, _)| o == name.as_str());
        if !known {
            let names: Vec<&str> = scene
                .variables
                .iter()
                .map(String::as_str)
                .chain(scene.observables.iter().map(|(o, _)| o.as_str()))
                .collect();
            bail!(
                "--measure `{m}`: `{name}` is not a variable or observable of scene {} ({})",
                scene.id,
                names.join(", ")
            );
        }
        list.push(m);
    }
    let values = measure_system_noting(scene, method, &list).map_err(|e| anyhow!("{e}"))?;
    let mut out = String::new();
    let mut notes = Vec::new();
    for (v, caveat) in values {
        let v = v.map_err(|e| anyhow!("{e}"))?;
        let _ = writeln!(out, "{}", Num(v));
        notes.extend(caveat);
    }
    crate::out!("{out}")?;
    for note in notes {
        crate::errln!("warning: {note}");
    }
    Ok(ExitCode::SUCCESS)
}

fn write_samples(
    scene: &SystemScene,
    method: OdeMethod,
    samples: usize,
    format: SimFormat,
    show_stats: bool,
) -> anyhow::Result<ExitCode> {
    // The run measures and the app play, computing every observable: a
    // row is written only where the state and every observable are
    // finite, and the run stops with the cause where one is not.
    let plan = SystemPlan {
        observables: vec![true; scene.observables.len()],
        metered: Vec::new(),
        periods: Vec::new(),
        ..SystemPlan::for_scene(scene, method, &[]).headless()
    };
    let mut run = SystemRun::with_plan(scene, method, plan).map_err(|e| anyhow!("{e}"))?;
    let system = System::compile(scene, false).map_err(|e| anyhow!("{e}"))?;
    let columns: Vec<&str> = std::iter::once("t")
        .chain(scene.variables.iter().map(String::as_str))
        .chain(scene.observables.iter().map(|(o, _)| o.as_str()))
        .collect();
    let mut out = crate::cmd::output::stdout();
    match format {
        SimFormat::Csv => writeln!(out, "{}", columns.join(","))?,
        SimFormat::Json => write!(
            out,
            "{{\"scene\":{},\"method\":{},\"setting\":{},\"t_end\":{},\"samples\":[",
            serde_json::to_string(&scene.id)?,
            serde_json::to_string(method.kind.name())?,
            serde_json::to_string(&method.setting)?,
            serde_json::to_string(&scene.duration)?
        )?,
    }
    let rows = write_rows(
        scene, &mut run, &system, &columns, samples, format, &mut out,
    );
    let work = run.work();
    let stats = Stats {
        steps: work.steps,
        rejected: work.rejected,
        rhs_evals: work.rhs_evals,
        jacobian_evals: work.jac_evals,
        lu_decompositions: work.lu_decomps,
        lu: work.lu.map(|k| k.name()),
        stiff_from: run.diagnostics().stiff_at,
        conserved: (run.conserved_drift().into_iter())
            .map(|d| Conserved {
                name: d.name,
                start: d.start,
                max_change: d.change,
                max_drift: d.relative,
            })
            .collect(),
        fixed_sums: if method.kind.holds_fixed_sums() {
            (system.fixed_sums(0.0, &scene.initial).iter())
                .map(|c| crate::sim::solvers::ode::fixed::show(c, &scene.variables))
                .map(|s| crate::text::safe::one_line(&s).into_owned())
                .collect()
        } else {
            Vec::new()
        },
    };
    if format == SimFormat::Json {
        let why = rows.as_ref().err().map(|e| e.to_string());
        crate::cmd::sim_samples::close_json(&mut out, why.as_deref(), &stats)?;
    } else if show_stats {
        crate::errln!("{}", stats.line());
    }
    out.flush()?;
    rows.map(|()| ExitCode::SUCCESS)
}

/// The rows of [`write_samples`]; an error ends them where the run stops.
fn write_rows(
    scene: &SystemScene,
    run: &mut SystemRun,
    system: &System,
    columns: &[&str],
    samples: usize,
    format: SimFormat,
    out: &mut impl Write,
) -> anyhow::Result<()> {
    let last = samples - 1;
    let mut observables = vec![0.0; system.observable_count()];
    // Each row waits for the next sample: a run that then blows up may
    // have reached the row only by a step across the singularity
    // (x' = x² printed 1.05e9 at t = 1, where the solution is infinite).
    let mut pending: Option<(f64, String)> = None;
    let mut written = 0;
    let mut flush = |row: String, out: &mut dyn Write| -> anyhow::Result<()> {
        match format {
            SimFormat::Csv => writeln!(out, "{row}")?,
            SimFormat::Json => {
                let sep = if written > 0 { "," } else { "" };
                write!(out, "{sep}\n{{{row}}}")?;
            }
        }
        written += 1;
        Ok(())
    };
    for k in 0..samples {
        let t = if k == last {
            scene.duration
        } else {
            k as f64 * scene.duration / last as f64
        };
        run.advance_to(t);
        if let Some(e) = run.error() {
            let why = describe(e);
            if let Some((t_row, row)) = pending.take() {
                // Within four steps of a blow-up (or a millionth of the
                // time, at the singularity) no method vouches for a value.
                if let RunError::Ode(SolveError::BlowUp { t: t_b }) = e {
                    let step = run.last_step().map_or(0.0, |(t0, t1)| t1 - t0);
                    let near = (4.0 * step).max(1e-6 * t_b.abs().max(1.0));
                    if t_b - t_row <= near {
                        bail!(
                            "{why} (the run stops here; the row at t = {} is not printed: it lies within {} of the blow-up, where no step can vouch for a value)",
                            Num(t_row),
                            num::sig(t_b - t_row, 2)
                        );
                    }
                }
                flush(row, out)?;
            }
            bail!("{why} (the run stops here)");
        }
        let y = run.state().to_vec();
        system.observables_into(t, &y, &mut observables);
        if observables.iter().any(|v| !v.is_finite()) {
            if let Some((_, row)) = pending.take() {
                flush(row, out)?;
            }
            let why = system
                .observable_fault(t, &y)
                .map(|f| f.describe(scene, t))
                .unwrap_or_else(|| format!("an observable is not finite at t = {}", Num(t)));
            bail!("{why} (the run stops here)");
        }
        let mut row = Vec::with_capacity(columns.len());
        row.push(t);
        row.extend_from_slice(&y);
        row.extend_from_slice(&observables);
        let text = match format {
            SimFormat::Csv => {
                let cells: Vec<String> = row.iter().map(|v| num::show(*v)).collect();
                cells.join(",")
            }
            SimFormat::Json => {
                let mut cells = Vec::with_capacity(row.len());
                for (c, v) in columns.iter().zip(&row) {
                    cells.push(format!(
                        "{}:{}",
                        serde_json::to_string(c)?,
                        serde_json::to_string(v)?
                    ));
                }
                cells.join(",")
            }
        };
        if let Some((_, row)) = pending.replace((t, text)) {
            flush(row, out)?;
        }
    }
    if let Some((_, row)) = pending.take() {
        flush(row, out)?;
    }
    Ok(())
}

/// The measures the scene's prompts use, in order of first use.
pub fn prompt_measures(deck: &Deck, scene_id: &str) -> Vec<Measure> {
    crate::predict::audit::prompt_measures(deck, scene_id)
}

/// The scene's measurements and each prompt's verdict, as `check` judges
/// them (the same run, and the same run again 1.5× as long); whether any
/// prompt's answer is wrong.
fn report(deck: &Deck, scene: &SystemScene, method: OdeMethod) -> anyhow::Result<(String, bool)> {
    let measures = prompt_measures(deck, &scene.id);
    let run = Run::system(scene, method, &measures).map_err(|e| anyhow!("{}", describe(&e)))?;
    let mut out = String::new();
    let state: Vec<String> = scene
        .variables
        .iter()
        .zip(&scene.initial)
        .map(|(v, x)| format!("{v} = {}", Num(*x)))
        .collect();
    let _ = writeln!(
        out,
        "scene {} ({}): system of {}, {}, {} {}, method {}",
        scene.id,
        deck.id,
        crate::text::plural(scene.variables.len(), "variable", "variables"),
        state.join(", "),
        Num(scene.duration),
        scene.time_unit,
        method.label()
    );
    let _ = writeln!(out, "measurements:");
    if measures.is_empty() {
        let _ = writeln!(out, "  (no prompt measures this scene)");
    }
    for m in &measures {
        let name = m.to_string();
        match (
            run.measured.get(*m),
            run.missing.iter().find(|(x, _)| x == m),
        ) {
            (Some(v), _) => {
                let _ = writeln!(out, "  {name:<18} {}", crate::cmd::sim_scene::number(v));
            }
            (None, why) => {
                let why = why.map_or("not measured", |(_, w)| w.as_str());
                let _ = writeln!(out, "  {name:<18} - ({why})");
            }
        }
    }
    let prompts: Vec<&Prompt> = deck
        .prompts
        .iter()
        .filter(|p| p.scene == scene.id)
        .collect();
    if !prompts.is_empty() {
        let _ = writeln!(out, "prompts:");
    }
    let mut wrong = false;
    for p in prompts {
        let problem = audit_run(p, &run);
        let slips = audit_slips(p, &run);
        wrong |= problem.is_some() || !slips.is_empty();
        let ok = problem.is_none() && slips.is_empty();
        let _ = writeln!(
            out,
            "  {}",
            crate::cmd::sim_scene::prompt_line(p, &run.measured, ok)
        );
        if let Some(problem) = problem {
            let _ = writeln!(out, "    {}", problem.message);
        }
        for (_, message) in slips {
            let _ = writeln!(out, "    {message}");
        }
    }
    Ok((out, wrong))
}
