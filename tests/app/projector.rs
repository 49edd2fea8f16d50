//! raylab on a classroom projector: every preset at 100%, 150% and 200% on a 1280x800 screen (and on
//! 1920x1080), checked from what egui actually paints: no two pieces of text overprint each other,
//! no text is cut off at the side of its panel or the window, and the view keeps at least half the
//! window's width. Then presentation mode, stepped through with the keys a clicker sends.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use common::app_view;

use egui::epaint::{ClippedShape, Shape};
use egui::{Rect, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raylab::app::render_view::RenderView;
use raylab::app::triangle_view::TriangleView;
use raylab::app::{RaylabApp, ViewKind};

/// A projector of `width`x`height` pixels at `zoom`: the window is that many pixels, and egui draws
/// `zoom` pixels per point (what Ctrl + does).
fn projector(width: f32, height: f32, zoom: f32) -> Harness<'static, RaylabApp> {
    Harness::builder()
        .with_size(Vec2::new(width, height) / zoom)
        .with_pixels_per_point(zoom)
        .with_max_steps(200)
        .build_eframe(|cc| {
            raylab::app::set_style(&cc.egui_ctx);
            RaylabApp::new()
        })
}

/// One piece of painted text: what it says, where it is, and the part of it that can be seen.
#[derive(Debug)]
struct PaintedText {
    text: String,
    rect: Rect,
    visible: Rect,
    clip: Rect,
    /// Cut short with “…” to fit its width.
    elided: bool,
}

