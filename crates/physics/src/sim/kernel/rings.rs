//! The free-rotation path for a body of revolution (disk, lens): the mesh is rings of vertices
//! at azimuths 2πj/n joined by strips of faces. In the stone's frame, with u the water's up
//! direction turned into it, ring k's vertex j stands at height B_k + r_k s_j above the
//! surface, s_j = u_x cos(2πj/n) + u_y sin(2πj/n) the same for every ring: its wet vertices
//! are one arc of azimuths about the lowest, the same centre M on every ring. Each ring's
//! surely wet arc (height below −δ) and the arc outside which every vertex is surely dry
//! (above +δ, δ far above rounding) are read off running maxima and minima of s over the
//! offsets from M, so every strip's wholly wet faces are one column range, found in O(1)
//! without visiting a face; only the columns between the two arcs (the waterline and a margin
//! of one column) are classified from their exact heights and clipped, as the reference does.
//! The layout comes from the mesh builder ([`super::super::stone::revolution_layout`]) and is
//! checked against the mesh here (topology, and every vertex within 1e-13 of its ring).

use glam::DVec3;

use super::{
    dot, finish, frame, wet_faces, Acc, Call, Ctx, FaceLoad, FaceSoa, ForceSum, KernelMesh,
    KernelScratch, Mesh, LANES,
};
use crate::sim::mesh::RevolutionLayout;

/// A ring of vertices: centre (x, y), height z and radius r in the body frame (r = 0: a pole).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ring {
    cx: f64,
    cy: f64,
    z: f64,
    r: f64,
}

/// The faces between two rings: `per_column` faces for each of the n columns, from `start` in
/// [`Revolution::faces`].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Strip {
    rings: [usize; 2],
    start: usize,
    per_column: usize,
}

/// The body of revolution's faces in strip and column order, with its rings.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Revolution {
    n: usize,
    cos: Vec<f64>,
    sin: Vec<f64>,
    rings: Vec<Ring>,
    strips: Vec<Strip>,
    pub(super) faces: FaceSoa,
    /// Largest |coordinate| of a vertex (m).
    reach: f64,
    /// Every vertex of the mesh is on a ring.
    all_on_rings: bool,
}

impl Revolution {
    /// From the centred mesh, its normals and areas and the builder's layout; `None` when the
    /// layout does not describe the mesh.
    pub(super) fn new(
        mesh: &Mesh,
        normals: &[DVec3],
        areas: &[f64],
        layout: &RevolutionLayout,
        reach: f64,
    ) -> Option<Self> {
        let n = layout.segments;
        let angle = |j: usize| std::f64::consts::TAU * j as f64 / n as f64;
        let cos: Vec<f64> = (0..n).map(|j| angle(j).cos()).collect();
        let sin: Vec<f64> = (0..n).map(|j| angle(j).sin()).collect();
        let tol = 1e-13 * reach;
        let mut rings = Vec::with_capacity(layout.rings.len());
        for ids in &layout.rings {
            let pts: Vec<DVec3> = ids
                .iter()
                .map(|&i| mesh.positions.get(i as usize).copied())
                .collect::<Option<_>>()?;
            if pts.len() != 1 && pts.len() != n {
                return None;
            }
            let k = pts.len() as f64;
            let (cx, cy) = (
                pts.iter().map(|p| p.x).sum::<f64>() / k,
                pts.iter().map(|p| p.y).sum::<f64>() / k,
            );
            let r = if pts.len() == 1 {
                0.0
            } else {
                pts.iter().map(|p| (p.x - cx).hypot(p.y - cy)).sum::<f64>() / k
            };
            let ring = Ring {
                cx,
                cy,
                z: pts[0].z,
                r,
            };
            let fits = pts.iter().enumerate().all(|(j, p)| {
                let ideal = DVec3::new(cx + r * cos[j], cy + r * sin[j], ring.z);
                (*p - ideal).abs().max_element() <= tol
            });
            if !fits {
                return None;
            }
            rings.push(ring);
        }
        let mut seen = vec![false; mesh.triangles.len()];
        let mut faces = FaceSoa::default();
        let mut strips = Vec::with_capacity(layout.strips.len());
        for ([a, b], columns) in &layout.strips {
            let per_column = columns.first().map_or(0, Vec::len);
            if columns.len() != n || per_column == 0 {
                return None;
            }
            let (ra, rb) = (layout.rings.get(*a)?, layout.rings.get(*b)?);
            strips.push(Strip {
                rings: [*a, *b],
                start: faces.len(),
                per_column,
            });
            for (j, tris) in columns.iter().enumerate() {
                let corner = |ring: &Vec<u32>, o: usize| ring[(j + o) % ring.len()];
                let allowed = [corner(ra, 0), corner(ra, 1), corner(rb, 0), corner(rb, 1)];
                if tris.len() != per_column {
                    return None;
                }
                for &t in tris {
                    let tri = *mesh.triangles.get(t as usize)?;
                    if seen[t as usize] || !tri.iter().all(|v| allowed.contains(v)) {
                        return None;
                    }
                    seen[t as usize] = true;
                    let t = t as usize;
                    faces.push(
                        tri.map(|i| mesh.positions[i as usize]),
                        normals[t],
                        areas[t],
                        tri,
                    );
                }
            }
        }
        if !seen.iter().all(|&s| s) {
            return None;
        }
        let mut on_ring = vec![false; mesh.positions.len()];
        for &i in layout.rings.iter().flatten() {
            on_ring[i as usize] = true;
        }
        Some(Self {
            n,
            cos,
            sin,
            rings,
            strips,
            faces,
            reach,
            all_on_rings: on_ring.iter().all(|&v| v),
        })
    }

