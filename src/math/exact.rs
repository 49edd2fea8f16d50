//! Exact rational arithmetic: the reference every floating-point result is judged by.
//!
//! Every finite `f64` is a rational number (an integer times a power of two), so a float input converts
//! to [`Exact`] without rounding, and the solvers run on it with no rounding at all. Decimal text such as
//! `0.1` or `17/22` can also be read exactly, as the number a person wrote.

use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::str::FromStr;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// Fractions whose denominator is at most this are printed as `n/d`.
const SMALL_DENOMINATOR: u64 = 1_000_000;
/// Fractions longer than this many characters are printed as a float with a note instead.
const LONGEST_FRACTION: usize = 24;

/// An exact rational number (a `BigRational` with the few conveniences raylab needs).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Exact(pub BigRational);

/// Why a piece of text is not an exact number. Each holds the text as [`quoted`] shows it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ParseExactError {
    /// Not `[+-]digits[.digits][e[+-]digits]` or a fraction of two such.
    #[error("{0} is not a number")]
    NotANumber(String),
    /// A fraction whose denominator is zero.
    #[error("{0} divides by zero")]
    DividesByZero(String),
    /// An exponent past ±[`MAX_EXPONENT`].
    #[error("{0} has an exponent past ±{MAX_EXPONENT}")]
    ExponentTooLarge(String),
}

impl Exact {
    /// The exact value of a finite float; `None` for NaN and the infinities, which are not numbers.
    pub fn from_f64(x: f64) -> Option<Exact> {
        BigRational::from_float(x).map(Exact)
    }

    /// An integer.
    pub fn from_int(n: i64) -> Exact {
        Exact(BigRational::from_integer(BigInt::from(n)))
    }

    /// The fraction `numerator / denominator`; `None` if the denominator is zero.
    pub fn ratio(numerator: i64, denominator: i64) -> Option<Exact> {
        (denominator != 0).then(|| {
            Exact(BigRational::new(
                BigInt::from(numerator),
                BigInt::from(denominator),
            ))
        })
    }

    /// The nearest `f64` (may be ±inf or 0 when the value is outside the float range).
    pub fn to_f64(&self) -> f64 {
        self.0.to_f64().unwrap_or_else(|| {
            // `to_f64` only fails on overflow of both parts; fall back to a quotient of logs.
            let sign = if self.0.is_negative() { -1.0 } else { 1.0 };
            let digits = self.0.numer().bits() as i64 - self.0.denom().bits() as i64;
            if digits > 0 {
                sign * f64::INFINITY
            } else {
                0.0
            }
        })
    }

    /// About how many decimal digits the reduced fraction has, numerator and denominator together.
    pub fn digits(&self) -> usize {
        let bits = self.0.numer().bits() + self.0.denom().bits();
        (bits as f64 * std::f64::consts::LOG10_2).ceil() as usize
    }

    /// True if the value is zero.
    pub fn is_zero(&self) -> bool {
        self.0.is_zero()
    }

    /// The absolute value.
    pub fn abs(&self) -> Exact {
        Exact(self.0.abs())
    }

    /// The quotient, or `None` when dividing by zero.
    pub fn checked_div(&self, other: &Exact) -> Option<Exact> {
        (!other.is_zero()).then(|| Exact(&self.0 / &other.0))
    }

    /// True if the denominator is 1.
    pub fn is_integer(&self) -> bool {
        self.0.is_integer()
    }

    /// The whole fraction, however long: `-17/22`, `3`.
    pub fn fraction(&self) -> String {
        if self.0.is_integer() {
            self.0.numer().to_string()
        } else {
            format!("{}/{}", self.0.numer(), self.0.denom())
        }
    }

    /// True if [`Exact::display`] shows the fraction itself (small denominator, short text).
    pub fn is_short(&self) -> bool {
        let small = self
            .0
            .denom()
            .to_u64()
            .is_some_and(|d| d <= SMALL_DENOMINATOR);
        small && self.fraction().len() <= LONGEST_FRACTION
    }

    /// For people: the fraction when it is short (`21/22`); the shortest decimal that reads back as the
    /// same float when the value is a float's (a float input such as −6.7, whose fraction has a
    /// denominator like 2⁵²); else `≈` and ten significant digits, worked out from the exact value so
    /// that values beyond the float range still read (`≈1e400`).
    pub fn display(&self) -> String {
        if self.is_short() {
            self.fraction()
        } else if let Some(float) = self.as_float() {
            shortest_decimal(float)
        } else {
            format!("≈{}", self.significant(10))
        }
    }

