//! Readouts: the run's numbers, the table of contacts, live plots of height, speed, wetted area and
//! the water's lift (against Tang et al. 2021's 3.80 g bounce threshold) over time, where the frame
//! time goes, and export (trajectory CSV, screenshot).

use egui::{RichText, Ui};
use egui_plot::{HLine, Line, LineStyle, Plot, PlotPoint, PlotPoints};
use glam::DVec3;

use super::{Action, FrameTiming, Readouts};
use stoneskip_physics::sim::{ContactEvent, StepSample, TANG_BOUNCE_G};

/// Time series for the plots, thinned: every step in contact, every 2 ms in flight.
#[derive(Debug, Clone, Default)]
pub struct PlotSeries {
    pub height: Vec<PlotPoint>,
    pub speed: Vec<PlotPoint>,
    /// cm²
    pub area: Vec<PlotPoint>,
    /// The water's upward force over the stone's weight when it was sampled (g; none without
    /// gravity), so a later live change of gravity does not rewrite the past.
    pub lift: Vec<PlotPoint>,
    last_t: f64,
}

impl PlotSeries {
    /// Most points kept per series; past it every other point is dropped.
    pub const MAX_POINTS: usize = 40_000;
    /// Spacing of flight samples (s).
    pub const FLIGHT_SPACING: f64 = 0.002;

    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// The four series as drawn over [0, end] in `buckets` columns (see `decimate`).
    pub fn decimated(&self, buckets: usize, end: f64) -> [Vec<PlotPoint>; 4] {
        let x1 = end.max(0.1);
        [
            decimate(&self.height, 0.0, x1, buckets),
            decimate(&self.speed, 0.0, x1, buckets),
            decimate(&self.area, 0.0, x1, buckets),
            decimate(&self.lift, 0.0, x1, buckets),
        ]
    }

    /// Adds a step of a stone weighing `weight` N (its lift is kept in g; none without gravity).
    pub fn push(&mut self, s: &StepSample, weight: f64) {
        if !s.in_contact && !self.height.is_empty() && s.time - self.last_t < Self::FLIGHT_SPACING {
            return;
        }
        self.last_t = s.time;
        let p = s.state.position;
        let v = s.state.velocity;
        self.height.push(PlotPoint::new(s.time, p.z));
        self.speed.push(PlotPoint::new(s.time, v.length()));
        self.area.push(PlotPoint::new(s.time, s.wetted_area * 1e4));
        let g = s.force.z / weight;
        if weight > 0.0 && g.is_finite() {
            self.lift.push(PlotPoint::new(s.time, g));
        }
        if self.height.len() > Self::MAX_POINTS {
            for series in [
                &mut self.height,
                &mut self.speed,
                &mut self.area,
                &mut self.lift,
            ] {
                let mut i = 0;
                series.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
            }
        }
    }
}

/// The run's numbers now.
pub fn readouts_ui(ui: &mut Ui, r: &Readouts) {
    egui::Grid::new("readouts")
        .num_columns(2)
        .spacing([16.0, 4.0])
        .show(ui, |ui| {
            let big = |s: String| RichText::new(s).size(16.0).strong();
            ui.label("Skips");
            ui.label(big(format!("{}", r.skips)));
            ui.end_row();
            ui.label("Distance");
            ui.label(big(format!("{:.2} m", r.distance)));
            ui.end_row();
            ui.label("Time").on_hover_text(
                "Simulated time. After the outcome the stone stays where it ended and the water's \
                 rings run on (the outcome row says when the throw ended)",
            );
            ui.monospace(format!("{:.4} s", r.time));
            ui.end_row();
            ui.label("Speed");
            ui.monospace(format!("{:.3} m/s", r.speed));
            ui.end_row();
            ui.label("Height");
            ui.monospace(format!("{:+.4} m", r.height));
            ui.end_row();
            ui.label("Attitude").on_hover_text(
                "Tilt (nose up) and bank (roll) to the path. In flight the air's pitching moment \
                 rolls a spinning stone: less spin, more roll",
            );
            // Rounded first, so a bank of −0.01° reads +0.0°, not −0.0°.
            let tenth = |x: f64| (x * 10.0).round() / 10.0 + 0.0;
            ui.monospace(format!(
                "tilt {:+.1}°  bank {:+.1}°",
                tenth(r.attitude_deg[0]),
                tenth(r.attitude_deg[1])
            ));
            ui.end_row();
            ui.label("Spin")
                .on_hover_text("About the stone's own axis; locked: the attitude is held");
            ui.monospace(match r.spin_rev_s {
                Some(w) => format!("{w:.2} rev/s"),
                None => "locked".to_owned(),
            });
            ui.end_row();
            ui.label("Water");
            if r.in_contact {
                ui.label(
                    RichText::new(format!("in contact, {:.1} cm² wet", r.wetted_area * 1e4))
                        .color(egui::Color32::from_rgb(120, 200, 255)),
                );
            } else {
                ui.label("in the air");
            }
            ui.end_row();
            ui.label("Outcome");
            // Wrapped: a long ending ("dug in nose-down at touch 2 (tilt −1.1°)") in the
            // panel's width, not past the window's edge.
            ui.add(egui::Label::new(r.outcome.as_deref().unwrap_or("—")).wrap());
            ui.end_row();
            if let Some(g) = r.glide {
                ui.label("Glide").on_hover_text(
                    "The last contact was a planing slide, not a bounce: its distance is part of \
                     the distance above",
                );
                ui.monospace(format!("{g:.2} m slid on the water"));
                ui.end_row();
            }
        });
}

