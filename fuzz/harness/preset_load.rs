//! Fuzz harness (a): preset text → load. Never a panic; every error is one line that names the
//! file and a line inside the text (and the field, for a value out of range or an unknown
//! field); every preset that loads is valid and survives a save → load round trip unchanged.

use std::path::Path;

use stoneskip_physics::preset::{self, PresetError};

/// Runs the target on one input; panics on a finding.
pub fn run(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let path = Path::new("fuzz.ron");
    let lines = text.lines().count().max(1) + 1;
    match preset::parse(text, path) {
        Ok(p) => {
            assert!(p.validate().is_ok(), "a loaded preset is valid");
            let saved = preset::to_ron_string(&p).expect("a valid preset serialises");
            let back = preset::parse(&saved, path).expect("a saved preset loads");
            assert_eq!(back, p, "round trip:\n{saved}");
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("fuzz.ron:"), "names the file: {msg}");
            assert!(!msg.contains('\n'), "one line: {msg}");
            match &e {
                PresetError::Syntax { line, .. } => {
                    assert!((1..=lines).contains(line), "line {line} of {lines}: {msg}");
                }
                PresetError::Invalid { line, error, .. } => {
                    assert!((1..=lines).contains(line), "line {line} of {lines}: {msg}");
                    assert!(!error.field.is_empty(), "names the field: {msg}");
                    assert!(msg.contains(&error.field), "names the field: {msg}");
                }
                PresetError::Read { .. } | PresetError::Write { .. } => {
                    panic!("parsing text cannot fail to read or write: {msg}")
                }
            }
        }
    }
}
