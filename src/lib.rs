//! stoneskip: a physically based stone-skipping simulator.
pub mod sim;
