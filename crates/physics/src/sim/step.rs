//! One step of the stone: a flight or a contact step under the preset's integrator (the paper's
//! eqs. 30–38, symplectic Euler, RK4, or Dormand–Prince 5(4) with error control and the exit, the
//! touch and the sinking instant located inside the step; Hairer, Nørsett & Wanner, *Solving ODEs
//! I*, §II.4–6). [`super::Simulation`] calls [`fixed_step`] or [`adaptive_step`] and keeps the
//! clock, the record and the water; the touch search itself is `touch.rs`.

use std::cell::Cell;

use glam::{DMat3, DQuat, DVec3};

use super::air::Air;
use super::hydro::{
    lowest_clearance, underside_submerged, FlatSurface, ForceSum, Scratch, Surface,
};
use super::integrate::{
    fly, mesh_orientation, q4, step_dp5, step_paper, step_rk4, step_symplectic_euler, BodyState,
    Deriv, Dynamics, ErrorScales,
};
use super::params::{Integrator, Rotation};
use super::stone::Stone;
use super::touch::{first_touch, first_wet_by, FlightBound, RevolutionBound, WaveBound};
use super::water::{EtaPatch, WaterGrid};
use super::Motion;

/// A contact step that ended past the tick's end (`steps_across_ticks`): its start and the
/// derivatives at both ends. Its end is the stone's current state and time, which stay so until
/// the next step replaces this.
#[derive(Debug, Clone, Copy)]
pub(super) struct Overshoot {
    pub(super) t0: f64,
    pub(super) s0: BodyState,
    pub(super) d0: Deriv,
    pub(super) d1: Deriv,
}

impl Overshoot {
    /// Position and orientation at `t` inside the step that ends at `t1` in `s1`: cubic Hermite
    /// on its ends' values and derivatives (third order; the orientation renormalised), for
    /// drawing only.
    pub(super) fn pose_at(&self, t: f64, t1: f64, s1: &BodyState) -> (DVec3, DQuat) {
        let h = t1 - self.t0;
        let x = (t - self.t0) / h;
        let (x2, x3) = (x * x, x * x * x);
        let (h00, h10) = (2.0 * x3 - 3.0 * x2 + 1.0, x3 - 2.0 * x2 + x);
        let (h01, h11) = (-2.0 * x3 + 3.0 * x2, x3 - x2);
        let position = self.s0.position * h00
            + self.d0.dx * (h * h10)
            + s1.position * h01
            + self.d1.dx * (h * h11);
        let v = q4(self.s0.orientation) * h00
            + self.d0.dq * (h * h10)
            + q4(s1.orientation) * h01
            + self.d1.dq * (h * h11);
        let orientation = DQuat::from_xyzw(v.x, v.y, v.z, v.w).normalize();
        (position, orientation)
    }
}

/// One accepted step of the stone.
pub(super) struct Step {
    pub(super) state: BodyState,
    pub(super) h: f64,
    /// Forces at the step's end.
    pub(super) force: ForceSum,
    /// Integrated with the water's forces (its loads go to the water); false for exact flight.
    pub(super) contact: bool,
    /// The derivative at the step's start (contact steps).
    pub(super) k1: Option<Deriv>,
    /// Ended with the underside submerged.
    pub(super) sunk: bool,
}

impl Step {
    pub(super) fn flight(state: BodyState, h: f64) -> Self {
        Self {
            state,
            h,
            force: ForceSum::default(),
            contact: false,
            k1: None,
            sunk: false,
        }
    }
}

/// Everything a step needs besides the motion.
pub(super) struct StepContext<'a> {
    pub(super) dy: Dynamics<'a>,
    pub(super) integrator: Integrator,
    pub(super) tolerance: f64,
    /// Upper bound of the surface's slope (0 when flat).
    pub(super) slope: f64,
    pub(super) air: Option<Air>,
    /// A contact step that ends in the water but left it at a stage is shortened to that stage
    /// (`steps_across_ticks`: steps longer than the tick could hide a short hop).
    pub(super) hidden_exits: bool,
    /// The last flight flown (start, duration, end): a flight step flies the interval its touch
    /// probe has just flown to prove it clear.
    pub(super) last_flight: Cell<Option<(BodyState, f64, BodyState)>>,
}

