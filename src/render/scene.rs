//! The scene description the renderer draws: stone pose and mesh, water heights, trail, contact
//! markers, splash cues and the camera. It is built from a [`Simulation`] the same way in the window
//! and offscreen, so a picture test checks the picture the app shows. Building it never steps the
//! physics; the caller's ticks do.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{DQuat, DVec3, Vec3};

use super::camera::Camera;
use crate::sim::stone::Mesh;
use crate::sim::{ContactEvent, Simulation, StepSample};

/// How long a splash cue lasts after a contact begins (s of simulated time).
pub const SPLASH_DURATION: f64 = 0.9;

/// The stone as drawn.
#[derive(Debug, Clone, Copy)]
pub struct StoneView<'a> {
    /// Body-frame mesh (centre of mass at the origin).
    pub mesh: &'a Mesh,
    /// World position of the centre of mass (m).
    pub position: DVec3,
    /// Stone → world rotation.
    pub orientation: DQuat,
    /// Largest horizontal half-extent (m): scales the material and the shadow.
    pub radius: f64,
}

/// The water grid's heights as drawn.
#[derive(Debug, Clone, Copy)]
pub struct WaterView<'a> {
    /// η (m above z = 0), row-major `iy * nx + ix`.
    pub heights: &'a [f32],
    pub nx: usize,
    pub ny: usize,
    /// Cell size (m).
    pub cell: f64,
    /// The grid's −x, −y corner (m).
    pub origin: [f64; 2],
    /// Changes whenever `heights` does (the renderer uploads only then).
    pub revision: u64,
}

/// Where the stone touched the water.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker {
    pub x: f64,
    pub y: f64,
    /// The episode ended with the stone in the air again.
    pub skip: bool,
    /// The episode is still going on.
    pub open: bool,
}

/// A splash cue: a contact seen `age` seconds after it began.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Splash {
    pub x: f64,
    pub y: f64,
    /// Simulated seconds since the contact began.
    pub age: f64,
    /// Entry speed (m/s): sizes the crown.
    pub speed: f64,
}

/// What to draw besides the physics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneStyle {
    pub show_trail: bool,
    pub show_markers: bool,
    pub show_splashes: bool,
    /// Multiplies the water's slopes in the shading (1 = true to the simulation).
    pub ripple_gain: f32,
}

impl Default for SceneStyle {
    fn default() -> Self {
        Self {
            show_trail: true,
            show_markers: true,
            show_splashes: true,
            ripple_gain: 1.0,
        }
    }
}

/// Everything one frame shows.
#[derive(Debug, Clone)]
pub struct Scene<'a> {
    pub camera: Camera,
    /// Simulated time (s): animates the fine wind ripples.
    pub time: f64,
    pub stone: Option<StoneView<'a>>,
    pub water: Option<WaterView<'a>>,
    /// The centre of mass's path so far (world, m).
    pub trail: &'a [Vec3],
    pub markers: Vec<Marker>,
    pub splashes: Vec<Splash>,
    pub style: SceneStyle,
}

impl<'a> Scene<'a> {
    /// The scene of `sim` now. `pose` overrides the stone's pose (the app's interpolation between
    /// two ticks); `heights` must have been refreshed from `sim`.
    pub fn from_simulation(
        sim: &'a Simulation,
        pose: Option<(DVec3, DQuat)>,
        trail: &'a Trail,
        heights: &'a WaterHeights,
        camera: Camera,
        style: SceneStyle,
    ) -> Self {
        let (position, orientation) = pose.unwrap_or_else(|| sim.world_from_stone());
        let stone = Some(StoneView {
            mesh: &sim.stone().mesh,
            position,
            orientation,
            radius: sim.stone().shape.half_extent(),
        });
        let water = sim.water().and_then(|w| {
            (heights.data.len() == w.nx() * w.ny() && !heights.data.is_empty()).then(|| WaterView {
                heights: &heights.data,
                nx: w.nx(),
                ny: w.ny(),
                cell: w.cell(),
                origin: w.origin(),
                revision: heights.revision,
            })
        });
        let t = sim.time();
        Self {
            camera,
            time: t,
            stone,
            water,
            trail: trail.points(),
            markers: markers_of(sim.contacts()),
            splashes: splashes_of(sim.contacts(), t),
            style,
        }
    }

    /// Axis-aligned box around the trail, the markers and the stone (for "frame all").
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut pts: Vec<Vec3> = self.trail.to_vec();
        pts.extend(
            self.markers
                .iter()
                .map(|m| Vec3::new(m.x as f32, m.y as f32, 0.0)),
        );
        if let Some(s) = &self.stone {
            pts.push(s.position.as_vec3());
        }
        let first = *pts.first()?;
        let (lo, hi) = pts
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        // Include the water level.
        Some((lo.with_z(lo.z.min(0.0)), hi.with_z(hi.z.max(0.0))))
    }
}

/// One marker per contact episode.
pub fn markers_of(contacts: &[ContactEvent]) -> Vec<Marker> {
    contacts
        .iter()
        .map(|c| Marker {
            x: c.x,
            y: c.y,
            skip: c.skip,
            open: c.open,
        })
        .collect()
}

