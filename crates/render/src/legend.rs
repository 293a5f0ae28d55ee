//! The legend and scale drawn into an exported picture (issue 48: View PNG and `stoneskip
//! render`): what the throw did (skips, distance, how it ended), what the side view's ticks and
//! stone glyphs mean, and a bar of round metres where the camera has a scale (side and top
//! views). Drawn on the CPU in a strip under the finished image, so it never covers the throw,
//! with egui's own font (Ubuntu Light, through ab_glyph): a picture read away from the app
//! explains itself.

use ab_glyph::{Font as _, FontRef, PxScale, ScaleFont as _};
use glam::Vec3;
use image::{Rgba, RgbaImage};

use super::camera::{Camera, Framing, ViewMode};
use stoneskip_physics::sim::Simulation;

/// Text height (px) of a legend line in a picture 1280 px wide; scaled with the picture.
const TEXT_PX: f32 = 16.0;

/// Pictures smaller than this (px, either side) get no legend: it would cover them.
pub const MIN_SIDE: u32 = 240;

/// One line of the legend and its colour.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendLine {
    pub text: String,
    pub color: [u8; 3],
}

/// A scale bar: `metres` long, `pixels` long on the picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaleBar {
    pub metres: f32,
    pub pixels: f32,
}

/// What a picture's legend says.
#[derive(Debug, Clone, PartialEq)]
pub struct Legend {
    pub lines: Vec<LegendLine>,
    pub scale: Option<ScaleBar>,
}

const WHITE: [u8; 3] = [245, 245, 245];
const PALE: [u8; 3] = [200, 215, 235];

/// A glyph colour as the legend writes it (the scene's linear colours brightened to read on
/// the legend's dark backing).
fn legend_color(c: [f32; 4]) -> [u8; 3] {
    let lift = |u: f32| (80.0 + 175.0 * u.clamp(0.0, 1.0)) as u8;
    [lift(c[0]), lift(c[1]), lift(c[2])]
}

/// The legend of `sim` seen by `camera` in `view` (`exaggeration` the side view's), for a
/// picture `width` × `height` px. `framing` gives the throw's heading for the scale.
pub fn legend_of(
    sim: &Simulation,
    view: ViewMode,
    camera: &Camera,
    framing: &Framing,
    size: (u32, u32),
) -> Legend {
    let skips = sim.skips();
    let head = format!(
        "{}: {skips} skip{}, {:.1} m",
        sim.preset().name,
        if skips == 1 { "" } else { "s" },
        sim.distance()
    );
    let mut lines = vec![LegendLine {
        text: head,
        color: WHITE,
    }];
    if sim.is_finished() {
        lines.push(LegendLine {
            text: format!("ended: {}", sim.ending().words()),
            color: WHITE,
        });
    }
    let view_words = match view {
        ViewMode::Side => format!(
            "side view, heights ×{:.0} (the stones' angles drawn true)",
            camera.exaggeration
        ),
        m => format!("{} view", m.name()),
    };
    lines.push(LegendLine {
        text: view_words,
        color: PALE,
    });
    if view == ViewMode::Side {
        use super::build::{
            GLYPH_BANKED_COLOR, GLYPH_DUG_IN_COLOR, GLYPH_EDGE_COLOR, SIDE_END_COLOR,
            SIDE_SKIP_COLOR,
        };
        let entries = [
            ("green tick: a skip", SIDE_SKIP_COLOR),
            ("red tick: the contact it stayed in", SIDE_END_COLOR),
            (
                "stone: its tilt as it met the water (nose up or down)",
                [0.55, 0.65, 0.85, 1.0],
            ),
            ("orange stone: banked over 10°", GLYPH_BANKED_COLOR),
            (
                "purple stone: on its edge, banked over 20°",
                GLYPH_EDGE_COLOR,
            ),
        ];
        lines.extend(entries.into_iter().map(|(t, c)| LegendLine {
            text: t.to_owned(),
            color: legend_color(c),
        }));
        if let Some(n) = super::build::dug_in_touch(sim) {
            lines.push(LegendLine {
                text: format!("red stone: dug in nose-down here (touch {n})"),
                color: legend_color(GLYPH_DUG_IN_COLOR),
            });
        }
    }
    Legend {
        lines,
        scale: scale_bar(view, camera, framing, size),
    }
}

