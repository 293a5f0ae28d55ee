//! Phase study: the skipping domain of Clanet, Hersen & Bocquet (Nature 427, 29, 2004) and
//! Rosellini et al. (JFM 543, 2005) for their aluminium disc (R 2.5 cm, e 2.75 mm, 14.579 g) at
//! fixed attitude (the high-spin limit), water off: number of skips over tilt × speed (β = 20°,
//! their Fig. 1b) and tilt × impact angle (U = 3.5 m/s, Fig. 1c), under each force law; the
//! minimal speed per tilt beside the published magic angle (~20°), the measured ~2.5 m/s and the
//! 2D model's 2.3 m/s (physics.md §3, VC-8, VC-11), and the largest impact angle (~45° measured).
//!
//! Runs are independent and deterministic; they go over the cores with rayon and are collected in
//! grid order, so the results do not depend on the thread count.

use rayon::prelude::*;

use crate::sim::params::ForceLaw;
use crate::sim::params::Preset;
use crate::sim::reference::{self, MinSpeedOptions, Plate2d};
use crate::sim::scenario::{at_impact, first_contact, min_speed, IMPACT_CLEARANCE};
use crate::sim::Simulation;

use super::plot::{self, half_steps, Cell, Chart, Heatmap, Legend, Mark, Panel, RefLine, Series};
use super::style::{colors, law_color, law_name, skip_class, skip_classes};
use super::table::{md_table, sig, Csv};
use super::throws::{clanet_disc, EVAL_CAP};

use super::{check_cancel, linspace_step, Ctx, StudyError};

/// Impact angle of the tilt × speed map and of the minimal-speed curves (Clanet's Fig. 1b).
pub const BETA_DEG: f64 = 20.0;
/// Speed of the tilt × impact-angle map (Clanet's Fig. 1c).
pub const SPEED_BETA_MAP: f64 = 3.5;

/// The grids of the maps.
#[derive(Debug, Clone)]
pub struct Grid {
    pub tilts: Vec<f64>,
    pub speeds: Vec<f64>,
    pub betas: Vec<f64>,
}

pub fn grid(quick: bool) -> Grid {
    if quick {
        Grid {
            tilts: linspace_step(5.0, 45.0, 10.0),
            speeds: linspace_step(1.0, 7.0, 1.0),
            betas: linspace_step(10.0, 60.0, 10.0),
        }
    } else {
        Grid {
            tilts: linspace_step(5.0, 45.0, 2.5),
            speeds: linspace_step(0.5, 8.0, 0.25),
            betas: linspace_step(2.5, 60.0, 2.5),
        }
    }
}

/// The 2D model (reference.rs) with the same law and coefficients as the 3D defaults, ventilated
/// like the 3D solver.
pub fn plate_2d(law: ForceLaw, tilt_deg: f64) -> Plate2d {
    let (cl, cf) = law.default_coefficients();
    let l2 = match law {
        ForceLaw::Rosellini => reference::ForceLaw::Rosellini { c_l: cl, c_f: cf },
        ForceLaw::Paper => reference::ForceLaw::Newtonian { c_d: cl, c_f: cf },
        ForceLaw::Bocquet => reference::ForceLaw::bocquet(cl, cf),
    };
    Plate2d::clanet_disc(tilt_deg.to_radians())
        .with_law(l2)
        .with_ventilated(true)
}

/// Adaptive tolerance of the phase runs: the shipped 1e-6, but 1e-4 under Bocquet's law. With his
/// C_f = 1 on the light disc, tolerance 1e-6 drives Adaptive to sub-microsecond steps (up to 8e5
/// force evaluations for a 20 ms contact, see the stability study); 1e-4 gives the same skips.
pub fn tolerance(law: ForceLaw) -> f64 {
    match law {
        ForceLaw::Bocquet => 1e-4,
        _ => 1e-6,
    }
}

/// Clanet's disc under `law` at `tilt` (degrees), with the phase tolerance.
pub fn disc(law: ForceLaw, tilt: f64) -> Preset {
    let mut p = clanet_disc(law, tilt);
    p.physics.tolerance = tolerance(law);
    p
}

