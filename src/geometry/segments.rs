//! 2D segment–segment intersection (seed 000), as a 2x2 system solved by Cramer's rule.
//!
//! A(t) = A1 + t(A2−A1) and B(s) = B1 + s(B2−B1) meet where t(A2−A1) − s(B2−B1) = B1 − A1, i.e.
//! M X = Y with M = [A2−A1 | B1−B2], X = (t, s), Y = B1 − A1. The infinite lines cross whenever |M| ≠ 0;
//! the segments cross only if both t and s are in [0, 1].

use glam::DVec2;

use super::steps::{
    SystemWords, check, det_check, length, record_quotient, record_replaced, record_system,
    record_verdict,
};
use super::{
    InvalidInput, Lecture, Reading, SegmentsLecture, check_finite, check_size, negligible, read_vec,
};
use crate::math::linalg::{
    M2, V2, add, cross2, det2, dot, from_columns, is_zero_vector, norm_f64, scale, sub, with_column,
};
use crate::math::real::Real;
use crate::trace::{
    Column, Determinant, Formula, Matrix, Number, Payload, Scalar, Status, Step, StepSink, Vector,
};

/// Two segments, in the lecture's names.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentPair<R> {
    /// Start of segment A.
    pub a1: V2<R>,
    /// End of segment A.
    pub a2: V2<R>,
    /// Start of segment B.
    pub b1: V2<R>,
    /// End of segment B.
    pub b2: V2<R>,
}

impl SegmentPair<f64> {
    /// The pair in f64, which holds every input as it is.
    pub fn from_floats([a1, a2, b1, b2]: [DVec2; 4]) -> SegmentPair<f64> {
        SegmentPair {
            a1: a1.to_array(),
            a2: a2.to_array(),
            b1: b1.to_array(),
            b2: b2.to_array(),
        }
    }
}

impl<R: Real> SegmentPair<R> {
    /// Converts float inputs as [`Reading`] says.
    pub fn read(
        reading: Reading,
        [a1, a2, b1, b2]: [DVec2; 4],
    ) -> Result<SegmentPair<R>, InvalidInput> {
        Ok(SegmentPair {
            a1: read_vec(reading, "A1", a1.to_array())?,
            a2: read_vec(reading, "A2", a2.to_array())?,
            b1: read_vec(reading, "B1", b1.to_array())?,
            b2: read_vec(reading, "B2", b2.to_array())?,
        })
    }
}

/// How two segments relate.
#[derive(Clone, Debug, PartialEq)]
pub enum SegmentsOutcome {
    /// The segments cross at a point inside both: 0 < t < 1 and 0 < s < 1.
    Crossing,
    /// They meet at an endpoint of one or both: t or s is exactly 0 or 1, and both are in [0, 1].
    Touching,
    /// The lines cross, but outside at least one segment.
    LinesCrossOutside {
        /// t is outside [0, 1].
        t_outside: bool,
        /// s is outside [0, 1].
        s_outside: bool,
    },
    /// Parallel lines that never meet.
    Parallel,
    /// One line, and the segments share the interval in [`SegmentsSolution::overlap`].
    CollinearOverlap,
    /// One line, but the segments do not share a point.
    CollinearDisjoint,
    /// A segment has zero length.
    DegenerateSegment {
        /// A1 = A2.
        a: bool,
        /// B1 = B2.
        b: bool,
    },
    /// An input is NaN or infinite in this precision.
    InvalidInput(InvalidInput),
}

impl SegmentsOutcome {
    /// The stable kebab-case status word used in JSON.
    pub fn status(&self) -> Status {
        match self {
            SegmentsOutcome::Crossing => Status::Crossing,
            SegmentsOutcome::Touching => Status::Touching,
            SegmentsOutcome::LinesCrossOutside { .. } => Status::LinesCrossOutside,
            SegmentsOutcome::Parallel => Status::Parallel,
            SegmentsOutcome::CollinearOverlap => Status::CollinearOverlap,
            SegmentsOutcome::CollinearDisjoint => Status::CollinearDisjoint,
            SegmentsOutcome::DegenerateSegment { .. } => Status::DegenerateSegment,
            SegmentsOutcome::InvalidInput(_) => Status::InvalidInput,
        }
    }

    /// True if the segments share at least one point.
    pub fn segments_meet(&self) -> bool {
        matches!(
            self,
            SegmentsOutcome::Crossing
                | SegmentsOutcome::Touching
                | SegmentsOutcome::CollinearOverlap
        )
    }
}

