//! `flipcard sim --scene ID [--deck PATH]`: one scene's measurements, each
//! with its formula value, and the verdict the simulation gives on each
//! prompt that uses the scene.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};

use crate::cmd::args::{Cli, SimArgs};
use crate::deck::{Answer, Deck, Prompt, Scene, load_paths};
use crate::predict::audit::audit;
use crate::predict::{Prediction, verdict};
use crate::sim::scene::measure::{Measurements, formula_name};
use crate::sim::scene::measure_scene;
use crate::sim::solvers::registry::method;
use crate::text::num::Num;
use crate::text::plural;

/// The decks to read: `--deck PATH`, else the global `--decks DIR`, else
/// the bundled ones.
pub(super) fn deck_path(cli: &Cli, args: &SimArgs) -> PathBuf {
    args.deck
        .clone()
        .or_else(|| cli.decks.clone())
        .unwrap_or_else(crate::cmd::paths::bundled_decks)
}

fn load(paths: &[PathBuf]) -> anyhow::Result<Vec<Deck>> {
    for p in paths {
        if !p.exists() {
            bail!("{}: no such file or directory", p.display());
        }
    }
    let loaded = load_paths(paths);
    if loaded.errors() > 0 {
        crate::errln!("{}", loaded.render_all());
        bail!(
            "{} in the decks (run `flipcard check` for details)",
            plural(loaded.errors(), "error", "errors")
        );
    }
    Ok(loaded.decks)
}

/// `1, 2, 3` with each number in its shortest round-trip spelling.
fn triple(v: &[f64; 3]) -> String {
    crate::text::num::triple(v, ", ")
}

/// Six significant digits without trailing zeros, integers plainly.
pub fn number(v: f64) -> String {
    crate::text::num::rounded(v, 6)
}

/// `flipcard sim --scene ID`: runs the scene and prints its measurements,
/// then each prompt on it with the verdict its expected answer gets.
pub fn scene(cli: &Cli, args: &SimArgs, id: &str) -> anyhow::Result<ExitCode> {
    let decks = load(&[deck_path(cli, args)])?;
    let Some((deck, scene)) = decks.iter().find_map(|d| d.scene(id).map(|s| (d, s))) else {
        let known: Vec<&str> = decks
            .iter()
            .flat_map(|d| d.scenes.iter().map(|s| s.id.as_str()))
            .collect();
        bail!("no scene {id:?} (scenes: {})", known.join(", "));
    };
    let body = crate::sim::Body::new(scene.inertia)?;
    let omega0 = crate::sim::rigid::model::omega(scene.omega)?;
    let m = method(args.method.into(), args.tol, args.dt, &body, &omega0)?;
    let measured =
        measure_scene(scene, m).with_context(|| format!("scene {id} with {}", m.name()))?;
    crate::out!("{}", report(deck, scene, &measured, m.name()))?;
    // An answer the run contradicts is an error in the deck, as `check`
    // reports it.
    let wrong = deck
        .prompts
        .iter()
        .filter(|p| p.scene == scene.id)
        .any(|p| audit(p, scene, &measured).is_some());
    Ok(if wrong {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
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
        Num(scene.duration)
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
        let problem = audit(p, scene, m);
        let _ = writeln!(out, "  {}", prompt_line(p, m, problem.is_none()));
        if let Some(problem) = problem {
            let _ = writeln!(out, "    {}", problem.message);
        }
    }
    out
}

/// `middle-axis: expected flips: holds (flips = 3: flips > 0)`.
/// `ok`: the run agrees with the expected answer (see [`audit`]).
fn prompt_line(p: &Prompt, m: &Measurements, ok: bool) -> String {
    let Some(prediction) = Prediction::expected(p) else {
        return format!("{}: expected answer names no choice", p.id);
    };
    let v = verdict(p, m, prediction);
    let status = if ok { "ok" } else { "WRONG" };
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
                        Num(c.when.value),
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
