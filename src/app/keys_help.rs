//! The Keys window (`?` or F1, or the top bar's "Keys" button): every action the mouse can do and the
//! key that does it, and how a screen reader reads the app.

use egui::{RichText, Ui};

use super::RaylabApp;

/// Every key the app reads, with what it does, grouped as a student meets them.
pub const KEYS: &[(&str, &[(&str, &str)])] = &[
    (
        "Everywhere",
        &[
            (
                "Tab / Shift+Tab",
                "next / previous control or canvas handle",
            ),
            ("Space or Enter", "press the focused button"),
            ("Ctrl + / Ctrl − / Ctrl 0", "zoom in / out / back to 100%"),
            ("F5", "presentation mode on or off (leaves a lesson)"),
            ("? or F1", "this window"),
            ("Esc", "let go of a handle; close a menu or this window"),
        ],
    ),
    (
        "A canvas handle (a vertex, an endpoint, A(t), B(s), P(β, γ), L, D)",
        &[
            (
                "← → ↑ ↓",
                "move it (endpoints on the 0.25 grid, parameters by 0.05)",
            ),
            ("Shift + arrows", "fine steps (0.01; vertices by 0.05)"),
            ("Enter", "solve: slide the parameters to the solution"),
        ],
    ),
    (
        "The canvas itself (Tab to it)",
        &[
            (
                "← → ↑ ↓",
                "orbit the 3D views and the render's camera; pan the Segments plot",
            ),
            ("+ / −", "zoom in / out (the render's camera dollies)"),
            ("Ctrl + arrows", "pan the render's camera"),
            ("R", "reset the render's camera"),
            (
                "Enter, Shift + arrows",
                "on a render: probe a pixel, then the next one over",
            ),
        ],
    ),
    (
        "Presentation and lessons",
        &[
            ("Space, → or Page Down", "next step or slide"),
            ("← or Page Up", "back"),
            ("Esc", "leave"),
        ],
    ),
    (
        "Practice",
        &[
            ("Tab to the answer box, type, Enter", "check the answer"),
            ("Esc", "leave practice"),
        ],
    ),
];

impl RaylabApp {
    /// Opens or closes the Keys window on `?` or F1 (not while a text box takes the typing).
    pub(super) fn keys_help_toggle(&mut self, ctx: &egui::Context) {
        let typing = ctx.text_edit_focused();
        let pressed = ctx.input_mut(|i| {
            i.consume_key(egui::Modifiers::NONE, egui::Key::F1)
                || (!typing
                    && i.events
                        .iter()
                        .any(|e| matches!(e, egui::Event::Text(t) if t == "?")))
        });
        if pressed {
            self.keys_open = !self.keys_open;
        }
    }

    /// The Keys window, while open.
    pub(super) fn keys_help_ui(&mut self, ctx: &egui::Context) {
        let mut open = self.keys_open;
        // Within the screen at any zoom: the descriptions wrap, the window scrolls.
        let screen = ctx.content_rect();
        let width = (screen.width() - 40.0).clamp(200.0, 640.0);
        egui::Window::new("Keys")
            .open(&mut open)
            .collapsible(false)
            .vscroll(true)
            .default_width(width)
            .max_width(width)
            .max_height(screen.height() - 60.0)
            .default_pos(screen.left_top() + egui::vec2(20.0, 40.0))
            .show(ctx, keys_table);
        if open && ctx.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Escape)) {
            open = false;
        }
        self.keys_open = open;
    }
}

/// The keys, a group at a time; then how a screen reader reads the app.
fn keys_table(ui: &mut Ui) {
    for (group, keys) in KEYS {
        ui.label(RichText::new(*group).strong());
        egui::Grid::new(*group)
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                for (key, what) in *keys {
                    ui.label(RichText::new(*key).monospace());
                    ui.add(egui::Label::new(*what).wrap());
                    ui.end_row();
                }
            });
        ui.add_space(6.0);
    }
    ui.label(RichText::new("Screen reader").strong());
    ui.label(
        "Each handle is named with its value (\"vertex A at (3, 0, 0)\"), each step of the \
         solve reads as one line of text, and the verdict is announced when it changes.",
    );
}
