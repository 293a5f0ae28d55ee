//! The app's real panels driven as a person drives them, through egui's own test harness
//! (`egui_kittest`: AccessKit queries by label, clicks, typed text at a human pace), on the
//! app's model with no window or GPU. Issue 39.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use egui::accesskit::Role;
use egui_kittest::kittest::{NodeT as _, Queryable};
use egui_kittest::Harness;
use stoneskip::app::{Model, Options};
use stoneskip::ui::Phase;
use stoneskip_physics::preset;

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
    harness_sized(m, [1280.0, 800.0])
}

/// [`harness`] in a window of `size` points (a tall one shows every row without scrolling).
fn harness_sized(m: Model, size: [f32; 2]) -> Harness<'static, Model> {
    harness_with(m, size, true)
}

/// The app at 1280 × 720 with `preset` loaded and the Experiments panel opened by its button.
fn experiments_open(preset: &str, dir: &Path) -> Harness<'static, Model> {
    let mut h = harness_sized(model(preset, dir), [1280.0, 720.0]);
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Experiments").click();
    h.run_ok();
    h
}

/// The harness; `check_names`: every settle (`run_ok`) also checks that each widget on screen
/// has an accessible name. The monkey leaves it off: it reaches states (rows that appear with
/// a switch) whose names `the_physics_panel_leads_with_what_a_class_changes` does not cover, and
/// its invariants are the ones it states.
fn harness_with(m: Model, size: [f32; 2], check_names: bool) -> Harness<'static, Model> {
    Harness::builder()
        .with_size(size)
        .with_accessibility_check(check_names)
        .with_max_steps(10_000)
        // As the app does: a glyph no font has (a typed "٣") is drawn as a box.
        .allow_missing_glyphs()
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

/// Steps until the background lake check of the edited throw has answered: its message (the
/// throw would leave the lake) moves the rows below it, so a row's place is read after it.
fn settle_lake_check(h: &mut Harness<'_, Model>) {
    let t0 = std::time::Instant::now();
    while h.state().lake_stale || h.state_mut().poll_lake_check() {
        assert!(
            t0.elapsed().as_secs() < 120,
            "the lake check did not answer"
        );
        h.step();
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    pause(h, 2);
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
    let headless = stoneskip_physics::sim::simulate(&p).expect("a run");
    assert_eq!(readout(&h, "Skips"), headless.skips.to_string());
    assert_eq!(
        readout(&h, "Distance"),
        format!("{:.2} m", headless.distance)
    );
}

/// splitmix64: the monkey's dice, reproducible from its printed seed.
struct Dice(u64);

impl Dice {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// What a monkey types: numbers at and past every edge, nothing, other scripts, a flood.
fn monkey_strings() -> Vec<String> {
    let mut s: Vec<String> = [
        "nan", "NaN", "-0", "1e308", "-1e308", "1e-320", "inf", "-inf", "", "٣", "٣٥", "35", "0",
        "-5", "0.5", "12", "abc", "1,5", "  7 ", "0x10", "°", "%", "-", ".", "1e", "😀",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    s.push("9".repeat(400));
    s.push("stone ".repeat(120));
    s
}

/// The widgets a person can press, as (role, rect).
fn pressables(h: &Harness<'_, Model>) -> Vec<(Role, egui::Rect)> {
    use Role::*;
    h.root()
        .query_all(egui_kittest::kittest::by().recursive(true))
        .filter_map(|n| {
            let role = n.accesskit_node().role();
            let wanted = matches!(
                role,
                Button
                    | Slider
                    | SpinButton
                    | CheckBox
                    | RadioButton
                    | TextInput
                    | DisclosureTriangle
                    | ComboBox
                    | Tab
                    | MenuItem
                    | Link
            );
            (wanted && !n.accesskit_node().is_disabled()).then(|| (role, n.rect()))
        })
        .filter(|(_, r)| r.is_positive() && r.max.x < 1280.0 && r.max.y < 800.0)
        .collect()
}

fn press(h: &mut Harness<'_, Model>, at: egui::Pos2, button: egui::PointerButton) {
    h.hover_at(at);
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button,
            pressed,
            modifiers: Default::default(),
        });
    }
}

