//! Pure geometry: the lecture's solvers, generic over the precision they run in. Never imports egui.

pub mod parallelogram;
pub mod segments;
mod steps;
pub mod triangle;

pub use crate::math::{Precision, Real};

use std::marker::PhantomData;

use crate::math::{InPrecision, in_precision};
use crate::trace::{Payload, Recorder, Status, Step, StepSink, Trace, Verdict};

/// One of the lecture's problems, as a type: how its float inputs are read, and its solver.
///
/// A solver computes every value first, as the slide does, and records the steps afterwards into a
/// [`StepSink`]: a [`Recorder`] keeps them, `()` drops them at no cost. The command line, the lessons,
/// the exercises and the views all solve through this trait.
pub trait Lecture {
    /// The solver's name in a trace: `segments`, `triangle` or `parallelogram`.
    const NAME: &'static str;
    /// The inputs as floats (points and vectors as the app and scene files hold them).
    type Floats: Copy;
    /// The problem in precision `R`.
    type Problem<R: Real>;
    /// The answer in precision `R`.
    type Answer<R: Real>;

    /// Reads float inputs as `reading` says, naming the first one precision `R` cannot hold.
    fn read<R: Real>(
        floats: Self::Floats,
        reading: Reading,
    ) -> Result<Self::Problem<R>, InvalidInput>;

    /// Solves `problem`, recording every step into `steps`.
    fn solve<R: Real>(problem: &Self::Problem<R>, steps: &mut impl StepSink) -> Self::Answer<R>;

    /// The answer to inputs that could not be read, its one step recorded into `steps`.
    fn refuse<R: Real>(bad: InvalidInput, steps: &mut impl StepSink) -> Self::Answer<R>;

    /// The answer and every step that led to it.
    fn traced<R: Real>(problem: &Self::Problem<R>) -> (Self::Answer<R>, Trace) {
        let mut steps = Recorder::new(Self::NAME, R::PRECISION);
        let answer = Self::solve(problem, &mut steps);
        (answer, steps.into_trace())
    }

    /// Reads float inputs and solves them (an input that cannot be read is refused).
    fn solve_floats<R: Real>(
        floats: Self::Floats,
        reading: Reading,
        steps: &mut impl StepSink,
    ) -> Self::Answer<R> {
        match Self::read(floats, reading) {
            Ok(problem) => Self::solve(&problem, steps),
            Err(bad) => Self::refuse(bad, steps),
        }
    }

    /// The steps of solving float inputs in `precision`, chosen at run time.
    fn trace_floats(floats: Self::Floats, reading: Reading, precision: Precision) -> Trace
    where
        Self: Sized,
    {
        in_precision(precision, TraceFloats::<Self>(floats, reading, PhantomData))
    }
}

/// [`Lecture::trace_floats`] in the precision [`in_precision`] picks.
struct TraceFloats<L: Lecture>(L::Floats, Reading, PhantomData<L>);

impl<L: Lecture> InPrecision for TraceFloats<L> {
    type Output = Trace;
    fn run<R: Real>(self) -> Trace {
        let mut steps = Recorder::new(L::NAME, R::PRECISION);
        L::solve_floats::<R>(self.0, self.1, &mut steps);
        steps.into_trace()
    }
}

/// Two segments (seed 000).
pub enum SegmentsLecture {}
/// A ray and a triangle (seeds 000, 002, 003).
pub enum TriangleLecture {}
/// A ray and a parallelogram (seed 001).
pub enum ParallelogramLecture {}

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
            float: L::solve_floats(floats, reading, &mut ()),
            exact: L::solve_floats(floats, reading, &mut ()),
            trace: L::trace_floats(floats, reading, precision),
        }
    }
}

/// Records the verdict on an input that cannot be used (the whole trace of such a solve).
fn record_refusal(rec: &mut impl StepSink, status: Status, message: impl FnOnce() -> String) {
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
