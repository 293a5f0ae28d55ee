//! What the app draws over the 3D view: the score, the camera's name and the side view's
//! exaggeration, warnings for implausible setups, the status message (timed, dismissable, over the
//! view so it never pushes the layout), and the help and about windows.

use egui::{Align2, Color32, FontId, RichText};

use super::model::Model;
use crate::render::camera::ViewMode;
use crate::ui::{self, Action, Phase};

fn shadowed_text(
    painter: &egui::Painter,
    pos: egui::Pos2,
    align: Align2,
    text: &str,
    size: f32,
    color: Color32,
) {
    painter.text(
        pos + egui::vec2(1.5, 1.5),
        align,
        text,
        FontId::proportional(size),
        Color32::from_black_alpha(150),
    );
    painter.text(pos, align, text, FontId::proportional(size), color);
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
        shadowed_text(
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
        shadowed_text(
            &painter,
            rect.right_top() + egui::vec2(-14.0, 10.0),
            Align2::RIGHT_TOP,
            &label,
            big,
            Color32::from_rgb(255, 230, 150),
        );
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
        let mut y = rect.top() + 42.0;
        let lines = self
            .notices
            .iter()
            .map(|(t, error)| {
                let c = if *error {
                    Color32::from_rgb(255, 120, 100)
                } else {
                    Color32::from_rgb(150, 200, 255)
                };
                (t.clone(), c)
            })
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
            let h = galley.size().y;
            painter.galley(egui::pos2(rect.left() + 14.0, y), galley, Color32::WHITE);
            y += h + 4.0;
        }
        self.status_ui(ui, actions);
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
