//! Every ray–triangle method raylab knows, in f32, f64 and exact arithmetic: Cramer's rule (the lecture's),
//! Möller–Trumbore, the plane-then-edges test, the normal equations, glam's inverse, Woop–Benthin–Wald's
//! watertight test and the exact rational reference. The accuracy study compares them; the renderer,
//! the probe and the command line use them.
//!
//! Every method answers the same question with the same rules as the lecture — hit if and only if
//! β ≥ 0, γ ≥ 0, β + γ ≤ 1 and t > t_min, edges included — so any disagreement with the exact reference
//! is a rounding error, never a difference of convention.

pub mod cramer;
pub mod inverse;
pub mod moller_trumbore;
pub mod normal_equations;
pub mod plane;
pub mod reference;
pub mod soa;
pub mod watertight;

use serde::{Deserialize, Serialize};

use crate::geometry::triangle::{self, RayTriangle};
use crate::geometry::{Lecture, Real, TriangleLecture};
use crate::math::exact::Exact;
use crate::math::linalg::V3;

/// A float precision a method can run in.
pub trait Float: Real + Copy + Send + Sync + 'static {
    /// Machine epsilon.
    const EPS: Self;
    /// The smallest positive normal number.
    const MIN_POSITIVE: Self;
    /// Converts, rounding to nearest.
    fn of(x: f64) -> Self;
    /// The square root.
    fn sqrt(self) -> Self;
    /// The larger of two.
    fn max(self, other: Self) -> Self;
    /// `self / other` (IEEE: ±inf or NaN on zero).
    fn div(self, other: Self) -> Self;
}

macro_rules! float_impl {
    ($t:ty) => {
        impl Float for $t {
            const EPS: $t = <$t>::EPSILON;
            const MIN_POSITIVE: $t = <$t>::MIN_POSITIVE;
            fn of(x: f64) -> $t {
                x as $t
            }
            fn sqrt(self) -> $t {
                <$t>::sqrt(self)
            }
            fn max(self, other: $t) -> $t {
                <$t>::max(self, other)
            }
            fn div(self, other: $t) -> $t {
                self / other
            }
        }
    };
}

float_impl!(f32);
float_impl!(f64);

/// A ray and a triangle, in one precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case<F> {
    /// Vertices A, B, C.
    pub tri: [V3<F>; 3],
    /// The ray's origin.
    pub origin: V3<F>,
    /// The ray's direction.
    pub dir: V3<F>,
}

impl Case<f64> {
    /// The lecture's example: the triangle (3,0,0), (0,3,0), (0,0,3) and the ray from the origin
    /// along (1,1,1), which meets it at t = 1 (β = γ = 1/3).
    pub const LECTURE: Case<f64> = Case {
        tri: [[3.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 3.0]],
        origin: [0.0; 3],
        dir: [1.0, 1.0, 1.0],
    };

    /// Seed 003's notebook example: its triangle and the ray from the origin along (0.1, 0.1, 1),
    /// which meets it at about (0.1184, 0.1184, 1.1842); non-integer inputs, so exact arithmetic
    /// meets real fractions.
    pub const SEED003: Case<f64> = Case {
        tri: [[0.0, 1.0, 1.5], [1.0, 0.0, 1.25], [-1.0, 0.0, 1.0]],
        origin: [0.0; 3],
        dir: [0.1, 0.1, 1.0],
    };

    /// A, B, C, the origin and the direction, in the order the lecture's solver reads them.
    pub fn vectors(&self) -> [V3<f64>; 5] {
        let [a, b, c] = self.tri;
        [a, b, c, self.origin, self.dir]
    }

    /// Rounds every coordinate to f32 (f32 runs and their exact judge both see these numbers).
    pub fn to_f32(&self) -> Case<f32> {
        let r = |v: V3<f64>| v.map(|x| x as f32);
        Case {
            tri: self.tri.map(r),
            origin: r(self.origin),
            dir: r(self.dir),
        }
    }
}

