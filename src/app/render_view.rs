//! The Render view: a scene rendered one ray per pixel, with the scene's effects as toggles, the method,
//! the timing and work of the last render, a common bug rendered beside the correct image, a pixel probe
//! that loads a pixel's ray into the Triangle view, and the probed ray in world and object space.
//!
//! Renders run as a [`Job`] (a thread natively, slices of frames on the web) and only when something
//! they depend on changed.

use super::view::{ActiveSolve, Request, View, not_mine};
use super::widgets::palette::Readable as _;
use super::{ViewKind, parallelogram_view, triangle_view};
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
use crate::render::assets::{AssetSource, OnDisk};
use crate::render::objects::Geometry;
use crate::render::probe::{Probe, probe};
use crate::render::scene_load::{SceneLoad, UNITS_PER_MESH, mesh_names};
use crate::render::{Bug, Prepared, RenderJob, Rendered};
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
    #[serde(skip)]
    runtime: Runtime,
}

/// What is not saved: the prepared scene, the jobs, the images, the probe.
#[derive(Default)]
struct Runtime {
    prepared: Option<(RenderScene, Result<Arc<Prepared>, String>)>,
    /// A scene with large meshes being prepared in the background.
    loading: Option<Loading>,
    correct: Slot,
    buggy: Slot,
    probe: Option<Probe>,
    /// What the probe was made under: it is redone when that changes.
    probe_key: Option<Choices>,
    /// The probed ray with what it met, as the problem its steps are shown for.
    probed_problem: Option<Action>,
}

/// A copy starts without images: they render again when it is shown.
impl Clone for Runtime {
    fn clone(&self) -> Runtime {
        Runtime::default()
    }
}

impl std::fmt::Debug for Runtime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Runtime")
            .field(
                "rendering",
                &(self.correct.running.is_some() || self.buggy.running.is_some()),
            )
            .finish_non_exhaustive()
    }
}

/// A scene being prepared in the background, its meshes loading with their progress.
struct Loading {
    /// The scene it is for.
    key: RenderScene,
    /// Its mesh files, in the order they load.
    meshes: Vec<String>,
    job: Job<Result<Prepared, String>>,
}

/// Meshes larger than this in all load in the background, with a progress bar and Cancel; smaller
/// ones load at once (in well under a second).
const BACKGROUND_MESH_BYTES: u64 = 4 << 20;

/// True if the scene's meshes are found and large enough to load in the background (a missing or
/// refused one is reported at once, by the plain preparation).
fn loads_in_background(scene: &RenderScene, assets: &OnDisk) -> bool {
    let mut total = 0;
    for name in mesh_names(scene) {
        match assets.size(&name, crate::files::MESH) {
            Ok(size) => total += size,
            Err(_) => return false,
        }
    }
    total > BACKGROUND_MESH_BYTES
}

/// One image: the render in flight and the one shown.
#[derive(Default)]
struct Slot {
    running: Option<(Choices, Job<Rendered>)>,
    shown: Option<Shown>,
    error: Option<String>,
    /// The choices whose render failed inside (a panic): not started again until they change.
    failed: Option<Choices>,
}

/// What a render (or a probe) depends on: it is made again when any of these change.
#[derive(Clone, Debug, PartialEq)]
struct Choices {
    scene: RenderScene,
    effects: Vec<Effect>,
    method: Option<Method>,
    /// The bug of the second image; for a probe, none.
    bug: Option<Bug>,
    /// The probed pixel (probes only).
    pixel: Option<(usize, usize)>,
}

/// A finished render on screen.
struct Shown {
    key: Choices,
    rendered: Rendered,
    texture: TextureHandle,
}

impl View for RenderView {
    fn kind(&self) -> ViewKind {
        ViewKind::Render
    }

    fn open(&mut self, problem: &Problem, folder: Option<String>) -> Result<(), String> {
        let Problem::Render(scene) = problem else {
            return Err(not_mine(self.kind()));
        };
        self.load(scene.clone(), folder)
    }

    fn problem(&self) -> Option<Problem> {
        Some(Problem::Render(self.scene.clone()))
    }

