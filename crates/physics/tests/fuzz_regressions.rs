//! The fuzz campaigns' findings and corpora, on stable (issue 14). Every input that ever failed a
//! fuzz target is kept in `fuzz/regressions/TARGET/`, and the minimised corpora in
//! `fuzz/corpus/TARGET/`; both are replayed here through the very harnesses the fuzz targets run
//! (`fuzz/harness/*.rs`), so a finding that comes back fails `cargo test` without nightly. The
//! findings themselves are also written out as plain tests below.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use stoneskip_physics::sim::params::{Limiter, Precision};
use stoneskip_physics::sim::water::{WaterConfig, WaterGrid};

#[path = "../../../fuzz/harness/preset_load.rs"]
mod preset_load;
#[path = "../../../fuzz/harness/simulate.rs"]
mod simulate;
#[path = "../../../fuzz/harness/water.rs"]
mod water;

/// Runs `run` on every file of `fuzz/DIR/TARGET`, at most `limit` of them (sorted by name); returns
/// how many ran.
fn replay(dir: &str, target: &str, limit: usize, run: fn(&[u8])) -> usize {
    let d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz")
        .join(dir)
        .join(target);
    let Ok(rd) = std::fs::read_dir(&d) else {
        return 0;
    };
    let mut files: Vec<_> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    for f in files.iter().take(limit) {
        let data = std::fs::read(f).unwrap();
        let name = f.display().to_string();
        let r = std::panic::catch_unwind(|| run(&data));
        assert!(r.is_ok(), "{name} fails the {target} harness again");
    }
    files.len().min(limit)
}

#[test]
fn every_saved_finding_passes_its_harness() {
    let n = replay("regressions", "preset_load", usize::MAX, preset_load::run)
        + replay("regressions", "simulate", usize::MAX, simulate::run)
        + replay("regressions", "water", usize::MAX, water::run);
    println!("{n} saved findings replayed");
    assert!(n >= 1, "the water findings are kept");
}

#[test]
fn preset_corpus_passes_its_harness() {
    let n = replay("corpus", "preset_load", usize::MAX, preset_load::run);
    println!("{n} preset texts replayed");
    assert!(n > 0);
}

#[test]
fn water_corpus_passes_its_harness() {
    let n = replay("corpus", "water", usize::MAX, water::run);
    println!("{n} water cases replayed");
    assert!(n > 0);
}

/// The simulate corpus is slow in the dev profile (a run is up to 0.25 s of simulated time with up
/// to 128 segments): a sample of 40 in CI, all with `STONESKIP_FUZZ_ALL=1`.
#[test]
fn simulate_corpus_passes_its_harness() {
    let limit = if std::env::var_os("STONESKIP_FUZZ_ALL").is_some() {
        usize::MAX
    } else {
        40
    };
    let n = replay("corpus", "simulate", limit, simulate::run);
    println!("{n} presets simulated");
    assert!(n > 0);
}

/// Finding W1, f64 storage: one column's bed raised to the rest surface (its depth kept, so its
/// surface stands H above the others) drains into its neighbours, and the K limiter, which lets a
/// column give exactly what it holds, leaves it at −1.7e-18 m: d + β(in − K·out) rounds below zero.
#[test]
fn drained_column_keeps_a_non_negative_depth() {
    let cfg = WaterConfig {
        nx: 17,
        ny: 7,
        cell: 0.0328149387858607,
        depth: 0.8714586777549436,
        gravity: 4.804689289258022,
        density: 100.00000067520887,
        damping: 0.0,
        diagonal_pipes: false,
        limiter: Limiter::MassConserving,
        origin: [-9.99986410140988, 7.4114990274914305],
        dt: None,
        precision: Precision::F64,
    };
    let mut w = WaterGrid::with_config(cfg).unwrap();
    w.set_bed(0, 3, -0.0);
    w.advance(0.04062486235998219);
    assert!(w.min_depth() >= 0.0, "depth {}", w.min_depth());
}

/// Finding W1, f32 storage: a 58 N·s impulse on a 9 × 9 mm footprint of a 2 cm deep lake without
/// gravity pushes one column dry in one step, to −1.9e-9 m.
#[test]
fn impulse_drained_column_keeps_a_non_negative_depth() {
    let cfg = WaterConfig {
        nx: 12,
        ny: 2,
        cell: 0.01568207268825637,
        depth: 0.02,
        gravity: 0.0,
        density: 100.00000067520887,
        damping: 0.0,
        diagonal_pipes: false,
        limiter: Limiter::MassConserving,
        origin: [2.39196777632273, 7.411608541713004],
        dt: None,
        precision: Precision::F32,
    };
    let mut w = WaterGrid::with_config(cfg).unwrap();
    w.deposit_impulse_box(
        2.5113705264848094,
        7.431509399446023,
        0.00008872886754080121,
        57.64705882352939,
    );
    w.advance(0.026394034904985233);
    assert!(w.min_depth() >= 0.0, "depth {}", w.min_depth());
}
