//! Unit tests of the grid's internals: determinism across chunkings and segments, the limiter,
//! deposits.

use super::kernel::kfactor;
use super::storage::Num;
use super::*;
use crate::sim::params::Swell;

const BOTH: [Precision; 2] = [Precision::F64, Precision::F32];

fn grid(nx: usize, ny: usize, diag: bool, limiter: Limiter) -> WaterGrid {
    grid_in(nx, ny, diag, limiter, Precision::F64)
}

fn grid_in(nx: usize, ny: usize, diag: bool, limiter: Limiter, p: Precision) -> WaterGrid {
    let cfg = WaterConfig {
        diagonal_pipes: diag,
        limiter,
        damping: 0.2,
        precision: p,
        ..WaterConfig::unit(nx, ny)
    }
    .with_courant(0.6);
    WaterGrid::with_config(cfg).unwrap()
}

/// The whole stored state (pads included), as bit patterns.
fn bits(w: &WaterGrid) -> Vec<u64> {
    each!(&w.state, f => f.cur.iter().map(|v| v.bits()).collect())
}

/// A scene that uses every path: bed and dry cells, pressure, a violent drop (K active).
fn setup(w: &mut WaterGrid) {
    let (nx, ny) = (w.nx(), w.ny());
    for iy in 0..ny {
        for ix in nx.saturating_sub(3)..nx {
            w.set_bed(ix, iy, 0.4 * (ix + 3 - nx) as f64 - 0.6);
            let b = w.bed(ix, iy);
            w.set_depth(ix, iy, (-b).max(0.0));
        }
    }
    w.set_eta(nx / 3, ny / 2, 2.5);
}

fn scene(w: &mut WaterGrid, steps: usize) {
    setup(w);
    run(w, steps);
}

fn run(w: &mut WaterGrid, steps: usize) {
    let (nx, ny) = (w.nx(), w.ny());
    for s in 0..steps {
        let f = s as f64 / steps as f64;
        w.deposit_impulse(f * nx as f64, (1.0 - f) * ny as f64, 3e4);
        w.deposit_impulse_cell(1, ny - 1, 1e4);
        w.step();
    }
}

/// The segmented row pipeline gives the same bits for any segment length.
#[test]
fn any_segment_length_gives_the_same_result() {
    for (diag, p) in [false, true].into_iter().flat_map(|d| BOTH.map(|p| (d, p))) {
        for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
            let mut reference = grid_in(23, 9, diag, limiter, p);
            scene(&mut reference, 60);
            for seg in [1, 2, 3, 7, 22, 23] {
                let mut w = grid_in(23, 9, diag, limiter, p);
                w.co.seg = seg;
                w.set_chunk_rows(Some(3));
                scene(&mut w, 60);
                assert_eq!(
                    bits(&w),
                    bits(&reference),
                    "diag {diag} {limiter:?} {p:?} seg {seg}"
                );
            }
        }
    }
}

/// The chunked in-place sweep gives the serial result bit for bit, for every chunking (each chunk
/// recomputes its halo from copies of the old neighbouring rows).
#[test]
fn any_chunking_gives_the_serial_result() {
    for (diag, p) in [false, true].into_iter().flat_map(|d| BOTH.map(|p| (d, p))) {
        for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
            for (nx, ny) in [(9, 11), (1, 7), (6, 2)] {
                let mut serial = grid_in(nx, ny, diag, limiter, p);
                serial.set_chunk_rows(Some(usize::MAX));
                scene(&mut serial, 60);
                for rows in [2, 3, 4, 5] {
                    let mut w = grid_in(nx, ny, diag, limiter, p);
                    w.set_chunk_rows(Some(rows));
                    scene(&mut w, 60);
                    assert_eq!(
                        bits(&w),
                        bits(&serial),
                        "diag {diag} {limiter:?} {p:?} {nx}×{ny} rows {rows}"
                    );
                }
            }
        }
    }
}

