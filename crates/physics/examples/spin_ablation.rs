//! What takes the skips at high spin? The shipped default throw's spin sweep (the fidelity study's
//! five launch heights ±1 mm, median and range of skips) with the shipped model and without friction
//! (C_f = 0). (Savitsky's planing centre, a third variant here before, is retired:
//! docs/studies/retired.md.)
//! A diagnosis, not a model: friction at C_f = 0 is not physical (issue 11, session 7's note).
//!
//! `cargo run --release -p stoneskip-physics --example spin_ablation` (about 4 minutes on two cores)

use std::f64::consts::TAU;
use std::path::Path;

use anyhow::Result;
use rayon::prelude::*;

const REVS: [f64; 10] = [0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 60.0, 80.0, 150.0];
const HEIGHTS: [f64; 5] = [0.0, -1e-3, -5e-4, 5e-4, 1e-3];

fn main() -> Result<()> {
    let p = stoneskip_physics::preset::load(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/presets/default.ron"
    )))?;
    let variants: [(&str, Option<f64>); 2] = [("shipped", None), ("C_f = 0", Some(0.0))];
    let jobs: Vec<(usize, usize, f64)> = (0..variants.len())
        .flat_map(|v| (0..REVS.len()).flat_map(move |r| HEIGHTS.map(|dz| (v, r, dz))))
        .collect();
    let runs = jobs
        .par_iter()
        .map(|&(v, r, dz)| {
            let mut q = p.clone();
            let (_, cf) = variants[v];
            if cf.is_some() {
                q.physics.friction_coefficient = cf;
            }
            q.launch.spin = REVS[r] * TAU;
            q.launch.position[2] += dz;
            Ok((v, r, stoneskip_physics::sim::simulate(&q)?.skips))
        })
        .collect::<Result<Vec<_>>>()?;
    println!(
        "| model | {} |",
        REVS.map(|r| format!("{r} rev/s")).join(" | ")
    );
    println!("|---|{}", "---|".repeat(REVS.len()));
    for (v, (name, ..)) in variants.iter().enumerate() {
        let cells: Vec<String> = (0..REVS.len())
            .map(|r| {
                let mut k: Vec<usize> = runs
                    .iter()
                    .filter(|o| o.0 == v && o.1 == r)
                    .map(|o| o.2)
                    .collect();
                k.sort_unstable();
                format!("{} ({}–{})", k[k.len() / 2], k[0], k[k.len() - 1])
            })
            .collect();
        println!("| {name} | {} |", cells.join(" | "));
    }
    Ok(())
}
