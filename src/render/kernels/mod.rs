//! The SIMD kernels, set apart from the code that reads as the lecture: each computes what a scalar
//! function elsewhere in render computes, for several rays, triangles or boxes at once, with the
//! same float operations in the same order (no fused multiply-add unless a proof says why it is
//! harmless), so the same decisions and numbers to the bit.
//!
//! | kernel | lanes | the scalar path it stands for |
//! |---|---|---|
//! | [`moller_trumbore4`] | four rays, one lone triangle | [`crate::intersect::moller_trumbore::hit`] |
//! | [`parallelogram4`] | four rays, one parallelogram (or one ray in one scalar lane) | seed 001's lean solver |
//! | [`crack_free4`] | one ray, four triangles of a BVH leaf | [`super::crack_free::ShearedRay::intersect`] |
//! | [`boxes4`] | one ray, a BVH node's four boxes | the node's portable box test |
//! | [`narrow`] | sixteen rays, f32 box tests eight at a time; or one ray, a node's four boxes in f32 | the one-ray box test (it only culls) |
//! | the coverage rows ([`super::coverage_rows`]) | a row of rays compiled with AVX2 | the same loop compiled for the baseline |
//!
//! No safe function runs AVX2 code on a processor without it: every kernel takes an [`Avx2`], a
//! proof that the processor has AVX2 and FMA which only [`Avx2::detect`] makes, and
//! [`crate::render::Prepared::new`] detects once, when the scene is prepared
//! ([`crate::render::Prepared::simd`]; set it to `None` to force the scalar paths, as the tests do).
//! Hot loops that are compiled twice (once for the baseline, once with AVX2 inside a
//! `#[target_feature]` function) are generic over [`Isa`]: [`Scalar`] or [`Avx2`], chosen at
//! compile time, so the choice costs nothing inside the loop.

/// In a test: the processor's [`Avx2`], or on a processor without AVX2 and FMA a note on stderr
/// and a return, so the test says it was skipped.
#[cfg(test)]
macro_rules! avx2_or_skip {
    () => {
        match $crate::render::kernels::Avx2::detect() {
            Some(avx2) => avx2,
            None => {
                eprintln!("skipped: this processor has no AVX2 and FMA");
                return;
            }
        }
    };
}
#[cfg(test)]
pub(in crate::render) use avx2_or_skip;

pub mod boxes4;
pub mod crack_free4;
pub mod moller_trumbore4;
pub mod narrow;
pub mod parallelogram4;

/// Proof that the processor runs AVX2 and FMA (with POPCNT and BMI1, which every processor with
/// AVX2 has, for the bit sets of rays): a value exists only where [`Avx2::detect`] found
/// them (the field is private), so a function that takes one may run AVX2 code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx2 {
    /// Whether the processor also runs AVX-512F (see [`Avx2::avx512`]).
    avx512: bool,
    /// Off x86-64 no value can exist: no processor there has AVX2.
    #[cfg(not(target_arch = "x86_64"))]
    never: std::convert::Infallible,
}

impl Avx2 {
    /// The proof, when this processor has AVX2 and FMA; `None` elsewhere (other processors, the
    /// web page).
    pub fn detect() -> Option<Avx2> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("popcnt")
            && std::arch::is_x86_feature_detected!("bmi1")
        {
            return Some(Avx2 {
                avx512: std::arch::is_x86_feature_detected!("avx512f"),
            });
        }
        None
    }

    /// Code that takes a proof off x86-64, where none can exist, never runs.
    #[cfg(not(target_arch = "x86_64"))]
    pub fn unreachable(self) -> ! {
        match self.never {}
    }

    /// The proof that the processor also runs AVX-512F, when [`Avx2::detect`] found it.
    pub fn avx512(self) -> Option<Avx512> {
        self.avx512.then_some(Avx512 { _detected: () })
    }

    /// The same proof, but giving no [`Avx512`]: the kernels that have one then take their AVX2
    /// form (the tests compare the two on one machine).
    pub fn without_avx512(mut self) -> Avx2 {
        self.avx512 = false;
        self
    }
}

/// Asks the processor to start loading the `lines` cache lines from `start` (a hint: nothing
/// happens off x86-64, and a prefetch changes no memory and no program state, whatever the
/// address).
#[inline(always)]
pub fn prefetch_lines<T>(start: *const T, lines: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let start = start.cast::<i8>();
        for line in 0..lines {
            // SAFETY: as above (`wrapping_add` keeps the pointer arithmetic itself defined).
            #[allow(unsafe_code)]
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(64 * line))
            };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (start, lines);
}

/// Proof that the processor runs AVX-512F as well as AVX2 and FMA: made only by
/// [`Avx2::avx512`] (the field is private). The packet walk's box test then takes its sixteen rays
/// in one register ([`narrow`]), not in two of eight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx512 {
    _detected: (),
}