/// The scene is not trivial: the water moved and the limiter dried a column. Volume is kept to
/// the rounding of the stored depths: ~ulp·√(steps) relative (1e-13 in f64, 1e-6 in f32).
#[test]
fn scene_exercises_the_limiter() {
    for (p, tol, dry) in [(Precision::F64, 1e-13, 1e-9), (Precision::F32, 1e-6, 1e-6)] {
        let mut w = grid_in(9, 11, true, Limiter::MassConserving, p);
        setup(&mut w);
        let v0 = w.volume();
        run(&mut w, 60);
        assert!(w.max_abs_eta() > 0.1);
        let dv = ((w.volume() - v0) / v0).abs();
        assert!(dv < tol, "{p:?}: ΔV/V {dv}");
        assert!(w.min_depth() < dry);
    }
}

/// f32 storage reports its own traffic; readings are f64 either way.
#[test]
fn bytes_per_column_follow_precision_and_pipes() {
    for (diag, p, bytes) in [
        (false, Precision::F32, 24),
        (true, Precision::F32, 40),
        (false, Precision::F64, 48),
        (true, Precision::F64, 80),
    ] {
        let w = grid_in(4, 4, diag, Limiter::MassConserving, p);
        assert_eq!(w.bytes_per_column_step(), bytes);
        assert_eq!(w.precision(), p);
    }
    let mut w = grid_in(4, 4, false, Limiter::MassConserving, Precision::F32);
    w.set_depth(1, 1, 0.1);
    assert_eq!(w.depth(1, 1), f64::from(0.1f32));
}

#[test]
fn chunk_bounds_cover_the_rows() {
    let mut w = grid(4, 37, false, Limiter::MassConserving);
    for rows in [2, 3, 10, 36, 100] {
        w.set_chunk_rows(Some(rows));
        for (r0, r1) in [(0, 37), (5, 9), (20, 37)] {
            let b = w.chunk_bounds(r0, r1, 4 * (r1 - r0));
            assert_eq!(b[0].0, r0);
            assert_eq!(b[b.len() - 1].1, r1);
            for p in b.windows(2) {
                assert_eq!(p[0].1, p[1].0);
            }
            assert!(b.iter().all(|&(a, z)| z - a >= 2));
        }
    }
}

/// A stone's wake over still water: vertical and horizontal impulses along a line at 3 cells a step
/// (faster than the waves, like the stone), then a few steps without any.
fn wake(w: &mut WaterGrid, step: usize) {
    let x = 3.0 + 3.0 * step as f64;
    let y = 0.4 * w.ny() as f64 + 0.05 * step as f64;
    if x < w.nx() as f64 - 2.0 && step % 5 != 4 {
        w.deposit_impulse_box(x, y, 0.7, 2e4);
        w.deposit_momentum_box(x, y, 0.7, [3e3, -1e3]);
        w.deposit_impulse(x - 1.3, y + 0.6, 5e3);
    }
}

/// Stepping only the window where water may move gives the whole grid's result bit for bit, for
/// both stencils, limiters and precisions and any chunking; the window stays smaller than the grid
/// while the wake is young, and nothing outside it has moved.
#[test]
fn stepping_only_the_moving_window_gives_the_whole_grid_result() {
    for (diag, p) in [false, true].into_iter().flat_map(|d| BOTH.map(|p| (d, p))) {
        for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
            for rows in [None, Some(2), Some(5)] {
                let at_rest = grid_in(60, 23, diag, limiter, p);
                let mut all = at_rest.clone();
                all.step_everywhere();
                let mut w = at_rest.clone();
                w.set_chunk_rows(rows);
                assert_eq!(w.active_window(), None);
                let mut smallest = usize::MAX;
                for step in 0..40 {
                    wake(&mut all, step);
                    wake(&mut w, step);
                    all.step();
                    w.step();
                    let case = format!("diag {diag} {limiter:?} {p:?} rows {rows:?} step {step}");
                    assert_eq!(bits(&w), bits(&all), "{case}");
                    let (x0, x1, y0, y1) = w.active_window().expect("the wake moves water");
                    smallest = smallest.min((x1 - x0 + 1) * (y1 - y0 + 1));
                    for iy in 0..w.ny() {
                        for ix in 0..w.nx() {
                            if !(x0..=x1).contains(&ix) || !(y0..=y1).contains(&iy) {
                                assert_eq!(w.depth(ix, iy), at_rest.depth(ix, iy), "{case}");
                            }
                        }
                    }
                }
                assert!(w.max_abs_eta() > 1e-3, "the wake made waves");
                assert!(
                    smallest < 60 * 23 / 4,
                    "the window stayed small: {smallest}"
                );
            }
        }
    }
}

