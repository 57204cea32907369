//! `flipcard check` on the fixture trees under tests/decks/, through the
//! real binary.
//!
//! Each case is a folder with `decks/`, `content/` and `expect.txt`. The
//! expectation lists every diagnostic the case must produce, one per line
//! as `path:line:col: severity: message fragment` (paths relative to the
//! case folder), each optionally followed by `  = help: fragment`; valid
//! cases also give `summary: <the stdout line>`. Invalid cases hold exactly
//! one problem, so exactly one error.

use std::fs;
use std::path::{Path, PathBuf};

use crate::support::Flipcard;

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn cases(kind: &str) -> Vec<PathBuf> {
    let dir = manifest_dir().join("tests/decks").join(kind);
    let mut out: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    out.sort();
    out
}

#[derive(Debug)]
struct Expected {
    /// `path:line:col`
    location: String,
    severity: String,
    fragment: String,
    help: Option<String>,
}

#[derive(Debug, Default)]
struct Expectation {
    /// Paths to check (default `decks`).
    args: Vec<String>,
    summary: Option<String>,
    diagnostics: Vec<Expected>,
}

fn expectation(case: &Path) -> Expectation {
    let path = case.join("expect.txt");
    let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut exp = Expectation::default();
    for line in text.lines() {
        if line.trim().is_empty() || line.starts_with('#') {
            continue;
        }
        if let Some(a) = line.strip_prefix("args: ") {
            exp.args = a.split_whitespace().map(str::to_string).collect();
        } else if let Some(s) = line.strip_prefix("summary: ") {
            exp.summary = Some(s.to_string());
        } else if let Some(h) = line.strip_prefix("  = help: ") {
            let last = exp
                .diagnostics
                .last_mut()
                .unwrap_or_else(|| panic!("{}: help before a diagnostic", path.display()));
            last.help = Some(h.to_string());
        } else {
            let (location, rest) = split_headline(line)
                .unwrap_or_else(|| panic!("{}: not a diagnostic line: {line}", path.display()));
            let (severity, fragment) = rest.split_once(": ").unwrap();
            exp.diagnostics.push(Expected {
                location,
                severity: severity.to_string(),
                fragment: fragment.to_string(),
                help: None,
            });
        }
    }
    if exp.args.is_empty() {
        exp.args.push("decks".to_string());
    }
    exp
}

/// `path:line:col` and the rest of a headline (`error: message`).
fn split_headline(line: &str) -> Option<(String, &str)> {
    for sev in [": error: ", ": warning: "] {
        if let Some(i) = line.find(sev) {
            let location = &line[..i];
            let mut parts = location.rsplitn(3, ':');
            let col = parts.next()?;
            let row = parts.next()?;
            if col.parse::<usize>().is_ok() && row.parse::<usize>().is_ok() {
                return Some((location.to_string(), &line[i + 2..]));
            }
        }
    }
    None
}

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

fn check(dir: &Path, args: &[&str]) -> Run {
    let out = Flipcard::without_data()
        .current_dir(dir)
        .arg("check")
        .args(args)
        .run();
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: out.stdout(),
        stderr: out.stderr(),
    }
}

fn headlines(stderr: &str) -> Vec<(usize, &str)> {
    stderr
        .lines()
        .enumerate()
        .filter(|(_, l)| split_headline(l).is_some())
        .collect()
}

