//! Ray–triangle intersection by Cramer's rule, in the lecture's form (seed 000, seed 004).
//!
//! Setting the ray equal to the triangle's parametric form, L + tD = A + β(B−A) + γ(C−A), and moving the
//! unknowns to the left gives M X = Y with M = [A−B | A−C | D], X = (β, γ, t) and Y = A − L. Cramer's
//! rule replaces column i of M by Y to get Mi, and X_i = |Mi| / |M|. The ray hits the triangle if and
//! only if β ≥ 0, γ ≥ 0, β + γ ≤ 1 and t > t_min (open at t_min: a ray starting on the triangle with
//! t_min = 0 does not hit it).

mod narration;

use glam::DVec3;

use std::array::from_ref;

use super::steps::{
    SystemWords, check, det_check, length, record_quotient, record_replaced, record_system,
    record_verdict,
};
use super::{
    InvalidInput, Lecture, Reading, TriangleLecture, check_finite, check_size, negligible, read,
    read_vec,
};
use crate::math::exact::{Exact, SignedRoot};
use crate::math::linalg::{
    CofactorTerm, M3, V3, add, all_finite, cofactor_terms3, cross, dot, from_columns,
    is_zero_vector, norm_f64, scale, sub, sum_terms, with_column,
};
use crate::math::real::Real;
use crate::trace::{
    ClosedForm, Column, Determinant, Formula, Matrix, Number, Payload, Scalar, Status, Step,
    StepSink, Vector,
};
use narration::{area_explanation, parallel_explanation, verdict_message, verdict_sentence};

/// A ray and a triangle, in the lecture's names.
#[derive(Clone, Debug, PartialEq)]
pub struct RayTriangle<R> {
    /// Vertex A (the key vertex of the parametric form).
    pub a: V3<R>,
    /// Vertex B.
    pub b: V3<R>,
    /// Vertex C.
    pub c: V3<R>,
    /// The ray's origin L.
    pub origin: V3<R>,
    /// The ray's direction D (not necessarily unit length).
    pub dir: V3<R>,
    /// Hits need t > t_min.
    pub t_min: R,
}

impl RayTriangle<f64> {
    /// The problem in f64, which holds every input as it is.
    pub fn from_floats([a, b, c, origin, dir]: [DVec3; 5], t_min: f64) -> RayTriangle<f64> {
        RayTriangle {
            a: a.to_array(),
            b: b.to_array(),
            c: c.to_array(),
            origin: origin.to_array(),
            dir: dir.to_array(),
            t_min,
        }
    }
}

impl<R: Real> RayTriangle<R> {
    /// Converts float inputs as [`Reading`] says.
    pub fn read(
        reading: Reading,
        [a, b, c, origin, dir]: [DVec3; 5],
        t_min: f64,
    ) -> Result<RayTriangle<R>, InvalidInput> {
        Ok(RayTriangle {
            a: read_vec(reading, "A", a.to_array())?,
            b: read_vec(reading, "B", b.to_array())?,
            c: read_vec(reading, "C", c.to_array())?,
            origin: read_vec(reading, "L", origin.to_array())?,
            dir: read_vec(reading, "D", dir.to_array())?,
            t_min: read(reading, "t_min", t_min)?,
        })
    }
}

/// The inequality a point outside the triangle fails, named by the edge it is beyond.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// β < 0: beyond edge CA (the side of the line AC away from B).
    Ca,
    /// γ < 0: beyond edge AB (the side of the line AB away from C).
    Ab,
    /// β + γ > 1: beyond edge BC (the side of the line BC away from A).
    Bc,
}

impl Edge {
    /// `CA`, `AB` or `BC`.
    pub fn name(self) -> &'static str {
        match self {
            Edge::Ca => "CA",
            Edge::Ab => "AB",
            Edge::Bc => "BC",
        }
    }

    /// The inequality that failed.
    pub fn inequality(self) -> &'static str {
        match self {
            Edge::Ca => "β ≥ 0",
            Edge::Ab => "γ ≥ 0",
            Edge::Bc => "β + γ ≤ 1",
        }
    }
}

