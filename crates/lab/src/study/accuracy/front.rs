//! Real time against error on the shipped default throw, stone only (issue 12), and on a faster,
//! flatter one (issue 41): the throw of `assets/presets/default.ron` with the water off — free
//! rotation, the smooth Résal spin, Archimedes on the wetted faces, the air in flight — run at
//! every mesh × tolerance × step setting of [`front_settings`], each timed alone (one run at a
//! time, so no other shares the core; the best of [`repeats`] rounds over all the settings),
//! against a fine mesh at a tight tolerance. The cost axis is real time (simulated seconds per wall second), the one the issue's
//! 300× goal is stated in; the force evaluations are the noise-free companion. Work-precision
//! charts after Hairer, Nørsett & Wanner, *Solving ODEs I* §II.10.

use stoneskip_physics::sim::params::{Preset, Quadrature};

use super::{
    discretisation_name, errors, is_discretisation, measure, triangles, Discretisation, Errors,
    RunStats, FLOOR,
};
use crate::study::plot::{self, Chart, Legend, Mark, Panel, RefLine, Series};
use crate::study::style::{colors, Rgb};
use crate::study::table::{md_table, pct, sig, Csv};
use crate::study::{check_cancel, Ctx, StudyError};

/// The real-time goal for this throw (issue 12).
pub const GOAL: f64 = 300.0;

/// One setting of the sweep and its run.
#[derive(Debug, Clone)]
pub struct FrontPoint {
    pub segments: u32,
    pub bands: u32,
    /// The mesh's triangles; 0 for the smooth quadrature, which does not sum over them.
    pub triangles: usize,
    /// `stone.quadrature: Smooth` (meridian × around nodes): the forces on the smooth lens, the
    /// mesh above only drawing it and testing its sinking.
    pub smooth: Option<(u32, u32)>,
    pub tolerance: f64,
    /// `physics.steps_across_ticks`.
    pub across: bool,
    /// The run; its `wall` is the best of the repeats.
    pub stats: RunStats,
    pub err: Errors,
}

impl FrontPoint {
    pub fn discretisation(&self) -> Discretisation {
        ((self.segments, self.bands), self.smooth)
    }

    /// Simulated seconds per wall-clock second.
    pub fn real_time(&self) -> f64 {
        self.stats.final_time / self.stats.wall.max(1e-9)
    }

    /// Within 1 % of the reference in distance, with its skips.
    pub fn within_one_percent(&self) -> bool {
        self.judged() < 0.01
    }

    /// The error a setting is judged by: distance, or 1 (100 %) when a skip is wrong.
    pub fn judged(&self) -> f64 {
        if self.err.skips != 0 {
            1.0
        } else {
            self.err.distance
        }
    }

    /// The judged error in words: the distance error, or the skips it gets wrong.
    fn error_text(&self) -> String {
        if self.err.skips != 0 {
            format!("{:+} skips", self.err.skips)
        } else {
            pct(self.err.distance, 2)
        }
    }
}

/// A throw the front is measured on.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontThrow {
    /// Its name in the report's headings.
    pub title: &'static str,
    /// The file stem of its CSV and chart.
    pub stem: &'static str,
    /// How it differs from the shipped default, in the report.
    pub launch: &'static str,
    /// Its preset, water off.
    pub preset: Preset,
}

/// The throws of the front: the shipped default, and the same stone thrown faster and flatter
/// (15 m/s released from 15 cm, so it meets the water at a shallower angle; issue 41 asks for
/// both).
pub fn front_throws() -> Vec<FrontThrow> {
    let mut base = Preset::default();
    base.water.enabled = false;
    let mut fast = base.clone();
    fast.launch.velocity[0] = 15.0;
    fast.launch.position[2] = 0.15;
    vec![
        FrontThrow {
            title: "The shipped default",
            stem: "front",
            launch: "`assets/presets/default.ron` (12 m/s, released level from 30 cm)",
            preset: base,
        },
        FrontThrow {
            title: "A faster, flatter throw",
            stem: "front_fast",
            launch: "`assets/presets/default.ron` thrown at 15 m/s, released level from 15 cm",
            preset: fast,
        },
    ]
}

