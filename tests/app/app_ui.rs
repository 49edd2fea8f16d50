//! The app driven like a person would: load presets by their labels, drag the painted handles, move
//! sliders, press buttons, and read what is shown.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use common::{
    app_at, app_view, click_image, load_preset, press, shows_text_containing, step_while,
    wait_for_render,
};
use egui::accesskit::Role;
use egui::{Pos2, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raylab::app::accuracy_view::AccuracyView;
use raylab::app::parallelogram_view::ParallelogramView;
use raylab::app::render_view::RenderView;
use raylab::app::segments_view::{Handle, SegmentsView};
use raylab::app::triangle_view::TriangleView;
use raylab::app::view::LectureView as _;
use raylab::app::{RaylabApp, ViewKind};

fn harness() -> Harness<'static, RaylabApp> {
    common::app_harness()
}

/// Drags from one screen point to another in small steps, as a hand would.
fn drag(harness: &mut Harness<'static, RaylabApp>, from: Pos2, to: Pos2) {
    harness.hover_at(from);
    harness.run();
    harness.drag_at(from);
    harness.run();
    for k in 1..=8 {
        harness.hover_at(from + (to - from) * (k as f32 / 8.0));
        harness.run();
    }
    harness.drop_at(to);
    harness.run();
}

/// Clicks the widgets with these labels one after another (a menu, then its item), the app running
/// after each click.
fn click(harness: &mut Harness<'static, RaylabApp>, labels: &[&str]) {
    for label in labels {
        harness.get_by_label(label).click();
        harness.run();
    }
}

fn shows(harness: &Harness<'static, RaylabApp>, text: &str) -> bool {
    harness.query_all_by_label(text).next().is_some()
}

#[test]
fn dragging_t_and_s_onto_the_crossing_reads_17_22_and_21_22() {
    let mut harness = app_at("Seed 000: segments that cross");
    assert_eq!(harness.state().state.view, ViewKind::Segments);
    let solved = app_view::<SegmentsView>(&harness).solve(raylab::geometry::Precision::Exact);
    let view = app_view::<SegmentsView>(&harness);
    let crossing = view
        .crossing_on_screen(&solved)
        .expect("the lines cross on screen");
    let t_handle = view.handle_on_screen(Handle::T).unwrap();
    // Drop a few pixels off the crossing: the handle snaps onto it.
    drag(&mut harness, t_handle, crossing + Vec2::new(3.0, -2.0));
    assert!(shows(&harness, "t = 17/22"), "t did not land on 17/22");
    let view = app_view::<SegmentsView>(&harness);
    let s_handle = view.handle_on_screen(Handle::S).unwrap();
    let crossing = view.crossing_on_screen(&solved).unwrap();
    drag(&mut harness, s_handle, crossing + Vec2::new(-2.0, 4.0));
    assert!(shows(&harness, "s = 21/22"), "s did not land on 21/22");
    assert!(shows(&harness, "A(t) = B(s): the handles meet"));
}

#[test]
fn a_handle_dragged_elsewhere_does_not_snap() {
    let mut harness = app_at("Seed 000: segments that cross");
    let view = app_view::<SegmentsView>(&harness);
    let t_handle = view.handle_on_screen(Handle::T).unwrap();
    let a2 = view.handle_on_screen(Handle::Endpoint(1)).unwrap();
    // Slide t toward A2 and beyond it onto the faded line.
    let beyond = a2 + (a2 - t_handle) * 0.5;
    drag(&mut harness, t_handle, beyond);
    let t = app_view::<SegmentsView>(&harness).t;
    assert!(t > 1.0 && t < 1.6, "t = {t}");
    assert!(!shows(&harness, "t = 17/22"));
}

#[test]
fn beta_gamma_sliders_move_p_inside_and_outside() {
    let mut harness = app_at("Seed 000: the lecture triangle");
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    for (beta, gamma, verdict) in [
        (0.25, 0.25, "P(β, γ) is inside the triangle"),
        (
            0.25,
            0.9,
            "P(β, γ) is outside: fails β + γ ≤ 1 (beyond edge BC)",
        ),
        (
            -0.2,
            0.5,
            "P(β, γ) is outside: fails β ≥ 0 (beyond edge CA)",
        ),
    ] {
        for (slider, value) in [("β", beta), ("γ", gamma)] {
            harness
                .get_by_role_and_label(Role::Slider, slider)
                .set_value_accesskit(value);
        }
        harness.run();
        assert!(shows(&harness, verdict), "β = {beta}, γ = {gamma}");
    }
}

#[test]
fn solve_slides_to_one_third_one_third_one() {
    let mut harness = app_at("Seed 000: the lecture triangle");
    click(&mut harness, &["Solve"]);
    for text in ["β = 1/3", "γ = 1/3", "t = 1", "P(β, γ) = L + tD: they meet"] {
        assert!(shows(&harness, text), "{text} is not shown");
    }
}

