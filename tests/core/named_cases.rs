//! Every named outcome and every kind of bad input, in every precision: the right status, a trace that
//! renders, and no panic.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{DVec2, DVec3};
use raylab::geometry::parallelogram::{self, ParallelogramOutcome, RayParallelogram};
use raylab::geometry::segments::{self, SegmentPair, SegmentsOutcome};
use raylab::geometry::triangle::{RayTriangle, TriangleOutcome};
use raylab::geometry::{Lecture, ParallelogramLecture, Real, SegmentsLecture, TriangleLecture};
use raylab::math::exact::Exact;
use raylab::trace::{Trace, to_latex, to_text};

const LECTURE: [[f64; 3]; 3] = raylab::intersect::Case::LECTURE.tri;

/// Renders a trace every way; any panic fails the test.
fn render_all(trace: &Trace) {
    assert!(!to_text(trace).is_empty());
    assert!(to_latex(trace).contains("\\["));
    assert!(serde_json::to_string(trace).is_ok());
    assert!(trace.verdict().is_some(), "every trace ends with a verdict");
}

fn triangle_status<R: Real>(v: [[f64; 3]; 5], t_min: f64) -> (&'static str, String) {
    let problem = match RayTriangle::<R>::read(
        raylab::geometry::Reading::FloatValue,
        v.map(DVec3::from_array),
        t_min,
    ) {
        Ok(problem) => problem,
        // Only the exact type refuses to convert NaN and ∞; that is the invalid-input path too.
        Err(bad) => return ("invalid-input", bad.to_string()),
    };
    let (solved, trace) = TriangleLecture::traced(&problem);
    render_all(&trace);
    (
        solved.outcome.status().word(),
        trace.verdict().unwrap().message.clone(),
    )
}

/// Runs a triangle case in all three precisions and expects the same status from each.
fn expect_triangle(v: [[f64; 3]; 5], t_min: f64, status: &str, words: &str) {
    for (precision, (got, message)) in [
        ("f32", triangle_status::<f32>(v, t_min)),
        ("f64", triangle_status::<f64>(v, t_min)),
        ("exact", triangle_status::<Exact>(v, t_min)),
    ] {
        assert_eq!(got, status, "{precision}: {message}");
        assert!(
            message.contains(words),
            "{precision}: '{message}' lacks '{words}'"
        );
    }
}

fn lecture_with(origin: [f64; 3], dir: [f64; 3]) -> [[f64; 3]; 5] {
    [LECTURE[0], LECTURE[1], LECTURE[2], origin, dir]
}

#[test]
fn triangle_named_outcomes() {
    let o = [0.0; 3];
    expect_triangle(lecture_with(o, [1.0, 1.0, 1.0]), 0.0, "hit", "hits");
    expect_triangle(
        lecture_with(o, [1.0, 1.0, -0.5]),
        0.0,
        "miss-outside",
        "edge AB",
    );
    expect_triangle(
        lecture_with(o, [-1.0, -1.0, -1.0]),
        0.0,
        "miss-behind",
        "behind",
    );
    // Parallel to the plane x + y + z = 3, off it and in it.
    expect_triangle(
        lecture_with(o, [1.0, -1.0, 0.0]),
        0.0,
        "parallel",
        "never meets",
    );
    expect_triangle(
        lecture_with([1.0, 1.0, 1.0], [1.0, -1.0, 0.0]),
        0.0,
        "parallel",
        "lies in it",
    );
    expect_triangle(
        lecture_with(o, [0.0, 0.0, 0.0]),
        0.0,
        "invalid-input",
        "zero vector",
    );
    let collinear = [
        [0.0; 3],
        [1.0, 1.0, 1.0],
        [2.0, 2.0, 2.0],
        [0.0, 0.0, 5.0],
        [1.0, 0.0, 0.0],
    ];
    expect_triangle(collinear, 0.0, "degenerate-triangle", "collinear");
    let point = [[1.0; 3], [1.0; 3], [1.0; 3], [0.0; 3], [1.0, 1.0, 1.0]];
    expect_triangle(point, 0.0, "degenerate-triangle", "no area");
}

#[test]
fn t_min_is_open() {
    // The lecture ray hits at t = 1: t_min = 1 excludes it, t_min just below keeps it.
    let v = lecture_with([0.0; 3], [1.0, 1.0, 1.0]);
    expect_triangle(v, 1.0, "miss-behind", "not greater than t_min");
    expect_triangle(v, 0.5, "hit", "t = 1");
    // A ray starting on the triangle (t = 0) does not hit it with the default t_min = 0.
    expect_triangle(
        lecture_with([1.0, 1.0, 1.0], [1.0, 1.0, 1.0]),
        0.0,
        "miss-behind",
        "t = 0",
    );
}

