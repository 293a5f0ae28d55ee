//! Rendering with wgpu: the stone, the water surface (a height field from the simulated grid), the
//! sky, the trail, contact markers and splash cues; the camera; offscreen capture to PNG.
//!
//! The same [`Scene`] (plain data, built from a [`Simulation`] by [`build::scene_of`]) is drawn in
//! the app's window and offscreen, so `stoneskip render` and the picture tests show what the app
//! shows, camera by camera ([`ViewMode`]). The renderer ([`SceneRenderer`], one struct per pass in
//! [`passes`]) sees only the scene. This module never steps the physics on its own clock:
//! [`render_image`] ticks the simulation exactly as the app does, then draws.

pub mod build;
pub mod camera;
pub mod gpu;
pub mod legend;
pub mod mesh;
pub mod offscreen;
pub mod passes;
pub mod renderer;
pub mod scene;

use std::path::Path;

pub use build::{Trail, WaterHeights};
pub use camera::{Camera, ViewMode};
pub use offscreen::Offscreen;
pub use renderer::{RendererConfig, SceneRenderer, Viewport};
pub use scene::{Line, Scene, SceneStyle, WaterView};

use stoneskip_physics::sim::params::Preset;
use stoneskip_physics::sim::{SimError, Simulation};

/// Why a picture could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(
        "no graphics adapter found: tried {tried}. To fix: install a driver — on Debian/Ubuntu \
         without a GPU, Mesa's software renderers: `apt-get install mesa-vulkan-drivers libvulkan1 \
         libegl1 libgl1-mesa-dri` — or choose a backend with WGPU_BACKEND=gl (or vulkan); an empty \
         WGPU_BACKEND disables every backend"
    )]
    NoAdapter { tried: String },
    #[error("the graphics adapter {adapter} refused a device: {message}")]
    Device { adapter: String, message: String },
    #[error("cannot read the picture back from the GPU: {0}")]
    Readback(String),
    #[error("picture size {width}×{height} is out of range (1 to 8192 pixels a side)")]
    Size { width: u32, height: u32 },
    #[error("time {0} s is out of range (expected a finite time ≥ 0)")]
    Time(f64),
    #[error("vertical exaggeration {0} is not offered (expected 1, 5, 10 or 20)")]
    Exaggeration(f32),
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error("cannot write the PNG: {0}")]
    Image(#[from] image::ImageError),
}

/// Number of ticks of `dt` that reach simulated time `time` (the same count the app runs).
pub fn ticks_until(time: f64, dt: f64) -> u64 {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(time) || !positive(dt) {
        return 0;
    }
    (time / dt - 1e-6).ceil().max(0.0) as u64
}

/// A simulation advanced to `time` with its trail: the state every picture of a preset starts from.
pub struct SimulatedScene {
    pub sim: Simulation,
    pub trail: Trail,
    pub heights: WaterHeights,
}

impl SimulatedScene {
    /// Builds the preset's simulation and ticks it up to `time` (s).
    pub fn at_time(preset: &Preset, time: f64) -> Result<Self, RenderError> {
        if !time.is_finite() || time < 0.0 {
            return Err(RenderError::Time(time));
        }
        let mut sim = Simulation::new(preset)?;
        let mut trail = Trail::new();
        trail.start(sim.state().position);
        for _ in 0..ticks_until(time, preset.physics.dt) {
            sim.tick_with(&mut |s| trail.push(s));
        }
        let mut heights = WaterHeights::new();
        heights.refresh(&sim, 0);
        Ok(Self {
            sim,
            trail,
            heights,
        })
    }

