//! The study: every float method in f32 and f64 on every family, judged against the exact reference,
//! with wrong decisions, cracks, double hits, errors of t and of the barycentrics, and time per test.
//!
//! It runs in units (one family × precision × method at a time) so a caller can show progress, cancel,
//! or spread the work over frames.

use serde::Serialize;

use super::families::{Family, Probe, generate};
use super::reference::{Reference, reference};
use super::{Answer, Case, Float, InverseSolve, Method};
use crate::geometry::Precision;
use crate::platform::Stopwatch;

/// How big a study to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// Rays per family (the seam and fan families get `shared_rays`).
    pub rays: usize,
    /// Rays for the seam sweep and the vertex fan.
    pub shared_rays: usize,
    /// The random seed.
    pub seed: u64,
    /// Seconds of timing per method, precision and family (at least one pass).
    pub timing_seconds: f64,
}

impl Config {
    /// `raylab bench --quick`: a few seconds.
    pub fn quick() -> Config {
        Config {
            rays: 1500,
            shared_rays: 5000,
            seed: 2019,
            timing_seconds: 0.01,
        }
    }

    /// `raylab bench`: a few minutes at most.
    pub fn full() -> Config {
        Config {
            rays: 20_000,
            shared_rays: 200_000,
            seed: 2019,
            timing_seconds: 0.05,
        }
    }
}

/// One row of the results: a method in a precision on a family.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Record {
    /// The method.
    pub method: String,
    /// f32 or f64 (`exact` for the reference's own row).
    pub precision: String,
    /// The family.
    pub family: String,
    /// Rays cast.
    pub rays: usize,
    /// Ray–triangle tests (a seam ray is two tests, a fan ray one per triangle).
    pub tests: usize,
    /// Tests whose hit/miss differs from the exact reference.
    pub wrong_decisions: usize,
    /// Seam and fan rays that the exact reference says hit, but hit no triangle.
    pub cracks: usize,
    /// Seam and fan rays that hit two or more triangles where the exact reference hits at most one.
    pub double_hits: usize,
    /// The largest relative error of t.
    pub max_rel_err_t: f64,
    /// The largest error of t in units in the last place of the precision.
    pub max_ulps_t: f64,
    /// The largest error of β or γ (they are of order 1), in units of the precision's ε.
    pub max_eps_err_barycentric: f64,
    /// Tests the method decided in exact arithmetic (the watertight fallback).
    pub exact_fallbacks: usize,
    /// Time per ray–triangle test, nanoseconds.
    pub ns_per_test: f64,
    /// For families with a knob (grazing angle, offset, scale, aspect): (knob, largest relative error of
    /// t) for each knob value, ascending.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub error_by_parameter: Vec<[f64; 2]>,
}

/// One family's rays with their exact verdicts, in both precisions.
struct Prepared {
    family: Family,
    probes: Vec<Probe>,
    cases64: Vec<Case<f64>>,
    cases32: Vec<Case<f32>>,
    refs64: Vec<Reference>,
    refs32: Vec<Reference>,
    /// For each probe, the range of its cases.
    spans: Vec<std::ops::Range<usize>>,
}

fn prepare(family: Family, config: &Config) -> Prepared {
    let count = if family.shares_geometry() {
        config.shared_rays
    } else {
        config.rays
    };
    let probes = generate(family, count, config.seed);
    let mut spans = Vec::with_capacity(probes.len());
    let mut cases64 = Vec::new();
    for probe in &probes {
        let start = cases64.len();
        cases64.extend(probe.cases.iter().copied());
        spans.push(start..cases64.len());
    }
    let cases32: Vec<Case<f32>> = cases64.iter().map(Case::to_f32).collect();
    let refs64 = cases64.iter().map(reference).collect();
    let refs32 = cases32.iter().map(reference).collect();
    Prepared {
        family,
        probes,
        cases64,
        cases32,
        refs64,
        refs32,
        spans,
    }
}