#[test]
fn triangle_bad_input_in_every_field() {
    for field in 0..5 {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut v = lecture_with([0.0; 3], [1.0, 1.0, 1.0]);
            v[field][1] = bad;
            expect_triangle(v, 0.0, "invalid-input", ["A", "B", "C", "L", "D"][field]);
        }
    }
    let v = lecture_with([0.0; 3], [1.0, 1.0, 1.0]);
    expect_triangle(v, f64::NAN, "invalid-input", "t_min");
}

#[test]
fn f32_overflow_is_named_not_nonsense() {
    // 1e30 is a finite f32, but the determinants (~1e90) are not: f32 says so, f64 and exact solve it.
    let v = [
        [3e30, 0.0, 0.0],
        [0.0, 3e30, 0.0],
        [0.0, 0.0, 3e30],
        [0.0; 3],
        [1.0, 1.0, 1.0],
    ];
    let (status, message) = triangle_status::<f32>(v, 0.0);
    assert_eq!(status, "invalid-input");
    assert!(message.contains("overflow f32"), "{message}");
    assert_eq!(triangle_status::<f64>(v, 0.0).0, "hit");
    assert_eq!(triangle_status::<Exact>(v, 0.0).0, "hit");
    // 1e300 does not even fit in an f32.
    let huge = [
        [1e300, 0.0, 0.0],
        LECTURE[1],
        LECTURE[2],
        [0.0; 3],
        [1.0, 1.0, 1.0],
    ];
    let (status, message) = triangle_status::<f32>(huge, 0.0);
    assert_eq!(status, "invalid-input");
    assert!(message.contains("infinite in f32"), "{message}");
}

fn segments_status<R: Real>(points: [[f64; 2]; 4]) -> segments::SegmentsSolution<R> {
    match SegmentPair::<R>::read(
        raylab::geometry::Reading::FloatValue,
        points.map(DVec2::from_array),
    ) {
        Ok(pair) => {
            let (solved, trace) = SegmentsLecture::traced(&pair);
            render_all(&trace);
            solved
        }
        Err(_) => panic!("conversion fails only for the exact type on non-finite input"),
    }
}

fn expect_segments(points: [[f64; 2]; 4], status: &str) {
    assert_eq!(
        segments_status::<f32>(points).outcome.status().word(),
        status,
        "f32"
    );
    assert_eq!(
        segments_status::<f64>(points).outcome.status().word(),
        status,
        "f64"
    );
    assert_eq!(
        segments_status::<Exact>(points).outcome.status().word(),
        status,
        "exact"
    );
}

#[test]
fn segments_named_outcomes() {
    expect_segments([[0.0, 0.0], [2.0, 2.0], [0.0, 2.0], [2.0, 0.0]], "crossing");
    // B starts on A's midpoint; A ends on B: both kinds of touching.
    expect_segments([[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 5.0]], "touching");
    expect_segments([[0.0, 0.0], [2.0, 0.0], [2.0, 0.0], [3.0, 1.0]], "touching");
    expect_segments(
        [[0.0, 0.0], [1.0, 0.0], [5.0, -1.0], [5.0, 1.0]],
        "lines-cross-outside",
    );
    expect_segments([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]], "parallel");
    expect_segments(
        [[0.0, 0.0], [4.0, 0.0], [6.0, 0.0], [2.0, 0.0]],
        "collinear-overlap",
    );
    expect_segments(
        [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]],
        "collinear-disjoint",
    );
    expect_segments(
        [[1.0, 1.0], [1.0, 1.0], [0.0, 0.0], [2.0, 2.0]],
        "degenerate-segment",
    );
}

