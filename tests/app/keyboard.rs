//! raylab without a mouse, as a student who cannot drag or cannot see uses it: Tab reaches the
//! canvas's handles, the arrows move them, Enter solves; the accessibility tree names every handle
//! with its value, reads each step whole and announces the verdict; a lesson and a practice problem
//! go from start to end with keys alone.

use crate::common;

use common::app_view;
use egui::Key;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raylab::app::segments_view::SegmentsView;
use raylab::app::triangle_view::TriangleView;
use raylab::app::{RaylabApp, ViewKind};

/// The label of the node with the keyboard focus, if any.
fn focused(harness: &Harness<'static, RaylabApp>) -> Option<String> {
    harness
        .query_all_by(|node| node.is_focused())
        .next()
        .map(|node| {
            let access = node.accesskit_node();
            access.label().or(access.value()).unwrap_or_default()
        })
}

/// Presses Tab until the focused node's label satisfies `wanted` (at most 300 presses).
fn tab_to(harness: &mut Harness<'static, RaylabApp>, what: &str, wanted: impl Fn(&str) -> bool) {
    for _ in 0..300 {
        if focused(harness).is_some_and(|label| wanted(&label)) {
            return;
        }
        harness.key_press(Key::Tab);
        harness.run();
    }
    panic!(
        "Tab never reached {what} (last focus: {:?})",
        focused(harness)
    );
}

/// Opens a top-bar menu and one of its items with Tab and Enter alone.
fn open_from_menu(harness: &mut Harness<'static, RaylabApp>, menu: &str, item: &str) {
    tab_to(harness, menu, |l| l == menu);
    press(harness, egui::Modifiers::NONE, Key::Enter);
    tab_to(harness, item, |l| l == item);
    press(harness, egui::Modifiers::NONE, Key::Enter);
}

/// Presses a key, with modifiers, and lets the app settle.
fn press(harness: &mut Harness<'static, RaylabApp>, modifiers: egui::Modifiers, key: Key) {
    harness.key_press_modifiers(modifiers, key);
    harness.run();
}

/// Presses a key while renders run on a worker thread: the app asks for frames until they finish, so
/// it is stepped (the key's frame and one more) rather than run to rest.
fn press_while_rendering(
    harness: &mut Harness<'static, RaylabApp>,
    modifiers: egui::Modifiers,
    key: Key,
) {
    harness.key_press_modifiers(modifiers, key);
    harness.step();
    harness.step();
}

/// The text a screen reader reads for the step whose spoken text starts with `start`.
fn step_text(harness: &Harness<'static, RaylabApp>, start: &str) -> String {
    harness
        .query_all_by(|node| {
            node.role() == Role::Group && node.label().is_some_and(|l| l.starts_with(start))
        })
        .next()
        .and_then(|node| node.accesskit_node().label())
        .unwrap_or_else(|| {
            let all: Vec<String> = harness
                .query_all_by(|node| node.role() == Role::Group)
                .filter_map(|n| n.accesskit_node().label())
                .collect();
            panic!("no step reads “{start}…”: {all:#?}")
        })
}

/// The verdict a screen reader announces (a polite live region).
fn verdict(harness: &Harness<'static, RaylabApp>) -> String {
    let node = harness
        .query_all_by(|node| node.role() == Role::Status)
        .next()
        .expect("a verdict in the tree");
    assert_eq!(
        node.accesskit_node().live(),
        egui::accesskit::Live::Polite,
        "the verdict is announced when it changes"
    );
    node.accesskit_node().label().unwrap_or_default()
}