/// A number a person can read that is not one: Rust's `NaN`, `inf` or `-inf` as a word. What a
/// person is typing into a focused field is theirs, not a readout (the field refuses it).
fn non_finite_words(h: &Harness<'_, Model>) -> Vec<String> {
    let nodes: Vec<_> = h
        .root()
        .query_all(egui_kittest::kittest::by().recursive(true))
        .collect();
    let typing: Vec<String> = nodes
        .iter()
        .filter(|n| n.is_focused())
        .filter_map(|n| n.accesskit_node().value())
        .collect();
    // While "nan" or "1e400" is being typed, the field and its spin button show the number being
    // typed (Rust spells it NaN or inf); it is refused when the typing ends.
    let typing_non_finite = typing
        .iter()
        .any(|t| t.trim().parse::<f64>().is_ok_and(|x| !x.is_finite()));
    nodes
        .iter()
        .filter_map(|n| {
            let a = n.accesskit_node();
            let v = a.value()?;
            let bad = v
                .split(|c: char| !c.is_alphanumeric())
                .any(|w| w == "NaN" || w == "inf");
            (bad && !typing_non_finite && !typing.contains(&v))
                .then(|| format!("{:?} {:?}: {v}", a.role(), a.label()))
        })
        .collect()
}

/// Every file under `dir` with its bytes.
fn snapshot(dir: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let p = e.path();
            if p.is_file() {
                out.push((p.clone(), std::fs::read(&p).expect("readable")));
            }
        }
    }
    out.sort();
    out
}

/// Runs the current throw (or a new one) to its end by whole ticks, at most `cap`; returns the
/// number of ticks and the run's summary as JSON with the pose's bits.
/// `None` when the monkey left settings a throw refuses (a lake past the column limit: the app
/// says so and throws nothing, so there is no throw to replay).
fn finish(m: &mut Model, cap: u64) -> Option<(u64, String)> {
    if m.phase == Phase::Ready {
        m.throw();
        if m.phase == Phase::Ready {
            return None;
        }
    }
    while !m.sim.is_finished() && m.ticks < cap {
        m.tick_once();
    }
    Some(fingerprint(m))
}

fn fingerprint(m: &Model) -> (u64, String) {
    let (p, q) = m.sim.world_from_stone();
    let bits: Vec<u64> = [p.x, p.y, p.z, q.x, q.y, q.z, q.w]
        .iter()
        .map(|x| x.to_bits())
        .collect();
    let json = serde_json::to_string(&m.sim.summary()).expect("a summary");
    (m.ticks, format!("{json} {bits:?}"))
}

/// Thousands of random clicks, drags, keys and typed strings on the real panels. Invariants: no
/// panic; no NaN or infinity in any readout; the preset files untouched unless saved (and every
/// saved one whole); Replay bit-exact afterwards. `STONESKIP_MONKEY_SEED` replays a seed,
/// `STONESKIP_MONKEY_ACTIONS` sets the count (10 000).
#[test]
fn a_monkey_cannot_break_the_app() {
    let seed = std::env::var("STONESKIP_MONKEY_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(1, |d| d.as_nanos() as u64)
        });
    let actions: usize = std::env::var("STONESKIP_MONKEY_ACTIONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000);
    println!("monkey seed {seed} ({actions} actions): STONESKIP_MONKEY_SEED={seed} replays it");
    let dir = tempfile::tempdir().expect("a temporary folder");
    let users = dir.path().join("presets");
    std::fs::create_dir_all(&users).expect("a presets folder");
    let lesson = users.join("lesson.ron");
    std::fs::write(&lesson, preset::SHIPPED[1].1).expect("a user preset");
    let mut m = model("default", dir.path());
    m.library.refresh();
    let shipped_dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/presets");
    let shipped_before = snapshot(&shipped_dir);
    let mut h = harness_with(m, [1280.0, 800.0], false);
    h.run_ok();
    let mut dice = Dice(seed);
    let strings = monkey_strings();
    let keys = {
        use egui::Key::*;
        [
            Space, P, S, R, Num1, Num2, Num3, Num4, Num5, E, F, F1, M, Escape, Enter, Tab,
            Backspace, ArrowUp, ArrowDown, ArrowLeft, ArrowRight, Delete, Home, End, A,
        ]
    };
    let mut targets = pressables(&h);
    let t0 = std::time::Instant::now();
    for i in 0..actions {
        if i % 20 == 0 {
            targets = pressables(&h);
        }
        let roll = dice.below(100);
        let anywhere = egui::pos2(dice.unit() * 1280.0, dice.unit() * 800.0);
        let widget = targets
            .get(dice.below(targets.len().max(1)))
            .map(|(_, r)| r.center());
        match roll {
            0..=44 => press(
                &mut h,
                widget.unwrap_or(anywhere),
                egui::PointerButton::Primary,
            ),
            45..=54 => press(&mut h, anywhere, egui::PointerButton::Primary),
            55..=57 => press(&mut h, anywhere, egui::PointerButton::Secondary),
            58..=72 => {
                h.event(egui::Event::Text(dice.pick(&strings).clone()));
                if dice.below(2) == 0 {
                    h.key_press(egui::Key::Enter);
                }
            }
            73..=87 => h.key_press(*dice.pick(&keys)),
            88..=94 => {
                let from = widget.unwrap_or(anywhere);
                let to = egui::pos2(dice.unit() * 1280.0, dice.unit() * 800.0);
                h.drag_at(from);
                h.hover_at(from.lerp(to, 0.5));
                h.drop_at(to);
            }
            _ => {
                h.hover_at(anywhere);
                h.event(egui::Event::MouseWheel {
                    unit: egui::MouseWheelUnit::Point,
                    delta: egui::vec2(0.0, (dice.unit() - 0.5) * 400.0),
                    phase: egui::TouchPhase::Move,
                    source: egui::MouseWheelSource::Wheel,
                    modifiers: Default::default(),
                });
            }
        }
        h.step();
        if i % 50 == 0 {
            let bad = non_finite_words(&h);
            assert!(bad.is_empty(), "seed {seed}, action {i}: {bad:?}");
            let (p, q) = h.state().sim.world_from_stone();
            assert!(
                p.is_finite() && q.is_finite(),
                "seed {seed}, action {i}: pose {p} {q}"
            );
        }
    }
    h.run_ok();
    println!(
        "monkey: {actions} actions in {:.0} s, {} throws",
        t0.elapsed().as_secs_f64(),
        h.state().throws
    );
    let bad = non_finite_words(&h);
    assert!(bad.is_empty(), "seed {seed}: {bad:?}");
    assert_eq!(
        snapshot(&shipped_dir),
        shipped_before,
        "seed {seed}: a shipped preset changed"
    );
    assert_eq!(
        std::fs::read(&lesson).expect("still there"),
        preset::SHIPPED[1].1.as_bytes(),
        "seed {seed}: a user's preset changed without a save over it"
    );
    for (path, _) in snapshot(&users) {
        assert!(
            path.extension().is_some_and(|e| e == "ron"),
            "seed {seed}: a stray file {} (a save left a temporary behind)",
            path.display()
        );
        preset::load(&path)
            .unwrap_or_else(|e| panic!("seed {seed}: a saved preset is broken: {e}"));
    }
    let mut m = h.into_state();
    let cap = 4_000;
    let Some(first) = finish(&mut m, cap) else {
        let why = m.status.as_ref().map(|s| s.message.text.clone());
        println!("seed {seed}: the last settings are refused ({why:?}), no throw to replay");
        return;
    };
    m.replay();
    while m.ticks < first.0 {
        m.tick_once();
    }
    assert_eq!(
        fingerprint(&m),
        first,
        "seed {seed}: Replay is not bit-exact"
    );
}