/// Why a ray misses a triangle.
#[derive(Clone, Debug, PartialEq)]
pub enum TriangleMiss {
    /// The ray meets the plane outside the triangle, beyond these edges.
    Outside {
        /// Every failed inequality, as the edge it puts the point beyond.
        edges: Vec<Edge>,
    },
    /// The point is in the triangle but not in front of the origin: t ≤ t_min.
    Behind,
    /// |M| = 0 (or negligible): the ray is parallel to the triangle's plane.
    Parallel {
        /// True if the ray lies in the plane itself.
        in_plane: bool,
    },
    /// A, B and C are collinear (or coincide): the triangle has no area.
    DegenerateTriangle,
    /// D = 0: there is no ray.
    ZeroDirection,
    /// An input is NaN or infinite in this precision.
    InvalidInput(InvalidInput),
}

/// Hit, or a miss that says why.
#[derive(Clone, Debug, PartialEq)]
pub enum TriangleOutcome {
    /// β ≥ 0, γ ≥ 0, β + γ ≤ 1 and t > t_min.
    Hit,
    /// Not a hit.
    Miss(TriangleMiss),
}

impl TriangleOutcome {
    /// The stable kebab-case status word used in JSON.
    pub fn status(&self) -> Status {
        match self {
            TriangleOutcome::Hit => Status::Hit,
            TriangleOutcome::Miss(miss) => match miss {
                TriangleMiss::Outside { .. } => Status::MissOutside,
                TriangleMiss::Behind => Status::MissBehind,
                TriangleMiss::Parallel { .. } => Status::Parallel,
                TriangleMiss::DegenerateTriangle => Status::DegenerateTriangle,
                TriangleMiss::ZeroDirection | TriangleMiss::InvalidInput(_) => Status::InvalidInput,
            },
        }
    }

    /// True for a hit.
    pub fn is_hit(&self) -> bool {
        matches!(self, TriangleOutcome::Hit)
    }
}

/// The solution of M X = Y, when it exists.
#[derive(Clone, Debug, PartialEq)]
pub struct Barycentric<R> {
    /// β = |M1| / |M|.
    pub beta: R,
    /// γ = |M2| / |M|.
    pub gamma: R,
    /// t = |M3| / |M|, in units of |D|.
    pub t: R,
    /// α = 1 − β − γ.
    pub alpha: R,
    /// L + tD: the hit point, or where the ray's line meets the plane on a miss.
    pub point: V3<R>,
    /// The distance from L to the point, t·|D| (in f64: it needs a square root).
    pub distance: f64,
    /// The exact distance when exact: ±√(t²·(D·D)).
    pub distance_exact: Option<SignedRoot>,
}

/// The answer of [`solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleSolution<R> {
    /// Hit, or why not.
    pub outcome: TriangleOutcome,
    /// β, γ, t, α and the point, whenever |M| ≠ 0.
    pub solution: Option<Barycentric<R>>,
}

impl<R: Real> TriangleSolution<R> {
    /// The verdict's sentence for people (the same as in the trace, which need not be recorded).
    pub fn message(&self) -> String {
        verdict_message(&self.outcome, self.solution.as_ref())
    }
}

impl Lecture for TriangleLecture {
    const NAME: &'static str = "triangle";
    type Floats = ([DVec3; 5], f64);
    type Problem<R: Real> = RayTriangle<R>;
    type Answer<R: Real> = TriangleSolution<R>;

    fn read<R: Real>(
        (vectors, t_min): Self::Floats,
        reading: Reading,
    ) -> Result<RayTriangle<R>, InvalidInput> {
        RayTriangle::read(reading, vectors, t_min)
    }

    fn solve<R: Real>(problem: &RayTriangle<R>, steps: &mut impl StepSink) -> TriangleSolution<R> {
        solve(problem, steps)
    }

