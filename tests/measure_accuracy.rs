//! Every system measure against its exact value, through the real binary
//! (`flipcard sim --scene ID --measure …`, the run `check` and the verdict
//! take, at the scene's default tolerance): a Kepler orbit of eccentricity
//! 0.9, a rosette orbit (Kepler plus a 1/r³ force, whose radial motion is
//! a Kepler orbit's with a smaller angular momentum), and two coupled
//! oscillators whose energy beats. The scenes and their closed forms are in
//! `tests/decks/valid/measures-exact/decks/orbits.toml`; the target is
//! 1e-6 relative. Extremes and crossings read from samples alone missed by
//! up to 3e-5 here (a peak between two samples), and `period` of a beating
//! energy read its carrier's crossings.

use std::f64::consts::PI;

use crate::support::Flipcard;

const TARGET: f64 = 1e-6;

fn decks() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/decks/valid/measures-exact/decks"
    )
    .to_string()
}

/// The values `sim --scene` prints for `measures`, one a line.
fn measure(scene: &str, measures: &[&str]) -> Vec<f64> {
    let mut args = vec!["sim".to_string(), "--decks".into(), decks()];
    args.extend(["--scene".to_string(), scene.to_string()]);
    for m in measures {
        args.extend(["--measure".to_string(), m.to_string()]);
    }
    let out = Flipcard::without_data().args(&args).run();
    assert!(out.status.success(), "{}", out.stderr());
    let values: Vec<f64> = out
        .stdout()
        .lines()
        .map(|l| l.trim().parse().unwrap_or_else(|_| panic!("{l:?}")))
        .collect();
    assert_eq!(values.len(), measures.len(), "{}", out.stdout());
    values
}

fn close(what: &str, got: f64, exact: f64, within: f64) {
    let rel = (got - exact).abs() / exact.abs();
    assert!(
        rel <= within,
        "{what}: {got} against exact {exact} ({rel:.1e} relative)"
    );
}

/// The largest of `f` on [a, b]: a fine scan, then golden sections.
fn peak(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let n = 200_000;
    let h = (b - a) / n as f64;
    let k = (0..=n)
        .max_by(|&i, &j| f(a + i as f64 * h).total_cmp(&f(a + j as f64 * h)))
        .unwrap();
    let (mut lo, mut hi) = (a + (k as f64 - 1.0) * h, a + (k as f64 + 1.0) * h);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(c) > f(d) {
            hi = d;
        } else {
            lo = c;
        }
    }
    f(0.5 * (lo + hi))
}

const GM: f64 = 4.0 * PI * PI;

#[test]
fn kepler_orbit_measures_are_exact() {
    // a = 1 AU, e = 0.9, from perihelion: T = 1 yr, r between 0.1 and 1.9,
    // slowest at aphelion, ⟨r⟩ = a(1 + e²/2) over whole periods.
    let (a, e) = (1.0, 0.9);
    let got = measure(
        "kepler",
        &[
            "max(r)",
            "min(speed)",
            "period(r)",
            "period(x)",
            "mean(r)",
            "amplitude(r)",
            "crossings(x)",
        ],
    );
    close("max(r)", got[0], a * (1.0 + e), TARGET);
    let v_aphelion = (GM / a * (1.0 - e) / (1.0 + e)).sqrt();
    close("min(speed)", got[1], v_aphelion, TARGET);
    close("period(r)", got[2], 1.0, TARGET);
    close("period(x)", got[3], 1.0, TARGET);
    close("mean(r)", got[4], a * (1.0 + e * e / 2.0), TARGET);
    close("amplitude(r)", got[5], a * e, TARGET);
    // x changes sign twice an orbit, never at the ends of the 3-year run.
    assert_eq!(got[6], 6.0);
}

#[test]
fn kepler_orbit_times_and_counts_are_exact() {
    // Kepler's equation: t = (E − e sin E)/(2π) yr at eccentric anomaly E.
    let e: f64 = 0.9;
    let t_of = |ecc_anomaly: f64| (ecc_anomaly - e * ecc_anomaly.sin()) / (2.0 * PI);
    let got = measure(
        "kepler",
        &[
            "time_of(x < 0)",
            "time_of(r = 1)",
            "time_of(r >= 0.1)",
            "count(r > 1)",
            "count(x = 0)",
        ],
    );
    // x < 0 past a true anomaly of 90°, where cos E = e.
    close("time_of(x < 0)", got[0], t_of(e.acos()), TARGET);
    // r = a(1 − e cos E) = 1 at E = 90°.
    close("time_of(r = 1)", got[1], t_of(PI / 2.0), TARGET);
    // Holds at the start.
    assert_eq!(got[2], 0.0);
    // Beyond r = a once an orbit; x = 0 twice.
    assert_eq!(got[3], 3.0);
    assert_eq!(got[4], 6.0);
    let out = Flipcard::without_data()
        .args(["sim", "--decks", &decks(), "--scene", "kepler"])
        .args(["--measure", "time_of(r > 2)"])
        .run();
    assert!(!out.status.success());
    assert!(
        out.stderr()
            .contains("time_of(r > 2): r > 2 never holds over the run"),
        "{}",
        out.stderr()
    );
}

