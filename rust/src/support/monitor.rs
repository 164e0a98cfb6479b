//! Progress reports and cancellation between chunks of work.

use crate::support::error::Result;

/// Receives progress from long computations and may stop them by returning an error
/// (e.g. `Error::Interrupted`). Called from the thread that started the computation,
/// never from rayon workers.
pub trait Monitor {
    /// `done` of `total` units of `stage` are finished.
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> Result<()>;
}

/// A monitor that reports nothing and never stops.
pub struct Silent;

impl Monitor for Silent {
    fn progress(&mut self, _stage: &str, _done: usize, _total: usize) -> Result<()> {
        Ok(())
    }
}
