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
        })
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
