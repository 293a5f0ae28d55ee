//! The physics of stoneskip: a stone (a triangle mesh of revolution) thrown at water, per-triangle
//! hydrodynamic forces in contact (paper §3.2, eqs. 11–29), time stepping (eqs. 30–38 and better
//! schemes), and the O'Brien–Hodgins column-and-pipe water (paper §3.3, eqs. 39–41).
//!
//! Depends on glam, serde, thiserror and rayon only; knows nothing of frames, windows or clocks.

pub mod params;
pub mod reference;
pub mod water;
