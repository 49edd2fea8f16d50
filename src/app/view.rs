//! What every tab does, as one trait. The frame loop, scene files, presentation, highlighting and the
//! saved state treat the views alike through [`View`]; the registry ([`super::VIEWS`]) lists them.
//!
//! A new view is one file and one line in the registry: a lecture view (one problem, solved with its
//! steps) implements [`LectureView`] and gets [`View`] from it; any other view implements [`View`].
//! The app keeps each view's saved state under its name ([`ViewKind::name`]), asks it what its frames
//! depend on ([`View::fingerprint`]), and carries its solve ([`ActiveSolve`]) and its requests
//! ([`Request`]) without knowing their types.

use std::any::Any;
use std::fmt;

use egui::Ui;
use serde::Serialize;
use serde::de::DeserializeOwned;

use super::highlight::{Element, Parameter};
use super::widgets::canvas_state::CanvasState;
use super::{RaylabApp, ViewKind};
use crate::geometry::Precision;
use crate::scene::{LectureScene, Problem};
use crate::trace::Trace;

/// One frame's solve of the open view: what it draws, and the steps the step panel shows. The view
/// that made it reads it back as its own type ([`ActiveSolve::get`]).
pub struct ActiveSolve(Option<Box<dyn Solve>>);

/// A solve of any type that holds its steps.
trait Solve {
    fn steps(&self) -> &Trace;
    fn as_any(&self) -> &dyn Any;
}

impl<S: AsRef<Trace> + 'static> Solve for S {
    fn steps(&self) -> &Trace {
        self.as_ref()
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl ActiveSolve {
    /// Nothing to solve (the Accuracy view; the Render view before a pixel is probed).
    pub fn nothing() -> ActiveSolve {
        ActiveSolve(None)
    }

    /// A solve, with its steps.
    pub fn new<S: AsRef<Trace> + 'static>(solved: S) -> ActiveSolve {
        ActiveSolve(Some(Box::new(solved)))
    }

    /// The steps for the step panel, if there is a solve.
    pub fn trace(&self) -> Option<&Trace> {
        self.0.as_ref().map(|s| s.steps())
    }

    /// The solve, if it is an `S` (a view's own; not when the tab changed this frame).
    pub fn get<S: 'static>(&self) -> Option<&S> {
        self.0.as_ref()?.as_any().downcast_ref()
    }
}

/// What a view asks the app to do after drawing (open a probed ray in another view, switch tabs, …).
pub struct Request(Box<dyn FnOnce(&mut RaylabApp)>);

impl Request {
    /// A request to run `change` on the app.
    pub fn new(change: impl FnOnce(&mut RaylabApp) + 'static) -> Request {
        Request(Box::new(change))
    }

    /// Carries it out.
    pub fn apply(self, app: &mut RaylabApp) {
        (self.0)(app)
    }
}

/// A tab of the app.
pub trait View: AnyView {
    /// True if it opens this problem (the app opens a scene in the view that does).
    fn opens(&self, problem: &Problem) -> bool;

    /// Opens a problem of its kind (a render scene's meshes and textures are found in `folder`).
    fn open(&mut self, problem: &Problem, folder: Option<String>) -> Result<(), OpenError>;

    /// Its problem as it stands now (to save it, to tell whether it was edited); `None` for a view
    /// with no problem of its own.
    fn problem(&self) -> Option<Problem>;

    /// Solves what it shows, with the step panel in `precision`.
    fn solve_frame(&self, precision: Precision) -> ActiveSolve;

    /// The precision of its steps when it keeps its own rather than the app's (the Render view's
    /// probe: f64 unless the step panel's picker says otherwise); `None`: the app's.
    fn own_precision(&self) -> Option<Precision> {
        None
    }

    /// Whose steps the step panel shows, when that needs saying (the Render view's probed pixel,
    /// the image it was clicked on and the ray of its tree).
    fn steps_subject(&self) -> Option<String> {
        None
    }

    /// Sets the precision it keeps (see [`View::own_precision`]); a view without one ignores it.
    fn set_own_precision(&mut self, _precision: Precision) {}

