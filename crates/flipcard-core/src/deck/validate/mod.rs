//! The validated stage: raw deck and content files → domain types, with
//! every problem reported. Nothing is built when something is wrong; the
//! checks still all run so one pass reports everything.

pub mod answer;
pub mod cloze;
pub mod content;
pub mod derivation;
pub mod formula;
pub mod knob;
pub mod misconception;
pub mod prose;
pub mod scene;
pub mod system;
pub mod text;
pub mod vary;

use std::collections::HashMap;

pub use crate::deck::id::is_id;
use crate::deck::model::{Card, CardKind, Explain, Prompt, Scene, SystemScene, Text};
use crate::deck::raw::{List, RawAnswer, RawCard, RawDeckFile, RawPrompt, RawText, Span, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;

use text::{Kind, Langs};

/// The id shape of `s` (lowercased, other characters turned into `-`).
fn slug(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars().flat_map(char::to_lowercase) {
        if c.is_ascii_lowercase() || c.is_ascii_digit() {
            out.push(c);
        } else if !out.ends_with('-') {
            out.push('-');
        }
    }
    out.trim_matches('-').to_string()
}

/// Checks an id's shape; false (and reported) when it is not an id.
pub fn id(rep: &mut FileReport, s: &Str, kind: &str) -> bool {
    if is_id(&s.value) {
        return true;
    }
    let suggestion = slug(&s.value);
    let hint = if suggestion.is_empty() {
        "ids are lowercase letters and digits joined by single hyphens, e.g. `middle-axis`"
            .to_string()
    } else {
        format!("ids are lowercase letters and digits joined by single hyphens: `{suggestion}`")
    };
    rep.error(
        s.span.clone(),
        format!("{kind} id `{}` is not a valid id", s.value.escape_debug()),
        Some(hint),
    );
    false
}

/// Reports each id used a second time, pointing back at the first.
pub(crate) fn unique(rep: &mut FileReport, ids: &[&Str], kind: &str) -> bool {
    let mut seen: HashMap<&str, &Span> = HashMap::new();
    let mut ok = true;
    for s in ids {
        match seen.get(s.value.as_str()) {
            Some(first) => {
                let line = rep.line_of(first.start);
                rep.error(
                    s.span.clone(),
                    format!("duplicate {kind} id `{}`", s.value),
                    Some(format!("first used on line {line}; ids must be unique")),
                );
                ok = false;
            }
            None => {
                seen.insert(&s.value, &s.span);
            }
        }
    }
    ok
}

/// What the links of one kind can name: the ids as written, and what is
/// known of the items whose id is broken. A link that names nothing may be
/// meant for one of those, whose own error already says what is wrong.
#[derive(Debug, Clone, Default)]
pub struct Targets {
    pub ids: Vec<String>,
    /// Some item has no id that could be read (missing, or not a string).
    pub unnamed: bool,
    /// The id shape ([`slug`]) of each id that is not a valid id.
    pub misshapen: Vec<String>,
    /// Ids that exist somewhere else, where they are reported as missing
    /// from here (a section in a translation only).
    pub elsewhere: Vec<String>,
}

impl Targets {
    pub fn of<'a>(ids: impl IntoIterator<Item = Option<&'a Str>>) -> Targets {
        let mut t = Targets::default();
        for id in ids {
            match id {
                Some(s) => {
                    if !is_id(&s.value) {
                        t.misshapen.push(slug(&s.value));
                    }
                    t.ids.push(s.value.clone());
                }
                None => t.unnamed = true,
            }
        }
        t
    }

    pub fn contains(&self, name: &str) -> bool {
        self.ids.iter().any(|i| i == name)
    }

    /// Whether `name` may be the id of an item whose id is broken: one has
    /// none, or one is close to it once made an id (`Stability`, or
    /// `$\frac{body-frame` where an escape ate a letter and more was pasted).
    pub(crate) fn may_mean(&self, name: &str) -> bool {
        let wanted = slug(name);
        let near = |m: &String| {
            let contains = wanted.len() >= 3 && m.len() >= 3;
            contains && (m.contains(&wanted) || wanted.contains(m.as_str()))
        };
        self.unnamed
            || suggest::closest(&wanted, self.misshapen.iter().map(String::as_str)).is_some()
            || self.misshapen.iter().any(near)
            || self.elsewhere.iter().any(|e| e == name)
    }
}

