//! The stone's coupling into the water (Newton's third law, design.md §5): impulses deposited on
//! columns, bilinearly or over a square footprint. The vertical impulse acts as an external pressure
//! during the next water step; the horizontal impulse goes into the momentum of the pipes.
//!
//! **Horizontal momentum.** In the column-and-pipe model the water's horizontal momentum lives in the
//! pipe flows: the water in a pipe of length L carries ρ·Q·L along the pipe (mass ρAL at speed Q/A),
//! and the flow law is exactly Newton's second law for it, ΔQ·ρL = Δt·A·ΔP. A horizontal impulse J on
//! a column is therefore given to the axis pipes that join it to its neighbours, ΔQ = J/(ρL) shared
//! between the two pipes along J's axis (all to the one that exists at a wall; a one-column-wide grid
//! has no pipe along that axis and cannot take it). Away from the walls the pressure and gravity terms
//! of the flow law only move momentum between pipes (their sums telescope), so ρ Σ Q·L·e of the whole
//! grid changes only by the impulses received, the damping and the limiter (tests/water.rs).

use super::storage::each;
use super::{WaterGrid, BOX_MIN_HALF};

impl WaterGrid {
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
    /// not finite; a square of `half` ≤ `BOX_MIN_HALF`·l (a point) is deposited bilinearly, as by
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
        let (ox, oy) = self.footprint(x, y, half);
        self.spread_impulse(&ox, &oy, impulse);
    }

    /// The footprint [x ± half] × [y ± half]'s overlaps with the columns along x and along y.
    fn footprint(&self, x: f64, y: f64, half: f64) -> (Overlaps, Overlaps) {
        let ([ox, oy], l) = (self.cfg.origin, self.cfg.cell);
        (
            overlaps((x - ox) / l, half / l, self.cfg.nx),
            overlaps((y - oy) / l, half / l, self.cfg.ny),
        )
    }

    fn spread_impulse(&mut self, ox: &Overlaps, oy: &Overlaps, impulse: f64) {
        for (j, &fy) in oy.weights().iter().enumerate() {
            let row = impulse * fy;
            for (i, &fx) in ox.weights().iter().enumerate() {
                self.deposit_impulse_cell(ox.first + i, oy.first + j, row * fx);
            }
        }
    }

    fn spread_momentum(&mut self, ox: &Overlaps, oy: &Overlaps, j: [f64; 2]) {
        for (jj, &fy) in oy.weights().iter().enumerate() {
            for (ii, &fx) in ox.weights().iter().enumerate() {
                let w = fy * fx;
                self.deposit_momentum_cell(ox.first + ii, oy.first + jj, [j[0] * w, j[1] * w]);
            }
        }
    }

    /// A contact face's load: [`Self::deposit_impulse_box`] of `impulse` and
    /// [`Self::deposit_momentum_box`] of `j` over the same footprint, its overlaps with the columns
    /// found once (the same sums, in the same order, as the two calls).
    pub fn deposit_load_box(&mut self, x: f64, y: f64, half: f64, impulse: f64, j: [f64; 2]) {
        let l = self.cfg.cell;
        if !half.is_finite() || half <= BOX_MIN_HALF * l || !self.contains(x, y) {
            self.deposit_impulse_box(x, y, half, impulse);
            self.deposit_momentum_box(x, y, half, j);
            return;
        }
        let (ox, oy) = self.footprint(x, y, half);
        if impulse.is_finite() {
            self.spread_impulse(&ox, &oy, impulse);
        }
        if j[0].is_finite() && j[1].is_finite() && j != [0.0, 0.0] {
            self.spread_momentum(&ox, &oy, j);
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

    /// Horizontal impulse `j` (N·s on the water along +x and +y) spread over the square footprint
    /// [x − half, x + half] × [y − half, y + half] as [`Self::deposit_impulse_box`] spreads a vertical
    /// one (bilinearly when `half` ≤ `BOX_MIN_HALF`·l). At the next water step each column's part
    /// goes into the momentum of its axis pipes (see the module documentation). Ignored outside the
    /// grid or if not finite.
    pub fn deposit_momentum_box(&mut self, x: f64, y: f64, half: f64, j: [f64; 2]) {
        let usable = j[0].is_finite() && j[1].is_finite() && half.is_finite();
        if !usable || j == [0.0, 0.0] || !self.contains(x, y) {
            return;
        }
        let l = self.cfg.cell;
        if half <= BOX_MIN_HALF * l {
            let [(i0, i1, tx), (j0, j1, ty)] = self.bilinear(x, y);
            for (ix, iy, w) in [
                (i0, j0, (1.0 - tx) * (1.0 - ty)),
                (i1, j0, tx * (1.0 - ty)),
                (i0, j1, (1.0 - tx) * ty),
                (i1, j1, tx * ty),
            ] {
                self.deposit_momentum_cell(ix, iy, [j[0] * w, j[1] * w]);
            }
            return;
        }
        let (ox, oy) = self.footprint(x, y, half);
        self.spread_momentum(&ox, &oy, j);
    }

    /// Horizontal impulse (N·s along +x, +y) on one column; ignored outside the grid or if not
    /// finite.
    pub fn deposit_momentum_cell(&mut self, ix: usize, iy: usize, j: [f64; 2]) {
        let (nx, ny) = (self.cfg.nx, self.cfg.ny);
        if ix >= nx || iy >= ny || !(j[0].is_finite() && j[1].is_finite()) || j == [0.0, 0.0] {
            return;
        }
        if self.pending_momentum.is_empty() {
            self.pending_momentum = vec![[0.0; 2]; nx * ny];
        }
        let i = iy * nx + ix;
        if self.pending_momentum[i] == [0.0; 2] {
            self.touched_momentum.push(i);
        }
        self.pending_momentum[i][0] += j[0];
        self.pending_momentum[i][1] += j[1];
    }

    /// Every horizontal impulse (N·s along +x, +y) the pipes have accepted since the grid was built.
    pub fn momentum_received(&self) -> [f64; 2] {
        self.momentum_received
    }

    /// Gives the pipes the horizontal impulses gathered since the last step: ΔQ = J/(ρL) on the axis
    /// pipes of each column, divided by the step's damping factor so that the impulse itself is not
    /// damped (it enters the flow law as a forcing term, as the pressure does).
    pub(super) fn apply_pending_momentum(&mut self) {
        if self.touched_momentum.is_empty() {
            return;
        }
        let (nx, ny, l) = (self.cfg.nx, self.cfg.ny, self.cfg.cell);
        let damp = if self.co.damp > 1e-12 {
            self.co.damp
        } else {
            1.0
        };
        let scale = 1.0 / (self.cfg.density * l * damp);
        let mut touched = std::mem::take(&mut self.touched_momentum);
        for &i in &touched {
            let j = std::mem::take(&mut self.pending_momentum[i]);
            let (ix, iy) = (i % nx, i / nx);
            // Field 1: the +x pipe a column owns, field 2: its +y pipe.
            let along_x = [
                (ix > 0).then(|| (ix - 1, iy)),
                (ix + 1 < nx).then_some((ix, iy)),
            ];
            let along_y = [
                (iy > 0).then(|| (ix, iy - 1)),
                (iy + 1 < ny).then_some((ix, iy)),
            ];
            for (axis, pipes) in [(0, along_x), (1, along_y)] {
                let n = pipes.iter().flatten().count();
                if n == 0 || j[axis] == 0.0 {
                    continue;
                }
                let dq = j[axis] * scale / n as f64;
                for &(px, py) in pipes.iter().flatten() {
                    let k = self.co.at(px, py, axis + 1);
                    each!(&mut self.state, f => f.set(k, f.get(k) + dq));
                }
                self.momentum_received[axis] += j[axis];
            }
        }
        touched.clear();
        self.touched_momentum = touched;
    }

    pub(super) fn apply_pending_pressure(&mut self) {
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

    pub(super) fn clear_pressure(&mut self) {
        let (nx, w) = (self.cfg.nx, self.co.w());
        let len = self.cfg.ny * w;
        for &i in &self.touched {
            let (iy, ix) = (i / nx, i % nx);
            each!(&mut self.state, f => f.set_press(len, iy * w + 1 + ix, 0.0));
            self.row_press[iy] = false;
        }
        self.touched.clear();
    }
}

/// The fractions of a footprint's interval over a row of cells, from cell `first` on (inline up to
/// [`Overlaps::INLINE`] cells, so a face's footprint, which spans one or two, allocates nothing).
struct Overlaps {
    first: usize,
    len: usize,
    inline: [f64; Overlaps::INLINE],
    spill: Vec<f64>,
}

impl Overlaps {
    const INLINE: usize = 4;

    fn weights(&self) -> &[f64] {
        if self.spill.is_empty() {
            &self.inline[..self.len]
        } else {
            &self.spill
        }
    }
}

/// 1D overlaps of the interval [c − h, c + h] (in cells from the grid's edge, c in [0, n)) with the
/// cells [i, i + 1) of a row of n, as fractions of the interval: the first cell index and the
/// fractions from it on. The first and last cells of the row extend to ∓∞, so what lies beyond the
/// edge goes to them. The cells' bounds are the clamped interval's, so the fractions telescope to 1.
fn overlaps(c: f64, h: f64, n: usize) -> Overlaps {
    let (lo, hi) = (c - h, c + h);
    let last = n - 1;
    // ⌊lo⌋ and ⌈hi⌉ without libm's floor and ceil (a call each on plain x86-64): the cast
    // truncates, which is the floor for lo ≥ 0, and saturates at 0 below it and for NaN, as
    // ⌊lo⌋.max(0) does; ⌈hi⌉ is the truncation, plus one when hi has a fraction, and 1 for
    // hi ≤ 1 or NaN, as ⌈hi⌉.max(1) is.
    let i0 = (lo.max(0.0) as usize).min(last);
    let up = if hi > 1.0 {
        let t = hi as usize;
        if (t as f64) < hi {
            t.saturating_add(1)
        } else {
            t
        }
    } else {
        1
    };
    let i1 = (up - 1).clamp(i0, last);
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
    let weight = |i: usize| (bound(i + 1) - bound(i)) / span;
    let len = i1 - i0 + 1;
    let mut out = Overlaps {
        first: i0,
        len,
        inline: [0.0; Overlaps::INLINE],
        spill: Vec::new(),
    };
    if len <= Overlaps::INLINE {
        for (k, w) in out.inline.iter_mut().take(len).enumerate() {
            *w = weight(i0 + k);
        }
    } else {
        out.spill = (i0..=i1).map(weight).collect();
    }
    out
}

#[cfg(test)]
mod tests {
    /// The first and last cells of [`super::overlaps`] are those of ⌊lo⌋ and ⌈hi⌉ themselves.
    #[test]
    fn overlap_cells_are_floor_and_ceil() {
        let values = [
            -3.5,
            -1.0,
            -0.5,
            -0.0,
            0.0,
            0.25,
            0.999_999_999,
            1.0,
            1.5,
            2.0,
            2.000_000_1,
            7.0,
            9.75,
            11.0,
            1e30,
            f64::INFINITY,
        ];
        for &c in &values {
            for h in [0.0, 0.1, 0.5, 1.0, 2.5] {
                let (lo, hi) = (c - h, c + h);
                if lo.is_nan() || hi.is_nan() {
                    continue;
                }
                let last = 11;
                let i0 = (lo.floor().max(0.0) as usize).min(last);
                let i1 = ((hi.ceil().max(1.0) as usize) - 1).clamp(i0, last);
                let o = super::overlaps(c, h, 12);
                assert_eq!(o.first, i0, "c {c} h {h}");
                assert_eq!(o.first + o.len - 1, i1, "c {c} h {h}");
            }
        }
    }
}