    /// The scene with the app's default camera.
    pub fn scene(&self, style: SceneStyle) -> Scene<'_> {
        self.scene_for_view(style, ViewMode::Behind, 1.0, 16.0 / 9.0)
    }

    /// The scene as the app's `view` camera shows it in a view of `aspect`, with the same guides.
    pub fn scene_for_view(
        &self,
        style: SceneStyle,
        view: ViewMode,
        exaggeration: f32,
        aspect: f32,
    ) -> Scene<'_> {
        let framing = build::framing_of(&self.sim, &self.trail, None);
        let camera = camera::camera_for(view, &framing, aspect, exaggeration)
            .unwrap_or_else(|| Camera::default_for(self.sim.preset()));
        let mut scene = build::scene_of(&self.sim, None, &self.trail, &self.heights, camera, style);
        if view == ViewMode::Side {
            scene.side_view = true;
            scene
                .lines
                .extend(build::side_guides(&framing, self.sim.contacts(), &camera));
            let dug_in = build::dug_in_touch(&self.sim);
            scene.lines.extend(build::attitude_glyphs(
                &framing,
                self.sim.contacts(),
                &camera,
                dug_in,
            ));
        }
        scene
    }
}

/// Which camera a picture is taken with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureView {
    pub view: ViewMode,
    /// The side view's vertical exaggeration (1, 5, 10 or 20).
    pub exaggeration: f32,
}

impl Default for PictureView {
    fn default() -> Self {
        Self {
            view: ViewMode::Behind,
            exaggeration: 1.0,
        }
    }
}

/// Renders the preset's scene at simulated time `time` with the app's camera `view`.
pub fn render_image(
    preset: &Preset,
    width: u32,
    height: u32,
    time: f64,
    view: PictureView,
) -> Result<image::RgbaImage, RenderError> {
    render_with(preset, (width, height), time, view, false)
}

/// [`render_image`] with the legend and scale in a strip under it ([`legend`]): the picture
/// `stoneskip render` writes, taller than `height` by the strip.
pub fn render_picture(
    preset: &Preset,
    width: u32,
    height: u32,
    time: f64,
    view: PictureView,
) -> Result<image::RgbaImage, RenderError> {
    render_with(preset, (width, height), time, view, true)
}

fn render_with(
    preset: &Preset,
    (width, height): (u32, u32),
    time: f64,
    view: PictureView,
    with_legend: bool,
) -> Result<image::RgbaImage, RenderError> {
    if width == 0 || height == 0 || width > offscreen::MAX_SIDE || height > offscreen::MAX_SIDE {
        return Err(RenderError::Size { width, height });
    }
    if !camera::EXAGGERATIONS.contains(&view.exaggeration) {
        return Err(RenderError::Exaggeration(view.exaggeration));
    }
    let state = SimulatedScene::at_time(preset, time)?;
    let mut off = Offscreen::new()?;
    let aspect = width as f32 / height as f32;
    let scene = state.scene_for_view(SceneStyle::default(), view.view, view.exaggeration, aspect);
    let mut img = off.render(&scene, width, height)?;
    if with_legend {
        let framing = build::framing_of(&state.sim, &state.trail, None);
        let legend = legend::legend_of(
            &state.sim,
            view.view,
            &scene.camera,
            &framing,
            (width, height),
        );
        img = legend::with_legend(&img, &legend);
    }
    Ok(img)
}

/// `stoneskip render`: the scene at `time` offscreen with its legend ([`render_picture`]),
/// written as an 8-bit RGBA PNG.
pub fn render_to_png(
    preset: &Preset,
    out: &Path,
    width: u32,
    height: u32,
    time: f64,
    view: PictureView,
) -> Result<(), RenderError> {
    let img = render_picture(preset, width, height, time, view)?;
    img.save_with_format(out, image::ImageFormat::Png)
        .map_err(RenderError::from)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_reach_the_time_like_the_app() {
        assert_eq!(ticks_until(0.0, 0.0005), 0);
        assert_eq!(ticks_until(0.6, 0.0005), 1200);
        assert_eq!(ticks_until(0.60001, 0.0005), 1201);
        assert_eq!(ticks_until(f64::NAN, 0.0005), 0);
        assert_eq!(ticks_until(1.0, 0.0), 0);
    }
}
