//! Storage of the column-and-pipe grid: the kernel's shape and coefficients ([`Coeffs`]), the scalar
//! types the grid is stored and computed in (f32 or f64, [`Real`]), the padded row blocks of depths,
//! flows, bed and pressure ([`Fields`]), and the setters of the state (initial conditions, tests).

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

use crate::sim::params::Swell;

use crate::sim::params::Limiter;

use super::{Active, WaterConfig, WaterGrid};

/// Pipe areas (m²) of an axis and a diagonal pipe: the isotropic A_axis = ⅔Hl, A_diag = (√2/6)Hl
/// with diagonals (equal areas would make waves 1.55× too fast), A = Hl with axis pipes only.
pub(super) fn pipe_areas(cfg: &WaterConfig) -> (f64, f64) {
    let (l, h) = (cfg.cell, cfg.depth);
    if cfg.diagonal_pipes {
        (2.0 / 3.0 * h * l, std::f64::consts::SQRT_2 / 6.0 * h * l)
    } else {
        (h * l, 0.0)
    }
}

/// Shape of the kernel and its coefficients in f64, as derived from the configuration.
#[derive(Debug, Clone, Copy)]
pub(super) struct Coeffs {
    pub(super) nx: usize,
    pub(super) ny: usize,
    /// Fields per row block: depth + pipes (3 or 5).
    pub(super) nf: usize,
    pub(super) clamp: bool,
    /// e^{−γΔt}
    pub(super) damp: f64,
    /// Δt·g·A/L of an axis and a diagonal pipe.
    pub(super) gx: f64,
    pub(super) gd: f64,
    /// Δt·A/(ρL) of an axis and a diagonal pipe (pressure).
    pub(super) px: f64,
    pub(super) pd: f64,
    /// Δt / l²: flow (m³/s) to depth change per step.
    pub(super) beta: f64,
    /// Columns per segment of the row pipeline ([`SEGMENT`]; smaller in tests).
    pub(super) seg: usize,
}

impl Coeffs {
    /// The coefficients of a configuration at step `dt` (water.md §2–§3 for the pipe areas).
    pub(super) fn new(cfg: &WaterConfig, dt: f64) -> Self {
        let (l, g, rho) = (cfg.cell, cfg.gravity, cfg.density);
        let (ax, ad) = pipe_areas(cfg);
        let (lx, ld) = (l, std::f64::consts::SQRT_2 * l);
        Self {
            nx: cfg.nx,
            ny: cfg.ny,
            nf: if cfg.diagonal_pipes { 5 } else { 3 },
            clamp: cfg.limiter == Limiter::PaperClamp,
            damp: (-cfg.damping * dt).exp(),
            gx: dt * g * ax / lx,
            gd: dt * g * ad / ld,
            px: dt * ax / (rho * lx),
            pd: dt * ad / (rho * ld),
            beta: dt / (l * l),
            seg: SEGMENT,
        }
    }
    /// Padded length of one field of a row: one zero before and after the nx values.
    pub(super) fn w(&self) -> usize {
        self.nx + 2
    }
    pub(super) fn stride(&self) -> usize {
        self.nf * self.w()
    }
    pub(super) fn at(&self, ix: usize, iy: usize, f: usize) -> usize {
        iy * self.stride() + f * self.w() + 1 + ix
    }
}

/// The kernel's arithmetic: f32 or f64.
pub(super) trait Num:
    Copy
    + Default
    + Debug
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    /// Rounded from f64.
    fn of(x: f64) -> Self;
    /// Exactly to f64.
    fn get(self) -> f64;
    /// The bit pattern, widened (determinism tests).
    #[cfg(test)]
    fn bits(self) -> u64;
}

/// A storage scalar of the grid, and the type its arithmetic runs in ([`Real::Calc`]): f32 in f32
/// (four lanes per SSE2 instruction; f64 arithmetic on f32 storage measured 3.5× slower and no more
/// conservative, since the depth's own rounding is what drifts; see the module documentation) and
/// f64 in f64.
pub(super) trait Real: Num {
    type Calc: Num;
    fn up(self) -> Self::Calc;
    fn down(x: Self::Calc) -> Self;
}

