//! A two-value map in the Experiments panel (issue 48): one launch value along x, another along
//! y, every value with every other, each cell one throw coloured by its skips — Clanet, Hersen &
//! Bocquet's phase diagram (Nature 427, 2004, Fig. 3: tilt α against impact angle β) drawn from
//! the class's own throws. A cell that never bounced is grey ("no bounce"); a throw ended by a
//! bound of the simulation (the lake's edge under wavy contact, the time limit) is hollow, not a
//! result; a click on a cell watches that throw, as a dot does. The paper's marks: the magic
//! attack angle 20° and no bounce above about 45° of impact angle. Plain egui on
//! [`super::experiments`].

use egui::{Color32, RichText, Stroke, Ui};
use egui_plot::{HLine, Line, Plot, PlotPoints, Polygon, Text, VLine};

use super::experiments::{Experiment, Knob};

/// A throw that did not bounce: grey, away from the colour scale of the ones that did.
pub const NO_BOUNCE: Color32 = Color32::from_rgb(120, 120, 120);
const CHOSEN: Color32 = Color32::from_rgb(255, 110, 110);
const MARK: Color32 = Color32::from_rgb(255, 255, 255);
const PENDING: Color32 = Color32::from_rgba_premultiplied(40, 40, 40, 40);

/// The egui memory key (`egui::Id::unique(MAP_TRANSFORM)`) under which the map leaves its
/// `egui_plot::PlotTransform` each frame.
pub const MAP_TRANSFORM: &str = "experiment map transform";

/// The magic attack angle (°): Clanet et al. (2004) found the slowest skip near 20° of tilt.
pub const MAGIC_TILT_DEG: f64 = 20.0;
/// Above this impact angle (°) no stone bounced in Clanet et al. (2004).
pub const NO_BOUNCE_ABOVE_DEG: f64 = stoneskip_physics::sim::ending::STEEPEST_BOUNCE_DEG;

