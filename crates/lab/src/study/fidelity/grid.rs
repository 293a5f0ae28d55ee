//! The fidelity study's §9, the near field under refinement (issue 11, criterion 3: no
//! hovercraft). With wavy contact the stone rides the surface that the column-and-pipe water of
//! O'Brien & Hodgins (1995; paper §3.3, eqs. 39–41) carries, and the shipped presets owe their end
//! of planing to it (§3). Those columns are a shallow-water model: every wave runs at c = √(gH)
//! whatever its length (`../shared/reference/water.md`). On real water a wave as long as the
//! stone (λ ≈ 2R) is a deep-water wave: ω² = g k tanh(kH) (Lamb 1932, §228) with kH ≫ 1, so it
//! runs at √(g/k), slower, and disperses. A near field that is a property of the water, not of the
//! grid, must therefore converge as the cells shrink and must not depend on the rest depth H once
//! H is many stone sizes. This section throws the default and magic-angle throws from the §2
//! ensemble's launch heights over cells from 5 cm to 7 mm (the default also over depths from 0.1
//! to 1 m) and the record throw over 2 cm to 1 cm, on lakes wide enough for their curves, and reads
//! the "no hovercraft" rule and the record class's count (criterion 4) off every run. Compute,
//! then results, then the report.

use crate::study::par_map;
use glam::DVec3;

use stoneskip_physics::sim::metrics::{hovercraft, ThrowShape};
use stoneskip_physics::sim::params::{Preset, Shape};
use stoneskip_physics::sim::{Outcome, Simulation};

use super::super::table::{md_table, sig, Csv};
use super::super::{check_cancel, Ctx, StudyError};
use super::common::{
    ensemble_offsets, lower_median, shipped_for, MAX_EARLIER_CONTACT, MAX_FINAL_SHARE, QUICK_CELL,
};

/// The shipped presets' column and rest depth (m), the row the others are read against.
pub(super) const SHIPPED: (f64, f64) = (0.02, 0.3);

/// One throw of the ensemble under one water setting.
#[derive(Debug, Clone, Copy)]
pub struct GridRun {
    /// Launch height offset (m).
    pub dz: f64,
    pub shape: ThrowShape,
    pub outcome: Option<Outcome>,
    /// Longest contact of the run, the last included (s).
    pub longest_contact: f64,
    /// Highest the stone's lowest vertex stood above the still level while in contact (m): the
    /// water under it stood at least that high, so this is a lower bound of the crest it rode.
    pub crest: f64,
}

impl GridRun {
    pub fn glides(&self) -> bool {
        hovercraft(&self.shape, MAX_FINAL_SHARE, MAX_EARLIER_CONTACT).is_some()
    }
}

/// The ensemble of one shipped throw under one (cell, rest depth).
#[derive(Debug, Clone)]
pub struct GridCase {
    /// The shipped preset thrown (file stem).
    pub stem: &'static str,
    pub cell: f64,
    pub depth: f64,
    pub runs: Vec<GridRun>,
}

/// Runs of an ensemble that break the no-hovercraft rule.
pub(super) fn glides(runs: &[GridRun]) -> usize {
    runs.iter().filter(|r| r.glides()).count()
}

/// Runs of an ensemble that left the lake.
pub(super) fn left(runs: &[GridRun]) -> usize {
    let left = Some(Outcome::LeftDomain);
    runs.iter().filter(|r| r.outcome == left).count()
}

/// An ensemble's skip counts, sorted.
pub(super) fn sorted_skips(runs: &[GridRun]) -> Vec<usize> {
    let mut s: Vec<usize> = runs.iter().map(|r| r.shape.skips).collect();
    s.sort_unstable();
    s
}

/// `f` of every run of an ensemble, sorted.
pub(super) fn sorted_by(runs: &[GridRun], f: impl Fn(&GridRun) -> f64) -> Vec<f64> {
    let mut v: Vec<f64> = runs.iter().map(f).collect();
    v.sort_by(f64::total_cmp);
    v
}

/// The distinct items (throws, surfaces, series), in the order they first appear.
pub(super) fn distinct<T: PartialEq>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut t: Vec<T> = Vec::new();
    for item in items {
        if !t.contains(&item) {
            t.push(item);
        }
    }
    t
}

