//! Stages 5–7 of a take: channels → q, unwrapped (Euler branches and turns), smoothed, then v
//! and a. Coordinates are worked on as columns (one contiguous run of frames per coordinate,
//! a joint's coordinates side by side), joints and frames in parallel ([`super::par`]); every
//! column and every frame computes what the serial path computes, in the same order, so the
//! results do not depend on the number of threads.
//!
//! Where each part lives: here the stage functions and the column layout they share;
//! `continuity.rs` (Euler triples re-picked to be continuous, passages near gimbal lock and
//! glitches noted), `smooth.rs` (unwrapping and smoothing, groups of columns in parallel),
//! `derivatives.rs` (v and a by differences on the configuration manifold).

mod continuity;
mod derivatives;
mod smooth;

pub use continuity::make_euler_triples_continuous;
pub use derivatives::derivatives;
pub use smooth::{unwrap_and_smooth, unwrap_and_smooth_with};

use super::States;
use super::stages::Stage;
use crate::error::Error;
use crate::io::bvh::Bvh;
use crate::model::Model;
use crate::model::bvh::BvhMap;
use crate::motion::smooth::SmoothSpec;
use crate::par::{self, for_each_block};
use continuity::euler_continuity;
use derivatives::{EulerRates, derivative_columns};
use smooth::{smooth_columns, unwrap_revolute};

/// Stages 5–7: channels → q (unwrapped), smoothed, then v and a.
pub fn take_states(
    bvh: &Bvh,
    model: &Model,
    map: &BvhMap,
    smooth: &SmoothSpec,
) -> Result<States, Error> {
    take_states_with(bvh, model, map, smooth, &mut |_| true).map(|(s, _)| s)
}

/// [`take_states`] with progress and cancel ([`unwrap_and_smooth_with`]; the derivatives are
/// the last tenth), and a note for each euler joint that passes near gimbal lock or jumps
/// ([`make_euler_triples_continuous`]).
pub fn take_states_with(
    bvh: &Bvh,
    model: &Model,
    map: &BvhMap,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<(States, Vec<String>), Error> {
    take_states_marked(bvh, model, map, smooth, keep_going, &mut |_| {})
}

/// [`take_states_with`] that calls `done` at the end of each of its stages
/// ([`Stage::Coordinates`], [`Stage::Unwrap`], [`Stage::Smooth`], [`Stage::Derivatives`]).
pub fn take_states_marked(
    bvh: &Bvh,
    model: &Model,
    map: &BvhMap,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
    done: &mut dyn FnMut(Stage),
) -> Result<(States, Vec<String>), Error> {
    let n = bvh.frames;
    let mut cols = Columns {
        frames: n,
        data: crate::motion::take::q_columns(bvh, model, map),
    };
    done(Stage::Coordinates);
    let dt = bvh.frame_time;
    let triples = model.euler_triples();
    let mut notes = euler_continuity(bvh, map, &mut cols);
    unwrap_revolute(model, &mut cols);
    done(Stage::Unwrap);
    // the euler joints' v and a are made with their smoothing, from the smoothed rotations
    let mut rates = EulerRates::new(model.nv, n);
    smooth_columns(
        model,
        &triples,
        &mut cols,
        dt,
        smooth,
        Some(&mut rates),
        &mut |f| keep_going(0.9 * f),
    )?;
    done(Stage::Smooth);
    if !keep_going(0.9) {
        return Err(Error::Cancelled);
    }
    let (v, a, locked) = derivative_columns(model, &triples, &cols, Some(rates), dt);
    notes.extend(locked.iter().map(|&(b, frames)| {
        let joint = bvh_joint_name(bvh, map, model.idx_q[b]);
        format!(
            "`{joint}` reaches gimbal lock at {frames} frame(s) (its middle angle within \
             0.00001° of ±90°): there its rates cannot come from its rotation, so its \
             velocities and accelerations are its angles' differences, which may spike; use \
             the ball joint model (`--joints ball`, `set joints ball`)"
        )
    }));
    let states = States {
        time: (0..n).map(|k| bvh.time(k)).collect(),
        q: cols.rows(),
        v: v.rows(),
        a: a.rows(),
    };
    done(Stage::Derivatives);
    Ok((states, notes))
}

/// The name of the BVH joint whose rotation channel sets coordinate `iq` (an euler joint's
/// first hinge).
fn bvh_joint_name<'a>(bvh: &'a Bvh, map: &BvhMap, iq: usize) -> &'a str {
    map.joints
        .iter()
        .position(|jm| jm.channels.iter().any(|c| c.q == Some(iq)))
        .map_or("?", |j| bvh.joints[j].name.as_str())
}

