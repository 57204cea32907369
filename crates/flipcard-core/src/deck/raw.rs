//! The raw stage: deck and content files as written, every value with its
//! byte span. Reading reports wrong types, missing required fields and
//! unknown fields; what is missing or mistyped is `None` here, and the deck
//! it belongs to is never validated into a `Deck`.

use toml::de::{DeTable, DeValue};

use super::read::{self, Fields};
use super::report::FileReport;
use super::suggest;

pub use super::raw_derivation::{RawAsk, RawAskChoice, RawAskKind, RawDerivation, RawStep};
pub use super::raw_formula::{Entry, Named, RawFormula};
pub(crate) use super::raw_formula::{named, read_formula};
pub use super::raw_knob::RawKnob;
pub use super::raw_misconception::{RawMisconception, RawRange};
pub use super::raw_vary::{RawVaried, RawVary};
pub use super::read::{Flag, List, Num, RawAccept, RawText, Span, Str};

pub const DECK_FILE_FIELDS: &[&str] = &[
    "deck",
    "card",
    "prompt",
    "scene",
    "misconception",
    "derivation",
];
pub const DECK_FIELDS: &[&str] = &["id", "title", "description", "languages", "units", "parent"];
pub const CARD_FIELDS: &[&str] = &[
    "id", "kind", "front", "back", "accept", "explain", "prompt", "tags", "text", "expected",
    "vars",
];
pub const PROMPT_FIELDS: &[&str] = &[
    "id", "question", "scene", "explain", "tags", "answer", "vary",
];
pub const CHOICE_ANSWER_FIELDS: &[&str] = &["kind", "expected", "choices", "label", "unit"];
pub const NUMBER_ANSWER_FIELDS: &[&str] = &[
    "kind",
    "measure",
    "unit",
    "expected",
    "tolerance",
    "formula",
    "slips",
    "label",
    "misconceptions",
];
/// The keys of one known slip of a number answer.
pub const SLIP_FIELDS: &[&str] = &["value", "says", "misconception"];
pub const CHOICE_FIELDS: &[&str] = &["id", "label", "when", "misconception"];
pub const TOLERANCE_FIELDS: &[&str] = &["abs", "rel"];
pub const SCENE_FIELDS: &[&str] = &[
    "id",
    "title",
    "inertia",
    "omega",
    "duration",
    "show",
    "time_unit",
    "flat",
    "variables",
    "initial",
    "params",
    "equations",
    "observables",
    "conserved",
    "plot",
    "phase",
    "sketch",
    "atol",
    "hamiltonian",
    "labels",
    "knobs",
    "explore",
];
/// The keys of a system scene's `hamiltonian` (positions, momenta).
pub const HAMILTONIAN_FIELDS: &[&str] = &["q", "p"];
/// The keys of a sketch element (each takes an array of expressions).
pub(crate) const MARK_KEYS: &[&str] = &["line", "dot", "trail"];
pub const CONTENT_FILE_FIELDS: &[&str] = &["section"];
pub const SECTION_FIELDS: &[&str] = &["id", "title", "body", "see"];
pub const ANSWER_KINDS: &[&str] = &["choice", "number", "formula"];
/// The keys of a formula answer (`kind = "formula"`).
pub const FORMULA_ANSWER_FIELDS: &[&str] = &["kind", "expected", "vars"];

