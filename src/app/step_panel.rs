//! The step panel: draws a [`Trace`] step by step — matrices as bracketed grids with their columns in
//! the colours of the view, determinants expanded, β = |M1|/|M| with float and fraction, the checks with
//! ✓ / ✗, the verdict — and copies any step, or the whole trace, as LaTeX.
//!
//! It formats what the solver recorded and never computes a number itself.

use egui::{Color32, RichText, Stroke, Ui};

use super::widgets::palette;
use crate::geometry::Precision;
use crate::trace::{self, Matrix, Number, Payload, Step, Trace};

/// Draws the precision picker, then every step of the trace.
pub fn ui(ui: &mut Ui, trace: &Trace, precision: &mut Precision) {
    ui.horizontal_wrapped(|ui| {
        ui.heading("Steps");
        ui.label("in");
        for p in Precision::ALL {
            ui.selectable_value(precision, p, p.name())
                .on_hover_text(precision_tooltip(p));
        }
    });
    ui.horizontal(|ui| {
        if ui
            .button("Copy all as LaTeX")
            .on_hover_text("Copies every step as LaTeX (amsmath, amssymb, xcolor) for slides")
            .clicked()
        {
            ui.ctx().copy_text(trace::to_latex(trace));
        }
    });
    ui.separator();
    // Both ways: exact values of float inputs can be wider than the panel, and a wide step must scroll
    // inside the panel instead of widening it under the view.
    egui::ScrollArea::both()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            for (index, step) in trace.steps.iter().enumerate() {
                step_ui(ui, index + 1, step);
            }
        });
}

fn precision_tooltip(p: Precision) -> &'static str {
    match p {
        Precision::F32 => "Solve in single precision: about 7 significant digits",
        Precision::F64 => "Solve in double precision: about 16 significant digits",
        Precision::Exact => {
            "Solve in exact rational arithmetic: fractions like 17/22, with the float beside them"
        }
    }
}

/// One step as a card: its number and title, a LaTeX button, the explanation and the payload.
pub fn step_ui(ui: &mut Ui, number: usize, step: &Step) {
    egui::Frame::group(ui.style()).show(ui, |ui| {
        ui.set_width(ui.available_width());
        ui.horizontal(|ui| {
            ui.label(RichText::new(format!("{number}. {}", step.title)).strong());
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                if ui
                    .small_button("LaTeX")
                    .on_hover_text("Copy this step as LaTeX")
                    .clicked()
                {
                    ui.ctx().copy_text(trace::step_to_latex(step));
                }
            });
        });
        ui.label(RichText::new(&step.explanation).weak());
        payload_ui(ui, &step.id, &step.payload);
    });
}

fn payload_ui(ui: &mut Ui, id: &str, payload: &Payload) {
    match payload {
        Payload::System {
            matrix,
            unknowns,
            rhs,
            ..
        } => {
            ui.horizontal(|ui| {
                matrix_ui(ui, id, matrix, true);
                ui.label("·");
                let x: Vec<Vec<(String, Option<Color32>)>> =
                    unknowns.iter().map(|u| vec![(u.clone(), None)]).collect();
                grid_ui(ui, &format!("{id}-x"), "", &[], &x);
                ui.label("=");
                let y: Vec<Vec<(String, Option<Color32>)>> = rhs
                    .components
                    .iter()
                    .map(|n| vec![(n.shown(), Some(palette::RHS))])
                    .collect();
                grid_ui(ui, &format!("{id}-y"), "", &[], &y);
            });
        }
        Payload::Matrix(matrix) => {
            matrix_ui(ui, id, matrix, false);
        }
        Payload::Determinant(det) => determinant_ui(ui, det),
        Payload::Check(check) => {
            let (mark, color) = if check.passed {
                ("✓", palette::INSIDE)
            } else {
                ("✗", palette::OUTSIDE)
            };
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new(mark).color(color).strong().size(20.0));
                ui.label(RichText::new(&check.inequality).strong());
                ui.label(format!("(value {})", check.value.shown()));
            });
            if !check.passed {
                ui.label(RichText::new(&check.meaning).color(color));
            }
        }
        Payload::Verdict(verdict) => {
            let color = verdict_color(&verdict.status);
            egui::Frame::new()
                .stroke(Stroke::new(2.0, color))
                .inner_margin(6.0)
                .corner_radius(4.0)
                .show(ui, |ui| {
                    ui.label(
                        RichText::new(verdict.status.to_uppercase())
                            .color(color)
                            .strong(),
                    );
                    ui.label(&verdict.message);
                });
        }
        other => {
            for line in trace::payload_lines(other) {
                ui.label(RichText::new(line).monospace());
            }
        }
    }
}

