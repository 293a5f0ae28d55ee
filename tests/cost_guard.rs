//! The cost guard (issue 14; finding S1 in docs/reliability.md): a tick that yields between two
//! steps of the stone and resumes exactly, and the app model's frame budget built on it, which
//! stops a frame's physics even inside a tick, skips what it could not run, and says that the
//! physics runs behind. Every bound here is a count (steps, force evaluations, ticks), never a
//! wall-clock time: the model's wall budget is set out of reach so only its count budget acts.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![allow(clippy::field_reassign_with_default)]

use std::time::Duration;

use stoneskip::app::model::{FrameBudget, Pace, PACE_WINDOW};
use stoneskip::app::Model;
use stoneskip_physics::sim::params::{
    Attitude, ForceLaw, Integrator, Limiter, Precision, Preset, Rotation, Shape, Swell,
};
use stoneskip_physics::sim::{
    simulate, ContactEvent, Simulation, StepSample, Summary, TickProgress,
};

/// Every number of a contact episode, as bits.
fn contact_bits(c: &ContactEvent, out: &mut Vec<u64>) {
    out.extend(
        [c.t_start, c.t_end, c.x, c.y, c.beta_in]
            .iter()
            .chain(&c.v_in)
            .chain(&c.v_out)
            .chain(&c.attitude_in)
            .chain(&c.attitude_out)
            .map(|v| v.to_bits()),
    );
    out.push(u64::from(c.skip));
}

/// Every number of a summary, as bits (f64 bits, counts as they are).
fn summary_bits(s: &Summary) -> Vec<u64> {
    let mut out = vec![
        s.distance.to_bits(),
        s.final_time.to_bits(),
        s.steps,
        s.force_evals,
        s.skips as u64,
        s.contacts.len() as u64,
    ];
    if let Some(w) = &s.water {
        out.extend([w.volume_initial.to_bits(), w.volume_final.to_bits()]);
    }
    for c in &s.contacts {
        contact_bits(c, &mut out);
    }
    out
}

/// The time, state and forces of a step, as bits.
fn sample_bits(s: &StepSample) -> Vec<u64> {
    let st = &s.state;
    [s.time, s.wetted_area]
        .into_iter()
        .chain(st.position.to_array())
        .chain(st.velocity.to_array())
        .chain(st.orientation.to_array())
        .chain(st.angular_momentum.to_array())
        .chain(s.force.to_array())
        .map(f64::to_bits)
        .collect()
}

/// The default throw on a narrow lake with the water coupled and wavy contact on; Adaptive at a
/// tight tolerance and the longest tick, so that its ticks hold many steps.
fn wavy_throw(integrator: Integrator) -> Preset {
    let mut p = Preset::version_1();
    if integrator == Integrator::Adaptive {
        p.physics.tolerance = 1e-8;
        p.physics.dt = 0.02;
    } else {
        // Tumbling slowly end over end: its rim grazes the water once, in a tick that flies to
        // the touch and steps on from there.
        p.physics.rotation = Rotation::Free;
        p.launch.angular_velocity = [0.0, 10.0, 0.0];
    }
    p.water.size = [40.0, 4.0];
    p.water.cell = 0.1;
    p.water.wavy_contact = true;
    p.physics.integrator = integrator;
    p.physics.max_time = 3.0;
    p
}

/// Runs `p` to its end with `tick`, recording every step; returns the summary, the steps' bits,
/// the number of calls that yielded and the steps beyond the first of every call.
fn run_with(
    p: &Preset,
    tick: impl Fn(&mut Simulation, &mut dyn FnMut(&StepSample)) -> TickProgress,
) -> (Summary, Vec<Vec<u64>>, u64, u64) {
    let mut sim = Simulation::new(p).expect("valid preset");
    let mut steps = Vec::new();
    let mut partial = 0;
    let mut extra = 0;
    let mut calls = 0u64;
    while !sim.is_finished() {
        calls += 1;
        assert!(calls < 10_000_000, "the run must end");
        let before = sim.cost().0;
        if tick(&mut sim, &mut |s| steps.push(sample_bits(s))) == TickProgress::Partial {
            partial += 1;
            assert!(sim.tick_in_progress());
        }
        extra += (sim.cost().0 - before).saturating_sub(1);
    }
    (sim.summary(), steps, partial, extra)
}