/// The answer of [`solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentsSolution<R> {
    /// How the segments relate.
    pub outcome: SegmentsOutcome,
    /// t on the infinite line A, whenever the lines cross at one point.
    pub t: Option<R>,
    /// s on the infinite line B, whenever the lines cross at one point.
    pub s: Option<R>,
    /// A(t) = B(s), whenever the lines cross at one point.
    pub point: Option<V2<R>>,
    /// For collinear segments, the t values of B1 and B2 on line A.
    pub t_of_b: Option<[R; 2]>,
    /// For overlapping collinear segments, the shared part as an interval [t0, t1] of t.
    pub overlap: Option<[R; 2]>,
}

impl<R> SegmentsSolution<R> {
    fn new(outcome: SegmentsOutcome) -> SegmentsSolution<R> {
        SegmentsSolution {
            outcome,
            t: None,
            s: None,
            point: None,
            t_of_b: None,
            overlap: None,
        }
    }
}

impl<R: Real> SegmentsSolution<R> {
    /// The verdict's sentence for people (the same as in the trace, which need not be recorded).
    pub fn message(&self) -> String {
        verdict_message(self)
    }
}

const LABELS: [Column; 2] = [Column::A2MinusA1, Column::B1MinusB2];

impl Lecture for SegmentsLecture {
    const NAME: &'static str = "segments";
    type Floats = [DVec2; 4];
    type Problem<R: Real> = SegmentPair<R>;
    type Answer<R: Real> = SegmentsSolution<R>;

    fn read<R: Real>(points: [DVec2; 4], reading: Reading) -> Result<SegmentPair<R>, InvalidInput> {
        SegmentPair::read(reading, points)
    }

    fn solve<R: Real>(pair: &SegmentPair<R>, steps: &mut impl StepSink) -> SegmentsSolution<R> {
        solve(pair, steps)
    }

    fn refuse<R: Real>(bad: InvalidInput, steps: &mut impl StepSink) -> SegmentsSolution<R> {
        let solution = SegmentsSolution::new(SegmentsOutcome::InvalidInput(bad));
        super::record_refusal(steps, solution.outcome.status(), || {
            verdict_message(&solution)
        });
        solution
    }
}

/// Solves the 2x2 system by Cramer's rule and classifies, recording every step into `steps` (`()`
/// records nothing: the arithmetic is the same either way).
pub fn solve<R: Real>(pair: &SegmentPair<R>, steps: &mut impl StepSink) -> SegmentsSolution<R> {
    let values = values(pair);
    record(&values, steps);
    values.solution
}

/// Every value the lecture's solve computes, in the slide's order. A solve stops at the first check
/// that fails, so a stage after it is `None`.
struct Values<R> {
    /// The answer.
    solution: SegmentsSolution<R>,
    /// M = [A2−A1 | B1−B2] and Y = B1 − A1.
    system: Option<(M2<R>, V2<R>)>,
    /// The shorter segment's direction, and which segments have no length.
    lengths: Option<(V2<R>, [bool; 2])>,
    /// M1, M2: M with column i replaced by Y.
    replaced: Option<[M2<R>; 2]>,
    /// |M|.
    det: Option<R>,
    /// Whether |M| counts as zero (unset when |M| overflowed).
    parallel: Option<bool>,
    /// For parallel lines: (A2−A1) × (B1−A1), whether it counts as zero, and then t(B1), t(B2).
    collinear: Option<(R, bool)>,
    /// |M1|, |M2|.
    dets: Option<[R; 2]>,
    /// Whether t and s are in [0, 1].
    inside: Option<[bool; 2]>,
}

