//! stoneskip: a physically based stone-skipping simulator.
//!
//! Layers (imports run one way): `app` → `ui`, `render` → `sim`. `sim` is the physics and knows
//! nothing of frames or windows; `preset` and `report` are its file formats; `study` runs the
//! speed-versus-accuracy studies.
//!
//! Features: `app` (default) builds the desktop app, the renderer and the UI, and turns on
//! `charts`, the studies' PNG charts. With `--no-default-features` the crate is the physics, the
//! file formats and the headless studies (CSV and Markdown), and needs none of the graphics crates.

#[cfg(feature = "app")]
pub mod app;
#[cfg(feature = "app")]
pub mod render;
pub mod report;
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
