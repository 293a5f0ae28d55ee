//! What sets the step of a planing glide? The shipped default throw with the water off, at a tick
//! and tolerance given on the command line, every accepted step of the stone traced: its time,
//! length, whether in contact, the angle θ between the angular momentum and the symmetry axis, and
//! the speed; `locked` holds the attitude, `across` lets the contact steps cross the tick
//! (`physics.steps_across_ticks`) (docs/studies/kernel.md, "What sets the glide's step"; session 20).
//!
//! ```text
//! cargo run --release -p stoneskip-physics --example glide_steps -- 0.005 1e-6 [locked] [across] > steps.txt
//! ```
//!
//! Prints the run's summary to standard error and one line a step to standard output.

use std::fmt::Write as _;

use anyhow::Context;
use glam::DVec3;
use stoneskip_physics::sim::params::Rotation;
use stoneskip_physics::sim::Simulation;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let number = |i: usize, default: f64| -> anyhow::Result<f64> {
        args.get(i).map_or(Ok(default), |s| {
            s.parse()
                .with_context(|| format!("argument {i}: a number, got {s:?}"))
        })
    };
    let dt = number(1, 0.005)?;
    let tolerance = number(2, 1e-6)?;
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/presets/default.ron"
    ));
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    let mut preset = stoneskip_physics::preset::parse(&text, path)?;
    preset.water.enabled = false;
    preset.physics.dt = dt;
    preset.physics.tolerance = tolerance;
    let flag = |name: &str| args.iter().skip(3).any(|a| a == name);
    if flag("locked") {
        preset.physics.rotation = Rotation::Locked;
    }
    preset.physics.steps_across_ticks = flag("across");
    let mut sim = Simulation::new(&preset)?;
    let mut out = String::from("# time_s step_s in_contact theta_deg speed_m_s\n");
    let mut last = 0.0;
    while !sim.is_finished() {
        sim.tick_with(&mut |s| {
            let axis = s.state.orientation * DVec3::Z;
            let l = s.state.angular_momentum.normalize_or_zero();
            let theta = axis.dot(l).clamp(-1.0, 1.0).acos().to_degrees();
            let speed = s.state.velocity.length();
            // Writing to a String cannot fail.
            let _ = writeln!(
                out,
                "{} {} {} {theta} {speed}",
                s.time,
                s.time - last,
                u8::from(s.in_contact)
            );
            last = s.time;
        });
    }
    let (steps, evals) = sim.cost();
    eprintln!(
        "tick {dt} s, tolerance {tolerance}: {} skips, {:.6} m, {steps} steps, {evals} force \
         evaluations, {:.3} s simulated",
        sim.skips(),
        sim.distance(),
        sim.time()
    );
    print!("{out}");
    Ok(())
}
