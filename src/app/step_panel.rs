//! The step panel: draws a [`Trace`] step by step — matrices as bracketed grids with their columns in
//! the colours of the view, determinants expanded with their minors as small matrices, β = |M1|/|M|
//! with float and fraction, the checks with ✓ / ✗ and the value they tested, the verdict — and copies
//! any step, or the whole trace, as LaTeX.
//!
//! It formats what the solver recorded and never computes a number itself. Everything wraps to the
//! panel's width: the panel scrolls up and down, never sideways.

use egui::{Align, Color32, FontId, Layout, RichText, Stroke, TextStyle, Ui, Vec2};

use super::widgets::formula_text::{break_between_terms, keep_formulas_whole};
use super::widgets::palette;
use crate::geometry::Precision;
use crate::trace::{self, Column, Matrix, Number, Payload, Status, Step, Trace};

/// How long "Copied ✓" stays on a LaTeX button after a click, in seconds.
const COPIED_FOR: f64 = 2.0;

/// The arithmetic the steps are shown in: a precision, or (for the triangle) symbols.
pub struct Choice<'a> {
    /// f32, f64 or exact.
    pub precision: &'a mut Precision,
    /// Symbols instead of numbers, where the view offers them (`None`: not offered).
    pub symbolic: Option<&'a mut bool>,
    /// Whose steps these are, when the view says (the Render view: which pixel, image and ray).
    pub subject: Option<String>,
}

/// What the reader of the panel is pointing at.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PanelResponse {
    /// The id of the step under the pointer, so the view can highlight what it is about.
    pub hovered_step: Option<String>,
}

/// Draws the precision picker, then every step of the trace. `marked_column` is the label of a
/// column vector hovered in the view (`A−B`): its column is marked in every matrix. With `to_top`
/// (a new scene) the steps scroll back to the first.
pub fn ui(
    ui: &mut Ui,
    trace: &Trace,
    mut choice: Choice<'_>,
    marked_column: Option<Column>,
    to_top: bool,
) -> PanelResponse {
    let subject = choice.subject.take();
    ui.horizontal_wrapped(|ui| {
        ui.heading("Steps");
        ui.label("in");
        let Choice {
            precision,
            mut symbolic,
            subject: _,
        } = choice;
        let in_symbols = symbolic.as_deref().copied().unwrap_or(false);
        for p in <Precision as strum::IntoEnumIterator>::iter() {
            let response = ui
                .selectable_label(!in_symbols && *precision == p, p.name())
                .on_hover_text(precision_tooltip(p));
            if response.clicked() {
                *precision = p;
                if let Some(symbolic) = symbolic.as_deref_mut() {
                    *symbolic = false;
                }
            }
        }
        if let Some(symbolic) = symbolic {
            ui.selectable_value(symbolic, true, "symbolic").on_hover_text(
                "Seed 002: the system and Cramer's determinants in the symbols ax … dz, then the \
                 common terms merged into Möller–Trumbore's cross and dot products, each identity \
                 checked on this scene's numbers",
            );
        }
    });
    copy_button(
        ui,
        "Copy all as LaTeX",
        "Copies every step as LaTeX (amsmath, amssymb, xcolor) for slides",
        || trace::to_latex(trace),
    );
    if let Some(subject) = &subject {
        ui.add(egui::Label::new(RichText::new(format!("Of {subject}")).strong()).wrap());
    }
    ui.separator();
    let mut hovered_step = None;
    let mut scroll = egui::ScrollArea::vertical()
        .id_salt("steps-scroll")
        .auto_shrink([false, false]);
    if to_top {
        scroll = scroll.vertical_scroll_offset(0.0);
    }
    scroll.show(ui, |ui| {
        for (index, step) in trace.steps.iter().enumerate() {
            let card = step_ui(ui, index + 1, step, marked_column);
            if card.contains_pointer() {
                hovered_step = Some(step.id.clone());
            }
        }
    });
    PanelResponse { hovered_step }
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

/// One step as a card: its number and title (wrapped beside a LaTeX button), the explanation and the
/// payload. Returns the card's response, for hover.
pub fn step_ui(
    ui: &mut Ui,
    number: usize,
    step: &Step,
    marked_column: Option<Column>,
) -> egui::Response {
    let card = egui::Frame::group(ui.style())
        .show(ui, |ui| {
            ui.set_width(ui.available_width());
            title_row(ui, number, step);
            ui.add(egui::Label::new(RichText::new(&step.explanation).weak()).wrap());
            payload_ui(ui, &step.id, &step.payload, marked_column);
            float_expansions_ui(ui, &step.id, &step.payload);
        })
        .response;
    // A screen reader reads the step whole, as the text renderer writes it, not cell by cell.
    card.widget_info(|| {
        egui::WidgetInfo::labeled(egui::Role::Group, true, spoken_step(number, step))
    });
    card
}

/// A step as one text: "Step 11. t by Cramer's rule", its explanation and its payload's lines.
pub fn spoken_step(number: usize, step: &Step) -> String {
    let lines: Vec<String> = trace::step_to_text(step)
        .lines()
        .map(|line| line.trim().to_string())
        .filter(|line| !line.is_empty())
        .collect();
    format!("Step {number}. {}", lines.join("\n"))
}

/// The title beside its LaTeX button when it fits there on one row; else the title wraps (as text,
/// its formulas whole) across the whole width and the button goes below it.
fn title_row(ui: &mut Ui, number: usize, step: &Step) {
    let text = format!("{number}. {}", keep_formulas_whole(&step.title));
    let title = RichText::new(text.clone()).strong();
    let button_width = text_width(ui, "Copied ✓", TextStyle::Button)
        + 2.0 * ui.spacing().button_padding.x
        + ui.spacing().item_spacing.x;
    let one_row = text_width(ui, &text, TextStyle::Body) + button_width <= ui.available_width();
    let copy = |ui: &mut Ui| {
        copy_button(ui, "LaTeX", "Copy this step as LaTeX", || {
            trace::step_to_latex(step)
        });
    };
    // A screen reader (and a test looking it up) reads the title with plain spaces.
    let plain = format!("{number}. {}", step.title);
    let spoken = |response: egui::Response| {
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, &plain));
    };
    if one_row {
        ui.horizontal_top(|ui| {
            spoken(ui.add(egui::Label::new(title)));
            ui.with_layout(Layout::right_to_left(Align::TOP), copy);
        });
    } else {
        spoken(ui.add(egui::Label::new(title).wrap()));
        ui.with_layout(Layout::right_to_left(Align::TOP), copy);
    }
}

