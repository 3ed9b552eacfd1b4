//! A frame's work as phases of independent items, on the pool's threads under one scope.
//!
//! A cloth's substeps are many short passes (springs of the even bands, of the odd bands, the
//! stretch limit, the per-particle pass, six times a frame), each well under a millisecond.
//! A scope per pass costs more than the pass on all but the largest cloths: the pool's
//! threads are woken and waited for every time. Here the calling thread and the pool's
//! threads (no more of them than the machine has cores besides the caller's) go through all
//! the passes of the frame under one scope, each taking the items of a phase one at a time
//! from a shared count, and an item waits only until every item of the phases before its own
//! has finished. A thread that wakes late joins where the work has got to; the calling thread
//! never waits for one that has not started, it does the work itself.
//!
//! The calling thread takes a phase's items from the front and the pool's threads from the
//! back, so on two cores each keeps to its end of the cloth from pass to pass, and its part
//! of the particles stays in its own cache.
//!
//! No thread waits for an item that nobody runs: a thread moves on to a phase only once
//! every item of the phase before it is taken, so every item it waits for is held by a
//! running thread, which itself waits only for earlier items. Which thread runs an item
//! never changes what the item computes, so results do not depend on the number of threads.

use bevy::tasks::TaskPool;
use core::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

/// Spins before a waiting thread starts yielding its core to others.
const SPINS_BEFORE_YIELD: u32 = 1 << 12;

/// Runs `work(phase, item)` for every item of every phase (`sizes[phase]` items; a phase of
/// none is skipped): the items of a phase in any order and on any thread, each phase only
/// after every item of the phases before it has finished. On `pool`'s threads and this one
/// when a pool is given, the crate is built with `parallel` and the machine has more than one
/// core; else in order on this thread.
/// `claims`: scratch for counting the items taken, kept between calls so a frame allocates
/// nothing.
pub fn run_phases(
    pool: Option<&TaskPool>,
    sizes: &[usize],
    claims: &mut Claims,
    work: impl Fn(usize, usize) + Sync,
) {
    let total: usize = sizes.iter().sum();
    let helpers = pool.map_or(0, helpers);
    let Some(pool) = pool.filter(|_| cfg!(feature = "parallel") && helpers > 0 && total > 1) else {
        for (phase, &items) in sizes.iter().enumerate() {
            (0..items).for_each(|item| work(phase, item));
        }
        return;
    };
    let claims = claims.reset(sizes.len());
    let done = AtomicUsize::new(0);
    let worker = |end: End| {
        let mut start = 0;
        for (phase, (&items, claim)) in sizes.iter().zip(claims).enumerate() {
            while let Some(item) = end.take(claim, items) {
                wait_for(&done, start);
                // Counted as finished even if `work` panics, so no thread waits for it
                // forever; the panic reaches the caller when the scope ends.
                let _finished = Finished(&done);
                work(phase, item);
            }
            start += items;
        }
    };
    pool.scope(|scope| {
        for _ in 0..helpers {
            scope.spawn(async { worker(End::Back) });
        }
        worker(End::Front);
    });
}

/// Pool threads to ask in beside the calling thread: the pool's, but no more than the
/// machine's cores less the caller's. A thread waiting for a phase spins, so a third thread
/// on two cores takes turns from the two doing the work, and each phase then waits for
/// whichever was switched out (on the 2-core machine, a 256 x 256 cloth's dynamics with a
/// 2-thread pool, medians of three alternated runs: 4.50 ms a frame with three threads, 3.69
/// with two).
pub(super) fn helpers(pool: &TaskPool) -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    let cores = *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    pool.thread_num().min(cores.saturating_sub(1))
}

/// Scratch for [`run_phases`]: how many items of each phase have been taken. Kept between
/// calls so a frame allocates nothing; a clone starts empty.
#[derive(Debug, Default)]
pub struct Claims(Vec<AtomicU64>);