#[test]
fn tab_reaches_vertex_a_the_arrows_move_it_and_the_steps_read_the_new_values() {
    let mut harness = common::app_at("Seed 000: the lecture triangle");
    // The lecture's |M| = 27, read as one text, not cell by cell.
    let before = step_text(&harness, "Step 8. |M|");
    assert!(before.ends_with("\n= 27"), "{before}");
    tab_to(&mut harness, "vertex A", |l| l.starts_with("vertex A at"));
    assert_eq!(focused(&harness).unwrap(), "vertex A at (3, 0, 0)");
    // → then ↑: A moves a quarter along the axes nearest the screen's right and up.
    press(&mut harness, egui::Modifiers::NONE, Key::ArrowRight);
    press(&mut harness, egui::Modifiers::NONE, Key::ArrowUp);
    let a = app_view::<TriangleView>(&harness).scene.a;
    let moved: Vec<f64> = a.iter().zip([3.0, 0.0, 0.0]).map(|(x, y)| x - y).collect();
    assert_eq!(
        moved.iter().filter(|d| d.abs() == 0.25).count(),
        2,
        "two coordinates moved by 0.25: {a:?}"
    );
    // Shift + arrow: a fine step of 0.05.
    press(&mut harness, egui::Modifiers::SHIFT, Key::ArrowRight);
    let fine = app_view::<TriangleView>(&harness).scene.a;
    let step: f64 = fine.iter().zip(a).map(|(x, y)| (x - y).abs()).sum();
    assert!((step - 0.05).abs() < 1e-12, "{a:?} → {fine:?}");
    // The handle keeps the focus, and its name follows the value.
    let name = focused(&harness).unwrap();
    let text: Vec<String> = fine
        .iter()
        .map(|x| raylab::trace::format_float(*x, raylab::geometry::Precision::F64))
        .collect();
    assert_eq!(name, format!("vertex A at ({})", text.join(", ")));
    // The steps read the new solve: |M| is the exact determinant of the moved triangle.
    let after = step_text(&harness, "Step 8. |M|");
    let expected = exact_determinant(fine);
    let result = after.lines().last().unwrap_or_default();
    assert_eq!(
        result.trim_start_matches("= ").split_whitespace().next(),
        Some(expected.as_str()),
        "{after}"
    );
    // Enter solves: β, γ and t slide to the solution.
    press(&mut harness, egui::Modifiers::NONE, Key::Enter);
    common::step_while(&mut harness, 20, "the solve did not slide", |h| {
        app_view::<TriangleView>(h).animation.is_some()
    });
    assert!(common::shows_text_containing(&harness, "they meet"));
}

/// |M| = det[A−B | A−C | D] of the lecture triangle with vertex A at `a`, in exact arithmetic from
/// the numbers as typed (2.7 is 27/10, as the app reads them), written as the steps write it.
fn exact_determinant(a: [f64; 3]) -> String {
    use num_rational::BigRational;
    let q = |x: f64| {
        let typed = format!("{x}");
        let (whole, decimals) = typed.split_once('.').unwrap_or((&typed, ""));
        let digits: num_bigint::BigInt = format!("{whole}{decimals}").parse().unwrap();
        let scale = num_bigint::BigInt::from(10u32).pow(decimals.len() as u32);
        BigRational::new(digits, scale)
    };
    let [b, c, d] = [[0.0, 3.0, 0.0], [0.0, 0.0, 3.0], [1.0, 1.0, 1.0]];
    let column = |p: [f64; 3]| [0, 1, 2].map(|i| q(a[i]) - q(p[i]));
    let (u, v, w) = (column(b), column(c), d.map(q));
    let det = &u[0] * (&v[1] * &w[2] - &v[2] * &w[1]) - &v[0] * (&u[1] * &w[2] - &u[2] * &w[1])
        + &w[0] * (&u[1] * &v[2] - &u[2] * &v[1]);
    det.to_string()
}

#[test]
fn every_handle_of_every_lecture_preset_is_named_with_its_value() {
    let mut harness = common::app_harness();
    let expected = |kind: ViewKind| -> &[&str] {
        match kind {
            ViewKind::Segments => &[
                "endpoint A1 at",
                "endpoint A2 at",
                "endpoint B1 at",
                "endpoint B2 at",
                "A(t) at t =",
                "B(s) at s =",
            ],
            ViewKind::Triangle => &[
                "vertex A at",
                "vertex B at",
                "vertex C at",
                "ray origin L at",
                "direction D =",
                "P(β, γ) at β =",
                "L + tD at t =",
            ],
            ViewKind::Parallelogram => &[
                "corner c at",
                "edge e1 =",
                "edge e2 =",
                "ray origin o at",
                "direction d =",
                "p(α, β) at α =",
                "o + t d at t =",
            ],
            _ => &[],
        }
    };
    let mut checked = 0;
    for name in raylab::scene::preset_names() {
        let scene = raylab::scene::preset(name).expect("a shipped preset");
        if matches!(scene.problem, raylab::scene::Problem::Render(_)) {
            continue;
        }
        harness
            .state_mut()
            .load_scene(&scene)
            .expect("presets load");
        harness.run();
        let kind = harness.state().state.view;
        assert!(!expected(kind).is_empty(), "{name} opened {kind:?}");
        for prefix in expected(kind) {
            let named = harness
                .query_all_by(|node| {
                    node.role() == Role::Slider
                        && node.label().is_some_and(|l| l.starts_with(prefix))
                })
                .count();
            assert_eq!(named, 1, "{name}: no handle named “{prefix} …”");
        }
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} lecture presets");
}

