//! Reading and checking a student's answer, with hints taken from the exact solver's trace.
//!
//! An answer is a named outcome (`hit`, `outside BC`, `outside edge CA`, `outside α=1`, `outside A`,
//! `behind`, `parallel`, `degenerate`), or the unknowns in the order the problem lists them
//! (`1/4, 1/2, 3`, or by name: `β = 1/4, γ = 1/2, t = 3`), or both separated by `;`. Numbers are read
//! by the exact parser: a fraction or an integer must be exactly right; a decimal (a number written with
//! a point or an exponent) may be off by at most [`DECIMAL_TOLERANCE`].

use super::{Kind, Outcome, Problem};
use crate::math::exact::Exact;
use crate::trace::{Formula, Payload, Step};

/// A decimal answer counts as right when it is within this of the exact value (absolute): `0.773` is
/// right for 17/22 = 0.77272…, `0.77` is not. Fractions and integers are checked exactly.
pub const DECIMAL_TOLERANCE: f64 = 1e-3;

/// A step of the solver's trace to look at again.
#[derive(Clone, Debug, PartialEq)]
pub struct Hint {
    /// The step's id in the trace (`beta`, `check_bc`, `det_M1` …).
    pub step_id: String,
    /// The step's title.
    pub title: String,
    /// What to do there: the step's explanation, and its formula when it has one.
    pub text: String,
}

/// What the checker says.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Right; `answer` is the exact answer, e.g. `hit; β = 1/4, γ = 1/2, t = 3`.
    Right {
        /// The exact answer.
        answer: String,
    },
    /// Wrong, with a hint: the first step whose value differs from what the answer implies, the next
    /// such step after a second wrong answer, and so on (the last one again once they run out).
    Wrong {
        /// Where to look.
        hint: Hint,
    },
    /// Not an answer; says what was expected.
    Unreadable {
        /// What could not be read (its message is one line).
        error: AnswerError,
    },
}

