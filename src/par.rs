//! Frames and coordinates in parallel (rayon), with results bit-identical to the serial path.
//! A utility every layer may use (as `spatial`): the pipeline's stages, the ground-reaction
//! estimate.
//!
//! Work is cut into blocks (a run of frames, a joint's coordinates) that are independent of
//! one another, so each block computes the same floating-point operations in the same order
//! whatever thread runs it. Each worker slot owns its scratch (a `Workspace`, a `Smoother`),
//! made once per call by the caller, never per block. Each worker takes the next block as
//! soon as it is done with one, so blocks of unequal cost keep every worker busy. The caller's
//! progress callback is told of every finished block in order, on the calling thread, and stops
//! the work when it says so — so a front end's progress and cancel work as on the serial path.
//! With one slot (`--threads 1`, or a one-thread pool) no rayon call is made: the blocks run in
//! a plain loop on the calling thread.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

/// Worker slots to use: the threads of the current rayon pool (the global pool is sized by
/// `articula --threads N`, default all cores), at least one.
pub fn slots() -> usize {
    rayon::current_num_threads().max(1)
}

/// `scratch` for each of [`slots`] workers.
pub fn scratch<S>(make: impl Fn() -> S) -> Vec<S> {
    (0..slots()).map(|_| make()).collect()
}

/// Runs `work(scratch, first, block)` over `items` cut into blocks of `block` items (the last
/// may be shorter; `first` is the index of the block's first item), on `scratch.len()` workers
/// at once, each owning one scratch for the whole call and taking the next block as soon as it
/// is done with one. `report(first)` is called on the calling thread for every block, in
/// order, once the blocks up to it are finished; when it returns false the workers take no
/// more blocks and the result is `first` of that block (the items before it are computed;
/// later ones may be too, and are to be dropped). Returns `items.len()` when every report said
/// go on.
///
/// A caller outside the pool (the command line's main thread, the workbench's worker) waits
/// while the pool's threads work, and reports as their blocks finish: a caller that worked
/// too would leave one pool thread idle, and asleep when the next stage needs it (two threads,
/// minute take: the next parse took 7 ms instead of 4.3, in half the runs). A caller inside
/// the pool is one of the workers, so that nested calls never wait on threads that are all
/// waiting themselves.
pub fn for_each_block_reporting<T: Send, S: Send>(
    items: &mut [T],
    block: usize,
    scratch: &mut [S],
    work: impl Fn(&mut S, usize, &mut [T]) + Sync,
    report: &mut dyn FnMut(usize) -> bool,
) -> usize {
    let block = block.max(1);
    let n = items.len();
    if scratch.len() <= 1 {
        // the serial path
        let s = &mut scratch[0];
        for (b, chunk) in items.chunks_mut(block).enumerate() {
            let first = b * block;
            if !report(first) {
                return first;
            }
            work(s, first, chunk);
        }
        return n;
    }
    in_parallel(items, block, scratch, work, report)
}

/// [`for_each_block_reporting`] on two or more workers.
fn in_parallel<T: Send, S: Send>(
    items: &mut [T],
    block: usize,
    scratch: &mut [S],
    work: impl Fn(&mut S, usize, &mut [T]) + Sync,
    report: &mut dyn FnMut(usize) -> bool,
) -> usize {
    let n = items.len();
    let next = Mutex::new(items.chunks_mut(block).enumerate());
    let stop = AtomicBool::new(false);
    // the next block not yet taken, unless told to stop
    let take = || {
        if stop.load(Ordering::Relaxed) {
            return None;
        }
        next.lock().unwrap_or_else(|e| e.into_inner()).next()
    };
    // takes blocks until none is left, telling `done` of each
    let blocks = |s: &mut S, done: &mut dyn FnMut(usize)| {
        while let Some((b, chunk)) = take() {
            work(s, b * block, chunk);
            done(b);
        }
    };
    let mut progress = Progress {
        done: vec![false; n.div_ceil(block)],
        reported: 0,
        block,
        stopped_at: None,
        report,
    };
    let (finished, news) = mpsc::channel::<usize>();
    rayon::in_place_scope(|scope| {
        // a caller outside the pool waits for the workers and tells `report` as their blocks
        // finish; a caller inside it (a pool thread) is one of the workers, so that a pool
        // whose every thread is such a caller still gets the work done
        let (caller, workers) = if rayon::current_thread_index().is_some() {
            let (mine, others) = scratch.split_at_mut(1);
            (mine.first_mut(), others)
        } else {
            (None, scratch)
        };
        for s in workers {
            let finished = finished.clone();
            let blocks = &blocks;
            // the caller may have stopped listening: the block is then dropped anyway
            scope.spawn(move |_| {
                blocks(s, &mut |b| {
                    let _ = finished.send(b);
                })
            });
        }
        drop(finished);
        match caller {
            Some(s) => blocks(s, &mut |b| {
                progress.finish(b);
                while let Ok(b) = news.try_recv() {
                    progress.finish(b);
                }
                progress.tell(&stop);
            }),
            None => {
                // ends when every worker has ended (each drops its sender)
                while let Ok(b) = news.recv() {
                    progress.finish(b);
                    progress.tell(&stop);
                }
            }
        }
    });
    while let Ok(b) = news.try_recv() {
        progress.finish(b);
    }
    progress.tell(&stop);
    progress.stopped_at.unwrap_or(n)
}

