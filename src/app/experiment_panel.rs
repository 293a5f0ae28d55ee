//! The Experiments panel (along the window's foot, outside the 3D view, so the app's tile cache
//! redraws it only when a result arrives): choose a launch value and a range, throw them all in the background,
//! watch skips and distance against the value as results arrive, click a point (or a row) to
//! load and watch that throw, export the table as CSV. Plain egui on
//! [`super::experiments`]; the model applies the actions.

use egui::{Color32, RichText, Ui};
use egui_plot::{Line, MarkerShape, Plot, PlotPoints, Points};

use super::experiments::{Attitude, Experiment, Knob, Point, Spec, MAX_SIDE, MAX_THROWS};
use crate::ui::Action;

const SKIPS: Color32 = Color32::from_rgb(255, 200, 90);
const DISTANCE: Color32 = Color32::from_rgb(120, 200, 255);
const CHOSEN: Color32 = Color32::from_rgb(255, 110, 110);
const ATTITUDE: Color32 = Color32::from_rgb(170, 230, 140);

/// The attitude chart's choice (tilt or bank, first or last landing), kept in egui's memory
/// from frame to frame; a selector above the chart.
fn attitude_choice_ui(ui: &mut Ui) -> Attitude {
    let id = egui::Id::unique("experiment attitude");
    let mut choice: Attitude = ui.data(|d| d.get_temp(id)).unwrap_or_default();
    ui.horizontal(|ui| {
        let label = ui.weak("Attitude").id;
        egui::ComboBox::from_id_salt("experiment attitude chart")
            .selected_text(choice.name())
            .show_ui(ui, |ui| {
                for a in Attitude::ALL {
                    ui.selectable_value(&mut choice, a, a.name());
                }
            })
            .response
            .labelled_by(label)
            .on_hover_text(
                "The stone's attitude relative to its travel when it met the water: tilt below \
                 0 is nose-down (it digs in), a bank past 20° lands it on its edge",
            );
    });
    ui.data_mut(|d| d.insert_temp(id, choice));
    choice
}

/// The whole window's contents: the sweep's settings (`draft`, and `second`: a map's second
/// value, `None` for one value), then the results: charts against the value, or a map of two.
/// `chosen` is the point whose throw the view shows.
pub fn experiments_ui(
    ui: &mut Ui,
    (draft, second): (&mut Spec, &mut Option<Spec>),
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
                "Throw the stone many times, changing one thing (or two, on a map), with the \
                 physics as it is now. Each dot or cell is one throw: click it to watch that \
                 throw.",
            );
            spec_ui(ui, draft, second, busy);
            run_ui(ui, busy, experiment, actions);
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
            }
        });
        if let Some(y) = second.as_mut() {
            ui.separator();
            ui.vertical(|ui| {
                ui.set_width(SECOND_WIDTH);
                second_ui(ui, draft.knob, y, busy);
            });
        }
        let Some(e) = experiment else {
            return;
        };
        ui.separator();
        if e.second.is_some() {
            map_results_ui(ui, e, chosen, height, actions);
        } else {
            charts_ui(ui, e, chosen, height, actions);
        }
        ui.separator();
        ui.vertical(|ui| table_ui(ui, e, chosen, actions));
    });
}

/// A map's results: the map of skips, its legend.
fn map_results_ui(
    ui: &mut Ui,
    e: &Experiment,
    chosen: Option<usize>,
    height: f32,
    actions: &mut Vec<Action>,
) {
    let table_width = 260.0_f32.min(0.3 * ui.available_width());
    let legend_width = 110.0;
    let plot_height = (height - 40.0).max(80.0);
    // What the row leaves, up to cells three times as wide as tall.
    let width = (ui.available_width() - table_width - legend_width - 30.0)
        .min(plot_height * 3.0)
        .max(160.0);
    ui.vertical(|ui| {
        let y = e.second.map_or("", |s| s.knob.name());
        ui.weak(format!(
            "Skips over {} and {}, \"{}\"",
            e.spec.knob.name().to_lowercase(),
            y.to_lowercase(),
            e.loaded.name
        ));
        let size = egui::vec2(width, plot_height);
        if let Some(i) = super::map_panel::map_ui(ui, e, chosen, size) {
            actions.push(Action::LoadExperimentPoint(i));
        }
    });
    ui.vertical(|ui| {
        ui.set_width(legend_width);
        super::map_panel::legend_ui(ui, e);
    });
}

