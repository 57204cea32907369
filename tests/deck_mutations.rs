//! Property: whatever is done to a bundled deck's files, the loader never
//! panics, and every diagnostic points at a real place: an existing file,
//! a line of it (or the line after the last, for the end of the file) and
//! a column within that line (or just after its end).
//!
//! A bundled deck (`decks/torque-free-rotation.toml`, or
//! `decks/oscillations.toml` with its system scenes written as equations)
//! and its two content files are copied to a temporary folder with a few random mutations in some of
//! them — flipped bits, lines deleted, duplicated or swapped, the file cut
//! short, TOML fragments, quotes, brackets, escapes, huge numbers and
//! Unicode inserted anywhere or inside strings, values replaced — and
//! loaded through the library, as the app does.
//!
//! The default 512 cases take a few seconds in a debug build. For a longer
//! search set `PROPTEST_CASES` (a failure is shrunk, saved in
//! `tests/deck_mutations.proptest-regressions` and replayed first from then
//! on; commit that file with the fix):
//!
//! ```sh
//! PROPTEST_CASES=20000 cargo test --test main deck_mutations::
//! ```

use std::fs;
use std::path::{Path, PathBuf};

use proptest::prelude::*;
use proptest::sample::Index;

/// Cases run when `PROPTEST_CASES` is not set.
const DEFAULT_CASES: u32 = 256;

/// Each bundled deck: its deck file and its two content files.
const DECKS: [[&str; 3]; 4] = [
    [
        "decks/torque-free-rotation.toml",
        "content/torque-free-rotation/en.toml",
        "content/torque-free-rotation/hi-Latn.toml",
    ],
    [
        "decks/oscillations.toml",
        "content/oscillations/en.toml",
        "content/oscillations/hi-Latn.toml",
    ],
    [
        "decks/central-forces.toml",
        "content/central-forces/en.toml",
        "content/central-forces/hi-Latn.toml",
    ],
    [
        "decks/coupled-oscillators.toml",
        "content/coupled-oscillators/en.toml",
        "content/coupled-oscillators/hi-Latn.toml",
    ],
];

/// Pieces that reach the parser's and the validator's corners.
const FRAGMENTS: &[&str] = &[
    "[[card]]\n",
    "[[section]]\n",
    "[deck]\n",
    "[card]\n",
    "[prompt.answer]\n",
    "card = 5\n",
    "id = \"x\"\n",
    "a.b.c = 1\n",
    "= ",
    "=",
    "\"",
    "'",
    "'''",
    "\"\"\"",
    "[",
    "]",
    "{",
    "}",
    ",",
    ".",
    "#",
    "\\",
    "\\u",
    "\\u00e9",
    "\\uD800",
    "\\U0010FFFF",
    "\\U00110000",
    "\\x41",
    "1e999999",
    "-1e-999999",
    "99999999999999999999999999",
    "0x7fffffffffffffff",
    "nan",
    "-inf",
    "1979-05-27T07:32:00Z",
    "$",
    "$\\frac{",
    "\\omega_",
    "é",
    "中文",
    "😀",
    "\u{202e}",
    "\u{0}",
    "\u{7f}",
    "\r",
    "\r\n",
    "\t",
    "\n",
    "\u{feff}",
];

/// Values written over a key's value: types and ranges the checks see.
const VALUES: &[&str] = &[
    "\"\"",
    "\" \"",
    "0",
    "-1",
    "1e308",
    "-0.0",
    "true",
    "[]",
    "[1, 2]",
    "[0, 0, 0]",
    "[1.0, 2.0, 3.0, 4.0]",
    "[1e308, 1e308, 1e308]",
    "[-1, 2, 3]",
    "[1, 1, 2]",
    "[\"omega\", \"omega\"]",
    "[\"\"]",
    "{}",
    "{ en = '' }",
    "{ en = 'x', hi-Latn = 'y', fr = 'z' }",
    "{ rel = 0.1, abs = 0.1 }",
    "{ rel = -1 }",
    "\"choice\"",
    "\"number\"",
    "\"typed\"",
    "\"reversed\"",
    "\"flips\"",
    "\"flips >\"",
    "\"flips > 1e400\"",
    "\"flips => 1\"",
    "\"é > 1\"",
    "\" efold_time <= -0\"",
    "\"measure.flips == 2\"",
    "\"efold_time\"",
    "\"d\"",
    "'$\\frac{1}{'",
    "'$x$$'",
    "'\\\\'",
    "\"\\t\\u0007\"",
    "\"x\\u00e9y\"",
    "'''\n'''",
    "\"\"\"\n\\\n  \"\"\"",
];

#[derive(Debug, Clone)]
enum Mutation {
    FlipBit(Index, u8),
    DeleteLine(Index),
    DuplicateLine(Index),
    SwapLines(Index, Index),
    Truncate(Index),
    Insert(Index, String),
    /// Inserted just after one of the quotes, inside a string.
    InsertInString(Index, String),
    /// The value of one `key = value` line replaced.
    ReplaceValue(Index, String),
}

fn fragment() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => proptest::sample::select(FRAGMENTS).prop_map(str::to_string),
        1 => "\\PC{1,6}",
        1 => proptest::collection::vec(any::<char>(), 1..4)
            .prop_map(|cs| cs.into_iter().collect::<String>()),
    ]
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => proptest::sample::select(VALUES).prop_map(str::to_string),
        1 => fragment(),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        2 => (any::<Index>(), 0u8..8).prop_map(|(i, b)| Mutation::FlipBit(i, b)),
        2 => any::<Index>().prop_map(Mutation::DeleteLine),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
        4 => (any::<Index>(), fragment()).prop_map(|(i, f)| Mutation::Insert(i, f)),
        3 => (any::<Index>(), fragment()).prop_map(|(i, f)| Mutation::InsertInString(i, f)),
        3 => (any::<Index>(), value()).prop_map(|(i, v)| Mutation::ReplaceValue(i, v)),
    ]
}

