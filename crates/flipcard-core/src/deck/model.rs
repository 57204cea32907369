//! Validated domain types of a deck. Everything downstream (scheduler, store,
//! simulator, terminal UI) works on these, never on raw TOML.
//!
//! A value of these types has passed validation: ids are unique, every text
//! exists in every declared language, links resolve, scene numbers are physical.

pub use flipcard_sim::scene::knob::{Explore, Knob};
pub use flipcard_sim::scene::spec::{Measure, Panel, Scene, Stat, SystemPanel, SystemScene};
use std::collections::BTreeMap;
use std::path::PathBuf;

pub use flipcard_sim::system::equiv::Key as FormulaKey;
pub use flipcard_text::{Lang, Text};

/// A fully loaded and validated deck with its explanation sections.
#[derive(Debug, Clone, PartialEq)]
pub struct Deck {
    pub id: String,
    pub title: Text,
    pub description: Option<Text>,
    /// Declared languages, the first one being the deck's primary language.
    pub languages: Vec<Lang>,
    pub cards: Vec<Card>,
    pub prompts: Vec<Prompt>,
    pub scenes: Vec<Scene>,
    /// Scenes that are systems of equations.
    pub systems: Vec<SystemScene>,
    /// Explanation sections in reading order (the order of the primary
    /// language's content file); titles and bodies per language.
    pub sections: Vec<Section>,
    /// Units the deck declares for typed answers, besides the known ones.
    pub units: Vec<flipcard_text::units::Declared>,
    /// Named misconceptions (`[[misconception]]`) the prompts' wrong
    /// answers stand for.
    pub misconceptions: Vec<Misconception>,
    /// The knobs of the scenes that have them, and what each plots
    /// against its knob (`knobs`, `explore`).
    pub explore: Vec<Explore>,
    /// Derivations step by step (`[[derivation]]`), each a review item
    /// asked in the direction `derive`, in deck order.
    pub derivations: Vec<Derivation>,
    /// The deck file this was loaded from.
    pub path: PathBuf,
    /// The deck it sits under on home (`parent = "ID"`): studying that
    /// deck studies this one too.
    pub parent: Option<String>,
}

impl Deck {
    pub fn card(&self, id: &str) -> Option<&Card> {
        self.cards.iter().find(|c| c.id == id)
    }
    pub fn prompt(&self, id: &str) -> Option<&Prompt> {
        self.prompts.iter().find(|p| p.id == id)
    }
    pub fn scene(&self, id: &str) -> Option<&Scene> {
        self.scenes.iter().find(|s| s.id == id)
    }
    pub fn system(&self, id: &str) -> Option<&SystemScene> {
        self.systems.iter().find(|s| s.id == id)
    }
    pub fn section(&self, id: &str) -> Option<&Section> {
        self.sections.iter().find(|s| s.id == id)
    }
    /// The knobs of scene `id`, when it has any.
    pub fn explore(&self, id: &str) -> Option<&Explore> {
        self.explore.iter().find(|e| e.scene == id)
    }
    pub fn misconception(&self, id: &str) -> Option<&Misconception> {
        self.misconceptions.iter().find(|m| m.id == id)
    }
    pub fn derivation(&self, id: &str) -> Option<&Derivation> {
        self.derivations.iter().find(|d| d.id == id)
    }
}

/// A derivation shown step by step (`[[derivation]]`): a worked example
/// the first time, later with steps faded for the learner to supply
/// (`study::derive`). Its id shares the card id space (review history is
/// keyed by deck, id and direction `derive`, and no card has its id).
#[derive(Debug, Clone, PartialEq)]
pub struct Derivation {
    pub id: String,
    pub title: Text,
    /// The explanation section (and anchor) it belongs to.
    pub explain: Option<Explain>,
    pub tags: Vec<String>,
    /// The steps in order, at least one, at most
    /// `validate::derivation::MAX_STEPS`.
    pub steps: Vec<Step>,
}

/// One step of a derivation: its math, why it is taken, and what the
/// learner is asked before the math is shown when the step is faded.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// The step's math (`$…$`), in every language (the same string where
    /// the deck wrote one for all).
    pub math: Text,
    /// Why this step: shown with the math, and as the hint of a faded step.
    pub why: Text,
    pub ask: Option<Ask>,
}

