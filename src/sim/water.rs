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
//! **Memory traffic.** f64 storage; per column and step the sweep reads the depth and the 2 or 4 pipe
//! flows once and writes them back once: 48 B (4 pipes) or 80 B (8 pipes) of memory traffic, with no
//! write-allocate (the lines written were just read) ([`WaterGrid::bytes_per_column_step`]). Row
//! blocks hold each field padded by one zero at both ends, so the inner loops are plain slices without
//! edge branches and vectorise.
//!
//! Units are SI throughout: metres, seconds, m³/s, pascals, newton-seconds.

use rayon::prelude::*;

use crate::sim::params::{Limiter, ParamError, Swell, WaterParams, MAX_WATER_COLUMNS};

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
}

impl WaterConfig {
    /// A grid of `nx × ny` unit cells, H = 1, g = 9.81, ρ = 1000, no damping, 4 pipes, K limiter,
    /// origin (0, 0), automatic step: the setting of water.md §5's tests.
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

/// Per-step coefficients of the kernel.
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
    /// Coefficient of the x pipes of row j: a wall row also takes the mirrored diagonals.
    fn row_edge(&self, a: f64, ad: f64, j: usize) -> f64 {
        let walls = usize::from(j == 0) + usize::from(j + 1 == self.ny);
        match walls {
            0 => a,
            1 => a + ad,
            _ => a + 2.0 * ad,
        }
    }
    /// Coefficient of the y pipes of the first and last column.
    fn col_edge(&self, a: f64, ad: f64) -> f64 {
        if self.nx == 1 {
            a + 2.0 * ad
        } else {
            a + ad
        }
    }
}

/// Buffers of one chunk: new flows and K for two rows, the limited flows of the row before the chunk,
/// copies of the old rows on either side, and the surfaces of rows with a bed. Flow and K rows are
/// padded by one entry on each side (flows 0, K 1) so that the neighbours at ix ± 1 need no branch.
#[derive(Debug, Clone, Default)]
struct Scratch {
    w: usize,
    np: usize,
    /// New flows before the limiter: [slot 0..2][pipe 0..np][w].
    qn: Vec<f64>,
    /// Limited flows of the row before the chunk: [pipe 0..np][w].
    qf: Vec<f64>,
    /// Old row blocks just before and just after the chunk (rows r0 − 2, r0 − 1 and r1, r1 + 1).
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// [slot 0..2][w]
    k: Vec<f64>,
    /// Surfaces (depth + bed) of rows j and j + 1 where a bed is set.
    h0: Vec<f64>,
    h1: Vec<f64>,
}

impl Scratch {
    fn ensure(&mut self, nx: usize, np: usize) {
        let w = nx + 2;
        let stride = (np + 1) * w;
        self.lo.resize(2 * stride, 0.0);
        self.hi.resize(2 * stride, 0.0);
        if self.w != w || self.np != np {
            self.w = w;
            self.np = np;
            self.qn = vec![0.0; 2 * np * w];
            self.qf = vec![0.0; np * w];
            self.k = vec![1.0; 2 * w];
            self.h0 = vec![0.0; w];
            self.h1 = vec![0.0; w];
        }
    }
}

