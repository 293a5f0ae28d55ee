//! Whole throws as a converged result (issue 38): the contact reads only the ambient water and a
//! wetted-extent memory (`src/sim/memory.rs`) lets the water's rise lag the stone, so that planing
//! is unstable at speed and stable when slow (Hewitt, Balmforth & McElwaine 2011), the skip count
//! and distance converge under the numerics, and neighbouring launches give neighbouring throws.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use glam::DVec3;
use stoneskip_physics::sim::params::{LagLength, MemoryParams, Preset, Quadrature};
use stoneskip_physics::sim::{simulate, Summary};

fn load(stem: &str) -> Preset {
    stoneskip_physics::preset::load(Path::new(&format!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/presets/{}.ron"),
        stem
    )))
    .unwrap()
}

/// The shipped presets whose throws the issue checks.
const THROWS: [&str; 3] = ["default", "magic_angle", "record_throw"];

fn run(p: &Preset) -> Summary {
    simulate(p).unwrap()
}

/// Whether two runs agree as the issue asks: skips within `skips`, distance within `share`.
fn agree(a: &Summary, b: &Summary, skips: usize, share: f64) -> bool {
    a.skips.abs_diff(b.skips) <= skips && (a.distance - b.distance).abs() <= share * a.distance
}

fn brief(s: &Summary) -> String {
    format!(
        "{} skips over {:.3} m ({:?})",
        s.skips, s.distance, s.outcome
    )
}

/// The shipped throws read the ambient water only, with the memory on: the rest of these tests are
/// about the model they ship.
#[test]
fn shipped_throws_read_the_ambient_water_with_a_memory() {
    for stem in THROWS {
        let p = load(stem);
        assert!(!p.water.wavy_contact, "{stem}");
        assert!(p.physics.wetted_memory.is_some(), "{stem}");
    }
}

/// Converged: refining the tick 4×, the cell 2×, the mesh 2× (a smooth lens's quadrature nodes 2×
/// each way, the mesh it integrates over being its ellipsoid) or the tolerance 100× moves the skip
/// count by at most 1 and the distance by at most 2 %.
#[test]
fn whole_throws_converge_under_the_numerics() {
    for stem in THROWS {
        let p = load(stem);
        let base = run(&p);
        let mut variants = Vec::new();
        let mut v = p.clone();
        v.physics.dt /= 4.0;
        variants.push(("tick / 4", v));
        let mut v = p.clone();
        v.water.cell /= 2.0;
        // The record throw's 140 m lake at 1 cm passes the grid's column limit: narrowed to fit.
        let along = (v.water.size[0] / v.water.cell).ceil();
        v.water.size[1] = v.water.size[1].min((4e6 / along).floor() * v.water.cell);
        v.water.origin = None;
        variants.push(("cell / 2", v));
        let mut v = p.clone();
        match &mut v.stone.quadrature {
            Quadrature::Smooth { meridian, around } => {
                *meridian *= 2;
                *around *= 2;
                variants.push(("quadrature nodes × 2", v));
            }
            Quadrature::Faces => {
                v.stone.segments *= 2;
                variants.push(("mesh × 2", v));
            }
        }
        let mut v = p.clone();
        v.physics.tolerance /= 100.0;
        variants.push(("tolerance / 100", v));
        for (what, v) in variants {
            let s = run(&v);
            assert!(
                agree(&base, &s, 1, 0.02),
                "{stem}, {what}: {} against {}",
                brief(&s),
                brief(&base)
            );
        }
    }
}

/// Smooth: launches 0.02 m/s or 0.5 mm apart differ by at most 1 skip and 3 % of distance.
#[test]
fn neighbouring_launches_give_neighbouring_throws() {
    for stem in THROWS {
        let p = load(stem);
        let base = run(&p);
        for k in [-1.0, 1.0] {
            let mut v = p.clone();
            let vel = DVec3::from_array(v.launch.velocity);
            let horizontal = vel.truncate().length();
            let scale = (horizontal + 0.02 * k) / horizontal;
            v.launch.velocity = [vel.x * scale, vel.y * scale, vel.z];
            let s = run(&v);
            assert!(
                agree(&base, &s, 1, 0.03),
                "{stem}, speed {:+} m/s: {} against {}",
                0.02 * k,
                brief(&s),
                brief(&base)
            );
            let mut v = p.clone();
            v.launch.position[2] += 0.0005 * k;
            let s = run(&v);
            assert!(
                agree(&base, &s, 1, 0.03),
                "{stem}, height {:+} mm: {} against {}",
                0.5 * k,
                brief(&s),
                brief(&base)
            );
        }
    }
}

/// A skip is a hop you can see: in every shipped preset, no counted skip is followed by a flight
/// shorter than the stone's diameter; and on the columns' own near field, where the stone's crests
/// break one touch into several, those touches are one contact.
#[test]
fn a_skip_is_a_hop_you_can_see() {
    let mut stems: Vec<String> =
        std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/presets"))
            .unwrap()
            .map(|e| {
                let path = e.unwrap().path();
                path.file_stem().unwrap().to_string_lossy().to_string()
            })
            .collect();
    stems.sort();
    for stem in &stems {
        let p = load(stem);
        let diameter = 2.0 * p.stone.shape.half_extent();
        let s = run(&p);
        for pair in s.contacts.windows(2) {
            let hop = (pair[1].x - pair[0].exit_xy[0]).hypot(pair[1].y - pair[0].exit_xy[1]);
            assert!(
                hop >= diameter,
                "{stem}: a hop of {hop} m after a contact at t = {}",
                pair[0].t_start
            );
        }
    }
    // The stone riding its own rings on 2 cm columns touches again within millimetres.
    let mut wavy = load("default");
    wavy.water.wavy_contact = true;
    wavy.physics.wetted_memory = None;
    wavy.water.size = [40.0, 12.0];
    wavy.water.origin = Some([-2.0, -6.0]);
    wavy.water.cell = 0.02;
    let s = run(&wavy);
    assert!(
        s.contacts.iter().any(|c| c.touches > 1),
        "no contact gathered touches: {}",
        brief(&s)
    );
    let counted = s.contacts.iter().filter(|c| c.skip).count();
    assert_eq!(counted, s.skips);
}

