//! Explanation sections across the per-language content files: the same
//! section ids in every language, links between sections that resolve.

use crate::deck::model::{Section, Text};
use crate::deck::raw::{RawContentFile, RawSection, Str};
use crate::deck::report::FileReport;
use flipcard_text::LangMap;

use super::prose::{self, Place};
use super::text::{self, Kind};
use super::{Targets, id, link, unique};
use crate::deck::suggest;

/// Sections named in one error before "and N more".
const MISSING_LISTED: usize = 3;

/// One language's content file: its report, and what was read (`None` when
/// the file is missing or does not parse).
pub struct ContentFile<'s> {
    pub lang: String,
    pub rep: FileReport<'s>,
    pub raw: Option<RawContentFile>,
}

/// The sections, when every file is valid, and the section ids links may
/// name (from the primary language's file), when that file could be read.
pub struct Sections {
    pub sections: Option<Vec<Section>>,
    pub ids: Option<Targets>,
    /// The anchors of each section in each file read.
    pub anchors: super::Anchors,
    /// The titles of each section in each file read, for prose that
    /// names a section by its title.
    pub titles: prose::Titles,
}

/// Checks every content file; `files[0]` is the primary language's.
pub fn sections(files: &mut [ContentFile]) -> Sections {
    let mut ok = true;
    // Per file: the section ids it defines.
    let mut ids_of: Vec<Option<Targets>> = Vec::new();
    for f in files.iter_mut() {
        let Some(raw) = &f.raw else {
            ids_of.push(None);
            ok = false;
            continue;
        };
        let ids: Vec<&Str> = raw.sections.iter().filter_map(|s| s.id.as_ref()).collect();
        for s in &ids {
            ok &= id(&mut f.rep, s, "section");
        }
        ok &= unique(&mut f.rep, &ids, "section");
        ids_of.push(Some(Targets::of(
            raw.sections.iter().map(|s| s.id.as_ref()),
        )));
    }
    let own_primary_ids = ids_of.first().cloned().flatten();
    let mut primary_ids = own_primary_ids.clone();
    // A section written only in a translation is reported there, once;
    // links to it are not reported again as naming nothing.
    if let Some(primary) = &mut primary_ids {
        for other in ids_of.iter().skip(1).flatten() {
            for id in &other.ids {
                if !primary.contains(id) && !primary.elsewhere.contains(id) {
                    primary.elsewhere.push(id.clone());
                }
            }
        }
    }

    // Each file's sections: its own checks, and links against the primary
    // file's ids (the ones used; a translation with other ids is reported
    // below, once, rather than again at every link to them).
    let titles = titles(files);
    let mut anchors = super::Anchors::default();
    for (f, own_ids) in files.iter_mut().zip(&ids_of) {
        let Some(raw) = &f.raw else { continue };
        let targets = primary_ids.as_ref().or(own_ids.as_ref());
        for s in &raw.sections {
            ok &= section_texts(&mut f.rep, s);
            if let (Some(sid), Some(body)) = (&s.id, &s.body) {
                let what = format!("the body of section `{}`", sid.value);
                prose::check(&mut f.rep, body, &f.lang, &titles, Place::Body, &what);
                let (names, fine) = section_anchors(&mut f.rep, sid, body);
                ok &= fine;
                anchors
                    .of
                    .entry(sid.value.clone())
                    .or_default()
                    .push((f.lang.clone(), names));
            }
            if let Some(see) = &s.see {
                for target in &see.items {
                    ok &= link(&mut f.rep, target, targets, "section", "see");
                }
            }
            // Inline `[text](#id)` links, reported at the id in the body.
            if let Some(body) = &s.body {
                let token = f
                    .rep
                    .source
                    .get(body.span.clone())
                    .unwrap_or("")
                    .to_string();
                let mut from = 0;
                for target in flipcard_text::markup::links(&body.value) {
                    let anchor = format!("](#{target})");
                    let span = match body.value[from..].find(&anchor) {
                        Some(i) => {
                            let id_at = from + i + 3;
                            from = id_at;
                            let (a, _) = crate::deck::tomlstr::locate(&token, id_at);
                            let (b, _) = crate::deck::tomlstr::locate(&token, id_at + target.len());
                            body.span.start + a..body.span.start + b
                        }
                        None => body.span.clone(),
                    };
                    let at = Str {
                        value: target,
                        span,
                    };
                    ok &= link(&mut f.rep, &at, targets, "section", "body");
                }
            }
        }
    }

    // The same ids in every language.
    if let (Some(primary), Some(primary_raw)) =
        (&own_primary_ids, files.first().and_then(|f| f.raw.clone()))
    {
        for i in 1..files.len() {
            let (Some(other), Some(other_raw)) = (ids_of[i].clone(), files[i].raw.clone()) else {
                continue;
            };
            ok &= same_sections(files, i, primary, &primary_raw, &other, &other_raw);
        }
    }

    let sections = if ok { build(files) } else { None };
    Sections {
        sections,
        ids: primary_ids,
        anchors,
        titles,
    }
}

