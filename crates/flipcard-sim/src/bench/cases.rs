//! The problem set of the work–precision sweep, and the settings each
//! method is swept over.

use nalgebra::Vector3;

use crate::rigid::formula;
use crate::rigid::model::Body;
use crate::rigid::scales::scales;
use crate::solvers::Method;

/// One problem: a body, an initial ω and a span.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Short id used in the CSV (`a` … `e`).
    pub id: &'static str,
    pub name: &'static str,
    pub body: Body,
    pub omega0: Vector3<f64>,
    pub t_end: f64,
}

/// Distance of case (c) from the separatrix: (L² − 2E·I₂)/L².
pub(crate) const SEPARATRIX_DISTANCE: f64 = 1e-9;

fn body(i: [f64; 3]) -> Body {
    // The moments below are all physical; a typo would fail every bench test.
    Body::new(i).unwrap_or_else(|e| panic!("bench case moments {i:?}: {e}"))
}

/// (a) the notes' case, (b) a needle near its limit, (c) an orbit within
/// 1e-9 of the separatrix, (d) the notes' case spun 10⁴ times faster, (e) a
/// long run of 10⁴ periods. `quick` shortens every span.
pub fn cases(quick: bool) -> Vec<Case> {
    let short = |full: f64, quick_span: f64| if quick { quick_span } else { full };
    let notes = body([1.0, 2.0, 3.0]);
    // L² − 2E·I₂ = 3ω₃² − ω₁² for I = (1, 2, 3); with ω₂ = ω₃ = 1, L² = 16,
    // so ω₁ = √3 (1 − δ) puts the orbit 6δ/16 from the separatrix.
    let delta = SEPARATRIX_DISTANCE * 16.0 / 6.0;
    let near = Vector3::new(3f64.sqrt() * (1.0 - delta), 1.0, 1.0);
    // Case (e): 10⁴ periods of a generic circulation about the largest axis.
    let generic = Vector3::new(0.2, 0.5, 1.0);
    let period = formula::period(&notes, &generic).unwrap_or(1.0);
    vec![
        Case {
            id: "a",
            name: "notes: I = (1, 2, 3), ω = (0.01, 10, 0.01)",
            body: notes,
            omega0: Vector3::new(0.01, 10.0, 0.01),
            t_end: short(100.0, 10.0),
        },
        Case {
            id: "b",
            name: "needle: I = (1e-6, 1, 1 + 5e-7)",
            body: body([1e-6, 1.0, 1.0 + 5e-7]),
            omega0: Vector3::new(1e3, 1.0, 0.5),
            t_end: short(10.0, 1.0),
        },
        Case {
            id: "c",
            name: "1e-9 from the separatrix",
            body: notes,
            omega0: near,
            t_end: short(50.0, 10.0),
        },
        Case {
            id: "d",
            name: "fast: ω × 1e4",
            body: notes,
            omega0: Vector3::new(100.0, 1e5, 100.0),
            t_end: short(0.1, 0.001),
        },
        Case {
            id: "e",
            name: if quick {
                "long: 1e2 periods"
            } else {
                "long: 1e4 periods"
            },
            body: notes,
            omega0: generic,
            t_end: period * short(1e4, 1e2),
        },
    ]
}

/// Tolerances of the adaptive sweep.
pub(crate) fn tolerances(quick: bool) -> Vec<f64> {
    let exponents: Vec<i32> = if quick {
        vec![3, 5, 7, 9, 11, 13]
    } else {
        (3..=13).collect()
    };
    exponents.into_iter().map(|e| 10f64.powi(-e)).collect()
}

/// Fixed steps per turn of the fastest rate (of ω's nutation and of q).
pub(crate) fn steps_per_turn(quick: bool) -> Vec<f64> {
    if quick {
        vec![16.0, 64.0, 256.0]
    } else {
        vec![8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0, 1024.0, 2048.0]
    }
}

/// Every method × setting run on a case, the exact solver first.
pub fn methods(case: &Case, quick: bool) -> Vec<Method> {
    let rate = scales(&case.body, &case.omega0).fastest(true);
    let mut out = vec![Method::Exact];
    out.extend(
        tolerances(quick)
            .into_iter()
            .map(|tol| Method::Adaptive { tol }),
    );
    let dts: Vec<f64> = steps_per_turn(quick)
        .into_iter()
        .map(|n| std::f64::consts::TAU / (n * rate))
        .collect();
    for make in [
        (|dt| Method::Splitting { dt }) as fn(f64) -> Method,
        |dt| Method::Splitting4 { dt },
        |dt| Method::Rk4 { dt },
    ] {
        out.extend(dts.iter().map(|&dt| make(dt)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separatrix_case_is_as_close_as_promised() {
        let c = &cases(false)[2];
        let (l2, e) = (c.body.l2(&c.omega0), c.body.energy(&c.omega0));
        let distance = (l2 - 2.0 * e * 2.0) / l2;
        assert!(
            (distance - SEPARATRIX_DISTANCE).abs() < 1e-3 * SEPARATRIX_DISTANCE,
            "{distance}"
        );
    }

    #[test]
    fn notes_case_flips_about_36_times() {
        let c = &cases(false)[0];
        let half = formula::flip_interval(&c.body, &c.omega0, 1).unwrap();
        let flips = c.t_end / half;
        assert!((35.0..38.0).contains(&flips), "{flips}");
    }

    #[test]
    fn every_method_family_is_swept() {
        let c = &cases(true)[0];
        let m = methods(c, true);
        for name in ["exact", "adaptive", "splitting", "splitting4", "rk4"] {
            assert!(m.iter().any(|x| x.name() == name), "{name}");
        }
        assert_eq!(Method::Adaptive { tol: 1e-10 }.setting(), "tol=1e-10");
    }
}
