//! The flight's touch search ([`super::integrate::first_touch`] as [`super::StepContext::touch`]
//! drives it) against brute force, where its bounds are least forgiving: a fast-spun lens (the
//! revolution bound drops the spin's ωR), tilted and wobbling, flying low over the wake its own
//! contacts left on 2 cm columns (the wave bound: the crest over the swept rectangle).

use glam::{DMat3, DQuat, DVec3};

use super::integrate::BodyState;
use super::params::{AxialSpin, Preset, Rotation, Shape};
use super::{Simulation, StepContext};

/// A shipped-like throw (64-segment lens, free rotation, air, wavy contact on a 2 cm lake) run
/// past its first contact, so its rings and wake stand on the water around the stone.
fn wake() -> Simulation {
    let mut p = Preset::version_1();
    p.stone.shape = Shape::Lens {
        radius: 0.05,
        thickness: 0.012,
    };
    p.stone.segments = 64;
    p.launch.position = [0.0, 0.0, 0.1];
    p.launch.velocity = [12.0, 0.0, -0.5];
    p.launch.spin = 88.0;
    p.physics.rotation = Rotation::Free;
    p.physics.axial_spin = AxialSpin::Resal;
    p.physics.air = Some(Default::default());
    p.water.enabled = true;
    p.water.wavy_contact = true;
    p.water.size = [8.0, 2.0];
    p.water.origin = Some([-1.0, -1.0]);
    p.water.cell = 0.02;
    let mut sim = Simulation::new(&p).unwrap();
    // Out of the water after the first contact (whether it re-touched on the way out or not:
    // a graze of micrometres on the columns).
    while sim.contacts().is_empty() || sim.in_contact() {
        sim.tick();
        assert!(!sim.is_finished(), "the throw skips");
    }
    sim
}

/// A small deterministic generator (the test needs no crate for it).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Every flight that touches within the interval (sampled at 4 000 points) is found, and its
/// bracket holds the first sampled touch; the rest are proven clear or bracketed correctly.
#[test]
fn the_touch_search_never_misses_a_touch_over_a_wake() {
    let mut sim = wake();
    let first = sim.contacts()[0];
    let mut rng = Lcg(7);
    let (mut touching, mut clear) = (0, 0);
    for _ in 0..120 {
        // Over the first contact's rings, low, tilted 0–30°, spun at 30–300 rad/s with a wobble.
        let x = first.x + rng.range(-0.2, 0.6);
        let y = rng.range(-0.15, 0.15);
        let tilt = rng.range(0.0, 0.5);
        let orientation = DQuat::from_rotation_z(rng.range(0.0, 6.3))
            * DQuat::from_rotation_y(-tilt)
            * DQuat::from_rotation_z(rng.range(0.0, 6.3));
        let axis = orientation * DVec3::Z;
        let omega = axis * rng.range(30.0, 300.0)
            + DVec3::new(
                rng.range(-8.0, 8.0),
                rng.range(-8.0, 8.0),
                rng.range(-8.0, 8.0),
            );
        let stone = sim.stone();
        let r = DMat3::from_quat(orientation);
        let mut s = BodyState {
            position: DVec3::new(x, y, 0.0),
            velocity: DVec3::new(
                rng.range(6.0, 14.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.2, 0.6),
            ),
            orientation,
            angular_momentum: r * (stone.inertia * (r.transpose() * omega)),
            memory: 0.0,
        };
        sim.motion.state = s;
        sim.refresh_water_max();
        // Lowest vertex 0.2–12 mm above the water there.
        let c0 = sim.clearance(&s);
        s.position.z += rng.range(2e-4, 1.2e-2) - c0;
        sim.motion.state = s;
        sim.refresh_water_max();
        if sim.clearance(&s) <= 0.0 {
            continue;
        }
        let h = sim.preset.physics.dt;
        let found = with_context(&sim, |cx| cx.touch(&s, h));
        let brute = with_context(&sim, |cx| {
            (0..=4000)
                .map(|k| h * k as f64 / 4000.0)
                .find(|&t| cx.clear(&cx.flight(&s, t)) <= 0.0)
        });
        // A bracket is a wet end after a proven-dry stretch: never after the first sampled touch
        // (it may be before it, at a graze shorter than the sampling).
        if let Some((lo, hi)) = found {
            let wet = with_context(&sim, |cx| cx.clear(&cx.flight(&s, hi)));
            assert!(wet <= 0.0 && lo <= hi, "({lo}, {hi}) ends dry: {wet}");
        }
        match brute {
            Some(t) => {
                touching += 1;
                let (lo, _) = found.unwrap_or_else(|| panic!("missed a touch at {t} s: {s:?}"));
                assert!(lo <= t, "bracket from {lo} after the touch at {t}");
            }
            None => clear += 1,
        }
    }
    assert!(
        touching > 20 && clear > 20,
        "{touching} touching, {clear} clear"
    );
}

