//! The top bar: the Presets, Lessons, Practice, File and View menus, the tabs, the quick controls that
//! fit (the rest fold into the View menu), and the line under it with the scene's title, note and notice.

use egui::{RichText, Ui};

use super::widgets::palette::Readable as _;
use super::{Notice, RaylabApp, heading, widgets};

impl RaylabApp {
    /// The top bar: menus and tabs, wrapping onto a second row when the window is narrow; the quick
    /// controls (steps, presentation, zoom, theme) follow in the same row when they fit, and always
    /// sit in the View menu.
    pub(super) fn top_bar(&mut self, ui: &mut Ui) {
        let labels: Vec<&str> = self.state.tabs.iter().map(|tab| tab.kind.label()).collect();
        let quick = QuickGroups::that_fit(ui, &labels);
        ui.horizontal_wrapped(|ui| {
            ui.menu_button("Presets", |ui| self.presets_menu(ui))
                .response
                .on_hover_text("Load a lecture example or a hard case");
            ui.menu_button("Lessons", |ui| self.lessons_menu(ui))
                .response
                .on_hover_text("Play a lecture slide by slide, in presentation mode");
            ui.menu_button("Practice", |ui| self.practice_menu(ui))
                .response
                .on_hover_text(
                    "Predict, then check: a generated problem, a hint when wrong, a score",
                );
            ui.menu_button("Class", |ui| self.class_menu(ui))
                .response
                .on_hover_text(
                    "A live class: students answer on their phones, you see every answer",
                );
            ui.menu_button("File", |ui| self.file_menu(ui));
            ui.menu_button("View", |ui| self.view_menu(ui))
                .response
                .on_hover_text("Step panel, presentation mode, zoom and theme");
            if ui
                .button("Keys")
                .on_hover_text(
                    "Every key the app reads, and how a screen reader reads it (? or F1)",
                )
                .clicked()
            {
                self.keys_open = !self.keys_open;
            }
            ui.separator();
            for kind in self
                .state
                .tabs
                .iter()
                .map(|tab| tab.kind)
                .collect::<Vec<_>>()
            {
                ui.selectable_value(
                    &mut self.state.view,
                    kind,
                    RichText::new(kind.label()).strong(),
                );
            }
            self.quick_controls(ui, quick);
        });
        let (title, note) = &heading(&self.state);
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(title).strong());
            if self.class_hides_answer() {
                // The note often states the answer (β = γ = 1/3): not while the class answers.
                ui.label(
                    RichText::new("(the note shows after the reveal)")
                        .weak()
                        .italics(),
                )
                .on_hover_text("A live class is answering a question about this scene");
            } else if self.edited() {
                ui.label(
                    RichText::new("(edited)")
                        .color(widgets::palette::RHS.readable(ui))
                        .strong(),
                )
                .on_hover_text(
                    "The inputs have changed since this scene was loaded: the note below \
                         describes the scene as it was loaded",
                );
                let as_loaded = format!("As loaded: {note}");
                note_label(ui, RichText::new(&as_loaded).weak().italics(), &as_loaded);
            } else {
                note_label(ui, RichText::new(note).weak(), note);
            }
            if let Some(notice) = self.notice_here() {
                let color = if notice.error {
                    widgets::palette::OUTSIDE
                } else {
                    widgets::palette::INSIDE
                };
                ui.label(RichText::new(&notice.text).color(color.readable(ui)));
            }
        });
    }

    /// The notice to show on the open view: its own, or one about the whole app.
    pub(super) fn notice_here(&self) -> Option<&Notice> {
        self.notice
            .as_ref()
            .filter(|n| n.view.is_none_or(|view| view == self.state.view))
    }

    /// True when the open view's inputs differ from the scene as it was loaded.
    pub fn edited(&self) -> bool {
        let Some(loaded) = self
            .state
            .tab(self.state.view)
            .and_then(|tab| tab.loaded.as_ref())
        else {
            return false;
        };
        self.current_scene()
            .is_some_and(|scene| &scene.problem != loaded)
    }

    pub(super) fn presets_menu(&mut self, ui: &mut Ui) {
        let mut chosen = None;
        // A long list on a small or zoomed screen: it scrolls instead of running off the window.
        let max_height = (ui.ctx().content_rect().height() - 48.0).max(120.0);
        egui::ScrollArea::vertical()
            .max_height(max_height)
            .show(ui, |ui| {
                let mut group = None;
                for (index, preset) in self.presets.iter().enumerate() {
                    // A heading where the presets of the next view begin.
                    let kind = self.state.kind_of(&preset.problem);
                    if group != Some(kind) {
                        if group.is_some() {
                            ui.separator();
                        }
                        let label = kind.map_or("", |kind| kind.label());
                        ui.label(RichText::new(label).weak().small());
                        group = Some(kind);
                    }
                    if ui
                        .button(&preset.title)
                        .on_hover_text(&preset.note)
                        .clicked()
                    {
                        chosen = Some(index);
                    }
                }
            });
        if let Some(index) = chosen {
            let preset = self.presets[index].clone();
            self.notice = Some(match self.load_scene(&preset) {
                Ok(()) => Notice {
                    text: format!("Loaded “{}”", preset.title),
                    error: false,
                    view: self.state.kind_of(&preset.problem),
                },
                Err(error) => Notice::error(format!("Could not load “{}”: {error}", preset.title)),
            });
            ui.close();
        }
    }

    pub(super) fn lessons_menu(&mut self, ui: &mut Ui) {
        let mut chosen = None;
        for (name, lesson) in crate::lesson::built_in() {
            let tip = format!("{} ({} slides)", lesson.summary, lesson.slides.len());
            if ui.button(&lesson.title).on_hover_text(tip).clicked() {
                chosen = Some(name);
            }
        }
        if let Some(name) = chosen {
            if let Err(error) = self.start_lesson(name) {
                self.notice = Some(Notice::error(error.to_string()));
            }
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::Fullscreen(true));
            ui.close();
        }
    }

    pub(super) fn practice_menu(&mut self, ui: &mut Ui) {
        use crate::exercise::Kind;
        for (kind, label) in [
            (Kind::Segments, "Segments: find t and s"),
            (Kind::Triangle, "Triangle: find β, γ and t"),
            (Kind::Parallelogram, "Parallelogram: find α, β and t"),
        ] {
            if ui.button(label).clicked() {
                self.start_mixed_practice(kind);
                ui.close();
            }
        }
    }

    pub(super) fn file_menu(&mut self, ui: &mut Ui) {
        if ui
            .button("Open scene…")
            .on_hover_text("Load a scene file (.ron)")
            .clicked()
        {
            self.open_scene(ui.ctx());
            ui.close();
        }
        if ui
            .button("Save scene as…")
            .on_hover_text("Save the open view's inputs as a .ron scene file")
            .clicked()
        {
            self.save_scene();
            ui.close();
        }
    }

    pub(super) fn view_menu(&mut self, ui: &mut Ui) {
        ui.checkbox(&mut self.state.show_steps, "Step panel")
            .on_hover_text("Show or hide the step panel");
        if ui
            .button("Present (F5)")
            .on_hover_text(PRESENT_TIP)
            .clicked()
        {
            self.toggle_presentation(ui.ctx());
            ui.close();
        }
        ui.separator();
        ui.horizontal(zoom_controls);
        ui.horizontal(theme_buttons);
    }

    /// The quick controls that fit in the top bar's row: zoom first, then steps and presentation,
    /// then the theme (all of them are in the View menu too).
    pub(super) fn quick_controls(&mut self, ui: &mut Ui, quick: QuickGroups) {
        if quick.zoom {
            ui.separator();
            zoom_controls(ui);
        }
        if quick.steps {
            ui.separator();
            ui.toggle_value(&mut self.state.show_steps, "Steps")
                .on_hover_text("Show or hide the step panel");
            if ui.button("Present").on_hover_text(PRESENT_TIP).clicked() {
                self.toggle_presentation(ui.ctx());
            }
        }
        if quick.theme {
            ui.separator();
            theme_buttons(ui);
        }
    }
}

