//! A structure-of-arrays, SIMD-friendly f32 Möller–Trumbore: one ray against many triangles stored as a structure
//! of arrays, with no branches in the loop, so the compiler vectorises it (4 or 8 lanes).
//!
//! Per triangle it costs 27 multiplications and 18 additions or subtractions (45 flops) and one
//! division; `cargo bench --bench methods` compares its time per test with that floor.

/// Triangles as a structure of arrays: vertex A and the edges e1 = B − A, e2 = C − A.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrianglesSoA {
    /// A's coordinates.
    pub a: [Vec<f32>; 3],
    /// e1's coordinates.
    pub e1: [Vec<f32>; 3],
    /// e2's coordinates.
    pub e2: [Vec<f32>; 3],
}

impl TrianglesSoA {
    /// Packs triangles (A, B, C).
    pub fn new(triangles: &[[[f32; 3]; 3]]) -> TrianglesSoA {
        let mut soa = TrianglesSoA::default();
        for [a, b, c] in triangles {
            for k in 0..3 {
                soa.a[k].push(a[k]);
                soa.e1[k].push(b[k] - a[k]);
                soa.e2[k].push(c[k] - a[k]);
            }
        }
        soa
    }

    /// How many triangles.
    pub fn len(&self) -> usize {
        self.a[0].len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Writes t for every triangle the ray hits (β ≥ 0, γ ≥ 0, β + γ ≤ 1, t > 0) and +∞ for the others.
pub fn intersect(origin: [f32; 3], dir: [f32; 3], triangles: &TrianglesSoA, t_out: &mut [f32]) {
    let n = triangles.len().min(t_out.len());
    // Slices of exactly n elements: the compiler can then drop the bounds checks and vectorise.
    let [ax, ay, az] = cut(&triangles.a, n);
    let [e1x, e1y, e1z] = cut(&triangles.e1, n);
    let [e2x, e2y, e2z] = cut(&triangles.e2, n);
    let t_out = &mut t_out[..n];
    let [dx, dy, dz] = dir;
    for i in 0..n {
        // p = D × e2, det = e1 · p
        let px = dy * e2z[i] - dz * e2y[i];
        let py = dz * e2x[i] - dx * e2z[i];
        let pz = dx * e2y[i] - dy * e2x[i];
        let det = e1x[i] * px + e1y[i] * py + e1z[i] * pz;
        let inv = 1.0 / det;
        // s = L − A, β = s · p / det
        let sx = origin[0] - ax[i];
        let sy = origin[1] - ay[i];
        let sz = origin[2] - az[i];
        let beta = (sx * px + sy * py + sz * pz) * inv;
        // q = s × e1, γ = D · q / det, t = e2 · q / det
        let qx = sy * e1z[i] - sz * e1y[i];
        let qy = sz * e1x[i] - sx * e1z[i];
        let qz = sx * e1y[i] - sy * e1x[i];
        let gamma = (dx * qx + dy * qy + dz * qz) * inv;
        let t = (e2x[i] * qx + e2y[i] * qy + e2z[i] * qz) * inv;
        // A select, not a branch: NaN from det = 0 fails every comparison and becomes a miss.
        let hit = beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0 && t > 0.0;
        t_out[i] = if hit { t } else { f32::INFINITY };
    }
}

fn cut(v: &[Vec<f32>; 3], n: usize) -> [&[f32]; 3] {
    [&v[0][..n], &v[1][..n], &v[2][..n]]
}

/// Many rays (structure of arrays) against one triangle: for each ray whose test hits and is nearer
/// than `nearest[i]`, writes t, β, γ and `index` into the outputs. The loop has no branches, so it
/// vectorises over the rays (the renderer's coverage pass).
pub struct RaysSoA<'a> {
    /// Origins' x, y, z.
    pub origin: [&'a [f32]; 3],
    /// Directions' x, y, z.
    pub dir: [&'a [f32]; 3],
}

/// The nearest hits so far, per ray.
pub struct Nearest<'a> {
    /// t of the nearest hit (+∞ when none).
    pub t: &'a mut [f32],
    /// β of the nearest hit.
    pub beta: &'a mut [f32],
    /// γ of the nearest hit.
    pub gamma: &'a mut [f32],
    /// The triangle of the nearest hit (`u32::MAX` when none).
    pub index: &'a mut [u32],
}

/// Tests every ray of `rays` against one triangle (A, B, C) and keeps the nearest hits.
///
/// Always inlined, so a caller compiled for wider vectors (the renderer's AVX2 row loop) vectorises
/// it at that width.
#[inline(always)]
pub fn intersect_rays(
    triangle: [[f32; 3]; 3],
    index: u32,
    rays: &RaysSoA<'_>,
    nearest: &mut Nearest<'_>,
) {
    let n = rays.origin[0].len().min(nearest.t.len());
    let [a, b, c] = triangle;
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let (ox, oy, oz) = (
        &rays.origin[0][..n],
        &rays.origin[1][..n],
        &rays.origin[2][..n],
    );
    let (dx, dy, dz) = (&rays.dir[0][..n], &rays.dir[1][..n], &rays.dir[2][..n]);
    let (t_out, beta_out) = (&mut nearest.t[..n], &mut nearest.beta[..n]);
    let (gamma_out, index_out) = (&mut nearest.gamma[..n], &mut nearest.index[..n]);
    // Two passes, each a plain vector loop: the test (t, β, γ per ray, +∞ for a miss), then the merge
    // into the nearest hits. One fused loop with four conditional stores did not vectorise.
    let mut t_new = vec![0.0f32; n];
    let mut beta_new = vec![0.0f32; n];
    let mut gamma_new = vec![0.0f32; n];
    {
        let (t_new, beta_new, gamma_new) =
            (&mut t_new[..n], &mut beta_new[..n], &mut gamma_new[..n]);
        for i in 0..n {
            // p = D × e2, det = e1 · p
            let px = dy[i] * e2[2] - dz[i] * e2[1];
            let py = dz[i] * e2[0] - dx[i] * e2[2];
            let pz = dx[i] * e2[1] - dy[i] * e2[0];
            let det = e1[0] * px + e1[1] * py + e1[2] * pz;
            let inv = 1.0 / det;
            // s = L − A; β = s · p / det
            let sx = ox[i] - a[0];
            let sy = oy[i] - a[1];
            let sz = oz[i] - a[2];
            let beta = (sx * px + sy * py + sz * pz) * inv;
            // q = s × e1; γ = D · q / det; t = e2 · q / det
            let qx = sy * e1[2] - sz * e1[1];
            let qy = sz * e1[0] - sx * e1[2];
            let qz = sx * e1[1] - sy * e1[0];
            let gamma = (dx[i] * qx + dy[i] * qy + dz[i] * qz) * inv;
            let t = (e2[0] * qx + e2[1] * qy + e2[2] * qz) * inv;
            let hit = beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0 && t > 0.0;
            t_new[i] = if hit { t } else { f32::INFINITY };
            beta_new[i] = beta;
            gamma_new[i] = gamma;
        }
    }
    for i in 0..n {
        if t_new[i] < t_out[i] {
            t_out[i] = t_new[i];
            beta_out[i] = beta_new[i];
            gamma_out[i] = gamma_new[i];
            index_out[i] = index;
        }
    }
}
