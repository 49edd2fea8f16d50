//! The Render view: a scene rendered one ray per pixel, with the scene's effects as toggles, the method,
//! the timing and work of the last render, a common bug rendered beside the correct image, a pixel probe
//! that loads a pixel's ray into the Triangle view, and the probed ray in world and object space.
//!
//! Renders run as a [`Job`] (a thread natively, slices of frames on the web) and only when something
//! they depend on changed.

mod effects;
mod jobs;
mod orbit;
mod probe;
mod spaces;
mod tree;

pub use effects::grouped;

use jobs::{Choices, Runtime, loads_in_background};

use super::parallelogram_view;
use super::triangle_view;
use super::view::{ActiveSolve, OpenError, Request, View};
use super::widgets::palette::Readable as _;
use super::{RaylabApp, ViewKind};
use std::sync::Arc;

use egui::{Color32, ColorImage, RichText, Sense, Stroke, TextureHandle, TextureOptions, Ui, Vec2};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::widgets::labels::{LabelLayer, Priority};
use super::widgets::palette;
use super::widgets::scene3d::{Canvas, OrbitCamera};
use crate::geometry::{Precision, Reading};
use crate::intersect::Method;
use crate::math::linalg::{add, norm_f64, scale};
use crate::platform::Job;
use crate::render::budget::{BudgetedRender, OverTime};
use crate::render::inspect::probe::{Probe, probe};
use crate::render::inspect::ray_tree::{RayTree, ray_tree};
use crate::render::loading::assets::{AssetSource, OnDisk};
use crate::render::loading::scene_load::{SceneLoad, UNITS_PER_MESH, mesh_names};
use crate::render::objects::Geometry;
use crate::render::{Bug, Hit, Prepared, Rendered};
use crate::scene::render::{Effect, RenderScene};
use crate::scene::{ParallelogramScene, Problem, TriangleScene};

/// What the image area shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// The rendered image (and a bug's image beside it).
    #[default]
    Image,
    /// The probed ray in world space and in the object's space.
    Spaces,
}

/// The Render view's state; the scene and the choices persist, images do not.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct RenderView {
    /// The scene being rendered.
    pub scene: RenderScene,
    /// The effects switched on (a subset of the scene's).
    pub effects: Vec<Effect>,
    /// The method, or the scene's.
    pub method: Option<Method>,
    /// A bug to render beside the correct image.
    pub bug: Option<Bug>,
    /// Image or spaces.
    pub mode: Mode,
    /// The last probed pixel (row, column).
    pub probed: Option<(usize, usize)>,
    /// The folder of the scene's file, where its own meshes and textures are (`None`: a preset).
    pub folder: Option<String>,
    /// The camera as the user moved it (`None`: the scene's own); saved with the scene only when
    /// the user saves it.
    pub camera: Option<crate::scene::render::Camera>,
    /// The precision of a probed ray's steps: f64 by default (the renderer's own arithmetic; exact
    /// arithmetic on its floats reads in 17-digit decimals), picked in the step panel.
    pub probe_precision: Precision,
    /// The image the probed pixel was clicked on: the correct one (`None`) or the bug's.
    #[serde(skip)]
    pub probed_bug: Option<Bug>,
    /// The seconds a full render may take, estimated by its trial frame, before it waits for
    /// "Render anyway" (`None`: no limit).
    #[serde(skip, default = "default_time_budget")]
    time_budget: Option<f64>,
    #[serde(skip)]
    runtime: Runtime,
}

/// `raylab render`'s budget; none in a debug build, whose tests run many renders at once on one
/// thread pool: a trial frame queued behind another test's render measures the load, not the
/// scene (the budget test sets one).
fn default_time_budget() -> Option<f64> {
    (!cfg!(debug_assertions)).then(|| f64::from(crate::render::budget::TIME_BUDGET_SECONDS))
}

impl View for RenderView {
    fn opens(&self, problem: &Problem) -> bool {
        matches!(problem, Problem::Render(_))
    }

    fn open(&mut self, problem: &Problem, folder: Option<String>) -> Result<(), OpenError> {
        let Problem::Render(scene) = problem else {
            return Err(OpenError::NotMine);
        };
        self.load(scene.clone(), folder)
    }