/// A button that copies text and says "Copied ✓" for a moment after, so a teacher knows it worked.
fn copy_button(ui: &mut Ui, label: &str, tooltip: &str, text: impl FnOnce() -> String) {
    let id = ui.scope_id().with(("copied", label, ui.next_auto_id()));
    let now = ui.input(|i| i.time);
    let copied_at: Option<f64> = ui.data(|d| d.get_temp(id));
    let copied = copied_at.is_some_and(|at| now - at < COPIED_FOR);
    let shown = if copied { "Copied ✓" } else { label };
    let button = egui::Button::new(RichText::new(shown).small());
    if ui.add(button).on_hover_text(tooltip).clicked() {
        ui.ctx().copy_text(text());
        ui.data_mut(|d| d.insert_temp(id, now));
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_secs_f64(COPIED_FOR));
    } else if copied {
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_secs_f64(0.25));
    }
}

fn text_width(ui: &Ui, text: &str, style: TextStyle) -> f32 {
    let font = style.resolve(ui.style());
    galley_width(ui, text, font)
}

fn galley_width(ui: &Ui, text: &str, font: FontId) -> f32 {
    ui.fonts_mut(|f| f.layout_no_wrap(text.to_string(), font, Color32::WHITE))
        .size()
        .x
}

/// A payload: text wraps to the panel; matrices and expansions, whose long decimals cannot wrap,
/// scroll sideways inside their step when they do not fit, so the panel never widens under the view.
fn payload_ui(ui: &mut Ui, id: &str, payload: &Payload, marked_column: Option<Column>) {
    match payload {
        Payload::System { .. } | Payload::Matrix(_) | Payload::Determinant(_) => {
            let width = ui.available_width();
            egui::ScrollArea::horizontal()
                .id_salt(format!("{id}-wide"))
                .auto_shrink([false, true])
                .show(ui, |ui| payload_body(ui, id, payload, marked_column, width));
        }
        _ => {
            let width = ui.available_width();
            payload_body(ui, id, payload, marked_column, width)
        }
    }
}

