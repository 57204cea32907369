//! A prompt's `vary` (issue 24 §2), checked against the scene it varies:
//! each name an identifier the question shows as `{name}` (or
//! `{name:.N}`) in every language; a range `[lo, hi]` finite and ordered,
//! or `values` of finite numbers; a step positive, a scale finite and not
//! zero; a target (the name itself unless `target` says) that is a
//! parameter or `initial.VAR` of a system, `inertia[i]` or `omega[i]` of a
//! rigid body; and the scene at each number's ends and middle accepted by
//! the simulator. Whether every variant's run decides the answer is
//! `check`'s part (`predict::audit`), which runs them.

use crate::deck::model::{Draw, Varied};
use crate::deck::raw::{RawPrompt, RawText, RawVaried};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use flipcard_sim::scene::knob;
use flipcard_text::Text;
use flipcard_text::num::Num as Shown;

use super::knob::Turned;

/// At most this many numbers vary in one prompt.
pub const MAX_VARIED: usize = 8;
/// At most this many `values` in one list.
pub const MAX_VALUES: usize = 1000;

fn is_name(s: &str) -> bool {
    let mut b = s.bytes();
    s.len() <= 32
        && b.next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == b'_')
        && b.all(|c| c.is_ascii_alphanumeric() || c == b'_')
}

