//! A number the learner typed, with the unit they wrote: "2.04", "2.04 s",
//! "2040 ms", "365 days", "34 deg", "−3,2 rad/s". The answer's unit is the
//! prompt's; a typed unit of the same kind (time, angle, length, or a
//! quotient of them such as `AU/yr`) is converted to it, with SI prefixes on
//! seconds, metres and radians. A unit of another kind, or one this table
//! does not know, is refused with the unit the prompt expects: a number is
//! never compared in the wrong unit.
//!
//! Angles are a dimension of their own here (a learner who types `Hz`
//! against `rad/s` is converted with 2π rad a cycle; `1/s` against `rad/s`
//! is refused rather than guessed).

/// Why a typed answer was not read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParseError {
    NotANumber,
    /// A unit that is not the prompt's and cannot be converted to it.
    WrongUnit,
}

/// Reads "5.77", "5.77 1/s", "-3,2 rad/s", "2040 ms": a number and,
/// optionally, a unit (spaces and case ignored where unambiguous) that is
/// the prompt's `unit` or converts to it. A unicode minus is accepted.
pub fn parse_number(input: &str, unit: &str) -> Result<f64, ParseError> {
    parse_number_in(input, unit, &[])
}

/// As [`parse_number`], knowing also the units a deck declares.
pub fn parse_number_in(input: &str, unit: &str, declared: &[Declared]) -> Result<f64, ParseError> {
    let text = input.trim().replace('−', "-");
    let end = text
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_digit()
                || c == '.'
                || c == ','
                || ((c == '-' || c == '+') && (i == 0 || text[..i].ends_with(['e', 'E'])))
                || ((c == 'e' || c == 'E')
                    && text[i + 1..]
                        .starts_with(|d: char| d.is_ascii_digit() || d == '-' || d == '+')))
        })
        .map_or(text.len(), |(i, _)| i);
    let number = text[..end].replace(',', ".");
    let value: f64 = number.parse().map_err(|_| ParseError::NotANumber)?;
    if !value.is_finite() {
        return Err(ParseError::NotANumber);
    }
    let squash = |s: &str| s.split_whitespace().collect::<String>();
    let typed = squash(&text[end..]);
    if typed.is_empty() || typed.to_lowercase() == squash(unit).to_lowercase() {
        return Ok(value);
    }
    let converted =
        convert_in(value, &typed, &squash(unit), declared).ok_or(ParseError::WrongUnit)?;
    if converted.is_finite() {
        Ok(converted)
    } else {
        Err(ParseError::NotANumber)
    }
}

/// `value` in unit `from` expressed in unit `to`, when both are known and
/// of the same kind.
pub fn convert(value: f64, from: &str, to: &str) -> Option<f64> {
    convert_in(value, from, to, &[])
}

fn convert_in(value: f64, from: &str, to: &str, declared: &[Declared]) -> Option<f64> {
    // A prompt without a unit asks for a pure number.
    let to = if to.is_empty() { "1" } else { to };
    let a = Unit::parse(from, declared)?;
    let b = Unit::parse(to, declared)?;
    (a.dims == b.dims).then(|| value * a.factor / b.factor)
}

/// A unit a deck declares (`units = { ly = "9.4607e15 m" }`): its name and
/// what it is in the known units.
#[derive(Debug, Clone, PartialEq)]
pub struct Declared {
    pub name: String,
    unit: Unit,
}

/// Why a deck's unit declaration is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DeclareError {
    #[error(
        "`{0}` is not a unit name: letters, digits and `_`, starting with a letter, at most 32 bytes"
    )]
    BadName(String),
    #[error("`{0}` is already a unit flipcard knows")]
    Known(String),
    #[error(
        "`{0}` is not a positive number followed by a unit flipcard knows (e.g. \"9.4607e15 m\", \"27.32 d\", \"1e-3 rad/s\")"
    )]
    BadValue(String),
}