/// One table row: `label`, then an ensemble's skips, distances, runs that break the rule, longest
/// contacts and runs that left the lake (`lake_note` after the last).
pub(super) fn ensemble_row(label: String, runs: &[GridRun], lake_note: &str) -> Vec<String> {
    vec![
        label,
        spread(&sorted_skips(runs), |k: usize| k.to_string()),
        spread(&sorted_by(runs, |r| r.shape.distance), |x| sig(x, 3)),
        format!("{} of {}", glides(runs), runs.len()),
        spread(&sorted_by(runs, |r| r.longest_contact), |x| sig(x, 2)),
        format!("{} of {}{lake_note}", left(runs), runs.len()),
    ]
}

impl GridCase {
    pub fn glides(&self) -> usize {
        glides(&self.runs)
    }

    pub fn left(&self) -> usize {
        left(&self.runs)
    }

    fn skips(&self) -> Vec<usize> {
        sorted_skips(&self.runs)
    }

    fn sorted(&self, f: impl Fn(&GridRun) -> f64) -> Vec<f64> {
        sorted_by(&self.runs, f)
    }

    fn is_shipped(&self) -> bool {
        (self.cell, self.depth) == SHIPPED
    }
}

/// What §9 measured, and the stone and gravity its dispersion argument quotes.
#[derive(Debug, Clone)]
pub struct GridStudy {
    pub cases: Vec<GridCase>,
    /// The default stone's radius (m) and the gravity (m/s²).
    pub radius: f64,
    pub gravity: f64,
}

/// A shipped throw refined: its columns (m) and its lake (m), long enough for the throw and wide
/// enough for its curve, at most 4 M columns at its finest cell (the grid's limit). The first is
/// also thrown over other rest depths.
struct Throw {
    stem: &'static str,
    cells: &'static [f64],
    lake: [f64; 2],
}

const THROWS: [Throw; 3] = [
    Throw {
        stem: "default",
        cells: &[0.05, 0.03, 0.02, 0.014, 0.01, 0.007],
        lake: [32.0, 6.0],
    },
    Throw {
        stem: "magic_angle",
        cells: &[0.05, 0.03, 0.02, 0.014, 0.01, 0.007],
        lake: [32.0, 6.0],
    },
    // The record class runs ~60 m: 1 cm is its finest cell under 4 M columns.
    Throw {
        stem: "record_throw",
        cells: &[0.02, 0.014, 0.01],
        lake: [62.0, 6.0],
    },
];

/// The lake of `stem`'s runs (m), its −x, −y corner 2 m behind the launch and centred.
pub(super) fn lake(stem: &str) -> ([f64; 2], [f64; 2]) {
    let size = THROWS
        .iter()
        .find(|t| t.stem == stem)
        .map_or([32.0, 6.0], |t| t.lake);
    (size, [-2.0, -0.5 * size[1]])
}

/// The throws `cases` holds, in order.
fn throw_stems(quick: bool) -> Vec<&'static str> {
    distinct(cases(quick).into_iter().map(|(stem, ..)| stem))
}