/// A throw whose ticks yield after every step, or after every third step of the run, and resume
/// gives the very run of plain ticks: the same steps, summary and contacts, bit for bit, under
/// Adaptive and a fixed scheme. Yielding after every step splits every tick of n steps n − 1
/// times. (A fixed scheme's tick is one step but at a graze, where it flies to the touch and steps
/// on from there: its throw here has one.)
#[test]
fn a_tick_split_between_steps_is_bit_identical_to_a_whole_one() {
    for integrator in [Integrator::Adaptive, Integrator::Rk4] {
        let p = wavy_throw(integrator);
        let (plain, plain_steps, none, extra) = run_with(&p, |sim, on_step| {
            sim.tick_with(on_step);
            TickProgress::Done
        });
        assert_eq!(none, 0);
        if integrator == Integrator::Adaptive {
            assert!(
                extra >= 50,
                "ticks of several steps: {extra} steps beyond the first"
            );
        }
        for every in [1, 3] {
            let (split, split_steps, partial, _) = run_with(&p, |sim, on_step| {
                sim.tick_until(on_step, &|(steps, _)| steps % every == 0)
            });
            println!(
                "{integrator:?}, a yield after every {every}: {partial} yields in {} steps",
                split_steps.len()
            );
            if every == 1 {
                assert_eq!(partial, extra, "{integrator:?}: a yield after every step");
                assert!(partial >= 1, "{integrator:?}: no tick was split");
            } else if integrator == Integrator::Adaptive {
                assert!(
                    partial >= extra / 4,
                    "{integrator:?}: only {partial} yields"
                );
            }
            assert_eq!(plain_steps.len(), split_steps.len(), "{integrator:?}");
            assert!(plain_steps == split_steps, "{integrator:?}: steps differ");
            assert_eq!(summary_bits(&plain), summary_bits(&split), "{integrator:?}");
            assert_eq!(plain.outcome, split.outcome);
        }
        assert!(plain.skips >= 1 && plain.water.is_some(), "{plain:?}");
        assert_eq!(plain, simulate(&p).unwrap());
    }
}

/// Every call of `tick_until` takes at least one step, however eager the closure, so a caller
/// that yields at once still gets to the end; the water moves only when a tick is complete.
#[test]
fn a_yielding_tick_always_progresses_and_steps_the_water_at_its_end() {
    let p = wavy_throw(Integrator::Adaptive);
    let mut sim = Simulation::new(&p).unwrap();
    let mut calls = 0;
    while !sim.is_finished() {
        let (steps, _) = sim.cost();
        let water_steps = sim.water().map(|w| w.steps());
        let progress = sim.tick_until(&mut |_| {}, &|_| true);
        assert!(sim.cost().0 > steps, "every call takes a step");
        if progress == TickProgress::Partial {
            assert_eq!(sim.cost().0, steps + 1, "one step, then the yield");
            assert_eq!(sim.water().map(|w| w.steps()), water_steps);
        }
        calls += 1;
        assert!(calls < 1_000_000);
    }
    assert_eq!(sim.summary(), simulate(&p).unwrap());
}

