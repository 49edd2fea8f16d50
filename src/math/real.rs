//! The number types a solver can run in: `f32`, `f64` and [`Exact`] rationals.
//!
//! Every solver is generic over [`Real`], so one piece of code is the lecture's formula in all three
//! precisions, and the exact run is the judge of the two float runs.

use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

use serde::{Deserialize, Serialize};

use crate::math::exact::Exact;

/// The arithmetic precision a solver runs in, cheapest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
#[derive(strum::EnumIter, strum::IntoStaticStr)]
#[strum(serialize_all = "kebab-case")]
pub enum Precision {
    /// IEEE single precision.
    #[strum(serialize = "f32")]
    F32,
    /// IEEE double precision.
    #[default]
    #[strum(serialize = "f64")]
    F64,
    /// Exact rational arithmetic.
    Exact,
}

impl Precision {
    /// The name used on the command line and in JSON: `f32`, `f64`, `exact`.
    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// Work to do in a precision chosen at run time: [`in_precision`] calls [`InPrecision::run`] with its type.
/// (A closure cannot be generic over the number type; a trait's method can.)
pub trait InPrecision {
    /// What the work gives.
    type Output;
    /// Does the work in numbers of type `R`.
    fn run<R: Real>(self) -> Self::Output;
}

/// The one place a [`Precision`] chosen at run time becomes a number type.
pub fn in_precision<W: InPrecision>(precision: Precision, work: W) -> W::Output {
    match precision {
        Precision::F32 => work.run::<f32>(),
        Precision::F64 => work.run::<f64>(),
        Precision::Exact => work.run::<crate::math::exact::Exact>(),
    }
}

impl std::str::FromStr for Precision {
    type Err = crate::names::UnknownName;
    fn from_str(text: &str) -> Result<Precision, Self::Err> {
        crate::names::parse("precision", text)
    }
}

/// A number a solver can compute with: a field with an order, plus what the trace needs to show it.
///
/// Operators take values; `Copy` floats make that free, and exact rationals clone where needed.
pub trait Real:
    Clone
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
{
    /// Which precision this type is.
    const PRECISION: Precision;

    /// Relative tolerance for "zero" in scale-free tests (parallel, degenerate): a few units of
    /// rounding for floats, and 0 for exact arithmetic, where only a true zero is zero.
    const TOLERANCE: f64;

    /// Converts a float input: rounds to nearest for `f32`, exact for [`Exact`] (`None` if not finite).
    fn from_f64(x: f64) -> Option<Self>;
    /// Converts a float as a person wrote it: the shortest decimal that prints as `x` (0.1 → 1/10 for
    /// exact numbers; floats keep `x`, NaN included, for the solver to report).
    fn from_f64_as_written(x: f64) -> Option<Self> {
        Self::from_f64(x)
    }
    /// Converts exact text input; float types round the value to nearest.
    fn from_exact(x: &Exact) -> Self;
    /// The nearest `f64`, for display, norms and tolerances.
    fn to_f64(&self) -> f64;
    /// The exact value when this type is exact.
    fn to_exact(&self) -> Option<Exact>;
    /// The constant 0.
    fn zero() -> Self;
    /// The constant 1.
    fn one() -> Self;
    /// True for NaN or ±inf (never for exact numbers).
    fn is_finite(&self) -> bool;
    /// True only for an exact zero (floats: `== 0.0`).
    fn is_zero(&self) -> bool;
    /// The quotient, `None` if the divisor is zero.
    fn checked_div(&self, other: &Self) -> Option<Self>;
    /// The absolute value.
    fn abs(&self) -> Self;
    /// How many decimal digits the number holds (numerator and denominator together): what exact
    /// arithmetic on it costs. Floats are a fixed size: 0.
    fn digits(&self) -> usize {
        0
    }
}

/// Tolerance for floats: 16 units of roundoff in the precision.
const FLOAT_TOLERANCE_ULPS: f64 = 16.0;

macro_rules! float_real {
    ($t:ty, $precision:expr) => {
        impl Real for $t {
            const PRECISION: Precision = $precision;
            const TOLERANCE: f64 = FLOAT_TOLERANCE_ULPS * <$t>::EPSILON as f64;

            fn from_f64(x: f64) -> Option<$t> {
                Some(x as $t)
            }
            fn from_exact(x: &Exact) -> $t {
                x.to_f64() as $t
            }
            fn to_f64(&self) -> f64 {
                *self as f64
            }
            fn to_exact(&self) -> Option<Exact> {
                None
            }
            fn zero() -> $t {
                0.0
            }
            fn one() -> $t {
                1.0
            }
            fn is_finite(&self) -> bool {
                <$t>::is_finite(*self)
            }
            fn is_zero(&self) -> bool {
                *self == 0.0
            }
            fn checked_div(&self, other: &$t) -> Option<$t> {
                (*other != 0.0).then(|| *self / *other)
            }
            fn abs(&self) -> $t {
                <$t>::abs(*self)
            }
        }
    };
}

float_real!(f32, Precision::F32);
float_real!(f64, Precision::F64);

impl Real for Exact {
    const PRECISION: Precision = Precision::Exact;
    const TOLERANCE: f64 = 0.0;

    fn digits(&self) -> usize {
        Exact::digits(self)
    }

    fn from_f64(x: f64) -> Option<Exact> {
        Exact::from_f64(x)
    }
    fn from_f64_as_written(x: f64) -> Option<Exact> {
        // Rust prints the shortest decimal that reads back as x; read that decimal exactly.
        x.is_finite().then(|| format!("{x}").parse().ok()).flatten()
    }
    fn from_exact(x: &Exact) -> Exact {
        x.clone()
    }
    fn to_f64(&self) -> f64 {
        Exact::to_f64(self)
    }
    fn to_exact(&self) -> Option<Exact> {
        Some(self.clone())
    }
    fn zero() -> Exact {
        Exact::from_int(0)
    }
    fn one() -> Exact {
        Exact::from_int(1)
    }
    fn is_finite(&self) -> bool {
        true
    }
    fn is_zero(&self) -> bool {
        Exact::is_zero(self)
    }
    fn checked_div(&self, other: &Exact) -> Option<Exact> {
        Exact::checked_div(self, other)
    }
    fn abs(&self) -> Exact {
        Exact::abs(self)
    }
}