/// What a contact episode was, from its own data (duration and speeds).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactKind {
    /// Still going on.
    Open,
    /// Ended with the stone in the air, turned upward by the water.
    Skip,
    /// Ended with the stone in the air, but the water did not turn it upward: a crest brushed it.
    Graze,
    /// Did not end in the air, after a short contact.
    Sank,
    /// Did not end in the air, after sliding farther than `GLIDE_DIAMETERS` stone diameters: a
    /// planing slide, not a bounce.
    Glide,
}

/// A contact that slides farther than this many stone diameters without leaving the water is a
/// glide (a bounce's contact lasts one stiff-spring half-period, a few diameters at most).
pub const GLIDE_DIAMETERS: f64 = 5.0;

/// Horizontal distance slid during a contact (m): its duration times the mean of the entry and
/// exit horizontal speeds.
pub fn slide_distance(c: &ContactEvent) -> f64 {
    let h = |v: [f64; 3]| v[0].hypot(v[1]);
    let d = (c.t_end - c.t_start).max(0.0) * 0.5 * (h(c.v_in) + h(c.v_out));
    if d.is_finite() {
        d
    } else {
        0.0
    }
}

/// Classifies a contact of a stone `radius` metres across its half-width.
pub fn contact_kind(c: &ContactEvent, radius: f64) -> ContactKind {
    if c.open {
        ContactKind::Open
    } else if c.skip {
        ContactKind::Skip
    } else if c.graze {
        ContactKind::Graze
    } else if slide_distance(c) > GLIDE_DIAMETERS * 2.0 * radius {
        ContactKind::Glide
    } else {
        ContactKind::Sank
    }
}

/// The table of contact episodes (`radius`: the stone's half-width, for telling a glide); each
/// contact's peak lift in g against the weight it was made with, its tilt and bank when it met
/// the water, and under the table why the throw ended (`ending`, once it has).
pub fn contacts_ui(ui: &mut Ui, contacts: &[ContactEvent], radius: f64, ending: Option<&str>) {
    if let Some(e) = ending {
        ui.label(RichText::new(format!("Ending: {e}")).strong());
    }
    if contacts.is_empty() {
        ui.weak("no contact yet");
        return;
    }
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 6.0;
        for (word, color) in [
            ("skip", SKIP_GREEN),
            ("sank", SANK_RED),
            ("glide", GLIDE_BLUE),
        ] {
            ui.label(RichText::new(word).color(color).small());
        }
        ui.label(RichText::new("graze").weak().small());
    });
    // Issue 48: every column in the readouts panel's width, no sideways scroll: short headers
    // (their meaning on hover) and no digit finer than the model means.
    egui::ScrollArea::vertical()
        .id_salt("contacts")
        .max_height(150.0)
        .show(ui, |ui| {
            egui::Grid::new("contacts_grid")
                .striped(true)
                .num_columns(CONTACT_COLUMNS.len())
                // Each column as wide as its widest cell (egui's default minimum, 40 points a
                // column, alone took the table past the panel).
                .min_col_width(0.0)
                .spacing([7.0, 2.0])
                .show(ui, |ui| {
                    for (h, tip) in CONTACT_COLUMNS {
                        ui.label(RichText::new(h).strong()).on_hover_text(tip);
                    }
                    ui.end_row();
                    for (i, c) in contacts.iter().enumerate() {
                        contact_row_ui(ui, i + 1, c, radius);
                        ui.end_row();
                    }
                });
        });
}

