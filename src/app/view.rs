//! What every tab does, as one trait. The frame loop, scene files, presentation and highlighting treat
//! the views alike through [`View`]; [`RaylabApp::view`] and [`RaylabApp::view_mut`] are the registry
//! from a tab to its view. A new view is a file that implements [`View`], its [`ViewKind`], and its
//! line in the registry.

use egui::Ui;

use super::highlight::{Element, Parameter};
use super::{RaylabApp, ViewKind, accuracy_view, parallelogram_view, render_view};
use super::{segments_view, triangle_view};
use crate::geometry::Precision;
use crate::scene::Problem;
use crate::trace::Trace;

/// One frame's solve of the open view: what it draws and the step panel shows.
pub enum ActiveSolve {
    /// Two segments.
    Segments(segments_view::Solved),
    /// A ray and a triangle (also a probed pixel's ray in the Render view).
    Triangle(triangle_view::Solved),
    /// A ray and a parallelogram (also a probed pixel's ray in the Render view).
    Parallelogram(parallelogram_view::Solved),
    /// Nothing to solve (the Accuracy view; the Render view before a pixel is probed).
    Nothing,
}

impl ActiveSolve {
    /// The steps for the step panel, if there is a solve.
    pub fn trace(&self) -> Option<&Trace> {
        match self {
            ActiveSolve::Segments(s) => Some(&s.trace),
            ActiveSolve::Triangle(s) => Some(&s.trace),
            ActiveSolve::Parallelogram(s) => Some(&s.trace),
            ActiveSolve::Nothing => None,
        }
    }
}

/// What a view asks the app to do after drawing.
pub enum Request {
    /// The Render view's probe: open a ray in another view, or switch views.
    Render(render_view::Action),
    /// The Accuracy view's gallery: load this hard case into the Triangle view.
    Accuracy(accuracy_view::Action),
}

/// A tab of the app.
pub trait View {
    /// Its tab.
    fn kind(&self) -> ViewKind;

    /// Opens a problem of its kind (a render scene's meshes and textures are found in `folder`).
    fn open(&mut self, problem: &Problem, folder: Option<String>) -> Result<(), OpenError>;

    /// Its problem as it stands now (to save it, to tell whether it was edited); `None` for a view
    /// with no problem of its own.
    fn problem(&self) -> Option<Problem>;

    /// Solves what it shows, with the step panel in `precision`.
    fn solve_frame(&self, precision: Precision) -> ActiveSolve;

    /// Draws itself; `canvas_only` in presentation mode. A frame whose solve is not its own (the
    /// tab changed this frame) draws nothing and asks for the next frame.
    fn frame_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve, canvas_only: bool)
    -> Option<Request>;

    /// Emphasises what the step on screen is about.
    fn emphasise(&mut self, _elements: &[Element]) {}

    /// Slides a parameter to its value at the solution (a presentation step computed it).
    fn slide_to(&mut self, _parameter: Parameter, _solved: &ActiveSolve, _now: f64) {}
}

/// The [`View`] of a lecture view (Segments, Triangle, Parallelogram): its problem is
/// `Problem::$variant`, its frame's solve `ActiveSolve::$variant`, and it has `load(scene)`,
/// `solve(precision)`, `ui` and `present_ui(ui, solved)`, `show_parameter(parameter, solved, now)`
/// and a `highlight` list. Its `Default` is the first built-in scene of its kind, loaded into
/// `unloaded(scene)`.
macro_rules! lecture_view {
    ($view:ty, $variant:ident) => {
        impl Default for $view {
            fn default() -> Self {
                let scene = $crate::scene::first_built_in(|s| match s {
                    $crate::scene::Problem::$variant(p) => Some(p),
                    _ => None,
                });
                let mut view = Self::unloaded(scene.clone());
                view.load(scene);
                view
            }
        }

        impl $crate::app::view::View for $view {
            fn kind(&self) -> $crate::app::ViewKind {
                $crate::app::ViewKind::$variant
            }

            fn open(
                &mut self,
                problem: &$crate::scene::Problem,
                _folder: Option<String>,
            ) -> Result<(), $crate::app::view::OpenError> {
                let $crate::scene::Problem::$variant(scene) = problem else {
                    return Err($crate::app::view::not_mine(self.kind()));
                };
                self.load(scene.clone());
                Ok(())
            }

            fn problem(&self) -> Option<$crate::scene::Problem> {
                Some($crate::scene::Problem::$variant(self.scene.clone()))
            }

            fn solve_frame(
                &self,
                precision: $crate::geometry::Precision,
            ) -> $crate::app::view::ActiveSolve {
                $crate::app::view::ActiveSolve::$variant(self.solve(precision))
            }

            fn frame_ui(
                &mut self,
                ui: &mut egui::Ui,
                solved: &$crate::app::view::ActiveSolve,
                canvas_only: bool,
            ) -> Option<$crate::app::view::Request> {
                match solved {
                    $crate::app::view::ActiveSolve::$variant(s) if canvas_only => {
                        self.present_ui(ui, s)
                    }
                    $crate::app::view::ActiveSolve::$variant(s) => self.ui(ui, s),
                    _ => ui.ctx().request_repaint(),
                }
                None
            }

            fn emphasise(&mut self, elements: &[$crate::app::highlight::Element]) {
                self.highlight = elements.to_vec();
            }

            fn slide_to(
                &mut self,
                parameter: $crate::app::highlight::Parameter,
                solved: &$crate::app::view::ActiveSolve,
                now: f64,
            ) {
                if let $crate::app::view::ActiveSolve::$variant(s) = solved {
                    self.show_parameter(parameter, s, now);
                }
            }
        }
    };
}

/// The refusal of a problem that belongs to another view.
pub fn not_mine(kind: ViewKind) -> OpenError {
    OpenError::NotMine(kind)
}

/// Why a view cannot open a problem (the scene on screen is kept).
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// A problem of another view's kind.
    #[error("the {} view opens no such problem", .0.label())]
    NotMine(ViewKind),
    /// A render scene whose numbers, size, camera or settings are refused.
    #[error(transparent)]
    Scene(#[from] crate::scene::check::CheckError),
    /// A render scene whose objects or files cannot be prepared.
    #[error(transparent)]
    Prepare(#[from] crate::render::PrepareError),
}

impl RaylabApp {
    /// The view of a tab.
    pub fn view(&self, kind: ViewKind) -> &dyn View {
        match kind {
            ViewKind::Segments => &self.state.segments,
            ViewKind::Triangle => &self.state.triangle,
            ViewKind::Parallelogram => &self.state.parallelogram,
            ViewKind::Render => &self.state.render,
            ViewKind::Accuracy => &self.accuracy,
        }
    }

    /// The view of a tab, to change.
    pub fn view_mut(&mut self, kind: ViewKind) -> &mut dyn View {
        match kind {
            ViewKind::Segments => &mut self.state.segments,
            ViewKind::Triangle => &mut self.state.triangle,
            ViewKind::Parallelogram => &mut self.state.parallelogram,
            ViewKind::Render => &mut self.state.render,
            ViewKind::Accuracy => &mut self.accuracy,
        }
    }
}
