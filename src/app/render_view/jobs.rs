//! The Render view's background work: the prepared scene, the large-mesh load, and the two images
//! (correct and with a bug), each a render job started when its choices change.

use super::*;

/// What is not saved: the prepared scene, the jobs, the images, the probe.
#[derive(Default)]
pub(super) struct Runtime {
    pub(super) prepared: Option<(RenderScene, Result<Arc<Prepared>, String>)>,
    /// A scene with large meshes being prepared in the background.
    pub(super) loading: Option<Loading>,
    pub(super) correct: Slot,
    pub(super) buggy: Slot,
    pub(super) probe: Option<Probe>,
    /// What the probe was made under: it is redone when that changes.
    pub(super) probe_key: Option<Choices>,
    /// The probed ray with what it met, as the problem its steps are shown for.
    pub(super) probed_problem: Option<Action>,
    /// The probed pixel's ray tree.
    pub(super) tree: Option<RayTree>,
    /// The ray of the tree last opened in its view, by name (`None`: the primary ray).
    pub(super) opened: Option<String>,
    /// What to ask of the app on the next frame (a ray of the tree is loaded, then its view opens).
    pub(super) pending: Option<Action>,
    /// The measurement of each effect's cost.
    pub(super) cost: Option<effects::Cost>,
    /// The camera's motion and the frames shown while it moves.
    pub(super) orbit: orbit::Orbit,
    /// A render past the budget ([`crate::render::budget`]) waits for "Render anyway": why, shown.
    pub(super) past_budget: Option<PastBudget>,
    /// "Render anyway" was pressed for this scene.
    pub(super) budget_waived: Option<RenderScene>,
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
pub(super) struct Loading {
    /// The scene it is for.
    pub(super) key: RenderScene,
    /// Its mesh files, in the order they load.
    pub(super) meshes: Vec<String>,
    pub(super) job: Job<Result<Prepared, crate::render::PrepareError>>,
}

/// Meshes larger than this in all load in the background, with a progress bar and Cancel; smaller
/// ones load at once (in well under a second).
pub(super) const BACKGROUND_MESH_BYTES: u64 = 4 << 20;

/// True if the scene's meshes are found and large enough to load in the background (a missing or
/// refused one is reported at once, by the plain preparation).
pub(super) fn loads_in_background(scene: &RenderScene, assets: &OnDisk) -> bool {
    let mut total = 0;
    for name in mesh_names(scene) {
        match assets.size(&name, crate::files::MESH) {
            Ok(size) => total += size,
            Err(_) => return false,
        }
    }
    total > BACKGROUND_MESH_BYTES
}

/// Why a render waits for "Render anyway", as `raylab render` refuses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum PastBudget {
    /// Its settings may cast past the most rays a render may.
    Rays(crate::render::budget::WorstCase),
    /// Its trial frame says it would take past the time budget.
    Time(OverTime),
}

impl PastBudget {
    /// The sentence shown: why, and what to change.
    pub(super) fn sentence(&self) -> String {
        match self {
            PastBudget::Rays(worst) => format!(
                "Not rendered: {worst}. Lower samples_per_side, max_depth or occlusion_rays in the \
                 scene, or render it anyway (Cancel stops it)."
            ),
            PastBudget::Time(over) => format!(
                "Not rendered: {over}. Turn effects off, pick another method or no bug, or render \
                 it anyway (Cancel stops it)."
            ),
        }
    }
}

/// One image: the render in flight and the one shown.
#[derive(Default)]
pub(super) struct Slot {
    pub(super) running: Option<(Choices, Job<Result<Rendered, OverTime>>)>,
    pub(super) shown: Option<Shown>,
    pub(super) error: Option<String>,
    /// The choices whose render failed inside (a panic) or was refused: not started again until
    /// they change.
    pub(super) failed: Option<Choices>,
}

/// A render that ended this frame.
pub(super) enum Finished {
    /// Its image is shown: the frame's draft factor (`None`: the full image) and seconds.
    Shown(Option<u32>, f64),
    /// Its trial frame put it past the time budget: nothing was rendered.
    OverTime(OverTime),
}

impl Slot {
    /// The choices of the image running or shown.
    fn current(&self) -> Option<&Choices> {
        self.running
            .as_ref()
            .map(|(key, _)| key)
            .or(self.shown.as_ref().map(|shown| &shown.key))
    }

