//! Work split over Bevy's task pool: parts that touch disjoint data, run on the pool's
//! threads (and the calling thread) when the crate is built with `parallel`, else one after
//! another. Results never depend on how the parts are scheduled.
//!
//! Two shapes: [`for_each_part`], one job cut into parts under a scope of its own (the
//! calling thread working from the start, pool threads joining as they wake); and
//! [`run_phases`], a frame's many short passes under one scope, each pass's items run by
//! whichever thread takes them (with `Disjoint` handing each item its part of arrays that
//! the next pass cuts differently).

use bevy::tasks::TaskPool;

/// Runs `work` on every part: on `pool`'s threads and this one when a pool is given, the
/// crate is built with the `parallel` feature, the machine has more than one core and there
/// is more than one part; else in order on this thread.
///
/// The calling thread starts on the parts at once and the pool's threads (no more of them
/// than the machine has cores besides the caller's) take parts as they wake, one at a time,
/// so the caller never waits for a thread that has not started: a part per task, as a plain
/// scope would spawn, cost the mesh update of a 128 x 128 cloth the wake-up of a pool thread
/// for each part.
pub fn for_each_part<T: Send>(
    pool: Option<&TaskPool>,
    parts: impl Iterator<Item = T> + Send,
    work: impl Fn(T) + Sync,
) {
    let mut parts = parts.peekable();
    let Some(first) = parts.next() else {
        return;
    };
    let helpers = pool.map_or(0, phases::helpers);
    let Some(pool) =
        pool.filter(|_| cfg!(feature = "parallel") && helpers > 0 && parts.peek().is_some())
    else {
        // One part (or one core) needs no pool: a scope would cost more than small work.
        work(first);
        parts.for_each(work);
        return;
    };
    let queue = std::sync::Mutex::new(parts);
    // The lock is held only to take a part, never while one runs, so a panicking part
    // leaves it unpoisoned; a poisoned one would still hand out what is left.
    let take = || {
        queue
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .next()
    };
    let worker = || {
        while let Some(part) = take() {
            work(part);
        }
    };
    pool.scope(|scope| {
        for _ in 0..helpers {
            scope.spawn(async { worker() });
        }
        work(first);
        worker();
    });
}

/// How many parts to cut a job of `n` items into for `pool` (its threads and the calling
/// thread), each at least `smallest` items; 1 without a pool.
pub fn parts_for(pool: Option<&TaskPool>, n: usize, smallest: usize) -> usize {
    let threads = pool.map_or(1, |pool| 4 * (pool.thread_num() + 1));
    threads.min(n / smallest.max(1)).max(1)
}

/// `slice` cut into `parts` consecutive pieces of nearly equal length.
pub fn pieces<T>(slice: &mut [T], parts: usize) -> impl Iterator<Item = &mut [T]> {
    slice.chunks_mut(piece_size(slice.len(), parts))
}

/// The indices of piece `item` of `n` items cut into `parts` as [`pieces`] cuts them (empty
/// past the last piece): for work that takes its pieces by number.
pub fn piece(n: usize, parts: usize, item: usize) -> core::ops::Range<usize> {
    let size = piece_size(n, parts);
    (item * size).min(n)..((item + 1) * size).min(n)
}

/// The length of every piece but the last of `n` items cut into `parts`.
fn piece_size(n: usize, parts: usize) -> usize {
    n.div_ceil(parts.max(1)).max(1)
}

mod disjoint;
mod phases;

pub(crate) use disjoint::Disjoint;
pub use phases::{Claims, run_phases};

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::tasks::TaskPoolBuilder;

    /// Every part runs exactly once, whatever the number of threads and parts.
    #[test]
    fn every_part_runs_once_on_any_number_of_threads() {
        for threads in [1usize, 2, 4] {
            let pool = TaskPoolBuilder::new().num_threads(threads).build();
            for parts in [1usize, 2, 13] {
                for _ in 0..20 {
                    let mut counts = vec![0u32; 101];
                    for_each_part(Some(&pool), pieces(&mut counts, parts), |part| {
                        for count in part {
                            *count += 1;
                        }
                    });
                    assert!(
                        counts.iter().all(|&n| n == 1),
                        "{threads} threads, {parts} parts"
                    );
                }
            }
            for_each_part(Some(&pool), core::iter::empty::<u32>(), |_| unreachable!());
        }
    }

    #[test]
    fn a_panicking_part_reaches_the_caller() {
        let pool = TaskPoolBuilder::new().num_threads(2).build();
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            for_each_part(Some(&pool), 0..8, |part| {
                if part == 5 {
                    panic!("part failed");
                }
            })
        }));
        assert!(result.is_err());
    }
}