/// One map cell: the skips of a whole run (water off, 5 s at most).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPoint {
    pub law: ForceLaw,
    pub tilt: f64,
    pub speed: f64,
    pub beta: f64,
    pub skips: usize,
    /// Stopped at [`EVAL_CAP`] force evaluations.
    pub capped: bool,
}

/// Skips of the disc at tilt, speed and impact angle (degrees), and whether the run hit the cap.
pub fn skips(law: ForceLaw, tilt: f64, speed: f64, beta: f64) -> Result<(usize, bool), StudyError> {
    let p = at_impact(&disc(law, tilt), speed, beta.to_radians(), IMPACT_CLEARANCE)?;
    let mut sim = Simulation::new(&p)?;
    while !sim.is_finished() && sim.cost().1 < EVAL_CAP {
        sim.tick();
    }
    Ok((sim.skips(), !sim.is_finished()))
}

/// Whether the first contact skips.
pub fn first_skips(law: ForceLaw, tilt: f64, speed: f64, beta: f64) -> Result<bool, StudyError> {
    let p = at_impact(&disc(law, tilt), speed, beta.to_radians(), IMPACT_CLEARANCE)?;
    Ok(first_contact(&p)?.is_some_and(|c| c.skipped))
}

/// The tilt × speed map at β = 20°.
pub fn speed_map(law: ForceLaw, g: &Grid) -> Result<Vec<MapPoint>, StudyError> {
    let throws: Vec<(f64, f64, f64)> = g
        .tilts
        .iter()
        .flat_map(|&t| g.speeds.iter().map(move |&u| (t, u, BETA_DEG)))
        .collect();
    map_throws(law, &throws)
}

/// The tilt × impact-angle map at U = 3.5 m/s.
pub fn beta_map(law: ForceLaw, g: &Grid) -> Result<Vec<MapPoint>, StudyError> {
    let throws: Vec<(f64, f64, f64)> = g
        .tilts
        .iter()
        .flat_map(|&t| g.betas.iter().map(move |&b| (t, SPEED_BETA_MAP, b)))
        .collect();
    map_throws(law, &throws)
}

/// Skips of each (tilt, speed, β) throw, in parallel; the order of `throws` is kept.
fn map_throws(law: ForceLaw, throws: &[(f64, f64, f64)]) -> Result<Vec<MapPoint>, StudyError> {
    throws
        .par_iter()
        .map(|&(tilt, speed, beta)| {
            check_cancel()?;
            let (skips, capped) = skips(law, tilt, speed, beta)?;
            Ok(MapPoint {
                law,
                tilt,
                speed,
                beta,
                skips,
                capped,
            })
        })
        .collect()
}

/// Minimal speed (first contact skips) per tilt at β = 20°, by bisection to `rel_tol`.
pub fn min_speed_curve(
    law: ForceLaw,
    tilts: &[f64],
    rel_tol: f64,
) -> Result<Vec<Option<f64>>, StudyError> {
    tilts
        .par_iter()
        .map(|&t| {
            check_cancel()?;
            Ok(min_speed(
                &disc(law, t),
                BETA_DEG.to_radians(),
                0.3,
                20.0,
                rel_tol,
            )?)
        })
        .collect()
}

/// The 2D model's minimal speed per tilt at β = 20°.
pub fn min_speed_curve_2d(law: ForceLaw, tilts: &[f64]) -> Result<Vec<Option<f64>>, StudyError> {
    let opts = MinSpeedOptions {
        rel_tol: 1e-4,
        u_max: 50.0,
        ..MinSpeedOptions::default()
    };
    tilts
        .par_iter()
        .map(|&t| {
            Ok(reference::min_speed(
                &plate_2d(law, t),
                BETA_DEG.to_radians(),
                &opts,
            )?)
        })
        .collect()
}

