//! The Triangle view: a 3D triangle with its plane, the ray L + tD, and sliders for β, γ and t.
//!
//! The sliders move P(β, γ) = A + β(B−A) + γ(C−A) (drawn as the two legs from A, green inside and red
//! outside) and L + tD along the ray; "Solve" slides all three to the solution, where they meet. A, B
//! and C can be dragged in the plane facing the camera; the background orbits, the wheel zooms.

use super::widgets::palette::Readable as _;
use super::widgets::slide::{self, Slide};
use super::widgets::{Part, ShownValue, controls_below, handles, shown_values};
use egui::{FontId, Pos2, RichText, Sense, Stroke, Ui};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::highlight::{Column, Element, Parameter, Side};
use super::view::{LectureView, bits_of, first_scene};
use super::widgets::canvas_state::CanvasState;
use super::widgets::labels::{LabelLayer, Priority};
use super::widgets::palette::{self, faded};
use super::widgets::scene3d::{Canvas, OrbitCamera, Projector};
use super::widgets::{ParameterSlider, parameter_sliders, snap, status_line, vector_editor};
use crate::geometry::triangle::{self, Edge, TriangleMiss, TriangleOutcome};
use crate::geometry::{Precision, Reading, Shown, TriangleLecture};
use crate::scene::TriangleScene;
use crate::trace::format_float;

/// A drag in the canvas: a vertex, or the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Grab {
    Vertex(usize),
    Orbit,
}

/// A handle the keyboard moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TriangleHandle {
    Vertex(usize),
    Origin,
    Direction,
    PlanePoint,
    RayPoint,
}

/// Everything the Triangle view remembers.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct TriangleView {
    /// The inputs.
    pub scene: TriangleScene,
    /// The β slider.
    pub beta: f64,
    /// The γ slider.
    pub gamma: f64,
    /// The t slider.
    pub t: f64,
    /// The camera (saved), and the last frame's framing, projection and labels.
    #[serde(rename = "camera")]
    pub canvas: CanvasState,
    /// How exact arithmetic reads the inputs: as typed (0.1 is 1/10), or as the floats they are (the
    /// accuracy study's judge; hard cases load this way).
    pub reading: Reading,
    #[serde(skip)]
    grab: Option<Grab>,
    /// The running "Solve" animation, if any.
    #[serde(skip)]
    pub animation: Option<Slide<3>>,
    /// What the step on screen (or under the pointer) is about: drawn emphasised.
    #[serde(skip)]
    pub highlight: Vec<Element>,
    /// The column vector under the pointer in the canvas, for the step panel to mark.
    #[serde(skip)]
    pub hovered_column: Option<Column>,
}

/// The solves one frame needs: f64 for drawing, exact for fractions, and the trace for the panel.
pub type Solved = Shown<TriangleLecture>;

impl LectureView for TriangleView {
    type Scene = TriangleScene;
    type Solved = Solved;

    /// Loads a scene: new inputs, sliders at a starting point, camera framing the scene.
    fn load(&mut self, scene: TriangleScene) {
        let camera = self.first_camera(&scene);
        self.canvas.reset(camera);
        self.scene = scene;
        self.reading = Reading::AsWritten;
        self.beta = 0.2;
        self.gamma = 0.2;
        self.t = 0.5;
        self.animation = None;
    }

    fn scene(&self) -> &TriangleScene {
        &self.scene
    }

    /// Solves the current inputs.
    fn solve(&self, precision: Precision) -> Solved {
        Solved::new(
            (self.scene.vectors(), self.scene.t_min),
            self.reading,
            precision,
        )
    }

    /// The view: controls below, the 3D canvas above.
    fn ui(&mut self, ui: &mut Ui, solved: &Solved) {
        self.animate(ui);
        controls_below(ui, "triangle-controls", |ui, part| match part {
            Part::Controls => self.controls_ui(ui, solved),
            Part::Drawing => self.canvas_ui(ui, solved),
        });
    }