/// A gravity typed as "1e-320" (subnormal, inside the slider's 0–30 m/s²) once showed peak
/// lifts of `inf` g in the contacts table; every readout stays a number.
#[test]
fn a_subnormal_gravity_shows_no_infinity() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("magic_angle", dir.path()));
    h.run_ok();
    h.get_by_role_and_label(Role::DisclosureTriangle, "Physics")
        .click();
    h.run_ok();
    type_into(&mut h, "Gravity", "1e-320");
    assert!(h.state().edit.physics.gravity > 0.0 && h.state().edit.physics.gravity < 1e-300);
    // Without weight the stone flies straight: thrown down, so that it meets the water. The
    // lake check of the new gravity answers first: its message moves the launch rows down.
    settle_lake_check(&mut h);
    type_into(&mut h, "Elevation", "-10");
    h.get_by_role_and_label(Role::Button, "Throw").click();
    for _ in 0..600 {
        h.step();
    }
    assert!(
        !h.state().sim.contacts().is_empty(),
        "the stone touched the water"
    );
    let bad = non_finite_words(&h);
    assert!(bad.is_empty(), "{bad:?}");
}

/// The Experiments window: a tilt sweep of six throws runs in the background, its table fills,
/// Watch loads one throw and the view's run gives the same skips and distance as the sweep's;
/// the table exports as CSV.
#[test]
fn an_experiment_sweeps_tilt_and_watch_replays_a_point() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("magic_angle", dir.path()));
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Experiments").click();
    h.run_ok();
    type_into(&mut h, "Throws", "6");
    assert_eq!(h.state().experiment_draft.count, 6);
    h.get_by_role_and_label(Role::Button, "Run the experiment")
        .click();
    let t0 = std::time::Instant::now();
    while h.state().experiment.as_ref().is_none_or(|e| !e.finished()) {
        assert!(t0.elapsed().as_secs() < 120, "the sweep did not finish");
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.step();
    }
    pause(&mut h, 3);
    let watch: Vec<egui::Rect> = h
        .query_all_by_role_and_label(Role::Button, "Watch")
        .map(|n| n.rect())
        .collect();
    assert_eq!(watch.len(), 6, "one row per throw");
    let e = h.state().experiment.as_ref().expect("an experiment");
    let point = e.points[2].clone().expect("a result");
    let tilts: Vec<f64> = e
        .presets
        .iter()
        .map(|p| p.launch.attitude.tilt_deg)
        .collect();
    assert_eq!(tilts[0], 0.0);
    assert_eq!(tilts[5], 45.0);
    press(&mut h, watch[2].center(), egui::PointerButton::Primary);
    h.step();
    assert_eq!(h.state().edit.launch.attitude.tilt_deg, tilts[2]);
    until_outcome(&mut h, 5_000);
    let s = h.state().sim.summary();
    assert_eq!((s.skips, s.distance), (point.skips, point.distance));
    h.get_by_role_and_label(Role::Button, "Export CSV").click();
    h.run_ok();
    let csv: Vec<_> = std::fs::read_dir(dir.path().join("exports"))
        .expect("an exports folder")
        .flatten()
        .collect();
    assert_eq!(csv.len(), 1);
    let text = std::fs::read_to_string(csv[0].path()).expect("the CSV");
    assert_eq!(text.lines().filter(|l| !l.starts_with('#')).count(), 7);
}