/// A method's answer: hit with its parameters, or miss.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Answer<F> {
    /// The decision.
    pub hit: bool,
    /// t, β, γ when the method computed them (even for a miss, where meaningful).
    pub values: Option<[F; 3]>,
    /// True when the method handed the case to exact arithmetic (the watertight method does near zero).
    pub exact_fallback: bool,
    /// True when the method refused the input as outside its range (NaN, infinities).
    pub invalid_input: bool,
}

impl<F> Answer<F> {
    /// A miss with no values (parallel, degenerate, rejected early).
    pub fn miss() -> Answer<F> {
        Answer {
            hit: false,
            values: None,
            exact_fallback: false,
            invalid_input: false,
        }
    }

    /// A decision with its values.
    pub fn with(hit: bool, values: [F; 3]) -> Answer<F> {
        Answer {
            hit,
            values: Some(values),
            exact_fallback: false,
            invalid_input: false,
        }
    }
}

/// The methods compared, in this order (the reference last).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[derive(strum::EnumIter, strum::IntoStaticStr)]
#[strum(serialize_all = "kebab-case")]
pub enum Method {
    /// The lecture's Cramer's rule: four 3x3 determinants.
    Cramer,
    /// Möller–Trumbore: Cramer with the common terms collected.
    MollerTrumbore,
    /// Plane intersection, then the inside-outside edge test (seed 003, `or` fixed).
    Plane,
    /// Barycentrics by the 2x2 system of dot products (seed 004).
    NormalEquations,
    /// M X = Y solved with glam's matrix inverse.
    Inverse,
    /// Woop, Benthin and Wald's watertight test, with exact fallbacks near zero.
    Watertight,
    /// The same exact-deciding watertight test, by the name the renderer gives it: there
    /// `watertight` is the fast crack-free test for meshes (`render::crack_free`).
    WatertightExact,
    /// The exact rational reference.
    Exact,
}

impl Method {
    /// The float methods.
    pub const FLOAT: [Method; 6] = [
        Method::Cramer,
        Method::MollerTrumbore,
        Method::Plane,
        Method::NormalEquations,
        Method::Inverse,
        Method::Watertight,
    ];

    /// The name on the command line and in JSON (`moller-trumbore`).
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// Runs the method in precision F.
    pub fn run<F: Float + InverseSolve>(self, case: &Case<F>) -> Answer<F> {
        match self {
            Method::Cramer => cramer::intersect(case),
            Method::MollerTrumbore => moller_trumbore::intersect(case),
            Method::Plane => plane::intersect(case),
            Method::NormalEquations => normal_equations::intersect(case),
            Method::Inverse => inverse::intersect(case),
            Method::Watertight | Method::WatertightExact => watertight::intersect(case),
            Method::Exact => {
                let exact = exact_answer(case);
                Answer {
                    hit: exact.hit,
                    values: exact.values.map(|v| v.map(|x| F::of(x.to_f64()))),
                    exact_fallback: false,
                    invalid_input: false,
                }
            }
        }
    }
}

impl Method {
    /// Runs the method in precision F and records its steps.
    ///
    /// Cramer's rule and the exact reference show the lecture's full trace (M, M1–M3, expansions); each
    /// other method shows its own intermediate values (Möller–Trumbore's shared cross products, the
    /// plane's normal and hit point, the normal equations' matrix, the watertight shear and edge
    /// functions with their bounds), then the four checks and whether floats or exact arithmetic decided.
    pub fn trace<F: Float + InverseSolve>(self, case: &Case<F>) -> crate::trace::Trace {
        use crate::trace::Recorder;
        let lecture = |c: &Case<F>| {
            let problem = RayTriangle {
                a: c.tri[0],
                b: c.tri[1],
                c: c.tri[2],
                origin: c.origin,
                dir: c.dir,
                t_min: F::zero(),
            };
            TriangleLecture::traced(&problem).1
        };
        match self {
            Method::Cramer => lecture(case),
            Method::Exact => match exact_problem(case) {
                Some(problem) => TriangleLecture::traced(&problem).1,
                None => {
                    let mut rec = Recorder::new("exact", crate::geometry::Precision::Exact);
                    let refused = Answer {
                        invalid_input: true,
                        ..Answer::miss()
                    };
                    record::outcome::<F>(&mut rec, &refused);
                    rec.into_trace()
                }
            },
            Method::MollerTrumbore
            | Method::Plane
            | Method::NormalEquations
            | Method::Inverse
            | Method::Watertight
            | Method::WatertightExact => {
                let mut rec = Recorder::new(self.name(), F::PRECISION);
                for (id, v) in ["A", "B", "C", "L", "D"].into_iter().zip([
                    &case.tri[0],
                    &case.tri[1],
                    &case.tri[2],
                    &case.origin,
                    &case.dir,
                ]) {
                    record::vector(&mut rec, id, id, "An input, in this precision.", v);
                }
                match self {
                    Method::MollerTrumbore => moller_trumbore::intersect_recorded(case, &mut rec),
                    Method::Plane => plane::intersect_recorded(case, &mut rec),
                    Method::NormalEquations => normal_equations::intersect_recorded(case, &mut rec),
                    Method::Inverse => inverse::intersect_recorded(case, &mut rec),
                    _ => watertight::intersect_recorded(case, &mut rec),
                };
                rec.into_trace()
            }
        }
    }
}

