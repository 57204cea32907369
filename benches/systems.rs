//! Compiled deck expressions against the same right-hand side written in
//! Rust: the pendulum θ' = ω, ω' = −g/L·sin θ (target: within 3×), and its
//! Jacobian; then a live system scene's frame (the work of one 30 fps frame
//! of the pendulum with every panel), whose time against 33 ms is its
//! share of a core. Then the hostile shapes: 25 observables doubling each
//! other (one evaluation of the equation that uses the last), and one frame
//! of a scene too heavy for the clock at ×64, which must return after its
//! 20 ms slice plus at most one step (target: under 33 ms, a frame).
//!
//!     cargo bench --bench systems

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use flipcard::sim::scene::spec::{Mark, SystemPanel, SystemScene};
use flipcard::sim::scene::system::SystemRun;
use flipcard::sim::solvers::ode::{OdeKind, OdeMethod, OdeSystem};
use flipcard::sim::system::System;
use nalgebra::DMatrix;

fn pendulum() -> SystemScene {
    SystemScene {
        id: "pendulum-170".into(),
        title: None,
        variables: vec!["theta".into(), "omega".into()],
        initial: vec![2.9670597283903604, 0.0],
        params: vec![("g".into(), 9.81), ("L".into(), 1.0)],
        equations: vec!["omega".into(), "-g/L*sin(theta)".into()],
        observables: vec![
            (
                "energy".into(),
                "0.5*L^2*omega^2 + g*L*(1 - cos(theta))".into(),
            ),
            ("x".into(), "L*sin(theta)".into()),
            ("y".into(), "-L*cos(theta)".into()),
        ],
        conserved: vec!["energy".into()],
        duration: 20.0,
        show: vec![
            SystemPanel::Plot,
            SystemPanel::Phase,
            SystemPanel::Sketch,
            SystemPanel::Diagnostics,
        ],
        plot: vec!["theta".into()],
        phase: Some(["theta".into(), "omega".into()]),
        sketch: vec![
            Mark::Line(["0".into(), "0".into(), "x".into(), "y".into()]),
            Mark::Dot(["x".into(), "y".into()], None),
            Mark::Trail(["x".into(), "y".into()]),
        ],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

struct Native {
    g: f64,
    l: f64,
}

impl OdeSystem for Native {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -self.g / self.l * y[0].sin();
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        jac[(0, 0)] = 0.0;
        jac[(0, 1)] = 1.0;
        jac[(1, 0)] = -self.g / self.l * y[0].cos();
        jac[(1, 1)] = 0.0;
    }
}

fn rhs(c: &mut Criterion) {
    let compiled = System::compile(&pendulum(), true).expect("compiles");
    let native = Native { g: 9.81, l: 1.0 };
    let mut g = c.benchmark_group("pendulum_rhs");
    let y = [0.7, -1.3];
    g.bench_function("compiled", |b| {
        let mut dy = [0.0; 2];
        b.iter(|| {
            compiled.rhs(0.0, black_box(&y), &mut dy);
            black_box(dy)
        })
    });
    g.bench_function("rust", |b| {
        let mut dy = [0.0; 2];
        b.iter(|| {
            native.rhs(0.0, black_box(&y), &mut dy);
            black_box(dy)
        })
    });
    g.finish();
    let mut g = c.benchmark_group("pendulum_jacobian");
    g.bench_function("compiled", |b| {
        let mut j = DMatrix::zeros(2, 2);
        b.iter(|| {
            compiled.jacobian(0.0, black_box(&y), &mut j);
            black_box(j[(1, 0)])
        })
    });
    g.bench_function("rust", |b| {
        let mut j = DMatrix::zeros(2, 2);
        b.iter(|| {
            native.jacobian(0.0, black_box(&y), &mut j);
            black_box(j[(1, 0)])
        })
    });
    g.finish();
}

/// One frame of the live pendulum at speed 1: 20 s of scene in 12 s of
/// wall time, so 1/30 s of wall clock is 0.0556 s of scene.
fn live_frame(c: &mut Criterion) {
    let scene = pendulum();
    let method = OdeMethod::default_for(OdeKind::Auto, scene.duration);
    let step = scene.duration / 12.0 / 30.0;
    c.bench_function("live_pendulum_frame", |b| {
        let mut run = SystemRun::new(&scene, method, &[]).expect("runs");
        b.iter(|| {
            if run.finished() {
                run = SystemRun::new(&scene, method, &[]).expect("runs");
            }
            run.advance_to(run.t() + step);
            black_box(run.state()[0])
        })
    });
}

/// x'' = −x + 0·o25 with o0 = x, o_k = o_{k−1} + o_{k−1}: 2^25 additions
/// inlined, 26 shared.
fn chained_observables(c: &mut Criterion) {
    let mut scene = pendulum();
    scene.variables = vec!["x".into(), "v".into()];
    scene.initial = vec![1.0, 0.0];
    scene.params.clear();
    scene.equations = vec!["v".into(), "-x + 0*o25".into()];
    scene.observables = std::iter::once(("o0".to_string(), "x".to_string()))
        .chain((1..=25).map(|k| (format!("o{k}"), format!("o{} + o{}", k - 1, k - 1))))
        .collect();
    scene.conserved.clear();
    scene.sketch.clear();
    let compiled = System::compile(&scene, true).expect("compiles");
    let y = [0.7, -1.3];
    c.bench_function("chained_observables_rhs", |b| {
        let mut dy = [0.0; 2];
        b.iter(|| {
            compiled.rhs(0.0, black_box(&y), &mut dy);
            black_box(dy[1])
        })
    });
}

/// A scene check accepts whose steps (about 1.4e6 operations each) cannot
/// keep up with the clock at ×64: one app frame asks for 4.3 s of scene,
/// hundreds of steps, and works for its 20 ms slice.
fn heavy_frame(c: &mut Criterion) {
    fn balanced(levels: usize) -> String {
        if levels == 0 {
            "x".to_string()
        } else {
            let half = balanced(levels - 1);
            format!("({half})+({half})")
        }
    }
    let term = balanced(12);
    let mut scene = pendulum();
    scene.variables = vec!["x".into(), "v".into()];
    scene.initial = vec![1.0, 0.0];
    scene.params.clear();
    scene.equations = vec!["v".into(), "-100*x + 1e-30*a10".into()];
    scene.observables = std::iter::once(("a0".to_string(), term.clone()))
        .chain((1..11).map(|i| (format!("a{i}"), format!("a{} + {term}", i - 1))))
        .collect();
    scene.conserved.clear();
    scene.sketch.clear();
    scene.show = vec![SystemPanel::Plot];
    scene.plot = vec!["x".into()];
    scene.phase = None;
    scene.duration = 25.0;
    let method = OdeMethod::default_for(OdeKind::Auto, scene.duration);
    let demand = 1.0 / 30.0 * (25.0 / 12.0) * 64.0;
    let slice = std::time::Duration::from_millis(20);
    c.bench_function("heavy_frame_sliced", |b| {
        let mut run = SystemRun::new(&scene, method, &[]).expect("runs");
        b.iter(|| {
            if run.finished() {
                run = SystemRun::new(&scene, method, &[]).expect("runs");
            }
            let target = run.t() + demand;
            black_box(
                run.advance_within(target, flipcard::sim::scene::slice::Slice::lasting(slice)),
            )
        })
    });
}

criterion_group!(benches, rhs, live_frame, chained_observables, heavy_frame);
criterion_main!(benches);
