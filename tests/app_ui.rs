//! The app driven like a person would: load presets by their labels, drag the painted handles, move
//! sliders, press buttons, and read what is shown.

use egui::accesskit::Role;
use egui::{Pos2, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raylab::app::segments_view::Handle;
use raylab::app::{RaylabApp, ViewKind};

fn harness() -> Harness<'static, RaylabApp> {
    Harness::builder()
        .with_size(Vec2::new(1280.0, 800.0))
        .with_max_steps(200)
        .build_eframe(|cc| {
            raylab::app::set_style(&cc.egui_ctx);
            RaylabApp::new()
        })
}

fn load_preset(harness: &mut Harness<'static, RaylabApp>, title: &str) {
    harness.get_by_label("Presets").click();
    harness.run();
    harness.get_by_role_and_label(Role::Button, title).click();
    harness.run();
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

fn shows(harness: &Harness<'static, RaylabApp>, text: &str) -> bool {
    harness.query_by_label(text).is_some()
}

#[test]
fn dragging_t_and_s_onto_the_crossing_reads_17_22_and_21_22() {
    let mut harness = harness();
    load_preset(&mut harness, "Seed 000: segments that cross");
    assert_eq!(harness.state().state.view, ViewKind::Segments);
    let solved = harness
        .state()
        .state
        .segments
        .solve(raylab::geometry::Precision::Exact);
    let view = &harness.state().state.segments;
    let crossing = view
        .crossing_on_screen(&solved)
        .expect("the lines cross on screen");
    let t_handle = view.handle_on_screen(Handle::T).unwrap();
    // Drop a few pixels off the crossing: the handle snaps onto it.
    drag(&mut harness, t_handle, crossing + Vec2::new(3.0, -2.0));
    assert!(shows(&harness, "t = 17/22"), "t did not land on 17/22");
    let view = &harness.state().state.segments;
    let s_handle = view.handle_on_screen(Handle::S).unwrap();
    let crossing = view.crossing_on_screen(&solved).unwrap();
    drag(&mut harness, s_handle, crossing + Vec2::new(-2.0, 4.0));
    assert!(shows(&harness, "s = 21/22"), "s did not land on 21/22");
    assert!(shows(&harness, "A(t) = B(s): the handles meet"));
}

#[test]
fn a_handle_dragged_elsewhere_does_not_snap() {
    let mut harness = harness();
    load_preset(&mut harness, "Seed 000: segments that cross");
    let view = &harness.state().state.segments;
    let t_handle = view.handle_on_screen(Handle::T).unwrap();
    let a2 = view.handle_on_screen(Handle::Endpoint(1)).unwrap();
    // Slide t toward A2 and beyond it onto the faded line.
    let beyond = a2 + (a2 - t_handle) * 0.5;
    drag(&mut harness, t_handle, beyond);
    let t = harness.state().state.segments.t;
    assert!(t > 1.0 && t < 1.6, "t = {t}");
    assert!(!shows(&harness, "t = 17/22"));
}

#[test]
fn beta_gamma_sliders_move_p_inside_and_outside() {
    let mut harness = harness();
    load_preset(&mut harness, "Seed 000: the lecture triangle");
    assert_eq!(harness.state().state.view, ViewKind::Triangle);
    harness
        .get_by_role_and_label(Role::Slider, "β")
        .set_value_accesskit(0.25);
    harness
        .get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.25);
    harness.run();
    assert!(shows(&harness, "P(β, γ) is inside the triangle"));
    harness
        .get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.9);
    harness.run();
    assert!(shows(
        &harness,
        "P(β, γ) is outside: fails β + γ ≤ 1 (beyond edge BC)"
    ));
    harness
        .get_by_role_and_label(Role::Slider, "β")
        .set_value_accesskit(-0.2);
    harness
        .get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.5);
    harness.run();
    assert!(shows(
        &harness,
        "P(β, γ) is outside: fails β ≥ 0 (beyond edge CA)"
    ));
}

#[test]
fn solve_slides_to_one_third_one_third_one() {
    let mut harness = harness();
    load_preset(&mut harness, "Seed 000: the lecture triangle");
    harness.get_by_label("Solve").click();
    harness.run();
    assert!(shows(&harness, "β = 1/3"));
    assert!(shows(&harness, "γ = 1/3"));
    assert!(shows(&harness, "t = 1"));
    assert!(shows(&harness, "P(β, γ) = L + tD: they meet"));
}

#[test]
fn a_parallel_ray_shows_its_named_state() {
    let mut harness = harness();
    load_preset(&mut harness, "Ray parallel to the triangle's plane");
    let status = harness
        .state()
        .state
        .triangle
        .solve(raylab::geometry::Precision::F64);
    assert_eq!(status.float.outcome.status(), "parallel");
    assert!(shows(
        &harness,
        "the ray is parallel to the triangle's plane and never meets it (|M| = 0)"
    ));
    // Solve has nothing to slide to.
    assert!(harness.get_by_label("Solve").accesskit_node().is_disabled());
}
