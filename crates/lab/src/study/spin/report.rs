//! The spin study's outputs: the spin × tilt map and the spin-limited count as CSV and charts, and
//! the Markdown section the phase report appends.

use super::{
    fit_exponent, spin_limited, CountPoint, SpinGrid, SpinPoint, SpinResult, CENTRE_KEY,
    CENTRE_NAME, MAP_BETA_DEG, MAP_SPEED, REV, TYPICAL_RADIUS,
};
use crate::study::plot::{
    self, half_steps, Cell, Chart, Heatmap, Legend, Mark, Panel, RefLine, Series,
};
use crate::study::style::{colors, skip_class, skip_classes};
use crate::study::table::{md_table, sig, Csv};
use crate::study::{Ctx, StudyError};

/// Writes the CSVs and charts; returns the Markdown section.
pub fn write(ctx: &Ctx, g: &SpinGrid, results: &[SpinResult]) -> Result<String, StudyError> {
    write_csvs(ctx, results)?;
    map_figure(ctx, g, results)?;
    count_figure(ctx, g, results)?;
    Ok(report(g, results))
}

/// First spin of the map (per tilt) whose first contact skips.
fn map_threshold(g: &SpinGrid, map: &[SpinPoint], tilt: f64) -> Option<f64> {
    g.spins.iter().copied().find(|&s| {
        map.iter()
            .any(|p| p.tilt == tilt && p.rev_s == s && p.first_skip)
    })
}

/// spin_map.csv and spin_counts.csv.
fn write_csvs(ctx: &Ctx, results: &[SpinResult]) -> Result<(), StudyError> {
    let mut csv = Csv::new(&[
        "centre",
        "tilt_deg",
        "spin_rev_s",
        "skips",
        "first_skip",
        "first_contact_s",
        "inclination_change_deg",
        "axis_turn_deg",
        "capped",
    ]);
    for r in results {
        for p in &r.map {
            csv.push(vec![
                CENTRE_KEY.into(),
                p.tilt.into(),
                p.rev_s.into(),
                p.skips.into(),
                p.first_skip.into(),
                p.first_duration.into(),
                p.inclination_change.into(),
                p.axis_turn.into(),
                p.capped.into(),
            ]);
        }
    }
    ctx.write_csv("spin_map.csv", &csv)?;
    let mut ccsv = Csv::new(&[
        "centre",
        "spin_rev_s",
        "skips",
        "rebounds",
        "distance_m",
        "lateral_m",
    ]);
    for r in results {
        for p in &r.counts {
            ccsv.push(vec![
                CENTRE_KEY.into(),
                p.rev_s.map_or("locked".into(), |s| sig(s, 4)).into(),
                p.skips.into(),
                p.rebounds.into(),
                p.distance.into(),
                p.lateral.into(),
            ]);
        }
    }
    ctx.write_csv("spin_counts.csv", &ccsv)?;
    Ok(())
}

/// spin_tilt.png: the skips over spin × tilt per pressure centre, with the threshold curves.
fn map_figure(ctx: &Ctx, g: &SpinGrid, results: &[SpinResult]) -> Result<(), StudyError> {
    let tilt_edges = half_steps(&g.tilts);
    let spin_edges = half_steps(&g.spins);
    let mut panels = Vec::new();
    for r in results {
        let cells: Vec<Cell> = r
            .map
            .iter()
            .filter_map(|p| {
                let i = g.tilts.iter().position(|t| *t == p.tilt)?;
                let j = g.spins.iter().position(|s| *s == p.rev_s)?;
                Some(Cell {
                    x0: tilt_edges[i].0,
                    x1: tilt_edges[i].1,
                    y0: spin_edges[j].0,
                    y1: spin_edges[j].1,
                    class: skip_class(p.skips),
                })
            })
            .collect();
        let threshold: Vec<(f64, f64)> = g
            .tilts
            .iter()
            .filter_map(|&t| map_threshold(g, &r.map, t).map(|s| (t, s)))
            .collect();
        // One revolution per contact: Ω = 1/τ with τ the first contact's duration at that tilt
        // and the threshold spin.
        let one_rev: Vec<(f64, f64)> = g
            .tilts
            .iter()
            .filter_map(|&t| {
                let s = map_threshold(g, &r.map, t)?;
                let p = r.map.iter().find(|p| p.tilt == t && p.rev_s == s)?;
                (p.first_duration > 0.0).then(|| (t, 1.0 / p.first_duration))
            })
            .collect();
        panels.push(Panel::Heat(Heatmap {
            title: format!("pressure at {}", CENTRE_NAME),
            x_label: "tilt (attack angle) α (°)".into(),
            y_label: "spin Ω (rev/s)".into(),
            x_range: (
                tilt_edges.first().map_or(0.0, |e| e.0),
                tilt_edges.last().map_or(50.0, |e| e.1),
            ),
            y_range: (
                spin_edges.first().map_or(0.0, |e| e.0),
                spin_edges.last().map_or(100.0, |e| e.1),
            ),
            cells,
            classes: skip_classes(),
            overlays: vec![
                Series::new(
                    "spin threshold (first contact skips)",
                    threshold,
                    colors::BLACK,
                    Mark::LinePoints,
                ),
                Series::new(
                    "one revolution per contact (Ωτ = 1)",
                    one_rev,
                    colors::ORANGE,
                    Mark::Dashed,
                ),
            ],
            lines: vec![],
            legend: Legend::UpperRight,
        }));
    }
    plot::draw(
        &ctx.path("spin_tilt.png"),
        (1800, 760),
        2,
        Some("Skips of Clanet's disc over spin × tilt (U 3.5 m/s, β 20°, free rotation)"),
        &panels,
    )
}

