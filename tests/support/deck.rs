//! What the tests of a bundled deck built from system scenes share: the
//! deck and its content files read as TOML, measures of a scene run
//! through the real binary (`flipcard sim --scene ID --deck FILE --measure
//! M`), a choice's `when` evaluated on those measures, and the prompts
//! marked `# vary: <name> = [lo, hi]` re-run at other values.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::Flipcard;

pub const LANGS: [&str; 2] = ["en", "hi-Latn"];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read_toml(path: &Path) -> toml::Table {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `[[name]]` tables of a deck or content file.
pub fn array<'a>(table: &'a toml::Table, name: &str) -> Vec<&'a toml::Table> {
    table
        .get(name)
        .and_then(|v| v.as_array())
        .map(|a| a.iter().filter_map(|v| v.as_table()).collect())
        .unwrap_or_default()
}

pub fn find<'a>(table: &'a toml::Table, name: &str, id: &str) -> &'a toml::Table {
    array(table, name)
        .into_iter()
        .find(|t| t.get("id").and_then(|v| v.as_str()) == Some(id))
        .unwrap_or_else(|| panic!("no {name} {id}"))
}

/// One bundled deck: `decks/ID.toml` with `content/ID/`.
pub struct BundledDeck {
    pub id: &'static str,
}

impl BundledDeck {
    pub fn path(&self) -> PathBuf {
        root().join("decks").join(format!("{}.toml", self.id))
    }

    pub fn deck(&self) -> toml::Table {
        read_toml(&self.path())
    }

    pub fn source(&self) -> String {
        std::fs::read_to_string(self.path()).unwrap()
    }

    pub fn content_path(&self, lang: &str) -> PathBuf {
        root()
            .join("content")
            .join(self.id)
            .join(format!("{lang}.toml"))
    }

    pub fn sections(&self, lang: &str) -> toml::Table {
        read_toml(&self.content_path(lang))
    }

    /// Each measure of a scene, measured in one run of the binary.
    pub fn measure(&self, scene: &str, measures: &[&str]) -> Vec<f64> {
        measure_in(&self.path(), scene, measures)
    }

    pub fn measure_one(&self, scene: &str, m: &str) -> f64 {
        self.measure(scene, &[m])[0]
    }

    /// The texts of a card, prompt, misconception or section in each
    /// language (every text under it, joined), `$` dropped so that
    /// `$T = 2.041$ s` reads `T = 2.041 s`.
    pub fn texts_of(&self, kind: &str, id: &str) -> Vec<String> {
        if kind == "section" {
            return LANGS
                .iter()
                .map(|lang| {
                    let content = self.sections(lang);
                    let s = find(&content, "section", id);
                    format!(
                        "{}\n{}",
                        s["title"].as_str().unwrap(),
                        s["body"].as_str().unwrap()
                    )
                    .replace('$', "")
                })
                .collect();
        }
        let deck = self.deck();
        let item = toml::Value::Table(find(&deck, kind, id).clone());
        let mut out = BTreeMap::new();
        texts(&item, &mut out);
        LANGS
            .iter()
            .map(|lang| {
                out.get(*lang)
                    .unwrap_or_else(|| panic!("{kind} {id}: no {lang} text"))
                    .replace('$', "")
            })
            .collect()
    }

    /// `text` is written in every language's text of `kind` `id`.
    pub fn assert_quoted(&self, kind: &str, id: &str, text: &str) {
        for (lang, body) in LANGS.iter().zip(self.texts_of(kind, id)) {
            assert!(
                body.contains(text),
                "{text:?} is not in the {lang} text of {kind} {id}"
            );
        }
    }

