//! The camera: an orbit camera (target, yaw, pitch, distance) with the app's views — the default
//! view (contract: behind and above the launch point, looking along the throw, the horizon in the
//! upper third), following the stone, a side view like the paper's Fig. 13, and framing a box.
//!
//! World frame z up. Matrices are right-handed with wgpu's depth range, reversed (near → 1, infinity
//! → 0) for precision from the stone to the horizon.
//!
//! Vertical exaggeration (the side view's 5×, 10×, 20×, as a plot of a flat trajectory would) is a
//! scale of z before the view transform: the camera lives in the exaggerated "view space"
//! (`to_view_space`), the matrices take true world points, and `eye_world` is the eye in the world.

use glam::{Mat4, Vec2, Vec3, Vec4};

use stoneskip_physics::sim::params::Preset;

/// Vertical field of view of every view (radians).
pub const FOV_Y: f32 = 50.0 * std::f32::consts::PI / 180.0;
/// Vertical field of view of the side view (radians): narrow, so it reads like a plot.
pub const SIDE_FOV_Y: f32 = 20.0 * std::f32::consts::PI / 180.0;
/// Near clipping distance (m).
pub const NEAR: f32 = 0.02;
/// Lowest eye height the controls allow (m): the view stays above the water.
pub const MIN_EYE_HEIGHT: f32 = 0.05;
/// Eye of the default view: this far behind the launch point (m) …
pub const DEFAULT_BACK: f32 = 2.6;
/// … and this far above it (m). The view looks down at the launch point, 17° below the
/// horizontal: the horizon sits at 0.66 of the half-height above the centre, a sixth of the
/// height from the top (in the upper third), and the throw runs up the middle of the picture.
pub const DEFAULT_RISE: f32 = 0.8;

/// The side view's vertical exaggerations offered (1 = true proportions).
pub const EXAGGERATIONS: [f32; 4] = [1.0, 5.0, 10.0, 20.0];

/// The app's cameras (`stoneskip render --view`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewMode {
    /// Behind and above the launch point, looking along the throw (the default before a throw).
    Behind,
    /// From the throw's left, the whole trajectory so far in view, heights exaggerated.
    Side,
    /// A chase camera close behind the stone (the default while a throw runs).
    Follow,
    /// From above, the whole trajectory in view.
    Top,
    /// Wherever the user orbited, panned or zoomed to.
    Free,
}

impl ViewMode {
    /// `behind`, `side`, `follow`, `top` (the command line's names).
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "behind" => Some(Self::Behind),
            "side" => Some(Self::Side),
            "follow" | "chase" => Some(Self::Follow),
            "top" => Some(Self::Top),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Behind => "behind",
            Self::Side => "side",
            Self::Follow => "follow",
            Self::Top => "top",
            Self::Free => "free",
        }
    }
}

/// What the views are framed on (world, m): plain data taken from the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Framing {
    /// The launch point and the throw's heading (radians about +z from +x).
    pub launch: Vec3,
    pub heading: f32,
    /// The stone's centre of mass and velocity now.
    pub stone: Vec3,
    pub velocity: Vec3,
    /// The stone's largest horizontal half-extent.
    pub radius: f32,
    /// Box around what was thrown so far (trail, markers, stone, the water level).
    pub bounds: (Vec3, Vec3),
}

/// How far ahead of the stone the side and top views keep open water (m).
pub const LEAD: f32 = 2.5;

/// The camera of `mode` for `framing` in a view of `aspect`; `None` for [`ViewMode::Free`].
pub fn camera_for(mode: ViewMode, f: &Framing, aspect: f32, exaggeration: f32) -> Option<Camera> {
    let along = Vec3::new(f.heading.cos(), f.heading.sin(), 0.0);
    match mode {
        ViewMode::Behind => Some(Camera::orbiting(f.launch, f.heading)),
        ViewMode::Follow => Some(Camera::chase(f.stone, f.velocity, f.heading, f.radius)),
        ViewMode::Side => {
            // At least the launch and a few metres ahead of it and of the stone, so the flight
            // has room and the stone never reaches the view's edge (under its labels).
            let ahead = f.launch + along * 3.0;
            let lead = f.stone.with_z(0.0) + along * LEAD;
            let lo = f.bounds.0.min(f.launch.min(ahead).with_z(0.0)).min(lead);
            let hi = f.bounds.1.max(f.launch.max(ahead)).max(lead);
            Some(Camera::side_view(lo, hi, f.heading, aspect, exaggeration))
        }
        ViewMode::Top => {
            let lead = f.stone.with_z(0.0) + along * LEAD;
            let ahead = f.launch + along * 3.0;
            let lo = f.bounds.0.min(f.launch.min(ahead)).min(lead);
            let hi = f.bounds.1.max(f.launch.max(ahead)).max(lead);
            Some(Camera::top_view(lo, hi, f.heading, aspect))
        }
        ViewMode::Free => None,
    }
}

