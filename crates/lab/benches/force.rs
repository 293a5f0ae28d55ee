//! One force evaluation (issue 12): the fast kernel (`hydro::evaluate`) against the scalar
//! reference (`hydro::evaluate_reference`) on the default lens at 32, 64 and 96 segments, in four
//! poses — grazing (lowest vertex 1 % of the vertical extent under), mid-contact (10 %), deep
//! (wholly under) and free rotation (mid-contact, ω ≠ 0, so the body-frame ring path) — plus
//! `lowest_clearance` and `underside_submerged` against their references, and the free pose on
//! wavy water (`wavy`: a ripple of the near field's scale, with the shipped default's physics,
//! buoyancy on every wetted face included, so the depths read the surface). Criterion measures each
//! side by side; a summary then prints, from its own timings (median of repeats), the ratios.
//!
//! Run: `cargo bench --bench force -- --quick`.
//! Instruction counts (noise-free): `FORCE_COUNT=pose,segments,path,reps` runs only that many
//! evaluations (path: fast, reference, clear, clear_ref, sink, sink_ref) and exits; run it under
//! `valgrind --tool=callgrind` with reps 0 and N and divide the difference by N.
//! Whole throws: `FORCE_THROW=preset.ron,segments,reps[,tolerance[,locked]]` runs the preset with
//! the water off at that mesh (optionally at another tolerance, or with the attitude locked) and
//! prints the real-time factor (simulated / wall seconds, best of the repeats) and the result; `FORCE_MESH=1` prints, for the default throw and the accuracy study's three throws, the
//! distance and skips per mesh and tolerance against a 192-segment, tolerance-1e-8 run.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::time::Instant;

use criterion::Criterion;
use glam::{DQuat, DVec3};
use stoneskip_lab::study::throws;
use stoneskip_physics::sim::hydro::{
    evaluate, evaluate_reference, lowest_clearance, lowest_clearance_reference,
    underside_submerged, underside_submerged_reference, FlatSurface, HydroParams, Pose, Scratch,
    Surface,
};
use stoneskip_physics::sim::params::{Integrator, Physics, Preset, Quadrature, Shape, StoneParams};
use stoneskip_physics::sim::stone::Stone;
use stoneskip_physics::sim::{simulate, Summary};

const POSES: [&str; 4] = ["grazing", "mid", "deep", "free"];

/// The free pose on wavy water (the meshes only: the smooth quadrature refuses wavy contact).
const WAVY: &str = "wavy";

/// Wavy water at the near field's scale: crests 1 cm high, 8 cm apart along x and 11 cm along y.
struct Ripple;

impl Surface for Ripple {
    fn height(&self, x: f64, y: f64) -> f64 {
        0.01 * (std::f64::consts::TAU * x / 0.08 + 0.7).sin()
            * (std::f64::consts::TAU * y / 0.11).cos()
    }
    fn max_height(&self) -> f64 {
        0.01
    }
}

/// The force constants of a pose: the shipped default's physics on wavy water, else the
/// paper's defaults.
fn params(name: &str) -> HydroParams {
    if name == WAVY {
        let p = stoneskip_physics::preset::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../assets/presets/default.ron"
        )))
        .expect("shipped preset");
        HydroParams::from_physics(&p.physics)
    } else {
        HydroParams::from_physics(&Physics::version_1())
    }
}

/// The surface of a pose.
fn surface(name: &str) -> &'static dyn Surface {
    if name == WAVY {
        &Ripple
    } else {
        &FlatSurface
    }
}

fn lens(segments: u32) -> Stone {
    lens_with(segments, Quadrature::Faces)
}

/// The lens with `quadrature` (its mesh at `segments` places the poses and draws it).
fn lens_with(segments: u32, quadrature: Quadrature) -> Stone {
    Stone::new(&StoneParams {
        shape: Shape::Lens {
            radius: 0.05,
            thickness: 0.012,
        },
        mass: 0.1,
        segments,
        bands: None,
        quadrature,
    })
    .expect("valid stone")
}

/// The smooth quadrature benched beside the meshes: (meridian, around) nodes.
const SMOOTH: (u32, u32) = (12, 2);

