//! Charts the app soak's CSV (`STONESKIP_SOAK`, see `src/app/soak.rs`): resident memory and frame
//! time against throw number, and checks the memory growth bound of docs/reliability.md.
//!
//! `cargo run --release -p stoneskip-lab --features charts --example soak_chart -- docs/reliability/soak.csv docs/reliability/soak.png`
//!
//! The bound: the presets come round in cycles of N throws (N shipped presets); the largest resident
//! memory over the last whole cycle may exceed the largest over the cycle holding throw 50 by at
//! most [`GROWTH_BOUND_MB`]. Exit code 1 when it does not hold.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{anyhow, bail, Context as _, Result};
use stoneskip_lab::study::plot::{draw, Chart, Legend, Mark, Panel, RefLine, Series};
use stoneskip_lab::study::style::{colors, Rgb};

/// Most growth of resident memory (MB) allowed from the cycle of throw 50 to the last cycle.
const GROWTH_BOUND_MB: f64 = 32.0;

/// One colour for each of the nine shipped presets.
const COLORS: [Rgb; 9] = [
    colors::BLUE,
    colors::RED,
    colors::GREEN,
    colors::ORANGE,
    colors::PURPLE,
    colors::SKY,
    colors::GREY,
    colors::BLACK,
    colors::YELLOW,
];

struct Row {
    throw: f64,
    preset: String,
    rss: f64,
    median: f64,
    max: f64,
}

fn read(path: &PathBuf) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() < 6 {
            bail!("{}:{}: expected at least 6 fields", path.display(), i + 1);
        }
        let num = |k: usize| -> Result<f64> {
            f[k].parse::<f64>()
                .map_err(|e| anyhow!("{}:{}: field {}: {e}", path.display(), i + 1, k + 1))
        };
        rows.push(Row {
            throw: num(0)?,
            preset: f[1].to_owned(),
            rss: num(2)?,
            median: num(4)?,
            max: num(5)?,
        });
    }
    if rows.is_empty() {
        bail!("{}: no rows", path.display());
    }
    Ok(rows)
}

fn main() -> Result<()> {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let [csv, png] = args.as_slice() else {
        bail!("usage: soak_chart SOAK.csv OUT.png");
    };
    let rows = read(csv)?;
    let cycle = rows
        .iter()
        .map(|r| r.preset.as_str())
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    let cycle_max = |c: usize| {
        rows.iter()
            .skip(c * cycle)
            .take(cycle)
            .map(|r| r.rss)
            .fold(f64::NAN, f64::max)
    };
    let whole = rows.len() / cycle;
    let ref_cycle = 49 / cycle;
    let verdict = if whole > ref_cycle + 1 {
        let (a, b) = (cycle_max(ref_cycle), cycle_max(whole - 1));
        let held = b - a <= GROWTH_BOUND_MB;
        println!(
            "{} throws, cycles of {cycle}: largest resident {a:.1} MB over throws {}–{}, {b:.1} MB over throws {}–{} (the last whole cycle): growth {:+.1} MB, bound {GROWTH_BOUND_MB} MB: {}",
            rows.len(),
            ref_cycle * cycle + 1,
            (ref_cycle + 1) * cycle,
            (whole - 1) * cycle + 1,
            whole * cycle,
            b - a,
            if held { "held" } else { "NOT held" }
        );
        Some((a, held))
    } else {
        println!("{} throws: too few for the growth check", rows.len());
        None
    };

    let mut rss = Chart::new(
        "Resident memory after each throw",
        "throw",
        "resident memory (MB)",
    )
    .legend(Legend::LowerRight)
    .series(Series::new(
        "VmRSS",
        rows.iter().map(|r| (r.throw, r.rss)).collect(),
        colors::BLUE,
        Mark::LinePoints,
    ));
    if let Some((a, _)) = verdict {
        rss = rss.line(RefLine::h(
            format!("bound: cycle of throw 50 + {GROWTH_BOUND_MB} MB"),
            a + GROWTH_BOUND_MB,
            colors::RED,
        ));
    }
    let mut by_preset: BTreeMap<&str, Vec<&Row>> = BTreeMap::new();
    for r in &rows {
        by_preset.entry(&r.preset).or_default().push(r);
    }
    let mut frames = Chart::new(
        "Frame time per throw: median (dots) and largest (line), by preset",
        "throw",
        "frame time (ms)",
    )
    .log_y()
    .legend(Legend::UpperRight);
    for (k, (name, rs)) in by_preset.iter().enumerate() {
        let color = COLORS[k % COLORS.len()];
        frames = frames
            .series(Series::new(
                *name,
                rs.iter().map(|r| (r.throw, r.median)).collect(),
                color,
                Mark::Points,
            ))
            .series(Series::new(
                "",
                rs.iter().map(|r| (r.throw, r.max)).collect(),
                color,
                Mark::Dashed,
            ));
    }
    draw(
        png,
        (1400, 1000),
        1,
        Some("App soak under Xvfb (lavapipe), 640×400 window"),
        &[Panel::Chart(rss), Panel::Chart(frames)],
    )
    .map_err(|e| anyhow!("drawing {}: {e}", png.display()))?;
    println!("chart in {}", png.display());
    if verdict.is_some_and(|(_, held)| !held) {
        std::process::exit(1);
    }
    Ok(())
}
