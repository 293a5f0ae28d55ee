//! egui panels (placeholder).
