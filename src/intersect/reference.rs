//! The exact reference, fast enough for hundreds of thousands of rays.
//!
//! Every finite float is an integer times a power of two, so scaling all fifteen coordinates of a case
//! by one common power of two makes them integers; the lecture's determinants |M|, |M1|, |M2|, |M3| are
//! then exact big integers (no fractions, no gcds), and the decision is a comparison of their signs:
//! β ≥ 0 ⟺ |M1|·|M| ≥ 0, β + γ ≤ 1 ⟺ (|M| − |M1| − |M2|)·|M| ≥ 0, t > 0 ⟺ |M3|·|M| > 0.
//! t, β and γ are the correctly rounded f64 of the exact quotients.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use super::{Case, Float};

/// The exact verdict on a case, and its exact parameters rounded once to f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// Hit under the lecture's rules (edges included, t > 0).
    pub hit: bool,
    /// (t, β, γ) rounded to nearest f64, when |M| ≠ 0.
    pub values: Option<[f64; 3]>,
}

/// Decides a case exactly.
pub fn reference<F: Float>(case: &Case<F>) -> Reference {
    let coordinates: Vec<f64> = case
        .tri
        .iter()
        .chain([&case.origin, &case.dir])
        .flat_map(|v| v.iter().map(|x| x.to_f64()))
        .collect();
    let integers = scale_to_integers(&coordinates);
    let v = |i: usize| {
        [
            integers[3 * i].clone(),
            integers[3 * i + 1].clone(),
            integers[3 * i + 2].clone(),
        ]
    };
    let (a, b, c, origin, dir) = (v(0), v(1), v(2), v(3), v(4));
    let diff = |p: &[BigInt; 3], q: &[BigInt; 3]| [&p[0] - &q[0], &p[1] - &q[1], &p[2] - &q[2]];
    let columns = [diff(&a, &b), diff(&a, &c), dir];
    let y = diff(&a, &origin);
    let det = det3(&columns);
    if det.is_zero() {
        return Reference {
            hit: false,
            values: None,
        };
    }
    let replaced = |i: usize| {
        let mut m = columns.clone();
        m[i] = y.clone();
        det3(&m)
    };
    let (d1, d2, d3) = (replaced(0), replaced(1), replaced(2));
    let same_sign = |x: &BigInt| !(x.is_negative() ^ det.is_negative()) || x.is_zero();
    let rest = &det - &d1 - &d2;
    let hit = same_sign(&d1)
        && same_sign(&d2)
        && same_sign(&rest)
        && !d3.is_zero()
        && (d3.is_negative() == det.is_negative());
    let quotient = |n: &BigInt| {
        BigRational::new(n.clone(), det.clone())
            .to_f64()
            .unwrap_or(f64::NAN)
    };
    Reference {
        hit,
        values: Some([quotient(&d3), quotient(&d1), quotient(&d2)]),
    }
}

/// The determinant of three columns, by cofactor expansion.
fn det3(columns: &[[BigInt; 3]; 3]) -> BigInt {
    let m = |row: usize, col: usize| &columns[col][row];
    let minor =
        |r1: usize, r2: usize, c1: usize, c2: usize| m(r1, c1) * m(r2, c2) - m(r1, c2) * m(r2, c1);
    m(0, 0) * minor(1, 2, 1, 2) - m(0, 1) * minor(1, 2, 0, 2) + m(0, 2) * minor(1, 2, 0, 1)
}

/// Scales finite floats by one power of two so that all become integers.
fn scale_to_integers(values: &[f64]) -> Vec<BigInt> {
    // x = mantissa · 2^exponent exactly; the smallest exponent becomes 2^0.
    let parts: Vec<(i64, i32)> = values.iter().map(|x| decompose(*x)).collect();
    let lowest = parts
        .iter()
        .filter(|(m, _)| *m != 0)
        .map(|(_, e)| *e)
        .min()
        .unwrap_or(0);
    parts
        .iter()
        .map(|(mantissa, exponent)| BigInt::from(*mantissa) << ((exponent - lowest) as usize))
        .collect()
}

/// (m, e) with x = m · 2^e exactly.
fn decompose(x: f64) -> (i64, i32) {
    if x == 0.0 {
        return (0, 0);
    }
    let bits = x.to_bits();
    let sign = if bits >> 63 == 0 { 1 } else { -1 };
    let exponent = ((bits >> 52) & 0x7ff) as i32;
    let fraction = (bits & 0x000f_ffff_ffff_ffff) as i64;
    let (mantissa, exponent) = if exponent == 0 {
        (fraction, -1074)
    } else {
        (fraction | 0x0010_0000_0000_0000, exponent - 1075)
    };
    (sign * mantissa, exponent)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intersect::exact_answer;

    #[test]
    fn decomposition_is_exact() {
        for x in [1.0, -0.1, 3e-310, 1e300, 2.5, -7.0] {
            let (m, e) = decompose(x);
            let two = BigRational::from_integer(BigInt::from(2));
            let scale = num_traits::pow(two, e.unsigned_abs() as usize);
            let m = BigRational::from_integer(BigInt::from(m));
            let value = if e >= 0 { m * scale } else { m / scale };
            assert_eq!(Some(value), BigRational::from_float(x), "{x}");
        }
    }

    #[test]
    fn agrees_with_the_rational_solver() {
        let lecture = Case::LECTURE;
        let r = reference(&lecture);
        assert!(r.hit);
        assert_eq!(r.values, Some([1.0, 1.0 / 3.0, 1.0 / 3.0]));
        let mut rng = 12345u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng % 2001) as f64 / 100.0 - 10.0
        };
        for _ in 0..300 {
            let mut p = || [next(), next(), next()];
            let case = Case {
                tri: [p(), p(), p()],
                origin: p(),
                dir: p(),
            };
            let fast = reference(&case);
            let slow = exact_answer(&case);
            assert_eq!(fast.hit, slow.hit, "{case:?}");
            assert_eq!(fast.values.is_some(), slow.values.is_some());
            if let (Some(f), Some(s)) = (fast.values, slow.values) {
                for (x, y) in f.iter().zip(s) {
                    assert_eq!(*x, y.to_f64());
                }
            }
        }
    }
}