/// Checks that `s` names one of `targets`; `targets` is `None` when they
/// could not be read (their own errors say why), and then nothing is said.
/// A link that may be meant for an item with a broken id is not reported
/// either (it fails quietly): fixing the id fixes it.
pub fn link(
    rep: &mut FileReport,
    s: &Str,
    targets: Option<&Targets>,
    kind: &str,
    field: &str,
) -> bool {
    let Some(targets) = targets else {
        return true;
    };
    if targets.contains(&s.value) {
        return true;
    }
    if targets.may_mean(&s.value) {
        return false;
    }
    let hint =
        suggest::did_you_mean(&s.value, targets.ids.iter().map(String::as_str)).or_else(|| {
            if targets.ids.is_empty() {
                Some(format!("the deck has no {kind}s"))
            } else {
                None
            }
        });
    // Every link to a missing id has one cause: the id (often renamed).
    rep.error_once(
        format!("{kind} `{}` does not exist", s.value),
        s.span.clone(),
        format!(
            "`{field}` links to {kind} `{}`, which does not exist",
            s.value
        ),
        hint,
    );
    false
}

/// What the `[deck]` table says, as far as it is valid.
#[derive(Debug, Clone, Default)]
pub struct Header {
    pub id: Option<String>,
    pub title: Option<Text>,
    pub description: Option<Option<Text>>,
    pub langs: Langs,
    /// Each declared language with the span of its entry in `languages`.
    pub lang_spans: Vec<(String, Span)>,
    /// The units the deck declares.
    pub units: Vec<flipcard_text::units::Declared>,
    /// The deck it sits under (`parent`), when valid.
    pub parent: Option<String>,
}

/// A BCP 47 tag's shape: a 2-8 letter language subtag, then subtags of
/// 1-8 letters or digits (`en`, `hi-Latn`, `pt-BR`).
pub fn is_lang_tag(s: &str) -> bool {
    let mut parts = s.split('-');
    let first_ok = parts
        .next()
        .is_some_and(|p| (2..=8).contains(&p.len()) && p.bytes().all(|b| b.is_ascii_alphabetic()));
    first_ok
        && parts.all(|p| (1..=8).contains(&p.len()) && p.bytes().all(|b| b.is_ascii_alphanumeric()))
}

/// Checks `[deck]`: id (and that it names the file), languages, title.
pub fn header(rep: &mut FileReport, raw: &RawDeckFile, file_stem: &str) -> Header {
    let mut h = Header::default();
    let Some(d) = &raw.deck else {
        return h;
    };
    if let Some(s) = &d.id
        && id(rep, s, "deck")
    {
        if s.value != file_stem {
            rep.error(
                s.span.clone(),
                format!(
                    "deck id `{}` does not match the file name `{file_stem}.toml`",
                    s.value
                ),
                Some(format!(
                    "rename the file to {}.toml or set id = \"{file_stem}\"",
                    s.value
                )),
            );
        }
        h.id = Some(s.value.clone());
    }
    if let Some(list) = &d.languages {
        h.langs = languages(rep, list);
        if h.langs.known && declared_differently(rep, raw, list) {
            // Every text would say it lacks one language and has another.
            h.langs.known = false;
        }
        h.lang_spans = list
            .items
            .iter()
            .map(|s| (s.value.clone(), s.span.clone()))
            .collect();
    }
    h.title = d
        .title
        .as_ref()
        .and_then(|t| text::text(rep, t, &h.langs, "the deck title"));
    for e in d.units.iter().flat_map(|u| &u.entries) {
        match flipcard_text::units::declare(&e.key.value, &e.value.value) {
            Ok(unit) => h.units.push(unit),
            Err(err @ flipcard_text::units::DeclareError::BadValue(_)) => {
                rep.error(e.value.span.clone(), err.to_string(), None)
            }
            Err(err) => rep.error(
                e.key.span.clone(),
                err.to_string(),
                Some(
                    "declare a unit the learner may type, e.g. units = { ly = \"9.4607e15 m\" }"
                        .to_string(),
                ),
            ),
        }
    }
    if let Some(p) = &d.parent
        && id(rep, p, "parent deck")
    {
        if h.id.as_deref() == Some(p.value.as_str()) {
            rep.error(
                p.span.clone(),
                format!("deck `{}` cannot be its own parent", p.value),
                Some("name the deck it belongs under, or remove `parent`".to_string()),
            );
        } else {
            h.parent = Some(p.value.clone());
        }
    }
    h.description = match &d.description {
        None => Some(None),
        Some(t) => text::text(rep, t, &h.langs, "the deck description").map(Some),
    };
    h
}

