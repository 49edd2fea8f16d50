//! Widgets the views share: the palette, the 3D canvas, and editors for points and vectors.

pub mod canvas_state;
pub mod formula_text;
pub mod handles;
pub mod labels;
pub mod palette;
pub mod scene3d;
pub mod slide;

use egui::{RichText, Ui};

/// Edits a point or vector with one drag value per component; returns true if it changed.
///
/// Values snap to `step` while dragging (typing can give any number), so dragged coordinates stay
/// readable decimals and exact arithmetic shows short fractions.
pub fn vector_editor<const N: usize>(
    ui: &mut Ui,
    name: &str,
    color: Option<egui::Color32>,
    tooltip: &str,
    value: &mut [f64; N],
    step: f64,
) -> bool {
    let mut changed = false;
    ui.horizontal(|ui| {
        let mut label = RichText::new(name).strong();
        if let Some(color) = color {
            label = label.color(palette::ink(color, ui.visuals()));
        }
        ui.label(label).on_hover_text(tooltip);
        for (axis, component) in ["x", "y", "z"].iter().zip(value.iter_mut()) {
            let response = ui
                .add(
                    egui::DragValue::new(component)
                        .speed(step)
                        .max_decimals(6)
                        .prefix(format!("{axis} ")),
                )
                .on_hover_text(format!("{tooltip}: the {axis} coordinate (drag or type)"));
            if response.changed() {
                if response.dragged() {
                    *component = snap(*component, step);
                }
                changed = true;
            }
        }
    });
    changed
}

/// The verdict in the top-left corner of a canvas, on a backing so it reads over the drawing, wrapped
/// to the canvas width. Its `rect` is the box it covers, for labels to keep clear of; `paint` it after
/// the drawing, so no line or point of the drawing crosses its text.
pub fn verdict_overlay(
    ui: &Ui,
    painter: &egui::Painter,
    rect: egui::Rect,
    trace: &crate::trace::Trace,
    keep_clear: &[egui::Pos2],
) -> Option<VerdictOverlay> {
    if answers_hidden(ui.ctx()) {
        return None;
    }
    let verdict = trace.verdict()?;
    let color = palette::ink(
        crate::app::step_panel::verdict_color(verdict.status),
        ui.visuals(),
    );
    let galley = painter.layout(
        formula_text::keep_formulas_whole(&verdict.message),
        egui::FontId::proportional(17.0),
        color,
        (rect.width() - 24.0).max(50.0),
    );
    let covers = verdict_corner(rect, galley.size(), keep_clear);
    announce_verdict(ui, &verdict.message, covers);
    Some(VerdictOverlay {
        rect: covers,
        fill: ui.visuals().extreme_bg_color.gamma_multiply(0.85),
        galley,
        color,
    })
}

/// Where the verdict's box goes in `rect`: the top-left corner, unless a handle in `keep_clear` is
/// under it; then the first corner (bottom-left, top-right, bottom-right) clear of every handle, or
/// the one over the fewest. A student must see and grab every handle.
fn verdict_corner(rect: egui::Rect, size: egui::Vec2, keep_clear: &[egui::Pos2]) -> egui::Rect {
    let (inset, margin) = (egui::vec2(8.0, 6.0), 4.0);
    let room = rect.shrink2(inset);
    let corners = [
        room.left_top(),
        egui::pos2(room.left(), room.bottom() - size.y),
        egui::pos2(room.right() - size.x, room.top()),
        room.right_bottom() - size,
    ];
    let boxes = corners.map(|at| egui::Rect::from_min_size(at, size).expand(margin));
    // A handle's dot and ring reach about 9 points from its centre.
    let covered = |b: &egui::Rect| {
        keep_clear
            .iter()
            .filter(|p| b.expand(9.0).contains(**p))
            .count()
    };
    boxes
        .iter()
        .copied()
        .enumerate()
        .min_by_key(|(i, b)| (covered(b), *i))
        .map_or(boxes[0], |(_, b)| b)
}

/// Puts the verdict in the accessibility tree as a polite live region: a screen reader announces it
/// when a drag or a key changes it. Its bounds are the box it covers (tests check no handle is
/// under it).
fn announce_verdict(ui: &Ui, message: &str, covers: egui::Rect) {
    let id = egui::Id::unique("raylab-verdict");
    ui.ctx().accesskit_node_builder(id, |node| {
        node.set_role(egui::accesskit::Role::Status);
        node.set_live(egui::accesskit::Live::Polite);
        node.set_label(format!("Verdict: {message}"));
        node.set_bounds(egui::accesskit::Rect {
            x0: covers.min.x.into(),
            y0: covers.min.y.into(),
            x1: covers.max.x.into(),
            y1: covers.max.y.into(),
        });
    });
}

