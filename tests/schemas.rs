//! The published JSON Schemas match the Rust types they are generated from,
//! and name exactly the fields the deck reader knows.
//!
//! After changing the format: `UPDATE_SCHEMAS=1 cargo test --test main schemas::`.

use std::collections::BTreeSet;
use std::fs;
use std::path::PathBuf;

use flipcard::deck::raw;
use flipcard::deck::schema;
use serde_json::Value;

fn check_file(name: &str, schema: &Value) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("schema")
        .join(name);
    let fresh = schema::to_text(schema);
    if std::env::var_os("UPDATE_SCHEMAS").is_some() {
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(&path, &fresh).unwrap();
        return;
    }
    let stored = fs::read_to_string(&path).unwrap_or_default();
    assert!(
        stored == fresh,
        "{} is stale: regenerate it with `UPDATE_SCHEMAS=1 cargo test --test main schemas::`",
        path.display()
    );
}

#[test]
fn deck_schema_is_up_to_date() {
    check_file("deck.schema.json", &schema::deck_schema());
}

#[test]
fn content_schema_is_up_to_date() {
    check_file("content.schema.json", &schema::content_schema());
}

fn keys(object: &Value) -> BTreeSet<String> {
    object["properties"]
        .as_object()
        .map(|m| m.keys().cloned().collect())
        .unwrap_or_default()
}

fn set(fields: &[&str]) -> BTreeSet<String> {
    fields.iter().map(|s| s.to_string()).collect()
}

#[test]
fn schemas_name_the_fields_the_reader_knows() {
    let deck = schema::deck_schema();
    let defs = &deck["definitions"];
    assert_eq!(keys(&deck), set(raw::DECK_FILE_FIELDS));
    assert_eq!(keys(&defs["DeckHeader"]), set(raw::DECK_FIELDS));
    assert_eq!(keys(&defs["Card"]), set(raw::CARD_FIELDS));
    assert_eq!(keys(&defs["Prompt"]), set(raw::PROMPT_FIELDS));
    assert_eq!(keys(&defs["Choice"]), set(raw::CHOICE_FIELDS));
    assert_eq!(keys(&defs["Scene"]), set(raw::SCENE_FIELDS));
    assert_eq!(
        keys(&defs["Knob"]),
        set(flipcard::deck::raw_knob::KNOB_FIELDS)
    );
    // One `if kind == … then …` branch per kind of answer.
    let answers: Vec<&Value> = defs["Answer"]["allOf"]
        .as_array()
        .unwrap()
        .iter()
        .map(|branch| {
            assert_eq!(
                branch["if"]["properties"]["kind"]["const"],
                branch["then"]["properties"]["kind"]["const"]
            );
            &branch["then"]
        })
        .collect();
    assert!(defs["Answer"].get("oneOf").is_none());
    let by_kind = |kind: &str| {
        *answers
            .iter()
            .find(|a| a["properties"]["kind"]["const"] == kind)
            .unwrap_or_else(|| panic!("no {kind} answer in the schema"))
    };
    assert_eq!(keys(by_kind("choice")), set(raw::CHOICE_ANSWER_FIELDS));
    assert_eq!(keys(by_kind("number")), set(raw::NUMBER_ANSWER_FIELDS));
    let kinds: BTreeSet<String> = answers
        .iter()
        .map(|a| {
            a["properties"]["kind"]["const"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    assert_eq!(kinds, set(raw::ANSWER_KINDS));
    let tolerance: BTreeSet<String> = defs["Tolerance"]["oneOf"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(keys)
        .collect();
    assert_eq!(tolerance, set(raw::TOLERANCE_FIELDS));
    assert_eq!(keys(&defs["Slip"]), set(raw::SLIP_FIELDS));
    assert_eq!(
        keys(&defs["Misconception"]),
        set(flipcard::deck::raw_misconception::MISCONCEPTION_FIELDS)
    );
    assert_eq!(
        keys(&defs["WrongRange"]),
        set(flipcard::deck::raw_misconception::RANGE_FIELDS)
    );

    // Derivations, their steps and each kind of a step's ask.
    use flipcard::deck::raw_derivation as rd;
    assert_eq!(keys(&defs["Derivation"]), set(rd::DERIVATION_FIELDS));
    assert_eq!(keys(&defs["DerivationStep"]), set(rd::STEP_FIELDS));
    assert_eq!(keys(&defs["StepChoice"]), set(rd::ASK_CHOICE_FIELDS));
    let asks = defs["StepAsk"]["allOf"].as_array().unwrap();
    let ask = |kind: &str| {
        &asks
            .iter()
            .find(|b| b["if"]["properties"]["kind"]["const"] == kind)
            .unwrap_or_else(|| panic!("no {kind} ask in the schema"))["then"]
    };
    assert_eq!(asks.len(), rd::ASK_KINDS.len());
    assert_eq!(keys(ask("reveal")), set(rd::REVEAL_ASK_FIELDS));
    assert_eq!(keys(ask("choice")), set(rd::CHOICE_ASK_FIELDS));
    assert_eq!(keys(ask("formula")), set(rd::FORMULA_ASK_FIELDS));

    let content = schema::content_schema();
    assert_eq!(keys(&content), set(raw::CONTENT_FILE_FIELDS));
    assert_eq!(
        keys(&content["definitions"]["Section"]),
        set(raw::SECTION_FIELDS)
    );
}

#[test]
fn enumerations_come_from_the_model() {
    let deck = schema::deck_schema();
    let defs = &deck["definitions"];
    let names = |def: &str| -> Vec<String> {
        defs[def]["enum"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap().to_string())
            .collect()
    };
    use flipcard::deck::Panel;
    use flipcard::sim::scene::vocabulary;
    assert_eq!(
        names("Measure"),
        vocabulary::rigid_rows()
            .map(|(r, _)| r.name.to_string())
            .collect::<Vec<_>>()
    );
    assert_eq!(
        names("Panel"),
        Panel::ALL.map(|p| p.name().to_string()).to_vec()
    );
    assert_eq!(
        names("CardKind"),
        ["basic", "reversed", "typed", "cloze", "formula"]
    );
}
