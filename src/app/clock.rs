//! A fixed-step clock after Glenn Fiedler's "Fix your timestep!" and bevy's `Time<Fixed>`: real
//! time accumulates (scaled by the playback speed), whole fixed steps are taken out of it, and what
//! remains gives the interpolation factor between the last two steps. Pause stops accumulating;
//! Step asks for exactly one step; a cap on the steps of one frame stops the spiral of death and
//! reports the simulated time it skipped instead of squeezing it into bigger steps.
//!
//! The clock knows no wall clock of its own: the caller hands it the real seconds of each frame,
//! so every rule here is a unit test.

/// Longest real time one frame may add (s): a window stalled for seconds does not fast-forward.
pub const MAX_FRAME_DT: f64 = 0.25;

/// What one frame of the clock asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Advance {
    /// Whole fixed steps to run now.
    pub steps: u64,
    /// Simulated time dropped by the per-frame cap (s).
    pub skipped: f64,
}

/// The fixed-step accumulator.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedClock {
    step: f64,
    accumulator: f64,
    /// Simulated seconds per real second (slow motion below 1, fast playback above).
    speed: f64,
    paused: bool,
    /// Most steps one frame may run.
    max_steps: u64,
    /// Simulated time skipped in all (s).
    skipped_total: f64,
    /// One step requested by [`FixedClock::request_step`].
    step_pending: bool,
}

impl FixedClock {
    /// A clock of fixed step `step` (s) running at most `max_steps` steps a frame.
    pub fn new(step: f64, max_steps: u64) -> Self {
        Self {
            step: sane_step(step),
            accumulator: 0.0,
            speed: 1.0,
            paused: false,
            max_steps: max_steps.max(1),
            skipped_total: 0.0,
            step_pending: false,
        }
    }

    pub fn step(&self) -> f64 {
        self.step
    }

    /// Changes the fixed step (a live change of `dt`); the accumulated time is kept.
    pub fn set_step(&mut self, step: f64) {
        self.step = sane_step(step);
    }

    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Playback speed, clamped to [0.01, 8]; a non-finite value keeps the old one.
    pub fn set_speed(&mut self, speed: f64) {
        if speed.is_finite() {
            self.speed = speed.clamp(0.01, 8.0);
        }
    }

    pub fn set_max_steps(&mut self, n: u64) {
        self.max_steps = n.max(1);
    }

    pub fn max_steps(&self) -> u64 {
        self.max_steps
    }

    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// Pausing stops accumulating and drops the partial step (the drawn pose is then the last step's).
    pub fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
        if paused {
            self.accumulator = 0.0;
        }
    }

    /// Asks for exactly one step at the next [`FixedClock::advance`], paused or not.
    pub fn request_step(&mut self) {
        self.step_pending = true;
    }

    /// Back to an empty accumulator (a new run); speed and pause stay.
    pub fn reset(&mut self) {
        self.accumulator = 0.0;
        self.step_pending = false;
    }

    pub fn skipped_total(&self) -> f64 {
        self.skipped_total
    }

    pub fn clear_skipped(&mut self) {
        self.skipped_total = 0.0;
    }

    /// Adds `real_dt` seconds of real time and says how many whole steps are due.
    pub fn advance(&mut self, real_dt: f64) -> Advance {
        if std::mem::take(&mut self.step_pending) {
            self.accumulator = 0.0;
            return Advance {
                steps: 1,
                skipped: 0.0,
            };
        }
        if self.paused {
            return Advance {
                steps: 0,
                skipped: 0.0,
            };
        }
        let dt = if real_dt.is_finite() {
            real_dt.clamp(0.0, MAX_FRAME_DT)
        } else {
            0.0
        };
        self.accumulator += dt * self.speed;
        // A tiny tolerance so that 0.1 s of 0.0005 s steps is 200 steps, not 199.
        let due = ((self.accumulator / self.step) + 1e-9).floor().max(0.0) as u64;
        let steps = due.min(self.max_steps);
        self.accumulator = (self.accumulator - steps as f64 * self.step).max(0.0);
        let mut skipped = 0.0;
        if due > steps {
            let whole = (due - steps) as f64 * self.step;
            self.accumulator = (self.accumulator - whole).max(0.0);
            skipped = whole;
            self.skipped_total += whole;
        }
        Advance { steps, skipped }
    }

    /// Simulated time the caller could not run (a wall-time budget ran out) after [`advance`]
    /// promised it: counted as skipped.
    ///
    /// [`advance`]: FixedClock::advance
    pub fn skip_steps(&mut self, steps: u64) {
        let t = steps as f64 * self.step;
        self.skipped_total += t;
    }

    /// How far the present lies between the last two steps (0 = at the last step, < 1).
    pub fn alpha(&self) -> f64 {
        (self.accumulator / self.step).clamp(0.0, 1.0)
    }
}

