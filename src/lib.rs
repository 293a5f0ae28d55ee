//! stoneskip: a physically based stone-skipping simulator; the product.
//!
//! The desktop app (`app`, `ui`) and the command line's formats and sweeps (`report`, `sweep`),
//! over the workspace's crates, which each file names itself: the physics and the preset format
//! (`stoneskip_physics`), the renderer (`stoneskip_render`), the 2D reference
//! (`stoneskip_reference`) and the studies (`stoneskip_lab`). Imports run one way: `app` → `ui`,
//! both onto the crates.
//!
//! Features: `app` (default) builds the desktop app, the renderer and the UI; `lab` (default) the
//! studies, `charts` (default) their PNG charts. With `--no-default-features` the crate is the
//! file formats and the headless `simulate` and `sweep`, and needs none of the graphics crates.

#[cfg(feature = "app")]
pub mod app;
pub mod report;
pub mod sweep;
#[cfg(feature = "app")]
pub mod ui;
