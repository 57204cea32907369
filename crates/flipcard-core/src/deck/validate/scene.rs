//! Scenes: physical moments of inertia, a finite ω, a sane duration, known
//! panels.

use crate::deck::model::{Panel, Scene};
use crate::deck::raw::{Flag, List, Num, RawScene};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use flipcard_sim::error::ModelError;
use flipcard_sim::rigid::model::Body;
use flipcard_sim::scene::{SceneField, check_scene};
use flipcard_text::num;

use super::text::{self, Kind, Langs};

/// Longest run a scene may ask for, in its time unit: beyond this a typo
/// (a missing decimal point) is far likelier than intent.
pub(crate) const MAX_DURATION: f64 = 1e6;

pub fn scene(rep: &mut FileReport, raw: &RawScene, langs: &Langs, what: &str) -> Option<Scene> {
    let title = raw
        .title
        .as_ref()
        .map(|t| text::text(rep, t, langs, &format!("the title of {what}")));
    let inertia = raw
        .inertia
        .as_ref()
        .and_then(|l| inertia(rep, l, raw.flat.as_ref()));
    let omega = raw.omega.as_ref().and_then(|l| omega(rep, l));
    let duration = raw.duration.as_ref().and_then(|d| duration(rep, d));
    let show = raw.show.as_ref().and_then(|l| show(rep, l, what));
    let time_unit = match &raw.time_unit {
        Some(u) => text::string(rep, u, Kind::Plain, "`time_unit`").then(|| u.value.clone()),
        None => Some("s".to_string()),
    };
    if let (Some(i), Some(w), Some(d), Some(panels)) = (inertia, omega, duration, show.as_ref()) {
        // The simulator's own test of the scene, so that a deck that passes
        // here always runs.
        let orientation = panels.contains(&Panel::Body);
        if let Err(problem) = check_scene(i, w, d, orientation) {
            let span = match problem.field {
                SceneField::Inertia => raw.inertia.as_ref().map(|l| l.span.clone()),
                SceneField::Omega => raw.omega.as_ref().map(|l| l.span.clone()),
                SceneField::Duration => raw.duration.as_ref().map(|n| n.span.clone()),
            };
            let help = match problem.field {
                SceneField::Duration => "shorten the duration, or slow the spin down",
                SceneField::Omega | SceneField::Inertia => {
                    "pick units in which ω and the moments are nearer 1"
                }
            };
            if let Some(span) = span {
                rep.error(span, problem.error.to_string(), Some(help.to_string()));
            }
            return None;
        }
    }
    Some(Scene {
        id: raw.id.as_ref()?.value.clone(),
        title: title.map_or(Some(None), |t| t.map(Some))?,
        inertia: inertia?,
        omega: omega?,
        duration: duration?,
        show: show?,
        time_unit: time_unit?,
    })
}

fn three(rep: &mut FileReport, list: &List<Num>, name: &str) -> Option<[f64; 3]> {
    match <[Num; 3]>::try_from(list.items.clone()) {
        Ok(v) => Some(v.map(|n| n.value)),
        Err(items) => {
            rep.error(
                list.span.clone(),
                format!("`{name}` must hold 3 numbers, found {}", items.len()),
                None,
            );
            None
        }
    }
}

