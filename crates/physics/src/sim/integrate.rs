//! Time stepping of the stone (paper eqs. 4–8 in flight, 30–38 in contact) and the better schemes
//! the literature asks for (physics.md §7.4):
//! - `Paper`: forces from the start of the step, velocity by Euler, position by the trapezoid;
//! - `SymplecticEuler`: velocity first, then position with the new velocity;
//! - `Rk4`: classical fourth order;
//! - `Adaptive`: exact flight, Dormand–Prince 5(4) with error control in contact (Hairer, Nørsett &
//!   Wanner, *Solving ODEs I*, §II.5).
//!
//! The state is a rigid body: position, velocity, orientation (unit quaternion, stone → world) and
//! angular momentum (world frame). With `Rotation::Locked` the attitude is held (ω = 0, the paper's
//! model); with `Free` Euler's equations turn the torque into spin, precession and pitch.
//! With `axial_spin: Resal` a free disk or lens meets the water in a Résal frame, as gyroscope
//! theory calls a frame that follows the symmetry axis but not the spin about it, its azimuth
//! held to the flow (`mesh_orientation`). That is a choice of where the facets of the smooth
//! body's mesh lie, not new physics: the body's dynamics (axisymmetric inertia) do not change.

use glam::{DMat3, DQuat, DVec3, DVec4};

use super::air::{Air, AIR_SUBSTEP};
use super::hydro::{evaluate, lowest_clearance, ForceSum, HydroParams, Pose, Scratch, Surface};
use super::memory::{geometric_immersion, WettedMemory, MAX_MEMORY};
use super::params::{AxialSpin, Rotation};
use super::stone::Stone;

/// The stone's dynamical state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Centre of mass (m).
    pub position: DVec3,
    /// m/s
    pub velocity: DVec3,
    /// Stone → world.
    pub orientation: DQuat,
    /// World frame (kg m²/s).
    pub angular_momentum: DVec3,
    /// The wetted-extent memory's effective immersion d_e (m; `memory.rs`): 0 in flight and
    /// without the memory.
    pub memory: f64,
}

/// Time derivative of a [`BodyState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Deriv {
    pub dx: DVec3,
    pub dv: DVec3,
    pub dq: DVec4,
    pub dl: DVec3,
    /// ḋ_e = (d_g − d_e) / τ.
    pub dm: f64,
    /// 1/τ at this state (not a derivative: what the fixed-step integrators relax with).
    pub relax: f64,
}

impl Deriv {
    const ZERO: Deriv = Deriv {
        dx: DVec3::ZERO,
        dv: DVec3::ZERO,
        dq: DVec4::ZERO,
        dl: DVec3::ZERO,
        dm: 0.0,
        relax: 0.0,
    };

    /// The memory after a fixed step `h` from `d_e`: its exact relaxation to this derivative's
    /// target (stable at any step).
    fn relaxed_memory(&self, d_e: f64, h: f64) -> f64 {
        if self.relax > 0.0 {
            WettedMemory::relax(d_e, d_e + self.dm / self.relax, self.relax, h)
        } else {
            (d_e + self.dm * h).clamp(0.0, MAX_MEMORY)
        }
    }
}

pub(super) fn q4(q: DQuat) -> DVec4 {
    DVec4::new(q.x, q.y, q.z, q.w)
}

fn normalize_q(v: DVec4) -> DQuat {
    let len = v.length();
    if len > 0.0 && len.is_finite() {
        let n = v / len;
        DQuat::from_xyzw(n.x, n.y, n.z, n.w)
    } else {
        DQuat::IDENTITY
    }
}

impl BodyState {
    /// self + Σ wᵢ kᵢ · h (quaternion renormalised).
    pub(crate) fn combine(&self, h: f64, terms: &[(f64, &Deriv)]) -> BodyState {
        let mut s = Deriv::ZERO;
        for &(w, k) in terms {
            if w == 0.0 {
                continue;
            }
            s.dx += k.dx * w;
            s.dv += k.dv * w;
            s.dq += k.dq * w;
            s.dl += k.dl * w;
            s.dm += k.dm * w;
        }
        BodyState {
            position: self.position + s.dx * h,
            velocity: self.velocity + s.dv * h,
            orientation: normalize_q(q4(self.orientation) + s.dq * h),
            angular_momentum: self.angular_momentum + s.dl * h,
            memory: (self.memory + s.dm * h).clamp(-MAX_MEMORY, MAX_MEMORY),
        }
    }

    /// Whether every component (position, velocity, orientation, angular momentum, memory) is
    /// finite: no NaN or infinity.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.velocity.is_finite()
            && self.orientation.is_finite()
            && self.angular_momentum.is_finite()
            && self.memory.is_finite()
    }
}

