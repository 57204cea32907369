//! Shared by the integration tests: the one way to run the binary
//! ([`Flipcard`]), reference solutions for the simulator tests, and what a
//! test needs from the machine it runs on.
//!
//! A test that needs a program (tmux, Chromium, `sqlite3`, Python's
//! `sqlite3` module, `setpriv`, `unshare`) or a permission (mounting a
//! tmpfs) asks [`require`] first. Where it is missing the test is skipped
//! with a note, except under `CI=true` (`.ci/run` sets it, and installs
//! every such program): there a missing one fails the test, so that no
//! test passes in CI without having run.

#![allow(dead_code)]

pub mod cli;
pub mod deck;

pub use cli::{Flipcard, Output, release_binary, test_binary};

use std::collections::HashMap;
use std::process::{Command, Stdio};
use std::sync::Mutex;

/// Whether this is a CI run (`CI=true`), where nothing may be skipped.
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// Whether `program args` runs and exits 0 (its output is dropped).
pub fn works(program: &str, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Whether a test may go on that needs `what`: true when `available`.
/// Otherwise, under `CI=true`, the test fails naming `what` and `how` to
/// provide it; elsewhere a note says what is not run, once per `what`,
/// and the answer is false.
pub fn require(available: bool, what: &str, how: &str) -> bool {
    if available {
        return true;
    }
    assert!(
        !in_ci(),
        "{what} is missing, and CI=true runs every test ({how})"
    );
    static NOTED: Mutex<Vec<String>> = Mutex::new(Vec::new());
    let mut noted = NOTED.lock().unwrap_or_else(|e| e.into_inner());
    if !noted.iter().any(|w| w == what) {
        noted.push(what.to_string());
        eprintln!("skipped what needs {what}: it is missing ({how}); under CI=true this fails");
    }
    false
}

/// [`require`] for a program, probed once per test run: `tmux`, `sqlite3`,
/// `python3`, `setpriv`, `unshare`, `mkfifo`.
pub fn require_tool(tool: &str) -> bool {
    let (probe, package): (&[&str], &str) = match tool {
        "tmux" => (&["-V"], "tmux"),
        "sqlite3" => (&["-version"], "sqlite3"),
        "python3" => (&["--version"], "python3"),
        "setpriv" | "unshare" => (&["--version"], "util-linux"),
        "mkfifo" => (&["--version"], "coreutils"),
        other => panic!("support::require_tool: no probe for `{other}`"),
    };
    let works = probed(tool, || works(tool, probe));
    require(
        works,
        &format!("`{tool}`"),
        &format!("apt-get install -y {package}"),
    )
}

/// [`require`] for a Python module (`python3 -c "import MODULE"`).
pub fn require_python_module(module: &str) -> bool {
    let key = format!("python3 -c 'import {module}'");
    let works = probed(&key, || {
        works("python3", &["-c", &format!("import {module}")])
    });
    require(
        works,
        &format!("Python 3 with its `{module}` module"),
        "apt-get install -y python3",
    )
}

/// Chromium's name on this machine, through [`require`].
pub fn require_chromium() -> Option<&'static str> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|b| works(b, &["--version"]));
    require(found.is_some(), "Chromium", "apt-get install -y chromium")
        .then_some(found)
        .flatten()
}

/// `check` run once per key and remembered.
fn probed(key: &str, check: impl FnOnce() -> bool) -> bool {
    static SEEN: Mutex<Option<HashMap<String, bool>>> = Mutex::new(None);
    if let Some(&known) = SEEN
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .get_or_insert_with(HashMap::new)
        .get(key)
    {
        return known;
    }
    let result = check();
    SEEN.lock()
        .unwrap_or_else(|e| e.into_inner())
        .get_or_insert_with(HashMap::new)
        .insert(key.to_string(), result);
    result
}
