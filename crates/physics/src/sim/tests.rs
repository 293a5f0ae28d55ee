//! The run's own tests: the clock and the stepping (ticks, resumable ticks, steps across ticks),
//! the lake handed out and back, the record's words, the evaluation guard and the unread water.

use super::*;
use crate::sim::params::Rotation;
/// `stone.quadrature: Smooth` on a disk (as a version-2 file or the app's shape menu leaves
/// it when the shipped lens becomes a disk) throws exactly as the disk's faces.
#[test]
fn a_smooth_flag_on_a_disk_throws_as_its_faces() {
    let mut p = Preset::default();
    p.stone.shape = params::Shape::Disk {
        radius: 0.05,
        thickness: 0.01,
    };
    p.physics.max_time = 1.0;
    assert!(!p.stone.quadrature.is_faces());
    let smooth = simulate(&p).unwrap();
    p.stone.quadrature = params::Quadrature::Faces;
    assert_eq!(smooth, simulate(&p).unwrap());
    assert!(smooth.contacts.len() > 1, "{smooth:?}");
}

#[test]
fn outcomes_read_as_words() {
    assert_eq!(Outcome::Sank.words(), "sank");
    assert_eq!(Outcome::LeftDomain.words(), "left the lake");
    assert_eq!(Outcome::Timeout.words(), "still going at the time limit");
}

/// Issue 48: on the ambient water (wavy contact off) the lake's edge ends nothing — the stone
/// flies on past the columns and the throw ends by its physics; with wavy contact the stone
/// reads the columns, so their edge still ends the run (`left_domain`).
#[test]
fn only_wavy_contact_ends_a_throw_at_the_lake_edge() {
    let mut p = Preset::default();
    p.water.size = [3.0, 2.0];
    p.water.origin = Some([-1.0, -1.0]);
    p.water.cell = 0.05;
    p.physics.max_time = 3.0;
    let ambient = simulate(&p).unwrap();
    assert_ne!(ambient.outcome, Some(Outcome::LeftDomain), "{ambient:?}");
    assert!(ambient.distance > 3.0, "{}", ambient.distance);
    let mut wavy = p.clone();
    wavy.water.wavy_contact = true;
    let edged = simulate(&wavy).unwrap();
    assert_eq!(edged.outcome, Some(Outcome::LeftDomain), "{edged:?}");
    assert!(edged.distance < 2.5, "{}", edged.distance);
}

/// Live physics edits keep a smooth stone's conditions: a faceted spin under free rotation or
/// is refused with the field named, and the run goes on as it was.
#[test]
fn live_physics_keeps_the_smooth_quadrature_consistent() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    p.stone.quadrature = params::Quadrature::Smooth {
        meridian: 8,
        around: 4,
    };
    let mut sim = Simulation::new(&p).unwrap();
    let mut faceted = p.physics;
    faceted.rotation = Rotation::Free;
    faceted.axial_spin = params::AxialSpin::Faceted;
    assert_eq!(
        sim.set_physics(faceted).unwrap_err().field,
        "physics.axial_spin"
    );
    assert_eq!(sim.preset.physics, p.physics);
    let mut heavier = p.physics;
    heavier.gravity = 12.0;
    sim.set_physics(heavier).unwrap();
}