/// (throw, cell, rest depth) of every case.
fn cases(quick: bool) -> Vec<(&'static str, f64, f64)> {
    let first = THROWS[0].stem;
    if quick {
        return vec![(first, QUICK_CELL, SHIPPED.1)];
    }
    let mut c: Vec<(&'static str, f64, f64)> = THROWS
        .iter()
        .flat_map(|t| t.cells.iter().map(|&cell| (t.stem, cell, SHIPPED.1)))
        .collect();
    c.extend([(first, SHIPPED.0, 0.1), (first, SHIPPED.0, 1.0)]);
    c
}

/// Runs `p` to its outcome, watching the lowest vertex while in contact.
pub(super) fn grid_run(p: &Preset, dz: f64) -> Result<GridRun, StudyError> {
    check_cancel()?;
    let mut sim = Simulation::new(p)?;
    // The lake is not stepped when nothing reads it (wavy contact off).
    sim.skip_unread_water();
    let body: Vec<DVec3> = sim.stone().mesh.positions.clone();
    let mut crest = f64::NEG_INFINITY;
    while !sim.is_finished() {
        sim.tick_with(&mut |s| {
            if s.in_contact {
                let q = s.state.orientation;
                let low = body
                    .iter()
                    .map(|v| (q * *v).z)
                    .fold(f64::INFINITY, f64::min);
                crest = crest.max(s.state.position.z + low);
            }
        });
    }
    let summary = sim.summary();
    let l = p.launch.position;
    let shape = stoneskip_physics::sim::metrics::throw_shape(&summary, [l[0], l[1]]);
    let longest_contact = summary
        .contacts
        .iter()
        .map(|c| c.t_end - c.t_start)
        .fold(0.0, f64::max);
    Ok(GridRun {
        dz,
        shape,
        outcome: summary.outcome,
        longest_contact,
        crest: if crest.is_finite() { crest } else { f64::NAN },
    })
}

/// Each case with its ensemble: the case's preset (`preset`) thrown from every launch-height
/// offset of `offsets`, all on rayon's pool; in the order of `cases`.
pub(super) fn run_cases<C: Copy>(
    cases: Vec<C>,
    preset: impl Fn(C) -> Result<Preset, StudyError>,
    offsets: &[f64],
) -> Result<Vec<(C, Vec<GridRun>)>, StudyError> {
    let throws = cases
        .iter()
        .map(|&c| preset(c))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(cases.into_iter().zip(ensembles(throws, offsets)?).collect())
}

/// Every preset of `throws` from each launch-height offset of `offsets`, on rayon's pool: the
/// runs of each preset (its ensemble), in the order of `throws`.
fn ensembles(throws: Vec<Preset>, offsets: &[f64]) -> Result<Vec<Vec<GridRun>>, StudyError> {
    let n = throws.len();
    let jobs: Vec<(usize, Preset, f64)> = throws
        .into_iter()
        .enumerate()
        .flat_map(|(i, p)| offsets.iter().map(move |&dz| (i, p.clone(), dz)))
        .collect();
    let runs = par_map(jobs, |(i, mut p, dz)| {
        p.launch.position[2] += dz;
        grid_run(&p, dz).map(|run| (i, run))
    })?;
    let mut out = vec![Vec::new(); n];
    for (i, run) in runs {
        out[i].push(run);
    }
    Ok(out)
}

/// The lower median of an ensemble's distances (m).
pub(super) fn median_distance(runs: &[GridRun]) -> Option<f64> {
    lower_median_f(&sorted_by(runs, |r| r.shape.distance))
}

/// A run of `skips` over `distance` whose last contact covers `final_share` of it (the studies'
/// unit tests).
#[cfg(test)]
pub(super) fn test_run(skips: usize, distance: f64, final_share: f64) -> GridRun {
    GridRun {
        dz: 0.0,
        shape: stoneskip_physics::sim::metrics::ThrowShape {
            skips,
            distance,
            final_contact_length: final_share * distance,
            final_share,
            final_duration: 5.0 * final_share,
            longest_earlier_contact: 0.05,
            tail_longest_hop: 0.5,
            lateral: -1.0,
        },
        outcome: Some(Outcome::Sank),
        longest_contact: 5.0 * final_share,
        crest: 0.001,
    }
}

pub fn compute(ctx: &Ctx) -> Result<GridStudy, StudyError> {
    let q = ctx.quick;
    ctx.progress("the near field under refinement");
    let mut presets = Vec::new();
    for stem in throw_stems(q) {
        let mut p = shipped_for(stem, q)?;
        let (size, origin) = lake(stem);
        p.water.size = size;
        p.water.origin = Some(origin);
        presets.push((stem, p));
    }
    let throw = |(stem, cell, depth): (&str, f64, f64)| {
        let (_, p) = presets
            .iter()
            .find(|(s, _)| *s == stem)
            .ok_or_else(|| StudyError::Failed(format!("no preset for `{stem}`")))?;
        let mut r = p.clone();
        r.water.cell = cell;
        r.water.depth = depth;
        Ok(r)
    };
    let cases = run_cases(cases(q), throw, &ensemble_offsets(q))?
        .into_iter()
        .map(|((stem, cell, depth), runs)| GridCase {
            stem,
            cell,
            depth,
            runs,
        })
        .collect();
    let (_, p) = presets
        .first()
        .ok_or_else(|| StudyError::Failed("no throw to refine".into()))?;
    let radius = match p.stone.shape {
        Shape::Disk { radius, .. } | Shape::Lens { radius, .. } => radius,
        Shape::Plate { length, width, .. } => 0.5 * length.max(width),
    };
    Ok(GridStudy {
        cases,
        radius,
        gravity: p.physics.gravity,
    })
}

pub fn write_csvs(ctx: &Ctx, g: &GridStudy) -> Result<(), StudyError> {
    let mut c = Csv::new(&[
        "throw",
        "cell_m",
        "depth_m",
        "launch_dz_m",
        "outcome",
        "skips",
        "distance_m",
        "final_share",
        "longest_earlier_s",
        "longest_contact_s",
        "crest_m",
        "lateral_m",
        "glide",
    ]);
    for case in &g.cases {
        for r in &case.runs {
            c.push(vec![
                case.stem.into(),
                case.cell.into(),
                case.depth.into(),
                r.dz.into(),
                r.outcome.map_or("none", Outcome::as_str).into(),
                r.shape.skips.into(),
                r.shape.distance.into(),
                r.shape.final_share.into(),
                r.shape.longest_earlier_contact.into(),
                r.longest_contact.into(),
                r.crest.into(),
                r.shape.lateral.into(),
                r.glides().into(),
            ]);
        }
    }
    ctx.write_csv("near_refinement.csv", &c)
}

/// The lower median of sorted finite values.
pub(super) fn lower_median_f(v: &[f64]) -> Option<f64> {
    let v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    v.get(v.len().checked_sub(1)? / 2).copied()
}

/// A column size in centimetres, to a tenth of a millimetre ("2", "1.4", "0.7").
pub(super) fn cm(cell: f64) -> String {
    format!("{}", (1e3 * cell).round() / 10.0)
}

/// "median (lo–hi)" of sorted values shown by `show`.
pub(super) fn spread<T: Copy>(v: &[T], show: impl Fn(T) -> String) -> String {
    match (v.first(), v.get(v.len().saturating_sub(1) / 2), v.last()) {
        (Some(&lo), Some(&mid), Some(&hi)) => {
            format!("{} ({}–{})", show(mid), show(lo), show(hi))
        }
        _ => "—".into(),
    }
}

fn case_rows(g: &GridStudy) -> Vec<Vec<String>> {
    g.cases
        .iter()
        .map(|c| {
            let mm = |x: f64| sig(1e3 * x, 2);
            vec![
                format!(
                    "{}, {} cm, H {} m{}",
                    c.stem,
                    cm(c.cell),
                    c.depth,
                    if c.is_shipped() { " (shipped)" } else { "" }
                ),
                spread(&c.skips(), |s: usize| s.to_string()),
                format!("{} of {}", c.glides(), c.runs.len()),
                spread(&c.sorted(|r| r.longest_contact), |x| sig(x, 2)),
                spread(&c.sorted(|r| r.crest), mm),
                format!("{} of {}", c.left(), c.runs.len()),
            ]
        })
        .collect()
}

/// The cases at the shipped depth on `cells`, summed over the throws: (cell, glides, runs),
/// in the order the cells first appear.
fn by_cell(g: &GridStudy, cells: impl Fn(f64) -> bool) -> Vec<(f64, usize, usize)> {
    let mut out: Vec<(f64, usize, usize)> = Vec::new();
    for c in g
        .cases
        .iter()
        .filter(|c| c.depth == SHIPPED.1 && cells(c.cell))
    {
        match out.iter_mut().find(|(cell, ..)| *cell == c.cell) {
            Some(e) => {
                e.1 += c.glides();
                e.2 += c.runs.len();
            }
            None => out.push((c.cell, c.glides(), c.runs.len())),
        }
    }
    out
}

/// The throws the cases hold, in order.
fn throws(g: &GridStudy) -> Vec<&'static str> {
    distinct(g.cases.iter().map(|c| c.stem))
}

