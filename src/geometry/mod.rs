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

impl<L: Lecture> AsRef<Trace> for Shown<L> {
    fn as_ref(&self) -> &Trace {
        &self.trace
    }
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

/// The most decimal digits a solve's exact inputs may hold in all (numerators and denominators
/// together, reduced). The solve's work grows with about the square of this: 20 000 digits take about
/// a second, the 80 000 of eight coordinates like 1e±10000 half a minute.
pub const EXACT_DIGIT_BUDGET: usize = 20_000;

/// Checks that exact inputs fit [`EXACT_DIGIT_BUDGET`] (floats always do), before any arithmetic.
pub(crate) fn check_size<R: Real, const N: usize>(
    fields: &[(&str, &[R; N])],
    more: &[&R],
) -> Result<(), InvalidInput> {
    let digits: usize = fields
        .iter()
        .flat_map(|(_, v)| v.iter())
        .chain(more.iter().copied())
        .map(Real::digits)
        .sum();
    if digits <= EXACT_DIGIT_BUDGET {
        return Ok(());
    }
    Err(InvalidInput {
        field: "inputs".into(),
        problem: format!(
            "too large for exact arithmetic: about {digits} digits in all, past the budget of \
             {EXACT_DIGIT_BUDGET} (the solve would take minutes)"
        ),
    })
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

#[cfg(test)]
mod tests {
    use super::{
        Lecture, ParallelogramLecture, Precision, Reading, SegmentsLecture, TriangleLecture,
    };
    use crate::trace::{Trace, to_latex, to_text};
    use glam::{DVec2, DVec3};

    /// No reader may print ∞ or a false 0 for a length exact arithmetic knows.
    fn assert_reads_every_length(trace: &Trace, expected: &[&str]) {
        let text = to_text(trace);
        let latex = to_latex(trace);
        assert!(!text.contains("= ∞") && !text.contains("= -∞"), "{text}");
        assert!(
            !latex.contains("= \\infty") && !latex.contains("=\\infty"),
            "{latex}"
        );
        for shown in expected {
            assert!(text.contains(shown), "{shown} missing from\n{text}");
        }
    }

    #[test]
    fn lengths_beyond_the_float_range_read_as_exact_roots_not_infinity_or_zero() {
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let exact = |vectors, t_min| {
            TriangleLecture::trace_floats((vectors, t_min), Reading::AsWritten, Precision::Exact)
        };
        // Legs of 10^200: twice the area is 10^400, past f64's ∞; the distance t·|D| = 1.
        let huge = [
            v(0.0, 0.0, 0.0),
            v(1e200, 0.0, 0.0),
            v(0.0, 1e200, 0.0),
            v(1.0, 1.0, 1.0),
        ];
        let trace = exact([huge[0], huge[1], huge[2], huge[3], v(0.0, 0.0, -1.0)], 0.0);
        assert_reads_every_length(&trace, &["|(A−B)×(A−C)| / 2 = ≈5e399", "t·|D| = 1"]);
        // Legs of 10^-200: the area 10^-400 / 2 is not 0.
        let tiny = [v(0.0, 0.0, 0.0), v(1e-200, 0.0, 0.0), v(0.0, 1e-200, 0.0)];
        let trace = exact(
            [
                tiny[0],
                tiny[1],
                tiny[2],
                v(1e-201, 1e-201, 1.0),
                v(0.0, 0.0, -1.0),
            ],
            0.0,
        );
        assert_reads_every_length(&trace, &["|(A−B)×(A−C)| / 2 = ≈5e-401", "|D| = 1;"]);
        // A ray of direction 10^300 reaching t = 10^-300 travels 1, its |D| read as ≈1e300.
        let trace = exact(
            [
                huge[0],
                v(4.0, 0.0, 0.0),
                v(0.0, 4.0, 0.0),
                huge[3],
                v(0.0, 0.0, -1e300),
            ],
            0.0,
        );
        assert_reads_every_length(&trace, &["|D| = ≈1e300", "t·|D| = 1"]);

        let diagonal = [DVec2::new(0.0, 0.0), DVec2::new(1e300, 1e300)];
        let points = [
            diagonal[0],
            diagonal[1],
            DVec2::new(0.0, 1e300),
            DVec2::new(1e300, 0.0),
        ];
        let trace = SegmentsLecture::trace_floats(points, Reading::AsWritten, Precision::Exact);
        assert_reads_every_length(&trace, &["min(|A2−A1|, |B2−B1|) = 1.414213562e300"]);
        let square = [
            v(0.0, 0.0, 0.0),
            v(1e300, 0.0, 0.0),
            v(0.0, 1e300, 0.0),
            v(1.0, 1.0, 1.0),
        ];
        let vectors = [
            square[0],
            square[1],
            square[2],
            square[3],
            v(0.0, 0.0, -1.0),
        ];
        let trace =
            ParallelogramLecture::trace_floats(vectors, Reading::AsWritten, Precision::Exact);
        assert_reads_every_length(&trace, &["|e1 × e2| = ≈1e600"]);
    }
}

#[cfg(test)]
mod budget {
    use super::triangle::{RayTriangle, TriangleMiss, TriangleOutcome, solve};
    use super::{EXACT_DIGIT_BUDGET, segments};
    use crate::math::exact::Exact;

    #[test]
    fn exact_inputs_past_the_digit_budget_are_refused_before_any_arithmetic() {
        let exact = |text: &str| text.parse::<Exact>().unwrap();
        // Eight coordinates of 10^±10000: each within the ±10 000 exponent limit, 80 000 digits in all
        // (a solve of them ran for half a minute).
        let (big, small) = (exact("1e10000"), exact("1e-10000"));
        let zero = Exact::from_int(0);
        let problem = RayTriangle {
            a: [small.clone(), zero.clone(), zero.clone()],
            b: [big.clone(), small.clone(), zero.clone()],
            c: [zero.clone(), big.clone(), small.clone()],
            origin: [exact("0.1"), small.clone(), Exact::from_int(1)],
            dir: [small.clone(), zero.clone(), Exact::from_int(-1)],
            t_min: zero.clone(),
        };
        let solved = solve(&problem, &mut ());
        let TriangleOutcome::Miss(TriangleMiss::InvalidInput(bad)) = &solved.outcome else {
            panic!("{:?}", solved.outcome)
        };
        assert!(
            bad.to_string().contains("too large for exact arithmetic"),
            "{bad}"
        );
        assert!(
            bad.to_string().contains(&EXACT_DIGIT_BUDGET.to_string()),
            "{bad}"
        );
        // One fraction 1e10000/1e-10000 = 10^20000 is past it alone.
        let pair = segments::SegmentPair {
            a1: [zero.clone(), zero.clone()],
            a2: [exact("1e10000/1e-10000"), zero.clone()],
            b1: [zero.clone(), Exact::from_int(1)],
            b2: [Exact::from_int(1), zero.clone()],
        };
        let solved = segments::solve(&pair, &mut ());
        assert!(
            solved.message().contains("too large for exact arithmetic"),
            "{}",
            solved.message()
        );
        // A thousand-digit coordinate is well within it, and solved.
        let problem = RayTriangle {
            b: [exact("1e1000"), zero.clone(), zero.clone()],
            ..RayTriangle::<Exact>::read(
                crate::geometry::Reading::FloatValue,
                [
                    [0.0; 3],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.1, 0.1, 1.0],
                    [0.0, 0.0, -1.0],
                ]
                .map(glam::DVec3::from),
                0.0,
            )
            .unwrap()
        };
        assert_eq!(solve(&problem, &mut ()).outcome, TriangleOutcome::Hit);
    }
}

/// How the text reader writes the lecture solvers' numbers (here, above both, as the layers ask).
#[cfg(test)]
mod readable_numbers {
    use crate::geometry::segments::SegmentPair;
    use crate::geometry::triangle::RayTriangle;
    use crate::geometry::{Lecture, SegmentsLecture, TriangleLecture};
    use crate::trace::to_text;
    use glam::{DVec2, DVec3};