    fn refuse<R: Real>(bad: InvalidInput, steps: &mut impl StepSink) -> TriangleSolution<R> {
        let outcome = TriangleOutcome::Miss(TriangleMiss::InvalidInput(bad));
        super::record_refusal(steps, outcome.status(), || {
            verdict_message::<R>(&outcome, None)
        });
        TriangleSolution {
            outcome,
            solution: None,
        }
    }
}

/// Solves the lecture's system by Cramer's rule, recording every step into `steps` (`()` records
/// nothing: the arithmetic is the same either way).
pub fn solve<R: Real>(problem: &RayTriangle<R>, steps: &mut impl StepSink) -> TriangleSolution<R> {
    let values = values(problem);
    record(problem, &values, steps);
    TriangleSolution {
        outcome: values.outcome,
        solution: values.solution,
    }
}

/// Every value the lecture's solve computes, in the slide's order. A solve stops at the first check
/// that fails, so a stage after it is `None`.
struct Values<R> {
    /// Hit, or why not.
    outcome: TriangleOutcome,
    /// M = [A−B | A−C | D] and Y = A − L.
    system: Option<(M3<R>, V3<R>)>,
    /// (A−B)×(A−C), whose length is twice the area, and whether it counts as zero.
    area: Option<(V3<R>, bool)>,
    /// M1, M2, M3: M with column i replaced by Y.
    replaced: Option<[M3<R>; 3]>,
    /// |M| expanded along its first row.
    det: Option<Expansion<R>>,
    /// Whether |M| counts as zero (unset when |M| overflowed).
    parallel: Option<bool>,
    /// |M1|, |M2|, |M3|.
    dets: Option<[Expansion<R>; 3]>,
    /// β, γ, t, α and the point.
    solution: Option<Barycentric<R>>,
    /// The edges P(β, γ) is beyond, and whether t > t_min.
    checks: Option<(Vec<Edge>, bool)>,
}

/// A determinant's first-row expansion and its value.
struct Expansion<R> {
    terms: [CofactorTerm<R>; 3],
    value: R,
}

impl<R: Real> Expansion<R> {
    fn of(m: &M3<R>) -> Expansion<R> {
        let terms = cofactor_terms3(m);
        let value = sum_terms(&terms);
        Expansion { terms, value }
    }
}

