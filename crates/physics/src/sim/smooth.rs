//! The force law of [`super::hydro`] (paper eqs. 11–26, read per unit area: pressure and friction
//! at each point of the wetted surface, eq. 24's sum becoming an integral) integrated over the
//! smooth ellipsoid of revolution a lens mesh stands for, on flat water, instead of over its
//! triangles (issue 12: `stone.quadrature: Smooth`).
//!
//! The lens is x²/a² + y²/a² + z²/c² = 1 in its body frame. A meridian is parametrised by the polar
//! angle ψ of its outward normal N = (sin ψ cos φ, sin ψ sin φ, cos ψ): with D = √(a² sin²ψ +
//! c² cos²ψ), the point is ρ = a² sin ψ / D, z = c² cos ψ / D and the meridian's radius of
//! curvature R = a²c²/D³, so dA = ρ R dψ dφ (every quantity smooth in ψ, also at the rim, where the
//! normal turns fastest along the surface). The lens is symmetric about its axis, so the forces
//! are summed in the body frame turned about it until the water's up direction is u = (−h, 0,
//! u_z): a point's height above flat water is then A(ψ) − B(ψ) cos φ (A = z₀ + u_z z, B = hρ, z₀
//! the centre's height), lowest at φ = 0 on every latitude.
//!
//! - **Along the meridian.** The wet latitudes are one interval [ψ₁, ψ₂] about the lowest point's
//!   ψ* (the lowest point per latitude is unimodal on a convex body). Its ends, where a latitude's
//!   lowest point is at the water's height, are the roots of a quadratic form in (cos ψ, sin ψ)
//!   (`touching`). The interval is cut where it reaches from a cap into the rim band (ψ = 2
//!   atan(c/a) from a pole: in ψ the caps hold most of the area in a few degrees); ψ = ψ_m − ψ_h
//!   cos t maps each range onto t ∈ [0, π] so the arcs' √(ψ − ψ₁) growth at the ends becomes
//!   smooth, and a Gauss–Legendre rule in t (nodes by Newton on P_n) integrates it.
//! - **Around a latitude.** Its wet arc is |φ| ≤ β (cos β = A/B), and its normal velocity (V + ω⊥ ×
//!   r)·N = P + Q cos φ + S sin φ is a first harmonic, so the arc is cut exactly where the law
//!   switches (v_n = 0: ventilation, max(0, v_n)). All of it is algebraic in τ = tan(φ/8) (cos φ
//!   and sin φ are rational in τ). On each piece the pressure — the law's (C_L ρ U v_n, C_L ρ
//!   v_n²/2 or C_L ρ U²/2) and the hydrostatic ρ g d, d = −(z₀ + u·r) — is a trig polynomial of
//!   degree ≤ 2 in φ, as are N and r × N = k (sin φ, −cos φ, 0) (k = ρ cos ψ − z sin ψ), so its
//!   force and torque are integrated in closed form; only the friction (|v_t| v_t, a few per cent
//!   of the load) is summed at `around` Gauss nodes in τ.
//!
//! Every node and range end moves smoothly with the pose, and a range or piece that appears does
//! so with zero width, so the force stays continuous for the step control. The clearance is the
//! ellipsoid's support function, z₀ − √(a²|u_xy|² + c²u_z²), exact. Faces of the mesh converge to
//! these integrals as it is refined (tests). The law, the frames and the options (ventilation,
//! pressure sign, hydrostatic pressure) are `hydro::face_force`'s; a ventilated piece receding
//! from the water carries only the hydrostatic pressure (`hydrostatic: WettedFaces`). The axial
//! spin is not felt as normal velocity (the smooth body's `axial_spin`), and the pressure passes
//! through the axis (r × N ⊥ a), so it takes no axial torque.

use glam::{DMat3, DQuat, DVec3};

use super::law::{friction_force, pressure_sign, FaceLoad, ForceSum, HydroParams, Pose};
use super::params::ForceLaw;

