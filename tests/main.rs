//! Every integration test in one binary: one link of the crate instead of
//! one per file. Run one file's tests with `cargo test --test main NAME::`.

mod architecture;
mod store_support;
mod support;

mod bench_cli;
mod bundled_deck;
mod bundled_decks;
mod check_cli;
mod check_files;
mod check_robustness;
mod check_sim_agree;
mod class_report;
mod cli_output;
mod deck_library;
mod deck_mutations;
mod deck_oscillations;
mod deck_physics;
mod doc_examples;
mod exam_plan;
mod import_reviews_cli;
mod ode_solvers;
mod optimize_cli;
mod plan_cli;
mod portable;
mod sched_golden;
mod sched_golden_custom;
mod schema_cli;
mod schemas;
mod sim_cli;
mod sim_exact;
mod sim_integrators;
mod sim_scene_cli;
mod store;
mod store_cli;
mod store_durability;
mod store_merge;
mod store_outside_clients;
mod store_props;
mod store_safety;
mod store_status;
mod sync;
mod system_cli;
mod true_retention;
mod tui_browser_e2e;
mod tui_e2e;
