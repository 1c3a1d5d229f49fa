//! How long work reports its progress: an observer the caller supplies. The library
//! never draws anything; the command line turns these calls into a progress bar, and
//! tests and library users pass [`Silent`].

/// Receives progress of a run (samples written) or of a batch (cases finished). Called
/// from worker threads in parallel batches, hence `Sync` and `&self`.
pub trait Progress: Sync {
    /// Work of `total` units starts (samples of a run, cases of a batch).
    fn begin(&self, _total: u64) {}
    /// `done` units are finished so far.
    fn set(&self, _done: u64) {}
    /// `n` more units are finished.
    fn inc(&self, _n: u64) {}
    /// The work ended (completed, failed or stopped).
    fn finish(&self) {}
    /// True when the caller asks the work to stop (Ctrl-C on the command line): a run
    /// stops before its next output sample and keeps what it computed (status
    /// `interrupted`); a batch starts no further case. Polled, so it must be cheap.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {}

/// Passes only the caller's stop request on: a run inside a batch stops with the batch
/// (status `interrupted`) but reports no progress of its own.
#[derive(Clone, Copy)]
pub struct StopOnly<'a>(pub &'a dyn Progress);

impl Progress for StopOnly<'_> {
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}