/// The largest impact angle (degrees) whose first contact skips at `speed`, by bisection between
/// a skipping `lo` and a failing `hi`, to `tol` degrees.
pub fn max_beta(
    law: ForceLaw,
    tilt: f64,
    speed: f64,
    lo: f64,
    hi: f64,
    tol: f64,
) -> Result<f64, StudyError> {
    let (mut a, mut b) = (lo, hi);
    while b - a > tol {
        let m = 0.5 * (a + b);
        if first_skips(law, tilt, speed, m)? {
            a = m;
        } else {
            b = m;
        }
    }
    Ok(0.5 * (a + b))
}

/// β_max per tilt at U = 3.5 m/s: bracketed by the map (largest skipping β, next β), refined.
pub fn max_beta_curve(
    law: ForceLaw,
    g: &Grid,
    map: &[MapPoint],
    tol: f64,
) -> Result<Vec<Option<f64>>, StudyError> {
    g.tilts
        .par_iter()
        .map(|&t| {
            check_cancel()?;
            let own: Vec<&MapPoint> = map.iter().filter(|m| m.law == law && m.tilt == t).collect();
            let Some(last) = own
                .iter()
                .filter(|m| m.skips > 0)
                .map(|m| m.beta)
                .reduce(f64::max)
            else {
                return Ok(None);
            };
            let next = g.betas.iter().copied().find(|&b| b > last).unwrap_or(80.0);
            if !first_skips(law, t, SPEED_BETA_MAP, last)? {
                return Ok(Some(last));
            }
            Ok(Some(max_beta(law, t, SPEED_BETA_MAP, last, next, tol)?))
        })
        .collect()
}

