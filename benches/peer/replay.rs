//! The peer bench's rows per kind of ray, raylab's side, kept in one place for the bench
//! (`embree.rs`) and the profiling loop (`examples/ray_kind_loop.rs`): a kind's logged rays in
//! chunks, each in the order the render casts them, cast again in the current rayon pool.

use raylab::render::ray_log::{LoggedRay, cast_run_again, in_casting_order};
use raylab::render::{Prepared, Stats};
use rayon::prelude::*;

/// Rays a chunk: 4096, or fewer so that each of `threads` has eight chunks or more (512 at
/// least). Embree's script gives each thread every other ray; in six chunks of 4096, the one-light
/// scene's 22 922 shadow rays split 0.60 ms to 0.44 ms of one thread's work.
pub fn chunk_size(rays: usize, threads: usize) -> usize {
    (rays / (8 * threads)).clamp(512, 4096)
}

/// `rays`, all of one kind, split into chunks of [`chunk_size`] for `threads`, each put in the
/// order the render casts its rays (before any clock starts): the rays and the chunk size.
pub fn in_chunks(rays: &[LoggedRay], threads: usize) -> (Vec<LoggedRay>, usize) {
    // Checked here, before any clock: each chunk is then cast as one run, unscanned.
    assert!(
        rays.windows(2).all(|pair| pair[0].kind == pair[1].kind),
        "a row's rays are of one kind"
    );
    let chunk = chunk_size(rays.len(), threads);
    let mut rays = rays.to_vec();
    rays.chunks_mut(chunk).for_each(in_casting_order);
    (rays, chunk)
}

/// Casts `rays` (from [`in_chunks`]) again in chunks of `chunk`, each a run of one kind in
/// casting order ([`cast_run_again`]), in parallel in the current rayon pool: the rays that met
/// something.
pub fn cast_chunks(prepared: &Prepared, rays: &[LoggedRay], chunk: usize) -> usize {
    rays.par_chunks(chunk)
        .map(|chunk| cast_run_again(prepared, chunk, &mut Stats::default()))
        .sum()
}