fn languages(rep: &mut FileReport, list: &List<Str>) -> Langs {
    let mut ok = true;
    if list.items.is_empty() {
        rep.error(
            list.span.clone(),
            "`languages` is empty: declare at least one language",
            Some("languages = [\"en\"]".to_string()),
        );
        ok = false;
    }
    let mut seen: Vec<&str> = Vec::new();
    for s in &list.items {
        if !is_lang_tag(&s.value) {
            rep.error(
                s.span.clone(),
                format!("`{}` is not a BCP 47 language tag", s.value.escape_debug()),
                Some("e.g. \"en\", \"hi-Latn\" (Hindi in Latin script), \"pt-BR\"".to_string()),
            );
            ok = false;
        } else if seen.contains(&s.value.as_str()) {
            rep.error(
                s.span.clone(),
                format!("language `{}` is declared twice", s.value),
                None,
            );
            ok = false;
        }
        seen.push(&s.value);
    }
    Langs {
        list: list.items.iter().map(|s| s.value.clone()).collect(),
        known: ok,
    }
}

/// Reports a declared language that no text gives while the texts give an
/// undeclared one like it (`hi-latn` declared, `hi-Latn` written): the
/// declaration is the one mistake. True when reported.
fn declared_differently(rep: &mut FileReport, raw: &RawDeckFile, list: &List<Str>) -> bool {
    let texts = texts_by_language(raw);
    if texts.is_empty() {
        return false;
    }
    let declared: Vec<&str> = list.items.iter().map(|s| s.value.as_str()).collect();
    let used = |lang: &str| texts.iter().filter(|keys| keys.contains(&lang)).count();
    let mut undeclared: Vec<&str> = texts
        .iter()
        .flatten()
        .copied()
        .filter(|k| !declared.contains(k))
        .collect();
    undeclared.sort_unstable();
    undeclared.dedup();
    let unused: Vec<&Str> = list.items.iter().filter(|s| used(&s.value) == 0).collect();
    let mut found = false;
    for s in &unused {
        let like = suggest::closest(&s.value, undeclared.iter().copied())
            .or_else(|| (unused.len() == 1 && undeclared.len() == 1).then(|| undeclared[0]));
        let Some(written) = like else { continue };
        rep.error(
            s.span.clone(),
            format!(
                "language `{}` is declared, but the texts give `{written}` instead",
                s.value
            ),
            Some(format!(
                "declare \"{written}\" (tags are matched exactly, in texts and content file names)"
            )),
        );
        found = true;
    }
    found
}

/// The language keys of every text written as a table of languages.
fn texts_by_language(raw: &RawDeckFile) -> Vec<Vec<&str>> {
    let mut texts: Vec<&RawText> = Vec::new();
    if let Some(d) = &raw.deck {
        texts.extend(d.title.iter().chain(&d.description));
    }
    for c in &raw.cards {
        texts.extend(c.front.iter().chain(&c.back));
    }
    for p in &raw.prompts {
        texts.extend(&p.question);
        match &p.answer {
            Some(RawAnswer::Choice {
                choices: Some(list),
                ..
            }) => texts.extend(list.items.iter().filter_map(|c| c.label.as_ref())),
            Some(RawAnswer::Number { formula, .. }) => texts.extend(formula),
            _ => {}
        }
    }
    for s in &raw.scenes {
        texts.extend(&s.title);
    }
    for m in &raw.misconceptions {
        texts.extend(m.title.iter().chain(&m.why_it_seems_right).chain(&m.fix));
    }
    texts.extend(derivation::texts(raw));
    texts
        .into_iter()
        .filter_map(|t| match t {
            RawText::ByLang { entries, .. } => {
                Some(entries.iter().map(|(k, _)| k.value.as_str()).collect())
            }
            RawText::Plain(_) => None,
        })
        .collect()
}

/// What the deck file's cards, prompts and scenes validate into.
pub struct Body {
    pub cards: Vec<Card>,
    pub prompts: Vec<Prompt>,
    pub scenes: Vec<Scene>,
    pub systems: Vec<SystemScene>,
    pub misconceptions: Vec<crate::deck::model::Misconception>,
    /// The scenes' knobs and explore measures (`knob`).
    pub explore: Vec<crate::deck::model::Explore>,
    /// The deck's derivations (`derivation`).
    pub derivations: Vec<crate::deck::model::Derivation>,
}

