//! Throw presets as RON files (design.md §6): load with errors that name the file, line, column
//! and field and say what was expected; save atomically (a temporary file renamed over the old one,
//! so an existing preset is never left half-written).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::sim::params::{schema_expected, with_schema, ParamError, Preset, LATEST_SCHEMA};

/// Why a preset could not be read or written. Displayed as one line: `file:line:col: message`.
#[derive(Debug, thiserror::Error)]
pub enum PresetError {
    /// The file could not be read (missing, unreadable) and is not a shipped preset's name.
    #[error(
        "{path}: cannot read the preset: {error} (a file, or a shipped preset's name: {})",
        shipped_names()
    )]
    Read {
        /// The file that was asked for.
        path: PathBuf,
        /// The operating system's reason.
        error: std::io::Error,
    },
    /// The text is not valid RON for a preset (bad syntax, an unknown field, a wrong type).
    #[error("{path}:{line}:{col}: {message}")]
    Syntax {
        /// The file (or `assets/presets/STEM.ron` for a shipped preset).
        path: PathBuf,
        /// 1-based line where RON found the error.
        line: usize,
        /// 1-based column where RON found the error.
        col: usize,
        /// RON's message, with the expected fields spelled out for an unknown field.
        message: String,
    },
    /// The text parses but a value is out of range or inconsistent, or the `version` is unknown.
    #[error("{path}:{line}: {error}")]
    Invalid {
        /// The file (or `assets/presets/STEM.ron` for a shipped preset).
        path: PathBuf,
        /// Best-effort 1-based line of the offending field (1 when it is not found).
        line: usize,
        /// The field and what was expected of it.
        error: ParamError,
    },
    /// Saving failed (an invalid preset, a read-only folder, a full disk); the old file is kept.
    #[error("{path}: cannot save the preset: {message}")]
    Write {
        /// The file that was to be written.
        path: PathBuf,
        /// Why, in one line.
        message: String,
    },
}

/// The shipped presets (`assets/presets/`), by file stem, as compiled in.
pub const SHIPPED: [(&str, &str); 9] = [
    ("default", crate::sim::params::SHIPPED_DEFAULT_RON),
    (
        "magic_angle",
        include_str!("../../../assets/presets/magic_angle.ron"),
    ),
    (
        "record_throw",
        include_str!("../../../assets/presets/record_throw.ron"),
    ),
    (
        "too_slow",
        include_str!("../../../assets/presets/too_slow.ron"),
    ),
    (
        "too_steep",
        include_str!("../../../assets/presets/too_steep.ron"),
    ),
    ("paper", include_str!("../../../assets/presets/paper.ron")),
    (
        "bocquet_plate",
        include_str!("../../../assets/presets/bocquet_plate.ron"),
    ),
    (
        "clanet_disc",
        include_str!("../../../assets/presets/clanet_disc.ron"),
    ),
    (
        "no_spin_dive",
        include_str!("../../../assets/presets/no_spin_dive.ron"),
    ),
];

fn shipped_names() -> String {
    SHIPPED.map(|(stem, _)| stem).join(", ")
}

/// The shipped preset `stem` (`default`, `record_throw`, …) as compiled in; `None` for another name.
pub fn shipped(stem: &str) -> Option<Result<Preset, PresetError>> {
    SHIPPED
        .iter()
        .find(|(s, _)| *s == stem)
        .map(|(stem, text)| parse(text, Path::new(&format!("assets/presets/{stem}.ron"))))
}

/// A preset file, or, when no such file exists, the shipped preset of that name (`default`,
/// `record_throw`, …, with or without `.ron`): what the command line's `--preset` takes.
pub fn load_file_or_shipped(arg: &Path) -> Result<Preset, PresetError> {
    if !arg.exists() {
        let name = arg.to_string_lossy();
        let stem = name.strip_suffix(".ron").unwrap_or(&name);
        if let Some(preset) = shipped(stem) {
            return preset;
        }
    }
    load(arg)
}

/// Reads and validates a preset file.
pub fn load(path: &Path) -> Result<Preset, PresetError> {
    let text = fs::read_to_string(path).map_err(|error| PresetError::Read {
        path: path.to_owned(),
        error,
    })?;
    parse(&text, path)
}

