//! The `stoneskip` command line (design.md §7): the desktop app by default, and headless
//! `simulate`, `render` and `study`.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use stoneskip::report::{json_summary, text_summary, CsvWriter};
use stoneskip::sweep::{Knob, Plan, Spec, MAX_SIDE, MAX_THROWS};
use stoneskip_physics::preset;
use stoneskip_physics::sim::params::Preset;
use stoneskip_physics::sim::{Simulation, StepSample};

#[derive(Parser)]
#[command(
    name = "stoneskip",
    version,
    about = "A physically based stone-skipping simulator"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
// Built without the `app` feature, `gui` and `render` are still parsed, to answer with a clear
// message, but their arguments are never read.
#[cfg_attr(not(feature = "app"), allow(dead_code))]
enum Command {
    /// Opens the desktop app (the default).
    Gui {
        /// Preset to load at start.
        #[arg(long)]
        preset: Option<PathBuf>,
        /// Smoke test: render this many frames, then exit.
        #[arg(long)]
        frames: Option<u64>,
    },
    /// Runs a preset headless and prints a summary.
    Simulate {
        /// A preset file (RON), or a shipped preset's name: default, magic_angle, record_throw,
        /// too_slow, too_steep, paper, bocquet_plate, clanet_disc, no_spin_dive.
        #[arg(long)]
        preset: PathBuf,
        /// One JSON object on stdout instead of the text summary.
        #[arg(long)]
        json: bool,
        /// Writes the trajectory as CSV.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Steps the water even when nothing reads it (wavy contact off), e.g. for its volume drift.
        #[arg(long)]
        step_water: bool,
    },
    /// Throws a preset many times, changing one launch value from one number to another (or two
    /// values, every one with every other: a map), and writes the results as a CSV table: the
    /// same table the app's Experiments panel exports.
    ///
    /// Each throw runs headless, like `simulate`, on every core of the machine. The table has
    /// one row per throw: the value (and the second value), the skips, the distance (m), how the
    /// throw ended in words, whether that is a result of the throw (no: the lake's edge or the
    /// time limit stopped it), the work it took, and the stone's tilt and bank (degrees) when it
    /// met the water first and last. Lines starting with # say what was swept and on which
    /// preset.
    ///
    /// Example: stoneskip sweep --preset magic_angle --vary tilt --from 0 --to 45 --count 46
    ///
    /// A map, Clanet's phase diagram: stoneskip sweep --preset clanet_disc --vary tilt --from 0
    /// --to 45 --count 10 --vary2 impact_angle --from2 5 --to2 60 --count2 12
    Sweep {
        /// A preset file (RON), or a shipped preset's name (see `simulate --help`).
        #[arg(long)]
        preset: PathBuf,
        /// What to change: speed (m/s), tilt (degrees), impact_angle (degrees: how steeply the
        /// stone comes down onto the water; the throw then starts at the water), spin (rev/s),
        /// height (m) or mass (kg).
        #[arg(long)]
        vary: String,
        /// The first value, in the unit above (default: a range worth trying first, e.g. tilt
        /// from 0 to 45 degrees).
        #[arg(long)]
        from: Option<f64>,
        /// The last value, in the same unit.
        #[arg(long)]
        to: Option<f64>,
        /// How many throws, both ends included (2 to 200; default: a round step, e.g. every
        /// degree of tilt). With a second value: how many values of the first, 2 to 20
        /// (default: a round step, e.g. tilt from 0 to 45 degrees every 5).
        #[arg(long)]
        count: Option<usize>,
        /// A second value to change, for a map: every value of the first is thrown with every
        /// value of the second (the same names as --vary; not the same one twice, and not
        /// height with impact_angle).
        #[arg(long)]
        vary2: Option<String>,
        /// The second value's first number.
        #[arg(long, requires = "vary2")]
        from2: Option<f64>,
        /// The second value's last number.
        #[arg(long, requires = "vary2")]
        to2: Option<f64>,
        /// How many values of the second, 2 to 20 (at most 400 throws in all).
        #[arg(long, requires = "vary2")]
        count2: Option<usize>,
        /// The CSV file to write (default: print the table).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Renders the scene at time T offscreen to a PNG.
    Render {
        /// A preset file (RON), or a shipped preset's name (see `simulate --help`).
        #[arg(long)]
        preset: PathBuf,
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value_t = 1280)]
        width: u32,
        #[arg(long, default_value_t = 720)]
        height: u32,
        /// Simulated time of the picture (s).
        #[arg(long, default_value_t = 0.0)]
        time: f64,
        /// The app's camera: behind, side, follow or top.
        #[arg(long, default_value = "behind")]
        view: String,
        /// The side view's vertical exaggeration: 1, 5, 10 or 20.
        #[arg(long, default_value_t = 1.0)]
        exaggerate: f32,
    },
    /// Runs a study (accuracy, stability, phase, defaults, fidelity, whole_throw, first_bounce, attitude; spin: the phase study's spin axis alone) and writes CSV, PNG and Markdown.
    Study {
        name: String,
        #[arg(long)]
        out: PathBuf,
        /// A small version for CI.
        #[arg(long)]
        quick: bool,
    },
}

