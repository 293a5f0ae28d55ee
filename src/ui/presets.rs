//! Presets: the shipped ones (`assets/presets/*.ron`) and the user's own (in the user's config
//! directory); load one, save the current settings under a name (atomically), replay the last throw.

use std::path::{Path, PathBuf};

use egui::Ui;

use super::{message_ui, Action, Message};

/// The presets on disk and the panel's own state.
#[derive(Debug, Clone, Default)]
pub struct PresetLibrary {
    pub shipped_dir: Option<PathBuf>,
    pub user_dir: Option<PathBuf>,
    pub shipped: Vec<PathBuf>,
    pub user: Vec<PathBuf>,
    /// Name typed for "Save as".
    pub save_name: String,
    /// A path typed for "Open file".
    pub open_path: String,
    /// The file the current settings came from.
    pub current: Option<PathBuf>,
    pub message: Option<Message>,
}

impl PresetLibrary {
    /// Finds the shipped presets (beside the working directory, the executable, or the source tree)
    /// and the user's directory (the platform's config folder: on Linux
    /// `$XDG_CONFIG_HOME/stoneskip/presets` or `~/.config/stoneskip/presets`).
    pub fn discover() -> Self {
        let mut lib = Self {
            shipped_dir: shipped_dir(),
            user_dir: user_dir(),
            ..Self::default()
        };
        lib.refresh();
        lib
    }

    /// Re-reads both directories.
    pub fn refresh(&mut self) {
        self.shipped = self
            .shipped_dir
            .as_deref()
            .map(list_ron)
            .unwrap_or_default();
        self.user = self.user_dir.as_deref().map(list_ron).unwrap_or_default();
    }

    /// The file a name is saved to in the user's directory.
    pub fn user_path(&self, name: &str) -> Option<PathBuf> {
        let stem = file_stem_for(name);
        if stem.is_empty() {
            return None;
        }
        self.user_dir
            .as_ref()
            .map(|d| d.join(format!("{stem}.ron")))
    }
}

fn list_ron(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|it| {
            it.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "ron"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

fn shipped_dir() -> Option<PathBuf> {
    let rel = Path::new("assets").join("presets");
    let mut candidates = vec![rel.clone()];
    if let Ok(exe) = std::env::current_exe() {
        for dir in exe.ancestors().skip(1).take(4) {
            candidates.push(dir.join(&rel));
        }
    }
    candidates.push(Path::new(env!("CARGO_MANIFEST_DIR")).join(&rel));
    candidates.into_iter().find(|p| p.is_dir())
}

/// The user's presets: the platform's config folder for stoneskip (`directories`; on Linux
/// `$XDG_CONFIG_HOME/stoneskip` or `~/.config/stoneskip`), `presets` inside it.
fn user_dir() -> Option<PathBuf> {
    directories::ProjectDirs::from("", "", "stoneskip").map(|p| p.config_dir().join("presets"))
}

/// A file name from a preset name: letters, digits, '-' and '_' kept, the rest as '_'.
pub fn file_stem_for(name: &str) -> String {
    let s: String = name
        .trim()
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    s.trim_matches('_').chars().take(64).collect()
}

fn preset_list(ui: &mut Ui, files: &[PathBuf], current: Option<&Path>, actions: &mut Vec<Action>) {
    for p in files {
        let name = p
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let selected = current == Some(p.as_path());
        if ui
            .selectable_label(selected, name)
            .on_hover_text(p.display().to_string())
            .clicked()
        {
            actions.push(Action::LoadPreset(p.clone()));
        }
    }
}

/// The presets panel.
pub fn presets_ui(
    ui: &mut Ui,
    lib: &mut PresetLibrary,
    can_replay: bool,
    actions: &mut Vec<Action>,
) {
    ui.label("Shipped");
    ui.indent("shipped", |ui| {
        if lib.shipped.is_empty() {
            ui.weak("none found (assets/presets)");
        }
        preset_list(ui, &lib.shipped, lib.current.as_deref(), actions);
    });
    ui.label("Yours").on_hover_text(
        lib.user_dir
            .as_ref()
            .map_or("no user directory (HOME unset)".to_owned(), |d| {
                d.display().to_string()
            }),
    );
    ui.indent("user", |ui| {
        if lib.user.is_empty() {
            ui.weak("none saved yet");
        }
        preset_list(ui, &lib.user, lib.current.as_deref(), actions);
    });
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut lib.save_name)
                .hint_text("name")
                .desired_width(140.0),
        );
        let ok = lib.user_path(&lib.save_name).is_some();
        if ui
            .add_enabled(ok, egui::Button::new("Save as"))
            .on_hover_text("Saves the current settings in your presets (atomically)")
            .clicked()
        {
            actions.push(Action::SavePresetAs(lib.save_name.clone()));
        }
    });
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut lib.open_path)
                .hint_text("path/to/preset.ron")
                .desired_width(140.0),
        );
        if ui
            .add_enabled(!lib.open_path.trim().is_empty(), egui::Button::new("Open"))
            .clicked()
        {
            actions.push(Action::LoadPreset(PathBuf::from(lib.open_path.trim())));
        }
    });
    ui.horizontal(|ui| {
        if ui.button("Rescan").clicked() {
            actions.push(Action::RefreshPresets);
        }
        if ui
            .add_enabled(can_replay, egui::Button::new("Replay last throw"))
            .on_hover_text(
                "Runs the last throw again exactly (the same preset, the same live changes)",
            )
            .clicked()
        {
            actions.push(Action::Replay);
        }
    });
    if let Some(m) = &lib.message {
        message_ui(ui, m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_stems_are_safe() {
        assert_eq!(file_stem_for("My throw #2"), "my_throw__2");
        assert_eq!(file_stem_for("../etc/passwd"), "etc_passwd");
        assert_eq!(file_stem_for("  "), "");
    }
}