/// Why an answer could not be read; each message says what was expected instead.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AnswerError {
    /// Neither an outcome nor the right number of values.
    #[error(
        "expected {} (fractions or decimals) or an outcome: hit, outside {}, {}parallel, degenerate",
        .kind.unknowns().iter().map(|u| u.1).collect::<Vec<_>>().join(", "),
        .kind.edges().join("|"),
        if *.kind == Kind::Segments { "" } else { "behind, " }
    )]
    Expected {
        /// The problem's kind, which decides the unknowns and edges.
        kind: Kind,
    },
    /// Words after an outcome that takes none (`hit there`).
    #[error("'{text}': nothing may follow '{outcome}'")]
    TrailingWords {
        /// The part of the answer.
        text: String,
        /// The outcome word.
        outcome: String,
    },
    /// `outside` with no edge, or one the problem does not have.
    #[error(
        "outside which {}? expected one of {}",
        if *.kind == Kind::Parallelogram { "side" } else { "edge" },
        .kind.edges().join(", ")
    )]
    UnknownEdge {
        /// The problem's kind.
        kind: Kind,
    },
    /// `x = 1` where x names no unknown.
    #[error("'{0}' is not one of the unknowns")]
    UnknownName(String),
    /// A number that is not a fraction or decimal.
    #[error("{0}")]
    Number(#[from] crate::math::exact::ParseExactError),
    /// The same unknown named twice.
    #[error("{0} is given twice")]
    GivenTwice(&'static str),
    /// Fewer values than unknowns.
    #[error("a value is missing")]
    Missing,
}

/// One problem being practised. Each answer gets the hint of its own first wrong step; the same wrong
/// answer given again gets the next one.
#[derive(Clone, Debug)]
pub struct Practice {
    /// The problem.
    pub problem: Problem,
    /// Wrong answers so far.
    pub wrong_answers: usize,
    /// The last wrong answer (spaces removed, lower case) and how many times in a row it was given.
    last_wrong: Option<(String, usize)>,
}

impl Practice {
    /// Starts on a problem.
    pub fn new(problem: Problem) -> Practice {
        Practice {
            problem,
            wrong_answers: 0,
            last_wrong: None,
        }
    }

    /// Checks an answer: a changed answer gets the hint of its own first wrong step, a repeated one
    /// the next.
    pub fn check(&mut self, answer: &str) -> Verdict {
        let key: String = answer.split_whitespace().collect::<String>().to_lowercase();
        let repeats = match &self.last_wrong {
            Some((last, times)) if *last == key => *times,
            _ => 0,
        };
        let verdict = check(&self.problem, answer, repeats);
        match verdict {
            Verdict::Wrong { .. } => {
                self.wrong_answers += 1;
                self.last_wrong = Some((key, repeats + 1));
            }
            Verdict::Right { .. } => self.last_wrong = None,
            Verdict::Unreadable { .. } => {}
        }
        verdict
    }
}

/// Checks `answer` against the problem's exact answer. The hint is the first step of the trace whose
/// value differs from what this answer implies; `repeats` (how many times this same wrong answer was
/// given before) moves it on to the next such steps. A decimal that is close but outside
/// [`DECIMAL_TOLERANCE`] is told to round less.
#[allow(
    clippy::expect_used,
    reason = "every trace a solver records ends with its verdict"
)]
pub fn check(problem: &Problem, answer: &str, repeats: usize) -> Verdict {
    let claim = match read_claim(problem.kind(), answer) {
        Ok(claim) => claim,
        Err(error) => return Verdict::Unreadable { error },
    };
    if claim_is_right(problem, &claim) {
        return Verdict::Right {
            answer: problem.answer.text(),
        };
    }
    if let Some(hint) = round_less(problem, &claim) {
        return Verdict::Wrong { hint };
    }
    let differing: Vec<&Step> = problem
        .trace
        .steps
        .iter()
        .filter(|step| step_differs(problem, &claim, step))
        .collect();
    let step = differing
        .get(repeats.min(differing.len().saturating_sub(1)))
        .copied()
        .or_else(|| problem.trace.steps.iter().find(|s| s.id == "verdict"))
        .expect("every trace ends with a verdict");
    Verdict::Wrong {
        hint: hint(step, yours(problem.kind(), &claim, &step.id)),
    }
}

/// A decimal near an unknown's value but outside the tolerance (0.67 for 2/3): the student rounded
/// too far, and is told so rather than sent back to Cramer's rule.
fn round_less(problem: &Problem, claim: &Claim) -> Option<Hint> {
    let values = claim.values.as_ref()?;
    let near = Exact::from_int(1) / Exact::from_int(100);
    let (slot, claimed) = values.iter().enumerate().find(|(slot, claimed)| {
        problem.answer.values.get(*slot).is_some_and(|truth| {
            let off = (&claimed.value - &truth.value).abs();
            let scale = truth.value.abs().max(Exact::from_int(1));
            !claimed.matches(&truth.value) && !claimed.tolerance.is_zero() && off <= &near * &scale
        })
    })?;
    let (id, symbol, _) = problem.kind().unknowns()[slot];
    let step = problem.trace.step(id)?;
    Some(Hint {
        step_id: step.id.clone(),
        title: "Round less".into(),
        text: format!(
            "{} = {} is close, but a decimal must be within {DECIMAL_TOLERANCE} of {symbol}: give more \
             decimals, or the exact fraction.",
            symbol, claimed.written
        ),
    })
}

/// The student's own value at a step, when the answer gives one (`your t = 1/2`, or for a check
/// `your β + γ = 3/2`).
fn yours(kind: Kind, claim: &Claim, id: &str) -> Option<String> {
    let values = claim.values.as_ref()?;
    if let Some(claimed) = claimed_unknown(kind, values, id) {
        return Some(claimed.written);
    }
    claimed_check_value(kind, values, id).map(|claimed| claimed.value.display())
}

