//! The stone's triangle mesh (paper §3.1, Fig. 3): a closed mesh of revolution (disk, lens) or a
//! thin box (plate), its mass properties by signed tetrahedra, and its layout in rings for the
//! force kernel. Body frame: centre of mass at the origin, symmetry axis = body z, a plate's length
//! along body x; triangles wind counter-clockwise seen from outside, so `(b − a) × (c − a)` points
//! outward.

use glam::{DMat3, DVec3};

use super::params::Shape;

/// A closed triangle mesh in the stone's body frame (centre of mass at the origin).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Vertex positions (m, body frame).
    pub positions: Vec<DVec3>,
    /// Vertex indices of each triangle, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Outward unit normal and area of triangle `i` (body frame).
    pub fn normal_area(&self, i: usize) -> (DVec3, f64) {
        let [a, b, c] = self.corners(i);
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len > 0.0 {
            (n / len, 0.5 * len)
        } else {
            (DVec3::Z, 0.0)
        }
    }

    /// The three vertices of triangle `i` in winding order (m, body frame).
    pub fn corners(&self, i: usize) -> [DVec3; 3] {
        let [a, b, c] = self.triangles[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Total surface area.
    pub fn surface_area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|i| self.normal_area(i).1)
            .sum()
    }
}

/// Volume, centroid and inertia of a closed mesh of uniform density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MassProperties {
    pub volume: f64,
    pub centroid: DVec3,
    /// Inertia tensor about the centroid, for the given mass (kg m²).
    pub inertia: DMat3,
}

/// Mass properties by summing signed tetrahedra (origin, a, b, c) over the triangles: the second
/// moment of a tetrahedron is det/120 · (a aᵀ + b bᵀ + c cᵀ + s sᵀ), s = a + b + c.
pub(crate) fn mass_properties(mesh: &Mesh, mass: f64) -> MassProperties {
    let mut vol6 = 0.0;
    let mut first = DVec3::ZERO;
    let mut second = DMat3::ZERO;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let det = a.dot(b.cross(c));
        let s = a + b + c;
        vol6 += det;
        first += det * s;
        let outer = |u: DVec3| DMat3::from_cols(u * u.x, u * u.y, u * u.z);
        second += (outer(a) + outer(b) + outer(c) + outer(s)) * (det / 120.0);
    }
    let volume = vol6 / 6.0;
    if volume.abs() < f64::MIN_POSITIVE {
        return MassProperties {
            volume: 0.0,
            centroid: DVec3::ZERO,
            inertia: DMat3::IDENTITY * mass,
        };
    }
    let centroid = first / (4.0 * vol6);
    let density = mass / volume;
    // Second moment about the origin, then about the centroid (parallel axis).
    let c_o = second * density;
    let c_cm = c_o
        - DMat3::from_cols(
            centroid * centroid.x,
            centroid * centroid.y,
            centroid * centroid.z,
        ) * mass;
    let trace = c_cm.x_axis.x + c_cm.y_axis.y + c_cm.z_axis.z;
    let inertia = DMat3::IDENTITY * trace - c_cm;
    MassProperties {
        volume,
        centroid,
        inertia,
    }
}

/// A lens's latitude bands: `bands` when a preset names it, else half the segments; at least 4.
pub fn lens_bands(segments: u32, bands: Option<u32>) -> u32 {
    bands.unwrap_or(segments / 2).max(4)
}

/// Builds the mesh of a shape, not yet centred: `segments` around, and for a lens `bands`
/// latitude bands ([`lens_bands`]).
pub fn build_mesh(shape: &Shape, segments: u32, bands: Option<u32>) -> Mesh {
    let n = segments.max(3) as usize;
    match *shape {
        Shape::Disk { radius, thickness } => disk_mesh(radius, thickness, n),
        Shape::Lens { radius, thickness } => {
            lens_mesh(radius, thickness, n, lens_bands(segments, bands) as usize)
        }
        Shape::Plate {
            length,
            width,
            thickness,
        } => plate_mesh(length, width, thickness),
    }
}

/// How a mesh of revolution from [`build_mesh`] is laid out (the force kernel's ring path; the
/// kernel checks it against the mesh before using it): rings of vertices at azimuths 2πj/n, and
/// strips of faces between two rings, column by column.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RevolutionLayout {
    /// Vertices per ring (n).
    pub segments: usize,
    /// Each ring's vertex indices in azimuth order (n of them), or one vertex (a pole).
    pub rings: Vec<Vec<u32>>,
    /// Each strip's two rings and, for each column j (between azimuths j and j + 1), the
    /// triangles whose corners are among those rings' vertices j and j + 1.
    pub strips: Vec<([usize; 2], Vec<Vec<u32>>)>,
}

