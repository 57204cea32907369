//! A scene's knobs and its `explore` measure (issue 24 §1), checked against
//! the scene they turn: each knob names a parameter or `initial.VAR` of a
//! system, `inertia[i]` or `omega[i]` of a rigid body; its range is finite
//! and ordered, its step positive, its scale finite and not zero, the
//! scene's own value inside the range; and the scene built at the range's
//! ends and middle passes the simulator's own acceptance (`check_scene` for
//! a rigid body; compiling, the cost limit and a finite start for a
//! system), so no value a learner can reach is one the simulator refuses.

use crate::deck::raw::{Num, RawKnob, RawScene, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use flipcard_sim::scene::knob::{self, Explore, Knob, Target};
use flipcard_sim::scene::spec::{Panel, Scene, SystemScene};
use flipcard_sim::scene::system::check_cost;
use flipcard_sim::solvers::ode::OdeSystem;
use flipcard_sim::system::System;
use flipcard_text::num::Num as Shown;

use super::answer::{self, SceneKind};
use super::text::{self, Langs};

/// The scene a knob turns, as validated.
#[derive(Clone, Copy)]
pub enum Turned<'a> {
    Rigid(&'a Scene),
    System(&'a SystemScene),
}

impl Turned<'_> {
    pub(super) fn target(&self, name: &str) -> Option<Target> {
        match self {
            Turned::Rigid(_) => Target::rigid(name),
            Turned::System(s) => Target::system(s, name),
        }
    }

    fn own(&self, target: &Target) -> Option<f64> {
        match self {
            Turned::Rigid(s) => knob::rigid_value(s, target),
            Turned::System(s) => knob::system_value(s, target),
        }
    }

    /// The names a knob of this scene may take, for a hint.
    pub(super) fn names(&self) -> Vec<String> {
        match self {
            Turned::Rigid(_) => ["inertia", "omega"]
                .iter()
                .flat_map(|f| (0..3).map(move |i| format!("{f}[{i}]")))
                .collect(),
            Turned::System(s) => s
                .params
                .iter()
                .map(|(p, _)| p.clone())
                .chain(s.variables.iter().map(|v| format!("initial.{v}")))
                .collect(),
        }
    }

    /// Why the simulator refuses this scene with `target` at `value`
    /// (scene units), if it does.
    pub(super) fn refusal(&self, target: &Target, value: f64) -> Option<String> {
        match self {
            Turned::Rigid(s) => {
                let s = knob::set_rigid(s, target, value);
                flipcard_sim::scene::check_scene(
                    s.inertia,
                    s.omega,
                    s.duration,
                    s.shows(Panel::Body),
                )
                .err()
                .map(|p| p.error.to_string())
            }
            Turned::System(s) => system_refusal(&knob::set_system(s, target, value)),
        }
    }
}

/// What the deck's system check refuses in a scene whose numbers changed:
/// its programs, its cost, a start that is not finite.
fn system_refusal(scene: &SystemScene) -> Option<String> {
    let system = match System::compile(scene, false) {
        Ok(s) => s,
        Err(e) => return Some(e.message),
    };
    if let Err(e) = check_cost(scene, &system.cost()) {
        return Some(e.to_string());
    }
    let fault = system
        .rhs_fault(0.0, &scene.initial)
        .or_else(|| system.observable_fault(0.0, &scene.initial));
    if let Some(f) = fault {
        return Some(format!(
            "{} gives {} at t = 0: {}",
            f.source.describe(scene),
            Shown(f.value),
            f.cause
        ));
    }
    let mut dy = vec![0.0; scene.initial.len()];
    system.rhs(0.0, &scene.initial, &mut dy);
    dy.iter().position(|d| !d.is_finite()).map(|k| {
        format!(
            "the equation of `{}` is not finite at t = 0",
            scene.variables[k]
        )
    })
}

/// The scene's knobs and explore measure; `None` after an error (reported),
/// `Some(None)` for a scene with neither.
pub fn explore(
    rep: &mut FileReport,
    raw: &RawScene,
    langs: &Langs,
    what: &str,
    scene: Turned,
) -> Option<Option<Explore>> {
    let id = match scene {
        Turned::Rigid(s) => s.id.clone(),
        Turned::System(s) => s.id.clone(),
    };
    let Some(list) = &raw.knobs else {
        if let Some(e) = &raw.explore {
            rep.error(
                e.span.clone(),
                format!("`explore` of {what} plots a measure against a knob, but the scene has no `knobs`"),
                Some("knobs = [{ name = \"…\", min = …, max = …, step = …, label = { en = \"…\" } }]".to_string()),
            );
            return None;
        }
        return Some(None);
    };
    let mut ok = true;
    let mut knobs = Vec::new();
    let mut seen: Vec<&str> = Vec::new();
    for k in &list.items {
        if let Some(n) = &k.name {
            if seen.contains(&n.value.as_str()) {
                rep.error(
                    n.span.clone(),
                    format!("knob `{}` is declared twice in {what}", n.value),
                    Some("one knob per number".to_string()),
                );
                ok = false;
                continue;
            }
            seen.push(&n.value);
        }
        match one(rep, k, langs, scene) {
            Some(knob) => knobs.push(knob),
            None => ok = false,
        }
    }
    let measure = match &raw.explore {
        None => None,
        Some(s) => {
            let names: Vec<String>;
            let kind = match scene {
                Turned::Rigid(_) => SceneKind::Rigid,
                Turned::System(sys) => {
                    names = sys
                        .variables
                        .iter()
                        .cloned()
                        .chain(sys.observables.iter().map(|(n, _)| n.clone()))
                        .collect();
                    SceneKind::System(&names)
                }
            };
            match answer::measure_text(rep, s, Some(kind)) {
                Some(m) => Some(m),
                None => {
                    ok = false;
                    None
                }
            }
        }
    };
    ok.then_some(Some(Explore {
        scene: id,
        knobs,
        measure,
    }))
}

/// A finite number, reported at its span otherwise.
fn finite(rep: &mut FileReport, n: &Num, field: &str) -> bool {
    if n.value.is_finite() {
        return true;
    }
    rep.error(
        n.span.clone(),
        format!(
            "a knob's `{field}` is {}, not a finite number",
            Shown(n.value)
        ),
        None,
    );
    false
}

fn one(rep: &mut FileReport, k: &RawKnob, langs: &Langs, scene: Turned) -> Option<Knob> {
    let name: &Str = k.name.as_ref()?;
    let label = k.label.as_ref().and_then(|l| {
        text::text(
            rep,
            l,
            langs,
            &format!("the label of knob `{}`", name.value),
        )
    });
    let Some(target) = scene.target(&name.value) else {
        let names = scene.names();
        let hint = suggest::did_you_mean(&name.value, names.iter().map(String::as_str))
            .or_else(|| Some(format!("knobs of this scene: {}", names.join(", "))));
        let kind = match scene {
            Turned::Rigid(_) => "a rigid body's `inertia[i]` or `omega[i]` (i = 0, 1, 2)",
            Turned::System(_) => "a parameter or `initial.VAR` of the scene",
        };
        rep.error(
            name.span.clone(),
            format!("unknown knob `{}`: a knob turns {kind}", name.value),
            hint,
        );
        return None;
    };
    let (min, max, step) = (k.min.as_ref()?, k.max.as_ref()?, k.step.as_ref()?);
    let mut ok = finite(rep, min, "min") & finite(rep, max, "max");
    if ok && min.value >= max.value {
        rep.error(
            max.span.clone(),
            format!(
                "knob `{}`: `max` {} is not above `min` {}",
                name.value,
                Shown(max.value),
                Shown(min.value)
            ),
            Some("write the range low to high: min < max".to_string()),
        );
        ok = false;
    }
    if !(step.value.is_finite() && step.value > 0.0) {
        rep.error(
            step.span.clone(),
            format!(
                "knob `{}`: `step` is {}; a step is a positive, finite number",
                name.value,
                Shown(step.value)
            ),
            None,
        );
        ok = false;
    } else if ok && (max.value - min.value) / step.value > knob::MAX_STEPS {
        rep.error(
            step.span.clone(),
            format!(
                "knob `{}`: `step` {} cuts the range into more than {} steps",
                name.value,
                Shown(step.value),
                knob::MAX_STEPS
            ),
            Some("a larger step".to_string()),
        );
        ok = false;
    }
    let scale = k.scale.as_ref().map_or(1.0, |s| s.value);
    if let Some(s) = &k.scale
        && !(s.value.is_finite() && s.value != 0.0)
    {
        rep.error(
            s.span.clone(),
            format!(
                "knob `{}`: `scale` is {}; the scene gets value × scale, a finite number other than 0",
                name.value,
                Shown(s.value)
            ),
            Some("degrees shown, radians run: scale = 0.017453292519943295".to_string()),
        );
        ok = false;
    }
    if !ok {
        return None;
    }
    let (min, max, step) = (min.value, max.value, step.value);
    // The scene's own value, in the knob's unit.
    let own = scene.own(&target).map(|v| v / scale);
    if let Some(own) = own {
        let slack = 1e-9 * own.abs().max(min.abs()).max(max.abs()).max(1e-300);
        if own < min - slack || own > max + slack {
            rep.error(
                k.span.clone(),
                format!(
                    "knob `{}`: the scene's own value {} is outside its range [{}, {}]",
                    name.value,
                    Shown(knob::tidy(own)),
                    Shown(min),
                    Shown(max)
                ),
                Some("the range holds the scene as written, so exploring starts there".to_string()),
            );
            return None;
        }
    }
    let knob = Knob {
        target,
        min,
        max,
        step,
        scale,
        label: label?,
    };
    // The simulator's own acceptance at the ends and the middle.
    for value in [knob.min, knob.middle(), knob.max] {
        if let Some(why) = scene.refusal(&knob.target, value * scale) {
            rep.error(
                k.span.clone(),
                format!(
                    "knob `{}` at {}: the simulator refuses the scene: {why}",
                    name.value,
                    Shown(value)
                ),
                Some("narrow the range to values the scene runs at".to_string()),
            );
            return None;
        }
    }
    Some(knob)
}