impl StepContext<'_> {
    pub(super) fn clear(&self, st: &BodyState) -> f64 {
        let q = mesh_orientation(self.dy.resal, st);
        lowest_clearance(self.dy.stone, st.position, q, self.dy.surface)
    }

    /// The underside wholly below the waterline the water's law sees (with the wetted-extent
    /// memory, the ambient surface raised by d_e − d_g).
    pub(super) fn submerged(&self, st: &BodyState) -> bool {
        let q = mesh_orientation(self.dy.resal, st);
        underside_submerged(
            self.dy.stone,
            self.dy.wetted_position(st),
            q,
            self.dy.surface,
        )
    }

    pub(super) fn flight(&self, s: &BodyState, t: f64) -> BodyState {
        if let Some((s0, t0, end)) = self.last_flight.get() {
            if s0 == *s && t0 == t {
                return end;
            }
        }
        let end = fly(
            self.dy.stone,
            self.dy.rotation,
            self.dy.gravity,
            self.air.as_ref(),
            s,
            t,
        );
        self.last_flight.set(Some((*s, t, end)));
        end
    }

    /// The first touch along the exact flight from `s` over [0, h] (see [`first_touch`]): `None`
    /// when proven clear, else the bracket of the first touch.
    pub(super) fn touch(&self, s: &BodyState, h: f64) -> Option<(f64, f64)> {
        let stone = self.dy.stone;
        // With air the speed and the angular momentum change in flight: bound them over [0, h].
        let (a_air, m_air) = match &self.air {
            Some(air) => {
                let (f, m) = air.bounds(s.velocity.length() + 2.0 * self.dy.gravity * h);
                (f / stone.mass, m)
            }
            None => (0.0, 0.0),
        };
        let omega = match self.dy.rotation {
            Rotation::Locked => 0.0,
            Rotation::Free => {
                (s.angular_momentum.length() + m_air * h) / stone.principal_moments().min_element()
            }
        };
        let speed_h = s.velocity.x.hypot(s.velocity.y) + a_air * h;
        let max_eta = self.dy.surface.max_height();
        let radius = stone.bounding_radius;
        let mut bound =
            FlightBound::new(radius, speed_h, omega, self.slope, max_eta).with_air(a_air);
        let axis = self.axis_turn(s, m_air * h);
        if let Some((perp, _)) = axis {
            let facet = stone.facet_gap(self.slope).unwrap_or(f64::INFINITY);
            bound = bound.with_revolution(radius, speed_h, perp, self.slope, facet);
        }
        // At the origin no early-out applies: the lowest vertex's offset itself.
        let rise = |st: &BodyState| {
            let q = mesh_orientation(self.dy.resal, st);
            lowest_clearance(stone, DVec3::ZERO, q, &FlatSurface)
        };
        let crest = |lo: [f64; 2], hi: [f64; 2]| self.dy.surface.max_height_over(lo, hi);
        let wave = (!self.dy.surface.is_flat()).then(|| WaveBound {
            rise: &rise,
            crest: &crest,
            radius,
            rate: omega * radius,
            revolution: axis.map(|(perp, flat)| RevolutionBound {
                rate: perp * radius,
                facet: flat,
            }),
            drift: a_air,
        });
        first_touch(
            &|st: &BodyState, t: f64| self.flight(st, t),
            &|st: &BodyState| self.clear(st),
            &bound,
            wave.as_ref(),
            s,
            h,
        )
    }

    /// For a free body of revolution: a bound of the angular speed of its symmetry axis over a
    /// flight from `s` whose torques change the angular momentum by at most `kick` (N·m·s), and
    /// the facet gap of its rings on flat water. The axis turns at |ω⊥| = |L × a| / I₁, and a
    /// torque changes |L × a| by at most its own size. `None` for any other body or rotation.
    pub(super) fn axis_turn(&self, s: &BodyState, kick: f64) -> Option<(f64, f64)> {
        let stone = self.dy.stone;
        if self.dy.rotation != Rotation::Free || !stone.is_axisymmetric() {
            return None;
        }
        let flat = stone.facet_gap(0.0)?;
        let a = s.orientation * DVec3::Z;
        let m = stone.principal_moments();
        Some((
            (s.angular_momentum.cross(a).length() + kick) / m.x.min(m.y),
            flat,
        ))
    }

    /// The contact step of this context's integrator from `s` (derivative `k1`) over `h`, with
    /// the forces evaluated (and the face loads recorded) at its end: (state, end derivative, end
    /// forces, force evaluations). Adaptive: one Dormand–Prince step, without error control.
    pub(super) fn contact_step(
        &self,
        s: &BodyState,
        k1: &Deriv,
        h: f64,
        scratch: &mut Scratch,
    ) -> (BodyState, Deriv, ForceSum, u64) {
        let dy = &self.dy;
        let (state, evals) = match self.integrator {
            Integrator::Adaptive => {
                let scales = error_scales(dy, s);
                let a = step_dp5(dy, s, k1, h, self.tolerance, &scales, scratch);
                return (a.state, a.k_end, a.force_end, a.evals);
            }
            Integrator::Paper => (step_paper(dy, s, k1, h), 0),
            Integrator::SymplecticEuler => (step_symplectic_euler(dy, s, k1, h), 0),
            Integrator::Rk4 => (step_rk4(dy, s, k1, h, scratch), 3),
        };
        let (k_end, f_end) = dy.derivative(&state, scratch, true);
        (state, k_end, f_end, evals + 1)
    }
}

