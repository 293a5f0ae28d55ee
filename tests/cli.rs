//! The command-line contract (design.md §7): `simulate` prints a summary, JSON or CSV; bad input
//! exits non-zero with one clear message naming the file, line and field; the same preset gives
//! identical JSON twice.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::{Command, Output};

fn stoneskip(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stoneskip"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// One line on stderr, starting with `stoneskip: error:`, containing every `needle`.
fn assert_clear_error(out: &Output, needles: &[&str]) {
    assert!(!out.status.success(), "must fail");
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one message, got: {err}");
    assert!(lines[0].starts_with("stoneskip: error:"), "{err}");
    for n in needles {
        assert!(lines[0].contains(n), "`{n}` missing from: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

const QUICK: &str = "physics: (max_time: 2.0), water: (enabled: false)";

#[test]
fn bad_input_gets_one_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Malformed RON: line and column of the problem.
    let f = write(
        d,
        "malformed.ron",
        "(\n  name: \"x\",\n  stone: (mass: 0.1,,),\n)",
    );
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", &f]),
        &["malformed.ron:3:"],
    );
    // An unknown field: named, with what was expected.
    let f = write(d, "unknown.ron", "(\n  stone: (\n    weight: 0.1,\n  ),\n)");
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", &f]),
        &["unknown.ron:3:", "weight", "expected one of", "mass"],
    );
    // A negative mass: file, line, field and the expected range.
    let f = write(
        d,
        "negative.ron",
        "(\n  name: \"n\",\n  stone: (\n    mass: -0.1,\n  ),\n)",
    );
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", &f]),
        &[
            "negative.ron:4:",
            "stone.mass",
            "expected a positive number",
        ],
    );
    // NaN.
    let f = write(d, "nan.ron", "(launch: (spin: NaN))");
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", &f]),
        &["nan.ron:1:", "launch.spin", "finite"],
    );
    // A zero dt.
    let f = write(d, "dt.ron", "(\n  physics: (\n    dt: 0.0,\n  ),\n)");
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", &f]),
        &["dt.ron:3:", "physics.dt"],
    );
    // A missing file.
    let missing = d.join("missing.ron");
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", &missing.to_string_lossy()]),
        &["missing.ron", "cannot read"],
    );
}

#[test]
fn json_is_complete_and_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(dir.path(), "p.ron", &format!("({QUICK})"));
    let a = stoneskip(&["simulate", "--preset", &f, "--json"]);
    let b = stoneskip(&["simulate", "--preset", &f, "--json"]);
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    assert_eq!(a.stdout, b.stdout, "identical JSON twice");
    // The run's speed goes to stderr, never into the JSON.
    let err = String::from_utf8_lossy(&a.stderr);
    assert!(
        err.lines()
            .any(|l| l.starts_with("simulated ") && l.contains("of wall time")),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    assert_eq!(v["schema"], 1);
    for key in [
        "name",
        "outcome",
        "skips",
        "distance",
        "final_time",
        "steps",
        "force_evals",
        "contacts",
        "water",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert!(v["water"].is_null());
    let c = &v["contacts"][0];
    for key in [
        "t_start",
        "t_end",
        "skip",
        "x",
        "y",
        "v_in",
        "v_out",
        "attitude_in",
        "attitude_out",
        "beta_in",
        "peak_lift",
    ] {
        assert!(c.get(key).is_some(), "contact missing {key}");
    }
    assert!(["sank", "timeout", "left_domain"].contains(&v["outcome"].as_str().unwrap()));
}

#[test]
fn csv_has_header_and_dense_rows() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        dir.path(),
        "p.ron",
        "(physics: (dt: 0.02, integrator: Paper, max_time: 2.0), water: (enabled: false))",
    );
    let csv = dir.path().join("t.csv");
    let out = stoneskip(&["simulate", "--preset", &f, "--csv", &csv.to_string_lossy()]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz,in_contact,wetted_area,fx,fy,fz"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    assert!(rows.len() > 10);
    for w in rows.windows(2) {
        assert_eq!(w[1].len(), 19);
        let gap = w[1][0] - w[0][0];
        // At least every 1/240 s of flight (with a large dt, flight rows are interpolated).
        if w[0][14] == 0.0 && w[1][14] == 0.0 {
            assert!(gap <= 1.0 / 240.0 + 1e-9, "gap {gap}");
        }
        assert!(gap >= 0.0);
    }
}