/// What the presentation button does.
const PRESENT_TIP: &str = "Presentation mode: the view fills the screen and the steps come one at a \
     time, large. Space, → or Page Down: next step; ← or Page Up: back; Esc: leave";

/// Which groups of quick controls the top bar's row has room for.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct QuickGroups {
    zoom: bool,
    steps: bool,
    theme: bool,
}

impl QuickGroups {
    /// Adds the groups in order of use while the row still fits the window.
    pub(super) fn that_fit(ui: &Ui, tabs: &[&str]) -> QuickGroups {
        let menus_and_tabs = ["Presets", "Lessons", "Practice", "File", "View", "Keys"]
            .into_iter()
            .chain(tabs.iter().copied());
        let mut used = row_width(ui, menus_and_tabs) + 24.0;
        let mut fits = |labels: &[&str]| {
            used += row_width(ui, labels.iter().copied());
            used <= ui.available_width()
        };
        let zoom = fits(&["−", "100%", "+"]);
        let steps = zoom && fits(&["Steps", "Present"]);
        let theme = steps && fits(&["Light", "Dark", "System"]);
        QuickGroups { zoom, steps, theme }
    }
}

/// The width a row of buttons with these labels takes, with a separator before it.
fn row_width<'a>(ui: &Ui, labels: impl Iterator<Item = &'a str>) -> f32 {
    let font = egui::TextStyle::Button.resolve(ui.style());
    let spacing = ui.spacing();
    let per_item = 2.0 * spacing.button_padding.x + spacing.item_spacing.x;
    let text: f32 = labels
        .map(|label| {
            ui.painter()
                .layout_no_wrap(label.into(), font.clone(), egui::Color32::WHITE)
                .size()
                .x
                + per_item
        })
        .sum();
    text + 2.0 * spacing.item_spacing.x + 1.0
}

