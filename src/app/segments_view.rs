//! The Segments view (seed 000): two 2D segments with draggable endpoints, and draggable handles for t on
//! segment A and s on segment B that slide along their lines — beyond [0, 1] onto the faded lines too.
//!
//! A handle dropped within a few pixels of the crossing snaps onto it exactly (hold Shift to move
//! freely), so a drag can land on t = 17/22; "Go to intersection" slides both handles there.

use super::widgets::palette::Readable as _;
use super::widgets::slide::{self, Slide};
use super::widgets::{Part, ShownValue, controls_below, handles, shown_values};
use egui::{FontId, Pos2, Rect, RichText, Sense, Shape, Stroke, Ui, pos2, vec2};
use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::highlight::{Column, Element, Parameter, Side};
use super::view::{LectureView, bits_of, first_scene};
use super::widgets::labels::{LabelLayer, PlacedLabel, Priority};
use super::widgets::palette::{self, faded};
use super::widgets::{ParameterSlider, parameter_sliders, snap, status_line, vector_editor};
use crate::geometry::segments::{self, SegmentsOutcome};
use crate::geometry::{Precision, Reading, SegmentsLecture, Shown};
use crate::scene::SegmentsScene;
use crate::trace::format_float;

/// Something a drag can move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handle {
    /// An endpoint: 0 = A1, 1 = A2, 2 = B1, 3 = B2.
    Endpoint(usize),
    /// The t handle on segment A.
    T,
    /// The s handle on segment B.
    S,
    /// The background: pans the view.
    Pan,
}

/// How close (in points) a dragged handle must come to the crossing to snap onto it.
pub const SNAP_POINTS: f32 = 10.0;

/// World to screen for the 2D plot: a uniform scale, y up.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame2d {
    /// The plot area.
    pub rect: Rect,
    /// The world point at the centre of the plot.
    pub center: DVec2,
    /// Screen points per world unit.
    pub scale: f64,
    /// Where `center` is drawn: the middle of the plot below the verdict box.
    pub middle: Pos2,
}

impl Frame2d {
    /// World to screen.
    pub fn screen_from_world(&self, p: DVec2) -> Pos2 {
        let offset = (p - self.center) * self.scale;
        self.middle + vec2(offset.x as f32, -offset.y as f32)
    }

    /// Screen to world.
    pub fn world_from_screen(&self, p: Pos2) -> DVec2 {
        let offset = p - self.middle;
        self.center + DVec2::new(offset.x as f64, -offset.y as f64) / self.scale
    }
}

/// Everything the Segments view remembers.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct SegmentsView {
    /// The inputs.
    pub scene: SegmentsScene,
    /// The t handle (on A).
    pub t: f64,
    /// The s handle (on B).
    pub s: f64,
    /// Draw the lines beyond [0, 1], faded.
    pub show_lines: bool,
    /// Draw k evenly spaced samples along each segment (seed 000's k = 32).
    pub show_samples: bool,
    /// How many samples.
    pub samples: usize,
    /// The world point at the centre of the plot.
    pub center: [f64; 2],
    /// The half-height of the plot, in world units.
    pub half_extent: f64,
    #[serde(skip)]
    grab: Option<Handle>,
    /// The last frame's world-to-screen mapping (tests use it to find handles).
    #[serde(skip)]
    pub frame: Option<Frame2d>,
    #[serde(skip)]
    animation: Option<Slide<2>>,
    /// What the step on screen is about: drawn emphasised.
    #[serde(skip)]
    pub highlight: Vec<Element>,
    /// Where each label went last frame (tests read it).
    #[serde(skip)]
    pub labels: Vec<PlacedLabel>,
}

/// The solves one frame needs: f64 for drawing, exact for fractions, and the trace for the panel.
pub type Solved = Shown<SegmentsLecture>;

impl LectureView for SegmentsView {
    type Scene = SegmentsScene;
    type Solved = Solved;

    /// Loads a scene: new segments, handles at the start, view fitted.
    fn load(&mut self, scene: SegmentsScene) {
        self.scene = scene;
        self.t = 0.25;
        self.s = 0.25;
        self.animation = None;
        self.fit();
    }

