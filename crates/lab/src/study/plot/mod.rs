//! Charts for the studies, as data: line and point charts on linear or logarithmic axes, and
//! class-coloured maps (the phase diagrams), one or several panels per PNG. The drawing itself is
//! `bitmap` (plotters' bitmap backend), built with the `charts` feature; without it [`draw`]
//! draws nothing and the studies write their CSV and Markdown only.
//!
//! Values that a log axis cannot show (≤ 0, non-finite) are dropped from the drawing, never passed
//! to plotters.

use std::path::Path;

use super::style::Rgb;
use super::StudyError;

#[cfg(feature = "charts")]
mod bitmap;

/// Whether this build draws the PNG charts (the `charts` feature).
pub const CHARTS: bool = cfg!(feature = "charts");

/// Loads the charts' font once (a no-op without the `charts` feature).
pub fn ensure_font() -> Result<(), StudyError> {
    #[cfg(feature = "charts")]
    bitmap::ensure_font()?;
    Ok(())
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    Line,
    Points,
    LinePoints,
    Dashed,
}

/// One labelled data series.
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: Rgb,
    pub mark: Mark,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb, mark: Mark) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            mark,
        }
    }
}

/// A labelled horizontal or vertical reference line (theory, published value).
#[derive(Debug, Clone)]
pub struct RefLine {
    pub label: String,
    pub value: f64,
    pub horizontal: bool,
    pub color: Rgb,
}

impl RefLine {
    pub fn h(label: impl Into<String>, value: f64, color: Rgb) -> Self {
        Self {
            label: label.into(),
            value,
            horizontal: true,
            color,
        }
    }
    pub fn v(label: impl Into<String>, value: f64, color: Rgb) -> Self {
        Self {
            label: label.into(),
            value,
            horizontal: false,
            color,
        }
    }
}

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Legend {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
    MiddleRight,
    MiddleLeft,
    None,
}

/// A chart of series on linear or log axes.
#[derive(Debug, Clone)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_log: bool,
    pub y_log: bool,
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub series: Vec<Series>,
    pub lines: Vec<RefLine>,
    pub legend: Legend,
}

impl Chart {
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_log: false,
            y_log: false,
            x_range: None,
            y_range: None,
            series: Vec::new(),
            lines: Vec::new(),
            legend: Legend::UpperRight,
        }
    }
    pub fn log_x(mut self) -> Self {
        self.x_log = true;
        self
    }
    pub fn log_y(mut self) -> Self {
        self.y_log = true;
        self
    }
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
    pub fn legend(mut self, l: Legend) -> Self {
        self.legend = l;
        self
    }
    pub fn series(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
    pub fn line(mut self, l: RefLine) -> Self {
        self.lines.push(l);
        self
    }
}

/// One cell of a class-coloured map.
#[derive(Debug, Clone, Copy)]
pub struct Cell {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
    pub class: usize,
}

/// A map of cells coloured by class (e.g. number of skips), with series drawn over it.
#[derive(Debug, Clone)]
pub struct Heatmap {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub cells: Vec<Cell>,
    /// Label and colour of each class.
    pub classes: Vec<(String, Rgb)>,
    pub overlays: Vec<Series>,
    pub lines: Vec<RefLine>,
    pub legend: Legend,
}

/// A panel of a figure.
#[derive(Debug, Clone)]
pub enum Panel {
    Chart(Chart),
    Heat(Heatmap),
}

/// Draws `panels` in a grid of `cols` columns into a PNG of `size` pixels, under an optional title.
/// Without the `charts` feature it draws nothing.
pub fn draw(
    path: &Path,
    size: (u32, u32),
    cols: usize,
    title: Option<&str>,
    panels: &[Panel],
) -> Result<(), StudyError> {
    #[cfg(feature = "charts")]
    bitmap::draw(path, size, cols, title, panels)?;
    #[cfg(not(feature = "charts"))]
    let _ = (path, size, cols, title, panels);
    Ok(())
}

/// Cell edges of a map axis: halfway between neighbouring values, half a spacing beyond the ends.
pub fn half_steps(v: &[f64]) -> Vec<(f64, f64)> {
    let n = v.len();
    (0..n)
        .map(|i| {
            let lo = if i > 0 {
                0.5 * (v[i - 1] + v[i])
            } else {
                v[i] - 0.5 * (v.get(1).map_or(1.0, |b| b - v[0]))
            };
            let hi = if i + 1 < n {
                0.5 * (v[i] + v[i + 1])
            } else {
                v[i] + 0.5 * (if n > 1 { v[i] - v[i - 1] } else { 1.0 })
            };
            (lo, hi)
        })
        .collect()
}

/// Formats a tick value compactly: 1e-5, 0.02, 150, 2e+06.
pub fn tick(v: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.0e}");
        s.replace("e-0", "e-").replace("e0", "e")
    } else {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_compact() {
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(1e-5), "1e-5");
        assert_eq!(tick(0.02), "0.02");
        assert_eq!(tick(150.0), "150");
        assert_eq!(tick(2e6), "2e6");
        assert_eq!(tick(f64::NAN), "");
    }
}
