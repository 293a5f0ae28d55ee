//! Robustness over the parameter space the UI allows (a property test): no panic, no NaN, and
//! always an outcome — including grazing, vertical, flat (tilt 0) and very fast throws. Runs are
//! capped in time and use no water grid or a small one, so the test covers breadth, not length.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![allow(clippy::field_reassign_with_default)]

use proptest::prelude::*;
use stoneskip_physics::sim::params::{
    Attitude, AxialSpin, ForceLaw, Integrator, LagLength, Limiter, MemoryParams, Precision, Preset,
    Quadrature, Rotation, Shape, StoneParams,
};
use stoneskip_physics::sim::{Simulation, Summary};

fn finite_summary(s: &Summary) {
    assert!(s.outcome.is_some(), "every run ends with an outcome");
    assert!(s.distance.is_finite() && s.final_time.is_finite());
    for c in &s.contacts {
        for v in c
            .v_in
            .iter()
            .chain(&c.v_out)
            .chain(&c.attitude_in)
            .chain(&c.attitude_out)
        {
            assert!(v.is_finite(), "{c:?}");
        }
        assert!(c.t_end >= c.t_start && c.beta_in.is_finite());
    }
    if let Some(w) = &s.water {
        assert!(w.volume_final.is_finite());
    }
}

/// Proptest's find (CI, session 29): a plate launched banked 56° and rising, with no water forces
/// (C_l = C_f = 0), touches the plane for less than the crossings' tolerance at launch; its exit
/// was located a rounding before its entry.
#[test]
fn a_touch_at_launch_ends_no_earlier_than_it_starts() {
    let text = "(version: 1, stone: (shape: Plate(length: 0.17630329237430623, width: \
                0.15117411982532494, thickness: 0.002102518623745575), mass: 1.6101989624317856, \
                segments: 8), launch: (position: (0.0, 0.0, 0.08579990496549814), velocity: \
                (5.13982097049158, 0.0, 7.927901479845613), attitude: (tilt_deg: \
                20.91672334871741, bank_deg: 55.748937151529034, heading_deg: 0.0), spin: \
                379.79384331638533), physics: (force_law: Rosellini, lift_coefficient: 0.0, \
                friction_coefficient: 0.0, ventilated: false, integrator: Rk4, rotation: Free, \
                axial_spin: Faceted, dt: 0.004883858815194481, max_time: 1.5), water: (enabled: \
                false, size: (6.0, 3.0), origin: (-3.0, -1.5), cell: 0.1))";
    let p = stoneskip_physics::preset::parse(text, std::path::Path::new("found.ron")).unwrap();
    let s = run(&p);
    assert!(!s.contacts.is_empty());
    finite_summary(&s);
}

fn run(p: &Preset) -> Summary {
    let mut sim = Simulation::new(p).expect("valid preset");
    let mut ok = true;
    let s = sim.run(
        &mut |st| {
            ok &= st.state.is_finite() && st.force.is_finite() && st.wetted_area.is_finite();
        },
        &|| false,
    );
    assert!(ok, "non-finite step in {p:?}");
    finite_summary(&s);
    s
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (0.01..0.15f64, 0.05..0.5f64).prop_map(|(r, f)| Shape::Disk {
            radius: r,
            thickness: (2.0 * r * f).max(0.001)
        }),
        (0.01..0.15f64, 0.05..0.5f64).prop_map(|(r, f)| Shape::Lens {
            radius: r,
            thickness: (2.0 * r * f).max(0.001)
        }),
        (0.02..0.3f64, 0.02..0.3f64, 0.001..0.03f64).prop_map(|(l, w, t)| Shape::Plate {
            length: l,
            width: w,
            thickness: t
        }),
    ]
}