/// The revolution bound's facet term is what makes it safe: the lowest vertex of a spinning,
/// faceted lens rises and falls as its facets turn under it, by up to the facet gap on flat
/// water, and the gap is small (tens of µm at 64 segments) against the spin's ωR over a step.
#[test]
fn a_spinning_lens_lowest_vertex_wobbles_by_at_most_its_facet_gap() {
    let sim = wake();
    let stone = sim.stone();
    let gap = stone.kernel().facet_gap(0.0).unwrap();
    let expected = 0.05 * (1.0 - (std::f64::consts::PI / 64.0).cos());
    assert!(
        gap >= expected && gap < 1.01 * expected,
        "{gap} vs {expected}"
    );
    let orientation = DQuat::from_rotation_y(-0.35);
    let axis = orientation * DVec3::Z;
    let r = DMat3::from_quat(orientation);
    let omega = axis * 300.0;
    let s = BodyState {
        position: DVec3::new(0.0, 0.0, 0.5),
        velocity: DVec3::ZERO,
        orientation,
        angular_momentum: r * (stone.inertia * (r.transpose() * omega)),
        memory: 0.0,
    };
    let rise = |st: &BodyState| {
        super::lowest_clearance(stone, DVec3::ZERO, st.orientation, &super::FlatSurface)
    };
    let step = std::f64::consts::TAU / 300.0 / 64.0 / 40.0;
    let rises: Vec<f64> = (0..400)
        .map(|k| {
            rise(&super::integrate::flight(
                stone,
                Rotation::Free,
                0.0,
                &s,
                step * k as f64,
            ))
        })
        .collect();
    let (lo, hi) = rises
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    // A pure spin: the axis stays, so only the facets move the lowest vertex.
    assert!(hi - lo <= gap, "wobble {} > gap {gap}", hi - lo);
    assert!(
        hi - lo > 0.5 * expected * 0.35_f64.sin(),
        "the facets do wobble it: {}",
        hi - lo
    );
}

fn with_context<R>(sim: &Simulation, f: impl FnOnce(&StepContext) -> R) -> R {
    let physics = sim.preset.physics;
    let surface = sim.surface();
    let cx = StepContext {
        dy: super::integrate::Dynamics {
            stone: &sim.stone,
            hydro: sim.hydro,
            gravity: physics.gravity,
            rotation: physics.rotation,
            surface: &surface,
            record_loads: false,
            resal: sim.resal(),
            memory: None,
        },
        integrator: physics.integrator,
        tolerance: physics.tolerance,
        slope: surface.max_slope(),
        air: sim.air,
        hidden_exits: false,
        last_flight: std::cell::Cell::new(None),
    };
    f(&cx)
}

/// Over the wake, the kernel's clearance (its boxes tried against the highest η under each) is
/// the reference's, vertex by vertex, bit for bit.
#[test]
fn the_clearance_over_a_wake_is_the_reference_one() {
    let mut sim = wake();
    let first = sim.contacts()[0];
    let mut rng = Lcg(11);
    let mut near = 0;
    for _ in 0..300 {
        let orientation = DQuat::from_rotation_z(rng.range(0.0, 6.3))
            * DQuat::from_rotation_y(-rng.range(0.0, 1.6))
            * DQuat::from_rotation_z(rng.range(0.0, 6.3));
        let mut s = sim.motion.state;
        s.orientation = orientation;
        s.position = DVec3::new(
            first.x + rng.range(-0.2, 0.6),
            rng.range(-0.15, 0.15),
            rng.range(-0.01, 0.06),
        );
        sim.motion.state = s;
        sim.refresh_water_max();
        let surface = sim.surface();
        let stone = sim.stone();
        let fast = super::lowest_clearance(stone, s.position, s.orientation, &surface);
        let reference =
            super::hydro::lowest_clearance_reference(stone, s.position, s.orientation, &surface);
        assert_eq!(fast.to_bits(), reference.to_bits(), "{s:?}");
        near += usize::from(fast.abs() < 0.01);
    }
    assert!(near > 50, "{near} poses within 1 cm of the water");
}
