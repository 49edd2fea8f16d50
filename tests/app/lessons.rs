//! Lessons say what the view shows: every number a slide's narration states for t, s, α, β, γ, β + γ
//! or a determinant equals the view's state on that slide, a 3D slide shows its triangle from the
//! front (not edge-on) and its ray along its length (not end-on), the verdict waits for the slide
//! that reaches it, and a slide that names a common bug shows it beside the correct image.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use glam::DVec3;
use raylab::app::parallelogram_view::ParallelogramView;
use raylab::app::render_view::RenderView;
use raylab::app::segments_view::SegmentsView;
use raylab::app::triangle_view::TriangleView;
use raylab::app::{RaylabApp, ViewKind};
use raylab::trace::Payload;

/// The quantities a narration may state a value for, longest first (so "β + γ" is read before "γ").
const NAMES: [&str; 10] = [
    "β + γ", "|M1|", "|M2|", "|M3|", "|M|", "α", "β", "γ", "t", "s",
];

/// A number as the lessons write it: `17/22`, `27 / 27`, `−1`, `0.5`.
fn number(text: &str) -> Option<f64> {
    let text = text.trim().replace('−', "-");
    match text.split_once('/') {
        Some((top, bottom)) => {
            Some(top.trim().parse::<f64>().ok()? / bottom.trim().parse::<f64>().ok()?)
        }
        None => text.parse().ok(),
    }
}

/// The value a chain ends in (`1/3.`, `2/3 ≤ 1`, `1 exactly`), or `None` when it goes on as
/// arithmetic (`1 − β − γ`) or is no number at all.
fn stated_value(item: &str) -> Option<f64> {
    let item = item.trim().trim_end_matches('.');
    let mut words = item.split_whitespace();
    let first = words.next()?;
    let (value, rest) = match (words.next(), words.next()) {
        // `27 / 27`: a fraction written with spaces.
        (Some("/"), Some(bottom)) => (number(&format!("{first}/{bottom}"))?, words.next()),
        (next, _) => (number(first)?, next),
    };
    let arithmetic = rest.is_some_and(|word| word.starts_with(['+', '-', '−', '×', '·', '/', '*']));
    (!arithmetic).then_some(value)
}

/// The quantity an item of a chain names (`With |M|`, `the ray hits the triangle at t`), when it ends
/// in one that is not part of a sum or product (`α + β + γ` names none).
fn named(item: &str) -> Option<&'static str> {
    let item = item.trim();
    NAMES.into_iter().find(|name| {
        item.strip_suffix(name).is_some_and(|before| {
            let before = before.trim_end();
            (before.is_empty() || item[..item.len() - name.len()].ends_with(' '))
                && !before.ends_with(['+', '-', '−', '×', '·', '/', '*', '('])
        })
    })
}

/// Every `name = … = value` a narration states: "β = γ = 1/3" states β and γ, "s = |M2| / |M| =
/// 21/22" states s, "α = 1 − β − γ" states nothing.
fn narrated_values(narration: &[String]) -> Vec<(&'static str, f64)> {
    let mut stated = Vec::new();
    for line in narration {
        let clauses = line
            .split([',', ':', ';'])
            .flat_map(|c| c.split(" and "))
            .flat_map(|c| c.split(" so "));
        for clause in clauses {
            let items: Vec<&str> = clause.split(" = ").collect();
            let Some(value) = items.last().and_then(|last| stated_value(last)) else {
                continue;
            };
            for item in &items[..items.len() - 1] {
                if let Some(name) = named(item) {
                    stated.push((name, value));
                }
            }
        }
    }
    stated
}

#[test]
fn narrations_are_read_as_the_lessons_write_them() {
    let lines = |text: &str| vec![text.to_string()];
    assert_eq!(
        narrated_values(&lines("β = γ = 1/3, so β + γ = 2/3 ≤ 1: inside.")),
        vec![("β", 1.0 / 3.0), ("γ", 1.0 / 3.0), ("β + γ", 2.0 / 3.0)]
    );
    assert_eq!(
        narrated_values(&lines("With |M| = 27 and |M1| = 9: β = 1/3.")),
        vec![("|M|", 27.0), ("|M1|", 9.0), ("β", 1.0 / 3.0)]
    );
    assert_eq!(
        narrated_values(&lines("s = |M2| / |M| = 21/22.")),
        vec![("s", 21.0 / 22.0)]
    );
    assert_eq!(
        narrated_values(&lines("t = 27 / 27 = 1: the hit.")),
        vec![("t", 1.0)]
    );
    assert_eq!(
        narrated_values(&lines("here the plane is met at t = −1, behind")),
        vec![("t", -1.0)]
    );
    for nothing in [
        "P = α A + β B + γ C with α + β + γ = 1: α = 1 − β − γ.",
        "A(t) = A1 + t (A2 − A1), with t from 0 to 1.",
        "D = (1, 1, 1) has length √3",
        "M⁻¹ = adj(M) / |M|, when |M| ≠ 0.",
    ] {
        assert_eq!(narrated_values(&lines(nothing)), vec![], "{nothing}");
    }
}