/// Issue 39, finding 5: opening every settings section kept shrinking the 3D view (590 to
/// 430 px of a 1280 px window, the contacts table widest); the side panels now keep to their widths, so the view keeps at
/// least 1280 − 2 × 360 px.
#[test]
fn opening_the_panels_keeps_the_view_wide() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("default", dir.path()));
    h.run_ok();
    let before = h.state().view_rect.width();
    for section in ["Physics", "Water", "Wobble (angular velocity)", "Display"] {
        if let Some(n) = h.query_by_role_and_label(Role::DisclosureTriangle, section) {
            n.click();
            h.run_ok();
        }
    }
    // The contacts table fills during a throw.
    h.get_by_role_and_label(Role::Button, "Throw").click();
    until_outcome(&mut h, 5_000);
    h.run_ok();
    let after = h.state().view_rect.width();
    assert!(
        after >= 1280.0 - 2.0 * 360.0 - 1.0,
        "the view shrank from {before} to {after} px"
    );
}

/// Issue 39, finding 3: the Physics panel shows what a class changes (gravity, the water, the
/// water's lag, the air, rotation); the paper's laws and the numerical switches wait, collapsed,
/// under "Paper and validation".
#[test]
fn the_physics_panel_leads_with_what_a_class_changes() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    // Tall enough that no row is scrolled out of the accessibility tree.
    let mut h = harness_sized(model("default", dir.path()), [1280.0, 4000.0]);
    h.run_ok();
    h.get_by_role_and_label(Role::DisclosureTriangle, "Physics")
        .click();
    h.run_ok();
    assert!(h.query_by_role_and_label(Role::Slider, "Gravity").is_some());
    assert!(h
        .query_by_role_and_label(Role::Slider, "Water density")
        .is_some());
    assert!(h
        .query_by_role_and_label(Role::Slider, "Time step")
        .is_none());
    assert!(h
        .query_by_role_and_label(Role::ComboBox, "Force law")
        .is_none());
    h.get_by_role_and_label(Role::DisclosureTriangle, "Paper and validation")
        .click();
    h.run_ok();
    assert!(h
        .query_by_role_and_label(Role::ComboBox, "Force law")
        .is_some());
    assert!(h
        .query_by_role_and_label(Role::Slider, "Time step")
        .is_some());
    // Every section open in a window tall enough to show it all: `run_ok` checks that every
    // widget has an accessible name (the monkey found the Display panel's two sliders without).
    for section in ["Water", "Wobble (angular velocity)", "Display"] {
        h.get_by_role_and_label(Role::DisclosureTriangle, section)
            .click();
        h.run_ok();
    }
    assert!(h
        .query_by_role_and_label(Role::Slider, "Render scale")
        .is_some());
}

/// Issue 39, finding 6: on the old 4 m lake many "what if" throws ended "left the lake" (on a 6 m
/// one still a throw from 0.78 m and a 20 g stone, which curve 3 m aside). On the default lake
/// (40 × 12 m) the ends and middle of every sweep the Experiments panel suggests stay on the
/// water, so a class's first experiments are about skipping, not the lake's edge.
#[test]
fn what_if_throws_of_the_default_stay_on_its_lake() {
    use stoneskip::app::experiments::{Knob, Spec};
    let base = preset::shipped("default").expect("shipped").expect("valid");
    let mut left = Vec::new();
    for knob in Knob::ALL {
        let spec = Spec {
            count: 3,
            ..Spec::suggested(knob)
        };
        for x in spec.values() {
            let s = stoneskip_physics::sim::simulate(&knob.set(&base, x)).expect("a run");
            if s.outcome == Some(stoneskip_physics::sim::Outcome::LeftDomain) {
                left.push(format!("{} {x}", knob.name()));
            }
        }
    }
    assert!(left.is_empty(), "left the lake: {left:?}");
}

