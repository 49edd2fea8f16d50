//! Ray–parallelogram intersection (seed 001): p(α, β) = c + α e1 + β e2 with (α, β) in [0, 1]², and the
//! ray r(t) = o + t d with t ≥ 0.
//!
//! Setting them equal, o + t d = c + α e1 + β e2, and moving the unknowns left gives
//! α e1 + β e2 − t d = o − c, i.e. M (α, β, t)ᵀ = o − c with M = [e1 | e2 | −d]. When M is invertible,
//! (α, β, t)ᵀ = M⁻¹ (o − c), and M⁻¹ = adj(M) / |M|.
//!
//! Seed 001 prints the right-hand side as c − o: a sign slip (with c − o every α, β and t comes out
//! negated). The tests pin the corrected form with a worked example.

pub mod lean;

use glam::DVec3;

use super::steps::{SystemWords, check, det_check, length, record_system, record_verdict};
use super::{
    InvalidInput, Lecture, ParallelogramLecture, Reading, check_finite, check_size, negligible,
    read_vec,
};
use crate::math::linalg::{
    CofactorTerm, M3, V3, add, adjugate3, all_finite, cofactor_terms3, cross, from_columns,
    is_zero_vector, mul_vec, neg, norm_f64, scale, sub, sum_terms,
};
use crate::math::real::Real;
use crate::trace::{
    Column, Determinant, Formula, Matrix, Number, Payload, Scalar, Status, Step, StepSink, Vector,
};

/// A ray and a parallelogram, in seed 001's names.
#[derive(Clone, Debug, PartialEq)]
pub struct RayParallelogram<R> {
    /// The corner c.
    pub corner: V3<R>,
    /// The first edge vector e1.
    pub e1: V3<R>,
    /// The second edge vector e2.
    pub e2: V3<R>,
    /// The ray's origin o.
    pub origin: V3<R>,
    /// The ray's direction d.
    pub dir: V3<R>,
}

impl<R> RayParallelogram<R> {
    /// The problem from its five vectors in the slide's order: c, e1, e2, o, d.
    pub fn new([corner, e1, e2, origin, dir]: [V3<R>; 5]) -> RayParallelogram<R> {
        RayParallelogram {
            corner,
            e1,
            e2,
            origin,
            dir,
        }
    }
}

impl RayParallelogram<f64> {
    /// The problem in f64, which holds every input as it is.
    pub fn from_floats(vectors: [DVec3; 5]) -> RayParallelogram<f64> {
        RayParallelogram::new(vectors.map(|v| v.to_array()))
    }
}

impl<R: Real> RayParallelogram<R> {
    /// Converts float inputs as [`Reading`] says.
    pub fn read(
        reading: Reading,
        [corner, e1, e2, origin, dir]: [DVec3; 5],
    ) -> Result<RayParallelogram<R>, InvalidInput> {
        Ok(RayParallelogram {
            corner: read_vec(reading, "c", corner.to_array())?,
            e1: read_vec(reading, "e1", e1.to_array())?,
            e2: read_vec(reading, "e2", e2.to_array())?,
            origin: read_vec(reading, "o", origin.to_array())?,
            dir: read_vec(reading, "d", dir.to_array())?,
        })
    }
}

/// A bound on α or β that a point outside the parallelogram breaks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// α < 0: before the edge through c along e2.
    AlphaBelow,
    /// α > 1: past the opposite edge.
    AlphaAbove,
    /// β < 0: before the edge through c along e1.
    BetaBelow,
    /// β > 1: past the opposite edge.
    BetaAbove,
}

impl Side {
    /// The broken bound, e.g. `α ≥ 0`.
    pub fn inequality(self) -> &'static str {
        match self {
            Side::AlphaBelow => "α ≥ 0",
            Side::AlphaAbove => "α ≤ 1",
            Side::BetaBelow => "β ≥ 0",
            Side::BetaAbove => "β ≤ 1",
        }
    }
}

/// Hit, or a miss that says why.
#[derive(Clone, Debug, PartialEq)]
pub enum ParallelogramOutcome {
    /// α, β in [0, 1] and t ≥ 0.
    Hit,
    /// The ray meets the plane outside the parallelogram.
    Outside {
        /// Every broken bound.
        sides: Vec<Side>,
    },
    /// Inside, but t < 0: behind the ray's origin.
    Behind,
    /// |M| = 0: the ray is parallel to the parallelogram's plane.
    Parallel,
    /// e1 and e2 are parallel (or zero): no area.
    Degenerate,
    /// d = 0: there is no ray.
    ZeroDirection,
    /// An input is NaN or infinite in this precision.
    InvalidInput(InvalidInput),
}

