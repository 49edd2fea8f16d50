//! `raylab solve`: one case from flags, or many from JSON lines, printed as text, JSON or LaTeX.

use serde::Serialize;
use serde_json::{Map, Value, json};

use super::input::{Coords, InputError, Literal};
use crate::geometry::parallelogram::{self, ParallelogramSolution, RayParallelogram};
use crate::geometry::segments::{self, SegmentPair, SegmentsOutcome, SegmentsSolution};
use crate::geometry::triangle::{
    self, RayTriangle, TriangleMiss, TriangleOutcome, TriangleSolution,
};
use crate::geometry::{Precision, Real};
use crate::math::{InPrecision, in_precision};
use crate::trace::{Recorder, Status, StepSink, Trace};

/// One problem to solve, with its inputs as the user wrote them.
#[derive(Clone, Debug, PartialEq)]
pub enum Case {
    /// Two 2D segments A1–A2 and B1–B2.
    Segments {
        /// A1, A2, B1, B2.
        points: [Coords<2>; 4],
    },
    /// A ray L + tD and a triangle A, B, C.
    Triangle {
        /// A, B, C, L (origin), D (direction).
        vectors: [Coords<3>; 5],
        /// Hits need t > t_min.
        t_min: Literal,
    },
    /// A ray o + t d and a parallelogram c + α e1 + β e2.
    Parallelogram {
        /// c (corner), e1, e2, o (origin), d (direction).
        vectors: [Coords<3>; 5],
    },
}

/// Why a case given on the command line is not solved.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SolveError {
    /// A flag's number or vector that the precision cannot hold.
    #[error("--{flag}: {error}")]
    Flag {
        /// The flag, without its dashes.
        flag: &'static str,
        /// Why.
        error: InputError,
    },
    /// `--tmin` with a method that always tests t > 0.
    #[error("--method {} tests t > 0; --tmin applies to cramer and exact only", .0.name())]
    TMinNotApplicable(crate::intersect::Method),
    /// `--precision exact` with a float-only method.
    #[error("--method {} runs in f32 or f64; use --method exact for exact arithmetic", .0.name())]
    FloatOnly(crate::intersect::Method),
}

impl Case {
    /// Ok if `precision` can hold every number (exact holds any), else the refusal naming the flag.
    pub fn fits(&self, precision: Precision) -> Result<(), SolveError> {
        let named = |flag: &'static str, result: Result<(), InputError>| {
            result.map_err(|error| SolveError::Flag { flag, error })
        };
        match self {
            Case::Segments { points } => ["a1", "a2", "b1", "b2"]
                .iter()
                .zip(points)
                .try_for_each(|(flag, p)| named(flag, p.fits(precision))),
            Case::Triangle { vectors, t_min } => ["a", "b", "c", "origin", "dir"]
                .iter()
                .zip(vectors)
                .try_for_each(|(flag, v)| named(flag, v.fits(precision)))
                .and_then(|()| named("tmin", t_min.fits(precision))),
            Case::Parallelogram { vectors } => ["corner", "e1", "e2", "origin", "dir"]
                .iter()
                .zip(vectors)
                .try_for_each(|(flag, v)| named(flag, v.fits(precision))),
        }
    }

    /// `segments`, `triangle` or `parallelogram`.
    pub fn kind(&self) -> &'static str {
        match self {
            Case::Segments { .. } => "segments",
            Case::Triangle { .. } => "triangle",
            Case::Parallelogram { .. } => "parallelogram",
        }
    }
}

/// The result of one solve: the JSON object (without the trace) and the trace.
#[derive(Clone, Debug)]
pub struct Report {
    /// `status`, the parameters, `point`, `exact`, …
    pub fields: Map<String, Value>,
    /// Every step.
    pub trace: Trace,
}

