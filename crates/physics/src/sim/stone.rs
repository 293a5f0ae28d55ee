//! The stone: a closed triangle mesh of revolution (paper §3.1, Fig. 3) or a thin box, its mass
//! properties from the mesh (signed-tetrahedron integrals), and its attitude (design.md §3–4).
//!
//! Body frame: centre of mass at the origin, symmetry axis = body z, a plate's length along body x.
//! Triangles wind counter-clockwise seen from outside, so `(b − a) × (c − a)` points outward.

use glam::{DMat3, DQuat, DVec3};

use std::sync::OnceLock;

use super::kernel::KernelMesh;
pub use super::mesh::{build_mesh, lens_bands, Mesh};
pub(crate) use super::mesh::{mass_properties, revolution_layout, RevolutionLayout};
use super::params::{Attitude, ParamError, Quadrature, Shape, StoneParams};
use super::smooth::SmoothLens;

/// The mesh arranged for the force kernel, built on first use. It is derived from the stone's
/// mesh, so two stones with equal meshes have equal kernels whether built or not.
#[derive(Debug, Clone, Default)]
struct LazyKernel(OnceLock<KernelMesh>);

impl PartialEq for LazyKernel {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// The rigid stone: mesh about its centre of mass, mass and inertia.
#[derive(Debug, Clone, PartialEq)]
pub struct Stone {
    /// The preset's shape and dimensions.
    pub shape: Shape,
    /// kg
    pub mass: f64,
    /// The closed triangle mesh, centred on the centre of mass (body frame).
    pub mesh: Mesh,
    /// Body-frame inertia about the centre of mass (kg m²).
    pub inertia: DMat3,
    /// Inverse of `inertia` (1/(kg m²), body frame).
    pub inv_inertia: DMat3,
    /// m³: the mesh's, or the smooth lens's with `stone.quadrature: Smooth`.
    pub volume: f64,
    /// Radius of the sphere about the centre of mass that holds every vertex.
    pub bounding_radius: f64,
    /// Body-frame outward unit normals and areas of the triangles.
    pub normals: Vec<DVec3>,
    /// Triangle areas (m²), in the order of the mesh's triangles.
    pub areas: Vec<f64>,
    /// How the mesh is laid out in rings, if it is (what the force kernel is built with).
    layout: Option<RevolutionLayout>,
    /// The mesh arranged for the force kernel (struct-of-arrays, bounding hierarchies), built on
    /// first use: a smooth lens over flat water never needs it.
    kernel: LazyKernel,
    /// `stone.quadrature: Smooth`: the lens's smooth ellipsoid, on which the forces are
    /// integrated over flat water (its clearance and sink test too: the mesh then only draws it).
    pub smooth: Option<SmoothLens>,
}

impl Stone {
    /// Builds the stone from its parameters (validated here): the mesh, moved so the centre of
    /// mass is at the origin, and its mass properties (the smooth lens's own with
    /// `quadrature: Smooth`); an error for a shape of no volume or a singular inertia.
    pub fn new(params: &StoneParams) -> Result<Self, ParamError> {
        params.validate()?;
        let mut mesh = build_mesh(&params.shape, params.segments, params.bands);
        let props = mass_properties(&mesh, params.mass);
        if props.volume <= 0.0 {
            return Err(ParamError::new(
                "stone.shape",
                "expected a shape with positive volume",
            ));
        }
        for p in &mut mesh.positions {
            *p -= props.centroid;
        }
        let inv_inertia = props.inertia.inverse();
        if !inv_inertia.is_finite() {
            return Err(ParamError::new(
                "stone.shape",
                "expected a shape with a finite, invertible inertia tensor",
            ));
        }
        let bounding_radius = mesh
            .positions
            .iter()
            .map(|p| p.length())
            .fold(0.0, f64::max);
        let (normals, areas): (Vec<DVec3>, Vec<f64>) = (0..mesh.triangles.len())
            .map(|i| mesh.normal_area(i))
            .unzip();
        let layout = revolution_layout(&params.shape, params.segments, params.bands);
        let smooth = match (params.quadrature, params.shape) {
            (Quadrature::Smooth { meridian, around }, Shape::Lens { radius, thickness }) => Some(
                SmoothLens::new(radius, 0.5 * thickness, meridian as usize, around as usize),
            ),
            _ => None,
        };
        // The smooth body's own mass properties (the inscribed mesh's are a little smaller).
        let (inertia, inv_inertia, volume) = match &smooth {
            Some(s) => {
                let i = s.inertia(params.mass);
                (i, i.inverse(), s.volume())
            }
            None => (props.inertia, inv_inertia, props.volume),
        };
        Ok(Self {
            layout,
            kernel: LazyKernel::default(),
            smooth,
            shape: params.shape,
            mass: params.mass,
            inertia,
            inv_inertia,
            volume,
            bounding_radius,
            mesh,
            normals,
            areas,
        })
    }

