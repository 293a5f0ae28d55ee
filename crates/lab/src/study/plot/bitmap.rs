//! The plotters backend of [`super`]: draws charts and maps into PNGs with the bitmap backend.
//!
//! Text uses DejaVu Sans, shipped in `assets/fonts/` and compiled in (`include_bytes!`), registered
//! with plotters' ab_glyph renderer, so no system font lookup happens at run time.

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::{tick, Chart, Heatmap, Legend, Mark, Panel};
use crate::study::style::Rgb;
use crate::study::StudyError;

/// DejaVu Sans (Bitstream Vera licence, `assets/fonts/LICENSE-DejaVu.txt`).
static FONT: &[u8] = include_bytes!("../../../../../assets/fonts/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Registers the shipped font once; later calls return the first result.
pub fn ensure_font() -> Result<(), StudyError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE
        .get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if ok {
        Ok(())
    } else {
        Err(StudyError::Failed(
            "the shipped font assets/fonts/DejaVuSans.ttf could not be loaded".into(),
        ))
    }
}

/// plotters' colour of an [`Rgb`].
fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

fn plot_err(path: &Path, message: String) -> StudyError {
    StudyError::Plot {
        path: path.to_path_buf(),
        message,
    }
}

/// Draws `panels` in a grid of `cols` columns into a PNG of `size` pixels, under an optional title.
pub fn draw(
    path: &Path,
    size: (u32, u32),
    cols: usize,
    title: Option<&str>,
    panels: &[Panel],
) -> Result<(), StudyError> {
    ensure_font()?;
    let err = |e: DrawingAreaErrorKind<_>| plot_err(path, e.to_string());
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let area = match title {
        Some(t) => root.titled(t, (FAMILY, 28)).map_err(&err)?,
        None => root.clone(),
    };
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let areas = area.split_evenly((rows, cols));
    for (panel, a) in panels.iter().zip(areas.iter()) {
        match panel {
            Panel::Chart(c) => draw_chart(a, c).map_err(|e| plot_err(path, e))?,
            Panel::Heat(h) => draw_heat(a, h).map_err(|e| plot_err(path, e))?,
        }
    }
    root.present().map_err(&err)?;
    Ok(())
}

