//! The bundled deck `torque-free-rotation`: it loads without diagnostics, has
//! the promised amount of content in both languages, and every hand-computed
//! answer of its prompts agrees with the closed-form physics of its scene.

use std::f64::consts::PI;

use flipcard::deck::{Answer, Deck, Measure, Scene, Text};

const DECK_ID: &str = "torque-free-rotation";
const LANGS: [&str; 2] = ["en", "hi-Latn"];

fn deck() -> Deck {
    let loaded = flipcard::bundled::load();
    // Not even a warning: the thin plate I = (1, 2, 3) of the worked
    // numbers is declared `flat = true` on purpose.
    assert!(
        loaded.diagnostics.is_empty(),
        "the bundled decks must load cleanly:\n{}",
        loaded.render_all()
    );
    loaded
        .decks
        .into_iter()
        .find(|d| d.id == DECK_ID)
        .unwrap_or_else(|| panic!("deck {DECK_ID} is not among the bundled decks"))
}

/// Every text in every language is present and has visible content.
fn assert_full(text: &Text, what: &str, problems: &mut Vec<String>) {
    for lang in LANGS {
        match text.0.get(lang) {
            Some(s) if !s.trim().is_empty() => {}
            Some(_) => problems.push(format!("{what}: empty in {lang}")),
            None => problems.push(format!("{what}: missing {lang}")),
        }
    }
}

#[test]
fn declares_english_and_hinglish() {
    let deck = deck();
    assert_eq!(deck.languages, LANGS);
}

#[test]
fn has_the_promised_amount_of_content() {
    let deck = deck();
    assert!(deck.cards.len() >= 30, "{} cards", deck.cards.len());
    assert!(deck.prompts.len() >= 7, "{} prompts", deck.prompts.len());
    assert!(
        deck.sections.len() >= 14,
        "{} sections",
        deck.sections.len()
    );
    for prompt in &deck.prompts {
        assert!(
            deck.scene(&prompt.scene).is_some(),
            "prompt {} runs missing scene {}",
            prompt.id,
            prompt.scene
        );
    }
    // Sections are shared across languages; each needs a real title and body
    // in both, which `every_text_exists_in_both_languages` checks.
}

#[test]
fn uses_every_card_kind() {
    use flipcard::deck::CardKind;
    let deck = deck();
    for kind in [CardKind::Basic, CardKind::Reversed, CardKind::Typed] {
        assert!(
            deck.cards.iter().any(|c| c.kind == kind),
            "no {} card",
            kind.as_str()
        );
    }
    for card in deck.cards.iter().filter(|c| c.kind == CardKind::Typed) {
        assert!(
            !card.accept.is_empty(),
            "typed card {} accepts nothing",
            card.id
        );
    }
}

#[test]
fn every_text_exists_in_both_languages() {
    let deck = deck();
    let mut problems = Vec::new();
    assert_full(&deck.title, "deck title", &mut problems);
    for card in &deck.cards {
        assert_full(
            &card.front,
            &format!("card {} front", card.id),
            &mut problems,
        );
        assert_full(&card.back, &format!("card {} back", card.id), &mut problems);
    }
    for prompt in &deck.prompts {
        let id = &prompt.id;
        assert_full(
            &prompt.question,
            &format!("prompt {id} question"),
            &mut problems,
        );
        match &prompt.answer {
            Answer::Choice { choices, .. } => {
                for choice in choices {
                    let what = format!("prompt {id} choice {}", choice.id);
                    assert_full(&choice.label, &what, &mut problems);
                }
            }
            Answer::Number { formula, .. } => match formula {
                Some(f) => assert_full(f, &format!("prompt {id} formula"), &mut problems),
                None => problems.push(format!("prompt {id}: no formula")),
            },
            // A formula answer's key is one language-free formula.
            Answer::Formula(_) => {}
        }
    }
    for section in &deck.sections {
        let id = &section.id;
        assert_full(
            &section.title,
            &format!("section {id} title"),
            &mut problems,
        );
        assert_full(&section.body, &format!("section {id} body"), &mut problems);
    }
    assert!(problems.is_empty(), "{problems:#?}");
}

#[test]
fn every_card_opens_an_explanation() {
    let deck = deck();
    for card in &deck.cards {
        let section = card
            .explain
            .as_ref()
            .map(|e| e.section.as_str())
            .unwrap_or_else(|| panic!("card {} has no explanation", card.id));
        assert!(
            deck.section(section).is_some(),
            "card {} → {section}",
            card.id
        );
    }
}

// ---------------------------------------------------------------------------
// Closed-form physics of a scene, to check the authored answers against.
// ---------------------------------------------------------------------------

/// Index of the largest |ω| component: the axis the scene spins about.
fn dominant_axis(scene: &Scene) -> usize {
    (0..3)
        .max_by(|&a, &b| scene.omega[a].abs().total_cmp(&scene.omega[b].abs()))
        .unwrap_or(0)
}