    fn scene(&self) -> &SegmentsScene {
        &self.scene
    }

    /// Solves the current inputs.
    fn solve(&self, precision: Precision) -> Solved {
        let points = self.scene.points();
        Solved::new(points, Reading::AsWritten, precision)
    }

    /// The view: controls below, the plot above.
    fn ui(&mut self, ui: &mut Ui, solved: &Solved) {
        self.animate(ui);
        controls_below(ui, "segments-controls", |ui, part| match part {
            Part::Controls => self.controls_ui(ui, solved),
            Part::Drawing => self.plot_ui(ui, solved),
        });
    }

    /// The plot alone, filling the space (presentation mode).
    fn present_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        self.animate(ui);
        self.plot_ui(ui, solved);
    }

    /// Slides t or s to its value at the crossing (presentation mode).
    fn show_parameter(&mut self, parameter: Parameter, solved: &Solved, now: f64) {
        let mut to = self
            .animation
            .as_ref()
            .map_or([self.t, self.s], Slide::target);
        match (parameter, solved.float.t, solved.float.s) {
            (Parameter::T, Some(t), _) => to[0] = t,
            (Parameter::S, _, Some(s)) => to[1] = s,
            _ => return,
        }
        self.animation = Slide::new([self.t, self.s], to, now);
    }

    fn settle(&mut self) {
        if let Some(slide) = self.animation.take() {
            [self.t, self.s] = slide.target();
        }
    }

    fn highlight(&mut self, elements: &[Element]) {
        self.highlight = elements.to_vec();
    }

    fn fingerprint(&self, bits: &mut Vec<u64>) {
        let points = self.scene.points().into_iter().flat_map(|p| p.to_array());
        bits_of(bits, points.chain([self.t, self.s]));
        bits.push(u64::from(self.show_lines));
    }
}

impl Default for SegmentsView {
    fn default() -> SegmentsView {
        first_scene(SegmentsView::unloaded)
    }
}

impl SegmentsView {
    /// The view of `scene` before [`SegmentsView::load`] places its handles and fits the plot.
    fn unloaded(scene: SegmentsScene) -> SegmentsView {
        SegmentsView {
            scene,
            t: 0.0,
            s: 0.0,
            show_lines: true,
            show_samples: false,
            samples: 32,
            center: [0.0, 0.0],
            half_extent: 4.0,
            grab: None,
            frame: None,
            animation: None,
            highlight: Vec::new(),
            labels: Vec::new(),
        }
    }

    /// Fits the plot around both segments (and the origin).
    pub fn fit(&mut self) {
        let points = self.scene.points();
        let (mut min, mut max) = (DVec2::ZERO, DVec2::ZERO);
        for p in points.iter().filter(|p| p.is_finite()) {
            min = min.min(*p);
            max = max.max(*p);
        }
        self.center = ((min + max) / 2.0).to_array();
        self.half_extent = ((max - min).max_element() / 2.0 + 1.0).max(1.0);
    }

    fn animate(&mut self, ui: &Ui) {
        let mut values = [self.t, self.s];
        slide::advance(ui, &mut self.animation, &mut values);
        [self.t, self.s] = values;
    }

