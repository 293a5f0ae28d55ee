//! Validation of the 2D reference model (`stoneskip_reference`) against the analytic results and
//! model reproductions of `shared/reference/physics.md` §6 (VC-1, VC-2, VC-4, VC-5, VC-7, VC-8, VC-11).
//! Expected numbers and tolerances are the ones listed there.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use stoneskip_reference::{
    first_contact_skips, min_speed, simulate, ForceLaw, Integration, MinSpeedOptions, Outcome2d,
    Plate2d, State2d,
};

fn deg(d: f64) -> f64 {
    d.to_radians()
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// Bocquet's contact analysis: square reference stone, V_x frozen, vertical force ½ C ρ V_x² S.
fn frozen_reference() -> Plate2d {
    Plate2d::bocquet_reference()
        .with_law(ForceLaw::bocquet_small_angle(1.0, 1.0))
        .with_frozen_vx(true)
}

fn entry(vx: f64, vz: f64) -> State2d {
    State2d {
        t: 0.0,
        x: 0.0,
        z_low: 0.0,
        vx,
        vz,
    }
}

fn one_contact(dt: f64) -> Integration {
    Integration {
        max_contacts: 1,
        ..Integration::with_dt(dt)
    }
}

/// VC-1: ω₀, t_c, d_max and V_z,out of the frozen-V_x contact, eqs. (4)–(7), analytic and integrated.
#[test]
fn vc1_frozen_contact_matches_eqs_4_to_7() {
    let p = frozen_reference();
    // (V_x, ω₀, t_c, d_max) from physics.md VC-1.
    for (vx, omega, tc, dmax) in [
        (5.0, 241.64, 13.672e-3, 2.2440e-3),
        (12.0, 579.94, 5.5337e-3, 0.8918e-3),
    ] {
        let w = 0.5;
        assert!(rel(p.omega0(vx).unwrap(), omega) < 1e-4);
        assert!(rel(p.contact_time(vx, w).unwrap(), tc) < 1e-3);
        assert!(rel(p.max_depth(vx, w).unwrap(), dmax) < 1e-3);

        let run = simulate(&p, entry(vx, -w), &one_contact(1e-6)).unwrap();
        let c = run.contacts[0];
        assert!(c.skipped);
        assert!(rel(c.duration(), tc) < 1e-3, "t_c {}", c.duration());
        assert!(rel(c.max_depth, dmax) < 1e-3, "d_max {}", c.max_depth);
        assert!(rel(c.v_out[1], 0.5) < 1e-3, "V_z,out {}", c.v_out[1]);
        // Converged: against the closed forms to 1e-6 relative.
        assert!(rel(c.duration(), p.contact_time(vx, w).unwrap()) < 1e-6);
        assert!(rel(c.max_depth, p.max_depth(vx, w).unwrap()) < 1e-6);
        assert!(rel(c.v_out[1], w) < 1e-6);
        assert_eq!(c.v_out[0], vx);
    }
}

/// VC-1: the integrator converges at its order (RK4: 4 on the contact time).
#[test]
fn vc1_contact_time_converges_at_fourth_order() {
    let p = frozen_reference();
    let (vx, w) = (12.0, 0.5);
    let exact = p.contact_time(vx, w).unwrap();
    let err = |dt: f64| {
        let run = simulate(&p, entry(vx, -w), &one_contact(dt)).unwrap();
        (run.contacts[0].duration() - exact).abs()
    };
    let errors: Vec<f64> = [200e-6, 100e-6, 50e-6].iter().map(|&dt| err(dt)).collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!(
            (3.6..=4.4).contains(&order),
            "order {order}, errors {errors:?}"
        );
    }
    // The exit speed converges at least as fast (the oscillator's energy error of RK4 is O(dt⁵)).
    let vz_err = |dt: f64| {
        let run = simulate(&p, entry(vx, -w), &one_contact(dt)).unwrap();
        (run.contacts[0].v_out[1] - w).abs()
    };
    let (e1, e2) = (vz_err(200e-6), vz_err(100e-6));
    assert!((e1 / e2).log2() > 3.6, "V_z errors {e1} {e2}");
}

