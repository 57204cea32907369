//! `flipcard sim --scene ID [--deck PATH]`: one scene's measurements, each
//! with its formula value, and the verdict the simulation gives on each
//! prompt that uses the scene.

use std::fmt::Write as _;
use std::process::ExitCode;

use anyhow::{Context, bail};

use crate::cmd::args::{Cli, SimArgs};
use crate::cmd::sim_samples::{Request, write_samples};
use crate::deck::{Answer, Deck, Loaded, Measure, Prompt, Scene, load_paths};
use crate::predict::audit::{Run, audit, audit_slips};
use crate::predict::{Prediction, verdict};
use crate::sim::scene::measure::{Measurements, formula_name};
use crate::sim::scene::measure_scene;
use crate::sim::solvers::registry::method;
use crate::text::num::Num;
use crate::text::plural;

/// The decks to read: `--deck PATH` alone, else every deck source. The
/// label names them in messages.
pub(super) fn decks_for(cli: &Cli, args: &SimArgs) -> anyhow::Result<(Loaded, Option<String>)> {
    match &args.deck {
        Some(p) => {
            if !p.exists() {
                bail!("{}: no such file or directory", p.display());
            }
            Ok((
                load_paths(std::slice::from_ref(p)),
                Some(p.display().to_string()),
            ))
        }
        None => Ok((crate::cmd::library::load(cli).loaded, None)),
    }
}

/// The decks of [`decks_for`], refused when any has an error.
pub(super) fn load(cli: &Cli, args: &SimArgs) -> anyhow::Result<Vec<Deck>> {
    let (loaded, _) = decks_for(cli, args)?;
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

/// `flipcard sim --scene ID` of a rigid scene among `decks` (a system
/// scene's is [`crate::cmd::sim_system::run`]): runs the scene and prints
/// its measurements, then each prompt on it with the verdict its expected
/// answer gets.
pub fn scene(args: &SimArgs, decks: &[Deck], id: &str) -> anyhow::Result<ExitCode> {
    let Some((deck, scene)) = decks.iter().find_map(|d| d.scene(id).map(|s| (d, s))) else {
        let known: Vec<&str> = decks
            .iter()
            .flat_map(|d| {
                d.scenes
                    .iter()
                    .map(|s| s.id.as_str())
                    .chain(d.systems.iter().map(|s| s.id.as_str()))
            })
            .collect();
        bail!("no scene {id:?} (scenes: {})", known.join(", "));
    };
    let body = crate::sim::Body::new(scene.inertia)?;
    let omega0 = crate::sim::rigid::model::omega(scene.omega)?;
    if args.samples.is_some() {
        // The scene's run, sampled as `sim --inertia … --omega …` samples.
        let request = Request::new(args, body, omega0, scene.duration)?;
        let mut solver = crate::sim::make(
            request.method,
            request.body,
            request.omega0,
            crate::sim::Needs { orientation: true },
        )?;
        solver.plan(request.t_end)?;
        let mut out = crate::cmd::output::stdout();
        write_samples(&request, solver.as_mut(), args.format, args.stats, &mut out)?;
        return Ok(ExitCode::SUCCESS);
    }
    let kind =
        crate::sim::Kind::try_from(args.method.unwrap_or(crate::cmd::args::MethodArg::Exact))?;
    let m = method(kind, args.tol, args.dt, &body, &omega0)?;
    if !args.measure.is_empty() {
        let mut wanted = Vec::new();
        for text in &args.measure {
            let measure = Measure::parse(text).map_err(|e| anyhow::anyhow!("--measure {e}"))?;
            if measure.is_system() {
                bail!("--measure `{measure}` is a system measure; scene {id} is a rigid body");
            }
            wanted.push(measure);
        }
        let measured =
            measure_scene(scene, m).with_context(|| format!("scene {id} with {}", m.name()))?;
        let mut out = String::new();
        for w in wanted {
            let v = measured
                .get(w)
                .ok_or_else(|| anyhow::anyhow!("{w}: the run of scene {id} does not measure it (it does not apply to this motion)"))?;
            let _ = writeln!(out, "{}", Num(v));
        }
        crate::out!("{out}")?;
        return Ok(ExitCode::SUCCESS);
    }
    let measured =
        measure_scene(scene, m).with_context(|| format!("scene {id} with {}", m.name()))?;
    crate::out!("{}", report(deck, scene, &measured, m.name()))?;
    // An answer the run contradicts is an error in the deck, as `check`
    // reports it.
    let wrong = deck
        .prompts
        .iter()
        .filter(|p| p.scene == scene.id)
        .any(|p| {
            audit(p, scene, &measured).is_some()
                || !audit_slips(p, &Run::rigid(scene, measured.clone())).is_empty()
        });
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
        let slips = audit_slips(p, &Run::rigid(scene, m.clone()));
        let ok = problem.is_none() && slips.is_empty();
        let _ = writeln!(out, "  {}", prompt_line(p, m, ok));
        if let Some(problem) = problem {
            let _ = writeln!(out, "    {}", problem.message);
        }
        for (_, message) in slips {
            let _ = writeln!(out, "    {message}");
        }
    }
    out
}

/// `middle-axis: expected flips: holds (flips = 3: flips > 0)`.
/// `ok`: the run agrees with the expected answer (see [`audit`]).
pub(super) fn prompt_line(p: &Prompt, m: &Measurements, ok: bool) -> String {
    if let Answer::Formula(key) = &p.answer {
        // No run decides a formula: `flipcard grade` checks answers to it.
        return format!(
            "{}: expected formula {} (graded by `flipcard grade`, not by the run)",
            p.id,
            crate::text::safe::one_line(&key.expected)
        );
    }
    let Some(prediction) = Prediction::expected(p) else {
        return format!("{}: expected answer names no choice", p.id);
    };
    let v = verdict(p, m, prediction);
    let status = if ok { "ok" } else { "WRONG" };
    match &p.answer {
        Answer::Formula(_) => String::new(),
        Answer::Choice { choices, expected } => {
            let holding: Vec<String> = v
                .holding
                .iter()
                .map(|&i| {
                    let c = &choices[i];
                    let values: Vec<String> = c
                        .when
                        .measures()
                        .into_iter()
                        .map(|x| format!("{x} = {}", m.get(x).map_or("-".into(), number)))
                        .collect();
                    format!("{} ({}: {})", c.id, values.join(", "), c.when)
                })
                .collect();
            let holds = if holding.is_empty() {
                "none".to_string()
            } else {
                holding.join(", ")
            };
            let expected = expected.as_deref().unwrap_or("(the run decides)");
            format!("{}: expected {expected}: {status}; holds: {holds}", p.id)
        }
        Answer::Number {
            measure,
            expected,
            unit,
            slips,
            ..
        } => {
            let measured = m.get(*measure).map_or("-".into(), number);
            // Each known slip's value on this run, as the verdict takes it.
            let slips: Vec<String> = slips
                .iter()
                .map(|s| {
                    let value = m
                        .get(*measure)
                        .and_then(|r| s.value_for(r))
                        .map_or("-".into(), number);
                    format!("{} = {value} {unit}", s.value)
                })
                .collect();
            let slips = if slips.is_empty() {
                String::new()
            } else {
                format!("; slips: {}", slips.join(", "))
            };
            format!(
                "{}: expected {} = {} {unit}: {status}; measured {measured} {unit}{slips}",
                p.id,
                measure,
                expected.map_or_else(|| measured.clone(), number)
            )
        }
    }
}
