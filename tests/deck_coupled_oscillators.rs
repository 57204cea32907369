//! The bundled deck `coupled-oscillators`: it has the promised content in
//! both languages, `flipcard check` passes it clean, every prompt's answer
//! and every number its texts state is measured through the real binary
//! (`flipcard sim --scene ID --deck decks/coupled-oscillators.toml
//! --measure M`), the closed forms it teaches (the two normal-mode
//! frequencies, the beat 2π/(ω₂ − ω₁), the detuned transfer
//! κ/√(κ² + δ²)) agree with the simulator, and every prompt marked
//! `# vary:` stays decidable over its whole range.

use std::collections::BTreeSet;
use std::f64::consts::PI;

use crate::support::deck::{
    BundledDeck, LANGS, Verdict, array, assert_checks_clean, find, measure_in, run_prompt,
    run_varied, varied,
};

const DECK: BundledDeck = BundledDeck {
    id: "coupled-oscillators",
};
const G: f64 = 9.81;

fn close(what: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{what}: measured {got}, the deck says {want} (rel {rel})"
    );
}

/// ω₁ and ω₂ of two 1 m pendulums of 1 kg with a spring `k`.
fn modes(k: f64) -> (f64, f64) {
    (G.sqrt(), (G + 2.0 * k).sqrt())
}

/// The beats scene with spring `k`, `duration` long: the deck file.
fn beats_with(dir: &std::path::Path, k: f64, duration: f64) -> std::path::PathBuf {
    DECK.edited(dir, "beats", &[("k", k), ("duration", duration)])
}

