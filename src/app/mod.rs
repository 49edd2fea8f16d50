//! The egui app: a tab per view, the step panel beside it, presets, scene files, themes and zoom.
//!
//! The app only turns state into widgets and input into state changes; every number it shows comes
//! from the core's solvers and their Trace.

pub mod accuracy_view;
pub mod class_view;
pub mod highlight;
mod keys_help;
pub mod launch;
pub mod lesson_view;
#[cfg(test)]
mod midpoint_view;
#[cfg(not(target_arch = "wasm32"))]
pub mod native_dialog;
pub mod parallelogram_view;
pub mod practice_view;
mod presentation;
pub mod render_view;
mod scene_files;
pub mod segments_view;
mod state;
pub mod step_panel;
mod style;
mod top_bar;
pub mod triangle_view;
pub mod view;
pub mod widgets;

pub use launch::Launch;
use scene_files::Dialog;
pub use state::{AppState, Tab, ViewKind};
use state::{STATE_KEY, heading};
use style::enlarge;
pub use style::set_style;

use egui::Ui;

use crate::geometry::Precision;
use crate::scene::{self, Problem, Scene};
use crate::trace::Trace;
use accuracy_view::AccuracyView;
use parallelogram_view::ParallelogramView;
use render_view::RenderView;
use segments_view::SegmentsView;
use triangle_view::TriangleView;
use view::{ActiveSolve, ViewEntry, fresh, restored};

/// The registry: the app's tabs in order, each with how its view is made. A new view is its file
/// (with its `mod` line above) and its line here.
pub const VIEWS: &[ViewEntry] = &[
    ViewEntry::new(ViewKind::Segments, restored::<SegmentsView>),
    ViewEntry::new(ViewKind::Triangle, restored::<TriangleView>),
    ViewEntry::new(ViewKind::Parallelogram, restored::<ParallelogramView>),
    ViewEntry::new(ViewKind::Render, restored::<RenderView>),
    ViewEntry::new(ViewKind::Accuracy, fresh::<AccuracyView>),
];

/// A message in the status line: what was loaded or saved, or what went wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct Notice {
    /// The text.
    pub text: String,
    /// True for an error.
    pub error: bool,
    /// The view it is about (shown only there), or `None` for the whole app (a file that could not
    /// be opened).
    pub view: Option<ViewKind>,
}

impl Notice {
    /// News for the whole app: what was loaded or saved.
    pub fn info(text: impl Into<String>) -> Notice {
        Notice {
            text: text.into(),
            error: false,
            view: None,
        }
    }

    /// What went wrong, for the whole app.
    pub fn error(text: impl Into<String>) -> Notice {
        Notice {
            error: true,
            ..Notice::info(text)
        }
    }
}

/// The eframe app.
pub struct RaylabApp {
    /// The persistent state.
    pub state: AppState,
    presets: Vec<Scene>,
    dialog: Option<Dialog>,
    /// The last notice.
    pub notice: Option<Notice>,
    /// Scene files the browser's file picker has read (web).
    inbox: crate::platform::Inbox,
    /// The desktop's native Open/Save dialog while it is open.
    #[cfg(not(target_arch = "wasm32"))]
    browsing: Option<native_dialog::Browsing>,
    /// Presentation mode: the index of the step on screen.
    pub presentation: Option<usize>,
    /// The open view as each presentation step left it (by step), so Back restores what Next set.
    presented_views: Vec<Option<Box<dyn view::View>>>,
    /// Where the open view was drawn last frame (tests check it keeps half the window).
    pub view_rect: Option<egui::Rect>,
    /// A new scene was loaded: the step panel goes back to its first step.
    steps_to_top: bool,
    /// The lesson being played, if any.
    pub lesson: Option<lesson_view::LessonRun>,
    /// Seed 002's symbolic derivation for the Triangle view's scene, and the scene it was made for.
    symbolic: Option<(crate::scene::TriangleScene, Trace)>,
    /// The practice session, if any.
    pub practice: Option<practice_view::PracticeRun>,
    /// The seed of the last practice problem (each new one takes the next).
    pub practice_seed: u64,
    /// The live class being taught, if any.
    pub class: Option<class_view::ClassRun>,
    /// The Class → Start / Join dialog while it is open.
    class_dialog: Option<class_view::ClassDialog>,
    /// The saved class was resumed (or there was none) at start.
    class_resumed: bool,
    /// The Keys window is open.
    pub keys_open: bool,
}