/// A one-value experiment's charts: skips, distance and the stone's attitude at a landing (a
/// selector), side by side, against the value.
fn charts_ui(
    ui: &mut Ui,
    e: &Experiment,
    chosen: Option<usize>,
    height: f32,
    actions: &mut Vec<Action>,
) {
    // The charts share the value along x; it is named once, above them (an axis label under
    // each would crowd out the tick numbers).
    // The table keeps room for its Watch buttons and the ending's first words.
    let table_width = 320.0_f32.min(0.34 * ui.available_width());
    let chart_width = ((ui.available_width() - table_width - 60.0) / 3.0).max(120.0);
    let size = egui::vec2(chart_width, (height - 56.0).max(80.0));
    let against = format!(
        "against {} ({}), \"{}\"",
        e.spec.knob.name().to_lowercase(),
        e.spec.knob.unit(),
        e.loaded.name
    );
    for (name, axis, color, value) in [
        (
            "Skips",
            "skips",
            SKIPS,
            (|p| Some(p.skips as f64)) as fn(&Point) -> Option<f64>,
        ),
        ("Distance", "distance (m)", DISTANCE, |p| Some(p.distance)),
    ] {
        ui.vertical(|ui| {
            // Each column as wide as its chart: a long title is cut (whole on hover).
            ui.set_width(size.x);
            let title = format!("{name} {against}");
            ui.add(egui::Label::new(RichText::new(&title).weak()).truncate())
                .on_hover_text(title);
            if let Some(i) = chart_ui(ui, e, chosen, (name, axis, color), &value, size) {
                actions.push(Action::LoadExperimentPoint(i));
            }
        });
    }
    ui.vertical(|ui| {
        ui.set_width(size.x);
        let attitude = attitude_choice_ui(ui);
        let value = move |p: &Point| attitude.of(p);
        let series = (attitude.name(), "degrees", ATTITUDE);
        if let Some(i) = chart_ui(ui, e, chosen, series, &value, size) {
            actions.push(Action::LoadExperimentPoint(i));
        }
    });
}

/// Run or Stop, and Export CSV.
fn run_ui(ui: &mut Ui, busy: bool, e: Option<&Experiment>, actions: &mut Vec<Action>) {
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
        if let Some(e) = e {
            if ui
                .add_enabled(e.done() > 0, egui::Button::new("Export CSV"))
                .on_hover_text("The table as a CSV file, in the exports folder")
                .clicked()
            {
                actions.push(Action::ExportExperiment);
            }
        }
    });
}

/// The width of the second value's column (points).
const SECOND_WIDTH: f32 = 200.0;

/// The width of the sweep's settings column (points).
const SPEC_WIDTH: f32 = 250.0;

fn running(e: &Experiment) -> bool {
    !e.finished() && !e.stopped()
}

/// What to vary, its range and the number of throws; whether to map a second value.
fn spec_ui(ui: &mut Ui, draft: &mut Spec, second: &mut Option<Spec>, busy: bool) {
    let map = second.is_some();
    egui::Grid::new("experiment spec")
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, |ui| {
            let exclude = second.map(|y| y.knob);
            if knob_rows_ui(ui, draft, ("Vary", "From", "Throws"), exclude, map) {
                // A map's second value moves off a pair that cannot be mapped.
                if let Some(y) = second.as_mut() {
                    if !pairs(draft.knob, y.knob) {
                        *y = Spec::for_map(partner(draft.knob));
                    }
                }
            }
        });
    let mut on = map;
    ui.add_enabled_ui(!busy, |ui| {
        ui.checkbox(&mut on, "Map a second value").on_hover_text(
            "Every value with every value of a second one, on a grid: each cell one throw, \
             coloured by its skips (try tilt against impact angle: Clanet's 2004 diagram)",
        )
    });
    if on != map {
        *second = on.then(|| {
            if draft.count > MAX_SIDE {
                *draft = Spec::for_map(draft.knob);
            }
            Spec::for_map(partner(draft.knob))
        });
    }
}

/// A map's second value: what, its range and how many values.
fn second_ui(ui: &mut Ui, first: Knob, y: &mut Spec, busy: bool) {
    ui.strong("Mapped against");
    ui.add_enabled_ui(!busy, |ui| {
        egui::Grid::new("experiment second")
            .num_columns(2)
            .spacing([10.0, 6.0])
            .show(ui, |ui| {
                knob_rows_ui(ui, y, ("Second", "From (2nd)", "Values"), Some(first), true);
            });
    });
}

/// Whether two values can be mapped together (not one twice; an impact angle fixes the
/// height).
fn pairs(a: Knob, b: Knob) -> bool {
    crate::sweep::Plan {
        x: Spec::suggested(a),
        y: Some(Spec::suggested(b)),
    }
    .conflict()
    .is_none()
}

/// The value a map of `k` is first drawn against: tilt against impact angle (Clanet's
/// diagram), anything else against tilt (speed × tilt: the minimal speed at each angle).
fn partner(k: Knob) -> Knob {
    match k {
        Knob::Tilt => Knob::ImpactAngle,
        _ => Knob::Tilt,
    }
}