/// `width` is the panel's: what a row must fit in to stay on one line.
fn payload_body(
    ui: &mut Ui,
    id: &str,
    payload: &Payload,
    marked_column: Option<Column>,
    width: f32,
) {
    let visuals = ui.visuals().clone();
    let ink = |c: Color32| palette::ink(c, &visuals);
    match payload {
        Payload::System {
            matrix,
            unknowns,
            rhs,
            ..
        } => {
            let m = matrix_grid(matrix, marked_column, &visuals);
            let x = Grid::column(unknowns.iter().map(|u| (u.clone(), None)).collect());
            let y = Grid::column(
                rhs.components
                    .iter()
                    .map(|n| (n.shown(), Some(ink(palette::RHS))))
                    .collect(),
            );
            let operators =
                text_width(ui, " · = ", TextStyle::Body) + 4.0 * ui.spacing().item_spacing.x;
            let wide = m.width(ui) + x.width(ui) + y.width(ui) + operators;
            if wide <= width {
                ui.horizontal(|ui| {
                    m.show(ui, &format!("{id}-m"));
                    ui.label("·");
                    x.show(ui, &format!("{id}-x"));
                    ui.label("=");
                    y.show(ui, &format!("{id}-y"));
                });
            } else {
                // Too narrow for one row: M on its own, then · X = Y beneath it, the vectors at
                // the row's top and the signs dropped to their middle row (egui would centre them
                // on the row's first height, at the top).
                m.show(ui, &format!("{id}-m"));
                let rows = unknowns.len();
                ui.horizontal_top(|ui| {
                    level_sign(ui, "·", rows);
                    x.show(ui, &format!("{id}-x"));
                    level_sign(ui, "=", rows);
                    y.show(ui, &format!("{id}-y"));
                });
            }
        }
        Payload::Matrix(matrix) => {
            let grid = matrix_grid(matrix, marked_column, &visuals);
            ui.horizontal(|ui| {
                ui.label(RichText::new(format!("{} =", matrix.name)).strong());
                grid.show(ui, id);
            });
            if let Some(column) = matrix.replaced_column {
                ui.add(
                    egui::Label::new(
                        RichText::new(format!("column {} replaced by Y", column + 1))
                            .color(ink(palette::RHS)),
                    )
                    .wrap(),
                );
            }
        }
        Payload::Determinant(det) => determinant_ui(ui, id, det),
        Payload::Check(check) => {
            let (mark, color) = if check.passed {
                ("✓", ink(palette::INSIDE))
            } else {
                ("✗", ink(palette::OUTSIDE))
            };
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new(mark).color(color).strong().size(20.0));
                ui.label(RichText::new(&check.inequality).strong());
                ui.label(format!("({})", trace::check_value(check)));
            });
            if !check.passed {
                ui.add(egui::Label::new(RichText::new(&check.meaning).color(color)).wrap());
            }
        }
        Payload::Verdict(verdict) => {
            let color = ink(verdict_color(verdict.status));
            egui::Frame::new()
                .stroke(Stroke::new(2.0, color))
                .inner_margin(6.0)
                .corner_radius(4.0)
                .show(ui, |ui| {
                    ui.label(
                        RichText::new(verdict.status.word().to_uppercase())
                            .color(color)
                            .strong(),
                    );
                    ui.add(egui::Label::new(&verdict.message).wrap());
                });
        }
        other => {
            for line in trace::payload_lines(other) {
                math_line(ui, &line);
            }
        }
    }
}

/// A sign between column vectors of `rows` cells, dropped to their middle row.
fn level_sign(ui: &mut Ui, sign: &str, rows: usize) {
    let row = ui.text_style_height(&TextStyle::Monospace) + ui.spacing().item_spacing.y;
    let drop = (rows as f32 * row - ui.text_style_height(&TextStyle::Body)) / 2.0;
    ui.vertical(|ui| {
        ui.add_space(drop.max(0.0));
        ui.label(sign);
    });
}

/// A line of math in monospace, wrapped only between its terms; read (and found) with plain spaces.
fn math_line(ui: &mut Ui, line: &str) {
    let shown = RichText::new(break_between_terms(line)).monospace();
    ui.add(egui::Label::new(shown).wrap())
        .widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, line));
}

