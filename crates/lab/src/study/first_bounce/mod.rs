//! The first bounce and the whole throw from one contact law (issue 47): every candidate law of
//! the wetted-extent memory (`sim/memory.rs`) measured against Clanet, Hersen & Bocquet's first
//! bounce (Nature 427, 2004: the contact time at α = β = 20°, the steepest impact angle that still
//! bounces at 3.5 m/s, the minimal speed against tilt) and against the whole throws issue 38 holds
//! (convergence under tick, surface and tolerance; final slides; the record throw from a hand's
//! height; Hewitt's tangential touches; spin). Compute (this module), then results ([`FirstBounce`]),
//! then report (`report.rs`): the Pareto table of the laws, the {α, β} domain at 3.5 m/s and the
//! contact time against α for the shipped law and the laws it replaced, and the record throw's
//! count against its release height.
//!
//! The laws (first_bounce_memory.md §3–4): dd_e/dt = A·max(ḋ_g, 0) + (d_g − d_e)/τ with
//! τ = λ s_g/(|U| (1 + Π/Π_c)), Π = |ṡ_g|/|U|: A = 0 and no Π_c is the constant lag of issue 38;
//! Π_c = 0.12 the linearised Wagner strip's lag against its reduced frequency
//! (docs/studies/wagner_lag, the b/s = 2–3 curves: λ_c(ω̂)/λ_c(0) ≈ 1/(1 + ω̂/Π_c) with
//! Π_c = 0.09–0.15); A the entry lead of Wagner's condition (π/2 a wedge, 4/3 a flat plate from a
//! fixed edge, ½–¾ with a Kutta edge and a finite patch).

pub mod report;

use stoneskip_physics::sim::metrics::ThrowShape;
use stoneskip_physics::sim::params::{LagLength, MemoryParams, Preset, Quadrature, Rotation};
use stoneskip_physics::sim::scenario::{at_impact, first_contact, min_speed, IMPACT_CLEARANCE};
use stoneskip_physics::sim::simulate;

use super::par_map;
use super::whole_throw::{halve_cell, preset, shape_of, tangential_preset, Change, Model, THROWS};
use super::{check_cancel, Ctx, StudyError};

/// One candidate law of the memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Law {
    pub name: &'static str,
    /// `None`: the quasi-steady contact.
    pub memory: Option<MemoryParams>,
}

const fn memory(lag: f64, strip_frequency: Option<f64>, entry_lead: f64) -> Option<MemoryParams> {
    Some(MemoryParams {
        lag,
        length: LagLength::Wetted,
        strip_frequency,
        entry_lead,
    })
}

/// Π_c of the Wagner strip's b/s = 2–3 curves.
pub const STRIP_FREQUENCY: f64 = 0.12;

/// The laws measured, the shipped one among them: the quasi-steady contact, issue 38's constant
/// lag (shipped), the reference's entry lead, the strip's Π-lag at its own Π_c (with λ as shipped
/// and raised so that the hops keep λ ≈ 2, with Wagner's entry lead at a Kutta edge), and the
/// Π-lag at larger Π_c (the front between the first bounce and the slides). The strip's span
/// scaling, τ = κ_b b_g/|U|, was measured and retired (docs/studies/retired.md).
pub const LAWS: [Law; 9] = [
    Law {
        name: "quasi-steady",
        memory: None,
    },
    Law {
        name: "lag λ 2 (issue 38, shipped)",
        memory: memory(2.0, None, 0.0),
    },
    Law {
        name: "lead A 1, λ 4",
        memory: memory(4.0, None, 1.0),
    },
    Law {
        name: "strip Π-lag λ 2, Π_c 0.12",
        memory: memory(2.0, Some(STRIP_FREQUENCY), 0.0),
    },
    Law {
        name: "strip Π-lag λ 6, Π_c 0.12",
        memory: memory(6.0, Some(STRIP_FREQUENCY), 0.0),
    },
    Law {
        name: "strip Π-lag λ 2, Π_c 0.12, lead ¾",
        memory: memory(2.0, Some(STRIP_FREQUENCY), 0.75),
    },
    Law {
        name: "Π-lag λ 2, Π_c 0.25",
        memory: memory(2.0, Some(0.25), 0.0),
    },
    Law {
        name: "Π-lag λ 2, Π_c 1",
        memory: memory(2.0, Some(1.0), 0.0),
    },
    Law {
        name: "Π-lag λ 3, Π_c 1",
        memory: memory(3.0, Some(1.0), 0.0),
    },
];

