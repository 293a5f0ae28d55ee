//! The Experiments panel (along the window's foot, outside the 3D view, so the app's tile cache
//! redraws it only when a result arrives): choose a launch value and a range, throw them all in the background,
//! watch skips and distance against the value as results arrive, click a point (or a row) to
//! load and watch that throw, export the table as CSV. Plain egui on
//! [`super::experiments`]; the model applies the actions.

use egui::{Color32, RichText, Ui};
use egui_plot::{Line, MarkerShape, Plot, PlotPoints, Points};

use super::experiments::{Experiment, Knob, Point, Spec, MAX_THROWS};
use crate::ui::Action;

const SKIPS: Color32 = Color32::from_rgb(255, 200, 90);
const DISTANCE: Color32 = Color32::from_rgb(120, 200, 255);
const CHOSEN: Color32 = Color32::from_rgb(255, 110, 110);

/// The whole window's contents. `chosen` is the point whose throw the view shows.
pub fn experiments_ui(
    ui: &mut Ui,
    draft: &mut Spec,
    experiment: Option<&Experiment>,
    chosen: Option<usize>,
    loaded_name: &str,
    actions: &mut Vec<Action>,
) {
    let busy = experiment.is_some_and(running);
    if busy {
        // The app sleeps when nothing moves: wake it to take and draw the results.
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_millis(100));
    }
    let height = ui.available_height();
    ui.horizontal_top(|ui| {
        ui.vertical(|ui| {
            ui.set_width(SPEC_WIDTH);
            // Its words on hover: the column stays short, so the panel does not grow past a
            // third of the window and the 3D view keeps at least 60 % of a 1280 × 720 window.
            ui.strong("Experiments").on_hover_text(
                "Throw the stone many times, changing one thing, with the physics as it is \
                 now. Each dot is one throw: click it to watch that throw.",
            );
            spec_ui(ui, draft, busy, actions);
            if let Some(e) = experiment {
                progress_ui(ui, e);
                // Old results stay readable after another preset is loaded, labelled as such.
                if e.loaded.name != loaded_name {
                    ui.label(
                        RichText::new(format!(
                            "These results are for \"{}\", not the preset loaded now",
                            e.loaded.name
                        ))
                        .color(Color32::from_rgb(255, 200, 120)),
                    );
                }
                if ui
                    .add_enabled(e.done() > 0, egui::Button::new("Export CSV"))
                    .on_hover_text("The table as a CSV file, in the exports folder")
                    .clicked()
                {
                    actions.push(Action::ExportExperiment);
                }
            }
        });
        let Some(e) = experiment else {
            return;
        };
        ui.separator();
        // The charts share the value along x; it is named once, above them (an axis label
        // under each would crowd out the tick numbers).
        let table_width = 330.0_f32.min(0.35 * ui.available_width());
        let chart_width = ((ui.available_width() - table_width - 24.0) / 2.0).max(120.0);
        for (name, axis, color, value) in [
            (
                "Skips",
                "skips",
                SKIPS,
                (|p| p.skips as f64) as fn(&Point) -> f64,
            ),
            ("Distance", "distance (m)", DISTANCE, |p| p.distance),
        ] {
            let size = egui::vec2(chart_width, (height - 56.0).max(80.0));
            ui.vertical(|ui| {
                ui.weak(format!(
                    "{name} against {} ({}), \"{}\"",
                    e.spec.knob.name().to_lowercase(),
                    e.spec.knob.unit(),
                    e.loaded.name
                ));
                if let Some(i) = chart_ui(ui, e, chosen, (name, axis, color), value, size) {
                    actions.push(Action::LoadExperimentPoint(i));
                }
            });
        }
        ui.separator();
        ui.vertical(|ui| table_ui(ui, e, chosen, actions));
    });
}

/// The width of the sweep's settings column (points).
const SPEC_WIDTH: f32 = 250.0;

fn running(e: &Experiment) -> bool {
    !e.finished() && !e.stopped()
}