/// An orbit camera looking at `target` from `distance` along the direction (yaw, pitch).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Point looked at (m).
    pub target: Vec3,
    /// Direction of view about +z from +x (radians).
    pub yaw: f32,
    /// Elevation of the view direction (radians, negative looks down).
    pub pitch: f32,
    /// Eye to target (m).
    pub distance: f32,
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// Heights are drawn this many times taller (1 = true; the side view's 5×, 10×, 20×).
    pub exaggeration: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self::orbiting(Vec3::ZERO, 0.0)
    }
}

impl Camera {
    /// The default view of a preset (contract): behind and above the launch point, looking along
    /// the throw's heading, the horizon in the upper third.
    pub fn default_for(preset: &Preset) -> Self {
        let l = &preset.launch;
        let launch = Vec3::new(
            l.position[0] as f32,
            l.position[1] as f32,
            l.position[2] as f32,
        );
        Self::orbiting(launch, throw_heading(preset))
    }

    /// The default view's geometry about `point`: [`DEFAULT_BACK`] behind it along `yaw`,
    /// [`DEFAULT_RISE`] above it, looking at it (so orbit and zoom turn about the launch point).
    fn orbiting(point: Vec3, yaw: f32) -> Self {
        let mut cam = Self {
            target: point,
            yaw,
            pitch: -(DEFAULT_RISE / DEFAULT_BACK).atan(),
            distance: DEFAULT_BACK.hypot(DEFAULT_RISE),
            fov_y: FOV_Y,
            exaggeration: 1.0,
        };
        cam.keep_above_water();
        cam
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        direction(self.yaw, self.pitch)
    }

    /// Eye position in view space (m; heights exaggerated).
    pub fn eye(&self) -> Vec3 {
        self.target - self.forward() * self.distance
    }

    /// Eye position in the world (m).
    pub fn eye_world(&self) -> Vec3 {
        self.from_view_space(self.eye())
    }

    fn k(&self) -> f32 {
        if self.exaggeration.is_finite() && self.exaggeration > 0.0 {
            self.exaggeration
        } else {
            1.0
        }
    }

    /// A world point in the exaggerated space the camera lives in.
    pub fn to_view_space(&self, world: Vec3) -> Vec3 {
        world * Vec3::new(1.0, 1.0, self.k())
    }

    /// Back from [`Camera::to_view_space`].
    pub fn from_view_space(&self, p: Vec3) -> Vec3 {
        p / Vec3::new(1.0, 1.0, self.k())
    }