impl std::str::FromStr for Method {
    type Err = crate::names::UnknownName;
    fn from_str(text: &str) -> Result<Method, Self::Err> {
        crate::names::parse("method", text)
    }
}

pub use inverse::InverseSolve;

/// The exact reference on the very numbers a float case holds: (t, β, γ) as exact rationals.
pub fn exact_answer<F: Float>(case: &Case<F>) -> Answer<Exact> {
    let Some(problem) = exact_problem(case) else {
        return Answer {
            invalid_input: true,
            ..Answer::miss()
        };
    };
    let solved = triangle::solve(&problem, &mut ());
    Answer {
        hit: solved.outcome.is_hit(),
        values: solved.solution.map(|s| [s.t, s.beta, s.gamma]),
        exact_fallback: false,
        invalid_input: false,
    }
}

/// The case as the lecture's problem in exact arithmetic, on the exact values of its floats (t_min = 0);
/// `None` if a coordinate is NaN or infinite.
pub fn exact_problem<F: Float>(case: &Case<F>) -> Option<RayTriangle<Exact>> {
    let e = |v: &V3<F>| -> Option<V3<Exact>> {
        Some([
            Exact::from_f64(v[0].to_f64())?,
            Exact::from_f64(v[1].to_f64())?,
            Exact::from_f64(v[2].to_f64())?,
        ])
    };
    Some(RayTriangle {
        a: e(&case.tri[0])?,
        b: e(&case.tri[1])?,
        c: e(&case.tri[2])?,
        origin: e(&case.origin)?,
        dir: e(&case.dir)?,
        t_min: Exact::from_int(0),
    })
}

/// True if every coordinate of the case is finite.
pub fn finite<F: Float>(case: &Case<F>) -> bool {
    case.tri
        .iter()
        .chain([&case.origin, &case.dir])
        .all(|v| v.iter().all(|x| x.is_finite()))
}

/// The lecture's inclusive test on computed barycentrics and t (t_min = 0, open). A t that
/// overflowed the precision (∞, when the true t may well fit) is no hit: the method cannot say.
pub fn decide<F: Float>(t: F, beta: F, gamma: F) -> bool {
    let zero = F::zero();
    beta >= zero && gamma >= zero && beta + gamma <= F::one() && t > zero && t.is_finite()
}

/// Recording helpers shared by the methods: a vector, a scalar, and the closing checks and verdict.
pub(crate) mod record {
    use super::{Answer, Float};
    use crate::math::linalg::V3;
    use crate::trace::{Check, Number, Payload, Scalar, Status, Step, StepSink, Vector, Verdict};

    /// Records a named vector.
    #[inline(always)]
    pub fn vector<F: Float>(rec: &mut impl StepSink, id: &str, title: &str, note: &str, v: &V3<F>) {
        rec.push(|| Step::new(id, title, note, Payload::Vector(Vector::of(id, id, v))));
    }