/// Runs the whole study; `progress(done, total)` is called after each unit and stops it by
/// returning false (then `None` is returned).
pub fn run(config: &Config, mut progress: impl FnMut(usize, usize) -> bool) -> Option<Vec<Record>> {
    let units_per_family = 2 * Method::FLOAT.len() + 1;
    let total = Family::ALL.len() * (units_per_family + 1);
    let mut done = 0;
    let mut records = Vec::new();
    for family in Family::ALL {
        let prepared = prepare(family, config);
        done += 1;
        if !progress(done, total) {
            return None;
        }
        for method in Method::FLOAT {
            for precision in [Precision::F32, Precision::F64] {
                records.push(match precision {
                    Precision::F32 => measure(
                        method,
                        &prepared,
                        &prepared.cases32,
                        &prepared.refs32,
                        config,
                    ),
                    _ => measure(
                        method,
                        &prepared,
                        &prepared.cases64,
                        &prepared.refs64,
                        config,
                    ),
                });
                done += 1;
                if !progress(done, total) {
                    return None;
                }
            }
        }
        records.push(measure_exact(&prepared, config));
        done += 1;
        if !progress(done, total) {
            return None;
        }
    }
    Some(records)
}

/// Nanoseconds per test: whole passes over `tests` tests until the time is up (at least one pass).
fn ns_per_test(seconds: f64, tests: usize, mut pass: impl FnMut()) -> f64 {
    let clock = Stopwatch::start();
    let mut passes = 0;
    while passes == 0 || clock.seconds() < seconds {
        pass();
        passes += 1;
    }
    clock.seconds() * 1e9 / (passes * tests).max(1) as f64
}

impl Record {
    /// A row with its time and no errors yet.
    fn new(
        method: Method,
        precision: &str,
        prepared: &Prepared,
        tests: usize,
        ns_per_test: f64,
    ) -> Record {
        Record {
            method: method.name().into(),
            precision: precision.into(),
            family: prepared.family.name().into(),
            rays: prepared.probes.len(),
            tests,
            wrong_decisions: 0,
            cracks: 0,
            double_hits: 0,
            max_rel_err_t: 0.0,
            max_ulps_t: 0.0,
            max_eps_err_barycentric: 0.0,
            exact_fallbacks: 0,
            ns_per_test,
            error_by_parameter: Vec::new(),
        }
    }
}

/// Times the exact reference itself (its answers are right by definition).
fn measure_exact(prepared: &Prepared, config: &Config) -> Record {
    let sample = &prepared.cases64[..prepared.cases64.len().min(500)];
    let ns = ns_per_test(config.timing_seconds, sample.len(), || {
        for case in sample {
            std::hint::black_box(super::exact_answer(std::hint::black_box(case)));
        }
    });
    Record::new(Method::Exact, "exact", prepared, prepared.cases64.len(), ns)
}

fn measure<F: Float + InverseSolve>(
    method: Method,
    prepared: &Prepared,
    cases: &[Case<F>],
    refs: &[Reference],
    config: &Config,
) -> Record {
    let answers: Vec<Answer<F>> = cases.iter().map(|c| method.run(c)).collect();
    let ns = ns_per_test(config.timing_seconds, cases.len(), || {
        for case in cases {
            std::hint::black_box(method.run(std::hint::black_box(case)));
        }
    });
    let mut record = Record::new(method, F::PRECISION.name(), prepared, cases.len(), ns);
    let mut by_parameter: std::collections::BTreeMap<u64, (f64, f64)> = Default::default();
    let parameters: Vec<f64> = prepared
        .spans
        .iter()
        .zip(&prepared.probes)
        .flat_map(|(span, probe)| std::iter::repeat_n(probe.parameter, span.len()))
        .collect();
    for ((answer, exact), parameter) in answers.iter().zip(refs).zip(&parameters) {
        record.wrong_decisions += usize::from(answer.hit != exact.hit);
        record.exact_fallbacks += usize::from(answer.exact_fallback);
        if let (Some(values), Some(truth)) = (answer.values, exact.values) {
            let [t, beta, gamma] = values.map(|x| x.to_f64());
            if ![t, beta, gamma].iter().all(|x| x.is_finite()) {
                continue;
            }
            let t_err = (t - truth[0]).abs();
            // Relative error and ulps are measured where t is not zero (a ray starting on the plane).
            if truth[0] != 0.0 {
                let relative = t_err / truth[0].abs();
                record.max_rel_err_t = record.max_rel_err_t.max(relative);
                let slot = by_parameter
                    .entry(parameter.to_bits())
                    .or_insert((*parameter, 0.0));
                slot.1 = slot.1.max(relative);
                record.max_ulps_t = record.max_ulps_t.max(t_err / ulp::<F>(truth[0]));
            }
            let bary_err = (beta - truth[1]).abs().max((gamma - truth[2]).abs());
            record.max_eps_err_barycentric = record
                .max_eps_err_barycentric
                .max(bary_err / F::EPS.to_f64());
        }
    }
    if by_parameter.len() > 1 && !prepared.family.shares_geometry() {
        let mut points: Vec<[f64; 2]> = by_parameter.values().map(|(p, e)| [*p, *e]).collect();
        points.sort_by(|a, b| a[0].total_cmp(&b[0]));
        record.error_by_parameter = points;
    }
    if prepared.family.shares_geometry() {
        for span in &prepared.spans {
            let exact_hits = refs[span.clone()].iter().filter(|r| r.hit).count();
            let hits = answers[span.clone()].iter().filter(|a| a.hit).count();
            record.cracks += usize::from(exact_hits >= 1 && hits == 0);
            record.double_hits += usize::from(hits >= 2 && exact_hits <= 1);
        }
    }
    record
}