/// Everything a derivative needs besides the state.
pub(crate) struct Dynamics<'a> {
    pub stone: &'a Stone,
    pub hydro: HydroParams,
    pub gravity: f64,
    pub rotation: Rotation,
    pub surface: &'a dyn Surface,
    /// Whether a `record` evaluation stores the face loads (false when no water reads them).
    pub record_loads: bool,
    /// The mesh meets the water in the Résal frame ([`mesh_orientation`]).
    pub resal: bool,
    /// The wetted-extent memory (`physics.wetted_memory`); `None`: the quasi-steady contact.
    pub memory: Option<WettedMemory>,
}

/// Whether a stone meets the water in the Résal frame: `axial_spin: Resal`, free rotation, a
/// disk or a lens (a body of revolution, its inertia axisymmetric for any segment count ≥ 3) whose
/// faces meet the water (the smooth lens's forces do not depend on its azimuth).
pub(crate) fn resal_applies(stone: &Stone, rotation: Rotation, axial_spin: AxialSpin) -> bool {
    axial_spin == AxialSpin::Resal
        && rotation == Rotation::Free
        && stone.shape.is_revolution()
        && stone.smooth.is_none()
}

/// The orientation the mesh meets the water at: the stone's own, or with `resal` the Résal frame
/// (`axial_spin: Resal`): the stone's turned about its symmetry axis so that the velocity's
/// component in the stone's plane points along the mesh's azimuth 0 (body x). Same symmetry
/// axis, so the same smooth body; the faceted mesh no longer turns with the spin. The stone's
/// own orientation when the velocity is along the axis (no azimuth to hold).
pub(crate) fn mesh_orientation(resal: bool, s: &BodyState) -> DQuat {
    if !resal {
        return s.orientation;
    }
    let vb = s.orientation.inverse() * s.velocity;
    if vb.x == 0.0 && vb.y == 0.0 {
        return s.orientation;
    }
    s.orientation * DQuat::from_rotation_z(vb.y.atan2(vb.x))
}

impl Dynamics<'_> {
    /// Angular velocity (world) of a state: ω = R I⁻¹ Rᵀ L; zero when the rotation is locked.
    pub fn angular_velocity(&self, s: &BodyState) -> DVec3 {
        angular_velocity(self.stone, self.rotation, s)
    }

    /// The pose the water sees: the state, its mesh in [`mesh_orientation`].
    pub fn pose(&self, s: &BodyState) -> Pose {
        Pose {
            position: s.position,
            velocity: s.velocity,
            orientation: mesh_orientation(self.resal, s),
            angular_velocity: self.angular_velocity(s),
        }
    }

    /// The centre of mass the water's law sees: the state's, lowered by d_e − d_g while the stone
    /// is below the ambient surface, which is the waterline raised by as much (`memory.rs`).
    pub fn wetted_position(&self, s: &BodyState) -> DVec3 {
        if self.memory.is_none() {
            return s.position;
        }
        let q = mesh_orientation(self.resal, s);
        let d_g = geometric_immersion(lowest_clearance(self.stone, s.position, q, self.surface));
        lowered(s, d_g)
    }

    /// The state's derivative and the water's forces on it.
    pub fn derivative(
        &self,
        s: &BodyState,
        scratch: &mut Scratch,
        record: bool,
    ) -> (Deriv, ForceSum) {
        let mut pose = self.pose(s);
        let (mut dm, mut relax, mut wet) = (0.0, 0.0, None);
        if let Some(memory) = &self.memory {
            let clearance =
                lowest_clearance(self.stone, pose.position, pose.orientation, self.surface);
            let d_g = geometric_immersion(clearance);
            let rates = memory.rates(pose.orientation, pose.velocity, pose.angular_velocity, d_g);
            relax = rates.relax;
            dm = rates.lead + (d_g - s.memory) * relax;
            pose.position = lowered(s, d_g);
            wet = Some(clearance <= 0.0);
        }
        let mut f = evaluate(
            self.stone,
            &self.hydro,
            &pose,
            self.surface,
            scratch,
            record && self.record_loads,
        );
        if let Some(wet) = wet {
            // In contact is the geometry's: the ambient surface's, not the memory's.
            f.in_contact = wet;
        }
        let mut d = Deriv {
            dx: s.velocity,
            dv: f.force / self.stone.mass - DVec3::Z * self.gravity,
            dq: DVec4::ZERO,
            dl: DVec3::ZERO,
            dm,
            relax,
        };
        if self.rotation == Rotation::Free {
            let w = pose.angular_velocity;
            // q̇ = ½ (0, ω) ⊗ q
            d.dq = q4(DQuat::from_xyzw(w.x, w.y, w.z, 0.0) * s.orientation) * 0.5;
            d.dl = f.torque;
        }
        (d, f)
    }
}

