//! JSON Schemas of deck and content files, for editors (Taplo / Even Better
//! TOML) to complete and check decks as they are typed. Published at
//! `schema/deck.schema.json` and `schema/content.schema.json`.
//!
//! The types here mirror the raw stage's tables (a test keeps their field
//! names equal to the ones the reader knows); the checks a schema cannot
//! express (links, languages, physics, LaTeX) are `flipcard check`'s.

use std::borrow::Cow;

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};

use super::model::{CardKind, Cmp, Panel, SystemPanel};
use flipcard_sim::scene::vocabulary;

pub(crate) const ID_PATTERN: &str = "^[a-z0-9]+(-[a-z0-9]+)*$";
/// Holds at least one character that is not white space.
pub(crate) const NOT_BLANK: &str = r"\S";
pub(crate) const LANG_PATTERN: &str = "^[A-Za-z]{2,8}(-[A-Za-z0-9]{1,8})*$";

/// A deck file: `decks/<deck-id>.toml`.
#[derive(JsonSchema)]
#[schemars(title = "flipcard deck", deny_unknown_fields)]
pub struct DeckFile {
    pub deck: DeckHeader,
    /// Flashcards, each under its own `[[card]]` header.
    pub card: Option<Vec<Card>>,
    /// Predict-then-check prompts, each under `[[prompt]]`.
    pub prompt: Option<Vec<Prompt>>,
    /// Simulations the prompts run, each under `[[scene]]`.
    pub scene: Option<Vec<Scene>>,
    /// Misconceptions a wrong answer may stand for, each under
    /// `[[misconception]]`.
    pub misconception: Option<Vec<Misconception>>,
    /// Derivations shown step by step, each under `[[derivation]]` with
    /// its steps under `[[derivation.step]]`: a review item (direction
    /// `derive`) whose later reviews leave steps for the learner.
    pub derivation: Option<Vec<Derivation>>,
}

/// A derivation: ordered steps, each with its math, why it is taken and
/// what the learner is asked when the step is faded.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Derivation {
    /// Stable identity, like a card's (no card may have it).
    pub id: Id,
    pub title: Text,
    /// The section (and anchor) `e` opens.
    pub explain: Option<ExplainLink>,
    pub tags: Option<Vec<NonEmpty>>,
    /// The steps in order: 1 to 40.
    #[schemars(length(min = 1, max = 40))]
    pub step: Vec<DerivationStep>,
}

/// One step of a derivation.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct DerivationStep {
    /// The step's math (`$…$`): one string for every language, or a text
    /// per language.
    pub math: Text,
    /// Why this step is taken; the hint when the step is faded.
    pub why: Text,
    /// What a faded step asks before its math is shown (without it, the
    /// learner thinks, then reveals).
    pub ask: Option<StepAsk>,
}

/// What a faded step asks.
#[derive(JsonSchema)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum StepAsk {
    /// Think, then reveal: nothing is checked.
    Reveal {
        /// The question put to the learner (may hold math).
        question: Option<Text>,
    },
    /// Pick one of 2 to 9 choices; `answer` is the right one's id.
    Choice {
        question: Option<Text>,
        #[schemars(length(min = 2, max = 9))]
        choices: Vec<StepChoice>,
        answer: Id,
    },
    /// Type a formula, right when it equals `expected` at random points
    /// of the domain `vars` gives (as a formula card).
    Formula {
        question: Option<Text>,
        #[schemars(length(min = 1, max = 1000))]
        expected: String,
        vars: Vars,
    },
}

/// A choice of a step's ask.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct StepChoice {
    pub id: Id,
    pub label: Text,
}

/// A misconception: what learners believe, why it seems right (the
/// steel-man) and the fix, shown when a wrong answer stands for it.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Misconception {
    /// Named by choices (`misconception = "…"`), slips and ranges.
    pub id: Id,
    pub title: Text,
    /// Why the wrong idea seems right (may hold math).
    pub why_it_seems_right: Text,
    /// What is true instead (may hold math).
    pub fix: Text,
    /// The section (and anchor) `e` opens after the verdict.
    pub explain: Option<ExplainLink>,
}