    /// The deck's scenes, one with values changed (`name`: a parameter,
    /// `initial.VAR` or `duration`), written into `dir` as a deck of its
    /// own (the cards, prompts and sections left out: a prompt's expected
    /// number is the deck's value's, not the changed one's); the path of the
    /// new deck file. The edit is made in the text, so that everything else
    /// (the order of the observables included) stays as written.
    pub fn edited(&self, dir: &Path, scene: &str, values: &[(&str, f64)]) -> PathBuf {
        let mut text = self.source();
        for (name, value) in values {
            text = set_in_scene(&text, scene, name, *value);
        }
        // The header, then the scenes: every block that starts `[[scene]]`
        // up to the next `[[`.
        let first = text.find("\n[[").expect("a deck with tables") + 1;
        let mut kept = text[..first].to_string();
        for block in text[first..]
            .split("\n[[")
            .map(|b| b.trim_start_matches("[["))
        {
            if block.starts_with("scene]]") {
                kept.push_str("\n[[");
                kept.push_str(block);
            }
        }
        let decks = dir.join("decks");
        let content = dir.join("content").join(self.id);
        std::fs::create_dir_all(&decks).unwrap();
        std::fs::create_dir_all(&content).unwrap();
        for lang in LANGS {
            std::fs::write(content.join(format!("{lang}.toml")), "").unwrap();
        }
        let path = decks.join(format!("{}.toml", self.id));
        std::fs::write(&path, kept).unwrap();
        path
    }
}

/// `text` (a deck) with `name` of scene `scene` set to `value`: a
/// parameter (in its `params = { … }` line), `initial.VAR` (the variable's
/// place in `initial = [ … ]`) or `duration`.
pub fn set_in_scene(text: &str, scene: &str, name: &str, value: f64) -> String {
    let header = format!("[[scene]]\nid = \"{scene}\"\n");
    let start = text
        .find(&header)
        .unwrap_or_else(|| panic!("no scene {scene}"));
    let end = text[start + header.len()..]
        .find("\n[[")
        .map_or(text.len(), |i| start + header.len() + i);
    let block = &text[start..end];
    let line_of = |key: &str| -> (usize, usize) {
        let at = block
            .find(&format!("\n{key} = "))
            .unwrap_or_else(|| panic!("scene {scene} has no {key}"))
            + 1;
        (at, at + block[at..].find('\n').unwrap_or(block.len() - at))
    };
    let v = format!("{value:?}");
    let (key, new_line) = if name == "duration" {
        ("duration", format!("duration = {v}"))
    } else if let Some(var) = name.strip_prefix("initial.") {
        let (a, _) = line_of("variables");
        let vars_line = &block[a..a + block[a..].find('\n').unwrap()];
        let i = vars_line
            .split('"')
            .skip(1)
            .step_by(2)
            .position(|n| n == var)
            .unwrap_or_else(|| panic!("no variable {var}"));
        let (a, b) = line_of("initial");
        let inside = block[a..b]
            .trim_start_matches("initial = [")
            .trim_end_matches(']');
        let mut items: Vec<String> = inside.split(',').map(|x| x.trim().to_string()).collect();
        items[i] = v;
        ("initial", format!("initial = [{}]", items.join(", ")))
    } else {
        let (a, b) = line_of("params");
        let line = &block[a..b];
        let mut out = Vec::new();
        let mut found = false;
        let inside = line.trim_start_matches("params = {").trim_end_matches('}');
        for item in inside.split(',') {
            let (k, old) = item.split_once('=').expect("name = value");
            if k.trim() == name {
                found = true;
                out.push(format!("{} = {v}", k.trim()));
            } else {
                out.push(format!("{} = {}", k.trim(), old.trim()));
            }
        }
        assert!(found, "scene {scene} has no parameter {name}");
        ("params", format!("params = {{ {} }}", out.join(", ")))
    };
    let (a, b) = line_of(key);
    format!("{}{}{}", &text[..start + a], new_line, &text[start + b..])
}

/// Each measure of `scene` of the deck file `deck`, by the real binary.
pub fn measure_in(deck: &Path, scene: &str, measures: &[&str]) -> Vec<f64> {
    let out = Flipcard::without_data()
        .args(["sim", "--scene", scene, "--deck"])
        .arg(deck)
        .args(measures.iter().flat_map(|m| ["--measure", *m]))
        .run();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "sim --scene {scene} {measures:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let values: Vec<f64> = stdout
        .lines()
        .map(|l| {
            l.trim()
                .parse()
                .unwrap_or_else(|e| panic!("{scene}: {l:?} is not a number ({e})"))
        })
        .collect();
    assert_eq!(values.len(), measures.len(), "{scene}: {stdout}");
    for (m, v) in measures.iter().zip(&values) {
        assert!(v.is_finite(), "{scene}: {m} = {v}");
    }
    values
}

