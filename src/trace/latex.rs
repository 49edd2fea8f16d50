//! LaTeX rendering of a [`Trace`], ready to paste into slides: a `bmatrix` per matrix, determinants
//! expanded with `vmatrix` minors, and `\beta = \frac{|M_1|}{|M|} = …`.
//!
//! Needs amsmath and amssymb (`\checkmark`); the replaced column of M1..M3 uses `\color` from xcolor.
//! Beamer loads all three.

use std::fmt::Write;

use super::text::format_float;
use super::{Check, Determinant, Formula, Matrix, Number, Payload, Scalar, Step, Trace, Vector};

/// Renders a whole trace as a LaTeX fragment: a comment per step, then its display math.
pub fn to_latex(trace: &Trace) -> String {
    let mut out = format!(
        "% raylab: {} solve in {} arithmetic (needs amsmath, amssymb and xcolor; beamer loads them)\n",
        trace.solver,
        trace.precision.name()
    );
    for (index, step) in trace.steps.iter().enumerate() {
        let _ = writeln!(out, "% {}. {}: {}", index + 1, step.title, step.explanation);
        let _ = writeln!(out, "\\[ {} \\]", step_to_latex(step));
    }
    out
}

/// The display math of one step (without `\[ \]`).
pub fn step_to_latex(step: &Step) -> String {
    match &step.payload {
        Payload::System {
            matrix,
            unknowns_latex,
            rhs,
            ..
        } => format!(
            "M\\,X = Y:\\quad {} {} = {}",
            bmatrix(matrix),
            column(unknowns_latex),
            column(&rhs.components.iter().map(number).collect::<Vec<_>>())
        ),
        Payload::Matrix(matrix) => format!("{} = {}", matrix.latex_name, bmatrix(matrix)),
        Payload::Determinant(det) => determinant(det),
        Payload::Vector(vector) => vector_latex(vector),
        Payload::Scalar(scalar) => scalar_latex(scalar),
        Payload::Check(check) => check_latex(check),
        Payload::Symbolic(symbolic) => symbolic.latex.clone(),
        Payload::Verdict(verdict) => format!(
            "\\text{{{}: {}}}",
            verdict.status,
            escape_text(&verdict.message)
        ),
    }
}

/// A number in LaTeX: `\frac{17}{22}` for short exact fractions, `1.5 \times 10^{-12}` for small floats.
pub fn number(n: &Number) -> String {
    let shown = n.shown();
    if n.shown_exactly() {
        if let Some((num, den)) = shown.split_once('/') {
            return match num.strip_prefix('-') {
                Some(positive) => format!("-\\frac{{{positive}}}{{{den}}}"),
                None => format!("\\frac{{{num}}}{{{den}}}"),
            };
        }
        return shown;
    }
    // An exact value shown as a decimal (a float input's shortest form, or `≈` ten digits worked out
    // from the exact value, which stays right beyond the float range).
    if let Some(text) = &n.exact_shown {
        return match text.strip_prefix('≈') {
            Some(rounded) => format!("\\approx {}", decimal_latex(rounded)),
            None => decimal_latex(text),
        };
    }
    float_latex(n.value, n)
}

/// `1.5e-12` as `1.5 \times 10^{-12}`; plain decimals unchanged.
fn decimal_latex(text: &str) -> String {
    match text.split_once('e') {
        Some((mantissa, exponent)) => format!("{mantissa} \\times 10^{{{exponent}}}"),
        None => text.to_string(),
    }
}

fn float_latex(value: f64, n: &Number) -> String {
    let text = format_float(value, n.precision);
    match text.as_str() {
        "∞" => "\\infty".into(),
        "−∞" => "-\\infty".into(),
        "NaN" => "\\mathrm{NaN}".into(),
        _ => match text.split_once('e') {
            Some((mantissa, exponent)) => format!("{mantissa} \\times 10^{{{exponent}}}"),
            None => text,
        },
    }
}

/// Wraps negatives in parentheses for products.
fn paren(n: &Number) -> String {
    let text = number(n);
    if text.starts_with('-') {
        format!("\\left({text}\\right)")
    } else {
        text
    }
}

fn column(entries: &[String]) -> String {
    format!(
        "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
        entries.join(" \\\\ ")
    )
}

fn grid(rows: &[Vec<Number>], env: &str, highlight: Option<usize>) -> String {
    let body: Vec<String> = rows
        .iter()
        .map(|row| {
            row.iter()
                .enumerate()
                .map(|(col, n)| match highlight {
                    Some(h) if h == col => format!("{{\\color{{teal}} {}}}", number(n)),
                    _ => number(n),
                })
                .collect::<Vec<_>>()
                .join(" & ")
        })
        .collect();
    format!("\\begin{{{env}}} {} \\end{{{env}}}", body.join(" \\\\ "))
}