/// What a faded step asks.
#[derive(Debug, Clone, PartialEq)]
pub struct Ask {
    /// The question put to the learner (`None`: the screen's own words).
    pub question: Option<Text>,
    pub kind: AskKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum AskKind {
    /// Think, then reveal: nothing is checked.
    Reveal,
    /// Pick one; `answer` is the id of the right choice.
    Choice {
        choices: Vec<AskChoice>,
        answer: String,
    },
    /// Type a formula, checked by equivalence as a formula card's.
    Formula(FormulaKey),
}

#[derive(Debug, Clone, PartialEq)]
pub struct AskChoice {
    pub id: String,
    pub label: Text,
}

/// A misconception a wrong answer stands for (`[[misconception]]`): its
/// name, why it seems right (the steel-man) and the fix, in every language.
#[derive(Debug, Clone, PartialEq)]
pub struct Misconception {
    pub id: String,
    pub title: Text,
    pub why_it_seems_right: Text,
    pub fix: Text,
    /// The explanation section (and anchor) that treats it.
    pub explain: Option<Explain>,
}

/// Wrong numbers from `lo` to `hi` (both included) stand for the
/// misconception `id` (`misconceptions = [{ range = [lo, hi], id }]`).
#[derive(Debug, Clone, PartialEq)]
pub struct WrongRange {
    pub lo: f64,
    pub hi: f64,
    pub id: String,
}

impl WrongRange {
    pub fn contains(&self, v: f64) -> bool {
        self.lo <= v && v <= self.hi
    }
}

impl Card {
    /// The answers to compare a typed answer with when the learner reads
    /// `lang`: that language's own first (so the nearest shown is in the
    /// learner's language on a tie), then every other accepted answer.
    pub fn accepted(&self, lang: &str) -> Vec<String> {
        let mut out: Vec<String> = self.accept_by_lang.get(lang).cloned().unwrap_or_default();
        for a in &self.accept {
            if !out.contains(a) {
                out.push(a.clone());
            }
        }
        out
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CardKind {
    /// Asked front → back.
    Basic,
    /// Asked front → back and, as a separate review item, back → front.
    Reversed,
    /// The learner types the answer; compared against `Card::accept`.
    Typed,
    /// A text with deletions `{{c1::…}}`: `front` holds it, each number
    /// is its own review item, `back` holds optional extra notes.
    Cloze,
    /// The learner types a formula; compared with `Card::formula` at
    /// points of its domain (`flipcard_sim::system::equiv`).
    Formula,
}

impl CardKind {
    pub fn as_str(self) -> &'static str {
        match self {
            CardKind::Basic => "basic",
            CardKind::Reversed => "reversed",
            CardKind::Typed => "typed",
            CardKind::Cloze => "cloze",
            CardKind::Formula => "formula",
        }
    }

    /// Whether the learner types the answer (a typed or formula card).
    pub fn is_typed(self) -> bool {
        matches!(self, CardKind::Typed | CardKind::Formula)
    }

    pub const ALL: [CardKind; 5] = [
        CardKind::Basic,
        CardKind::Reversed,
        CardKind::Typed,
        CardKind::Cloze,
        CardKind::Formula,
    ];
}

impl Card {
    /// The deletion numbers of a cloze card (the same in every language,
    /// as validation ensures); empty for other kinds.
    pub(crate) fn cloze_numbers(&self) -> Vec<u16> {
        if self.kind != CardKind::Cloze {
            return Vec::new();
        }
        self.front
            .0
            .values()
            .next()
            .map(|t| super::cloze::numbers(t).into_iter().collect())
            .unwrap_or_default()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Card {
    /// Stable identity: review history is keyed by deck id + card id.
    pub id: String,
    pub kind: CardKind,
    pub front: Text,
    pub back: Text,
    /// Accepted typed answers (only for `CardKind::Typed`, never empty
    /// there), every language's, the primary language's first.
    pub accept: Vec<String>,
    /// The answers written for one language (`accept = { en = [...] }`);
    /// empty when one list serves every language.
    pub accept_by_lang: BTreeMap<String, Vec<String>>,
    /// Section id of the linked explanation.
    pub explain: Option<Explain>,
    /// Prompt id offered after the answer is shown.
    pub prompt: Option<String>,
    pub tags: Vec<String>,
    /// The key of a formula card (only for `CardKind::Formula`, always
    /// there).
    pub formula: Option<FormulaKey>,
}

/// A predict-then-check prompt: the learner commits to an answer, the scene
/// runs, and the verdict compares the prediction with what was measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Prompt {
    pub id: String,
    pub question: Text,
    /// Scene id that is run to check the prediction.
    pub scene: String,
    pub explain: Option<Explain>,
    pub answer: Answer,
    pub tags: Vec<String>,
    /// What the prompt measures, named in words by the deck (`label` in
    /// `[prompt.answer]`), when the measure's own name cannot say it.
    pub measured: Option<Measured>,
    /// The numbers each attempt draws anew (`vary`), in name order;
    /// empty for a prompt asked the same way every time. A varied
    /// prompt's answer is computed from each variant's run
    /// (`predict::variant`).
    pub vary: Vec<Varied>,
}

impl Prompt {
    /// The question in `lang` as a list shows it before any numbers are
    /// drawn: a varied prompt's `{name}` placeholders read "…".
    pub fn question_listed(&self, lang: &str) -> std::borrow::Cow<'_, str> {
        let text = self.question.get(lang);
        if self.vary.is_empty() {
            return text.into();
        }
        let names: Vec<&str> = self.vary.iter().map(|v| v.name.as_str()).collect();
        flipcard_text::fill::blanked(text, &names, "…").into()
    }
}

/// One number a varied prompt draws for each attempt: shown in the
/// question as `{name}` (in its own unit), set into the scene as its value
/// × `scale`.
#[derive(Debug, Clone, PartialEq)]
pub struct Varied {
    pub name: String,
    /// What it sets in the prompt's scene.
    pub target: flipcard_sim::scene::knob::Target,
    pub draw: Draw,
    /// The scene gets the drawn value × `scale`.
    pub scale: f64,
    /// The decimals the question shows it with (the most any `{name:.N}`
    /// asks for): a uniform draw is rounded to them, so the number read is
    /// the number run. `None`: three significant digits.
    pub decimals: Option<u8>,
}

impl Varied {
    /// The number a uniform `u` in [0, 1) draws: on the grid of a step,
    /// one of the values, or in the range rounded as the question shows it
    /// (to its decimals, else to three significant digits), never outside
    /// the range.
    pub fn value_at(&self, u: f64) -> f64 {
        let u = if u.is_finite() {
            u.clamp(0.0, 1.0)
        } else {
            0.0
        };
        match &self.draw {
            Draw::Values(v) => {
                let i = ((u * v.len() as f64) as usize).min(v.len().saturating_sub(1));
                v.get(i).copied().unwrap_or(f64::NAN)
            }
            Draw::Range {
                min,
                max,
                step: Some(step),
            } => {
                let last = ((max - min) / step).floor().max(0.0);
                let k = (u * (last + 1.0)).floor().min(last);
                flipcard_sim::scene::knob::tidy((min + k * step).clamp(*min, *max))
            }
            Draw::Range {
                min,
                max,
                step: None,
            } => {
                let v = min + u * (max - min);
                let rounded = match self.decimals {
                    Some(d) => {
                        let f = 10f64.powi(i32::from(d));
                        (v * f).round() / f
                    }
                    None => flipcard_text::num::sig(v, 3).parse().unwrap_or(v),
                };
                let r = if rounded.is_finite() { rounded } else { v };
                r.clamp(*min, *max)
            }
        }
    }