/// Zoom out, the zoom, zoom in.
fn zoom_controls(ui: &mut Ui) {
    let zoom = ui.ctx().zoom_factor();
    if ui.button("−").on_hover_text("Zoom out (Ctrl −)").clicked() {
        ui.ctx().set_zoom_factor((zoom - 0.1).max(0.5));
    }
    ui.label(format!("{:.0}%", zoom * 100.0))
        .on_hover_text("Zoom (Ctrl + / Ctrl − / Ctrl 0)");
    if ui.button("+").on_hover_text("Zoom in (Ctrl +)").clicked() {
        ui.ctx().set_zoom_factor((zoom + 0.1).min(3.0));
    }
}

/// Light, dark, or follow the system.
fn theme_buttons(ui: &mut Ui) {
    use egui::ThemePreference;
    let mut preference = ui.ctx().options(|o| o.theme_preference);
    let before = preference;
    for (value, label, tip) in [
        (
            ThemePreference::Light,
            "Light",
            "Light theme: dark text on white, best on most projectors",
        ),
        (ThemePreference::Dark, "Dark", "Dark theme"),
        (
            ThemePreference::System,
            "System",
            "Follow the system's theme",
        ),
    ] {
        ui.selectable_value(&mut preference, value, label)
            .on_hover_text(tip);
    }
    if preference != before {
        ui.ctx().set_theme(preference);
    }
}

/// Rows the scene's note may take beside its title.
const NOTE_ROWS: usize = 2;

/// The scene's note in at most [`NOTE_ROWS`] rows, ending in "…" when cut, the whole note on hover:
/// a long note must not push the view off a zoomed projector.
fn note_label(ui: &mut Ui, text: RichText, whole: &str) {
    let mut job = egui::text::LayoutJob::default();
    let valign = ui.text_valign();
    text.append_to(&mut job, ui.style(), egui::FontSelection::Default, valign);
    job.wrap.max_rows = NOTE_ROWS;
    job.wrap.overflow_character = Some('…');
    ui.add(egui::Label::new(job)).on_hover_text(whole);
}
