//! Seeded problems with readable answers: the answer is planned first (β = i/d, γ = j/d, a point on a
//! segment at t = i/d …), integer inputs are built around it, and then the exact solver is run on them.
//! Only the solver's answer is kept, and a candidate is drawn again unless the solver finds the planned
//! level, every answer has a denominator of at most [`MAX_DENOMINATOR`] and every input is small.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

use super::{Inputs, Kind, Level, Problem};
use crate::math::exact::Exact;

/// The most problems one call makes (a worksheet of more is not a worksheet).
pub const MAX_COUNT: usize = 100;
/// Every answer is a fraction whose denominator is at most this.
pub const MAX_DENOMINATOR: i64 = 12;
/// Every answer is at most this in size.
const LARGEST_ANSWER: i64 = 12;
/// Every input coordinate is an integer at most this in size.
const LARGEST_INPUT: i64 = 9;
/// Candidates drawn per problem before giving up (in practice a handful suffice).
const ATTEMPTS: usize = 10_000;

type V3 = [i64; 3];

/// Why no problems came out.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GenerateError {
    /// A count outside 1 ..= MAX_COUNT.
    #[error("the count must be 1 to {MAX_COUNT}, not {0}")]
    Count(usize),
    /// A level the kind has no problems of (segments are never `behind`).
    #[error("{} problems have no level {level}", .kind.name())]
    NoSuchLevel {
        /// The view's kind.
        kind: Kind,
        /// The level asked for.
        level: Level,
    },
    /// Every attempt failed the readability filters.
    #[error("found no readable {} problem at level {level} (this is a bug)", .kind.name())]
    NoneFound {
        /// The view's kind.
        kind: Kind,
        /// The level asked for.
        level: Level,
    },
}

/// `count` problems (1 ≤ count ≤ [`MAX_COUNT`]) from `seed`, all of `level` or, without one, the
/// levels in turn; the solver of each is drawn among those with that outcome. The same arguments
/// always give the same problems.
pub fn generate(
    seed: u64,
    count: usize,
    level: Option<Level>,
) -> Result<Vec<Problem>, GenerateError> {
    if count == 0 || count > MAX_COUNT {
        return Err(GenerateError::Count(count));
    }
    let mut rng = Pcg64::seed_from_u64(seed);
    (0..count)
        .map(|index| {
            let level = level.unwrap_or(Level::ALL[index % Level::ALL.len()]);
            let kinds = level.kinds();
            let kind = kinds[rng.random_range(0..kinds.len())];
            one_problem(&mut rng, index + 1, kind, level)
        })
        .collect()
}

/// One problem for the `kind` view at `level` (the app's exercises): the same seed gives the same one.
pub fn problem_for(seed: u64, kind: Kind, level: Level) -> Result<Problem, GenerateError> {
    if !level.kinds().contains(&kind) {
        return Err(GenerateError::NoSuchLevel { kind, level });
    }
    one_problem(&mut Pcg64::seed_from_u64(seed), 1, kind, level)
}

fn one_problem(
    rng: &mut Pcg64,
    number: usize,
    kind: Kind,
    level: Level,
) -> Result<Problem, GenerateError> {
    for _ in 0..ATTEMPTS {
        let candidate = match kind {
            Kind::Segments => segments(rng, level),
            Kind::Triangle => triangle(rng, level),
            Kind::Parallelogram => parallelogram(rng, level),
        };
        if let Some(problem) = candidate
            .filter(small_inputs)
            .and_then(|inputs| Problem::new(number, inputs))
            .filter(|p| p.level() == level && readable(p))
        {
            return Ok(problem);
        }
    }
    Err(GenerateError::NoneFound { kind, level })
}

fn small_inputs(inputs: &Inputs) -> bool {
    let bound = Exact::from_int(LARGEST_INPUT);
    inputs
        .named()
        .iter()
        .flat_map(|input| &input.value)
        .all(|x| x.abs() <= bound)
}