fn usable(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

/// Data range of one axis, padded; a log axis gets whole decades when it spans less than one.
fn auto_range(vals: impl Iterator<Item = f64>, log: bool, fixed: Option<(f64, f64)>) -> (f64, f64) {
    if let Some((a, b)) = fixed {
        if usable(a, log) && usable(b, log) && b > a {
            return (a, b);
        }
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| usable(*v, log)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        // Whole decades, plus a margin so the decade marks (the labels) are not on the border,
        // where plotters drops them.
        let (l, h) = (lo.log10().floor(), hi.log10().ceil());
        let h = if h <= l { l + 1.0 } else { h };
        (10f64.powf(l - 0.15), 10f64.powf(h + 0.15))
    } else {
        let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
        (lo - 0.05 * span, hi + 0.05 * span)
    }
}

/// Points of a series inside the ranges (lines are cut where a point is unusable).
fn segments(
    points: &[(f64, f64)],
    c: &Chart,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for &(x, y) in points {
        let ok = usable(x, c.x_log) && usable(y, c.y_log);
        if ok {
            // Clamp into the plotting range so a wild value shows at the border, not off the chart.
            let p = (x.clamp(xr.0, xr.1), y.clamp(yr.0, yr.1));
            if let Some(last) = out.last_mut() {
                last.push(p);
            }
        } else if out.last().is_some_and(|l| !l.is_empty()) {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

fn legend_pos(l: Legend) -> SeriesLabelPosition {
    match l {
        Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
        Legend::UpperRight | Legend::None => SeriesLabelPosition::UpperRight,
        Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
        Legend::LowerRight => SeriesLabelPosition::LowerRight,
        Legend::MiddleRight => SeriesLabelPosition::MiddleRight,
        Legend::MiddleLeft => SeriesLabelPosition::MiddleLeft,
    }
}

type DrawResult =
    Result<(), DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

fn draw_chart(area: &DrawingArea<BitMapBackend<'_>, Shift>, c: &Chart) -> Result<(), String> {
    let xs = c
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .chain(c.lines.iter().filter(|l| !l.horizontal).map(|l| l.value));
    let ys = c
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .chain(c.lines.iter().filter(|l| l.horizontal).map(|l| l.value));
    let xr = auto_range(xs, c.x_log, c.x_range);
    let yr = auto_range(ys, c.y_log, c.y_range);
    let mut b = ChartBuilder::on(area);
    b.caption(&c.title, (FAMILY, 20))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(74);
    let r = match (c.x_log, c.y_log) {
        (false, false) => {
            let cc = b
                .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
                .map_err(|e| e.to_string())?;
            fill_chart(cc, c, xr, yr)
        }
        (true, false) => {
            let cc = b
                .build_cartesian_2d((xr.0..xr.1).log_scale(), yr.0..yr.1)
                .map_err(|e| e.to_string())?;
            fill_chart(cc, c, xr, yr)
        }
        (false, true) => {
            let cc = b
                .build_cartesian_2d(xr.0..xr.1, (yr.0..yr.1).log_scale())
                .map_err(|e| e.to_string())?;
            fill_chart(cc, c, xr, yr)
        }
        (true, true) => {
            let cc = b
                .build_cartesian_2d((xr.0..xr.1).log_scale(), (yr.0..yr.1).log_scale())
                .map_err(|e| e.to_string())?;
            fill_chart(cc, c, xr, yr)
        }
    };
    r.map_err(|e| e.to_string())
}

fn fill_chart<'a, 'b: 'a, X, Y>(
    mut cc: ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>,
    c: &Chart,
    xr: (f64, f64),
    yr: (f64, f64),
) -> DrawResult
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let fmt = |v: &f64| tick(*v);
    cc.configure_mesh()
        .x_desc(c.x_label.as_str())
        .y_desc(c.y_label.as_str())
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .x_labels(8)
        .y_labels(8)
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()?;
    for l in &c.lines {
        let style = rgb(l.color).stroke_width(2);
        let pts = if l.horizontal {
            if !usable(l.value, c.y_log) || l.value < yr.0 || l.value > yr.1 {
                continue;
            }
            vec![(xr.0, l.value), (xr.1, l.value)]
        } else {
            if !usable(l.value, c.x_log) || l.value < xr.0 || l.value > xr.1 {
                continue;
            }
            vec![(l.value, yr.0), (l.value, yr.1)]
        };
        let col = rgb(l.color);
        cc.draw_series(DashedLineSeries::new(pts, 8, 6, style))?
            .label(l.label.as_str())
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (9, 0)], col.stroke_width(2))
                    + PathElement::new(vec![(15, 0), (24, 0)], col.stroke_width(2))
            });
    }
    for s in &c.series {
        let col = rgb(s.color);
        let segs = segments(&s.points, c, xr, yr);
        let mut labelled = false;
        let mark = s.mark;
        let (a, b, rad) = legend_shape(mark, 4);
        let legend = move |(x, y): (i32, i32)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(a.0, 0), (a.1, 0)], col.stroke_width(2))
                + PathElement::new(vec![(b.0, 0), (b.1, 0)], col.stroke_width(2))
                + Circle::new((12, 0), rad, col.filled())
        };
        for seg in segs {
            let ann = match s.mark {
                Mark::Line => cc.draw_series(LineSeries::new(seg.clone(), col.stroke_width(2)))?,
                Mark::Dashed => cc.draw_series(DashedLineSeries::new(
                    seg.clone(),
                    10,
                    6,
                    col.stroke_width(2),
                ))?,
                Mark::Points => {
                    cc.draw_series(seg.iter().map(|&p| Circle::new(p, 4, col.filled())))?
                }
                Mark::LinePoints => {
                    cc.draw_series(LineSeries::new(seg.clone(), col.stroke_width(2)))?;
                    cc.draw_series(seg.iter().map(|&p| Circle::new(p, 4, col.filled())))?
                }
            };
            if !labelled && !s.label.is_empty() {
                ann.label(s.label.as_str()).legend(legend);
                labelled = true;
            }
        }
    }
    if c.legend != Legend::None && (!c.series.is_empty() || !c.lines.is_empty()) {
        cc.configure_series_labels()
            .position(legend_pos(c.legend))
            .background_style(WHITE.mix(0.88))
            .border_style(RGBColor(160, 160, 160))
            .label_font((FAMILY, 14))
            .draw()?;
    }
    Ok(())
}

/// Legend sample of a mark: two path pieces (x ranges, pixels) and a dot radius.
fn legend_shape(mark: Mark, dot: i32) -> ((i32, i32), (i32, i32), i32) {
    match mark {
        Mark::Points => ((12, 12), (12, 12), dot),
        Mark::LinePoints => ((0, 12), (12, 24), dot),
        Mark::Line => ((0, 12), (12, 24), 0),
        Mark::Dashed => ((0, 9), (15, 24), 0),
    }
}

