//! Pictures of the app, rendered on the CPU (wgpu on Mesa's lavapipe): image snapshots that fail when a
//! view changes, and the README's screenshots.
//!
//! `RAYLAB_SCREENSHOTS=1 cargo test --test app screenshots::` rewrites `assets/screenshots/*.png`;
//! `UPDATE_SNAPSHOTS=1 cargo test --test app screenshots::` accepts changed snapshots in `tests/snapshots/`.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use common::{app_view, click_image, load_preset, press, wait_for_render};
use egui::Vec2;
use egui_kittest::kittest::Queryable;
use egui_kittest::{Harness, SnapshotOptions};
use raylab::app::RaylabApp;
use raylab::app::accuracy_view::AccuracyView;

fn harness(size: Vec2, pixels_per_point: f32, theme: egui::Theme) -> Harness<'static, RaylabApp> {
    Harness::builder()
        .with_size(size)
        .with_pixels_per_point(pixels_per_point)
        .with_theme(theme)
        .with_max_steps(200)
        .wgpu()
        .build_eframe(|cc| {
            raylab::app::set_style(&cc.egui_ctx);
            RaylabApp::new()
        })
}

/// The projector's 1280x800 pixels at 150%, in the light theme.
fn zoomed_projector() -> Harness<'static, RaylabApp> {
    harness(Vec2::new(1280.0, 800.0) / 1.5, 1.5, egui::Theme::Light)
}

/// The preset each view is shown with, and what is done before the picture.
const VIEWS: [(&str, &str, Option<&str>); 4] = [
    (
        "segments",
        "Seed 000: segments that cross",
        Some("Go to intersection"),
    ),
    ("triangle", "Seed 000: the lecture triangle", None),
    (
        "triangle-outside",
        "Ray missing the triangle",
        Some("Solve"),
    ),
    ("parallelogram", "Seed 001: ray and parallelogram", None),
];

fn prepare(harness: &mut Harness<'static, RaylabApp>, title: &str, button: Option<&str>) {
    load_preset(harness, title);
    if let Some(button) = button {
        harness.get_by_label(button).click();
        harness.run();
    }
    harness.remove_cursor();
    harness.run();
}

#[test]
fn views_match_their_snapshots() {
    let options = SnapshotOptions::default()
        .threshold(2.0)
        .max_failed_pixels(400);
    let mut results = egui_kittest::SnapshotResults::new();
    for (name, title, button) in VIEWS {
        let mut harness = harness(Vec2::new(1280.0, 800.0), 1.0, egui::Theme::Dark);
        prepare(&mut harness, title, button);
        harness.snapshot_options(name, &options);
        results.extend_harness(&mut harness);
    }
    results.unwrap();
}

#[test]
fn readme_screenshots() {
    let write = std::env::var_os("RAYLAB_SCREENSHOTS").is_some();
    let folder = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/screenshots");
    let shots = [
        ("segments", VIEWS[0], 1.0, egui::Theme::Light),
        ("triangle", VIEWS[1], 1.0, egui::Theme::Light),
        ("triangle-outside", VIEWS[2], 1.0, egui::Theme::Dark),
        ("parallelogram", VIEWS[3], 1.0, egui::Theme::Light),
        // A 1280x800 projector at 150% and 200%: the same window, 853x533 and 640x400 points.
        ("projector-150", VIEWS[1], 1.5, egui::Theme::Light),
        ("projector-200", VIEWS[1], 2.0, egui::Theme::Dark),
    ];
    for (file, (_, title, button), scale, theme) in shots {
        let size = Vec2::new(1280.0, 800.0) / scale;
        let mut harness = harness(size, scale, theme);
        prepare(&mut harness, title, button);
        let image = harness.render().expect("the CPU renderer draws");
        assert_eq!(image.width(), 1280);
        // Not a blank picture: many distinct colours.
        let distinct: std::collections::HashSet<[u8; 4]> = image.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 50, "{file} looks blank");
        if write {
            std::fs::create_dir_all(folder).unwrap();
            image.save(format!("{folder}/{file}.png")).unwrap();
        }
    }
    presentation_screenshot(folder, write);
    accessibility_screenshots(folder, write);
    lesson_screenshot(folder, write);
    practice_screenshot(folder, write);
    if write {
        accuracy_screenshot(folder);
    }
    render_screenshots(folder, write);
}

/// The README's Accessibility pictures: the Triangle view with P(β, γ) outside, its handle focused
/// from the keyboard (the ring), and the same picture as a student with deuteranopia sees it
/// (Machado et al.'s simulation, pixel by pixel).
fn accessibility_screenshots(folder: &str, write: bool) {
    use egui_kittest::kittest::NodeT as _;
    use raylab::app::widgets::palette::vision::{Deficiency, simulate};
    let mut harness = harness(Vec2::new(1280.0, 800.0), 1.0, egui::Theme::Light);
    load_preset(&mut harness, "Ray missing the triangle");
    harness.remove_cursor();
    for _ in 0..300 {
        let focused = harness
            .query_all_by(|node| node.is_focused())
            .next()
            .and_then(|node| node.accesskit_node().label());
        if focused.is_some_and(|label| label.starts_with("P(β, γ) at")) {
            break;
        }
        harness.key_press(egui::Key::Tab);
        harness.run();
    }
    // Two steps right and up: P moves in β and γ, its name follows.
    press(&mut harness, [egui::Key::ArrowRight, egui::Key::ArrowUp]);
    let normal = harness.render().expect("the CPU renderer draws");
    let mut seen = normal.clone();
    for pixel in seen.pixels_mut() {
        let [r, g, b, a] = pixel.0;
        let shown = simulate(egui::Color32::from_rgb(r, g, b), Deficiency::Deuteranopia);
        pixel.0 = [shown.r(), shown.g(), shown.b(), a];
    }
    // The simulation moved colours: the picture is not the same.
    assert_ne!(normal.as_raw(), seen.as_raw());
    if write {
        normal.save(format!("{folder}/accessibility.png")).unwrap();
        seen.save(format!("{folder}/accessibility-deuteranopia.png"))
            .unwrap();
    }
}

