//! Settings panels: the launch, the stone, the physical constants (live), the water (next throw)
//! and the display. Each returns whether it changed anything. Ranges stay inside
//! `Preset::validate`'s; degrees and rev/s are shown, radians and rad/s stored.

use egui::{Slider, SliderClamping, Ui};

use stoneskip_physics::sim::params::{
    AirParams, AxialSpin, ForceLaw, Hydrostatic, Integrator, LagLength, Launch, Limiter,
    MemoryParams, Physics, Precision, PressureSign, Quadrature, Rotation, Shape, StoneParams,
    Swell, WaterParams, MAX_WATER_COLUMNS,
};
pub use stoneskip_physics::sim::world::World;

use super::ViewSettings;

const TAU: f64 = std::f64::consts::TAU;

pub use crate::sweep::ranges;

/// What a typed number means: a finite number, or nothing (then the field keeps its old value).
/// Rust's parser accepts "nan" and "inf", which a clamped slider would turn into its maximum.
pub fn parse_finite(text: &str) -> Option<f64> {
    text.trim()
        .trim_end_matches(['°', '%', '×'])
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
}

thread_local! {
    /// The last number typed into a [`slider`], with its range: [`row`] reads it after the row's
    /// widget to say when the value was clamped.
    static TYPED: std::cell::Cell<Option<(f64, f64, f64)>> = const { std::cell::Cell::new(None) };
}

fn slider<'a>(value: &'a mut f64, range: std::ops::RangeInclusive<f64>) -> Slider<'a> {
    let (lo, hi) = (*range.start(), *range.end());
    Slider::new(value, range)
        .update_while_editing(false)
        .clamping(SliderClamping::Always)
        .custom_parser(move |text| {
            let v = parse_finite(text);
            if let Some(x) = v {
                TYPED.with(|t| t.set(Some((x, lo, hi))));
            }
            v
        })
}

/// The note for a typed `x` that the range `lo..=hi` clamped; `None` when it fitted.
pub fn clamp_note(x: f64, lo: f64, hi: f64) -> Option<String> {
    if x > hi {
        Some(format!("{x} is over the most, {hi}: set to {hi}"))
    } else if x < lo {
        Some(format!("{x} is under the least, {lo}: set to {lo}"))
    } else {
        None
    }
}

fn grid(ui: &mut Ui, id: &str, add: impl FnOnce(&mut Ui) -> bool) -> bool {
    egui::Grid::new(id)
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, add)
        .inner
}

/// The values that differ from the loaded preset, for marking their rows: each difference's field,
/// named as `app::edits` names it ("Speed", "gravity", "shape.Lens.radius", "size\[0\]",
/// "swell.heading deg"), with the preset's value as shown.
#[derive(Debug, Default)]
pub struct Marks {
    entries: Vec<(String, String)>,
    /// Which entries a drawn row has shown (differences without a row stay listed by the panel).
    shown: std::cell::RefCell<Vec<bool>>,
}

/// Colour of a row whose value differs from the loaded preset.
pub const MARK_COLOR: egui::Color32 = egui::Color32::from_rgb(255, 190, 70);

impl Marks {
    pub fn new<'a>(differences: impl IntoIterator<Item = (&'a str, &'a str)>) -> Self {
        let entries: Vec<(String, String)> = differences
            .into_iter()
            .map(|(f, v)| (f.to_owned(), v.to_owned()))
            .collect();
        let shown = std::cell::RefCell::new(vec![false; entries.len()]);
        Self { entries, shown }
    }

    /// The loaded preset's value for a row showing the fields `keys` (exact names), when any of
    /// them differs; several differing fields are joined.
    pub fn for_row(&self, keys: &[&str]) -> Option<String> {
        let mut shown = self.shown.borrow_mut();
        let mut values = Vec::new();
        for (i, (field, preset)) in self.entries.iter().enumerate() {
            if let Some(k) = keys.iter().find(|k| **k == field) {
                shown[i] = true;
                values.push(if keys.len() > 1 {
                    format!("{k} {preset}")
                } else {
                    preset.clone()
                });
            }
        }
        (!values.is_empty()).then(|| values.join(", "))
    }

    /// Whether a field outside those starting with one of `prefixes` differs.
    pub fn any_outside(&self, prefixes: &[&str]) -> bool {
        self.entries
            .iter()
            .any(|(f, _)| !prefixes.iter().any(|p| f.starts_with(p)))
    }

    /// The differing fields no drawn row has shown.
    pub fn unshown(&self) -> Vec<&str> {
        let shown = self.shown.borrow();
        self.entries
            .iter()
            .zip(shown.iter())
            .filter(|(_, s)| !**s)
            .map(|((f, _), _)| f.as_str())
            .collect()
    }
}

/// A row's label, marked (a dot, the mark colour, the preset's value in the tooltip) when one of
/// its fields `keys` differs from the loaded preset. Returns that value.
fn label_ui(ui: &mut Ui, marks: &Marks, keys: &[&str], label: &str, tip: &str) -> Option<String> {
    labelled_row_ui(ui, marks, keys, label, tip).0
}

/// [`label_ui`], also returning the label's id (what names the row's widget for a screen reader
/// and for the UI tests).
fn labelled_row_ui(
    ui: &mut Ui,
    marks: &Marks,
    keys: &[&str],
    label: &str,
    tip: &str,
) -> (Option<String>, egui::Id) {
    let preset = marks.for_row(keys);
    let id = match &preset {
        None => {
            let r = ui.label(label);
            if tip.is_empty() {
                r.id
            } else {
                r.on_hover_text(tip).id
            }
        }
        Some(v) => {
            ui.label(egui::RichText::new(format!("{label} •")).color(MARK_COLOR))
                .on_hover_text(marked_tip(tip, v))
                .id
        }
    };
    (preset, id)
}

/// A labelled row of radio buttons choosing `value` among `options` (value, label); true when
/// the choice changed.
fn choice_row_ui<T: PartialEq + Copy>(
    ui: &mut Ui,
    marks: &Marks,
    keys: &[&str],
    label: &str,
    tip: &str,
    value: &mut T,
    options: &[(T, &str)],
) -> bool {
    label_ui(ui, marks, keys, label, tip);
    let before = *value;
    ui.horizontal(|ui| {
        for &(option, text) in options {
            ui.radio_value(value, option, text);
        }
    });
    ui.end_row();
    before != *value
}

fn marked_tip(tip: &str, preset: &str) -> String {
    if tip.is_empty() {
        format!("Differs from the loaded preset: {preset}")
    } else {
        format!("{tip}\n\nDiffers from the loaded preset: {preset}")
    }
}

/// A dot after a widget outside a grid (a checkbox) whose field differs from the loaded preset.
fn dot_ui(ui: &mut Ui, marks: &Marks, key: &str) {
    if let Some(v) = marks.for_row(&[key]) {
        ui.label(egui::RichText::new("•").color(MARK_COLOR))
            .on_hover_text(marked_tip("", &v));
    }
}

