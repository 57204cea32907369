//! Every prompt of the bundled decks, run through its scene: the author's
//! expected answer must be what the simulation gives. For a choice, the
//! expected choice is the one (and only one) whose condition holds on the
//! measurements; for a number, the measured value is within the prompt's
//! tolerance of the expected one. Each is checked with the exact solver and
//! again with the adaptive one, so a wrong answer cannot hide behind one
//! method; a system scene (equations written in the deck, with no exact
//! solution) with `auto` and again with `radau`.

use flipcard::deck::Measure;
use flipcard::deck::{Answer, Deck, Prompt};
use flipcard::predict::{Prediction, verdict};
use flipcard::sim::Method;
use flipcard::sim::rigid::formula;
use flipcard::sim::scene::measure::Measurements;
use flipcard::sim::scene::measure_scene;
use flipcard::sim::scene::system::SystemRun;
use flipcard::sim::solvers::ode::{OdeKind, OdeMethod};

fn decks() -> Vec<Deck> {
    let loaded = flipcard::bundled::load();
    assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
    assert!(!loaded.decks.is_empty());
    loaded.decks
}

/// The measures a prompt's answer depends on.
fn prompt_measures(prompt: &Prompt) -> Vec<Measure> {
    let mut measures = match &prompt.answer {
        Answer::Choice { choices, .. } => choices.iter().flat_map(|c| c.when.measures()).collect(),
        Answer::Number { measure, .. } => vec![*measure],
        Answer::Formula(_) => Vec::new(),
    };
    measures.sort();
    measures.dedup();
    measures
}

/// The measurements of a prompt's scene: a rigid body with `rigid`, a
/// system with `system` at its default setting for the scene.
fn measure_prompt(deck: &Deck, prompt: &Prompt, rigid: Method, system: OdeKind) -> Measurements {
    if let Some(scene) = deck.scene(&prompt.scene) {
        return measure_scene(scene, rigid)
            .unwrap_or_else(|e| panic!("{}: scene {} does not run: {e}", prompt.id, scene.id));
    }
    let scene = deck
        .system(&prompt.scene)
        .unwrap_or_else(|| panic!("{}: no scene {}", prompt.id, prompt.scene));
    let measures = prompt_measures(prompt);
    let method = OdeMethod::default_for(system, scene.duration);
    let mut run = SystemRun::new(scene, method, &measures)
        .unwrap_or_else(|e| panic!("{}: scene {} does not compile: {e}", prompt.id, scene.id));
    run.run_to_end()
        .unwrap_or_else(|e| panic!("{}: scene {} does not run: {e}", prompt.id, scene.id));
    let m = run.measurements(&measures);
    for measure in measures {
        assert!(
            m.get(measure).is_some(),
            "{}: {measure} cannot be measured: {:?}",
            prompt.id,
            run.measure(measure)
        );
    }
    m
}

fn check(method: Method, system: OdeKind) {
    let mut checked = 0;
    let mut systems = 0;
    let mut problems = Vec::new();
    for deck in decks() {
        for prompt in &deck.prompts {
            // A varied prompt's answer is each variant's run's: `check`
            // runs its variants (`varied_prompts`).
            if !prompt.vary.is_empty() {
                continue;
            }
            // A formula prompt is no measurement: its key is right by
            // itself (`grade_cli` tests the slips).
            if let Answer::Formula(key) = &prompt.answer {
                let v = flipcard::sim::system::equiv::grade(key, &key.expected);
                assert!(v.is_right(), "{}: {v:?}", prompt.id);
                continue;
            }
            let m = measure_prompt(&deck, prompt, method, system);
            systems += usize::from(deck.system(&prompt.scene).is_some());
            let expected = Prediction::expected(prompt)
                .unwrap_or_else(|| panic!("{}: expected names no choice", prompt.id));
            let v = verdict(prompt, &m, expected);
            match &prompt.answer {
                Answer::Choice { choices, expected } => {
                    let expected = expected.as_deref().unwrap_or_default();
                    let holding: Vec<&str> =
                        v.holding.iter().map(|&i| choices[i].id.as_str()).collect();
                    if holding != [expected] {
                        problems.push(format!(
                            "{} ({}): expected {expected}, but {holding:?} hold on {:?}",
                            prompt.id,
                            prompt.scene,
                            m.values()
                        ));
                    }
                }
                Answer::Number {
                    measure, expected, ..
                } => {
                    if !v.correct {
                        problems.push(format!(
                            "{} ({}): expected {measure} = {expected:?}, measured {:?}",
                            prompt.id,
                            prompt.scene,
                            m.get(*measure)
                        ));
                    }
                }
                Answer::Formula(_) => {}
            }
            checked += 1;
        }
    }
    assert!(checked >= 9, "only {checked} prompts");
    assert!(systems >= 8, "only {systems} prompts on system scenes");
    assert!(
        problems.is_empty(),
        "{method:?}, {system:?}:\n{}",
        problems.join("\n")
    );
}

