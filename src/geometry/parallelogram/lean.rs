//! Seed 001's parallelogram solver, lean, for the renderer (one call a ray a pixel): the very same
//! float operations as [`super::solve`] in f64 (the same generic functions, in the
//! same order), so the same (α, β, t) to the last bit, but no recorder, no outcome with its words, no
//! hit point, and it stops as soon as α or β is outside [0, 1] (such a ray cannot be a hit, nor
//! inside for the `t < 0` bug). The scenes with a floor spend most of their parallelogram time here.

use crate::geometry::negligible;
use crate::math::linalg::{
    V3, adjugate3, all_finite, cofactor_terms3, cross, dot, from_columns, is_zero_vector, neg,
    norm_f64, sub, sum_terms,
};

/// What the renderer needs from seed 001's solver for one ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inside {
    /// (α, β, t) exactly as the solver computes them.
    pub alpha_beta_t: [f64; 3],
    /// The solver's verdict is a hit (t ≥ 0).
    pub hit: bool,
}

/// (α, β, t) and the solver's verdict when the ray's line meets the parallelogram with α and β in
/// [0, 1]; `None` when the solver finds no (α, β, t) or finds them outside.
#[inline]
pub fn solve_inside(
    [corner, e1, e2]: [&V3<f64>; 3],
    origin: &V3<f64>,
    dir: &V3<f64>,
) -> Option<Inside> {
    // The solver's refusals: a non-finite input, a zero direction.
    // Written out, not as `iter().all`: LLVM left that closure out of line in the renderer's
    // parallelogram test (3% of a shadow scene's instructions).
    let finite = all_finite(corner)
        && all_finite(e1)
        && all_finite(e2)
        && all_finite(origin)
        && all_finite(dir);
    if !finite || is_zero_vector(dir) {
        return None;
    }
    let minus_d = neg(dir);
    let m = from_columns([e1, e2, &minus_d]);
    let y = sub(origin, corner);
    let normal = cross(e1, e2);
    if !all_finite(&normal) {
        return None;
    }
    let degenerate = || {
        negligible::<f64>(
            norm_f64(&normal),
            norm_f64(e1) * norm_f64(e2),
            is_zero_vector(&normal),
        )
    };
    if !surely_above(&normal, e1, e2) && degenerate() {
        return None;
    }
    let det = sum_terms(&cofactor_terms3(&m));
    if !det.is_finite() {
        return None;
    }
    let parallel = || negligible::<f64>(det.abs(), norm_f64(&normal) * norm_f64(dir), det == 0.0);
    if !surely_above(&[det, 0.0, 0.0], &normal, dir) && parallel() {
        return None;
    }
    let adjugate = adjugate3(&m);
    // Row i of M⁻¹ (o − c), as the solver's inverse (each entry divided by |M|) times o − c.
    let row = |i: usize| dot(&adjugate[i].map(|x| x / det), &y);
    let in_unit = |x: f64| (0.0..=1.0).contains(&x);
    let alpha = row(0);
    if !in_unit(alpha) {
        return None;
    }
    let beta = row(1);
    if !in_unit(beta) {
        return None;
    }
    let t = row(2);
    if !t.is_finite() {
        return None;
    }
    Some(Inside {
        alpha_beta_t: [alpha, beta, t],
        hit: t >= 0.0,
    })
}

/// The parallelogram's normal e1 × e2 when its own inputs pass the solver's refusals that do not
/// depend on the ray (finite corner and edges, a finite normal, edges surely not parallel): then
/// only the ray's checks remain for [`solve_inside`]. `None` when the solver could refuse every ray,
/// or needs its norms to decide.
#[inline]
pub fn regular_normal([corner, e1, e2]: [&V3<f64>; 3]) -> Option<V3<f64>> {
    let normal = cross(e1, e2);
    let finite = [corner, e1, e2, &normal].iter().all(|v| all_finite(v));
    (finite && surely_above(&normal, e1, e2)).then_some(normal)
}

/// True when |x| > TOLERANCE · |a| · |b| surely, without the norms' square roots: |x| ≥ max|xᵢ| and
/// |a| |b| ≤ 3 max|aᵢ| max|bᵢ|, with a factor 2 for the norms' rounding. Then the solver's
/// `negligible` check is false; otherwise the caller runs that check itself.
#[inline(always)]
fn surely_above(x: &V3<f64>, a: &V3<f64>, b: &V3<f64>) -> bool {
    let largest = |v: &V3<f64>| v[0].abs().max(v[1].abs()).max(v[2].abs());
    let product = largest(a) * largest(b);
    let bound = <f64 as crate::math::real::Real>::TOLERANCE * 6.0 * product;
    // Far from overflow (the norms' product is up to 3 times `product`) and from underflow.
    let in_range = (product * 4.0).is_finite() && bound > 1e-280;
    in_range && largest(x) > bound
}

