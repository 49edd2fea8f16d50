//! Reading numbers and vectors from the command line and from batch JSON, with errors that name the
//! problem in one line.
//!
//! A number is read twice: as the nearest `f64` for the float solvers, and exactly as written for the
//! exact solver, so `0.1` is the float 0.1 in f64 runs and the fraction 1/10 in exact runs.

use glam::{DVec2, DVec3};

use crate::geometry::{Precision, Real};
use crate::math::exact::Exact;

/// The longest number text read, in characters, in every precision: a longer one is refused before any
/// work is done on it (a decimal of a million digits would otherwise take minutes to convert).
pub const MAX_NUMBER_CHARS: usize = 10_000;

pub use crate::math::exact::quoted;

/// Why a number or a vector the user wrote cannot be read; each message is one line for people.
/// Texts are held as [`quoted`] shows them.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum InputError {
    /// Longer than [`MAX_NUMBER_CHARS`].
    #[error("a number of {0} characters is longer than the limit of {MAX_NUMBER_CHARS}")]
    TooLong(usize),
    /// NaN.
    #[error("NaN is not allowed: coordinates must be finite numbers")]
    NaN,
    /// An infinity, as written.
    #[error("{0} is not allowed: coordinates must be finite numbers")]
    Infinite(String),
    /// Not a number at all (or a zero denominator, or a huge exponent).
    #[error(transparent)]
    Number(#[from] crate::math::exact::ParseExactError),
    /// A number past the range of a float precision.
    #[error("{text} is too large for {}; exact precision reads it", float_name(*.precision))]
    TooLarge {
        /// The number as written.
        text: String,
        /// The float precision that cannot hold it.
        precision: Precision,
    },
    /// A nonzero number that a float precision would round to 0.
    #[error("{text} is too small for {}: it would become 0; exact precision reads it", float_name(*.precision))]
    TooSmall {
        /// The number as written.
        text: String,
        /// The float precision that cannot hold it.
        precision: Precision,
    },
    /// A vector with the wrong number of components.
    #[error(
        "expected {expected} numbers separated by commas ({}), got {got}",
        if *.expected == 2 { "x,y" } else { "x,y,z" }
    )]
    Count {
        /// 2 or 3.
        expected: usize,
        /// How many parts there were.
        got: usize,
    },
    /// A batch value that is a JSON string with a bad escape.
    #[error("not a valid string")]
    BadString,
    /// A batch number given as null.
    #[error("null is not a number")]
    Null,
    /// A batch vector that is neither a string nor an array.
    #[error("expected a string \"x,y,…\" or an array of numbers")]
    NotAVector,
    /// A batch vector's JSON that does not parse (serde_json's message).
    #[error("not valid JSON: {0}")]
    Json(String),
    /// A vector's component (counted from 1) that cannot be read.
    #[error("component {index}: {error}")]
    Component {
        /// From 1.
        index: usize,
        /// Why.
        error: Box<InputError>,
    },
}

impl InputError {
    /// The same refusal, said of component `index` (from 0) of a vector.
    pub fn in_component(self, index: usize) -> InputError {
        InputError::Component {
            index: index + 1,
            error: Box::new(self),
        }
    }
}

fn float_name(precision: Precision) -> &'static str {
    match precision {
        Precision::F32 => "a 32-bit float",
        _ => "a 64-bit float",
    }
}

/// Refuses NaN, the infinities and texts past [`MAX_NUMBER_CHARS`], with a message for people.
fn refuse_non_numbers(trimmed: &str) -> Result<(), InputError> {
    if trimmed.len() > MAX_NUMBER_CHARS {
        let count = trimmed.chars().count();
        if count > MAX_NUMBER_CHARS {
            return Err(InputError::TooLong(count));
        }
    }
    let bare = trimmed.trim_start_matches(['+', '-']);
    if bare.eq_ignore_ascii_case("nan") {
        return Err(InputError::NaN);
    }
    if bare.eq_ignore_ascii_case("inf") || bare.eq_ignore_ascii_case("infinity") || bare == "∞" {
        return Err(InputError::Infinite(quoted(trimmed)));
    }
    Ok(())
}

/// Reads an exact number (integer, decimal or fraction) of at most [`MAX_NUMBER_CHARS`] characters.
pub fn read_exact(text: &str) -> Result<Exact, InputError> {
    let trimmed = text.trim();
    refuse_non_numbers(trimmed)?;
    Ok(trimmed.parse()?)
}