/// spin_count.png: skips and rebounds of the typical stone against spin.
fn count_figure(ctx: &Ctx, g: &SpinGrid, results: &[SpinResult]) -> Result<(), StudyError> {
    let mut chart = Chart::new(
        "typical stone (R 5 cm, 150 g, 12 m/s, α 15°): skips against spin",
        "spin Ω (rev/s)",
        "skips",
    )
    .log_x()
    .log_y()
    .x_range(1.5, 200.0)
    .y_range(0.5, 100.0)
    .legend(Legend::UpperLeft);
    let spins = &g.curve_spins;
    for (r, c) in results.iter().zip([colors::BLUE, colors::RED]) {
        chart = chart.series(Series::new(
            format!("skips, free rotation, {}", CENTRE_NAME),
            log_curve(&r.counts, |p| p.skips as f64),
            c,
            Mark::LinePoints,
        ));
        chart = chart.series(Series::new(
            format!("rebounds, {}", CENTRE_KEY),
            log_curve(&r.counts, |p| p.rebounds as f64),
            c,
            Mark::Dashed,
        ));
        if let Some(l) = r.counts.iter().find(|p| p.rev_s.is_none()) {
            chart = chart.line(RefLine::h(
                format!("locked attitude, {}: {}", CENTRE_KEY, l.skips),
                l.skips as f64,
                c,
            ));
        }
    }
    let g_acc = 9.81;
    let bocquet: Vec<(f64, f64)> = spins
        .iter()
        .map(|&s| (s, TYPICAL_RADIUS * (s * REV).powi(2) / g_acc))
        .filter(|p| p.1 >= 0.5 && p.1 <= 100.0)
        .collect();
    chart = chart.series(Series::new(
        "Bocquet (reported): N = Rω²/g",
        bocquet,
        colors::GREY,
        Mark::Dashed,
    ));
    plot::draw(
        &ctx.path("spin_count.png"),
        (1100, 700),
        1,
        None,
        &[Panel::Chart(chart)],
    )
}

/// (spin, value) of the free-rotation runs whose value can stand on a log axis (> 0).
fn log_curve(counts: &[CountPoint], value: impl Fn(&CountPoint) -> f64) -> Vec<(f64, f64)> {
    counts
        .iter()
        .filter_map(|p| Some((p.rev_s?, value(p))))
        .filter(|p| p.1 > 0.0)
        .collect()
}

/// Steps between neighbouring free-rotation spins where more spin gave less of `value`.
fn drops(counts: &[CountPoint], value: impl Fn(&CountPoint) -> f64) -> usize {
    counts
        .windows(2)
        .filter(|w| w[0].rev_s.is_some() && w[1].rev_s.is_some())
        .filter(|w| value(&w[1]) < value(&w[0]))
        .count()
}