/// The layout of [`build_mesh`]'s mesh for a disk or a lens; `None` for a plate.
pub(crate) fn revolution_layout(
    shape: &Shape,
    segments: u32,
    bands: Option<u32>,
) -> Option<RevolutionLayout> {
    let n = segments.max(3) as usize;
    let column = |f: &dyn Fn(usize) -> Vec<u32>| (0..n).map(f).collect::<Vec<_>>();
    match *shape {
        Shape::Disk { .. } => {
            // Vertices: 0 top centre, 1 bottom centre, 2 + 2i top rim, 3 + 2i bottom rim; faces
            // 4i top, 4i + 1 bottom, 4i + 2 and 4i + 3 the side.
            let rim = |k: u32| (0..n as u32).map(|i| k + 2 * i).collect();
            Some(RevolutionLayout {
                segments: n,
                rings: vec![vec![0], rim(2), rim(3), vec![1]],
                strips: vec![
                    ([0, 1], column(&|i| vec![4 * i as u32])),
                    (
                        [1, 2],
                        column(&|i| vec![4 * i as u32 + 2, 4 * i as u32 + 3]),
                    ),
                    ([2, 3], column(&|i| vec![4 * i as u32 + 1])),
                ],
            })
        }
        Shape::Lens { .. } => {
            let bands = lens_bands(segments, bands) as usize;
            let mut rings = vec![vec![0]];
            for k in 1..bands {
                rings.push((0..n).map(|i| (1 + (k - 1) * n + i) as u32).collect());
            }
            rings.push(vec![(1 + n * (bands - 1)) as u32]);
            let mut strips = vec![([0, 1], column(&|i| vec![i as u32]))];
            for k in 1..bands - 1 {
                let start = n + (k - 1) * 2 * n;
                strips.push((
                    [k, k + 1],
                    column(&|i| vec![(start + 2 * i) as u32, (start + 2 * i + 1) as u32]),
                ));
            }
            let start = n + (bands - 2) * 2 * n;
            strips.push(([bands - 1, bands], column(&|i| vec![(start + i) as u32])));
            Some(RevolutionLayout {
                segments: n,
                rings,
                strips,
            })
        }
        Shape::Plate { .. } => None,
    }
}

fn ring_point(radius: f64, angle: f64, z: f64) -> DVec3 {
    DVec3::new(radius * angle.cos(), radius * angle.sin(), z)
}

fn disk_mesh(radius: f64, thickness: f64, n: usize) -> Mesh {
    let h = 0.5 * thickness;
    let mut positions = Vec::with_capacity(2 * n + 2);
    positions.push(DVec3::new(0.0, 0.0, h)); // 0: top centre
    positions.push(DVec3::new(0.0, 0.0, -h)); // 1: bottom centre
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        positions.push(ring_point(radius, a, h)); // 2 + 2i: top rim
        positions.push(ring_point(radius, a, -h)); // 3 + 2i: bottom rim
    }
    let top = |i: usize| (2 + 2 * (i % n)) as u32;
    let bot = |i: usize| (3 + 2 * (i % n)) as u32;
    let mut triangles = Vec::with_capacity(4 * n);
    for i in 0..n {
        triangles.push([0, top(i), top(i + 1)]);
        triangles.push([1, bot(i + 1), bot(i)]);
        triangles.push([bot(i), bot(i + 1), top(i + 1)]);
        triangles.push([bot(i), top(i + 1), top(i)]);
    }
    Mesh {
        positions,
        triangles,
    }
}

/// Ellipsoid of revolution: `n` around, `bands` latitude bands uniform in the polar angle.
fn lens_mesh(radius: f64, thickness: f64, n: usize, bands: usize) -> Mesh {
    let h = 0.5 * thickness;
    let mut positions = Vec::with_capacity(2 + n * (bands - 1));
    positions.push(DVec3::new(0.0, 0.0, h)); // north pole
    for k in 1..bands {
        let phi = std::f64::consts::PI * k as f64 / bands as f64;
        let (s, c) = phi.sin_cos();
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            positions.push(ring_point(radius * s, a, h * c));
        }
    }
    positions.push(DVec3::new(0.0, 0.0, -h)); // south pole
    let south = (positions.len() - 1) as u32;
    let ring = |k: usize, i: usize| (1 + (k - 1) * n + (i % n)) as u32;
    let mut triangles = Vec::with_capacity(2 * n * bands);
    for i in 0..n {
        triangles.push([0, ring(1, i), ring(1, i + 1)]);
    }
    for k in 1..bands - 1 {
        for i in 0..n {
            let (a, b) = (ring(k, i), ring(k, i + 1));
            let (c, d) = (ring(k + 1, i), ring(k + 1, i + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    for i in 0..n {
        triangles.push([south, ring(bands - 1, i + 1), ring(bands - 1, i)]);
    }
    Mesh {
        positions,
        triangles,
    }
}

fn plate_mesh(length: f64, width: f64, thickness: f64) -> Mesh {
    let (x, y, z) = (0.5 * length, 0.5 * width, 0.5 * thickness);
    let positions = vec![
        DVec3::new(-x, -y, -z),
        DVec3::new(x, -y, -z),
        DVec3::new(x, y, -z),
        DVec3::new(-x, y, -z),
        DVec3::new(-x, -y, z),
        DVec3::new(x, -y, z),
        DVec3::new(x, y, z),
        DVec3::new(-x, y, z),
    ];
    let triangles = vec![
        [0, 2, 1],
        [0, 3, 2], // bottom (−z)
        [4, 5, 6],
        [4, 6, 7], // top (+z)
        [0, 1, 5],
        [0, 5, 4], // −y
        [2, 3, 7],
        [2, 7, 6], // +y
        [1, 2, 6],
        [1, 6, 5], // +x
        [3, 0, 4],
        [3, 4, 7], // −x
    ];
    Mesh {
        positions,
        triangles,
    }
}
