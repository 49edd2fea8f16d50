//! The study: every float method in f32 and f64 on every family, judged against the exact reference,
//! with wrong decisions, cracks, double hits, errors of t and of the barycentrics, and time per test.
//!
//! It runs as a [`StudyRun`], a stepper whose steps take a few milliseconds each, so a caller can show
//! progress, cancel, or spread the work over a web page's frames. Progress counts units: one family's
//! rays prepared and decided exactly, or one method in one precision measured.

use serde::Serialize;

use super::families::{Family, Probe, generate};
use crate::geometry::Precision;
use crate::intersect::reference::{Reference, reference};
use crate::intersect::{Answer, Case, Float, InverseSolve, Method};
use crate::platform::{Progress, Sliced, Stopwatch};

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
    /// The exact verdicts so far: filled a step at a time, f64 cases first.
    refs64: Vec<Reference>,
    refs32: Vec<Reference>,
    /// For each probe, the range of its cases.
    spans: Vec<std::ops::Range<usize>>,
}

/// Cases decided exactly, or answered by a method, per step (a few milliseconds at most).
const CASES_PER_STEP: usize = 256;

/// How long one timing step runs, seconds: long enough for a browser's coarse clock (0.1 ms).
const TIMING_STEP_SECONDS: f64 = 0.005;

impl Prepared {
    /// The family's rays, not yet decided.
    fn generate(family: Family, config: &Config) -> Prepared {
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
        Prepared {
            family,
            probes,
            refs64: Vec::with_capacity(cases64.len()),
            refs32: Vec::with_capacity(cases32.len()),
            cases64,
            cases32,
            spans,
        }
    }

    /// Decides the next cases exactly; true once every case is decided.
    fn decide_some(&mut self) -> bool {
        if self.refs64.len() < self.cases64.len() {
            let (from, to) = chunk(self.refs64.len(), self.cases64.len());
            self.refs64
                .extend(self.cases64[from..to].iter().map(reference));
        } else {
            let (from, to) = chunk(self.refs32.len(), self.cases32.len());
            self.refs32
                .extend(self.cases32[from..to].iter().map(reference));
        }
        self.refs32.len() == self.cases32.len()
    }
}

/// The next step's range of cases from `done` of `len`.
fn chunk(done: usize, len: usize) -> (usize, usize) {
    (done, (done + CASES_PER_STEP).min(len))
}

/// One method in one precision being measured: its answers on every case, then its time per test.
struct Measuring<F> {
    method: Method,
    answers: Vec<Answer<F>>,
    /// Seconds spent in timed steps, and the tests they ran.
    timed_seconds: f64,
    timed_tests: usize,
    /// Whole passes over the cases timed, and where the current pass is.
    passes: usize,
    next: usize,
}

impl<F: Float + InverseSolve> Measuring<F> {
    fn new(method: Method, cases: usize) -> Measuring<F> {
        Measuring {
            method,
            answers: Vec::with_capacity(cases),
            timed_seconds: 0.0,
            timed_tests: 0,
            passes: 0,
            next: 0,
        }
    }

    /// One step: the next answers, or a few milliseconds of timing (whole passes over the cases
    /// until `timing_seconds` is spent, at least one); the record once both are done.
    fn step(
        &mut self,
        prepared: &Prepared,
        cases: &[Case<F>],
        refs: &[Reference],
        config: &Config,
    ) -> Option<Record> {
        let method = self.method;
        if self.answers.len() < cases.len() {
            let (from, to) = chunk(self.answers.len(), cases.len());
            self.answers
                .extend(cases[from..to].iter().map(|c| method.run(c)));
            return None;
        }
        let finished = |m: &Self| m.passes > 0 && m.timed_seconds >= config.timing_seconds;
        let clock = Stopwatch::start();
        let mut tests = 0;
        while !finished(self) && clock.seconds() < TIMING_STEP_SECONDS {
            let (from, to) = chunk(self.next, cases.len());
            for case in &cases[from..to] {
                std::hint::black_box(method.run(std::hint::black_box(case)));
            }
            tests += to - from;
            self.next = to;
            if to == cases.len() {
                self.next = 0;
                self.passes += 1;
                // A pass that ends the timing ends this step too.
                if self.timed_seconds + clock.seconds() >= config.timing_seconds {
                    break;
                }
            }
        }
        self.timed_seconds += clock.seconds();
        self.timed_tests += tests;
        if !finished(self) {
            return None;
        }
        let ns = self.timed_seconds * 1e9 / self.timed_tests.max(1) as f64;
        Some(judge(method, prepared, &self.answers, refs, ns))
    }
}

/// A measurement in f32 or in f64.
enum Measurement {
    F32(Measuring<f32>),
    F64(Measuring<f64>),
}

/// Where a study is.
enum Stage {
    /// The next family's rays are to be generated.
    Generate,
    /// The family's cases are being decided exactly.
    Decide(Box<Prepared>),
    /// The family's `unit`-th measurement is under way (the float methods in f32 and f64, then the
    /// exact reference's own time).
    Measure(Box<Prepared>, usize, Option<Measurement>),
    /// Every family is done.
    Finished,
}

/// The whole study as a stepper ([`Sliced`]): a step takes a few milliseconds (generating a family's
/// rays, deciding a few hundred cases exactly, answering or timing a few hundred tests), so it runs
/// on a thread or, in a web page, a few steps per frame.
pub struct StudyRun {
    config: Config,
    /// The family being studied (index into [`Family::ALL`]).
    family: usize,
    stage: Stage,
    /// Units done: a family prepared, or a method in a precision measured.
    done: usize,
    records: Vec<Record>,
}

