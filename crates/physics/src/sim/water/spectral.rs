//! The spectral near field (`water.near_field: Spectral`): linear potential flow on a square patch of
//! water that travels with the stone, for the surface the stone touches. The columns
//! (`mod.rs`) are the shallow-water wave equation, c = √(gH) at every wavelength; at the stone's
//! scale real water is deep (a 10 cm wave in 0.3 m of water has kH ≈ 19) and dispersive, and the
//! columns' response to a pressure of wavenumber k, η_tt = H k² p/ρ, is kH times the true
//! deep-water one, k p/ρ (fidelity study §9: the near field does not converge on finer columns).
//!
//! **Model** (Lamb, *Hydrodynamics*, 6th ed. 1932, §§227–229, 255, 267, 348; Whitham, *Linear and
//! Nonlinear Waves*, 1974, §13.2). Irrotational, incompressible water of depth H under a surface
//! pressure p, linearised about rest: the surface elevation η and the velocity potential at the
//! surface φ obey, per Fourier mode of wavenumber k = |k|,
//!
//! * η̂_t = T φ̂ with T = k tanh(kH) (the Dirichlet-to-Neumann operator of the flat layer),
//! * φ̂_t = −s η̂ − p̂/ρ with s = g + σk²/ρ (Bernoulli at the surface; σ the surface tension,
//!   Laplace's pressure σ∇²η),
//!
//! so each mode is an oscillator of the capillary–gravity dispersion relation
//! ω² = (gk + σk³/ρ) tanh(kH) (Lamb §267). The step integrates every mode **exactly** over Δt with
//! the tick's pressure impulse spread evenly over it (a constant p̂ = Î/Δt): η̂ ← η̂ cos ωΔt +
//! (T/ω) φ̂ sin ωΔt − (Î/ρ)(T/ω²Δt)(1 − cos ωΔt), φ̂ ← φ̂ cos ωΔt − (ω/T) η̂ sin ωΔt −
//! (Î/ρ) sin(ωΔt)/(ωΔt); no Courant limit, no numerical dispersion. Viscosity damps each mode's
//! amplitude by e^{−2νk²Δt} (Lamb §348). The k = 0 mode keeps its η̂ (volume).
//!
//! **The patch.** n × n cells of side l (n a power of two) with periodic transforms (`fft.rs`);
//! within n/8 cells of each edge a sponge layer (Israeli & Orszag 1981) multiplies η and φ by
//! e^{−γ(d)Δt} each step, γ = [`SPONGE_RATE`]·(1 − d/w)² at distance d from the edge over the
//! width w, so the waves that run out do not come back round the periodic edges. When the stone is
//! more than n/8 cells from the centre the patch moves by whole cells to centre it again (fields
//! copied, the cells that enter at rest): the waves the stone left behind farther than n/2 cells are
//! forgotten, which does not matter for a stone that outruns them (they are behind it) and is
//! measured by the patch-size study.
//!
//! **Coupling.** The stone's vertical impulses (N·s, down) over each face's footprint enter as the
//! pressure impulse Î of the step. Shear (the horizontal impulse) does no work on an irrotational
//! flow at linear order and is not taken by the near field; the lake's columns still take it. The
//! stone reads η bilinearly between cell centres, as it reads the columns.

use super::fft::{Complex, Fft};

/// γ at the patch's edge (1/s): waves crossing a sponge of width w = n l/8 at group speed c_g are
/// damped by e^{−γ w/(3 c_g)} or more — for the default 1.28 m patch e^{−1.7} at c_g = 1 m/s
/// (a 64 cm gravity wave) and stronger for shorter, slower waves, and the sponge acts on both ways out.
pub const SPONGE_RATE: f64 = 40.0;

/// The near field's settings (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectralConfig {
    /// Cells along each side (a power of two, 16–1024).
    pub cells: usize,
    /// Cell side l (m).
    pub cell: f64,
    /// Rest depth H (m).
    pub depth: f64,
    /// g (m/s²).
    pub gravity: f64,
    /// ρ (kg/m³).
    pub density: f64,
    /// σ (N/m).
    pub surface_tension: f64,
    /// ν (m²/s).
    pub viscosity: f64,
    /// Whether the edges absorb (off only in tests of the periodic dynamics).
    pub sponge: bool,
}