#[test]
fn moving_an_endpoint_by_keys_changes_the_announced_verdict() {
    let mut harness = common::app_at("Seed 000: segments that cross");
    assert_eq!(
        verdict(&harness),
        "Verdict: the segments cross at t = 17/22, s = 21/22"
    );
    // B2 = (5, 1) goes up two quarters at a time until segment B no longer reaches A.
    tab_to(&mut harness, "endpoint B2", |l| {
        l.starts_with("endpoint B2 at")
    });
    for _ in 0..8 {
        press(&mut harness, egui::Modifiers::NONE, Key::ArrowUp);
    }
    assert_eq!(app_view::<SegmentsView>(&harness).scene.b2, [5.0, 3.0]);
    assert_eq!(focused(&harness).unwrap(), "endpoint B2 at (5, 3)");
    let announced = verdict(&harness);
    assert!(
        announced.starts_with("Verdict: the segments do not meet"),
        "{announced}"
    );
    // The t handle: the arrows step t by 0.05 and land on the crossing's t, as a drag snaps.
    let mut harness = common::app_at("Seed 000: segments that cross");
    tab_to(&mut harness, "A(t)", |l| l.starts_with("A(t) at"));
    for _ in 0..10 {
        press(&mut harness, egui::Modifiers::NONE, Key::ArrowRight);
    }
    // 0.25 + 10 × 0.05 = 0.75 lies within half a step of 17/22: it lands there.
    assert_eq!(app_view::<SegmentsView>(&harness).t, 17.0 / 22.0);
    // Esc lets the handle go; the arrows then move the focus, not the handle.
    press(&mut harness, egui::Modifiers::NONE, Key::Escape);
    assert!(focused(&harness).is_none());
}

#[test]
fn the_keys_window_opens_with_question_mark_and_lists_the_handle_keys() {
    let mut harness = common::app_harness();
    harness.run();
    harness.event(egui::Event::Text("?".into()));
    harness.run();
    assert!(harness.state().keys_open);
    assert!(common::shows_text_containing(&harness, "Shift + arrows"));
    assert!(common::shows_text_containing(&harness, "Tab / Shift+Tab"));
    press(&mut harness, egui::Modifiers::NONE, Key::Escape);
    assert!(!harness.state().keys_open);
    // F1 too, and the top bar's Keys button.
    press(&mut harness, egui::Modifiers::NONE, Key::F1);
    assert!(harness.state().keys_open);
}

#[test]
fn a_lesson_plays_from_start_to_end_with_keys_alone() {
    let mut harness = common::app_harness();
    harness.run();
    open_from_menu(
        &mut harness,
        "Lessons",
        "Seed 000: segments, then a ray and a triangle",
    );
    assert!(harness.state().lesson.is_some(), "Enter opened the lesson");
    assert!(harness.query_by_label("Slide 1 of 14").is_some());
    // The first slide asks a question: Tab to "Show the answer", Enter shows it.
    tab_to(&mut harness, "Show the answer", |l| l == "Show the answer");
    press(&mut harness, egui::Modifiers::NONE, Key::Enter);
    assert!(common::shows_text_containing(
        &harness,
        "two equations (x and y)"
    ));
    // Space to the end: every slide, then Esc leaves.
    for slide in 2..=14 {
        press(&mut harness, egui::Modifiers::NONE, Key::Space);
        let label = format!("Slide {slide} of 14");
        assert!(harness.query_by_label(&label).is_some(), "no {label}");
    }
    press(&mut harness, egui::Modifiers::NONE, Key::Escape);
    assert!(harness.state().lesson.is_none());
}

#[test]
fn a_practice_problem_is_answered_with_keys_alone() {
    let mut harness = common::app_harness();
    harness.run();
    open_from_menu(&mut harness, "Practice", "Triangle: find β, γ and t");
    assert!(harness.state().practice.is_some(), "Enter opened practice");
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    // Enter on a handle does not solve a practice problem for the student.
    tab_to(&mut harness, "P(β, γ)", |l| l.starts_with("P(β, γ) at"));
    let before = app_view::<TriangleView>(&harness).beta;
    press(&mut harness, egui::Modifiers::NONE, Key::Enter);
    harness.run();
    assert_eq!(app_view::<TriangleView>(&harness).beta, before);
    assert!(app_view::<TriangleView>(&harness).animation.is_none());
    // Tab to the answer box, type the exact answer (the outcome and the values: the menu's
    // levels are mixed), Enter checks it.
    tab_to(&mut harness, "the answer box", |l| l == "Your answer:");
    let answer = common::practice_answer(&harness).text();
    harness.event(egui::Event::Text(answer));
    harness.run();
    press(&mut harness, egui::Modifiers::NONE, Key::Enter);
    assert!(
        common::shows_text_containing(&harness, "Right:"),
        "the typed answer was checked"
    );
    assert!(
        harness
            .query_by_label("Score: 1 right of 1 tried")
            .is_some()
    );
}

