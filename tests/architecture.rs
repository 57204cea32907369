//! The layers of the source as ARCHITECTURE.md draws them, checked on the
//! source itself: each top-level module uses only the ones listed before it
//! (so there is no cycle between them), the modules inside any folder use
//! each other one way only (no import cycle among siblings), only the
//! terminal app uses ratatui or crossterm, only the commands and the
//! terminal app print, and only `io` touches the file system.
//!
//! The sources are `src/` and, once the workspace has them, each crate's
//! `crates/*/src/`. Test code (modules declared under `#[cfg(test)]`, such
//! as `tests.rs` and `tests/`, and `#[cfg(test)]` items) may reach across
//! layers for fixtures and is not looked at; neither are comments or the
//! insides of string literals.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Bottom to top: a module may use those before it.
const LAYERS: [&str; 14] = [
    "io", "text", "sim", "deck", "sched", "store", "predict", "catalog", "interop", "sync",
    "study", "bundled", "tui", "cmd",
];

/// The layers that are whole crates, by the name code calls them. (The
/// layers of `flipcard-core` and of the app crate are its top-level
/// modules.)
const CRATES: [(&str, &str); 3] = [
    ("io", "flipcard_io"),
    ("text", "flipcard_text"),
    ("sim", "flipcard_sim"),
];

/// Modules that compute and return values: no printing, no exiting, no
/// command line, no terminal.
const DOMAIN: [&str; 12] = [
    "io", "text", "sim", "deck", "sched", "store", "predict", "catalog", "interop", "sync",
    "study", "bundled",
];

/// The top-level modules that may print: the commands and the terminal app
/// (and the binary's `main.rs`).
const PRINTING: [&str; 2] = ["cmd", "tui"];

/// The top-level module that may use ratatui and crossterm.
const TERMINAL: &str = "tui";

fn manifest() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn src() -> PathBuf {
    manifest().join("src")
}

/// The source folders: `src/`, then each workspace crate's `src/`.
fn roots() -> Vec<PathBuf> {
    let mut roots = vec![src()];
    if let Ok(crates) = std::fs::read_dir(manifest().join("crates")) {
        let mut found: Vec<PathBuf> = crates
            .flatten()
            .map(|e| e.path().join("src"))
            .filter(|p| p.is_dir())
            .collect();
        found.sort();
        roots.extend(found);
    }
    roots.retain(|r| r.is_dir());
    roots
}

/// One non-test source file.
struct Source {
    /// The source folder it is in (`src/`, `crates/x/src/`).
    root: PathBuf,
    /// Its path inside the root, e.g. `store/log.rs`.
    rel: PathBuf,
    /// Its module path from the crate root: `store/log.rs` and
    /// `store/log/mod.rs` are `["store", "log"]`, `lib.rs` is `[]`.
    module: Vec<String>,
    /// Its code: comments and `#[cfg(test)]` items removed, the insides of
    /// string and character literals blanked, lines kept.
    code: String,
}

impl Source {
    fn top(&self) -> Option<&str> {
        self.module.first().map(String::as_str)
    }

    /// The layer it belongs to: the crate's, for a crate that is one layer;
    /// else its top-level module's.
    fn layer(&self) -> Option<&str> {
        for (layer, _) in CRATES {
            if self.root.ends_with(format!("crates/flipcard-{layer}/src")) {
                return Some(layer);
            }
        }
        self.top()
    }

    /// The binary's entry point, which may print.
    fn is_main(&self) -> bool {
        self.rel == Path::new("main.rs")
    }

    fn show(&self) -> String {
        let shown = self.root.strip_prefix(manifest()).unwrap_or(&self.root);
        shown.join(&self.rel).display().to_string()
    }

    /// `path:line`.
    fn at(&self, line: usize) -> String {
        format!("{}:{line}", self.show())
    }
}

/// Every non-test source file of every root, read once for all the tests.
fn sources() -> &'static [Source] {
    static SOURCES: OnceLock<Vec<Source>> = OnceLock::new();
    SOURCES.get_or_init(|| {
        roots()
            .into_iter()
            .flat_map(|root| {
                let mut files = Vec::new();
                collect(&root, &root, &mut files);
                sources_of(&root, files)
            })
            .collect()
    })
}

/// Every `.rs` file under `dir`, with its path inside `root` and its text.
fn collect(root: &Path, dir: &Path, out: &mut Vec<(PathBuf, String)>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect(root, &p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&p).unwrap_or_default();
            let rel = p.strip_prefix(root).unwrap_or(&p).to_path_buf();
            out.push((rel, text));
        }
    }
}