    /// The canvas alone, filling the space (presentation mode).
    fn present_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        self.animate(ui);
        self.canvas_ui(ui, solved);
    }

    /// Slides a parameter's handle to its value at the solution (presentation mode, on the step
    /// that computes it). Nothing happens when there is no solution.
    fn show_parameter(&mut self, parameter: Parameter, solved: &Solved, now: f64) {
        let Some(s) = solved.float.solution.as_ref() else {
            return;
        };
        let mut to = self
            .animation
            .as_ref()
            .map_or([self.beta, self.gamma, self.t], Slide::target);
        match parameter {
            Parameter::Beta => to[0] = s.beta,
            Parameter::Gamma => to[1] = s.gamma,
            Parameter::T => to[2] = s.t,
            Parameter::Alpha => [to[0], to[1]] = [s.beta, s.gamma],
            Parameter::S => return,
        }
        if let Some(slide) = Slide::new([self.beta, self.gamma, self.t], to, now) {
            self.animation = Some(slide);
        }
    }

    fn settle(&mut self) {
        if let Some(slide) = self.animation.take() {
            [self.beta, self.gamma, self.t] = slide.target();
        }
    }

    fn highlight(&mut self, elements: &[Element]) {
        self.highlight = elements.to_vec();
    }

    fn fingerprint(&self, bits: &mut Vec<u64>) {
        let vectors = self.scene.vectors().into_iter().flat_map(|v| v.to_array());
        bits_of(
            bits,
            vectors.chain([self.scene.t_min, self.beta, self.gamma, self.t]),
        );
    }

    fn canvas_mut(&mut self) -> Option<&mut CanvasState> {
        Some(&mut self.canvas)
    }
}

impl Default for TriangleView {
    fn default() -> TriangleView {
        first_scene(TriangleView::unloaded)
    }
}

impl TriangleView {
    /// The view of `scene` before [`TriangleView::load`] sets its sliders and camera.
    fn unloaded(scene: TriangleScene) -> TriangleView {
        TriangleView {
            scene,
            beta: 0.0,
            gamma: 0.0,
            t: 0.0,
            canvas: CanvasState::default(),
            reading: Reading::AsWritten,
            grab: None,
            animation: None,
            highlight: Vec::new(),
            hovered_column: None,
        }
    }

    fn points_of(&self, s: &TriangleScene) -> Vec<DVec3> {
        let mut points: Vec<DVec3> = [s.a, s.b, s.c, s.origin]
            .iter()
            .map(|p| DVec3::from(*p))
            .collect();
        points.push(DVec3::ZERO);
        points
    }

    /// The camera a scene opens with: framing it, across the ray and facing the triangle.
    fn first_camera(&self, s: &TriangleScene) -> OrbitCamera {
        let [a, b, c] = [s.a, s.b, s.c].map(DVec3::from);
        OrbitCamera::framing(&self.points_of(s))
            .across(DVec3::from(s.dir), Some((b - a).cross(c - a)))
    }

    fn animate(&mut self, ui: &Ui) {
        let mut values = [self.beta, self.gamma, self.t];
        slide::advance(ui, &mut self.animation, &mut values);
        [self.beta, self.gamma, self.t] = values;
    }