fn row(
    ui: &mut Ui,
    marks: &Marks,
    key: &str,
    label: &str,
    tip: &str,
    add: impl FnOnce(&mut Ui) -> egui::Response,
) -> bool {
    let (preset, label_id) = labelled_row_ui(ui, marks, &[key], label, tip);
    // The row's own id: a banner or warning drawn above it never renumbers its widget (a field
    // being typed in keeps its focus).
    TYPED.with(|t| t.set(None));
    let mut r = ui.push_id(key, add).inner.labelled_by(label_id);
    // A typed value the range clamped says so, on a line of its own under the row, until the
    // row changes again.
    let note_id = ui.scope_id().with(("clamp note", key));
    match TYPED.with(std::cell::Cell::take) {
        Some((x, lo, hi)) => {
            let note = clamp_note(x, lo, hi);
            ui.data_mut(|d| match note {
                Some(n) => {
                    d.insert_temp(note_id, n);
                }
                None => d.remove::<String>(note_id),
            });
        }
        None if r.changed() => ui.data_mut(|d| d.remove::<String>(note_id)),
        None => {}
    }
    if !tip.is_empty() {
        r = r.on_hover_text(tip);
    }
    if let Some(v) = preset {
        r = r.on_hover_text(format!("Loaded preset: {v}"));
    }
    ui.end_row();
    if let Some(note) = ui.data(|d| d.get_temp::<String>(note_id)) {
        ui.label("");
        ui.label(egui::RichText::new(note).color(egui::Color32::from_rgb(255, 200, 120)));
        ui.end_row();
    }
    r.changed()
}

/// The world row: Earth, Moon, Mars or no air, each setting gravity and the air together.
fn world_ui(ui: &mut Ui, physics: &mut Physics) -> bool {
    ui.label("World").on_hover_text(
        "Sets gravity and the air together. On the Moon (1.62 m/s², no air) the stone falls \
             six times more gently: each hop lasts six times longer and goes six times farther \
             for the same speed, and with no air to slow it, it skips far",
    );
    let now = World::of(physics);
    let mut changed = false;
    ui.horizontal(|ui| {
        for w in World::ALL {
            if ui
                .selectable_label(now == Some(w), w.name())
                .on_hover_text(format!(
                    "gravity {} m/s², {}",
                    w.gravity(),
                    w.air_density()
                        .map_or("no air".to_owned(), |d| format!("air {d} kg/m³"))
                ))
                .clicked()
                && now != Some(w)
            {
                w.apply(physics);
                changed = true;
            }
        }
    });
    ui.end_row();
    changed
}

/// Launch: speed, elevation and heading of the throw, the stone's attitude, position and spin.
/// Rows whose value differs from `marks` (the loaded preset) are marked.
pub fn launch_ui(ui: &mut Ui, launch: &mut Launch, marks: &Marks) -> bool {
    let v = launch.velocity;
    let speed0 = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let mut speed = speed0.clamp(0.5, 40.0);
    let mut elevation = if speed0 > 1e-9 {
        (v[2] / speed0).clamp(-1.0, 1.0).asin().to_degrees()
    } else {
        0.0
    };
    let mut heading = if v[0].hypot(v[1]) > 1e-9 {
        v[1].atan2(v[0]).to_degrees()
    } else {
        launch.attitude.heading_deg
    };
    elevation = elevation.clamp(-60.0, 45.0);
    heading = heading.clamp(-90.0, 90.0);
    let mut spin_rev = (launch.spin / TAU).clamp(*ranges::SPIN.start(), *ranges::SPIN.end());
    let mut changed = false;
    let mut velocity_changed = false;
    let mut spin_changed = false;
    changed |= grid(ui, "launch", |ui| {
        let mut c = false;
        velocity_changed |= row(
            ui,
            marks,
            "Speed",
            "Speed",
            "Launch speed of the centre of mass",
            |ui| ui.add(slider(&mut speed, ranges::SPEED).suffix(" m/s")),
        );
        velocity_changed |= row(
            ui,
            marks,
            "Elevation",
            "Elevation",
            "Angle of the launch velocity above the horizontal (negative: thrown downwards)",
            |ui| ui.add(slider(&mut elevation, -60.0..=45.0).suffix("°")),
        );
        velocity_changed |= row(
            ui,
            marks,
            "Heading",
            "Heading",
            "Direction of the throw, from +x towards +y",
            |ui| ui.add(slider(&mut heading, -90.0..=90.0).suffix("°")),
        );
        let att = &mut launch.attitude;
        c |= row(
            ui,
            marks,
            "Tilt",
            "Tilt",
            "Attitude: raises the stone's leading (+x) edge — the attack angle; ~20° is the magic angle",
            |ui| ui.add(slider(&mut att.tilt_deg, ranges::TILT).suffix("°")),
        );
        c |= row(
            ui,
            marks,
            "Bank",
            "Bank",
            "Attitude: roll about the throw axis",
            |ui| ui.add(slider(&mut att.bank_deg, -60.0..=60.0).suffix("°")),
        );
        c |= row(
            ui,
            marks,
            "Turn",
            "Turn",
            "Attitude: the stone's heading about the vertical",
            |ui| ui.add(slider(&mut att.heading_deg, -180.0..=180.0).suffix("°")),
        );
        spin_changed |= row(
            ui,
            marks,
            "Spin",
            "Spin",
            "Spin about the stone's axis (stored in rad/s); it steadies a free stone",
            |ui| ui.add(slider(&mut spin_rev, ranges::SPIN).suffix(" rev/s")),
        );
        label_ui(
            ui,
            marks,
            &["Position x", "Position y", "Position z"],
            "Position",
            "Centre of mass at launch (m); z is the height above the water",
        );
        let p = &mut launch.position;
        let r = ui.horizontal(|ui| {
            let a = ui.add(
                egui::DragValue::new(&mut p[0])
                    .update_while_editing(false)
                    .custom_parser(parse_finite)
                    .range(-50.0..=50.0)
                    .speed(0.05)
                    .prefix("x "),
            );
            let b = ui.add(
                egui::DragValue::new(&mut p[1])
                    .update_while_editing(false)
                    .custom_parser(parse_finite)
                    .range(-50.0..=50.0)
                    .speed(0.05)
                    .prefix("y "),
            );
            let z = ui.add(
                egui::DragValue::new(&mut p[2])
                    .update_while_editing(false)
                    .custom_parser(parse_finite)
                    .range(ranges::HEIGHT)
                    .speed(0.01)
                    .prefix("z "),
            );
            a.changed() || b.changed() || z.changed()
        });
        c |= r.inner;
        ui.end_row();
        c
    });
    changed |= wobble_ui(ui, launch, marks);
    if velocity_changed {
        let (e, h) = (elevation.to_radians(), heading.to_radians());
        launch.velocity = [
            speed * e.cos() * h.cos(),
            speed * e.cos() * h.sin(),
            speed * e.sin(),
        ];
        changed = true;
    }
    if spin_changed {
        launch.spin = spin_rev * TAU;
        changed = true;
    }
    changed
}

