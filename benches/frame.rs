//! CPU cost of one app frame at 1280x800: egui's pass (layout, solving, the step panel) plus
//! tessellation, for each view while a slider moves (so every frame re-solves and redraws).
//!
//! `cargo bench --bench frame`; the budget is 4 ms for the busiest view.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use egui::Vec2;
use egui_kittest::Harness;
use raylab::app::parallelogram_view::ParallelogramView;
use raylab::app::segments_view::SegmentsView;
use raylab::app::triangle_view::TriangleView;
use raylab::app::{RaylabApp, ViewKind};
use raylab::geometry::Precision;

fn harness(view: ViewKind, precision: Precision) -> Harness<'static, RaylabApp> {
    let mut harness = Harness::builder()
        .with_size(Vec2::new(1280.0, 800.0))
        .with_max_steps(1000)
        .build_eframe(|cc| {
            raylab::app::set_style(&cc.egui_ctx);
            RaylabApp::new()
        });
    harness.state_mut().state.view = view;
    harness.state_mut().state.precision = precision;
    harness.run();
    harness
}

fn frames(c: &mut Criterion) {
    for (name, view) in [
        ("segments", ViewKind::Segments),
        ("triangle", ViewKind::Triangle),
        ("parallelogram", ViewKind::Parallelogram),
    ] {
        for precision in [Precision::F64, Precision::Exact] {
            let mut harness = harness(view, precision);
            let mut k = 0u32;
            c.bench_function(&format!("frame/{name}/{}", precision.name()), |b| {
                b.iter(|| {
                    // Move a parameter, as a drag does, so the frame re-solves and redraws.
                    k = k.wrapping_add(1);
                    let nudge = f64::from(k % 100) / 1000.0;
                    let state = &mut harness.state_mut().state;
                    state.get_mut::<SegmentsView>().t = 0.3 + nudge;
                    state.get_mut::<TriangleView>().beta = 0.2 + nudge;
                    state.get_mut::<ParallelogramView>().alpha = 0.4 + nudge;
                    harness.step();
                    let output = harness.output();
                    let primitives = harness
                        .ctx
                        .tessellate(output.shapes.clone(), output.pixels_per_point);
                    black_box(primitives.len())
                })
            });
        }
    }
}

criterion_group!(benches, frames);
criterion_main!(benches);