/// The instruction set a hot loop compiled twice is specialised for: [`Scalar`] or [`Avx2`].
pub trait Isa: Copy {
    /// The AVX2 proof for [`Avx2`], none for [`Scalar`] (known at compile time).
    fn avx2(self) -> Option<Avx2>;
}

/// The portable code, on any processor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Scalar;

impl Isa for Scalar {
    #[inline(always)]
    fn avx2(self) -> Option<Avx2> {
        None
    }
}

impl Isa for Avx2 {
    #[inline(always)]
    fn avx2(self) -> Option<Avx2> {
        Some(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intersect::Method;
    use crate::render::generate::{grid_box, irregular_sphere, mesh_scene};
    use crate::render::{Bug, Prepared, Stats, render};
    use crate::scene::render::Camera;

    /// The image and counters of a render, with the kernels (`simd`) or the scalar paths alone.
    fn render_with(prepared: &Prepared, simd: Option<Avx2>) -> (Vec<[u32; 3]>, Vec<bool>, Stats) {
        let prepared = Prepared {
            simd,
            ..prepared.clone()
        };
        let (image, stats) = render(&prepared);
        let bits = image.pixels.iter().map(|p| p.map(f32::to_bits)).collect();
        (bits, image.covered, stats)
    }

    /// Every shipped render scene (made smaller, so a debug build renders it quickly), with each
    /// method and with shadow acne, and the generated meshes: the scalar paths, forced on this very
    /// machine, and the kernels render the same pixels to the bit and cast the same rays. Between
    /// them the scenes take every kernel: lone triangles four rays at a time and the coverage rows
    /// (seed 003), parallelograms four rays at a time beside a mesh (the floors of the effect
    /// scenes), BVH leaves four triangles at a time, the four-box test and the sixteen-ray f32 box
    /// test (the meshes; the grid box's rays run along its edges and through its vertices). Where
    /// the processor has AVX-512, the sixteen-ray box test in one register renders each scene
    /// again, compared with the same kernels taking eight rays at a time.
    #[test]
    fn every_kernel_renders_as_the_scalar_path_on_the_same_rays() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let mut cases: Vec<(String, Prepared)> = Vec::new();
        for (name, prepared) in crate::render::shipped_scenes(32, 20) {
            for method in [None, Some(Method::MollerTrumbore), Some(Method::Watertight)] {
                let mut variant = prepared.clone();
                variant.method = method.or(prepared.method);
                cases.push((format!("{name} {method:?}"), variant));
            }
            // The one bug that leaves the tests (and so the kernels) on.
            let mut variant = prepared.clone();
            variant.bug = Some(Bug::ShadowAcne);
            cases.push((format!("{name} shadow acne"), variant));
        }
        let (camera, side, triangles) = grid_box(12);
        cases.push((
            "grid box".into(),
            mesh_scene(&triangles, camera, side, side),
        ));
        let camera = Camera::Pinhole {
            position: [0.3, -3.6, 0.5],
            target: [0.0, 0.0, 0.0],
            fov_y: 40.0,
        };
        let sphere = irregular_sphere(3, 12);
        cases.push(("sphere".into(), mesh_scene(&sphere, camera, 64, 64)));
        assert!(cases.len() > 40, "{}", cases.len());
        let (mut hits, mut sixteen) = (0, 0);
        for (name, prepared) in &cases {
            let scalar = render_with(prepared, None);
            let kernels = render_with(prepared, Some(avx2));
            assert!(
                scalar.0 == kernels.0,
                "{name}: the kernels render other pixels"
            );
            assert!(
                scalar.1 == kernels.1,
                "{name}: the kernels cover other pixels"
            );
            // The rays and hits; not the box and triangle tests, which the f32 box test of sixteen
            // rays (conservative, so wider than the f64 one) may raise a little.
            let counted = |s: &Stats| (s.rays, s.hits, s.all_rays(), s.secondary.blocked);
            assert_eq!(counted(&scalar.2), counted(&kernels.2), "{name}");
            hits += scalar.2.hits;
            // With AVX-512 the packets' box test takes sixteen rays at once: the same answers, so
            // the same pixels and rays as eight at a time. (Not the tests counted: the threads'
            // last blockers make those vary a little from one render to the next.)
            if avx2.avx512().is_some() {
                let eight = render_with(prepared, Some(avx2.without_avx512()));
                assert!(kernels.0 == eight.0, "{name}: AVX-512 renders other pixels");
                assert!(kernels.1 == eight.1, "{name}: AVX-512 covers other pixels");
                assert_eq!(counted(&kernels.2), counted(&eight.2), "{name}");
                sixteen += 1;
            }
        }
        assert!(hits > 10_000, "{hits}");
        if sixteen == 0 {
            eprintln!("AVX-512 not compared: this processor has no AVX-512F");
        }
    }
}