    /// The numbers `deck check` tries alone: the ends and the middle of
    /// the range (on its grid), or the first, middle and last value.
    pub fn samples(&self) -> Vec<f64> {
        match &self.draw {
            Draw::Values(v) => {
                let mut out = vec![v[0], v[v.len() / 2], v[v.len() - 1]];
                out.dedup();
                out
            }
            Draw::Range { min, max, step } => {
                let mid = match step {
                    Some(s) => (min + ((max - min) / s / 2.0).floor() * s).clamp(*min, *max),
                    None => (min + max) / 2.0,
                };
                vec![*min, mid, *max]
            }
        }
    }
}

/// How a varied number is drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum Draw {
    /// Uniformly in `[min, max]`; on the grid `min + k·step` when a step
    /// is given.
    Range {
        min: f64,
        max: f64,
        step: Option<f64>,
    },
    /// One of these, each as likely.
    Values(Vec<f64>),
}

/// A prompt's measure named by its deck: the verdict reads it as
/// "time for B to get within 1% of rest: 4.30 s" rather than by the
/// measure's own name ("largest settle_h 4.30").
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// The measure it names: a number answer's `measure`, or the one
    /// measure a choice answer's conditions read.
    pub measure: Measure,
    /// What it is, in words, in every language.
    pub label: Text,
    /// Its unit, "" for none: a number answer's `unit`, a choice answer's
    /// own `unit`.
    pub unit: String,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    /// Pick one of several choices; the simulation's measurements decide
    /// which choice is right through each choice's `when` condition.
    Choice {
        choices: Vec<Choice>,
        /// The choice id the physics gives, worked out by hand by the author;
        /// tests compare it with the simulation. `None` on a varied prompt
        /// without one: the choice whose `when` holds in the variant's run.
        expected: Option<String>,
    },
    /// A number (with optional unit) compared with a measurement.
    Number {
        measure: Measure,
        /// Unit shown to the learner and accepted after the number (`s`, `d`, `rad/s`).
        unit: String,
        /// The value the formula gives, worked out by hand by the author;
        /// `None` on a varied prompt (`expected = "period(theta)"`): the
        /// value the variant's run measures.
        expected: Option<f64>,
        tolerance: Tolerance,
        /// The formula behind `expected`, shown in the verdict (may hold math).
        formula: Option<Text>,
        /// Known wrong numbers (`slips`): what a learner gets by a known
        /// mistake, and what it means, in the author's order.
        slips: Vec<Slip>,
        /// Ranges of wrong numbers that stand for a misconception, in the
        /// author's order.
        misconceptions: Vec<WrongRange>,
    },
    /// A typed formula, right when it equals `expected` over the domain
    /// (`flipcard_sim::system::equiv`); no measurement decides it.
    Formula(FormulaKey),
}

