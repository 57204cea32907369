//! `flipcard sim --list` and `flipcard sim --scene ID [--deck PATH]`: the
//! scenes of the decks, and one scene's measurements with the verdict the
//! simulation gives on each prompt that uses it.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};

use super::measure::{Measurements, Prediction, formula_name, verdict};
use super::run::{Kind, method};
use super::scene::measure_scene;
use crate::cli::{Cli, MethodArg, SimArgs};
use crate::deck::{Answer, Deck, Prompt, Scene, load_paths};

/// The decks to read: `--deck PATH`, else the global `--decks DIR`, else
/// the bundled ones.
fn deck_paths(cli: &Cli, args: &SimArgs) -> Vec<PathBuf> {
    let path = args
        .deck
        .clone()
        .or_else(|| cli.decks.clone())
        .unwrap_or_else(crate::paths::bundled_decks);
    vec![path]
}

fn load(paths: &[PathBuf]) -> anyhow::Result<Vec<Deck>> {
    for p in paths {
        if !p.exists() {
            bail!("{}: no such file or directory", p.display());
        }
    }
    let loaded = load_paths(paths);
    if loaded.errors() > 0 {
        eprintln!("{}", loaded.render_all());
        bail!(
            "{} errors in the decks (run `flipcard check` for details)",
            loaded.errors()
        );
    }
    Ok(loaded.decks)
}

/// `1, 2, 3` with each number in its shortest round-trip spelling.
fn triple(v: &[f64; 3]) -> String {
    format!("{}, {}, {}", v[0], v[1], v[2])
}

/// `flipcard sim --list`: id, deck, inertia, omega, duration, show.
pub fn list(cli: &Cli, args: &SimArgs) -> anyhow::Result<ExitCode> {
    let decks = load(&deck_paths(cli, args))?;
    let mut rows = vec![[
        "id".to_string(),
        "deck".to_string(),
        "inertia".to_string(),
        "omega".to_string(),
        "duration".to_string(),
        "show".to_string(),
    ]];
    for deck in &decks {
        for s in &deck.scenes {
            rows.push([
                s.id.clone(),
                deck.id.clone(),
                triple(&s.inertia),
                triple(&s.omega),
                format!("{} {}", s.duration, s.time_unit),
                s.show
                    .iter()
                    .map(|p| p.name())
                    .collect::<Vec<_>>()
                    .join(","),
            ]);
        }
    }
    let mut widths = [0usize; 6];
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    for row in &rows {
        let mut line = String::new();
        for (k, (w, cell)) in widths.iter().zip(row).enumerate() {
            if k + 1 == row.len() {
                line.push_str(cell);
            } else {
                let pad = w - cell.chars().count();
                let _ = write!(line, "{cell}{}  ", " ".repeat(pad));
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    print!("{out}");
    Ok(ExitCode::SUCCESS)
}

fn kind(m: MethodArg) -> Kind {
    match m {
        MethodArg::Exact => Kind::Exact,
        MethodArg::Adaptive => Kind::Adaptive,
        MethodArg::Splitting => Kind::Splitting,
        MethodArg::Splitting4 => Kind::Splitting4,
        MethodArg::Rk4 => Kind::Rk4,
    }
}

/// Six significant digits without trailing zeros, integers plainly.
pub fn number(v: f64) -> String {
    if v == v.trunc() && v.abs() < 1e15 {
        format!("{v:.0}")
    } else if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) {
        format!("{v:.5e}")
    } else {
        let digits = (5 - v.abs().log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// `flipcard sim --scene ID`: runs the scene and prints its measurements,
/// then each prompt on it with the verdict its expected answer gets.
pub fn scene(cli: &Cli, args: &SimArgs, id: &str) -> anyhow::Result<ExitCode> {
    let decks = load(&deck_paths(cli, args))?;
    let Some((deck, scene)) = decks.iter().find_map(|d| d.scene(id).map(|s| (d, s))) else {
        let known: Vec<&str> = decks
            .iter()
            .flat_map(|d| d.scenes.iter().map(|s| s.id.as_str()))
            .collect();
        bail!("no scene {id:?} (scenes: {})", known.join(", "));
    };
    let body = super::Body::new(scene.inertia)?;
    let omega0 = super::model::omega(scene.omega)?;
    let m = method(kind(args.method), args.tol, args.dt, &body, &omega0)?;
    let measured =
        measure_scene(scene, m).with_context(|| format!("scene {id} with {}", m.name()))?;
    print!("{}", report(deck, scene, &measured, m.name()));
    Ok(ExitCode::SUCCESS)
}

fn report(deck: &Deck, scene: &Scene, m: &Measurements, method: &str) -> String {
    let mut out = String::new();
    let unit = &scene.time_unit;
    let _ = writeln!(
        out,
        "scene {} ({}): I = ({}), ω₀ = ({}), {} {unit}, method {method}",
        scene.id,
        deck.id,
        triple(&scene.inertia),
        triple(&scene.omega),
        scene.duration
    );
    let _ = writeln!(out, "measurements:");
    for r in m.readings() {
        let name = r.measure.name();
        let value = number(r.value);
        match r.formula {
            Some(f) => {
                let _ = writeln!(
                    out,
                    "  {name:<18} {value:<14} formula {} = {}",
                    formula_name(r.measure),
                    number(f)
                );
            }
            None => {
                let _ = writeln!(out, "  {name:<18} {value}");
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
    for p in prompts {
        let _ = writeln!(out, "  {}", prompt_line(p, m));
    }
    out
}

/// `middle-axis: expected flips: holds (flips = 3: flips > 0)`.
fn prompt_line(p: &Prompt, m: &Measurements) -> String {
    let Some(prediction) = Prediction::expected(p) else {
        return format!("{}: expected answer names no choice", p.id);
    };
    let v = verdict(p, m, prediction);
    let status = if v.correct { "ok" } else { "WRONG" };
    match &p.answer {
        Answer::Choice { choices, expected } => {
            let holding: Vec<String> = v
                .holding
                .iter()
                .map(|&i| {
                    let c = &choices[i];
                    format!(
                        "{} ({} = {}: {} {} {})",
                        c.id,
                        c.when.measure.name(),
                        m.get(c.when.measure).map_or("-".into(), number),
                        c.when.measure.name(),
                        c.when.op.as_str(),
                        c.when.value
                    )
                })
                .collect();
            let holds = if holding.is_empty() {
                "none".to_string()
            } else {
                holding.join(", ")
            };
            format!("{}: expected {expected}: {status}; holds: {holds}", p.id)
        }
        Answer::Number {
            measure,
            expected,
            unit,
            ..
        } => {
            let measured = m.get(*measure).map_or("-".into(), number);
            format!(
                "{}: expected {} = {} {unit}: {status}; measured {measured} {unit}",
                p.id,
                measure.name(),
                number(*expected)
            )
        }
    }
}