/// Wrong numbers from `range[0]` to `range[1]` stand for misconception `id`.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct WrongRange {
    /// `[low, high]`, finite, both ends included; no number in it may be
    /// within the tolerance of `expected`.
    #[schemars(length(min = 2, max = 2))]
    pub range: Vec<f64>,
    pub id: Id,
}

/// The deck's identity, title and languages.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct DeckHeader {
    /// Must equal the file name without `.toml`; review history is keyed by it.
    pub id: Id,
    pub title: Text,
    /// One or two sentences for the home screen.
    pub description: Option<Text>,
    /// BCP 47 tags (`en`, `hi-Latn`); the first is the primary language.
    #[schemars(length(min = 1))]
    pub languages: Vec<LangTag>,
    /// Units a learner may type in a number answer besides the known ones,
    /// each a positive number and a known unit: `{ ly = "9.4607e15 m" }`.
    pub units: Option<std::collections::BTreeMap<String, String>>,
    /// The id of the deck this one sits under on home: studying the parent
    /// studies this deck too, and the parent's limits bound both.
    pub parent: Option<Id>,
}

/// A flashcard. A cloze card has `text` (and an optional `back` of notes);
/// every other kind has `front` and `back`.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
#[schemars(extend(
    "if" = { "properties": { "kind": { "const": "cloze" } }, "required": ["kind"] },
    "then" = { "required": ["text"], "not": { "required": ["front"] } },
    "else" = { "required": ["front", "back"], "not": { "required": ["text"] } }
))]
pub struct Card {
    /// Stable identity: edit the texts freely, never the id.
    pub id: Id,
    /// `basic` (default), `reversed` (also asked back → front), `typed`,
    /// `cloze` (each deletion number of `text` asked on its own) or
    /// `formula` (the learner types a formula, compared with `expected`).
    pub kind: Option<CardKindName>,
    pub front: Option<Text>,
    pub back: Option<Text>,
    /// The text of a cloze card, with deletions `{{c1::answer}}` or
    /// `{{c1::answer::hint}}`; several deletions may share a number, and
    /// every language must have the same numbers.
    pub text: Option<Text>,
    /// Accepted typed answers (typed cards only), compared ignoring case and spaces.
    pub accept: Option<Accept>,
    /// Id of the explanation section opened with `e`, or
    /// `section-id#anchor` to open it at the paragraph after the body's
    /// `{#anchor}` line.
    pub explain: Option<ExplainLink>,
    /// Id of a prompt offered after the answer is shown.
    pub prompt: Option<Id>,
    pub tags: Option<Vec<NonEmpty>>,
    /// A formula card's expected formula: `(I_2 - I_3) omega_2 omega_3 / I_1`.
    #[schemars(length(min = 1, max = 1000))]
    pub expected: Option<String>,
    /// A formula card's variables, each with its `[low, high]` domain.
    pub vars: Option<Vars>,
}

/// Each variable of a formula answer with the interval its values are
/// drawn from: `{ I1 = [1, 3], omega2 = [-2, 2] }`.
pub type Vars = std::collections::BTreeMap<String, [f64; 2]>;

/// Predict, then check: the learner answers, the scene runs, the
/// measurements decide.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Prompt {
    pub id: Id,
    pub question: Text,
    /// Id of the scene run to check the prediction.
    pub scene: Id,
    /// The explanation section opened with `e` after the verdict, or
    /// `section-id#anchor` to open it at the paragraph that answers.
    pub explain: Option<ExplainLink>,
    pub tags: Option<Vec<NonEmpty>>,
    pub answer: Answer,
    /// Numbers drawn anew for each attempt, shown as `{name}` (or
    /// `{name:.N}`) in the question: `theta0 = [20.0, 80.0]`, or a table.
    /// The answer is then computed from each variant's run.
    #[schemars(with = "Option<std::collections::BTreeMap<String, Varied>>")]
    pub vary: Option<()>,
}

