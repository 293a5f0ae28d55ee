//! What the app draws over the 3D view: the score, the camera's name and the side view's
//! exaggeration, warnings for implausible setups, the status message (timed, dismissable, over the
//! view so it never pushes the layout), and the help and about windows.

use egui::{Align2, Color32, FontId, RichText};

use super::model::Model;
use crate::ui::{self, Action, Phase};
use stoneskip_render::build;
use stoneskip_render::camera::ViewMode;

/// The side view's legend: its ticks and its stone glyphs (drawn at the true angle whatever the
/// exaggeration; coloured by bank, [`build::glyph_color`]).
pub const SIDE_LEGEND: &str = "ticks: green a skip, red where it stayed in · stones: its tilt as \
     it met the water, at the true angle; orange banked over 10°, purple on its edge, red dug in";

/// Text on a dark backing (readable over the pale sky, also on a washed-out projector) with a
/// drop shadow; returns where it was drawn.
fn shadowed_text(
    painter: &egui::Painter,
    pos: egui::Pos2,
    align: Align2,
    text: &str,
    size: f32,
    color: Color32,
) -> egui::Rect {
    let galley = painter.layout_no_wrap(text.to_owned(), FontId::proportional(size), color);
    let rect = align.anchor_size(pos, galley.size());
    painter.rect_filled(
        rect.expand2(egui::vec2(6.0, 2.0)),
        5.0,
        Color32::from_black_alpha(110),
    );
    painter.text(
        pos + egui::vec2(1.5, 1.5),
        align,
        text,
        FontId::proportional(size),
        Color32::from_black_alpha(150),
    );
    painter.galley(rect.min, galley, color);
    rect
}

/// Where the camera's name goes (its right-top corner): the view's top right, or under the score
/// when the two would meet.
fn camera_label_at(score: egui::Rect, label_width: f32, view: egui::Rect) -> egui::Pos2 {
    if score.right() + 24.0 + label_width < view.right() - 14.0 {
        view.right_top() + egui::vec2(-14.0, 10.0)
    } else {
        egui::pos2(view.right() - 14.0, score.bottom() + 4.0)
    }
}

