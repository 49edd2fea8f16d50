//! The Parallelogram view (seed 001): c + α e1 + β e2 against the ray o + t d, with sliders for α, β and
//! t, and the step panel solving M (α, β, t)ᵀ = o − c with M = [e1 | e2 | −d] through M⁻¹.

use egui::{FontId, RichText, Sense, Stroke, Ui};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::widgets::palette::{self, faded};
use super::widgets::scene3d::{Canvas, OrbitCamera, Projector};
use super::widgets::{ParameterSlider, parameter_sliders, status_line, vector_editor};
use crate::exact::Exact;
use crate::geometry::parallelogram::{self, ParallelogramOutcome, ParallelogramSolution};
use crate::geometry::{Precision, Reading};
use crate::scene::ParallelogramScene;
use crate::trace::{Trace, format_float};

/// Everything the Parallelogram view remembers.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct ParallelogramView {
    /// The inputs.
    pub scene: ParallelogramScene,
    /// The α slider.
    pub alpha: f64,
    /// The β slider.
    pub beta: f64,
    /// The t slider.
    pub t: f64,
    /// The camera.
    pub camera: OrbitCamera,
    /// The last frame's projection.
    #[serde(skip)]
    pub projector: Option<Projector>,
}

impl Default for ParallelogramView {
    fn default() -> ParallelogramView {
        let scene = crate::scene::built_in()
            .into_iter()
            .find_map(|s| match s.problem {
                crate::scene::Problem::Parallelogram(p) => Some(p),
                _ => None,
            })
            .expect("a parallelogram scene ships");
        let mut view = ParallelogramView {
            scene: scene.clone(),
            alpha: 0.0,
            beta: 0.0,
            t: 0.0,
            camera: OrbitCamera::default(),
            projector: None,
        };
        view.load(scene);
        view
    }
}

/// The solves one frame needs.
pub struct Solved {
    /// The f64 solve.
    pub float: ParallelogramSolution<f64>,
    /// The exact solve of the inputs as written.
    pub exact: ParallelogramSolution<Exact>,
    /// The trace in the step panel's precision.
    pub trace: Trace,
}

impl ParallelogramView {
    /// Loads a scene.
    pub fn load(&mut self, scene: ParallelogramScene) {
        let corner = DVec3::from(scene.corner);
        let points = [
            corner,
            corner + DVec3::from(scene.e1),
            corner + DVec3::from(scene.e2),
            DVec3::from(scene.origin),
            DVec3::ZERO,
        ];
        self.camera = OrbitCamera::framing(&points).across(DVec3::from(scene.dir));
        self.scene = scene;
        self.alpha = 0.5;
        self.beta = 0.5;
        self.t = 0.5;
    }

    fn vectors(&self) -> [DVec3; 5] {
        let s = &self.scene;
        [s.corner, s.e1, s.e2, s.origin, s.dir].map(DVec3::from)
    }

    /// Solves the current inputs.
    pub fn solve(&self, precision: Precision) -> Solved {
        let v = self.vectors();
        let trace = match precision {
            Precision::F32 => parallelogram::solve_inputs::<f32>(Reading::AsWritten, v, true).trace,
            Precision::F64 => parallelogram::solve_inputs::<f64>(Reading::AsWritten, v, true).trace,
            Precision::Exact => {
                parallelogram::solve_inputs::<Exact>(Reading::AsWritten, v, true).trace
            }
        };
        Solved {
            float: parallelogram::solve_inputs(Reading::AsWritten, v, false),
            exact: parallelogram::solve_inputs(Reading::AsWritten, v, false),
            trace: trace.expect("recorded"),
        }
    }

    /// The view: controls below, the 3D canvas above.
    pub fn ui(&mut self, ui: &mut Ui, solved: &Solved) {
        egui::Panel::bottom("parallelogram-controls")
            .resizable(false)
            .show(ui, |ui| self.controls_ui(ui, solved));
        egui::CentralPanel::default().show(ui, |ui| self.canvas_ui(ui, solved));
    }

