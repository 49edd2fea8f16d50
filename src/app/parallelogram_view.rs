//! The Parallelogram view (seed 001): c + α e1 + β e2 against the ray o + t d, with sliders for α, β and
//! t, and the step panel solving M (α, β, t)ᵀ = o − c with M = [e1 | e2 | −d] through M⁻¹.

use super::widgets::palette::Readable as _;
use super::widgets::{Part, ShownValue, controls_below, handles, shown_values};
use egui::{FontId, RichText, Sense, Stroke, Ui};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::highlight::{Column, Element, Parameter, Side};
use super::view::{LectureView, bits_of, first_scene};
use super::widgets::canvas_state::CanvasState;
use super::widgets::labels::{LabelLayer, Priority};
use super::widgets::palette::{self, faded};
use super::widgets::scene3d::{Canvas, OrbitCamera, Projector};
use super::widgets::{ParameterSlider, parameter_sliders, status_line, vector_editor};
use crate::geometry::parallelogram::{self, ParallelogramOutcome};
use crate::geometry::{ParallelogramLecture, Precision, Reading, Shown};
use crate::scene::ParallelogramScene;
use crate::trace::format_float;

/// A handle the keyboard moves: a point of the scene, or a parameter's point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Corner {
    C,
    E1,
    E2,
    O,
    D,
    Plane,
    Ray,
}

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
    /// The camera (saved), and the last frame's framing, projection and labels.
    #[serde(rename = "camera")]
    pub canvas: CanvasState,
    /// What the step on screen is about: drawn emphasised.
    #[serde(skip)]
    pub highlight: Vec<Element>,
}

/// The solves one frame needs: f64 for drawing, exact for fractions, and the trace for the panel.
pub type Solved = Shown<ParallelogramLecture>;

impl LectureView for ParallelogramView {
    type Scene = ParallelogramScene;
    type Solved = Solved;

    /// Loads a scene.
    fn load(&mut self, scene: ParallelogramScene) {
        let corner = DVec3::from(scene.corner);
        let points = [
            corner,
            corner + DVec3::from(scene.e1),
            corner + DVec3::from(scene.e2),
            DVec3::from(scene.origin),
            DVec3::ZERO,
        ];
        self.canvas.reset(OrbitCamera::framing(&points).across(
            DVec3::from(scene.dir),
            Some(DVec3::from(scene.e1).cross(DVec3::from(scene.e2))),
        ));
        self.scene = scene;
        self.alpha = 0.5;
        self.beta = 0.5;
        self.t = 0.5;
    }

    fn scene(&self) -> &ParallelogramScene {
        &self.scene
    }

    /// Solves the current inputs.
    fn solve(&self, precision: Precision) -> Solved {
        let v = self.scene.vectors();
        Solved::new(v, Reading::AsWritten, precision)
    }

    /// The view: controls below, the 3D canvas above.
    fn ui(&mut self, ui: &mut Ui, solved: &Solved) {
        controls_below(ui, "parallelogram-controls", |ui, part| match part {
            Part::Controls => self.controls_ui(ui, solved),
            Part::Drawing => self.canvas_ui(ui, solved),
        });
    }

    /// The canvas alone, filling the space (presentation mode).
    fn present_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        self.canvas_ui(ui, solved);
    }

    /// Slides a parameter to its value at the solution (presentation mode).
    fn show_parameter(&mut self, parameter: Parameter, solved: &Solved, _now: f64) {
        if let Some([alpha, beta, t]) = solved.float.alpha_beta_t {
            match parameter {
                Parameter::Alpha => self.alpha = alpha,
                Parameter::Beta => self.beta = beta,
                Parameter::T => self.t = t,
                Parameter::Gamma | Parameter::S => {}
            }
        }
    }

    fn highlight(&mut self, elements: &[Element]) {
        self.highlight = elements.to_vec();
    }

    fn fingerprint(&self, bits: &mut Vec<u64>) {
        let vectors = self.scene.vectors().into_iter().flat_map(|v| v.to_array());
        bits_of(bits, vectors.chain([self.alpha, self.beta, self.t]));
    }

    fn canvas_mut(&mut self) -> Option<&mut CanvasState> {
        Some(&mut self.canvas)
    }
}

