//! The fidelity study's §11, the coupling tick (issue 11, criterion 3: no hovercraft). §9 and §10
//! refined the near field in space at the shipped tick of 5 ms. In time the stone and the water
//! are coupled once a tick (`Simulation::finish_tick`): within a tick the stone reads the surface
//! the last tick left, and its face impulses move the water only at the tick's end (the columns
//! then take whole steps of their own Courant clock). So the stone runs up to a tick ahead of its
//! own wave, and a stone of diameter D at speed U crosses its own length in D/U (8 ms for the
//! default's 10 cm at 12 m/s), not long against 5 ms. This section throws the shipped throws on
//! the shipped 2 cm columns (§9's lakes) at ticks from 5 ms down to 0.3125 ms, from the §2
//! ensemble's launch heights, and reads the distance and the "no hovercraft" rule off every run.
//! (The 1 cm spectral patch of §10 ran here too until it was retired; its rows are in
//! docs/studies/retired.md.) Compute, then results, then the report.

use stoneskip_physics::sim::params::Preset;
use stoneskip_physics::sim::Outcome;

use super::super::table::{md_table, sig, Csv};
use super::super::{Ctx, StudyError};
use super::common::{ensemble_offsets, shipped_for, QUICK_CELL};
use super::grid::{and_list, distinct, ensemble_row, glides, median_distance, run_cases, GridRun};

/// The near field a case's stone rides on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surface {
    /// The shipped columns (the preset's cell; 5 cm when quick) on §9's lake, made longer and
    /// wider; `refined`: their own water step at most the tick (`water.max_step`), so that the
    /// water, not only the stone, is refined in time.
    Columns { cell: f64, refined: bool },
}

impl Surface {
    fn label(&self) -> String {
        match self {
            Surface::Columns { cell, refined } => format!(
                "columns {} cm{}",
                sig(100.0 * cell, 2),
                if *refined {
                    ", water step ≤ tick"
                } else {
                    ""
                }
            ),
        }
    }

    fn kind(&self) -> &'static str {
        match self {
            Surface::Columns { refined: false, .. } => "columns",
            Surface::Columns { refined: true, .. } => "columns (water step ≤ tick)",
        }
    }
}

/// The ensemble of one shipped throw on one surface at one tick.
#[derive(Debug, Clone)]
pub struct TickCase {
    pub stem: &'static str,
    pub surface: Surface,
    /// The coupling tick (s).
    pub dt: f64,
    pub runs: Vec<GridRun>,
}

/// What §11 measured.
#[derive(Debug, Clone)]
pub struct TickStudy {
    pub cases: Vec<TickCase>,
}

/// The ticks (s): the shipped 5 ms, then halved four times.
const TICKS: [f64; 5] = [0.005, 0.0025, 0.00125, 0.000625, 0.0003125];

/// Two successive ticks whose median distances differ by less than this fraction count as
/// converged in the tick.
const CONVERGED: f64 = 0.05;

/// How much longer than §9's the columns' lakes are (m).
const EXTRA_LENGTH: f64 = 20.0;
/// The columns' lakes' width (m; §9's are 6 m).
const COLUMNS_WIDTH: f64 = 12.0;

/// (throw, surface, tick) of every case.
fn cases(quick: bool) -> Vec<(&'static str, Surface, f64)> {
    let stems: &[&'static str] = if quick {
        &["default"]
    } else {
        &["default", "magic_angle", "record_throw"]
    };
    let ticks: &[f64] = if quick { &[TICKS[0], TICKS[2]] } else { &TICKS };
    let column = if quick { QUICK_CELL } else { 0.02 };
    let surfaces = [
        Surface::Columns {
            cell: column,
            refined: false,
        },
        Surface::Columns {
            cell: column,
            refined: true,
        },
    ];
    let mut out = Vec::new();
    for &stem in stems {
        for surface in surfaces {
            out.extend(ticks.iter().map(|&dt| (stem, surface, dt)));
        }
    }
    out
}

