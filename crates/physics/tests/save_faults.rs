//! Save faults (issue 14): a preset save killed with SIGKILL at a random moment leaves the old file
//! or the new one, never a torn one — tested on a real process, many times; a read-only folder and
//! a full disk give one clear message and lose nothing.
//!
//! The child processes are this test binary itself, re-run on the ignored test `child` with
//! `STONESKIP_SAVE_CHILD` set: `loop` saves two different presets in turn for ever, `once` saves one
//! and prints the error. Run more kills with `STONESKIP_SAVE_KILLS=2000 cargo test --test save_faults`.

// Test code: a failed unwrap is the failure report (the libraries may not unwrap).
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![cfg(unix)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use stoneskip_physics::preset;
use stoneskip_physics::sim::params::{Preset, Shape};

/// Two presets whose texts differ in length and content, so any mix of them is detectable.
fn presets() -> (Preset, Preset) {
    let a = Preset {
        name: "old".into(),
        ..Preset::version_1()
    };
    let mut b = Preset {
        name:
            "new preset with a much longer name, so that the two files have different lengths and \
               a file cut short or mixed from both can never parse as either"
                .into(),
        ..Preset::version_1()
    };
    b.stone.shape = Shape::Disk {
        radius: 0.04,
        thickness: 0.007,
    };
    b.water.swell = None;
    (a, b)
}

/// The bytes `preset::save` writes for `p`.
fn file_bytes(p: &Preset) -> Vec<u8> {
    let mut t = preset::to_ron_string(p).unwrap().into_bytes();
    t.push(b'\n');
    t
}

/// The child side: runs only when the parent sets `STONESKIP_SAVE_CHILD`.
#[test]
#[ignore = "a child process of the save-fault tests"]
fn child() {
    let Ok(mode) = std::env::var("STONESKIP_SAVE_CHILD") else {
        return;
    };
    let path = PathBuf::from(std::env::var("STONESKIP_SAVE_PATH").unwrap());
    let (a, b) = presets();
    match mode.as_str() {
        "loop" => {
            // Tell the parent the loop has started, then save for ever. (The leading newline ends
            // the harness's "test child ... " line.)
            println!("\nsaving");
            loop {
                for p in [&b, &a] {
                    preset::save(&path, p).unwrap();
                }
            }
        }
        "once" => match preset::save(&path, &b) {
            Ok(()) => println!("\nSAVED"),
            Err(e) => println!("\nERROR {e}"),
        },
        other => panic!("unknown child mode {other}"),
    }
}

/// This test binary, re-run on `child` in `mode`, saving to `path`.
fn child_command(mode: &str, path: &Path) -> Command {
    let mut c = Command::new(std::env::current_exe().unwrap());
    c.args([
        "child",
        "--exact",
        "--ignored",
        "--nocapture",
        "--test-threads=1",
    ])
    .env("STONESKIP_SAVE_CHILD", mode)
    .env("STONESKIP_SAVE_PATH", path);
    c
}

/// Deterministic numbers in [0, 1) (SplitMix64), for the kill moments.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Kills a saving child with SIGKILL at random moments; after every kill the preset is exactly the
/// old file or the new one. Counts how often the kill left the temporary file behind (the kill came
/// between creating it and the rename), to show the kills do land inside saves.
#[test]
fn sigkill_during_save_leaves_the_old_or_the_new_file() {
    let kills: usize = std::env::var("STONESKIP_SAVE_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let path = dir.path().join("thrown.ron");
    let (a, b) = presets();
    let (old, new) = (file_bytes(&a), file_bytes(&b));
    preset::save(&path, &a).unwrap();
    let mut rng = Rng(14);
    let (mut seen_old, mut seen_new, mut torn, mut mid_save) = (0, 0, 0, 0);
    let started = Instant::now();
    for _ in 0..kills {
        let mut child = child_command("loop", &path)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // Wait for the loop to start, then kill it 0–20 ms later.
        let stdout = child.stdout.take().unwrap();
        let started_saving = BufReader::new(stdout)
            .lines()
            .any(|l| l.is_ok_and(|l| l == "saving"));
        assert!(started_saving, "the child did not start");
        std::thread::sleep(Duration::from_secs_f64(0.02 * rng.next()));
        child.kill().unwrap(); // SIGKILL on Unix
        child.wait().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        if bytes == old {
            seen_old += 1;
        } else if bytes == new {
            seen_new += 1;
        } else {
            torn += 1;
        }
        // Temporary files left by the kill; removed so each round starts clean.
        for e in std::fs::read_dir(dir.path()).unwrap() {
            let e = e.unwrap();
            if e.file_name()
                .to_string_lossy()
                .starts_with(".thrown.ron.tmp-")
            {
                mid_save += 1;
                std::fs::remove_file(e.path()).unwrap();
            }
        }
    }
    println!(
        "{kills} SIGKILLs in {:.1} s: old file {seen_old}, new file {seen_new}, torn {torn}; \
         {mid_save} kills landed between the temporary file's creation and the rename",
        started.elapsed().as_secs_f64()
    );
    assert_eq!(torn, 0, "torn files");
    assert_eq!(seen_old + seen_new, kills);
    // The kills did land at different points: both files were seen, and some kills caught a save
    // in the middle.
    assert!(seen_old > 0 && seen_new > 0, "{seen_old} / {seen_new}");
    assert!(mid_save > 0, "no kill landed inside a save");
    assert_eq!(preset::load(&path).map(|_| ()).ok(), Some(()));
}

/// Runs a `once` child under `sh -c SCRIPT` (the script ends by exec'ing the child, "$@"); returns
/// its output line.
fn once_under(script: &str, path: &Path) -> String {
    let child = child_command("once", path);
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("{script} \"$@\""))
        .arg("sh")
        .arg(child.get_program())
        .args(child.get_args())
        .envs(child.get_envs().filter_map(|(k, v)| Some((k, v?))))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.lines()
        .find(|l| l.starts_with("ERROR") || l.starts_with("SAVED"))
        .unwrap_or_else(|| {
            panic!(
                "no result from the child: {text}\n{}",
                String::from_utf8_lossy(&out.stderr)
            )
        })
        .to_owned()
}

/// Whether this process may mount in its own mount namespace (root, `unshare` present).
fn can_mount() -> bool {
    Command::new("unshare")
        .args(["-m", "sh", "-c", "mount -t tmpfs -o size=16k tmpfs /mnt"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Asserts a failed save's message is one clear line naming the file and the cause, and that the
/// old file is intact with no temporary file left.
fn assert_refused(line: &str, path: &Path, old: &[u8], cause: &str) {
    println!("{line}");
    assert!(line.starts_with("ERROR "), "the save should fail: {line}");
    assert!(line.contains(&path.display().to_string()), "{line}");
    assert!(line.contains(cause), "{line}");
    assert!(line.contains("unchanged"), "{line}");
    assert_eq!(std::fs::read(path).unwrap(), old, "the old file is intact");
    let dir = path.parent().unwrap();
    let n = std::fs::read_dir(dir).unwrap().count();
    assert_eq!(n, 1, "no temporary file left in {}", dir.display());
}

/// A read-only folder: the save fails with a message naming the folder, the old file stays. Root
/// ignores permission bits, so as root the folder is made read-only by a read-only bind mount in a
/// private mount namespace.
#[test]
fn read_only_folder_is_refused_clearly_and_keeps_the_old_file() {
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let sub = dir.path().join("ro");
    std::fs::create_dir(&sub).unwrap();
    let path = sub.join("thrown.ron");
    let (a, _) = presets();
    preset::save(&path, &a).unwrap();
    let old = file_bytes(&a);
    let d = sub.display().to_string();
    let is_root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.starts_with(b"0\n"));
    let line = if !is_root {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&sub, std::fs::Permissions::from_mode(0o555)).unwrap();
        let line = once_under("exec", &path);
        std::fs::set_permissions(&sub, std::fs::Permissions::from_mode(0o755)).unwrap();
        line
    } else if can_mount() {
        let script = format!(
            "exec unshare -m sh -c 'mount --bind {d} {d} && mount -o remount,bind,ro {d} && exec \"$0\" \"$@\"'"
        );
        once_under(&script, &path)
    } else {
        println!("skipped: running as root without a private mount namespace");
        return;
    };
    assert_refused(&line, &path, &old, "is not writable");
}

/// A full disk: a 16 KiB tmpfs filled to the brim (as root, in a private mount namespace), and,
/// anywhere, a file-size limit (`ulimit -f`, with SIGXFSZ ignored so the write fails with EFBIG
/// instead of killing the process). Both give one clear message and keep the old file.
#[test]
fn full_disk_is_refused_clearly_and_keeps_the_old_file() {
    let (a, _) = presets();
    let old = file_bytes(&a);
    // A file-size limit of 1 block (512 or 1024 bytes), below the new preset's size.
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let sub = dir.path().join("limited");
    std::fs::create_dir(&sub).unwrap();
    let path = sub.join("thrown.ron");
    preset::save(&path, &a).unwrap();
    let line = once_under("ulimit -f 1 && trap '' XFSZ && exec", &path);
    assert_refused(&line, &path, &old, "no room to write it");
    // A really full file system.
    if !can_mount() {
        println!("full tmpfs: skipped (needs root and unshare)");
        return;
    }
    let mnt = dir.path().join("full");
    std::fs::create_dir(&mnt).unwrap();
    let path = mnt.join("thrown.ron");
    let m = mnt.display().to_string();
    // Mount, save the old preset (by copying its bytes), fill the rest, then run the child.
    let old_file = dir.path().join("old.ron");
    std::fs::write(&old_file, &old).unwrap();
    let script = format!(
        "exec unshare -m sh -c 'mount -t tmpfs -o size=16k tmpfs {m} && cp {o} {p} && \
         (dd if=/dev/zero of={m}/filler bs=1k count=64 2>/dev/null; true) && \
         \"$0\" \"$@\"; echo; cat {p} | cmp -s - {o} && echo KEPT; ls -A {m}'",
        o = old_file.display(),
        p = path.display()
    );
    let child = child_command("once", &path);
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("{script} \"$@\""))
        .arg("sh")
        .arg(child.get_program())
        .args(child.get_args())
        .envs(child.get_envs().filter_map(|(k, v)| Some((k, v?))))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("ERROR") || l.starts_with("SAVED"));
    println!("{text}");
    let line = line.unwrap_or("no result");
    assert!(line.starts_with("ERROR "), "{text}");
    assert!(line.contains("no room to write it"), "{line}");
    assert!(line.contains("unchanged"), "{line}");
    assert!(
        text.lines().any(|l| l == "KEPT"),
        "the old file is intact: {text}"
    );
    // Only the old file and the filler remain (the temporary file was removed).
    let names: Vec<&str> = text.lines().skip_while(|l| *l != "KEPT").skip(1).collect();
    assert_eq!(names, ["filler", "thrown.ron"], "{text}");
}