/// k in ω̈ = k ω for a small disturbance of a spin about axis `a`:
/// k = (I_a − I_b)(I_c − I_a) / (I_b I_c) · Ω².
fn small_disturbance_k(scene: &Scene, a: usize) -> f64 {
    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
    let i = scene.inertia;
    let spin = scene.omega[a];
    (i[a] - i[b]) * (i[c] - i[a]) / (i[b] * i[c]) * spin * spin
}

/// Body precession rate (I_s − I⊥)/I⊥ · ω_s of a symmetric top, where s is
/// the axis whose moment differs from the two equal ones; positive when the
/// transverse ω turns from axis s+1 towards axis s+2.
fn body_precession_rate(scene: &Scene) -> f64 {
    let i = scene.inertia;
    let s = (0..3)
        .find(|&s| i[(s + 1) % 3] == i[(s + 2) % 3])
        .unwrap_or_else(|| panic!("scene {} is not a symmetric top", scene.id));
    let perp = i[(s + 1) % 3];
    (i[s] - perp) / perp * scene.omega[s]
}

/// Complete elliptic integral of the first kind K(m) by the
/// arithmetic–geometric mean: K = π / (2 AGM(1, √(1 − m))).
fn elliptic_k(m: f64) -> f64 {
    let (mut a, mut g) = (1.0_f64, (1.0 - m).sqrt());
    for _ in 0..60 {
        let (next_a, next_g) = ((a + g) / 2.0, (a * g).sqrt());
        a = next_a;
        g = next_g;
    }
    PI / (2.0 * a)
}

/// Time between sign changes of ω along the middle axis: half the period of
/// the Jacobi elliptic solution, 2K(m)/λ (axes sorted so I₁ < I₂ < I₃).
fn flip_period(scene: &Scene) -> f64 {
    let mut axes = [0, 1, 2];
    axes.sort_by(|&a, &b| scene.inertia[a].total_cmp(&scene.inertia[b]));
    let i = axes.map(|a| scene.inertia[a]);
    let w = axes.map(|a| scene.omega[a]);
    let two_t: f64 = (0..3).map(|n| i[n] * w[n] * w[n]).sum();
    let l2: f64 = (0..3).map(|n| (i[n] * w[n]).powi(2)).sum();
    let (lambda2, m) = if l2 > two_t * i[1] {
        (
            (i[2] - i[1]) * (l2 - two_t * i[0]) / (i[0] * i[1] * i[2]),
            (i[1] - i[0]) * (two_t * i[2] - l2) / ((i[2] - i[1]) * (l2 - two_t * i[0])),
        )
    } else {
        (
            (i[1] - i[0]) * (two_t * i[2] - l2) / (i[0] * i[1] * i[2]),
            (i[2] - i[1]) * (l2 - two_t * i[0]) / ((i[1] - i[0]) * (two_t * i[2] - l2)),
        )
    };
    2.0 * elliptic_k(m) / lambda2.sqrt()
}

/// What the closed form says a measure comes out as for a scene, where it
/// says anything simple.
fn predicted(scene: &Scene, measure: Measure) -> Option<f64> {
    let axis = dominant_axis(scene);
    let k = small_disturbance_k(scene, axis);
    let equal = scene.inertia.iter().all(|&i| i == scene.inertia[0]);
    match measure {
        Measure::EfoldTime => Some(1.0 / k.sqrt()),
        Measure::GrowthRate => Some(k.sqrt()),
        Measure::OscillationFreq => Some((-k).sqrt()),
        Measure::PrecessionRate => Some(body_precession_rate(scene)),
        Measure::PrecessionPeriod => Some(2.0 * PI / body_precession_rate(scene).abs()),
        Measure::FlipPeriod => Some(flip_period(scene)),
        Measure::OmegaChange => Some(if equal { 0.0 } else { f64::NAN }),
        Measure::Flips => {
            if k <= 0.0 {
                return Some(0.0);
            }
            // Unstable: the first flip comes once the nudge ε has grown to
            // the spin Ω, after about ln(Ω/ε)/√k; count it only if the run
            // lasts comfortably longer than that.
            let spin = scene.omega[axis].abs();
            let nudge = (0..3)
                .filter(|&n| n != axis)
                .map(|n| scene.omega[n].abs())
                .fold(0.0, f64::max);
            let first_flip = (spin / nudge).ln() / k.sqrt();
            Some(if scene.duration > 2.0 * first_flip {
                1.0
            } else {
                f64::NAN
            })
        }
        // Drift has no closed form; system measures belong to system scenes.
        Measure::EnergyDrift | Measure::MomentumDrift | Measure::Of(..) => None,
    }
}

#[test]
fn number_answers_follow_from_their_scenes() {
    let deck = deck();
    let mut checked = 0;
    for prompt in &deck.prompts {
        // A varied prompt's answer is each variant's run's (`varied_prompts`).
        let Answer::Number {
            measure,
            expected: Some(expected),
            ..
        } = &prompt.answer
        else {
            continue;
        };
        let scene = deck.scene(&prompt.scene).expect("scene exists");
        let value = predicted(scene, *measure)
            .unwrap_or_else(|| panic!("prompt {}: no closed form for {measure:?}", prompt.id));
        assert!(
            (expected - value).abs() <= 1e-3 * value.abs(),
            "prompt {}: authored {expected}, closed form gives {value}",
            prompt.id
        );
        checked += 1;
    }
    assert!(checked >= 4, "only {checked} number prompts");
}

