//! Small vectors and matrices over any [`Real`], with determinants by cofactor expansion.
//!
//! glam stays at the edges (inputs and drawing); the solvers compute here so the same code runs in f32,
//! f64 and exact rationals. Matrices are stored as rows, and every determinant is expanded along the
//! first row, exactly as the lecture writes it, so the trace can show the very terms that were summed.

use super::real::Real;

/// A 2-vector.
pub type V2<R> = [R; 2];
/// A 3-vector.
pub type V3<R> = [R; 3];
/// A 2x2 matrix as rows.
pub type M2<R> = [[R; 2]; 2];
/// A 3x3 matrix as rows.
pub type M3<R> = [[R; 3]; 3];

/// `a − b`, componentwise.
pub fn sub<R: Real, const N: usize>(a: &[R; N], b: &[R; N]) -> [R; N] {
    std::array::from_fn(|i| a[i].clone() - b[i].clone())
}

/// `a + b`, componentwise.
pub fn add<R: Real, const N: usize>(a: &[R; N], b: &[R; N]) -> [R; N] {
    std::array::from_fn(|i| a[i].clone() + b[i].clone())
}

/// `−a`, componentwise.
pub fn neg<R: Real, const N: usize>(a: &[R; N]) -> [R; N] {
    std::array::from_fn(|i| -a[i].clone())
}

/// `k · a`.
pub fn scale<R: Real, const N: usize>(k: &R, a: &[R; N]) -> [R; N] {
    std::array::from_fn(|i| k.clone() * a[i].clone())
}

/// The dot product.
pub fn dot<R: Real, const N: usize>(a: &[R; N], b: &[R; N]) -> R {
    a.iter()
        .zip(b)
        .fold(R::zero(), |sum, (x, y)| sum + x.clone() * y.clone())
}

/// The cross product.
pub fn cross<R: Real>(a: &V3<R>, b: &V3<R>) -> V3<R> {
    let c = |i: usize, j: usize| a[i].clone() * b[j].clone() - a[j].clone() * b[i].clone();
    [c(1, 2), c(2, 0), c(0, 1)]
}

/// The 2D cross product `a.x b.y − a.y b.x` (a 2x2 determinant with a and b as columns).
pub fn cross2<R: Real>(a: &V2<R>, b: &V2<R>) -> R {
    a[0].clone() * b[1].clone() - a[1].clone() * b[0].clone()
}

/// Euclidean length, computed in f64 (it only feeds tolerances and distances). Scaled by the largest
/// component first, so coordinates near 1e200 do not overflow when squared.
pub fn norm_f64<R: Real, const N: usize>(a: &[R; N]) -> f64 {
    let values: [f64; N] = std::array::from_fn(|i| a[i].to_f64());
    let largest = values.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest
        * values
            .iter()
            .map(|x| (x / largest).powi(2))
            .sum::<f64>()
            .sqrt()
}

/// True if every component is finite.
pub fn all_finite<R: Real, const N: usize>(a: &[R; N]) -> bool {
    a.iter().all(Real::is_finite)
}

/// True if every component is exactly zero.
pub fn is_zero_vector<R: Real, const N: usize>(a: &[R; N]) -> bool {
    a.iter().all(Real::is_zero)
}

/// Converts to f64 components.
pub fn to_f64s<R: Real, const N: usize>(a: &[R; N]) -> [f64; N] {
    std::array::from_fn(|i| a[i].to_f64())
}

/// A matrix whose columns are the given vectors.
pub fn from_columns<R: Real, const N: usize>(columns: [&[R; N]; N]) -> [[R; N]; N] {
    std::array::from_fn(|row| std::array::from_fn(|col| columns[col][row].clone()))
}

/// The matrix with one column replaced (Cramer's M1, M2, M3).
pub fn with_column<R: Real, const N: usize>(
    m: &[[R; N]; N],
    column: usize,
    replacement: &[R; N],
) -> [[R; N]; N] {
    let mut out = m.clone();
    for (row, value) in out.iter_mut().zip(replacement) {
        row[column] = value.clone();
    }
    out
}

/// Matrix times vector.
pub fn mul_vec<R: Real, const N: usize>(m: &[[R; N]; N], v: &[R; N]) -> [R; N] {
    std::array::from_fn(|row| dot(&m[row], v))
}