/// Gauss–Legendre nodes and weights on [−1, 1] (n ≥ 1), nodes ascending.
pub(crate) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
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
    /// The friction rule's nodes x ≥ 0 (each x > 0 stands for ±x) and weights.
    around_half: Vec<(f64, f64)>,
    /// Where the caps meet the rim band, ψ = 2 atan(c/a) from a pole.
    cap: f64,
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
            cap: 2.0 * c.atan2(a),
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
        let (s, c) = polar_sin_cos(psi);
        let (a2, c2) = (self.a * self.a, self.c * self.c);
        let inv_d = 1.0 / (a2 * s * s + c2 * c * c).sqrt();
        Meridian {
            sin: s,
            cos: c,
            rho: a2 * s * inv_d,
            z: c2 * c * inv_d,
            curvature_radius: a2 * c2 * (inv_d * inv_d * inv_d),
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

    /// The polar angle ψ of the latitude whose lowest point is at the water's height, f(ψ) = z₀ +
    /// u_z z(ψ) − h ρ(ψ) = 0 (h = |u_xy|), on the pole's side of the lowest point's ψ* (`first`:
    /// in [0, ψ*], else in [ψ*, π]), where f changes sign. Times D = √(a² sin²ψ + c² cos²ψ) > 0 it
    /// reads z₀ D = h a² sin ψ − u_z c² cos ψ; squared, a quadratic form in (cos ψ, sin ψ) whose
    /// discriminant is a²c²z₀²(S² − z₀²) (S the support, √(a²h² + c²u_z²)), so its two directions
    /// come in closed form; of those on that side the root is the one that also solves the
    /// unsquared equation (the other has residual 2 z₀ D). Root finding on f where rounding leaves
    /// neither close enough.
    fn touching(&self, z0: f64, h: f64, uz: f64, first: bool) -> f64 {
        self.touching_closed(z0, h, uz, first).unwrap_or_else(|| {
            let lowest = |psi: f64| {
                let m = self.at(psi);
                z0 + uz * m.z - m.rho * h
            };
            let psi_star = h.atan2(-uz);
            if first {
                root(lowest, 0.0, psi_star)
            } else {
                root(lowest, psi_star, std::f64::consts::PI)
            }
        })
    }

    /// [`Self::touching`]'s closed form, `None` where rounding leaves no direction close enough.
    fn touching_closed(&self, z0: f64, h: f64, uz: f64, first: bool) -> Option<f64> {
        let (a2, c2) = (self.a * self.a, self.c * self.c);
        // α Y² + 2β X Y + γ X² = 0 in X = cos ψ, Y = sin ψ.
        let alpha = a2 * (h * h * a2 - z0 * z0);
        let beta = -h * uz * a2 * c2;
        let gamma = c2 * (uz * uz * c2 - z0 * z0);
        let disc = a2 * c2 * z0 * z0 * ((a2 * h * h + c2 * uz * uz) - z0 * z0);
        let q = -(beta + disc.max(0.0).sqrt().copysign(beta));
        let mut best: Option<(f64, f64, f64)> = None;
        for (x, y) in [(alpha, q), (q, gamma)] {
            let norm = (x * x + y * y).sqrt();
            // A zero (or NaN) direction is no root.
            if norm.is_nan() || norm <= 0.0 {
                continue;
            }
            let (x, y) = if y < 0.0 { (-x, -y) } else { (x, y) };
            let (x, y) = (x / norm, y / norm);
            // ψ ≤ ψ* (both in [0, π]) where (cos ψ, sin ψ) × (cos ψ*, sin ψ*) ≥ 0, and
            // (cos ψ*, sin ψ*) = (−u_z, h).
            let before = x * h + y * uz;
            if (first && before < 0.0) || (!first && before > 0.0) {
                continue;
            }
            let d = (a2 * y * y + c2 * x * x).sqrt();
            let r = (h * a2 * y - uz * c2 * x - z0 * d).abs();
            if best.is_none_or(|(_, _, b)| r < b) {
                best = Some((x, y, r));
            }
        }
        // Rounding leaves the residual at some ulps of the terms; the other direction's is 2|z₀|D.
        let tolerance = 1e-9 * (a2 * h + c2 * uz.abs() + self.a * z0.abs());
        best.filter(|&(_, _, r)| r <= tolerance)
            .map(|(x, y, _)| y.atan2(x))
    }

    /// Forces and torque on the lens over flat water (world frame); with `record` the vertical
    /// load of every loaded node is pushed to `loads` for the water coupling.
    ///
    /// The evaluation frame is the body frame turned about the axis (a symmetry of the lens) so
    /// that the water's up direction is u = (−h, 0, u_z): every latitude's lowest point is at
    /// azimuth φ = 0, and its wet arc is symmetric about it.
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
        let (rot, u_body) = Self::frame(pose.orientation);
        let z0 = pose.position.z;
        if self.clearance_in(z0, u_body) > 0.0 {
            return ForceSum::default();
        }
        let h = u_body.x.hypot(u_body.y);
        let (ex, ey) = if h > 0.0 {
            (-u_body.x / h, -u_body.y / h)
        } else {
            (1.0, 0.0)
        };
        let world_from_eval =
            rot * DMat3::from_cols(DVec3::new(ex, ey, 0.0), DVec3::new(-ey, ex, 0.0), DVec3::Z);
        let eval_from_world = world_from_eval.transpose();
        let u = DVec3::new(-h, 0.0, u_body.z);
        // A latitude's lowest point is at z₀ + u_z z − h ρ: unimodal in ψ, least at ψ*.
        let psi1 = if z0 + u.z * self.c <= 0.0 {
            0.0
        } else {
            self.touching(z0, h, u.z, true)
        };
        let psi2 = if z0 - u.z * self.c <= 0.0 {
            PI
        } else {
            self.touching(z0, h, u.z, false)
        };
        let cx = Ctx {
            hp,
            z0,
            u,
            v: eval_from_world * pose.velocity,
            w: eval_from_world * pose.angular_velocity,
            speed: pose.velocity.length(),
            receding_is_dry: hp.ventilated && !(hp.hydrostatic_wetted && hp.rho_g != 0.0),
        };
        let mut acc = Sums::default();
        let mut sink = record.then_some(Loads {
            world_from_eval: &world_from_eval,
            position: pose.position,
            loads,
        });
        // The caps hold most of the area in a few degrees of ψ about the poles (R is a²/c there,
        // c²/a at the rim): a wet range that reaches from a cap into the rim band is cut there.
        let cap = self.cap;
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
                // along its normal: ω⊥ · (r × N) = k (ω_x sin φ − ω_y cos φ).
                let lat = Latitude {
                    m,
                    weight: weight * m.rho * m.curvature_radius,
                    k,
                    p: m.cos * cx.v.z,
                    q: m.sin * cx.v.x - k * cx.w.y,
                    s: m.sin * cx.v.y + k * cx.w.x,
                };
                self.latitude(&cx, &lat, &mut acc, sink.as_mut());
            }
        }
        ForceSum {
            force: world_from_eval * acc.force,
            torque: world_from_eval * acc.torque,
            wetted_area: acc.area,
            in_contact: true,
        }
    }

    /// Integrates one wet latitude's arc, cut where the normal velocity changes sign. The arc
    /// is parametrised by τ = tan(φ/8), which maps the whole latitude onto |τ| ≤ tan(π/8) with
    /// cos φ and sin φ rational in τ (dφ = 8 dτ/(1 + τ²)): its ends and cuts are algebraic and no
    /// angle is ever formed. The friction's Gauss rule in τ is about as accurate as one in φ (the
    /// map's poles, τ = ±i, are far enough from the arc; with τ = tan(φ/4) its error grew by a
    /// fifth, with tan(φ/16) it fell by 2 %).
    fn latitude(&self, cx: &Ctx, lat: &Latitude, acc: &mut Sums, mut sink: Option<&mut Loads>) {
        let m = &lat.m;
        // Heights A − B cos φ: wet where cos φ ≥ A/B, |τ| ≤ τ_e.
        let a_coef = cx.z0 + cx.u.z * m.z;
        let b_coef = m.rho * -cx.u.x;
        // The arc's end in t = tan(φ/2) and in τ.
        let (t_edge, tau_edge) = if b_coef <= 0.0 || a_coef <= -b_coef {
            if a_coef > 0.0 {
                return;
            }
            // The whole latitude: φ = ±π, tan(π/8).
            (f64::INFINITY, std::f64::consts::SQRT_2 - 1.0)
        } else if a_coef >= b_coef {
            return;
        } else {
            // tan(β/8) with cos β = A/B, from tan(β/2) = √((B − A)/(B + A)).
            let t = ((b_coef - a_coef) / (b_coef + a_coef)).sqrt();
            (t, eighth_from_half(t))
        };
        // Where the normal velocity P + Q cos φ + S sin φ changes sign: with t = tan(φ/2),
        // (P − Q) t² + 2 S t + (P + Q) = 0.
        let (p, q, s) = (lat.p, lat.q, lat.s);
        let mut cuts = [-tau_edge, tau_edge, tau_edge, tau_edge];
        let mut n = 1;
        let disc = s * s + (q - p) * (q + p);
        if disc > 0.0 {
            let big = -(s + disc.sqrt().copysign(s));
            if big != 0.0 {
                let mut inner = [big / (p - q), (p + q) / big];
                inner.sort_by(f64::total_cmp);
                // τ is increasing in t, so a cut is inside the arc where its t is; only those
                // are carried to τ.
                for t in inner {
                    if t.abs() < t_edge {
                        let tau = eighth_from_half(t);
                        if tau > -tau_edge && tau < tau_edge {
                            cuts[n] = tau;
                            n += 1;
                        }
                    }
                }
            }
        }
        cuts[n] = tau_edge;
        for piece in cuts[..=n].windows(2) {
            if piece[1] > piece[0] {
                self.piece(cx, lat, (piece[0], piece[1]), acc, sink.as_deref_mut());
            }
        }
    }

    /// One piece [τ_lo, τ_hi] of a latitude's wet arc, on which the normal velocity keeps its
    /// sign: the pressure (the law's and the hydrostatic) in closed form, the friction by the
    /// Gauss rule in τ.
    fn piece(
        &self,
        cx: &Ctx,
        lat: &Latitude,
        (lo, hi): (f64, f64),
        acc: &mut Sums,
        sink: Option<&mut Loads>,
    ) {
        let m = &lat.m;
        let hp = cx.hp;
        let (tm, th) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let (cm, sm, _) = azimuth(tm);
        let vn_mid = lat.p + lat.q * cm + lat.s * sm;
        // A ventilated piece receding from the water carries only the hydrostatic pressure, and
        // that only when every wetted face feels it.
        let receding = hp.ventilated && vn_mid <= 0.0;
        if receding && cx.receding_is_dry {
            return;
        }
        let mut p = Harmonics::default();
        if hp.rho_g != 0.0 && (!receding || hp.hydrostatic_wetted) {
            // ρ g d, the depth d = −(z₀ + u·r) = D₀ + hρ cos φ (≥ 0 on the wet arc).
            p.a0 += hp.rho_g * -(cx.z0 + cx.u.z * m.z);
            p.a1 += hp.rho_g * -(cx.u.x * m.rho);
        }
        if !receding {
            dynamic_pressure(hp, cx.speed, (lat.p, lat.q, lat.s), vn_mid, &mut p);
        }
        let moments = Moments::over(azimuth(lo), azimuth(hi), lo, hi);
        let (j0, jc, js) = moments.of(&p);
        let weight = lat.weight;
        let mut force = DVec3::new(m.sin * jc, m.sin * js, m.cos * j0) * -weight;
        let mut torque = DVec3::new(js, -jc, 0.0) * (-weight * lat.k);
        if !receding && hp.friction != 0.0 {
            for &(x, w) in &self.around_half {
                let sides: &[f64] = if x == 0.0 { &[0.0] } else { &[1.0, -1.0] };
                for &side in sides {
                    let (cs, sn, dphi) = azimuth(tm + side * th * x);
                    let r = DVec3::new(m.rho * cs, m.rho * sn, m.z);
                    let normal = DVec3::new(m.sin * cs, m.sin * sn, m.cos);
                    let v = cx.v + cx.w.cross(r);
                    let area = weight * w * th * dphi;
                    let f = friction_force(hp, v - normal * v.dot(normal), area, cx.speed);
                    force += f;
                    torque += r.cross(f);
                }
            }
        }
        if force == DVec3::ZERO {
            return;
        }
        let area = weight * moments.len;
        acc.area += area;
        acc.force += force;
        acc.torque += torque;
        if let Some(sink) = sink {
            // One load at the piece's middle (in τ) carries its whole vertical force.
            let r = DVec3::new(m.rho * cm, m.rho * sm, m.z);
            let normal = DVec3::new(m.sin * cm, m.sin * sm, m.cos);
            sink.push(r, force, area * cx.u.dot(normal).abs());
        }
    }
}

