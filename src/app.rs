//! The desktop app (placeholder until the app lands).
use std::path::PathBuf;

pub fn run_app(_preset: Option<PathBuf>, _frames: Option<u64>) -> anyhow::Result<()> {
    anyhow::bail!("the desktop app is not built yet")
}
