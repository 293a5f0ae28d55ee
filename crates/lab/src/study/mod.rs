//! Speed-versus-accuracy studies (design.md §8, issue 5): work-precision charts — error against a
//! converged reference versus cost, after Hairer, Nørsett & Wanner, *Solving ODEs I* §II.10 — for
//! the integrators, the mesh and the water grid; stability limits where methods fail (the contact
//! oscillator of physics.md §1.3 and §7.4, the water's Courant limit of water.md §3, the paper's
//! eq. 41 clamp, Heron's formula on slivers); the skipping phase diagram of Clanet, Hersen &
//! Bocquet (Nature 2004) and Rosellini et al. (JFM 2005); and the cheapest settings under 1 % error.
//!
//! Each study writes CSV data, PNG charts and a Markdown `README.md` into its output folder. This
//! module is an edge of the program: it reads the wall clock (`std::time::Instant`) for the
//! wall-time cost axis; the deterministic cost is the simulation's force-evaluation count.

pub mod accuracy;
pub mod attitude;
pub mod defaults;
pub mod fidelity;
pub mod first_bounce;
pub mod phase;
pub mod plot;
pub mod spin;
pub mod stability;
pub mod style;
pub mod table;
pub mod throws;
pub mod whole_throw;

use std::path::Path;
use std::time::Instant;

mod shared;
pub use shared::{check_cancel, linspace_step, logspace, par_map, rel_err, Ctx, StudyError};
use shared::{install_ctrlc, write_atomic};

/// The studies `run_study` knows, in the order `all` runs them.
pub const STUDIES: [&str; 8] = [
    "accuracy",
    "stability",
    "phase",
    "defaults",
    "fidelity",
    "whole_throw",
    "first_bounce",
    "attitude",
];

/// Runs study `name` ("accuracy", "stability", "phase", "defaults", "fidelity", "whole_throw",
/// "first_bounce", "spin", "attitude" or "all") into `out`; `quick`
/// takes coarse grids (CI). With "all", each study writes into its own subfolder of `out`.
pub fn run_study(name: &str, out: &Path, quick: bool) -> anyhow::Result<()> {
    install_ctrlc();
    plot::ensure_font()?;
    let started = Instant::now();
    match name {
        "all" => {
            let mut index = Vec::new();
            for n in STUDIES {
                let dir = out.join(n);
                let secs = run_one(n, &dir, quick)?;
                index.push((n, secs));
            }
            for (n, s) in index {
                eprintln!("stoneskip study: {n} took {s:.1} s");
            }
        }
        other => {
            run_one(other, out, quick)?;
        }
    }
    eprintln!(
        "stoneskip study {name}: done in {:.1} s, output in {}",
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// Runs one named study; returns its wall time (s).
fn run_one(name: &str, out: &Path, quick: bool) -> Result<f64, StudyError> {
    let started = Instant::now();
    match name {
        "accuracy" => accuracy::run(&Ctx::new("accuracy", out, quick)?)?,
        "stability" => stability::run(&Ctx::new("stability", out, quick)?)?,
        "phase" => phase::run(&Ctx::new("phase", out, quick)?)?,
        "defaults" => defaults::run(&Ctx::new("defaults", out, quick)?)?,
        "fidelity" => fidelity::run(&Ctx::new("fidelity", out, quick)?)?,
        "whole_throw" => whole_throw::run_study(&Ctx::new("whole_throw", out, quick)?)?,
        "first_bounce" => first_bounce::run_study(&Ctx::new("first_bounce", out, quick)?)?,
        "attitude" => attitude::run(&Ctx::new("attitude", out, quick)?)?,
        // The phase study's spin axis alone (`phase` runs it too).
        "spin" => {
            let ctx = Ctx::new("spin", out, quick)?;
            let section = spin::run(&ctx)?;
            ctx.write(
                "README.md",
                &format!("# Spin study (the phase study's spin axis)\n\n{section}"),
            )?;
        }
        other => return Err(StudyError::Unknown(other.to_owned())),
    }
    if !plot::CHARTS {
        note_no_charts(out)?;
    }
    Ok(started.elapsed().as_secs_f64())
}

/// Says at the top of a study's report that its charts were not drawn (a build without the
/// `charts` feature), so the images it links to are missing.
fn note_no_charts(out: &Path) -> Result<(), StudyError> {
    let path = out.join("README.md");
    let text = std::fs::read_to_string(&path).map_err(|source| StudyError::Io {
        path: path.clone(),
        source,
    })?;
    let note = "> Charts not drawn: this stoneskip was built without the `charts` feature, so the \
                PNG images this report links to are missing; the CSV files hold the data.\n\n";
    write_atomic(out, "README.md", &format!("{note}{text}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_study_lists_the_names() {
        let dir = std::env::temp_dir().join("stoneskip-unknown-study");
        let e = run_study("nope", &dir, true).unwrap_err().to_string();
        assert!(
            e.contains("nope")
                && e.contains(
                    "accuracy, stability, phase, defaults, fidelity, whole_throw, first_bounce, spin, attitude, all"
                ),
            "{e}"
        );
    }
}
