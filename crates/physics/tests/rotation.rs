//! The stone as a free rigid body (physics.md §1.7, §7.3; VC-12, VC-13): torque-free flight,
//! the Dzhanibekov instability, spin stabilisation and its threshold, precession, and the locked
//! attitude left untouched by spin.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![allow(clippy::field_reassign_with_default)]

mod common;

use common::{
    clanet_at_impact, clanet_free as clanet, fit_exponent, logspace, spin_counts, spin_limited,
    spin_point, typical,
};
use glam::{DMat3, DQuat, DVec3};
use stoneskip_physics::sim::integrate::torque_free;
use stoneskip_physics::sim::params::{Integrator, Preset, Rotation, Shape, StoneParams};
use stoneskip_physics::sim::scenario::first_contact;
use stoneskip_physics::sim::stone::Stone;
use stoneskip_physics::sim::Simulation;

/// Angle (degrees) between the stone's axis at the first contact's start and end.
fn first_contact_axis_turn(p: &Preset) -> (bool, f64, [f64; 3], [f64; 3]) {
    let mut sim = Simulation::new(p).unwrap();
    let mut axis_in = None;
    let mut axis_out = DVec3::Z;
    let mut done = false;
    while !done && !sim.is_finished() {
        sim.tick();
        let (_, q) = sim.world_from_stone();
        if sim.in_contact() && axis_in.is_none() {
            axis_in = Some(q * DVec3::Z);
        }
        if let Some(c) = sim.contacts().first() {
            if !c.open {
                axis_out = q * DVec3::Z;
                done = true;
            }
        }
    }
    let c = sim.contacts()[0];
    let a = axis_in.unwrap_or(DVec3::Z);
    (
        c.skip,
        a.angle_between(axis_out).to_degrees(),
        c.attitude_in,
        c.attitude_out,
    )
}

/// Torque-free flight conserves angular momentum and kinetic energy to 1e-9 relative over a
/// throw; a disc spun about its axis keeps the axis, for every integrator.
#[test]
fn torque_free_flight_conserves() {
    for integrator in [
        Integrator::Adaptive,
        Integrator::Rk4,
        Integrator::Paper,
        Integrator::SymplecticEuler,
    ] {
        let mut p = clanet(20.0, 30.0);
        p.launch.position = [0.0, 0.0, 3.0];
        p.launch.velocity = [2.0, 0.0, 4.0];
        p.launch.angular_velocity = [6.0, -4.0, 1.0];
        p.physics.integrator = integrator;
        let mut sim = Simulation::new(&p).unwrap();
        let l0 = sim.state().angular_momentum;
        let e0 = 0.5 * sim.angular_velocity().dot(l0);
        while !sim.is_finished() && sim.time() < 1.5 {
            sim.tick();
            if sim.in_contact() || !sim.contacts().is_empty() {
                break;
            }
            let l = sim.state().angular_momentum;
            let e = 0.5 * sim.angular_velocity().dot(l);
            assert!(
                (l - l0).length() <= 1e-9 * l0.length(),
                "{integrator:?}: L drift"
            );
            assert!(
                (e - e0).abs() <= 1e-9 * e0,
                "{integrator:?}: rotational energy {e} vs {e0}"
            );
        }
        assert!(sim.time() > 1.0, "flew for a second");

        // Pure spin: the axis stays put.
        let mut p = clanet(20.0, 65.0);
        p.launch.position = [0.0, 0.0, 3.0];
        p.launch.velocity = [2.0, 0.0, 4.0];
        p.physics.integrator = integrator;
        let mut sim = Simulation::new(&p).unwrap();
        let a0 = sim.world_from_stone().1 * DVec3::Z;
        let mut a1 = a0;
        while sim.contacts().is_empty() && !sim.is_finished() {
            a1 = sim.world_from_stone().1 * DVec3::Z;
            sim.tick();
        }
        assert!(sim.time() > 1.0, "flew for a second");
        assert!(
            a0.angle_between(a1) < 1e-9,
            "{integrator:?}: axis drifted {}",
            a0.angle_between(a1)
        );
    }
}

