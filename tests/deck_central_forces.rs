//! The bundled deck `central-forces`: it has the promised content in both
//! languages, `flipcard check` passes it clean, every prompt's answer and
//! every number its texts state is measured through the real binary
//! (`flipcard sim --scene ID --deck decks/central-forces.toml --measure M`),
//! the closed forms it teaches (Kepler's third law, the turning points of
//! the effective potential, the escape speed, the apsidal precession under
//! a 1/r³ correction) agree with the simulator, and every prompt marked
//! `# vary:` stays decidable over its whole range.

use std::collections::BTreeSet;
use std::f64::consts::PI;

use crate::support::deck::{
    BundledDeck, LANGS, Verdict, array, assert_checks_clean, find, run_prompt, run_varied, varied,
};

const DECK: BundledDeck = BundledDeck {
    id: "central-forces",
};
/// GM of the Sun in AU³/yr².
const GM: f64 = 4.0 * PI * PI;
/// 1 AU/yr in km/s (IAU astronomical unit, Julian year).
const AU_PER_YR_KMS: f64 = 149_597_870.7 / (365.25 * 86_400.0);

fn close(what: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{what}: measured {got}, the deck says {want} (rel {rel})"
    );
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
    for kind in ["basic", "reversed", "cloze", "formula"] {
        assert!(kinds.contains(kind), "no {kind} card");
    }
    let prompts = array(&deck, "prompt");
    assert_eq!(prompts.len(), 8);
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
    // Orbits drawn in x–y, and at least one scene to explore.
    let scenes = array(&deck, "scene");
    assert!(
        scenes
            .iter()
            .any(|s| s.contains_key("knobs") && s.contains_key("explore"))
    );
    for s in &scenes {
        let sketch = s["sketch"].as_array().unwrap();
        assert!(
            sketch.iter().any(|m| m.get("trail").is_some()),
            "{}",
            s["id"]
        );
    }
}

#[test]
fn check_passes_it_without_a_warning() {
    assert_checks_clean(&DECK);
}

