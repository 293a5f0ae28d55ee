//! One frame: the panels (egui) decide the 3D view's rectangle and what the user asked for; the
//! model runs the ticks due (the fixed-step clock) and moves the camera; the scene and the panels
//! are drawn into a canvas texture and copied to the window. Frame-time totals for the
//! `--frames` report, and screenshots (with or without the panels).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{anyhow, Context as _, Result};
use winit::event_loop::ActiveEventLoop;

use super::files;
use super::model::{Model, Shot};
use super::platform::{App, Gfx, Recoveries};
use super::redraw::{self, PanelTiles};
use super::soak::{MAX_THROW_FRAMES, SOAK_SPEED};
use crate::ui::{Message, Phase};
use stoneskip_physics::sim::Outcome;
use stoneskip_render::legend;
use stoneskip_render::offscreen::read_rgba8;
use stoneskip_render::Viewport;

impl App {
    pub(super) fn frame(&mut self, event_loop: &ActiveEventLoop) {
        if !self.gpu_checks(event_loop) {
            return;
        }
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let model = &mut self.model;
        let frame_start = Instant::now();
        let real_dt = frame_gap(self.last_frame, frame_start, self.continuous);
        let was_resting = model.resting;
        self.last_frame = Some(frame_start);

        // Panels first: they decide the 3D view's rectangle and what the user asked for.
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let mut actions = Vec::new();
        let adapter = gfx.adapter.clone();
        let mut full = gfx
            .egui_ctx
            .run_ui(raw, |ui| model.build_ui(ui, &adapter, &mut actions));
        let ui_s = frame_start.elapsed().as_secs_f64();
        gfx.egui_state
            .handle_platform_output(&gfx.window, std::mem::take(&mut full.platform_output));
        self.repaint_at = full
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .and_then(|v| frame_start.checked_add(v.repaint_delay));
        model.update(actions, real_dt);
        let title = model.title();
        if title != self.title {
            gfx.window.set_title(&title);
            self.title = title;
        }

        // Draw: the scene in the 3D view's rectangle, then the panels over it.
        let render_start = Instant::now();
        let ppp = full.pixels_per_point;
        let prims = gfx
            .egui_ctx
            .tessellate(std::mem::take(&mut full.shapes), ppp);
        let result = draw(
            gfx,
            model,
            &prims,
            &mut full.textures_delta,
            ppp,
            &mut self.recoveries,
        );
        if let Err(e) = result {
            self.fatal = Some(e);
            event_loop.exit();
            return;
        }
        let render_s = render_start.elapsed().as_secs_f64();
        let timing = FrameTimes {
            real_dt: if was_resting { 0.0 } else { real_dt },
            frame: frame_start.elapsed().as_secs_f64(),
            render: render_s,
            ui: ui_s,
        };
        self.account(&timing, event_loop);
        self.soak_step(&timing, event_loop);
    }

    /// The soak (`STONESKIP_SOAK`): records the frame; once the throw rests (or runs too long),
    /// closes its row, loads the next shipped preset and throws it; writes the CSV at the end.
    fn soak_step(&mut self, f: &FrameTimes, event_loop: &ActiveEventLoop) {
        let Some(soak) = self.soak.as_mut() else {
            return;
        };
        let model = &mut self.model;
        let over = model.resting || (self.options.soak_until_outcome && model.sim.is_finished());
        let running = model.phase == Phase::Running && !over;
        if soak.started > 0 {
            soak.frame(1000.0 * f.frame, 1000.0 * f.real_dt);
            let cut = soak.frames() >= MAX_THROW_FRAMES;
            if running && !cut {
                return;
            }
            let preset = model.library.current.clone().unwrap_or_default();
            let outcome = model
                .sim
                .outcome()
                .map_or("no outcome", Outcome::words)
                .to_owned();
            soak.finish_throw(&preset, model.sim.time(), outcome, running);
            // Written after every throw: a soak stopped early keeps its rows.
            if let Err(e) = soak.write() {
                self.fatal = Some(e.context("the soak's CSV"));
                self.soak = None;
                event_loop.exit();
                return;
            }
            if soak.rows.len().is_multiple_of(50) {
                eprintln!("{}", soak.summary());
            }
        }
        if soak.done() {
            eprintln!("{}; rows in {}", soak.summary(), soak.csv().display());
            self.soak = None;
            event_loop.exit();
            return;
        }
        let next = soak.next_preset();
        model.load_preset(&next);
        model.clock.set_speed(SOAK_SPEED);
        model.throw();
    }