/// The contacts table's colours of a skip, a contact it sank in, and a glide.
const SKIP_GREEN: egui::Color32 = egui::Color32::from_rgb(140, 235, 110);
const SANK_RED: egui::Color32 = egui::Color32::from_rgb(255, 120, 100);
const GLIDE_BLUE: egui::Color32 = egui::Color32::from_rgb(120, 200, 255);

/// The contacts table's headers, short enough that the table fits the readouts panel, each
/// with what it means on hover.
pub const CONTACT_COLUMNS: [(&str, &str); 9] = [
    (
        "#",
        "the contact's number, in its kind's colour: skip, the water threw the stone back into the \
         air; sank; graze, a crest brushed the stone without turning it upward (not counted); \
         glide, a planing slide that never left the water",
    ),
    ("ms", "how long the contact lasted (ms)"),
    (
        "n",
        "touches of the water less than the stone's diameter apart: one contact, since a hop you \
         cannot see is not a skip",
    ),
    ("x", "where the contact started (x, m)"),
    ("v", "speed when it met the water (m/s)"),
    (
        "β",
        "angle of the velocity below the horizontal when it met the water (°)",
    ),
    (
        "tilt",
        "the stone's tilt when it met the water (°): its leading edge up; below zero it came in \
         nose-down and digs in",
    ),
    (
        "bank",
        "the stone's bank when it met the water (°): its roll about its travel; over 20° it lands \
         on its edge",
    ),
    (
        "g",
        "peak g: the water's largest upward push over the stone's weight; Tang et al. (2021) saw \
         a spun disc bounce only above 3.8 g",
    ),
];

/// One row of the contacts table: contact `number` (from 1).
fn contact_row_ui(ui: &mut Ui, number: usize, c: &ContactEvent, radius: f64) {
    let (mark, color) = match contact_kind(c, radius) {
        ContactKind::Open => ("...", ui.visuals().text_color()),
        ContactKind::Skip => ("skip", SKIP_GREEN),
        ContactKind::Graze => ("graze", ui.visuals().weak_text_color()),
        ContactKind::Sank => ("sank", SANK_RED),
        ContactKind::Glide => ("glide", GLIDE_BLUE),
    };
    // The number in the kind's colour (the key above the table), the word on hover.
    ui.label(RichText::new(format!("{number}")).monospace().color(color))
        .on_hover_text(format!(
            "{mark}: began at t = {:.3} s, slid {:.2} m",
            c.t_start,
            slide_distance(c)
        ));
    // No "-0": a value that rounds to zero prints unsigned.
    let round = |x: f64, digits: i32| {
        let k = 10f64.powi(digits);
        (x * k).round() / k + 0.0
    };
    ui.monospace(format!("{:.0}", round(1000.0 * (c.t_end - c.t_start), 0)));
    ui.monospace(format!("{}", c.touches));
    ui.monospace(format!("{:.1}", round(c.x, 1)));
    ui.monospace(format!(
        "{:.1}",
        round(DVec3::from_array(c.v_in).length(), 1)
    ));
    ui.monospace(format!("{:.0}°", round(c.beta_in, 0)));
    let tilt = round(c.attitude_in[0], 1);
    let tilt_text = RichText::new(format!("{tilt:+.1}°")).monospace();
    ui.label(if tilt < 0.0 {
        tilt_text.color(egui::Color32::from_rgb(255, 120, 100))
    } else {
        tilt_text
    });
    ui.monospace(format!("{:+.0}°", round(c.attitude_in[1], 0)));
    ui.monospace(
        c.peak_g()
            .map_or_else(|| "—".to_owned(), |g| format!("{g:.1}")),
    );
}

/// One earlier throw in the ghosts' table.
#[derive(Debug, Clone, PartialEq)]
pub struct GhostRow {
    pub number: u64,
    pub skips: usize,
    pub distance: f64,
    pub outcome: String,
    pub color: egui::Color32,
}

/// The last few throws, drawn as ghosts in the view, with their skips and distances.
pub fn ghosts_ui(ui: &mut Ui, rows: &[GhostRow]) {
    if rows.is_empty() {
        ui.weak("earlier throws appear here (and as faint trails in the view)");
        return;
    }
    egui::Grid::new("ghosts_grid")
        .striped(true)
        .num_columns(4)
        .spacing([12.0, 2.0])
        .show(ui, |ui| {
            for h in ["throw", "skips", "distance", "outcome"] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for r in rows.iter().rev() {
                ui.label(RichText::new(format!("#{}", r.number)).color(r.color));
                ui.monospace(format!("{}", r.skips));
                ui.monospace(format!("{:.2} m", r.distance));
                ui.label(&r.outcome);
                ui.end_row();
            }
        });
}