/// "a", "a and b", "a, b and c".
pub(super) fn and_list(items: &[&str]) -> String {
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => (*last).to_owned(),
        None => String::new(),
    }
}

/// One line for the lead table: how many runs break the rule, at the shipped cell and finer.
pub fn lead_words(g: &GridStudy) -> String {
    let cells = by_cell(g, |cell| cell <= SHIPPED.0);
    if cells.len() < 2 {
        return "not run (full study only)".into();
    }
    let ok = cells.iter().all(|c| c.1 == 0);
    format!(
        "runs that break the rule ({}; H {} m): {} ({})",
        throws(g).join(", "),
        SHIPPED.1,
        cells
            .iter()
            .map(|(cell, glides, runs)| format!("{} cm: {glides} of {runs}", cm(*cell)))
            .collect::<Vec<_>>()
            .join(", "),
        if ok { "yes" } else { "**no**" }
    )
}

/// What the table says, in words, and why.
fn findings(g: &GridStudy) -> String {
    let mut s = String::new();
    let total = |v: Vec<(f64, usize, usize)>| {
        v.iter().fold(None, |acc: Option<(usize, usize)>, c| {
            let (a, b) = acc.unwrap_or((0, 0));
            Some((a + c.1, b + c.2))
        })
    };
    let shipped = total(by_cell(g, |cell| cell == SHIPPED.0));
    let finer_cases: Vec<&GridCase> = g
        .cases
        .iter()
        .filter(|c| c.depth == SHIPPED.1 && c.cell < SHIPPED.0)
        .collect();
    if let Some((sh_glides, sh_runs)) = shipped {
        let (glides, runs) = total(by_cell(g, |cell| cell < SHIPPED.0)).unwrap_or((0, 0));
        s.push_str(&format!(
            "\n- At the shipped 2 cm, {sh_glides} of {sh_runs} runs break the rule. On finer \
             columns {glides} of {runs} do"
        ));
        let longest = finer_cases
            .iter()
            .flat_map(|c| c.runs.iter())
            .map(|r| r.longest_contact)
            .fold(0.0, f64::max);
        if glides > 0 {
            s.push_str(&format!(", with contacts up to {} s", sig(longest, 2)));
            s.push_str(if sh_glides == 0 {
                ": the planing glides the near field removed at 2 cm come back as the cells \
                 shrink."
            } else {
                "."
            });
        } else {
            s.push('.');
        }
        s.push_str(&crest_words(g));
    }
    let by_depth: Vec<&GridCase> = g
        .cases
        .iter()
        .filter(|c| c.stem == THROWS[0].stem && c.cell == SHIPPED.0)
        .collect();
    if by_depth.len() > 1 {
        let skips: Vec<String> = by_depth
            .iter()
            .map(|c| {
                format!(
                    "H {} m: median {}",
                    c.depth,
                    lower_median(&c.skips()).unwrap_or(0)
                )
            })
            .collect();
        let shallowest = by_depth
            .iter()
            .map(|c| c.depth)
            .fold(f64::INFINITY, f64::min);
        let kh = std::f64::consts::TAU / (2.0 * g.radius) * shallowest;
        s.push_str(&format!(
            "\n- At 2 cm the rest depth changes the {} throw's count ({}), although for a wave as \
             long as the stone every H here is deep water (kH ≥ {}, tanh kH ≥ {}): on real water \
             the lake's depth would not reach the stone's near field.",
            THROWS[0].stem,
            skips.join(", "),
            sig(kh, 2),
            sig(kh.tanh(), 3)
        ));
    }
    s.push_str(&record_words(g));
    s.push_str(&dispersion_words(g));
    s
}

