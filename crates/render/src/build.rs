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
use stoneskip_physics::sim::ending::{Ending, EDGE_BANK_DEG};
use stoneskip_physics::sim::launch_arc;
use stoneskip_physics::sim::params::Preset;
use stoneskip_physics::sim::stone::Stone;
use stoneskip_physics::sim::{ContactEvent, Simulation, StepSample};

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

/// The colours of the side view's attitude glyphs: level (bank within [`BANK_LEVEL_DEG`]),
/// banked (within [`EDGE_BANK_DEG`]), on its edge (beyond), and the touch it dug in nose-down at.
pub const GLYPH_LEVEL_COLOR: [f32; 4] = [0.07, 0.07, 0.06, 1.0];
pub const GLYPH_BANKED_COLOR: [f32; 4] = [0.95, 0.25, 0.0, 1.0];
pub const GLYPH_EDGE_COLOR: [f32; 4] = [0.6, 0.0, 0.6, 1.0];
pub const GLYPH_DUG_IN_COLOR: [f32; 4] = [0.9, 0.0, 0.0, 1.0];
/// A bank within this (°) draws the glyph as level.
pub const BANK_LEVEL_DEG: f64 = 10.0;

/// The glyph's thickness over its diameter: a pebble's 1 : 4, thick enough to read at a few
/// pixels (the shipped stones are thinner).
pub const GLYPH_THICKNESS: f64 = 0.25;

/// The glyph's size on screen: its diameter a share of the view's height.
pub const GLYPH_SHARE: f32 = 0.055;

/// The touch (counted from 1, as [`stoneskip_physics::sim::ending::Ending`] counts) where the throw dug in
/// nose-down, if it ended so.
pub fn dug_in_touch(sim: &Simulation) -> Option<usize> {
    match sim.ending() {
        Ending::NoseDown { touch, .. } => Some(touch),
        _ => None,
    }
}

/// The colour of a glyph for a stone that met the water banked `bank_deg`.
pub fn glyph_color(bank_deg: f64, dug_in: bool) -> [f32; 4] {
    if dug_in {
        GLYPH_DUG_IN_COLOR
    } else if bank_deg.abs() > EDGE_BANK_DEG {
        GLYPH_EDGE_COLOR
    } else if bank_deg.abs() > BANK_LEVEL_DEG {
        GLYPH_BANKED_COLOR
    } else {
        GLYPH_LEVEL_COLOR
    }
}

/// The outline of a stone 1 across and `thickness` thick met by the water at `tilt` and `bank`
/// (radians, relative to travel; design §3), seen from its side: an ellipse in (along travel,
/// up) whose long axis rises at `tilt` exactly (nose-up above zero, nose-down below), so the
/// angle a class reads off is the tilt. A bank opens it, as a rolled disc looks rounder from the
/// side: its short axis is the larger of `thickness` and the diameter times |sin bank|.
pub fn side_profile(tilt: f64, bank: f64, thickness: f64) -> Vec<[f64; 2]> {
    let (st, ct) = tilt.sin_cos();
    let long = 0.5;
    let short = (0.5 * thickness).max(0.5 * bank.sin().abs()).min(0.5);
    (0..GLYPH_POINTS)
        .map(|k| {
            let phi = k as f64 / GLYPH_POINTS as f64 * std::f64::consts::TAU;
            let (u, v) = (long * phi.cos(), short * phi.sin());
            [u * ct - v * st, u * st + v * ct]
        })
        .collect()
}

/// Points of a glyph's outline.
pub const GLYPH_POINTS: usize = 32;

/// Where the side view draws the glyph of a contact, and how large (m along the waterline):
/// its centre stands over the touch, on top of the touch's tick.
pub fn glyph_centre(c: &ContactEvent, camera: &Camera) -> (Vec3, f32) {
    let view_h = 2.0 * camera.distance * (0.5 * camera.fov_y).tan();
    let k = camera.exaggeration.max(1e-3);
    let size = GLYPH_SHARE * view_h;
    // The tick's top (5 % of the view's height, see [`side_guides`]) and half a glyph more.
    let rise = (0.05 * view_h + 0.6 * size) / k;
    (Vec3::new(c.x as f32, c.y as f32, rise), size)
}