    /// Smoothed frame times for the panel (idle time never counts) and the `--frames` report.
    fn account(&mut self, f: &FrameTimes, event_loop: &ActiveEventLoop) {
        let model = &mut self.model;
        let smooth = |old: f64, new: f64| {
            if old == 0.0 {
                new
            } else {
                0.9 * old + 0.1 * new
            }
        };
        let t = &mut model.timing;
        t.frame_ms = smooth(t.frame_ms, 1000.0 * f.frame);
        if f.real_dt > 0.0 {
            t.interval_ms = smooth(t.interval_ms, 1000.0 * f.real_dt);
        }
        t.physics_ms = smooth(t.physics_ms, 1000.0 * model.frame_physics);
        t.water_ms = smooth(t.water_ms, 1000.0 * model.frame_water);
        t.render_ms = smooth(t.render_ms, 1000.0 * f.render);
        t.ui_ms = smooth(t.ui_ms, 1000.0 * f.ui);
        // Totals past the first frames (shader compilation), for the --frames report.
        if model.frames >= 10 && f.real_dt > 0.0 {
            let st = &mut model.stats;
            st.frames += 1;
            st.wall += f.real_dt;
            st.physics += model.frame_physics;
            st.water += model.frame_water;
            st.lake += model.frame_lake;
            st.render += f.render;
            st.ui += f.ui;
            if model.last_full_redraw {
                st.full_redraws += 1;
                st.full_render += f.render;
            }
        }
        self.frames_drawn += 1;
        if self.frames_limit.is_some_and(|n| self.frames_drawn >= n) {
            if self.options.fps_report {
                eprintln!("{}", self.report());
            }
            event_loop.exit();
        }
    }

    /// The `--frames` report line.
    pub(super) fn report(&self) -> String {
        let model = &self.model;
        let st = &model.stats;
        let n = st.frames.max(1) as f64;
        let (w, h) = self
            .gfx
            .as_ref()
            .map_or((0, 0), |g| (g.config.width, g.config.height));
        let adapter = self.gfx.as_ref().map_or("", |g| g.adapter.as_str());
        format!(
            "stoneskip: {} frames at {w}x{h}; mean over the last {}: {:.1} fps ({:.2} ms a frame): physics {:.2} ms, water {:.2} ms (its own thread {:.2} ms), render {:.2} ms ({} full redraws at {:.2} ms, the rest {:.2} ms), panels {:.2} ms; {} ticks, {:.3} s simulated, {:.3} s dropped; render scale {:.2}; recovered: {} lost devices, {} lost surfaces, {} frames without a surface; {}",
            self.frames_drawn,
            st.frames,
            n / st.wall.max(1e-9),
            1000.0 * st.wall / n,
            1000.0 * st.physics / n,
            1000.0 * st.water / n,
            1000.0 * st.lake / n,
            1000.0 * st.render / n,
            st.full_redraws,
            1000.0 * st.full_render / st.full_redraws.max(1) as f64,
            1000.0 * (st.render - st.full_render) / (st.frames - st.full_redraws).max(1) as f64,
            1000.0 * st.ui / n,
            model.ticks,
            model.sim.time(),
            model.clock.skipped_total(),
            model.view.render_scale,
            self.recoveries.devices,
            self.recoveries.surfaces,
            self.recoveries.skipped,
            adapter
        )
    }
}

