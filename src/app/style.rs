//! Fonts and colours for a projector: DejaVu for the glyphs egui lacks, large text styles, solid scroll
//! bars, and every text colour at WCAG AA contrast in both themes.

use egui::Ui;

use super::widgets;

/// Scales every text style of this `Ui` by `factor` (the presented step, readable from the back).
pub(super) fn enlarge(ui: &mut Ui, factor: f32) {
    for font in ui.style_mut().text_styles.values_mut() {
        font.size *= factor;
    }
}

/// Fonts shipped with raylab (DejaVu, for the math symbols egui's default fonts lack: ✓ ✗ ≤ ≠ √ ∥ ᵀ),
/// and larger text than egui's default, readable on a projector.
pub fn set_style(ctx: &egui::Context) {
    use egui::{FontData, FontDefinitions, FontFamily, FontId, TextStyle};
    let mut fonts = FontDefinitions::default();
    for (name, bytes, family) in [
        (
            "DejaVuSans",
            &include_bytes!("../../assets/fonts/DejaVuSans.ttf")[..],
            FontFamily::Proportional,
        ),
        (
            "DejaVuSansMono",
            &include_bytes!("../../assets/fonts/DejaVuSansMono.ttf")[..],
            FontFamily::Monospace,
        ),
    ] {
        fonts.font_data.insert(
            name.into(),
            std::sync::Arc::new(FontData::from_static(bytes)),
        );
        // After egui's own fonts, so DejaVu only fills in the glyphs they lack.
        fonts.families.entry(family).or_default().push(name.into());
    }
    ctx.set_fonts(fonts);
    ctx.all_styles_mut(|style| {
        style.text_styles = [
            (
                TextStyle::Heading,
                FontId::new(22.0, FontFamily::Proportional),
            ),
            (TextStyle::Body, FontId::new(16.0, FontFamily::Proportional)),
            (
                TextStyle::Monospace,
                FontId::new(15.0, FontFamily::Monospace),
            ),
            (
                TextStyle::Button,
                FontId::new(16.0, FontFamily::Proportional),
            ),
            (
                TextStyle::Small,
                FontId::new(13.0, FontFamily::Proportional),
            ),
        ]
        .into();
        style.spacing.slider_width = 160.0;
        // Solid scroll bars, shown whenever there is more: on a zoomed projector a student must see
        // that the controls or the steps go on (egui's floating bars hide until hovered).
        style.spacing.scroll = egui::style::ScrollStyle::solid();
        readable_visuals(&mut style.visuals);
    });
}

/// Text a room can read: every text colour of the theme at WCAG AA (4.5:1) or better on every
/// background it is drawn on. egui's weak text (about 2.5:1 in Dark) and its error red on white are
/// mixed towards the theme's text colour just as far as that needs.
pub(super) fn readable_visuals(visuals: &mut egui::Visuals) {
    let backgrounds = widgets::palette::backgrounds(visuals);
    let readable = |c: egui::Color32| widgets::palette::readable_on(c, &backgrounds);
    let weak = visuals
        .panel_fill
        .blend(visuals.text_color().gamma_multiply(visuals.weak_text_alpha));
    visuals.weak_text_color = Some(readable(weak));
    visuals.hyperlink_color = readable(visuals.hyperlink_color);
    visuals.warn_fg_color = readable(visuals.warn_fg_color);
    visuals.error_fg_color = readable(visuals.error_fg_color);
    for widget in [
        &mut visuals.widgets.noninteractive,
        &mut visuals.widgets.inactive,
        &mut visuals.widgets.hovered,
        &mut visuals.widgets.active,
        &mut visuals.widgets.open,
    ] {
        let on = [widget.bg_fill, widget.weak_bg_fill];
        widget.fg_stroke.color = widgets::palette::readable_on(widget.fg_stroke.color, &on);
    }
}