#[test]
fn a_parallel_ray_shows_its_named_state() {
    let harness = app_at("Ray parallel to the triangle's plane");
    let status = app_view::<TriangleView>(&harness).solve(raylab::geometry::Precision::F64);
    assert_eq!(status.float.outcome.status().word(), "parallel");
    assert!(shows(
        &harness,
        "the ray is parallel to the triangle's plane and never meets it (|M| = 0, or negligible in floats)"
    ));
    // Solve has nothing to slide to.
    assert!(harness.get_by_label("Solve").accesskit_node().is_disabled());
}

/// Everything the app copied to the clipboard in the last frame.
fn copied(harness: &Harness<'static, RaylabApp>) -> Vec<String> {
    harness
        .output()
        .platform_output
        .commands
        .iter()
        .filter_map(|c| match c {
            egui::OutputCommand::CopyText(text) => Some(text.clone()),
            _ => None,
        })
        .collect()
}

#[test]
fn copy_as_latex_copies_the_core_latex() {
    let mut harness = app_at("Seed 000: the lecture triangle");
    harness.get_by_label("Copy all as LaTeX").click();
    harness.step();
    let text = copied(&harness).join("\n");
    assert!(
        text.contains("\\beta = \\frac{|M_1|}{|M|} = \\frac{9}{27} = \\frac{1}{3}"),
        "{text}"
    );
    // One step: the first "LaTeX" button copies the system M X = Y.
    harness.get_all_by_label("LaTeX").next().unwrap().click();
    harness.step();
    let step = copied(&harness).join("\n");
    assert!(step.starts_with("M\\,X = Y"), "{step}");
}

#[test]
fn the_app_is_idle_without_input() {
    let mut harness = harness();
    // With no input, frames stop: run() settles instead of hitting its step limit.
    assert!(harness.try_run().is_ok());
    load_preset(&mut harness, "Seed 000: the lecture triangle");
    harness.get_by_label("Solve").click();
    // The animation repaints until it ends, then the app is idle again.
    let steps = harness.try_run().expect("the animation ends");
    assert!(steps > 3, "the slide is animated ({steps} frames)");
    assert!(harness.try_run().expect("idle") <= 1);
}

#[test]
fn keyboard_zoom_works() {
    let mut harness = harness();
    let before = harness.ctx.zoom_factor();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Plus);
    harness.run();
    assert!(harness.ctx.zoom_factor() > before);
    click(&mut harness, &["−"]);
    click(&mut harness, &["−"]);
    assert!(harness.ctx.zoom_factor() < before);
}

#[test]
fn bad_inputs_never_panic() {
    let mut harness = harness();
    let bad_values = [f64::NAN, f64::INFINITY, -f64::INFINITY, 1e300, 0.0];
    for (round, bad) in bad_values.into_iter().enumerate() {
        {
            let state = &mut harness.state_mut().state;
            state.get_mut::<TriangleView>().scene.dir = [bad, 0.0, 0.0];
            state.get_mut::<TriangleView>().scene.a[round % 3] = bad;
            state.get_mut::<TriangleView>().beta = bad;
            state.get_mut::<SegmentsView>().scene.a1 = [bad, bad];
            state.get_mut::<SegmentsView>().t = bad;
            state.get_mut::<ParallelogramView>().scene.e1 = [bad; 3];
            state.get_mut::<ParallelogramView>().t = bad;
        }
        for view in ViewKind::ALL {
            harness.state_mut().state.view = view;
            for precision in <raylab::geometry::Precision as strum::IntoEnumIterator>::iter() {
                harness.state_mut().state.precision = precision;
                // A render this starts runs on a worker: wait for it, not for a number of frames.
                harness.step();
                step_while(&mut harness, 5, "the render did not finish", |h| {
                    h.state().state.get::<RenderView>().is_rendering()
                });
            }
        }
    }
    // A collapsed triangle and a zero direction are named, not crashes.
    load_preset(&mut harness, "Degenerate triangle");
    assert!(shows(
        &harness,
        "A, B and C are collinear: the triangle has no area"
    ));
    harness
        .state_mut()
        .state
        .get_mut::<TriangleView>()
        .scene
        .dir = [0.0; 3];
    harness.run();
    assert!(shows(
        &harness,
        "the direction D is the zero vector: no ray"
    ));
}