/// A box spun about its intermediate principal axis flips (the Dzhanibekov instability); about
/// its largest or smallest axis it does not. Energy and |L| are kept to 1e-6 on the general
/// (non-axisymmetric) torque-free path.
#[test]
fn dzhanibekov_flip_only_about_intermediate_axis() {
    let stone = Stone::new(&StoneParams {
        shape: Shape::Plate {
            length: 0.1,
            width: 0.06,
            thickness: 0.02,
        },
        mass: 0.2,
        segments: 8,
        bands: None,
        quadrature: Default::default(),
    })
    .unwrap();
    let m = stone.principal_moments();
    assert!(
        m.x < m.y && m.y < m.z,
        "x smallest, y intermediate, z largest: {m}"
    );
    for (axis, should_flip) in [(DVec3::X, false), (DVec3::Y, true), (DVec3::Z, false)] {
        let w_body = axis * 20.0 + DVec3::new(1e-3, 1e-3, 1e-3);
        let q0 = DQuat::IDENTITY;
        let l = DMat3::from_quat(q0) * (stone.inertia * w_body);
        let energy = |q: DQuat| {
            let r = DMat3::from_quat(q);
            0.5 * (r * (stone.inv_inertia * (r.transpose() * l))).dot(l)
        };
        let e0 = energy(q0);
        let mut q = q0;
        let mut min_align: f64 = 1.0;
        for _ in 0..400 {
            q = torque_free(&stone, q, l, 0.025);
            min_align = min_align.min((q * axis).dot(l.normalize()));
        }
        assert!((energy(q) - e0).abs() < 1e-6 * e0, "energy drift");
        if should_flip {
            assert!(
                min_align < -0.9,
                "intermediate axis must flip: min alignment {min_align}"
            );
        } else {
            assert!(
                min_align > 0.999,
                "stable axis stays: min alignment {min_align}"
            );
        }
    }
}

/// VC-13: Clanet's disc at α = 35°, β = 20°, U = 3.5 m/s. Without spin the lift on the trailing
/// part pitches it nose-down and it dives; at 65 rev/s it skips, the axis turned only by the
/// precession.
#[test]
fn spin_stabilises_vc13() {
    let (skip0, _, att_in0, att_out0) = first_contact_axis_turn(&clanet_at_impact(35.0, 0.0));
    assert!(!skip0, "no spin: dives");
    assert!(
        att_out0[0] < att_in0[0] - 30.0,
        "pitches nose-down: {att_in0:?} -> {att_out0:?}"
    );

    let (skip65, turn65, att_in, att_out) = first_contact_axis_turn(&clanet_at_impact(35.0, 65.0));
    assert!(skip65, "65 rev/s: skips");
    assert!(
        turn65 < 20.0,
        "axis turns by the precession only: {turn65}° ({att_in:?} -> {att_out:?})"
    );
}

/// The precession angle per contact is angular impulse / (I₃ ω): doubling the spin halves it
/// (within 25 %, the contact itself changing a little with the attitude).
#[test]
fn precession_per_contact_falls_as_one_over_spin() {
    let (s1, turn1, ..) = first_contact_axis_turn(&clanet_at_impact(20.0, 65.0));
    let (s2, turn2, ..) = first_contact_axis_turn(&clanet_at_impact(20.0, 130.0));
    assert!(s1 && s2);
    let ratio = turn1 / turn2;
    assert!(
        (ratio - 2.0).abs() < 0.5,
        "turn {turn1}° at 65 rev/s vs {turn2}° at 130 rev/s: ratio {ratio}"
    );
}