    fn controls_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        ui.add_space(4.0);
        ui.horizontal_wrapped(|ui| {
            let target = solved.float.alpha_beta_t;
            if ui
                .add_enabled(target.is_some(), egui::Button::new("Solve"))
                .on_hover_text("Set α, β and t to M⁻¹ (o − c)")
                .on_disabled_hover_text("M is singular: no unique solution")
                .clicked()
                && let Some([alpha, beta, t]) = target
            {
                (self.alpha, self.beta, self.t) = (alpha, beta, t);
            }
            if ui
                .button("Reset view")
                .on_hover_text("Frame the parallelogram and the ray again")
                .clicked()
            {
                let sliders = (self.alpha, self.beta, self.t);
                self.load(self.scene.clone());
                (self.alpha, self.beta, self.t) = sliders;
            }
        });
        parameter_sliders(
            ui,
            vec![
                ParameterSlider {
                    value: &mut self.alpha,
                    range: -0.5..=1.5,
                    name: "α",
                    tip: "How far along e1 from c",
                },
                ParameterSlider {
                    value: &mut self.beta,
                    range: -0.5..=1.5,
                    name: "β",
                    tip: "How far along e2 from c",
                },
                ParameterSlider {
                    value: &mut self.t,
                    range: -3.0..=3.0,
                    name: "t",
                    tip: "How far along the ray, in steps of d",
                },
            ],
        );
        let explored = self.exploration();
        status_line(ui, |ui| {
            let exact = solved.exact.alpha_beta_t.as_ref();
            for (i, (symbol, value)) in [("α", self.alpha), ("β", self.beta), ("t", self.t)]
                .into_iter()
                .enumerate()
            {
                let solution = solved.float.alpha_beta_t.map(|x| x[i]);
                let text = match (solution, exact) {
                    (Some(s), Some(e)) if s == value && e[i].is_short() => e[i].fraction(),
                    _ => format_float(value, Precision::F64),
                };
                ui.label(RichText::new(format!("{symbol} = {text}")).strong());
            }
        });
        status_line(ui, |ui| {
            let (text, color) = if explored.inside {
                ("p(α, β) is on the parallelogram", palette::INSIDE)
            } else {
                (
                    "p(α, β) is off the parallelogram: α and β must be in [0, 1]",
                    palette::OUTSIDE,
                )
            };
            ui.label(RichText::new(text).color(color));
            ui.label(format!(
                "distance |p(α, β) − (o + t d)| = {}",
                format_float(explored.gap, Precision::F64)
            ));
        });
        egui::CollapsingHeader::new("Inputs: c, e1, e2, o, d")
            .default_open(false)
            .show(ui, |ui| {
                let s = &mut self.scene;
                vector_editor(ui, "c", None, "The corner c", &mut s.corner, 0.05);
                vector_editor(
                    ui,
                    "e1",
                    Some(palette::BETA),
                    "Edge vector e1",
                    &mut s.e1,
                    0.05,
                );
                vector_editor(
                    ui,
                    "e2",
                    Some(palette::GAMMA),
                    "Edge vector e2",
                    &mut s.e2,
                    0.05,
                );
                vector_editor(
                    ui,
                    "o",
                    Some(palette::RAY),
                    "The ray's origin o",
                    &mut s.origin,
                    0.05,
                );
                vector_editor(
                    ui,
                    "d",
                    Some(palette::RAY),
                    "The ray's direction d",
                    &mut s.dir,
                    0.05,
                );
            });
    }

    fn problem(&self) -> parallelogram::RayParallelogram<f64> {
        parallelogram::RayParallelogram::from_f64(self.vectors()).expect("f64 holds every f64")
    }

    fn exploration(&self) -> parallelogram::Exploration<f64> {
        parallelogram::explore(&self.problem(), &self.alpha, &self.beta, &self.t)
    }

    fn canvas_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        if response.dragged() {
            self.camera.orbit(response.drag_delta());
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom(scroll);
            }
        }
        let projector = self.camera.projector(response.rect);
        let canvas = Canvas {
            painter: &painter,
            projector: &projector,
        };
        let text = ui.visuals().text_color();
        let font = FontId::proportional(16.0);
        let [c, _, _, o, d] = self.vectors();
        // The corners p(0,0), p(1,0), p(1,1), p(0,1) from the core's parametric form.
        let problem = self.problem();
        let corner =
            |alpha: f64, beta: f64| DVec3::from(parallelogram::point_at(&problem, &alpha, &beta));
        let (c_e1, c_e1_e2, c_e2) = (corner(1.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0));
        canvas.axes(&[c, c_e1, c_e2, o]);
        canvas.polygon(
            &[c, c_e1, c_e1_e2, c_e2],
            faded(palette::BETA, 40),
            Stroke::new(2.0, text),
        );
        canvas.arrow(c, c_e1, Stroke::new(3.0, palette::BETA));
        canvas.label(c_e1, "e1", palette::BETA, font.clone());
        canvas.arrow(c, c_e2, Stroke::new(3.0, palette::GAMMA));
        canvas.label(c_e2, "e2", palette::GAMMA, font.clone());
        canvas.label(c, "c", text, font.clone());
        let explored = self.exploration();
        let p = DVec3::from(explored.plane_point);
        let color = if explored.inside {
            palette::INSIDE
        } else {
            palette::OUTSIDE
        };
        canvas.dot(p, 7.0, color);
        canvas.label(p, "p(α, β)", color, font.clone());
        let t_star = solved.float.alpha_beta_t.map_or(1.0, |x| x[2]);
        let far = t_star.max(self.t).max(1.0) * 1.4;
        canvas.line(o, o + far * d, Stroke::new(2.5, palette::RAY));
        canvas.dashed(
            o + t_star.min(-1.0) * 1.4 * d,
            o,
            Stroke::new(1.5, faded(palette::RAY, 170)),
        );
        canvas.dot(o, 6.0, palette::RAY);
        canvas.label(o, "o", palette::RAY, font.clone());
        canvas.arrow(o, o + d, Stroke::new(3.0, palette::RAY));
        let on_ray = DVec3::from(explored.ray_point);
        canvas.dot(on_ray, 6.0, palette::RAY);
        canvas.label(on_ray, "o + t d", palette::RAY, font.clone());
        if explored.gap > 0.0 {
            canvas.dashed(p, on_ray, Stroke::new(1.0, faded(text, 140)));
        }
        if let Some(point) = solved.float.point {
            let (color, label) = match solved.float.outcome {
                ParallelogramOutcome::Hit => (palette::SOLUTION, "hit"),
                ParallelogramOutcome::Behind => (palette::OUTSIDE, "ghost hit behind o"),
                _ => (palette::OUTSIDE, "misses: off the parallelogram"),
            };
            canvas.ring(DVec3::from(point), 11.0, Stroke::new(2.5, color));
            canvas.label(DVec3::from(point), label, color, font.clone());
        }
        super::widgets::verdict_overlay(ui, &painter, response.rect, &solved.trace);
        self.projector = Some(projector);
    }
}