    fn controls_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let target = solved.float.t.zip(solved.float.s);
        ui.add_space(4.0);
        ui.horizontal_wrapped(|ui| {
            let go = ui
                .add_enabled(target.is_some(), egui::Button::new("Go to intersection"))
                .on_hover_text("Slide both handles to where the lines cross")
                .on_disabled_hover_text(
                    "The lines are parallel (|M| = 0): they have no single crossing",
                );
            if go.clicked()
                && let Some((t, s)) = target
            {
                self.animation = Slide::new([self.t, self.s], [t, s], ui.input(|i| i.time));
            }
            ui.checkbox(&mut self.show_lines, "Whole lines")
                .on_hover_text("Draw the lines beyond [0, 1], faded: lines know no bounds");
            ui.checkbox(&mut self.show_samples, "Samples")
                .on_hover_text(
                    "k evenly spaced points along each segment, as seed 000 samples them",
                );
            if self.show_samples {
                ui.add(
                    egui::DragValue::new(&mut self.samples)
                        .range(2..=64)
                        .prefix("k = "),
                )
                .on_hover_text("How many samples along each segment");
            }
            if ui
                .button("Fit")
                .on_hover_text("Fit the plot around both segments")
                .clicked()
            {
                self.fit();
            }
        });
        parameter_sliders(
            ui,
            vec![
                ParameterSlider::new(
                    &mut self.t,
                    -1.0..=2.0,
                    "t",
                    "A(t) = A1 + t(A2−A1): 0 at A1, 1 at A2",
                ),
                ParameterSlider::new(
                    &mut self.s,
                    -1.0..=2.0,
                    "s",
                    "B(s) = B1 + s(B2−B1): 0 at B1, 1 at B2",
                ),
            ],
        );
        self.status_ui(ui, solved);
        egui::CollapsingHeader::new("Inputs: A1, A2, B1, B2")
            .default_open(false)
            .show(ui, |ui| {
                let s = &mut self.scene;
                vector_editor(
                    ui,
                    "A1",
                    Some(palette::SEGMENT_A),
                    "Start of segment A",
                    &mut s.a1,
                    0.05,
                );
                vector_editor(
                    ui,
                    "A2",
                    Some(palette::SEGMENT_A),
                    "End of segment A",
                    &mut s.a2,
                    0.05,
                );
                vector_editor(
                    ui,
                    "B1",
                    Some(palette::SEGMENT_B),
                    "Start of segment B",
                    &mut s.b1,
                    0.05,
                );
                vector_editor(
                    ui,
                    "B2",
                    Some(palette::SEGMENT_B),
                    "End of segment B",
                    &mut s.b2,
                    0.05,
                );
            });
    }

    fn exploration(&self) -> segments::Exploration<f64> {
        let pair = segments::SegmentPair::from_floats(self.scene.points());
        segments::explore(&pair, &self.t, &self.s)
    }

    fn status_ui(&self, ui: &mut Ui, solved: &Solved) {
        let explored = self.exploration();
        status_line(ui, |ui| {
            let [t_text, s_text]: [String; 2] = shown_values(&[
                ShownValue {
                    value: self.t,
                    solution: solved.float.t,
                    exact: solved.exact.t.as_ref(),
                },
                ShownValue {
                    value: self.s,
                    solution: solved.float.s,
                    exact: solved.exact.s.as_ref(),
                },
            ]);
            ui.label(
                RichText::new(format!("t = {t_text}"))
                    .strong()
                    .color(palette::SEGMENT_A.readable(ui)),
            );
            ui.label(
                RichText::new(format!("s = {s_text}"))
                    .strong()
                    .color(palette::SEGMENT_B.readable(ui)),
            );
            let point = |p: [f64; 2]| {
                format!(
                    "({}, {})",
                    format_float(p[0], Precision::F64),
                    format_float(p[1], Precision::F64)
                )
            };
            ui.label(format!("A(t) = {}", point(explored.a_at_t)));
            ui.label(format!("B(s) = {}", point(explored.b_at_s)));
        });
        // A line of its own, so the plot above does not jump when the text changes length.
        status_line(ui, |ui| {
            // At the solution the handles meet exactly (in f64 the two points may differ in the last bit).
            let at_solution = solved.float.t == Some(self.t) && solved.float.s == Some(self.s);
            if at_solution || explored.gap == 0.0 {
                ui.label(
                    RichText::new("A(t) = B(s): the handles meet")
                        .strong()
                        .color(palette::SOLUTION.readable(ui)),
                );
            } else {
                ui.label(format!(
                    "distance |A(t) − B(s)| = {}",
                    format_float(explored.gap, Precision::F64)
                ))
                .on_hover_text(
                    "Drag the t and s handles together: the distance is zero only at the crossing",
                );
            }
        });
    }

    /// Where a handle was drawn last frame.
    pub fn handle_on_screen(&self, handle: Handle) -> Option<Pos2> {
        let frame = self.frame.as_ref()?;
        let explored = self.exploration();
        let world = match handle {
            Handle::Endpoint(i) => self.scene.points()[i],
            Handle::T => DVec2::from(explored.a_at_t),
            Handle::S => DVec2::from(explored.b_at_s),
            Handle::Pan => return None,
        };
        Some(frame.screen_from_world(world))
    }

    /// Where the lines cross, on screen (last frame).
    pub fn crossing_on_screen(&self, solved: &Solved) -> Option<Pos2> {
        let point = solved.float.point?;
        Some(self.frame.as_ref()?.screen_from_world(DVec2::from(point)))
    }

    fn plot_ui(&mut self, ui: &mut Ui, solved: &Solved) {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        let rect = response.rect;
        // The plot fits below the verdict box, so the box covers no handle.
        let verdict = if super::widgets::answers_hidden(ui.ctx()) {
            0.0
        } else {
            super::widgets::verdict_height(ui, rect.width(), &solved.trace).min(rect.height() / 2.0)
        };
        let plot = Rect::from_min_max(rect.min + vec2(0.0, verdict), rect.max);
        let frame = Frame2d {
            rect,
            center: DVec2::from(self.center),
            scale: plot.height().min(plot.width()).max(10.0) as f64 / (2.0 * self.half_extent),
            middle: plot.center(),
        };
        self.frame = Some(frame.clone());
        self.handle_input(ui, &response, &frame, solved);
        let keys = handles::canvas_keys(
            ui,
            &response,
            "Segments plot: the arrows pan, + and − zoom; Tab reaches its handles",
        );
        self.center[0] += keys.right as f64 * 0.1 * self.half_extent;
        self.center[1] += keys.up as f64 * 0.1 * self.half_extent;
        self.half_extent = (self.half_extent * (-keys.zoom as f64 * 0.12).exp()).clamp(0.05, 1e6);
        self.labels = self.draw(ui, &painter, &frame, solved);
        self.keyboard_ui(ui, solved);
        if self.grab.is_none()
            && let Some(pointer) = response.hover_pos()
            && self.handle_near(pointer).is_some()
        {
            ui.ctx().set_cursor_icon(egui::CursorIcon::Grab);
            response.on_hover_text(
                "Drag this handle (endpoints snap to a 0.25 grid; hold Shift to move freely)",
            );
        }
    }

    /// The handles as the keyboard and a screen reader reach them: named with their values, moved
    /// by the arrows (endpoints on the drag's 0.25 grid, Shift for 0.01; t and s by 0.05, landing
    /// on the crossing as a drag does, Shift for 0.01), Enter goes to the intersection.
    fn keyboard_ui(&mut self, ui: &Ui, solved: &Solved) {
        let explored = self.exploration();
        let [a_t, b_s] = [explored.a_at_t, explored.b_at_s].map(|p| handles::point_text(&p));
        let names = ["A1", "A2", "B1", "B2"];
        let mut handles: Vec<(Handle, String, String)> = (0..4)
            .map(|i| {
                let at = handles::point_text(&self.scene.points()[i].to_array());
                (
                    Handle::Endpoint(i),
                    names[i].to_string(),
                    format!("endpoint {} at {at}", names[i]),
                )
            })
            .collect();
        handles.push((
            Handle::T,
            "A(t)".into(),
            format!(
                "A(t) at t = {}, {a_t}",
                format_float(self.t, Precision::F64)
            ),
        ));
        handles.push((
            Handle::S,
            "B(s)".into(),
            format!(
                "B(s) at s = {}, {b_s}",
                format_float(self.s, Precision::F64)
            ),
        ));
        for (handle, key, description) in handles {
            let Some(at) = self.handle_on_screen(handle) else {
                continue;
            };
            let keys = handles::keyboard_handle(ui, &format!("segments {key}"), at, &description);
            if keys.solve
                && let Some((t, s)) = solved.float.t.zip(solved.float.s)
            {
                self.animation = Slide::new([self.t, self.s], [t, s], ui.input(|i| i.time));
            }
            if keys.moved() {
                self.animation = None;
                self.move_by_keys(handle, &keys, solved);
            }
        }
    }

    fn move_by_keys(&mut self, handle: Handle, keys: &handles::HandleKeys, solved: &Solved) {
        let along = keys.right + keys.up;
        match handle {
            Handle::T => {
                let step = keys.step(0.05, 0.01);
                self.t = handles::step_value(self.t, along, step, keys.fine, solved.float.t);
            }
            Handle::S => {
                let step = keys.step(0.05, 0.01);
                self.s = handles::step_value(self.s, along, step, keys.fine, solved.float.s);
            }
            Handle::Endpoint(i) => {
                let step = keys.step(0.25, 0.01);
                let point = [
                    &mut self.scene.a1,
                    &mut self.scene.a2,
                    &mut self.scene.b1,
                    &mut self.scene.b2,
                ]
                .into_iter()
                .nth(i);
                if let Some(point) = point {
                    point[0] = snap(point[0] + keys.right * step, step);
                    point[1] = snap(point[1] + keys.up * step, step);
                }
            }
            Handle::Pan => {}
        }
    }

    /// The handle under a screen point, if any (t and s first: they sit on top).
    fn handle_near(&self, pointer: Pos2) -> Option<Handle> {
        [
            Handle::T,
            Handle::S,
            Handle::Endpoint(0),
            Handle::Endpoint(1),
            Handle::Endpoint(2),
            Handle::Endpoint(3),
        ]
        .into_iter()
        .find(|h| {
            self.handle_on_screen(*h)
                .is_some_and(|at| at.distance(pointer) < 14.0)
        })
    }

    fn handle_input(
        &mut self,
        ui: &Ui,
        response: &egui::Response,
        frame: &Frame2d,
        solved: &Solved,
    ) {
        let pointer = response.interact_pointer_pos();
        if response.drag_started() {
            // Where the button went down, not where the drag was recognised a few points later.
            let pressed = ui.input(|i| i.pointer.press_origin()).or(pointer);
            let near = pressed.and_then(|p| self.handle_near(p));
            self.grab = Some(near.unwrap_or(Handle::Pan));
            self.animation = None;
        }
        if response.dragged()
            && let Some(pointer) = pointer
        {
            let world = frame.world_from_screen(pointer);
            let free = ui.input(|i| i.modifiers.shift);
            let crossing = self
                .crossing_on_screen(solved)
                .filter(|c| !free && c.distance(pointer) < SNAP_POINTS);
            let [a1, a2, b1, b2] = self.scene.points().map(|p| p.to_array());
            match self.grab {
                Some(Handle::T) => {
                    self.t = match (crossing, solved.float.t) {
                        (Some(_), Some(t)) => t,
                        _ => segments::nearest_parameter(&a1, &a2, &world.to_array()),
                    };
                }
                Some(Handle::S) => {
                    self.s = match (crossing, solved.float.s) {
                        (Some(_), Some(s)) => s,
                        _ => segments::nearest_parameter(&b1, &b2, &world.to_array()),
                    };
                }
                Some(Handle::Endpoint(i)) => {
                    let target = [
                        &mut self.scene.a1,
                        &mut self.scene.a2,
                        &mut self.scene.b1,
                        &mut self.scene.b2,
                    ];
                    let snapped = if free {
                        world.to_array()
                    } else {
                        world.to_array().map(|x| snap(x, 0.25))
                    };
                    if let Some(point) = target.into_iter().nth(i) {
                        *point = snapped;
                    }
                }
                Some(Handle::Pan) | None => {
                    let delta = response.drag_delta();
                    self.center[0] -= delta.x as f64 / frame.scale;
                    self.center[1] += delta.y as f64 / frame.scale;
                }
            }
        }
        if response.drag_stopped() {
            self.grab = None;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.half_extent =
                    (self.half_extent * (-scroll as f64 * 0.002).exp()).clamp(0.05, 1e6);
            }
        }
    }

    /// Draws the plot, then places every label clear of the others, the handles and the verdict.
    fn draw(
        &self,
        ui: &Ui,
        painter: &egui::Painter,
        frame: &Frame2d,
        solved: &Solved,
    ) -> Vec<PlacedLabel> {
        let text = ui.visuals().text_color();
        let mut labels = LabelLayer::new(frame.rect);
        handles::labels_avoid_focus_ring(ui.ctx(), &mut labels);
        // The handles: the four ends, A(t) and B(s) (as the core puts them).
        let explored = self.exploration();
        let [a1, a2, b1, b2] = self.scene.points();
        let handles = [
            a1,
            a2,
            b1,
            b2,
            DVec2::from(explored.a_at_t),
            DVec2::from(explored.b_at_s),
        ]
        .map(|p| frame.screen_from_world(p));
        let verdict =
            super::widgets::verdict_overlay(ui, painter, frame.rect, &solved.trace, &handles);
        if let Some(verdict) = &verdict {
            labels.avoid(verdict.rect);
        }
        draw_grid(ui, painter, frame, &mut labels);
        self.draw_highlights(painter, frame, solved);
        let [a1, a2, b1, b2] = self.scene.points();
        let to_screen = |p: DVec2| frame.screen_from_world(p);
        let far = 1e3 * self.half_extent.max(1.0);
        for (p1, p2, color, name) in [
            (a1, a2, palette::SEGMENT_A, "A"),
            (b1, b2, palette::SEGMENT_B, "B"),
        ] {
            let direction = p2 - p1;
            if self.show_lines && direction.length() > 0.0 {
                let unit = direction / direction.length();
                line(
                    painter,
                    frame,
                    [to_screen(p1 - unit * far), to_screen(p2 + unit * far)],
                    Stroke::new(1.5, faded(color, 70)),
                );
            }
            line(
                painter,
                frame,
                [to_screen(p1), to_screen(p2)],
                Stroke::new(4.0, color),
            );
            labels.prefer_clear_of(to_screen(p1), to_screen(p2));
            if self.show_samples {
                for i in 0..self.samples {
                    let u = i as f64 / (self.samples.max(2) - 1) as f64;
                    let sample = segments::point_on(&p1.to_array(), &p2.to_array(), &u);
                    painter.circle_filled(to_screen(DVec2::from(sample)), 3.0, color);
                }
            }
            for (p, suffix) in [(p1, "1"), (p2, "2")] {
                painter.circle_filled(to_screen(p), 7.0, color);
                labels.avoid_point(to_screen(p), 8.0);
                labels.add(
                    to_screen(p),
                    format!("{name}{suffix}"),
                    color,
                    FontId::proportional(18.0),
                    Priority::Key,
                    8.0,
                );
            }
        }
        self.draw_solution(painter, frame, solved, &mut labels);
        let explored = self.exploration();
        let at_t = to_screen(DVec2::from(explored.a_at_t));
        let at_s = to_screen(DVec2::from(explored.b_at_s));
        if explored.gap > 0.0 {
            dashed(
                painter,
                frame,
                [at_t, at_s],
                Stroke::new(1.0, faded(text, 150)),
            );
        }
        for (at, color, label) in [
            (at_t, palette::SEGMENT_A, "A(t)"),
            (at_s, palette::SEGMENT_B, "B(s)"),
        ] {
            painter.circle(
                at,
                9.0,
                ui.visuals().extreme_bg_color,
                Stroke::new(3.0, color),
            );
            labels.avoid_point(at, 10.0);
            labels.add(
                at,
                label,
                color,
                FontId::proportional(17.0),
                Priority::Key,
                10.0,
            );
        }
        self.draw_class_cloud(painter, frame);
        if let Some(verdict) = verdict {
            verdict.paint(painter);
        }
        labels.paint(ui, painter, ui.scope_id().with("segments-labels"))
    }

    /// Emphasises what the step on screen is about: a wide glow under each highlighted element.
    /// A live class's predictions: each student's A(t) on segment A and B(s) on segment B.
    fn draw_class_cloud(&self, painter: &egui::Painter, frame: &Frame2d) {
        let problem = crate::scene::Problem::Segments(self.scene.clone());
        let [a1, a2, b1, b2] = self.scene.points();
        super::class_view::draw_cloud(painter, &problem, |[t, s]| {
            [(t, a1, a2), (s, b1, b2)]
                .into_iter()
                .filter_map(|(value, p1, p2)| {
                    value.map(|value| frame.screen_from_world(p1 + value * (p2 - p1)))
                })
                .collect()
        });
    }

    fn draw_highlights(&self, painter: &egui::Painter, frame: &Frame2d, solved: &Solved) {
        let [a1, a2, b1, b2] = self.scene.points().map(|p| frame.screen_from_world(p));
        let glow = |color: egui::Color32| Stroke::new(12.0, faded(color, 90));
        let explored = self.exploration();
        for element in &self.highlight {
            match element {
                Element::Column(Column::A2MinusA1) => {
                    line(painter, frame, [a1, a2], glow(palette::SEGMENT_A))
                }
                Element::Column(Column::B1MinusB2) => {
                    line(painter, frame, [b2, b1], glow(palette::SEGMENT_B))
                }
                Element::Rhs => line(painter, frame, [a1, b1], glow(palette::RHS)),
                Element::Side(Side::SegmentA) => {
                    for p in [a1, a2] {
                        painter.circle_stroke(p, 13.0, glow(palette::SEGMENT_A));
                    }
                }
                Element::Side(Side::SegmentB) => {
                    for p in [b1, b2] {
                        painter.circle_stroke(p, 13.0, glow(palette::SEGMENT_B));
                    }
                }
                Element::Parameter(Parameter::T) => {
                    let at = frame.screen_from_world(DVec2::from(explored.a_at_t));
                    painter.circle_stroke(at, 15.0, glow(palette::SEGMENT_A));
                }
                Element::Parameter(Parameter::S) => {
                    let at = frame.screen_from_world(DVec2::from(explored.b_at_s));
                    painter.circle_stroke(at, 15.0, glow(palette::SEGMENT_B));
                }
                Element::Hit => {
                    if let Some(p) = solved.float.point {
                        let at = frame.screen_from_world(DVec2::from(p));
                        painter.circle_stroke(at, 16.0, glow(palette::SOLUTION));
                    }
                }
                _ => {}
            }
        }
    }

    fn draw_solution(
        &self,
        painter: &egui::Painter,
        frame: &Frame2d,
        solved: &Solved,
        labels: &mut LabelLayer,
    ) {
        // A practice problem's outcome is for the student to predict.
        if super::widgets::answers_hidden(painter.ctx()) {
            return;
        }
        let s = &solved.float;
        match &s.outcome {
            SegmentsOutcome::Crossing | SegmentsOutcome::Touching => {
                if let Some(p) = s.point {
                    let at = frame.screen_from_world(DVec2::from(p));
                    painter.circle_filled(at, 6.0, palette::SOLUTION);
                    labels.avoid_point(at, 7.0);
                }
            }
            SegmentsOutcome::LinesCrossOutside { .. } => {
                if let Some(p) = s.point {
                    let at = frame.screen_from_world(DVec2::from(p));
                    painter.circle_stroke(at, 8.0, Stroke::new(2.0, palette::OUTSIDE));
                    labels.avoid_point(at, 9.0);
                    labels.add(
                        at,
                        "lines cross here, off a segment",
                        palette::OUTSIDE,
                        FontId::proportional(16.0),
                        Priority::Normal,
                        9.0,
                    );
                }
            }
            SegmentsOutcome::CollinearOverlap => {
                if let Some([from, to]) = s.overlap {
                    let (a1, a2) = (&self.scene.a1, &self.scene.a2);
                    let at = |u: f64| {
                        frame.screen_from_world(DVec2::from(segments::point_on(a1, a2, &u)))
                    };
                    line(
                        painter,
                        frame,
                        [at(from), at(to)],
                        Stroke::new(9.0, faded(palette::SOLUTION, 170)),
                    );
                }
            }
            _ => {}
        }
    }
}