/// One point of the error-against-time plot: a method in a precision, over one family or all.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The method.
    pub method: String,
    /// f32 or f64.
    pub precision: String,
    /// Time per test: the mean over the families' rows.
    pub ns_per_test: f64,
    /// The largest relative error of t over the families.
    pub max_rel_err_t: f64,
    /// Wrong decisions, summed.
    pub wrong_decisions: usize,
}

/// The float methods' rows for one family (or, with `None`, summarised over all families: worst
/// error, summed wrong decisions, mean time).
pub fn summary(records: &[Record], family: Option<&str>) -> Vec<Summary> {
    let mut out = Vec::new();
    for method in Method::FLOAT {
        for precision in ["f32", "f64"] {
            let rows: Vec<&Record> = records
                .iter()
                .filter(|r| r.method == method.name() && r.precision == precision)
                .filter(|r| family.is_none_or(|f| r.family == f))
                .collect();
            if rows.is_empty() {
                continue;
            }
            out.push(Summary {
                method: method.name().into(),
                precision: precision.into(),
                ns_per_test: rows.iter().map(|r| r.ns_per_test).sum::<f64>() / rows.len() as f64,
                max_rel_err_t: rows.iter().map(|r| r.max_rel_err_t).fold(0.0, f64::max),
                wrong_decisions: rows.iter().map(|r| r.wrong_decisions).sum(),
            });
        }
    }
    out
}

/// The spacing of floats of precision F at x (for errors in ulps).
fn ulp<F: Float>(x: f64) -> f64 {
    if F::PRECISION == Precision::F32 {
        let v = (x.abs() as f32).max(f32::MIN_POSITIVE);
        (f32::from_bits(v.to_bits() + 1) - v) as f64
    } else {
        let v = x.abs().max(f64::MIN_POSITIVE);
        f64::from_bits(v.to_bits() + 1) - v
    }
}

/// The table as text: one row per record.
pub fn table(records: &[Record]) -> String {
    let mut out = format!(
        "{:<17} {:<5} {:<9} {:>7} {:>7} {:>6} {:>6} {:>10} {:>10} {:>10} {:>8} {:>9}\n",
        "method",
        "prec",
        "family",
        "tests",
        "wrong",
        "cracks",
        "double",
        "rel err t",
        "ulps t",
        "bary (ε)",
        "exact",
        "ns/test"
    );
    for r in records {
        out.push_str(&format!(
            "{:<17} {:<5} {:<9} {:>7} {:>7} {:>6} {:>6} {:>10.2e} {:>10.2e} {:>10.2e} {:>8} {:>9.1}\n",
            r.method, r.precision, r.family, r.tests, r.wrong_decisions, r.cracks, r.double_hits,
            r.max_rel_err_t, r.max_ulps_t, r.max_eps_err_barycentric, r.exact_fallbacks, r.ns_per_test
        ));
    }
    out
}

/// The records as CSV with a header.
pub fn csv(records: &[Record]) -> String {
    let mut out = String::from(
        "method,precision,family,rays,tests,wrong_decisions,cracks,double_hits,max_rel_err_t,max_ulps_t,max_eps_err_barycentric,exact_fallbacks,ns_per_test\n",
    );
    for r in records {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            r.method,
            r.precision,
            r.family,
            r.rays,
            r.tests,
            r.wrong_decisions,
            r.cracks,
            r.double_hits,
            r.max_rel_err_t,
            r.max_ulps_t,
            r.max_eps_err_barycentric,
            r.exact_fallbacks,
            r.ns_per_test
        ));
    }
    out
}
