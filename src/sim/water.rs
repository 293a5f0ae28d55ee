//! Column-and-pipe water surface: the volume model of O'Brien & Hodgins, "Dynamic Simulation of
//! Splashing Fluids" (Computer Animation '95), as used by the paper (§3.3, eqs. 39–41), with the fixes the
//! literature found (design.md §5, `shared/reference/water.md`):
//!
//! * **Columns and pipes.** A square grid of `nx × ny` columns of cell size l and rest depth H. Each pipe
//!   carries one **signed** flow Q (m³/s), stored once by the column that owns it, so Q_{ij→kl} =
//!   −Q_{kl→ij} holds by construction (eq. 39). Four axis pipes, optionally the four diagonals; with
//!   diagonals the pipe areas are the isotropic A_axis = ⅔Hl, A_diag = (√2/6)Hl (equal areas would make
//!   waves 1.55× too fast); with axis pipes only A = Hl. Linearised, the grid is the shallow-water wave
//!   equation with c² = gH.
//! * **Flow law** (O'Brien eqs. 1.2–1.5 of water.md): Q ← e^{−γΔt}·Q + Δt·(gA/L)·(h_i − h_j) +
//!   Δt·(A/(ρL))·(E_i − E_j), with h = bed + depth the surface and E the external pressure of the stone
//!   (Newton's third law): E enters as a pressure head E/(ρg) on the surface. γ is the damping per second.
//! * **Symplectic update.** Flows first, then depths from the *new* flows: ΔV_i = Δt·Σ(inflow). The
//!   literal "average of old and new flows" update is unstable at every step (water.md §1).
//! * **Non-negative volume** (eq. 40). [`Limiter::MassConserving`]: Mei, Decaudin & Hu 2007 (eqs. 4–5),
//!   applied per *source* column to signed flows: each pipe's flow is scaled by K of its upwind column,
//!   K = min(1, V/(Δt·Σ outflow)). Volume is conserved to rounding and V ≥ 0 for any Δt.
//!   [`Limiter::PaperClamp`]: the paper's eq. 41 — a column whose new volume would be negative gets 0
//!   (creates water); kept as the studied alternative.
//! * **Walls.** Closed: no flow through a boundary face. With diagonal pipes, the diagonal pipes a mirror
//!   image across the wall would have add to the pipe along the wall, so a wall is an exact mirror (the
//!   Neumann boundary of the isotropic 9-point stencil): the method of images holds for both stencils.
//! * **Stability.** The grid runs on its own fixed clock Δt_w, chosen at construction at
//!   [`COURANT_SAFETY`] of the Courant limit r = cΔt/l ≤ 1/√2 (4 pipes) or √3/2 (8 pipes), capped at
//!   [`MAX_STEP`]. No accepted parameter can make it unstable: the linear scheme is stable below the
//!   limit whatever H, l and g are, K only scales flows down, the damping only removes momentum, and
//!   the external pressure is a bounded forcing.
//!
//! **Parallel and deterministic.** One step is a single fused sweep over rows with a two-row lag held
//! in small row buffers: new flows of row j → K of row j → limited flows of row j − 1 → depths of row
//! j − 1, the four stages taking turns on segments of 128 columns so that what one stage writes is
//! still in L1 when the next reads it. Every new value is computed from old values only (Jacobi). The sweep writes in place, a row
//! being overwritten only after its last read; rows are cut into chunks run by rayon, and each chunk
//! works from a copy of the two old rows on either side of it (the double buffer, reduced to the rows
//! that need one) and recomputes the flows of the two rows before it. The result therefore does not
//! depend on the chunking or on the number of threads, bit for bit. Every sum is formed in a fixed,
//! symmetric order (pairs of opposite pipes), so a symmetric state stays symmetric bit for bit.
//!
//! **Precision** ([`Precision`]). The depths, flows, bed and pressure are stored in f32 (the preset's
//! default) or f64 ([`WaterConfig::unit`], validation). The kernel is generic over the storage scalar
//! and does its arithmetic in the same type, the coefficients converted to it once per step. In f32
//! the inner loops run four columns per SSE2 instruction: measured 3.5× faster than f64 arithmetic on
//! f32 storage, which was no more conservative (nor was a depth update alone in f64, 30 % slower):
//! what drifts is the rounding of each stored depth to f32, half an ulp per changed column and step,
//! not the sums. Every flow is stored once and read by both columns it joins, so the fluxes still
//! telescope: f64 conserves volume to ~1e-15 relative, f32 to ~1e-8–3e-7 over 10 000 steps with
//! splashes and dry cells (tests/water.rs, T2 in f32). Every reading (η, depth, flow, volume) is
//! returned in f64; [`WaterGrid::volume`] sums in f64, compensated. Determinism for any chunking and
//! mirror symmetry hold bit for bit in both precisions (the chunks' buffers hold the storage type).
//!
//! **Memory traffic.** Per column and step the sweep reads the depth and the 2 or 4 pipe flows once
//! and writes them back once: 2·(1 + pipes)·size ([`WaterGrid::bytes_per_column_step`]): 24 B (4 pipes)
//! or 40 B (8 pipes) in f32, 48 B or 80 B in f64, with no write-allocate (the lines written were just
//! read). water.md §6.2's fused bound of 28 B/column in f32 also reads a bed; on the flat bed none is
//! stored (rows with a bed add one read of it). Row blocks hold each field padded by one zero at both
//! ends, so the inner loops are plain slices without edge branches and vectorise.
//!
//! Units are SI throughout: metres, seconds, m³/s, pascals, newton-seconds.

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

use rayon::prelude::*;

use crate::sim::params::{Limiter, ParamError, Precision, Swell, WaterParams, MAX_WATER_COLUMNS};

/// Fraction of the Courant limit at which the automatic water step runs: r = 0.7/√2 ≈ 0.495 with axis
/// pipes, r = 0.7·√3/2 ≈ 0.606 with diagonals. Below the limit by 30 %, and near the top, where the
/// leapfrog-like scheme is most accurate (its phase error shrinks as r grows towards the limit).
pub const COURANT_SAFETY: f64 = 0.7;
/// Longest automatic water step (s): one 60 Hz frame.
pub const MAX_STEP: f64 = 1.0 / 60.0;
/// Courant limit cΔt/l of the 4-pipe scheme, 1/√2.
pub const COURANT_LIMIT_4: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Courant limit cΔt/l of the isotropic 8-pipe scheme, √3/2.
pub const COURANT_LIMIT_8: f64 = 0.866_025_403_784_438_6;

/// Half-width (in cells) at or below which [`WaterGrid::deposit_impulse_box`] treats its square as a
/// point and deposits bilinearly.
pub const BOX_MIN_HALF: f64 = 1e-6;

/// Columns below which a step runs on the calling thread (rayon's overhead would dominate).
const PARALLEL_MIN_COLUMNS: usize = 16_384;
/// Fewest rows in an automatic chunk (each chunk recomputes two rows of flows before it).
const MIN_CHUNK_ROWS: usize = 16;

/// Everything that defines a grid, in raw numbers: what [`WaterGrid::new`] derives from a preset, and what
/// tests and studies set directly (any grid shape, an explicit step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaterConfig {
    /// Columns along x and y (at least 1 each).
    pub nx: usize,
    pub ny: usize,
    /// Cell size l (m).
    pub cell: f64,
    /// Rest depth H (m); sets the pipe areas and the wave speed √(gH).
    pub depth: f64,
    /// m/s² (0 allowed: no restoring force, no waves).
    pub gravity: f64,
    /// kg/m³
    pub density: f64,
    /// Flow damping γ (1/s): Q ← e^{−γΔt} Q each step.
    pub damping: f64,
    pub diagonal_pipes: bool,
    pub limiter: Limiter,
    /// World position of the grid's −x, −y corner (m).
    pub origin: [f64; 2],
    /// `None`: the automatic step under the Courant limit. `Some(dt)`: exactly this step, with **no**
    /// stability check (for stability studies; see [`WaterGrid::courant`]).
    pub dt: Option<f64>,
    /// Storage (and arithmetic) precision of the depths and flows.
    pub precision: Precision,
}

impl WaterConfig {
    /// A grid of `nx × ny` unit cells, H = 1, g = 9.81, ρ = 1000, no damping, 4 pipes, K limiter,
    /// origin (0, 0), automatic step, f64: the setting of water.md §5's tests.
    pub fn unit(nx: usize, ny: usize) -> Self {
        Self {
            nx,
            ny,
            cell: 1.0,
            depth: 1.0,
            gravity: 9.81,
            density: 1000.0,
            damping: 0.0,
            diagonal_pipes: false,
            limiter: Limiter::MassConserving,
            origin: [0.0, 0.0],
            dt: None,
            precision: Precision::F64,
        }
    }

    /// This configuration with the step set from a Courant number r = cΔt/l.
    pub fn with_courant(mut self, r: f64) -> Self {
        let c = (self.gravity * self.depth).sqrt();
        self.dt = Some(r * self.cell / c);
        self
    }