    /// How far the lowest vertex's clearance can stand above that of the rings themselves (every
    /// point of every ring, each turned onto the symmetry axis), over a surface of slope at most
    /// `slope` (see `integrate::RevolutionBound`): the nearest vertex to any ring point is at most
    /// the chord 2r sin(π/2n) away, over which a height and the surface under it change by
    /// (1 + S) times that; on flat water the sampled cosine's own gap, r(1 − cos π/n). A ring
    /// centred off the axis (by rounding) adds twice its offset. `None` when a vertex is on no
    /// ring.
    pub(super) fn facet_gap(&self, slope: f64) -> Option<f64> {
        if !self.all_on_rings {
            return None;
        }
        let half = std::f64::consts::PI / self.n as f64;
        let tol = 1e-13 * self.reach;
        let gap = self
            .rings
            .iter()
            .map(|g| {
                let off = g.cx.hypot(g.cy) + tol;
                let sampled = if slope == 0.0 {
                    g.r * (1.0 - half.cos())
                } else {
                    2.0 * g.r * (0.5 * half).sin() * (1.0 + slope)
                };
                sampled + 2.0 * off * (1.0 + slope)
            })
            .fold(0.0, f64::max);
        Some(gap + 1e-12 * self.reach)
    }
}

/// An arc of vertex (or column) offsets from M, inclusive; empty when lo > hi.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Arc {
    lo: i64,
    hi: i64,
}

impl Arc {
    const EMPTY: Arc = Arc { lo: 1, hi: 0 };
    const FULL: Arc = Arc {
        lo: -(1 << 40),
        hi: 1 << 40,
    };
    fn is_empty(self) -> bool {
        self.lo > self.hi
    }
}

/// Per evaluation: s over the offsets from M, with its running maxima from M outwards (for the
/// surely wet arcs) and minima from the far side inwards (for the surely dry ones).
#[derive(Debug, Clone, Default)]
pub(super) struct RingScratch {
    s: Vec<f64>,
    /// Right (offsets 0..=hr) and left (offsets 0..=hl, going down) sides.
    max: [Vec<f64>; 2],
    tail: [Vec<f64>; 2],
    /// The largest and the smallest s.
    smax: f64,
    smin: f64,
    wet: Vec<Arc>,
    maybe: Vec<Arc>,
    /// Faces crossing the waterline and their corners' heights, clipped together in lanes.
    band: Vec<(u32, [f64; 3])>,
    /// Their wetted patches (normal, centroid, area), for the wholly wet faces' lanes.
    patches: FaceSoa,
}