/// One mode pair's coefficients for a step of Δt.
#[derive(Debug, Clone, Copy, Default)]
struct Mode {
    /// e^{−2νk²Δt} cos ωΔt
    c: f64,
    /// e^{−2νk²Δt} (T/ω) sin ωΔt
    eta_from_phi: f64,
    /// −e^{−2νk²Δt} (ω/T) sin ωΔt
    phi_from_eta: f64,
    /// η̂'s response to Î = 1 N·s/m² spread over the step: −(T/(ρω²Δt))(1 − cos ωΔt)
    eta_from_impulse: f64,
    /// φ̂'s: −sin(ωΔt)/(ρωΔt)
    phi_from_impulse: f64,
}

/// The patch of water that travels with the stone.
#[derive(Debug, Clone)]
pub struct SpectralField {
    cfg: SpectralConfig,
    fft: Fft,
    /// World (x, y) of the patch's −x, −y corner; always `anchor` plus whole cells.
    origin: [f64; 2],
    /// η (m) and φ (m²/s), row-major (y rows of x cells).
    eta: Vec<f64>,
    phi: Vec<f64>,
    /// The pressure impulse gathered for the next step (N·s on each cell, down).
    impulse: Vec<f64>,
    pending: bool,
    /// Whether any value is non-zero (still water needs no transform).
    moving: bool,
    modes: Vec<Mode>,
    sponge: Vec<f64>,
    /// The Δt the coefficients are for.
    coeff_dt: f64,
    z: Vec<Complex>,
    p: Vec<Complex>,
    scratch: Vec<Complex>,
    time: f64,
    steps: u64,
    /// N·s received over the patch, and N·s that fell outside it (lost).
    received: f64,
    missed: f64,
}

impl SpectralField {
    /// A patch at rest centred on world (x, y); `None` unless `cfg.cells` is a power of two ≥ 16.
    pub fn new(cfg: SpectralConfig, centre: [f64; 2]) -> Option<Self> {
        if cfg.cells < 16 {
            return None;
        }
        let fft = Fft::new(cfg.cells)?;
        let n2 = cfg.cells * cfg.cells;
        let half = 0.5 * cfg.cells as f64 * cfg.cell;
        Some(Self {
            cfg,
            fft,
            origin: [centre[0] - half, centre[1] - half],
            eta: vec![0.0; n2],
            phi: vec![0.0; n2],
            impulse: vec![0.0; n2],
            pending: false,
            moving: false,
            modes: Vec::new(),
            sponge: Vec::new(),
            coeff_dt: f64::NAN,
            z: Vec::new(),
            p: Vec::new(),
            scratch: Vec::new(),
            time: 0.0,
            steps: 0,
            received: 0.0,
            missed: 0.0,
        })
    }

