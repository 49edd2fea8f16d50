//! Scene files from the app: Open and Save (a typed path on the desktop, the file picker and a download
//! in a web page), and the files a web page's picker has read.

use super::{Notice, RaylabApp};
use crate::scene::Scene;

/// The open or save dialog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Dialog {
    Open,
    Save,
}

impl RaylabApp {
    pub(super) fn dialog_ui(&mut self, ctx: &egui::Context) {
        let Some(dialog) = self.dialog else {
            return;
        };
        let title = match dialog {
            Dialog::Open => "Open scene",
            Dialog::Save => "Save scene as",
        };
        let mut open = true;
        let mut done = false;
        egui::Window::new(title)
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .show(ctx, |ui| {
                let label = ui.label("Path of a .ron scene file:");
                ui.add(egui::TextEdit::singleline(&mut self.state.scene_path).desired_width(420.0))
                    .labelled_by(label.id);
                let action = match dialog {
                    Dialog::Open => "Open",
                    Dialog::Save => "Save",
                };
                ui.horizontal(|ui| {
                    if ui.button(action).clicked() {
                        self.notice = Some(self.run_dialog(dialog));
                        done = true;
                    }
                    done |= self.browse_ui(ui, dialog);
                });
            });
        if !open || done {
            self.dialog = None;
            // A native dialog still open answers nobody now.
            #[cfg(not(target_arch = "wasm32"))]
            {
                self.browsing = None;
            }
        }
    }

    /// The Browse… button that opens the desktop's own dialog, and its answer: a chosen file is
    /// opened or saved at once (true: raylab's dialog is done). Without a native dialog the typed
    /// path stays, with a note.
    #[cfg(not(target_arch = "wasm32"))]
    fn browse_ui(&mut self, ui: &mut egui::Ui, dialog: Dialog) -> bool {
        use super::native_dialog::{Answer, Browsing};
        if let Some(answer) = self.browsing.as_mut().and_then(Browsing::answer) {
            self.browsing = None;
            match answer {
                Answer::Chosen(path) => {
                    self.state.scene_path = path.display().to_string();
                    self.notice = Some(self.run_dialog(dialog));
                    return true;
                }
                Answer::Cancelled => {}
                Answer::Unavailable => {
                    self.notice = Some(Notice::error(
                        "No system file dialog here: type the path instead",
                    ));
                }
            }
        }
        let browsing = self.browsing.is_some();
        let button = ui
            .add_enabled(!browsing, egui::Button::new("Browse…"))
            .on_hover_text("Choose the file in the system's own file dialog")
            .on_disabled_hover_text("The system's file dialog is open");
        if button.clicked() {
            let name = self
                .current_scene()
                .map_or_else(|| "scene.ron".into(), |scene| file_name(&scene.title));
            let ctx = ui.ctx().clone();
            self.browsing = Browsing::start(
                dialog == Dialog::Save,
                &self.state.scene_path,
                &name,
                move || ctx.request_repaint(),
            );
        }
        false
    }

    #[cfg(target_arch = "wasm32")]
    fn browse_ui(&mut self, _ui: &mut egui::Ui, _dialog: Dialog) -> bool {
        false
    }

    /// File → Open: the path dialog on the desktop, the browser's file picker on the web.
    pub(super) fn open_scene(&mut self, ctx: &egui::Context) {
        if crate::platform::TYPED_PATHS {
            self.dialog = Some(Dialog::Open);
            return;
        }
        let ctx = ctx.clone();
        if let Err(error) =
            crate::platform::pick_file(".ron", &self.inbox, move || ctx.request_repaint())
        {
            self.notice = Some(Notice::error(format!(
                "Could not open the file picker: {error}"
            )));
        }
    }

    /// File → Save: the path dialog on the desktop, a download on the web.
    pub(super) fn save_scene(&mut self) {
        if crate::platform::TYPED_PATHS {
            self.dialog = Some(Dialog::Save);
            return;
        }
        self.notice = Some(match self.current_scene() {
            Some(scene) => {
                let name = file_name(&scene.title);
                match crate::platform::download(&name, &scene.to_ron()) {
                    Ok(()) => Notice::info(format!("Downloaded {name}")),
                    Err(error) => Notice::error(format!("Could not save: {error}")),
                }
            }
            None => no_scene_to_save(),
        });
    }

    /// Loads the scene files the web's file picker has read.
    pub(super) fn receive_files(&mut self) {
        for file in self.inbox.take() {
            self.notice = Some(
                match file.map_err(|e| e.to_string()).and_then(|(name, text)| {
                    let scene = Scene::from_ron(&text, &name).map_err(|error| error.to_string())?;
                    self.load_scene(&scene)
                        .map_err(|error| format!("{name}: {error}"))?;
                    Ok(name)
                }) {
                    Ok(name) => Notice::info(format!("Opened {name}")),
                    Err(error) => Notice::error(format!(
                        "Could not open: {error} (the current scene is kept)"
                    )),
                },
            );
        }
    }

    /// Opens or saves the scene at the dialog's path; the current scene is kept if opening fails.
    pub fn run_dialog_path(&mut self, save: bool) -> Notice {
        self.run_dialog(if save { Dialog::Save } else { Dialog::Open })
    }

    pub(super) fn run_dialog(&mut self, dialog: Dialog) -> Notice {
        let path = std::path::PathBuf::from(self.state.scene_path.trim());
        match dialog {
            Dialog::Open => match Scene::load(&path)
                .map_err(|e| e.to_string())
                .and_then(|scene| {
                    let folder = path.parent().map(|f| f.display().to_string());
                    self.load_scene_from(&scene, folder)
                        .map_err(|e| format!("{}: {e}", path.display()))
                }) {
                Ok(()) => Notice {
                    text: format!("Opened {}", path.display()),
                    error: false,
                    view: Some(self.state.view),
                },
                Err(error) => Notice::error(format!(
                    "Could not open: {error} (the current scene is kept)"
                )),
            },
            Dialog::Save => match self.current_scene().map(|scene| scene.save(&path)) {
                Some(Ok(())) => Notice::info(format!("Saved {}", path.display())),
                Some(Err(error)) => {
                    Notice::error(format!("Could not save {}: {error}", path.display()))
                }
                None => no_scene_to_save(),
            },
        }
    }
}

/// The notice when the open view has no scene (the Accuracy view).
pub(super) fn no_scene_to_save() -> Notice {
    Notice::error("Open a Segments, Triangle, Parallelogram or Render view to save its scene")
}

/// A file name for a scene, from its title: `Seed 000: the lecture triangle` →
/// `seed-000-the-lecture-triangle.ron`.
pub(super) fn file_name(title: &str) -> String {
    let words: Vec<String> = title
        .split(|c: char| !c.is_alphanumeric())
        .filter(|word| !word.is_empty())
        .map(str::to_lowercase)
        .collect();
    if words.is_empty() {
        "raylab-scene.ron".into()
    } else {
        format!("{}.ron", words.join("-"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_file_names_come_from_titles() {
        assert_eq!(
            file_name("Seed 000: the lecture triangle"),
            "seed-000-the-lecture-triangle.ron"
        );
        assert_eq!(file_name("  "), "raylab-scene.ron");
    }
}