/// A deferred lake (`lake.rs`), handed out every few ticks and stepped on another thread while
/// the stone runs on, ends bit for bit as the lake stepped at every tick's end, and the stone's
/// run is the same; the stone flies on past the lake's edge (the ambient water's columns are a
/// window of rings, issue 48), while the grid is out a physics edit is refused, and a grid goes back only to the run it came from.
#[test]
fn a_lake_stepped_elsewhere_is_the_lake_stepped_here() {
    let mut p = Preset::default();
    p.water.size = [8.0, 3.0];
    p.water.origin = Some([-1.0, -1.5]);
    p.water.cell = 0.05;
    p.physics.max_time = 1.5;
    let mut here = Simulation::new(&p).unwrap();
    while !here.is_finished() {
        here.tick();
    }
    let mut away = Simulation::new(&p).unwrap();
    assert!(away.defer_lake(true));
    let mut job: Option<std::thread::JoinHandle<SteppedLake>> = None;
    let mut ticks = 0;
    while !away.is_finished() {
        away.tick();
        ticks += 1;
        if ticks % 3 == 0 {
            if let Some(j) = job.take() {
                assert!(away.return_lake(j.join().unwrap()));
            }
            if let Some(next) = away.take_lake() {
                assert!(away.water().is_none() && away.lake_geometry().is_some());
                assert!(away.set_physics(away.preset().physics).is_err());
                job = Some(std::thread::spawn(move || next.run()));
            }
        }
    }
    if let Some(j) = job.take() {
        assert!(away.return_lake(j.join().unwrap()));
    }
    assert!(!away.defer_lake(false));
    assert_eq!(here.summary(), away.summary());
    assert_ne!(away.outcome(), Some(Outcome::LeftDomain));
    let end = away.state().position;
    let lake = away.lake_geometry().unwrap();
    assert!(
        !lake.contains(end.x, end.y),
        "ended at {end:?}, inside the lake"
    );
    let (a, b) = (here.water().unwrap(), away.water().unwrap());
    assert_eq!(a.steps(), b.steps());
    assert!(a.steps() > 20 && a.max_abs_eta() > 1e-4, "{}", a.steps());
    for iy in 0..a.ny() {
        for ix in 0..a.nx() {
            assert_eq!(a.eta(ix, iy).to_bits(), b.eta(ix, iy).to_bits());
        }
    }
    // A grid from another run is refused (and this run's lake stays out).
    let mut other = Simulation::new(&p).unwrap();
    other.defer_lake(true);
    other.tick();
    let stranger = other.take_lake().unwrap().run();
    away.defer_lake(true);
    away.tick();
    let _out = away.take_lake().unwrap();
    assert!(!away.return_lake(stranger));
    assert!(away.water().is_none());
}

/// With wavy contact the stone reads the columns: the lake cannot be deferred.
#[test]
fn a_lake_the_stone_reads_is_not_deferred() {
    let mut p = Preset::default();
    p.water.wavy_contact = true;
    p.water.size = [4.0, 2.0];
    p.water.origin = Some([-1.0, -1.0]);
    p.water.cell = 0.05;
    let mut sim = Simulation::new(&p).unwrap();
    assert!(!sim.defer_lake(true));
    sim.tick();
    assert!(sim.take_lake().is_none());
}

/// Finding S3: a costly tick's face impulses are handed to the water once they reach the
/// flush bound, not kept to the tick's end; the grid sums them per column in the same order,
/// so the run is bit for bit the one that kept them all, stone and water alike.
#[test]
fn a_costly_ticks_face_loads_are_flushed_with_the_same_results() {
    let mut p = Preset::version_1();
    p.physics.tolerance = 1e-9;
    p.physics.dt = 0.02;
    p.physics.max_time = 0.6;
    p.water.wavy_contact = true;
    p.water.size = [6.0, 2.0];
    p.water.origin = Some([-1.0, -1.0]);
    p.water.cell = 0.05;
    let run = |flush: usize| {
        let mut sim = Simulation::new(&p).unwrap();
        sim.pending_flush = flush;
        while !sim.is_finished() {
            sim.tick();
        }
        sim
    };
    let (kept, flushed) = (run(usize::MAX), run(64));
    assert!(
        kept.pending_high > 1_000,
        "a tick held {}",
        kept.pending_high
    );
    // At most the bound plus one step's start and end loads.
    let faces = 2 * kept.stone.mesh.triangles.len();
    assert!(
        flushed.pending_high < 64 + faces,
        "{}",
        flushed.pending_high
    );
    assert_eq!(kept.summary(), flushed.summary());
    let (a, b) = (kept.water().unwrap(), flushed.water().unwrap());
    for iy in 0..a.ny() {
        for ix in 0..a.nx() {
            assert_eq!(
                a.eta(ix, iy).to_bits(),
                b.eta(ix, iy).to_bits(),
                "column {ix}, {iy}"
            );
        }
    }
}

