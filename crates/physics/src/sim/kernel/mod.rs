//! The fast force kernel (issue 12): the per-face model of [`hydro::evaluate_reference`] (paper
//! eqs. 11–26: clip each face by the water, pressure and friction per wetted face, their sums),
//! organised so that only the faces the water touches are visited and the wholly wet ones run in
//! vector lanes without clipping.
//!
//! - Locked attitude (ω = 0, or an orientation already cached): the faces are turned into world
//!   axes once and sorted by their lowest vertex. Against the plane z = 0 the wholly wet faces are
//!   then a prefix and the dry ones a suffix, both found by bisection; only the band between is
//!   classified and clipped. A wavy surface bisects on its highest point and classifies the
//!   candidates from the grid's heights (looked up once per vertex).
//! - Free rotation: the water plane and the velocities are turned into the stone's own frame (no
//!   vertex is rotated). A disk or a lens goes by its rings (`rings.rs`: each strip's wholly wet
//!   faces are one column range found without visiting a face, only the waterline columns are
//!   classified and clipped); a plate by a hierarchy of bounding boxes (positions and normals,
//!   body frame) that culls the dry part and passes wholly wet boxes to the lanes unclassified.
//! - [`lowest_clearance`] and [`underside_submerged`] search the same hierarchies, and return
//!   exactly what the reference versions return (they evaluate the same floating-point
//!   expressions for the candidates, and the bounds carry a margin far above rounding).
//!
//! The law itself is mirrored in lanes (`lane_law`, the same operations in the same order as
//! `law::face_force`, so each face's force is bit-identical to it); `fast_path_supports`
//! names every [`HydroParams`] field, so a new option does not compile until it is either
//! implemented here or sent to the reference. Lanes are four wide whatever the machine, and no
//! fused multiply-add is used, so the AVX2 and the plain x86-64 builds give identical bits.
//!
//! [`hydro::evaluate_reference`]: super::hydro::evaluate_reference

use glam::{DMat3, DQuat, DVec3};

use super::contact::clip_triangle;
use super::law::{pressure_sign, FaceLoad, ForceSum, HydroParams, Pose, Surface};
use super::mesh::{Mesh, RevolutionLayout};
use super::params::ForceLaw;

mod rings;

/// Width of the vector lanes (f64).
pub(crate) const LANES: usize = 4;
/// Most faces (or vertices) in a leaf of a hierarchy.
const LEAF: usize = 16;
const NO_CHILD: u32 = u32::MAX;

/// True when the fast kernel implements every option of `hp`; otherwise [`hydro::evaluate`] uses
/// the reference. Every field is named: a field added to [`HydroParams`] stops this compiling
/// until it is handled (return false for any value the kernel does not implement).
///
/// [`hydro::evaluate`]: super::hydro::evaluate
pub(crate) fn fast_path_supports(hp: &HydroParams) -> bool {
    // The kernel takes these as they are: the lanes' law mirrors `face_force` for every law
    // (tested bit for bit), ventilation either way, either pressure sign, smooth or
    // faceted spin, with or without buoyancy, on the loaded or on every wetted face.
    let HydroParams {
        law,
        lift: _,
        friction: _,
        density: _,
        ventilated: _,
        opposing: _,
        smooth_spin: _,
        rho_g: _,
        hydrostatic_wetted: _,
    } = *hp;
    match law {
        ForceLaw::Paper | ForceLaw::Bocquet | ForceLaw::Rosellini => true,
    }
}

/// `u·p` in the order glam evaluates `(R p).z` when `u` is R's last row: a vertex's height offset
/// bit-identical to the reference's.
#[inline(always)]
fn dot(u: DVec3, p: DVec3) -> f64 {
    (u.x * p.x + u.y * p.y) + u.z * p.z
}

/// A box of a hierarchy: positions (body frame) and, for faces, outward normals.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    centre: DVec3,
    half: DVec3,
    ncentre: DVec3,
    nhalf: DVec3,
    start: u32,
    end: u32,
    left: u32,
    right: u32,
}

impl Node {
    /// Bounds of u·p over the box (exact arithmetic; callers add the margin).
    #[inline]
    fn bound(&self, u: DVec3) -> (f64, f64) {
        let m = u.dot(self.centre);
        let r = u.x.abs() * self.half.x + u.y.abs() * self.half.y + u.z.abs() * self.half.z;
        (m - r, m + r)
    }
    #[inline]
    fn normal_bound(&self, u: DVec3) -> (f64, f64) {
        let m = u.dot(self.ncentre);
        let r = u.x.abs() * self.nhalf.x + u.y.abs() * self.nhalf.y + u.z.abs() * self.nhalf.z;
        (m - r, m + r)
    }
    fn is_leaf(&self) -> bool {
        self.left == NO_CHILD
    }
    fn range(&self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// One item to place in a hierarchy: its sort key and the boxes of its points and normal.
#[derive(Debug, Clone, Copy)]
struct Item {
    key: DVec3,
    lo: DVec3,
    hi: DVec3,
    nlo: DVec3,
    nhi: DVec3,
}

/// Median-split hierarchy over `items`: returns the nodes (root first) and the items' order.
fn build_hierarchy(items: &[Item]) -> (Vec<Node>, Vec<usize>) {
    let mut order: Vec<usize> = (0..items.len()).collect();
    let mut nodes = Vec::new();
    if !items.is_empty() {
        build_node(items, &mut order, 0, items.len(), &mut nodes);
    }
    (nodes, order)
}

fn build_node(
    items: &[Item],
    order: &mut [usize],
    start: usize,
    end: usize,
    nodes: &mut Vec<Node>,
) -> u32 {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (mut nlo, mut nhi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (mut klo, mut khi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for &i in &order[start..end] {
        let it = &items[i];
        lo = lo.min(it.lo);
        hi = hi.max(it.hi);
        nlo = nlo.min(it.nlo);
        nhi = nhi.max(it.nhi);
        klo = klo.min(it.key);
        khi = khi.max(it.key);
    }
    let index = nodes.len() as u32;
    nodes.push(Node {
        centre: (lo + hi) * 0.5,
        half: (hi - lo) * 0.5,
        ncentre: (nlo + nhi) * 0.5,
        nhalf: (nhi - nlo) * 0.5,
        start: start as u32,
        end: end as u32,
        left: NO_CHILD,
        right: NO_CHILD,
    });
    if end - start <= LEAF {
        return index;
    }
    let extent = khi - klo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    // Split at a multiple of the lane width so whole boxes fill the lanes: the items below the
    // split along the axis go left (a deterministic selection, ties by index).
    let count = end - start;
    let mid = start + ((count / 2).div_ceil(LANES) * LANES).min(count - 1);
    order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
        items[a].key[axis]
            .total_cmp(&items[b].key[axis])
            .then(a.cmp(&b))
    });
    let left = build_node(items, order, start, mid, nodes);
    let right = build_node(items, order, mid, end, nodes);
    nodes[index as usize].left = left;
    nodes[index as usize].right = right;
    index
}

/// Faces as struct-of-arrays: corners `pos[corner][axis]`, normal, area centroid, area and the
/// mesh vertex indices of the corners.
#[derive(Debug, Clone, PartialEq, Default)]
struct FaceSoa {
    pos: [[Vec<f64>; 3]; 3],
    n: [Vec<f64>; 3],
    g: [Vec<f64>; 3],
    area: Vec<f64>,
    verts: Vec<[u32; 3]>,
}

impl FaceSoa {
    fn len(&self) -> usize {
        self.area.len()
    }

    fn push(&mut self, corners: [DVec3; 3], normal: DVec3, area: f64, verts: [u32; 3]) {
        let g = (corners[0] + corners[1] + corners[2]) * (1.0 / 3.0);
        for (k, c) in corners.iter().enumerate() {
            for a in 0..3 {
                self.pos[k][a].push(c[a]);
            }
        }
        for a in 0..3 {
            self.n[a].push(normal[a]);
            self.g[a].push(g[a]);
        }
        self.area.push(area);
        self.verts.push(verts);
    }

    /// Normals, centroids and areas only (the wetted patches of clipped faces), `len` of them, every
    /// one zero (an empty patch) until set.
    fn reset_patches(&mut self, len: usize) {
        for col in self.n.iter_mut().chain(&mut self.g) {
            col.clear();
            col.resize(len, 0.0);
        }
        self.area.clear();
        self.area.resize(len, 0.0);
    }

    fn corner(&self, k: usize, i: usize) -> DVec3 {
        DVec3::new(self.pos[k][0][i], self.pos[k][1][i], self.pos[k][2][i])
    }
    fn normal(&self, i: usize) -> DVec3 {
        DVec3::new(self.n[0][i], self.n[1][i], self.n[2][i])
    }
    fn centroid(&self, i: usize) -> DVec3 {
        DVec3::new(self.g[0][i], self.g[1][i], self.g[2][i])
    }
}

/// The stone's mesh arranged for the kernel (body frame): faces and vertices in the order of
/// their bounding hierarchies. Built once per stone ([`super::stone::Stone::new`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct KernelMesh {
    faces: FaceSoa,
    face_nodes: Vec<Node>,
    vertices: Vec<DVec3>,
    vertex_nodes: Vec<Node>,
    vertex_count: usize,
    /// Margin on the boxes' bounds of u·p, far above the rounding of u·p (m).
    slack: f64,
    /// A body of revolution's rings and strips (the free-rotation path without boxes).
    revolution: Option<rings::Revolution>,
    /// The stone is a body of revolution (a disk or a lens), whatever its layout.
    of_revolution: bool,
    /// Radius of the sphere about the centre of mass that holds every vertex (m).
    bounding_radius: f64,
}

/// Margin on the bounds of u·n (unit normals).
const NORMAL_SLACK: f64 = 1e-12;

impl KernelMesh {
    /// From the centred mesh, its body-frame normals and areas, and its layout when it is a
    /// body of revolution (checked against the mesh; unused when it does not fit);
    /// `of_revolution` and `bounding_radius` are the stone's.
    pub(crate) fn new(
        mesh: &Mesh,
        normals: &[DVec3],
        areas: &[f64],
        layout: Option<&RevolutionLayout>,
        of_revolution: bool,
        bounding_radius: f64,
    ) -> Self {
        let reach = mesh
            .positions
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        // Faces that face apart go apart early (the top and bottom of a thin stone), so boxes are
        // thin along their normals and wholly wet or dry more often.
        let items: Vec<Item> = mesh
            .triangles
            .iter()
            .zip(normals)
            .map(|(tri, &n)| {
                let c = tri.map(|i| mesh.positions[i as usize]);
                Item {
                    key: (c[0] + c[1] + c[2]) * (1.0 / 3.0) + n * reach,
                    lo: c[0].min(c[1]).min(c[2]),
                    hi: c[0].max(c[1]).max(c[2]),
                    nlo: n,
                    nhi: n,
                }
            })
            .collect();
        let (face_nodes, face_order) = build_hierarchy(&items);
        let mut faces = FaceSoa::default();
        for &t in &face_order {
            let tri = mesh.triangles[t];
            faces.push(
                tri.map(|i| mesh.positions[i as usize]),
                normals[t],
                areas[t],
                tri,
            );
        }
        let vitems: Vec<Item> = mesh
            .positions
            .iter()
            .map(|&p| Item {
                key: p,
                lo: p,
                hi: p,
                nlo: DVec3::ZERO,
                nhi: DVec3::ZERO,
            })
            .collect();
        let (vertex_nodes, vertex_order) = build_hierarchy(&vitems);
        let vertices = vertex_order.iter().map(|&i| mesh.positions[i]).collect();
        Self {
            faces,
            face_nodes,
            vertices,
            vertex_nodes,
            vertex_count: mesh.positions.len(),
            slack: 1e-12 * reach.max(f64::MIN_POSITIVE),
            revolution: layout.and_then(|l| rings::Revolution::new(mesh, normals, areas, l, reach)),
            of_revolution,
            bounding_radius,
        }
    }

