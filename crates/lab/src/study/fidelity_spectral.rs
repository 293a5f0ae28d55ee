//! The fidelity study's §10, a deep-water near field (issue 11, criterion 3: no hovercraft). §9
//! found that the columns' near field does not converge: they are shallow-water waves, whose
//! response to a pressure of wavenumber k, η_tt = H k² p/ρ, is kH times the deep-water one, k p/ρ
//! (kH ≈ 19 at the stone's scale in 0.3 m of water). This section throws the same shipped throws on
//! the spectral near field (`sim::water::spectral`: linear potential flow of depth H with the
//! capillary–gravity dispersion relation ω² = (gk + σk³/ρ) tanh(kH), Lamb 1932 §§229, 267, 348,
//! on a patch that travels with the stone), on patches of 2 cm, 1 cm and 5 mm cells over the same
//! 1.28 m side and of 1 cm cells over twice the side, and on flat water (z = 0), from the §2
//! ensemble's launch heights, and reads the "no hovercraft" rule off every run. Compute, then
//! results, then the report.

use crate::sim::params::{NearField, Preset};
use crate::sim::Outcome;

use super::fidelity::{ensemble_offsets, shipped_for, MAX_EARLIER_CONTACT, MAX_FINAL_SHARE};
use super::fidelity_grid::{
    and_list, cm, distinct, ensemble_row, glides, median_distance, run_cases, GridRun, GridStudy,
    SHIPPED,
};
use super::table::{md_table, sig, Csv};
use super::{Ctx, StudyError};

/// The surface a case's stone touches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Near {
    /// z = 0 (wavy contact off).
    Flat,
    /// The spectral near field: cells along a side and the cell (m).
    Spectral { cells: u32, cell: f64 },
}

impl Near {
    fn label(&self) -> String {
        match self {
            Near::Flat => "flat water".into(),
            Near::Spectral { cells, cell } => format!(
                "spectral, {} cm cells, {} m patch",
                cm(*cell),
                sig(*cells as f64 * cell, 3)
            ),
        }
    }

    fn is_spectral(&self) -> bool {
        matches!(self, Near::Spectral { .. })
    }

    /// The patch side (m); 0 for flat water.
    fn side(&self) -> f64 {
        match self {
            Near::Flat => 0.0,
            Near::Spectral { cells, cell } => *cells as f64 * cell,
        }
    }
}

/// The ensemble of one shipped throw on one surface.
#[derive(Debug, Clone)]
pub struct NearCase {
    pub stem: &'static str,
    pub near: Near,
    pub runs: Vec<GridRun>,
}

impl NearCase {
    pub fn glides(&self) -> usize {
        glides(&self.runs)
    }

    fn median_distance(&self) -> Option<f64> {
        median_distance(&self.runs)
    }
}

/// What §10 measured.
#[derive(Debug, Clone)]
pub struct SpectralStudy {
    pub cases: Vec<NearCase>,
}

/// Within this fraction of flat water's median distance a near field counts as close to flat.
const NEAR_FLAT: f64 = 0.1;

/// The patches: 2 cm, 1 cm and 5 mm cells over 1.28 m (refinement), 1 cm over 2.56 m (size).
const PATCHES: [(u32, f64); 4] = [(64, 0.02), (128, 0.01), (256, 0.005), (256, 0.01)];

/// (throw, surface) of every case.
fn cases(quick: bool) -> Vec<(&'static str, Near)> {
    let stems: &[&'static str] = if quick {
        &["default"]
    } else {
        &["default", "magic_angle", "record_throw"]
    };
    let patches: &[(u32, f64)] = if quick { &PATCHES[..1] } else { &PATCHES };
    stems
        .iter()
        .flat_map(|&stem| {
            std::iter::once((stem, Near::Flat)).chain(
                patches
                    .iter()
                    .map(move |&(cells, cell)| (stem, Near::Spectral { cells, cell })),
            )
        })
        .collect()
}

/// The lake of `stem`'s runs (m): long and wide enough that flat-water runs end on it (§9's lakes
/// cut the default's 36 m glide short). Nothing steps it (only its extent is read), so its size
/// costs memory only.
fn lake(stem: &str) -> [f64; 2] {
    if stem == "record_throw" {
        [110.0, 12.0]
    } else {
        [60.0, 12.0]
    }
}

/// The shipped throw `stem` on `near`.
pub(super) fn preset(stem: &str, near: Near, quick: bool) -> Result<Preset, StudyError> {
    let mut p = shipped_for(stem, quick)?;
    let size = lake(stem);
    p.water.size = size;
    p.water.origin = Some([-2.0, -0.5 * size[1]]);
    // The columns are not read: the coarsest cell the grid allows for the lake keeps them small.
    p.water.cell = p.water.cell.max(0.05);
    match near {
        Near::Flat => p.water.wavy_contact = false,
        Near::Spectral { cells, cell } => {
            p.water.wavy_contact = true;
            p.water.near_field = NearField::Spectral;
            p.water.spectral.cells = cells;
            p.water.spectral.cell = cell;
        }
    }
    Ok(p)
}