/// A number as the student wrote it: its exact value and how far off it may be.
#[derive(Clone, Debug, PartialEq)]
struct Claimed {
    value: Exact,
    tolerance: Exact,
    /// As the student wrote it.
    written: String,
}

impl Claimed {
    fn matches(&self, truth: &Exact) -> bool {
        (&self.value - truth).abs() <= self.tolerance
    }

    fn plus(&self, other: &Claimed) -> Claimed {
        Claimed {
            value: &self.value + &other.value,
            tolerance: &self.tolerance + &other.tolerance,
            written: format!("{} + {}", self.written, other.written),
        }
    }
}

/// What an answer says: an outcome, the unknowns (in [`Kind::unknowns`] order), or both.
#[derive(Clone, Debug, Default)]
struct Claim {
    outcome: Option<Outcome>,
    values: Option<Vec<Claimed>>,
}

/// Reads an outcome and the values, forgivingly: brackets are ignored, and values may be separated by
/// commas, semicolons or (when named) spaces: `(2/3, 1/3)`, `2/3; 1/3`, `t=2/3 s=1/3`.
fn read_claim(kind: Kind, text: &str) -> Result<Claim, AnswerError> {
    let mut claim = Claim::default();
    let text = text.replace(['(', ')', '[', ']', '{', '}'], " ");
    let mut items = Vec::new();
    for part in text.split(';').map(str::trim).filter(|p| !p.is_empty()) {
        if let Some(outcome) = read_outcome(kind, part)? {
            claim.outcome = Some(outcome);
        } else {
            items.extend(value_items(part));
        }
    }
    if !items.is_empty() {
        claim.values = Some(read_values(kind, &items)?);
    }
    if claim.outcome.is_none() && claim.values.is_none() {
        return Err(AnswerError::Expected { kind });
    }
    Ok(claim)
}

/// The values in one part of an answer: split at commas, and at spaces between named values
/// (`t = 2/3 s = 1/3` is two items).
fn value_items(part: &str) -> Vec<String> {
    let mut items = Vec::new();
    for item in part.split(',').map(str::trim).filter(|i| !i.is_empty()) {
        let mut joined = item.to_string();
        while joined.contains(" =") || joined.contains("= ") {
            joined = joined.replace(" =", "=").replace("= ", "=");
        }
        items.extend(joined.split_whitespace().map(str::to_string));
    }
    items
}

/// An outcome word, with the edge for `outside`; `None` if the text is not an outcome at all.
fn read_outcome(kind: Kind, text: &str) -> Result<Option<Outcome>, AnswerError> {
    let lower = text.to_lowercase();
    let mut words = lower.split_whitespace();
    let first = words.next().unwrap_or_default();
    let rest: String = words
        .filter(|w| *w != "edge" && *w != "side" && *w != "segment")
        .collect();
    let outcome = match first {
        "hit" | "cross" | "crossing" => Outcome::Hit,
        "behind" => Outcome::Behind,
        "parallel" => Outcome::Parallel,
        "degenerate" => Outcome::Degenerate,
        "outside" => Outcome::Outside {
            beyond: read_edge(kind, &rest)?,
        },
        _ => return Ok(None),
    };
    if first != "outside" && !rest.is_empty() {
        return Err(AnswerError::TrailingWords {
            text: text.to_string(),
            outcome: first.to_string(),
        });
    }
    Ok(Some(outcome))
}

fn read_edge(kind: Kind, text: &str) -> Result<String, AnswerError> {
    let normal = text
        .replace("alpha", "α")
        .replace("beta", "β")
        .to_uppercase()
        .replace('Α', "α")
        .replace('Β', "β");
    let reversed: String = normal.chars().rev().collect();
    kind.edges()
        .iter()
        .find(|edge| {
            let edge = edge.to_uppercase().replace('Α', "α").replace('Β', "β");
            // A triangle's edge may be named either way round: AB or BA.
            edge == normal || (kind == Kind::Triangle && edge == reversed)
        })
        .map(|edge| edge.to_string())
        .ok_or(AnswerError::UnknownEdge { kind })
}

