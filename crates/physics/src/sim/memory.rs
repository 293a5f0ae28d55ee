//! The wetted-extent memory (issue 38; `shared/reference/whole_throw_memory.md` §3, item B): the
//! waterline the stone's faces are clipped against follows the history of the motion, not the
//! instant.
//!
//! In impact theory the wetted extent of a body entering water is set by the history of its
//! penetration (von Kármán 1929; Wagner 1932, the Wagner condition), on exit the wetted area lags
//! the motion (Vega-Martínez et al. 2019), and what ends planing is the time variation of the water
//! rising ahead of the body (Hewitt, Balmforth & McElwaine 2011, J. Fluid Mech. 669). A reduced
//! form with one state: the effective immersion d_e of the stone's lowest point relaxes to the
//! geometric immersion d_g below the ambient surface,
//!
//! ```text
//! dd_e/dt = (d_g − d_e) / τ,   τ = λ L / |U|,
//! ```
//!
//! U the centre of mass's speed and λ the preset's `physics.wetted_memory.lag`. The length L is,
//! by default (`length: Wetted`), the geometric streamwise wetted length s_g: the transit time of
//! the water under the patch, the scale on which a linearised Wagner strip (a planing flat plate
//! whose spray root obeys Wagner's condition: unsteady thin-aerofoil theory with a moving leading
//! edge, derived in docs/studies/wagner_lag) lags its wetted length behind its draft, with
//! λ ≈ 1–3 where that model is self-consistent. `length: Radius` is the reduced form of
//! whole_throw_memory.md, L = R (τ = κ R/|U|). s_g is the waterline's extent along the horizontal
//! flow in closed form: for a lens, the plane's cut of its ellipsoid; for a disk or a plate, the
//! flat bottom face's d_g / tan α (α its slope along the flow), capped at the face's length; held
//! at no less than a hundredth of the radius (a lag of 40 µs at 12 m/s), where the touch begins.
//! While any vertex is below the ambient surface (d_g > 0) each face is
//! clipped against that surface raised by d_e − d_g, which is the same as evaluating the
//! unchanged force law with the stone lowered by d_e − d_g (a vertical shift leaves every lever
//! arm, normal and velocity as it was); when the stone clears the ambient surface the contact
//! ends and d_e returns to 0, so the raised line never holds the stone in the water past its
//! geometric exit. The pressure law is unchanged, so every face's force still opposes its motion
//! into the water: no contact gains energy. κ = 0 is the quasi-steady contact (d_e = d_g).
//!
//! Two options, off unless a preset names them (issue 47; first_bounce_memory.md §2–3,
//! docs/studies/first_bounce):
//!
//! ```text
//! dd_e/dt = A·max(ḋ_g, 0) + (d_g − d_e)/τ,   τ = λ L / (|U| (1 + Π/Π_c)),   Π = |ṡ_g|/|U|,
//! ```
//!
//! Π_c (`strip_frequency`) the linearised Wagner strip's fall of its lag with the reduced frequency
//! (docs/studies/wagner_lag: λ_c(ω̂)/λ_c(0) ≈ 1/(1 + ω̂/Π_c), Π_c ≈ 0.09–0.15 on its b/s = 2–3
//! curves), ṡ_g = (∂s_g/∂d_g) ḋ_g with Π held at most `MAX_REDUCED_FREQUENCY` (5); A (`entry_lead`)
//! Wagner's condition, the wetted extent of an entering body outrunning the geometric one (4/3 a
//! flat plate from a fixed edge, ½–¾ with a Kutta edge and a finite patch). ḋ_g is the sinking
//! speed of the shape's support point (the envelope theorem). The lead only deepens d_e while the
//! stone sinks, so the faces' forces still oppose their motion: no energy is gained.

use glam::{DQuat, DVec3};

use super::params::{LagLength, MemoryParams, Shape};

/// Largest effective immersion an integrator may hold (m): far below any stone's centre, so a
/// fixed-step integrator run far past its stable step stays finite.
pub(crate) const MAX_MEMORY: f64 = 1.0;

/// The shortest wetted length the lag is taken over, as a share of the stone's radius.
pub(crate) const MIN_WETTED_SHARE: f64 = 0.01;