impl Report {
    /// The full JSON object, with the trace unless `with_trace` is false.
    #[allow(
        clippy::expect_used,
        reason = "serde_json writes any value made of maps with string keys, numbers and strings"
    )]
    pub fn to_json(&self, with_trace: bool) -> Value {
        let mut fields = self.fields.clone();
        if with_trace {
            fields.put(
                "trace",
                serde_json::to_value(&self.trace).expect("a trace always serializes"),
            );
        }
        Value::Object(fields)
    }
}

/// Solves a case in the chosen precision.
pub fn run(case: &Case, precision: Precision) -> Report {
    struct Run<'a>(&'a Case);
    impl InPrecision for Run<'_> {
        type Output = Report;
        fn run<R: Real>(self) -> Report {
            let mut fields = Map::new();
            let trace = solve_posed_traced(&pose::<R>(self.0), &mut fields);
            Report { fields, trace }
        }
    }
    in_precision(precision, Run(case))
}

/// A problem in one precision, ready to solve.
#[derive(Clone, Debug, PartialEq)]
pub enum Posed<R> {
    /// Two 2D segments.
    Segments(SegmentPair<R>),
    /// A ray and a triangle.
    Triangle(RayTriangle<R>),
    /// A ray and a parallelogram.
    Parallelogram(RayParallelogram<R>),
}

impl<R> Posed<R> {
    /// `segments`, `triangle` or `parallelogram`.
    pub fn kind(&self) -> &'static str {
        match self {
            Posed::Segments(_) => "segments",
            Posed::Triangle(_) => "triangle",
            Posed::Parallelogram(_) => "parallelogram",
        }
    }
}

/// The case's numbers in precision `R` (rounded once from the exact value of the text).
fn pose<R: Real>(case: &Case) -> Posed<R> {
    match case {
        Case::Segments { points } => Posed::Segments(SegmentPair {
            a1: convert(&points[0]),
            a2: convert(&points[1]),
            b1: convert(&points[2]),
            b2: convert(&points[3]),
        }),
        Case::Triangle { vectors, t_min } => Posed::Triangle(RayTriangle {
            a: convert(&vectors[0]),
            b: convert(&vectors[1]),
            c: convert(&vectors[2]),
            origin: convert(&vectors[3]),
            dir: convert(&vectors[4]),
            t_min: R::from_exact(&t_min.exact),
        }),
        Case::Parallelogram { vectors } => {
            Posed::Parallelogram(RayParallelogram::new(std::array::from_fn(|i| {
                convert(&vectors[i])
            })))
        }
    }
}

/// Solves a posed problem into the report's fields, recording every step into `steps` (`()` records
/// none: a solve without a trace formats no step at all).
pub fn solve_posed<R: Real>(
    posed: &Posed<R>,
    fields: &mut impl FieldSink,
    steps: &mut impl StepSink,
) {
    fields.put("kind", posed.kind());
    fields.put("precision", R::PRECISION.name());
    match posed {
        Posed::Segments(pair) => segments_report(&segments::solve(pair, steps), fields),
        Posed::Triangle(problem) => triangle_report(&triangle::solve(problem, steps), fields),
        Posed::Parallelogram(problem) => {
            parallelogram_report(&parallelogram::solve(problem, steps), fields)
        }
    }
}

/// [`solve_posed`] with every step: the trace.
pub fn solve_posed_traced<R: Real>(posed: &Posed<R>, fields: &mut impl FieldSink) -> Trace {
    let mut steps = Recorder::new(posed.kind(), R::PRECISION);
    solve_posed(posed, fields, &mut steps);
    steps.into_trace()
}

fn convert<R: Real, const N: usize>(c: &Coords<N>) -> [R; N] {
    let exact = c.exact();
    std::array::from_fn(|i| R::from_exact(&exact[i]))
}

/// A value in a report: a JSON float where a float holds it. An exact value beyond the float range
/// (t = 10^400, which would be ∞, or 10^-400, which would be 0) is written as a string from the exact
/// value, `"≈1e400"`; a float precision's NaN or ±inf is written as null (JSON has no such numbers).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum JsonNumber {
    /// The value as a float.
    Float(f64),
    /// The exact value where no float holds it.
    Text(String),
}

