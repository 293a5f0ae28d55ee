//! The scene description the renderer draws: plain data — stone pose and mesh, water heights,
//! trail, contact markers, splash cues, guide lines and the camera. [`super::build`] makes it from a
//! simulation the same way in the window and offscreen, so a picture test checks the picture the
//! app shows; the renderer never sees a simulation.

use glam::{DQuat, DVec3, Vec3};

use super::camera::Camera;
use stoneskip_physics::sim::stone::Mesh;

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

/// A straight guide line (waterline, skip ticks, aim preview, halo, ghost trails), drawn over
/// the scene at a constant pixel width.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Ends (world, m).
    pub a: Vec3,
    pub b: Vec3,
    /// Width in pixels of the full-resolution view.
    pub width_px: f32,
    /// Linear RGB and alpha.
    pub color: [f32; 4],
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
    /// Guide lines, drawn over everything.
    pub lines: Vec<Line>,
    pub style: SceneStyle,
    /// Drawn for the side view: the trail dark and wide, to read on a projector over the pale
    /// sky (issue 39).
    pub side_view: bool,
}

impl Scene<'_> {
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