/// Checks cards, prompts and scenes; `section_ids` are the explanation
/// sections links may name (`None` when the content could not be read).
pub fn body(
    rep: &mut FileReport,
    raw: &RawDeckFile,
    langs: &Langs,
    section_ids: Option<&Targets>,
    (anchors, titles): (&Anchors, &prose::Titles),
) -> Option<Body> {
    let card_ids: Vec<&Str> = raw.cards.iter().filter_map(|c| c.id.as_ref()).collect();
    let prompt_ids: Vec<&Str> = raw.prompts.iter().filter_map(|p| p.id.as_ref()).collect();
    let scene_ids: Vec<&Str> = raw.scenes.iter().filter_map(|s| s.id.as_ref()).collect();
    let mut ok = true;
    for (list, kind) in [
        (&card_ids, "card"),
        (&prompt_ids, "prompt"),
        (&scene_ids, "scene"),
    ] {
        for s in list {
            ok &= id(rep, s, kind);
        }
        ok &= unique(rep, list, kind);
    }
    let prompt_names = Targets::of(raw.prompts.iter().map(|p| p.id.as_ref()));
    let scene_names = Targets::of(raw.scenes.iter().map(|s| s.id.as_ref()));

    if raw.deck.is_some()
        && raw.cards.is_empty()
        && raw.prompts.is_empty()
        && raw.derivations.is_empty()
    {
        rep.warning(
            raw.deck.as_ref().map_or(0..0, |d| d.span.clone()),
            "the deck has no cards and no prompts",
            None,
        );
    }

    let mut cards = Vec::new();
    for c in &raw.cards {
        let owner = named("card", &c.id);
        text_prose(rep, &c.front, "the front", &owner, langs, titles);
        text_prose(rep, &c.back, "the back", &owner, langs, titles);
        match card(rep, c, langs, (section_ids, anchors), &prompt_names) {
            Some(c) => cards.push(c),
            None => ok = false,
        }
    }
    let quantities: HashMap<&str, Option<Vec<String>>> = raw
        .scenes
        .iter()
        .filter_map(|s| {
            let id = s.id.as_ref()?.value.as_str();
            Some((id, s.system.as_ref().map(system::quantities)))
        })
        .collect();
    // The numbers of each scene a number answer's slips may name.
    let scopes: HashMap<&str, Vec<(String, f64)>> = raw
        .scenes
        .iter()
        .filter_map(|s| Some((s.id.as_ref()?.value.as_str(), scope(s)?)))
        .collect();
    let mut prompts = Vec::new();
    for p in &raw.prompts {
        let owner = named("prompt", &p.id);
        text_prose(rep, &p.question, "the question", &owner, langs, titles);
        let kind = p
            .scene
            .as_ref()
            .and_then(|s| quantities.get(s.value.as_str()))
            .map(|q| match q {
                Some(names) => answer::SceneKind::System(names),
                None => answer::SceneKind::Rigid,
            });
        let scope = p
            .scene
            .as_ref()
            .and_then(|s| scopes.get(s.value.as_str()))
            .map(Vec::as_slice);
        match prompt(
            rep,
            p,
            langs,
            (section_ids, anchors),
            &scene_names,
            (kind, scope),
        ) {
            Some(p) => prompts.push(p),
            None => ok = false,
        }
    }
    let mut scenes = Vec::new();
    let mut systems = Vec::new();
    let mut explore = Vec::new();
    for s in &raw.scenes {
        let what =
            s.id.as_ref()
                .filter(|i| is_id(&i.value))
                .map_or("a scene".to_string(), |i| format!("scene `{}`", i.value));
        if let Some(sys) = &s.system {
            match system::scene(rep, s, sys, langs, &what) {
                Some(sys) => {
                    match knob::explore(rep, s, langs, &what, knob::Turned::System(&sys)) {
                        Some(e) => explore.extend(e),
                        None => ok = false,
                    }
                    systems.push(sys)
                }
                None => ok = false,
            }
            continue;
        }
        match scene::scene(rep, s, langs, &what) {
            Some(body) => {
                match knob::explore(rep, s, langs, &what, knob::Turned::Rigid(&body)) {
                    Some(e) => explore.extend(e),
                    None => ok = false,
                }
                scenes.push(body)
            }
            None => ok = false,
        }
    }
    // Each varied prompt against the scene it varies.
    for p in raw.prompts.iter().filter(|p| p.vary.is_some()) {
        let (Some(id), Some(scene)) = (&p.id, &p.scene) else {
            continue;
        };
        let Some(prompt) = prompts.iter_mut().find(|q| q.id == id.value) else {
            continue;
        };
        let what = format!("prompt `{}`", id.value);
        let turned = match (
            systems.iter().find(|s| s.id == scene.value),
            scenes.iter().find(|s| s.id == scene.value),
        ) {
            (Some(sys), _) => knob::Turned::System(sys),
            (None, Some(body)) => knob::Turned::Rigid(body),
            // The scene's own error is reported.
            (None, None) => {
                ok = false;
                continue;
            }
        };
        if matches!(prompt.answer, crate::deck::model::Answer::Formula(_)) {
            rep.error(
                p.vary.as_ref().map_or(p.span.clone(), |v| v.span.clone()),
                format!("{what} is answered by a formula, which `vary` cannot change"),
                Some("vary a prompt whose answer the run measures (a choice or a number)".into()),
            );
            ok = false;
            continue;
        }
        match vary::vary(rep, p, &prompt.question, &what, turned) {
            Some(v) => prompt.vary = v,
            None => ok = false,
        }
    }
    let misconceptions = misconception::declared(rep, raw, langs, (section_ids, anchors));
    ok &= misconception::uses(rep, raw);
    let derivations = derivation::derivations(rep, raw, langs, (section_ids, anchors));
    ok.then_some(Body {
        derivations: derivations?,
        cards,
        prompts,
        scenes,
        systems,
        misconceptions: misconceptions?,
        explore,
    })
}