/// The module path of a file inside its root: `store/log.rs` and
/// `store/log/mod.rs` are `store::log`; the crate roots (`lib.rs`,
/// `main.rs`) are the empty path.
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    if let Some(last) = parts.last_mut() {
        *last = last.trim_end_matches(".rs").to_string();
    }
    let root_file = parts.len() == 1 && (parts[0] == "lib" || parts[0] == "main");
    if root_file || parts.last().is_some_and(|l| l == "mod") {
        parts.pop();
    }
    parts
}

/// The files of one root as sources, leaving out every module declared
/// under `#[cfg(test)]` (`#[cfg(test)] mod tests;`) and all below it.
fn sources_of(root: &Path, files: Vec<(PathBuf, String)>) -> Vec<Source> {
    let mut test_modules: BTreeSet<Vec<String>> = BTreeSet::new();
    for (rel, text) in &files {
        let module = module_of(rel);
        for name in test_module_names(&clean(text)) {
            let mut m = module.clone();
            m.push(name);
            test_modules.insert(m);
        }
    }
    files
        .into_iter()
        .filter_map(|(rel, text)| {
            let module = module_of(&rel);
            let under_test = (1..=module.len()).any(|n| test_modules.contains(&module[..n]));
            (!under_test).then(|| Source {
                root: root.to_path_buf(),
                code: code(&text),
                module,
                rel,
            })
        })
        .collect()
}

/// `text` without comments, with the insides of string and character
/// literals blanked; every newline is kept, so lines still count right.
fn clean(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let n = b.len();
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < n {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < n && b[i] != '\n' {
                i += 1;
            }
            continue;
        }
        if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < n {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
            continue;
        }
        let starts_word = i == 0 || !ident(b[i - 1]);
        // Raw strings: r"…", r#"…"#, br"…", cr"…".
        if starts_word && (c == 'r' || ((c == 'b' || c == 'c') && next == Some('r'))) {
            let mut j = i + if c == 'r' { 1 } else { 2 };
            let mut hashes = 0;
            while j < n && b[j] == '#' {
                hashes += 1;
                j += 1;
            }
            if j < n && b[j] == '"' {
                out.extend(&b[i..=j]);
                j += 1;
                while j < n {
                    let closes = b[j] == '"' && (1..=hashes).all(|k| b.get(j + k) == Some(&'#'));
                    if closes {
                        out.push('"');
                        out.extend(std::iter::repeat_n('#', hashes));
                        j += 1 + hashes;
                        break;
                    }
                    out.push(blank(b[j]));
                    j += 1;
                }
                i = j;
                continue;
            }
        }
        if c == '"' {
            out.push('"');
            i += 1;
            while i < n {
                match b[i] {
                    '\\' => {
                        out.push(' ');
                        i += 1;
                        if i < n {
                            out.push(blank(b[i]));
                            i += 1;
                        }
                    }
                    '"' => {
                        out.push('"');
                        i += 1;
                        break;
                    }
                    other => {
                        out.push(blank(other));
                        i += 1;
                    }
                }
            }
            continue;
        }
        if c == '\'' {
            // A character literal ('x', '\n', '\u{1F600}', '\''), else a
            // lifetime or a label ('a).
            if next == Some('\\') {
                out.push('\'');
                i += 3;
                while i < n && b[i] != '\'' && b[i] != '\n' {
                    i += 1;
                }
                out.push_str("  '");
                i += 1;
                continue;
            }
            if b.get(i + 2) == Some(&'\'') {
                out.push_str("' '");
                i += 3;
                continue;
            }
        }
        out.push(c);
        i += 1;
    }
    out
}

/// Where the item after the attribute ending at `from` ends: after its
/// first `;` or its first block, outside brackets.
fn item_end(code: &[char], mut from: usize) -> usize {
    let mut depth = 0usize;
    while from < code.len() {
        match code[from] {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' => depth = depth.saturating_sub(1),
            '}' => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return from + 1;
                }
            }
            ';' if depth == 0 => return from + 1,
            _ => {}
        }
        from += 1;
    }
    code.len()
}

const CFG_TEST: &str = "#[cfg(test)]";

/// The spans of cleaned `code` that only tests compile: each item under
/// `#[cfg(test)]`, from the attribute to the item's end.
fn test_spans(code: &str) -> Vec<(usize, usize)> {
    let chars: Vec<char> = code.chars().collect();
    let text: String = chars.iter().collect();
    let mut spans = Vec::new();
    let mut search = 0;
    while let Some(found) = text[search..].find(CFG_TEST) {
        // Byte offset to char offset (the cleaned code keeps non-ASCII
        // characters outside literals, in names).
        let start = text[..search + found].chars().count();
        let end = item_end(&chars, start + CFG_TEST.chars().count());
        spans.push((start, end));
        search = text
            .char_indices()
            .nth(end)
            .map_or(text.len(), |(byte, _)| byte);
    }
    spans
}

