//! Lessons: a lecture as an ordered list of slides, each a built-in scene, the step of its solve on
//! screen (highlighted in the view as presentation mode does), the precision and a few lines of
//! narration. Lessons are RON files in `assets/lessons/`, shipped inside the binary like the scenes.
//!
//! This module only reads and checks lessons; the app plays them.

use serde::{Deserialize, Serialize};

use crate::geometry::{Precision, Reading};
use crate::scene::{self, Problem};
use crate::trace::Trace;

/// A lecture, slide by slide.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lesson {
    /// Shown in the Lessons menu and on every slide.
    pub title: String,
    /// One sentence: what the lesson covers and which lecture material it follows.
    pub summary: String,
    /// The slides, in order.
    pub slides: Vec<Slide>,
}

/// One slide: a scene, the step of its solve on screen, and what the teacher says.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Slide {
    /// A short title.
    pub title: String,
    /// The built-in scene, by its file name without `.ron` (`seed000-triangle`).
    pub scene: String,
    /// The id of the step shown and highlighted (`system`, `M1`, `beta`, `check_bc`, `verdict`), or
    /// none for a slide about the picture alone.
    #[serde(default)]
    pub step: Option<String>,
    /// The arithmetic the steps are shown in (exact unless the slide is about floats).
    #[serde(default = "exact")]
    pub precision: Precision,
    /// Show the steps in symbols (seed 002's derivation, for a triangle scene) instead of numbers.
    #[serde(default)]
    pub symbolic: bool,
    /// Where a 3D view's camera looks from (the scene is framed to fill the view from there); on a
    /// render scene, where its pinhole camera looks at its target from, at the scene's distance.
    #[serde(default)]
    pub camera: Option<Camera>,
    /// A common bug rendered beside the correct image (a render scene's slide about the bugs).
    #[serde(default)]
    pub bug: Option<crate::render::bug::Bug>,
    /// What the teacher says, a line each. Math is written as text (β = |M1| / |M|).
    pub narration: Vec<String>,
    /// A question for the room, with its answer revealed on request.
    #[serde(default)]
    pub question: Option<Question>,
}

fn exact() -> Precision {
    Precision::Exact
}

/// A camera direction for a 3D slide, in degrees.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Around the vertical (z) axis.
    pub yaw: f64,
    /// Above the xy plane (−89 to 89).
    pub pitch: f64,
}

/// A question on a slide.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Question {
    /// What is asked.
    pub ask: String,
    /// The answer, revealed on request.
    pub answer: String,
}

/// The lessons that ship with raylab: (file name, RON text).
pub const BUILT_IN: &[(&str, &str)] = &[
    (
        "seed000-segments-and-triangle.ron",
        include_str!("../assets/lessons/seed000-segments-and-triangle.ron"),
    ),
    (
        "seed001-parallelogram.ron",
        include_str!("../assets/lessons/seed001-parallelogram.ron"),
    ),
    (
        "seed002-symbolic-cramer.ron",
        include_str!("../assets/lessons/seed002-symbolic-cramer.ron"),
    ),
    (
        "seed003-one-ray-to-a-render.ron",
        include_str!("../assets/lessons/seed003-one-ray-to-a-render.ron"),
    ),
    (
        "seed004-barycentrics-and-transforms.ron",
        include_str!("../assets/lessons/seed004-barycentrics-and-transforms.ron"),
    ),
];

/// A lesson file that does not read, at a line and column (from 1).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{column}: {error}")]
pub struct LessonError {
    /// The file's name as given.
    pub file: String,
    /// The line.
    pub line: usize,
    /// The column.
    pub column: usize,
    /// What RON says.
    pub error: ron::Error,
}

impl Lesson {
    /// Reads a lesson; errors name the file, line and column.
    pub fn from_ron(text: &str, file: &str) -> Result<Lesson, LessonError> {
        ron::from_str(text).map_err(|e| LessonError {
            file: file.to_string(),
            line: e.span.start.line,
            column: e.span.start.col,
            error: e.code,
        })
    }