/// Prose on a card (front and back) or a prompt's question that names a
/// section by a title none has.
fn text_prose(
    rep: &mut FileReport,
    text: &Option<RawText>,
    part: &str,
    owner: &str,
    langs: &Langs,
    titles: &prose::Titles,
) {
    match text {
        Some(RawText::Plain(s)) => {
            if let Some(lang) = langs.list.first() {
                let what = format_args!("{part} of {owner}");
                prose::check(rep, s, lang, titles, prose::Place::Card, what);
            }
        }
        Some(RawText::ByLang { entries, .. }) => {
            for (lang, s) in entries {
                let what = format_args!("the `{}` text of {part} of {owner}", lang.value);
                prose::check(rep, s, &lang.value, titles, prose::Place::Card, what);
            }
        }
        None => {}
    }
}

fn named(kind: &str, id: &Option<Str>) -> String {
    match id {
        Some(s) if is_id(&s.value) => format!("{kind} `{}`", s.value),
        _ => format!("a {kind}"),
    }
}

fn tags(rep: &mut FileReport, tags: &Option<List<Str>>) -> Option<Vec<String>> {
    let Some(list) = tags else {
        return Some(Vec::new());
    };
    let mut ok = true;
    for t in &list.items {
        ok &= text::string(rep, t, Kind::Plain, "a tag");
    }
    ok.then(|| list.items.iter().map(|t| t.value.clone()).collect())
}

/// The numbers of a scene as written that a slip's formula may name (see
/// `flipcard_sim::scene::quantities`): a rigid body's moments, initial spin
/// and k, or a system's params. `None` for a rigid body whose numbers are
/// no body's: the scene's own check reports them, and a slip on it is not
/// reported again for naming `k`.
fn scope(s: &crate::deck::raw::RawScene) -> Option<Vec<(String, f64)>> {
    if let Some(sys) = &s.system {
        return Some(
            sys.params
                .iter()
                .flat_map(|p| &p.entries)
                .filter(|e| e.value.value.is_finite())
                .map(|e| (e.key.value.clone(), e.value.value))
                .collect(),
        );
    }
    let three = |l: &Option<List<crate::deck::raw::Num>>| -> Option<[f64; 3]> {
        let l = l.as_ref()?;
        let v: Vec<f64> = l.items.iter().map(|n| n.value).collect();
        let a: [f64; 3] = v.try_into().ok()?;
        a.iter().all(|x| x.is_finite()).then_some(a)
    };
    let names = flipcard_sim::scene::quantities::rigid(three(&s.inertia)?, three(&s.omega)?);
    (names.len() == flipcard_sim::scene::quantities::RIGID.len()).then_some(names)
}