/// Issue 48, finding 4: a typed spin over the range says so beside the field, and the range
/// reaches 150 rev/s (Clanet's 65 and the model's high-spin limit above 100).
#[test]
fn a_clamped_value_says_so_and_spin_reaches_150() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    // Tall enough that a lake message above the launch rows keeps Spin in sight.
    let mut h = harness_sized(model("default", dir.path()), [1280.0, 2000.0]);
    h.run_ok();
    type_into(&mut h, "Spin", "150");
    settle_lake_check(&mut h);
    let spin = h.state().edit.launch.spin / std::f64::consts::TAU;
    assert!((spin - 150.0).abs() < 1e-9, "150 rev/s typed gave {spin}");
    assert!(
        h.query_by_label_contains("is over the most").is_none(),
        "a value inside the range got a clamp note"
    );
    // A value changed from the preset marks its row: "Spin •".
    type_into(&mut h, "Spin •", "400");
    settle_lake_check(&mut h);
    let spin = h.state().edit.launch.spin / std::f64::consts::TAU;
    assert!((spin - 150.0).abs() < 1e-9, "400 rev/s typed gave {spin}");
    assert!(
        h.query_by_label_contains("400 is over the most, 150")
            .is_some(),
        "no note that 400 rev/s was clamped to 150"
    );
    // The note goes once the field takes a value it keeps.
    type_into(&mut h, "Spin •", "30");
    assert!(h.query_by_label_contains("is over the most").is_none());
}

/// Issue 48, finding 3: one click sets a world's gravity and air together.
#[test]
fn a_world_sets_gravity_and_air_in_one_click() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness_sized(model("default", dir.path()), [1280.0, 2000.0]);
    h.run_ok();
    h.get_by_role_and_label(Role::DisclosureTriangle, "Physics")
        .click();
    h.run_ok();
    h.get_by_label("Moon").click();
    h.run_ok();
    let p = &h.state().edit.physics;
    assert_eq!((p.gravity, p.air), (1.62, None));
    assert!(p.max_time >= 120.0, "{} s", p.max_time);
    h.get_by_label("Mars").click();
    h.run_ok();
    let p = &h.state().edit.physics;
    assert_eq!(p.gravity, 3.71);
    assert_eq!(p.air.map(|a| a.density), Some(0.020));
    h.get_by_label("Earth").click();
    h.run_ok();
    let p = &h.state().edit.physics;
    assert_eq!(p.gravity, 9.81);
    assert_eq!(p.air.map(|a| a.density), Some(1.204));
}

/// Issue 48, finding 6: a click that lands just beside a field (on the panel, on no widget)
/// and then "45" typed leaves the camera alone; over the 3D view a digit still picks one.
#[test]
fn digits_typed_after_a_click_beside_a_field_keep_the_camera() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("default", dir.path()));
    h.run_ok();
    let view = h.state().view_mode;
    let field = value_box_rect(&h, "Tilt");
    let beside = egui::pos2(field.right() + 6.0, field.center().y);
    press(&mut h, beside, egui::PointerButton::Primary);
    pause(&mut h, 2);
    for (key, text) in [(egui::Key::Num4, "4"), (egui::Key::Num5, "5")] {
        h.key_press(key);
        h.event(egui::Event::Text(text.to_owned()));
        pause(&mut h, FRAMES_PER_KEY);
    }
    assert_eq!(
        h.state().view_mode,
        view,
        "a digit typed beside a field moved the camera"
    );
    // The view itself still answers to its keys.
    let centre = h.state().view_rect.center();
    press(&mut h, centre, egui::PointerButton::Primary);
    pause(&mut h, 2);
    h.key_press(egui::Key::Num3);
    pause(&mut h, 2);
    assert_eq!(h.state().view_mode, stoneskip_render::ViewMode::Side);
}

/// Issue 48, finding 2: the readouts say why a throw ended, from its last touch.
#[test]
fn the_outcome_readout_says_why_the_throw_ended() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("too_slow", dir.path()));
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Throw").click();
    until_outcome(&mut h, 5_000);
    let outcome = readout(&h, "Outcome");
    assert!(outcome.starts_with("too slow to skip"), "{outcome}");
    assert!(
        h.query_by_label_contains("Ending: too slow to skip")
            .is_some(),
        "the contacts table does not say why"
    );
}

