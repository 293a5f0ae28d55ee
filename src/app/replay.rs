//! Replay: the preset of the last throw and the live physics changes made during it, each at the
//! tick it took effect. Replaying rebuilds the simulation from the same preset and applies the same
//! changes at the same ticks, so the replay is bit-identical to the original run (design §4: the
//! app and the command line make the same calls).

use stoneskip_physics::sim::params::{Physics, Preset};
use stoneskip_physics::sim::Simulation;

/// The last throw and its live changes.
#[derive(Debug, Clone, Default)]
pub struct ReplayLog {
    last_throw: Option<Preset>,
    /// (tick, physics) in tick order.
    log: Vec<(u64, Physics)>,
    /// Changes still to apply while replaying, the next one last.
    queue: Vec<(u64, Physics)>,
    replaying: bool,
}

impl ReplayLog {
    /// A fresh throw of `preset`: the log starts empty.
    pub fn start_throw(&mut self, preset: Preset) {
        self.last_throw = Some(preset);
        self.log.clear();
        self.queue.clear();
        self.replaying = false;
    }

    /// Nothing to replay any more (another preset was loaded).
    pub fn forget(&mut self) {
        *self = Self::default();
    }

    /// Stops applying logged changes (a reset); the log is kept for a later replay.
    pub fn stop(&mut self) {
        self.queue.clear();
        self.replaying = false;
    }

    pub fn can_replay(&self) -> bool {
        self.last_throw.is_some()
    }

    /// A replay is running (its changes are being applied).
    pub fn is_replaying(&self) -> bool {
        self.replaying
    }

    pub fn changes(&self) -> usize {
        self.log.len()
    }

    /// The user changed the physics live at `tick`: recorded, and it takes over from any replayed
    /// change still to come.
    pub fn record(&mut self, tick: u64, physics: Physics) {
        self.queue.clear();
        self.replaying = false;
        self.log.retain(|(t, _)| *t <= tick);
        self.log.push((tick, physics));
    }

    /// Starts a replay: the preset to rebuild from; the logged changes are queued.
    pub fn start_replay(&mut self) -> Option<Preset> {
        let preset = self.last_throw.clone()?;
        self.queue = self.log.iter().rev().copied().collect();
        self.replaying = true;
        Some(preset)
    }

    /// Applies the changes due at `tick` (before that tick runs).
    pub fn apply_due(&mut self, tick: u64, sim: &mut Simulation) {
        while self.queue.last().is_some_and(|(t, _)| *t <= tick) {
            if let Some((_, p)) = self.queue.pop() {
                // The logged physics was accepted once; a failure here would be a bug, not input.
                let _ = sim.set_physics(p);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::model::Model;
    use stoneskip_physics::sim::params::Preset;
    use stoneskip_physics::sim::Summary;

    /// A small lake so the test runs in a moment; the coupling to the water is on.
    fn preset() -> Preset {
        let mut p = Preset::version_1();
        p.water.size = [6.0, 2.0];
        p.water.cell = 0.05;
        p.physics.max_time = 3.0;
        p
    }

    /// Runs the model's loop at 60 frames a second until the outcome; `change_at` applies a
    /// live gravity change at the first frame past that simulated time (s).
    fn run_in_app(model: &mut Model, change_at: Option<f64>) -> Summary {
        let mut changed = false;
        let mut frames = 0;
        while !model.sim.is_finished() && frames < 100_000 {
            if let Some(t) = change_at {
                if !changed && model.sim.time() >= t {
                    model.edit.physics.gravity = 9.0;
                    model.handle(crate::ui::Action::PhysicsEdited);
                    changed = true;
                }
            }
            model.advance(1.0 / 60.0);
            frames += 1;
        }
        model.sim.summary()
    }

    #[test]
    fn a_replay_is_bit_identical_to_the_run_and_to_simulate() {
        let p = preset();
        let mut model = Model::new(p.clone(), None, Default::default()).unwrap();
        model.throw();
        let first = run_in_app(&mut model, None);
        assert!(first.outcome.is_some());
        model.replay();
        let again = run_in_app(&mut model, None);
        let headless = stoneskip_physics::sim::simulate(&p).unwrap();
        // PartialEq on the f64 fields: bit for bit (no NaN in a summary). The headless run leaves
        // the water at rest when the stone does not read it; the app steps it for the rings.
        assert_eq!(first, again);
        let stone_only = |s: &stoneskip_physics::sim::Summary| stoneskip_physics::sim::Summary {
            water: None,
            ..s.clone()
        };
        assert_eq!(stone_only(&first), stone_only(&headless));
        assert_eq!(
            headless.water.map(|w| w.stepped),
            p.water.enabled.then_some(p.water.wavy_contact)
        );
        assert!(first.skips >= 1, "{first:?}");
    }

    #[test]
    fn a_replay_repeats_live_changes_at_the_same_tick() {
        let p = preset();
        let mut model = Model::new(p.clone(), None, Default::default()).unwrap();
        model.throw();
        let changed = run_in_app(&mut model, Some(0.1));
        // The live change is a different run from the preset's …
        assert_ne!(changed, stoneskip_physics::sim::simulate(&p).unwrap());
        // … and the replay repeats it exactly, although nobody touches the panel now.
        model.edit.physics.gravity = p.physics.gravity;
        model.replay();
        assert!(model.replay_log.is_replaying());
        let again = run_in_app(&mut model, None);
        assert_eq!(changed, again);
    }
}