/// For a step whose numbers include float values shown by their shortest decimal (exact mode on a
/// probed pixel's floats), the whole exact value of each, one click away.
fn float_expansions_ui(ui: &mut Ui, id: &str, payload: &Payload) {
    let mut floats: Vec<(String, String)> = Vec::new();
    for n in payload_numbers(payload) {
        if let Some(expansion) = &n.float_expansion {
            let pair = (n.shown(), expansion.clone());
            if !floats.contains(&pair) {
                floats.push(pair);
            }
        }
    }
    if floats.is_empty() {
        return;
    }
    egui::CollapsingHeader::new(RichText::new("Float values, exactly").small())
        .id_salt(format!("{id}-floats"))
        .show(ui, |ui| {
            ui.add(
                egui::Label::new(
                    RichText::new(
                        "Numbers such as -6.7 here are floats: each is shown by the shortest \
                         decimal that reads back as the same float, and computed with exactly its \
                         value, which is:",
                    )
                    .weak(),
                )
                .wrap(),
            );
            for (shown, expansion) in floats {
                ui.add(
                    egui::Label::new(RichText::new(format!("{shown} = {expansion}")).monospace())
                        .wrap(),
                );
            }
        })
        .header_response
        .on_hover_text("The exact value of each float in this step");
}

/// Every number a payload shows.
fn payload_numbers(payload: &Payload) -> Vec<&Number> {
    fn matrix(m: &Matrix) -> Vec<&Number> {
        m.rows.iter().flatten().collect()
    }
    match payload {
        Payload::System { matrix: m, rhs, .. } => {
            let mut all = matrix(m);
            all.extend(&rhs.components);
            all
        }
        Payload::Matrix(m) => matrix(m),
        Payload::Determinant(det) => {
            let mut all = Vec::new();
            for term in &det.terms {
                all.push(&term.element);
                all.extend(term.minor.iter().flatten());
            }
            all
        }
        Payload::Vector(v) => v.components.iter().collect(),
        Payload::Scalar(s) => vec![&s.value],
        Payload::Check(c) => vec![&c.value],
        Payload::Verdict(_) | Payload::Symbolic(_) => Vec::new(),
    }
}

/// A determinant's expansion one term per line, each 2x2 minor drawn as a small matrix between bars:
/// |M| = a·|…| / − b·|…| / + c·|…|, then the products, then the value.
fn determinant_ui(ui: &mut Ui, id: &str, det: &crate::trace::Determinant) {
    let name = format!("|{}| ", det.of);
    let pad = " ".repeat(name.chars().count());
    let mono = |ui: &mut Ui, text: String| {
        ui.label(RichText::new(text).monospace());
    };
    let has_minors = det.terms.first().is_some_and(|t| t.minor.len() > 1);
    if has_minors {
        for (i, term) in det.terms.iter().enumerate() {
            let lead = if i == 0 { &name } else { &pad };
            let sign = signed(i, term.sign);
            // A little room between the terms: touching, two minors' bars read as one 4x2 one.
            if i > 0 {
                ui.add_space(4.0);
            }
            ui.horizontal(|ui| {
                mono(ui, format!("{lead}{sign}{}·", term.element.factor()));
                let cells = term
                    .minor
                    .iter()
                    .map(|row| row.iter().map(|n| (n.shown(), None)).collect())
                    .collect();
                Grid {
                    rows: cells,
                    header: Vec::new(),
                    bars: true,
                }
                .show(ui, &format!("{id}-minor-{i}"));
            });
        }
        let products = trace::expansion_products(det);
        math_line(ui, &format!("{pad}= {products}"));
    } else {
        // A 2x2 determinant: ad − bc on one line.
        let terms = trace::expansion_products(det);
        math_line(ui, &format!("{name}= {terms}"));
    }
    let value = if det.value.is_zero() {
        "0 (exactly)".to_string()
    } else {
        det.value.shown()
    };
    mono(ui, format!("{pad}= {value}"));
}

fn signed(i: usize, sign: i8) -> &'static str {
    match (i, sign < 0) {
        (0, false) => "= ",
        (0, true) => "= −",
        (_, true) => "  − ",
        (_, false) => "  + ",
    }
}

/// Green for a meeting, red for a miss, amber for a degenerate or invalid case.
pub fn verdict_color(status: Status) -> Color32 {
    if status.meets() {
        palette::INSIDE
    } else if status.misses() {
        palette::OUTSIDE
    } else {
        palette::RHS
    }
}

/// A cell's text and colour.
type Cell = (String, Option<Color32>);

