//! Canvas handles a keyboard and a screen reader can reach. Each handle the mouse can drag (a vertex,
//! an endpoint, the t and s handles, P(β, γ)) also gets a focusable node here, named with its value
//! ("vertex A at (3, 0, 0)"): Tab reaches it, a ring shows the focus, the arrow keys move it (Shift
//! for fine steps) and Enter asks the view to solve. The node senses no click or drag, so the
//! canvas under it still gets every drag.

use egui::{Id, Key, Modifiers, Pos2, Rect, Sense, Stroke, Ui, vec2};
use glam::DVec3;

/// The side of the square a handle's node covers, in points (its dot is drawn smaller).
const NODE_SIDE: f32 = 22.0;

/// The focus ring's radius, in points.
pub const RING_RADIUS: f32 = NODE_SIDE / 2.0;

/// Where the focus ring of a canvas handle was drawn last frame, if one has the focus: labels keep
/// clear of it (a label under the ring loses its first letter).
pub fn focus_ring(ctx: &egui::Context) -> Option<Pos2> {
    let frame = ctx.cumulative_pass_nr();
    ctx.data(|d| d.get_temp::<(u64, Pos2)>(ring_id()))
        .filter(|(at_frame, _)| at_frame + 1 >= frame)
        .map(|(_, at)| at)
}

/// Keeps the labels of `layer` clear of the focus ring, if a handle has the focus.
pub fn labels_avoid_focus_ring(ctx: &egui::Context, layer: &mut super::labels::LabelLayer) {
    if let Some(at) = focus_ring(ctx) {
        layer.avoid_point(at, RING_RADIUS + 4.0);
    }
}

fn ring_id() -> Id {
    Id::unique("raylab-handle-ring")
}

/// What the keys did to a focused handle this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HandleKeys {
    /// Arrow steps: +1 right, −1 left.
    pub right: f64,
    /// Arrow steps: +1 up, −1 down.
    pub up: f64,
    /// Shift was held: a fine step.
    pub fine: bool,
    /// Enter: solve (slide to the solution).
    pub solve: bool,
}

impl HandleKeys {
    /// True if an arrow moved the handle.
    pub fn moved(&self) -> bool {
        self.right != 0.0 || self.up != 0.0
    }

    /// The step a value moves by: `coarse`, or `fine` with Shift.
    pub fn step(&self, coarse: f64, fine: f64) -> f64 {
        if self.fine { fine } else { coarse }
    }
}

/// The stable id of a handle's node (tests and the focus find it by this key).
pub fn handle_id(key: &str) -> Id {
    Id::unique(("raylab-handle", key))
}

/// Places a handle's node at `at`, named `description` in the accessibility tree; while it has
/// the focus, draws the focus ring and reads the arrows and Enter (which then move no other focus
/// and step no slide).
pub fn keyboard_handle(ui: &Ui, key: &str, at: Pos2, description: &str) -> HandleKeys {
    // A point past the float range has no place on screen (a bad input): no node.
    if !(at.x.is_finite() && at.y.is_finite()) {
        return HandleKeys::default();
    }
    let id = handle_id(key);
    let rect = Rect::from_center_size(at, vec2(NODE_SIDE, NODE_SIDE));
    let response = ui.interact(rect, id, Sense::focusable_noninteractive());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Slider, true, description));
    if !response.has_focus() {
        return HandleKeys::default();
    }
    hold_arrows(ui, id);
    let frame = ui.ctx().cumulative_pass_nr();
    ui.ctx().data_mut(|d| d.insert_temp(ring_id(), (frame, at)));
    let ring = ui.visuals().selection.stroke.color;
    let painter = ui.painter();
    painter.circle_stroke(
        at,
        RING_RADIUS + 2.0,
        Stroke::new(4.0, ui.visuals().extreme_bg_color),
    );
    painter.circle_stroke(at, RING_RADIUS, Stroke::new(3.0, ring));
    read_keys(ui)
}