/// One varied number: `[lo, hi]`, or a table.
#[derive(JsonSchema)]
#[serde(untagged)]
pub enum Varied {
    /// Drawn uniformly in `[lo, hi]`.
    Range([f64; 2]),
    Table(VariedTable),
}

/// A varied number as a table.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct VariedTable {
    /// Drawn uniformly in `[lo, hi]` (or on the grid of `step`).
    pub range: Option<[f64; 2]>,
    /// One of these, each as likely.
    #[schemars(length(min = 2, max = 1000))]
    pub values: Option<Vec<f64>>,
    /// With `range`: drawn on the grid lo + k·step.
    pub step: Option<f64>,
    /// What it sets: a parameter or `initial.VAR`, `inertia[i]` or
    /// `omega[i]` (the name itself when left out).
    pub target: Option<String>,
    /// The scene gets value × `scale`.
    pub scale: Option<f64>,
}

/// A number answer's `expected`: the number the physics gives, or (a
/// varied prompt) the measure each variant's answer is.
#[derive(JsonSchema)]
#[serde(untagged)]
pub enum NumberExpected {
    Number(f64),
    /// The measure, as `measure` is written: `period(theta)`.
    Computed(String),
}

/// How the prediction is given and judged.
#[derive(JsonSchema)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Answer {
    /// Pick one choice; the choice whose `when` holds after the run is right.
    Choice {
        /// The choice id the physics gives (worked out by the author); a
        /// varied prompt may leave it out (each variant's run decides).
        expected: Option<Id>,
        #[schemars(length(min = 2))]
        choices: Vec<Choice>,
        /// The one measure the choices' conditions read, in words, for the
        /// verdict ("time for B to get within 1% of rest"); may hold math.
        label: Option<Text>,
        /// The unit of what `label` names, shown after its value (only with `label`).
        unit: Option<String>,
    },
    /// Type a number (with an optional unit), right within `tolerance` of the measurement.
    Number {
        /// What is measured (may be left out when `expected` names it).
        measure: Option<AnyMeasure>,
        /// Unit shown and accepted after the number, e.g. `s`.
        unit: Option<String>,
        /// The value the formula gives; on a varied prompt, the measure
        /// each variant's answer is (`"period(theta)"`).
        expected: NumberExpected,
        tolerance: Tolerance,
        /// How `expected` follows (may hold math).
        formula: Option<Text>,
        /// Known wrong numbers: a learner's number within `tolerance` of
        /// one is told what it is and what it means.
        slips: Option<Vec<Slip>>,
        /// What `measure` is, in words, for the verdict ("time for the
        /// amplitude to fall to 1/e"); may hold math.
        label: Option<Text>,
        /// Ranges of wrong numbers that stand for a misconception (a slip
        /// that matches says its own first).
        misconceptions: Option<Vec<WrongRange>>,
    },
    /// Type a formula, right when it equals `expected` at random points
    /// of the domain `vars` gives (no measurement decides it).
    Formula {
        /// The formula: `(I_3 - I_2)(I_2 - I_1) Omega^2 / (I_1 I_3)`.
        #[schemars(length(min = 1, max = 1000))]
        expected: String,
        /// Each variable with its `[low, high]` domain.
        vars: Vars,
    },
}

/// A known wrong number of a number answer.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Slip {
    /// A formula (system-scene expression syntax) over the scene's numbers
    /// (a rigid body: `I1 I2 I3`, `w1 w2 w3`, `k`; a system: its `params`),
    /// `measured` (the run's value of the measure), `pi` and `e`: `1/k`.
    #[schemars(length(min = 1, max = 256))]
    pub value: String,
    /// What that number means, shown in the verdict (may hold math).
    pub says: Text,
    /// The misconception this wrong number stands for.
    pub misconception: Option<Id>,
}

