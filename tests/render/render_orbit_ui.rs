//! The Render view's live camera, driven as a student would: drag the image to orbit, see quick
//! frames follow the drag and the full image after it, the frame counter climb, an effect toggled
//! in mid-orbit change the rays at once, and the reset button bring back the scene's camera and its
//! image to the bit.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use common::{app_at, app_view, shows_text_containing, step_while, wait_for_render};
use egui::Vec2;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raylab::app::RaylabApp;
use raylab::app::render_view::RenderView;
use raylab::app::view::View;
use raylab::render::Image;
use raylab::scene::Problem;

fn shown(harness: &Harness<'static, RaylabApp>) -> Image {
    app_view::<RenderView>(harness)
        .rendered()
        .expect("an image is shown")
        .image
        .clone()
}

/// The number after "Frame " in the render's summary.
fn frame_number(harness: &Harness<'static, RaylabApp>) -> u64 {
    let text = harness
        .query_all_by(|node| node.value().is_some_and(|l| l.starts_with("Frame ")))
        .next()
        .expect("a frame counter")
        .accesskit_node()
        .value()
        .unwrap_or_default();
    let start = text.find("Frame ").expect("Frame") + "Frame ".len();
    let digits: String = text[start..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().expect("a frame number")
}

/// Steps, holding the drag, until a frame of the wanted kind (quick or full) is shown.
fn until_frame(harness: &mut Harness<'static, RaylabApp>, quick: bool, full_width: usize) {
    step_while(harness, 5, "no frame of that kind came", |h| {
        let view = app_view::<RenderView>(h);
        view.is_rendering() || (view.rendered().unwrap().image.width < full_width) != quick
    });
}

#[test]
fn dragging_the_image_orbits_with_quick_frames_then_the_full_image() {
    let mut harness = app_at("Effect: shadows");
    let original = shown(&harness);
    let (width, height) = (original.width, original.height);
    let scene_camera = app_view::<RenderView>(&harness).scene.camera.clone();
    let first = frame_number(&harness);

    // Press on the image and move, holding the button: quick frames, smaller, follow the camera.
    let centre = common::press_on_image(&mut harness, "Correct render");
    for k in 1..=4 {
        harness.hover_at(centre + Vec2::new(15.0 * k as f32, 4.0 * k as f32));
        harness.step();
    }
    until_frame(&mut harness, true, width);
    let quick = shown(&harness);
    assert!(
        quick.width < width && quick.height < height,
        "{}x{}",
        quick.width,
        quick.height
    );
    assert!(shows_text_containing(&harness, "(quick, 1/"));
    // Frames a second while moving (one, on a slow machine's debug build).
    assert!(
        shows_text_containing(&harness, "frames/s")
            || shows_text_containing(&harness, " 1 frame/s")
    );
    assert!(frame_number(&harness) > first);
    let shadow_rays = app_view::<RenderView>(&harness)
        .rendered()
        .unwrap()
        .stats
        .secondary
        .shadow_rays;
    assert!(shadow_rays > 0);

    // Shadows off in mid-orbit (through the accessibility action, as the pointer is busy
    // dragging): the next quick frame casts none, and the screen says so.
    harness.get_by_label("shadows").click_accesskit();
    harness.step();
    harness.hover_at(centre + Vec2::new(70.0, 20.0));
    harness.step();
    step_while(&mut harness, 5, "the quick frame kept its shadows", |h| {
        let rendered = app_view::<RenderView>(h).rendered().unwrap();
        h.state().state.get::<RenderView>().is_rendering()
            || rendered.stats.secondary.shadow_rays > 0
    });
    assert!(shown(&harness).width < width, "still a quick frame");
    assert!(shows_text_containing(&harness, "shadow rays: 0"));
    let during = frame_number(&harness);

    // Released, the full image comes, from the new camera: other pixels, its full size.
    harness.drop_at(centre + Vec2::new(70.0, 20.0));
    harness.run();
    wait_for_render(&mut harness);
    until_frame(&mut harness, false, width);
    let moved = shown(&harness);
    assert_eq!((moved.width, moved.height), (width, height));
    assert!(!shows_text_containing(&harness, "(quick"));
    assert!(frame_number(&harness) > during);
    let view = app_view::<RenderView>(&harness);
    assert!(view.camera.is_some(), "the camera moved");
    // The scene keeps its camera; the view's problem (what Save writes) has the moved one.
    assert_eq!(view.scene.camera, scene_camera);
    let Some(Problem::Render(saved)) = view.problem() else {
        panic!("a render problem")
    };
    assert_eq!(Some(saved.camera), view.camera.clone());

    // Shadows back on and the camera reset: the scene's image, to the bit.
    harness.get_by_label("shadows").click();
    harness.run();
    harness.get_by_label("Reset camera").click();
    wait_for_render(&mut harness);
    assert!(app_view::<RenderView>(&harness).camera.is_none());
    assert!(
        shown(&harness) == original,
        "the reset camera renders the scene's image"
    );
}

/// R resets the camera as the button does; a lesson's slide can aim the Render view's camera; the
/// image-plane camera of seed 003 does not move (no button).
#[test]
fn the_r_key_resets_and_an_image_plane_stays() {
    let mut harness = app_at("Effect: shadows");
    let original = shown(&harness);
    harness
        .state_mut()
        .state
        .get_mut::<RenderView>()
        .aim(1.0, 0.5);
    // Stepped, not run to rest: the app asks for frames until the render ends (wait_for_render).
    harness.step();
    wait_for_render(&mut harness);
    assert!(
        shown(&harness) != original,
        "the aimed camera sees otherwise"
    );
    harness.key_press(egui::Key::R);
    harness.step();
    wait_for_render(&mut harness);
    assert!(shown(&harness) == original);

    let harness = app_at("Seed 003: facing ratio");
    assert!(harness.query_by_label("Reset camera").is_none());
}

/// Orbiting beside a bug's image: both images follow the camera, the bug's never replaced by the
/// "rendering…" placeholder while the camera moves.
#[test]
fn the_bug_image_follows_the_orbit() {
    let mut harness = app_at("Render: common bugs");
    common::pick_bug(&mut harness, "accepting t < 0");
    let width = shown(&harness).width;
    let centre = common::press_on_image(&mut harness, "Correct render");
    for k in 1..=6 {
        harness.hover_at(centre + Vec2::new(10.0 * k as f32, 3.0 * k as f32));
        harness.step();
        // Every frame of the drag shows the bug's image (no placeholder).
        assert!(
            harness
                .query_by_label("With the bug: accepting t < 0 render")
                .is_some(),
            "the bug's image stays up at step {k}"
        );
    }
    until_frame(&mut harness, true, width);
    let view = app_view::<RenderView>(&harness);
    let bug_image = view.rendered_with_bug().unwrap().image.width;
    assert!(bug_image <= width);
    harness.drop_at(centre + Vec2::new(60.0, 18.0));
    harness.step();
    wait_for_render(&mut harness);
    assert_eq!(
        shown(&harness).width,
        width,
        "the full image after the drag"
    );
}
