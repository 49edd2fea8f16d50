//! Splitting long thin triangles before the build ("early split clipping"): a triangle whose box
//! is much larger than itself (a sliver lying across the axes) is given to the builder as several
//! references, each the triangle clipped to a slab of its box, with the clipped part's box. The
//! boxes of a triangle's references together hold all of it, so a ray that meets the triangle
//! meets one of them, and the hierarchy still finds every hit.

use super::Bounds;
use crate::math::linalg::{V3, add, cross, norm_f64, scale, sub};

/// A triangle's box is split at most this deep (into at most 2^depth pieces). On a 1.3-million
/// triangle sphere of slivers, depth 2 cut the triangle tests per ray from 55 to 16 and the render
/// time by a third; depth 3 was no faster.
const MAX_DEPTH: u32 = 2;
/// A piece is split while its box's half area is above this many times the triangle's own area
/// (a triangle in an axis plane has 2 or more; a sliver across the axes has hundreds).
const WASTE: f64 = 8.0;

/// The boxes of `triangle`'s references: its own box, or the boxes of its pieces.
pub(super) fn pieces(triangle: &[V3<f64>; 3], out: &mut Vec<Bounds>) {
    let whole = Bounds::of(triangle);
    let area = triangle_area(triangle);
    let largest = triangle
        .iter()
        .flatten()
        .fold(0.0f64, |m, c| m.max(c.abs()));
    // Only where the clipping's arithmetic can neither overflow nor underflow (and not a
    // degenerate triangle): the error bound below then holds.
    let in_range = largest > 1e-100 && largest < 1e100;
    if !(in_range && area > 0.0 && whole.half_area() > WASTE * area) {
        out.push(whole);
        return;
    }
    // A clipped point p + s(q − p) errs by a few ulps of the largest coordinate; every piece is
    // widened by 64 of them (within the triangle's own box) to cover it.
    let margin = 64.0 * f64::EPSILON * largest;
    split(triangle, whole, whole, area * WASTE, margin, MAX_DEPTH, out);
}

/// Splits `piece` (a box holding the triangle's part within it) at the middle of its longest axis,
/// while it is wasteful and `depth` allows; pushes the boxes of the parts.
fn split(
    triangle: &[V3<f64>; 3],
    whole: Bounds,
    piece: Bounds,
    limit: f64,
    margin: f64,
    depth: u32,
    out: &mut Vec<Bounds>,
) {
    if depth == 0 || piece.half_area() <= limit {
        out.push(piece);
        return;
    }
    let axis = (0..3)
        .max_by(|&a, &b| (piece.max[a] - piece.min[a]).total_cmp(&(piece.max[b] - piece.min[b])))
        .unwrap_or(0);
    let middle = piece.min[axis] * 0.5 + piece.max[axis] * 0.5;
    let inside = middle > piece.min[axis] && middle < piece.max[axis];
    if !inside {
        out.push(piece);
        return;
    }
    for (low, high) in [(piece.min[axis], middle), (middle, piece.max[axis])] {
        let part = clipped(triangle, axis, low, high, margin, whole).and_within(piece);
        if !part.is_empty() {
            split(triangle, whole, part, limit, margin, depth - 1, out);
        }
    }
}

/// The box of the triangle's points with `low ≤ p[axis] ≤ high`, widened by `margin` on the other
/// axes and kept within `whole`.
fn clipped(
    triangle: &[V3<f64>; 3],
    axis: usize,
    low: f64,
    high: f64,
    margin: f64,
    whole: Bounds,
) -> Bounds {
    let mut bounds = Bounds::EMPTY;
    for (i, p) in triangle.iter().enumerate() {
        if (low..=high).contains(&p[axis]) {
            bounds = bounds.grow(p);
        }
        let q = &triangle[(i + 1) % 3];
        for plane in [low, high] {
            // The edge p → q crosses the plane strictly between its ends.
            if (p[axis] - plane) * (q[axis] - plane) < 0.0 {
                let s = (plane - p[axis]) / (q[axis] - p[axis]);
                let mut point = add(p, &scale(&s, &sub(q, p)));
                point[axis] = plane;
                bounds = bounds.grow(&point);
            }
        }
    }
    if bounds.is_empty() {
        return bounds;
    }
    for k in 0..3 {
        if k != axis {
            bounds.min[k] -= margin;
            bounds.max[k] += margin;
        }
    }
    bounds.and_within(whole)
}

