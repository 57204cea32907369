//! What a scene computes, derived from what it shows, before anything runs:
//! the orientation only when the body is drawn, the polhode geometry only
//! when the polhode is drawn, and the diagnostics (a second, exact run for
//! the error) only when the diagnostics are shown. A scene that shows ω
//! alone integrates three numbers and nothing else.

use crate::rigid::formula;
use crate::rigid::model::Body;
use crate::scene::spec::{Panel, Scene};
use crate::solvers::{Method, Needs};

/// Which closed form describes a body's free motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Shape {
    /// Three equal moments: ω never changes, the body turns uniformly.
    Sphere,
    /// Two equal moments: ω precesses uniformly about the symmetry `axis`
    /// (0-based), with sin and cos.
    SymmetricTop { axis: usize },
    /// Three distinct moments: Jacobi elliptic functions.
    Asymmetric,
}

impl Shape {
    pub(crate) fn of(body: &Body) -> Shape {
        let i = body.inertia;
        if i[0] == i[1] && i[1] == i[2] {
            Shape::Sphere
        } else if let Some(axis) = formula::symmetry_axis(body) {
            Shape::SymmetricTop { axis }
        } else {
            Shape::Asymmetric
        }
    }
}

/// The per-scene plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Plan {
    /// The solver integrates q only when the body is drawn.
    pub needs: Needs,
    /// The momentum sphere, separatrix and orbit are built only when the
    /// polhode is drawn.
    pub polhode: bool,
    /// Invariant drift is tracked, and the error against a second, exact run
    /// (unless the run is the exact one), only when diagnostics are shown.
    pub diagnostics: bool,
    pub shape: Shape,
    /// The method a scene plays with unless the learner picks another: the
    /// closed form, exact and cheapest for every shape (uniform rotation
    /// for a sphere, sin/cos for a symmetric top, elliptic functions else).
    pub default_method: Method,
}

impl Plan {
    pub(crate) fn for_scene(scene: &Scene, body: &Body) -> Plan {
        Plan {
            needs: Needs {
                orientation: scene.shows(Panel::Body),
            },
            polhode: scene.shows(Panel::Polhode),
            diagnostics: scene.shows(Panel::Diagnostics),
            shape: Shape::of(body),
            default_method: Method::Exact,
        }
    }

    /// Whether a run with `method` also runs the exact solution beside it
    /// (for the error shown in the diagnostics).
    pub(crate) fn reference_run(&self, method: &Method) -> bool {
        self.diagnostics && *method != Method::Exact
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(inertia: [f64; 3], show: &[Panel]) -> Scene {
        Scene {
            id: "s".into(),
            title: None,
            inertia,
            omega: [0.01, 10.0, 0.01],
            duration: 8.0,
            show: show.to_vec(),
            time_unit: "s".into(),
        }
    }

    fn plan(s: &Scene) -> Plan {
        Plan::for_scene(s, &Body::new(s.inertia).unwrap())
    }

    #[test]
    fn computes_only_what_is_shown() {
        let p = plan(&scene([1.0, 2.0, 3.0], &[Panel::Omega]));
        assert!(!p.needs.orientation && !p.polhode && !p.diagnostics);
        assert!(!p.reference_run(&Method::Rk4 { dt: 0.01 }));
        let p = plan(&scene([1.0, 2.0, 3.0], &[Panel::Omega, Panel::Body]));
        assert!(p.needs.orientation && !p.polhode);
        let p = plan(&scene(
            [1.0, 2.0, 3.0],
            &[Panel::Polhode, Panel::Diagnostics],
        ));
        assert!(!p.needs.orientation && p.polhode && p.diagnostics);
        assert!(p.reference_run(&Method::Adaptive { tol: 1e-8 }));
        assert!(
            !p.reference_run(&Method::Exact),
            "exact needs no second run"
        );
    }

    #[test]
    fn omega_only_exact_run_builds_no_orientation() {
        use crate::rigid::exact::Exact;
        use crate::solvers::Solver;
        let s = scene([1.0, 2.0, 3.0], &[Panel::Omega, Panel::Polhode]);
        let body = Body::new(s.inertia).unwrap();
        let p = Plan::for_scene(&s, &body);
        let mut exact = Exact::new(body, s.omega.into(), p.needs).unwrap();
        for k in 0..100 {
            let state = exact.advance(0.08 * k as f64).unwrap();
            assert_eq!(state.q, nalgebra::UnitQuaternion::identity());
        }
        assert!(
            !exact.orientation_prepared(),
            "no orientation constants built"
        );
        let s = scene([1.0, 2.0, 3.0], &[Panel::Body]);
        let p = Plan::for_scene(&s, &body);
        let exact = Exact::new(body, s.omega.into(), p.needs).unwrap();
        assert!(exact.orientation_prepared());
    }

    #[test]
    fn shapes_pick_their_closed_form() {
        assert_eq!(plan(&scene([2.0, 2.0, 2.0], &[])).shape, Shape::Sphere);
        assert_eq!(
            plan(&scene([1.0, 1.0, 1.0032787], &[])).shape,
            Shape::SymmetricTop { axis: 2 }
        );
        assert_eq!(
            plan(&scene([3.0, 2.0, 3.0], &[])).shape,
            Shape::SymmetricTop { axis: 1 }
        );
        let p = plan(&scene([1.0, 2.0, 3.0], &[]));
        assert_eq!(p.shape, Shape::Asymmetric);
        assert_eq!(p.default_method, Method::Exact);
    }
}
