//! Numbers as a user reads them, in output, messages and the terminal view.
//!
//! Every f64 is written in its shortest round-trip form (reading the text
//! back gives the same bits). Rust's `{}` alone would spell 1e-300 with 300
//! zeros and 1.5e308 with 309 digits, so magnitudes outside [1e-4, 1e16)
//! take an exponent instead: `1e-300`, `5e-324`, `1.5e308`, while ordinary
//! values keep their plain spelling (`0.25`, `12.5`, `100`, `-0`).

use std::fmt;

/// Below this magnitude a number is written with an exponent...
const PLAIN_MIN: f64 = 1e-4;
/// ...and from this one on (the same bounds as Rust's `{:?}` and Python's
/// `repr`, so no plain spelling runs past 17 significant places).
const PLAIN_MAX: f64 = 1e16;

/// Formats as [`show`] inside `format!` without an intermediate string:
/// `format!("dt = {}", Num(dt))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        let a = x.abs();
        if a.is_finite() && a != 0.0 && !(PLAIN_MIN..PLAIN_MAX).contains(&a) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
}

/// `x` in shortest round-trip form, with an exponent when very large or small.
pub fn show(x: f64) -> String {
    Num(x).to_string()
}

/// `x` rounded to `digits` significant digits and shown as [`show`] does:
/// `rounded(2.7531234, 4)` = `2.753`, `rounded(4.0, 6)` = `4`,
/// `rounded(1.23456789e-300, 3)` = `1.23e-300`.
pub fn rounded(x: f64, digits: usize) -> String {
    if !x.is_finite() || digits == 0 {
        return show(x);
    }
    let text = format!("{:.*e}", digits - 1, x);
    match text.parse::<f64>() {
        Ok(r) if r.is_finite() => show(r),
        // Rounding up past f64::MAX: round towards zero instead.
        _ => show(below(x.abs(), digits).copysign(x)),
    }
}

/// The largest number of `digits` significant decimal digits not above
/// `x` (x > 0 finite), for stating an upper limit that, copied back, is
/// accepted: `below(113.59, 4)` = 113.5.
pub fn below(x: f64, digits: usize) -> f64 {
    if !(x.is_finite() && x > 0.0) || digits == 0 {
        return x;
    }
    let text = format!("{:.*e}", digits - 1, x);
    let Some((mantissa, exponent)) = text.split_once('e') else {
        return x;
    };
    let (Ok(mantissa), Ok(exponent)) = (
        mantissa.replace('.', "").parse::<u64>(),
        exponent.parse::<i32>(),
    ) else {
        return x;
    };
    let exponent = exponent - (digits as i32 - 1);
    let value = |m: u64, e: i32| format!("{m}e{e}").parse::<f64>().unwrap_or(x);
    let rounded = value(mantissa, exponent);
    let smallest = 10u64.pow(digits as u32 - 1);
    if rounded <= x {
        rounded
    } else if mantissa > smallest {
        value(mantissa - 1, exponent)
    } else {
        // Rounding carried into the next decade (9.99 → 1.0e1).
        value(10 * smallest - 1, exponent - 1)
    }
}

/// Three numbers as `a, b, c` (`sep` between them).
pub fn triple(v: &[f64; 3], sep: &str) -> String {
    format!("{}{sep}{}{sep}{}", Num(v[0]), Num(v[1]), Num(v[2]))
}

/// `x` to `digits` significant digits keeping trailing zeros, for values
/// read side by side ("1.49, 4.24 and 7.00 s"): plain within
/// [1e-3, 1e6), with an exponent outside.
pub fn sig(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    let a = x.abs();
    if !x.is_finite() || x == 0.0 {
        return show(x);
    }
    if !(1e-3..1e6).contains(&a) {
        return format!("{:.*e}", digits - 1, x);
    }
    // The decimals that leave `digits` significant ones after rounding
    // (9.996 to 3 digits is 10.0, not 9.996 → "10.00").
    let mut decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0);
    let text = format!("{:.*}", decimals as usize, x);
    let rounded: f64 = text.parse().unwrap_or(x);
    if rounded.abs() >= 10f64.powi(a.log10().floor() as i32 + 1) && decimals > 0 {
        decimals -= 1;
    }
    format!("{:.*}", decimals as usize, x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extremes_take_an_exponent_and_ordinary_numbers_do_not() {
        let cases = [
            (1e-300, "1e-300"),
            (5e-324, "5e-324"),
            (-5e-324, "-5e-324"),
            (1.5e308, "1.5e308"),
            (f64::MAX, "1.7976931348623157e308"),
            (1e16, "1e16"),
            (9999999999999998.0, "9999999999999998"),
            (1e-4, "0.0001"),
            (9.9e-5, "9.9e-5"),
            (0.25, "0.25"),
            (12.5, "12.5"),
            (100.0, "100"),
            (1e9, "1000000000"),
            (0.0, "0"),
            (-0.0, "-0"),
            (f64::INFINITY, "inf"),
            (f64::NAN, "NaN"),
        ];
        for (x, want) in cases {
            assert_eq!(show(x), want, "{x:e}");
        }
    }

    #[test]
    fn rounded_keeps_a_few_digits_in_the_same_spelling() {
        assert_eq!(rounded(2.7531234, 4), "2.753");
        assert_eq!(rounded(4.0, 6), "4");
        assert_eq!(rounded(-0.043483642, 3), "-0.0435");
        assert_eq!(rounded(577.35026918962, 6), "577.35");
        assert_eq!(rounded(1.23456789e-300, 3), "1.23e-300");
        assert_eq!(rounded(1.5e308, 6), "1.5e308");
        assert_eq!(rounded(f64::MAX, 2), "1.7e308");
        assert_eq!(rounded(-f64::MAX, 2), "-1.7e308");
        assert_eq!(rounded(1234567.0, 3), "1230000");
    }

    #[test]
    fn limits_round_down_to_a_few_digits() {
        assert_eq!(below(113.5962, 4), 113.5);
        assert_eq!(below(113.5, 4), 113.5);
        assert_eq!(below(304495732.9, 3), 304000000.0);
        assert_eq!(below(9.99999, 2), 9.9);
        assert_eq!(below(1.5e308, 3), 1.5e308);
        assert_eq!(below(f64::MAX, 4), 1.797e308);
        assert_eq!(below(5e-324, 2), 5e-324);
        assert_eq!(show(below(1.0 / 3.0 * 1e-300, 4)), "3.333e-301");
    }

    #[test]
    fn every_spelling_reads_back_bit_for_bit_and_stays_short() {
        let mut x = f64::MIN_POSITIVE / 4503599627370496.0;
        while x.is_finite() {
            for v in [x, -x, x * 1.2345678901234567, 1.0 / 3.0 * x] {
                let s = show(v);
                assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
                assert!(s.len() <= 24, "{s}");
            }
            x *= 7.0;
        }
    }

    #[test]
    fn sig_keeps_trailing_zeros_to_the_digits_asked() {
        assert_eq!(sig(7.0, 3), "7.00");
        assert_eq!(sig(1.4913, 3), "1.49");
        assert_eq!(sig(0.17321, 3), "0.173");
        assert_eq!(sig(305.2, 3), "305");
        assert_eq!(sig(9.996, 3), "10.0");
        assert_eq!(sig(-2.5, 2), "-2.5");
        assert_eq!(sig(0.0, 3), "0");
        assert_eq!(sig(1.5e-5, 3), "1.50e-5");
    }
}