/// The names of the modules `code` declares under `#[cfg(test)]` in a
/// file of their own (`#[cfg(test)] mod tests;`).
fn test_module_names(code: &str) -> Vec<String> {
    let chars: Vec<char> = code.chars().collect();
    test_spans(code)
        .into_iter()
        .filter_map(|(start, end)| {
            let item: String = chars[start..end].iter().collect();
            let tokens: Vec<String> = tokens(&item).into_iter().map(|(t, _)| t).collect();
            let at = tokens.iter().position(|t| t == "mod")?;
            (tokens.last().map(String::as_str) == Some(";")).then(|| tokens.get(at + 1).cloned())?
        })
        .collect()
}

/// What the checks read of a file: comments and `#[cfg(test)]` items
/// removed, literals blanked, lines kept.
fn code(text: &str) -> String {
    let cleaned = clean(text);
    let mut chars: Vec<char> = cleaned.chars().collect();
    for (start, end) in test_spans(&cleaned) {
        for c in &mut chars[start..end] {
            if *c != '\n' {
                *c = ' ';
            }
        }
    }
    chars.into_iter().collect()
}

/// The tokens of cleaned code with their lines: names (`r#type` as
/// `type`), `::`, `!=`, and single characters otherwise; numbers and
/// literals count as names or characters, which no check looks for.
fn tokens(code: &str) -> Vec<(String, usize)> {
    let b: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_alphanumeric() || c == '_' {
            let start = i;
            while i < b.len() && (b[i].is_alphanumeric() || b[i] == '_') {
                i += 1;
            }
            let mut word: String = b[start..i].iter().collect();
            if word == "r" && b.get(i) == Some(&'#') {
                let after = i + 1;
                let mut j = after;
                while j < b.len() && (b[j].is_alphanumeric() || b[j] == '_') {
                    j += 1;
                }
                if j > after {
                    word = b[after..j].iter().collect();
                    i = j;
                }
            }
            out.push((word, line));
        } else if c == ':' && b.get(i + 1) == Some(&':') {
            out.push(("::".to_string(), line));
            i += 2;
        } else if c == '!' && b.get(i + 1) == Some(&'=') {
            out.push(("!=".to_string(), line));
            i += 2;
        } else {
            out.push((c.to_string(), line));
            i += 1;
        }
    }
    out
}

/// A path named in code, resolved from the crate root, and its line.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Named {
    path: Vec<String>,
    line: usize,
    /// The name a `use … as name` gives it.
    alias: Option<String>,
    /// Whether it is a glob's module (`use path::*`).
    glob: bool,
}

impl Named {
    fn new(path: Vec<String>, line: usize) -> Named {
        Named {
            path,
            line,
            alias: None,
            glob: false,
        }
    }
}

/// Every path that code in `module` names through `crate::`, `$crate::`,
/// `super::` or `self::`, resolved from the crate root, the groups of a
/// `use` expanded (`use crate::{a::{b, c}, d}` names `a::b`, `a::c` and
/// `d`; a glob names the module it is taken from).
fn paths(code: &str, module: &[String]) -> Vec<Named> {
    let toks = tokens(code);
    let mut out = Vec::new();
    for k in 0..toks.len() {
        let t = toks[k].0.as_str();
        let starts = matches!(t, "crate" | "super" | "self")
            && toks.get(k + 1).is_some_and(|n| n.0 == "::")
            && (k == 0 || toks[k - 1].0 != "::");
        if starts {
            tree(&toks, k, module.to_vec(), &mut out);
        }
    }
    out
}

/// Reads the use tree (or path) at `toks[k]` under `prefix`, adding the
/// paths it names to `out`; returns the index after it.
fn tree(
    toks: &[(String, usize)],
    mut k: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Named>,
) -> usize {
    loop {
        let Some((t, line)) = toks.get(k) else {
            return k;
        };
        match t.as_str() {
            "{" => {
                k += 1;
                while k < toks.len() && toks[k].0 != "}" {
                    k = tree(toks, k, prefix.clone(), out);
                    // Skip `as name` and anything else up to the next item.
                    while k < toks.len() && toks[k].0 != "," && toks[k].0 != "}" {
                        k += 1;
                    }
                    if toks.get(k).is_some_and(|t| t.0 == ",") {
                        k += 1;
                    }
                }
                return k + 1;
            }
            "*" => {
                out.push(Named {
                    glob: true,
                    ..Named::new(prefix, *line)
                });
                return k + 1;
            }
            word if word
                .chars()
                .next()
                .is_some_and(|c| c.is_alphabetic() || c == '_') =>
            {
                match word {
                    "crate" => prefix.clear(),
                    "super" => {
                        prefix.pop();
                    }
                    "self" => {}
                    _ => prefix.push(word.to_string()),
                }
                if toks.get(k + 1).is_some_and(|n| n.0 == "::") {
                    k += 2;
                } else {
                    let alias = toks
                        .get(k + 1)
                        .filter(|t| t.0 == "as")
                        .and_then(|_| toks.get(k + 2))
                        .map(|t| t.0.clone());
                    out.push(Named {
                        alias,
                        ..Named::new(prefix, *line)
                    });
                    return k + 1;
                }
            }
            _ => {
                // `crate::f::<T>`: the path ends before the generics.
                out.push(Named::new(prefix, *line));
                return k;
            }
        }
    }
}