/// Scales of the Dormand–Prince error norm at state `s`.
pub(super) fn error_scales(dy: &Dynamics, s: &BodyState) -> ErrorScales {
    let r = dy.stone.bounding_radius;
    let g = dy.gravity.max(1e-3);
    ErrorScales {
        position: r,
        velocity: s.velocity.length().max((g * r).sqrt()),
        angular_momentum: s
            .angular_momentum
            .length()
            .max(dy.stone.principal_moments().max_element() * (g / r).sqrt()),
    }
}

/// The derivative at the motion's state: the last step's end (FSAL) or a fresh evaluation.
pub(super) fn start_derivative(dy: &Dynamics, m: &mut Motion) -> Deriv {
    match m.fsal {
        Some((k, _)) => k,
        None => {
            m.force_evals += 1;
            dy.derivative(&m.state, &mut m.scratch, false).0
        }
    }
}

/// One step of a fixed-step scheme over the rest of the tick `h_max`. Every scheme flies exactly
/// (eqs. 4–8 are exact for a parabola; the torque-free rotation has a closed form): they differ in
/// contact only. A flight that touches the water inside the tick but is clear again at its end (a
/// graze of a spinning stone, or over a wave) flies exactly to the touch; the scheme then steps from
/// there over the tick's rest.
pub(super) fn fixed_step(cx: &StepContext, m: &mut Motion, h_max: f64) -> Step {
    let prev = m.state;
    let in_flight = |m: &mut Motion| {
        m.fsal = None;
        m.prev_loads.clear();
    };
    match cx.touch(&prev, h_max) {
        None => {
            in_flight(m);
            return Step::flight(cx.flight(&prev, h_max), h_max);
        }
        Some((lo, hi)) if hi > 0.0 && cx.clear(&cx.flight(&prev, h_max)) > 0.0 => {
            in_flight(m);
            let t = first_wet_by(lo, hi, 60, |t| cx.clear(&cx.flight(&prev, t)));
            return Step::flight(cx.flight(&prev, t), t);
        }
        Some(_) => {}
    }
    let k1 = start_derivative(&cx.dy, m);
    let (state, k_end, force, evals) = cx.contact_step(&prev, &k1, h_max, &mut m.scratch);
    m.force_evals += evals;
    m.fsal = Some((k_end, force));
    Step {
        state,
        h: h_max,
        force,
        contact: true,
        k1: Some(k1),
        sunk: false,
    }
}

/// How far the highest vertex of the faces whose outward normal points down is above the surface
/// (m): the underside is submerged (design.md §4 "sank", [`underside_submerged`]) exactly when this
/// is negative; +∞ without a downward face. Continuous in the state, so the sinking instant can be
/// found by a secant method.
pub(super) fn underside_height(
    stone: &Stone,
    resal: bool,
    st: &BodyState,
    surface: &dyn Surface,
) -> f64 {
    let rot = DMat3::from_quat(mesh_orientation(resal, st));
    let mut highest = f64::NEG_INFINITY;
    let mut any_down = false;
    for (t, tri) in stone.mesh.triangles.iter().enumerate() {
        if (rot * stone.normals[t]).z >= 0.0 {
            continue;
        }
        any_down = true;
        for &i in tri {
            let w = st.position + rot * stone.mesh.positions[i as usize];
            highest = highest.max(w.z - surface.height(w.x, w.y));
        }
    }
    if any_down {
        highest
    } else {
        f64::INFINITY
    }
}