    fn validate(&self) -> Result<(), ParamError> {
        if self.nx == 0 || self.ny == 0 {
            return Err(ParamError::new(
                "water.cell",
                format!(
                    "expected at least one column each way, found {} × {}",
                    self.nx, self.ny
                ),
            ));
        }
        if self.nx.saturating_mul(self.ny) > MAX_WATER_COLUMNS {
            return Err(ParamError::new(
                "water.cell",
                format!(
                    "expected at most {MAX_WATER_COLUMNS} columns, found {} × {}",
                    self.nx, self.ny
                ),
            ));
        }
        positive("water.cell", self.cell)?;
        positive("water.depth", self.depth)?;
        positive("physics.water_density", self.density)?;
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(ParamError::new(
                "physics.gravity",
                format!("expected a finite number ≥ 0 m/s², found {}", self.gravity),
            ));
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(ParamError::new(
                "water.damping",
                format!("expected a finite number ≥ 0 1/s, found {}", self.damping),
            ));
        }
        if !(self.origin[0].is_finite() && self.origin[1].is_finite()) {
            return Err(ParamError::new(
                "water.origin",
                format!("expected finite coordinates, found {:?}", self.origin),
            ));
        }
        if let Some(dt) = self.dt {
            positive("water.dt", dt)?;
        }
        Ok(())
    }
}

fn positive(field: &str, v: f64) -> Result<(), ParamError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(
            field,
            format!("expected a finite positive number, found {v}"),
        ))
    }
}

/// Shape of the kernel and its coefficients in f64, as derived from the configuration.
#[derive(Debug, Clone, Copy)]
struct Coeffs {
    nx: usize,
    ny: usize,
    /// Fields per row block: depth + pipes (3 or 5).
    nf: usize,
    clamp: bool,
    /// e^{−γΔt}
    damp: f64,
    /// Δt·g·A/L of an axis and a diagonal pipe.
    gx: f64,
    gd: f64,
    /// Δt·A/(ρL) of an axis and a diagonal pipe (pressure).
    px: f64,
    pd: f64,
    /// Δt / l²: flow (m³/s) to depth change per step.
    beta: f64,
    /// Columns per segment of the row pipeline ([`SEGMENT`]; smaller in tests).
    seg: usize,
}

impl Coeffs {
    /// Padded length of one field of a row: one zero before and after the nx values.
    fn w(&self) -> usize {
        self.nx + 2
    }
    fn stride(&self) -> usize {
        self.nf * self.w()
    }
    fn at(&self, ix: usize, iy: usize, f: usize) -> usize {
        iy * self.stride() + f * self.w() + 1 + ix
    }
}