/// A grid of cells between brackets (or the bars of a determinant), with an optional header row of
/// coloured column labels; a marked column gets a highlight behind its label.
struct Grid {
    header: Vec<(String, Option<Color32>, bool)>,
    rows: Vec<Vec<Cell>>,
    bars: bool,
}

/// Columns are at least this wide, so short numbers line up under their labels.
const MIN_COLUMN: f32 = 28.0;

impl Grid {
    fn column(cells: Vec<Cell>) -> Grid {
        Grid {
            header: Vec::new(),
            rows: cells.into_iter().map(|c| vec![c]).collect(),
            bars: false,
        }
    }

    /// The width the grid will take, measured from its text.
    fn width(&self, ui: &Ui) -> f32 {
        let columns = self.rows.first().map_or(0, Vec::len);
        let mono = TextStyle::Monospace.resolve(ui.style());
        let small = TextStyle::Small.resolve(ui.style());
        let spacing = ui.spacing().item_spacing.x;
        let mut total = 8.0 + 4.0 + 2.0 * spacing;
        for col in 0..columns {
            let cells = self
                .rows
                .iter()
                .filter_map(|r| r.get(col))
                .map(|(t, _)| galley_width(ui, t, mono.clone()));
            let label = self
                .header
                .get(col)
                .map(|(t, _, _)| galley_width(ui, t, small.clone()));
            let widest = cells.chain(label).fold(MIN_COLUMN, f32::max);
            total += widest + spacing;
        }
        total
    }

    fn show(&self, ui: &mut Ui, id: &str) {
        self.show_inline(ui, id);
    }

    /// One grid for labels and cells, so each label sits over its column; the brackets (or bars)
    /// hug the cells.
    fn show_inline(&self, ui: &mut Ui, id: &str) {
        let marked_fill = ui.visuals().selection.bg_fill;
        let mut cells: Option<egui::Rect> = None;
        ui.horizontal(|ui| {
            ui.add_space(8.0);
            egui::Grid::new(format!("{id}-grid"))
                .min_col_width(MIN_COLUMN)
                .show(ui, |ui| {
                    if !self.header.is_empty() {
                        for (label, color, marked) in &self.header {
                            let mut text = RichText::new(label).small();
                            if let Some(color) = color {
                                text = text.color(*color).strong();
                            }
                            if *marked {
                                text = text.background_color(marked_fill).strong();
                            }
                            ui.label(text);
                        }
                        ui.end_row();
                    }
                    for row in &self.rows {
                        for (col, (text, color)) in row.iter().enumerate() {
                            let mut cell = RichText::new(text).monospace();
                            if let Some(color) = color {
                                cell = cell.color(*color);
                            }
                            if self.header.get(col).is_some_and(|h| h.2) {
                                cell = cell.background_color(marked_fill).strong();
                            }
                            let rect = ui.label(cell).rect;
                            cells = Some(cells.map_or(rect, |r| r.union(rect)));
                        }
                        ui.end_row();
                    }
                });
            ui.add_space(4.0);
        });
        if let Some(rect) = cells {
            let rect = rect.expand2(Vec2::new(6.0, 2.0));
            if self.bars {
                bars(ui, rect);
            } else {
                brackets(ui, rect);
            }
        }
    }
}

fn matrix_grid(matrix: &Matrix, marked_column: Option<Column>, visuals: &egui::Visuals) -> Grid {
    let header: Vec<(String, Option<Color32>, bool)> = matrix
        .columns
        .iter()
        .enumerate()
        .map(|(index, &column)| {
            let color = if matrix.replaced_column == Some(index) {
                Some(palette::RHS)
            } else {
                palette::column_color(column)
            };
            let marked = marked_column == Some(column);
            (
                column.label().to_string(),
                color.map(|c| palette::ink(c, visuals)),
                marked,
            )
        })
        .collect();
    let rows = matrix
        .rows
        .iter()
        .map(|row| {
            row.iter()
                .zip(&header)
                .map(|(n, (_, color, _))| (n.shown(), *color))
                .collect()
        })
        .collect();
    Grid {
        header,
        rows,
        bars: false,
    }
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

/// The straight bars of a determinant |…|.
fn bars(ui: &Ui, rect: egui::Rect) {
    let stroke = Stroke::new(1.5, ui.visuals().text_color());
    let painter = ui.painter();
    for x in [rect.left() + 2.0, rect.right() - 2.0] {
        painter.line_segment(
            [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
            stroke,
        );
    }
}