    fn segments_text(points: [[f64; 2]; 4]) -> String {
        let pair = SegmentPair::<crate::math::exact::Exact>::read(
            crate::geometry::Reading::FloatValue,
            points.map(DVec2::from_array),
        )
        .unwrap();
        to_text(&SegmentsLecture::traced(&pair).1)
    }

    #[test]
    fn fractions_in_products_and_quotients_are_parenthesised() {
        let text = segments_text([[1.5, 2.0], [6.0, 1.25], [2.0, 6.0], [5.0, 1.0]]);
        // Not 9/2·5, which reads as 9/(2·5); not 29/2 / 81/4.
        assert!(text.contains("|M| = (9/2)·5 − (-3)·(-3/4)"), "{text}");
        assert!(
            text.contains("t = |M1| / |M| = (29/2) / (81/4) = 58/81"),
            "{text}"
        );
        // Each check names the value it tested.
        assert!(
            text.contains("✓ 0 ≤ t ≤ 1   (t = 58/81 ≈ 0.7160493827)"),
            "{text}"
        );
        assert!(text.contains("(|M| = 81/4 ≈ 20.25)"), "{text}");
        assert!(
            text.contains("(min(|A2−A1|, |B2−B1|) = 4.562071898)"),
            "{text}"
        );
        assert!(!text.contains("(value"), "{text}");
    }

    #[test]
    fn float_inputs_read_as_their_shortest_decimal() {
        let v = [
            [-6.7, 0.0, 0.0],
            [0.0, 3.0, 0.0],
            [0.0, 0.0, 3.0],
            [0.1, 0.2, 0.3],
            [1.0, 1.0, 1.0],
        ];
        let problem = RayTriangle::<crate::math::exact::Exact>::read(
            crate::geometry::Reading::FloatValue,
            v.map(DVec3::from_array),
            0.0,
        )
        .unwrap();
        let (_, trace) = TriangleLecture::traced(&problem);
        let text = to_text(&trace);
        // The float −6.7 is computed with its exact value but read as the shortest decimal, and a
        // value that is not a float is marked ≈: never "≈-6.7000000000e0".
        assert!(text.contains("⎡ -6.7  -6.7  1 ⎤"), "{text}");
        assert!(text.contains("Y = (≈-6.8, -0.2, -0.3)"), "{text}");
        assert!(!text.contains("e0"), "{text}");
        let m = match &trace.step("M").unwrap().payload {
            crate::trace::Payload::Matrix(m) => m.clone(),
            other => panic!("{other:?}"),
        };
        assert_eq!(
            m.rows[0][0].float_expansion.as_deref(),
            Some("-6.70000000000000017763568394002504646778106689453125")
        );
        assert!(!m.rows[0][0].shown_exactly());
    }
}