/// Clanet's reference speed (m/s).
pub const CLANET_SPEED: f64 = 3.5;

/// Clanet's disc (`clanet_disc`'s stone and launch) under the shipped default's physics (air,
/// buoyancy, free body, tolerance) with `law`'s memory.
pub fn clanet(law: &Law) -> Result<Preset, StudyError> {
    let mut p = preset(Model::After, "clanet_disc")?;
    p.physics = preset(Model::After, "default")?.physics;
    p.physics.wetted_memory = law.memory;
    Ok(p)
}

/// A throw of `base` tilted `tilt_deg` hitting at `speed` and `beta_deg`: its first contact,
/// `None` if the stone sank in it.
pub fn first(
    base: &Preset,
    tilt_deg: f64,
    speed: f64,
    beta_deg: f64,
) -> Result<Option<f64>, StudyError> {
    check_cancel()?;
    let mut p = base.clone();
    p.launch.attitude.tilt_deg = tilt_deg;
    let p = at_impact(&p, speed, beta_deg.to_radians(), IMPACT_CLEARANCE)?;
    Ok(first_contact(&p)?.filter(|c| c.skipped).map(|c| c.duration))
}

/// The steepest impact angle (degrees) that still bounces at `tilt_deg` and [`CLANET_SPEED`], by
/// bisection over 5–85° to `steps` halvings; 0 when 5° does not bounce.
pub fn steepest(base: &Preset, tilt_deg: f64, steps: usize) -> Result<f64, StudyError> {
    let (mut a, mut b) = (5.0, 85.0);
    if first(base, tilt_deg, CLANET_SPEED, a)?.is_none() {
        return Ok(0.0);
    }
    for _ in 0..steps {
        let m = 0.5 * (a + b);
        if first(base, tilt_deg, CLANET_SPEED, m)?.is_some() {
            a = m;
        } else {
            b = m;
        }
    }
    Ok(0.5 * (a + b))
}

/// The refinements of issue 38's convergence check: tick / 4, cell / 2, the surface × 2 (a smooth
/// lens's quadrature nodes doubled each way, a mesh's segments doubled), tolerance / 100.
pub const REFINEMENTS: [Change; 5] = [
    ("as shipped", |_| {}),
    ("tick / 4", |p| p.physics.dt /= 4.0),
    ("cell / 2", halve_cell),
    ("surface × 2", surface_doubled),
    ("tolerance / 100", |p| p.physics.tolerance /= 100.0),
];

fn surface_doubled(p: &mut Preset) {
    p.stone.segments *= 2;
    if let Quadrature::Smooth { meridian, around } = p.stone.quadrature {
        p.stone.quadrature = Quadrature::Smooth {
            meridian: 2 * meridian,
            around: 2 * around,
        };
    }
}

/// A shipped preset with `law`'s memory where it has one.
pub fn with_law(stem: &str, law: &Law) -> Result<Preset, StudyError> {
    let mut p = preset(Model::After, stem)?;
    if p.physics.wetted_memory.is_some() {
        p.physics.wetted_memory = law.memory;
    }
    Ok(p)
}

