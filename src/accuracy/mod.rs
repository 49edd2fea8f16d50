//! What accuracy costs in time: the intersection methods of [`crate::intersect`], each in f32 and f64,
//! judged against the exact rational solver on seeded families of easy and hard rays ([`study`]), and the
//! gallery of hard cases ([`hard_cases`]).

pub mod families;
pub mod hard_cases;
pub mod study;

/// The struct-of-arrays kernel (intersect/soa.rs) against the scalar method, on the study's random
/// family (tested here, above both, as the layers ask).
#[cfg(test)]
mod struct_of_arrays_kernel {
    use crate::accuracy::families::{Family, generate};
    use crate::intersect::moller_trumbore;
    use crate::intersect::soa::{Nearest, RaysSoA, TrianglesSoA, intersect, intersect_rays};

    #[test]
    fn agrees_with_the_scalar_method() {
        for probe in generate(Family::Random, 400, 4) {
            let case = probe.cases[0].to_f32();
            let soa = TrianglesSoA::new(&[case.tri]);
            let mut t = [0.0f32];
            intersect(case.origin, case.dir, &soa, &mut t);
            let scalar = moller_trumbore::intersect(&case);
            assert_eq!(t[0].is_finite(), scalar.hit);
            if scalar.hit {
                assert_eq!(t[0], scalar.values.unwrap()[0]);
            }
        }
    }

    #[test]
    fn many_rays_keep_the_nearest_scalar_hit() {
        let probes = generate(Family::Random, 300, 6);
        let cases: Vec<_> = probes.iter().map(|p| p.cases[0].to_f32()).collect();
        let columns = |f: &dyn Fn(&crate::intersect::Case<f32>) -> [f32; 3]| -> [Vec<f32>; 3] {
            std::array::from_fn(|k| cases.iter().map(|c| f(c)[k]).collect())
        };
        let origin = columns(&|c| c.origin);
        let dir = columns(&|c| c.dir);
        let rays = RaysSoA {
            origin: [&origin[0], &origin[1], &origin[2]],
            dir: [&dir[0], &dir[1], &dir[2]],
        };
        let n = cases.len();
        let (mut t, mut beta, mut gamma, mut index) = (
            vec![f32::INFINITY; n],
            vec![0.0; n],
            vec![0.0; n],
            vec![u32::MAX; n],
        );
        let mut nearest = Nearest {
            t: &mut t,
            beta: &mut beta,
            gamma: &mut gamma,
            index: &mut index,
        };
        // One triangle against every ray: the batch must decide, and find t, as the scalar method does.
        let triangle = cases[0].tri;
        intersect_rays(triangle, 7, &rays, &mut nearest);
        for (i, case) in cases.iter().enumerate() {
            let scalar = moller_trumbore::intersect(&crate::intersect::Case {
                tri: triangle,
                ..*case
            });
            assert_eq!(index[i] == 7, scalar.hit, "ray {i}");
            if scalar.hit {
                assert_eq!(t[i], scalar.values.unwrap()[0]);
            }
        }
    }
}
