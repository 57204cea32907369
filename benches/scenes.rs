//! The live view's cost: the seed scene (`middle-axis-spin`: ω, body and
//! polhode panels, 8 s) played at 30 frames per scene second, as the
//! terminal view plays it, with the closed form. The view's budget is 5%
//! of a core: 30 frames must take under 50 ms of work per second, so one
//! whole play (240 frames) must stay well under 400 ms. Also the headless
//! measurement a verdict needs, and `flipcard check` of the bundled decks
//! with every prompt's scene run (its budget: under a second).
//!
//!     cargo bench --bench scenes

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use flipcard::deck::{Deck, Scene};
use flipcard::sim::Method;
use flipcard::sim::scene::{SceneRun, measure_scene};

fn seed_scene() -> Scene {
    let loaded = flipcard::bundled::load();
    let decks: Vec<Deck> = loaded.decks;
    decks
        .iter()
        .find_map(|d| d.scene("middle-axis-spin").cloned())
        .expect("the bundled deck has the seed scene")
}

fn play(scene: &Scene) -> f64 {
    let mut run = SceneRun::with_trace_len(scene, Method::Exact, 400).expect("scene runs");
    let mut t = 0.0;
    let mut acc = 0.0;
    while !run.finished() {
        t += 1.0 / 30.0;
        let frame = run.advance_to(t);
        acc += frame.omega[0] + frame.q.map_or(0.0, |q| q.w);
    }
    acc
}

fn scenes(c: &mut Criterion) {
    let scene = seed_scene();
    c.bench_function("seed scene: one play, 240 frames, exact", |b| {
        b.iter(|| play(black_box(&scene)))
    });
    c.bench_function("seed scene: one frame after setup", |b| {
        let mut run = SceneRun::new(&scene, Method::Exact).expect("scene runs");
        let mut t = 0.0;
        b.iter(|| {
            t += 1.0 / 30.0;
            if t > scene.duration {
                run = SceneRun::new(&scene, Method::Exact).expect("scene runs");
                t = 1.0 / 30.0;
            }
            black_box(run.advance_to(t).omega)
        })
    });
    c.bench_function("seed scene: headless measurements, exact", |b| {
        b.iter(|| measure_scene(black_box(&scene), Method::Exact))
    });
    c.bench_function("check of the bundled decks, every prompt simulated", |b| {
        b.iter(|| {
            let loaded = black_box(flipcard::bundled::load());
            let judged = flipcard::predict::audit::check_loaded(&loaded);
            assert!(judged.is_empty() && loaded.errors() == 0);
            loaded.decks.len()
        })
    });
}

criterion_group!(benches, scenes);
criterion_main!(benches);
