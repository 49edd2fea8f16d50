//! M X = Y solved with glam's 3x3 matrix inverse (f32: `Mat3`, f64: `DMat3`).

use glam::{DMat3, DVec3, Mat3, Vec3};

use super::{Answer, Case, Float, decide, record};
use crate::math::linalg::sub;
use crate::trace::StepSink;

/// Solving a 3x3 system through glam's inverse, in the precision's own matrix type.
pub trait InverseSolve: Float {
    /// X = M⁻¹ Y for M with the given columns; `None` when |M| = 0.
    fn solve_by_inverse(columns: [[Self; 3]; 3], y: [Self; 3]) -> Option<[Self; 3]>;
}

impl InverseSolve for f32 {
    fn solve_by_inverse(columns: [[f32; 3]; 3], y: [f32; 3]) -> Option<[f32; 3]> {
        let m = Mat3::from_cols_array_2d(&columns);
        (m.determinant() != 0.0).then(|| (m.inverse() * Vec3::from_array(y)).to_array())
    }
}

impl InverseSolve for f64 {
    fn solve_by_inverse(columns: [[f64; 3]; 3], y: [f64; 3]) -> Option<[f64; 3]> {
        let m = DMat3::from_cols_array_2d(&columns);
        (m.determinant() != 0.0).then(|| (m.inverse() * DVec3::from_array(y)).to_array())
    }
}

/// Intersects by inverting M.
pub fn intersect<F: InverseSolve>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (`()` records nothing, at no cost).
pub fn intersect_recorded<F: InverseSolve>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let [a, b, c] = &case.tri;
    let columns = [sub(a, b), sub(a, c), case.dir];
    let y = sub(a, &case.origin);
    record::vector(
        rec,
        "Y",
        "Y = A − L",
        "M = [A−B | A−C | D] goes to glam as three columns.",
        &y,
    );
    let answer = match F::solve_by_inverse(columns, y) {
        Some([beta, gamma, t]) => Answer::with(decide(t, beta, gamma), [t, beta, gamma]),
        None => Answer::miss(),
    };
    record::finish(rec, answer)
}