/// The default throw's attitude (tilt 20°) and velocity, at a depth of `fraction` of the stone's
/// vertical extent; "free" tilts and banks it and spins it.
fn pose(stone: &Stone, name: &str) -> Pose {
    let free = name == "free" || name == WAVY;
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

/// Runs `path` once on a prepared case over `w` (a persistent scratch, as the simulation keeps one).
fn run(
    path: &str,
    stone: &Stone,
    hp: &HydroParams,
    p: &Pose,
    w: &dyn Surface,
    s: &mut Scratch,
) -> f64 {
    match path {
        "fast" => evaluate(stone, hp, p, w, s, false).force.z,
        "reference" => evaluate_reference(stone, hp, p, w, s, false).force.z,
        "clear" => lowest_clearance(stone, p.position, p.orientation, w),
        "clear_ref" => lowest_clearance_reference(stone, p.position, p.orientation, w),
        "sink" => underside_submerged(stone, p.position, p.orientation, w) as u8 as f64,
        _ => underside_submerged_reference(stone, p.position, p.orientation, w) as u8 as f64,
    }
}

/// Median wall time of one call (ns) over repeats of a timed batch.
fn median_ns(path: &str, stone: &Stone, hp: &HydroParams, p: &Pose, w: &dyn Surface) -> f64 {
    let mut s = Scratch::default();
    run(path, stone, hp, p, w, &mut s);
    let batch = 200;
    let mut times: Vec<f64> = (0..31)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                black_box(run(path, stone, hp, black_box(p), w, &mut s));
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
    let (hp, w) = (params(pose_name), surface(pose_name));
    let p = pose(&stone, pose_name);
    let mut s = Scratch::default();
    let mut acc = run(path, &stone, &hp, &p, w, &mut s);
    for _ in 0..reps.parse::<u32>().expect("reps") {
        acc += run(path, &stone, &hp, black_box(&p), w, &mut s);
    }
    println!("{acc}");
}

/// Runs `p` `reps` times; the best wall time (s) and the summary.
fn time_throw(p: &Preset, reps: u32) -> (f64, Summary) {
    let mut best = f64::INFINITY;
    let mut summary = None;
    for _ in 0..reps.max(1) {
        let t = Instant::now();
        let s = simulate(black_box(p)).expect("runs");
        best = best.min(t.elapsed().as_secs_f64());
        summary = Some(s);
    }
    (best, summary.expect("at least one run"))
}

fn describe(s: &Summary) -> String {
    format!(
        "{} skips, distance {:.12} m, {:.4} s, {} steps, {} force evaluations, {:?}",
        s.skips, s.distance, s.final_time, s.steps, s.force_evals, s.outcome
    )
}

fn throw_mode(spec: &str) {
    let parts: Vec<&str> = spec.split(',').collect();
    let (path, segments, reps) = match parts[..] {
        [path, segments, reps, ..] => (path, segments, reps),
        _ => {
            eprintln!("FORCE_THROW=preset.ron,segments,reps[,tolerance[,locked]]");
            std::process::exit(2);
        }
    };
    let mut p = stoneskip_physics::preset::load(std::path::Path::new(path)).expect("preset");
    p.water.enabled = false;
    p.stone.segments = segments.parse().expect("segments");
    if let Some(tolerance) = parts.get(3) {
        p.physics.tolerance = tolerance.parse().expect("tolerance");
    }
    if parts.get(4) == Some(&"locked") {
        p.physics.rotation = stoneskip_physics::sim::params::Rotation::Locked;
    }
    let (wall, s) = time_throw(&p, reps.parse().expect("reps"));
    println!(
        "{path} at {segments} segments, water off: {:.2} ms, {:.0}x real time; {}",
        wall * 1e3,
        s.final_time / wall,
        describe(&s)
    );
}

/// Distance and skips per mesh and tolerance against a fine reference, for the default throw and
/// the accuracy study's throws.
fn mesh_mode() {
    let mut cases: Vec<(String, Preset)> = Vec::new();
    let mut default = stoneskip_physics::preset::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/presets/default.ron"
    )))
    .expect("shipped preset");
    default.water.enabled = false;
    cases.push(("default".into(), default));
    let base = throws::base(Integrator::Adaptive, 0.005, 1e-6);
    for t in throws::THROWS {
        cases.push((t.key.into(), throws::preset(&t, &base).expect("throw")));
    }
    for (name, case) in &cases {
        let with = |segments: u32, tolerance: f64| {
            let mut p = case.clone();
            p.stone.segments = segments;
            p.physics.tolerance = tolerance;
            if name != "default" {
                // The study throws start just above the water: place each mesh the same way.
                let t = throws::THROWS
                    .iter()
                    .find(|t| t.key == name)
                    .expect("known throw");
                let b = Preset {
                    stone: p.stone,
                    physics: p.physics,
                    ..throws::base(Integrator::Adaptive, 0.005, tolerance)
                };
                p = throws::preset(t, &b).expect("throw");
            }
            p
        };
        let (_, fine) = time_throw(&with(192, 1e-8), 1);
        println!("{name}: 192 segments, tolerance 1e-8: {}", describe(&fine));
        for segments in [32, 48, 64, 96, 128, 192] {
            for tolerance in [1e-6, 1e-5, 3e-5] {
                let (wall, s) = time_throw(&with(segments, tolerance), 1);
                println!(
                    "  {segments:>3} segments, tol {tolerance:.0e}: distance {:+.3} % off, skips {} ({:+}), {} evals, {:.0}x real time",
                    100.0 * (s.distance - fine.distance) / fine.distance,
                    s.skips,
                    s.skips as i64 - fine.skips as i64,
                    s.force_evals,
                    s.final_time / wall
                );
            }
        }
    }
}

