//! A class question from end to end, without a network: the teacher's scene as a [`QuestionSpec`], the
//! spec read into an exact exercise problem (the exact solver gives the true answer, never a float),
//! the [`QuestionView`] a device draws, and the judging of a student's prediction.

use glam::{DVec2, DVec3};

use super::protocol::{Figure, Given, QuestionSpec, QuestionState, QuestionView, TrueAnswer};
use crate::exercise::{Inputs, Kind, Level, Problem};
use crate::math::exact::{Exact, shortest_decimal};
use crate::scene;

/// A predicted value counts as right within 1/20 of the true one (at least 1/20 absolute), judged in
/// exact arithmetic: a prediction dragged on a phone is a guess of where, not a computation, so 0.27
/// for β = 1/4 is right. As numerator and denominator.
pub const PREDICTION_TOLERANCE: (i64, i64) = (1, 20);

/// The longest number text read in a question or an answer.
const MAX_NUMBER_CHARS: usize = 40;

/// The largest power of ten a question or answer may write (`1e-30`): far past any classroom number,
/// and small enough that exact arithmetic on it is instant.
const MAX_EXPONENT: i64 = 40;

/// Why a question cannot be asked.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum QuestionError {
    /// Not one of the three solvers.
    #[error("unknown question kind '{0}' (expected segments, triangle or parallelogram)")]
    UnknownKind(String),
    /// The wrong count of points or coordinates.
    #[error("a {kind} question takes {points} points of {dims} coordinates")]
    Shape {
        /// The kind.
        kind: &'static str,
        /// Points expected.
        points: usize,
        /// Coordinates each.
        dims: usize,
    },
    /// A coordinate that is not a plain number.
    #[error("{0}")]
    Number(String),
    /// The exact solver's outcome is one no question can ask (touching segments, a point beyond two
    /// edges at once).
    #[error(
        "this problem's outcome (touching, or beyond two edges at once) is not one a student can pick; move a point a little"
    )]
    NoSingleOutcome,
    /// The prompt is empty or too long.
    #[error("a question's wording has 1 to 300 characters")]
    Prompt,
}

/// Reads a number of a question or an answer exactly: a decimal or fraction of at most 40 characters,
/// with an exponent of at most ±40.
pub fn read_number(text: &str) -> Result<Exact, String> {
    let text = text.trim();
    if text.chars().count() > MAX_NUMBER_CHARS {
        return Err(format!(
            "a number has at most {MAX_NUMBER_CHARS} characters"
        ));
    }
    for part in text.split('/') {
        if let Some((_, exponent)) = part.split_once(['e', 'E']) {
            match exponent.trim().parse::<i64>() {
                Ok(e) if e.abs() <= MAX_EXPONENT => {}
                _ => return Err(format!("'{text}': an exponent is at most ±{MAX_EXPONENT}")),
            }
        }
    }
    text.parse::<Exact>().map_err(|e| e.to_string())
}

/// The kind a spec names.
fn kind_of(name: &str) -> Result<Kind, QuestionError> {
    [Kind::Segments, Kind::Triangle, Kind::Parallelogram]
        .into_iter()
        .find(|kind| kind.name() == name)
        .ok_or_else(|| QuestionError::UnknownKind(name.chars().take(40).collect()))
}

/// The spec of a lecture scene's problem, asked with `prompt`; `None` for a render scene. Each
/// coordinate is written as the shortest decimal that reads back as the float, so 0.1 stays 0.1.
pub fn spec_of_scene(problem: &scene::Problem, prompt: &str) -> Option<QuestionSpec> {
    fn texts<const N: usize>(points: &[[f64; N]]) -> Vec<Vec<String>> {
        points
            .iter()
            .map(|p| p.iter().map(|x| shortest_decimal(*x)).collect())
            .collect()
    }
    let (kind, inputs) = match problem {
        scene::Problem::Segments(s) => (Kind::Segments, texts(&s.points().map(|p| p.to_array()))),
        scene::Problem::Triangle(t) => (Kind::Triangle, texts(&t.vectors().map(|v| v.to_array()))),
        scene::Problem::Parallelogram(p) => (
            Kind::Parallelogram,
            texts(&p.vectors().map(|v| v.to_array())),
        ),
        scene::Problem::Render(_) => return None,
    };
    Some(QuestionSpec {
        kind: kind.name().into(),
        prompt: prompt.into(),
        inputs,
    })
}