    /// The float whose exact value this is, if there is one.
    pub fn as_float(&self) -> Option<f64> {
        let float = self.to_f64();
        (float.is_finite() && Exact::from_f64(float).as_ref() == Some(self)).then_some(float)
    }

    /// The whole decimal expansion when it ends (the denominator is 2^a·5^b, as for every float):
    /// `-6.70000000000000017763568394002504646778106689453125`. `None` for 1/3 and the like.
    pub fn decimal_expansion(&self) -> Option<String> {
        let mut denominator = self.0.denom().clone();
        let (two, five) = (BigInt::from(2), BigInt::from(5));
        let (mut twos, mut fives) = (0usize, 0usize);
        while (&denominator % &two).is_zero() {
            denominator /= &two;
            twos += 1;
        }
        while (&denominator % &five).is_zero() {
            denominator /= &five;
            fives += 1;
        }
        if !denominator.is_one() {
            return None;
        }
        let places = twos.max(fives);
        let scaled =
            self.0.abs() * BigRational::from_integer(num_traits::pow(BigInt::from(10), places));
        let digits = scaled.to_integer().to_string();
        let sign = if self.0.is_negative() { "-" } else { "" };
        if places == 0 {
            return Some(format!("{sign}{digits}"));
        }
        let padded = format!("{digits:0>width$}", width = places + 1);
        let (whole, frac) = padded.split_at(padded.len() - places);
        Some(format!("{sign}{whole}.{frac}"))
    }

    /// The value rounded to `digits` significant digits, computed exactly (so 10^400 and 10^-400 read
    /// right where a float would say ∞ or 0): plain decimals for exponents −5…9, else `1.5e400`.
    pub fn significant(&self, digits: usize) -> String {
        if self.0.is_zero() {
            return "0".into();
        }
        let digits = digits.max(1);
        let magnitude = self.0.abs();
        let ten = BigRational::from_integer(BigInt::from(10));
        let power = |k: i64| -> BigRational {
            let p = num_traits::pow(ten.clone(), k.unsigned_abs() as usize);
            if k >= 0 { p } else { BigRational::one() / p }
        };
        // Estimate the decimal exponent from the bit lengths, then correct it by comparison.
        let bits = magnitude.numer().bits() as i64 - magnitude.denom().bits() as i64;
        let mut exponent = (bits as f64 * std::f64::consts::LOG10_2).floor() as i64;
        while magnitude < power(exponent) {
            exponent -= 1;
        }
        while magnitude >= power(exponent + 1) {
            exponent += 1;
        }
        let scale = digits as i64 - 1 - exponent;
        let mut mantissa = (&magnitude * power(scale)).round().to_integer();
        if mantissa >= num_traits::pow(BigInt::from(10), digits) {
            mantissa /= BigInt::from(10);
            exponent += 1;
        }
        let mantissa = mantissa.to_string();
        let sign = if self.0.is_negative() { "-" } else { "" };
        let text = if (-5..10).contains(&exponent) {
            let exp = exponent as usize;
            if exponent >= 0 && exp + 1 >= mantissa.len() {
                format!("{mantissa}{}", "0".repeat(exp + 1 - mantissa.len()))
            } else if exponent >= 0 {
                format!("{}.{}", &mantissa[..exp + 1], &mantissa[exp + 1..])
            } else {
                let zeros = "0".repeat((-exponent - 1) as usize);
                format!("0.{zeros}{mantissa}")
            }
        } else {
            let (first, rest) = mantissa.split_at(1);
            let rest = rest.trim_end_matches('0');
            let point = if rest.is_empty() { "" } else { "." };
            format!("{first}{point}{rest}e{exponent}")
        };
        let text = if text.contains('.') && !text.contains('e') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        };
        format!("{sign}{text}")
    }

    /// If this is the square of a rational, that rational (non-negative root); used to print √ exactly.
    pub fn exact_sqrt(&self) -> Option<Exact> {
        if self.0.is_negative() {
            return None;
        }
        let (n, d) = (self.0.numer(), self.0.denom());
        let (rn, rd) = (n.sqrt(), d.sqrt());
        (&rn * &rn == *n && &rd * &rd == *d).then(|| Exact(BigRational::new(rn, rd)))
    }
}

