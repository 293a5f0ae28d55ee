//! stoneskip-lab: the studies. Each is compute (`mod.rs`) → results → report (`report.rs`): CSV,
//! Markdown and, with the `charts` feature, PNG charts (plotters). They measure the physics crate
//! (speed against accuracy, stability, the magic angle, whole throws) and are reached from the
//! command line as `stoneskip study NAME`; nothing in the app depends on them.

pub mod study;
