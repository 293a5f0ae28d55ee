//! Offscreen picture tests: render the app's scene on whatever adapter wgpu finds (CI: Mesa's
//! llvmpipe/lavapipe software rasterisers) and check the picture — sky above, water below, the stone
//! where the camera projects it, rings after a contact — and compare it with a reference PNG.
//!
//! Without any adapter these tests FAIL, unless `STONESKIP_SKIP_GPU_TESTS=1` says to skip them.
//! Regenerate the reference pictures with `STONESKIP_UPDATE_REFERENCE=1 cargo test --test render`.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;

use glam::Vec3;
use stoneskip_physics::sim::params::Preset;
use stoneskip_render::{Offscreen, PictureView, SceneStyle, SimulatedScene, ViewMode};

const W: u32 = 320;
const H: u32 = 180;

/// The throw the pictures are drawn for: the default throw until issue 11, kept fixed
/// (`tests/reference_images/throw.ron`) so the reference pictures do not move with the shipped one.
fn default_preset() -> Preset {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference_images/throw.ron");
    stoneskip_physics::preset::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The offscreen renderer, or `None` when the tests are told to skip without an adapter.
fn offscreen() -> Option<Offscreen> {
    match Offscreen::new() {
        Ok(o) => {
            eprintln!("adapter: {}", o.adapter());
            Some(o)
        }
        Err(e) => {
            if std::env::var("STONESKIP_SKIP_GPU_TESTS").is_ok_and(|v| v == "1") {
                eprintln!("SKIPPED (STONESKIP_SKIP_GPU_TESTS=1): {e}");
                None
            } else {
                panic!("{e}\n(set STONESKIP_SKIP_GPU_TESTS=1 to skip the picture tests on a machine without any adapter)");
            }
        }
    }
}

fn luma(p: &image::Rgba<u8>) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

/// Mean colour of rows [y0, y1).
fn mean_rows(img: &image::RgbaImage, y0: u32, y1: u32) -> [f64; 4] {
    let mut s = [0.0; 4];
    let mut n = 0.0;
    for y in y0..y1 {
        for x in 0..img.width() {
            let p = img.get_pixel(x, y);
            for c in 0..3 {
                s[c] += p[c] as f64;
            }
            s[3] += luma(p);
            n += 1.0;
        }
    }
    s.map(|v| v / n)
}

/// Largest per-channel difference in the window of `radius` pixels around (cx, cy).
fn max_diff_near(a: &image::RgbaImage, b: &image::RgbaImage, cx: f32, cy: f32, radius: i64) -> u8 {
    let mut m = 0u8;
    for dy in -radius..=radius {
        for dx in -radius..=radius {
            let x = cx as i64 + dx;
            let y = cy as i64 + dy;
            if x < 0 || y < 0 || x >= a.width() as i64 || y >= a.height() as i64 {
                continue;
            }
            let (p, q) = (
                a.get_pixel(x as u32, y as u32),
                b.get_pixel(x as u32, y as u32),
            );
            for c in 0..3 {
                m = m.max(p[c].abs_diff(q[c]));
            }
        }
    }
    m
}

#[test]
fn sky_above_water_below_and_stone_where_projected() {
    let Some(mut off) = offscreen() else { return };
    let preset = default_preset();
    // In flight, before the first contact.
    let state = SimulatedScene::at_time(&preset, 0.05).unwrap();
    assert!(state.sim.contacts().is_empty());
    let scene = state.scene(SceneStyle::default());
    let with_stone = off.render(&scene, W, H).unwrap();
    assert_eq!(with_stone.dimensions(), (W, H));

    // Sky: the top rows are bluish (blue above red) and brighter than the water at the bottom.
    let sky = mean_rows(&with_stone, 0, H / 8);
    let water = mean_rows(&with_stone, H * 3 / 4, H);
    assert!(sky[2] > sky[0] + 10.0, "sky not bluish: {sky:?}");
    assert!(
        sky[3] > water[3] + 40.0,
        "sky {sky:?} not brighter than water {water:?}"
    );
    // Water: blue-green, darker, green and blue above red.
    assert!(
        water[1] > water[0] && water[2] > water[0],
        "water colour {water:?}"
    );

    // The stone: where the camera projects its centre, the picture differs from one without it.
    let pos = state.sim.state().position.as_vec3();
    let px = scene
        .camera
        .project(pos, W, H)
        .expect("the stone is in front of the camera");
    assert!(
        px.x > 0.0 && px.y > 0.0 && px.x < W as f32 && px.y < H as f32,
        "stone at {px:?}"
    );
    let mut without = scene.clone();
    without.stone = None;
    let no_stone = off.render(&without, W, H).unwrap();
    let d = max_diff_near(&with_stone, &no_stone, px.x, px.y, 1);
    assert!(d > 20, "the stone changes pixels near {px:?} by only {d}");
    // Far from the stone (the sky) nothing changes.
    assert_eq!(max_diff_near(&with_stone, &no_stone, 10.0, 5.0, 4), 0);
}

#[test]
fn rings_change_the_water_after_a_contact() {
    let Some(mut off) = offscreen() else { return };
    let preset = default_preset();
    let probe = SimulatedScene::at_time(&preset, 0.5).unwrap();
    let first = *probe
        .sim
        .contacts()
        .first()
        .expect("the default throw touches the water within 0.5 s");
    let before = SimulatedScene::at_time(&preset, (first.t_start - 0.02).max(0.0)).unwrap();
    let after = SimulatedScene::at_time(&preset, first.t_start + 0.3).unwrap();
    // Only the water differs: no stone, trail, markers or splash cues, the same wind-ripple time.
    let style = SceneStyle {
        show_trail: false,
        show_markers: false,
        show_splashes: false,
        ripple_gain: 1.0,
    };
    let mut a = before.scene(style);
    let mut b = after.scene(style);
    a.stone = None;
    b.stone = None;
    b.time = a.time;
    let img_a = off.render(&a, W, H).unwrap();
    let img_b = off.render(&b, W, H).unwrap();
    let px = a
        .camera
        .project(Vec3::new(first.x as f32, first.y as f32, 0.0), W, H)
        .expect("contact point in view");
    // Rings spread ~0.5 m in 0.3 s: look in a window around the touch point.
    let mut changed = 0;
    let r = 25i64;
    for dy in -r / 2..=r / 2 {
        for dx in -r..=r {
            let (x, y) = (px.x as i64 + dx, px.y as i64 + dy);
            if x < 0 || y < 0 || x >= W as i64 || y >= H as i64 {
                continue;
            }
            let (p, q) = (
                img_a.get_pixel(x as u32, y as u32),
                img_b.get_pixel(x as u32, y as u32),
            );
            if (0..3).any(|c| p[c].abs_diff(q[c]) > 6) {
                changed += 1;
            }
        }
    }
    assert!(
        changed > 40,
        "only {changed} pixels changed around the contact at {px:?}"
    );
    // The sky is untouched.
    assert_eq!(max_diff_near(&img_a, &img_b, W as f32 / 2.0, 5.0, 4), 0);
}

/// Compares with `tests/reference_images/NAME` within a tolerance (mean difference and the share of
/// clearly different pixels, as wgpu's examples do); `STONESKIP_UPDATE_REFERENCE=1` rewrites it.
fn compare_with_reference(img: &image::RgbaImage, name: &str) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/reference_images")
        .join(name);
    if std::env::var("STONESKIP_UPDATE_REFERENCE").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        img.save(&path).unwrap();
        eprintln!("wrote {}", path.display());
        return;
    }
    let reference = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "cannot read {}: {e} (create it with STONESKIP_UPDATE_REFERENCE=1 cargo test --test render)",
                path.display()
            )
        })
        .to_rgba8();
    assert_eq!(reference.dimensions(), img.dimensions());
    let mut sum = 0u64;
    let mut bad = 0usize;
    for (p, q) in img.pixels().zip(reference.pixels()) {
        let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
        sum += d as u64;
        if d > 24 {
            bad += 1;
        }
    }
    let n = (img.width() * img.height()) as f64;
    let mean = sum as f64 / n;
    let share = bad as f64 / n;
    if mean > 1.5 || share > 0.01 {
        let out = std::env::temp_dir().join(format!("stoneskip-actual-{name}"));
        let _ = img.save(&out);
        panic!(
            "{name}: mean difference {mean:.3} (limit 1.5), {:.2} % of pixels differ by more than 24 (limit 1 %); \
             this run's picture: {}",
            100.0 * share,
            out.display()
        );
    }
}