/// Issue 48, finding 7: at 1280 × 720 the Experiments panel leaves the 3D view at least 60 % of
/// the window's height.
#[test]
fn experiments_leave_the_view_most_of_the_height() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = experiments_open("default", dir.path());
    assert!(h.state().show_experiments);
    // With results on its charts, as a class sees it.
    type_into(&mut h, "Throws", "3");
    h.get_by_role_and_label(Role::Button, "Run the experiment")
        .click();
    let t0 = std::time::Instant::now();
    while h.state().experiment.as_ref().is_none_or(|e| !e.finished()) {
        assert!(t0.elapsed().as_secs() < 120, "the sweep did not finish");
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.step();
    }
    pause(&mut h, 3);
    let view = h.state().view_rect.height();
    assert!(view >= 0.6 * 720.0, "the view is {view} px of 720");
}

/// Issue 48, finding 7: at 1280 × 720 the contacts table shows every column, tilt and bank at
/// landing included, inside the readouts panel: no sideways scroll to reach peak g. The throw
/// with the widest numbers: the default on the Moon without air (59 skips over 234 m).
#[test]
fn the_contacts_table_fits_its_panel() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut moon = model("default", dir.path());
    let mut p = moon.sim.preset().clone();
    stoneskip_physics::sim::world::World::Moon.apply(&mut p.physics);
    let mut m = Model::new(p, None, Options::default()).expect("the model");
    m.library = std::mem::take(&mut moon.library);
    m.out_dir = moon.out_dir.clone();
    let mut h = harness_sized(m, [1280.0, 720.0]);
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Throw").click();
    until_outcome(&mut h, 40_000);
    assert!(h.state().sim.contacts().len() >= 10);
    assert!(h.state().sim.distance() >= 100.0);
    pause(&mut h, 3);
    // The readouts panel's content runs from its headings' left edge to the window's.
    let panel_left = h
        .get_by_role_and_label(Role::DisclosureTriangle, "Contacts")
        .rect()
        .left();
    let panel_right = 1280.0;
    for name in ["#", "tilt", "bank", "g"] {
        let r = h.get_by_label(name).rect();
        assert!(
            r.left() >= panel_left && r.right() <= panel_right,
            "{name} at {r:?}, the panel spans {panel_left}..{panel_right}"
        );
    }
    // A row's numbers reach as far as its header: its last cell inside the panel too.
    let header = h.get_by_label("#").rect();
    let widest = h
        .query_all_by_label_contains("°")
        .map(|n| n.rect())
        .filter(|r| r.top() >= header.bottom() && r.top() < header.bottom() + 150.0)
        // The table's own clip: inside its scroll bar.
        .map(|r| r.right())
        .fold(0.0f32, f32::max);
    assert!(widest > header.right(), "no row of the table found");
    // The numbers stop short of the vertical scroll bar (59 rows scroll) at the panel's edge.
    assert!(
        widest <= panel_right - 12.0,
        "a cell ends at {widest}, under the scroll bar"
    );
    // Nor does any other text of the panel run past the window's edge (the outcome's words).
    for n in h.query_all_by_role(Role::Label) {
        let r = n.rect();
        if r.left() >= panel_left && r.top() < 720.0 {
            assert!(
                r.right() <= panel_right + 0.5,
                "{:?} ends at {}",
                n.accesskit_node().value(),
                r.right()
            );
        }
    }
    assert!(widest <= panel_right, "a cell ends at {widest}");
}

/// The default throw with a heavier stone, `mass` kg: its landings tip it differently (issue 48,
/// finding 2: 0.16–0.28 kg give 3 / 1 / 15 / 1 / 1 / 11 / 10 skips).
fn default_with_mass(mass: f64, dir: &Path) -> Model {
    let mut m = model("default", dir);
    let mut p = m.sim.preset().clone();
    p.stone.mass = mass;
    let mut fresh = Model::new(p, None, Options::default()).expect("the model");
    fresh.library = std::mem::take(&mut m.library);
    fresh.out_dir = m.out_dir.clone();
    fresh
}