/// The prompt's varied numbers in the deck's order (empty without
/// `vary`); `None` after an error (reported). `question` is the validated
/// question, whose placeholders set how each number is rounded.
pub fn vary(
    rep: &mut FileReport,
    raw: &RawPrompt,
    question: &Text,
    what: &str,
    scene: Turned,
) -> Option<Vec<Varied>> {
    let Some(list) = &raw.vary else {
        return Some(Vec::new());
    };
    if list.items.is_empty() {
        rep.error(
            list.span.clone(),
            format!("`vary` of {what} varies nothing"),
            Some("vary = { theta0 = [20.0, 80.0] }, or leave `vary` out".into()),
        );
        return None;
    }
    if list.items.len() > MAX_VARIED {
        rep.error(
            list.span.clone(),
            format!(
                "`vary` of {what} varies {} numbers; at most {MAX_VARIED}",
                list.items.len()
            ),
            None,
        );
        return None;
    }
    let names: Vec<&str> = list.items.iter().map(|v| v.name.value.as_str()).collect();
    // Where each name shows, language by language, and with how many
    // decimals at most.
    let mut decimals: Vec<Option<u8>> = vec![None; names.len()];
    let mut ok = true;
    for (lang, text) in &question.0 {
        let span = question_span(raw, lang.as_str());
        match flipcard_text::fill::placeholders(text, &names) {
            Err(e) => {
                rep.error(
                    span,
                    format!(
                        "the {lang} question of {what} shows `{{{}:{}}}`, a format that does not read",
                        e.name, e.format
                    ),
                    Some(format!(
                        "{{{0}}} shows the shortest number, {{{0}:.1}} one decimal (at most .{1})",
                        e.name,
                        flipcard_text::fill::MAX_DECIMALS
                    )),
                );
                ok = false;
            }
            Ok(found) => {
                for (i, n) in names.iter().enumerate() {
                    let mut seen = false;
                    for p in found.iter().filter(|p| p.name == *n) {
                        seen = true;
                        if let Some(d) = p.decimals {
                            decimals[i] = Some(decimals[i].map_or(d, |e| e.max(d)));
                        }
                    }
                    if !seen && is_name(n) {
                        rep.error(
                            list.items[i].name.span.clone(),
                            format!(
                                "`{n}` varies, but the {lang} question of {what} never shows it: the learner would predict without the number"
                            ),
                            Some(format!("write {{{n}}} where the question gives it")),
                        );
                        ok = false;
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    for (i, v) in list.items.iter().enumerate() {
        match one(rep, v, what, scene, decimals[i]) {
            Some(v) => out.push(v),
            None => ok = false,
        }
    }
    // Drawn in name order, whatever order a TOML reader keeps: a stored
    // seed draws the same numbers in every version.
    out.sort_by(|a, b| a.name.cmp(&b.name));
    ok.then_some(out)
}

/// The span of the question's text in `lang` (the question's whole span
/// when it is one plain string).
fn question_span(raw: &RawPrompt, lang: &str) -> std::ops::Range<usize> {
    match &raw.question {
        Some(RawText::ByLang { entries, span }) => entries
            .iter()
            .find(|(l, _)| l.value == lang)
            .map_or(span.clone(), |(_, s)| s.span.clone()),
        Some(RawText::Plain(s)) => s.span.clone(),
        None => raw.span.clone(),
    }
}

fn one(
    rep: &mut FileReport,
    v: &RawVaried,
    what: &str,
    scene: Turned,
    decimals: Option<u8>,
) -> Option<Varied> {
    let name = &v.name.value;
    if !is_name(name) {
        rep.error(
            v.name.span.clone(),
            format!(
                "`{}` is not a name a question can show: letters, digits and _, starting with a letter (at most 32)",
                flipcard_text::safe::one_line(name)
            ),
            None,
        );
        return None;
    }
    let target_name = v
        .target
        .as_ref()
        .map_or(name.as_str(), |t| t.value.as_str());
    let target_span = v
        .target
        .as_ref()
        .map_or(v.name.span.clone(), |t| t.span.clone());
    let Some(target) = scene.target(target_name) else {
        let names = scene.names();
        let hint = suggest::did_you_mean(target_name, names.iter().map(String::as_str))
            .or_else(|| Some(format!("numbers of this scene: {}", names.join(", "))));
        let hint = match &v.target {
            None => hint.map(|h| format!("{h}; or name it with `target`: {name} = {{ range = […], target = \"initial.theta\" }}")),
            Some(_) => hint,
        };
        rep.error(
            target_span,
            format!(
                "`{target_name}` in `vary` of {what} is not a number of the scene: a varied number sets a parameter or `initial.VAR` of a system, `inertia[i]` or `omega[i]` of a rigid body"
            ),
            hint,
        );
        return None;
    };
    let scale = v.scale.as_ref().map_or(1.0, |s| s.value);
    if let Some(s) = &v.scale
        && !(s.value.is_finite() && s.value != 0.0)
    {
        rep.error(
            s.span.clone(),
            format!(
                "`vary.{name}`: `scale` is {}; the scene gets value × scale, a finite number other than 0",
                Shown(s.value)
            ),
            Some("degrees shown, radians run: scale = 0.017453292519943295".into()),
        );
        return None;
    }
    let draw = match (&v.range, &v.values) {
        (Some(_), Some(values)) => {
            rep.error(
                values.span.clone(),
                format!("`vary.{name}` has both `range` and `values`"),
                Some("one of them".into()),
            );
            return None;
        }
        (None, None) => {
            rep.error(
                v.span.clone(),
                format!("`vary.{name}` says neither `range` nor `values`"),
                Some(format!(
                    "{name} = [lo, hi], or {name} = {{ values = [ … ] }}"
                )),
            );
            return None;
        }
        (Some(r), None) => {
            let [lo, hi] = r.items.as_slice() else {
                rep.error(
                    r.span.clone(),
                    format!(
                        "`vary.{name}` has {} numbers; a range is two, `[lo, hi]`",
                        r.items.len()
                    ),
                    Some(format!("a list of values: {name} = {{ values = [ … ] }}")),
                );
                return None;
            };
            for n in [lo, hi] {
                if !n.value.is_finite() {
                    rep.error(
                        n.span.clone(),
                        format!("`vary.{name}`: {} is not a finite number", Shown(n.value)),
                        None,
                    );
                    return None;
                }
            }
            if !(hi.value - lo.value).is_finite() {
                rep.error(
                    r.span.clone(),
                    format!(
                        "`vary.{name}`: the range [{}, {}] is wider than a number can span",
                        Shown(lo.value),
                        Shown(hi.value)
                    ),
                    None,
                );
                return None;
            }
            if lo.value >= hi.value {
                rep.error(
                    r.span.clone(),
                    format!(
                        "`vary.{name}`: the range [{}, {}] is not low to high",
                        Shown(lo.value),
                        Shown(hi.value)
                    ),
                    Some("[lo, hi] with lo < hi; one number needs no `vary`".into()),
                );
                return None;
            }
            let step = match &v.step {
                None => None,
                Some(s) if s.value.is_finite() && s.value > 0.0 => {
                    if (hi.value - lo.value) / s.value > knob::MAX_STEPS {
                        rep.error(
                            s.span.clone(),
                            format!(
                                "`vary.{name}`: `step` {} cuts the range into more than {} steps",
                                Shown(s.value),
                                knob::MAX_STEPS
                            ),
                            None,
                        );
                        return None;
                    }
                    Some(s.value)
                }
                Some(s) => {
                    rep.error(
                        s.span.clone(),
                        format!(
                            "`vary.{name}`: `step` is {}; a step is a positive, finite number",
                            Shown(s.value)
                        ),
                        None,
                    );
                    return None;
                }
            };
            Draw::Range {
                min: lo.value,
                max: hi.value,
                step,
            }
        }
        (None, Some(values)) => {
            if let Some(s) = &v.step {
                rep.error(
                    s.span.clone(),
                    format!("`vary.{name}`: `step` goes with a `range`, not with `values`"),
                    None,
                );
                return None;
            }
            if values.items.len() < 2 || values.items.len() > MAX_VALUES {
                rep.error(
                    values.span.clone(),
                    format!(
                        "`vary.{name}` lists {} values; a varied number has 2 to {MAX_VALUES}",
                        values.items.len()
                    ),
                    None,
                );
                return None;
            }
            if let Some(n) = values.items.iter().find(|n| !n.value.is_finite()) {
                rep.error(
                    n.span.clone(),
                    format!("`vary.{name}`: {} is not a finite number", Shown(n.value)),
                    None,
                );
                return None;
            }
            Draw::Values(values.items.iter().map(|n| n.value).collect())
        }
    };
    let varied = Varied {
        name: name.clone(),
        target,
        draw,
        scale,
        decimals,
    };
    // The simulator's own acceptance at the ends and the middle (each
    // number alone; `check` runs whole variants).
    for value in varied.samples() {
        if let Some(why) = scene.refusal(&varied.target, value * scale) {
            rep.error(
                v.span.clone(),
                format!(
                    "`vary.{name}` at {}: the simulator refuses the scene: {why}",
                    Shown(value)
                ),
                Some("narrow the range to values the scene runs at".into()),
            );
            return None;
        }
    }
    Some(varied)
}