    /// For a body of revolution whose every vertex is on a ring about body z: how far its lowest
    /// vertex's clearance can stand above that of its rings, over a surface of slope at most
    /// `slope` (the facet term of `integrate::RevolutionBound`). `None` for any other mesh.
    pub fn facet_gap(&self, slope: f64) -> Option<f64> {
        self.revolution.as_ref()?.facet_gap(slope)
    }
}

/// Depth-first walk of a hierarchy with a fixed stack (balanced median splits: depth ≤ 40).
struct Walk {
    stack: [u32; 64],
    len: usize,
}

impl Walk {
    fn new(nodes: &[Node]) -> Self {
        let mut w = Self {
            stack: [0; 64],
            len: 0,
        };
        if !nodes.is_empty() {
            w.push(0);
        }
        w
    }
    fn push(&mut self, i: u32) {
        if self.len < self.stack.len() {
            self.stack[self.len] = i;
            self.len += 1;
        }
    }
    fn pop(&mut self) -> Option<u32> {
        self.len = self.len.checked_sub(1)?;
        Some(self.stack[self.len])
    }
    /// Pushes both children, `first` to be popped first.
    fn push_pair(&mut self, first: u32, second: u32) {
        self.push(second);
        self.push(first);
    }
}

/// The stone's orientation: R (stone → world) and u = Rᵀ ẑ, whose dot with a body point gives the
/// point's height above the centre of mass exactly as (R p).z.
fn frame(orientation: DQuat) -> (DMat3, DVec3) {
    let rot = DMat3::from_quat(orientation);
    let u = DVec3::new(rot.x_axis.z, rot.y_axis.z, rot.z_axis.z);
    (rot, u)
}

/// Signed height of the stone's lowest vertex above the surface: equal to
/// [`super::hydro::lowest_clearance_reference`].
pub fn lowest_clearance(
    km: &KernelMesh,
    bounding_radius: f64,
    position: DVec3,
    orientation: DQuat,
    surface: &dyn Surface,
) -> f64 {
    if position.z - bounding_radius > surface.max_height() {
        return position.z - bounding_radius - surface.max_height();
    }
    let (rot, u) = frame(orientation);
    let nodes = &km.vertex_nodes;
    let mut walk = Walk::new(nodes);
    if surface.is_flat() {
        // Rounding is monotonic, so min (z + oᵢ) = z + min oᵢ.
        let mut best = f64::INFINITY;
        while let Some(i) = walk.pop() {
            let node = &nodes[i as usize];
            if node.bound(u).0 - km.slack > best {
                continue;
            }
            if node.is_leaf() {
                for &p in &km.vertices[node.range()] {
                    best = best.min(dot(u, p));
                }
            } else {
                let (l, r) = (node.left, node.right);
                let (bl, br) = (nodes[l as usize].bound(u).0, nodes[r as usize].bound(u).0);
                if bl <= br {
                    walk.push_pair(l, r);
                } else {
                    walk.push_pair(r, l);
                }
            }
        }
        return (position.z + best) - 0.0;
    }
    // Wavy: d = (z + o) − η ≥ (z + o) − η_max, and both roundings are monotonic. A box the
    // surface's highest point cannot rule out is tried against the highest η under its own
    // horizontal extent (the world box of its vertices, widened far beyond rounding).
    let max_h = surface.max_height();
    let abs = DMat3::from_cols(rot.x_axis.abs(), rot.y_axis.abs(), rot.z_axis.abs());
    let widen = km.slack + 1e-12 * (position.x.abs() + position.y.abs());
    let mut best = f64::INFINITY;
    while let Some(i) = walk.pop() {
        let node = &nodes[i as usize];
        let low = position.z + (node.bound(u).0 - km.slack);
        if low - max_h > best {
            continue;
        }
        if best.is_finite() {
            let c = position + rot * node.centre;
            let h = abs * node.half + DVec3::splat(widen);
            let crest = surface.max_height_over([c.x - h.x, c.y - h.y], [c.x + h.x, c.y + h.y]);
            if low - crest > best {
                continue;
            }
        }
        if node.is_leaf() {
            for &p in &km.vertices[node.range()] {
                let w = position + rot * p;
                best = best.min(w.z - surface.height(w.x, w.y));
            }
        } else {
            let (l, r) = (node.left, node.right);
            if nodes[l as usize].bound(u).0 <= nodes[r as usize].bound(u).0 {
                walk.push_pair(l, r);
            } else {
                walk.push_pair(r, l);
            }
        }
    }
    best
}

/// True when every vertex of the faces whose outward normal points down is below the surface:
/// equal to [`super::hydro::underside_submerged_reference`].
pub fn underside_submerged(
    km: &KernelMesh,
    position: DVec3,
    orientation: DQuat,
    surface: &dyn Surface,
) -> bool {
    let (rot, u) = frame(orientation);
    let flat = surface.is_flat();
    let min_h = if flat { 0.0 } else { surface.min_height() };
    let nodes = &km.face_nodes;
    let f = &km.faces;
    // Look for a witness: a downward face with a vertex at or above the surface.
    let mut walk = Walk::new(nodes);
    while let Some(i) = walk.pop() {
        let node = &nodes[i as usize];
        if node.normal_bound(u).0 - NORMAL_SLACK >= 0.0 {
            continue; // no downward face
        }
        if position.z + (node.bound(u).1 + km.slack) < min_h {
            continue; // every vertex surely under
        }
        if node.is_leaf() {
            for t in node.range() {
                if dot(u, f.normal(t)) >= 0.0 {
                    continue;
                }
                for k in 0..3 {
                    let p = f.corner(k, t);
                    let dry = if flat {
                        position.z + dot(u, p) >= 0.0
                    } else {
                        let w = position + rot * p;
                        w.z >= surface.height(w.x, w.y)
                    };
                    if dry {
                        return false;
                    }
                }
            }
        } else {
            let (l, r) = (node.left, node.right);
            // The higher box first: it more likely holds a dry vertex.
            if nodes[l as usize].bound(u).1 >= nodes[r as usize].bound(u).1 {
                walk.push_pair(l, r);
            } else {
                walk.push_pair(r, l);
            }
        }
    }
    // No witness: submerged when some face points down.
    let mut walk = Walk::new(nodes);
    while let Some(i) = walk.pop() {
        let node = &nodes[i as usize];
        if node.normal_bound(u).0 - NORMAL_SLACK >= 0.0 {
            continue;
        }
        if node.is_leaf() {
            if node.range().any(|t| dot(u, f.normal(t)) < 0.0) {
                return true;
            }
        } else {
            walk.push_pair(node.left, node.right);
        }
    }
    false
}

/// Reusable state of the kernel: the sorted world-axis faces of the last held orientation, the
/// per-vertex heights of a wavy surface, and index lists.
#[derive(Debug, Clone, Default)]
pub struct KernelScratch {
    sorted: Option<Sorted>,
    heights: VertexHeights,
    wet: Vec<u32>,
    rings: rings::RingScratch,
}

/// Faces in world axes (offsets from the centre of mass) for one orientation, in groups of
/// similar vertical extent (each at most half the previous group's), each group sorted by its
/// faces' highest vertex: against a level the wholly wet faces of a group are a prefix, and the
/// faces crossing it lie within the group's extent above it.
#[derive(Debug, Clone)]
struct Sorted {
    orientation: DQuat,
    faces: FaceSoa,
    zmin: Vec<f64>,
    zmax: Vec<f64>,
    /// (start, end, largest extent) of each group.
    groups: Vec<(usize, usize, f64)>,
    /// The lowest vertex's offset.
    lowest: f64,
    /// Vertex offsets (world axes), mesh order.
    offsets: Vec<DVec3>,
}

/// Number of extent groups (the last holds every smaller face).
const GROUPS: usize = 8;

impl Sorted {
    fn new(km: &KernelMesh, orientation: DQuat) -> Self {
        let rot = DMat3::from_quat(orientation);
        let b = &km.faces;
        let n = b.len();
        let mut offsets = vec![DVec3::ZERO; km.vertex_count];
        for i in 0..n {
            for k in 0..3 {
                offsets[b.verts[i][k] as usize] = rot * b.corner(k, i);
            }
        }
        let keys: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let z = b.verts[i].map(|v| offsets[v as usize].z);
                (z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]))
            })
            .collect();
        let top = keys.iter().map(|k| k.1 - k.0).fold(0.0, f64::max);
        let group_of = |k: (f64, f64)| {
            let e = k.1 - k.0;
            let mut g = 0;
            let mut bound = top * 0.5;
            while g + 1 < GROUPS && e <= bound {
                g += 1;
                bound *= 0.5;
            }
            g
        };
        let mut order: Vec<(usize, usize)> = (0..n).map(|i| (group_of(keys[i]), i)).collect();
        order.sort_by(|&(ga, a), &(gc, c)| {
            ga.cmp(&gc)
                .then(keys[a].1.total_cmp(&keys[c].1))
                .then(keys[a].0.total_cmp(&keys[c].0))
                .then(a.cmp(&c))
        });
        let mut faces = FaceSoa::default();
        let (mut zmin, mut zmax) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let mut groups: Vec<(usize, usize, f64)> = Vec::new();
        for (k, &(g, i)) in order.iter().enumerate() {
            if k == 0 || order[k - 1].0 != g {
                groups.push((k, k, 0.0));
            }
            if let Some(last) = groups.last_mut() {
                last.1 = k + 1;
                last.2 = last.2.max(keys[i].1 - keys[i].0);
            }
            let v = b.verts[i];
            faces.push(
                v.map(|j| offsets[j as usize]),
                rot * b.normal(i),
                b.area[i],
                v,
            );
            zmin.push(keys[i].0);
            zmax.push(keys[i].1);
        }
        let lowest = zmin.iter().copied().fold(f64::INFINITY, f64::min);
        Self {
            orientation,
            faces,
            zmin,
            zmax,
            groups,
            lowest,
            offsets,
        }
    }

    /// End of the faces of group `(start, end, extent)` whose highest vertex may be at most
    /// `extent` above `level` (a margin far above rounding included).
    fn reach(&self, (start, end, extent): (usize, usize, f64), level: f64, scale: f64) -> usize {
        let limit = level + extent * (1.0 + 1e-9) + 1e-12 * scale;
        start + self.zmax[start..end].partition_point(|&m| m <= limit)
    }
}

