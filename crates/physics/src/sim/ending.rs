//! Every ending in words (issue 48): why a throw ended, read off the physics of its last touch —
//! the stone's attitude (tilt and bank relative to its travel) and its speed and descent when it
//! met the water — not only the [`Outcome`]. One function, [`ending`], so the app's readouts, the
//! contacts table, `simulate`'s text and JSON, and the Experiments table and CSV say the same.

use glam::DVec3;
use serde::Serialize;

use super::{ContactEvent, Outcome, Summary, OPEN_WATER_LIMIT};

/// Above this impact angle (the velocity's angle below the horizontal at the touch) no stone
/// bounces, whatever its speed (Clanet, Hersen & Bocquet 2004, Nature 427: ~45°).
pub const STEEPEST_BOUNCE_DEG: f64 = 45.0;

/// A bank (roll about the direction of travel) beyond which the stone meets the water on its
/// rim rather than its face: its lift then tips sideways and down, and it does not bounce flat.
/// Skipping stones stay within a few degrees of level over their skips; the shipped default
/// sinks at 15 m/s after landing banked 26°.
pub const EDGE_BANK_DEG: f64 = 20.0;

/// Why a throw ended, from the physics of its last touch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Ending {
    /// No outcome yet (running, or stopped by the user).
    Running,
    /// Sank at its first touch, arriving level and not too steep: it was too slow to skip.
    TooSlow {
        /// Speed at the touch (m/s).
        speed: f64,
    },
    /// Sank at the end of a contact after skipping, arriving level: it had slowed too much.
    SankAfterLastSkip {
        /// Skips before it sank.
        skips: usize,
        /// The contact it sank in, counted from 1.
        touch: usize,
        /// Speed when that contact began (m/s).
        speed: f64,
        /// Tilt when that contact began and when the stone went under (°): a tilt that falls
        /// in the water is the stone digging in.
        tilt: [f64; 2],
    },
    /// Sank with its leading edge down (tilt below zero when it met the water or when it went
    /// under): the water pushes a nose-down face further down.
    NoseDown {
        /// The contact it sank in, counted from 1.
        touch: usize,
        /// The lower of the tilts at the touch and when it went under (°).
        tilt: f64,
    },
    /// Sank after meeting the water banked beyond [`EDGE_BANK_DEG`].
    OnEdge {
        /// The contact it sank in, counted from 1.
        touch: usize,
        /// Bank at the touch (°).
        bank: f64,
    },
    /// Sank after meeting the water steeper than [`STEEPEST_BOUNCE_DEG`].
    TooSteep {
        /// The contact it sank in, counted from 1.
        touch: usize,
        /// Impact angle below the horizontal (°).
        descent: f64,
    },
    /// Still skipping or flying when the run reached `max_time`.
    TimeLimit {
        /// The time reached (s).
        time: f64,
    },
    /// Left the water grid where the contact reads it (wavy contact): not a result of the throw.
    LeftLake,
    /// Flew past the far limit (1 km) from the launch.
    FarLimit,
    /// The integration failed.
    Diverged,
}

impl Ending {
    /// A short snake_case name (the JSON's `kind`, the CSV's `ending` column).
    pub fn kind(&self) -> &'static str {
        match self {
            Ending::Running => "running",
            Ending::TooSlow { .. } => "too_slow",
            Ending::SankAfterLastSkip { .. } => "sank_after_last_skip",
            Ending::NoseDown { .. } => "nose_down",
            Ending::OnEdge { .. } => "on_edge",
            Ending::TooSteep { .. } => "too_steep",
            Ending::TimeLimit { .. } => "time_limit",
            Ending::LeftLake => "left_lake",
            Ending::FarLimit => "far_limit",
            Ending::Diverged => "diverged",
        }
    }

    /// The ending as a person says it, with the number that decided it.
    pub fn words(&self) -> String {
        match *self {
            Ending::Running => "stopped".to_owned(),
            Ending::TooSlow { speed } => {
                format!("too slow to skip ({speed:.1} m/s at the first touch)")
            }
            Ending::SankAfterLastSkip {
                skips,
                touch,
                speed,
                tilt,
            } => format!(
                "sank after its last skip ({skips} skip{}; touch {touch} at {speed:.1} m/s, tilt \
                 {:.0}° to {:.0}°)",
                if skips == 1 { "" } else { "s" },
                tilt[0] + 0.0,
                tilt[1] + 0.0
            ),
            Ending::NoseDown { touch, tilt } => {
                format!("dug in nose-down at touch {touch} (tilt {tilt:.1}°)")
            }
            Ending::OnEdge { touch, bank } => format!(
                "landed on its edge at touch {touch} (bank {:.0}°, over {EDGE_BANK_DEG:.0}°)",
                bank.abs()
            ),
            Ending::TooSteep { touch, descent } => format!(
                "came in too steep at touch {touch} ({descent:.0}° down, over {STEEPEST_BOUNCE_DEG:.0}°)"
            ),
            Ending::TimeLimit { time } => format!("still going at the time limit ({time:.0} s)"),
            Ending::LeftLake => "left the lake (not a result: wavy contact ends a throw at the lake's edge)".to_owned(),
            Ending::FarLimit => format!("flew past {:.0} km", OPEN_WATER_LIMIT / 1000.0),
            Ending::Diverged => "diverged (the numbers stopped being finite)".to_owned(),
        }
    }

    /// Whether the throw's numbers are a result of the throw, not of the simulation's bounds
    /// (the lake's edge, the time limit, a failed integration, a run not ended).
    pub fn is_result(&self) -> bool {
        !matches!(
            self,
            Ending::Running | Ending::LeftLake | Ending::TimeLimit { .. } | Ending::Diverged
        )
    }
}