    /// How far the lowest vertex can stand above the lowest point of its rings over a surface of
    /// slope at most `slope` (`integrate::RevolutionBound`); 0 for the smooth lens over flat water,
    /// where its own surface is what meets the water (elsewhere the mesh does, as in `hydro`).
    /// `None` for a mesh that is not rings.
    pub fn facet_gap(&self, slope: f64) -> Option<f64> {
        if self.smooth.is_some() && slope == 0.0 {
            return Some(0.0);
        }
        self.kernel().facet_gap(slope)
    }

    /// The mesh arranged for the force kernel.
    pub fn kernel(&self) -> &KernelMesh {
        self.kernel.0.get_or_init(|| {
            KernelMesh::new(
                &self.mesh,
                &self.normals,
                &self.areas,
                self.layout.as_ref(),
                self.shape.is_revolution(),
                self.bounding_radius,
            )
        })
    }

    /// Principal moments (I_xx, I_yy, I_zz) in the body frame (the meshes are built on their
    /// principal axes).
    pub fn principal_moments(&self) -> DVec3 {
        DVec3::new(
            self.inertia.x_axis.x,
            self.inertia.y_axis.y,
            self.inertia.z_axis.z,
        )
    }

    /// True when the body is axisymmetric about body z (I_xx = I_yy): torque-free motion is then a
    /// regular precession with a closed form.
    pub fn is_axisymmetric(&self) -> bool {
        let m = self.principal_moments();
        (m.x - m.y).abs() <= 1e-9 * m.x.abs().max(m.y.abs())
    }
}

/// Orientation (stone → world) from the preset's angles: Rz(heading) · Rx(bank) · Ry(−tilt).
pub fn orientation_from_attitude(att: &Attitude) -> DQuat {
    DQuat::from_rotation_z(att.heading_deg.to_radians())
        * DQuat::from_rotation_x(att.bank_deg.to_radians())
        * DQuat::from_rotation_y(-att.tilt_deg.to_radians())
}

/// Attitude of the stone's axis relative to the direction of travel, in degrees
/// [tilt, bank, heading] (design.md §3): with d the unit horizontal velocity and s = ẑ × d,
/// tilt = asin(−a·d), bank = atan2(−a·s, a·ẑ), heading = atan2(d_y, d_x).
pub fn reported_attitude(world_from_stone: DQuat, velocity: DVec3) -> [f64; 3] {
    let a = world_from_stone * DVec3::Z;
    let horizontal = DVec3::new(velocity.x, velocity.y, 0.0);
    let d = if horizontal.length_squared() > 1e-24 {
        horizontal.normalize()
    } else {
        // At rest horizontally: use the stone's own +x direction, projected.
        let bx = world_from_stone * DVec3::X;
        let h = DVec3::new(bx.x, bx.y, 0.0);
        if h.length_squared() > 1e-24 {
            h.normalize()
        } else {
            DVec3::X
        }
    };
    let s = DVec3::Z.cross(d);
    let tilt = (-a.dot(d)).clamp(-1.0, 1.0).asin();
    let bank = (-a.dot(s)).atan2(a.z);
    let heading = d.y.atan2(d.x);
    [tilt.to_degrees(), bank.to_degrees(), heading.to_degrees()]
}

/// Inclination of the stone's plane to the water (degrees) from a reported [tilt, bank, heading]
/// ([`reported_attitude`]): the axis has a_z = cos(tilt)·cos(bank).
pub fn inclination(att: [f64; 3]) -> f64 {
    (att[0].to_radians().cos() * att[1].to_radians().cos())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// The stone's axis (world) from a reported [tilt, bank, heading]: [`reported_attitude`] inverted.
pub fn axis_from_reported(att: [f64; 3]) -> DVec3 {
    let (t, b, h) = (
        att[0].to_radians(),
        att[1].to_radians(),
        att[2].to_radians(),
    );
    let d = DVec3::new(h.cos(), h.sin(), 0.0);
    let s = DVec3::Z.cross(d);
    let az = t.cos() * b.cos();
    d * (-t.sin()) + s * (-b.tan() * az) + DVec3::Z * az
}

#[cfg(test)]
mod tests {
    use super::*;

    fn closed_and_outward(mesh: &Mesh) {
        // Closed: every directed edge appears once and its reverse once.
        let mut edges = std::collections::HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge {a}->{b} repeated");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}->{b} unmatched");
        }
        // Outward: positive volume; each normal points away from the centroid for convex shapes.
        for i in 0..mesh.triangles.len() {
            let (n, area) = mesh.normal_area(i);
            let [a, b, c] = mesh.corners(i);
            let centre = (a + b + c) / 3.0;
            assert!(area > 0.0);
            assert!(n.dot(centre) > 0.0, "triangle {i} points inward");
        }
    }