/// `section-id` or `section-id#anchor`.
pub struct ExplainLink;

impl JsonSchema for ExplainLink {
    fn schema_name() -> Cow<'static, str> {
        "ExplainLink".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let id = ID_PATTERN.trim_start_matches('^').trim_end_matches('$');
        json_schema!({
            "description": "A section id, or `section-id#anchor` where the section's body has a line `{#anchor}` above the paragraph to open at.",
            "type": "string",
            "pattern": format!("^{id}(#{id})?$"),
        })
    }
}

#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Choice {
    pub id: Id,
    pub label: Text,
    pub when: Condition,
    /// The misconception this (wrong) choice stands for.
    pub misconception: Option<Id>,
}

/// `{ abs = x }`: |given − measured| ≤ x; `{ rel = r }`: ≤ r·|measured|.
pub struct Tolerance;

impl JsonSchema for Tolerance {
    fn schema_name() -> Cow<'static, str> {
        "Tolerance".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let one = |key: &str, meaning: &str| {
            serde_json::json!({
                "type": "object",
                "properties": { key: { "description": meaning, "type": "number", "exclusiveMinimum": 0 } },
                "required": [key],
                "additionalProperties": false,
            })
        };
        json_schema!({
            "description": "How far the typed number may be from the measured value: exactly one of `abs` and `rel`, positive.",
            "oneOf": [
                one("abs", "|given − measured| ≤ abs"),
                one("rel", "|given − measured| ≤ rel · |measured|"),
            ],
        })
    }
}

/// A system's absolute tolerance: one number, or a table of variables'.
pub struct AtolSchema;

impl JsonSchema for AtolSchema {
    fn schema_name() -> Cow<'static, str> {
        "Atol".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let positive = serde_json::json!({
            "type": "number",
            "minimum": flipcard_sim::scene::spec::SceneAtol::MIN
        });
        json_schema!({
            "description": "Absolute tolerance of the error control: one number for every variable, or a table naming some variables (the others keep the method's default, 1e-2 × rtol). About a millionth of the size a variable reaches.",
            "oneOf": [
                positive,
                { "type": "object", "additionalProperties": positive, "minProperties": 1 },
            ],
        })
    }
}

/// A simulation: a torque-free rigid body (`inertia`, `omega`) or a system
/// of equations (`variables`, `initial`, `equations`), never both.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
#[schemars(extend("oneOf" = [
    { "required": ["inertia", "omega"], "not": { "required": ["variables"] } },
    { "required": ["variables", "initial", "equations"], "not": { "anyOf": [{ "required": ["inertia"] }, { "required": ["omega"] }, { "required": ["flat"] }] } }
]))]
pub struct Scene {
    pub id: Id,
    pub title: Option<Text>,
    /// Rigid body: principal moments of inertia (kg·m²): positive, finite,
    /// Iᵢ + Iⱼ ≥ Iₖ.
    #[schemars(extend("items" = { "type": "number", "exclusiveMinimum": 0 }))]
    pub inertia: Option<[f64; 3]>,
    /// Rigid body: body-frame angular velocity at t = 0 (rad per time
    /// unit), finite.
    pub omega: Option<[f64; 3]>,
    /// Run length in time units: > 0 (at most 1e6 for a rigid body; any
    /// finite length for a system, whose step budget guards the run time).
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub duration: f64,
    /// Panels shown; the scene computes only what they need.
    #[schemars(length(min = 1))]
    pub show: Vec<AnyPanel>,
    /// Label of the time unit (default `s`; `d` for days).
    pub time_unit: Option<NonEmpty>,
    /// Rigid body: flat on purpose (one moment equals the sum of the other
    /// two); silences the flat-body warning.
    pub flat: Option<bool>,
    /// System: the state's names, in order.
    #[schemars(length(min = 1))]
    pub variables: Option<Vec<VarName>>,
    /// System: one finite number per variable.
    pub initial: Option<Vec<f64>>,
    /// System: named constants.
    pub params: Option<std::collections::BTreeMap<String, f64>>,
    /// System: d/dt of each variable, same order, as expressions.
    pub equations: Option<Vec<Expression>>,
    /// System: named expressions; each may use the ones before it.
    pub observables: Option<std::collections::BTreeMap<String, Expression>>,
    /// System: observables whose drift the diagnostics report.
    pub conserved: Option<Vec<VarName>>,
    /// System: the absolute tolerance, one positive number for every
    /// variable or a table of some variables' own (`{ y2 = 1e-20 }`).
    pub atol: Option<AtolSchema>,
    /// System: a separable Hamiltonian H = T(p) + V(q), for the symplectic
    /// methods (`verlet`, `verlet4`): every variable once, as a position
    /// or a momentum.
    pub hamiltonian: Option<HamiltonianSchema>,
    /// System: variables or observables plotted against time.
    pub plot: Option<Vec<VarName>>,
    /// System: the pair of the phase portrait (horizontal, vertical).
    #[schemars(length(min = 2, max = 2))]
    pub phase: Option<Vec<VarName>>,
    /// System: lines, dots and trails drawn from expressions.
    pub sketch: Option<Vec<SketchMark>>,
    /// System: how the plots name some variables or observables, the
    /// names the question uses (`{ xc = "A" }`), 1 to 24 characters.
    pub labels: Option<std::collections::BTreeMap<String, String>>,
    /// Numbers the learner may turn while exploring the scene; the run
    /// restarts at each new value.
    pub knobs: Option<Vec<Knob>>,
    /// The measure plotted against a knob as the learner explores
    /// (`period(theta)`, `flip_period`); only with `knobs`.
    pub explore: Option<String>,
}