impl ParallelogramOutcome {
    /// The stable status word, shared with triangles (`degenerate-triangle` for a flat parallelogram).
    pub fn status(&self) -> Status {
        match self {
            ParallelogramOutcome::Hit => Status::Hit,
            ParallelogramOutcome::Outside { .. } => Status::MissOutside,
            ParallelogramOutcome::Behind => Status::MissBehind,
            ParallelogramOutcome::Parallel => Status::Parallel,
            ParallelogramOutcome::Degenerate => Status::DegenerateTriangle,
            ParallelogramOutcome::ZeroDirection | ParallelogramOutcome::InvalidInput(_) => {
                Status::InvalidInput
            }
        }
    }

    /// True for a hit.
    pub fn is_hit(&self) -> bool {
        matches!(self, ParallelogramOutcome::Hit)
    }
}

/// The answer of [`solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct ParallelogramSolution<R> {
    /// Hit, or why not.
    pub outcome: ParallelogramOutcome,
    /// (α, β, t) = M⁻¹ (o − c), whenever M is invertible.
    pub alpha_beta_t: Option<V3<R>>,
    /// o + t d, whenever M is invertible.
    pub point: Option<V3<R>>,
}

impl<R> ParallelogramSolution<R> {
    /// The verdict's sentence for people (the same as in the trace, which need not be recorded).
    pub fn message(&self) -> String {
        verdict_message(&self.outcome)
    }
}

const LABELS: [Column; 3] = [Column::E1, Column::E2, Column::MinusD];

impl Lecture for ParallelogramLecture {
    const NAME: &'static str = "parallelogram";
    type Floats = [DVec3; 5];
    type Problem<R: Real> = RayParallelogram<R>;
    type Answer<R: Real> = ParallelogramSolution<R>;

    fn read<R: Real>(
        vectors: [DVec3; 5],
        reading: Reading,
    ) -> Result<RayParallelogram<R>, InvalidInput> {
        RayParallelogram::read(reading, vectors)
    }

    fn solve<R: Real>(
        problem: &RayParallelogram<R>,
        steps: &mut impl StepSink,
    ) -> ParallelogramSolution<R> {
        solve(problem, steps)
    }

    fn refuse<R: Real>(bad: InvalidInput, steps: &mut impl StepSink) -> ParallelogramSolution<R> {
        let outcome = ParallelogramOutcome::InvalidInput(bad);
        super::record_refusal(steps, outcome.status(), || verdict_message(&outcome));
        ParallelogramSolution {
            outcome,
            alpha_beta_t: None,
            point: None,
        }
    }
}

/// Solves by the inverse matrix, recording every step into `steps` (`()` records nothing: the
/// arithmetic is the same either way).
pub fn solve<R: Real>(
    p: &RayParallelogram<R>,
    steps: &mut impl StepSink,
) -> ParallelogramSolution<R> {
    let values = values(p);
    record(&values, steps);
    values.solution
}

/// Every value the lecture's solve computes, in the slide's order. A solve stops at the first check
/// that fails, so a stage after it is `None`.
struct Values<R> {
    /// The answer.
    solution: ParallelogramSolution<R>,
    /// M = [e1 | e2 | −d] and o − c.
    system: Option<(M3<R>, V3<R>)>,
    /// |e1 × e2| and whether it counts as zero.
    area: Option<(V3<R>, bool)>,
    /// |M| expanded along its first row.
    det: Option<([CofactorTerm<R>; 3], R)>,
    /// Whether |M| counts as zero (unset when |M| overflowed).
    parallel: Option<bool>,
    /// adj(M) and M⁻¹ = adj(M) / |M|.
    inverse: Option<(M3<R>, M3<R>)>,
    /// The sides (α, β) breaks, and whether t ≥ 0.
    checks: Option<(Vec<Side>, bool)>,
}

