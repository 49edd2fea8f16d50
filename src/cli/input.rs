//! Reading numbers and vectors from the command line and from batch JSON, with errors that name the
//! problem in one line.
//!
//! A number is read twice: as the nearest `f64` for the float solvers, and exactly as written for the
//! exact solver, so `0.1` is the float 0.1 in f64 runs and the fraction 1/10 in exact runs.

use glam::{DVec2, DVec3};

use crate::exact::Exact;

/// A number as the user wrote it.
#[derive(Clone, Debug, PartialEq)]
pub struct Literal {
    /// The nearest f64.
    pub value: f64,
    /// The exact value of the text.
    pub exact: Exact,
}

impl Literal {
    /// Reads one number: `3`, `-2.5`, `1e-3`, `17/22`. NaN, infinities and overflow are refused.
    pub fn parse(text: &str) -> Result<Literal, String> {
        let trimmed = text.trim();
        let lower = trimmed.to_ascii_lowercase();
        let bare = lower.trim_start_matches(['+', '-']);
        if bare == "nan" {
            return Err("NaN is not allowed: coordinates must be finite numbers".into());
        }
        if bare == "inf" || bare == "infinity" || bare == "∞" {
            return Err(format!(
                "'{trimmed}' is not allowed: coordinates must be finite numbers"
            ));
        }
        let exact: Exact = trimmed
            .parse()
            .map_err(|e: crate::exact::ParseExactError| e.0)?;
        let value = exact.to_f64();
        if !value.is_finite() {
            return Err(format!("'{trimmed}' is too large for a 64-bit float"));
        }
        Ok(Literal { value, exact })
    }
}

/// A vector of N numbers as the user wrote them.
#[derive(Clone, Debug, PartialEq)]
pub struct Coords<const N: usize>(pub [Literal; N]);

impl<const N: usize> Coords<N> {
    /// Reads `x,y` (N = 2) or `x,y,z` (N = 3).
    pub fn parse(text: &str) -> Result<Coords<N>, String> {
        let parts: Vec<&str> = text.split(',').collect();
        Coords::from_parts(&parts)
    }

    /// Reads N separate number texts.
    pub fn from_parts(parts: &[&str]) -> Result<Coords<N>, String> {
        if parts.len() != N {
            let form = if N == 2 { "x,y" } else { "x,y,z" };
            return Err(format!(
                "expected {N} numbers separated by commas ({form}), got {}",
                parts.len()
            ));
        }
        let mut literals = Vec::with_capacity(N);
        for (i, part) in parts.iter().enumerate() {
            literals.push(Literal::parse(part).map_err(|e| format!("component {}: {e}", i + 1))?);
        }
        Ok(Coords(literals.try_into().expect("length checked above")))
    }

    /// The exact values.
    pub fn exact(&self) -> [Exact; N] {
        std::array::from_fn(|i| self.0[i].exact.clone())
    }

    /// The f64 values.
    pub fn values(&self) -> [f64; N] {
        std::array::from_fn(|i| self.0[i].value)
    }
}

impl Coords<2> {
    /// As a glam vector.
    pub fn dvec2(&self) -> DVec2 {
        DVec2::from_array(self.values())
    }
}

impl Coords<3> {
    /// As a glam vector.
    pub fn dvec3(&self) -> DVec3 {
        DVec3::from_array(self.values())
    }
}

/// clap value parser for `x,y`.
pub fn parse_coords2(text: &str) -> Result<Coords<2>, String> {
    Coords::parse(text)
}

/// clap value parser for `x,y,z`.
pub fn parse_coords3(text: &str) -> Result<Coords<3>, String> {
    Coords::parse(text)
}

/// clap value parser for one number.
pub fn parse_literal(text: &str) -> Result<Literal, String> {
    Literal::parse(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_both_ways() {
        let tenth = Literal::parse("0.1").unwrap();
        assert_eq!(tenth.value, 0.1);
        assert_eq!(tenth.exact, Exact::ratio(1, 10).unwrap());
        let third = Literal::parse("1/3").unwrap();
        assert_eq!(third.value, 1.0 / 3.0);
    }

    #[test]
    fn refuses_non_finite_and_malformed() {
        for bad in ["nan", "NaN", "-inf", "inf", "1e400", "abc", "", "1/0"] {
            assert!(Literal::parse(bad).is_err(), "{bad:?}");
        }
        let err = Coords::<2>::parse("1,2,3").unwrap_err();
        assert_eq!(err, "expected 2 numbers separated by commas (x,y), got 3");
        let err = Coords::<3>::parse("1,x,3").unwrap_err();
        assert_eq!(err, "component 2: 'x' is not a number");
        assert!(Coords::<3>::parse("1,nan,3").unwrap_err().contains("NaN"));
    }
}
