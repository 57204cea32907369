//! Rendering every text of a deck-sized corpus (about 100 KB of card texts
//! and section bodies full of formulas), as the app does when it loads.

use criterion::{Criterion, criterion_group, criterion_main};
use flipcard::text::{check, markup, render};

/// Card-like texts and section-like bodies from the formulas of the
/// torque-free rotation notes, repeated to about `bytes`.
fn corpus(bytes: usize) -> (Vec<String>, Vec<String>) {
    const FORMULAS: &[&str] = &[
        r"\mathbf I = \mathrm{diag}(I_1,I_2,I_3)",
        r"\left(\frac{d\vec L}{dt}\right)_{\text{body}} + \vec\omega\times\vec L = \vec N",
        r"I_1\dot\omega_1 = (I_2-I_3)\,\omega_2\omega_3",
        r"\dfrac{dT}{dt} = I_1\omega_1\dot\omega_1 + I_2\omega_2\dot\omega_2 + I_3\omega_3\dot\omega_3",
        r"2T=\sum I_i\omega_i^2",
        r"L^2=\sum I_i^2\omega_i^2",
        r"\Rightarrow \ddot\omega_1 = \frac{(I_2-I_3)(I_3-I_1)}{I_1 I_2}\Omega^2\,\omega_1",
        r"\Omega_b=\dfrac{I_3-I_\perp}{I_\perp}\,\omega_3",
        r"k = \frac{(I_3-I_2)(I_2-I_1)}{I_1I_3}\Omega^2 = \frac{(1)(1)}{3}\cdot 100 = 33.3 > 0",
    ];
    let (mut cards, mut bodies) = (Vec::new(), Vec::new());
    let mut total = 0;
    for i in 0.. {
        if total >= bytes {
            break;
        }
        let f = FORMULAS[i % FORMULAS.len()];
        let g = FORMULAS[(i + 3) % FORMULAS.len()];
        let card =
            format!("Why does $\\vec\\omega$ move in the body frame? Because ${f}$, so ${g}$.");
        let body = format!(
            "In the body frame **the inertia tensor** is constant: $$ {f} $$\n\
             The price is an *extra term*, and\n\n- ${g}$ holds\n- energy is conserved: ${f}$\n\n\
             Costs \\$0, and a star * stays a star."
        );
        total += card.len() + body.len();
        cards.push(card);
        bodies.push(body);
    }
    (cards, bodies)
}

fn bench(c: &mut Criterion) {
    let (cards, bodies) = corpus(100_000);
    c.bench_function("render 100 KB of deck texts", |b| {
        b.iter(|| {
            let mut n = 0;
            for t in &cards {
                n += render(t).len();
            }
            for t in &bodies {
                n += markup::parse(t).len();
            }
            n
        })
    });
    c.bench_function("check 100 KB of deck texts", |b| {
        b.iter(|| {
            cards
                .iter()
                .chain(&bodies)
                .map(|t| check(t).len())
                .sum::<usize>()
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