/// The kernel's arithmetic: f32 or f64.
trait Num:
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
trait Real: Num {
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

/// The coefficients of one step in the kernel's arithmetic type, converted once per step.
#[derive(Debug, Clone, Copy)]
struct Kc<C> {
    damp: C,
    gd: C,
    pd: C,
    beta: C,
    /// The axis pipes' Δt·gA/L and Δt·A/(ρL).
    gx: C,
    px: C,
    /// The same for the x pipes of a row with 0, 1 or 2 walls (they take the mirrored diagonals).
    gx_row: [C; 3],
    px_row: [C; 3],
    /// The same for the y pipes of the first and last column.
    gy_edge: C,
    py_edge: C,
}

impl<C: Num> Kc<C> {
    fn new(co: &Coeffs) -> Self {
        let row = |a: f64, ad: f64| [C::of(a), C::of(a + ad), C::of(a + 2.0 * ad)];
        let edge = |a: f64, ad: f64| C::of(if co.nx == 1 { a + 2.0 * ad } else { a + ad });
        Self {
            damp: C::of(co.damp),
            gd: C::of(co.gd),
            pd: C::of(co.pd),
            beta: C::of(co.beta),
            gx: C::of(co.gx),
            px: C::of(co.px),
            gx_row: row(co.gx, co.gd),
            px_row: row(co.px, co.pd),
            gy_edge: edge(co.gx, co.gd),
            py_edge: edge(co.px, co.pd),
        }
    }
    /// Walls of row j: 0, 1 or 2 (a one-row grid).
    fn walls(j: usize, ny: usize) -> usize {
        usize::from(j == 0) + usize::from(j + 1 == ny)
    }
}

/// Buffers of one chunk: new flows and K for two rows, the limited flows of the row before the chunk,
/// copies of the old rows on either side, and the surfaces of rows with a bed. Flow and K rows are
/// padded by one entry on each side (flows 0, K 1) so that the neighbours at ix ± 1 need no branch.
/// Everything is held in the storage type, so a value the chunk keeps for itself equals the one its
/// neighbour stores.
#[derive(Debug, Clone, Default)]
struct Scratch<T> {
    w: usize,
    np: usize,
    /// New flows before the limiter: [slot 0..2][pipe 0..np][w].
    qn: Vec<T>,
    /// Limited flows of the row before the chunk: [pipe 0..np][w].
    qf: Vec<T>,
    /// Old row blocks just before and just after the chunk (rows r0 − 2, r0 − 1 and r1, r1 + 1).
    lo: Vec<T>,
    hi: Vec<T>,
    /// [slot 0..2][w]
    k: Vec<T>,
    /// Surfaces (depth + bed) of rows j and j + 1 where a bed is set.
    h0: Vec<T>,
    h1: Vec<T>,
}

impl<T: Num> Scratch<T> {
    fn ensure(&mut self, nx: usize, np: usize) {
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

/// The stored fields of a grid in one precision.
#[derive(Debug, Clone)]
struct Fields<T> {
    /// Row blocks: [depth | qx | qy | (qd | qa)], each field `nx + 2` long (a zero pad at both ends).
    /// qx: (ix,iy)→(ix+1,iy); qy: (ix,iy)→(ix,iy+1); qd: (ix,iy)→(ix+1,iy+1); qa: (ix,iy)→(ix−1,iy+1).
    /// The wall pipes and the pads stay 0.
    cur: Vec<T>,
    /// Bed elevation + H per column (0 on the flat bed z = −H), rows padded like the state; empty
    /// while the bed is flat.
    bed: Vec<T>,
    /// External pressure (Pa) during the current step, rows padded like the state; empty until the
    /// first deposit.
    press: Vec<T>,
    scratch: Vec<Scratch<T>>,
}

/// The fields in the precision chosen at construction.
#[derive(Debug, Clone)]
enum State {
    F32(Fields<f32>),
    F64(Fields<f64>),
}

/// Runs `$e` with `$f` bound to the fields of either precision.
macro_rules! each {
    ($s:expr, $f:ident => $e:expr) => {
        match $s {
            State::F32($f) => $e,
            State::F64($f) => $e,
        }
    };
}

impl<T: Real> Fields<T> {
    /// Water at rest at depth `h`, every flow 0.
    fn new(co: &Coeffs, h: f64) -> Self {
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

    fn get(&self, i: usize) -> f64 {
        self.cur[i].get()
    }

    fn set(&mut self, i: usize, v: f64) {
        self.cur[i] = T::of(v);
    }

    /// Bed + H at padded index `i`, if a bed is stored.
    fn bed_at(&self, i: usize) -> Option<f64> {
        self.bed.get(i).map(|b| b.get())
    }

    fn set_bed(&mut self, len: usize, i: usize, v: f64) {
        if self.bed.is_empty() {
            self.bed = vec![T::ZERO; len];
        }
        self.bed[i] = T::of(v);
    }

    fn set_press(&mut self, len: usize, i: usize, v: f64) {
        if self.press.is_empty() {
            self.press = vec![T::ZERO; len];
        }
        self.press[i] = T::of(v);
    }

    /// η of every column, row-major, as f32 (the surface in f64, then rounded once).
    fn eta_f32(&self, co: &Coeffs, h: f64, out: &mut Vec<f32>) {
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
    fn depth_sum(&self, co: &Coeffs) -> f64 {
        let mut sum = Neumaier::default();
        for row in self.cur.chunks_exact(co.stride()) {
            for &d in &row[1..=co.nx] {
                sum.add(d.get());
            }
        }
        sum.value()
    }

    fn min_depth(&self, co: &Coeffs) -> f64 {
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

    fn clear_flows(&mut self, co: &Coeffs) {
        let w = co.w();
        for row in self.cur.chunks_exact_mut(co.stride()) {
            row[w..].fill(T::ZERO);
        }
    }

    /// One step over the chunks (see [`WaterGrid::step`]).
    fn step(
        &mut self,
        co: &Coeffs,
        chunks: &[(usize, usize)],
        row_bed: &[bool],
        row_press: &[bool],
        has_press: bool,
    ) {
        let kc = Kc::<T::Calc>::new(co);
        let stride = co.stride();
        if self.scratch.len() < chunks.len() {
            self.scratch.resize_with(chunks.len(), Scratch::default);
        }
        for s in self.scratch.iter_mut().take(chunks.len()) {
            s.ensure(co.nx, co.nf - 1);
        }
        // Each chunk keeps a copy of the old rows it reads beyond its ends (two each side): the
        // neighbouring chunks overwrite them in place.
        for (&(r0, r1), s) in chunks
            .iter()
            .zip(self.scratch.iter_mut())
            .skip(usize::from(chunks.len() <= 1))
        {
            let lo = r0.saturating_sub(2);
            s.lo[(lo + 2 - r0) * stride..].copy_from_slice(&self.cur[lo * stride..r0 * stride]);
            let hi = (r1 + 2).min(co.ny);
            s.hi[..(hi - r1) * stride].copy_from_slice(&self.cur[r1 * stride..hi * stride]);
        }
        let input = Input {
            bed: (!self.bed.is_empty()).then_some(self.bed.as_slice()),
            press: (has_press && !self.press.is_empty()).then_some(self.press.as_slice()),
            row_bed,
            row_press,
        };
        if chunks.len() <= 1 {
            if let Some(s) = self.scratch.first_mut() {
                run_chunk(co, &kc, &input, 0, co.ny, &mut self.cur, s);
            }
        } else {
            let mut parts: Vec<(usize, usize, &mut [T], &mut Scratch<T>)> =
                Vec::with_capacity(chunks.len());
            let mut rest: &mut [T] = &mut self.cur;
            for (&(r0, r1), s) in chunks.iter().zip(self.scratch.iter_mut()) {
                let (head, tail) = rest.split_at_mut((r1 - r0) * stride);
                parts.push((r0, r1, head, s));
                rest = tail;
            }
            parts
                .into_par_iter()
                .for_each(|(r0, r1, out, s)| run_chunk(co, &kc, &input, r0, r1, out, s));
        }
    }
}

/// The water surface: columns joined by pipes (see the module documentation).
#[derive(Debug, Clone)]
pub struct WaterGrid {
    cfg: WaterConfig,
    dt: f64,
    co: Coeffs,
    /// Depths, flows, bed and pressure in the grid's precision.
    state: State,
    /// Rows whose bed is set.
    row_bed: Vec<bool>,
    /// Impulses (N·s, down) deposited since the last step; empty until the first deposit.
    pending: Vec<f64>,
    touched: Vec<usize>,
    /// Every impulse (N·s, down) a column has accepted since the grid was built.
    received: f64,
    /// Rows holding external pressure during the current step.
    row_press: Vec<bool>,
    chunk_rows: Option<usize>,
    steps: u64,
    clock: f64,
}

impl WaterGrid {
    /// A grid for a preset's water: `origin` is the −x, −y corner (the caller resolves the default via
    /// [`WaterParams::origin_for`]), `gravity` and `density` come from the physics.
    pub fn new(
        params: &WaterParams,
        origin: [f64; 2],
        gravity: f64,
        density: f64,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        let nx = (params.size[0] / params.cell).ceil();
        let ny = (params.size[1] / params.cell).ceil();
        if !(nx >= 1.0 && ny >= 1.0 && nx * ny <= MAX_WATER_COLUMNS as f64) {
            return Err(ParamError::new(
                "water.cell",
                format!("expected 1 to {MAX_WATER_COLUMNS} columns, found {nx} × {ny}"),
            ));
        }
        let cfg = WaterConfig {
            nx: nx as usize,
            ny: ny as usize,
            cell: params.cell,
            depth: params.depth,
            gravity,
            density,
            damping: params.damping,
            diagonal_pipes: params.diagonal_pipes,
            limiter: params.limiter,
            origin,
            dt: None,
            precision: params.precision,
        };
        let mut grid = Self::with_config(cfg)?;
        if let Some(swell) = params.swell {
            grid.set_swell(&swell);
        }
        Ok(grid)
    }

    /// A grid from raw numbers (tests, studies): water at rest at depth H on a flat bed.
    pub fn with_config(cfg: WaterConfig) -> Result<Self, ParamError> {
        cfg.validate()?;
        let c = (cfg.gravity * cfg.depth).sqrt();
        let limit = if cfg.diagonal_pipes {
            COURANT_LIMIT_8
        } else {
            COURANT_LIMIT_4
        };
        let dt = match cfg.dt {
            Some(dt) => dt,
            None if c > 0.0 => (COURANT_SAFETY * limit * cfg.cell / c).min(MAX_STEP),
            None => MAX_STEP,
        };
        let (l, h, g, rho) = (cfg.cell, cfg.depth, cfg.gravity, cfg.density);
        // Pipe areas and lengths (water.md §2–§3).
        let (ax, ad) = if cfg.diagonal_pipes {
            (2.0 / 3.0 * h * l, std::f64::consts::SQRT_2 / 6.0 * h * l)
        } else {
            (h * l, 0.0)
        };
        let (lx, ld) = (l, std::f64::consts::SQRT_2 * l);
        let nf = if cfg.diagonal_pipes { 5 } else { 3 };
        let co = Coeffs {
            nx: cfg.nx,
            ny: cfg.ny,
            nf,
            clamp: cfg.limiter == Limiter::PaperClamp,
            damp: (-cfg.damping * dt).exp(),
            gx: dt * g * ax / lx,
            gd: dt * g * ad / ld,
            px: dt * ax / (rho * lx),
            pd: dt * ad / (rho * ld),
            beta: dt / (l * l),
            seg: SEGMENT,
        };
        let state = match cfg.precision {
            Precision::F32 => State::F32(Fields::new(&co, h)),
            Precision::F64 => State::F64(Fields::new(&co, h)),
        };
        Ok(Self {
            cfg,
            dt,
            co,
            state,
            row_bed: vec![false; cfg.ny],
            pending: Vec::new(),
            received: 0.0,
            touched: Vec::new(),
            row_press: vec![false; cfg.ny],
            chunk_rows: None,
            steps: 0,
            clock: 0.0,
        })
    }

    // --- geometry and clock -------------------------------------------------------------------

    pub fn nx(&self) -> usize {
        self.cfg.nx
    }
    pub fn ny(&self) -> usize {
        self.cfg.ny
    }
    /// Cell size l (m).
    pub fn cell(&self) -> f64 {
        self.cfg.cell
    }
    /// World position of the −x, −y corner (m).
    pub fn origin(&self) -> [f64; 2] {
        self.cfg.origin
    }
    /// Rest depth H (m).
    pub fn rest_depth(&self) -> f64 {
        self.cfg.depth
    }
    pub fn config(&self) -> &WaterConfig {
        &self.cfg
    }
    /// The water's own fixed step Δt_w (s).
    pub fn step_dt(&self) -> f64 {
        self.dt
    }
    /// Simulated time the water has reached (s): steps taken × Δt_w.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.dt
    }
    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// Wave speed c = √(gH) (m/s).
    pub fn wave_speed(&self) -> f64 {
        (self.cfg.gravity * self.cfg.depth).sqrt()
    }
    /// Courant number r = cΔt/l of the step in use.
    pub fn courant(&self) -> f64 {
        self.wave_speed() * self.dt / self.cfg.cell
    }
    /// Largest stable Courant number of the stencil: 1/√2 (4 pipes) or √3/2 (8 pipes).
    pub fn courant_limit(&self) -> f64 {
        if self.cfg.diagonal_pipes {
            COURANT_LIMIT_8
        } else {
            COURANT_LIMIT_4
        }
    }
    /// Storage precision of the depths and flows.
    pub fn precision(&self) -> Precision {
        self.cfg.precision
    }
    /// Memory traffic of one column update (B) on the flat bed: the depth and every pipe flow read
    /// once and written back once in the storage precision: 24 B (4 pipes) or 40 B (8 pipes) in f32,
    /// 48 B or 80 B in f64. The update is in place, so there is no write-allocate traffic on top.
    pub fn bytes_per_column_step(&self) -> usize {
        let size = match self.cfg.precision {
            Precision::F32 => std::mem::size_of::<f32>(),
            Precision::F64 => std::mem::size_of::<f64>(),
        };
        2 * self.co.nf * size
    }

    /// Adds `dt` (s) to the water's clock and runs every whole water step now due (0, 1 or many).
    /// Deterministic: the same calls give the same steps. A non-finite or negative `dt` is ignored.
    pub fn advance(&mut self, dt: f64) {
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        self.clock = self.clock.max(self.time()) + dt;
        // A tolerance of 1e-9 steps absorbs the rounding of a clock advanced in step-sized increments.
        let due = (self.clock / self.dt + 1e-9).floor();
        while (self.steps as f64) < due {
            self.step();
        }
    }

    /// Runs exactly one water step. Uses the current rayon pool (`pool.install(|| grid.step())` picks
    /// one); the result is bit-identical for any number of threads.
    pub fn step(&mut self) {
        self.apply_pending_pressure();
        let chunks = self.chunk_bounds();
        let has_press = !self.touched.is_empty();
        let (co, row_bed, row_press) = (&self.co, &self.row_bed, &self.row_press);
        each!(&mut self.state, f => f.step(co, &chunks, row_bed, row_press, has_press));
        self.clear_pressure();
        self.steps += 1;
    }

    /// Rows per chunk for the parallel step: `None` (default) chooses from the grid size and the pool's
    /// threads; `Some(n)` forces chunks of n ≥ 2 rows (determinism tests). Results never depend on it.
    pub fn set_chunk_rows(&mut self, rows: Option<usize>) {
        self.chunk_rows = rows.map(|r| r.max(2));
    }

    fn chunk_bounds(&self) -> Vec<(usize, usize)> {
        let ny = self.co.ny;
        let n = match self.chunk_rows {
            Some(r) => ny.div_ceil(r).min(ny / 2).max(1),
            None => {
                let threads = rayon::current_num_threads();
                if threads <= 1 || self.cfg.nx * ny < PARALLEL_MIN_COLUMNS {
                    1
                } else {
                    (2 * threads).min(ny / MIN_CHUNK_ROWS).max(1)
                }
            }
        };
        // Even split: every chunk has at least 2 rows when n ≤ ny / 2.
        (0..n).map(|c| (c * ny / n, (c + 1) * ny / n)).collect()
    }

    // --- coupling -----------------------------------------------------------------------------

    /// Impulse (N·s) pushing the water DOWN at world (x, y), spread bilinearly onto the 4 nearest
    /// column centres (the four parts sum to the impulse, to rounding; within half a cell of the edge
    /// the edge columns take it all); ignored outside the grid or if not finite. At the next water step
    /// the impulses gathered since the last one act as a constant external pressure E = J/(Δt_w·l²)
    /// on their columns for that step: the total force on the water is ΣJ/Δt_w (Newton's third law of
    /// the stone's contact forces, averaged over the water step).
    pub fn deposit_impulse(&mut self, x: f64, y: f64, impulse: f64) {
        if !impulse.is_finite() || !self.contains(x, y) {
            return;
        }
        let [(i0, i1, tx), (j0, j1, ty)] = self.bilinear(x, y);
        let a = impulse * (1.0 - ty);
        let b = impulse - a;
        let a1 = a * tx;
        let b1 = b * tx;
        self.deposit_impulse_cell(i0, j0, a - a1);
        self.deposit_impulse_cell(i1, j0, a1);
        self.deposit_impulse_cell(i0, j1, b - b1);
        self.deposit_impulse_cell(i1, j1, b1);
    }

    /// Impulse (N·s, down) spread uniformly over the axis-aligned square [x − half, x + half] ×
    /// [y − half, y + half] (a contact footprint): each column takes the impulse times the fraction of
    /// the square its cell covers, the product of the two 1D overlaps, so the parts sum to the impulse
    /// to rounding and the pressure does not depend on the cell size once the cells are smaller than
    /// the square. Parts beyond the grid's edge go to the edge columns, so nothing is lost while the
    /// centre is over the grid. Ignored if the centre is outside the grid, or the impulse or `half` is
    /// not finite; a square of `half` ≤ [`BOX_MIN_HALF`]·l (a point) is deposited bilinearly, as by
    /// [`Self::deposit_impulse`].
    pub fn deposit_impulse_box(&mut self, x: f64, y: f64, half: f64, impulse: f64) {
        if !impulse.is_finite() || !half.is_finite() || !self.contains(x, y) {
            return;
        }
        let l = self.cfg.cell;
        if half <= BOX_MIN_HALF * l {
            self.deposit_impulse(x, y, impulse);
            return;
        }
        let [ox, oy] = self.cfg.origin;
        let (i0, wx) = overlaps((x - ox) / l, half / l, self.cfg.nx);
        let (j0, wy) = overlaps((y - oy) / l, half / l, self.cfg.ny);
        for (j, &fy) in wy.iter().enumerate() {
            let row = impulse * fy;
            for (i, &fx) in wx.iter().enumerate() {
                self.deposit_impulse_cell(i0 + i, j0 + j, row * fx);
            }
        }
    }

    /// Impulse (N·s, down) on one column; ignored outside the grid or if not finite.
    pub fn deposit_impulse_cell(&mut self, ix: usize, iy: usize, impulse: f64) {
        if ix >= self.cfg.nx || iy >= self.cfg.ny || !impulse.is_finite() || impulse == 0.0 {
            return;
        }
        if self.pending.is_empty() {
            self.pending = vec![0.0; self.cfg.nx * self.cfg.ny];
        }
        let i = iy * self.cfg.nx + ix;
        if self.pending[i] == 0.0 {
            self.touched.push(i);
        }
        self.pending[i] += impulse;
        self.received += impulse;
    }

    /// Every impulse (N·s, down) the columns have accepted since the grid was built: with the stone's
    /// coupling, the water's side of Newton's third law.
    pub fn impulse_received(&self) -> f64 {
        self.received
    }

    /// Impulse (N·s) gathered for the next step, all columns together.
    pub fn pending_impulse(&self) -> f64 {
        let mut seen = self.touched.clone();
        seen.sort_unstable();
        seen.dedup();
        seen.iter().map(|&i| self.pending[i]).sum()
    }

    fn apply_pending_pressure(&mut self) {
        if self.touched.is_empty() {
            return;
        }
        let (nx, w) = (self.cfg.nx, self.co.w());
        let len = self.cfg.ny * w;
        let scale = 1.0 / (self.dt * self.cfg.cell * self.cfg.cell);
        // Two passes: a column may be listed twice if its sum returned to zero in between.
        for &i in &self.touched {
            let (iy, ix) = (i / nx, i % nx);
            let p = self.pending[i] * scale;
            each!(&mut self.state, f => f.set_press(len, iy * w + 1 + ix, p));
            self.row_press[iy] = true;
        }
        for &i in &self.touched {
            self.pending[i] = 0.0;
        }
    }

    fn clear_pressure(&mut self) {
        let (nx, w) = (self.cfg.nx, self.co.w());
        let len = self.cfg.ny * w;
        for &i in &self.touched {
            let (iy, ix) = (i / nx, i % nx);
            each!(&mut self.state, f => f.set_press(len, iy * w + 1 + ix, 0.0));
            self.row_press[iy] = false;
        }
        self.touched.clear();
    }

    // --- sampling -----------------------------------------------------------------------------

    /// Column indices and weights for bilinear sampling on column centres; points in the outer half
    /// cell take the edge column's value.
    fn bilinear(&self, x: f64, y: f64) -> [(usize, usize, f64); 2] {
        let l = self.cfg.cell;
        let axis = |p: f64, o: f64, n: usize| {
            let f = ((p - o) / l - 0.5).clamp(0.0, (n - 1) as f64);
            let i0 = (f.floor() as usize).min(n.saturating_sub(2));
            let t = (f - i0 as f64).clamp(0.0, 1.0);
            (i0, (i0 + 1).min(n - 1), t)
        };
        [
            axis(x, self.cfg.origin[0], self.cfg.nx),
            axis(y, self.cfg.origin[1], self.cfg.ny),
        ]
    }

    /// Whether world (x, y) lies over the grid.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let [ox, oy] = self.cfg.origin;
        let l = self.cfg.cell;
        x >= ox && y >= oy && x < ox + self.cfg.nx as f64 * l && y < oy + self.cfg.ny as f64 * l
    }

    /// Surface elevation η (m) above the rest level z = 0 at world (x, y), bilinear between column
    /// centres; 0 outside the grid.
    pub fn surface_height(&self, x: f64, y: f64) -> f64 {
        if !self.contains(x, y) {
            return 0.0;
        }
        let [(i0, i1, tx), (j0, j1, ty)] = self.bilinear(x, y);
        let a = self.eta(i0, j0) + tx * (self.eta(i1, j0) - self.eta(i0, j0));
        let b = self.eta(i0, j1) + tx * (self.eta(i1, j1) - self.eta(i0, j1));
        a + ty * (b - a)
    }

    /// η (m) of column (ix, iy): bed + depth, relative to the rest level; 0 outside the grid.
    pub fn eta(&self, ix: usize, iy: usize) -> f64 {
        if ix >= self.cfg.nx || iy >= self.cfg.ny {
            return 0.0;
        }
        let (i, j) = (self.at(ix, iy, 0), iy * self.co.w() + 1 + ix);
        let (d, b) = each!(&self.state, f => (f.get(i), f.bed_at(j)));
        match b {
            Some(b) => (d + b) - self.cfg.depth,
            None => d - self.cfg.depth,
        }
    }

    /// η of every column, row-major (iy * nx + ix), for rendering as a texture.
    pub fn eta_f32(&self, out: &mut Vec<f32>) {
        let (co, h) = (&self.co, self.cfg.depth);
        each!(&self.state, f => f.eta_f32(co, h, out));
    }

    /// Total water volume (m³): l²·Σ depth, Neumaier-compensated.
    pub fn volume(&self) -> f64 {
        let sum = each!(&self.state, f => f.depth_sum(&self.co));
        sum * self.cfg.cell * self.cfg.cell
    }

    /// Water depth (m) of column (ix, iy); 0 outside the grid.
    pub fn depth(&self, ix: usize, iy: usize) -> f64 {
        if ix >= self.cfg.nx || iy >= self.cfg.ny {
            return 0.0;
        }
        let i = self.at(ix, iy, 0);
        each!(&self.state, f => f.get(i))
    }

    /// Smallest depth of any column (m); NaN if any depth is NaN.
    pub fn min_depth(&self) -> f64 {
        each!(&self.state, f => f.min_depth(&self.co))
    }

    /// Largest |η| over the grid (m); NaN if any η is NaN.
    pub fn max_abs_eta(&self) -> f64 {
        let mut m = 0.0f64;
        for iy in 0..self.cfg.ny {
            for ix in 0..self.cfg.nx {
                let e = self.eta(ix, iy).abs();
                if e.is_nan() {
                    return f64::NAN;
                }
                m = m.max(e);
            }
        }
        m
    }

    /// Bed elevation z (m) of column (ix, iy): −H unless set by [`Self::set_bed`] (or outside the grid).
    pub fn bed(&self, ix: usize, iy: usize) -> f64 {
        let b = if ix < self.cfg.nx && iy < self.cfg.ny {
            let j = iy * self.co.w() + 1 + ix;
            each!(&self.state, f => f.bed_at(j)).unwrap_or(0.0)
        } else {
            0.0
        };
        b - self.cfg.depth
    }

    /// The flow (m³/s) of pipe `pipe` (0: +x, 1: +y, 2: +x+y, 3: −x+y) owned by column (ix, iy); 0 for a
    /// wall, a missing pipe or outside the grid.
    pub fn flow(&self, ix: usize, iy: usize, pipe: usize) -> f64 {
        if ix >= self.cfg.nx || iy >= self.cfg.ny || pipe + 1 >= self.co.nf {
            return 0.0;
        }
        let i = self.at(ix, iy, pipe + 1);
        each!(&self.state, f => f.get(i))
    }

    /// Index of field `f` (0 depth, 1.. pipes) of column (ix, iy) in the state.
    fn at(&self, ix: usize, iy: usize, f: usize) -> usize {
        self.co.at(ix, iy, f)
    }

    // --- state setters (tests, studies, initial conditions) -----------------------------------

    /// Sets the depth (m, clamped to ≥ 0) of column (ix, iy); ignored outside the grid or if not finite.
    pub fn set_depth(&mut self, ix: usize, iy: usize, depth: f64) {
        if ix < self.cfg.nx && iy < self.cfg.ny && depth.is_finite() {
            let i = self.at(ix, iy, 0);
            let d = depth.max(0.0);
            each!(&mut self.state, f => f.set(i, d));
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
        // Flow per unit η along each pipe: (gA/c)(e·n); A_axis, A_diag as in `with_config`.
        let h = self.cfg.depth;
        let (ax, ad) = if self.cfg.diagonal_pipes {
            (2.0 / 3.0 * h * l, std::f64::consts::SQRT_2 / 6.0 * h * l)
        } else {
            (h * l, 0.0)
        };
        let g = self.cfg.gravity;
        let (fx, fd) = if c > 0.0 {
            (g * ax / c, g * ad / c)
        } else {
            (0.0, 0.0)
        };
        let r2 = std::f64::consts::FRAC_1_SQRT_2;
        let diag = self.cfg.diagonal_pipes;
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

/// 1D overlaps of the interval [c − h, c + h] (in cells from the grid's edge, c in [0, n)) with the
/// cells [i, i + 1) of a row of n, as fractions of the interval: the first cell index and the
/// fractions from it on. The first and last cells of the row extend to ∓∞, so what lies beyond the
/// edge goes to them. The cells' bounds are the clamped interval's, so the fractions telescope to 1.
fn overlaps(c: f64, h: f64, n: usize) -> (usize, Vec<f64>) {
    let (lo, hi) = (c - h, c + h);
    let last = n - 1;
    let i0 = (lo.floor().max(0.0) as usize).min(last);
    let i1 = ((hi.ceil().max(1.0) as usize) - 1).clamp(i0, last);
    let span = hi - lo;
    let bound = |i: usize| {
        if i == 0 {
            lo
        } else if i > last {
            hi
        } else {
            (i as f64).clamp(lo, hi)
        }
    };
    let w = (i0..=i1)
        .map(|i| (bound(i + 1) - bound(i)) / span)
        .collect();
    (i0, w)
}

/// Neumaier's compensated sum.
#[derive(Debug, Default, Clone, Copy)]
struct Neumaier {
    sum: f64,
    c: f64,
}

impl Neumaier {
    fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.c += (self.sum - t) + x;
        } else {
            self.c += (x - t) + self.sum;
        }
        self.sum = t;
    }
    fn value(&self) -> f64 {
        self.sum + self.c
    }
}

// ---------------------------------------------------------------------------------------------
// The kernel
// ---------------------------------------------------------------------------------------------

/// Read-only inputs of one step.
struct Input<'a, T> {
    bed: Option<&'a [T]>,
    press: Option<&'a [T]>,
    row_bed: &'a [bool],
    row_press: &'a [bool],
}

/// Columns per segment of the row pipeline: the arrays one segment touches (≈ 20 of them) stay in
/// the L1 cache between the stages.
const SEGMENT: usize = 128;

fn run_chunk<T: Real>(
    co: &Coeffs,
    kc: &Kc<T::Calc>,
    input: &Input<T>,
    r0: usize,
    r1: usize,
    own: &mut [T],
    s: &mut Scratch<T>,
) {
    if co.nf == 5 {
        chunk::<T, true>(co, kc, input, r0, r1, own, s);
    } else {
        chunk::<T, false>(co, kc, input, r0, r1, own, s);
    }
}

/// Old row block `j` as seen by the chunk [r0, r1) at row `at`: the copies of the two rows on either
/// side, or the chunk's own rows from `at` on (`tail`), which are not overwritten yet.
#[inline]
fn old_row<'a, T>(
    j: usize,
    (r0, r1, at, stride): (usize, usize, usize, usize),
    tail: &'a [T],
    lo: &'a [T],
    hi: &'a [T],
) -> &'a [T] {
    if j < r0 {
        let k = j + 2 - r0;
        &lo[k * stride..(k + 1) * stride]
    } else if j >= r1 {
        let k = j - r1;
        &hi[k * stride..(k + 1) * stride]
    } else {
        &tail[(j - at) * stride..(j - at + 1) * stride]
    }
}

/// One chunk of rows [r0, r1), updated in place in one fused sweep. For each row j, starting two rows
/// early, four stages: A(j) the new flows of row j's pipes (reads old rows j, j + 1); K(j) the limiter
/// of row j (needs A(j − 1), A(j)); F(j − 1) the limited flows of row j − 1 (needs K(j − 1), K(j)),
/// written over row j − 1's old flows (or, for the row before the chunk, into a buffer); D(j − 1) the
/// new depths of row j − 1 (needs F(j − 2), F(j − 1)). Within a row the stages run segment by
/// segment, F and D one column behind A and K (their only look-ahead), so a segment's data is still in
/// L1 when the next stage reads it. A row is overwritten only after the last read of its old values.
/// Row ny is virtual (K = 1). Two slots per buffer hold rows j − 1 and j; a slot not yet written holds
/// zero flows, which is what the rows before the grid carry.
fn chunk<T: Real, const DIAG: bool>(
    co: &Coeffs,
    kc: &Kc<T::Calc>,
    input: &Input<T>,
    r0: usize,
    r1: usize,
    own: &mut [T],
    s: &mut Scratch<T>,
) {
    let (nx, ny) = (co.nx, co.ny);
    let stride = co.stride();
    let w = co.w();
    let blk = (co.nf - 1) * w;
    let Scratch {
        qn,
        qf,
        k,
        h0,
        h1,
        lo,
        hi,
        ..
    } = s;
    qn.fill(T::ZERO);
    qf.fill(T::ZERO);
    k.fill(T::ONE);
    for j in r0.saturating_sub(2)..=r1 {
        let cur = j % 2;
        let real = j < ny;
        let limit = real && j + 1 >= r0 && !co.clamp;
        let finish = j >= r0 && j > 0; // F(j − 1) runs; D(j − 1) too if row j − 1 is the chunk's
        let mine = finish && j > r0;
        if !real {
            k[cur * w..(cur + 1) * w].fill(T::ONE);
        }
        // The chunk's rows before j (written) and from j on (still old).
        let at = j.clamp(r0, r1);
        let (head, tail) = own.split_at_mut((at - r0) * stride);
        let tail: &[T] = tail;
        let span = (r0, r1, at, stride);
        let jr = j.min(ny - 1);
        let ju = (j + 1).min(ny - 1);
        let (row, up) = if real {
            (
                old_row(jr, span, tail, lo, hi),
                old_row(ju, span, tail, lo, hi),
            )
        } else {
            (&[][..], &[][..])
        };
        // Surfaces of rows j and j + 1: the depths, plus the bed where one is set.
        let bed_rows = real && (input.row_bed[jr] || input.row_bed[ju]);
        if bed_rows {
            surface(h0, &row[..w], input.bed, jr * w);
            surface(h1, &up[..w], input.bed, ju * w);
        }
        let (ha, hb): (&[T], &[T]) = if bed_rows {
            (h0, h1)
        } else if real {
            (&row[..w], &up[..w])
        } else {
            (&[], &[])
        };
        let (qa, qb) = qn.split_at_mut(blk);
        let (qn_j, qn_prev): (&mut [T], &[T]) = if cur == 0 { (qa, qb) } else { (qb, qa) };
        let (ka, kb) = k.split_at_mut(w);
        let (k_j, k_prev): (&mut [T], &[T]) = if cur == 0 { (ka, kb) } else { (kb, ka) };
        // Where F(j − 1) and D(j − 1) write, and the limited flows of row j − 2 that D reads.
        let (d_out, f_out, before): (&mut [T], &mut [T], &[T]) = if mine {
            let n = head.len() / stride; // rows r0 .. j: row j − 1 is the last
            let (older, last) = head.split_at_mut((n - 1) * stride);
            let (d, f) = last.split_at_mut(w);
            let before: &[T] = if n >= 2 {
                &older[(n - 2) * stride + w..]
            } else {
                &qf[..]
            };
            (d, f, before)
        } else {
            (&mut [], &mut qf[..], &[])
        };
        let mut a = 1;
        loop {
            let b = (a + co.seg).min(nx + 1);
            if real {
                flows::<T, DIAG>(co, kc, input, j, a, b, row, ha, hb, qn_j);
                if limit {
                    limiter::<T, DIAG>(k_j, &row[..w], qn_j, qn_prev, w, kc.beta, a, b);
                }
            }
            // F and D lag one column behind: [a − 1, b − 1), and the last column at the end.
            let fb = if b == nx + 1 { nx + 1 } else { b - 1 };
            let fa = a.max(2) - 1;
            if finish && fa < fb {
                finalize::<T, DIAG>(f_out, qn_prev, k_prev, k_j, w, fa, fb);
                if mine {
                    depth::<T, DIAG>(d_out, f_out, before, w, kc.beta, co.clamp, fa, fb);
                }
            }
            if b == nx + 1 {
                break;
            }
            a = b;
        }
    }
}

/// A(j) on padded columns [a, b): the new, unlimited flows of row j's pipes into `qn` ([pipe][w]), from
/// the old flows of row j and the surfaces `h0`, `h1` of rows j and j + 1 (padded).
#[allow(clippy::too_many_arguments)]
fn flows<T: Real, const DIAG: bool>(
    co: &Coeffs,
    kc: &Kc<T::Calc>,
    input: &Input<T>,
    j: usize,
    a: usize,
    b: usize,
    row: &[T],
    h0: &[T],
    h1: &[T],
    qn: &mut [T],
) {
    let (nx, ny, w) = (co.nx, co.ny, co.w());
    let has_up = j + 1 < ny;
    let (qn_x, rest) = qn.split_at_mut(w);
    let (qn_y, rest) = rest.split_at_mut(w);
    let (qn_d, qn_a) = rest.split_at_mut(if DIAG { w } else { 0 });
    let old = |f: usize| &row[f * w..(f + 1) * w];
    let (gx, gd, damp) = (kc.gx, kc.gd, kc.damp);
    let walls = Kc::<T::Calc>::walls(j, ny);
    // Interior ranges: the x and +x+y pipes of the last column and the −x+y pipe of the first are walls.
    let bx = b.min(nx);
    let aa = a.max(2);
    if has_up {
        // One pass over every pipe of the segment (the wall pipes are computed, then zeroed).
        let gxr = kc.gx_row[walls];
        let n = b - a;
        let (q_x, q_y) = (&old(1)[a..b], &old(2)[a..b]);
        let (h, hr, hu) = (&h0[a..b], &h0[a + 1..b + 1], &h1[a..b]);
        if DIAG {
            let (q_d, q_a) = (&old(3)[a..b], &old(4)[a..b]);
            let (hur, hul) = (&h1[a + 1..b + 1], &h1[a - 1..b - 1]);
            let (fx, fy) = (&mut qn_x[a..b], &mut qn_y[a..b]);
            let (fd, fa) = (&mut qn_d[a..b], &mut qn_a[a..b]);
            for i in 0..n {
                let hi = h[i].up();
                fx[i] = T::down(damp * q_x[i].up() + gxr * (hi - hr[i].up()));
                fy[i] = T::down(damp * q_y[i].up() + gx * (hi - hu[i].up()));
                fd[i] = T::down(damp * q_d[i].up() + gd * (hi - hur[i].up()));
                fa[i] = T::down(damp * q_a[i].up() + gd * (hi - hul[i].up()));
            }
        } else {
            let (fx, fy) = (&mut qn_x[a..b], &mut qn_y[a..b]);
            for i in 0..n {
                let hi = h[i].up();
                fx[i] = T::down(damp * q_x[i].up() + gxr * (hi - hr[i].up()));
                fy[i] = T::down(damp * q_y[i].up() + gx * (hi - hu[i].up()));
            }
        }
        if b > nx {
            qn_x[nx] = T::ZERO;
        }
        let ge = kc.gy_edge;
        for e in edges(nx) {
            if a <= e && e < b {
                qn_y[e] = T::down(damp * old(2)[e].up() + ge * (h0[e].up() - h1[e].up()));
            }
        }
    } else {
        grad(qn_x, old(1), h0, h0, 1, damp, kc.gx_row[walls], a, bx);
        if b > nx {
            qn_x[nx] = T::ZERO;
        }
        qn_y[a..b].fill(T::ZERO);
        if DIAG {
            qn_d[a..b].fill(T::ZERO);
            qn_a[a..b].fill(T::ZERO);
        }
    }
    if DIAG && b > nx {
        qn_d[nx] = T::ZERO;
    }
    if DIAG && a <= 1 {
        qn_a[1] = T::ZERO;
    }
    // External pressure E: + Δt·(A/(ρL))·(E_i − E_j), on the rows that hold some.
    let Some(press) = input.press else {
        return;
    };
    let ju = if has_up { j + 1 } else { j };
    if !(input.row_press[j] || input.row_press[ju]) {
        return;
    }
    let p0 = &press[j * w..(j + 1) * w];
    let p1 = &press[ju * w..(ju + 1) * w];
    let (px, pd) = (kc.px, kc.pd);
    add_grad(qn_x, p0, p0, 1, kc.px_row[walls], a, bx);
    if has_up {
        add_grad(qn_y, p0, p1, 0, px, aa, bx);
        let pe = kc.py_edge;
        for e in edges(nx) {
            if a <= e && e < b {
                qn_y[e] = T::down(qn_y[e].up() + pe * (p0[e].up() - p1[e].up()));
            }
        }
        if DIAG {
            add_grad(qn_d, p0, p1, 1, pd, a, bx);
            add_grad(qn_a, p0, p1, -1, pd, aa, b);
        }
    }
}

/// The padded indices of the first and last column (one index when nx = 1).
fn edges(nx: usize) -> impl Iterator<Item = usize> {
    [1, nx].into_iter().take(if nx == 1 { 1 } else { 2 })
}

/// h = depth + bed on a padded row.
fn surface<T: Real>(h: &mut [T], d: &[T], bed: Option<&[T]>, at: usize) {
    let n = d.len();
    let h = &mut h[..n];
    match bed {
        Some(bed) => {
            let bed = &bed[at..at + n];
            for i in 0..n {
                h[i] = T::down(d[i].up() + bed[i].up());
            }
        }
        None => h.copy_from_slice(d),
    }
}

/// qn[p] = damp·q[p] + c·(h0[p] − h1[p + off]) for p in [a, b) (off = +1, 0 or −1 picks the pipe's
/// other end in row j (x: h1 = h0) or row j + 1).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn grad<T: Real>(
    qn: &mut [T],
    q: &[T],
    h0: &[T],
    h1: &[T],
    off: isize,
    damp: T::Calc,
    c: T::Calc,
    a: usize,
    b: usize,
) {
    if a >= b {
        return;
    }
    let n = b - a;
    let o = (a as isize + off) as usize;
    let (qn, q, h0, h1) = (&mut qn[a..b], &q[a..b], &h0[a..b], &h1[o..o + n]);
    for i in 0..n {
        qn[i] = T::down(damp * q[i].up() + c * (h0[i].up() - h1[i].up()));
    }
}

/// qn[p] += c·(p0[p] − p1[p + off]) for p in [a, b): the pressure term, same pipes as [`grad`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn add_grad<T: Real>(qn: &mut [T], p0: &[T], p1: &[T], off: isize, c: T::Calc, a: usize, b: usize) {
    if a >= b {
        return;
    }
    let n = b - a;
    let o = (a as isize + off) as usize;
    let (qn, p0, p1) = (&mut qn[a..b], &p0[a..b], &p1[o..o + n]);
    for i in 0..n {
        qn[i] = T::down(qn[i].up() + c * (p0[i].up() - p1[i].up()));
    }
}