/// Finding S1's second input (fuzz/slow/simulate/s1b-tumbling-plate-tolerance-7e-7, as the fuzz
/// harness builds it): a 44 cm plate launched half under water, tumbling at 70 rad/s about every
/// axis, Paper law, Adaptive at 7.4·10⁻⁷, water and wavy contact on: 3.6·10⁷ force evaluations per
/// simulated second, about 36 000 in each of its 1.37 ms ticks.
fn s1b() -> Preset {
    let mut p = Preset::version_1();
    p.stone.shape = Shape::Plate {
        length: 0.44078431372549015,
        width: 0.44078431372549015,
        thickness: 0.05574143712263123,
    };
    p.stone.mass = 0.17183998461489247;
    p.stone.segments = 28;
    let l = &mut p.launch;
    l.position = [5.294117647058826, 35.04901979701803, 0.0];
    l.velocity = [13.417200860557298, 26.53446108945339, 16.721975470100904];
    l.attitude = Attitude {
        tilt_deg: 57.117647058823536,
        bank_deg: 42.117647058823536,
        heading_deg: 126.35294117647061,
    };
    l.spin = 330.79122646621937;
    l.angular_velocity = [70.19607843137254; 3];
    let ph = &mut p.physics;
    ph.gravity = 16.588371723561636;
    ph.water_density = 1703.5294117647059;
    ph.force_law = ForceLaw::Paper;
    ph.lift_coefficient = Some(2.764705882352941);
    ph.friction_coefficient = Some(1.1058518353630444);
    ph.ventilated = true;
    ph.integrator = Integrator::Adaptive;
    ph.tolerance = 7.423148141583322e-7;
    ph.rotation = Rotation::Free;
    ph.dt = 0.0013732705833386402;
    ph.max_time = 0.14270588235294118;
    let w = &mut p.water;
    w.enabled = true;
    w.wavy_contact = true;
    w.size = [3.1058823529411765, 2.004319852684699];
    w.origin = None;
    w.cell = 0.04982181674747829;
    w.depth = 0.02;
    w.damping = 1.4705882352941178;
    w.diagonal_pipes = true;
    w.limiter = Limiter::PaperClamp;
    w.precision = Precision::F64;
    w.swell = Some(Swell {
        amplitude: 0.0029411764705882353,
        wavelength: 8.964705882352941,
        heading_deg: -74.11764705882354,
    });
    p
}

/// The force evaluations of each of the first `steps` steps of `p`'s run, and the time after
/// them (a tick that yields after every step: one step a call).
fn evals_per_step(p: &Preset, steps: u64) -> (Vec<u64>, f64) {
    let mut sim = Simulation::new(p).unwrap();
    let mut out = Vec::new();
    while sim.cost().0 < steps && !sim.is_finished() {
        let (s0, e0) = sim.cost();
        sim.tick_until(&mut |_| {}, &|_| true);
        let (s1, e1) = sim.cost();
        assert!(s1 <= s0 + 1);
        if s1 > s0 {
            out.push(e1 - e0);
        }
    }
    (out, sim.time())
}