/// The spin threshold of VC-13: the smallest spin at which the first contact is a skip. The
/// literature's rule of thumb is about one revolution per contact time (Ω τ ≈ 1).
#[test]
fn spin_threshold_is_about_one_revolution_per_contact() {
    let skips = |rev_s: f64| {
        first_contact(&clanet_at_impact(35.0, rev_s))
            .unwrap()
            .map(|c| (c.skipped, c.duration))
            .unwrap()
    };
    let (mut lo, mut hi) = (0.0, 80.0);
    assert!(!skips(lo).0 && skips(hi).0);
    while hi - lo > 0.5 {
        let mid = 0.5 * (lo + hi);
        if skips(mid).0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (_, tau) = skips(hi);
    let revolutions = hi * tau;
    eprintln!(
        "spin threshold {hi:.1} rev/s, contact {:.1} ms, {revolutions:.2} revolutions per contact",
        tau * 1e3
    );
    assert!((0.3..3.0).contains(&revolutions), "Ω τ = {revolutions}");
}

/// At a fixed speed more spin never gives fewer skips. Counted as rebounds — contacts the stone
/// leaves rising — since a spinning stone can also rock off the surface while still sinking (a graze
/// of a few ms that the skip count includes), and as distance. As the spin grows the precession of
/// every contact shrinks as 1/ω and the attitude history approaches the locked one, so both can only
/// grow. Three throws of a 10 cm, 150 g disc over 0–150 rev/s.
#[test]
fn more_spin_never_fewer_skips() {
    for (vx, vz, tilt) in [(6.0, -0.5, 20.0), (9.0, -0.8, 20.0), (12.0, -0.5, 15.0)] {
        let mut rows = Vec::new();
        for rev_s in (0..=15).map(|i| 10.0 * i as f64) {
            let mut p = typical(Some(rev_s));
            p.launch.velocity = [vx, 0.0, vz];
            p.launch.attitude.tilt_deg = tilt;
            let s = stoneskip_physics::sim::simulate(&p).unwrap();
            let rebounds = s
                .contacts
                .iter()
                .filter(|c| c.skip && c.v_out[2] > 0.0)
                .count();
            rows.push((rev_s, rebounds, s.distance));
        }
        eprintln!("{vx} m/s: (rev/s, rebounds, distance) {rows:?}");
        for w in rows.windows(2) {
            assert!(
                w[1].1 >= w[0].1,
                "{vx} m/s: fewer rebounds at more spin: {rows:?}"
            );
            // 1 mm: the integrator's tolerance on a run of metres.
            assert!(
                w[1].2 >= w[0].2 - 1e-3,
                "{vx} m/s: shorter at more spin: {rows:?}"
            );
        }
        assert!(rows[15].1 > rows[0].1, "{rows:?}");
    }
}

/// The spin-limited count. Each contact turns the axis by about its angular impulse over I₃ω, always
/// in the same sense (the lift acts behind the centre of mass), so the attitude drifts coherently
/// and the number of contacts before it fails grows as ω¹ — not as Bocquet's reported ω², which
/// needs kicks that add like a random walk. Fitted where the count is spin-limited (2 ≤ N ≤ N_L/2),
/// on the spin limit alone (1/N = 1/N_spin + 1/N_L); the raw count grows more slowly still.
/// Tolerance: ±0.35 on the exponent, for integer counts of 2–5 over less than a decade of spin.
#[test]
fn spin_limited_count_grows_linearly_not_quadratically() {
    let spins = logspace(40.0, 155.0, 13);
    let counts = spin_counts(&spins).unwrap();
    let (raw, alone) = spin_limited(&counts);
    let p_raw = fit_exponent(&raw).unwrap();
    let p = fit_exponent(&alone).unwrap();
    eprintln!(
        "counts {:?}",
        counts
            .iter()
            .map(|c| (c.rev_s, c.skips))
            .collect::<Vec<_>>()
    );
    eprintln!("spin-limited {raw:?}: N ∝ ω^{p_raw:.2}; spin limit alone ∝ ω^{p:.2}");
    assert!(raw.len() >= 6, "{raw:?}");
    assert!((0.65..1.35).contains(&p), "exponent {p}");
    assert!(p_raw <= p + 1e-12 && p_raw > 0.3, "raw exponent {p_raw}");
}

/// VC-12: Clanet's reference throw, α = β = 20° at 65 rev/s, skips with the stone's inclination to
/// the water nearly unchanged through the contact (design.md: a few degrees at most): the contact's
/// nose-down torque turns the axis mostly in azimuth (precession into bank). Without spin the same
/// torque pitches the stone over.
#[test]
fn vc12_inclination_nearly_unchanged_at_65_rev_s() {
    let p = spin_point(20.0, 65.0).unwrap();
    eprintln!("{p:?}");
    assert!(p.first_skip, "skips");
    assert!(p.inclination_change.abs() < 3.0, "{p:?}");
    assert!(p.axis_turn > 2.0 * p.inclination_change.abs(), "{p:?}");
    let still = spin_point(20.0, 0.0).unwrap();
    assert!(still.inclination_change < -10.0, "without spin: {still:?}");
}

/// A banked, spinning stone curves sideways (the lift leans with the stone); with the attitude
/// locked the same throw would go straight only without bank.
#[test]
fn banked_spinning_stone_curves() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    p.physics.rotation = Rotation::Free;
    p.launch.attitude.bank_deg = 10.0;
    let s = stoneskip_physics::sim::simulate(&p).unwrap();
    let last = s.contacts.last().unwrap();
    eprintln!("bank 10°: lateral {:.3} m over {:.2} m", last.y, last.x);
    assert!(last.y.abs() > 0.05, "curves: y = {}", last.y);
}