/// The shipped throw `stem` on `surface` at tick `dt`: §9's shipped-column run on a lake
/// [`EXTRA_LENGTH`] longer.
fn preset(stem: &str, surface: Surface, dt: f64, quick: bool) -> Result<Preset, StudyError> {
    let Surface::Columns { refined, .. } = surface;
    let mut p = shipped_for(stem, quick)?;
    let (size, _) = super::grid::lake(stem);
    // §9's lake, longer and wider: at finer ticks the record throw reached §9's far end, and with
    // the water step refined a throw can curve out of its sides.
    p.water.size = [size[0] + EXTRA_LENGTH, COLUMNS_WIDTH];
    p.water.origin = Some([-2.0, -0.5 * COLUMNS_WIDTH]);
    if refined {
        p.water.max_step = Some(dt);
    }
    p.physics.dt = dt;
    Ok(p)
}

pub fn compute(ctx: &Ctx) -> Result<TickStudy, StudyError> {
    let q = ctx.quick;
    ctx.progress("the coupling tick");
    let throw = |(stem, surface, dt)| preset(stem, surface, dt, q);
    let cases = run_cases(cases(q), throw, &ensemble_offsets(q))?
        .into_iter()
        .map(|((stem, surface, dt), runs)| TickCase {
            stem,
            surface,
            dt,
            runs,
        })
        .collect();
    Ok(TickStudy { cases })
}

pub fn write_csvs(ctx: &Ctx, s: &TickStudy) -> Result<(), StudyError> {
    let mut c = Csv::new(&[
        "throw",
        "surface",
        "cell_m",
        "tick_s",
        "launch_dz_m",
        "outcome",
        "skips",
        "distance_m",
        "final_share",
        "longest_earlier_s",
        "longest_contact_s",
        "glide",
    ]);
    for case in &s.cases {
        let Surface::Columns { cell, .. } = case.surface;
        for r in &case.runs {
            c.push(vec![
                case.stem.into(),
                case.surface.kind().into(),
                cell.into(),
                case.dt.into(),
                r.dz.into(),
                r.outcome.map_or("none", Outcome::as_str).into(),
                r.shape.skips.into(),
                r.shape.distance.into(),
                r.shape.final_share.into(),
                r.shape.longest_earlier_contact.into(),
                r.longest_contact.into(),
                r.glides().into(),
            ]);
        }
    }
    ctx.write_csv("coupling_tick.csv", &c)
}

/// (throw, surface) pairs in the order the cases hold them.
fn series(s: &TickStudy) -> Vec<(&'static str, Surface)> {
    distinct(s.cases.iter().map(|c| (c.stem, c.surface)))
}

/// The coarsest and the finest tick the study ran (s).
fn tick_range(s: &TickStudy) -> (f64, f64) {
    s.cases.iter().fold((0.0, f64::INFINITY), |(hi, lo), c| {
        (f64::max(hi, c.dt), f64::min(lo, c.dt))
    })
}

/// The cases of one series, by tick from the coarsest.
fn of<'a>(s: &'a TickStudy, stem: &str, surface: Surface) -> Vec<&'a TickCase> {
    let mut v: Vec<&TickCase> = s
        .cases
        .iter()
        .filter(|c| c.stem == stem && c.surface == surface)
        .collect();
    v.sort_by(|a, b| b.dt.total_cmp(&a.dt));
    v
}

/// A tick in milliseconds, as the tables show it.
fn ms(dt: f64) -> String {
    sig(1e3 * dt, 3)
}

/// One series' median distances from the coarsest tick to the finest, and whether its two finest
/// ticks agree within [`CONVERGED`].
fn trend(cases: &[&TickCase]) -> (Vec<f64>, Option<bool>) {
    let d: Vec<f64> = cases
        .iter()
        .filter_map(|c| median_distance(&c.runs))
        .collect();
    let converged = match d.as_slice() {
        [.., a, b] => Some((b - a).abs() <= CONVERGED * a.abs()),
        _ => None,
    };
    (d, converged)
}