/// The arithmetic of the slide: M X = Y, the length and |M| checks, Cramer's rule, the two
/// interval checks; for parallel lines, whether they are one line and where B's ends sit on it.
/// Records nothing.
#[allow(
    clippy::expect_used,
    reason = "a division by |M| runs only after |M| was checked to be nonzero"
)]
fn values<R: Real>(p: &SegmentPair<R>) -> Values<R> {
    let mut v = Values::stopped_at(SegmentsOutcome::Crossing);
    let stop = |mut v: Values<R>, outcome| {
        v.solution.outcome = outcome;
        v
    };
    let inputs = [("A1", &p.a1), ("A2", &p.a2), ("B1", &p.b1), ("B2", &p.b2)];
    if let Err(bad) = check_finite(&inputs).and(check_size(&inputs, &[])) {
        return stop(v, SegmentsOutcome::InvalidInput(bad));
    }

    // The system M X = Y.
    let (d_a, b1_minus_b2) = (sub(&p.a2, &p.a1), sub(&p.b1, &p.b2));
    let y = sub(&p.b1, &p.a1);
    let (m, y) = v.system.insert((from_columns([&d_a, &b1_minus_b2]), y));

    // Both segments need a length.
    let (a_degenerate, b_degenerate) = (is_zero_vector(&d_a), is_zero_vector(&b1_minus_b2));
    let shorter = shorter(&d_a, &b1_minus_b2).clone();
    v.lengths = Some((shorter, [a_degenerate, b_degenerate]));
    if a_degenerate || b_degenerate {
        let (a, b) = (a_degenerate, b_degenerate);
        return stop(v, SegmentsOutcome::DegenerateSegment { a, b });
    }

    // Cramer's matrices, and |M|: zero when the lines are parallel.
    let mi = v
        .replaced
        .insert([with_column(m, 0, y), with_column(m, 1, y)]);
    let det_m = &*v.det.insert(det2(m));
    if !det_m.is_finite() {
        return stop(v, overflow::<R>());
    }
    let scale_of_m = norm_f64(&d_a) * norm_f64(&b1_minus_b2);
    let parallel = negligible::<R>(det_m.to_f64().abs(), scale_of_m, det_m.is_zero());
    v.parallel = Some(parallel);
    if parallel {
        return parallel_case(v, p, &d_a);
    }
    let [det_m1, det_m2] = v.dets.insert(mi.each_ref().map(det2));
    if !det_m1.is_finite() || !det_m2.is_finite() {
        return stop(v, overflow::<R>());
    }

    // t and s by Cramer's rule; on the segments when both are in [0, 1].
    let quotient = |det: &R| {
        det.checked_div(det_m)
            .expect("|M| was checked to be nonzero")
    };
    let (t, s) = (quotient(det_m1), quotient(det_m2));
    let in_unit = |x: &R| x >= &R::zero() && x <= &R::one();
    let (t_inside, s_inside) = (in_unit(&t), in_unit(&s));
    v.inside = Some([t_inside, s_inside]);
    let at_end = |x: &R| x.is_zero() || (x.clone() - R::one()).is_zero();
    let outcome = match (t_inside, s_inside) {
        (true, true) if at_end(&t) || at_end(&s) => SegmentsOutcome::Touching,
        (true, true) => SegmentsOutcome::Crossing,
        _ => SegmentsOutcome::LinesCrossOutside {
            t_outside: !t_inside,
            s_outside: !s_inside,
        },
    };
    v.solution = SegmentsSolution {
        point: Some(add(&p.a1, &scale(&t, &d_a))),
        t: Some(t),
        s: Some(s),
        ..SegmentsSolution::new(outcome)
    };
    v
}

impl<R> Values<R> {
    fn stopped_at(outcome: SegmentsOutcome) -> Values<R> {
        Values {
            solution: SegmentsSolution::new(outcome),
            system: None,
            lengths: None,
            replaced: None,
            det: None,
            parallel: None,
            collinear: None,
            dets: None,
            inside: None,
        }
    }
}

fn overflow<R: Real>() -> SegmentsOutcome {
    SegmentsOutcome::InvalidInput(InvalidInput {
        field: "input".into(),
        problem: format!(
            "the determinants overflow {}: the coordinates are too large for this precision",
            R::PRECISION.name()
        ),
    })
}

