//! Compiled deck expressions against the same right-hand side written in
//! Rust: the pendulum θ' = ω, ω' = −g/L·sin θ (target: within 3×), and its
//! Jacobian; then a live system scene's frame (the work of one 30 fps frame
//! of the pendulum with every panel), whose time against 33 ms is its
//! share of a core.
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
            Mark::Dot(["x".into(), "y".into()]),
            Mark::Trail(["x".into(), "y".into()]),
        ],
        time_unit: "s".into(),
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

criterion_group!(benches, rhs, live_frame);
criterion_main!(benches);