    /// The scene as the view shows it: through the moved camera, if the user moved it.
    fn problem(&self) -> Option<Problem> {
        let mut scene = self.scene.clone();
        scene.camera = self.view_camera();
        Some(Problem::Render(scene))
    }

    /// The probed pixel's ray against what it met (or came nearest to): the step panel shows its
    /// steps, judged as the renderer saw it (exact arithmetic on the floats themselves for a triangle).
    fn solve_frame(&self, precision: Precision) -> ActiveSolve {
        match self.probed_problem() {
            Some(Action::Triangle(scene)) => ActiveSolve::new(triangle_view::Solved::new(
                (scene.vectors(), scene.t_min),
                Reading::FloatValue,
                precision,
            )),
            Some(Action::Parallelogram(scene)) => ActiveSolve::new(
                parallelogram_view::Solved::new(scene.vectors(), Reading::AsWritten, precision),
            ),
            _ => ActiveSolve::nothing(),
        }
    }

    fn steps_subject(&self) -> Option<String> {
        RenderView::steps_subject(self)
    }

    fn frame_ui(
        &mut self,
        ui: &mut Ui,
        _solved: &ActiveSolve,
        _canvas_only: bool,
    ) -> Option<Request> {
        let action = self.ui(ui)?;
        Some(Request::new(move |app: &mut RaylabApp| {
            app.render_action(action)
        }))
    }

    /// The probed pixel: the step panel's solve changes with it.
    fn fingerprint(&self, bits: &mut Vec<u64>) {
        let (row, column) = self.probed.unwrap_or((usize::MAX, usize::MAX));
        bits.extend([row as u64, column as u64, self.probe_precision as u64]);
    }

    fn own_precision(&self) -> Option<Precision> {
        Some(self.probe_precision)
    }

    fn set_own_precision(&mut self, precision: Precision) {
        self.probe_precision = precision;
    }

    fn save(&self) -> Option<String> {
        ron::to_string(self).ok()
    }

    fn aim(&mut self, yaw: f64, pitch: f64) {
        self.look_from(yaw, pitch);
    }
}

/// What the view asks the app to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Show this probed triangle in the Triangle view (and its steps in the panel).
    Triangle(TriangleScene),
    /// Show this probed parallelogram in the Parallelogram view.
    Parallelogram(ParallelogramScene),
    /// Switch to the given view.
    Open(super::ViewKind),
}

impl Default for RenderView {
    fn default() -> RenderView {
        let scene = crate::scene::first_built_in(|s| match s {
            crate::scene::Problem::Render(r) => Some(r),
            _ => None,
        });
        RenderView {
            effects: scene.effects.clone(),
            scene,
            method: None,
            bug: None,
            mode: Mode::Image,
            probed: None,
            folder: None,
            camera: None,
            probe_precision: Precision::F64,
            probed_bug: None,
            time_budget: default_time_budget(),
            runtime: Runtime::default(),
        }
    }
}

/// Where a scene finds meshes and textures besides the shipped ones: beside its file and in the
/// folder above (as `raylab render` looks), then under the working folder.
fn assets(folder: Option<&str>) -> OnDisk {
    let mut folders: Vec<std::path::PathBuf> = Vec::new();
    if let Some(folder) = folder {
        folders.push(folder.into());
        folders.push(std::path::Path::new(folder).join(".."));
    }
    folders.extend([".".into(), "assets".into()]);
    OnDisk(folders)
}

/// The space between the correct image and the buggy one.
const IMAGE_GAP: f32 = 12.0;

/// What the images' layout is worked out from ([`RenderView::image_grid`]).
struct ImageGrid {
    /// The image's size in pixels (at least 1).
    width: f32,
    height: f32,
    /// Images side by side: 2 with a bug, else 1.
    panes: f32,
    /// The caption's height above each image.
    caption: f32,
}