/// Frames per tile of [`Columns::rows`]: a column's tile is four cache lines read in one run
/// (fewer page walks than one line per column and tile), the tile 24 kB on a 96-coordinate
/// model, in the first-level cache.
const TILE: usize = 32;

/// Configurations stored by coordinate: column `j` (every frame of coordinate `j`) is
/// `data[j·frames .. (j+1)·frames]`, so a joint's coordinates are one contiguous slice.
struct Columns {
    frames: usize,
    data: Vec<f64>,
}

impl Columns {
    /// The columns of `rows` (`frames × nq`), filled in parallel.
    fn of_rows(rows: &[Vec<f64>], nq: usize) -> Self {
        let frames = rows.len();
        let mut data = vec![0.0; nq * frames];
        if frames > 0 {
            let block = frames * par::even_block(nq);
            for_each_block(
                &mut data,
                block,
                &mut par::scratch(|| ()),
                |_, first, chunk| {
                    for (c, col) in chunk.chunks_mut(frames).enumerate() {
                        let j = first / frames + c;
                        for (x, row) in col.iter_mut().zip(rows) {
                            *x = row[j];
                        }
                    }
                },
            );
        }
        Self { frames, data }
    }

    /// Writes the columns back into `rows`, in parallel over frames; within a worker's frames,
    /// a few dozen rows at a time, column by column (each column read in one run while those
    /// rows stay in the cache).
    fn to_rows(&self, rows: &mut [Vec<f64>]) {
        const ROWS_AT_ONCE: usize = 32;
        let (n, data) = (self.frames, &self.data);
        let block = par::even_block(rows.len());
        for_each_block(rows, block, &mut par::scratch(|| ()), |_, first, chunk| {
            for (b, some) in chunk.chunks_mut(ROWS_AT_ONCE).enumerate() {
                let k0 = first + b * ROWS_AT_ONCE;
                let width = some.first().map_or(0, Vec::len);
                for j in 0..width {
                    let col = &data[j * n + k0..j * n + k0 + some.len()];
                    for (row, x) in some.iter_mut().zip(col) {
                        row[j] = *x;
                    }
                }
            }
        });
    }

    /// The rows (`frames × columns`), made in parallel over frames: each worker copies a tile
    /// of [`TILE`] frames of every column into its scratch,
    /// then gathers each row from the tile into the row's own allocation, made beforehand on
    /// the calling thread (no zero-filling of rows that are then overwritten).
    fn rows(&self) -> Vec<Vec<f64>> {
        let (n, data) = (self.frames, &self.data);
        let width = data.len().checked_div(n).unwrap_or(0);
        // allocated here, filled by the workers within their capacity: rows a worker
        // allocated would come from its own malloc arena, whose pages are given back and
        // faulted in again at every take (twice the page faults with two threads)
        let mut rows: Vec<Vec<f64>> = (0..n).map(|_| Vec::with_capacity(width)).collect();
        if width == 0 {
            return rows;
        }
        let block = par::even_block(n);
        let mut scratch = par::scratch(|| vec![[0.0; TILE]; width]);
        for_each_block(&mut rows, block, &mut scratch, |tile, first, chunk| {
            for (b, some) in chunk.chunks_mut(TILE).enumerate() {
                let k0 = first + b * TILE;
                let m = some.len();
                // tile[j][d] = column j at frame k0 + d (a full tile by fixed-size copies)
                let columns = tile.iter_mut().zip(data.chunks_exact(n));
                if m == TILE {
                    for (t, col) in columns {
                        *t = col[k0..k0 + TILE].try_into().expect("a full tile");
                    }
                } else {
                    for (t, col) in columns {
                        t[..m].copy_from_slice(&col[k0..k0 + m]);
                    }
                }
                for (d, row) in some.iter_mut().enumerate() {
                    row.extend(tile.iter().map(|t| t[d]));
                }
            }
        });
        rows
    }

    /// Column `j`.
    fn col(&self, j: usize) -> &[f64] {
        &self.data[j * self.frames..(j + 1) * self.frames]
    }

    /// One mutable slice per column.
    fn each_mut(&mut self) -> Vec<Option<&mut [f64]>> {
        if self.frames == 0 {
            return vec![];
        }
        self.data.chunks_mut(self.frames).map(Some).collect()
    }
}
