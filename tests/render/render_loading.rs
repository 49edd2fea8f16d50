//! A render scene with a large mesh loads in the background: the Render view shows the load's
//! progress and a Cancel button, stays responsive, then renders; a cancelled load says so.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use common::{app_view, shows_text_containing};

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raylab::app::RaylabApp;
use raylab::app::render_view::RenderView;

fn harness() -> Harness<'static, RaylabApp> {
    common::app_harness()
}

/// A scene file whose one object is a grid of `n` × `n` squares (2n² triangles) in its own OBJ
/// file beside it, in a fresh folder.
fn grid_scene(n: usize) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("raylab-ui-loading-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let mut obj = String::new();
    for row in 0..=n {
        for column in 0..=n {
            let (x, y) = (column as f64 / n as f64, row as f64 / n as f64);
            let _ = writeln!(obj, "v {:.5} {:.5} 3", 2.0 * x - 1.0, 2.0 * y - 1.0);
        }
    }
    let at = |row: usize, column: usize| row * (n + 1) + column + 1;
    for row in 0..n {
        for column in 0..n {
            let (a, b) = (at(row, column), at(row, column + 1));
            let (c, d) = (at(row + 1, column + 1), at(row + 1, column));
            let _ = writeln!(obj, "f {a} {b} {c}\nf {a} {c} {d}");
        }
    }
    std::fs::write(dir.join("meshes/grid.obj"), obj).unwrap();
    let scene = dir.join("grid.ron");
    std::fs::write(
        &scene,
        "(title: \"grid\", note: \"a large mesh\", problem: Render((width: 32, height: 32, camera: ImagePlane(x: (1.0, -1.0), y: (1.0, -1.0), z: 1.0), objects: [(shape: Mesh(obj: \"meshes/grid.obj\"))], effects: [\"coverage\"])))",
    )
    .unwrap();
    scene
}

fn open(harness: &mut Harness<'static, RaylabApp>, path: &std::path::Path) {
    let scene = raylab::scene::Scene::load(path).unwrap();
    let folder = path.parent().unwrap().display().to_string();
    harness
        .state_mut()
        .load_scene_from(&scene, Some(folder))
        .unwrap();
    harness.step();
}

#[test]
fn a_large_mesh_loads_in_the_background_with_progress_and_cancel() {
    // 2 × 350² = 245 000 triangles, about 7 MB: large enough to load in the background.
    let path = grid_scene(350);
    let mut harness = harness();
    open(&mut harness, &path);
    assert!(app_view::<RenderView>(&harness).is_loading());
    assert!(shows_text_containing(&harness, "loading mesh 1 of 1"));
    assert!(harness.query_by_label("Cancel").is_some());
    // The app keeps drawing frames while it loads, then renders.
    let started = Instant::now();
    let mut frames_while_loading = 0;
    while app_view::<RenderView>(&harness).is_rendering() {
        assert!(started.elapsed().as_secs() < 120, "the load never finished");
        if app_view::<RenderView>(&harness).is_loading() {
            frames_while_loading += 1;
        }
        std::thread::sleep(Duration::from_millis(10));
        harness.step();
    }
    assert!(frames_while_loading > 1, "{frames_while_loading} frames");
    let rendered = app_view::<RenderView>(&harness)
        .rendered()
        .expect("rendered");
    assert!(rendered.stats.hits > 0);

    // Opened again and cancelled: the load stops and the view says so.
    open(&mut harness, &path);
    assert!(app_view::<RenderView>(&harness).is_loading());
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.step();
    assert!(!app_view::<RenderView>(&harness).is_loading());
    assert!(shows_text_containing(&harness, "cancelled"));
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
}
