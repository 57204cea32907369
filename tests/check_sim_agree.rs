//! `flipcard check` and the simulator judge a scene by the same test: over
//! moments and spins from 1e-320 to 1e308, every scene `check` accepts
//! runs to its end with finite output (through the scene runner and
//! through the same path `flipcard sim` takes), and every scene it refuses
//! the simulator refuses too.

use flipcard::deck::diag::Severity;
use flipcard::deck::{Panel, Scene, load_dir};
use flipcard::sim::scene::{SceneRun, measure_scene};
use flipcard::sim::solvers::registry::{Kind, method};
use flipcard::sim::{Body, Method, Needs, make};
use nalgebra::Vector3;

const SHAPES: [[f64; 3]; 4] = [
    [1.0, 2.0, 3.0],
    [1.0, 1.5, 2.0],
    [1e-9, 1.0, 1.0],
    [2.0, 2.0, 3.0],
];
const DIRECTIONS: [[f64; 3]; 2] = [[0.01, 1.0, 0.01], [1.0, 1.0, 0.5]];
const INERTIA_SCALES: [f64; 11] = [
    1e-320, 1e-308, 1e-300, 1e-200, 1e-100, 1e-10, 1.0, 1e10, 1e100, 1e300, 1e308,
];
const OMEGA_SCALES: [f64; 13] = [
    5e-324, 1e-320, 1e-300, 1e-160, 1e-150, 1e-100, 1e-10, 1.0, 1e3, 1e100, 1e150, 1e154, 1e300,
];
const DURATIONS: [f64; 2] = [1.0, 1e3];

struct Case {
    inertia: [f64; 3],
    omega: [f64; 3],
    duration: f64,
    show: Vec<Panel>,
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (n, &si) in INERTIA_SCALES.iter().enumerate() {
        for shape in SHAPES {
            for &sw in &OMEGA_SCALES {
                for direction in DIRECTIONS {
                    for duration in DURATIONS {
                        let inertia = shape.map(|v| v * si);
                        let omega = direction.map(|v| v * sw);
                        if inertia.iter().chain(&omega).any(|v| !v.is_finite()) {
                            continue;
                        }
                        // Half the cases draw the body, so the spin counts.
                        let show = if n % 2 == 0 {
                            vec![Panel::Omega]
                        } else {
                            vec![Panel::Omega, Panel::Body]
                        };
                        out.push(Case {
                            inertia,
                            omega,
                            duration,
                            show,
                        });
                    }
                }
            }
        }
    }
    out
}

/// One deck holding every case as a scene; returns the first line of each
/// scene and whether `check` reported an error inside it.
fn check(cases: &[Case]) -> Vec<bool> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("content/extreme")).unwrap();
    std::fs::create_dir(dir.path().join("decks")).unwrap();
    std::fs::write(dir.path().join("content/extreme/en.toml"), "").unwrap();
    let mut text =
        String::from("[deck]\nid = \"extreme\"\ntitle = 'Extreme'\nlanguages = [\"en\"]\n");
    let mut starts = Vec::new();
    for (k, c) in cases.iter().enumerate() {
        starts.push(text.lines().count() + 2);
        let triple = |v: [f64; 3]| format!("[{:e}, {:e}, {:e}]", v[0], v[1], v[2]);
        let show: Vec<String> = c.show.iter().map(|p| format!("\"{}\"", p.name())).collect();
        text.push_str(&format!(
            "\n[[scene]]\nid = \"s{k}\"\ninertia = {}\nomega = {}\nduration = {:e}\nshow = [{}]\n",
            triple(c.inertia),
            triple(c.omega),
            c.duration,
            show.join(", ")
        ));
    }
    let path = dir.path().join("decks/extreme.toml");
    std::fs::write(&path, &text).unwrap();
    let loaded = load_dir(&path);
    let total = text.lines().count() + 1;
    (0..cases.len())
        .map(|k| {
            let (from, to) = (starts[k], starts.get(k + 1).copied().unwrap_or(total));
            !loaded
                .diagnostics
                .iter()
                .any(|d| d.severity == Severity::Error && d.line >= from && d.line < to)
        })
        .collect()
}

/// Whether the simulator runs the case to its end, every number finite.
fn simulate(c: &Case) -> Result<(), String> {
    let scene = Scene {
        id: "s".into(),
        title: None,
        inertia: c.inertia,
        omega: c.omega,
        duration: c.duration,
        show: c.show.clone(),
        time_unit: "s".into(),
    };
    let m = measure_scene(&scene, Method::Exact).map_err(|e| e.to_string())?;
    if m.readings().iter().any(|r| !r.value.is_finite()) {
        return Err(format!("non-finite measurement: {m:?}"));
    }
    let mut run = SceneRun::new(&scene, Method::Exact).map_err(|e| e.to_string())?;
    run.advance_to(c.duration);
    if let Some(e) = run.error() {
        return Err(e.to_string());
    }
    // As `flipcard sim --inertia … --omega … --t-end duration` runs it.
    let body = Body::new(c.inertia).map_err(|e| e.to_string())?;
    let w0 = Vector3::from(c.omega);
    let exact = method(Kind::Exact, None, None, &body, &w0).map_err(|e| e.to_string())?;
    let mut solver =
        make(exact, body, w0, Needs { orientation: true }).map_err(|e| e.to_string())?;
    solver.plan(c.duration).map_err(|e| e.to_string())?;
    for k in 0..=8 {
        let t = c.duration * k as f64 / 8.0;
        let s = solver.advance(t).map_err(|e| e.to_string())?;
        let numbers = [body.energy(&s.omega), body.l2(&s.omega)];
        let all = s.omega.iter().chain(s.q.coords.iter()).chain(&numbers);
        if !all.clone().all(|v| v.is_finite()) {
            return Err(format!("non-finite state at t = {t}: {s:?}"));
        }
    }
    Ok(())
}

