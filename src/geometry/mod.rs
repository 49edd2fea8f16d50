//! Pure geometry: the lecture's solvers, generic over the precision they run in. Never imports egui.

pub mod parallelogram;
pub mod segments;
pub mod triangle;

pub use crate::math::{Precision, Real};

use glam::{DVec2, DVec3};

use crate::math::{InPrecision, in_precision};
use crate::trace::{Payload, Recorder, Status, Step, Trace, Verdict};

/// A lecture problem in one precision, and its solver: the answer alone (no step is even formatted),
/// or the answer with every step.
pub trait Solver {
    /// What the solver decides and computes.
    type Answer;
    /// The answer.
    fn solve(&self) -> Self::Answer;
    /// The answer and every step that led to it.
    fn solve_traced(&self) -> (Self::Answer, Trace);
}

/// Each lecture module's problem answers through that module's own `solve` and `solve_traced`.
macro_rules! solver_in_module {
    ($($module:ident: $problem:ident -> $answer:ident),* $(,)?) => {$(
        impl<R: Real> Solver for $module::$problem<R> {
            type Answer = $module::$answer<R>;
            fn solve(&self) -> Self::Answer {
                $module::solve(self)
            }
            fn solve_traced(&self) -> (Self::Answer, Trace) {
                $module::solve_traced(self)
            }
        }
    )*};
}

solver_in_module! {
    segments: SegmentPair -> SegmentsSolution,
    triangle: RayTriangle -> TriangleSolution,
    parallelogram: RayParallelogram -> ParallelogramSolution,
}

/// A lecture problem as the app holds it: f64 inputs, read into a precision when solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Inputs {
    /// A1, A2, B1, B2.
    Segments([DVec2; 4]),
    /// A, B, C, L, D and t_min.
    Triangle([DVec3; 5], f64),
    /// c, e1, e2, o, d.
    Parallelogram([DVec3; 5]),
}

/// The steps of solving `inputs`, read as `reading`, in `precision`.
pub fn traced(inputs: Inputs, reading: Reading, precision: Precision) -> Trace {
    struct Traced(Inputs, Reading);
    impl InPrecision for Traced {
        type Output = Trace;
        fn run<R: Real>(self) -> Trace {
            let Traced(inputs, reading) = self;
            match inputs {
                Inputs::Segments(points) => segments::solve_inputs_traced::<R>(reading, points).1,
                Inputs::Triangle(vectors, t_min) => {
                    triangle::solve_inputs_traced::<R>(reading, vectors, t_min).1
                }
                Inputs::Parallelogram(vectors) => {
                    parallelogram::solve_inputs_traced::<R>(reading, vectors).1
                }
            }
        }
    }
    in_precision(precision, Traced(inputs, reading))
}

/// One of the lecture's problems, as a type: its float inputs and its answer in any precision.
pub trait Lecture {
    /// The inputs as floats (points and vectors as the app and scene files hold them).
    type Floats: Copy;
    /// The answer in precision `R`.
    type Answer<R: Real>;
    /// Reads the inputs as `reading` says and solves in precision `R`.
    fn answer<R: Real>(floats: Self::Floats, reading: Reading) -> Self::Answer<R>;
    /// The inputs as [`traced`] takes them.
    fn inputs(floats: Self::Floats) -> Inputs;
}

/// Two segments (seed 000).
pub enum SegmentsLecture {}
/// A ray and a triangle (seeds 000, 002, 003).
pub enum TriangleLecture {}
/// A ray and a parallelogram (seed 001).
pub enum ParallelogramLecture {}

/// Each lecture type reads its floats through its module's `solve_inputs`, and hands them to
/// [`traced`] as its `Inputs` variant: `|floats pattern| (arguments) => variant`.
macro_rules! lecture_of_module {
    ($($lecture:ident: $module:ident::$answer:ident, $floats:ty,
        |$pattern:pat_param| ($($arg:ident),*) => $variant:ident;)*) => {$(
        impl Lecture for $lecture {
            type Floats = $floats;
            type Answer<R: Real> = $module::$answer<R>;
            fn answer<R: Real>($pattern: $floats, reading: Reading) -> Self::Answer<R> {
                $module::solve_inputs(reading, $($arg),*)
            }
            fn inputs($pattern: $floats) -> Inputs {
                Inputs::$variant($($arg),*)
            }
        }
    )*};
}