/// The record class's throw (issue 11, criterion 4: at least this many skips).
const RECORD: (&str, usize) = ("record_throw", 40);

/// Does the record class survive finer columns?
fn record_words(g: &GridStudy) -> String {
    let cases: Vec<&GridCase> = g
        .cases
        .iter()
        .filter(|c| c.stem == RECORD.0 && c.depth == SHIPPED.1)
        .collect();
    if cases.len() < 2 {
        return String::new();
    }
    let at: Vec<String> = cases
        .iter()
        .map(|c| {
            format!(
                "{} cm: median {} skips, longest contact {} s",
                cm(c.cell),
                lower_median(&c.skips()).unwrap_or(0),
                sig(
                    lower_median_f(&c.sorted(|r| r.longest_contact)).unwrap_or(0.0),
                    2
                )
            )
        })
        .collect();
    let keep: Vec<String> = cases
        .iter()
        .filter(|c| lower_median(&c.skips()).unwrap_or(0) >= RECORD.1)
        .map(|c| format!("{} cm", cm(c.cell)))
        .collect();
    format!(
        "\n- The record class (criterion 4: at least {} skips) under refinement: {}. It keeps \
         its count {}.",
        RECORD.1,
        at.join("; "),
        if keep.is_empty() {
            "on none of them".to_owned()
        } else {
            format!("on {} only", keep.join(", "))
        }
    )
}