#[test]
fn state_survives_a_restart() {
    let mut harness = app_at("Seed 000: alternative 2");
    harness.state_mut().state.get_mut::<TriangleView>().beta = 0.125;
    let saved = ron::to_string(&harness.state().state).unwrap();
    let restored: raylab::app::AppState = ron::from_str(&saved).unwrap();
    assert_eq!(restored.view, ViewKind::Triangle);
    assert_eq!(restored.get::<TriangleView>().scene.dir, [1.0, 0.0, 0.0]);
    assert_eq!(restored.get::<TriangleView>().beta, 0.125);
    // Older or partial state files fall back to defaults field by field.
    let partial: raylab::app::AppState = ron::from_str("(view: Parallelogram)").unwrap();
    assert_eq!(partial.view, ViewKind::Parallelogram);
    // A state saved before the Render view (three titles) still reads, titles and all.
    let before = r#"(view: Triangle, titles: (("a", "1"), ("b", "2"), ("c", "3")))"#;
    let before: raylab::app::AppState = ron::from_str(before).unwrap();
    assert_eq!(before.view, ViewKind::Triangle);
    assert_eq!(
        before.title(ViewKind::Triangle),
        ("b".to_string(), "2".to_string())
    );
    assert!(!before.title(ViewKind::Render).0.is_empty());
}