/// Every part the study runs, one job each.
#[derive(Debug, Clone, Copy)]
enum Job {
    /// Clanet's contact at α = β = 20°.
    Contact,
    Steepest(f64),
    MinSpeed(f64),
    /// A shipped throw under a refinement.
    Throw(&'static str, usize),
    /// The record throw released at this height (m) and this share of its speed.
    Record(f64, f64),
    /// The default at this spin (rev/s), free (`None`) or held at this tilt (degrees).
    Spin(f64, Option<f64>),
    /// Hewitt's tangential touch at this speed (m/s).
    Hewitt(f64),
}

/// What one job measured.
#[derive(Debug, Clone, Copy)]
enum Out {
    Time(Option<f64>),
    Angle(f64),
    Speed(Option<f64>),
    Throw(ThrowShape, [f64; 3]),
    /// The second contact's vertical restitution (0 without a second skip).
    Restitution(f64),
}

/// The tilts of the {α, β} domain's search (degrees).
pub const DOMAIN_TILTS: [f64; 7] = [10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0];
/// The tilts of the minimal speed (degrees).
pub const MIN_SPEED_TILTS: [f64; 5] = [10.0, 15.0, 20.0, 25.0, 30.0];
/// Release heights of the record throw (m).
pub const RELEASE_HEIGHTS: [f64; 5] = [0.1, 0.2, 0.3, 0.4, 0.5];
/// Spins of the default throw (rev/s).
pub const SPINS: [f64; 8] = [0.0, 5.0, 10.0, 15.0, 20.0, 50.0, 100.0, 150.0];
/// Spins at which the held count is compared (rev/s).
pub const HELD_SPINS: [f64; 2] = [100.0, 150.0];
/// The tilts (degrees) the held default is compared at: its launch tilt, and about the mean tilt
/// at landing the free stone settles to at 15–150 rev/s (7–9° under issue 38's lag).
pub const HELD_TILTS: [f64; 2] = [20.0, 8.0];

fn jobs(quick: bool) -> Vec<Job> {
    let mut j = vec![Job::Contact];
    let tilts: &[f64] = if quick { &[20.0] } else { &DOMAIN_TILTS };
    j.extend(tilts.iter().map(|&t| Job::Steepest(t)));
    let tilts: &[f64] = if quick { &[20.0] } else { &MIN_SPEED_TILTS };
    j.extend(tilts.iter().map(|&t| Job::MinSpeed(t)));
    let throws: &[&'static str] = if quick { &THROWS[..1] } else { &THROWS };
    for &stem in throws {
        let n = if quick { 1 } else { REFINEMENTS.len() };
        j.extend((0..n).map(|i| Job::Throw(stem, i)));
    }
    if !quick {
        for stem in stoneskip_physics::preset::SHIPPED.map(|(s, _)| s) {
            if !THROWS.contains(&stem) {
                j.push(Job::Throw(stem, 0));
            }
        }
        j.extend(RELEASE_HEIGHTS.iter().map(|&h| Job::Record(h, 1.0)));
        j.extend([Job::Record(0.3, 0.9), Job::Record(0.3, 0.85)]);
        j.extend(SPINS.iter().map(|&s| Job::Spin(s, None)));
        for tilt in HELD_TILTS {
            j.extend(HELD_SPINS.iter().map(|&s| Job::Spin(s, Some(tilt))));
        }
    }
    j.extend([Job::Hewitt(3.0), Job::Hewitt(12.0)]);
    j
}

fn throw(p: &Preset) -> Result<Out, StudyError> {
    check_cancel()?;
    let s = simulate(p)?;
    Ok(Out::Throw(shape_of(&s, p), landing_tilts(&s.contacts)))
}

/// The tilt (degrees, relative to travel) at a throw's first and second landings and its mean
/// over every landing; NaN where there is none.
fn landing_tilts(contacts: &[stoneskip_physics::sim::ContactEvent]) -> [f64; 3] {
    let at = |i: usize| contacts.get(i).map_or(f64::NAN, |c| c.attitude_in[0]);
    let mean = if contacts.is_empty() {
        f64::NAN
    } else {
        contacts.iter().map(|c| c.attitude_in[0]).sum::<f64>() / contacts.len() as f64
    };
    [at(0), at(1), mean]
}

fn run_job(law: &Law, job: Job, quick: bool) -> Result<Out, StudyError> {
    let steps = if quick { 5 } else { 10 };
    Ok(match job {
        Job::Contact => Out::Time(first(&clanet(law)?, 20.0, CLANET_SPEED, 20.0)?),
        Job::Steepest(t) => Out::Angle(steepest(&clanet(law)?, t, steps)?),
        Job::MinSpeed(t) => {
            let mut p = clanet(law)?;
            p.launch.attitude.tilt_deg = t;
            let tol = if quick { 2e-2 } else { 2e-3 };
            Out::Speed(min_speed(&p, 20f64.to_radians(), 0.5, 10.0, tol)?)
        }
        Job::Throw(stem, i) => {
            let mut p = with_law(stem, law)?;
            (REFINEMENTS[i].1)(&mut p);
            throw(&p)?
        }
        Job::Record(h, share) => {
            let mut p = with_law("record_throw", law)?;
            p.launch.position[2] = h;
            p.launch.velocity = p.launch.velocity.map(|v| v * share);
            throw(&p)?
        }
        Job::Spin(rev, held) => {
            let mut p = with_law("default", law)?;
            p.launch.spin = rev * std::f64::consts::TAU;
            if let Some(tilt) = held {
                p.physics.rotation = Rotation::Locked;
                p.launch.attitude.tilt_deg = tilt;
            }
            throw(&p)?
        }
        Job::Hewitt(speed) => {
            check_cancel()?;
            let mut p = tangential_preset(speed)?;
            p.physics.wetted_memory = law.memory;
            let s = simulate(&p)?;
            Out::Restitution(
                s.contacts
                    .get(1)
                    .filter(|c| c.skip)
                    .map_or(0.0, |c| c.v_out[2] / -c.v_in[2]),
            )
        }
    })
}

/// A whole throw's result in the law's row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrowResult {
    pub stem: &'static str,
    pub change: &'static str,
    pub shape: ThrowShape,
    /// Tilt at the first and second landings and the mean over every landing (degrees).
    pub tilts: [f64; 3],
    /// The preset has a memory, so the law applies to it.
    pub on_law: bool,
}

/// One law's measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct LawRow {
    pub law: Law,
    /// Clanet's contact at α = β = 20° (s); `None` if the disc sank.
    pub contact: Option<f64>,
    /// (tilt, steepest bouncing impact angle), degrees.
    pub steepest: Vec<(f64, f64)>,
    /// (tilt, minimal speed at β = 20°), degrees and m/s.
    pub min_speed: Vec<(f64, Option<f64>)>,
    /// Shipped throws under refinements, and the other shipped presets as shipped.
    pub throws: Vec<ThrowResult>,
    /// The record throw: (release height m, speed share, result).
    pub record: Vec<(f64, f64, ThrowResult)>,
    /// The default at each spin: (rev/s, the tilt it was held at or `None` when free, result).
    pub spin: Vec<(f64, Option<f64>, ThrowResult)>,
    /// Hewitt's tangential touches: (speed, the second contact's vertical restitution; above 1 a
    /// small heave oscillation about planing grows, so the stone skips on).
    pub hewitt: Vec<(f64, f64)>,
    /// Wall time of the law's runs (s, this machine).
    pub seconds: f64,
}