/// The sweep: the reference run and every setting.
#[derive(Debug, Clone)]
pub struct Front {
    /// The throw swept.
    pub throw: FrontThrow,
    pub reference: RunStats,
    pub points: Vec<FrontPoint>,
    /// The shipped throw's own mesh and tolerance (its steps tick-bound).
    pub shipped: (u32, u32, f64),
    /// The shipped throw's smooth quadrature nodes, if it integrates over its ellipsoid.
    pub shipped_smooth: Option<(u32, u32)>,
}

/// What the sweep runs.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontSettings {
    /// (segments, bands).
    pub meshes: Vec<(u32, u32)>,
    /// The smooth quadrature's (meridian, around) nodes, on the shipped mesh.
    pub smooth: Vec<(u32, u32)>,
    pub tolerances: Vec<f64>,
    /// The reference's segments, bands and tolerance (tick-bound steps).
    pub reference: (u32, u32, f64),
}

/// The meshes and tolerances swept, and the reference's mesh and tolerance.
pub fn front_settings(quick: bool) -> FrontSettings {
    if quick {
        FrontSettings {
            meshes: vec![(16, 8)],
            smooth: vec![(8, 2)],
            tolerances: vec![1e-6, 1e-4],
            reference: (24, 12, 1e-7),
        }
    } else {
        FrontSettings {
            meshes: vec![(32, 16), (32, 32), (48, 24), (48, 32), (64, 32), (96, 48)],
            smooth: vec![(8, 2), (10, 2), (12, 2), (16, 2), (12, 6)],
            tolerances: vec![1e-6, 1e-5, 3e-5, 1e-4, 1e-3],
            reference: (192, 96, 1e-8),
        }
    }
}

/// Wall-clock runs per setting; the best is kept (the others confirm the same result, so the
/// quick run in CI checks that too).
pub fn repeats(quick: bool) -> usize {
    if quick {
        2
    } else {
        5
    }
}

/// The shipped default throw with the water off, at a mesh (or the smooth quadrature's nodes on
/// it), tolerance and step rule.
fn setting(
    base: &Preset,
    (segments, bands): (u32, u32),
    smooth: Option<(u32, u32)>,
    tolerance: f64,
    across: bool,
) -> Preset {
    let mut p = base.clone();
    p.stone.segments = segments;
    p.stone.bands = Some(bands);
    p.stone.quadrature = match smooth {
        Some((meridian, around)) => Quadrature::Smooth { meridian, around },
        None => Quadrature::Faces,
    };
    p.physics.tolerance = tolerance;
    p.physics.steps_across_ticks = across;
    p
}

/// Keeps the faster of two runs of the same setting; an error if they differ otherwise (they must
/// not: the same preset gives the same bits).
fn keep_faster(best: &mut RunStats, again: RunStats) -> Result<(), StudyError> {
    if again.distance.to_bits() != best.distance.to_bits() || again.force_evals != best.force_evals
    {
        return Err(StudyError::Failed(format!(
            "real time against error: two runs of the same setting differ ({} and {} m)",
            best.distance, again.distance
        )));
    }
    if again.wall < best.wall {
        *best = again;
    }
    Ok(())
}