/// Where `e` opens the reader: a section, and a place inside it
/// (`explain = "section-id#anchor"`, the anchor a `{#anchor}` line of the
/// section's body in every language).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Explain {
    pub section: String,
    pub anchor: Option<String>,
}

impl From<&str> for Explain {
    /// `"section"` or `"section#anchor"`, as a deck writes it.
    fn from(s: &str) -> Explain {
        match s.split_once('#') {
            Some((section, anchor)) => Explain {
                section: section.to_string(),
                anchor: Some(anchor.to_string()),
            },
            None => Explain {
                section: s.to_string(),
                anchor: None,
            },
        }
    }
}

impl std::fmt::Display for Explain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.section)?;
        match &self.anchor {
            Some(a) => write!(f, "#{a}"),
            None => Ok(()),
        }
    }
}

/// A known wrong number of a number answer: `value` is a formula over the
/// scene's numbers (see `flipcard_sim::scene::quantities`) and `measured`,
/// the run's value of the prompt's measure; a learner's number within the
/// prompt's tolerance of it gets `says` in the verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Slip {
    /// The formula as written (`1/k`), shown in the verdict.
    pub value: String,
    /// What that number means, in every language.
    pub says: Text,
    /// The scene's numbers the formula may read, with their values.
    pub scope: Vec<(String, f64)>,
    /// The misconception this slip stands for.
    pub misconception: Option<String>,
}

impl Slip {
    /// The slip's number when the run measured `measured`; `None` when it
    /// is not finite there (or the formula does not read, which a loaded
    /// deck's never does).
    pub fn value_for(&self, measured: f64) -> Option<f64> {
        let mut names = self.scope.clone();
        names.push((
            flipcard_sim::scene::quantities::MEASURED.to_string(),
            measured,
        ));
        flipcard_sim::system::formula::evaluate(&self.value, &names).ok()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    pub id: String,
    pub label: Text,
    /// This choice is right when the condition holds for the measurements.
    pub when: Condition,
    /// The misconception this choice stands for, when it is wrong.
    pub misconception: Option<String>,
}

/// A choice's `when`: comparisons joined by `and` and `or` (`and` binds
/// tighter), each a chain of terms (`flips > 0`, `0.2 < max(f2) < 0.9`,
/// `period(x1) < period(x2)`, `abs(final(x)) < 0.1 or flips > 2`). Every
/// chain names a measure. Kept as alternatives of conjunctions.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    /// `or` of `and`s of comparisons; never empty, nor any of its parts.
    pub any: Vec<Vec<Comparison>>,
}

/// One comparison of two terms, `left op right`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparison {
    pub left: Term,
    pub op: Cmp,
    pub right: Term,
}

/// What a comparison compares: a number, a measure, or a measure's size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Term {
    Number(f64),
    Measure(Measure),
    /// `abs(measure)`.
    Abs(Measure),
}

impl Term {
    fn measure(self) -> Option<Measure> {
        match self {
            Term::Number(_) => None,
            Term::Measure(m) | Term::Abs(m) => Some(m),
        }
    }

