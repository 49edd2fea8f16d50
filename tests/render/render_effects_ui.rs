//! The Render view's effects past ray casting, driven through the app as a student would: an effect
//! toggled by its label, the rays by kind read off the screen, each effect's cost measured, a pixel
//! in shadow probed and its shadow ray found in the ray tree and opened in the Triangle view.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use common::{app_at, app_view, click_image, shows_text_containing, step_while, wait_for_render};
use egui::Vec2;
use egui_kittest::kittest::Queryable;
use raylab::app::ViewKind;
use raylab::app::parallelogram_view::ParallelogramView;
use raylab::app::render_view::RenderView;
use raylab::app::render_view::grouped;
use raylab::app::triangle_view::TriangleView;
use raylab::render::ray_kinds::RayKind;
use raylab::render::secondary::LightTest;

/// Clicks the widget with this label, scrolled into view first (the probe's column scrolls).
fn click_label(harness: &mut egui_kittest::Harness<'static, raylab::app::RaylabApp>, label: &str) {
    harness.get_by_label(label).scroll_to_me();
    harness.run();
    harness.get_by_label(label).click();
    harness.run();
}

#[test]
fn shadows_toggle_their_rays_and_a_shadowed_pixel_opens_its_shadow_ray() {
    let mut harness = app_at("Effect: shadows");
    assert_eq!(harness.state().state.view, ViewKind::Render);
    let stats = app_view::<RenderView>(&harness).rendered().unwrap().stats;
    let shadow = stats.secondary.shadow_rays;
    assert!(shadow > 10_000, "{shadow}");
    // The rays by kind are on the screen: one shadow ray per lit hit, one primary ray per pixel.
    assert!(shows_text_containing(
        &harness,
        &format!("shadow rays: {}", grouped(shadow))
    ));
    assert!(shows_text_containing(
        &harness,
        &format!("primary rays: {}", grouped(200 * 150))
    ));

    // Turned off by its label, the effect casts no shadow ray, and the screen says so.
    harness.get_by_label("shadows").click();
    wait_for_render(&mut harness);
    let stats = app_view::<RenderView>(&harness).rendered().unwrap().stats;
    assert_eq!(stats.secondary.shadow_rays, 0);
    assert!(shows_text_containing(&harness, "shadow rays: 0"));
    assert!(shows_text_containing(&harness, "shadow (off)"));
    harness.get_by_label("shadows").click();
    wait_for_render(&mut harness);
    assert!(shows_text_containing(
        &harness,
        &format!("shadow rays: {}", grouped(shadow))
    ));

    // The image's centre sees the floor at the origin, in the triangle's shadow (the light is
    // straight above the triangle).
    click_image(&mut harness, "Correct render", Vec2::new(0.5, 0.5));
    let tree = app_view::<RenderView>(&harness)
        .ray_tree()
        .cloned()
        .unwrap();
    assert_eq!(tree.root.hit.unwrap().object, 0, "the floor");
    let light = tree.root.lights[0];
    let LightTest::Blocked(shadow_ray, _) = light.test else {
        panic!("the centre is in shadow: {light:?}");
    };
    assert_eq!(
        light.blocker.unwrap().object,
        1,
        "the triangle is in the way"
    );
    assert!(shows_text_containing(&harness, "Shadow ray → light 1:"));
    assert!(shows_text_containing(
        &harness,
        "blocked by object 2 (triangle)"
    ));
    // The probe names the floor as the parallelogram it is, with no triangle index (a parallelogram
    // has no triangles; only a mesh's hit names one).
    assert!(shows_text_containing(
        &harness,
        "hit object 1 (parallelogram): t ="
    ));
    assert!(!shows_text_containing(&harness, "), triangle"));
    // The pixel says which number is its row (a bare "(74, 100)" reads as x and y).
    let (row, column) = app_view::<RenderView>(&harness).probed.unwrap();
    assert!(
        column > row,
        "the image is wider than tall, clicked at its centre"
    );
    assert!(shows_text_containing(
        &harness,
        &format!("Pixel (row {row}, column {column})")
    ));

    // Its steps: the shadow ray against the triangle that blocks it, in the Triangle view.
    click_label(
        &mut harness,
        "Open the shadow ray to light 1 from the primary ray in the Triangle (3D) view",
    );
    let state = &harness.state().state;
    assert_eq!(state.view, ViewKind::Triangle);
    let triangle = &state.get::<TriangleView>().scene;
    assert_eq!(
        (triangle.origin, triangle.dir),
        (shadow_ray.origin, shadow_ray.dir)
    );
    assert!(
        state
            .title(ViewKind::Triangle)
            .0
            .contains("the shadow ray to light 1"),
        "{:?}",
        state.title(ViewKind::Triangle)
    );
    assert!(shows_text_containing(
        &harness,
        "the ray hits the triangle at t ="
    ));

    // Back in the Render view, the primary ray's own button opens the primary ray again (the floor
    // is a parallelogram), not the shadow ray the Triangle view holds.
    harness.get_by_label("Render").click();
    harness.run();
    click_label(&mut harness, "Open in Parallelogram →");
    let state = &harness.state().state;
    assert_eq!(state.view, ViewKind::Parallelogram);
    assert_eq!(
        state.get::<ParallelogramView>().scene.origin,
        tree.root.ray.origin
    );
    assert_eq!(
        state.get::<ParallelogramView>().scene.dir,
        tree.root.ray.dir
    );
}