/// The side view's attitude glyphs: at each touch ([`glyph_touches`]), the stone as it met the
/// water — its profile at its tilt, drawn at the true angle whatever the exaggeration (the
/// heights of the glyph are divided by it, as the camera multiplies them), coloured by its bank
/// ([`glyph_color`]); the touch it dug in nose-down at (`dug_in`, counted from 1) drawn in red
/// and wider.
pub fn attitude_glyphs(
    framing: &Framing,
    contacts: &[ContactEvent],
    camera: &Camera,
    dug_in: Option<usize>,
) -> Vec<Line> {
    let along = Vec3::new(framing.heading.cos(), framing.heading.sin(), 0.0);
    let k = camera.exaggeration.max(1e-3);
    let mut lines = Vec::new();
    for i in glyph_touches(framing, contacts, camera, dug_in) {
        let c = &contacts[i];
        let [tilt, bank, _] = c.attitude_in;
        let here = dug_in == Some(i + 1);
        let (centre, size) = glyph_centre(c, camera);
        let to_world = |q: [f64; 2]| {
            centre + along * (q[0] as f32 * size) + Vec3::Z * (q[1] as f32 * size / k)
        };
        let outline = side_profile(tilt.to_radians(), bank.to_radians(), GLYPH_THICKNESS);
        let color = glyph_color(bank, here);
        let width_px = if here { 4.0 } else { 2.5 };
        let n = outline.len();
        lines.extend((0..n).map(|j| Line {
            a: to_world(outline[j]),
            b: to_world(outline[(j + 1) % n]),
            width_px,
            color,
        }));
    }
    lines
}

/// Glyphs closer than this many glyph widths along the waterline are not both drawn.
pub const GLYPH_GAP: f32 = 1.15;

