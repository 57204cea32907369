//! `flipcard schema [--out DIR]`: the schemas an editor needs, written for
//! a deck folder outside the repository.

use std::path::Path;

use crate::support::Flipcard;

fn checked_in(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("schema")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn writes_both_schemas_into_a_new_folder() {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let out = dir.path().join("course").join("schema");
    let run = Flipcard::without_data()
        .args(["schema", "--out"])
        .arg(&out)
        .run();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    for name in ["deck.schema.json", "content.schema.json"] {
        let written = std::fs::read_to_string(out.join(name))
            .unwrap_or_else(|e| panic!("{name} not written: {e}"));
        assert_eq!(written, checked_in(name), "{name}");
        assert!(stdout.contains(name), "{stdout}");
        let json: serde_json::Value =
            serde_json::from_str(&written).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(json.get("$schema").is_some(), "{name}");
    }
}

#[test]
fn defaults_to_schema_in_the_current_folder() {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let run = Flipcard::without_data()
        .current_dir(dir.path())
        .arg("schema")
        .run();
    assert!(run.status.success());
    assert!(dir.path().join("schema/deck.schema.json").is_file());
}

#[test]
fn an_output_path_that_is_a_file_is_one_line_of_error() {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let file = dir.path().join("taken");
    std::fs::write(&file, "x").unwrap_or_else(|e| panic!("{e}"));
    let run = Flipcard::without_data()
        .args(["schema", "--out"])
        .arg(&file)
        .run();
    assert_eq!(run.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("taken"), "{stderr}");
}