/// Parses and validates preset text; `path` names it in messages. The omitted fields take the
/// base of the file's `version` (design.md §3: 1, or omitted, the model before the fidelity work;
/// 2 the shipped default).
pub fn parse(text: &str, path: &Path) -> Result<Preset, PresetError> {
    let syntax = |e: ron::error::SpannedError| PresetError::Syntax {
        path: path.to_owned(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: explain(&e.code),
    };
    let version = schema_of(text);
    if !(1..=LATEST_SCHEMA).contains(&version) {
        return Err(PresetError::Invalid {
            path: path.to_owned(),
            line: locate_field(text, "version"),
            error: ParamError::new("version", schema_expected(version)),
        });
    }
    let preset: Preset =
        with_schema(version, || ron::Options::default().from_str(text)).map_err(syntax)?;
    preset.validate().map_err(|error| PresetError::Invalid {
        path: path.to_owned(),
        line: locate_field(text, &error.field),
        error,
    })?;
    Ok(preset)
}

/// The `version` a preset's text states (1 when it states none). A text that does not parse is
/// read as version 1 here; the full parse then reports its error.
fn schema_of(text: &str) -> u32 {
    /// Only the version; every other field is skipped unread.
    #[derive(serde::Deserialize)]
    struct VersionOnly {
        #[serde(default = "one")]
        version: u32,
    }
    fn one() -> u32 {
        1
    }
    ron::Options::default()
        .from_str::<VersionOnly>(text)
        .map_or(1, |v| v.version)
}

/// RON's message, with what was expected spelled out for the common cases.
fn explain(code: &ron::Error) -> String {
    match code {
        ron::Error::NoSuchStructField {
            expected,
            found,
            outer,
        } => format!(
            "unknown field `{found}`{}; expected one of: {}",
            outer
                .as_ref()
                .map(|o| format!(" in `{o}`"))
                .unwrap_or_default(),
            expected.join(", ")
        ),
        other => other.to_string(),
    }
}

/// Best-effort line of a dotted field path (`stone.mass`) in the text: the first line naming the
/// last component after the line naming the one before it. 1-based; 1 when not found.
fn locate_field(text: &str, field: &str) -> usize {
    let mut start_line = 0;
    let parts: Vec<&str> = field.split('.').collect();
    let mut found = None;
    for part in &parts {
        // Skip axis suffixes (position.x) that are not written as fields.
        let needle = format!("{part}:");
        let hit = text
            .lines()
            .enumerate()
            .skip(start_line)
            .find(|(_, l)| {
                let l = l.split("//").next().unwrap_or("");
                l.contains(&needle)
            })
            .map(|(i, _)| i);
        if let Some(i) = hit {
            start_line = i;
            found = Some(i);
        }
    }
    found.map_or(1, |i| i + 1)
}

/// Preset as pretty RON text.
pub fn to_ron_string(preset: &Preset) -> Result<String, ron::Error> {
    let config = ron::ser::PrettyConfig::new()
        .struct_names(false)
        .indentor("    ".to_owned());
    ron::ser::to_string_pretty(preset, config)
}

/// Saves a preset atomically: write a temporary file beside the target and flush it to disk, rename
/// it over the target, then flush the folder so the rename itself is on disk. A crash or a kill at
/// any moment leaves the old file or the new one, never a mix (after a kill a hidden
/// `.NAME.tmp-PID` file may remain). On error the old file is untouched and the message says why
/// (a read-only folder, a full disk) in one line.
pub fn save(path: &Path, preset: &Preset) -> Result<(), PresetError> {
    let fail = |message: String| PresetError::Write {
        path: path.to_owned(),
        message,
    };
    preset.validate().map_err(|e| fail(e.to_string()))?;
    let text = to_ron_string(preset).map_err(|e| fail(e.to_string()))?;
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = path
        .file_name()
        .ok_or_else(|| fail("expected a file name".to_owned()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let written = (|| -> std::io::Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.write_all(b"\n")?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if let Err(e) = written {
        // Best effort: the temporary file may not exist.
        let _ = fs::remove_file(&tmp);
        return Err(fail(format!(
            "{}; the existing file, if any, is unchanged",
            io_reason(&e, dir)
        )));
    }
    sync_dir(dir).map_err(|e| {
        fail(format!(
            "the new preset replaced the old one, but the folder could not be flushed to disk: {e}"
        ))
    })
}

/// Why a write into `dir` failed, in words.
fn io_reason(e: &std::io::Error, dir: &Path) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::PermissionDenied | K::ReadOnlyFilesystem => {
            format!("the folder {} is not writable ({e})", dir.display())
        }
        K::StorageFull | K::FileTooLarge | K::QuotaExceeded => {
            format!("no room to write it: the disk is full or a file-size limit was reached ({e})")
        }
        K::NotFound => format!("the folder {} does not exist ({e})", dir.display()),
        _ => e.to_string(),
    }
}

/// Flushes a folder's entries (the rename) to disk. Where folders cannot be opened or flushed
/// (Windows, some network file systems) there is nothing more to do.
fn sync_dir(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::io::ErrorKind as K;
        match fs::File::open(dir).and_then(|d| d.sync_all()) {
            Err(e) if !matches!(e.kind(), K::InvalidInput | K::Unsupported) => return Err(e),
            _ => {}
        }
    }
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::{Physics, Rotation};

    #[test]
    fn every_shipped_preset_is_compiled_in_and_parses() {
        let files = fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/presets"))
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .path()
                    .extension()
                    .is_some_and(|x| x == "ron")
            })
            .count();
        assert_eq!(files, SHIPPED.len());
        for (stem, text) in SHIPPED {
            let from_file = load(Path::new(&format!(
                "{}/../../assets/presets/{stem}.ron",
                env!("CARGO_MANIFEST_DIR")
            )))
            .unwrap();
            assert_eq!(from_file, parse(text, Path::new(stem)).unwrap(), "{stem}");
        }
    }

    /// Every shipped preset is written in the newest schema, and says nothing a user cannot read:
    /// no issue numbers, no source paths.
    #[test]
    fn every_shipped_preset_is_version_2_in_plain_words() {
        for (stem, text) in SHIPPED {
            assert_eq!(schema_of(text), LATEST_SCHEMA, "{stem}");
            assert_eq!(parse(text, Path::new(stem)).unwrap().version, 2, "{stem}");
            assert!(!text.contains("issue") && !text.contains("src/"), "{stem}");
        }
        // The default names every field where the schemas' bases differ: it reads the same with
        // version 1's base as with its own.
        let as_v1 = with_schema(1, || {
            ron::Options::default().from_str::<Preset>(crate::sim::params::SHIPPED_DEFAULT_RON)
        })
        .unwrap();
        let as_v2 = with_schema(2, || {
            ron::Options::default().from_str::<Preset>(crate::sim::params::SHIPPED_DEFAULT_RON)
        })
        .unwrap();
        assert_eq!(as_v1, as_v2);
    }

    #[test]
    fn default_round_trips() {
        let p = Preset::version_1();
        let text = to_ron_string(&p).unwrap();
        let q = parse(&text, Path::new("x.ron")).unwrap();
        assert_eq!(p, q);
    }

    /// `Preset::default()` is the shipped default, one definition: the file as compiled in.
    #[test]
    fn the_compiled_in_default_is_valid() {
        let shipped = shipped("default").unwrap().unwrap();
        assert_eq!(Preset::default(), shipped);
        Preset::default().validate().unwrap();
        // The shipped model, not the paper's: free, smooth, buoyant, with air and memory.
        let physics = Preset::default().physics;
        assert!(physics.air.is_some() && physics.wetted_memory.is_some() && physics.buoyancy);
    }

    /// A `version: 2` preset's omitted fields are the shipped default's, part by part and inside
    /// a part; what it names replaces only that field.
    #[test]
    fn version_2_omits_to_the_shipped_default() {
        let shipped = Preset::default();
        let bare = parse("(version: 2)", Path::new("v2.ron")).unwrap();
        assert_eq!(
            bare,
            Preset {
                version: 2,
                ..shipped.clone()
            }
        );
        let text = "(\n  version: 2,\n  launch: (spin: 10.0),\n  physics: (rotation: Locked),\n)";
        let p = parse(text, Path::new("v2.ron")).unwrap();
        assert_eq!(p.launch.spin, 10.0);
        assert_eq!(p.launch.velocity, shipped.launch.velocity);
        assert_eq!(p.physics.rotation, Rotation::Locked);
        assert_eq!(
            Physics {
                rotation: shipped.physics.rotation,
                ..p.physics
            },
            shipped.physics
        );
        assert_eq!((&p.stone, &p.water), (&shipped.stone, &shipped.water));
        // The version may come last; it still decides every omitted field before it.
        let late = parse("(launch: (spin: 10.0), version: 2)", Path::new("late.ron")).unwrap();
        assert_eq!(late.physics, shipped.physics);
    }

    /// A `version: 1` preset (or one without a version) keeps its meaning: omitted fields are the
    /// model before the fidelity work, whatever the shipped default became.
    #[test]
    fn version_1_files_keep_their_meaning() {
        for text in ["()", "(version: 1)"] {
            assert_eq!(
                parse(text, Path::new("v1.ron")).unwrap(),
                Preset::version_1()
            );
        }
        let p = parse("(physics: (rotation: Free))", Path::new("v1.ron")).unwrap();
        assert_eq!(
            p.physics,
            Physics {
                rotation: Rotation::Free,
                ..Physics::version_1()
            }
        );
        assert!(p.physics.air.is_none() && p.physics.wetted_memory.is_none());
    }

    #[test]
    fn an_unknown_version_names_its_line_and_both_schemas() {
        let e = parse("(\n  name: \"x\",\n  version: 3,\n)", Path::new("v3.ron"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("v3.ron:3:"), "{e}");
        assert!(e.contains("version") && e.contains("found 3"), "{e}");
        assert!(e.contains("expected 1") && e.contains("or 2"), "{e}");
        let mut p = Preset::version_1();
        p.version = 0;
        assert!(save(&std::env::temp_dir().join("stoneskip-v0.ron"), &p).is_err());
    }

    /// A saved preset means the same under either schema: every field whose two bases differ is
    /// written, `None` included (the shipped default names a lake corner, air and a memory).
    #[test]
    fn a_saved_preset_reads_back_under_either_version() {
        let mut cases: Vec<Preset> = SHIPPED
            .iter()
            .map(|(stem, text)| parse(text, Path::new(stem)).unwrap())
            .collect();
        let mut bare = Preset::default();
        bare.water.origin = None;
        bare.physics.air = None;
        bare.physics.wetted_memory = None;
        cases.push(bare);
        cases.push(Preset::version_1());
        for p in cases {
            for version in 1..=LATEST_SCHEMA {
                let p = Preset {
                    version,
                    ..p.clone()
                };
                let text = to_ron_string(&p).unwrap();
                assert_eq!(parse(&text, Path::new("rt.ron")).unwrap(), p, "{text}");
            }
        }
    }

    #[test]
    fn design_example_parses() {
        let text = r#"(
    version: 1,
    name: "Magic angle",
    stone: (
        shape: Disk(radius: 0.05, thickness: 0.01),
        mass: 0.1,
        segments: 32,
    ),
    launch: (
        position: (0.0, 0.0, 0.3),
        velocity: (8.0, 0.0, -0.6),
        attitude: (tilt_deg: 20.0, bank_deg: 0.0, heading_deg: 0.0),
        spin: 0.0,
        angular_velocity: (0.0, 0.0, 0.0),
    ),
    physics: (
        gravity: 9.81, water_density: 1000.0,
        force_law: Rosellini,
        lift_coefficient: 0.5, friction_coefficient: 0.005,
        ventilated: true,
        integrator: Adaptive,
        tolerance: 1e-6,
        rotation: Locked,
        dt: 0.0005,
        max_time: 20.0,
    ),
    water: (
        enabled: true, wavy_contact: false,
        size: (40.0, 12.0), origin: (-2.0, -6.0), cell: 0.05, depth: 0.3,
        damping: 0.05,
        diagonal_pipes: true, limiter: MassConserving,
        swell: None,
    ),
)"#;
        let p = parse(text, Path::new("magic.ron")).unwrap();
        assert_eq!(p.name, "Magic angle");
        assert_eq!(p.water.origin, Some([-2.0, -6.0]));
        assert_eq!(p.physics.lift_coefficient, Some(0.5));
        let swell = "(water: (swell: Some((amplitude: 0.02, wavelength: 3.0, heading_deg: 90.0))))";
        let q = parse(swell, Path::new("s.ron")).unwrap();
        assert!(q.water.swell.is_some());
    }

    #[test]
    fn unknown_field_names_line_and_field() {
        let text = "(\n  stone: (\n    mass: 0.1,\n    colour: 3,\n  ),\n)";
        let e = parse(text, Path::new("bad.ron")).unwrap_err().to_string();
        assert!(e.starts_with("bad.ron:4:"), "{e}");
        assert!(e.contains("colour"), "{e}");
        assert!(e.contains("expected one of"), "{e}");
    }

    #[test]
    fn negative_mass_names_line_and_field() {
        let text = "(\n  name: \"x\",\n  stone: (\n    mass: -0.1,\n  ),\n)";
        let e = parse(text, Path::new("neg.ron")).unwrap_err().to_string();
        assert!(e.starts_with("neg.ron:4:"), "{e}");
        assert!(e.contains("stone.mass"), "{e}");
        assert!(e.contains("expected a positive number"), "{e}");
    }

    /// The water's precision parses and round-trips; `pressure_centre: Faces` and `near_field:
    /// Columns` (which every preset saved before they were folded away names) still parse, mean
    /// what leaving them out means, and are not written back.
    #[test]
    fn pressure_centre_and_precision_parse() {
        let text = "(\n  physics: (rotation: Free, pressure_centre: Faces),\n  water: (precision: F64, near_field: Columns),\n)";
        let p = parse(text, Path::new("ok.ron")).unwrap();
        let without = "(\n  physics: (rotation: Free),\n  water: (precision: F64),\n)";
        assert_eq!(p, parse(without, Path::new("ok.ron")).unwrap());
        assert_eq!(p.water.precision, crate::sim::params::Precision::F64);
        let written = to_ron_string(&p).unwrap();
        assert!(!written.contains("pressure_centre") && !written.contains("near_field"));
        let back = parse(&written, Path::new("rt.ron")).unwrap();
        assert_eq!(back, p);
    }

    /// A retired value gets one message: its file and line, the field, that it is retired, what
    /// to write instead and where its results are.
    #[test]
    fn a_retired_value_says_so_and_where_its_results_are() {
        for (text, field, value, instead) in [
            (
                "(\n  name: \"old\",\n  physics: (\n    pressure_centre: Planing(0.75),\n  ),\n)",
                "physics.pressure_centre",
                "Planing",
                "leave the field out",
            ),
            (
                "(\n  name: \"old\",\n  physics: (\n    axial_spin: Smooth,\n  ),\n)",
                "physics.axial_spin",
                "Smooth",
                "write Resal",
            ),
            (
                "(\n  name: \"old\",\n  water: (\n    near_field: Spectral,\n  ),\n)",
                "water.near_field",
                "Spectral",
                "leave the field out",
            ),
        ] {
            let e = parse(text, Path::new("old.ron")).unwrap_err().to_string();
            assert!(e.starts_with("old.ron:4:"), "{e}");
            assert!(e.contains(&format!("`{field}: {value}` is retired")), "{e}");
            assert!(e.contains(instead), "{e}");
            assert!(e.contains("docs/studies/retired.md"), "{e}");
        }
    }

    /// A preset saved before the retirements still loads: it names `pressure_centre: Faces`,
    /// `near_field: Columns` and the spectral patch's settings, which are read and ignored (and
    /// not written again).
    #[test]
    fn a_preset_saved_before_the_retirements_still_loads() {
        let text = "(\n  version: 1,\n  physics: (pressure_centre: Faces, axial_spin: Resal),\n  \
                    water: (near_field: Columns, spectral: (cells: 128, cell: 0.01, \
                    surface_tension: 0.0728, viscosity: 1e-6)),\n)";
        let p = parse(text, Path::new("saved.ron")).unwrap();
        assert_eq!(
            p,
            Preset {
                physics: Physics {
                    axial_spin: crate::sim::params::AxialSpin::Resal,
                    ..Physics::version_1()
                },
                ..Preset::version_1()
            }
        );
        assert!(!to_ron_string(&p).unwrap().contains("spectral"));
    }

    /// The page a retired value's message points to exists and keeps that value's results.
    #[test]
    fn each_retired_value_has_its_results_written() {
        let page = fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../docs/studies/retired.md"
        ))
        .unwrap();
        for heading in [
            "## `physics.axial_spin: Smooth`",
            "## `physics.pressure_centre: Planing(f)`",
            "## `water.near_field: Spectral`",
        ] {
            assert!(page.contains(heading), "{heading}");
        }
        assert!(page.contains("research-variants-before-retirement"));
    }

    /// `physics.steps_across_ticks` (numerics): omitted in a version-1 preset it is false; it is
    /// always written (the shipped default sets it, so a version-2 file needs `false` spelled
    /// out); when named it round-trips.
    #[test]
    fn steps_across_ticks_round_trips() {
        let p = Preset::version_1();
        assert!(!p.physics.steps_across_ticks);
        assert!(to_ron_string(&p)
            .unwrap()
            .contains("steps_across_ticks: false"));
        let text = "(\n  physics: (steps_across_ticks: true),\n)";
        let q = parse(text, Path::new("across.ron")).unwrap();
        assert!(q.physics.steps_across_ticks);
        let written = to_ron_string(&q).unwrap();
        assert!(written.contains("steps_across_ticks: true"), "{written}");
        assert_eq!(parse(&written, Path::new("rt.ron")).unwrap(), q);
    }

    /// `stone.quadrature` (numerics): omitted in a version-1 preset it is `Faces`; it is always
    /// written (the shipped lenses are smooth); a smooth lens is refused, with the field named,
    /// with a faceted spin or out-of-range nodes; wavy contact and a disk take it.
    #[test]
    fn quadrature_round_trips_and_is_refused_where_it_cannot_apply() {
        let p = Preset::version_1();
        assert!(p.stone.quadrature.is_faces());
        assert!(to_ron_string(&p).unwrap().contains("quadrature: Faces"));
        let flat = "(\n  stone: (quadrature: Smooth(meridian: 16, around: 6)),\n  water: (wavy_contact: false),\n)";
        let q = parse(flat, Path::new("smooth.ron")).unwrap();
        assert_eq!(
            q.stone.quadrature,
            crate::sim::params::Quadrature::Smooth {
                meridian: 16,
                around: 6
            }
        );
        let written = to_ron_string(&q).unwrap();
        assert!(written.contains("quadrature: Smooth("), "{written}");
        assert_eq!(parse(&written, Path::new("rt.ron")).unwrap(), q);
        let refused = |text: &str, field: &str| {
            let e = parse(text, Path::new("bad.ron")).unwrap_err().to_string();
            assert!(e.starts_with("bad.ron:") && e.contains(field), "{e}");
        };
        let smooth = "quadrature: Smooth(meridian: 16, around: 6)";
        // Wavy contact is allowed: there the mesh's faces carry the load.
        let wavy =
            format!("(\n  stone: ({smooth}),\n  water: (enabled: true, wavy_contact: true),\n)");
        assert!(parse(&wavy, Path::new("wavy.ron")).is_ok());
        // A disk takes it too: there the faces carry the load (`Stone::new`).
        let disk =
            format!("(\n  stone: (shape: Disk(radius: 0.05, thickness: 0.01), {smooth}),\n)");
        assert!(parse(&disk, Path::new("disk.ron")).is_ok());
        refused(
            "(\n  stone: (quadrature: Smooth(meridian: 1, around: 6)),\n)",
            "stone.quadrature.meridian",
        );
        refused(
            &format!(
                "(\n  stone: ({smooth}),\n  physics: (rotation: Free, axial_spin: Faceted),\n  \
                 water: (wavy_contact: false),\n)"
            ),
            "physics.axial_spin",
        );
    }

    #[test]
    fn save_is_atomic_and_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.ron");
        let p = Preset {
            name: "saved".into(),
            ..Preset::version_1()
        };
        save(&path, &p).unwrap();
        assert_eq!(load(&path).unwrap(), p);
        // An invalid preset is refused and the old file is kept intact.
        let mut bad = p.clone();
        bad.stone.mass = f64::NAN;
        assert!(save(&path, &bad).is_err());
        assert_eq!(load(&path).unwrap(), p);
        let leftovers = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(leftovers, 1, "no temporary files left behind");
    }
}
