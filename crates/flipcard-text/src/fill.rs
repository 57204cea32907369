//! Placeholders of a varied prompt's text (issue 24 §2): `{theta0}` shows
//! a drawn number as its shortest decimal, `{theta0:.1}` with one decimal.
//! Only names the caller knows are placeholders, so the braces of math
//! (`\frac{a}{b}`, `\sqrt{L/g}`) pass through untouched; a group that is
//! exactly a varied name (`\frac{L}{g}` when `L` varies) is a placeholder,
//! and an author keeps it math by writing `{ L }`.

use std::ops::Range;

/// The most decimals a placeholder may ask for.
pub const MAX_DECIMALS: u8 = 12;

/// One placeholder found in a text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Placeholder<'a> {
    pub name: &'a str,
    /// `Some(n)` for `{name:.n}`.
    pub decimals: Option<u8>,
    /// Where it is, braces included (bytes).
    pub range: Range<usize>,
}

/// Why a placeholder of a known name does not read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BadFormat {
    pub name: String,
    pub format: String,
    pub range: Range<usize>,
}

/// The placeholders of `text` naming one of `names`, in order; a known
/// name with a format other than `.N` (N ≤ [`MAX_DECIMALS`]) is an error.
pub fn placeholders<'a>(
    text: &'a str,
    names: &[&'a str],
) -> Result<Vec<Placeholder<'a>>, BadFormat> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != b'{' {
            i += 1;
            continue;
        }
        let Some(len) = text[i + 1..].find(['}', '{']) else {
            break;
        };
        let end = i + 1 + len;
        if bytes[end] == b'{' {
            i = end;
            continue;
        }
        let inner = &text[i + 1..end];
        let (name, format) = match inner.split_once(':') {
            Some((n, f)) => (n, Some(f)),
            None => (inner, None),
        };
        if let Some(&known) = names.iter().find(|n| **n == name) {
            let decimals = match format {
                None => None,
                Some(f) => match f
                    .strip_prefix('.')
                    .filter(|d| {
                        !d.is_empty() && d.len() <= 2 && d.bytes().all(|b| b.is_ascii_digit())
                    })
                    .and_then(|d| d.parse::<u8>().ok())
                    .filter(|d| *d <= MAX_DECIMALS)
                {
                    Some(d) => Some(d),
                    None => {
                        return Err(BadFormat {
                            name: name.to_string(),
                            format: f.to_string(),
                            range: i..end + 1,
                        });
                    }
                },
            };
            out.push(Placeholder {
                name: known,
                decimals,
                range: i..end + 1,
            });
        }
        i = end + 1;
    }
    Ok(out)
}

/// `text` with each placeholder of `values` replaced by its number;
/// unknown braces are left as written. A placeholder whose format does
/// not read is left as written too (a loaded deck's never is).
pub fn fill(text: &str, values: &[(&str, f64)]) -> String {
    let names: Vec<&str> = values.iter().map(|(n, _)| *n).collect();
    replaced(text, &names, |p| {
        let v = values
            .iter()
            .find(|(n, _)| *n == p.name)
            .map_or(f64::NAN, |(_, v)| *v);
        shown(v, p.decimals)
    })
}

/// `text` with each placeholder of `names` shown as `blank` (the numbers
/// are not drawn yet).
pub fn blanked(text: &str, names: &[&str], blank: &str) -> String {
    replaced(text, names, |_| blank.to_string())
}

/// `text` with each placeholder of `names` replaced by `with` of it; as
/// written when a placeholder's format does not read.
fn replaced(text: &str, names: &[&str], with: impl Fn(&Placeholder) -> String) -> String {
    let Ok(found) = placeholders(text, names) else {
        return text.to_string();
    };
    let mut out = String::with_capacity(text.len() + 8 * found.len());
    let mut at = 0;
    for p in &found {
        out.push_str(&text[at..p.range.start]);
        out.push_str(&with(p));
        at = p.range.end;
    }
    out.push_str(&text[at..]);
    out
}

/// A drawn number as a placeholder shows it.
pub fn shown(v: f64, decimals: Option<u8>) -> String {
    match decimals {
        Some(d) => {
            let s = format!("{v:.*}", usize::from(d));
            // "-0" reads as a sign the number does not have.
            if s.trim_start_matches('-')
                .bytes()
                .all(|b| b == b'0' || b == b'.')
            {
                s.trim_start_matches('-').to_string()
            } else {
                s
            }
        }
        None => crate::num::show(v),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_known_names_are_placeholders() {
        let t = r"Released at {theta0:.0}° with $\sqrt{L/g}$ and $\frac{a}{b}$, L = {L} m";
        let found = placeholders(t, &["theta0", "L"]).unwrap();
        let names: Vec<_> = found.iter().map(|p| (p.name, p.decimals)).collect();
        assert_eq!(names, [("theta0", Some(0)), ("L", None)]);
        assert_eq!(
            fill(t, &[("theta0", 35.0), ("L", 1.25)]),
            r"Released at 35° with $\sqrt{L/g}$ and $\frac{a}{b}$, L = 1.25 m"
        );
    }

    #[test]
    fn formats_are_checked() {
        let e = placeholders("{L:x}", &["L"]).unwrap_err();
        assert_eq!(
            (e.name.as_str(), e.format.as_str(), e.range),
            ("L", "x", 0..5)
        );
        assert!(placeholders("{L:.13}", &["L"]).is_err());
        assert!(placeholders("{L:.12}", &["L"]).is_ok());
        // Unknown names are never errors, whatever follows them.
        assert!(placeholders("{M:zz}", &["L"]).unwrap().is_empty());
    }

    #[test]
    fn shown_numbers() {
        assert_eq!(shown(1.0 / 3.0, Some(2)), "0.33");
        assert_eq!(shown(-0.001, Some(1)), "0.0");
        assert_eq!(shown(2.5, None), "2.5");
        assert_eq!(fill("{a}{a:.1}{{a}}", &[("a", 2.0)]), "22.0{2}");
    }

    // Longer: PROPTEST_CASES=100000 cargo test -p flipcard-text fill::
    proptest::proptest! {
        #[test]
        fn any_text_fills_without_panicking(text in "\\PC{0,80}", v in -1e300f64..1e300) {
            let out = fill(&text, &[("a", v), ("theta0", v)]);
            // Text without braces is returned as it is.
            if !text.contains('{') {
                proptest::prop_assert_eq!(out, text);
            }
        }
    }
}
