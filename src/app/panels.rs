//! The app's panels on the model: the top bar, the settings and readouts panels, the 3D view's
//! input (orbit, pan, zoom, the throw gesture) and its overlays (score, side-view exaggeration,
//! status message, warnings, help, about). Plain egui: no window or GPU type here.

use std::time::Instant;

use egui::{Color32, RichText};
use glam::Vec2;

use super::edits::{launch_differences, section_differences, Difference};
use super::lake;
use super::model::{gesture_launch, Model};
use crate::ui::{self, Action, GhostRow, Phase, Section, SimControls, ViewRequest};
use stoneskip_physics::sim::params::Rotation;
use stoneskip_render::build::ghost_color;
use stoneskip_render::camera::{ViewMode, EXAGGERATIONS};

/// The side panels' widths (points): a wide table scrolls inside its panel rather than narrowing
/// the 3D view (issue 39: the contacts table took it from 635 to 433 px of a 1280 px window).
const PANEL_WIDTH: std::ops::RangeInclusive<f32> = 240.0..=360.0;

/// Pointer within this many points of the stone starts a throw gesture (before a throw).
pub const GESTURE_GRAB_RADIUS: f32 = 48.0;

/// The colour of a value that differs from the loaded preset, and of a warning.
const CHANGED: Color32 = Color32::from_rgb(255, 190, 90);
const WARN: Color32 = Color32::from_rgb(255, 150, 90);

/// Marks a panel's values that differ from the loaded preset (the preset's value on hover) and
/// offers to revert the panel.
fn changes_ui(
    ui: &mut egui::Ui,
    changed: &[Difference],
    section: Section,
    actions: &mut Vec<Action>,
) {
    if changed.is_empty() {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        let n = changed.len();
        let s = if n == 1 { "" } else { "s" };
        ui.colored_label(CHANGED, format!("• {n} value{s} changed from the preset"));
        if ui
            .small_button("Revert to preset")
            .on_hover_text("Put this panel back to the loaded preset's values")
            .clicked()
        {
            actions.push(Action::Revert(section));
        }
    });
    ui.horizontal_wrapped(|ui| {
        for d in changed {
            ui.label(
                RichText::new(format!("• {} {}", d.field, d.now))
                    .small()
                    .color(CHANGED),
            )
            .on_hover_text(format!("preset: {}", d.preset));
        }
    });
}

fn request_of(mode: ViewMode) -> Option<ViewRequest> {
    match mode {
        ViewMode::Behind => Some(ViewRequest::Default),
        ViewMode::Side => Some(ViewRequest::Side),
        ViewMode::Follow => Some(ViewRequest::Follow),
        ViewMode::Top => Some(ViewRequest::Top),
        ViewMode::Free => None,
    }
}

