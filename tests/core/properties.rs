//! Property tests: the float solvers against the exact solver on the very same inputs.
//!
//! The bound. Cramer's rule computes each determinant by a first-row cofactor expansion of entries
//! that are themselves rounded differences (A − B, …). Counting roundings (one per entry, two per
//! product, one per subtraction and addition), every term carries at most 8 of them, so
//!     |fl(|X|) − |X||  ≤  E(X) = γ₈ · perm(|X|)  ≈  4ε · perm(|X|),
//! where perm(|X|) is the permanent of the entries' absolute values (the sum of |products|) and
//! ε is the machine epsilon (2u). A quotient β = |M1| / |M| then satisfies
//!     |β̂ − β|  ≤  (E(M1) + |β|·E(M)) / (||M|| − E(M))  +  ε|β|,
//! and likewise for γ, t (and for t, s of segments, with 2x2 determinants). The tests check this
//! bound on every random case where it is meaningful (E(M) < ||M|| / 2), and that the float
//! classification equals the exact one whenever every tested quantity is farther from its boundary
//! than its error bound.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use raylab::geometry::Real;
use raylab::geometry::segments::{self, SegmentPair};
use raylab::geometry::triangle::{self, RayTriangle};
use raylab::math::exact::Exact;
use raylab::math::linalg::{M2, M3, V3, cross, from_columns, norm_f64, sub, with_column};

/// γ₈ = 8u/(1 − 8u) with u = ε/2, rounded up generously.
fn gamma8(eps: f64) -> f64 {
    4.0 * eps * (1.0 + 1e-6)
}

fn perm3(m: &M3<Exact>) -> f64 {
    let a = |i: usize, j: usize| m[i][j].to_f64().abs();
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    perms
        .iter()
        .map(|p| a(0, p[0]) * a(1, p[1]) * a(2, p[2]))
        .sum()
}

fn perm2(m: &M2<Exact>) -> f64 {
    let a = |i: usize, j: usize| m[i][j].to_f64().abs();
    a(0, 0) * a(1, 1) + a(0, 1) * a(1, 0)
}

/// The error bound of a Cramer quotient x = det_i / det.
fn quotient_bound(x: f64, err_i: f64, err: f64, det: f64, eps: f64) -> f64 {
    (err_i + x.abs() * err) / (det.abs() - err) + eps * x.abs()
}

fn to_exact<const N: usize>(v: &[f64; N]) -> [Exact; N] {
    v.map(|x| Exact::from_f64(x).unwrap())
}

/// Inputs: a triangle, an origin, and a target point in the triangle's plane at barycentric (β, γ)
/// drawn around [0, 1] so that many rays pass near the edges.
fn triangle_case() -> impl Strategy<Value = [[f64; 3]; 5]> {
    let point = || prop::array::uniform3(-10.0f64..10.0);
    (
        point(),
        point(),
        point(),
        point(),
        -0.2f64..1.2,
        -0.2f64..1.2,
        0.1f64..3.0,
    )
        .prop_map(|(a, b, c, origin, beta, gamma, reach)| {
            let target: [f64; 3] =
                std::array::from_fn(|i| a[i] + beta * (b[i] - a[i]) + gamma * (c[i] - a[i]));
            let dir = std::array::from_fn(|i| (target[i] - origin[i]) / reach);
            [a, b, c, origin, dir]
        })
}

/// Rounds every coordinate to f32, so that an f32 run and the exact judge see the same numbers.
fn round_to_f32(v: [[f64; 3]; 5]) -> [[f64; 3]; 5] {
    v.map(|p| p.map(|x| x as f32 as f64))
}