pub fn compute(ctx: &Ctx) -> Result<SpectralStudy, StudyError> {
    let q = ctx.quick;
    ctx.progress("a deep-water near field");
    let throw = |(stem, near)| preset(stem, near, q);
    let cases = run_cases(cases(q), throw, &ensemble_offsets(q))?
        .into_iter()
        .map(|((stem, near), runs)| NearCase { stem, near, runs })
        .collect();
    Ok(SpectralStudy { cases })
}

pub fn write_csvs(ctx: &Ctx, s: &SpectralStudy) -> Result<(), StudyError> {
    let mut c = Csv::new(&[
        "throw",
        "surface",
        "cells",
        "cell_m",
        "launch_dz_m",
        "outcome",
        "skips",
        "distance_m",
        "final_share",
        "longest_earlier_s",
        "longest_contact_s",
        "crest_m",
        "glide",
    ]);
    for case in &s.cases {
        let (cells, cell) = match case.near {
            Near::Flat => (0, 0.0),
            Near::Spectral { cells, cell } => (cells, cell),
        };
        for r in &case.runs {
            c.push(vec![
                case.stem.into(),
                if case.near.is_spectral() {
                    "spectral"
                } else {
                    "flat"
                }
                .into(),
                (cells as usize).into(),
                cell.into(),
                r.dz.into(),
                r.outcome.map_or("none", Outcome::as_str).into(),
                r.shape.skips.into(),
                r.shape.distance.into(),
                r.shape.final_share.into(),
                r.shape.longest_earlier_contact.into(),
                r.longest_contact.into(),
                r.crest.into(),
                r.glides().into(),
            ]);
        }
    }
    ctx.write_csv("near_spectral.csv", &c)
}

/// The throws the cases hold, in order.
fn throws(s: &SpectralStudy) -> Vec<&'static str> {
    distinct(s.cases.iter().map(|c| c.stem))
}

/// Runs that break the rule and runs, summed over the throws, on the cases `pick` selects.
fn tally(s: &SpectralStudy, pick: impl Fn(&NearCase) -> bool) -> (usize, usize) {
    s.cases
        .iter()
        .filter(|c| pick(c))
        .fold((0, 0), |(g, n), c| (g + c.glides(), n + c.runs.len()))
}

/// The spectral patches the study ran, in order.
fn patches(s: &SpectralStudy) -> Vec<Near> {
    distinct(
        s.cases
            .iter()
            .filter(|c| c.near.is_spectral())
            .map(|c| c.near),
    )
}

/// One line for the lead table.
pub fn lead_words(s: &SpectralStudy) -> String {
    let mut parts: Vec<String> = patches(s)
        .iter()
        .map(|n| {
            let (g, r) = tally(s, |c| c.near == *n);
            match n {
                Near::Spectral { cell, .. } => {
                    format!("{} cm, {} m: {g} of {r}", cm(*cell), sig(n.side(), 3))
                }
                Near::Flat => String::new(),
            }
        })
        .collect();
    let (fg, fr) = tally(s, |c| c.near == Near::Flat);
    parts.push(format!("flat water: {fg} of {fr}"));
    let ok = tally(s, |c| c.near.is_spectral()).0 == 0;
    format!(
        "runs that break the rule ({}): {} ({})",
        throws(s).join(", "),
        parts.join(", "),
        if ok { "yes" } else { "**no**" }
    )
}

fn case_rows(s: &SpectralStudy, g: &GridStudy) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    for stem in throws(s) {
        // §9's shipped columns for the same throw, for comparison.
        if let Some(c) = g
            .cases
            .iter()
            .find(|c| c.stem == stem && (c.cell, c.depth) == SHIPPED)
        {
            rows.push(ensemble_row(
                format!("{stem}, columns {} cm (shipped, §9)", cm(c.cell)),
                &c.runs,
                " (§9's lake)",
            ));
        }
        for c in s.cases.iter().filter(|c| c.stem == stem) {
            rows.push(ensemble_row(
                format!("{stem}, {}", c.near.label()),
                &c.runs,
                "",
            ));
        }
    }
    rows
}

/// The largest relative difference of a spectral case's median distance from flat water's, per
/// throw: (throw, worst |Δ|/flat).
fn distance_gaps(s: &SpectralStudy) -> Vec<(&'static str, f64)> {
    throws(s)
        .into_iter()
        .filter_map(|stem| {
            let of = |pick: &dyn Fn(&NearCase) -> bool| {
                s.cases
                    .iter()
                    .filter(|c| c.stem == stem && pick(c))
                    .filter_map(NearCase::median_distance)
                    .collect::<Vec<f64>>()
            };
            let flat = *of(&|c| c.near == Near::Flat).first()?;
            let worst = of(&|c| c.near.is_spectral())
                .iter()
                .map(|d| (d - flat).abs() / flat)
                .fold(0.0, f64::max);
            Some((stem, worst))
        })
        .collect()
}