/// The launch's extra angular velocity (world frame), in a collapsed section.
fn wobble_ui(ui: &mut Ui, launch: &mut Launch, marks: &Marks) -> bool {
    let mut c = false;
    let wobble = match marks.for_row(&["Wobble x", "Wobble y", "Wobble z"]) {
        Some(_) => egui::RichText::new("Wobble (angular velocity) •").color(MARK_COLOR),
        None => egui::RichText::new("Wobble (angular velocity)"),
    };
    egui::CollapsingHeader::new(wobble)
        .id_salt("wobble")
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                for (i, axis) in ["x", "y", "z"].iter().enumerate() {
                    c |= ui
                        .add(
                            egui::DragValue::new(&mut launch.angular_velocity[i])
                                .update_while_editing(false)
                                .custom_parser(parse_finite)
                                .range(-100.0..=100.0)
                                .speed(0.1)
                                .prefix(format!("{axis} ")),
                        )
                        .on_hover_text("rad/s, world frame, added to the spin")
                        .changed();
                }
            });
        });
    c
}

/// Stone: shape and size, mass, mesh resolution.
pub fn stone_ui(ui: &mut Ui, stone: &mut StoneParams, marks: &Marks) -> bool {
    let mut changed = false;
    let kind = stone.shape.kind_name();
    let radius = stone.shape.half_extent().clamp(0.01, 0.3);
    let thickness = stone.shape.thickness().clamp(0.001, 0.1);
    let shape_key = |field: &str| format!("shape.{kind}.{field}");
    let (k_radius, k_length) = (shape_key("radius"), shape_key("length"));
    let (k_width, k_thickness) = (shape_key("width"), shape_key("thickness"));
    let shape_preset = marks.for_row(&["shape"]);
    let shape_label = match shape_preset {
        Some(_) => egui::RichText::new("Shape •").color(MARK_COLOR).into(),
        None => egui::WidgetText::from("Shape"),
    };
    let shape_combo = egui::ComboBox::from_label(shape_label)
        .selected_text(kind)
        .show_ui(ui, |ui| {
            let options = [
                (
                    "Lens",
                    "Ellipsoid of revolution: a real pebble, the paper's stone",
                    Shape::Lens {
                        radius,
                        thickness: thickness.min(2.0 * radius),
                    },
                ),
                (
                    "Disk",
                    "Flat-faced cylinder: the literature's disc",
                    Shape::Disk {
                        radius,
                        thickness: thickness.min(2.0 * radius),
                    },
                ),
                (
                    "Plate",
                    "Thin box: Bocquet's square plate",
                    Shape::Plate {
                        length: (2.0 * radius).min(0.6),
                        width: (2.0 * radius).min(0.6),
                        thickness,
                    },
                ),
            ];
            for (name, tip, shape) in options {
                if ui
                    .selectable_label(kind == name, name)
                    .on_hover_text(tip)
                    .clicked()
                    && kind != name
                {
                    stone.shape = shape;
                    changed = true;
                }
            }
        });
    if let Some(v) = shape_preset {
        shape_combo.response.on_hover_text(marked_tip("", &v));
    }
    changed |= grid(ui, "stone", |ui| {
        let mut c = false;
        match &mut stone.shape {
            Shape::Disk { radius, thickness } | Shape::Lens { radius, thickness } => {
                c |= row(
                    ui,
                    marks,
                    &k_radius,
                    "Radius",
                    "Radius of the stone",
                    |ui| ui.add(slider(radius, 0.01..=0.3).suffix(" m")),
                );
                let max_t = (2.0 * *radius).min(0.1);
                c |= row(
                    ui,
                    marks,
                    &k_thickness,
                    "Thickness",
                    "At most the diameter",
                    |ui| ui.add(slider(thickness, 0.001..=max_t).suffix(" m")),
                );
                if *thickness > 2.0 * *radius {
                    *thickness = 2.0 * *radius;
                    c = true;
                }
            }
            Shape::Plate {
                length,
                width,
                thickness,
            } => {
                c |= row(
                    ui,
                    marks,
                    &k_length,
                    "Length",
                    "Along the stone's x axis",
                    |ui| ui.add(slider(length, 0.02..=0.6).suffix(" m")),
                );
                c |= row(ui, marks, &k_width, "Width", "Across", |ui| {
                    ui.add(slider(width, 0.02..=0.6).suffix(" m"))
                });
                c |= row(
                    ui,
                    marks,
                    &k_thickness,
                    "Thickness",
                    "Plate thickness",
                    |ui| ui.add(slider(thickness, 0.001..=0.1).suffix(" m")),
                );
            }
        }
        c |= row(
            ui,
            marks,
            "mass",
            "Mass",
            "Mass (the inertia follows from the mesh)",
            |ui| {
                ui.add(
                    slider(&mut stone.mass, ranges::MASS)
                        .logarithmic(true)
                        .suffix(" kg"),
                )
            },
        );
        c | mesh_rows_ui(ui, stone, marks)
    });
    changed
}

/// The mesh rows: segments around, and a lens's latitude bands.
fn mesh_rows_ui(ui: &mut Ui, stone: &mut StoneParams, marks: &Marks) -> bool {
    let mut c = row(
        ui,
        marks,
        "segments",
        "Mesh",
        "Rim resolution: segments around the stone",
        |ui| {
            ui.add(
                Slider::new(&mut stone.segments, 8..=128)
                    .update_while_editing(false)
                    .custom_parser(parse_finite)
                    .clamping(SliderClamping::Always)
                    .suffix(" segments"),
            )
        },
    );
    if matches!(stone.shape, Shape::Lens { .. }) {
        c |= row(
            ui,
            marks,
            "bands",
            "Bands",
            "Latitude bands of the lens, pole to pole (auto: half the segments)",
            |ui| bands_ui(ui, stone),
        );
        c |= row(
            ui,
            marks,
            "quadrature",
            "Forces on",
            "Where the force law is summed: every wetted triangle of the mesh, or the smooth lens \
             the mesh stands for (Gauss nodes along the wet latitudes × friction nodes around each \
             arc, the pressure exact around it; over flat water: with wavy contact the triangles carry \
             the load)",
            |ui| quadrature_ui(ui, stone),
        );
    }
    c
}

/// A lens's quadrature: its mesh's faces, or the smooth lens with its node counts.
fn quadrature_ui(ui: &mut Ui, stone: &mut StoneParams) -> egui::Response {
    ui.horizontal(|ui| {
        let mut smooth = !stone.quadrature.is_faces();
        let mut r = ui.checkbox(&mut smooth, "smooth lens");
        if r.changed() {
            stone.quadrature = if smooth {
                Quadrature::Smooth {
                    meridian: 12,
                    around: 2,
                }
            } else {
                Quadrature::Faces
            };
        }
        if let Quadrature::Smooth { meridian, around } = &mut stone.quadrature {
            for (n, suffix, tip) in [
                (
                    meridian,
                    " ×",
                    "Gauss nodes along the wet latitudes (per range)",
                ),
                (
                    around,
                    " nodes",
                    "Gauss nodes for the friction on each piece of a wet arc (the pressure is exact around it)",
                ),
            ] {
                let s = ui
                    .add(
                        egui::DragValue::new(n).update_while_editing(false)
                            .range(2..=64)
                            .custom_parser(parse_finite)
                            .suffix(suffix),
                    )
                    .on_hover_text(tip);
                r = r.union(s);
            }
        }
        r
    })
    .inner
}

