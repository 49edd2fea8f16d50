//! Scene files (RON): a titled problem the app can load, save and open.
//!
//! Every lecture example and hard case ships as a file in `assets/scenes/`, embedded in the binary so the
//! preset menu works wherever raylab runs. A malformed file is reported with its name, line and column.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use crate::geometry::{
    Lecture, ParallelogramLecture, Precision, Reading, SegmentsLecture, TriangleLecture,
};
use crate::trace::Trace;

pub mod check;
pub mod lighting;
pub mod render;

pub use render::RenderScene;

/// Two 2D segments A1–A2 and B1–B2.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentsScene {
    /// Start of segment A.
    pub a1: [f64; 2],
    /// End of segment A.
    pub a2: [f64; 2],
    /// Start of segment B.
    pub b1: [f64; 2],
    /// End of segment B.
    pub b2: [f64; 2],
}

/// A triangle A, B, C and a ray L + tD.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriangleScene {
    /// Vertex A.
    pub a: [f64; 3],
    /// Vertex B.
    pub b: [f64; 3],
    /// Vertex C.
    pub c: [f64; 3],
    /// The ray's origin L.
    pub origin: [f64; 3],
    /// The ray's direction D.
    pub dir: [f64; 3],
    /// Hits need t > t_min.
    #[serde(default)]
    pub t_min: f64,
}

/// A parallelogram c + α e1 + β e2 and a ray o + t d.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelogramScene {
    /// The corner c.
    pub corner: [f64; 3],
    /// Edge vector e1.
    pub e1: [f64; 3],
    /// Edge vector e2.
    pub e2: [f64; 3],
    /// The ray's origin o.
    pub origin: [f64; 3],
    /// The ray's direction d.
    pub dir: [f64; 3],
}

/// The problem a scene sets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Problem {
    /// Two 2D segments.
    Segments(SegmentsScene),
    /// A ray and a triangle.
    Triangle(TriangleScene),
    /// A ray and a parallelogram.
    Parallelogram(ParallelogramScene),
    /// A per-pixel render: camera, objects and effects.
    Render(RenderScene),
}

impl SegmentsScene {
    /// A1, A2, B1, B2 as the solver takes them.
    pub fn points(&self) -> [DVec2; 4] {
        [self.a1, self.a2, self.b1, self.b2].map(DVec2::from)
    }
}

impl TriangleScene {
    /// A, B, C, L, D as the solver takes them.
    pub fn vectors(&self) -> [DVec3; 5] {
        [self.a, self.b, self.c, self.origin, self.dir].map(DVec3::from)
    }
}

impl ParallelogramScene {
    /// c, e1, e2, o, d as the solver takes them.
    pub fn vectors(&self) -> [DVec3; 5] {
        [self.corner, self.e1, self.e2, self.origin, self.dir].map(DVec3::from)
    }
}

impl Problem {
    /// The steps of solving the lecture problem, its inputs read as `reading`, in `precision`;
    /// `None` for a render scene.
    pub fn trace(&self, reading: Reading, precision: Precision) -> Option<Trace> {
        Some(match self {
            Problem::Segments(s) => SegmentsLecture::trace_floats(s.points(), reading, precision),
            Problem::Triangle(t) => {
                TriangleLecture::trace_floats((t.vectors(), t.t_min), reading, precision)
            }
            Problem::Parallelogram(p) => {
                ParallelogramLecture::trace_floats(p.vectors(), reading, precision)
            }
            Problem::Render(_) => return None,
        })
    }
}

/// The inputs of one kind of lecture problem, as a type: which [`Problem`] variant holds them.
pub trait LectureScene: Clone + 'static {
    /// The inputs in `problem`, if it is this kind.
    fn of(problem: &Problem) -> Option<&Self>;
    /// The inputs as a problem.
    fn into_problem(self) -> Problem;
}

/// Each scene type is held by the [`Problem`] variant of its name.
macro_rules! lecture_scene {
    ($($scene:ident in $variant:ident),*) => {$(
        impl LectureScene for $scene {
            fn of(problem: &Problem) -> Option<&$scene> {
                match problem {
                    Problem::$variant(scene) => Some(scene),
                    _ => None,
                }
            }
            fn into_problem(self) -> Problem {
                Problem::$variant(self)
            }
        }
    )*};
}