/// Adds the law's dynamic pressure per unit area on a piece where the normal velocity is
/// v_n = P + Q cos φ + S sin φ with the sign of `vn_mid`, as a trig polynomial in φ: the laws of
/// `hydro::face_force` (Rosellini's C_L ρ U v_n, the paper's C_L ρ v_n²/2, Bocquet's C_L ρ U²/2),
/// with its sign convention (as printed every loaded face is pushed along −N; opposing the
/// motion, a receding one is pulled).
fn dynamic_pressure(
    hp: &HydroParams,
    speed: f64,
    (pp, q, s): (f64, f64, f64),
    vn_mid: f64,
    p: &mut Harmonics,
) {
    let sign = pressure_sign(hp.opposing, vn_mid);
    match hp.law {
        ForceLaw::Rosellini => {
            // C_L ρ U max(0, v_n), or C_L ρ U |v_n| with the sign: v_n itself.
            if hp.opposing || vn_mid > 0.0 {
                let k = hp.lift * hp.density * speed;
                p.a0 += k * pp;
                p.a1 += k * q;
                p.b1 += k * s;
            }
        }
        ForceLaw::Paper => {
            // v_n² = P² + (Q² + S²)/2 + 2PQ cos φ + 2PS sin φ + (Q² − S²)/2 cos 2φ + QS sin 2φ.
            let k = sign * hp.lift * 0.5 * hp.density;
            p.a0 += k * (pp * pp + 0.5 * (q * q + s * s));
            p.a1 += k * 2.0 * pp * q;
            p.b1 += k * 2.0 * pp * s;
            p.a2 += k * 0.5 * (q - s) * (q + s);
            p.b2 += k * q * s;
        }
        ForceLaw::Bocquet => p.a0 += sign * hp.lift * 0.5 * hp.density * speed * speed,
    }
}

