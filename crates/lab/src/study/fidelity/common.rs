//! What the fidelity study's sections share (issue 40: the study's shared parts in one module, so
//! the sections import it and not each other): the "no hovercraft" limits, the presets of issue
//! 11's model as compiled in, the model before issue 11, a throw's shape, the spin sweep's runs and
//! their ensembles, and rayon's ordered map.

use crate::study::par_map;
use std::f64::consts::TAU;

use stoneskip_physics::sim::metrics::{throw_shape, ThrowShape};
use stoneskip_physics::sim::params::{AxialSpin, Preset, Rotation};
use stoneskip_physics::sim::{simulate, Summary};

use super::super::{check_cancel, StudyError};

/// The "no hovercraft" limits of issue 11: the last contact at most this share of the distance…
pub const MAX_FINAL_SHARE: f64 = 0.10;
/// …and no earlier contact longer than this (s).
pub const MAX_EARLIER_CONTACT: f64 = 0.3;

/// The presets of issue 11's model as they shipped until issue 38 (the stone on its own near
/// field: wavy contact on 2 cm columns, the quasi-steady contact), by file stem, as compiled in from
/// `docs/studies/fidelity/presets/`: this study is the record of that model, regenerated from its
/// own presets. The shipped presets moved on to the ambient contact with the wetted-extent memory
/// (docs/studies/whole_throw).
pub const SHIPPED: [(&str, &str); 9] = [
    (
        "default",
        include_str!("../../../../../docs/studies/fidelity/presets/default.ron"),
    ),
    (
        "magic_angle",
        include_str!("../../../../../docs/studies/fidelity/presets/magic_angle.ron"),
    ),
    (
        "too_steep",
        include_str!("../../../../../docs/studies/fidelity/presets/too_steep.ron"),
    ),
    (
        "too_slow",
        include_str!("../../../../../docs/studies/fidelity/presets/too_slow.ron"),
    ),
    (
        "record_throw",
        include_str!("../../../../../docs/studies/fidelity/presets/record_throw.ron"),
    ),
    (
        "paper",
        include_str!("../../../../../docs/studies/fidelity/presets/paper.ron"),
    ),
    (
        "bocquet_plate",
        include_str!("../../../../../docs/studies/fidelity/presets/bocquet_plate.ron"),
    ),
    (
        "clanet_disc",
        include_str!("../../../../../docs/studies/fidelity/presets/clanet_disc.ron"),
    ),
    (
        "no_spin_dive",
        include_str!("../../../../../docs/studies/fidelity/presets/no_spin_dive.ron"),
    ),
];

/// Column size of the near-field water in `--quick` runs (coarse: 15× cheaper than the presets'
/// 2 cm, and still free of planing glides, §3).
pub const QUICK_CELL: f64 = 0.05;

/// A shipped preset, with its near-field water coarsened to [`QUICK_CELL`] in quick runs.
pub fn shipped_for(stem: &str, quick: bool) -> Result<Preset, StudyError> {
    let mut p = shipped(stem)?;
    if quick && p.water.wavy_contact {
        p.water.cell = p.water.cell.max(QUICK_CELL);
    }
    Ok(p)
}

pub fn shipped(stem: &str) -> Result<Preset, StudyError> {
    let (_, text) = SHIPPED
        .iter()
        .find(|(s, _)| *s == stem)
        .ok_or_else(|| StudyError::Failed(format!("no shipped preset `{stem}`")))?;
    let path = format!("assets/presets/{stem}.ron");
    stoneskip_physics::preset::parse(text, std::path::Path::new(&path))
        .map_err(|e| StudyError::Failed(e.to_string()))
}

/// The model before issue 11 on the same throw: locked attitude, flat water, no buoyancy, facets.
pub fn before(p: &Preset) -> Preset {
    let mut q = p.clone();
    q.physics.rotation = Rotation::Locked;
    q.physics.buoyancy = false;
    q.physics.axial_spin = AxialSpin::Faceted;
    q.physics.air = None;
    q.water.wavy_contact = false;
    q
}

pub fn shape(p: &Preset) -> Result<(Summary, ThrowShape), StudyError> {
    check_cancel()?;
    let s = simulate(p)?;
    let l = p.launch.position;
    let t = throw_shape(&s, [l[0], l[1]]);
    Ok((s, t))
}