impl RenderView {
    /// Loads a scene whose file is in `folder` (`None` for a preset), or says why it cannot be
    /// rendered (the current scene and folder are then kept).
    ///
    /// A scene with large meshes is only checked here: its meshes load in the background
    /// ([`RenderView::update`]), with a progress bar and a Cancel button.
    pub fn load(&mut self, scene: RenderScene, folder: Option<String>) -> Result<(), OpenError> {
        let files = assets(folder.as_deref());
        let prepared = if loads_in_background(&scene, &files) {
            scene.check().map_err(OpenError::Scene)?;
            None
        } else {
            Some(Prepared::new(&scene, &files)?)
        };
        self.folder = folder;
        self.effects = scene.effects.clone();
        // A bug picked for one scene is not carried into the next: its sentence would describe
        // an image the new scene may not show (the acne text over the antialiasing scene).
        self.bug = None;
        self.runtime = Runtime::default();
        if let Some(prepared) = prepared {
            self.runtime.prepared = Some((scene.clone(), Ok(Arc::new(prepared))));
        }
        self.scene = scene;
        self.camera = None;
        self.probed = None;
        Ok(())
    }

    /// Sets the seconds a full render may take, estimated by its trial frame, before it waits for
    /// "Render anyway" (`None`: no limit; the default is `raylab render`'s).
    pub fn set_time_budget(&mut self, seconds: Option<f64>) {
        self.time_budget = seconds;
    }

    /// True while a render runs (or the scene's meshes load).
    pub fn is_rendering(&self) -> bool {
        self.runtime.correct.running.is_some()
            || self.runtime.buggy.running.is_some()
            || self.runtime.loading.is_some()
    }

    /// True while the scene's meshes load.
    pub fn is_loading(&self) -> bool {
        self.runtime.loading.is_some()
    }

    /// The last finished correct render.
    pub fn rendered(&self) -> Option<&Rendered> {
        self.runtime.correct.shown.as_ref().map(|s| &s.rendered)
    }

    /// The last finished render with the bug.
    pub fn rendered_with_bug(&self) -> Option<&Rendered> {
        self.runtime.buggy.shown.as_ref().map(|s| &s.rendered)
    }

    /// The probe of the last clicked pixel.
    pub fn probe(&self) -> Option<&Probe> {
        self.runtime.probe.as_ref()
    }

    /// The probed ray with the triangle (or parallelogram) it met, for the step panel.
    pub fn probed_problem(&self) -> Option<&Action> {
        self.runtime.probed_problem.as_ref()
    }

    /// The ray tree of the probed pixel.
    pub fn ray_tree(&self) -> Option<&RayTree> {
        self.runtime.tree.as_ref()
    }

    /// Draws the view.
    pub fn ui(&mut self, ui: &mut Ui) -> Option<Action> {
        self.update(ui.ctx());
        // A ray of the tree was loaded last frame: now its view opens.
        let pending = self.runtime.pending.take();
        self.controls_ui(ui);
        let mut action = None;
        match self.mode {
            Mode::Image => {
                // The image comes first: on a zoomed projector the text beside or below it
                // scrolls, the image keeps its place.
                self.loading_ui(ui);
                // Beside the image when there is room for a column 18 lines wide and an image 10
                // lines wide (the image gives up width for it, a bug's pair of images does not);
                // below it on a narrow screen or under a wide image.
                // When the image would be small (150% and 200% on a projector), the image and
                // everything below it, the render's summary too, scroll together: the image takes
                // the whole height, as a class needs it.
                let body = ui.text_style_height(&egui::TextStyle::Body);
                let side = 18.0 * body;
                // Below the image: room for the rays by kind, the cost button and a probed pixel.
                let below = 8.5 * body;
                // Room for the summary (three lines), an image of 14 lines and what goes below it;
                // with less (150% and 200% on a projector), the image takes the whole height and
                // the rest scrolls under it.
                if ui.available_height() < 3.0 * body + 14.0 * body + below {
                    let available = ui.available_size();
                    egui::ScrollArea::vertical()
                        .id_salt("render-tight")
                        .auto_shrink([false, false])
                        .show(ui, |ui| {
                            // The summary's first line shows whole under the image: the rest
                            // is a scroll away.
                            let line = body + 2.0 * ui.spacing().item_spacing.y;
                            let room = Vec2::new(available.x, available.y - line);
                            self.images_ui(ui, &mut action, room);
                            self.status_ui(ui);
                            self.details_ui(ui, &mut action, true, false);
                        });
                    return self.finish_ui(ui, action, pending);
                }
                self.status_ui(ui);
                let available = ui.available_size();
                if available.x >= side + 10.0 * body
                    // Two images side by side keep their full size: the column goes below them.
                    && (self.bug.is_none() || self.images_width(ui) + side <= available.x)
                    // One image goes where it is larger, unless the column beside it would shrink
                    // it to two thirds or less (seed 003's 2:1 image): then the column goes below.
                    && self.fit_scale(ui, available - Vec2::new(0.0, below))
                        < 1.45 * self.fit_scale(ui, Vec2::new(available.x - side - 12.0, available.y))
                {
                    let images = self.images_width(ui).min(available.x - side - 12.0);
                    ui.horizontal_top(|ui| {
                        ui.vertical(|ui| {
                            ui.set_width(images);
                            let room = ui.available_size();
                            self.images_ui(ui, &mut action, room);
                        });
                        ui.vertical(|ui| self.details_ui(ui, &mut action, false, true));
                    });
                } else {
                    let room = available - Vec2::new(0.0, below);
                    self.images_ui(ui, &mut action, room);
                    self.details_ui(ui, &mut action, true, true);
                }
            }
            Mode::Spaces => self.spaces_ui(ui),
        }
        self.finish_ui(ui, action, pending)
    }