#[test]
fn text_summary_has_contact_table() {
    let out = stoneskip(&["simulate", "--preset", "assets/presets/magic_angle.ron"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("outcome sank"), "{text}");
    assert!(text.contains("t_start"), "{text}");
}

#[test]
fn every_shipped_preset_loads_and_runs() {
    for entry in std::fs::read_dir("assets/presets").unwrap() {
        let path = entry.unwrap().path();
        let p = stoneskip_physics::preset::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!p.name.is_empty());
    }
}

/// Built without the `app` feature, the window and the renderer answer with one clear message, and
/// the headless subcommands still work.
#[cfg(not(feature = "app"))]
#[test]
fn headless_build_says_the_app_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("x.png");
    for args in [
        vec![],
        vec!["gui"],
        vec![
            "render",
            "--preset",
            "assets/presets/default.ron",
            "--out",
            png.to_str().unwrap(),
        ],
    ] {
        let out = stoneskip(&args);
        assert_clear_error(&out, &["without the `app` feature", "simulate"]);
    }
    assert!(!png.exists());
}

/// `--preset` takes a shipped preset's name as well as a file: the same run as the file's, bit for
/// bit; a name that is neither gets one message listing the shipped names (issue 39, finding 8).
#[test]
fn preset_by_shipped_name() {
    let by_name = stoneskip(&["simulate", "--preset", "magic_angle", "--json"]);
    assert!(by_name.status.success(), "{by_name:?}");
    let by_file = stoneskip(&[
        "simulate",
        "--preset",
        "assets/presets/magic_angle.ron",
        "--json",
    ]);
    assert_eq!(by_name.stdout, by_file.stdout);
    let ron = stoneskip(&["simulate", "--preset", "magic_angle.ron", "--json"]);
    assert_eq!(ron.stdout, by_file.stdout);
    assert_clear_error(
        &stoneskip(&["simulate", "--preset", "no_such_throw"]),
        &["no_such_throw", "default", "record_throw"],
    );
}