/// The costly throw in the app: each frame stops at its budget of force evaluations (plus at
/// most the one step that crossed it), inside a tick; the run still moves on from frame to frame;
/// the clock skips what could not run instead of piling it up; the model says it runs behind, by
/// how much, and the number is the measured real time over simulated time.
#[test]
fn a_costly_throw_keeps_each_frame_within_its_budget_and_says_it_runs_behind() {
    const BUDGET: u64 = 10_000;
    const FRAMES: u64 = 30;
    const FRAME: f64 = 1.0 / 60.0;
    let p = s1b();
    let mut model = Model::new(p.clone(), None, Default::default()).unwrap();
    model.budget = FrameBudget {
        wall: Duration::from_secs(3600),
        wall_behind: Duration::from_secs(3600),
        force_evals: BUDGET,
    };
    model.throw();
    let dt = p.physics.dt;
    let mut frame_evals = Vec::new();
    let mut inside = 0u64;
    let mut t = model.sim.time();
    let t0 = t;
    for frame in 1..=FRAMES {
        let (_, e0) = model.sim.cost();
        model.advance(FRAME);
        let (_, e1) = model.sim.cost();
        frame_evals.push(e1 - e0);
        inside += u64::from(model.sim.tick_in_progress());
        assert!(model.sim.time() > t, "frame {frame}: the run moves on");
        t = model.sim.time();
        // Promised = run or skipped, to the clock's remainder: nothing piles up.
        let started = model.ticks + u64::from(model.sim.tick_in_progress());
        let accounted = model.clock.skipped_total() + started as f64 * dt;
        assert!(
            (accounted - frame as f64 * FRAME).abs() <= dt + 1e-9,
            "frame {frame}: {accounted} s accounted for of {} s",
            frame as f64 * FRAME
        );
    }
    assert!(!model.sim.is_finished(), "S1 is far from its end");
    assert!(
        model.ticks < FRAMES && inside == FRAMES,
        "frames end inside a tick: {inside}"
    );
    // The bound: the budget, plus the last step (the budget is checked between steps).
    let (per_step, t_ref) = evals_per_step(&p, model.sim.cost().0);
    assert_eq!(
        t_ref.to_bits(),
        model.sim.time().to_bits(),
        "the app's split ticks follow the very run of a plain one"
    );
    let worst_step = per_step.iter().copied().max().unwrap();
    println!(
        "{} steps, {} ticks, at most {worst_step} evaluations in one; frames of {}–{} evaluations",
        per_step.len(),
        model.ticks,
        frame_evals.iter().min().unwrap(),
        frame_evals.iter().max().unwrap()
    );
    for (i, e) in frame_evals.iter().enumerate() {
        assert!(
            *e <= BUDGET + worst_step,
            "frame {}: {e} evaluations over a budget of {BUDGET} (+ {worst_step})",
            i + 1
        );
        assert!(*e >= BUDGET, "frame {}: stopped early ({e})", i + 1);
    }
    let r = model.running_behind().expect("it runs behind");
    // All the frames lie inside the pace's window.
    assert!(FRAMES as f64 * FRAME < PACE_WINDOW);
    let expected = FRAMES as f64 * FRAME / (t - t0);
    assert!(
        (r - expected).abs() <= 1e-9 * expected,
        "{r} real s per simulated s, measured {expected}"
    );
    assert!(r > 5.0, "{r}");
    model.refresh_shown();
    assert_eq!(model.shown.behind, Some(r));
    let words = stoneskip::ui::behind_words(r, 1.0);
    assert_eq!(
        words,
        format!("physics running behind: {r:.0}× slower than real time")
    );
}

/// A whole throw through the app with a frame budget smaller than its costly ticks: frames end
/// inside ticks, ticks complete inside frames and new ones begin; each frame stays within its
/// budget plus one step, nothing piles up, and the run is the headless one, bit for bit.
#[test]
fn a_throw_under_a_tight_frame_budget_is_the_headless_run() {
    const BUDGET: u64 = 40;
    const FRAME: f64 = 1.0 / 60.0;
    let p = wavy_throw(Integrator::Adaptive);
    let mut model = Model::new(p.clone(), None, Default::default()).unwrap();
    model.budget = FrameBudget {
        wall: Duration::from_secs(3600),
        wall_behind: Duration::from_secs(3600),
        force_evals: BUDGET,
    };
    model.throw();
    let (per_step, _) = evals_per_step(&p, u64::MAX);
    let worst_step = per_step.iter().copied().max().unwrap();
    let (mut frames, mut inside, mut both) = (0u64, 0u64, 0u64);
    while !model.sim.is_finished() {
        let (_, e0) = model.sim.cost();
        let ticks = model.ticks;
        model.advance(FRAME);
        frames += 1;
        let e = model.sim.cost().1 - e0;
        assert!(e <= BUDGET + worst_step, "frame {frames}: {e} evaluations");
        inside += u64::from(model.sim.tick_in_progress());
        // A tick completed in this frame and the next one yielded in it.
        both += u64::from(model.ticks > ticks && model.sim.tick_in_progress());
        let started = model.ticks + u64::from(model.sim.tick_in_progress());
        let accounted = model.clock.skipped_total() + started as f64 * p.physics.dt;
        assert!((accounted - frames as f64 * FRAME).abs() <= p.physics.dt + 1e-9);
        assert!(frames < 1_000_000);
    }
    println!("{frames} frames: {inside} end inside a tick, {both} after completing one");
    assert!(
        inside >= 10 && both >= 5,
        "{inside} frames inside a tick, {both} both"
    );
    let mut headless = Simulation::new(&p).unwrap();
    for _ in 0..model.ticks {
        headless.tick();
    }
    assert_eq!(
        summary_bits(&model.sim.summary()),
        summary_bits(&headless.summary())
    );
}

