//! The steps the three lecture solvers share in shape: the system M X = Y with M and Y, Cramer's
//! matrices, the |M| ≠ 0 check, a quotient |Mi| / |M|, any check, and the verdict. Each solver
//! gives its own names and words; the layout of a step is written once, here.

use crate::math::Real;
use crate::math::exact::{Exact, SignedRoot};
use crate::math::linalg::{dot, norm_f64};
use crate::trace::{
    Check, Formula, Matrix, Number, Operand, Payload, Scalar, Status, Step, StepSink, Vector,
    Verdict,
};

/// The words of the system step and of its M and Y steps.
pub(super) struct SystemWords {
    /// How the system was set up ("Set L + tD = … and move the unknowns … to the left.").
    pub setup: &'static str,
    /// The titles and explanations of the M and Y steps, or `None` when the system step shows them
    /// alone.
    pub apart: Option<[[&'static str; 2]; 2]>,
    /// The system's title.
    pub title: &'static str,
    /// The unknowns as text and as LaTeX.
    pub unknowns: &'static [[&'static str; 2]],
}

/// Records the system M X = Y and, for the solvers that show them apart, M and Y.
pub(super) fn record_system(
    steps: &mut impl StepSink,
    words: &SystemWords,
    matrix: impl Fn() -> Matrix,
    rhs: impl Fn() -> Vector,
) {
    steps.push(|| {
        Step::new(
            "system",
            words.title,
            words.setup,
            Payload::System {
                matrix: matrix(),
                unknowns: words
                    .unknowns
                    .iter()
                    .map(|[text, _]| (*text).into())
                    .collect(),
                unknowns_latex: words
                    .unknowns
                    .iter()
                    .map(|[_, tex]| (*tex).into())
                    .collect(),
                rhs: rhs(),
            },
        )
    });
    let Some([[m_title, m_explanation], [y_title, y_explanation]]) = words.apart else {
        return;
    };
    steps.push(|| Step::new("M", m_title, m_explanation, Payload::Matrix(matrix())));
    steps.push(|| Step::new("Y", y_title, y_explanation, Payload::Vector(rhs())));
}

/// Records Cramer's matrices M1, M2, …: M with column i replaced by Y, each built by `matrix(i)`.
pub(super) fn record_replaced(
    steps: &mut impl StepSink,
    count: usize,
    matrix: impl Fn(usize) -> Matrix,
) {
    for i in 0..count {
        steps.push(|| {
            let name = format!("M{}", i + 1);
            Step::new(
                &name,
                format!("{name}: M with column {} replaced by Y", i + 1),
                "Cramer's rule: replace one column of M by the right-hand side Y.",
                Payload::Matrix(matrix(i).replacing(i)),
            )
        });
    }
}

/// A check step.
pub(super) fn check(
    [id, title, explanation]: [&str; 3],
    [inequality, latex]: [&str; 2],
    value: Number,
    passed: bool,
    meaning: impl Into<String>,
) -> Step {
    Step::new(
        id,
        title,
        explanation,
        Payload::Check(Check {
            inequality: inequality.into(),
            latex: latex.into(),
            value,
            passed,
            meaning: meaning.into(),
        }),
    )
}

/// The check |M| ≠ 0, with the solver's explanation and what failing it means.
pub(super) fn det_check<R: Real>(
    det_m: &R,
    parallel: bool,
    explanation: &str,
    meaning: &str,
) -> Step {
    let words = ["check_det", "|M| is not zero", explanation];
    check(
        words,
        ["|M| ≠ 0", "|M| \\neq 0"],
        Number::of(det_m),
        !parallel,
        meaning,
    )
}

/// The unknown `symbol` = |Mi| / |M| by Cramer's rule; `numerator` is |Mi| as text and LaTeX.
pub(super) fn record_quotient<R: Real>(
    steps: &mut impl StepSink,
    [id, symbol, latex]: [&str; 3],
    [numerator, numerator_latex]: [&str; 2],
    [det_mi, det_m, value]: [&R; 3],
    explanation: &str,
) {
    steps.push(|| {
        Step::new(id, format!("{symbol} by Cramer's rule"), explanation, {
            Payload::Scalar(Scalar {
                symbol: symbol.into(),
                latex: latex.into(),
                formula: Some(Formula::Quotient {
                    numerator: Operand::of(numerator, numerator_latex, det_mi),
                    denominator: Operand::of("|M|", "|M|", det_m),
                }),
                value: Number::of(value),
                closed_form: None,
            })
        })
    });
}

/// Records the verdict step.
pub(super) fn record_verdict(
    steps: &mut impl StepSink,
    explanation: impl Into<String>,
    status: Status,
    message: impl FnOnce() -> String,
) {
    steps.push(|| {
        Step::new(
            "verdict",
            "Verdict",
            explanation,
            Payload::Verdict(Verdict {
                status,
                message: message(),
            }),
        )
    });
}

/// The length |v| of a solver vector divided by `divisor` (|n| / 2 for a triangle's area), as a check
/// shows it: the float where it is a normal number; past the float range, in an exact solve, the exact
/// root √(v·v) / divisor, so it reads `≈1.7e400` rather than ∞, or `≈1e-400` rather than 0.
pub(super) fn length<R: Real, const N: usize>(v: &[R; N], divisor: f64) -> Number {
    let value = norm_f64(v) / divisor;
    if value.is_normal() {
        return Number::float(value, R::PRECISION);
    }
    let exact_root = dot(v, v)
        .to_exact()
        .filter(|square| !square.is_zero())
        .and_then(|square| {
            let divisor = Exact::from_f64(divisor * divisor)?;
            Some(SignedRoot {
                negative: false,
                square: square.checked_div(&divisor)?,
            })
        });
    match exact_root {
        Some(root) => Number::root(&root),
        None => Number::float(value, R::PRECISION),
    }
}