/// A lens's latitude bands: "auto" (half the segments) or a count.
fn bands_ui(ui: &mut Ui, stone: &mut StoneParams) -> egui::Response {
    ui.horizontal(|ui| {
        let mut auto = stone.bands.is_none();
        let mut r = ui.checkbox(&mut auto, "auto");
        if r.changed() {
            stone.bands = if auto {
                None
            } else {
                Some(stoneskip_physics::sim::stone::lens_bands(stone.segments, None).min(128))
            };
        }
        if let Some(bands) = stone.bands.as_mut() {
            let s = ui.add(
                Slider::new(bands, 4..=128)
                    .update_while_editing(false)
                    .custom_parser(parse_finite)
                    .clamping(SliderClamping::Always)
                    .suffix(" bands"),
            );
            // The union carries the slider's `changed` into the row's response.
            r = r.union(s);
        }
        r
    })
    .inner
}

/// The physics fields a class changes, drawn first (their `app::edits` names' prefixes).
const CLASS_PHYSICS: &[&str] = &[
    "gravity",
    "water density",
    "wetted memory",
    "air",
    "rotation",
];

/// The physical constants, applied live: first what a class changes (gravity, the water, the
/// water's lag, the air, whether the stone turns), then, collapsed, the paper's laws and the
/// validation switches.
pub fn physics_ui(ui: &mut Ui, physics: &mut Physics, marks: &Marks) -> bool {
    let mut changed = false;
    changed |= grid(ui, "physics", |ui| {
        let mut c = world_ui(ui, physics);
        c |= row(ui, marks, "gravity", "Gravity", "g", |ui| {
            ui.add(slider(&mut physics.gravity, 0.0..=30.0).suffix(" m/s²"))
        });
        c |= row(
            ui,
            marks,
            "water density",
            "Water density",
            "ρ of the water",
            |ui| ui.add(slider(&mut physics.water_density, 100.0..=3000.0).suffix(" kg/m³")),
        );
        c |= memory_ui(ui, physics, marks);
        c |= air_ui(ui, physics, marks);
        c |= choice_row_ui(
            ui,
            marks,
            &["rotation"],
            "Rotation",
            "Locked: attitude held (the paper). Free: a rigid body with spin and torque.",
            &mut physics.rotation,
            &[(Rotation::Locked, "Locked"), (Rotation::Free, "Free")],
        );
        c
    });
    changed |= paper_group_ui(ui, physics, marks);
    changed
}

/// The Physics panel's collapsed group: the paper's laws, the loading options, the integrator,
/// the free body's variants and the tick. Marked (and open the first time) when a value in there
/// differs from the loaded preset.
fn paper_group_ui(ui: &mut Ui, physics: &mut Physics, marks: &Marks) -> bool {
    let mut changed = false;
    // Marked when a value in there differs from the preset (and open, the first time).
    let differs = marks.any_outside(CLASS_PHYSICS);
    let title = if differs {
        "Paper and validation •"
    } else {
        "Paper and validation"
    };
    egui::CollapsingHeader::new(title)
        .id_salt("physics_paper")
        .default_open(differs)
        .show(ui, |ui| {
            ui.weak(
                "The laws and numerical choices the studies compare. The shipped presets set \
                 them; a class rarely needs to.",
            );
            changed |= grid(ui, "physics paper", |ui| {
                let mut c = false;
        let label = labelled_row_ui(
            ui,
            marks,
            &["force law"],
            "Force law",
            "Rosellini: pressure C_l ρ U max(0, v_n) S (puts the magic angle near 20°); Paper: ½ C_l ρ v_n² S; \
             Bocquet: ½ C_l ρ U² S (his 2D model)",
        ).1;
        let before = physics.force_law;
        egui::ComboBox::from_id_salt("force_law")
            .selected_text(format!("{:?}", physics.force_law))
            .show_ui(ui, |ui| {
                for law in ForceLaw::ALL {
                    ui.selectable_value(&mut physics.force_law, law, format!("{law:?}"));
                }
            })
            .response
            .labelled_by(label);
        ui.end_row();
        c |= before != physics.force_law;
        let (dl, df) = physics.force_law.default_coefficients();
        c |= coefficient_row(
            ui,
            marks,
            ["lift coefficient", "C_l", "Lift (pressure) coefficient"],
            &mut physics.lift_coefficient,
            dl,
            0.0..=5.0,
        );
        c |= coefficient_row(
            ui,
            marks,
            ["friction coefficient", "C_f", "Friction coefficient"],
            &mut physics.friction_coefficient,
            df,
            0.0..=2.0,
        );
        let label = labelled_row_ui(
            ui,
            marks,
            &["ventilated"],
            "Ventilated",
            "Pressure and friction only on faces advancing into the water (the rear sits in an air cavity)",
        ).1;
        c |= ui
            .checkbox(&mut physics.ventilated, "")
            .labelled_by(label)
            .changed();
        ui.end_row();
        c |= loading_options_ui(ui, physics, marks);
        let label = labelled_row_ui(ui, marks, &["integrator"], "Integrator", "").1;
        let before = physics.integrator;
        egui::ComboBox::from_id_salt("integrator")
            .selected_text(format!("{:?}", physics.integrator))
            .show_ui(ui, |ui| {
                for i in Integrator::ALL {
                    ui.selectable_value(&mut physics.integrator, i, format!("{i:?}"));
                }
            })
            .response
            .labelled_by(label);
        ui.end_row();
        c |= before != physics.integrator;
        if physics.integrator == Integrator::Adaptive {
            c |= row(
                ui,
                marks,
                "tolerance",
                "Tolerance",
                "Adaptive's relative error per step",
                |ui| ui.add(slider(&mut physics.tolerance, 1e-10..=1e-3).logarithmic(true)),
            );
            let label = labelled_row_ui(
                ui,
                marks,
                &["steps across ticks"],
                "Steps across ticks",
                "Contact steps may end past the tick when no water takes the stone's loads (water \
                 off): fewer force evaluations, the stone up to one step ahead of the tick",
            )
            .1;
            c |= ui
                .checkbox(&mut physics.steps_across_ticks, "")
                .labelled_by(label)
                .changed();
            ui.end_row();
        }
        if physics.rotation == Rotation::Free {
            c |= free_body_rows_ui(ui, physics, marks);
        }
        c |= row(
            ui,
            marks,
            "dt",
            "Time step",
            "The tick: fixed step (Adaptive's upper bound)",
            |ui| {
                ui.add(
                    slider(&mut physics.dt, 5e-5..=0.02)
                        .logarithmic(true)
                        .custom_formatter(|v, _| format!("{:.3} ms", v * 1000.0)),
                )
            },
        );
        c |= row(
            ui,
            marks,
            "max time",
            "Max time",
            "The run ends (timeout) here",
            |ui| ui.add(slider(&mut physics.max_time, 1.0..=120.0).suffix(" s")),
        );
                c
            });
        });
    changed
}