lecture_of_module! {
    SegmentsLecture: segments::SegmentsSolution, [DVec2; 4], |points| (points) => Segments;
    TriangleLecture: triangle::TriangleSolution, ([DVec3; 5], f64),
        |(vectors, t_min)| (vectors, t_min) => Triangle;
    ParallelogramLecture: parallelogram::ParallelogramSolution, [DVec3; 5],
        |vectors| (vectors) => Parallelogram;
}

/// A problem solved for a view: in f64 (to draw), exactly (to show fractions), and traced in the
/// precision the step panel shows.
pub struct Shown<L: Lecture> {
    /// The f64 solve.
    pub float: L::Answer<f64>,
    /// The exact solve.
    pub exact: L::Answer<crate::math::exact::Exact>,
    /// Every step, in the chosen precision.
    pub trace: Trace,
}

impl<L: Lecture> Shown<L> {
    /// Solves `floats`, read as `reading`, for a view whose step panel shows `precision`.
    pub fn new(floats: L::Floats, reading: Reading, precision: Precision) -> Shown<L> {
        Shown {
            float: L::answer(floats, reading),
            exact: L::answer(floats, reading),
            trace: traced(L::inputs(floats), reading, precision),
        }
    }
}

/// Records the verdict on an input that cannot be used (the whole trace of such a solve).
fn record_refusal(rec: &mut Recorder, status: Status, message: impl FnOnce() -> String) {
    rec.push(|| {
        Step::new("verdict", "Verdict", "An input cannot be used.", {
            Payload::Verdict(Verdict {
                status,
                message: message(),
            })
        })
    });
}

/// A named input that is not a finite number (or does not fit the precision).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidInput {
    /// The input's name as the lecture writes it (`A`, `D`, `t_min`, …).
    pub field: String,
    /// What is wrong with it, in a few words.
    pub problem: String,
}

impl std::fmt::Display for InvalidInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.problem)
    }
}

/// How float inputs become solver numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Reading {
    /// The float's own value (exact for [`crate::math::exact::Exact`]: 0.1 is 3602879701896397/2^55).
    #[default]
    FloatValue,
    /// The shortest decimal that prints as the float (0.1 is 1/10), as a person typed or dragged it.
    AsWritten,
}

/// Converts one float input, naming it if it cannot be represented (only exact numbers refuse NaN).
pub(crate) fn read<R: Real>(reading: Reading, name: &str, x: f64) -> Result<R, InvalidInput> {
    let value = match reading {
        Reading::FloatValue => R::from_f64(x),
        Reading::AsWritten => R::from_f64_as_written(x),
    };
    value.ok_or_else(|| InvalidInput {
        field: name.into(),
        problem: "is not a finite number".into(),
    })
}

/// Converts a float vector input.
pub(crate) fn read_vec<R: Real, const N: usize>(
    reading: Reading,
    name: &str,
    v: [f64; N],
) -> Result<[R; N], InvalidInput> {
    let parts: Vec<R> = v
        .iter()
        .map(|x| read(reading, name, *x))
        .collect::<Result<_, _>>()?;
    Ok(parts
        .try_into()
        .unwrap_or_else(|_| unreachable!("N parts in, N out")))
}

/// Checks that every named input is finite in precision `R` (an f64 can overflow to ∞ in f32).
pub(crate) fn check_finite<R: Real, const N: usize>(
    fields: &[(&str, &[R; N])],
) -> Result<(), InvalidInput> {
    for (name, value) in fields {
        if let Some(bad) = value.iter().find(|x| !x.is_finite()) {
            let problem = if bad.to_f64().is_nan() {
                "is not a number (NaN)".to_string()
            } else {
                format!("is infinite in {} (too large?)", R::PRECISION.name())
            };
            return Err(InvalidInput {
                field: name.to_string(),
                problem,
            });
        }
    }
    Ok(())
}

/// True if a quantity counts as zero relative to the scale of the inputs it came from.
///
/// Exact arithmetic needs a true zero (`exactly_zero`). For floats, `magnitude ≤ TOLERANCE · scale`,
/// where `scale` bounds the magnitude the quantity could have had (e.g. `|u|·|v|` for `|u × v|`), so the
/// test is a dimensionless sine and does not change when every input is scaled by the same factor.
pub(crate) fn negligible<R: Real>(magnitude: f64, scale: f64, exactly_zero: bool) -> bool {
    if R::TOLERANCE == 0.0 {
        exactly_zero
    } else {
        exactly_zero || magnitude <= R::TOLERANCE * scale
    }
}