/// ±√q for an exact rational q ≥ 0: an exact value that is usually not rational (a length).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignedRoot {
    /// True for −√q.
    pub negative: bool,
    /// The radicand q.
    pub square: Exact,
}

impl SignedRoot {
    fn sign(&self) -> &'static str {
        if self.negative { "−" } else { "" }
    }

    /// The nearest float: ±√ of the square's nearest float, or, when that is out of the float range,
    /// of its value scaled by a power of four first (so √(10^800) is 10^400, not ∞).
    pub fn to_f64(&self) -> f64 {
        let sign = if self.negative { -1.0 } else { 1.0 };
        let square = self.square.to_f64();
        if square.is_finite() && (square != 0.0 || self.square.is_zero()) {
            return sign * square.sqrt();
        }
        // Out of range: take out 4^k (whose root is 2^k) until the rest is a normal float.
        let bits = self.square.0.numer().bits() as i64 - self.square.0.denom().bits() as i64;
        let k = bits / 2;
        let scale = Exact(BigRational::new(
            BigInt::one(),
            BigInt::one() << (2 * k.unsigned_abs()),
        ));
        let rest = if k >= 0 {
            &self.square * &scale
        } else {
            self.square.checked_div(&scale).unwrap_or_default()
        };
        sign * rest.to_f64().sqrt() * 2f64.powi(k as i32)
    }

    /// √q as a·√b / d with b free of small square factors (√(236/25) = 2√59/5, √(1/2) = √2/2), when
    /// q's numerator and denominator are small enough to search (`None` past 2^128).
    fn simplified(&self) -> Option<(BigInt, BigInt, BigInt)> {
        let (n, d) = (self.square.0.numer(), self.square.0.denom());
        // √(n/d) = √(n·d) / d.
        let mut rest = n * d;
        if rest.bits() > 128 || rest.is_zero() {
            return None;
        }
        let mut outside = BigInt::one();
        // Small primes' squares out of the radicand (composite p never divide what is left).
        for p in (2u32..10_002).map(BigInt::from) {
            let square = &p * &p;
            if square > rest {
                break;
            }
            while (&rest % &square).is_zero() {
                rest /= &square;
                outside *= &p;
            }
        }
        // Their greatest common divisor, by Euclid.
        let (mut x, mut y) = (outside.clone(), d.clone());
        while !y.is_zero() {
            (x, y) = (y.clone(), x % y);
        }
        let divisor = x;
        Some((&outside / &divisor, rest, d / &divisor))
    }

    /// The whole exact value, however long: `√3`, `2/3`, `√2/2`, `2√59/5`.
    pub fn full(&self) -> String {
        let body = match (self.square.exact_sqrt(), self.simplest()) {
            (Some(root), _) => root.fraction(),
            (None, Some((a, b, d))) => {
                let a = if a.is_one() {
                    String::new()
                } else {
                    a.to_string()
                };
                let d = if d.is_one() {
                    String::new()
                } else {
                    format!("/{d}")
                };
                format!("{a}√{b}{d}")
            }
            (None, None) => self.as_written(),
        };
        format!("{}{body}", self.sign())
    }

    /// √ of the square as it stands: `√3`, `√(1/2)`.
    fn as_written(&self) -> String {
        if self.square.is_integer() {
            format!("√{}", self.square.fraction())
        } else {
            format!("√({})", self.square.fraction())
        }
    }

    /// [`SignedRoot::simplified`] where it reads no longer than the root as it stands (a huge
    /// radicand with one small square in it reads better left alone).
    fn simplest(&self) -> Option<(BigInt, BigInt, BigInt)> {
        let (a, b, d) = self.simplified()?;
        // Without the √: the factor, the radicand, "/" and the divisor.
        let digits = |n: &BigInt| if n.is_one() { 0 } else { n.to_string().len() };
        let simplified = digits(&a) + b.to_string().len() + digits(&d) + usize::from(!d.is_one());
        (simplified < self.as_written().chars().count()).then_some((a, b, d))
    }

    /// For people: [`SignedRoot::full`] when short, else `None` (show the float instead).
    pub fn short(&self) -> Option<String> {
        let root = self.square.exact_sqrt();
        let short = match &root {
            Some(root) => root.is_short(),
            None => self.square.is_short(),
        };
        short.then(|| self.full())
    }

    /// For people: [`SignedRoot::short`] when there is one, else `≈` and ten significant digits
    /// worked out from the exact square, so that a root beyond the float range still reads
    /// (`≈1.414213562e400`, not ∞; `≈1e-400`, not 0).
    pub fn display(&self) -> String {
        self.short().unwrap_or_else(|| {
            let sign = if self.negative { "-" } else { "" };
            format!("≈{sign}{}", self.approximation().significant(10))
        })
    }

    /// A rational within about a part in 10^15 of √q: q = r·100^k with r near 1, so √q = √r·10^k,
    /// and √r is a float's square root.
    fn approximation(&self) -> Exact {
        let q = &self.square.0;
        if q.is_zero() {
            return Exact::from_int(0);
        }
        let bits = q.numer().bits() as i64 - q.denom().bits() as i64;
        let k = (bits as f64 * std::f64::consts::LOG10_2 / 2.0).floor() as i64;
        let ten_k = num_traits::pow(
            BigRational::from_integer(BigInt::from(10)),
            k.unsigned_abs() as usize,
        );
        let (r, scale) = if k >= 0 {
            (q / (&ten_k * &ten_k), ten_k)
        } else {
            (q * (&ten_k * &ten_k), BigRational::one() / ten_k)
        };
        let root_r = Exact::from_f64(Exact(r).to_f64().sqrt()).unwrap_or_default();
        Exact(root_r.0 * scale)
    }

    /// LaTeX for [`SignedRoot::short`]: `\sqrt{3}`, `\frac{2}{3}`, `\frac{\sqrt{2}}{2}`.
    pub fn short_latex(&self) -> Option<String> {
        self.short()?;
        let frac = |e: &Exact| {
            if e.is_integer() {
                e.fraction()
            } else {
                format!("\\frac{{{}}}{{{}}}", e.0.numer(), e.0.denom())
            }
        };
        let body = match (self.square.exact_sqrt(), self.simplest()) {
            (Some(root), _) => frac(&root),
            (None, Some((a, b, d))) => {
                let a = if a.is_one() {
                    String::new()
                } else {
                    a.to_string()
                };
                let top = format!("{a}\\sqrt{{{b}}}");
                if d.is_one() {
                    top
                } else {
                    format!("\\frac{{{top}}}{{{d}}}")
                }
            }
            (None, None) => format!("\\sqrt{{{}}}", frac(&self.square)),
        };
        Some(format!("{}{body}", if self.negative { "-" } else { "" }))
    }
}