/// How high the water the first throw rode stood, at the shipped cell and finer.
fn crest_words(g: &GridStudy) -> String {
    let crests: Vec<String> = g
        .cases
        .iter()
        .filter(|c| c.stem == THROWS[0].stem && c.depth == SHIPPED.1 && c.cell <= SHIPPED.0)
        .filter_map(|c| {
            lower_median_f(&c.sorted(|r| r.crest))
                .map(|x| format!("{} mm at {} cm", sig(1e3 * x, 2), cm(c.cell)))
        })
        .collect();
    if crests.is_empty() {
        return String::new();
    }
    format!(
        " The {} throw's lowest vertex stood well above the still level while in contact \
         (medians {}): it rides water that earlier contacts and its own pressure raised, so \
         these counts are the near field's, not flat water's.",
        THROWS[0].stem,
        crests.join(", ")
    )
}

/// What the runs say about the rule under refinement at the shipped depth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Verdict {
    /// No finer cell was run (`--quick`).
    Untested,
    /// Every run at the shipped cell and finer keeps the rule.
    Holds,
    /// The shipped cell keeps it, finer cells break it.
    OnlyAtTheShippedCell,
    /// The shipped cell breaks it already: (runs that break it, runs) there and, when run, on
    /// the finer cells.
    Fails {
        shipped: (usize, usize),
        finer: Option<(usize, usize)>,
    },
}

/// Runs that break the rule and runs, summed over the cells `cells` picks at the shipped depth;
/// `None` without such a cell.
fn breaks(g: &GridStudy, cells: impl Fn(f64) -> bool) -> Option<(usize, usize)> {
    by_cell(g, cells)
        .iter()
        .map(|c| (c.1, c.2))
        .reduce(|a, b| (a.0 + b.0, a.1 + b.1))
}

fn verdict(g: &GridStudy) -> Verdict {
    let shipped = breaks(g, |cell| cell == SHIPPED.0);
    let finer = breaks(g, |cell| cell < SHIPPED.0);
    match (shipped, finer) {
        (Some(s), _) if s.0 > 0 => Verdict::Fails { shipped: s, finer },
        (None, _) | (Some(_), None) => Verdict::Untested,
        (Some(_), Some((0, _))) => Verdict::Holds,
        (Some(_), Some(_)) => Verdict::OnlyAtTheShippedCell,
    }
}

/// The shallow-water columns against deep water at the stone's own length, and what follows
/// from the runs.
fn dispersion_words(g: &GridStudy) -> String {
    let lambda = 2.0 * g.radius;
    let k = std::f64::consts::TAU / lambda;
    let h = SHIPPED.1;
    let shallow = (g.gravity * h).sqrt();
    let deep = (g.gravity * (k * h).tanh() / k).sqrt();
    let mut s = format!(
        "\n- The columns carry shallow-water waves, all at c = √(gH) = {} m/s for H = {} m. A \
         wave as long as the stone (λ = 2R = {} m, k = {} 1/m) has kH = {}: on real water it is \
         a deep-water wave running at √(g tanh(kH)/k) = {} m/s ({}× slower) that disperses, its \
         crest spreading into a train, while the columns' crests travel intact. So even where \
         the columns converge they converge to shallow-water waves, which at the stone's scale \
         are not the physics of the water.\n\n",
        sig(shallow, 3),
        h,
        sig(lambda, 2),
        sig(k, 3),
        sig(k * h, 3),
        sig(deep, 2),
        sig(shallow / deep, 2),
    );
    const DEEP: &str = "Water whose short waves are deep-water waves (a dispersive height \
         field, e.g. Tessendorf's iWave 2004, or a potential-flow patch that moves with the stone, \
         as issue 11 suggests) is what a converged near field needs; §10 ran one (retired since: \
         docs/studies/retired.md). Reported, not tuned.\n";
    match verdict(g) {
        Verdict::Untested => s.push_str("Finer columns are run by the full study only.\n"),
        Verdict::Holds => s.push_str(
            "On every finer column the rule still holds: the end of planing survives refinement.\n",
        ),
        Verdict::OnlyAtTheShippedCell => {
            s.push_str(
                "So criterion 3 holds for the shipped presets at their 2 cm cell, not as a \
                 property of the model: down to the finest cell here the near field has not \
                 converged, and what it would converge to is shallow water. ",
            );
            s.push_str(DEEP);
        }
        Verdict::Fails {
            shipped: (n, m),
            finer,
        } => {
            s.push_str(&format!(
                "So the end of planing is not a property of the model: at the shipped cell \
                 already {n} of {m} runs from the launch ensemble break the rule (the shipped \
                 presets' own launches are §6's), "
            ));
            if let Some((fn_, fm)) = finer {
                s.push_str(&format!("on finer cells {fn_} of {fm} do, "));
            }
            s.push_str("and what the columns would converge to is shallow water. ");
            s.push_str(DEEP);
        }
    }
    s
}