/// A tick's work is bounded by evaluations, not only by steps: the fuzz-found costly preset
/// (a 36 cm disc at tolerance 1.3e-10, found by the headless soak: 2.3·10⁷ evaluations in one
/// tick) with the guard lowered so the test is quick ends `diverged` with the reason, its tick
/// within the guard plus one step's attempts.
#[test]
fn a_tick_past_its_evaluation_guard_is_reported_diverged() {
    let mut p = Preset::version_1();
    p.stone.shape = params::Shape::Disk {
        radius: 0.181,
        thickness: 0.0764,
    };
    p.stone.mass = 0.449;
    p.stone.segments = 79;
    p.launch.position = [0.0, 0.0, 0.17];
    p.launch.velocity = [13.68, -3.57, -10.22];
    p.launch.attitude.tilt_deg = 19.7;
    p.launch.attitude.bank_deg = 56.3;
    p.physics.force_law = params::ForceLaw::Bocquet;
    p.physics.tolerance = 1.29e-10;
    p.physics.dt = 4.06e-4;
    p.physics.max_time = 0.0588;
    p.water.enabled = false;
    let mut sim = Simulation::new(&p).unwrap();
    sim.max_evals_per_tick = 20_000;
    let mut worst = 0;
    while !sim.is_finished() {
        let before = sim.cost().1;
        sim.tick();
        worst = worst.max(sim.cost().1 - before);
    }
    assert_eq!(
        sim.outcome(),
        Some(Outcome::Diverged),
        "{:?}",
        sim.summary()
    );
    let why = sim.diverged_reason().unwrap();
    assert!(why.contains("force evaluations in one tick"), "{why}");
    assert!(worst <= 20_000 + 10_000, "{worst} evaluations in a tick");
}

/// The aim preview follows the run's own flight: a vacuum parabola without air, a longer arc
/// with the lift of a stone tilted into the flow, each ending on the water where the run's
/// first touch of the centre of mass would be.
#[test]
fn the_launch_arc_is_the_runs_first_flight() {
    let mut p = Preset::version_1();
    p.launch.position = [0.0, 0.0, 0.3];
    p.launch.velocity = [12.0, 0.0, 0.0];
    let stone = Stone::new(&p.stone).unwrap();
    let vacuum = launch_arc(&p, &stone, 0.01, 5.0);
    let end = *vacuum.last().unwrap();
    assert!(end.z.abs() < 1e-9, "ends on the water: {end}");
    let t = (2.0 * 0.3 / p.physics.gravity).sqrt();
    assert!(
        (end.x - 12.0 * t).abs() < 1e-9,
        "the parabola lands at {}",
        12.0 * t
    );
    p.physics.air = Some(air::AirParams::default());
    let with_air = launch_arc(&p, &stone, 0.01, 5.0);
    let end_air = *with_air.last().unwrap();
    assert!(end_air.z.abs() < 1e-9);
    assert!(
        end_air.x > end.x,
        "lift carries it farther: {} vs {}",
        end_air.x,
        end.x
    );
    let sim = Simulation::new(&p).unwrap();
    let direct = sim.fly(&launch_state(&p, &stone), 0.1);
    let on_arc = with_air[10];
    assert!(
        (direct.position - on_arc).length() < 1e-6,
        "{direct:?} vs {on_arc}"
    );
}

/// With wavy contact off the stone meets the plane z = 0, so leaving the water at rest changes
/// nothing the run reports about the stone, bit for bit; with wavy contact on, the water is read
/// and keeps stepping.
#[test]
fn unread_water_is_left_at_rest_without_changing_the_stone() {
    let mut p = Preset::version_1();
    p.water.wavy_contact = false;
    p.water.cell = 0.05;
    p.water.size = [16.0, 2.0];
    p.physics.max_time = 1.0;
    let mut stepped = Simulation::new(&p).unwrap();
    let a = stepped.run(&mut |_| {}, &|| false);
    let b = simulate(&p).unwrap();
    let (wa, wb) = (a.water.unwrap(), b.water.unwrap());
    assert!(wa.stepped && !wb.stepped);
    assert_eq!(wb.volume_final, wb.volume_initial);
    assert!(a.skips >= 1, "{a:?}");
    assert_eq!(Summary { water: None, ..a }, Summary { water: None, ..b });
    let mut q = p.clone();
    q.water.wavy_contact = true;
    let mut sim = Simulation::new(&q).unwrap();
    assert!(!sim.skip_unread_water());
    sim.tick();
    assert!(sim.summary().water.unwrap().stepped);
}

