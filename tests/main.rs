//! Every integration test in one binary: one link of the crate instead of
//! one per file. Run one file's tests with `cargo test --test main NAME::`.

mod architecture;
mod store_support;
mod support;

mod bench_cli;
mod bundled_deck;
mod bundled_decks;
mod cards_cli;
mod check_cli;
mod check_files;
mod check_robustness;
mod check_sim_agree;
mod cli_output;
mod deck_mutations;
mod deck_physics;
mod ode_solvers;
mod sched_golden;
mod schemas;
mod sim_cli;
mod sim_exact;
mod sim_integrators;
mod sim_scene_cli;
mod store;
mod store_cli;
mod store_durability;
mod store_outside_clients;
mod store_props;
mod store_safety;
mod store_status;
mod tui_browser_e2e;
mod tui_e2e;