/// The refusal of a number that a float precision cannot hold.
/// True if a decimal's digits before its exponent are not all zero (its value is not 0).
fn nonzero_mantissa(text: &str) -> bool {
    let mantissa = text.split(['e', 'E']).next().unwrap_or_default();
    mantissa.bytes().any(|b| (b'1'..=b'9').contains(&b))
}

fn too_small(quoted_text: &str, precision: Precision) -> InputError {
    InputError::TooSmall {
        text: quoted_text.to_string(),
        precision,
    }
}

fn too_large(quoted_text: &str, precision: Precision) -> InputError {
    InputError::TooLarge {
        text: quoted_text.to_string(),
        precision,
    }
}

/// Reads number text straight into a solver's precision: floats without building an exact value
/// (the batch's hot path), exact numbers exactly. A float precision refuses a number it cannot hold.
pub trait ReadNumber: Real {
    /// The nearest value of `text` in this precision, or why there is none.
    fn read(text: &str) -> Result<Self, InputError>;
}

/// `-12.5`, `3`, `+.5`: at most 24 bytes of digits with an optional leading sign and one point, and
/// at least one digit (no exponent, so no float can overflow or underflow it).
fn is_plain_decimal(text: &str) -> bool {
    plain_decimal(text).is_some()
}

/// A plain decimal (see [`is_plain_decimal`]) as its digits read as an integer `m` and the count `k`
/// of digits after the point (the value is ±m / 10^k), when it has at most 15 digits; `None` for
/// any other text, and `Some((negative, None, 0))` for a plain decimal with more digits.
fn plain_decimal(text: &str) -> Option<(bool, Option<u64>, u32)> {
    let bytes = text.as_bytes();
    if bytes.len() > 24 {
        return None;
    }
    let (negative, digits) = match bytes.first()? {
        b'-' => (true, &bytes[1..]),
        b'+' => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let (mut mantissa, mut count, mut decimals, mut point) = (0u64, 0, 0, false);
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
                count += 1;
                decimals += u32::from(point);
            }
            b'.' if !point => point = true,
            _ => return None,
        }
    }
    match count {
        0 => None,
        1..=15 => Some((negative, Some(mantissa), decimals)),
        _ => Some((negative, None, 0)),
    }
}

/// The nearest f64 to a short plain decimal, computed directly: ±m / 10^k with m < 10^15 < 2^53 and
/// k ≤ 15 is one division of two floats that hold their values exactly, so it is rounded once, as
/// the full parser rounds (the classic fast path of decimal-to-float conversion).
fn short_decimal_f64(text: &str) -> Option<f64> {
    const POWERS: [f64; 16] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
    ];
    let (negative, Some(mantissa), decimals) = plain_decimal(text)? else {
        return None;
    };
    let value = mantissa as f64 / POWERS[decimals as usize];
    Some(if negative { -value } else { value })
}

macro_rules! read_float {
    ($t:ty, $short:expr) => {
        impl ReadNumber for $t {
            fn read(text: &str) -> Result<$t, InputError> {
                let trimmed = text.trim();
                if let Some(value) = $short(trimmed) {
                    return Ok(value);
                }
                // The common case first (batch lines hold millions): a short plain decimal, digits
                // with at most a sign and a point, is exactly what the float parser and the exact
                // reader agree on, so the full checks below are not needed.
                if is_plain_decimal(trimmed)
                    && let Ok(value) = trimmed.parse::<$t>()
                    && (value != 0.0 || !nonzero_mantissa(trimmed))
                {
                    return Ok(value);
                }
                refuse_non_numbers(trimmed)?;
                let (value, nonzero) = if trimmed.contains('/') {
                    // A fraction: rounded once, from its exact value.
                    let exact = read_exact(trimmed)?;
                    (<$t>::from_exact(&exact), !exact.is_zero())
                } else {
                    crate::math::exact::check_decimal(trimmed)?;
                    let value = trimmed.parse::<$t>().map_err(|_| {
                        crate::math::exact::ParseExactError::NotANumber(quoted(trimmed))
                    })?;
                    (value, nonzero_mantissa(trimmed))
                };
                if !value.is_finite() {
                    Err(too_large(&quoted(trimmed), <$t>::PRECISION))
                } else if value == 0.0 && nonzero {
                    Err(too_small(&quoted(trimmed), <$t>::PRECISION))
                } else {
                    Ok(value)
                }
            }
        }
    };
}

read_float!(f32, |_| None);
read_float!(f64, short_decimal_f64);

impl ReadNumber for Exact {
    fn read(text: &str) -> Result<Exact, InputError> {
        read_exact(text)
    }
}