/// Problems with `run` against `exp`, each prefixed by the case name;
/// `prefix` is prepended to expected paths.
fn compare(name: &str, run: &Run, exp: &Expectation, prefix: &str) -> Vec<String> {
    let mut problems = Vec::new();
    let lines: Vec<&str> = run.stderr.lines().collect();
    let heads = headlines(&run.stderr);
    for e in &exp.diagnostics {
        let start = format!("{prefix}{}: {}: ", e.location, e.severity);
        let found = heads
            .iter()
            .find(|(_, l)| l.starts_with(&start) && l.contains(&e.fragment));
        let Some(&(at, _)) = found else {
            problems.push(format!(
                "{name}: expected `{start}{}`\n--- stderr:\n{}",
                e.fragment, run.stderr
            ));
            continue;
        };
        if let Some(help) = &e.help {
            let block_end = heads
                .iter()
                .map(|&(i, _)| i)
                .find(|&i| i > at)
                .unwrap_or(lines.len());
            let has_help = lines[at..block_end]
                .iter()
                .any(|l| l.starts_with("  = help: ") && l.contains(help.as_str()));
            if !has_help {
                problems.push(format!("{name}: expected help `{help}` after `{start}`"));
            }
        }
    }
    if heads.len() != exp.diagnostics.len() {
        problems.push(format!(
            "{name}: expected {} diagnostics, got {}\n--- stderr:\n{}",
            exp.diagnostics.len(),
            heads.len(),
            run.stderr
        ));
    }
    if run.stderr.contains("panicked") {
        problems.push(format!("{name}: panicked\n{}", run.stderr));
    }
    problems
}

fn args(exp: &Expectation) -> Vec<&str> {
    exp.args.iter().map(String::as_str).collect()
}

fn count(exp: &Expectation, severity: &str) -> usize {
    exp.diagnostics
        .iter()
        .filter(|d| d.severity == severity)
        .count()
}

