//! System scenes: names, lengths, expressions (down to the character inside
//! the string, within the parser's depth and size), the panels'
//! references, the compiled programs within their size and a step within
//! what the app can play, and equations and observables that are finite at
//! t = 0 (or the first operation that is not, and why).

use std::collections::HashMap;

use crate::deck::raw::{List, Named, Num, RawAtol, RawHamiltonian, RawScene, RawSystem, Span, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use crate::deck::tomlstr;
use flipcard_sim::scene::spec::{Hamiltonian, Mark, SceneAtol, SystemPanel, SystemScene};
use flipcard_sim::scene::system::check_cost;
use flipcard_sim::solvers::ode::OdeSystem;
use flipcard_sim::system::System;
use flipcard_sim::system::compile::{Fault, Source};
use flipcard_sim::system::expr::{self, BUILTINS, ExprError, FUNCTIONS, MAX_NAME};
use flipcard_text::num::Num as Shown;

use super::text::{self, Kind, Langs};

/// The quantities a system scene's measures may name (variables, then
/// observables), read from the raw scene so prompts can be checked before
/// the scene itself is.
pub fn quantities(raw: &RawSystem) -> Vec<String> {
    let mut out: Vec<String> = raw
        .variables
        .items
        .iter()
        .map(|s| s.value.clone())
        .collect();
    if let Some(o) = &raw.observables {
        out.extend(o.entries.iter().map(|e| e.key.value.clone()));
    }
    out
}

/// The file span of bytes `at..at + len` of the decoded string `s`.
pub(crate) fn span_in(rep: &FileReport, s: &Str, at: usize, len: usize) -> Span {
    let token = rep.source.get(s.span.clone()).unwrap_or("");
    let start = s.span.start + tomlstr::locate(token, at).0;
    let end = s.span.start + tomlstr::locate(token, at + len.max(1)).0;
    start..end.max(start + 1)
}

fn report_expr(rep: &mut FileReport, s: &Str, e: ExprError, what: &str, scope: &[&str]) {
    let hint = match &e.unknown {
        Some(name) => suggest::did_you_mean(name, scope.iter().copied()).or_else(|| {
            let mut known: Vec<&str> = scope.to_vec();
            known.retain(|k| !BUILTINS.contains(k));
            Some(if known.is_empty() {
                "names: t, pi, e".to_string()
            } else {
                format!("names here: {}, t, pi, e", known.join(", "))
            })
        }),
        None => e.hint.clone(),
    };
    let span = span_in(rep, s, e.at, e.len);
    rep.error(span, format!("{what}: {}", e.message), hint);
}

/// Parses `s` and checks its names against `scope`; reported on failure.
fn expression(rep: &mut FileReport, s: &Str, what: &str, scope: &[&str]) -> bool {
    let node = match expr::parse(&s.value) {
        Ok(n) => n,
        Err(e) => {
            report_expr(rep, s, e, what, scope);
            return false;
        }
    };
    let known = |n: &str| scope.contains(&n) || BUILTINS.contains(&n);
    match expr::check_names(&node, &known) {
        Ok(()) => true,
        Err(e) => {
            report_expr(rep, s, e, what, scope);
            false
        }
    }
}

/// A name an author gives: its shape, its length, and that it does not
/// hide a function, a constant or time.
fn name(rep: &mut FileReport, s: &Str, kind: &str) -> bool {
    let n = s.value.as_str();
    let problem = if !expr::is_name(n) {
        Some((
            format!("{kind} name `{}` is not a name", n.escape_debug()),
            "names are a letter or `_`, then letters, digits or `_` (theta, omega_1)".to_string(),
        ))
    } else if n.len() > MAX_NAME {
        Some((
            format!("{kind} name `{n}` is longer than {MAX_NAME} characters"),
            "shorten it".to_string(),
        ))
    } else if FUNCTIONS.iter().any(|(f, _)| *f == n) {
        Some((
            format!("{kind} name `{n}` shadows the function `{n}`"),
            "pick another name".to_string(),
        ))
    } else if BUILTINS.contains(&n) {
        let what = match n {
            "t" => "time",
            "pi" => "the constant π",
            _ => "Euler's number",
        };
        Some((
            format!("{kind} name `{n}` shadows {what}"),
            "pick another name".to_string(),
        ))
    } else {
        None
    };
    match problem {
        Some((message, hint)) => {
            rep.error(s.span.clone(), message, Some(hint));
            false
        }
        None => true,
    }
}

/// Looks `s` up among `known`; reported with a did-you-mean when missing.
/// The longest label a scene may give a quantity (`labels`).
const MAX_LABEL_CHARS: usize = 24;

fn names_one(rep: &mut FileReport, s: &Str, known: &[&str], field: &str, kinds: &str) -> bool {
    if known.contains(&s.value.as_str()) {
        return true;
    }
    let hint = suggest::did_you_mean(&s.value, known.iter().copied()).or_else(|| {
        Some(if known.is_empty() {
            format!("the scene has no {kinds}")
        } else {
            format!("{kinds}: {}", known.join(", "))
        })
    });
    rep.error(
        s.span.clone(),
        format!(
            "`{field}` names `{}`, which is not one of the scene's {kinds}",
            s.value
        ),
        hint,
    );
    false
}

/// `hamiltonian`'s names: each a variable, every variable once (in `q` or
/// in `p`), as many positions as momenta.
fn hamiltonian_names(rep: &mut FileReport, h: &RawHamiltonian, vars: &[&str]) -> bool {
    let mut ok = true;
    let mut seen: Vec<&str> = Vec::new();
    for s in h.q.items.iter().chain(&h.p.items) {
        if !names_one(rep, s, vars, "hamiltonian", "variables") {
            ok = false;
        } else if seen.contains(&s.value.as_str()) {
            rep.error(
                s.span.clone(),
                format!("`hamiltonian` names `{}` twice", s.value),
                Some("each variable is a position (`q`) or a momentum (`p`), once".to_string()),
            );
            ok = false;
        } else {
            seen.push(&s.value);
        }
    }
    if !ok {
        return false;
    }
    if h.q.items.len() != h.p.items.len() {
        rep.error(
            h.span.clone(),
            format!(
                "`hamiltonian` declares {} and {}; each position needs its momentum",
                flipcard_text::plural(h.q.items.len(), "position", "positions"),
                flipcard_text::plural(h.p.items.len(), "momentum", "momenta")
            ),
            Some("hamiltonian = { q = [\"x\", \"y\"], p = [\"vx\", \"vy\"] }".to_string()),
        );
        return false;
    }
    if let Some(missing) = vars.iter().find(|v| !seen.contains(v)) {
        rep.error(
            h.span.clone(),
            format!("`hamiltonian` leaves out the variable `{missing}`; every variable is a position or a momentum"),
            Some("a symplectic method moves the whole state; name it in `q` or `p`".to_string()),
        );
        return false;
    }
    true
}

/// An absolute tolerance: a positive, finite number (below 1e-300 no
/// error estimate is meaningful).
fn tolerance(rep: &mut FileReport, n: &Num, what: &str) -> bool {
    let v = n.value;
    if SceneAtol::allowed(v) {
        return true;
    }
    rep.error(
        n.span.clone(),
        format!(
            "{what} is {}: an absolute tolerance is a positive, finite number of at least 1e-300",
            Shown(v)
        ),
        Some(
            "about a millionth of the size the variable reaches, e.g. atol = { y2 = 1e-20 }"
                .to_string(),
        ),
    );
    false
}

fn numbers(
    rep: &mut FileReport,
    list: &List<Num>,
    count: usize,
    field: &str,
    what: &str,
) -> Option<Vec<f64>> {
    if list.items.len() != count {
        rep.error(
            list.span.clone(),
            format!(
                "`{field}` of {what} has {} for {}",
                flipcard_text::plural(list.items.len(), "number", "numbers"),
                flipcard_text::plural(count, "variable", "variables")
            ),
            Some("give one number per variable, in the order of `variables`".to_string()),
        );
        return None;
    }
    let mut ok = true;
    for n in &list.items {
        if !n.value.is_finite() {
            rep.error(
                n.span.clone(),
                format!("`{field}` holds {}, not a finite number", Shown(n.value)),
                None,
            );
            ok = false;
        }
    }
    ok.then(|| list.items.iter().map(|n| n.value).collect())
}

/// Reports each name given twice (among variables, params, observables).
fn unique(rep: &mut FileReport, all: &[(&Str, &str)]) -> bool {
    let mut seen: HashMap<&str, (&Span, &str)> = HashMap::new();
    let mut ok = true;
    for (s, kind) in all {
        if let Some((first, first_kind)) = seen.get(s.value.as_str()) {
            let line = rep.line_of(first.start);
            rep.error(
                s.span.clone(),
                format!("`{}` is named twice in the scene", s.value),
                Some(format!(
                    "first as a {first_kind} on line {line}; here as a {kind}"
                )),
            );
            ok = false;
        } else {
            seen.insert(&s.value, (&s.span, kind));
        }
    }
    ok
}

fn panels(rep: &mut FileReport, list: &List<Str>, what: &str) -> Option<Vec<SystemPanel>> {
    let names = || SystemPanel::ALL.iter().map(|p| p.name());
    if list.items.is_empty() {
        rep.error(
            list.span.clone(),
            format!("`show` of {what} is empty: a scene shows at least one panel"),
            Some(format!(
                "panels of a system: {}",
                names().collect::<Vec<_>>().join(", ")
            )),
        );
        return None;
    }
    let mut out = Vec::new();
    let mut ok = true;
    for s in &list.items {
        match SystemPanel::from_name(&s.value) {
            Some(p) if out.contains(&p) => rep.warning(
                s.span.clone(),
                format!("panel `{}` is listed twice", s.value),
                None,
            ),
            Some(p) => out.push(p),
            None => {
                ok = false;
                let rigid = matches!(s.value.as_str(), "omega" | "body" | "polhode");
                let hint = if rigid {
                    format!(
                        "`{}` is a rigid-body panel; a system shows {}",
                        s.value,
                        names().collect::<Vec<_>>().join(", ")
                    )
                } else {
                    suggest::did_you_mean(&s.value, names()).unwrap_or_else(|| {
                        format!(
                            "panels of a system: {}",
                            names().collect::<Vec<_>>().join(", ")
                        )
                    })
                };
                rep.error(
                    s.span.clone(),
                    format!("unknown panel `{}`", s.value),
                    Some(hint),
                );
            }
        }
    }
    ok.then_some(out)
}

fn duration(rep: &mut FileReport, n: &Num) -> Option<f64> {
    if n.value.is_finite() && n.value > 0.0 {
        return Some(n.value);
    }
    rep.error(
        n.span.clone(),
        format!(
            "duration {} is not a positive finite number",
            Shown(n.value)
        ),
        None,
    );
    None
}

pub fn scene(
    rep: &mut FileReport,
    raw: &RawScene,
    sys: &RawSystem,
    langs: &Langs,
    what: &str,
) -> Option<SystemScene> {
    let title = raw
        .title
        .as_ref()
        .map(|t| text::text(rep, t, langs, &format!("the title of {what}")));
    let duration = raw.duration.as_ref().and_then(|d| duration(rep, d));
    let show = raw.show.as_ref().and_then(|l| panels(rep, l, what));
    let time_unit = match &raw.time_unit {
        Some(u) => text::string(rep, u, Kind::Plain, "`time_unit`").then(|| u.value.clone()),
        None => Some("s".to_string()),
    };

    // Names.
    let mut ok = true;
    let params: Named<Num> = sys.params.clone().unwrap_or(Named {
        entries: Vec::new(),
        span: 0..0,
    });
    let observables: Named<Str> = sys.observables.clone().unwrap_or(Named {
        entries: Vec::new(),
        span: 0..0,
    });
    if sys.variables.items.is_empty() {
        rep.error(
            sys.variables.span.clone(),
            format!("`variables` of {what} is empty: a system has at least one variable"),
            None,
        );
        ok = false;
    }
    let mut all: Vec<(&Str, &str)> = Vec::new();
    for v in &sys.variables.items {
        ok &= name(rep, v, "variable");
        all.push((v, "variable"));
    }
    for p in &params.entries {
        ok &= name(rep, &p.key, "parameter");
        all.push((&p.key, "parameter"));
    }
    for o in &observables.entries {
        ok &= name(rep, &o.key, "observable");
        all.push((&o.key, "observable"));
    }
    ok &= unique(rep, &all);
    let mut param_values = Vec::new();
    for p in &params.entries {
        if p.value.value.is_finite() {
            param_values.push((p.key.value.clone(), p.value.value));
        } else {
            rep.error(
                p.value.span.clone(),
                format!(
                    "parameter `{}` is {}, not a finite number",
                    p.key.value,
                    Shown(p.value.value)
                ),
                None,
            );
            ok = false;
        }
    }
    let n = sys.variables.items.len();
    let initial = sys
        .initial
        .as_ref()
        .and_then(|l| numbers(rep, l, n, "initial", what));

    // Expressions.
    let vars: Vec<&str> = sys
        .variables
        .items
        .iter()
        .map(|s| s.value.as_str())
        .collect();
    let pars: Vec<&str> = params
        .entries
        .iter()
        .map(|e| e.key.value.as_str())
        .collect();
    let obs: Vec<&str> = observables
        .entries
        .iter()
        .map(|e| e.key.value.as_str())
        .collect();
    let full: Vec<&str> = vars.iter().chain(&pars).chain(&obs).copied().collect();
    let mut equations = None;
    if let Some(list) = &sys.equations {
        if list.items.len() != n {
            rep.error(
                list.span.clone(),
                format!(
                    "`equations` of {what} has {} for {}",
                    flipcard_text::plural(list.items.len(), "equation", "equations"),
                    flipcard_text::plural(n, "variable", "variables")
                ),
                Some("give d/dt of each variable, in the order of `variables`".to_string()),
            );
            ok = false;
        } else {
            let mut eq_ok = true;
            for (k, s) in list.items.iter().enumerate() {
                let var = vars.get(k).copied().unwrap_or("?");
                eq_ok &= expression(rep, s, &format!("the equation of `{var}`"), &full);
            }
            ok &= eq_ok;
            equations = eq_ok.then(|| list.items.iter().map(|s| s.value.clone()).collect());
        }
    }
    for (k, o) in observables.entries.iter().enumerate() {
        let before: Vec<&str> = vars.iter().chain(&pars).chain(&obs[..k]).copied().collect();
        let node = expr::parse(&o.value.value);
        // A later observable gets its own message: the order is the fix.
        if let Ok(node) = &node {
            let mut used = Vec::new();
            expr::names(node, &mut used);
            if let Some(later) = used.iter().find(|u| obs[k..].contains(&u.as_str())) {
                let at = o.value.value.find(later.as_str()).unwrap_or(0);
                let span = span_in(rep, &o.value, at, later.len());
                rep.error(
                    span,
                    format!(
                        "observable `{}` uses `{later}`, which is not defined before it",
                        o.key.value
                    ),
                    Some(
                        "an observable may use only the observables written before it".to_string(),
                    ),
                );
                ok = false;
                continue;
            }
        }
        ok &= expression(
            rep,
            &o.value,
            &format!("observable `{}`", o.key.value),
            &before,
        );
    }

    // What the panels and diagnostics name.
    let quantities: Vec<&str> = vars.iter().chain(&obs).copied().collect();
    let mut plot = Vec::new();
    if let Some(list) = &sys.plot {
        for s in &list.items {
            ok &= names_one(rep, s, &quantities, "plot", "variables and observables");
            plot.push(s.value.clone());
        }
    }
    let atol = match &sys.atol {
        None => None,
        Some(RawAtol::All(n)) => {
            ok &= tolerance(rep, n, "`atol`");
            Some(SceneAtol::All(n.value))
        }
        Some(RawAtol::Each(table)) => {
            let mut each = Vec::new();
            for e in &table.entries {
                ok &= names_one(rep, &e.key, &vars, "atol", "variables");
                ok &= tolerance(rep, &e.value, &format!("`atol` of `{}`", e.key.value));
                each.push((e.key.value.clone(), e.value.value));
            }
            Some(SceneAtol::Each(each))
        }
    };
    // The plots' names for some quantities: each a quantity of the scene,
    // each label a short plain name.
    let mut labels = Vec::new();
    if let Some(table) = &sys.labels {
        for e in &table.entries {
            ok &= names_one(
                rep,
                &e.key,
                &quantities,
                "labels",
                "variables and observables",
            );
            let l = &e.value;
            let chars = l.value.chars().count();
            if l.value.trim().is_empty() || chars > MAX_LABEL_CHARS {
                rep.error(
                    l.span.clone(),
                    format!(
                        "the label of `{}` is {chars} characters long; a label is a short name, 1 to {MAX_LABEL_CHARS} characters",
                        e.key.value
                    ),
                    Some("the name the question uses, e.g. labels = { xc = \"A\" }".to_string()),
                );
                ok = false;
            } else {
                ok &= text::string(
                    rep,
                    l,
                    text::Kind::Plain,
                    &format!("the label of `{}`", e.key.value),
                );
            }
            labels.push((e.key.value.clone(), l.value.clone()));
        }
    }
    let mut conserved = Vec::new();
    if let Some(list) = &sys.conserved {
        for s in &list.items {
            ok &= names_one(rep, s, &obs, "conserved", "observables");
            conserved.push(s.value.clone());
        }
    }
    let hamiltonian = sys.hamiltonian.as_ref().map(|h| {
        ok &= hamiltonian_names(rep, h, &vars);
        Hamiltonian {
            q: h.q.items.iter().map(|s| s.value.clone()).collect(),
            p: h.p.items.iter().map(|s| s.value.clone()).collect(),
        }
    });
    let mut phase = None;
    if let Some(list) = &sys.phase {
        if list.items.len() != 2 {
            rep.error(
                list.span.clone(),
                format!(
                    "`phase` names 2 quantities (horizontal, vertical), found {}",
                    list.items.len()
                ),
                Some("phase = [\"theta\", \"omega\"]".to_string()),
            );
            ok = false;
        } else {
            for s in &list.items {
                ok &= names_one(rep, s, &quantities, "phase", "variables and observables");
            }
            phase = Some([list.items[0].value.clone(), list.items[1].value.clone()]);
        }
    }
    let mut sketch = Vec::new();
    if let Some(list) = &sys.sketch {
        for m in &list.items {
            let need = if m.key.value == "line" { 4 } else { 2 };
            if m.exprs.items.len() != need {
                let shape = if need == 4 { "x1, y1, x2, y2" } else { "x, y" };
                rep.error(
                    m.exprs.span.clone(),
                    format!(
                        "a sketch `{}` takes {need} expressions ({shape}), found {}",
                        m.key.value,
                        m.exprs.items.len()
                    ),
                    None,
                );
                ok = false;
                continue;
            }
            let mut mark_ok = true;
            for s in &m.exprs.items {
                mark_ok &= expression(rep, s, &format!("the sketch `{}`", m.key.value), &full);
            }
            ok &= mark_ok;
            let e: Vec<String> = m.exprs.items.iter().map(|s| s.value.clone()).collect();
            sketch.push(match m.key.value.as_str() {
                "line" => Mark::Line([e[0].clone(), e[1].clone(), e[2].clone(), e[3].clone()]),
                "dot" => {
                    let label = match &m.label {
                        Some(l) => {
                            let t = text::text(rep, l, langs, "a dot's `label`");
                            ok &= t.is_some();
                            t
                        }
                        None => None,
                    };
                    Mark::Dot([e[0].clone(), e[1].clone()], label)
                }
                _ => Mark::Trail([e[0].clone(), e[1].clone()]),
            });
        }
    }
    if let (Some(show), Some(list)) = (&show, &raw.show) {
        let missing = [
            (SystemPanel::Plot, plot.is_empty(), "plot = [\"theta\"]"),
            (
                SystemPanel::Phase,
                phase.is_none(),
                "phase = [\"theta\", \"omega\"]",
            ),
            (
                SystemPanel::Sketch,
                sketch.is_empty(),
                "sketch = [{ dot = [\"x\", \"y\"] }]",
            ),
        ];
        for (panel, absent, example) in missing {
            if show.contains(&panel) && absent && ok {
                let at = list
                    .items
                    .iter()
                    .find(|s| s.value == panel.name())
                    .map_or(list.span.clone(), |s| s.span.clone());
                rep.error(
                    at,
                    format!(
                        "{what} shows `{}` but does not say what to draw there",
                        panel.name()
                    ),
                    Some(example.to_string()),
                );
                ok = false;
            }
        }
    }

    let scene = SystemScene {
        id: raw.id.as_ref()?.value.clone(),
        title: title.map_or(Some(None), |t| t.map(Some))?,
        variables: vars.iter().map(|v| v.to_string()).collect(),
        initial: initial?,
        params: param_values,
        equations: equations?,
        observables: observables
            .entries
            .iter()
            .map(|e| (e.key.value.clone(), e.value.value.clone()))
            .collect(),
        conserved,
        duration: duration?,
        show: show?,
        plot,
        phase,
        sketch,
        time_unit: time_unit?,
        atol,
        hamiltonian,
        labels,
    };
    if !ok {
        return None;
    }
    // The compiled scene: each program within its size, each step within
    // what the app can play, and the right-hand side and observables finite
    // at the start (a scene that cannot take its first step is an error of
    // the deck, not of the run).
    let list = sys.equations.as_ref()?;
    let system = match System::compile(&scene, false) {
        Ok(s) => s,
        Err(e) => {
            let span = e
                .source
                .and_then(|src| source_span(sys, src))
                .unwrap_or_else(|| raw.span.clone());
            rep.error(
                span,
                format!("{what}: {}", e.message),
                Some("split it into smaller observables, or simplify it".to_string()),
            );
            return None;
        }
    };
    if let Err(e) = check_cost(&scene, &system.cost()) {
        rep.error(
            list.span.clone(),
            e.to_string(),
            Some("use fewer variables or shorter equations".to_string()),
        );
        return None;
    }
    if let (Some(h), Some(why)) = (&sys.hamiltonian, system.hamiltonian_error(&scene)) {
        rep.error(
            h.span.clone(),
            format!("`hamiltonian` of {what}: {why}"),
            Some("declare `hamiltonian` only for x' = f(p), p' = g(q): positions whose rates read momenta, momenta whose rates read positions".to_string()),
        );
        return None;
    }
    let state = || {
        scene
            .variables
            .iter()
            .zip(&scene.initial)
            .map(|(v, x)| format!("{v} = {}", Shown(*x)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let hint = "check the initial values and the parameters (a division by zero, a root or log of a negative)";
    // "the equation of `x` gives inf at t = 0 (initial state x = 1):
    // division by zero".
    let at_start = |f: &Fault| {
        let inside = if f.written_in != f.source {
            format!(" in {}", f.written_in.describe(&scene))
        } else {
            String::new()
        };
        format!(
            "{} gives {} at t = 0 (initial state {}): {}{inside}",
            f.source.describe(&scene),
            Shown(f.value),
            state(),
            f.cause
        )
    };
    let mut finite = true;
    if let Some(f) = system.rhs_fault(0.0, &scene.initial) {
        let span = source_span(sys, f.written_in).unwrap_or_else(|| list.span.clone());
        rep.error(span, at_start(&f), Some(hint.to_string()));
        finite = false;
    } else {
        let mut dy = vec![0.0; n];
        system.rhs(0.0, &scene.initial, &mut dy);
        for (k, d) in dy.iter().enumerate() {
            if !d.is_finite() {
                rep.error(
                    list.items[k].span.clone(),
                    format!(
                        "the equation of `{}` gives {} at t = 0 (initial state {})",
                        scene.variables[k],
                        Shown(*d),
                        state()
                    ),
                    Some(hint.to_string()),
                );
                finite = false;
            }
        }
    }
    if let Some(f) = system.observable_fault(0.0, &scene.initial) {
        let span = source_span(sys, f.written_in).unwrap_or_else(|| raw.span.clone());
        rep.error(span, at_start(&f), Some(hint.to_string()));
        finite = false;
    }
    finite.then_some(scene)
}

/// The span of the expression `source` names.
fn source_span(sys: &RawSystem, source: Source) -> Option<Span> {
    match source {
        Source::Equation(k) => sys.equations.as_ref()?.items.get(k).map(|s| s.span.clone()),
        Source::Observable(k) => sys
            .observables
            .as_ref()?
            .entries
            .get(k)
            .map(|e| e.value.span.clone()),
        Source::Mark(k) => sys
            .sketch
            .as_ref()?
            .items
            .iter()
            .flat_map(|m| &m.exprs.items)
            .nth(k)
            .map(|s| s.span.clone()),
    }
}
