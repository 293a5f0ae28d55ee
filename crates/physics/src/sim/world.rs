//! Worlds (issue 48): Earth, the Moon, Mars, or Earth without air — gravity, the air's density
//! and a time limit that fits a throw there, set together, so "what if the Moon?" is one choice,
//! not three hidden steps.

use super::params::{AirParams, Physics};

/// A world: gravity and the air together (issue 48), for "what if the Moon?" in one click.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum World {
    /// 9.81 m/s², air 1.204 kg/m³.
    Earth,
    /// 1.62 m/s², no air.
    Moon,
    /// 3.71 m/s², air 0.020 kg/m³.
    Mars,
    /// Earth's gravity without air (the paper's vacuum).
    NoAir,
}

impl World {
    /// Every world, in the panel's order.
    pub const ALL: [World; 4] = [World::Earth, World::Moon, World::Mars, World::NoAir];

    /// The world's name as the panel shows it.
    pub fn name(self) -> &'static str {
        match self {
            World::Earth => "Earth",
            World::Moon => "Moon",
            World::Mars => "Mars",
            World::NoAir => "No air",
        }
    }

    /// Gravity (m/s²).
    pub fn gravity(self) -> f64 {
        match self {
            World::Earth | World::NoAir => 9.81,
            World::Moon => 1.62,
            World::Mars => 3.71,
        }
    }

    /// The air's density (kg/m³); `None`: no air.
    pub fn air_density(self) -> Option<f64> {
        match self {
            World::Earth => Some(AirParams::default().density),
            // The mean surface pressure's density (about 0.6 kPa of CO₂ at 210 K).
            World::Mars => Some(0.020),
            World::Moon | World::NoAir => None,
        }
    }

    /// A time limit that fits a throw here (s): every flight lasts longer as gravity weakens
    /// (by g_Earth / g for the same launch), so Earth's 20 s becomes about a minute on Mars and
    /// two on the Moon, where the default stone skips for 38 s without air (59 skips, 234 m).
    pub fn time_limit(self) -> f64 {
        match self {
            World::Earth | World::NoAir => 20.0,
            World::Mars => 60.0,
            World::Moon => 120.0,
        }
    }

    /// Sets `physics`'s gravity and air to this world's (the air's coefficients kept when it
    /// has air), and raises its time limit to [`World::time_limit`] where it is shorter.
    pub fn apply(self, physics: &mut Physics) {
        physics.gravity = self.gravity();
        physics.air = self.air_density().map(|density| AirParams {
            density,
            ..physics.air.unwrap_or_default()
        });
        physics.max_time = physics.max_time.max(self.time_limit());
    }

    /// The world whose gravity and air `physics` has, if any.
    pub fn of(physics: &Physics) -> Option<World> {
        World::ALL.into_iter().find(|w| {
            (physics.gravity - w.gravity()).abs() < 1e-9
                && match (w.air_density(), physics.air) {
                    (None, None) => true,
                    (Some(d), Some(a)) => (a.density - d).abs() < 1e-9,
                    _ => false,
                }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each world sets gravity and the air together and is read back as itself; the air's
    /// coefficients survive a trip through the Moon and back; the time limit only grows.
    #[test]
    fn a_world_sets_gravity_and_air_together() {
        let mut p = Physics::version_1();
        p.air = Some(AirParams {
            lift_slope: 2.5,
            ..AirParams::default()
        });
        for w in World::ALL {
            w.apply(&mut p);
            assert_eq!(World::of(&p), Some(w), "{}", w.name());
            assert_eq!(p.gravity, w.gravity());
            assert_eq!(p.air.map(|a| a.density), w.air_density());
            assert!(p.max_time >= w.time_limit());
            assert!(p.validate().is_ok(), "{}", w.name());
        }
        World::Earth.apply(&mut p);
        assert_eq!(
            p.air.map(|a| a.lift_slope),
            Some(AirParams::default().lift_slope)
        );
        assert_eq!(p.max_time, World::Moon.time_limit());
        p.gravity = 5.0;
        assert_eq!(World::of(&p), None);
    }
}