/// A pressure per unit area along a latitude, a0 + a1 cos φ + b1 sin φ + a2 cos 2φ + b2 sin 2φ.
#[derive(Default)]
struct Harmonics {
    a0: f64,
    a1: f64,
    b1: f64,
    a2: f64,
    b2: f64,
}

/// The integrals of cos kφ and sin kφ (k = 1, 2, 3) over a piece [φ_a, φ_b] and its angle.
struct Moments {
    len: f64,
    ic: [f64; 3],
    is: [f64; 3],
}

impl Moments {
    /// From cos and sin of the ends (`azimuth` at τ_lo and τ_hi) and the ends themselves.
    fn over((ca, sa, _): (f64, f64, f64), (cb, sb, _): (f64, f64, f64), lo: f64, hi: f64) -> Self {
        // |τ| < 1 on both ends, so 1 + τ_lo τ_hi > 0 and the difference of the atans is one atan.
        let len = 8.0 * small_atan((hi - lo) / (1.0 + lo * hi));
        // cos kφ and sin kφ at both ends by the multiple-angle formulas.
        let multiples = |c: f64, s: f64| {
            let (c2, s2) = ((c - s) * (c + s), 2.0 * s * c);
            ([c, c2, c * c2 - s * s2], [s, s2, s * c2 + c * s2])
        };
        let (cos_a, sin_a) = multiples(ca, sa);
        let (cos_b, sin_b) = multiples(cb, sb);
        let mut ic = [0.0; 3];
        let mut is = [0.0; 3];
        for k in 0..3 {
            const OVER_K: [f64; 3] = [1.0, 0.5, 1.0 / 3.0];
            ic[k] = (sin_b[k] - sin_a[k]) * OVER_K[k];
            is[k] = (cos_a[k] - cos_b[k]) * OVER_K[k];
        }
        Self { len, ic, is }
    }