impl JsonNumber {
    fn of<R: Real>(x: &R) -> JsonNumber {
        let float = x.to_f64();
        match x.to_exact() {
            Some(exact) if !float.is_finite() || (float == 0.0 && !exact.is_zero()) => {
                JsonNumber::Text(exact.display())
            }
            _ => JsonNumber::Float(float),
        }
    }
}

fn optional<R: Real>(x: Option<&R>) -> Option<JsonNumber> {
    x.map(JsonNumber::of)
}

fn vector<R: Real, const N: usize>(v: Option<&[R; N]>) -> Option<[JsonNumber; N]> {
    v.map(|v| std::array::from_fn(|i| JsonNumber::of(&v[i])))
}

/// Where a report's fields go, in order: a JSON map (for a single solve, which adds to it), or
/// straight onto a batch's output line (no map, no allocation per field).
pub trait FieldSink {
    /// Adds the field `key`.
    fn put(&mut self, key: &'static str, value: impl Serialize);
}

impl FieldSink for Map<String, Value> {
    #[allow(
        clippy::expect_used,
        reason = "serde_json writes any value made of maps with string keys, numbers and strings"
    )]
    fn put(&mut self, key: &'static str, value: impl Serialize) {
        let value = serde_json::to_value(value).expect("report fields always serialize");
        self.insert(key.into(), value);
    }
}

/// Collects exact strings for named values when the precision is exact; empty otherwise.
struct ExactFields(Map<String, Value>);

impl ExactFields {
    fn new() -> ExactFields {
        ExactFields(Map::new())
    }

    fn scalar<R: Real>(&mut self, name: &str, x: Option<&R>) {
        if let Some(exact) = x.and_then(Real::to_exact) {
            self.0.insert(name.into(), json!(exact.fraction()));
        }
    }

    fn vector<R: Real, const N: usize>(&mut self, name: &str, v: Option<&[R; N]>) {
        if let Some(v) = v.filter(|_| R::PRECISION == Precision::Exact) {
            let parts: Vec<Value> = v
                .iter()
                .filter_map(Real::to_exact)
                .map(|e| json!(e.fraction()))
                .collect();
            self.0.insert(name.into(), Value::Array(parts));
        }
    }

    fn finish(self, fields: &mut impl FieldSink) {
        if !self.0.is_empty() {
            fields.put("exact", self.0);
        }
    }
}

fn segments_report<R: Real>(solution: &SegmentsSolution<R>, fields: &mut impl FieldSink) {
    fields.put("status", solution.outcome.status());
    fields.put("message", solution.message());
    match &solution.outcome {
        SegmentsOutcome::LinesCrossOutside {
            t_outside,
            s_outside,
        } => {
            let mut outside = Vec::new();
            if *t_outside {
                outside.push("t");
            }
            if *s_outside {
                outside.push("s");
            }
            fields.put("outside", &outside);
        }
        SegmentsOutcome::DegenerateSegment { a, b } => {
            fields.put("zero_length", json!({"a": a, "b": b}));
        }
        SegmentsOutcome::InvalidInput(bad) => {
            fields.put("field", json!(bad.field));
        }
        _ => {}
    }
    fields.put("t", optional(solution.t.as_ref()));
    fields.put("s", optional(solution.s.as_ref()));
    fields.put("point", vector(solution.point.as_ref()));
    fields.put("overlap", vector(solution.overlap.as_ref()));
    let mut exact = ExactFields::new();
    exact.scalar("t", solution.t.as_ref());
    exact.scalar("s", solution.s.as_ref());
    exact.vector("point", solution.point.as_ref());
    exact.vector("overlap", solution.overlap.as_ref());
    exact.finish(fields);
}