/// Signed heights of the vertices above a wavy surface, each looked up once per evaluation.
#[derive(Debug, Clone, Default)]
struct VertexHeights {
    /// (d, the generation it was computed in) per vertex: one slot, one bounds check.
    slots: Vec<(f64, u32)>,
    generation: u32,
}

impl VertexHeights {
    fn start(&mut self, count: usize) {
        if self.slots.len() != count {
            self.slots = vec![(0.0, 0); count];
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.slots.fill((0.0, 0));
            self.generation = 1;
        }
    }

    /// d = w.z − η(w.x, w.y) of vertex `i` at world point `world()` (inlined into the face loops:
    /// called three times a classified face, it is most of their cost).
    #[inline(always)]
    fn get(&mut self, i: u32, surface: &dyn Surface, world: impl FnOnce() -> DVec3) -> f64 {
        let generation = self.generation;
        let slot = &mut self.slots[i as usize];
        if slot.1 != generation {
            let w = world();
            *slot = (w.z - surface.height(w.x, w.y), generation);
        }
        slot.0
    }
}

/// The per-evaluation constants, in the frame of the face data.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    lift: f64,
    friction: f64,
    density: f64,
    ventilated: bool,
    opposing: bool,
    rho_g: f64,
    /// Receding ventilated faces keep their hydrostatic load (`hydrostatic: WettedFaces`).
    wetted: bool,
    /// Centre-of-mass velocity and angular velocity (frame), speed U.
    v: DVec3,
    w: DVec3,
    speed: f64,
    /// The angular velocity the pressure sees (`axial_spin`), when it differs from `w`.
    normal_w: Option<DVec3>,
    /// The symmetry axis (frame) whose pressure torque is removed (`axial_spin: Smooth`).
    axis: Option<DVec3>,
    record: bool,
    /// Frame → world (`None`: the frame is world axes).
    rot: Option<DMat3>,
    position: DVec3,
    /// World ẑ in the frame: a frame offset's height is `up·r`.
    up: DVec3,
    /// The surface, for the buoyant depth of a face on wavy water (`None`: flat).
    wavy: Option<&'a dyn Surface>,
}

impl<'a> Ctx<'a> {
    fn new(
        km: &KernelMesh,
        hp: &HydroParams,
        pose: &Pose,
        rot: Option<DMat3>,
        call: &Call<'a>,
    ) -> Self {
        let to_frame = |x: DVec3| match rot {
            Some(r) => r.transpose() * x,
            None => x,
        };
        // As the reference's `SpinSplit`: ω_⊥ = ω − (ω·a)a on a smooth body of revolution.
        let revolution = km.of_revolution;
        let (normal_w, axis) = if hp.smooth_spin && revolution {
            let a = pose.orientation * DVec3::Z;
            let w = pose.angular_velocity;
            (Some(to_frame(w - a * w.dot(a))), Some(to_frame(a)))
        } else {
            (None, None)
        };
        Self {
            lift: hp.lift,
            friction: hp.friction,
            density: hp.density,
            ventilated: hp.ventilated,
            opposing: hp.opposing,
            rho_g: hp.rho_g,
            wetted: hp.hydrostatic_wetted && hp.rho_g != 0.0,
            v: to_frame(pose.velocity),
            w: to_frame(pose.angular_velocity),
            speed: pose.velocity.length(),
            normal_w,
            axis,
            record: call.record,
            rot,
            position: pose.position,
            up: rot.map_or(DVec3::Z, |r| DVec3::new(r.x_axis.z, r.y_axis.z, r.z_axis.z)),
            wavy: (!call.surface.is_flat()).then_some(call.surface),
        }
    }

    /// Any issue-11 option on (the SIMD chunks have a leaner variant without them).
    fn has_extras(&self) -> bool {
        self.opposing || self.rho_g != 0.0 || self.normal_w.is_some() || self.axis.is_some()
    }

    /// A ventilated face receding from the water (V·N ≤ 0) carries nothing, known before it is
    /// clipped: the angular velocity the pressure sees is zero, and receding faces carry no
    /// hydrostatic load.
    fn culls_receding(&self) -> bool {
        self.ventilated && !self.wetted && self.normal_w.unwrap_or(self.w) == DVec3::ZERO
    }

    /// Depth below the surface of the point at frame offset `r` from the centre of mass.
    #[inline(always)]
    fn depth(&self, r: [f64; 3]) -> f64 {
        let z = self.position.z + ((self.up.x * r[0] + self.up.y * r[1]) + self.up.z * r[2]);
        match self.wavy {
            None => -z,
            Some(surface) => {
                let o = DVec3::from_array(r);
                let w = self.position + self.rot.map_or(o, |m| m * o);
                surface.height(w.x, w.y) - z
            }
        }
    }

    /// A loaded face's record for the water: world centroid, F_z, footprint.
    fn load(&self, centroid: DVec3, f: DVec3, normal: DVec3, area: f64) -> FaceLoad {
        let (c, fz, nz) = match self.rot {
            Some(r) => (r * centroid, (r * f).z, (r * normal).z),
            None => (centroid, f.z, normal.z),
        };
        FaceLoad {
            x: self.position.x + c.x,
            y: self.position.y + c.y,
            fz,
            footprint: area * nz.abs(),
        }
    }
}

const PAPER: u8 = 0;
const BOCQUET: u8 = 1;
const ROSELLINI: u8 = 2;

fn law_code(law: ForceLaw) -> u8 {
    match law {
        ForceLaw::Paper => PAPER,
        ForceLaw::Bocquet => BOCQUET,
        ForceLaw::Rosellini => ROSELLINI,
    }
}

/// [`super::hydro::face_force`] in `N` lanes, the same operations in the same order: the force on
/// faces of normal n, wetted area S, local velocity v, normal velocity v_n and buoyant depth;
/// `false` in the mask where it is zero.
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn lane_law<const N: usize, const LAW: u8>(
    c: &Ctx,
    n: &[[f64; N]; 3],
    area: &[f64; N],
    v: &[[f64; N]; 3],
    vn: &[f64; N],
    depth: &[f64; N],
) -> ([[f64; N]; 3], [bool; N]) {
    let mut f = [[0.0; N]; 3];
    let mut nonzero = [false; N];
    for l in 0..N {
        let (nx, ny, nz) = (n[0][l], n[1][l], n[2][l]);
        let (vx, vy, vz) = (v[0][l], v[1][l], v[2][l]);
        let vn = vn[l];
        let half_rho_s = 0.5 * c.density * area[l];
        let vdn = (vx * nx + vy * ny) + vz * nz;
        let (tx, ty, tz) = (vx - nx * vdn, vy - ny * vdn, vz - nz * vdn);
        let vt_len = ((tx * tx + ty * ty) + tz * tz).sqrt();
        let (pressure, friction) = match LAW {
            PAPER => (
                c.lift * half_rho_s * vn * vn,
                c.friction * half_rho_s * vt_len * vt_len,
            ),
            BOCQUET => (
                c.lift * half_rho_s * c.speed * c.speed,
                c.friction * half_rho_s * c.speed * c.speed,
            ),
            _ => {
                let vn_loaded = if c.opposing { vn.abs() } else { vn.max(0.0) };
                (
                    c.lift * c.density * area[l] * c.speed * vn_loaded,
                    c.friction * half_rho_s * vt_len * vt_len,
                )
            }
        };
        let sign = pressure_sign(c.opposing, vn);
        let hydrostatic = c.rho_g * depth[l].max(0.0) * area[l];
        let p = sign * pressure + hydrostatic;
        let (mut fx, mut fy, mut fz) = (-nx * p, -ny * p, -nz * p);
        let q = friction / vt_len;
        if vt_len > 0.0 {
            fx -= tx * q;
            fy -= ty * q;
            fz -= tz * q;
        }
        // Receding and ventilated: nothing, or (`WettedFaces`) the hydrostatic load alone.
        if c.ventilated && vn <= 0.0 {
            if c.wetted {
                (fx, fy, fz) = (-nx * hydrostatic, -ny * hydrostatic, -nz * hydrostatic);
            } else {
                (fx, fy, fz) = (0.0, 0.0, 0.0);
            }
        }
        f[0][l] = fx;
        f[1][l] = fy;
        f[2][l] = fz;
        nonzero[l] = fx != 0.0 || fy != 0.0 || fz != 0.0;
    }
    (f, nonzero)
}

