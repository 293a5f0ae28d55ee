//! Air on the stone in flight: the lift, drag and pitching moment of a spinning disc wing.
//!
//! Model: the six-degree-of-freedom flying-disc model of Crowther & Potts (2007, *Simulation of a
//! spin-stabilised sports disc*, Sports Engineering 10), with the linear coefficients Hummel fitted
//! to flight and wind-tunnel data (2003, *Frisbee flight simulation and throw biomechanics*, MSc
//! thesis, UC Davis; Potts & Crowther 2002's wind-tunnel loads): with α the angle of attack (the
//! air meeting the underside is α > 0), q = ½ ρ_air U², S = π R² the plan area and d = 2R,
//!
//!   L = q S C_L along the disc's axis made normal to the flight path,   C_L = C_Lα α,
//!   D = q S C_D against the velocity,                                   C_D = C_D0 + C_Dα α²,
//!   M = q S d C_M, nose up about v̂ × â (the centre of pressure ahead),  C_M = C_Mα α.
//!
//! A stone's lens is up–down symmetric, so the camber terms of a Frisbee (C_L0, C_M0, its
//! zero-lift angle) vanish; the slopes and C_D0 are Hummel's (1.91, 0.69, 0.43 per radian, 0.18).
//! Beyond the measured range (|α| > 30°, Potts & Crowther) the coefficients are held at their 30°
//! values: there is no stall model. The damping derivatives (pitch, roll and spin damping, each
//! below 2 % of the moments here) are left out. In contact the water's forces are ~10³ times
//! larger, so the air acts in flight only, where the pitching moment precesses a spinning stone
//! (a roll of J/(I₃ ω) per unit of moment impulse: less spin, more roll) and the lift lengthens a hop.
//!
//! Flight with air is integrated by kick–drift–kick splitting (Strang): half a kick of the air's
//! force and torque, the exact force-free flight (parabola and torque-free precession), half a
//! kick, in substeps of at most `AIR_SUBSTEP`; second order, and exact flight when the air is off.

use glam::{DQuat, DVec3};

pub use super::params::AirParams;
use super::params::Shape;

/// Longest substep of the kick–drift–kick flight (s).
pub(crate) const AIR_SUBSTEP: f64 = 2.5e-4;

/// Largest angle of attack of the linear coefficients (rad): 30°, the edge of the measured range.
pub(crate) const ALPHA_MAX: f64 = std::f64::consts::FRAC_PI_6;

/// The air's model for one stone: coefficients with the stone's plan area and diameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Air {
    params: AirParams,
    /// ½ ρ S (kg/m)
    half_rho_s: f64,
    /// d (m)
    diameter: f64,
}

/// The air's force (N, world) and torque about the centre of mass (N m, world).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AirLoad {
    /// Lift plus drag (N, world).
    pub force: DVec3,
    /// Pitching moment about the centre of mass (N m, world).
    pub torque: DVec3,
    /// Angle of attack (rad).
    pub alpha: f64,
}

impl Air {
    /// For a stone of plan area `area` (m²) and chord `chord` (m): π R² and 2R for a disc or lens.
    pub fn new(params: AirParams, area: f64, chord: f64) -> Self {
        Self {
            params,
            half_rho_s: 0.5 * params.density * area,
            diameter: chord,
        }
    }

    /// For a shape: a disc or lens by its circle; a plate by its rectangle and its length.
    pub fn for_shape(params: AirParams, shape: &Shape) -> Self {
        match *shape {
            Shape::Disk { radius, .. } | Shape::Lens { radius, .. } => {
                Self::new(params, std::f64::consts::PI * radius * radius, 2.0 * radius)
            }
            Shape::Plate { length, width, .. } => Self::new(params, length * width, length),
        }
    }

    /// The air's load on a stone moving at `velocity` (still air) with its symmetry axis along
    /// `orientation · ẑ`.
    pub fn load(&self, velocity: DVec3, orientation: DQuat) -> AirLoad {
        let speed = velocity.length();
        if speed == 0.0 || !speed.is_finite() {
            return AirLoad::default();
        }
        let v_hat = velocity / speed;
        let axis = orientation * DVec3::Z;
        let along = v_hat.dot(axis).clamp(-1.0, 1.0);
        let alpha = -along.asin();
        let a = alpha.clamp(-ALPHA_MAX, ALPHA_MAX);
        let p = &self.params;
        let q_s = self.half_rho_s * speed * speed;
        // The axis made normal to the path: the lift's direction for α > 0 (zero when the stone
        // moves along its axis, where the lift has no direction and the linear model none either).
        let normal = axis - v_hat * along;
        let n_len = normal.length();
        let lift_dir = if n_len > 1e-12 {
            normal / n_len
        } else {
            DVec3::ZERO
        };
        let pitch_axis = v_hat.cross(axis);
        let p_len = pitch_axis.length();
        let pitch_dir = if p_len > 1e-12 {
            pitch_axis / p_len
        } else {
            DVec3::ZERO
        };
        let lift = lift_dir * (q_s * p.lift_slope * a);
        let drag = -v_hat * (q_s * (p.drag_zero + p.drag_slope * a * a));
        AirLoad {
            force: lift + drag,
            torque: pitch_dir * (q_s * self.diameter * p.moment_slope * a),
            alpha,
        }
    }