/// The unit `name` declared as `definition`, a positive number and a known
/// unit (none: a pure number).
pub fn declare(name: &str, definition: &str) -> Result<Declared, DeclareError> {
    let word = name.len() <= 32
        && name.starts_with(|c: char| c.is_alphabetic())
        && name.chars().all(|c| c.is_alphanumeric() || c == '_');
    if !word {
        return Err(DeclareError::BadName(name.to_string()));
    }
    if Unit::parse(name, &[]).is_some() {
        return Err(DeclareError::Known(name.to_string()));
    }
    let bad = || DeclareError::BadValue(definition.to_string());
    let text = definition.trim();
    let end = text
        .find(|c: char| c.is_whitespace() || !(c.is_ascii_alphanumeric() || "+-.".contains(c)))
        .unwrap_or(text.len());
    let (number, rest) = text.split_at(end);
    let factor: f64 = number.parse().map_err(|_| bad())?;
    if !(factor.is_finite() && factor > 0.0) {
        return Err(bad());
    }
    let rest: String = rest.split_whitespace().collect();
    let base = if rest.is_empty() {
        Unit {
            factor: 1.0,
            dims: NONE,
        }
    } else {
        Unit::parse(&rest, &[]).ok_or_else(bad)?
    };
    let factor = factor * base.factor;
    if !(factor.is_finite() && factor > 0.0) {
        return Err(bad());
    }
    Ok(Declared {
        name: name.to_string(),
        unit: Unit {
            factor,
            dims: base.dims,
        },
    })
}

/// Exponents of (time, angle, length).
type Dims = [i8; 3];

const TIME: Dims = [1, 0, 0];
const ANGLE: Dims = [0, 1, 0];
const LENGTH: Dims = [0, 0, 1];
const NONE: Dims = [0, 0, 0];

/// A unit as a factor to SI (s, rad, m) and its dimensions.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Unit {
    factor: f64,
    dims: Dims,
}

/// Units by name: (names, factor to SI, dimensions, takes SI prefixes).
const UNITS: &[(&[&str], f64, Dims, bool)] = &[
    (&["s", "sec", "secs", "second", "seconds"], 1.0, TIME, true),
    (&["min", "mins", "minute", "minutes"], 60.0, TIME, false),
    (&["h", "hr", "hrs", "hour", "hours"], 3600.0, TIME, false),
    (&["d", "day", "days"], 86_400.0, TIME, false),
    (&["wk", "week", "weeks"], 604_800.0, TIME, false),
    // The Julian year, the astronomers' (365.25 d).
    (
        &["yr", "yrs", "year", "years", "a"],
        31_557_600.0,
        TIME,
        false,
    ),
    (&["rad", "radian", "radians"], 1.0, ANGLE, true),
    (
        &["deg", "degree", "degrees", "°"],
        std::f64::consts::PI / 180.0,
        ANGLE,
        false,
    ),
    (
        &["rev", "revs", "turn", "turns", "cycle", "cycles"],
        std::f64::consts::TAU,
        ANGLE,
        false,
    ),
    (
        &["m", "metre", "metres", "meter", "meters"],
        1.0,
        LENGTH,
        true,
    ),
    (&["au"], 1.495_978_707e11, LENGTH, false),
    (&["1"], 1.0, NONE, false),
];

/// SI prefixes a unit may take.
const PREFIXES: &[(&str, f64)] = &[
    ("n", 1e-9),
    ("µ", 1e-6),
    ("μ", 1e-6),
    ("u", 1e-6),
    ("m", 1e-3),
    ("c", 1e-2),
    ("k", 1e3),
];

impl Unit {
    /// A unit written as `a`, `a/b`, `a/b^2`, `a*b`, `Hz`; `None` when a
    /// part is unknown. At most 64 bytes are read.
    fn parse(text: &str, declared: &[Declared]) -> Option<Unit> {
        if text.is_empty() || text.len() > 64 {
            return None;
        }
        let (num, den) = match text.split_once('/') {
            Some((n, d)) => (n, Some(d)),
            None => (text, None),
        };
        let mut unit = Unit::product(num, declared)?;
        if let Some(den) = den {
            let d = Unit::product(den, declared)?;
            unit.factor /= d.factor;
            for i in 0..3 {
                unit.dims[i] -= d.dims[i];
            }
        }
        Some(unit)
    }

