//! stoneskip-physics: the simulation of a thrown stone and the water it meets, and the preset
//! format that states a throw. It knows no frames, windows or wall-clock time, and depends on
//! glam, serde, thiserror, rayon and ron only (the crate boundary proves it): the desktop app, the
//! command line and the studies build on it.
//!
//! - [`sim`]: the stone (a triangle mesh of revolution), the per-face water forces, the
//!   integrators, the wetted-extent memory, the column-and-pipe water, the run and its summary
//!   (Do, Ra, Kim & Ryu 2005; O'Brien & Hodgins 1995; see each module);
//! - [`preset`]: RON presets (load with file:line:col and the field, atomic save) and the shipped
//!   presets compiled in.

#![warn(missing_docs)]

pub mod preset;
pub mod sim;