/// The memory's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WettedMemory {
    /// λ (or κ with `LagLength::Radius`), dimensionless.
    pub lag: f64,
    pub length: LagLength,
    /// The stone's shape (the wetted length's geometry).
    pub shape: Shape,
    /// R (m): a disk's or lens's radius, half a plate's length along body x.
    pub radius: f64,
    /// Π_c (`None`: a lag independent of the contact's reduced frequency).
    pub strip_frequency: Option<f64>,
    /// A, Wagner's entry lead.
    pub entry_lead: f64,
}

/// The memory's rates at one state: dd_e/dt = `lead` + (d_g − d_e) · `relax`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct MemoryRates {
    /// 1/τ (1/s).
    pub relax: f64,
    /// A·max(ḋ_g, 0) (m/s).
    pub lead: f64,
}

impl WettedMemory {
    /// The memory of a stone of `shape`; `None` without one (quasi-steady).
    pub fn new(params: Option<MemoryParams>, shape: &Shape) -> Option<Self> {
        let params = params?;
        let radius = match *shape {
            Shape::Disk { radius, .. } | Shape::Lens { radius, .. } => radius,
            Shape::Plate { length, .. } => 0.5 * length,
        };
        (params.lag > 0.0 && params.lag.is_finite() && radius > 0.0).then_some(Self {
            lag: params.lag,
            length: params.length,
            shape: *shape,
            radius,
            strip_frequency: params.strip_frequency,
            entry_lead: params.entry_lead,
        })
    }

    /// The rates of a stone at `orientation` moving at `velocity` and turning at `spin` (world),
    /// its lowest point `d_g` below the ambient surface: ḋ_g is the lowest point's sinking speed
    /// (the support point's velocity, by the envelope theorem), ṡ_g = (∂s_g/∂d_g) ḋ_g.
    pub fn rates(&self, orientation: DQuat, velocity: DVec3, spin: DVec3, d_g: f64) -> MemoryRates {
        let needs_rate = self.strip_frequency.is_some() || self.entry_lead > 0.0;
        if !needs_rate {
            return MemoryRates {
                relax: self.relax_rate(orientation, velocity, d_g),
                lead: 0.0,
            };
        }
        let offset = orientation * lowest_point(&self.shape, orientation);
        let sinking = -(velocity + spin.cross(offset)).z;
        let lead = self.entry_lead * sinking.max(0.0);
        let mut relax = self.relax_rate(orientation, velocity, d_g);
        if let Some(pc) = self.strip_frequency {
            let floor = MIN_WETTED_SHARE * self.radius;
            let growth = wetted_growth(&self.shape, orientation, velocity, d_g, floor) * sinking;
            let pi = (growth.abs() / velocity.length()).min(MAX_REDUCED_FREQUENCY);
            let r = relax * (1.0 + pi / pc);
            relax = if r.is_finite() { r } else { 0.0 };
        }
        MemoryRates { relax, lead }
    }

    /// 1/τ = |U| / (λ L) (1/s) of a stone at `orientation` (stone → world) moving at `velocity`
    /// with its lowest point `d_g` below the ambient surface; 0 at rest, where the memory holds.
    pub fn relax_rate(&self, orientation: DQuat, velocity: DVec3, d_g: f64) -> f64 {
        let length = match self.length {
            LagLength::Radius => self.radius,
            LagLength::Wetted => wetted_length(&self.shape, orientation, velocity, d_g)
                .max(MIN_WETTED_SHARE * self.radius),
        };
        let r = velocity.length() / (self.lag * length);
        if r.is_finite() {
            r
        } else {
            0.0
        }
    }

    /// The memory's state after `h` at a fixed target `d_g` and rate `rate` (exact relaxation,
    /// stable at any step: the fixed-step integrators use it).
    pub fn relax(d_e: f64, d_g: f64, rate: f64, h: f64) -> f64 {
        (d_g + (d_e - d_g) * (-rate * h).exp()).clamp(0.0, MAX_MEMORY)
    }
}

/// The largest reduced frequency Π the lag is shortened by: the strip's curves reach ω̂ = 5
/// (first_bounce_memory.md §2); at the first instant of a touch ∂s_g/∂d_g is unbounded.
pub(crate) const MAX_REDUCED_FREQUENCY: f64 = 5.0;

