//! The desktop app under a display: opens the window, throws (`STONESKIP_AUTOTHROW=1`), renders a
//! few frames and exits 0. Needs a display — run it as `xvfb-run -a cargo test --test app_smoke`;
//! without one it says so and passes (the picture tests in `render.rs` cover the renderer headless).

use std::process::Command;

#[test]
fn gui_renders_frames_and_exits_cleanly() {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        eprintln!("SKIPPED: no display; run `xvfb-run -a cargo test --test app_smoke`");
        return;
    }
    let out = Command::new(env!("CARGO_BIN_EXE_stoneskip"))
        .args(["gui", "--frames", "30"])
        .env("STONESKIP_AUTOTHROW", "1")
        .env("STONESKIP_FPS_REPORT", "1")
        .output()
        .expect("the stoneskip binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stoneskip gui failed: {stderr}");
    assert!(stderr.contains("30 frames"), "no frame report: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_broken_preset_is_refused_with_its_location() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("broken.ron");
    std::fs::write(&path, "(\n    version: 1,\n    stone: (mass: -1.0),\n)\n").expect("write");
    // Loading fails before any window opens, with file:line and the field.
    let out = Command::new(env!("CARGO_BIN_EXE_stoneskip"))
        .args(["gui", "--frames", "1", "--preset"])
        .arg(&path)
        .output()
        .expect("the stoneskip binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("broken.ron:3"), "{stderr}");
    assert!(stderr.contains("stone.mass"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