/// The row that matters only for a free rigid body: the axial spin.
fn free_body_rows_ui(ui: &mut Ui, physics: &mut Physics, marks: &Marks) -> bool {
    let mut c = false;
    c |= choice_row_ui(
        ui,
        marks,
        &["axial spin"],
        "Axial spin",
        "Résal: the pebble is a smooth body of revolution, so its spin about its own axis moves \
                 no water normal to its surface (only friction feels it), and the mesh meets the water \
                 without turning with the spin (its facets held to the flow, so they do not ripple the \
                 force as they sweep past the waterline). Faceted: the mesh's flat facets paddle the \
                 water as they spin.",
        &mut physics.axial_spin,
        &[
            (AxialSpin::Resal, "Résal"),
            (AxialSpin::Faceted, "Faceted"),
        ],
    );
    c
}

/// A coefficient the law defaults: `field` is [field name, label, tooltip].
fn coefficient_row(
    ui: &mut Ui,
    marks: &Marks,
    field: [&str; 3],
    value: &mut Option<f64>,
    default: f64,
    range: std::ops::RangeInclusive<f64>,
) -> bool {
    let [key, name, tip] = field;
    let label = labelled_row_ui(ui, marks, &[key], name, tip).1;
    let mut changed = false;
    ui.horizontal(|ui| {
        let mut custom = value.is_some();
        if ui
            .checkbox(&mut custom, "")
            .labelled_by(label)
            .on_hover_text(format!("Set it; unchecked: the law's default {default}"))
            .changed()
        {
            *value = custom.then_some(default);
            changed = true;
        }
        match value {
            Some(v) => {
                changed |= ui.add(slider(v, range).logarithmic(false)).changed();
            }
            None => {
                ui.weak(format!("law default {default}"));
            }
        }
    });
    ui.end_row();
    changed
}

/// The water grid: these need a new simulation (applied at the next throw or reset).
pub fn water_ui(ui: &mut Ui, water: &mut WaterParams, marks: &Marks) -> bool {
    let mut changed = false;
    ui.horizontal(|ui| {
        changed |= ui
            .checkbox(&mut water.enabled, "Simulate the water (rings)")
            .on_hover_text("Off: a flat, rigid surface at z = 0")
            .changed();
        dot_ui(ui, marks, "enabled");
    });
    ui.horizontal(|ui| {
        changed |= ui
            .checkbox(&mut water.wavy_contact, "Wavy contact")
            .on_hover_text("The stone meets the simulated surface instead of z = 0")
            .changed();
        dot_ui(ui, marks, "wavy contact");
    });
    changed |= grid(ui, "water", |ui| {
        let mut c = false;
        c |= row(
            ui,
            marks,
            "size[0]",
            "Length",
            "Extent of the grid along x",
            |ui| {
                ui.add(
                    slider(&mut water.size[0], 2.0..=200.0)
                        .logarithmic(true)
                        .suffix(" m"),
                )
            },
        );
        c |= row(
            ui,
            marks,
            "size[1]",
            "Width",
            "Extent of the grid along y",
            |ui| {
                ui.add(
                    slider(&mut water.size[1], 2.0..=200.0)
                        .logarithmic(true)
                        .suffix(" m"),
                )
            },
        );
        // Cells: at least 4 across, at most MAX_WATER_COLUMNS in all.
        let area = water.size[0] * water.size[1];
        let min_cell = ((area / MAX_WATER_COLUMNS as f64).sqrt() * 1.02).max(0.005);
        let max_cell = (water.size[0].min(water.size[1]) / 4.5)
            .min(1.0)
            .max(min_cell);
        c |= row(
            ui,
            marks,
            "cell",
            "Cell",
            "Column size: finer shows smaller ripples, costs more",
            |ui| {
                ui.add(
                    slider(&mut water.cell, min_cell..=max_cell)
                        .logarithmic(true)
                        .suffix(" m"),
                )
            },
        );
        c |= row(
            ui,
            marks,
            "depth",
            "Depth",
            "Rest depth H: wave speed √(gH)",
            |ui| {
                ui.add(
                    slider(&mut water.depth, 0.02..=5.0)
                        .logarithmic(true)
                        .suffix(" m"),
                )
            },
        );
        c |= row(ui, marks, "damping", "Damping", "Per second", |ui| {
            ui.add(slider(&mut water.damping, 0.0..=5.0).suffix(" 1/s"))
        });
        c |= max_step_row(ui, marks, &mut water.max_step);
        label_ui(ui, marks, &["diagonal pipes"], "Pipes", "");
        c |= ui
            .checkbox(&mut water.diagonal_pipes, "diagonals (isotropic)")
            .changed();
        ui.end_row();
        let label = labelled_row_ui(
            ui,
            marks,
            &["limiter"],
            "Limiter",
            "MassConserving: exact volume, never negative (Mei et al.). PaperClamp: eq. 41, creates water",
        ).1;
        let before = water.limiter;
        egui::ComboBox::from_id_salt("limiter")
            .selected_text(format!("{:?}", water.limiter))
            .show_ui(ui, |ui| {
                ui.selectable_value(
                    &mut water.limiter,
                    Limiter::MassConserving,
                    "MassConserving",
                );
                ui.selectable_value(&mut water.limiter, Limiter::PaperClamp, "PaperClamp");
            })
            .response
            .labelled_by(label);
        ui.end_row();
        c |= before != water.limiter;
        let label = labelled_row_ui(
            ui,
            marks,
            &["precision"],
            "Precision",
            "Storage of depths and flows: F32 halves the memory traffic; F64 conserves volume to rounding",
        ).1;
        let before = water.precision;
        egui::ComboBox::from_id_salt("precision")
            .selected_text(format!("{:?}", water.precision))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut water.precision, Precision::F32, "F32");
                ui.selectable_value(&mut water.precision, Precision::F64, "F64");
            })
            .response
            .labelled_by(label);
        ui.end_row();
        c |= before != water.precision;
        c
    });
    changed |= swell_ui(ui, water, marks);
    changed
}

/// The columns' longest step: unchecked, the automatic one under the Courant limit; checked, at
/// most the slider's (fidelity study §11 refines it with the tick).
fn max_step_row(ui: &mut Ui, marks: &Marks, max_step: &mut Option<f64>) -> bool {
    let label = labelled_row_ui(
        ui,
        marks,
        &["max step"],
        "Water step",
        "The columns' longest step. Unchecked: 70 % of the Courant limit. A shorter step is always \
         stable, costs more, and lets the water answer the stone sooner",
    ).1;
    let mut changed = false;
    ui.horizontal(|ui| {
        let mut capped = max_step.is_some();
        if ui
            .checkbox(&mut capped, "")
            .labelled_by(label)
            .on_hover_text("At most this step; unchecked: the automatic step")
            .changed()
        {
            *max_step = capped.then_some(1e-3);
            changed = true;
        }
        match max_step {
            Some(v) => {
                let mut ms = *v * 1e3;
                if ui
                    .add(
                        slider(&mut ms, 0.01..=100.0)
                            .logarithmic(true)
                            .suffix(" ms"),
                    )
                    .changed()
                {
                    *v = ms * 1e-3;
                    changed = true;
                }
            }
            None => {
                ui.weak("automatic (Courant)");
            }
        }
    });
    ui.end_row();
    changed
}