impl RaylabApp {
    /// The app with default state (tests, first start).
    pub fn new() -> RaylabApp {
        RaylabApp::with_views(VIEWS)
    }

    /// The app with the tabs of `registry` (the app's is [`VIEWS`]; a test may add a view of its own).
    pub fn with_views(registry: &[ViewEntry]) -> RaylabApp {
        RaylabApp {
            state: AppState::with_views(registry),
            presets: scene::built_in(),
            dialog: None,
            notice: None,
            inbox: crate::platform::Inbox::default(),
            #[cfg(not(target_arch = "wasm32"))]
            browsing: None,
            presentation: None,
            presented_views: Vec::new(),
            view_rect: None,
            steps_to_top: false,
            lesson: None,
            symbolic: None,
            practice: None,
            practice_seed: 0,
            class: None,
            class_dialog: None,
            class_resumed: false,
            keys_open: false,
        }
    }

    /// Opens what a launch asks for (a preset, then a view); a name that is not known is reported in
    /// the status line, and the remembered state is kept.
    pub fn launch(&mut self, launch: &Launch) {
        let mut problems = Vec::new();
        if let Some(name) = &launch.preset {
            match scene::preset(name) {
                Some(preset) => match self.load_scene(&preset) {
                    Ok(()) => {
                        self.notice = Some(Notice {
                            text: format!("Loaded “{}”", preset.title),
                            error: false,
                            view: self.state.kind_of(&preset.problem),
                        })
                    }
                    Err(error) => problems.push(format!("“{name}”: {error}")),
                },
                None => problems.push(format!(
                    "no preset named “{name}” (there are: {})",
                    scene::preset_names().join(", ")
                )),
            }
        }
        if let Some(name) = &launch.view {
            let kinds: Vec<ViewKind> = self.state.tabs.iter().map(|tab| tab.kind).collect();
            match kinds.iter().find(|kind| kind.name() == name) {
                Some(kind) => self.state.view = *kind,
                None => problems.push(format!(
                    "no view named “{name}” (there are: {})",
                    kinds
                        .iter()
                        .map(|kind| kind.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
            }
        }
        if let Some(name) = &launch.lesson
            && let Err(error) = self.start_lesson(name)
        {
            problems.push(error.to_string());
        }
        if !problems.is_empty() {
            self.notice = Some(Notice::error(problems.join("; ")));
        }
    }

    /// The app as eframe starts it: projector-friendly text, and the state of the last session.
    pub fn from_creation_context(cc: &eframe::CreationContext<'_>) -> RaylabApp {
        set_style(&cc.egui_ctx);
        let mut app = RaylabApp::new();
        if let Some(storage) = cc.storage
            && let Some(state) = eframe::get_value::<AppState>(storage, STATE_KEY)
        {
            app.state = state;
        }
        app
    }

    /// Loads a scene into its view and switches to it; a render scene whose meshes or textures
    /// cannot be read is refused, and the scene on screen is kept.
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), view::OpenError> {
        self.load_scene_from(scene, None)
    }

    /// Loads a scene read from a file in `folder`, where a render scene's own meshes and textures are.
    pub fn load_scene_from(
        &mut self,
        scene: &Scene,
        folder: Option<String>,
    ) -> Result<(), view::OpenError> {
        let kind = self
            .state
            .kind_of(&scene.problem)
            .ok_or(view::OpenError::NotMine)?;
        let tab = self.state.tab_mut(kind).ok_or(view::OpenError::NotMine)?;
        tab.view.open(&scene.problem, folder)?;
        tab.title = (scene.title.clone(), scene.note.clone());
        tab.loaded = Some(scene.problem.clone());
        self.state.view = kind;
        self.steps_to_top = true;
        Ok(())
    }

    /// Carries out what the Render view asked for: a probed ray into the Triangle or Parallelogram
    /// view (its steps then show in the panel), or a switch of view.
    pub(crate) fn render_action(&mut self, action: render_view::Action) {
        let probed = self.state.find::<RenderView>();
        let title = format!(
            "{} of “{}”",
            probed.map(|r| r.probed_ray_name()).unwrap_or_default(),
            self.state.title(ViewKind::Render).0
        );
        let note = "The ray the renderer cast for that pixel, and what it met.".to_string();
        self.steps_to_top = true;
        let problem = match action {
            render_view::Action::Triangle(scene) => Problem::Triangle(scene),
            render_view::Action::Parallelogram(scene) => Problem::Parallelogram(scene),
            render_view::Action::Open(kind) => {
                self.state.view = kind;
                return;
            }
        };
        let Some(kind) = self.state.kind_of(&problem) else {
            return;
        };
        if let Some(tab) = self.state.tab_mut(kind)
            && tab.view.open(&problem, None).is_ok()
        {
            tab.loaded = Some(problem);
            tab.title = (title, note);
        }
        // Judge the probe as the renderer saw it: exact arithmetic on the floats themselves.
        if kind == ViewKind::Triangle
            && let Some(triangle) = self.state.find_mut::<TriangleView>()
        {
            triangle.reading = crate::geometry::Reading::FloatValue;
        }
    }

    /// Loads a hard case of the Accuracy view's gallery into the Triangle view, judged as the
    /// gallery does: exact arithmetic on the float values themselves.
    pub(crate) fn load_hard_case(
        &mut self,
        scene: scene::TriangleScene,
        title: String,
        note: String,
    ) {
        let loaded = self.load_scene(&Scene {
            title,
            note,
            problem: Problem::Triangle(scene),
        });
        debug_assert!(loaded.is_ok(), "a triangle always loads");
        if let Some(triangle) = self.state.find_mut::<TriangleView>() {
            triangle.reading = crate::geometry::Reading::FloatValue;
        }
    }

    /// The open view's inputs as a scene, for saving.
    pub fn current_scene(&self) -> Option<Scene> {
        let problem = self.view(self.state.view).problem()?;
        let (title, note) = self.state.title(self.state.view);
        Some(Scene {
            title,
            note,
            problem,
        })
    }

    fn solve(&self) -> ActiveSolve {
        let view = self.view(self.state.view);
        view.solve_frame(view.own_precision().unwrap_or(self.state.precision))
    }

    /// Everything a solve depends on, to tell whether a frame changed it: the tab, the precision,
    /// and each view's titles and what it says its frames depend on.
    fn fingerprint(&self) -> Fingerprint {
        let s = &self.state;
        let mut numbers = Vec::new();
        for tab in &s.tabs {
            tab.view.fingerprint(&mut numbers);
        }
        Fingerprint {
            view: s.view,
            precision: s.precision,
            titles: s.tabs.iter().map(|tab| tab.title.clone()).collect(),
            numbers,
        }
    }
}

/// What [`RaylabApp::fingerprint`] compares.
#[derive(PartialEq)]
struct Fingerprint {
    view: ViewKind,
    precision: Precision,
    titles: Vec<(String, String)>,
    numbers: Vec<u64>,
}

impl Default for RaylabApp {
    fn default() -> RaylabApp {
        RaylabApp::new()
    }
}

impl eframe::App for RaylabApp {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        self.receive_files();
        self.keys_help_toggle(ui.ctx());
        if ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::F5)) {
            if self.lesson.is_some() {
                self.leave_lesson(ui.ctx());
            } else if self.practice.is_none() {
                // Presenting a practice problem would show its answer: F5 waits until it is left.
                self.toggle_presentation(ui.ctx());
            }
        }
        let before = self.fingerprint();
        let solved = self.solve();
        self.class_frame(ui.ctx());
        // A live class's open question: the view keeps its answer to itself until the reveal.
        let class_hides = self.class_hides_answer();
        if class_hides {
            widgets::hide_answers(ui.ctx(), true);
        }
        let workbench =
            self.lesson.is_none() && self.practice.is_none() && self.presentation.is_none();
        if self.class.is_some() && !workbench {
            egui::Panel::bottom("class-strip").show(ui, |ui| self.class_strip_ui(ui));
        }
        match self.presentation {
            _ if self.lesson.is_some() => self.lesson_ui(ui, &solved),
            _ if self.practice.is_some() => self.practice_ui(ui, &solved),
            Some(index) => self.presentation_ui(ui, &solved, index),
            None => self.workbench_ui(ui, &solved),
        }
        if class_hides {
            widgets::hide_answers(ui.ctx(), false);
        }
        self.dialog_ui(&ui.ctx().clone());
        self.class_dialog_ui(&ui.ctx().clone());
        self.keys_help_ui(&ui.ctx().clone());
        // The step panel was drawn before this frame's drags: draw once more so it catches up.
        if self.fingerprint() != before {
            ui.ctx().request_repaint();
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STATE_KEY, &self.state);
    }
}

