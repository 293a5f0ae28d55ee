//! Settings panels: the launch, the stone, the physical constants (live), the water (next throw)
//! and the display. Each returns whether it changed anything. Ranges stay inside
//! `Preset::validate`'s; degrees and rev/s are shown, radians and rad/s stored.

use egui::{Slider, SliderClamping, Ui};

use crate::sim::params::{
    AxialSpin, ForceLaw, Integrator, Launch, Limiter, Physics, Precision, PressureCentre,
    PressureSign, Rotation, Shape, StoneParams, Swell, WaterParams, MAX_WATER_COLUMNS,
    SAVITSKY_CENTRE,
};

use super::ViewSettings;

const TAU: f64 = std::f64::consts::TAU;

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

fn slider<'a>(value: &'a mut f64, range: std::ops::RangeInclusive<f64>) -> Slider<'a> {
    Slider::new(value, range)
        .clamping(SliderClamping::Always)
        .custom_parser(parse_finite)
}

fn grid(ui: &mut Ui, id: &str, add: impl FnOnce(&mut Ui) -> bool) -> bool {
    egui::Grid::new(id)
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, add)
        .inner
}

fn row(ui: &mut Ui, label: &str, tip: &str, add: impl FnOnce(&mut Ui) -> egui::Response) -> bool {
    ui.label(label).on_hover_text(tip);
    let changed = add(ui).on_hover_text(tip).changed();
    ui.end_row();
    changed
}