fn read_keys(ui: &Ui) -> HandleKeys {
    let hidden = super::answers_hidden(ui.ctx());
    ui.input_mut(|i| {
        let mut keys = HandleKeys::default();
        // Shift first: a plain pattern also takes a shifted key.
        for (modifiers, fine) in [(Modifiers::SHIFT, true), (Modifiers::NONE, false)] {
            let moved = arrows(i, modifiers);
            keys.fine |= fine && moved != egui::Vec2::ZERO;
            keys.right += f64::from(moved.x);
            keys.up += f64::from(moved.y);
        }
        // A practice problem or an open class question is not solved for the student.
        keys.solve = !hidden && i.consume_key(Modifiers::NONE, Key::Enter);
        keys
    })
}

/// A point as a screen reader reads it: "(2.25, 1.75)".
pub fn point_text(p: &[f64]) -> String {
    let parts: Vec<String> = p
        .iter()
        .map(|x| crate::trace::format_float(*x, crate::geometry::Precision::F64))
        .collect();
    format!("({})", parts.join(", "))
}

/// A parameter's value as a screen reader reads it.
pub fn value_text(x: f64) -> String {
    crate::trace::format_float(x, crate::geometry::Precision::F64)
}

/// What the keys did to a focused canvas (Tab reaches it like any control).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CanvasKeys {
    /// Arrow steps: +1 right, −1 left.
    pub right: f32,
    /// Arrow steps: +1 up, −1 down.
    pub up: f32,
    /// + zooms in (positive), − out (negative).
    pub zoom: f32,
}

/// Names a canvas in the accessibility tree (`description` says what its keys do) and, while it has
/// the focus, draws a ring round it and reads the arrows and + / −.
pub fn canvas_keys(ui: &Ui, response: &egui::Response, description: &str) -> CanvasKeys {
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, description));
    focused_keys(ui, response)
}

/// The arrows and + / − pressed while `response` has the focus (with its ring drawn); none else.
pub fn focused_keys(ui: &Ui, response: &egui::Response) -> CanvasKeys {
    if !response.has_focus() {
        return CanvasKeys::default();
    }
    hold_arrows(ui, response.id);
    let ring = ui.visuals().selection.stroke.color;
    ui.painter().rect_stroke(
        response.rect.shrink(2.0),
        2.0,
        Stroke::new(3.0, ring),
        egui::StrokeKind::Inside,
    );
    ui.input_mut(|i| {
        let moved = arrows(i, Modifiers::NONE);
        let mut pressed = |key| presses(i, Modifiers::NONE, key);
        CanvasKeys {
            right: moved.x,
            up: moved.y,
            zoom: pressed(Key::Plus) + pressed(Key::Equals) - pressed(Key::Minus),
        }
    })
}

/// How many times `key` was pressed with `modifiers` this frame (the presses are taken).
pub fn presses(i: &mut egui::InputState, modifiers: Modifiers, key: Key) -> f32 {
    let mut count = 0.0;
    while i.consume_key(modifiers, key) {
        count += 1.0;
    }
    count
}

/// The arrows pressed with `modifiers` this frame (taken): x is right − left, y is up − down.
pub fn arrows(i: &mut egui::InputState, modifiers: Modifiers) -> egui::Vec2 {
    let mut pressed = |key| presses(i, modifiers, key);
    egui::vec2(
        pressed(Key::ArrowRight) - pressed(Key::ArrowLeft),
        pressed(Key::ArrowUp) - pressed(Key::ArrowDown),
    )
}

/// The focused widget `id` keeps the arrows (they move it, not the focus), and the presenter keys
/// leave them to it.
fn hold_arrows(ui: &Ui, id: Id) {
    ui.memory_mut(|m| {
        m.set_focus_lock_filter(
            id,
            egui::EventFilter {
                horizontal_arrows: true,
                vertical_arrows: true,
                tab: false,
                escape: false,
            },
        )
    });
    mark_focused(ui.ctx());
}