    /// Records a named scalar.
    #[inline(always)]
    pub fn scalar<F: Float>(
        rec: &mut impl StepSink,
        id: &str,
        title: &str,
        note: &str,
        symbol: &str,
        value: F,
    ) {
        rec.push(|| {
            Step::new(
                id,
                title,
                note,
                Payload::Scalar(Scalar {
                    symbol: symbol.into(),
                    latex: latex_symbol(symbol),
                    formula: None,
                    value: Number::of(&value),
                    closed_form: None,
                }),
            )
        });
    }

    /// The LaTeX for a symbol the methods use (Greek letters and products spelled out).
    fn latex_symbol(symbol: &str) -> String {
        symbol
            .replace('β', "\\beta ")
            .replace('γ', "\\gamma ")
            .replace('α', "\\alpha ")
            .replace('·', " \\cdot ")
            .trim()
            .to_string()
    }

    /// Records the checks and the verdict of an answer, and returns it (every method ends with this).
    #[inline(always)]
    pub fn finish<F: Float>(rec: &mut impl StepSink, answer: Answer<F>) -> Answer<F> {
        outcome(rec, &answer);
        answer
    }

    /// Records the lecture's four checks on the method's values, and the verdict.
    #[inline(always)]
    pub fn outcome<F: Float>(rec: &mut impl StepSink, answer: &Answer<F>) {
        if !rec.is_recording() {
            return;
        }
        if let Some([t, beta, gamma]) = answer.values {
            let zero = F::zero();
            let checks = [
                ("check_ca", "β ≥ 0", "\\beta \\ge 0", beta, beta >= zero),
                ("check_ab", "γ ≥ 0", "\\gamma \\ge 0", gamma, gamma >= zero),
                (
                    "check_bc",
                    "β + γ ≤ 1",
                    "\\beta + \\gamma \\le 1",
                    beta + gamma,
                    beta + gamma <= F::one(),
                ),
                ("check_t", "t > 0", "t > 0", t, t > zero),
            ];
            for (id, text, latex, value, passed) in checks {
                rec.push(|| {
                    Step::new(
                        id,
                        format!("Check {text}"),
                        "Computed by this method, in its precision.",
                        Payload::Check(Check {
                            inequality: text.into(),
                            latex: latex.into(),
                            value: Number::of(&value),
                            passed,
                            meaning: "this inequality fails".into(),
                        }),
                    )
                });
            }
        }
        let overflowed = answer
            .values
            .is_some_and(|v| v.iter().any(|x| !x.is_finite()));
        let how = if answer.invalid_input {
            "the input is outside the method's range (NaN or infinite): a miss"
        } else if overflowed {
            "a value overflowed this precision (t, β or γ is not a finite number): the method cannot \
             decide, so it reports no hit"
        } else if answer.exact_fallback {
            "decided in exact arithmetic: a value was within its rounding bound of zero"
        } else if answer.values.is_none() {
            "rejected before solving (a zero determinant or direction)"
        } else {
            "decided in floating point"
        };
        rec.push(|| {
            Step::new(
                "verdict",
                "Verdict",
                how,
                Payload::Verdict(Verdict {
                    status: if answer.hit {
                        Status::Hit
                    } else {
                        Status::Miss
                    },
                    message: how.into(),
                }),
            )
        });
    }
}

#[cfg(test)]
mod tests {
    use super::{Case, Method};

    #[test]
    fn a_t_that_overflows_f32_is_no_hit_and_the_verdict_says_so() {
        // The true t = 10^18 fits in f32, but Möller–Trumbore's e2 · q = 10^56 does not: t = ∞.
        let case = Case::<f32> {
            tri: [[0.0, 0.0, 0.0], [1e19, 0.0, 0.0], [0.0, 1e19, 0.0]],
            origin: [0.1, 0.1, 1e18],
            dir: [0.0, 0.0, -1.0],
        };
        let answer = Method::MollerTrumbore.run(&case);
        assert!(!answer.hit, "{answer:?}");
        assert!(answer.values.is_some_and(|[t, _, _]| t.is_infinite()));
        let trace = Method::MollerTrumbore.trace(&case);
        let message = &trace.verdict().expect("a verdict").message;
        assert!(message.contains("overflowed this precision"), "{message}");
    }
}
