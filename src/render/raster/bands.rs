//! Two threads for a big frame: the canvas cut into two bands of rows, and independent
//! passes run side by side, on a small pool of the renderer's own.
//!
//! Every dot is computed by the same arithmetic whichever band holds it (the kernels take
//! the index of their buffers' first dot, `origin`, and keep absolute rows), and passes run
//! side by side write buffers of their own that are joined in the sequential order: a frame
//! drawn in bands is the same, bit for bit, as one drawn on one thread (tested).
//!
//! The pool is the renderer's own, not rayon's global one: the editor draws while a bind
//! or the levels of detail keep the global pool busy, and a frame must not wait behind
//! them. A renderer already running on a rayon thread (a batch of pictures, `render --all`)
//! draws on that thread alone: its callers are parallel already.

use std::sync::OnceLock;

/// Triangles from which a frame's big passes are worth a second thread (a handful of
/// microseconds to hand work over, against about 30 ns a triangle and pass).
pub(super) const PARALLEL_TRIANGLES: usize = 16_384;

/// Threads of the renderer's pool: two bands, or two passes side by side.
const THREADS: usize = 2;

/// The renderer's pool, made at its first use (`None` when no thread can be made: the
/// frame is then drawn on the caller's thread).
fn pool() -> Option<&'static rayon::ThreadPool> {
    static POOL: OnceLock<Option<rayon::ThreadPool>> = OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(THREADS)
            .thread_name(|i| format!("grimace-render-{i}"))
            .build()
            .ok()
    })
    .as_ref()
}

/// Whether a frame of `triangles` triangles runs on two threads: big enough (at least
/// `min`), and not already on a rayon thread.
pub(super) fn parallel(triangles: usize, min: usize) -> bool {
    triangles >= min && rayon::current_thread_index().is_none() && pool().is_some()
}

/// Runs `a` and `b` side by side on the renderer's pool when `parallel`, else one after
/// the other on this thread.
pub(super) fn join<RA: Send, RB: Send>(
    parallel: bool,
    a: impl FnOnce() -> RA + Send,
    b: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    match pool().filter(|_| parallel) {
        Some(pool) => pool.join(a, b),
        None => (a(), b()),
    }
}

/// The row where the second band starts on a canvas of `height` rows: the middle when the
/// frame runs in two bands, else `height` (one band of every row).
pub(super) fn split_row(height: usize, parallel: bool) -> usize {
    if parallel {
        height / 2
    } else {
        height
    }
}

/// A band of rows `rows.0..rows.1` of a canvas `width` dots wide: its buffers start at the
/// canvas's dot `origin` (= `rows.0 * width`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Band {
    pub rows: (usize, usize),
    pub width: usize,
}

impl Band {
    /// The two bands of a `width` x `height` canvas split at row `split`.
    pub fn pair(width: usize, height: usize, split: usize) -> [Band; 2] {
        [(0, split), (split, height)].map(|rows| Band { rows, width })
    }

    /// The index of the band's first dot in the canvas's buffers.
    pub fn origin(&self) -> usize {
        self.rows.0 * self.width
    }

    /// The dots of the band in a canvas buffer's prefix: where the second band starts.
    pub fn cut(&self) -> usize {
        self.rows.1 * self.width
    }

    /// The box `[x0, x1, y0, y1]` cut to the band's rows (empty when it misses them).
    #[inline]
    pub fn clip(&self, [x0, x1, y0, y1]: [usize; 4]) -> [usize; 4] {
        [x0, x1, y0.max(self.rows.0), y1.min(self.rows.1)]
    }
}
