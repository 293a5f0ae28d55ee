//! Geometry for the GPU: the stone's vertices with smooth normals split at creases, and the
//! triangle indices of the projected water grid. Built once per stone or viewport size, never per
//! frame.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use stoneskip_physics::sim::stone::Mesh;

/// Faces meeting at more than this angle keep a hard edge (a disc's rim, a plate's corners).
pub const CREASE_DEG: f64 = 50.0;

/// One vertex of the stone: body-frame position and normal.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct StoneVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// Unindexed vertices (three per triangle) with normals averaged over the faces around each
/// corner's vertex whose normals are within [`CREASE_DEG`] of the corner's face.
pub fn stone_vertices(mesh: &Mesh) -> Vec<StoneVertex> {
    let n_tri = mesh.triangles.len();
    let face: Vec<(DVec3, f64)> = (0..n_tri).map(|i| mesh.normal_area(i)).collect();
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); mesh.positions.len()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for &v in tri {
            if let Some(list) = around.get_mut(v as usize) {
                list.push(t);
            }
        }
    }
    let cos_crease = CREASE_DEG.to_radians().cos();
    let mut out = Vec::with_capacity(3 * n_tri);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let (fn_t, _) = face[t];
        for &v in tri {
            let mut sum = DVec3::ZERO;
            if let Some(list) = around.get(v as usize) {
                for &o in list {
                    let (fn_o, area) = face[o];
                    if fn_o.dot(fn_t) >= cos_crease {
                        sum += fn_o * area;
                    }
                }
            }
            let normal = sum.try_normalize().unwrap_or(fn_t);
            let p = mesh
                .positions
                .get(v as usize)
                .copied()
                .unwrap_or(DVec3::ZERO);
            out.push(StoneVertex {
                position: p.as_vec3().to_array(),
                normal: normal.as_vec3().to_array(),
            });
        }
    }
    out
}

/// A cheap fingerprint of a mesh (so the renderer re-uploads only a changed stone).
pub fn mesh_key(mesh: &Mesh) -> u64 {
    // FNV-1a over the coordinates' bits and the triangle count.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: u64| {
        h ^= x;
        h = h.wrapping_mul(0x0100_0000_01b3);
    };
    eat(mesh.triangles.len() as u64);
    for p in &mesh.positions {
        eat(p.x.to_bits());
        eat(p.y.to_bits());
        eat(p.z.to_bits());
    }
    h
}

/// Triangle indices of an `mx` × `my` vertex grid (vertex index = iy * mx + ix).
pub fn grid_indices(mx: u32, my: u32) -> Vec<u32> {
    let mut idx = Vec::with_capacity(6 * (mx.saturating_sub(1) * my.saturating_sub(1)) as usize);
    for iy in 0..my.saturating_sub(1) {
        for ix in 0..mx.saturating_sub(1) {
            let a = iy * mx + ix;
            let b = a + 1;
            let c = a + mx;
            let d = c + 1;
            idx.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    idx
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use stoneskip_physics::sim::params::{Shape, StoneParams};
    use stoneskip_physics::sim::stone::Stone;

    #[test]
    fn stone_normals_point_outward() {
        for shape in [
            Shape::Disk {
                radius: 0.05,
                thickness: 0.01,
            },
            Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            Shape::Plate {
                length: 0.1,
                width: 0.08,
                thickness: 0.004,
            },
        ] {
            let stone = Stone::new(&StoneParams {
                shape,
                mass: 0.1,
                segments: 24,
                bands: None,
                quadrature: Default::default(),
            })
            .unwrap();
            let v = stone_vertices(&stone.mesh);
            assert_eq!(v.len(), 3 * stone.mesh.triangles.len());
            for x in &v {
                let p = Vec3::from_array(x.position);
                let n = Vec3::from_array(x.normal);
                assert!((n.length() - 1.0).abs() < 1e-4);
                assert!(n.dot(p) > -1e-6, "{shape:?}: inward normal at {p:?}");
            }
        }
    }

    #[test]
    fn grid_indices_cover_every_cell() {
        let idx = grid_indices(3, 2);
        assert_eq!(idx.len(), 12);
        assert!(idx.iter().all(|&i| i < 6));
    }
}