/// A number as the user wrote it.
#[derive(Clone, Debug, PartialEq)]
pub struct Literal {
    /// The nearest f64 (±inf past the f64 range: only exact precision can use such a number).
    pub value: f64,
    /// The exact value of the text.
    pub exact: Exact,
    /// The text, as an error message quotes it.
    pub quoted: String,
}

impl Literal {
    /// Reads one number: `3`, `-2.5`, `1e-3`, `17/22`, of any size up to [`MAX_NUMBER_CHARS`]
    /// characters. NaN and infinities are refused; a float precision refuses a number past its range
    /// later ([`Literal::fits`]).
    pub fn parse(text: &str) -> Result<Literal, InputError> {
        let exact = read_exact(text)?;
        Ok(Literal {
            value: exact.to_f64(),
            quoted: quoted(text.trim()),
            exact,
        })
    }

    /// Ok if `precision` can hold the number (exact holds any), else the refusal.
    pub fn fits(&self, precision: Precision) -> Result<(), InputError> {
        let rounded = match precision {
            Precision::Exact => return Ok(()),
            Precision::F64 => self.value,
            Precision::F32 => f64::from(f32::from_exact(&self.exact)),
        };
        if !rounded.is_finite() {
            Err(too_large(&self.quoted, precision))
        } else if rounded == 0.0 && !self.exact.is_zero() {
            // 1e-400 in f64, 1e-50 in f32: refused as overflow is, not silently 0.
            Err(too_small(&self.quoted, precision))
        } else {
            Ok(())
        }
    }
}

/// A vector of N numbers as the user wrote them.
#[derive(Clone, Debug, PartialEq)]
pub struct Coords<const N: usize>(pub [Literal; N]);

impl<const N: usize> Coords<N> {
    /// Reads `x,y` (N = 2) or `x,y,z` (N = 3).
    pub fn parse(text: &str) -> Result<Coords<N>, InputError> {
        let parts: Vec<&str> = text.split(',').collect();
        Coords::from_parts(&parts)
    }

    /// Reads N separate number texts.
    pub fn from_parts(parts: &[&str]) -> Result<Coords<N>, InputError> {
        let count = InputError::Count {
            expected: N,
            got: parts.len(),
        };
        if parts.len() != N {
            return Err(count);
        }
        let mut literals = Vec::with_capacity(N);
        for (i, part) in parts.iter().enumerate() {
            literals.push(Literal::parse(part).map_err(|e| e.in_component(i))?);
        }
        let literals: [Literal; N] = literals.try_into().map_err(|_| count)?;
        Ok(Coords(literals))
    }