/// The colour of `skips` on a scale up to `max` skips: grey for none, then viridis (dark blue
/// through green to yellow), which reads in order and in grey print.
pub fn skips_color(skips: usize, max: usize) -> Color32 {
    if skips == 0 {
        return NO_BOUNCE;
    }
    const STOPS: [[f32; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if max <= 1 {
        1.0
    } else {
        (skips - 1).min(max - 1) as f32 / (max - 1) as f32
    };
    let f = t * (STOPS.len() - 1) as f32;
    let i = (f.floor() as usize).min(STOPS.len() - 2);
    let (a, b, u) = (STOPS[i], STOPS[i + 1], f - i as f32);
    let c = |k: usize| (a[k] + (b[k] - a[k]) * u).round() as u8;
    Color32::from_rgb(c(0), c(1), c(2))
}

/// The grid's geometry: the values along each side and a cell's half-size in their units.
struct Grid {
    xs: Vec<f64>,
    ys: Vec<f64>,
    half: [f64; 2],
}

impl Grid {
    fn of(e: &Experiment) -> Option<Self> {
        let plan = e.plan();
        let (xs, ys) = (plan.x_values(), plan.y_values());
        let half = |v: &[f64]| match v {
            [a, .., b] => ((b - a) / (v.len() - 1) as f64 / 2.0).abs().max(1e-12),
            _ => 0.5,
        };
        (!ys.is_empty()).then(|| Self {
            half: [half(&xs), half(&ys)],
            xs,
            ys,
        })
    }

    /// The index of the cell nearest `(x, y)` (value units).
    fn nearest(&self, x: f64, y: f64) -> usize {
        let near = |v: &[f64], z: f64| {
            v.iter()
                .enumerate()
                .min_by(|a, b| (a.1 - z).abs().total_cmp(&(b.1 - z).abs()))
                .map_or(0, |(i, _)| i)
        };
        near(&self.xs, x) * self.ys.len() + near(&self.ys, y)
    }

    /// The corners of cell `i`.
    fn corners(&self, i: usize) -> Vec<[f64; 2]> {
        let (x, y) = (self.xs[i / self.ys.len()], self.ys[i % self.ys.len()]);
        let [hx, hy] = self.half;
        vec![
            [x - hx, y - hy],
            [x + hx, y - hy],
            [x + hx, y + hy],
            [x - hx, y + hy],
        ]
    }
}

/// The most skips among the results (the colour scale's top; at least 1).
pub fn most_skips(e: &Experiment) -> usize {
    e.points
        .iter()
        .flatten()
        .filter(|p| p.result)
        .map(|p| p.skips)
        .max()
        .unwrap_or(1)
        .max(1)
}

/// The map of `e` (a two-value experiment) in `size`; returns the cell clicked, if it has a
/// throw to watch.
pub fn map_ui(
    ui: &mut Ui,
    e: &Experiment,
    chosen: Option<usize>,
    size: egui::Vec2,
) -> Option<usize> {
    let (Some(grid), Some(second)) = (Grid::of(e), e.second) else {
        return None;
    };
    let max = most_skips(e);
    let (kx, ky) = (e.spec.knob, second.knob);
    let words = {
        let points = e.points.clone();
        let (xs, ys, half) = (grid.xs.clone(), grid.ys.clone(), grid.half);
        let e_spec = e.spec;
        // The cell under the pointer and its throw, in words.
        move |x: f64, y: f64| {
            let g = Grid {
                xs: xs.clone(),
                ys: ys.clone(),
                half,
            };
            let i = g.nearest(x, y);
            let (vx, vy) = (g.xs[i / g.ys.len()], g.ys[i % g.ys.len()]);
            let k = |k: Knob, v: f64| format!("{} {v} {}", k.name().to_lowercase(), k.unit());
            let what = match points.get(i).and_then(Option::as_ref) {
                None => "not thrown yet".to_owned(),
                Some(p) if !p.result => "not a result".to_owned(),
                Some(p) if p.skips == 0 => "no bounce".to_owned(),
                Some(p) => format!("{} skips", p.skips),
            };
            format!("{}, {}: {what}", k(e_spec.knob, vx), k(second.knob, vy))
        }
    };
    let axis = |k: Knob| format!("{} ({})", k.name().to_lowercase(), k.unit());
    let response = Plot::new("experiment map")
        .width(size.x)
        .height(size.y)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .show_grid(false)
        .include_x(grid.xs[0] - grid.half[0])
        .include_x(grid.xs[grid.xs.len() - 1] + grid.half[0])
        .include_y(grid.ys[0] - grid.half[1])
        .include_y(grid.ys[grid.ys.len() - 1] + grid.half[1])
        .set_margin_fraction(egui::vec2(0.0, 0.0))
        .x_axis_label(axis(kx))
        .y_axis_label(axis(ky))
        .custom_x_axes(vec![egui_plot::AxisHints::new_x()
            .label(axis(kx))
            .label_spacing(22.0..=40.0)])
        .custom_y_axes(vec![egui_plot::AxisHints::new_y()
            .label(axis(ky))
            .label_spacing(14.0..=24.0)])
        .label_formatter(move |pos| {
            let p = match pos {
                egui_plot::HoverPosition::NearDataPoint { position, .. } => position,
                egui_plot::HoverPosition::Elsewhere { position } => position,
            };
            Some(words(p.x, p.y))
        })
        .show(ui, |plot| {
            for (i, p) in e.points.iter().enumerate() {
                let cell = Polygon::new("cell", PlotPoints::from(grid.corners(i)))
                    .allow_hover(false)
                    .id(("map cell", i));
                let cell = match p {
                    None => cell.fill_color(PENDING).stroke(Stroke::NONE),
                    Some(p) if !p.result => cell
                        .fill_color(Color32::TRANSPARENT)
                        .stroke(Stroke::new(1.5, skips_color(p.skips, max))),
                    Some(p) => cell
                        .fill_color(skips_color(p.skips, max))
                        .stroke(Stroke::new(0.5, Color32::from_black_alpha(90))),
                };
                plot.polygon(cell);
            }
            marks(plot, kx, ky, &grid);
            if let Some(c) = chosen.filter(|&c| c < e.points.len()) {
                let mut ring = grid.corners(c);
                ring.push(ring[0]);
                plot.line(
                    Line::new("chosen", PlotPoints::from(ring))
                        .color(CHOSEN)
                        .width(2.5)
                        .allow_hover(false),
                );
            }
        });
    // Where the map was drawn, for a test that clicks a cell as a person would.
    ui.data_mut(|d| d.insert_temp(egui::Id::unique(MAP_TRANSFORM), response.transform));
    let r = response
        .response
        .on_hover_text("Click a cell to watch that throw");
    if !r.clicked() {
        return None;
    }
    let at = r.interact_pointer_pos()?;
    let v = response.transform.value_from_position(at);
    let i = grid.nearest(v.x, v.y);
    e.points.get(i)?.as_ref().map(|_| i)
}

/// The paper's marks: the magic attack angle (20° of tilt) and no bounce above about 45° of
/// impact angle, on whichever side those values are.
fn marks(plot: &mut egui_plot::PlotUi<'_>, kx: Knob, ky: Knob, grid: &Grid) {
    let (x0, y1) = (grid.xs[0], grid.ys[grid.ys.len() - 1] + grid.half[1]);
    for (k, on_x) in [(kx, true), (ky, false)] {
        let (at, words) = match k {
            Knob::Tilt => (MAGIC_TILT_DEG, "magic angle 20°"),
            Knob::ImpactAngle => (NO_BOUNCE_ABOVE_DEG, "no bounce above 45° (Clanet 2004)"),
            _ => continue,
        };
        let stroke = Stroke::new(1.5, MARK);
        if on_x {
            plot.vline(VLine::new(words, at).stroke(stroke).allow_hover(false));
            plot.text(
                Text::new(
                    words,
                    [at, y1].into(),
                    RichText::new(words).color(MARK).small(),
                )
                .anchor(egui::Align2::LEFT_TOP),
            );
        } else {
            plot.hline(HLine::new(words, at).stroke(stroke).allow_hover(false));
            plot.text(
                Text::new(
                    words,
                    [x0, at].into(),
                    RichText::new(words).color(MARK).small(),
                )
                .anchor(egui::Align2::LEFT_BOTTOM),
            );
        }
    }
}

/// The colour legend: the scale's steps, "no bounce" and "not a result".
pub fn legend_ui(ui: &mut Ui, e: &Experiment) {
    let max = most_skips(e);
    ui.strong("Skips");
    let swatch = |ui: &mut Ui, fill: Color32, hollow: bool, words: String| {
        ui.horizontal(|ui| {
            let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 10.0), egui::Sense::hover());
            if hollow {
                ui.painter().rect_stroke(
                    rect,
                    0.0,
                    Stroke::new(1.5, fill),
                    egui::StrokeKind::Inside,
                );
            } else {
                ui.painter().rect_filled(rect, 0.0, fill);
            }
            ui.small(words);
        });
    };
    // The most, the middle and one: the scale's ends and middle, so the legend stays short.
    let mut levels = vec![max, max.div_ceil(2), 1];
    levels.dedup();
    for s in levels {
        swatch(ui, skips_color(s, max), false, format!("{s}"));
    }
    swatch(ui, NO_BOUNCE, false, "0: no bounce".to_owned());
    swatch(
        ui,
        Color32::LIGHT_GRAY,
        true,
        "hollow: not a result".to_owned(),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_bounce_stands_apart_from_every_skip_count() {
        for max in [1, 2, 7, 40] {
            for s in 1..=max {
                assert_ne!(skips_color(s, max), NO_BOUNCE);
            }
            // The scale runs dark to bright.
            let lum = |c: Color32| c.r() as u32 + c.g() as u32 + c.b() as u32;
            if max > 1 {
                assert!(lum(skips_color(1, max)) < lum(skips_color(max, max)));
            }
        }
    }
}
