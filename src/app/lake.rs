//! Does the throw stay on the lake? Before a throw the stone is run once on flat water (no grid:
//! cheap, as `sim::scenario::fit_water_to_throw` sizes lakes) and its track's extent is compared
//! with the water grid. With wavy contact the real track differs from the flat-water one, so the
//! check keeps a margin ([`WARN_MARGIN`]) and the fit a larger one ([`FIT_MARGIN`]).

use stoneskip_physics::sim::params::{Preset, MAX_WATER_COLUMNS};
use stoneskip_physics::sim::scenario::fit_water_to_throw;
use stoneskip_physics::sim::Simulation;

/// The flat-water track coming closer than this to an edge (m) counts as leaving the lake.
pub const WARN_MARGIN: f64 = 0.5;
/// Water added on every side of the flat-water track when the lake is fitted to the throw (m).
pub const FIT_MARGIN: f64 = 3.0;

/// An axis-aligned rectangle in the water plane (m): `lo` the −x, −y corner, `hi` the +x, +y one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub lo: [f64; 2],
    pub hi: [f64; 2],
}

/// The lake of a preset: its grid's rectangle, or `None` without water.
pub fn lake_rect(p: &Preset) -> Option<Rect> {
    if !p.water.enabled {
        return None;
    }
    let lo = p
        .water
        .origin_for([p.launch.position[0], p.launch.position[1]]);
    Some(Rect {
        lo,
        hi: [lo[0] + p.water.size[0], lo[1] + p.water.size[1]],
    })
}

/// Most force evaluations the flat-water check may spend (it runs on the UI thread): a shipped
/// preset needs at most 2.5·10⁴ (`record_throw`); a throw costlier than this (finding S1 in
/// docs/reliability.md) goes unchecked rather than freeze the app.
pub const MAX_CHECK_EVALS: u64 = 400_000;

/// The extent of the stone's track on flat water (its centre of mass from launch to outcome), or
/// why there is none (an invalid preset, or a throw too costly to check).
pub fn flat_track(p: &Preset) -> Result<Rect, String> {
    flat_track_until(p, &|| false)
}

/// [`flat_track`], given up (an error) as soon as `stop` says so.
pub fn flat_track_until(p: &Preset, stop: &dyn Fn() -> bool) -> Result<Rect, String> {
    let mut dry = p.clone();
    dry.water.enabled = false;
    let mut sim = Simulation::new(&dry).map_err(|e| e.to_string())?;
    let s = sim.state().position;
    let (mut lo, mut hi) = ([s.x, s.y], [s.x, s.y]);
    let too_costly = |(_, evals): (u64, u64)| evals >= MAX_CHECK_EVALS || stop();
    while !sim.is_finished() {
        if too_costly(sim.cost()) {
            return Err(format!(
                "the throw costs more than {MAX_CHECK_EVALS} force evaluations on flat water: \
                 not checked against the lake"
            ));
        }
        sim.tick_until(
            &mut |step| {
                let q = step.state.position;
                if q.x.is_finite() && q.y.is_finite() {
                    lo = [lo[0].min(q.x), lo[1].min(q.y)];
                    hi = [hi[0].max(q.x), hi[1].max(q.y)];
                }
            },
            &too_costly,
        );
    }
    Ok(Rect { lo, hi })
}

/// Where the flat-water track leaves the lake (or comes within `margin` of its edge): the edges
/// crossed, in words, or `None` when the track stays inside.
pub fn leaves_lake(track: Rect, lake: Rect, margin: f64) -> Option<String> {
    let mut edges = Vec::new();
    if track.hi[0] > lake.hi[0] - margin {
        edges.push("far (+x)");
    }
    if track.lo[0] < lake.lo[0] + margin {
        edges.push("near (−x)");
    }
    if track.hi[1] > lake.hi[1] - margin {
        edges.push("left (+y)");
    }
    if track.lo[1] < lake.lo[1] + margin {
        edges.push("right (−y)");
    }
    (!edges.is_empty()).then(|| edges.join(" and "))
}