/// One line for the lead table: the rule at the finest tick, per surface, and whether the
/// distances settled.
pub fn lead_words(s: &TickStudy) -> String {
    let (_, finest) = tick_range(s);
    let mut parts = Vec::new();
    for kind in distinct(s.cases.iter().map(|c| c.surface.kind())) {
        let (g, n) = s
            .cases
            .iter()
            .filter(|c| c.dt == finest && c.surface.kind() == kind)
            .fold((0, 0), |(g, n), c| (g + glides(&c.runs), n + c.runs.len()));
        if n > 0 {
            parts.push(format!("{kind} {g} of {n}"));
        }
    }
    let ok = s
        .cases
        .iter()
        .filter(|c| c.dt == finest)
        .all(|c| glides(&c.runs) == 0);
    let settled = series(s)
        .iter()
        .filter(|(stem, surface)| trend(&of(s, stem, *surface)).1 == Some(true))
        .count();
    format!(
        "runs that break the rule at a {} ms tick: {} ({}); distances settled (two finest ticks \
         within {:.0} %) in {settled} of {} series",
        ms(finest),
        parts.join(", "),
        if ok { "yes" } else { "**no**" },
        100.0 * CONVERGED,
        series(s).len()
    )
}

fn case_rows(s: &TickStudy) -> Vec<Vec<String>> {
    s.cases
        .iter()
        .map(|c| {
            let mut row = ensemble_row(format!("{}, {}", c.stem, c.surface.label()), &c.runs, "");
            row.insert(1, ms(c.dt));
            row
        })
        .collect()
}

/// What the table says, in words.
fn findings(s: &TickStudy) -> String {
    let mut w = String::from("\n");
    for (stem, surface) in series(s) {
        let cases = of(s, stem, surface);
        let (d, converged) = trend(&cases);
        let (first, last) = match (cases.first(), cases.last()) {
            (Some(a), Some(b)) => (a, b),
            _ => continue,
        };
        w.push_str(&format!(
            "- {stem} on {}: median distance {} m from {} ms to {} ms; runs that break the rule {} \
             of {} at {} ms, {} of {} at {} ms; {}.",
            surface.label(),
            d.iter().map(|x| sig(*x, 3)).collect::<Vec<_>>().join(" → "),
            ms(first.dt),
            ms(last.dt),
            glides(&first.runs),
            first.runs.len(),
            ms(first.dt),
            glides(&last.runs),
            last.runs.len(),
            ms(last.dt),
            match converged {
                Some(true) => format!(
                    "the two finest ticks agree within {:.0} %",
                    100.0 * CONVERGED
                ),
                Some(false) => "still moving at the finest tick".into(),
                None => "one tick only".into(),
            }
        ));
        w.push('\n');
    }
    w.push_str(&verdicts(s));
    w
}

/// The series whose verdict on the rule differs between the coarsest tick and the finest.
fn verdicts(s: &TickStudy) -> String {
    let changed: Vec<String> = series(s)
        .into_iter()
        .filter_map(|(stem, surface)| {
            let cases = of(s, stem, surface);
            let (a, b) = (cases.first()?, cases.last()?);
            (glides(&a.runs) != glides(&b.runs)).then(|| {
                format!(
                    "{stem} on {} ({} of {} at {} ms, {} of {} at {} ms)",
                    surface.label(),
                    glides(&a.runs),
                    a.runs.len(),
                    ms(a.dt),
                    glides(&b.runs),
                    b.runs.len(),
                    ms(b.dt)
                )
            })
        })
        .collect();
    if changed.is_empty() {
        return "- The verdict on the rule is the same at every tick in every series.\n".into();
    }
    format!(
        "- The verdict on the rule changes with the tick: {}. What the coarse tick shows there is \
         the coupling's lag, not the model's answer.\n",
        changed.join("; ")
    )
}

