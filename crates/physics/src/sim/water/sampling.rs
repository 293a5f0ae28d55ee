//! Readings of the water: the surface η (per column and bilinear between column centres), depths,
//! flows, bed and volume, all in f64 whatever the storage precision.

use super::storage::each;
use super::WaterGrid;

/// η (m) of a rectangle of a grid's columns at one revision of its surface ([`WaterGrid::fill_patch`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct EtaPatch {
    ix0: usize,
    iy0: usize,
    nx: usize,
    ny: usize,
    revision: u64,
    /// Row-major from (ix0, iy0).
    eta: Vec<f64>,
}

impl EtaPatch {
    fn holds(&self, i0: usize, i1: usize, j0: usize, j1: usize) -> bool {
        i0 >= self.ix0 && i1 < self.ix0 + self.nx && j0 >= self.iy0 && j1 < self.iy0 + self.ny
    }
    /// η of column (ix, iy), which the patch holds.
    #[inline]
    pub fn at(&self, ix: usize, iy: usize) -> f64 {
        self.eta[(iy - self.iy0) * self.nx + (ix - self.ix0)]
    }
    /// The columns held: (first ix, first iy, count in x, count in y).
    #[cfg(test)]
    pub(crate) fn bounds(&self) -> (usize, usize, usize, usize) {
        (self.ix0, self.iy0, self.nx, self.ny)
    }
}

/// Bilinear readings of a grid's surface through a current [`EtaPatch`], with the grid's bounds
/// and the patch's column range turned into coordinates once: a point whose four columns the patch
/// holds costs a few comparisons and four loads, and gives [`WaterGrid::surface_height`]'s value bit
/// for bit (the same expressions); any other point is read from the grid as before.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PatchReader<'a> {
    grid: &'a WaterGrid,
    patch: &'a EtaPatch,
    /// The grid's lower corner (its origin).
    lo: [f64; 2],
    cell: f64,
    /// The fractional column coordinates f (as [`WaterGrid::bilinear`] forms them) whose four
    /// columns lie in the patch without clamping: f ∈ [first, last).
    first: [f64; 2],
    last: [f64; 2],
}

impl<'a> PatchReader<'a> {
    /// A reader of `grid` through `patch` (a stale or empty patch sends every reading to the grid).
    pub fn new(grid: &'a WaterGrid, patch: &'a EtaPatch) -> Self {
        let [ox, oy] = grid.cfg.origin;
        let l = grid.cfg.cell;
        let usable = patch.revision == grid.revision && patch.nx >= 2 && patch.ny >= 2;
        let (first, last) = if usable {
            (
                [patch.ix0 as f64, patch.iy0 as f64],
                [
                    (patch.ix0 + patch.nx - 1) as f64,
                    (patch.iy0 + patch.ny - 1) as f64,
                ],
            )
        } else {
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2])
        };
        Self {
            grid,
            patch,
            lo: [ox, oy],
            cell: l,
            first,
            last,
        }
    }

    /// [`WaterGrid::surface_height`] at world (x, y).
    #[inline]
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let fx = (x - self.lo[0]) / self.cell - 0.5;
        let fy = (y - self.lo[1]) / self.cell - 0.5;
        // Inside the patch f ≥ 0 and f < n − 1, so the point is over the grid, `bilinear`'s
        // clamps change nothing, its floor is the cast and i0 + 1 is the next column. Any other
        // point (off the grid: 0, NaN) is read as the grid reads it.
        if !(fx >= self.first[0] && fx < self.last[0] && fy >= self.first[1] && fy < self.last[1]) {
            return self.grid.surface_height_in(Some(self.patch), x, y);
        }
        // 0 ≤ f < n: the signed conversion is one instruction and the same floor.
        let (i0, j0) = (fx as i64 as usize, fy as i64 as usize);
        let (tx, ty) = (fx - i0 as f64, fy - j0 as f64);
        let p = self.patch;
        let at = (j0 - p.iy0) * p.nx + (i0 - p.ix0);
        let (e00, e10) = (p.eta[at], p.eta[at + 1]);
        let (e01, e11) = (p.eta[at + p.nx], p.eta[at + p.nx + 1]);
        let a = e00 + tx * (e10 - e00);
        let b = e01 + tx * (e11 - e01);
        a + ty * (b - a)
    }

    /// [`WaterGrid::max_height_in`] over the rectangle [lo, hi].
    pub fn max_height_over(&self, lo: [f64; 2], hi: [f64; 2]) -> Option<f64> {
        self.grid.max_height_in(self.patch, lo, hi)
    }
}