fn preset() -> impl Strategy<Value = Preset> {
    (
        (shape(), 0.005..2.0f64, 8u32..40),
        (0.0..2.0f64, 0.1..40.0f64, -89.0..60.0f64),
        (
            -90.0..90.0f64,
            -60.0..60.0f64,
            -180.0..180.0f64,
            -400.0..400.0f64,
        ),
        (0usize..3, 0usize..4, any::<bool>(), any::<bool>()),
        (1e-4..5e-3f64, 0.0..3.0f64, 0.0..0.05f64),
        (any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>()),
        (
            any::<bool>(),
            2u32..24,
            2u32..12,
            prop::option::of((0.1..=10.0f64, any::<bool>())),
        ),
    )
        .prop_map(
            |(
                (shape, mass, segments),
                (z, speed, elev),
                (tilt, bank, heading, spin),
                (law, integ, vent, free),
                (dt, cl, cf),
                (water, wavy, paper_clamp, f64_water),
                (smooth, meridian, around, memory),
            )| {
                let mut p = Preset::version_1();
                p.stone = StoneParams {
                    shape,
                    mass,
                    segments,
                    bands: None,
                    quadrature: Default::default(),
                };
                let (e, h) = (elev.to_radians(), heading.to_radians());
                p.launch.position = [0.0, 0.0, z];
                p.launch.velocity = [
                    speed * e.cos() * h.cos(),
                    speed * e.cos() * h.sin(),
                    speed * e.sin(),
                ];
                p.launch.attitude = Attitude {
                    tilt_deg: tilt,
                    bank_deg: bank,
                    heading_deg: heading,
                };
                p.launch.spin = spin;
                p.physics.force_law = ForceLaw::ALL[law];
                p.physics.integrator = Integrator::ALL[integ];
                p.physics.ventilated = vent;
                p.physics.rotation = if free {
                    Rotation::Free
                } else {
                    Rotation::Locked
                };
                p.physics.dt = dt;
                p.physics.lift_coefficient = Some(cl);
                p.physics.friction_coefficient = Some(cf);
                p.physics.max_time = 1.5;
                p.water.enabled = water;
                p.water.wavy_contact = wavy;
                p.water.size = [6.0, 3.0];
                p.water.cell = 0.1;
                p.water.origin = Some([-3.0, -1.5]);
                p.water.limiter = if paper_clamp {
                    Limiter::PaperClamp
                } else {
                    Limiter::MassConserving
                };
                p.water.precision = if f64_water {
                    Precision::F64
                } else {
                    Precision::F32
                };
                // The wetted-extent memory at any λ the Physics panel allows, either length.
                p.physics.wetted_memory = memory.map(|(lag, wetted)| MemoryParams {
                    lag,
                    length: if wetted {
                        LagLength::Wetted
                    } else {
                        LagLength::Radius
                    },
                    ..MemoryParams::default()
                });
                if smooth {
                    // The smooth lens (flat water only; validation refuses the rest).
                    p.stone.quadrature = Quadrature::Smooth { meridian, around };
                    p.physics.axial_spin = AxialSpin::Resal;
                }
                p
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]
    #[test]
    fn any_allowed_preset_ends_cleanly(p in preset()) {
        prop_assume!(p.validate().is_ok());
        run(&p);
    }
}

/// The corners the random draw rarely hits exactly.
#[test]
fn corner_cases_end_cleanly() {
    let mut cases = Vec::new();
    let base = {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.physics.max_time = 3.0;
        p
    };
    // Grazing: lowest point a hair above, velocity almost horizontal.
    let mut p = base.clone();
    p.launch.position = [0.0, 0.0, 0.0125];
    p.launch.velocity = [10.0, 0.0, -1e-6];
    cases.push(p);
    // Vertical drop, flat stone (tilt 0): the whole underside wets at once.
    let mut p = base.clone();
    p.launch.velocity = [0.0, 0.0, -5.0];
    p.launch.attitude.tilt_deg = 0.0;
    cases.push(p);
    // Flat and fast.
    let mut p = base.clone();
    p.launch.velocity = [99.0, 0.0, -2.0];
    p.launch.attitude.tilt_deg = 0.0;
    cases.push(p);
    // Edge-on (tilt 90) and upside-down bank.
    let mut p = base.clone();
    p.launch.attitude.tilt_deg = 90.0;
    cases.push(p);
    let mut p = base.clone();
    p.launch.attitude.bank_deg = 90.0;
    p.physics.rotation = Rotation::Free;
    cases.push(p);
    // Thrown straight up, and starting below the surface.
    let mut p = base.clone();
    p.launch.velocity = [0.0, 0.0, 20.0];
    cases.push(p);
    let mut p = base.clone();
    p.launch.position = [0.0, 0.0, -0.2];
    cases.push(p);
    // The paper's integrator at the paper's 20 frames/s.
    let mut p = base.clone();
    p.physics.integrator = Integrator::Paper;
    p.physics.dt = 0.05;
    cases.push(p);
    // Zero gravity: never comes down; must time out.
    let mut p = base.clone();
    p.physics.gravity = 0.0;
    p.launch.velocity = [1.0, 0.0, 0.5];
    cases.push(p);
    // Every corner again on the smooth lens.
    let smooth: Vec<Preset> = cases
        .iter()
        .map(|p| {
            let mut p = p.clone();
            p.stone.quadrature = Quadrature::Smooth {
                meridian: 8,
                around: 4,
            };
            p.physics.axial_spin = AxialSpin::Resal;
            p
        })
        .collect();
    cases.extend(smooth);
    for p in cases {
        p.validate().unwrap();
        run(&p);
    }
}