/// A grid at round world units with labelled axes; the numbers go through the label pass as minor
/// labels, so they give way to the scene's labels.
fn draw_grid(ui: &Ui, painter: &egui::Painter, frame: &Frame2d, labels: &mut LabelLayer) {
    let text = ui.visuals().text_color();
    let number_color = ui.visuals().weak_text_color();
    let rect = frame.rect;
    let world_min = frame.world_from_screen(rect.left_bottom());
    let world_max = frame.world_from_screen(rect.right_top());
    // A spacing of 1, 2 or 5 times a power of ten, about 60 points apart.
    let raw = 60.0 / frame.scale;
    let power = 10f64.powf(raw.log10().floor());
    let spacing = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|s| *s >= raw)
        .unwrap_or(raw);
    // Nothing sensible to draw for a view at infinity or a grid of thousands of lines.
    let lines = ((world_max - world_min) / spacing).max_element();
    if !world_min.is_finite() || !world_max.is_finite() || !(0.0..=500.0).contains(&lines) {
        return;
    }
    let font = FontId::proportional(13.0);
    let grid = Stroke::new(1.0, faded(text, 25));
    let axis = Stroke::new(1.5, faded(text, 120));
    let mut x = (world_min.x / spacing).floor() * spacing;
    while x <= world_max.x {
        let top = frame.screen_from_world(DVec2::new(x, world_max.y));
        let bottom = frame.screen_from_world(DVec2::new(x, world_min.y));
        painter.line_segment([top, bottom], if x == 0.0 { axis } else { grid });
        let label_at = frame
            .screen_from_world(DVec2::new(x, 0.0))
            .y
            .max(rect.top() + 2.0)
            .min(rect.bottom() - 18.0);
        labels.add_fixed(
            pos2(top.x + 3.0, label_at + 2.0),
            egui::Align2::LEFT_TOP,
            format_float(x, Precision::F64),
            number_color,
            font.clone(),
        );
        x += spacing;
    }
    let mut y = (world_min.y / spacing).floor() * spacing;
    while y <= world_max.y {
        let left = frame.screen_from_world(DVec2::new(world_min.x, y));
        let right = frame.screen_from_world(DVec2::new(world_max.x, y));
        painter.line_segment([left, right], if y == 0.0 { axis } else { grid });
        if y != 0.0 {
            let label_at = frame
                .screen_from_world(DVec2::new(0.0, y))
                .x
                .max(rect.left() + 2.0)
                .min(rect.right() - 40.0);
            labels.add_fixed(
                pos2(label_at + 3.0, left.y - 2.0),
                egui::Align2::LEFT_BOTTOM,
                format_float(y, Precision::F64),
                number_color,
                font.clone(),
            );
        }
        y += spacing;
    }
    // The axis names sit at the ends of the axes (or at the edge when an axis is off screen).
    let origin = frame.screen_from_world(DVec2::ZERO);
    let x_axis_y = origin.y.max(rect.top() + 24.0).min(rect.bottom() - 6.0);
    let y_axis_x = origin.x.max(rect.left() + 6.0).min(rect.right() - 24.0);
    for (at, align, name) in [
        (
            pos2(rect.right() - 8.0, x_axis_y - 4.0),
            egui::Align2::RIGHT_BOTTOM,
            "x",
        ),
        (
            pos2(y_axis_x + 8.0, rect.top() + 4.0),
            egui::Align2::LEFT_TOP,
            "y",
        ),
    ] {
        labels.add_fixed(at, align, name, text, FontId::proportional(16.0));
    }
}

/// A line clipped to a frame around the plot: far-off or non-finite ends would make the tessellator
/// work for ever (a dashed line 1e300 points long) or draw nonsense.
fn line(painter: &egui::Painter, frame: &Frame2d, [a, b]: [Pos2; 2], stroke: Stroke) {
    let bound = frame
        .rect
        .expand(frame.rect.width().max(frame.rect.height()));
    if let Some(points) = super::widgets::scene3d::clip_to_rect(a, b, bound) {
        painter.line_segment(points, stroke);
    }
}

/// A dashed line, clipped like [`line`].
fn dashed(painter: &egui::Painter, frame: &Frame2d, [a, b]: [Pos2; 2], stroke: Stroke) {
    let bound = frame
        .rect
        .expand(frame.rect.width().max(frame.rect.height()));
    if let Some(points) = super::widgets::scene3d::clip_to_rect(a, b, bound) {
        painter.extend(Shape::dashed_line(&points, stroke, 6.0, 4.0));
    }
}
