//! The record of one solve: an ordered list of steps, each a title, one sentence and a payload.
//!
//! One Trace, many readers: the CLI prints it as text, JSON or LaTeX, the app's step panel draws it, and
//! the tests read it. Solvers fill it with the very numbers they computed, so no reader ever recomputes.

use serde::Serialize;

use crate::math::exact::{Exact, SignedRoot};
use crate::math::linalg::{CofactorTerm, M2, M3};
use crate::math::real::{Precision, Real};

mod latex;
mod text;

pub use latex::{number as latex_number, step_to_latex, to_latex};
pub use text::{
    check_value, expansion_products, format_float, payload_lines, step_to_text, to_text,
};

/// A number as computed: its float value and, when the solve was exact, its exact value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Number {
    /// The value (rounded to the nearest f64 when exact; f32 values convert to f64 without change).
    pub value: f64,
    /// The exact fraction (`"17/22"`), present only for exact solves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exact: Option<String>,
    /// The exact value as a person should read it: the fraction when short, else `≈` and the float.
    #[serde(skip)]
    pub exact_shown: Option<String>,
    /// The precision it was computed in (decides how many digits are meaningful).
    #[serde(skip)]
    pub precision: Precision,
    /// When the exact value is a float's and is shown as its shortest decimal (`-6.7`), the whole exact
    /// decimal expansion (`-6.70000000000000017763568394002504646778106689453125`), for readers that
    /// offer it on request.
    #[serde(skip)]
    pub float_expansion: Option<String>,
}

impl Number {
    /// Records a solver value.
    pub fn of<R: Real>(x: &R) -> Number {
        let exact = x.to_exact();
        let float_expansion = exact
            .as_ref()
            .filter(|e| !e.is_short() && e.as_float().is_some())
            .and_then(Exact::decimal_expansion);
        Number {
            value: x.to_f64(),
            exact: exact.as_ref().map(Exact::fraction),
            exact_shown: exact.as_ref().map(Exact::display),
            precision: R::PRECISION,
            float_expansion,
        }
    }

    /// A float that is not the output of a solver precision (e.g. a distance with a square root).
    pub fn float(value: f64, precision: Precision) -> Number {
        Number {
            value,
            exact: None,
            exact_shown: None,
            precision,
            float_expansion: None,
        }
    }

    /// An exact root (a length): its nearest float, shown as [`SignedRoot::display`] writes it.
    pub fn root(root: &SignedRoot) -> Number {
        Number {
            value: root.to_f64(),
            exact: Some(root.full()),
            exact_shown: Some(root.display()),
            precision: Precision::Exact,
            float_expansion: None,
        }
    }

    /// How a person reads it: `1/3` for short exact values, else the float with meaningful digits.
    pub fn shown(&self) -> String {
        match &self.exact_shown {
            Some(shown) => shown.clone(),
            None => format_float(self.value, self.precision),
        }
    }

    /// True if [`Number::shown`] is an exact fraction or integer.
    pub fn shown_exactly(&self) -> bool {
        self.float_expansion.is_none()
            && self
                .exact_shown
                .as_deref()
                .is_some_and(|s| !s.starts_with('≈'))
    }

    /// True if the value is exactly zero (in exact mode, or a float that is 0).
    pub fn is_zero(&self) -> bool {
        match &self.exact {
            Some(fraction) => fraction == "0",
            None => self.value == 0.0,
        }
    }

    /// [`Number::shown`], in parentheses when it is negative or a fraction, so that a product
    /// reads right: `(11/2)·5`, `3·(−3)`.
    pub fn factor(&self) -> String {
        let shown = self.shown();
        if shown.starts_with('-') || shown.starts_with('−') || shown.contains('/') {
            format!("({shown})")
        } else {
            shown
        }
    }
}

/// Records a vector.
pub fn numbers<R: Real, const N: usize>(v: &[R; N]) -> Vec<Number> {
    v.iter().map(Number::of).collect()
}

/// A column of a system's matrix, by what it is: the app colours and marks columns by this, never by
/// the label. JSON writes the label (`A−B`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Column {
    /// A−B, the first column of the triangle's M (the β leg reversed).
    AMinusB,
    /// A−C, the second column of the triangle's M.
    AMinusC,
    /// D, the ray's direction (third column of the triangle's M).
    D,
    /// e1, the parallelogram's first edge.
    E1,
    /// e2, the parallelogram's second edge.
    E2,
    /// −d, the parallelogram ray's direction reversed.
    MinusD,
    /// A2−A1, segment A's direction.
    A2MinusA1,
    /// B1−B2, segment B's direction reversed.
    B1MinusB2,
    /// Y, the right-hand side (in Cramer's M1, M2, M3, where it replaces a column).
    Y,
    /// A column with no name (the entries of an inverse).
    Unnamed,
}