/// What modules re-export (`pub use child::Item;`, `pub use run::*;`), so
/// that a path through a re-export counts where the item is defined: a
/// module using `super::Store` uses the sibling that defines `Store`.
struct Reexports {
    modules: BTreeSet<Vec<String>>,
    /// (module, name) → the path it re-exports under that name.
    named: BTreeMap<(Vec<String>, String), Vec<String>>,
    /// module → the modules whose public items it re-exports by a glob.
    globs: BTreeMap<Vec<String>, Vec<Vec<String>>>,
    /// module → the names of the public items it defines.
    defined: BTreeMap<Vec<String>, BTreeSet<String>>,
}

impl Reexports {
    fn of(files: &[&Source]) -> Reexports {
        let mut r = Reexports {
            modules: files.iter().map(|s| s.module.clone()).collect(),
            named: BTreeMap::new(),
            globs: BTreeMap::new(),
            defined: BTreeMap::new(),
        };
        for s in files {
            let toks = tokens(&s.code);
            for k in (0..toks.len()).filter(|&k| toks[k].0 == "pub") {
                // `pub(crate)`, `pub(super)`, `pub(in …)`.
                let mut j = k + 1;
                if toks.get(j).is_some_and(|t| t.0 == "(") {
                    while j < toks.len() && toks[j].0 != ")" {
                        j += 1;
                    }
                    j += 1;
                }
                while toks.get(j).is_some_and(|t| {
                    matches!(t.0.as_str(), "async" | "unsafe" | "const" | "extern")
                }) && toks
                    .get(j + 1)
                    .is_some_and(|t| matches!(t.0.as_str(), "fn" | "unsafe" | "extern"))
                {
                    j += 1;
                }
                let Some((keyword, _)) = toks.get(j) else {
                    continue;
                };
                match keyword.as_str() {
                    "use" => {
                        let mut found = Vec::new();
                        tree(&toks, j + 1, s.module.clone(), &mut found);
                        for n in found {
                            if n.glob {
                                r.globs.entry(s.module.clone()).or_default().push(n.path);
                            } else if let Some(name) = n.alias.clone().or(n.path.last().cloned()) {
                                r.named.insert((s.module.clone(), name), n.path);
                            }
                        }
                    }
                    "fn" | "struct" | "enum" | "static" | "const" | "type" | "trait" | "mod"
                    | "union" => {
                        if let Some((name, _)) = toks.get(j + 1) {
                            r.defined
                                .entry(s.module.clone())
                                .or_default()
                                .insert(name.clone());
                        }
                    }
                    _ => {}
                }
            }
        }
        r
    }

    /// `path` followed through the re-exports on it to the module that
    /// defines the item (a few steps at most; a loop stops where it is).
    fn resolve(&self, mut path: Vec<String>) -> Vec<String> {
        for _ in 0..8 {
            let Some(n) = (0..=path.len())
                .rev()
                .find(|&n| self.modules.contains(&path[..n]))
            else {
                return path;
            };
            let Some(name) = path.get(n) else {
                return path;
            };
            let module = path[..n].to_vec();
            let next = if let Some(target) = self.named.get(&(module.clone(), name.clone())) {
                target.iter().chain(&path[n + 1..]).cloned().collect()
            } else {
                let glob = self.globs.get(&module).and_then(|from| {
                    from.iter().find(|g| {
                        self.defined.get(*g).is_some_and(|d| d.contains(name))
                            || self.named.contains_key(&((*g).clone(), name.clone()))
                    })
                });
                match glob {
                    Some(g) => g.iter().chain(&path[n..]).cloned().collect(),
                    None => return path,
                }
            };
            if next == path {
                return path;
            }
            path = next;
        }
        path
    }
}

/// One dependency between two modules of one folder, and what shows it.
#[derive(Debug, Clone)]
struct Edge {
    from: Vec<String>,
    to: Vec<String>,
    /// `file:line` and the path named there.
    evidence: String,
}