#[test]
fn choice_answers_follow_from_their_scenes() {
    let deck = deck();
    let mut checked = 0;
    for prompt in &deck.prompts {
        let Answer::Choice {
            choices,
            expected: Some(expected),
        } = &prompt.answer
        else {
            continue;
        };
        let scene = deck.scene(&prompt.scene).expect("scene exists");
        let mut right = Vec::new();
        for choice in choices {
            let value = predicted(scene, choice.when.measure()).unwrap_or_else(|| {
                panic!("prompt {}: no closed form for {:?}", prompt.id, choice.when)
            });
            assert!(
                value.is_finite(),
                "prompt {}: the closed form cannot decide {:?}",
                prompt.id,
                choice.when
            );
            if choice.when.holds(value) {
                right.push(choice.id.as_str());
            }
        }
        assert_eq!(
            right,
            [expected.as_str()],
            "prompt {}: exactly the expected choice must hold",
            prompt.id
        );
        checked += 1;
    }
    assert!(checked >= 3, "only {checked} choice prompts");
}

#[test]
fn the_earth_scene_is_in_days_and_covers_two_wobbles() {
    let deck = deck();
    let earth = deck
        .prompts
        .iter()
        .find(|p| {
            matches!(
                p.answer,
                Answer::Number {
                    measure: Measure::PrecessionPeriod,
                    ..
                }
            )
        })
        .and_then(|p| deck.scene(&p.scene))
        .expect("a prompt asks for Earth's free precession period");
    assert_eq!(earth.time_unit, "d");
    let period = 2.0 * PI / body_precession_rate(earth).abs();
    assert!(
        (period - 305.0).abs() < 1.0,
        "rigid-Earth period {period} d"
    );
    assert!(earth.duration >= 2.0 * period, "run {} d", earth.duration);
}

/// The seed's two derivations (issue 24 §5): Euler's equations from the
/// transport theorem and the stability criterion, every text in both
/// languages, at least one formula and one choice ask among them, every
/// ask's own answer graded right as the review screen grades it, and the
/// criterion's k the same formula as the deck's growth-rate prompt (spin
/// about axis 2) with the axes 1 and 2 exchanged.
#[test]
fn the_derivations_are_sound_and_agree_with_the_prompts() {
    use flipcard::deck::AskKind;
    use flipcard::study::derive::{StepAnswer, StepVerdict, check};
    let d = deck();
    let ids: Vec<&str> = d.derivations.iter().map(|x| x.id.as_str()).collect();
    assert_eq!(ids, ["derive-euler-equations", "derive-stability"]);
    let mut problems = Vec::new();
    let (mut formulas, mut choices) = (0, 0);
    for x in &d.derivations {
        assert_full(&x.title, &x.id, &mut problems);
        for (i, s) in x.steps.iter().enumerate() {
            let what = format!("{} step {}", x.id, i + 1);
            assert_full(&s.math, &what, &mut problems);
            assert_full(&s.why, &what, &mut problems);
            let Some(ask) = &s.ask else { continue };
            let right = match &ask.kind {
                AskKind::Reveal => continue,
                AskKind::Choice { answer, choices: c } => {
                    choices += 1;
                    for choice in c {
                        assert_full(&choice.label, &what, &mut problems);
                    }
                    check(Some(ask), &StepAnswer::Chose(answer))
                }
                AskKind::Formula(key) => {
                    formulas += 1;
                    check(Some(ask), &StepAnswer::Typed(&key.expected))
                }
            };
            assert_eq!(right, StepVerdict::Right, "{what}");
        }
    }
    assert!(problems.is_empty(), "{problems:#?}");
    assert!(
        formulas >= 1 && choices >= 1,
        "{formulas} formula, {choices} choice asks"
    );

    // k about axis 1 is the prompt's k about axis 2 with 1 and 2 exchanged.
    let prompt = d
        .prompt("middle-axis-growth-formula")
        .expect("the growth-rate formula prompt");
    let Answer::Formula(about_2) = &prompt.answer else {
        panic!("a formula prompt")
    };
    // The moments' indices exchanged (not the power of Omega).
    let swapped = about_2
        .expected
        .replace("I_1", "I_#")
        .replace("I_2", "I_1")
        .replace("I_#", "I_2");
    assert_ne!(swapped, about_2.expected);
    let k = d
        .derivation("derive-stability")
        .expect("the stability derivation")
        .steps
        .iter()
        .filter_map(|s| s.ask.as_ref())
        .find(|a| matches!(a.kind, AskKind::Formula(_)))
        .expect("the stability derivation asks for k");
    assert_eq!(
        check(Some(k), &StepAnswer::Typed(&swapped)),
        StepVerdict::Right,
        "{swapped}"
    );
    // The sign matters: the other order of one factor is wrong.
    assert!(
        check(
            Some(k),
            &StepAnswer::Typed("(I_1 - I_3)(I_1 - I_2) Omega^2 / (I_2 I_3)")
        )
        .is_wrong()
    );
}