/// A canvas's verdict, laid out, to be painted over the drawing.
pub struct VerdictOverlay {
    /// The box it covers (its backing).
    pub rect: egui::Rect,
    fill: egui::Color32,
    galley: std::sync::Arc<egui::Galley>,
    color: egui::Color32,
}

impl VerdictOverlay {
    /// Paints the backing and the text.
    pub fn paint(self, painter: &egui::Painter) {
        painter.rect_filled(self.rect, 4.0, self.fill);
        let at = self.rect.min + egui::vec2(4.0, 4.0);
        painter.galley(at, self.galley, self.color);
    }
}

/// While a practice problem is unanswered the views keep their verdict to themselves: set for the
/// frame's drawing of the view, and cleared after it.
pub fn hide_answers(ctx: &egui::Context, hidden: bool) {
    ctx.data_mut(|d| d.insert_temp(answers_hidden_id(), hidden));
}

/// True while a practice problem's answer is hidden (see [`hide_answers`]).
pub fn answers_hidden(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp(answers_hidden_id()).unwrap_or(false))
}

fn answers_hidden_id() -> egui::Id {
    egui::Id::unique("raylab-answers-hidden")
}

/// The height the verdict box will take at the top of a canvas this wide (for framing the scene
/// below it).
pub fn verdict_height(ui: &Ui, width: f32, trace: &crate::trace::Trace) -> f32 {
    trace.verdict().map_or(0.0, |verdict| {
        let galley = ui.painter().layout(
            formula_text::keep_formulas_whole(&verdict.message),
            egui::FontId::proportional(17.0),
            egui::Color32::WHITE,
            (width - 24.0).max(50.0),
        );
        galley.size().y + 14.0
    })
}

/// A parameter slider: the value, its range, its symbol and what it means.
pub struct ParameterSlider<'a> {
    /// The parameter.
    pub value: &'a mut f64,
    /// The slider's range (typing or animating can go beyond it).
    pub range: std::ops::RangeInclusive<f64>,
    /// The symbol, e.g. `β`: also the slider's accessible label.
    pub name: &'a str,
    /// The tooltip.
    pub tip: &'a str,
}

/// A lecture view's two parts.
pub enum Part {
    /// The controls, in a strip below.
    Controls,
    /// The drawing, above, filling the rest.
    Drawing,
}

/// Lays out a lecture view: `draw(ui, Part::Controls)` in a strip at the bottom that scrolls when
/// short (at most 45% of the height, so the drawing keeps at least 55%), folded under a header on a
/// [`SHORT_VIEW`], then `draw(ui, Part::Drawing)` above it. `id` names the strip.
///
/// On a view this short (points; a 1280x800 projector at 200%), the controls fold under one header
/// and the drawing takes the height.
pub const SHORT_VIEW: f32 = 360.0;

pub fn controls_below(ui: &mut egui::Ui, id: &str, mut draw: impl FnMut(&mut egui::Ui, Part)) {
    let controls_height = (ui.available_height() * 0.45).max(48.0);
    let short = ui.available_height() < SHORT_VIEW;
    egui::Panel::bottom(id.to_string())
        .resizable(false)
        .max_size(controls_height)
        .show(ui, |ui| {
            // The strip starts at the panel's last height, and a scroll area fits the room it is
            // given: its smallest scrolled height lets it ask for its content (up to the cap), or
            // the strip would never grow past its first height and cut the controls off.
            let mut controls = |ui: &mut egui::Ui| {
                egui::ScrollArea::vertical()
                    .auto_shrink([false, true])
                    .min_scrolled_height(controls_height)
                    .show(ui, |ui| draw(ui, Part::Controls));
            };
            if short {
                egui::CollapsingHeader::new("Controls: Solve and the sliders")
                    .id_salt((id, "folded"))
                    .default_open(false)
                    .show(ui, controls)
                    .header_response
                    .on_hover_text("Folded to give the drawing the room on a zoomed screen");
            } else {
                controls(ui);
            }
        });
    egui::CentralPanel::default().show(ui, |ui| draw(ui, Part::Drawing));
}

impl<'a> ParameterSlider<'a> {
    /// A slider for `value` over `range`, labelled `name`, explained by `tip`.
    pub fn new(
        value: &'a mut f64,
        range: std::ops::RangeInclusive<f64>,
        name: &'a str,
        tip: &'a str,
    ) -> ParameterSlider<'a> {
        ParameterSlider {
            value,
            range,
            name,
            tip,
        }
    }
}

