//! Exercises: seeded problems for the Segments, Triangle and Parallelogram solvers, each with its exact
//! answer and trace from the exact solver (never computed here), and a checker that reads a student's
//! answer and hints at the step that differs. Pure core: no UI crate.
//!
//! A problem belongs to a level, the outcome it teaches: `hit`, `outside` (the miss names the edge it
//! is beyond), `behind`, `parallel` or `degenerate`. Segments have no `behind` (a segment has two ends,
//! both are `outside`).

mod check;
mod generate;
mod sheet;
#[cfg(test)]
mod tests;

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use crate::geometry::parallelogram::{ParallelogramOutcome, RayParallelogram, Side};
use crate::geometry::segments::{SegmentPair, SegmentsOutcome};
use crate::geometry::triangle::{RayTriangle, TriangleMiss, TriangleOutcome};
use crate::geometry::{Lecture, ParallelogramLecture, SegmentsLecture, TriangleLecture};
use crate::math::exact::Exact;
use crate::trace::Trace;

pub use check::{AnswerError, DECIMAL_TOLERANCE, Hint, Practice, Verdict, check};
pub use generate::{GenerateError, MAX_COUNT, MAX_DENOMINATOR, generate, problem_for};
pub use sheet::{key_latex, problems_json, worksheet_latex};

/// Which solver a problem is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// Two 2D segments (seed 000).
    Segments,
    /// A ray and a triangle (seed 000).
    Triangle,
    /// A ray and a parallelogram (seed 001).
    Parallelogram,
}

impl Kind {
    /// `segments`, `triangle` or `parallelogram`, as `raylab solve` names them.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Segments => "segments",
            Kind::Triangle => "triangle",
            Kind::Parallelogram => "parallelogram",
        }
    }

    /// The unknowns a student finds, in the order the solver's trace computes them:
    /// (step id, plain symbol, LaTeX symbol). The step id is also the key in `raylab solve`'s JSON.
    pub fn unknowns(self) -> &'static [(&'static str, &'static str, &'static str)] {
        match self {
            Kind::Segments => &[("t", "t", "t"), ("s", "s", "s")],
            Kind::Triangle => &[
                ("beta", "β", "\\beta"),
                ("gamma", "γ", "\\gamma"),
                ("t", "t", "t"),
            ],
            Kind::Parallelogram => &[
                ("alpha", "α", "\\alpha"),
                ("beta", "β", "\\beta"),
                ("t", "t", "t"),
            ],
        }
    }

    /// The names of what a miss can be beyond: edges of a triangle, sides of a parallelogram (the
    /// line α = 0 …), or the segment whose parameter leaves [0, 1].
    pub fn edges(self) -> &'static [&'static str] {
        match self {
            Kind::Segments => &["A", "B"],
            Kind::Triangle => &["AB", "BC", "CA"],
            Kind::Parallelogram => &["α=0", "α=1", "β=0", "β=1"],
        }
    }
}

/// What a problem teaches: the outcome the solver finds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Level {
    /// The ray (or segment) hits inside.
    Hit,
    /// It meets the plane (or line) beyond one edge.
    Outside,
    /// Inside, but behind the ray's origin.
    Behind,
    /// Parallel to the plane (or line): no single solution.
    Parallel,
    /// The triangle, parallelogram or a segment has no extent.
    Degenerate,
}

impl Level {
    /// Every level, in teaching order.
    pub const ALL: [Level; 5] = [
        Level::Hit,
        Level::Outside,
        Level::Behind,
        Level::Parallel,
        Level::Degenerate,
    ];

    /// The word used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Level::Hit => "hit",
            Level::Outside => "outside",
            Level::Behind => "behind",
            Level::Parallel => "parallel",
            Level::Degenerate => "degenerate",
        }
    }

    /// The solvers that have this outcome (segments are never `behind`).
    pub fn kinds(self) -> &'static [Kind] {
        match self {
            Level::Behind => &[Kind::Triangle, Kind::Parallelogram],
            _ => &[Kind::Segments, Kind::Triangle, Kind::Parallelogram],
        }
    }
}

/// A level word that names no level.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown level '{0}' (expected hit, outside, behind, parallel or degenerate)")]
pub struct UnknownLevel(pub String);

impl FromStr for Level {
    type Err = UnknownLevel;

    fn from_str(text: &str) -> Result<Level, UnknownLevel> {
        let word = text.trim().to_ascii_lowercase();
        Level::ALL
            .into_iter()
            .find(|level| level.name() == word)
            .ok_or_else(|| UnknownLevel(text.to_string()))
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The outcome of a problem, as a student names it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "outcome", rename_all = "kebab-case")]
pub enum Outcome {
    /// A hit (segments: they cross).
    Hit,
    /// A miss beyond one edge (one of [`Kind::edges`]).
    Outside {
        /// The edge's name: `BC`, `α=1`, `A`.
        beyond: String,
    },
    /// Inside, but behind the origin.
    Behind,
    /// Parallel: |M| = 0.
    Parallel,
    /// No area (or a segment of no length).
    Degenerate,
}