/// The contacts (indices) whose glyphs the side view draws: every touch (grazes left out) but
/// one that would overlap the last drawn (touches closer than [`GLYPH_GAP`] glyphs apart, as the
/// small hops at a long throw's end are seen from far); the touch it dug in at always, in place
/// of its neighbour. Zooming in (a smaller glyph in metres) brings the others back.
pub fn glyph_touches(
    framing: &Framing,
    contacts: &[ContactEvent],
    camera: &Camera,
    dug_in: Option<usize>,
) -> Vec<usize> {
    let along = Vec3::new(framing.heading.cos(), framing.heading.sin(), 0.0);
    let mut kept: Vec<(usize, f32)> = Vec::new();
    for (i, c) in contacts.iter().enumerate() {
        let [tilt, bank, _] = c.attitude_in;
        if c.graze || !(tilt.is_finite() && bank.is_finite()) {
            continue;
        }
        let (centre, size) = glyph_centre(c, camera);
        let s = (centre - framing.launch).dot(along);
        let must = dug_in == Some(i + 1);
        match kept.last() {
            Some(&(_, last)) if (s - last).abs() < GLYPH_GAP * size => {
                if must {
                    kept.pop();
                    kept.push((i, s));
                }
            }
            _ => kept.push((i, s)),
        }
    }
    kept.into_iter().map(|(i, _)| i).collect()
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
    use stoneskip_physics::sim::integrate::BodyState;

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

    /// The angle (°) of the longest chord through the outline's centre: the glyph's long axis.
    fn long_axis_deg(pts: &[[f64; 2]]) -> f64 {
        let far = pts
            .iter()
            .max_by(|p, q| p[0].hypot(p[1]).total_cmp(&q[0].hypot(q[1])))
            .unwrap();
        // Either end of the axis: fold to (−90°, 90°].
        let a = far[1].atan2(far[0]).to_degrees();
        if a > 90.0 {
            a - 180.0
        } else if a <= -90.0 {
            a + 180.0
        } else {
            a
        }
    }

    /// Issue 48: the glyph's long axis rises at the stone's tilt whatever its bank; a bank
    /// only opens it (its area grows).
    #[test]
    fn the_glyph_is_drawn_at_the_tilt() {
        for tilt in [-8.0f64, -1.1, 0.0, 8.4, 20.0, 45.0] {
            for bank in [-26.0f64, 0.0, 5.0, 30.0] {
                let pts = side_profile(tilt.to_radians(), bank.to_radians(), GLYPH_THICKNESS);
                assert_eq!(pts.len(), GLYPH_POINTS);
                // Half the angle between two outline points bounds the error of the sampled axis.
                let tol = 360.0 / GLYPH_POINTS as f64;
                let got = long_axis_deg(&pts);
                assert!((got - tilt).abs() <= tol, "tilt {tilt} bank {bank}: {got}");
                assert!(pts.iter().all(|p| p[0].is_finite() && p[1].is_finite()));
            }
        }
        // Exactly: the first point is the nose, at the tilt.
        let p = side_profile((-1.1f64).to_radians(), 0.0, GLYPH_THICKNESS)[0];
        assert!((p[1].atan2(p[0]).to_degrees() + 1.1).abs() < 1e-9);
        let width = |b: f64| {
            let pts = side_profile(0.0, b.to_radians(), GLYPH_THICKNESS);
            pts.iter().map(|p| p[1]).fold(f64::MIN, f64::max)
        };
        assert!(width(40.0) > 1.5 * width(0.0));
        assert_eq!(width(0.0), width(5.0));
    }

    /// Issue 48: the side view's vertical exaggeration does not bend the glyphs: at ×1, ×5, ×10
    /// and ×20 a touch's glyph points, on screen, at the stone's tilt (within a degree: the side
    /// camera's narrow perspective).
    #[test]
    fn exaggeration_leaves_the_glyphs_angle_true() {
        let mut sim = Simulation::new(&Preset::default()).unwrap();
        while sim.contacts().len() < 2 && sim.time() < 5.0 {
            sim.tick();
        }
        let mut c = sim.contacts()[1];
        c.attitude_in = [-12.0, 0.0, 0.0];
        let trail = Trail::new();
        let framing = framing_of(&sim, &trail, None);
        let (w, h) = (1280u32, 720u32);
        for k in [1.0f32, 5.0, 10.0, 20.0] {
            let lo = framing.bounds.0;
            let hi = framing.bounds.1;
            let cam = Camera::side_view(lo, hi, framing.heading, w as f32 / h as f32, k);
            let lines = attitude_glyphs(&framing, &[c], &cam, None);
            assert_eq!(lines.len(), GLYPH_POINTS);
            // The nose (first point) and the tail (half way round).
            let nose = cam.project(lines[0].a, w, h).unwrap();
            let tail = cam.project(lines[GLYPH_POINTS / 2].a, w, h).unwrap();
            let on_screen = (tail.y - nose.y).atan2(nose.x - tail.x).to_degrees();
            assert!((on_screen + 12.0).abs() < 1.0, "×{k}: {on_screen}°");
            // A glyph a class can see: tens of pixels across.
            assert!(
                nose.distance(tail) > 20.0,
                "×{k}: {} px",
                nose.distance(tail)
            );
        }
    }

    /// Touches too close to tell apart at the view's scale share one glyph; the touch a throw
    /// dug in at is always drawn.
    #[test]
    fn close_touches_share_a_glyph_and_the_dug_in_one_is_always_drawn() {
        let mut sim = Simulation::new(&Preset::default()).unwrap();
        while sim.contacts().is_empty() && sim.time() < 5.0 {
            sim.tick();
        }
        let c = sim.contacts()[0];
        let trail = Trail::new();
        let framing = framing_of(&sim, &trail, None);
        let cam = Camera::side_view(
            Vec3::ZERO,
            Vec3::new(200.0, 0.0, 0.3),
            framing.heading,
            16.0 / 9.0,
            10.0,
        );
        let (_, size) = glyph_centre(&c, &cam);
        let at = |x: f64| ContactEvent { x, ..c };
        let far = 2.0 * size as f64;
        let near = 0.3 * size as f64;
        let touches = [
            at(10.0),
            at(10.0 + near),
            at(10.0 + far),
            at(10.0 + far + near),
        ];
        assert_eq!(glyph_touches(&framing, &touches, &cam, None), vec![0, 2]);
        assert_eq!(glyph_touches(&framing, &touches, &cam, Some(4)), vec![0, 3]);
        // Close in, every touch has its own.
        let close = Camera::side_view(
            Vec3::ZERO,
            Vec3::new(0.5, 0.0, 0.3),
            framing.heading,
            16.0 / 9.0,
            10.0,
        );
        let small: Vec<ContactEvent> = (0..4).map(|k| at(k as f64 * near)).collect();
        assert_eq!(glyph_touches(&framing, &small, &close, None).len(), 4);
    }

    /// The glyph of the touch a throw dug in at is the red one; the others are coloured by bank.
    #[test]
    fn the_dug_in_touch_is_red_and_banks_have_colours() {
        assert_eq!(glyph_color(0.0, true), GLYPH_DUG_IN_COLOR);
        assert_eq!(glyph_color(-3.0, false), GLYPH_LEVEL_COLOR);
        assert_eq!(glyph_color(15.0, false), GLYPH_BANKED_COLOR);
        assert_eq!(glyph_color(-26.0, false), GLYPH_EDGE_COLOR);
    }

    #[test]
    fn splashes_fade_out() {
        let mut sim =
            Simulation::new(&stoneskip_physics::sim::params::Preset::version_1()).unwrap();
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
