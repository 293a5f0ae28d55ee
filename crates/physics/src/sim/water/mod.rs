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
//! * **Coupling** (`deposits.rs`). The stone's vertical impulse enters as the external pressure E of
//!   the next step; its horizontal impulse as momentum of the axis pipes under its footprint
//!   (ΔQ = J/(ρL): the water in a pipe carries ρQL), so the water takes the stone's whole impulse.
//! * **Walls.** Closed: no flow through a boundary face. With diagonal pipes, the diagonal pipes a mirror
//!   image across the wall would have add to the pipe along the wall, so a wall is an exact mirror (the
//!   Neumann boundary of the isotropic 9-point stencil): the method of images holds for both stencils.
//! * **Stability.** The grid runs on its own fixed clock Δt_w, chosen at construction at
//!   [`COURANT_SAFETY`] of the Courant limit r = cΔt/l ≤ 1/√2 (4 pipes) or √3/2 (8 pipes), capped at
//!   `MAX_STEP`. No accepted parameter can make it unstable: the linear scheme is stable below the
//!   limit whatever H, l and g are, K only scales flows down, the damping only removes momentum, and
//!   the external pressure is a bounded forcing.
//!
//! * **Only where water moves** (`Active`). Still water on the flat bed stays still bit for bit
//!   (zero flows from equal surfaces, K = 1, depth + 0), so a step computes only the window of
//!   columns that may move, grown by the stencil's one column and by the columns the stone's
//!   impulses reach; the rest keep their values. A bed, a swell or a depth set by hand make the
//!   whole grid active. Tested against [`WaterGrid::step_everywhere`], bit for bit.
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
//! **Layout.** This file: the configuration, the grid and its clock; `storage.rs`: the scalar types,
//! the padded row blocks and the state setters; `kernel.rs`: the fused sweep; `deposits.rs`: the
//! coupling; `sampling.rs`: the readings.
//!
//! Units are SI throughout: metres, seconds, m³/s, pascals, newton-seconds.

mod deposits;
mod kernel;
mod sampling;
mod storage;
#[cfg(test)]
mod tests;

use crate::sim::params::{Limiter, ParamError, Precision, WaterParams, MAX_WATER_COLUMNS};

use storage::{each, Coeffs, Fields, State};

pub(crate) use sampling::{EtaPatch, PatchReader};

/// Fraction of the Courant limit at which the automatic water step runs: r = 0.7/√2 ≈ 0.495 with axis
/// pipes, r = 0.7·√3/2 ≈ 0.606 with diagonals. Below the limit by 30 %, and near the top, where the
/// leapfrog-like scheme is most accurate (its phase error shrinks as r grows towards the limit).
pub const COURANT_SAFETY: f64 = 0.7;
/// Longest automatic water step (s): one 60 Hz frame.
pub(crate) const MAX_STEP: f64 = 1.0 / 60.0;
/// Courant limit cΔt/l of the 4-pipe scheme, 1/√2.
pub const COURANT_LIMIT_4: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Courant limit cΔt/l of the isotropic 8-pipe scheme, √3/2.
pub const COURANT_LIMIT_8: f64 = 0.866_025_403_784_438_6;

/// Half-width (in cells) at or below which [`WaterGrid::deposit_impulse_box`] treats its square as a
/// point and deposits bilinearly.
pub(crate) const BOX_MIN_HALF: f64 = 1e-6;

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
    /// Columns along y.
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
    /// Add the four diagonal pipes to the four axis pipes (the isotropic 9-point stencil, pipe
    /// areas A_axis = ⅔Hl, A_diag = (√2/6)Hl).
    pub diagonal_pipes: bool,
    /// How a column is kept from a negative volume (eq. 40): Mei et al. 2007's K factor or the
    /// paper's eq. 41 clamp.
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