/// Parallel lines: one line (collinear) or two. For one line, B1 and B2 are placed on A's parameter t.
#[allow(
    clippy::expect_used,
    reason = "the squared length was checked to be nonzero just above"
)]
fn parallel_case<R: Real>(mut v: Values<R>, p: &SegmentPair<R>, d_a: &V2<R>) -> Values<R> {
    let b1_minus_a1 = sub(&p.b1, &p.a1);
    let offset = cross2(d_a, &b1_minus_a1);
    let collinear = negligible::<R>(
        offset.to_f64().abs(),
        norm_f64(d_a) * norm_f64(&b1_minus_a1),
        offset.is_zero(),
    );
    v.collinear = Some((offset, collinear));
    if !collinear {
        v.solution.outcome = SegmentsOutcome::Parallel;
        return v;
    }
    // Project B1 and B2 onto line A: t = (P − A1)·(A2−A1) / |A2−A1|².
    let length_squared = dot(d_a, d_a);
    // |A2−A1|² can underflow to 0 for a segment of length ~1e-30 in f32: say so rather than divide.
    if length_squared.is_zero() {
        v.solution.outcome = SegmentsOutcome::InvalidInput(InvalidInput {
            field: "A1, A2".into(),
            problem: format!(
                "segment A is too short for {}: its squared length underflows to 0",
                R::PRECISION.name()
            ),
        });
        return v;
    }
    let t_of = |v: &V2<R>| {
        dot(v, d_a)
            .checked_div(&length_squared)
            .expect("the squared length was checked to be nonzero")
    };
    let (t_b1, t_b2) = (t_of(&b1_minus_a1), t_of(&sub(&p.b2, &p.a1)));
    let (low, high) = if t_b1 <= t_b2 {
        (t_b1.clone(), t_b2.clone())
    } else {
        (t_b2.clone(), t_b1.clone())
    };
    let from = if low > R::zero() { low } else { R::zero() };
    let to = if high < R::one() { high } else { R::one() };
    let overlaps = from <= to;
    let outcome = if overlaps {
        SegmentsOutcome::CollinearOverlap
    } else {
        SegmentsOutcome::CollinearDisjoint
    };
    v.solution = SegmentsSolution {
        t_of_b: Some([t_b1, t_b2]),
        overlap: overlaps.then_some([from, to]),
        ..SegmentsSolution::new(outcome)
    };
    v
}

/// Records what [`values`] computed, step by step, and the verdict.
fn record<R: Real>(v: &Values<R>, steps: &mut impl StepSink) {
    if !steps.is_recording() {
        return;
    }
    record_stages(v, steps);
    let solution = &v.solution;
    let explanation = "What the numbers say about the two segments.";
    record_verdict(steps, explanation, solution.outcome.status(), || {
        verdict_message(solution)
    });
    if let Some(point) = &solution.point {
        steps.push(|| {
            Step::new(
                "point",
                "Where the lines cross: A(t) = B(s)",
                "Substituting t into A(t) gives the same point as s in B(s).",
                Payload::Vector(Vector::of("P", "P", point)),
            )
        });
    }
}

/// The steps before the verdict, as far as the solve went.
fn record_stages<R: Real>(v: &Values<R>, steps: &mut impl StepSink) {
    let Some((m, y)) = &v.system else { return };
    let matrix = || Matrix::of2("M", "M", m, LABELS);
    record_system(steps, &SYSTEM, matrix, || Vector::of("Y", "Y", y));
    let Some((shorter, [a_degenerate, b_degenerate])) = &v.lengths else {
        return;
    };
    steps.push(|| length_check(shorter, !(*a_degenerate || *b_degenerate)));
    let (Some(mi), Some(det_m)) = (&v.replaced, &v.det) else {
        return;
    };
    record_replaced(steps, 2, |i| {
        Matrix::of2(
            &format!("M{}", i + 1),
            &format!("M_{}", i + 1),
            &mi[i],
            LABELS,
        )
    });
    record_det(steps, m, det_m, ["M", "M"]);
    let Some(parallel) = v.parallel else { return };
    steps.push(|| det_check(det_m, parallel, parallel_explanation::<R>(), PARALLEL));
    if let Some((offset, collinear)) = &v.collinear {
        steps.push(|| collinear_check(offset, *collinear));
        if let Some([t_b1, t_b2]) = &v.solution.t_of_b {
            record_ends_on_a(steps, t_b1, t_b2);
        }
        return;
    }
    let Some([det_m1, det_m2]) = &v.dets else {
        return;
    };
    record_det(steps, &mi[0], det_m1, ["M1", "M_1"]);
    record_det(steps, &mi[1], det_m2, ["M2", "M_2"]);
    let (Some(t), Some(s), Some([t_inside, s_inside])) = (&v.solution.t, &v.solution.s, v.inside)
    else {
        return;
    };
    let quotients = [
        (["t", "|M1|", "|M_1|"], det_m1, t, T_NOTE),
        (["s", "|M2|", "|M_2|"], det_m2, s, S_NOTE),
    ];
    for ([symbol, numerator, numerator_latex], det_mi, value, note) in quotients {
        let names = [symbol, symbol, symbol];
        let values = [det_mi, det_m, value];
        record_quotient(steps, names, [numerator, numerator_latex], values, note);
    }
    steps.push(|| unit_interval_check(["check_t", "t", "A"], t, t_inside));
    steps.push(|| unit_interval_check(["check_s", "s", "B"], s, s_inside));
}