/// `1/4, 1/2, 3` or `β = 1/4, γ = 1/2, t = 3` (names as symbols or words: `beta`).
#[allow(clippy::expect_used, reason = "the tolerance is a finite constant")]
fn read_values(kind: Kind, items: &[String]) -> Result<Vec<Claimed>, AnswerError> {
    let unknowns = kind.unknowns();
    let mut values: Vec<Option<Claimed>> = vec![None; unknowns.len()];
    if items.len() != unknowns.len() {
        return Err(AnswerError::Expected { kind });
    }
    for (position, item) in items.iter().enumerate() {
        let (slot, number) = match item.split_once('=') {
            Some((name, number)) => {
                let name = name.trim().to_lowercase();
                let slot = unknowns
                    .iter()
                    .position(|(id, symbol, _)| name == *id || name == *symbol)
                    .ok_or_else(|| AnswerError::UnknownName(name.clone()))?;
                (slot, number.trim())
            }
            None => (position, item.as_str()),
        };
        let value: Exact = number.parse()?;
        let decimal = number.contains(['.', 'e', 'E']);
        let tolerance = if decimal {
            Exact::from_f64(DECIMAL_TOLERANCE).expect("finite")
        } else {
            Exact::from_int(0)
        };
        let written = number.to_string();
        if values[slot]
            .replace(Claimed {
                value,
                tolerance,
                written,
            })
            .is_some()
        {
            return Err(AnswerError::GivenTwice(unknowns[slot].1));
        }
    }
    values
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .ok_or(AnswerError::Missing)
}

fn claim_is_right(problem: &Problem, claim: &Claim) -> bool {
    let answer = &problem.answer;
    let outcome_right = claim.outcome.as_ref().is_none_or(|o| *o == answer.outcome);
    let values_right = claim.values.as_ref().is_none_or(|values| {
        !answer.values.is_empty()
            && values
                .iter()
                .zip(&answer.values)
                .all(|(claimed, truth)| claimed.matches(&truth.value))
    });
    outcome_right && values_right
}

/// The exact value of a recorded number, when the solve kept one.
fn exact_of(number: &crate::trace::Number) -> Option<Exact> {
    number.exact.as_deref()?.parse().ok()
}

fn step_differs(problem: &Problem, claim: &Claim, step: &Step) -> bool {
    let kind = problem.kind();
    match &step.payload {
        Payload::Scalar(scalar) => claim
            .values
            .as_ref()
            .and_then(|values| claimed_unknown(kind, values, &step.id))
            .zip(exact_of(&scalar.value))
            .is_some_and(|(claimed, truth)| !claimed.matches(&truth)),
        Payload::Check(check) => {
            let by_outcome = claim
                .outcome
                .as_ref()
                .and_then(|o| passes_if(kind, o, &step.id))
                .is_some_and(|passes| passes != check.passed);
            let by_values = claim.values.as_ref().is_some_and(|values| {
                match claimed_check_value(kind, values, &step.id) {
                    Some(claimed) => {
                        exact_of(&check.value).is_some_and(|truth| !claimed.matches(&truth))
                    }
                    // Numbers for every unknown say that the system has one solution.
                    None => is_solvability_check(&step.id) && !check.passed,
                }
            });
            by_outcome || by_values
        }
        Payload::Verdict(_) => claim
            .outcome
            .as_ref()
            .is_some_and(|o| *o != problem.answer.outcome),
        _ => false,
    }
}

fn is_solvability_check(id: &str) -> bool {
    matches!(id, "check_area" | "check_lengths" | "check_det")
}

fn claimed_unknown(kind: Kind, values: &[Claimed], id: &str) -> Option<Claimed> {
    let slot = kind.unknowns().iter().position(|u| u.0 == id)?;
    values.get(slot).cloned()
}