/// The shortest decimal that reads back as `x`: `-6.7`, `0.1`, `1e-7`, `2.5e20`.
pub fn shortest_decimal(x: f64) -> String {
    let scientific = format!("{x:e}");
    let exponent: i32 = scientific
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    if (-5..15).contains(&exponent) {
        format!("{x}")
    } else {
        scientific
    }
}

/// Reads an exact number as written: an integer, a decimal (`-2.5`, `1e-3`, `.5`) or a fraction (`17/22`).
impl FromStr for Exact {
    type Err = ParseExactError;

    fn from_str(text: &str) -> Result<Exact, ParseExactError> {
        let text = text.trim();
        if let Some((num, den)) = text.split_once('/') {
            let num = parse_decimal(num.trim())?;
            let den = parse_decimal(den.trim())?;
            return num
                .checked_div(&den)
                .ok_or_else(|| ParseExactError::DividesByZero(quoted(text)));
        }
        parse_decimal(text)
    }
}

/// The largest decimal exponent read (`1e10000`), so that no text asks for an unbounded power of ten.
pub const MAX_EXPONENT: i64 = 10_000;

/// How much of a bad number an error message quotes.
const QUOTED_CHARS: usize = 32;

/// A number text for an error message: whole when short, else its start, its end and its length.
pub fn quoted(text: &str) -> String {
    let count = text.chars().count();
    if count <= QUOTED_CHARS {
        return format!("'{text}'");
    }
    let head: String = text.chars().take(QUOTED_CHARS - 8).collect();
    let tail: String = text.chars().skip(count - 6).collect();
    format!("'{head}…{tail}' ({count} characters)")
}

/// A decimal split into its parts: `[+-]whole[.frac][e[+-]exponent]`.
struct Decimal<'a> {
    negative: bool,
    whole: &'a str,
    frac: &'a str,
    exponent: i64,
}

