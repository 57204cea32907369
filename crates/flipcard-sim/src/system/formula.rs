//! A formula over named numbers, worked out once: a number prompt's known
//! slips (`value = "1/k"`) are read with the same parser as a system
//! scene's expressions ([`super::expr`]) and evaluated by the same
//! compiled program ([`super::compile`]), so a formula means one thing
//! wherever a deck writes it and there is no second evaluator.

use super::compile::{Source, System};
use super::expr::{self, ExprError};
use super::spec::SystemScene;

/// Whether `name` is one `evaluate` reads besides the `names` given:
/// the constants `pi` and `e` (never the time `t`: a formula here is a
/// number, not a function of time).
fn builtin(name: &str) -> bool {
    name == "pi" || name == "e"
}

/// Checks `text` against the names a formula may use: syntax, arity, and
/// every name known (`known`, or `pi` and `e`). The error is placed inside
/// `text` (byte offset), with the unknown name for a did-you-mean.
pub fn check(text: &str, known: &dyn Fn(&str) -> bool) -> Result<(), ExprError> {
    let node = expr::parse(text)?;
    expr::check_names(&node, &|n| builtin(n) || known(n))
}

/// The value of `text` with each of `names` standing for its number.
/// A formula that does not read (see [`check`]) is its error; one whose
/// value is not finite is an error at its start saying why (`division by
/// zero`, `square root of a negative number (sqrt(-2))`).
pub fn evaluate(text: &str, names: &[(String, f64)]) -> Result<f64, ExprError> {
    check(text, &|n| names.iter().any(|(m, _)| m == n))?;
    // Names an author may not give a scene (`t` aside, which `check`
    // refused) are never in `names` from a deck; a name the compiler
    // cannot take is refused like an unknown one.
    let scene = SystemScene::one_formula(
        Vec::new(),
        names.to_vec(),
        ("value".to_string(), text.to_string()),
    );
    let whole = |message: String| ExprError {
        at: 0,
        len: text.len().max(1),
        message,
        hint: None,
        unknown: None,
    };
    let system = System::compile(&scene, false).map_err(|e| whole(e.message))?;
    let value = system.observable(0, 0.0, &[]);
    if value.is_finite() {
        return Ok(value);
    }
    let what = if value.is_nan() { "NaN" } else { "infinite" };
    Err(whole(match system.observable_fault(0.0, &[]) {
        Some(fault) if fault.source == Source::Observable(0) => {
            format!("the formula is {what}: {}", fault.cause)
        }
        _ => format!("the formula is {what}"),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(pairs: &[(&str, f64)]) -> Vec<(String, f64)> {
        pairs.iter().map(|(n, v)| (n.to_string(), *v)).collect()
    }

    #[test]
    fn a_formula_reads_its_names_and_the_constants() {
        let k = names(&[("k", 100.0 / 3.0)]);
        let tau = evaluate("1/sqrt(k)", &k).unwrap();
        assert!((tau - 0.173_205).abs() < 1e-6, "{tau}");
        assert!((evaluate("1/k", &k).unwrap() - 0.03).abs() < 1e-12);
        let g = names(&[("g", 9.81), ("L", 1.0)]);
        let t0 = evaluate("2*pi*sqrt(L/g)", &g).unwrap();
        assert!((t0 - 2.006_066).abs() < 1e-6, "{t0}");
        assert!((evaluate("e^0", &[]).unwrap() - 1.0).abs() < 1e-15);
        assert!((evaluate("-2^2", &[]).unwrap() + 4.0).abs() < 1e-15);
    }

    #[test]
    fn a_formula_that_does_not_read_is_placed_inside_it() {
        let k = names(&[("k", 2.0)]);
        let e = evaluate("1/kk", &k).unwrap_err();
        assert_eq!((e.at, e.unknown.as_deref()), (2, Some("kk")));
        // Time is no name of a formula worked out once.
        assert_eq!(evaluate("t + k", &k).unwrap_err().at, 0);
        let e = evaluate("k +* 2", &k).unwrap_err();
        assert_eq!(e.at, 3);
    }

    #[test]
    fn a_value_that_is_not_finite_says_why() {
        let k = names(&[("k", -4.0), ("z", 0.0)]);
        let e = evaluate("1/sqrt(k)", &k).unwrap_err();
        assert!(
            e.message.contains("square root of a negative number"),
            "{e}"
        );
        let e = evaluate("1/z", &k).unwrap_err();
        assert!(e.message.contains("division by zero"), "{e}");
    }
}