/// With the attitude locked, spin and wobble change nothing, bit for bit.
#[test]
fn locked_results_ignore_spin() {
    let mut a = Preset::version_1();
    a.water.enabled = false;
    a.physics.rotation = Rotation::Locked;
    a.launch.spin = 0.0;
    let mut b = a.clone();
    b.launch.spin = 400.0;
    b.launch.angular_velocity = [3.0, -2.0, 1.0];
    let sa = stoneskip_physics::sim::simulate(&a).unwrap();
    let sb = stoneskip_physics::sim::simulate(&b).unwrap();
    assert_eq!(sa, sb);
}

/// A tumbling disc whose lowest point is clear of the water at both ends of a tick still dips in
/// between: a 10 cm disc at 2 cm, flat, flipping about a diameter half a turn per tick, is edge-on
/// (3 cm under) mid-tick. The flight's clearance is bounded along the exact torque-free motion and
/// the interval halved where the bound allows a touch, so the contact is found, and its start is
/// the first touch of the exact motion (found here by brute force on 200 000 samples of the tick).
#[test]
fn tumbling_stone_grazes_inside_a_tick() {
    use stoneskip_physics::sim::hydro::{lowest_clearance, FlatSurface};
    use stoneskip_physics::sim::integrate::flight;
    let dt = 0.005;
    for integrator in [Integrator::Adaptive, Integrator::Rk4, Integrator::Paper] {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.stone = StoneParams {
            shape: Shape::Disk {
                radius: 0.05,
                thickness: 0.01,
            },
            mass: 0.1,
            segments: 48,
            bands: None,
            quadrature: Default::default(),
        };
        p.physics.rotation = Rotation::Free;
        p.physics.integrator = integrator;
        p.physics.dt = dt;
        p.launch.position = [0.0, 0.0, 0.02];
        p.launch.velocity = [5.0, 0.0, 0.0];
        p.launch.attitude.tilt_deg = 0.0;
        p.launch.spin = 0.0;
        p.launch.angular_velocity = [0.0, std::f64::consts::PI / dt, 0.0];
        let mut sim = Simulation::new(&p).unwrap();
        let s0 = *sim.state();
        let clear = |t: f64| {
            let s = flight(sim.stone(), Rotation::Free, p.physics.gravity, &s0, t);
            lowest_clearance(sim.stone(), s.position, s.orientation, &FlatSurface)
        };
        assert!(
            clear(0.0) > 0.004 && clear(dt) > 0.004,
            "clear at both ends"
        );
        let n = 200_000;
        let touch = (0..=n)
            .map(|i| dt * i as f64 / n as f64)
            .find(|&t| clear(t) <= 0.0)
            .expect("dips mid-tick");
        sim.tick();
        let c = sim.contacts().first().copied();
        let c = c.unwrap_or_else(|| {
            panic!("{integrator:?}: the graze inside the first tick was missed")
        });
        assert!(
            (c.t_start - touch).abs() <= dt / n as f64,
            "{integrator:?}: contact starts at {} s, the exact motion touches at {touch} s",
            c.t_start
        );
    }
}
