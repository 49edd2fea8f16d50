//! The desktop's own Open and Save dialogs (rfd: the XDG desktop portal on Linux, else zenity; the
//! system's dialogs on Windows and macOS), run on a thread of their own so the window keeps drawing.
//! Where neither can open (no session bus for the portal, no zenity on a display: a bare X server,
//! a classroom machine without a desktop, CI) none is tried, and raylab's own typed path stays the
//! way to name a file.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// What a native dialog said.
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    /// The file chosen.
    Chosen(PathBuf),
    /// Closed without a choice.
    Cancelled,
    /// No native dialog could be opened here.
    Unavailable,
}

/// A native dialog on its thread; [`Browsing::answer`] is `None` until it is closed.
pub struct Browsing {
    slot: Arc<Mutex<Option<Answer>>>,
}

impl Browsing {
    /// Opens the native dialog to open (`save` false) or save a `.ron` scene, starting in the folder
    /// of `current` (the typed path) and, to save, suggesting `file_name`; `wake` is called when it
    /// closes. `None` where no thread can be started.
    pub fn start(
        save: bool,
        current: &str,
        file_name: &str,
        wake: impl Fn() + Send + 'static,
    ) -> Option<Browsing> {
        if !can_open() {
            let slot = Arc::new(Mutex::new(Some(Answer::Unavailable)));
            return Some(Browsing { slot });
        }
        let slot = Arc::new(Mutex::new(None));
        let answer = Arc::clone(&slot);
        let mut dialog = rfd::FileDialog::new()
            .set_title(if save { "Save scene as" } else { "Open scene" })
            .add_filter("raylab scene", &["ron"]);
        if let Some(folder) = start_folder(current) {
            dialog = dialog.set_directory(folder);
        }
        if save {
            dialog = dialog.set_file_name(file_name);
        }
        std::thread::Builder::new()
            .name("raylab-file-dialog".into())
            .spawn(move || {
                let chosen = if save {
                    dialog.save_file()
                } else {
                    dialog.pick_file()
                };
                if let Ok(mut slot) = answer.lock() {
                    *slot = Some(chosen.map_or(Answer::Cancelled, Answer::Chosen));
                }
                wake();
            })
            .ok()?;
        Some(Browsing { slot })
    }

    /// The dialog's answer once it is closed (given once).
    pub fn answer(&mut self) -> Option<Answer> {
        self.slot.lock().ok()?.take()
    }
}

/// True where rfd can show a dialog: on Linux and the BSDs a session bus for the desktop portal, or
/// zenity on a display; elsewhere the system's own dialogs always can.
fn can_open() -> bool {
    if cfg!(any(target_os = "windows", target_os = "macos")) {
        return true;
    }
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    let bus = set("DBUS_SESSION_BUS_ADDRESS")
        || std::env::var_os("XDG_RUNTIME_DIR")
            .is_some_and(|dir| Path::new(&dir).join("bus").exists());
    let display = set("DISPLAY") || set("WAYLAND_DISPLAY");
    bus || (display && on_path("zenity"))
}

/// True when `program` is an executable file in a folder of PATH.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|path| {
        std::env::split_paths(&path).any(|folder| folder.join(program).is_file())
    })
}

/// The folder of the typed path when it exists, else the working folder.
fn start_folder(current: &str) -> Option<PathBuf> {
    let typed = PathBuf::from(current.trim());
    let folder = if typed.is_dir() {
        Some(typed)
    } else {
        typed.parent().filter(|p| p.is_dir()).map(PathBuf::from)
    };
    folder
        .filter(|f| !f.as_os_str().is_empty())
        .or_else(|| std::env::current_dir().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dialog_starts_in_the_typed_paths_folder() {
        let here = std::env::current_dir().unwrap();
        assert_eq!(
            start_folder("assets/scenes/render-mesh.ron"),
            Some("assets/scenes".into())
        );
        assert_eq!(start_folder("assets"), Some("assets".into()));
        assert_eq!(start_folder("no/such/folder/x.ron"), Some(here.clone()));
        assert_eq!(start_folder(""), Some(here));
    }
}