fn sane_step(step: f64) -> f64 {
    if step.is_finite() && step > 0.0 {
        step
    } else {
        1e-3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 0.0005;

    #[test]
    fn accumulates_real_time_into_whole_steps() {
        let mut c = FixedClock::new(DT, 10_000);
        // 1/60 s is 33.3 steps: 33 now, the remainder carried.
        let a = c.advance(1.0 / 60.0);
        assert_eq!(a.steps, 33);
        assert!((c.alpha() - (1.0 / 60.0 / DT - 33.0)).abs() < 1e-6);
        // Three frames make 100 steps in all: nothing is lost.
        let total = a.steps + c.advance(1.0 / 60.0).steps + c.advance(1.0 / 60.0).steps;
        assert_eq!(total, 100);
        assert!(c.alpha() < 1e-6);
    }

    #[test]
    fn alpha_interpolates_between_steps() {
        let mut c = FixedClock::new(0.01, 100);
        assert_eq!(c.advance(0.025).steps, 2);
        assert!((c.alpha() - 0.5).abs() < 1e-9);
        assert!((0.0..1.0).contains(&c.alpha()));
    }

    #[test]
    fn pause_stops_accumulating() {
        let mut c = FixedClock::new(DT, 10_000);
        c.advance(0.0103);
        c.set_paused(true);
        for _ in 0..100 {
            assert_eq!(c.advance(0.1).steps, 0);
        }
        assert_eq!(c.alpha(), 0.0);
        c.set_paused(false);
        assert_eq!(c.advance(0.01).steps, 20);
    }

    #[test]
    fn slow_motion_and_fast_playback_scale_time() {
        let mut slow = FixedClock::new(DT, 10_000);
        slow.set_speed(0.1);
        assert_eq!(slow.advance(0.1).steps, 20);
        let mut fast = FixedClock::new(DT, 10_000);
        fast.set_speed(4.0);
        assert_eq!(fast.advance(0.1).steps, 800);
        fast.set_speed(f64::NAN);
        assert_eq!(fast.speed(), 4.0);
    }

    #[test]
    fn step_runs_exactly_one_step() {
        let mut c = FixedClock::new(DT, 10_000);
        c.set_paused(true);
        c.request_step();
        assert_eq!(c.advance(1.0).steps, 1);
        assert_eq!(c.advance(1.0).steps, 0);
        // Also while running: the step replaces the frame's accumulation.
        c.set_paused(false);
        c.request_step();
        assert_eq!(c.advance(0.2).steps, 1);
    }

    #[test]
    fn the_cap_reports_the_time_it_skipped() {
        let mut c = FixedClock::new(DT, 100);
        let a = c.advance(0.2);
        // 400 steps were due, 100 run, 300 skipped.
        assert_eq!(a.steps, 100);
        assert!((a.skipped - 300.0 * DT).abs() < 1e-9, "{}", a.skipped);
        assert!((c.skipped_total() - 0.15).abs() < 1e-9);
        // No spiral: the next ordinary frame is back to normal.
        assert_eq!(c.advance(0.01).steps, 20);
        c.clear_skipped();
        assert_eq!(c.skipped_total(), 0.0);
    }

    #[test]
    fn a_stalled_frame_adds_at_most_the_frame_limit() {
        let mut c = FixedClock::new(0.01, 1_000_000);
        assert_eq!(c.advance(30.0).steps, 25);
        assert_eq!(c.advance(f64::NAN).steps, 0);
        assert_eq!(c.advance(-1.0).steps, 0);
    }
}
