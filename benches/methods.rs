//! Time per ray–triangle test of every method in f32 and f64 on one fixed batch of random rays, the
//! batched structure-of-arrays f32 kernel, and a probe of this machine's vector arithmetic rate (for the
//! kernel's floor: 45 flops per test at the probe's rate).
//!
//! `cargo bench --bench methods`

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use raylab::accuracy::families::{Family, generate};
use raylab::intersect::soa::{self, TrianglesSoA};
use raylab::intersect::{Case, Float, InverseSolve, Method};

const BATCH: usize = 4096;

fn cases() -> Vec<Case<f64>> {
    generate(Family::Random, BATCH, 17)
        .into_iter()
        .map(|p| p.cases[0])
        .collect()
}

/// How many of `cases` `method` finds a hit in: the work one timed iteration does.
fn hits<F: Float + InverseSolve>(method: Method, cases: &[Case<F>]) -> usize {
    cases
        .iter()
        .filter(|case| method.run(black_box(*case)).hit)
        .count()
}

fn methods(c: &mut Criterion) {
    let cases64 = cases();
    let cases32: Vec<Case<f32>> = cases64.iter().map(Case::to_f32).collect();
    let mut group = c.benchmark_group("method");
    group.throughput(Throughput::Elements(BATCH as u64));
    for method in Method::FLOAT {
        group.bench_function(format!("{}/f32", method.name()), |b| {
            b.iter(|| hits(method, &cases32))
        });
        group.bench_function(format!("{}/f64", method.name()), |b| {
            b.iter(|| hits(method, &cases64))
        });
    }
    group.finish();
    let mut exact = c.benchmark_group("method-exact");
    let few = &cases64[..64];
    exact.throughput(Throughput::Elements(few.len() as u64));
    exact.bench_function("exact/rational", |b| b.iter(|| hits(Method::Exact, few)));
    exact.bench_function("exact/integer-reference", |b| {
        b.iter(|| {
            few.iter()
                .filter(|case| raylab::intersect::reference::reference(black_box(*case)).hit)
                .count()
        })
    });
    exact.finish();
}

fn kernel(c: &mut Criterion) {
    let cases32: Vec<Case<f32>> = cases().iter().map(Case::to_f32).collect();
    let triangles: Vec<[[f32; 3]; 3]> = cases32.iter().map(|c| c.tri).collect();
    let soa = TrianglesSoA::new(&triangles);
    let ray = cases32[0];
    let mut t = vec![0.0f32; BATCH];
    let mut group = c.benchmark_group("kernel");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function("soa-moller-trumbore/f32", |b| {
        b.iter(|| {
            soa::intersect(
                black_box(ray.origin),
                black_box(ray.dir),
                black_box(&soa),
                &mut t,
            )
        })
    });
    // The machine's rate for independent vector multiply-adds: 7 flops per element.
    let x: Vec<f32> = (0..BATCH).map(|i| i as f32 * 0.5).collect();
    let y: Vec<f32> = (0..BATCH).map(|i| i as f32 * 0.25).collect();
    let z: Vec<f32> = (0..BATCH).map(|i| i as f32 * 0.125).collect();
    let w: Vec<f32> = (0..BATCH).map(|i| i as f32 * 0.0625).collect();
    let mut out = vec![0.0f32; BATCH];
    group.bench_function("flops-probe/7-per-element", |b| {
        b.iter(|| {
            for ((o, (x, y)), (z, w)) in out.iter_mut().zip(x.iter().zip(&y)).zip(z.iter().zip(&w))
            {
                *o = x * 1.5 + y * 2.5 + z * 3.5 + w * 4.5;
            }
            black_box(&out);
        })
    });
    group.finish();
}

criterion_group!(benches, methods, kernel);
criterion_main!(benches);