impl LawRow {
    /// The steepest bouncing impact angle over the tilts (degrees).
    pub fn top_beta(&self) -> f64 {
        self.steepest.iter().map(|s| s.1).fold(0.0, f64::max)
    }

    /// The shipped throw `stem` as shipped.
    pub fn shipped(&self, stem: &str) -> Option<&ThrowResult> {
        self.throws
            .iter()
            .find(|t| t.stem == stem && t.change == REFINEMENTS[0].0)
    }

    /// The largest change of the count and the relative change of the distance of `stem` under
    /// the refinements.
    pub fn spread(&self, stem: &str) -> Option<(usize, f64)> {
        let base = self.shipped(stem)?.shape;
        let mut worst = (0, 0.0f64);
        for t in self.throws.iter().filter(|t| t.stem == stem) {
            worst.0 = worst.0.max(t.shape.skips.abs_diff(base.skips));
            let rel = (t.shape.distance - base.distance).abs() / base.distance.max(1e-9);
            worst.1 = worst.1.max(rel);
        }
        Some(worst)
    }

    /// The largest final-contact share over the shipped presets on the law (those with a memory)
    /// as shipped that skip (a throw that sinks at its first touch, as `too_steep` is meant to,
    /// has no slide after its skips).
    pub fn worst_slide(&self) -> (&'static str, f64) {
        self.throws
            .iter()
            .filter(|t| t.change == REFINEMENTS[0].0 && t.shape.skips > 0 && t.on_law)
            .map(|t| (t.stem, t.shape.final_share))
            .fold(("", 0.0), |a, b| if b.1 > a.1 { b } else { a })
    }
}

pub fn law_row(law: Law, quick: bool) -> Result<LawRow, StudyError> {
    let started = std::time::Instant::now();
    let jobs = jobs(quick);
    let outs = par_map(jobs.clone(), |job| run_job(&law, job, quick))?;
    let mut row = LawRow {
        law,
        contact: None,
        steepest: Vec::new(),
        min_speed: Vec::new(),
        throws: Vec::new(),
        record: Vec::new(),
        spin: Vec::new(),
        hewitt: Vec::new(),
        seconds: 0.0,
    };
    for (job, out) in jobs.into_iter().zip(outs) {
        let result = |stem, change, out| match out {
            Out::Throw(shape, tilts) => Some(ThrowResult {
                stem,
                change,
                shape,
                tilts,
                on_law: preset(Model::After, stem).is_ok_and(|p| p.physics.wetted_memory.is_some()),
            }),
            _ => None,
        };
        match (job, out) {
            (Job::Contact, Out::Time(t)) => row.contact = t,
            (Job::Steepest(t), Out::Angle(a)) => row.steepest.push((t, a)),
            (Job::MinSpeed(t), Out::Speed(u)) => row.min_speed.push((t, u)),
            (Job::Throw(stem, i), o) => row.throws.extend(result(stem, REFINEMENTS[i].0, o)),
            (Job::Record(h, k), o) => {
                if let Some(r) = result("record_throw", "release", o) {
                    row.record.push((h, k, r));
                }
            }
            (Job::Spin(rev, held), o) => {
                if let Some(r) = result("default", "spin", o) {
                    row.spin.push((rev, held, r));
                }
            }
            (Job::Hewitt(u), Out::Restitution(e)) => row.hewitt.push((u, e)),
            _ => {}
        }
    }
    row.seconds = started.elapsed().as_secs_f64();
    Ok(row)
}