/// Checks one float precision against the exact solver; returns false if the case was skipped.
fn check_triangle<R: Real>(v: [[f64; 3]; 5], eps: f64) -> Result<bool, TestCaseError> {
    let problem_exact = RayTriangle {
        a: to_exact(&v[0]),
        b: to_exact(&v[1]),
        c: to_exact(&v[2]),
        origin: to_exact(&v[3]),
        dir: to_exact(&v[4]),
        t_min: Exact::from_int(0),
    };
    let exact = triangle::solve(&problem_exact, &mut ());
    let Some(x) = exact.solution else {
        return Ok(false);
    };
    let p = &problem_exact;
    let (a_b, a_c, y) = (sub(&p.a, &p.b), sub(&p.a, &p.c), sub(&p.a, &p.origin));
    let m = from_columns([&a_b, &a_c, &p.dir]);
    let det = raylab::math::linalg::det3(&m).to_f64();
    let err = gamma8(eps) * perm3(&m);
    let normal: V3<Exact> = cross(&a_b, &a_c);
    let well_posed = err < det.abs() / 2.0
        && det.abs() > 32.0 * eps * norm_f64(&normal) * norm_f64(&p.dir)
        && norm_f64(&normal) > 32.0 * eps * norm_f64(&a_b) * norm_f64(&a_c);
    if !well_posed {
        return Ok(false);
    }
    let problem = RayTriangle::<R>::read(
        raylab::geometry::Reading::FloatValue,
        v.map(glam::DVec3::from_array),
        0.0,
    )
    .unwrap();
    let float = triangle::solve(&problem, &mut ());
    let Some(xf) = float.solution else {
        return Err(TestCaseError::fail(format!(
            "float found no solution for {v:?}"
        )));
    };
    let exact_values = [x.beta.to_f64(), x.gamma.to_f64(), x.t.to_f64()];
    let float_values = [xf.beta.to_f64(), xf.gamma.to_f64(), xf.t.to_f64()];
    let mut bounds = [0.0; 3];
    for i in 0..3 {
        let mi = with_column(&m, i, &y);
        let err_i = gamma8(eps) * perm3(&mi);
        bounds[i] = quotient_bound(exact_values[i], err_i, err, det, eps);
        let error = (float_values[i] - exact_values[i]).abs();
        prop_assert!(
            error <= bounds[i],
            "unknown {i}: error {error:e} > bound {:e} for {v:?}",
            bounds[i]
        );
    }
    // Away from every boundary, the decision is the exact one.
    let sum = exact_values[0] + exact_values[1];
    let sum_bound = bounds[0] + bounds[1] + eps * sum.abs();
    let clear = exact_values[0].abs() > bounds[0]
        && exact_values[1].abs() > bounds[1]
        && (1.0 - sum).abs() > sum_bound
        && exact_values[2].abs() > bounds[2];
    if clear {
        prop_assert_eq!(float.outcome, exact.outcome, "{:?}", v);
    }
    Ok(true)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn f64_cramer_triangle_is_within_the_bound(v in triangle_case()) {
        check_triangle::<f64>(v, f64::EPSILON)?;
    }

    #[test]
    fn f32_cramer_triangle_is_within_the_bound(v in triangle_case()) {
        check_triangle::<f32>(round_to_f32(v), f32::EPSILON as f64)?;
    }

    #[test]
    fn f64_cramer_segments_are_within_the_bound(
        points in prop::array::uniform4(prop::array::uniform2(-10.0f64..10.0)),
    ) {
        let pair_exact = SegmentPair {
            a1: to_exact(&points[0]), a2: to_exact(&points[1]),
            b1: to_exact(&points[2]), b2: to_exact(&points[3]),
        };
        let exact = segments::solve(&pair_exact, &mut ());
        let (Some(t), Some(s)) = (exact.t, exact.s) else { return Ok(()); };
        let p = &pair_exact;
        let (d_a, b1_b2, y) = (sub(&p.a2, &p.a1), sub(&p.b1, &p.b2), sub(&p.b1, &p.a1));
        let m = from_columns([&d_a, &b1_b2]);
        let det = raylab::math::linalg::det2(&m).to_f64();
        let eps = f64::EPSILON;
        let err = gamma8(eps) * perm2(&m);
        if err >= det.abs() / 2.0 || det.abs() <= 32.0 * eps * norm_f64(&d_a) * norm_f64(&b1_b2) {
            return Ok(());
        }
        let pair = SegmentPair::<f64>::read(raylab::geometry::Reading::FloatValue, points.map(glam::DVec2::from_array)).unwrap();
        let float = segments::solve(&pair, &mut ());
        let (tf, sf) = (float.t.unwrap(), float.s.unwrap());
        let mut bounds = [0.0; 2];
        for (i, (exact_value, float_value)) in [(t.to_f64(), tf), (s.to_f64(), sf)].into_iter().enumerate() {
            let err_i = gamma8(eps) * perm2(&with_column(&m, i, &y));
            bounds[i] = quotient_bound(exact_value, err_i, err, det, eps);
            prop_assert!((float_value - exact_value).abs() <= bounds[i]);
        }
        let margins = [t.to_f64(), 1.0 - t.to_f64(), s.to_f64(), 1.0 - s.to_f64()];
        if margins.iter().enumerate().all(|(i, m)| m.abs() > bounds[i / 2] * 2.0) {
            prop_assert_eq!(float.outcome, exact.outcome);
        }
    }
}

#[test]
fn the_properties_test_something() {
    // Guard against a generator that makes every case skip: most random cases are well posed.
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut checked = 0;
    for _ in 0..500 {
        let v = triangle_case().new_tree(&mut runner).unwrap().current();
        if check_triangle::<f64>(v, f64::EPSILON).unwrap() {
            checked += 1;
        }
    }
    assert!(checked > 400, "only {checked} of 500 cases were well posed");
}