/// The anchors (`{#name}` lines) of each section in each content file that
/// could be read, for `explain = "section#anchor"`.
#[derive(Debug, Clone, Default)]
pub struct Anchors {
    /// By section id: each language read, with the anchors of the section's
    /// body there (a language whose file lacks the section is left out;
    /// its own error says so).
    pub of: HashMap<String, Vec<(String, Vec<String>)>>,
}

/// An `explain` link: a section, or `section#anchor` with the anchor in
/// the section's body in every language.
fn explain_link(
    rep: &mut FileReport,
    s: &Option<Str>,
    (targets, anchors): (Option<&Targets>, &Anchors),
) -> Option<Option<Explain>> {
    let Some(s) = s else {
        return Some(None);
    };
    let Some((section, anchor)) = s.value.split_once('#') else {
        return link(rep, s, targets, "section", "explain")
            .then(|| Some(Explain::from(s.value.as_str())));
    };
    let section_at = Str {
        value: section.to_string(),
        span: system::span_in(rep, s, 0, section.len()),
    };
    let anchor_span = system::span_in(rep, s, section.len() + 1, anchor.len());
    if !link(rep, &section_at, targets, "section", "explain") {
        return None;
    }
    if !is_id(anchor) {
        rep.error(
            anchor_span,
            format!(
                "anchor `{}` in `explain` is not a valid id",
                flipcard_text::safe::one_line(anchor)
            ),
            Some(
                "explain = \"section-id#anchor\", where the section's body has a line {#anchor} above the paragraph"
                    .to_string(),
            ),
        );
        return None;
    }
    let Some(langs) = anchors.of.get(section) else {
        // Content that could not be read: its own errors say why.
        return Some(Some(Explain::from(s.value.as_str())));
    };
    let lacking: Vec<&str> = langs
        .iter()
        .filter(|(_, names)| !names.iter().any(|n| n == anchor))
        .map(|(lang, _)| lang.as_str())
        .collect();
    if lacking.is_empty() {
        return Some(Some(Explain::from(s.value.as_str())));
    }
    let known: Vec<&str> = {
        let mut all: Vec<&str> = langs
            .iter()
            .flat_map(|(_, names)| names.iter().map(String::as_str))
            .collect();
        all.sort_unstable();
        all.dedup();
        all
    };
    let files = if lacking.len() == langs.len() {
        "any language's content file".to_string()
    } else {
        let quoted: Vec<String> = lacking.iter().map(|l| format!("`{l}`")).collect();
        format!("the {} content file", quoted.join(" and "))
    };
    let elsewhere = lacking.len() < langs.len();
    let hint = if elsewhere {
        Some(format!(
            "put a line {{#{anchor}}} above the same paragraph of section `{section}` in {files}; every language opens at the anchor"
        ))
    } else {
        suggest::did_you_mean(anchor, known.iter().copied())
    };
    let hint = hint.or_else(|| {
        Some(if known.is_empty() {
            format!(
                "put a line {{#{anchor}}} above the paragraph in section `{section}` of every language's file"
            )
        } else {
            format!("anchors of section `{section}`: {}", known.join(", "))
        })
    });
    rep.error(
        anchor_span,
        format!(
            "`explain` links to anchor `{anchor}` of section `{section}`, which is not in {files}"
        ),
        hint,
    );
    None
}

fn optional_link(
    rep: &mut FileReport,
    s: &Option<Str>,
    targets: Option<&Targets>,
    kind: &str,
    field: &str,
) -> Option<Option<String>> {
    match s {
        None => Some(None),
        Some(s) => link(rep, s, targets, kind, field).then(|| Some(s.value.clone())),
    }
}

