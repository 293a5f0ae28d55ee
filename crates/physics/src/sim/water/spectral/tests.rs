//! The spectral near field against the linear theory it integrates: exact modes, the dispersion
//! relation, exact constant-pressure forcing, volume, symmetry, the sponge and the moving patch.

use super::*;
use std::f64::consts::PI;

fn cfg(cells: usize, cell: f64, sponge: bool) -> SpectralConfig {
    SpectralConfig {
        cells,
        cell,
        depth: 0.3,
        gravity: 9.81,
        density: 1000.0,
        surface_tension: 0.0728,
        viscosity: 0.0,
        sponge,
    }
}

/// A patch centred on the origin after a push of `impulse` N·s over the square of half-side
/// `half` about it and `steps` steps of 5 ms.
fn pushed(c: SpectralConfig, half: f64, impulse: f64, steps: usize) -> SpectralField {
    let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
    f.deposit(0.0, 0.0, half, impulse);
    for _ in 0..steps {
        f.advance(0.005);
    }
    f
}

/// Sets η = amp cos(k x) (x from the patch's −x edge) and φ = 0 on every cell.
fn standing_wave(f: &mut SpectralField, k: f64, amp: f64) {
    let (n, l) = (f.cells(), f.cell());
    for j in 0..n {
        for i in 0..n {
            let x = (i as f64 + 0.5) * l;
            f.set_cell(i, j, amp * (k * x).cos(), 0.0);
        }
    }
}

/// ω of the capillary–gravity relation (Lamb §267), written out independently of `mode`.
fn omega(k: f64, c: &SpectralConfig) -> f64 {
    ((c.gravity * k + c.surface_tension * k.powi(3) / c.density) * (k * c.depth).tanh()).sqrt()
}

#[test]
fn a_standing_wave_oscillates_at_the_dispersion_relations_frequency_for_any_step() {
    let c = cfg(32, 0.01, false);
    let m = 3.0;
    let k = 2.0 * PI * m / (32.0 * 0.01);
    let w = omega(k, &c);
    let amp = 1e-3;
    for (dt, steps) in [(0.005, 40usize), (0.02, 10), (0.2, 1)] {
        let mut f = SpectralField::new(c, [0.16, 0.16]).unwrap();
        standing_wave(&mut f, k, amp);
        for _ in 0..steps {
            f.advance(dt);
        }
        let t = dt * steps as f64;
        for i in 0..32 {
            let x = (i as f64 + 0.5) * 0.01;
            let want = amp * (w * t).cos() * (k * x).cos();
            let got = f.eta(i, 7);
            assert!(
                (got - want).abs() < 1e-12 * amp * steps as f64,
                "dt {dt}: cell {i}: {got} against {want}"
            );
        }
    }
}

#[test]
fn short_waves_are_deep_water_waves_and_long_ones_shallow() {
    // The model's frequency from a time series of one mode, against gk (deep) and gHk² (shallow).
    let measure = |cells: usize, cell: f64, depth: f64| {
        let mut c = cfg(cells, cell, false);
        c.depth = depth;
        c.surface_tension = 0.0;
        let k = 2.0 * PI / (cells as f64 * cell);
        let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
        standing_wave(&mut f, k, 1e-3);
        // A quarter period: η at the crest passes through zero at t = π/(2ω).
        let (mut t, dt) = (0.0, 1e-4);
        let mut prev = f.eta(0, 0);
        loop {
            f.advance(dt);
            t += dt;
            let e = f.eta(0, 0);
            if e <= 0.0 {
                let tz = t - dt * e / (e - prev);
                return (PI / (2.0 * tz), k);
            }
            prev = e;
        }
    };
    // A 10 cm wave over 0.3 m of water: kH = 19, deep.
    let (w, k) = measure(16, 0.1 / 16.0, 0.3);
    assert!((w / (9.81 * k).sqrt() - 1.0).abs() < 1e-3, "deep: {w}");
    // A 20 m wave over 5 cm: kH = 0.016, shallow (c = √(gH) within (kH)²/6).
    let (w, k) = measure(16, 20.0 / 16.0, 0.05);
    assert!(
        (w / ((9.81 * 0.05f64).sqrt() * k) - 1.0).abs() < 1e-3,
        "shallow: {w}"
    );
}

#[test]
fn a_pressure_held_over_a_step_is_integrated_exactly() {
    // The same impulse spread over one step or over four quarter steps: the same state.
    let c = cfg(32, 0.01, false);
    let one = {
        let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
        f.deposit(0.013, -0.021, 0.02, 0.01);
        f.advance(0.02);
        f
    };
    let four = {
        let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
        for _ in 0..4 {
            f.deposit(0.013, -0.021, 0.02, 0.0025);
            f.advance(0.005);
        }
        f
    };
    let scale = one.max_abs_eta();
    assert!(scale > 1e-7, "the impulse moved the water: {scale}");
    for j in 0..32 {
        for i in 0..32 {
            assert!((one.eta(i, j) - four.eta(i, j)).abs() < 1e-11 * scale);
        }
    }
}

#[test]
fn a_push_depresses_the_water_under_it_and_keeps_its_volume() {
    let mut f = pushed(cfg(64, 0.01, false), 0.03, 0.02, 1);
    assert!(
        f.height(0.0, 0.0) < 0.0,
        "under the push: {}",
        f.height(0.0, 0.0)
    );
    for _ in 0..50 {
        f.advance(0.005);
        assert!(f.volume().abs() < 1e-15, "volume {}", f.volume());
    }
    let (got, missed) = f.impulse_received();
    assert!(
        (got - 0.02).abs() < 1e-15 && missed.abs() < 1e-15,
        "{got}, {missed}"
    );
}

