//! The app's environment hooks, read once at start into [`Options`] (tests, CI and measurements
//! drive the app through them; nothing else reads the environment).
//!
//! | variable | effect |
//! | --- | --- |
//! | `STONESKIP_AUTOTHROW=1` | throws the loaded preset at start |
//! | `STONESKIP_FPS_REPORT=1` | with `--frames N`, prints frame-time totals on exit |
//! | `STONESKIP_NO_VSYNC=1` | presents without waiting for vertical sync |
//! | `STONESKIP_WINDOW_SIZE=WxH` | the window's first size in points (default 1280x800) |
//! | `STONESKIP_MSAA=1` or `4` | overrides the 3D view's multisampling |
//! | `STONESKIP_RENDER_SCALE=S` | resolution of the 3D view while animating (0.25–1) |
//! | `STONESKIP_VIEW=behind\|side\|follow\|top` | the first camera |
//! | `STONESKIP_EXAGGERATE=N` | the side view's vertical exaggeration (1, 5, 10 or 20) |
//! | `STONESKIP_OUTPUT_DIR=DIR` | where exports and screenshots go (default: the user's folders) |
//! | `STONESKIP_REQUIRE_DISPLAY=1` | (tests) no display is an error, not a skip |
//! | `STONESKIP_SOAK=N` | the soak: N automatic throws, cycling through the shipped presets |
//! | `STONESKIP_SOAK_UNTIL=outcome` | a soak throw ends at its outcome, not when the app rests |
//! | `STONESKIP_SOAK_CSV=FILE` | where the soak writes its per-throw rows (default `stoneskip-soak.csv`) |
//! | `STONESKIP_EXPERIMENT=VALUE[:N[:FROM:TO]]` | opens Experiments and runs the suggested sweep of `speed`, `tilt`, `impact_angle`, `spin`, `height` or `mass` (N throws, default 24; from FROM to TO) at start |
//! | `STONESKIP_EXPERIMENT_MAP=VALUE[:N]` | with `STONESKIP_EXPERIMENT`, maps it against a second value (`impact_angle`, …; N values a side, default 20: a 400-cell map) |
//! | `STONESKIP_LAKE_THREAD=0` | steps the lake inside the frame, not on its own thread (for comparison) |
//! | `STONESKIP_FAULT=KIND@N[,…]` | (tests) injects a GPU fault at frame N: `device_lost`, `surface_lost`, `gpu_error` |

use std::path::PathBuf;

use stoneskip_render::camera::{ViewMode, EXAGGERATIONS};

/// Everything the environment can set, parsed once.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub autothrow: bool,
    pub fps_report: bool,
    pub no_vsync: bool,
    /// Logical window size (points).
    pub window_size: (f64, f64),
    /// `Some(1)` or `Some(4)` when forced.
    pub msaa: Option<u32>,
    pub render_scale: Option<f32>,
    pub view: Option<ViewMode>,
    pub exaggeration: Option<f32>,
    pub output_dir: Option<PathBuf>,
    /// Automatic throws of the soak (1 to 10⁶).
    pub soak: Option<u64>,
    pub soak_csv: PathBuf,
    /// A soak throw ends at its outcome (not at rest).
    pub soak_until_outcome: bool,
    /// GPU faults to inject, in frame order.
    pub faults: Vec<Fault>,
    /// The experiment to run at start: the value varied over its suggested range, in so many
    /// throws.
    pub experiment: Option<(super::experiments::Knob, usize)>,
    /// A map's second value at start (`STONESKIP_EXPERIMENT_MAP=VALUE[:N]`, N values, default
    /// 20; the first value then has at most 20): with `experiment`, a two-value map.
    pub experiment_map: Option<(super::experiments::Knob, usize)>,
    /// The first value's range at start, from `STONESKIP_EXPERIMENT=VALUE:N:FROM:TO` (else the
    /// suggested one).
    pub experiment_range: Option<(f64, f64)>,
    /// The lake steps on its own thread while the frame draws (`Model::lake_thread`); the app
    /// turns it on unless `STONESKIP_LAKE_THREAD=0`, the default (tests) leaves it off.
    pub lake_thread: bool,
}