/// Splits and checks `[+-]digits[.digits][e[+-]digits]`, with at least one digit and an exponent of at
/// most [`MAX_EXPONENT`] either way.
fn split_decimal(text: &str) -> Result<Decimal<'_>, ParseExactError> {
    let bad = || ParseExactError::NotANumber(quoted(text));
    let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(i) => {
            let written = &text[i + 1..];
            let unsigned = written.strip_prefix(['+', '-']).unwrap_or(written);
            if unsigned.is_empty() || !all_digits(unsigned) {
                return Err(bad());
            }
            let exponent = written.parse::<i64>().unwrap_or(i64::MAX);
            if exponent.unsigned_abs() > MAX_EXPONENT as u64 {
                return Err(ParseExactError::ExponentTooLarge(quoted(text)));
            }
            (&text[..i], exponent)
        }
        None => (text, 0),
    };
    let (negative, unsigned) = match mantissa.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, mantissa.strip_prefix('+').unwrap_or(mantissa)),
    };
    let (whole, frac) = unsigned.split_once('.').unwrap_or((unsigned, ""));
    if whole.is_empty() && frac.is_empty() || !all_digits(whole) || !all_digits(frac) {
        return Err(bad());
    }
    Ok(Decimal {
        negative,
        whole,
        frac,
        exponent,
    })
}

/// Checks that `text` is a decimal [`Exact`] would read, without computing its value.
pub fn check_decimal(text: &str) -> Result<(), ParseExactError> {
    split_decimal(text).map(|_| ())
}

/// Parses `[+-]digits[.digits][e[+-]digits]` exactly.
fn parse_decimal(text: &str) -> Result<Exact, ParseExactError> {
    let Decimal {
        negative,
        whole,
        frac,
        exponent,
    } = split_decimal(text)?;
    let digits: BigInt = if whole.is_empty() || frac.is_empty() {
        format!("{whole}{frac}").parse()
    } else {
        let mut both = String::with_capacity(whole.len() + frac.len());
        both.push_str(whole);
        both.push_str(frac);
        both.parse()
    }
    .map_err(|_| ParseExactError::NotANumber(quoted(text)))?;
    let scale = exponent - frac.len() as i64;
    let power = num_traits::pow(BigInt::from(10), scale.unsigned_abs() as usize);
    let value = if scale >= 0 {
        BigRational::from_integer(digits * power)
    } else {
        BigRational::new(digits, power)
    };
    Ok(Exact(if negative { -value } else { value }))
}

impl fmt::Display for Exact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.display())
    }
}

macro_rules! exact_binary_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Exact {
            type Output = Exact;
            fn $method(self, other: Exact) -> Exact {
                Exact(self.0 $op other.0)
            }
        }
        impl<'a> $trait<&'a Exact> for &'a Exact {
            type Output = Exact;
            fn $method(self, other: &'a Exact) -> Exact {
                Exact(&self.0 $op &other.0)
            }
        }
    };
}

exact_binary_op!(Add, add, +);
exact_binary_op!(Sub, sub, -);
exact_binary_op!(Mul, mul, *);

/// Division panics on a zero divisor, like integer division; solvers use [`Exact::checked_div`].
impl Div for Exact {
    type Output = Exact;
    fn div(self, other: Exact) -> Exact {
        Exact(self.0 / other.0)
    }
}