/// A knob: `name` is a system's parameter or `initial.VAR`, a rigid body's
/// `inertia[i]` or `omega[i]`; the scene gets value × `scale`; `check`
/// runs the scene at `min`, the middle and `max`.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Knob {
    /// `g`, `initial.theta`, `inertia[1]`, `omega[2]`.
    #[schemars(length(min = 1))]
    pub name: String,
    /// Lower end, in the knob's unit; holds the scene's own value with `max`.
    pub min: f64,
    /// Upper end, above `min`.
    pub max: f64,
    /// What one key turns: positive.
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub step: f64,
    /// The scene gets value × scale (degrees shown, radians run:
    /// 0.017453292519943295); not 0. Default 1.
    pub scale: Option<f64>,
    /// What the knob turns, in words.
    pub label: Text,
}

/// A system's separable Hamiltonian: its positions and their momenta.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct HamiltonianSchema {
    /// Positions: variables whose rates read only momenta.
    #[schemars(length(min = 1))]
    pub q: Vec<VarName>,
    /// Momenta, one per position: variables whose rates read only
    /// positions.
    #[schemars(length(min = 1))]
    pub p: Vec<VarName>,
}

/// A name of a variable, parameter or observable.
pub struct VarName;

impl JsonSchema for VarName {
    fn schema_name() -> Cow<'static, str> {
        "VarName".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "A letter or `_`, then letters, digits or `_` (at most 31).",
            "type": "string",
            "pattern": "^[A-Za-z_][A-Za-z0-9_]{0,30}$",
        })
    }
}

/// An expression of a system scene.
pub struct Expression;

impl JsonSchema for Expression {
    fn schema_name() -> Cow<'static, str> {
        "Expression".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let functions = flipcard_sim::system::expr::FUNCTIONS
            .iter()
            .map(|(f, _)| *f)
            .collect::<Vec<_>>()
            .join(" ");
        json_schema!({
            "description": format!("Numbers, + - * / ^, parentheses, the variables, params, observables, t, pi, e and the functions {functions}."),
            "type": "string",
            "pattern": NOT_BLANK,
        })
    }
}

/// `{ line = [x1, y1, x2, y2] }`, `{ dot = [x, y] }` (with an optional
/// `label`) or `{ trail = [x, y] }`.
pub struct SketchMark;