/// Where a lake lies: its grid's columns and cell (kept by `Simulation` while the grid is handed
/// out, `sim::lake`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LakeGeometry {
    /// Columns along x.
    pub nx: usize,
    /// Columns along y.
    pub ny: usize,
    /// Column width (m).
    pub cell: f64,
    /// The −x, −y corner (m).
    pub origin: [f64; 2],
}

impl LakeGeometry {
    /// The +x, +y corner (m).
    pub fn far_corner(&self) -> [f64; 2] {
        let [ox, oy] = self.origin;
        [
            ox + self.nx as f64 * self.cell,
            oy + self.ny as f64 * self.cell,
        ]
    }

    /// Whether world (x, y) lies over the lake.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let ([ox, oy], [hx, hy]) = (self.origin, self.far_corner());
        x >= ox && y >= oy && x < hx && y < hy
    }
}

/// The water surface: columns joined by pipes (see the module documentation).
#[derive(Debug, Clone)]
pub struct WaterGrid {
    cfg: WaterConfig,
    dt: f64,
    /// The longest step a preset allows (`water.max_step`), under the automatic one.
    max_step: Option<f64>,
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
    /// Horizontal impulses (N·s along +x, +y) deposited since the last step, per column; empty until
    /// the first deposit.
    pending_momentum: Vec<[f64; 2]>,
    touched_momentum: Vec<usize>,
    /// Every horizontal impulse (N·s) the pipes have accepted since the grid was built.
    momentum_received: [f64; 2],
    /// Rows holding external pressure during the current step.
    row_press: Vec<bool>,
    chunk_rows: Option<usize>,
    steps: u64,
    clock: f64,
    /// (time, steps) when the step last changed: time = t₀ + (steps − n₀)·Δt_w.
    epoch: (f64, u64),
    /// The columns that may differ from rest; every other column is at rest with zero flows, and a
    /// step leaves it so (see [`Active`]).
    active: Active,
    /// Counts every change of the surface (a step, a set depth or bed, a swell), so a copy of part
    /// of it ([`EtaPatch`]) knows when it is stale.
    revision: u64,
}

