//! Which parts of the panels a frame must draw again. On a software rasteriser every panel pixel
//! costs, and during a throw only a few readouts change from one frame to the next; so egui's
//! output outside the 3D view is fingerprinted per tile ([`TILE`] points square, every triangle
//! hashed — clipped to its clip rectangle — into each tile its box touches, in drawing order), and
//! only the tiles whose fingerprint changed are drawn again (merged into a few rectangles), with
//! everything egui draws over them, clipped to them. Equal fingerprints draw equal pixels, so the
//! result is the full redraw's, pixel for pixel.

use egui::epaint::{Primitive, Vertex};
use egui::{ClippedPrimitive, Pos2, Rect};

/// Side of a fingerprint tile (points).
pub const TILE: f32 = 32.0;

/// At most this many rectangles are drawn again (more are joined): each draws the panels' meshes
/// again.
pub const MAX_RECTS: usize = 8;

/// Per-tile fingerprints of one frame's panels.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelTiles {
    /// The screen (points) and the 3D view it was taken with; another layout compares unequal.
    screen: Rect,
    view: Rect,
    ppp: f32,
    cols: usize,
    rows: usize,
    hashes: Vec<u64>,
}

/// A 64-bit mix (splitmix64's finaliser): cheap, and good enough to tell two meshes apart.
fn mix(mut h: u64, v: u64) -> u64 {
    h ^= v
        .wrapping_add(0x9e37_79b9_7f4a_7c15)
        .wrapping_add(h << 6)
        .wrapping_add(h >> 2);
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^ (h >> 31)
}

fn vertex_hash(h: u64, v: &Vertex) -> u64 {
    let h = mix(
        h,
        u64::from(v.pos.x.to_bits()) << 32 | u64::from(v.pos.y.to_bits()),
    );
    let h = mix(
        h,
        u64::from(v.uv.x.to_bits()) << 32 | u64::from(v.uv.y.to_bits()),
    );
    mix(h, u64::from(u32::from_le_bytes(v.color.to_array())))
}

fn rect_hash(h: u64, r: Rect) -> u64 {
    let h = mix(
        h,
        u64::from(r.min.x.to_bits()) << 32 | u64::from(r.min.y.to_bits()),
    );
    mix(
        h,
        u64::from(r.max.x.to_bits()) << 32 | u64::from(r.max.y.to_bits()),
    )
}

impl PanelTiles {
    /// Fingerprints `prims` (points) on `screen`, the 3D view being `view`. Tiles wholly inside
    /// the view are left out: the view is drawn again every frame anyway.
    pub fn new(prims: &[ClippedPrimitive], screen: Rect, view: Rect, ppp: f32) -> Self {
        let cols = ((screen.width() / TILE).ceil().max(1.0)) as usize;
        let rows = ((screen.height() / TILE).ceil().max(1.0)) as usize;
        let mut hashes = vec![0u64; cols * rows];
        let tile_range = |lo: f32, hi: f32, n: usize| {
            let a = ((lo / TILE).floor().max(0.0) as usize).min(n - 1);
            let b = (((hi / TILE).ceil().max(1.0) as usize).saturating_sub(1)).min(n - 1);
            (a, b)
        };
        let mut touch = |bbox: Rect, value: u64| {
            let bbox = bbox.translate(-screen.min.to_vec2());
            if !(bbox.max.x > 0.0 && bbox.max.y > 0.0 && bbox.is_finite()) {
                return;
            }
            let (x0, x1) = tile_range(bbox.min.x, bbox.max.x, cols);
            let (y0, y1) = tile_range(bbox.min.y, bbox.max.y, rows);
            for ty in y0..=y1 {
                for tx in x0..=x1 {
                    let h = &mut hashes[ty * cols + tx];
                    *h = mix(*h, value);
                }
            }
        };
        for (i, p) in prims.iter().enumerate() {
            let clip = p.clip_rect.intersect(screen);
            if !clip.is_positive() || view.contains_rect(clip) {
                continue;
            }
            match &p.primitive {
                Primitive::Mesh(m) => {
                    let base = rect_hash(mix(i as u64, m.texture_id_u64()), clip);
                    for tri in m.indices.chunks_exact(3) {
                        let mut h = base;
                        let mut bbox = Rect::NOTHING;
                        for &k in tri {
                            if let Some(v) = m.vertices.get(k as usize) {
                                h = vertex_hash(h, v);
                                bbox.extend_with(v.pos);
                            }
                        }
                        let bbox = bbox.intersect(clip);
                        if bbox.is_positive() {
                            touch(bbox, h);
                        }
                    }
                }
                // A callback draws what it likes: its tiles are never equal.
                Primitive::Callback(_) => touch(clip, mix(base_seed(), i as u64)),
            }
        }
        // Tiles wholly inside the view do not count.
        for ty in 0..rows {
            for tx in 0..cols {
                if view.contains_rect(tile_rect(screen, tx, ty)) {
                    hashes[ty * cols + tx] = 0;
                }
            }
        }
        Self {
            screen,
            view,
            ppp,
            cols,
            rows,
            hashes,
        }
    }