#[test]
fn has_the_promised_content_in_both_languages() {
    let deck = DECK.deck();
    let languages: Vec<&str> = deck["deck"]["languages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(languages, LANGS);
    let cards = array(&deck, "card");
    assert!(cards.len() >= 25, "{} cards", cards.len());
    let kinds: BTreeSet<&str> = cards
        .iter()
        .map(|c| c.get("kind").and_then(|v| v.as_str()).unwrap_or("basic"))
        .collect();
    for kind in ["basic", "reversed", "cloze", "formula", "typed"] {
        assert!(kinds.contains(kind), "no {kind} card");
    }
    assert_eq!(array(&deck, "prompt").len(), 8);
    assert!(varied(&DECK.source()).len() >= 4, "half the prompts varied");
    assert!(!array(&deck, "misconception").is_empty());
    let ids: Vec<Vec<String>> = LANGS
        .iter()
        .map(|lang| {
            array(&DECK.sections(lang), "section")
                .iter()
                .map(|s| s["id"].as_str().unwrap().to_string())
                .collect()
        })
        .collect();
    assert!(ids[0].len() >= 8, "{} sections", ids[0].len());
    assert_eq!(ids[0], ids[1], "the same sections in the same order");
    assert!(
        array(&deck, "scene")
            .iter()
            .any(|s| s.contains_key("knobs") && s.contains_key("explore"))
    );
}

#[test]
fn check_passes_it_without_a_warning() {
    assert_checks_clean(&DECK);
}

#[test]
fn every_prompt_answer_is_what_the_simulator_measures() {
    let deck = DECK.deck();
    let mut measured = 0;
    for p in array(&deck, "prompt") {
        // A varied prompt's answer is each variant's run's: `check` runs
        // its variants, and `varied_prompts_stay_decidable_over_their_range`
        // holds them to the closed forms.
        if p.contains_key("vary") {
            continue;
        }
        let answer = p["answer"].as_table().unwrap();
        if answer["kind"].as_str() == Some("formula") {
            continue;
        }
        measured += 1;
        match run_prompt(&DECK.path(), p) {
            Verdict::Number(got) => {
                let want = answer["expected"].as_float().unwrap();
                let rel = answer["tolerance"]["rel"].as_float().unwrap();
                close(p["id"].as_str().unwrap(), got, want, rel);
            }
            Verdict::Choices(holding) => {
                assert_eq!(
                    holding,
                    [answer["expected"].as_str().unwrap()],
                    "{}",
                    p["id"]
                );
            }
        }
    }
    // Seven run-decided prompts, four of them varied.
    assert_eq!(measured, 3);
}

/// The numbers the cards and sections state, each measured (or computed
/// from what was measured) and found written in both languages.
#[test]
fn every_number_the_texts_state_is_measured() {
    let t1 = DECK.measure_one("in-phase", "period(x1)");
    let v = DECK.measure(
        "out-of-phase",
        &["period(x1)", "min(e1)", "max(e1)", "final(E)"],
    );
    let t2 = v[0];
    close("in-phase period", t1, 2.006, 1e-3);
    close("out-of-phase period", t2, 1.911, 1e-3);
    let (w1, w2) = (2.0 * PI / t1, 2.0 * PI / t2);
    close("ω1", w1, 3.132, 1e-3);
    close("ω2", w2, 3.288, 1e-3);
    close("ω2 − ω1", w2 - w1, 0.1558, 1e-3);
    close("each pendulum's share", v[1], 0.05405, 1e-4);
    close("each pendulum's share", v[2], 0.05405, 1e-4);
    close("total", v[3], 0.1081, 1e-3);
    for (kind, id) in [
        ("card", "in-phase-mode"),
        ("card", "mistake-spring-slows-all"),
        ("section", "normal-modes"),
        ("section", "example-numbers"),
    ] {
        DECK.assert_quoted(kind, id, "2.006");
    }
    for t in ["3.288", "1.911"] {
        DECK.assert_quoted("card", "out-of-phase-mode", t);
        DECK.assert_quoted("section", "normal-modes", t);
        DECK.assert_quoted("section", "example-numbers", t);
    }
    DECK.assert_quoted("section", "normal-modes", "3.132");
    DECK.assert_quoted("section", "example-numbers", "0.1558");
    for t in ["0.05405", "0.1081"] {
        DECK.assert_quoted("card", "mode-start-no-beats", t);
        DECK.assert_quoted("section", "normal-modes", t);
    }

    // Beats: over in half the round trip, back in the round trip; all of
    // it gets across (pendulum 2 out to 0.1 m).
    let v = DECK.measure("beats", &["beat(x1)", "beat(e1)", "max(x2)", "min(e1)"]);
    close("round trip", v[0], 40.34, 1e-3);
    close("round trip of the energy", v[1], 40.34, 1e-3);
    close("over", v[0] / 2.0, 20.17, 1e-3);
    close("pendulum 2's swing", v[2], 0.1, 1e-3);
    assert!(v[3] < 1e-3 * 0.04905, "pendulum 1 all but still: {}", v[3]);
    for (kind, id) in [
        ("card", "transfer-time"),
        ("section", "beats"),
        ("section", "example-numbers"),
    ] {
        DECK.assert_quoted(kind, id, "20.17");
        DECK.assert_quoted(kind, id, "40.34");
    }
    DECK.assert_quoted("card", "round-trip-typed", "40.34");
    // Weak coupling: π m ω1 / k ≈ 19.7 s; k = 0.25 gives 79.7 s and still
    // the full 0.1 m.
    close("π m ω1/k", PI * w1 / 0.5, 19.7, 2e-3);
    let v = DECK.measure("weak-spring", &["beat(x1)", "max(x2)"]);
    close("round trip at k = 0.25", v[0], 79.7, 1e-3);
    close("pendulum 2's swing at k = 0.25", v[1], 0.1, 1e-3);
    for (kind, id) in [("card", "weak-coupling-approx"), ("section", "beats")] {
        DECK.assert_quoted(kind, id, "19.7");
    }
    DECK.assert_quoted("card", "weak-still-complete", "79.7");
    DECK.assert_quoted("section", "beats", "79.7");

    // The knob's ends, as the worked example quotes them.
    for (k, want) in [(0.3, 66.6), (2.0, 10.8)] {
        let dir = tempfile::tempdir().unwrap();
        let got = measure_in(&beats_with(dir.path(), k, 160.0), "beats", &["beat(x1)"])[0];
        close(&format!("round trip at k = {k}"), got, want, 5e-3);
    }
    DECK.assert_quoted("section", "example-numbers", "66.6");
    DECK.assert_quoted("section", "example-numbers", "10.8");

    // Detuned to 0.8 m: 0.038 m, at most 18% of the energy, beats every
    // 16.1 s.
    let v = DECK.measure("detuned", &["max(x2)", "max(share2)", "beat(x1)"]);
    close("pendulum 2's swing", v[0], 0.038, 0.01);
    close("pendulum 2's share", v[1], 0.18, 0.02);
    close("detuned beat", v[2], 16.1, 1e-3);
    let (kappa, delta) = (0.5, 0.5 * (G / 0.8 - G));
    close("δ", delta, 1.226, 1e-3);
    close(
        "κ/√(κ² + δ²)",
        kappa / (kappa * kappa + delta * delta).sqrt(),
        0.3776,
        1e-4,
    );
    close("share of the swing", v[0] / 0.1, 0.3776, 1e-3);
    for (kind, id) in [("card", "detuned-fraction"), ("section", "detuning")] {
        for t in ["0.038", "1.226", "0.3776", "18%"] {
            DECK.assert_quoted(kind, id, t);
        }
    }
    DECK.assert_quoted("card", "mistake-detuned-complete", "0.038");
    DECK.assert_quoted("card", "detuned-faster", "16.1");
    DECK.assert_quoted("section", "detuning", "16.1");
}

/// ω₁ = √(g/L) whatever the spring, ω₂ = √(g/L + 2k/m), and the beat
/// 2π/(ω₂ − ω₁), over a range of springs.
#[test]
fn normal_modes_and_beats_follow_the_closed_forms() {
    // Within the beats scene's knob, 0.3 to 2 N/m.
    for k in [0.3, 0.5, 1.0, 2.0] {
        let (w1, w2) = modes(k);
        for (scene, w) in [("in-phase", w1), ("out-of-phase", w2)] {
            let dir = tempfile::tempdir().unwrap();
            let path = DECK.edited(dir.path(), scene, &[("k", k)]);
            let t = measure_in(&path, scene, &["period(x1)"])[0];
            close(&format!("{scene} at k = {k}"), t, 2.0 * PI / w, 1e-6);
        }
        let dir = tempfile::tempdir().unwrap();
        let beat = measure_in(&beats_with(dir.path(), k, 160.0), "beats", &["beat(x1)"])[0];
        close(
            &format!("beat at k = {k}"),
            beat,
            2.0 * PI / (w2 - w1),
            1e-5,
        );
    }
}

/// The largest swing of a detuned pendulum 2 follows κ/√(κ² + δ²) and is
/// complete only when tuned.
#[test]
fn detuning_makes_the_transfer_incomplete() {
    for l2 in [0.6, 0.8, 0.9, 1.0, 1.2] {
        let dir = tempfile::tempdir().unwrap();
        let path = DECK.edited(dir.path(), "detuned", &[("L2", l2)]);
        let got = measure_in(&path, "detuned", &["max(x2)"])[0];
        let delta: f64 = 0.5 * (G / l2 - G);
        let want = 0.1 * 0.5 / (0.25 + delta * delta).sqrt();
        close(&format!("largest swing at L2 = {l2}"), got, want, 5e-3);
    }
}

#[test]
fn the_total_energy_is_conserved() {
    for scene in [
        "in-phase",
        "out-of-phase",
        "beats",
        "weak-spring",
        "detuned",
    ] {
        let drift = DECK.measure_one(scene, "drift(E)");
        assert!(drift < 1e-6, "{scene}: {drift}");
    }
}

/// Each prompt marked `# vary: name = [lo, hi]`, at both ends and the
/// middle: a choice decided as at the deck's own value, a number equal to
/// the closed form at that value.
#[test]
fn varied_prompts_stay_decidable_over_their_range() {
    let deck = DECK.deck();
    let runs = run_varied(&DECK);
    assert_eq!(runs.len(), 3 * 4);
    for (id, x, verdict) in runs {
        let p = find(&deck, "prompt", &id);
        match verdict {
            // The deck's answer when it states one; else exactly one
            // choice holds (the variant's run decides).
            Verdict::Choices(holding) => match p["answer"].get("expected") {
                Some(e) => assert_eq!(holding, [e.as_str().unwrap()], "{id} at {x}"),
                None => assert_eq!(holding.len(), 1, "{id} at {x}: {holding:?}"),
            },
            Verdict::Number(got) => {
                let want = match id.as_str() {
                    "in-phase-period" => 2.0 * PI / modes(x).0,
                    "out-of-phase-period" => 2.0 * PI / modes(x).1,
                    other => panic!("no closed form for {other}"),
                };
                close(&format!("{id} at {x}"), got, want, 1e-6);
            }
        }
    }
}