macro_rules! num {
    ($t:ty, $bits:ty) => {
        impl Num for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline(always)]
            fn of(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn get(self) -> f64 {
                f64::from(self)
            }
            #[cfg(test)]
            fn bits(self) -> u64 {
                u64::from(self.to_bits())
            }
        }
    };
}
num!(f32, u32);
num!(f64, u64);

/// Storage and arithmetic in the same type (measured: f64 arithmetic on f32 storage is 3.5× slower).
macro_rules! real_in_itself {
    ($t:ty) => {
        impl Real for $t {
            type Calc = $t;
            #[inline(always)]
            fn up(self) -> $t {
                self
            }
            #[inline(always)]
            fn down(x: $t) -> $t {
                x
            }
        }
    };
}
real_in_itself!(f64);
real_in_itself!(f32);

/// The stored fields of a grid in one precision.
#[derive(Debug, Clone)]
pub(super) struct Fields<T> {
    /// Row blocks: [depth | qx | qy | (qd | qa)], each field `nx + 2` long (a zero pad at both ends).
    /// qx: (ix,iy)→(ix+1,iy); qy: (ix,iy)→(ix,iy+1); qd: (ix,iy)→(ix+1,iy+1); qa: (ix,iy)→(ix−1,iy+1).
    /// The wall pipes and the pads stay 0.
    pub(super) cur: Vec<T>,
    /// Bed elevation + H per column (0 on the flat bed z = −H), rows padded like the state; empty
    /// while the bed is flat.
    pub(super) bed: Vec<T>,
    /// External pressure (Pa) during the current step, rows padded like the state; empty until the
    /// first deposit.
    pub(super) press: Vec<T>,
    pub(super) scratch: Vec<Scratch<T>>,
}

/// The fields in the precision chosen at construction.
#[derive(Debug, Clone)]
pub(super) enum State {
    F32(Fields<f32>),
    F64(Fields<f64>),
}

/// Runs `$e` with `$f` bound to the fields of either precision.
macro_rules! each {
    ($s:expr, $f:ident => $e:expr) => {
        match $s {
            $crate::sim::water::storage::State::F32($f) => $e,
            $crate::sim::water::storage::State::F64($f) => $e,
        }
    };
}

pub(super) use each;

impl<T: Real> Fields<T> {
    /// Water at rest at depth `h`, every flow 0.
    pub(super) fn new(co: &Coeffs, h: f64) -> Self {
        let mut cur = vec![T::ZERO; co.ny * co.stride()];
        for row in cur.chunks_exact_mut(co.stride()) {
            row[1..=co.nx].fill(T::of(h));
        }
        Self {
            cur,
            bed: Vec::new(),
            press: Vec::new(),
            scratch: Vec::new(),
        }
    }

    pub(super) fn get(&self, i: usize) -> f64 {
        self.cur[i].get()
    }

    pub(super) fn set(&mut self, i: usize, v: f64) {
        self.cur[i] = T::of(v);
    }

    /// Bed + H at padded index `i`, if a bed is stored.
    pub(super) fn bed_at(&self, i: usize) -> Option<f64> {
        self.bed.get(i).map(|b| b.get())
    }

    /// η of column (ix, iy) inside the grid: bed + depth − the rest depth `h`, in f64.
    #[inline]
    pub(super) fn eta_at(&self, co: &Coeffs, h: f64, ix: usize, iy: usize) -> f64 {
        let d = self.cur[co.at(ix, iy, 0)].get();
        match self.bed_at(iy * co.w() + 1 + ix) {
            Some(b) => (d + b) - h,
            None => d - h,
        }
    }

    pub(super) fn set_bed(&mut self, len: usize, i: usize, v: f64) {
        if self.bed.is_empty() {
            self.bed = vec![T::ZERO; len];
        }
        self.bed[i] = T::of(v);
    }

    pub(super) fn set_press(&mut self, len: usize, i: usize, v: f64) {
        if self.press.is_empty() {
            self.press = vec![T::ZERO; len];
        }
        self.press[i] = T::of(v);
    }

    /// η of every column, row-major, as f32 (the surface in f64, then rounded once).
    pub(super) fn eta_f32(&self, co: &Coeffs, h: f64, out: &mut Vec<f32>) {
        let nx = co.nx;
        out.clear();
        out.reserve(nx * co.ny);
        for (iy, row) in self.cur.chunks_exact(co.stride()).enumerate() {
            let d = &row[1..=nx];
            let at = iy * co.w() + 1;
            match self.bed.get(at..at + nx) {
                Some(b) => out.extend(
                    d.iter()
                        .zip(b)
                        .map(|(&d, &b)| ((d.get() + b.get()) - h) as f32),
                ),
                None => out.extend(d.iter().map(|&d| (d.get() - h) as f32)),
            }
        }
    }