    pub fn view_from_world(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Z)
            * Mat4::from_scale(Vec3::new(1.0, 1.0, self.k()))
    }

    /// Reversed-depth infinite perspective for a viewport of `aspect` = width / height.
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 1e-3 {
            aspect
        } else {
            1.0
        };
        let fov = self.fov_y.clamp(0.05, 3.0);
        glam::camera::rh::proj::directx::perspective_infinite_reverse(fov, aspect, NEAR)
    }

    pub fn clip_from_world(&self, aspect: f32) -> Mat4 {
        self.clip_from_view(aspect) * self.view_from_world()
    }

    /// Pixel (x right, y down, from the top-left corner) where a world point appears in a
    /// `width` × `height` image; `None` behind the eye.
    pub fn project(&self, world: Vec3, width: u32, height: u32) -> Option<Vec2> {
        let clip = self.clip_from_world(width as f32 / height.max(1) as f32) * world.extend(1.0);
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = Vec4::new(clip.x / clip.w, clip.y / clip.w, 0.0, 0.0);
        Some(Vec2::new(
            (ndc.x * 0.5 + 0.5) * width as f32,
            (0.5 - ndc.y * 0.5) * height as f32,
        ))
    }

    /// Turns about the target (radians).
    pub fn orbit(&mut self, d_yaw: f32, d_pitch: f32) {
        self.yaw = wrap_angle(self.yaw + d_yaw);
        self.pitch = (self.pitch + d_pitch).clamp(-1.5, 1.5);
        self.keep_above_water();
    }

    /// Moves towards the target (`factor` < 1) or away (> 1).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(0.15, 2000.0);
        }
        self.keep_above_water();
    }

    /// Lifts the target so the eye stays [`MIN_EYE_HEIGHT`] above the water at rest.
    pub fn keep_above_water(&mut self) {
        let z = self.eye().z;
        if z < MIN_EYE_HEIGHT {
            self.target.z += MIN_EYE_HEIGHT - z;
        }
    }

    /// Slides the target across the view by a drag of (dx, dy) pixels in a viewport `height`
    /// pixels tall, so the point under the cursor stays under it.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let per_pixel = 2.0 * self.distance * (0.5 * self.fov_y).tan() / height.max(1.0);
        let f = self.forward();
        let right = f.cross(Vec3::Z).normalize_or(Vec3::X);
        let up = right.cross(f);
        self.target += (-dx * right + dy * up) * per_pixel;
        self.keep_above_water();
    }

    /// Keeps the view direction and distance, moving the target to `point`.
    pub fn follow(&mut self, point: Vec3) {
        self.target = point;
        self.keep_above_water();
    }

    /// Looks at the box [lo, hi] from the throw's left side, level with the flight, like the
    /// paper's Fig. 13 (a side view of the trajectory), heights `exaggeration` × taller: the whole
    /// box fits the view. A narrow field of view keeps the perspective close to a plot's.
    pub fn side_view(lo: Vec3, hi: Vec3, heading: f32, aspect: f32, exaggeration: f32) -> Self {
        let k = if exaggeration.is_finite() && exaggeration > 0.0 {
            exaggeration
        } else {
            1.0
        };
        let centre = 0.5 * (lo + hi);
        let along = Vec3::new(heading.cos(), heading.sin(), 0.0);
        let extent = ((hi - lo) * Vec3::new(1.0, 1.0, 0.0))
            .dot(along.abs())
            .max(0.5);
        let z1 = hi.z.max(0.0) * k;
        let fov = SIDE_FOV_Y;
        let half = (0.5 * fov).tan();
        let fit_w = 0.5 * extent / (half * aspect.max(0.2));
        // Looking across the throw (+90° from its heading) from an eye just above the water, so
        // the horizon lies on the waterline as a plot's axis would, tilted up at the middle of the
        // flight: the waterline sits between 55 % and 85 % of the height.
        let distance = (1.12 * fit_w + 0.5).max(z1 / (1.4 * half)).max(0.5);
        let tilt = (0.5 * z1 / distance).clamp(0.1 * half, 0.7 * half).atan();
        let eye_z = 2.0 * MIN_EYE_HEIGHT;
        let mut cam = Self {
            target: Vec3::new(centre.x, centre.y, eye_z + tilt.sin() * distance),
            yaw: wrap_angle(heading + std::f32::consts::FRAC_PI_2),
            pitch: tilt,
            distance,
            fov_y: fov,
            exaggeration: k,
        };
        cam.keep_above_water();
        cam
    }

    /// Looks down on the box [lo, hi] from above, the throw running up the picture.
    pub fn top_view(lo: Vec3, hi: Vec3, heading: f32, aspect: f32) -> Self {
        let centre = 0.5 * (lo + hi);
        let along = Vec3::new(heading.cos(), heading.sin(), 0.0);
        let size = (hi - lo) * Vec3::new(1.0, 1.0, 0.0);
        let length = size.dot(along.abs()).max(1.0);
        let width = size
            .dot(Vec3::new(along.y.abs(), along.x.abs(), 0.0))
            .max(1.0);
        let half = (0.5 * FOV_Y).tan();
        let distance = 1.15 * (0.5 * length / half).max(0.5 * width / (half * aspect.max(0.2)));
        let mut cam = Self {
            target: centre.with_z(0.0),
            yaw: heading,
            pitch: -1.45,
            distance,
            fov_y: FOV_Y,
            exaggeration: 1.0,
        };
        cam.keep_above_water();
        cam
    }

    /// A chase camera close behind the stone: looking along its horizontal velocity (or the
    /// throw's heading when it barely moves), a little above it.
    pub fn chase(stone: Vec3, velocity: Vec3, heading: f32, radius: f32) -> Self {
        let yaw = if velocity.truncate().length() > 0.3 {
            velocity.y.atan2(velocity.x)
        } else {
            heading
        };
        let mut cam = Self {
            target: stone.with_z(stone.z.max(0.0)),
            yaw,
            pitch: -14.0_f32.to_radians(),
            distance: (12.0 * radius).clamp(0.45, 3.0),
            fov_y: FOV_Y,
            exaggeration: 1.0,
        };
        cam.keep_above_water();
        cam
    }

    /// Moves a fraction `k` (0–1) of the way to `to` (smooth camera moves between views).
    pub fn blend(&mut self, to: &Camera, k: f32) {
        let k = if k.is_finite() {
            k.clamp(0.0, 1.0)
        } else {
            1.0
        };
        self.target = self.target.lerp(to.target, k);
        self.yaw = wrap_angle(self.yaw + wrap_angle(to.yaw - self.yaw) * k);
        self.pitch += (to.pitch - self.pitch) * k;
        self.distance += (to.distance - self.distance) * k;
        self.fov_y += (to.fov_y - self.fov_y) * k;
        self.exaggeration = to.exaggeration;
    }

    /// Keeps the view direction, moving target and distance so the box [lo, hi] fits the view.
    pub fn frame(&mut self, lo: Vec3, hi: Vec3, aspect: f32) {
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(0.25);
        let half = 0.5 * self.fov_y.min(self.fov_y * aspect.clamp(0.2, 5.0));
        self.target = centre;
        self.distance = (1.1 * radius / half.sin()).clamp(0.3, 2000.0);
        self.keep_above_water();
    }
}