impl JsonSchema for SketchMark {
    fn schema_name() -> Cow<'static, str> {
        "SketchMark".into()
    }
    fn json_schema(g: &mut SchemaGenerator) -> Schema {
        let e = g.subschema_for::<Expression>().to_value();
        let text = g.subschema_for::<Text>().to_value();
        let one = |key: &str, n: usize| {
            let mut properties = serde_json::Map::new();
            properties.insert(
                key.to_string(),
                serde_json::json!({ "type": "array", "items": e.clone(), "minItems": n, "maxItems": n }),
            );
            if key == "dot" {
                let mut label = text.clone();
                if let Some(o) = label.as_object_mut() {
                    o.insert(
                        "description".into(),
                        "Drawn beside the dot (e.g. 'Sun').".into(),
                    );
                }
                properties.insert("label".into(), label);
            }
            serde_json::json!({
                "type": "object",
                "properties": properties,
                "required": [key],
                "additionalProperties": false,
            })
        };
        json_schema!({
            "description": "A sketch element; coordinates are expressions.",
            "oneOf": [one("line", 4), one("dot", 2), one("trail", 2)],
        })
    }
}

/// A panel of a rigid-body or a system scene.
pub struct AnyPanel;

impl JsonSchema for AnyPanel {
    fn schema_name() -> Cow<'static, str> {
        "AnyPanel".into()
    }
    fn json_schema(g: &mut SchemaGenerator) -> Schema {
        let rigid = g.subschema_for::<PanelName>().to_value();
        let system = names_schema(
            "A panel of a system scene.",
            SystemPanel::ALL.iter().map(|p| p.name()).collect(),
        )
        .to_value();
        json_schema!({ "anyOf": [rigid, system] })
    }
}

/// A measure: a rigid-body measure's name, or `stat(N)` on a system.
pub struct AnyMeasure;

impl JsonSchema for AnyMeasure {
    fn schema_name() -> Cow<'static, str> {
        "AnyMeasure".into()
    }
    fn json_schema(g: &mut SchemaGenerator) -> Schema {
        let rigid = g.subschema_for::<MeasureName>().to_value();
        json_schema!({ "anyOf": [rigid, {
            "description": "A statistic of a system's variable or observable N over the run.",
            "type": "string",
            "pattern": format!("^{}$", system_measure_pattern()),
        }] })
    }
}

/// `(max|min|…)\(name\)`.
/// A decimal number as a deck writes it (`2`, `-0.5`, `1e-3`).
const NUMBER: &str = r"[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?";

fn system_measure_pattern() -> String {
    let names = |level: bool| {
        vocabulary::stat_rows()
            .filter(|(_, s)| s.event().is_some() == level)
            .map(|(r, _)| r.name)
            .collect::<Vec<_>>()
            .join("|")
    };
    let (plain, with_level) = (names(false), names(true));
    let name = r"[A-Za-z_][A-Za-z0-9_]*";
    let number = NUMBER;
    format!(
        r"(({plain})\(\s*{name}\s*\)|({with_level})\(\s*{name}\s*(==|>=|<=|=|>|<)\s*{number}\s*\))"
    )
}

/// A content file: `content/<deck-id>/<lang>.toml`.
#[derive(JsonSchema)]
#[schemars(title = "flipcard explanations", deny_unknown_fields)]
pub struct ContentFile {
    /// Explanation sections, each under its own `[[section]]` header.
    pub section: Option<Vec<Section>>,
}

/// One explanation section, in this file's language.
#[derive(JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Section {
    /// The same ids in every language's file.
    pub id: Id,
    pub title: NonEmpty,
    /// Paragraphs split by blank lines, `- ` list items, `*emphasis*`, `**strong**`, `$math$`.
    pub body: NonEmpty,
    /// Ids of related sections.
    pub see: Option<Vec<Id>>,
}

/// Lowercase letters and digits joined by single hyphens, e.g. `middle-axis`.
pub struct Id;