/// Issue 48: a throw that ends dug in nose-down shows it in the side view: the red glyph at the
/// touch it dug in at, and "dug in nose-down here" over it (what Watch on such a point shows).
#[test]
fn a_nose_down_ending_is_marked_in_the_side_view() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness_sized(default_with_mass(0.18, dir.path()), [1280.0, 720.0]);
    h.run_ok();
    h.state_mut().handle(stoneskip::ui::Action::View(
        stoneskip::ui::ViewRequest::Side,
    ));
    h.get_by_role_and_label(Role::Button, "Throw").click();
    until_outcome(&mut h, 20_000);
    let ending = h.state().sim.ending();
    let stoneskip_physics::sim::ending::Ending::NoseDown { touch, tilt } = ending else {
        panic!("the 0.18 kg throw ended {ending:?}, not nose-down");
    };
    assert!(tilt < 0.0);
    let label = h
        .query_by_label_contains("dug in nose-down here")
        .expect("no label over the touch it dug in at");
    let words = format!(
        "{:?} {:?}",
        label.accesskit_node().label(),
        label.accesskit_node().value()
    );
    assert!(words.contains(&format!("touch {touch}")), "{words}");
    // The label stands in the view, and the red glyph is drawn at that touch.
    let view = h.state().view_rect;
    assert!(view.contains(label.rect().center()), "{:?}", label.rect());
    let red = stoneskip_render::build::GLYPH_DUG_IN_COLOR;
    let scene = h.state().scene();
    let at = h.state().sim.contacts()[touch - 1];
    let glyph: Vec<_> = scene.lines.iter().filter(|l| l.color == red).collect();
    assert!(!glyph.is_empty(), "no red glyph");
    assert!(glyph
        .iter()
        .all(|l| (l.a.x - at.x as f32).abs() < 5.0 && l.a.z > 0.0));
}

/// Issue 48, finding 7: `paper` opens saying what it shows, not warning about its own designed
/// time step; the same step in a user's own preset (here paper with another mass) is warned of.
#[test]
fn a_shipped_preset_never_warns_about_its_own_design() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness(model("paper", dir.path()));
    h.run_ok();
    assert!(
        h.query_by_label_contains("is too long").is_none(),
        "paper warns: {:?}",
        h.state().warnings
    );
    assert!(
        h.query_by_label_contains("at its own 0.20 ms time step")
            .is_some(),
        "paper does not say what it shows"
    );
    type_into(&mut h, "Mass", "0.12");
    pause(&mut h, 3);
    assert!(
        h.query_by_label_contains("is too long for the Paper integrator")
            .is_some(),
        "a user's own preset at that step is not warned of: {:?}",
        h.state().warnings
    );
    assert!(h
        .query_by_label_contains("at its own 0.20 ms time step")
        .is_none());
}

/// Issue 48, finding 7: "The model in detail" opens each item with a plain sentence, the
/// sources after it, and spin first of what turns the stone.
#[test]
fn the_model_in_detail_opens_each_item_plainly() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = harness_sized(model("default", dir.path()), [1280.0, 2400.0]);
    h.run_ok();
    h.state_mut().show_about = true;
    h.run_ok();
    let top = |h: &Harness<'_, Model>, text: &str| h.get_by_label_contains(text).rect().top();
    let spin = top(&h, "Spin keeps the stone steady");
    let sources = top(&h, "[Tang et al. 2021; Clanet et al. 2004");
    assert!(spin < sources, "the sources come before the plain sentence");
    assert!(spin < top(&h, "The stone can be held at one angle"));
    assert!(spin < top(&h, "Spinning about its own middle"));
}

