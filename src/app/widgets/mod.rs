//! Widgets the views share: the palette, the 3D canvas, and editors for points and vectors.

pub mod palette;
pub mod scene3d;

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
            label = label.color(color);
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