    /// ∫p, ∫p cos φ and ∫p sin φ over the piece (products to sums of cos kφ and sin kφ).
    fn of(&self, p: &Harmonics) -> (f64, f64, f64) {
        let (l, c, s) = (self.len, &self.ic, &self.is);
        let j0 = p.a0 * l + p.a1 * c[0] + p.b1 * s[0] + p.a2 * c[1] + p.b2 * s[1];
        let jc = p.a0 * c[0]
            + 0.5 * (p.a1 * (l + c[1]) + p.b1 * s[1] + p.a2 * (c[2] + c[0]) + p.b2 * (s[2] + s[0]));
        let js = p.a0 * s[0]
            + 0.5 * (p.a1 * s[1] + p.b1 * (l - c[1]) + p.a2 * (s[2] - s[0]) + p.b2 * (c[0] - c[2]));
        (j0, jc, js)
    }
}

/// sin ψ and cos ψ of a polar angle ψ ∈ [0, π] by Taylor polynomials on three octant-wide
/// pieces (|x| ≤ π/4, where the next terms are below 5e-17): a few multiplies where the library's
/// `sin_cos` handles any argument. Other arguments go to `sin_cos`.
#[inline]
fn polar_sin_cos(psi: f64) -> (f64, f64) {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    // Horner in x² for sin x / x and cos x.
    let sin_cos = |x: f64| {
        let x2 = x * x;
        let sin = x
            * (1.0
                + x2 * (-1.0 / 6.0
                    + x2 * (1.0 / 120.0
                        + x2 * (-1.0 / 5040.0
                            + x2 * (1.0 / 362880.0
                                + x2 * (-1.0 / 39916800.0
                                    + x2 * (1.0 / 6227020800.0
                                        + x2 * (-1.0 / 1307674368000.0))))))));
        let cos = 1.0
            + x2 * (-0.5
                + x2 * (1.0 / 24.0
                    + x2 * (-1.0 / 720.0
                        + x2 * (1.0 / 40320.0
                            + x2 * (-1.0 / 3628800.0
                                + x2 * (1.0 / 479001600.0
                                    + x2 * (-1.0 / 87178291200.0
                                        + x2 * (1.0 / 20922789888000.0))))))));
        (sin, cos)
    };
    if (0.0..=FRAC_PI_4).contains(&psi) {
        sin_cos(psi)
    } else if psi > FRAC_PI_4 && psi <= 3.0 * FRAC_PI_4 {
        let (s, c) = sin_cos(psi - FRAC_PI_2);
        (c, -s)
    } else if psi > 3.0 * FRAC_PI_4 && psi <= PI {
        let (s, c) = sin_cos(PI - psi);
        (s, -c)
    } else {
        psi.sin_cos()
    }
}