/// The swell: on or off, and its amplitude (at most half the depth), wavelength and direction.
fn swell_ui(ui: &mut Ui, water: &mut WaterParams, marks: &Marks) -> bool {
    let mut changed = false;
    let mut swell = water.swell.is_some();
    ui.horizontal(|ui| {
        if ui.checkbox(&mut swell, "Swell (a wavy lake)").changed() {
            water.swell = swell.then(Swell::default);
            changed = true;
        }
        dot_ui(ui, marks, "swell");
    });
    let depth = water.depth;
    if let Some(s) = water.swell.as_mut() {
        changed |= grid(ui, "swell", |ui| {
            let mut c = false;
            c |= row(
                ui,
                marks,
                "swell.amplitude",
                "Amplitude",
                "At most half the depth",
                |ui| ui.add(slider(&mut s.amplitude, 0.0..=(0.5 * depth).min(0.3)).suffix(" m")),
            );
            c |= row(ui, marks, "swell.wavelength", "Wavelength", "", |ui| {
                ui.add(
                    slider(&mut s.wavelength, 0.2..=30.0)
                        .logarithmic(true)
                        .suffix(" m"),
                )
            });
            c |= row(
                ui,
                marks,
                "swell.heading deg",
                "Direction",
                "The swell travels this way, from +x",
                |ui| ui.add(slider(&mut s.heading_deg, -180.0..=180.0).suffix("°")),
            );
            c
        });
        if s.amplitude > 0.5 * depth {
            s.amplitude = 0.5 * depth;
            changed = true;
        }
    }
    changed
}

/// What the view draws besides the physics.
pub fn display_ui(ui: &mut Ui, view: &mut ViewSettings) {
    ui.checkbox(&mut view.show_trail, "Trajectory trail");
    ui.checkbox(
        &mut view.show_markers,
        "Contact markers (green: skip, red: did not leave the water)",
    );
    ui.checkbox(&mut view.show_splashes, "Splash cues");
    ui.horizontal(|ui| {
        let label = ui.label("Ripple contrast").on_hover_text(
            "Multiplies the water's slopes in the shading only (1 = true to the simulation)",
        );
        ui.add(
            Slider::new(&mut view.ripple_gain, 0.0..=5.0)
                .update_while_editing(false)
                .custom_parser(parse_finite)
                .clamping(SliderClamping::Always)
                .suffix("×"),
        )
        .labelled_by(label.id);
    });
    ui.horizontal(|ui| {
        let label = ui.label("Render scale").on_hover_text(
            "Resolution of the 3D view while the throw animates (stills are always sharp); \
             lower it on a software renderer for a smoother picture",
        );
        ui.add(
            Slider::new(&mut view.render_scale, 0.25..=1.0)
                .update_while_editing(false)
                .custom_parser(parse_finite)
                .clamping(SliderClamping::Always)
                .custom_formatter(|v, _| format!("{:.0} %", v * 100.0)),
        )
        .labelled_by(label.id);
    });
}

/// The wetted-extent memory (issue 38, `sim/memory.rs`): on or off, its λ and its length.
fn memory_ui(ui: &mut Ui, physics: &mut Physics, marks: &Marks) -> bool {
    let mut c = false;
    let label = labelled_row_ui(
        ui,
        marks,
        &["wetted memory"],
        "Water's lag",
        "The water under a fast stone takes a moment to rise and to fall back, so the wet patch \
         lags the stone's motion. This stops a fast stone from gliding flat along the surface, \
         and makes a whole throw come out the same at any time step. Off: the paper's contact; \
         fast throws then end in a long glide. (τ = λ L/|U|, L the wet patch's length along the \
         flow: Wagner 1932; Hewitt et al. 2011.)",
    )
    .1;
    let mut on = physics.wetted_memory.is_some();
    if ui.checkbox(&mut on, "").labelled_by(label).changed() {
        physics.wetted_memory = on.then(MemoryParams::default);
        c = true;
    }
    ui.end_row();
    if let Some(memory) = physics.wetted_memory.as_mut() {
        c |= row(
            ui,
            marks,
            "wetted memory.lag",
            "λ",
            "The lag in units of L/|U|: about 1–3 from the Wagner strip; the shipped 2",
            |ui| ui.add(slider(&mut memory.lag, 0.1..=10.0).logarithmic(true)),
        );
        c |= choice_row_ui(
            ui,
            marks,
            &["wetted memory.length"],
            "Lag length L",
            "Wetted: the patch's geometric length along the flow (the transit time, shipped). \
             Radius: the stone's radius (the reduced form τ = κ R/|U| of the first analysis).",
            &mut memory.length,
            &[(LagLength::Wetted, "Wetted"), (LagLength::Radius, "Radius")],
        );
        c |= impact_memory_ui(ui, marks, memory);
    }
    c
}

/// The memory's two impact options (issue 47): the lag shortened at a fast-growing patch (the
/// Wagner strip's Π_c) and Wagner's entry lead. With both Clanet's disc bounces as he measured; a
/// whole throw then ends in a long glide (docs/studies/first_bounce).
fn impact_memory_ui(ui: &mut Ui, marks: &Marks, memory: &mut MemoryParams) -> bool {
    let mut strip = memory.strip_frequency.is_some();
    let mut c = row(
        ui,
        marks,
        "wetted memory.strip frequency",
        "Shorter lag at impact",
        "On: the lag shrinks when the wet patch grows fast, as at a hard first touch \
         (τ = λ L/(|U|(1 + Π/Π_c)), Π the patch's growth over the speed; the Wagner strip's \
         Π_c is 0.12, a larger one keeps more lag). Clanet's single bounce then lasts as he \
         measured; whole throws glide.",
        |ui| {
            ui.horizontal(|ui| {
                let mut r = ui.checkbox(&mut strip, "");
                if let Some(pc) = memory.strip_frequency.as_mut() {
                    r |= ui.add(slider(pc, 0.01..=10.0).logarithmic(true).text("Π_c"));
                }
                r
            })
            .inner
        },
    );
    if strip != memory.strip_frequency.is_some() {
        memory.strip_frequency = strip.then_some(STRIP_FREQUENCY);
        c = true;
    }
    c |= row(
        ui,
        marks,
        "wetted memory.entry lead",
        "Entry lead A",
        "How far the wet patch runs ahead of the stone while it goes in (Wagner 1932): 0 off, \
         ¾ a plate with a clean trailing edge, 4/3 a plate from a fixed edge",
        |ui| ui.add(slider(&mut memory.entry_lead, 0.0..=2.0)),
    );
    c
}

/// The Wagner strip's Π_c (docs/studies/wagner_lag): the value the Physics panel turns on.
const STRIP_FREQUENCY: f64 = 0.12;