impl RaylabApp {
    /// The usual layout: top bar, step panel, the open view.
    fn workbench_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve) {
        self.set_highlight(Vec::new());
        egui::Panel::top("top-bar").show(ui, |ui| self.top_bar(ui));
        if self.class.is_some() {
            // A live class: its panel takes the steps' place (the steps would give the answer away).
            side_panel(ui, "class", 0.3, 380.0, 0.45).show(ui, |ui| self.class_panel_ui(ui));
        } else if self.state.show_steps {
            // About 40% of the window, never more than half: the view keeps at least half the width.
            side_panel(ui, "steps", 0.4, 420.0, 0.5).show(ui, |ui| match solved.trace() {
                    Some(trace) => {
                        let triangle = self.state.view == ViewKind::Triangle;
                        let shown = self.state.find::<TriangleView>();
                        let marked = shown.and_then(|t| t.hovered_column);
                        let marked = marked.filter(|_| triangle);
                        let to_top = std::mem::take(&mut self.steps_to_top);
                        let symbolic_on = triangle && self.state.symbolic;
                        if symbolic_on {
                            self.refresh_symbolic();
                        }
                        let trace = match &self.symbolic {
                            Some((_, symbolic)) if symbolic_on => symbolic,
                            _ => trace,
                        };
                        let mut symbolic = self.state.symbolic;
                        // The view's own precision where it keeps one (the Render view's probe).
                        let own = self.view(self.state.view).own_precision();
                        let mut precision = own.unwrap_or(self.state.precision);
                        let choice = step_panel::Choice {
                            precision: &mut precision,
                            symbolic: triangle.then_some(&mut symbolic),
                            subject: self.view(self.state.view).steps_subject(),
                        };
                        let panel = step_panel::ui(ui, trace, choice, marked, to_top);
                        let solver = trace.solver.clone();
                        self.state.symbolic = symbolic;
                        match own {
                            Some(_) => self.view_mut(self.state.view).set_own_precision(precision),
                            None => self.state.precision = precision,
                        }
                        if let Some(step) = panel.hovered_step {
                            self.set_highlight(highlight::of_step(&solver, &step));
                        }
                    }
                    None if self.state.view == ViewKind::Render => {
                        ui.heading("Steps");
                        ui.label("Click a pixel of the render: the steps of its ray against the triangle it hit (or came nearest to) show here.");
                    }
                    None => {
                        ui.heading("Steps");
                        ui.label("Load a hard case from the gallery to see its steps in the Triangle view.");
                    }
                });
        }
        let view = egui::CentralPanel::default().show(ui, |ui| self.view_ui(ui, solved, false));
        self.view_rect = Some(view.response.rect);
    }

    /// Seed 002's derivation for the Triangle view's scene, made again only when the scene changes.
    fn refresh_symbolic(&mut self) {
        let Some(triangle) = self.state.find::<TriangleView>() else {
            return;
        };
        let scene = triangle.scene.clone();
        let reading = triangle.reading;
        if self
            .symbolic
            .as_ref()
            .is_none_or(|(made_for, _)| *made_for != scene)
        {
            // The scene's numbers as the Triangle view reads them; none if one is not finite.
            let numbers =
                crate::geometry::triangle::RayTriangle::<crate::math::exact::Exact>::read(
                    reading,
                    [scene.a, scene.b, scene.c, scene.origin, scene.dir]
                        .map(glam::DVec3::from_array),
                    scene.t_min,
                )
                .ok()
                .map(|p| [p.a, p.b, p.c, p.origin, p.dir]);
            let trace = crate::symbolic::trace(numbers.as_ref());
            self.symbolic = Some((scene, trace));
        }
    }

    /// The open view; `canvas_only` in presentation mode (no controls, the drawing fills the space).
    fn view_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve, canvas_only: bool) {
        if let Some(request) = self
            .view_mut(self.state.view)
            .frame_ui(ui, solved, canvas_only)
        {
            request.apply(self);
        }
    }

    /// Tells the open view what to emphasise.
    fn set_highlight(&mut self, elements: Vec<highlight::Element>) {
        for tab in &mut self.state.tabs {
            tab.view.emphasise(&elements);
        }
    }
}

