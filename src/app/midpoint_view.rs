//! A toy lecture view, the count of what a new view touches: this file, its `mod` line in mod.rs, and
//! its line in a registry (here the test's: the app's tabs plus this one). It solves a problem the app
//! has (two segments) another way: the midpoint M = (A1 + A2) / 2 of segment A, with its step.

use egui::Ui;
use serde::{Deserialize, Serialize};

use super::highlight::{Element, Parameter};
use super::view::{LectureView, bits_of, first_scene};
use crate::geometry::Precision;
use crate::scene::SegmentsScene;
use crate::trace::{Payload, Step, Trace, Vector};

/// The midpoint of segment A.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct MidpointView {
    /// The inputs (segment B is not used).
    pub scene: SegmentsScene,
}

/// One frame's solve: the midpoint, and its step.
pub struct Solved {
    midpoint: [f64; 2],
    trace: Trace,
}

impl AsRef<Trace> for Solved {
    fn as_ref(&self) -> &Trace {
        &self.trace
    }
}

impl LectureView for MidpointView {
    type Scene = SegmentsScene;
    type Solved = Solved;

    fn load(&mut self, scene: SegmentsScene) {
        self.scene = scene;
    }

    fn scene(&self) -> &SegmentsScene {
        &self.scene
    }

    fn solve(&self, precision: Precision) -> Solved {
        let [a1, a2] = [self.scene.a1, self.scene.a2];
        let midpoint = [(a1[0] + a2[0]) / 2.0, (a1[1] + a2[1]) / 2.0];
        let mut trace = Trace::new("midpoint", precision);
        trace.steps.push(Step::new(
            "M",
            "Midpoint of A",
            "Half way from A1 to A2: M = (A1 + A2) / 2.",
            Payload::Vector(Vector::of("M", "M", &midpoint)),
        ));
        Solved { midpoint, trace }
    }

    fn ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let [x, y] = solved.midpoint;
        ui.label(format!("M = ({x}, {y})"));
        if ui.button("Move A1 right").clicked() {
            self.scene.a1[0] += 1.0;
        }
    }

    fn present_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        self.ui(ui, solved);
    }

    fn show_parameter(&mut self, _parameter: Parameter, _solved: &Solved, _now: f64) {}

    fn highlight(&mut self, _elements: &[Element]) {}

    fn fingerprint(&self, bits: &mut Vec<u64>) {
        bits_of(bits, self.scene.a1.into_iter().chain(self.scene.a2));
    }
}

impl Default for MidpointView {
    fn default() -> MidpointView {
        first_scene(|scene| MidpointView { scene })
    }
}

#[cfg(test)]
mod tests {
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;

    use super::*;
    use crate::app::view::{ViewEntry, restored};
    use crate::app::{RaylabApp, VIEWS, ViewKind};

    const MIDPOINT: ViewKind = ViewKind::new("midpoint", "Midpoint");

    /// The view, registered by one line in a registry, is a tab: it draws, its step shows in the step
    /// panel, a change of its inputs redraws both, and it is saved under its name.
    #[test]
    fn a_view_registered_by_one_line_is_a_tab_with_steps() {
        let harness = Harness::builder()
            .with_size(egui::Vec2::new(1280.0, 800.0))
            .build_eframe(|cc| {
                crate::app::set_style(&cc.egui_ctx);
                let registry: Vec<ViewEntry> = VIEWS
                    .iter()
                    .copied()
                    .chain([ViewEntry::new(MIDPOINT, restored::<MidpointView>)])
                    .collect();
                RaylabApp::with_views(&registry)
            });
        let mut harness = harness;
        harness.run();
        harness.get_by_label("Midpoint").click();
        harness.run();
        assert_eq!(harness.state().state.view.name(), "midpoint");
        // Seed 000's A runs from (1, 2) to (6, 1): M shows in the view and in its step.
        let shown =
            |harness: &Harness<'_, RaylabApp>, text: &str| harness.query_all_by_label(text).count();
        assert_eq!(shown(&harness, "M = (3.5, 1.5)"), 2);
        // The step's title, and the step read whole by a screen reader.
        assert_eq!(
            harness.query_all_by_label_contains("Midpoint of A").count(),
            2
        );
        harness.get_by_label("Move A1 right").click();
        harness.run();
        assert_eq!(shown(&harness, "M = (4, 1.5)"), 2);
        assert_eq!(shown(&harness, "M = (3.5, 1.5)"), 0);
        let step = harness.state().solve();
        assert_eq!(step.get::<Solved>().map(|s| s.midpoint), Some([4.0, 1.5]));
        let saved = ron::to_string(&harness.state().state).unwrap();
        assert!(
            saved.contains(r#""midpoint":(view:Some("(scene:(a1:(2.0,2.0)"#),
            "{saved}"
        );
    }
}