/// Every non-empty text egui painted in the last frame.
fn painted_texts(harness: &Harness<'static, RaylabApp>) -> Vec<PaintedText> {
    fn walk(shape: &Shape, clip: Rect, out: &mut Vec<PaintedText>) {
        match shape {
            Shape::Vec(shapes) => shapes.iter().for_each(|s| walk(s, clip, out)),
            Shape::Text(text) if !text.galley.text().trim().is_empty() => {
                // Row by row: a label that continues a wrapped row starts with leading space that
                // is not its text, and its second row starts left of its first.
                for row in &text.galley.rows {
                    if row.glyphs.iter().all(|g| g.chr.is_whitespace()) {
                        continue;
                    }
                    let rect = row
                        .rect_without_leading_space()
                        .translate(text.pos.to_vec2());
                    out.push(PaintedText {
                        // Non-breaking spaces (formulas kept whole) read as spaces.
                        text: text.galley.text().replace('\u{a0}', " "),
                        rect,
                        visible: rect.intersect(clip),
                        clip,
                        elided: text.galley.elided,
                    });
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    for ClippedShape {
        clip_rect, shape, ..
    } in &harness.output().shapes
    {
        walk(shape, *clip_rect, &mut out);
    }
    out
}

/// What is wrong with the last frame on a screen of `screen` points: overprinted or cut text, a view
/// narrower than half the window.
fn layout_problems(harness: &Harness<'static, RaylabApp>, screen: Rect) -> Vec<String> {
    let texts = painted_texts(harness);
    let mut problems = Vec::new();
    let seen: Vec<&PaintedText> = texts
        .iter()
        .filter(|t| t.visible.is_positive() && screen.intersects(t.visible))
        .collect();
    for (i, a) in seen.iter().enumerate() {
        for b in &seen[i + 1..] {
            // Glyph boxes include a little leading: a real overprint covers more than a sliver.
            let overlap = a.visible.shrink(1.0).intersect(b.visible.shrink(1.0));
            if overlap.is_positive() && overlap.area() > 4.0 {
                problems.push(format!("“{}” overprints “{}”", a.text, b.text));
            }
        }
        // Cut short: a status line that ends in “B(s…” tells the student nothing.
        // (A preset's note and the presenter's "Highlighted:" row keep to their rows on purpose:
        // whole on hover and to a screen reader.)
        if a.elided && !preset_notes().contains(&a.text) && !a.text.starts_with("Highlighted:") {
            problems.push(format!("“{}” is cut short with …", a.text));
        }
        // Cut at the side: part of it shows, part is clipped away left or right.
        let cut_right = a.rect.max.x > a.clip.max.x.min(screen.max.x) + 1.0;
        let cut_left = a.rect.min.x < a.clip.min.x.max(screen.min.x) - 1.0;
        if cut_right || cut_left {
            problems.push(format!("“{}” is cut at the side", a.text));
        }
    }
    // No widget reaches past the window's sides (a button half off screen cannot be clicked).
    for node in harness.root().children_recursive() {
        let access = node.accesskit_node();
        if access.bounding_box().is_none() {
            continue;
        }
        let rect = node.rect();
        let named = access.label().or(access.value()).unwrap_or_default();
        if rect.is_positive() && !named.is_empty() && rect.max.x > screen.max.x + 1.0 {
            problems.push(format!(
                "{:?} “{named}” reaches past the window",
                access.role()
            ));
        }
    }
    problems.extend(covered_handles(harness));
    let view = harness.state().view_rect.expect("a view was drawn");
    if view.width() < screen.width() / 2.0 - 1.0 {
        problems.push(format!(
            "the view is {:.0} of {:.0} points wide",
            view.width(),
            screen.width()
        ));
    }
    problems
}

/// The presets' notes: the heading shows one cut to its rows, read whole on hover and by a screen
/// reader (its label's text is the whole note).
fn preset_notes() -> Vec<String> {
    raylab::scene::preset_names()
        .iter()
        .filter_map(|name| raylab::scene::preset(name))
        .map(|scene| scene.note)
        .collect()
}

/// Canvas handles (named in the accessibility tree "vertex A at …") that a canvas label or the
/// verdict box covers: a student could neither see nor grab them. A handle outside its canvas is
/// clipped away, not covered.
fn covered_handles(harness: &Harness<'static, RaylabApp>) -> Vec<String> {
    use egui::accesskit::Role;
    let nodes: Vec<_> = harness.root().children_recursive().collect();
    let named = |node: &egui_kittest::Node<'_>| node.accesskit_node().label().unwrap_or_default();
    let canvases: Vec<Rect> = nodes
        .iter()
        .filter(|n| n.accesskit_node().role() == Role::Canvas)
        .map(|n| n.rect())
        .collect();
    // Canvas labels are named nodes with no value (egui's own labels carry their text as a value).
    let covers: Vec<(String, Rect)> = nodes
        .iter()
        .filter(|n| {
            let access = n.accesskit_node();
            (access.role() == Role::Label && access.label().is_some() && access.value().is_none())
                || access.role() == Role::Status
        })
        .map(|n| (named(n), n.rect()))
        .collect();
    let mut problems = Vec::new();
    for handle in nodes
        .iter()
        .filter(|n| n.accesskit_node().role() == Role::Slider && named(n).contains(" at "))
    {
        let dot = Rect::from_center_size(handle.rect().center(), Vec2::splat(8.0));
        if !canvases.iter().any(|c| c.contains_rect(dot)) {
            continue;
        }
        for (cover, rect) in &covers {
            if rect.intersects(dot) {
                problems.push(format!("“{}” is under “{cover}”", named(handle)));
            }
        }
    }
    problems
}

/// The scene with a render's image shrunk (same aspect) to at most 64 pixels a side: the view scales
/// the image to the room it has, so the layout is the same, and a debug build renders the effect
/// scenes (the Cornell box casts millions of rays) in a moment instead of minutes.
fn small_image(mut scene: raylab::scene::Scene) -> raylab::scene::Scene {
    if let raylab::scene::Problem::Render(render) = &mut scene.problem {
        let k = render.width.max(render.height).div_ceil(64);
        (render.width, render.height) = (render.width.div_ceil(k), render.height.div_ceil(k));
    }
    scene
}

/// Loads a preset with its image made small (see [`small_image`]), waits for its render and rests
/// with the pointer away.
fn load_small(harness: &mut Harness<'static, RaylabApp>, scene: raylab::scene::Scene) {
    harness
        .state_mut()
        .load_scene(&small_image(scene))
        .expect("presets load");
    common::wait_for_render(harness);
    harness.remove_cursor();
    harness.run();
}

/// Loads every preset at every zoom on a screen and collects what is wrong, per case.
fn check_every_preset(width: f32, height: f32, zooms: &[f32]) -> Vec<String> {
    let mut problems = Vec::new();
    for zoom in zooms {
        let mut harness = projector(width, height, *zoom);
        let screen = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(width, height) / *zoom);
        for name in raylab::scene::preset_names() {
            let scene = raylab::scene::preset(name).expect("a shipped preset");
            load_small(&mut harness, scene);
            for problem in layout_problems(&harness, screen) {
                problems.push(format!("{name} at {width}x{height}, {zoom}x: {problem}"));
            }
        }
    }
    problems
}

#[test]
fn every_preset_reads_cleanly_on_a_1280x800_projector_at_100_150_and_200_percent() {
    let problems = check_every_preset(1280.0, 800.0, &[1.0, 1.5, 2.0]);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_preset_reads_cleanly_on_1920x1080() {
    let problems = check_every_preset(1920.0, 1080.0, &[1.0, 1.5, 2.0]);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_top_bar_folds_what_does_not_fit_into_the_view_menu() {
    for zoom in [1.0, 1.5, 2.0] {
        let mut harness = projector(1280.0, 800.0, zoom);
        harness.run();
        // Every view's tab is on screen at every zoom.
        for kind in ViewKind::ALL {
            let tab = harness.get_by_label(kind.label()).rect();
            assert!(tab.max.x <= 1280.0 / zoom, "{} is off screen", kind.label());
        }
        // The View menu always holds the quick controls.
        harness.get_by_label("View").click();
        harness.run();
        assert!(harness.query_by_label("Present (F5)").is_some());
        assert!(harness.query_by_label("System").is_some());
    }
}

#[test]
fn presentation_keys_step_through_the_lecture_triangle_with_linked_highlighting() {
    let mut harness = projector(1280.0, 800.0, 1.0);
    common::load_preset(&mut harness, "Seed 000: the lecture triangle");
    harness.key_press(egui::Key::F5);
    harness.run();
    assert_eq!(harness.state().presentation, Some(0));
    assert!(harness.query_by_label("Step 1 of 23").is_some());
    // The system: the three column vectors of M.
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: column A−B, column A−C, column D"
    );
    // Space, → and Page Down go forward, as presentation clickers send them.
    common::press(&mut harness, [egui::Key::Space, egui::Key::ArrowRight]);
    assert!(harness.query_by_label("Step 3 of 23").is_some());
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: right-hand side Y"
    );
    // Step 5 is M1: Y in place of the first column, A−B.
    common::press(&mut harness, [egui::Key::PageDown; 2]);
    assert!(harness.query_by_label("Step 5 of 23").is_some());
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: right-hand side Y, column A−B"
    );
    // On to β = |M1|/|M| (step 13): the β handle slides to β* = 1/3.
    common::press(&mut harness, [egui::Key::Space; 8]);
    assert!(harness.query_by_label("Step 13 of 23").is_some());
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: β at its solution"
    );
    assert!((app_view::<TriangleView>(&harness).beta - 1.0 / 3.0).abs() < 1e-12);
    // The check β + γ ≤ 1 (step 19) highlights edge BC; ← and Page Up go back.
    common::press(&mut harness, [egui::Key::ArrowRight; 6]);
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: edge BC (β + γ ≤ 1)"
    );
    common::press(&mut harness, [egui::Key::ArrowRight; 2]);
    assert!(harness.query_by_label("Step 21 of 23").is_some());
    assert_eq!(
        common::highlighted(&harness),
        "Highlighted: where the ray meets the plane"
    );
    common::press(&mut harness, [egui::Key::ArrowLeft, egui::Key::PageUp]);
    assert!(harness.query_by_label("Step 19 of 23").is_some());
    // The view fills the screen beside the one step: no top bar, no controls.
    assert!(harness.query_by_label("Presets").is_none());
    assert!(harness.query_by_label("Solve").is_none());
    // Esc leaves.
    harness.key_press(egui::Key::Escape);
    harness.run();
    assert_eq!(harness.state().presentation, None);
    assert!(harness.query_by_label("Presets").is_some());
}