    /// The frame's action: the one taken, else a ray of the tree loaded last frame.
    fn finish_ui(
        &self,
        ui: &Ui,
        action: Option<Action>,
        pending: Option<Action>,
    ) -> Option<Action> {
        if self.runtime.pending.is_some() {
            ui.ctx().request_repaint();
        }
        action.or(pending)
    }

    /// Beside or below the image: the rays by kind, each effect's cost, the probe and its ray tree.
    /// `compact`: the rays by kind on wrapped lines rather than a table (below the image);
    /// `scroll`: in a scroll area of their own.
    fn details_ui(
        &mut self,
        ui: &mut Ui,
        action: &mut Option<Action>,
        compact: bool,
        scroll: bool,
    ) {
        let mut details = |ui: &mut Ui| {
            self.rays_by_kind_ui(ui, compact);
            self.cost_ui(ui);
            ui.separator();
            if let Some(probed) = self.probe_ui(ui) {
                *action = Some(probed);
            }
        };
        if scroll {
            egui::ScrollArea::vertical()
                .id_salt("render-probe")
                .auto_shrink([false, false])
                .show(ui, details);
        } else {
            details(ui);
        }
    }

    /// How much the images are enlarged when they fit in `room` (below their caption).
    fn fit_scale(&self, ui: &Ui, room: Vec2) -> f32 {
        let grid = self.image_grid(ui);
        let across = (room.x - IMAGE_GAP * (grid.panes - 1.0)) / grid.panes / grid.width;
        across.min((room.y - grid.caption) / grid.height)
    }

    /// The width the images take when they fill the height left (the side column goes beside them
    /// when there is room).
    fn images_width(&self, ui: &Ui) -> f32 {
        let grid = self.image_grid(ui);
        let scale = ((ui.available_height() - grid.caption).max(120.0) / grid.height).max(0.05);
        grid.width * scale * grid.panes + IMAGE_GAP * (grid.panes - 1.0)
    }

    /// The images' layout numbers: the image's size (the scene's), the panes
    /// (two beside a bug) and the caption above each.
    fn image_grid(&self, ui: &Ui) -> ImageGrid {
        // The scene's size: a quick frame, smaller, is shown enlarged to it.
        let (width, height) = (self.scene.width, self.scene.height);
        ImageGrid {
            width: width.max(1) as f32,
            height: height.max(1) as f32,
            panes: if self.bug.is_some() { 2.0 } else { 1.0 },
            // "Correct" and "With the bug: …" above a pair; one image needs no caption.
            caption: if self.bug.is_some() {
                ui.text_style_height(&egui::TextStyle::Body) + ui.spacing().item_spacing.y
            } else {
                0.0
            },
        }
    }