/// The Render view: the transformed object probed, a common bug beside the correct image, and a probe
/// whose ray went into the step panel.
fn render_screenshots(folder: &str, write: bool) {
    let shots: [(&str, &str, Option<&str>, Vec2); 3] = [
        (
            "render",
            "Render: a transformed object",
            None,
            Vec2::new(0.55, 0.35),
        ),
        (
            "render-bug",
            "Render: common bugs",
            Some("accepting t < 0"),
            Vec2::new(0.3, 0.5),
        ),
        (
            "render-probe",
            "Seed 003: facing ratio",
            None,
            Vec2::new(0.45, 0.5),
        ),
    ];
    for (file, title, bug, at) in shots {
        let mut harness = harness(Vec2::new(1280.0, 800.0), 1.0, egui::Theme::Light);
        load_preset(&mut harness, title);
        wait_for_render(&mut harness);
        if let Some(bug) = bug {
            common::pick_bug(&mut harness, bug);
        }
        click_image(&mut harness, "Correct render", at);
        harness.remove_cursor();
        harness.run();
        let image = harness.render().expect("the CPU renderer draws");
        if write {
            image.save(format!("{folder}/{file}.png")).unwrap();
        }
    }
}

/// The Accuracy view after a small study (only when rewriting the screenshots: it takes a while).
fn accuracy_screenshot(folder: &str) {
    let mut harness = harness(Vec2::new(1280.0, 800.0), 1.0, egui::Theme::Light);
    common::start_study(&mut harness, [400, 600], 2019, 0.01);
    while app_view::<AccuracyView>(&harness).is_running() {
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.step();
    }
    harness.state_mut().state.show_steps = false;
    harness.run();
    harness.remove_cursor();
    harness.run();
    let image = harness.render().expect("the CPU renderer draws");
    image.save(format!("{folder}/accuracy.png")).unwrap();
}

/// Presentation mode on the projector at 150%: the lecture triangle at step 5 (M1), its Y and A−B
/// highlighted in the view.
fn presentation_screenshot(folder: &str, write: bool) {
    let mut harness = zoomed_projector();
    prepare(&mut harness, VIEWS[1].1, None);
    harness.key_press(egui::Key::F5);
    harness.run();
    advance_and_save(
        &mut harness,
        4,
        "Step 5 of 23",
        folder,
        "presentation",
        write,
    );
}

/// A lesson on the projector at 150%: seed 000's slide on β = |M1|/|M|, with its narration and step.
fn lesson_screenshot(folder: &str, write: bool) {
    let mut harness = zoomed_projector();
    harness.run();
    harness
        .state_mut()
        .start_lesson("seed000-segments-and-triangle")
        .expect("a shipped lesson");
    advance_and_save(&mut harness, 8, "Slide 9 of 14", folder, "lesson", write);
}

/// Practice at 150%: a triangle problem beyond an edge, after a wrong answer and its hint.
fn practice_screenshot(folder: &str, write: bool) {
    let mut harness = zoomed_projector();
    harness.run();
    harness.state_mut().start_practice(
        raylab::exercise::Kind::Triangle,
        raylab::exercise::Level::Outside,
    );
    harness.run();
    harness.get_by_label("Your answer:").click();
    harness.run();
    harness.get_by_label("Your answer:").type_text("hit");
    harness.run();
    harness.get_by_label("Check").click();
    harness.run();
    save_shot(&mut harness, folder, "practice", write);
}

/// Presses Space `presses` times, as the clicker's "next" does, checks that the screen has come to
/// `shown` (a step or slide counter), and saves it as [`save_shot`] does.
fn advance_and_save(
    harness: &mut Harness<'static, RaylabApp>,
    presses: usize,
    shown: &str,
    folder: &str,
    name: &str,
    write: bool,
) {
    press(harness, std::iter::repeat_n(egui::Key::Space, presses));
    assert!(
        harness.query_by_label(shown).is_some(),
        "{shown:?} not shown"
    );
    save_shot(harness, folder, name, write);
}

/// The picture of a 1280-pixel-wide screen as it stands, with the pointer away, saved as
/// `folder/name.png` when the screenshots are being rewritten.
fn save_shot(harness: &mut Harness<'static, RaylabApp>, folder: &str, name: &str, write: bool) {
    harness.remove_cursor();
    harness.run();
    let image = harness.render().expect("the CPU renderer draws");
    assert_eq!(image.width(), 1280);
    if write {
        image.save(format!("{folder}/{name}.png")).unwrap();
    }
}