/// The air in flight (`air.rs`): on or off, and its density and coefficients when on.
fn air_ui(ui: &mut Ui, physics: &mut Physics, marks: &Marks) -> bool {
    let mut c = false;
    let label = labelled_row_ui(
        ui,
        marks,
        &["air"],
        "Air in flight",
        "Lift, drag and the pitching moment of a spinning disc between contacts (Crowther & Potts \
         2007; Hummel 2003's coefficients, a lens has no camber). The moment rolls a slowly spun \
         stone in the air. Off: a vacuum, the paper's parabola.",
    )
    .1;
    let mut on = physics.air.is_some();
    if ui.checkbox(&mut on, "").labelled_by(label).changed() {
        physics.air = on.then(AirParams::default);
        c = true;
    }
    ui.end_row();
    if let Some(air) = physics.air.as_mut() {
        type AirRow<'a> = (
            &'a str,
            &'a str,
            &'a str,
            &'a mut f64,
            std::ops::RangeInclusive<f64>,
            &'a str,
        );
        let rows: [AirRow; 5] = [
            (
                "air.density",
                "Air density",
                "ρ of the air",
                &mut air.density,
                0.0..=5.0,
                " kg/m³",
            ),
            (
                "air.lift slope",
                "C_Lα",
                "Lift per radian of attack",
                &mut air.lift_slope,
                0.0..=5.0,
                " /rad",
            ),
            (
                "air.drag zero",
                "C_D0",
                "Drag at zero attack",
                &mut air.drag_zero,
                0.0..=1.0,
                "",
            ),
            (
                "air.drag slope",
                "C_Dα",
                "Drag per radian² of attack",
                &mut air.drag_slope,
                0.0..=5.0,
                " /rad²",
            ),
            (
                "air.moment slope",
                "C_Mα",
                "Pitching moment per radian of attack (nose up: the centre of pressure ahead)",
                &mut air.moment_slope,
                -2.0..=2.0,
                " /rad",
            ),
        ];
        for (key, label, tip, value, range, unit) in rows {
            c |= row(ui, marks, key, label, tip, |ui| {
                ui.add(slider(value, range).suffix(unit))
            });
        }
    }
    c
}

