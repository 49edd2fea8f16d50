//! Plain-text rendering of a [`Trace`], readable in a terminal: matrices with brackets, determinants
//! expanded with their numbers, every check with ✓ or ✗.

use std::fmt::Write;

use super::{Check, Determinant, Formula, Matrix, Number, Payload, Scalar, Step, Trace, Vector};
use crate::math::real::Precision;

/// Formats a float with the digits its precision can mean: 8 significant digits for f32, 10 otherwise.
/// Integers print without a decimal point; very large and small magnitudes use scientific notation.
pub fn format_float(value: f64, precision: Precision) -> String {
    if value.is_nan() {
        return "NaN".into();
    }
    if value.is_infinite() {
        return if value > 0.0 { "∞" } else { "−∞" }.into();
    }
    if value == 0.0 {
        return "0".into();
    }
    if value.fract() == 0.0 && value.abs() < 1e15 {
        return format!("{value:.0}");
    }
    let significant = if precision == Precision::F32 { 8 } else { 10 };
    // Formatted on the stack (a batch formats millions): one allocation, for the result.
    let mut scientific = StackText::default();
    let _ = write!(scientific, "{value:.*e}", significant - 1);
    let (mantissa, exponent) = scientific
        .as_str()
        .split_once('e')
        .unwrap_or((scientific.as_str(), "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    if (-5..10).contains(&exponent) {
        let decimals = (significant as i32 - 1 - exponent).max(0) as usize;
        let mut fixed = StackText::default();
        let _ = write!(fixed, "{value:.decimals$}");
        trim_zeros(fixed.as_str()).to_string()
    } else {
        format!("{}e{exponent}", trim_zeros(mantissa))
    }
}

/// A short text built on the stack (a float's digits: at most 10 before the point here, 14 after).
struct StackText {
    bytes: [u8; 48],
    len: usize,
}

impl Default for StackText {
    fn default() -> Self {
        StackText {
            bytes: [0; 48],
            len: 0,
        }
    }
}

impl StackText {
    fn as_str(&self) -> &str {
        // Only whole strs are written, so the bytes are UTF-8; an empty text if that ever broke.
        std::str::from_utf8(&self.bytes[..self.len]).unwrap_or_default()
    }
}

impl Write for StackText {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let end = self.len + s.len();
        self.bytes
            .get_mut(self.len..end)
            .ok_or(std::fmt::Error)?
            .copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

fn trim_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

/// A number with its float beside it when it is exact: `1/3 ≈ 0.3333333333`.
fn with_float(n: &Number) -> String {
    match &n.exact_shown {
        Some(_) if n.shown_exactly() && n.value.fract() != 0.0 && n.value.is_finite() => {
            format!("{} ≈ {}", n.shown(), format_float(n.value, n.precision))
        }
        _ => n.shown(),
    }
}

/// Wraps a negative number or a fraction in parentheses so `3·(−3)` and `(11/2)·5` read right.
fn paren(n: &Number) -> String {
    n.factor()
}

/// Renders a whole trace.
pub fn to_text(trace: &Trace) -> String {
    let mut out = String::new();
    let heading = format!(
        "{} solve, in {} arithmetic",
        trace.solver,
        trace.precision.name()
    );
    let _ = writeln!(out, "{heading}\n{}", "═".repeat(heading.chars().count()));
    for (index, step) in trace.steps.iter().enumerate() {
        let _ = write!(out, "\n{}. {}", index + 1, step_to_text(step));
    }
    out
}

/// Renders one step: title, explanation, then the payload indented.
pub fn step_to_text(step: &Step) -> String {
    let mut out = format!("{}\n   {}\n", step.title, step.explanation);
    for line in payload_lines(&step.payload) {
        let _ = writeln!(out, "     {line}");
    }
    out
}

/// The lines of one payload, as the text renderer prints them (the app reuses them).
pub fn payload_lines(payload: &Payload) -> Vec<String> {
    match payload {
        Payload::System {
            matrix,
            unknowns,
            rhs,
            ..
        } => {
            let cells = |v: &[String]| v.iter().map(|s| vec![s.clone()]).collect::<Vec<_>>();
            let x = bracket(&cells(unknowns), &["X".into()], None);
            let y = bracket(
                &cells(&rhs.components.iter().map(Number::shown).collect::<Vec<_>>()),
                std::slice::from_ref(&rhs.name),
                None,
            );
            let m = matrix_block(matrix);
            let middle = m.len() / 2 + m.len() % 2;
            let mut times = vec![String::new(); m.len()];
            times[middle.min(m.len() - 1)] = "·".into();
            let mut equals = vec![String::new(); m.len()];
            equals[middle.min(m.len() - 1)] = "=".into();
            side_by_side(&[m, times, x, equals, y])
        }
        Payload::Matrix(matrix) => {
            let mut lines = matrix_block(matrix);
            if let Some(column) = matrix.replaced_column {
                lines.push(format!("(column {} replaced by Y)", column + 1));
            }
            lines
        }
        Payload::Determinant(det) => determinant_lines(det),
        Payload::Vector(vector) => vec![vector_line(vector)],
        Payload::Scalar(scalar) => vec![scalar_line(scalar)],
        Payload::Check(check) => vec![check_line(check)],
        Payload::Verdict(verdict) => vec![format!(
            "⇒ {}: {}",
            verdict.status.word().to_uppercase(),
            verdict.message
        )],
        Payload::Symbolic(symbolic) => symbolic.lines.clone(),
    }
}

fn matrix_block(matrix: &Matrix) -> Vec<String> {
    let cells: Vec<Vec<String>> = matrix
        .rows
        .iter()
        .map(|row| row.iter().map(Number::shown).collect())
        .collect();
    let mut labels: Vec<String> = matrix
        .columns
        .iter()
        .map(|c| c.label().to_string())
        .collect();
    if let Some(column) = matrix.replaced_column {
        labels[column] = format!("▼{}", labels[column]);
    }
    bracket(&cells, &labels, Some(&matrix.name))
}

/// Lays out a bracketed grid with a header of column labels; `name =` goes before the middle row.
fn bracket(cells: &[Vec<String>], labels: &[String], name: Option<&str>) -> Vec<String> {
    let columns = labels.len().max(cells.first().map_or(0, Vec::len));
    let width = |col: usize| {
        cells
            .iter()
            .filter_map(|row| row.get(col))
            .chain(labels.get(col))
            .map(|s| s.chars().count())
            .max()
            .unwrap_or(1)
    };
    let widths: Vec<usize> = (0..columns).map(width).collect();
    let row_text = |row: &[String]| {
        row.iter()
            .zip(&widths)
            .map(|(cell, w)| format!("{cell:>w$}"))
            .collect::<Vec<_>>()
            .join("  ")
    };
    let prefix = name.map(|n| format!("{n} = ")).unwrap_or_default();
    let blank = " ".repeat(prefix.chars().count());
    let middle = cells.len() / 2;
    let mut lines = vec![format!("{blank}  {}", row_text(labels))];
    for (i, row) in cells.iter().enumerate() {
        let (left, right) = match (cells.len(), i) {
            (1, _) => ('[', ']'),
            (_, 0) => ('⎡', '⎤'),
            (n, i) if i + 1 == n => ('⎣', '⎦'),
            _ => ('⎢', '⎥'),
        };
        let lead = if i == middle { &prefix } else { &blank };
        lines.push(format!("{lead}{left} {} {right}", row_text(row)));
    }
    lines
}

/// Joins blocks of lines left to right, padding each block to its widest line.
fn side_by_side(blocks: &[Vec<String>]) -> Vec<String> {
    let height = blocks.iter().map(Vec::len).max().unwrap_or(0);
    (0..height)
        .map(|row| {
            blocks
                .iter()
                .map(|block| {
                    let width = block.iter().map(|l| l.chars().count()).max().unwrap_or(0);
                    // Bottom-align shorter blocks so operators sit on the middle row of the tallest.
                    let offset = height - block.len();
                    let line = row
                        .checked_sub(offset)
                        .and_then(|r| block.get(r))
                        .map_or("", String::as_str);
                    format!("{line:<width$}")
                })
                .collect::<Vec<_>>()
                .join(" ")
                .trim_end()
                .to_string()
        })
        .collect()
}

fn determinant_lines(det: &Determinant) -> Vec<String> {
    let minor_text = |m: &[Vec<Number>]| {
        if m.len() == 1 {
            paren(&m[0][0])
        } else {
            let rows: Vec<String> = m
                .iter()
                .map(|r| r.iter().map(Number::shown).collect::<Vec<_>>().join(" "))
                .collect();
            format!("|{}|", rows.join("; "))
        }
    };
    let symbolic = join_terms(det, |t| {
        format!("{}·{}", paren(&t.element), minor_text(&t.minor))
    });
    let name = format!("|{}| = ", det.of);
    let pad = " ".repeat(name.chars().count() - 2);
    let mut lines = vec![format!("{name}{symbolic}")];
    if det.terms.first().is_some_and(|t| t.minor.len() > 1) {
        lines.push(format!("{pad}= {}", expansion_products(det)));
    }
    lines.push(format!("{pad}= {}", with_float(&det.value)));
    lines
}

/// The expansion's terms, each written by `term_text`, joined by their signs: `a − b + c`.
fn join_terms(det: &Determinant, term_text: impl Fn(&super::ExpansionTerm) -> String) -> String {
    let mut text = String::new();
    for (i, term) in det.terms.iter().enumerate() {
        text.push_str(match (i, term.sign < 0) {
            (0, true) => "−",
            (0, false) => "",
            (_, true) => " − ",
            (_, false) => " + ",
        });
        text.push_str(&term_text(term));
    }
    text
}

/// Each element times its minor's determinant: `(11/2)·5 − (−3)·(−11/4)` (the app draws it too).
pub fn expansion_products(det: &Determinant) -> String {
    join_terms(det, |t| {
        format!("{}·{}", paren(&t.element), paren(&t.minor_det))
    })
}

fn vector_line(vector: &Vector) -> String {
    let parts: Vec<String> = vector.components.iter().map(Number::shown).collect();
    format!("{} = ({})", vector.name, parts.join(", "))
}

fn scalar_line(scalar: &Scalar) -> String {
    let mut text = format!("{} = ", scalar.symbol);
    match &scalar.formula {
        Some(Formula::Quotient {
            numerator,
            denominator,
        }) => {
            let _ = write!(
                text,
                "{} / {} = {} / {} = ",
                numerator.symbol,
                denominator.symbol,
                paren(&numerator.value),
                paren(&denominator.value)
            );
        }
        Some(Formula::Expression { text: formula, .. }) => {
            let _ = write!(text, "{formula} = ");
        }
        None => {}
    }
    match &scalar.closed_form {
        Some(closed) => {
            let _ = write!(
                text,
                "{} ≈ {}",
                closed.text,
                format_float(scalar.value.value, scalar.value.precision)
            );
        }
        None => text.push_str(&with_float(&scalar.value)),
    }
    text
}

fn check_line(check: &Check) -> String {
    let mark = if check.passed { "✓" } else { "✗" };
    let mut text = format!("{mark} {}   ({})", check.inequality, check_value(check));
    if !check.passed {
        let _ = write!(text, ": {}", check.meaning);
    }
    text
}

/// The tested value named by the inequality's left-hand side: `β + γ = 3/4` for `β + γ ≤ 1`.
pub fn check_value(check: &Check) -> String {
    let sides: Vec<&str> = check
        .inequality
        .split(['≤', '≥', '<', '>', '≠', '='])
        .map(str::trim)
        .collect();
    // `x ≤ 1` names x; `0 ≤ α ≤ 1` names α; a compound test such as `A2 ≠ A1 and B2 ≠ B1` names nothing.
    let name = match sides.as_slice() {
        _ if check.inequality.contains(" and ") => "",
        [lhs, _] => lhs,
        [_, middle, _] => middle,
        _ => "",
    };
    let value = if check.value.is_zero() {
        "0".to_string()
    } else {
        with_float(&check.value)
    };
    if name.is_empty() {
        format!("value {value}")
    } else {
        format!("{name} = {value}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_show_meaningful_digits() {
        assert_eq!(format_float(3.0, Precision::F64), "3");
        assert_eq!(format_float(-3.0, Precision::F64), "-3");
        assert_eq!(format_float(1.0 / 3.0, Precision::F64), "0.3333333333");
        assert_eq!(
            format_float((1.0f32 / 3.0) as f64, Precision::F32),
            "0.33333334"
        );
        assert_eq!(format_float(45.0 / 38.0, Precision::F64), "1.184210526");
        assert_eq!(format_float(1.5e-12, Precision::F64), "1.5e-12");
        assert_eq!(format_float(2.5e20, Precision::F64), "2.5e20");
        assert_eq!(format_float(f64::NAN, Precision::F64), "NaN");
        assert_eq!(format_float(f64::NEG_INFINITY, Precision::F64), "−∞");
    }

    #[test]
    fn brackets_align_columns() {
        let cells = vec![
            vec!["3".to_string(), "-10".to_string()],
            vec!["12".to_string(), "1".to_string()],
        ];
        let lines = bracket(&cells, &["a".into(), "b".into()], Some("M"));
        assert_eq!(lines[1], "    ⎡  3  -10 ⎤");
        assert_eq!(lines[2], "M = ⎣ 12    1 ⎦");
    }
}