/// The arithmetic of the slide: M (α, β, t)ᵀ = o − c, the area and |M| checks, the inverse by the
/// adjugate, then the three interval checks. Records nothing.
#[allow(
    clippy::expect_used,
    reason = "a division by |M| runs only after |M| was checked to be nonzero"
)]
fn values<R: Real>(p: &RayParallelogram<R>) -> Values<R> {
    let mut v = Values::stopped_at(ParallelogramOutcome::Hit);
    let stop = |mut v: Values<R>, outcome| {
        v.solution.outcome = outcome;
        v
    };
    let inputs = [
        ("c", &p.corner),
        ("e1", &p.e1),
        ("e2", &p.e2),
        ("o", &p.origin),
        ("d", &p.dir),
    ];
    if let Err(bad) = check_finite(&inputs).and(check_size(&inputs, &[])) {
        return stop(v, ParallelogramOutcome::InvalidInput(bad));
    }
    if is_zero_vector(&p.dir) {
        return stop(v, ParallelogramOutcome::ZeroDirection);
    }

    // The system M (α, β, t)ᵀ = o − c.
    let m = from_columns([&p.e1, &p.e2, &neg(&p.dir)]);
    let (m, y) = v.system.insert((m, sub(&p.origin, &p.corner)));

    // A flat parallelogram: e1 × e2 = 0.
    let normal = cross(&p.e1, &p.e2);
    if !all_finite(&normal) {
        return stop(v, overflow::<R>());
    }
    let area_scale = norm_f64(&p.e1) * norm_f64(&p.e2);
    let degenerate = negligible::<R>(norm_f64(&normal), area_scale, is_zero_vector(&normal));
    v.area = Some((normal.clone(), degenerate));
    if degenerate {
        return stop(v, ParallelogramOutcome::Degenerate);
    }

    // |M|: zero when the ray is parallel to the plane.
    let terms = cofactor_terms3(m);
    let value = sum_terms(&terms);
    let det = &v.det.insert((terms, value)).1;
    if !det.is_finite() {
        return stop(v, overflow::<R>());
    }
    let parallel = negligible::<R>(
        det.to_f64().abs(),
        norm_f64(&normal) * norm_f64(&p.dir),
        det.is_zero(),
    );
    v.parallel = Some(parallel);
    if parallel {
        return stop(v, ParallelogramOutcome::Parallel);
    }

    // (α, β, t)ᵀ = M⁻¹ (o − c), with M⁻¹ = adj(M) / |M|.
    let adjugate = adjugate3(m);
    let inverse = adjugate
        .clone()
        .map(|row| row.map(|x| x.checked_div(det).expect("|M| was checked to be nonzero")));
    let x = mul_vec(&inverse, y);
    v.inverse = Some((adjugate, inverse));
    if x.iter().any(|v| !v.is_finite()) {
        return stop(v, overflow::<R>());
    }

    // On the parallelogram when 0 ≤ α ≤ 1 and 0 ≤ β ≤ 1; on the ray when t ≥ 0.
    let sides: Vec<Side> = [0, 1]
        .into_iter()
        .filter_map(|i| side_broken(i, &x[i]))
        .collect();
    let in_front = x[2] >= R::zero();
    let outcome = if !sides.is_empty() {
        ParallelogramOutcome::Outside {
            sides: sides.clone(),
        }
    } else if !in_front {
        ParallelogramOutcome::Behind
    } else {
        ParallelogramOutcome::Hit
    };
    v.checks = Some((sides, in_front));
    v.solution = ParallelogramSolution {
        outcome,
        point: Some(add(&p.origin, &scale(&x[2], &p.dir))),
        alpha_beta_t: Some(x),
    };
    v
}

impl<R> Values<R> {
    fn stopped_at(outcome: ParallelogramOutcome) -> Values<R> {
        Values {
            solution: ParallelogramSolution {
                outcome,
                alpha_beta_t: None,
                point: None,
            },
            system: None,
            area: None,
            det: None,
            parallel: None,
            inverse: None,
            checks: None,
        }
    }
}

/// The side of [0, 1] that α (`i` = 0) or β (`i` = 1) breaks, if any.
fn side_broken<R: Real>(i: usize, value: &R) -> Option<Side> {
    let [below, above] = [
        [Side::AlphaBelow, Side::AlphaAbove],
        [Side::BetaBelow, Side::BetaAbove],
    ][i];
    if value < &R::zero() {
        Some(below)
    } else if value > &R::one() {
        Some(above)
    } else {
        None
    }
}

fn overflow<R: Real>() -> ParallelogramOutcome {
    ParallelogramOutcome::InvalidInput(InvalidInput {
        field: "input".into(),
        problem: format!(
            "the computation overflows {}: the coordinates are too large for this precision",
            R::PRECISION.name()
        ),
    })
}