/// max(x, 0) as a plain compare (vectorises to one max).
#[inline(always)]
fn pos<C: Num>(x: C) -> C {
    if x > C::ZERO {
        x
    } else {
        C::ZERO
    }
}

/// min(x, 0) as a plain compare.
#[inline(always)]
fn neg<C: Num>(x: C) -> C {
    if x < C::ZERO {
        x
    } else {
        C::ZERO
    }
}

/// K = min(1, cap/out), cap = max(depth, 0): never NaN (out > cap ≥ 0 before dividing).
#[inline(always)]
fn kfactor<C: Num>(depth: C, out: C) -> C {
    let cap = pos(depth);
    if out > cap {
        cap / out
    } else {
        C::ONE
    }
}

/// K(j) on padded columns [a, b): min(1, depth/(β·Σ outflow)) (Mei et al. 2007, eq. 4), from the new
/// flows of row j (`own`) and row j − 1 (`before`; zeros before the grid). Outflows are summed in pairs
/// of opposite pipes, so mirror images round alike.
#[allow(clippy::too_many_arguments)]
fn limiter<T: Real, const DIAG: bool>(
    k: &mut [T],
    d: &[T],
    own: &[T],
    before: &[T],
    w: usize,
    beta: T::Calc,
    a: usize,
    b: usize,
) {
    let n = b - a;
    let (k, d) = (&mut k[a..b], &d[a..b]);
    let x_own = &own[a..b];
    let x_left = &own[a - 1..b - 1];
    let y_own = &own[w + a..w + b];
    let y_below = &before[w + a..w + b];
    // Outflow of a column through the pipe pair (own, other end's): max(q, 0) + max(−q′, 0).
    let out = |q: T, q_in: T| pos(q.up()) + pos(-q_in.up());
    if DIAG {
        let d_own = &own[2 * w + a..2 * w + b];
        let a_own = &own[3 * w + a..3 * w + b];
        // The +x+y pipe into (p, j) is owned by (p − 1, j − 1), the −x+y pipe by (p + 1, j − 1).
        let d_below = &before[2 * w + a - 1..2 * w + b - 1];
        let a_below = &before[3 * w + a + 1..3 * w + b + 1];
        for i in 0..n {
            let ox = out(x_own[i], x_left[i]);
            let oy = out(y_own[i], y_below[i]);
            let od = out(d_own[i], d_below[i]);
            let oa = out(a_own[i], a_below[i]);
            k[i] = T::down(kfactor(d[i].up(), beta * ((ox + oy) + (od + oa))));
        }
    } else {
        for i in 0..n {
            let ox = out(x_own[i], x_left[i]);
            let oy = out(y_own[i], y_below[i]);
            k[i] = T::down(kfactor(d[i].up(), beta * (ox + oy)));
        }
    }
}

