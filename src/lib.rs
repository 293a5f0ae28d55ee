//! stoneskip: a physically based stone-skipping simulator.
//!
//! The product: the desktop app (`app`, `ui`) and the command line's formats (`report`), over the
//! workspace's crates: the physics (`sim`, `preset`: stoneskip-physics), the renderer (`render`:
//! stoneskip-render), the 2D reference (`reference`) and the studies (`study`: stoneskip-lab).
//! Imports run one way: `app` → `ui`, `render` → `sim`.
//!
//! Features: `app` (default) builds the desktop app, the renderer and the UI, and turns on
//! `charts`, the studies' PNG charts; `lab` (default) the studies. With `--no-default-features`
//! the crate is the physics, the file formats and the headless `simulate`, and needs none of the
//! graphics crates.

#[cfg(feature = "app")]
pub mod app;
/// The renderer lives in the `stoneskip-render` crate (wgpu; behind the `app` feature).
#[cfg(feature = "app")]
pub use stoneskip_render as render;
pub mod report;
pub mod sweep;
#[cfg(feature = "app")]
pub mod ui;

/// The physics and the preset format live in the `stoneskip-physics` crate, which draws nothing;
/// they keep their paths here (`stoneskip::sim`, `stoneskip::preset`).
pub use stoneskip_physics::{preset, sim};

/// Bocquet's 2D flat plate, the yardstick of the 3D solver: a crate of its own (no ties to the
/// physics).
pub use stoneskip_reference as reference;

/// The studies live in the `stoneskip-lab` crate (the `lab` feature, on by default);
/// `stoneskip study` reaches them here.
#[cfg(feature = "lab")]
pub use stoneskip_lab::study;