/// The system's words.
const SYSTEM: SystemWords = SystemWords {
    title: "The system M X = Y",
    setup: "Set A1 + t(A2−A1) = B1 + s(B2−B1) and move the unknowns t, s to the left.",
    unknowns: &[["t", "t"], ["s", "s"]],
    apart: Some([
        [
            "M = [A2−A1 | B1−B2]",
            "The columns are the direction of A and the reversed direction of B.",
        ],
        ["Y = B1 − A1", "The right-hand side: from A1 to B1."],
    ]),
};
const T_NOTE: &str = "How far along A from A1, in units of A2−A1.";
const S_NOTE: &str = "How far along B from B1, in units of B2−B1.";
const PARALLEL: &str = "the lines are parallel: no single crossing point";

/// The shorter of two vectors (by their float lengths; by their exact squares where the floats
/// cannot tell).
fn shorter<'a, R: Real>(a: &'a V2<R>, b: &'a V2<R>) -> &'a V2<R> {
    match norm_f64(a).partial_cmp(&norm_f64(b)) {
        Some(std::cmp::Ordering::Less) => a,
        Some(std::cmp::Ordering::Greater) => b,
        _ if dot(a, a) <= dot(b, b) => a,
        _ => b,
    }
}

fn length_check<R: Real>(shorter: &V2<R>, passed: bool) -> Step {
    check(
        [
            "check_lengths",
            "Both segments have a length",
            "A segment whose endpoints coincide is a single point, with no direction to follow.",
        ],
        [
            "min(|A2−A1|, |B2−B1|) > 0",
            "\\min(|A_2-A_1|, |B_2-B_1|) > 0",
        ],
        length(shorter, 1.0),
        passed,
        "a segment has zero length",
    )
}

fn collinear_check<R: Real>(offset: &R, collinear: bool) -> Step {
    check(
        [
            "check_collinear",
            "Are the parallel lines one line?",
            "B1 lies on line A exactly when (A2−A1) × (B1−A1) = 0.",
        ],
        ["(A2−A1) × (B1−A1) = 0", "(A_2-A_1) \\times (B_1-A_1) = 0"],
        Number::of(offset),
        collinear,
        "two distinct parallel lines: they never meet",
    )
}

/// Records t(B1) and t(B2), where B's ends sit on line A.
fn record_ends_on_a<R: Real>(steps: &mut impl StepSink, t_b1: &R, t_b2: &R) {
    for (id, point, point_latex, value) in
        [("t_b1", "B1", "B_1", t_b1), ("t_b2", "B2", "B_2", t_b2)]
    {
        steps.push(|| {
            Step::new(
                id,
                format!("t({point}) on line A"),
                "Where an endpoint of B sits on A's parameter.",
                Payload::Scalar(Scalar {
                    symbol: format!("t({point})"),
                    latex: format!("t({point_latex})"),
                    formula: Some(Formula::Expression {
                        text: format!("({point}−A1)·(A2−A1) / |A2−A1|²"),
                        latex: format!(
                            "\\frac{{({point_latex}-A_1)\\cdot(A_2-A_1)}}{{|A_2-A_1|^2}}"
                        ),
                    }),
                    value: Number::of(value),
                    closed_form: None,
                }),
            )
        });
    }
}

fn record_det<R: Real>(steps: &mut impl StepSink, m: &M2<R>, value: &R, [name, latex]: [&str; 2]) {
    steps.push(|| {
        Step::new(
            format!("det_{name}"),
            format!("|{name}|"),
            "A 2x2 determinant: the product of the diagonal minus the product of the anti-diagonal.",
            Payload::Determinant(Determinant::of2(name, latex, m, value)),
        )
    });
}

/// The check `0 ≤ x ≤ 1`; `names` is the step's id, the symbol and the segment.
fn unit_interval_check<R: Real>([id, symbol, segment]: [&str; 3], x: &R, inside: bool) -> Step {
    let (side, start_or_end) = if x < &R::zero() {
        ("before", "start")
    } else {
        ("past", "end")
    };
    let title = format!("Check 0 ≤ {symbol} ≤ 1");
    let note = "The crossing is on the segment itself only for parameters in [0, 1].";
    check(
        [id, &title, note],
        [
            &format!("0 ≤ {symbol} ≤ 1"),
            &format!("0 \\le {symbol} \\le 1"),
        ],
        Number::of(x),
        inside,
        format!("the crossing is on line {segment} {side} the segment's {start_or_end}"),
    )
}