/// What to vary, its range and the number of throws; Run or Stop.
fn spec_ui(ui: &mut Ui, draft: &mut Spec, busy: bool, actions: &mut Vec<Action>) {
    egui::Grid::new("experiment spec")
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, |ui| {
            let label = ui.label("Vary").id;
            let before = draft.knob;
            egui::ComboBox::from_id_salt("experiment knob")
                .selected_text(format!("{} ({})", draft.knob.name(), draft.knob.unit()))
                .show_ui(ui, |ui| {
                    for k in Knob::ALL {
                        ui.selectable_value(
                            &mut draft.knob,
                            k,
                            format!("{} ({})", k.name(), k.unit()),
                        );
                    }
                })
                .response
                .labelled_by(label);
            if draft.knob != before {
                *draft = Spec {
                    count: draft.count,
                    ..Spec::suggested(draft.knob)
                };
            }
            ui.end_row();
            let (lo, hi) = draft.knob.range();
            let label = ui.label("From").id;
            ui.horizontal(|ui| {
                for (value, name) in [(&mut draft.from, "from"), (&mut draft.to, "to")] {
                    ui.add(
                        egui::DragValue::new(value)
                            .range(lo..=hi)
                            .speed((hi - lo) / 200.0)
                            .custom_parser(crate::ui::parse_finite)
                            .update_while_editing(false)
                            .suffix(format!(" {}", draft.knob.unit())),
                    )
                    .labelled_by(label)
                    .on_hover_text(format!("The sweep's {name} value"));
                    if name == "from" {
                        ui.label("to");
                    }
                }
            });
            ui.end_row();
            let label = ui.label("Throws").id;
            ui.add(
                egui::Slider::new(&mut draft.count, 2..=MAX_THROWS)
                    .clamping(egui::SliderClamping::Always)
                    .logarithmic(true)
                    .update_while_editing(false),
            )
            .labelled_by(label);
            ui.end_row();
        });
    ui.horizontal(|ui| {
        if busy {
            if ui.button("Stop").clicked() {
                actions.push(Action::StopExperiment);
            }
        } else if ui
            .button(RichText::new("Run the experiment").strong())
            .on_hover_text("Throws them all in the background, on every core but the view's")
            .clicked()
        {
            actions.push(Action::RunExperiment);
        }
    });
}

fn progress_ui(ui: &mut Ui, e: &Experiment) {
    let (done, n) = (e.done(), e.points.len());
    let state = if e.finished() {
        format!("{n} throws in {:.1} s", e.elapsed)
    } else if e.stopped() {
        format!("stopped: {done} of {n} thrown")
    } else {
        format!("{done} of {n} thrown ({:.1} s)…", e.elapsed)
    };
    ui.add(egui::ProgressBar::new(done as f32 / n.max(1) as f32).text(state));
    let bounded = e.points.iter().flatten().filter(|p| !p.result).count();
    if bounded > 0 {
        ui.label(
            RichText::new(format!(
                "{bounded} not a result (hollow dots, out of the line): ended by the lake's edge, \
                 the time limit or a failed run, not by the throw"
            ))
            .color(Color32::from_rgb(255, 200, 120)),
        )
        .on_hover_text(
            "With wavy contact the stone reads the lake's columns, so their edge ends the throw; \
             see each throw's ending in the table",
        );
    }
}