/// A determinant's expansion one term per line, so a 3x3 expansion fits a narrow panel:
/// |M| = a·|…| / − b·|…| / + c·|…| / = products / = value.
fn determinant_ui(ui: &mut Ui, det: &crate::trace::Determinant) {
    let name = format!("|{}| ", det.of);
    let pad = " ".repeat(name.chars().count());
    let signed = |i: usize, sign: i8| match (i, sign < 0) {
        (0, false) => "= ".to_string(),
        (0, true) => "= −".to_string(),
        (_, true) => "  − ".to_string(),
        (_, false) => "  + ".to_string(),
    };
    let shown = |n: &Number| {
        let text = n.shown();
        if text.starts_with('-') {
            format!("({text})")
        } else {
            text
        }
    };
    let mut lines = Vec::new();
    for (i, term) in det.terms.iter().enumerate() {
        let minor = if term.minor.len() == 1 {
            shown(&term.minor[0][0])
        } else {
            let rows: Vec<String> = term
                .minor
                .iter()
                .map(|r| r.iter().map(Number::shown).collect::<Vec<_>>().join(" "))
                .collect();
            format!("|{}|", rows.join("; "))
        };
        let lead = if i == 0 { name.clone() } else { pad.clone() };
        lines.push(format!(
            "{lead}{}{}·{minor}",
            signed(i, term.sign),
            shown(&term.element)
        ));
    }
    if det.terms.first().is_some_and(|t| t.minor.len() > 1) {
        let products: Vec<String> = det
            .terms
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let sign = match (i, t.sign < 0) {
                    (0, true) => "−",
                    (0, false) => "",
                    (_, true) => " − ",
                    (_, false) => " + ",
                };
                format!("{sign}{}·{}", shown(&t.element), shown(&t.minor_det))
            })
            .collect();
        lines.push(format!("{pad}= {}", products.concat()));
    }
    lines.push(format!("{pad}= {}", det.value.shown()));
    for line in lines {
        ui.label(RichText::new(line).monospace());
    }
}

/// Green for a meeting, red for a miss, amber for a degenerate or invalid case.
pub fn verdict_color(status: &str) -> Color32 {
    match status {
        "hit" | "crossing" | "touching" | "collinear-overlap" => palette::INSIDE,
        "miss-outside" | "miss-behind" | "lines-cross-outside" | "collinear-disjoint" => {
            palette::OUTSIDE
        }
        _ => palette::RHS,
    }
}

fn matrix_ui(ui: &mut Ui, id: &str, matrix: &Matrix, in_system: bool) {
    let labels: Vec<(String, Option<Color32>)> = matrix
        .column_labels
        .iter()
        .enumerate()
        .map(|(col, label)| {
            let color = if matrix.replaced_column == Some(col) {
                Some(palette::RHS)
            } else {
                palette::column_color(label)
            };
            (label.clone(), color)
        })
        .collect();
    let rows: Vec<Vec<(String, Option<Color32>)>> = matrix
        .rows
        .iter()
        .map(|row| {
            row.iter()
                .zip(&labels)
                .map(|(n, (_, color))| (cell_text(n), *color))
                .collect()
        })
        .collect();
    let name = if in_system {
        String::new()
    } else {
        format!("{} =", matrix.name)
    };
    grid_ui(ui, id, &name, &labels, &rows);
}

fn cell_text(n: &Number) -> String {
    n.shown()
}

/// A bracketed grid with an optional header row of coloured labels.
fn grid_ui(
    ui: &mut Ui,
    id: &str,
    name: &str,
    header: &[(String, Option<Color32>)],
    rows: &[Vec<(String, Option<Color32>)>],
) {
    ui.horizontal(|ui| {
        if !name.is_empty() {
            ui.label(RichText::new(name).strong());
        }
        ui.vertical(|ui| {
            if !header.is_empty() {
                ui.horizontal(|ui| {
                    ui.add_space(8.0);
                    egui::Grid::new(format!("{id}-header"))
                        .min_col_width(48.0)
                        .show(ui, |ui| {
                            for (label, color) in header {
                                let mut text = RichText::new(label).small();
                                if let Some(color) = color {
                                    text = text.color(*color).strong();
                                }
                                ui.label(text);
                            }
                            ui.end_row();
                        });
                });
            }
            let response = ui
                .horizontal(|ui| {
                    ui.add_space(8.0);
                    egui::Grid::new(format!("{id}-cells"))
                        .min_col_width(48.0)
                        .show(ui, |ui| {
                            for row in rows {
                                for (text, color) in row {
                                    let mut cell = RichText::new(text).monospace();
                                    if let Some(color) = color {
                                        cell = cell.color(*color);
                                    }
                                    ui.label(cell);
                                }
                                ui.end_row();
                            }
                        });
                    ui.add_space(4.0);
                })
                .response;
            brackets(ui, response.rect);
        });
    });
}

fn brackets(ui: &Ui, rect: egui::Rect) {
    let stroke = Stroke::new(1.5, ui.visuals().text_color());
    let painter = ui.painter();
    let (top, bottom) = (rect.top(), rect.bottom());
    for (x, tick) in [(rect.left() + 2.0, 5.0), (rect.right() - 2.0, -5.0)] {
        painter.line_segment([egui::pos2(x, top), egui::pos2(x, bottom)], stroke);
        painter.line_segment([egui::pos2(x, top), egui::pos2(x + tick, top)], stroke);
        painter.line_segment(
            [egui::pos2(x, bottom), egui::pos2(x + tick, bottom)],
            stroke,
        );
    }
}