impl Model {
    /// Score, view label, hint, warnings and the status message, inside the 3D view.
    pub(super) fn view_overlay_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let rect = self.view_rect;
        let painter = ui.painter_at(rect);
        let r = &self.shown.readouts;
        let mut score = format!(
            "{} skip{}   {:.2} m",
            r.skips,
            if r.skips == 1 { "" } else { "s" },
            r.distance
        );
        if let Some(o) = &self.shown.outcome {
            score.push_str(&format!("   {o}"));
        }
        let pos = rect.left_top() + egui::vec2(14.0, 10.0);
        let score_rect = shadowed_text(
            &painter,
            pos,
            Align2::LEFT_TOP,
            &score,
            22.0,
            Color32::WHITE,
        );
        let label = match self.view_mode {
            ViewMode::Side => format!("side view, heights ×{:.0}", self.exaggeration),
            m => format!("{} view", m.name()),
        };
        let big = if self.view_mode == ViewMode::Side {
            20.0
        } else {
            14.0
        };
        // Beside the score where it fits, else under it (a narrow view never prints one over the
        // other).
        let width = painter
            .layout_no_wrap(label.clone(), FontId::proportional(big), Color32::WHITE)
            .size()
            .x;
        let label_at = camera_label_at(score_rect, width, rect);
        let label_rect = shadowed_text(
            &painter,
            label_at,
            Align2::RIGHT_TOP,
            &label,
            big,
            Color32::from_rgb(255, 230, 150),
        );
        if self.view_mode == ViewMode::Side {
            self.side_scale_ui(&painter);
            self.dug_in_label_ui(ui);
        }
        let hint = if self.phase == Phase::Ready {
            "Space or drag from the stone: throw   ·   1–4: cameras   ·   F1 or ?: help"
        } else {
            "drag: orbit   right-drag: pan   wheel: zoom   ·   1–4: cameras   ·   F1 or ?: help"
        };
        painter.text(
            rect.left_bottom() + egui::vec2(14.0, -10.0),
            Align2::LEFT_BOTTOM,
            hint,
            FontId::proportional(13.0),
            Color32::from_white_alpha(190),
        );
        let mut y = score_rect.bottom().max(label_rect.bottom()) + 8.0;
        // The side view's tick legend leads the stack, so no notice is drawn over it.
        let legend = (self.view_mode == ViewMode::Side)
            .then(|| (SIDE_LEGEND.to_owned(), Color32::from_rgb(225, 232, 240)));
        let glide = self
            .glide_words()
            .map(|t| (t, Color32::from_rgb(140, 215, 255)));
        // A shipped preset says what it shows, never warns about its own design (issue 48).
        let design = super::model::design_note(self.sim.preset())
            .map(|t| (t, Color32::from_rgb(150, 200, 255)));
        let glide = glide.into_iter().chain(design);
        let lines = legend
            .into_iter()
            .chain(glide)
            .chain(self.notices.iter().map(|(t, error)| {
                let c = if *error {
                    Color32::from_rgb(255, 120, 100)
                } else {
                    Color32::from_rgb(150, 200, 255)
                };
                (t.clone(), c)
            }))
            .chain(
                self.warnings
                    .iter()
                    .map(|w| (format!("! {w}"), Color32::from_rgb(255, 200, 90))),
            );
        for (text, color) in lines {
            let galley = painter.layout(
                text,
                FontId::proportional(13.0),
                color,
                (rect.width() - 28.0).max(100.0),
            );
            let size = galley.size();
            let at = egui::pos2(rect.left() + 14.0, y);
            // A dark backing keeps light text readable over the bright sky and water.
            painter.rect_filled(
                egui::Rect::from_min_size(at, size).expand(3.0),
                4.0,
                Color32::from_black_alpha(120),
            );
            // A label, not paint, so a screen reader (and a test) reads it; it senses no click,
            // so a drag over it still turns the camera.
            ui.put(
                egui::Rect::from_min_size(at, size),
                egui::Label::new(galley).selectable(false),
            );
            y += size.y + 8.0;
        }
        self.status_ui(ui, actions);
    }

    /// A throw that ended in a long planing slide, flagged where a class looks (issue 39: a
    /// 28 m glide was only a table row): the last contact a glide ([`ui::contact_kind`]) over a
    /// quarter of the throw's distance or longer than a second.
    fn glide_words(&self) -> Option<String> {
        let radius = self.sim.stone().shape.half_extent();
        let c = self.shown.contacts.last()?;
        if ui::contact_kind(c, radius) != ui::ContactKind::Glide {
            return None;
        }
        let slid = ui::slide_distance(c);
        let time = c.t_end - c.t_start;
        let distance = self.shown.readouts.distance.max(1e-9);
        (slid > 0.25 * distance || time > 1.0).then(|| {
            format!(
                "Glide: the stone stopped skipping and slid {slid:.1} m over the water for \
                 {time:.1} s before it sank."
            )
        })
    }

    /// Over the side view's glyph of the touch where the throw dug in nose-down (the red one,
    /// [`build::attitude_glyphs`]): "dug in nose-down here" and its tilt, what a class sees
    /// after Watch on such a throw.
    fn dug_in_label_ui(&self, ui: &egui::Ui) {
        let Some(touch) = build::dug_in_touch(&self.sim) else {
            return;
        };
        let Some(c) = self.sim.contacts().get(touch.saturating_sub(1)) else {
            return;
        };
        let rect = self.view_rect;
        let (centre, size) = build::glyph_centre(c, &self.camera);
        let top = centre + glam::Vec3::Z * (0.5 * size / self.camera.exaggeration.max(1e-3));
        let (w, h) = (rect.width().max(1.0) as u32, rect.height().max(1.0) as u32);
        let Some(q) = self.camera.project(top, w, h) else {
            return;
        };
        let at = rect.min + egui::vec2(q.x, q.y - 6.0);
        if !rect.contains(at) {
            return;
        }
        // A label (not paint) so a screen reader, and a test, find it.
        egui::Area::new(egui::Id::unique("dug_in_label"))
            .order(egui::Order::Foreground)
            .interactable(false)
            .pivot(Align2::CENTER_BOTTOM)
            .fixed_pos(at)
            .show(ui.ctx(), |ui| {
                egui::Frame::new()
                    .fill(Color32::from_black_alpha(150))
                    .corner_radius(5.0)
                    .inner_margin(egui::Margin::symmetric(6, 2))
                    .show(ui, |ui| {
                        ui.label(
                            RichText::new(format!(
                                "dug in nose-down here (touch {touch}, tilt {:+.1}°)",
                                c.attitude_in[0] + 0.0
                            ))
                            .size(15.0)
                            .color(Color32::from_rgb(255, 140, 120)),
                        );
                    });
            });
    }

    /// The side view's distance marks along the waterline (every 1, 2, 5 or 10 m from the launch);
    /// the legend of its ticks leads the notices in [`Self::view_overlay_ui`].
    fn side_scale_ui(&self, painter: &egui::Painter) {
        let rect = self.view_rect;
        let f = self.framing();
        let along = glam::Vec3::new(f.heading.cos(), f.heading.sin(), 0.0);
        let to_screen = |d: f32| {
            let p = f.launch.with_z(0.0) + along * d;
            let (w, h) = (rect.width().max(1.0) as u32, rect.height().max(1.0) as u32);
            self.camera
                .project(p, w, h)
                .map(|q| rect.min + egui::vec2(q.x, q.y))
        };
        let (Some(a), Some(b)) = (to_screen(0.0), to_screen(1.0)) else {
            return;
        };
        let px_per_m = (b.x - a.x).abs().max(1e-3);
        let step = [1.0, 2.0, 5.0, 10.0, 20.0, 50.0]
            .into_iter()
            .find(|s| s * px_per_m >= 70.0)
            .unwrap_or(100.0);
        let color = Color32::from_rgb(20, 60, 110);
        for k in 0..200 {
            let d = k as f32 * step;
            let Some(p) = to_screen(d) else { break };
            if p.x > rect.right() - 10.0 || p.x < rect.left() {
                if p.x > rect.right() {
                    break;
                }
                continue;
            }
            painter.line_segment([p, p + egui::vec2(0.0, 6.0)], egui::Stroke::new(1.5, color));
            painter.text(
                p + egui::vec2(0.0, 8.0),
                Align2::CENTER_TOP,
                format!("{d:.0} m"),
                FontId::proportional(12.0),
                color,
            );
        }
    }

    /// The status message: a toast at the bottom of the view with a close button.
    fn status_ui(&self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let Some(status) = &self.status else {
            return;
        };
        // Wake up when it is due to fade, even at rest.
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_secs(1));
        let rect = self.view_rect;
        egui::Area::new(egui::Id::unique("status_toast"))
            .order(egui::Order::Foreground)
            .fixed_pos(rect.left_bottom() + egui::vec2(14.0, -64.0))
            .show(ui.ctx(), |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_max_width((rect.width() - 60.0).max(200.0));
                    ui.horizontal(|ui| {
                        ui::message_ui(ui, &status.message);
                        if ui
                            .small_button("×")
                            .on_hover_text("Dismiss (Esc)")
                            .clicked()
                        {
                            actions.push(Action::DismissMessage);
                        }
                    });
                });
            });
    }

    /// The help and about windows.
    pub(super) fn windows_ui(&mut self, ctx: &egui::Context) {
        let mut open = self.show_help;
        egui::Window::new(RichText::new("Help: keys and gestures").strong())
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .anchor(Align2::CENTER_CENTER, egui::vec2(0.0, 0.0))
            .show(ctx, ui::help_ui);
        self.show_help = open;
        let mut open = self.show_about;
        egui::Window::new(RichText::new("About the model").strong())
            .open(&mut open)
            .collapsible(false)
            .default_width(560.0)
            .anchor(Align2::CENTER_CENTER, egui::vec2(0.0, 0.0))
            .show(ctx, ui::about_ui);
        self.show_about = open;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::Options;

    /// The throw run to its end in the app's model, with its readouts refreshed.
    fn finished(p: stoneskip_physics::sim::params::Preset) -> Model {
        let mut m = Model::new(p, None, Options::default()).unwrap();
        m.throw();
        while !m.sim.is_finished() {
            m.tick_once();
        }
        m.phase = Phase::Paused;
        m.refresh_shown();
        m
    }

    /// Issue 39, finding 5: "23 skips 32.69 m sank" and "side view, heights ×10" printed over
    /// each other in a 430 px view; the name drops under the score when they would meet.
    #[test]
    fn the_camera_name_never_covers_the_score() {
        let score = egui::Rect::from_min_size(egui::pos2(14.0, 10.0), egui::vec2(260.0, 26.0));
        for view_width in [300.0, 430.0, 600.0, 1000.0] {
            let view = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(view_width, 500.0));
            let width = 210.0;
            let at = camera_label_at(score, width, view);
            let label = egui::Rect::from_min_max(
                egui::pos2(at.x - width, at.y),
                at + egui::vec2(0.0, 22.0),
            );
            assert!(
                !label.intersects(score),
                "{view_width}: {label:?} over {score:?}"
            );
        }
    }

    /// Issue 39, finding 7: a throw that ends in a long planing slide says so over the view; the
    /// shipped default, whose last contact is a short slide into the sink, does not.
    #[test]
    fn a_long_glide_is_flagged_in_the_view() {
        let default = stoneskip_physics::preset::shipped("default")
            .unwrap()
            .unwrap();
        assert_eq!(finished(default.clone()).glide_words(), None);
        // Quasi-steady contact on flat water (the water's lag off): a fast throw planes away.
        let mut p = default;
        p.physics.wetted_memory = None;
        p.water.enabled = false;
        let m = finished(p);
        let words = m.glide_words().expect("a glide");
        assert!(
            words.starts_with("Glide: the stone stopped skipping"),
            "{words}"
        );
    }
}