    /// Takes the running render's image when it has finished (as the texture `name`), or its
    /// failure; says how it ended, `None` while it runs or when it failed.
    fn take_finished(&mut self, ctx: &egui::Context, name: &str) -> Option<Finished> {
        let (key, mut job) = self.running.take()?;
        if let Some(failure) = job.failure() {
            self.error = Some(format!(
                "the render stopped on an internal error: {failure}"
            ));
            self.failed = Some(key);
            return None;
        }
        let rendered = match job.poll() {
            None => {
                self.running = Some((key, job));
                return None;
            }
            Some(Err(over)) => {
                self.failed = Some(key);
                return Some(Finished::OverTime(over));
            }
            Some(Ok(rendered)) => rendered,
        };
        let image = &rendered.image;
        let pixels = ColorImage::from_rgb([image.width, image.height], &image.to_rgb8());
        // A full image shows its pixels as squares (they are probed one by one); a quick frame,
        // enlarged, is smoothed.
        let filter = match key.draft {
            Some(_) => TextureOptions::LINEAR,
            None => TextureOptions::NEAREST,
        };
        let texture = ctx.load_texture(name, pixels, filter);
        let frame = Finished::Shown(key.draft, rendered.seconds);
        self.shown = Some(Shown {
            key,
            rendered,
            texture,
        });
        Some(frame)
    }
}

/// What a render (or a probe) depends on: it is made again when any of these change.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Choices {
    pub(super) scene: RenderScene,
    /// The camera the view looks through (the scene's, or moved by the user).
    pub(super) camera: crate::scene::render::Camera,
    pub(super) effects: Vec<Effect>,
    pub(super) method: Option<Method>,
    /// The bug of the second image; for a probe, none.
    pub(super) bug: Option<Bug>,
    /// The probed pixel (probes only).
    pub(super) pixel: Option<(usize, usize)>,
    /// A quick frame while the camera moves: the image at 1/n of its sides, one sample a pixel.
    pub(super) draft: Option<u32>,
}

/// A finished render on screen.
pub(super) struct Shown {
    pub(super) key: Choices,
    pub(super) rendered: Rendered,
    pub(super) texture: TextureHandle,
}

impl RenderView {
    /// The scene prepared with the current choices (and a bug), through the view's camera, or why
    /// not.
    pub(super) fn prepared(&mut self, bug: Option<Bug>) -> Result<Arc<Prepared>, String> {
        self.prepared_draft(bug, None)
    }

    /// [`RenderView::prepared`], or with `draft` a quick frame of it: 1/n of its sides (rounded up),
    /// one sample a pixel.
    pub(super) fn prepared_draft(
        &mut self,
        bug: Option<Bug>,
        draft: Option<u32>,
    ) -> Result<Arc<Prepared>, String> {
        let prepared = match &self.runtime.prepared {
            Some((key, prepared)) if *key == self.scene => prepared.clone(),
            _ => {
                if self
                    .runtime
                    .loading
                    .as_ref()
                    .is_some_and(|l| l.key == self.scene)
                {
                    return Err("the scene's meshes are still loading".into());
                }
                let prepared = Prepared::new(&self.scene, &assets(self.folder.as_deref()))
                    .map(Arc::new)
                    .map_err(|e| e.to_string());
                self.runtime.prepared = Some((self.scene.clone(), prepared.clone()));
                prepared
            }
        }?;
        let mut prepared = Prepared::clone(&prepared);
        prepared.effects = self.effects.clone();
        prepared.method = self.method.or(prepared.method);
        prepared.bug = bug;
        prepared.camera = self.view_camera();
        Ok(Arc::new(match draft {
            Some(n) => prepared.quick_frame(n),
            None => prepared,
        }))
    }