/// atan x for 0 ≤ x ≤ 1 (a piece's angle over 8), by two halvings, x/(1 + √(1 + x²)), to at
/// most tan(π/16) < 0.2, and the Taylor series to x²³ (the next term below 4e-19). Other
/// arguments go to `atan`.
#[inline]
fn small_atan(x: f64) -> f64 {
    if !(0.0..=1.0).contains(&x) {
        return x.atan();
    }
    let y = half_tangent(half_tangent(x));
    let y2 = y * y;
    // 1 − y²/3 + y⁴/5 − … − y²²/23, by Horner.
    const SERIES: [f64; 12] = [
        1.0,
        -1.0 / 3.0,
        1.0 / 5.0,
        -1.0 / 7.0,
        1.0 / 9.0,
        -1.0 / 11.0,
        1.0 / 13.0,
        -1.0 / 15.0,
        1.0 / 17.0,
        -1.0 / 19.0,
        1.0 / 21.0,
        -1.0 / 23.0,
    ];
    let sum = SERIES.iter().rev().fold(0.0, |acc, &c| c + y2 * acc);
    4.0 * y * sum
}

/// cos φ, sin φ and dφ/dτ at τ = tan(φ/8).
#[inline(always)]
fn azimuth(tau: f64) -> (f64, f64, f64) {
    let t2 = tau * tau;
    let d = 1.0 / (1.0 + t2);
    // cos and sin of φ/4, then of φ/2 and φ by doubling.
    let (c, s) = ((1.0 - t2) * d, 2.0 * tau * d);
    let (c, s) = ((c - s) * (c + s), 2.0 * s * c);
    ((c - s) * (c + s), 2.0 * s * c, 8.0 * d)
}

/// tan(x/2) from t = tan(x), x ∈ [−π/2, π/2] (t = ±∞ at the ends).
fn half_tangent(t: f64) -> f64 {
    if t.abs() <= 1.0 {
        t / (1.0 + (1.0 + t * t).sqrt())
    } else {
        let r = 1.0 / t.abs();
        (1.0 / (r + (r * r + 1.0).sqrt())).copysign(t)
    }
}

/// τ = tan(φ/8) from t = tan(φ/2), φ ∈ [−π, π] (t = ±∞ at φ = ±π).
fn eighth_from_half(t: f64) -> f64 {
    half_tangent(half_tangent(t))
}

/// What every node of one evaluation shares (evaluation frame).
struct Ctx<'a> {
    hp: &'a HydroParams,
    z0: f64,
    /// The water's up direction, (−h, 0, u_z).
    u: DVec3,
    v: DVec3,
    w: DVec3,
    /// Centre-of-mass speed U.
    speed: f64,
    /// A ventilated piece receding from the water carries nothing (only the loaded faces feel
    /// the hydrostatic pressure, or there is none).
    receding_is_dry: bool,
}

