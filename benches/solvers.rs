//! Time per solve of each solver in each precision, with and without recording the trace.
//!
//! `cargo bench --bench solvers` prints the figures; compare within one run (same machine, same load).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DVec2, DVec3};
use raylab::geometry::parallelogram::{self, RayParallelogram};
use raylab::geometry::segments::{self, SegmentPair};
use raylab::geometry::triangle::{self, RayTriangle};
use raylab::geometry::{Lecture, Real, TriangleLecture};
use raylab::intersect::Case;
use raylab::math::exact::Exact;

/// Seed 003's ray and triangle: non-integer inputs, so the exact run meets real fractions.
fn seed003<R: Real>() -> RayTriangle<R> {
    let v = Case::SEED003.vectors();
    RayTriangle::read(
        raylab::geometry::Reading::FloatValue,
        v.map(DVec3::from_array),
        0.0,
    )
    .unwrap()
}

fn seed000_segments<R: Real>() -> SegmentPair<R> {
    let p = [[1.0, 2.0], [6.0, 1.0], [2.0, 6.0], [5.0, 1.0]];
    SegmentPair::read(
        raylab::geometry::Reading::FloatValue,
        p.map(DVec2::from_array),
    )
    .unwrap()
}

fn square<R: Real>() -> RayParallelogram<R> {
    let v = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
        [0.1, 0.0, -1.0],
    ];
    RayParallelogram::read(
        raylab::geometry::Reading::FloatValue,
        v.map(DVec3::from_array),
    )
    .unwrap()
}

fn bench_precision<R: Real>(c: &mut Criterion) {
    let name = R::PRECISION.name();
    let tri = seed003::<R>();
    let seg = seed000_segments::<R>();
    let par = square::<R>();
    c.bench_function(&format!("triangle/{name}"), |b| {
        b.iter(|| triangle::solve(black_box(&tri), &mut ()))
    });
    c.bench_function(&format!("triangle/{name}/traced"), |b| {
        b.iter(|| TriangleLecture::traced(black_box(&tri)))
    });
    c.bench_function(&format!("segments/{name}"), |b| {
        b.iter(|| segments::solve(black_box(&seg), &mut ()))
    });
    c.bench_function(&format!("parallelogram/{name}"), |b| {
        b.iter(|| parallelogram::solve(black_box(&par), &mut ()))
    });
}

fn solvers(c: &mut Criterion) {
    bench_precision::<f32>(c);
    bench_precision::<f64>(c);
    bench_precision::<Exact>(c);
}

criterion_group!(benches, solvers);
criterion_main!(benches);
