//! The simulation controls (throw, pause, step, reset, replay, slow motion) and the camera
//! controls, in the top bar.

use egui::{RichText, Slider, SliderClamping, Ui};

use super::{Action, Phase, SimControls, ViewRequest, ViewSettings};

/// Throw (Space), Pause (P), Step (S), Reset (R), Replay; slow motion; the run's state.
pub fn simulation_ui(ui: &mut Ui, c: &mut SimControls, actions: &mut Vec<Action>) {
    let can_throw = c.invalid.is_none();
    if ui
        .add_enabled(
            can_throw,
            egui::Button::new(RichText::new("Throw").strong()),
        )
        .on_hover_text("Space: a new throw from the settings")
        .clicked()
    {
        actions.push(Action::Throw);
    }
    let pause_label = if c.phase == Phase::Paused {
        "Resume"
    } else {
        "Pause"
    };
    if ui
        .add_enabled(c.phase != Phase::Ready, egui::Button::new(pause_label))
        .on_hover_text("P")
        .clicked()
    {
        actions.push(Action::TogglePause);
    }
    if ui
        .add_enabled(
            can_throw || c.phase != Phase::Ready,
            egui::Button::new("Step"),
        )
        .on_hover_text("S: exactly one tick")
        .clicked()
    {
        actions.push(Action::Step);
    }
    if ui
        .add_enabled(can_throw, egui::Button::new("Reset"))
        .on_hover_text("R: back to the launch point with the current settings")
        .clicked()
    {
        actions.push(Action::Reset);
    }
    if ui
        .add_enabled(c.can_replay, egui::Button::new("Replay"))
        .on_hover_text("The last throw again, bit for bit")
        .clicked()
    {
        actions.push(Action::Replay);
    }
    ui.separator();
    let label = ui
        .label("Playback")
        .on_hover_text("Playback: simulated seconds per real second (below 1: slow motion)");
    ui.add(
        Slider::new(&mut c.speed, 0.01..=4.0)
            .update_while_editing(false)
            .clamping(SliderClamping::Always)
            .logarithmic(true)
            .custom_parser(super::parse_finite)
            .custom_formatter(|v, _| format!("{v:.2}×")),
    )
    .labelled_by(label.id);
    for fast in [2.0, 4.0] {
        if ui
            .selectable_label((c.speed - fast).abs() < 1e-9, format!("{fast:.0}×"))
            .on_hover_text("Faster than real time (results are unchanged: the same ticks run)")
            .clicked()
        {
            c.speed = fast;
        }
    }
    ui.separator();
    let state = match (c.phase, &c.outcome) {
        (Phase::Ready, _) => "ready".to_owned(),
        (_, Some(o)) if c.phase == Phase::Paused => format!("{o}, paused"),
        (_, Some(o)) if c.resting => format!("{o} (at rest)"),
        (_, Some(o)) => o.clone(),
        (Phase::Running, None) => "running".to_owned(),
        (Phase::Paused, None) => "paused".to_owned(),
    };
    ui.monospace(format!("t = {:7.3} s  {state}", c.time));
    if let (Some(n), true) = (c.replaying, c.phase != Phase::Ready) {
        ui.label(
            RichText::new(format!(
                "replay ({n} live physics change{})",
                if n == 1 { "" } else { "s" }
            ))
            .color(egui::Color32::from_rgb(150, 200, 255)),
        );
    }
}

/// The physics running behind in words: `real_per_sim` real seconds per simulated second
/// (measured over the last second), at the playback `speed` asked for.
pub fn behind_words(real_per_sim: f64, speed: f64) -> String {
    if !real_per_sim.is_finite() {
        return "physics running behind: no simulated time advanced in the last second".to_owned();
    }
    if real_per_sim >= 1.0 {
        let n = if real_per_sim >= 10.0 {
            format!("{real_per_sim:.0}")
        } else {
            format!("{real_per_sim:.1}")
        };
        return format!("physics running behind: {n}× slower than real time");
    }
    format!(
        "physics running behind: {:.1}× real time of the {speed:.1}× asked",
        1.0 / real_per_sim.max(1e-9)
    )
}

/// The run's passing notices (running behind, changes waiting, why the settings are refused),
/// as (text, is an error) lines: the app draws them over the 3D view, so they never move the
/// layout.
pub fn notices(c: &SimControls) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    if let Some(r) = c.behind {
        out.push((
            format!(
                "{} (the playback is {:.1} s behind the clock; every step is still computed, so \
                 results are unchanged)",
                behind_words(r, c.speed),
                c.dropped_total
            ),
            false,
        ));
    } else if c.dropping_now {
        out.push((
            format!(
                "running behind: the playback is {:.1} s behind the clock (every step is still \
                 computed, so results are unchanged)",
                c.dropped_total
            ),
            false,
        ));
    }
    if c.pending_changes {
        out.push(("changes apply on the next throw / reset".to_owned(), false));
    }
    if let Some(why) = &c.invalid {
        out.push((format!("invalid: {why}"), true));
    }
    out
}

/// Camera: behind, side (with its exaggeration), follow, top, frame all; which panels show;
/// screenshots. `current` is the camera now (`None`: where the user moved it).
pub fn view_ui(
    ui: &mut Ui,
    view: &mut ViewSettings,
    current: Option<ViewRequest>,
    exaggeration: f32,
    actions: &mut Vec<Action>,
) {
    ui.label("View");
    for (req, name, tip) in [
        (ViewRequest::Default, "Behind", "1: behind and above the launch point, looking along the throw"),
        (ViewRequest::Follow, "Follow", "2 or F: a chase camera close behind the stone (the default while a throw runs)"),
        (ViewRequest::Side, "Side", "3: from the side, the whole trajectory with the waterline and skip ticks (the paper's Fig. 13), heights exaggerated"),
        (ViewRequest::Top, "Top", "4: from above"),
    ] {
        if ui
            .selectable_label(current == Some(req), name)
            .on_hover_text(tip)
            .clicked()
        {
            actions.push(Action::View(req));
        }
    }
    if current == Some(ViewRequest::Side) {
        let mut k = exaggeration;
        egui::ComboBox::from_id_salt("exaggeration")
            .width(56.0)
            .selected_text(format!("{k:.0}× z"))
            .show_ui(ui, |ui| {
                for e in [1.0, 5.0, 10.0, 20.0] {
                    ui.selectable_value(&mut k, e, format!("{e:.0}×"));
                }
            })
            .response
            .accessible_name("Vertical exaggeration")
            .on_hover_text("Vertical exaggeration of the side view (E cycles)");
        if k != exaggeration {
            actions.push(Action::Exaggerate(k));
        }
    }
    if ui
        .button("Frame all")
        .on_hover_text("5 or double-click: fit the trajectory in view")
        .clicked()
    {
        actions.push(Action::View(ViewRequest::FrameAll));
    }
    ui.separator();
    ui.toggle_value(&mut view.show_settings, "Settings");
    ui.toggle_value(&mut view.show_readouts, "Readouts");
    if ui
        .button("Screenshot")
        .on_hover_text("Save the 3D view as a PNG (without the panels; the Export panel saves the whole window)")
        .clicked()
    {
        actions.push(Action::Screenshot { panels: false });
    }
}