impl Outcome {
    /// The level this outcome belongs to.
    pub fn level(&self) -> Level {
        match self {
            Outcome::Hit => Level::Hit,
            Outcome::Outside { .. } => Level::Outside,
            Outcome::Behind => Level::Behind,
            Outcome::Parallel => Level::Parallel,
            Outcome::Degenerate => Level::Degenerate,
        }
    }

    /// How a student writes it: `hit`, `outside BC`, `behind` …
    pub fn text(&self) -> String {
        match self {
            Outcome::Outside { beyond } => format!("outside {beyond}"),
            other => other.level().name().into(),
        }
    }
}

/// A problem's inputs, exact (small integers by construction). Triangles take t_min = 0.
#[derive(Clone, Debug, PartialEq)]
pub enum Inputs {
    /// A1, A2, B1, B2.
    Segments([[Exact; 2]; 4]),
    /// A, B, C, L (origin), D (direction).
    Triangle([[Exact; 3]; 5]),
    /// c (corner), e1, e2, o (origin), d (direction).
    Parallelogram([[Exact; 3]; 5]),
}

/// One named input: its lecture name, LaTeX name, `raylab solve` flag and coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    /// `A1`, `L`, `e1` …
    pub name: &'static str,
    /// `A_1`, `L`, `e_1` …
    pub latex: &'static str,
    /// The flag of `raylab solve`, without dashes: `a1`, `origin`, `e1` …
    pub flag: &'static str,
    /// The coordinates.
    pub value: Vec<Exact>,
}

const SEGMENT_NAMES: [(&str, &str, &str); 4] = [
    ("A1", "A_1", "a1"),
    ("A2", "A_2", "a2"),
    ("B1", "B_1", "b1"),
    ("B2", "B_2", "b2"),
];
const TRIANGLE_NAMES: [(&str, &str, &str); 5] = [
    ("A", "A", "a"),
    ("B", "B", "b"),
    ("C", "C", "c"),
    ("L", "L", "origin"),
    ("D", "D", "dir"),
];
const PARALLELOGRAM_NAMES: [(&str, &str, &str); 5] = [
    ("c", "c", "corner"),
    ("e1", "e_1", "e1"),
    ("e2", "e_2", "e2"),
    ("o", "o", "origin"),
    ("d", "d", "dir"),
];

impl Inputs {
    /// Which solver.
    pub fn kind(&self) -> Kind {
        match self {
            Inputs::Segments(_) => Kind::Segments,
            Inputs::Triangle(_) => Kind::Triangle,
            Inputs::Parallelogram(_) => Kind::Parallelogram,
        }
    }