/// F(j) on padded columns [a, b): each pipe of row j scaled by K of its upwind column, the owner's
/// (`k_own`, row j) for a positive flow, the other end's (`k_own` at p + 1, or `k_up`, row j + 1) for a
/// negative one: max(q, 0)·K_owner + min(q, 0)·K_other, where one term is an exact zero, so this is
/// exactly q·K_upwind without a branch.
fn finalize<T: Real, const DIAG: bool>(
    qf: &mut [T],
    qn: &[T],
    k_own: &[T],
    k_up: &[T],
    w: usize,
    a: usize,
    b: usize,
) {
    let n = b - a;
    let scale = |q: T, k_owner: T, k_other: T| {
        let q = q.up();
        T::down(pos(q) * k_owner.up() + neg(q) * k_other.up())
    };
    let (kd, kr, ku) = (&k_own[a..b], &k_own[a + 1..b + 1], &k_up[a..b]);
    let (qx, qy) = (&qn[a..b], &qn[w + a..w + b]);
    let (fx, rest) = qf.split_at_mut(w);
    let (fy, rest) = rest.split_at_mut(w);
    let (fx, fy) = (&mut fx[a..b], &mut fy[a..b]);
    if DIAG {
        let (fd, fa) = rest.split_at_mut(w);
        let (fd, fa) = (&mut fd[a..b], &mut fa[a..b]);
        let (qd, qa) = (&qn[2 * w + a..2 * w + b], &qn[3 * w + a..3 * w + b]);
        let (kur, kul) = (&k_up[a + 1..b + 1], &k_up[a - 1..b - 1]);
        for i in 0..n {
            fx[i] = scale(qx[i], kd[i], kr[i]);
            fy[i] = scale(qy[i], kd[i], ku[i]);
            fd[i] = scale(qd[i], kd[i], kur[i]);
            fa[i] = scale(qa[i], kd[i], kul[i]);
        }
    } else {
        for i in 0..n {
            fx[i] = scale(qx[i], kd[i], kr[i]);
            fy[i] = scale(qy[i], kd[i], ku[i]);
        }
    }
}