/// Where the loads of a recorded evaluation go (world frame).
struct Loads<'a> {
    world_from_eval: &'a DMat3,
    position: DVec3,
    loads: &'a mut Vec<FaceLoad>,
}

impl Loads<'_> {
    /// The vertical load of force `f` (evaluation frame) acting at `r`, over `footprint` m².
    fn push(&mut self, r: DVec3, f: DVec3, footprint: f64) {
        let world = self.position + *self.world_from_eval * r;
        self.loads.push(FaceLoad {
            x: world.x,
            y: world.y,
            fz: (*self.world_from_eval * f).z,
            footprint,
        });
    }
}

/// One wet latitude: its meridian point, the weight of its ψ node times ρR, k = ρ cos ψ −
/// z sin ψ (r × N = k (sin φ, −cos φ, 0)), and its normal velocity P + Q cos φ + S sin φ.
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
            ..Physics::version_1()
        };
        p.axial_spin = crate::sim::params::AxialSpin::Resal;
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

    #[test]
    fn polar_sin_cos_is_the_library_one_to_rounding() {
        let n = 200_000;
        for i in 0..=n {
            let psi = std::f64::consts::PI * i as f64 / n as f64;
            let (s, c) = polar_sin_cos(psi);
            let (s0, c0) = psi.sin_cos();
            assert!(
                (s - s0).abs() <= 4e-16 && (c - c0).abs() <= 4e-16,
                "{psi}: {s} {c} vs {s0} {c0}"
            );
        }
        assert_eq!(polar_sin_cos(4.0), 4.0f64.sin_cos());
    }

    #[test]
    fn small_atan_is_the_library_one_to_rounding() {
        let n = 100_000;
        for i in 0..=n {
            let x = i as f64 / n as f64;
            let (a, a0) = (small_atan(x), x.atan());
            assert!(
                (a - a0).abs() <= 4.0 * f64::EPSILON * a0.max(f64::MIN_POSITIVE),
                "{x}: {a} vs {a0}"
            );
        }
        assert_eq!(small_atan(3.0), 3.0f64.atan());
    }

    /// The wet range's ends in closed form are the roots of the lowest point's height along the
    /// meridian that root finding gives.
    #[test]
    fn wet_range_ends_are_the_roots_of_the_lowest_height() {
        use std::f64::consts::PI;
        let smooth = SmoothLens::new(0.05, 0.006, 8, 2);
        let mut seed = 23;
        let (mut found, mut fallbacks) = (0, 0);
        for _ in 0..2000 {
            let tilt = PI * rng(&mut seed);
            let (h, uz) = (tilt.sin(), tilt.cos());
            let support = (0.05f64 * 0.05 * h * h + 0.006 * 0.006 * uz * uz).sqrt();
            let z0 = support * (1.0 - 2.0 * rng(&mut seed));
            let lowest = |psi: f64| {
                let m = smooth.at(psi);
                z0 + uz * m.z - m.rho * h
            };
            let psi_star = h.atan2(-uz);
            for (lo, hi, end, first) in [
                (0.0, psi_star, z0 + uz * 0.006, true),
                (psi_star, PI, z0 - uz * 0.006, false),
            ] {
                if end <= 0.0 {
                    continue;
                }
                let Some(closed) = smooth.touching_closed(z0, h, uz, first) else {
                    fallbacks += 1;
                    continue;
                };
                let found_by_root = root(lowest, lo, hi);
                assert!(
                    (closed - found_by_root).abs() < 1e-9,
                    "tilt {tilt} z0 {z0}: {closed} vs {found_by_root}"
                );
                found += 1;
            }
        }
        // The closed form serves all but the odd pose where rounding blurs it.
        assert!(
            found > 1000 && fallbacks * 100 < found,
            "{found} {fallbacks}"
        );
    }

    /// One latitude's arc, integrated by `latitude` (algebraic ends and cuts in τ, the pressure
    /// in closed form), against a brute force: the arc and its cuts found with angles (acos,
    /// atan2) and `hydro::face_force` summed at 48 Gauss nodes in φ on every piece.
    #[test]
    fn a_latitude_matches_face_force_summed_densely() {
        use crate::sim::hydro::face_force;
        use std::f64::consts::{PI, TAU};
        let smooth = SmoothLens::new(0.05, 0.006, 8, 48);
        let dense = gauss_legendre(48);
        let mut seed = 17;
        let mut checked = 0;
        let cases = [
            (ForceLaw::Rosellini, true, false),
            (ForceLaw::Rosellini, false, true),
            (ForceLaw::Paper, false, false),
            (ForceLaw::Paper, false, true),
            (ForceLaw::Bocquet, true, true),
        ];
        // The pressure alone is exact (to rounding); the friction, |v_t| v_t, is summed at nodes
        // on both sides and converges more slowly (Bocquet's, U² along v_t, whose direction turns
        // fast where v_t nearly vanishes, too slowly for a check).
        for ((law, ventilated, opposing), friction) in
            cases.into_iter().flat_map(|c| [(c, false), (c, true)])
        {
            let mut hp = hp(law);
            hp.ventilated = ventilated;
            hp.opposing = opposing;
            if !friction {
                hp.friction = 0.0;
            }
            if friction && law == ForceLaw::Bocquet {
                continue;
            }
            let tolerance = if friction { 1e-6 } else { 1e-10 };
            for _ in 0..200 {
                let psi = PI * rng(&mut seed);
                let m = smooth.at(psi);
                let h = rng(&mut seed);
                let cx = Ctx {
                    hp: &hp,
                    z0: 0.01 * (rng(&mut seed) - 0.5),
                    u: DVec3::new(-h, 0.0, (1.0 - h * h).sqrt()),
                    v: DVec3::new(8.0 * rng(&mut seed), rng(&mut seed) - 0.5, -rng(&mut seed)),
                    w: DVec3::new(
                        20.0 * (rng(&mut seed) - 0.5),
                        20.0 * (rng(&mut seed) - 0.5),
                        90.0,
                    ),
                    speed: 9.0,
                    receding_is_dry: hp.ventilated && !(hp.hydrostatic_wetted && hp.rho_g != 0.0),
                };
                let k = m.rho * m.cos - m.z * m.sin;
                let lat = Latitude {
                    m,
                    weight: 1e-3,
                    k,
                    p: m.cos * cx.v.z,
                    q: m.sin * cx.v.x - k * cx.w.y,
                    s: m.sin * cx.v.y + k * cx.w.x,
                };
                let mut acc = Sums::default();
                smooth.latitude(&cx, &lat, &mut acc, None);
                // The brute force: the wet arc |φ| ≤ β and the cuts θ_v ± γ, as angles.
                let (a_coef, b_coef) = (cx.z0 + cx.u.z * m.z, m.rho * h);
                let beta = if a_coef <= -b_coef {
                    PI
                } else if a_coef >= b_coef {
                    continue;
                } else {
                    (a_coef / b_coef).acos()
                };
                let mut ends = vec![-beta, beta];
                let r = lat.q.hypot(lat.s);
                if r > lat.p.abs() {
                    let (theta_v, gamma) = (lat.s.atan2(lat.q), (-lat.p / r).acos());
                    for cut in [theta_v - gamma, theta_v + gamma] {
                        let cut = cut - TAU * ((cut + PI) / TAU).floor();
                        if cut > -beta && cut < beta {
                            ends.push(cut);
                        }
                    }
                }
                ends.sort_by(f64::total_cmp);
                let mut want = Sums::default();
                for piece in ends.windows(2) {
                    let (mid, half) = (0.5 * (piece[0] + piece[1]), 0.5 * (piece[1] - piece[0]));
                    for &(x, w) in &dense {
                        let (sn, cs) = (mid + half * x).sin_cos();
                        let r = DVec3::new(m.rho * cs, m.rho * sn, m.z);
                        let normal = DVec3::new(m.sin * cs, m.sin * sn, m.cos);
                        let vn = lat.p + lat.q * cs + lat.s * sn;
                        let depth = -(cx.z0 + cx.u.dot(r));
                        let area = lat.weight * w * half;
                        let v = cx.v + cx.w.cross(r);
                        let f = face_force(&hp, normal, area, v, vn, cx.speed, depth);
                        want.force += f;
                        want.torque += r.cross(f);
                    }
                }
                let scale = want.force.length().max(1e-9);
                assert!(
                    (acc.force - want.force).length() < tolerance * scale
                        && (acc.torque - want.torque).length() < tolerance * scale * 0.05,
                    "{law:?} friction {friction} ψ {psi}: {:?} vs {:?}; {:?} vs {:?}",
                    acc.force,
                    want.force,
                    acc.torque,
                    want.torque
                );
                checked += 1;
            }
        }
        assert!(checked > 800, "{checked}");
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
