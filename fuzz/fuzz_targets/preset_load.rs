//! Fuzz target (a): preset text → load. The logic and its
//! invariants are in `harness/preset_load.rs`, shared with the stable replay test
//! `crates/physics/tests/fuzz_regressions.rs`.
#![no_main]

#[path = "../harness/preset_load.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::run(data));