/// Every section's title in every file read; unknown when a file could
/// not be read.
fn titles(files: &[ContentFile]) -> prose::Titles {
    let mut t = prose::Titles {
        of: Vec::new(),
        known: files
            .iter()
            .all(|f| f.raw.as_ref().is_some_and(|r| !r.unread)),
    };
    for f in files {
        for s in f.raw.iter().flat_map(|r| &r.sections) {
            if let (Some(id), Some(title)) = (&s.id, &s.title) {
                t.of.push((id.value.clone(), f.lang.clone(), title.value.clone()));
            }
        }
    }
    t
}

/// The anchors of a section's body (`{#name}` lines), each an id used once
/// in the body; false (and reported at the name) when one is not.
fn section_anchors(rep: &mut FileReport, sid: &Str, body: &Str) -> (Vec<String>, bool) {
    let mut names: Vec<String> = Vec::new();
    let mut ok = true;
    for (name, at) in flipcard_text::markup::anchors(&body.value) {
        let span = super::system::span_in(rep, body, at, name.len());
        if !super::is_id(&name) {
            rep.error(
                span,
                format!(
                    "anchor `{}` in section `{}` is not a valid id",
                    flipcard_text::safe::one_line(&name),
                    sid.value
                ),
                Some(
                    "anchors are ids like section ids: lowercase letters and digits joined by single hyphens"
                        .to_string(),
                ),
            );
            ok = false;
        } else if names.contains(&name) {
            rep.error(
                span,
                format!(
                    "anchor `{name}` is declared twice in section `{}`",
                    sid.value
                ),
                Some("each anchor names one place of the section".to_string()),
            );
            ok = false;
        } else {
            names.push(name);
        }
    }
    (names, ok)
}

/// Compares translation `i`'s section ids with the primary file's. Ids that
/// are broken are left to their own errors, and a section whose id differs
/// (a typo in one file) is one error in the translation, not also one for
/// the id it lacks.
fn same_sections(
    files: &mut [ContentFile],
    i: usize,
    primary: &Targets,
    primary_raw: &RawContentFile,
    other: &Targets,
    other_raw: &RawContentFile,
) -> bool {
    let primary_path = files[0].rep.path.clone();
    let other_path = files[i].rep.path.clone();
    let valid = |s: &RawSection| s.id.clone().filter(|sid| super::is_id(&sid.value));
    // A file whose sections could not all be read says so itself.
    let mut missing: Vec<Str> = primary_raw
        .sections
        .iter()
        .filter_map(valid)
        .filter(|_| !other_raw.unread)
        .filter(|sid| !other.contains(&sid.value) && !other.may_mean(&sid.value))
        .collect();
    let extra: Vec<Str> = other_raw
        .sections
        .iter()
        .filter_map(valid)
        .filter(|_| !primary_raw.unread)
        .filter(|sid| !primary.contains(&sid.value) && !primary.may_mean(&sid.value))
        .collect();
    let ok = missing.is_empty() && extra.is_empty();
    let single_pair = missing.len() == 1 && extra.len() == 1;
    let mut unpaired: Vec<&Str> = Vec::new();
    for sid in &extra {
        let partner = suggest::closest(&sid.value, missing.iter().map(|m| m.value.as_str()))
            .map(str::to_string)
            .or_else(|| single_pair.then(|| missing[0].value.clone()));
        let Some(partner) = partner else {
            unpaired.push(sid);
            continue;
        };
        missing.retain(|m| m.value != partner);
        files[i].rep.error(
            sid.span.clone(),
            format!(
                "section `{}` is not in the primary language's file {}",
                sid.value,
                primary_path.display()
            ),
            Some(format!(
                "did you mean `{partner}`? every language's content file has the same section ids"
            )),
        );
    }
    let same_ids = || Some("every language's content file has the same section ids".to_string());
    // Sections only in the translation (the primary file unfinished), and
    // sections it lacks (the translation unfinished): one error each way,
    // at the first.
    if let Some(first) = unpaired.first() {
        let names: Vec<&str> = unpaired.iter().map(|m| m.value.as_str()).collect();
        files[i].rep.error(
            first.span.clone(),
            format!(
                "{} in the primary language's file {}",
                sections_are(&names, "not"),
                primary_path.display()
            ),
            same_ids(),
        );
    }
    if let Some(first) = missing.first() {
        let names: Vec<&str> = missing.iter().map(|m| m.value.as_str()).collect();
        files[0].rep.error(
            first.span.clone(),
            format!(
                "{} missing from {}",
                sections_are(&names, ""),
                other_path.display()
            ),
            same_ids(),
        );
    }
    for s in &other_raw.sections {
        let Some(sid) = &s.id else { continue };
        if let Some(p) = primary_raw
            .sections
            .iter()
            .find(|p| p.id.as_ref().map(|i| &i.value) == Some(&sid.value))
        {
            see_agrees(&mut files[i].rep, p, s, &primary_path);
        }
    }
    ok
}

