//! Studies (placeholder until the studies land).
use std::path::Path;

pub fn run_study(name: &str, _out: &Path, _quick: bool) -> anyhow::Result<()> {
    anyhow::bail!("unknown study `{name}`")
}
