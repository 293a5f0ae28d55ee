//! Water-grid throughput against the memory-bandwidth bound (water.md §6, design.md §5).
//!
//! Criterion measures one water step (column updates per second as its throughput) on a 1024² grid
//! (4 and 8 pipes) and on the default 40 m × 12 m lake at 5 cm (800 × 240 = 192 000 columns), with one
//! thread and with all of them, plus a STREAM-like triad a = b + s·c. A summary then prints, from its own
//! timings (median of repeats), the achieved bytes/s of each grid (bytes per column per step ×
//! columns/s) over the triad's bandwidth, and the CPU share the default lake needs in real time.
//!
//! Run: `cargo bench --bench water -- --quick` (needs `[[bench]] name = "water" harness = false`).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rayon::prelude::*;
use stoneskip::sim::params::WaterParams;
use stoneskip::sim::water::{WaterConfig, WaterGrid};

/// Triad arrays: 3 × 8 B × 2²⁴ = 384 MiB, far past the last-level cache.
const TRIAD_N: usize = 1 << 24;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn square(n: usize, diag: bool) -> WaterGrid {
    let cfg = WaterConfig {
        cell: 0.05,
        depth: 0.3,
        damping: 0.05,
        diagonal_pipes: diag,
        ..WaterConfig::unit(n, n)
    };
    let mut w = WaterGrid::with_config(cfg).expect("valid grid");
    seed_waves(&mut w);
    w
}

fn default_lake() -> WaterGrid {
    let p = WaterParams::default();
    let mut w = WaterGrid::new(&p, p.origin_for([0.0, 0.0]), 9.81, 1000.0).expect("valid preset");
    seed_waves(&mut w);
    w
}

/// A few splashes so that the flows are not all zero (the work per column does not depend on it).
fn seed_waves(w: &mut WaterGrid) {
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

/// A named way to build a grid.
type MakeGrid = fn() -> WaterGrid;

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

fn benches(c: &mut Criterion) {
    let threads = rayon::current_num_threads();
    let mut counts = vec![1];
    if threads > 1 {
        counts.push(threads);
    }

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

    let grids: [(&str, MakeGrid); 3] = [
        ("lake_800x240_8pipe", default_lake),
        ("sq1024_8pipe", || square(1024, true)),
        ("sq1024_4pipe", || square(1024, false)),
    ];
    let mut g = c.benchmark_group("water_step");
    for (name, make) in grids {
        let mut w = make();
        g.throughput(Throughput::Elements((w.nx() * w.ny()) as u64));
        for &t in &counts {
            let p = pool(t);
            g.bench_function(format!("{name}/{t}thr"), |b| {
                b.iter(|| p.install(|| w.step()))
            });
        }
    }
    g.finish();

    summary(&counts);
}

/// Own timings, so the ratios can be printed: columns/s, bytes/s, share of the triad bandwidth.
fn summary(counts: &[usize]) {
    let mut triad = Triad::new();
    println!("\n== water summary (median of repeats) ==");
    let mut bw = Vec::new();
    for &t in counts {
        let p = pool(t);
        let d = median_time(7, || p.install(|| triad.run(3.0)));
        let gbs = 24.0 * TRIAD_N as f64 / d.as_secs_f64() / 1e9;
        println!(
            "triad {t} thread(s): {gbs:.1} GB/s (24 B/element; {:.1} GB/s counting write-allocate)",
            gbs * 32.0 / 24.0
        );
        bw.push(gbs);
    }
    drop(triad);
    let grids: [(&str, MakeGrid); 3] = [
        ("default lake 800×240, 8 pipes", default_lake),
        ("1024², 8 pipes", || square(1024, true)),
        ("1024², 4 pipes", || square(1024, false)),
    ];
    for (name, make) in grids {
        let mut w = make();
        let cols = (w.nx() * w.ny()) as f64;
        let bytes = w.bytes_per_column_step() as f64;
        for (&t, &gbs) in counts.iter().zip(&bw) {
            let p = pool(t);
            let steps = (2e8 / cols).clamp(5.0, 200.0) as usize;
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
            // The triad moves 32 B per element (24 B counted by STREAM + write-allocate of a); the
            // in-place water step moves exactly its bytes per column.
            println!(
                "{name}, {t} thread(s): {:.3} ms/step, {:.1} M columns/s × {bytes} B = {achieved:.1} GB/s = {:.0} % of the triad's {:.1} GB/s of traffic ({:.0} % of its STREAM figure)",
                per_step * 1e3,
                cps / 1e6,
                100.0 * achieved / (gbs * 32.0 / 24.0),
                gbs * 32.0 / 24.0,
                100.0 * achieved / gbs,
            );
            if name.starts_with("default") {
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