    /// Starts renders whose inputs changed and takes finished ones; asks for frames while running.
    pub fn update(&mut self, ctx: &egui::Context) {
        // A drag that ended away from the image (or in another mode) ends here.
        if !ctx.input(|i| i.pointer.any_down()) {
            self.runtime.orbit.end_drag();
        }
        self.runtime.orbit.tick(ctx.input(|i| i.time));
        if self.poll_loading(ctx) {
            return;
        }
        self.start_if_changed(ctx, None);
        match self.bug {
            Some(bug) => self.start_if_changed(ctx, Some(bug)),
            None => self.runtime.buggy = Slot::default(),
        }
        self.poll_cost(ctx);
        let now = ctx.input(|i| i.time);
        let correct = self.runtime.correct.take_finished(ctx, "render");
        let buggy = self.runtime.buggy.take_finished(ctx, "render-bug");
        if let Some(Finished::Shown(draft, seconds)) = correct {
            self.runtime.orbit.frame_shown((draft, seconds), now);
        }
        for finished in [correct, buggy] {
            if let Some(Finished::OverTime(over)) = finished {
                self.runtime.past_budget = Some(PastBudget::Time(over));
            }
        }
        // On the desktop the render's thread wakes the UI as rows come in; asking for every frame
        // here as well kept the UI drawing flat out beside the render, on a core it needs.
        if self.is_rendering() && !crate::platform::THREADS {
            ctx.request_repaint();
        }
        // The camera stops counting as moving a moment after the last scroll: then the full
        // image renders.
        if let Some(wait) = self.runtime.orbit.settles_in(now) {
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(wait));
        }
        // A probe follows the choices it was made under.
        if self.probed.is_some() && self.runtime.probe_key.as_ref() != Some(&self.probe_key()) {
            self.reprobe();
        }
    }

    /// The image with `bug` (none: the correct one).
    pub(super) fn slot_mut(&mut self, bug: Option<Bug>) -> &mut Slot {
        match bug {
            Some(_) => &mut self.runtime.buggy,
            None => &mut self.runtime.correct,
        }
    }

    /// Starts the render of the image with `bug` when its choices changed (and did not fail before).
    pub(super) fn start_if_changed(&mut self, ctx: &egui::Context, bug: Option<Bug>) {
        let wanted = Choices {
            scene: self.scene.clone(),
            camera: self.view_camera(),
            effects: self.effects.clone(),
            method: self.method,
            bug,
            pixel: None,
            draft: self.runtime.orbit.draft(),
        };
        let slot = self.slot_mut(bug);
        if slot.current() == Some(&wanted) || slot.failed.as_ref() == Some(&wanted) {
            return;
        }
        // A camera held still in mid-drag: the quick frame shown stays (a new divisor alone is no
        // reason to render the same view again, and would keep both cores busy).
        let only_divisor = |key: &Choices| {
            key.draft.is_some()
                && wanted.draft.is_some()
                && Choices {
                    draft: wanted.draft,
                    ..key.clone()
                } == wanted
        };
        if slot.current().is_some_and(only_divisor) {
            return;
        }
        // While the camera moves, a quick frame in flight is finished, not replaced: the next one
        // starts from wherever the camera is then (replaced at every mouse move, none would end).
        if wanted.draft.is_some()
            && slot
                .running
                .as_ref()
                .is_some_and(|(key, _)| key.draft.is_some())
        {
            return;
        }
        let waived = self.runtime.budget_waived.as_ref() == Some(&self.scene);
        let prepared = self.prepared_draft(bug, wanted.draft);
        // Past the budget, as `raylab render` refuses it: nothing starts until "Render anyway".
        let past = prepared
            .as_ref()
            .ok()
            .and_then(|p| crate::render::budget::past_budget(p))
            .filter(|_| !waived);
        if let Some(worst) = past {
            self.runtime.past_budget = Some(PastBudget::Rays(worst));
            let slot = self.slot_mut(bug);
            slot.running = None;
            slot.failed = Some(wanted);
            return;
        }
        self.runtime.past_budget = None;
        // A full image first runs its trial frame, as `raylab render` does; quick frames and a
        // waived budget do not.
        let budget = self
            .time_budget
            .filter(|_| wanted.draft.is_none() && !waived);
        let started = prepared.and_then(|prepared| {
            let waker = ctx.clone();
            let work = BudgetedRender::new(prepared, budget);
            Job::start("raylab-render", work, move || waker.request_repaint())
        });
        let slot = self.slot_mut(bug);
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

    /// Starts the background preparation of a scene with large meshes, or takes its result; true
    /// while it runs (nothing renders until it is done).
    pub(super) fn poll_loading(&mut self, ctx: &egui::Context) -> bool {
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
            None => loading.job.poll().map(|r| r.map_err(|e| e.to_string())),
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
    pub(super) fn loading_ui(&mut self, ui: &mut Ui) {
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
}