/// `steps_across_ticks` (numerics): with no water taking the stone's loads, the contact steps
/// end past the tick, so the same throw takes fewer force evaluations. It is the same equation
/// solved to the same tolerance, so both runs keep the skips and land within the integration
/// error of a tight-tolerance run: at most the sum of the local errors, each at most the
/// tolerance (relative to the error norm's scales), so `steps × tolerance` relative.
#[test]
fn steps_across_ticks_take_fewer_evaluations_for_the_same_throw() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    p.physics.max_time = 10.0;
    let run = |across: bool, tolerance: f64| {
        let mut q = p.clone();
        q.physics.steps_across_ticks = across;
        q.physics.tolerance = tolerance;
        simulate(&q).unwrap()
    };
    let (tick, across, tight) = (run(false, 1e-6), run(true, 1e-6), run(false, 1e-10));
    assert_eq!(tight.outcome, Some(Outcome::Sank), "{tight:?}");
    assert!(tight.skips >= 2, "{tight:?}");
    for s in [&tick, &across] {
        assert_eq!((s.outcome, s.skips), (tight.outcome, tight.skips), "{s:?}");
        let error = (s.distance - tight.distance).abs() / tight.distance;
        assert!(
            error <= s.steps as f64 * 1e-6,
            "error {error} over {} steps",
            s.steps
        );
    }
    assert!(
        (across.force_evals as f64) < 0.9 * tick.force_evals as f64,
        "{} against {}",
        across.force_evals,
        tick.force_evals
    );
}

/// The wetted-extent memory's exit tail ([`EXIT_APPROACH`]): the shipped default, stone alone,
/// to the end of its first contact at the shipped tolerance and at 1e-3 leaves the water when
/// and as a run at 1e-10 does, to the sum of the
/// local errors (steps × tolerance relative to the error norm's scales: |v| for the velocity,
/// the stone's radius over the exit's clearance rate for the instant).
#[test]
fn the_memory_exit_is_where_a_tight_tolerance_puts_it() {
    let mut p = Preset::default();
    p.water.enabled = false;
    assert!(p.physics.wetted_memory.is_some());
    let first_exit = |tolerance: f64| {
        let mut q = p.clone();
        q.physics.tolerance = tolerance;
        let mut sim = Simulation::new(&q).unwrap();
        while sim.contacts().is_empty() || sim.in_contact() {
            sim.tick();
            assert!(!sim.is_finished());
        }
        (sim.contacts()[0], sim.cost().0)
    };
    let (tight, _) = first_exit(1e-10);
    for tolerance in [p.physics.tolerance, 1e-3] {
        let (c, steps) = first_exit(tolerance);
        let budget = steps as f64 * tolerance;
        let speed = DVec3::from_array(tight.v_out).length();
        let dv = (DVec3::from_array(c.v_out) - DVec3::from_array(tight.v_out)).length();
        assert!(dv <= budget * speed, "{tolerance}: v_out off by {dv} m/s");
        // A position error of `budget` radii moves the exit by that over the rate the lowest
        // point leaves at, |v_z| + ωR: some metres a second, so 1 m/s bounds it from below.
        let (radius, leaving) = (Simulation::new(&p).unwrap().stone().bounding_radius, 1.0);
        let dt = (c.t_end - tight.t_end).abs();
        assert!(
            dt <= budget * radius / leaving,
            "{tolerance}: exit off by {dt} s"
        );
    }
}

/// Steps longer than the tick may jump a hop shorter than themselves: the record throw released
/// from 30 cm on flat water under the quasi-steady contact has one of 1.4 ms (touch 3 ends at
/// 0.8233 s with v_z 0.05 m/s, touch 4 begins at 0.8247 s), which an across-ticks step at the
/// shipped tolerance stepped over (6 touches for 7) until a step that leaves the water at a
/// stage was retried shortened to it. Every run at tolerance 1e-7 to 1e-10, ticks or not, has
/// the 7. The hop is shorter than the stone, so the two touches are one contact.
#[test]
fn steps_across_ticks_do_not_jump_a_short_hop() {
    let mut p = crate::preset::shipped("record_throw").unwrap().unwrap();
    p.water.enabled = false;
    p.physics.wetted_memory = None;
    p.launch.position[2] = 0.3;
    let run = |across: bool, tolerance: f64| {
        let mut q = p.clone();
        q.physics.steps_across_ticks = across;
        q.physics.tolerance = tolerance;
        simulate(&q).unwrap()
    };
    let converged = run(false, 1e-7);
    let across = run(true, 1e-6);
    assert_eq!(across.skips, converged.skips, "{across:?}");
    let touches = |s: &Summary| s.contacts.iter().map(|c| c.touches).sum::<u32>();
    assert_eq!(touches(&across), touches(&converged), "{across:?}");
    let short_hop = |s: &Summary| s.contacts.iter().any(|c| c.touches > 1);
    assert!(short_hop(&converged) && short_hop(&across));
}