/// The default pebble with its attitude held touching flat water almost tangentially
/// (v_z = −0.1 m/s) at `speed`, its lowest point 0.5 mm above the water (the study's throw).
fn tangential(speed: f64) -> Preset {
    stoneskip_lab::study::whole_throw::tangential_preset(speed).unwrap()
}

/// Planing is unstable at speed and stable when slow (Hewitt et al. 2011): at 12 m/s the held
/// pebble makes at least 3 skips and no contact longer than 0.3 s while faster than 6 m/s; at
/// 3 m/s at most 2 skips.
#[test]
fn planing_is_unstable_at_speed_and_stable_when_slow() {
    let fast = run(&tangential(12.0));
    assert!(fast.skips >= 3, "12 m/s: {}", brief(&fast));
    for c in &fast.contacts {
        if DVec3::from_array(c.v_in).length() > 6.0 {
            assert!(
                c.t_end - c.t_start <= 0.3,
                "12 m/s: a contact of {} s at {} m/s",
                c.t_end - c.t_start,
                DVec3::from_array(c.v_in).length()
            );
        }
    }
    let slow = run(&tangential(3.0));
    assert!(slow.skips <= 2, "3 m/s: {}", brief(&slow));
}

/// With the memory no contact gains energy: the pressure law is unchanged, so every face's force
/// opposes its motion into the water; the memory only moves the waterline. With the attitude held
/// the stone leaves a contact at the height it entered, so its speed may not grow (Adaptive to
/// 1e-6: good to far better than 1e-4). Checked on a long, gentle run and a hard first touch, for
/// short and long memories of both lengths, and with the Wagner strip's Π-lag and Wagner's entry
/// lead (issue 47), which only deepen the waterline while the stone sinks.
#[test]
fn the_memory_never_gains_energy() {
    let memories = [
        (0.5, LagLength::Wetted, None, 0.0),
        (2.0, LagLength::Wetted, None, 0.0),
        (6.0, LagLength::Wetted, None, 0.0),
        (0.2, LagLength::Radius, None, 0.0),
        (1.5, LagLength::Radius, None, 0.0),
        (2.0, LagLength::Wetted, Some(0.12), 0.0),
        (2.0, LagLength::Wetted, Some(0.12), 0.75),
        (4.0, LagLength::Wetted, None, 1.0),
        (6.0, LagLength::Wetted, Some(1.0), 4.0 / 3.0),
    ];
    for (lag, length, strip_frequency, entry_lead) in memories {
        let kappa = MemoryParams {
            lag,
            length,
            strip_frequency,
            entry_lead,
        };
        for (speed, vz) in [(12.0, -0.1), (8.0, -1.5)] {
            let mut p = tangential(speed);
            p.launch.velocity[2] = vz;
            p.physics.wetted_memory = Some(kappa);
            p.physics.max_time = 4.0;
            let s = run(&p);
            assert!(!s.contacts.is_empty());
            for c in s.contacts.iter().filter(|c| c.skip) {
                let ratio =
                    DVec3::from_array(c.v_out).length() / DVec3::from_array(c.v_in).length();
                assert!(
                    ratio <= 1.0 + 1e-4,
                    "{kappa:?}, {speed} m/s: ×{ratio} over the contact at {}",
                    c.t_start
                );
            }
        }
    }
}

/// The memory's state is part of the motion: bit-identical replays (determinism), and it changes
/// the throw.
#[test]
fn the_memory_is_deterministic_and_matters() {
    let mut p = tangential(12.0);
    p.physics.wetted_memory = None;
    let a = run(&p);
    let b = run(&p);
    assert_eq!(a.contacts, b.contacts);
    assert_eq!(a.distance.to_bits(), b.distance.to_bits());
    p.physics.wetted_memory = Some(MemoryParams::default());
    let c = run(&p);
    assert_ne!(
        a.skips,
        c.skips,
        "the memory changes nothing: {}",
        brief(&c)
    );
}

/// The shipped lenses integrate the law over their smooth ellipsoid (issue 41); their 64-segment
/// facets give the same throws within the bounds of refining the numerics, and the ellipsoid is
/// the nearer to the 192-segment mesh (within 0.3 % where the facets are within 1 %): the memory
/// reads the same geometry either way.
#[test]
fn the_smooth_lens_throws_as_the_mesh() {
    for stem in THROWS {
        let p = load(stem);
        assert!(
            !p.stone.quadrature.is_faces(),
            "{stem} ships the smooth lens"
        );
        let smooth = run(&p);
        let mut faces = p.clone();
        faces.stone.quadrature = Quadrature::Faces;
        let f = run(&faces);
        assert!(
            agree(&smooth, &f, 1, 0.02),
            "{stem}: the facets {} against the smooth lens {}",
            brief(&f),
            brief(&smooth)
        );
    }
}