/// The lines of `bytes`, each with its `\n`.
fn lines(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes
        .split_inclusive(|&b| b == b'\n')
        .map(<[u8]>::to_vec)
        .collect()
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    match m {
        Mutation::FlipBit(at, bit) if !bytes.is_empty() => {
            let i = at.index(bytes.len());
            bytes[i] ^= 1 << bit;
        }
        Mutation::DeleteLine(at) | Mutation::DuplicateLine(at) => {
            let mut ls = lines(bytes);
            if ls.is_empty() {
                return;
            }
            let i = at.index(ls.len());
            if matches!(m, Mutation::DeleteLine(_)) {
                ls.remove(i);
            } else {
                ls.insert(i, ls[i].clone());
            }
            *bytes = ls.concat();
        }
        Mutation::SwapLines(a, b) => {
            let mut ls = lines(bytes);
            if ls.is_empty() {
                return;
            }
            let (a, b) = (a.index(ls.len()), b.index(ls.len()));
            ls.swap(a, b);
            *bytes = ls.concat();
        }
        Mutation::Truncate(at) => {
            let len = at.index(bytes.len() + 1);
            bytes.truncate(len);
        }
        Mutation::Insert(at, text) => {
            let i = at.index(bytes.len() + 1);
            bytes.splice(i..i, text.bytes());
        }
        Mutation::InsertInString(at, text) => {
            let quotes: Vec<usize> = (0..bytes.len())
                .filter(|&i| matches!(bytes[i], b'\'' | b'"'))
                .collect();
            if quotes.is_empty() {
                return;
            }
            let i = quotes[at.index(quotes.len())] + 1;
            bytes.splice(i..i, text.bytes());
        }
        Mutation::ReplaceValue(at, value) => {
            let mut ls = lines(bytes);
            let with_value: Vec<usize> = (0..ls.len())
                .filter(|&i| ls[i].windows(3).any(|w| w == b" = "))
                .collect();
            if with_value.is_empty() {
                return;
            }
            let line = &mut ls[with_value[at.index(with_value.len())]];
            let eq = line.windows(3).position(|w| w == b" = ").unwrap_or(0);
            line.truncate(eq + 3);
            line.extend_from_slice(value.as_bytes());
            line.push(b'\n');
            *bytes = ls.concat();
        }
        Mutation::FlipBit(..) => {}
    }
}

fn bundled(rel: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every diagnostic's place, checked against the file as written.
fn check_locations(loaded: &flipcard::deck::Loaded) -> Result<(), TestCaseError> {
    for d in &loaded.diagnostics {
        let head = d.headline();
        let bytes =
            fs::read(&d.path).map_err(|e| TestCaseError::fail(format!("{head}: the file: {e}")))?;
        // Positions are counted in the text the loader read, which for
        // invalid UTF-8 is the valid part before the bad byte: the same
        // characters as the lossy text up to there.
        let text = String::from_utf8_lossy(&bytes);
        let file_lines: Vec<&str> = text.split('\n').collect();
        prop_assert!(d.line >= 1, "{head}: no line");
        prop_assert!(
            d.line <= file_lines.len(),
            "{head}: line past the end ({} lines)",
            file_lines.len()
        );
        let chars = file_lines[d.line - 1].chars().count();
        prop_assert!(
            d.col >= 1 && d.col <= chars + 1,
            "{head}: column outside the line ({chars} characters)"
        );
        prop_assert!(d.width >= 1, "{head}: no width");
    }
    Ok(())
}

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    ProptestConfig {
        cases,
        // Shrinking reloads the deck per step; keep a failure's report quick.
        max_shrink_iters: 256,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn mutated_decks_load_without_panics_and_with_real_locations(
        deck in 0..DECKS.len(),
        files in 1u8..8,
        mutations in proptest::collection::vec(mutation(), 1..5),
    ) {
        let dir = tempfile::tempdir().unwrap();
        for (i, rel) in DECKS[deck].iter().enumerate() {
            let mut bytes = bundled(rel);
            if files & (1 << i) != 0 {
                for m in &mutations {
                    apply(&mut bytes, m);
                }
            }
            let path: PathBuf = dir.path().join(rel);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(&path, bytes).unwrap();
        }
        let loaded = flipcard::deck::load_dir(&dir.path().join("decks"));
        check_locations(&loaded)?;
        // Rendering every diagnostic with its source line must not panic.
        let _ = loaded.render_all();
    }
}

/// The unmutated copy loads cleanly, so the failures above are the
/// mutations' doing.
#[test]
fn the_unmutated_copies_are_valid() {
    for files in DECKS {
        let dir = tempfile::tempdir().unwrap();
        for rel in files {
            let path = dir.path().join(rel);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(&path, bundled(rel)).unwrap();
        }
        let loaded = flipcard::deck::load_dir(&dir.path().join("decks"));
        assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
        assert_eq!(loaded.decks.len(), 1);
    }
}

/// A deck added to decks/ is mutated too.
#[test]
fn every_bundled_deck_is_covered() {
    let decks = Path::new(env!("CARGO_MANIFEST_DIR")).join("decks");
    let mut bundled: Vec<String> = fs::read_dir(&decks)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| format!("decks/{}", e.file_name().to_string_lossy()))
        .collect();
    bundled.sort();
    let mut covered: Vec<String> = DECKS.iter().map(|d| d[0].to_string()).collect();
    covered.sort();
    assert_eq!(bundled, covered);
}