/// Columns of a lake covering `track` plus `margin` on every side in cells of `cell` metres,
/// counted as `fit_water_to_throw` sizes it.
pub fn fitted_columns(track: Rect, margin: f64, cell: f64) -> f64 {
    let n = |a: f64, b: f64| ((b - a + 2.0 * margin) / cell).ceil().max(8.0);
    n(track.lo[0], track.hi[0]) * n(track.lo[1], track.hi[1])
}

/// The preset with its lake fitted to the throw (cell size kept), or why not: a lake too large for
/// [`MAX_WATER_COLUMNS`] at this cell size is refused, never coarsened silently.
pub fn fit_lake(p: &Preset, track: Rect) -> Result<Preset, String> {
    let columns = fitted_columns(track, FIT_MARGIN, p.water.cell);
    if columns > MAX_WATER_COLUMNS as f64 {
        return Err(format!(
            "a lake for this throw needs {:.1} million columns of {:.1} cm, more than the {:.1} \
             million allowed: use larger cells (Water ▸ Cell) or a shorter throw",
            columns / 1e6,
            p.water.cell * 100.0,
            MAX_WATER_COLUMNS as f64 / 1e6
        ));
    }
    fit_water_to_throw(p, FIT_MARGIN).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(lo: [f64; 2], hi: [f64; 2]) -> Rect {
        Rect { lo, hi }
    }

    #[test]
    fn a_track_inside_the_lake_stays() {
        let lake = rect([-2.0, -3.0], [43.0, 3.0]);
        assert_eq!(leaves_lake(rect([0.0, -0.1], [30.0, 0.1]), lake, 0.5), None);
        // Within the margin of the far edge: it may leave once the waves deflect it.
        let near = leaves_lake(rect([0.0, -0.1], [42.8, 0.1]), lake, 0.5).unwrap();
        assert!(near.contains("far"), "{near}");
        let both = leaves_lake(rect([0.0, -4.0], [50.0, 0.1]), lake, 0.5).unwrap();
        assert!(both.contains("far") && both.contains("right"), "{both}");
    }

    #[test]
    fn a_fast_or_turned_throw_leaves_the_default_lake() {
        let mut p = Preset::version_1();
        p.water.size = [20.0, 4.0];
        p.water.cell = 0.05;
        let lake = lake_rect(&p).unwrap();
        let track = flat_track(&p).unwrap();
        assert!(track.hi[0] > track.lo[0] + 1.0, "{track:?}");
        // A throw at 45° heads for the side of a 4 m wide lake.
        let mut turned = p.clone();
        let v = turned.launch.velocity[0];
        turned.launch.velocity = [v * 0.5f64.sqrt(), v * 0.5f64.sqrt(), 0.0];
        let t = flat_track(&turned).unwrap();
        assert!(t.hi[1] > lake.hi[1], "{t:?} in {lake:?}");
        let edges = leaves_lake(t, lake, WARN_MARGIN).unwrap();
        assert!(edges.contains("left"), "{edges}");
        // Fitting makes the flat-water track stay, with the margin to spare, and keeps the cell.
        let fitted = fit_lake(&turned, t).unwrap();
        assert_eq!(fitted.water.cell, turned.water.cell);
        let fitted_lake = lake_rect(&fitted).unwrap();
        assert_eq!(leaves_lake(t, fitted_lake, FIT_MARGIN - 1e-6), None);
        assert_eq!(
            leaves_lake(flat_track(&fitted).unwrap(), fitted_lake, WARN_MARGIN),
            None
        );
    }

    #[test]
    fn a_lake_too_large_for_the_cell_is_refused_not_coarsened() {
        let p = Preset::version_1();
        let long = rect([0.0, -1.0], [500.0, 1.0]);
        // 506 m × 8 m at 1 cm: 40 million columns.
        let mut fine = p.clone();
        fine.water.cell = 0.01;
        assert!(fitted_columns(long, FIT_MARGIN, 0.01) > MAX_WATER_COLUMNS as f64);
        let e = fit_lake(&fine, long).unwrap_err();
        assert!(e.contains("million columns") && e.contains("1.0 cm"), "{e}");
    }
}