/// The arithmetic of the slide: M X = Y, the area and |M| checks, Cramer's rule, then the four
/// inequalities. Records nothing.
#[allow(
    clippy::expect_used,
    reason = "a division by |M| runs only after |M| was checked to be nonzero"
)]
fn values<R: Real>(p: &RayTriangle<R>) -> Values<R> {
    let mut v = Values::stopped_at(TriangleOutcome::Hit);
    let stop = |mut v: Values<R>, miss| {
        v.outcome = TriangleOutcome::Miss(miss);
        v
    };
    let inputs = [
        ("A", &p.a),
        ("B", &p.b),
        ("C", &p.c),
        ("L", &p.origin),
        ("D", &p.dir),
    ];
    let t_min = [("t_min", from_ref(&p.t_min))];
    let checked = check_finite(&inputs)
        .and(check_finite(&t_min))
        .and(check_size(&inputs, &[&p.t_min]));
    if let Err(bad) = checked {
        return stop(v, TriangleMiss::InvalidInput(bad));
    }
    if is_zero_vector(&p.dir) {
        return stop(v, TriangleMiss::ZeroDirection);
    }

    // The system M X = Y.
    let (a_minus_b, a_minus_c) = (sub(&p.a, &p.b), sub(&p.a, &p.c));
    let y = sub(&p.a, &p.origin);
    let (m, y) = v
        .system
        .insert((from_columns([&a_minus_b, &a_minus_c, &p.dir]), y));

    // Degenerate triangle: the two edge vectors are parallel, n = (A−B)×(A−C) = 0.
    let normal = cross(&a_minus_b, &a_minus_c);
    if !all_finite(&normal) {
        return stop(v, overflow::<R>());
    }
    let area_scale = norm_f64(&a_minus_b) * norm_f64(&a_minus_c);
    let degenerate = negligible::<R>(norm_f64(&normal), area_scale, is_zero_vector(&normal));
    v.area = Some((normal.clone(), degenerate));
    if degenerate {
        return stop(v, TriangleMiss::DegenerateTriangle);
    }

    // Cramer's matrices, and |M|: zero when the ray is parallel to the plane.
    let mi = v
        .replaced
        .insert(std::array::from_fn(|col| with_column(m, col, y)));
    let det_m = &v.det.insert(Expansion::of(m)).value;
    if !det_m.is_finite() {
        return stop(v, overflow::<R>());
    }
    let parallel = negligible::<R>(
        det_m.to_f64().abs(),
        norm_f64(&normal) * norm_f64(&p.dir),
        det_m.is_zero(),
    );
    v.parallel = Some(parallel);
    if parallel {
        let in_plane = negligible::<R>(
            dot(&normal, y).to_f64().abs(),
            norm_f64(&normal) * norm_f64(y),
            dot(&normal, y).is_zero(),
        );
        return stop(v, TriangleMiss::Parallel { in_plane });
    }
    let dets = v.dets.insert(mi.each_ref().map(Expansion::of));
    if dets.iter().any(|d| !d.value.is_finite()) {
        return stop(v, overflow::<R>());
    }

    // β, γ, t by Cramer's rule; α from α + β + γ = 1.
    let quotient = |i: usize| {
        dets[i]
            .value
            .checked_div(det_m)
            .expect("|M| was checked to be nonzero")
    };
    let (beta, gamma, t) = (quotient(0), quotient(1), quotient(2));
    let alpha = R::one() - beta.clone() - gamma.clone();

    // In the triangle when β ≥ 0, γ ≥ 0, β + γ ≤ 1; in front when t > t_min.
    let failed = edges_failed(&beta, &gamma);
    let in_front = t > p.t_min;
    v.outcome = if !failed.is_empty() {
        TriangleOutcome::Miss(TriangleMiss::Outside {
            edges: failed.clone(),
        })
    } else if !in_front {
        TriangleOutcome::Miss(TriangleMiss::Behind)
    } else {
        TriangleOutcome::Hit
    };
    v.checks = Some((failed, in_front));
    let point = add(&p.origin, &scale(&t, &p.dir));
    let (distance, distance_exact) = distance_along(&t, &p.dir);
    v.solution = Some(Barycentric {
        beta,
        gamma,
        t,
        alpha,
        point,
        distance,
        distance_exact,
    });
    v
}

impl<R> Values<R> {
    fn stopped_at(outcome: TriangleOutcome) -> Values<R> {
        Values {
            outcome,
            system: None,
            area: None,
            replaced: None,
            det: None,
            parallel: None,
            dets: None,
            solution: None,
            checks: None,
        }
    }
}

/// Records what [`values`] computed, step by step, and the verdict.
fn record<R: Real>(p: &RayTriangle<R>, v: &Values<R>, steps: &mut impl StepSink) {
    if !steps.is_recording() {
        return;
    }
    record_stages(p, v, steps);
    let solution = v.solution.as_ref();
    record_verdict(
        steps,
        verdict_sentence(&v.outcome),
        v.outcome.status(),
        || verdict_message(&v.outcome, solution),
    );
    if let Some(found) = solution {
        record_point(steps, p, found, v.outcome.is_hit());
    }
}