/// A legend drawn beside a chart: class swatches, then series samples, then reference lines.
fn side_legend(area: &DrawingArea<BitMapBackend<'_>, Shift>, h: &Heatmap) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    let style = (FAMILY, 14).into_font().color(&BLACK);
    let mut y = 60;
    for (label, col) in &h.classes {
        area.draw(&Rectangle::new(
            [(6, y - 7), (22, y + 7)],
            rgb(*col).filled(),
        ))
        .map_err(e)?;
        area.draw(&Text::new(label.clone(), (30, y - 7), style.clone()))
            .map_err(e)?;
        y += 22;
    }
    y += 10;
    for s in &h.overlays {
        let (a, b, rad) = legend_shape(s.mark, 5);
        let col = rgb(s.color);
        area.draw(&PathElement::new(
            vec![(a.0 + 2, y), (a.1 + 2, y)],
            col.stroke_width(3),
        ))
        .map_err(e)?;
        area.draw(&PathElement::new(
            vec![(b.0 + 2, y), (b.1 + 2, y)],
            col.stroke_width(3),
        ))
        .map_err(e)?;
        if rad > 0 {
            area.draw(&Circle::new((14, y), rad, col.filled()))
                .map_err(e)?;
        }
        area.draw(&Text::new(s.label.clone(), (30, y - 7), style.clone()))
            .map_err(e)?;
        y += 22;
    }
    for l in &h.lines {
        let col = rgb(l.color);
        area.draw(&PathElement::new(
            vec![(2, y), (11, y)],
            col.stroke_width(2),
        ))
        .map_err(e)?;
        area.draw(&PathElement::new(
            vec![(17, y), (26, y)],
            col.stroke_width(2),
        ))
        .map_err(e)?;
        area.draw(&Text::new(l.label.clone(), (30, y - 7), style.clone()))
            .map_err(e)?;
        y += 22;
    }
    Ok(())
}

fn draw_heat(area: &DrawingArea<BitMapBackend<'_>, Shift>, h: &Heatmap) -> Result<(), String> {
    let area = if h.legend == Legend::None {
        area.clone()
    } else {
        let w = area.dim_in_pixel().0 as i32;
        let (plot, side) = area.split_horizontally(w - 210);
        side_legend(&side, h)?;
        plot
    };
    let area = &area;
    let mut b = ChartBuilder::on(area);
    b.caption(&h.title, (FAMILY, 20))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(64);
    let cc = b
        .build_cartesian_2d(h.x_range.0..h.x_range.1, h.y_range.0..h.y_range.1)
        .map_err(|e| e.to_string())?;
    fill_heat(cc, h).map_err(|e| e.to_string())
}

fn fill_heat<'a, 'b: 'a>(
    mut cc: ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    h: &Heatmap,
) -> DrawResult {
    let fmt = |v: &f64| tick(*v);
    cc.configure_mesh()
        .x_desc(h.x_label.as_str())
        .y_desc(h.y_label.as_str())
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .disable_mesh()
        .draw()?;
    let classes = &h.classes;
    cc.draw_series(h.cells.iter().filter_map(|cell| {
        let (_, col) = classes.get(cell.class)?;
        Some(Rectangle::new(
            [(cell.x0, cell.y0), (cell.x1, cell.y1)],
            rgb(*col).filled(),
        ))
    }))?;
    let (xr, yr) = (h.x_range, h.y_range);
    for l in &h.lines {
        let pts = if l.horizontal {
            vec![(xr.0, l.value), (xr.1, l.value)]
        } else {
            vec![(l.value, yr.0), (l.value, yr.1)]
        };
        let col = rgb(l.color);
        cc.draw_series(DashedLineSeries::new(pts, 8, 6, col.stroke_width(2)))?;
    }
    for s in &h.overlays {
        let col = rgb(s.color);
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .filter(|p| (xr.0..=xr.1).contains(&p.0) && (yr.0..=yr.1).contains(&p.1))
            .collect();
        match s.mark {
            Mark::Points => {
                cc.draw_series(pts.iter().map(|&p| Circle::new(p, 5, col.filled())))?;
            }
            Mark::Dashed => {
                cc.draw_series(DashedLineSeries::new(pts, 10, 6, col.stroke_width(3)))?;
            }
            Mark::Line => {
                cc.draw_series(LineSeries::new(pts, col.stroke_width(3)))?;
            }
            Mark::LinePoints => {
                cc.draw_series(LineSeries::new(pts.clone(), col.stroke_width(3)))?;
                cc.draw_series(pts.iter().map(|&p| Circle::new(p, 4, col.filled())))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ranges_are_whole_decades() {
        let r = auto_range([0.003, 0.2].into_iter(), true, None);
        assert!(r.0 < 1e-3 && r.0 > 5e-4 && r.1 > 1.0 && r.1 < 2.0, "{r:?}");
        let r = auto_range([0.0, -1.0, f64::NAN].into_iter(), true, None);
        assert_eq!(r, (0.1, 10.0));
    }
}