/// Running sums in `N` lanes (frame axes).
#[derive(Debug, Clone, Copy)]
struct LaneAcc<const N: usize> {
    force: [[f64; N]; 3],
    torque: [[f64; N]; 3],
    area: [f64; N],
    /// Σ (r × pressure force)·a, removed with `axial_spin: Smooth`.
    axial: [f64; N],
}

impl<const N: usize> Default for LaneAcc<N> {
    fn default() -> Self {
        Self {
            force: [[0.0; N]; 3],
            torque: [[0.0; N]; 3],
            area: [0.0; N],
            axial: [0.0; N],
        }
    }
}

/// The sums over all faces (frame axes).
#[derive(Debug, Clone, Copy)]
struct Acc {
    force: DVec3,
    torque: DVec3,
    area: f64,
    axial: f64,
    /// Running sums of the wholly wet faces in chunks of the ranges, chunks of the lists, one by
    /// one, and of the clipped faces: added at the end, in that order.
    chunks: LaneAcc<LANES>,
    listed: LaneAcc<LANES>,
    single: LaneAcc<1>,
    band: LaneAcc<1>,
    /// The clipped faces of the ring path, four at a time.
    band4: LaneAcc<LANES>,
}

impl Default for Acc {
    fn default() -> Self {
        Self {
            force: DVec3::ZERO,
            torque: DVec3::ZERO,
            area: 0.0,
            axial: 0.0,
            chunks: LaneAcc::default(),
            listed: LaneAcc::default(),
            single: LaneAcc::default(),
            band: LaneAcc::default(),
            band4: LaneAcc::default(),
        }
    }
}

impl Acc {
    fn add_lanes<const N: usize>(&mut self, la: &LaneAcc<N>) {
        for l in 0..N {
            let at = |a: &[[f64; N]; 3]| DVec3::new(a[0][l], a[1][l], a[2][l]);
            self.force += at(&la.force);
            self.torque += at(&la.torque);
            self.area += la.area[l];
            self.axial += la.axial[l];
        }
    }
}

/// The faces of `N` lanes: normal, area, the point the load acts at (offset from the centre of
/// mass: the wetted centroid) and whether the lane is wholly wet (its corners bound the wetted
/// length) or clipped (the caller extends the wetted length).
struct Lanes<const N: usize> {
    n: [[f64; N]; 3],
    g: [[f64; N]; 3],
    area: [f64; N],
}

/// Where a chunk of `N` faces comes from.
trait Source<const N: usize>: Copy {
    fn at(self, col: &[f64]) -> [f64; N];
    fn index(self, l: usize) -> usize;
}

#[derive(Clone, Copy)]
struct Contiguous(usize);
impl<const N: usize> Source<N> for Contiguous {
    #[inline(always)]
    fn at(self, col: &[f64]) -> [f64; N] {
        let mut out = [0.0; N];
        out.copy_from_slice(&col[self.0..self.0 + N]);
        out
    }
    #[inline(always)]
    fn index(self, l: usize) -> usize {
        self.0 + l
    }
}

#[derive(Clone, Copy)]
struct Gathered<const N: usize>([usize; N]);
impl<const N: usize> Source<N> for Gathered<N> {
    #[inline(always)]
    fn at(self, col: &[f64]) -> [f64; N] {
        let mut out = [0.0; N];
        for (o, &i) in out.iter_mut().zip(&self.0) {
            *o = col[i];
        }
        out
    }
    #[inline(always)]
    fn index(self, l: usize) -> usize {
        self.0[l]
    }
}

#[inline(always)]
fn load<const N: usize, S: Source<N>>(f: &FaceSoa, s: S) -> Lanes<N> {
    Lanes {
        n: [s.at(&f.n[0]), s.at(&f.n[1]), s.at(&f.n[2])],
        g: [s.at(&f.g[0]), s.at(&f.g[1]), s.at(&f.g[2])],
        area: s.at(&f.area),
    }
}

/// Law and sums for `N` faces; returns the mask of loaded faces and their forces.
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn contribute<const N: usize, const LAW: u8, const ROT: bool>(
    c: &Ctx,
    x: &Lanes<N>,
    acc: &mut LaneAcc<N>,
) -> ([bool; N], [[f64; N]; 3]) {
    let g = &x.g;
    let mut v = [[c.v.x; N], [c.v.y; N], [c.v.z; N]];
    if ROT {
        let w = c.w;
        for l in 0..N {
            v[0][l] = c.v.x + (w.y * g[2][l] - g[1][l] * w.z);
            v[1][l] = c.v.y + (w.z * g[0][l] - g[2][l] * w.x);
            v[2][l] = c.v.z + (w.x * g[1][l] - g[0][l] * w.y);
        }
    }
    let n = &x.n;
    let mut vn = [0.0; N];
    match c.normal_w {
        // The pressure sees ω_⊥ only: v_n from V + ω_⊥ × r.
        Some(wn) => {
            for l in 0..N {
                let (ux, uy, uz) = if ROT {
                    (
                        c.v.x + (wn.y * g[2][l] - g[1][l] * wn.z),
                        c.v.y + (wn.z * g[0][l] - g[2][l] * wn.x),
                        c.v.z + (wn.x * g[1][l] - g[0][l] * wn.y),
                    )
                } else {
                    (c.v.x, c.v.y, c.v.z)
                };
                vn[l] = (ux * n[0][l] + uy * n[1][l]) + uz * n[2][l];
            }
        }
        None => {
            for l in 0..N {
                vn[l] = (v[0][l] * n[0][l] + v[1][l] * n[1][l]) + v[2][l] * n[2][l];
            }
        }
    }
    let mut depth = [0.0; N];
    if c.rho_g != 0.0 {
        for l in 0..N {
            depth[l] = c.depth([g[0][l], g[1][l], g[2][l]]);
        }
    }
    let (f, nonzero) = lane_law::<N, LAW>(c, n, &x.area, &v, &vn, &depth);
    let mut loaded = [false; N];
    for l in 0..N {
        loaded[l] = nonzero[l] && x.area[l] > 0.0;
        let keep = |a: f64| if loaded[l] { a } else { 0.0 };
        let (fx, fy, fz) = (f[0][l], f[1][l], f[2][l]);
        let (gx, gy, gz) = (g[0][l], g[1][l], g[2][l]);
        acc.force[0][l] += keep(fx);
        acc.force[1][l] += keep(fy);
        acc.force[2][l] += keep(fz);
        acc.torque[0][l] += keep(gy * fz - fy * gz);
        acc.torque[1][l] += keep(gz * fx - fz * gx);
        acc.torque[2][l] += keep(gx * fy - fx * gy);
        acc.area[l] += keep(x.area[l]);
    }
    if let Some(a) = c.axis {
        for l in 0..N {
            let (nx, ny, nz) = (n[0][l], n[1][l], n[2][l]);
            let pn = (f[0][l] * nx + f[1][l] * ny) + f[2][l] * nz;
            let (px, py, pz) = (nx * pn, ny * pn, nz * pn);
            let (gx, gy, gz) = (g[0][l], g[1][l], g[2][l]);
            let t = DVec3::new(gy * pz - py * gz, gz * px - pz * gx, gx * py - px * gy);
            acc.axial[l] += if loaded[l] { t.dot(a) } else { 0.0 };
        }
    }
    (loaded, f)
}

/// Wholly wet faces from `s`: law, sums, the records.
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn wet_chunk<const N: usize, const LAW: u8, const ROT: bool, S: Source<N>>(
    c: &Ctx,
    faces: &FaceSoa,
    s: S,
    acc: &mut LaneAcc<N>,
    loads: &mut Vec<FaceLoad>,
) {
    let x = load(faces, s);
    let (loaded, f) = contribute::<N, LAW, ROT>(c, &x, acc);
    if c.record {
        for l in 0..N {
            if loaded[l] {
                let fl = DVec3::new(f[0][l], f[1][l], f[2][l]);
                let i = s.index(l);
                loads.push(c.load(faces.centroid(i), fl, faces.normal(i), faces.area[i]));
            }
        }
    }
}