fn triangle_report<R: Real>(solved: &TriangleSolution<R>, fields: &mut impl FieldSink) {
    fields.put("status", solved.outcome.status());
    fields.put("message", solved.message());
    if let TriangleOutcome::Miss(miss) = &solved.outcome {
        insert_triangle_miss(fields, miss);
    }
    let s = solved.solution.as_ref();
    let hit = solved.outcome.is_hit();
    fields.put("beta", optional(s.map(|s| &s.beta)));
    fields.put("gamma", optional(s.map(|s| &s.gamma)));
    fields.put("t", optional(s.map(|s| &s.t)));
    fields.put("alpha", optional(s.map(|s| &s.alpha)));
    fields.put("distance", s.map(|s| s.distance));
    fields.put("point", vector(s.filter(|_| hit).map(|s| &s.point)));
    if !hit {
        fields.put("plane_point", vector(s.map(|s| &s.point)));
    }
    let mut exact = ExactFields::new();
    exact.scalar("beta", s.map(|s| &s.beta));
    exact.scalar("gamma", s.map(|s| &s.gamma));
    exact.scalar("t", s.map(|s| &s.t));
    exact.scalar("alpha", s.map(|s| &s.alpha));
    exact.vector(
        if hit { "point" } else { "plane_point" },
        s.map(|s| &s.point),
    );
    if let Some(distance) = s.and_then(|s| s.distance_exact.as_ref()) {
        exact.0.insert("distance".into(), json!(distance.full()));
    }
    exact.finish(fields);
}

fn insert_triangle_miss(fields: &mut impl FieldSink, miss: &TriangleMiss) {
    match miss {
        TriangleMiss::Outside { edges } => {
            let failed: Vec<&str> = edges.iter().map(|e| e.inequality()).collect();
            let beyond: Vec<&str> = edges.iter().map(|e| e.name()).collect();
            fields.put("failed", &failed);
            fields.put("beyond_edges", &beyond);
        }
        TriangleMiss::Parallel { in_plane } => {
            fields.put("in_plane", in_plane);
        }
        TriangleMiss::ZeroDirection => {
            fields.put("field", json!("D"));
            fields.put("reason", json!("zero-direction"));
        }
        TriangleMiss::InvalidInput(bad) => {
            fields.put("field", json!(bad.field));
        }
        TriangleMiss::Behind | TriangleMiss::DegenerateTriangle => {}
    }
}

fn parallelogram_report<R: Real>(solved: &ParallelogramSolution<R>, fields: &mut impl FieldSink) {
    fields.put("status", solved.outcome.status());
    fields.put("message", solved.message());
    match &solved.outcome {
        parallelogram::ParallelogramOutcome::Outside { sides } => {
            let failed: Vec<&str> = sides.iter().map(|s| s.inequality()).collect();
            fields.put("failed", &failed);
        }
        parallelogram::ParallelogramOutcome::Degenerate => {
            fields.put("reason", json!("degenerate-parallelogram"));
        }
        parallelogram::ParallelogramOutcome::ZeroDirection => {
            fields.put("field", json!("d"));
            fields.put("reason", json!("zero-direction"));
        }
        parallelogram::ParallelogramOutcome::InvalidInput(bad) => {
            fields.put("field", json!(bad.field));
        }
        _ => {}
    }
    let x = solved.alpha_beta_t.as_ref();
    let hit = solved.outcome.is_hit();
    fields.put("alpha", optional(x.map(|x| &x[0])));
    fields.put("beta", optional(x.map(|x| &x[1])));
    fields.put("t", optional(x.map(|x| &x[2])));
    fields.put("point", vector(solved.point.as_ref().filter(|_| hit)));
    if !hit {
        fields.put("plane_point", vector(solved.point.as_ref()));
    }
    let mut exact = ExactFields::new();
    exact.scalar("alpha", x.map(|x| &x[0]));
    exact.scalar("beta", x.map(|x| &x[1]));
    exact.scalar("t", x.map(|x| &x[2]));
    exact.vector(
        if hit { "point" } else { "plane_point" },
        solved.point.as_ref(),
    );
    exact.finish(fields);
}

/// Copies the verdict's sentence into the report as `message`.
fn insert_message(fields: &mut Map<String, Value>, trace: Option<&Trace>) {
    if let Some(verdict) = trace.and_then(Trace::verdict) {
        fields.put("message", json!(verdict.message));
    }
}

