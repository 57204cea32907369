//! Every prompt of the bundled decks, run through its scene: the author's
//! expected answer must be what the simulation gives. For a choice, the
//! expected choice is the one (and only one) whose condition holds on the
//! measurements; for a number, the measured value is within the prompt's
//! tolerance of the expected one. Each is checked with the exact solver and
//! again with the adaptive one, so a wrong answer cannot hide behind one
//! method.

use flipcard::cmd::paths::bundled_decks;
use flipcard::deck::{Answer, Deck, load_dir};
use flipcard::sim::Method;
use flipcard::sim::measure::{Prediction, verdict};
use flipcard::sim::scene::measure_scene;

fn decks() -> Vec<Deck> {
    let loaded = load_dir(&bundled_decks());
    assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
    assert!(!loaded.decks.is_empty());
    loaded.decks
}

fn check(method: Method) {
    let mut checked = 0;
    let mut problems = Vec::new();
    for deck in decks() {
        for prompt in &deck.prompts {
            let scene = deck
                .scene(&prompt.scene)
                .unwrap_or_else(|| panic!("{}: no scene {}", prompt.id, prompt.scene));
            let m = measure_scene(scene, method)
                .unwrap_or_else(|e| panic!("{}: scene {} does not run: {e}", prompt.id, scene.id));
            let expected = Prediction::expected(prompt)
                .unwrap_or_else(|| panic!("{}: expected names no choice", prompt.id));
            let v = verdict(prompt, &m, expected);
            match &prompt.answer {
                Answer::Choice { choices, expected } => {
                    let holding: Vec<&str> =
                        v.holding.iter().map(|&i| choices[i].id.as_str()).collect();
                    if holding != [expected.as_str()] {
                        problems.push(format!(
                            "{} ({}): expected {expected}, but {holding:?} hold on {:?}",
                            prompt.id,
                            scene.id,
                            m.values()
                        ));
                    }
                }
                Answer::Number {
                    measure, expected, ..
                } => {
                    if !v.correct {
                        problems.push(format!(
                            "{} ({}): expected {} = {expected}, measured {:?}",
                            prompt.id,
                            scene.id,
                            measure.name(),
                            m.get(*measure)
                        ));
                    }
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 9, "only {checked} prompts");
    assert!(problems.is_empty(), "{method:?}:\n{}", problems.join("\n"));
}

#[test]
fn every_expected_answer_is_what_the_exact_solution_gives() {
    check(Method::Exact);
}

#[test]
fn every_expected_answer_is_what_the_adaptive_solver_gives() {
    check(Method::Adaptive { tol: 1e-10 });
}

#[test]
fn a_wrong_prediction_is_judged_wrong() {
    for deck in decks() {
        for prompt in &deck.prompts {
            let scene = deck.scene(&prompt.scene).unwrap();
            let m = measure_scene(scene, Method::Exact).unwrap();
            let wrong = match &prompt.answer {
                Answer::Choice { choices, expected } => {
                    Prediction::Choice(choices.iter().position(|c| &c.id != expected).unwrap())
                }
                Answer::Number { expected, .. } => Prediction::Number(expected * 2.0 + 1.0),
            };
            assert!(!verdict(prompt, &m, wrong).correct, "{}", prompt.id);
        }
    }
}