/// The wholly wet faces `range` (contiguous) and `list` (gathered) into `acc`: whole chunks of
/// the range, whole chunks of the list and the rest one by one, each into its own lanes (the AVX2
/// path fills the first itself, with the same bits).
#[inline(always)]
fn wet_faces_body<const LAW: u8, const ROT: bool>(
    c: &Ctx,
    faces: &FaceSoa,
    range: std::ops::Range<usize>,
    list: &[u32],
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
    chunks_done: bool,
) {
    let full = range.start + (range.len() / LANES) * LANES;
    if !chunks_done {
        let mut i = range.start;
        while i < full {
            wet_chunk::<LANES, LAW, ROT, _>(c, faces, Contiguous(i), &mut acc.chunks, loads);
            i += LANES;
        }
    }
    let mut chunks = list.chunks_exact(LANES);
    for ch in chunks.by_ref() {
        if chunks_done {
            continue;
        }
        let idx = [ch[0], ch[1], ch[2], ch[3]].map(|j| j as usize);
        wet_chunk::<LANES, LAW, ROT, _>(c, faces, Gathered(idx), &mut acc.listed, loads);
    }
    for j in (full..range.end).chain(chunks.remainder().iter().map(|&j| j as usize)) {
        wet_chunk::<1, LAW, ROT, _>(c, faces, Gathered([j]), &mut acc.single, loads);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn wet_faces_avx2<const LAW: u8, const ROT: bool>(
    c: &Ctx,
    faces: &FaceSoa,
    range: std::ops::Range<usize>,
    list: &[u32],
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) {
    let full = range.start + (range.len() / LANES) * LANES;
    // SAFETY: AVX2 is enabled in this function; the chunks lie inside the face arrays.
    unsafe {
        simd::plain_chunks::<LAW, ROT>(c, faces, range.start, full, &mut acc.chunks, loads);
        simd::plain_list::<LAW, ROT>(c, faces, list, &mut acc.listed, loads);
    };
    wet_faces_body::<LAW, ROT>(c, faces, range, list, acc, loads, true)
}

fn wet_faces_portable<const LAW: u8, const ROT: bool>(
    c: &Ctx,
    faces: &FaceSoa,
    range: std::ops::Range<usize>,
    list: &[u32],
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) {
    wet_faces_body::<LAW, ROT>(c, faces, range, list, acc, loads, false)
}

/// Wholly wet faces, on the widest vector unit the machine has (same bits on every one).
fn wet_faces<const LAW: u8, const ROT: bool>(
    c: &Ctx,
    faces: &FaceSoa,
    range: std::ops::Range<usize>,
    list: &[u32],
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) {
    if range.is_empty() && list.is_empty() {
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above).
        unsafe { wet_faces_avx2::<LAW, ROT>(c, faces, range, list, acc, loads) };
        return;
    }
    wet_faces_portable::<LAW, ROT>(c, faces, range, list, acc, loads)
}

/// Explicit AVX2 for every option (buoyancy on wavy water reads each face's depth through the scalar expression): the operations of [`lane_law`] and [`contribute`]
/// in the same order, four faces per register.
#[cfg(target_arch = "x86_64")]
mod simd {
    use super::{Ctx, FaceLoad, FaceSoa, LaneAcc, BOCQUET, PAPER};
    use glam::DVec3;
    use std::arch::x86_64::*;

    #[inline(always)]
    unsafe fn ld(col: &[f64], i: usize) -> __m256d {
        debug_assert!(i + 4 <= col.len());
        // SAFETY: the caller keeps i + 4 within the column.
        unsafe { _mm256_loadu_pd(col.as_ptr().add(i)) }
    }

    /// Faces `start..end` (a multiple of four long) into `la`.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn plain_chunks<const LAW: u8, const ROT: bool>(
        c: &Ctx,
        f: &FaceSoa,
        start: usize,
        end: usize,
        la: &mut LaneAcc<4>,
        loads: &mut Vec<FaceLoad>,
    ) {
        // SAFETY: AVX2 is enabled here as in the caller.
        unsafe {
            if c.has_extras() {
                chunks::<LAW, ROT, false, true>(c, f, start, end, &[], la, loads)
            } else {
                chunks::<LAW, ROT, false, false>(c, f, start, end, &[], la, loads)
            }
        }
    }

    /// Faces `list` (whole chunks of four; the rest is left to the caller) into `la`.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn plain_list<const LAW: u8, const ROT: bool>(
        c: &Ctx,
        f: &FaceSoa,
        list: &[u32],
        la: &mut LaneAcc<4>,
        loads: &mut Vec<FaceLoad>,
    ) {
        let n = list.len() / 4 * 4;
        // SAFETY: AVX2 is enabled here as in the caller.
        unsafe {
            if c.has_extras() {
                chunks::<LAW, ROT, true, true>(c, f, 0, n, list, la, loads)
            } else {
                chunks::<LAW, ROT, true, false>(c, f, 0, n, list, la, loads)
            }
        }
    }

    /// Faces `start..end` of the arrays, or of `list` when `GATHER`.
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    unsafe fn chunks<const LAW: u8, const ROT: bool, const GATHER: bool, const EXTRA: bool>(
        c: &Ctx,
        f: &FaceSoa,
        start: usize,
        end: usize,
        list: &[u32],
        la: &mut LaneAcc<4>,
        loads: &mut Vec<FaceLoad>,
    ) {
        assert!((end - start).is_multiple_of(4));
        if GATHER {
            assert!(end <= list.len() && list.iter().all(|&j| (j as usize) < f.len()));
        } else {
            assert!(end <= f.len());
        }
        let ld = |col: &[f64], k: usize| {
            if GATHER {
                _mm256_set_pd(
                    col[list[k + 3] as usize],
                    col[list[k + 2] as usize],
                    col[list[k + 1] as usize],
                    col[list[k] as usize],
                )
            } else {
                // SAFETY: k + 4 ≤ end ≤ len (asserted above).
                unsafe { ld(col, k) }
            }
        };
        let set = |x: f64| _mm256_set1_pd(x);
        let (vx0, vy0, vz0) = (set(c.v.x), set(c.v.y), set(c.v.z));
        let (wx, wy, wz) = (set(c.w.x), set(c.w.y), set(c.w.z));
        let half_rho = set(0.5 * c.density);
        let lift = set(c.lift);
        let lift_rho = set(c.lift * c.density);
        let friction = set(c.friction);
        let speed = set(c.speed);
        let zero = _mm256_setzero_pd();
        let sign_bit = set(-0.0);
        let vent = if c.ventilated {
            _mm256_castsi256_pd(_mm256_set1_epi64x(-1))
        } else {
            zero
        };
        let rd = |a: &[f64; 4]| unsafe { _mm256_loadu_pd(a.as_ptr()) };
        let mut af = [rd(&la.force[0]), rd(&la.force[1]), rd(&la.force[2])];
        let mut at = [rd(&la.torque[0]), rd(&la.torque[1]), rd(&la.torque[2])];
        let mut aa = rd(&la.area);
        let mut ax = rd(&la.axial);
        let split = c.normal_w.is_some();
        let wn = c.normal_w.unwrap_or(glam::DVec3::ZERO);
        let (wnx, wny, wnz) = (set(wn.x), set(wn.y), set(wn.z));
        let pos_z = set(c.position.z);
        let (upx, upy, upz) = (set(c.up.x), set(c.up.y), set(c.up.z));
        let dot_up = |x: __m256d, y: __m256d, z: __m256d| {
            _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(upx, x), _mm256_mul_pd(upy, y)),
                _mm256_mul_pd(upz, z),
            )
        };
        let mut i = start;
        while i < end {
            // SAFETY: i + 4 ≤ end ≤ len.
            let (nx, ny, nz) = (ld(&f.n[0], i), ld(&f.n[1], i), ld(&f.n[2], i));
            let (gx, gy, gz) = (ld(&f.g[0], i), ld(&f.g[1], i), ld(&f.g[2], i));
            let area = ld(&f.area, i);
            let ([vx, vy, vz], vdn, vn) = velocities::<ROT, EXTRA>(
                [vx0, vy0, vz0],
                [wx, wy, wz],
                split.then_some([wnx, wny, wnz]),
                [nx, ny, nz],
                [gx, gy, gz],
            );
            let hrs = _mm256_mul_pd(half_rho, area);
            let tx = _mm256_sub_pd(vx, _mm256_mul_pd(nx, vdn));
            let ty = _mm256_sub_pd(vy, _mm256_mul_pd(ny, vdn));
            let tz = _mm256_sub_pd(vz, _mm256_mul_pd(nz, vdn));
            let vt_len = _mm256_sqrt_pd(_mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(tx, tx), _mm256_mul_pd(ty, ty)),
                _mm256_mul_pd(tz, tz),
            ));
            let (pressure, fric) = law_lanes::<LAW, EXTRA>(
                c,
                [lift, lift_rho, friction, speed],
                hrs,
                area,
                vn,
                vt_len,
            );
            let neg = |x: __m256d| _mm256_xor_pd(x, sign_bit);
            let wavy = wavy_depths::<EXTRA>(c, [gx, gy, gz]);
            let depth = || wavy.unwrap_or_else(|| neg(_mm256_add_pd(pos_z, dot_up(gx, gy, gz))));
            let (p, hydrostatic) = normal_load::<EXTRA>(c, pressure, vn, area, depth);
            let mut fx = _mm256_mul_pd(neg(nx), p);
            let mut fy = _mm256_mul_pd(neg(ny), p);
            let mut fz = _mm256_mul_pd(neg(nz), p);
            let q = _mm256_div_pd(fric, vt_len);
            let tangential = _mm256_cmp_pd::<_CMP_GT_OQ>(vt_len, zero);
            fx = _mm256_blendv_pd(fx, _mm256_sub_pd(fx, _mm256_mul_pd(tx, q)), tangential);
            fy = _mm256_blendv_pd(fy, _mm256_sub_pd(fy, _mm256_mul_pd(ty, q)), tangential);
            fz = _mm256_blendv_pd(fz, _mm256_sub_pd(fz, _mm256_mul_pd(tz, q)), tangential);
            let receding = _mm256_and_pd(vent, _mm256_cmp_pd::<_CMP_LE_OQ>(vn, zero));
            let wetted = EXTRA && c.wetted;
            if wetted {
                [fx, fy, fz] = hydrostatic_when([fx, fy, fz], [nx, ny, nz], hydrostatic, receding);
            }
            let any = _mm256_or_pd(
                _mm256_or_pd(
                    _mm256_cmp_pd::<_CMP_NEQ_UQ>(fx, zero),
                    _mm256_cmp_pd::<_CMP_NEQ_UQ>(fy, zero),
                ),
                _mm256_cmp_pd::<_CMP_NEQ_UQ>(fz, zero),
            );
            let carried = if wetted {
                any
            } else {
                _mm256_andnot_pd(receding, any)
            };
            let loaded = _mm256_and_pd(carried, _mm256_cmp_pd::<_CMP_GT_OQ>(area, zero));
            let keep = |x: __m256d| _mm256_and_pd(x, loaded);
            af[0] = _mm256_add_pd(af[0], keep(fx));
            af[1] = _mm256_add_pd(af[1], keep(fy));
            af[2] = _mm256_add_pd(af[2], keep(fz));
            let torque = [
                _mm256_sub_pd(_mm256_mul_pd(gy, fz), _mm256_mul_pd(fy, gz)),
                _mm256_sub_pd(_mm256_mul_pd(gz, fx), _mm256_mul_pd(fz, gx)),
                _mm256_sub_pd(_mm256_mul_pd(gx, fy), _mm256_mul_pd(fx, gy)),
            ];
            for k in 0..3 {
                at[k] = _mm256_add_pd(at[k], keep(torque[k]));
            }
            aa = _mm256_add_pd(aa, keep(area));
            if let (true, Some(a)) = (EXTRA, c.axis) {
                ax = _mm256_add_pd(
                    ax,
                    keep(axial_lanes(a, [nx, ny, nz], [gx, gy, gz], [fx, fy, fz])),
                );
            }
            if c.record {
                record_lanes::<GATHER>(c, f, list, i, [fx, fy, fz], loaded, loads);
            }
            i += 4;
        }
        let wr = |a: &mut [f64; 4], v: __m256d| unsafe { _mm256_storeu_pd(a.as_mut_ptr(), v) };
        for k in 0..3 {
            wr(&mut la.force[k], af[k]);
            wr(&mut la.torque[k], at[k]);
        }
        wr(&mut la.area, aa);
        wr(&mut la.axial, ax);
    }
    /// With buoyancy on wavy water, four faces' depths below the surface over their centroids `g`
    /// (`None` otherwise): the surface is read one face at a time, by the scalar lanes' own
    /// expression ([`Ctx::depth`]), so the depths are theirs bit for bit.
    #[target_feature(enable = "avx2")]
    fn wavy_depths<const EXTRA: bool>(c: &Ctx, g: [__m256d; 3]) -> Option<__m256d> {
        if !(EXTRA && c.rho_g != 0.0 && c.wavy.is_some()) {
            return None;
        }
        let lanes = |x: __m256d| {
            let mut a = [0.0; 4];
            // SAFETY: AVX2 is enabled here; `a` holds four f64.
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), x) };
            a
        };
        let [x, y, z] = g.map(lanes);
        let d = [0, 1, 2, 3].map(|l| c.depth([x[l], y[l], z[l]]));
        // SAFETY: `d` holds four f64.
        Some(unsafe { _mm256_loadu_pd(d.as_ptr()) })
    }

    /// `WettedFaces`: where `receding`, a face keeps its hydrostatic load −N h alone.
    #[target_feature(enable = "avx2")]
    fn hydrostatic_when(
        f: [__m256d; 3],
        n: [__m256d; 3],
        h: __m256d,
        receding: __m256d,
    ) -> [__m256d; 3] {
        let sign_bit = _mm256_set1_pd(-0.0);
        let load = |n: __m256d| _mm256_mul_pd(_mm256_xor_pd(n, sign_bit), h);
        [0, 1, 2].map(|k| _mm256_blendv_pd(f[k], load(n[k]), receding))
    }

    /// The faces' velocities v = V + ω × g (or V), v·N, and the normal velocity the pressure sees
    /// (from ω_⊥ on the smooth body, `wn`), for four faces with normals `n` and centroids `g`.
    #[target_feature(enable = "avx2")]
    fn velocities<const ROT: bool, const EXTRA: bool>(
        v0: [__m256d; 3],
        w: [__m256d; 3],
        wn: Option<[__m256d; 3]>,
        n: [__m256d; 3],
        g: [__m256d; 3],
    ) -> ([__m256d; 3], __m256d, __m256d) {
        let [vx0, vy0, vz0] = v0;
        let [nx, ny, nz] = n;
        let [gx, gy, gz] = g;
        let spun = |[wx, wy, wz]: [__m256d; 3]| {
            [
                _mm256_add_pd(
                    vx0,
                    _mm256_sub_pd(_mm256_mul_pd(wy, gz), _mm256_mul_pd(gy, wz)),
                ),
                _mm256_add_pd(
                    vy0,
                    _mm256_sub_pd(_mm256_mul_pd(wz, gx), _mm256_mul_pd(gz, wx)),
                ),
                _mm256_add_pd(
                    vz0,
                    _mm256_sub_pd(_mm256_mul_pd(wx, gy), _mm256_mul_pd(gx, wy)),
                ),
            ]
        };
        let v = if ROT { spun(w) } else { v0 };
        let dot3 = |[ax, ay, az]: [__m256d; 3]| {
            _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(ax, nx), _mm256_mul_pd(ay, ny)),
                _mm256_mul_pd(az, nz),
            )
        };
        let vdn = dot3(v);
        // The normal velocity: from V + ω_⊥ × r on the smooth body, else v·N.
        let vn = match (EXTRA, wn) {
            (true, Some(wn)) => {
                if ROT {
                    dot3(spun(wn))
                } else {
                    dot3(v0)
                }
            }
            _ => vdn,
        };
        (v, vdn, vn)
    }

    /// sign · pressure + hydrostatic, and hydrostatic, for four faces: the sign of v_n when the
    /// pressure opposes the motion, else +1; ρ g max(0, depth) S with buoyancy (`depth`: the wetted
    /// centroids' depths below the surface).
    #[target_feature(enable = "avx2")]
    fn normal_load<const EXTRA: bool>(
        c: &Ctx,
        pressure: __m256d,
        vn: __m256d,
        area: __m256d,
        depth: impl Fn() -> __m256d,
    ) -> (__m256d, __m256d) {
        let zero = _mm256_setzero_pd();
        let set = |x: f64| _mm256_set1_pd(x);
        let signed = if EXTRA && c.opposing {
            let gt = _mm256_cmp_pd::<_CMP_GT_OQ>(vn, zero);
            let lt = _mm256_cmp_pd::<_CMP_LT_OQ>(vn, zero);
            let sign = _mm256_blendv_pd(_mm256_blendv_pd(zero, set(-1.0), lt), set(1.0), gt);
            _mm256_mul_pd(sign, pressure)
        } else {
            _mm256_mul_pd(set(1.0), pressure)
        };
        let hydrostatic = if EXTRA && c.rho_g != 0.0 {
            _mm256_mul_pd(
                _mm256_mul_pd(set(c.rho_g), _mm256_max_pd(depth(), zero)),
                area,
            )
        } else {
            zero
        };
        (_mm256_add_pd(signed, hydrostatic), hydrostatic)
    }

    /// Pressure and friction magnitudes of the law for four faces (`k`: C_l, C_l ρ, C_f, U).
    #[target_feature(enable = "avx2")]
    fn law_lanes<const LAW: u8, const EXTRA: bool>(
        c: &Ctx,
        k: [__m256d; 4],
        hrs: __m256d,
        area: __m256d,
        vn: __m256d,
        vt_len: __m256d,
    ) -> (__m256d, __m256d) {
        let [lift, lift_rho, friction, speed] = k;
        let zero = _mm256_setzero_pd();
        let sign_bit = _mm256_set1_pd(-0.0);
        match LAW {
            PAPER => (
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(lift, hrs), vn), vn),
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(friction, hrs), vt_len), vt_len),
            ),
            BOCQUET => (
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(lift, hrs), speed), speed),
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(friction, hrs), speed), speed),
            ),
            _ => (
                _mm256_mul_pd(
                    _mm256_mul_pd(_mm256_mul_pd(lift_rho, area), speed),
                    if EXTRA && c.opposing {
                        _mm256_andnot_pd(sign_bit, vn)
                    } else {
                        _mm256_max_pd(vn, zero)
                    },
                ),
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(friction, hrs), vt_len), vt_len),
            ),
        }
    }

    /// (g × p)·a for the pressure part p = N (f·N) of four faces' forces `f`.
    #[target_feature(enable = "avx2")]
    fn axial_lanes(a: DVec3, n: [__m256d; 3], g: [__m256d; 3], f: [__m256d; 3]) -> __m256d {
        let [nx, ny, nz] = n;
        let [gx, gy, gz] = g;
        let [fx, fy, fz] = f;
        let pn = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(fx, nx), _mm256_mul_pd(fy, ny)),
            _mm256_mul_pd(fz, nz),
        );
        let (px, py, pz) = (
            _mm256_mul_pd(nx, pn),
            _mm256_mul_pd(ny, pn),
            _mm256_mul_pd(nz, pn),
        );
        let t0 = _mm256_sub_pd(_mm256_mul_pd(gy, pz), _mm256_mul_pd(py, gz));
        let t1 = _mm256_sub_pd(_mm256_mul_pd(gz, px), _mm256_mul_pd(pz, gx));
        let t2 = _mm256_sub_pd(_mm256_mul_pd(gx, py), _mm256_mul_pd(px, gy));
        let set = |x: f64| _mm256_set1_pd(x);
        _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(t0, set(a.x)), _mm256_mul_pd(t1, set(a.y))),
            _mm256_mul_pd(t2, set(a.z)),
        )
    }

    /// Records the loads of the four faces from `i` (of `list` when `GATHER`) that carry one.
    #[target_feature(enable = "avx2")]
    fn record_lanes<const GATHER: bool>(
        c: &Ctx,
        f: &FaceSoa,
        list: &[u32],
        i: usize,
        force: [__m256d; 3],
        loaded: __m256d,
        loads: &mut Vec<FaceLoad>,
    ) {
        let mut out = [[0.0; 4]; 3];
        let mut mask = [0.0; 4];
        // SAFETY: stores into local arrays of four.
        unsafe {
            _mm256_storeu_pd(out[0].as_mut_ptr(), force[0]);
            _mm256_storeu_pd(out[1].as_mut_ptr(), force[1]);
            _mm256_storeu_pd(out[2].as_mut_ptr(), force[2]);
            _mm256_storeu_pd(mask.as_mut_ptr(), loaded);
        }
        for l in 0..4 {
            if mask[l].to_bits() != 0 {
                let j = if GATHER { list[i + l] as usize } else { i + l };
                let fl = DVec3::new(out[0][l], out[1][l], out[2][l]);
                loads.push(c.load(f.centroid(j), fl, f.normal(j), f.area[j]));
            }
        }
    }
}