/// Height (m), speed (m/s), wetted area (cm²) and the water's lift (g, with Tang et al.'s bounce
/// threshold) over time up to `end`, sharing the time axis (series as [`PlotSeries::decimated`]
/// gives them).
pub fn plots_ui(ui: &mut Ui, series: &[Vec<PlotPoint>; 4], end: f64) {
    let link = egui::Id::unique("stoneskip_plots_x");
    let looks = [
        (
            "height",
            "height z (m)",
            egui::Color32::from_rgb(120, 200, 255),
        ),
        (
            "speed",
            "speed |v| (m/s)",
            egui::Color32::from_rgb(255, 200, 90),
        ),
        (
            "wetted",
            "wet (cm²)",
            egui::Color32::from_rgb(140, 230, 140),
        ),
        ("lift", "lift (g)", egui::Color32::from_rgb(240, 140, 200)),
    ];
    for ((id, label, color), data) in looks.into_iter().zip(series.iter()) {
        let last = id == "lift";
        let plot = Plot::new(id)
            .height(if last { 96.0 } else { 82.0 })
            .y_axis_label(label)
            .x_axis_label(if last { "time t (s)" } else { "" })
            .link_axis(link, [true, false])
            .allow_scroll(false)
            .allow_zoom(false)
            .allow_drag(false)
            .include_x(0.0)
            .include_x(end.max(0.1))
            .include_y(0.0)
            .show_axes([last, true]);
        // The lift's first impact can reach tens of g; up to four times the threshold keeps the
        // threshold and the later contacts readable (each contact's peak is in the table).
        let plot = if last {
            plot.default_y_bounds(-1.0, 4.0 * TANG_BOUNCE_G)
        } else {
            plot
        };
        let response = plot.show(ui, |plot| {
            plot.line(Line::new(label, PlotPoints::Borrowed(data)).color(color));
            if last {
                plot.hline(
                    HLine::new("Tang 2021: a bounce needs 3.8 g", TANG_BOUNCE_G)
                        .color(egui::Color32::GRAY)
                        .style(LineStyle::dashed_loose()),
                );
            }
        });
        if last {
            response.response.on_hover_text(
                "the water's upward force over the stone's weight; Tang et al. (2021) saw a spun \
                 disc bounce only when it passed 3.8 g (dashed). Drawn up to about 15 g: a first \
                 impact's higher peak is in the contact table's peak g column",
            );
        }
    }
}

/// The points of a time series (sorted by x) as drawn in `buckets` columns over [x0, x1]: each
/// column's lowest and highest point, in order; all points when there are few.
pub fn decimate(data: &[PlotPoint], x0: f64, x1: f64, buckets: usize) -> Vec<PlotPoint> {
    if data.len() <= 2 * buckets.max(1) || x1 <= x0 {
        return data.to_vec();
    }
    let width = (x1 - x0) / buckets as f64;
    let mut out = Vec::with_capacity(2 * buckets + 2);
    let mut current: Option<(i64, PlotPoint, PlotPoint)> = None;
    let flush = |out: &mut Vec<PlotPoint>, lo: PlotPoint, hi: PlotPoint| {
        if lo.x <= hi.x {
            out.push(lo);
            if hi.x != lo.x || hi.y != lo.y {
                out.push(hi);
            }
        } else {
            out.push(hi);
            out.push(lo);
        }
    };
    for &p in data {
        let b = ((p.x - x0) / width).floor() as i64;
        match current.as_mut() {
            Some((cb, lo, hi)) if *cb == b => {
                if p.y < lo.y {
                    *lo = p;
                }
                if p.y > hi.y {
                    *hi = p;
                }
            }
            _ => {
                if let Some((_, lo, hi)) = current.take() {
                    flush(&mut out, lo, hi);
                }
                current = Some((b, p, p));
            }
        }
    }
    if let Some((_, lo, hi)) = current {
        flush(&mut out, lo, hi);
    }
    if let (Some(&last), Some(&end)) = (out.last(), data.last()) {
        if last.x != end.x {
            out.push(end);
        }
    }
    out
}