/// One spin of the sweep: the throw itself, and the same throw launched from heights a fraction of
/// a millimetre apart. On the near field one run's count is sensitive to the waves of the contacts
/// before (section 3), so the trend is read from the ensemble's median, not from one run.
#[derive(Debug, Clone)]
pub struct SpinRun {
    pub rev_per_s: f64,
    pub shape: ThrowShape,
    /// Skips of each member of the ensemble, sorted (the throw itself included).
    pub members: Vec<usize>,
    /// The stone's tilt (°) as it leaves its first contact; NaN without one.
    pub tilt_after_first: f64,
    /// Duration of the first contact (s); NaN without one.
    pub first_contact_s: f64,
    /// The stone's tilt (°) as it enters its last contact; NaN without one.
    pub tilt_at_last: f64,
}

impl SpinRun {
    /// The ensemble's median skip count (the lower middle for an even count).
    pub fn median(&self) -> usize {
        lower_median(&self.members).unwrap_or(self.shape.skips)
    }
}

/// The middle of sorted counts (the lower middle for an even count); `None` when empty.
pub fn lower_median(v: &[usize]) -> Option<usize> {
    v.get((v.len().max(1) - 1) / 2).copied()
}

pub fn spin_revs(quick: bool) -> Vec<f64> {
    if quick {
        vec![0.0, 10.0, 20.0, 40.0, 80.0, 150.0]
    } else {
        vec![
            0.0, 2.5, 5.0, 7.5, 10.0, 12.5, 15.0, 17.5, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0, 80.0,
            100.0, 125.0, 150.0,
        ]
    }
}

/// Launch-height offsets (m) of the spin ensemble: ±1 mm in half-millimetre steps (the throw
/// itself alone when quick).
pub fn ensemble_offsets(quick: bool) -> Vec<f64> {
    if quick {
        vec![0.0]
    } else {
        vec![0.0, -1e-3, -5e-4, 5e-4, 1e-3]
    }
}

/// `p` at each spin of `revs`, each from the launch heights `offsets` apart.
pub fn spin_runs(p: &Preset, revs: &[f64], offsets: &[f64]) -> Result<Vec<SpinRun>, StudyError> {
    let jobs: Vec<(f64, f64)> = revs
        .iter()
        .flat_map(|&rev| offsets.iter().map(move |&dz| (rev, dz)))
        .collect();
    let results = par_map(jobs, |(rev, dz)| {
        let mut q = p.clone();
        q.launch.spin = rev * TAU;
        q.launch.position[2] += dz;
        shape(&q).map(|(s, t)| {
            let (first, last) = (s.contacts.first(), s.contacts.last());
            let run = SpinRun {
                rev_per_s: rev,
                shape: t,
                members: Vec::new(),
                tilt_after_first: first.map_or(f64::NAN, |c| c.attitude_out[0]),
                first_contact_s: first.map_or(f64::NAN, |c| c.t_end - c.t_start),
                tilt_at_last: last.map_or(f64::NAN, |c| c.attitude_in[0]),
            };
            (dz, run)
        })
    })?;
    Ok(revs
        .iter()
        .filter_map(|&rev| {
            let of_rev: Vec<_> = results.iter().filter(|r| r.1.rev_per_s == rev).collect();
            let mut members: Vec<usize> = of_rev.iter().map(|r| r.1.shape.skips).collect();
            members.sort_unstable();
            let centre = of_rev.iter().find(|r| r.0 == 0.0)?;
            Some(SpinRun {
                members,
                ..centre.1.clone()
            })
        })
        .collect())
}

/// One shipped preset, before and after.
#[derive(Debug, Clone)]
pub struct PresetCheck {
    pub stem: &'static str,
    pub before: ThrowShape,
    pub after: ThrowShape,
    /// Why the "no hovercraft" rule fails after, if it does.
    pub glide: Option<String>,
    /// The preset keeps the paper's own model: its law, the attitude locked, flat water (issue 11
    /// lets one shipped preset show it).
    pub paper_model: bool,
}

/// Drops in the ensemble's median skip count as spin rises (ignoring a single one-skip wobble).
pub fn spin_drops(runs: &[SpinRun]) -> usize {
    let mut best = 0usize;
    let mut drops = 0;
    let mut wobble_used = false;
    for r in runs {
        let s = r.median();
        if s + 1 == best && !wobble_used {
            wobble_used = true;
        } else if s < best {
            drops += 1;
        }
        best = best.max(s);
    }
    drops
}