/// A face crossing the surface: clipped (paper Fig. 5), then the law for its wetted part.
fn band_face<const LAW: u8, const ROT: bool>(
    c: &Ctx,
    faces: &FaceSoa,
    i: usize,
    d: [f64; 3],
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) {
    let normal = faces.normal(i);
    if c.culls_receding() && normal.dot(c.v) <= 0.0 {
        return; // receding without rotation: carries nothing
    }
    let p = [faces.corner(0, i), faces.corner(1, i), faces.corner(2, i)];
    let Some(patch) = clip_triangle(p, d) else {
        return;
    };
    if patch.area <= 0.0 {
        return;
    }
    let x = Lanes::<1> {
        n: [[normal.x], [normal.y], [normal.z]],
        g: [[patch.centroid.x], [patch.centroid.y], [patch.centroid.z]],
        area: [patch.area],
    };
    let (loaded, f) = contribute::<1, LAW, ROT>(c, &x, &mut acc.band);
    if !loaded[0] {
        return;
    }
    if c.record {
        let fl = DVec3::new(f[0][0], f[1][0], f[2][0]);
        loads.push(c.load(patch.centroid, fl, normal, patch.area));
    }
}

/// A face whose corners have signed heights `d`: wholly wet (no clipping), crossing, or dry.
/// Returns whether any corner is wet.
#[inline]
fn classify<const LAW: u8, const ROT: bool>(
    c: &Ctx,
    faces: &FaceSoa,
    i: usize,
    d: [f64; 3],
    wet: &mut Vec<u32>,
    acc: &mut Acc,
    loads: &mut Vec<FaceLoad>,
) -> bool {
    let n_wet = d.iter().filter(|&&x| x <= 0.0).count();
    match n_wet {
        0 => false,
        3 => {
            wet.push(i as u32);
            true
        }
        _ => {
            band_face::<LAW, ROT>(c, faces, i, d, acc, loads);
            true
        }
    }
}

