//! Seeded random directions and sample positions: the same image every run and on every thread, as
//! each pixel draws from its own generator, seeded by the scene's seed and the pixel.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

use crate::math::linalg::V3;

/// A pixel's own random numbers, from the scene's seed and the pixel's index.
pub fn pixel_rng(seed: u64, pixel: usize) -> Pcg32 {
    // SplitMix64's finaliser spreads neighbouring pixels over unrelated streams.
    let mut z = seed ^ (pixel as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    Pcg32::seed_from_u64(z ^ (z >> 31))
}

/// k×k stratified positions in the unit pixel: one jittered point in each cell, row by row.
pub fn stratified(k: u32, rng: &mut impl Rng) -> Vec<(f64, f64)> {
    let k = k.max(1);
    let cell = 1.0 / f64::from(k);
    let mut points = Vec::with_capacity((k * k) as usize);
    for i in 0..k {
        for j in 0..k {
            let x = (f64::from(j) + rng.random::<f64>()) * cell;
            let y = (f64::from(i) + rng.random::<f64>()) * cell;
            points.push((x, y));
        }
    }
    points
}

/// A unit direction over the hemisphere about the unit normal `n`, cosine-weighted (denser near `n`).
pub fn cosine_hemisphere(n: &V3<f64>, rng: &mut impl Rng) -> V3<f64> {
    let (u1, u2): (f64, f64) = (rng.random(), rng.random());
    let r = u1.sqrt();
    let phi = 2.0 * std::f64::consts::PI * u2;
    let (x, y, z) = (r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
    let (t, b) = tangents(n);
    std::array::from_fn(|k| x * t[k] + y * b[k] + z * n[k])
}

/// Two unit vectors completing the unit `n` to an orthonormal frame (Duff et al. 2017, branchless).
fn tangents(n: &V3<f64>) -> (V3<f64>, V3<f64>) {
    let sign = 1f64.copysign(n[2]);
    let a = -1.0 / (sign + n[2]);
    let b = n[0] * n[1] * a;
    (
        [1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]],
        [b, sign + n[1] * n[1] * a, -n[1]],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::linalg::dot;

    #[test]
    fn stratified_samples_fill_each_cell_once() {
        let mut rng = pixel_rng(7, 3);
        for k in 1..=5 {
            let points = stratified(k, &mut rng);
            assert_eq!(points.len(), (k * k) as usize);
            let mut cells: Vec<(u32, u32)> = points
                .iter()
                .map(|(x, y)| ((y * f64::from(k)) as u32, (x * f64::from(k)) as u32))
                .collect();
            cells.sort_unstable();
            cells.dedup();
            assert_eq!(cells.len(), (k * k) as usize);
        }
    }

    #[test]
    fn hemisphere_directions_are_unit_and_above_the_surface() {
        let mut rng = pixel_rng(1, 0);
        let mut mean_cos = 0.0;
        for n in [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.6, -0.8, 0.0]] {
            for _ in 0..4000 {
                let d = cosine_hemisphere(&n, &mut rng);
                assert!((dot(&d, &d) - 1.0).abs() < 1e-12);
                assert!(dot(&d, &n) >= 0.0);
                mean_cos += dot(&d, &n);
            }
        }
        // Cosine-weighted: E[cos θ] = 2/3.
        assert!((mean_cos / 12_000.0 - 2.0 / 3.0).abs() < 0.02, "{mean_cos}");
    }

    #[test]
    fn a_pixel_draws_the_same_numbers_every_time() {
        let a: f64 = pixel_rng(3, 10).random();
        let b: f64 = pixel_rng(3, 10).random();
        let c: f64 = pixel_rng(3, 11).random();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
