//! Oracle tests of the fast force kernel (issue 12): on many random poses — grazing, mid-contact,
//! deep, free rotation — every fast path agrees with the scalar reference (`evaluate_reference`,
//! `lowest_clearance_reference`, `underside_submerged_reference`) for the three force laws,
//! ventilated or not, both pressure centres, the issue-11 options (buoyancy on the loaded or on
//! every wetted face), locked and free rotation, flat and wavy water, for a disc, a lens and a
//! plate at 32, 64 and 96 segments.
//!
//! Tolerance: 1e-12 relative. The two differ only in the order of the sums and in where the face
//! points are formed (the reference adds the centre of mass first, the kernel works in offsets), so
//! the difference is a few ulps of the terms summed. Force: relative to the larger of |F| and the
//! bound M = ρ (C_l + C_f) U_loc² S_wet of Σ|f_face| (U_loc = |V| + |ω| R): where the faces' forces
//! cancel (a closed surface wholly under, not ventilated) |F| alone measures only rounding. Torque:
//! relative to the larger of |τ| and R times the force's scale (every lever arm is at most R).
//! Areas and loads: relative to themselves (Σ|term| for the loads). The clearance and the sink test
//! must agree exactly.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{DQuat, DVec3};
use stoneskip_physics::sim::hydro::{
    evaluate, evaluate_reference, lowest_clearance, lowest_clearance_reference,
    underside_submerged, underside_submerged_reference, FlatSurface, ForceSum, HydroParams, Pose,
    Scratch, Surface,
};
use stoneskip_physics::sim::params::{ForceLaw, Shape, StoneParams};
use stoneskip_physics::sim::stone::Stone;

const TOL: f64 = 1e-12;

/// xorshift64: deterministic poses.
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f()
    }
    fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// A travelling swell across the stone: η = a sin(k·x + φ), wavelength 0.3 m, a = 3 mm; with or
/// without a known lower bound (the kernel then classifies every candidate face).
struct Swell {
    amplitude: f64,
    k: DVec3,
    phase: f64,
    bounded_below: bool,
}

impl Surface for Swell {
    fn height(&self, x: f64, y: f64) -> f64 {
        self.amplitude * (self.k.x * x + self.k.y * y + self.phase).sin()
    }
    fn max_height(&self) -> f64 {
        self.amplitude
    }
    fn min_height(&self) -> f64 {
        if self.bounded_below {
            -self.amplitude
        } else {
            f64::NEG_INFINITY
        }
    }
}

fn stones() -> Vec<(String, Stone)> {
    let mut out = Vec::new();
    for segments in [32, 64, 96] {
        for shape in [
            Shape::Disk {
                radius: 0.05,
                thickness: 0.01,
            },
            Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            Shape::Plate {
                length: 0.12,
                width: 0.07,
                thickness: 0.008,
            },
        ] {
            let stone = Stone::new(&StoneParams {
                shape,
                mass: 0.1,
                segments,
                bands: None,
                quadrature: Default::default(),
            })
            .expect("valid stone");
            out.push((format!("{shape:?}/{segments}"), stone));
        }
    }
    // A lens whose latitude bands a preset names (`stone.bands`): coarser and finer than the
    // default half of the segments.
    for (segments, bands) in [(48, 12), (40, 48)] {
        let stone = Stone::new(&StoneParams {
            shape: Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            mass: 0.1,
            segments,
            bands: Some(bands),
            quadrature: Default::default(),
        })
        .expect("valid stone");
        out.push((format!("Lens/{segments}x{bands}"), stone));
    }
    out
}

/// The options of issue 11 on top: none, the pressure opposing the motion with buoyancy, smooth
/// axial spin, all three, and smooth spin with buoyancy on every wetted face
/// (`hydrostatic: WettedFaces`).
const EXTRAS: [&str; 5] = [
    "paper",
    "opposing+buoyancy",
    "smooth",
    "all",
    "smooth+wetted",
];

fn params(law: ForceLaw, ventilated: bool, extras: &str) -> HydroParams {
    let (lift, friction) = law.default_coefficients();
    let all = extras == "all";
    let wetted = extras == "smooth+wetted";
    HydroParams {
        law,
        lift,
        friction,
        density: 1000.0,
        ventilated,
        opposing: all || extras == "opposing+buoyancy",
        smooth_spin: all || wetted || extras == "smooth",
        rho_g: if all || wetted || extras == "opposing+buoyancy" {
            9810.0
        } else {
            0.0
        },
        hydrostatic_wetted: wetted,
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Grazing,
    Mid,
    Deep,
    Free,
}

/// Vertical extent (lowest, highest offset) of the stone's vertices in an orientation.
fn extent(stone: &Stone, q: DQuat) -> (f64, f64) {
    stone
        .mesh
        .positions
        .iter()
        .map(|&p| (q * p).z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
            (lo.min(z), hi.max(z))
        })
}