/// Runs one of the accuracy study's methods on a triangle case (`raylab solve triangle --method`).
///
/// `cramer` is the lecture's solver (the default); `exact` is the same in exact arithmetic; the others
/// run in f32 or f64 and report what they decided, with their own trace. t_min is 0 for them.
pub fn method_report(
    vectors: &[Coords<3>; 5],
    t_min: &Literal,
    method: crate::intersect::Method,
    precision: Precision,
) -> Result<Report, SolveError> {
    use crate::intersect::Method;
    let lecture = || Case::Triangle {
        vectors: vectors.clone(),
        t_min: t_min.clone(),
    };
    if !t_min.exact.is_zero() && !matches!(method, Method::Cramer | Method::Exact) {
        return Err(SolveError::TMinNotApplicable(method));
    }
    if method != Method::Exact {
        lecture().fits(precision)?;
    }
    let named = |mut report: Report| {
        report.fields.put("method", json!(method.name()));
        report
    };
    match (method, precision) {
        (Method::Exact, _) => Ok(named(run(&lecture(), Precision::Exact))),
        (Method::Cramer, p) => Ok(named(run(&lecture(), p))),
        (_, Precision::Exact) => Err(SolveError::FloatOnly(method)),
        (_, Precision::F32) => Ok(float_method_report::<f32>(vectors, method)),
        (_, Precision::F64) => Ok(float_method_report::<f64>(vectors, method)),
    }
}

fn float_method_report<F: crate::intersect::Float + crate::intersect::InverseSolve>(
    vectors: &[Coords<3>; 5],
    method: crate::intersect::Method,
) -> Report {
    let v = |i: usize| convert::<F, 3>(&vectors[i]);
    let case = crate::intersect::Case {
        tri: [v(0), v(1), v(2)],
        origin: v(3),
        dir: v(4),
    };
    let answer = method.run(&case);
    let trace = method.trace(&case);
    let status = match answer.values {
        _ if answer.hit => Status::Hit,
        _ if answer.invalid_input => Status::InvalidInput,
        // The method gave up before solving: the exact solver says why (parallel, degenerate, D = 0).
        None => unsolved_status(&case),
        Some(values) if values.iter().any(|x| !x.is_finite()) => Status::InvalidInput,
        Some([_, beta, gamma]) => {
            let outside = beta < F::zero() || gamma < F::zero() || beta + gamma > F::one();
            if outside {
                Status::MissOutside
            } else {
                Status::MissBehind
            }
        }
    };
    let mut fields = Map::new();
    fields.put("kind", json!("triangle"));
    fields.put("method", json!(method.name()));
    fields.put("precision", json!(F::PRECISION.name()));
    fields.put("status", json!(status));
    insert_message(&mut fields, Some(&trace));
    let values = answer.values;
    fields.put("t", optional(values.as_ref().map(|v| &v[0])));
    fields.put("beta", optional(values.as_ref().map(|v| &v[1])));
    fields.put("gamma", optional(values.as_ref().map(|v| &v[2])));
    fields.put("exact_fallback", json!(answer.exact_fallback));
    Report { fields, trace }
}

/// Why a float method found no solution, in the triangle status words, as the exact solver sees it.
fn unsolved_status<F: crate::intersect::Float>(case: &crate::intersect::Case<F>) -> Status {
    let Some(problem) = crate::intersect::exact_problem(case) else {
        return Status::InvalidInput;
    };
    match triangle::solve(&problem, &mut ()).outcome {
        TriangleOutcome::Miss(TriangleMiss::DegenerateTriangle) => Status::DegenerateTriangle,
        TriangleOutcome::Miss(TriangleMiss::ZeroDirection | TriangleMiss::InvalidInput(_)) => {
            Status::InvalidInput
        }
        // Exactly solvable, but this method's own rounding found |M| = 0.
        _ => Status::Parallel,
    }
}