    /// The probed pixel's ray against what it met (or came nearest to): the step panel shows its
    /// steps, judged as the renderer saw it (exact arithmetic on the floats themselves for a triangle).
    fn solve_frame(&self, precision: Precision) -> ActiveSolve {
        match self.probed_problem() {
            Some(Action::Triangle(scene)) => ActiveSolve::Triangle(triangle_view::Solved::new(
                (scene.vectors(), scene.t_min),
                Reading::FloatValue,
                precision,
            )),
            Some(Action::Parallelogram(scene)) => ActiveSolve::Parallelogram(
                parallelogram_view::Solved::new(scene.vectors(), Reading::AsWritten, precision),
            ),
            _ => ActiveSolve::Nothing,
        }
    }

    fn frame_ui(
        &mut self,
        ui: &mut Ui,
        _solved: &ActiveSolve,
        _canvas_only: bool,
    ) -> Option<Request> {
        self.ui(ui).map(Request::Render)
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

impl RenderView {
    /// Loads a scene whose file is in `folder` (`None` for a preset), or says why it cannot be
    /// rendered (the current scene and folder are then kept).
    ///
    /// A scene with large meshes is only checked here: its meshes load in the background
    /// ([`RenderView::update`]), with a progress bar and a Cancel button.
    pub fn load(&mut self, scene: RenderScene, folder: Option<String>) -> Result<(), String> {
        let files = assets(folder.as_deref());
        let prepared = if loads_in_background(&scene, &files) {
            scene.check()?;
            None
        } else {
            Some(Prepared::new(&scene, &files)?)
        };
        self.folder = folder;
        self.effects = scene.effects.clone();
        self.runtime = Runtime::default();
        if let Some(prepared) = prepared {
            self.runtime.prepared = Some((scene.clone(), Ok(Arc::new(prepared))));
        }
        self.scene = scene;
        self.probed = None;
        Ok(())
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

    /// The scene prepared with the current choices (and a bug), or why not.
    #[allow(clippy::expect_used, reason = "the slot was filled just above")]
    fn prepared(&mut self, bug: Option<Bug>) -> Result<Arc<Prepared>, String> {
        let key = self.scene.clone();
        if self
            .runtime
            .prepared
            .as_ref()
            .is_none_or(|(k, _)| *k != key)
        {
            if self.runtime.loading.as_ref().is_some_and(|l| l.key == key) {
                return Err("the scene's meshes are still loading".into());
            }
            let prepared =
                Prepared::new(&self.scene, &assets(self.folder.as_deref())).map(Arc::new);
            self.runtime.prepared = Some((key, prepared));
        }
        let (_, prepared) = self.runtime.prepared.as_ref().expect("just prepared");
        let mut prepared = Prepared::clone(prepared.as_ref().map_err(Clone::clone)?);
        prepared.effects = self.effects.clone();
        prepared.method = self.method.or(prepared.method);
        prepared.bug = bug;
        Ok(Arc::new(prepared))
    }

    /// Starts renders whose inputs changed and takes finished ones; asks for frames while running.
    #[allow(
        clippy::expect_used,
        reason = "the slot's job was running: it just finished"
    )]
    pub fn update(&mut self, ctx: &egui::Context) {
        if self.poll_loading(ctx) {
            return;
        }
        let key = |bug: Option<Bug>| Choices {
            scene: self.scene.clone(),
            effects: self.effects.clone(),
            method: self.method,
            bug,
            pixel: None,
        };
        let correct_key = key(None);
        let buggy_key = self.bug.map(|b| key(Some(b)));
        for (which, wanted) in [(false, Some(correct_key)), (true, buggy_key)] {
            let bug = if which { self.bug } else { None };
            let Some(wanted) = wanted else {
                self.runtime.buggy = Slot::default();
                continue;
            };
            let slot = if which {
                &self.runtime.buggy
            } else {
                &self.runtime.correct
            };
            let current = slot
                .running
                .as_ref()
                .map(|(k, _)| k)
                .or(slot.shown.as_ref().map(|s| &s.key));
            if current != Some(&wanted) && slot.failed.as_ref() != Some(&wanted) {
                let started = self.prepared(bug).and_then(|prepared| {
                    let waker = ctx.clone();
                    Job::start("raylab-render", RenderJob::new(prepared), move || {
                        waker.request_repaint()
                    })
                });
                let slot = if which {
                    &mut self.runtime.buggy
                } else {
                    &mut self.runtime.correct
                };
                match started {
                    Ok(job) => {
                        slot.running = Some((wanted, job));
                        slot.error = None;
                    }
                    Err(error) => {
                        slot.running = None;
                        slot.error = Some(error);
                    }
                }
            }
        }
        for (name, slot) in [
            ("render", &mut self.runtime.correct),
            ("render-bug", &mut self.runtime.buggy),
        ] {
            if let Some(failure) = slot.running.as_ref().and_then(|(_, job)| job.failure()) {
                let (key, _) = slot.running.take().expect("running");
                slot.error = Some(format!(
                    "the render stopped on an internal error: {failure}"
                ));
                slot.failed = Some(key);
                continue;
            }
            let finished = slot.running.as_mut().and_then(|(_, job)| job.poll());
            if let Some(rendered) = finished {
                let (key, _) = slot.running.take().expect("running");
                let image = &rendered.image;
                let pixels = ColorImage::from_rgb([image.width, image.height], &image.to_rgb8());
                let texture = ctx.load_texture(name, pixels, TextureOptions::NEAREST);
                slot.shown = Some(Shown {
                    key,
                    rendered,
                    texture,
                });
            }
        }
        if self.is_rendering() {
            ctx.request_repaint();
        }
        // A probe follows the choices it was made under.
        if self.probed.is_some() && self.runtime.probe_key.as_ref() != Some(&self.probe_key()) {
            self.reprobe();
        }
    }

    /// Starts the background preparation of a scene with large meshes, or takes its result; true
    /// while it runs (nothing renders until it is done).
    fn poll_loading(&mut self, ctx: &egui::Context) -> bool {
        let key = self.scene.clone();
        if self
            .runtime
            .prepared
            .as_ref()
            .is_some_and(|(k, _)| *k == key)
        {
            self.runtime.loading = None;
            return false;
        }
        if self.runtime.loading.as_ref().is_none_or(|l| l.key != key) {
            self.runtime.loading = None;
            let files = assets(self.folder.as_deref());
            if !loads_in_background(&self.scene, &files) {
                return false;
            }
            let waker = ctx.clone();
            let work = SceneLoad::new(self.scene.clone(), files);
            match Job::start("raylab-load", work, move || waker.request_repaint()) {
                Ok(job) => {
                    let meshes = mesh_names(&self.scene);
                    self.runtime.loading = Some(Loading {
                        key: key.clone(),
                        meshes,
                        job,
                    });
                }
                Err(error) => {
                    self.runtime.prepared = Some((key, Err(error)));
                    return false;
                }
            }
        }
        let Some(loading) = self.runtime.loading.as_mut() else {
            return false;
        };
        let finished = match loading.job.failure() {
            Some(failure) => Some(Err(format!(
                "loading the scene stopped on an internal error: {failure}"
            ))),
            None => loading.job.poll(),
        };
        if let Some(result) = finished {
            self.runtime.loading = None;
            self.runtime.prepared = Some((key, result.map(Arc::new)));
            return false;
        }
        // On the web the work runs in poll, a slice a frame: ask for the next frame.
        if !crate::platform::THREADS {
            ctx.request_repaint();
        }
        true
    }

    /// The load's progress bar and its Cancel button; a cancelled load leaves the scene unrendered,
    /// with a note saying so.
    fn loading_ui(&mut self, ui: &mut Ui) {
        let Some(loading) = &self.runtime.loading else {
            return;
        };
        let (done, total) = loading.job.progress();
        let count = loading.meshes.len();
        let index = (done / UNITS_PER_MESH).min(count.saturating_sub(1));
        let text = if done / UNITS_PER_MESH >= count {
            "preparing the scene…".to_string()
        } else {
            format!(
                "loading mesh {} of {count} ({})… {}%",
                index + 1,
                loading.meshes[index],
                done % UNITS_PER_MESH * 100 / UNITS_PER_MESH
            )
        };
        let mut cancel = false;
        ui.horizontal(|ui| {
            cancel = ui
                .button("Cancel")
                .on_hover_text("Stop loading the scene's meshes")
                .clicked();
            ui.add(egui::ProgressBar::new(done as f32 / total as f32).text(text));
        });
        if cancel {
            let key = loading.key.clone();
            self.runtime.loading = None;
            self.runtime.prepared = Some((
                key,
                Err(
                    "the load of its meshes was cancelled (open the scene again to load it)".into(),
                ),
            ));
        }
    }

    /// The choices a probe depends on.
    fn probe_key(&self) -> Choices {
        Choices {
            scene: self.scene.clone(),
            effects: self.effects.clone(),
            method: self.method,
            bug: None,
            pixel: self.probed,
        }
    }

    /// Casts the probed pixel's ray again under the current choices.
    fn reprobe(&mut self) {
        self.runtime.probe_key = Some(self.probe_key());
        let (probe, problem) = match (self.probed, self.prepared(None)) {
            (Some((row, column)), Ok(prepared))
                if row < prepared.height && column < prepared.width =>
            {
                let result = probe(&prepared, row, column);
                let problem = probed_problem(&prepared, &result);
                (Some(result), problem)
            }
            _ => (None, None),
        };
        self.runtime.probe = probe;
        self.runtime.probed_problem = problem;
    }

    /// The probed ray with the triangle (or parallelogram) it met, for the step panel.
    pub fn probed_problem(&self) -> Option<&Action> {
        self.runtime.probed_problem.as_ref()
    }

    /// Draws the view.
    pub fn ui(&mut self, ui: &mut Ui) -> Option<Action> {
        self.update(ui.ctx());
        self.controls_ui(ui);
        let mut action = None;
        match self.mode {
            Mode::Image => {
                // The image comes first: on a zoomed projector the text below it scrolls, the
                // image keeps its place.
                self.loading_ui(ui);
                self.status_ui(ui);
                let below = 4.5 * ui.text_style_height(&egui::TextStyle::Body);
                self.images_ui(ui, &mut action, below);
                egui::ScrollArea::vertical()
                    .id_salt("render-probe")
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        if let Some(probed) = self.probe_ui(ui) {
                            action = Some(probed);
                        }
                    });
            }
            Mode::Spaces => self.spaces_ui(ui),
        }
        action
    }

    fn controls_ui(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Effects:");
            for effect in self.scene.effects.clone() {
                let mut on = self.effects.contains(&effect);
                if ui
                    .toggle_value(&mut on, effect.name())
                    .on_hover_text(effect.explanation())
                    .changed()
                {
                    if on {
                        self.effects.push(effect);
                    } else {
                        self.effects.retain(|e| *e != effect);
                    }
                }
            }
            ui.separator();
            let label = ui.label("Method:");
            let shown = self.method.map_or("scene's", Method::name);
            egui::ComboBox::from_id_salt("render-method")
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.method, None, "scene's")
                        .on_hover_text(
                            "The scene's method: watertight for meshes, Möller–Trumbore otherwise",
                        );
                    for method in Method::FLOAT {
                        ui.selectable_value(&mut self.method, Some(method), method.name());
                    }
                })
                .response
                .labelled_by(label.id)
                .on_hover_text("The ray–triangle test every pixel uses");
        });
        ui.horizontal_wrapped(|ui| {
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
                .on_hover_text(
                    "Render the same scene with a common mistake, beside the correct image",
                );
            ui.separator();
            ui.selectable_value(&mut self.mode, Mode::Image, "Image")
                .on_hover_text("The rendered image; click a pixel to probe its ray");
            ui.selectable_value(&mut self.mode, Mode::Spaces, "World vs object space")
                .on_hover_text(
                    "The probed ray and object in world space and in the object's own space",
                );
        });
        if let Some(bug) = self.bug {
            ui.label(RichText::new(bug.sentence()).color(palette::OUTSIDE.readable(ui)));
        }
    }

    fn status_ui(&self, ui: &mut Ui) {
        let slot = &self.runtime.correct;
        if let Some(error) = slot.error.as_ref().or(self.runtime.buggy.error.as_ref()) {
            ui.label(
                RichText::new(format!("Cannot render: {error}"))
                    .color(palette::OUTSIDE.readable(ui)),
            );
        }
        if let Some((_, job)) = &slot.running {
            let (done, total) = job.progress();
            ui.add(
                egui::ProgressBar::new(done as f32 / total as f32)
                    .text(format!("rendering… row {done} of {total}")),
            );
        }
        let Some(shown) = &slot.shown else {
            return;
        };
        let Rendered {
            image,
            stats,
            seconds,
        } = &shown.rendered;
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
            "{}×{} in {:.1} ms: {} of {} pixels hit",
            image.width,
            image.height,
            seconds * 1e3,
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
    fn images_ui(&mut self, ui: &mut Ui, action: &mut Option<Action>, below: f32) {
        let Some(shown) = &self.runtime.correct.shown else {
            ui.label("Rendering…");
            return;
        };
        let (width, height) = (shown.rendered.image.width, shown.rendered.image.height);
        let panes = if self.bug.is_some() { 2.0 } else { 1.0 };
        let gap = 12.0;
        // Room for the caption above and for `below` under the image, but never a thumbnail.
        let caption = ui.text_style_height(&egui::TextStyle::Body) + ui.spacing().item_spacing.y;
        let available = ui.available_size() - Vec2::new(0.0, caption + below);
        let available = Vec2::new(available.x, available.y.max(120.0));
        let scale = ((available.x - gap * (panes - 1.0)) / panes / width as f32)
            .min(available.y / height as f32)
            .max(0.05);
        let size = Vec2::new(width as f32, height as f32) * scale;
        let probed = self.probed;
        let mut clicked = None;
        ui.horizontal_top(|ui| {
            ui.spacing_mut().item_spacing.x = gap;
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
                    ui.label(RichText::new(&title).strong());
                    // While a new render runs, the old image belongs to other choices: the bug's
                    // image of another bug is not shown at all, the correct one is marked.
                    let stale = slot.running.is_some();
                    let shown = match &slot.shown {
                        Some(shown) if !(stale && bug_slot) => shown,
                        _ => {
                            rendering_placeholder(ui, size);
                            return;
                        }
                    };
                    let response = ui
                        .add(egui::Image::new((shown.texture.id(), size)).sense(Sense::click()))
                        .on_hover_text("Click a pixel to probe its ray");
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
                    if response.clicked()
                        && let Some(pixel) = response.interact_pointer_pos().and_then(to_pixel)
                    {
                        clicked = Some(pixel);
                    }
                    if stale {
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
        if let Some(pixel) = clicked {
            *action = self.probe_pixel(pixel);
        }
    }

    /// Probes a pixel; the hit (or nearest missed) primitive goes to its view.
    pub fn probe_pixel(&mut self, pixel: (usize, usize)) -> Option<Action> {
        self.probed = Some(pixel);
        self.reprobe();
        self.runtime.probed_problem.clone()
    }

    /// What the probe found, and a button to the view that shows its steps.
    fn probe_ui(&self, ui: &mut Ui) -> Option<Action> {
        let Some(probe) = &self.runtime.probe else {
            ui.label(
                RichText::new(
                    "Click a pixel: its ray goes into the Triangle view and the step panel.",
                )
                .weak(),
            );
            return None;
        };
        let vector = |v: &[f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
        let (row, column) = probe.pixel;
        let mut action = None;
        let in_image = self
            .rendered()
            .and_then(|r| r.image.covered.get(row * r.image.width + column).copied());
        if in_image.is_some_and(|covered| covered != probe.hit.is_some()) {
            ui.label(
                RichText::new(
                    "On this edge pixel the image and the probe disagree: the image took the fast \
                     path (Möller–Trumbore in f32, a row at a time), the probe casts in f64.",
                )
                .color(palette::OUTSIDE.readable(ui)),
            );
        }
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(format!("Pixel ({row}, {column})")).strong());
            ui.label(format!(
                "O = {}  D = {}",
                vector(&probe.origin),
                vector(&probe.dir)
            ));
        });
        ui.horizontal_wrapped(|ui| {
            match probe.hit {
                Some(hit) => {
                    let kind = self.object_kind(hit.object);
                    let names = if kind == "parallelogram" {
                        ("α", "β")
                    } else {
                        ("β", "γ")
                    };
                    ui.label(
                        RichText::new(format!(
                            "hit object {} ({kind}), triangle {}: t = {:.6}, {} = {:.6}, {} = {:.6}",
                            hit.object + 1,
                            hit.primitive,
                            hit.t,
                            names.0,
                            hit.beta,
                            names.1,
                            hit.gamma
                        ))
                        .color(palette::INSIDE.readable(ui)),
                    );
                    if let Some(facing) = probe.facing {
                        ui.label(format!("facing ratio n̂·(−ê) = {facing:.4}"));
                    }
                    let [r, g, b] = probe.color.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
                    ui.label(format!("colour ({r}, {g}, {b})"));
                    let (rect, _) = ui.allocate_exact_size(Vec2::splat(16.0), Sense::hover());
                    ui.painter().rect_filled(rect, 2.0, Color32::from_rgb(r, g, b));
                }
                None => {
                    let text = match probe.nearest_miss {
                        Some((object, triangle)) => format!(
                            "missed everything; the nearest is object {} triangle {triangle}: \
                             the step panel says why",
                            object + 1
                        ),
                        None => "missed everything: no triangle to show".into(),
                    };
                    ui.label(RichText::new(text).color(palette::OUTSIDE.readable(ui)));
                }
            }
            let target = match probe.triangle {
                Some(_) => Some(super::ViewKind::Triangle),
                None if probe.hit.is_some() => Some(super::ViewKind::Parallelogram),
                None => None,
            };
            if let Some(kind) = target
                && ui
                    .button(format!("Open in {} →", kind.label()))
                    .on_hover_text("The same ray and primitive, with sliders and every step")
                    .clicked()
            {
                action = Some(Action::Open(kind));
            }
        });
        action
    }

    fn object_kind(&self, index: usize) -> &'static str {
        match self.scene.objects.get(index).map(|o| &o.shape) {
            Some(crate::scene::render::Shape::Triangle { .. }) => "triangle",
            Some(crate::scene::render::Shape::Parallelogram { .. }) => "parallelogram",
            Some(crate::scene::render::Shape::Mesh { .. }) => "mesh",
            None => "?",
        }
    }

    /// The probed ray and its object in world space and in object space, side by side.
    fn spaces_ui(&mut self, ui: &mut Ui) {
        let Some(probe) = self.runtime.probe.clone() else {
            ui.label("Click a pixel in the image first (try the transformed-object preset): its ray and the triangle it meets are drawn here in both spaces.");
            return;
        };
        let Ok(prepared) = self.prepared(None) else {
            return;
        };
        let target = probe
            .hit
            .map(|h| (h.object, h.primitive))
            .or(probe.nearest_miss);
        let Some((index, primitive)) = target else {
            ui.label("The probed ray met no triangle: probe another pixel.");
            return;
        };
        let object = &prepared.objects[index];
        let object_vertices = match &object.geometry {
            Geometry::Triangles { triangles, .. } => triangles[primitive].vertices,
            Geometry::Parallelogram { corner, e1, e2, .. } => [
                *corner,
                crate::math::linalg::add(corner, e1),
                crate::math::linalg::add(corner, e2),
            ],
        };
        let world_vertices = object_vertices.map(|v| {
            object
                .object_to_world
                .transform_point3(DVec3::from(v))
                .to_array()
        });
        let mut stats = crate::render::Stats::default();
        let (object_origin, object_dir) =
            crate::render::cast::to_object_space(object, probe.origin, probe.dir, None, &mut stats);
        let t = probe.hit.map(|h| h.t);
        let transformed = object.world_to_object.is_some();
        ui.label(if transformed {
            "The ray goes into object space as O' = M⁻¹O (a point) and D' = M⁻¹D (a direction, not normalised), so O' + tD' = M⁻¹(O + tD): the same t in both spaces."
        } else {
            "This object has no transform: object space is world space. Probe the stretched sphere of the transformed-object preset to see the two differ."
        });
        let half = (ui.available_width() - 12.0) / 2.0;
        let height = (ui.available_height() - 130.0).max(160.0);
        ui.horizontal_top(|ui| {
            for (title, vertices, origin, dir) in [
                ("World space", world_vertices, probe.origin, probe.dir),
                ("Object space", object_vertices, object_origin, object_dir),
            ] {
                ui.vertical(|ui| {
                    ui.set_width(half);
                    ui.label(RichText::new(title).strong());
                    // Each space solves its own problem (Cramer, f64, the t where the ray meets the
                    // plane): the t shown is not copied from the other side.
                    let own = crate::intersect::Method::Cramer.run(&crate::intersect::Case {
                        tri: vertices,
                        origin,
                        dir,
                    });
                    let t = own.values.filter(|_| t.is_some()).map(|[t, _, _]| t);
                    draw_space(ui, Vec2::new(half, height), vertices, origin, dir, t);
                    let v = |p: [f64; 3]| format!("({:.3}, {:.3}, {:.3})", p[0], p[1], p[2]);
                    ui.label(format!(
                        "origin {}, direction {} (|D| = {:.4})",
                        v(origin),
                        v(dir),
                        norm_f64(&dir)
                    ));
                    if let Some(t) = t {
                        let point = add(&origin, &scale(&t, &dir));
                        ui.label(format!("t = {t:.6}, hit point {}", v(point)));
                    }
                });
            }
        });
        if let Some(t) = t
            && transformed
        {
            ui.label(
                RichText::new(format!(
                    "Normalising D' would make the object-space t read t·|D'| = {:.6} instead of {t:.6}: the bug \"normalising D in object space\".",
                    t * norm_f64(&object_dir)
                ))
                .color(palette::OUTSIDE.readable(ui)),
            );
        }
    }
}