#[test]
fn check_accepts_exactly_the_scenes_the_simulator_runs() {
    let cases = cases();
    assert!(cases.len() > 1000, "{}", cases.len());
    let verdicts = check(&cases);
    let (mut accepted, mut refused) = (0, 0);
    let mut disagreements = Vec::new();
    for (c, &ok) in cases.iter().zip(&verdicts) {
        let ran = simulate(c);
        match (ok, &ran) {
            (true, Ok(())) => accepted += 1,
            (false, Err(_)) => refused += 1,
            _ => disagreements.push(format!(
                "I = {:?}, ω = {:?}, {} s, show {:?}: check {}, simulator {:?}",
                c.inertia,
                c.omega,
                c.duration,
                c.show,
                if ok { "accepts" } else { "refuses" },
                ran
            )),
        }
    }
    assert!(
        disagreements.is_empty(),
        "{} of {} cases:\n{}",
        disagreements.len(),
        cases.len(),
        disagreements.join("\n")
    );
    // Both sides of the boundary are exercised.
    assert!(accepted > 100 && refused > 100, "{accepted} {refused}");
}

/// What `check` accepts of a prompt's answer, the learner's verdict gives
/// too, and keeps giving for a longer run of the same scene: over run
/// lengths around the flips of a middle-axis spin (flips at 1.09 s, then
/// every 1.96 s) and about a stable axis, and every count condition.
#[test]
fn an_answer_check_accepts_stays_right_in_a_longer_run() {
    use flipcard::deck::{Answer, Choice, Cmp, Condition, Measure, Prompt, Text};
    use flipcard::predict::audit::audit;
    use flipcard::predict::{Prediction, verdict};

    let text = |s: &str| Text([("en".to_string(), s.to_string())].into());
    let conditions: Vec<(Cmp, f64)> = [Cmp::Eq, Cmp::Ne, Cmp::Lt, Cmp::Le, Cmp::Gt, Cmp::Ge]
        .into_iter()
        .flat_map(|op| [0.0, 1.0, 2.0, 3.0].map(|v| (op, v)))
        .collect();
    let (mut accepted, mut refused) = (0, 0);
    for omega in [[0.1, 10.0, 0.1], [0.1, 0.1, 10.0]] {
        for duration in [0.5, 1.0, 1.5, 2.5, 3.0, 3.5, 5.0, 6.0, 9.0] {
            let scene = |d: f64| Scene {
                id: "s".into(),
                title: None,
                inertia: [1.0, 2.0, 3.0],
                omega,
                duration: d,
                show: vec![Panel::Omega],
                time_unit: "s".into(),
            };
            let short = measure_scene(&scene(duration), Method::Exact).unwrap();
            let long = measure_scene(&scene(duration * 4.0), Method::Exact).unwrap();
            for &(op, value) in &conditions {
                // The condition, and its complement as the other choice.
                let when = Condition::compare(Measure::Flips, op, value);
                let other = Condition::compare(
                    Measure::Flips,
                    match op {
                        Cmp::Eq => Cmp::Ne,
                        Cmp::Ne => Cmp::Eq,
                        Cmp::Lt => Cmp::Ge,
                        Cmp::Le => Cmp::Gt,
                        Cmp::Gt => Cmp::Le,
                        Cmp::Ge => Cmp::Lt,
                    },
                    value,
                );
                let prompt = Prompt {
                    id: "p".into(),
                    question: text("?"),
                    scene: "s".into(),
                    explain: None,
                    tags: vec![],
                    answer: Answer::Choice {
                        expected: Some("a".into()),
                        choices: vec![
                            Choice {
                                misconception: None,
                                id: "a".into(),
                                label: text("a"),
                                when,
                            },
                            Choice {
                                misconception: None,
                                id: "b".into(),
                                label: text("b"),
                                when: other,
                            },
                        ],
                    },
                    measured: None,
                    vary: Vec::new(),
                };
                let expected = Prediction::Choice(0);
                if audit(&prompt, &scene(duration), &short).is_none() {
                    accepted += 1;
                    let now = verdict(&prompt, &short, expected);
                    let later = verdict(&prompt, &long, expected);
                    assert!(
                        now.correct && later.correct,
                        "ω₀ = {omega:?}, {duration} s, flips {} {value}: accepted, \
                         but right now: {}, in a 4× run: {} ({:?} flips)",
                        op.as_str(),
                        now.correct,
                        later.correct,
                        long.get(Measure::Flips)
                    );
                } else {
                    refused += 1;
                }
            }
        }
    }
    assert!(accepted > 50 && refused > 50, "{accepted} {refused}");
}