fn main() {
    if let Err(e) = run() {
        eprintln!("stoneskip: error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        #[cfg(feature = "app")]
        None => stoneskip::app::run_app(None, None),
        #[cfg(feature = "app")]
        Some(Command::Gui { preset, frames }) => stoneskip::app::run_app(preset, frames),
        #[cfg(not(feature = "app"))]
        None | Some(Command::Gui { .. }) | Some(Command::Render { .. }) => Err(without_app()),
        Some(Command::Simulate {
            preset,
            json,
            csv,
            step_water,
        }) => simulate(&preset, json, csv.as_deref(), step_water),
        #[cfg(feature = "app")]
        Some(Command::Render {
            preset,
            out,
            width,
            height,
            time,
            view,
            exaggerate,
        }) => {
            let p = preset::load_file_or_shipped(&preset)?;
            let view = stoneskip_render::PictureView {
                view: parse_view(&view).map_err(anyhow::Error::msg)?,
                exaggeration: exaggerate,
            };
            stoneskip_render::render_to_png(&p, &out, width, height, time, view)
                .with_context(|| format!("rendering {}", out.display()))
        }
        Some(Command::Study { name, out, quick }) => run_study(&name, &out, quick),
        Some(Command::Sweep {
            preset,
            vary,
            from,
            to,
            count,
            vary2,
            from2,
            to2,
            count2,
            out,
        }) => {
            let map = vary2.is_some();
            let x = sweep_spec(&vary, [from, to], count, ("", map))?;
            let y = match vary2 {
                Some(v) => Some(sweep_spec(&v, [from2, to2], count2, ("2", map))?),
                None => None,
            };
            sweep(&preset, Plan { x, y }, out.as_deref())
        }
    }
}

/// One value of `sweep`: the knob named `vary`, its range and count, each defaulting to the
/// suggested sweep (a map's side when `map`); `tag` is "" or "2" (which options to name in an
/// error).
fn sweep_spec(
    vary: &str,
    [from, to]: [Option<f64>; 2],
    count: Option<usize>,
    (tag, map): (&str, bool),
) -> Result<Spec> {
    let knob = Knob::parse(vary).with_context(|| {
        format!(
            "unknown value to vary \"{vary}\" (expected speed, tilt, impact_angle, spin, height \
             or mass)"
        )
    })?;
    let suggested = if map {
        Spec::for_map(knob)
    } else {
        Spec::suggested(knob)
    };
    let spec = Spec {
        knob,
        from: from.unwrap_or(suggested.from),
        to: to.unwrap_or(suggested.to),
        count: count.unwrap_or(suggested.count),
    };
    let (lo, hi) = knob.range();
    for (name, v) in [("--from", spec.from), ("--to", spec.to)] {
        if !(lo..=hi).contains(&v) {
            anyhow::bail!(
                "{name}{tag} {v} is outside {}'s range, {lo} to {hi} {}",
                knob.name().to_lowercase(),
                knob.unit()
            );
        }
    }
    if !(2..=MAX_THROWS).contains(&spec.count) {
        anyhow::bail!("--count{tag} {} is outside 2 to {MAX_THROWS}", spec.count);
    }
    Ok(spec)
}

/// `sweep`: the Experiments panel's table, headless, on every core.
fn sweep(path: &Path, plan: Plan, out: Option<&Path>) -> Result<()> {
    if let Some(y) = plan.y {
        for (name, s) in [("--count", plan.x), ("--count2", y)] {
            if s.count > MAX_SIDE {
                anyhow::bail!("{name} {} is over {MAX_SIDE}, a map's most a side", s.count);
            }
        }
    }
    if let Some(why) = plan.conflict() {
        anyhow::bail!("--vary2 cannot be mapped with --vary: {why}");
    }
    let p: Preset = preset::load_file_or_shipped(path)?;
    p.validate()
        .with_context(|| format!("{}", path.display()))?;
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let c = cancel.clone();
        // Ctrl-C stops the sweep cleanly; failing to install the handler only loses that nicety.
        let _ = ctrlc::set_handler(move || c.store(true, Ordering::SeqCst));
    }
    let started = Instant::now();
    let points = stoneskip::sweep::run(&p, &plan, &cancel);
    eprintln!(
        "{} throws in {:.1} s on {} threads",
        points.len(),
        started.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    match out {
        Some(o) => {
            let f =
                std::fs::File::create(o).with_context(|| format!("creating {}", o.display()))?;
            stoneskip::sweep::write_csv(std::io::BufWriter::new(f), &p, &p, &plan, &points)
                .with_context(|| format!("writing {}", o.display()))
        }
        None => stoneskip::sweep::write_csv(std::io::stdout().lock(), &p, &p, &plan, &points),
    }
}

/// `study NAME`: the lab's studies.
#[cfg(feature = "lab")]
fn run_study(name: &str, out: &std::path::Path, quick: bool) -> Result<()> {
    stoneskip_lab::study::run_study(name, out, quick)
}

/// A build without the lab has no studies to run.
#[cfg(not(feature = "lab"))]
fn run_study(name: &str, _out: &std::path::Path, _quick: bool) -> Result<()> {
    anyhow::bail!(
        "this stoneskip was built without the `lab` feature, so it has no studies (asked for \
         `{name}`); rebuild with the default features, or `--features lab`"
    )
}

/// The answer of a headless build to `gui`, `render` or no subcommand.
#[cfg(not(feature = "app"))]
fn without_app() -> anyhow::Error {
    anyhow::anyhow!(
        "this stoneskip was built without the `app` feature, so it has no window and no renderer \
         (`gui`, `render`); `simulate` and `study` work. Rebuild with the default features for the app."
    )
}

/// `--view`: one of the app's cameras.
#[cfg(feature = "app")]
fn parse_view(s: &str) -> Result<stoneskip_render::ViewMode, String> {
    match stoneskip_render::ViewMode::parse(s) {
        Some(stoneskip_render::ViewMode::Free) | None => Err(format!(
            "unknown view \"{s}\" (expected behind, side, follow or top)"
        )),
        Some(v) => Ok(v),
    }
}

/// The most time a run has left: it ends at `max_time` at the latest, `remaining` simulated
/// seconds away, advancing at `rate` simulated seconds per real second.
fn time_left(remaining: f64, rate: f64) -> String {
    if !(rate > 0.0 && rate.is_finite()) {
        return "no estimate of the time left: no simulated time advanced in the last second"
            .to_owned();
    }
    let s = remaining.max(0.0) / rate;
    let span = if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.0} days", s / 86_400.0)
    };
    format!("at most ~{span} left at the current rate, {rate:.3e} simulated s per s")
}