    /// The effects, method and bug (folded under a header on a short view, a projector at 200%,
    /// so the image takes the height), then the camera and the mode.
    fn controls_ui(&mut self, ui: &mut Ui) {
        if ui.available_height() < super::widgets::SHORT_VIEW + 40.0 {
            let on = self.effects.len();
            let summary = format!(
                "Controls: {on} of {} effects on, {}",
                self.scene.effects.len(),
                self.bug
                    .map_or("no bug".to_string(), |bug| format!("bug: {}", bug.name()))
            );
            egui::CollapsingHeader::new(summary)
                .id_salt("render-controls-folded")
                .default_open(false)
                .show(ui, |ui| {
                    self.effects_row(ui);
                    ui.horizontal_wrapped(|ui| self.bug_ui(ui));
                    self.bug_sentence_ui(ui);
                })
                .header_response
                .on_hover_text(
                    "Effects, method and bug: folded to give the image the room on a zoomed screen",
                );
            // The camera's reset and the mode stay out: an orbit or a probe needs them.
            ui.horizontal_wrapped(|ui| self.camera_and_mode_ui(ui));
            return;
        }
        self.effects_row(ui);
        ui.horizontal_wrapped(|ui| {
            self.bug_ui(ui);
            ui.separator();
            self.camera_and_mode_ui(ui);
        });
        self.bug_sentence_ui(ui);
    }