/// The steps before the verdict, as far as the solve went.
fn record_stages<R: Real>(p: &RayTriangle<R>, v: &Values<R>, steps: &mut impl StepSink) {
    let Some((m, y)) = &v.system else { return };
    let matrix = || Matrix::of3("M", "M", m, LABELS);
    record_system(steps, &SYSTEM, matrix, || Vector::of("Y", "Y", y));
    let Some((normal, degenerate)) = &v.area else {
        return;
    };
    steps.push(|| area_check(normal, *degenerate));
    let (Some(mi), Some(det_m)) = (&v.replaced, &v.det) else {
        return;
    };
    record_replaced(steps, 3, |i| {
        Matrix::of3(
            &format!("M{}", i + 1),
            &format!("M_{}", i + 1),
            &mi[i],
            LABELS,
        )
    });
    record_det(steps, det_m, ["M", "M"], DET_M_NOTE);
    let Some(parallel) = v.parallel else { return };
    steps.push(|| {
        det_check(
            &det_m.value,
            parallel,
            parallel_explanation::<R>(),
            PARALLEL,
        )
    });
    let Some(dets) = &v.dets else { return };
    for (i, det) in dets.iter().enumerate() {
        record_det(
            steps,
            det,
            [["M1", "M_1"], ["M2", "M_2"], ["M3", "M_3"]][i],
            DET_MI_NOTE,
        );
    }
    let (Some(s), Some((failed, in_front))) = (&v.solution, &v.checks) else {
        return;
    };
    for (i, unknown) in UNKNOWNS.into_iter().enumerate() {
        let numerator = [&format!("|M{}|", i + 1), &format!("|M_{}|", i + 1)];
        let values = [&dets[i].value, &det_m.value, [&s.beta, &s.gamma, &s.t][i]];
        record_quotient(
            steps,
            unknown,
            numerator.map(String::as_str),
            values,
            UNKNOWN_NOTES[i],
        );
    }
    steps.push(|| alpha_step(&s.alpha));
    record_checks(steps, p, s, failed, *in_front);
}

/// The system's words.
const SYSTEM: SystemWords = SystemWords {
    title: "The system M X = Y",
    setup: "Set L + tD = A + β(B−A) + γ(C−A) and move the unknowns β, γ, t to the left.",
    unknowns: &[["β", "\\beta"], ["γ", "\\gamma"], ["t", "t"]],
    apart: Some([
        [
            "M = [A−B | A−C | D]",
            "The columns are the two edge vectors from B and C to A, and the ray's direction.",
        ],
        [
            "Y = A − L",
            "The right-hand side: the vector from the ray's origin L to the vertex A.",
        ],
    ]),
};
const DET_M_NOTE: &str = "The determinant of M, expanded along the first row.";
const DET_MI_NOTE: &str = "Expanded along the first row, like |M|.";
const PARALLEL: &str =
    "the ray is parallel to the triangle's plane, so M X = Y has no unique solution";

/// Column labels of M (the app colours columns by them).
const LABELS: [Column; 3] = [Column::AMinusB, Column::AMinusC, Column::D];
const UNKNOWNS: [[&str; 3]; 3] = [
    ["beta", "β", "\\beta"],
    ["gamma", "γ", "\\gamma"],
    ["t", "t", "t"],
];
const UNKNOWN_NOTES: [&str; 3] = [
    "β = |M1| / |M|: how far to go along B−A from A.",
    "γ = |M2| / |M|: how far to go along C−A from A.",
    "t = |M3| / |M|: how far along the ray, in units of |D| (not a distance unless |D| = 1).",
];

/// The miss of a solve whose numbers outgrew the precision.
fn overflow<R: Real>() -> TriangleMiss {
    TriangleMiss::InvalidInput(InvalidInput {
        field: "input".into(),
        problem: format!(
            "the determinants overflow {}: the coordinates are too large for this precision",
            R::PRECISION.name()
        ),
    })
}

fn area_check<R: Real>(normal: &V3<R>, degenerate: bool) -> Step {
    check(
        [
            "check_area",
            "The triangle has an area",
            area_explanation::<R>(),
        ],
        ["|(A−B)×(A−C)| / 2 > 0", "\\tfrac12 |(A-B)\\times(A-C)| > 0"],
        length(normal, 2.0),
        !degenerate,
        "A, B and C are collinear: the triangle is a segment or a point",
    )
}