impl StudyRun {
    /// Units per family: preparing it, each float method in f32 and f64, and the exact reference.
    const UNITS_PER_FAMILY: usize = 1 + 2 * Method::FLOAT.len() + 1;

    /// A study of this size, not started.
    pub fn new(config: Config) -> StudyRun {
        StudyRun {
            config,
            family: 0,
            stage: Stage::Generate,
            done: 0,
            records: Vec::new(),
        }
    }

    /// Units in all.
    pub fn total(&self) -> usize {
        Family::ALL.len() * Self::UNITS_PER_FAMILY
    }

    /// The stage after the family's last unit.
    fn next_family(&mut self) -> Stage {
        self.family += 1;
        if self.family < Family::ALL.len() {
            Stage::Generate
        } else {
            Stage::Finished
        }
    }
}

impl Sliced for StudyRun {
    type Output = Vec<Record>;

    fn step(&mut self) -> Progress<Vec<Record>> {
        let config = &self.config;
        self.stage = match std::mem::replace(&mut self.stage, Stage::Finished) {
            Stage::Generate => Stage::Decide(Box::new(Prepared::generate(
                Family::ALL[self.family],
                config,
            ))),
            Stage::Decide(mut prepared) => {
                if prepared.decide_some() {
                    self.done += 1;
                    Stage::Measure(prepared, 0, None)
                } else {
                    Stage::Decide(prepared)
                }
            }
            Stage::Measure(prepared, unit, measurement) => {
                let floats = 2 * Method::FLOAT.len();
                let (record, measurement) = if unit == floats {
                    (Some(measure_exact(&prepared, config)), None)
                } else {
                    let method = Method::FLOAT[unit / 2];
                    let p = &*prepared;
                    match measurement {
                        Some(Measurement::F32(mut m)) => (
                            m.step(p, &p.cases32, &p.refs32, config),
                            Some(Measurement::F32(m)),
                        ),
                        Some(Measurement::F64(mut m)) => (
                            m.step(p, &p.cases64, &p.refs64, config),
                            Some(Measurement::F64(m)),
                        ),
                        None if unit % 2 == 0 => (
                            None,
                            Some(Measurement::F32(Measuring::new(method, p.cases32.len()))),
                        ),
                        None => (
                            None,
                            Some(Measurement::F64(Measuring::new(method, p.cases64.len()))),
                        ),
                    }
                };
                match record {
                    None => Stage::Measure(prepared, unit, measurement),
                    Some(record) => {
                        self.records.push(record);
                        self.done += 1;
                        if unit == floats {
                            self.next_family()
                        } else {
                            Stage::Measure(prepared, unit + 1, None)
                        }
                    }
                }
            }
            Stage::Finished => Stage::Finished,
        };
        match self.stage {
            Stage::Finished => Progress::Finished(std::mem::take(&mut self.records)),
            _ => Progress::Working {
                done: self.done,
                total: self.total(),
            },
        }
    }
}

/// Runs the whole study; `progress(done, total)` is called after each unit and stops it by
/// returning false (then `None` is returned).
pub fn run(config: &Config, mut progress: impl FnMut(usize, usize) -> bool) -> Option<Vec<Record>> {
    let mut study = StudyRun::new(config.clone());
    let mut reported = 0;
    loop {
        match study.step() {
            Progress::Working { done, total } => {
                if done != reported {
                    reported = done;
                    if !progress(done, total) {
                        return None;
                    }
                }
            }
            Progress::Finished(records) => {
                let total = study.total();
                return progress(total, total).then_some(records);
            }
        }
    }
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
            std::hint::black_box(crate::intersect::exact_answer(std::hint::black_box(case)));
        }
    });
    Record::new(Method::Exact, "exact", prepared, prepared.cases64.len(), ns)
}

/// A method's record from its answers on every case and its time per test.
fn judge<F: Float>(
    method: Method,
    prepared: &Prepared,
    answers: &[Answer<F>],
    refs: &[Reference],
    ns: f64,
) -> Record {
    let mut record = Record::new(method, F::PRECISION.name(), prepared, answers.len(), ns);
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

/// One row of results.csv: a [`Record`] without its per-knob errors.
#[derive(Serialize)]
struct CsvRow<'a> {
    method: &'a str,
    precision: &'a str,
    family: &'a str,
    rays: usize,
    tests: usize,
    wrong_decisions: usize,
    cracks: usize,
    double_hits: usize,
    max_rel_err_t: f64,
    max_ulps_t: f64,
    max_eps_err_barycentric: f64,
    exact_fallbacks: usize,
    ns_per_test: f64,
}

/// The records as CSV, a header and a line per record (the per-knob errors are in the JSON only).
pub fn csv(records: &[Record]) -> Result<String, CsvError> {
    let mut writer = csv::Writer::from_writer(Vec::new());
    for r in records {
        writer
            .serialize(CsvRow {
                method: &r.method,
                precision: &r.precision,
                family: &r.family,
                rays: r.rays,
                tests: r.tests,
                wrong_decisions: r.wrong_decisions,
                cracks: r.cracks,
                double_hits: r.double_hits,
                max_rel_err_t: r.max_rel_err_t,
                max_ulps_t: r.max_ulps_t,
                max_eps_err_barycentric: r.max_eps_err_barycentric,
                exact_fallbacks: r.exact_fallbacks,
                ns_per_test: r.ns_per_test,
            })
            .map_err(|e| CsvError(e.to_string()))?;
    }
    let bytes = writer.into_inner().map_err(|e| CsvError(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| CsvError(e.to_string()))
}

/// The CSV writer failed (a record it cannot write, which raylab's records never are).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cannot write the CSV: {0}")]
pub struct CsvError(pub String);
