//! Batch throughput: `raylab solve --batch --no-trace` on JSON lines held in memory, in lines a second.
//!
//! `cargo bench --bench batch` prints the figure as `thrpt` (elements = lines), for f64 and exact.
//! One thread: the batch itself is sequential.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rand::{Rng, SeedableRng};
use raylab::cli::batch::run_batch;
use raylab::geometry::Precision;

/// `count` lines of triangle, segments and parallelogram cases: numbers with three decimals, some as
/// arrays and some as strings, hits and misses, as a renderer or a student's test file would write them.
fn lines(count: usize) -> String {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(15);
    let mut number = move || format!("{:.3}", rng.random_range(-5.0..5.0));
    let mut vector = |n: usize| (0..n).map(|_| number()).collect::<Vec<_>>().join(",");
    let mut text = String::new();
    for i in 0..count {
        let line = match i % 4 {
            0 => format!(
                r#"{{"kind":"triangle","a":[3,0,0],"b":[0,3,0],"c":[0,0,3],"origin":[{}],"dir":[{}]}}"#,
                vector(3),
                vector(3)
            ),
            1 => format!(
                r#"{{"kind":"triangle","a":"{}","b":"{}","c":"{}","origin":"0,0,0","dir":"1,1,1"}}"#,
                vector(3),
                vector(3),
                vector(3)
            ),
            2 => format!(
                r#"{{"kind":"segments","a1":[{}],"a2":[{}],"b1":[{}],"b2":[{}]}}"#,
                vector(2),
                vector(2),
                vector(2),
                vector(2)
            ),
            _ => format!(
                r#"{{"kind":"parallelogram","corner":[0,0,0],"e1":[2,0,0],"e2":[0,1,0],"origin":[{}],"dir":[{}]}}"#,
                vector(3),
                vector(3)
            ),
        };
        text.push_str(&line);
        text.push('\n');
    }
    text
}

fn batch(c: &mut Criterion) {
    const LINES: usize = 10_000;
    let input = lines(LINES);
    let mut group = c.benchmark_group("batch");
    group.throughput(Throughput::Elements(LINES as u64));
    for (name, precision, count) in [
        ("f64 no-trace", Precision::F64, LINES),
        ("exact no-trace", Precision::Exact, LINES / 10),
    ] {
        let input: String = input.lines().take(count).flat_map(|l| [l, "\n"]).collect();
        group.throughput(Throughput::Elements(count as u64));
        group.bench_function(name, |b| {
            b.iter(|| {
                let bad = run_batch(
                    black_box(input.as_bytes()),
                    std::io::sink(),
                    std::io::sink(),
                    precision,
                    false,
                )
                .unwrap();
                assert_eq!(bad, 0);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