/// The lowest point of a curve: (tilt, value).
pub fn argmin(tilts: &[f64], v: &[Option<f64>]) -> Option<(f64, f64)> {
    tilts
        .iter()
        .zip(v)
        .filter_map(|(t, u)| u.map(|u| (*t, u)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Everything per law.
#[derive(Debug, Clone)]
pub struct LawResult {
    pub law: ForceLaw,
    pub speed_map: Vec<MapPoint>,
    pub beta_map: Vec<MapPoint>,
    pub min_speed: Vec<Option<f64>>,
    pub min_speed_2d: Vec<Option<f64>>,
    pub beta_max: Vec<Option<f64>>,
}

pub fn run(ctx: &Ctx) -> Result<(), StudyError> {
    let g = grid(ctx.quick);
    let rel_tol = if ctx.quick { 1e-2 } else { 2e-3 };
    let mut results = Vec::new();
    for law in ForceLaw::ALL {
        ctx.progress(&format!(
            "{}: tilt × speed map ({} runs)",
            law_name(law),
            g.tilts.len() * g.speeds.len()
        ));
        let sm = speed_map(law, &g)?;
        ctx.progress(&format!("{}: tilt × impact-angle map", law_name(law)));
        let bm = beta_map(law, &g)?;
        ctx.progress(&format!(
            "{}: minimal speed and largest impact angle per tilt",
            law_name(law)
        ));
        let ms = min_speed_curve(law, &g.tilts, rel_tol)?;
        let ms2 = min_speed_curve_2d(law, &g.tilts)?;
        let bmax = max_beta_curve(law, &g, &bm, if ctx.quick { 1.0 } else { 0.25 })?;
        results.push(LawResult {
            law,
            speed_map: sm,
            beta_map: bm,
            min_speed: ms,
            min_speed_2d: ms2,
            beta_max: bmax,
        });
    }
    write(ctx, &g, &results)
}

fn write(ctx: &Ctx, g: &Grid, results: &[LawResult]) -> Result<(), StudyError> {
    let mut csv = Csv::new(&[
        "law",
        "map",
        "tilt_deg",
        "speed_m_s",
        "beta_deg",
        "skips",
        "capped",
    ]);
    for r in results {
        for (m, map) in [("tilt_speed", &r.speed_map), ("tilt_beta", &r.beta_map)] {
            for p in map.iter() {
                csv.push(vec![
                    law_name(r.law).into(),
                    m.into(),
                    p.tilt.into(),
                    p.speed.into(),
                    p.beta.into(),
                    p.skips.into(),
                    p.capped.into(),
                ]);
            }
        }
    }
    ctx.write_csv("phase_maps.csv", &csv)?;
    let mut ccsv = Csv::new(&[
        "law",
        "tilt_deg",
        "min_speed_3d_m_s",
        "min_speed_2d_m_s",
        "beta_max_deg_at_3_5_m_s",
    ]);
    for r in results {
        for (k, t) in g.tilts.iter().enumerate() {
            let f = |v: &[Option<f64>]| v.get(k).copied().flatten().unwrap_or(f64::NAN);
            ccsv.push(vec![
                law_name(r.law).into(),
                (*t).into(),
                f(&r.min_speed).into(),
                f(&r.min_speed_2d).into(),
                f(&r.beta_max).into(),
            ]);
        }
    }
    ctx.write_csv("min_speed.csv", &ccsv)?;

    let tilt_edges = half_steps(&g.tilts);
    let speed_edges = half_steps(&g.speeds);
    let beta_edges = half_steps(&g.betas);
    let xr = (
        tilt_edges.first().map_or(0.0, |e| e.0),
        tilt_edges.last().map_or(50.0, |e| e.1),
    );
    let mut speed_panels = Vec::new();
    let mut beta_panels = Vec::new();
    for r in results {
        let cells = |map: &[MapPoint],
                     ys: &[f64],
                     edges: &[(f64, f64)],
                     y_of: &dyn Fn(&MapPoint) -> f64|
         -> Vec<Cell> {
            map.iter()
                .filter_map(|p| {
                    let i = g.tilts.iter().position(|t| *t == p.tilt)?;
                    let j = ys.iter().position(|y| *y == y_of(p))?;
                    Some(Cell {
                        x0: tilt_edges[i].0,
                        x1: tilt_edges[i].1,
                        y0: edges[j].0,
                        y1: edges[j].1,
                        class: skip_class(p.skips),
                    })
                })
                .collect()
        };
        let curve = |v: &[Option<f64>]| -> Vec<(f64, f64)> {
            g.tilts
                .iter()
                .zip(v)
                .filter_map(|(t, u)| u.map(|u| (*t, u)))
                .collect()
        };
        speed_panels.push(Panel::Heat(Heatmap {
            title: format!("{} law: skips at β = 20°", law_name(r.law)),
            x_label: "tilt (attack angle) α (°)".into(),
            y_label: "impact speed U (m/s)".into(),
            x_range: xr,
            y_range: (
                speed_edges.first().map_or(0.0, |e| e.0),
                speed_edges.last().map_or(8.0, |e| e.1),
            ),
            cells: cells(&r.speed_map, &g.speeds, &speed_edges, &|p| p.speed),
            classes: skip_classes(),
            overlays: vec![
                Series::new(
                    "minimal speed (3D)",
                    curve(&r.min_speed),
                    colors::BLACK,
                    Mark::LinePoints,
                ),
                Series::new(
                    "minimal speed (2D model)",
                    curve(&r.min_speed_2d),
                    colors::PURPLE,
                    Mark::Dashed,
                ),
                Series::new(
                    "measured: 2.5 m/s at 20°",
                    vec![(20.0, 2.5)],
                    colors::ORANGE,
                    Mark::Points,
                ),
            ],
            lines: vec![],
            legend: Legend::UpperRight,
        }));
        beta_panels.push(Panel::Heat(Heatmap {
            title: format!("{} law: skips at U = 3.5 m/s", law_name(r.law)),
            x_label: "tilt (attack angle) α (°)".into(),
            y_label: "impact angle β (°)".into(),
            x_range: xr,
            y_range: (
                beta_edges.first().map_or(0.0, |e| e.0),
                beta_edges.last().map_or(60.0, |e| e.1),
            ),
            cells: cells(&r.beta_map, &g.betas, &beta_edges, &|p| p.beta),
            classes: skip_classes(),
            overlays: vec![Series::new(
                "largest β that skips",
                curve(&r.beta_max),
                colors::BLACK,
                Mark::LinePoints,
            )],
            lines: vec![RefLine::h("measured limit ≈ 45°", 45.0, colors::ORANGE)],
            legend: Legend::UpperRight,
        }));
    }
    plot::draw(
        &ctx.path("phase_tilt_speed.png"),
        (2100, 760),
        3,
        Some("Skipping domain of Clanet's disc (R 2.5 cm, 2.75 mm, 14.6 g), tilt × speed, β = 20°"),
        &speed_panels,
    )?;
    plot::draw(
        &ctx.path("phase_tilt_beta.png"),
        (2100, 760),
        3,
        Some("Skipping domain of Clanet's disc, tilt × impact angle, U = 3.5 m/s"),
        &beta_panels,
    )?;

    // Minimal speed and largest β curves.
    let mut ms = Chart::new(
        "minimal speed at β = 20° (first contact skips)",
        "tilt (attack angle) α (°)",
        "minimal impact speed (m/s)",
    )
    .y_range(0.0, 12.0)
    .legend(Legend::UpperRight)
    .line(RefLine::v(
        "magic angle ≈ 20° (measured)",
        20.0,
        colors::GREY,
    ))
    .line(RefLine::h("measured ≈ 2.5 m/s", 2.5, colors::ORANGE));
    let mut bm = Chart::new(
        "largest impact angle that skips at U = 3.5 m/s",
        "tilt (attack angle) α (°)",
        "β_max (°)",
    )
    .y_range(0.0, 70.0)
    .legend(Legend::LowerRight)
    .line(RefLine::h("measured ≈ 45°", 45.0, colors::ORANGE));
    for r in results {
        let c = law_color(r.law);
        let curve = |v: &[Option<f64>]| -> Vec<(f64, f64)> {
            g.tilts
                .iter()
                .zip(v)
                .filter_map(|(t, u)| u.map(|u| (*t, u)))
                .collect()
        };
        ms = ms
            .series(Series::new(
                format!("{} (3D)", law_name(r.law)),
                curve(&r.min_speed),
                c,
                Mark::LinePoints,
            ))
            .series(Series::new(
                format!("{} (2D model)", law_name(r.law)),
                curve(&r.min_speed_2d),
                c,
                Mark::Dashed,
            ));
        bm = bm.series(Series::new(
            law_name(r.law),
            curve(&r.beta_max),
            c,
            Mark::LinePoints,
        ));
    }
    ms = ms
        .series(Series::new(
            "VC-8 published 2D (Rosellini)",
            vec![
                (10.0, 2.42),
                (15.0, 2.26),
                (20.0, 2.27),
                (25.0, 2.37),
                (30.0, 2.54),
                (40.0, 3.09),
            ],
            colors::SKY,
            Mark::Points,
        ))
        .series(Series::new(
            "VC-11 published 2D (|V_n|², C_D 1.4)",
            vec![
                (15.0, 3.52),
                (20.0, 3.22),
                (25.0, 3.11),
                (30.0, 3.13),
                (40.0, 3.47),
            ],
            colors::PURPLE,
            Mark::Points,
        ));
    plot::draw(
        &ctx.path("min_speed.png"),
        (1600, 700),
        2,
        Some("Magic angle: Clanet's disc under each force law (locked attitude)"),
        &[Panel::Chart(ms), Panel::Chart(bm)],
    )?;

    let mut text = report(ctx, g, results);
    text.push('\n');
    text.push_str(&super::spin::run(ctx)?);
    ctx.write("README.md", &text)
}

fn report(ctx: &Ctx, g: &Grid, results: &[LawResult]) -> String {
    let mut s = String::from("# Phase study: the skipping domain and the magic angle\n\n");
    s.push_str(&format!(
        "Generated by `stoneskip study phase{}` in {:.0} s. Clanet's aluminium disc (R 2.5 cm, e 2.75 mm, 14.579 g, 48 rim segments), locked attitude (the high-spin limit), water off, each force law with its default coefficients (Rosellini C_l 0.5, C_f 0.005; Paper C_l 1.4, C_f 0.005; Bocquet C_l 1, C_f 1), Adaptive integrator at tolerance 1e-6 (1e-4 under Bocquet's law: with C_f = 1 on this 14.6 g disc, 1e-6 drives the step controller to sub-microsecond steps — up to 8e5 force evaluations for a 20 ms contact — for the same skips). Throws at impact; a cell counts the skips of the whole run. Tilt {}–{}°, speed {}–{} m/s, impact angle {}–{}°.\n\n",
        if ctx.quick { " --quick" } else { "" },
        ctx.elapsed(),
        g.tilts.first().copied().unwrap_or(0.0),
        g.tilts.last().copied().unwrap_or(0.0),
        g.speeds.first().copied().unwrap_or(0.0),
        g.speeds.last().copied().unwrap_or(0.0),
        g.betas.first().copied().unwrap_or(0.0),
        g.betas.last().copied().unwrap_or(0.0),
    ));
    let capped: usize = results
        .iter()
        .map(|r| {
            r.speed_map
                .iter()
                .chain(&r.beta_map)
                .filter(|p| p.capped)
                .count()
        })
        .sum();
    s.push_str(&format!(
        "Runs stopped at the cap of {EVAL_CAP} force evaluations (their skips so far are counted): {capped}.\n\n"
    ));
    s.push_str("Published: magic angle ≈ 20°, minimal speed ≈ 2.5 m/s measured (Clanet et al. 2004) and 2.3 m/s in the 2D model with Rosellini's law (physics.md VC-8: 2.42, 2.26, 2.27, 2.37, 2.54 m/s at 10–30°); no bounce above an impact angle of ≈ 45°. The 2D model (reference.rs) here uses the same law and coefficients as the 3D runs.\n\n");
    let mut rows = Vec::new();
    for r in results {
        let m3 = argmin(&g.tilts, &r.min_speed);
        let m2 = argmin(&g.tilts, &r.min_speed_2d);
        let at20 = g
            .tilts
            .iter()
            .position(|t| (*t - 20.0).abs() < 1e-9)
            .and_then(|k| r.min_speed.get(k).copied().flatten());
        let bmax = r
            .beta_max
            .iter()
            .zip(&g.tilts)
            .filter_map(|(b, t)| b.map(|b| (*t, b)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        rows.push(vec![
            law_name(r.law).to_string(),
            m3.map_or("–".into(), |(t, u)| format!("{t}° ({} m/s)", sig(u, 3))),
            at20.map_or("–".into(), |u| format!("{} m/s", sig(u, 3))),
            m2.map_or("–".into(), |(t, u)| format!("{t}° ({} m/s)", sig(u, 3))),
            bmax.map_or("–".into(), |(t, b)| format!("{}° at α = {t}°", sig(b, 3))),
        ]);
    }
    s.push_str(&md_table(
        &[
            "law",
            "magic angle, 3D (lowest minimal speed)",
            "minimal speed at 20°",
            "magic angle, 2D model",
            "largest β that skips (U 3.5 m/s)",
        ],
        &rows,
    ));
    s.push_str("\n![min speed](min_speed.png)\n\n![phase tilt speed](phase_tilt_speed.png)\n\n![phase tilt beta](phase_tilt_beta.png)\n\n");
    s.push_str("## Minimal speed per tilt (m/s, β = 20°)\n\n");
    let mut hdr: Vec<String> = vec!["tilt (°)".into()];
    for r in results {
        hdr.push(format!("{} 3D", law_name(r.law)));
        hdr.push(format!("{} 2D", law_name(r.law)));
    }
    let hdr_ref: Vec<&str> = hdr.iter().map(String::as_str).collect();
    let mut rows = Vec::new();
    for (k, t) in g.tilts.iter().enumerate() {
        let mut row = vec![format!("{t}")];
        for r in results {
            let f = |v: &[Option<f64>]| {
                v.get(k)
                    .copied()
                    .flatten()
                    .map_or("–".into(), |u| sig(u, 3))
            };
            row.push(f(&r.min_speed));
            row.push(f(&r.min_speed_2d));
        }
        rows.push(row);
    }
    s.push_str(&md_table(&hdr_ref, &rows));
    s.push_str("\n`–`: no skip up to 20 m/s (3D) or 50 m/s (2D).\n");
    s
}
