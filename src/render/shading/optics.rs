//! The optics of mirrors and glass: the reflected direction, Snell's law with total internal
//! reflection, and Schlick's approximation of the Fresnel reflectance.

use crate::math::linalg::{V3, dot};

/// The mirror direction r = d − 2(d·n)n of `d` about the unit normal `n` (|r| = |d|).
pub fn reflect(d: &V3<f64>, n: &V3<f64>) -> V3<f64> {
    let along = 2.0 * dot(d, n);
    std::array::from_fn(|k| d[k] - along * n[k])
}

/// The refracted unit direction of the unit direction `d` crossing a surface with unit normal `n`
/// facing against `d` (d·n < 0), from index `eta_from` into `eta_to` (Snell: η₁ sin θ₁ = η₂ sin θ₂);
/// `None` past the critical angle (total internal reflection).
pub fn refract(d: &V3<f64>, n: &V3<f64>, eta_from: f64, eta_to: f64) -> Option<V3<f64>> {
    let eta = eta_from / eta_to;
    let cos_in = -dot(d, n);
    let sin2_out = eta * eta * (1.0 - cos_in * cos_in);
    if sin2_out > 1.0 {
        return None;
    }
    let cos_out = (1.0 - sin2_out).sqrt();
    Some(std::array::from_fn(|k| {
        eta * d[k] + (eta * cos_in - cos_out) * n[k]
    }))
}

/// Schlick's Fresnel reflectance R(θ) = R₀ + (1 − R₀)(1 − cos θ)⁵, R₀ = ((η₁ − η₂)/(η₁ + η₂))², with
/// θ the angle on the side of the lower index (the refracted angle when leaving the denser medium).
pub fn schlick(cos_in: f64, eta_from: f64, eta_to: f64) -> f64 {
    let r0 = ((eta_from - eta_to) / (eta_from + eta_to)).powi(2);
    let cos = if eta_from > eta_to {
        // Leaving the denser side: Schlick's formula takes the angle in the thinner medium.
        let eta = eta_from / eta_to;
        let sin2_out = eta * eta * (1.0 - cos_in * cos_in);
        if sin2_out > 1.0 {
            return 1.0;
        }
        (1.0 - sin2_out).sqrt()
    } else {
        cos_in
    };
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}

/// The critical angle (radians) leaving index `eta_from` for a lower `eta_to`; `None` if there is none.
pub fn critical_angle(eta_from: f64, eta_to: f64) -> Option<f64> {
    (eta_from > eta_to).then(|| (eta_to / eta_from).asin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::linalg::cross;

    fn close(a: &V3<f64>, b: &V3<f64>) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
    }

    #[test]
    fn the_reflected_direction_mirrors_the_normal_component() {
        let n = [0.0, 0.0, 1.0];
        assert!(close(&reflect(&[1.0, 2.0, -3.0], &n), &[1.0, 2.0, 3.0]));
        // A tilted normal: the angle in equals the angle out, and the three lie in one plane.
        let n = [0.6, 0.0, 0.8];
        let d = [0.3, -0.5, -0.9];
        let r = reflect(&d, &n);
        assert!((dot(&r, &n) + dot(&d, &n)).abs() < 1e-12);
        assert!((dot(&r, &r) - dot(&d, &d)).abs() < 1e-12);
        assert!(dot(&cross(&d, &n), &r).abs() < 1e-12);
    }

    #[test]
    fn snell_holds_and_total_internal_reflection_starts_at_the_critical_angle() {
        let n = [0.0, 0.0, 1.0];
        let at = |theta: f64| [theta.sin(), 0.0, -theta.cos()];
        // Air into glass at 30°: sin θ₂ = sin 30° / 1.5.
        let out = refract(&at(30f64.to_radians()), &n, 1.0, 1.5).unwrap();
        assert!((out[0] - 0.5 / 1.5).abs() < 1e-12, "{out:?}");
        assert!((dot(&out, &out) - 1.0).abs() < 1e-12);
        // Glass into air: the critical angle is asin(1/1.5) ≈ 41.81°.
        let critical = critical_angle(1.5, 1.0).unwrap();
        assert!((critical.to_degrees() - 41.810_314_895_778_6).abs() < 1e-9);
        let below = refract(&at(critical - 1e-9), &n, 1.5, 1.0).unwrap();
        assert!(below[0] > 0.999_99, "grazing out: {below:?}");
        assert_eq!(refract(&at(critical + 1e-9), &n, 1.5, 1.0), None);
        assert_eq!(critical_angle(1.0, 1.5), None);
    }

    #[test]
    fn schlick_goes_from_r0_head_on_to_one_past_the_critical_angle() {
        assert!((schlick(1.0, 1.0, 1.5) - 0.04).abs() < 1e-12);
        assert!((schlick(0.0, 1.0, 1.5) - 1.0).abs() < 1e-12);
        let critical = critical_angle(1.5, 1.0).unwrap();
        assert_eq!(schlick((critical + 1e-6).cos(), 1.5, 1.0), 1.0);
        assert!((schlick(1.0, 1.5, 1.0) - 0.04).abs() < 1e-12);
    }
}
