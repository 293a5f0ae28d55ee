//! Fuzz target (b): a valid preset in the app's ranges → simulate. The logic and its
//! invariants are in `harness/simulate.rs`, shared with the stable replay test
//! `crates/physics/tests/fuzz_regressions.rs`.
#![no_main]

#[path = "../harness/simulate.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::run(data));