/// The triangle's area, |AB × AC| / 2.
fn triangle_area([a, b, c]: &[V3<f64>; 3]) -> f64 {
    0.5 * norm_f64(&cross(&sub(b, a), &sub(c, a)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Long thin triangles at random angles (near the origin and far from it), with integer
    /// vertices, and every point on them whose weights are in 32nds (each exact in f64): each point
    /// lies in one of its triangle's piece boxes, every piece lies within the triangle's box, and
    /// the pieces are much smaller than the whole. A triangle in an axis plane stays whole, and so
    /// does one beyond the range where the clipping's error bound holds.
    #[test]
    fn the_pieces_hold_every_point_of_their_triangle() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(9);
        let (mut split_up, mut kept_whole) = (0, 0);
        for round in 0..600 {
            let offset = [0.0, 1e6, -3e9][round % 3];
            let corner: V3<f64> =
                std::array::from_fn(|_| random.random_range(-1000..1000) as f64 + offset);
            let long: V3<f64> = std::array::from_fn(|_| random.random_range(-4096..4096) as f64);
            // Every fourth triangle is not thin (and not always split).
            let width = if round % 4 == 0 { 4096 } else { 64 };
            let short: V3<f64> = std::array::from_fn(|_| random.random_range(-width..width) as f64);
            let triangle = [
                corner,
                std::array::from_fn(|k| corner[k] + long[k]),
                std::array::from_fn(|k| corner[k] + short[k]),
            ];
            let whole = Bounds::of(&triangle);
            let mut boxes = Vec::new();
            pieces(&triangle, &mut boxes);
            assert!(!boxes.is_empty() && boxes.len() <= 1 << MAX_DEPTH);
            for piece in &boxes {
                assert_eq!(piece.and_within(whole), *piece, "{triangle:?}");
            }
            if boxes.len() > 1 {
                split_up += 1;
                let areas: f64 = boxes.iter().map(Bounds::half_area).sum();
                assert!(areas < 0.8 * whole.half_area(), "{triangle:?} {boxes:?}");
            } else {
                kept_whole += 1;
            }
            for i in 0..=32 {
                for j in 0..=32 - i {
                    let point: V3<f64> = std::array::from_fn(|k| {
                        let weighted = triangle[0][k] * (32 - i - j) as f64
                            + triangle[1][k] * i as f64
                            + triangle[2][k] * j as f64;
                        weighted / 32.0
                    });
                    let inside =
                        |b: &Bounds| (0..3).all(|k| (b.min[k]..=b.max[k]).contains(&point[k]));
                    assert!(boxes.iter().any(inside), "{triangle:?} {point:?} {boxes:?}");
                }
            }
        }
        assert!(split_up > 300 && kept_whole > 10, "{split_up} {kept_whole}");
        let whole_only = |triangle: [V3<f64>; 3]| {
            let mut boxes = Vec::new();
            pieces(&triangle, &mut boxes);
            boxes == [Bounds::of(&triangle)]
        };
        assert!(whole_only([
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0]
        ]));
        // A sliver so large or so small that clipping it could overflow or underflow stays whole.
        let sliver = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.0, 0.01, 0.0]];
        assert!(!whole_only(sliver));
        for scale in [1e200, 1e-200] {
            assert!(whole_only(sliver.map(|v| v.map(|c| c * scale))));
        }
    }
}