/// Every answer a short fraction: denominator at most [`MAX_DENOMINATOR`], size at most 12.
fn readable(problem: &Problem) -> bool {
    let bound = Exact::from_int(LARGEST_ANSWER);
    let small_denominator = Exact::from_int(MAX_DENOMINATOR);
    problem.answer.values.iter().all(|v| {
        let denominator = Exact(num_rational::BigRational::from_integer(
            v.value.0.denom().clone(),
        ));
        v.value.abs() <= bound && denominator <= small_denominator
    })
}

fn exact<const N: usize>(v: [i64; N]) -> [Exact; N] {
    v.map(Exact::from_int)
}

fn random<const N: usize>(rng: &mut Pcg64, size: i64) -> [i64; N] {
    std::array::from_fn(|_| rng.random_range(-size..=size))
}

fn sub<const N: usize>(a: [i64; N], b: [i64; N]) -> [i64; N] {
    std::array::from_fn(|i| a[i] - b[i])
}

fn add<const N: usize>(a: [i64; N], b: [i64; N]) -> [i64; N] {
    std::array::from_fn(|i| a[i] + b[i])
}

fn scale<const N: usize>(k: i64, a: [i64; N]) -> [i64; N] {
    a.map(|x| k * x)
}

fn gcd(a: i64, b: i64) -> i64 {
    if b == 0 { a.abs() } else { gcd(b, a % b) }
}

