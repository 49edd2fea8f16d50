//! The lecture's worked examples, with their exact answers (seeds 000, 001 and 003).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{DVec2, DVec3};
use raylab::geometry::parallelogram::{ParallelogramOutcome, RayParallelogram};
use raylab::geometry::segments::{self, SegmentPair, SegmentsOutcome};
use raylab::geometry::triangle::{self, Edge, RayTriangle, TriangleMiss, TriangleOutcome};
use raylab::geometry::{Lecture, ParallelogramLecture, Real, SegmentsLecture, TriangleLecture};
use raylab::intersect::Case;
use raylab::math::exact::Exact;
use raylab::trace::Trace;

fn q(text: &str) -> Exact {
    text.parse().unwrap()
}

fn exact_segments(points: [[f64; 2]; 4]) -> (segments::SegmentsSolution<Exact>, Trace) {
    let pair = SegmentPair::read(
        raylab::geometry::Reading::FloatValue,
        points.map(DVec2::from_array),
    )
    .unwrap();
    SegmentsLecture::traced(&pair)
}

fn triangle_in<R: Real>(v: [[f64; 3]; 5]) -> (triangle::TriangleSolution<R>, Trace) {
    let problem = RayTriangle::<R>::read(
        raylab::geometry::Reading::FloatValue,
        v.map(DVec3::from_array),
        0.0,
    )
    .unwrap();
    TriangleLecture::traced(&problem)
}

/// The lecture's triangle (3,0,0), (0,3,0), (0,0,3) and a ray from the origin along `dir`.
fn lecture_along(dir: [f64; 3]) -> [[f64; 3]; 5] {
    Case {
        dir,
        ..Case::LECTURE
    }
    .vectors()
}

#[test]
fn seed000_segments_meet_at_17_22_and_21_22() {
    let (solved, trace) = exact_segments([[1.0, 2.0], [6.0, 1.0], [2.0, 6.0], [5.0, 1.0]]);
    assert_eq!(solved.outcome, SegmentsOutcome::Crossing);
    assert_eq!(solved.t, Some(q("17/22")));
    assert_eq!(solved.s, Some(q("21/22")));
    assert_eq!(solved.point, Some([q("107/22"), q("27/22")]));
    // The trace shows the Cramer quotients with the determinants 17, 21 and 22.
    assert_eq!(
        trace.scalar("t").unwrap().value.exact.as_deref(),
        Some("17/22")
    );
    assert_eq!(
        trace.scalar("s").unwrap().value.exact.as_deref(),
        Some("21/22")
    );
    let text = raylab::trace::to_text(&trace);
    assert!(text.contains("t = |M1| / |M| = 17 / 22 = 17/22"), "{text}");
    assert!(text.contains("s = |M2| / |M| = 21 / 22 = 21/22"), "{text}");
}

#[test]
fn seed000_first_segments_do_not_meet_and_say_why() {
    // A = (1,1)-(6,3), B = (2,6)-(4,3): the lines cross at t = 13/19, s = 23/19 > 1.
    let (solved, trace) = exact_segments([[1.0, 1.0], [6.0, 3.0], [2.0, 6.0], [4.0, 3.0]]);
    assert_eq!(
        solved.outcome,
        SegmentsOutcome::LinesCrossOutside {
            t_outside: false,
            s_outside: true
        }
    );
    assert_eq!(solved.t, Some(q("13/19")));
    assert_eq!(solved.s, Some(q("23/19")));
    let verdict = trace.verdict().unwrap().message.clone();
    assert!(verdict.contains("s = 23/19 is outside [0, 1]"), "{verdict}");
}

#[test]
fn seed000_lecture_triangle_gives_thirds_and_t_one() {
    let (solved, trace) = triangle_in::<Exact>(lecture_along([1.0, 1.0, 1.0]));
    assert_eq!(solved.outcome, TriangleOutcome::Hit);
    let s = solved.solution.unwrap();
    assert_eq!((s.beta, s.gamma, s.t), (q("1/3"), q("1/3"), q("1")));
    assert_eq!(s.alpha, q("1/3"));
    assert_eq!(s.point, [q("1"), q("1"), q("1")]);
    // The lecture prints t = √3: that is the distance t·|D|, while t itself is 1.
    assert_eq!(s.distance_exact.unwrap().full(), "√3");
    assert!((s.distance - 3f64.sqrt()).abs() < 1e-15);
    for id in [
        "system", "M", "Y", "M1", "M2", "M3", "det_M", "det_M1", "det_M2", "det_M3", "beta",
        "gamma", "t", "alpha", "check_ca", "check_ab", "check_bc", "check_t", "verdict", "point",
        "distance",
    ] {
        assert!(trace.step(id).is_some(), "the trace has no step {id}");
    }
    assert_eq!(trace.checks().filter(|c| c.passed).count(), 6);
}