/// §9 of the report.
pub fn section(g: &GridStudy) -> String {
    let mut s = format!(
        "\n## 9. The near field under refinement\n\nThe shipped {} throw{} (wavy contact, the \
         shipped model) from the §2 ensemble's launch heights on lakes wide enough for their \
         curves ({}), for column sizes and rest depths H. A run breaks the rule when it skips twice and its last \
         contact covers more than {:.0} % of the distance or an earlier one lasts longer than \
         {} s.\n\n",
        and_list(&throws(g)),
        if throws(g).len() > 1 { "s" } else { "" },
        throws(g)
            .iter()
            .map(|stem| {
                let (size, _) = lake(stem);
                format!("{stem} {} × {} m", size[0], size[1])
            })
            .collect::<Vec<_>>()
            .join(", "),
        100.0 * MAX_FINAL_SHARE,
        MAX_EARLIER_CONTACT
    );
    s.push_str(&md_table(
        &[
            "columns",
            "skips, median (range)",
            "runs that break the rule",
            "longest contact (s)",
            "highest crest ridden (mm)",
            "left the lake",
        ],
        &case_rows(g),
    ));
    s.push_str(&findings(g));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(skips: usize, longest_earlier: f64, crest: f64) -> GridRun {
        GridRun {
            dz: 0.0,
            shape: ThrowShape {
                skips,
                distance: 14.0,
                final_contact_length: 0.2,
                final_share: 0.2 / 14.0,
                final_duration: 0.1,
                longest_earlier_contact: longest_earlier,
                tail_longest_hop: 0.5,
                lateral: -1.0,
            },
            outcome: Some(Outcome::Sank),
            longest_contact: longest_earlier.max(0.1),
            crest,
        }
    }

    fn study() -> GridStudy {
        GridStudy {
            cases: vec![
                GridCase {
                    stem: "default",
                    cell: 0.02,
                    depth: 0.3,
                    runs: vec![run(12, 0.1, 0.004), run(9, 0.12, 0.005)],
                },
                GridCase {
                    stem: "default",
                    cell: 0.01,
                    depth: 0.3,
                    runs: vec![run(5, 0.54, 0.012), run(8, 0.03, 0.009)],
                },
                GridCase {
                    stem: "default",
                    cell: 0.02,
                    depth: 1.0,
                    runs: vec![run(4, 0.04, 0.003), run(4, 0.05, 0.003)],
                },
            ],
            radius: 0.05,
            gravity: 9.81,
        }
    }

    #[test]
    fn a_glide_on_finer_columns_is_reported_against_the_shipped_cell() {
        let g = study();
        assert_eq!(g.cases[1].glides(), 1);
        let lead = lead_words(&g);
        assert!(
            lead.contains("(default; H 0.3 m): 2 cm: 0 of 2, 1 cm: 1 of 2 (**no**)"),
            "{lead}"
        );
        let words = findings(&g);
        assert!(words.contains("On finer columns 1 of 2 do"), "{words}");
        assert!(words.contains("contacts up to 0.54 s"), "{words}");
        assert!(
            words.contains("(medians 4.0 mm at 2 cm, 9.0 mm at 1 cm)"),
            "{words}"
        );
        assert!(
            words.contains("H 0.3 m: median 9, H 1 m: median 4"),
            "{words}"
        );
        // kH = 2π/0.1 × 0.3 = 18.8 for the shallowest depth at 2 cm here.
        assert!(words.contains("kH ≥ 19, tanh kH ≥ 1.00"), "{words}");
        assert!(section(&g).contains("The shipped default throw (wavy"));
        assert_eq!(record_words(&g), "");
        assert_eq!(and_list(&["a", "b", "c"]), "a, b and c");
        assert_eq!(and_list(&["a"]), "a");
        let mut rec = g.clone();
        for (i, skips) in [(0, 54), (1, 14)] {
            let mut c = g.cases[i].clone();
            c.stem = RECORD.0;
            for r in &mut c.runs {
                r.shape.skips = skips;
            }
            rec.cases.push(c);
        }
        let words = record_words(&rec);
        assert!(
            words.contains("2 cm: median 54 skips, longest contact 0.10 s"),
            "{words}"
        );
        assert!(words.contains("1 cm: median 14 skips"), "{words}");
        assert!(
            words.contains("It keeps its count on 2 cm only."),
            "{words}"
        );
        // A second throw's runs add to the counts at their cells.
        let mut two = g.clone();
        let mut other = two.cases[1].clone();
        other.stem = "magic_angle";
        two.cases.push(other);
        two.cases.push(g.cases[0].clone());
        let lead = lead_words(&two);
        assert!(lead.contains("(default, magic_angle; H 0.3 m)"), "{lead}");
        assert!(lead.contains("1 cm: 2 of 4"), "{lead}");
        let words = section(&two);
        assert!(
            words.contains("The shipped default and magic_angle throws (wavy"),
            "{words}"
        );
        assert!(
            words.contains("| magic_angle, 1 cm, H 0.3 m | 5 (5–8) | 1 of 2 |"),
            "{words}"
        );
    }

    #[test]
    fn the_dispersion_numbers_follow_from_the_stone_and_the_depth() {
        let words = dispersion_words(&study());
        // c = √(9.81 · 0.3) = 1.716 m/s; λ = 0.1 m, k = 62.8 1/m, kH = 18.8, √(g/k) = 0.395 m/s.
        assert!(words.contains("√(gH) = 1.72 m/s"), "{words}");
        assert!(words.contains("not as a property of the model"), "{words}");
        assert!(words.contains("k = 62.8 1/m) has kH = 18.8"), "{words}");
        assert!(words.contains("= 0.40 m/s (4.3× slower)"), "{words}");
    }

    #[test]
    fn a_glide_at_the_shipped_cell_is_counted_with_the_finer_ones() {
        let mut g = study();
        g.cases[0].runs[1] = run(9, 0.45, 0.005);
        assert_eq!(
            verdict(&g),
            Verdict::Fails {
                shipped: (1, 2),
                finer: Some((1, 2))
            }
        );
        let words = dispersion_words(&g);
        assert!(
            words.contains("already 1 of 2 runs from the launch ensemble break the rule"),
            "{words}"
        );
        assert!(words.contains("on finer cells 1 of 2 do"), "{words}");
        assert!(words.contains("§10 ran one"), "{words}");
        // Without finer cells (the quick run) the words claim none.
        g.cases.retain(|c| c.cell >= SHIPPED.0);
        assert_eq!(
            verdict(&g),
            Verdict::Fails {
                shipped: (1, 2),
                finer: None
            }
        );
        assert!(!dispersion_words(&g).contains("finer cells"));
    }

    #[test]
    fn the_quick_run_has_one_case_and_no_finer_cells() {
        assert_eq!(cases(true).len(), 1);
        let mut g = study();
        g.cases.retain(|c| c.cell >= SHIPPED.0);
        assert_eq!(verdict(&g), Verdict::Untested);
        g.cases.retain(|c| !c.is_shipped());
        assert!(dispersion_words(&g).contains("full study only"));
        let full = cases(false);
        for t in &THROWS {
            assert!(full.contains(&(t.stem, SHIPPED.0, SHIPPED.1)));
            assert!(full.iter().any(|c| c.0 == t.stem && c.1 < SHIPPED.0));
            // Every lake stays under the grid's 4 M columns at its finest cell.
            let finest = t.cells.iter().copied().fold(f64::INFINITY, f64::min);
            let (size, _) = lake(t.stem);
            assert!((size[0] / finest).ceil() * (size[1] / finest).ceil() <= 4.0e6);
        }
    }
}