impl Column {
    /// The column's label as the step panel writes it.
    pub fn label(self) -> &'static str {
        match self {
            Column::AMinusB => "A−B",
            Column::AMinusC => "A−C",
            Column::D => "D",
            Column::E1 => "e1",
            Column::E2 => "e2",
            Column::MinusD => "−d",
            Column::A2MinusA1 => "A2−A1",
            Column::B1MinusB2 => "B1−B2",
            Column::Y => "Y",
            Column::Unnamed => "",
        }
    }
}

impl Serialize for Column {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.label())
    }
}

/// A named matrix, with a label for each column and, for Cramer's M1..M3, the column replaced by Y.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Matrix {
    /// Plain name, e.g. `M1`.
    pub name: String,
    /// LaTeX name, e.g. `M_1`.
    pub latex_name: String,
    /// The entries, row by row.
    pub rows: Vec<Vec<Number>>,
    /// What each column is (`A−B`, `A−C`, `D`, `Y`), written as its label.
    #[serde(rename = "column_labels")]
    pub columns: Vec<Column>,
    /// The column replaced by the right-hand side, if any (0-based).
    pub replaced_column: Option<usize>,
}

impl Matrix {
    /// Records a 3x3 matrix.
    pub fn of3<R: Real>(name: &str, latex_name: &str, m: &M3<R>, columns: [Column; 3]) -> Matrix {
        Matrix {
            name: name.into(),
            latex_name: latex_name.into(),
            rows: m.iter().map(numbers).collect(),
            columns: columns.to_vec(),
            replaced_column: None,
        }
    }

    /// Records a 2x2 matrix.
    pub fn of2<R: Real>(name: &str, latex_name: &str, m: &M2<R>, columns: [Column; 2]) -> Matrix {
        Matrix {
            name: name.into(),
            latex_name: latex_name.into(),
            rows: m.iter().map(numbers).collect(),
            columns: columns.to_vec(),
            replaced_column: None,
        }
    }

    /// Marks a column as replaced by the right-hand side Y (and labels it `Y`).
    pub fn replacing(mut self, column: usize) -> Matrix {
        self.replaced_column = Some(column);
        if let Some(replaced) = self.columns.get_mut(column) {
            *replaced = Column::Y;
        }
        self
    }
}

/// A named vector.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Vector {
    /// Plain name, e.g. `Y`.
    pub name: String,
    /// LaTeX name.
    pub latex_name: String,
    /// The components.
    pub components: Vec<Number>,
}

impl Vector {
    /// Records a vector.
    pub fn of<R: Real, const N: usize>(name: &str, latex_name: &str, v: &[R; N]) -> Vector {
        Vector {
            name: name.into(),
            latex_name: latex_name.into(),
            components: numbers(v),
        }
    }
}

/// One term `sign · element · |minor|` of a determinant's expansion along its first row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExpansionTerm {
    /// +1 or −1.
    pub sign: i8,
    /// The first-row element.
    pub element: Number,
    /// The minor (2x2 for a 3x3 determinant, 1x1 for a 2x2 one).
    pub minor: Vec<Vec<Number>>,
    /// The minor's determinant.
    pub minor_det: Number,
}

/// A determinant with its cofactor expansion written out with the numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Determinant {
    /// Plain name of the matrix, e.g. `M1`.
    pub of: String,
    /// LaTeX name of the matrix.
    pub latex_of: String,
    /// The expansion along the first row.
    pub terms: Vec<ExpansionTerm>,
    /// The determinant.
    pub value: Number,
}

impl Determinant {
    /// Records a 3x3 determinant from the terms the solver summed.
    pub fn of3<R: Real>(
        of: &str,
        latex_of: &str,
        terms: &[CofactorTerm<R>; 3],
        value: &R,
    ) -> Determinant {
        Determinant {
            of: of.into(),
            latex_of: latex_of.into(),
            terms: terms
                .iter()
                .map(|term| ExpansionTerm {
                    sign: term.sign,
                    element: Number::of(&term.element),
                    minor: term.minor.iter().map(numbers).collect(),
                    minor_det: Number::of(&term.minor_det),
                })
                .collect(),
            value: Number::of(value),
        }
    }

    /// Records a 2x2 determinant `ad − bc` as two terms with 1x1 minors.
    pub fn of2<R: Real>(of: &str, latex_of: &str, m: &M2<R>, value: &R) -> Determinant {
        let term = |sign: i8, element: &R, minor: &R| ExpansionTerm {
            sign,
            element: Number::of(element),
            minor: vec![vec![Number::of(minor)]],
            minor_det: Number::of(minor),
        };
        Determinant {
            of: of.into(),
            latex_of: latex_of.into(),
            terms: vec![term(1, &m[0][0], &m[1][1]), term(-1, &m[0][1], &m[1][0])],
            value: Number::of(value),
        }
    }
}