    /// Ok if `precision` can hold every component, else the refusal naming the component.
    pub fn fits(&self, precision: Precision) -> Result<(), InputError> {
        for (i, literal) in self.0.iter().enumerate() {
            literal.fits(precision).map_err(|e| e.in_component(i))?;
        }
        Ok(())
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

#[cfg(test)]
mod underflow {
    use super::{InputError, Literal, ReadNumber};
    use crate::geometry::Precision;

    #[test]
    fn a_nonzero_number_a_float_would_round_to_zero_is_refused_like_one_too_large() {
        let small = |text: &str, precision| {
            Literal::parse(text)
                .unwrap()
                .fits(precision)
                .unwrap_err()
                .to_string()
        };
        assert!(small("1e-400", Precision::F64).contains("too small for"));
        assert!(small("1e-50", Precision::F32).contains("it would become 0"));
        assert!(small("1/1e400", Precision::F64).contains("too small"));
        assert_eq!(
            Literal::parse("1e-400").unwrap().fits(Precision::Exact),
            Ok(())
        );
        assert_eq!(
            Literal::parse("0e-400").unwrap().fits(Precision::F64),
            Ok(())
        );
        // The batch's readers refuse it too, on every path (plain decimal, exponent, fraction).
        let plain = format!("0.{}1", "0".repeat(400));
        for text in [plain.as_str(), "1e-400", "1/1e400", "-2.5e-330"] {
            assert!(
                matches!(
                    <f64 as ReadNumber>::read(text),
                    Err(InputError::TooSmall { .. })
                ),
                "{text}"
            );
        }
        assert!(matches!(
            <f32 as ReadNumber>::read("1e-50"),
            Err(InputError::TooSmall { .. })
        ));
        // Subnormals are not 0: read as they are; and a written zero stays zero.
        assert!(<f64 as ReadNumber>::read("1e-310").is_ok_and(|v| v > 0.0));
        assert_eq!(<f64 as ReadNumber>::read("0.000"), Ok(0.0));
        assert_eq!(<f64 as ReadNumber>::read("-0e-999"), Ok(-0.0));
    }
}

/// clap value parser for `x,y`.
pub fn parse_coords2(text: &str) -> Result<Coords<2>, InputError> {
    Coords::parse(text)
}

/// clap value parser for `x,y,z`.
pub fn parse_coords3(text: &str) -> Result<Coords<3>, InputError> {
    Coords::parse(text)
}

/// clap value parser for one number.
pub fn parse_literal(text: &str) -> Result<Literal, InputError> {
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
        for bad in ["nan", "NaN", "-inf", "inf", "abc", "", "1/0"] {
            assert!(Literal::parse(bad).is_err(), "{bad:?}");
        }
        let huge = Literal::parse("1e400").unwrap();
        assert!(huge.fits(Precision::Exact).is_ok());
        assert_eq!(
            huge.fits(Precision::F64).unwrap_err().to_string(),
            "'1e400' is too large for a 64-bit float; exact precision reads it"
        );
        assert!(
            Literal::parse("1e39")
                .unwrap()
                .fits(Precision::F32)
                .is_err()
        );
        let err = Coords::<2>::parse("1,2,3").unwrap_err().to_string();
        assert_eq!(err, "expected 2 numbers separated by commas (x,y), got 3");
        let err = Coords::<3>::parse("1,x,3").unwrap_err().to_string();
        assert_eq!(err, "component 2: 'x' is not a number");
        assert!(
            Coords::<3>::parse("1,nan,3")
                .unwrap_err()
                .to_string()
                .contains("NaN")
        );
    }

    #[test]
    fn any_size_up_to_the_limit_and_short_refusals_past_it() {
        let digits = "7".repeat(5000);
        let big = Literal::parse(&digits).unwrap();
        assert_eq!(big.exact.fraction(), digits);
        let err = big.fits(Precision::F64).unwrap_err().to_string();
        assert!(err.len() < 120, "{err}");
        assert!(err.contains("(5000 characters)"), "{err}");
        let million = "1".repeat(1_000_000);
        let clock = std::time::Instant::now();
        for precision in [Precision::F32, Precision::F64, Precision::Exact] {
            let err = match precision {
                Precision::F32 => f32::read(&million).map(|_| ()),
                Precision::F64 => f64::read(&million).map(|_| ()),
                Precision::Exact => Exact::read(&million).map(|_| ()),
            }
            .unwrap_err()
            .to_string();
            assert!(err.contains("longer than the limit of 10000"), "{err}");
        }
        // The refusal is by length (the message says so), before any digit is read; the clock is only
        // a hang guard, generous enough for a loaded debug run (the speed is not this test's to judge).
        assert!(clock.elapsed().as_secs() < 10);
        assert!(f64::read(&"9".repeat(400)).unwrap_err().to_string().len() < 120);
        assert_eq!(f64::read("1.0000000000000000000001").unwrap(), 1.0);
        assert_eq!(
            Exact::read("1.0000000000000000000001").unwrap(),
            "10000000000000000000001/10000000000000000000000"
                .parse()
                .unwrap()
        );
    }

    #[test]
    fn floats_read_from_text_equal_the_rounded_exact_value() {
        for text in [
            "0.1",
            "-2.5e-3",
            "1/3",
            "123456789012345678901234567890",
            ".5",
        ] {
            // (1e-400, which both floats would round to 0, is refused: see the underflow tests.)
            let exact: Exact = text.parse().unwrap();
            assert_eq!(f64::read(text).unwrap(), exact.to_f64(), "{text}");
            assert_eq!(f32::read(text).unwrap(), f32::from_exact(&exact), "{text}");
        }
    }

    #[test]
    fn the_short_decimal_path_rounds_as_the_full_parser() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(15);
        let mut texts: Vec<String> = [
            "0",
            "-0",
            "+0.0",
            "5.",
            ".5",
            "-.5",
            "999999999999999",
            "0.000000000000001",
            "123456789.012345",
            "-9007199254740.991",
            "0.1",
            "0.3",
            "1234567890123456",
        ]
        .map(String::from)
        .to_vec();
        for _ in 0..20_000 {
            let digits = rng.random_range(1..=16);
            let mut text: String = (0..digits)
                .map(|_| char::from(b'0' + rng.random_range(0..10u8)))
                .collect();
            text.insert(rng.random_range(0..=digits), '.');
            if rng.random_bool(0.5) {
                text.insert(0, '-');
            }
            texts.push(text);
        }
        for text in &texts {
            let full: f64 = text.parse().unwrap();
            let read = f64::read(text).unwrap();
            assert_eq!(read.to_bits(), full.to_bits(), "{text}");
        }
    }
}