/// ∂s_g/∂d_g (dimensionless) by a central difference over a depth step of a thousandth of the
/// radius, one-sided at the surface.
fn wetted_growth(shape: &Shape, orientation: DQuat, velocity: DVec3, d_g: f64, floor: f64) -> f64 {
    let eps = 0.1 * floor;
    let lo = (d_g - eps).max(0.0);
    let hi = d_g + eps;
    let s = |d: f64| wetted_length(shape, orientation, velocity, d).max(floor);
    (s(hi) - s(lo)) / (hi - lo)
}

/// The lowest point of the stone's shape (body frame) when `orientation` (stone → world) holds
/// it: the support point along the world's down direction (a lens's ellipsoid, a disk's bottom
/// rim, a plate's bottom corner).
pub(crate) fn lowest_point(shape: &Shape, orientation: DQuat) -> DVec3 {
    let u = orientation.inverse() * DVec3::Z;
    match *shape {
        Shape::Lens { radius, thickness } => {
            let axes = DVec3::new(radius, radius, 0.5 * thickness);
            let m = axes * axes * u;
            let norm = (axes * u).length();
            if norm > 0.0 {
                -m / norm
            } else {
                DVec3::ZERO
            }
        }
        Shape::Disk { radius, thickness } => {
            let h = DVec3::new(u.x, u.y, 0.0)
                .try_normalize()
                .unwrap_or(DVec3::ZERO);
            -h * radius - DVec3::Z * (0.5 * thickness).copysign(u.z)
        }
        Shape::Plate {
            length,
            width,
            thickness,
        } => -DVec3::new(
            (0.5 * length).copysign(u.x),
            (0.5 * width).copysign(u.y),
            (0.5 * thickness).copysign(u.z),
        ),
    }
}

/// The geometric immersion of the lowest point below the ambient surface (m, ≥ 0) from its
/// clearance above it.
pub(crate) fn geometric_immersion(clearance: f64) -> f64 {
    (-clearance).max(0.0)
}

/// The geometric streamwise wetted length s_g (m): the extent along the horizontal flow of the
/// stone's waterline when its lowest point is `d_g` below a horizontal surface. The stone's
/// diameter when it moves straight up or down (no streamwise direction).
pub(crate) fn wetted_length(shape: &Shape, orientation: DQuat, velocity: DVec3, d_g: f64) -> f64 {
    let flow = DVec3::new(velocity.x, velocity.y, 0.0);
    let Some(flow) = flow.try_normalize() else {
        return 2.0 * shape.half_extent();
    };
    let body = orientation.inverse();
    let (n, e) = (body * DVec3::Z, body * flow);
    match *shape {
        Shape::Lens { radius, thickness } => {
            ellipsoid_chord(DVec3::new(radius, radius, 0.5 * thickness), n, e, d_g)
        }
        Shape::Disk { radius, .. } => flat_face_chord(n, e, d_g, 2.0 * radius),
        Shape::Plate { length, width, .. } => {
            flat_face_chord(n, e, d_g, (length * e.x).abs() + (width * e.y).abs())
        }
    }
}

/// The chord along `e` (body, horizontal) of the cut of the ellipsoid of semi-axes `axes` by the
/// plane normal to `n` (body, up) at `d` above its lowest point: in u = D⁻¹x the ellipsoid is the
/// unit sphere, the plane (Dn)·u = −|Dn| + d cuts it in a circle of radius ρ about δ m̂, and
/// e·x = (De)·u spans 2ρ |(De)⊥m̂|.
fn ellipsoid_chord(axes: DVec3, n: DVec3, e: DVec3, d: f64) -> f64 {
    let m = axes * n;
    let mlen = m.length();
    if mlen <= 0.0 {
        return 0.0;
    }
    let delta = (d / mlen - 1.0).clamp(-1.0, 1.0);
    let rho = (1.0 - delta * delta).max(0.0).sqrt();
    let de = axes * e;
    let along = de.dot(m / mlen);
    2.0 * rho * (de.length_squared() - along * along).max(0.0).sqrt()
}