/// A patch gives the grid's own heights bit for bit where it holds the columns, and the grid's
/// elsewhere; once the surface steps, the stale patch is not read.
#[test]
fn a_patch_of_heights_reads_like_the_grid() {
    for p in BOTH {
        let mut w = grid_in(30, 14, true, Limiter::MassConserving, p);
        for step in 0..12 {
            wake(&mut w, step);
            w.step();
        }
        let mut patch = EtaPatch::default();
        w.fill_patch(&mut patch, (4, 17), (2, 9));
        assert_eq!(patch.bounds(), (4, 2, 14, 8));
        let points = (0..2000).map(|k| {
            let k = k as f64;
            (
                (k * 0.618_034).fract() * 34.0 - 2.0,
                (k * 0.414_214).fract() * 18.0 - 2.0,
            )
        });
        let reader = PatchReader::new(&w, &patch);
        for (x, y) in points.clone() {
            let (a, b) = (
                w.surface_height_in(Some(&patch), x, y),
                w.surface_height(x, y),
            );
            assert_eq!(a.to_bits(), b.to_bits(), "{p:?} at ({x}, {y})");
            assert_eq!(
                reader.height(x, y).to_bits(),
                b.to_bits(),
                "{p:?} reader at ({x}, {y})"
            );
        }
        // The highest η over a rectangle inside the patch bounds the surface there and is reached
        // at a column centre inside it; beyond the patch there is no answer.
        for (k, (x, y)) in points.clone().take(300).enumerate() {
            let (hx, hy) = (0.1 + 0.02 * (k % 97) as f64, 0.1 + 0.015 * (k % 89) as f64);
            let (lo, hi) = ([x - hx, y - hy], [x + hx, y + hy]);
            let held = lo[0] >= 4.5 && hi[0] < 17.5 && lo[1] >= 2.5 && hi[1] < 9.5;
            let Some(m) = reader.max_height_over(lo, hi) else {
                assert!(!held, "{lo:?} {hi:?} is inside the patch");
                continue;
            };
            let mut seen = f64::NEG_INFINITY;
            for i in 0..=40 {
                for j in 0..=40 {
                    let (px, py) = (
                        lo[0] + 2.0 * hx * i as f64 / 40.0,
                        lo[1] + 2.0 * hy * j as f64 / 40.0,
                    );
                    seen = seen.max(w.surface_height(px.min(hi[0]), py.min(hi[1])));
                }
            }
            assert!(
                seen <= m,
                "{p:?}: {seen} above the bound {m} over {lo:?}..{hi:?}"
            );
        }
        wake(&mut w, 12);
        w.step();
        let moved = points.clone().any(|(x, y)| {
            let (gx, gy) = (x.clamp(4.0, 17.0), y.clamp(2.0, 9.0));
            patch.at(gx as usize, gy as usize) != w.eta(gx as usize, gy as usize)
        });
        assert!(moved, "the step changed the patch's columns");
        let reader = PatchReader::new(&w, &patch);
        for (x, y) in points {
            let (a, b) = (
                w.surface_height_in(Some(&patch), x, y),
                w.surface_height(x, y),
            );
            assert_eq!(a.to_bits(), b.to_bits(), "{p:?} stale patch at ({x}, {y})");
            assert_eq!(
                reader.height(x, y).to_bits(),
                b.to_bits(),
                "{p:?} stale reader"
            );
        }
        assert_eq!(
            reader.max_height_over([5.0, 3.0], [6.0, 4.0]),
            None,
            "stale"
        );
    }
}