/// Runs the reference and every setting, one at a time (so each has the core to itself), in
/// [`repeats`] rounds over all the settings, so that a slow spell of the machine spreads over
/// many settings instead of one setting's every run.
pub fn front_sweep(ctx: &Ctx, throw: FrontThrow) -> Result<Front, StudyError> {
    let base = throw.preset.clone();
    let shipped = (
        base.stone.segments,
        stoneskip_physics::sim::stone::lens_bands(base.stone.segments, base.stone.bands),
        base.physics.tolerance,
    );
    let FrontSettings {
        meshes,
        smooth,
        tolerances,
        reference: (rs, rb, rt),
    } = front_settings(ctx.quick);
    ctx.progress(&format!(
        "real time against error: {} (stone only), reference {rs} × {rb} at {rt:e}",
        throw.title.to_lowercase()
    ));
    let reference = measure(&setting(&base, (rs, rb), None, rt, false))?;
    let shipped_mesh = (shipped.0, shipped.1);
    let shipped_smooth = match base.stone.quadrature {
        Quadrature::Smooth { meridian, around } => Some((meridian, around)),
        Quadrature::Faces => None,
    };
    let mut discretisations = Vec::new();
    for &mesh in &meshes {
        let triangles = triangles(&setting(&base, mesh, None, 1e-6, false).stone);
        discretisations.push((mesh, None, triangles));
    }
    discretisations.extend(smooth.iter().map(|&nodes| (shipped_mesh, Some(nodes), 0)));
    let mut cases = Vec::new();
    for &(mesh, smooth, triangles) in &discretisations {
        for &tolerance in &tolerances {
            for across in [false, true] {
                let p = setting(&base, mesh, smooth, tolerance, across);
                cases.push((mesh, smooth, triangles, tolerance, across, p));
            }
        }
    }
    let mut best: Vec<Option<RunStats>> = vec![None; cases.len()];
    for round in 0..repeats(ctx.quick) {
        ctx.progress(&format!("  round {} of {}", round + 1, repeats(ctx.quick)));
        for (case, slot) in cases.iter().zip(best.iter_mut()) {
            check_cancel()?;
            let run = measure(&case.5)?;
            match slot {
                Some(b) => keep_faster(b, run)?,
                None => *slot = Some(run),
            }
        }
    }
    let points = cases
        .into_iter()
        .zip(best)
        .filter_map(
            |(((segments, bands), smooth, triangles, tolerance, across, _), stats)| {
                let stats = stats?;
                let err = errors(&stats, &reference);
                Some(FrontPoint {
                    segments,
                    bands,
                    triangles,
                    smooth,
                    tolerance,
                    across,
                    stats,
                    err,
                })
            },
        )
        .collect();
    Ok(Front {
        throw,
        reference,
        points,
        shipped,
        shipped_smooth,
    })
}

/// The settings no other setting beats on both real time and distance error (skips wrong count
/// as 100 %), fastest first.
pub fn pareto(points: &[FrontPoint]) -> Vec<&FrontPoint> {
    let err = FrontPoint::judged;
    let mut out: Vec<&FrontPoint> = points
        .iter()
        .filter(|p| {
            !points.iter().any(|q| {
                (q.real_time() > p.real_time() && err(q) <= err(p))
                    || (q.real_time() >= p.real_time() && err(q) < err(p))
            })
        })
        .collect();
    out.sort_by(|a, b| b.real_time().total_cmp(&a.real_time()));
    out
}

// ------------------------------------------------------------------------------------------------
// Report
// ------------------------------------------------------------------------------------------------

/// `front.csv` (the throw's stem): every setting.
pub fn front_csv(front: &Front) -> Csv {
    let mut csv = Csv::new(&[
        "segments",
        "bands",
        "triangles",
        "quadrature",
        "tolerance",
        "across_ticks",
        "skips",
        "skips_error",
        "distance_m",
        "distance_error",
        "contact_error",
        "force_evals",
        "steps",
        "sim_time_s",
        "wall_s",
        "real_time",
    ]);
    for p in &front.points {
        csv.push(vec![
            p.segments.into(),
            p.bands.into(),
            p.triangles.into(),
            quadrature_name(p).into(),
            p.tolerance.into(),
            p.across.into(),
            p.stats.skips.into(),
            p.err.skips.into(),
            p.stats.distance.into(),
            p.err.distance.into(),
            p.err.contact.into(),
            p.stats.force_evals.into(),
            p.stats.steps.into(),
            p.stats.final_time.into(),
            p.stats.wall.into(),
            p.real_time().into(),
        ]);
    }
    csv
}