/// Forces and torque of the water on the stone: the fast path of [`super::hydro::evaluate`]
/// (callers check `fast_path_supports` first).
pub fn evaluate(
    km: &KernelMesh,
    hp: &HydroParams,
    pose: &Pose,
    surface: &dyn Surface,
    ks: &mut KernelScratch,
    loads: &mut Vec<FaceLoad>,
    record: bool,
) -> ForceSum {
    if record {
        loads.clear();
    }
    if pose.position.z - km.bounding_radius > surface.max_height() {
        return ForceSum::default();
    }
    let rot = pose.angular_velocity != DVec3::ZERO;
    let held = ks.sorted.as_ref().map(|s| s.orientation) == Some(pose.orientation);
    let call = Call {
        hp,
        pose,
        surface,
        record,
    };
    match (law_code(hp.law), rot, held || !rot) {
        (PAPER, false, _) => sorted_path::<PAPER, false>(km, &call, ks, loads),
        (BOCQUET, false, _) => sorted_path::<BOCQUET, false>(km, &call, ks, loads),
        (_, false, _) => sorted_path::<ROSELLINI, false>(km, &call, ks, loads),
        (PAPER, true, true) => sorted_path::<PAPER, true>(km, &call, ks, loads),
        (BOCQUET, true, true) => sorted_path::<BOCQUET, true>(km, &call, ks, loads),
        (_, true, true) => sorted_path::<ROSELLINI, true>(km, &call, ks, loads),
        (PAPER, true, false) => body_path::<PAPER>(km, &call, ks, loads),
        (BOCQUET, true, false) => body_path::<BOCQUET>(km, &call, ks, loads),
        (_, true, false) => body_path::<ROSELLINI>(km, &call, ks, loads),
    }
}

/// The arguments of one evaluation.
struct Call<'a> {
    hp: &'a HydroParams,
    pose: &'a Pose,
    surface: &'a dyn Surface,
    record: bool,
}

/// The sums as a [`ForceSum`] (world axes).
fn finish(c: &Ctx, acc: &Acc, in_contact: bool) -> ForceSum {
    let mut acc = *acc;
    let (chunks, listed, single, band, band4) =
        (acc.chunks, acc.listed, acc.single, acc.band, acc.band4);
    acc.add_lanes(&chunks);
    acc.add_lanes(&listed);
    acc.add_lanes(&single);
    acc.add_lanes(&band);
    acc.add_lanes(&band4);
    let mut torque = acc.torque;
    if let Some(a) = c.axis {
        // The smooth body's pressure passes through its axis: no torque about it.
        torque -= a * acc.axial;
    }
    let to_world = |x: DVec3| match c.rot {
        Some(r) => r * x,
        None => x,
    };
    ForceSum {
        force: to_world(acc.force),
        torque: to_world(torque),
        wetted_area: acc.area,
        in_contact,
    }
}

/// Held orientation: faces sorted by height in world axes.
fn sorted_path<const LAW: u8, const ROT: bool>(
    km: &KernelMesh,
    call: &Call,
    ks: &mut KernelScratch,
    loads: &mut Vec<FaceLoad>,
) -> ForceSum {
    let pose = call.pose;
    if ks.sorted.as_ref().map(|s| s.orientation) != Some(pose.orientation) {
        ks.sorted = Some(Sorted::new(km, pose.orientation));
    }
    let KernelScratch {
        sorted,
        heights,
        wet,
        ..
    } = ks;
    let Some(s) = sorted.as_ref() else {
        return ForceSum::default();
    };
    let c = Ctx::new(km, call.hp, pose, None, call);
    let z = pose.position.z;
    let faces = &s.faces;
    let mut acc = Acc::default();
    wet.clear();
    let scale = z.abs() + km.bounding_radius;
    let in_contact;
    if call.surface.is_flat() {
        // Some corner wet ⇔ the lowest is; wholly wet ⇔ the highest is (rounding is monotonic).
        in_contact = z + s.lowest <= 0.0;
        if !in_contact {
            return ForceSum::default();
        }
        for &group in &s.groups {
            let (start, end, _) = group;
            let kw = start + s.zmax[start..end].partition_point(|&m| z + m <= 0.0);
            wet_faces::<LAW, ROT>(&c, faces, start..kw, &[], &mut acc, loads);
            for i in kw..s.reach(group, -z, scale) {
                let pz = &faces.pos;
                let d = [z + pz[0][2][i], z + pz[1][2][i], z + pz[2][2][i]];
                classify::<LAW, ROT>(&c, faces, i, d, wet, &mut acc, loads);
            }
        }
        wet_faces::<LAW, ROT>(&c, faces, 0..0, wet, &mut acc, loads);
    } else {
        let max_h = call.surface.max_height();
        heights.start(km.vertex_count);
        let mut any = false;
        for &group in &s.groups {
            for i in group.0..s.reach(group, max_h - z, scale + max_h.abs()) {
                if (z + s.zmin[i]) - max_h > 0.0 {
                    continue; // surely dry
                }
                let verts = faces.verts[i];
                let mut h = |k: usize| {
                    let v = verts[k];
                    heights.get(v, call.surface, || pose.position + s.offsets[v as usize])
                };
                let d = [h(0), h(1), h(2)];
                any |= classify::<LAW, ROT>(&c, faces, i, d, wet, &mut acc, loads);
            }
        }
        in_contact = any;
        wet_faces::<LAW, ROT>(&c, faces, 0..0, wet, &mut acc, loads);
    }
    if !in_contact {
        return ForceSum::default();
    }
    finish(&c, &acc, true)
}