fn card(
    rep: &mut FileReport,
    raw: &RawCard,
    langs: &Langs,
    sections: (Option<&Targets>, &Anchors),
    prompt_ids: &Targets,
) -> Option<Card> {
    let what = named("card", &raw.id);
    let kind = match &raw.kind {
        None => Some(CardKind::Basic),
        Some(k) => {
            let kinds = CardKind::ALL;
            let found = kinds.into_iter().find(|c| c.as_str() == k.value);
            if found.is_none() {
                let names = kinds.map(CardKind::as_str);
                rep.error(
                    k.span.clone(),
                    format!("unknown card kind `{}`", k.value),
                    suggest::did_you_mean(&k.value, names)
                        .or_else(|| Some(format!("kinds: {}", names.join(", ")))),
                );
            }
            found
        }
    };
    if kind == Some(CardKind::Cloze) {
        if let Some(f) = &raw.front {
            rep.error(
                f.span(),
                format!("cloze {what} has `text`, not `front`"),
                Some("write the deletions in text = { en = '{{c1::answer}} …' }".to_string()),
            );
        }
    } else if let Some(t) = &raw.text {
        rep.error(
            t.span(),
            format!("`text` belongs to cloze cards; {what} is not one"),
            Some("did you mean kind = \"cloze\"?".to_string()),
        );
    }
    let front = if kind == Some(CardKind::Cloze) {
        raw.text.as_ref().and_then(|t| {
            let text = text::text_of(
                rep,
                t,
                langs,
                format_args!("the text of {what}"),
                text::Kind::Cloze,
            );
            let deletions = cloze::deletions(rep, t, &what);
            text.filter(|_| deletions)
        })
    } else {
        raw.front
            .as_ref()
            .and_then(|t| text::text(rep, t, langs, format_args!("the front of {what}")))
    };
    let back = match &raw.back {
        // `back = ''`, written so: a card whose back is empty (an imported
        // Anki note's empty field); a back of only spaces is a mistake.
        Some(RawText::Plain(s)) if s.value.is_empty() => Some(Text::default()),
        Some(t) => text::text(rep, t, langs, format_args!("the back of {what}")),
        // Only cloze cards may leave the back out (it holds extra notes).
        None => Some(Text::default()),
    };
    let accept = accept(rep, raw, kind, &what, langs);
    let key = match (&raw.formula, kind) {
        (Some(f), Some(CardKind::Formula)) => formula::key(rep, f, &what).map(Some),
        (Some(f), _) => {
            let span = f
                .expected
                .as_ref()
                .map_or(f.span.clone(), |e| e.span.clone());
            rep.error(
                span,
                format!("`expected` and `vars` belong to formula cards; {what} is not one"),
                Some("did you mean kind = \"formula\"?".to_string()),
            );
            None
        }
        (None, _) => Some(None),
    };
    let explain = explain_link(rep, &raw.explain, sections);
    let prompt = optional_link(rep, &raw.prompt, Some(prompt_ids), "prompt", "prompt");
    let tags = tags(rep, &raw.tags);
    Some(Card {
        id: raw.id.as_ref()?.value.clone(),
        kind: kind?,
        front: front?,
        back: back?,
        accept: accept.as_ref()?.0.clone(),
        accept_by_lang: accept?.1,
        explain: explain?,
        prompt: prompt?,
        tags: tags?,
        formula: key?,
    })
}

/// Typed cards need accepted answers; on other kinds `accept` is a warning
/// (likely a forgotten `kind = "typed"`) and is dropped.
type Accepted = (Vec<String>, std::collections::BTreeMap<String, Vec<String>>);

fn accept(
    rep: &mut FileReport,
    raw: &RawCard,
    kind: Option<CardKind>,
    what: &str,
    langs: &Langs,
) -> Option<Accepted> {
    let mut ok = true;
    let mut by_lang = std::collections::BTreeMap::new();
    if let Some(a) = &raw.accept {
        for s in a.items() {
            ok &= text::string(rep, s, Kind::Plain, "an accepted answer");
        }
        if let crate::deck::raw::RawAccept::ByLang { entries, .. } = a {
            for (lang, list) in entries {
                if langs.known && !langs.list.contains(&lang.value) {
                    let hint = crate::deck::suggest::did_you_mean(
                        &lang.value,
                        langs.list.iter().map(String::as_str),
                    )
                    .or_else(|| Some(format!("the deck's languages: {}", langs.list.join(", "))));
                    rep.error(
                        lang.span.clone(),
                        format!(
                            "`accept` of {what} gives answers in `{}`, which the deck does not declare",
                            lang.value
                        ),
                        hint,
                    );
                    ok = false;
                }
                let values: Vec<String> = list.items.iter().map(|s| s.value.clone()).collect();
                by_lang.insert(lang.value.clone(), values);
            }
        }
    }
    // Every answer, the primary language's first.
    let all = |a: &crate::deck::raw::RawAccept| -> Vec<String> {
        let mut out: Vec<String> = langs
            .list
            .first()
            .and_then(|p| by_lang.get(p))
            .cloned()
            .unwrap_or_default();
        for s in a.items() {
            if !out.contains(&s.value) {
                out.push(s.value.clone());
            }
        }
        out
    };
    match (kind, &raw.accept) {
        (Some(CardKind::Typed), Some(a)) if !a.items().is_empty() => {
            ok.then(|| (all(a), by_lang.clone()))
        }
        (Some(CardKind::Typed), Some(a)) => {
            rep.error(
                a.span(),
                format!("`accept` of typed {what} is empty"),
                Some("list at least one accepted answer".to_string()),
            );
            None
        }
        (Some(CardKind::Typed), None) => {
            rep.error(
                raw.span.clone(),
                format!("typed {what} has no `accept` list"),
                Some("accept = ['answer', 'other spelling']".to_string()),
            );
            None
        }
        (Some(_), Some(a)) => {
            rep.warning(
                a.span(),
                format!("`accept` is only used by typed cards; ignored on {what}"),
                Some("did you mean kind = \"typed\"?".to_string()),
            );
            ok.then(|| (Vec::new(), std::collections::BTreeMap::new()))
        }
        (Some(_), None) => Some((Vec::new(), std::collections::BTreeMap::new())),
        (None, _) => None,
    }
}