/// The position of `s` lowered by its memory's d_e − d_g while the lowest point is `d_g` > 0 below
/// the ambient surface; the position itself when it is not below.
fn lowered(s: &BodyState, d_g: f64) -> DVec3 {
    if d_g > 0.0 {
        s.position - DVec3::Z * (s.memory - d_g)
    } else {
        s.position
    }
}

/// ω = R I⁻¹ Rᵀ L (world), or zero with a locked attitude.
pub fn angular_velocity(stone: &Stone, rotation: Rotation, s: &BodyState) -> DVec3 {
    match rotation {
        Rotation::Locked => DVec3::ZERO,
        Rotation::Free => {
            let r = DMat3::from_quat(s.orientation);
            r * (stone.inv_inertia * (r.transpose() * s.angular_momentum))
        }
    }
}

/// Rotation by the rotation vector `w·h` applied on the left (world frame): exp(w h) q.
fn rotate_by(q: DQuat, w: DVec3, h: f64) -> DQuat {
    let angle = w.length() * h;
    if angle == 0.0 || !angle.is_finite() {
        return q;
    }
    (DQuat::from_axis_angle(w.normalize(), angle) * q).normalize()
}

/// Exact force-free motion over `t` (positive or negative): a parabola under gravity, and
/// torque-free rotation — closed form (regular precession) for an axisymmetric stone, RK4 with
/// fine steps otherwise.
pub fn flight(stone: &Stone, rotation: Rotation, gravity: f64, s: &BodyState, t: f64) -> BodyState {
    let g = DVec3::Z * gravity;
    let mut out = *s;
    out.position = s.position + s.velocity * t - g * (0.5 * t * t);
    out.velocity = s.velocity - g * t;
    if rotation == Rotation::Free && s.angular_momentum != DVec3::ZERO {
        out.orientation = torque_free(stone, s.orientation, s.angular_momentum, t);
    }
    out
}

/// Flight over `t` (positive or negative) with the air's lift, drag and pitching moment
/// (kick–drift–kick around the exact [`flight`], substeps of at most `AIR_SUBSTEP`; see
/// `air.rs`), or the exact force-free flight without air.
pub fn fly(
    stone: &Stone,
    rotation: Rotation,
    gravity: f64,
    air: Option<&Air>,
    s: &BodyState,
    t: f64,
) -> BodyState {
    match air {
        None => flight(stone, rotation, gravity, s, t),
        Some(air) => fly_split(stone, rotation, gravity, air, s, t, AIR_SUBSTEP),
    }
}

/// [`fly`] with the air, in substeps of at most `substep`.
fn fly_split(
    stone: &Stone,
    rotation: Rotation,
    gravity: f64,
    air: &Air,
    s: &BodyState,
    t: f64,
    substep: f64,
) -> BodyState {
    let n = (t.abs() / substep).ceil();
    let n = if n.is_finite() {
        n.clamp(1.0, 1e7) as usize
    } else {
        1
    };
    let h = t / n as f64;
    let mut st = *s;
    // The closing half kick of one substep and the opening one of the next act at the same
    // attitude: they are taken as one kick (leapfrog), two air loads a substep instead of four.
    air_kick(rotation, air, &mut st, 0.5 * h, stone.mass);
    for i in 0..n {
        st = flight(stone, rotation, gravity, &st, h);
        let kick = if i + 1 == n { 0.5 * h } else { h };
        air_kick(rotation, air, &mut st, kick, stone.mass);
    }
    st
}

/// The air's impulse over `h` at the state's attitude (held during the kick): velocity, and
/// angular momentum when free, by the midpoint rule (the drag depends on the velocity it changes,
/// so an Euler kick would make the splitting first order).
fn air_kick(rotation: Rotation, air: &Air, st: &mut BodyState, h: f64, mass: f64) {
    let first = air.load(st.velocity, st.orientation);
    let mid = air.load(st.velocity + first.force * (0.5 * h / mass), st.orientation);
    st.velocity += mid.force * (h / mass);
    if rotation == Rotation::Free {
        st.angular_momentum += mid.torque * h;
    }
}