/// The two indices of 0, 1, 2 other than `skip`, in order: the rows or columns a minor keeps.
#[inline(always)]
pub fn other_two(skip: usize) -> [usize; 2] {
    match skip {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

/// The minor of a 3x3 matrix: delete `row` and `col`.
pub fn minor3<R: Real>(m: &M3<R>, row: usize, col: usize) -> M2<R> {
    let (rows, cols) = (other_two(row), other_two(col));
    std::array::from_fn(|i| std::array::from_fn(|j| m[rows[i]][cols[j]].clone()))
}

/// The 2x2 determinant `ad − bc`.
pub fn det2<R: Real>(m: &M2<R>) -> R {
    m[0][0].clone() * m[1][1].clone() - m[0][1].clone() * m[1][0].clone()
}

/// One term of a cofactor expansion along the first row: `sign · element · |minor|`.
#[derive(Clone, Debug)]
pub struct CofactorTerm<R> {
    /// +1 or −1.
    pub sign: i8,
    /// The first-row element.
    pub element: R,
    /// The 2x2 minor that multiplies it.
    pub minor: M2<R>,
    /// Its determinant.
    pub minor_det: R,
}

/// The three terms of `|m| = a|A| − b|B| + c|C|` along the first row.
pub fn cofactor_terms3<R: Real>(m: &M3<R>) -> [CofactorTerm<R>; 3] {
    std::array::from_fn(|col| {
        let minor = minor3(m, 0, col);
        CofactorTerm {
            sign: if col == 1 { -1 } else { 1 },
            element: m[0][col].clone(),
            minor_det: det2(&minor),
            minor,
        }
    })
}

/// Sums a cofactor expansion.
pub fn sum_terms<R: Real>(terms: &[CofactorTerm<R>]) -> R {
    terms.iter().fold(R::zero(), |sum, term| {
        let product = term.element.clone() * term.minor_det.clone();
        if term.sign < 0 {
            sum - product
        } else {
            sum + product
        }
    })
}

/// The 3x3 determinant, expanded along the first row.
pub fn det3<R: Real>(m: &M3<R>) -> R {
    sum_terms(&cofactor_terms3(m))
}

/// The adjugate (transpose of the cofactor matrix), so that `m · adj(m) = |m| I`.
pub fn adjugate3<R: Real>(m: &M3<R>) -> M3<R> {
    std::array::from_fn(|row| {
        std::array::from_fn(|col| {
            // adj[row][col] = (−1)^(row+col) |minor(col,row)|
            let minor = det2(&minor3(m, col, row));
            if (row + col) % 2 == 1 { -minor } else { minor }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::exact::Exact;

    fn q(n: i64) -> Exact {
        Exact::from_int(n)
    }

    #[test]
    fn determinant_matches_rule_of_sarrus() {
        let m = [[2.0, -3.0, 1.0], [2.0, 0.0, -1.0], [1.0, 4.0, 5.0]];
        let [[a, b, c], [d, e, f], [g, h, i]] = m;
        // aei + bfg + cdh − ceg − bdi − afh
        let sarrus = a * e * i + b * f * g + c * d * h - c * e * g - b * d * i - a * f * h;
        assert_eq!(det3(&m), sarrus);
        assert_eq!(det3(&m), 49.0);
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn adjugate_inverts_exactly() {
        let m = [[q(2), q(-3), q(1)], [q(2), q(0), q(-1)], [q(1), q(4), q(5)]];
        let adj = adjugate3(&m);
        let det = det3(&m);
        for i in 0..3 {
            for j in 0..3 {
                let entry = (0..3).fold(q(0), |s, k| s + m[i][k].clone() * adj[k][j].clone());
                let expected = if i == j { det.clone() } else { q(0) };
                assert_eq!(entry, expected);
            }
        }
    }

    #[test]
    fn norms_do_not_overflow_or_underflow() {
        assert_eq!(norm_f64(&[3.0, 4.0]), 5.0);
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b;
        assert!(close(norm_f64(&[3e200, 4e200]), 5e200));
        assert!(close(norm_f64(&[3e-200, 4e-200]), 5e-200));
        assert_eq!(norm_f64(&[0.0, 0.0, 0.0]), 0.0);
        assert!(norm_f64(&[f64::NAN, 1.0]).is_nan());
        assert_eq!(norm_f64(&[f64::INFINITY, 1.0]), f64::INFINITY);
    }

    #[test]
    fn cross_is_orthogonal() {
        let a = [q(1), q(2), q(3)];
        let b = [q(-4), q(5), q(7)];
        let c = cross(&a, &b);
        assert!(dot(&a, &c).is_zero() && dot(&b, &c).is_zero());
        assert_eq!(cross2(&[q(1), q(0)], &[q(0), q(1)]), q(1));
    }
}