/// The water surface: columns joined by pipes (see the module documentation).
#[derive(Debug, Clone)]
pub struct WaterGrid {
    cfg: WaterConfig,
    dt: f64,
    co: Coeffs,
    /// Row blocks: [depth | qx | qy | (qd | qa)], each field `nx + 2` long (a zero pad at both ends).
    /// qx: (ix,iy)→(ix+1,iy); qy: (ix,iy)→(ix,iy+1); qd: (ix,iy)→(ix+1,iy+1); qa: (ix,iy)→(ix−1,iy+1).
    /// The wall pipes and the pads stay 0.
    cur: Vec<f64>,
    /// Bed elevation + H per column (0 on the flat bed z = −H), rows padded like the state; empty
    /// while the bed is flat.
    bed: Vec<f64>,
    row_bed: Vec<bool>,
    /// Impulses (N·s, down) deposited since the last step; empty until the first deposit.
    pending: Vec<f64>,
    touched: Vec<usize>,
    /// External pressure (Pa) during the current step, rows padded like the state; empty until the
    /// first deposit.
    press: Vec<f64>,
    /// Rows holding external pressure during the current step.
    row_press: Vec<bool>,
    scratch: Vec<Scratch>,
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
        let mut cur = vec![0.0; cfg.ny * co.stride()];
        for row in cur.chunks_exact_mut(co.stride()) {
            row[1..=cfg.nx].fill(h);
        }
        Ok(Self {
            cfg,
            dt,
            co,
            cur,
            bed: Vec::new(),
            row_bed: vec![false; cfg.ny],
            pending: Vec::new(),
            touched: Vec::new(),
            press: Vec::new(),
            row_press: vec![false; cfg.ny],
            scratch: Vec::new(),
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
    /// Memory traffic of one column update (B): the depth and every pipe flow read once and written
    /// back once, in f64 (48 B with 4 pipes, 80 B with 8). The update is in place, so there is no
    /// write-allocate traffic on top.
    pub fn bytes_per_column_step(&self) -> usize {
        2 * self.co.nf * std::mem::size_of::<f64>()
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
        let co = self.co;
        let stride = co.stride();
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
            press: (!self.touched.is_empty() && !self.press.is_empty())
                .then_some(self.press.as_slice()),
            row_bed: &self.row_bed,
            row_press: &self.row_press,
        };
        if chunks.len() <= 1 {
            if let Some(s) = self.scratch.first_mut() {
                run_chunk(&co, &input, 0, co.ny, &mut self.cur, s);
            }
        } else {
            let mut parts: Vec<(usize, usize, &mut [f64], &mut Scratch)> =
                Vec::with_capacity(chunks.len());
            let mut rest: &mut [f64] = &mut self.cur;
            for (&(r0, r1), s) in chunks.iter().zip(self.scratch.iter_mut()) {
                let (head, tail) = rest.split_at_mut((r1 - r0) * stride);
                parts.push((r0, r1, head, s));
                rest = tail;
            }
            parts
                .into_par_iter()
                .for_each(|(r0, r1, out, s)| run_chunk(&co, &input, r0, r1, out, s));
        }
        self.clear_pressure();
        self.steps += 1;
    }

    /// Rows per chunk for the parallel step: `None` (default) chooses from the grid size and the pool's
    /// threads; `Some(n)` forces chunks of n ≥ 2 rows (determinism tests). Results never depend on it.
    pub fn set_chunk_rows(&mut self, rows: Option<usize>) {
        self.chunk_rows = rows.map(|r| r.max(2));
    }

    fn chunk_bounds(&mut self) -> Vec<(usize, usize)> {
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
        if self.scratch.len() < n {
            self.scratch.resize_with(n, Scratch::default);
        }
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
        if self.press.is_empty() {
            self.press = vec![0.0; self.cfg.ny * w];
        }
        let scale = 1.0 / (self.dt * self.cfg.cell * self.cfg.cell);
        // Two passes: a column may be listed twice if its sum returned to zero in between.
        for &i in &self.touched {
            let (iy, ix) = (i / nx, i % nx);
            self.press[iy * w + 1 + ix] = self.pending[i] * scale;
            self.row_press[iy] = true;
        }
        for &i in &self.touched {
            self.pending[i] = 0.0;
        }
    }

    fn clear_pressure(&mut self) {
        let (nx, w) = (self.cfg.nx, self.co.w());
        for &i in &self.touched {
            let (iy, ix) = (i / nx, i % nx);
            self.press[iy * w + 1 + ix] = 0.0;
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
        let d = self.cur[self.at(ix, iy, 0)];
        match self.bed.get(iy * self.co.w() + 1 + ix) {
            Some(&b) => (d + b) - self.cfg.depth,
            None => d - self.cfg.depth,
        }
    }

    /// η of every column, row-major (iy * nx + ix), for rendering as a texture.
    pub fn eta_f32(&self, out: &mut Vec<f32>) {
        let (nx, h) = (self.cfg.nx, self.cfg.depth);
        out.clear();
        out.reserve(nx * self.cfg.ny);
        for (iy, row) in self.cur.chunks_exact(self.co.stride()).enumerate() {
            let d = &row[1..=nx];
            let at = iy * self.co.w() + 1;
            match self.bed.get(at..at + nx) {
                Some(b) => out.extend(d.iter().zip(b).map(|(&d, &b)| ((d + b) - h) as f32)),
                None => out.extend(d.iter().map(|&d| (d - h) as f32)),
            }
        }
    }

    /// Total water volume (m³): l²·Σ depth, Neumaier-compensated.
    pub fn volume(&self) -> f64 {
        let nx = self.cfg.nx;
        let mut sum = Neumaier::default();
        for row in self.cur.chunks_exact(self.co.stride()) {
            for &d in &row[1..=nx] {
                sum.add(d);
            }
        }
        sum.value() * self.cfg.cell * self.cfg.cell
    }

    /// Water depth (m) of column (ix, iy); 0 outside the grid.
    pub fn depth(&self, ix: usize, iy: usize) -> f64 {
        if ix >= self.cfg.nx || iy >= self.cfg.ny {
            return 0.0;
        }
        self.cur[self.at(ix, iy, 0)]
    }

    /// Smallest depth of any column (m); NaN if any depth is NaN.
    pub fn min_depth(&self) -> f64 {
        let nx = self.cfg.nx;
        let mut m = f64::INFINITY;
        for row in self.cur.chunks_exact(self.co.stride()) {
            for &d in &row[1..=nx] {
                if d.is_nan() {
                    return f64::NAN;
                }
                m = m.min(d);
            }
        }
        m
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
            self.bed
                .get(iy * self.co.w() + 1 + ix)
                .copied()
                .unwrap_or(0.0)
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
        self.cur[self.at(ix, iy, pipe + 1)]
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
            self.cur[i] = depth.max(0.0);
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
        if self.bed.is_empty() {
            self.bed = vec![0.0; self.cfg.ny * w];
        }
        self.bed[iy * w + 1 + ix] = z + self.cfg.depth;
        self.row_bed[iy] = true;
    }

    /// Zeroes every flow (the water is then at rest, whatever its surface).
    pub fn clear_flows(&mut self) {
        let w = self.co.w();
        for row in self.cur.chunks_exact_mut(self.co.stride()) {
            row[w..].fill(0.0);
        }
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
                self.cur[q(0)] = (eta(xc, yc, 0.0) - bed).max(0.0);
                if ix + 1 < nx {
                    self.cur[q(1)] = fx * cs * eta(xc + 0.5 * l, yc, t_half);
                }
                if iy + 1 < ny {
                    self.cur[q(2)] = fx * sn * eta(xc, yc + 0.5 * l, t_half);
                    if diag && ix + 1 < nx {
                        self.cur[q(3)] =
                            fd * r2 * (cs + sn) * eta(xc + 0.5 * l, yc + 0.5 * l, t_half);
                    }
                    if diag && ix > 0 {
                        self.cur[q(4)] =
                            fd * r2 * (sn - cs) * eta(xc - 0.5 * l, yc + 0.5 * l, t_half);
                    }
                }
            }
        }
    }
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
struct Input<'a> {
    bed: Option<&'a [f64]>,
    press: Option<&'a [f64]>,
    row_bed: &'a [bool],
    row_press: &'a [bool],
}

