//! Rendering (placeholder until the renderer lands).
use std::path::Path;

use crate::sim::params::Preset;

pub fn render_to_png(_preset: &Preset, _out: &Path, _w: u32, _h: u32, _t: f64) -> anyhow::Result<()> {
    anyhow::bail!("the renderer is not built yet")
}