/// Splash cues of the contacts that began less than [`SPLASH_DURATION`] before `time`.
pub fn splashes_of(contacts: &[ContactEvent], time: f64) -> Vec<Splash> {
    contacts
        .iter()
        .filter(|c| time >= c.t_start && time - c.t_start < SPLASH_DURATION)
        .map(|c| Splash {
            x: c.x,
            y: c.y,
            age: time - c.t_start,
            speed: DVec3::from_array(c.v_in).length(),
        })
        .collect()
}

/// The trajectory as drawn: centre-of-mass positions, thinned so a point is kept every
/// [`Trail::SPACING`] metres, at every change of contact, and at the newest sample.
#[derive(Debug, Clone, Default)]
pub struct Trail {
    points: Vec<Vec3>,
    last_kept: Option<Vec3>,
    last_contact: bool,
    /// The last point is the newest position, not yet kept.
    moving_end: bool,
}

impl Trail {
    /// Distance between kept points (m).
    pub const SPACING: f32 = 0.01;
    /// Most points kept; past it the spacing doubles (a very long run stays cheap to draw).
    pub const MAX_POINTS: usize = 20_000;

    pub fn new() -> Self {
        Self::default()
    }

    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Starts the trail at the launch position.
    pub fn start(&mut self, position: DVec3) {
        self.clear();
        let p = position.as_vec3();
        self.points.push(p);
        self.last_kept = Some(p);
    }

    /// Adds an accepted step of the simulation.
    pub fn push(&mut self, sample: &StepSample) {
        let p = sample.state.position.as_vec3();
        if !p.is_finite() {
            return;
        }
        let spacing = Self::SPACING * (1 + self.points.len() / Self::MAX_POINTS) as f32;
        let far = self.last_kept.is_none_or(|q| q.distance(p) >= spacing);
        let keep = far || sample.in_contact != self.last_contact;
        match (self.moving_end, self.points.last_mut()) {
            // The moving end (newest position) becomes a kept point, or moves on.
            (true, Some(last)) => *last = p,
            _ => self.points.push(p),
        }
        self.moving_end = !keep;
        if keep {
            self.last_kept = Some(p);
        }
        self.last_contact = sample.in_contact;
    }

    pub fn points(&self) -> &[Vec3] {
        &self.points
    }
}

static NEXT_REVISION: AtomicU64 = AtomicU64::new(1);

/// The water heights copied out of the grid for the renderer; refreshed only when the water has
/// stepped (the copy is the CPU's whole per-frame water work).
#[derive(Debug, Clone, Default)]
pub struct WaterHeights {
    data: Vec<f32>,
    revision: u64,
    seen: Option<(u64, u64)>,
}

impl WaterHeights {
    pub fn new() -> Self {
        Self::default()
    }

    /// Copies η from `sim` if the grid stepped since the last call. `generation` must change when
    /// the simulation is rebuilt (a new grid). Returns whether a copy happened.
    pub fn refresh(&mut self, sim: &Simulation, generation: u64) -> bool {
        let Some(w) = sim.water() else {
            self.data.clear();
            self.seen = None;
            return false;
        };
        let key = (generation, w.steps());
        if self.seen == Some(key) {
            return false;
        }
        w.eta_f32(&mut self.data);
        self.seen = Some(key);
        // Unique across every WaterHeights of the process, so a renderer never mistakes one for another.
        self.revision = NEXT_REVISION.fetch_add(1, Ordering::Relaxed);
        true
    }

    pub fn data(&self) -> &[f32] {
        &self.data
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::integrate::BodyState;

    fn sample(t: f64, x: f64, in_contact: bool) -> StepSample {
        StepSample {
            time: t,
            state: BodyState {
                position: DVec3::new(x, 0.0, 0.1),
                velocity: DVec3::X,
                orientation: DQuat::IDENTITY,
                angular_momentum: DVec3::ZERO,
            },
            angular_velocity: DVec3::ZERO,
            in_contact,
            wetted_area: 0.0,
            force: DVec3::ZERO,
        }
    }

    #[test]
    fn trail_thins_but_keeps_the_newest_point_and_contact_changes() {
        let mut trail = Trail::new();
        trail.start(DVec3::new(0.0, 0.0, 0.1));
        for i in 1..=1000 {
            // 1 mm apart: about one point kept per centimetre.
            trail.push(&sample(i as f64 * 1e-4, i as f64 * 1e-3, false));
        }
        let n = trail.points().len();
        assert!((95..=110).contains(&n), "{n} points");
        assert!((trail.points()[n - 1].x - 1.0).abs() < 1e-6);
        let before = trail.points().len();
        trail.push(&sample(0.2, 1.0001, true));
        trail.push(&sample(0.2001, 1.0002, true));
        assert!(trail.points().len() > before);
    }

    #[test]
    fn splashes_fade_out() {
        let mut sim = Simulation::new(&crate::sim::params::Preset::default()).unwrap();
        while sim.contacts().is_empty() && sim.time() < 2.0 {
            sim.tick();
        }
        let c = sim.contacts()[0];
        assert!(splashes_of(&[c], c.t_start - 0.1).is_empty());
        assert_eq!(splashes_of(&[c], c.t_start + 0.1).len(), 1);
        assert!(splashes_of(&[c], c.t_start + SPLASH_DURATION + 0.01).is_empty());
        assert_eq!(markers_of(&[c]).len(), 1);
    }
}