/// A small 3D drawing framed on the triangle: the triangle, the ray towards it, and the hit at t.
fn draw_space(
    ui: &mut Ui,
    size: Vec2,
    vertices: [[f64; 3]; 3],
    origin: [f64; 3],
    dir: [f64; 3],
    t: Option<f64>,
) {
    let (response, painter) = ui.allocate_painter(size, Sense::hover());
    let (o, d) = (DVec3::from(origin), DVec3::from(dir));
    // A mesh's triangle is small beside the ray: draw around the hit, scaled so the triangle fills
    // the canvas (only the picture is scaled; the numbers below it are the real ones).
    let center = o + d * t.unwrap_or(0.0);
    let size_of = vertices
        .iter()
        .map(|v| (DVec3::from(*v) - center).length())
        .fold(1e-300, f64::max);
    let local = |p: DVec3| (p - center) / size_of * 2.0;
    let [a, b, c] = vertices.map(|v| local(DVec3::from(v)));
    let hit = DVec3::ZERO;
    let framed = [a, b, c, hit];
    let camera = OrbitCamera::framing(&framed).across(d);
    let projector = camera.projector(response.rect);
    let canvas = Canvas {
        painter: &painter,
        projector: &projector,
    };
    canvas.polygon(
        &[a, b, c],
        palette::faded(palette::BETA, 90),
        Stroke::new(2.0, palette::BETA),
    );
    // Labels go through the label pass: they avoid each other, the hit dot and the canvas edge.
    let mut labels = LabelLayer::new(response.rect);
    for (p, name) in [(a, "A"), (b, "B"), (c, "C")] {
        if let Some(at) = canvas.dot(p, 3.5, palette::BETA) {
            labels.avoid_point(at, 4.0);
        }
        canvas.place_label(&mut labels, p, name, palette::BETA, Priority::Normal);
    }
    // The ray from well before the triangle to a little past it (the scaled triangle reaches 2 from
    // the hit), its direction drawn where it comes in.
    let step = d.normalize_or_zero() * 4.0;
    canvas.line(hit - step, hit + step * 0.5, Stroke::new(2.0, palette::RAY));
    canvas.arrow(
        hit - step,
        hit - step + step * 0.4,
        Stroke::new(3.0, palette::RAY),
    );
    canvas.place_label(
        &mut labels,
        hit - step,
        "ray",
        palette::RAY,
        Priority::Minor,
    );
    if let Some(t) = t {
        if let Some(at) = canvas.dot(hit, 6.0, palette::SOLUTION) {
            labels.avoid_point(at, 7.0);
        }
        let text = format!("t = {t:.4}");
        canvas.place_label(&mut labels, hit, text, palette::SOLUTION, Priority::Key);
    }
    labels.paint(ui, &painter, response.id.with("space-labels"));
}