/// Seed 000's three alternatives: (L, D, β, γ, t, α).
#[test]
fn seed000_three_alternatives() {
    let big = [[6.0, 0.0, 0.0], [0.0, 6.0, 0.0], [0.0, 0.0, 6.0]];
    let cases = [
        ([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], "1/3", "1/3", "1", "1/3"),
        ([1.0, 1.0, 1.0], [1.0, 0.0, 0.0], "1/6", "1/6", "3", "2/3"),
        // Through the midpoint of edge BC: β + γ = 1 exactly, which still counts as a hit.
        ([0.0, 0.0, 0.0], [0.0, 1.0, 1.0], "1/2", "1/2", "3", "0"),
    ];
    for (origin, dir, beta, gamma, t, alpha) in cases {
        let (solved, _) = triangle_in::<Exact>([big[0], big[1], big[2], origin, dir]);
        assert_eq!(
            solved.outcome,
            TriangleOutcome::Hit,
            "L={origin:?} D={dir:?}"
        );
        let s = solved.solution.unwrap();
        assert_eq!(
            [s.beta, s.gamma, s.t, s.alpha],
            [q(beta), q(gamma), q(t), q(alpha)]
        );
        // The float run agrees on these small integer inputs.
        let (float, _) = triangle_in::<f64>([big[0], big[1], big[2], origin, dir]);
        assert!(float.outcome.is_hit());
    }
}

#[test]
fn seed003_ray_hits_at_its_printed_point() {
    let (float, _) = triangle_in::<f64>(Case::SEED003.vectors());
    assert!(float.outcome.is_hit());
    let p = float.solution.unwrap().point;
    let printed = [0.11842105, 0.11842105, 1.18421053];
    for (got, want) in p.iter().zip(printed) {
        assert!((got - want).abs() < 5e-9, "{p:?}");
    }
    // Exactly (with 0.1 read as the float it is), the point is close to (9/76, 9/76, 45/38);
    // reading 0.1 as 1/10 it is exactly that.
    let tenth = q("1/10");
    let problem = RayTriangle {
        a: [q("0"), q("1"), q("3/2")],
        b: [q("1"), q("0"), q("5/4")],
        c: [q("-1"), q("0"), q("1")],
        origin: [q("0"), q("0"), q("0")],
        dir: [tenth.clone(), tenth, q("1")],
        t_min: q("0"),
    };
    let exact = triangle::solve(&problem, &mut ()).solution.unwrap();
    assert_eq!(exact.point, [q("9/76"), q("9/76"), q("45/38")]);
    assert_eq!(exact.t, q("45/38"));
}

#[test]
fn seed001_parallelogram_by_inverse() {
    let problem = RayParallelogram::<Exact>::read(
        raylab::geometry::Reading::FloatValue,
        [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
            [0.0, 0.0, -1.0],
        ]
        .map(DVec3::from_array),
    )
    .unwrap();
    let (solved, trace) = ParallelogramLecture::traced(&problem);
    assert_eq!(solved.outcome, ParallelogramOutcome::Hit);
    assert_eq!(solved.alpha_beta_t, Some([q("1/4"), q("1/2"), q("1")]));
    for id in ["system", "det_M", "adj_M", "inverse", "product", "check_t"] {
        assert!(trace.step(id).is_some(), "no step {id}");
    }
    // M⁻¹ = adj(M) / |M| holds in the recorded numbers: |M| = 2 here.
    let latex = raylab::trace::to_latex(&trace);
    assert!(
        latex.contains("M^{-1} = \\begin{bmatrix} \\frac{1}{2} & 0 & 0"),
        "{latex}"
    );
}

#[test]
fn misses_name_the_edge() {
    let cases = [
        ([1.0, 1.0, -0.5], vec![Edge::Ab]),
        ([1.0, -0.5, 1.0], vec![Edge::Ca]),
        ([-0.5, 1.0, 1.0], vec![Edge::Bc]),
        ([-1.0, 1.0, 1.0], vec![Edge::Bc]),
        ([3.0, -1.0, -1.0], vec![Edge::Ca, Edge::Ab]),
    ];
    for (dir, edges) in cases {
        let (solved, _) = triangle_in::<Exact>(lecture_along(dir));
        let expected = TriangleOutcome::Miss(TriangleMiss::Outside {
            edges: edges.clone(),
        });
        assert_eq!(solved.outcome, expected, "D = {dir:?}");
    }
}
