//! Building a [`Scene`] from a [`Simulation`]: the stone's pose, the water heights copied for the
//! GPU, the thinned trail, the contact markers and splash cues, and the guide lines (the side view's
//! waterline and skip ticks, the aim preview, ghosts of earlier throws). The app and `stoneskip
//! render` build it the same way. Building never steps the physics; the caller's ticks do.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{DQuat, DVec3, Vec3};

use super::camera::{throw_heading, Camera, Framing};
use super::scene::{
    Line, Marker, Scene, SceneStyle, Splash, StoneView, WaterView, SPLASH_DURATION,
};
use crate::sim::launch_arc;
use crate::sim::params::Preset;
use crate::sim::stone::Stone;
use crate::sim::{ContactEvent, Simulation, StepSample};

/// The scene of `sim` now. `pose` overrides the stone's pose (the app's interpolation between
/// two ticks); `heights` must have been refreshed from `sim`.
pub fn scene_of<'a>(
    sim: &'a Simulation,
    pose: Option<(DVec3, DQuat)>,
    trail: &'a Trail,
    heights: &'a WaterHeights,
    camera: Camera,
    style: SceneStyle,
) -> Scene<'a> {
    let (position, orientation) = pose.unwrap_or_else(|| sim.world_from_stone());
    let stone = Some(StoneView {
        mesh: &sim.stone().mesh,
        position,
        orientation,
        radius: sim.stone().shape.half_extent(),
    });
    // The lake's geometry, also while its grid steps on another thread (`sim::lake`); its
    // heights are the copy `heights` holds.
    let water = sim.lake_geometry().and_then(|g| {
        (heights.data.len() == g.nx * g.ny && !heights.data.is_empty()).then(|| WaterView {
            heights: &heights.data,
            nx: g.nx,
            ny: g.ny,
            cell: g.cell,
            origin: g.origin,
            revision: heights.revision,
        })
    });
    let t = sim.time();
    let lines = sim
        .lake_geometry()
        .map(|g| lake_rim(g.origin, g.far_corner()))
        .unwrap_or_default();
    Scene {
        camera,
        time: t,
        stone,
        water,
        trail: trail.points(),
        markers: markers_of(sim.contacts()),
        splashes: splashes_of(sim.contacts(), t),
        lines,
        style,
        side_view: false,
    }
}

/// The colour of the lake's rim: sand, unlike water or sky.
pub const RIM_COLOR: [f32; 4] = [0.95, 0.78, 0.35, 1.0];

/// Longest piece of the rim (m).
pub const RIM_PIECE: f32 = 0.5;

/// The lake's edges: a sand-coloured shore line around the water grid (`lo` its −x, −y corner,
/// `hi` the +x, +y one) with short posts at the corners, so the edge shows in every camera.
pub fn lake_rim(lo: [f64; 2], hi: [f64; 2]) -> Vec<Line> {
    let posts = corners(lo, hi).into_iter().map(|c| Line {
        a: c,
        b: c + Vec3::Z * 0.5,
        width_px: 3.0,
        color: RIM_COLOR,
    });
    rectangle(lo, hi, 3.0, RIM_COLOR).chain(posts).collect()
}

/// The corners of the rectangle [lo, hi] at z = 0, counter-clockwise from `lo`.
fn corners(lo: [f64; 2], hi: [f64; 2]) -> [Vec3; 4] {
    [
        Vec3::new(lo[0] as f32, lo[1] as f32, 0.0),
        Vec3::new(hi[0] as f32, lo[1] as f32, 0.0),
        Vec3::new(hi[0] as f32, hi[1] as f32, 0.0),
        Vec3::new(lo[0] as f32, hi[1] as f32, 0.0),
    ]
}

/// The edges of the rectangle [lo, hi] at z = 0 in pieces of at most [`RIM_PIECE`]: a chase
/// camera stands inside it, and a line with an end behind the eye is not drawn.
fn rectangle(
    lo: [f64; 2],
    hi: [f64; 2],
    width_px: f32,
    color: [f32; 4],
) -> impl Iterator<Item = Line> {
    let c = corners(lo, hi);
    (0..4).flat_map(move |k| {
        let (a, b) = (c[k], c[(k + 1) % 4]);
        let n = ((a.distance(b) / RIM_PIECE).ceil() as usize).clamp(1, 4096);
        (0..n).map(move |i| Line {
            a: a.lerp(b, i as f32 / n as f32),
            b: a.lerp(b, (i + 1) as f32 / n as f32),
            width_px,
            color,
        })
    })
}