/// The sides' lengths for n vertices: right offsets 0..=hr, left offsets 1..=hl (n = 1 + hr + hl).
fn sides(n: usize) -> [usize; 2] {
    let hr = n / 2;
    [hr, n - 1 - hr]
}

impl RingScratch {
    /// Fills the running extremes for u; returns M (the index of the lowest s).
    fn prepare(&mut self, rev: &Revolution, u: DVec3) -> usize {
        let n = rev.n;
        self.s.clear();
        self.s
            .extend((0..n).map(|j| u.x * rev.cos[j] + u.y * rev.sin[j]));
        let mut m = 0;
        for j in 1..n {
            if self.s[j] < self.s[m] {
                m = j;
            }
        }
        self.smin = self.s[m];
        let h = sides(n);
        for (side, &h) in h.iter().enumerate() {
            let at = |d: usize| {
                let j = if side == 0 { m + d } else { m + n - d };
                self.s[j % n]
            };
            let (max, tail) = (&mut self.max[side], &mut self.tail[side]);
            max.clear();
            let mut run = f64::NEG_INFINITY;
            for d in 0..=h {
                run = run.max(at(d));
                max.push(run);
            }
            tail.clear();
            tail.resize(h + 1, f64::INFINITY);
            let mut run = f64::INFINITY;
            for d in (0..h).rev() {
                run = run.min(at(d + 1));
                tail[d] = run;
            }
        }
        self.smax = self.max[0][self.max[0].len() - 1].max(self.max[1][self.max[1].len() - 1]);
        m
    }

    /// The surely wet and the possibly wet arc of a ring whose vertex heights above the
    /// surface are b + r s_j − level (wet below `wet_level` − δ, dry above `dry_level` + δ).
    fn arcs(&self, ring: &Ring, b: f64, levels: (f64, f64), delta: f64) -> (Arc, Arc) {
        let (wet_level, dry_level) = levels;
        let r = ring.r;
        let sure_wet = |s: f64| (b + r * s) - wet_level < -delta;
        let sure_dry = |s: f64| (b + r * s) - dry_level > delta;
        if sure_wet(self.smax) {
            return (Arc::FULL, Arc::FULL);
        }
        if sure_dry(self.smin) {
            return (Arc::EMPTY, Arc::EMPTY);
        }
        if r == 0.0 {
            return (Arc::EMPTY, Arc::FULL);
        }
        // Wet: the last offset on each side whose running maximum is surely wet.
        let wet = if sure_wet(self.max[0][0]) {
            let last = |m: &[f64]| m.partition_point(|&x| sure_wet(x)) as i64 - 1;
            Arc {
                lo: -last(&self.max[1]),
                hi: last(&self.max[0]),
            }
        } else {
            Arc::EMPTY
        };
        // Maybe: the first offset on each side beyond which everything is surely dry.
        let first = |t: &[f64]| t.partition_point(|&x| !sure_dry(x)) as i64;
        let maybe = Arc {
            lo: -first(&self.tail[1]),
            hi: first(&self.tail[0]),
        };
        (wet, maybe)
    }
}

/// Columns of a strip between rings with arcs `a` and `b` (offsets from M, n columns): the
/// wholly wet columns (one arc) and the columns to classify (up to two arcs).
fn columns(n: i64, a: (Arc, Arc), b: (Arc, Arc)) -> (Arc, [Arc; 2]) {
    let wet_v = Arc {
        lo: a.0.lo.max(b.0.lo),
        hi: a.0.hi.min(b.0.hi),
    };
    // Column d joins vertices d and d + 1.
    let wet = if wet_v.is_empty() {
        Arc::EMPTY
    } else {
        Arc {
            lo: wet_v.lo,
            hi: wet_v.hi - 1,
        }
    };
    if wet.hi - wet.lo + 1 >= n {
        return (Arc { lo: 0, hi: n - 1 }, [Arc::EMPTY; 2]);
    }
    let maybe_v = match (a.1.is_empty(), b.1.is_empty()) {
        (true, true) => return (wet, [Arc::EMPTY; 2]),
        (true, false) => b.1,
        (false, true) => a.1,
        (false, false) => Arc {
            lo: a.1.lo.min(b.1.lo),
            hi: a.1.hi.max(b.1.hi),
        },
    };
    let maybe = Arc {
        lo: maybe_v.lo - 1,
        hi: maybe_v.hi,
    };
    if wet.is_empty() {
        if maybe.hi - maybe.lo + 1 >= n {
            return (wet, [Arc { lo: 0, hi: n - 1 }, Arc::EMPTY]);
        }
        return (wet, [maybe, Arc::EMPTY]);
    }
    if maybe.hi - maybe.lo + 1 >= n {
        // Everything but the wet columns.
        let rest = Arc {
            lo: wet.hi + 1,
            hi: wet.lo - 1 + n,
        };
        return (wet, [rest, Arc::EMPTY]);
    }
    (
        wet,
        [
            Arc {
                lo: maybe.lo,
                hi: wet.lo - 1,
            },
            Arc {
                lo: wet.hi + 1,
                hi: maybe.hi,
            },
        ],
    )
}