    /// Σ depth over the columns, in f64, Neumaier-compensated.
    pub(super) fn depth_sum(&self, co: &Coeffs) -> f64 {
        let mut sum = Neumaier::default();
        for row in self.cur.chunks_exact(co.stride()) {
            for &d in &row[1..=co.nx] {
                sum.add(d.get());
            }
        }
        sum.value()
    }

    pub(super) fn min_depth(&self, co: &Coeffs) -> f64 {
        let mut m = f64::INFINITY;
        for row in self.cur.chunks_exact(co.stride()) {
            for &d in &row[1..=co.nx] {
                let d = d.get();
                if d.is_nan() {
                    return f64::NAN;
                }
                m = m.min(d);
            }
        }
        m
    }

    pub(super) fn clear_flows(&mut self, co: &Coeffs) {
        let w = co.w();
        for row in self.cur.chunks_exact_mut(co.stride()) {
            row[w..].fill(T::ZERO);
        }
    }
}

impl WaterGrid {
    /// Sets the water depth of column (ix, iy) (m, clamped to ≥ 0) and makes the whole grid
    /// active; a column outside the grid or a non-finite depth is ignored.
    pub fn set_depth(&mut self, ix: usize, iy: usize, depth: f64) {
        if ix < self.cfg.nx && iy < self.cfg.ny && depth.is_finite() {
            let i = self.at(ix, iy, 0);
            let d = depth.max(0.0);
            each!(&mut self.state, f => f.set(i, d));
            self.revision += 1;
            self.active = Active::All;
        }
    }

    /// Sets the surface elevation η (m) of column (ix, iy) by changing its depth (≥ 0).
    pub fn set_eta(&mut self, ix: usize, iy: usize, eta: f64) {
        let bed = self.bed(ix, iy);
        self.set_depth(ix, iy, eta - bed);
    }

    /// Adds `dv` m³ to column (ix, iy) (the depth stays ≥ 0); ignored outside the grid.
    pub fn add_volume(&mut self, ix: usize, iy: usize, dv: f64) {
        let a = self.cfg.cell * self.cfg.cell;
        let d = self.depth(ix, iy);
        self.set_depth(ix, iy, d + dv / a);
    }

    /// Sets the bed elevation z (m) of column (ix, iy) (the flat bed is z = −H); the depth is kept.
    /// Ignored outside the grid or if not finite.
    pub fn set_bed(&mut self, ix: usize, iy: usize, z: f64) {
        if ix >= self.cfg.nx || iy >= self.cfg.ny || !z.is_finite() {
            return;
        }
        let w = self.co.w();
        let (len, v) = (self.cfg.ny * w, z + self.cfg.depth);
        each!(&mut self.state, f => f.set_bed(len, iy * w + 1 + ix, v));
        self.row_bed[iy] = true;
        self.revision += 1;
        self.active = Active::All;
    }

    /// Zeroes every flow (the water is then at rest, whatever its surface).
    pub fn clear_flows(&mut self) {
        each!(&mut self.state, f => f.clear_flows(&self.co));
    }