/// Orientation after `t` of torque-free motion with angular momentum `l` (world, constant).
pub fn torque_free(stone: &Stone, q0: DQuat, l: DVec3, t: f64) -> DQuat {
    let moments = stone.principal_moments();
    if stone.is_axisymmetric() {
        // R(t) = Rot(L̂, |L| t / I_t) · R0 · Rot_body(ẑ, λ t), λ = L·a (1/I_a − 1/I_t).
        let (it, ia) = (moments.x, moments.z);
        let a = q0 * DVec3::Z;
        let lambda = l.dot(a) * (1.0 / ia - 1.0 / it);
        let lmag = l.length();
        let precess = DQuat::from_axis_angle(l / lmag, lmag * t / it);
        let body = DQuat::from_rotation_z(lambda * t);
        (precess * q0 * body).normalize()
    } else {
        // General body: RK4 on q̇ = ½ ω q with ω = R I⁻¹ Rᵀ L, steps of at most 0.01 rad.
        let omega = |q: DQuat| {
            let r = DMat3::from_quat(q);
            r * (stone.inv_inertia * (r.transpose() * l))
        };
        let w0 = omega(q0).length();
        let n = ((w0 * t.abs() / 0.01).ceil() as usize).clamp(1, 1_000_000);
        let h = t / n as f64;
        let f = |q: DQuat| {
            let w = omega(q);
            q4(DQuat::from_xyzw(w.x, w.y, w.z, 0.0) * q) * 0.5
        };
        let mut q = q0;
        for _ in 0..n {
            let k1 = f(q);
            let k2 = f(normalize_q(q4(q) + k1 * (0.5 * h)));
            let k3 = f(normalize_q(q4(q) + k2 * (0.5 * h)));
            let k4 = f(normalize_q(q4(q) + k3 * h));
            q = normalize_q(q4(q) + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0));
        }
        q
    }
}

/// One step of the paper's scheme (eqs. 30–38) from `s` with its derivative `k1` (the forces of the
/// step's start): v' = v + a h, x' = x + (v + v')/2 h; the attitude (if free) turns with the starting
/// ω. The caller evaluates the forces at the step's end (the loads the step ends with, and the next
/// step's `k1`).
pub(crate) fn step_paper(dy: &Dynamics, s: &BodyState, k1: &Deriv, h: f64) -> BodyState {
    let v1 = s.velocity + k1.dv * h;
    let mut out = *s;
    out.position = s.position + (s.velocity + v1) * (0.5 * h);
    out.velocity = v1;
    out.memory = k1.relaxed_memory(s.memory, h);
    if dy.rotation == Rotation::Free {
        let w = dy.angular_velocity(s);
        out.orientation = rotate_by(s.orientation, w, h);
        out.angular_momentum = s.angular_momentum + k1.dl * h;
    }
    out
}

/// Semi-implicit (symplectic) Euler from `s` with its derivative `k1`: v' = v + a h, x' = x + v' h;
/// L' = L + τ h, then the attitude turns with ω(L').
pub(crate) fn step_symplectic_euler(dy: &Dynamics, s: &BodyState, k1: &Deriv, h: f64) -> BodyState {
    let mut out = *s;
    out.velocity = s.velocity + k1.dv * h;
    out.position = s.position + out.velocity * h;
    out.memory = k1.relaxed_memory(s.memory, h);
    if dy.rotation == Rotation::Free {
        out.angular_momentum = s.angular_momentum + k1.dl * h;
        let w = angular_velocity(dy.stone, dy.rotation, &out);
        out.orientation = rotate_by(s.orientation, w, h);
    }
    out
}

/// Classical RK4 from `s` with its first stage `k1`: three more force evaluations.
pub(crate) fn step_rk4(
    dy: &Dynamics,
    s: &BodyState,
    k1: &Deriv,
    h: f64,
    scratch: &mut Scratch,
) -> BodyState {
    let (k2, _) = dy.derivative(&s.combine(0.5 * h, &[(1.0, k1)]), scratch, false);
    let (k3, _) = dy.derivative(&s.combine(0.5 * h, &[(1.0, &k2)]), scratch, false);
    let (k4, _) = dy.derivative(&s.combine(h, &[(1.0, &k3)]), scratch, false);
    s.combine(
        h,
        &[
            (1.0 / 6.0, k1),
            (1.0 / 3.0, &k2),
            (1.0 / 3.0, &k3),
            (1.0 / 6.0, &k4),
        ],
    )
}

// Dormand–Prince 5(4) tableau.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A2: [f64; 1] = [0.2];
const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
const A5: [f64; 4] = [
    19372.0 / 6561.0,
    -25360.0 / 2187.0,
    64448.0 / 6561.0,
    -212.0 / 729.0,
];
const A6: [f64; 5] = [
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
];
const B5: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
/// b − b̂ (fifth- minus fourth-order weights), seven stages (FSAL).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Scales of the error norm: an error of `tolerance × scale` in any part is a ratio of 1.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ErrorScales {
    pub position: f64,
    pub velocity: f64,
    pub angular_momentum: f64,
}