/// Free rotation of a body of revolution: see the module's documentation.
pub(super) fn ring_path<const LAW: u8>(
    km: &KernelMesh,
    rev: &Revolution,
    call: &Call,
    ks: &mut KernelScratch,
    loads: &mut Vec<FaceLoad>,
) -> ForceSum {
    let pose = call.pose;
    let (rot, u) = frame(pose.orientation);
    let c = Ctx::new(km, call.hp, pose, Some(rot), call);
    let surface = call.surface;
    let flat = surface.is_flat();
    let levels = if flat {
        (0.0, 0.0)
    } else {
        (surface.min_height(), surface.max_height())
    };
    let z = pose.position.z;
    let finite = |x: f64| if x.is_finite() { x.abs() } else { 0.0 };
    let delta = 1e-12
        * (z.abs()
            + (u.x.abs() + u.y.abs() + u.z.abs()) * rev.reach
            + finite(levels.0)
            + finite(levels.1));
    let KernelScratch {
        heights,
        wet,
        rings: rs,
        ..
    } = ks;
    wet.clear();
    let mut band = std::mem::take(&mut rs.band);
    band.clear();
    let culls = c.culls_receding();
    if !flat {
        heights.start(km.vertex_count);
    }
    let m = rs.prepare(rev, u);
    let (mut wet_arcs, mut maybe_arcs) =
        (std::mem::take(&mut rs.wet), std::mem::take(&mut rs.maybe));
    wet_arcs.clear();
    maybe_arcs.clear();
    let mut in_contact = false;
    for ring in &rev.rings {
        let b = z + ((u.x * ring.cx + u.y * ring.cy) + u.z * ring.z);
        let (w, mb) = rs.arcs(ring, b, levels, delta);
        in_contact |= !w.is_empty();
        wet_arcs.push(w);
        maybe_arcs.push(mb);
    }
    let faces = &rev.faces;
    let n = rev.n as i64;
    let mut acc = Acc::default();
    let column = |d: i64| (m as i64 + d).rem_euclid(n) as usize;
    for strip in &rev.strips {
        let [a, b] = strip.rings;
        let (wet_cols, mixed) = columns(
            n,
            (wet_arcs[a], maybe_arcs[a]),
            (wet_arcs[b], maybe_arcs[b]),
        );
        let pc = strip.per_column;
        if !wet_cols.is_empty() {
            let (c0, count) = (
                column(wet_cols.lo),
                (wet_cols.hi - wet_cols.lo + 1) as usize,
            );
            let first = count.min(rev.n - c0);
            for (from, len) in [(c0, first), (0, count - first)] {
                let range = strip.start + from * pc..strip.start + (from + len) * pc;
                wet_range::<LAW>(&c, faces, range, wet, &mut acc, loads);
            }
        }
        for arc in mixed {
            for d in arc.lo..=arc.hi {
                let col = strip.start + column(d) * pc;
                for i in col..col + pc {
                    let dd = if flat {
                        let h = |k: usize| z + dot(u, faces.corner(k, i));
                        [h(0), h(1), h(2)]
                    } else {
                        // Three calls in order, not `[0, 1, 2].map`: the array map's closure
                        // is not inlined here and costs more than the lookups it makes.
                        let (verts, position) = (faces.verts[i], pose.position);
                        let mut h = |k: usize| {
                            heights.get(verts[k], surface, || position + rot * faces.corner(k, i))
                        };
                        [h(0), h(1), h(2)]
                    };
                    match dd.iter().filter(|&&x| x <= 0.0).count() {
                        0 => continue,
                        3 => wet.push(i as u32),
                        _ => {
                            if !(culls && faces.normal(i).dot(c.v) <= 0.0) {
                                band.push((i as u32, dd));
                            }
                        }
                    }
                    in_contact = true;
                }
            }
        }
    }
    rs.wet = wet_arcs;
    rs.maybe = maybe_arcs;
    wet_faces::<LAW, true>(&c, faces, 0..0, wet, &mut acc, loads);
    band_faces::<LAW>(&c, faces, &band, &mut rs.patches, &mut acc, loads);
    rs.band = band;
    if !in_contact {
        return ForceSum::default();
    }
    finish(&c, &acc, true)
}