fn simulate(path: &Path, json: bool, csv: Option<&Path>, step_water: bool) -> Result<()> {
    let preset: Preset = preset::load_file_or_shipped(path)?;
    let mut sim = Simulation::new(&preset).with_context(|| format!("{}", path.display()))?;
    if !step_water {
        sim.skip_unread_water();
    }
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let c = cancel.clone();
        // Ctrl-C stops the run cleanly; failing to install the handler only loses that nicety.
        let _ = ctrlc::set_handler(move || c.store(true, Ordering::SeqCst));
    }
    let mut writer = match csv {
        Some(p) => {
            let f =
                std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?;
            let mut w = CsvWriter::new(std::io::BufWriter::new(f), &sim)?;
            w.start(&StepSample {
                time: 0.0,
                state: *sim.state(),
                angular_velocity: sim.angular_velocity(),
                in_contact: sim.in_contact(),
                wetted_area: 0.0,
                force: glam::DVec3::ZERO,
            })?;
            Some(w)
        }
        None => None,
    };
    let started = Instant::now();
    let (mut last_report, mut last_t) = (started, sim.time());
    let mut io_error: Option<std::io::Error> = None;
    while !sim.is_finished() && !cancel.load(Ordering::SeqCst) {
        // A costly tick (finding S1) yields between steps for the report and for Ctrl-C; the
        // next call resumes it, so the run is the same.
        let due = |_| cancel.load(Ordering::SeqCst) || last_report.elapsed().as_secs_f64() > 1.0;
        sim.tick_until(
            &mut |s| {
                if let Some(w) = writer.as_mut() {
                    if io_error.is_none() {
                        if let Err(e) = w.step(s) {
                            io_error = Some(e);
                        }
                    }
                }
            },
            &due,
        );
        if let Some(e) = io_error.take() {
            return Err(e).context("writing the CSV");
        }
        let since = last_report.elapsed().as_secs_f64();
        if since > 1.0 {
            let rate = (sim.time() - last_t) / since;
            last_report = Instant::now();
            last_t = sim.time();
            eprintln!(
                "t = {:.6} s simulated, {} skips so far ({:.1} s elapsed; {})",
                sim.time(),
                sim.skips(),
                started.elapsed().as_secs_f64(),
                time_left(preset.physics.max_time - sim.time(), rate)
            );
        }
    }
    if let Some(w) = writer {
        w.finish().context("writing the CSV")?;
    }
    if cancel.load(Ordering::SeqCst) {
        eprintln!("stoneskip: interrupted at t = {:.3} s", sim.time());
    }
    // The run's speed, on stderr so that stdout stays the same bits run after run.
    eprintln!(
        "{}",
        speed_line(sim.time(), started.elapsed().as_secs_f64())
    );
    let summary = sim.summary();
    if json {
        println!("{}", json_summary(&summary)?);
    } else {
        print!("{}", text_summary(&summary));
    }
    Ok(())
}