impl Clone for Claims {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Claims {
    /// Counters for `phases` phases, all at zero.
    fn reset(&mut self, phases: usize) -> &[AtomicU64] {
        if self.0.len() < phases {
            self.0.resize_with(phases, AtomicU64::default);
        }
        let claims = &self.0[..phases];
        for claim in claims {
            claim.store(0, Ordering::Relaxed);
        }
        claims
    }
}

/// Which end of a phase's items a thread takes from: the calling thread from the front,
/// the pool's from the back, so that with two threads each keeps to its own part of the
/// data from one phase to the next (the first bands of a cloth and their particles on one
/// core, the last ones on the other) instead of pulling it across.
#[derive(Clone, Copy)]
enum End {
    Front,
    Back,
}

impl End {
    /// Takes the next item from this end of a phase of `items` items whose claims are
    /// counted in `claim` (taken from the front in the low 32 bits, from the back in the
    /// high ones); `None` once every item is taken.
    fn take(self, claim: &AtomicU64, items: usize) -> Option<usize> {
        let before = claim.fetch_add(
            match self {
                End::Front => 1,
                End::Back => 1 << 32,
            },
            Ordering::Relaxed,
        );
        let (front, back) = ((before & 0xffff_ffff) as usize, (before >> 32) as usize);
        (front + back < items).then(|| match self {
            End::Front => front,
            End::Back => items - 1 - back,
        })
    }
}

/// Counts one item as finished when dropped.
struct Finished<'a>(&'a AtomicUsize);

impl Drop for Finished<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::Release);
    }
}

/// Waits until `done` reaches `count`: spinning, then giving the core away between looks.
fn wait_for(done: &AtomicUsize, count: usize) {
    let mut spins = 0;
    while done.load(Ordering::Acquire) < count {
        if spins < SPINS_BEFORE_YIELD {
            spins += 1;
            core::hint::spin_loop();
        } else {
            std::thread::yield_now();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::tasks::TaskPoolBuilder;
    use std::sync::Mutex;

    /// Each phase's items see every item of the earlier phases finished and none of the later
    /// ones started, whatever the number of threads; every item runs exactly once.
    #[test]
    fn phases_run_in_order_and_every_item_once() {
        let sizes = [3usize, 0, 1, 7, 2, 0, 5, 1];
        let total: usize = sizes.iter().sum();
        for threads in [1usize, 2, 4] {
            let pool = TaskPoolBuilder::new().num_threads(threads).build();
            for _ in 0..50 {
                let finished: Vec<AtomicUsize> =
                    sizes.iter().map(|_| AtomicUsize::new(0)).collect();
                let runs = Mutex::new(vec![0u32; total]);
                run_phases(
                    Some(&pool),
                    &sizes,
                    &mut Claims::default(),
                    |phase, item| {
                        for (earlier, count) in finished.iter().enumerate() {
                            let count = count.load(Ordering::Acquire);
                            if earlier < phase {
                                assert_eq!(count, sizes[earlier], "phase {phase} began early");
                            } else if earlier > phase {
                                assert_eq!(count, 0, "phase {earlier} began before {phase} ended");
                            }
                        }
                        let first: usize = sizes[..phase].iter().sum();
                        runs.lock().unwrap()[first + item] += 1;
                        std::thread::yield_now();
                        finished[phase].fetch_add(1, Ordering::Release);
                    },
                );
                assert!(runs.into_inner().unwrap().iter().all(|&n| n == 1));
            }
        }
    }

    #[test]
    fn without_a_pool_items_run_in_order() {
        let order = Mutex::new(Vec::new());
        run_phases(None, &[2, 0, 3], &mut Claims::default(), |phase, item| {
            order.lock().unwrap().push((phase, item))
        });
        assert_eq!(
            order.into_inner().unwrap(),
            [(0, 0), (0, 1), (2, 0), (2, 1), (2, 2)]
        );
    }

    #[test]
    fn a_panicking_item_reaches_the_caller_instead_of_stalling_the_others() {
        let pool = TaskPoolBuilder::new().num_threads(2).build();
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            run_phases(
                Some(&pool),
                &[2, 2, 2],
                &mut Claims::default(),
                |phase, item| {
                    if phase == 0 && item == 1 {
                        panic!("item failed");
                    }
                },
            )
        }));
        assert!(result.is_err());
    }
}