/// Across ticks the pose drawn at a tick's end is the stone's at the tick's time, interpolated
/// inside the step that passed it: at every tick within the integration error of a tick-bound
/// run, where the stone's own state, up to a step ahead, is many times farther off.
#[test]
fn steps_across_ticks_draw_the_pose_at_the_ticks_time() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    let mut tick_bound = Simulation::new(&p).unwrap();
    p.physics.steps_across_ticks = true;
    let mut across = Simulation::new(&p).unwrap();
    let (mut drawn, mut own, mut turn) = (0.0f64, 0.0f64, 0.0f64);
    while !tick_bound.is_finished() && !across.is_finished() {
        tick_bound.tick();
        across.tick();
        let (x, q) = tick_bound.world_from_stone();
        let (y, r) = across.world_from_stone();
        drawn = drawn.max((y - x).length());
        own = own.max((across.state().position - x).length());
        turn = turn.max(q.angle_between(r));
    }
    assert!(drawn < 1e-3 && turn < 1e-3, "{drawn} m, {turn} rad");
    assert!(own > 10.0 * drawn, "{own} against {drawn}");
}

/// Across ticks the clock still keeps the ticks (its n-th tick ends at n dt) and the stone is
/// at or ahead of it by less than its longest step; with a lake that takes the loads (the
/// app's case: the rings) the option changes nothing, bit for bit.
#[test]
fn steps_across_ticks_keep_the_clock_and_leave_a_coupled_run_alone() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    p.physics.steps_across_ticks = true;
    let dt = p.physics.dt;
    let mut sim = Simulation::new(&p).unwrap();
    let (mut ticks, mut ahead, mut longest) = (0u32, 0u32, 0.0f64);
    while !sim.is_finished() {
        let mut last = sim.time();
        sim.tick_with(&mut |s| {
            longest = longest.max(s.time - last);
            last = s.time;
        });
        ticks += 1;
        assert!((sim.clock - f64::from(ticks) * dt).abs() < 1e-9 * f64::from(ticks));
        assert!(sim.time() >= sim.clock && sim.time() - sim.clock < longest.max(dt));
        ahead += u32::from(sim.time() > sim.clock);
    }
    assert!(
        ahead > 0 && longest > dt,
        "{ahead} ticks ahead, longest step {longest}"
    );

    let mut q = Preset::version_1();
    q.physics.max_time = 1.0;
    let run = |across: bool| {
        let mut r = q.clone();
        r.physics.steps_across_ticks = across;
        Simulation::new(&r).unwrap().run(&mut |_| {}, &|| false)
    };
    let (on, off) = (run(true), run(false));
    assert!(
        on.skips >= 1 && on.water.as_ref().is_some_and(|w| w.stepped),
        "{on:?}"
    );
    assert_eq!(on, off);
}

/// A step whose forces overflow (the velocity of an explicit scheme run far past its stability
/// limit) ends the run as diverged, at the last finite state, with the reason; it used to be
/// reported as a sinking.
#[test]
fn a_non_finite_step_is_reported_as_diverged() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    p.physics.integrator = Integrator::Paper;
    let mut sim = Simulation::new(&p).unwrap();
    // In the water, with a speed whose square overflows.
    sim.motion.state.position.z = 0.0;
    sim.motion.state.velocity = DVec3::new(1e200, 0.0, -1e200);
    let before = sim.motion.state;
    sim.tick();
    assert_eq!(sim.outcome(), Some(Outcome::Diverged));
    assert_eq!(sim.state(), &before, "stops at the last finite state");
    let reason = sim.diverged_reason().unwrap();
    assert!(reason.contains("non-finite"), "{reason}");
    let s = sim.summary();
    assert_eq!(s.outcome.map(Outcome::as_str), Some("diverged"));
    assert_eq!(s.diverged_reason.as_deref(), Some(reason));
}

/// On flat water a skip turns a fall into a climb, so the water's mean upward force over the
/// contact, m g + m (v_out.z − v_in.z)/T, exceeds the stone's weight, and so does its peak;
/// the last contact, the one the stone sank in, has a peak too.
#[test]
fn a_skips_peak_lift_exceeds_the_weight() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    let mut sim = Simulation::new(&p).unwrap();
    let s = sim.run(&mut |_| {}, &|| false);
    let weight = sim.stone().mass * p.physics.gravity;
    assert!(s.skips >= 2, "{s:?}");
    for c in &s.contacts {
        let mean = sim.stone().mass * (c.v_out[2] - c.v_in[2]) / (c.t_end - c.t_start) + weight;
        if c.skip {
            assert!(mean > weight && c.peak_lift > weight, "{c:?}");
            assert!(c.peak_g().unwrap() > 1.0);
        }
        assert!(c.peak_lift > 0.0 && c.peak_lift.is_finite(), "{c:?}");
    }
    let mut weightless = s.contacts[0];
    weightless.weight = 0.0;
    assert_eq!(weightless.peak_g(), None);
    // A subnormal gravity (typed "1e-320"): the ratio would overflow to infinity.
    weightless.weight = 1e-320;
    assert_eq!(weightless.peak_g(), None);
}