/// Result of one Dormand–Prince attempt.
pub(crate) struct Dp5Step {
    pub state: BodyState,
    /// Derivative and forces at the new state (the next step's first stage, FSAL).
    pub k_end: Deriv,
    pub force_end: ForceSum,
    /// Error ratio (≤ 1 accepts).
    pub error: f64,
    /// Force evaluations used.
    pub evals: u64,
    /// The earliest stage (as a fraction of the step) at which no vertex touched the water, if
    /// any: a contact step whose stages leave the water may hide an exit and re-entry.
    pub first_dry: Option<f64>,
}

/// One Dormand–Prince 5(4) attempt from `s` with first stage `k1` (already known). The stage at
/// the new state is evaluated with `record` so its face loads can feed the water.
pub(crate) fn step_dp5(
    dy: &Dynamics,
    s: &BodyState,
    k1: &Deriv,
    h: f64,
    tol: f64,
    scales: &ErrorScales,
    scratch: &mut Scratch,
) -> Dp5Step {
    let mut first_dry = None;
    let mut dry = |stage: usize, f: &ForceSum| {
        if !f.in_contact && first_dry.is_none() {
            first_dry = Some(C[stage]);
        }
    };
    let (k2, f2) = dy.derivative(&s.combine(h, &[(A2[0], k1)]), scratch, false);
    dry(1, &f2);
    let (k3, f3) = dy.derivative(&s.combine(h, &[(A3[0], k1), (A3[1], &k2)]), scratch, false);
    dry(2, &f3);
    let (k4, f4) = dy.derivative(
        &s.combine(h, &[(A4[0], k1), (A4[1], &k2), (A4[2], &k3)]),
        scratch,
        false,
    );
    dry(3, &f4);
    let (k5, f5) = dy.derivative(
        &s.combine(h, &[(A5[0], k1), (A5[1], &k2), (A5[2], &k3), (A5[3], &k4)]),
        scratch,
        false,
    );
    dry(4, &f5);
    let (k6, f6) = dy.derivative(
        &s.combine(
            h,
            &[
                (A6[0], k1),
                (A6[1], &k2),
                (A6[2], &k3),
                (A6[3], &k4),
                (A6[4], &k5),
            ],
        ),
        scratch,
        false,
    );
    dry(5, &f6);
    let state = s.combine(
        h,
        &[
            (B5[0], k1),
            (B5[2], &k3),
            (B5[3], &k4),
            (B5[4], &k5),
            (B5[5], &k6),
        ],
    );
    let (k7, force_end) = dy.derivative(&state, scratch, true);
    let ks = [k1, &k2, &k3, &k4, &k5, &k6, &k7];
    let mut ex = DVec3::ZERO;
    let mut ev = DVec3::ZERO;
    let mut el = DVec3::ZERO;
    let mut em = 0.0;
    for (e, k) in E.iter().zip(ks) {
        ex += k.dx * *e;
        ev += k.dv * *e;
        el += k.dl * *e;
        em += k.dm * *e;
    }
    let ratio = |err: DVec3, scale: f64| (err * h).abs().max_element() / (tol * scale);
    let mut error = ratio(ex, scales.position).max(ratio(ev, scales.velocity));
    if dy.memory.is_some() {
        error = error.max((em * h).abs() / (tol * scales.position));
    }
    if dy.rotation == Rotation::Free {
        error = error.max(ratio(el, scales.angular_momentum));
    }
    if !error.is_finite() || !state.is_finite() {
        error = f64::INFINITY;
    }
    Dp5Step {
        state,
        k_end: k7,
        force_end,
        error,
        evals: 6,
        first_dry,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::air::AirParams;
    use crate::sim::params::{Shape, StoneParams};
    use crate::sim::touch::{first_touch, FlightBound};

    /// A lens thrown at 12 m/s, 20° nose up, spinning at `spin` rad/s.
    fn thrown(stone: &Stone, spin: f64) -> BodyState {
        let q = DQuat::from_rotation_y(-20f64.to_radians());
        let r = DMat3::from_quat(q);
        BodyState {
            position: DVec3::new(0.0, 0.0, 0.3),
            velocity: DVec3::new(12.0, 0.0, 0.5),
            orientation: q,
            angular_momentum: r * (stone.inertia * DVec3::new(0.0, 0.0, spin)),
            memory: 0.0,
        }
    }

    fn lens_air(stone_radius: f64) -> Air {
        Air::for_shape(
            AirParams::default(),
            &Shape::Lens {
                radius: stone_radius,
                thickness: 0.01,
            },
        )
    }

    #[test]
    fn flight_with_air_is_second_order_and_reversible() {
        let stone = disc();
        let air = lens_air(0.05);
        let s = thrown(&stone, 90.0);
        let t = 0.3;
        let at = |h: f64| fly_split(&stone, Rotation::Free, 9.81, &air, &s, t, h);
        let fine = at(AIR_SUBSTEP / 16.0);
        let err = |h: f64| {
            let e = at(h);
            (e.position - fine.position).length()
                + (e.orientation * DVec3::Z - fine.orientation * DVec3::Z).length() * 0.05
        };
        let (e1, e2) = (err(4.0 * AIR_SUBSTEP), err(2.0 * AIR_SUBSTEP));
        // Halving the substep quarters the error (Strang splitting is second order) ...
        assert!((e1 / e2 - 4.0).abs() < 0.5, "ratio {}", e1 / e2);
        // ... and at the shipped substep the landing point is good to a micrometre.
        assert!(err(AIR_SUBSTEP) < 1e-6, "error {}", err(AIR_SUBSTEP));
        // Flying back returns to the start: the composition is symmetric, up to the midpoint
        // kick's third-order asymmetry and the rounding of 2 400 substeps.
        let back = fly(
            &stone,
            Rotation::Free,
            9.81,
            Some(&air),
            &at(AIR_SUBSTEP),
            -t,
        );
        let dv = (back.velocity - s.velocity).length();
        let dl =
            (back.angular_momentum - s.angular_momentum).length() / s.angular_momentum.length();
        assert!((back.position - s.position).length() < 1e-10);
        assert!(dv < 1e-10 && dl < 1e-10, "{dv} {dl}");
        // Without air it is the exact flight, bit for bit.
        assert_eq!(
            fly(&stone, Rotation::Free, 9.81, None, &s, t),
            flight(&stone, Rotation::Free, 9.81, &s, t)
        );
    }

    #[test]
    fn air_only_takes_energy_from_the_flight_and_lifts_it() {
        let stone = disc();
        let air = lens_air(0.05);
        let s = thrown(&stone, 0.0);
        let energy = |b: &BodyState| {
            0.5 * stone.mass * b.velocity.length_squared() + stone.mass * 9.81 * b.position.z
        };
        let mut b = s;
        let mut vac = s;
        for _ in 0..30 {
            let next = fly(&stone, Rotation::Locked, 9.81, Some(&air), &b, 0.01);
            // Lift does no work and drag only takes: the energy falls, to the splitting's error.
            assert!(
                energy(&next) < energy(&b) + 1e-9,
                "{} -> {}",
                energy(&b),
                energy(&next)
            );
            b = next;
            vac = flight(&stone, Rotation::Locked, 9.81, &vac, 0.01);
        }
        // Tilted nose up into the flow, the stone is held up: after 0.3 s it is higher than in a
        // vacuum by about ½ (L/m) t² (the lift changes little over the flight).
        let l = air.load(s.velocity, s.orientation).force.z / stone.mass;
        let gain = b.position.z - vac.position.z;
        assert!(
            gain > 0.0 && (gain / (0.5 * l * 0.09) - 1.0).abs() < 0.3,
            "gain {gain}, ½ a t² {}",
            0.5 * l * 0.09
        );
    }

    /// With the air pulling harder than gravity (a dense air, a light stone), the centre's height
    /// is no longer concave: a flight can touch and rise again inside an interval whose ends are
    /// dry. The search with the air's bound never proves such a flight clear.
    #[test]
    fn touch_search_with_air_never_misses_a_touch() {
        let stone = disc();
        let air = Air::for_shape(
            AirParams {
                density: 40.0,
                ..AirParams::default()
            },
            &Shape::Disk {
                radius: 0.05,
                thickness: 0.01,
            },
        );
        let fly_air = |s: &BodyState, t: f64| fly(&stone, Rotation::Locked, 9.81, Some(&air), s, t);
        let clear = |s: &BodyState| s.position.z - 0.005;
        let h = 0.02;
        let mut touching = 0;
        for i in 0..200 {
            let vz = -2.0 + 0.01 * i as f64;
            let s = BodyState {
                position: DVec3::new(0.0, 0.0, 0.01),
                velocity: DVec3::new(12.0, 0.0, vz),
                orientation: DQuat::from_rotation_y(-0.3),
                angular_momentum: DVec3::ZERO,
                memory: 0.0,
            };
            let speed = s.velocity.length() + 2.0 * 9.81 * h;
            let lift = air.bounds(speed).0 / stone.mass;
            assert!(lift > 9.81, "the test needs a lift above gravity");
            let bound = FlightBound::new(0.05, 12.0, 0.0, 0.0, 0.0).with_air(lift);
            let wet = (0..=400).any(|k| clear(&fly_air(&s, h * k as f64 / 400.0)) <= 0.0);
            let found = first_touch(&fly_air, &clear, &bound, None, &s, h);
            if wet {
                touching += 1;
                assert!(found.is_some(), "missed the touch of vz = {vz}");
            }
        }
        assert!(touching > 10, "some flights touch ({touching})");
    }

    #[test]
    fn the_pitching_moment_rolls_a_spinning_stone_by_m_over_i_omega() {
        let stone = disc();
        let air = lens_air(0.05);
        for spin in [100.0, 400.0] {
            let s = thrown(&stone, spin);
            let t = 0.05;
            let end = fly(&stone, Rotation::Free, 9.81, Some(&air), &s, t);
            let m = air.load(s.velocity, s.orientation).torque.length();
            let expected = m * t / (stone.principal_moments().z * spin);
            let turned = (s.orientation * DVec3::Z).angle_between(end.orientation * DVec3::Z);
            // Gyroscopic precession: the axis turns by M t / (I₃ ω), sideways (a roll), within the
            // change of M over the flight.
            assert!(
                (turned / expected - 1.0).abs() < 0.15,
                "spin {spin}: {turned} vs {expected}"
            );
            let side = (end.orientation * DVec3::Z).y;
            assert!(
                side.abs() > 0.9 * (turned.sin() * 0.9),
                "the turn is a roll: y {side}"
            );
        }
    }

    fn disc() -> Stone {
        Stone::new(&StoneParams {
            shape: Shape::Disk {
                radius: 0.05,
                thickness: 0.01,
            },
            mass: 0.1,
            segments: 32,
            bands: None,
            quadrature: Default::default(),
        })
        .unwrap()
    }

    /// `axial_spin: Resal`: the water sees the same body whatever the spin's phase. Turning the
    /// stone about its own axis (what the spin does between two evaluations) leaves the force and
    /// torque unchanged to rounding, where the mesh turning with the spin (the retired `Smooth`) changes
    /// them by the facets' ripple; the Résal frame keeps the symmetry axis and holds the in-plane
    /// velocity at azimuth 0.
    #[test]
    fn the_resal_frame_takes_the_spin_phase_out_of_the_force() {
        use crate::sim::hydro::FlatSurface;
        use crate::sim::params::{AxialSpin, Physics};
        // The built-in pebble: a 5 cm, 12 mm, 100 g lens of 32 segments.
        let stone = Stone::new(&StoneParams::version_1()).unwrap();
        // The same smooth law with the frame held (Résal) or turning with the spin (the retired
        // `axial_spin: Smooth`).
        let dynamics = |held: bool| {
            let physics = Physics {
                rotation: Rotation::Free,
                axial_spin: AxialSpin::Resal,
                buoyancy: true,
                ..Physics::version_1()
            };
            Dynamics {
                stone: &stone,
                hydro: HydroParams::from_physics(&physics),
                gravity: 9.81,
                rotation: Rotation::Free,
                surface: &FlatSurface,
                record_loads: false,
                resal: held && resal_applies(&stone, Rotation::Free, AxialSpin::Resal),
                memory: None,
            }
        };
        let (resal, smooth) = (dynamics(true), dynamics(false));
        assert!(resal.resal && !smooth.resal);
        let mut scratch = Scratch::default();
        let (mut ripple, mut worst) = (0.0f64, 0.0f64);
        for k in 0..24 {
            let mut s = thrown(&stone, 90.0);
            s.position.z = -0.002;
            let phase = 0.37 * k as f64;
            let turned = BodyState {
                orientation: s.orientation * DQuat::from_rotation_z(phase),
                ..s
            };
            let q = mesh_orientation(true, &turned);
            assert!((q * DVec3::Z - s.orientation * DVec3::Z).length() < 1e-12);
            let vb = q.inverse() * s.velocity;
            assert!(vb.y.abs() < 1e-12 * vb.length() && vb.x > 0.0, "{vb}");
            let mut force = |d: &Dynamics, st: &BodyState| {
                let (_, f) = d.derivative(st, &mut scratch, false);
                (f.force, f.torque)
            };
            let (f0, t0) = force(&resal, &s);
            let (f1, t1) = force(&resal, &turned);
            assert!(f0.length() > 1.0, "in contact: {f0}");
            worst = worst
                .max((f1 - f0).length() / f0.length())
                .max((t1 - t0).length() / t0.length());
            let (g0, _) = force(&smooth, &s);
            let (g1, _) = force(&smooth, &turned);
            ripple = ripple.max((g1 - g0).length() / g0.length());
        }
        assert!(worst < 1e-12, "Résal: {worst}");
        assert!(
            ripple > 1e-6,
            "a mesh turning with the spin ripples: {ripple}"
        );
    }

    #[test]
    fn axisymmetric_torque_free_matches_fine_rk4() {
        let stone = disc();
        let q0 = DQuat::from_rotation_y(-0.3) * DQuat::from_rotation_x(0.1);
        let r = DMat3::from_quat(q0);
        // Spin about the axis plus a wobble.
        let w_body = DVec3::new(3.0, -2.0, 300.0);
        let l = r * (stone.inertia * w_body);
        let exact = torque_free(&stone, q0, l, 0.05);
        // Reference: generic RK4 path by pretending the body is not symmetric is not reachable, so
        // integrate q̇ = ½ ω q directly with tiny steps.
        let mut q = q0;
        let n = 200_000;
        let h = 0.05 / n as f64;
        for _ in 0..n {
            let rr = DMat3::from_quat(q);
            let w = rr * (stone.inv_inertia * (rr.transpose() * l));
            q = rotate_by(q, w, h);
        }
        let axis_err = ((exact * DVec3::Z) - (q * DVec3::Z)).length();
        assert!(axis_err < 1e-4, "axis error {axis_err}");
    }

    /// The clearance search on a synthetic flight: the centre falls along a parabola while the
    /// lowest point wobbles by `amp` at angular frequency `w` (clearance relative to the centre
    /// −d − amp·sin²(w x), x advancing at 1 m/s), so its rate is at most amp·w. A dip between two dry
    /// ends is found, and its bracket holds the first touch; a wobble that stays clear is proven so.
    #[test]
    fn touch_search_finds_a_dip_between_dry_ends() {
        let stone = disc();
        let (d, amp, w, h) = (0.005, 0.03, std::f64::consts::PI / 0.01, 0.01);
        let fly = |s: &BodyState, t: f64| flight(&stone, Rotation::Locked, 9.81, s, t);
        let rel = |s: &BodyState| -d - amp * (w * s.position.x).sin().powi(2);
        let bound = FlightBound {
            rate: amp * w,
            floor: -d - amp,
            lift: 0.0,
            revolution: None,
        };
        for (z0, touches) in [(0.02, true), (0.036, false)] {
            let s = BodyState {
                position: DVec3::new(0.0, 0.0, z0),
                velocity: DVec3::new(1.0, 0.0, 0.0),
                orientation: DQuat::IDENTITY,
                angular_momentum: DVec3::ZERO,
                memory: 0.0,
            };
            let clear = |st: &BodyState| st.position.z + rel(st);
            assert!(clear(&s) > 0.0 && clear(&fly(&s, h)) > 0.0);
            let found = first_touch(&fly, &clear, &bound, None, &s, h);
            // Brute force on the same flight.
            let first = (0..=100_000)
                .map(|i| h * i as f64 / 100_000.0)
                .find(|&t| clear(&fly(&s, t)) <= 0.0);
            assert_eq!(found.is_some(), touches, "z0 {z0}: {found:?}");
            assert_eq!(first.is_some(), touches);
            if let (Some((lo, hi)), Some(t)) = (found, first) {
                assert!(clear(&fly(&s, lo)) > 0.0 && clear(&fly(&s, hi)) <= 0.0);
                assert!(lo <= t && t <= hi + h / 100_000.0, "{lo} {t} {hi}");
            }
        }
    }

    #[test]
    fn flight_is_exact_parabola() {
        let stone = disc();
        let s = BodyState {
            position: DVec3::new(0.0, 0.0, 1.0),
            velocity: DVec3::new(3.0, 1.0, 2.0),
            orientation: DQuat::IDENTITY,
            angular_momentum: DVec3::ZERO,
            memory: 0.0,
        };
        let t = 0.37;
        let out = flight(&stone, Rotation::Locked, 9.81, &s, t);
        assert!((out.position.z - (1.0 + 2.0 * t - 0.5 * 9.81 * t * t)).abs() < 1e-15);
        let back = flight(&stone, Rotation::Locked, 9.81, &out, -t);
        assert!((back.position - s.position).length() < 1e-14);
    }
}
