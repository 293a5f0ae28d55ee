//! The water step's kernel: one fused, in-place sweep over rows (flows → limiter → limited flows →
//! depths), cut into chunks run by rayon, bit-identical for any chunking (see the module documentation
//! of [`super`]).

use rayon::prelude::*;

use super::storage::{Coeffs, Fields, Num, Real, Scratch};

/// The coefficients of one step in the kernel's arithmetic type, converted once per step.
#[derive(Debug, Clone, Copy)]
pub(super) struct Kc<C> {
    pub(super) damp: C,
    pub(super) gd: C,
    pub(super) pd: C,
    pub(super) beta: C,
    /// The axis pipes' Δt·gA/L and Δt·A/(ρL).
    pub(super) gx: C,
    pub(super) px: C,
    /// The same for the x pipes of a row with 0, 1 or 2 walls (they take the mirrored diagonals).
    pub(super) gx_row: [C; 3],
    pub(super) px_row: [C; 3],
    /// The same for the y pipes of the first and last column.
    pub(super) gy_edge: C,
    pub(super) py_edge: C,
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

impl<T: Real> Fields<T> {
    /// One step (see [`WaterGrid::step`]) over the rows of `chunks` (contiguous, ascending) and the padded columns `cols`
    /// ([c0, c1) ⊆ [1, nx + 1)); everything outside must be at rest with its neighbours (the grid's
    /// active window guarantees it), so it keeps its values.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn step(
        &mut self,
        co: &Coeffs,
        chunks: &[(usize, usize)],
        cols: (usize, usize),
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
        let whole = chunks.len() == 1 && chunks[0] == (0, co.ny);
        for (&(r0, r1), s) in chunks
            .iter()
            .zip(self.scratch.iter_mut())
            .skip(usize::from(whole))
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
        let Some(&(first, _)) = chunks.first() else {
            return;
        };
        if chunks.len() == 1 {
            let (r0, r1) = chunks[0];
            if let Some(s) = self.scratch.first_mut() {
                let own = &mut self.cur[r0 * stride..r1 * stride];
                run_chunk(co, &kc, &input, (r0, r1), cols, own, s);
            }
        } else {
            let mut parts: Vec<(usize, usize, &mut [T], &mut Scratch<T>)> =
                Vec::with_capacity(chunks.len());
            let mut rest: &mut [T] = &mut self.cur[first * stride..];
            for (&(r0, r1), s) in chunks.iter().zip(self.scratch.iter_mut()) {
                let (head, tail) = rest.split_at_mut((r1 - r0) * stride);
                parts.push((r0, r1, head, s));
                rest = tail;
            }
            parts
                .into_par_iter()
                .for_each(|(r0, r1, out, s)| run_chunk(co, &kc, &input, (r0, r1), cols, out, s));
        }
    }
}

/// Read-only inputs of one step.
pub(super) struct Input<'a, T> {
    bed: Option<&'a [T]>,
    press: Option<&'a [T]>,
    row_bed: &'a [bool],
    row_press: &'a [bool],
}

pub(super) fn run_chunk<T: Real>(
    co: &Coeffs,
    kc: &Kc<T::Calc>,
    input: &Input<T>,
    rows: (usize, usize),
    cols: (usize, usize),
    own: &mut [T],
    s: &mut Scratch<T>,
) {
    if co.nf == 5 {
        chunk::<T, true>(co, kc, input, rows, cols, own, s);
    } else {
        chunk::<T, false>(co, kc, input, rows, cols, own, s);
    }
}

/// Old row block `j` as seen by the chunk [r0, r1) at row `at`: the copies of the two rows on either
/// side, or the chunk's own rows from `at` on (`tail`), which are not overwritten yet.
#[inline]
pub(super) fn old_row<'a, T>(
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
/// zero flows, which is what the rows before the grid carry. Only the padded columns [c0, c1) are
/// computed: the buffers hold zero flows and K = 1 beyond them, which is what water at rest has.
pub(super) fn chunk<T: Real, const DIAG: bool>(
    co: &Coeffs,
    kc: &Kc<T::Calc>,
    input: &Input<T>,
    (r0, r1): (usize, usize),
    (c0, c1): (usize, usize),
    own: &mut [T],
    s: &mut Scratch<T>,
) {
    let ny = co.ny;
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
        let mut a = c0;
        loop {
            let b = (a + co.seg).min(c1);
            if real {
                flows::<T, DIAG>(co, kc, input, j, a, b, row, ha, hb, qn_j);
                if limit {
                    limiter::<T, DIAG>(k_j, &row[..w], qn_j, qn_prev, w, kc.beta, a, b);
                }
            }
            // F and D lag one column behind: [a − 1, b − 1), and the last column at the end.
            let fb = if b == c1 { c1 } else { b - 1 };
            let fa = if a == c0 { c0 } else { a - 1 };
            if finish && fa < fb {
                finalize::<T, DIAG>(f_out, qn_prev, k_prev, k_j, w, fa, fb);
                if mine {
                    depth::<T, DIAG>(d_out, f_out, before, w, kc.beta, fa, fb);
                }
            }
            if b == c1 {
                break;
            }
            a = b;
        }
    }
}

/// A(j) on padded columns [a, b): the new, unlimited flows of row j's pipes into `qn` ([pipe][w]), from
/// the old flows of row j and the surfaces `h0`, `h1` of rows j and j + 1 (padded).
#[allow(clippy::too_many_arguments)]
pub(super) fn flows<T: Real, const DIAG: bool>(
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
pub(super) fn edges(nx: usize) -> impl Iterator<Item = usize> {
    [1, nx].into_iter().take(if nx == 1 { 1 } else { 2 })
}

/// h = depth + bed on a padded row.
pub(super) fn surface<T: Real>(h: &mut [T], d: &[T], bed: Option<&[T]>, at: usize) {
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
pub(super) fn grad<T: Real>(
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
pub(super) fn add_grad<T: Real>(
    qn: &mut [T],
    p0: &[T],
    p1: &[T],
    off: isize,
    c: T::Calc,
    a: usize,
    b: usize,
) {
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
pub(super) fn pos<C: Num>(x: C) -> C {
    if x > C::ZERO {
        x
    } else {
        C::ZERO
    }
}

/// min(x, 0) as a plain compare.
#[inline(always)]
pub(super) fn neg<C: Num>(x: C) -> C {
    if x < C::ZERO {
        x
    } else {
        C::ZERO
    }
}

/// K = min(1, cap/out), cap = max(depth, 0): never NaN (out > cap ≥ 0 before dividing).
#[inline(always)]
pub(super) fn kfactor<C: Num>(depth: C, out: C) -> C {
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
pub(super) fn limiter<T: Real, const DIAG: bool>(
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
pub(super) fn finalize<T: Real, const DIAG: bool>(
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
/// (`own`) and row j − 1 (`before`), pipes in opposite pairs; then max(0, ·). Under the paper's
/// limiter that is its eq. 41 clamp; under Mei's K a column gives at most what it holds, so the
/// update can only round below zero (finding W1 of docs/reliability.md: −1.7e-18 m in f64, −1.9e-9 m
/// in f32), and the clamp trims that rounding, keeping the grid's contract d ≥ 0.
pub(super) fn depth<T: Real, const DIAG: bool>(
    d: &mut [T],
    own: &[T],
    before: &[T],
    w: usize,
    beta: T::Calc,
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
    for v in d.iter_mut() {
        *v = T::down(pos(v.up()));
    }
}