/// Columns per segment of the row pipeline: the arrays one segment touches (≈ 20 of them) stay in
/// the L1 cache between the stages.
const SEGMENT: usize = 128;

fn run_chunk(co: &Coeffs, input: &Input, r0: usize, r1: usize, own: &mut [f64], s: &mut Scratch) {
    if co.nf == 5 {
        chunk::<true>(co, input, r0, r1, own, s);
    } else {
        chunk::<false>(co, input, r0, r1, own, s);
    }
}

/// Old row block `j` as seen by the chunk [r0, r1) at row `at`: the copies of the two rows on either
/// side, or the chunk's own rows from `at` on (`tail`), which are not overwritten yet.
#[inline]
fn old_row<'a>(
    j: usize,
    (r0, r1, at, stride): (usize, usize, usize, usize),
    tail: &'a [f64],
    lo: &'a [f64],
    hi: &'a [f64],
) -> &'a [f64] {
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
fn chunk<const DIAG: bool>(
    co: &Coeffs,
    input: &Input,
    r0: usize,
    r1: usize,
    own: &mut [f64],
    s: &mut Scratch,
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
    qn.fill(0.0);
    qf.fill(0.0);
    k.fill(1.0);
    for j in r0.saturating_sub(2)..=r1 {
        let cur = j % 2;
        let real = j < ny;
        let limit = real && j + 1 >= r0 && !co.clamp;
        let finish = j >= r0 && j > 0; // F(j − 1) runs; D(j − 1) too if row j − 1 is the chunk's
        let mine = finish && j > r0;
        if !real {
            k[cur * w..(cur + 1) * w].fill(1.0);
        }
        // The chunk's rows before j (written) and from j on (still old).
        let at = j.clamp(r0, r1);
        let (head, tail) = own.split_at_mut((at - r0) * stride);
        let tail: &[f64] = tail;
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
        let (ha, hb): (&[f64], &[f64]) = if bed_rows {
            (h0, h1)
        } else if real {
            (&row[..w], &up[..w])
        } else {
            (&[], &[])
        };
        let (qa, qb) = qn.split_at_mut(blk);
        let (qn_j, qn_prev): (&mut [f64], &[f64]) = if cur == 0 { (qa, qb) } else { (qb, qa) };
        let (ka, kb) = k.split_at_mut(w);
        let (k_j, k_prev): (&mut [f64], &[f64]) = if cur == 0 { (ka, kb) } else { (kb, ka) };
        // Where F(j − 1) and D(j − 1) write, and the limited flows of row j − 2 that D reads.
        let (d_out, f_out, before): (&mut [f64], &mut [f64], &[f64]) = if mine {
            let n = head.len() / stride; // rows r0 .. j: row j − 1 is the last
            let (older, last) = head.split_at_mut((n - 1) * stride);
            let (d, f) = last.split_at_mut(w);
            let before: &[f64] = if n >= 2 {
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
                flows::<DIAG>(co, input, j, a, b, row, ha, hb, qn_j);
                if limit {
                    limiter::<DIAG>(k_j, &row[..w], qn_j, qn_prev, w, co.beta, a, b);
                }
            }
            // F and D lag one column behind: [a − 1, b − 1), and the last column at the end.
            let fb = if b == nx + 1 { nx + 1 } else { b - 1 };
            let fa = a.max(2) - 1;
            if finish && fa < fb {
                finalize::<DIAG>(f_out, qn_prev, k_prev, k_j, w, fa, fb);
                if mine {
                    depth::<DIAG>(d_out, f_out, before, w, co.beta, co.clamp, fa, fb);
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
fn flows<const DIAG: bool>(
    co: &Coeffs,
    input: &Input,
    j: usize,
    a: usize,
    b: usize,
    row: &[f64],
    h0: &[f64],
    h1: &[f64],
    qn: &mut [f64],
) {
    let (nx, ny, w) = (co.nx, co.ny, co.w());
    let has_up = j + 1 < ny;
    let (qn_x, rest) = qn.split_at_mut(w);
    let (qn_y, rest) = rest.split_at_mut(w);
    let (qn_d, qn_a) = rest.split_at_mut(if DIAG { w } else { 0 });
    let old = |f: usize| &row[f * w..(f + 1) * w];
    let (gx, gd, damp) = (co.gx, co.gd, co.damp);
    // Interior ranges: the x and +x+y pipes of the last column and the −x+y pipe of the first are walls.
    let bx = b.min(nx);
    let aa = a.max(2);
    grad(qn_x, old(1), h0, h0, 1, damp, co.row_edge(gx, gd, j), a, bx);
    if b > nx {
        qn_x[nx] = 0.0;
    }
    if has_up {
        grad(qn_y, old(2), h0, h1, 0, damp, gx, a, b);
        let ge = co.col_edge(gx, gd);
        for e in edges(nx) {
            if a <= e && e < b {
                qn_y[e] = damp * old(2)[e] + ge * (h0[e] - h1[e]);
            }
        }
        if DIAG {
            grad(qn_d, old(3), h0, h1, 1, damp, gd, a, bx);
            grad(qn_a, old(4), h0, h1, -1, damp, gd, aa, b);
        }
    } else {
        qn_y[a..b].fill(0.0);
        if DIAG {
            qn_d[a..b].fill(0.0);
            qn_a[a..b].fill(0.0);
        }
    }
    if DIAG && b > nx {
        qn_d[nx] = 0.0;
    }
    if DIAG && a <= 1 {
        qn_a[1] = 0.0;
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
    let (px, pd) = (co.px, co.pd);
    add_grad(qn_x, p0, p0, 1, co.row_edge(px, pd, j), a, bx);
    if has_up {
        add_grad(qn_y, p0, p1, 0, px, aa, bx);
        let pe = co.col_edge(px, pd);
        for e in edges(nx) {
            if a <= e && e < b {
                qn_y[e] += pe * (p0[e] - p1[e]);
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
fn surface(h: &mut [f64], d: &[f64], bed: Option<&[f64]>, at: usize) {
    let n = d.len();
    let h = &mut h[..n];
    match bed {
        Some(bed) => {
            let bed = &bed[at..at + n];
            for i in 0..n {
                h[i] = d[i] + bed[i];
            }
        }
        None => h.copy_from_slice(d),
    }
}

/// qn[p] = damp·q[p] + c·(h0[p] − h1[p + off]) for p in [a, b) (off = +1, 0 or −1 picks the pipe's
/// other end in row j (x: h1 = h0) or row j + 1).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn grad(
    qn: &mut [f64],
    q: &[f64],
    h0: &[f64],
    h1: &[f64],
    off: isize,
    damp: f64,
    c: f64,
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
        qn[i] = damp * q[i] + c * (h0[i] - h1[i]);
    }
}

/// qn[p] += c·(p0[p] − p1[p + off]) for p in [a, b): the pressure term, same pipes as [`grad`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn add_grad(qn: &mut [f64], p0: &[f64], p1: &[f64], off: isize, c: f64, a: usize, b: usize) {
    if a >= b {
        return;
    }
    let n = b - a;
    let o = (a as isize + off) as usize;
    let (qn, p0, p1) = (&mut qn[a..b], &p0[a..b], &p1[o..o + n]);
    for i in 0..n {
        qn[i] += c * (p0[i] - p1[i]);
    }
}

/// max(x, 0) as a plain compare (vectorises to one max).
#[inline(always)]
fn pos(x: f64) -> f64 {
    if x > 0.0 {
        x
    } else {
        0.0
    }
}

/// min(x, 0) as a plain compare.
#[inline(always)]
fn neg(x: f64) -> f64 {
    if x < 0.0 {
        x
    } else {
        0.0
    }
}

/// K = min(1, cap/out), cap = max(depth, 0): never NaN (out > cap ≥ 0 before dividing).
#[inline(always)]
fn kfactor(depth: f64, out: f64) -> f64 {
    let cap = pos(depth);
    if out > cap {
        cap / out
    } else {
        1.0
    }
}

/// K(j) on padded columns [a, b): min(1, depth/(β·Σ outflow)) (Mei et al. 2007, eq. 4), from the new
/// flows of row j (`own`) and row j − 1 (`before`; zeros before the grid). Outflows are summed in pairs
/// of opposite pipes, so mirror images round alike.
#[allow(clippy::too_many_arguments)]
fn limiter<const DIAG: bool>(
    k: &mut [f64],
    d: &[f64],
    own: &[f64],
    before: &[f64],
    w: usize,
    beta: f64,
    a: usize,
    b: usize,
) {
    let n = b - a;
    let (k, d) = (&mut k[a..b], &d[a..b]);
    let x_own = &own[a..b];
    let x_left = &own[a - 1..b - 1];
    let y_own = &own[w + a..w + b];
    let y_below = &before[w + a..w + b];
    if DIAG {
        let d_own = &own[2 * w + a..2 * w + b];
        let a_own = &own[3 * w + a..3 * w + b];
        // The +x+y pipe into (p, j) is owned by (p − 1, j − 1), the −x+y pipe by (p + 1, j − 1).
        let d_below = &before[2 * w + a - 1..2 * w + b - 1];
        let a_below = &before[3 * w + a + 1..3 * w + b + 1];
        for i in 0..n {
            let ox = pos(x_own[i]) + pos(-x_left[i]);
            let oy = pos(y_own[i]) + pos(-y_below[i]);
            let od = pos(d_own[i]) + pos(-d_below[i]);
            let oa = pos(a_own[i]) + pos(-a_below[i]);
            k[i] = kfactor(d[i], beta * ((ox + oy) + (od + oa)));
        }
    } else {
        for i in 0..n {
            let ox = pos(x_own[i]) + pos(-x_left[i]);
            let oy = pos(y_own[i]) + pos(-y_below[i]);
            k[i] = kfactor(d[i], beta * (ox + oy));
        }
    }
}

/// F(j) on padded columns [a, b): each pipe of row j scaled by K of its upwind column, the owner's
/// (`k_own`, row j) for a positive flow, the other end's (`k_own` at p + 1, or `k_up`, row j + 1) for a
/// negative one: max(q, 0)·K_owner + min(q, 0)·K_other, where one term is an exact zero, so this is
/// exactly q·K_upwind without a branch.
fn finalize<const DIAG: bool>(
    qf: &mut [f64],
    qn: &[f64],
    k_own: &[f64],
    k_up: &[f64],
    w: usize,
    a: usize,
    b: usize,
) {
    let n = b - a;
    let kd = &k_own[a..b];
    let scale = |f: &mut [f64], q: &[f64], ku: &[f64]| {
        let (f, q, ku) = (&mut f[..n], &q[..n], &ku[..n]);
        for i in 0..n {
            f[i] = pos(q[i]) * kd[i] + neg(q[i]) * ku[i];
        }
    };
    let (fx, rest) = qf.split_at_mut(w);
    let (fy, rest) = rest.split_at_mut(w);
    scale(&mut fx[a..b], &qn[a..b], &k_own[a + 1..b + 1]);
    scale(&mut fy[a..b], &qn[w + a..w + b], &k_up[a..b]);
    if DIAG {
        let (fd, fa) = rest.split_at_mut(w);
        scale(
            &mut fd[a..b],
            &qn[2 * w + a..2 * w + b],
            &k_up[a + 1..b + 1],
        );
        scale(
            &mut fa[a..b],
            &qn[3 * w + a..3 * w + b],
            &k_up[a - 1..b - 1],
        );
    }
}

/// D(j) on padded columns [a, b): depth + β·Σ(inflow − outflow) from the limited flows of row j
/// (`own`) and row j − 1 (`before`), pipes in opposite pairs; then the paper's eq. 41 clamp if asked.
#[allow(clippy::too_many_arguments)]
fn depth<const DIAG: bool>(
    d: &mut [f64],
    own: &[f64],
    before: &[f64],
    w: usize,
    beta: f64,
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
    if DIAG {
        let d_own = &own[2 * w + a..2 * w + b];
        let a_own = &own[3 * w + a..3 * w + b];
        let d_below = &before[2 * w + a - 1..2 * w + b - 1];
        let a_below = &before[3 * w + a + 1..3 * w + b + 1];
        for i in 0..n {
            let sx = x_left[i] - x_own[i];
            let sy = y_below[i] - y_own[i];
            let sd = d_below[i] - d_own[i];
            let sa = a_below[i] - a_own[i];
            d[i] += beta * ((sx + sy) + (sd + sa));
        }
    } else {
        for i in 0..n {
            let sx = x_left[i] - x_own[i];
            let sy = y_below[i] - y_own[i];
            d[i] += beta * (sx + sy);
        }
    }
    if clamp {
        for v in d.iter_mut() {
            *v = pos(*v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize, diag: bool, limiter: Limiter) -> WaterGrid {
        let cfg = WaterConfig {
            diagonal_pipes: diag,
            limiter,
            damping: 0.2,
            ..WaterConfig::unit(nx, ny)
        }
        .with_courant(0.6);
        WaterGrid::with_config(cfg).unwrap()
    }

    fn bits(w: &WaterGrid) -> Vec<u64> {
        w.cur.iter().map(|v| v.to_bits()).collect()
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
        for diag in [false, true] {
            for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
                let mut reference = grid(23, 9, diag, limiter);
                scene(&mut reference, 60);
                for seg in [1, 2, 3, 7, 22, 23] {
                    let mut w = grid(23, 9, diag, limiter);
                    w.co.seg = seg;
                    w.set_chunk_rows(Some(3));
                    scene(&mut w, 60);
                    assert_eq!(
                        bits(&w),
                        bits(&reference),
                        "diag {diag} {limiter:?} seg {seg}"
                    );
                }
            }
        }
    }

    /// The chunked in-place sweep gives the serial result bit for bit, for every chunking (each chunk
    /// recomputes its halo from copies of the old neighbouring rows).
    #[test]
    fn any_chunking_gives_the_serial_result() {
        for diag in [false, true] {
            for limiter in [Limiter::MassConserving, Limiter::PaperClamp] {
                for (nx, ny) in [(9, 11), (1, 7), (6, 2)] {
                    let mut serial = grid(nx, ny, diag, limiter);
                    serial.set_chunk_rows(Some(usize::MAX));
                    scene(&mut serial, 60);
                    for rows in [2, 3, 4, 5] {
                        let mut w = grid(nx, ny, diag, limiter);
                        w.set_chunk_rows(Some(rows));
                        scene(&mut w, 60);
                        assert_eq!(
                            bits(&w),
                            bits(&serial),
                            "diag {diag} {limiter:?} {nx}×{ny} rows {rows}"
                        );
                    }
                }
            }
        }
    }

    /// The scene is not trivial: the water moved and the limiter dried a column.
    #[test]
    fn scene_exercises_the_limiter() {
        let mut w = grid(9, 11, true, Limiter::MassConserving);
        setup(&mut w);
        let v0 = w.volume();
        run(&mut w, 60);
        assert!(w.max_abs_eta() > 0.1);
        assert!(((w.volume() - v0) / v0).abs() < 1e-13);
        assert!(w.min_depth() < 1e-9);
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
            let k = kfactor(d, o);
            assert!(k.is_finite() && (0.0..=1.0).contains(&k), "{d} {o} {k}");
        }
        assert_eq!(kfactor(1.0, 4.0), 0.25);
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
}