/// Real time since the last frame (s) when the frames were drawn back to back; 0 after a wait
/// (rest, idle), which is neither frame time nor time the simulation should catch up on.
pub fn frame_gap(last: Option<Instant>, now: Instant, back_to_back: bool) -> f64 {
    match last {
        Some(t) if back_to_back => now.saturating_duration_since(t).as_secs_f64(),
        _ => 0.0,
    }
}

/// Wall times of one frame (s).
struct FrameTimes {
    /// Real time since the previous frame when it was drawn back to back (0 after a wait).
    real_dt: f64,
    frame: f64,
    render: f64,
    ui: f64,
}

/// Records and presents one frame; writes a screenshot when asked.
fn draw(
    gfx: &mut Gfx,
    model: &mut Model,
    prims: &[egui::ClippedPrimitive],
    textures: &mut egui::TexturesDelta,
    ppp: f32,
    recoveries: &mut Recoveries,
) -> Result<()> {
    let device = &gfx.gpu.device;
    let queue = &gfx.gpu.queue;
    let textures_changed = !textures.set.is_empty() || !textures.free.is_empty();
    for (id, deltas) in textures.set.drain() {
        for d in deltas {
            gfx.egui_renderer.update_texture(device, queue, id, &d);
        }
    }
    let mut current = gfx.surface.get_current_texture();
    if std::mem::take(&mut gfx.surface_lost) {
        // Fault injection: the frame acquired is dropped unpresented, as a lost surface's would be.
        current = wgpu::CurrentSurfaceTexture::Lost;
    }
    let frame = match current {
        wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => {
            Some(f)
        }
        wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
            // Drawn again next frame, on the reconfigured surface.
            gfx.surface.configure(device, &gfx.config);
            recoveries.surfaces += 1;
            None
        }
        wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
            recoveries.skipped += 1;
            None
        }
        wgpu::CurrentSurfaceTexture::Validation => {
            if gfx.watch.lost.load(std::sync::atomic::Ordering::Acquire) {
                // The device went: the next frame rebuilds it.
                None
            } else {
                return Err(anyhow!(
                    "the window's surface failed validation on {}: {}",
                    gfx.adapter,
                    gfx.watch.message()
                ));
            }
        }
    };
    if let Some(frame) = frame {
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let size = (gfx.config.width, gfx.config.height);
        // Everything is drawn into an ordinary texture, then copied to the window by a
        // write-only pass: blending straight into a software swapchain image reads it back, which
        // lavapipe makes very slow (the panels cost 5× more).
        let fresh_canvas = gfx.canvas.as_ref().is_none_or(|(s, _, _)| *s != size);
        let (canvas_tex, canvas) = canvas_view(gfx, size);
        // Without MSAA the 3D view is redrawn with only the panels' tiles that changed (none while
        // the panels are unchanged); see `redraw`.
        let tiles = PanelTiles::new(prims, redraw::screen_rect(size, ppp), model.view_rect, ppp);
        let changed = match &gfx.ui_tiles {
            Some(last)
                if gfx.scene.config().sample_count == 1 && !fresh_canvas && !textures_changed =>
            {
                tiles.changed_since(last)
            }
            _ => None,
        };
        let redraw = changed.map_or(Redraw::Full, Redraw::Partial);
        gfx.ui_tiles = Some(tiles);
        model.last_full_redraw = redraw == Redraw::Full;
        // A reduced-resolution frame of a still scene: follow it with a sharp one.
        model.sharp_pending = (model.animating()
            && model.view.render_scale < 1.0
            && (model.phase != Phase::Running || model.resting))
            || std::mem::take(&mut model.just_rested);
        let mut bufs = render_frame(
            gfx,
            model,
            prims,
            ppp,
            FrameTarget {
                view: &canvas,
                size,
                full_res: false,
                redraw,
                panels: true,
            },
        );
        let mut encoder = gfx
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("present"),
            });
        if gfx.config.usage.contains(wgpu::TextureUsages::COPY_DST) {
            encoder.copy_texture_to_texture(
                canvas_tex.as_image_copy(),
                frame.texture.as_image_copy(),
                wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
            );
        } else {
            gfx.scene
                .blit_to(&gfx.gpu.device, &mut encoder, &canvas, &view);
        }
        bufs.push(encoder.finish());
        gfx.gpu.queue.submit(bufs);
        gfx.gpu.queue.present(frame);
    }
    if let Some(shot) = model.screenshot.take() {
        let message = match screenshot(gfx, model, prims, ppp, shot) {
            Ok(p) => Message::info(format!("screenshot saved to {}", p.display())),
            Err(e) => Message::error(format!("screenshot failed: {e:#}")),
        };
        model.post(message);
    }
    for id in textures.free.drain() {
        gfx.egui_renderer.free_texture(&id);
    }
    Ok(())
}

