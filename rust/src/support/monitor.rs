//! Progress reports and cancellation between chunks of work.

use crate::support::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Receives progress from long computations and may stop them by returning an error
/// (e.g. `Error::Interrupted`). Called from the thread that started the computation,
/// never from rayon workers.
pub trait Monitor {
    /// `done` of `total` units of `stage` are finished.
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> Result<()>;

    /// The stop request of this computation, for the loops that run on other threads (the
    /// workers of a parallel loop) and cannot report progress; by default one never made.
    fn stop(&self) -> Stop {
        Stop::default()
    }
}

/// A request to stop one computation, shared by every thread that runs part of it: made
/// once (`request`), polled by `check` in long loops.
#[derive(Debug, Clone, Default)]
pub struct Stop(Arc<AtomicBool>);

impl Stop {
    /// Asks every holder of this request to stop.
    pub fn request(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// `Error::Interrupted` once a stop was requested.
    pub fn check(&self) -> Result<()> {
        if self.0.load(Ordering::Relaxed) {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    }
}

/// A monitor that reports nothing and never stops.
pub struct Silent;

impl Monitor for Silent {
    fn progress(&mut self, _stage: &str, _done: usize, _total: usize) -> Result<()> {
        Ok(())
    }
}