/// The view's values on screen, by the names a narration uses.
fn view_values(harness: &Harness<'static, RaylabApp>) -> Vec<(&'static str, f64)> {
    let app = harness.state();
    let mut values = match app.state.view {
        ViewKind::Triangle => {
            let view = app.state.get::<TriangleView>();
            vec![
                ("β", view.beta),
                ("γ", view.gamma),
                ("β + γ", view.beta + view.gamma),
                ("t", view.t),
            ]
        }
        ViewKind::Parallelogram => {
            let view = app.state.get::<ParallelogramView>();
            vec![("α", view.alpha), ("β", view.beta), ("t", view.t)]
        }
        ViewKind::Segments => {
            let view = app.state.get::<SegmentsView>();
            vec![("t", view.t), ("s", view.s)]
        }
        _ => Vec::new(),
    };
    // The determinants of the view's own solve, as its step panel shows them.
    let trace = app
        .current_scene()
        .and_then(|scene| raylab::lesson::trace_of(&scene.problem));
    for step in trace.iter().flat_map(|t| &t.steps) {
        if let Payload::Determinant(det) = &step.payload {
            let name = NAMES.into_iter().find(|n| *n == format!("|{}|", det.of));
            if let Some(name) = name {
                values.push((name, det.value.value));
            }
        }
    }
    values
}

/// How well a 3D view shows its shape and its ray (1 at best; 0 with the face edge-on or the ray
/// end-on, its handles on top of each other), as its camera measures it.
fn facing(harness: &Harness<'static, RaylabApp>) -> Option<f64> {
    let app = harness.state();
    let (normal, dir, camera) = match app.state.view {
        ViewKind::Triangle => {
            let view = app.state.get::<TriangleView>();
            let [a, b, c] = [view.scene.a, view.scene.b, view.scene.c].map(DVec3::from);
            ((b - a).cross(c - a), view.scene.dir, &view.canvas.camera)
        }
        ViewKind::Parallelogram => {
            let view = app.state.get::<ParallelogramView>();
            let [e1, e2] = [view.scene.e1, view.scene.e2].map(DVec3::from);
            (e1.cross(e2), view.scene.dir, &view.canvas.camera)
        }
        _ => return None,
    };
    Some(camera.shows(DVec3::from(dir), Some(normal)))
}

/// Every slide of every lesson: the narrated values are the view's, the 3D ones face the room, and a
/// slide that names a common bug shows one it names.
#[test]
fn every_slide_narrates_what_the_view_shows() {
    let mut harness = common::app_harness();
    let mut problems = Vec::new();
    let mut checked = 0;
    for name in raylab::lesson::lesson_names() {
        harness.state_mut().start_lesson(name).unwrap();
        let slides = harness
            .state()
            .lesson
            .as_ref()
            .unwrap()
            .lesson
            .slides
            .clone();
        for (index, slide) in slides.iter().enumerate() {
            common::wait_for_render(&mut harness);
            harness.run();
            let at = format!("{name} slide {} (“{}”)", index + 1, slide.title);
            let shown = view_values(&harness);
            for (quantity, said) in narrated_values(&slide.narration) {
                checked += 1;
                match shown.iter().find(|(n, _)| *n == quantity) {
                    Some((_, value)) if (value - said).abs() <= 1e-9 * said.abs().max(1.0) => {}
                    Some((_, value)) => problems.push(format!(
                        "{at}: says {quantity} = {said}, the view has {value}"
                    )),
                    None => problems.push(format!(
                        "{at}: says {quantity} = {said}, the view has no {quantity}"
                    )),
                }
            }
            if let Some(facing) = facing(&harness)
                && facing < 0.25
            {
                problems.push(format!(
                    "{at}: the shape is seen edge-on or its ray end-on ({facing:.2})"
                ));
            }
            // The verdict waits for the slide that reaches it (a slide in symbols comes before).
            if matches!(
                harness.state().state.view,
                ViewKind::Triangle | ViewKind::Segments | ViewKind::Parallelogram
            ) && slide.question.is_none()
            {
                let trace = raylab::scene::preset(&slide.scene)
                    .and_then(|scene| raylab::lesson::trace_of(&scene.problem))
                    .unwrap();
                let verdict = trace.verdict_step();
                let here = slide
                    .step
                    .as_ref()
                    .and_then(|id| trace.steps.iter().position(|s| &s.id == id));
                let reached = !slide.symbolic && here.is_some() && here >= verdict;
                let shown = harness
                    .query_all_by(|node| {
                        node.role() == egui::accesskit::Role::Status
                            && node.label().is_some_and(|l| l.starts_with("Verdict:"))
                    })
                    .next()
                    .is_some();
                if shown && !reached {
                    problems.push(format!(
                        "{at}: the verdict shows before the solve reaches it"
                    ));
                } else if reached && !shown {
                    problems.push(format!("{at}: the verdict's slide does not show it"));
                }
            }
            let named_bugs: Vec<raylab::render::bug::Bug> =
                <raylab::render::bug::Bug as strum::IntoEnumIterator>::iter()
                    .filter(|bug| slide.narration.iter().any(|line| line.contains(bug.name())))
                    .collect();
            if !named_bugs.is_empty() {
                let bug = harness.state().state.get::<RenderView>().bug;
                if !bug.is_some_and(|bug| named_bugs.contains(&bug)) {
                    problems.push(format!(
                        "{at}: names {named_bugs:?} and shows the bug {bug:?}"
                    ));
                }
            }
            harness.key_press(egui::Key::Space);
        }
        harness.key_press(egui::Key::Escape);
        harness.run();
    }
    // The lessons do state values: the test is not empty by accident.
    assert!(checked >= 20, "only {checked} narrated values");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
