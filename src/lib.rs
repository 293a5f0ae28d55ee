//! stoneskip: a physically based stone-skipping simulator.
//!
//! Layers (imports run one way): `app` → `ui`, `render` → `sim`. `sim` is the physics and knows
//! nothing of frames or windows; `preset` and `report` are its file formats; `study` runs the
//! speed-versus-accuracy studies.

pub mod app;
pub mod preset;
pub mod render;
pub mod report;
pub mod sim;
pub mod study;
pub mod ui;
