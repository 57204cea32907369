//! The core's integration tests, in one binary: the scheduler against
//! py-fsrs's golden runs (default and custom parameters), the exam plan,
//! the sync property search over the store, and load balancing across
//! machines (`sync_balance`). They need nothing but this
//! crate, so editing the app or a deck does not rebuild them. Run one
//! file's tests with `cargo test --test main -p flipcard-core NAME::` (or
//! from this folder); `PROPTEST_CASES=1000` searches longer.

mod exam_plan;
mod sched_golden;
mod sched_golden_custom;
mod sync_balance;
mod sync_props;
