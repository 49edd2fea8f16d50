//! A printable worksheet and its answer key (LaTeX for pdflatex: amsmath only), and the same problems
//! as JSON. Every number printed comes from the problem's exact answer or its exact trace.

use serde_json::{Value as Json, json};

use super::{Answer, Input, Kind, Problem};
use crate::math::exact::Exact;
use crate::trace::{Payload, latex_number};

const PREAMBLE: &str = "\\documentclass[11pt]{article}\n\\usepackage{amsmath}\n\
                        \\usepackage[T1]{fontenc}\n\\setlength{\\parindent}{0pt}\n\
                        \\setlength{\\parskip}{4pt}\n";

/// The worksheet: every problem, with room to work, and no answers.
pub fn worksheet_latex(seed: u64, problems: &[Problem]) -> String {
    let mut out = format!(
        "{PREAMBLE}\\begin{{document}}\n\\section*{{raylab worksheet (seed {seed})}}\n\
         Give every answer exactly as a fraction (such as $\\frac{{17}}{{22}}$), or as a decimal to \
         within ${DECIMAL}$. Then say what happens: a hit, outside (name the edge it is beyond), \
         behind the origin, parallel, or degenerate.\n\\begin{{enumerate}}\n",
        DECIMAL = "10^{-3}"
    );
    for problem in problems {
        out += &format!("\\item {}\n\n\\vspace{{5cm}}\n", statement(problem));
    }
    out + "\\end{enumerate}\n\\end{document}\n"
}

/// The answer key: each problem's outcome and exact unknowns, and the determinants on the way. Before
/// each answer a comment `% key N: outcome=… id=value …` holds it for programs.
pub fn key_latex(seed: u64, problems: &[Problem]) -> String {
    let mut out = format!(
        "{PREAMBLE}\\begin{{document}}\n\\section*{{raylab worksheet (seed {seed}): answer key}}\n\
         Every answer is exact, from raylab's exact solver.\n\\begin{{enumerate}}\n"
    );
    for problem in problems {
        out += &format!(
            "% key {}: {}\n",
            problem.number,
            key_comment(&problem.answer)
        );
        out += &format!(
            "\\item {}\n\n\\textbf{{Answer:}} {}\n\n{}\n",
            statement(problem),
            answer_latex(problem),
            determinants_latex(problem)
        );
    }
    out + "\\end{enumerate}\n\\end{document}\n"
}

/// The problems as JSON: seed, and per problem its kind, level, exact inputs (fractions as strings),
/// the `raylab solve` command that solves it, and the exact answer.
pub fn problems_json(seed: u64, problems: &[Problem]) -> Json {
    let list: Vec<Json> = problems.iter().map(problem_json).collect();
    json!({ "seed": seed, "problems": list })
}

fn problem_json(problem: &Problem) -> Json {
    let inputs: serde_json::Map<String, Json> = problem
        .inputs
        .named()
        .into_iter()
        .map(|input| {
            let parts: Vec<Json> = input.value.iter().map(|x| json!(x.fraction())).collect();
            (input.name.to_string(), Json::Array(parts))
        })
        .collect();
    let values: serde_json::Map<String, Json> = problem
        .answer
        .values
        .iter()
        .map(|v| (v.id.to_string(), json!(v.value.fraction())))
        .collect();
    let mut answer = json!({ "outcome": problem.answer.outcome.level().name() });
    if let super::Outcome::Outside { beyond } = &problem.answer.outcome {
        answer["beyond"] = json!(beyond);
    }
    answer["values"] = Json::Object(values);
    answer["text"] = json!(problem.answer.text());
    json!({
        "number": problem.number,
        "kind": problem.kind().name(),
        "level": problem.level().name(),
        "inputs": inputs,
        "command": solve_command(problem),
        "answer": answer,
    })
}

/// `raylab solve triangle --a 1,2,0 … --precision exact`.
fn solve_command(problem: &Problem) -> String {
    let mut command = format!("raylab solve {}", problem.kind().name());
    for input in problem.inputs.named() {
        let parts: Vec<String> = input.value.iter().map(Exact::fraction).collect();
        command += &format!(" --{} {}", input.flag, parts.join(","));
    }
    command + " --precision exact"
}