/// Launch: speed, elevation and heading of the throw, the stone's attitude, position and spin.
pub fn launch_ui(ui: &mut Ui, launch: &mut Launch) -> bool {
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
    let mut spin_rev = (launch.spin / TAU).clamp(-75.0, 75.0);
    let mut changed = false;
    let mut velocity_changed = false;
    let mut spin_changed = false;
    changed |= grid(ui, "launch", |ui| {
        let mut c = false;
        velocity_changed |= row(ui, "Speed", "Launch speed of the centre of mass", |ui| {
            ui.add(slider(&mut speed, 0.5..=40.0).suffix(" m/s"))
        });
        velocity_changed |= row(
            ui,
            "Elevation",
            "Angle of the launch velocity above the horizontal (negative: thrown downwards)",
            |ui| ui.add(slider(&mut elevation, -60.0..=45.0).suffix("°")),
        );
        velocity_changed |= row(
            ui,
            "Heading",
            "Direction of the throw, from +x towards +y",
            |ui| ui.add(slider(&mut heading, -90.0..=90.0).suffix("°")),
        );
        let att = &mut launch.attitude;
        c |= row(
            ui,
            "Tilt",
            "Attitude: raises the stone's leading (+x) edge — the attack angle; ~20° is the magic angle",
            |ui| ui.add(slider(&mut att.tilt_deg, -45.0..=75.0).suffix("°")),
        );
        c |= row(ui, "Bank", "Attitude: roll about the throw axis", |ui| {
            ui.add(slider(&mut att.bank_deg, -60.0..=60.0).suffix("°"))
        });
        c |= row(
            ui,
            "Turn",
            "Attitude: the stone's heading about the vertical",
            |ui| ui.add(slider(&mut att.heading_deg, -180.0..=180.0).suffix("°")),
        );
        spin_changed |= row(
            ui,
            "Spin",
            "Spin about the stone's axis (stored in rad/s); it steadies a free stone",
            |ui| ui.add(slider(&mut spin_rev, -75.0..=75.0).suffix(" rev/s")),
        );
        ui.label("Position")
            .on_hover_text("Centre of mass at launch (m); z is the height above the water");
        let p = &mut launch.position;
        let r = ui.horizontal(|ui| {
            let a = ui.add(
                egui::DragValue::new(&mut p[0])
                    .custom_parser(parse_finite)
                    .range(-50.0..=50.0)
                    .speed(0.05)
                    .prefix("x "),
            );
            let b = ui.add(
                egui::DragValue::new(&mut p[1])
                    .custom_parser(parse_finite)
                    .range(-50.0..=50.0)
                    .speed(0.05)
                    .prefix("y "),
            );
            let z = ui.add(
                egui::DragValue::new(&mut p[2])
                    .custom_parser(parse_finite)
                    .range(0.0..=5.0)
                    .speed(0.01)
                    .prefix("z "),
            );
            a.changed() || b.changed() || z.changed()
        });
        c |= r.inner;
        ui.end_row();
        c
    });
    egui::CollapsingHeader::new("Wobble (angular velocity)")
        .id_salt("wobble")
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                for (i, axis) in ["x", "y", "z"].iter().enumerate() {
                    changed |= ui
                        .add(
                            egui::DragValue::new(&mut launch.angular_velocity[i])
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

/// Stone: shape and size, mass, mesh resolution.
pub fn stone_ui(ui: &mut Ui, stone: &mut StoneParams) -> bool {
    let mut changed = false;
    let kind = stone.shape.kind_name();
    let radius = stone.shape.half_extent().clamp(0.01, 0.3);
    let thickness = stone.shape.thickness().clamp(0.001, 0.1);
    egui::ComboBox::from_label("Shape")
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
    changed |= grid(ui, "stone", |ui| {
        let mut c = false;
        match &mut stone.shape {
            Shape::Disk { radius, thickness } | Shape::Lens { radius, thickness } => {
                c |= row(ui, "Radius", "Radius of the stone", |ui| {
                    ui.add(slider(radius, 0.01..=0.3).suffix(" m"))
                });
                let max_t = (2.0 * *radius).min(0.1);
                c |= row(ui, "Thickness", "At most the diameter", |ui| {
                    ui.add(slider(thickness, 0.001..=max_t).suffix(" m"))
                });
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
                c |= row(ui, "Length", "Along the stone's x axis", |ui| {
                    ui.add(slider(length, 0.02..=0.6).suffix(" m"))
                });
                c |= row(ui, "Width", "Across", |ui| {
                    ui.add(slider(width, 0.02..=0.6).suffix(" m"))
                });
                c |= row(ui, "Thickness", "Plate thickness", |ui| {
                    ui.add(slider(thickness, 0.001..=0.1).suffix(" m"))
                });
            }
        }
        c |= row(
            ui,
            "Mass",
            "Mass (the inertia follows from the mesh)",
            |ui| {
                ui.add(
                    slider(&mut stone.mass, 0.005..=3.0)
                        .logarithmic(true)
                        .suffix(" kg"),
                )
            },
        );
        c |= row(
            ui,
            "Mesh",
            "Rim resolution: segments around the stone",
            |ui| {
                ui.add(
                    Slider::new(&mut stone.segments, 8..=128)
                        .custom_parser(parse_finite)
                        .clamping(SliderClamping::Always)
                        .suffix(" segments"),
                )
            },
        );
        c
    });
    changed
}

/// Physical constants, force law and integrator: applied live at the next step.
pub fn physics_ui(ui: &mut Ui, physics: &mut Physics) -> bool {
    let mut changed = false;
    changed |= grid(ui, "physics", |ui| {
        let mut c = false;
        c |= row(ui, "Gravity", "g", |ui| {
            ui.add(slider(&mut physics.gravity, 0.0..=30.0).suffix(" m/s²"))
        });
        c |= row(ui, "Water density", "ρ of the water", |ui| {
            ui.add(slider(&mut physics.water_density, 100.0..=3000.0).suffix(" kg/m³"))
        });
        ui.label("Force law").on_hover_text(
            "Rosellini: pressure C_l ρ U max(0, v_n) S (puts the magic angle near 20°); Paper: ½ C_l ρ v_n² S; \
             Bocquet: ½ C_l ρ U² S (his 2D model)",
        );
        let before = physics.force_law;
        egui::ComboBox::from_id_salt("force_law")
            .selected_text(format!("{:?}", physics.force_law))
            .show_ui(ui, |ui| {
                for law in ForceLaw::ALL {
                    ui.selectable_value(&mut physics.force_law, law, format!("{law:?}"));
                }
            });
        ui.end_row();
        c |= before != physics.force_law;
        let (dl, df) = physics.force_law.default_coefficients();
        c |= coefficient_row(
            ui,
            "C_l",
            "Lift (pressure) coefficient",
            &mut physics.lift_coefficient,
            dl,
            0.0..=5.0,
        );
        c |= coefficient_row(
            ui,
            "C_f",
            "Friction coefficient",
            &mut physics.friction_coefficient,
            df,
            0.0..=2.0,
        );
        ui.label("Ventilated").on_hover_text(
            "Pressure and friction only on faces advancing into the water (the rear sits in an air cavity)",
        );
        c |= ui.checkbox(&mut physics.ventilated, "").changed();
        ui.end_row();
        c |= loading_options_ui(ui, physics);
        ui.label("Integrator");
        let before = physics.integrator;
        egui::ComboBox::from_id_salt("integrator")
            .selected_text(format!("{:?}", physics.integrator))
            .show_ui(ui, |ui| {
                for i in Integrator::ALL {
                    ui.selectable_value(&mut physics.integrator, i, format!("{i:?}"));
                }
            });
        ui.end_row();
        c |= before != physics.integrator;
        if physics.integrator == Integrator::Adaptive {
            c |= row(
                ui,
                "Tolerance",
                "Adaptive's relative error per step",
                |ui| ui.add(slider(&mut physics.tolerance, 1e-10..=1e-3).logarithmic(true)),
            );
        }
        ui.label("Rotation").on_hover_text(
            "Locked: attitude held (the paper). Free: a rigid body with spin and torque.",
        );
        let before = physics.rotation;
        ui.horizontal(|ui| {
            ui.radio_value(&mut physics.rotation, Rotation::Locked, "Locked");
            ui.radio_value(&mut physics.rotation, Rotation::Free, "Free");
        });
        ui.end_row();
        c |= before != physics.rotation;
        if physics.rotation == Rotation::Free {
            ui.label("Pressure centre").on_hover_text(
                "Where the lift acts along the flow (torque only). Faces: each face's centroid (the paper). \
                 Planing: a fraction of the wetted length ahead of its trailing edge (Savitsky: 0.75).",
            );
            let before = physics.pressure_centre;
            let mut planing = matches!(physics.pressure_centre, PressureCentre::Planing(_));
            ui.horizontal(|ui| {
                ui.radio_value(&mut planing, false, "Faces");
                ui.radio_value(&mut planing, true, "Planing");
            });
            ui.end_row();
            physics.pressure_centre = match (planing, physics.pressure_centre) {
                (false, _) => PressureCentre::Faces,
                (true, PressureCentre::Planing(f)) => PressureCentre::Planing(f),
                (true, PressureCentre::Faces) => PressureCentre::Planing(SAVITSKY_CENTRE),
            };
            if let PressureCentre::Planing(f) = &mut physics.pressure_centre {
                c |= row(
                    ui,
                    "Centre at",
                    "Fraction of the wetted length ahead of its trailing edge",
                    |ui| ui.add(slider(f, 0.0..=1.0)),
                );
            }
            c |= before != physics.pressure_centre;
            ui.label("Axial spin").on_hover_text(
                "Smooth: the pebble is a smooth body of revolution, so its spin about its own axis moves                  no water normal to its surface (only friction feels it). Faceted: the mesh's flat facets                  paddle the water as they spin.",
            );
            let before = physics.axial_spin;
            ui.horizontal(|ui| {
                ui.radio_value(&mut physics.axial_spin, AxialSpin::Smooth, "Smooth");
                ui.radio_value(&mut physics.axial_spin, AxialSpin::Faceted, "Faceted");
            });
            ui.end_row();
            c |= before != physics.axial_spin;
        }
        c |= row(
            ui,
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
        c |= row(ui, "Max time", "The run ends (timeout) here", |ui| {
            ui.add(slider(&mut physics.max_time, 1.0..=120.0).suffix(" s"))
        });
        c
    });
    changed
}

fn coefficient_row(
    ui: &mut Ui,
    name: &str,
    tip: &str,
    value: &mut Option<f64>,
    default: f64,
    range: std::ops::RangeInclusive<f64>,
) -> bool {
    ui.label(name).on_hover_text(tip);
    let mut changed = false;
    ui.horizontal(|ui| {
        let mut custom = value.is_some();
        if ui
            .checkbox(&mut custom, "")
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
pub fn water_ui(ui: &mut Ui, water: &mut WaterParams) -> bool {
    let mut changed = false;
    changed |= ui
        .checkbox(&mut water.enabled, "Simulate the water (rings)")
        .on_hover_text("Off: a flat, rigid surface at z = 0")
        .changed();
    changed |= ui
        .checkbox(&mut water.wavy_contact, "Wavy contact")
        .on_hover_text("The stone meets the simulated surface instead of z = 0")
        .changed();
    changed |= grid(ui, "water", |ui| {
        let mut c = false;
        c |= row(ui, "Length", "Extent of the grid along x", |ui| {
            ui.add(
                slider(&mut water.size[0], 2.0..=200.0)
                    .logarithmic(true)
                    .suffix(" m"),
            )
        });
        c |= row(ui, "Width", "Extent of the grid along y", |ui| {
            ui.add(
                slider(&mut water.size[1], 2.0..=200.0)
                    .logarithmic(true)
                    .suffix(" m"),
            )
        });
        // Cells: at least 4 across, at most MAX_WATER_COLUMNS in all.
        let area = water.size[0] * water.size[1];
        let min_cell = ((area / MAX_WATER_COLUMNS as f64).sqrt() * 1.02).max(0.005);
        let max_cell = (water.size[0].min(water.size[1]) / 4.5)
            .min(1.0)
            .max(min_cell);
        c |= row(
            ui,
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
        c |= row(ui, "Depth", "Rest depth H: wave speed √(gH)", |ui| {
            ui.add(
                slider(&mut water.depth, 0.02..=5.0)
                    .logarithmic(true)
                    .suffix(" m"),
            )
        });
        c |= row(ui, "Damping", "Per second", |ui| {
            ui.add(slider(&mut water.damping, 0.0..=5.0).suffix(" 1/s"))
        });
        ui.label("Pipes");
        c |= ui
            .checkbox(&mut water.diagonal_pipes, "diagonals (isotropic)")
            .changed();
        ui.end_row();
        ui.label("Limiter").on_hover_text(
            "MassConserving: exact volume, never negative (Mei et al.). PaperClamp: eq. 41, creates water",
        );
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
            });
        ui.end_row();
        c |= before != water.limiter;
        ui.label("Precision").on_hover_text(
            "Storage of depths and flows: F32 halves the memory traffic; F64 conserves volume to rounding",
        );
        let before = water.precision;
        egui::ComboBox::from_id_salt("precision")
            .selected_text(format!("{:?}", water.precision))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut water.precision, Precision::F32, "F32");
                ui.selectable_value(&mut water.precision, Precision::F64, "F64");
            });
        ui.end_row();
        c |= before != water.precision;
        c
    });
    let mut swell = water.swell.is_some();
    if ui.checkbox(&mut swell, "Swell (a wavy lake)").changed() {
        water.swell = swell.then(Swell::default);
        changed = true;
    }
    let depth = water.depth;
    if let Some(s) = water.swell.as_mut() {
        changed |= grid(ui, "swell", |ui| {
            let mut c = false;
            c |= row(ui, "Amplitude", "At most half the depth", |ui| {
                ui.add(slider(&mut s.amplitude, 0.0..=(0.5 * depth).min(0.3)).suffix(" m"))
            });
            c |= row(ui, "Wavelength", "", |ui| {
                ui.add(
                    slider(&mut s.wavelength, 0.2..=30.0)
                        .logarithmic(true)
                        .suffix(" m"),
                )
            });
            c |= row(
                ui,
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
        ui.label("Ripple contrast").on_hover_text(
            "Multiplies the water's slopes in the shading only (1 = true to the simulation)",
        );
        ui.add(
            Slider::new(&mut view.ripple_gain, 0.0..=5.0)
                .custom_parser(parse_finite)
                .clamping(SliderClamping::Always)
                .suffix("×"),
        );
    });
    ui.horizontal(|ui| {
        ui.label("Render scale").on_hover_text(
            "Resolution of the 3D view while the throw animates (stills are always sharp); \
             lower it on a software renderer for a smoother picture",
        );
        ui.add(
            Slider::new(&mut view.render_scale, 0.25..=1.0)
                .custom_parser(parse_finite)
                .clamping(SliderClamping::Always)
                .custom_formatter(|v, _| format!("{:.0} %", v * 100.0)),
        );
    });
}

/// The options of how faces are loaded (issue 11): receding faces without ventilation, buoyancy.
fn loading_options_ui(ui: &mut Ui, physics: &mut Physics) -> bool {
    let mut c = false;
    if !physics.ventilated {
        ui.label("Receding faces").on_hover_text(
            "As printed (the paper's eq. 19): a wetted face moving out of the water is still pushed                  along −N, which gives the stone energy. Opposes motion: each face's pressure opposes its                  own normal velocity (never gains energy).",
        );
        let before = physics.pressure_sign;
        ui.horizontal(|ui| {
            ui.radio_value(
                &mut physics.pressure_sign,
                PressureSign::AsPrinted,
                "As printed",
            );
            ui.radio_value(
                &mut physics.pressure_sign,
                PressureSign::OpposesMotion,
                "Opposes motion",
            );
        });
        ui.end_row();
        c |= before != physics.pressure_sign;
    }
    ui.label("Buoyancy").on_hover_text(
        "Hydrostatic pressure ρ g d on each loaded face (Archimedes): matters once the stone is deep",
    );
    c |= ui.checkbox(&mut physics.buoyancy, "").changed();
    ui.end_row();
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

    #[test]
    fn typing_into_a_slider_takes_numbers_and_refuses_nan() {
        // The typing path works: a number is taken …
        assert_eq!(type_into_slider(12.5, "20"), 20.0);
        // … "nan" and "inf" keep the old value (they used to set the maximum).
        assert_eq!(type_into_slider(12.5, "nan"), 12.5);
        assert_eq!(type_into_slider(12.5, "inf"), 12.5);
    }
}