/// The wetted part of face `i` of `faces` whose corners stand `d` above the surface, one or two
/// of them wet: area and centroid of the corner triangle cut off at the odd corner (the one wet
/// or dry alone), or of the rest. The same polygon as [`super::super::contact::clip_triangle`]'s.
#[inline(always)]
fn clipped(faces: &FaceSoa, i: usize, d: [f64; 3]) -> (f64, DVec3) {
    let wet = d.map(|x| x <= 0.0);
    let a = if wet[0] == wet[1] {
        2
    } else if wet[0] == wet[2] {
        1
    } else {
        0
    };
    let (b, e) = ((a + 1) % 3, (a + 2) % 3);
    let (t1, t2) = (d[a] / (d[a] - d[b]), d[a] / (d[a] - d[e]));
    let pa = faces.corner(a, i);
    let corner = pa + ((faces.corner(b, i) - pa) * t1 + (faces.corner(e, i) - pa) * t2) / 3.0;
    let frac = t1 * t2;
    let area = faces.area[i];
    if wet[a] {
        (area * frac, corner)
    } else {
        let rest = 1.0 - frac;
        (area * rest, (faces.centroid(i) - corner * frac) / rest)
    }
}

/// The faces crossing the waterline: clipped, then their wetted patches through the wholly wet
/// faces' lanes (padded with empty patches to whole chunks).
fn band_faces<const LAW: u8>(
    c: &Ctx,
    faces: &FaceSoa,
    band: &[(u32, [f64; 3])],
    patches: &mut FaceSoa,
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) {
    if band.is_empty() {
        return;
    }
    let len = band.len().div_ceil(LANES) * LANES;
    patches.reset_patches(len);
    for (slot, &(i, d)) in band.iter().enumerate() {
        let i = i as usize;
        let (area, g) = clipped(faces, i, d);
        for k in 0..3 {
            patches.n[k][slot] = faces.n[k][i];
            patches.g[k][slot] = g[k];
        }
        patches.area[slot] = area;
    }
    wet_faces::<LAW, true>(c, patches, 0..len, &[], acc, loads);
}