    /// Starts a travelling swell η = A·sin(k·(n·x)) (n = heading) over the whole grid, with the flows of
    /// the linear travelling wave Q = (gA_pipe/c)(e·n)·η at each pipe's midpoint, taken half a step
    /// back (flows live at half steps), so it travels instead of splitting into two standing halves.
    pub fn set_swell(&mut self, swell: &Swell) {
        if !(swell.wavelength.is_finite() && swell.wavelength > 0.0 && swell.amplitude.is_finite())
        {
            return;
        }
        let (nx, ny, l) = (self.cfg.nx, self.cfg.ny, self.cfg.cell);
        let [ox, oy] = self.cfg.origin;
        let k = 2.0 * std::f64::consts::PI / swell.wavelength;
        let (sn, cs) = swell.heading_deg.to_radians().sin_cos();
        let c = self.wave_speed();
        let omega = c * k;
        let amp = swell.amplitude;
        let eta = |x: f64, y: f64, t: f64| amp * (k * (cs * x + sn * y) - omega * t).sin();
        let t_half = -0.5 * self.dt;
        // Flow per unit η along each pipe: (gA/c)(e·n).
        let (ax, ad) = pipe_areas(&self.cfg);
        let g = self.cfg.gravity;
        let (fx, fd) = if c > 0.0 {
            (g * ax / c, g * ad / c)
        } else {
            (0.0, 0.0)
        };
        let r2 = std::f64::consts::FRAC_1_SQRT_2;
        let diag = self.cfg.diagonal_pipes;
        self.revision += 1;
        self.active = Active::All;
        let co = self.co;
        for iy in 0..ny {
            let yc = oy + (iy as f64 + 0.5) * l;
            for ix in 0..nx {
                let xc = ox + (ix as f64 + 0.5) * l;
                let bed = self.bed(ix, iy);
                let q = |f: usize| co.at(ix, iy, f);
                let mut put = |f: usize, v: f64| each!(&mut self.state, s => s.set(q(f), v));
                put(0, (eta(xc, yc, 0.0) - bed).max(0.0));
                if ix + 1 < nx {
                    put(1, fx * cs * eta(xc + 0.5 * l, yc, t_half));
                }
                if iy + 1 < ny {
                    put(2, fx * sn * eta(xc, yc + 0.5 * l, t_half));
                    if diag && ix + 1 < nx {
                        put(
                            3,
                            fd * r2 * (cs + sn) * eta(xc + 0.5 * l, yc + 0.5 * l, t_half),
                        );
                    }
                    if diag && ix > 0 {
                        put(
                            4,
                            fd * r2 * (sn - cs) * eta(xc - 0.5 * l, yc + 0.5 * l, t_half),
                        );
                    }
                }
            }
        }
    }
}

/// Neumaier's compensated sum.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Neumaier {
    pub(super) sum: f64,
    pub(super) c: f64,
}

impl Neumaier {
    pub(super) fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.c += (self.sum - t) + x;
        } else {
            self.c += (x - t) + self.sum;
        }
        self.sum = t;
    }
    pub(super) fn value(&self) -> f64 {
        self.sum + self.c
    }
}

/// Columns per segment of the row pipeline: the arrays one segment touches (≈ 20 of them) stay in
/// the L1 cache between the stages.
pub(super) const SEGMENT: usize = 128;

/// Buffers of one chunk: new flows and K for two rows, the limited flows of the row before the chunk,
/// copies of the old rows on either side, and the surfaces of rows with a bed. Flow and K rows are
/// padded by one entry on each side (flows 0, K 1) so that the neighbours at ix ± 1 need no branch.
/// Everything is held in the storage type, so a value the chunk keeps for itself equals the one its
/// neighbour stores.
#[derive(Debug, Clone, Default)]
pub(super) struct Scratch<T> {
    pub(super) w: usize,
    pub(super) np: usize,
    /// New flows before the limiter: [slot 0..2][pipe 0..np][w].
    pub(super) qn: Vec<T>,
    /// Limited flows of the row before the chunk: [pipe 0..np][w].
    pub(super) qf: Vec<T>,
    /// Old row blocks just before and just after the chunk (rows r0 − 2, r0 − 1 and r1, r1 + 1).
    pub(super) lo: Vec<T>,
    pub(super) hi: Vec<T>,
    /// [slot 0..2][w]
    pub(super) k: Vec<T>,
    /// Surfaces (depth + bed) of rows j and j + 1 where a bed is set.
    pub(super) h0: Vec<T>,
    pub(super) h1: Vec<T>,
}

impl<T: Num> Scratch<T> {
    pub(super) fn ensure(&mut self, nx: usize, np: usize) {
        let w = nx + 2;
        let stride = (np + 1) * w;
        self.lo.resize(2 * stride, T::ZERO);
        self.hi.resize(2 * stride, T::ZERO);
        if self.w != w || self.np != np {
            self.w = w;
            self.np = np;
            self.qn = vec![T::ZERO; 2 * np * w];
            self.qf = vec![T::ZERO; np * w];
            self.k = vec![T::ONE; 2 * w];
            self.h0 = vec![T::ZERO; w];
            self.h1 = vec![T::ZERO; w];
        }
    }
}
