//! Batch throughput: `raylab solve --batch --no-trace` on JSON lines held in memory, in lines a second.
//!
//! `cargo bench --bench batch` prints the figure as `thrpt` in lines a second, for f64 and exact.
//! One thread: the batch itself is sequential. The time measured is the thread's CPU time (on Unix),
//! so the figure is the speed of one core even on a machine busy with other work, where wall-clock
//! time would count the time the thread waited for a core.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;

use criterion::measurement::{Measurement, ValueFormatter};
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

/// The CPU time of the calling thread, in nanoseconds (wall-clock time where there is no such clock).
struct ThreadCpuTime;

#[cfg(unix)]
fn thread_nanos() -> u64 {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec it is given; the clock exists on every Unix we build.
    #[allow(unsafe_code)]
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    assert_eq!(status, 0, "the thread's CPU clock");
    now.tv_sec as u64 * 1_000_000_000 + now.tv_nsec as u64
}

#[cfg(not(unix))]
fn thread_nanos() -> u64 {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_nanos() as u64
}

impl Measurement for ThreadCpuTime {
    type Intermediate = u64;
    type Value = u64;

    fn start(&self) -> u64 {
        thread_nanos()
    }

    fn end(&self, start: u64) -> u64 {
        thread_nanos() - start
    }

    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }

    fn zero(&self) -> u64 {
        0
    }

    fn to_f64(&self, value: &u64) -> f64 {
        *value as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        self
    }
}

impl ValueFormatter for ThreadCpuTime {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        values.iter_mut().for_each(|v| *v /= 1e6);
        "ms (CPU)"
    }

    fn scale_throughputs(
        &self,
        _: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let lines = match *throughput {
            Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => n as f64,
            _ => 1.0,
        };
        values.iter_mut().for_each(|ns| *ns = lines * 1e9 / *ns);
        "lines/s"
    }

    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

fn batch(c: &mut Criterion<ThreadCpuTime>) {
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

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(ThreadCpuTime);
    targets = batch
}
criterion_main!(benches);
