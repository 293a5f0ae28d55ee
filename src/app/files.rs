//! Where the app writes: exports and screenshots go to the user's own folders (the `directories`
//! crate: the Pictures or Documents folder's `stoneskip`, else the platform's data folder), never
//! the working directory, named after the preset and the date and time (UTC); `STONESKIP_OUTPUT_DIR`
//! overrides the folder. The trajectory CSV opens with comment lines naming the preset and the
//! units of every column.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result};

use crate::report::CsvWriter;
use crate::ui::file_stem_for;
use stoneskip_physics::sim::{Simulation, StepSample};

/// The folder for exports: `overridden`, else `~/Pictures/stoneskip` (or Documents), else the
/// platform's data folder for stoneskip, else the home folder, else the temporary folder.
pub fn output_dir(overridden: Option<&Path>) -> PathBuf {
    if let Some(d) = overridden {
        return d.to_owned();
    }
    if let Some(u) = directories::UserDirs::new() {
        if let Some(d) = u.picture_dir().or_else(|| u.document_dir()) {
            return d.join("stoneskip");
        }
    }
    if let Some(p) = directories::ProjectDirs::from("", "", "stoneskip") {
        return p.data_dir().join("exports");
    }
    directories::BaseDirs::new()
        .map(|b| b.home_dir().join("stoneskip"))
        .unwrap_or_else(|| std::env::temp_dir().join("stoneskip"))
}

/// `dir/<preset>-<YYYY-MM-DD_HH-MM-SS>Z.<ext>`, with `-2`, `-3`, … when that name is taken.
pub fn output_path(dir: &Path, preset_name: &str, ext: &str) -> PathBuf {
    let stem = match file_stem_for(preset_name) {
        s if s.is_empty() => "throw".to_owned(),
        s => s,
    };
    let base = format!("{stem}-{}", utc_stamp(unix_secs()));
    let mut path = dir.join(format!("{base}.{ext}"));
    let mut n = 2;
    while path.exists() && n < 1000 {
        path = dir.join(format!("{base}-{n}.{ext}"));
        n += 1;
    }
    path
}

fn unix_secs() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64)
}

/// "2026-12-01_17-42-05Z" for a Unix time (civil-from-days, H. Hinnant).
pub fn utc_stamp(secs: i64) -> String {
    let days = secs.div_euclid(86_400);
    let rem = secs.rem_euclid(86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}_{:02}-{:02}-{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The comment lines above the CSV's header row: the preset and each column's unit.
pub fn csv_preamble(preset_name: &str) -> String {
    format!(
        "# stoneskip trajectory of the preset \"{}\"\n\
         # units: t s; x y z m (centre of mass, z up, water at rest z = 0); vx vy vz m/s; \
         qw qx qy qz stone-to-world unit quaternion; wx wy wz rad/s (world); in_contact 0/1; \
         wetted_area m^2; fx fy fz N (water on stone)\n",
        preset_name.replace(['\n', '"'], " ")
    )
}

/// Creates (or truncates) the file at `path`, creating its folder first; the error names the path.
pub fn create_file(path: &Path) -> Result<std::io::BufWriter<std::fs::File>> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    Ok(std::io::BufWriter::new(file))
}

/// Writes the run's samples as CSV to `path` (creating the folder).
pub fn write_csv(path: &Path, sim: &Simulation, samples: &[StepSample]) -> Result<()> {
    let mut out = create_file(path)?;
    out.write_all(csv_preamble(&sim.preset().name).as_bytes())?;
    let mut w = CsvWriter::new(out, sim)?;
    let mut it = samples.iter();
    if let Some(first) = it.next() {
        w.start(first)?;
    }
    for s in it {
        w.step(s)?;
    }
    w.finish()?.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamps_are_utc_dates() {
        assert_eq!(utc_stamp(0), "1970-01-01_00-00-00Z");
        assert_eq!(utc_stamp(951_782_400), "2000-02-29_00-00-00Z");
        assert_eq!(utc_stamp(1_796_146_925), "2026-12-01_17-42-05Z");
    }

    #[test]
    fn files_go_to_the_users_folder_named_after_the_preset() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(output_dir(Some(dir.path())), dir.path());
        // Never the working directory.
        let cwd = std::env::current_dir().unwrap();
        assert_ne!(output_dir(None), cwd);
        assert!(output_dir(None).is_absolute());
        let p = output_path(dir.path(), "Magic angle", "csv");
        assert_eq!(p.parent(), Some(dir.path()));
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        assert!(name.starts_with("magic_angle-20"), "{name}");
        assert!(name.ends_with("Z.csv"), "{name}");
        // A second export in the same second gets its own name.
        std::fs::write(&p, "x").unwrap();
        assert_ne!(output_path(dir.path(), "Magic angle", "csv"), p);
    }

    #[test]
    fn the_csv_names_the_preset_and_its_units() {
        let dir = tempfile::tempdir().unwrap();
        let mut preset = stoneskip_physics::sim::params::Preset::version_1();
        preset.water.enabled = false;
        let mut sim = Simulation::new(&preset).unwrap();
        let mut samples = Vec::new();
        for _ in 0..20 {
            sim.tick_with(&mut |s| samples.push(*s));
        }
        let path = dir.path().join("sub").join("t.csv");
        write_csv(&path, &sim, &samples).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines = text.lines();
        assert!(lines.next().unwrap().contains("\"Default throw\""));
        let units = lines.next().unwrap();
        for u in ["t s", "m/s", "rad/s", "m^2", "N"] {
            assert!(units.contains(u), "{units}");
        }
        assert!(lines.next().unwrap().starts_with("t,"));
        assert!(text.lines().count() >= 20);
    }
}