/// The default wording of a question about a scene of this kind (the phone says how to answer).
pub fn default_prompt(kind: &str) -> &'static str {
    match kind {
        "segments" => "Where do the segments cross?",
        "parallelogram" => "Where does the ray meet the parallelogram?",
        _ => "Where does the ray meet the triangle?",
    }
}

/// A question read and solved: the exact problem (with its true answer) and what devices show.
#[derive(Clone, Debug)]
pub struct Asked {
    /// The exact problem; its answer is the truth students are judged by.
    pub problem: Problem,
    /// The spec as the teacher sent it.
    pub spec: QuestionSpec,
}

impl Asked {
    /// Reads a spec: its kind, its numbers (exactly), and solves it with the exact solver.
    pub fn new(spec: QuestionSpec) -> Result<Asked, QuestionError> {
        let kind = kind_of(&spec.kind)?;
        let prompt = spec.prompt.trim();
        if prompt.is_empty() || prompt.chars().count() > 300 {
            return Err(QuestionError::Prompt);
        }
        let dims = if kind == Kind::Segments { 2 } else { 3 };
        let points = if kind == Kind::Segments { 4 } else { 5 };
        let shape = QuestionError::Shape {
            kind: kind.name(),
            points,
            dims,
        };
        if spec.inputs.len() != points || spec.inputs.iter().any(|p| p.len() != dims) {
            return Err(shape);
        }
        let mut numbers = Vec::with_capacity(points * dims);
        for text in spec.inputs.iter().flatten() {
            numbers.push(read_number(text).map_err(QuestionError::Number)?);
        }
        let inputs = match kind {
            Kind::Segments => Inputs::Segments(std::array::from_fn(|i| {
                std::array::from_fn(|j| numbers[i * 2 + j].clone())
            })),
            Kind::Triangle => Inputs::Triangle(std::array::from_fn(|i| {
                std::array::from_fn(|j| numbers[i * 3 + j].clone())
            })),
            Kind::Parallelogram => Inputs::Parallelogram(std::array::from_fn(|i| {
                std::array::from_fn(|j| numbers[i * 3 + j].clone())
            })),
        };
        let problem = Problem::new(0, inputs).ok_or(QuestionError::NoSingleOutcome)?;
        Ok(Asked { problem, spec })
    }

    /// The question as devices show it.
    pub fn view(&self, id: i64, number: i64, state: QuestionState) -> QuestionView {
        let kind = self.problem.kind();
        QuestionView {
            id,
            number,
            kind: kind.name().into(),
            spec: self.spec.clone(),
            prompt: self.spec.prompt.trim().into(),
            unknowns: kind.unknowns().iter().map(|u| u.1.to_string()).collect(),
            outcomes: outcomes(kind),
            inputs: self
                .problem
                .inputs
                .named()
                .iter()
                .map(|input| {
                    let coordinates: Vec<String> =
                        input.value.iter().map(Exact::fraction).collect();
                    format!("{} = ({})", input.name, coordinates.join(", "))
                })
                .collect(),
            figure: figure(&self.problem.inputs),
            state,
        }
    }

    /// The true answer.
    pub fn truth(&self) -> TrueAnswer {
        let answer = &self.problem.answer;
        TrueAnswer {
            outcome: answer.outcome.text(),
            values: answer.values.iter().map(|v| v.value.fraction()).collect(),
            numbers: answer.values.iter().map(|v| v.value.to_f64()).collect(),
            text: answer.text(),
        }
    }