/// The problem a probe loads into a view: the ray with the triangle it hit or came nearest to, or the
/// parallelogram it hit (in world space: a corner is a point, edges are directions).
fn probed_problem(prepared: &Prepared, result: &Probe) -> Option<Action> {
    if let Some([a, b, c]) = result.triangle {
        return Some(Action::Triangle(TriangleScene {
            a,
            b,
            c,
            origin: result.origin,
            dir: result.dir,
            t_min: 0.0,
        }));
    }
    let object = &prepared.objects[result.hit?.object];
    let Geometry::Parallelogram { corner, e1, e2, .. } = &object.geometry else {
        return None;
    };
    let m = object.object_to_world;
    Some(Action::Parallelogram(ParallelogramScene {
        corner: m.transform_point3(DVec3::from(*corner)).to_array(),
        e1: m.transform_vector3(DVec3::from(*e1)).to_array(),
        e2: m.transform_vector3(DVec3::from(*e2)).to_array(),
        origin: result.origin,
        dir: result.dir,
    }))
}

/// Where an image is being rendered and none is right to show yet: an empty frame that says so (the
/// progress bar above counts the rows; nothing here animates, so an idle app draws no frames).
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
    painter.text(
        band.left_center() + Vec2::new(8.0, 0.0),
        egui::Align2::LEFT_CENTER,
        "rendering… (the previous image)",
        egui::TextStyle::Body.resolve(ui.style()),
        ui.visuals().text_color(),
    );
}