/// A face's load deposited at once (one footprint for both parts) leaves the grid as the two
/// separate deposits do, bit for bit: points, boxes over one and many cells, at the edges, and the
/// values each part ignores.
#[test]
fn a_load_deposited_at_once_is_the_two_deposits() {
    for p in BOTH {
        let mut a = grid_in(20, 9, false, Limiter::MassConserving, p);
        let mut b = grid_in(20, 9, false, Limiter::MassConserving, p);
        let loads = (0..400).map(|k| {
            let f = k as f64;
            let x = (f * 0.618_034).fract() * 22.0 - 1.0;
            let y = (f * 0.414_214).fract() * 11.0 - 1.0;
            let half = [0.0, 1e-9, 0.2, 0.45, 1.3, 6.0, f64::NAN][k % 7];
            let impulse = [3.0, -1.5, 0.0, f64::INFINITY][k % 4];
            let j = [
                [0.4, -0.2],
                [0.0, 0.0],
                [f64::NAN, 1.0],
                [1.0, 0.0],
                [-2.0, 3.0],
            ][k % 5];
            (x, y, half, impulse, j)
        });
        for (step, chunk) in loads.collect::<Vec<_>>().chunks(50).enumerate() {
            for &(x, y, half, impulse, j) in chunk {
                a.deposit_load_box(x, y, half, impulse, j);
                b.deposit_impulse_box(x, y, half, impulse);
                b.deposit_momentum_box(x, y, half, j);
            }
            assert_eq!(
                a.impulse_received().to_bits(),
                b.impulse_received().to_bits()
            );
            a.step();
            b.step();
            assert_eq!(
                a.momentum_received(),
                b.momentum_received(),
                "{p:?} step {step}"
            );
            for iy in 0..9 {
                for ix in 0..20 {
                    assert_eq!(a.eta(ix, iy).to_bits(), b.eta(ix, iy).to_bits());
                    for pipe in 0..2 {
                        assert_eq!(
                            a.flow(ix, iy, pipe).to_bits(),
                            b.flow(ix, iy, pipe).to_bits()
                        );
                    }
                }
            }
        }
    }
}

/// K never divides by zero: dry, negative-by-rounding and idle columns give finite factors.
#[test]
fn k_factor_is_always_finite() {
    for (d, o) in [
        (0.0, 0.0),
        (0.0, 1.0),
        (-1e-20, 0.0),
        (-1e-20, 1.0),
        (1.0, 0.0),
        (1.0, 4.0),
    ] {
        let k: f64 = kfactor(d, o);
        assert!(k.is_finite() && (0.0..=1.0).contains(&k), "{d} {o} {k}");
    }
    assert_eq!(kfactor(1.0f64, 4.0), 0.25);
    assert_eq!(kfactor(0.0f32, 0.0), 1.0);
}

/// Sampling at a column centre gives that column's η; between centres it is linear.
#[test]
fn surface_height_is_bilinear_on_column_centres() {
    let mut w = grid(5, 4, false, Limiter::MassConserving);
    w.cfg.origin = [10.0, -2.0];
    w.set_eta(2, 1, 0.4);
    assert!((w.surface_height(12.5, -0.5) - 0.4).abs() < 1e-15);
    assert!((w.surface_height(13.0, -0.5) - 0.2).abs() < 1e-15);
    assert!((w.surface_height(12.5, -0.25) - 0.3).abs() < 1e-15);
    assert_eq!(w.surface_height(9.9, 0.0), 0.0);
    assert_eq!(w.surface_height(15.0, 0.0), 0.0);
    // The outer half cell takes the edge column.
    w.set_eta(0, 0, 0.1);
    assert!((w.surface_height(10.1, -1.9) - 0.1).abs() < 1e-15);
}

/// No gravity: no waves and no restoring force, but pressure still pushes water; nothing is NaN.
#[test]
fn zero_gravity_stays_finite() {
    let cfg = WaterConfig {
        gravity: 0.0,
        ..WaterConfig::unit(8, 8)
    };
    let mut w = WaterGrid::with_config(cfg).unwrap();
    assert_eq!(w.step_dt(), MAX_STEP);
    let v0 = w.volume();
    for _ in 0..50 {
        w.deposit_impulse(4.0, 4.0, 1e5);
        w.step();
    }
    assert!(w.max_abs_eta().is_finite() && w.max_abs_eta() > 0.0);
    assert!(w.min_depth() >= -1e-15);
    assert!(((w.volume() - v0) / v0).abs() < 1e-13);
}

