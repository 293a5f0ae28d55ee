//! The phase study's outputs: the maps and curves as CSV, the class-coloured maps and the
//! minimal-speed chart, and the Markdown report (the spin section appended).

use super::{argmin, Grid, LawResult, MapPoint, EVAL_CAP};
use crate::study::plot::{
    self, half_steps, Cell, Chart, Heatmap, Legend, Mark, Panel, RefLine, Series,
};
use crate::study::style::{colors, law_color, law_name, skip_class, skip_classes};
use crate::study::table::{md_table, sig, Csv};
use crate::study::{Ctx, StudyError};

/// Writes the CSVs, the charts and the report.
pub fn write(ctx: &Ctx, g: &Grid, results: &[LawResult]) -> Result<(), StudyError> {
    write_csvs(ctx, g, results)?;
    map_figures(ctx, g, results)?;
    curve_figure(ctx, g, results)?;
    let mut text = report(ctx, g, results);
    text.push('\n');
    text.push_str(&crate::study::spin::run(ctx)?);
    ctx.write("README.md", &text)
}

/// phase_maps.csv and min_speed.csv.
fn write_csvs(ctx: &Ctx, g: &Grid, results: &[LawResult]) -> Result<(), StudyError> {
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
    Ok(())
}

/// (tilt, value) of the tilts where a curve has a value.
fn curve(g: &Grid, v: &[Option<f64>]) -> Vec<(f64, f64)> {
    g.tilts
        .iter()
        .zip(v)
        .filter_map(|(t, u)| u.map(|u| (*t, u)))
        .collect()
}

/// phase_tilt_speed.png and phase_tilt_beta.png: the skips of every law, class-coloured.
fn map_figures(ctx: &Ctx, g: &Grid, results: &[LawResult]) -> Result<(), StudyError> {
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
                    curve(g, &r.min_speed),
                    colors::BLACK,
                    Mark::LinePoints,
                ),
                Series::new(
                    "minimal speed (2D model)",
                    curve(g, &r.min_speed_2d),
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
                curve(g, &r.beta_max),
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
    Ok(())
}

/// min_speed.png: the minimal speed and the largest impact angle per tilt, every law.
fn curve_figure(ctx: &Ctx, g: &Grid, results: &[LawResult]) -> Result<(), StudyError> {
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
        ms = ms
            .series(Series::new(
                format!("{} (3D)", law_name(r.law)),
                curve(g, &r.min_speed),
                c,
                Mark::LinePoints,
            ))
            .series(Series::new(
                format!("{} (2D model)", law_name(r.law)),
                curve(g, &r.min_speed_2d),
                c,
                Mark::Dashed,
            ));
        bm = bm.series(Series::new(
            law_name(r.law),
            curve(g, &r.beta_max),
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
    Ok(())
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