impl JsonSchema for Id {
    fn schema_name() -> Cow<'static, str> {
        "Id".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "Lowercase letters and digits joined by single hyphens, e.g. `middle-axis`.",
            "type": "string",
            "pattern": ID_PATTERN,
        })
    }
}

/// A BCP 47 language tag.
pub struct LangTag;

impl JsonSchema for LangTag {
    fn schema_name() -> Cow<'static, str> {
        "LangTag".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "A BCP 47 language tag, e.g. `en`, `hi-Latn`.",
            "type": "string",
            "pattern": LANG_PATTERN,
        })
    }
}

/// A string with at least one character.
pub struct NonEmpty;

impl JsonSchema for NonEmpty {
    fn schema_name() -> Cow<'static, str> {
        "NonEmpty".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({ "type": "string", "pattern": NOT_BLANK })
    }
}

/// Accepted typed answers: one list, or one list per language.
pub struct Accept;

impl JsonSchema for Accept {
    fn schema_name() -> Cow<'static, str> {
        "Accept".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let list = serde_json::json!({
            "type": "array",
            "items": { "type": "string", "pattern": NOT_BLANK },
        });
        json_schema!({
            "description": "Accepted typed answers: ['middle', 'intermediate'] for every language, or { en = ['middle'], hi-Latn = ['beech wala'] } by language.",
            "anyOf": [
                list,
                {
                    "type": "object",
                    "propertyNames": { "pattern": LANG_PATTERN },
                    "additionalProperties": list,
                    "minProperties": 1,
                },
            ],
        })
    }
}

/// A text in every declared language.
pub struct Text;

impl JsonSchema for Text {
    fn schema_name() -> Cow<'static, str> {
        "Text".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "One string per declared language: { en = '...', hi-Latn = '...' } (a plain string when the deck declares one language). Write math in literal strings '...' so backslashes stay.",
            "anyOf": [
                {
                    "type": "object",
                    "propertyNames": { "pattern": LANG_PATTERN },
                    "additionalProperties": { "type": "string", "pattern": NOT_BLANK },
                    "minProperties": 1,
                },
                { "type": "string", "pattern": NOT_BLANK },
            ],
        })
    }
}

fn names_schema(description: &str, names: Vec<&'static str>) -> Schema {
    json_schema!({ "description": description, "type": "string", "enum": names })
}

pub struct CardKindName;

impl JsonSchema for CardKindName {
    fn schema_name() -> Cow<'static, str> {
        "CardKind".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        names_schema(
            "How the card is asked.",
            CardKind::ALL.map(CardKind::as_str).to_vec(),
        )
    }
}

pub(crate) struct MeasureName;

impl JsonSchema for MeasureName {
    fn schema_name() -> Cow<'static, str> {
        "Measure".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        names_schema(
            "What a scene's run measures.",
            vocabulary::rigid_rows().map(|(r, _)| r.name).collect(),
        )
    }
}

pub(crate) struct PanelName;

impl JsonSchema for PanelName {
    fn schema_name() -> Cow<'static, str> {
        "Panel".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        names_schema(
            "A panel of the scene view.",
            Panel::ALL.iter().map(|p| p.name()).collect(),
        )
    }
}

/// Comparisons of measures and numbers joined by `and`/`or`, e.g.
/// `flips > 0` or `0.2 < max(x) < 0.9`.
pub struct Condition;

