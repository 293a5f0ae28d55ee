//! Fuzz target (c): the water grid under random settings, deposits and steps. The logic and its
//! invariants are in `harness/water.rs`, shared with the stable replay test
//! `crates/physics/tests/fuzz_regressions.rs`.
#![no_main]

#[path = "../harness/water.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::run(data));