/// Remembers that a handle had the focus this frame (see [`handle_focused`]).
fn mark_focused(ctx: &egui::Context) {
    let frame = ctx.cumulative_pass_nr();
    ctx.data_mut(|d| d.insert_temp(focused_id(), frame));
}

/// True if a canvas handle had the keyboard focus this frame or the one before: the arrows are its
/// own then, not the slides'.
pub fn handle_focused(ctx: &egui::Context) -> bool {
    let frame = ctx.cumulative_pass_nr();
    ctx.data(|d| d.get_temp::<u64>(focused_id()))
        .is_some_and(|at| at + 1 >= frame)
}

fn focused_id() -> Id {
    Id::unique("raylab-handle-focused")
}

/// A value stepped by the arrows, landing on `solution` when it passes within half a step of it (as
/// a dragged handle snaps onto the crossing), unless the step is fine.
pub fn step_value(value: f64, steps: f64, step: f64, fine: bool, solution: Option<f64>) -> f64 {
    let moved = value + steps * step;
    match solution {
        Some(target) if !fine && (moved - target).abs() < step / 2.0 => target,
        _ => super::snap(moved, step),
    }
}

/// A 3D point stepped by the arrows: along the world axis that runs most nearly right on screen
/// (← →) and the one that runs most nearly up (↑ ↓), then snapped to `grid` (as a dragged vertex is).
pub fn step_point(
    point: [f64; 3],
    keys: &HandleKeys,
    screen_right: DVec3,
    screen_up: DVec3,
    step: f64,
    grid: f64,
) -> [f64; 3] {
    let right_axis = nearest_axis(screen_right, None);
    let up_axis = nearest_axis(screen_up, Some(right_axis.0));
    let mut moved = DVec3::from(point);
    moved[right_axis.0] += keys.right * right_axis.1 * step;
    moved[up_axis.0] += keys.up * up_axis.1 * step;
    moved.to_array().map(|x| super::snap(x, grid))
}

/// The world axis (index, sign) most nearly along `direction`, other than `except`.
fn nearest_axis(direction: DVec3, except: Option<usize>) -> (usize, f64) {
    (0..3)
        .filter(|&axis| Some(axis) != except)
        .map(|axis| (axis, direction[axis]))
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map_or((0, 1.0), |(axis, along)| (axis, along.signum()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coarse_step_lands_on_the_solution_it_passes_near() {
        // 0.75 is within half a step (0.025) of 17/22 ≈ 0.7727: it lands there.
        let solution = 17.0 / 22.0;
        assert_eq!(step_value(0.7, 1.0, 0.05, false, Some(solution)), solution);
        // A fine step never snaps.
        assert_eq!(step_value(0.76, 1.0, 0.01, true, Some(solution)), 0.77);
        // Far from it, the value keeps to the step's grid.
        assert_eq!(step_value(0.25, -2.0, 0.05, false, Some(solution)), 0.15);
    }

    #[test]
    fn a_point_moves_along_the_axes_nearest_the_screen_directions() {
        let keys = HandleKeys {
            right: 1.0,
            up: -1.0,
            ..HandleKeys::default()
        };
        // Looking down −y with z up: right is +x (a little tilted), up is +z.
        let right = DVec3::new(0.9, 0.1, -0.2).normalize();
        let up = DVec3::new(0.1, 0.3, 0.95).normalize();
        let moved = step_point([3.0, 0.0, 0.0], &keys, right, up, 0.25, 0.05);
        assert_eq!(moved, [3.25, 0.0, -0.25]);
        // Right pointing along −y: the right arrow moves y down.
        let moved = step_point(
            [0.0; 3],
            &keys,
            -DVec3::Y,
            DVec3::Y * 0.1 + DVec3::Z,
            0.5,
            0.05,
        );
        assert_eq!(moved, [0.0, -0.5, -0.5]);
    }
}
