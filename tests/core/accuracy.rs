//! The accuracy study's claims, checked: the watertight method leaves no crack and makes no wrong
//! decision on the seam sweep and the vertex fan, while f32 Möller–Trumbore cracks; the exact references
//! agree with each other; and the families are what they say.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use raylab::accuracy::families::{Family, generate};
use raylab::intersect::reference::reference;
use raylab::intersect::{Case, Float, InverseSolve, Method, exact_answer, watertight};

/// Runs a method over a family's probes: (tests, wrong decisions, cracks, fallbacks).
fn audit<F: Float + InverseSolve>(
    method: Method,
    family: Family,
    rays: usize,
    convert: impl Fn(&Case<f64>) -> Case<F>,
) -> (usize, usize, usize, usize) {
    let (mut tests, mut wrong, mut cracks, mut fallbacks) = (0, 0, 0, 0);
    for probe in generate(family, rays, 1) {
        let mut exact_hits = 0;
        let mut hits = 0;
        for case in &probe.cases {
            let case = convert(case);
            let answer = method.run(&case);
            let truth = reference(&case);
            tests += 1;
            wrong += usize::from(answer.hit != truth.hit);
            fallbacks += usize::from(answer.exact_fallback);
            exact_hits += usize::from(truth.hit);
            hits += usize::from(answer.hit);
        }
        cracks += usize::from(exact_hits > 0 && hits == 0);
    }
    (tests, wrong, cracks, fallbacks)
}

const SHARED_RAYS: usize = 100_000;

#[test]
fn watertight_f64_has_no_cracks_and_no_wrong_decisions_on_the_seam() {
    let (tests, wrong, cracks, _) =
        audit::<f64>(Method::Watertight, Family::Seam, SHARED_RAYS, |c| *c);
    assert_eq!(tests, 2 * SHARED_RAYS);
    assert_eq!((wrong, cracks), (0, 0));
}

#[test]
fn watertight_f32_has_no_cracks_and_no_wrong_decisions_on_the_seam() {
    let (_, wrong, cracks, _) =
        audit::<f32>(Method::Watertight, Family::Seam, SHARED_RAYS, Case::to_f32);
    assert_eq!((wrong, cracks), (0, 0));
}

#[test]
fn watertight_has_no_cracks_and_no_wrong_decisions_on_the_vertex_fan() {
    let (tests, wrong, cracks, _) =
        audit::<f64>(Method::Watertight, Family::Fan, SHARED_RAYS, |c| *c);
    assert!(tests >= 5 * SHARED_RAYS);
    assert_eq!((wrong, cracks), (0, 0));
    let (_, wrong, cracks, _) = audit::<f32>(
        Method::Watertight,
        Family::Fan,
        SHARED_RAYS / 4,
        Case::to_f32,
    );
    assert_eq!((wrong, cracks), (0, 0));
}

#[test]
fn f32_moller_trumbore_cracks_where_watertight_does_not() {
    let (_, wrong, cracks, _) =
        audit::<f32>(Method::MollerTrumbore, Family::Seam, 20_000, Case::to_f32);
    assert!(
        cracks > 0,
        "the seam sweep should show Möller–Trumbore's cracks"
    );
    assert!(wrong > cracks);
}

#[test]
fn watertight_float_path_agrees_with_the_independent_rational_solver() {
    // Away from edges the watertight method decides in floats; check those decisions against the
    // core's BigRational Cramer solver (a different code path from the integer reference).
    let mut float_decisions = 0;
    for family in Family::ALL {
        for probe in generate(family, 300, 5) {
            for case in &probe.cases {
                let answer = watertight::intersect(case);
                let truth = exact_answer(case);
                assert_eq!(answer.hit, truth.hit, "{family:?} {case:?}");
                float_decisions += usize::from(!answer.exact_fallback);
                let answer32 = watertight::intersect(&case.to_f32());
                assert_eq!(
                    answer32.hit,
                    exact_answer(&case.to_f32()).hit,
                    "{family:?} f32 {case:?}"
                );
            }
        }
    }
    assert!(
        float_decisions > 1000,
        "most decisions stay in floats ({float_decisions})"
    );
}

#[test]
fn the_integer_reference_matches_the_rational_solver_on_every_family() {
    for family in Family::ALL {
        for probe in generate(family, 200, 9) {
            for case in &probe.cases {
                let fast = reference(case);
                let slow = exact_answer(case);
                assert_eq!(fast.hit, slow.hit, "{family:?} {case:?}");
                if let (Some(f), Some(s)) = (fast.values, slow.values) {
                    assert_eq!(f[0], s[0].to_f64());
                }
            }
        }
    }
}

#[test]
fn the_study_runs_in_short_steps_to_the_records_of_a_whole_run() {
    use raylab::accuracy::study::{Config, StudyRun, run};
    use raylab::platform::{Progress, Sliced};
    let config = Config {
        rays: 60,
        shared_rays: 60,
        seed: 5,
        timing_seconds: 0.0,
    };
    let mut study = StudyRun::new(config.clone());
    let (mut steps, mut last) = (0, 0);
    let mut stepped = loop {
        steps += 1;
        match study.step() {
            Progress::Working { done, total } => {
                assert!(
                    last <= done && done < total,
                    "{done} of {total} after {last}"
                );
                last = done;
            }
            Progress::Finished(records) => break records,
        }
    };
    // Deciding a family and answering its cases take several steps each, not one unit each.
    assert!(steps > 2 * study.total(), "{steps} steps");
    let mut whole = run(&config, |_, _| true).unwrap();
    for record in stepped.iter_mut().chain(&mut whole) {
        record.ns_per_test = 0.0;
    }
    assert_eq!(stepped, whole);
}

#[test]
fn the_quick_study_produces_every_record() {
    use raylab::accuracy::study::{Config, run};
    let config = Config {
        rays: 60,
        shared_rays: 60,
        seed: 3,
        timing_seconds: 0.0,
    };
    let mut calls = 0;
    let records = run(&config, |_, _| {
        calls += 1;
        true
    })
    .unwrap();
    assert_eq!(
        records.len(),
        Family::ALL.len() * (2 * Method::FLOAT.len() + 1)
    );
    assert!(calls > 10);
    for r in &records {
        assert!(r.ns_per_test > 0.0, "{r:?}");
        if r.method == "watertight" {
            assert_eq!((r.wrong_decisions, r.cracks), (0, 0), "{r:?}");
        }
    }
    // Cancelling stops the run.
    assert!(run(&config, |done, _| done < 3).is_none());
    let json = serde_json::to_value(&records).unwrap();
    for field in [
        "method",
        "precision",
        "family",
        "rays",
        "wrong_decisions",
        "cracks",
        "double_hits",
        "max_rel_err_t",
        "ns_per_test",
    ] {
        assert!(json[0].get(field).is_some(), "JSON lacks {field}");
    }
}

#[test]
fn every_method_traces_its_own_steps() {
    let lecture = Case::LECTURE;
    let own_step = [
        (Method::Cramer, "det_M1"),
        (Method::MollerTrumbore, "p"),
        (Method::Plane, "n"),
        (Method::NormalEquations, "gram"),
        (Method::Inverse, "Y"),
        (Method::Watertight, "UVW"),
        (Method::Exact, "det_M3"),
    ];
    for (method, id) in own_step {
        for trace in [method.trace(&lecture), method.trace(&lecture.to_f32())] {
            assert!(
                trace.step(id).is_some(),
                "{} lacks step {id}",
                method.name()
            );
            let verdict = trace.verdict().expect("a verdict");
            assert_eq!(verdict.status.word(), "hit", "{}", method.name());
        }
    }
}
