//! What a bake reports to its caller and asks of it while it runs: rows done, and whether
//! to go on. The layouts' bake loops call it from worker threads.

/// Progress and cancellation of one bake, shared by the worker threads that bake its rows.
///
/// Any `Fn() + Sync` closure is one (its call counts a row, and it never cancels), so a
/// caller with no use for cancellation passes `&|| {}` or its progress bar's callback.
pub trait BakeProgress: Sync {
    /// One row of work is done (as many rows in all as the layout's `bake_rows`).
    fn row_done(&self);
    /// Whether the caller no longer wants the result: the rows not yet started are skipped,
    /// and the bake returns `BakeError::Cancelled` instead of a table.
    fn cancelled(&self) -> bool {
        false
    }
}

impl<F: Fn() + Sync> BakeProgress for F {
    fn row_done(&self) {
        self()
    }
}

/// A row of `width` values: `row()` unless the bake is cancelled, else zeros without the
/// work, so that a cancelled bake's remaining rows cost next to nothing and the planes keep
/// their sizes.
pub(crate) fn row_unless_cancelled(
    progress: &dyn BakeProgress,
    width: usize,
    row: impl FnOnce() -> Vec<f64>,
) -> Vec<f64> {
    if progress.cancelled() {
        return vec![0.0; width];
    }
    let values = row();
    progress.row_done();
    values
}