    /// Upper bounds of the air's force (N) and torque (N m) at speeds up to `speed`.
    pub fn bounds(&self, speed: f64) -> (f64, f64) {
        let p = &self.params;
        let q_s = self.half_rho_s * speed * speed;
        let cl = p.lift_slope.abs() * ALPHA_MAX;
        let cd = p.drag_zero.abs() + p.drag_slope.abs() * ALPHA_MAX * ALPHA_MAX;
        (
            q_s * (cl + cd),
            q_s * self.diameter * p.moment_slope.abs() * ALPHA_MAX,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc() -> Air {
        Air::for_shape(
            AirParams::default(),
            &Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
        )
    }

    /// A stone tilted nose up by `tilt` moving along +x.
    fn tilted(tilt: f64) -> DQuat {
        DQuat::from_rotation_y(-tilt)
    }

    #[test]
    fn lift_drag_and_moment_follow_the_linear_coefficients() {
        let air = disc();
        let (u, tilt) = (12.0, 10f64.to_radians());
        let load = air.load(DVec3::new(u, 0.0, 0.0), tilted(tilt));
        assert!((load.alpha - tilt).abs() < 1e-12, "alpha {}", load.alpha);
        let q_s = 0.5 * 1.204 * std::f64::consts::PI * 0.05 * 0.05 * u * u;
        // Lift is vertical (the path is horizontal), drag along −x.
        assert!((load.force.z - q_s * 1.91 * tilt).abs() < 1e-12 * q_s);
        let cd = 0.18 + 0.69 * tilt * tilt;
        assert!((load.force.x + q_s * cd).abs() < 1e-12 * q_s);
        assert!(load.force.y.abs() < 1e-15);
        // Nose up for a stone moving along +x is a rotation about −y.
        let m = q_s * 0.1 * 0.43 * tilt;
        assert!((load.torque.y + m).abs() < 1e-12 * m, "{:?}", load.torque);
    }

    #[test]
    fn an_upside_down_stone_feels_the_same_air() {
        let air = disc();
        let v = DVec3::new(9.0, 1.0, -2.0);
        let q = tilted(0.3) * DQuat::from_rotation_z(0.7);
        let flipped = q * DQuat::from_rotation_x(std::f64::consts::PI);
        let (a, b) = (air.load(v, q), air.load(v, flipped));
        assert!((a.force - b.force).length() < 1e-12 * a.force.length());
        assert!((a.torque - b.torque).length() < 1e-12 * a.torque.length());
    }

    #[test]
    fn the_load_is_bounded_and_finite_at_any_attitude() {
        let air = disc();
        let u = 20.0;
        let (f_max, m_max) = air.bounds(u);
        for i in 0..200 {
            let t = i as f64 * 0.1;
            let q = DQuat::from_euler(glam::EulerRot::ZYX, t, 1.7 * t, 0.3 * t);
            let v = DVec3::new(t.cos(), t.sin(), (0.5 * t).cos()).normalize() * u;
            let l = air.load(v, q);
            assert!(l.force.is_finite() && l.torque.is_finite());
            assert!(l.force.length() <= f_max * (1.0 + 1e-12));
            assert!(l.torque.length() <= m_max * (1.0 + 1e-12));
        }
        // Moving along the axis: no lift, no moment, only drag.
        let l = air.load(DVec3::new(0.0, 0.0, -5.0), DQuat::IDENTITY);
        assert_eq!(l.torque, DVec3::ZERO);
        assert!(l.force.x == 0.0 && l.force.y == 0.0 && l.force.z > 0.0);
        assert_eq!(air.load(DVec3::ZERO, DQuat::IDENTITY), AirLoad::default());
    }

    #[test]
    fn no_lift_at_zero_incidence() {
        let l = disc().load(DVec3::new(12.0, 0.0, 0.0), DQuat::IDENTITY);
        assert_eq!(l.alpha, 0.0);
        assert_eq!(l.force.z, 0.0);
        assert_eq!(l.torque, DVec3::ZERO);
    }
}