impl Neg for Exact {
    type Output = Exact;
    fn neg(self) -> Exact {
        Exact(-self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(text: &str) -> Exact {
        text.parse().unwrap()
    }

    #[test]
    fn floats_convert_without_rounding() {
        // 0.1 as a float is not 1/10: it is 3602879701896397 / 2^55.
        let tenth = Exact::from_f64(0.1).unwrap();
        assert_ne!(tenth, q("1/10"));
        assert_eq!(tenth.fraction(), "3602879701896397/36028797018963968");
        assert_eq!(tenth.to_f64(), 0.1);
        assert_eq!(Exact::from_f64(f64::NAN), None);
        assert_eq!(Exact::from_f64(f64::INFINITY), None);
        assert_eq!(Exact::from_f64(-2.5).unwrap(), q("-5/2"));
    }

    #[test]
    fn decimal_text_reads_exactly() {
        assert_eq!(q("0.1"), Exact::ratio(1, 10).unwrap());
        assert_eq!(q("-2.5e2"), Exact::from_int(-250));
        assert_eq!(q(".5"), q("1/2"));
        assert_eq!(q("1E-3"), q("1/1000"));
        assert_eq!(q("17/22").fraction(), "17/22");
        assert_eq!(q("+3"), Exact::from_int(3));
        for bad in [
            "", "-", ".", "1..2", "abc", "1e", "nan", "inf", "1/0", "1e99999", "1,2",
        ] {
            assert!(bad.parse::<Exact>().is_err(), "{bad:?} should not parse");
        }
    }

    #[test]
    fn long_numbers_read_exactly_and_errors_quote_them_briefly() {
        let digits = format!("1.{}1", "0".repeat(998));
        let value = q(&digits);
        assert_eq!(value.0.denom().to_string().len(), 1000);
        assert_eq!(q("1e10000").0.numer().to_string().len(), 10001);
        let err = format!("1e{}", MAX_EXPONENT + 1)
            .parse::<Exact>()
            .unwrap_err()
            .to_string();
        assert!(err.contains("exponent past"), "{err}");
        let err = format!("{}x", "5".repeat(5000))
            .parse::<Exact>()
            .unwrap_err()
            .to_string();
        assert!(err.len() < 80, "{err}");
        assert!(err.contains("(5001 characters)"), "{err}");
    }

    #[test]
    fn display_prefers_short_fractions() {
        assert_eq!(q("21/22").display(), "21/22");
        assert_eq!(q("-4").display(), "-4");
        // The fraction of the float 0.1 has a denominator of 2^55: shown as the float it is.
        let float = Exact::from_f64(-6.7).unwrap();
        assert_eq!(float.display(), "-6.7");
        assert_eq!(
            float.decimal_expansion().unwrap(),
            "-6.70000000000000017763568394002504646778106689453125"
        );
        assert_eq!(Exact::from_f64(1e-7).unwrap().display(), "1e-7");
        // Not a float, not short: ten significant digits, marked ≈.
        assert_eq!(q("1/3").decimal_expansion(), None);
        let long = q("1/3") * Exact::from_f64(0.1).unwrap();
        assert_eq!(long.display(), "≈0.03333333333");
        assert_eq!(q("2/3").significant(3), "0.667");
        assert_eq!(q("-123456789/1000").significant(4), "-123500");
        assert_eq!(q("3/8").decimal_expansion().unwrap(), "0.375");
    }

    #[test]
    fn values_beyond_the_float_range_still_read() {
        let huge: Exact = "1e400".parse().unwrap();
        assert_eq!(huge.to_f64(), f64::INFINITY);
        assert_eq!(huge.significant(10), "1e400");
        let tiny = Exact::from_int(1)
            .checked_div(&(huge.clone() * q("3")))
            .unwrap();
        assert_eq!(tiny.display(), "≈3.333333333e-401");
        assert_eq!(q("999999999999/1000000000000").significant(3), "1");
    }

    #[test]
    fn square_roots_print_exactly() {
        let root = |text: &str, negative: bool| SignedRoot {
            negative,
            square: q(text),
        };
        assert_eq!(root("3", false).full(), "√3");
        assert_eq!(root("4/9", false).full(), "2/3");
        assert_eq!(root("1/2", true).full(), "−√2/2");
        assert_eq!(
            root("1/2", true).short_latex().unwrap(),
            "-\\frac{\\sqrt{2}}{2}"
        );
        // The worksheet's √(236/25): the square 4 comes out.
        assert_eq!(root("236/25", false).full(), "2√59/5");
        assert_eq!(
            root("236/25", false).short_latex().unwrap(),
            "\\frac{2\\sqrt{59}}{5}"
        );
        assert_eq!(root("12", false).full(), "2√3");
        assert_eq!(root("3/4", false).full(), "√3/2");
        assert_eq!(root("4/9", false).short_latex().unwrap(), "\\frac{2}{3}");
        let long = root("1/288800000000000000000000001", false);
        assert_eq!(long.short(), None);
        assert_eq!(long.short_latex(), None);
        assert_eq!(long.full(), "√(1/288800000000000000000000001)");
        assert_eq!(q("-1").exact_sqrt(), None);
    }

    #[test]
    fn huge_values_do_not_panic_when_converted() {
        let big = q("1e400");
        assert_eq!(big.to_f64(), f64::INFINITY);
        assert_eq!((-big.clone()).to_f64(), f64::NEG_INFINITY);
        assert_eq!(q("1e-400").to_f64(), 0.0);
    }
}