/// "simulated T s in W s of wall time (R× real time)": how fast a headless run went (the stone's
/// construction not included; real time is the simulated time over the wall time).
fn speed_line(simulated: f64, wall: f64) -> String {
    let rate = if wall > 0.0 {
        format!("{:.0}× real time", simulated / wall)
    } else {
        "too fast to time".into()
    };
    format!("simulated {simulated:.3} s in {wall:.3} s of wall time ({rate})")
}

#[cfg(test)]
mod tests {
    use super::{speed_line, time_left};

    #[test]
    fn the_speed_line_is_simulated_over_wall_time() {
        assert_eq!(
            speed_line(6.57, 0.0438),
            "simulated 6.570 s in 0.044 s of wall time (150× real time)"
        );
        assert!(speed_line(1.0, 0.0).ends_with("(too fast to time)"));
    }

    #[test]
    fn the_time_left_is_the_remaining_time_over_the_rate() {
        // 0.1 s left at 10⁻³ simulated s per s: 100 s.
        assert!(time_left(0.1, 1e-3).starts_with("at most ~100 s left"));
        assert!(time_left(1.0, 1e-3).starts_with("at most ~17 min left"));
        assert!(time_left(20.0, 1e-3).starts_with("at most ~5.6 h left"));
        assert!(time_left(20.0, 1e-5).starts_with("at most ~23 days left"));
        assert!(time_left(-1.0, 1.0).starts_with("at most ~0 s left"));
        assert!(time_left(1.0, 0.0).starts_with("no estimate"));
        assert!(time_left(1.0, f64::NAN).starts_with("no estimate"));
    }
}