/// One marker per contact episode, grazes left out (they are not bounces a student sees).
pub fn markers_of(contacts: &[ContactEvent]) -> Vec<Marker> {
    contacts
        .iter()
        .filter(|c| !c.graze)
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
    /// (generation, the grid's steps) of the copy.
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
            // A lake stepping on another thread keeps its last copy; no lake, none.
            if sim.lake_geometry().is_none() {
                self.data.clear();
                self.seen = None;
            }
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

/// What the views frame for `sim` with `trail` (see [`Framing`]).
pub fn framing_of(sim: &Simulation, trail: &Trail, pose: Option<(DVec3, DQuat)>) -> Framing {
    let stone = pose.map_or(sim.state().position, |p| p.0).as_vec3();
    let launch = sim.launch_position().as_vec3();
    let mut lo = launch.min(stone).with_z(0.0);
    let mut hi = launch.max(stone);
    for p in trail.points() {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    for c in sim.contacts() {
        let p = Vec3::new(c.x as f32, c.y as f32, 0.0);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    Framing {
        launch,
        heading: throw_heading(sim.preset()),
        stone,
        velocity: sim.state().velocity.as_vec3(),
        radius: sim.stone().shape.half_extent() as f32,
        bounds: (lo.with_z(lo.z.min(0.0)), hi.with_z(hi.z.max(0.0))),
    }
}

/// Colour of the side view's waterline.
pub const WATERLINE_COLOR: [f32; 4] = [0.05, 0.25, 0.55, 0.9];
/// Colours of the skip ticks: a skip, a contact that did not end in the air, one still going on.
pub const SKIP_COLOR: [f32; 4] = [0.45, 1.0, 0.3, 1.0];
pub const END_COLOR: [f32; 4] = [1.0, 0.3, 0.2, 1.0];
pub const OPEN_COLOR: [f32; 4] = [1.0, 1.0, 1.0, 1.0];

/// The side view's colours, dark and saturated so they read on a projector over the pale sky:
/// the trail, a skip's tick, the tick of the contact that stayed in the water, one still going.
pub const SIDE_TRAIL_COLOR: [f32; 4] = [0.03, 0.09, 0.32, 1.0];
pub const SIDE_SKIP_COLOR: [f32; 4] = [0.0, 0.5, 0.12, 1.0];
pub const SIDE_END_COLOR: [f32; 4] = [0.8, 0.05, 0.05, 1.0];
pub const SIDE_OPEN_COLOR: [f32; 4] = [0.35, 0.35, 0.35, 1.0];

/// The side view's guides: the waterline under the whole trajectory and a tick rising from each
/// contact (green: a skip; red: a contact that did not end in the air; white: still going on; none
/// for a graze).
pub fn side_guides(framing: &Framing, contacts: &[ContactEvent], camera: &Camera) -> Vec<Line> {
    let along = Vec3::new(framing.heading.cos(), framing.heading.sin(), 0.0);
    let (lo, hi) = framing.bounds;
    let from = (lo - framing.launch).dot(along).min(0.0) - 2.0;
    let to = (hi - framing.launch).dot(along).max(3.0) + 2.0;
    let base = framing.launch.with_z(0.0);
    let mut lines = vec![Line {
        a: base + along * from,
        b: base + along * to,
        width_px: 1.5,
        color: WATERLINE_COLOR,
    }];
    // Ticks 5 % of the view's height, whatever the exaggeration.
    let view_h = 2.0 * camera.distance * (0.5 * camera.fov_y).tan();
    let tick = 0.05 * view_h / camera.exaggeration.max(1e-3);
    for c in contacts.iter().filter(|c| !c.graze) {
        let color = if c.open {
            SIDE_OPEN_COLOR
        } else if c.skip {
            SIDE_SKIP_COLOR
        } else {
            SIDE_END_COLOR
        };
        let p = Vec3::new(c.x as f32, c.y as f32, 0.0);
        lines.push(Line {
            a: p,
            b: p + Vec3::Z * tick,
            width_px: 3.0,
            color,
        });
    }
    lines
}

/// The aim preview: the first flight's arc from the launch until the centre of mass reaches the
/// water (the run's own flight model: the exact parabola, or with the air's forces when the preset
/// has them; design §4), dashed.
pub fn aim_preview(preset: &Preset, stone: &Stone) -> Vec<Line> {
    let mut path = launch_arc(preset, stone, 0.01, 5.0);
    if path.len().is_multiple_of(2) {
        // An odd count of points: dashes of one leg, gaps of one, ending on the landing point.
        path.insert(path.len() - 1, path[path.len() - 1]);
    }
    let n = path.len() - 1;
    let at = |k: usize| path[k].as_vec3();
    let color = [0.6, 0.95, 1.0, 0.9];
    let mut lines: Vec<Line> = (0..n)
        .step_by(2)
        .map(|k| Line {
            a: at(k),
            b: at(k + 1),
            width_px: 2.5,
            color,
        })
        .collect();
    // A ring where the centre of mass reaches the water.
    let land = at(n).with_z(0.0);
    let r = 0.25;
    let ring = |k: usize| {
        let a = k as f32 / 24.0 * std::f32::consts::TAU;
        land + Vec3::new(a.cos(), a.sin(), 0.0) * r
    };
    lines.extend((0..24).map(|k| Line {
        a: ring(k),
        b: ring(k + 1),
        width_px: 2.0,
        color,
    }));
    lines
}

/// Ghosts of earlier throws: their trails as thin lines, older ones fainter.
pub fn ghost_lines(ghosts: &[Vec<Vec3>]) -> Vec<Line> {
    let n = ghosts.len().max(1) as f32;
    let mut lines = Vec::new();
    for (i, pts) in ghosts.iter().enumerate() {
        let alpha = 0.25 + 0.45 * (i as f32 + 1.0) / n;
        let color = ghost_color(i, alpha);
        lines.extend(pts.windows(2).map(|w| Line {
            a: w[0],
            b: w[1],
            width_px: 1.5,
            color,
        }));
    }
    lines
}

/// The colour of ghost `i` (the table of earlier throws uses the same).
pub fn ghost_color(i: usize, alpha: f32) -> [f32; 4] {
    const C: [[f32; 3]; 5] = [
        [0.55, 0.75, 1.0],
        [0.95, 0.6, 1.0],
        [0.6, 1.0, 0.85],
        [1.0, 0.65, 0.55],
        [0.85, 0.85, 0.85],
    ];
    let c = C[i % C.len()];
    [c[0], c[1], c[2], alpha]
}

/// A trail thinned to at most `max` points (for ghosts).
pub fn thinned(points: &[Vec3], max: usize) -> Vec<Vec3> {
    if points.len() <= max.max(2) {
        return points.to_vec();
    }
    let step = points.len().div_ceil(max.max(2));
    let mut out: Vec<Vec3> = points.iter().step_by(step).copied().collect();
    if let Some(last) = points.last() {
        out.push(*last);
    }
    out
}

#[cfg(test)]
mod tests {

    /// WCAG 2 contrast ratio of two sRGB colours (components 0–1).
    fn contrast(a: [f32; 3], b: [f32; 3]) -> f32 {
        let lum = |c: [f32; 3]| {
            let lin = |u: f32| {
                if u <= 0.04045 {
                    u / 12.92
                } else {
                    ((u + 0.055) / 1.055).powf(2.4)
                }
            };
            0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2])
        };
        let (x, y) = (lum(a), lum(b));
        (x.max(y) + 0.05) / (x.min(y) + 0.05)
    }

    /// Issue 39, finding 5: the side view's trail and ticks read on a projector. Against the
    /// side view's pale sky (about rgb 196 214 238 on screen) the trail passes WCAG's 7:1 and the
    /// ticks its 3:1 for graphics; the old pale yellow trail had 1.3:1.
    #[test]
    fn the_side_view_reads_on_a_projector() {
        let sky = [196.0 / 255.0, 214.0 / 255.0, 238.0 / 255.0];
        let rgb = |c: [f32; 4]| [c[0], c[1], c[2]];
        assert!(contrast(rgb(SIDE_TRAIL_COLOR), sky) >= 7.0);
        for tick in [SIDE_SKIP_COLOR, SIDE_END_COLOR, SIDE_OPEN_COLOR] {
            assert!(contrast(rgb(tick), sky) >= 3.0, "{tick:?}");
        }
        assert!(contrast([1.0, 0.78, 0.25], sky) < 1.5);
    }

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
                memory: 0.0,
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
        let mut sim = Simulation::new(&crate::sim::params::Preset::version_1()).unwrap();
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