    fn controls_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let target = solved
            .float
            .solution
            .as_ref()
            .map(|s| [s.beta, s.gamma, s.t]);
        ui.add_space(4.0);
        ui.horizontal_wrapped(|ui| {
            let solve = ui
                .add_enabled(target.is_some(), egui::Button::new("Solve"))
                .on_hover_text(
                    "Slide β, γ and t to the solution of M X = Y, where P(β, γ) meets L + tD",
                )
                .on_disabled_hover_text(
                    "M X = Y has no unique solution (|M| = 0): nothing to slide to",
                );
            if solve.clicked()
                && let Some(to) = target
            {
                self.animation =
                    Slide::new([self.beta, self.gamma, self.t], to, ui.input(|i| i.time));
            }
            if ui
                .button("Reset view")
                .on_hover_text("Frame the triangle and the ray again")
                .clicked()
            {
                let camera = self.first_camera(&self.scene);
                self.canvas.reset(camera);
            }
        });
        let t_span = target.map_or(4.0, |[_, _, t]| 2.0 * t.abs() + 1.0);
        parameter_sliders(
            ui,
            vec![
                ParameterSlider::new(&mut self.beta, -0.5..=1.5, "β", "How far along B−A from A"),
                ParameterSlider::new(&mut self.gamma, -0.5..=1.5, "γ", "How far along C−A from A"),
                ParameterSlider::new(
                    &mut self.t,
                    -t_span..=t_span,
                    "t",
                    "How far along the ray, in steps of D",
                ),
            ],
        );
        self.status_ui(ui, solved);
        egui::CollapsingHeader::new("Inputs: A, B, C, L, D")
            .default_open(false)
            .show(ui, |ui| self.inputs_ui(ui));
    }

    fn status_ui(&self, ui: &mut Ui, solved: &Solved) {
        let explored = self.exploration();
        let exact = solved.exact.solution.as_ref();
        let float = solved.float.solution.as_ref();
        status_line(ui, |ui| {
            let texts = shown_values(&[
                ShownValue {
                    value: self.beta,
                    solution: float.map(|s| s.beta),
                    exact: exact.map(|s| &s.beta),
                },
                ShownValue {
                    value: self.gamma,
                    solution: float.map(|s| s.gamma),
                    exact: exact.map(|s| &s.gamma),
                },
                ShownValue {
                    value: self.t,
                    solution: float.map(|s| s.t),
                    exact: exact.map(|s| &s.t),
                },
            ]);
            for (symbol, text) in ["β", "γ", "t"].into_iter().zip(texts) {
                ui.label(RichText::new(format!("{symbol} = {text}")).strong());
            }
        });
        status_line(ui, |ui| {
            let degenerate = matches!(
                solved.float.outcome,
                TriangleOutcome::Miss(TriangleMiss::DegenerateTriangle)
            );
            let (text, color) = if degenerate {
                (
                    "No triangle: A, B and C lie on one line, so P(β, γ) is neither inside nor \
                     outside"
                        .to_string(),
                    palette::OUTSIDE,
                )
            } else if explored.outside.is_empty() {
                (
                    "P(β, γ) is inside the triangle".to_string(),
                    palette::INSIDE,
                )
            } else {
                let failed: Vec<String> = explored
                    .outside
                    .iter()
                    .map(|e| format!("{} (beyond edge {})", e.inequality(), e.name()))
                    .collect();
                (
                    format!("P(β, γ) is outside: fails {}", failed.join(", ")),
                    palette::OUTSIDE,
                )
            };
            ui.label(RichText::new(text).color(color.readable(ui)));
        });
        status_line(ui, |ui| {
            let gap = explored.gap;
            if self.points_meet(solved, gap) {
                ui.label(
                    RichText::new("P(β, γ) = L + tD: they meet")
                        .color(palette::SOLUTION.readable(ui))
                        .strong(),
                );
            } else {
                ui.label(format!(
                    "distance |P(β, γ) − (L + tD)| = {}",
                    format_float(gap, Precision::F64)
                ))
                .on_hover_text("Zero only at the solution (β*, γ*, t*); press Solve to get there");
            }
        });
        // The solution's t and distance: not while a class (or a practice problem) is answering.
        if super::widgets::answers_hidden(ui.ctx()) {
            return;
        }
        status_line(ui, |ui| {
            if let Some(s) = exact {
                // A distance is never negative: behind L, say so and give how far back.
                let distance = s
                    .distance_exact
                    .as_ref()
                    .and_then(|d| d.short())
                    .map(|d| d.trim_start_matches('−').to_string())
                    .unwrap_or_else(|| format_float(s.distance.abs(), Precision::F64));
                let behind = s.t.to_f64() < 0.0;
                let text = if behind {
                    format!(
                        "t* = {}: behind L, at distance |t*|·|D| = {distance} back along the ray",
                        s.t.display()
                    )
                } else {
                    format!("t* = {} (distance t*·|D| = {distance})", s.t.display())
                };
                ui.label(text)
                    .on_hover_text("t counts steps of D; the distance along the ray is |t|·|D|");
            }
        });
    }

    /// True when P(β, γ) and L + tD are the same point: the sliders sit on the solution (where in f64
    /// the two points may still differ in the last bit), or the gap is exactly zero.
    fn points_meet(&self, solved: &Solved, gap: f64) -> bool {
        let at_solution = solved
            .float
            .solution
            .as_ref()
            .is_some_and(|s| [s.beta, s.gamma, s.t] == [self.beta, self.gamma, self.t]);
        at_solution || gap == 0.0
    }

    fn problem(&self) -> triangle::RayTriangle<f64> {
        triangle::RayTriangle::from_floats(self.scene.vectors(), self.scene.t_min)
    }

    fn exploration(&self) -> triangle::Exploration<f64> {
        triangle::explore(&self.problem(), &self.beta, &self.gamma, &self.t)
    }

    fn inputs_ui(&mut self, ui: &mut Ui) {
        let mut as_typed = self.reading == Reading::AsWritten;
        ui.checkbox(&mut as_typed, "Exact arithmetic reads the numbers as typed (0.1 is 1/10)")
            .on_hover_text(
                "Off: exact arithmetic uses the exact value of each float (0.1 is 3602879701896397/2^55), \
                 as the accuracy study does when it judges float methods",
            );
        self.reading = if as_typed {
            Reading::AsWritten
        } else {
            Reading::FloatValue
        };
        let s = &mut self.scene;
        vector_editor(
            ui,
            "A",
            None,
            "Vertex A, the corner the legs start from",
            &mut s.a,
            0.05,
        );
        vector_editor(ui, "B", Some(palette::BETA), "Vertex B", &mut s.b, 0.05);
        vector_editor(ui, "C", Some(palette::GAMMA), "Vertex C", &mut s.c, 0.05);
        vector_editor(
            ui,
            "L",
            Some(palette::RAY),
            "The ray's origin L",
            &mut s.origin,
            0.05,
        );
        vector_editor(
            ui,
            "D",
            Some(palette::RAY),
            "The ray's direction D (any length)",
            &mut s.dir,
            0.05,
        );
        ui.horizontal(|ui| {
            let label = ui
                .label("t_min")
                .on_hover_text("A hit needs t > t_min (open: t = t_min is a miss)");
            ui.add(egui::DragValue::new(&mut s.t_min).speed(0.05))
                .labelled_by(label.id);
        });
    }

    /// Where a vertex (0 = A, 1 = B, 2 = C) was drawn last frame.
    pub fn vertex_on_screen(&self, index: usize) -> Option<Pos2> {
        let p = DVec3::from([self.scene.a, self.scene.b, self.scene.c][index]);
        self.canvas.screen_from_world(p)
    }

    fn canvas_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        let rect = response.rect;
        self.handle_input(ui, &response);
        let keys = handles::canvas_keys(
            ui,
            &response,
            "Triangle canvas: the arrows orbit, + and − zoom; Tab reaches its handles",
        );
        self.canvas.orbit_by_keys(keys);
        let points = self.points_to_frame(solved);
        let projector = self.canvas.projector_for(
            rect,
            || points,
            || super::widgets::verdict_height(ui, rect.width(), &solved.trace),
        );
        let canvas = Canvas {
            painter: &painter,
            projector: &projector,
        };
        self.hovered_column = response
            .hover_pos()
            .and_then(|pointer| self.column_near(&canvas, pointer));
        if self.hovered_column.is_some() {
            ui.ctx().set_cursor_icon(egui::CursorIcon::Help);
        }
        self.canvas.labels = self.draw(ui, &canvas, solved);
        self.keyboard_ui(ui, &projector, solved);
        self.canvas.projector = Some(projector);
        if self.grab.is_none() && self.hovered_vertex(&response).is_some() {
            ui.ctx().set_cursor_icon(egui::CursorIcon::Grab);
            response.on_hover_text("Drag to move this vertex in the plane facing you");
        }
    }

    /// The handles as the keyboard and a screen reader reach them, named with their values. The
    /// arrows move A, B, C, L and D's tip along the world axes nearest the screen's right and up (by
    /// 0.25, Shift 0.05, on the drag's 0.05 grid), P(β, γ) in β (← →) and γ (↑ ↓), L + tD in t (by
    /// 0.05, Shift 0.01, landing on the solution as a slide does); Enter solves.
    fn keyboard_ui(&mut self, ui: &Ui, projector: &Projector, solved: &Solved) {
        let [a, b, c, l, d] = self.scene.vectors();
        let explored = self.exploration();
        let (beta, gamma, t) = (self.beta, self.gamma, self.t);
        let plane_point = DVec3::from(explored.plane_point);
        let ray_point = DVec3::from(explored.ray_point);
        let side = if explored.outside.is_empty() {
            "inside"
        } else {
            "outside"
        };
        let text = |p: DVec3| handles::point_text(&p.to_array());
        let value = handles::value_text;
        let handles = [
            (
                TriangleHandle::Vertex(0),
                a,
                format!("vertex A at {}", text(a)),
            ),
            (
                TriangleHandle::Vertex(1),
                b,
                format!("vertex B at {}", text(b)),
            ),
            (
                TriangleHandle::Vertex(2),
                c,
                format!("vertex C at {}", text(c)),
            ),
            (
                TriangleHandle::Origin,
                l,
                format!("ray origin L at {}", text(l)),
            ),
            (
                TriangleHandle::Direction,
                l + d,
                format!(
                    "direction D = {}, its tip L + D at {}",
                    text(d),
                    text(l + d)
                ),
            ),
            (
                TriangleHandle::PlanePoint,
                plane_point,
                format!(
                    "P(β, γ) at β = {}, γ = {}: {}, {side} the triangle",
                    value(beta),
                    value(gamma),
                    text(plane_point)
                ),
            ),
            (
                TriangleHandle::RayPoint,
                ray_point,
                format!("L + tD at t = {}: {}", value(t), text(ray_point)),
            ),
        ];
        let solution = solved
            .float
            .solution
            .as_ref()
            .map(|s| [s.beta, s.gamma, s.t]);
        for (handle, world, description) in handles {
            let Some(at) = projector.screen_from_world(world) else {
                continue;
            };
            let key = format!("triangle {handle:?}");
            let keys = handles::keyboard_handle(ui, &key, at, &description);
            if keys.solve
                && let Some(to) = solution
            {
                self.animation = Slide::new([beta, gamma, t], to, ui.input(|i| i.time));
            }
            if keys.moved() {
                self.animation = None;
                self.move_by_keys(handle, &keys, projector, solution);
            }
        }
    }

    fn move_by_keys(
        &mut self,
        handle: TriangleHandle,
        keys: &handles::HandleKeys,
        projector: &Projector,
        solution: Option<[f64; 3]>,
    ) {
        let [beta_star, gamma_star, t_star] = solution.map_or([None; 3], |s| s.map(Some));
        let step = keys.step(0.05, 0.01);
        let moved = |p: [f64; 3]| {
            let step = keys.step(0.25, 0.05);
            handles::step_point(p, keys, projector.right, projector.up, step, 0.05)
        };
        let s = &mut self.scene;
        match handle {
            TriangleHandle::Vertex(0) => s.a = moved(s.a),
            TriangleHandle::Vertex(1) => s.b = moved(s.b),
            TriangleHandle::Vertex(_) => s.c = moved(s.c),
            TriangleHandle::Origin => s.origin = moved(s.origin),
            TriangleHandle::Direction => {
                let tip = moved((DVec3::from(s.origin) + DVec3::from(s.dir)).to_array());
                s.dir = (DVec3::from(tip) - DVec3::from(s.origin)).to_array();
            }
            TriangleHandle::PlanePoint => {
                self.beta = handles::step_value(self.beta, keys.right, step, keys.fine, beta_star);
                self.gamma = handles::step_value(self.gamma, keys.up, step, keys.fine, gamma_star);
            }
            TriangleHandle::RayPoint => {
                let along = keys.right + keys.up;
                self.t = handles::step_value(self.t, along, step, keys.fine, t_star);
            }
        }
    }

    /// The points the camera frames: the triangle, the ray's origin, and the solution.
    fn points_to_frame(&self, solved: &Solved) -> Vec<DVec3> {
        let mut points = self.points_of(&self.scene);
        points.pop(); // not the world origin: it may be far from the scene
        let [_, _, _, l, d] = self.scene.vectors();
        points.push(l + d);
        if let Some(s) = solved.float.solution.as_ref() {
            points.push(DVec3::from(s.point));
        }
        points
    }

    /// The vertex under the pointer, if any.
    fn hovered_vertex(&self, response: &egui::Response) -> Option<usize> {
        let pointer = response.hover_pos()?;
        (0..3).find(|&i| {
            self.vertex_on_screen(i)
                .is_some_and(|at| at.distance(pointer) < 14.0)
        })
    }

    /// The column vector of M drawn under the pointer: the edges A−B, A−C and the direction D.
    fn column_near(&self, canvas: &Canvas, pointer: Pos2) -> Option<Column> {
        let [a, b, c, l, d] = self.scene.vectors();
        [
            (b, a, Column::AMinusB),
            (c, a, Column::AMinusC),
            (l, l + d, Column::D),
        ]
        .into_iter()
        .find(|(from, to, _)| {
            canvas
                .projector
                .segment(*from, *to)
                .is_some_and(|[p, q]| distance_to_segment(pointer, p, q) < 6.0)
        })
        .map(|(_, _, column)| column)
    }

    fn handle_input(&mut self, ui: &Ui, response: &egui::Response) {
        if response.drag_started() {
            // Where the button went down, not where the drag was recognised a few points later.
            let pointer = ui
                .input(|i| i.pointer.press_origin())
                .or(response.interact_pointer_pos());
            let near = (0..3).find(|&i| {
                let at = self.vertex_on_screen(i);
                matches!((at, pointer), (Some(a), Some(p)) if a.distance(p) < 14.0)
            });
            self.grab = Some(near.map_or(Grab::Orbit, Grab::Vertex));
        }
        if response.dragged() {
            let delta = response.drag_delta();
            if self.grab == Some(Grab::Orbit) {
                self.canvas.auto_frame = false;
            }
            match self.grab {
                Some(Grab::Vertex(i)) => {
                    let vertex = [&mut self.scene.a, &mut self.scene.b, &mut self.scene.c]
                        .into_iter()
                        .nth(i);
                    if let (Some(projector), Some(vertex)) = (&self.canvas.projector, vertex) {
                        let moved = DVec3::from(*vertex)
                            + projector.drag_in_view_plane(DVec3::from(*vertex), delta);
                        *vertex = moved.to_array();
                    }
                }
                Some(Grab::Orbit) | None => self.canvas.camera.orbit(delta),
            }
        }
        if response.drag_stopped() {
            if let Some(Grab::Vertex(i)) = self.grab
                && let Some(vertex) = [&mut self.scene.a, &mut self.scene.b, &mut self.scene.c]
                    .into_iter()
                    .nth(i)
            {
                *vertex = vertex.map(|x| snap(x, 0.05));
            }
            self.grab = None;
        }
        self.canvas.zoom_on_scroll(ui, response);
    }

    /// Draws the scene, then places every label clear of the others, the handles and the verdict.
    fn draw(
        &self,
        ui: &Ui,
        canvas: &Canvas,
        solved: &Solved,
    ) -> Vec<super::widgets::labels::PlacedLabel> {
        let text = ui.visuals().text_color();
        let mut labels = LabelLayer::new(canvas.projector.rect);
        handles::labels_avoid_focus_ring(ui.ctx(), &mut labels);
        // The handles: A, B, C, L, D's tip, P(β, γ) and L + tD (those two as the core puts them).
        let [a, b, c, l, d] = self.scene.vectors();
        let explored = self.exploration();
        let handles: Vec<egui::Pos2> = [
            a,
            b,
            c,
            l,
            l + d,
            DVec3::from(explored.plane_point),
            DVec3::from(explored.ray_point),
        ]
        .into_iter()
        .filter_map(|p| canvas.projector.screen_from_world(p))
        .collect();
        let verdict = super::widgets::verdict_overlay(
            ui,
            canvas.painter,
            canvas.projector.rect,
            &solved.trace,
            &handles,
        );
        if let Some(verdict) = &verdict {
            labels.avoid(verdict.rect);
        }
        canvas.axes_labelled(&[a, b, c, l], &mut labels);

        // A practice problem's outcome is for the student to name: a degenerate triangle is then
        // drawn as any other (its three points on one line), not marked as failed.
        let hidden = super::widgets::answers_hidden(canvas.painter.ctx());
        let degenerate = matches!(
            solved.float.outcome,
            TriangleOutcome::Miss(TriangleMiss::DegenerateTriangle)
        );
        if degenerate && hidden {
            canvas.polygon(&[a, b, c], faded(palette::BETA, 40), Stroke::new(2.0, text));
        } else if !degenerate {
            // The parametric form covers the whole plane: a faint grid of constant β and γ.
            let problem = self.problem();
            let plane =
                |beta: f64, gamma: f64| DVec3::from(triangle::point_at(&problem, &beta, &gamma));
            let grid = Stroke::new(1.0, faded(text, 28));
            for k in -2..=4 {
                let u = k as f64 * 0.5;
                canvas.line(plane(u, -1.0), plane(u, 2.0), grid);
                canvas.line(plane(-1.0, u), plane(2.0, u), grid);
            }
            canvas.polygon(&[a, b, c], faded(palette::BETA, 40), Stroke::new(2.0, text));
        } else {
            canvas.line(a, b, Stroke::new(3.0, palette::OUTSIDE));
            canvas.line(b, c, Stroke::new(3.0, palette::OUTSIDE));
            canvas.place_label(
                &mut labels,
                (a + c) / 2.0,
                "degenerate: A, B, C on one line",
                palette::OUTSIDE,
                Priority::Normal,
            );
        }
        self.draw_highlights(canvas, solved, &mut labels);
        for (p, name) in [(a, "A"), (b, "B"), (c, "C")] {
            canvas.dot(p, 6.0, text);
            canvas.place_label(&mut labels, p, name, text, Priority::Key);
            if let Some(at) = canvas.screen(p) {
                labels.avoid_point(at, 7.0);
            }
        }
        for (from, to) in [(a, b), (b, c), (c, a)] {
            guide(canvas, &mut labels, from, to);
        }

        // The two legs from A: β(B−A), then γ(C−A).
        let explored = self.exploration();
        let after_beta = DVec3::from(explored.beta_end);
        let point = DVec3::from(explored.plane_point);
        canvas.arrow(a, after_beta, Stroke::new(3.0, palette::BETA));
        canvas.arrow(after_beta, point, Stroke::new(3.0, palette::GAMMA));
        guide(canvas, &mut labels, a, after_beta);
        guide(canvas, &mut labels, after_beta, point);
        let inside = explored.outside.is_empty();
        let p_color = if degenerate {
            text
        } else if inside {
            palette::INSIDE
        } else {
            palette::OUTSIDE
        };
        self.draw_ray(canvas, solved, [l, d], &mut labels);
        let on_ray = DVec3::from(explored.ray_point);
        for (p, radius, color, inside) in [
            (on_ray, 6.0, palette::RAY, true),
            (point, 7.0, p_color, inside || degenerate),
        ] {
            if let Some(at) = canvas.inside_mark(p, radius, color, inside) {
                labels.avoid_point(at, radius + 1.0);
            }
        }
        // Where the two points coincide (at the solution), one label names both.
        let together = self.points_meet(solved, explored.gap);
        if together {
            canvas.place_label(
                &mut labels,
                point,
                "P(β, γ) = L + tD",
                p_color,
                Priority::Key,
            );
        } else {
            canvas.dashed(point, on_ray, Stroke::new(1.0, faded(text, 140)));
            canvas.place_label(&mut labels, point, "P(β, γ)", p_color, Priority::Key);
            canvas.place_label(&mut labels, on_ray, "L + tD", palette::RAY, Priority::Key);
        }
        // The keyboard's handles at L and D's tip: no label covers them either.
        for p in [l, l + d] {
            if let Some(at) = canvas.screen(p) {
                labels.avoid_point(at, 6.0);
            }
        }
        self.draw_solution(canvas, solved, [a, b, c, l], &mut labels);
        self.draw_class_cloud(canvas, [a, b, c]);
        if let Some(verdict) = verdict {
            verdict.paint(canvas.painter);
        }
        labels.paint(ui, canvas.painter, ui.scope_id().with("triangle-labels"))
    }

    /// A live class's predictions of P(β, γ), one point each, on this scene's triangle.
    fn draw_class_cloud(&self, canvas: &Canvas, [a, b, c]: [DVec3; 3]) {
        let problem = crate::scene::Problem::Triangle(self.scene.clone());
        super::class_view::draw_cloud(canvas.painter, &problem, |values| match values {
            [Some(beta), Some(gamma)] => canvas
                .projector
                .screen_from_world(a + beta * (b - a) + gamma * (c - a))
                .into_iter()
                .collect(),
            _ => Vec::new(),
        });
    }

    /// Emphasises what the step on screen is about: a wide glow under each highlighted vector,
    /// edge or point, with the vector's name.
    fn draw_highlights(&self, canvas: &Canvas, solved: &Solved, labels: &mut LabelLayer) {
        let [a, b, c, l, d] = self.scene.vectors();
        let glow = |color: egui::Color32| Stroke::new(11.0, faded(color, 90));
        // A vector from one point to another, glowing, with its name at its middle.
        let glowing_arrow = |labels: &mut LabelLayer, (from, to), name: &str, color| {
            canvas.line(from, to, glow(color));
            canvas.arrow(from, to, Stroke::new(3.0, color));
            canvas.place_label(labels, (from + to) / 2.0, name, color, Priority::Normal);
        };
        let mut emphasised = self.highlight.clone();
        if let Some(column) = self.hovered_column {
            emphasised.push(Element::Column(column));
        }
        for element in emphasised {
            match element {
                Element::Column(Column::AMinusB) => {
                    glowing_arrow(labels, (b, a), "A−B", palette::BETA);
                }
                Element::Column(Column::AMinusC) => {
                    glowing_arrow(labels, (c, a), "A−C", palette::GAMMA);
                }
                Element::Column(Column::D) => canvas.line(l, l + d, glow(palette::RAY)),
                Element::Rhs => glowing_arrow(labels, (l, a), "Y = A − L", palette::RHS),
                Element::Side(side) => {
                    let (from, to) = match side {
                        Side::Ca => (c, a),
                        Side::Ab => (a, b),
                        _ => (b, c),
                    };
                    canvas.line(from, to, glow(palette::SOLUTION));
                }
                Element::Origin => {
                    canvas.ring(l, 13.0, Stroke::new(4.0, faded(palette::SOLUTION, 200)));
                }
                Element::Hit => {
                    if let Some(s) = solved.float.solution.as_ref() {
                        canvas.ring(DVec3::from(s.point), 17.0, glow(palette::SOLUTION));
                    }
                }
                Element::Parameter(Parameter::Beta) => {
                    let explored = self.exploration();
                    canvas.line(a, DVec3::from(explored.beta_end), glow(palette::BETA));
                }
                Element::Parameter(Parameter::Gamma) => {
                    let explored = self.exploration();
                    let (from, to) = (explored.beta_end, explored.plane_point);
                    canvas.line(DVec3::from(from), DVec3::from(to), glow(palette::GAMMA));
                }
                Element::Parameter(Parameter::T) => {
                    let explored = self.exploration();
                    canvas.line(l, DVec3::from(explored.ray_point), glow(palette::RAY));
                }
                Element::Parameter(_) | Element::Column(_) => {}
            }
        }
    }

    fn draw_ray(
        &self,
        canvas: &Canvas,
        solved: &Solved,
        [l, d]: [DVec3; 2],
        labels: &mut LabelLayer,
    ) {
        // With no solution (parallel), draw the ray a few steps of D long.
        let t_star = solved.float.solution.as_ref().map_or(3.0, |s| s.t);
        let far = t_star.max(self.t).max(1.0) * 1.4;
        let back = t_star.min(self.t).min(-1.0) * 1.4;
        canvas.line(l, l + far * d, Stroke::new(2.5, palette::RAY));
        // Behind the origin (t < 0) the ray is dashed.
        canvas.dashed(l + back * d, l, Stroke::new(1.5, faded(palette::RAY, 170)));
        guide(canvas, labels, l + back * d, l + far * d);
        if let Some(at) = canvas.dot(l, 6.0, palette::RAY) {
            labels.avoid_point(at, 7.0);
        }
        canvas.place_label(labels, l, "L", palette::RAY, Priority::Key);
        canvas.arrow(l, l + d, Stroke::new(3.0, palette::RAY));
        canvas.place_label(labels, l + d, "D", palette::RAY, Priority::Normal);
    }

    fn draw_solution(
        &self,
        canvas: &Canvas,
        solved: &Solved,
        [a, b, c, l]: [DVec3; 4],
        labels: &mut LabelLayer,
    ) {
        // A practice problem's outcome is for the student to predict.
        if super::widgets::answers_hidden(canvas.painter.ctx()) {
            return;
        }
        let outcome = &solved.float.outcome;
        let Some(s) = solved.float.solution.as_ref() else {
            if matches!(
                outcome,
                TriangleOutcome::Miss(TriangleMiss::Parallel { .. })
            ) {
                canvas.place_label(
                    labels,
                    l,
                    "ray ∥ plane: |M| = 0",
                    palette::OUTSIDE,
                    Priority::Normal,
                );
            }
            return;
        };
        let hit = DVec3::from(s.point);
        let (ring, label, color) = match outcome {
            TriangleOutcome::Hit => (
                Stroke::new(3.0, palette::SOLUTION),
                "hit".to_string(),
                palette::SOLUTION,
            ),
            TriangleOutcome::Miss(TriangleMiss::Behind) => (
                Stroke::new(2.0, faded(palette::OUTSIDE, 200)),
                "ghost hit behind L (t ≤ t_min)".to_string(),
                palette::OUTSIDE,
            ),
            TriangleOutcome::Miss(TriangleMiss::Outside { edges }) => {
                for edge in edges {
                    let (from, to) = match edge {
                        Edge::Ca => (c, a),
                        Edge::Ab => (a, b),
                        Edge::Bc => (b, c),
                    };
                    canvas.line(from, to, Stroke::new(4.0, palette::OUTSIDE));
                    failed_edge_ticks(canvas, from, to);
                }
                let names: Vec<&str> = edges.iter().map(|e| e.name()).collect();
                (
                    Stroke::new(2.0, palette::OUTSIDE),
                    format!("misses: beyond {}", names.join(", ")),
                    palette::OUTSIDE,
                )
            }
            _ => return,
        };
        if let Some(at) = canvas.ring(hit, 11.0, ring) {
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
}

/// A drawn line that labels would rather not cross.
/// Short ticks across a failed edge, every 12 points: the edge reads as a barrier by its shape too,
/// not by its red alone (under deuteranopia the red edge and the green ray look alike).
fn failed_edge_ticks(canvas: &Canvas, from: DVec3, to: DVec3) {
    let Some([p, q]) = canvas.projector.segment(from, to) else {
        return;
    };
    let along = q - p;
    let length = along.length();
    if !(length.is_finite() && length > 1.0) {
        return;
    }
    let across = egui::vec2(-along.y, along.x) / length * 6.0;
    let stroke = Stroke::new(2.5, palette::OUTSIDE);
    let ticks = (length / 12.0).floor().min(400.0) as usize;
    for k in 1..ticks {
        let at = p + along * (k as f32 / ticks as f32);
        canvas
            .painter
            .line_segment([at - across, at + across], stroke);
    }
}

fn guide(canvas: &Canvas, labels: &mut LabelLayer, from: DVec3, to: DVec3) {
    if let Some([p, q]) = canvas.projector.segment(from, to) {
        labels.prefer_clear_of(p, q);
    }
}

/// Distance from a point to a screen segment.
fn distance_to_segment(p: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let k = ((p - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
    p.distance(a + ab * k)
}