/// Every translatable text under `value`: tables whose keys are languages.
fn texts(value: &toml::Value, out: &mut BTreeMap<String, String>) {
    match value {
        toml::Value::Table(t) => {
            if !t.is_empty()
                && t.keys().all(|k| LANGS.contains(&k.as_str()))
                && t.values().all(|v| v.is_str())
            {
                for (lang, text) in t {
                    let all = out.entry(lang.clone()).or_default();
                    all.push_str(text.as_str().unwrap());
                    all.push('\n');
                }
            } else {
                t.values().for_each(|v| texts(v, out));
            }
        }
        toml::Value::Array(a) => a.iter().for_each(|v| texts(v, out)),
        _ => {}
    }
}

// ---------------------------------------------------------------------------
// Conditions
// ---------------------------------------------------------------------------

const OPS: [&str; 6] = ["<=", ">=", "==", "!=", "<", ">"];

/// The measures a `when` reads: `0.95 <= period(x2) <= 1.05 and max(a) > 1`
/// → `period(x2)`, `max(a)`.
pub fn measures_of(when: &str) -> Vec<String> {
    let mut out = Vec::new();
    for clause in when.split(" or ").flat_map(|c| c.split(" and ")) {
        for term in split_ops(clause).0 {
            let t = term.trim();
            let t = t
                .strip_prefix("abs(")
                .and_then(|r| r.strip_suffix(')'))
                .unwrap_or(t);
            if t.parse::<f64>().is_err() && !out.iter().any(|m| m == t) {
                out.push(t.to_string());
            }
        }
    }
    out
}

/// `a < b <= c` → ([a, b, c], [<, <=]).
fn split_ops(clause: &str) -> (Vec<String>, Vec<&'static str>) {
    let (mut terms, mut ops) = (Vec::new(), Vec::new());
    let mut rest = clause;
    'outer: loop {
        let mut best: Option<(usize, &'static str)> = None;
        for op in OPS {
            if let Some(i) = rest.find(op) {
                // The longest operator at the earliest place.
                if best.is_none_or(|(j, o)| i < j || (i == j && op.len() > o.len())) {
                    best = Some((i, op));
                }
            }
        }
        match best {
            Some((i, op)) => {
                terms.push(rest[..i].trim().to_string());
                ops.push(op);
                rest = &rest[i + op.len()..];
            }
            None => {
                terms.push(rest.trim().to_string());
                break 'outer;
            }
        }
    }
    (terms, ops)
}

/// Whether `when` holds on the measured values (`and` binds tighter than
/// `or`, a chain `a < b < c` holds when each comparison does).
pub fn holds(when: &str, values: &BTreeMap<String, f64>) -> bool {
    let value = |t: &str| -> f64 {
        let t = t.trim();
        if let Ok(x) = t.parse::<f64>() {
            return x;
        }
        if let Some(inner) = t.strip_prefix("abs(").and_then(|r| r.strip_suffix(')')) {
            return values[inner].abs();
        }
        *values
            .get(t)
            .unwrap_or_else(|| panic!("{t} was not measured"))
    };
    when.split(" or ").any(|alt| {
        alt.split(" and ").all(|clause| {
            let (terms, ops) = split_ops(clause);
            assert!(!ops.is_empty(), "no comparison in {clause:?}");
            ops.iter().enumerate().all(|(i, op)| {
                let (a, b) = (value(&terms[i]), value(&terms[i + 1]));
                match *op {
                    "<" => a < b,
                    "<=" => a <= b,
                    ">" => a > b,
                    ">=" => a >= b,
                    "==" => a == b,
                    "!=" => a != b,
                    _ => unreachable!(),
                }
            })
        })
    })
}

// ---------------------------------------------------------------------------
// Prompts
// ---------------------------------------------------------------------------