/// A probed pixel's ray solved in exact arithmetic has long decimals that cannot wrap: the step panel
/// keeps its width (they scroll sideways inside their step) and nothing of the panel is cut off.
#[test]
fn a_probed_pixel_with_long_decimals_keeps_the_step_panel_whole() {
    for zoom in [1.5, 2.0] {
        let mut harness = projector(1280.0, 800.0, zoom);
        let screen = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(1280.0, 800.0) / zoom);
        common::load_preset(&mut harness, "Render: a transformed object");
        harness
            .state_mut()
            .state
            .get_mut::<RenderView>()
            .probe_precision = raylab::geometry::Precision::Exact;
        harness.run();
        common::click_image(&mut harness, "Correct render", Vec2::new(0.55, 0.35));
        harness.remove_cursor();
        harness.run();
        assert!(
            app_view::<RenderView>(&harness).probed.is_some(),
            "the click probed a pixel"
        );
        let texts = painted_texts(&harness);
        for wanted in ["Steps", "Copy all as LaTeX", "1. The system M X = Y"] {
            let text = texts
                .iter()
                .find(|t| t.text == wanted)
                .unwrap_or_else(|| panic!("“{wanted}” is not drawn at {zoom}x"));
            assert!(
                text.rect.min.x >= text.clip.min.x - 1.0 && text.rect.max.x <= screen.max.x + 1.0,
                "“{wanted}” is cut at {zoom}x: {:?} in {:?}",
                text.rect,
                text.clip
            );
        }
        let view = harness.state().view_rect.unwrap();
        assert!(view.width() >= screen.width() / 2.0 - 1.0, "{view:?}");
    }
}

