//! `flipcard sim`: one trajectory, sampled at N evenly spaced times, as CSV
//! or JSON. Every float is printed in shortest round-trip form (with an
//! exponent when very large or small, see [`crate::text::num`]), so reading the
//! output back gives the computed values bit for bit.

use std::io::Write;
use std::process::ExitCode;

use anyhow::{Context, anyhow, bail};

use crate::cmd::args::{Cli, SimArgs};
use crate::cmd::sim_samples::{Request, write_samples};
use crate::cmd::{sim_scene, sim_system};
use crate::sim::Needs;
use crate::sim::rigid::model::{self, Body};
use crate::sim::solvers::registry;
use crate::text::num::{self, Num};
use crate::text::plural;

pub fn run(cli: &Cli, args: &SimArgs) -> anyhow::Result<ExitCode> {
    if args.list {
        return list(cli, args);
    }
    if let Some(id) = &args.scene {
        let decks = sim_scene::load(cli, args)?;
        if let Some(prompt) = &args.prompt {
            return crate::cmd::sim_variant::run(args, &decks, id, prompt);
        }
        if let Some((deck, system)) = decks.iter().find_map(|d| d.system(id).map(|s| (d, s))) {
            let system = sim_system::with_atol(args, system)?;
            return sim_system::run(args, deck, &system);
        }
        if args.atol.is_some() {
            anyhow::bail!(
                "--atol: scene {id} is a rigid body; only a system scene takes an absolute tolerance"
            );
        }
        return sim_scene::scene(args, &decks, id);
    }
    let request = request(args)?;
    let mut solver = registry::make(
        request.method,
        request.body,
        request.omega0,
        Needs { orientation: true },
    )?;
    solver.plan(request.t_end)?;
    let mut out = crate::cmd::output::stdout();
    write_samples(&request, solver.as_mut(), args.format, args.stats, &mut out)?;
    Ok(ExitCode::SUCCESS)
}

/// `sim --list`: one line per scene of the decks (`--deck PATH`, else
/// `--decks`, else the bundled ones): id, deck, setup, panels and title.
fn list(cli: &Cli, args: &SimArgs) -> anyhow::Result<ExitCode> {
    let (loaded, label) = sim_scene::decks_for(cli, args)?;
    if loaded.decks.is_empty() && loaded.errors() > 0 {
        let (place, check) = match &label {
            Some(l) => (format!(" in {l}"), format!("flipcard check {l}")),
            None => (String::new(), "flipcard check".to_string()),
        };
        bail!(
            "no deck{place} loads ({}; run `{check}`)",
            plural(loaded.errors(), "error", "errors"),
        );
    }
    let mut out = crate::cmd::output::stdout();
    for deck in &loaded.decks {
        let lang = deck.languages.first().map_or("en", String::as_str);
        for scene in &deck.scenes {
            writeln!(out, "{}", scene_line(deck, scene, lang))?;
        }
        for system in &deck.systems {
            writeln!(out, "{}", system_line(deck, system, lang))?;
        }
    }
    out.flush()?;
    if loaded.errors() > 0 {
        crate::errln!(
            "flipcard: warning: {} in the decks, some scenes may be missing (run `flipcard check`)",
            plural(loaded.errors(), "error", "errors")
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn scene_line(deck: &crate::deck::Deck, scene: &crate::deck::Scene, lang: &str) -> String {
    let triple = |v: [f64; 3]| num::triple(&v, ",");
    let shows: Vec<&str> = scene.show.iter().map(|p| p.name()).collect();
    let title = scene.title.as_ref().map_or("", |t| t.get(lang));
    format!(
        "{}\t{}\tinertia={}\tomega={}\tduration={} {}\tshow={}\t{}",
        scene.id,
        deck.id,
        triple(scene.inertia),
        triple(scene.omega),
        Num(scene.duration),
        scene.time_unit,
        shows.join(","),
        title
    )
}

fn system_line(deck: &crate::deck::Deck, s: &crate::deck::SystemScene, lang: &str) -> String {
    let shows: Vec<&str> = s.show.iter().map(|p| p.name()).collect();
    let initial: Vec<String> = s.initial.iter().map(|v| num::show(*v)).collect();
    format!(
        "{}\t{}\tvariables={}\tinitial={}\tduration={} {}\tshow={}\t{}",
        s.id,
        deck.id,
        s.variables.join(","),
        initial.join(","),
        Num(s.duration),
        s.time_unit,
        shows.join(","),
        s.title.as_ref().map_or("", |t| t.get(lang))
    )
}

/// The request `sim --inertia … --omega … --t-end …` makes.
fn request(args: &SimArgs) -> anyhow::Result<Request> {
    let inertia = triple("--inertia", args.inertia.as_deref())?;
    let omega = triple("--omega", args.omega.as_deref())?;
    let t_end = number("--t-end", args.t_end.as_deref())?;
    let body = Body::new(inertia).context("--inertia")?;
    let omega0 = model::omega(omega).context("--omega")?;
    if !(t_end.is_finite() && t_end > 0.0) {
        bail!(
            "--t-end: must be a positive finite time, got {}",
            Num(t_end)
        );
    }
    Request::new(args, body, omega0, t_end)
}

fn number(flag: &str, text: Option<&str>) -> anyhow::Result<f64> {
    let text = text.ok_or_else(|| anyhow!("{flag} is required (or use --scene ID)"))?;
    parse(flag, text)
}

fn parse(flag: &str, text: &str) -> anyhow::Result<f64> {
    text.trim()
        .parse::<f64>()
        .map_err(|_| anyhow!("{flag}: '{}' is not a number", text.trim()))
}

fn triple(flag: &str, text: Option<&str>) -> anyhow::Result<[f64; 3]> {
    let text = text.ok_or_else(|| anyhow!("{flag} is required (or use --scene ID)"))?;
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 3 {
        bail!(
            "{flag}: expected 3 comma-separated numbers, got {} in '{text}'",
            parts.len()
        );
    }
    let mut values = [0.0; 3];
    for (value, part) in values.iter_mut().zip(&parts) {
        *value = parse(flag, part)?;
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triples_parse_and_explain_what_is_wrong() {
        assert_eq!(
            triple("--inertia", Some("1, 2,3")).unwrap(),
            [1.0, 2.0, 3.0]
        );
        let err = triple("--inertia", Some("1,2")).unwrap_err().to_string();
        assert!(err.contains("expected 3"), "{err}");
        let err = triple("--omega", Some("1,x,3")).unwrap_err().to_string();
        assert!(err.contains("'x' is not a number"), "{err}");
        let err = triple("--omega", None).unwrap_err().to_string();
        assert!(err.contains("required"), "{err}");
    }
}