/// What a prompt's run gives: the choices that hold, or the measured
/// number.
#[derive(Debug, PartialEq)]
pub enum Verdict {
    Choices(Vec<String>),
    Number(f64),
}

/// Runs `prompt` (a table of the deck) on the deck file `deck`.
pub fn run_prompt(deck: &Path, prompt: &toml::Table) -> Verdict {
    let scene = prompt["scene"].as_str().unwrap();
    let answer = prompt["answer"].as_table().unwrap();
    match answer["kind"].as_str().unwrap() {
        "number" => {
            let m = answer["measure"].as_str().unwrap();
            Verdict::Number(measure_in(deck, scene, &[m])[0])
        }
        "choice" => {
            let choices = answer["choices"].as_array().unwrap();
            let mut wanted: Vec<String> = Vec::new();
            for c in choices {
                for m in measures_of(c["when"].as_str().unwrap()) {
                    if !wanted.contains(&m) {
                        wanted.push(m);
                    }
                }
            }
            let refs: Vec<&str> = wanted.iter().map(String::as_str).collect();
            let values: BTreeMap<String, f64> = wanted
                .iter()
                .cloned()
                .zip(measure_in(deck, scene, &refs))
                .collect();
            Verdict::Choices(
                choices
                    .iter()
                    .filter(|c| holds(c["when"].as_str().unwrap(), &values))
                    .map(|c| c["id"].as_str().unwrap().to_string())
                    .collect(),
            )
        }
        other => panic!("prompt {}: a {other} answer is not measured", prompt["id"]),
    }
}

/// `# vary: <name> = [lo, hi]` written right above a `[[prompt]]` (other
/// comment lines may come between): prompt id → (name, lo, hi).
pub fn varied(source: &str) -> BTreeMap<String, (String, f64, f64)> {
    let mut out = BTreeMap::new();
    let mut pending: Option<(String, f64, f64)> = None;
    let mut in_prompt_header = false;
    for line in source.lines() {
        let l = line.trim();
        if let Some(spec) = l.strip_prefix("# vary:") {
            let (name, range) = spec.split_once('=').expect("# vary: name = [lo, hi]");
            let range = range.trim().trim_start_matches('[').trim_end_matches(']');
            let (lo, hi) = range.split_once(',').expect("[lo, hi]");
            pending = Some((
                name.trim().to_string(),
                lo.trim().parse().unwrap(),
                hi.trim().parse().unwrap(),
            ));
        } else if l == "[[prompt]]" {
            in_prompt_header = pending.is_some();
        } else if in_prompt_header {
            if let Some(id) = l.strip_prefix("id = ") {
                let (name, lo, hi) = pending.take().unwrap();
                out.insert(id.trim_matches('"').to_string(), (name, lo, hi));
                in_prompt_header = false;
            }
        } else if !l.starts_with('#') && !l.is_empty() {
            assert!(
                pending.is_none(),
                "a `# vary:` line not above a prompt: {l}"
            );
        }
    }
    out
}

/// Each varied prompt at the low end, the middle and the high end of its
/// range: (prompt id, value, verdict).
pub fn run_varied(deck: &BundledDeck) -> Vec<(String, f64, Verdict)> {
    let table = deck.deck();
    let mut out = Vec::new();
    for (id, (name, lo, hi)) in varied(&deck.source()) {
        let prompt = find(&table, "prompt", &id);
        let scene = prompt["scene"].as_str().unwrap();
        for x in [lo, 0.5 * (lo + hi), hi] {
            let dir = tempfile::tempdir().unwrap();
            let path = deck.edited(dir.path(), scene, &[(name.as_str(), x)]);
            out.push((id.clone(), x, run_prompt(&path, prompt)));
        }
    }
    out
}

/// `flipcard check FILE`: passes, with neither an error nor a warning.
pub fn assert_checks_clean(deck: &BundledDeck) {
    let out = Flipcard::without_data().arg("check").arg(deck.path()).run();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(
        !stdout.contains("warning") && !stderr.contains("warning"),
        "{stdout}{stderr}"
    );
    assert!(stdout.contains(": ok"), "{stdout}");
}