fn report(g: &SpinGrid, results: &[SpinResult]) -> String {
    let mut s = String::from("## Spin axis: the stone as a free rigid body\n\n");
    s.push_str(&format!(
        "`rotation: Free`, Rosellini law. Map: Clanet's disc at U {MAP_SPEED} m/s, β {MAP_BETA_DEG}°, tilt {}–{}°, spin {}–{} rev/s; a cell counts the skips of the whole run. The pressure acts at each wetted face's centroid (the paper's eqs. 25–26); Savitsky's planing centre, compared here until issue 40, is retired, and its rows are in docs/studies/retired.md. Published (VC-12, VC-13): without spin the disc pitches nose-down and dives; about one revolution per contact is enough to skip; at 65 rev/s, α = β = 20°, α stays nearly constant through the contact.\n\n",
        g.tilts.first().copied().unwrap_or(0.0),
        g.tilts.last().copied().unwrap_or(0.0),
        g.spins.first().copied().unwrap_or(0.0),
        g.spins.last().copied().unwrap_or(0.0),
    ));
    let mut rows = Vec::new();
    for r in results {
        let thr = r
            .threshold
            .map_or("none up to 100 rev/s".into(), |(w, tau)| {
                format!(
                    "{} rev/s; contact {} ms: {} rev per contact",
                    sig(w, 3),
                    sig(tau * 1e3, 3),
                    sig(w * tau, 2)
                )
            });
        let v = &r.vc12;
        let v0 = &r.vc12_no_spin;
        rows.push(vec![
            CENTRE_NAME.to_string(),
            thr,
            format!(
                "{}: inclination {:+.1}°, axis turn {:.1}°",
                if v.first_skip { "skips" } else { "no skip" },
                v.inclination_change,
                v.axis_turn
            ),
            format!(
                "{}: inclination {:+.1}°",
                if v0.first_skip { "skips" } else { "dives" },
                v0.inclination_change
            ),
        ]);
    }
    s.push_str(&md_table(
        &[
            "pressure centre",
            "spin threshold at α = 35° (VC-13)",
            "VC-12: 65 rev/s, α = β = 20°, first contact",
            "same without spin",
        ],
        &rows,
    ));
    s.push_str("\nThe inclination is the angle between the stone's plane and the water (Clanet's α seen from the side); the axis turn is the whole change of the axis direction. At 65 rev/s almost all of the turn is a change of azimuth — gyroscopic precession of the nose-down torque into bank — while the inclination barely moves; without spin the same torque pitches the stone nose-down.\n\n![spin tilt](spin_tilt.png)\n\n");
    s.push_str("### Spin-limited count\n\n");
    let mut rows = Vec::new();
    for r in results {
        let locked = r
            .counts
            .iter()
            .find(|p| p.rev_s.is_none())
            .map_or(0, |p| p.rebounds);
        let (lim, alone) = spin_limited(&r.counts);
        let p = fit_exponent(&lim);
        let p_alone = fit_exponent(&alone);
        let range = match (lim.first(), lim.last()) {
            (Some(a), Some(b)) => format!("{}–{} rev/s", sig(a.0, 3), sig(b.0, 3)),
            _ => "–".into(),
        };
        let mono = drops(&r.counts, |p| p.skips as f64);
        let mono_r = drops(&r.counts, |p| p.rebounds as f64);
        let mono_d = drops(&r.counts, |p| p.distance);
        rows.push(vec![
            CENTRE_NAME.to_string(),
            locked.to_string(),
            range,
            p.map_or("–".into(), |p| sig(p, 2)),
            p_alone.map_or("–".into(), |p| sig(p, 2)),
            format!("{mono} (rebounds: {mono_r}; distance: {mono_d})"),
        ]);
    }
    s.push_str(&md_table(
        &[
            "pressure centre",
            "locked (the high-spin limit): rebounds",
            "spin-limited range (2 ≤ N ≤ N_L/2)",
            "fitted p in N ∝ Ω^p",
            "p of the spin limit alone, N_spin = N·N_L/(N_L − N)",
            "steps where more spin gave fewer skips",
        ],
        &rows,
    ));
    s.push_str("\nBocquet reports N_spin ∝ ω² (N ≈ Rω²/g fits the press figures of 5, 15 and 38 skips at 5, 9 and 14 rev/s). This rigid-body model does not give it: the angular impulse of each contact turns the axis by about J/(I₃ω), in the same sense every time (the lift always acts behind the centre of mass), so the attitude drifts coherently and the spin limit grows about linearly with the spin (the raw count less, since the slowing stone uses up its speed limit at the same time). An ω² law needs the per-contact kicks to add like a random walk (√N growth of the drift), for which the model has no source. The model's stone is also much less stable than the reported throws: at 14 rev/s it makes one or two skips where the press reports 38.\n\nRebounds are contacts the stone leaves rising; a skip also counts a graze, where a wobbling stone rocks off the surface while still sinking. With the pressure at the faces, more spin never gave fewer rebounds or a shorter run. With the planing centre the count rises to a peak at 20–30 rev/s and falls again before it grows: the centre ahead of the centre of mass on a deeply wetted, nearly flat stone makes a nose-up moment that rights it, and at low spin the stone rocks back up between hops (the \"trout\" regime of VC-13), which stiffer gyroscopes suppress.\n\n![spin count](spin_count.png)\n");
    s
}