    /// Draws itself; `canvas_only` in presentation mode. A frame whose solve is not its own (the
    /// tab changed this frame) draws nothing and asks for the next frame.
    fn frame_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve, canvas_only: bool)
    -> Option<Request>;

    /// Adds the bits of everything its solve and drawing depend on (the app draws once more when a
    /// frame changed them: the step panel was drawn before the frame's drags).
    fn fingerprint(&self, _bits: &mut Vec<u64>) {}

    /// What it saves across restarts (RON), or `None` if nothing (see [`restored`]).
    fn save(&self) -> Option<String> {
        None
    }

    /// True if it has steps to present one at a time (presentation mode, lessons).
    fn presents(&self) -> bool {
        false
    }

    /// Emphasises what the step on screen is about.
    fn emphasise(&mut self, _elements: &[Element]) {}

    /// Slides a parameter to its value at the solution (a presentation step computed it).
    fn slide_to(&mut self, _parameter: Parameter, _solved: &ActiveSolve, _now: f64) {}

    /// Ends a running slide at once, its parameters where it was taking them.
    fn settle(&mut self) {}

    /// Its 3D canvas, if it has one (a lesson's slide turns the camera).
    fn canvas_mut(&mut self) -> Option<&mut CanvasState> {
        None
    }

    /// Turns its camera to look from `yaw` about z and `pitch` above the xy plane (radians), as a
    /// lesson's slide asks.
    fn aim(&mut self, yaw: f64, pitch: f64) {
        if let Some(canvas) = self.canvas_mut() {
            canvas.camera.yaw = yaw;
            canvas.camera.pitch = pitch;
        }
    }
}

/// What every view is without writing it: its concrete type (the app reaches a view it knows by
/// type, as the Render view's probe does the Triangle view) and a copy of it.
pub trait AnyView: Any {
    /// As `Any`, to reach the concrete view.
    fn as_any(&self) -> &dyn Any;
    /// As `Any`, to change the concrete view.
    fn as_any_mut(&mut self) -> &mut dyn Any;
    /// A copy.
    fn clone_view(&self) -> Box<dyn View>;
}

impl<V: View + Clone> AnyView for V {
    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }

    fn clone_view(&self) -> Box<dyn View> {
        Box::new(self.clone())
    }
}

impl fmt::Debug for dyn View {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(
            &self
                .save()
                .unwrap_or_else(|| "(a view that saves nothing)".into()),
        )
    }
}

/// A lecture view: one problem of the lecture (two segments, a ray and a triangle, …) with its
/// parameters on sliders, solved every frame with its steps. It gets [`View`] from this trait: its
/// problem is opened, saved, solved, drawn and presented through these methods alone.
pub trait LectureView: Clone + Serialize + DeserializeOwned + 'static {
    /// Its inputs: which kind of problem it opens.
    type Scene: LectureScene;
    /// One frame's solve, with its steps.
    type Solved: AsRef<Trace> + 'static;

    /// Its inputs now.
    fn scene(&self) -> &Self::Scene;
    /// Loads new inputs: sliders at a starting point, the camera framing them.
    fn load(&mut self, scene: Self::Scene);
    /// Solves its inputs, with the step panel in `precision`.
    fn solve(&self, precision: Precision) -> Self::Solved;
    /// The view: controls and drawing.
    fn ui(&mut self, ui: &mut Ui, solved: &Self::Solved);
    /// The drawing alone, filling the space (presentation mode).
    fn present_ui(&mut self, ui: &mut Ui, solved: &Self::Solved);
    /// Slides a parameter's handle to its value at the solution (presentation mode, on the step
    /// that computes it).
    fn show_parameter(&mut self, parameter: Parameter, solved: &Self::Solved, now: f64);
    /// Ends a running slide at once, its parameters at their targets (a lesson slide puts what
    /// earlier slides computed in place before its own step slides).
    fn settle(&mut self) {}
    /// Emphasises what the step on screen is about.
    fn highlight(&mut self, elements: &[Element]);
    /// Adds the bits of its inputs and sliders (see [`View::fingerprint`]).
    fn fingerprint(&self, bits: &mut Vec<u64>);
    /// Its 3D canvas, if it has one.
    fn canvas_mut(&mut self) -> Option<&mut CanvasState> {
        None
    }
}

impl<L: LectureView> View for L {
    fn opens(&self, problem: &Problem) -> bool {
        L::Scene::of(problem).is_some()
    }