/// One value's rows in a grid: what to vary (leaving out `exclude` and what cannot pair with
/// it), from and to, how many (2 to 20 on a `map`'s side). True when the value changed.
fn knob_rows_ui(
    ui: &mut Ui,
    draft: &mut Spec,
    (vary, from, count): (&str, &str, &str),
    exclude: Option<Knob>,
    map: bool,
) -> bool {
    let label = ui.label(vary).id;
    let before = draft.knob;
    egui::ComboBox::from_id_salt(("experiment knob", vary))
        .selected_text(format!("{} ({})", draft.knob.name(), draft.knob.unit()))
        .show_ui(ui, |ui| {
            for k in Knob::ALL {
                if exclude.is_some_and(|x| !pairs(k, x)) {
                    continue;
                }
                ui.selectable_value(&mut draft.knob, k, format!("{} ({})", k.name(), k.unit()));
            }
        })
        .response
        .labelled_by(label);
    let changed = draft.knob != before;
    if changed {
        *draft = if map {
            Spec::for_map(draft.knob)
        } else {
            Spec {
                count: draft.count,
                ..Spec::suggested(draft.knob)
            }
        };
    }
    ui.end_row();
    let (lo, hi) = draft.knob.range();
    let label = ui.label(from).id;
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
    let label = ui.label(count).id;
    let most = if map { MAX_SIDE } else { MAX_THROWS };
    draft.count = draft.count.clamp(2, most);
    ui.add(
        egui::Slider::new(&mut draft.count, 2..=most)
            .clamping(egui::SliderClamping::Always)
            .logarithmic(!map)
            .update_while_editing(false),
    )
    .labelled_by(label)
    .on_hover_text(if map {
        "How many values along this side of the map (2 to 20; 400 throws at most)"
    } else {
        "How many throws, both ends included"
    });
    ui.end_row();
    changed
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
    value: &dyn Fn(&Point) -> Option<f64>,
    size: egui::Vec2,
) -> Option<usize> {
    // Throws ended by a bound of the simulation (the lake's edge under wavy contact, the time
    // limit) are no result: drawn hollow and left out of the trend line. A throw with no value
    // (an attitude when it never touched) has no dot.
    let series = |result: bool| -> Vec<[f64; 2]> {
        e.points
            .iter()
            .flatten()
            .filter(|p| p.result == result)
            .filter_map(|p| value(p).map(|y| [p.value, y]))
            .collect()
    };
    let (pts, bounded) = (series(true), series(false));
    let (lo, hi) = (e.spec.from.min(e.spec.to), e.spec.from.max(e.spec.to));
    // Skips are whole numbers: their axis is numbered by whole numbers only.
    let whole = name == "Skips";
    let (knob_name, unit) = (e.spec.knob.name().to_lowercase(), e.spec.knob.unit());
    let chosen_pt = chosen
        .and_then(|i| e.points.get(i).cloned().flatten())
        .and_then(|p| value(&p).map(|y| [p.value, y]));
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
            if axis == "degrees" {
                // Level: a tilt below it is nose-down.
                plot.hline(egui_plot::HLine::new("level", 0.0).color(Color32::GRAY));
            }
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

/// The results as a table; each row's button loads that throw. Only the rows in sight are
/// laid out (a 400-cell map's table costs the frame no more than a short one).
fn table_ui(ui: &mut Ui, e: &Experiment, chosen: Option<usize>, actions: &mut Vec<Action>) {
    let knobs: Vec<Knob> = std::iter::once(e.spec.knob)
        .chain(e.second.map(|s| s.knob))
        .collect();
    let cell = |ui: &mut Ui, width: f32, text: RichText| {
        ui.add_sized([width, 16.0], egui::Label::new(text).truncate())
    };
    let value_width = if e.second.is_some() { 48.0 } else { 62.0 };
    ui.horizontal(|ui| {
        for k in &knobs {
            cell(
                ui,
                value_width,
                RichText::new(format!("{} ({})", k.name(), k.unit())).strong(),
            )
            .on_hover_text(format!("{} ({})", k.name(), k.unit()));
        }
        cell(ui, 32.0, RichText::new("skips").strong());
        cell(ui, 52.0, RichText::new("distance (m)").strong()).on_hover_text("distance (m)");
        ui.add_space(48.0);
        ui.strong("ending");
    });
    let rows: Vec<usize> = (0..e.points.len())
        .filter(|&i| e.points[i].is_some())
        .collect();
    let row_height = ui.spacing().interact_size.y;
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .id_salt("experiment table")
        .show_rows(ui, row_height, rows.len(), |ui, range| {
            for &i in &rows[range] {
                let Some(p) = &e.points[i] else { continue };
                let text = |s: String| {
                    let t = RichText::new(s).monospace();
                    if chosen == Some(i) {
                        t.color(CHOSEN)
                    } else {
                        t
                    }
                };
                ui.horizontal(|ui| {
                    ui.set_height(row_height);
                    cell(ui, value_width, text(format!("{}", p.value)));
                    if let Some(y) = p.second {
                        cell(ui, value_width, text(format!("{y}")));
                    }
                    cell(ui, 32.0, text(p.skips.to_string()));
                    cell(ui, 52.0, text(format!("{:.2}", p.distance)));
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
                });
            }
        });
}