#[test]
fn matches_reference_picture() {
    let Some(mut off) = offscreen() else { return };
    let preset = default_preset();
    let state = SimulatedScene::at_time(&preset, 0.6).unwrap();
    let img = off
        .render(&state.scene(SceneStyle::default()), W, H)
        .unwrap();
    compare_with_reference(&img, "default_t0.6_320x180.png");
}

#[test]
fn render_to_png_writes_rgba8() {
    if offscreen().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    // A width whose rows need padding to 256 bytes on readback.
    stoneskip_render::render_to_png(
        &default_preset(),
        &out,
        203,
        101,
        0.2,
        PictureView::default(),
    )
    .unwrap();
    let img = image::open(&out).unwrap();
    assert_eq!(img.color(), image::ColorType::Rgba8);
    assert_eq!((img.width(), img.height()), (203, 101));
}

/// Pixels that differ by more than `threshold` in some channel: (count, x range, y range).
fn changed(
    a: &image::RgbaImage,
    b: &image::RgbaImage,
    threshold: u8,
) -> (usize, (u32, u32), (u32, u32)) {
    let mut n = 0;
    let (mut x0, mut x1, mut y0, mut y1) = (u32::MAX, 0, u32::MAX, 0);
    for (x, y, p) in a.enumerate_pixels() {
        let q = b.get_pixel(x, y);
        if (0..3).any(|c| p[c].abs_diff(q[c]) > threshold) {
            n += 1;
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    (n, (x0, x1), (y0, y1))
}

/// The default throw after its outcome (3.84 s): the whole trajectory is in the trail.
fn finished_default() -> SimulatedScene {
    let state = SimulatedScene::at_time(&default_preset(), 4.0).unwrap();
    assert!(state.sim.is_finished());
    state
}

/// The picture of `view` with and without the trail (its pixels are where the two differ).
fn with_and_without_trail(
    off: &mut Offscreen,
    state: &SimulatedScene,
    view: ViewMode,
    exaggeration: f32,
) -> (image::RgbaImage, image::RgbaImage, stoneskip_render::Camera) {
    let aspect = W as f32 / H as f32;
    let on = state.scene_for_view(SceneStyle::default(), view, exaggeration, aspect);
    let off_style = SceneStyle {
        show_trail: false,
        ..SceneStyle::default()
    };
    let without = state.scene_for_view(off_style, view, exaggeration, aspect);
    (
        off.render(&on, W, H).unwrap(),
        off.render(&without, W, H).unwrap(),
        on.camera,
    )
}

#[test]
fn side_view_at_10x_shows_the_whole_trajectory_above_the_waterline() {
    let Some(mut off) = offscreen() else { return };
    let state = finished_default();
    let (img, no_trail, cam) = with_and_without_trail(&mut off, &state, ViewMode::Side, 10.0);
    if std::env::var("STONESKIP_KEEP_PICTURES").is_ok_and(|v| v == "1") {
        let _ = img.save(std::env::temp_dir().join("stoneskip-side-10x.png"));
    }
    let (n, (x0, x1), (y0, _)) = changed(&img, &no_trail, 30);
    assert!(n > 200, "only {n} trajectory pixels");
    // From the launch to where it sank (20.4 m): most of the picture's width.
    assert!(
        (x1 - x0) as f32 > 0.7 * W as f32,
        "the trajectory spans x {x0}..{x1} of {W}"
    );
    // The waterline lies in the picture, and the first arc rises well above it: 0.3 m × 10.
    let launch = state.sim.launch_position().as_vec3();
    let water_px = cam
        .project(launch.with_z(0.0), W, H)
        .expect("the waterline is in front of the camera");
    assert!(
        water_px.y > 0.0 && water_px.y < H as f32,
        "waterline at {water_px:?}"
    );
    // Released level, the launch is the first arc's top: the trail reaches its height as projected
    // (3 m at 10×), which stands well clear of the waterline.
    let launch_px = cam.project(launch, W, H).unwrap();
    assert!(
        water_px.y - launch_px.y > 0.1 * H as f32,
        "the launch at {launch_px:?} is not well above the waterline at {water_px:?}"
    );
    assert!(
        (y0 as f32) < launch_px.y + 3.0,
        "the trajectory's top {y0} is below the launch at {}",
        launch_px.y
    );
    // The launch and the end point both project inside the picture.
    let end = state.sim.state().position.as_vec3();
    for p in [launch, end] {
        let q = cam.project(p, W, H).unwrap();
        assert!(q.x >= 0.0 && q.x <= W as f32, "{p:?} at {q:?}");
    }
    compare_with_reference(&img, "side_10x_t4.0_320x180.png");
}

#[test]
fn exaggeration_makes_the_arcs_taller() {
    let Some(mut off) = offscreen() else { return };
    let state = finished_default();
    let height = |off: &mut Offscreen, k: f32| {
        let (img, no_trail, _) = with_and_without_trail(off, &state, ViewMode::Side, k);
        let (_, _, (y0, y1)) = changed(&img, &no_trail, 30);
        y1.saturating_sub(y0)
    };
    let (h1, h10) = (height(&mut off, 1.0), height(&mut off, 10.0));
    // At 1× the 0.3 m arcs over 20 m are a few pixels tall; at 10× many times that.
    assert!(h10 > 4 * h1.max(1), "1×: {h1} px, 10×: {h10} px");
}

#[test]
fn top_view_shows_the_throw_running_up_the_picture() {
    let Some(mut off) = offscreen() else { return };
    let state = finished_default();
    let (img, no_trail, _) = with_and_without_trail(&mut off, &state, ViewMode::Top, 1.0);
    let (n, _, (y0, y1)) = changed(&img, &no_trail, 30);
    assert!(n > 50, "only {n} trajectory pixels");
    assert!(
        (y1 - y0) as f32 > 0.6 * H as f32,
        "the trajectory spans y {y0}..{y1}"
    );
}

#[test]
fn follow_view_shows_the_stone_large_in_the_middle() {
    let Some(mut off) = offscreen() else { return };
    let state = SimulatedScene::at_time(&default_preset(), 0.3).unwrap();
    let scene = state.scene_for_view(
        SceneStyle::default(),
        ViewMode::Follow,
        1.0,
        W as f32 / H as f32,
    );
    let with = off.render(&scene, W, H).unwrap();
    let mut none = scene.clone();
    none.stone = None;
    let without = off.render(&none, W, H).unwrap();
    let (n, (x0, x1), (y0, y1)) = changed(&with, &without, 20);
    // The chase camera is close: the stone covers a good patch near the centre, at least half
    // of its face's projected ellipse (a: its radius over the distance in pixels, b: a times the
    // sine of the angle between the line of sight and the face); the thin rim shows little.
    let stone = scene.stone.as_ref().unwrap();
    let to_eye = scene.camera.eye_world() - stone.position.as_vec3();
    let normal = (stone.orientation * glam::DVec3::Z).as_vec3();
    let f_px = 0.5 * H as f32 / (0.5 * scene.camera.fov_y).tan();
    let a = stone.radius as f32 / to_eye.length() * f_px;
    let b = a * normal.dot(to_eye.normalize()).abs();
    let ellipse = std::f32::consts::PI * a * b;
    assert!(
        n as f32 > 0.5 * ellipse && n > 150,
        "the stone covers only {n} pixels (its face projects to {ellipse:.0})"
    );
    let (cx, cy) = ((x0 + x1) as f32 / 2.0, (y0 + y1) as f32 / 2.0);
    assert!(
        (cx - W as f32 / 2.0).abs() < 0.2 * W as f32,
        "stone at x {cx}"
    );
    assert!(
        (cy - H as f32 / 2.0).abs() < 0.3 * H as f32,
        "stone at y {cy}"
    );
}

#[test]
fn a_far_stone_is_never_drawn_smaller_than_12_pixels() {
    let Some(mut off) = offscreen() else { return };
    // Behind the launch point, the stone 6 m away: 10 cm across is about 5 px at this size.
    let state = SimulatedScene::at_time(&default_preset(), 0.7).unwrap();
    let scene = state.scene(SceneStyle {
        show_trail: false,
        show_markers: false,
        show_splashes: false,
        ripple_gain: 1.0,
    });
    let with = off.render(&scene, W, H).unwrap();
    let mut none = scene.clone();
    none.stone = None;
    let without = off.render(&none, W, H).unwrap();
    let (n, (x0, x1), (y0, y1)) = changed(&with, &without, 20);
    assert!(
        x1 - x0 + 1 >= 12 && y1 - y0 + 1 >= 12,
        "drawn {}×{} px",
        x1 - x0 + 1,
        y1 - y0 + 1
    );
    assert!(n > 60, "only {n} pixels");
}

#[test]
fn render_refuses_an_exaggeration_it_does_not_offer() {
    let dir = tempfile::tempdir().unwrap();
    let view = PictureView {
        view: ViewMode::Side,
        exaggeration: 7.0,
    };
    let e = stoneskip_render::render_to_png(
        &default_preset(),
        &dir.path().join("x.png"),
        64,
        36,
        0.0,
        view,
    )
    .unwrap_err();
    assert!(format!("{e:#}").contains("exaggeration 7"), "{e:#}");
}

#[test]
fn the_render_command_draws_every_camera() {
    if offscreen().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let preset = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/presets/default.ron");
    let mut pictures = Vec::new();
    for view in ["behind", "side", "follow", "top"] {
        let out = dir.path().join(format!("{view}.png"));
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_stoneskip"))
            .args([
                "render", "--width", "160", "--height", "90", "--time", "1.0",
            ])
            .args(["--view", view, "--exaggerate", "10", "--preset"])
            .arg(&preset)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{view}: {}",
            String::from_utf8_lossy(&status.stderr)
        );
        pictures.push(image::open(&out).unwrap().to_rgba8());
    }
    // Four cameras, four different pictures.
    for i in 0..pictures.len() {
        for j in i + 1..pictures.len() {
            assert!(
                changed(&pictures[i], &pictures[j], 30).0 > 500,
                "views {i} and {j} look alike"
            );
        }
    }
}

/// Sand, the rim's colour (0.95, 0.78, 0.35): red above green, green at least 0.7 of red, both
/// well above blue (water and sky are blue-grey, the skip ticks green, the end tick red, its green
/// 0.3 of its red).
fn sandy(p: &image::Rgba<u8>) -> bool {
    let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
    r > 150 && g > 100 && r >= g && 10 * g >= 7 * r && r - b > 70
}

#[test]
fn the_lakes_edges_show_as_a_sand_rim_in_every_camera() {
    let Some(mut off) = offscreen() else { return };
    // The shipped default's lake (the rim is drawn for any lake; this one is what users see first).
    let shipped = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/presets/default.ron");
    let mut shipped = stoneskip_physics::preset::load(&shipped).unwrap_or_else(|e| panic!("{e}"));
    // Its near edge 1 m behind the launch (2 m as shipped): the side view frames the trajectory,
    // whose length depends on the run, and a short run leaves a 2 m margin out of the frame.
    shipped.water.origin = Some([-1.0, -2.0]);
    let state = SimulatedScene::at_time(&shipped, 4.0).unwrap();
    let water = state.sim.water().expect("the default has a lake");
    let (o, c) = (water.origin(), water.cell());
    let hi = [o[0] + water.nx() as f64 * c, o[1] + water.ny() as f64 * c];
    let aspect = W as f32 / H as f32;
    for view in [
        ViewMode::Behind,
        ViewMode::Top,
        ViewMode::Side,
        ViewMode::Follow,
    ] {
        // No trail or markers: the trail is yellow too.
        let style = SceneStyle {
            show_trail: false,
            show_markers: false,
            ..SceneStyle::default()
        };
        let scene = state.scene_for_view(style, view, 10.0, aspect);
        let rim = stoneskip_render::build::lake_rim(o, hi);
        assert!(
            rim.iter().all(|l| scene.lines.contains(l)),
            "{view:?}: the scene lacks the rim"
        );
        let with = off.render(&scene, W, H).unwrap();
        let mut bare = scene.clone();
        bare.lines.retain(|l| !rim.contains(l));
        let without = off.render(&bare, W, H).unwrap();
        // The rim's pixels: changed, sand-coloured, and near where the camera projects an edge.
        let near_edge = |x: u32, y: u32| {
            rim.iter().any(|l| {
                (0..=64).any(|k| {
                    let p = l.a.lerp(l.b, k as f32 / 64.0);
                    scene.camera.project(p, W, H).is_some_and(|q| {
                        (q.x - x as f32).abs() < 6.0 && (q.y - y as f32).abs() < 6.0
                    })
                })
            })
        };
        let (mut rim_px, mut stray) = (0, 0);
        for (x, y, p) in with.enumerate_pixels() {
            let q = without.get_pixel(x, y);
            if (0..3).any(|ch| p[ch].abs_diff(q[ch]) > 30) {
                if sandy(p) && near_edge(x, y) {
                    rim_px += 1;
                } else if !sandy(p) {
                    stray += 1;
                }
            }
        }
        // The rest is the line's antialiased fringe, and in the side view the waterline over it.
        eprintln!("{view:?}: {rim_px} rim pixels, {stray} other changed");

        assert!(rim_px >= 40, "{view:?}: only {rim_px} rim pixels");
        // Nothing sand-coloured along the edges without the rim: the rim is what shows.
        let sand_bare = without
            .enumerate_pixels()
            .filter(|(x, y, p)| sandy(p) && near_edge(*x, *y))
            .count();
        assert!(
            sand_bare * 10 < rim_px,
            "{view:?}: {sand_bare} sand pixels without the rim"
        );
    }
}

/// Issue 39, finding 4: the follow camera drew the columns' two-cell mode (centimetre crests on
/// 2 cm columns) as spikes beside the stone. The water is drawn through a 1-2-1 filter whose
/// slopes are the Sobel operator's, which cancel a checkerboard exactly: a lake of ±1 cm
/// checkerboard columns draws as the flat lake, while a smooth swell of the same height does not.
#[test]
fn the_columns_two_cell_mode_is_not_drawn() {
    let Some(mut off) = offscreen() else { return };
    let state = SimulatedScene::at_time(&default_preset(), 0.0).unwrap();
    let style = SceneStyle {
        show_trail: false,
        show_markers: false,
        show_splashes: false,
        ripple_gain: 1.0,
    };
    let flat_scene = state.scene_for_view(style, ViewMode::Follow, 1.0, W as f32 / H as f32);
    let water = flat_scene.water.expect("a lake");
    let (nx, ny) = (water.nx, water.ny);
    let mut picture = |heights: &[f32], revision: u64| {
        let mut scene = flat_scene.clone();
        scene.water = Some(stoneskip_render::WaterView {
            heights,
            revision,
            ..water
        });
        off.render(&scene, W, H).unwrap()
    };
    let flat = vec![0.0_f32; nx * ny];
    let checker: Vec<f32> = (0..nx * ny)
        .map(|i| {
            if (i % nx + i / nx) % 2 == 0 {
                0.01
            } else {
                -0.01
            }
        })
        .collect();
    let swell: Vec<f32> = (0..nx * ny)
        .map(|i| 0.01 * ((i % nx) as f32 * water.cell as f32 * 12.0).sin())
        .collect();
    let (a, b, c) = (
        picture(&flat, u64::MAX - 3),
        picture(&checker, u64::MAX - 2),
        picture(&swell, u64::MAX - 1),
    );
    let diff = |x: &image::RgbaImage, y: &image::RgbaImage| {
        x.pixels()
            .zip(y.pixels())
            .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap_or(0))
            .max()
            .unwrap_or(0)
    };
    assert!(
        diff(&a, &b) <= 2,
        "the checkerboard shows: {}",
        diff(&a, &b)
    );
    assert!(
        diff(&a, &c) > 20,
        "a smooth swell must show: {}",
        diff(&a, &c)
    );
}

