//! One force evaluation (issue 12): the fast kernel (`hydro::evaluate`) against the scalar
//! reference (`hydro::evaluate_reference`) on the default lens at 32 and 96 segments, in four
//! poses — grazing (lowest vertex 1 % of the vertical extent under), mid-contact (10 %), deep
//! (wholly under) and free rotation (mid-contact, ω ≠ 0, so the body-frame hierarchy path) — plus
//! `lowest_clearance` and `underside_submerged` against their references. Criterion measures each
//! side by side; a summary then prints, from its own timings (median of repeats), the ratios.
//!
//! Run: `cargo bench --bench force -- --quick`.
//! Instruction counts (noise-free): `FORCE_COUNT=pose,segments,path,reps` runs only that many
//! evaluations (path: fast, reference, clear, clear_ref, sink, sink_ref) and exits; run it under
//! `valgrind --tool=callgrind` with reps 0 and N and divide the difference by N.

use std::hint::black_box;
use std::time::Instant;

use criterion::Criterion;
use glam::{DQuat, DVec3};
use stoneskip::sim::hydro::{
    evaluate, evaluate_reference, lowest_clearance, lowest_clearance_reference,
    underside_submerged, underside_submerged_reference, FlatSurface, HydroParams, Pose, Scratch,
};
use stoneskip::sim::params::{Physics, Shape, StoneParams};
use stoneskip::sim::stone::Stone;

const POSES: [&str; 4] = ["grazing", "mid", "deep", "free"];

fn lens(segments: u32) -> Stone {
    Stone::new(&StoneParams {
        shape: Shape::Lens {
            radius: 0.05,
            thickness: 0.012,
        },
        mass: 0.1,
        segments,
    })
    .expect("valid stone")
}

/// The default throw's attitude (tilt 20°) and velocity, at a depth of `fraction` of the stone's
/// vertical extent; "free" tilts and banks it and spins it.
fn pose(stone: &Stone, name: &str) -> Pose {
    let free = name == "free";
    let orientation = if free {
        DQuat::from_rotation_x(0.15) * DQuat::from_rotation_y(-0.4)
    } else {
        DQuat::from_rotation_y(-20f64.to_radians())
    };
    let (lo, hi) = stone
        .mesh
        .positions
        .iter()
        .map(|&p| (orientation * p).z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
            (a.min(z), b.max(z))
        });
    let fraction = match name {
        "grazing" => 0.01,
        "deep" => 1.2,
        _ => 0.1,
    };
    Pose {
        position: DVec3::new(0.0, 0.0, -lo - fraction * (hi - lo)),
        velocity: DVec3::new(10.0, 0.0, -1.0),
        orientation,
        angular_velocity: if free {
            DVec3::new(4.0, -3.0, 60.0)
        } else {
            DVec3::ZERO
        },
    }
}

/// Runs `path` once on a prepared case (a persistent scratch, as the simulation keeps one).
fn run(path: &str, stone: &Stone, hp: &HydroParams, p: &Pose, s: &mut Scratch) -> f64 {
    let flat = FlatSurface;
    match path {
        "fast" => evaluate(stone, hp, p, &flat, s, false).force.z,
        "reference" => evaluate_reference(stone, hp, p, &flat, s, false).force.z,
        "clear" => lowest_clearance(stone, p.position, p.orientation, &flat),
        "clear_ref" => lowest_clearance_reference(stone, p.position, p.orientation, &flat),
        "sink" => underside_submerged(stone, p.position, p.orientation, &flat) as u8 as f64,
        _ => underside_submerged_reference(stone, p.position, p.orientation, &flat) as u8 as f64,
    }
}

/// Median wall time of one call (ns) over repeats of a timed batch.
fn median_ns(path: &str, stone: &Stone, hp: &HydroParams, p: &Pose) -> f64 {
    let mut s = Scratch::default();
    run(path, stone, hp, p, &mut s);
    let batch = 200;
    let mut times: Vec<f64> = (0..31)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                black_box(run(path, stone, hp, black_box(p), &mut s));
            }
            t.elapsed().as_secs_f64() * 1e9 / batch as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn count_mode(spec: &str) {
    let parts: Vec<&str> = spec.split(',').collect();
    let [pose_name, segments, path, reps] = parts[..] else {
        eprintln!("FORCE_COUNT=pose,segments,path,reps");
        std::process::exit(2);
    };
    let stone = lens(segments.parse().expect("segments"));
    let hp = HydroParams::from_physics(&Physics::default());
    let p = pose(&stone, pose_name);
    let mut s = Scratch::default();
    let mut acc = run(path, &stone, &hp, &p, &mut s);
    for _ in 0..reps.parse::<u32>().expect("reps") {
        acc += run(path, &stone, &hp, black_box(&p), &mut s);
    }
    println!("{acc}");
}

fn main() {
    if let Ok(spec) = std::env::var("FORCE_COUNT") {
        count_mode(&spec);
        return;
    }
    let hp = HydroParams::from_physics(&Physics::default());
    let mut c = Criterion::default().configure_from_args();
    let cases: Vec<(u32, Stone)> = [32, 96].map(|n| (n, lens(n))).into();
    for (n, stone) in &cases {
        let mut group = c.benchmark_group(format!("force/{n}"));
        for name in POSES {
            let p = pose(stone, name);
            for path in ["fast", "reference"] {
                let mut s = Scratch::default();
                group.bench_function(format!("{name}/{path}"), |b| {
                    b.iter(|| run(path, stone, &hp, black_box(&p), &mut s))
                });
            }
        }
        let p = pose(stone, "mid");
        for path in ["clear", "clear_ref", "sink", "sink_ref"] {
            let mut s = Scratch::default();
            group.bench_function(format!("mid/{path}"), |b| {
                b.iter(|| run(path, stone, &hp, black_box(&p), &mut s))
            });
        }
        group.finish();
    }
    println!("\nsummary (median ns per call; reference / fast):");
    for (n, stone) in &cases {
        for name in POSES {
            let p = pose(stone, name);
            let fast = median_ns("fast", stone, &hp, &p);
            let reference = median_ns("reference", stone, &hp, &p);
            println!(
                "  {n:>3} segments {name:>8}: fast {fast:>9.0} ns, reference {reference:>9.0} ns, ratio {:>6.1}x",
                reference / fast
            );
        }
        let p = pose(stone, "mid");
        for (fast, reference) in [("clear", "clear_ref"), ("sink", "sink_ref")] {
            let f = median_ns(fast, stone, &hp, &p);
            let r = median_ns(reference, stone, &hp, &p);
            println!(
                "  {n:>3} segments {fast:>8}: fast {f:>9.0} ns, reference {r:>9.0} ns, ratio {:>6.1}x",
                r / f
            );
        }
    }
    c.final_summary();
}
