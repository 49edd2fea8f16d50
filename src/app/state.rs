//! What the app remembers across restarts ([`AppState`], saved by eframe under [`STATE_KEY`]), how an
//! older saved state is read, and the tabs ([`ViewKind`]).

use serde::{Deserialize, Serialize};

use super::parallelogram_view::ParallelogramView;
use super::render_view::RenderView;
use super::segments_view::SegmentsView;
use super::triangle_view::TriangleView;
use crate::geometry::Precision;
use crate::scene::{self, Problem};

/// The storage key of the state.
pub(super) const STATE_KEY: &str = "raylab-state";

/// The views, one tab each.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ViewKind {
    /// Two 2D segments.
    #[default]
    Segments,
    /// A ray and a triangle in 3D.
    Triangle,
    /// A ray and a parallelogram in 3D.
    Parallelogram,
    /// A per-pixel render with effects, a pixel probe and common bugs.
    Render,
    /// What accuracy costs: methods × precisions against exact.
    Accuracy,
}

impl ViewKind {
    /// Every view, in tab order.
    pub const ALL: [ViewKind; 5] = [
        ViewKind::Segments,
        ViewKind::Triangle,
        ViewKind::Parallelogram,
        ViewKind::Render,
        ViewKind::Accuracy,
    ];

    /// The views that solve one problem (and have a scene to save).
    pub const PROBLEMS: [ViewKind; 4] = [
        ViewKind::Segments,
        ViewKind::Triangle,
        ViewKind::Parallelogram,
        ViewKind::Render,
    ];

    /// The short name a web page's `?view=` uses.
    pub fn name(self) -> &'static str {
        match self {
            ViewKind::Segments => "segments",
            ViewKind::Triangle => "triangle",
            ViewKind::Parallelogram => "parallelogram",
            ViewKind::Render => "render",
            ViewKind::Accuracy => "accuracy",
        }
    }

    /// The tab label.
    pub fn label(self) -> &'static str {
        match self {
            ViewKind::Segments => "Segments (2D)",
            ViewKind::Triangle => "Triangle (3D)",
            ViewKind::Parallelogram => "Parallelogram",
            ViewKind::Render => "Render",
            ViewKind::Accuracy => "Accuracy",
        }
    }
}

/// Everything that persists across restarts.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct AppState {
    /// The open tab.
    pub view: ViewKind,
    /// The step panel's arithmetic.
    pub precision: Precision,
    /// Show the step panel.
    pub show_steps: bool,
    /// Show the Triangle view's steps in symbols (seed 002) instead of numbers.
    pub symbolic: bool,
    /// The Segments view.
    pub segments: SegmentsView,
    /// The Triangle view.
    pub triangle: TriangleView,
    /// The Parallelogram view.
    pub parallelogram: ParallelogramView,
    /// The Render view.
    pub render: RenderView,
    /// Title and note of the scene last loaded, per view.
    #[serde(deserialize_with = "titles_of_any_age")]
    pub titles: [(String, String); 4],
    /// The path in the open / save dialog.
    pub scene_path: String,
    /// Each view's scene as it was loaded, to tell when its inputs have been edited.
    pub loaded: [Option<Problem>; 4],
    /// The live class being taught, to resume it after a restart.
    pub class: Option<super::class_view::ClassLink>,
}

impl Default for AppState {
    fn default() -> AppState {
        let presets = scene::built_in();
        let first_of = |kind: ViewKind| {
            presets
                .iter()
                .find(|s| view_of(&s.problem) == kind)
                .map(|s| (s.title.clone(), s.note.clone()))
                .unwrap_or_default()
        };
        AppState {
            view: ViewKind::Segments,
            precision: Precision::Exact,
            show_steps: true,
            symbolic: false,
            segments: SegmentsView::default(),
            triangle: TriangleView::default(),
            parallelogram: ParallelogramView::default(),
            render: RenderView::default(),
            titles: ViewKind::PROBLEMS.map(first_of),
            scene_path: default_scene_path(),
            loaded: ViewKind::PROBLEMS.map(|kind| {
                presets
                    .iter()
                    .find(|s| view_of(&s.problem) == kind)
                    .map(|s| s.problem.clone())
            }),
            class: None,
        }
    }
}

/// Reads the titles of a state saved before the Render view, which had three; the Render view's comes
/// from the presets. (Without this the whole saved state would fail to read and be lost.)
fn titles_of_any_age<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<[(String, String); 4], D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Titles {
        Now([(String, String); 4]),
        BeforeRender([(String, String); 3]),
    }
    Ok(match Titles::deserialize(deserializer)? {
        Titles::Now(titles) => titles,
        Titles::BeforeRender([segments, triangle, parallelogram]) => {
            let render = AppState::default().titles[ViewKind::Render as usize].clone();
            [segments, triangle, parallelogram, render]
        }
    })
}

fn default_scene_path() -> String {
    std::env::var("HOME")
        .map(|home| format!("{home}/raylab-scene.ron"))
        .unwrap_or_else(|_| "raylab-scene.ron".into())
}

pub(super) fn view_of(problem: &Problem) -> ViewKind {
    match problem {
        Problem::Segments(_) => ViewKind::Segments,
        Problem::Triangle(_) => ViewKind::Triangle,
        Problem::Parallelogram(_) => ViewKind::Parallelogram,
        Problem::Render(_) => ViewKind::Render,
    }
}

/// The title and note shown for a view.
pub(super) fn heading(state: &AppState) -> (String, String) {
    match state.view {
        ViewKind::Accuracy => (
            "What accuracy costs".into(),
            "Every method in f32 and f64 on easy and hard rays, judged by exact arithmetic.".into(),
        ),
        view => state.titles[view as usize].clone(),
    }
}
