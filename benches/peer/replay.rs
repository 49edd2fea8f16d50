//! The peer bench's rows per kind of ray, raylab's side, kept in one place for the bench
//! (`embree.rs`) and the profiling loop (`examples/ray_kind_loop.rs`): a kind's logged rays in
//! chunks, each in the order the render casts them, cast again in the current rayon pool.

use raylab::render::ray_log::{LoggedRay, cast_all_again, in_casting_order};
use raylab::render::{Prepared, Stats};
use rayon::prelude::*;

/// Rays a chunk: 4096, or fewer so that each of `threads` has eight chunks or more (512 at
/// least). Embree's script gives each thread every other ray; in six chunks of 4096, the one-light
/// scene's 22 922 shadow rays split 0.60 ms to 0.44 ms of one thread's work.
pub fn chunk_size(rays: usize, threads: usize) -> usize {
    (rays / (8 * threads)).clamp(512, 4096)
}

/// `rays` split into chunks of [`chunk_size`] for `threads`, each put in the order the render
/// casts its rays (before any clock starts): the rays and the chunk size.
pub fn in_chunks(rays: &[LoggedRay], threads: usize) -> (Vec<LoggedRay>, usize) {
    let chunk = chunk_size(rays.len(), threads);
    let mut rays = rays.to_vec();
    rays.chunks_mut(chunk).for_each(in_casting_order);
    (rays, chunk)
}

/// Casts `rays` again in chunks of `chunk`, in parallel in the current rayon pool: the rays that
/// met something.
pub fn cast_chunks(prepared: &Prepared, rays: &[LoggedRay], chunk: usize) -> usize {
    rays.par_chunks(chunk)
        .map(|chunk| cast_all_again(prepared, chunk, &mut Stats::default()))
        .sum()
}