fn parallel_explanation<R: Real>() -> &'static str {
    if R::TOLERANCE == 0.0 {
        "Exact arithmetic: the lines are parallel only if |M| is exactly zero."
    } else {
        "|M| counts as zero when |M| ≤ 16ε·|A2−A1|·|B2−B1|, i.e. the lines are within 16ε radians of parallel."
    }
}

fn verdict_message<R: Real>(s: &SegmentsSolution<R>) -> String {
    let shown = |x: &Option<R>| {
        x.as_ref()
            .map(|x| Number::of(x).shown())
            .unwrap_or_default()
    };
    let (t, sv) = (shown(&s.t), shown(&s.s));
    match &s.outcome {
        SegmentsOutcome::Crossing => format!("the segments cross at t = {t}, s = {sv}"),
        SegmentsOutcome::Touching => {
            format!("the segments touch at an endpoint: t = {t}, s = {sv}")
        }
        SegmentsOutcome::LinesCrossOutside {
            t_outside,
            s_outside,
        } => {
            let which = match (t_outside, s_outside) {
                (true, true) => format!("both t = {t} and s = {sv} are outside [0, 1]"),
                (true, false) => format!("t = {t} is outside [0, 1] (s = {sv} is inside)"),
                _ => format!("s = {sv} is outside [0, 1] (t = {t} is inside)"),
            };
            format!("the segments do not meet: their lines cross, but {which}")
        }
        SegmentsOutcome::Parallel => {
            "the lines are parallel and distinct: the segments never meet".into()
        }
        SegmentsOutcome::CollinearOverlap => {
            let [from, to] = s
                .overlap
                .as_ref()
                .map(|[a, b]| [Number::of(a).shown(), Number::of(b).shown()])
                .unwrap_or_default();
            if from == to {
                format!("the segments lie on one line and share a single point, t = {from}")
            } else {
                format!("the segments lie on one line and overlap for t in [{from}, {to}]")
            }
        }
        SegmentsOutcome::CollinearDisjoint => {
            "the segments lie on one line but do not overlap".into()
        }
        SegmentsOutcome::DegenerateSegment { a, b } => match (a, b) {
            (true, true) => "both segments have zero length (each is a single point)".into(),
            (true, false) => "segment A has zero length (A1 = A2): it is a single point".into(),
            _ => "segment B has zero length (B1 = B2): it is a single point".into(),
        },
        SegmentsOutcome::InvalidInput(bad) => format!("invalid input: {bad}"),
    }
}

/// Where the t and s handles are: A(t), B(s) and the distance between them.
#[derive(Clone, Debug, PartialEq)]
pub struct Exploration<R> {
    /// A(t) = A1 + t(A2−A1).
    pub a_at_t: V2<R>,
    /// B(s) = B1 + s(B2−B1).
    pub b_at_s: V2<R>,
    /// |A(t) − B(s)|: zero exactly at the crossing.
    pub gap: f64,
}

/// Evaluates both parametric forms.
pub fn explore<R: Real>(p: &SegmentPair<R>, t: &R, s: &R) -> Exploration<R> {
    let a_at_t = point_on(&p.a1, &p.a2, t);
    let b_at_s = point_on(&p.b1, &p.b2, s);
    let gap = norm_f64(&sub(&a_at_t, &b_at_s));
    Exploration {
        a_at_t,
        b_at_s,
        gap,
    }
}

/// P1 + u(P2 − P1).
pub fn point_on<R: Real>(p1: &V2<R>, p2: &V2<R>, u: &R) -> V2<R> {
    add(p1, &scale(u, &sub(p2, p1)))
}

/// The parameter of the point of the line P1 + u(P2 − P1) nearest to q (for dragging a handle along
/// its line); 0 for a zero-length segment.
pub fn nearest_parameter(p1: &V2<f64>, p2: &V2<f64>, q: &V2<f64>) -> f64 {
    let direction = sub(p2, p1);
    let length_squared = dot(&direction, &direction);
    if length_squared == 0.0 || !length_squared.is_finite() {
        return 0.0;
    }
    dot(&sub(q, p1), &direction) / length_squared
}
