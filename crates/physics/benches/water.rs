//! Water-grid throughput against the memory-bandwidth bound (water.md §6, design.md §5).
//!
//! Criterion measures one water step (column updates per second as its throughput) in f32 and f64
//! storage, with 4 and 8 pipes, on 1024² and 2000² grids (2048² is past the 4 M columns a grid may
//! have; 2000² is the largest square allowed) and on the default 40 m × 12 m lake at 5 cm
//! (800 × 240 = 192 000 columns, 8 pipes), with one thread and with all of them, plus a STREAM-like
//! triad a = b + s·c (f64, 24 B/element, 32 B counting the write-allocate of a). A summary then
//! prints, from its own timings (median of repeats, the triad timed the same way in the same run), for
//! each case: columns/s, bytes per column, the achieved GB/s and its share of the triad bandwidth,
//! and the ratio of columns/s to water.md §6.2's bound for a fused f32 4-pipe pass, triad bandwidth /
//! 28 B per column, flagged "within 2×" when it is ≥ 0.5.
//!
//! Run: `cargo bench --bench water -- --quick` (needs `[[bench]] name = "water" harness = false`).
//! `WATER_CASES=sq2000_4pipe_f32` (a substring) keeps only the matching cases, in both parts.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rayon::prelude::*;
use stoneskip_physics::sim::params::{Precision, WaterParams};
use stoneskip_physics::sim::water::{WaterConfig, WaterGrid};

/// Triad arrays: 3 × 8 B × 2²⁴ = 384 MiB, far past the last-level cache.
const TRIAD_N: usize = 1 << 24;
/// water.md §6.2: bytes per column of a fused f32 4-pipe pass (reads d, b, Qx, Qy; writes d, Qx, Qy).
const BOUND_BYTES: f64 = 28.0;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn square(n: usize, diag: bool, precision: Precision) -> WaterGrid {
    let cfg = WaterConfig {
        cell: 0.05,
        depth: 0.3,
        damping: 0.05,
        diagonal_pipes: diag,
        precision,
        ..WaterConfig::unit(n, n)
    };
    let mut w = WaterGrid::with_config(cfg).expect("valid grid");
    seed_waves(&mut w);
    w
}

fn default_lake(precision: Precision) -> WaterGrid {
    let p = WaterParams {
        precision,
        ..WaterParams::version_1()
    };
    let mut w = WaterGrid::new(&p, p.origin_for([0.0, 0.0]), 9.81, 1000.0).expect("valid preset");
    seed_waves(&mut w);
    w
}

/// A few splashes so that the flows are not all zero (the work per column does not depend on it).
/// Every column is stepped, moving or not: this measures the sweep per column, not the window.
fn seed_waves(w: &mut WaterGrid) {
    w.step_everywhere();
    let [ox, oy] = w.origin();
    let (sx, sy) = (w.nx() as f64 * w.cell(), w.ny() as f64 * w.cell());
    for k in 1..8 {
        let f = k as f64 / 8.0;
        w.deposit_impulse(ox + f * sx, oy + (1.0 - f) * sy, 0.5);
    }
    for _ in 0..20 {
        w.step();
    }
}

/// One benchmarked grid: a name and how to build it.
struct Case {
    name: String,
    make: Box<dyn Fn() -> WaterGrid>,
}

/// Every case: both precisions, the default lake and 4- and 8-pipe squares of 1024² and 2000².
fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (p, tag) in [(Precision::F32, "f32"), (Precision::F64, "f64")] {
        out.push(Case {
            name: format!("lake_800x240_8pipe_{tag}"),
            make: Box::new(move || default_lake(p)),
        });
        for n in [1024, 2000] {
            for (diag, pipes) in [(false, 4), (true, 8)] {
                out.push(Case {
                    name: format!("sq{n}_{pipes}pipe_{tag}"),
                    make: Box::new(move || square(n, diag, p)),
                });
            }
        }
    }
    match std::env::var("WATER_CASES") {
        Ok(f) => out.into_iter().filter(|c| c.name.contains(&f)).collect(),
        Err(_) => out,
    }
}

struct Triad {
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
}

impl Triad {
    fn new() -> Self {
        Self {
            a: vec![0.0; TRIAD_N],
            b: vec![1.0; TRIAD_N],
            c: vec![2.0; TRIAD_N],
        }
    }
    /// a = b + s·c in parallel blocks of the current pool.
    fn run(&mut self, s: f64) {
        const BLOCK: usize = 1 << 16;
        self.a
            .par_chunks_mut(BLOCK)
            .zip(self.b.par_chunks(BLOCK))
            .zip(self.c.par_chunks(BLOCK))
            .for_each(|((a, b), c)| {
                for ((a, &b), &c) in a.iter_mut().zip(b).zip(c) {
                    *a = b + s * c;
                }
            });
        black_box(&self.a);
    }
}