#[derive(Debug, Clone, PartialEq, Default)]
pub struct RawDeckFile {
    pub deck: Option<RawDeckHeader>,
    pub cards: Vec<RawCard>,
    pub prompts: Vec<RawPrompt>,
    pub scenes: Vec<RawScene>,
    /// `[[misconception]]` tables (see `raw_misconception`).
    pub misconceptions: Vec<RawMisconception>,
    /// `[[derivation]]` tables (see `raw_derivation`).
    pub derivations: Vec<RawDerivation>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawDeckHeader {
    pub span: Span,
    pub id: Option<Str>,
    pub title: Option<RawText>,
    pub description: Option<RawText>,
    pub languages: Option<List<Str>>,
    /// Units the deck's learners may type (`units = { ly = "9.4607e15 m" }`).
    pub units: Option<Named<Str>>,
    /// The id of the deck this one sits under on home (`parent = "ID"`).
    pub parent: Option<Str>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawCard {
    pub span: Span,
    pub id: Option<Str>,
    pub kind: Option<Str>,
    pub front: Option<RawText>,
    pub back: Option<RawText>,
    /// The text of a cloze card (which has no `front`).
    pub text: Option<RawText>,
    pub accept: Option<RawAccept>,
    pub explain: Option<Str>,
    pub prompt: Option<Str>,
    pub tags: Option<List<Str>>,
    /// A formula card's key (`expected`, `vars`), when either is written.
    pub formula: Option<RawFormula>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawPrompt {
    pub span: Span,
    pub id: Option<Str>,
    pub question: Option<RawText>,
    pub scene: Option<Str>,
    pub explain: Option<Str>,
    pub tags: Option<List<Str>>,
    pub answer: Option<RawAnswer>,
    /// The numbers each attempt draws anew (`raw_vary`).
    pub vary: Option<RawVary>,
}

#[derive(Debug, Clone, PartialEq)]
// One per prompt, read once and validated at once: boxing the number
// answer's fields would buy nothing but indirection.
#[allow(clippy::large_enum_variant)]
pub enum RawAnswer {
    Choice {
        span: Span,
        expected: Option<Str>,
        choices: Option<List<RawChoice>>,
        /// What the choices' one measure is, in words (`label`), and its
        /// unit (`unit`), for the verdict.
        label: Option<RawText>,
        unit: Option<Str>,
    },
    Number {
        span: Span,
        measure: Option<Str>,
        unit: Option<Str>,
        expected: Option<Num>,
        /// `expected = "period(theta)"`: the answer is what the run of each
        /// variant measures (a varied prompt's).
        computed: Option<Str>,
        tolerance: Option<RawTolerance>,
        formula: Option<RawText>,
        /// Known wrong numbers (`slips = [{ value = "1/k", says = … }]`).
        slips: Option<List<RawSlip>>,
        /// What `measure` is, in words, for the verdict.
        label: Option<RawText>,
        /// Ranges of wrong numbers that stand for a misconception.
        misconceptions: Option<List<RawRange>>,
    },
    /// A typed formula compared with `expected` over `vars`.
    Formula(RawFormula),
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawSlip {
    pub span: Span,
    pub value: Option<Str>,
    pub says: Option<RawText>,
    /// The misconception this slip stands for.
    pub misconception: Option<Str>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawChoice {
    pub span: Span,
    pub id: Option<Str>,
    pub label: Option<RawText>,
    pub when: Option<Str>,
    /// The misconception this choice stands for.
    pub misconception: Option<Str>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawTolerance {
    pub span: Span,
    pub abs: Option<Num>,
    pub rel: Option<Num>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawScene {
    pub span: Span,
    pub id: Option<Str>,
    pub title: Option<RawText>,
    pub inertia: Option<List<Num>>,
    pub omega: Option<List<Num>>,
    pub duration: Option<Num>,
    pub show: Option<List<Str>>,
    pub time_unit: Option<Str>,
    pub flat: Option<Flag>,
    /// Present only in a system scene (`variables` makes one).
    pub system: Option<RawSystem>,
    /// Numbers the learner may turn while exploring (`raw_knob`).
    pub knobs: Option<List<RawKnob>>,
    /// The measure plotted against a knob (`explore = "period(theta)"`).
    pub explore: Option<Str>,
}

/// One sketch element: `{ line = [...] }`, `{ dot = [...] }` or
/// `{ trail = [...] }`.
#[derive(Debug, Clone, PartialEq)]
pub struct RawMark {
    pub span: Span,
    pub key: Str,
    pub exprs: List<Str>,
    /// A dot's `label`.
    pub label: Option<RawText>,
}

/// The fields of a system scene as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RawSystem {
    pub variables: List<Str>,
    pub initial: Option<List<Num>>,
    pub params: Option<Named<Num>>,
    pub equations: Option<List<Str>>,
    pub observables: Option<Named<Str>>,
    pub conserved: Option<List<Str>>,
    pub plot: Option<List<Str>>,
    pub phase: Option<List<Str>>,
    pub sketch: Option<List<RawMark>>,
    pub atol: Option<RawAtol>,
    pub hamiltonian: Option<RawHamiltonian>,
    /// How the plots name some quantities (`labels = { xc = "A" }`).
    pub labels: Option<Named<Str>>,
}

/// A separable Hamiltonian as written: `hamiltonian = { q = [...], p = [...] }`.
#[derive(Debug, Clone, PartialEq)]
pub struct RawHamiltonian {
    pub span: Span,
    pub q: List<Str>,
    pub p: List<Str>,
}

/// A system scene's absolute tolerance: one number for every variable, or
/// a table of some variables' own (`atol = { y2 = 1e-20 }`).
#[derive(Debug, Clone, PartialEq)]
pub enum RawAtol {
    All(Num),
    Each(Named<Num>),
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct RawContentFile {
    pub sections: Vec<RawSection>,
    /// Some sections could not be read at all (a misspelt `[[section]]`
    /// header, a `section` that is not an array of tables): which ids the
    /// file has is not known, and it is not compared with the others.
    pub unread: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawSection {
    pub span: Span,
    pub id: Option<Str>,
    pub title: Option<Str>,
    pub body: Option<Str>,
    pub see: Option<List<Str>>,
}

/// Names a table in messages by its id when it has a readable one.
fn label(kind: &str, fields: &Fields) -> String {
    match fields.get("id").and_then(|v| match v.get_ref() {
        toml::de::DeValue::String(s) => Some(s.to_string()),
        _ => None,
    }) {
        Some(id) if super::id::is_id(&id) => format!("{kind} `{id}`"),
        _ => kind.to_string(),
    }
}

pub(crate) fn read_deck_file(rep: &mut FileReport, root: &DeTable, root_span: Span) -> RawDeckFile {
    let has = |key: &str| {
        root.iter().any(|(k, _)| {
            let name: &str = k.get_ref();
            name == key
        })
    };
    if !has("deck") && has("section") {
        rep.error(
            0..0,
            "this is a content file ([[section]]), not a deck file",
            Some(
                "check the deck file decks/<deck-id>.toml; its content files are found from it"
                    .to_string(),
            ),
        );
        return RawDeckFile::default();
    }
    let top = Fields::open(
        rep,
        root,
        root_span,
        "the deck file",
        DECK_FILE_FIELDS,
        |name| {
            matches!(name, "section" | "sections").then(|| {
                "explanation sections belong in content/<deck-id>/<lang>.toml, not in the deck file"
                    .to_string()
            })
        },
    );
    let mut file = RawDeckFile::default();
    match top.get("deck") {
        Some(v) => {
            if let Some(t) = read::table(rep, v, "`deck`") {
                file.deck = Some(read_header(rep, t, v.span()));
            }
        }
        // A misspelt [deck] is already reported as an unknown field.
        None if root.iter().any(|(k, _)| {
            suggest::closest(k.get_ref(), DECK_FILE_FIELDS.iter().copied()) == Some("deck")
        }) => {}
        None => rep.error(
            0..0,
            "the deck file has no [deck] table",
            Some("start the file with [deck] and its id, title and languages".to_string()),
        ),
    }
    if let Some(v) = top.get("card") {
        for (t, span) in read::tables(rep, v, "card") {
            file.cards.push(read_card(rep, t, span));
        }
    }
    if let Some(v) = top.get("prompt") {
        for (t, span) in read::tables(rep, v, "prompt") {
            file.prompts.push(read_prompt(rep, t, span));
        }
    }
    if let Some(v) = top.get("scene") {
        for (t, span) in read::tables(rep, v, "scene") {
            file.scenes.push(read_scene(rep, t, span));
        }
    }
    if let Some(v) = top.get("misconception") {
        for (t, span) in read::tables(rep, v, "misconception") {
            file.misconceptions
                .push(super::raw_misconception::read_misconception(rep, t, span));
        }
    }
    if let Some(v) = top.get("derivation") {
        for (t, span) in read::tables(rep, v, "derivation") {
            file.derivations
                .push(super::raw_derivation::read_derivation(rep, t, span));
        }
    }
    file
}

/// The cards of a tree holding only `[[card]]` tables (a part of a large
/// deck file, `super::chunked`), appended to `out`, as
/// [`read_deck_file`] reads them.
pub(crate) fn read_cards_into(rep: &mut FileReport, root: &DeTable, out: &mut Vec<RawCard>) {
    for (k, v) in root.iter() {
        let key: &str = k.get_ref();
        if key == "card" {
            for (t, span) in read::tables(rep, v, "card") {
                out.push(read_card(rep, t, span));
            }
        }
    }
}

fn read_header(rep: &mut FileReport, t: &DeTable, span: Span) -> RawDeckHeader {
    let f = Fields::open(rep, t, span.clone(), "[deck]", DECK_FIELDS, |_| None);
    RawDeckHeader {
        span,
        id: f.string(rep, "id", true),
        title: f.text(rep, "title", true),
        description: f.text(rep, "description", false),
        languages: f.strings(rep, "languages", true),
        units: named(rep, &f, "units", |r, v, w: &str| read::string(r, v, w)),
        parent: f.string(rep, "parent", false),
    }
}

fn read_card(rep: &mut FileReport, t: &DeTable, span: Span) -> RawCard {
    let probe = Fields::open(
        rep,
        t,
        span.clone(),
        "[[card]]",
        CARD_FIELDS,
        |name| match name {
            "question" | "answer" => Some("a card has `front` and `back`".to_string()),
            "accepted" | "accepts" => Some("did you mean `accept`?".to_string()),
            _ => None,
        },
    );
    let what = label("card", &probe);
    let f = probe.named(what);
    let kind = f.string(rep, "kind", false);
    let cloze = kind.as_ref().is_some_and(|k| k.value == "cloze");
    let formula = kind.as_ref().is_some_and(|k| k.value == "formula")
        || f.get("expected").is_some()
        || f.get("vars").is_some();
    let formula = formula.then(|| read_formula(rep, &f, span.clone()));
    RawCard {
        span,
        id: f.string(rep, "id", true),
        kind,
        front: if cloze {
            f.text(rep, "front", false)
        } else {
            f.text(rep, "front", true)
        },
        back: f.text(rep, "back", !cloze),
        text: if cloze {
            f.text(rep, "text", true)
        } else {
            f.text(rep, "text", false)
        },
        accept: f.accept(rep, "accept"),
        explain: f.string(rep, "explain", false),
        prompt: f.string(rep, "prompt", false),
        tags: f.strings(rep, "tags", false),
        formula,
    }
}

fn read_prompt(rep: &mut FileReport, t: &DeTable, span: Span) -> RawPrompt {
    let probe = Fields::open(
        rep,
        t,
        span.clone(),
        "[[prompt]]",
        PROMPT_FIELDS,
        |name| match name {
            "front" | "back" => Some("a prompt asks its `question`".to_string()),
            _ => None,
        },
    );
    let what = label("prompt", &probe);
    let f = probe.named(what);
    let answer = f
        .require(rep, "answer")
        .and_then(|v| read::table(rep, v, "`answer`").map(|t| (t, v.span())))
        .and_then(|(t, span)| read_answer(rep, t, span, &f.what));
    RawPrompt {
        span,
        id: f.string(rep, "id", true),
        question: f.text(rep, "question", true),
        scene: f.string(rep, "scene", true),
        explain: f.string(rep, "explain", false),
        tags: f.strings(rep, "tags", false),
        answer,
        vary: super::raw_vary::read_vary(rep, &f),
    }
}

fn read_answer(rep: &mut FileReport, t: &DeTable, span: Span, owner: &str) -> Option<RawAnswer> {
    // Which fields are known depends on the kind, so read it first.
    let kind_value = t.iter().find(|(k, _)| {
        let name: &str = k.get_ref();
        name == "kind"
    });
    let Some((_, kind_value)) = kind_value else {
        rep.error(
            span,
            format!("the answer of {owner} is missing the required field `kind`"),
            Some("kind = \"choice\", kind = \"number\" or kind = \"formula\"".to_string()),
        );
        return None;
    };
    let kind = read::string(rep, kind_value, "`kind`")?;
    let what = format!("the answer of {owner}");
    match kind.value.as_str() {
        "choice" => {
            let f = Fields::open(rep, t, span.clone(), &what, CHOICE_ANSWER_FIELDS, |name| {
                NUMBER_ANSWER_FIELDS
                    .contains(&name)
                    .then(|| format!("`{name}` belongs to kind = \"number\" answers"))
            });
            let choices = f.require(rep, "choices").and_then(|v| {
                let arr = read::array(rep, v, "`choices`")?;
                let items = arr
                    .iter()
                    .filter_map(|item| {
                        let t = read::table(rep, item, "each choice")?;
                        Some(read_choice(rep, t, item.span()))
                    })
                    .collect();
                Some(List {
                    items,
                    span: v.span(),
                })
            });
            Some(RawAnswer::Choice {
                span,
                // Required unless the prompt varies: checked with `vary`.
                expected: f.string(rep, "expected", false),
                choices,
                label: f.text(rep, "label", false),
                unit: f.string(rep, "unit", false),
            })
        }
        "number" => {
            let f = Fields::open(rep, t, span.clone(), &what, NUMBER_ANSWER_FIELDS, |name| {
                CHOICE_ANSWER_FIELDS
                    .contains(&name)
                    .then(|| format!("`{name}` belongs to kind = \"choice\" answers"))
            });
            let tolerance = f.require(rep, "tolerance").and_then(|v| {
                let t = read::table(rep, v, "`tolerance`")?;
                let tf = Fields::open(rep, t, v.span(), "`tolerance`", TOLERANCE_FIELDS, |_| None);
                Some(RawTolerance {
                    span: v.span(),
                    abs: tf.number(rep, "abs", false),
                    rel: tf.number(rep, "rel", false),
                })
            });
            Some(RawAnswer::Number {
                span,
                measure: f.string(rep, "measure", false),
                unit: f.string(rep, "unit", false),
                expected: f
                    .get("expected")
                    .filter(|v| !matches!(v.get_ref(), toml::de::DeValue::String(_)))
                    .and_then(|v| read::number(rep, v, "`expected`")),
                computed: f.get("expected").and_then(|v| match v.get_ref() {
                    toml::de::DeValue::String(_) => read::string(rep, v, "`expected`"),
                    _ => None,
                }),
                tolerance,
                formula: f.text(rep, "formula", false),
                slips: f.get("slips").and_then(|v| {
                    let arr = read::array(rep, v, "`slips`")?;
                    let items = arr
                        .iter()
                        .filter_map(|item| {
                            let t = read::table(rep, item, "each slip")?;
                            let f =
                                Fields::open(rep, t, item.span(), "a slip", SLIP_FIELDS, |name| {
                                    match name {
                                        "formula" | "expr" => {
                                            Some("did you mean `value`?".to_string())
                                        }
                                        "means" | "label" | "text" | "why" => {
                                            Some("did you mean `says`?".to_string())
                                        }
                                        _ => None,
                                    }
                                });
                            Some(RawSlip {
                                span: item.span(),
                                value: f.string(rep, "value", true),
                                says: f.text(rep, "says", true),
                                misconception: f.string(rep, "misconception", false),
                            })
                        })
                        .collect();
                    Some(List {
                        items,
                        span: v.span(),
                    })
                }),
                label: f.text(rep, "label", false),
                misconceptions: super::raw_misconception::read_ranges(rep, &f),
            })
        }
        "formula" => {
            let f = Fields::open(rep, t, span.clone(), &what, FORMULA_ANSWER_FIELDS, |_| None);
            Some(RawAnswer::Formula(read_formula(rep, &f, span)))
        }
        other => {
            rep.error(
                kind.span.clone(),
                format!("unknown answer kind `{other}`"),
                suggest::did_you_mean(other, ANSWER_KINDS.iter().copied()).or_else(|| {
                    Some("kind = \"choice\", kind = \"number\" or kind = \"formula\"".to_string())
                }),
            );
            None
        }
    }
}

fn read_choice(rep: &mut FileReport, t: &DeTable, span: Span) -> RawChoice {
    let probe = Fields::open(rep, t, span.clone(), "choice", CHOICE_FIELDS, |_| None);
    let what = label("choice", &probe);
    let f = probe.named(what);
    RawChoice {
        span,
        id: f.string(rep, "id", true),
        label: f.text(rep, "label", true),
        when: f.string(rep, "when", true),
        misconception: f.string(rep, "misconception", false),
    }
}

fn read_scene(rep: &mut FileReport, t: &DeTable, span: Span) -> RawScene {
    let probe = Fields::open(
        rep,
        t,
        span.clone(),
        "[[scene]]",
        SCENE_FIELDS,
        |name| match name {
            "moments" | "inertia_tensor" => Some("did you mean `inertia`?".to_string()),
            "omega0" | "angular_velocity" | "w" => Some("did you mean `omega`?".to_string()),
            "t_end" | "time" => Some("did you mean `duration`?".to_string()),
            _ => None,
        },
    );
    let what = label("scene", &probe);
    let f = probe.named(what);
    let is_system = f.get("variables").is_some();
    if !is_system && f.get("inertia").is_none() && f.get("omega").is_none() {
        rep.error(
            span.clone(),
            format!(
                "{} is neither a rigid body (`inertia`, `omega`) nor a system (`variables`, `equations`)",
                f.what
            ),
            Some("give `inertia` and `omega` for a rigid body, or `variables`, `initial` and `equations` for a system".to_string()),
        );
    }
    let system = if is_system {
        for key in ["inertia", "omega", "flat"] {
            if let Some(v) = f.get(key) {
                rep.error(
                    v.span(),
                    format!(
                        "`{key}` belongs to a rigid-body scene, but {} has `variables` (a system)",
                        f.what
                    ),
                    Some("a scene is either a rigid body or a system; split it in two".to_string()),
                );
            }
        }
        f.strings(rep, "variables", true)
            .map(|variables| RawSystem {
                variables,
                initial: f.numbers(rep, "initial", true),
                params: named(rep, &f, "params", |r, v, w: &str| read::number(r, v, w)),
                equations: f.strings(rep, "equations", true),
                observables: named(rep, &f, "observables", |rep, v, what| {
                    read::string(rep, v, what)
                }),
                conserved: f.strings(rep, "conserved", false),
                plot: f.strings(rep, "plot", false),
                phase: f.strings(rep, "phase", false),
                sketch: sketch(rep, &f),
                atol: match f.get("atol") {
                    Some(v) if matches!(v.get_ref(), DeValue::Table(_)) => {
                        named(rep, &f, "atol", |r, v, w: &str| read::number(r, v, w))
                            .map(RawAtol::Each)
                    }
                    Some(v) => read::number(rep, v, "`atol`").map(RawAtol::All),
                    None => None,
                },
                hamiltonian: hamiltonian(rep, &f),
                labels: named(rep, &f, "labels", |r, v, w: &str| read::string(r, v, w)),
            })
    } else {
        for key in [
            "initial",
            "params",
            "equations",
            "observables",
            "conserved",
            "plot",
            "phase",
            "sketch",
            "atol",
            "hamiltonian",
            "labels",
        ] {
            if let Some(v) = f.get(key) {
                rep.error(
                    v.span(),
                    format!(
                        "`{key}` belongs to a system scene, but {} has no `variables`",
                        f.what
                    ),
                    Some("a system declares its state with `variables = [...]`".to_string()),
                );
            }
        }
        None
    };
    RawScene {
        span,
        id: f.string(rep, "id", true),
        title: f.text(rep, "title", false),
        inertia: if is_system {
            None
        } else {
            f.numbers(rep, "inertia", true)
        },
        omega: if is_system {
            None
        } else {
            f.numbers(rep, "omega", true)
        },
        duration: f.number(rep, "duration", true),
        show: f.strings(rep, "show", true),
        time_unit: f.string(rep, "time_unit", false),
        flat: if is_system { None } else { f.flag(rep, "flat") },
        system,
        knobs: super::raw_knob::read_knobs(rep, &f),
        explore: f.string(rep, "explore", false),
    }
}

/// `hamiltonian = { q = [...], p = [...] }`, both lists required.
fn hamiltonian(rep: &mut FileReport, f: &Fields) -> Option<RawHamiltonian> {
    let v = f.get("hamiltonian")?;
    let t = read::table(rep, v, "`hamiltonian`")?;
    let h = Fields::open(
        rep,
        t,
        v.span(),
        "`hamiltonian`",
        HAMILTONIAN_FIELDS,
        |_| None,
    );
    let (q, p) = (h.strings(rep, "q", true), h.strings(rep, "p", true));
    Some(RawHamiltonian {
        span: v.span(),
        q: q?,
        p: p?,
    })
}

fn sketch(rep: &mut FileReport, f: &Fields) -> Option<List<RawMark>> {
    let v = f.get("sketch")?;
    let arr = read::array(rep, v, "`sketch`")?;
    let mut items = Vec::new();
    let mut ok = true;
    for item in arr.iter() {
        let Some(t) = read::table(rep, item, "each item of `sketch`") else {
            ok = false;
            continue;
        };
        // A dot may carry a label beside its one key.
        let label_value = t.get("label");
        let keys: Vec<_> = t.iter().filter(|(k, _)| k.get_ref() != "label").collect();
        if keys.len() != 1 {
            rep.error(
                item.span(),
                format!(
                    "each item of `sketch` has one key (line, dot or trail), found {}",
                    keys.len()
                ),
                Some(
                    "sketch = [{ line = [\"0\", \"0\", \"x\", \"y\"] }, { dot = [\"x\", \"y\"] }]"
                        .to_string(),
                ),
            );
            ok = false;
            continue;
        }
        let (k, value) = keys[0];
        let name: &str = k.get_ref();
        if !MARK_KEYS.contains(&name) {
            rep.error(
                k.span(),
                format!("unknown sketch element `{name}`"),
                suggest::did_you_mean(name, MARK_KEYS.iter().copied())
                    .or_else(|| Some("sketch elements: line, dot, trail".to_string())),
            );
            ok = false;
            continue;
        }
        let what = format!("`{name}`");
        let Some(a) = read::array(rep, value, &what) else {
            ok = false;
            continue;
        };
        let exprs: Vec<Str> = a
            .iter()
            .filter_map(|e| read::string(rep, e, &format!("each coordinate of {what}")))
            .collect();
        if exprs.len() != a.len() {
            ok = false;
            continue;
        }
        let label = match label_value {
            Some(l) if name == "dot" => match read::text(rep, l, "`label`") {
                Some(t) => Some(t),
                None => {
                    ok = false;
                    continue;
                }
            },
            Some(l) => {
                rep.error(
                    l.span(),
                    format!("a `{name}` has no `label`; only a `dot` does"),
                    Some("{ dot = [\"x\", \"y\"], label = 'Sun' }".to_string()),
                );
                ok = false;
                continue;
            }
            None => None,
        };
        items.push(RawMark {
            span: item.span(),
            key: Str {
                value: name.to_string(),
                span: k.span(),
            },
            exprs: List {
                items: exprs,
                span: value.span(),
            },
            label,
        });
    }
    ok.then_some(List {
        items,
        span: v.span(),
    })
}

pub(crate) fn read_content_file(
    rep: &mut FileReport,
    root: &DeTable,
    root_span: Span,
) -> RawContentFile {
    let top = Fields::open(
        rep,
        root,
        root_span,
        "a content file",
        CONTENT_FILE_FIELDS,
        |name| match name {
            "deck" | "card" | "prompt" | "scene" | "derivation" => Some(format!(
                "[[{name}]] belongs in the deck file decks/<deck-id>.toml; content files hold [[section]] only"
            )),
            _ => None,
        },
    );
    let mut file = RawContentFile {
        unread: root.iter().any(|(k, _)| {
            let name: &str = k.get_ref();
            name != "section"
                && suggest::closest(name, CONTENT_FILE_FIELDS.iter().copied()) == Some("section")
        }),
        ..RawContentFile::default()
    };
    if let Some(v) = top.get("section") {
        let written = match v.get_ref() {
            toml::de::DeValue::Array(a) => a.len(),
            _ => usize::MAX,
        };
        for (t, span) in read::tables(rep, v, "section") {
            file.sections.push(read_section(rep, t, span));
        }
        file.unread |= file.sections.len() != written;
    }
    file
}

fn read_section(rep: &mut FileReport, t: &DeTable, span: Span) -> RawSection {
    let probe = Fields::open(
        rep,
        t,
        span.clone(),
        "[[section]]",
        SECTION_FIELDS,
        |name| match name {
            "text" | "content" => Some("did you mean `body`?".to_string()),
            _ => None,
        },
    );
    let what = label("section", &probe);
    let f = probe.named(what);
    RawSection {
        span,
        id: f.string(rep, "id", true),
        title: f.string(rep, "title", true),
        body: f.string(rep, "body", true),
        see: f.strings(rep, "see", false),
    }
}