/// Where the frame time goes.
pub fn timing_ui(ui: &mut Ui, t: &FrameTiming, adapter: &str) {
    if t.interval_ms > 0.0 {
        ui.label(
            RichText::new(format!(
                "{:.0} fps ({:.1} ms between frames)",
                1000.0 / t.interval_ms,
                t.interval_ms
            ))
            .strong(),
        );
    }
    ui.label(format!("{:.1} ms of work a frame:", t.frame_ms));
    let total = t.frame_ms.max(1e-6);
    for (name, ms, color, tip) in [
        (
            "physics",
            t.physics_ms,
            egui::Color32::from_rgb(255, 200, 90),
            "Stone ticks: integration, contact, forces",
        ),
        (
            "water",
            t.water_ms,
            egui::Color32::from_rgb(120, 200, 255),
            "Water grid steps, and copying η to the GPU",
        ),
        (
            "render",
            t.render_ms,
            egui::Color32::from_rgb(200, 150, 255),
            "Scene and panels drawn, submitted, presented",
        ),
        (
            "panels",
            t.ui_ms,
            egui::Color32::from_rgb(160, 160, 160),
            "Building the panels (egui)",
        ),
    ] {
        ui.horizontal(|ui| {
            ui.label(format!("{name:8}")).on_hover_text(tip);
            let frac = (ms / total).clamp(0.0, 1.0) as f32;
            ui.add(
                egui::ProgressBar::new(frac)
                    .desired_width(120.0)
                    .fill(color.gamma_multiply(0.7))
                    .text(format!("{ms:.2} ms")),
            );
        });
    }
    ui.weak(adapter);
}

/// Export buttons.
pub fn export_ui(ui: &mut Ui, has_samples: bool, actions: &mut Vec<Action>) {
    ui.horizontal(|ui| {
        if ui
            .add_enabled(has_samples, egui::Button::new("Trajectory CSV"))
            .on_hover_text("t, x, y, z, v, q, ω, contact, wetted area, force per step (as `stoneskip simulate --csv`)")
            .clicked()
        {
            actions.push(Action::ExportCsv);
        }
        if ui
            .button("Window PNG")
            .on_hover_text("The whole window, panels included")
            .clicked()
        {
            actions.push(Action::Screenshot { panels: true });
        }
        if ui
            .button("View PNG")
            .on_hover_text("The 3D view alone, without the panels")
            .clicked()
        {
            actions.push(Action::Screenshot { panels: false });
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_extremes_in_order() {
        let data: Vec<PlotPoint> = (0..10_000)
            .map(|i| {
                PlotPoint::new(
                    i as f64 * 1e-3,
                    if i == 5_000 { 9.0 } else { (i % 7) as f64 },
                )
            })
            .collect();
        let d = decimate(&data, 0.0, 10.0, 100);
        assert!(d.len() <= 202);
        assert!(d.windows(2).all(|w| w[0].x <= w[1].x));
        assert!(d.iter().any(|p| p.y == 9.0));
        assert_eq!(d.last().map(|p| p.x), data.last().map(|p| p.x));
    }

    /// A step at `time` with the water's upward force `fz` (N).
    fn sample(time: f64, fz: f64) -> StepSample {
        StepSample {
            time,
            state: stoneskip_physics::sim::integrate::BodyState {
                position: DVec3::ZERO,
                velocity: DVec3::X,
                orientation: glam::DQuat::IDENTITY,
                angular_momentum: DVec3::ZERO,
                memory: 0.0,
            },
            angular_velocity: DVec3::ZERO,
            in_contact: true,
            wetted_area: 0.0,
            force: DVec3::new(1.0, 0.0, fz),
        }
    }

    #[test]
    fn the_lift_plot_is_the_waters_upward_force_over_the_weight() {
        let mut plots = PlotSeries::default();
        for (i, fz) in [0.0, 2.0, 7.5, 0.0].into_iter().enumerate() {
            plots.push(&sample(i as f64 * 0.01, fz), 0.5);
        }
        let [height, .., lift] = plots.decimated(400, 0.03);
        assert_eq!(height.len(), 4);
        let g: Vec<f64> = lift.iter().map(|p| p.y).collect();
        assert_eq!(g, [0.0, 4.0, 15.0, 0.0]);
        // A later step of a heavier stone (gravity changed live) leaves the earlier points as
        // they were.
        plots.push(&sample(0.04, 2.0), 1.0);
        let g: Vec<f64> = plots.decimated(400, 0.04)[3].iter().map(|p| p.y).collect();
        assert_eq!(g, [0.0, 4.0, 15.0, 0.0, 2.0]);
        // Without gravity there is no weight to measure the lift by.
        let mut weightless = PlotSeries::default();
        weightless.push(&sample(0.0, 1.0), 0.0);
        // A subnormal gravity typed into the slider: the ratio overflows, and is not drawn.
        weightless.push(&sample(0.01, 1.0), 1e-320);
        assert!(weightless.decimated(400, 0.03)[3].is_empty());
    }
}