/// A named operand of a formula: `|M1|` with its value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Operand {
    /// Plain symbol.
    pub symbol: String,
    /// LaTeX symbol.
    pub latex: String,
    /// Its value.
    pub value: Number,
}

impl Operand {
    /// Records an operand.
    pub fn of<R: Real>(symbol: &str, latex: &str, value: &R) -> Operand {
        Operand {
            symbol: symbol.into(),
            latex: latex.into(),
            value: Number::of(value),
        }
    }
}

/// How a scalar was obtained.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "form", rename_all = "kebab-case")]
#[allow(clippy::large_enum_variant)] // one per step of a trace: size does not matter, plain data reads best
pub enum Formula {
    /// `numerator / denominator`, as in Cramer's rule.
    Quotient {
        /// The numerator.
        numerator: Operand,
        /// The denominator.
        denominator: Operand,
    },
    /// Any other expression, written symbolically.
    Expression {
        /// Plain text, e.g. `1 − β − γ`.
        text: String,
        /// LaTeX.
        latex: String,
    },
}

/// A named scalar with how it was computed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Scalar {
    /// Plain symbol, e.g. `β`.
    pub symbol: String,
    /// LaTeX symbol, e.g. `\beta`.
    pub latex: String,
    /// How it was computed, if worth saying.
    pub formula: Option<Formula>,
    /// The value.
    pub value: Number,
    /// An exact closed form when the value is not rational, e.g. `√3` for a distance.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_form: Option<ClosedForm>,
}

/// An exact value that is not a fraction, written out (only when it is short enough to read).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClosedForm {
    /// Plain text, e.g. `√3`.
    pub text: String,
    /// LaTeX, e.g. `\sqrt{3}`.
    pub latex: String,
}

/// An inequality tested by the solver.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    /// Plain text, e.g. `β + γ ≤ 1`.
    pub inequality: String,
    /// LaTeX, e.g. `\beta + \gamma \le 1`.
    pub latex: String,
    /// The value of the left-hand side that was tested.
    pub value: Number,
    /// Whether it held.
    pub passed: bool,
    /// What failing it means, e.g. `P is beyond edge BC`.
    pub meaning: String,
}

/// What a solver decided, in one word. JSON, the text and LaTeX readers write the kebab-case word; the
/// app colours a verdict by [`Status::meets`] and [`Status::misses`], never by the word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// The ray meets the triangle or parallelogram.
    Hit,
    /// An intersection method's miss, without a reason.
    Miss,
    /// The ray's line meets the plane outside the shape.
    MissOutside,
    /// The shape is behind the ray's start (t ≤ t_min).
    MissBehind,
    /// The ray or the segments are parallel.
    Parallel,
    /// The triangle (or parallelogram) has no area.
    DegenerateTriangle,
    /// An input cannot be used (not finite, or a zero direction).
    InvalidInput,
    /// The segments cross inside both.
    Crossing,
    /// The segments touch at an end.
    Touching,
    /// The segments' lines cross outside a segment.
    LinesCrossOutside,
    /// Collinear segments that overlap.
    CollinearOverlap,
    /// Collinear segments apart.
    CollinearDisjoint,
    /// A segment of zero length.
    DegenerateSegment,
}

impl Status {
    /// The stable kebab-case word (`hit`, `miss-outside`, `crossing`, …).
    pub fn word(self) -> &'static str {
        match self {
            Status::Hit => "hit",
            Status::Miss => "miss",
            Status::MissOutside => "miss-outside",
            Status::MissBehind => "miss-behind",
            Status::Parallel => "parallel",
            Status::DegenerateTriangle => "degenerate-triangle",
            Status::InvalidInput => "invalid-input",
            Status::Crossing => "crossing",
            Status::Touching => "touching",
            Status::LinesCrossOutside => "lines-cross-outside",
            Status::CollinearOverlap => "collinear-overlap",
            Status::CollinearDisjoint => "collinear-disjoint",
            Status::DegenerateSegment => "degenerate-segment",
        }
    }

    /// The two meet: a hit, crossing or touching segments, or an overlap.
    pub fn meets(self) -> bool {
        matches!(
            self,
            Status::Hit | Status::Crossing | Status::Touching | Status::CollinearOverlap
        )
    }

    /// A well-posed miss: outside, behind, crossing outside, collinear apart. (Parallel, degenerate
    /// and invalid inputs are neither a meeting nor a miss.)
    pub fn misses(self) -> bool {
        matches!(
            self,
            Status::Miss
                | Status::MissOutside
                | Status::MissBehind
                | Status::LinesCrossOutside
                | Status::CollinearDisjoint
        )
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.word())
    }
}

/// The outcome of the solve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// What was decided.
    pub status: Status,
    /// One sentence for people.
    pub message: String,
}

