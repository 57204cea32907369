//! The release binary on its own: copied into an empty folder, run from
//! another empty folder with a bare environment and, where the system lets
//! an unprivileged user make a mount namespace, with the repository hidden
//! under an empty tmpfs. It must still open on the bundled decks, and
//! `check`, `decks`, `sim --list` and `sim --scene` must work.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use crate::support::release_binary;

const REPO: &str = env!("CARGO_MANIFEST_DIR");

/// A command that runs the program hidden from the repository, or `None`
/// (with the reason printed) when mount namespaces are not available.
fn hiding_prefix() -> Option<Vec<String>> {
    let probe = Command::new("unshare")
        .args([
            "-rm",
            "sh",
            "-c",
            "mount -t tmpfs none \"$1\" && test ! -e \"$1/decks\"",
            "sh",
            REPO,
        ])
        .output();
    match probe {
        Ok(o) if o.status.success() => Some(
            [
                "unshare",
                "-rm",
                "sh",
                "-c",
                "mount -t tmpfs none \"$1\" && shift && exec \"$@\"",
                "sh",
                REPO,
            ]
            .map(String::from)
            .to_vec(),
        ),
        other => {
            // Under CI=true the repository must be hidden.
            crate::support::require(
                false,
                "a mount namespace to hide the repository in",
                &format!(
                    "`unshare -rm` from util-linux, allowed to this user; here: {other:?}; \
                     without it the binary still runs alone from an empty folder"
                ),
            );
            None
        }
    }
}

struct Alone {
    _dir: tempfile::TempDir,
    bin: PathBuf,
    cwd: PathBuf,
    home: PathBuf,
    prefix: Option<Vec<String>>,
}

impl Alone {
    fn new() -> Alone {
        let dir = tempfile::tempdir().unwrap();
        let bin_dir = dir.path().join("bin");
        let cwd = dir.path().join("elsewhere");
        let home = dir.path().join("home");
        for d in [&bin_dir, &cwd, &home] {
            std::fs::create_dir_all(d).unwrap();
        }
        let bin = bin_dir.join("flipcard");
        std::fs::copy(release_binary(), &bin).unwrap();
        Alone {
            _dir: dir,
            bin,
            cwd,
            home,
            prefix: hiding_prefix(),
        }
    }

    /// The argv that runs flipcard `args`, hidden when possible.
    fn argv(&self, args: &[&str]) -> Vec<String> {
        let mut v = self.prefix.clone().unwrap_or_default();
        v.push(self.bin.display().to_string());
        v.extend(args.iter().map(|s| s.to_string()));
        v
    }

    fn run(&self, args: &[&str]) -> Output {
        let argv = self.argv(args);
        Command::new(&argv[0])
            .args(&argv[1..])
            .current_dir(&self.cwd)
            .env_clear()
            .env("PATH", "/usr/bin:/bin")
            .env("HOME", &self.home)
            .env("FLIPCARD_NOW", "2026-03-02T09:00:00Z")
            .output()
            .unwrap()
    }
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn the_binary_alone_carries_its_decks() {
    let alone = Alone::new();
    let bundled = flipcard::bundled::load();
    // The first bundled deck with a rigid-body scene.
    let deck = bundled
        .decks
        .iter()
        .find(|d| !d.scenes.is_empty())
        .expect("a bundled deck with a rigid-body scene");

    let out = alone.run(&["check"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stdout).trim(),
        flipcard::cmd::check::summary(&bundled)
    );

    let out = alone.run(&["decks"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let listing = text(&out.stdout);
    let row = listing
        .lines()
        .find(|l| l.starts_with(&deck.id))
        .unwrap_or_else(|| panic!("{listing}"));
    assert!(
        row.contains("bundled") && row.trim_end().ends_with("ok"),
        "{row}"
    );

    let out = alone.run(&["sim", "--list"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let scenes = bundled
        .decks
        .iter()
        .map(|d| d.scenes.len() + d.systems.len())
        .sum::<usize>();
    assert_eq!(text(&out.stdout).lines().count(), scenes);

    let scene = &deck.scenes[0].id;
    let out = alone.run(&["sim", "--scene", scene]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains(scene.as_str()),
        "{}",
        text(&out.stdout)
    );

    opens_in_a_terminal(&alone, deck.title.get("en"));
}

/// The terminal app shows the bundled deck's title (in tmux; skipped with
/// a note when tmux is missing, failed then under `CI=true`).
fn opens_in_a_terminal(alone: &Alone, title: &str) {
    if !crate::support::require_tool("tmux") {
        return;
    }
    let socket = format!("flipcard-alone-{}", std::process::id());
    let tmux = |args: &[&str]| {
        Command::new("tmux")
            .args(["-L", &socket, "-f", "/dev/null"])
            .args(args)
            .output()
            .unwrap()
    };
    let quoted: Vec<String> = alone
        .argv(&[])
        .iter()
        .map(|a| format!("'{}'", a.replace('\'', "'\\''")))
        .collect();
    let script = format!(
        "cd '{}' && env -i PATH=/usr/bin:/bin HOME='{}' TERM=xterm-256color {}; sleep 60",
        alone.cwd.display(),
        alone.home.display(),
        quoted.join(" ")
    );
    let started = tmux(&[
        "new-session",
        "-d",
        "-s",
        "a",
        "-x",
        "100",
        "-y",
        "30",
        "sh",
        "-c",
        &script,
    ]);
    assert!(started.status.success(), "{}", text(&started.stderr));
    let deadline = Instant::now() + Duration::from_secs(30);
    let screen = loop {
        let s = text(&tmux(&["capture-pane", "-p", "-t", "a"]).stdout);
        if s.contains(title) || Instant::now() > deadline {
            break s;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let _ = tmux(&["send-keys", "-t", "a", "q"]);
    std::thread::sleep(Duration::from_millis(200));
    let _ = tmux(&["kill-server"]);
    assert!(
        screen.contains(title),
        "the deck is not on screen:\n{screen}"
    );
}

#[test]
fn only_the_work_precision_table_is_looked_up_in_the_source_tree() {
    // Decks come from the binary; nothing else outside tests may find
    // files through the build's source path.
    let mut hits = Vec::new();
    let mut stack = vec![Path::new(REPO).join("src")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "tests") {
                    stack.push(p);
                }
                continue;
            }
            let code = std::fs::read_to_string(&p).unwrap_or_default();
            let code = code.split("#[cfg(test)]").next().unwrap_or("");
            if code.contains("env!(\"CARGO_MANIFEST_DIR\")") {
                hits.push(p.strip_prefix(REPO).unwrap().display().to_string());
            }
        }
    }
    assert_eq!(hits, ["src/cmd/paths.rs"], "only the optional bench table");
}