/// The dependencies between sibling modules (files and folders of one
/// folder) among the sources of one crate: a file in `a/b/` naming
/// something in `a/c/` makes `a::b` use `a::c`. A module using its own
/// parent or children is no such edge.
fn sibling_edges(files: &[&Source]) -> Vec<Edge> {
    let mut edges = Vec::new();
    let modules: BTreeSet<&[String]> = files.iter().map(|s| s.module.as_slice()).collect();
    let reexports = Reexports::of(files);
    for s in files {
        for mut named in paths(&s.code, &s.module) {
            named.path = reexports.resolve(named.path);
            let Some(target) = (0..=named.path.len())
                .rev()
                .map(|n| &named.path[..n])
                .find(|p| modules.contains(p))
            else {
                continue;
            };
            let common = s
                .module
                .iter()
                .zip(target)
                .take_while(|(a, b)| a == b)
                .count();
            if common < s.module.len() && common < target.len() {
                edges.push(Edge {
                    from: s.module[..=common].to_vec(),
                    to: target[..=common].to_vec(),
                    evidence: format!("{} `{}`", s.at(named.line), named.path.join("::")),
                });
            }
        }
    }
    edges
}

/// The sources of each crate (each root), apart.
fn crates(sources: &[Source]) -> BTreeMap<String, Vec<&Source>> {
    let mut by_root: BTreeMap<String, Vec<&Source>> = BTreeMap::new();
    for s in sources {
        let root = s.root.strip_prefix(manifest()).unwrap_or(&s.root);
        by_root
            .entry(root.display().to_string())
            .or_default()
            .push(s);
    }
    by_root
}

/// The groups of modules that use each other round a cycle (strongly
/// connected components of more than one module), each sorted, with the
/// edges inside the group.
fn cycles(edges: &[Edge]) -> Vec<(Vec<Vec<String>>, Vec<Edge>)> {
    let mut graph: BTreeMap<&Vec<String>, BTreeSet<&Vec<String>>> = BTreeMap::new();
    for e in edges {
        graph.entry(&e.from).or_default().insert(&e.to);
        graph.entry(&e.to).or_default();
    }
    // Tarjan's algorithm.
    struct Walk<'a> {
        graph: &'a BTreeMap<&'a Vec<String>, BTreeSet<&'a Vec<String>>>,
        index: BTreeMap<&'a Vec<String>, usize>,
        low: BTreeMap<&'a Vec<String>, usize>,
        stack: Vec<&'a Vec<String>>,
        on_stack: BTreeSet<&'a Vec<String>>,
        found: Vec<Vec<Vec<String>>>,
    }
    impl<'a> Walk<'a> {
        fn visit(&mut self, v: &'a Vec<String>) {
            let i = self.index.len();
            self.index.insert(v, i);
            self.low.insert(v, i);
            self.stack.push(v);
            self.on_stack.insert(v);
            for &w in &self.graph[v] {
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(lw);
                } else if self.on_stack.contains(w) {
                    let iw = self.index[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(iw);
                }
            }
            if self.low[v] == self.index[v] {
                let mut group = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack.remove(w);
                    group.push(w.clone());
                    if w == v {
                        break;
                    }
                }
                if group.len() > 1 {
                    group.sort();
                    self.found.push(group);
                }
            }
        }
    }
    let mut walk = Walk {
        graph: &graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !walk.index.contains_key(v) {
            walk.visit(v);
        }
    }
    let mut found = walk.found;
    found.sort();
    found
        .into_iter()
        .map(|group| {
            let inside: Vec<Edge> = edges
                .iter()
                .filter(|e| group.contains(&e.from) && group.contains(&e.to))
                .cloned()
                .collect();
            (group, inside)
        })
        .collect()
}

/// A cycle as a failure says it: the folder (from the crate's `root`), the
/// modules, and for each dependency inside it the first place that shows
/// it.
fn describe(root: &str, group: &[Vec<String>], inside: &[Edge]) -> String {
    let folder: Vec<&str> = std::iter::once(root)
        .chain(group[0][..group[0].len() - 1].iter().map(String::as_str))
        .collect();
    let names: Vec<&str> = group.iter().map(|m| m[m.len() - 1].as_str()).collect();
    let mut text = format!("in {}/: {}", folder.join("/"), names.join(" <-> "));
    let mut shown: BTreeSet<(&Vec<String>, &Vec<String>)> = BTreeSet::new();
    let mut sorted: Vec<&Edge> = inside.iter().collect();
    sorted.sort_by(|a, b| (&a.from, &a.to, &a.evidence).cmp(&(&b.from, &b.to, &b.evidence)));
    for e in sorted {
        if shown.insert((&e.from, &e.to)) {
            text.push_str(&format!(
                "\n    {} -> {}: {}",
                e.from[e.from.len() - 1],
                e.to[e.to.len() - 1],
                e.evidence
            ));
        }
    }
    text
}

/// The non-test code of every file of a top-level module.
fn code_of(module: &str) -> Vec<(String, &'static str)> {
    sources()
        .iter()
        .filter(|s| s.layer() == Some(module))
        .map(|s| (s.show(), s.code.as_str()))
        .collect()
}