fn main() {
    if let Ok(spec) = std::env::var("FORCE_COUNT") {
        count_mode(&spec);
        return;
    }
    if let Ok(spec) = std::env::var("FORCE_THROW") {
        throw_mode(&spec);
        return;
    }
    if std::env::var("FORCE_MESH").is_ok() {
        mesh_mode();
        return;
    }
    let hp = params("mid");
    let flat = &FlatSurface;
    let mut c = Criterion::default().configure_from_args();
    let cases: Vec<(u32, Stone)> = [32, 64, 96].map(|n| (n, lens(n))).into();
    let meshes_poses = || POSES.into_iter().chain([WAVY]);
    for (n, stone) in &cases {
        let mut group = c.benchmark_group(format!("force/{n}"));
        for name in meshes_poses() {
            let (p, hp, w) = (pose(stone, name), params(name), surface(name));
            for path in ["fast", "reference"] {
                let mut s = Scratch::default();
                group.bench_function(format!("{name}/{path}"), |b| {
                    b.iter(|| run(path, stone, &hp, black_box(&p), w, &mut s))
                });
            }
        }
        let p = pose(stone, "mid");
        for path in ["clear", "clear_ref", "sink", "sink_ref"] {
            let mut s = Scratch::default();
            group.bench_function(format!("mid/{path}"), |b| {
                b.iter(|| run(path, stone, &hp, black_box(&p), flat, &mut s))
            });
        }
        group.finish();
    }
    let (meridian, around) = SMOOTH;
    let smooth = lens_with(64, Quadrature::Smooth { meridian, around });
    let mut group = c.benchmark_group(format!("force/smooth {meridian}x{around}"));
    for name in POSES {
        let p = pose(&smooth, name);
        let mut s = Scratch::default();
        group.bench_function(name, |b| {
            b.iter(|| run("fast", &smooth, &hp, black_box(&p), flat, &mut s))
        });
    }
    group.finish();
    println!("\nsummary (median ns per call; reference / fast):");
    for (n, stone) in &cases {
        for name in meshes_poses() {
            let (p, hp, w) = (pose(stone, name), params(name), surface(name));
            let fast = median_ns("fast", stone, &hp, &p, w);
            let reference = median_ns("reference", stone, &hp, &p, w);
            println!(
                "  {n:>3} segments {name:>8}: fast {fast:>9.0} ns, reference {reference:>9.0} ns, ratio {:>6.1}x",
                reference / fast
            );
        }
        let p = pose(stone, "mid");
        for (fast, reference) in [("clear", "clear_ref"), ("sink", "sink_ref")] {
            let f = median_ns(fast, stone, &hp, &p, flat);
            let r = median_ns(reference, stone, &hp, &p, flat);
            println!(
                "  {n:>3} segments {fast:>8}: fast {f:>9.0} ns, reference {r:>9.0} ns, ratio {:>6.1}x",
                r / f
            );
        }
    }
    for name in POSES {
        let p = pose(&smooth, name);
        let sm = median_ns("fast", &smooth, &hp, &p, flat);
        let faces: Vec<String> = cases
            .iter()
            .map(|(n, stone)| {
                let f = median_ns("fast", stone, &hp, &p, flat);
                format!("{n} faces {:.1}x", f / sm)
            })
            .collect();
        println!(
            "  smooth {meridian}x{around} {name:>8}: {sm:>9.0} ns; the meshes' fast path over it: {}",
            faces.join(", ")
        );
    }
    c.final_summary();
}