/// The water's step Δt_w for a configuration: the explicit one, or [`COURANT_SAFETY`] of the Courant
/// limit, capped at [`MAX_STEP`].
fn step_for(cfg: &WaterConfig) -> f64 {
    let c = (cfg.gravity * cfg.depth).sqrt();
    let limit = if cfg.diagonal_pipes {
        COURANT_LIMIT_8
    } else {
        COURANT_LIMIT_4
    };
    match cfg.dt {
        Some(dt) => dt,
        None if c > 0.0 => (COURANT_SAFETY * limit * cfg.cell / c).min(MAX_STEP),
        None => MAX_STEP,
    }
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
        if params.max_step.is_some() {
            grid.max_step = params.max_step;
            grid.retime();
        }
        if let Some(swell) = params.swell {
            grid.set_swell(&swell);
        }
        Ok(grid)
    }

    /// A grid from raw numbers (tests, studies): water at rest at depth H on a flat bed.
    pub fn with_config(cfg: WaterConfig) -> Result<Self, ParamError> {
        cfg.validate()?;
        let dt = step_for(&cfg);
        let co = Coeffs::new(&cfg, dt);
        let h = cfg.depth;
        let state = match cfg.precision {
            Precision::F32 => State::F32(Fields::new(&co, h)),
            Precision::F64 => State::F64(Fields::new(&co, h)),
        };
        Ok(Self {
            cfg,
            dt,
            max_step: None,
            co,
            state,
            row_bed: vec![false; cfg.ny],
            pending: Vec::new(),
            received: 0.0,
            touched: Vec::new(),
            pending_momentum: Vec::new(),
            touched_momentum: Vec::new(),
            momentum_received: [0.0; 2],
            row_press: vec![false; cfg.ny],
            chunk_rows: None,
            steps: 0,
            clock: 0.0,
            epoch: (0.0, 0),
            revision: 0,
            active: Active::Rest,
        })
    }

    /// Changes gravity and the water's density live (the physics panel): the flow law's
    /// coefficients follow, and so does the automatic step (the Courant number stays at
    /// [`COURANT_SAFETY`] of the limit whatever g is; an explicit step is kept). The clock goes on
    /// from the water's present time, whatever the new step. The state (depths, flows, bed) is kept.
    pub fn set_constants(&mut self, gravity: f64, density: f64) -> Result<(), ParamError> {
        let cfg = WaterConfig {
            gravity,
            density,
            ..self.cfg
        };
        cfg.validate()?;
        if cfg == self.cfg {
            return Ok(());
        }
        self.epoch = (self.time(), self.steps);
        self.cfg = cfg;
        self.retime();
        Ok(())
    }

    /// The step for the configuration ([`step_for`], under the preset's `max_step`) and the flow
    /// law's coefficients for it.
    fn retime(&mut self) {
        let auto = step_for(&self.cfg);
        self.dt = self.max_step.map_or(auto, |m| auto.min(m));
        self.co = Coeffs::new(&self.cfg, self.dt);
    }

    // --- geometry and clock -------------------------------------------------------------------

    /// Where the grid lies: its columns and cell.
    pub fn geometry(&self) -> LakeGeometry {
        LakeGeometry {
            nx: self.cfg.nx,
            ny: self.cfg.ny,
            cell: self.cfg.cell,
            origin: self.cfg.origin,
        }
    }

    /// Columns along x.
    pub fn nx(&self) -> usize {
        self.cfg.nx
    }
    /// Columns along y.
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
    /// The grid's defining numbers (shape, cell, depth, constants, limiter, step).
    pub fn config(&self) -> &WaterConfig {
        &self.cfg
    }
    /// The water's own fixed step Δt_w (s).
    pub fn step_dt(&self) -> f64 {
        self.dt
    }
    /// Simulated time the water has reached (s): steps taken × Δt_w (counted from the last change
    /// of the step, [`Self::set_constants`]).
    pub fn time(&self) -> f64 {
        let (t0, n0) = self.epoch;
        t0 + (self.steps - n0) as f64 * self.dt
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
        let (t0, n0) = self.epoch;
        let due = ((self.clock - t0) / self.dt + 1e-9).floor();
        while ((self.steps - n0) as f64) < due {
            self.step();
        }
    }

    /// Runs exactly one water step. Uses the current rayon pool (`pool.install(|| grid.step())` picks
    /// one); the result is bit-identical for any number of threads.
    pub fn step(&mut self) {
        // The columns this step can change: those that may already move, the ones the pending
        // impulses reach (a momentum deposit also loads the pipes its column's −x and −y neighbours
        // own), and one ring around them, where a wave can arrive within one step.
        let (nx, ny) = (self.cfg.nx, self.cfg.ny);
        let deposits = self.touched.iter().chain(&self.touched_momentum);
        let reached = deposits.fold(self.active, |a, &i| a.with(i % nx, i / nx, 1, nx, ny));
        let region = reached.grown(1, nx, ny);
        self.apply_pending_momentum();
        self.apply_pending_pressure();
        if let Some((x0, x1, y0, y1)) = region.bounds(nx, ny) {
            let chunks = self.chunk_bounds(y0, y1 + 1, (x1 - x0 + 1) * (y1 - y0 + 1));
            let has_press = !self.touched.is_empty();
            let (co, row_bed, row_press) = (&self.co, &self.row_bed, &self.row_press);
            let cols = (x0 + 1, x1 + 2);
            each!(&mut self.state, f => f.step(co, &chunks, cols, row_bed, row_press, has_press));
        }
        self.active = region;
        self.clear_pressure();
        self.steps += 1;
        self.revision += 1;
    }

    /// Rows per chunk for the parallel step: `None` (default) chooses from the grid size and the pool's
    /// threads; `Some(n)` forces chunks of n ≥ 2 rows (determinism tests). Results never depend on it.
    pub fn set_chunk_rows(&mut self, rows: Option<usize>) {
        self.chunk_rows = rows.map(|r| r.max(2));
    }

    /// From now on every step computes every column, moving or not, instead of the window where
    /// water may move: the same result bit for bit (the reference the window is tested against).
    pub fn step_everywhere(&mut self) {
        self.active = Active::All;
    }

    /// The columns the last step computed, (x0, x1, y0, y1) inclusive; `None` when the water is
    /// wholly at rest.
    pub fn active_window(&self) -> Option<(usize, usize, usize, usize)> {
        self.active.bounds(self.cfg.nx, self.cfg.ny)
    }

    /// The chunks of rows [r0, r1) for a step over `columns` columns.
    fn chunk_bounds(&self, r0: usize, r1: usize, columns: usize) -> Vec<(usize, usize)> {
        let rows = r1 - r0;
        let n = match self.chunk_rows {
            Some(r) => rows.div_ceil(r).min(rows / 2).max(1),
            None => {
                let threads = rayon::current_num_threads();
                if threads <= 1 || columns < PARALLEL_MIN_COLUMNS {
                    1
                } else {
                    (2 * threads).min(rows / MIN_CHUNK_ROWS).max(1)
                }
            }
        };
        // Even split: every chunk has at least 2 rows when n ≤ rows / 2.
        (0..n)
            .map(|c| (r0 + c * rows / n, r0 + (c + 1) * rows / n))
            .collect()
    }
}

