//! The Render view's budget and Cancel: a render whose settings may cast past the budget waits for
//! "Render anyway", as `raylab render` refuses it; a render in flight stops on Cancel.

use crate::common;

use common::app_view;
use egui_kittest::kittest::Queryable;
use raylab::app::render_view::RenderView;
use raylab::scene::Problem;

/// A shipped render scene with its settings changed by `change`.
fn preset_with(
    name: &str,
    change: impl FnOnce(&mut raylab::scene::RenderScene),
) -> raylab::scene::Scene {
    let mut scene = raylab::scene::preset(name).expect("a shipped preset");
    if let Problem::Render(render) = &mut scene.problem {
        change(render);
    }
    scene
}

/// "Render anyway" renders the scene that waited, and the refusal goes.
fn renders_anyway(harness: &mut egui_kittest::Harness<'static, raylab::app::RaylabApp>) {
    harness.get_by_label("Render anyway").click();
    common::wait_for_render(harness);
    assert!(app_view::<RenderView>(harness).rendered().is_some());
    assert!(!common::shows_text_containing(harness, "Not rendered"));
}

#[test]
fn a_render_past_the_budget_waits_for_render_anyway() {
    let mut harness = common::app_harness();
    harness.run();
    // Within every limit, but max_depth 16 with refraction and 1024 occlusion rays at 16×16 samples:
    // its worst case is far past 10¹² rays. The camera looks away from the glass, so every ray
    // misses and rendering it anyway is quick here.
    let scene = preset_with("effect-refraction", |render| {
        (render.width, render.height) = (8, 6);
        render.camera = raylab::scene::render::Camera::Pinhole {
            position: [0.0, -4.0, 0.0],
            target: [0.0, -8.0, 0.0],
            fov_y: 40.0,
        };
        render.effects.extend([
            raylab::scene::render::Effect::AmbientOcclusion,
            raylab::scene::render::Effect::Antialiasing,
        ]);
        render.settings.max_depth = 16;
        render.settings.occlusion_rays = 1024;
        render.settings.samples_per_side = 16;
    });
    harness
        .state_mut()
        .load_scene(&scene)
        .expect("the scene loads");
    harness.run();
    assert!(!app_view::<RenderView>(&harness).is_rendering());
    assert!(common::shows_text_containing(
        &harness,
        "Not rendered: this render may cast up to"
    ));
    renders_anyway(&mut harness);
}

#[test]
fn cancel_stops_a_render_in_flight() {
    let mut harness = common::app_harness();
    harness.run();
    let scene = raylab::scene::preset("render-cornell-box").expect("a shipped preset");
    harness
        .state_mut()
        .load_scene(&scene)
        .expect("the scene loads");
    harness.step();
    harness.step();
    assert!(app_view::<RenderView>(&harness).is_rendering());
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.step();
    assert!(!app_view::<RenderView>(&harness).is_rendering());
    assert!(common::shows_text_containing(&harness, "cancelled"));
}

/// A render whose trial frame says it would take past the time budget waits for "Render anyway",
/// in the words `raylab render` uses. The budget here is a millisecond, so any scene large enough
/// for a trial (the transformed scene, 480×320) passes it on any machine.
#[test]
fn a_render_estimated_past_the_time_budget_waits_for_render_anyway() {
    let mut harness = common::app_harness();
    harness.run();
    let scene = raylab::scene::preset("render-transformed").expect("a shipped preset");
    harness
        .state_mut()
        .load_scene(&scene)
        .expect("the scene loads");
    harness
        .state_mut()
        .state
        .get_mut::<RenderView>()
        .set_time_budget(Some(0.001));
    common::wait_for_render(&mut harness);
    assert!(app_view::<RenderView>(&harness).rendered().is_none());
    // "Not rendered: this render would take about 0.1 s on 2 threads here (about 310 k rays), past
    // the budget of 0.0 s. Turn effects off, …"
    assert!(common::shows_text_containing(
        &harness,
        "Not rendered: this render would take about"
    ));
    assert!(common::shows_text_containing(
        &harness,
        "threads here (about"
    ));
    // Nothing renders, and nothing says it does.
    assert!(!common::shows_text_containing(&harness, "Rendering…"));
    renders_anyway(&mut harness);
}