#[test]
fn every_invalid_case_fails_with_its_one_diagnostic() {
    let cases = cases("invalid");
    assert!(cases.len() >= 25, "only {} invalid cases", cases.len());
    let mut problems = Vec::new();
    for case in &cases {
        let name = case.file_name().unwrap().to_string_lossy().into_owned();
        let exp = expectation(case);
        if count(&exp, "error") != 1 {
            problems.push(format!("{name}: expect.txt must list exactly one error"));
        }
        let run = check(case, &args(&exp));
        if run.code != 1 {
            problems.push(format!("{name}: exit code {} instead of 1", run.code));
        }
        if !run.stdout.is_empty() {
            problems.push(format!("{name}: stdout not empty: {}", run.stdout));
        }
        let tally = match count(&exp, "warning") {
            1 => "1 error, 1 warning".to_string(),
            n => format!("1 error, {n} warnings"),
        };
        if run.stderr.lines().last() != Some(tally.as_str()) {
            problems.push(format!(
                "{name}: last line is not `{tally}`:\n{}",
                run.stderr
            ));
        }
        problems.extend(compare(&name, &run, &exp, ""));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n\n"));
}

#[test]
fn every_valid_case_passes_with_its_summary() {
    let cases = cases("valid");
    assert!(cases.len() >= 2);
    let mut problems = Vec::new();
    for case in &cases {
        let name = case.file_name().unwrap().to_string_lossy().into_owned();
        let exp = expectation(case);
        let run = check(case, &args(&exp));
        if run.code != 0 {
            problems.push(format!("{name}: exit code {}\n{}", run.code, run.stderr));
        }
        let summary = exp
            .summary
            .as_deref()
            .unwrap_or("(no summary in expect.txt)");
        if run.stdout != format!("{summary}\n") {
            problems.push(format!(
                "{name}: stdout `{}` instead of `{summary}`",
                run.stdout
            ));
        }
        if count(&exp, "error") != 0 {
            problems.push(format!("{name}: a valid case expects no errors"));
        }
        problems.extend(compare(&name, &run, &exp, ""));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n\n"));
}

/// One run over every invalid case reports every case's problem: nothing
/// stops at the first broken deck. (The cases all name their deck `d`, so
/// the run also reports each later `d` as a duplicate deck id.)
#[test]
fn one_run_reports_the_problems_of_every_deck() {
    let cases = cases("invalid");
    let root = manifest_dir();
    let mut paths = Vec::new();
    let mut expected = Vec::new();
    for case in &cases {
        let rel = case
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let exp = expectation(case);
        for a in &exp.args {
            paths.push(format!("{rel}/{a}"));
        }
        for e in &exp.diagnostics {
            expected.push(format!("{rel}/{}: {}: ", e.location, e.severity));
        }
    }
    let arg_refs: Vec<&str> = paths.iter().map(String::as_str).collect();
    let run = check(&root, &arg_refs);
    assert_eq!(run.code, 1);
    let heads: Vec<&str> = headlines(&run.stderr).into_iter().map(|(_, l)| l).collect();
    // Messages naming other files carry the prefix too, so only positions
    // are compared here; the per-case test checks the text.
    let missing: Vec<&String> = expected
        .iter()
        .filter(|start| !heads.iter().any(|l| l.starts_with(start.as_str())))
        .collect();
    assert!(missing.is_empty(), "missing: {missing:#?}");
    let others: Vec<&&str> = heads
        .iter()
        .filter(|l| !expected.iter().any(|start| l.starts_with(start.as_str())))
        .collect();
    assert!(
        others
            .iter()
            .all(|l| l.contains("error: deck id `d` is also used by")),
        "unexpected: {others:#?}"
    );
    assert!(heads.len() > 1, "{heads:#?}");
    let tally = format!("{} errors, 0 warnings", heads.len());
    assert_eq!(run.stderr.lines().last(), Some(tally.as_str()));
}

#[test]
fn a_missing_path_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let run = check(dir.path(), &["no-such-decks"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("no-such-decks"), "{}", run.stderr);
    assert!(run.stdout.is_empty());
}

#[test]
fn an_unknown_option_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let run = check(dir.path(), &["--strict"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.contains("--strict"), "{}", run.stderr);
}

#[test]
fn an_empty_folder_is_clean_but_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("decks")).unwrap();
    let run = check(dir.path(), &["decks"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "0 decks, 0 cards, 0 prompts, 0 scenes, 0 sections: ok\n"
    );
    assert!(
        run.stderr.contains("warning: no deck files"),
        "{}",
        run.stderr
    );
}

#[test]
fn a_deck_file_can_be_named_directly() {
    let case = manifest_dir().join("tests/decks/valid/full");
    let run = check(&case, &["decks/spinning-top.toml"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "1 deck, 3 cards, 2 prompts, 2 scenes, 2 sections: ok\n"
    );
}

#[test]
fn without_paths_the_bundled_decks_are_checked() {
    let run = check(&manifest_dir(), &[]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.ends_with(" sections: ok\n"), "{}", run.stdout);
    assert!(!run.stderr.contains("error"), "{}", run.stderr);
}

/// `--no-simulate` checks everything but the answers against the runs:
/// the deck with a wrong expected answer passes, and only the answer was
/// wrong in it.
#[test]
fn no_simulate_skips_the_runs_and_only_them() {
    for case in ["answer-contradicts-run", "number-contradicts-run"] {
        let dir = manifest_dir().join("tests/decks/invalid").join(case);
        let judged = check(&dir, &["decks"]);
        assert_eq!(judged.code, 1, "{case}: {}", judged.stderr);
        assert!(
            judged.stderr.contains("but this "),
            "{case}: {}",
            judged.stderr
        );
        let skipped = check(&dir, &["--no-simulate", "decks"]);
        assert_eq!(skipped.code, 0, "{case}: {}", skipped.stderr);
        assert!(skipped.stderr.is_empty(), "{case}: {}", skipped.stderr);
        assert!(skipped.stdout.ends_with(": ok\n"), "{}", skipped.stdout);
    }
}

/// The bundled decks check without a warning: every prose reference to a
/// section (`see *Title*`, `dekho *Title*`) names a real title or is a
/// link, so a new check that finds something there finds a real mistake.
#[test]
fn the_bundled_decks_check_without_warnings() {
    let run = check(&manifest_dir(), &["--no-simulate", "decks"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stderr, "", "warnings on the bundled decks");
    assert!(run.stdout.ends_with(": ok\n"), "{}", run.stdout);
}
