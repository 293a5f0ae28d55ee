//! The fidelity study's §7, the air in flight (issue 11): the shipped pebbles with the air's
//! lift, drag and pitching moment on and off (`src/sim/air.rs`: Crowther & Potts 2007's disc
//! model, Hummel 2003's coefficients), the spin sweep without it, and the roll a spinning stone
//! takes in its first flight against the gyroscopic estimate M t/(I₃ ω) (a moment M turns an
//! angular momentum I₃ ω at M/(I₃ ω) radians a second). Compute, then results, then the report.

use crate::study::par_map;
use std::f64::consts::TAU;

use stoneskip_physics::sim::air::Air;
use stoneskip_physics::sim::metrics::ThrowShape;
use stoneskip_physics::sim::stone::{orientation_from_attitude, Stone};

use super::super::table::{md_table, sig, Csv};
use super::super::{Ctx, StudyError};
use super::common::{
    ensemble_offsets, shape, shipped_for, spin_revs, spin_runs, PresetCheck, SpinRun,
};

/// The shipped pebbles compared with the air off and on.
const PEBBLES: [&str; 3] = ["default", "magic_angle", "record_throw"];

/// One shipped pebble with the air off and as shipped (on).
#[derive(Debug, Clone)]
pub struct AirPreset {
    pub stem: &'static str,
    pub off: ThrowShape,
    pub on: ThrowShape,
}

/// The first flight of the default throw at one spin: how far the air rolled it.
#[derive(Debug, Clone, Copy)]
pub struct FirstRoll {
    pub rev_per_s: f64,
    /// Launch to the first touch (s).
    pub flight_s: f64,
    /// The stone's bank relative to its path at the first touch (°); launched level (0°).
    pub bank_deg: f64,
    /// |M| t / (I₃ ω) with the launch's moment M held (°).
    pub estimate_deg: f64,
}

/// What §7 measured.
#[derive(Debug, Clone)]
pub struct AirStudy {
    pub presets: Vec<AirPreset>,
    /// The default throw's spin sweep with the air off (the shipped sweep has it on).
    pub sweep_off: Vec<SpinRun>,
    pub rolls: Vec<FirstRoll>,
    /// The record throw at the steeper 15° tilt it had before the air (with the air).
    pub record_steeper: Option<ThrowShape>,
}

fn roll_spins(quick: bool) -> Vec<f64> {
    if quick {
        vec![10.0, 40.0, 150.0]
    } else {
        vec![5.0, 10.0, 14.0, 20.0, 40.0, 80.0, 150.0]
    }
}

/// §7's runs; `shipped` holds the shipped presets' runs as shipped (air on), measured in §6, so
/// only the air-off runs are new here.
pub fn compute(ctx: &Ctx, shipped: &[PresetCheck]) -> Result<AirStudy, StudyError> {
    let q = ctx.quick;
    ctx.progress("the air in flight");
    let pebbles: Vec<&PresetCheck> = PEBBLES
        .iter()
        .filter_map(|stem| shipped.iter().find(|c| c.stem == *stem))
        .collect();
    let presets = par_map(pebbles, |check| {
        let mut off = shipped_for(check.stem, q)?;
        off.physics.air = None;
        Ok(AirPreset {
            stem: check.stem,
            off: shape(&off)?.1,
            on: check.after,
        })
    })?;
    let mut p = shipped_for("default", q)?;
    p.physics.air = None;
    let sweep_off = spin_runs(&p, &spin_revs(q), &ensemble_offsets(q))?;
    let rolls = par_map(roll_spins(q), |rev| first_roll(q, rev))?;
    let record_steeper = if q {
        None
    } else {
        let mut r = shipped_for("record_throw", q)?;
        r.launch.attitude.tilt_deg = 15.0;
        Some(shape(&r)?.1)
    };
    Ok(AirStudy {
        presets,
        sweep_off,
        rolls,
        record_steeper,
    })
}

/// The default throw at `rev` rev/s up to its first touch.
fn first_roll(quick: bool, rev: f64) -> Result<FirstRoll, StudyError> {
    let mut p = shipped_for("default", quick)?;
    p.launch.spin = rev * TAU;
    p.physics.max_time = 0.6;
    let (s, _) = shape(&p)?;
    let first = s
        .contacts
        .first()
        .ok_or_else(|| StudyError::Failed(format!("no touch at {rev} rev/s")))?;
    let stone = Stone::new(&p.stone)?;
    let params = p
        .physics
        .air
        .ok_or_else(|| StudyError::Failed("the shipped default has no air".into()))?;
    let air = Air::for_shape(params, &p.stone.shape);
    let v0 = glam::DVec3::from_array(p.launch.velocity);
    let m = air
        .load(v0, orientation_from_attitude(&p.launch.attitude))
        .torque
        .length();
    let l = stone.principal_moments().z * p.launch.spin;
    Ok(FirstRoll {
        rev_per_s: rev,
        flight_s: first.t_start,
        bank_deg: first.attitude_in[1],
        estimate_deg: (m * first.t_start / l).to_degrees(),
    })
}

