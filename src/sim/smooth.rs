//! The force law of [`super::hydro`] (paper eqs. 11–26, read per unit area: pressure and friction
//! at each point of the wetted surface, eq. 24's sum becoming an integral) integrated over the
//! smooth ellipsoid of revolution a lens mesh stands for, on flat water, instead of over its
//! triangles (issue 12: `stone.quadrature: Smooth`).
//!
//! The lens is x²/a² + y²/a² + z²/c² = 1 in its body frame. A meridian is parametrised by the polar
//! angle ψ of its outward normal N = (sin ψ cos θ, sin ψ sin θ, cos ψ): with D = √(a² sin²ψ +
//! c² cos²ψ), the point is ρ = a² sin ψ / D, z = c² cos ψ / D and the meridian's radius of
//! curvature R = a²c²/D³, so dA = ρ R dψ dθ (every quantity smooth in ψ, also at the rim, where the
//! normal turns fastest along the surface). With u the water's up direction in the body frame and
//! z₀ the centre's height, a point's height above flat water is A(ψ) + B(ψ) cos(θ − θ_u) (A = z₀ +
//! u_z z, B = ρ|u_xy|): each latitude's wet part is one arc, found exactly (the waterline needs no
//! clipping), and its normal velocity (V + ω⊥ × r)·N = P + Q cos θ + S sin θ is a first harmonic too,
//! so the arc is cut exactly where the law switches (v_n = 0: ventilation, max(0, v_n)). The wet
//! latitudes are one interval [ψ₁, ψ₂] about the lowest point's ψ* (the lowest point per latitude
//! is unimodal on a convex body), its ends found by root finding, cut where it reaches from a cap
//! into the rim band (ψ = 2 atan(c/a) from a pole: in ψ the caps hold most of the area in a few
//! degrees); ψ = ψ_m − ψ_h cos t maps each range onto t ∈ [0, π] so the arcs' √(ψ − ψ₁) growth
//! at the ends becomes smooth. Gauss–Legendre rules (the nodes by Newton on P_n) then integrate
//! in t and in θ on every piece. Every node moves smoothly with the pose, and a range or piece
//! that appears does so with zero width, so the force stays continuous for the step control.
//!
//! The clearance is the ellipsoid's support function, z₀ − √(a²|u_xy|² + c²u_z²), exact. Faces of
//! the mesh converge to these integrals as it is refined (tests). The law, the frames and the
//! options (ventilation, pressure sign, hydrostatic pressure) are `hydro::face_force`'s, called at
//! each node with the node's area; a ventilated piece receding from the water carries only the
//! hydrostatic pressure (`hydrostatic: WettedFaces`), integrated there in closed form (depth and
//! normal are first harmonics in θ). The axial spin is not felt as normal velocity (the smooth
//! body's `axial_spin`), and the pressure passes through the axis (r × N ⊥ a), so it takes no
//! axial torque.

use glam::{DMat3, DQuat, DVec3};

use super::hydro::{face_force, FaceLoad, ForceSum, HydroParams, Pose};

/// Gauss–Legendre nodes and weights on [−1, 1] (n ≥ 1), nodes ascending.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let n = n.max(1);
    let mut out = vec![(0.0, 0.0); n];
    for i in 0..n.div_ceil(2) {
        // Tricomi's initial guess, then Newton on P_n.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        if 2 * i + 1 == n {
            x = 0.0;
        }
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            let dx = p / d;
            x -= dx;
            if dx.abs() <= 1e-16 {
                break;
            }
        }
        let (_, d) = legendre(n, x);
        let w = 2.0 / ((1.0 - x * x) * d * d);
        out[i] = (-x, w);
        out[n - 1 - i] = (x, w);
    }
    out
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

/// A lens as a smooth ellipsoid of revolution with its quadrature rules.
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothLens {
    /// Equatorial radius and half-thickness (m).
    a: f64,
    c: f64,
    /// Along the wet latitudes: ψ = ψ_m − ψ_h cos t on each range, Gauss–Legendre in t ∈ [0, π];
    /// (cos t, its weight × dψ/dt / ψ_h).
    meridian: Vec<(f64, f64)>,
    /// The θ rule's nodes x ≥ 0 (each x > 0 stands for ±x) and weights.
    around_half: Vec<(f64, f64)>,
}