/// Whether `line` is one of the side view's attitude glyphs (by its colours).
fn is_glyph(line: &stoneskip_render::Line) -> bool {
    use stoneskip_render::build::{
        GLYPH_BANKED_COLOR, GLYPH_DUG_IN_COLOR, GLYPH_EDGE_COLOR, GLYPH_LEVEL_COLOR,
    };
    [
        GLYPH_LEVEL_COLOR,
        GLYPH_BANKED_COLOR,
        GLYPH_EDGE_COLOR,
        GLYPH_DUG_IN_COLOR,
    ]
    .contains(&line.color)
}

/// Issue 48: the side view draws the stone as it met the water at each touch, over the touch:
/// the picture differs from one without the glyphs around each skip's projected glyph, and
/// only in the upper part of the view above the waterline.
#[test]
fn the_side_view_draws_the_stones_tilt_at_each_touch() {
    let Some(mut off) = offscreen() else { return };
    let state = finished_default();
    let (w, h) = (640u32, 360u32);
    let aspect = w as f32 / h as f32;
    let with = state.scene_for_view(SceneStyle::default(), ViewMode::Side, 10.0, aspect);
    let mut without = with.clone();
    without.lines.retain(|l| !is_glyph(l));
    let glyphs = with.lines.len() - without.lines.len();
    let cam = with.camera;
    let framing = stoneskip_render::build::framing_of(&state.sim, &state.trail, None);
    let drawn = stoneskip_render::build::glyph_touches(&framing, state.sim.contacts(), &cam, None);
    let touches = state.sim.contacts().iter().filter(|c| !c.graze).count();
    assert!(touches > 3);
    // Touches too close to tell apart at this scale share a glyph; most have their own.
    assert!(
        2 * drawn.len() >= touches,
        "{} glyphs for {touches} touches",
        drawn.len()
    );
    assert_eq!(
        glyphs,
        drawn.len() * stoneskip_render::build::GLYPH_POINTS,
        "{glyphs} glyph lines for {touches} touches"
    );
    let a = off.render(&with, w, h).unwrap();
    let b = off.render(&without, w, h).unwrap();
    if std::env::var("STONESKIP_KEEP_PICTURES").is_ok_and(|v| v == "1") {
        let _ = a.save(std::env::temp_dir().join("stoneskip-side-glyphs.png"));
    }
    let mut seen = 0;
    for c in drawn.iter().map(|&i| &state.sim.contacts()[i]) {
        let (centre, _) = stoneskip_render::build::glyph_centre(c, &cam);
        let q = cam.project(centre, w, h).unwrap();
        if q.x < 0.0 || q.x >= w as f32 || q.y < 0.0 || q.y >= h as f32 {
            continue;
        }
        // Above the waterline where the touch is.
        let water = cam.project(centre.with_z(0.0), w, h).unwrap();
        assert!(q.y < water.y, "glyph at {q:?}, water at {water:?}");
        if max_diff_near(&a, &b, q.x, q.y, 6) > 60 {
            seen += 1;
        }
    }
    assert_eq!(seen, drawn.len(), "{seen} of {} glyphs seen", drawn.len());
}