fn pose(rng: &mut Rng, stone: &Stone, kind: Kind) -> Pose {
    let heading = rng.range(-3.1, 3.1);
    let orientation = if kind == Kind::Free {
        DQuat::from_axis_angle(rng.unit(), rng.range(0.0, std::f64::consts::PI))
    } else {
        DQuat::from_rotation_z(heading)
            * DQuat::from_rotation_x(rng.range(-0.25, 0.25))
            * DQuat::from_rotation_y(-rng.range(0.08, 0.6))
    };
    let (lo, hi) = extent(stone, orientation);
    let fraction = match kind {
        Kind::Grazing => rng.range(5e-3, 5e-2),
        Kind::Mid => rng.range(0.2, 0.8),
        Kind::Deep => rng.range(1.05, 1.5),
        Kind::Free => rng.range(0.01, 1.2),
    };
    let z = -lo - fraction * (hi - lo);
    let speed = rng.range(2.0, 14.0);
    let beta = rng.range(0.05, 0.7);
    let dir = heading + rng.range(-0.3, 0.3);
    let velocity = DVec3::new(
        speed * beta.cos() * dir.cos(),
        speed * beta.cos() * dir.sin(),
        -speed * beta.sin(),
    );
    let angular_velocity = if kind == Kind::Free {
        rng.unit() * rng.range(1.0, 120.0)
    } else {
        DVec3::ZERO
    };
    Pose {
        position: DVec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), z),
        velocity,
        orientation,
        angular_velocity,
    }
}

/// Σ F_z, Σ footprint, Σ x F_z, Σ y F_z of the recorded loads, and the scales to compare them by.
fn load_sums(s: &Scratch) -> ([f64; 4], [f64; 4]) {
    let mut sum = [0.0; 4];
    let mut scale = [0.0; 4];
    for l in &s.loads {
        let terms = [l.fz, l.footprint, l.x * l.fz, l.y * l.fz];
        for k in 0..4 {
            sum[k] += terms[k];
            scale[k] += terms[k].abs();
        }
    }
    (sum, scale)
}

/// Agreement of two evaluations; `loads`: the reference's and the kernel's scratch after a
/// recording evaluation.
fn agree(
    what: &str,
    stone: &Stone,
    hp: &HydroParams,
    p: &Pose,
    r: &ForceSum,
    f: &ForceSum,
    loads: Option<(&Scratch, &Scratch)>,
) {
    assert_eq!(r.in_contact, f.in_contact, "{what}: contact");
    let u_loc = p.velocity.length() + p.angular_velocity.length() * stone.bounding_radius;
    let bound = hp.density * (hp.lift + hp.friction) * u_loc * u_loc * r.wetted_area;
    let fscale = r.force.length().max(bound);
    let tscale = r.torque.length().max(stone.bounding_radius * fscale);
    let df = (r.force - f.force).length();
    let dt = (r.torque - f.torque).length();
    let da = (r.wetted_area - f.wetted_area).abs();
    assert!(
        df <= TOL * fscale,
        "{what}: force {} vs {} ({:e} rel)",
        f.force,
        r.force,
        df / fscale
    );
    assert!(
        dt <= TOL * tscale,
        "{what}: torque {} vs {} ({:e} rel)",
        f.torque,
        r.torque,
        dt / tscale
    );
    assert!(
        da <= TOL * r.wetted_area,
        "{what}: area {} vs {}",
        f.wetted_area,
        r.wetted_area
    );
    let Some((rs, fs)) = loads else {
        return;
    };
    assert_eq!(rs.loads.len(), fs.loads.len(), "{what}: loaded faces");
    let (ra, scale) = load_sums(rs);
    let (fa, _) = load_sums(fs);
    for k in 0..4 {
        assert!(
            (ra[k] - fa[k]).abs() <= TOL * scale[k],
            "{what}: load sum {k}: {} vs {}",
            fa[k],
            ra[k]
        );
    }
}

/// The clearance and the sink test agree exactly with the reference's.
fn clearance_agrees(what: &str, stone: &Stone, p: &Pose, surface: &dyn Surface) -> bool {
    let r = lowest_clearance_reference(stone, p.position, p.orientation, surface);
    let f = lowest_clearance(stone, p.position, p.orientation, surface);
    assert_eq!(r, f, "{what}: lowest clearance");
    let r = underside_submerged_reference(stone, p.position, p.orientation, surface);
    let f = underside_submerged(stone, p.position, p.orientation, surface);
    assert_eq!(r, f, "{what}: underside submerged");
    r
}

/// Every combination of ventilation and the extra options.
fn options() -> Vec<(bool, &'static str)> {
    let mut out = Vec::new();
    for ventilated in [true, false] {
        for extras in EXTRAS {
            out.push((ventilated, extras));
        }
    }
    out
}