/// What the table says, in words.
fn findings(s: &SpectralStudy) -> String {
    let (sg, sr) = tally(s, |c| c.near.is_spectral());
    let (fg, fr) = tally(s, |c| c.near == Near::Flat);
    let longest = s
        .cases
        .iter()
        .filter(|c| c.near.is_spectral())
        .flat_map(|c| c.runs.iter())
        .map(|r| r.longest_contact)
        .fold(0.0, f64::max);
    let gaps = distance_gaps(s);
    let mut w = format!(
        "\n- On the deep-water near field {sg} of {sr} runs break the rule (contacts up to {} s); \
         on flat water {fg} of {fr}.",
        sig(longest, 2)
    );
    let worst = gaps.iter().map(|(_, g)| *g).fold(0.0, f64::max);
    if !gaps.is_empty() {
        w.push_str(&format!(
            " Every spectral patch's median distance lies within {:.1} % of flat water's ({}).",
            100.0 * worst,
            gaps.iter()
                .map(|(stem, g)| format!("{stem} {:.1} %", 100.0 * g))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if sg > 0 && !gaps.is_empty() && worst < NEAR_FLAT {
        w.push_str(
            "\n- Why: at the stone's scale the water is deep, and its response to the stone's \
             pressure is kH times stiffer than the columns' (k p/ρ against H k² p/ρ), so the stone \
             meets nearly still water and its runs stay close to the flat-water ones, planing glide \
             included. What broke up planing on the shipped 2 cm columns (§3) is then the columns' \
             excess compliance, not a property of water; the linear near field does not do it. \
             Hewitt et al. (2011) trace the end of planing to the water rising ahead of the plate, \
             which in a deep lake is the nonlinear splash-up of the impact (Wagner's wetted \
             length), outside this linear model: a candidate for the next step, not built.\n",
        );
    } else if sg == sr && sr > 0 {
        w.push_str(&format!(
            "\n- Every run on every patch ends in a planing glide, as on flat water; the median \
             distances stay within {:.1} % of flat water's but move with the patch (the table), \
             so the distance is not converged on the finest one.\n",
            100.0 * worst
        ));
    } else {
        w.push('\n');
    }
    w
}

/// §10 of the report (§9's shipped-column rows quoted for comparison).
pub fn section(s: &SpectralStudy, g: &GridStudy) -> String {
    let mut out = format!(
        "\n## 10. A deep-water near field\n\nThe shipped {} throw{} (§9's launch heights, on lakes long \
         enough for the flat-water runs) on the spectral near field (`water.near_field: Spectral`: linear potential flow of depth \
         H = {} m with the capillary–gravity dispersion relation, σ = 0.0728 N/m, ν = 10⁻⁶ m²/s, \
         each mode integrated exactly per tick, a sponge in the outer eighth of the patch, the \
         patch following the stone) and on flat water. The rule as in §9 (the last contact at \
         most {:.0} % of the distance, no earlier one longer than {} s).\n\n",
        and_list(&throws(s)),
        if throws(s).len() > 1 { "s" } else { "" },
        SHIPPED.1,
        100.0 * MAX_FINAL_SHARE,
        MAX_EARLIER_CONTACT
    );
    out.push_str(&md_table(
        &[
            "surface",
            "skips, median (range)",
            "distance (m)",
            "runs that break the rule",
            "longest contact (s)",
            "left the lake",
        ],
        &case_rows(s, g),
    ));
    out.push_str(&findings(s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    use super::super::fidelity_grid::test_run as run;

    fn study() -> SpectralStudy {
        SpectralStudy {
            cases: vec![
                NearCase {
                    stem: "default",
                    near: Near::Flat,
                    runs: vec![run(4, 36.0, 0.7), run(4, 35.0, 0.7)],
                },
                NearCase {
                    stem: "default",
                    near: Near::Spectral {
                        cells: 64,
                        cell: 0.02,
                    },
                    runs: vec![run(3, 34.2, 0.7), run(12, 18.0, 0.02)],
                },
            ],
        }
    }

    #[test]
    fn the_lead_counts_glides_per_patch_and_on_flat_water() {
        let s = study();
        assert_eq!(s.cases[1].glides(), 1);
        assert_eq!(
            lead_words(&s),
            "runs that break the rule (default): 2 cm, 1.28 m: 1 of 2, flat water: 2 of 2 (**no**)"
        );
    }

    #[test]
    fn the_distance_gap_is_read_against_flat_waters_median() {
        let s = study();
        // Lower medians: flat 35.0, spectral 18.0.
        let gaps = distance_gaps(&s);
        assert_eq!(gaps.len(), 1);
        assert!((gaps[0].1 - 17.0 / 35.0).abs() < 1e-12, "{gaps:?}");
        let w = findings(&s);
        assert!(w.contains("1 of 2 runs break the rule"), "{w}");
        assert!(w.contains("default 48.6 %"), "{w}");
    }

    #[test]
    fn quick_runs_one_throw_flat_and_on_one_patch() {
        let c = cases(true);
        assert_eq!(c.len(), 2);
        assert_eq!(c[0], ("default", Near::Flat));
        assert_eq!(cases(false).len(), 3 * (1 + PATCHES.len()));
    }
}