/// `front.png` (the throw's stem): the judged error against real time (left) and against the noise-free cost,
/// force evaluations × triangles (right); a line per mesh and step rule, tolerances along it.
pub fn front_chart(ctx: &Ctx, front: &Front) -> Result<(), StudyError> {
    let y = "distance error (a wrong skip count: 100 %)";
    let chart = |title: &str, x: &str| {
        Chart::new(title, x, y)
            .log_x()
            .log_y()
            .legend(Legend::LowerLeft)
            .line(RefLine::h("1 %", 0.01, colors::GREY))
    };
    let mut by_time = chart("real time", "real time (simulated s per wall s)").line(RefLine::v(
        "300×",
        GOAL,
        colors::GREY,
    ));
    let mut by_work = chart(
        "noise-free cost",
        "triangle evaluations per throw (force evals × triangles)",
    );
    // The meshes take the palette's colours, the smooth quadratures dark and neutral ones.
    let smooth_colors = [
        colors::BLACK,
        colors::GREY,
        colors::YELLOW,
        Rgb(140, 80, 20),
    ];
    let (mut meshes, mut smooths) = (0, 0);
    for key in discretisations(front) {
        let col = if key.1.is_some() {
            smooths += 1;
            smooth_colors[(smooths - 1) % smooth_colors.len()]
        } else {
            meshes += 1;
            colors::CYCLE[(meshes - 1) % 6]
        };
        for across in [false, true] {
            let pts: Vec<&FrontPoint> = front
                .points
                .iter()
                .filter(|p| is_discretisation(p.discretisation(), key) && p.across == across)
                .collect();
            let Some(first) = pts.first() else {
                continue;
            };
            let mut label = quadrature_name(first);
            if across {
                label.push_str(", across ticks");
            }
            let mark = match (across, first.smooth.is_some()) {
                (false, false) => Mark::LinePoints,
                (true, false) => Mark::Dashed,
                (false, true) => Mark::Points,
                (true, true) => Mark::Line,
            };
            let series = |x: &dyn Fn(&FrontPoint) -> f64| {
                let xy = pts.iter().map(|p| (x(p), p.judged().max(FLOOR))).collect();
                Series::new(label.clone(), xy, col, mark)
            };
            by_time = by_time.series(series(&|p| p.real_time()));
            // The smooth quadrature sums over no triangles: real time is its only cost axis.
            if first.smooth.is_none() {
                by_work =
                    by_work.series(series(&|p| p.stats.force_evals as f64 * p.triangles as f64));
            }
        }
    }
    plot::draw(
        &ctx.path(&format!("{}.png", front.throw.stem)),
        (1600, 700),
        2,
        Some(&format!(
            "{}, stone only: error against speed (tolerances along each line)",
            front.throw.title
        )),
        &[Panel::Chart(by_time), Panel::Chart(by_work)],
    )
}

/// What a setting sums the forces over, in the report.
fn quadrature_name(p: &FrontPoint) -> String {
    discretisation_name(p.discretisation())
}

/// The swept meshes, then the smooth quadratures, in the order they were run.
fn discretisations(front: &Front) -> Vec<Discretisation> {
    let mut out: Vec<Discretisation> = Vec::new();
    for p in &front.points {
        if !out
            .iter()
            .any(|&k| is_discretisation(p.discretisation(), k))
        {
            out.push(p.discretisation());
        }
    }
    out
}

/// A setting's name in the report.
fn name(p: &FrontPoint) -> String {
    format!(
        "{}, tolerance {}{}",
        quadrature_name(p),
        sig(p.tolerance, 1),
        if p.across { ", across ticks" } else { "" }
    )
}

/// A setting's cell: real time, then the distance error or the skips it gets wrong.
fn cell(p: &FrontPoint) -> String {
    let err = if p.err.skips != 0 {
        format!("**{}**", p.error_text())
    } else {
        p.error_text()
    };
    format!("{}×, {err}", sig(p.real_time(), 3))
}