/// Where a grid's water may move. A column at rest (its depth the rest depth on the flat bed, its
/// flows zero) whose neighbours are at rest and that receives no impulse stays at rest bit for bit
/// through a step: its new flows are e^{−γΔt}·0 + Δt·(gA/L)·(H − H) = 0, its limiter 1 and its
/// depth H + Δt·0. So a step need only compute the window of columns that may move grown by one
/// ring, and the window grows by at most one column a step (the stencil's reach), plus what the
/// stone deposits. A bed, a swell or a depth set by hand make the whole grid active.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Active {
    /// Every column at rest.
    Rest,
    /// Columns [x0, x1] × [y0, y1] may move; the rest are at rest.
    Window(usize, usize, usize, usize),
    /// Any column may move.
    All,
}

/// Columns [x0, x1] × [y0, y1] grown by `ring` on every side, clamped to an nx × ny grid.
fn grow_window(
    (x0, x1, y0, y1): (usize, usize, usize, usize),
    ring: usize,
    nx: usize,
    ny: usize,
) -> (usize, usize, usize, usize) {
    (
        x0.saturating_sub(ring),
        (x1 + ring).min(nx - 1),
        y0.saturating_sub(ring),
        (y1 + ring).min(ny - 1),
    )
}

impl Active {
    /// Also column (ix, iy) and `ring` columns around it.
    fn with(self, ix: usize, iy: usize, ring: usize, nx: usize, ny: usize) -> Self {
        let (x0, x1, y0, y1) = grow_window((ix, ix, iy, iy), ring, nx, ny);
        match self {
            Active::Rest => Active::Window(x0, x1, y0, y1),
            Active::Window(a0, a1, b0, b1) => {
                Active::Window(a0.min(x0), a1.max(x1), b0.min(y0), b1.max(y1))
            }
            Active::All => Active::All,
        }
    }

    /// Grown by `ring` columns on every side (clamped to the grid).
    fn grown(self, ring: usize, nx: usize, ny: usize) -> Self {
        match self {
            Active::Window(x0, x1, y0, y1) => {
                let (x0, x1, y0, y1) = grow_window((x0, x1, y0, y1), ring, nx, ny);
                Active::Window(x0, x1, y0, y1)
            }
            other => other,
        }
    }

    /// Inclusive column bounds, `None` at rest.
    fn bounds(self, nx: usize, ny: usize) -> Option<(usize, usize, usize, usize)> {
        match self {
            Active::Rest => None,
            Active::Window(x0, x1, y0, y1) => Some((x0, x1, y0, y1)),
            Active::All => Some((0, nx - 1, 0, ny - 1)),
        }
    }
}