/// Which blocks of [`for_each_block_reporting`] are finished, and how far `report` has been
/// told of them, in order.
struct Progress<'r> {
    done: Vec<bool>,
    reported: usize,
    block: usize,
    stopped_at: Option<usize>,
    report: &'r mut dyn FnMut(usize) -> bool,
}

impl Progress<'_> {
    fn finish(&mut self, b: usize) {
        self.done[b] = true;
    }

    /// Tells `report` of every block finished in order since the last call, until it says
    /// stop (then `stop` is set, and no block is told again).
    fn tell(&mut self, stop: &AtomicBool) {
        while self.stopped_at.is_none()
            && self.reported < self.done.len()
            && self.done[self.reported]
        {
            let first = self.reported * self.block;
            if !(self.report)(first) {
                self.stopped_at = Some(first);
                stop.store(true, Ordering::Relaxed);
            }
            self.reported += 1;
        }
    }
}

/// [`for_each_block_reporting`] without progress: every item computed.
pub fn for_each_block<T: Send, S: Send>(
    items: &mut [T],
    block: usize,
    scratch: &mut [S],
    work: impl Fn(&mut S, usize, &mut [T]) + Sync,
) {
    for_each_block_reporting(items, block, scratch, work, &mut |_| true);
}

/// Blocks of about `items / slots` items: one block per worker.
pub fn even_block(items: usize) -> usize {
    items.div_ceil(slots()).max(1)
}

#[cfg(test)]
mod tests {
    //! Every block is worked on once with its own index, the reports come in order, a report
    //! that says stop stops the work at its block, from a caller outside the pool (which waits)
    //! and from one inside it (which works), also when every pool thread is such a caller.
    use super::*;

    /// `for_each_block_reporting` over 1,000 items in blocks of 7 on `slots` scratches, the
    /// report saying stop at item `stop_at` (a block's first item); each item written with its
    /// index by whichever worker took its block. Returns the result, the items and the reports.
    fn run(slots: usize, stop_at: Option<usize>) -> (usize, Vec<Option<usize>>, Vec<usize>) {
        let mut items = vec![None; 1000];
        let mut scratch: Vec<usize> = (0..slots).collect();
        let mut reports = vec![];
        let reached = for_each_block_reporting(
            &mut items,
            7,
            &mut scratch,
            |_, first, block| {
                for (i, x) in block.iter_mut().enumerate() {
                    // blocks of unequal cost
                    std::hint::black_box((0..(first + i) % 97 * 50).sum::<usize>());
                    *x = Some(first + i);
                }
            },
            &mut |first| {
                reports.push(first);
                Some(first) != stop_at
            },
        );
        (reached, items, reports)
    }

    fn check(slots: usize) {
        let (reached, items, reports) = run(slots, None);
        assert_eq!(reached, 1000);
        assert!(items.iter().enumerate().all(|(i, x)| *x == Some(i)));
        assert_eq!(reports, (0..1000).step_by(7).collect::<Vec<_>>());
        let (reached, items, reports) = run(slots, Some(490));
        assert_eq!(reached, 490);
        assert!(items[..490].iter().enumerate().all(|(i, x)| *x == Some(i)));
        assert_eq!(reports, (0..=490).step_by(7).collect::<Vec<_>>());
    }

    #[test]
    fn every_block_once_reports_in_order_and_stop_stops_outside_and_inside_the_pool() {
        // the serial path, then two and three workers from outside the pool
        for slots in [1, 2, 3] {
            check(slots);
        }
        // from inside a pool of two, and from both its threads at once
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| check(2));
        pool.install(|| rayon::join(|| check(2), || check(2)));
    }
}