/// `v = g · w` with `w` primitive (its components share no factor); `None` for the zero vector.
fn primitive<const N: usize>(v: [i64; N]) -> Option<(i64, [i64; N])> {
    let g = v.iter().fold(0, |g, &x| gcd(g, x));
    (g != 0).then(|| (g, v.map(|x| x / g)))
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A nonzero multiplier in ±1..=±3 with the sign asked for.
fn multiplier(rng: &mut Pcg64, negative: bool) -> i64 {
    let k = rng.random_range(1..=3);
    if negative { -k } else { k }
}

/// A multiplier that keeps a collinear point off the two it is collinear with: −2, −1 or 2.
fn flat_multiplier(rng: &mut Pcg64) -> i64 {
    [-2, -1, 2][rng.random_range(0..3)]
}

/// Two planned coordinates `i/d`, `j/d` of a point in a triangle's or a parallelogram's plane, in the
/// region the level asks for; `edge` picks one of [`Kind::edges`] for `outside`.
fn plan(rng: &mut Pcg64, kind: Kind, level: Level) -> (i64, i64, i64) {
    let d = rng.random_range(3..=6);
    let edge = rng.random_range(0..kind.edges().len());
    loop {
        let (i, j) = (rng.random_range(-d..=2 * d), rng.random_range(-d..=2 * d));
        let in_unit = |x: i64| 0 < x && x < d;
        let inside = match kind {
            Kind::Triangle => i > 0 && j > 0 && i + j < d,
            _ => in_unit(i) && in_unit(j),
        };
        let wanted = match (level, kind) {
            (Level::Outside, Kind::Triangle) => match edge {
                0 => j < 0 && i > 0 && i < d,     // AB: γ < 0
                1 => i > 0 && j > 0 && i + j > d, // BC: β + γ > 1
                _ => i < 0 && j > 0 && j < d,     // CA: β < 0
            },
            (Level::Outside, _) => match edge {
                0 => i < 0 && in_unit(j),
                1 => i > d && in_unit(j),
                2 => j < 0 && in_unit(i),
                _ => j > d && in_unit(i),
            },
            _ => inside,
        };
        if wanted {
            return (i, j, d);
        }
    }
}

/// A ray from `origin` through the point `scaled / d`: (direction, the planned t's sign is that of
/// `behind`). `None` when the point is the origin.
fn ray_through(rng: &mut Pcg64, origin: V3, scaled: V3, d: i64, behind: bool) -> Option<V3> {
    let (_, w) = primitive(sub(scaled, scale(d, origin)))?;
    Some(scale(multiplier(rng, behind), w))
}

fn triangle(rng: &mut Pcg64, level: Level) -> Option<Inputs> {
    let (a, b) = (random::<3>(rng, 3), random::<3>(rng, 3));
    let mut c = random::<3>(rng, 3);
    let origin = random::<3>(rng, 4);
    let dir = match level {
        Level::Parallel => {
            let (i, j) = (rng.random_range(-2..=2), rng.random_range(-2..=2));
            primitive(add(scale(i, sub(b, a)), scale(j, sub(c, a))))?.1
        }
        Level::Degenerate => {
            // C on the line AB, apart from A and B: the edges are there, the area is not.
            if a == b {
                return None;
            }
            c = add(a, scale(flat_multiplier(rng), sub(b, a)));
            random::<3>(rng, 3)
        }
        _ => {
            let (i, j, d) = plan(rng, Kind::Triangle, level);
            // d·P = d·A + i(B − A) + j(C − A).
            let scaled = add(scale(d, a), add(scale(i, sub(b, a)), scale(j, sub(c, a))));
            ray_through(rng, origin, scaled, d, level == Level::Behind)?
        }
    };
    if level != Level::Degenerate && cross(sub(b, a), sub(c, a)) == [0; 3] {
        return None;
    }
    Some(Inputs::Triangle([a, b, c, origin, dir].map(exact)))
}

fn parallelogram(rng: &mut Pcg64, level: Level) -> Option<Inputs> {
    let corner = random::<3>(rng, 3);
    let e1 = random::<3>(rng, 3);
    let mut e2 = random::<3>(rng, 3);
    let origin = random::<3>(rng, 4);
    let dir = match level {
        Level::Parallel => {
            let (i, j) = (rng.random_range(-2..=2), rng.random_range(-2..=2));
            primitive(add(scale(i, e1), scale(j, e2)))?.1
        }
        Level::Degenerate => {
            // e2 along e1 (both nonzero): the edges are there, the area is not.
            if e1 == [0; 3] {
                return None;
            }
            e2 = scale(flat_multiplier(rng), e1);
            random::<3>(rng, 3)
        }
        _ => {
            let (i, j, d) = plan(rng, Kind::Parallelogram, level);
            // d·P = d·c + i·e1 + j·e2.
            let scaled = add(scale(d, corner), add(scale(i, e1), scale(j, e2)));
            ray_through(rng, origin, scaled, d, level == Level::Behind)?
        }
    };
    if level != Level::Degenerate && cross(e1, e2) == [0; 3] {
        return None;
    }
    Some(Inputs::Parallelogram(
        [corner, e1, e2, origin, dir].map(exact),
    ))
}

fn segments(rng: &mut Pcg64, level: Level) -> Option<Inputs> {
    let a1 = random::<2>(rng, 4);
    let a2 = random::<2>(rng, 4);
    let b1 = random::<2>(rng, 4);
    let b2 = match level {
        Level::Parallel => {
            let negative = rng.random_bool(0.5);
            add(
                b1,
                scale(multiplier(rng, negative), primitive(sub(a2, a1))?.1),
            )
        }
        Level::Degenerate => b1,
        _ => {
            let d = rng.random_range(2..=6);
            // Which segment misses the crossing, for `outside`: 0 for A, 1 for B.
            let misses = (level == Level::Outside).then(|| rng.random_range(0..2));
            let i = if misses == Some(0) {
                if rng.random_bool(0.5) {
                    rng.random_range(-d..=-1)
                } else {
                    rng.random_range(d + 1..=2 * d)
                }
            } else {
                rng.random_range(1..d)
            };
            // d·P = d·A1 + i(A2 − A1); B2 = B1 + k·w with d(P − B1) = g·w, so s = g / (d·k).
            let scaled = add(scale(d, a1), scale(i, sub(a2, a1)));
            let (g, w) = primitive(sub(scaled, scale(d, b1)))?;
            let k = if misses == Some(1) {
                if g > d && rng.random_bool(0.5) {
                    1
                } else {
                    -rng.random_range(1..=2)
                }
            } else {
                g / d + rng.random_range(1..=2)
            };
            add(b1, scale(k, w))
        }
    };
    Some(Inputs::Segments([a1, a2, b1, b2].map(exact)))
}