/// D(j) on padded columns [a, b): depth + β·Σ(inflow − outflow) from the limited flows of row j
/// (`own`) and row j − 1 (`before`), pipes in opposite pairs; then the paper's eq. 41 clamp if asked.
#[allow(clippy::too_many_arguments)]
fn depth<T: Real, const DIAG: bool>(
    d: &mut [T],
    own: &[T],
    before: &[T],
    w: usize,
    beta: T::Calc,
    clamp: bool,
    a: usize,
    b: usize,
) {
    let n = b - a;
    let d = &mut d[a..b];
    let x_own = &own[a..b];
    let x_left = &own[a - 1..b - 1];
    let y_own = &own[w + a..w + b];
    let y_below = &before[w + a..w + b];
    let net = |q_in: T, q_out: T| q_in.up() - q_out.up();
    if DIAG {
        let d_own = &own[2 * w + a..2 * w + b];
        let a_own = &own[3 * w + a..3 * w + b];
        let d_below = &before[2 * w + a - 1..2 * w + b - 1];
        let a_below = &before[3 * w + a + 1..3 * w + b + 1];
        for i in 0..n {
            let sx = net(x_left[i], x_own[i]);
            let sy = net(y_below[i], y_own[i]);
            let sd = net(d_below[i], d_own[i]);
            let sa = net(a_below[i], a_own[i]);
            d[i] = T::down(d[i].up() + beta * ((sx + sy) + (sd + sa)));
        }
    } else {
        for i in 0..n {
            let sx = net(x_left[i], x_own[i]);
            let sy = net(y_below[i], y_own[i]);
            d[i] = T::down(d[i].up() + beta * (sx + sy));
        }
    }
    if clamp {
        for v in d.iter_mut() {
            *v = T::down(pos(v.up()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BOTH: [Precision; 2] = [Precision::F64, Precision::F32];

    fn grid(nx: usize, ny: usize, diag: bool, limiter: Limiter) -> WaterGrid {
        grid_in(nx, ny, diag, limiter, Precision::F64)
    }

    fn grid_in(nx: usize, ny: usize, diag: bool, limiter: Limiter, p: Precision) -> WaterGrid {
        let cfg = WaterConfig {
            diagonal_pipes: diag,
            limiter,
            damping: 0.2,
            precision: p,
            ..WaterConfig::unit(nx, ny)
        }
        .with_courant(0.6);
        WaterGrid::with_config(cfg).unwrap()
    }

    /// The whole stored state (pads included), as bit patterns.
    fn bits(w: &WaterGrid) -> Vec<u64> {
        each!(&w.state, f => f.cur.iter().map(|v| v.bits()).collect())
    }

    /// A scene that uses every path: bed and dry cells, pressure, a violent drop (K active).
    fn setup(w: &mut WaterGrid) {
        let (nx, ny) = (w.nx(), w.ny());
        for iy in 0..ny {
            for ix in nx.saturating_sub(3)..nx {
                w.set_bed(ix, iy, 0.4 * (ix + 3 - nx) as f64 - 0.6);
                let b = w.bed(ix, iy);
                w.set_depth(ix, iy, (-b).max(0.0));
            }
        }
        w.set_eta(nx / 3, ny / 2, 2.5);
    }

    fn scene(w: &mut WaterGrid, steps: usize) {
        setup(w);
        run(w, steps);
    }

    fn run(w: &mut WaterGrid, steps: usize) {
        let (nx, ny) = (w.nx(), w.ny());
        for s in 0..steps {
            let f = s as f64 / steps as f64;
            w.deposit_impulse(f * nx as f64, (1.0 - f) * ny as f64, 3e4);
            w.deposit_impulse_cell(1, ny - 1, 1e4);
            w.step();
        }
    }

    /// The segmented row pipeline gives the same bits for any segment length.
    #[test]
    fn any_segment_length_gives_the_same_result() {
        for (diag, p) in [false, true].into_iter().flat_map(|d| BOTH.map(|p| (d, p))) {
            for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
                let mut reference = grid_in(23, 9, diag, limiter, p);
                scene(&mut reference, 60);
                for seg in [1, 2, 3, 7, 22, 23] {
                    let mut w = grid_in(23, 9, diag, limiter, p);
                    w.co.seg = seg;
                    w.set_chunk_rows(Some(3));
                    scene(&mut w, 60);
                    assert_eq!(
                        bits(&w),
                        bits(&reference),
                        "diag {diag} {limiter:?} {p:?} seg {seg}"
                    );
                }
            }
        }
    }

    /// The chunked in-place sweep gives the serial result bit for bit, for every chunking (each chunk
    /// recomputes its halo from copies of the old neighbouring rows).
    #[test]
    fn any_chunking_gives_the_serial_result() {
        for (diag, p) in [false, true].into_iter().flat_map(|d| BOTH.map(|p| (d, p))) {
            for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
                for (nx, ny) in [(9, 11), (1, 7), (6, 2)] {
                    let mut serial = grid_in(nx, ny, diag, limiter, p);
                    serial.set_chunk_rows(Some(usize::MAX));
                    scene(&mut serial, 60);
                    for rows in [2, 3, 4, 5] {
                        let mut w = grid_in(nx, ny, diag, limiter, p);
                        w.set_chunk_rows(Some(rows));
                        scene(&mut w, 60);
                        assert_eq!(
                            bits(&w),
                            bits(&serial),
                            "diag {diag} {limiter:?} {p:?} {nx}×{ny} rows {rows}"
                        );
                    }
                }
            }
        }
    }

    /// The scene is not trivial: the water moved and the limiter dried a column. Volume is kept to
    /// the rounding of the stored depths: ~ulp·√(steps) relative (1e-13 in f64, 1e-6 in f32).
    #[test]
    fn scene_exercises_the_limiter() {
        for (p, tol, dry) in [(Precision::F64, 1e-13, 1e-9), (Precision::F32, 1e-6, 1e-6)] {
            let mut w = grid_in(9, 11, true, Limiter::MassConserving, p);
            setup(&mut w);
            let v0 = w.volume();
            run(&mut w, 60);
            assert!(w.max_abs_eta() > 0.1);
            let dv = ((w.volume() - v0) / v0).abs();
            assert!(dv < tol, "{p:?}: ΔV/V {dv}");
            assert!(w.min_depth() < dry);
        }
    }

    /// f32 storage reports its own traffic; readings are f64 either way.
    #[test]
    fn bytes_per_column_follow_precision_and_pipes() {
        for (diag, p, bytes) in [
            (false, Precision::F32, 24),
            (true, Precision::F32, 40),
            (false, Precision::F64, 48),
            (true, Precision::F64, 80),
        ] {
            let w = grid_in(4, 4, diag, Limiter::MassConserving, p);
            assert_eq!(w.bytes_per_column_step(), bytes);
            assert_eq!(w.precision(), p);
        }
        let mut w = grid_in(4, 4, false, Limiter::MassConserving, Precision::F32);
        w.set_depth(1, 1, 0.1);
        assert_eq!(w.depth(1, 1), f64::from(0.1f32));
    }

    #[test]
    fn chunk_bounds_cover_the_rows() {
        let mut w = grid(4, 37, false, Limiter::MassConserving);
        for rows in [2, 3, 10, 36, 100] {
            w.set_chunk_rows(Some(rows));
            let b = w.chunk_bounds();
            assert_eq!(b[0].0, 0);
            assert_eq!(b[b.len() - 1].1, 37);
            for p in b.windows(2) {
                assert_eq!(p[0].1, p[1].0);
            }
            assert!(b.iter().all(|&(a, z)| z - a >= 2));
        }
    }

    /// K never divides by zero: dry, negative-by-rounding and idle columns give finite factors.
    #[test]
    fn k_factor_is_always_finite() {
        for (d, o) in [
            (0.0, 0.0),
            (0.0, 1.0),
            (-1e-20, 0.0),
            (-1e-20, 1.0),
            (1.0, 0.0),
            (1.0, 4.0),
        ] {
            let k: f64 = kfactor(d, o);
            assert!(k.is_finite() && (0.0..=1.0).contains(&k), "{d} {o} {k}");
        }
        assert_eq!(kfactor(1.0f64, 4.0), 0.25);
        assert_eq!(kfactor(0.0f32, 0.0), 1.0);
    }

    /// Sampling at a column centre gives that column's η; between centres it is linear.
    #[test]
    fn surface_height_is_bilinear_on_column_centres() {
        let mut w = grid(5, 4, false, Limiter::MassConserving);
        w.cfg.origin = [10.0, -2.0];
        w.set_eta(2, 1, 0.4);
        assert!((w.surface_height(12.5, -0.5) - 0.4).abs() < 1e-15);
        assert!((w.surface_height(13.0, -0.5) - 0.2).abs() < 1e-15);
        assert!((w.surface_height(12.5, -0.25) - 0.3).abs() < 1e-15);
        assert_eq!(w.surface_height(9.9, 0.0), 0.0);
        assert_eq!(w.surface_height(15.0, 0.0), 0.0);
        // The outer half cell takes the edge column.
        w.set_eta(0, 0, 0.1);
        assert!((w.surface_height(10.1, -1.9) - 0.1).abs() < 1e-15);
    }

    /// No gravity: no waves and no restoring force, but pressure still pushes water; nothing is NaN.
    #[test]
    fn zero_gravity_stays_finite() {
        let cfg = WaterConfig {
            gravity: 0.0,
            ..WaterConfig::unit(8, 8)
        };
        let mut w = WaterGrid::with_config(cfg).unwrap();
        assert_eq!(w.step_dt(), MAX_STEP);
        let v0 = w.volume();
        for _ in 0..50 {
            w.deposit_impulse(4.0, 4.0, 1e5);
            w.step();
        }
        assert!(w.max_abs_eta().is_finite() && w.max_abs_eta() > 0.0);
        assert!(w.min_depth() >= -1e-15);
        assert!(((w.volume() - v0) / v0).abs() < 1e-13);
    }

    /// The swell starts as the preset says: η = A sin(k n·x) at the column centres.
    #[test]
    fn swell_sets_the_initial_surface() {
        let mut w = grid(40, 6, true, Limiter::MassConserving);
        w.set_swell(&Swell {
            amplitude: 0.1,
            wavelength: 10.0,
            heading_deg: 0.0,
        });
        let k = 2.0 * std::f64::consts::PI / 10.0;
        for ix in 0..40 {
            let e = 0.1 * (k * (ix as f64 + 0.5)).sin();
            assert!((w.eta(ix, 3) - e).abs() < 1e-15);
        }
        assert!(w.flow(5, 3, 0) != 0.0 && w.flow(5, 3, 1) == 0.0);
    }

    // --- the box footprint ---------------------------------------------------------------------

    /// The deposited impulse of every column, row-major.
    fn pending_field(w: &WaterGrid) -> Vec<f64> {
        if w.pending.is_empty() {
            vec![0.0; w.nx() * w.ny()]
        } else {
            w.pending.clone()
        }
    }

    fn box_grid(n: usize, cell: f64, origin: [f64; 2]) -> WaterGrid {
        WaterGrid::with_config(WaterConfig {
            cell,
            origin,
            ..WaterConfig::unit(n, n)
        })
        .unwrap()
    }

    /// The parts sum to the impulse (to rounding), inside, across an edge and in a corner.
    #[test]
    fn box_deposit_keeps_the_impulse() {
        for (x, y, half) in [
            (3.37, 4.81, 0.9),
            (0.2, 4.0, 1.3),
            (7.9, 0.1, 2.2),
            (5.0, 5.0, 40.0),
            (1.23, 6.54, 0.3),
        ] {
            let mut w = box_grid(8, 1.0, [0.0, 0.0]);
            w.deposit_impulse_box(x, y, half, 7.5);
            let sum: f64 = pending_field(&w).iter().sum();
            assert!((sum / 7.5 - 1.0).abs() < 1e-14, "({x}, {y}, {half}): {sum}");
            assert!(pending_field(&w).iter().all(|&p| p >= 0.0));
        }
    }

    /// A square that is exactly one cell gives that cell everything; one covering four cells' quarters
    /// gives each a quarter; a point-sized square falls back to the bilinear deposit.
    #[test]
    fn box_deposit_on_cells() {
        let mut w = box_grid(6, 0.5, [-1.0, 2.0]);
        w.deposit_impulse_box(-1.0 + 2.25, 2.0 + 1.75, 0.25, 3.0);
        let p = pending_field(&w);
        assert_eq!(p[3 * 6 + 4], 3.0);
        assert_eq!(p.iter().filter(|&&v| v != 0.0).count(), 1);

        let mut w = box_grid(6, 0.5, [-1.0, 2.0]);
        w.deposit_impulse_box(-1.0 + 1.0, 2.0 + 1.5, 0.25, 2.0);
        let p = pending_field(&w);
        for (ix, iy) in [(1, 2), (2, 2), (1, 3), (2, 3)] {
            assert_eq!(p[iy * 6 + ix], 0.5, "({ix}, {iy})");
        }
        assert_eq!(p.iter().filter(|&&v| v != 0.0).count(), 4);

        for half in [0.0, -1.0, 1e-9] {
            let mut a = box_grid(6, 0.5, [-1.0, 2.0]);
            let mut b = box_grid(6, 0.5, [-1.0, 2.0]);
            a.deposit_impulse_box(0.13, 3.31, half, 2.0);
            b.deposit_impulse(0.13, 3.31, 2.0);
            assert_eq!(pending_field(&a), pending_field(&b), "half {half}");
        }
        // Outside the grid or not finite: nothing.
        let mut w = box_grid(6, 0.5, [-1.0, 2.0]);
        w.deposit_impulse_box(-1.01, 3.0, 0.5, 1.0);
        w.deposit_impulse_box(0.0, 3.0, f64::NAN, 1.0);
        w.deposit_impulse_box(0.0, 3.0, f64::INFINITY, 1.0);
        w.deposit_impulse_box(0.0, f64::NAN, 0.5, 1.0);
        w.deposit_impulse_box(0.0, 3.0, 0.5, f64::INFINITY);
        assert_eq!(w.pending_impulse(), 0.0);
    }

    /// A square centred on a symmetric grid gives a deposit with the square's 8 symmetries.
    #[test]
    fn box_deposit_is_symmetric() {
        let n = 9;
        let mut w = box_grid(n, 0.1, [0.0, 0.0]);
        w.deposit_impulse_box(0.45, 0.45, 0.27, 1.0);
        let p = pending_field(&w);
        let at = |ix: usize, iy: usize| p[iy * n + ix];
        for iy in 0..n {
            for ix in 0..n {
                let v = at(ix, iy);
                for m in [
                    at(iy, ix),
                    at(n - 1 - ix, iy),
                    at(ix, n - 1 - iy),
                    at(n - 1 - iy, n - 1 - ix),
                ] {
                    assert!((v - m).abs() <= 1e-15, "({ix}, {iy}): {v} vs {m}");
                }
            }
        }
        // Cells inside the square take the impulse × their share of its area, l²/(2·half)².
        assert!((at(4, 4) - 0.01 / (0.54 * 0.54)).abs() < 1e-14);
    }

    /// Convergence: once the cells are smaller than the square, halving them does not change the
    /// pressure footprint: the four fine columns of each coarse column take exactly its impulse (the
    /// overlap areas add up), also where the square crosses the edge.
    #[test]
    fn box_footprint_does_not_change_when_the_cell_is_halved() {
        for (x, y, half) in [(0.937, 1.012, 0.31), (0.05, 1.71, 0.26), (1.0, 1.0, 0.2)] {
            let mut coarse = box_grid(20, 0.1, [0.0, 0.0]);
            let mut fine = box_grid(40, 0.05, [0.0, 0.0]);
            coarse.deposit_impulse_box(x, y, half, 1.0);
            fine.deposit_impulse_box(x, y, half, 1.0);
            let (c, f) = (pending_field(&coarse), pending_field(&fine));
            for iy in 0..20 {
                for ix in 0..20 {
                    let sum: f64 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                        .iter()
                        .map(|&(dx, dy)| f[(2 * iy + dy) * 40 + 2 * ix + dx])
                        .sum();
                    let want = c[iy * 20 + ix];
                    assert!(
                        (sum - want).abs() < 1e-14,
                        "({x}, {y}) cell ({ix}, {iy}): fine {sum} coarse {want}"
                    );
                }
            }
        }
    }
}
