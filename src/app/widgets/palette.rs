//! The colours every view and the step panel share, so a column of M and the vector it came from match.

use egui::Color32;

use crate::trace::Column;

/// Segment A (seed 000 draws it dark red).
pub const SEGMENT_A: Color32 = Color32::from_rgb(0xd0, 0x45, 0x3a);
/// Segment B (seed 000 draws it dark green).
pub const SEGMENT_B: Color32 = Color32::from_rgb(0x2e, 0x9d, 0x4f);
/// The β leg, B−A (and the A−B column of M).
pub const BETA: Color32 = Color32::from_rgb(0x3a, 0x7b, 0xe0);
/// The γ leg, C−A (and the A−C column of M).
pub const GAMMA: Color32 = Color32::from_rgb(0xa0, 0x5a, 0xd8);
/// The ray and its direction D (and the D column of M).
pub const RAY: Color32 = Color32::from_rgb(0x14, 0xa5, 0xb0);
/// The right-hand side Y, and the replaced columns of M1, M2, M3.
pub const RHS: Color32 = Color32::from_rgb(0xe0, 0x98, 0x10);
/// A point inside, a check that passed.
pub const INSIDE: Color32 = Color32::from_rgb(0x2e, 0xa8, 0x4a);
/// A point outside, a check that failed.
pub const OUTSIDE: Color32 = Color32::from_rgb(0xe0, 0x3c, 0x31);
/// The solution point (orange, as seed 000 draws it).
pub const SOLUTION: Color32 = Color32::from_rgb(0xf0, 0x80, 0x10);

/// The colour of a matrix column, by what the column is.
pub fn column_color(column: Column) -> Option<Color32> {
    match column {
        Column::AMinusB | Column::E1 => Some(BETA),
        Column::AMinusC | Column::E2 => Some(GAMMA),
        Column::D | Column::MinusD => Some(RAY),
        Column::Y => Some(RHS),
        Column::A2MinusA1 => Some(SEGMENT_A),
        Column::B1MinusB2 => Some(SEGMENT_B),
        Column::Unnamed => None,
    }
}

/// A faded version of a colour (lines beyond [0, 1], the plane).
pub fn faded(color: Color32, alpha: u8) -> Color32 {
    Color32::from_rgba_unmultiplied(color.r(), color.g(), color.b(), alpha)
}

/// WCAG's minimum contrast for normal text (AA): what a student at the back of a room needs.
pub const MIN_TEXT_CONTRAST: f32 = 4.5;

/// Relative luminance of an sRGB colour (WCAG 2.x), ignoring alpha.
pub fn luminance(color: Color32) -> f32 {
    let channel = |c: u8| {
        let c = c as f32 / 255.0;
        if c <= 0.039_28 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * channel(color.r()) + 0.7152 * channel(color.g()) + 0.0722 * channel(color.b())
}

/// WCAG contrast ratio of two colours, from 1 (same) to 21 (black on white).
pub fn contrast(a: Color32, b: Color32) -> f32 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// The colour itself if it reads at [`MIN_TEXT_CONTRAST`] on every one of `backgrounds`, else the
/// same hue mixed towards black (on light backgrounds) or white (on dark ones) until it does: the
/// amber of Y stays amber in the Dark theme and turns a readable brown in the Light one.
pub fn readable_on(color: Color32, backgrounds: &[Color32]) -> Color32 {
    let Some(&darkest) = backgrounds
        .iter()
        .min_by(|a, b| luminance(**a).total_cmp(&luminance(**b)))
    else {
        return color;
    };
    let light = luminance(darkest) > 0.18;
    let target = if light {
        Color32::BLACK
    } else {
        Color32::WHITE
    };
    let reads = |c: Color32| {
        backgrounds
            .iter()
            .all(|bg| contrast(c, *bg) >= MIN_TEXT_CONTRAST)
    };
    let mut mixed = Color32::from_rgb(color.r(), color.g(), color.b());
    for step in 1..=20 {
        if reads(mixed) {
            break;
        }
        mixed = mix(color, target, step as f32 / 20.0);
    }
    mixed
}

/// A text colour for `color` in these visuals: readable on panels, windows and text fields.
pub fn ink(color: Color32, visuals: &egui::Visuals) -> Color32 {
    readable_on(color, &backgrounds(visuals))
}

/// The backgrounds text is drawn on in these visuals.
pub fn backgrounds(visuals: &egui::Visuals) -> [Color32; 4] {
    [
        visuals.panel_fill,
        visuals.window_fill,
        visuals.extreme_bg_color,
        visuals.panel_fill.blend(visuals.faint_bg_color),
    ]
}

fn mix(a: Color32, b: Color32, amount: f32) -> Color32 {
    let lerp = |x: u8, y: u8| (x as f32 + (y as f32 - x as f32) * amount).round() as u8;
    Color32::from_rgb(lerp(a.r(), b.r()), lerp(a.g(), b.g()), lerp(a.b(), b.b()))
}

/// Every colour the views write text in, by name (the contrast test reads each one).
pub const TEXT_COLOURS: [(&str, Color32); 9] = [
    ("segment A", SEGMENT_A),
    ("segment B", SEGMENT_B),
    ("β", BETA),
    ("γ", GAMMA),
    ("ray", RAY),
    ("Y", RHS),
    ("inside", INSIDE),
    ("outside", OUTSIDE),
    ("solution", SOLUTION),
];

/// `colour.readable(ui)`: [`ink`] for text drawn in this ui.
pub trait Readable {
    /// The colour, darkened or lightened just enough to read on this theme's backgrounds.
    fn readable(self, ui: &egui::Ui) -> Color32;
}

impl Readable for Color32 {
    fn readable(self, ui: &egui::Ui) -> Color32 {
        ink(self, ui.visuals())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contrast_matches_wcag_examples() {
        assert!((contrast(Color32::BLACK, Color32::WHITE) - 21.0).abs() < 0.01);
        assert!((contrast(Color32::WHITE, Color32::WHITE) - 1.0).abs() < 0.001);
        // #767676 on white is the lightest grey that passes AA (4.54:1).
        let grey = Color32::from_gray(0x76);
        assert!((contrast(grey, Color32::WHITE) - 4.54).abs() < 0.01);
    }

    #[test]
    fn readable_colours_pass_on_both_themes() {
        for visuals in [egui::Visuals::light(), egui::Visuals::dark()] {
            for (name, colour) in TEXT_COLOURS {
                let ink = ink(colour, &visuals);
                for bg in backgrounds(&visuals) {
                    assert!(
                        contrast(ink, bg) >= MIN_TEXT_CONTRAST,
                        "{name} on {bg:?}: {:.2}",
                        contrast(ink, bg)
                    );
                }
            }
        }
        // The amber of Y is darkened in Light and left alone in Dark.
        assert_ne!(ink(RHS, &egui::Visuals::light()), RHS);
        assert_eq!(ink(RHS, &egui::Visuals::dark()), RHS);
    }
}