    fn effects_row(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Effects:");
            for effect in self.scene.effects.clone() {
                let mut on = self.effects.contains(&effect);
                if ui
                    .toggle_value(&mut on, effect.name())
                    .on_hover_text(effects::effect_hint(effect, &self.scene))
                    .changed()
                {
                    if on {
                        self.effects.push(effect);
                    } else {
                        self.effects.retain(|e| *e != effect);
                    }
                }
            }
            self.method_ui(ui);
        });
    }

    fn camera_and_mode_ui(&mut self, ui: &mut Ui) {
        self.camera_ui(ui);
        ui.selectable_value(&mut self.mode, Mode::Image, "Image")
            .on_hover_text("The rendered image; click a pixel to probe its ray");
        ui.selectable_value(&mut self.mode, Mode::Spaces, "World vs object space")
            .on_hover_text(
                "The probed ray and object in world space and in the object's own space",
            );
    }

    fn bug_sentence_ui(&self, ui: &mut Ui) {
        if let Some(bug) = self.bug {
            ui.label(RichText::new(bug.sentence()).color(palette::OUTSIDE.readable(ui)));
        }
    }

    /// "Method:" and its box: the scene's, or a float method.
    fn method_ui(&mut self, ui: &mut Ui) {
        let shown = self.method.map_or("scene's", Method::name);
        if label_with_box_fits(ui, "Method:", shown) {
            ui.separator();
        } else {
            ui.end_row();
        }
        let label = ui.label("Method:");
        egui::ComboBox::from_id_salt("render-method")
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.method, None, "scene's")
                        .on_hover_text(
                            "The scene's method: watertight for meshes, Möller–Trumbore otherwise",
                        );
                    for method in Method::FLOAT {
                        let choice =
                            ui.selectable_value(&mut self.method, Some(method), method.name());
                        if method == Method::Watertight {
                            choice.on_hover_text(
                                "For meshes, the crack-free test: exact signs where rounding could \
                                 flip them and a tie rule for rays exactly on an edge, so no ray is \
                                 lost or counted twice between two triangles",
                            );
                        }
                    }
                    ui.selectable_value(
                        &mut self.method,
                        Some(Method::WatertightExact),
                        Method::WatertightExact.name(),
                    )
                    .on_hover_text(
                        "The exact-deciding watertight test the accuracy study and the probe use: \
                         every decision exactly right, with big-integer arithmetic near edges \
                         (slower)",
                    );
                })
                .response
                .labelled_by(label.id)
                .on_hover_text("The ray–triangle test every pixel uses");
    }

    /// "Compare with a bug:" and its box.
    fn bug_ui(&mut self, ui: &mut Ui) {
        let label = ui.label("Compare with a bug:");
        egui::ComboBox::from_id_salt("render-bug")
            .selected_text(self.bug.map_or("none", Bug::name))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut self.bug, None, "none");
                for bug in <Bug as strum::IntoEnumIterator>::iter() {
                    ui.selectable_value(&mut self.bug, Some(bug), bug.name())
                        .on_hover_text(bug.sentence());
                }
            })
            .response
            .labelled_by(label.id)
            .on_hover_text("Render the same scene with a common mistake, beside the correct image");
    }

    /// Stops the renders in flight (a dropped job stops after its band); they start again when a
    /// choice changes.
    fn cancel_renders(&mut self) {
        for slot in [&mut self.runtime.correct, &mut self.runtime.buggy] {
            if let Some((key, _)) = slot.running.take() {
                slot.failed = Some(key);
                slot.error =
                    Some("cancelled (change the scene or a choice to render again)".into());
            }
        }
    }

    fn status_ui(&mut self, ui: &mut Ui) {
        if let Some(past) = self.runtime.past_budget {
            ui.label(RichText::new(past.sentence()).color(palette::OUTSIDE.readable(ui)));
            if ui
                .button("Render anyway")
                .on_hover_text("Start this render although it may take hours; Cancel stops it")
                .clicked()
            {
                self.runtime.budget_waived = Some(self.scene.clone());
                self.runtime.past_budget = None;
                self.runtime.correct.failed = None;
                self.runtime.buggy.failed = None;
            }
        }
        let slot = &self.runtime.correct;
        if let Some(error) = slot.error.as_ref().or(self.runtime.buggy.error.as_ref()) {
            ui.label(
                RichText::new(format!("Cannot render: {error}"))
                    .color(palette::OUTSIDE.readable(ui)),
            );
        }
        // Quick frames while the camera moves come too fast for a progress bar.
        if let Some((key, job)) = &slot.running
            && key.draft.is_none()
        {
            let (done, total) = job.progress();
            // Before its first band the job has not said how many rows there are.
            let text = if done == 0 && total <= 1 {
                format!("rendering… {} rows", self.scene.height)
            } else {
                format!("rendering… row {done} of {total}")
            };
            let mut cancel = false;
            ui.horizontal(|ui| {
                cancel = ui
                    .button("Cancel")
                    .on_hover_text(
                        "Stop this render (any change to the scene or a choice renders again)",
                    )
                    .clicked();
                ui.add(egui::ProgressBar::new(done as f32 / total as f32).text(text));
            });
            if cancel {
                self.cancel_renders();
                return;
            }
        }
        let slot = &self.runtime.correct;
        let Some(shown) = &slot.shown else {
            return;
        };
        let stats = &shown.rendered.stats;
        let method = self
            .method
            .map_or_else(|| self.scene_method_label(), |m| m.name().to_string());
        // One line, the counters of the work done a click away: the image needs the height.
        let counters: Vec<String> = stats
            .counters()
            .iter()
            .skip(1)
            .map(|(name, value)| format!("{name} {value}"))
            .collect();
        // The summary wraps; the counters are one click away below it.
        let summary = format!(
            "{}: {} of {} pixels hit",
            self.frame_summary(&shown.rendered, shown.key.draft),
            stats.hits,
            stats.rays
        );
        ui.add(egui::Label::new(RichText::new(summary).strong()).wrap());
        egui::CollapsingHeader::new("work done")
            .id_salt("render-work")
            .show(ui, |ui| {
                ui.label(format!("Method: {method}."));
                ui.label(RichText::new(counters.join(" · ")).weak());
            })
            .header_response
            .on_hover_text(
                "The method and the work the render did: an effect that is off costs zero",
            );
    }

    fn scene_method_label(&self) -> String {
        match self.scene.method {
            Some(method) => method.0.name().into(),
            None => "the default (watertight for meshes, moller-trumbore otherwise)".into(),
        }
    }

    /// The image (and the bug's image beside it); a click probes a pixel.
    fn images_ui(&mut self, ui: &mut Ui, action: &mut Option<Action>, room: Vec2) {
        let Some(shown) = &self.runtime.correct.shown else {
            // A render that waits for "Render anyway" (or failed) is said so by the status above.
            if self.runtime.correct.running.is_some() {
                ui.label("Rendering…");
            }
            return;
        };
        let (width, height) = (shown.rendered.image.width, shown.rendered.image.height);
        let grid = self.image_grid(ui);
        // `room` holds the caption above and the image, but never a thumbnail.
        let available = room - Vec2::new(0.0, grid.caption);
        let available = Vec2::new(available.x, available.y.max(120.0));
        let scale = ((available.x - IMAGE_GAP * (grid.panes - 1.0)) / grid.panes / grid.width)
            .min(available.y / grid.height)
            .max(0.05);
        let size = Vec2::new(grid.width, grid.height) * scale;
        let probed = self.probed;
        let mut clicked = None;
        let mut motion = orbit::Motion::default();
        let movable = self.camera_moves();
        let moving = self.runtime.orbit.moving();
        let bug = self.bug;
        ui.horizontal_top(|ui| {
            ui.spacing_mut().item_spacing.x = IMAGE_GAP;
            for (slot, title) in [
                (&self.runtime.correct, "Correct".to_string()),
                (
                    &self.runtime.buggy,
                    format!("With the bug: {}", self.bug.map_or("", Bug::name)),
                ),
            ] {
                if title.starts_with("With") && self.bug.is_none() {
                    continue;
                }
                let bug_slot = title.starts_with("With");
                ui.vertical(|ui| {
                    if bug.is_some() {
                        ui.label(RichText::new(&title).strong());
                    }
                    // While a new render runs, the old image belongs to other choices: the bug's
                    // image of another bug is not shown at all, the correct one is marked. While
                    // the camera moves, the bug's image of the same bug stays up, a frame behind.
                    let stale = slot.running.is_some();
                    let same_bug = slot.shown.as_ref().is_some_and(|s| s.key.bug == bug);
                    let shown = match &slot.shown {
                        Some(shown) if !(stale && bug_slot) || (moving && same_bug) => shown,
                        _ => {
                            rendering_placeholder(ui, size);
                            return;
                        }
                    };
                    let quick = shown.key.draft.is_some();
                    let hint = match (movable, quick) {
                        (_, true) => "A quick frame while the camera moves: the full image follows",
                        (true, false) => {
                            "Click a pixel to probe its ray; drag to orbit, Shift-drag to pan, \
                             scroll to move nearer"
                        }
                        (false, false) => "Click a pixel to probe its ray",
                    };
                    // One id whatever the layout around it (it changes while the camera
                    // moves), so the keyboard focus stays on the image.
                    let (rect, _) = ui.allocate_exact_size(size, Sense::hover());
                    egui::Image::new((shown.texture.id(), size)).paint_at(ui, rect);
                    let id = egui::Id::unique(("raylab-render-image", bug_slot));
                    let response = ui
                        .interact(rect, id, Sense::click_and_drag())
                        .on_hover_text(hint);
                    // The image focused: Shift + arrows move the probed pixel a pixel at a
                    // time, Enter probes (first the centre): read before the plain arrows orbit.
                    if !quick
                        && let Some(pixel) = probe_keys(ui, &response, probed, (height, width))
                    {
                        clicked = Some((pixel, bug_slot));
                    }
                    motion.read(ui, &response, movable);
                    let name = format!("{title} render");
                    response
                        .widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &name));
                    let to_pixel = |pos: egui::Pos2| {
                        let local = (pos - response.rect.min) / scale;
                        let (column, row) = (local.x.floor(), local.y.floor());
                        (column >= 0.0
                            && row >= 0.0
                            && (column as usize) < width
                            && (row as usize) < height)
                            .then_some((row as usize, column as usize))
                    };
                    // A quick frame's pixels are not the image's: only a full one is probed.
                    if response.clicked()
                        && !quick
                        && let Some(pixel) = response.interact_pointer_pos().and_then(to_pixel)
                    {
                        clicked = Some((pixel, bug_slot));
                    }
                    // While the camera moves, every frame is a step behind it: no band.
                    if stale && !moving && !quick {
                        rendering_band(ui, response.rect);
                    }
                    if let Some((row, column)) = probed {
                        let center = response.rect.min
                            + Vec2::new(column as f32 + 0.5, row as f32 + 0.5) * scale;
                        let painter = ui.painter_at(response.rect);
                        painter.circle_stroke(center, 7.0, Stroke::new(2.5, Color32::WHITE));
                        painter.circle_stroke(center, 9.0, Stroke::new(1.5, Color32::BLACK));
                    }
                });
            }
        });
        self.apply_motion(motion, ui.input(|i| i.time));
        if let Some((pixel, bug_slot)) = clicked {
            *action = self.probe_pixel_in(pixel, if bug_slot { self.bug } else { None });
        }
    }
}