/// A point of a meridian: radius ρ, height z, the meridian's radius of curvature R.
#[derive(Debug, Clone, Copy)]
struct Meridian {
    sin: f64,
    cos: f64,
    rho: f64,
    z: f64,
    curvature_radius: f64,
}

impl SmoothLens {
    /// Radius `a`, half-thickness `c`; `meridian` nodes along the wet latitudes and `around`
    /// nodes on each arc piece.
    pub fn new(a: f64, c: f64, meridian: usize, around: usize) -> Self {
        Self {
            a,
            c,
            meridian: gauss_legendre(meridian)
                .into_iter()
                .map(|(x, w)| {
                    let t = 0.5 * std::f64::consts::PI * (x + 1.0);
                    (t.cos(), w * 0.5 * std::f64::consts::PI * t.sin())
                })
                .collect(),
            around_half: gauss_legendre(around)
                .into_iter()
                .filter(|&(x, _)| x >= 0.0)
                .collect(),
        }
    }

    /// The ellipsoid's volume (m³).
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.a * self.a * self.c
    }

    /// Body-frame inertia of a uniform ellipsoid of mass `mass` (kg m²).
    pub fn inertia(&self, mass: f64) -> DMat3 {
        let (a2, c2) = (self.a * self.a, self.c * self.c);
        let side = mass * (a2 + c2) / 5.0;
        DMat3::from_diagonal(DVec3::new(side, side, 2.0 * mass * a2 / 5.0))
    }

    fn at(&self, psi: f64) -> Meridian {
        let (s, c) = psi.sin_cos();
        let (a2, c2) = (self.a * self.a, self.c * self.c);
        let d = (a2 * s * s + c2 * c * c).sqrt();
        Meridian {
            sin: s,
            cos: c,
            rho: a2 * s / d,
            z: c2 * c / d,
            curvature_radius: a2 * c2 / (d * d * d),
        }
    }

    /// The water's up direction in the body frame and the body's rotation.
    fn frame(orientation: DQuat) -> (DMat3, DVec3) {
        let rot = DMat3::from_quat(orientation);
        (rot, rot.transpose() * DVec3::Z)
    }

    /// Height of the lowest point above flat water (its support function).
    fn clearance_in(&self, z0: f64, u: DVec3) -> f64 {
        let h2 = u.x * u.x + u.y * u.y;
        z0 - (self.a * self.a * h2 + self.c * self.c * u.z * u.z).sqrt()
    }

    /// Signed height of the lowest point of the smooth lens above flat water.
    pub fn clearance(&self, position: DVec3, orientation: DQuat) -> f64 {
        let (_, u) = Self::frame(orientation);
        self.clearance_in(position.z, u)
    }

    /// Whether the whole underside (the points whose outward normal points down) is below flat
    /// water: the sink test of `hydro::underside_submerged` on the smooth lens. On a convex body
    /// the height has no maximum inside the underside, so its highest point is on the silhouette
    /// N·u = 0, the plane section uᵀM r = 0 (M = diag(a⁻², a⁻², c⁻²)); there the largest u·r is
    /// √(S − 1/T) with S = uᵀM⁻¹u (the support's square) and T = uᵀMu (Lagrange multipliers).
    pub fn underside_submerged(&self, position: DVec3, orientation: DQuat) -> bool {
        let (_, u) = Self::frame(orientation);
        let h2 = u.x * u.x + u.y * u.y;
        let (a2, c2) = (self.a * self.a, self.c * self.c);
        let support2 = a2 * h2 + c2 * u.z * u.z;
        let t = h2 / a2 + u.z * u.z / c2;
        let rise = (support2 - 1.0 / t).max(0.0).sqrt();
        position.z + rise < 0.0
    }

    /// Forces and torque on the lens over flat water (world frame); with `record` the vertical
    /// load of every loaded node is pushed to `loads` for the water coupling.
    pub fn evaluate(
        &self,
        hp: &HydroParams,
        pose: &Pose,
        loads: &mut Vec<FaceLoad>,
        record: bool,
    ) -> ForceSum {
        use std::f64::consts::PI;
        if record {
            loads.clear();
        }
        let (rot, u) = Self::frame(pose.orientation);
        let z0 = pose.position.z;
        if self.clearance_in(z0, u) > 0.0 {
            return ForceSum::default();
        }
        let horizontal = u.x.hypot(u.y);
        // The lowest point per latitude, A − B: unimodal in ψ, least at the lowest point's ψ*.
        let lowest = |psi: f64| {
            let m = self.at(psi);
            z0 + u.z * m.z - m.rho * horizontal
        };
        let psi_star = horizontal.atan2(-u.z);
        let psi1 = if lowest(0.0) <= 0.0 {
            0.0
        } else {
            root(lowest, 0.0, psi_star)
        };
        let psi2 = if lowest(PI) <= 0.0 {
            PI
        } else {
            root(lowest, psi_star, PI)
        };
        let rt = rot.transpose();
        let w_b = rt * pose.angular_velocity;
        let cx = Ctx {
            hp,
            z0,
            u,
            horizontal,
            theta_u: u.y.atan2(u.x),
            v_b: rt * pose.velocity,
            w_b,
            speed: pose.velocity.length(),
            receding_is_dry: hp.ventilated && !(hp.hydrostatic_wetted && hp.rho_g != 0.0),
        };
        let mut acc = Sums::default();
        let mut sink = record.then_some(Loads {
            rot: &rot,
            position: pose.position,
            loads,
        });
        // The caps hold most of the area in a few degrees of ψ about the poles (R is a²/c there,
        // c²/a at the rim): a wet range that reaches from a cap into the rim band is cut there.
        let cap = 2.0 * self.c.atan2(self.a);
        let mut ends = [psi1, psi2, psi2, psi2];
        let mut n = 1;
        for b in [cap, PI - cap] {
            if b > psi1 && b < psi2 {
                ends[n] = b;
                n += 1;
            }
        }
        ends[n] = psi2;
        for range in ends[..=n].windows(2) {
            let (mid, half) = (0.5 * (range[0] + range[1]), 0.5 * (range[1] - range[0]));
            for &(cos_t, weight) in &self.meridian {
                let weight = weight * half;
                if weight <= 0.0 {
                    continue;
                }
                let m = self.at(mid - half * cos_t);
                let k = m.rho * m.cos - m.z * m.sin;
                // Only ω's part across the axis, ω⊥ = (ω_x, ω_y, 0), moves the smooth surface
                // along its normal: ω⊥ · (r × N) = k (ω_x sin θ − ω_y cos θ).
                let lat = Latitude {
                    m,
                    weight: weight * m.rho * m.curvature_radius,
                    k,
                    p: m.cos * cx.v_b.z,
                    q: m.sin * cx.v_b.x - k * cx.w_b.y,
                    s: m.sin * cx.v_b.y + k * cx.w_b.x,
                };
                self.latitude(&cx, &lat, &mut acc, sink.as_mut());
            }
        }
        ForceSum {
            force: rot * acc.force,
            torque: rot * acc.torque,
            wetted_area: acc.area,
            in_contact: true,
        }
    }

    /// Integrates one wet latitude's arc, cut where the normal velocity changes sign.
    fn latitude(&self, cx: &Ctx, lat: &Latitude, acc: &mut Sums, mut sink: Option<&mut Loads>) {
        use std::f64::consts::{PI, TAU};
        let m = &lat.m;
        let a_coef = cx.z0 + cx.u.z * m.z;
        let b_coef = m.rho * cx.horizontal;
        // The wet arc [start, start + width] (heights A + B cos(θ − θ_u) ≤ 0).
        let (start, width) = if b_coef <= 0.0 || a_coef <= -b_coef {
            if a_coef > 0.0 {
                return;
            }
            (cx.theta_u, TAU)
        } else if a_coef >= b_coef {
            return;
        } else {
            let beta = (a_coef / b_coef).acos();
            (cx.theta_u + PI - beta, 2.0 * beta)
        };
        // Where the normal velocity P + Q cos θ + S sin θ changes sign inside the arc.
        let (p, q, s) = (lat.p, lat.q, lat.s);
        let r = q.hypot(s);
        let mut cuts = [0.0, width, width, width];
        let mut n = 1;
        if r > 0.0 && (-p / r).abs() < 1.0 {
            let gamma = (-p / r).acos();
            let theta_v = s.atan2(q);
            // Offsets from the arc's start in [0, 2π) (the angles lie within a few turns of it).
            let wrap = |b: f64| {
                let d = b - start;
                d - TAU * (d / TAU).floor()
            };
            let mut inner = [theta_v - gamma, theta_v + gamma].map(wrap);
            inner.sort_by(f64::total_cmp);
            for off in inner {
                if off > 0.0 && off < width {
                    cuts[n] = off;
                    n += 1;
                }
            }
        }
        cuts[n] = width;
        for piece in cuts[..=n].windows(2) {
            let (pm, ph) = (
                start + 0.5 * (piece[0] + piece[1]),
                0.5 * (piece[1] - piece[0]),
            );
            if ph <= 0.0 {
                continue;
            }
            // Gauss nodes come in pairs ±x: cos and sin of pm ± ph x from one sin_cos each.
            let (sm, cm) = pm.sin_cos();
            let receding = cx.hp.ventilated && p + q * cm + s * sm <= 0.0;
            // A receding piece carries nothing when only the loaded faces feel the water, and
            // only the hydrostatic pressure when every wetted face does: that one in closed form.
            if receding && cx.receding_is_dry {
                continue;
            }
            if receding {
                hydrostatic_piece(cx, lat, ph, (sm, cm), acc, sink.as_deref_mut());
                continue;
            }
            for &(x, w) in &self.around_half {
                let (sx, cx_) = if x == 0.0 {
                    (0.0, 1.0)
                } else {
                    (ph * x).sin_cos()
                };
                let sides: &[f64] = if x == 0.0 { &[1.0] } else { &[1.0, -1.0] };
                for &sign in sides {
                    let (sn, cs) = (sm * cx_ + sign * cm * sx, cm * cx_ - sign * sm * sx);
                    node(cx, lat, (sn, cs), w * ph, acc, sink.as_deref_mut());
                }
            }
        }
    }
}