/// The {α, β} domain of Clanet's disc at [`CLANET_SPEED`]: whether it bounces, and the contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainCell {
    pub law: usize,
    pub tilt_deg: f64,
    pub beta_deg: f64,
    /// The first contact's duration (s) when it bounced.
    pub contact: Option<f64>,
}

/// The laws whose domain is charted: the quasi-steady contact, the shipped law and the law that
/// comes nearest Clanet's first bounce.
pub const DOMAIN_LAWS: [usize; 3] = [0, SHIPPED_LAW, FIRST_BOUNCE_LAW];

/// The law the presets ship (an index into [`LAWS`]).
pub const SHIPPED_LAW: usize = 1;

/// The law nearest Clanet's first bounce (the strip's Π-lag with Wagner's entry lead).
pub const FIRST_BOUNCE_LAW: usize = 5;

fn domain(quick: bool) -> Result<Vec<DomainCell>, StudyError> {
    let step = if quick { 10.0 } else { 2.5 };
    let tilts = super::linspace_step(5.0, 45.0, step);
    let betas = super::linspace_step(5.0, 60.0, step);
    let mut jobs = Vec::new();
    for &law in &DOMAIN_LAWS {
        for &tilt_deg in &tilts {
            for &beta_deg in &betas {
                jobs.push((law, tilt_deg, beta_deg));
            }
        }
    }
    par_map(jobs, |(law, tilt_deg, beta_deg)| {
        let base = clanet(&LAWS[law])?;
        Ok(DomainCell {
            law,
            tilt_deg,
            beta_deg,
            contact: first(&base, tilt_deg, CLANET_SPEED, beta_deg)?,
        })
    })
}

/// Everything the study measured.
#[derive(Debug, Clone)]
pub struct FirstBounce {
    pub rows: Vec<LawRow>,
    pub domain: Vec<DomainCell>,
}

/// The laws to measure: all, or in `--quick` the quasi-steady contact and the shipped law.
fn laws(quick: bool) -> Vec<Law> {
    if quick {
        vec![LAWS[0], LAWS[SHIPPED_LAW]]
    } else {
        LAWS.to_vec()
    }
}

/// Runs every part of the study.
pub fn compute(ctx: &Ctx) -> Result<FirstBounce, StudyError> {
    let mut rows = Vec::new();
    for law in laws(ctx.quick) {
        let row = law_row(law, ctx.quick)?;
        ctx.progress(&format!("{}: {:.1} s", law.name, row.seconds));
        rows.push(row);
    }
    let domain = domain(ctx.quick)?;
    ctx.progress("the {α, β} domain");
    Ok(FirstBounce { rows, domain })
}

/// Computes, then writes the CSVs and the report.
pub fn run_study(ctx: &Ctx) -> Result<(), StudyError> {
    let r = compute(ctx)?;
    report::write(ctx, &r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lag withholds lift while the disc goes deeper: its contact is longer and its domain
    /// smaller than the quasi-steady contact's, and the strip's lag, shorter at Clanet's Π ≈ 1,
    /// lies between them.
    #[test]
    fn a_lag_lengthens_the_contact_and_narrows_the_domain() {
        let contact = |law: usize| {
            first(&clanet(&LAWS[law]).unwrap(), 20.0, CLANET_SPEED, 20.0)
                .unwrap()
                .unwrap()
        };
        let (quasi, lag, strip) = (contact(0), contact(SHIPPED_LAW), contact(3));
        assert!(quasi < strip && strip < lag, "{quasi} {strip} {lag}");
        let top = |law: usize| steepest(&clanet(&LAWS[law]).unwrap(), 20.0, 5).unwrap();
        // Five halvings of 80°: 2.5° apart at most.
        assert!(
            top(0) > top(SHIPPED_LAW) + 2.5,
            "{} {}",
            top(0),
            top(SHIPPED_LAW)
        );
    }
}