fn prompt(
    rep: &mut FileReport,
    raw: &RawPrompt,
    langs: &Langs,
    sections: (Option<&Targets>, &Anchors),
    scene_ids: &Targets,
    (kind, scope): (Option<answer::SceneKind>, Option<answer::Scope>),
) -> Option<Prompt> {
    let what = named("prompt", &raw.id);
    let question = raw
        .question
        .as_ref()
        .and_then(|t| text::text(rep, t, langs, &format!("the question of {what}")));
    let scene = raw
        .scene
        .as_ref()
        .and_then(|s| link(rep, s, Some(scene_ids), "scene", "scene").then(|| s.value.clone()));
    let explain = explain_link(rep, &raw.explain, sections);
    let tags = tags(rep, &raw.tags);
    let answer = raw
        .answer
        .as_ref()
        .and_then(|a| answer::answer(rep, a, langs, &what, kind, scope, raw.vary.is_some()));
    let measured = match (raw.answer.as_ref(), answer.as_ref()) {
        (Some(r), Some(a)) => answer::measured(rep, r, a, langs)?,
        _ => None,
    };
    Some(Prompt {
        id: raw.id.as_ref()?.value.clone(),
        question: question?,
        scene: scene?,
        explain: explain?,
        answer: answer?,
        tags: tags?,
        measured,
        // Checked against the scene once the scenes are (`body`).
        vary: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_lowercase_words_joined_by_hyphens() {
        for ok in ["a", "middle-axis", "euler-2", "x1-y2-z3"] {
            assert!(is_id(ok), "{ok}");
        }
        for bad in ["", "-a", "a-", "a--b", "Middle", "a_b", "a b", "é", "a.b"] {
            assert!(!is_id(bad), "{bad}");
        }
        assert_eq!(slug("Middle_Axis 2"), "middle-axis-2");
    }

    #[test]
    fn links_may_mean_an_item_whose_id_is_broken() {
        let s = |v: &str| Str {
            value: v.to_string(),
            span: 0..0,
        };
        let (bad, typo, ate) = (s("Middle Axis"), s("stabilty"), s("$\u{c}rac{body-frame"));
        let t = Targets::of([Some(&bad), Some(&s("racket")), Some(&typo), Some(&ate)]);
        assert!(t.contains("racket") && !t.may_mean("racket"));
        assert!(t.may_mean("middle-axis"));
        assert!(t.may_mean("body-frame"));
        // A valid id that is merely close to another is a link to report.
        assert!(!t.may_mean("stability"));
        assert!(!t.may_mean("earth"));
        assert!(Targets::of([None, Some(&bad)]).may_mean("earth"));
    }

    #[test]
    fn language_tags_have_the_bcp47_shape() {
        for ok in ["en", "hi-Latn", "pt-BR", "zh-Hant-TW", "de-CH-1996"] {
            assert!(is_lang_tag(ok), "{ok}");
        }
        for bad in ["", "e", "en_", "en_US", "hi-", "-en", "englishlanguage"] {
            assert!(!is_lang_tag(bad), "{bad}");
        }
    }
}
