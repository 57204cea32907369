//! Prompts that come back as new variants (issue 24 §2). A varied prompt
//! (`vary` in the deck) draws its numbers for each attempt from a seed
//! that is stored with the attempt; the drawn numbers are set into the
//! prompt's scene, shown in its question (`{theta0}`), and the answer is
//! what the variant's run measures (a number prompt's measure, the choice
//! whose `when` holds). One seed gives the same variant on every machine
//! and in every version: the generator is SplitMix64, written out here,
//! and a seed is at most [`MAX_SEED`] (2⁵³ − 1, exact in JSON).

use crate::deck::{Answer, Deck, Prompt, Scene, SystemScene};
use flipcard_sim::scene::knob;
use flipcard_sim::scene::measure::Measurements;

/// The largest seed: 2⁵³ − 1, a number every JSON reader holds exactly.
pub const MAX_SEED: u64 = crate::store::MAX_VARIANT;

/// The numbers of one attempt at a varied prompt.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    /// The seed they were drawn from (`None` for numbers chosen, as
    /// `check` chooses the ends of each range).
    pub seed: Option<u64>,
    /// Each varied number by name, in name order, in its own unit.
    pub values: Vec<(String, f64)>,
}

impl Variant {
    /// "theta0 = 35, L = 1.25", as messages name a variant.
    pub fn describe(&self) -> String {
        self.values
            .iter()
            .map(|(n, v)| format!("{n} = {}", flipcard_text::num::show(*v)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// SplitMix64: one step of the generator.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from the generator.
fn uniform(state: &mut u64) -> f64 {
    (splitmix(state) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The variant seed `seed` draws for `prompt`: each varied number in name
/// order takes the next uniform number.
pub fn draw(prompt: &Prompt, seed: u64) -> Variant {
    let mut state = seed;
    Variant {
        seed: Some(seed),
        values: prompt
            .vary
            .iter()
            .map(|v| (v.name.clone(), v.value_at(uniform(&mut state))))
            .collect(),
    }
}

/// A seed for a new attempt: from the deck, the prompt, how many attempts
/// came before and the time, so each return draws anew (and a test with a
/// fixed clock draws the same).
pub fn seed_for(deck: &str, prompt: &str, attempts: u32, now_ms: i64) -> u64 {
    // FNV-1a over the words, then mixed.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in deck
        .bytes()
        .chain([0])
        .chain(prompt.bytes())
        .chain([0])
        .chain(attempts.to_le_bytes())
        .chain(now_ms.to_le_bytes())
    {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01B3);
    }
    splitmix(&mut h) & MAX_SEED
}

/// A new variant for an attempt, other than `last` when the prompt can
/// give another (up to 16 seeds are tried).
pub fn fresh(prompt: &Prompt, seed: u64, last: Option<&Variant>) -> Variant {
    let mut state = seed;
    let mut v = draw(prompt, seed);
    for _ in 0..16 {
        if last.is_none_or(|l| l.values != v.values) {
            break;
        }
        v = draw(prompt, splitmix(&mut state) & MAX_SEED);
    }
    v
}

/// The variants `check` runs: every number at its low end, at its high
/// end, each alone at its ends with the others in the middle, all in the
/// middle, and four seeded draws; the same ones every time.
pub fn samples(prompt: &Prompt) -> Vec<Variant> {
    let sets: Vec<Vec<f64>> = prompt.vary.iter().map(|v| v.samples()).collect();
    let mid = |s: &Vec<f64>| s[s.len() / 2];
    let named = |values: Vec<f64>| Variant {
        seed: None,
        values: prompt
            .vary
            .iter()
            .map(|v| v.name.clone())
            .zip(values)
            .collect(),
    };
    let mut out: Vec<Variant> = Vec::new();
    let mut push = |v: Variant| {
        if !out.iter().any(|o| o.values == v.values) {
            out.push(v);
        }
    };
    push(named(sets.iter().map(|s| s[0]).collect()));
    push(named(sets.iter().map(|s| s[s.len() - 1]).collect()));
    push(named(sets.iter().map(mid).collect()));
    if sets.len() > 1 {
        for i in 0..sets.len() {
            for end in [0, sets[i].len() - 1] {
                push(named(
                    sets.iter()
                        .enumerate()
                        .map(|(j, s)| if j == i { s[end] } else { mid(s) })
                        .collect(),
                ));
            }
        }
    }
    let mut state = seed_for("check", &prompt.id, 0, 0);
    for _ in 0..4 {
        push(draw(prompt, splitmix(&mut state) & MAX_SEED));
    }
    out
}

/// A prompt's scene, of either kind.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneOf {
    Rigid(Scene),
    System(Box<SystemScene>),
}

/// A prompt as one attempt asks it: the question (and every text that
/// shows the numbers) filled in, the scene with the variant's numbers, the
/// slips reading them.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    pub prompt: Prompt,
    pub scene: SceneOf,
    pub variant: Option<Variant>,
}

/// `prompt` of `deck` asked with `variant` (as written when `None`, or
/// when the prompt does not vary); `None` when its scene is not in the
/// deck.
pub fn resolve(deck: &Deck, prompt: &Prompt, variant: Option<&Variant>) -> Option<Resolved> {
    let mut scene = match (deck.system(&prompt.scene), deck.scene(&prompt.scene)) {
        (Some(s), _) => SceneOf::System(Box::new(s.clone())),
        (None, Some(s)) => SceneOf::Rigid(s.clone()),
        (None, None) => return None,
    };
    let variant = variant.filter(|_| !prompt.vary.is_empty());
    let Some(variant) = variant else {
        return Some(Resolved {
            prompt: prompt.clone(),
            scene,
            variant: None,
        });
    };
    for v in &prompt.vary {
        let Some((_, value)) = variant.values.iter().find(|(n, _)| *n == v.name) else {
            continue;
        };
        let x = value * v.scale;
        scene = match scene {
            SceneOf::System(s) => SceneOf::System(Box::new(knob::set_system(&s, &v.target, x))),
            SceneOf::Rigid(s) => SceneOf::Rigid(knob::set_rigid(&s, &v.target, x)),
        };
    }
    let values: Vec<(&str, f64)> = variant
        .values
        .iter()
        .map(|(n, v)| (n.as_str(), *v))
        .collect();
    let fill = |t: &flipcard_text::Text| {
        flipcard_text::Text(
            t.0.iter()
                .map(|(l, s)| (l.clone(), flipcard_text::fill::fill(s, &values)))
                .collect(),
        )
    };
    let mut p = prompt.clone();
    p.question = fill(&p.question);
    if let Some(m) = &mut p.measured {
        m.label = fill(&m.label);
    }
    // The numbers a slip's formula reads, at the variant's values.
    let scope = match &scene {
        SceneOf::System(s) => s.params.clone(),
        SceneOf::Rigid(s) => flipcard_sim::scene::quantities::rigid(s.inertia, s.omega),
    };
    match &mut p.answer {
        Answer::Choice { choices, .. } => {
            for c in choices {
                c.label = fill(&c.label);
            }
        }
        Answer::Number { formula, slips, .. } => {
            if let Some(f) = formula {
                *f = fill(f);
            }
            for s in slips {
                s.says = fill(&s.says);
                for (name, value) in &mut s.scope {
                    if let Some((_, v)) = scope.iter().find(|(n, _)| n == name) {
                        *value = *v;
                    }
                }
            }
        }
        Answer::Formula(_) => {}
    }
    Some(Resolved {
        prompt: p,
        scene,
        variant: Some(variant.clone()),
    })
}

/// Why a variant's run does not decide its prompt.
#[derive(Debug, Clone, PartialEq)]
pub enum Undecided {
    /// The number prompt's measure was not made (`why`, when said).
    NotMeasured,
    /// No choice's `when` holds.
    NoChoice,
    /// Several hold (their ids).
    Several(Vec<String>),
}

/// `prompt` (resolved) with the answer its run decides written in as
/// `expected`, as `check` audits it: the measured number, or the one
/// choice that holds.
pub fn decided(prompt: &Prompt, m: &Measurements) -> Result<Prompt, Undecided> {
    let mut p = prompt.clone();
    match &mut p.answer {
        Answer::Number {
            measure, expected, ..
        } => match m.get(*measure) {
            Some(v) if v.is_finite() => *expected = Some(v),
            _ => return Err(Undecided::NotMeasured),
        },
        Answer::Choice { choices, expected } => {
            let holding: Vec<&str> = choices
                .iter()
                .filter(|c| c.when.holds_on(|x| m.get(x)).unwrap_or(false))
                .map(|c| c.id.as_str())
                .collect();
            match holding.as_slice() {
                [] => return Err(Undecided::NoChoice),
                [one] => {
                    if expected.is_none() {
                        *expected = Some(one.to_string());
                    }
                }
                many => {
                    return Err(Undecided::Several(
                        many.iter().map(|s| s.to_string()).collect(),
                    ));
                }
            }
        }
        Answer::Formula(_) => {}
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::{Draw, Varied};
    use flipcard_sim::scene::knob::Target;

    fn varied(name: &str, draw: Draw, decimals: Option<u8>) -> Varied {
        Varied {
            name: name.into(),
            target: Target::Param(name.into()),
            draw,
            scale: 1.0,
            decimals,
        }
    }

    fn prompt(vary: Vec<Varied>) -> Prompt {
        Prompt {
            id: "p".into(),
            question: flipcard_text::Text::default(),
            scene: "s".into(),
            explain: None,
            answer: Answer::Choice {
                choices: Vec::new(),
                expected: None,
            },
            tags: Vec::new(),
            measured: None,
            vary,
        }
    }

    #[test]
    fn a_seed_draws_the_same_numbers_always() {
        let p = prompt(vec![
            varied(
                "theta0",
                Draw::Range {
                    min: 20.0,
                    max: 80.0,
                    step: None,
                },
                Some(0),
            ),
            varied(
                "L",
                Draw::Range {
                    min: 0.5,
                    max: 2.0,
                    step: None,
                },
                None,
            ),
            varied("k", Draw::Values(vec![1.0, 2.0, 4.0]), None),
        ]);
        // Pinned: a stored seed must draw these in every version.
        let v = draw(&p, 12345);
        let again = draw(&p, 12345);
        assert_eq!(v, again);
        let got: Vec<f64> = v.values.iter().map(|(_, x)| *x).collect();
        assert_eq!(
            got, PINNED,
            "the generator changed: stored seeds would draw other numbers"
        );
        assert_ne!(draw(&p, 12346).values, v.values);
    }
    /// Seed 12345 through SplitMix64 gives the uniforms 0.13308, 0.20482 and
    /// 0.11954 (worked out apart, in Python): 20 + 0.13308 × 60 = 27.98,
    /// shown with 0 decimals, is 28; 0.5 + 0.20482 × 1.5 = 0.80722, to
    /// three digits, 0.807; the first of three values.
    const PINNED: [f64; 3] = [28.0, 0.807, 1.0];

    // Longer: PROPTEST_CASES=100000 cargo test -p flipcard-core variant::
    proptest::proptest! {
        #[test]
        fn every_draw_is_in_range_and_as_shown(
            seed in 0u64..=MAX_SEED,
            lo in -1e6f64..1e6,
            span in 1e-3f64..1e6,
            decimals in proptest::option::of(0u8..6),
            step in proptest::option::of(1e-3f64..10.0),
        ) {
            let hi = lo + span;
            let step = step.filter(|s| span / s < 1e6);
            let p = prompt(vec![varied("a", Draw::Range { min: lo, max: hi, step }, decimals)]);
            let v = draw(&p, seed).values[0].1;
            proptest::prop_assert!((lo..=hi).contains(&v), "{v} outside [{lo}, {hi}]");
            if let (Some(d), None) = (decimals, step) {
                // The question shows exactly the number run (or an end).
                let shown: f64 = flipcard_text::fill::shown(v, Some(d)).parse().unwrap();
                proptest::prop_assert!(shown == v || v == lo || v == hi, "{v} shown as {shown}");
            }
            proptest::prop_assert!(seed_for("d", "p", 3, seed as i64) <= MAX_SEED);
        }
    }

    #[test]
    fn fresh_variants_differ_from_the_last_when_they_can() {
        let p = prompt(vec![varied("k", Draw::Values(vec![1.0, 2.0]), None)]);
        for seed in 0..50 {
            let last = draw(&p, seed);
            assert_ne!(fresh(&p, seed, Some(&last)).values, last.values);
        }
    }

    #[test]
    fn samples_cover_the_ends_and_the_middle() {
        let p = prompt(vec![
            varied(
                "a",
                Draw::Range {
                    min: 0.0,
                    max: 10.0,
                    step: Some(5.0),
                },
                None,
            ),
            varied("b", Draw::Values(vec![1.0, 2.0, 3.0]), None),
        ]);
        let s = samples(&p);
        let has = |a: f64, b: f64| s.iter().any(|v| v.values[0].1 == a && v.values[1].1 == b);
        assert!(has(0.0, 1.0) && has(10.0, 3.0) && has(5.0, 2.0));
        assert!(has(0.0, 2.0) && has(10.0, 2.0) && has(5.0, 1.0) && has(5.0, 3.0));
        assert!(s.len() >= 7 && s.len() <= 11, "{}", s.len());
        assert_eq!(samples(&p), s, "the same every time");
    }
}