/// A bar of round metres about a fifth of the picture wide, where the camera has a scale: the
/// side view (along the waterline at the launch) and the top view. None for the perspective
/// cameras behind and following the stone.
pub fn scale_bar(
    view: ViewMode,
    camera: &Camera,
    framing: &Framing,
    (w, h): (u32, u32),
) -> Option<ScaleBar> {
    if !matches!(view, ViewMode::Side | ViewMode::Top) {
        return None;
    }
    let along = Vec3::new(framing.heading.cos(), framing.heading.sin(), 0.0);
    let base = framing.launch.with_z(0.0);
    let a = camera.project(base, w, h)?;
    let b = camera.project(base + along, w, h)?;
    let px_per_m = a.distance(b);
    if !(px_per_m.is_finite() && px_per_m > 1e-3) {
        return None;
    }
    let want = 0.2 * w as f32 / px_per_m;
    let metres = [
        0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0,
    ]
    .into_iter()
    .rev()
    .find(|m| *m <= want)
    .unwrap_or(0.1);
    Some(ScaleBar {
        metres,
        pixels: metres * px_per_m,
    })
}

/// The picture with `legend` in a strip under it, so the legend never covers the throw: the
/// throw's numbers and the camera on the left over the scale bar, what the colours mean on the
/// right. A picture under [`MIN_SIDE`] comes back as it is.
pub fn with_legend(img: &RgbaImage, legend: &Legend) -> RgbaImage {
    let (w, h) = img.dimensions();
    let Some(font) = FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).ok() else {
        return img.clone();
    };
    if w < MIN_SIDE || h < MIN_SIDE {
        return img.clone();
    }
    let px = (TEXT_PX * w.min(2 * h) as f32 / 1280.0).clamp(11.0, 32.0);
    let scaled = font.as_scaled(PxScale::from(px));
    let line_h = (scaled.height() + scaled.line_gap()).ceil() + 2.0;
    let pad = (0.6 * px).round();
    // The first lines (the throw and the camera) on the left; the colours' meanings on the right.
    let split = legend.lines.len().min(LEFT_LINES);
    let (left, right) = legend.lines.split_at(split);
    let bar = legend.scale.filter(|s| s.pixels < 0.45 * w as f32);
    let left_h = left.len() as f32 * line_h + if bar.is_some() { line_h + px } else { 0.0 };
    let right_h = right.len() as f32 * line_h;
    let strip = (left_h.max(right_h) + 2.0 * pad).ceil() as u32;
    let mut out = RgbaImage::from_pixel(w, h + strip, Rgba([22, 26, 38, 255]));
    image::imageops::replace(&mut out, img, 0, 0);
    let left_w = left
        .iter()
        .map(|l| text_width(&font, px, &l.text))
        .fold(bar.map_or(0.0, |s| s.pixels + 4.0 * px), f32::max);
    let right_x = (pad + left_w + 2.0 * pad).max(0.45 * w as f32);
    let top = h as f32 + pad;
    for (k, line) in left.iter().enumerate() {
        let y = top + k as f32 * line_h;
        draw_text(&mut out, &font, px, (pad, y), &line.text, line.color);
    }
    for (k, line) in right.iter().enumerate() {
        let y = top + k as f32 * line_h;
        draw_text(&mut out, &font, px, (right_x, y), &line.text, line.color);
    }
    if let Some(s) = bar {
        let (bx, by) = (pad, top + left.len() as f32 * line_h + 0.6 * px);
        let thick = (0.25 * px).max(2.0);
        fill(&mut out, (bx, by, bx + s.pixels, by + thick), WHITE, 1.0);
        for x in [bx, bx + s.pixels - thick] {
            fill(
                &mut out,
                (x, by - 0.5 * px, x + thick, by + thick),
                WHITE,
                1.0,
            );
        }
        let label = if s.metres >= 1.0 {
            format!("{:.0} m (along the waterline)", s.metres)
        } else {
            format!("{:.0} cm (along the waterline)", s.metres * 100.0)
        };
        draw_text(
            &mut out,
            &font,
            px,
            (bx + s.pixels + 0.6 * px, by - 0.6 * px),
            &label,
            WHITE,
        );
    }
    out
}

