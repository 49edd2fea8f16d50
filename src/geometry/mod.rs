//! Pure geometry: the lecture's solvers, generic over the precision they run in. Never imports egui.

pub mod parallelogram;
pub mod segments;
pub mod triangle;

pub use crate::math::{Precision, Real};

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

/// How float inputs become solver numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Reading {
    /// The float's own value (exact for [`crate::math::exact::Exact`]: 0.1 is 3602879701896397/2^55).
    #[default]
    FloatValue,
    /// The shortest decimal that prints as the float (0.1 is 1/10), as a person typed or dragged it.
    AsWritten,
}

/// Converts one float input, naming it if it cannot be represented (only exact numbers refuse NaN).
pub(crate) fn read<R: Real>(reading: Reading, name: &str, x: f64) -> Result<R, InvalidInput> {
    let value = match reading {
        Reading::FloatValue => R::from_f64(x),
        Reading::AsWritten => R::from_f64_as_written(x),
    };
    value.ok_or_else(|| InvalidInput {
        field: name.into(),
        problem: "is not a finite number".into(),
    })
}

/// Converts a float vector input.
pub(crate) fn read_vec<R: Real, const N: usize>(
    reading: Reading,
    name: &str,
    v: [f64; N],
) -> Result<[R; N], InvalidInput> {
    let parts: Vec<R> = v
        .iter()
        .map(|x| read(reading, name, *x))
        .collect::<Result<_, _>>()?;
    Ok(parts
        .try_into()
        .unwrap_or_else(|_| unreachable!("N parts in, N out")))
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