/// The wetted length behind the lowest point of a flat bottom face (outward normal −`n`'s
/// stone axis, body z) sloping at α along `e`: d / tan α, at most `cap` (the face's length along
/// the flow).
fn flat_face_chord(n: DVec3, e: DVec3, d: f64, cap: f64) -> f64 {
    // The face's plane z_body = const rises along e at (a·e)/(a·ẑ) with a = body z in world axes:
    // in body axes a = (0, 0, 1), ẑ = n, e = e.
    let slope = e.z.abs() / n.z.abs().max(f64::MIN_POSITIVE);
    if slope * cap <= d {
        cap
    } else {
        d / slope
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn off_at_zero_and_radius_by_shape() {
        let lens = Shape::Lens {
            radius: 0.05,
            thickness: 0.01,
        };
        assert!(WettedMemory::new(None, &lens).is_none());
        let radius = LagLength::Radius;
        let p = |lag| {
            Some(MemoryParams {
                lag,
                length: radius,
                ..MemoryParams::default()
            })
        };
        assert!(WettedMemory::new(p(0.0), &lens).is_none());
        assert_eq!(
            WettedMemory::new(p(0.2), &lens).map(|m| m.radius),
            Some(0.05)
        );
        let plate = Shape::Plate {
            length: 0.1,
            width: 0.2,
            thickness: 0.002,
        };
        assert_eq!(
            WettedMemory::new(p(0.2), &plate).map(|m| m.radius),
            Some(0.05)
        );
    }

    #[test]
    fn relaxation_is_exact_and_bounded() {
        let lens = Shape::Lens {
            radius: 0.05,
            thickness: 0.01,
        };
        let params = MemoryParams {
            lag: 0.2,
            length: LagLength::Radius,
            ..MemoryParams::default()
        };
        let m = WettedMemory::new(Some(params), &lens).unwrap();
        let rate = m.relax_rate(DQuat::IDENTITY, DVec3::X * 12.0, 1e-3);
        // τ = κ R / U = 0.2 × 0.05 / 12 s.
        assert!((1.0 / rate - 0.2 * 0.05 / 12.0).abs() < 1e-15);
        // One time constant closes 1 − 1/e of the gap.
        let d = WettedMemory::relax(0.0, 1e-3, rate, 1.0 / rate);
        assert!((d - 1e-3 * (1.0 - (-1.0f64).exp())).abs() < 1e-15);
        // Any step: between the start and the target.
        for h in [1e-6, 1e-3, 1.0, 1e6] {
            let d = WettedMemory::relax(2e-3, 1e-3, rate, h);
            assert!((1e-3..=2e-3).contains(&d));
        }
        assert_eq!(m.relax_rate(DQuat::IDENTITY, DVec3::ZERO, 1e-3), 0.0);
        assert_eq!(geometric_immersion(0.01), 0.0);
        assert_eq!(geometric_immersion(-0.01), 0.01);
    }
}

#[cfg(test)]
mod wetted_length_tests {
    use super::*;

    /// A stone tilted nose up by `tilt` (the preset's Ry(−tilt)), moving along +x.
    fn tilted(tilt_deg: f64) -> DQuat {
        DQuat::from_rotation_y(-tilt_deg.to_radians())
    }

    /// A flat face at tilt α wets d / tan α behind its lowest point, up to its length.
    #[test]
    fn a_tilted_disk_wets_d_over_tan_alpha() {
        let disk = Shape::Disk {
            radius: 0.05,
            thickness: 0.01,
        };
        let d = 7.4e-4;
        let s = wetted_length(&disk, tilted(20.0), DVec3::X * 12.0, d);
        assert!((s - d / 20f64.to_radians().tan()).abs() < 1e-12, "{s}");
        // Lying flat it wets its whole diameter at once.
        let s = wetted_length(&disk, tilted(0.0), DVec3::X * 12.0, 1e-4);
        assert_eq!(s, 0.1);
        // Falling straight down: no streamwise direction, the diameter.
        assert_eq!(wetted_length(&disk, tilted(20.0), -DVec3::Z, d), 0.1);
    }

    /// A lens: level, the cut of its ellipsoid at depth d is a circle of radius R √(2d/b − d²/b²)
    /// (b the half-thickness); tilted, the chord of the cut ellipse, nearly the flat face's at
    /// small depth when the lens is thin, and the diameter when cut through its middle.
    #[test]
    fn a_lens_wets_the_chord_of_its_ellipsoid() {
        let (r, b) = (0.05, 0.006);
        let lens = Shape::Lens {
            radius: r,
            thickness: 2.0 * b,
        };
        let d = 1e-3;
        let level = wetted_length(&lens, tilted(0.0), DVec3::X * 12.0, d);
        let want = 2.0 * r * (2.0 * d / b - d * d / (b * b)).sqrt();
        assert!((level - want).abs() < 1e-12, "{level} against {want}");
        let through = wetted_length(&lens, tilted(0.0), DVec3::X * 12.0, b);
        assert!((through - 2.0 * r).abs() < 1e-12);
        // Tilted 20°: the world-x roots of the ellipsoid's quadratic along lines across the plane.
        let q = tilted(20.0);
        let got = wetted_length(&lens, q, DVec3::X * 3.0, d);
        let inv = DVec3::new(1.0 / r, 1.0 / r, 1.0 / b);
        let z0 = -(DVec3::new(r, r, b) * (q.inverse() * DVec3::Z)).length() + d;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in -20000..=20000 {
            let y = r * i as f64 / 20000.0;
            // |D⁻¹ Qᵀ (x, y, z0)|² = 1: a x² + 2 b' x + c = 0.
            let (u, w) = (
                inv * (q.inverse() * DVec3::X),
                inv * (q.inverse() * DVec3::new(0.0, y, z0)),
            );
            let (qa, qb, qc) = (u.dot(u), u.dot(w), w.dot(w) - 1.0);
            let disc = qb * qb - qa * qc;
            if disc >= 0.0 {
                lo = lo.min((-qb - disc.sqrt()) / qa);
                hi = hi.max((-qb + disc.sqrt()) / qa);
            }
        }
        assert!((got - (hi - lo)).abs() < 1e-9, "{got} against {}", hi - lo);
    }
}

#[cfg(test)]
mod law_tests {
    use super::*;

    fn lens() -> Shape {
        Shape::Lens {
            radius: 0.05,
            thickness: 0.012,
        }
    }

    fn memory(shape: Shape, strip_frequency: Option<f64>, entry_lead: f64) -> WettedMemory {
        let params = MemoryParams {
            lag: 2.0,
            length: LagLength::Wetted,
            strip_frequency,
            entry_lead,
        };
        WettedMemory::new(Some(params), &shape).unwrap()
    }

    /// The lowest point is the support point: no point of the shape lies lower along the world's
    /// up direction, for a lens, a disk and a plate at any attitude.
    #[test]
    fn the_lowest_point_is_lowest() {
        let shapes = [
            lens(),
            Shape::Disk {
                radius: 0.03,
                thickness: 0.004,
            },
            Shape::Plate {
                length: 0.1,
                width: 0.06,
                thickness: 0.005,
            },
        ];
        for shape in shapes {
            for (tilt, bank, heading) in [
                (20.0f64, 0.0f64, 0.0f64),
                (7.0, -30.0, 40.0),
                (-15.0, 60.0, 200.0),
            ] {
                let q = DQuat::from_rotation_z(heading.to_radians())
                    * DQuat::from_rotation_x(bank.to_radians())
                    * DQuat::from_rotation_y(-tilt.to_radians());
                let low = (q * lowest_point(&shape, q)).z;
                // Sample the shape's surface: a lens's ellipsoid, a disk's rims, a plate's corners.
                let mut lowest_sample = f64::INFINITY;
                for i in 0..720 {
                    let phi = i as f64 * std::f64::consts::TAU / 720.0;
                    for j in 0..=90 {
                        let p = match shape {
                            Shape::Lens { radius, thickness } => {
                                let th = (j as f64 / 90.0 - 0.5) * std::f64::consts::PI;
                                DVec3::new(
                                    radius * th.cos() * phi.cos(),
                                    radius * th.cos() * phi.sin(),
                                    0.5 * thickness * th.sin(),
                                )
                            }
                            Shape::Disk { radius, thickness } => DVec3::new(
                                radius * phi.cos(),
                                radius * phi.sin(),
                                if j % 2 == 0 { 0.5 } else { -0.5 } * thickness,
                            ),
                            Shape::Plate {
                                length,
                                width,
                                thickness,
                            } => DVec3::new(
                                0.5 * length * if i % 2 == 0 { 1.0 } else { -1.0 },
                                0.5 * width * if (i / 2) % 2 == 0 { 1.0 } else { -1.0 },
                                0.5 * thickness * if j % 2 == 0 { 1.0 } else { -1.0 },
                            ),
                        };
                        lowest_sample = lowest_sample.min((q * p).z);
                    }
                }
                // The sampled surface can only be as low as the support point, and its sampling
                // misses it by at most the chord sag of a 0.5° step on the largest radius.
                assert!(
                    low <= lowest_sample + 1e-12,
                    "{shape:?} {tilt}: {low} > {lowest_sample}"
                );
                assert!(
                    lowest_sample - low < 0.06 * 4e-5,
                    "{shape:?} {tilt}: {low} vs {lowest_sample}"
                );
            }
        }
    }

    /// Without Π_c and lead the rates are issue 38's law, bit for bit.
    #[test]
    fn without_the_new_terms_the_law_is_unchanged() {
        let m = memory(lens(), None, 0.0);
        let q = DQuat::from_rotation_y(-0.2);
        for d in [1e-5, 1e-3, 4e-3] {
            let r = m.rates(
                q,
                DVec3::new(12.0, 0.0, -0.8),
                DVec3::new(0.0, 3.0, 80.0),
                d,
            );
            assert_eq!(r.relax, m.relax_rate(q, DVec3::new(12.0, 0.0, -0.8), d));
            assert_eq!(r.lead, 0.0);
        }
    }

    /// On a disk's flat face s_g = d/tan α, so ṡ_g = ḋ_g/tan α and the strip's lag is
    /// τ = λ s_g / (|U| + |ṡ_g|/Π_c); the lead is A·ḋ_g while sinking and 0 while rising.
    #[test]
    fn the_strip_lag_shortens_with_the_growth_of_the_wetted_length() {
        let disk = Shape::Disk {
            radius: 0.025,
            thickness: 0.00275,
        };
        let (alpha, pc, lead) = (20f64.to_radians(), 0.12, 0.75);
        let m = memory(disk, Some(pc), lead);
        let q = DQuat::from_rotation_y(-alpha);
        let d = 4e-3;
        let v = DVec3::new(3.3, 0.0, -1.2);
        let r = m.rates(q, v, DVec3::ZERO, d);
        let s = d / alpha.tan();
        let s_dot = 1.2 / alpha.tan();
        let want = (v.length() + s_dot / pc) / (2.0 * s);
        assert!(
            (r.relax / want - 1.0).abs() < 1e-6,
            "{} against {want}",
            r.relax
        );
        assert!((r.lead - lead * 1.2).abs() < 1e-12, "{}", r.lead);
        // Rising: the lag shortens as much (|ṡ_g|), the lead is off.
        let up = DVec3::new(3.3, 0.0, 1.2);
        let r = m.rates(q, up, DVec3::ZERO, d);
        assert!((r.relax / want - 1.0).abs() < 1e-6);
        assert_eq!(r.lead, 0.0);
        // A spin about the axis does not move the lowest point of a body of revolution.
        let spun = m.rates(q, v, q * DVec3::Z * 400.0, d);
        assert!((spun.relax / want - 1.0).abs() < 1e-6 && (spun.lead - lead * 1.2).abs() < 1e-9);
        // Π is capped: at the first instant of a lens's touch ∂s_g/∂d_g is unbounded.
        let m = memory(lens(), Some(pc), 0.0);
        let r = m.rates(q, v, DVec3::ZERO, 0.0);
        let cap = m.relax_rate(q, v, 0.0) * (1.0 + MAX_REDUCED_FREQUENCY / pc);
        assert!(
            r.relax.is_finite() && r.relax <= cap * (1.0 + 1e-12),
            "{}",
            r.relax
        );
    }
}