    #[test]
    fn meshes_are_closed_with_outward_normals() {
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
                thickness: 0.002,
            },
        ] {
            closed_and_outward(&build_mesh(&shape, 24, None));
        }
    }

    #[test]
    fn disk_mass_properties_match_cylinder_formulas_to_polygon_accuracy() {
        let (r, t, m) = (0.05, 0.01, 0.1);
        let n = 256;
        let mesh = build_mesh(
            &Shape::Disk {
                radius: r,
                thickness: t,
            },
            n,
            None,
        );
        let p = mass_properties(&mesh, m);
        // Inscribed polygon: area (n/2) r² sin(2π/n).
        let poly_area = 0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).sin();
        assert!((p.volume - poly_area * t).abs() < 1e-15);
        assert!(p.centroid.length() < 1e-15);
        // Polygon's polar moment differs from the circle's by O((2π/n)²).
        let rel = (2.0 * std::f64::consts::PI / n as f64).powi(2);
        let i3 = 0.5 * m * r * r;
        let i1 = 0.25 * m * r * r + m * t * t / 12.0;
        assert!((p.inertia.z_axis.z - i3).abs() / i3 < rel);
        assert!((p.inertia.x_axis.x - i1).abs() / i1 < rel);
        assert!(p.inertia.x_axis.y.abs() < 1e-12 * i1);
    }

    #[test]
    fn plate_inertia_is_exact() {
        let (a, b, c, m) = (0.1, 0.06, 0.004, 0.2);
        let p = mass_properties(
            &build_mesh(
                &Shape::Plate {
                    length: a,
                    width: b,
                    thickness: c,
                },
                8,
                None,
            ),
            m,
        );
        assert!((p.volume - a * b * c).abs() < 1e-18);
        let expect = DVec3::new(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12.0);
        let got = DVec3::new(p.inertia.x_axis.x, p.inertia.y_axis.y, p.inertia.z_axis.z);
        assert!((got - expect).length() < 1e-15, "{got} vs {expect}");
    }

    /// `stone.bands` sets a lens's latitude bands: 2n(bands − 1) triangles, closed and outward,
    /// its layout describing the mesh; `None` is the mesh of half the segments.
    #[test]
    fn lens_bands_set_the_latitude_rings() {
        let lens = Shape::Lens {
            radius: 0.05,
            thickness: 0.012,
        };
        for (n, bands) in [(32, 4), (48, 12), (40, 48), (64, 32)] {
            let mesh = build_mesh(&lens, n, Some(bands));
            closed_and_outward(&mesh);
            assert_eq!(mesh.triangles.len(), 2 * n as usize * (bands as usize - 1));
            let layout = revolution_layout(&lens, n, Some(bands)).unwrap();
            assert_eq!(layout.rings.len(), bands as usize + 1);
        }
        assert_eq!(build_mesh(&lens, 64, None), build_mesh(&lens, 64, Some(32)));
    }

    #[test]
    fn lens_volume_converges_to_ellipsoid() {
        let (r, t) = (0.05, 0.012);
        let exact = 4.0 / 3.0 * std::f64::consts::PI * r * r * 0.5 * t;
        let mut last_err = f64::INFINITY;
        for n in [16, 32, 64, 128] {
            let p = mass_properties(
                &build_mesh(
                    &Shape::Lens {
                        radius: r,
                        thickness: t,
                    },
                    n,
                    None,
                ),
                0.1,
            );
            let err = (p.volume - exact).abs() / exact;
            assert!(
                err < last_err / 3.0,
                "second-order convergence: {err} after {last_err}"
            );
            last_err = err;
        }
        // Inscribed polygons lose ~(2π/n)²/6 of the area around; the meridian, at the same angular
        // spacing, loses at most twice that of the volume (its chords are weighted by r²).
        let bound = (std::f64::consts::TAU / 128.0).powi(2) / 2.0;
        assert!(last_err < bound, "{last_err} vs {bound}");
    }

    #[test]
    fn reported_attitude_equals_preset_when_velocity_along_heading() {
        let att = Attitude {
            tilt_deg: 17.0,
            bank_deg: -8.0,
            heading_deg: 30.0,
        };
        let q = orientation_from_attitude(&att);
        let h = att.heading_deg.to_radians();
        let v = DVec3::new(5.0 * h.cos(), 5.0 * h.sin(), -1.0);
        let r = reported_attitude(q, v);
        assert!((r[0] - 17.0).abs() < 1e-9, "{r:?}");
        assert!((r[1] + 8.0).abs() < 1e-9, "{r:?}");
        assert!((r[2] - 30.0).abs() < 1e-9, "{r:?}");
    }

    #[test]
    fn tilt_raises_the_leading_edge() {
        let q = orientation_from_attitude(&Attitude {
            tilt_deg: 20.0,
            bank_deg: 0.0,
            heading_deg: 0.0,
        });
        let front = q * DVec3::new(0.05, 0.0, 0.0);
        assert!(front.z > 0.0);
    }
}