    /// `a*b*c` (or `a·b`), each with an optional integer power `^n`.
    fn product(text: &str, declared: &[Declared]) -> Option<Unit> {
        let mut unit = Unit {
            factor: 1.0,
            dims: NONE,
        };
        for part in text.split(['*', '·']) {
            let (name, power) = match part.split_once('^') {
                Some((n, p)) => (n, p.parse::<i8>().ok().filter(|p| (-4..=4).contains(p))?),
                None => (part, 1),
            };
            let one = match declared.iter().find(|d| d.name == name) {
                Some(d) => d.unit,
                None => Unit::one(name)?,
            };
            unit.factor *= one.factor.powi(i32::from(power));
            for i in 0..3 {
                unit.dims[i] += one.dims[i] * power;
            }
        }
        Some(unit)
    }

    /// One named unit, possibly prefixed ("ms", "km", "mrad"), or `Hz`.
    fn one(name: &str) -> Option<Unit> {
        if name.eq_ignore_ascii_case("hz") {
            return Some(Unit {
                factor: std::f64::consts::TAU,
                dims: [-1, 1, 0],
            });
        }
        let lookup = |n: &str| {
            UNITS.iter().find_map(|(names, factor, dims, prefixed)| {
                names
                    .iter()
                    .any(|x| *x == n || (n.len() > 1 && x.eq_ignore_ascii_case(n)))
                    .then_some((*factor, *dims, *prefixed))
            })
        };
        if let Some((factor, dims, _)) = lookup(name) {
            return Some(Unit { factor, dims });
        }
        PREFIXES.iter().find_map(|(p, scale)| {
            let rest = name.strip_prefix(p)?;
            let (factor, dims, prefixed) = lookup(rest)?;
            prefixed.then_some(Unit {
                factor: factor * scale,
                dims,
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_deck_declares_units_in_known_ones() {
        let ly = declare("ly", "9.4607e15 m").unwrap();
        let month = declare("lunar_month", "27.321661 d").unwrap();
        let both = [ly, month];
        let v = parse_number_in("13.368 lunar_month", "yr", &both).unwrap();
        assert!((v - 13.368 * 27.321661 / 365.25).abs() < 1e-12, "{v}");
        let v = parse_number_in("1 ly/yr", "km/s", &both).unwrap();
        assert!((v - 9.4607e15 / 31_557_600.0 / 1e3).abs() < 1e-9, "{v}");
        // The prompt's own unit may be a declared one.
        let v = parse_number_in("2 yr", "lunar_month", &both).unwrap();
        assert!((v - 2.0 * 365.25 / 27.321661).abs() < 1e-12, "{v}");
        // A declared unit of another kind is still refused.
        assert_eq!(
            parse_number_in("2 ly", "s", &both),
            Err(ParseError::WrongUnit)
        );
        // Not known without the deck.
        assert_eq!(parse_number("2 ly", "m"), Err(ParseError::WrongUnit));
        // A pure number.
        let dozen = declare("dozen", "12").unwrap();
        assert_eq!(parse_number_in("2 dozen", "", &[dozen]), Ok(24.0));
    }

    #[test]
    fn a_declaration_is_refused_with_its_reason() {
        assert_eq!(declare("s", "2 s"), Err(DeclareError::Known("s".into())));
        assert_eq!(declare("km", "1 m"), Err(DeclareError::Known("km".into())));
        assert!(matches!(
            declare("light year", "1 m"),
            Err(DeclareError::BadName(_))
        ));
        assert!(matches!(
            declare("2x", "1 m"),
            Err(DeclareError::BadName(_))
        ));
        for bad in [
            "", "m", "-1 m", "0 s", "1 parsec", "inf s", "1e308 yr", "nan",
        ] {
            assert!(
                matches!(declare("u", bad), Err(DeclareError::BadValue(_))),
                "{bad:?}"
            );
        }
    }

    #[test]
    fn numbers_with_the_prompts_unit_or_none() {
        assert_eq!(parse_number("5.77", "1/s"), Ok(5.77));
        assert_eq!(parse_number(" 5.77 1/s ", "1/s"), Ok(5.77));
        assert_eq!(parse_number("5,77 1 / S", "1/s"), Ok(5.77));
        assert_eq!(parse_number("−3e-2", "rad/s"), Ok(-0.03));
        assert_eq!(parse_number("305 d", "d"), Ok(305.0));
        assert_eq!(parse_number("fast", "1/s"), Err(ParseError::NotANumber));
        assert_eq!(parse_number("", "1/s"), Err(ParseError::NotANumber));
        assert_eq!(parse_number("1e999", "1/s"), Err(ParseError::NotANumber));
    }

    fn close(got: Result<f64, ParseError>, want: f64) {
        let got = got.unwrap_or_else(|e| panic!("{e:?}, want {want}"));
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
            "{got} vs {want}"
        );
    }

    #[test]
    fn units_a_student_writes_are_converted_to_the_prompts() {
        close(parse_number("2040 ms", "s"), 2.04);
        close(parse_number("2.04 s", "s"), 2.04);
        close(parse_number("365 days", "d"), 365.0);
        close(parse_number("1 yr", "d"), 365.25);
        close(parse_number("2 min", "s"), 120.0);
        close(parse_number("0.5 s", "ms"), 500.0);
        close(parse_number("180 deg", "rad"), std::f64::consts::PI);
        close(parse_number("34°", "rad"), 34.0_f64.to_radians());
        close(parse_number("1 Hz", "rad/s"), std::f64::consts::TAU);
        close(parse_number("27.39 AU/yr", "AU/yr"), 27.39);
        close(
            parse_number("1 AU/yr", "km/s"),
            1.495_978_707e8 / 31_557_600.0,
        );
        close(parse_number("3 1/min", "1/s"), 0.05);
    }

    #[test]
    fn another_kind_of_unit_or_an_unknown_one_is_refused() {
        assert_eq!(parse_number("305 kg", "d"), Err(ParseError::WrongUnit));
        assert_eq!(parse_number("2 m", "s"), Err(ParseError::WrongUnit));
        assert_eq!(parse_number("2 1/s", "rad/s"), Err(ParseError::WrongUnit));
        assert_eq!(parse_number("2 s", "1/s"), Err(ParseError::WrongUnit));
        assert_eq!(parse_number("2 parsecs", "m"), Err(ParseError::WrongUnit));
        assert_eq!(parse_number("2 s^99", "s"), Err(ParseError::WrongUnit));
        let long = format!("2 {}", "s*".repeat(100));
        assert_eq!(parse_number(&long, "s"), Err(ParseError::WrongUnit));
    }

    mod props {
        use super::super::*;
        use proptest::prelude::*;

        const KNOWN: &[&str] = &[
            "s", "ms", "min", "h", "d", "yr", "rad", "deg", "rev", "m", "km", "AU", "1/s", "rad/s",
            "Hz", "AU/yr", "m/s", "km/s", "1/d",
        ];

        proptest! {
            /// Converting there and back gives the number back, and any
            /// text never panics.
            #[test]
            fn round_trips(v in -1e6f64..1e6, a in 0..KNOWN.len(), b in 0..KNOWN.len()) {
                if let Some(there) = convert(v, KNOWN[a], KNOWN[b]) {
                    let back = convert(there, KNOWN[b], KNOWN[a]).unwrap();
                    prop_assert!((back - v).abs() <= 1e-9 * v.abs().max(1.0));
                }
            }

            #[test]
            fn any_text_is_a_number_or_a_refusal(text in "\\PC{0,40}", unit in "\\PC{0,8}") {
                if let Ok(v) = parse_number(&text, &unit) {
                    prop_assert!(v.is_finite());
                }
            }
        }
    }
}