impl Model {
    /// All panels and the 3D view's input; pushes what the user asked for.
    pub fn build_ui(&mut self, ui: &mut egui::Ui, adapter: &str, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        // Where the last press landed decides who gets a letter or a digit: the 3D view (its
        // shortcuts) or the panel clicked last (a field beside which a click landed, the
        // Experiments panel), so typing "45" there never switches the camera.
        let (pressed, hover) = ctx.input(|i| {
            (
                i.pointer
                    .any_pressed()
                    .then(|| i.pointer.press_origin())
                    .flatten(),
                i.pointer.hover_pos(),
            )
        });
        if let Some(at) = pressed {
            self.keys_to_view = self.view_rect.contains(at);
        }
        let view_has_pointer = hover.is_some_and(|p| self.view_rect.contains(p));
        if !ctx.egui_wants_keyboard_input() {
            self.shortcuts_ui(&ctx, self.keys_to_view || view_has_pointer, actions);
        }
        self.refresh_shown();
        // The lake check runs the throw on flat water, in the background: once a drag has
        // ended, not every frame.
        if self.lake_stale && !ctx.input(|i| i.pointer.any_down()) {
            self.start_lake_check();
        }
        if self.poll_lake_check() {
            ctx.request_repaint_after(std::time::Duration::from_millis(50));
        }
        if self.status.as_ref().is_some_and(|s| s.expired()) {
            self.status = None;
            // The presets panel's copy of the message goes with it.
            self.library.message = None;
        }
        self.top_bar_ui(ui, actions);
        self.experiments_panel_ui(ui, actions);
        if self.view.show_settings {
            egui::Panel::left("settings")
                .default_size(330.0)
                .size_range(PANEL_WIDTH)
                .resizable(true)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| self.settings_ui(ui, actions));
                });
        }
        if self.view.show_readouts {
            egui::Panel::right("readouts")
                .default_size(330.0)
                .size_range(PANEL_WIDTH)
                .resizable(true)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical()
                        .show(ui, |ui| self.readouts_ui(ui, adapter, actions));
                });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            self.view_input_ui(ui, actions);
            self.view_overlay_ui(ui, actions);
        });
        self.windows_ui(&ctx);
    }

    /// The Experiments panel along the window's foot, the full width (drawn before the side
    /// panels), resizable.
    fn experiments_panel_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        if !self.show_experiments {
            return;
        }
        // Under a third of the window's height at first, so the 3D view keeps at least 60 % of
        // it (1280 × 720: the view 450 px of 720); drag the edge for more.
        let first = (0.3 * ui.available_height()).clamp(160.0, 260.0);
        egui::Panel::bottom("experiments")
            .resizable(true)
            .default_size(first)
            .size_range(160.0..=520.0)
            .show(ui, |ui| {
                super::experiment_panel::experiments_ui(
                    ui,
                    (&mut self.experiment_draft, &mut self.experiment_second),
                    self.experiment.as_ref(),
                    self.experiment_chosen,
                    &self.loaded.name,
                    actions,
                );
            });
    }

    /// The keyboard's shortcuts; the letters and digits only when `to_view` (the 3D view has the
    /// pointer or was pressed last), Space, F1, ? and Escape always.
    fn shortcuts_ui(&mut self, ctx: &egui::Context, to_view: bool, actions: &mut Vec<Action>) {
        use egui::Key;
        ctx.input(|i| {
            let global = [Key::Space, Key::F1, Key::Escape];
            let k = |key| (to_view || global.contains(&key)) && i.key_pressed(key);
            if k(Key::Space) && self.invalid.is_none() {
                actions.push(Action::Throw);
            }
            for (key, action) in [
                (Key::P, Action::TogglePause),
                (Key::S, Action::Step),
                (Key::R, Action::Reset),
                (Key::Num1, Action::View(ViewRequest::Default)),
                (Key::Num2, Action::View(ViewRequest::Follow)),
                (Key::F, Action::View(ViewRequest::Follow)),
                (Key::Num3, Action::View(ViewRequest::Side)),
                (Key::Num4, Action::View(ViewRequest::Top)),
                (Key::Num5, Action::View(ViewRequest::FrameAll)),
            ] {
                if k(key) {
                    actions.push(action);
                }
            }
            if k(Key::E) {
                let i = EXAGGERATIONS
                    .iter()
                    .position(|e| *e == self.exaggeration)
                    .map_or(0, |i| (i + 1) % EXAGGERATIONS.len());
                actions.push(Action::Exaggerate(EXAGGERATIONS[i]));
                if self.view_mode != ViewMode::Side {
                    actions.push(Action::View(ViewRequest::Side));
                }
            }
            let question = i
                .events
                .iter()
                .any(|e| matches!(e, egui::Event::Text(t) if t == "?"));
            if k(Key::F1) || question {
                self.show_help = !self.show_help;
            }
            if k(Key::M) {
                self.show_about = !self.show_about;
            }
            if k(Key::X) {
                self.show_experiments = !self.show_experiments;
            }
            if k(Key::Escape) {
                self.show_help = false;
                self.show_about = false;
                actions.push(Action::DismissMessage);
            }
        });
    }

    fn top_bar_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let mut controls = SimControls {
            phase: self.phase,
            speed: self.clock.speed(),
            time: self.shown.readouts.time,
            outcome: self.shown.outcome.clone(),
            resting: self.resting,
            replaying: self
                .replay_log
                .is_replaying()
                .then(|| self.replay_log.changes()),
            pending_changes: self.pending_changes,
            dropped_total: self.shown.dropped_total,
            dropping_now: self.shown.dropping_now,
            behind: self.shown.behind,
            can_replay: self.replay_log.can_replay(),
            invalid: self.invalid.clone(),
        };
        egui::Panel::top("top_bar").show(ui, |ui| {
            ui.add_space(2.0);
            ui.horizontal_wrapped(|ui| {
                ui.heading("stoneskip");
                ui.separator();
                ui::simulation_ui(ui, &mut controls, actions);
            });
            ui.horizontal_wrapped(|ui| {
                let current = request_of(self.view_mode);
                ui::view_ui(ui, &mut self.view, current, self.exaggeration, actions);
                ui.separator();
                if ui.button("Help").on_hover_text("F1 or ?").clicked() {
                    self.show_help = !self.show_help;
                }
                if ui.button("About the model").on_hover_text("M").clicked() {
                    self.show_about = !self.show_about;
                }
                if ui
                    .selectable_label(self.show_experiments, "Experiments")
                    .on_hover_text("X: throw many times, changing one thing, and chart the results")
                    .clicked()
                {
                    self.show_experiments = !self.show_experiments;
                }
            });
            ui.add_space(2.0);
        });
        if controls.speed != self.clock.speed() {
            self.set_speed(controls.speed);
        }
        self.notices = ui::notices(&controls);
    }

    /// Playback speed (the per-frame cap on ticks grows with it).
    pub fn set_speed(&mut self, speed: f64) {
        self.clock.set_speed(speed);
        let dt = self.clock.step();
        let cap = super::model::MAX_SIM_PER_FRAME * self.clock.speed().max(1.0) / dt;
        self.clock.set_max_steps(cap.ceil() as u64);
    }

    fn settings_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let head = |s: &str, changed: &[Difference]| {
            if changed.is_empty() {
                RichText::new(s).heading()
            } else {
                RichText::new(format!("{s} •")).heading()
            }
        };
        let d_launch = launch_differences(&self.loaded.launch, &self.edit.launch);
        let d_stone = section_differences(&self.loaded.stone, &self.edit.stone);
        let d_physics = section_differences(&self.loaded.physics, &self.edit.physics);
        let d_water = section_differences(&self.loaded.water, &self.edit.water);
        let marks = |d: &[Difference]| {
            ui::Marks::new(d.iter().map(|d| (d.field.as_str(), d.preset.as_str())))
        };
        egui::CollapsingHeader::new(head("Launch", &d_launch))
            .id_salt("launch_panel")
            .default_open(true)
            .show(ui, |ui| {
                changes_ui(ui, &d_launch, Section::Launch, actions);
                self.lake_exit_ui(ui, actions);
                if ui::launch_ui(ui, &mut self.edit.launch, &marks(&d_launch)) {
                    actions.push(Action::SceneEdited);
                }
                if self.edit.physics.rotation == Rotation::Locked {
                    // A spin slider that silently does nothing would mislead: say so, offer the fix.
                    ui.horizontal_wrapped(|ui| {
                        ui.weak("Spin has no effect while the attitude is Locked (the paper's high-spin limit).");
                        if ui
                            .small_button("Free rotation")
                            .on_hover_text("Physics ▸ Rotation: Free — torque, spin and gyroscope")
                            .clicked()
                        {
                            self.edit.physics.rotation = Rotation::Free;
                            actions.push(Action::PhysicsEdited);
                        }
                    });
                }
            });
        egui::CollapsingHeader::new(head("Stone", &d_stone))
            .id_salt("stone_panel")
            .default_open(true)
            .show(ui, |ui| {
                changes_ui(ui, &d_stone, Section::Stone, actions);
                if ui::stone_ui(ui, &mut self.edit.stone, &marks(&d_stone)) {
                    actions.push(Action::SceneEdited);
                }
            });
        egui::CollapsingHeader::new(head("Physics", &d_physics))
            .id_salt("physics_panel")
            .default_open(false)
            .show(ui, |ui| {
                changes_ui(ui, &d_physics, Section::Physics, actions);
                ui.weak("Applied live, at the next step.");
                if ui::physics_ui(ui, &mut self.edit.physics, &marks(&d_physics)) {
                    actions.push(Action::PhysicsEdited);
                }
            });
        egui::CollapsingHeader::new(head("Water", &d_water))
            .id_salt("water_panel")
            .default_open(false)
            .show(ui, |ui| {
                changes_ui(ui, &d_water, Section::Water, actions);
                self.lake_exit_ui(ui, actions);
                ui.weak("Needs a new simulation: applied on the next throw or reset.");
                if ui::water_ui(ui, &mut self.edit.water, &marks(&d_water)) {
                    actions.push(Action::SceneEdited);
                }
            });
        egui::CollapsingHeader::new(head("Presets", &[]))
            .default_open(true)
            .show(ui, |ui| {
                let can_replay = self.replay_log.can_replay();
                ui::presets_ui(ui, &mut self.library, can_replay, actions);
            });
        egui::CollapsingHeader::new(head("Display", &[]))
            .default_open(false)
            .show(ui, |ui| ui::display_ui(ui, &mut self.view));
    }

    /// The edited throw would leave the lake: say so before the throw, offer the fit.
    fn lake_exit_ui(&self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let (Some(edges), Some(track)) = (&self.lake_exit, self.lake_track) else {
            return;
        };
        let lake = lake::lake_rect(&self.edit);
        // In plain words: which side, how far the stone goes and where the water drawn ends.
        let sides = edges
            .replace(" (+x)", "")
            .replace(" (−x)", "")
            .replace(" (+y)", "")
            .replace(" (−y)", "");
        let reach = track.hi[0] - self.edit.launch.position[0];
        let ends = lake.map_or(0.0, |r| r.hi[0] - self.edit.launch.position[0]);
        let wavy = self.edit.water.wavy_contact;
        let text = if wavy {
            format!(
                "With wavy contact the stone reads the lake, so its {sides} edge would stop this \
                 throw: it goes {reach:.0} m out, the lake ends {ends:.0} m out. Fit the lake, or \
                 the throw is no result."
            )
        } else {
            format!(
                "The stone flies past the lake's {sides} edge ({reach:.0} m out; the lake ends \
                 {ends:.0} m out): the rings stop there, the throw runs on to its end."
            )
        };
        let color = if wavy {
            WARN
        } else {
            egui::Color32::from_rgb(150, 200, 255)
        };
        let tip = lake.map_or_else(String::new, |r| {
            format!(
                "The lake spans x {:.1}…{:.1} m, y {:.1}…{:.1} m. Fitting adds {:.0} m of water on \
                 every side of the flat-water track and keeps the cell size.",
                r.lo[0],
                r.hi[0],
                r.lo[1],
                r.hi[1],
                lake::FIT_MARGIN
            )
        });
        ui.horizontal_wrapped(|ui| {
            ui.colored_label(color, text).on_hover_text(&tip);
            if ui
                .small_button("Fit the lake to the throw")
                .on_hover_text(&tip)
                .clicked()
            {
                actions.push(Action::FitLake);
            }
        });
    }

    fn readouts_ui(&mut self, ui: &mut egui::Ui, adapter: &str, actions: &mut Vec<Action>) {
        let head = |s: &str| RichText::new(s).heading();
        let radius = self.sim.stone().shape.half_extent();
        let shown = &self.shown;
        egui::CollapsingHeader::new(head("Readouts"))
            .default_open(true)
            .show(ui, |ui| ui::readouts_ui(ui, &shown.readouts));
        egui::CollapsingHeader::new(head("Contacts"))
            .default_open(true)
            .show(ui, |ui| {
                ui::contacts_ui(ui, &shown.contacts, radius, shown.ending.as_deref());
            });
        egui::CollapsingHeader::new(head("Export"))
            .default_open(true)
            .show(ui, |ui| {
                ui::export_ui(ui, self.samples.len() > 1, actions);
                ui.weak(format!("Files go to {}", self.out_dir.display()));
            });
        egui::CollapsingHeader::new(head("Earlier throws"))
            .default_open(true)
            .show(ui, |ui| {
                let rows: Vec<GhostRow> = self
                    .ghosts
                    .iter()
                    .enumerate()
                    .map(|(i, g)| {
                        let c = ghost_color(i, 1.0);
                        GhostRow {
                            number: g.number,
                            skips: g.skips,
                            distance: g.distance,
                            outcome: g.outcome.clone(),
                            color: Color32::from_rgb(
                                (c[0] * 255.0) as u8,
                                (c[1] * 255.0) as u8,
                                (c[2] * 255.0) as u8,
                            ),
                        }
                    })
                    .collect();
                ui::ghosts_ui(ui, &rows);
            });
        egui::CollapsingHeader::new(head("Plots"))
            .default_open(true)
            .show(ui, |ui| ui::plots_ui(ui, &shown.plots, shown.plot_end));
        egui::CollapsingHeader::new(head("Frame time"))
            .default_open(false)
            .show(ui, |ui| ui::timing_ui(ui, &shown.timing, adapter));
    }

    /// The 3D view: orbit (drag), pan (right or middle drag), zoom (wheel), frame all (double
    /// click); before a throw, a drag that starts on the stone is a throw gesture.
    fn view_input_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let rect = ui.max_rect();
        self.view_rect = rect;
        let resp = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        if resp.drag_started_by(egui::PointerButton::Primary) && self.phase == Phase::Ready {
            let near = |p: egui::Pos2| {
                self.stone_on_screen()
                    .is_some_and(|s| s.distance(p) < GESTURE_GRAB_RADIUS)
            };
            let origin = ui.input(|i| i.pointer.press_origin());
            self.gesture = origin.or(resp.interact_pointer_pos()).filter(|p| near(*p));
        }
        if let Some(start) = self.gesture {
            if resp.drag_stopped() {
                self.gesture = None;
                if let Some(end) = resp.interact_pointer_pos() {
                    let d = end - start;
                    let yaw = self.camera.yaw;
                    self.edit.launch =
                        gesture_launch(&self.edit.launch, Vec2::new(d.x, d.y), rect.height(), yaw);
                    actions.push(Action::SceneEdited);
                    actions.push(Action::Throw);
                }
            } else if let Some(now) = resp.interact_pointer_pos() {
                self.gesture_preview_ui(ui, start, now, rect);
            }
            return;
        }
        let delta = resp.drag_delta();
        if resp.dragged() && delta != egui::Vec2::ZERO {
            self.camera_moved_at = Some(Instant::now());
            self.view_mode = ViewMode::Free;
        }
        if resp.dragged_by(egui::PointerButton::Primary) {
            self.camera.orbit(-delta.x * 0.006, -delta.y * 0.006);
        } else if resp.dragged_by(egui::PointerButton::Secondary)
            || resp.dragged_by(egui::PointerButton::Middle)
        {
            self.camera.pan(delta.x, delta.y, rect.height());
        }
        if resp.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom((-scroll * 0.0025).exp());
                self.camera_moved_at = Some(Instant::now());
                self.view_mode = ViewMode::Free;
            }
        }
        if resp.double_clicked() {
            actions.push(Action::View(ViewRequest::FrameAll));
        }
    }

    /// The gesture's arrow and the speed it would throw at.
    fn gesture_preview_ui(
        &self,
        ui: &egui::Ui,
        start: egui::Pos2,
        now: egui::Pos2,
        rect: egui::Rect,
    ) {
        let d = now - start;
        let l = gesture_launch(
            &self.edit.launch,
            Vec2::new(d.x, d.y),
            rect.height(),
            self.camera.yaw,
        );
        let speed = glam::DVec3::from_array(l.velocity).length();
        let painter = ui.painter_at(rect);
        let stroke = egui::Stroke::new(3.0, Color32::from_rgb(150, 240, 255));
        painter.arrow(start, d, stroke);
        painter.text(
            now + egui::vec2(12.0, -12.0),
            egui::Align2::LEFT_BOTTOM,
            format!("{speed:.1} m/s, heading {:+.0}°", l.attitude.heading_deg),
            egui::FontId::proportional(16.0),
            Color32::WHITE,
        );
    }
}
