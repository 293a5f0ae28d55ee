//! The smooth quadrature of a lens (`stone.quadrature: Smooth`, src/sim/smooth.rs) on a whole
//! throw: the shipped default throw with the water off (flat water), as shipped otherwise.
//!
//! The quadrature integrates the same per-area law over the ellipsoid the mesh is inscribed in, so
//! refined meshes must converge to it (a faceted surface's error falls as the square of the facet
//! size: halving it cuts the error about four-fold), and its own node counts must agree with each
//! other to well within the 1 % the shipped mesh is held to.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use stoneskip_physics::sim::params::{Preset, Quadrature};
use stoneskip_physics::sim::Summary;

fn default_throw(segments: u32, quadrature: Quadrature) -> Summary {
    let mut p: Preset = stoneskip_physics::preset::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/presets/default.ron"
    )))
    .unwrap();
    p.water.enabled = false;
    // The quasi-steady contact: the quadrature's convergence of the force, read off a throw whose
    // end is not a threshold (with the memory the throw's last slide starts at one skip or the
    // next as the mesh passes 96 → 128 segments: 1 % of distance; crates/lab/tests/whole_throw.rs).
    p.physics.wetted_memory = None;
    p.stone.segments = segments;
    p.stone.bands = Some(segments / 2);
    p.stone.quadrature = quadrature;
    stoneskip_physics::sim::simulate(&p).unwrap()
}

fn smooth(meridian: u32, around: u32) -> Quadrature {
    Quadrature::Smooth { meridian, around }
}

#[test]
fn meshes_converge_to_the_smooth_quadrature_on_a_whole_throw() {
    let reference = default_throw(32, smooth(32, 12));
    let coarse = default_throw(16, smooth(12, 2));
    let rel = |s: &Summary| (s.distance - reference.distance).abs() / reference.distance;
    assert_eq!(coarse.skips, reference.skips);
    // The quadrature's own convergence: far inside the 1 % a shipped mesh must meet.
    assert!(
        rel(&coarse) < 2e-3,
        "{} vs {}",
        coarse.distance,
        reference.distance
    );
    let m48 = default_throw(48, Quadrature::Faces);
    let m96 = default_throw(96, Quadrature::Faces);
    assert_eq!(m96.skips, reference.skips);
    // Halving the facets cuts the mesh's error about four-fold (at least two-fold here).
    assert!(rel(&m96) < 0.5 * rel(&m48), "{} {}", rel(&m96), rel(&m48));
    assert!(rel(&m96) < 5e-3, "{}", rel(&m96));
}

/// The same preset gives the same bits with the smooth quadrature too.
#[test]
fn smooth_quadrature_is_deterministic() {
    let a = default_throw(16, smooth(12, 2));
    let b = default_throw(16, smooth(12, 2));
    assert_eq!(a, b);
    assert!(a.skips > 0 && a.force_evals > 0);
}