lecture_scene!(SegmentsScene in Segments, TriangleScene in Triangle, ParallelogramScene in Parallelogram);

/// The first built-in problem that `pick` takes: a view's starting scene.
#[allow(
    clippy::expect_used,
    reason = "a preset of every kind ships; the scene tests load each one"
)]
pub fn first_built_in<T>(pick: impl Fn(Problem) -> Option<T>) -> T {
    built_in()
        .into_iter()
        .find_map(|scene| pick(scene.problem))
        .expect("a preset of each kind ships")
}

/// A scene file: a title, a one-line note, and the problem.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Shown in the preset menu.
    pub title: String,
    /// One line on what the scene shows.
    pub note: String,
    /// The problem.
    pub problem: Problem,
}

/// Why a scene could not be read: the file, where in it (when known), and what was wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The file name (or `<text>`).
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based column, when known.
    pub column: Option<usize>,
    /// What was wrong or expected.
    pub problem: SceneProblem,
}

/// What was wrong with a scene file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneProblem {
    /// Not the file itself (missing, a directory, too large, unreadable).
    #[error(transparent)]
    Read(#[from] crate::files::ReadError),
    /// Not UTF-8 text, from this byte (counted from 0).
    #[error("not a text file (invalid UTF-8 at byte {0})")]
    NotText(usize),
    /// Not a scene in RON (what ron expected, a typo's field named plainly).
    #[error("{}", describe(.0))]
    Format(Box<ron::Error>),
    /// A scene, with numbers or settings it cannot be drawn with.
    #[error(transparent)]
    Check(#[from] check::CheckError),
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.line, self.column) {
            (Some(line), Some(column)) => {
                write!(f, "{}:{line}:{column}: {}", self.file, self.problem)
            }
            _ => write!(f, "{}: {}", self.file, self.problem),
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.problem)
    }
}
impl Scene {
    /// Parses RON text; `file` names it in errors.
    pub fn from_ron(text: &str, file: &str) -> Result<Scene, SceneError> {
        // A byte-order mark (as some Windows editors write) is not part of the scene.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let scene: Scene = ron::from_str(text).map_err(|e| SceneError {
            file: file.into(),
            line: Some(e.span.start.line),
            column: Some(e.span.start.col),
            problem: SceneProblem::Format(Box::new(e.code)),
        })?;
        scene.check_finite().map_err(|error| SceneError {
            file: file.into(),
            line: None,
            column: None,
            problem: error.into(),
        })?;
        Ok(scene)
    }

    /// Pretty RON, as saved.
    #[allow(
        clippy::expect_used,
        reason = "a scene holds only numbers, strings and enums, which RON always writes"
    )]
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new().depth_limit(3);
        ron::ser::to_string_pretty(self, config).expect("scenes always serialize")
    }

    /// Reads a scene file from disk (a regular file of at most [`crate::files::SCENE`]'s size).
    pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
        use crate::files::{SCENE, read_regular};
        let name = path.display().to_string();
        let failed = |problem: SceneProblem| SceneError {
            file: name.clone(),
            line: None,
            column: None,
            problem,
        };
        let bytes = read_regular(path, SCENE).map_err(|e| failed(e.into()))?;
        let text = String::from_utf8(bytes)
            .map_err(|e| failed(SceneProblem::NotText(e.utf8_error().valid_up_to())))?;
        Scene::from_ron(&text, &name)
    }

    /// Writes the scene to disk: into a temporary file beside `path`, renamed over it when complete.
    pub fn save(&self, path: &std::path::Path) -> std::io::Result<()> {
        let text = self.to_ron();
        crate::files::write_atomically(path, |out| out.write_all(text.as_bytes()))
    }

    /// NaN and infinities are not valid coordinates in a file.
    fn check_finite(&self) -> Result<(), check::CheckError> {
        let values: Vec<f64> = match &self.problem {
            Problem::Segments(s) => [s.a1, s.a2, s.b1, s.b2].concat(),
            Problem::Triangle(t) => [t.a, t.b, t.c, t.origin, t.dir, [t.t_min; 3]].concat(),
            Problem::Parallelogram(p) => [p.corner, p.e1, p.e2, p.origin, p.dir].concat(),
            Problem::Render(render) => return render.check(),
        };
        match values.iter().find(|v| !v.is_finite()) {
            Some(&value) => Err(check::CheckError::NotFinite {
                what: "coordinates",
                value,
            }),
            None => Ok(()),
        }
    }
}