/// One node of a latitude's arc at azimuth (sin θ, cos θ), weight `w` in θ: the law of
/// `hydro::face_force` with the node's area.
#[inline(always)]
fn node(
    cx: &Ctx,
    lat: &Latitude,
    (sn, cs): (f64, f64),
    w: f64,
    acc: &mut Sums,
    sink: Option<&mut Loads>,
) {
    let m = &lat.m;
    let r_b = DVec3::new(m.rho * cs, m.rho * sn, m.z);
    let normal = DVec3::new(m.sin * cs, m.sin * sn, m.cos);
    let area = lat.weight * w;
    let v = cx.v_b + cx.w_b.cross(r_b);
    let vn = lat.p + lat.q * cs + lat.s * sn;
    let depth = -(cx.z0 + cx.u.dot(r_b));
    let f = face_force(cx.hp, normal, area, v, vn, cx.speed, depth);
    if f == DVec3::ZERO {
        return;
    }
    acc.area += area;
    acc.force += f;
    acc.torque += r_b.cross(f);
    if let Some(sink) = sink {
        sink.push(r_b, f, area * cx.u.dot(normal).abs());
    }
}

/// The hydrostatic load ρ g d on a piece [pm − ph, pm + ph] of a latitude's wet arc (its half
/// width ph, and sin and cos of its middle pm), exactly: the depth d = D₀ − ρ(u_x cos θ +
/// u_y sin θ) and the normal are first harmonics in θ, so the force −ρ g ∫ d N dA and its torque
/// (r × N = k (sin θ, −cos θ, 0)) are integrals of products of two.
fn hydrostatic_piece(
    cx: &Ctx,
    lat: &Latitude,
    ph: f64,
    (sm, cm): (f64, f64),
    acc: &mut Sums,
    sink: Option<&mut Loads>,
) {
    let m = &lat.m;
    let (sh, ch) = ph.sin_cos();
    let (sa, ca) = (sm * ch - cm * sh, cm * ch + sm * sh);
    let (sb, cb) = (sm * ch + cm * sh, cm * ch - sm * sh);
    let len = 2.0 * ph;
    // ∫cos, ∫sin, ∫cos², ∫sin², ∫sin cos over the piece.
    let (ic, is) = (sb - sa, ca - cb);
    let icc = 0.5 * len + 0.5 * (sb * cb - sa * ca);
    let (iss, ics) = (len - icc, 0.5 * (sb * sb - sa * sa));
    let d0 = -(cx.z0 + cx.u.z * m.z);
    let (ux, uy) = (m.rho * cx.u.x, m.rho * cx.u.y);
    let i_d = d0 * len - (ux * ic + uy * is);
    let i_dc = d0 * ic - (ux * icc + uy * ics);
    let i_ds = d0 * is - (ux * ics + uy * iss);
    let scale = -cx.hp.rho_g * lat.weight;
    let f = DVec3::new(m.sin * i_dc, m.sin * i_ds, m.cos * i_d) * scale;
    if f == DVec3::ZERO {
        return;
    }
    let area = lat.weight * len;
    acc.area += area;
    acc.force += f;
    acc.torque += DVec3::new(i_ds, -i_dc, 0.0) * (scale * lat.k);
    if let Some(sink) = sink {
        // One load at the piece's middle carries its whole vertical force.
        let r_b = DVec3::new(m.rho * cm, m.rho * sm, m.z);
        let normal = DVec3::new(m.sin * cm, m.sin * sm, m.cos);
        sink.push(r_b, f, area * cx.u.dot(normal).abs());
    }
}

