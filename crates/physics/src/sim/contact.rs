//! Triangle ∩ water (paper §3.2, Fig. 5): the wetted part of a triangle is the triangle clipped by
//! the water surface — a triangle (one vertex under), a quadrilateral (two under) or the whole
//! triangle (three under). Area by the cross product, ½|Σ pᵢ × pᵢ₊₁|, and the area centroid.
//!
//! The paper's Heron formula (eqs. 9–10) equals the cross product in exact arithmetic but loses all
//! digits on slivers; it is kept here only as the studied alternative ([`heron_area`]).

use glam::DVec3;

/// The wetted part of one triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WettedPatch {
    /// m²
    pub area: f64,
    /// Area centroid (world frame).
    pub centroid: DVec3,
}

/// Clips triangle `p` by the water surface. `d[i]` is vertex i's signed height above the surface
/// (z − η); a vertex is wet when `d ≤ 0`. Along each edge the surface is taken as linear, which is
/// exact for a flat surface. Returns `None` when no vertex is wet.
pub(crate) fn clip_triangle(p: [DVec3; 3], d: [f64; 3]) -> Option<WettedPatch> {
    let wet = [d[0] <= 0.0, d[1] <= 0.0, d[2] <= 0.0];
    let count = wet.iter().filter(|&&w| w).count();
    match count {
        0 => None,
        3 => {
            let (area, centroid) = polygon_area_centroid(&p);
            Some(WettedPatch { area, centroid })
        }
        _ => {
            let mut poly = [DVec3::ZERO; 4];
            let mut n = 0;
            for i in 0..3 {
                let j = (i + 1) % 3;
                if wet[i] {
                    poly[n] = p[i];
                    n += 1;
                }
                if wet[i] != wet[j] {
                    // d[i] and d[j] have opposite signs (one ≤ 0 < other), so the denominator is > 0.
                    let s = d[i] / (d[i] - d[j]);
                    poly[n] = p[i] + (p[j] - p[i]) * s;
                    n += 1;
                }
            }
            let (area, centroid) = polygon_area_centroid(&poly[..n]);
            Some(WettedPatch { area, centroid })
        }
    }
}

/// Area (½|Σ (pₖ − p₀) × (pₖ₊₁ − p₀)|) and area centroid of a planar convex polygon.
pub fn polygon_area_centroid(pts: &[DVec3]) -> (f64, DVec3) {
    if pts.len() < 3 {
        return (0.0, pts.first().copied().unwrap_or(DVec3::ZERO));
    }
    let p0 = pts[0];
    let mut area_vec = DVec3::ZERO;
    let mut weighted = DVec3::ZERO;
    let mut weight = 0.0;
    for k in 1..pts.len() - 1 {
        let c = (pts[k] - p0).cross(pts[k + 1] - p0);
        area_vec += c;
        let w = c.length();
        weighted += (p0 + pts[k] + pts[k + 1]) * (w / 3.0);
        weight += w;
    }
    let area = 0.5 * area_vec.length();
    let centroid = if weight > 0.0 {
        weighted / weight
    } else {
        pts.iter().copied().sum::<DVec3>() / pts.len() as f64
    };
    (area, centroid)
}

/// Heron's formula (paper eqs. 9–10) from the side lengths, as printed: s = (a+b+c)/2,
/// S = √(s(s−a)(s−b)(s−c)). Cancellation makes it lose every digit on slivers.
pub fn heron_area(p: [DVec3; 3]) -> f64 {
    let a = (p[0] - p[1]).length();
    let b = (p[1] - p[2]).length();
    let c = (p[2] - p[0]).length();
    let s = 0.5 * (a + b + c);
    (s * (s - a) * (s - b) * (s - c)).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> [DVec3; 3] {
        [
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(2.0, 0.0, 1.0),
            DVec3::new(0.0, 2.0, 1.0),
        ]
    }

    fn heights(p: [DVec3; 3], level: f64) -> [f64; 3] {
        [p[0].z - level, p[1].z - level, p[2].z - level]
    }

    #[test]
    fn dry_triangle_has_no_patch() {
        let p = tri();
        assert!(clip_triangle(p, heights(p, -2.0)).is_none());
    }

    #[test]
    fn all_under_is_whole_triangle() {
        // Fig. 5(a).
        let p = tri();
        let w = clip_triangle(p, heights(p, 5.0)).unwrap();
        let exact = 0.5 * (DVec3::new(2.0, 0.0, 2.0).cross(DVec3::new(0.0, 2.0, 2.0))).length();
        assert!((w.area - exact).abs() < 1e-15);
        assert!((w.centroid - DVec3::new(2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0)).length() < 1e-15);
    }

    #[test]
    fn one_under_is_similar_triangle() {
        // Fig. 5(c): vertex 0 under, at level 0 the wet part is the corner triangle scaled by 1/2.
        let p = tri();
        let full = clip_triangle(p, heights(p, 5.0)).unwrap().area;
        let w = clip_triangle(p, heights(p, 0.0)).unwrap();
        assert!(
            (w.area - full * 0.25).abs() < 1e-14,
            "{} vs {}",
            w.area,
            full * 0.25
        );
        // Centroid of the corner triangle (p0, mid01, mid02).
        let c = (p[0] + (p[0] + p[1]) * 0.5 + (p[0] + p[2]) * 0.5) / 3.0;
        assert!((w.centroid - c).length() < 1e-15);
    }

    #[test]
    fn two_under_is_quadrilateral_complement() {
        // Fig. 5(b): the wet part is the triangle minus the dry corner triangle.
        let p = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(2.0, 0.0, -1.0),
            DVec3::new(0.0, 2.0, -1.0),
        ];
        let full = clip_triangle(p, heights(p, 5.0)).unwrap();
        let w = clip_triangle(p, heights(p, 0.0)).unwrap();
        assert!((w.area - 0.75 * full.area).abs() < 1e-14);
        // Centroid: (full·c_full − dry·c_dry)/wet.
        let dry_c = (p[0] + (p[0] + p[1]) * 0.5 + (p[0] + p[2]) * 0.5) / 3.0;
        let c = (full.centroid * full.area - dry_c * 0.25 * full.area) / (0.75 * full.area);
        assert!((w.centroid - c).length() < 1e-14);
    }

    #[test]
    fn wet_area_is_continuous_across_levels() {
        let p = tri();
        let mut last = 0.0;
        for k in 0..=400 {
            let level = -1.0 + 2.0 * k as f64 / 400.0;
            let a = clip_triangle(p, heights(p, level)).map_or(0.0, |w| w.area);
            assert!(a >= last - 1e-15, "area must grow with the water level");
            assert!(a - last < 0.05, "no jumps");
            last = a;
        }
    }

    #[test]
    fn sliver_cross_product_exact_heron_loses_digits() {
        // A needle: base 1, height 1e-9, area 5e-10 exactly (representable vertices).
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.5, 1e-9, 0.0),
        ];
        let exact = 0.5e-9;
        let (a, _) = polygon_area_centroid(&p);
        assert!((a - exact).abs() / exact < 1e-12, "cross product {a}");
        let h = heron_area(p);
        assert!(
            (h - exact).abs() / exact > 1e-3,
            "Heron {h} should be badly off on a sliver"
        );
    }
}