/// The report's section.
pub fn front_md(ctx: &Ctx, front: &Front) -> String {
    let FrontSettings {
        tolerances,
        reference: (rs, rb, rt),
        ..
    } = front_settings(ctx.quick);
    let r = &front.reference;
    let stem = front.throw.stem;
    let mut s = format!(
        "\n## {}, stone only: real time against error\n\n",
        front.throw.title
    );
    s.push_str(&format!(
        "The throw of {} with the water off (free rotation, the Résal spin, Archimedes on the wetted faces, the air in flight; the 5 ms tick), at each mesh (segments × bands) or smooth quadrature (`stone.quadrature: Smooth`, meridian × around Gauss nodes on the lens's ellipsoid instead of its faces; `crates/physics/src/sim/smooth.rs`), `Adaptive` tolerance, and step rule (tick-bound, or `physics.steps_across_ticks`), against {rs} × {rb} at tolerance {} ({} skips, {} m, {} force evaluations). Each setting runs alone, once in each of {} rounds over all the settings, the best wall time kept (the whole run, the stone's construction included); real time is the simulated time over it, noisy on this shared machine by some ±15 % between regenerations. Cell: real time, distance error (a wrong skip count in bold). ![{stem}]({stem}.png)\n\n",
        front.throw.launch,
        sig(rt, 1),
        r.skips,
        sig(r.distance, 6),
        r.force_evals,
        repeats(ctx.quick),
    ));
    let mut header = vec!["mesh, steps".to_string()];
    header.extend(
        tolerances
            .iter()
            .map(|t| format!("tolerance {}", sig(*t, 1))),
    );
    let mut rows = Vec::new();
    for key in discretisations(front) {
        for across in [false, true] {
            let of =
                |p: &&FrontPoint| is_discretisation(p.discretisation(), key) && p.across == across;
            let Some(first) = front.points.iter().find(of) else {
                continue;
            };
            let mut row = vec![format!(
                "{}{}",
                quadrature_name(first),
                if across { ", across ticks" } else { "" }
            )];
            for &t in &tolerances {
                let p = front.points.iter().filter(of).find(|p| p.tolerance == t);
                row.push(p.map_or_else(|| "–".into(), cell));
            }
            rows.push(row);
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    s.push_str(&md_table(&header, &rows));
    s.push_str(&front_findings(front));
    s
}

/// The findings: the shipped setting, the fastest within 1 %, and the 300× goal.
fn front_findings(front: &Front) -> String {
    let mut s = String::from("\n");
    let (sn, sb, st) = front.shipped;
    if let Some(p) = front.points.iter().find(|p| {
        p.smooth == front.shipped_smooth
            && p.segments == sn
            && p.bands == sb
            && p.tolerance == st
            && !p.across
    }) {
        s.push_str(&format!(
            "- The shipped setting ({}): {}× real time, {} force evaluations, distance {}.\n",
            name(p),
            sig(p.real_time(), 3),
            p.stats.force_evals,
            if p.err.skips != 0 {
                format!("with {}", p.error_text())
            } else {
                format!("within {}", p.error_text())
            }
        ));
    }
    let fastest = |ok: &dyn Fn(&FrontPoint) -> bool| {
        front
            .points
            .iter()
            .filter(|p| ok(p))
            .max_by(|a, b| a.real_time().total_cmp(&b.real_time()))
    };
    match fastest(&|p| p.within_one_percent()) {
        Some(p) => s.push_str(&format!(
            "- The fastest setting within 1 % in distance with the reference's skips: {}, {}× real time ({} force evaluations, {}).\n",
            name(p),
            sig(p.real_time(), 3),
            p.stats.force_evals,
            pct(p.err.distance, 2)
        )),
        None => s.push_str("- No setting stays within 1 % with the reference's skips.\n"),
    }
    let goal = format!("{}×", sig(GOAL, 3));
    let reaching = front
        .points
        .iter()
        .filter(|p| p.within_one_percent() && p.real_time() >= GOAL)
        .count();
    match reaching {
        1.. => s.push_str(&format!(
            "- {reaching} setting(s) within 1 % reach {goal} on this machine.\n"
        )),
        0 => {
            s.push_str(&format!(
                "- No setting within 1 % reaches {goal} on this machine."
            ));
            match fastest(&|p| p.real_time() >= GOAL) {
                Some(p) => s.push_str(&format!(
                    " The settings that do are off by more: the fastest, {}, runs {}× with {}.\n",
                    name(p),
                    sig(p.real_time(), 3),
                    p.error_text()
                )),
                None => s.push_str(" No swept setting reaches it at all.\n"),
            }
        }
    }
    // Where the smooth quadrature stands: the fastest of it and of the meshes within 0.1 %.
    let tight = |smooth: bool| fastest(&|p| p.smooth.is_some() == smooth && p.judged() < 1e-3);
    if front.points.iter().any(|p| p.smooth.is_some()) {
        let say = |p: Option<&FrontPoint>| {
            p.map_or_else(
                || "none".to_string(),
                |p| {
                    format!(
                        "{} ({}×, {})",
                        name(p),
                        sig(p.real_time(), 3),
                        p.error_text()
                    )
                },
            )
        };
        s.push_str(&format!(
            "- Within 0.1 % with the reference's skips, the fastest smooth quadrature: {}; the fastest mesh: {}.\n",
            say(tight(true)),
            say(tight(false))
        ));
    }
    let front_pts = pareto(&front.points);
    let list: Vec<String> = front_pts
        .iter()
        .map(|p| {
            format!(
                "{} ({}×, {})",
                name(p),
                sig(p.real_time(), 3),
                p.error_text()
            )
        })
        .collect();
    s.push_str(&format!(
        "- The front (no other setting both faster and closer), fastest first: {}.\n",
        list.join("; ")
    ));
    s
}

/// The settings that hold on every throw of the front: within 1 % with the reference's skips on
/// each, fastest first by their slowest real time; which of them reach the goal on all.
pub fn fronts_findings(fronts: &[Front]) -> String {
    let Some(first) = fronts.first() else {
        return String::new();
    };
    let same = |a: &FrontPoint, b: &FrontPoint| {
        is_discretisation(a.discretisation(), b.discretisation())
            && a.tolerance == b.tolerance
            && a.across == b.across
    };
    let mut held: Vec<(f64, String)> = first
        .points
        .iter()
        .filter_map(|p| {
            let each: Vec<&FrontPoint> = fronts
                .iter()
                .filter_map(|f| f.points.iter().find(|q| same(p, q)))
                .collect();
            let all = each.len() == fronts.len() && each.iter().all(|q| q.within_one_percent());
            all.then(|| {
                let slowest = each
                    .iter()
                    .map(|q| q.real_time())
                    .fold(f64::INFINITY, f64::min);
                let cells: Vec<String> = each
                    .iter()
                    .map(|q| format!("{}×, {}", sig(q.real_time(), 3), q.error_text()))
                    .collect();
                (slowest, format!("{} ({})", name(p), cells.join("; ")))
            })
        })
        .collect();
    held.sort_by(|a, b| b.0.total_cmp(&a.0));
    let titles: Vec<String> = fronts
        .iter()
        .map(|f| f.throw.title.to_lowercase())
        .collect();
    let mut s = format!(
        "\n## Both throws\n\nA setting holds when it is within 1 % with the reference's skips on every throw ({}).\n\n",
        titles.join(", ")
    );
    let goal = format!("{}×", sig(GOAL, 3));
    let reaching: Vec<&str> = held
        .iter()
        .filter(|(slowest, _)| *slowest >= GOAL)
        .map(|(_, text)| text.as_str())
        .collect();
    if reaching.is_empty() {
        s.push_str(&format!(
            "- No setting holds and reaches {goal} on every throw.\n"
        ));
    } else {
        s.push_str(&format!(
            "- Holding and at {goal} or more on every throw: {}.\n",
            reaching.join("; ")
        ));
    }
    let listed: Vec<&str> = held.iter().take(5).map(|(_, t)| t.as_str()).collect();
    s.push_str(&format!(
        "- The fastest that hold, by their slower throw: {}.\n",
        if listed.is_empty() {
            "none".to_string()
        } else {
            listed.join("; ")
        }
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(real_time: f64, distance: f64, skips: i64) -> FrontPoint {
        FrontPoint {
            segments: 32,
            bands: 16,
            triangles: 0,
            smooth: None,
            tolerance: 1e-6,
            across: false,
            stats: RunStats {
                distance: 1.0,
                skips: 1,
                durations: vec![],
                starts: vec![],
                final_time: real_time,
                force_evals: 1,
                steps: 1,
                wall: 1.0,
                outcome: "sank",
            },
            err: Errors {
                distance,
                skips,
                contact: 0.0,
                entry: 0.0,
            },
        }
    }

    /// The front keeps exactly the settings nothing dominates, fastest first; a wrong skip count
    /// is as bad as any error.
    #[test]
    fn pareto_keeps_the_undominated_settings() {
        let pts = vec![
            point(100.0, 1e-3, 0),
            point(200.0, 1e-2, 0),
            point(150.0, 2e-2, 0), // slower and worse than the 200× one
            point(300.0, 1e-4, 1), // fastest, but a skip wrong
            point(50.0, 1e-3, 0),  // as accurate as the 100× one, slower
        ];
        let front: Vec<f64> = pareto(&pts).iter().map(|p| p.real_time()).collect();
        assert_eq!(front, vec![300.0, 200.0, 100.0]);
    }

    /// A setting holds only where it is within 1 % with the right skips on every throw, and
    /// reaches the goal only where its slower throw does.
    #[test]
    fn both_throws_must_hold_a_setting() {
        let at = |tolerance: f64, p: FrontPoint| FrontPoint { tolerance, ..p };
        let front = |points: Vec<FrontPoint>| Front {
            throw: front_throws()[0].clone(),
            reference: point(1.0, 0.0, 0).stats,
            points,
            shipped: (32, 16, 1e-6),
            shipped_smooth: None,
        };
        let fronts = [
            front(vec![
                at(1e-3, point(400.0, 1e-3, 0)),
                at(1e-4, point(350.0, 1e-3, 0)),
                at(1e-5, point(200.0, 1e-3, 0)),
            ]),
            front(vec![
                at(1e-3, point(500.0, 1e-3, 1)), // a skip wrong here
                at(1e-4, point(320.0, 5e-3, 0)),
                at(1e-5, point(250.0, 2e-2, 0)), // over 1 % here
            ]),
        ];
        let text = fronts_findings(&fronts);
        assert!(
            text.contains("or more on every throw: 32 × 16, tolerance 1e-4 (350×"),
            "{text}"
        );
        assert!(!text.contains("tolerance 0.001 ("), "{text}");
        assert!(!text.contains("tolerance 1e-5 ("), "{text}");
    }

    /// Of two runs of a setting the faster is kept; two that differ in result are an error.
    #[test]
    fn repeats_keep_the_faster_run_and_refuse_different_results() {
        let run = |wall: f64, distance: f64| RunStats {
            wall,
            distance,
            ..point(1.0, 0.0, 0).stats
        };
        let mut best = run(2.0, 10.0);
        keep_faster(&mut best, run(1.0, 10.0)).unwrap();
        assert_eq!(best.wall, 1.0);
        keep_faster(&mut best, run(3.0, 10.0)).unwrap();
        assert_eq!(best.wall, 1.0);
        assert!(keep_faster(&mut best, run(0.5, 10.0 + 1e-12)).is_err());
    }

    /// The sweep contains the shipped default's own mesh and tolerance, so the report can place it.
    #[test]
    fn the_full_sweep_contains_the_shipped_setting() {
        let p = Preset::default();
        let sweep = front_settings(false);
        let bands = stoneskip_physics::sim::stone::lens_bands(p.stone.segments, p.stone.bands);
        assert!(sweep.meshes.contains(&(p.stone.segments, bands)));
        assert!(sweep.tolerances.contains(&p.physics.tolerance));
        if let Quadrature::Smooth { meridian, around } = p.stone.quadrature {
            assert!(sweep.smooth.contains(&(meridian, around)));
        }
    }
}
