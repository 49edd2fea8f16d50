//! The colours every view and the step panel share, so a column of M and the vector it came from match.

use egui::Color32;

use crate::trace::Column;

// The pairs a student must tell apart (A and B, inside and outside, hit and miss, the columns A−B,
// A−C, D and Y) stay apart for the three colour-vision deficiencies too: no red against green, and
// β, γ, the ray and Y in blue, magenta, green and amber (see [`vision`], whose test checks it).

/// Segment A (seed 000 draws it dark red; red stays, against B's blue).
pub const SEGMENT_A: Color32 = Color32::from_rgb(0xd0, 0x45, 0x3a);
/// Segment B (seed 000 draws it dark green: blue here, which no colour deficiency confuses with red).
pub const SEGMENT_B: Color32 = Color32::from_rgb(0x2a, 0x7f, 0xd4);
/// The β leg, B−A (and the A−B column of M).
pub const BETA: Color32 = Color32::from_rgb(0x3a, 0x6c, 0xe0);
/// The γ leg, C−A (and the A−C column of M): magenta, apart from β's blue even without red cones.
pub const GAMMA: Color32 = Color32::from_rgb(0xc1, 0x45, 0x8f);
/// The ray and its direction D (and the D column of M).
pub const RAY: Color32 = Color32::from_rgb(0x00, 0xad, 0x58);
/// The right-hand side Y, and the replaced columns of M1, M2, M3.
pub const RHS: Color32 = Color32::from_rgb(0xdf, 0xa6, 0x12);
/// A point inside, a check that passed (bluish green).
pub const INSIDE: Color32 = Color32::from_rgb(0x00, 0xd0, 0x93);
/// A point outside, a check that failed (a pinkish red: apart from the hit's amber, which a plain red
/// is not for deuteranopia once both are darkened to read as text).
pub const OUTSIDE: Color32 = Color32::from_rgb(0xff, 0x21, 0x5e);
/// The solution point (orange-yellow: a hit, apart from the red of a miss).
pub const SOLUTION: Color32 = Color32::from_rgb(0xf0, 0xa8, 0x00);

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

/// Colour-vision deficiencies, simulated to check that the pairs that matter stay apart.
pub mod vision {
    use egui::Color32;

    /// A colour-vision deficiency (the dichromat, severity 1).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Deficiency {
        /// No red cones.
        Protanopia,
        /// No green cones (the most common).
        Deuteranopia,
        /// No blue cones.
        Tritanopia,
    }

    impl Deficiency {
        /// All three.
        pub const ALL: [Deficiency; 3] = [
            Deficiency::Protanopia,
            Deficiency::Deuteranopia,
            Deficiency::Tritanopia,
        ];

        /// The simulation matrix on linear RGB: Machado, Oliveira and Fernandes (2009), "A
        /// physiologically-based model for simulation of color vision deficiency", severity 1.0.
        fn matrix(self) -> [[f32; 3]; 3] {
            match self {
                Deficiency::Protanopia => [
                    [0.152_286, 1.052_583, -0.204_868],
                    [0.114_503, 0.786_281, 0.099_216],
                    [-0.003_882, -0.048_116, 1.051_998],
                ],
                Deficiency::Deuteranopia => [
                    [0.367_322, 0.860_646, -0.227_968],
                    [0.280_085, 0.672_501, 0.047_413],
                    [-0.011_820, 0.042_940, 0.968_881],
                ],
                Deficiency::Tritanopia => [
                    [1.255_528, -0.076_749, -0.178_779],
                    [-0.078_411, 0.930_809, 0.147_602],
                    [0.004_733, 0.691_367, 0.303_900],
                ],
            }
        }
    }

    /// The sRGB channel as linear light.
    fn linear(c: u8) -> f32 {
        let c = f32::from(c) / 255.0;
        if c <= 0.040_45 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    }

    /// Linear light as an sRGB channel.
    fn encoded(c: f32) -> u8 {
        let c = c.clamp(0.0, 1.0);
        let c = if c <= 0.003_130_8 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (c * 255.0).round() as u8
    }

    /// How `color` looks to someone with `deficiency`.
    pub fn simulate(color: Color32, deficiency: Deficiency) -> Color32 {
        let rgb = [color.r(), color.g(), color.b()].map(linear);
        let m = deficiency.matrix();
        let row = |i: usize| encoded(m[i][0] * rgb[0] + m[i][1] * rgb[1] + m[i][2] * rgb[2]);
        Color32::from_rgb(row(0), row(1), row(2))
    }

    /// CIELAB (D65) of an sRGB colour.
    fn lab(color: Color32) -> [f32; 3] {
        let [r, g, b] = [color.r(), color.g(), color.b()].map(linear);
        let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.950_47;
        let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.088_83;
        let f = |t: f32| {
            if t > 0.008_856 {
                t.cbrt()
            } else {
                7.787 * t + 16.0 / 116.0
            }
        };
        let (fx, fy, fz) = (f(x), f(y), f(z));
        [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
    }

    /// The CIE76 colour difference ΔE: about 2 is just noticeable, 15 and more is clearly another
    /// colour at a glance.
    pub fn delta_e(a: Color32, b: Color32) -> f32 {
        let (a, b) = (lab(a), lab(b));
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    }

    /// The least ΔE two colours keep for every deficiency.
    pub const MIN_DIFFERENCE: f32 = 15.0;

    /// The pairs a student must tell apart, by name. (The ray and a failed edge fall to ΔE 4 under
    /// deuteranopia: no colour left in the palette keeps them apart in both themes, so a failed edge
    /// carries ticks across it, and the ray its arrows.)
    pub const PAIRS: [(&str, Color32, &str, Color32); 9] = {
        use super::*;
        [
            ("segment A", SEGMENT_A, "segment B", SEGMENT_B),
            ("inside", INSIDE, "outside", OUTSIDE),
            ("hit", SOLUTION, "miss", OUTSIDE),
            ("A−B", BETA, "A−C", GAMMA),
            ("A−B", BETA, "D", RAY),
            ("A−C", GAMMA, "D", RAY),
            ("A−B", BETA, "Y", RHS),
            ("A−C", GAMMA, "Y", RHS),
            ("D", RAY, "Y", RHS),
        ]
    };
}