    fn open(&mut self, problem: &Problem, _folder: Option<String>) -> Result<(), OpenError> {
        let scene = L::Scene::of(problem).ok_or(OpenError::NotMine)?;
        self.load(scene.clone());
        Ok(())
    }

    fn problem(&self) -> Option<Problem> {
        Some(self.scene().clone().into_problem())
    }

    fn solve_frame(&self, precision: Precision) -> ActiveSolve {
        ActiveSolve::new(self.solve(precision))
    }

    fn frame_ui(
        &mut self,
        ui: &mut Ui,
        solved: &ActiveSolve,
        canvas_only: bool,
    ) -> Option<Request> {
        match solved.get::<L::Solved>() {
            Some(s) if canvas_only => self.present_ui(ui, s),
            Some(s) => self.ui(ui, s),
            None => ui.ctx().request_repaint(),
        }
        None
    }

    fn fingerprint(&self, bits: &mut Vec<u64>) {
        LectureView::fingerprint(self, bits);
    }

    fn save(&self) -> Option<String> {
        ron::to_string(self).ok()
    }

    fn presents(&self) -> bool {
        true
    }

    fn emphasise(&mut self, elements: &[Element]) {
        self.highlight(elements);
    }

    fn slide_to(&mut self, parameter: Parameter, solved: &ActiveSolve, now: f64) {
        if let Some(s) = solved.get::<L::Solved>() {
            self.show_parameter(parameter, s, now);
        }
    }

    fn settle(&mut self) {
        LectureView::settle(self);
    }

    fn canvas_mut(&mut self) -> Option<&mut CanvasState> {
        LectureView::canvas_mut(self)
    }
}

/// A lecture view of the first built-in scene of its kind (its `Default`).
pub fn first_scene<L: LectureView>(unloaded: impl FnOnce(L::Scene) -> L) -> L {
    let scene = crate::scene::first_built_in(|problem| L::Scene::of(&problem).cloned());
    let mut view = unloaded(scene.clone());
    view.load(scene);
    view
}

/// The bits of some numbers, for [`View::fingerprint`]: bits, not values, so that NaN (an input
/// being typed) equals itself, or every frame would differ.
pub fn bits_of(bits: &mut Vec<u64>, numbers: impl IntoIterator<Item = f64>) {
    bits.extend(numbers.into_iter().map(f64::to_bits));
}

/// A line of the registry: a tab, and how its view is made.
#[derive(Clone, Copy)]
pub struct ViewEntry {
    /// Its tab: name (the key of its saved state, `?view=`) and label.
    pub kind: ViewKind,
    /// Makes the view from what it saved (see [`View::save`]), or afresh from `None` or from a
    /// saved state it cannot read.
    pub build: fn(Option<&str>) -> Box<dyn View>,
}

impl ViewEntry {
    /// The line of a tab and how its view is made.
    pub const fn new(kind: ViewKind, build: fn(Option<&str>) -> Box<dyn View>) -> ViewEntry {
        ViewEntry { kind, build }
    }
}

/// A [`ViewEntry::build`] for a view that saves itself: read back from its RON, field by field
/// (with `#[serde(default)]`), or its default.
pub fn restored<V: View + Default + DeserializeOwned>(saved: Option<&str>) -> Box<dyn View> {
    let view: V = saved
        .and_then(|text| ron::from_str(text).ok())
        .unwrap_or_default();
    Box::new(view)
}

/// A [`ViewEntry::build`] for a view that saves nothing: its default, every time.
pub fn fresh<V: View + Default>(_saved: Option<&str>) -> Box<dyn View> {
    Box::new(V::default())
}

/// Why a view cannot open a problem (the scene on screen is kept).
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// A problem of another view's kind.
    #[error("no view opens such a problem")]
    NotMine,
    /// A render scene whose numbers, size, camera or settings are refused.
    #[error(transparent)]
    Scene(#[from] crate::scene::check::CheckError),
    /// A render scene whose objects or files cannot be prepared.
    #[error(transparent)]
    Prepare(#[from] crate::render::PrepareError),
}

impl RaylabApp {
    /// The view of a tab (the first view when no tab has that kind).
    pub fn view(&self, kind: ViewKind) -> &dyn View {
        self.state.view_of_kind(kind)
    }

    /// The view of a tab, to change.
    pub fn view_mut(&mut self, kind: ViewKind) -> &mut dyn View {
        self.state.view_of_kind_mut(kind)
    }
}
