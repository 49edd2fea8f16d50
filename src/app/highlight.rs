//! Linked highlighting: what each step of a solve is about, so the view can show it while the step is
//! on screen (presentation mode) or hovered (the step panel), and the step panel can mark the column
//! of a vector hovered in the view.
//!
//! Steps are looked up by their stable ids (`system`, `M1`, `det_M1`, `beta`, `check_bc`, `verdict`),
//! which the solvers document as the key for readers that look a step up.

pub use crate::trace::Column;

/// A parameter whose handle moves to its solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// β (triangle, parallelogram).
    Beta,
    /// γ (triangle).
    Gamma,
    /// α (parallelogram; for the triangle, 1 − β − γ).
    Alpha,
    /// t, along the ray or segment A.
    T,
    /// s, along segment B.
    S,
}

/// An edge of the triangle, as an inside check tests it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// Edge CA: the check β ≥ 0.
    Ca,
    /// Edge AB: the check γ ≥ 0.
    Ab,
    /// Edge BC: the check β + γ ≤ 1.
    Bc,
    /// The parallelogram's α bounds (its two edges along e2).
    AlphaBounds,
    /// The parallelogram's β bounds (its two edges along e1).
    BetaBounds,
    /// Segment A's ends (0 ≤ t ≤ 1).
    SegmentA,
    /// Segment B's ends (0 ≤ s ≤ 1).
    SegmentB,
}

/// One thing in the view a step is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Element {
    /// A column vector of M.
    Column(Column),
    /// The right-hand side Y (A − L, o − c, B1 − A1).
    Rhs,
    /// A parameter's handle at its solution.
    Parameter(Parameter),
    /// What an inside check tests.
    Side(Side),
    /// The ray's origin (the check on t).
    Origin,
    /// The solution point.
    Hit,
}

impl Element {
    /// What a person (or a screen reader) is told is highlighted, in a solve by `solver`.
    pub fn name(self, solver: &str) -> String {
        match self {
            Element::Column(column) => format!("column {}", column.label()),
            Element::Rhs => "right-hand side Y".into(),
            Element::Parameter(p) => format!(
                "{} at its solution",
                match p {
                    Parameter::Beta => "β",
                    Parameter::Gamma => "γ",
                    Parameter::Alpha => "α",
                    Parameter::T => "t",
                    Parameter::S => "s",
                }
            ),
            Element::Side(side) => match side {
                Side::Ca => "edge CA (β ≥ 0)".into(),
                Side::Ab => "edge AB (γ ≥ 0)".into(),
                Side::Bc => "edge BC (β + γ ≤ 1)".into(),
                Side::AlphaBounds => "the edges α = 0 and α = 1".into(),
                Side::BetaBounds => "the edges β = 0 and β = 1".into(),
                Side::SegmentA => "the ends of segment A".into(),
                Side::SegmentB => "the ends of segment B".into(),
            },
            Element::Origin => "the ray's origin".into(),
            // Not "the hit": on a miss it is still where the lines (or ray and plane) meet.
            Element::Hit if solver == "segments" => "where the lines cross".into(),
            Element::Hit => "where the ray meets the plane".into(),
        }
    }
}

/// What a step of a solver's trace is about. Unknown ids highlight nothing.
pub fn of_step(solver: &str, step_id: &str) -> Vec<Element> {
    use Column::*;
    use Element::{Column as C, Hit, Origin, Parameter as P, Rhs};
    let columns: &[Column] = match solver {
        "segments" => &[A2MinusA1, B1MinusB2],
        "parallelogram" => &[E1, E2, MinusD],
        _ => &[AMinusB, AMinusC, D],
    };
    let all_columns = || columns.iter().map(|c| C(*c)).collect::<Vec<_>>();
    // Cramer's Mi: Y in place of column i.
    let replaced = |i: usize| columns.get(i).map_or(vec![Rhs], |c| vec![Rhs, C(*c)]);
    match (solver, step_id) {
        (_, "system" | "M" | "det_M" | "check_det" | "adj_M" | "inverse") => all_columns(),
        (_, "Y") => vec![Rhs],
        (_, "product") => {
            let mut elements = all_columns();
            elements.push(Rhs);
            // Seed 001's product is X = (α, β, t): all three at once.
            if solver == "parallelogram" {
                elements.extend([P(Parameter::Alpha), P(Parameter::Beta), P(Parameter::T)]);
            }
            elements
        }
        ("segments", "check_lengths") => all_columns(),
        (_, "check_area") => columns.iter().take(2).map(|c| C(*c)).collect(),
        (_, "M1" | "det_M1") => replaced(0),
        (_, "M2" | "det_M2") => replaced(1),
        (_, "M3" | "det_M3") => replaced(2),
        // Seed 002's merges: |M| and |Mi| as triple products of the same columns.
        (_, "merge_M") => all_columns(),
        (_, "merge_M1") => replaced(0),
        (_, "merge_M2") => replaced(1),
        (_, "merge_M3") => replaced(2),
        (_, "beta") => vec![P(Parameter::Beta)],
        (_, "gamma") => vec![P(Parameter::Gamma)],
        (_, "alpha") => vec![P(Parameter::Alpha)],
        (_, "t") => vec![P(Parameter::T)],
        (_, "s") => vec![P(Parameter::S)],
        (_, "check_ca") => vec![Element::Side(Side::Ca)],
        (_, "check_ab") => vec![Element::Side(Side::Ab)],
        (_, "check_bc") => vec![Element::Side(Side::Bc)],
        ("parallelogram", "check_alpha") => vec![Element::Side(Side::AlphaBounds)],
        ("parallelogram", "check_beta") => vec![Element::Side(Side::BetaBounds)],
        ("segments", "check_t") => vec![Element::Side(Side::SegmentA)],
        ("segments", "check_s") => vec![Element::Side(Side::SegmentB)],
        (_, "check_t") => vec![Origin],
        (_, "verdict" | "point") => vec![Hit],
        (_, "distance") => vec![Origin, Hit],
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cramers_matrices_highlight_y_and_the_column_they_replace() {
        assert_eq!(
            of_step("triangle", "M1"),
            vec![Element::Rhs, Element::Column(Column::AMinusB)]
        );
        assert_eq!(
            of_step("triangle", "det_M3"),
            vec![Element::Rhs, Element::Column(Column::D)]
        );
        assert_eq!(
            of_step("segments", "M2"),
            vec![Element::Rhs, Element::Column(Column::B1MinusB2)]
        );
    }

    #[test]
    fn seed_002s_merges_highlight_the_columns_of_their_triple_products() {
        assert_eq!(of_step("triangle-symbolic", "merge_M").len(), 3);
        assert_eq!(
            of_step("triangle-symbolic", "merge_M2"),
            vec![Element::Rhs, Element::Column(Column::AMinusC)]
        );
        // Every merge step of the derivation highlights something.
        for step in crate::symbolic::trace(None).steps {
            if step.id.starts_with("merge_") {
                assert!(
                    !of_step("triangle-symbolic", &step.id).is_empty(),
                    "{}",
                    step.id
                );
            }
        }
    }

    #[test]
    fn every_step_of_the_lecture_triangle_highlights_something() {
        use crate::geometry::{Precision, Reading};
        let lecture =
            crate::scene::preset("seed000-triangle").expect("the lecture's triangle ships");
        let trace = lecture
            .problem
            .trace(Reading::AsWritten, Precision::Exact)
            .expect("a lecture problem");
        for step in &trace.steps {
            assert!(
                !of_step(&trace.solver, &step.id).is_empty(),
                "step {} highlights nothing",
                step.id
            );
        }
    }
}