/// The sinking instant inside a contact step, located as entry and exit are: if the step from
/// `prev` ends with the underside submerged and did not start so, the step is cut to where the
/// underside's highest point reaches the surface, by the Illinois (regula falsi) method on the
/// integrator's own step from `prev`, to 1e-9 of the stone's size in height or of the step in time.
/// So the sinking time and place converge with the integrator rather than stopping at the step's
/// end.
pub(super) fn locate_sink(
    cx: &StepContext,
    m: &mut Motion,
    prev: &BodyState,
    k1: &Deriv,
    step: Step,
) -> Step {
    if !cx.submerged(&step.state) {
        return step;
    }
    if cx.submerged(prev) {
        return Step { sunk: true, ..step };
    }
    let height = |st: &BodyState| {
        let wetted = BodyState {
            position: cx.dy.wetted_position(st),
            ..*st
        };
        underside_height(cx.dy.stone, cx.dy.resal, &wetted, cx.dy.surface)
    };
    let eps = 1e-9 * cx.dy.stone.bounding_radius;
    let (mut lo, mut f_lo) = (0.0, height(prev).max(0.0));
    let (mut hi, mut f_hi) = (step.h, height(&step.state).min(0.0));
    let mut side = 0i8;
    // The step to `hi` when the last trial set it (its end loads are the scratch's).
    let mut at_hi = None;
    for _ in 0..60 {
        if hi - lo <= 1e-9 * step.h || -f_hi <= eps {
            break;
        }
        let mut x = hi - f_hi * (hi - lo) / (f_hi - f_lo);
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let (s, k_end, force, evals) = cx.contact_step(prev, k1, x, &mut m.scratch);
        m.force_evals += evals;
        let fx = height(&s);
        at_hi = None;
        if fx < 0.0 && cx.submerged(&s) {
            (hi, f_hi) = (x, fx);
            at_hi = Some((s, k_end, force));
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        } else {
            (lo, f_lo) = (x, fx.max(0.0));
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        }
    }
    let (state, k_end, force) = at_hi.unwrap_or_else(|| {
        let (s, k, f, evals) = cx.contact_step(prev, k1, hi, &mut m.scratch);
        m.force_evals += evals;
        (s, k, f)
    });
    m.fsal = Some((k_end, force));
    Step {
        state,
        h: hi,
        force,
        contact: true,
        k1: Some(*k1),
        sunk: cx.submerged(&state),
    }
}

/// One Adaptive step: exact flight to `h_max` or to the first touch; error-controlled
/// Dormand–Prince steps of at most `h_contact` in contact.
pub(super) fn adaptive_step(cx: &StepContext, m: &mut Motion, h_max: f64, h_contact: f64) -> Step {
    let dy = &cx.dy;
    let s = m.state;
    if !m.in_contact && cx.clear(&s) > 0.0 {
        m.fsal = None;
        m.prev_loads.clear();
        return match cx.touch(&s, h_max) {
            None => Step::flight(cx.flight(&s, h_max), h_max),
            Some((lo, hi)) => {
                // Locate the first touch by bisection on the exact flight.
                let t = first_wet_by(lo, hi, 80, |t| cx.clear(&cx.flight(&s, t)));
                Step::flight(cx.flight(&s, t), t)
            }
        };
    }
    let k1 = start_derivative(dy, m);
    let scales = error_scales(dy, &s);
    if m.h_adaptive <= 0.0 {
        // First contact: a fraction of the contact's time scale r / |v|.
        m.h_adaptive = 0.01 * dy.stone.bounding_radius / s.velocity.length().max(0.1);
    }
    let h_min = 1e-10;
    let mut h = m.h_adaptive.min(h_contact);
    let c0 = cx.clear(&s).min(0.0);
    let mut exit_refinements = 0;
    let mut hidden_refinements = 0;
    // With the memory: the estimated time to the exit from `s` once a step has been shortened
    // towards it ([`EXIT_APPROACH`]).
    let mut approach = None;
    loop {
        let attempt = step_dp5(dy, &s, &k1, h, cx.tolerance, &scales, &mut m.scratch);
        m.force_evals += attempt.evals;
        let err = attempt.error;
        let c1 = cx.clear(&attempt.state);
        if dy.memory.is_some() && c1 > 0.0 && err > 1.0 && exit_refinements < MAX_EXIT_APPROACHES {
            let exit = h * (-c0 / (c1 - c0));
            if exit > 0.0 && exit < h {
                exit_refinements += 1;
                approach = Some(exit);
                h = (exit * EXIT_APPROACH).max(h_min);
                continue;
            }
        }
        if err <= 1.0 || h <= h_min {
            // Leaving the water inside the step: the force has a kink there, which the error
            // estimate does not see. Shorten the step to end at the exit (secant on the lowest
            // vertex's clearance), so no step integrates across it.
            if c1 > 0.0 && exit_refinements < 3 && h > 64.0 * h_min {
                let f = -c0 / (c1 - c0);
                if f < 0.99 {
                    exit_refinements += 1;
                    h = (h * f * 1.0001).max(h_min);
                    continue;
                }
            }
            // In the water at both ends but out of it at a stage: the step may have jumped a
            // short hop. Retry it shortened to that stage, so the exit, if there is one, falls at
            // or before its end and is located as above.
            if let Some(c) = attempt.first_dry.filter(|_| cx.hidden_exits && c1 <= 0.0) {
                if hidden_refinements < 3 && h > 64.0 * h_min {
                    hidden_refinements += 1;
                    exit_refinements += 1;
                    h = (h * c).max(h_min);
                    continue;
                }
            }
            let grow = if err > 0.0 {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            } else {
                5.0
            };
            // A step clipped by the tick boundary or shortened to the exit keeps the
            // controller's earlier proposal.
            let clipped = (h >= h_contact && m.h_adaptive > h_contact) || exit_refinements > 0;
            if let Some(exit) = approach {
                // Approaching the memory's exit: the next step tries to reach past it.
                m.h_adaptive = (h * grow).min((exit - h) * EXIT_REACH).max(h_min);
            } else if !clipped || grow < 1.0 {
                m.h_adaptive = (h * grow).max(h_min);
            }
            m.fsal = Some((attempt.k_end, attempt.force_end));
            return Step {
                state: attempt.state,
                h,
                force: attempt.force_end,
                contact: true,
                k1: Some(k1),
                sunk: false,
            };
        }
        let shrink = if err.is_finite() {
            (0.9 * err.powf(-0.2)).clamp(0.1, 0.9)
        } else {
            0.1
        };
        h = (h * shrink).max(h_min);
    }
}