/// `outcome=outside:BC beta=1/4 gamma=3/4 t=2` (ASCII edge names: `alpha=1` for α=1).
fn key_comment(answer: &Answer) -> String {
    let outcome = match &answer.outcome {
        super::Outcome::Outside { beyond } => {
            format!(
                "outside:{}",
                beyond.replace('α', "alpha").replace('β', "beta")
            )
        }
        other => other.level().name().to_string(),
    };
    let values: Vec<String> = answer
        .values
        .iter()
        .map(|v| format!(" {}={}", v.id, v.value.fraction()))
        .collect();
    format!("outcome={outcome}{}", values.concat())
}

/// An exact number in LaTeX: `3`, `\frac{1}{4}`, `-\frac{3}{2}`.
fn exact_latex(x: &Exact) -> String {
    if x.is_integer() {
        return x.fraction();
    }
    let (numerator, denominator) = (x.0.numer(), x.0.denom());
    let sign = if numerator < &num_bigint::BigInt::from(0) {
        "-"
    } else {
        ""
    };
    format!("{sign}\\frac{{{}}}{{{denominator}}}", numerator.magnitude())
}

fn vector_latex(input: &Input) -> String {
    let parts: Vec<String> = input.value.iter().map(exact_latex).collect();
    format!("{} = ({})", input.latex, parts.join(", "))
}

/// The problem as the student reads it.
fn statement(problem: &Problem) -> String {
    let named = problem.inputs.named();
    let v = |i: usize| format!("${}$", vector_latex(&named[i]));
    match problem.kind() {
        Kind::Segments => format!(
            "\\textit{{Segments.}} Segment $A$ runs from {} to {}, segment $B$ from {} to {}. \
             Find $t$ and $s$ with $A_1 + t(A_2 - A_1) = B_1 + s(B_2 - B_1)$. Do the segments cross? \
             If not: outside $A$ or outside $B$ (which segment does not reach the crossing), parallel, \
             or degenerate?",
            v(0),
            v(1),
            v(2),
            v(3)
        ),
        Kind::Triangle => format!(
            "\\textit{{Triangle.}} The triangle {}, {}, {} and the ray $L + tD$ with {}, {}. \
             Solve $M X = Y$ with $M = [A - B \\mid A - C \\mid D]$, $X = (\\beta, \\gamma, t)$, \
             $Y = A - L$ by Cramer's rule. Does the ray hit ($t > 0$)? If not: outside which edge \
             ($AB$, $BC$, $CA$), behind, parallel, or degenerate?",
            v(0),
            v(1),
            v(2),
            v(3),
            v(4)
        ),
        Kind::Parallelogram => format!(
            "\\textit{{Parallelogram.}} The parallelogram $c + \\alpha e_1 + \\beta e_2$, \
             $0 \\le \\alpha, \\beta \\le 1$, with {}, {}, {}, and the ray $o + t d$ with {}, {}. \
             Find $\\alpha$, $\\beta$ and $t$. Does the ray hit ($t \\ge 0$)? If not: outside which \
             side ($\\alpha = 0$, $\\alpha = 1$, $\\beta = 0$, $\\beta = 1$), behind, parallel, or \
             degenerate?",
            v(0),
            v(1),
            v(2),
            v(3),
            v(4)
        ),
    }
}

fn answer_latex(problem: &Problem) -> String {
    let answer = &problem.answer;
    let outcome = match &answer.outcome {
        super::Outcome::Outside { beyond } => {
            let edge = beyond.replace('α', "\\alpha ").replace('β', "\\beta ");
            let what = match problem.kind() {
                Kind::Segments => "segment",
                Kind::Triangle => "edge",
                Kind::Parallelogram => "side",
            };
            format!("outside, beyond {what} ${edge}$")
        }
        other => other.level().name().to_string(),
    };
    let values: Vec<String> = answer
        .values
        .iter()
        .map(|v| format!("${} = {}$", v.latex, exact_latex(&v.value)))
        .collect();
    if values.is_empty() {
        let why = match answer.outcome {
            super::Outcome::Parallel => "$|M| = 0$, no single solution",
            _ => "no area, no single solution",
        };
        format!("{outcome} ({why}).")
    } else {
        format!("{outcome}; {}.", values.join(", "))
    }
}

/// The determinants the exact solve computed, as a check on the way: `|M| = 12, |M_1| = 3 …`.
fn determinants_latex(problem: &Problem) -> String {
    let parts: Vec<String> = problem
        .trace
        .steps
        .iter()
        .filter_map(|step| match &step.payload {
            Payload::Determinant(det) => Some(format!(
                "$|{}| = {}$",
                det.latex_of,
                latex_number(&det.value)
            )),
            _ => None,
        })
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("On the way: {}.\n", parts.join(", "))
    }
}
