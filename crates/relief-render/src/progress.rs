//! How long work reports its progress to a front end (a progress bar, or nothing).

/// Receives the progress of long work: a stage begun, items done, the stage ended.
pub trait Progress: Sync {
    /// A stage of `total` items (`None`: an amount not known ahead) named `what` begins.
    fn begin(&self, what: &str, total: Option<u64>);
    /// `n` more items are done.
    fn advance(&self, n: u64);
    /// `done` items are done in all.
    fn set(&self, done: u64);
    /// The stage ended.
    fn end(&self);
}

/// Progress nobody watches.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {
    fn begin(&self, _what: &str, _total: Option<u64>) {}
    fn advance(&self, _n: u64) {}
    fn set(&self, _done: u64) {}
    fn end(&self) {}
}