/// What every node of one evaluation shares (body frame).
struct Ctx<'a> {
    hp: &'a HydroParams,
    z0: f64,
    /// The water's up direction.
    u: DVec3,
    /// |u_xy|
    horizontal: f64,
    /// Azimuth of u's horizontal part: the highest point of every latitude.
    theta_u: f64,
    v_b: DVec3,
    w_b: DVec3,
    /// Centre-of-mass speed U.
    speed: f64,
    /// A ventilated piece receding from the water carries nothing (only the loaded faces feel
    /// the hydrostatic pressure, or there is none).
    receding_is_dry: bool,
}

/// Where the loads of a recorded evaluation go (world frame).
struct Loads<'a> {
    rot: &'a DMat3,
    position: DVec3,
    loads: &'a mut Vec<FaceLoad>,
}

impl Loads<'_> {
    /// The vertical load of force `f` (body frame) acting at `r_b`, over `footprint` m².
    fn push(&mut self, r_b: DVec3, f: DVec3, footprint: f64) {
        let world = self.position + *self.rot * r_b;
        self.loads.push(FaceLoad {
            x: world.x,
            y: world.y,
            fz: (*self.rot * f).z,
            footprint,
        });
    }
}

/// One wet latitude: its meridian point, the weight of its ψ node times ρR, k = ρ cos ψ −
/// z sin ψ (r × N = k (sin θ, −cos θ, 0)), and its normal velocity P + Q cos θ + S sin θ.
struct Latitude {
    m: Meridian,
    weight: f64,
    k: f64,
    p: f64,
    q: f64,
    s: f64,
}