/// Every prompt's answer on the deck's own run: a number within its
/// tolerance, a choice with exactly the expected condition holding.
#[test]
fn every_prompt_answer_is_what_the_simulator_measures() {
    let deck = DECK.deck();
    for p in array(&deck, "prompt") {
        // A varied prompt's answer is each variant's run's: `check` runs
        // its variants, and `varied_prompts_stay_decidable_over_their_range`
        // holds them to the closed forms.
        if p.contains_key("vary") {
            continue;
        }
        let answer = p["answer"].as_table().unwrap();
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
}

/// The numbers the cards and sections state, each measured (or computed
/// from what was measured) and found written in both languages.
#[test]
fn every_number_the_texts_state_is_measured() {
    // The launch at 0.8 × 2π: L, E, the turning points, the circular radius
    // and the bottom of the effective potential.
    let v = DECK.measure(
        "launch",
        &["final(L)", "final(E)", "min(r)", "max(r)", "min(Ueff)"],
    );
    let (l, e, rmin, rmax, umin) = (v[0], v[1], v[2], v[3], v[4]);
    close("L", l, 5.027, 1e-3);
    close("E", e, -26.85, 1e-3);
    close("perihelion", rmin, 0.4706, 1e-4);
    close("aphelion", rmax, 1.0, 1e-9);
    close("r_c = L²/GM", l * l / GM, 0.64, 1e-6);
    close("U_eff at r_c", umin, -30.84, 1e-3);
    close("−(GM)²/(2L²)", -GM * GM / (2.0 * l * l), umin, 1e-6);
    for (kind, id) in [
        ("card", "turning-points"),
        ("section", "effective-potential"),
    ] {
        for t in ["5.027", "-26.85", "0.4706"] {
            DECK.assert_quoted(kind, id, t);
        }
    }
    for (kind, id) in [
        ("card", "circular-minimum"),
        ("section", "effective-potential"),
    ] {
        for t in ["0.64", "-30.84"] {
            DECK.assert_quoted(kind, id, t);
        }
    }

    // The e = 0.9 orbit.
    let v = DECK.measure(
        "eccentric",
        &[
            "min(r)",
            "max(r)",
            "min(v)",
            "max(v)",
            "period(x)",
            "max(x)",
            "min(x)",
        ],
    );
    let (rp, ra, va, vp, t) = (v[0], v[1], v[2], v[3], v[4]);
    close("perihelion", rp, 0.1, 1e-6);
    close("aphelion", ra, 1.9, 1e-6);
    close("aphelion speed", va, 1.441, 1e-3);
    close("perihelion speed", vp, 27.39, 1e-3);
    close("v_p/v_a", vp / va, 19.0, 1e-5);
    let ecc = (ra - rp) / (ra + rp);
    close("eccentricity", ecc, 0.9, 1e-6);
    close("(1 + e)/(1 − e)", (1.0 + ecc) / (1.0 - ecc), vp / va, 1e-5);
    close("force ratio", (ra / rp).powi(2), 361.0, 1e-5);
    close("period", t, 1.0, 1e-5);
    close("centre to Sun", -(v[5] + v[6]) / 2.0, 0.9, 1e-6);
    for t in ["27.39", "1.441", "19"] {
        DECK.assert_quoted("card", "apsis-speeds", t);
        DECK.assert_quoted("section", "example-eccentric", t);
    }
    DECK.assert_quoted("section", "example-eccentric", "361");
    DECK.assert_quoted("section", "example-eccentric", "0.9 AU");
    DECK.assert_quoted("card", "kepler-first", "0.9 AU");
    DECK.assert_quoted("card", "symplectic", "361");
    for id in ["eccentric-period", "mistake-eccentric"] {
        DECK.assert_quoted("card", id, "1 yr");
    }

    // Circular speed 2π AU/yr at 1 AU (about 30 km/s), period 1 yr; at 4 AU,
    // π AU/yr and 8 yr.
    let v = DECK.measure(
        "two-circles",
        &[
            "min(r1)",
            "max(r1)",
            "period(x1)",
            "min(r2)",
            "max(r2)",
            "period(x2)",
        ],
    );
    close("inner circle", v[0], 1.0, 1e-6);
    close("inner circle", v[1], 1.0, 1e-6);
    close("inner period", v[2], 1.0, 1e-6);
    close("outer circle", v[3], 4.0, 1e-6);
    close("outer circle", v[4], 4.0, 1e-6);
    close("outer period", v[5], 8.0, 1e-6);
    close("2π AU/yr in km/s", 2.0 * PI * AU_PER_YR_KMS, 30.0, 0.01);
    for (kind, id) in [
        ("card", "circular-speed"),
        ("section", "circular-and-escape"),
    ] {
        DECK.assert_quoted(kind, id, "30 km/s");
    }
    DECK.assert_quoted("card", "kepler-third", "8 yr");
    DECK.assert_quoted("section", "kepler-laws", "8 yr");

    // Escape: at 1.5 × 2π, E = +4.93 and 39 AU after 10 yr.
    let v = DECK.measure("escape", &["final(E)", "max(r)"]);
    close("E", v[0], 4.93, 1e-3);
    close("distance after 10 yr", v[1], 39.0, 0.01);
    DECK.assert_quoted("card", "escape-direction", "+4.93");
    DECK.assert_quoted("section", "circular-and-escape", "+4.93");
    DECK.assert_quoted("section", "circular-and-escape", "39 AU");

    // Precession: 3.655° per orbit at λ/L² = 0.02 (180° λ/L² = 3.6°).
    let v = DECK.measure("precession", &["max(adv)", "final(L)"]);
    close("advance", v[0], 3.655, 1e-4);
    close("L", v[1], 8.0, 1e-6);
    close("λ/L²", 1.28 / (v[1] * v[1]), 0.02, 1e-6);
    close("180° λ/L²", 180.0 * 1.28 / (v[1] * v[1]), 3.6, 1e-6);
    for (kind, id) in [("card", "precession-formula"), ("section", "precession")] {
        for t in ["3.655", "3.6^\\circ"] {
            DECK.assert_quoted(kind, id, t);
        }
    }

    // The heavy planet: 300 times heavier, still 1 yr.
    let scene = find(&DECK.deck(), "scene", "heavy-light").clone();
    assert_eq!(scene["params"]["m2"].as_float(), Some(300.0));
    close(
        "heavy period",
        DECK.measure_one("heavy-light", "period(x2)"),
        1.0,
        1e-6,
    );
    DECK.assert_quoted("card", "mistake-heavy", "300");
    DECK.assert_quoted("section", "mistakes", "300");
}

/// E ≥ 0 exactly from √2 times the circular speed: just below it the probe
/// turns back, just above it does not.
#[test]
fn escape_speed_is_root_two_times_circular() {
    let v_esc = (2.0 * GM).sqrt();
    close("v_esc", v_esc, 8.886, 1e-4);
    close("v_esc in km/s", v_esc * AU_PER_YR_KMS, 42.0, 0.01);
    for (kind, id) in [("card", "escape-speed"), ("section", "circular-and-escape")] {
        for t in ["8.886", "6.283", "42 km/s"] {
            DECK.assert_quoted(kind, id, t);
        }
    }
    let at = |vy: f64| {
        let dir = tempfile::tempdir().unwrap();
        let path = DECK.edited(dir.path(), "escape", &[("initial.vy", vy)]);
        crate::support::deck::measure_in(&path, "escape", &["final(E)", "max(r)", "final(r)"])
    };
    // 0.9 × v_esc: a = 2.6 AU, back within the 10 yr run.
    let below = at(0.9 * v_esc);
    assert!(below[0] < 0.0 && below[2] < below[1], "{below:?}");
    let above = at(1.05 * v_esc);
    assert!(above[0] > 0.0 && above[2] == above[1], "{above:?}");
}

/// T² ∝ a³: the two circles' periods, and ellipses launched at other
/// speeds, each against 2π sqrt(a³/GM) with a from vis-viva.
#[test]
fn periods_follow_keplers_third_law() {
    let v = DECK.measure("two-circles", &["period(x1)", "period(x2)"]);
    close("T2/T1", v[1] / v[0], 4f64.powf(1.5), 1e-6);
    for vy in [4.0, 5.5, 7.0, 8.0] {
        let dir = tempfile::tempdir().unwrap();
        let path = DECK.edited(
            dir.path(),
            "launch",
            &[("initial.vy", vy), ("duration", 12.0)],
        );
        let t = crate::support::deck::measure_in(&path, "launch", &["period(x)"])[0];
        let a = 1.0 / (2.0 - vy * vy / GM);
        close(
            &format!("period at vy = {vy}"),
            t,
            2.0 * PI * (a.powi(3) / GM).sqrt(),
            1e-6,
        );
    }
}

/// The perihelion moves by 360° (1/√(1 − λ/L²) − 1) per orbit: forward
/// for an extra pull, backward for an extra push, within 1e-4° however
/// small the turn.
#[test]
fn precession_follows_the_closed_form_both_ways() {
    for lam in [-2.0, -1.28, -0.2, 0.1, 0.3, 1.28, 3.0] {
        let dir = tempfile::tempdir().unwrap();
        let path = DECK.edited(dir.path(), "precession", &[("lam", lam)]);
        let v = crate::support::deck::measure_in(&path, "precession", &["max(adv)", "max(ret)"]);
        let want = 360.0 * (1.0 / (1.0 - lam / 64.0_f64).sqrt() - 1.0);
        if lam > 0.0 {
            assert!(
                (v[0] - want).abs() < 1e-4,
                "advance at λ = {lam}: {} against {want}",
                v[0]
            );
            assert_eq!(v[1], 0.0, "λ = {lam}");
        } else {
            assert!(
                (v[1] + want).abs() < 1e-4,
                "regress at λ = {lam}: {} against {}",
                v[1],
                -want
            );
            assert_eq!(v[0], 0.0, "λ = {lam}");
        }
    }
}

/// Energy and angular momentum, declared conserved, hold on the hardest
/// runs.
#[test]
fn energy_and_angular_momentum_are_conserved() {
    for scene in ["eccentric", "precession", "launch", "escape"] {
        let v = DECK.measure(scene, &["drift(E)", "drift(L)"]);
        assert!(v[0] < 1e-5 && v[1] < 1e-5, "{scene}: {v:?}");
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
                    // From perihelion 0.1 AU at speed x: the other root of
                    // E r² + GM r − L²/2 = 0, and L/r there.
                    "aphelion-speed" => {
                        let (l, e) = (0.1 * x, 0.5 * x * x - GM / 0.1);
                        let ra = -l * l / (2.0 * e * 0.1);
                        l / ra
                    }
                    // From aphelion 1 AU at speed x: the other root.
                    "turning-point" => {
                        let (l, e) = (x, 0.5 * x * x - GM);
                        -l * l / (2.0 * e)
                    }
                    "precession-angle" => 360.0 * (1.0 / (1.0 - x / 64.0).sqrt() - 1.0),
                    other => panic!("no closed form for {other}"),
                };
                close(&format!("{id} at {x}"), got, want, 1e-4);
            }
        }
    }
}