pub fn write_csvs(ctx: &Ctx, a: &AirStudy) -> Result<(), StudyError> {
    let mut c = Csv::new(&[
        "preset",
        "air",
        "skips",
        "distance_m",
        "final_share",
        "lateral_m",
    ]);
    for p in &a.presets {
        for (air, t) in [("off", &p.off), ("on", &p.on)] {
            c.push(vec![
                p.stem.into(),
                air.into(),
                t.skips.into(),
                t.distance.into(),
                t.final_share.into(),
                t.lateral.into(),
            ]);
        }
    }
    ctx.write_csv("air_presets.csv", &c)?;
    let mut c = Csv::new(&["rev_per_s", "flight_s", "bank_deg", "estimate_deg"]);
    for r in &a.rolls {
        c.push(vec![
            r.rev_per_s.into(),
            r.flight_s.into(),
            r.bank_deg.into(),
            r.estimate_deg.into(),
        ]);
    }
    ctx.write_csv("air_first_roll.csv", &c)
}

/// §7 of the report; `sweep_on` is the shipped (air on) spin sweep.
pub fn section(a: &AirStudy, sweep_on: &[SpinRun]) -> String {
    let mut s = String::from(
        "\n## 7. The air in flight\n\nBetween contacts the shipped pebbles feel the air: a spinning \
         disc wing's lift C_Lα α, drag C_D0 + C_Dα α² and nose-up pitching moment C_Mα α \
         (Crowther & Potts 2007's model with Hummel 2003's coefficients, no camber for a lens; \
         `src/sim/air.rs`). At 12 m/s and 20° the lift is about half the default pebble's weight. \
         The moment does not pitch a spinning stone, it rolls it, by M/(I₃ω) a second: less spin, \
         more roll.\n\n",
    );
    let rows: Vec<Vec<String>> = a
        .presets
        .iter()
        .flat_map(|p| {
            [("off", &p.off), ("on", &p.on)].map(|(air, t)| {
                vec![
                    format!("{} {air}", p.stem),
                    t.skips.to_string(),
                    sig(t.distance, 3),
                    format!("{:.0} %", 100.0 * t.final_share),
                    sig(t.lateral, 2),
                ]
            })
        })
        .collect();
    s.push_str(&md_table(
        &[
            "preset, air",
            "skips",
            "distance (m)",
            "last contact",
            "sideways (m)",
        ],
        &rows,
    ));
    if let Some(r) = &a.record_steeper {
        s.push_str(&format!(
            "\nThe record throw at 15° of tilt (its tilt before the air): {} skips over {} m, {} m \
             sideways: its first hop's lift holds it up and the moment rolls it off its path, which \
             is why the record preset is thrown flat, at 10° (\"a stone that stays long in the air \
             rolls onto its side\", Steiner, whole_throw.md §3).\n",
            r.skips,
            sig(r.distance, 3),
            sig(r.lateral, 2)
        ));
    }
    s.push_str(
        "\n### The roll in the first flight\n\nThe default throw from its launch (level, 20° of \
         tilt) to the first touch, against spin: its bank at the touch, and M t/(I₃ω) with the \
         launch's moment.\n\n",
    );
    let rows: Vec<Vec<String>> = a
        .rolls
        .iter()
        .map(|r| {
            vec![
                sig(r.rev_per_s, 3),
                sig(r.flight_s, 3),
                sig(r.bank_deg, 3),
                sig(r.estimate_deg, 3),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &[
            "spin (rev/s)",
            "first flight (s)",
            "bank at the touch (°)",
            "M t/(I₃ω) (°)",
        ],
        &rows,
    ));
    s.push_str(&sweep_comparison(a, sweep_on));
    s
}

fn sweep_comparison(a: &AirStudy, sweep_on: &[SpinRun]) -> String {
    let mut s = String::from(
        "\n### Spin, with and without the air\n\nThe default throw's spin sweep (the medians of §2's \
         launch heights) as shipped and with the air off:\n\n",
    );
    let rows: Vec<Vec<String>> = sweep_on
        .iter()
        .filter_map(|on| {
            let off = a.sweep_off.iter().find(|r| r.rev_per_s == on.rev_per_s)?;
            Some(vec![
                sig(on.rev_per_s, 3),
                on.median().to_string(),
                off.median().to_string(),
            ])
        })
        .collect();
    s.push_str(&md_table(
        &["spin (rev/s)", "median, air on", "median, air off"],
        &rows,
    ));
    s.push_str(&format!(
        "\nDrops of the median as spin rises: {} with the air, {} without.\n",
        super::common::spin_drops(sweep_on),
        super::common::spin_drops(&a.sweep_off)
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gyroscopic estimate is the physics the air model must show at high spin, where the
    /// roll is small. The estimate holds the launch's moment, ∝ α: over the first flight the
    /// descending path raises α from 20° towards 30°, so the roll may exceed it by up to half.
    #[test]
    fn a_fast_spun_stone_rolls_as_the_gyroscope_says() {
        let r = first_roll(true, 150.0).unwrap();
        assert!(r.bank_deg.abs() > 0.0);
        assert!(
            (r.bank_deg.abs() / r.estimate_deg - 1.0).abs() < 0.5,
            "bank {} against {}",
            r.bank_deg,
            r.estimate_deg
        );
        let slow = first_roll(true, 40.0).unwrap();
        assert!(
            slow.bank_deg.abs() > r.bank_deg.abs(),
            "less spin, more roll"
        );
    }
}
