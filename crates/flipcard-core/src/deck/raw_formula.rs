//! The raw stage's named tables and the key of a formula answer, below
//! `raw` and `raw_derivation` (both read a formula key: a formula card or
//! answer, and a derivation step's formula ask): a table of named values
//! in the order written (`params = { g = 9.81 }`, `vars = { x = [1, 2] }`)
//! and a formula's `expected` with its `vars`.

use super::read::{self, Fields, List, Num, Span, Str};
use super::report::FileReport;

/// A named value of a table written inline (`params = { g = 9.81 }`), the
/// key with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry<T> {
    pub key: Str,
    pub value: T,
}

/// A table of named values, in the order written.
#[derive(Debug, Clone, PartialEq)]
pub struct Named<T> {
    pub entries: Vec<Entry<T>>,
    pub span: Span,
}

/// The key of a formula answer as written: the expected formula and
/// `vars = { I1 = [1, 3], … }`, each variable's interval.
#[derive(Debug, Clone, PartialEq)]
pub struct RawFormula {
    pub span: Span,
    pub expected: Option<Str>,
    pub vars: Option<Named<List<Num>>>,
}

/// `expected` and `vars` of a formula card or answer.
pub(crate) fn read_formula(rep: &mut FileReport, f: &Fields, span: Span) -> RawFormula {
    RawFormula {
        span,
        expected: f.string(rep, "expected", true),
        vars: f.require(rep, "vars").and_then(|_| {
            named(rep, f, "vars", |rep, v, what| {
                let arr = read::array(rep, v, what)?;
                let items = arr
                    .iter()
                    .map(|n| read::number(rep, n, &format!("each end of {what}")))
                    .collect::<Option<Vec<_>>>()?;
                Some(List {
                    items,
                    span: v.span(),
                })
            })
        }),
    }
}

/// An optional inline table of named values, in the order written.
pub(crate) fn named<T>(
    rep: &mut FileReport,
    f: &Fields,
    key: &str,
    value: impl Fn(&mut FileReport, &read::Value, &str) -> Option<T>,
) -> Option<Named<T>> {
    let v = f.get(key)?;
    let t = read::table(rep, v, &format!("`{key}`"))?;
    let mut entries = Vec::new();
    let mut ok = true;
    for (k, item) in t.iter() {
        let name = Str {
            value: k.get_ref().to_string(),
            span: k.span(),
        };
        match value(rep, item, &format!("`{}` in `{key}`", name.value)) {
            Some(value) => entries.push(Entry { key: name, value }),
            None => ok = false,
        }
    }
    // The table keeps keys sorted; the author's order is the source order.
    entries.sort_by_key(|e| e.key.span.start);
    ok.then_some(Named {
        entries,
        span: v.span(),
    })
}
