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
    ui.label("Speed")
        .on_hover_text("Slow motion: simulated seconds per real second");
    ui.add(
        Slider::new(&mut c.speed, 0.01..=1.0)
            .clamping(SliderClamping::Always)
            .logarithmic(true)
            .custom_formatter(|v, _| format!("{v:.2}×")),
    );
    ui.separator();
    let state = match (c.phase, c.outcome) {
        (Phase::Ready, _) => "ready".to_owned(),
        (_, Some(o)) if c.phase == Phase::Paused => format!("{o}, paused"),
        (_, Some(o)) => o.to_owned(),
        (Phase::Running, None) => "running".to_owned(),
        (Phase::Paused, None) => "paused".to_owned(),
    };
    ui.monospace(format!("t = {:7.3} s  {state}", c.time));
    if c.dropping_now {
        ui.label(
            RichText::new(format!("running behind: {:.2} s of simulated time skipped", c.dropped_total))
                .color(egui::Color32::from_rgb(255, 190, 80)),
        )
        .on_hover_text(
            "A slow frame may run only so many ticks; the rest of the time is dropped (shown in slower \
             motion), never squeezed into bigger steps: results are unchanged",
        );
    }
    if c.pending_changes {
        ui.label(
            RichText::new("changes apply on the next throw / reset")
                .color(egui::Color32::from_rgb(150, 200, 255)),
        );
    }
    if let Some(why) = &c.invalid {
        ui.label(
            RichText::new(format!("invalid: {why}")).color(egui::Color32::from_rgb(255, 110, 100)),
        );
    }
}

/// Camera: default view, side view, frame all, follow; which panels show.
pub fn view_ui(ui: &mut Ui, view: &mut ViewSettings, actions: &mut Vec<Action>) {
    ui.label("View");
    if ui
        .button("Behind")
        .on_hover_text("1: behind and above the launch point, looking along the throw")
        .clicked()
    {
        actions.push(Action::View(ViewRequest::Default));
    }
    if ui
        .button("Side")
        .on_hover_text("2: from the side, the whole trajectory (the paper's Fig. 13)")
        .clicked()
    {
        actions.push(Action::View(ViewRequest::Side));
    }
    if ui
        .button("Frame all")
        .on_hover_text("3: fit the trajectory in view")
        .clicked()
    {
        actions.push(Action::View(ViewRequest::FrameAll));
    }
    ui.toggle_value(&mut view.follow, "Follow")
        .on_hover_text("F: the camera follows the stone");
    ui.separator();
    ui.toggle_value(&mut view.show_settings, "Settings");
    ui.toggle_value(&mut view.show_readouts, "Readouts");
    if ui
        .button("Screenshot")
        .on_hover_text("Save a screenshot (PNG)")
        .clicked()
    {
        actions.push(Action::Screenshot);
    }
}