/// The swell starts as the preset says: η = A sin(k n·x) at the column centres.
#[test]
fn swell_sets_the_initial_surface() {
    let mut w = grid(40, 6, true, Limiter::MassConserving);
    w.set_swell(&Swell {
        amplitude: 0.1,
        wavelength: 10.0,
        heading_deg: 0.0,
    });
    let k = 2.0 * std::f64::consts::PI / 10.0;
    for ix in 0..40 {
        let e = 0.1 * (k * (ix as f64 + 0.5)).sin();
        assert!((w.eta(ix, 3) - e).abs() < 1e-15);
    }
    assert!(w.flow(5, 3, 0) != 0.0 && w.flow(5, 3, 1) == 0.0);
}

// --- the box footprint ---------------------------------------------------------------------

/// The deposited impulse of every column, row-major.
fn pending_field(w: &WaterGrid) -> Vec<f64> {
    if w.pending.is_empty() {
        vec![0.0; w.nx() * w.ny()]
    } else {
        w.pending.clone()
    }
}

fn box_grid(n: usize, cell: f64, origin: [f64; 2]) -> WaterGrid {
    WaterGrid::with_config(WaterConfig {
        cell,
        origin,
        ..WaterConfig::unit(n, n)
    })
    .unwrap()
}

/// The parts sum to the impulse (to rounding), inside, across an edge and in a corner.
#[test]
fn box_deposit_keeps_the_impulse() {
    for (x, y, half) in [
        (3.37, 4.81, 0.9),
        (0.2, 4.0, 1.3),
        (7.9, 0.1, 2.2),
        (5.0, 5.0, 40.0),
        (1.23, 6.54, 0.3),
    ] {
        let mut w = box_grid(8, 1.0, [0.0, 0.0]);
        w.deposit_impulse_box(x, y, half, 7.5);
        let sum: f64 = pending_field(&w).iter().sum();
        assert!((sum / 7.5 - 1.0).abs() < 1e-14, "({x}, {y}, {half}): {sum}");
        assert!(pending_field(&w).iter().all(|&p| p >= 0.0));
    }
}

/// A square that is exactly one cell gives that cell everything; one covering four cells' quarters
/// gives each a quarter; a point-sized square falls back to the bilinear deposit.
#[test]
fn box_deposit_on_cells() {
    let mut w = box_grid(6, 0.5, [-1.0, 2.0]);
    w.deposit_impulse_box(-1.0 + 2.25, 2.0 + 1.75, 0.25, 3.0);
    let p = pending_field(&w);
    assert_eq!(p[3 * 6 + 4], 3.0);
    assert_eq!(p.iter().filter(|&&v| v != 0.0).count(), 1);

    let mut w = box_grid(6, 0.5, [-1.0, 2.0]);
    w.deposit_impulse_box(-1.0 + 1.0, 2.0 + 1.5, 0.25, 2.0);
    let p = pending_field(&w);
    for (ix, iy) in [(1, 2), (2, 2), (1, 3), (2, 3)] {
        assert_eq!(p[iy * 6 + ix], 0.5, "({ix}, {iy})");
    }
    assert_eq!(p.iter().filter(|&&v| v != 0.0).count(), 4);

    for half in [0.0, -1.0, 1e-9] {
        let mut a = box_grid(6, 0.5, [-1.0, 2.0]);
        let mut b = box_grid(6, 0.5, [-1.0, 2.0]);
        a.deposit_impulse_box(0.13, 3.31, half, 2.0);
        b.deposit_impulse(0.13, 3.31, 2.0);
        assert_eq!(pending_field(&a), pending_field(&b), "half {half}");
    }
    // Outside the grid or not finite: nothing.
    let mut w = box_grid(6, 0.5, [-1.0, 2.0]);
    w.deposit_impulse_box(-1.01, 3.0, 0.5, 1.0);
    w.deposit_impulse_box(0.0, 3.0, f64::NAN, 1.0);
    w.deposit_impulse_box(0.0, 3.0, f64::INFINITY, 1.0);
    w.deposit_impulse_box(0.0, f64::NAN, 0.5, 1.0);
    w.deposit_impulse_box(0.0, 3.0, 0.5, f64::INFINITY);
    assert_eq!(w.pending_impulse(), 0.0);
}