/// A live change of gravity does not rewrite the past (issue 39, finding 2): the contacts
/// before it keep the peak g they had, read against the weight they were made with.
#[test]
fn a_live_gravity_change_keeps_earlier_peaks() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    let mut sim = Simulation::new(&p).unwrap();
    while sim.contacts().first().is_none_or(|c| c.open) {
        sim.tick();
    }
    let before = sim.contacts()[0].peak_g().unwrap();
    let mut heavy = p.physics;
    heavy.gravity = 30.0;
    sim.set_physics(heavy).unwrap();
    sim.run(&mut |_| {}, &|| false);
    assert_eq!(sim.contacts()[0].peak_g(), Some(before));
    assert!(before > 1.0, "{before}");
}

/// A run that ends otherwise carries no reason.
#[test]
fn other_outcomes_carry_no_reason() {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    let s = simulate(&p).unwrap();
    assert_eq!(s.outcome, Some(Outcome::Sank));
    assert_eq!(s.diverged_reason, None);
}

/// On the columns' own surface (wavy contact, the near field frozen at each tick of the
/// magic-angle throw's first contacts) the faceted lens converges as on flat water: 96
/// segments are nearer 192 than 64 are, by about the square of the facet size ((64/96)² =
/// 0.44), and 64 are within 1 % (mean force errors 0.21 % and 0.071 % when written). So the
/// mesh, not the surface, sets the error of a wavy contact's force.
#[test]
fn meshes_converge_on_the_columns_surface() {
    use crate::sim::hydro::{evaluate, Scratch};
    let mut p = crate::preset::shipped("magic_angle").unwrap().unwrap();
    p.water.wavy_contact = true;
    p.physics.wetted_memory = None;
    let mesh = |segments: u32| {
        let mut sp = p.stone.clone();
        sp.segments = segments;
        sp.bands = Some(segments / 2);
        Stone::new(&sp).unwrap()
    };
    let (m64, m96, m192) = (mesh(64), mesh(96), mesh(192));
    let mut sim = Simulation::new(&p).unwrap();
    let (mut e64, mut e96, mut poses) = (0.0, 0.0, 0);
    while sim.time() < 0.8 && !sim.is_finished() {
        sim.tick();
        let surface = sim.surface();
        assert!(!surface.is_flat());
        let dy = Dynamics {
            stone: &sim.stone,
            hydro: sim.hydro,
            gravity: p.physics.gravity,
            rotation: p.physics.rotation,
            surface: &surface,
            record_loads: false,
            resal: sim.resal(),
            memory: None,
        };
        let pose = dy.pose(sim.state());
        let mut sc = Scratch::default();
        let mut force =
            |stone: &Stone| evaluate(stone, &sim.hydro, &pose, &surface, &mut sc, false).force;
        let fine = force(&m192);
        if fine.length() < 1.0 {
            continue;
        }
        e64 += (force(&m64) - fine).length() / fine.length();
        e96 += (force(&m96) - fine).length() / fine.length();
        poses += 1;
    }
    assert!(poses >= 10, "{poses} contact poses");
    let (e64, e96) = (e64 / poses as f64, e96 / poses as f64);
    assert!(
        e96 < 0.6 * e64 && e64 < 0.01,
        "64: {e64:.2e}, 96: {e96:.2e}"
    );
}

/// The outcome's instant stays put while the clock runs on with the water after it, and it
/// is the summary's final time.
#[test]
fn the_end_time_is_the_outcomes_instant() {
    let mut p = Preset::version_1();
    p.water.enabled = true;
    let mut sim = Simulation::new(&p).unwrap();
    while !sim.is_finished() {
        assert_eq!(sim.end_time(), None);
        sim.tick();
    }
    let end = sim.end_time().unwrap();
    assert!(end <= sim.time() && end > 0.0, "{end} vs {}", sim.time());
    for _ in 0..5 {
        sim.tick();
    }
    assert_eq!(sim.end_time(), Some(end));
    assert!(sim.time() > end + 4.0 * p.physics.dt);
    assert_eq!(sim.summary().final_time, end);
}