    /// The rectangles (points) to draw again after `last`: `None` when the whole window must be
    /// (another layout, or changes scattered everywhere), else the changed tiles merged into row
    /// runs, those into blocks, at most [`MAX_RECTS`] — empty when the panels are unchanged.
    pub fn changed_since(&self, last: &PanelTiles) -> Option<Vec<Rect>> {
        if self.screen != last.screen
            || self.view != last.view
            || self.ppp != last.ppp
            || self.hashes.len() != last.hashes.len()
        {
            return None;
        }
        // Runs of changed tiles per row: (row, first col, last col).
        let mut runs: Vec<(usize, usize, usize)> = Vec::new();
        for ty in 0..self.rows {
            let mut tx = 0;
            while tx < self.cols {
                let k = ty * self.cols + tx;
                if self.hashes[k] == last.hashes[k] {
                    tx += 1;
                    continue;
                }
                let start = tx;
                while tx < self.cols
                    && self.hashes[ty * self.cols + tx] != last.hashes[ty * self.cols + tx]
                {
                    tx += 1;
                }
                runs.push((ty, start, tx - 1));
            }
        }
        if runs.len() > 4 * self.rows + 64 {
            return None;
        }
        // A run meeting a block that ends on the row above (columns overlapping or within a tile)
        // joins it: (first row, last row, col0, col1).
        let mut blocks: Vec<(usize, usize, usize, usize)> = Vec::new();
        for (ty, a, b) in runs {
            match blocks
                .iter_mut()
                .find(|blk| blk.1 + 1 >= ty && a <= blk.3 + 1 && blk.2 <= b + 1)
            {
                Some(blk) => *blk = (blk.0, ty, blk.2.min(a), blk.3.max(b)),
                None => blocks.push((ty, ty, a, b)),
            }
        }
        // Still too many: join the pair whose union adds the fewest tiles, until few enough.
        let area = |b: &(usize, usize, usize, usize)| (b.1 - b.0 + 1) * (b.3 - b.2 + 1);
        let union = |p: &(usize, usize, usize, usize), q: &(usize, usize, usize, usize)| {
            (p.0.min(q.0), p.1.max(q.1), p.2.min(q.2), p.3.max(q.3))
        };
        while blocks.len() > MAX_RECTS {
            let mut best = (usize::MAX, 0, 1);
            for i in 0..blocks.len() {
                for j in i + 1..blocks.len() {
                    let u = union(&blocks[i], &blocks[j]);
                    let extra = area(&u).saturating_sub(area(&blocks[i]) + area(&blocks[j]));
                    if extra < best.0 {
                        best = (extra, i, j);
                    }
                }
            }
            let (_, i, j) = best;
            let q = blocks.swap_remove(j);
            blocks[i] = union(&blocks[i], &q);
        }
        // The view's own pixels are drawn again anyway: the rectangles leave it out.
        Some(
            blocks
                .into_iter()
                .flat_map(|(y0, y1, x0, x1)| {
                    let r = tile_rect(self.screen, x0, y0)
                        .union(tile_rect(self.screen, x1, y1))
                        .intersect(self.screen);
                    outside(r, self.view)
                })
                .collect(),
        )
    }
}

/// The parts of `r` outside `view`: at most four rectangles (above, below, left, right of it).
pub fn outside(r: Rect, view: Rect) -> Vec<Rect> {
    let cut = r.intersect(view);
    if !cut.is_positive() {
        return vec![r];
    }
    let parts = [
        Rect::from_min_max(r.min, Pos2::new(r.max.x, cut.min.y)),
        Rect::from_min_max(Pos2::new(r.min.x, cut.max.y), r.max),
        Rect::from_min_max(
            Pos2::new(r.min.x, cut.min.y),
            Pos2::new(cut.min.x, cut.max.y),
        ),
        Rect::from_min_max(
            Pos2::new(cut.max.x, cut.min.y),
            Pos2::new(r.max.x, cut.max.y),
        ),
    ];
    parts.into_iter().filter(|p| p.is_positive()).collect()
}