/// A square centred on a symmetric grid gives a deposit with the square's 8 symmetries.
#[test]
fn box_deposit_is_symmetric() {
    let n = 9;
    let mut w = box_grid(n, 0.1, [0.0, 0.0]);
    w.deposit_impulse_box(0.45, 0.45, 0.27, 1.0);
    let p = pending_field(&w);
    let at = |ix: usize, iy: usize| p[iy * n + ix];
    for iy in 0..n {
        for ix in 0..n {
            let v = at(ix, iy);
            for m in [
                at(iy, ix),
                at(n - 1 - ix, iy),
                at(ix, n - 1 - iy),
                at(n - 1 - iy, n - 1 - ix),
            ] {
                assert!((v - m).abs() <= 1e-15, "({ix}, {iy}): {v} vs {m}");
            }
        }
    }
    // Cells inside the square take the impulse × their share of its area, l²/(2·half)².
    assert!((at(4, 4) - 0.01 / (0.54 * 0.54)).abs() < 1e-14);
}

/// Convergence: once the cells are smaller than the square, halving them does not change the
/// pressure footprint: the four fine columns of each coarse column take exactly its impulse (the
/// overlap areas add up), also where the square crosses the edge.
#[test]
fn box_footprint_does_not_change_when_the_cell_is_halved() {
    for (x, y, half) in [(0.937, 1.012, 0.31), (0.05, 1.71, 0.26), (1.0, 1.0, 0.2)] {
        let mut coarse = box_grid(20, 0.1, [0.0, 0.0]);
        let mut fine = box_grid(40, 0.05, [0.0, 0.0]);
        coarse.deposit_impulse_box(x, y, half, 1.0);
        fine.deposit_impulse_box(x, y, half, 1.0);
        let (c, f) = (pending_field(&coarse), pending_field(&fine));
        for iy in 0..20 {
            for ix in 0..20 {
                let sum: f64 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .map(|&(dx, dy)| f[(2 * iy + dy) * 40 + 2 * ix + dx])
                    .sum();
                let want = c[iy * 20 + ix];
                assert!(
                    (sum - want).abs() < 1e-14,
                    "({x}, {y}) cell ({ix}, {iy}): fine {sum} coarse {want}"
                );
            }
        }
    }
}

/// `water.max_step` caps the automatic step (a shorter step is always stable), keeps it capped when
/// gravity changes live, and leaves the automatic step alone when it is longer than the step.
#[test]
fn a_preset_can_cap_the_water_step() {
    use crate::sim::params::WaterParams;
    let auto = WaterGrid::new(&WaterParams::version_1(), [0.0, 0.0], 9.81, 1000.0).unwrap();
    let capped_params = WaterParams {
        max_step: Some(0.25 * auto.step_dt()),
        ..WaterParams::version_1()
    };
    let mut capped = WaterGrid::new(&capped_params, [0.0, 0.0], 9.81, 1000.0).unwrap();
    assert_eq!(capped.step_dt(), 0.25 * auto.step_dt());
    // Four times the gravity halves the Courant step: still under it, and still capped.
    capped.set_constants(4.0 * 9.81, 1000.0).unwrap();
    assert!(capped.step_dt() <= 0.25 * auto.step_dt());
    assert!(capped.courant() <= capped.courant_limit());
    let loose = WaterParams {
        max_step: Some(0.1),
        ..WaterParams::version_1()
    };
    let w = WaterGrid::new(&loose, [0.0, 0.0], 9.81, 1000.0).unwrap();
    assert_eq!(w.step_dt(), auto.step_dt());
    let bad = WaterParams {
        max_step: Some(0.0),
        ..WaterParams::version_1()
    };
    assert_eq!(bad.validate().unwrap_err().field, "water.max_step");
}