/// The pixel the keys probe on a focused image, if any: Shift + arrows step from the probed pixel
/// (the centre before any), Enter probes it as it stands.
fn probe_keys(
    ui: &Ui,
    response: &egui::Response,
    probed: Option<(usize, usize)>,
    (height, width): (usize, usize),
) -> Option<(usize, usize)> {
    use egui::{Key, Modifiers};
    if !response.has_focus() || height == 0 || width == 0 {
        return None;
    }
    let (row, column) = probed.unwrap_or((height / 2, width / 2));
    ui.input_mut(|i| {
        let moved = super::widgets::handles::arrows(i, Modifiers::SHIFT);
        let (right, down) = (moved.x as i64, -moved.y as i64);
        let enter = i.consume_key(Modifiers::NONE, Key::Enter);
        let step =
            |at: usize, by: i64, size: usize| (at as i64 + by).clamp(0, size as i64 - 1) as usize;
        (right != 0 || down != 0 || enter)
            .then(|| (step(row, down, height), step(column, right, width)))
    })
}

/// Where an image is being rendered and none is right to show yet: an empty frame that says so (the
/// progress bar above counts the rows; nothing here animates, so an idle app draws no frames).
/// In a wrapping row: whether a separator, `label` and a combo box showing `choice` fit in what is
/// left of this one (else the caller starts the next row, so that a label never ends a row with its
/// box alone on the next).
fn label_with_box_fits(ui: &Ui, label: &str, choice: &str) -> bool {
    let width = |text: &str| {
        egui::WidgetText::from(text)
            .into_galley(
                ui,
                Some(egui::TextWrapMode::Extend),
                f32::INFINITY,
                egui::TextStyle::Button,
            )
            .size()
            .x
    };
    let spacing = ui.spacing();
    let choice = width(choice) + spacing.icon_width + spacing.icon_spacing;
    let combo = spacing.combo_width.max(choice) + 2.0 * spacing.button_padding.x;
    // What is left of this row (a wrapping row's available width is the whole row's).
    let left = ui.max_rect().max.x - ui.cursor().min.x;
    let separator = 2.0 * spacing.item_spacing.x + 1.0;
    left >= separator + width(label) + spacing.item_spacing.x + combo
}