/// Heading of a preset's throw (radians about +z from +x): its horizontal velocity, or the stone's
/// heading when thrown straight down.
pub fn throw_heading(preset: &Preset) -> f32 {
    let v = preset.launch.velocity;
    if v[0].hypot(v[1]) > 1e-6 {
        v[1].atan2(v[0]) as f32
    } else {
        preset.launch.attitude.heading_deg.to_radians() as f32
    }
}

fn direction(yaw: f32, pitch: f32) -> Vec3 {
    Vec3::new(
        pitch.cos() * yaw.cos(),
        pitch.cos() * yaw.sin(),
        pitch.sin(),
    )
}

fn wrap_angle(a: f32) -> f32 {
    let tau = std::f32::consts::TAU;
    let w = a.rem_euclid(tau);
    if w > std::f32::consts::PI {
        w - tau
    } else {
        w
    }
}

#[cfg(test)]
mod tests {

    /// Issue 39, finding 5: the side and top views keep open water ahead of the stone, so it never
    /// runs to the view's edge (under the labels and warnings drawn there).
    #[test]
    fn side_and_top_views_keep_water_ahead_of_the_stone() {
        let f = Framing {
            launch: Vec3::new(0.0, 0.0, 0.3),
            heading: 0.0,
            stone: Vec3::new(20.0, 0.0, 0.02),
            velocity: Vec3::new(8.0, 0.0, 0.5),
            radius: 0.05,
            bounds: (Vec3::new(0.0, -0.3, 0.0), Vec3::new(20.0, 0.3, 0.3)),
        };
        let (w, h) = (800, 600);
        for mode in [ViewMode::Side, ViewMode::Top] {
            let cam = camera_for(mode, &f, w as f32 / h as f32, 10.0).unwrap();
            let at = |p: Vec3| cam.project(p, w, h).unwrap();
            let stone = at(f.stone);
            let ahead = at(f.stone + Vec3::X * (LEAD - 0.01));
            for p in [stone, ahead] {
                assert!(
                    p.x >= 0.0 && p.x <= w as f32 && p.y >= 0.0 && p.y <= h as f32,
                    "{mode:?} {p}"
                );
            }
            // The stone is well inside, not at the edge it runs towards.
            let travel = ahead - stone;
            let margin = if travel.x.abs() > travel.y.abs() {
                w as f32 - stone.x
            } else {
                stone.y
            };
            assert!(
                margin > 0.05 * w.min(h) as f32,
                "{mode:?}: the stone {stone} at the edge"
            );
        }
    }

    use super::*;

    #[test]
    fn default_view_puts_horizon_in_upper_third() {
        let cam = Camera::default_for(&Preset::version_1());
        // A far point on the horizon ahead.
        let far = cam.eye() + Vec3::new(5000.0, 0.0, -cam.eye().z);
        let p = cam.project(far, 320, 180).unwrap();
        assert!(p.y < 60.0 && p.y > 0.0, "horizon at y = {}", p.y);
        // The launch point is in the middle of the view.
        let launch = cam.project(Vec3::new(0.0, 0.0, 0.3), 320, 180).unwrap();
        assert!(
            (launch - Vec2::new(160.0, 90.0)).length() < 1.0,
            "{launch:?}"
        );
    }

    #[test]
    fn controls_keep_the_eye_above_water() {
        let mut cam = Camera::default_for(&Preset::version_1());
        cam.orbit(0.0, 3.0);
        assert!(cam.eye().z >= MIN_EYE_HEIGHT - 1e-5);
        cam.pan(0.0, -5000.0, 100.0);
        assert!(cam.eye().z >= MIN_EYE_HEIGHT - 1e-5);
    }

    #[test]
    fn eye_is_behind_and_above_launch() {
        let cam = Camera::default_for(&Preset::version_1());
        let eye = cam.eye();
        assert!(eye.x < 0.0 && eye.z > 0.3, "{eye:?}");
        assert!(cam.forward().x > 0.9);
    }
}