/// A GPU fault the app injects into itself (`STONESKIP_FAULT`), to test its recovery.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fault {
    pub kind: FaultKind,
    /// The frame (counted from 0) before which it strikes.
    pub frame: u64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultKind {
    /// `device.destroy()`: the device is lost as if the driver had reset.
    DeviceLost,
    /// The next `get_current_texture` is treated as `Lost` (the surface is reconfigured).
    SurfaceLost,
    /// An invalid call on a live device (a validation error nobody catches): reported, fatal.
    GpuError,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            autothrow: false,
            fps_report: false,
            no_vsync: false,
            window_size: (1280.0, 800.0),
            msaa: None,
            render_scale: None,
            view: None,
            exaggeration: None,
            output_dir: None,
            soak: None,
            soak_csv: PathBuf::from("stoneskip-soak.csv"),
            soak_until_outcome: false,
            faults: Vec::new(),
            experiment: None,
            experiment_map: None,
            experiment_range: None,
            lake_thread: false,
        }
    }
}

impl Options {
    /// Reads the process environment.
    pub fn from_env() -> Self {
        Self::from_lookup(|k| std::env::var(k).ok())
    }

    /// Parses with `get` as the environment (tests pass a map). Unparsable values are ignored.
    pub fn from_lookup(get: impl Fn(&str) -> Option<String>) -> Self {
        let flag = |k: &str| get(k).is_some_and(|v| v.trim() == "1");
        let d = Self::default();
        Self {
            autothrow: flag("STONESKIP_AUTOTHROW"),
            fps_report: flag("STONESKIP_FPS_REPORT"),
            no_vsync: flag("STONESKIP_NO_VSYNC"),
            window_size: get("STONESKIP_WINDOW_SIZE")
                .and_then(|v| parse_size(&v))
                .unwrap_or(d.window_size),
            msaa: get("STONESKIP_MSAA").and_then(|v| match v.trim() {
                "1" => Some(1),
                "4" => Some(4),
                _ => None,
            }),
            render_scale: get("STONESKIP_RENDER_SCALE")
                .and_then(|v| v.trim().parse::<f32>().ok())
                .filter(|s| s.is_finite() && (0.25..=1.0).contains(s)),
            view: get("STONESKIP_VIEW").and_then(|v| ViewMode::parse(&v)),
            exaggeration: get("STONESKIP_EXAGGERATE")
                .and_then(|v| v.trim().parse::<f32>().ok())
                .filter(|e| EXAGGERATIONS.contains(e)),
            output_dir: get("STONESKIP_OUTPUT_DIR")
                .filter(|v| !v.trim().is_empty())
                .map(PathBuf::from),
            soak: get("STONESKIP_SOAK")
                .and_then(|v| v.trim().parse::<u64>().ok())
                .filter(|n| (1..=1_000_000).contains(n)),
            soak_csv: get("STONESKIP_SOAK_CSV")
                .filter(|v| !v.trim().is_empty())
                .map_or(d.soak_csv, PathBuf::from),
            soak_until_outcome: get("STONESKIP_SOAK_UNTIL").is_some_and(|v| v.trim() == "outcome"),
            experiment: get("STONESKIP_EXPERIMENT").and_then(|v| {
                let (name, count) = v.split_once(':').unwrap_or((&v, ""));
                let knob = super::experiments::Knob::parse(name)?;
                let count = count.split(':').next()?.trim().parse().unwrap_or(24);
                Some((knob, count))
            }),
            experiment_range: get("STONESKIP_EXPERIMENT").and_then(|v| {
                let mut parts = v.split(':').skip(2).map(|x| x.trim().parse::<f64>().ok());
                let (from, to) = (parts.next()??, parts.next()??);
                (from.is_finite() && to.is_finite()).then_some((from, to))
            }),
            experiment_map: get("STONESKIP_EXPERIMENT_MAP").and_then(|v| {
                let (name, count) = v.split_once(':').unwrap_or((&v, ""));
                let knob = super::experiments::Knob::parse(name)?;
                Some((knob, count.trim().parse().unwrap_or(20)))
            }),
            faults: get("STONESKIP_FAULT")
                .map(|v| parse_faults(&v))
                .unwrap_or_default(),
            lake_thread: get("STONESKIP_LAKE_THREAD").is_none_or(|v| v.trim() != "0"),
        }
    }
}

/// "device_lost@30,surface_lost@10" → the faults sorted by frame; unknown entries are ignored.
fn parse_faults(v: &str) -> Vec<Fault> {
    let mut faults: Vec<Fault> = v
        .split(',')
        .filter_map(|f| {
            let (kind, frame) = f.trim().split_once('@')?;
            let kind = match kind.trim() {
                "device_lost" => FaultKind::DeviceLost,
                "surface_lost" => FaultKind::SurfaceLost,
                "gpu_error" => FaultKind::GpuError,
                _ => return None,
            };
            let frame = frame.trim().parse::<u64>().ok()?;
            Some(Fault { kind, frame })
        })
        .collect();
    faults.sort_by_key(|f| f.frame);
    faults
}