/// A normal throw is untouched by the guard: every frame runs all its ticks whole, nothing is
/// skipped, nothing is said, and the run is the headless one.
#[test]
fn a_normal_throw_runs_every_tick_whole() {
    // The shipped default throw, on a narrower lake in coarser cells so the test runs in a moment.
    let mut p = Preset::version_1();
    p.water.size = [40.0, 4.0];
    p.water.cell = 0.1;
    let mut model = Model::new(p.clone(), None, Default::default()).unwrap();
    model.budget.wall = Duration::from_secs(3600);
    model.budget.wall_behind = Duration::from_secs(3600);
    model.throw();
    let mut frames = 0u64;
    let mut worst = 0;
    while !model.sim.is_finished() {
        let (_, e0) = model.sim.cost();
        model.advance(1.0 / 60.0);
        worst = worst.max(model.sim.cost().1 - e0);
        frames += 1;
        assert!(!model.sim.tick_in_progress(), "frame {frames}");
        assert_eq!(model.running_behind(), None, "frame {frames}");
        assert!(frames < 100_000);
    }
    assert_eq!(model.clock.skipped_total(), 0.0);
    println!(
        "{frames} frames, at most {worst} force evaluations in one; {:?}",
        model.sim.summary().outcome
    );
    assert!(
        model.sim.skips() >= 3,
        "a whole throw: {}",
        model.sim.skips()
    );
    assert!(
        worst < stoneskip::app::model::PHYSICS_EVAL_BUDGET / 10,
        "{worst} evaluations in a frame"
    );
    // The frame that saw the outcome ran its remaining ticks (water only): as many plain ticks.
    let mut headless = Simulation::new(&p).unwrap();
    for _ in 0..model.ticks {
        headless.tick();
    }
    assert_eq!(
        summary_bits(&model.sim.summary()),
        summary_bits(&headless.summary())
    );
}

/// The pace says "behind" while a frame of the last second ran short, and clears a second of
/// frames that kept up later.
#[test]
fn running_behind_clears_once_the_physics_keeps_up() {
    let mut pace = Pace::default();
    assert_eq!(pace.behind(), None);
    // Frames of 1/8 s (exact in binary): the window of one second holds eight.
    for _ in 0..30 {
        pace.record(0.125, 0.00125, true);
    }
    let r = pace.behind().unwrap();
    assert!((r - 100.0).abs() < 1e-9, "{r}");
    for i in 0..7 {
        pace.record(0.125, 0.125, false);
        assert!(
            pace.behind().is_some(),
            "frame {i}: a short frame is in the window"
        );
    }
    pace.record(0.125, 0.125, false);
    assert_eq!(pace.behind(), None);
    // Nothing advanced at all: an infinite slowdown, said in words.
    pace.clear();
    pace.record(0.125, 0.0, true);
    assert_eq!(pace.behind(), Some(f64::INFINITY));
    assert!(stoneskip::ui::behind_words(f64::INFINITY, 1.0).contains("no simulated time"));
}