#[derive(Default)]
struct Sums {
    force: DVec3,
    torque: DVec3,
    area: f64,
}

/// A root of `f` in [lo, hi] where f(lo) and f(hi) differ in sign (Illinois false position, with
/// bisection's bracket kept), to the last bits of ψ.
fn root(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut a, mut b) = (lo, hi);
    let (mut fa, mut fb) = (f(a), f(b));
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 || fa.signum() == fb.signum() {
        return b;
    }
    let mut side = 0;
    for _ in 0..100 {
        let mut x = (a * fb - b * fa) / (fb - fa);
        if !(x > a.min(b) && x < a.max(b)) {
            x = 0.5 * (a + b);
        }
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if fx.signum() == fb.signum() {
            b = x;
            fb = fx;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = x;
            fa = fx;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
        if (b - a).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()).max(1.0) {
            break;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::hydro::{evaluate_reference, FlatSurface, Scratch};
    use crate::sim::params::{ForceLaw, Physics, Quadrature, Shape, StoneParams};
    use crate::sim::stone::Stone;

    fn lens(segments: u32, quadrature: Quadrature) -> Stone {
        Stone::new(&StoneParams {
            shape: Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            mass: 0.1,
            segments,
            bands: Some(segments / 2),
            quadrature,
        })
        .unwrap()
    }

    fn rng(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    fn hp(law: ForceLaw) -> HydroParams {
        let mut p = Physics {
            force_law: law,
            buoyancy: true,
            ..Physics::default()
        };
        p.axial_spin = crate::sim::params::AxialSpin::Smooth;
        p.hydrostatic = crate::sim::params::Hydrostatic::WettedFaces;
        HydroParams::from_physics(&p)
    }

    fn random_pose(seed: &mut u64) -> Pose {
        let tilt = 0.6 * rng(seed);
        let yaw = std::f64::consts::TAU * rng(seed);
        let orientation = DQuat::from_rotation_z(yaw) * DQuat::from_rotation_y(-tilt);
        let reach = 0.05 * tilt.sin() + 0.006 * tilt.cos();
        Pose {
            position: DVec3::new(0.0, 0.0, reach * (1.0 - 1.6 * rng(seed))),
            velocity: DVec3::new(4.0 + 8.0 * rng(seed), rng(seed) - 0.5, -2.0 * rng(seed)),
            orientation,
            angular_velocity: DVec3::new(
                20.0 * (rng(seed) - 0.5),
                20.0 * (rng(seed) - 0.5),
                300.0 * (rng(seed) - 0.5),
            ),
        }
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_2n_minus_1() {
        for n in 1..=24 {
            let rule = gauss_legendre(n);
            for k in 0..2 * n {
                let sum: f64 = rule.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                let exact = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k as f64 + 1.0)
                };
                assert!((sum - exact).abs() < 1e-13, "n {n} k {k}: {sum} vs {exact}");
            }
        }
    }

    /// Every point of the lens (a = 0.05, c = 0.006) on an n × n grid of the parametric angle φ
    /// (x = a sin φ, z = c cos φ: even in area) and the azimuth, turned by a random rotation: the
    /// offset from the centre and the outward normal's direction, world axes.
    fn sampled_surface(seed: &mut u64, n: usize) -> (DQuat, Vec<(DVec3, DVec3)>) {
        let q = DQuat::from_rotation_z(6.0 * rng(seed)) * DQuat::from_rotation_y(3.0 * rng(seed));
        let rot = DMat3::from_quat(q);
        let mut out = Vec::with_capacity((n + 1) * n);
        for i in 0..=n {
            let (sp, cp) = (std::f64::consts::PI * i as f64 / n as f64).sin_cos();
            for j in 0..n {
                let (s, c) = (std::f64::consts::TAU * j as f64 / n as f64).sin_cos();
                let p = rot * DVec3::new(0.05 * sp * c, 0.05 * sp * s, 0.006 * cp);
                let normal = rot * DVec3::new(sp * c / 0.05, sp * s / 0.05, cp / 0.006);
                out.push((p, normal));
            }
        }
        (q, out)
    }

    #[test]
    fn clearance_is_the_lowest_point_of_the_ellipsoid() {
        let smooth = SmoothLens::new(0.05, 0.006, 8, 8);
        let mut seed = 3;
        for _ in 0..40 {
            let (q, points) = sampled_surface(&mut seed, 600);
            let lowest = points
                .iter()
                .map(|(p, _)| p.z)
                .fold(f64::INFINITY, f64::min);
            let c = smooth.clearance(DVec3::ZERO, q);
            // The sampled minimum is above the true one by at most the sampling's gap.
            assert!(c <= lowest + 1e-15 && c > lowest - 2e-6, "{c} vs {lowest}");
        }
    }

    /// The sink test's highest underside point is the highest point of a dense sampling of the
    /// surface where the normal points down.
    #[test]
    fn underside_test_finds_the_highest_point_facing_down() {
        let smooth = SmoothLens::new(0.05, 0.006, 8, 8);
        let mut seed = 5;
        for _ in 0..40 {
            let (q, points) = sampled_surface(&mut seed, 600);
            let highest = points
                .iter()
                .filter(|(_, n)| n.z < 0.0)
                .map(|(p, _)| p.z)
                .fold(f64::NEG_INFINITY, f64::max);
            // Just below that height the underside is not all under; well below, it is.
            let below = |z: f64| smooth.underside_submerged(DVec3::new(0.0, 0.0, z), q);
            assert!(!below(-highest + 1e-9), "{highest}");
            assert!(below(-highest - 1e-4), "{highest} {q:?}");
        }
    }

    /// A submerged lens at rest feels Archimedes' ρ g V upwards and no torque: the quadrature
    /// converges to it (spectrally: the integrand is smooth over the whole surface).
    #[test]
    fn submerged_lens_feels_archimedes() {
        let hp = hp(ForceLaw::Rosellini);
        let pose = Pose {
            position: DVec3::new(0.0, 0.0, -0.2),
            velocity: DVec3::ZERO,
            orientation: DQuat::from_rotation_y(0.4),
            angular_velocity: DVec3::ZERO,
        };
        let expected = hp.rho_g * 4.0 / 3.0 * std::f64::consts::PI * 0.05 * 0.05 * 0.006;
        let error = |meridian: usize, around: usize| {
            let f = SmoothLens::new(0.05, 0.006, meridian, around).evaluate(
                &hp,
                &pose,
                &mut Vec::new(),
                false,
            );
            let error = (f.force - DVec3::Z * expected).length() / expected;
            (error, f.torque.length() / (expected * 0.05))
        };
        let (e8, e16, e32) = (error(8, 8), error(16, 8), error(32, 16));
        assert!(e16.0 < 0.05 * e8.0 && e16.0 < 1e-5, "{e8:?} {e16:?}");
        assert!(e32.0 < 1e-9 && e32.1 < 1e-9, "{e32:?}");
    }

    /// The faceted mesh converges to the smooth integrals as it is refined: at every pose the
    /// 192-segment mesh is closer to them than the 48-segment one, and the error falls about
    /// as the square of the facet size.
    #[test]
    fn refined_meshes_converge_to_the_smooth_quadrature() {
        let coarse = lens(48, Quadrature::Faces);
        let fine = lens(192, Quadrature::Faces);
        let smooth = SmoothLens::new(0.05, 0.006, 48, 32);
        for law in [ForceLaw::Rosellini, ForceLaw::Paper] {
            let hp = hp(law);
            let mut seed = 11;
            let (mut e_coarse, mut e_fine) = (0.0f64, 0.0f64);
            for _ in 0..40 {
                let pose = random_pose(&mut seed);
                let s = smooth.evaluate(&hp, &pose, &mut Vec::new(), false);
                let (mut sc, mut sf) = (Scratch::default(), Scratch::default());
                let c = evaluate_reference(&coarse, &hp, &pose, &FlatSurface, &mut sc, false);
                let f = evaluate_reference(&fine, &hp, &pose, &FlatSurface, &mut sf, false);
                let scale = s.force.length().max(1e-3);
                e_coarse = e_coarse.max((c.force - s.force).length() / scale);
                e_fine = e_fine.max((f.force - s.force).length() / scale);
            }
            assert!(e_fine < 0.4 * e_coarse, "{law:?}: {e_fine} vs {e_coarse}");
            assert!(e_fine < 0.02, "{law:?}: {e_fine}");
        }
    }
}
