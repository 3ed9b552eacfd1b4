//! Work split over Bevy's task pool: parts that touch disjoint data, run on the pool's
//! threads (and the calling thread) when the crate is built with `parallel`, else one after
//! another. Results never depend on how the parts are scheduled.
//!
//! Two shapes: [`for_each_part`], one job cut into parts under a scope of its own; and
//! [`run_phases`], a frame's many short passes under one scope, each pass's items run by
//! whichever thread takes them (with `Disjoint` handing each item its part of arrays that
//! the next pass cuts differently).

use bevy::tasks::TaskPool;

/// Runs `work` on every part: on `pool`'s threads when one is given, the crate is built with
/// the `parallel` feature and there is more than one part, else in order on this thread.
pub fn for_each_part<T: Send>(
    pool: Option<&TaskPool>,
    parts: impl Iterator<Item = T>,
    work: impl Fn(T) + Sync,
) {
    let mut parts = parts.peekable();
    let first = parts.next();
    match pool.filter(|_| cfg!(feature = "parallel") && parts.peek().is_some()) {
        Some(pool) => {
            let work = &work;
            pool.scope(|scope| {
                for part in first.into_iter().chain(parts) {
                    scope.spawn(async move { work(part) });
                }
            });
        }
        // One part (or none) needs no pool: a scope would cost more than small work.
        None => first.into_iter().chain(parts).for_each(work),
    }
}

/// How many parts to cut a job of `n` items into for `pool` (its threads and the calling
/// thread), each at least `smallest` items; 1 without a pool.
pub fn parts_for(pool: Option<&TaskPool>, n: usize, smallest: usize) -> usize {
    let threads = pool.map_or(1, |pool| 4 * (pool.thread_num() + 1));
    threads.min(n / smallest.max(1)).max(1)
}

/// `slice` cut into `parts` consecutive pieces of nearly equal length.
pub fn pieces<T>(slice: &mut [T], parts: usize) -> impl Iterator<Item = &mut [T]> {
    let size = slice.len().div_ceil(parts.max(1)).max(1);
    slice.chunks_mut(size)
}

mod disjoint;
mod phases;

pub(crate) use disjoint::Disjoint;
pub use phases::{Claims, run_phases};