fn section_texts(rep: &mut FileReport, s: &RawSection) -> bool {
    let what = match &s.id {
        Some(i) if super::is_id(&i.value) => format!("section `{}`", i.value),
        _ => "a section".to_string(),
    };
    let mut ok = true;
    if let Some(t) = &s.title {
        ok &= text::string(rep, t, Kind::Math, &format!("the title of {what}"));
    }
    if let Some(b) = &s.body {
        ok &= text::string(rep, b, Kind::Math, &format!("the body of {what}"));
    }
    ok && s.title.is_some() && s.body.is_some()
}

/// A translation's `see` list is optional; when given it must match the
/// primary file's, which is the one used (a warning: the links still work).
fn see_agrees(
    rep: &mut FileReport,
    primary: &RawSection,
    other: &RawSection,
    primary_path: &std::path::Path,
) {
    let Some(see) = &other.see else { return };
    let values = |s: &RawSection| -> Vec<String> {
        s.see
            .as_ref()
            .map(|l| l.items.iter().map(|i| i.value.clone()).collect())
            .unwrap_or_default()
    };
    if values(primary) != values(other) {
        rep.warning(
            see.span.clone(),
            format!(
                "`see` differs from the one in {}, which is the one used",
                primary_path.display()
            ),
            Some(
                "give `see` in the primary language's file only, or the same list everywhere"
                    .to_string(),
            ),
        );
    }
}

/// "section `a` is", "sections `a` and `b` are", "sections `a`, `b`, `c`
/// and 4 more are", with `not` after the verb when given.
fn sections_are(names: &[&str], not: &str) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    let not = if not.is_empty() {
        String::new()
    } else {
        format!(" {not}")
    };
    match quoted.len() {
        0 | 1 => format!("section {} is{not}", quoted.join("")),
        n if n <= MISSING_LISTED => format!(
            "sections {} and {} are{not}",
            quoted[..n - 1].join(", "),
            quoted[n - 1]
        ),
        n => format!(
            "sections {} and {} more are{not}",
            quoted[..MISSING_LISTED].join(", "),
            n - MISSING_LISTED
        ),
    }
}

/// The sections in the primary file's order, each with every language.
fn build(files: &[ContentFile]) -> Option<Vec<Section>> {
    let primary = files.first()?.raw.as_ref()?;
    let mut out = Vec::new();
    for s in &primary.sections {
        let sid = s.id.as_ref()?.value.clone();
        let mut title = LangMap::new();
        let mut body = LangMap::new();
        for f in files {
            let raw = f.raw.as_ref()?;
            let this = raw
                .sections
                .iter()
                .find(|x| x.id.as_ref().is_some_and(|i| i.value == sid))?;
            title.insert(f.lang.clone(), this.title.as_ref()?.value.clone());
            body.insert(f.lang.clone(), this.body.as_ref()?.value.clone());
        }
        out.push(Section {
            id: sid,
            title: Text(title),
            body: Text(body),
            see: s
                .see
                .as_ref()
                .map(|l| l.items.iter().map(|i| i.value.clone()).collect())
                .unwrap_or_default(),
        });
    }
    Some(out)
}