/// "1280x720" → (1280, 720), within 320–8192 × 240–8192.
fn parse_size(v: &str) -> Option<(f64, f64)> {
    let (w, h) = v.split_once('x')?;
    let (w, h) = (w.trim().parse::<f64>().ok()?, h.trim().parse::<f64>().ok()?);
    ((320.0..=8192.0).contains(&w) && (240.0..=8192.0).contains(&h)).then_some((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(pairs: &[(&str, &str)]) -> Options {
        let map: std::collections::HashMap<String, String> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        Options::from_lookup(|k| map.get(k).cloned())
    }

    #[test]
    fn parses_each_hook_once_and_ignores_nonsense() {
        // The app steps its lake on its own thread unless told not to; the default (the models
        // of the tests) steps it inside the frame.
        assert_eq!(
            with(&[]),
            Options {
                lake_thread: true,
                ..Options::default()
            }
        );
        assert!(!with(&[("STONESKIP_LAKE_THREAD", "0")]).lake_thread);
        let o = with(&[
            ("STONESKIP_AUTOTHROW", "1"),
            ("STONESKIP_WINDOW_SIZE", "1280x720"),
            ("STONESKIP_MSAA", "4"),
            ("STONESKIP_VIEW", "side"),
            ("STONESKIP_EXAGGERATE", "10"),
            ("STONESKIP_RENDER_SCALE", "1"),
        ]);
        assert!(o.autothrow && !o.fps_report);
        assert_eq!(o.window_size, (1280.0, 720.0));
        assert_eq!(o.msaa, Some(4));
        assert_eq!(o.view, Some(ViewMode::Side));
        assert_eq!(o.exaggeration, Some(10.0));
        assert_eq!(o.render_scale, Some(1.0));
        let bad = with(&[
            ("STONESKIP_AUTOTHROW", "yes"),
            ("STONESKIP_WINDOW_SIZE", "99999x1"),
            ("STONESKIP_MSAA", "8"),
            ("STONESKIP_EXAGGERATE", "nan"),
            ("STONESKIP_RENDER_SCALE", "nan"),
        ]);
        assert_eq!(
            bad,
            Options {
                lake_thread: true,
                ..Options::default()
            }
        );
    }

    #[test]
    fn an_experiment_at_start_parses() {
        use crate::app::experiments::Knob;
        assert_eq!(
            with(&[("STONESKIP_EXPERIMENT", "Tilt")]).experiment,
            Some((Knob::Tilt, 24))
        );
        assert_eq!(
            with(&[("STONESKIP_EXPERIMENT", "speed:120")]).experiment,
            Some((Knob::Speed, 120))
        );
        assert_eq!(with(&[("STONESKIP_EXPERIMENT", "wind")]).experiment, None);
        let mass = with(&[("STONESKIP_EXPERIMENT", "mass:8:0.14:0.28")]);
        assert_eq!(mass.experiment, Some((Knob::Mass, 8)));
        assert_eq!(mass.experiment_range, Some((0.14, 0.28)));
        assert_eq!(
            with(&[("STONESKIP_EXPERIMENT_MAP", "impact_angle:12")]).experiment_map,
            Some((Knob::ImpactAngle, 12))
        );
    }

    #[test]
    fn soak_and_faults_parse() {
        let o = with(&[
            ("STONESKIP_SOAK", "500"),
            ("STONESKIP_SOAK_CSV", "/tmp/s.csv"),
            ("STONESKIP_SOAK_UNTIL", "outcome"),
            (
                "STONESKIP_FAULT",
                "device_lost@30, surface_lost@10,bogus@3,device_lost@x",
            ),
        ]);
        assert_eq!(o.soak, Some(500));
        assert_eq!(o.soak_csv, PathBuf::from("/tmp/s.csv"));
        assert!(o.soak_until_outcome);
        assert_eq!(
            o.faults,
            vec![
                Fault {
                    kind: FaultKind::SurfaceLost,
                    frame: 10
                },
                Fault {
                    kind: FaultKind::DeviceLost,
                    frame: 30
                },
            ]
        );
        assert_eq!(with(&[("STONESKIP_SOAK", "0")]).soak, None);
        assert_eq!(with(&[("STONESKIP_SOAK", "-3")]).soak, None);
    }
}
