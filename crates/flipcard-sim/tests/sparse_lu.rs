//! Radau IIA with a sparse LU on a system whose Jacobian no ordering makes
//! a narrow band: the Brusselator on a 15×15 grid (450 variables, the
//! deck of tests/fixtures/brusselator2d written out here as equations),
//! compiled as a deck's system is. The sparse factors give the dense
//! factors' run: the same steps and the same state.

use std::time::Instant;

use flipcard_sim::scene::spec::{SystemPanel, SystemScene};
use flipcard_sim::solvers::ode::lu::{LuKind, LuPlan, Reuse};
use flipcard_sim::solvers::ode::{Atol, OdeSolver, OdeSystem, Options, Radau5};
use flipcard_sim::system::System;
use nalgebra::DMatrix;

const N: usize = 15;

/// The scene tests/fixtures/brusselator2d/make.py writes.
fn brusselator_2d() -> SystemScene {
    let c = (N as f64 + 1.0).powi(2) / 50.0;
    let cells: Vec<(usize, usize)> = (1..=N).flat_map(|i| (1..=N).map(move |j| (i, j))).collect();
    let at = |s: &str, edge: &str, a: usize, b: usize| {
        if (1..=N).contains(&a) && (1..=N).contains(&b) {
            format!("{s}{a}_{b}")
        } else {
            edge.to_string()
        }
    };
    let lap = |s: &str, edge: &str, i: usize, j: usize| {
        format!(
            "{} + {} + {} + {} - 4*{s}{i}_{j}",
            at(s, edge, i - 1, j),
            at(s, edge, i + 1, j),
            at(s, edge, i, j - 1),
            at(s, edge, i, j + 1)
        )
    };
    let mut variables: Vec<String> = cells.iter().map(|(i, j)| format!("u{i}_{j}")).collect();
    variables.extend(cells.iter().map(|(i, j)| format!("v{i}_{j}")));
    let tau = 2.0 * std::f64::consts::PI / (N as f64 + 1.0);
    let mut initial: Vec<f64> = cells
        .iter()
        .map(|&(i, j)| 1.0 + (tau * i as f64).sin() * (tau * j as f64).sin())
        .collect();
    initial.extend(std::iter::repeat_n(3.0, N * N));
    let mut equations: Vec<String> = cells
        .iter()
        .map(|&(i, j)| {
            format!(
                "1 + u{i}_{j}^2*v{i}_{j} - 4*u{i}_{j} + c*({})",
                lap("u", "1", i, j)
            )
        })
        .collect();
    equations.extend(cells.iter().map(|&(i, j)| {
        format!(
            "3*u{i}_{j} - u{i}_{j}^2*v{i}_{j} + c*({})",
            lap("v", "3", i, j)
        )
    }));
    SystemScene {
        id: "bruss2d".into(),
        title: None,
        variables,
        initial,
        params: vec![("c".into(), c)],
        equations,
        observables: vec![],
        conserved: vec![],
        duration: 10.0,
        show: vec![SystemPanel::Plot],
        plot: vec!["u8_8".into()],
        phase: None,
        sketch: vec![],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

fn opts(rtol: f64) -> Options {
    Options {
        rtol,
        atol: Atol::Scalar(1e-2 * rtol),
        t_stop: Some(10.0),
        ..Options::default()
    }
}

/// A run to t = 10 in the form `kind`: the end state, the work, how the
/// sparse factorisations went, seconds.
fn run(
    scene: &SystemScene,
    kind: LuKind,
    rtol: f64,
) -> (Vec<f64>, flipcard_sim::solvers::ode::Work, Reuse, f64) {
    let sys = System::compile(scene, true).unwrap();
    let start = Instant::now();
    let mut radau = Radau5::new(sys, 0.0, &scene.initial, &opts(rtol)).unwrap();
    assert!(radau.force_lu(kind), "{kind:?}");
    let y = radau.advance(10.0).unwrap().to_vec();
    let secs = start.elapsed().as_secs_f64();
    (y, radau.work(), radau.lu_reuse(), secs)
}

#[test]
fn the_grid_is_factored_sparse_and_agrees_with_dense() {
    let scene = brusselator_2d();
    let sys = System::compile(&scene, true).unwrap();
    let n = sys.dim();
    assert_eq!(n, 2 * N * N);
    let radau = Radau5::new(sys, 0.0, &scene.initial, &opts(1e-6)).unwrap();
    assert_eq!(radau.lu_kind(), LuKind::Sparse);
    let (sparse, ws, reuse, _) = run(&scene, LuKind::Sparse, 1e-6);
    let (dense, wd, _, _) = run(&scene, LuKind::Dense, 1e-6);
    assert_eq!(ws.lu, Some(LuKind::Sparse));
    assert_eq!(wd.lu, Some(LuKind::Dense));
    // Every factorisation after the first reuses the last one's pivots
    // (the real and the complex matrix counted apart): the grid's Newton
    // matrices are diagonally dominant enough that none falls back.
    assert_eq!(reuse.reused + reuse.fresh, 2 * ws.lu_decomps, "{reuse:?}");
    assert!(
        reuse.reused >= 2 * (ws.lu_decomps - 1),
        "{reuse:?} of {ws:?}"
    );
    // Same Newton solves up to rounding: the same run, step for step.
    assert!(ws.steps.abs_diff(wd.steps) <= 2, "{ws:?} {wd:?}");
    let worst = sparse
        .iter()
        .zip(&dense)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-8, "sparse and dense differ by {worst:e}");
}

/// Steps, LU time share and run time of each form on the grid (wall
/// times: run on a quiet machine; the counts do not depend on it).
#[test]
#[ignore = "a measurement: cargo test --release -p flipcard-sim --test main sparse_lu -- --ignored --nocapture"]
fn forms_measured_on_the_grid() {
    let scene = brusselator_2d();
    let sys = System::compile(&scene, true).unwrap();
    let n = sys.dim();
    let mut jac = DMatrix::zeros(n, n);
    sys.jacobian(0.0, &scene.initial, &mut jac);
    for rtol in [1e-4, 1e-6, 1e-8] {
        for kind in LuKind::ALL {
            let plan = LuPlan::forced(kind, n, sys.sparsity().as_deref()).unwrap();
            let reps = 5;
            let t0 = Instant::now();
            for r in 0..reps {
                let f = plan.factor(&jac, 10.0 + r as f64, 8.0, 3.0);
                assert!(f.is_invertible());
            }
            let per_lu = t0.elapsed().as_secs_f64() / reps as f64;
            // Refactored in place on the last factors' pivots (the sparse
            // form only; the others factor afresh each time).
            let mut f = Some(plan.factor(&jac, 10.0, 8.0, 3.0));
            let t0 = Instant::now();
            for r in 0..reps {
                let (g, _) = plan.refactor(f.take(), &jac, 11.0 + r as f64, 8.0, 3.0);
                assert!(g.is_invertible());
                f = Some(g);
            }
            let per_refactor = t0.elapsed().as_secs_f64() / reps as f64;
            let (_, w, reuse, secs) = run(&scene, kind, rtol);
            println!(
                "rtol {rtol:e} {:>6}: {} steps, {} rejected, {} LU ({} reused, {} afresh, real and complex apart), {:.3} ms per LU afresh, {:.3} ms refactored, run {:.3} s, LU share {:.0}%",
                kind.name(),
                w.steps,
                w.rejected,
                w.lu_decomps,
                reuse.reused,
                reuse.fresh,
                per_lu * 1e3,
                per_refactor * 1e3,
                secs,
                100.0 * per_refactor * w.lu_decomps as f64 / secs
            );
        }
    }
}