/// Runs every combination of the options over `poses` random poses of each kind on `surface`.
fn oracle(surface_name: &str, surface: &dyn Surface, poses: usize, seed: u64) {
    let mut rng = Rng(seed);
    let mut submerged = 0;
    let mut contacts = 0;
    let mut evaluations = 0;
    for (name, stone) in stones() {
        for law in ForceLaw::ALL {
            for (ventilated, extras) in options() {
                let hp = params(law, ventilated, extras);
                {
                    for kind in [Kind::Grazing, Kind::Mid, Kind::Deep, Kind::Free] {
                        // One scratch per run of poses, as the simulation keeps one.
                        let mut fs = Scratch::default();
                        for i in 0..poses {
                            let p = pose(&mut rng, &stone, kind);
                            let what = format!(
                                "{surface_name} {name} {law:?} vent {ventilated} {extras} {kind:?} #{i}"
                            );
                            let record = i % 2 == 0;
                            let mut rs = Scratch::default();
                            let r = evaluate_reference(&stone, &hp, &p, surface, &mut rs, record);
                            let f = evaluate(&stone, &hp, &p, surface, &mut fs, record);
                            agree(&what, &stone, &hp, &p, &r, &f, record.then_some((&rs, &fs)));
                            contacts += r.in_contact as usize;
                            evaluations += 1;
                            // The same orientation again with rotation: the held (sorted) faces
                            // with ω × r velocities.
                            if kind != Kind::Free {
                                let spun = Pose {
                                    angular_velocity: rng.unit() * 50.0,
                                    ..p
                                };
                                let mut rs = Scratch::default();
                                let r =
                                    evaluate_reference(&stone, &hp, &spun, surface, &mut rs, true);
                                let f = evaluate(&stone, &hp, &spun, surface, &mut fs, true);
                                agree(
                                    &format!("{what} spun"),
                                    &stone,
                                    &hp,
                                    &spun,
                                    &r,
                                    &f,
                                    Some((&rs, &fs)),
                                );
                            }
                            submerged += clearance_agrees(&what, &stone, &p, surface) as usize;
                        }
                    }
                }
            }
        }
    }
    // The poses must exercise what they claim: contact nearly always (a 3 mm swell lifts the
    // water off some grazing poses), some sinking (deep poses).
    assert!(
        contacts * 20 >= evaluations * 17,
        "{contacts} of {evaluations} in contact"
    );
    assert!(submerged > 0, "no deep pose had its underside submerged");
}

#[test]
fn fast_paths_match_the_reference_on_flat_water() {
    oracle("flat", &FlatSurface, 3, 0x2545_f491_4f6c_dd1d);
}

#[test]
fn fast_paths_match_the_reference_on_a_swell() {
    for (i, bounded_below) in [true, false].into_iter().enumerate() {
        let swell = Swell {
            amplitude: 0.003,
            k: DVec3::new(1.0, 0.6, 0.0).normalize() * (std::f64::consts::TAU / 0.3),
            phase: 0.4 + i as f64,
            bounded_below,
        };
        oracle("swell", &swell, 1, 0x9e37_79b9_7f4a_7c15 + i as u64);
    }
}

/// Far above the water, at the surface's highest point, and fully under: the early outs and the
/// extremes of the searches.
#[test]
fn clearance_and_sink_test_agree_at_the_extremes() {
    let mut rng = Rng(7);
    for (name, stone) in stones() {
        for _ in 0..50 {
            let q = DQuat::from_axis_angle(rng.unit(), rng.range(0.0, 3.1));
            let (lo, hi) = extent(&stone, q);
            for z in [1.0, -lo, -lo + 1e-9, -lo - 1e-9, -hi, -hi - 1e-9, -1.0] {
                let p = Pose {
                    position: DVec3::new(0.1, -0.2, z),
                    velocity: DVec3::new(5.0, 0.0, -1.0),
                    orientation: q,
                    angular_velocity: DVec3::ZERO,
                };
                clearance_agrees(&format!("{name} z {z}"), &stone, &p, &FlatSurface);
            }
            let p = Pose {
                position: DVec3::new(0.0, 0.0, -1.0),
                velocity: DVec3::ZERO,
                orientation: q,
                angular_velocity: DVec3::ZERO,
            };
            assert!(underside_submerged(&stone, p.position, q, &FlatSurface));
        }
    }
}

/// The kernel is deterministic: the same pose gives the same bits, cached or not.
#[test]
fn kernel_is_deterministic() {
    let mut rng = Rng(99);
    for (_, stone) in stones() {
        let hp = params(ForceLaw::Rosellini, true, "all");
        for kind in [Kind::Mid, Kind::Free] {
            let p = pose(&mut rng, &stone, kind);
            let mut a = Scratch::default();
            let first = evaluate(&stone, &hp, &p, &FlatSurface, &mut a, true);
            let again = evaluate(&stone, &hp, &p, &FlatSurface, &mut a, true);
            let fresh = evaluate(&stone, &hp, &p, &FlatSurface, &mut Scratch::default(), true);
            assert_eq!(first, again);
            assert_eq!(first, fresh);
        }
    }
}