    /// Every reason the lesson cannot be played: a scene that is not built in, a step its solve
    /// does not have, a slide with no narration.
    pub fn problems(&self) -> Vec<String> {
        let mut problems = Vec::new();
        if self.slides.is_empty() {
            problems.push("a lesson needs at least one slide".to_string());
        }
        for (index, slide) in self.slides.iter().enumerate() {
            let at = format!("slide {} (“{}”)", index + 1, slide.title);
            if slide.narration.iter().all(|line| line.trim().is_empty()) {
                problems.push(format!("{at}: no narration"));
            }
            let Some(scene) = scene::preset(&slide.scene) else {
                problems.push(format!("{at}: no built-in scene named “{}”", slide.scene));
                continue;
            };
            if let Some(camera) = slide.camera {
                let turns = match &scene.problem {
                    Problem::Triangle(_) | Problem::Parallelogram(_) => true,
                    // The Render view orbits a pinhole camera about its target.
                    Problem::Render(render) => render.camera.orbit_angles().is_some(),
                    _ => false,
                };
                if !turns {
                    problems.push(format!(
                        "{at}: a camera is for the Triangle and Parallelogram views and a render \
                         scene's pinhole camera"
                    ));
                }
                if !(camera.yaw.is_finite() && (-89.0..=89.0).contains(&camera.pitch)) {
                    problems.push(format!(
                        "{at}: the camera's pitch must be −89 to 89 degrees"
                    ));
                }
            }
            if slide.bug.is_some() && !matches!(scene.problem, Problem::Render(_)) {
                problems.push(format!(
                    "{at}: a bug is rendered beside a render scene's image"
                ));
            }
            if let Some(step) = &slide.step {
                let trace = if slide.symbolic {
                    matches!(scene.problem, Problem::Triangle(_))
                        .then(|| crate::symbolic::trace(None))
                } else {
                    trace_of(&scene.problem)
                };
                match trace {
                    Some(trace) if trace.step(step).is_some() => {}
                    Some(trace) => problems.push(format!(
                        "{at}: the solve of “{}” has no step “{step}” (it has {})",
                        slide.scene,
                        trace
                            .steps
                            .iter()
                            .map(|s| s.id.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )),
                    None => problems.push(format!(
                        "{at}: “{}” has no {}steps",
                        slide.scene,
                        if slide.symbolic { "symbolic " } else { "" }
                    )),
                }
            }
        }
        problems
    }
}

/// The exact solve of a scene's problem, as the step panel shows it (inputs read as written);
/// `None` for a render scene.
pub fn trace_of(problem: &Problem) -> Option<Trace> {
    problem.trace(Reading::AsWritten, Precision::Exact)
}

/// Every built-in lesson, in menu order.
#[allow(
    clippy::expect_used,
    reason = "the shipped lessons are embedded at build time; tests check every one"
)]
pub fn built_in() -> Vec<(&'static str, Lesson)> {
    BUILT_IN
        .iter()
        .map(|(file, text)| {
            let lesson = Lesson::from_ron(text, file).expect("built-in lessons are valid");
            (file.trim_end_matches(".ron"), lesson)
        })
        .collect()
}

/// A built-in lesson by its file name without `.ron`, as `raylab --lesson` and `?lesson=` name it.
pub fn lesson(name: &str) -> Option<Lesson> {
    built_in()
        .into_iter()
        .find(|(stem, _)| *stem == name)
        .map(|(_, lesson)| lesson)
}

/// A lesson name that names no built-in lesson; the message lists them.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no lesson named “{name}” (there are: {})", lesson_names().join(", "))]
pub struct UnknownLesson {
    /// The name given.
    pub name: String,
}

/// The built-in lessons' names for [`lesson`].
pub fn lesson_names() -> Vec<&'static str> {
    scene::stems(BUILT_IN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_lesson_loads_and_every_slide_solves() {
        for (name, lesson) in built_in() {
            assert!(!lesson.slides.is_empty(), "{name}");
            assert_eq!(lesson.problems(), Vec::<String>::new(), "{name}");
        }
    }

    #[test]
    fn the_list_matches_the_folder() {
        scene::assert_lists_the_folder(BUILT_IN, "lessons");
    }

    #[test]
    fn a_broken_lesson_says_what_is_wrong() {
        let text = r#"(title: "x", summary: "y", slides: [
            (title: "a", scene: "no-such-scene", narration: ["hi"]),
            (title: "b", scene: "seed000-triangle", step: Some("gamma2"), narration: [""]),
        ])"#;
        let lesson = Lesson::from_ron(text, "broken.ron").unwrap();
        let problems = lesson.problems();
        assert!(
            problems[0].contains("no built-in scene named “no-such-scene”"),
            "{problems:?}"
        );
        assert!(problems[1].contains("no narration"), "{problems:?}");
        assert!(problems[2].contains("has no step “gamma2”"), "{problems:?}");
        // A camera turns the 3D views and a render scene's pinhole, not seed 003's image plane.
        let cameras = r#"(title: "x", summary: "y", slides: [
            (title: "a", scene: "effect-shadows", camera: Some((yaw: 30, pitch: 20)),
             narration: ["hi"]),
            (title: "b", scene: "seed003-facing", camera: Some((yaw: 30, pitch: 20)),
             narration: ["hi"]),
        ])"#;
        let problems = Lesson::from_ron(cameras, "cameras.ron").unwrap().problems();
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].starts_with("slide 2"), "{problems:?}");
        assert!(problems[0].contains("a camera is for"), "{problems:?}");
        // A bug is rendered beside a render scene's image, not on a lecture scene.
        let bugs = r#"(title: "x", summary: "y", slides: [
            (title: "a", scene: "render-common-bugs", bug: Some(NegativeT), narration: ["hi"]),
            (title: "b", scene: "seed000-triangle", bug: Some(NegativeT), narration: ["hi"]),
        ])"#;
        let problems = Lesson::from_ron(bugs, "bugs.ron").unwrap().problems();
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].starts_with("slide 2"), "{problems:?}");
        assert!(
            problems[0].contains("a bug is rendered beside"),
            "{problems:?}"
        );
        let typo = Lesson::from_ron(r#"(title: "x", summry: "y", slides: [])"#, "typo.ron");
        assert!(typo.unwrap_err().to_string().starts_with("typo.ron:1:"));
    }
}