/// The parameter sliders in one row when the view is wide enough, else one per row (a slider is a
/// composite widget, so a wrapping row cannot wrap it).
pub fn parameter_sliders(ui: &mut Ui, sliders: Vec<ParameterSlider<'_>>) {
    let one_row = ui.available_width() >= 270.0 * sliders.len() as f32;
    let add = |ui: &mut Ui, slider: ParameterSlider<'_>| {
        ui.add(
            egui::Slider::new(slider.value, slider.range)
                .text(slider.name)
                .clamping(egui::SliderClamping::Never)
                .max_decimals(4),
        )
        .on_hover_text(slider.tip);
    };
    if one_row {
        ui.horizontal(|ui| sliders.into_iter().for_each(|s| add(ui, s)));
    } else {
        ui.vertical(|ui| sliders.into_iter().for_each(|s| add(ui, s)));
    }
}

/// A line of status text: what does not fit wraps onto the next row (never cut with "…": on a
/// zoomed projector "B(s…" told the student nothing).
pub fn status_line(ui: &mut Ui, add_contents: impl FnOnce(&mut Ui)) {
    ui.horizontal_wrapped(|ui| {
        ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Wrap);
        add_contents(ui);
    });
}

/// A parameter on a status line: its handle's value, and the solver's solution in floats and (when
/// exact) as a fraction.
pub struct ShownValue<'a> {
    /// Where the handle is.
    pub value: f64,
    /// The float solution, if the solve found one.
    pub solution: Option<f64>,
    /// The exact solution, if the solve was exact.
    pub exact: Option<&'a crate::math::exact::Exact>,
}

impl ShownValue<'_> {
    /// The exact fraction this handle shows: the solution's when it sits on it, or, beside an exact
    /// solve, the handle's own value when that is a short fraction (0.5 is 1/2).
    fn fraction(&self) -> Option<String> {
        match (self.solution, self.exact) {
            (Some(s), Some(e)) if s == self.value && e.is_short() => Some(e.fraction()),
            // Only beside an exact solve: with no exact answer to compare, decimals.
            (_, Some(_)) => crate::math::exact::Exact::from_f64(self.value)
                .filter(crate::math::exact::Exact::is_short)
                .map(|e| e.fraction()),
            _ => None,
        }
    }
}

/// The values of one status line in one format: all fractions when every one is a short fraction
/// (`α = 1/4  β = 1/2  t = 1`), else all decimals (never `α = 0.5  β = 1/2`).
pub fn shown_values<const N: usize>(values: &[ShownValue<'_>; N]) -> [String; N] {
    let fractions = values.each_ref().map(ShownValue::fraction);
    if fractions.iter().all(Option::is_some) {
        fractions.map(Option::unwrap_or_default)
    } else {
        values
            .each_ref()
            .map(|v| crate::trace::format_float(v.value, crate::geometry::Precision::F64))
    }
}

/// Rounds to a multiple of `step`, then to the float whose shortest decimal is that multiple
/// (so 0.30000000000000004 becomes 0.3).
pub fn snap(value: f64, step: f64) -> f64 {
    if !value.is_finite() || step <= 0.0 {
        return value;
    }
    let decimals = (-step.log10()).ceil().max(0.0) as usize + 1;
    format!("{:.decimals$}", (value / step).round() * step)
        .parse()
        .unwrap_or(value)
}

#[cfg(test)]
mod tests {
    use super::{ShownValue, shown_values};

    #[test]
    fn a_status_line_uses_one_format() {
        let quarter: crate::math::exact::Exact = "1/4".parse().unwrap();
        let half: crate::math::exact::Exact = "1/2".parse().unwrap();
        // α (solution 1/4) and β (solution 0.75, shown as 1/2) at these values.
        let line = |[alpha, beta]: [f64; 2]| {
            shown_values(&[
                ShownValue {
                    value: alpha,
                    solution: Some(0.25),
                    exact: Some(&quarter),
                },
                ShownValue {
                    value: beta,
                    solution: Some(0.75),
                    exact: Some(&half),
                },
            ])
        };
        // α on its solution 1/4, β at 0.5 (not its solution): both fractions.
        assert_eq!(line([0.25, 0.5]), ["1/4", "1/2"]);
        // One value that is no short fraction turns the whole line into decimals.
        assert_eq!(line([0.5, 0.3]), ["0.5", "0.3"]);
    }

    use super::snap;

    #[test]
    fn snapping_gives_short_decimals() {
        assert_eq!(snap(0.30000000000000004, 0.05), 0.3);
        assert_eq!(snap(1.2349, 0.05), 1.25);
        assert_eq!(snap(-0.024, 0.05), -0.0);
        assert_eq!(format!("{}", snap(2.0 / 3.0, 0.05)), "0.65");
        assert!(snap(f64::NAN, 0.05).is_nan());
    }
}