    /// The term's value, with `get` for the measures (None where the run
    /// has none).
    fn value(self, get: &impl Fn(Measure) -> Option<f64>) -> Option<f64> {
        match self {
            Term::Number(v) => Some(v),
            Term::Measure(m) => get(m),
            Term::Abs(m) => get(m).map(f64::abs),
        }
    }
}

impl std::fmt::Display for Term {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Term::Number(v) => write!(f, "{}", flipcard_text::num::Num(*v)),
            Term::Measure(m) => write!(f, "{m}"),
            Term::Abs(m) => write!(f, "abs({m})"),
        }
    }
}

impl Cmp {
    /// Whether `a op b`.
    pub fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
        }
    }
}

impl Condition {
    /// `measure op value`, the simplest condition.
    pub fn compare(measure: Measure, op: Cmp, value: f64) -> Condition {
        Condition {
            any: vec![vec![Comparison {
                left: Term::Measure(measure),
                op,
                right: Term::Number(value),
            }]],
        }
    }

    /// The measures it names, in order of first appearance.
    pub fn measures(&self) -> Vec<Measure> {
        let mut out = Vec::new();
        for c in self.any.iter().flatten() {
            for m in [c.left.measure(), c.right.measure()].into_iter().flatten() {
                if !out.contains(&m) {
                    out.push(m);
                }
            }
        }
        out
    }

    /// The first measure it names (what a verdict reads first).
    pub fn measure(&self) -> Measure {
        self.measures().first().copied().unwrap_or(Measure::Flips)
    }

    /// `measure op number` when that is all it says.
    pub fn single(&self) -> Option<(Measure, Cmp, f64)> {
        match self.any.as_slice() {
            [conj] => match conj.as_slice() {
                [
                    Comparison {
                        left: Term::Measure(m),
                        op,
                        right: Term::Number(v),
                    },
                ] => Some((*m, *op, *v)),
                _ => None,
            },
            _ => None,
        }
    }

    /// Whether it holds with the run's values from `get`; None when a
    /// measure it needs is missing (a condition on a measure the run could
    /// not make never holds).
    pub fn holds_on(&self, get: impl Fn(Measure) -> Option<f64>) -> Option<bool> {
        let mut any = false;
        for conj in &self.any {
            let mut all = true;
            for c in conj {
                let (a, b) = (c.left.value(&get)?, c.right.value(&get)?);
                all &= c.op.holds(a, b);
            }
            any |= all;
        }
        Some(any)
    }

    /// Whether it holds when every measure it names reads `measured` (for
    /// a condition on one measure).
    pub fn holds(&self, measured: f64) -> bool {
        self.holds_on(|_| Some(measured)).unwrap_or(false)
    }
}

impl std::fmt::Display for Condition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, conj) in self.any.iter().enumerate() {
            if i > 0 {
                f.write_str(" or ")?;
            }
            // A chain `a < m < b` is two comparisons sharing `m`: written
            // once.
            let mut prev: Option<Term> = None;
            for (j, c) in conj.iter().enumerate() {
                if prev == Some(c.left) {
                    write!(f, " {} {}", c.op.as_str(), c.right)?;
                } else {
                    if j > 0 {
                        f.write_str(" and ")?;
                    }
                    write!(f, "{} {} {}", c.left, c.op.as_str(), c.right)?;
                }
                prev = Some(c.right);
            }
        }
        Ok(())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Cmp {
    pub const ALL: [(&'static str, Cmp); 6] = [
        ("==", Cmp::Eq),
        ("!=", Cmp::Ne),
        ("<=", Cmp::Le),
        (">=", Cmp::Ge),
        ("<", Cmp::Lt),
        (">", Cmp::Gt),
    ];
    pub fn as_str(self) -> &'static str {
        Cmp::ALL
            .iter()
            .find(|(_, c)| *c == self)
            .map(|(s, _)| *s)
            .unwrap_or("==")
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// |given − measured| ≤ value.
    Abs(f64),
    /// |given − measured| ≤ value · |measured|.
    Rel(f64),
}

impl Tolerance {
    pub fn accepts(&self, given: f64, measured: f64) -> bool {
        let diff = (given - measured).abs();
        match *self {
            Tolerance::Abs(a) => diff <= a,
            Tolerance::Rel(r) => diff <= r * measured.abs(),
        }
    }
}

/// One explanation section, in every declared language.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    pub id: String,
    pub title: Text,
    pub body: Text,
    /// Ids of related sections (the concept map), in the author's order.
    pub see: Vec<String>,
}