#[test]
fn rosette_orbit_radial_measures_are_exact() {
    // r'' = (h² − c)/r³ − GM/r²: Kepler's radial equation with h² − c.
    let (r0, v0) = (0.1, 2.0 * PI * 19f64.sqrt());
    let h = r0 * v0;
    let c = 0.05 * h * h;
    let energy = (h * h - c) / (2.0 * r0 * r0) - GM / r0;
    let a = -GM / (2.0 * energy);
    let got = measure("kepler-perturbed", &["max(r)", "min(r)", "period(r)"]);
    close("max(r)", got[0], 2.0 * a - r0, TARGET);
    close("min(r)", got[1], r0, TARGET);
    let radial = 2.0 * PI * (a.powi(3) / GM).sqrt();
    close("period(r)", got[2], radial, TARGET);
}

#[test]
fn a_gated_apsidal_angle_is_exact() {
    // φ while the comet climbs to aphelion, 0 after: its largest value is
    // the apsidal angle π/γ, γ = √(1 − c/h²) = √0.95, reached at half the
    // radial period.
    let (r0, v0) = (0.1, 2.0 * PI * 19f64.sqrt());
    let h = r0 * v0;
    let c = 0.05 * h * h;
    let energy = (h * h - c) / (2.0 * r0 * r0) - GM / r0;
    let a = -GM / (2.0 * energy);
    let radial = 2.0 * PI * (a.powi(3) / GM).sqrt();
    let got = measure("rosette-apsis", &["max(apsis)", "time_of(vr < 0)"]);
    close("max(apsis)", got[0], 180.0 / 0.95f64.sqrt(), TARGET);
    close("time_of(vr < 0)", got[1], radial / 2.0, TARGET);
}

#[test]
fn a_beat_without_an_envelope_is_refused_with_its_reason() {
    // The rosette's radial speed peaks at the same height every turn.
    let out = Flipcard::without_data()
        .args(["sim", "--decks", &decks(), "--scene", "kepler-perturbed"])
        .args(["--measure", "beat(vr)"])
        .run();
    assert!(!out.status.success());
    let err = out.stderr();
    assert!(
        err.contains("beat(vr): its peaks are all the same height"),
        "{err}"
    );
}

#[test]
fn coupled_oscillators_beat_exactly() {
    // x1 = cos Δt cos Σt, x2 = sin Δt sin Σt with ω₁ = 1, ω₂ = √1.2.
    let (w1, w2) = (1.0f64, 1.2f64.sqrt());
    let (d, s) = ((w2 - w1) / 2.0, (w2 + w1) / 2.0);
    let beat = PI / d;
    let got = measure(
        "coupled",
        &[
            "min(x1)",
            "max(x2)",
            "beat(x1)",
            "beat(x2)",
            "beat(e1)",
            "beat(v1)",
            "amplitude(x2)",
            "crossings(x1)",
        ],
    );
    let x1 = |t: f64| (d * t).cos() * (s * t).cos();
    let x2 = |t: f64| (d * t).sin() * (s * t).sin();
    close("min(x1)", got[0], -peak(|t| -x1(t), 0.0, 200.0), TARGET);
    let max_x2 = peak(x2, 0.0, 200.0);
    close("max(x2)", got[1], max_x2, TARGET);
    for (i, name) in [
        (2, "beat(x1)"),
        (3, "beat(x2)"),
        (4, "beat(e1)"),
        (5, "beat(v1)"),
    ] {
        close(name, got[i], beat, TARGET);
    }
    let min_x2 = -peak(|t| -x2(t), 0.0, 200.0);
    close("amplitude(x2)", got[6], (max_x2 - min_x2) / 2.0, TARGET);
    // Zeros of cos Σt and of cos Δt in (0, 200).
    let zeros = |w: f64| ((200.0 * w / PI) - 0.5).floor() + 1.0;
    assert_eq!(got[7], zeros(s) + zeros(d));
}