/// Records what [`values`] computed, step by step, and the verdict.
fn record<R: Real>(v: &Values<R>, steps: &mut impl StepSink) {
    if !steps.is_recording() {
        return;
    }
    record_stages(v, steps);
    let solution = &v.solution;
    record_verdict(
        steps,
        "What the checks decide.",
        solution.outcome.status(),
        || verdict_message(&solution.outcome),
    );
    if let Some(point) = &solution.point {
        let title = if solution.outcome.is_hit() {
            "Hit point o + t d"
        } else {
            "Where the ray's line meets the plane, o + t d"
        };
        steps.push(|| {
            Step::new("point", title, "Knowing t gives the point.", {
                Payload::Vector(Vector::of("P", "P", point))
            })
        });
    }
}

/// The steps before the verdict, as far as the solve went.
fn record_stages<R: Real>(v: &Values<R>, steps: &mut impl StepSink) {
    let Some((m, y)) = &v.system else { return };
    let matrix = || Matrix::of3("M", "M", m, LABELS);
    record_system(steps, &SYSTEM, matrix, || Vector::of("o − c", "o - c", y));
    let Some((normal, degenerate)) = &v.area else {
        return;
    };
    steps.push(|| area_check(normal, *degenerate));
    let Some((terms, det)) = &v.det else { return };
    steps.push(|| {
        Step::new(
            "det_M",
            "|M|",
            "The determinant of M, expanded along the first row.",
            Payload::Determinant(Determinant::of3("M", "M", terms, det)),
        )
    });
    let Some(parallel) = v.parallel else { return };
    steps.push(|| det_check(det, parallel, PARALLEL_NOTE, PARALLEL));
    let Some((adjugate, inverse)) = &v.inverse else {
        return;
    };
    record_inverse(steps, adjugate, inverse);
    let (Some(x), Some((_, in_front))) = (&v.solution.alpha_beta_t, &v.checks) else {
        return;
    };
    steps.push(|| {
        Step::new(
            "product",
            "(α, β, t)ᵀ = M⁻¹ (o − c)",
            "Multiply the inverse by the right-hand side.",
            Payload::Vector(Vector::of("(α, β, t)", "(\\alpha, \\beta, t)", x)),
        )
    });
    let unknowns = [
        ("alpha", "α", "\\alpha"),
        ("beta", "β", "\\beta"),
        ("t", "t", "t"),
    ];
    for (i, (id, symbol, latex)) in unknowns.into_iter().enumerate() {
        steps.push(|| {
            Step::new(id, symbol, "Read off the product.", {
                Payload::Scalar(Scalar {
                    symbol: symbol.into(),
                    latex: latex.into(),
                    formula: Some(Formula::Expression {
                        text: format!("row {} of M⁻¹ (o − c)", i + 1),
                        latex: format!("\\left(M^{{-1}}(o-c)\\right)_{}", i + 1),
                    }),
                    value: Number::of(&x[i]),
                    closed_form: None,
                })
            })
        });
    }
    record_checks(steps, x, *in_front);
}

/// The system's words (M and o − c are shown in the system step alone).
const SYSTEM: SystemWords = SystemWords {
    title: "The system M (α, β, t)ᵀ = o − c",
    setup: "Set o + t d = c + α e1 + β e2 and move the unknowns left: α e1 + β e2 − t d = o − c (seed 001 prints c − o, a sign slip).",
    unknowns: &[["α", "\\alpha"], ["β", "\\beta"], ["t", "t"]],
    apart: None,
};
const PARALLEL_NOTE: &str = "M is invertible only if d is not in the plane of e1 and e2 (for floats: |M| > 16ε·|e1×e2|·|d|).";
const PARALLEL: &str = "the ray is parallel to the parallelogram's plane";

fn area_check<R: Real>(normal: &V3<R>, degenerate: bool) -> Step {
    check(
        [
            "check_area",
            "The parallelogram has an area",
            "Its area is |e1 × e2|; seed 001 requires e1 and e2 not parallel and not zero.",
        ],
        ["|e1 × e2| > 0", "|e_1 \\times e_2| > 0"],
        length(normal, 1.0),
        !degenerate,
        "e1 and e2 are parallel or zero: the parallelogram is flat",
    )
}