fn inertia(rep: &mut FileReport, list: &List<Num>, flat: Option<&Flag>) -> Option<[f64; 3]> {
    let values = three(rep, list, "inertia")?;
    // Every bad moment is reported, not only the first Body::new meets.
    let mut ok = true;
    for (i, n) in list.items.iter().enumerate() {
        let axis = i + 1;
        let problem = if !n.value.is_finite() {
            Some(ModelError::NonFiniteInertia {
                axis,
                value: n.value,
            })
        } else if n.value <= 0.0 {
            Some(ModelError::NonPositiveInertia {
                axis,
                value: n.value,
            })
        } else {
            None
        };
        if let Some(e) = problem {
            rep.error(n.span.clone(), e.to_string(), None);
            ok = false;
        }
    }
    if !ok {
        return None;
    }
    match Body::new(values) {
        Ok(_) => {}
        Err(e @ ModelError::Triangle { k, .. }) => {
            rep.error(
                list.items[k - 1].span.clone(),
                e.to_string(),
                Some("principal moments obey Iᵢ + Iⱼ ≥ Iₖ; check for a typo".to_string()),
            );
            return None;
        }
        Err(e) => {
            rep.error(list.span.clone(), e.to_string(), None);
            return None;
        }
    }
    let flat_axis = (0..3).find(|&k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        values[i] + values[j] <= values[k] * (1.0 + 4.0 * f64::EPSILON)
    });
    // A flat body is a limit case, so it is flagged unless the author says
    // it is meant; saying so of a body that is not flat is a mistake too.
    match (flat_axis, flat.map(|f| f.value)) {
        (Some(k), None | Some(false)) => {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let (i, j) = (i.min(j) + 1, i.max(j) + 1);
            rep.warning(
                list.items[k].span.clone(),
                format!(
                    "flat body: I{i} + I{j} = I{} (all mass in one plane); allowed, but make sure it is meant",
                    k + 1
                ),
                Some("if it is, say so with `flat = true` in this scene".to_string()),
            );
        }
        (None, Some(true)) => {
            let span = flat
                .map(|f| f.span.clone())
                .unwrap_or_else(|| list.span.clone());
            rep.error(
                span,
                "`flat = true` but no moment equals the sum of the other two: the body is not flat",
                Some(
                    "remove `flat`, or fix the moments (a flat body has Iₖ = Iᵢ + Iⱼ)".to_string(),
                ),
            );
            return None;
        }
        _ => {}
    }
    Some(values)
}

fn omega(rep: &mut FileReport, list: &List<Num>) -> Option<[f64; 3]> {
    let values = three(rep, list, "omega")?;
    let mut ok = true;
    for (i, n) in list.items.iter().enumerate() {
        if !n.value.is_finite() {
            let e = ModelError::NonFiniteOmega {
                axis: i + 1,
                value: n.value,
            };
            rep.error(n.span.clone(), e.to_string(), None);
            ok = false;
        }
    }
    if ok && values.iter().all(|&w| w == 0.0) {
        rep.warning(list.span.clone(), "ω = 0: the body does not move", None);
    }
    ok.then_some(values)
}

fn duration(rep: &mut FileReport, n: &Num) -> Option<f64> {
    let problem = if !n.value.is_finite() {
        Some(format!("duration {} is not finite", num::show(n.value)))
    } else if n.value <= 0.0 {
        Some(format!("duration {} is not positive", num::show(n.value)))
    } else if n.value > MAX_DURATION {
        Some(format!(
            "duration {} is longer than the limit of {MAX_DURATION:e} time units",
            num::show(n.value)
        ))
    } else {
        None
    };
    match problem {
        Some(message) => {
            rep.error(n.span.clone(), message, None);
            None
        }
        None => Some(n.value),
    }
}

fn show(
    rep: &mut FileReport,
    list: &List<crate::deck::raw::Str>,
    what: &str,
) -> Option<Vec<crate::deck::model::Panel>> {
    let names = || Panel::ALL.iter().map(|p| p.name());
    if list.items.is_empty() {
        rep.error(
            list.span.clone(),
            format!("`show` of {what} is empty: a scene shows at least one panel"),
            Some(format!(
                "panels: {}",
                names().collect::<Vec<_>>().join(", ")
            )),
        );
        return None;
    }
    let mut panels = Vec::new();
    let mut ok = true;
    for s in &list.items {
        match Panel::from_name(&s.value) {
            Some(p) if panels.contains(&p) => rep.warning(
                s.span.clone(),
                format!("panel `{}` is listed twice", s.value),
                None,
            ),
            Some(p) => panels.push(p),
            None => {
                ok = false;
                let hint = suggest::did_you_mean(&s.value, names()).unwrap_or_else(|| {
                    format!("panels: {}", names().collect::<Vec<_>>().join(", "))
                });
                rep.error(
                    s.span.clone(),
                    format!("unknown panel `{}`", s.value),
                    Some(hint),
                );
            }
        }
    }
    ok.then_some(panels)
}