fn record_det<R: Real>(
    steps: &mut impl StepSink,
    det: &Expansion<R>,
    [name, latex]: [&str; 2],
    explanation: &str,
) {
    steps.push(|| {
        Step::new(
            format!("det_{name}"),
            format!("|{name}|"),
            explanation,
            Payload::Determinant(Determinant::of3(name, latex, &det.terms, &det.value)),
        )
    });
}

fn alpha_step<R: Real>(alpha: &R) -> Step {
    Step::new(
        "alpha",
        "α, the third barycentric coordinate",
        "The weights of A, B and C add up to 1, so α = 1 − β − γ.",
        Payload::Scalar(Scalar {
            symbol: "α".into(),
            latex: "\\alpha".into(),
            formula: Some(Formula::Expression {
                text: "1 − β − γ".into(),
                latex: "1 - \\beta - \\gamma".into(),
            }),
            value: Number::of(alpha),
            closed_form: None,
        }),
    )
}

/// Records the four checks: the three inequalities of the triangle and t > t_min.
fn record_checks<R: Real>(
    steps: &mut impl StepSink,
    p: &RayTriangle<R>,
    s: &Barycentric<R>,
    failed: &[Edge],
    in_front: bool,
) {
    let inside_checks = [
        (Edge::Ca, s.beta.clone(), "\\beta \\ge 0"),
        (Edge::Ab, s.gamma.clone(), "\\gamma \\ge 0"),
        (
            Edge::Bc,
            s.beta.clone() + s.gamma.clone(),
            "\\beta + \\gamma \\le 1",
        ),
    ];
    for (edge, value, latex) in inside_checks {
        steps.push(|| {
            let id = format!("check_{}", edge.name().to_lowercase());
            let title = format!("Check {}", edge.inequality());
            check(
                [&id, &title, INSIDE_NOTE],
                [edge.inequality(), latex],
                Number::of(&value),
                !failed.contains(&edge),
                format!("the point is beyond edge {}", edge.name()),
            )
        });
    }
    steps.push(|| {
        let t_min = Number::of(&p.t_min);
        let inequality = format!("t > {}", t_min.shown());
        let latex = format!("t > {}", crate::trace::latex_number(&t_min));
        let meaning = if s.t < R::zero() {
            "the plane is behind the ray's origin"
        } else {
            "the plane is not beyond t_min"
        };
        let words = ["check_t", "Check t > t_min", IN_FRONT_NOTE];
        check(
            words,
            [&inequality, &latex],
            Number::of(&s.t),
            in_front,
            meaning,
        )
    });
}

const INSIDE_NOTE: &str =
    "A point of the plane is in the triangle only if all three inequalities hold.";
const IN_FRONT_NOTE: &str = "The hit must be in front of the ray's origin (t_min is excluded).";

/// t·|D|, with its exact closed form when exact (t²·(D·D) under a square root).
fn distance_along<R: Real>(t: &R, dir: &V3<R>) -> (f64, Option<SignedRoot>) {
    let exact = t
        .to_exact()
        .zip(dot(dir, dir).to_exact())
        .map(|(t, dd)| SignedRoot {
            negative: t < Exact::from_int(0),
            square: &(&t * &t) * &dd,
        });
    // In exact precision the float comes from the exact square, so t = 10^400 along a D of length
    // √3·10^-400 reads √3 ≈ 1.732, not ∞·0 = NaN.
    let distance = match &exact {
        Some(root) => root.to_f64(),
        None => t.to_f64() * norm_f64(dir),
    };
    (distance, exact)
}