/// The Experiments panel's export of `plan` on `base` (run in the background as the app runs it,
/// then written as the panel's Export CSV writes it), as bytes.
#[cfg(feature = "app")]
fn panel_export(
    base: &stoneskip_physics::sim::params::Preset,
    plan: impl Into<stoneskip::sweep::Plan>,
    dir: &Path,
) -> Vec<u8> {
    let mut e = stoneskip::app::experiments::Experiment::start(base, base, plan);
    let t0 = std::time::Instant::now();
    while !e.finished() {
        assert!(
            t0.elapsed().as_secs() < 300,
            "the panel's experiment did not finish"
        );
        e.poll();
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let panel = dir.join("panel.csv");
    e.write_csv(&panel).unwrap();
    std::fs::read(&panel).unwrap()
}

/// Issue 48: `stoneskip sweep` writes the table the Experiments panel exports, byte for byte
/// (one compute and one writer serve both), and says in plain words what it does. The panel is
/// the app's (the `app` feature).
#[cfg(feature = "app")]
#[test]
fn sweep_writes_the_experiments_export_byte_for_byte() {
    use stoneskip::sweep::{Knob, Spec};
    let dir = tempfile::tempdir().unwrap();
    let cli = dir.path().join("cli.csv");
    let out = stoneskip(&[
        "sweep",
        "--preset",
        "magic_angle",
        "--vary",
        "tilt",
        "--from",
        "10",
        "--to",
        "40",
        "--count",
        "4",
        "--out",
        cli.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let base = stoneskip_physics::preset::shipped("magic_angle")
        .unwrap()
        .unwrap();
    let spec = Spec {
        knob: Knob::Tilt,
        from: 10.0,
        to: 40.0,
        count: 4,
    };
    let a = std::fs::read(&cli).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&a),
        String::from_utf8_lossy(&panel_export(&base, spec, dir.path())),
        "the command and the panel differ"
    );
    let text = String::from_utf8(a).unwrap();
    assert!(
        text.starts_with("# stoneskip sweep of the preset \"Magic angle\""),
        "{text}"
    );
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(rows.len(), 5, "{text}");
    assert!(rows[2].starts_with("20,"), "{text}");
    // A swept speed is written as swept: 7, not the 6.999999999999999 its velocity reads back.
    let speeds = stoneskip(&[
        "sweep",
        "--preset",
        "magic_angle",
        "--vary",
        "speed",
        "--from",
        "6",
        "--to",
        "8",
        "--count",
        "3",
    ]);
    let speeds = String::from_utf8_lossy(&speeds.stdout);
    let first: Vec<&str> = speeds
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').next().unwrap_or(""))
        .collect();
    assert_eq!(first, ["6", "7", "8"], "{speeds}");
    let help = stoneskip(&["sweep", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    for words in ["Experiments panel", "every core", "tilt (degrees)"] {
        assert!(help.contains(words), "`{words}` missing from: {help}");
    }
}

/// Issue 48: a two-value `stoneskip sweep` (a map: every tilt with every impact angle) writes
/// the table the Experiments panel's map exports, byte for byte, one row per throw with both
/// values as columns; `--help` names the second value in plain words, and a pair that cannot be
/// mapped gets one clear message.
#[cfg(feature = "app")]
#[test]
fn a_two_value_sweep_writes_the_maps_export_byte_for_byte() {
    use stoneskip::sweep::{Knob, Plan, Spec};
    let dir = tempfile::tempdir().unwrap();
    let cli = dir.path().join("cli.csv");
    let out = stoneskip(&[
        "sweep",
        "--preset",
        "clanet_disc",
        "--vary",
        "tilt",
        "--from",
        "10",
        "--to",
        "30",
        "--count",
        "2",
        "--vary2",
        "impact_angle",
        "--from2",
        "10",
        "--to2",
        "60",
        "--count2",
        "3",
        "--out",
        cli.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let base = stoneskip_physics::preset::shipped("clanet_disc")
        .unwrap()
        .unwrap();
    let plan = Plan {
        x: Spec {
            knob: Knob::Tilt,
            from: 10.0,
            to: 30.0,
            count: 2,
        },
        y: Some(Spec {
            knob: Knob::ImpactAngle,
            from: 10.0,
            to: 60.0,
            count: 3,
        }),
    };
    let a = std::fs::read(&cli).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&a),
        String::from_utf8_lossy(&panel_export(&base, plan, dir.path())),
        "the command and the panel differ"
    );
    let text = String::from_utf8(a).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(
        rows[0].starts_with("tilt_deg,impact_angle_deg,skips,"),
        "{text}"
    );
    // 2 × 3 throws: each tilt with each impact angle.
    let pairs: Vec<String> = rows[1..]
        .iter()
        .map(|r| r.split(',').take(2).collect::<Vec<_>>().join(","))
        .collect();
    assert_eq!(
        pairs,
        ["10,10", "10,35", "10,60", "30,10", "30,35", "30,60"],
        "{text}"
    );
    let help = stoneskip(&["sweep", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    for words in ["--vary2", "--count2", "impact_angle", "map"] {
        assert!(help.contains(words), "`{words}` missing from: {help}");
    }
    let clash = stoneskip(&[
        "sweep",
        "--preset",
        "default",
        "--vary",
        "height",
        "--vary2",
        "impact_angle",
    ]);
    assert_clear_error(&clash, &["height"]);
    let big = stoneskip(&[
        "sweep", "--preset", "default", "--vary", "tilt", "--count", "21", "--vary2", "speed",
    ]);
    assert_clear_error(&big, &["--count 21", "20"]);
}