/// Why the run of `s` ended, read from its outcome and its last contact (design.md §4: a
/// contact's `attitude_in` is [tilt, bank, heading] relative to the travel at its first touch,
/// `attitude_out` when it ended — for the contact it sank in, when it went under).
pub fn ending(s: &Summary) -> Ending {
    read(s.outcome, &s.contacts, s.skips, s.distance, s.final_time)
}

/// [`ending`] from a run's parts (what [`super::Simulation::ending`] reads without a summary).
pub(crate) fn read(
    outcome: Option<Outcome>,
    contacts: &[ContactEvent],
    skips: usize,
    distance: f64,
    final_time: f64,
) -> Ending {
    match outcome {
        None => Ending::Running,
        Some(Outcome::Timeout) => Ending::TimeLimit { time: final_time },
        Some(Outcome::Diverged) => Ending::Diverged,
        Some(Outcome::LeftDomain) if distance >= OPEN_WATER_LIMIT => Ending::FarLimit,
        Some(Outcome::LeftDomain) => Ending::LeftLake,
        Some(Outcome::Sank) => sank(contacts, skips),
    }
}

fn sank(contacts: &[ContactEvent], skips: usize) -> Ending {
    let Some(last) = contacts.last() else {
        // Sinking needs a contact; read as the slowest ending if a summary says otherwise.
        return Ending::TooSlow { speed: 0.0 };
    };
    let touch = contacts.len();
    let speed = DVec3::from_array(last.v_in).length();
    let [tilt_in, bank_in, _] = last.attitude_in;
    let tilt_out = last.attitude_out[0];
    if last.beta_in > STEEPEST_BOUNCE_DEG {
        Ending::TooSteep {
            touch,
            descent: last.beta_in,
        }
    } else if bank_in.abs() > EDGE_BANK_DEG {
        Ending::OnEdge {
            touch,
            bank: bank_in,
        }
    } else if tilt_in < 0.0 || tilt_out < 0.0 {
        Ending::NoseDown {
            touch,
            tilt: tilt_in.min(tilt_out),
        }
    } else if skips == 0 {
        Ending::TooSlow { speed }
    } else {
        Ending::SankAfterLastSkip {
            skips,
            touch,
            speed,
            tilt: [tilt_in, tilt_out],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(v_in: [f64; 3], attitude_in: [f64; 3], attitude_out: [f64; 3]) -> ContactEvent {
        let beta_in = (-v_in[2]).atan2(v_in[0].hypot(v_in[1])).to_degrees();
        ContactEvent {
            t_start: 0.0,
            t_end: 0.01,
            skip: false,
            graze: false,
            x: 0.0,
            y: 0.0,
            v_in,
            v_out: [0.0; 3],
            attitude_in,
            attitude_out,
            beta_in,
            peak_lift: 0.0,
            touches: 1,
            weight: 1.0,
            exit_xy: [0.0; 2],
            open: false,
        }
    }

    fn summary(outcome: Option<Outcome>, contacts: Vec<ContactEvent>, skips: usize) -> Summary {
        Summary {
            schema: 1,
            name: String::new(),
            outcome,
            diverged_reason: None,
            skips,
            distance: 5.0,
            final_time: 20.0,
            steps: 0,
            force_evals: 0,
            contacts,
            water: None,
        }
    }

    const LEVEL: [f64; 3] = [10.0, 0.0, 0.0];

    #[test]
    fn a_level_stone_that_sinks_was_too_slow() {
        let first = summary(
            Some(Outcome::Sank),
            vec![touch([1.6, 0.0, -0.3], LEVEL, LEVEL)],
            0,
        );
        assert_eq!(
            ending(&first),
            Ending::TooSlow {
                speed: 1.6f64.hypot(0.3)
            }
        );
        assert!(ending(&first).words().starts_with("too slow to skip"));
        let later = summary(
            Some(Outcome::Sank),
            vec![
                touch([5.0, 0.0, -0.5], LEVEL, LEVEL),
                touch([2.0, 0.0, 0.0], LEVEL, LEVEL),
            ],
            1,
        );
        assert_eq!(
            ending(&later),
            Ending::SankAfterLastSkip {
                skips: 1,
                touch: 2,
                speed: 2.0,
                tilt: [10.0, 10.0]
            }
        );
        assert_eq!(
            ending(&later).words(),
            "sank after its last skip (1 skip; touch 2 at 2.0 m/s, tilt 10° to 10°)"
        );
    }

    #[test]
    fn the_attitude_at_the_last_touch_decides() {
        let v = [5.0, 0.0, -0.5];
        let two = |a_in: [f64; 3], a_out: [f64; 3]| {
            ending(&summary(
                Some(Outcome::Sank),
                vec![touch(v, LEVEL, LEVEL), touch(v, a_in, a_out)],
                1,
            ))
        };
        // Arriving nose-down, or pitched nose-down before going under.
        assert_eq!(
            two([-1.1, 0.0, 0.0], LEVEL),
            Ending::NoseDown {
                touch: 2,
                tilt: -1.1
            }
        );
        assert_eq!(
            two(LEVEL, [-30.0, 0.0, 0.0]),
            Ending::NoseDown {
                touch: 2,
                tilt: -30.0
            }
        );
        // Banked past the edge limit, either way; within it, level.
        assert_eq!(
            two([8.0, -26.0, 0.0], LEVEL),
            Ending::OnEdge {
                touch: 2,
                bank: -26.0
            }
        );
        assert!(two([8.0, 26.0, 0.0], LEVEL).words().contains("on its edge"));
        assert!(matches!(
            two([8.0, 19.0, 0.0], LEVEL),
            Ending::SankAfterLastSkip { .. }
        ));
        // Steeper than any bounce.
        let steep = ending(&summary(
            Some(Outcome::Sank),
            vec![touch([4.0, 0.0, -4.8], [20.0, 0.0, 0.0], LEVEL)],
            0,
        ));
        assert!(matches!(steep, Ending::TooSteep { touch: 1, descent } if descent > 50.0));
    }

    #[test]
    fn bounds_of_the_simulation_are_not_results() {
        let s = |o| ending(&summary(o, vec![touch(LEVEL, LEVEL, LEVEL)], 3));
        assert_eq!(s(Some(Outcome::LeftDomain)), Ending::LeftLake);
        assert_eq!(s(Some(Outcome::Timeout)), Ending::TimeLimit { time: 20.0 });
        for e in [
            s(None),
            s(Some(Outcome::LeftDomain)),
            s(Some(Outcome::Timeout)),
            s(Some(Outcome::Diverged)),
        ] {
            assert!(!e.is_result(), "{e:?}");
        }
        assert!(s(Some(Outcome::Sank)).is_result());
        let mut far = summary(Some(Outcome::LeftDomain), Vec::new(), 0);
        far.distance = OPEN_WATER_LIMIT + 1.0;
        assert_eq!(ending(&far), Ending::FarLimit);
        assert_eq!(
            ending(&summary(Some(Outcome::Sank), Vec::new(), 0)).kind(),
            "too_slow"
        );
    }

    fn faster(p: &crate::sim::params::Preset, k: f64) -> crate::sim::params::Preset {
        let mut q = p.clone();
        q.launch.velocity = q.launch.velocity.map(|v| v * k);
        q
    }

    /// Issue 48: on the ambient water (the shipped case) no throw of a shipped preset, thrown
    /// 1.5× faster, ends by the lake's edge (or by the time limit): it ends by its physics.
    #[test]
    fn shipped_presets_thrown_faster_end_by_their_physics() {
        for (stem, _) in crate::preset::SHIPPED {
            let p = crate::preset::shipped(stem).unwrap().unwrap();
            if p.water.wavy_contact {
                continue;
            }
            let s = crate::sim::simulate(&faster(&p, 1.5)).unwrap();
            let e = ending(&s);
            assert!(e.is_result(), "{stem} 1.5× faster: {} ({e:?})", e.words());
        }
    }

    /// Issue 48: the default stone on the Moon without air skips on to its end (it sinks), not
    /// to the time limit; and farther than on Earth.
    #[test]
    fn the_default_on_the_moon_runs_to_its_end() {
        let earth = crate::preset::shipped("default").unwrap().unwrap();
        let mut moon = earth.clone();
        crate::sim::world::World::Moon.apply(&mut moon.physics);
        assert_eq!((moon.physics.gravity, moon.physics.air), (1.62, None));
        let s = crate::sim::simulate(&moon).unwrap();
        assert_eq!(s.outcome, Some(Outcome::Sank), "{}", ending(&s).words());
        let on_earth = crate::sim::simulate(&earth).unwrap();
        assert!(s.distance > 2.0 * on_earth.distance, "{} m", s.distance);
    }
}