/// VC-2: critical speed V_c(β) (eq. 9) and β_max (eq. 10): closed form and integrated bisection.
#[test]
fn vc2_critical_speed_and_beta_max() {
    let p = frozen_reference();
    for (beta, expected) in [(0.0, 0.6955), (5.0, 0.6993), (10.0, 0.7114), (20.0, 0.7719)] {
        let formula = p.critical_speed(deg(beta)).unwrap().unwrap();
        assert!(rel(formula, expected) < 5e-3, "β {beta}: {formula}");
        // Integrated: smallest frozen V_x = U cos β that skips. β → 0 is taken at 0.01°.
        let b = deg(beta.max(0.01));
        let u = min_speed(&p, b, &MinSpeedOptions::default())
            .unwrap()
            .unwrap();
        let vc = u * b.cos();
        assert!(rel(vc, expected) < 5e-3, "β {beta}: integrated {vc}");
        assert!(
            rel(vc, formula) < 1e-4,
            "β {beta}: integrated {vc} vs {formula}"
        );
    }
    let beta_max = p.beta_max().unwrap().to_degrees();
    assert!(rel(beta_max, 40.0) < 5e-3, "β_max {beta_max}");
    assert_eq!(p.critical_speed(deg(40.5)).unwrap(), None);
    assert_eq!(
        min_speed(&p, deg(41.0), &MinSpeedOptions::default()).unwrap(),
        None
    );
    // Integrated β_max: bisect the largest β that still skips at V_x = 100 m/s (≈ 0.001° below β_max).
    let vx = 100.0;
    let skips = |b: f64| first_contact_skips(&p, vx / b.cos(), b, 1e-5, 1.0).unwrap();
    let (mut lo, mut hi) = (deg(30.0), deg(50.0));
    assert!(skips(lo) && !skips(hi));
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if skips(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    assert!(
        rel(lo.to_degrees(), 40.0) < 5e-3,
        "integrated β_max {}",
        lo.to_degrees()
    );
    // At a finite speed the bound is a little lower: tan² β < tan² β_max − 2 g d_full / V_x².
    assert!(lo.to_degrees() <= beta_max && beta_max - lo.to_degrees() < 0.01);
}

/// VC-4: I = V_x + μ(V_z + g t) = 11.571556 at every exit of the full model (V_x free, |V|² law).
#[test]
fn vc4_invariant_holds_at_every_exit() {
    for p in [
        Plate2d::bocquet_reference(),
        Plate2d::bocquet_reference().with_law(ForceLaw::bocquet_small_angle(1.0, 1.0)),
        Plate2d::bocquet_reference().with_ventilated(true),
    ] {
        let mu = p.mu().unwrap();
        let run = simulate(&p, entry(12.0, -0.3), &Integration::with_dt(2e-6)).unwrap();
        let i0 = p.invariant(0.0, 12.0, -0.3).unwrap();
        assert!((i0 - 11.571556).abs() < 1e-6);
        let invariants = run.exit_invariants(mu, p.g);
        assert!(invariants.len() > 10);
        for i in invariants {
            assert!(rel(i, i0) < 1e-6, "I = {i}");
        }
    }
}

/// VC-5: distance ≈ V_x0²/(2μg) = 5.14 m and duration ≈ I/(μg) within 10 %; ends by sinking at
/// V_x ≈ 0.2–0.3 m/s. The runs of physics.md gave 4.80, 5.04, 5.13 m.
#[test]
fn vc5_distance_and_duration_follow_solid_friction() {
    let p = Plate2d::bocquet_reference();
    let d_est = p.distance_estimate(12.0).unwrap();
    assert!(rel(d_est, 5.14) < 1e-3);
    for (vz0, reported) in [(-0.3, 4.80), (-0.1, 5.04), (-0.03, 5.13)] {
        let run = simulate(&p, entry(12.0, vz0), &Integration::with_dt(2e-6)).unwrap();
        assert_eq!(run.outcome, Outcome2d::Sank);
        assert!(rel(run.distance, d_est) < 0.10, "D = {}", run.distance);
        assert!(rel(run.distance, reported) < 0.01, "D = {}", run.distance);
        let t_est = p.duration_estimate(12.0, vz0).unwrap();
        assert!(
            rel(run.final_time(), t_est) < 0.10,
            "T = {}",
            run.final_time()
        );
        assert!((0.1..0.4).contains(&run.final_state.vx));
    }
}

/// VC-7: the number of skips scales as V_x0² (exponent 2 ± 0.3) and stays below Bocquet's N_c.
#[test]
fn vc7_bounce_count_scales_as_speed_squared() {
    let p = Plate2d::bocquet_reference();
    let speeds = [6.0, 8.0, 12.0];
    let mut pts = Vec::new();
    for v in speeds {
        let run = simulate(&p, entry(v, -0.1), &Integration::with_dt(2e-6)).unwrap();
        let n = run.skips() as f64;
        let nc = p.bounce_estimate(v).unwrap();
        assert!(n > 0.0 && n < nc, "V {v}: N {n}, N_c {nc}");
        pts.push((v.ln(), n.ln()));
    }
    // Least-squares slope of ln N against ln V.
    let k = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / k, sy / k);
    let num: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let den: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = num / den;
    assert!((slope - 2.0).abs() <= 0.3, "exponent {slope}");
    assert!(rel(p.bounce_estimate(12.0).unwrap(), 39.5) < 5e-3);
}