/// A resizable panel on the right that opens at `share` of the window's width, at least 240 points
/// and at most `widest`, and never grows past `most` of the window (the view keeps the rest).
fn side_panel(ui: &Ui, id: &'static str, share: f32, widest: f32, most: f32) -> egui::Panel {
    let full = ui.available_width();
    let width = (full * share).clamp(240.0, widest).min(full * most);
    // Each zoom keeps its own width: one width for all, clamped to the narrower window of a zoomed
    // screen, came back narrower after every zoom in and out (630 → 480 → 358 points).
    let zoom = (ui.ctx().zoom_factor() * 100.0).round() as u32;
    egui::Panel::right(egui::Id::unique((id, zoom)))
        .resizable(true)
        .default_size(width)
        .size_range(width.min(240.0)..=full * most)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pairs a student must tell apart (A and B, inside and outside, hit and miss, the columns
    /// A−B, A−C, D and Y) stay apart as a student with protanopia, deuteranopia or tritanopia sees them
    /// (Machado et al.'s simulation): ΔE at least 15, drawn as lines (the palette's colours) and as
    /// text in both themes (the colours darkened or lightened to read). Red against green, as raylab
    /// drew segments A and B and inside and outside, falls to 6 and 5 for deuteranopia as dark-theme text.
    #[test]
    fn the_pairs_that_matter_stay_apart_for_colour_blind_students_in_both_themes() {
        use widgets::palette::ink;
        use widgets::palette::vision::{Deficiency, MIN_DIFFERENCE, PAIRS, delta_e, simulate};
        let ctx = egui::Context::default();
        set_style(&ctx);
        let mut failures = Vec::new();
        for theme in [egui::Theme::Light, egui::Theme::Dark] {
            let visuals = ctx.style_of(theme).visuals.clone();
            for (first, a, second, b) in PAIRS {
                for (drawn, a, b) in [("line", a, b), ("text", ink(a, &visuals), ink(b, &visuals))]
                {
                    for deficiency in Deficiency::ALL {
                        let difference = delta_e(simulate(a, deficiency), simulate(b, deficiency));
                        if difference < MIN_DIFFERENCE {
                            failures.push(format!(
                                "{theme:?} {drawn}: {first} and {second} under {deficiency:?}: ΔE {difference:.1}"
                            ));
                        }
                    }
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// Every text colour of both themes, as set_style leaves them, against the backgrounds it is drawn
    /// on: at least 4.5:1 (WCAG AA), so a student at the back of a room can read it.
    #[test]
    fn every_text_colour_reads_at_4_5_to_1_in_both_themes() {
        use widgets::palette::{MIN_TEXT_CONTRAST, TEXT_COLOURS, backgrounds, contrast, ink};
        let ctx = egui::Context::default();
        set_style(&ctx);
        for theme in [egui::Theme::Light, egui::Theme::Dark] {
            let visuals = ctx.style_of(theme).visuals.clone();
            let mut failures = Vec::new();
            let mut check = |name: &str, text: egui::Color32, on: &[egui::Color32]| {
                for bg in on {
                    let ratio = contrast(text, *bg);
                    if ratio < MIN_TEXT_CONTRAST {
                        failures.push(format!("{theme:?} {name} {text:?} on {bg:?}: {ratio:.2}"));
                    }
                }
            };
            let panels = backgrounds(&visuals);
            check("text", visuals.text_color(), &panels);
            check("weak text", visuals.weak_text_color(), &panels);
            check("strong text", visuals.strong_text_color(), &panels);
            check("link", visuals.hyperlink_color, &panels);
            check("warning", visuals.warn_fg_color, &panels);
            check("error", visuals.error_fg_color, &panels);
            for (name, colour) in TEXT_COLOURS {
                check(name, ink(colour, &visuals), &panels);
            }
            let widgets = &visuals.widgets;
            for (name, w) in [
                ("label", &widgets.noninteractive),
                ("button", &widgets.inactive),
                ("hovered button", &widgets.hovered),
                ("pressed button", &widgets.active),
                ("open menu", &widgets.open),
            ] {
                check(name, w.fg_stroke.color, &[w.bg_fill, w.weak_bg_fill]);
            }
            check(
                "selected",
                visuals.selection.stroke.color,
                &[visuals.selection.bg_fill],
            );
            assert!(failures.is_empty(), "{failures:#?}");
        }
    }

    #[test]
    fn a_query_names_a_preset_and_a_view() {
        assert_eq!(
            Launch::from_query("?preset=triangle-outside&view=Accuracy&x=1"),
            Launch {
                preset: Some("triangle-outside".into()),
                view: Some("accuracy".into()),
                lesson: None,
            }
        );
        assert_eq!(
            Launch::from_query("?lesson=seed001-parallelogram")
                .lesson
                .as_deref(),
            Some("seed001-parallelogram")
        );
        assert_eq!(Launch::from_query(""), Launch::default());
        assert_eq!(Launch::from_query("?preset=&view"), Launch::default());
    }

    #[test]
    fn a_launch_opens_its_preset_and_view_and_names_what_it_does_not_know() {
        let mut app = RaylabApp::new();
        app.launch(&Launch::from_query("?preset=triangle-outside"));
        assert_eq!(app.state.view, ViewKind::Triangle);
        assert!(app.notice.as_ref().is_some_and(|n| !n.error));
        app.launch(&Launch::from_query("?view=accuracy"));
        assert_eq!(app.state.view, ViewKind::Accuracy);
        app.launch(&Launch::from_query("?preset=nope&view=nowhere"));
        assert_eq!(app.state.view, ViewKind::Accuracy);
        let notice = app.notice.take().unwrap();
        assert!(notice.error);
        assert!(notice.text.contains("“nope”") && notice.text.contains("triangle-outside"));
        assert!(notice.text.contains("“nowhere”") && notice.text.contains("accuracy"));
        // A lesson starts at its first slide, on that slide's scene.
        app.launch(&Launch::from_query("?lesson=seed001-parallelogram"));
        assert_eq!(app.lesson.as_ref().map(|run| run.slide), Some(0));
        assert_eq!(app.state.view, ViewKind::Parallelogram);
        app.lesson = None;
        app.launch(&Launch::from_query("?lesson=nope"));
        assert!(app.lesson.is_none());
        let notice = app.notice.unwrap();
        assert!(
            notice.text.contains("no lesson named “nope”"),
            "{}",
            notice.text
        );
        assert!(notice.text.contains("seed000-segments-and-triangle"));
    }

    /// A typo in a scene file is refused with its line and column, and the app keeps its scene; Save
    /// replaces a file whole and leaves no temporary file, and a folder is not overwritten.
    #[test]
    fn open_refuses_a_typo_and_save_replaces_files_whole() {
        let dir = std::env::temp_dir().join(format!("raylab-app-files-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let mut app = RaylabApp::new();
        app.launch(&Launch::from_query("?preset=render-mesh"));
        let before = app.state.get::<RenderView>().scene.clone();
        let typo = dir.join("typo.ron");
        let text = scene::preset("render-mesh").unwrap().to_ron();
        std::fs::write(
            &typo,
            text.replace("effects:", "methd: Some(\"plane\"), effects:"),
        )
        .unwrap();
        app.state.scene_path = typo.display().to_string();
        let notice = app.run_dialog_path(false);
        assert!(notice.error);
        assert!(
            notice.text.contains("typo.ron:") && notice.text.contains("unknown field 'methd'"),
            "{}",
            notice.text
        );
        assert_eq!(app.state.get::<RenderView>().scene, before);

        let saved = dir.join("saved.ron");
        std::fs::write(&saved, "an older file").unwrap();
        app.state.scene_path = saved.display().to_string();
        assert!(!app.run_dialog_path(true).error);
        assert_eq!(
            Scene::load(&saved).unwrap().problem,
            Problem::Render(before)
        );
        app.state.scene_path = dir.display().to_string();
        assert!(app.run_dialog_path(true).error);
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["saved.ron", "typo.ron"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