impl WaterGrid {
    /// Column indices and weights for bilinear sampling on column centres; points in the outer half
    /// cell take the edge column's value.
    pub(super) fn bilinear(&self, x: f64, y: f64) -> [(usize, usize, f64); 2] {
        let l = self.cfg.cell;
        let axis = |p: f64, o: f64, n: usize| {
            let f = ((p - o) / l - 0.5).clamp(0.0, (n - 1) as f64);
            // f ≥ 0 (or NaN, which casts to 0 as its floor does), so the cast is the floor without
            // the libm call.
            let i0 = (f as usize).min(n.saturating_sub(2));
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
        self.geometry().contains(x, y)
    }

    /// Surface elevation η (m) above the rest level z = 0 at world (x, y), bilinear between column
    /// centres; 0 outside the grid.
    pub fn surface_height(&self, x: f64, y: f64) -> f64 {
        self.surface_height_in(None, x, y)
    }

    /// [`WaterGrid::surface_height`], reading the columns from `patch` where it holds them and is
    /// current (the same values, so the same result bit for bit), from the grid elsewhere.
    pub(crate) fn surface_height_in(&self, patch: Option<&EtaPatch>, x: f64, y: f64) -> f64 {
        if !self.contains(x, y) {
            return 0.0;
        }
        let [(i0, i1, tx), (j0, j1, ty)] = self.bilinear(x, y);
        let held = patch.filter(|p| p.revision == self.revision && p.holds(i0, i1, j0, j1));
        let [e00, e10, e01, e11] = match held {
            Some(p) => [p.at(i0, j0), p.at(i1, j0), p.at(i0, j1), p.at(i1, j1)],
            None => {
                // The four columns in one pass over the storage (the same values `eta` gives).
                let (co, h) = (&self.co, self.cfg.depth);
                each!(&self.state, f => [
                    f.eta_at(co, h, i0, j0),
                    f.eta_at(co, h, i1, j0),
                    f.eta_at(co, h, i0, j1),
                    f.eta_at(co, h, i1, j1),
                ])
            }
        };
        let a = e00 + tx * (e10 - e00);
        let b = e01 + tx * (e11 - e01);
        a + ty * (b - a)
    }

    /// The highest η the surface ([`WaterGrid::surface_height`]) takes over the world rectangle
    /// [lo, hi], from the columns `patch` holds: the bilinear surface at a point is a weighted
    /// mean of the four columns [`WaterGrid::bilinear`] picks there, and those indices grow with
    /// the coordinate, so the columns picked anywhere in the rectangle lie between those picked
    /// at its corners; 0 counts where the rectangle reaches past the grid. `None` when the patch
    /// is stale or does not hold those columns.
    pub(crate) fn max_height_in(
        &self,
        patch: &EtaPatch,
        lo: [f64; 2],
        hi: [f64; 2],
    ) -> Option<f64> {
        if patch.revision != self.revision || !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
            return None;
        }
        let [(i0, _, _), (j0, _, _)] = self.bilinear(lo[0], lo[1]);
        let [(_, i1, _), (_, j1, _)] = self.bilinear(hi[0], hi[1]);
        if !patch.holds(i0, i1, j0, j1) {
            return None;
        }
        let inside = self.contains(lo[0], lo[1]) && self.contains(hi[0], hi[1]);
        let mut m = if inside { f64::NEG_INFINITY } else { 0.0 };
        for iy in j0..=j1 {
            let row = (iy - patch.iy0) * patch.nx;
            for &e in &patch.eta[row + (i0 - patch.ix0)..=row + (i1 - patch.ix0)] {
                m = m.max(e);
            }
        }
        Some(m)
    }

    /// Copies η of the columns [x0, x1] × [y0, y1] (clamped to the grid) into `patch`, tagged with
    /// the surface's revision: a stone stepping over a still surface reads it many times a tick.
    pub(crate) fn fill_patch(
        &self,
        patch: &mut EtaPatch,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
    ) {
        let (x1, y1) = (x1.min(self.cfg.nx - 1), y1.min(self.cfg.ny - 1));
        patch.eta.clear();
        patch.revision = self.revision;
        if x0 > x1 || y0 > y1 {
            patch.nx = 0;
            patch.ny = 0;
            return;
        }
        (patch.ix0, patch.iy0, patch.nx, patch.ny) = (x0, y0, x1 - x0 + 1, y1 - y0 + 1);
        let (co, h) = (&self.co, self.cfg.depth);
        each!(&self.state, f => {
            for iy in y0..=y1 {
                patch.eta.extend((x0..=x1).map(|ix| f.eta_at(co, h, ix, iy)));
            }
        });
    }

    /// η (m) of column (ix, iy): bed + depth, relative to the rest level; 0 outside the grid.
    pub fn eta(&self, ix: usize, iy: usize) -> f64 {
        if ix >= self.cfg.nx || iy >= self.cfg.ny {
            return 0.0;
        }
        let (co, h) = (&self.co, self.cfg.depth);
        each!(&self.state, f => f.eta_at(co, h, ix, iy))
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
    pub(super) fn at(&self, ix: usize, iy: usize, f: usize) -> usize {
        self.co.at(ix, iy, f)
    }
}