/// Vertex of the parabola through the smallest sampled value and its neighbours.
fn parabola_vertex(angles: &[f64], speeds: &[f64]) -> f64 {
    let i = (1..speeds.len() - 1)
        .min_by(|&a, &b| speeds[a].total_cmp(&speeds[b]))
        .unwrap();
    let h = angles[i + 1] - angles[i];
    let (um, u0, up) = (speeds[i - 1], speeds[i], speeds[i + 1]);
    angles[i] - h * (up - um) / (2.0 * (up - 2.0 * u0 + um))
}

/// VC-8: Rosellini's U·U_n law on the Clanet disc, β = 20°: U_min(α) within 3 %, minimum at 15–20°.
#[test]
fn vc8_rosellini_minimal_speed_and_magic_angle() {
    let angles = [10.0, 15.0, 20.0, 25.0, 30.0];
    let expected = [2.42, 2.26, 2.27, 2.37, 2.54];
    let mut got = Vec::new();
    for (a, e) in angles.iter().zip(expected) {
        let disc = Plate2d::clanet_disc(deg(*a));
        let u = min_speed(&disc, deg(20.0), &MinSpeedOptions::default())
            .unwrap()
            .unwrap();
        assert!(rel(u, e) < 0.03, "α {a}: {u} vs {e}");
        got.push(u);
    }
    let magic = parabola_vertex(&angles, &got);
    assert!((15.0..=20.0).contains(&magic), "magic angle {magic}");
}

/// VC-11: Newtonian law, C_D = 1.4, Clanet disc, β = 20°: U_min(α) within 3 %, optimum at 25–30°.
#[test]
fn vc11_newtonian_minimal_speed_and_optimum() {
    let angles = [15.0, 20.0, 25.0, 30.0];
    let expected = [3.52, 3.22, 3.11, 3.13];
    let mut got = Vec::new();
    for (a, e) in angles.iter().zip(expected) {
        let disc = Plate2d::clanet_disc(deg(*a)).with_law(ForceLaw::newtonian(1.4));
        let u = min_speed(&disc, deg(20.0), &MinSpeedOptions::default())
            .unwrap()
            .unwrap();
        assert!(rel(u, e) < 0.03, "α {a}: {u} vs {e}");
        got.push(u);
    }
    let optimum = parabola_vertex(&angles, &got);
    assert!((25.0..=30.0).contains(&optimum), "optimum {optimum}");
}

/// The bisection's default 10 µs step is converged: it agrees with 2 µs to 0.1 % (in fact ~1e-8).
#[test]
fn min_speed_is_converged_in_the_step() {
    let coarse = MinSpeedOptions {
        rel_tol: 1e-6,
        ..MinSpeedOptions::default()
    };
    let fine = MinSpeedOptions { dt: 2e-6, ..coarse };
    for disc in [
        Plate2d::clanet_disc(deg(20.0)),
        Plate2d::clanet_disc(deg(25.0)).with_law(ForceLaw::newtonian(1.4)),
    ] {
        let a = min_speed(&disc, deg(20.0), &coarse).unwrap().unwrap();
        let b = min_speed(&disc, deg(20.0), &fine).unwrap().unwrap();
        assert!(rel(a, b) < 1e-3, "{a} vs {b}");
    }
}

/// Model reproduction (physics.md §3): the Rosellini disc at U = 3.5 m/s, α = β = 20° bounces after
/// 36.5 ms with exit velocity (2.55, +0.46) m/s; 24.0 ms at 5.0 m/s (τ ∝ 1/U); at 3.5 m/s it skips for
/// β from ~5° to ~41° and not at 45°.
#[test]
fn rosellini_reference_throw() {
    let disc = Plate2d::clanet_disc(deg(20.0));
    let run = simulate(
        &disc,
        State2d::impact(3.5, deg(20.0)),
        &Integration {
            max_contacts: 1,
            ..Integration::default()
        },
    )
    .unwrap();
    let c = run.contacts[0];
    assert!(c.skipped);
    assert!(rel(c.duration(), 36.5e-3) < 0.01, "τ {}", c.duration());
    assert!(rel(c.v_out[0], 2.55) < 0.01 && rel(c.v_out[1], 0.46) < 0.02);
    let run = simulate(
        &disc,
        State2d::impact(5.0, deg(20.0)),
        &Integration {
            max_contacts: 1,
            ..Integration::with_dt(5e-6)
        },
    )
    .unwrap();
    assert!(rel(run.contacts[0].duration(), 24.0e-3) < 0.01);
    for (beta, skips) in [(5.0, true), (20.0, true), (40.0, true), (45.0, false)] {
        assert_eq!(
            first_contact_skips(&disc, 3.5, deg(beta), 1e-5, 2.0).unwrap(),
            skips,
            "β {beta}"
        );
    }
}