/// A contact with the wetted-extent memory ends in a singular tail: as the stone leaves, its
/// geometric wetted length s_g goes to 0, so the memory's relaxation rate |U|/(λ s_g) grows
/// without bound while d_e still holds millimetres (`memory.rs`), and at the geometric exit the
/// load drops from that of d_e to nothing. A step that reaches across the exit sees d_e change at
/// tens of m/s and its error estimate explodes; shrinking by that estimate alone approached the
/// exit geometrically with a rejection each time (4 in 10 of the default throw's force
/// evaluations). Such a step is instead shortened to this share of the estimated time to the exit
/// (secant on the lowest point's clearance), and the next one reaches [`EXIT_REACH`] times past
/// what is left, until a step that crosses passes its error test and is cut at the exit.
pub(super) const EXIT_APPROACH: f64 = 0.8;

/// After a step shortened towards the exit ([`EXIT_APPROACH`]), the next tries this many times the
/// estimated rest.
pub(super) const EXIT_REACH: f64 = 1.25;

/// Most times one contact step is shortened towards the exit ([`EXIT_APPROACH`]).
pub(super) const MAX_EXIT_APPROACHES: u32 = 4;

/// The highest η (−∞ when no column lies within `reach` of (x, y)) and the largest
/// |Δη|/l between neighbouring columns there, over the columns whose centres lie within `reach`
/// (m) of (x, y) in x and y, and one more on each side; those columns are left in `patch`.
pub(super) fn local_bounds(
    w: &WaterGrid,
    patch: &mut EtaPatch,
    x: f64,
    y: f64,
    reach: f64,
) -> (f64, f64) {
    let [ox, oy] = w.origin();
    let l = w.cell();
    let span = |c: f64, o: f64, n: usize| {
        let lo = ((c - reach - o) / l - 1.5).floor().max(0.0);
        let hi = ((c + reach - o) / l + 0.5).ceil().min(n as f64 - 1.0);
        (lo as usize, hi as usize, hi >= lo)
    };
    let (x0, x1, okx) = span(x, ox, w.nx());
    let (y0, y1, oky) = span(y, oy, w.ny());
    w.fill_patch(patch, (x0, x1), (y0, y1));
    if !(okx && oky) {
        return (f64::NEG_INFINITY, 0.0);
    }
    // Beyond the grid the surface is at rest (η = 0): count it when the reach extends past an edge.
    let inside = |c: f64, o: f64, n: usize| c - reach > o && c + reach < o + n as f64 * l;
    let mut m = if inside(x, ox, w.nx()) && inside(y, oy, w.ny()) {
        f64::NEG_INFINITY
    } else {
        0.0
    };
    let (mut sx, mut sy) = (0.0f64, 0.0f64);
    for iy in y0..=y1 {
        for ix in x0..=x1 {
            let e = patch.at(ix, iy);
            m = m.max(e);
            if ix > x0 {
                sx = sx.max((e - patch.at(ix - 1, iy)).abs());
            }
            if iy > y0 {
                sy = sy.max((e - patch.at(ix, iy - 1)).abs());
            }
        }
    }
    (m, sx.hypot(sy) / l)
}