/// Free rotation: body frame, boxes cull.
fn body_path<const LAW: u8>(
    km: &KernelMesh,
    call: &Call,
    ks: &mut KernelScratch,
    loads: &mut Vec<FaceLoad>,
) -> ForceSum {
    if let Some(rev) = &km.revolution {
        return rings::ring_path::<LAW>(km, rev, call, ks, loads);
    }
    let pose = call.pose;
    let (rot, u) = frame(pose.orientation);
    let c = Ctx::new(km, call.hp, pose, Some(rot), call);
    let surface = call.surface;
    let flat = surface.is_flat();
    let (max_h, min_h) = if flat {
        (0.0, 0.0)
    } else {
        (surface.max_height(), surface.min_height())
    };
    let z = pose.position.z;
    let faces = &km.faces;
    let nodes = &km.face_nodes;
    let KernelScratch { heights, wet, .. } = ks;
    wet.clear();
    if !flat {
        heights.start(km.vertex_count);
    }
    let mut acc = Acc::default();
    let mut in_contact = false;
    let mut walk = Walk::new(nodes);
    while let Some(ni) = walk.pop() {
        let node = &nodes[ni as usize];
        let (lb, ub) = node.bound(u);
        if (z + (lb - km.slack)) - max_h > 0.0 {
            continue; // wholly dry
        }
        if (z + (ub + km.slack)) - min_h <= 0.0 {
            in_contact = true;
            wet_faces::<LAW, true>(&c, faces, node.range(), &[], &mut acc, loads);
            continue;
        }
        if !node.is_leaf() {
            walk.push_pair(node.left, node.right);
            continue;
        }
        for i in node.range() {
            let d = if flat {
                let h = |k: usize| z + dot(u, faces.corner(k, i));
                [h(0), h(1), h(2)]
            } else {
                let (verts, position) = (faces.verts[i], pose.position);
                let mut h = |k: usize| {
                    heights.get(verts[k], surface, || position + rot * faces.corner(k, i))
                };
                [h(0), h(1), h(2)]
            };
            in_contact |= classify::<LAW, true>(&c, faces, i, d, wet, &mut acc, loads);
        }
    }
    wet_faces::<LAW, true>(&c, faces, 0..0, wet, &mut acc, loads);
    if !in_contact {
        return ForceSum::default();
    }
    finish(&c, &acc, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::hydro::face_force;

    /// A tiny deterministic generator (xorshift) for the tests.
    fn rng(seed: &mut u64) -> f64 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The lanes' law is the reference's, bit for bit, for every law, ventilation, pressure sign,
    /// buoyancy on the loaded or every wetted face, with the normal velocity given apart (smooth
    /// spin) or as v·N.
    #[test]
    fn lane_law_is_face_force_bit_for_bit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for law in ForceLaw::ALL {
            for options in 0..16u32 {
                let (lift, friction) = law.default_coefficients();
                let hp = HydroParams {
                    law,
                    lift,
                    friction,
                    density: 1000.0,
                    ventilated: options & 1 != 0,
                    opposing: options & 2 != 0,
                    smooth_spin: false,
                    rho_g: if options & 4 != 0 { 9810.0 } else { 0.0 },
                    hydrostatic_wetted: options & 8 != 0,
                };
                for i in 0..500 {
                    let mut r = || 2.0 * rng(&mut seed) - 1.0;
                    let normal = DVec3::new(r(), r(), r()).normalize();
                    let v = DVec3::new(10.0 * r(), 3.0 * r(), 2.0 * r());
                    let area = 1e-4 * (1.0 + r());
                    let depth = 0.01 * r();
                    // Every other face: a normal velocity of its own (the smooth body's).
                    let vn = if i % 2 == 0 { v.dot(normal) } else { 5.0 * r() };
                    let pose = Pose {
                        position: DVec3::ZERO,
                        velocity: v,
                        orientation: DQuat::IDENTITY,
                        angular_velocity: DVec3::ZERO,
                    };
                    let call = Call {
                        hp: &hp,
                        pose: &pose,
                        surface: &super::super::hydro::FlatSurface,
                        record: false,
                    };
                    let stone = crate::sim::stone::Stone::new(
                        &crate::sim::params::StoneParams::version_1(),
                    )
                    .unwrap();
                    let c = Ctx::new(stone.kernel(), &hp, &pose, None, &call);
                    let speed = v.length();
                    let expect = face_force(&hp, normal, area, v, vn, speed, depth);
                    let n = [[normal.x], [normal.y], [normal.z]];
                    let vv = [[v.x], [v.y], [v.z]];
                    let (a, vn, d) = (&[area], &[vn], &[depth]);
                    let (f, nonzero) = match law_code(law) {
                        PAPER => lane_law::<1, PAPER>(&c, &n, a, &vv, vn, d),
                        BOCQUET => lane_law::<1, BOCQUET>(&c, &n, a, &vv, vn, d),
                        _ => lane_law::<1, ROSELLINI>(&c, &n, a, &vv, vn, d),
                    };
                    let got = DVec3::new(f[0][0], f[1][0], f[2][0]);
                    assert_eq!(got.to_array(), expect.to_array(), "{law:?} {options}");
                    assert_eq!(nonzero[0], expect != DVec3::ZERO);
                }
            }
        }
    }

    /// The explicit-AVX2 chunks give the portable lanes' bits (where the machine has AVX2).
    #[cfg(target_arch = "x86_64")]
    /// The AVX2 chunks over faces `0..end` for `law`, with or without rotation.
    ///
    /// # Safety
    /// AVX2 must be available.
    #[cfg(target_arch = "x86_64")]
    unsafe fn simd_all(
        law: ForceLaw,
        spin: bool,
        c: &Ctx,
        faces: &FaceSoa,
        end: usize,
    ) -> LaneAcc<LANES> {
        let mut la = LaneAcc::<LANES>::default();
        let mut loads = Vec::new();
        macro_rules! go {
            ($law:ident, $rot:literal) => {
                // SAFETY: the caller checked AVX2.
                unsafe { simd::plain_chunks::<$law, $rot>(c, faces, 0, end, &mut la, &mut loads) }
            };
        }
        match (law_code(law), spin) {
            (PAPER, false) => go!(PAPER, false),
            (PAPER, true) => go!(PAPER, true),
            (BOCQUET, false) => go!(BOCQUET, false),
            (BOCQUET, true) => go!(BOCQUET, true),
            (_, false) => go!(ROSELLINI, false),
            (_, true) => go!(ROSELLINI, true),
        }
        la
    }

    #[test]
    fn avx2_chunks_match_the_portable_lanes_bit_for_bit() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        use crate::sim::params::{Shape, StoneParams};
        let stone = crate::sim::stone::Stone::new(&StoneParams {
            shape: Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            mass: 0.1,
            segments: 32,
            bands: None,
            quadrature: Default::default(),
        })
        .unwrap();
        let faces = &stone.kernel().faces;
        let end = faces.len() / LANES * LANES;
        let mut seed = 12345u64;
        // Wavy water: buoyancy reads each face's depth below a surface that is not a plane.
        struct Ripple;
        impl Surface for Ripple {
            fn height(&self, x: f64, y: f64) -> f64 {
                0.003 * (40.0 * x + 25.0 * y + 0.3).sin()
            }
            fn max_height(&self) -> f64 {
                0.003
            }
        }
        let flat = super::super::hydro::FlatSurface;
        for law in ForceLaw::ALL {
            for (ventilated, spin, extras) in (0..64u32).map(|k| (k & 1 != 0, k & 2 != 0, k >> 2)) {
                for surface in [&flat as &dyn Surface, &Ripple] {
                    let (lift, friction) = law.default_coefficients();
                    let hp = HydroParams {
                        law,
                        lift,
                        friction,
                        density: 1000.0,
                        ventilated,
                        opposing: extras & 1 != 0,
                        smooth_spin: extras & 2 != 0,
                        rho_g: if extras & 4 != 0 { 9810.0 } else { 0.0 },
                        hydrostatic_wetted: extras & 8 != 0,
                    };
                    let mut r = || 2.0 * rng(&mut seed) - 1.0;
                    let pose = Pose {
                        position: DVec3::new(0.0, 0.0, -0.004),
                        velocity: DVec3::new(10.0 * r(), 2.0 * r(), -3.0 * r().abs()),
                        orientation: DQuat::IDENTITY,
                        angular_velocity: if spin {
                            DVec3::new(r(), r(), r()) * 80.0
                        } else {
                            DVec3::ZERO
                        },
                    };
                    let call = Call {
                        hp: &hp,
                        pose: &pose,
                        surface,
                        record: false,
                    };
                    let c = Ctx::new(stone.kernel(), &hp, &pose, None, &call);
                    let run = |simd: bool| {
                        let mut la = LaneAcc::<LANES>::default();
                        if simd {
                            // SAFETY: AVX2 checked above.
                            la = unsafe { simd_all(law, spin, &c, faces, end) };
                        } else {
                            let mut loads = Vec::new();
                            for i in (0..end).step_by(LANES) {
                                let s = Contiguous(i);
                                match (law_code(law), spin) {
                                    (PAPER, false) => wet_chunk::<LANES, PAPER, false, _>(
                                        &c, faces, s, &mut la, &mut loads,
                                    ),
                                    (PAPER, true) => wet_chunk::<LANES, PAPER, true, _>(
                                        &c, faces, s, &mut la, &mut loads,
                                    ),
                                    (BOCQUET, false) => wet_chunk::<LANES, BOCQUET, false, _>(
                                        &c, faces, s, &mut la, &mut loads,
                                    ),
                                    (BOCQUET, true) => wet_chunk::<LANES, BOCQUET, true, _>(
                                        &c, faces, s, &mut la, &mut loads,
                                    ),
                                    (_, false) => wet_chunk::<LANES, ROSELLINI, false, _>(
                                        &c, faces, s, &mut la, &mut loads,
                                    ),
                                    (_, true) => wet_chunk::<LANES, ROSELLINI, true, _>(
                                        &c, faces, s, &mut la, &mut loads,
                                    ),
                                }
                            }
                        }
                        la
                    };
                    let (a, b) = (run(true), run(false));
                    let bits = |la: &LaneAcc<LANES>| {
                        let mut v: Vec<u64> = Vec::new();
                        for k in 0..3 {
                            v.extend(la.force[k].map(f64::to_bits));
                            v.extend(la.torque[k].map(f64::to_bits));
                        }
                        v.extend(la.area.map(f64::to_bits));
                        v.extend(la.axial.map(f64::to_bits));
                        v
                    };
                    assert_eq!(
                        bits(&a),
                        bits(&b),
                        "{law:?} vent {ventilated} spin {spin} options {extras} flat {}",
                        surface.is_flat()
                    );
                    assert!(a.area.iter().sum::<f64>() > 0.0);
                }
            }
        }
    }

    #[test]
    fn hierarchy_boxes_hold_their_items() {
        use crate::sim::params::{Shape, StoneParams};
        let stone = crate::sim::stone::Stone::new(&StoneParams {
            shape: Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            mass: 0.1,
            segments: 40,
            bands: None,
            quadrature: Default::default(),
        })
        .unwrap();
        let km = stone.kernel();
        assert_eq!(km.faces.len(), stone.mesh.triangles.len());
        assert_eq!(km.vertices.len(), stone.mesh.positions.len());
        for node in &km.face_nodes {
            for i in node.range() {
                for k in 0..3 {
                    let p = km.faces.corner(k, i);
                    let off = (p - node.centre).abs() - node.half;
                    assert!(off.max_element() <= km.slack, "corner outside its box");
                }
                let off = (km.faces.normal(i) - node.ncentre).abs() - node.nhalf;
                assert!(off.max_element() <= NORMAL_SLACK);
            }
            if !node.is_leaf() {
                let (l, r) = (
                    &km.face_nodes[node.left as usize],
                    &km.face_nodes[node.right as usize],
                );
                assert_eq!(
                    (l.start, l.end, r.start, r.end),
                    (node.start, r.start, l.end, node.end)
                );
            } else {
                assert!(node.end - node.start <= LEAF as u32);
            }
        }
    }
}