    /// Checks a student's answer before it is stored: the outcome must be one offered and each value
    /// a readable number; returns the answer with its values trimmed.
    pub fn check_given(&self, given: Given) -> Result<Given, String> {
        let kind = self.problem.kind();
        if let Some(outcome) = &given.outcome
            && !outcomes(kind).contains(outcome)
        {
            return Err(format!(
                "'{}' is not an outcome of this question",
                outcome.chars().take(40).collect::<String>()
            ));
        }
        if given.values.len() > kind.unknowns().len() {
            return Err(format!(
                "this question asks for at most {} values",
                kind.unknowns().len()
            ));
        }
        let mut values = Vec::with_capacity(given.values.len());
        for value in given.values {
            let value = value
                .map(|v| v.trim().to_string())
                .filter(|v| !v.is_empty());
            if let Some(text) = &value {
                read_number(text)?;
            }
            values.push(value);
        }
        if given.outcome.is_none() && values.iter().all(Option::is_none) {
            return Err("an answer needs an outcome or a value".into());
        }
        Ok(Given {
            outcome: given.outcome,
            values,
        })
    }

    /// Whether an answer is right: its outcome (when given) is the true one and each value given is
    /// within 1/20 of the exact value (at least 1/20). An answer of values alone is right when the
    /// outcome is a hit and the values are.
    pub fn is_right(&self, given: &Given) -> bool {
        let answer = &self.problem.answer;
        let outcome_right = match &given.outcome {
            Some(outcome) => *outcome == answer.outcome.text(),
            None => answer.outcome.level() == Level::Hit,
        };
        // Judged exactly: |value − truth| ≤ 1/20 · max(1, |truth|).
        let (numerator, denominator) = PREDICTION_TOLERANCE;
        let tolerance = Exact::ratio(numerator, denominator).unwrap_or_default();
        let one = Exact::from_int(1);
        let values_right = given.values.iter().enumerate().all(|(i, value)| {
            let Some(value) = value else { return true };
            let (Some(truth), Ok(value)) = (answer.values.get(i), read_number(value)) else {
                return false;
            };
            let scale = truth.value.abs().max(one.clone());
            (value - truth.value.clone()).abs() <= tolerance.clone() * scale
        });
        outcome_right && values_right
    }
}

/// The numbers of an answer's values, for drawing (none where not given).
pub fn numbers_of(given: &Given) -> Vec<Option<f64>> {
    given
        .values
        .iter()
        .map(|v| {
            v.as_deref()
                .and_then(|t| read_number(t).ok())
                .map(|x| x.to_f64())
                .filter(|x| x.is_finite())
        })
        .collect()
}

/// Every outcome a student may pick for a kind, in teaching order.
pub fn outcomes(kind: Kind) -> Vec<String> {
    let mut all = vec!["hit".to_string()];
    all.extend(kind.edges().iter().map(|edge| format!("outside {edge}")));
    for level in [Level::Behind, Level::Parallel, Level::Degenerate] {
        if level.kinds().contains(&kind) {
            all.push(level.name().into());
        }
    }
    all
}

/// The figure a phone draws: segments as given, a triangle or parallelogram laid flat in its own plane.
fn figure(inputs: &Inputs) -> Figure {
    let f = |x: &Exact| x.to_f64();
    let points = match inputs {
        Inputs::Segments(points) => ["A1", "A2", "B1", "B2"]
            .iter()
            .zip(points)
            .map(|(name, p)| (name.to_string(), [f(&p[0]), f(&p[1])]))
            .collect(),
        Inputs::Triangle([a, b, c, ..]) => {
            let [a, b, c] = [a, b, c].map(|p| DVec3::new(f(&p[0]), f(&p[1]), f(&p[2])));
            let (u, v) = flat(b - a, c - a);
            vec![
                ("A".into(), [0.0, 0.0]),
                ("B".into(), u.to_array()),
                ("C".into(), v.to_array()),
            ]
        }
        Inputs::Parallelogram([_, e1, e2, ..]) => {
            let [e1, e2] = [e1, e2].map(|p| DVec3::new(f(&p[0]), f(&p[1]), f(&p[2])));
            let (u, v) = flat(e1, e2);
            vec![
                ("c".into(), [0.0, 0.0]),
                ("c+e1".into(), u.to_array()),
                ("c+e1+e2".into(), (u + v).to_array()),
                ("c+e2".into(), v.to_array()),
            ]
        }
    };
    Figure { points }
}

