//! Frames and coordinates in parallel (rayon), with results bit-identical to the serial path.
//! A utility every layer may use (as `spatial`): the pipeline's stages, the ground-reaction
//! estimate.
//!
//! Work is cut into blocks (a run of frames, a joint's coordinates) that are independent of
//! one another, so each block computes the same floating-point operations in the same order
//! whatever thread runs it. Each worker slot owns its scratch (a `Workspace`, a `Smoother`),
//! made once per call by the caller, never per block. The blocks go in rounds of one block per
//! slot; between rounds, on the calling thread, the caller's progress callback is told of every
//! block of the round in order, and stops the work when it says so — so a front end's progress
//! and cancel work as on the serial path. With one slot (`--threads 1`, or a one-thread pool)
//! no rayon call is made: the blocks run in a plain loop on the calling thread.

use rayon::prelude::*;

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
/// may be shorter; `first` is the index of the block's first item), `scratch.len()` blocks at
/// a time in parallel. After each round, `report(first)` is called for each of its blocks in
/// order; when it returns false the work stops and the result is `first` of that block (the
/// items before it are computed; later ones may be too, and are to be dropped). Returns
/// `items.len()` when every report said go on.
pub fn rounds<T: Send, S: Send>(
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
    let per_round = block * scratch.len();
    for (r, round) in items.chunks_mut(per_round).enumerate() {
        let start = r * per_round;
        round
            .par_chunks_mut(block)
            .zip(scratch.par_iter_mut())
            .enumerate()
            .for_each(|(b, (chunk, s))| work(s, start + b * block, chunk));
        for first in (start..start + round.len()).step_by(block) {
            if !report(first) {
                return first;
            }
        }
    }
    n
}

/// [`rounds`] without progress: every item computed.
pub fn for_each_block<T: Send, S: Send>(
    items: &mut [T],
    block: usize,
    scratch: &mut [S],
    work: impl Fn(&mut S, usize, &mut [T]) + Sync,
) {
    rounds(items, block, scratch, work, &mut |_| true);
}

/// Blocks of about `items / slots` items, so that a call without progress is one round.
pub fn even_block(items: usize) -> usize {
    items.div_ceil(slots()).max(1)
}