/// The window-sized texture every frame is drawn into before it is copied to the window; it keeps
/// the panels' pixels between frames.
fn canvas_view(gfx: &mut Gfx, size: (u32, u32)) -> (wgpu::Texture, wgpu::TextureView) {
    if let Some((s, tex, view)) = &gfx.canvas {
        if *s == size {
            return (tex.clone(), view.clone());
        }
    }
    let tex = gfx.gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("canvas"),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: gfx.config.format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
    gfx.canvas = Some((size, tex.clone(), view.clone()));
    (tex, view)
}

/// Where and how a frame is drawn.
struct FrameTarget<'a> {
    view: &'a wgpu::TextureView,
    size: (u32, u32),
    /// The 3D view at full resolution even while animating (screenshots).
    full_res: bool,
    redraw: Redraw,
    /// Draw the panels; without, the 3D view fills the whole target (screenshots).
    panels: bool,
}

/// Records the scene and the panels into the target; returns the command buffers to submit.
fn render_frame(
    gfx: &mut Gfx,
    model: &Model,
    prims: &[egui::ClippedPrimitive],
    ppp: f32,
    out: FrameTarget,
) -> Vec<wgpu::CommandBuffer> {
    let FrameTarget {
        view: target,
        size,
        full_res,
        redraw,
        panels,
    } = out;
    let device = &gfx.gpu.device;
    let queue = &gfx.gpu.queue;
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("frame"),
    });
    let r = model.view_rect;
    let viewport = if panels {
        Viewport {
            x: r.min.x * ppp,
            y: r.min.y * ppp,
            width: (r.width() * ppp).max(1.0),
            height: (r.height() * ppp).max(1.0),
        }
    } else {
        Viewport::full(size.0, size.1)
    };
    let scene = model.scene();
    // Reduced resolution while things move (stills are always sharp).
    let scale = if model.animating() && model.phase == Phase::Running && !full_res {
        model.view.render_scale
    } else {
        1.0
    };

    gfx.scene.set_render_scale(scale);
    gfx.scene.render(
        device,
        queue,
        &mut encoder,
        target,
        size,
        viewport,
        &scene,
        (redraw == Redraw::Full).then_some(wgpu::Color {
            r: 0.1,
            g: 0.1,
            b: 0.11,
            a: 1.0,
        }),
    );
    if !panels {
        return vec![encoder.finish()];
    }
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [size.0, size.1],
        pixels_per_point: ppp,
    };
    // A partial redraw keeps the panels' pixels but those of the changed tiles: what egui draws
    // over the 3D view and over those tiles is drawn again, clipped to them, over the window's
    // background colour there.
    let clipped: Vec<egui::ClippedPrimitive>;
    let prims = match &redraw {
        Redraw::Full => prims,
        Redraw::Partial(tiles) => {
            let background = if gfx.config.format.is_srgb() {
                egui::Color32::from_rgb(89, 89, 93)
            } else {
                egui::Color32::from_rgb(26, 26, 28)
            };
            // Rectangle by rectangle (they may overlap one another, never the view): the
            // background, then everything over it.
            let mut again = redraw::clipped_to(prims, &[r]);
            for t in tiles {
                let mut m = egui::Mesh::default();
                m.add_colored_rect(*t, background);
                again.push(egui::ClippedPrimitive {
                    clip_rect: *t,
                    primitive: egui::epaint::Primitive::Mesh(m),
                });
                again.extend(redraw::clipped_to(prims, std::slice::from_ref(t)));
            }
            clipped = again;
            &clipped
        }
    };
    let mut bufs = gfx
        .egui_renderer
        .update_buffers(device, queue, &mut encoder, prims, &screen);
    {
        let mut pass = encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            })
            .forget_lifetime();
        gfx.egui_renderer.render(&mut pass, prims, &screen);
    }
    bufs.push(encoder.finish());
    bufs
}