fn rendering_placeholder(ui: &mut Ui, size: Vec2) {
    let (rect, _) = ui.allocate_exact_size(size, Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_stroke(
        rect,
        4.0,
        Stroke::new(1.0, ui.visuals().weak_text_color()),
        egui::StrokeKind::Inside,
    );
    ui.put(
        egui::Rect::from_center_size(rect.center(), Vec2::new(rect.width(), 40.0)),
        |ui: &mut Ui| ui.centered_and_justified(|ui| ui.label("rendering…")).inner,
    );
}

/// A band across the top of an image that is being rendered again: it shows the previous choices.
fn rendering_band(ui: &Ui, rect: egui::Rect) {
    let band = egui::Rect::from_min_size(rect.min, Vec2::new(rect.width(), 26.0));
    let painter = ui.painter_at(rect);
    painter.rect_filled(
        band,
        0.0,
        ui.visuals().extreme_bg_color.gamma_multiply(0.85),
    );
    // The long note where it fits, else the short one: a small image (zoomed in) clips no words.
    let font = egui::TextStyle::Body.resolve(ui.style());
    let color = ui.visuals().text_color();
    let room = band.width() - 16.0;
    let galley = ["rendering… (the previous image)", "rendering…"]
        .into_iter()
        .map(|text| painter.layout_no_wrap(text.into(), font.clone(), color))
        .find(|galley| galley.size().x <= room);
    if let Some(galley) = galley {
        let at = band.left_center() + Vec2::new(8.0, -galley.size().y / 2.0);
        painter.galley(at, galley, color);
    }
}