/// Two 3D edge vectors from one corner laid into a plane with their lengths and angle kept: the first
/// along x, the second above it. A zero or non-finite first edge falls back to the second's length.
fn flat(u: DVec3, v: DVec3) -> (DVec2, DVec2) {
    let length = u.length();
    if !(length.is_finite() && length > 0.0) {
        return (DVec2::ZERO, DVec2::new(0.0, v.length()));
    }
    let along = u.dot(v) / length;
    let across = u.cross(v).length() / length;
    let flat = (DVec2::new(length, 0.0), DVec2::new(along, across));
    if [flat.0, flat.1].iter().all(|p| p.is_finite()) {
        flat
    } else {
        (DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle_spec() -> QuestionSpec {
        // Seed 000's triangle: A (1, 0, 0), B (0, 1, 0), C (0, 0, 1), L at the origin, D (1, 1, 1).
        QuestionSpec {
            kind: "triangle".into(),
            prompt: "Where?".into(),
            inputs: vec![
                vec!["1".into(), "0".into(), "0".into()],
                vec!["0".into(), "1".into(), "0".into()],
                vec!["0".into(), "0".into(), "1".into()],
                vec!["0".into(), "0".into(), "0".into()],
                vec!["1".into(), "1".into(), "1".into()],
            ],
        }
    }

    #[test]
    fn the_truth_comes_from_the_exact_solver() {
        let asked = Asked::new(triangle_spec()).unwrap();
        let truth = asked.truth();
        assert_eq!(truth.outcome, "hit");
        assert_eq!(truth.values, ["1/3", "1/3", "1/3"]);
        let view = asked.view(7, 1, QuestionState::Open);
        assert_eq!(view.unknowns, ["β", "γ", "t"]);
        assert_eq!(
            view.outcomes,
            [
                "hit",
                "outside AB",
                "outside BC",
                "outside CA",
                "behind",
                "parallel",
                "degenerate"
            ]
        );
        // The flat triangle keeps the edge lengths: |B − A| = √2 and |C − B| = √2.
        let p = &view.figure.points;
        let length = |a: [f64; 2], b: [f64; 2]| DVec2::from(a).distance(DVec2::from(b));
        assert!((length(p[0].1, p[1].1) - 2f64.sqrt()).abs() < 1e-12);
        assert!((length(p[1].1, p[2].1) - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn predictions_are_judged_within_the_tolerance() {
        let asked = Asked::new(triangle_spec()).unwrap();
        let given = |outcome: Option<&str>, values: &[&str]| Given {
            outcome: outcome.map(String::from),
            values: values.iter().map(|v| Some(v.to_string())).collect(),
        };
        assert!(asked.is_right(&given(Some("hit"), &["0.35", "0.3"])));
        assert!(asked.is_right(&given(None, &["1/3", "1/3", "1/3"])));
        assert!(!asked.is_right(&given(Some("hit"), &["0.5", "0.3"])));
        // The bound is exact: 1/3 + 1/20 = 23/60 is right, a hair past it is not (f64 rounds them equal).
        assert!(asked.is_right(&given(Some("hit"), &["23/60", "1/3"])));
        assert!(!asked.is_right(&given(Some("hit"), &["0.38333333333333333333334", "1/3"])));
        assert!(!asked.is_right(&given(Some("behind"), &[])));
        assert!(asked.check_given(given(Some("inside"), &[])).is_err());
        assert!(asked.check_given(given(Some("hit"), &["1e99999"])).is_err());
        assert!(asked.check_given(given(None, &[])).is_err());
    }

    #[test]
    fn bad_specs_are_refused_with_a_reason() {
        let mut spec = triangle_spec();
        spec.inputs.pop();
        assert!(matches!(Asked::new(spec), Err(QuestionError::Shape { .. })));
        let mut spec = triangle_spec();
        spec.kind = "sphere".into();
        assert!(Asked::new(spec).is_err());
        let mut spec = triangle_spec();
        spec.inputs[0][0] = "1e10000/1e-10000".into();
        assert!(matches!(Asked::new(spec), Err(QuestionError::Number(_))));
    }
}
