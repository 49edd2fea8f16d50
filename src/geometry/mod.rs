//! Pure geometry: the lecture's solvers, generic over the precision they run in. Never imports egui.

pub mod linalg;
pub mod parallelogram;
pub mod real;
pub mod segments;
pub mod triangle;

pub use real::{Precision, Real};

/// A named input that is not a finite number (or does not fit the precision).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidInput {
    /// The input's name as the lecture writes it (`A`, `D`, `t_min`, …).
    pub field: String,
    /// What is wrong with it, in a few words.
    pub problem: String,
}

impl std::fmt::Display for InvalidInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.problem)
    }
}

/// Checks that every named input is finite in precision `R` (an f64 can overflow to ∞ in f32).
pub(crate) fn check_finite<R: Real, const N: usize>(
    fields: &[(&str, &[R; N])],
) -> Result<(), InvalidInput> {
    for (name, value) in fields {
        if let Some(bad) = value.iter().find(|x| !x.is_finite()) {
            let problem = if bad.to_f64().is_nan() {
                "is not a number (NaN)".to_string()
            } else {
                format!("is infinite in {} (too large?)", R::PRECISION.name())
            };
            return Err(InvalidInput {
                field: name.to_string(),
                problem,
            });
        }
    }
    Ok(())
}

/// True if a quantity counts as zero relative to the scale of the inputs it came from.
///
/// Exact arithmetic needs a true zero (`exactly_zero`). For floats, `magnitude ≤ TOLERANCE · scale`,
/// where `scale` bounds the magnitude the quantity could have had (e.g. `|u|·|v|` for `|u × v|`), so the
/// test is a dimensionless sine and does not change when every input is scaled by the same factor.
pub(crate) fn negligible<R: Real>(magnitude: f64, scale: f64, exactly_zero: bool) -> bool {
    if R::TOLERANCE == 0.0 {
        exactly_zero
    } else {
        exactly_zero || magnitude <= R::TOLERANCE * scale
    }
}