#[test]
fn collinear_overlap_is_an_interval_of_t() {
    // A from 0 to 4 on the x axis; B from 6 back to 2: B covers t in [1/2, 3/2], so the overlap is
    // t in [1/2, 1].
    let solved = segments_status::<Exact>([[0.0, 0.0], [4.0, 0.0], [6.0, 0.0], [2.0, 0.0]]);
    let half = Exact::ratio(1, 2).unwrap();
    assert_eq!(solved.overlap, Some([half.clone(), Exact::from_int(1)]));
    assert_eq!(
        solved.t_of_b,
        Some([Exact::ratio(3, 2).unwrap(), half.clone()])
    );
    let message = solved.message();
    assert!(message.contains("t in [1/2, 1]"), "{message}");
    // Touching end to end is a one-point overlap.
    let solved = segments_status::<Exact>([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
    assert_eq!(
        solved.overlap,
        Some([Exact::from_int(1), Exact::from_int(1)])
    );
}

#[test]
fn lines_crossing_outside_say_which_parameter() {
    let solved = segments_status::<Exact>([[0.0, 0.0], [1.0, 0.0], [5.0, -1.0], [5.0, 1.0]]);
    assert_eq!(
        solved.outcome,
        SegmentsOutcome::LinesCrossOutside {
            t_outside: true,
            s_outside: false
        }
    );
    assert_eq!(solved.t, Some(Exact::from_int(5)));
    assert_eq!(solved.s, Some(Exact::ratio(1, 2).unwrap()));
}

#[test]
fn segments_bad_input() {
    for field in 0..4 {
        let mut points = [[0.0, 0.0], [2.0, 2.0], [0.0, 2.0], [2.0, 0.0]];
        points[field][0] = f64::NAN;
        for solved in [
            segments_status::<f32>(points).outcome,
            segments_status::<f64>(points).outcome,
        ] {
            assert_eq!(solved.status().word(), "invalid-input");
        }
        let converted = SegmentPair::<Exact>::read(
            raylab::geometry::Reading::FloatValue,
            points.map(DVec2::from_array),
        );
        assert_eq!(
            converted.unwrap_err().field,
            ["A1", "A2", "B1", "B2"][field]
        );
    }
}

fn parallelogram_outcome(v: [[f64; 3]; 5]) -> ParallelogramOutcome {
    let exact = RayParallelogram::<Exact>::read(
        raylab::geometry::Reading::FloatValue,
        v.map(DVec3::from_array),
    )
    .unwrap();
    let (solved, trace) = ParallelogramLecture::traced(&exact);
    render_all(&trace);
    let float = RayParallelogram::<f64>::read(
        raylab::geometry::Reading::FloatValue,
        v.map(DVec3::from_array),
    )
    .unwrap();
    assert_eq!(
        parallelogram::solve(&float, &mut ()).outcome.status(),
        solved.outcome.status()
    );
    solved.outcome
}

#[test]
fn parallelogram_named_outcomes() {
    let square =
        |origin: [f64; 3], dir: [f64; 3]| [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], origin, dir];
    let down = [0.0, 0.0, -1.0];
    assert_eq!(
        parallelogram_outcome(square([0.5, 0.5, 1.0], down)),
        ParallelogramOutcome::Hit
    );
    // Corners and edges count: α, β in the closed interval, and t = 0 is allowed (seed 001: t ≥ 0).
    assert_eq!(
        parallelogram_outcome(square([1.0, 1.0, 1.0], down)),
        ParallelogramOutcome::Hit
    );
    assert_eq!(
        parallelogram_outcome(square([0.5, 0.5, 0.0], down)),
        ParallelogramOutcome::Hit
    );
    assert_eq!(
        parallelogram_outcome(square([1.5, -0.5, 1.0], down))
            .status()
            .word(),
        "miss-outside"
    );
    assert_eq!(
        parallelogram_outcome(square([0.5, 0.5, -1.0], down)),
        ParallelogramOutcome::Behind
    );
    assert_eq!(
        parallelogram_outcome(square([0.5, 0.5, 1.0], [1.0, 1.0, 0.0])),
        ParallelogramOutcome::Parallel
    );
    assert_eq!(
        parallelogram_outcome(square([0.5, 0.5, 1.0], [0.0; 3])),
        ParallelogramOutcome::ZeroDirection
    );
    let flat = [
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        down,
    ];
    assert_eq!(
        parallelogram_outcome(flat),
        ParallelogramOutcome::Degenerate
    );
}

#[test]
fn outside_parallelogram_names_both_broken_bounds() {
    use raylab::geometry::parallelogram::Side;
    let v = [
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.5, -0.5, 1.0],
        [0.0, 0.0, -1.0],
    ];
    assert_eq!(
        parallelogram_outcome(v),
        ParallelogramOutcome::Outside {
            sides: vec![Side::AlphaAbove, Side::BetaBelow]
        }
    );
}

#[test]
fn nearly_parallel_rays_use_a_scale_free_tolerance() {
    // The same grazing ray at every scale gets the same answer: the tolerance is relative.
    for scale in [1e-20, 1e-5, 1.0, 1e5, 1e20] {
        // The lecture triangle at this scale, the ray from the origin rising `dz` out of its plane.
        let rising = |dz: f64| {
            let [a, b, c] = LECTURE.map(|v| v.map(|x| x * scale));
            [a, b, c, [0.0; 3], [1.0, -1.0, dz]]
        };
        let grazing = rising(1e-17);
        assert_eq!(
            triangle_status::<f64>(grazing, 0.0).0,
            "parallel",
            "scale {scale}"
        );
        let steep = rising(1e-3);
        assert_ne!(
            triangle_status::<f64>(steep, 0.0).0,
            "parallel",
            "scale {scale}"
        );
        // Exact arithmetic only calls a true zero parallel.
        assert_ne!(triangle_status::<Exact>(grazing, 0.0).0, "parallel");
    }
    let _ = TriangleOutcome::Hit;
}