    pub fn config(&self) -> &SpectralConfig {
        &self.cfg
    }
    pub fn cells(&self) -> usize {
        self.cfg.cells
    }
    pub fn cell(&self) -> f64 {
        self.cfg.cell
    }
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }
    pub fn time(&self) -> f64 {
        self.time
    }
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// The patch's side (m).
    pub fn side(&self) -> f64 {
        self.cfg.cells as f64 * self.cfg.cell
    }
    /// N·s deposited on the patch so far, and N·s whose footprint lay outside it.
    pub fn impulse_received(&self) -> (f64, f64) {
        (self.received, self.missed)
    }

    /// New gravity and density (the coefficients follow at the next step).
    pub fn set_constants(&mut self, gravity: f64, density: f64) {
        self.cfg.gravity = gravity;
        self.cfg.density = density;
        self.coeff_dt = f64::NAN;
    }

    /// η of cell (i, j) (x index, y index).
    pub fn eta(&self, i: usize, j: usize) -> f64 {
        self.eta[j * self.cfg.cells + i]
    }

    /// Sets η and φ of cell (i, j) (tests and initial states).
    pub fn set_cell(&mut self, i: usize, j: usize, eta: f64, phi: f64) {
        let k = j * self.cfg.cells + i;
        self.eta[k] = eta;
        self.phi[k] = phi;
        self.moving = true;
    }

    /// Σ η l² (m³): the displaced volume.
    pub fn volume(&self) -> f64 {
        self.eta.iter().sum::<f64>() * self.cfg.cell * self.cfg.cell
    }

    /// The largest |η| (m).
    pub fn max_abs_eta(&self) -> f64 {
        self.eta.iter().fold(0.0, |m, e| m.max(e.abs()))
    }

    /// Fractional cell coordinates of world (x, y) on the cell-centre lattice.
    fn lattice(&self, x: f64, y: f64) -> (f64, f64) {
        let l = self.cfg.cell;
        (
            (x - self.origin[0]) / l - 0.5,
            (y - self.origin[1]) / l - 0.5,
        )
    }

    /// η (m) at world (x, y), bilinear between cell centres; 0 (rest) off the lattice.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let n = self.cfg.cells;
        let (fx, fy) = self.lattice(x, y);
        let last = (n - 1) as f64;
        if !(fx >= 0.0 && fy >= 0.0 && fx < last && fy < last) {
            return 0.0;
        }
        let (i, j) = (fx as usize, fy as usize);
        let (tx, ty) = (fx - i as f64, fy - j as f64);
        let at = j * n + i;
        let (e00, e10) = (self.eta[at], self.eta[at + 1]);
        let (e01, e11) = (self.eta[at + n], self.eta[at + n + 1]);
        let a = e00 + tx * (e10 - e00);
        let b = e01 + tx * (e11 - e01);
        a + ty * (b - a)
    }

    /// The cells whose centres lie within the rectangle [lo, hi] grown by one cell, clamped to the
    /// patch: (i0, i1, j0, j1) inclusive, and whether the rectangle reaches past the patch.
    fn cells_over(&self, lo: [f64; 2], hi: [f64; 2]) -> Option<(usize, usize, usize, usize, bool)> {
        let n = self.cfg.cells as f64;
        let (ax, ay) = self.lattice(lo[0], lo[1]);
        let (bx, by) = self.lattice(hi[0], hi[1]);
        if !(ax.is_finite() && ay.is_finite() && bx.is_finite() && by.is_finite()) {
            return None;
        }
        let outside = ax < 0.0 || ay < 0.0 || bx > n - 1.0 || by > n - 1.0;
        let clamp = |v: f64| v.clamp(0.0, n - 1.0) as usize;
        let (i0, i1) = (clamp(ax.floor() - 1.0), clamp(bx.ceil() + 1.0));
        let (j0, j1) = (clamp(ay.floor() - 1.0), clamp(by.ceil() + 1.0));
        if bx < -1.0 || by < -1.0 || ax > n || ay > n {
            return Some((1, 0, 1, 0, true));
        }
        Some((i0, i1, j0, j1, outside))
    }

    /// The highest η over the rectangle [lo, hi] (an upper bound of the bilinear surface there; 0
    /// counted where it reaches past the patch) and the largest |Δη|/l between neighbouring cells
    /// in it (a bound of the bilinear surface's slope).
    pub fn bounds_over(&self, lo: [f64; 2], hi: [f64; 2]) -> (f64, f64) {
        let Some((i0, i1, j0, j1, outside)) = self.cells_over(lo, hi) else {
            return (f64::INFINITY, f64::INFINITY);
        };
        let n = self.cfg.cells;
        let mut m = if outside { 0.0 } else { f64::NEG_INFINITY };
        let (mut sx, mut sy) = (0.0f64, 0.0f64);
        for j in j0..=j1.min(n - 1) {
            for i in i0..=i1.min(n - 1) {
                let e = self.eta[j * n + i];
                m = m.max(e);
                if i < i1 {
                    sx = sx.max((self.eta[j * n + i + 1] - e).abs());
                }
                if j < j1 {
                    sy = sy.max((self.eta[(j + 1) * n + i] - e).abs());
                }
            }
        }
        if m == f64::NEG_INFINITY {
            m = 0.0;
        }
        (m, sx.hypot(sy) / self.cfg.cell)
    }

    /// Impulse (N·s, pushing the water down) spread uniformly over the square [x ± half] × [y ±
    /// half]: each cell takes the fraction of the square it covers (a point, `half` ≤ l/1000, goes
    /// to its one cell). A footprint wholly or partly off the patch loses that part (counted in
    /// [`Self::impulse_received`]).
    pub fn deposit(&mut self, x: f64, y: f64, half: f64, impulse: f64) {
        if !impulse.is_finite() || !half.is_finite() || impulse == 0.0 {
            return;
        }
        let n = self.cfg.cells;
        let l = self.cfg.cell;
        let half = half.max(1e-3 * l);
        let along = |c: f64, o: f64| {
            let (a, b) = ((c - half - o) / l, (c + half - o) / l);
            let first = a.floor().max(0.0);
            let last = (b.ceil() - 1.0).min(n as f64 - 1.0);
            (a, b, first, last)
        };
        let (ax, bx, fx, lx) = along(x, self.origin[0]);
        let (ay, by, fy, ly) = along(y, self.origin[1]);
        let width = (bx - ax) * (by - ay);
        let inside = ax >= 0.0 && ay >= 0.0 && bx <= n as f64 && by <= n as f64;
        let mut taken = 0.0;
        if fx <= lx && fy <= ly {
            for j in fy as usize..=ly as usize {
                let wy = (by.min(j as f64 + 1.0) - ay.max(j as f64)).max(0.0);
                for i in fx as usize..=lx as usize {
                    let wx = (bx.min(i as f64 + 1.0) - ax.max(i as f64)).max(0.0);
                    let part = impulse * (wx * wy / width);
                    self.impulse[j * n + i] += part;
                    taken += part;
                }
            }
            self.pending = true;
        }
        if inside {
            // Every part landed: the whole impulse, without the parts' rounding.
            taken = impulse;
        }
        self.received += taken;
        self.missed += impulse - taken;
    }

    /// Moves the patch by whole cells so that world (x, y) is within half a cell of its centre,
    /// when it has drifted more than n/8 cells from it. Returns whether it moved.
    pub fn follow(&mut self, x: f64, y: f64) -> bool {
        let n = self.cfg.cells;
        let l = self.cfg.cell;
        let half = 0.5 * n as f64 * l;
        let dx = ((x - self.origin[0] - half) / l).round();
        let dy = ((y - self.origin[1] - half) / l).round();
        if !(dx.is_finite() && dy.is_finite()) {
            return false;
        }
        let limit = (n / 8) as f64;
        if dx.abs() <= limit && dy.abs() <= limit {
            return false;
        }
        let (sx, sy) = (dx as i64, dy as i64);
        self.origin = [
            self.origin[0] + sx as f64 * l,
            self.origin[1] + sy as f64 * l,
        ];
        if self.moving || self.pending {
            for field in [&mut self.eta, &mut self.phi, &mut self.impulse] {
                shift(field, n, sx, sy);
            }
        }
        true
    }

    /// Advances by Δt (s): every mode exactly, the impulses gathered since the last step spread
    /// evenly over it; then the sponge. Returns whether the surface may have changed (still water
    /// with nothing pushed on it stays still).
    pub fn advance(&mut self, dt: f64) -> bool {
        if !(dt > 0.0 && dt.is_finite()) {
            return false;
        }
        self.time += dt;
        self.steps += 1;
        if !self.moving && !self.pending {
            return false;
        }
        if self.coeff_dt != dt {
            self.prepare(dt);
        }
        self.transform_in();
        self.evolve();
        self.transform_out();
        self.impulse.iter_mut().for_each(|v| *v = 0.0);
        self.pending = false;
        self.moving = true;
        true
    }

    /// The coefficients of every mode pair and the sponge's factors for a step of Δt.
    fn prepare(&mut self, dt: f64) {
        let c = self.cfg;
        let n = c.cells;
        let dk = 2.0 * std::f64::consts::PI / (n as f64 * c.cell);
        let wave = |i: usize| {
            let m = if i <= n / 2 {
                i as f64
            } else {
                i as f64 - n as f64
            };
            m * dk
        };
        let area = c.cell * c.cell;
        self.modes = (0..n * n)
            .map(|idx| {
                let k = wave(idx % n).hypot(wave(idx / n));
                mode(k, dt, &c, area)
            })
            .collect();
        let w = (n / 8).max(1) as f64;
        let edge = |i: usize| {
            let d = (i as f64 + 0.5).min(n as f64 - i as f64 - 0.5);
            if c.sponge && d < w {
                SPONGE_RATE * (1.0 - d / w).powi(2)
            } else {
                0.0
            }
        };
        let g: Vec<f64> = (0..n).map(edge).collect();
        self.sponge = (0..n * n)
            .map(|idx| (-(g[idx % n].max(g[idx / n])) * dt).exp())
            .collect();
        self.coeff_dt = dt;
    }

    /// z = η + iφ and p = impulse per cell, to Fourier space.
    fn transform_in(&mut self) {
        self.z.clear();
        self.z
            .extend(self.eta.iter().zip(&self.phi).map(|(&e, &f)| [e, f]));
        self.fft.transform_2d(&mut self.z, &mut self.scratch, false);
        self.p.clear();
        if self.pending {
            self.p.extend(self.impulse.iter().map(|&v| [v, 0.0]));
            self.fft.transform_2d(&mut self.p, &mut self.scratch, false);
        }
    }

    /// Each pair of modes (k, −k): η̂ and φ̂ unpacked from z, stepped, packed again.
    fn evolve(&mut self) {
        let n = self.cfg.cells;
        let neg = |i: usize| (n - i) % n;
        for j in 0..n {
            for i in 0..n {
                let a = j * n + i;
                let b = neg(j) * n + neg(i);
                if b < a {
                    continue;
                }
                let (za, zb) = (self.z[a], self.z[b]);
                // H(k) = (Z(k) + Z̄(−k))/2, Φ(k) = (Z(k) − Z̄(−k))/(2i).
                let h = |p: Complex, q: Complex| [0.5 * (p[0] + q[0]), 0.5 * (p[1] - q[1])];
                let f = |p: Complex, q: Complex| [0.5 * (p[1] + q[1]), -0.5 * (p[0] - q[0])];
                let (ha, fa) = (h(za, zb), f(za, zb));
                let (hb, fb) = (h(zb, za), f(zb, za));
                let m = self.modes[a];
                let (pa, pb) = if self.p.is_empty() {
                    ([0.0; 2], [0.0; 2])
                } else {
                    (self.p[a], self.p[b])
                };
                let step = |h: Complex, f: Complex, p: Complex| {
                    let e = [
                        m.c * h[0] + m.eta_from_phi * f[0] + m.eta_from_impulse * p[0],
                        m.c * h[1] + m.eta_from_phi * f[1] + m.eta_from_impulse * p[1],
                    ];
                    let g = [
                        m.c * f[0] + m.phi_from_eta * h[0] + m.phi_from_impulse * p[0],
                        m.c * f[1] + m.phi_from_eta * h[1] + m.phi_from_impulse * p[1],
                    ];
                    // Z = H + iΦ
                    [e[0] - g[1], e[1] + g[0]]
                };
                self.z[a] = step(ha, fa, pa);
                if b != a {
                    self.z[b] = step(hb, fb, pb);
                }
            }
        }
    }

    /// Back to η and φ, with the sponge.
    fn transform_out(&mut self) {
        self.fft.transform_2d(&mut self.z, &mut self.scratch, true);
        for (k, v) in self.z.iter().enumerate() {
            let s = self.sponge[k];
            self.eta[k] = v[0] * s;
            self.phi[k] = v[1] * s;
        }
    }
}