/// Tests: a random parallelogram (c, e1, e2), a ray's origin, and a direction aimed at (α, β) that is
/// within `edge` of 0 or 1 on half of the draws (so the rays graze its edges and corners).
#[cfg(test)]
pub(crate) fn random_ray_near_edges(random: &mut rand_pcg::Pcg64, edge: f64) -> [V3<f64>; 5] {
    use rand::Rng;
    fn vector(random: &mut rand_pcg::Pcg64, r: f64) -> V3<f64> {
        std::array::from_fn(|_| random.random_range(-r..r))
    }
    let (corner, e1, e2) = (
        vector(random, 3.0),
        vector(random, 2.0),
        vector(random, 2.0),
    );
    let [origin, dir] = random_ray_at(random, [&corner, &e1, &e2], edge);
    [corner, e1, e2, origin, dir]
}

/// Tests: a ray's origin and a direction aimed at (α, β) of the parallelogram (c, e1, e2), within
/// `edge` of 0 or 1 on half of the draws.
#[cfg(test)]
pub(crate) fn random_ray_at(
    random: &mut rand_pcg::Pcg64,
    [corner, e1, e2]: [&V3<f64>; 3],
    edge: f64,
) -> [V3<f64>; 2] {
    use rand::Rng;
    let origin: V3<f64> = std::array::from_fn(|_| random.random_range(-8.0..8.0));
    let mut near_edge = || match random.random_range(0..4) {
        0 => random.random_range(-edge..edge),
        1 => 1.0 + random.random_range(-edge..edge),
        _ => random.random_range(-0.5..1.5),
    };
    let (a, b) = (near_edge(), near_edge());
    let target: V3<f64> = std::array::from_fn(|k| corner[k] + a * e1[k] + b * e2[k]);
    let dir = crate::math::linalg::sub(&target, &origin);
    [origin, dir]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::parallelogram::{RayParallelogram, solve};
    use rand::SeedableRng;

    /// The solver's answer reduced to what [`solve_inside`] gives.
    fn reference(problem: &RayParallelogram<f64>) -> Option<Inside> {
        let solution = solve(problem, &mut ());
        let [alpha, beta, t] = solution.alpha_beta_t?;
        let inside = (0.0..=1.0).contains(&alpha) && (0.0..=1.0).contains(&beta);
        inside.then_some(Inside {
            alpha_beta_t: [alpha, beta, t],
            hit: solution.outcome.is_hit(),
        })
    }

    /// Bit for bit the solver's (α, β, t) and verdict, on random parallelograms with rays aimed near
    /// their edges and corners, behind, grazing, parallel, degenerate and with non-finite inputs.
    #[test]
    fn the_lean_solver_gives_the_solvers_bits() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(2);
        let (mut inside, mut hits) = (0, 0);
        for i in 0..200_000 {
            let [corner, mut e1, e2, origin, mut dir] = random_ray_near_edges(&mut random, 1e-13);
            match i % 50 {
                0 => {
                    let n = cross(&e1, &e2);
                    dir = std::array::from_fn(|k| e1[k] + 1e-17 * n[k]);
                }
                1 => e1 = e2.map(|x| x * 3.0),
                2 => dir = [0.0; 3],
                3 => dir[1] = f64::NAN,
                4 => dir = dir.map(|x| -x),
                // Near the solver's thresholds: e1 almost parallel to e2, d almost in the plane.
                5 => e1 = std::array::from_fn(|k| 3.0 * e2[k] + 1e-14 * corner[k]),
                6 => {
                    let n = cross(&e1, &e2);
                    dir = std::array::from_fn(|k| e2[k] + 3e-15 * n[k] * (i % 7) as f64);
                }
                _ => {}
            }
            // Far from 1: where the norms' products overflow or underflow.
            let scale = match i % 9 {
                0 => 1e-150,
                1 => 1e100,
                2 => 1e153,
                _ => 1.0,
            };
            let (corner, e1, e2) = (corner.map(|x| x * scale), e1.map(|x| x * scale), e2);
            let (origin, dir) = (origin.map(|x| x * scale), dir.map(|x| x * scale));
            let problem = RayParallelogram::new([corner, e1, e2, origin, dir]);
            let expected = reference(&problem);
            let got = solve_inside([&corner, &e1, &e2], &origin, &dir);
            let bits = |x: Option<Inside>| x.map(|x| (x.alpha_beta_t.map(f64::to_bits), x.hit));
            assert_eq!(bits(got), bits(expected), "{problem:?}");
            inside += expected.is_some() as usize;
            hits += expected.is_some_and(|x| x.hit) as usize;
        }
        assert!(inside > 20_000 && hits > 10_000, "{inside} {hits}");
    }
}