#[test]
fn scenes_save_and_open_and_bad_files_keep_the_scene() {
    let dir = std::env::temp_dir().join(format!("raylab-ui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mine.ron");
    let mut harness = app_at("Seed 000: alternative 3");
    harness
        .state_mut()
        .state
        .get_mut::<TriangleView>()
        .scene
        .origin = [0.5, 0.25, 0.0];
    harness.state_mut().state.scene_path = path.display().to_string();
    // Save through the File menu and its dialog.
    click(&mut harness, &["File", "Save scene as…"]);
    harness.get_by_role_and_label(Role::Button, "Save").click();
    harness.run();
    assert!(path.exists());
    assert!(harness.state().notice.as_ref().is_some_and(|n| !n.error));

    load_preset(&mut harness, "Seed 000: segments that cross");
    click(&mut harness, &["File", "Open scene…"]);
    harness.get_by_role_and_label(Role::Button, "Open").click();
    harness.run();
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    assert_eq!(
        app_view::<TriangleView>(&harness).scene.origin,
        [0.5, 0.25, 0.0]
    );

    // A malformed file: the error names file, line and column; nothing the user had is lost.
    let bad = dir.join("bad.ron");
    std::fs::write(
        &bad,
        "(\n  title: \"x\",\n  note: \"y\",\n  problem: Triangle((a: (1.0, 2.0))),\n)",
    )
    .unwrap();
    harness.state_mut().state.scene_path = bad.display().to_string();
    let notice = harness.state_mut().run_dialog_path(false);
    assert!(notice.error);
    assert!(notice.text.contains("bad.ron:4:"), "{}", notice.text);
    assert_eq!(
        app_view::<TriangleView>(&harness).scene.origin,
        [0.5, 0.25, 0.0]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Browse… opens the system's file dialog on its own thread; on a machine with no desktop (no
/// session bus for the portal, no display for zenity, as in CI) none is tried, and the typed path
/// stays, with a note saying so. Skipped where a real dialog could open.
#[test]
fn browse_falls_back_to_the_typed_path_without_a_desktop() {
    let desktop = ["DISPLAY", "WAYLAND_DISPLAY", "DBUS_SESSION_BUS_ADDRESS"]
        .iter()
        .any(|name| std::env::var_os(name).is_some())
        || std::env::var_os("XDG_RUNTIME_DIR")
            .is_some_and(|dir| std::path::Path::new(&dir).join("bus").exists());
    if desktop {
        eprintln!("skipped: a desktop is here, and a real file dialog would open");
        return;
    }
    let mut harness = app_at("Seed 000: alternative 3");
    harness.state_mut().state.scene_path = "kept/as/typed.ron".into();
    click(&mut harness, &["File", "Open scene…"]);
    harness.state_mut().notice = None;
    harness.get_by_label("Browse…").click();
    let started = std::time::Instant::now();
    while harness.state().notice.is_none() {
        assert!(
            started.elapsed().as_secs() < 20,
            "the dialog never came back"
        );
        harness.run();
    }
    let notice = harness.state().notice.clone().unwrap();
    assert!(notice.error);
    assert!(
        notice.text.contains("type the path instead"),
        "{}",
        notice.text
    );
    assert_eq!(harness.state().state.scene_path, "kept/as/typed.ron");
    // raylab's own dialog is still open, with its path field and Open button.
    harness.get_by_role_and_label(Role::Button, "Open");
}

#[test]
fn the_accuracy_view_runs_in_the_background_and_loads_hard_cases() {
    let mut harness = harness();
    common::start_study(&mut harness, [40, 40], 1, 0.0);
    // The UI keeps drawing frames while the named worker thread measures.
    step_while(&mut harness, 20, "the study did not finish", |h| {
        h.state().state.get::<AccuracyView>().is_running()
    });
    assert!(!app_view::<AccuracyView>(&harness).records.is_empty());
    assert!(shows(
        &harness,
        "Largest relative error of t against time per test"
    ));
    // Picking the seam family leaves its rows in the table (the picker's button and the rows).
    click(&mut harness, &["seam"]);
    assert!(
        harness.query_all_by_label("seam").count() > 1,
        "the picker and the table list the seam sweep"
    );
    // A hard case loads into the Triangle view with its trace.
    harness
        .get_all_by_label("Load")
        .next()
        .unwrap()
        .scroll_to_me();
    harness.run();
    harness.get_all_by_label("Load").next().unwrap().click();
    harness.run();
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    assert!(shows(&harness, "Hard case: through an edge"));
    // Judged as the gallery judges it: exact arithmetic on the float values.
    assert_eq!(
        app_view::<TriangleView>(&harness).reading,
        raylab::geometry::Reading::FloatValue
    );
}

#[test]
fn a_running_study_can_be_cancelled() {
    let mut harness = harness();
    common::start_study(&mut harness, [3000, 3000], 1, 0.05);
    harness.get_by_label("Cancel").click();
    step_while(&mut harness, 20, "cancel did not stop the study", |h| {
        h.state().state.get::<AccuracyView>().is_running()
    });
    assert!(
        app_view::<AccuracyView>(&harness)
            .status
            .contains("cancelled")
    );
}

/// While a second study runs, the first one's results stay up, and the view says they are the last
/// run's (before, nothing told them from this run's).
#[test]
fn a_new_run_says_the_results_shown_are_the_last_runs() {
    let mut harness = harness();
    common::start_study(&mut harness, [60, 60], 1, 0.01);
    step_while(&mut harness, 20, "the study did not finish", |h| {
        h.state().state.get::<AccuracyView>().is_running()
    });
    let note = "Below: the last run's results, until this run finishes and replaces them";
    assert!(!shows(&harness, note));
    common::start_study(&mut harness, [3000, 3000], 2, 0.05);
    assert!(app_view::<AccuracyView>(&harness).is_running());
    harness.step();
    assert!(shows(&harness, note));
    harness.get_by_label("Cancel").click();
    step_while(&mut harness, 20, "cancel did not stop the study", |h| {
        h.state().state.get::<AccuracyView>().is_running()
    });
    assert!(!shows(&harness, note));
}

#[test]
fn the_render_view_renders_turns_effects_off_and_probes_a_pixel() {
    let mut harness = app_at("Seed 003: facing ratio");
    assert_eq!(harness.state().state.view, ViewKind::Render);
    let stats = app_view::<RenderView>(&harness).rendered().unwrap().stats;
    // The covered pixels of seed 003's own script, and one shading per hit.
    assert_eq!((stats.hits, stats.shading), (38737, 38737));
    assert!(shows_text_containing(
        &harness,
        "38737 of 131072 pixels hit"
    ));

    // Turning facing-ratio off renders again without it: the same hits, no shading at all.
    harness.get_by_label("facing-ratio").click();
    wait_for_render(&mut harness);
    let stats = app_view::<RenderView>(&harness).rendered().unwrap().stats;
    assert_eq!((stats.hits, stats.shading), (38737, 0));
    harness.get_by_label("facing-ratio").click();
    wait_for_render(&mut harness);

    // A click in the triangle: its ray goes into the Triangle view and the step panel.
    click_image(&mut harness, "Correct render", Vec2::new(0.45, 0.5));
    let probe = app_view::<RenderView>(&harness).probe().cloned().unwrap();
    let hit = probe
        .hit
        .expect("the middle of the image is on the triangle");
    assert!(shows_text_containing(&harness, "hit object 1 (triangle)"));
    assert!(shows_text_containing(
        &harness,
        &format!("t = {:.6}", hit.t)
    ));
    assert!(shows_text_containing(&harness, "facing ratio"));
    let triangle = &app_view::<TriangleView>(&harness).scene;
    assert_eq!((triangle.origin, triangle.dir), (probe.origin, probe.dir));
    // The step panel shows the probed ray's solve, ending in a hit.
    assert!(shows(&harness, "1. The system M X = Y"));
    assert!(shows_text_containing(
        &harness,
        "the ray hits the triangle at t ="
    ));
    click(&mut harness, &["Open in Triangle (3D) →"]);
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
}

#[test]
fn a_common_bug_renders_beside_the_correct_image() {
    let mut harness = app_at("Render: common bugs");
    click(&mut harness, &["Compare with a bug:"]);
    harness
        .get_by_role_and_label(Role::Button, "accepting t < 0")
        .click();
    wait_for_render(&mut harness);
    assert!(shows(&harness, "With the bug: accepting t < 0 render"));
    assert!(shows_text_containing(&harness, "objects behind the camera"));
    let render = app_view::<RenderView>(&harness);
    let (correct, buggy) = (
        render.rendered().unwrap(),
        render.rendered_with_bug().unwrap(),
    );
    // The triangle behind the camera shows up: more pixels are hit.
    assert!(
        buggy.stats.hits > correct.stats.hits + 1000,
        "{} vs {}",
        buggy.stats.hits,
        correct.stats.hits
    );
}

/// A pixel probed on the bug's image is that image's ray (accepting t < 0: a hit behind the camera),
/// said so beside the probe and above the steps; the same pixel on the correct image is the correct
/// ray. Before, either image probed the correct one.
#[test]
fn a_probe_reports_the_image_it_was_clicked_on() {
    let mut harness = app_at("Render: common bugs");
    common::pick_bug(&mut harness, "accepting t < 0");
    // A pixel the bug draws (the triangle behind the camera) and the correct image does not.
    let render = app_view::<RenderView>(&harness);
    let (correct, buggy) = (
        &render.rendered().unwrap().image,
        &render.rendered_with_bug().unwrap().image,
    );
    let index = (0..correct.pixels.len())
        .find(|&i| buggy.covered[i] && !correct.covered[i])
        .expect("the bug draws pixels the correct image does not");
    let (row, column) = (index / correct.width, index % correct.width);
    let at = Vec2::new(
        (column as f32 + 0.5) / correct.width as f32,
        (row as f32 + 0.5) / correct.height as f32,
    );
    click_image(&mut harness, "With the bug: accepting t < 0 render", at);
    harness.run();
    let render = app_view::<RenderView>(&harness);
    assert_eq!(render.probed, Some((row, column)));
    let hit = render
        .probe()
        .unwrap()
        .hit
        .expect("the bug's ray hits behind the camera");
    assert!(hit.t < 0.0, "t = {}", hit.t);
    let said =
        format!("Pixel (row {row}, column {column}) of the image with the bug “accepting t < 0”");
    assert!(shows(&harness, &said), "no “{said}”");
    assert!(shows(&harness, &format!("Of {said}: the primary ray")));
    // The same pixel on the correct image: its own ray, which misses.
    click_image(&mut harness, "Correct render", at);
    harness.run();
    let render = app_view::<RenderView>(&harness);
    assert!(render.probe().unwrap().hit.is_none_or(|hit| hit.t > 0.0));
    assert!(shows(
        &harness,
        &format!("Pixel (row {row}, column {column}) of the correct image")
    ));
}

#[test]
fn the_spaces_mode_shows_one_t_in_world_and_object_space() {
    let mut harness = app_at("Render: a transformed object");
    click_image(&mut harness, "Correct render", Vec2::new(0.55, 0.35));
    let hit = app_view::<RenderView>(&harness)
        .probe()
        .unwrap()
        .hit
        .unwrap();
    assert_eq!(hit.object, 0, "the probe is on the stretched sphere");
    click(&mut harness, &["World vs object space"]);
    assert!(shows(&harness, "World space"));
    assert!(shows(&harness, "Object space"));
    let t = format!("t = {:.6}", hit.t);
    let count = harness
        .query_all_by(|node| {
            node.label().is_some_and(|l| l.contains(&t))
                || node.value().is_some_and(|v| v.contains(&t))
        })
        .count();
    assert!(count >= 2, "the same {t} in both spaces ({count} found)");
    assert!(shows_text_containing(&harness, "Normalising D' would make"));
}

#[test]
fn a_render_scene_with_a_missing_mesh_keeps_the_scene() {
    let dir = std::env::temp_dir().join(format!("raylab-ui-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("missing-mesh.ron");
    std::fs::write(
        &bad,
        "(title: \"x\", note: \"y\", problem: Render((width: 8, height: 8, camera: ImagePlane(x: (1.0, -1.0), y: (1.0, -1.0), z: 1.0), objects: [(shape: Mesh(obj: \"meshes/nowhere.obj\"))], effects: [\"coverage\"])))",
    )
    .unwrap();
    let mut harness = app_at("Render: a closed mesh");
    let before = app_view::<RenderView>(&harness).scene.clone();
    harness.state_mut().state.scene_path = bad.display().to_string();
    let notice = harness.state_mut().run_dialog_path(false);
    assert!(notice.error);
    assert!(
        notice.text.contains("meshes/nowhere.obj"),
        "{}",
        notice.text
    );
    assert_eq!(app_view::<RenderView>(&harness).scene, before);
    // The same scene with its mesh beside the file opens: a scene's own files are found there.
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/assets/meshes/octasphere.obj"),
        dir.join("meshes/nowhere.obj"),
    )
    .unwrap();
    let notice = harness.state_mut().run_dialog_path(false);
    assert!(!notice.error, "{}", notice.text);
    assert_ne!(app_view::<RenderView>(&harness).scene, before);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_lesson_plays_with_the_keys_and_a_slide_survives_exploring() {
    let mut harness = harness();
    click(
        &mut harness,
        &["Lessons", "Seed 000: segments, then a ray and a triangle"],
    );
    assert!(shows(&harness, "Slide 1 of 14"));
    assert_eq!(harness.state().state.view, ViewKind::Segments);
    assert!(shows(&harness, "Two segments in parametric form"));
    // The question's answer is revealed on request.
    assert!(!shows_text_containing(&harness, "two equations (x and y)"));
    click(&mut harness, &["Show the answer"]);
    assert!(shows_text_containing(&harness, "two equations (x and y)"));
    // Space, → and Page Down go forward, as a clicker sends them; each slide loads its scene.
    press(
        &mut harness,
        [egui::Key::Space, egui::Key::ArrowRight, egui::Key::PageDown],
    );
    assert!(shows(&harness, "Slide 4 of 14"));
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: s at its solution"
    );
    press(&mut harness, [egui::Key::Space; 4]);
    assert!(shows(&harness, "Slide 8 of 14"));
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: right-hand side Y, column A−B"
    );
    // β = |M1|/|M| slides the β handle to 1/3.
    harness.key_press(egui::Key::ArrowRight);
    harness.run();
    assert!(shows(&harness, "Slide 9 of 14"));
    assert!((app_view::<TriangleView>(&harness).beta - 1.0 / 3.0).abs() < 1e-12);
    // Leave the slide's scene to explore: drag vertex A away, as a student would...
    let lecture_a = app_view::<TriangleView>(&harness).scene.a;
    let a = app_view::<TriangleView>(&harness)
        .vertex_on_screen(0)
        .unwrap();
    drag(&mut harness, a, a + Vec2::new(-60.0, 40.0));
    assert_ne!(
        app_view::<TriangleView>(&harness).scene.a,
        lecture_a,
        "the drag moved A"
    );
    // ...and come back to the slide as the lesson has it.
    click(&mut harness, &["↺ Restore slide"]);
    assert_eq!(app_view::<TriangleView>(&harness).scene.a, lecture_a);
    assert!(shows(&harness, "Slide 9 of 14"));
    // ← and Page Up go back; Esc leaves with the slide's scene open.
    press(&mut harness, [egui::Key::ArrowLeft, egui::Key::PageUp]);
    assert!(shows(&harness, "Slide 7 of 14"));
    harness.key_press(egui::Key::Escape);
    harness.run();
    assert!(harness.state().lesson.is_none());
    assert!(shows(&harness, "Presets"));
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
}

#[test]
fn the_steps_switch_to_symbols_and_back() {
    let mut harness = app_at("Seed 000: the lecture triangle");
    click(&mut harness, &["symbolic"]);
    // Seed 002's expanded |M|, and each merge checked on the lecture's numbers (|M| = 27).
    assert!(shows_text_containing(&harness, "|M| = ax*by*dz - ax*bz*dy"));
    assert!(shows_text_containing(&harness, "✓ on this scene: 27 = 27"));
    assert!(shows_text_containing(
        &harness,
        "merged (q, r and four dot products"
    ));
    // Back to numbers.
    click(&mut harness, &["exact"]);
    assert!(!shows_text_containing(&harness, "ax*by*dz"));
    assert!(shows_text_containing(
        &harness,
        "β = |M1| / |M| = 9 / 27 = 1/3"
    ));
}

#[test]
fn a_practice_problem_is_checked_with_a_hint_when_wrong_and_scored_when_right() {
    let mut harness = harness();
    click(&mut harness, &["Practice", "Triangle: find β, γ and t"]);
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    // The menu opens mixed levels; this test practises hits (the "hit" level in the bar).
    harness.state_mut().start_practice(
        raylab::exercise::Kind::Triangle,
        raylab::exercise::Level::Hit,
    );
    harness.run();
    // Nothing is tried before an answer is given.
    assert!(shows(&harness, "Score: 0 right of 0 tried"));
    // The view keeps the verdict to itself until the answer is right.
    assert!(!painted(&harness, "the ray hits the triangle"));
    let answer = |harness: &mut Harness<'static, RaylabApp>, text: &str| {
        let field = harness.get_by_label("Your answer:");
        field.click();
        harness.run();
        harness.get_by_label("Your answer:").type_text(text);
        harness.run();
        harness.get_by_label("Check").click();
        harness.run();
    };
    // A wrong guess: the hint names the step to look at again.
    answer(&mut harness, "1/2, 1/2, 1");
    assert!(shows_text_containing(
        &harness,
        "Not yet (1 wrong so far). Look again at"
    ));
    assert!(shows(&harness, "Score: 0 right of 1 tried"));
    // The right answer, read from the exact solver's own values (β, γ, t).
    let values: Vec<String> = common::practice_answer(&harness)
        .values
        .iter()
        .map(|v| v.value.fraction())
        .collect();
    // The answer changed to β and γ right, t wrong: the hint is t's step (its own first wrong
    // step), not the step after the first answer's; the same answer again moves on.
    let trace =
        raylab::lesson::trace_of(&harness.state().current_scene().unwrap().problem).unwrap();
    let t_title = &trace.step("t").unwrap().title;
    let clear = |harness: &mut Harness<'static, RaylabApp>| {
        harness
            .state_mut()
            .practice
            .as_mut()
            .unwrap()
            .answer
            .clear();
    };
    // A 0 written after t's value makes it another number (1 → 10, 3/2 → 3/20).
    let t_wrong = format!("{}, {}, {}0", values[0], values[1], values[2]);
    clear(&mut harness);
    answer(&mut harness, &t_wrong);
    let at_t = format!("Look again at “{t_title}”");
    assert!(shows_text_containing(&harness, &at_t), "no “{at_t}”");
    clear(&mut harness);
    answer(&mut harness, &t_wrong);
    assert!(shows_text_containing(&harness, "Not yet (3 wrong so far)"));
    assert!(
        !shows_text_containing(&harness, &at_t),
        "the same answer again stays at t"
    );
    clear(&mut harness);
    answer(&mut harness, &values.join(", "));
    assert!(shows_text_containing(&harness, "Right: hit;"));
    assert!(shows(&harness, "Score: 1 right of 1 tried"));
    // Right: the verdict and the steps are revealed.
    assert!(painted(&harness, "the ray hits the triangle"));
    assert!(shows_text_containing(&harness, "the ray hits the triangle"));
    assert!(!shows(&harness, "Reveal the answer"));
    click(&mut harness, &["New problem"]);
    assert!(shows(&harness, "Score: 1 right of 1 tried"));
    // F5 does not present an unanswered problem (the steps would give it away).
    harness.key_press(egui::Key::F5);
    harness.run();
    assert!(harness.state().presentation.is_none());
    harness.key_press(egui::Key::Escape);
    harness.run();
    assert!(harness.state().practice.is_none());
}

/// True if some text painted in the last frame (labels on a canvas included) contains `needle`.
fn painted(harness: &Harness<'static, RaylabApp>, needle: &str) -> bool {
    any_shape(harness, &|shape| match shape {
        egui::epaint::Shape::Text(text) => text.galley.text().contains(needle),
        _ => false,
    })
}

/// Whether any shape painted in the last frame (inside nested lists too) is one `test` accepts.
fn any_shape(
    harness: &Harness<'static, RaylabApp>,
    test: &dyn Fn(&egui::epaint::Shape) -> bool,
) -> bool {
    fn walk(shape: &egui::epaint::Shape, test: &dyn Fn(&egui::epaint::Shape) -> bool) -> bool {
        match shape {
            egui::epaint::Shape::Vec(shapes) => shapes.iter().any(|s| walk(s, test)),
            other => test(other),
        }
    }
    harness
        .output()
        .shapes
        .iter()
        .any(|clipped| walk(&clipped.shape, test))
}

#[test]
fn an_outcome_is_picked_with_one_click() {
    let mut harness = harness();
    click(&mut harness, &["Practice", "Triangle: find β, γ and t"]);
    // The level picker in the practice bar: a ray beyond one edge.
    click(&mut harness, &["outside"]);
    let outcome = common::practice_answer(&harness).outcome.text();
    assert!(outcome.starts_with("outside "), "{outcome}");
    // The wrong edge first, then the right one.
    let wrong = ["outside AB", "outside BC", "outside CA"]
        .into_iter()
        .find(|o| *o != outcome)
        .unwrap();
    harness.get_by_label(wrong).click();
    harness.run();
    assert!(shows_text_containing(&harness, "Not yet (1 wrong so far)"));
    harness.get_by_label(&outcome).click();
    harness.run();
    assert!(shows_text_containing(
        &harness,
        &format!("Right: {outcome}")
    ));
}

/// Seed 001's slide 4 asks "Does the ray hit the parallelogram?": the view keeps its verdict to
/// itself until "Show the answer", then says it.
#[test]
fn a_lesson_question_is_asked_before_the_view_answers_it() {
    let mut harness = harness();
    click(
        &mut harness,
        &["Lessons", "Seed 001: a ray and a parallelogram"],
    );
    press(&mut harness, [egui::Key::Space; 3]);
    assert!(shows(&harness, "Slide 4 of 5"));
    assert!(shows_text_containing(
        &harness,
        "Does the ray hit the parallelogram?"
    ));
    assert!(!painted(&harness, "the ray hits the parallelogram"));
    assert!(!shows_text_containing(
        &harness,
        "the ray hits the parallelogram"
    ));
    click(&mut harness, &["Show the answer"]);
    assert!(painted(&harness, "the ray hits the parallelogram"));
    // The next slide, without a question, shows its verdict at once.
    harness.key_press(egui::Key::Space);
    harness.run();
    assert!(shows(&harness, "Slide 5 of 5"));
    assert!(painted(&harness, "the ray hits the parallelogram"));
}

/// Practice opens on mixed levels: the bar highlights "mixed", and neither the bar, the problem's
/// note nor the view names the outcome before the answer; problems in a row draw different levels.
#[test]
fn mixed_practice_names_no_outcome_before_the_answer() {
    let mut harness = harness();
    click(&mut harness, &["Practice", "Triangle: find β, γ and t"]);
    let mut levels = std::collections::BTreeSet::new();
    for _ in 0..8 {
        let run = harness.state().practice.clone().unwrap();
        assert!(run.mixed);
        levels.insert(run.level.name());
        let selected: Vec<String> = harness
            .query_all_by(|node| node.toggled() == Some(egui::accesskit::Toggled::True))
            .filter_map(|node| node.accesskit_node().label())
            .collect();
        assert_eq!(selected, ["mixed"], "only mixed is highlighted");
        // The verdicts' words (the panel lists every outcome as a choice, so those words are not
        // searched for).
        for verdict in [
            "the ray hits the triangle",
            "the ray meets the plane outside",
            "behind the ray's origin",
            "the ray is parallel to",
            "the triangle has no area",
        ] {
            assert!(
                !painted(&harness, verdict),
                "{verdict} painted before the answer"
            );
        }
        // The scene's note (its title line once practice is left) names no level either.
        let (_, note) = harness.state().state.title(ViewKind::Triangle);
        assert_eq!(note, "A problem: predict, then check.");
        click(&mut harness, &["New problem"]);
    }
    assert!(levels.len() >= 3, "{levels:?}");
    // Revealed, the outcome is named.
    let answer = common::practice_answer(&harness).text();
    click(&mut harness, &["Reveal the answer"]);
    let outcome = answer.split(';').next().unwrap().to_string();
    assert!(
        shows_text_containing(&harness, &outcome),
        "{outcome} after the reveal"
    );
}

/// The note that a lesson was left is said in the view the lesson left, not carried into other tabs.
#[test]
fn the_left_lesson_note_stays_with_its_view() {
    let mut harness = harness();
    click(
        &mut harness,
        &["Lessons", "Seed 000: segments, then a ray and a triangle"],
    );
    harness.key_press(egui::Key::Escape);
    harness.run();
    assert!(shows_text_containing(&harness, "Left “Seed 000"));
    click(&mut harness, &["Triangle (3D)"]);
    assert!(!shows_text_containing(&harness, "Left “Seed 000"));
    click(&mut harness, &["Segments (2D)"]);
    assert!(shows_text_containing(&harness, "Left “Seed 000"));
}

/// A probed ray's steps are in f64 by default (the app's lecture views stay exact), and the step
/// panel's picker changes the probe's precision alone: exact reads the renderer's floats in full.
#[test]
fn a_probe_steps_in_f64_with_an_exact_toggle() {
    use raylab::geometry::Precision;
    let mut harness = app_at("Render: a transformed object");
    assert_eq!(harness.state().state.precision, Precision::Exact);
    click_image(&mut harness, "Correct render", Vec2::new(0.55, 0.35));
    assert_eq!(
        app_view::<RenderView>(&harness).probe_precision,
        Precision::F64
    );
    let trace_precision = |harness: &Harness<'static, RaylabApp>| {
        let solved = harness.state().state.tab(ViewKind::Render).unwrap();
        let view = &solved.view;
        view.solve_frame(view.own_precision().unwrap())
            .trace()
            .map(|t| t.precision)
    };
    assert_eq!(trace_precision(&harness), Some(Precision::F64));
    let selected = |harness: &Harness<'static, RaylabApp>| -> Vec<String> {
        harness
            .query_all_by(|node| node.toggled() == Some(egui::accesskit::Toggled::True))
            .filter_map(|node| node.accesskit_node().label())
            .collect()
    };
    assert!(selected(&harness).contains(&"f64".to_string()));
    click(&mut harness, &["exact"]);
    assert_eq!(
        app_view::<RenderView>(&harness).probe_precision,
        Precision::Exact
    );
    assert_eq!(trace_precision(&harness), Some(Precision::Exact));
    click(&mut harness, &["f32"]);
    assert_eq!(
        app_view::<RenderView>(&harness).probe_precision,
        Precision::F32
    );
    // The lecture views keep theirs.
    assert_eq!(harness.state().state.precision, Precision::Exact);
}

/// Whether a line in this colour was painted in the last frame.
fn painted_line_in(harness: &Harness<'static, RaylabApp>, color: egui::Color32) -> bool {
    any_shape(harness, &|shape| match shape {
        egui::epaint::Shape::LineSegment { stroke, .. } => stroke.color == color,
        _ => false,
    })
}

/// A degenerate practice triangle is drawn as any triangle until the answer: its edges are not
/// marked as a failed check (they were, in the miss colour, giving the outcome away).
#[test]
fn a_degenerate_practice_triangle_is_not_marked_before_the_answer() {
    use raylab::app::widgets::palette;
    let mut harness = harness();
    harness.state_mut().start_practice(
        raylab::exercise::Kind::Triangle,
        raylab::exercise::Level::Degenerate,
    );
    harness.run();
    assert!(!painted_line_in(&harness, palette::OUTSIDE));
    click(&mut harness, &["Reveal the answer"]);
    assert!(painted_line_in(&harness, palette::OUTSIDE));
    assert!(painted(&harness, "degenerate: A, B, C on one line"));
}