fn tile_rect(screen: Rect, tx: usize, ty: usize) -> Rect {
    let min = screen.min + egui::vec2(tx as f32 * TILE, ty as f32 * TILE);
    Rect::from_min_max(min, min + egui::vec2(TILE, TILE))
}

/// A value that differs every call (for callbacks).
fn base_seed() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// What egui draws inside `rects`, clipped to them, in egui's order per rectangle.
pub fn clipped_to(prims: &[ClippedPrimitive], rects: &[Rect]) -> Vec<ClippedPrimitive> {
    let mut out = Vec::new();
    for r in rects {
        for p in prims {
            let clip = p.clip_rect.intersect(*r);
            if clip.is_positive() {
                out.push(ClippedPrimitive {
                    clip_rect: clip,
                    primitive: p.primitive.clone(),
                });
            }
        }
    }
    out
}

trait TextureKey {
    fn texture_id_u64(&self) -> u64;
}

impl TextureKey for egui::Mesh {
    fn texture_id_u64(&self) -> u64 {
        match self.texture_id {
            egui::TextureId::Managed(n) => n << 1,
            egui::TextureId::User(n) => (n << 1) | 1,
        }
    }
}

/// The whole screen in points for a window of `size` pixels.
pub fn screen_rect(size: (u32, u32), ppp: f32) -> Rect {
    Rect::from_min_max(
        Pos2::ZERO,
        Pos2::new(size.0 as f32 / ppp, size.1 as f32 / ppp),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Color32, Mesh};

    fn rect_prim(r: Rect, color: Color32, clip: Rect) -> ClippedPrimitive {
        let mut m = Mesh::default();
        m.add_colored_rect(r, color);
        ClippedPrimitive {
            clip_rect: clip,
            primitive: Primitive::Mesh(m),
        }
    }

    /// A window 640 × 320 points: a right panel from x = 480, the 3D view left of it.
    fn layout() -> (Rect, Rect, Rect) {
        let screen = Rect::from_min_max(Pos2::ZERO, Pos2::new(640.0, 320.0));
        let view = Rect::from_min_max(Pos2::ZERO, Pos2::new(480.0, 320.0));
        let panel = Rect::from_min_max(Pos2::new(480.0, 0.0), Pos2::new(640.0, 320.0));
        (screen, view, panel)
    }

    fn frame(readout: Rect, color: Color32) -> Vec<ClippedPrimitive> {
        let (_, view, panel) = layout();
        vec![
            rect_prim(panel, Color32::DARK_GRAY, panel),
            rect_prim(readout, color, panel),
            // Something over the view (the score): never decides a panel redraw.
            rect_prim(
                Rect::from_min_size(Pos2::new(10.0, 10.0), egui::vec2(50.0, 20.0)),
                color,
                view,
            ),
        ]
    }

    #[test]
    fn an_unchanged_panel_draws_nothing_again() {
        let (screen, view, _) = layout();
        let readout = Rect::from_min_size(Pos2::new(500.0, 100.0), egui::vec2(60.0, 14.0));
        let a = PanelTiles::new(&frame(readout, Color32::WHITE), screen, view, 1.0);
        // The part over the view changed colour: still nothing to redraw in the panels.
        let mut f = frame(readout, Color32::WHITE);
        f[2] = rect_prim(
            Rect::from_min_size(Pos2::new(10.0, 10.0), egui::vec2(50.0, 20.0)),
            Color32::RED,
            view,
        );
        let b = PanelTiles::new(&f, screen, view, 1.0);
        assert_eq!(b.changed_since(&a), Some(vec![]));
    }

    #[test]
    fn a_changed_readout_redraws_only_its_tiles() {
        let (screen, view, panel) = layout();
        let readout = Rect::from_min_size(Pos2::new(500.0, 100.0), egui::vec2(60.0, 14.0));
        let a = PanelTiles::new(&frame(readout, Color32::WHITE), screen, view, 1.0);
        let b = PanelTiles::new(&frame(readout, Color32::YELLOW), screen, view, 1.0);
        let rects = b.changed_since(&a).expect("a partial redraw");
        assert_eq!(rects.len(), 1, "{rects:?}");
        assert!(!rects[0].intersects(view) || rects[0].intersect(view).area() == 0.0);
        let r = rects[0];
        // The rectangle covers the readout, lies in the panel's tiles, and is far smaller than it.
        assert!(r.contains_rect(readout), "{r:?}");
        assert!(
            r.min.x >= panel.min.x - TILE && r.max.x <= panel.max.x,
            "{r:?}"
        );
        assert!(r.area() <= 0.25 * panel.area(), "{r:?} against {panel:?}");
        // What is drawn again: every primitive touching it, clipped to it, in order.
        let prims = frame(readout, Color32::YELLOW);
        let again = clipped_to(&prims, &rects);
        assert_eq!(again.len(), 2, "the panel's fill and the readout");
        assert!(again.iter().all(|p| r.contains_rect(p.clip_rect)));
    }

    #[test]
    fn a_moved_readout_redraws_where_it_was_and_where_it_is() {
        let (screen, view, _) = layout();
        let at = |y: f32| Rect::from_min_size(Pos2::new(500.0, y), egui::vec2(60.0, 14.0));
        let a = PanelTiles::new(&frame(at(40.0), Color32::WHITE), screen, view, 1.0);
        let b = PanelTiles::new(&frame(at(240.0), Color32::WHITE), screen, view, 1.0);
        let rects = b.changed_since(&a).expect("a partial redraw");
        assert!(rects.iter().any(|r| r.contains_rect(at(40.0))), "{rects:?}");
        assert!(
            rects.iter().any(|r| r.contains_rect(at(240.0))),
            "{rects:?}"
        );
    }

    #[test]
    fn scattered_changes_join_into_few_rectangles_covering_them() {
        let (screen, view, _) = layout();
        let at = |i: usize| {
            Rect::from_min_size(
                Pos2::new(490.0 + 70.0 * (i % 2) as f32, 8.0 + 20.0 * i as f32),
                egui::vec2(20.0, 6.0),
            )
        };
        let readouts = |color: Color32| {
            let mut f = frame(at(0), Color32::WHITE);
            f.extend((0..15).map(|i| rect_prim(at(i), color, layout().2)));
            f
        };
        let a = PanelTiles::new(&readouts(Color32::WHITE), screen, view, 1.0);
        let b = PanelTiles::new(&readouts(Color32::GREEN), screen, view, 1.0);
        let rects = b.changed_since(&a).expect("a partial redraw");
        assert!(rects.len() <= MAX_RECTS, "{rects:?}");
        for i in 0..15 {
            assert!(
                rects.iter().any(|r| r.contains_rect(at(i))),
                "{i}: {rects:?}"
            );
        }
    }

    #[test]
    fn a_change_at_the_views_edge_never_covers_the_view() {
        // A view edge inside a tile (x = 470): the changed tile is cut there.
        let screen = Rect::from_min_max(Pos2::ZERO, Pos2::new(640.0, 320.0));
        let view = Rect::from_min_max(Pos2::new(0.0, 40.0), Pos2::new(470.0, 320.0));
        let panel = Rect::from_min_max(Pos2::new(470.0, 0.0), Pos2::new(640.0, 320.0));
        let f = |c: Color32| vec![rect_prim(panel, c, panel)];
        let a = PanelTiles::new(&f(Color32::WHITE), screen, view, 1.0);
        let b = PanelTiles::new(&f(Color32::BLUE), screen, view, 1.0);
        let rects = b.changed_since(&a).expect("a partial redraw");
        assert!(!rects.is_empty());
        for r in &rects {
            assert!(
                r.intersect(view).area() <= 0.0,
                "{r:?} covers the view {view:?}"
            );
        }
        let covered: f32 = rects.iter().map(|r| r.intersect(panel).area()).sum();
        assert!(
            covered >= panel.area() - 1e-3,
            "the whole changed panel: {covered}"
        );
    }

    #[test]
    fn another_layout_redraws_everything() {
        let (screen, view, _) = layout();
        let readout = Rect::from_min_size(Pos2::new(500.0, 100.0), egui::vec2(60.0, 14.0));
        let a = PanelTiles::new(&frame(readout, Color32::WHITE), screen, view, 1.0);
        let narrower = Rect::from_min_max(Pos2::ZERO, Pos2::new(470.0, 320.0));
        let b = PanelTiles::new(&frame(readout, Color32::WHITE), screen, narrower, 1.0);
        assert_eq!(b.changed_since(&a), None);
        let c = PanelTiles::new(&frame(readout, Color32::WHITE), screen, view, 2.0);
        assert_eq!(c.changed_since(&a), None);
    }
}
