//! The layers as ARCHITECTURE.md draws them, checked on the source itself:
//! each layer uses only the ones listed before it (so there is no cycle
//! between them), only the terminal app draws, and only the commands and
//! the terminal app see the command line or print. The crates of the
//! workspace hold the coarse order (a crate cannot name one that depends
//! on it); this test holds the order of the layers inside a crate too.
//!
//! Test code (`src/**/tests/`, `#[cfg(test)]` blocks) may reach across
//! layers for fixtures and is not looked at; neither are comments.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Bottom to top: a module may use those before it.
const LAYERS: [&str; 14] = [
    "io", "text", "sim", "deck", "sched", "store", "predict", "catalog", "interop", "sync",
    "study", "bundled", "tui", "cmd",
];

/// The layers that are whole crates, by the name code calls them.
const CRATES: [(&str, &str); 3] = [
    ("io", "flipcard_io"),
    ("text", "flipcard_text"),
    ("sim", "flipcard_sim"),
];

/// The layers that are modules of `flipcard-core`.
const CORE: [&str; 8] = [
    "deck", "sched", "store", "predict", "catalog", "interop", "sync", "study",
];

/// Modules that compute and return values: no printing, no exiting, no
/// command line, no terminal.
const DOMAIN: [&str; 12] = [
    "io", "text", "sim", "deck", "sched", "store", "predict", "catalog", "interop", "sync",
    "study", "bundled",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn src() -> PathBuf {
    root().join("src")
}

/// The code of every non-test file of a layer, comments removed.
fn code_of(module: &str) -> Vec<(PathBuf, String)> {
    let mut files = Vec::new();
    if CRATES.iter().any(|(m, _)| *m == module) {
        collect(
            &root().join(format!("crates/flipcard-{module}/src")),
            &mut files,
        );
    } else {
        let dir = if CORE.contains(&module) {
            root().join("crates/flipcard-core/src")
        } else {
            src()
        };
        let single = dir.join(format!("{module}.rs"));
        if single.is_file() {
            files.push(single);
        }
        collect(&dir.join(module), &mut files);
    }
    files
        .into_iter()
        .map(|f| {
            let text = std::fs::read_to_string(&f).unwrap_or_default();
            (f, strip(&text))
        })
        .collect()
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if p.is_dir() {
            if name != "tests" {
                collect(&p, out);
            }
        } else if name.ends_with(".rs") && name != "tests.rs" && name != "testkit.rs" {
            out.push(p);
        }
    }
}

/// The code before the first `#[cfg(test)]`, without `//` comments.
fn strip(text: &str) -> String {
    let before_tests = text.split("#[cfg(test)]").next().unwrap_or("");
    before_tests
        .lines()
        .map(|l| match l.find("//") {
            // A `//` inside a string literal (a URL) is rare in this code
            // base; cutting there only loses text after it.
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The layers `code` names through `crate::` (including the grouped form
/// `crate::{a, b::c}`) or by their crate's name (`flipcard_sim::`).
fn uses(code: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for (module, krate) in CRATES {
        if code.contains(&format!("{krate}::")) {
            found.insert(module.to_string());
        }
    }
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    found.insert(name);
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                found.insert(name);
            }
        }
    }
    found
}

#[test]
fn every_top_level_module_has_a_layer() {
    let mut declared: BTreeSet<String> = BTreeSet::new();
    for lib in ["src/lib.rs", "crates/flipcard-core/src/lib.rs"] {
        let lib = std::fs::read_to_string(root().join(lib)).unwrap();
        declared.extend(
            lib.lines()
                .filter_map(|l| l.trim().strip_prefix("pub mod "))
                .map(|l| l.trim_end_matches(';').to_string()),
        );
    }
    let members = std::fs::read_dir(root().join("crates")).unwrap();
    for member in members.flatten() {
        let name = member.file_name().to_string_lossy().into_owned();
        if let Some(layer) = name.strip_prefix("flipcard-")
            && layer != "core"
        {
            declared.insert(layer.to_string());
        }
    }
    let declared: BTreeSet<&str> = declared.iter().map(String::as_str).collect();
    let layered: BTreeSet<&str> = LAYERS.into_iter().collect();
    assert_eq!(
        declared, layered,
        "the crates and lib.rs files and the layers differ: place a new module in LAYERS and ARCHITECTURE.md"
    );
}

#[test]
fn modules_use_only_the_layers_below_them() {
    let mut graph: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
    let mut wrong = Vec::new();
    for (rank, module) in LAYERS.iter().enumerate() {
        let below: BTreeSet<&str> = LAYERS[..rank].iter().copied().collect();
        for (file, code) in code_of(module) {
            for used in uses(&code) {
                if used != *module && LAYERS.contains(&used.as_str()) {
                    if !below.contains(used.as_str()) {
                        wrong.push(format!("{}: {module} uses {used}", file.display()));
                    }
                    graph.entry(module).or_default().insert(used);
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "dependencies against the layers:\n{}",
        wrong.join("\n")
    );
    // Which also means no cycle; said outright, for the reader of a failure.
    for (module, used) in &graph {
        for u in used {
            let back = graph.get(u.as_str()).is_some_and(|s| s.contains(*module));
            assert!(!back, "{module} and {u} use each other");
        }
    }
}

#[test]
fn only_the_terminal_app_draws() {
    for module in LAYERS.iter().filter(|m| **m != "tui") {
        for (file, code) in code_of(module) {
            for lib in ["ratatui::", "crossterm::"] {
                assert!(
                    !code.contains(lib),
                    "{} uses {lib}: only tui draws",
                    file.display()
                );
            }
        }
    }
}

#[test]
fn domain_modules_never_see_the_command_line_print_or_exit() {
    let forbidden = [
        "cmd::",
        "Cli",
        "println!",
        "print!(",
        "eprintln!",
        "eprint!(",
        "errln!",
        "outln!",
        "out!(",
        "process::exit",
        "std::io::stdout",
        "std::io::stderr",
    ];
    for module in DOMAIN {
        for (file, code) in code_of(module) {
            for f in forbidden {
                assert!(
                    !code.contains(f),
                    "{} contains `{f}`: domain modules return values and typed errors",
                    file.display()
                );
            }
        }
    }
}

/// Every file operation goes through `io`, where the disciplines live
/// (regular files only, whole replacements, one fsync rule).
#[test]
fn only_io_touches_the_file_system() {
    let mut wrong = Vec::new();
    for module in LAYERS.iter().filter(|m| **m != "io") {
        for (file, code) in code_of(module) {
            for f in ["std::fs", "fs::File", "fs::OpenOptions", "rustix::fs"] {
                if code.contains(f) {
                    wrong.push(format!("{} uses `{f}`", file.display()));
                }
            }
            if code
                .lines()
                .any(|l| l.trim_start().starts_with("use std::{") && l.contains(" fs"))
            {
                wrong.push(format!("{} imports std's fs", file.display()));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "file operations outside io (use crate::io):\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_checker_sees_what_it_should() {
    // The checks above pass vacuously if these helpers find nothing.
    let found =
        uses("use crate::{sim::Method, text}; let x = crate::deck::load(p); flipcard_io::open");
    assert_eq!(
        found,
        ["deck", "io", "sim", "text"]
            .map(String::from)
            .into_iter()
            .collect()
    );
    assert!(strip("a // crate::cmd\n#[cfg(test)]\ncrate::tui").trim() == "a");
    assert!(code_of("sim").len() > 20, "the sim sources were not found");
    assert!(
        code_of("store").len() > 10,
        "the store sources were not found"
    );
    assert!(code_of("tui").len() > 20, "the tui sources were not found");
}