/// The value a check tests, as the student's numbers would make it (β + γ for check_bc …).
fn claimed_check_value(kind: Kind, values: &[Claimed], id: &str) -> Option<Claimed> {
    let unknown = |name: &str| claimed_unknown(kind, values, name);
    match (kind, id) {
        (Kind::Triangle, "check_ca") => unknown("beta"),
        (Kind::Triangle, "check_ab") => unknown("gamma"),
        (Kind::Triangle, "check_bc") => Some(unknown("beta")?.plus(&unknown("gamma")?)),
        (Kind::Parallelogram, "check_alpha") => unknown("alpha"),
        (Kind::Parallelogram, "check_beta") => unknown("beta"),
        (Kind::Segments, "check_s") => unknown("s"),
        (_, "check_t") => unknown("t"),
        _ => None,
    }
}

/// The check a miss beyond `edge` fails.
fn edge_check(kind: Kind, edge: &str) -> String {
    match kind {
        Kind::Segments => if edge == "A" { "check_t" } else { "check_s" }.into(),
        Kind::Triangle => format!("check_{}", edge.to_lowercase()),
        Kind::Parallelogram => if edge.starts_with('α') {
            "check_alpha"
        } else {
            "check_beta"
        }
        .into(),
    }
}

/// Whether a check passes if the outcome were `outcome`; `None` where the outcome does not say.
fn passes_if(kind: Kind, outcome: &Outcome, id: &str) -> Option<bool> {
    let solvable = !matches!(outcome, Outcome::Parallel | Outcome::Degenerate);
    let is_edge_check = (0..kind.edges().len()).any(|i| edge_check(kind, kind.edges()[i]) == id);
    match id {
        "check_area" | "check_lengths" => Some(*outcome != Outcome::Degenerate),
        "check_det" => (*outcome != Outcome::Degenerate).then_some(solvable),
        _ if is_edge_check => match outcome {
            Outcome::Outside { beyond } => Some(edge_check(kind, beyond) != id),
            Outcome::Hit | Outcome::Behind => Some(true),
            _ => None,
        },
        "check_t" => match outcome {
            Outcome::Hit => Some(true),
            Outcome::Behind => Some(false),
            _ => None,
        },
        _ => None,
    }
}

/// The hint at `step`: what to do there, its formula with the step's own numbers, and the student's
/// value beside them when the answer gives one.
fn hint(step: &Step, yours: Option<String>) -> Hint {
    let formula = match &step.payload {
        Payload::Scalar(scalar) => match &scalar.formula {
            Some(Formula::Quotient {
                numerator,
                denominator,
            }) => Some(format!(
                "{} = {} / {}, with {} = {} and {} = {}",
                scalar.symbol,
                numerator.symbol,
                denominator.symbol,
                numerator.symbol,
                numerator.value.shown(),
                denominator.symbol,
                denominator.value.shown()
            )),
            Some(Formula::Expression { text, .. }) => Some(format!("{} = {text}", scalar.symbol)),
            None => None,
        },
        Payload::Check(check) => Some(format!("check {}", check.inequality)),
        _ => None,
    };
    let mut text = match formula {
        Some(formula) => format!("{} ({formula})", step.explanation),
        None => step.explanation.clone(),
    };
    if let Some(yours) = yours {
        // What the value is called: the unknown, or the left side of the check (β + γ).
        let name = match &step.payload {
            Payload::Scalar(scalar) => Some(scalar.symbol.clone()),
            Payload::Check(check) => check
                .inequality
                .rsplit_once(['≥', '≤', '>', '<'])
                .and_then(|(left, _)| left.rsplit(['≥', '≤', '>', '<']).next())
                .map(|left| left.trim().to_string()),
            _ => None,
        };
        let name = name.map(|n| format!("{n} = ")).unwrap_or_default();
        text.push_str(&format!(" Your answer gives {name}{yours}."));
    }
    Hint {
        step_id: step.id.clone(),
        title: step.title.clone(),
        text,
    }
}