/// Issue 48: the exported picture (`stoneskip render`, and the app's View PNG, which draws the
/// same legend) carries its legend and scale in a strip under the view: the view's pixels are
/// those of the picture without it, and the strip holds lines of light text and the bar.
#[test]
fn the_exported_picture_has_a_legend_and_a_scale() {
    if offscreen().is_none() {
        return;
    }
    let preset = default_preset();
    let view = PictureView {
        view: ViewMode::Side,
        exaggeration: 10.0,
    };
    let (w, h) = (640u32, 360u32);
    let plain = stoneskip_render::render_image(&preset, w, h, 4.0, view).unwrap();
    let with = stoneskip_render::render_picture(&preset, w, h, 4.0, view).unwrap();
    if std::env::var("STONESKIP_KEEP_PICTURES").is_ok_and(|v| v == "1") {
        let _ = with.save(std::env::temp_dir().join("stoneskip-legend.png"));
    }
    assert_eq!(with.width(), w);
    assert!(
        with.height() > h + 40,
        "no strip: {} px tall",
        with.height()
    );
    let top = image::imageops::crop_imm(&with, 0, 0, w, h).to_image();
    let (n, _, _) = changed(&plain, &top, 30);
    assert_eq!(n, 0, "the legend covers {n} pixels of the view");
    // Several lines of text: light pixels in rows spread over the strip.
    let rows: std::collections::BTreeSet<u32> = with
        .enumerate_pixels()
        .filter(|(_, y, p)| *y >= h && luma(p) > 150.0)
        .map(|(_, y, _)| y)
        .collect();
    assert!(
        rows.len() > 30,
        "text on only {} rows of the strip",
        rows.len()
    );
    // The legend's scale: the side view has one, of round metres, about a fifth of the width.
    let state = SimulatedScene::at_time(&preset, 4.0).unwrap();
    let scene = state.scene_for_view(
        SceneStyle::default(),
        ViewMode::Side,
        10.0,
        w as f32 / h as f32,
    );
    let framing = stoneskip_render::build::framing_of(&state.sim, &state.trail, None);
    let legend = stoneskip_render::legend::legend_of(
        &state.sim,
        ViewMode::Side,
        &scene.camera,
        &framing,
        (w, h),
    );
    let bar = legend.scale.expect("a scale in the side view");
    assert!([1.0, 2.0, 5.0, 10.0].contains(&bar.metres), "{bar:?}");
    assert!(
        bar.pixels > 0.08 * w as f32 && bar.pixels <= 0.21 * w as f32,
        "{bar:?}"
    );
    // It names the skips and what the glyphs mean.
    let text: Vec<&str> = legend.lines.iter().map(|l| l.text.as_str()).collect();
    assert!(
        text[0].contains(&format!("{} skips", state.sim.skips())),
        "{text:?}"
    );
    assert!(text.iter().any(|t| t.contains("tilt")), "{text:?}");
    // The behind view is in perspective: no scale.
    assert!(
        stoneskip_render::legend::scale_bar(ViewMode::Behind, &scene.camera, &framing, (w, h))
            .is_none()
    );
}