/// A mode of wavenumber k (1/m) over Δt: the exact propagator of (η̂, φ̂) and its response to a
/// pressure impulse per cell spread evenly over the step (the transform of N·s per cell; per area
/// it is that over l²).
fn mode(k: f64, dt: f64, c: &SpectralConfig, area: f64) -> Mode {
    let damp = (-2.0 * c.viscosity * k * k * dt).exp();
    let rho = c.density;
    if k == 0.0 {
        // T = 0, ω = 0: η̂₀ is the volume; φ̂₀ takes the impulse (and reads nowhere).
        return Mode {
            c: 1.0,
            eta_from_phi: 0.0,
            phi_from_eta: -(c.gravity) * dt,
            eta_from_impulse: 0.0,
            phi_from_impulse: -1.0 / (rho * area),
        };
    }
    let t = k * (k * c.depth).tanh();
    let s = c.gravity + c.surface_tension * k * k / rho;
    let w = (t * s).sqrt();
    let x = w * dt;
    let (sn, cs) = x.sin_cos();
    // 1 − cos x without cancellation, and sin x / x near 0.
    let one_minus_cos = 2.0 * (0.5 * x).sin().powi(2);
    let sinc = if x > 1e-8 { sn / x } else { 1.0 };
    Mode {
        c: damp * cs,
        eta_from_phi: damp * t / w * sn,
        phi_from_eta: -damp * w / t * sn,
        eta_from_impulse: -damp * t / (rho * area * w * w * dt) * one_minus_cos,
        phi_from_impulse: -damp * sinc / (rho * area),
    }
}

/// Moves `field` (n × n, row-major) so that cell (i, j) takes the value of cell (i + sx, j + sy),
/// cells from outside the patch entering at rest (0). In place: the source of cell k is k + d with
/// d = sy·n + sx, so walking up when d > 0 (down when d < 0) reads every source before it is
/// overwritten.
fn shift(field: &mut [f64], n: usize, sx: i64, sy: i64) {
    let ni = n as i64;
    if sx.abs() >= ni || sy.abs() >= ni {
        field.iter_mut().for_each(|v| *v = 0.0);
        return;
    }
    let d = sy * ni + sx;
    let mut set = |k: i64| {
        let (j, i) = (k / ni, k % ni);
        let (oi, oj) = (i + sx, j + sy);
        field[k as usize] = if (0..ni).contains(&oi) && (0..ni).contains(&oj) {
            field[(k + d) as usize]
        } else {
            0.0
        };
    };
    if d > 0 {
        (0..ni * ni).for_each(&mut set);
    } else if d < 0 {
        (0..ni * ni).rev().for_each(&mut set);
    }
}

#[cfg(test)]
mod tests;