/// The options of how faces are loaded (issue 11): receding faces without ventilation, buoyancy.
fn loading_options_ui(ui: &mut Ui, physics: &mut Physics, marks: &Marks) -> bool {
    let mut c = false;
    if !physics.ventilated {
        c |= choice_row_ui(
            ui,
            marks,
            &["pressure sign"],
            "Receding faces",
            "As printed (the paper's eq. 19): a wetted face moving out of the water is still pushed along −N, which gives the stone energy. Opposes motion: each face's pressure opposes its own normal velocity (never gains energy).",
            &mut physics.pressure_sign,
            &[
                (PressureSign::AsPrinted, "As printed"),
                (PressureSign::OpposesMotion, "Opposes motion"),
            ],
        );
    }
    let label = labelled_row_ui(
        ui,
        marks,
        &["buoyancy"],
        "Buoyancy",
        "Hydrostatic pressure ρ g d on the wetted faces (Archimedes): matters once the stone is deep",
    ).1;
    c |= ui
        .checkbox(&mut physics.buoyancy, "")
        .labelled_by(label)
        .changed();
    ui.end_row();
    if physics.buoyancy {
        c |= choice_row_ui(
            ui,
            marks,
            &["hydrostatic"],
            "Hydrostatic on",
            "Wetted faces: every wetted face carries ρ g d, so a submerged stone feels Archimedes' \
             ρ g V (ventilation removes only the dynamic pressure and friction). Loaded faces: only \
             the faces carrying the dynamic pressure, the older model (a ventilated, submerged stone \
             then switches its buoyancy on and off).",
            &mut physics.hydrostatic,
            &[
                (Hydrostatic::WettedFaces, "Wetted faces"),
                (Hydrostatic::LoadedFaces, "Loaded faces"),
            ],
        );
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typing_nan_or_inf_keeps_the_old_value() {
        // egui keeps a field's value when its parser returns None.
        for bad in [
            "nan", "NaN", "-nan", "inf", "-inf", "infinity", "1e400", "", "abc",
        ] {
            assert_eq!(parse_finite(bad), None, "{bad}");
        }
        assert_eq!(parse_finite(" 3.5 "), Some(3.5));
        assert_eq!(parse_finite("20°"), Some(20.0));
        assert_eq!(parse_finite("-1e-3"), Some(-1e-3));
    }

    /// Types `text` into a slider's value box as a user does (click the number, clear it, type,
    /// Enter) and returns the value afterwards.
    fn type_into_slider(start: f64, text: &str) -> f64 {
        let ctx = egui::Context::default();
        let mut value = start;
        let mut t = 0.0;
        let mut frame = |events: Vec<egui::Event>, value: &mut f64| -> egui::Rect {
            t += 0.1;
            let input = egui::RawInput {
                screen_rect: Some(egui::Rect::from_min_size(
                    egui::Pos2::ZERO,
                    egui::vec2(800.0, 600.0),
                )),
                time: Some(t),
                events,
                ..Default::default()
            };
            let mut rect = egui::Rect::NOTHING;
            let mut out = ctx.run_ui(input, |ui| {
                rect = ui.add(slider(value, 0.5..=40.0).suffix(" m/s")).rect;
            });
            out.textures_delta.clear();
            rect
        };
        let rect = frame(vec![], &mut value);
        // The value box is at the slider's right end.
        let p = egui::pos2(rect.right() - 12.0, rect.center().y);
        let button = |pressed| egui::Event::PointerButton {
            pos: p,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        };
        let key = |key| egui::Event::Key {
            key,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers: egui::Modifiers::NONE,
        };
        frame(vec![egui::Event::PointerMoved(p), button(true)], &mut value);
        frame(vec![button(false)], &mut value);
        frame(vec![], &mut value);
        let mut typing: Vec<egui::Event> = (0..16).map(|_| key(egui::Key::Backspace)).collect();
        typing.extend((0..16).map(|_| key(egui::Key::Delete)));
        typing.push(egui::Event::Text(text.to_owned()));
        frame(typing, &mut value);
        frame(vec![key(egui::Key::Enter)], &mut value);
        frame(vec![], &mut value);
        value
    }

    use crate::app::edits::{launch_differences, section_differences, Difference};
    use stoneskip_physics::sim::params::Preset;

    fn marks_of(d: &[Difference]) -> Marks {
        Marks::new(d.iter().map(|d| (d.field.as_str(), d.preset.as_str())))
    }

    /// Draws `panel` once in a bare egui context (as the app does each frame).
    fn draw(panel: impl FnMut(&mut Ui)) {
        let ctx = egui::Context::default();
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(800.0, 2000.0),
            )),
            ..Default::default()
        };
        let mut panel = panel;
        let mut out = ctx.run_ui(input, |ui| panel(ui));
        out.textures_delta.clear();
    }

    #[test]
    fn marks_pick_the_rows_that_differ_with_the_presets_value() {
        let p = Preset::version_1();
        let mut launch = p.launch;
        let v = glam::DVec3::from_array(launch.velocity);
        launch.velocity = (v * 14.0 / v.length()).to_array();
        launch.angular_velocity[1] = 3.0;
        let m = marks_of(&launch_differences(&p.launch, &launch));
        let speed = m.for_row(&["Speed"]).expect("Speed differs");
        assert!(
            speed.starts_with(&format!("{}", v.length().round())),
            "{speed}"
        );
        assert_eq!(m.for_row(&["Tilt"]), None);
        assert_eq!(
            m.for_row(&["Heading"]),
            None,
            "turning nothing marks nothing"
        );
        assert_eq!(
            m.for_row(&["Wobble x", "Wobble y", "Wobble z"]).as_deref(),
            Some("Wobble y 0 rad/s")
        );
        let mut physics = p.physics;
        physics.gravity = 1.62;
        let m = marks_of(&section_differences(&p.physics, &physics));
        assert_eq!(
            m.for_row(&["gravity"]),
            Some(format!("{}", p.physics.gravity))
        );
        assert_eq!(m.for_row(&["water density"]), None);
        assert_eq!(m.for_row(&["dt"]), None);
        // A swell added: its checkbox is marked (the preset had none), not its rows.
        let mut water = p.water;
        water.swell = Some(Swell::default());
        let m = marks_of(&section_differences(&p.water, &water));
        assert_eq!(m.for_row(&["swell"]).as_deref(), Some("none"));
        assert_eq!(m.for_row(&["swell.amplitude"]), None);
        // Nothing changed: no row is marked.
        let m = marks_of(&section_differences(&p.water, &p.water));
        assert_eq!(m.for_row(&["cell"]), None);
        assert!(m.unshown().is_empty());
    }

    /// Every value a panel can change, changed at once: each difference lands on a drawn row (the
    /// rows' field names match the names `app::edits` gives), none is left unmarked.
    #[test]
    fn every_difference_a_panel_can_make_is_marked_on_its_row() {
        let mut p = Preset::version_1();
        p.physics.rotation = Rotation::Free;
        p.physics.integrator = Integrator::Adaptive;
        p.physics.ventilated = false;
        p.water.swell = Some(Swell::default());
        let mut l = p.launch;
        l.velocity = [9.0, 1.0, 2.0];
        l.attitude.tilt_deg += 1.0;
        l.attitude.bank_deg += 1.0;
        l.attitude.heading_deg += 1.0;
        l.spin += 1.0;
        l.position = [0.5, 0.5, 0.5];
        l.angular_velocity = [1.0, 2.0, 3.0];
        let mut stone = p.stone.clone();
        stone.shape = match stone.shape {
            Shape::Lens { radius, thickness } => Shape::Lens {
                radius: radius * 1.1,
                thickness: thickness * 1.1,
            },
            other => other,
        };
        stone.mass *= 1.5;
        stone.segments += 8;
        stone.bands = Some(20);
        let mut ph = p.physics;
        ph.gravity = 5.0;
        ph.water_density = 900.0;
        ph.force_law = ForceLaw::Bocquet;
        ph.lift_coefficient = Some(1.0);
        ph.friction_coefficient = Some(0.5);
        ph.pressure_sign = PressureSign::OpposesMotion;
        ph.buoyancy = true;
        ph.hydrostatic = match ph.hydrostatic {
            Hydrostatic::WettedFaces => Hydrostatic::LoadedFaces,
            Hydrostatic::LoadedFaces => Hydrostatic::WettedFaces,
        };
        ph.tolerance *= 10.0;
        ph.steps_across_ticks = true;
        ph.air = Some(AirParams::default());
        ph.axial_spin = match ph.axial_spin {
            AxialSpin::Resal => AxialSpin::Faceted,
            AxialSpin::Faceted => AxialSpin::Resal,
        };
        ph.dt *= 0.5;
        ph.max_time += 1.0;
        ph.wetted_memory = Some(MemoryParams {
            lag: 3.0,
            length: match ph.wetted_memory.map(|m| m.length) {
                Some(LagLength::Wetted) => LagLength::Radius,
                _ => LagLength::Wetted,
            },
            strip_frequency: Some(0.5),
            entry_lead: 0.5,
        });
        let mut w = p.water;
        w.enabled = !w.enabled;
        w.wavy_contact = !w.wavy_contact;
        w.size = [30.0, 10.0];
        w.cell *= 1.5;
        w.depth *= 1.5;
        w.damping += 0.1;
        w.diagonal_pipes = !w.diagonal_pipes;
        w.limiter = Limiter::PaperClamp;
        w.precision = Precision::F64;
        w.max_step = Some(5e-4);
        w.swell = Some(Swell {
            amplitude: 0.03,
            wavelength: 2.0,
            heading_deg: 45.0,
        });
        let d = [
            launch_differences(&p.launch, &l),
            section_differences(&p.stone, &stone),
            section_differences(&p.physics, &ph),
            section_differences(&p.water, &w),
        ];
        let counts: Vec<usize> = d.iter().map(Vec::len).collect();
        assert_eq!(counts, [13, 5, 15, 14], "{d:?}");
        let m: Vec<Marks> = d.iter().map(|d| marks_of(d)).collect();
        draw(|ui| {
            launch_ui(ui, &mut l, &m[0]);
            stone_ui(ui, &mut stone, &m[1]);
            physics_ui(ui, &mut ph, &m[2]);
            water_ui(ui, &mut w, &m[3]);
        });
        for (section, marks) in ["launch", "stone", "physics", "water"].iter().zip(&m) {
            assert!(
                marks.unshown().is_empty(),
                "{section}: {:?}",
                marks.unshown()
            );
        }
        // The rest: ventilation (it hides "Receding faces"), rotation and integrator (they hide
        // the free stone's and Adaptive's rows), another shape.
        let mut ph2 = p.physics;
        ph2.ventilated = true;
        ph2.rotation = Rotation::Locked;
        ph2.integrator = Integrator::Rk4;
        let mut stone2 = p.stone.clone();
        stone2.shape = Shape::Plate {
            length: 0.1,
            width: 0.08,
            thickness: 0.01,
        };
        let m2 = marks_of(&section_differences(&p.physics, &ph2));
        let m3 = marks_of(&section_differences(&p.stone, &stone2));
        draw(|ui| {
            physics_ui(ui, &mut ph2, &m2);
            stone_ui(ui, &mut stone2, &m3);
        });
        assert!(m2.unshown().is_empty(), "{:?}", m2.unshown());
        assert_eq!(m2.for_row(&["rotation"]).as_deref(), Some("Free"));
        assert!(m3.unshown().is_empty(), "{:?}", m3.unshown());
    }

    /// Every water step the validator accepts survives being drawn: the slider's range holds the
    /// validator's, so showing a preset never changes it.
    #[test]
    fn drawing_the_water_step_keeps_every_valid_setting() {
        for step in [1e-5, 2e-3, 0.1] {
            let mut w = WaterParams {
                wavy_contact: true,
                max_step: Some(step),
                ..WaterParams::version_1()
            };
            assert!(w.validate().is_ok());
            let before = w;
            draw(|ui| {
                water_ui(ui, &mut w, &Marks::default());
            });
            assert_eq!(w, before);
        }
    }

    #[test]
    fn typing_into_a_slider_takes_numbers_and_refuses_nan() {
        // The typing path works: a number is taken …
        assert_eq!(type_into_slider(12.5, "20"), 20.0);
        // … "nan" and "inf" keep the old value (they used to set the maximum).
        assert_eq!(type_into_slider(12.5, "nan"), 12.5);
        assert_eq!(type_into_slider(12.5, "inf"), 12.5);
    }
}