/// Wholly wet faces `range`: its whole chunks of lanes now, the rest to the gathered list.
fn wet_range<const LAW: u8>(
    c: &Ctx,
    faces: &FaceSoa,
    range: std::ops::Range<usize>,
    list: &mut Vec<u32>,
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) {
    let full = range.start + range.len() / LANES * LANES;
    wet_faces::<LAW, true>(c, faces, range.start..full, &[], acc, loads);
    list.extend((full..range.end).map(|i| i as u32));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::{Shape, StoneParams};
    use crate::sim::stone::Stone;

    fn stone(shape: Shape, segments: u32) -> Stone {
        Stone::new(&StoneParams {
            shape,
            mass: 0.1,
            segments,
            bands: None,
            quadrature: Default::default(),
        })
        .unwrap()
    }

    const LENS: Shape = Shape::Lens {
        radius: 0.05,
        thickness: 0.012,
    };
    const DISK: Shape = Shape::Disk {
        radius: 0.05,
        thickness: 0.01,
    };

    /// Disks and lenses get the ring path at every mesh (odd n included, 8 to 256 segments), holding every face
    /// once; a plate does not, nor a layout that does not describe the mesh.
    #[test]
    fn bodies_of_revolution_get_rings_and_bad_layouts_are_refused() {
        for segments in [9, 32, 64, 96, 256] {
            for shape in [LENS, DISK] {
                let s = stone(shape, segments);
                let rev = s
                    .kernel()
                    .revolution
                    .as_ref()
                    .expect("ring layout accepted");
                assert_eq!(rev.faces.len(), s.mesh.triangles.len());
            }
        }
        for (segments, bands) in [(48, 12), (40, 48)] {
            let s = Stone::new(&StoneParams {
                shape: LENS,
                mass: 0.1,
                segments,
                bands: Some(bands),
                quadrature: Default::default(),
            })
            .unwrap();
            let rev = s
                .kernel()
                .revolution
                .as_ref()
                .expect("banded lens accepted");
            assert_eq!(rev.faces.len(), s.mesh.triangles.len());
        }
        let plate = Shape::Plate {
            length: 0.1,
            width: 0.05,
            thickness: 0.01,
        };
        assert!(stone(plate, 32).kernel().revolution.is_none());
        let s = stone(LENS, 32);
        let layout = crate::sim::stone::revolution_layout(&LENS, 32, None).unwrap();
        let reach = 0.05;
        let mut swapped = layout.clone();
        swapped.rings.swap(3, 4);
        assert!(Revolution::new(&s.mesh, &s.normals, &s.areas, &swapped, reach).is_none());
        let mut rotated = layout.clone();
        rotated.rings[5].rotate_left(1);
        assert!(Revolution::new(&s.mesh, &s.normals, &s.areas, &rotated, reach).is_none());
        let mut missing = layout;
        missing.strips.pop();
        assert!(Revolution::new(&s.mesh, &s.normals, &s.areas, &missing, reach).is_none());
    }

    /// Every surely wet arc holds only vertices under the surface and every vertex outside the
    /// possibly wet arc is above it, on random tilts and depths, flat water.
    #[test]
    fn arcs_bound_the_exact_classification() {
        let s = stone(LENS, 64);
        let rev = s.kernel().revolution.as_ref().unwrap();
        let mut seed = 77u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let layout = crate::sim::stone::revolution_layout(&LENS, 64, None).unwrap();
        let mut rs = RingScratch::default();
        let (mut wet_seen, mut dry_seen) = (0, 0);
        for trial in 0..400 {
            // Near level as well as steep tilts.
            let tilt = if trial % 2 == 0 {
                1e-9 * rnd()
            } else {
                1.5 * rnd()
            };
            let q = glam::DQuat::from_rotation_z(6.3 * rnd()) * glam::DQuat::from_rotation_y(tilt);
            let (_, u) = frame(q);
            let z = 0.03 * (rnd() - 0.5);
            let m = rs.prepare(rev, u) as i64;
            let delta = 1e-12 * (z.abs() + 3.0 * rev.reach);
            for (ring, ids) in rev.rings.iter().zip(&layout.rings) {
                let b = z + ((u.x * ring.cx + u.y * ring.cy) + u.z * ring.z);
                let (wet, maybe) = rs.arcs(ring, b, (0.0, 0.0), delta);
                let n = ids.len() as i64;
                for d in -n..=n {
                    let j = (m + d).rem_euclid(n) as usize;
                    let h = z + dot(u, s.mesh.positions[ids[j] as usize]);
                    if (wet.lo..=wet.hi).contains(&d) {
                        assert!(h <= 0.0, "trial {trial}: offset {d} in the wet arc at {h}");
                        wet_seen += 1;
                    }
                    let inside = (maybe.lo..=maybe.hi).contains(&d)
                        || maybe.hi - maybe.lo + 1 >= n
                        || (maybe.lo..=maybe.hi).contains(&(d + n))
                        || (maybe.lo..=maybe.hi).contains(&(d - n));
                    if !inside {
                        assert!(h > 0.0, "trial {trial}: offset {d} outside at {h}");
                        dry_seen += 1;
                    }
                }
            }
        }
        assert!(wet_seen > 1000 && dry_seen > 1000, "{wet_seen} {dry_seen}");
    }
}