#[test]
fn every_expected_answer_is_what_the_exact_solution_gives() {
    check(Method::Exact, OdeKind::Auto);
}

#[test]
fn every_expected_answer_is_what_the_adaptive_solver_gives() {
    check(Method::Adaptive { tol: 1e-10 }, OdeKind::Radau);
}

#[test]
fn a_wrong_prediction_is_judged_wrong() {
    for deck in decks() {
        for prompt in &deck.prompts {
            // A varied prompt's answer is each variant's run's.
            if !prompt.vary.is_empty() {
                continue;
            }
            if let Answer::Formula(key) = &prompt.answer {
                let negated = format!("-({})", key.expected);
                let v = flipcard::sim::system::equiv::grade(key, &negated);
                assert!(!v.is_right(), "{}", prompt.id);
                continue;
            }
            let m = measure_prompt(&deck, prompt, Method::Exact, OdeKind::Auto);
            let wrong = match &prompt.answer {
                Answer::Choice { choices, expected } => Prediction::Choice(
                    choices
                        .iter()
                        .position(|c| Some(&c.id) != expected.as_ref())
                        .unwrap(),
                ),
                Answer::Number { expected, .. } => {
                    Prediction::Number(expected.unwrap_or(1.0) * 2.0 + 1.0)
                }
                Answer::Formula(_) => continue,
            };
            assert!(!verdict(prompt, &m, wrong).correct, "{}", prompt.id);
        }
    }
}

/// A scene spun fast about its middle axis (ω = 1000 rad/s, I = (1, 2, 3):
/// nutation λ ≈ 577 rad/s, a flip every 0.0275 s). `check` accepts it only
/// for durations its measurements resolve, and every duration it accepts
/// measures the flips, their period and the early growth in agreement with
/// the closed forms; longer ones are refused at the duration, with the limit.
#[test]
fn fast_scenes_that_pass_check_measure_what_the_formulas_say() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("content/fast")).unwrap();
    std::fs::create_dir(dir.path().join("decks")).unwrap();
    std::fs::write(dir.path().join("content/fast/en.toml"), "").unwrap();
    let mut accepted = Vec::new();
    for duration in ["1.0", "10.0", "100.0", "113.0", "114.0", "1e3", "1e6"] {
        let path = dir.path().join("decks/fast.toml");
        std::fs::write(
            &path,
            format!(
                "[deck]\nid = \"fast\"\ntitle = 'Fast'\nlanguages = [\"en\"]\n\n\
                 [[scene]]\nid = \"spin\"\ninertia = [1.0, 2.0, 3.0]\n\
                 omega = [0.01, 1000.0, 0.01]\nduration = {duration}\nshow = [\"omega\"]\n"
            ),
        )
        .unwrap();
        let loaded = flipcard::deck::load_dir(&path);
        if loaded.errors() > 0 {
            let text = loaded.render_all();
            assert!(
                text.contains("fast.toml:10:12: error: duration")
                    && text.contains("covers 113.5 time units"),
                "{duration}: {text}"
            );
            continue;
        }
        accepted.push(duration);
        let scene = loaded.decks[0].scene("spin").unwrap();
        let m = measure_scene(scene, Method::Exact).unwrap();
        let body = flipcard::sim::Body::new(scene.inertia).unwrap();
        let w0 = nalgebra::Vector3::from(scene.omega);
        let interval = formula::flip_interval(&body, &w0, 1).unwrap();
        let period = m.get(Measure::FlipPeriod).unwrap();
        assert!(
            (period - interval).abs() < 1e-6 * interval,
            "{duration}: flip period {period} vs 2K(m)/λ = {interval}"
        );
        let flips = m.get(Measure::Flips).unwrap();
        let expected = scene.duration / interval;
        assert!(
            (flips - expected).abs() <= 1.0,
            "{duration}: {flips} flips, {expected} flip intervals"
        );
        let growth = m.get(Measure::GrowthRate).unwrap();
        let root_k = formula::stability(&body, 1, 1000.0).sqrt();
        assert!(
            (growth - root_k).abs() < 0.02 * root_k,
            "{duration}: growth {growth} vs √k = {root_k}"
        );
    }
    assert_eq!(accepted, ["1.0", "10.0", "100.0", "113.0"]);
}