#[test]
fn a_centred_push_spreads_a_symmetric_ring() {
    // The patch's centre is a cell corner: a square footprint about it is symmetric.
    let f = pushed(cfg(64, 0.01, true), 0.025, 0.02, 40);
    let scale = f.max_abs_eta();
    for j in 0..64 {
        for i in 0..64 {
            let e = f.eta(i, j);
            for other in [f.eta(j, i), f.eta(63 - i, j), f.eta(i, 63 - j)] {
                assert!((e - other).abs() < 1e-12 * scale, "({i}, {j})");
            }
        }
    }
}

#[test]
fn the_sponge_lets_the_rings_out_and_nothing_comes_back() {
    let mut c = cfg(64, 0.02, true);
    c.viscosity = 0.0;
    let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
    f.deposit(0.0, 0.0, 0.05, 0.05);
    let mut peak: f64 = 0.0;
    for _ in 0..800 {
        f.advance(0.005);
        peak = peak.max(f.max_abs_eta());
    }
    // After 4 s all but the slowest waves have reached the edges (a 5 cm wave's group speed is
    // 0.14 m/s, the half patch 0.64 m).
    let left = f.max_abs_eta();
    assert!(left < 0.05 * peak, "{left} of a peak of {peak}");
    // Without the sponge the waves keep going round the periodic patch.
    c.sponge = false;
    let mut g = SpectralField::new(c, [0.0, 0.0]).unwrap();
    g.deposit(0.0, 0.0, 0.05, 0.05);
    for _ in 0..800 {
        g.advance(0.005);
    }
    assert!(
        g.max_abs_eta() > 4.0 * left,
        "{} against {left}",
        g.max_abs_eta()
    );
}

#[test]
fn the_patch_follows_the_stone_and_keeps_the_water_where_it_was() {
    let c = cfg(32, 0.01, false);
    let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
    f.deposit(0.03, 0.02, 0.01, 0.01);
    f.advance(0.005);
    let before = f.height(0.03, 0.02);
    assert!(!f.follow(0.03, 0.0), "3 cells off centre: within n/8 = 4");
    assert!(f.follow(0.05, -0.01), "5 cells off centre");
    assert_eq!(f.origin(), [-0.16 + 0.05, -0.16 - 0.01]);
    assert_eq!(f.height(0.03, 0.02), before);
    // The cells that entered are at rest.
    assert_eq!(f.eta(31, 15), 0.0);
}

#[test]
fn a_footprint_off_the_patch_is_counted_as_missed() {
    let c = cfg(16, 0.01, false);
    let mut f = SpectralField::new(c, [0.0, 0.0]).unwrap();
    // Half the square lies beyond the +x edge at 0.08 m.
    f.deposit(0.08, 0.0, 0.01, 1.0);
    let (got, missed) = f.impulse_received();
    assert!(
        (got - 0.5).abs() < 1e-12 && (missed - 0.5).abs() < 1e-12,
        "{got}, {missed}"
    );
    f.deposit(5.0, 0.0, 0.01, 1.0);
    assert!((f.impulse_received().1 - 1.5).abs() < 1e-12);
}

#[test]
fn bounds_cover_the_bilinear_surface() {
    let f = pushed(cfg(32, 0.01, false), 0.02, 0.02, 10);
    let (lo, hi) = ([-0.05, -0.04], [0.05, 0.06]);
    let (m, slope) = f.bounds_over(lo, hi);
    let d = 1e-4;
    let mut x = lo[0];
    while x <= hi[0] {
        let mut y = lo[1];
        while y <= hi[1] {
            let h = f.height(x, y);
            assert!(h <= m + 1e-15, "({x}, {y}): {h} above {m}");
            let gx = (f.height(x + d, y) - h) / d;
            let gy = (f.height(x, y + d) - h) / d;
            assert!(gx.hypot(gy) <= slope * (1.0 + 1e-6) + 1e-12);
            y += 0.0037;
        }
        x += 0.0031;
    }
}

#[test]
fn the_same_pushes_give_the_same_bits() {
    let run = || {
        let mut f = SpectralField::new(cfg(64, 0.01, true), [1.0, 2.0]).unwrap();
        for s in 0..30 {
            let x = 1.0 + 0.02 * s as f64;
            f.deposit(x, 2.0, 0.02, 0.003);
            f.advance(0.005);
            f.follow(x, 2.0);
        }
        f.eta.clone()
    };
    assert_eq!(run(), run());
}

/// The in-place shift gives what a copy would: cell (i, j) takes the old (i + sx, j + sy), rest
/// outside, for shifts in every direction, none, and past the patch.
#[test]
fn shifting_in_place_matches_a_copy() {
    let n = 8usize;
    let old: Vec<f64> = (0..n * n).map(|k| 1.0 + k as f64).collect();
    for sy in -9i64..=9 {
        for sx in -9i64..=9 {
            let mut f = old.clone();
            super::shift(&mut f, n, sx, sy);
            for j in 0..n as i64 {
                for i in 0..n as i64 {
                    let (oi, oj) = (i + sx, j + sy);
                    let want = if (0..n as i64).contains(&oi) && (0..n as i64).contains(&oj) {
                        old[(oj * n as i64 + oi) as usize]
                    } else {
                        0.0
                    };
                    assert_eq!(
                        f[(j * n as i64 + i) as usize],
                        want,
                        "({sx}, {sy}) at ({i}, {j})"
                    );
                }
            }
        }
    }
}