/// Median wall time of `f` over `reps` runs (after one warm-up).
fn median_time(reps: usize, mut f: impl FnMut()) -> Duration {
    f();
    let mut t: Vec<Duration> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed()
        })
        .collect();
    t.sort();
    t[reps / 2]
}

fn thread_counts() -> Vec<usize> {
    let threads = rayon::current_num_threads();
    let mut counts = vec![1];
    if threads > 1 {
        counts.push(threads);
    }
    counts
}

fn benches(c: &mut Criterion) {
    let counts = thread_counts();

    let mut g = c.benchmark_group("triad");
    g.throughput(Throughput::Bytes(24 * TRIAD_N as u64));
    let mut triad = Triad::new();
    for &t in &counts {
        let p = pool(t);
        g.bench_function(format!("{t}thr"), |b| {
            b.iter(|| p.install(|| triad.run(3.0)))
        });
    }
    g.finish();
    drop(triad);

    let mut g = c.benchmark_group("water_step");
    for case in cases() {
        let mut w = (case.make)();
        g.throughput(Throughput::Elements((w.nx() * w.ny()) as u64));
        for &t in &counts {
            let p = pool(t);
            g.bench_function(format!("{}/{t}thr", case.name), |b| {
                b.iter(|| p.install(|| w.step()))
            });
        }
    }
    g.finish();

    summary(&counts);
}

/// Own timings, so the ratios can be printed: columns/s, bytes/s, share of the triad bandwidth, and
/// columns/s over the 28 B/column bound.
fn summary(counts: &[usize]) {
    let mut triad = Triad::new();
    println!("\n== water summary (median of repeats) ==");
    let mut bw = Vec::new();
    for &t in counts {
        let p = pool(t);
        let d = median_time(7, || p.install(|| triad.run(3.0)));
        let gbs = 24.0 * TRIAD_N as f64 / d.as_secs_f64() / 1e9;
        println!(
            "triad {t} thread(s): {gbs:.1} GB/s (24 B/element; {:.1} GB/s counting write-allocate): bound {:.0} M columns/s at {BOUND_BYTES} B/column",
            gbs * 32.0 / 24.0,
            gbs * 1e3 / BOUND_BYTES,
        );
        bw.push(gbs);
    }
    drop(triad);
    println!(
        "{:<26} {:>3} {:>9} {:>10} {:>5} {:>7} {:>7} {:>7} {:>8}",
        "case", "thr", "ms/step", "Mcol/s", "B/col", "GB/s", "%triad", "%tr+WA", "vs 28 B"
    );
    for case in cases() {
        let mut w = (case.make)();
        let cols = (w.nx() * w.ny()) as f64;
        let bytes = w.bytes_per_column_step() as f64;
        for (&t, &gbs) in counts.iter().zip(&bw) {
            let p = pool(t);
            let steps = (1e8 / cols).clamp(5.0, 200.0) as usize;
            let d = median_time(5, || {
                p.install(|| {
                    for _ in 0..steps {
                        w.step();
                    }
                })
            });
            let per_step = d.as_secs_f64() / steps as f64;
            let cps = cols / per_step;
            let achieved = cps * bytes / 1e9;
            // The bound: the triad's bandwidth (STREAM's 24 B count) over 28 B per column.
            let ratio = cps / (gbs * 1e9 / BOUND_BYTES);
            println!(
                "{:<26} {t:>3} {:>9.3} {:>10.1} {bytes:>5} {achieved:>7.1} {:>6.0}% {:>6.0}% {ratio:>8.2} {}",
                case.name,
                per_step * 1e3,
                cps / 1e6,
                100.0 * achieved / gbs,
                100.0 * achieved / (gbs * 32.0 / 24.0),
                if ratio >= 0.5 { "within 2×" } else { "NOT within 2×" },
            );
            if case.name.starts_with("lake") {
                let rate = 1.0 / w.step_dt();
                println!(
                    "    real time needs {rate:.1} steps/s (Δt_w = {:.4} s, r = {:.3}): {:.1} % of the wall clock on {t} thread(s)",
                    w.step_dt(),
                    w.courant(),
                    100.0 * rate * per_step
                );
            }
        }
    }
    println!(
        "columns: %triad = achieved GB/s over the triad's 24 B/element figure, %tr+WA over its 32 B traffic; \
         vs 28 B = columns/s over (triad GB/s / {BOUND_BYTES} B), the fused f32 4-pipe bound (water.md §6.2)"
    );
}

criterion_group! {
    name = water;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = benches
}
criterion_main!(water);