/// What ron's error says, with an unknown field (usually a typo) named plainly.
fn describe(code: &ron::Error) -> String {
    match code {
        ron::Error::NoSuchStructField {
            expected,
            found,
            outer,
        } => {
            let within = outer
                .as_ref()
                .map(|o| format!(" in {o}"))
                .unwrap_or_default();
            let names: Vec<String> = expected.iter().map(|n| format!("'{n}'")).collect();
            let expected = match names.len() {
                1 => names[0].clone(),
                _ => format!("one of {}", names.join(", ")),
            };
            format!("unknown field '{found}'{within}, expected {expected}")
        }
        other => other.to_string(),
    }
}

/// The scenes shipped in `assets/scenes/`, embedded at compile time: (file name, RON text).
pub const BUILT_IN: &[(&str, &str)] = &[
    (
        "seed000-segments-cross.ron",
        include_str!("../../assets/scenes/seed000-segments-cross.ron"),
    ),
    (
        "seed000-segments-miss.ron",
        include_str!("../../assets/scenes/seed000-segments-miss.ron"),
    ),
    (
        "segments-touching.ron",
        include_str!("../../assets/scenes/segments-touching.ron"),
    ),
    (
        "segments-parallel.ron",
        include_str!("../../assets/scenes/segments-parallel.ron"),
    ),
    (
        "segments-collinear.ron",
        include_str!("../../assets/scenes/segments-collinear.ron"),
    ),
    (
        "seed000-triangle.ron",
        include_str!("../../assets/scenes/seed000-triangle.ron"),
    ),
    (
        "seed000-alternative-1.ron",
        include_str!("../../assets/scenes/seed000-alternative-1.ron"),
    ),
    (
        "seed000-alternative-2.ron",
        include_str!("../../assets/scenes/seed000-alternative-2.ron"),
    ),
    (
        "seed000-alternative-3.ron",
        include_str!("../../assets/scenes/seed000-alternative-3.ron"),
    ),
    (
        "seed003-ray.ron",
        include_str!("../../assets/scenes/seed003-ray.ron"),
    ),
    (
        "triangle-parallel.ron",
        include_str!("../../assets/scenes/triangle-parallel.ron"),
    ),
    (
        "triangle-outside.ron",
        include_str!("../../assets/scenes/triangle-outside.ron"),
    ),
    (
        "triangle-behind.ron",
        include_str!("../../assets/scenes/triangle-behind.ron"),
    ),
    (
        "triangle-degenerate.ron",
        include_str!("../../assets/scenes/triangle-degenerate.ron"),
    ),
    (
        "seed001-parallelogram.ron",
        include_str!("../../assets/scenes/seed001-parallelogram.ron"),
    ),
    (
        "seed003-facing.ron",
        include_str!("../../assets/scenes/seed003-facing.ron"),
    ),
    (
        "seed003-barycentric.ron",
        include_str!("../../assets/scenes/seed003-barycentric.ron"),
    ),
    (
        "render-textured-quad.ron",
        include_str!("../../assets/scenes/render-textured-quad.ron"),
    ),
    (
        "render-transformed.ron",
        include_str!("../../assets/scenes/render-transformed.ron"),
    ),
    (
        "render-mesh.ron",
        include_str!("../../assets/scenes/render-mesh.ron"),
    ),
    (
        "render-cornell-box.ron",
        include_str!("../../assets/scenes/render-cornell-box.ron"),
    ),
    (
        "effect-shadows.ron",
        include_str!("../../assets/scenes/effect-shadows.ron"),
    ),
    (
        "effect-reflections.ron",
        include_str!("../../assets/scenes/effect-reflections.ron"),
    ),
    (
        "effect-refraction.ron",
        include_str!("../../assets/scenes/effect-refraction.ron"),
    ),
    (
        "effect-ambient-occlusion.ron",
        include_str!("../../assets/scenes/effect-ambient-occlusion.ron"),
    ),
    (
        "effect-antialiasing.ron",
        include_str!("../../assets/scenes/effect-antialiasing.ron"),
    ),
    (
        "render-common-bugs.ron",
        include_str!("../../assets/scenes/render-common-bugs.ron"),
    ),
];