#[test]
fn a_render_is_probed_with_keys_and_the_probe_reads_as_text() {
    let mut harness = common::app_at("Seed 003: facing ratio");
    tab_to(&mut harness, "the render's image", |l| {
        l == "Correct render"
    });
    // Enter probes the centre pixel; Shift + → the next one over.
    press(&mut harness, egui::Modifiers::NONE, Key::Enter);
    let view = app_view::<raylab::app::render_view::RenderView>(&harness);
    let (height, width) = {
        let image = &view.rendered().expect("a render").image;
        (image.height, image.width)
    };
    assert_eq!(view.probed, Some((height / 2, width / 2)));
    press(&mut harness, egui::Modifiers::SHIFT, Key::ArrowRight);
    let view = app_view::<raylab::app::render_view::RenderView>(&harness);
    assert_eq!(view.probed, Some((height / 2, width / 2 + 1)));
    let hit = view
        .probe()
        .and_then(|p| p.hit)
        .expect("the centre is on the triangle");
    // What the probe found is text a screen reader reads.
    assert!(common::shows_text_containing(
        &harness,
        "hit object 1 (triangle)"
    ));
    assert!(common::shows_text_containing(
        &harness,
        &format!("t = {:.6}", hit.t)
    ));
}

#[test]
fn each_row_of_the_accuracy_table_reads_as_one_sentence() {
    let mut harness = common::app_harness();
    harness.run();
    common::start_study(&mut harness, [40, 40], 1, 0.0);
    common::step_while(&mut harness, 20, "the study did not finish", |h| {
        h.state()
            .state
            .get::<raylab::app::accuracy_view::AccuracyView>()
            .is_running()
    });
    let records = &app_view::<raylab::app::accuracy_view::AccuracyView>(&harness).records;
    let first = &records[0];
    let expected = format!(
        "{} in {}, {} rays: {} tests, {} wrong, {} cracks",
        first.method,
        first.precision,
        first.family,
        first.tests,
        first.wrong_decisions,
        first.cracks
    );
    let rows: Vec<String> = harness
        .query_all_by(|node| node.role() == Role::Row)
        .filter_map(|node| node.accesskit_node().label())
        .collect();
    assert!(
        rows.iter().any(|row| row.starts_with(&expected)),
        "no row reads “{expected}…”: {rows:#?}"
    );
}

#[test]
fn the_render_camera_orbits_pans_and_resets_from_the_keyboard() {
    use raylab::app::render_view::RenderView;
    let mut harness = common::app_at("Effect: shadows");
    tab_to(&mut harness, "the render's image", |l| {
        l == "Correct render"
    });
    assert!(app_view::<RenderView>(&harness).camera.is_none());
    // → orbits: the camera moves about its target, at the same distance.
    press_while_rendering(&mut harness, egui::Modifiers::NONE, Key::ArrowRight);
    let scene = app_view::<RenderView>(&harness).scene.camera.clone();
    let orbited = app_view::<RenderView>(&harness)
        .camera
        .clone()
        .expect("→ moved the camera");
    let (distance, ..) = scene.orbit_angles().unwrap();
    let (moved, ..) = orbited.orbit_angles().unwrap();
    assert!((distance - moved).abs() < 1e-9 * distance);
    // Ctrl + → pans: the camera moves again, and keeps its distance to its (moved) target.
    press_while_rendering(&mut harness, egui::Modifiers::CTRL, Key::ArrowRight);
    let panned = app_view::<RenderView>(&harness).camera.clone().unwrap();
    assert_ne!(panned, orbited);
    // R goes back to the scene's camera; every frame rendered meanwhile is a real one.
    press_while_rendering(&mut harness, egui::Modifiers::NONE, Key::R);
    assert!(app_view::<RenderView>(&harness).camera.is_none());
    common::wait_for_render(&mut harness);
}
