//! Progress and cancellation of an engine call ([`Control`]).

use crate::error::Error;
use crate::pipeline;
use crate::pipeline::stages::Stage;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

/// Progress and cancellation shared between a computation and whoever waits for it.
///
/// Progress is reported in 0‥1 of the current *span* ([`set_span`](Self::set_span)), a part
/// of the whole job: a job of several stages (a comparison re-running inverse dynamics at each
/// body mass) gives each stage its span, and the stage reports its own 0‥1 inside it. Every
/// field is an atomic: reporting allocates nothing and takes no lock.
#[derive(Debug)]
pub struct Control {
    cancel: AtomicBool,
    /// Progress of the whole job in parts per million.
    progress: AtomicU32,
    /// The current span: its start (high 32 bits) and end (low 32 bits) in parts per million.
    span: AtomicU64,
    /// How many times each pipeline stage ran (indexed by `Stage as usize`): what a
    /// recompute reran (issue 17 item 4), counted, not timed.
    stage_runs: [AtomicU32; STAGE_COUNT],
}

/// The number of [`Stage`]s.
pub const STAGE_COUNT: usize = pipeline::stages::STAGES.len();

impl Default for Control {
    fn default() -> Self {
        Self {
            cancel: AtomicBool::new(false),
            progress: AtomicU32::new(0),
            span: AtomicU64::new(PPM as u64),
            stage_runs: Default::default(),
        }
    }
}

/// Parts per million in one.
const PPM: u32 = 1_000_000;

fn ppm(f: f64) -> u32 {
    (f.clamp(0.0, 1.0) * f64::from(PPM)).round() as u32
}

impl Control {
    /// Asks the computation to stop at its next check.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
    /// True once [`cancel`](Self::cancel) was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
    /// Makes `from‥to` (parts of the whole job, 0‥1) the span that [`set_progress`]
    /// reports into, and moves the progress to `from`.
    ///
    /// [`set_progress`]: Self::set_progress
    pub fn set_span(&self, from: f64, to: f64) {
        let (a, b) = (ppm(from), ppm(to).max(ppm(from)));
        self.span
            .store((u64::from(a) << 32) | u64::from(b), Ordering::Relaxed);
        self.progress.store(a, Ordering::Relaxed);
    }
    /// The current span (0‥1 of the whole job).
    pub fn span(&self) -> (f64, f64) {
        let s = self.span.load(Ordering::Relaxed);
        let p = f64::from(PPM);
        (f64::from((s >> 32) as u32) / p, f64::from(s as u32) / p)
    }
    /// Records progress `f` in 0‥1 of the current span.
    pub fn set_progress(&self, f: f64) {
        let (from, to) = self.span();
        self.progress.store(
            ppm(from + (to - from) * f.clamp(0.0, 1.0)),
            Ordering::Relaxed,
        );
    }
    /// Progress of the whole job in 0‥1.
    pub fn progress(&self) -> f64 {
        f64::from(self.progress.load(Ordering::Relaxed)) / f64::from(PPM)
    }
    /// `Err(Cancelled)` once cancelled; engines call it in their loops.
    pub fn check(&self) -> Result<(), Error> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
    /// Counts one run of stage `s` (the pipeline's `done(Stage)` callback).
    pub fn done(&self, s: Stage) {
        self.stage_runs[s as usize].fetch_add(1, Ordering::Relaxed);
    }
    /// Forgets the stage runs counted so far: a preview's ([`Engine::preview_after`]), which
    /// the job's results do not count.
    ///
    /// [`Engine::preview_after`]: super::Engine::preview_after
    pub fn forget_stage_runs(&self) {
        for n in &self.stage_runs {
            n.store(0, Ordering::Relaxed);
        }
    }
    /// How many times each stage ran so far, indexed by `Stage as usize`.
    pub fn stage_runs(&self) -> [u32; STAGE_COUNT] {
        std::array::from_fn(|i| self.stage_runs[i].load(Ordering::Relaxed))
    }
    /// A progress callback for the library's loops (`keep_going(f) -> bool`): reports `f`
    /// mapped onto `from‥to` of the current span, and returns false once cancelled.
    pub fn stage(&self, from: f64, to: f64) -> impl FnMut(f64) -> bool + '_ {
        move |f| {
            self.set_progress(from + (to - from) * f);
            !self.is_cancelled()
        }
    }
}