impl Default for ParallelogramView {
    fn default() -> ParallelogramView {
        first_scene(ParallelogramView::unloaded)
    }
}

impl ParallelogramView {
    /// The view of `scene` before [`ParallelogramView::load`] sets its sliders and camera.
    fn unloaded(scene: ParallelogramScene) -> ParallelogramView {
        ParallelogramView {
            scene,
            alpha: 0.0,
            beta: 0.0,
            t: 0.0,
            canvas: CanvasState::default(),
            highlight: Vec::new(),
        }
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
                ParameterSlider::new(&mut self.alpha, -0.5..=1.5, "α", "How far along e1 from c"),
                ParameterSlider::new(&mut self.beta, -0.5..=1.5, "β", "How far along e2 from c"),
                ParameterSlider::new(
                    &mut self.t,
                    -3.0..=3.0,
                    "t",
                    "How far along the ray, in steps of d",
                ),
            ],
        );
        let explored = self.exploration();
        status_line(ui, |ui| {
            let exact = solved.exact.alpha_beta_t.as_ref();
            let parameters = [self.alpha, self.beta, self.t];
            let values: [ShownValue; 3] = std::array::from_fn(|i| ShownValue {
                value: parameters[i],
                solution: solved.float.alpha_beta_t.map(|x| x[i]),
                exact: exact.map(|e| &e[i]),
            });
            for (symbol, text) in ["α", "β", "t"].into_iter().zip(shown_values(&values)) {
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
            ui.label(RichText::new(text).color(color.readable(ui)));
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
        parallelogram::RayParallelogram::from_floats(self.scene.vectors())
    }

    fn exploration(&self) -> parallelogram::Exploration<f64> {
        parallelogram::explore(&self.problem(), &self.alpha, &self.beta, &self.t)
    }

    fn canvas_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        if response.dragged() {
            self.canvas.orbit(response.drag_delta());
        }
        self.canvas.zoom_on_scroll(ui, &response);
        let keys = handles::canvas_keys(
            ui,
            &response,
            "Parallelogram canvas: the arrows orbit, + and − zoom; Tab reaches its handles",
        );
        self.canvas.orbit_by_keys(keys);
        let [c, _, _, o, d] = self.scene.vectors();
        // The corners p(0,0), p(1,0), p(1,1), p(0,1) from the core's parametric form.
        let problem = self.problem();
        let corner =
            |alpha: f64, beta: f64| DVec3::from(parallelogram::point_at(&problem, &alpha, &beta));
        let (c_e1, c_e1_e2, c_e2) = (corner(1.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0));
        let projector = self.canvas.projector_for(
            response.rect,
            || {
                let mut points = vec![c, c_e1, c_e1_e2, c_e2, o, o + d];
                points.extend(solved.float.point.map(DVec3::from));
                points
            },
            || super::widgets::verdict_height(ui, response.rect.width(), &solved.trace),
        );
        let canvas = Canvas {
            painter: &painter,
            projector: &projector,
        };
        let mut labels = LabelLayer::new(response.rect);
        handles::labels_avoid_focus_ring(ui.ctx(), &mut labels);
        // The handles: corner, edges' tips, origin, direction's tip, p(α, β) and o + t d (those
        // two as the core puts them).
        let explored = self.exploration();
        let handles: Vec<egui::Pos2> = [
            c,
            c_e1,
            c_e2,
            o,
            o + d,
            DVec3::from(explored.plane_point),
            DVec3::from(explored.ray_point),
        ]
        .into_iter()
        .filter_map(|p| projector.screen_from_world(p))
        .collect();
        let verdict =
            super::widgets::verdict_overlay(ui, &painter, response.rect, &solved.trace, &handles);
        if let Some(verdict) = &verdict {
            labels.avoid(verdict.rect);
        }
        let text = ui.visuals().text_color();
        canvas.axes_labelled(&[c, c_e1, c_e2, o], &mut labels);
        canvas.polygon(
            &[c, c_e1, c_e1_e2, c_e2],
            faded(palette::BETA, 40),
            Stroke::new(2.0, text),
        );
        self.draw_highlights(&canvas, solved, [c, c_e1, c_e1_e2, c_e2], &mut labels);
        for (from, to, color, name) in [
            (c, c_e1, palette::BETA, "e1"),
            (c, c_e2, palette::GAMMA, "e2"),
        ] {
            canvas.arrow(from, to, Stroke::new(3.0, color));
            canvas.place_label(&mut labels, to, name, color, Priority::Key);
            guide(&canvas, &mut labels, from, to);
        }
        for (from, to) in [(c_e1, c_e1_e2), (c_e1_e2, c_e2)] {
            guide(&canvas, &mut labels, from, to);
        }
        if let Some(at) = canvas.dot(c, 4.0, text) {
            labels.avoid_point(at, 5.0);
        }
        canvas.place_label(&mut labels, c, "c", text, Priority::Key);
        let explored = self.exploration();
        let p = DVec3::from(explored.plane_point);
        let color = if explored.inside {
            palette::INSIDE
        } else {
            palette::OUTSIDE
        };
        let t_star = solved.float.alpha_beta_t.map_or(1.0, |x| x[2]);
        let far = t_star.max(self.t).max(1.0) * 1.4;
        let back = t_star.min(-1.0) * 1.4;
        canvas.line(o, o + far * d, Stroke::new(2.5, palette::RAY));
        canvas.dashed(o + back * d, o, Stroke::new(1.5, faded(palette::RAY, 170)));
        guide(&canvas, &mut labels, o + back * d, o + far * d);
        canvas.arrow(o, o + d, Stroke::new(3.0, palette::RAY));
        let on_ray = DVec3::from(explored.ray_point);
        if explored.gap > 0.0 {
            canvas.dashed(p, on_ray, Stroke::new(1.0, faded(text, 140)));
        }
        for (at, radius, dot_color, inside) in [
            (p, 7.0, color, explored.inside),
            (o, 6.0, palette::RAY, true),
            (on_ray, 6.0, palette::RAY, true),
        ] {
            if let Some(screen) = canvas.inside_mark(at, radius, dot_color, inside) {
                labels.avoid_point(screen, radius + 1.0);
            }
        }
        // The keyboard's handles at the tips of e1, e2 and d: no label covers them either.
        for tip in [c_e1, c_e2, o + d] {
            if let Some(at) = canvas.screen(tip) {
                labels.avoid_point(at, 6.0);
            }
        }
        canvas.place_label(&mut labels, o, "o", palette::RAY, Priority::Key);
        canvas.place_label(&mut labels, p, "p(α, β)", color, Priority::Key);
        canvas.place_label(&mut labels, on_ray, "o + t d", palette::RAY, Priority::Key);
        // A practice problem's outcome is for the student to predict.
        let hidden = super::widgets::answers_hidden(ui.ctx());
        if let Some(point) = solved.float.point.filter(|_| !hidden) {
            let (color, label) = match solved.float.outcome {
                ParallelogramOutcome::Hit => (palette::SOLUTION, "hit"),
                ParallelogramOutcome::Behind => (palette::OUTSIDE, "ghost hit behind o"),
                _ => (palette::OUTSIDE, "misses: off the parallelogram"),
            };
            if let Some(at) = canvas.ring(DVec3::from(point), 11.0, Stroke::new(2.5, color)) {
                labels.avoid_point(at, 12.0);
                labels.add(
                    at,
                    label,
                    color,
                    FontId::proportional(16.0),
                    Priority::Normal,
                    12.0,
                );
            }
        }
        self.draw_class_cloud(&canvas);
        if let Some(verdict) = verdict {
            verdict.paint(&painter);
        }
        self.canvas.labels = labels.paint(ui, &painter, ui.scope_id().with("parallelogram-labels"));
        self.keyboard_ui(ui, &projector, solved);
        self.canvas.projector = Some(projector);
    }

    /// The handles as the keyboard and a screen reader reach them, named with their values: c, the
    /// tips of e1 and e2, o and the tip of d move along the world axes nearest the screen's right
    /// and up (by 0.25, Shift 0.05, on a 0.05 grid); p(α, β) moves in α (← →) and β (↑ ↓), o + t d
    /// in t (by 0.05, Shift 0.01, landing on the solution); Enter solves.
    fn keyboard_ui(&mut self, ui: &Ui, projector: &Projector, solved: &Solved) {
        let [c, e1, e2, o, d] = self.scene.vectors();
        let explored = self.exploration();
        let (p, on_ray) = (
            DVec3::from(explored.plane_point),
            DVec3::from(explored.ray_point),
        );
        let text = |p: DVec3| handles::point_text(&p.to_array());
        let value = handles::value_text;
        let side = if explored.inside { "inside" } else { "outside" };
        let all = [
            (Corner::C, c, format!("corner c at {}", text(c))),
            (
                Corner::E1,
                c + e1,
                format!("edge e1 = {}, its tip at {}", text(e1), text(c + e1)),
            ),
            (
                Corner::E2,
                c + e2,
                format!("edge e2 = {}, its tip at {}", text(e2), text(c + e2)),
            ),
            (Corner::O, o, format!("ray origin o at {}", text(o))),
            (
                Corner::D,
                o + d,
                format!(
                    "direction d = {}, its tip o + d at {}",
                    text(d),
                    text(o + d)
                ),
            ),
            (
                Corner::Plane,
                p,
                format!(
                    "p(α, β) at α = {}, β = {}: {}, {side} the parallelogram",
                    value(self.alpha),
                    value(self.beta),
                    text(p)
                ),
            ),
            (
                Corner::Ray,
                on_ray,
                format!("o + t d at t = {}: {}", value(self.t), text(on_ray)),
            ),
        ];
        let solution = solved.float.alpha_beta_t;
        for (handle, world, description) in all {
            let Some(at) = projector.screen_from_world(world) else {
                continue;
            };
            let keys = handles::keyboard_handle(
                ui,
                &format!("parallelogram {handle:?}"),
                at,
                &description,
            );
            if keys.solve
                && let Some([alpha, beta, t]) = solution
            {
                (self.alpha, self.beta, self.t) = (alpha, beta, t);
            }
            if keys.moved() {
                self.move_by_keys(handle, &keys, projector, solution);
            }
        }
    }

    fn move_by_keys(
        &mut self,
        handle: Corner,
        keys: &handles::HandleKeys,
        projector: &Projector,
        solution: Option<[f64; 3]>,
    ) {
        let [alpha_star, beta_star, t_star] = solution.map_or([None; 3], |s| s.map(Some));
        let step = keys.step(0.05, 0.01);
        let moved = |p: DVec3| {
            let step = keys.step(0.25, 0.05);
            DVec3::from(handles::step_point(
                p.to_array(),
                keys,
                projector.right,
                projector.up,
                step,
                0.05,
            ))
        };
        let [c, e1, e2, o, d] = self.scene.vectors();
        let s = &mut self.scene;
        match handle {
            Corner::C => s.corner = moved(c).to_array(),
            Corner::E1 => s.e1 = (moved(c + e1) - c).to_array(),
            Corner::E2 => s.e2 = (moved(c + e2) - c).to_array(),
            Corner::O => s.origin = moved(o).to_array(),
            Corner::D => s.dir = (moved(o + d) - o).to_array(),
            Corner::Plane => {
                self.alpha =
                    handles::step_value(self.alpha, keys.right, step, keys.fine, alpha_star);
                self.beta = handles::step_value(self.beta, keys.up, step, keys.fine, beta_star);
            }
            Corner::Ray => {
                self.t = handles::step_value(self.t, keys.right + keys.up, step, keys.fine, t_star);
            }
        }
    }

    /// Emphasises what the step on screen is about.
    /// A live class's predictions of P(α, β) = c + α e1 + β e2, one point each.
    fn draw_class_cloud(&self, canvas: &Canvas) {
        let problem = crate::scene::Problem::Parallelogram(self.scene.clone());
        let [c, e1, e2, ..] = self.scene.vectors();
        super::class_view::draw_cloud(canvas.painter, &problem, |values| match values {
            [Some(alpha), Some(beta)] => canvas
                .projector
                .screen_from_world(c + alpha * e1 + beta * e2)
                .into_iter()
                .collect(),
            _ => Vec::new(),
        });
    }

    fn draw_highlights(
        &self,
        canvas: &Canvas,
        solved: &Solved,
        [c, c_e1, c_e1_e2, c_e2]: [DVec3; 4],
        labels: &mut LabelLayer,
    ) {
        let [_, _, _, o, d] = self.scene.vectors();
        let glow = |color: egui::Color32| Stroke::new(11.0, faded(color, 90));
        for element in &self.highlight {
            match element {
                Element::Column(Column::E1) => canvas.line(c, c_e1, glow(palette::BETA)),
                Element::Column(Column::E2) => canvas.line(c, c_e2, glow(palette::GAMMA)),
                Element::Column(Column::MinusD) => {
                    canvas.line(o, o - d, glow(palette::RAY));
                    canvas.arrow(o, o - d, Stroke::new(3.0, palette::RAY));
                    canvas.place_label(labels, o - d, "−d", palette::RAY, Priority::Normal);
                }
                Element::Rhs => {
                    canvas.line(c, o, glow(palette::RHS));
                    canvas.arrow(c, o, Stroke::new(3.0, palette::RHS));
                    canvas.place_label(
                        labels,
                        (c + o) / 2.0,
                        "o − c",
                        palette::RHS,
                        Priority::Normal,
                    );
                }
                Element::Side(Side::AlphaBounds) => {
                    canvas.line(c, c_e2, glow(palette::SOLUTION));
                    canvas.line(c_e1, c_e1_e2, glow(palette::SOLUTION));
                }
                Element::Side(Side::BetaBounds) => {
                    canvas.line(c, c_e1, glow(palette::SOLUTION));
                    canvas.line(c_e2, c_e1_e2, glow(palette::SOLUTION));
                }
                Element::Origin => {
                    canvas.ring(o, 13.0, Stroke::new(4.0, faded(palette::SOLUTION, 200)));
                }
                Element::Hit => {
                    if let Some(point) = solved.float.point {
                        canvas.ring(DVec3::from(point), 17.0, glow(palette::SOLUTION));
                    }
                }
                Element::Parameter(Parameter::T) => {
                    let on_ray = DVec3::from(self.exploration().ray_point);
                    canvas.line(o, on_ray, glow(palette::RAY));
                }
                Element::Parameter(Parameter::Alpha | Parameter::Beta) => {
                    let p = DVec3::from(self.exploration().plane_point);
                    canvas.ring(p, 14.0, glow(palette::INSIDE));
                }
                _ => {}
            }
        }
    }
}

/// A drawn line that labels would rather not cross.
fn guide(canvas: &Canvas, labels: &mut LabelLayer, from: DVec3, to: DVec3) {
    if let Some([p, q]) = canvas.projector.segment(from, to) {
        labels.prefer_clear_of(p, q);
    }
}