    /// The inputs by name, in the order `raylab solve` takes them.
    pub fn named(&self) -> Vec<Input> {
        fn zip<const N: usize, const K: usize>(
            names: &[(&'static str, &'static str, &'static str); K],
            values: &[[Exact; N]; K],
        ) -> Vec<Input> {
            names
                .iter()
                .zip(values)
                .map(|(&(name, latex, flag), value)| Input {
                    name,
                    latex,
                    flag,
                    value: value.to_vec(),
                })
                .collect()
        }
        match self {
            Inputs::Segments(points) => zip(&SEGMENT_NAMES, points),
            Inputs::Triangle(vectors) => zip(&TRIANGLE_NAMES, vectors),
            Inputs::Parallelogram(vectors) => zip(&PARALLELOGRAM_NAMES, vectors),
        }
    }

    /// Runs the exact solver: the outcome (`None` for one no level teaches, such as touching
    /// segments or a point beyond two edges), the unknowns' values in [`Kind::unknowns`] order (empty
    /// when there is no single solution), and the trace.
    fn solve(&self) -> (Option<Outcome>, Vec<Exact>, Trace) {
        match self {
            Inputs::Segments(points) => solve_segments(points),
            Inputs::Triangle(vectors) => solve_triangle(vectors),
            Inputs::Parallelogram(vectors) => solve_parallelogram(vectors),
        }
    }
}

fn solve_segments([a1, a2, b1, b2]: &[[Exact; 2]; 4]) -> (Option<Outcome>, Vec<Exact>, Trace) {
    let pair = SegmentPair {
        a1: a1.clone(),
        a2: a2.clone(),
        b1: b1.clone(),
        b2: b2.clone(),
    };
    let (solved, trace) = SegmentsLecture::traced(&pair);
    let outcome = match solved.outcome {
        SegmentsOutcome::Crossing => Some(Outcome::Hit),
        SegmentsOutcome::LinesCrossOutside {
            t_outside,
            s_outside,
        } if t_outside != s_outside => Some(Outcome::Outside {
            beyond: if t_outside { "A" } else { "B" }.into(),
        }),
        SegmentsOutcome::Parallel => Some(Outcome::Parallel),
        SegmentsOutcome::DegenerateSegment { .. } => Some(Outcome::Degenerate),
        _ => None,
    };
    let values = solved.t.into_iter().chain(solved.s).collect();
    (outcome, values, trace)
}

fn solve_triangle(
    [a, b, c, origin, dir]: &[[Exact; 3]; 5],
) -> (Option<Outcome>, Vec<Exact>, Trace) {
    let problem = RayTriangle {
        a: a.clone(),
        b: b.clone(),
        c: c.clone(),
        origin: origin.clone(),
        dir: dir.clone(),
        t_min: Exact::from_int(0),
    };
    let (solved, trace) = TriangleLecture::traced(&problem);
    let outcome = match solved.outcome {
        TriangleOutcome::Hit => Some(Outcome::Hit),
        TriangleOutcome::Miss(TriangleMiss::Outside { edges }) if edges.len() == 1 => {
            Some(Outcome::Outside {
                beyond: edges[0].name().into(),
            })
        }
        TriangleOutcome::Miss(TriangleMiss::Behind) => Some(Outcome::Behind),
        TriangleOutcome::Miss(TriangleMiss::Parallel { .. }) => Some(Outcome::Parallel),
        TriangleOutcome::Miss(TriangleMiss::DegenerateTriangle) => Some(Outcome::Degenerate),
        TriangleOutcome::Miss(_) => None,
    };
    let values = solved
        .solution
        .map(|s| vec![s.beta, s.gamma, s.t])
        .unwrap_or_default();
    (outcome, values, trace)
}

fn solve_parallelogram(vectors: &[[Exact; 3]; 5]) -> (Option<Outcome>, Vec<Exact>, Trace) {
    let problem = RayParallelogram::new(vectors.clone());
    let (solved, trace) = ParallelogramLecture::traced(&problem);
    let outcome = match solved.outcome {
        ParallelogramOutcome::Hit => Some(Outcome::Hit),
        ParallelogramOutcome::Outside { sides } if sides.len() == 1 => Some(Outcome::Outside {
            beyond: side_name(sides[0]).into(),
        }),
        ParallelogramOutcome::Behind => Some(Outcome::Behind),
        ParallelogramOutcome::Parallel => Some(Outcome::Parallel),
        ParallelogramOutcome::Degenerate => Some(Outcome::Degenerate),
        _ => None,
    };
    let values = solved.alpha_beta_t.map(|x| x.to_vec()).unwrap_or_default();
    (outcome, values, trace)
}

/// The line of the parallelogram a point is beyond, named by the bound it breaks.
fn side_name(side: Side) -> &'static str {
    match side {
        Side::AlphaBelow => "α=0",
        Side::AlphaAbove => "α=1",
        Side::BetaBelow => "β=0",
        Side::BetaAbove => "β=1",
    }
}

/// One unknown of the answer with its exact value.
#[derive(Clone, Debug, PartialEq)]
pub struct Value {
    /// The solver's step id and `raylab solve`'s JSON key: `beta`, `t` …
    pub id: &'static str,
    /// `β`, `t` …
    pub symbol: &'static str,
    /// `\beta`, `t` …
    pub latex: &'static str,
    /// The exact value, as the exact solver computed it.
    pub value: Exact,
}

/// The exact answer to a problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Answer {
    /// Hit, or why not.
    pub outcome: Outcome,
    /// The unknowns, in [`Kind::unknowns`] order; empty when parallel or degenerate.
    pub values: Vec<Value>,
}

impl Answer {
    /// `hit; β = 1/4, γ = 1/2, t = 3`.
    pub fn text(&self) -> String {
        let values: Vec<String> = self
            .values
            .iter()
            .map(|v| format!("{} = {}", v.symbol, v.value.fraction()))
            .collect();
        if values.is_empty() {
            self.outcome.text()
        } else {
            format!("{}; {}", self.outcome.text(), values.join(", "))
        }
    }
}

/// A generated problem: inputs, the exact answer and the exact solver's trace.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// Its number on the sheet, from 1.
    pub number: usize,
    /// The exact inputs.
    pub inputs: Inputs,
    /// The exact answer.
    pub answer: Answer,
    /// Every step of the exact solve (the checker's hints come from here).
    pub trace: Trace,
}

impl Problem {
    /// Solves `inputs` exactly; `None` if the outcome is one no level teaches.
    pub fn new(number: usize, inputs: Inputs) -> Option<Problem> {
        let (outcome, values, trace) = inputs.solve();
        let kind = inputs.kind();
        let values = kind
            .unknowns()
            .iter()
            .zip(values)
            .map(|(&(id, symbol, latex), value)| Value {
                id,
                symbol,
                latex,
                value,
            })
            .collect();
        Some(Problem {
            number,
            answer: Answer {
                outcome: outcome?,
                values,
            },
            inputs,
            trace,
        })
    }

    /// Which solver.
    pub fn kind(&self) -> Kind {
        self.inputs.kind()
    }

    /// The level its outcome belongs to.
    pub fn level(&self) -> Level {
        self.answer.outcome.level()
    }
}