/// How much of the window a frame draws again.
#[derive(Debug, Clone, PartialEq)]
enum Redraw {
    Full,
    /// The 3D view and what lies over it, and these rectangles of the panels (points); the rest
    /// of the panels' pixels are the last frame's.
    Partial(Vec<egui::Rect>),
}

/// Draws the window (scene and panels, [`Shot::Window`]) or the 3D view alone at the window's size
/// into a texture and saves it as a PNG in the output folder, named after the preset.
fn screenshot(
    gfx: &mut Gfx,
    model: &Model,
    prims: &[egui::ClippedPrimitive],
    ppp: f32,
    shot: Shot,
) -> Result<PathBuf> {
    let (w, h) = match shot {
        Shot::Window => (gfx.config.width, gfx.config.height),
        Shot::ViewOnly => {
            let r = model.view_rect;
            (
                (r.width() * ppp).round().max(1.0) as u32,
                (r.height() * ppp).round().max(1.0) as u32,
            )
        }
    };
    let format = gfx.config.format;
    let tex = gfx.gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("screenshot"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
    let bufs = render_frame(
        gfx,
        model,
        prims,
        ppp,
        FrameTarget {
            view: &view,
            size: (w, h),
            full_res: true,
            redraw: Redraw::Full,
            panels: shot == Shot::Window,
        },
    );
    gfx.gpu.queue.submit(bufs);
    let mut pixels = read_rgba8(&gfx.gpu.device, &gfx.gpu.queue, &tex, w, h)?;
    if matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for px in pixels.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    for px in pixels.chunks_exact_mut(4) {
        px[3] = 255;
    }
    let mut img = image::RgbaImage::from_raw(w, h, pixels)
        .ok_or_else(|| anyhow!("pixel count does not match"))?;
    if shot == Shot::ViewOnly {
        // The view alone leaves the panels behind: its legend and scale say what it shows.
        let legend = legend::legend_of(
            &model.sim,
            model.view_mode,
            &model.camera,
            &model.framing(),
            (w, h),
        );
        img = legend::with_legend(&img, &legend);
    }
    std::fs::create_dir_all(&model.out_dir)
        .with_context(|| format!("creating {}", model.out_dir.display()))?;
    let path = files::output_path(&model.out_dir, &model.sim.preset().name, "png");
    img.save_with_format(&path, image::ImageFormat::Png)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn idle_time_is_not_frame_time() {
        let t0 = Instant::now();
        let t1 = t0 + Duration::from_millis(40);
        assert!((frame_gap(Some(t0), t1, true) - 0.040).abs() < 1e-9);
        // After a wait (the app rested, or drew only on input) the gap counts for nothing: the
        // frame-time panel does not read "1 fps" and the clock does not fast-forward.
        assert_eq!(
            frame_gap(Some(t0), t0 + Duration::from_secs(30), false),
            0.0
        );
        assert_eq!(frame_gap(None, t1, true), 0.0);
    }
}