#[test]
fn a_mirror_pixel_shows_its_reflected_ray_and_each_effect_has_a_cost() {
    let mut harness = app_at("Effect: reflections");
    let stats = app_view::<RenderView>(&harness).rendered().unwrap().stats;
    let reflected = stats.secondary.rays(RayKind::Reflection);
    assert!(reflected > 0);
    assert!(shows_text_containing(
        &harness,
        &format!("reflection rays: {}", grouped(reflected))
    ));

    // Somewhere in the upper middle of the image is the mirror (object 2).
    let mut on_mirror = false;
    for (x, y) in [
        (0.45, 0.3),
        (0.35, 0.25),
        (0.55, 0.2),
        (0.3, 0.4),
        (0.6, 0.35),
    ] {
        click_image(&mut harness, "Correct render", Vec2::new(x, y));
        let tree = app_view::<RenderView>(&harness)
            .ray_tree()
            .cloned()
            .unwrap();
        if tree.root.hit.is_some_and(|h| h.object == 1) {
            let child = &tree.root.children[0];
            assert_eq!((child.kind, child.depth), (RayKind::Reflection, 1));
            on_mirror = true;
            break;
        }
    }
    assert!(on_mirror, "no click landed on the mirror");
    assert!(shows_text_containing(
        &harness,
        "The reflected ray (bounce 1)"
    ));

    // Each effect's cost: the scene rendered with all on, then without each.
    click_label(&mut harness, "Measure the cost of each effect");
    step_while(&mut harness, 20, "no cost table", |h| {
        !shows_text_containing(h, "without reflections")
    });
    assert!(shows_text_containing(&harness, "all effects on"));
    assert!(shows_text_containing(&harness, "without smooth-normals"));
}

/// A bug picked for one scene is gone when another scene loads: its sentence is not left over the
/// new scene's image.
#[test]
fn a_bug_is_not_carried_into_the_next_scene() {
    let mut harness = app_at("Render: common bugs");
    common::pick_bug(&mut harness, "accepting t < 0");
    assert!(
        app_view::<RenderView>(&harness)
            .rendered_with_bug()
            .is_some()
    );
    common::load_preset(&mut harness, "Effect: shadows");
    let view = app_view::<RenderView>(&harness);
    assert_eq!(view.bug, None);
    assert!(view.rendered_with_bug().is_none());
    assert!(
        harness
            .query_by_label("With the bug: accepting t < 0")
            .is_none()
    );
}