/// Parses every built-in scene, in menu order.
#[allow(
    clippy::expect_used,
    reason = "the shipped scenes are embedded at build time; tests load every one"
)]
pub fn built_in() -> Vec<Scene> {
    BUILT_IN
        .iter()
        .map(|(file, text)| Scene::from_ron(text, file).expect("built-in scenes are valid"))
        .collect()
}

/// A built-in scene by its file name without `.ron` (`triangle-outside`), as a web page's
/// `?preset=` names it.
#[allow(
    clippy::expect_used,
    reason = "the shipped scenes are embedded at build time; tests load every one"
)]
pub fn preset(stem: &str) -> Option<Scene> {
    BUILT_IN
        .iter()
        .find(|(file, _)| file.strip_suffix(".ron") == Some(stem))
        .map(|(file, text)| Scene::from_ron(text, file).expect("built-in scenes are valid"))
}

/// The built-in scenes' names for [`preset`].
pub fn preset_names() -> Vec<&'static str> {
    stems(BUILT_IN)
}

/// The names of files built into the binary, without `.ron` (scenes here, lessons too).
pub(crate) fn stems(files: &[(&'static str, &str)]) -> Vec<&'static str> {
    files
        .iter()
        .map(|(file, _)| file.trim_end_matches(".ron"))
        .collect()
}

/// Checks that `files` lists exactly the `.ron` files of `assets/<folder>` (a file added to the
/// folder but not to the list would never ship).
#[cfg(test)]
pub(crate) fn assert_lists_the_folder(files: &[(&str, &str)], folder: &str) {
    let dir = format!("{}/assets/{folder}", env!("CARGO_MANIFEST_DIR"));
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".ron"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = files.iter().map(|(f, _)| f.to_string()).collect();
    listed.sort();
    assert_eq!(
        listed, on_disk,
        "every file of {dir} is listed, and only those"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_byte_order_mark_does_not_break_a_scene() {
        let scene = &built_in()[0];
        let marked = format!("\u{feff}{}", scene.to_ron());
        assert_eq!(&Scene::from_ron(&marked, "marked.ron").unwrap(), scene);
    }

    #[test]
    fn every_built_in_scene_parses_and_round_trips() {
        for scene in built_in() {
            assert!(!scene.title.is_empty() && !scene.note.is_empty());
            let again = Scene::from_ron(&scene.to_ron(), "again").unwrap();
            assert_eq!(again, scene);
        }
    }

    /// True when every field and value of `original` is in `written` (which may add defaults).
    fn keeps_everything(original: &ron::Value, written: &ron::Value) -> bool {
        use ron::Value;
        match (original, written) {
            (Value::Map(a), Value::Map(b)) => a
                .iter()
                .all(|(key, value)| b.get(key).is_some_and(|w| keeps_everything(value, w))),
            (Value::Seq(a), Value::Seq(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| keeps_everything(x, y))
            }
            (Value::Option(Some(a)), Value::Option(Some(b))) => keeps_everything(a, b),
            (Value::Number(a), Value::Number(b)) => a.into_f64() == b.into_f64(),
            (a, b) => a == b,
        }
    }

    /// Each shipped file, written back from what was read, still holds every field it had: a field
    /// renamed or dropped in code fails here (and, being unknown, fails to read at all).
    #[test]
    fn every_shipped_scene_is_written_back_unchanged() {
        for (file, text) in BUILT_IN {
            let scene = Scene::from_ron(text, file).unwrap();
            let written = scene.to_ron();
            let original: ron::Value = ron::from_str(text).unwrap();
            let again: ron::Value = ron::from_str(&written).unwrap();
            assert!(
                keeps_everything(&original, &again),
                "{file} lost data when written back:\n{written}"
            );
            assert_eq!(Scene::from_ron(&written, file).unwrap(), scene, "{file}");
        }
    }

    #[test]
    fn an_unknown_field_is_refused_where_it_is() {
        let base = BUILT_IN
            .iter()
            .find(|(file, _)| *file == "render-mesh.ron")
            .unwrap()
            .1;
        for (from, to, found, within) in [
            (
                "effects:",
                "methd: Some(\"bogus\"), effects:",
                "methd",
                "RenderScene",
            ),
            (
                "color: (0.3",
                "transfrom: (scale: (2.0, 2.0, 2.0)), color: (0.3",
                "transfrom",
                "Object",
            ),
            (
                "color: (0.3",
                "texure: Some(\"x.png\"), color: (0.3",
                "texure",
                "Object",
            ),
            ("title:", "bogus: 1, title:", "bogus", "Scene"),
            ("fov_y: 35.0", "fov_y: 35.0, roll: 3.0", "roll", "Pinhole"),
            ("obj: \"", "ob: \"", "ob", "Mesh"),
        ] {
            let text = base.replacen(from, to, 1);
            let line = text
                .lines()
                .position(|l| l.contains(&format!("{found}:")))
                .unwrap()
                + 1;
            let err = Scene::from_ron(&text, "typo.ron").unwrap_err();
            assert_eq!(err.line, Some(line), "{err}");
            let message = err.to_string();
            assert!(
                message.contains(&format!("unknown field '{found}' in {within}, expected ")),
                "{message}"
            );
        }
        // Every other scene type too: segments, triangle, parallelogram and a transform.
        for text in [
            "(title: \"x\", note: \"y\", problem: Segments((a1: (0.0, 0.0), a2: (1.0, 0.0), b1: (0.0, 1.0), b2: (1.0, 1.0), a3: (0.0, 0.0))))",
            "(title: \"x\", note: \"y\", problem: Triangle((a: (0.0, 0.0, 0.0), b: (1.0, 0.0, 0.0), c: (0.0, 1.0, 0.0), origin: (0.0, 0.0, 1.0), dir: (0.0, 0.0, -1.0), tmin: 0.5)))",
            "(title: \"x\", note: \"y\", problem: Parallelogram((corner: (0.0, 0.0, 0.0), e1: (1.0, 0.0, 0.0), e2: (0.0, 1.0, 0.0), origin: (0.0, 0.0, 1.0), direction: (0.0, 0.0, -1.0))))",
            "(title: \"x\", note: \"y\", problem: Render((width: 4, height: 4, camera: ImagePlane(x: (1.0, -1.0), y: (1.0, -1.0), z: 1.0), objects: [(shape: Parallelogram(corner: (0.0, 0.0, 3.0), e1: (1.0, 0.0, 0.0), e2: (0.0, 1.0, 0.0)), transform: (translation: (1.0, 0.0, 0.0)))], effects: [])))",
        ] {
            let err = Scene::from_ron(text, "typo.ron").unwrap_err();
            assert!(
                err.problem.to_string().starts_with("unknown field"),
                "{err}"
            );
        }
    }

    #[test]
    fn presets_are_found_by_file_stem() {
        let scene = preset("triangle-outside").unwrap();
        assert!(matches!(scene.problem, Problem::Triangle(_)));
        assert!(preset("triangle-outside.ron").is_none());
        assert!(preset("nothing").is_none());
        assert_eq!(preset_names().len(), BUILT_IN.len());
        assert!(preset_names().contains(&"seed000-triangle"));
    }

    #[test]
    fn built_in_list_matches_the_folder() {
        assert_lists_the_folder(BUILT_IN, "scenes");
    }

    #[test]
    fn malformed_files_name_line_and_column() {
        let text = "(\n    title: \"x\",\n    note: \"y\",\n    problem: Segments((a1: (1.0, 2.0), a2: (1.0,), b1: (0.0, 0.0), b2: (1.0, 1.0))),\n)";
        let err = Scene::from_ron(text, "bad.ron").unwrap_err();
        assert_eq!(err.file, "bad.ron");
        assert_eq!(err.line, Some(4));
        assert!(err.to_string().starts_with("bad.ron:4:"), "{err}");
        let err = Scene::from_ron("(title: \"x\", note: \"y\")", "short.ron").unwrap_err();
        assert!(err.problem.to_string().contains("problem"), "{err}");
        let nan = "(title: \"x\", note: \"y\", problem: Segments((a1: (NaN, 2.0), a2: (1.0, 1.0), b1: (0.0, 0.0), b2: (1.0, 1.0))))";
        let err = Scene::from_ron(nan, "nan.ron").unwrap_err();
        assert!(err.problem.to_string().contains("finite"), "{err}");
    }
}