/// How many of the legend's first lines (the throw, its ending, the camera) go on the left.
const LEFT_LINES: usize = 3;

/// Width of `text` at `px` (px).
fn text_width(font: &FontRef<'_>, px: f32, text: &str) -> f32 {
    let scaled = font.as_scaled(PxScale::from(px));
    text.chars()
        .map(|c| scaled.h_advance(scaled.glyph_id(c)))
        .sum()
}

/// Blends `color` over the box (x0, y0, x1, y1) at `alpha`.
fn fill(img: &mut RgbaImage, (x0, y0, x1, y1): (f32, f32, f32, f32), color: [u8; 3], alpha: f32) {
    let (w, h) = img.dimensions();
    let clamp = |v: f32, n: u32| (v.round().max(0.0) as u32).min(n);
    for y in clamp(y0, h)..clamp(y1, h) {
        for x in clamp(x0, w)..clamp(x1, w) {
            blend(img.get_pixel_mut(x, y), color, alpha);
        }
    }
}

fn blend(p: &mut Rgba<u8>, color: [u8; 3], alpha: f32) {
    let a = alpha.clamp(0.0, 1.0);
    for c in 0..3 {
        p[c] = (p[c] as f32 * (1.0 - a) + color[c] as f32 * a).round() as u8;
    }
    p[3] = 255;
}

/// Draws `text` with its top left at `at` (px).
fn draw_text(
    img: &mut RgbaImage,
    font: &FontRef<'_>,
    px: f32,
    at: (f32, f32),
    text: &str,
    color: [u8; 3],
) {
    let scaled = font.as_scaled(PxScale::from(px));
    let (w, h) = img.dimensions();
    let mut x = at.0;
    let baseline = at.1 + scaled.ascent();
    for ch in text.chars() {
        let id = scaled.glyph_id(ch);
        let glyph = id.with_scale_and_position(px, ab_glyph::point(x, baseline));
        x += scaled.h_advance(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let (px_x, px_y) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
            if px_x >= 0 && px_y >= 0 && (px_x as u32) < w && (px_y as u32) < h {
                // Light text drawn a touch heavier than the thin font, to read on a projector.
                blend(
                    img.get_pixel_mut(px_x as u32, px_y as u32),
                    color,
                    (1.4 * coverage).min(1.0),
                );
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legend_goes_under_the_picture_and_leaves_a_small_one_alone() {
        let legend = Legend {
            lines: vec![LegendLine {
                text: "default: 23 skips, 32.4 m".to_owned(),
                color: WHITE,
            }],
            scale: Some(ScaleBar {
                metres: 5.0,
                pixels: 120.0,
            }),
        };
        let small = RgbaImage::new(200, 100);
        assert_eq!(with_legend(&small, &legend), small);
        let img = RgbaImage::from_pixel(640, 360, Rgba([128, 128, 128, 255]));
        let out = with_legend(&img, &legend);
        assert_eq!(out.width(), 640);
        assert!(out.height() > 360 + 20, "{}", out.height());
        // The picture itself untouched; the text's light pixels in the strip.
        assert!((0..360).all(|y| (0..640).all(|x| out.get_pixel(x, y) == img.get_pixel(x, y))));
        let bright = out
            .enumerate_pixels()
            .filter(|(_, y, p)| *y >= 360 && p[0] > 200)
            .count();
        assert!(bright > 50, "{bright} bright pixels");
    }
}