/// The top-level modules `code` in `module` names, and the layers that
/// are crates it names by their crate's name (`flipcard_sim::`).
fn uses(code: &str, module: &[String]) -> BTreeSet<String> {
    let mut found: BTreeSet<String> = paths(code, module)
        .into_iter()
        .filter_map(|n| n.path.first().cloned())
        .collect();
    for (layer, krate) in CRATES {
        if code.contains(&format!("{krate}::")) {
            found.insert(layer.to_string());
        }
    }
    found
}

#[test]
fn every_top_level_module_has_a_layer() {
    let mut declared: BTreeSet<String> = BTreeSet::new();
    for lib in ["src/lib.rs", "crates/flipcard-core/src/lib.rs"] {
        let lib = std::fs::read_to_string(manifest().join(lib)).unwrap();
        declared.extend(
            lib.lines()
                .filter_map(|l| l.trim().strip_prefix("pub mod "))
                .map(|l| l.trim_end_matches(';').to_string()),
        );
    }
    let members = std::fs::read_dir(manifest().join("crates")).unwrap();
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
    let sources = sources();
    for (rank, module) in LAYERS.iter().enumerate() {
        let below: BTreeSet<&str> = LAYERS[..rank].iter().copied().collect();
        for s in sources.iter().filter(|s| s.layer() == Some(module)) {
            for used in uses(&s.code, &s.module) {
                if used != *module && LAYERS.contains(&used.as_str()) {
                    if !below.contains(used.as_str()) {
                        wrong.push(format!("{}: {module} uses {used}", s.show()));
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

/// Inside every folder the modules use each other one way: the shared
/// piece sits in the lower module (or a small one both use), so a module
/// can be read, tested and moved with only what is below it.
#[test]
fn no_import_cycle_inside_a_folder() {
    let mut found = Vec::new();
    for (root, files) in crates(sources()) {
        for (group, inside) in cycles(&sibling_edges(&files)) {
            found.push(describe(&root, &group, &inside));
        }
    }
    assert!(
        found.is_empty(),
        "{} import cycle(s) among the modules of one folder; move what both \
         sides need into the lower module or a small one both use:\n{}",
        found.len(),
        found.join("\n")
    );
}

/// The places in `s` that print: the print macros (ours included),
/// `dbg!`, and the standard streams (`std::io::stdout`, `io::stderr()`,
/// `Stdout`); `.stdout(…)` of a `Command` is not printing.
fn printing(s: &Source) -> Vec<String> {
    const MACROS: [&str; 8] = [
        "println", "print", "eprintln", "eprint", "dbg", "out", "outln", "errln",
    ];
    const STREAMS: [&str; 4] = ["stdout", "stderr", "Stdout", "Stderr"];
    let toks = tokens(&s.code);
    let mut found = Vec::new();
    for (k, (t, line)) in toks.iter().enumerate() {
        let after = toks.get(k + 1).map(|n| n.0.as_str());
        let before = k.checked_sub(1).map(|p| toks[p].0.as_str());
        if MACROS.contains(&t.as_str()) && after == Some("!") {
            found.push(format!("{} `{t}!`", s.at(*line)));
        }
        if STREAMS.contains(&t.as_str()) && before != Some(".") {
            found.push(format!("{} `{t}`", s.at(*line)));
        }
    }
    found
}

/// Only the front ends say things: everything below returns values and
/// typed errors, and the command or the screen decides how to show them.
#[test]
fn only_the_commands_and_the_terminal_app_print() {
    let wrong: Vec<String> = sources()
        .iter()
        .filter(|s| !s.is_main() && !s.layer().is_some_and(|t| PRINTING.contains(&t)))
        .flat_map(printing)
        .collect();
    assert!(
        wrong.is_empty(),
        "printing outside cmd and tui (return the text or a typed error instead):\n{}",
        wrong.join("\n")
    );
}

/// The places in `s` that name ratatui or crossterm.
fn terminal_uses(s: &Source) -> Vec<String> {
    tokens(&s.code)
        .into_iter()
        .filter(|(t, _)| t == "ratatui" || t == "crossterm")
        .map(|(t, line)| format!("{} `{t}`", s.at(line)))
        .collect()
}

/// Only the terminal app draws or reads keys; the commands print lines
/// (they have never needed ratatui, so they get no exception).
#[test]
fn only_the_terminal_app_uses_ratatui_or_crossterm() {
    let wrong: Vec<String> = sources()
        .iter()
        .filter(|s| s.layer() != Some(TERMINAL))
        .flat_map(terminal_uses)
        .collect();
    assert!(
        wrong.is_empty(),
        "ratatui or crossterm outside tui:\n{}",
        wrong.join("\n")
    );
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
                    "{file} contains `{f}`: domain modules return values and typed errors",
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
                    wrong.push(format!("{file} uses `{f}`"));
                }
            }
            if code
                .lines()
                .any(|l| l.trim_start().starts_with("use std::{") && l.contains(" fs"))
            {
                wrong.push(format!("{file} imports std's fs"));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "file operations outside io (use crate::io):\n{}",
        wrong.join("\n")
    );
}

/// The files under `crates/` that may read the environment, and why. The
/// app's clock (`FLIPCARD_NOW`) is read by the app (`cmd::clock`) and
/// handed to the library as a `Clock` or a time, so the library's tests and
/// the in-process tests run the same whatever the shell exports.
const ENV_READERS: [(&str, &str); 1] = [(
    "crates/flipcard-core/src/sched/config.rs",
    "`~` in deck_paths and sync_dir is $HOME, as a shell expands it; not a clock",
)];

/// The places in `s` that read the environment (`env::var`, `var_os`,
/// `vars`, `vars_os`); `env!` (a build-time constant) is not a read.
fn env_reads(s: &Source) -> Vec<String> {
    const READS: [&str; 4] = ["var", "var_os", "vars", "vars_os"];
    tokens(&s.code)
        .windows(3)
        .filter(|w| w[0].0 == "env" && w[1].0 == "::" && READS.contains(&w[2].0.as_str()))
        .map(|w| format!("{} `env::{}`", s.at(w[0].1), w[2].0))
        .collect()
}

/// Library code takes what it needs to know (the time above all) as a
/// value; only the app reads the environment.
#[test]
fn library_crates_never_read_the_environment() {
    let in_crates = |s: &&Source| s.root.starts_with(manifest().join("crates"));
    let wrong: Vec<String> = sources()
        .iter()
        .filter(in_crates)
        .filter(|s| !ENV_READERS.iter().any(|(file, _)| s.show() == *file))
        .flat_map(env_reads)
        .collect();
    assert!(
        wrong.is_empty(),
        "the environment read in a library crate (read it in the app and pass the value):\n{}",
        wrong.join("\n")
    );
    for (file, why) in ENV_READERS {
        assert!(
            sources()
                .iter()
                .filter(in_crates)
                .any(|s| s.show() == file && !env_reads(s).is_empty()),
            "{file} no longer reads the environment ({why}): take it out of ENV_READERS"
        );
    }
}

/// Sources made from text, as if they were the files of `src/`.
fn fixture(files: &[(&str, &str)]) -> Vec<Source> {
    let files = files
        .iter()
        .map(|(rel, text)| (PathBuf::from(rel), text.to_string()))
        .collect();
    sources_of(&src(), files)
}

#[test]
fn the_checker_sees_what_it_should() {
    // The checks above pass vacuously if these helpers find nothing.
    let found = uses(
        "use crate::{sim::Method, text}; let x = crate::deck::load(p);",
        &["cmd".to_string()],
    );
    assert_eq!(
        found,
        ["deck", "sim", "text"]
            .map(String::from)
            .into_iter()
            .collect()
    );
    let code = code(
        "a // crate::cmd\n/* crate::tui */ \"crate::sync\" '\"' b\n#[cfg(test)]\nmod tests { crate::tui }\nc",
    );
    assert_eq!(code.lines().count(), 5, "lines are kept: {code:?}");
    assert!(
        !code.contains("crate::") && code.contains('a') && code.contains('b') && code.contains('c'),
        "{code:?}"
    );
    assert!(code_of("sim").len() > 20, "the sim sources were not found");
    assert!(
        code_of("store").len() > 10,
        "the store sources were not found"
    );
    assert!(code_of("tui").len() > 20, "the tui sources were not found");
    assert!(
        uses("flipcard_io::open(p)", &["sim".to_string()]).contains("io"),
        "a crate named by its crate name is a use"
    );
    let all = sources();
    assert!(
        all.iter()
            .all(|s| !s.show().contains("tests.rs") && !s.show().contains("/tests/")),
        "test modules are read"
    );
    assert!(all.iter().any(|s| s.is_main()), "main.rs was not found");
    // The real graph has many edges inside folders; none would mean the
    // paths were not read.
    let edges: usize = crates(all).values().map(|f| sibling_edges(f).len()).sum();
    assert!(edges > 200, "the module graph is nearly empty");
}

#[test]
fn paths_are_read_through_groups_super_and_self() {
    let module: Vec<String> = ["store", "log"].map(String::from).to_vec();
    let code = "use super::{codec::{self, Ms}, db::Store};\n\
                use crate::sched::{Config as C, types::*};\n\
                let x = super::super::deck::load(p);\n\
                let y = $crate::cmd::output::stdout();\n\
                let z = r#\"crate::tui\"#;";
    let found: BTreeSet<String> = paths(&self::code(code), &module)
        .into_iter()
        .map(|n| n.path.join("::"))
        .collect();
    let expected: BTreeSet<String> = [
        "store::codec",
        "store::codec::Ms",
        "store::db::Store",
        "sched::Config",
        "sched::types",
        "deck::load",
        "cmd::output::stdout",
    ]
    .map(String::from)
    .into_iter()
    .collect();
    assert_eq!(found, expected);
}

#[test]
fn a_cycle_among_siblings_is_found_and_named() {
    let files = [
        ("lib.rs", "pub mod a;"),
        (
            "a/mod.rs",
            "pub mod x;\npub mod y;\npub mod z;\n#[cfg(test)]\nmod tests;",
        ),
        ("a/x.rs", "use super::y::Thing;\n"),
        ("a/y.rs", "use crate::a::{z::{self, Other}};\n"),
        (
            "a/z.rs",
            "// crate::a::x\nfn f() { let s = \"crate::a::x\"; }\npub fn g() -> super::x::X { todo!() }",
        ),
        // Test code may go round: it is not read.
        ("a/tests.rs", "use crate::a::{x, y, z};"),
    ];
    let sources = fixture(&files);
    assert_eq!(sources.len(), 5, "the test module is left out");
    let found = cycles(&sibling_edges(&sources.iter().collect::<Vec<_>>()));
    assert_eq!(found.len(), 1, "{found:?}");
    let (group, inside) = &found[0];
    let text = describe("src", group, inside);
    assert!(text.starts_with("in src/a/: x <-> y <-> z"), "{text}");
    assert!(
        text.contains("x -> y: src/a/x.rs:1 `a::y::Thing`"),
        "{text}"
    );
    assert!(text.contains("z -> x: src/a/z.rs:3 `a::x::X`"), "{text}");
    // One way round is no cycle.
    let one_way = fixture(&files[..4]);
    assert!(cycles(&sibling_edges(&one_way.iter().collect::<Vec<_>>())).is_empty());
}

#[test]
fn printing_and_the_terminal_are_found_outside_literals_and_comments() {
    let files = [
        (
            "store/log.rs",
            "fn f() {\n    println!(\"x\");\n    let _ = std::io::stderr();\n    \
             let s = \"eprintln!(dbg!())\"; // print!()\n    cmd.stdout(Stdio::null());\n    \
             if out != 1 {}\n}\n#[cfg(test)]\nmod tests { fn t() { dbg!(1); } }",
        ),
        (
            "sync/plan.rs",
            "use ratatui::text::Line;\n// crossterm\nconst S: &str = \"crossterm\";",
        ),
    ];
    let sources = fixture(&files);
    let printed: Vec<String> = sources.iter().flat_map(printing).collect();
    assert_eq!(
        printed,
        [
            "src/store/log.rs:2 `println!`",
            "src/store/log.rs:3 `stderr`"
        ]
    );
    let drawn: Vec<String> = sources.iter().flat_map(terminal_uses).collect();
    assert_eq!(drawn, ["src/sync/plan.rs:1 `ratatui`"]);
}

#[test]
fn a_cycle_through_a_re_export_is_found() {
    // `x` names `Thing` and `y` names `g` through their parent's
    // re-exports; they still use each other.
    let files = [
        ("lib.rs", "pub mod a;"),
        (
            "a/mod.rs",
            "pub mod x;\npub mod y;\npub use x::Thing as Alias;\npub use y::*;",
        ),
        ("a/x.rs", "pub struct Thing;\nfn f() { super::g() }"),
        ("a/y.rs", "pub fn g() {}\nfn h(_: crate::a::Alias) {}"),
    ];
    let sources = fixture(&files);
    let found = cycles(&sibling_edges(&sources.iter().collect::<Vec<_>>()));
    assert_eq!(found.len(), 1, "{found:?}");
    let text = describe("src", &found[0].0, &found[0].1);
    assert!(text.contains("x -> y: src/a/x.rs:2 `a::y::g`"), "{text}");
    assert!(
        text.contains("y -> x: src/a/y.rs:2 `a::x::Thing`"),
        "{text}"
    );
}

#[test]
fn environment_reads_are_found_outside_literals_and_comments() {
    let files = [(
        "sched/clock.rs",
        "pub fn now() {\n    match std::env::var(NOW_VAR) {}\n    \
         let s = \"env::var\"; // std::env::var_os\n    let h = env::var_os(\"HOME\");\n    \
         let m = env!(\"CARGO_MANIFEST_DIR\");\n}\n#[cfg(test)]\n\
         mod tests { fn t() { std::env::var(\"X\"); } }",
    )];
    let sources = fixture(&files);
    let found: Vec<String> = sources.iter().flat_map(env_reads).collect();
    assert_eq!(
        found,
        [
            "src/sched/clock.rs:2 `env::var`",
            "src/sched/clock.rs:4 `env::var_os`"
        ]
    );
}
