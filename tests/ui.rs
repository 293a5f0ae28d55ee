//! The app's real panels driven as a person drives them, through egui's own test harness
//! (`egui_kittest`: AccessKit queries by label, clicks, typed text at a human pace), on the
//! app's model with no window or GPU. Issue 39.

use std::path::Path;

use egui::accesskit::Role;
use egui_kittest::kittest::{NodeT as _, Queryable};
use egui_kittest::Harness;
use stoneskip::app::{Model, Options};
use stoneskip::preset;

/// One frame at 60 fps; a person types about five keys a second, so 12 frames between keys.
const FRAMES_PER_KEY: usize = 12;

/// The app's model on a shipped preset, its user presets and exports in `dir`.
fn model(name: &str, dir: &Path) -> Model {
    let p = preset::shipped(name)
        .expect("a shipped name")
        .expect("a valid preset");
    let mut m = Model::new(p, None, Options::default()).expect("the model");
    m.library.user_dir = Some(dir.join("presets"));
    m.library.refresh();
    m.out_dir = dir.join("exports");
    m
}

/// The whole window's panels, as the app draws them, with the actions applied as the app
/// applies them; the physics advances by the harness's frame time.
fn harness(m: Model) -> Harness<'static, Model> {
    Harness::builder()
        .with_size([1280.0, 800.0])
        .with_max_steps(10_000)
        .build_ui_state(
            |ui, m: &mut Model| {
                let mut actions = Vec::new();
                m.build_ui(ui, "kittest", &mut actions);
                let dt = ui.input(|i| i.stable_dt).min(0.1) as f64;
                m.update(actions, dt);
            },
            m,
        )
}

fn pause(h: &mut Harness<'_, Model>, frames: usize) {
    for _ in 0..frames {
        h.step();
    }
}

/// The value box beside the slider labelled `label` (its row).
fn value_box_rect(h: &Harness<'_, Model>, label: &str) -> egui::Rect {
    let slider = h.get_by_role_and_label(Role::Slider, label).rect();
    let boxes = h.query_all_by_role(Role::SpinButton);
    boxes
        .map(|b| b.rect())
        .find(|r| (r.center().y - slider.center().y).abs() < 4.0 && r.left() >= slider.left())
        .unwrap_or_else(|| panic!("no value box beside the {label} slider"))
}

/// Clicks the value box of `label`'s slider, types `text` a key at a time with a person's
/// pauses, and presses Enter.
fn type_into(h: &mut Harness<'_, Model>, label: &str, text: &str) {
    let rect = value_box_rect(h, label);
    h.hover_at(rect.center());
    pause(h, 2);
    h.event(egui::Event::PointerButton {
        pos: rect.center(),
        button: egui::PointerButton::Primary,
        pressed: true,
        modifiers: Default::default(),
    });
    h.step();
    h.event(egui::Event::PointerButton {
        pos: rect.center(),
        button: egui::PointerButton::Primary,
        pressed: false,
        modifiers: Default::default(),
    });
    pause(h, FRAMES_PER_KEY);
    for c in text.chars() {
        h.event(egui::Event::Text(c.to_string()));
        pause(h, FRAMES_PER_KEY);
    }
    h.key_press(egui::Key::Enter);
    pause(h, FRAMES_PER_KEY);
}

#[test]
fn typed_values_stick_at_a_human_pace() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("default", dir.path()));
    h.run_ok();
    let view = h.state().view_mode;
    type_into(&mut h, "Tilt", "35");
    assert_eq!(h.state().edit.launch.attitude.tilt_deg, 35.0);
    type_into(&mut h, "Spin", "25");
    let spin = h.state().edit.launch.spin / std::f64::consts::TAU;
    assert!((spin - 25.0).abs() < 1e-9, "spin {spin} rev/s");
    assert_eq!(h.state().view_mode, view, "a typed digit moved the camera");
    type_into(&mut h, "Speed", "1000");
    let v = h.state().edit.launch.velocity;
    let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    assert!(
        (speed - 40.0).abs() < 1e-9,
        "1000 m/s typed gave {speed} m/s, not the 40 m/s maximum"
    );
}

/// The text beside the readout labelled `name` (its row of the Readouts grid).
fn readout(h: &Harness<'_, Model>, name: &str) -> String {
    let label = h
        .query_all_by_value(name)
        .find(|n| n.accesskit_node().role() == Role::Label)
        .unwrap_or_else(|| panic!("no readout {name}"))
        .rect();
    h.query_all_by_role(Role::Label)
        .filter(|n| {
            let r = n.rect();
            (r.center().y - label.center().y).abs() < 6.0 && r.left() > label.right()
        })
        .min_by(|a, b| a.rect().left().total_cmp(&b.rect().left()))
        .and_then(|n| n.accesskit_node().value())
        .unwrap_or_else(|| panic!("no value beside {name}"))
}

/// Frames until the throw has its outcome (at most `max`).
fn until_outcome(h: &mut Harness<'_, Model>, max: usize) {
    for _ in 0..max {
        h.step();
        if h.state().sim.outcome().is_some() {
            // The readouts refresh twice a second of wall time while the rings still spread.
            std::thread::sleep(std::time::Duration::from_millis(600));
            pause(h, 5);
            return;
        }
    }
    panic!("no outcome after {max} frames");
}

#[test]
fn the_throw_button_throws_and_the_readouts_show_the_headless_result() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("magic_angle", dir.path()));
    h.run_ok();
    assert_eq!(readout(&h, "Skips"), "0");
    h.get_by_role_and_label(Role::Button, "Throw").click();
    until_outcome(&mut h, 5_000);
    let p = preset::shipped("magic_angle")
        .expect("shipped")
        .expect("valid");
    let headless = stoneskip::sim::simulate(&p).expect("a run");
    assert_eq!(readout(&h, "Skips"), headless.skips.to_string());
    assert_eq!(
        readout(&h, "Distance"),
        format!("{:.2} m", headless.distance)
    );
}