/// §11 of the report.
pub fn section(s: &TickStudy) -> String {
    let throws = distinct(s.cases.iter().map(|c| c.stem));
    let mut out = format!(
        "\n## 11. The coupling tick\n\nThe stone and the water are coupled once a tick: within a \
         tick the stone reads the surface the last tick left, and its impulses move the water at \
         the tick's end, so the stone runs up to a tick ahead of its own wave (the default crosses \
         its own 10 cm in 8 ms). §9 ran at the shipped 5 ms. Here the {} throw{} on the shipped \
         columns (§9's lakes, {} m longer and {} m wide), as shipped (their own water step stays \
         at 70 % of the Courant limit, 7.1 ms at 2 cm) and with that step at most the tick \
         (`water.max_step`), at ticks from {} ms down to {} ms, from §2's launch heights. The \
         rule as in §9. (The spectral patch ran here too until it was retired: \
         docs/studies/retired.md.)\n\n",
        and_list(&throws),
        if throws.len() > 1 { "s" } else { "" },
        EXTRA_LENGTH,
        COLUMNS_WIDTH,
        ms(tick_range(s).0),
        ms(tick_range(s).1),
    );
    out.push_str(&md_table(
        &[
            "throw, surface",
            "tick (ms)",
            "skips, median (range)",
            "distance (m)",
            "runs that break the rule",
            "longest contact (s)",
            "left the lake",
        ],
        &case_rows(s),
    ));
    out.push_str(&findings(s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(distance: f64, final_share: f64) -> GridRun {
        super::super::grid::test_run(4, distance, final_share)
    }

    fn case(dt: f64, distance: f64, share: f64) -> TickCase {
        TickCase {
            stem: "default",
            surface: Surface::Columns {
                cell: 0.02,
                refined: false,
            },
            dt,
            runs: vec![run(distance, share), run(distance + 1.0, share)],
        }
    }

    #[test]
    fn the_trend_runs_from_the_coarsest_tick_and_checks_the_two_finest() {
        let s = TickStudy {
            cases: vec![
                case(0.000625, 12.0, 0.05),
                case(0.005, 17.0, 0.05),
                case(0.00125, 12.4, 0.5),
            ],
        };
        let surface = Surface::Columns {
            cell: 0.02,
            refined: false,
        };
        let (d, converged) = trend(&of(&s, "default", surface));
        assert_eq!(d, vec![17.0, 12.4, 12.0]);
        // |12.0 − 12.4| / 12.4 = 3.2 % ≤ 5 %.
        assert_eq!(converged, Some(true));
        let w = lead_words(&s);
        assert!(
            w.starts_with("runs that break the rule at a 0.625 ms tick: columns 0 of 2 (yes)"),
            "{w}"
        );
        assert!(w.ends_with("in 1 of 1 series"), "{w}");
    }

    #[test]
    fn a_verdict_that_changes_with_the_tick_is_named() {
        let s = TickStudy {
            cases: vec![case(0.005, 58.0, 0.01), case(0.0003125, 57.0, 0.5)],
        };
        let w = verdicts(&s);
        assert!(
            w.contains("default on columns 2.0 cm (0 of 2 at 5.00 ms, 2 of 2 at 0.312 ms)"),
            "{w}"
        );
        let same = TickStudy {
            cases: vec![case(0.005, 58.0, 0.01), case(0.0003125, 57.0, 0.01)],
        };
        assert!(verdicts(&same).contains("the same at every tick"));
    }

    #[test]
    fn quick_runs_two_ticks_on_each_surface() {
        assert_eq!(cases(true).len(), 4);
        assert_eq!(cases(false).len(), 3 * 2 * TICKS.len());
    }
}
