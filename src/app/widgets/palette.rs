//! The colours every view and the step panel share, so a column of M and the vector it came from match.

use egui::Color32;

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

/// The colour of a matrix column, by the label the solver gave it.
pub fn column_color(label: &str) -> Option<Color32> {
    match label {
        "A−B" | "e1" => Some(BETA),
        "A−C" | "e2" => Some(GAMMA),
        "D" | "−d" => Some(RAY),
        "Y" => Some(RHS),
        "A2−A1" => Some(SEGMENT_A),
        "B1−B2" => Some(SEGMENT_B),
        _ => None,
    }
}

/// A faded version of a colour (lines beyond [0, 1], the plane).
pub fn faded(color: Color32, alpha: u8) -> Color32 {
    Color32::from_rgba_unmultiplied(color.r(), color.g(), color.b(), alpha)
}