/// Finding S1's first input (fuzz/slow/simulate/s1-free-plate-tolerance-3e-10, as the fuzz
/// harness builds it): a 60 cm, 3 kg plate launched half under water at a 75° tilt, spinning at
/// 75 rev/s with 100 rad/s about every axis, free rotation, Adaptive at 3.5·10⁻¹⁰, 50 µs ticks,
/// no water grid: 6.3·10⁸ force evaluations per simulated second.
fn s1() -> Preset {
    let mut p = Preset::version_1();
    p.stone.shape = Shape::Plate {
        length: 0.5999999655643478,
        width: 0.6,
        thickness: 0.1,
    };
    p.stone.mass = 3.000000000000001;
    p.stone.segments = 21;
    let l = &mut p.launch;
    l.position = [50.0, 50.0, 0.0];
    l.velocity = [
        2.1648901405887335e-17,
        0.3535533905932738,
        0.35355339059327373,
    ];
    l.attitude = Attitude {
        tilt_deg: 75.0,
        bank_deg: 60.0,
        heading_deg: 180.0,
    };
    l.spin = 471.23889803846896;
    l.angular_velocity = [100.0; 3];
    let ph = &mut p.physics;
    ph.gravity = 30.0;
    ph.water_density = 3000.0;
    ph.force_law = ForceLaw::Rosellini;
    ph.lift_coefficient = Some(5.0);
    ph.friction_coefficient = Some(2.0);
    ph.ventilated = true;
    ph.integrator = Integrator::Adaptive;
    ph.tolerance = 3.522914625643156e-10;
    ph.rotation = Rotation::Free;
    ph.dt = 5.000000000000004e-5;
    ph.max_time = 0.01;
    p.water.enabled = false;
    p.water.size = [2.0, 2.0];
    p.water.cell = 0.02;
    p.water.depth = 0.02;
    p
}

/// The frame times docs/reliability.md reports ("Cost guard"): the app model on both S1 inputs
/// with the default budget, each frame fed the real time of the one before (as the app does).
/// A measurement, not a test: wall-clock figures depend on the machine.
#[test]
#[ignore = "a measurement: cargo test --release --test cost_guard -- --ignored --nocapture"]
fn measure_frame_times_on_s1() {
    const FRAMES: usize = 120;
    for (name, p) in [("s1", s1()), ("s1b", s1b())] {
        if let Ok(dir) = std::env::var("STONESKIP_GUARD_PRESETS") {
            let path = std::path::Path::new(&dir).join(format!("{name}.ron"));
            stoneskip_physics::preset::save(&path, &p).unwrap();
        }
        let mut model = Model::new(p.clone(), None, Default::default()).unwrap();
        model.throw();
        let mut times = Vec::new();
        let mut gap = 1.0 / 60.0;
        let (_, e0) = model.sim.cost();
        for _ in 0..FRAMES {
            let start = std::time::Instant::now();
            model.advance(gap);
            gap = start.elapsed().as_secs_f64();
            times.push(gap);
        }
        let evals = model.sim.cost().1 - e0;
        let wall: f64 = times.iter().sum();
        let first = times[0];
        let mut rest = times[1..].to_vec();
        rest.sort_by(f64::total_cmp);
        let n = rest.len();
        let behind = model.running_behind();
        println!(
            "{name}: {FRAMES} frames; advance: first {:.1} ms, then median {:.1} ms, 95th \
             percentile {:.1} ms, max {:.1} ms; {:.3} ms simulated in {wall:.2} s ({:.0}× \
             slower), {} ticks, {evals} evaluations ({:.2e}/s); shown: {:?}",
            1e3 * first,
            1e3 * rest[n / 2],
            1e3 * rest[n * 95 / 100],
            1e3 * rest[n - 1],
            1e3 * model.sim.time(),
            wall / model.sim.time(),
            model.ticks,
            evals as f64 / wall,
            behind.map(|r| stoneskip::ui::behind_words(r, 1.0)),
        );
    }
}
