//! The force law of one wetted face and the types of one evaluation (paper eqs. 11–26; design.md §4):
//! the constants ([`HydroParams`]), the pose, the surface, the sums; shared by the reference sum
//! (`hydro`), the fast kernel (`kernel`) and the smooth quadrature (`smooth`), which import it and
//! nothing of each other.
//!
//! For a wetted triangle with outward unit normal N, wetted area S, local velocity v at the wetted
//! centroid (v = V + ω × r), v_n = v·N, V_t = v − v_n N and U = |V| the centre-of-mass speed:
//! - Paper law (eqs. 17–18; eq. 17 reads C_l ρ_w): F_n = ½ C_l ρ v_n² S, F_t = ½ C_f ρ |V_t|² S;
//! - Bocquet law (eqs. 1–3): ½ C_l ρ U² S and ½ C_f ρ U² S;
//! - Rosellini law (Rosellini et al. 2005, eq. 4.2): C_l ρ U max(0, v_n) S, friction as the paper.
//!
//! The normal force acts along −N (eq. 19), friction along −V_t/|V_t| (eqs. 20–23); a zero |V_t|
//! gives zero friction. With ventilation, a face receding from the water (v_n ≤ 0) sits in the air
//! cavity and gets neither pressure nor friction.
//!
//! Options that extend the paper (issue 11; each a `physics` field whose default is the paper's model):
//! - `pressure_sign: OpposesMotion` — the energy-consistent reading of eq. 19: a receding wetted face
//!   (only possible with `ventilated: false`) is loaded along +N, so the pressure always opposes the
//!   face's normal velocity and its power −p|v_n| S is never positive (physics.md §7.1).
//! - `axial_spin: Resal` — the mesh stands for a smooth body of revolution, whose surface spinning
//!   about its axis a moves only along itself: the normal velocity is taken from V + ω_⊥ × r with
//!   ω_⊥ = ω − (ω·a)a, and the pressure's torque about a (zero on the smooth body) is removed, so the
//!   facets neither paddle the water nor spin the stone up; friction still sees the full ω × r.
//!   The mesh meets the water without turning with the spin (`integrate::mesh_orientation`): the
//!   pose this module gets is already in that frame. (`axial_spin: Smooth`, the same law on a mesh
//!   turning with the spin, is retired: docs/studies/retired.md.)
//! - `buoyancy: true` — hydrostatic pressure ρ g d on each loaded face (Archimedes; d the depth of the
//!   wetted centroid below the surface, exact for pressure linear in depth over a planar polygon),
//!   along −N: the buoyant term of planing lift (Savitsky 1964's second term; Hewitt et al. 2011).
//!   `hydrostatic: LoadedFaces` (default) loads only the faces that carry the dynamic pressure;
//!   `WettedFaces` loads every wetted face, so a submerged stone feels Archimedes' ρ g V.

use glam::{DQuat, DVec3};

use super::params::{ForceLaw, Hydrostatic, Physics, PressureSign};

/// The constants of one force evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HydroParams {
    /// Which law gives the pressure and friction (paper, Bocquet or Rosellini; see the module doc).
    pub law: ForceLaw,
    /// Lift (pressure) coefficient C_l: the preset's, or the law's default.
    pub lift: f64,
    /// Friction coefficient C_f: the preset's, or the law's default.
    pub friction: f64,
    /// Water density ρ (kg/m³).
    pub density: f64,
    /// Ventilation: a wetted face receding from the water (v_n ≤ 0) sits in the air cavity and
    /// gets no dynamic pressure nor friction.
    pub ventilated: bool,
    /// Pressure on a receding wetted face opposes its motion (`PressureSign::OpposesMotion`).
    pub opposing: bool,
    /// The axial spin of a body of revolution is not felt as normal velocity (`AxialSpin::Resal`).
    pub smooth_spin: bool,
    /// ρ g for hydrostatic pressure on the loaded faces (N/m³), 0 without buoyancy.
    pub rho_g: f64,
    /// The hydrostatic pressure acts on every wetted face, ventilated or not
    /// (`Hydrostatic::WettedFaces`).
    pub hydrostatic_wetted: bool,
}

impl HydroParams {
    /// The constants of a preset's `physics`: the law, its coefficients (the preset's or the
    /// law's defaults), ρ, the extension options, and ρ g when `buoyancy` is on.
    pub fn from_physics(p: &Physics) -> Self {
        let (lift, friction) = p.coefficients();
        Self {
            law: p.force_law,
            lift,
            friction,
            density: p.water_density,
            ventilated: p.ventilated,
            opposing: p.pressure_sign == PressureSign::OpposesMotion,
            smooth_spin: p.axial_spin.is_smooth(),
            rho_g: if p.buoyancy {
                p.water_density * p.gravity
            } else {
                0.0
            },
            hydrostatic_wetted: p.hydrostatic == Hydrostatic::WettedFaces,
        }
    }
}

