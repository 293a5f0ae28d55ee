//! Whole throws without water: the cost of the stone's physics alone. Prints, for each preset,
//! how many times faster than real time a throw runs (simulated seconds / wall seconds) and the
//! force evaluations it takes; each preset also with `physics.steps_across_ticks` (its steps free
//! of the tick, `name+across`), and each shipped lens on its 64-segment facets at the tolerance it
//! shipped with before issue 41 (`name+faces`: the reference path), side by side in the same run,
//! with the shipped path's speed as a ratio to it.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion};
use stoneskip_physics::sim::params::{Preset, Quadrature};
use stoneskip_physics::sim::simulate;

fn preset(name: &str) -> Preset {
    let mut p = stoneskip_physics::preset::load(Path::new(&format!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/presets/{}.ron"),
        name
    )))
    .expect("shipped preset");
    p.water.enabled = false;
    p
}

fn throws(c: &mut Criterion) {
    let mut group = c.benchmark_group("throw");
    group.sample_size(20);
    for name in [
        "default",
        "magic_angle",
        "bocquet_plate",
        "record_throw",
        "clanet_disc",
    ] {
        let plain = preset(name);
        let mut across = plain.clone();
        across.physics.steps_across_ticks = true;
        let shipped = measure(&mut group, name, &plain);
        measure(&mut group, &format!("{name}+across"), &across);
        if !plain.stone.quadrature.is_faces() {
            let mut faces = plain.clone();
            faces.stone.quadrature = Quadrature::Faces;
            faces.physics.tolerance = 1e-6;
            let reference = measure(&mut group, &format!("{name}+faces"), &faces);
            println!(
                "{name}: the smooth lens runs {:.2}x the facets' speed",
                shipped / reference
            );
        }
    }
    group.finish();
}

/// Benchmarks `p` under `name` and returns its real-time ratio (simulated over wall seconds).
fn measure(
    group: &mut criterion::BenchmarkGroup<criterion::measurement::WallTime>,
    name: &str,
    p: &Preset,
) -> f64 {
    // The real-time ratio, measured once outside criterion so it can be printed.
    let reps = 5;
    let start = Instant::now();
    let mut s = simulate(p).expect("runs");
    for _ in 1..reps {
        s = simulate(p).expect("runs");
    }
    let wall = start.elapsed().as_secs_f64() / reps as f64;
    println!(
        "{name}: {:.3} s simulated in {:.2} ms: {:.0}x real time; {} skips, {} steps, {} force evaluations ({:.2} us each incl. stepping)",
        s.final_time,
        wall * 1e3,
        s.final_time / wall,
        s.skips,
        s.steps,
        s.force_evals,
        wall * 1e6 / s.force_evals.max(1) as f64
    );
    group.bench_function(name, |b| b.iter(|| simulate(black_box(p))));
    s.final_time / wall
}

criterion_group!(benches, throws);
criterion_main!(benches);