fn record_inverse<R: Real>(steps: &mut impl StepSink, adjugate: &M3<R>, inverse: &M3<R>) {
    steps.push(|| {
        Step::new(
            "adj_M",
            "adj(M), the adjugate",
            "The transposed matrix of cofactors: M · adj(M) = |M| I.",
            Payload::Matrix(Matrix::of3(
                "adj(M)",
                "\\operatorname{adj}(M)",
                adjugate,
                [Column::Unnamed; 3],
            )),
        )
    });
    steps.push(|| {
        Step::new(
            "inverse",
            "M⁻¹ = adj(M) / |M|",
            "Each entry of the adjugate divided by the determinant.",
            Payload::Matrix(Matrix::of3("M⁻¹", "M^{-1}", inverse, [Column::Unnamed; 3])),
        )
    });
}

/// Records the checks 0 ≤ α ≤ 1, 0 ≤ β ≤ 1 and t ≥ 0.
fn record_checks<R: Real>(steps: &mut impl StepSink, x: &V3<R>, in_front: bool) {
    let note = "The point is on the parallelogram only if α and β are both in [0, 1].";
    for (i, [id, symbol, latex]) in [
        ["check_alpha", "α", "\\alpha"],
        ["check_beta", "β", "\\beta"],
    ]
    .into_iter()
    .enumerate()
    {
        let broken = side_broken(i, &x[i]);
        steps.push(|| {
            check(
                [id, &format!("Check 0 ≤ {symbol} ≤ 1"), note],
                [
                    &format!("0 ≤ {symbol} ≤ 1"),
                    &format!("0 \\le {latex} \\le 1"),
                ],
                Number::of(&x[i]),
                broken.is_none(),
                format!(
                    "the point breaks {}",
                    broken.map(Side::inequality).unwrap_or_default()
                ),
            )
        });
    }
    steps.push(|| {
        check(
            [
                "check_t",
                "Check t ≥ 0",
                "Seed 001 takes the ray for t in [0, ∞): t = 0 counts.",
            ],
            ["t ≥ 0", "t \\ge 0"],
            Number::of(&x[2]),
            in_front,
            "the plane is behind the ray's origin",
        )
    });
}

fn verdict_message(outcome: &ParallelogramOutcome) -> String {
    match outcome {
        ParallelogramOutcome::Hit => "the ray hits the parallelogram".into(),
        ParallelogramOutcome::Outside { sides } => {
            let broken: Vec<&str> = sides.iter().map(|s| s.inequality()).collect();
            format!(
                "the ray meets the plane outside the parallelogram: it breaks {}",
                broken.join(" and ")
            )
        }
        ParallelogramOutcome::Behind => {
            "the point is on the parallelogram but behind the ray's origin (t < 0)".into()
        }
        ParallelogramOutcome::Parallel => {
            "the ray is parallel to the parallelogram's plane (|M| = 0)".into()
        }
        ParallelogramOutcome::Degenerate => {
            "e1 and e2 are parallel or zero: the parallelogram has no area".into()
        }
        ParallelogramOutcome::ZeroDirection => "the direction d is the zero vector: no ray".into(),
        ParallelogramOutcome::InvalidInput(bad) => format!("invalid input: {bad}"),
    }
}

/// Where the sliders put things: p(α, β) on the plane, o + t d on the ray, and the gap.
#[derive(Clone, Debug, PartialEq)]
pub struct Exploration<R> {
    /// c + α e1 + β e2.
    pub plane_point: V3<R>,
    /// o + t d.
    pub ray_point: V3<R>,
    /// |p(α, β) − (o + t d)|.
    pub gap: f64,
    /// True if α and β are both in [0, 1].
    pub inside: bool,
}

/// The parametric form p(α, β) = c + α e1 + β e2: any point of the parallelogram's plane.
pub fn point_at<R: Real>(p: &RayParallelogram<R>, alpha: &R, beta: &R) -> V3<R> {
    let along = add(&scale(alpha, &p.e1), &scale(beta, &p.e2));
    add(&p.corner, &along)
}

/// Evaluates both parametric forms.
pub fn explore<R: Real>(p: &RayParallelogram<R>, alpha: &R, beta: &R, t: &R) -> Exploration<R> {
    let plane_point = point_at(p, alpha, beta);
    let ray_point = add(&p.origin, &scale(t, &p.dir));
    let gap = norm_f64(&sub(&plane_point, &ray_point));
    let unit = |x: &R| x >= &R::zero() && x <= &R::one();
    Exploration {
        plane_point,
        ray_point,
        gap,
        inside: unit(alpha) && unit(beta),
    }
}