fn record_point<R: Real>(
    rec: &mut impl StepSink,
    p: &RayTriangle<R>,
    s: &Barycentric<R>,
    hit: bool,
) {
    let title = if hit {
        "Hit point L + tD"
    } else {
        "Where the ray's line meets the plane, L + tD"
    };
    rec.push(|| {
        Step::new(
            "point",
            title,
            "Knowing t gives the point; A + β(B−A) + γ(C−A) is the same point.",
            Payload::Vector(Vector::of("P", "P", &s.point)),
        )
    });
    rec.push(|| {
        // |D| from the exact D·D where there is one: a D of 10^-400 is not of length 0.
        let d_norm = match dot(&p.dir, &p.dir).to_exact() {
            Some(dd) if !dd.is_zero() => SignedRoot {
                negative: false,
                square: dd,
            }
            .display(),
            _ => crate::trace::format_float(norm_f64(&p.dir), R::PRECISION),
        };
        let explanation = format!(
            "t counts steps of length |D| = {d_norm}; the distance along the ray is t·|D| (equal to t only for a unit D)."
        );
        let payload = Payload::Scalar(Scalar {
            symbol: "t·|D|".into(),
            latex: "t\\,|D|".into(),
            formula: None,
            value: match &s.distance_exact {
                // Beyond the float range (t = 10^400): the exact root, not ∞.
                Some(root) if !s.distance.is_normal() && !root.square.is_zero() => {
                    Number::root(root)
                }
                _ => Number::float(s.distance, R::PRECISION),
            },
            closed_form: s.distance_exact.as_ref().and_then(|root| {
                Some(ClosedForm {
                    text: root.short()?,
                    latex: root.short_latex()?,
                })
            }),
        });
        Step::new("distance", "Distance from L: t·|D|", explanation, payload)
    });
}

/// Where the sliders put things: P(β, γ) on the plane, L + tD on the ray, and the gap between them.
///
/// This is the "drive from the red to the green point" picture of seed 000: at the solution
/// (β*, γ*, t*) the gap is zero.
#[derive(Clone, Debug, PartialEq)]
pub struct Exploration<R> {
    /// A + β(B−A): the end of the first leg from A (the second leg, γ(C−A), ends at P).
    pub beta_end: V3<R>,
    /// P(β, γ) = A + β(B−A) + γ(C−A).
    pub plane_point: V3<R>,
    /// L + tD.
    pub ray_point: V3<R>,
    /// |P(β, γ) − (L + tD)|.
    pub gap: f64,
    /// The inequalities (β, γ) fails, as edges; empty when P is in the triangle.
    pub outside: Vec<Edge>,
}

/// Evaluates both parametric forms at the given parameters.
pub fn explore<R: Real>(p: &RayTriangle<R>, beta: &R, gamma: &R, t: &R) -> Exploration<R> {
    let beta_end = point_at(p, beta, &R::zero());
    let plane_point = point_at(p, beta, gamma);
    let ray_point = add(&p.origin, &scale(t, &p.dir));
    let gap = norm_f64(&sub(&plane_point, &ray_point));
    Exploration {
        beta_end,
        plane_point,
        ray_point,
        gap,
        outside: edges_failed(beta, gamma),
    }
}

/// The triangle's parametric form P(β, γ) = A + β(B−A) + γ(C−A): any point of its plane.
pub fn point_at<R: Real>(p: &RayTriangle<R>, beta: &R, gamma: &R) -> V3<R> {
    let legs = add(
        &scale(beta, &sub(&p.b, &p.a)),
        &scale(gamma, &sub(&p.c, &p.a)),
    );
    add(&p.a, &legs)
}

/// The edges a point with barycentrics (β, γ) is beyond (β < 0: CA, γ < 0: AB, β + γ > 1: BC).
pub fn edges_failed<R: Real>(beta: &R, gamma: &R) -> Vec<Edge> {
    let zero = R::zero();
    let mut edges = Vec::new();
    if beta < &zero {
        edges.push(Edge::Ca);
    }
    if gamma < &zero {
        edges.push(Edge::Ab);
    }
    if beta.clone() + gamma.clone() > R::one() {
        edges.push(Edge::Bc);
    }
    edges
}