/// Water force on one wetted face (eq. 24): normal N (unit, outward), wetted area S, local
/// velocity v (for friction), the face's normal velocity v_n (v·N, or the smooth body's, see
/// `axial_spin`), centre-of-mass speed U, and the depth of the wetted centroid below the surface.
pub(crate) fn face_force(
    hp: &HydroParams,
    normal: DVec3,
    area: f64,
    v: DVec3,
    vn: f64,
    speed: f64,
    depth: f64,
) -> DVec3 {
    if hp.ventilated && vn <= 0.0 {
        return if hp.hydrostatic_wetted {
            -normal * (hp.rho_g * depth.max(0.0) * area)
        } else {
            DVec3::ZERO
        };
    }
    let half_rho_s = 0.5 * hp.density * area;
    let pressure = match hp.law {
        ForceLaw::Paper => hp.lift * half_rho_s * vn * vn,
        ForceLaw::Bocquet => hp.lift * half_rho_s * speed * speed,
        ForceLaw::Rosellini => {
            let vn_loaded = if hp.opposing { vn.abs() } else { vn.max(0.0) };
            hp.lift * hp.density * area * speed * vn_loaded
        }
    };
    let sign = pressure_sign(hp.opposing, vn);
    let hydrostatic = hp.rho_g * depth.max(0.0) * area;
    let f = -normal * (sign * pressure + hydrostatic);
    f + friction_force(hp, v - normal * v.dot(normal), area, speed)
}

/// The sign of the dynamic pressure along −N on a face of normal velocity `vn`: as printed every
/// loaded face is pushed along −N; opposing its motion (`opposing`), a receding face (v_n < 0) is
/// pulled along +N and a face with v_n = 0 carries none.
#[inline(always)]
pub fn pressure_sign(opposing: bool, vn: f64) -> f64 {
    if !opposing || vn > 0.0 {
        1.0
    } else if vn < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The friction drag on a loaded face of `area` whose tangential velocity is `vt`: along −v_t,
/// C_f ρ S |v_t|² / 2 (the paper's and Rosellini's law) or C_f ρ S U² / 2 (Bocquet's).
#[inline]
pub(crate) fn friction_force(hp: &HydroParams, vt: DVec3, area: f64, speed: f64) -> DVec3 {
    let vt_len = vt.length();
    if vt_len > 0.0 {
        let half_rho_s = 0.5 * hp.density * area;
        let friction = match hp.law {
            ForceLaw::Bocquet => hp.friction * half_rho_s * speed * speed,
            ForceLaw::Paper | ForceLaw::Rosellini => hp.friction * half_rho_s * vt_len * vt_len,
        };
        -vt * (friction / vt_len)
    } else {
        DVec3::ZERO
    }
}

/// The water surface as the stone sees it: signed height above it of a world point.
pub trait Surface {
    /// Surface elevation η at (x, y).
    fn height(&self, x: f64, y: f64) -> f64;
    /// An upper bound of η over the whole surface (for cheap rejection).
    fn max_height(&self) -> f64;
    /// An upper bound of η over the rectangle [lo, hi] (world x, y); [`Surface::max_height`]
    /// unless the surface knows better.
    fn max_height_over(&self, _lo: [f64; 2], _hi: [f64; 2]) -> f64 {
        self.max_height()
    }
    /// A lower bound of η over the whole surface (lets the kernel skip classifying faces that are
    /// surely under); −∞ when unknown.
    fn min_height(&self) -> f64 {
        f64::NEG_INFINITY
    }
    /// True when the surface is the plane z = 0 (lets the hot loop skip the height lookups).
    fn is_flat(&self) -> bool {
        false
    }
}

/// The water at rest: z = 0.
#[derive(Debug, Clone, Copy, Default)]
pub struct FlatSurface;

impl Surface for FlatSurface {
    fn height(&self, _x: f64, _y: f64) -> f64 {
        0.0
    }
    fn max_height(&self) -> f64 {
        0.0
    }
    fn min_height(&self) -> f64 {
        0.0
    }
    fn is_flat(&self) -> bool {
        true
    }
}

/// Sum of the water's forces over the wetted triangles.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ForceSum {
    /// N (world frame)
    pub force: DVec3,
    /// N m about the centre of mass (world frame)
    pub torque: DVec3,
    /// m²
    pub wetted_area: f64,
    /// Any vertex at or below the surface.
    pub in_contact: bool,
}

/// Kinematic state needed to evaluate forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Centre of mass (m, world).
    pub position: DVec3,
    /// Centre-of-mass velocity V (m/s, world).
    pub velocity: DVec3,
    /// Stone → world rotation of the mesh the water meets (the Résal frame with
    /// `axial_spin: Resal`).
    pub orientation: DQuat,
    /// ω (rad/s, world).
    pub angular_velocity: DVec3,
}

/// The vertical load of one wetted face, for the water coupling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceLoad {
    /// Wetted centroid (world x, y; m).
    pub x: f64,
    /// Wetted centroid's world y (m).
    pub y: f64,
    /// F_z of the water on the stone through this face (N; the water gets −F_z).
    pub fz: f64,
    /// Horizontal footprint of the wetted part: its area times |N_z| (m²).
    pub footprint: f64,
}