/// Hovering a step in the panel highlights what it is about in the view, as presentation mode does.
#[test]
fn hovering_a_step_highlights_it_in_the_view() {
    let mut harness = projector(1280.0, 800.0, 1.0);
    common::load_preset(&mut harness, "Seed 000: the lecture triangle");
    let card = harness
        .get_by_label("5. M1: M with column 1 replaced by Y")
        .rect();
    harness.hover_at(card.center());
    harness.run();
    let names: Vec<String> = app_view::<TriangleView>(&harness)
        .highlight
        .iter()
        .map(|e| e.name("triangle"))
        .collect();
    assert_eq!(names, ["right-hand side Y", "column A−B"]);
    // Away from the panel, nothing stays highlighted.
    harness.hover_at(egui::pos2(5.0, 790.0));
    harness.run();
    assert!(app_view::<TriangleView>(&harness).highlight.is_empty());
}

/// Every slide of every lesson, and a practice problem of each kind, read cleanly on the projector at
/// 150% and 200%: the narration, the step and the view share the screen without overprinting.
#[test]
fn lessons_and_practice_read_cleanly_at_150_and_200_percent() {
    let mut problems = Vec::new();
    for zoom in [1.5, 2.0] {
        let screen = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(1280.0, 800.0) / zoom);
        let mut harness = projector(1280.0, 800.0, zoom);
        for name in raylab::lesson::lesson_names() {
            harness
                .state_mut()
                .start_lesson(name)
                .expect("a shipped lesson");
            common::wait_for_render(&mut harness);
            let slides = harness.state().lesson.as_ref().unwrap().lesson.slides.len();
            for slide in 0..slides {
                common::wait_for_render(&mut harness);
                for problem in presenter_problems(&mut harness, screen) {
                    problems.push(format!("{name} slide {} at {zoom}x: {problem}", slide + 1));
                }
                harness.key_press(egui::Key::Space);
                common::wait_for_render(&mut harness);
            }
            harness.key_press(egui::Key::Escape);
            harness.run();
        }
        for kind in [
            raylab::exercise::Kind::Segments,
            raylab::exercise::Kind::Triangle,
            raylab::exercise::Kind::Parallelogram,
        ] {
            harness
                .state_mut()
                .start_practice(kind, raylab::exercise::Level::Hit);
            harness.run();
            for problem in layout_problems(&harness, screen) {
                problems.push(format!("practice {} at {zoom}x: {problem}", kind.name()));
            }
            harness.key_press(egui::Key::Escape);
            harness.run();
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Text in the panel beside the view (a slide's narration and step, a presented step) that reaches
/// below the panel's bottom: cut in half, or below the fold where a clicker cannot scroll.
fn cut_below(harness: &Harness<'static, RaylabApp>, screen: Rect) -> Vec<String> {
    let view = harness.state().view_rect.expect("a view was drawn");
    let beside = |rect: Rect| rect.min.x >= view.max.x - 1.0;
    let mut problems: Vec<String> = painted_texts(harness)
        .into_iter()
        .filter(|t| beside(t.rect) && t.rect.max.y > t.clip.max.y + 1.0)
        .map(|t| format!("“{}” is cut at the bottom", t.text))
        .collect();
    // Below the fold: laid out (a screen reader finds it) but never painted.
    for node in harness.root().children_recursive() {
        let access = node.accesskit_node();
        let text = access.value().or(access.label()).unwrap_or_default();
        if access.bounding_box().is_none() || text.trim().is_empty() {
            continue;
        }
        let rect = node.rect();
        if beside(rect) && rect.min.y >= screen.max.y - 1.0 {
            problems.push(format!("“{text}” is below the fold"));
        }
    }
    problems
}

/// What is wrong with a presenter screen (a slide, a presented step) at rest, the pointer away:
/// the layout's problems and any text cut or below the fold beside the view.
fn presenter_problems(harness: &mut Harness<'static, RaylabApp>, screen: Rect) -> Vec<String> {
    harness.remove_cursor();
    harness.run();
    let mut problems = layout_problems(harness, screen);
    problems.extend(cut_below(harness, screen));
    problems
}

/// Presentation mode at 150% and 200%: every step of the lecture's triangle, parallelogram and
/// touching segments shows whole beside the view, none cut or below the fold (the |M| step's "= 27"
/// was cut in half at 200%, M⁻¹'s third row below the fold), nothing overprinted, and the view keeps
/// its height from step to step (the drawing jumped when "Highlighted:" wrapped the bar).
#[test]
fn presentation_steps_read_whole_at_150_and_200_percent() {
    let mut problems = Vec::new();
    for zoom in [1.5, 2.0] {
        let screen = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(1280.0, 800.0) / zoom);
        for preset in [
            "Seed 000: the lecture triangle",
            "Seed 001: ray and parallelogram",
            "Segments touching at an endpoint",
        ] {
            let mut harness = projector(1280.0, 800.0, zoom);
            common::load_preset(&mut harness, preset);
            harness.key_press(egui::Key::F5);
            harness.run();
            let mut step = 0;
            let mut heights = Vec::new();
            while harness.state().presentation.is_some_and(|s| s == step) {
                for problem in presenter_problems(&mut harness, screen) {
                    problems.push(format!("{preset} step {} at {zoom}x: {problem}", step + 1));
                }
                heights.push(harness.state().view_rect.expect("a view").height());
                harness.key_press(egui::Key::Space);
                harness.run();
                step += 1;
            }
            assert!(step > 10, "{preset}: only {step} steps presented");
            // The drawing keeps its place from step to step (the bar's height does not change).
            let (low, high) = heights
                .iter()
                .fold((f32::MAX, f32::MIN), |(l, h), x| (l.min(*x), h.max(*x)));
            if high - low > 1.0 {
                problems.push(format!(
                    "{preset} at {zoom}x: the view's height goes from {low:.0} to {high:.0} points"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Opens the controls a short view (200%) folds under one header; nothing where they are not folded.
fn unfold_controls(harness: &mut Harness<'static, RaylabApp>) {
    let header = harness
        .query_all_by(|node| node.label().is_some_and(|l| l.starts_with("Controls:")))
        .next()
        .map(|node| node.rect().center());
    if let Some(center) = header {
        harness.hover_at(center);
        harness.run();
        harness.get_by_label_contains("Controls:").click();
        harness.run();
    }
}

/// A long scene note keeps to two rows beside its title at 200% (ending in "…", whole on hover):
/// the Cornell box's note took five and left the image a sliver.
#[test]
fn a_long_note_takes_at_most_two_rows_at_200_percent() {
    let mut harness = projector(1280.0, 800.0, 2.0);
    let scene = small_image(raylab::scene::preset("render-cornell-box").expect("a shipped preset"));
    let note = scene.note.clone();
    harness
        .state_mut()
        .load_scene(&scene)
        .expect("presets load");
    common::wait_for_render(&mut harness);
    let title = harness.get_by_label("Render: a Cornell box").rect();
    let shown = harness.get_by_label(&note).rect();
    assert!(
        shown.height() < 2.5 * title.height(),
        "the note takes {:.0} points, its title's row {:.0}",
        shown.height(),
        title.height()
    );
}

/// The controls strip below a lecture view's drawing is as tall as its controls (up to 45% of the
/// view): every slider shows whole, not cut at the strip's bottom (the strip kept its first height,
/// a row or so, and the sliders scrolled out of sight).
#[test]
fn the_lecture_views_show_their_sliders_whole_below_the_drawing() {
    let views = [
        (
            "Seed 000: the lecture triangle",
            "Solve",
            &["β", "γ", "t"][..],
        ),
        (
            "Seed 001: ray and parallelogram",
            "Solve",
            &["α", "β", "t"][..],
        ),
        (
            "Seed 000: segments that cross",
            "Go to intersection",
            &["t", "s"][..],
        ),
    ];
    let mut problems = Vec::new();
    for zoom in [1.0, 1.5, 2.0] {
        for (preset, button, sliders) in views {
            let mut harness = projector(1280.0, 800.0, zoom);
            common::load_preset(&mut harness, preset);
            unfold_controls(&mut harness);
            harness.remove_cursor();
            harness.run();
            let strip = painted_texts(&harness)
                .into_iter()
                .find(|t| t.text == button)
                .unwrap_or_else(|| panic!("{preset}: no “{button}” at {zoom}x"))
                .clip;
            for name in sliders {
                let slider = harness.get_by_role_and_label(egui::accesskit::Role::Slider, name);
                let rect = slider.rect();
                if rect.max.y > strip.max.y + 1.0 {
                    problems.push(format!(
                        "{preset} at {zoom}x: slider {name} at {rect:?} is cut by the strip {strip:?}"
                    ));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A canvas's verdict is painted over the drawing: a whole line (segment B's, running off the top of
/// the plot) passes under its text, not through it.
#[test]
fn the_verdict_reads_over_the_drawing() {
    let mut harness = projector(1280.0, 800.0, 1.0);
    common::load_preset(&mut harness, "Seed 000: segments that cross");
    harness.remove_cursor();
    harness.run();
    let shapes: Vec<(usize, Shape)> = harness
        .output()
        .shapes
        .iter()
        .enumerate()
        .map(|(i, s)| (i, s.shape.clone()))
        .collect();
    let mut flat = Vec::new();
    fn flatten(shape: Shape, out: &mut Vec<Shape>) {
        match shape {
            Shape::Vec(shapes) => shapes.into_iter().for_each(|s| flatten(s, out)),
            shape => out.push(shape),
        }
    }
    for (_, shape) in shapes {
        flatten(shape, &mut flat);
    }
    let (at, verdict) = flat
        .iter()
        .enumerate()
        .find_map(|(i, s)| match s {
            Shape::Text(t) if t.galley.text().starts_with("the segments cross") => {
                Some((i, t.visual_bounding_rect()))
            }
            _ => None,
        })
        .expect("the verdict is drawn");
    let over: Vec<&Shape> = flat[at + 1..]
        .iter()
        .filter(|s| s.visual_bounding_rect().intersects(verdict))
        .collect();
    assert!(over.is_empty(), "drawn over the verdict: {over:?}");
    // The whole line does cross the verdict's box: the check above is not empty by chance.
    assert!(
        flat[..at]
            .iter()
            .any(|s| matches!(s, Shape::LineSegment { .. } | Shape::Path(_))
                && s.visual_bounding_rect().intersects(verdict)),
        "no line under the verdict"
    );
}

/// On a 1280x800 projector at 150% and 200% the Render view's image takes the height below its
/// controls (the class looks at the image; the summary, the rays by kind and the probe scroll below
/// it): over half the screen at 150%, over a third at 200% where the menus and controls take half;
/// the summary's first line shows whole below it.
/// Before, the summary and room for the details came first and the image had a fifth to a quarter.
/// At 100% the summary stays above the image.
#[test]
fn the_render_image_fills_the_height_on_a_zoomed_projector() {
    for (zoom, share) in [(1.0, 0.6), (1.5, 0.5), (2.0, 0.3)] {
        let mut harness = projector(1280.0, 800.0, zoom);
        let screen_height = 800.0 / zoom;
        common::load_preset(&mut harness, "Render: a closed mesh");
        let image = harness.get_by_label("Correct render").rect();
        assert!(
            image.height() >= share * screen_height,
            "at {zoom}x the image is {:.0} of {screen_height:.0} points tall",
            image.height()
        );
        let summary = harness.get_by_label_contains("pixels hit").rect();
        if zoom == 1.0 {
            assert!(summary.max.y <= image.min.y, "{summary:?} above {image:?}");
        } else {
            assert!(summary.min.y >= image.max.y, "{summary:?} below {image:?}");
            // Its first line whole, not cut by the scroll area's edge.
            let texts = painted_texts(&harness);
            let painted = texts
                .iter()
                .find(|t| t.text.contains("pixels hit"))
                .unwrap_or_else(|| panic!("no summary painted at {zoom}x"));
            assert!(
                painted.rect.max.y <= painted.clip.max.y,
                "at {zoom}x the summary {:?} is cut by {:?}",
                painted.rect,
                painted.clip
            );
        }
    }
}

/// The Render view's "Method:" label and its box share a row at every zoom: where the row has no
/// room for both, both go to the next one (before, the label ended the row and its box started the
/// next at 150% and 200%).
#[test]
fn the_method_label_keeps_its_box_on_its_row() {
    for zoom in [1.0, 1.5, 2.0] {
        for preset in ["Render: common bugs", "Render: a closed mesh"] {
            let mut harness = projector(1280.0, 800.0, zoom);
            common::load_preset(&mut harness, preset);
            unfold_controls(&mut harness);
            let label = harness
                .get_by_role_and_label(egui::accesskit::Role::Label, "Method:")
                .rect();
            let chooser = harness
                .get_by_role_and_label(egui::accesskit::Role::ComboBox, "Method:")
                .rect();
            assert!(
                chooser.min.y < label.max.y && label.min.y < chooser.max.y,
                "{preset} at {zoom}x: “Method:” at {label:?}, its box at {chooser:?}"
            );
        }
    }
}

/// The Keys window (?) reads whole on the projector: at 150% and 200% its descriptions wrap inside
/// the window and the window inside the screen.
#[test]
fn the_keys_window_reads_cleanly_at_150_and_200_percent() {
    for zoom in [1.5, 2.0] {
        let mut harness = projector(1280.0, 800.0, zoom);
        harness.run();
        harness.key_press(egui::Key::F1);
        harness.run();
        assert!(harness.state().keys_open);
        let screen = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(1280.0, 800.0) / zoom);
        // The window covers the view behind it (that is no overprint): only cut text counts.
        let problems: Vec<String> = layout_problems(&harness, screen)
            .into_iter()
            .filter(|p| p.contains(" cut ") || p.contains("past the window"))
            .collect();
        assert!(problems.is_empty(), "{zoom}x: {}", problems.join("\n"));
    }
}

/// Presentation steps keep what earlier steps set: on the touching segments, t's step slides A(t) to
/// its solution and s's step then slides B(s) without moving A(t) back; Back puts each step's view
/// back as Next left it, and Next computes the parameter again (it slides once more).
#[test]
fn presentation_steps_keep_their_parameters_going_forward_and_back() {
    use raylab::app::segments_view::SegmentsView;
    let mut harness = projector(1280.0, 800.0, 1.0);
    common::load_preset(&mut harness, "Segments touching at an endpoint");
    let start = {
        let view = app_view::<SegmentsView>(&harness);
        (view.t, view.s)
    };
    harness.key_press(egui::Key::F5);
    harness.run();
    let highlighted = |harness: &Harness<'static, RaylabApp>| common::highlighted(harness);
    // Forward to the step that slides t, then to the one that slides s.
    let mut steps = 0;
    while highlighted(&harness) != "Highlighted: t at its solution" {
        common::press(&mut harness, [egui::Key::Space]);
        steps += 1;
        assert!(steps < 30, "no step computes t");
    }
    let t_step = harness.state().presentation.unwrap();
    while highlighted(&harness) != "Highlighted: s at its solution" {
        common::press(&mut harness, [egui::Key::Space]);
        steps += 1;
        assert!(steps < 30, "no step computes s");
    }
    let s_step = harness.state().presentation.unwrap();
    let points = app_view::<SegmentsView>(&harness).scene.points();
    let pair = raylab::geometry::segments::SegmentPair::<f64>::from_floats(points);
    let solved = raylab::geometry::segments::solve(&pair, &mut ());
    let (t_star, s_star) = (solved.t.unwrap(), solved.s.unwrap());
    let view = app_view::<SegmentsView>(&harness);
    assert_eq!((view.t, view.s), (t_star, s_star), "both at their solution");
    // Back past t's step: A(t) where it started; Next: it slides to t* again.
    while harness.state().presentation.unwrap() >= t_step {
        common::press(&mut harness, [egui::Key::ArrowLeft]);
    }
    assert_eq!(app_view::<SegmentsView>(&harness).t, start.0);
    common::press(&mut harness, [egui::Key::ArrowRight]);
    assert_eq!(harness.state().presentation, Some(t_step));
    assert_eq!(app_view::<SegmentsView>(&harness).t, t_star);
    assert_eq!(app_view::<SegmentsView>(&harness).s, start.1);
    // A clicker pressed twice quickly (s's step follows t's): B(s)'s slide starts while A(t)'s is
    // on its way, and A(t) still lands on t*.
    assert_eq!(s_step, t_step + 1);
    common::press(&mut harness, [egui::Key::ArrowLeft]);
    harness.key_press(egui::Key::ArrowRight);
    harness.step();
    harness.key_press(egui::Key::ArrowRight);
    harness.run();
    assert_eq!(harness.state().presentation, Some(s_step));
    let view = app_view::<SegmentsView>(&harness);
    assert_eq!((view.t, view.s), (t_star, s_star));
}

/// At 200% the practice panel's feedback lies below its fold: Check scrolls it into view, the
/// "Not yet" line and its hint both whole on screen.
#[test]
fn practice_feedback_scrolls_into_view_at_200_percent() {
    for kind in [
        raylab::exercise::Kind::Triangle,
        raylab::exercise::Kind::Parallelogram,
    ] {
        let zoom = 2.0;
        let screen = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(1280.0, 800.0) / zoom);
        let mut harness = projector(1280.0, 800.0, zoom);
        harness
            .state_mut()
            .start_practice(kind, raylab::exercise::Level::Hit);
        harness.run();
        harness.get_by_label("Your answer:").click();
        harness.run();
        harness.get_by_label("Your answer:").type_text("7, 7, 7");
        harness.run();
        harness.get_by_label("Check").click();
        harness.run();
        let texts = painted_texts(&harness);
        let at = texts
            .iter()
            .position(|t| t.text.starts_with("Not yet"))
            .expect("the feedback is drawn");
        // The "Not yet" line and the hint's first row after it.
        for text in &texts[at..=at + 1] {
            let seen = text.rect.intersect(text.clip).intersect(screen);
            assert!(
                seen.height() >= text.rect.height() - 1.0,
                "{}: “{}” at {:?}, seen {:?}",
                kind.name(),
                text.text,
                text.rect,
                seen
            );
        }
    }
}

/// The step panel keeps its width through zooming in and out: back at 100% it is as wide as before
/// (it came back narrower each time, 630 → 480 → 358 points, clamped to the zoomed window's room).
#[test]
fn the_step_panel_keeps_its_width_through_zooming() {
    let mut harness = projector(1280.0, 800.0, 1.0);
    common::load_preset(&mut harness, "Seed 000: the lecture triangle");
    let view_width = |harness: &Harness<'static, RaylabApp>| {
        harness.state().view_rect.expect("a view was drawn").width() * harness.ctx.zoom_factor()
    };
    let first = view_width(&harness);
    for _ in 0..3 {
        for zoom in [1.5, 2.0, 1.0] {
            harness.ctx.set_zoom_factor(zoom);
            harness.run();
        }
        let now = view_width(&harness);
        assert!(
            (now - first).abs() < 2.0,
            "the view was {first:.0} pixels wide at 100%, after zooming {now:.0}"
        );
    }
}

/// At 200% on a 1280x800 projector the drawing (or the rendered image) takes over half the height: the
/// controls fold under one header (open on a click, the sliders whole), the verdict stays one row.
/// Before, the Triangle view's drawing had about a third of the height under a verdict and a
/// strip of sliders, and the Cornell box image 240 of 800 pixels under the effect controls.
#[test]
fn the_drawing_takes_most_of_a_200_percent_projector() {
    use egui::accesskit::Role;
    let screen_height = 800.0 / 2.0;
    for (preset, drawing) in [
        ("Seed 000: the lecture triangle", Role::Canvas),
        ("Seed 001: ray and parallelogram", Role::Canvas),
        ("Seed 000: segments that cross", Role::Canvas),
        ("Render: a Cornell box", Role::Image),
    ] {
        let mut harness = projector(1280.0, 800.0, 2.0);
        let scene = raylab::scene::preset_names()
            .iter()
            .filter_map(|name| raylab::scene::preset(name))
            .find(|scene| scene.title == preset)
            .expect("a shipped preset");
        load_small(&mut harness, scene);
        let rect = harness
            .query_all_by(|node| node.role() == drawing)
            .map(|node| node.rect())
            .max_by(|a, b| a.height().total_cmp(&b.height()))
            .unwrap_or_else(|| panic!("{preset}: no {drawing:?}"));
        assert!(
            rect.height() >= 0.5 * screen_height,
            "{preset}: the drawing is {:.0} of {screen_height:.0} points tall",
            rect.height()
        );
        // The folded controls open whole.
        let header = harness.get_by_label_contains("Controls:");
        header.click();
        harness.run();
        if drawing == Role::Canvas {
            let slider = harness.query_all_by_role(Role::Slider).next();
            assert!(slider.is_some(), "{preset}: no slider after unfolding");
        } else {
            harness.get_by_label("Compare with a bug:");
            // The camera's reset and the mode stay out of the fold, once.
            assert_eq!(
                harness.query_all_by_label("World vs object space").count(),
                1
            );
        }
    }
}