/// One chart of the results against the value; returns the point clicked.
fn chart_ui(
    ui: &mut Ui,
    e: &Experiment,
    chosen: Option<usize>,
    (name, axis, color): (&str, &str, Color32),
    value: fn(&Point) -> f64,
    size: egui::Vec2,
) -> Option<usize> {
    // Throws ended by a bound of the simulation (the lake's edge under wavy contact, the time
    // limit) are no result: drawn hollow and left out of the trend line.
    let pts: Vec<[f64; 2]> = e
        .points
        .iter()
        .flatten()
        .filter(|p| p.result)
        .map(|p| [p.value, value(p)])
        .collect();
    let bounded: Vec<[f64; 2]> = e
        .points
        .iter()
        .flatten()
        .filter(|p| !p.result)
        .map(|p| [p.value, value(p)])
        .collect();
    let (lo, hi) = (e.spec.from.min(e.spec.to), e.spec.from.max(e.spec.to));
    // Skips are whole numbers: their axis is numbered by whole numbers only.
    let whole = name == "Skips";
    let (knob_name, unit) = (e.spec.knob.name().to_lowercase(), e.spec.knob.unit());
    let chosen_pt = chosen
        .and_then(|i| e.points.get(i).cloned().flatten())
        .map(|p| [p.value, value(&p)]);
    let response = Plot::new(("experiment", name))
        .width(size.x)
        .height(size.y)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .include_x(lo)
        .include_x(hi)
        .include_y(0.0)
        // A chart of no skips still has a numbered axis, not a lone "0".
        .include_y(1.0)
        // Labels every 10° on a chart a third of the window wide (egui_plot asks for 60 points),
        // and numbers up the y axis at every range (small counts too): whole numbers for counts.
        .custom_x_axes(vec![
            egui_plot::AxisHints::new_x().label_spacing(22.0..=40.0)
        ])
        .custom_y_axes(vec![egui_plot::AxisHints::new_y()
            .label(axis)
            .label_spacing(12.0..=22.0)
            .formatter(move |mark, _| {
                let v = mark.value;
                if whole && (v - v.round()).abs() > 1e-9 {
                    String::new()
                } else {
                    format!("{}", (v * 1e6).round() / 1e6)
                }
            })])
        // The value under the pointer: the nearest throw's, or the pointer's place.
        .label_formatter(move |pos| {
            let (p, near) = match pos {
                egui_plot::HoverPosition::NearDataPoint { position, .. } => (position, true),
                egui_plot::HoverPosition::Elsewhere { position } => (position, false),
            };
            let y = if whole && near {
                format!("{:.0}", p.y)
            } else {
                format!("{:.2}", p.y)
            };
            Some(format!("{} {:.3} {unit}\n{axis} {y}", knob_name, p.x))
        })
        .show(ui, |plot| {
            plot.line(
                Line::new(name, PlotPoints::from(pts.clone())).color(color.gamma_multiply(0.6)),
            );
            plot.points(
                Points::new(name, PlotPoints::from(pts))
                    .color(color)
                    .radius(3.5)
                    .shape(MarkerShape::Circle)
                    .filled(true),
            );
            if !bounded.is_empty() {
                plot.points(
                    Points::new("not a result", PlotPoints::from(bounded))
                        .color(color)
                        .radius(4.0)
                        .shape(MarkerShape::Circle)
                        .filled(false),
                );
            }
            if let Some(c) = chosen_pt {
                plot.points(
                    Points::new("chosen", PlotPoints::from(vec![c]))
                        .color(CHOSEN)
                        .radius(6.0)
                        .filled(false),
                );
            }
        });
    let r = response
        .response
        .on_hover_text("Click a dot to watch that throw");
    if !r.clicked() {
        return None;
    }
    let at = r.interact_pointer_pos()?;
    let x = response.transform.value_from_position(at).x;
    e.points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.as_ref().map(|p| (i, (p.value - x).abs())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// The results as a table; each row's button loads that throw.
fn table_ui(ui: &mut Ui, e: &Experiment, chosen: Option<usize>, actions: &mut Vec<Action>) {
    let k = e.spec.knob;
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .id_salt("experiment table")
        .show(ui, |ui| {
            egui::Grid::new("experiment results")
                .num_columns(5)
                .striped(true)
                .spacing([12.0, 2.0])
                .show(ui, |ui| {
                    ui.strong(format!("{} ({})", k.name(), k.unit()));
                    ui.strong("skips");
                    ui.strong("distance (m)");
                    ui.label("");
                    ui.strong("ending");
                    ui.end_row();
                    for (i, p) in e.points.iter().enumerate() {
                        let Some(p) = p else { continue };
                        let text = |s: String| {
                            if chosen == Some(i) {
                                RichText::new(s).color(CHOSEN)
                            } else {
                                RichText::new(s)
                            }
                        };
                        ui.monospace(text(format!("{:.3}", p.value)));
                        ui.monospace(text(p.skips.to_string()));
                        ui.monospace(text(format!("{:.2}", p.distance)));
                        // Watch before the ending, whose words may run past the panel's edge
                        // (shown whole on hover).
                        if ui
                            .small_button("Watch")
                            .on_hover_text("Load this throw's settings and throw it")
                            .clicked()
                        {
                            actions.push(Action::LoadExperimentPoint(i));
                        }
                        let ending = if p.result {
                            text(p.outcome.clone())
                        } else {
                            text(format!("not a result: {}", p.outcome)).italics()
                        };
                        ui.add(egui::Label::new(ending).truncate())
                            .on_hover_text(&p.outcome);
                        ui.end_row();
                    }
                });
        });
}