fn bmatrix(matrix: &Matrix) -> String {
    grid(&matrix.rows, "bmatrix", matrix.replaced_column)
}

fn determinant(det: &Determinant) -> String {
    let signed = |i: usize, sign: i8, body: String| match (i, sign < 0) {
        (0, true) => format!("-{body}"),
        (0, false) => body,
        (_, true) => format!(" - {body}"),
        (_, false) => format!(" + {body}"),
    };
    let mut expansion = String::new();
    let mut products = String::new();
    for (i, term) in det.terms.iter().enumerate() {
        let minor = if term.minor.len() == 1 {
            paren(&term.minor[0][0])
        } else {
            grid(&term.minor, "vmatrix", None)
        };
        expansion.push_str(&signed(
            i,
            term.sign,
            format!("{} {minor}", paren(&term.element)),
        ));
        products.push_str(&signed(
            i,
            term.sign,
            format!("{} \\cdot {}", paren(&term.element), paren(&term.minor_det)),
        ));
    }
    // One line per stage, aligned at "=", so long float expansions fit on a slide.
    let mut out = format!("\\begin{{aligned}} |{}| &= {expansion}", det.latex_of);
    if det.terms.first().is_some_and(|t| t.minor.len() > 1) {
        let _ = write!(out, " \\\\ &= {products}");
    }
    let _ = write!(out, " \\\\ &= {} \\end{{aligned}}", number(&det.value));
    out
}

fn vector_latex(vector: &Vector) -> String {
    let parts: Vec<String> = vector.components.iter().map(number).collect();
    format!(
        "{} = \\left({}\\right)",
        vector.latex_name,
        parts.join(", ")
    )
}

fn scalar_latex(scalar: &Scalar) -> String {
    let mut out = format!("{} = ", scalar.latex);
    match &scalar.formula {
        Some(Formula::Quotient {
            numerator,
            denominator,
        }) => {
            let _ = write!(
                out,
                "\\frac{{{}}}{{{}}} = \\frac{{{}}}{{{}}} = ",
                numerator.latex,
                denominator.latex,
                number(&numerator.value),
                number(&denominator.value)
            );
        }
        Some(Formula::Expression { latex, .. }) => {
            let _ = write!(out, "{latex} = ");
        }
        None => {}
    }
    match &scalar.closed_form {
        Some(closed) => {
            let _ = write!(
                out,
                "{} \\approx {}",
                closed.latex,
                float_latex(scalar.value.value, &scalar.value)
            );
        }
        None => {
            out.push_str(&number(&scalar.value));
            if scalar.value.shown_exactly() && scalar.value.value.fract() != 0.0 {
                let _ = write!(
                    out,
                    " \\approx {}",
                    float_latex(scalar.value.value, &scalar.value)
                );
            }
        }
    }
    out
}

fn check_latex(check: &Check) -> String {
    let mark = if check.passed {
        "\\checkmark"
    } else {
        "\\times"
    };
    format!(
        "{} \\quad ({}) \\quad {mark}",
        check.latex,
        number(&check.value)
    )
}

/// Escapes text for `\text{}`: LaTeX specials, and the Unicode symbols raylab's messages use.
fn escape_text(text: &str) -> String {
    let mut out = String::new();
    for ch in text.chars() {
        match ch {
            '\\' => out.push_str("\\textbackslash{}"),
            '&' | '%' | '$' | '#' | '_' | '{' | '}' => {
                out.push('\\');
                out.push(ch);
            }
            '~' => out.push_str("\\textasciitilde{}"),
            '^' => out.push_str("\\textasciicircum{}"),
            'β' => out.push_str("$\\beta$"),
            'γ' => out.push_str("$\\gamma$"),
            'α' => out.push_str("$\\alpha$"),
            '−' => out.push('-'),
            '≤' => out.push_str("$\\le$"),
            '≥' => out.push_str("$\\ge$"),
            '≈' => out.push_str("$\\approx$"),
            '·' => out.push_str("$\\cdot$"),
            '√' => out.push_str("$\\surd$"),
            '|' => out.push_str("$|$"),
            '<' => out.push_str("$<$"),
            '>' => out.push_str("$>$"),
            _ => out.push(ch),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::exact::Exact;

    #[test]
    fn exact_fractions_become_frac() {
        let n = Number::of(&"-17/22".parse::<Exact>().unwrap());
        assert_eq!(number(&n), "-\\frac{17}{22}");
        let f = Number::of(&1.5e-12f64);
        assert_eq!(number(&f), "1.5 \\times 10^{-12}");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(
            escape_text("β + γ ≤ 1 & 50%"),
            "$\\beta$ + $\\gamma$ $\\le$ 1 \\& 50\\%"
        );
    }
}