impl JsonSchema for Condition {
    fn schema_name() -> Cow<'static, str> {
        "Condition".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let measures = vocabulary::rigid_rows()
            .map(|(r, _)| r.name)
            .chain(std::iter::once(system_measure_pattern().as_str()))
            .collect::<Vec<_>>()
            .join("|");
        let ops = Cmp::ALL
            .iter()
            .map(|(s, _)| *s)
            .collect::<Vec<_>>()
            .join("|");
        let number = NUMBER;
        let term = format!(r"(({measures})|abs\(\s*({measures})\s*\)|{number})");
        let chain = format!(r"{term}(\s*({ops})\s*{term})+");
        let pattern = format!(r"^\s*{chain}(\s+(and|or)\s+{chain})*\s*$");
        json_schema!({
            "description": "Comparisons of measures and numbers joined by `and` / `or` (`and` binds tighter), e.g. `flips > 0`, `0.2 < max(x) < 0.9`, `period(a) < period(b)`, `abs(final(x)) < 0.1 or flips > 2`; op is one of == != < <= > >=.",
            "type": "string",
            "pattern": pattern,
        })
    }
}

fn generate<T: JsonSchema>() -> serde_json::Value {
    let schema = SchemaSettings::draft07()
        .into_generator()
        .into_root_schema_for::<T>();
    let mut value = schema.to_value();
    strip_null(&mut value);
    value
}

/// TOML has no null: an optional field is simply left out, so the `null`
/// alternatives schemars gives `Option` fields are dropped.
fn strip_null(value: &mut serde_json::Value) {
    use serde_json::Value;
    match value {
        Value::Object(map) => {
            if let Some(Value::Array(types)) = map.get_mut("type") {
                types.retain(|t| t != "null");
                if types.len() == 1 {
                    let only = types.remove(0);
                    map.insert("type".into(), only);
                }
            }
            if let Some(Value::Array(alternatives)) = map.get_mut("anyOf") {
                alternatives.retain(|a| *a != serde_json::json!({ "type": "null" }));
                if alternatives.len() == 1 {
                    let only = alternatives.remove(0);
                    map.remove("anyOf");
                    if let Value::Object(inner) = only {
                        if inner.contains_key("$ref") && !map.is_empty() {
                            // draft-07 ignores keywords beside `$ref`.
                            map.insert("allOf".into(), Value::Array(vec![Value::Object(inner)]));
                        } else {
                            map.extend(inner);
                        }
                    }
                }
            }
            map.values_mut().for_each(strip_null);
        }
        Value::Array(items) => items.iter_mut().for_each(strip_null),
        _ => {}
    }
}

/// The schema of deck files.
pub fn deck_schema() -> serde_json::Value {
    let mut schema = generate::<DeckFile>();
    for kinds in ["/definitions/Answer", "/definitions/StepAsk"] {
        if let Some(answer) = schema.pointer_mut(kinds) {
            split_on_kind(answer);
        }
    }
    schema
}

/// Turns a `oneOf` of tagged variants into one `if kind == … then …` per
/// variant: an editor then checks a table against the variant its `kind`
/// names, and its error names the wrong field, where a failed `oneOf` lists
/// every alternative's complaints.
fn split_on_kind(schema: &mut serde_json::Value) {
    use serde_json::{Value, json};
    let Some(Value::Array(variants)) = schema.get("oneOf").cloned() else {
        return;
    };
    let mut kinds = Vec::new();
    let mut branches = Vec::new();
    for variant in variants {
        let Some(kind) = variant.pointer("/properties/kind/const").cloned() else {
            return;
        };
        kinds.push(kind.clone());
        branches.push(json!({
            "if": { "properties": { "kind": { "const": kind } }, "required": ["kind"] },
            "then": variant,
        }));
    }
    if let Value::Object(map) = schema {
        map.remove("oneOf");
        map.insert("type".into(), json!("object"));
        map.insert("required".into(), json!(["kind"]));
        map.insert(
            "properties".into(),
            json!({ "kind": { "description": "Which kind of answer; the other fields depend on it.", "enum": kinds } }),
        );
        map.insert("allOf".into(), Value::Array(branches));
    }
}

/// The schema of content files.
pub fn content_schema() -> serde_json::Value {
    generate::<ContentFile>()
}

/// Pretty JSON with a final newline, as checked in.
pub fn to_text(schema: &serde_json::Value) -> String {
    let mut s = serde_json::to_string_pretty(schema).unwrap_or_default();
    s.push('\n');
    s
}