/// The payload of a step.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[allow(clippy::large_enum_variant)] // one per step of a trace: size does not matter, plain data reads best
pub enum Payload {
    /// The linear system `M X = Y`.
    System {
        /// The matrix M.
        matrix: Matrix,
        /// The unknowns X, by symbol.
        unknowns: Vec<String>,
        /// The unknowns in LaTeX.
        unknowns_latex: Vec<String>,
        /// The right-hand side Y.
        rhs: Vector,
    },
    /// A matrix.
    Matrix(Matrix),
    /// A determinant with its expansion.
    Determinant(Determinant),
    /// A vector.
    Vector(Vector),
    /// A scalar.
    Scalar(Scalar),
    /// A tested inequality.
    Check(Check),
    /// The verdict.
    Verdict(Verdict),
    /// Expressions in symbols (seed 002's derivation), and whether an identity was checked to hold.
    Symbolic(Symbolic),
}

/// Lines of symbolic algebra: a matrix of expressions, an expanded determinant, an identity.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Symbolic {
    /// Plain text, a line each.
    pub lines: Vec<String>,
    /// The same in LaTeX.
    pub latex: String,
    /// For an identity: whether it held, both as polynomials and on the scene's numbers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holds: Option<bool>,
}

/// One step of a solve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Step {
    /// A stable key (`M1`, `det_M1`, `beta`, `check_beta`, `verdict`) for readers that look a step up.
    pub id: String,
    /// A short title.
    pub title: String,
    /// One sentence of explanation.
    pub explanation: String,
    /// What was computed.
    pub payload: Payload,
}

impl Step {
    /// A step.
    pub fn new(
        id: impl Into<String>,
        title: impl Into<String>,
        explanation: impl Into<String>,
        payload: Payload,
    ) -> Step {
        Step {
            id: id.into(),
            title: title.into(),
            explanation: explanation.into(),
            payload,
        }
    }
}

/// The record of one solve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Trace {
    /// Which solver made it (`segments`, `triangle`, `parallelogram`, …).
    pub solver: String,
    /// The precision it ran in.
    pub precision: Precision,
    /// The steps, in order.
    pub steps: Vec<Step>,
}

impl Trace {
    /// An empty trace.
    pub fn new(solver: &str, precision: Precision) -> Trace {
        Trace {
            solver: solver.into(),
            precision,
            steps: Vec::new(),
        }
    }

    /// The step with this id.
    pub fn step(&self, id: &str) -> Option<&Step> {
        self.steps.iter().find(|s| s.id == id)
    }

    /// The scalar step with this id.
    pub fn scalar(&self, id: &str) -> Option<&Scalar> {
        match &self.step(id)?.payload {
            Payload::Scalar(s) => Some(s),
            _ => None,
        }
    }

    /// The verdict, if the solve got that far (it always does).
    pub fn verdict(&self) -> Option<&Verdict> {
        self.steps.iter().rev().find_map(|s| match &s.payload {
            Payload::Verdict(v) => Some(v),
            _ => None,
        })
    }

    /// The index of the verdict's step: a presentation or lesson keeps the verdict off the view
    /// before it.
    pub fn verdict_step(&self) -> Option<usize> {
        self.steps
            .iter()
            .position(|s| matches!(s.payload, Payload::Verdict(_)))
    }

    /// Every check, in order.
    pub fn checks(&self) -> impl Iterator<Item = &Check> {
        self.steps.iter().filter_map(|s| match &s.payload {
            Payload::Check(c) => Some(c),
            _ => None,
        })
    }
}

/// Somewhere steps can go: a [`Recorder`], or `()` which drops them at no cost (the compiler removes
/// the calls entirely), for hot loops that must not pay for tracing.
pub trait StepSink {
    /// True if steps are kept.
    fn is_recording(&self) -> bool;
    /// Adds a step built by `build`, which runs only when recording.
    fn push(&mut self, build: impl FnOnce() -> Step);
}

impl StepSink for () {
    #[inline(always)]
    fn is_recording(&self) -> bool {
        false
    }
    #[inline(always)]
    fn push(&mut self, _build: impl FnOnce() -> Step) {}
}

impl StepSink for Recorder {
    fn is_recording(&self) -> bool {
        true
    }
    #[inline(always)]
    fn push(&mut self, build: impl FnOnce() -> Step) {
        self.trace.steps.push(build());
    }
}

/// Keeps every step of a solve. Not recording is `()`, the other [`StepSink`].
#[derive(Debug)]
pub struct Recorder {
    trace: Trace,
}

impl Recorder {
    /// A recorder for `solver`'s steps in `precision`.
    pub fn new(solver: &str, precision: Precision) -> Recorder {
        Recorder {
            trace: Trace::new(solver, precision),
        }
    }

    /// The recorded trace.
    pub fn into_trace(self) -> Trace {
        self.trace
    }
}
