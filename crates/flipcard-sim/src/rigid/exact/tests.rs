use super::*;

fn exact(inertia: [f64; 3], omega: [f64; 3]) -> Exact {
    Exact::new(
        Body::new(inertia).unwrap(),
        Vector3::from(omega),
        Needs { orientation: false },
    )
    .unwrap()
}

#[test]
fn classifies_regimes() {
    assert_eq!(exact([1.0, 2.0, 3.0], [0.0; 3]).regime(), Regime::Rest);
    assert_eq!(exact([2.0; 3], [1.0, -2.0, 3.0]).regime(), Regime::Steady);
    assert_eq!(
        exact([1.0, 2.0, 3.0], [0.0, 5.0, 0.0]).regime(),
        Regime::Steady
    );
    // A spin in the degenerate plane of a symmetric body is steady too.
    assert_eq!(
        exact([2.0, 2.0, 3.0], [1.0, 1.0, 0.0]).regime(),
        Regime::Steady
    );
    assert_eq!(
        exact([2.0, 3.0, 2.0], [1.0, 1.0, 0.5]).regime(),
        Regime::SymmetricTop { axis: 1 }
    );
    assert_eq!(
        exact([1.0, 2.0, 3.0], [0.1, 0.2, 1.0]).regime(),
        Regime::Circulation { axis: 2 }
    );
    assert_eq!(
        exact([3.0, 1.0, 2.0], [0.1, 1.0, 0.2]).regime(),
        Regime::Circulation { axis: 1 }
    );
    assert_eq!(
        exact([3.0, 4.0, 6.0], [2.0, 0.5, 1.0]).regime(),
        Regime::Separatrix { middle: 1 }
    );
}

#[test]
fn periods_follow_k() {
    let e = exact([1.0, 2.0, 3.0], [0.01, 10.0, 0.01]);
    let (m, mc) = e.parameter().unwrap();
    assert!(m > 0.99 && mc > 0.0 && mc < 1e-4);
    let k = crate::rigid::elliptic::complete_k(mc);
    assert_eq!(e.period(), Some(4.0 * k / e.rate()));
    assert_eq!(e.flip_interval(), Some(2.0 * k / e.rate()));
    assert_eq!(exact([3.0, 4.0, 6.0], [2.0, 0.5, 1.0]).period(), None);
    let top = exact([2.0, 2.0, 3.0], [1.0, 0.0, 4.0]);
    assert!((top.period().unwrap() - 2.0 * std::f64::consts::PI / 2.0).abs() < 1e-15);
    assert_eq!(top.flip_interval(), None);
    assert_eq!(top.precession_rate(), Some(2.0));
}

#[test]
fn orientation_is_built_only_on_demand() {
    let e = exact([1.0, 2.0, 3.0], [0.3, 1.0, 0.2]);
    assert!(!e.orientation_prepared());
    let _ = e.omega_at(3.0);
    assert!(!e.orientation_prepared());
    let _ = e.state_at(3.0);
    assert!(e.orientation_prepared());
}

#[test]
fn linear_stability_signs() {
    let body = Body::new([1.0, 2.0, 3.0]).unwrap();
    assert!(linear_stability(&body, 1, 2.0) > 0.0);
    assert!(linear_stability(&body, 0, 2.0) < 0.0);
    assert!(linear_stability(&body, 2, 2.0) < 0.0);
    // middle axis: k = (I2−I1)(I3−I2)Ω²/(I1 I3)
    assert_eq!(linear_stability(&body, 1, 2.0), 4.0 / 3.0);
}

#[test]
fn starts_exactly_at_the_given_state() {
    for (inertia, omega) in [
        ([1.0, 2.0, 3.0], [0.01, 10.0, 0.01]),
        ([3.0, 4.0, 6.0], [2.0, 0.5, 1.0]),
        ([2.0, 2.0, 3.0], [0.7, -0.2, 1.5]),
    ] {
        let e = exact(inertia, omega);
        assert_eq!(e.omega_at(0.0), Vector3::from(omega));
        let s = e.state_at(0.0);
        assert_eq!(s.omega, Vector3::from(omega));
        assert!(s.q.angle() < 1e-15);
    }
}