/// Waits (stepping the harness) until the experiment has finished.
fn until_experiment_done(h: &mut Harness<'_, Model>) {
    let t0 = std::time::Instant::now();
    while h.state().experiment.as_ref().is_none_or(|e| !e.finished()) {
        assert!(
            t0.elapsed().as_secs() < 300,
            "the experiment did not finish"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.step();
    }
    pause(h, 3);
}

/// Issue 48: a two-value map. "Map a second value" maps tilt against impact angle (Clanet's
/// diagram); every cell is thrown with both values, the first touch coming down at the cell's
/// impact angle; a click on a cell loads and watches that throw, as a dot does; the export has
/// both values as columns.
#[test]
fn a_map_of_tilt_and_impact_angle_runs_and_a_cell_watches_its_throw() {
    use stoneskip::app::experiments::Knob;
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = experiments_open("clanet_disc", dir.path());
    h.get_by_role_and_label(Role::CheckBox, "Map a second value")
        .click();
    h.run_ok();
    let second = h.state().experiment_second.expect("a second value");
    assert_eq!(
        (h.state().experiment_draft.knob, second.knob),
        (Knob::Tilt, Knob::ImpactAngle)
    );
    type_into(&mut h, "Throws", "3");
    type_into(&mut h, "Values", "4");
    h.get_by_role_and_label(Role::Button, "Run the experiment")
        .click();
    until_experiment_done(&mut h);
    let e = h.state().experiment.as_ref().expect("an experiment");
    assert_eq!(e.points.len(), 12, "3 tilts × 4 impact angles");
    let (xs, ys) = (e.plan().x_values(), e.plan().y_values());
    for (i, p) in e.presets.iter().enumerate() {
        assert_eq!(Knob::Tilt.get(p), xs[i / 4]);
        assert!((Knob::ImpactAngle.get(p) - ys[i % 4]).abs() < 1e-9);
    }
    // The view keeps most of the window with the map open.
    let view = h.state().view_rect.height();
    assert!(view >= 0.6 * 720.0, "the view is {view} px of 720");
    // Click the cell of the second tilt and the third impact angle.
    let t: egui_plot::PlotTransform = h
        .ctx
        .data(|d| d.get_temp(egui::Id::unique("experiment map transform")))
        .expect("the map was drawn");
    let at = t.position_from_point(&egui_plot::PlotPoint::new(xs[1], ys[2]));
    press(&mut h, at, egui::PointerButton::Primary);
    h.step();
    let i = 4 + 2;
    assert_eq!(h.state().experiment_chosen, Some(i));
    let edit = &h.state().edit;
    assert_eq!(Knob::Tilt.get(edit), xs[1]);
    assert!((Knob::ImpactAngle.get(edit) - ys[2]).abs() < 1e-9);
    let point = h.state().experiment.as_ref().unwrap().points[i]
        .clone()
        .expect("a result");
    until_outcome(&mut h, 5_000);
    let s = h.state().sim.summary();
    assert_eq!((s.skips, s.distance), (point.skips, point.distance));
    h.get_by_role_and_label(Role::Button, "Export CSV").click();
    h.run_ok();
    let csv = std::fs::read_dir(dir.path().join("exports"))
        .expect("an exports folder")
        .flatten()
        .next()
        .expect("a CSV");
    let text = std::fs::read_to_string(csv.path()).expect("the CSV");
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(rows.len(), 13, "{text}");
    assert!(
        rows[0].starts_with("tilt_deg,impact_angle_deg,skips"),
        "{text}"
    );
}

/// Issue 48: a 400-cell map (20 × 20) runs in the background, its results arriving while the
/// app draws, and Stop ends it early.
#[test]
fn a_400_cell_map_stops_when_asked() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = experiments_open("default", dir.path());
    h.get_by_role_and_label(Role::CheckBox, "Map a second value")
        .click();
    h.run_ok();
    type_into(&mut h, "Throws", "20");
    type_into(&mut h, "Values", "20");
    h.get_by_role_and_label(Role::Button, "Run the experiment")
        .click();
    pause(&mut h, 2);
    assert_eq!(h.state().experiment.as_ref().unwrap().points.len(), 400);
    h.get_by_role_and_label(Role::Button, "Stop").click();
    pause(&mut h, 2);
    let e = h.state().experiment.as_ref().unwrap();
    assert!(e.stopped());
    // The throws under way end at their next step; no new one starts.
    let t0 = std::time::Instant::now();
    let mut last = usize::MAX;
    while last != h.state().experiment.as_ref().unwrap().done() {
        last = h.state().experiment.as_ref().unwrap().done();
        assert!(t0.elapsed().as_secs() < 60);
        std::thread::sleep(std::time::Duration::from_millis(300));
        h.step();
    }
    assert!(last < 400, "{last} of 400 thrown after Stop");
    assert!(h
        .query_by_role_and_label(Role::Button, "Run the experiment")
        .is_some());
}

/// Issue 48, finding 2: the one-value charts show the stone's attitude at a landing beside
/// skips and distance (a selector: tilt or bank, first or last landing; the last, which
/// decided how a throw that sank ended, first), each throw's as its run recorded it.
#[test]
fn the_attitude_chart_shows_the_tilt_at_a_landing() {
    use stoneskip::app::experiments::{Attitude, Knob, Spec};
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut h = experiments_open("default", dir.path());
    h.state_mut().experiment_draft = Spec {
        knob: Knob::Mass,
        from: 0.16,
        to: 0.2,
        count: 3,
    };
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Run the experiment")
        .click();
    until_experiment_done(&mut h);
    h.get_by_role_and_label(Role::ComboBox, "Attitude").click();
    h.run_ok();
    h.get_by_label("Tilt at the first landing").click();
    h.run_ok();
    let choice: Option<Attitude> = h
        .ctx
        .data(|d| d.get_temp(egui::Id::unique("experiment attitude")));
    assert_eq!(choice, Some(Attitude::FirstTilt));
    let e = h.state().experiment.as_ref().expect("an experiment");
    for p in e.points.iter().flatten() {
        let s = stoneskip_physics::sim::simulate(&Knob::Mass.set(&e.base, p.value)).expect("a run");
        let first = s.contacts.first().expect("a touch").attitude_in[0];
        let last = s.contacts.last().expect("a touch").attitude_in[0];
        assert_eq!(Attitude::FirstTilt.of(p), Some(first));
        assert_eq!(Attitude::LastTilt.of(p), Some(last));
    }
}
