//! Errors, progress and interruption across the Python boundary: crate errors become the
//! exceptions of `mdrvisc.errors`; computations run on a rayon worker with the GIL released
//! while the calling thread serves Ctrl-C, and progress callbacks are served between chunks
//! of work.

use crate::error::Error;
use crate::monitor::Monitor;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Raises the matching exception class of `mdrvisc.errors`.
pub(crate) fn to_pyerr(py: Python<'_>, e: Error) -> PyErr {
    let errors = match py.import("mdrvisc.errors") {
        Ok(m) => m,
        Err(err) => return err,
    };
    let msg = e.to_string();
    let made = match &e {
        Error::InvalidInput(_) => errors
            .getattr("InvalidInputError")
            .and_then(|c| c.call1((msg,))),
        Error::NotConverged {
            iterations,
            residual,
            ..
        } => errors
            .getattr("ConvergenceError")
            .and_then(|c| c.call1((msg, *iterations, *residual))),
        Error::Domain(_) => errors.getattr("DomainError").and_then(|c| c.call1((msg,))),
        Error::Interrupted => return pyo3::exceptions::PyKeyboardInterrupt::new_err(msg),
    };
    match made {
        Ok(obj) => PyErr::from_value(obj),
        Err(err) => err,
    }
}

/// Serves an optional Python callback `progress(stage, done, total)` at most every 200 ms
/// (and at the end of each stage), and stops the computation when the callback raises or
/// the calling thread caught a signal (`run`).
pub(crate) struct PyMonitor {
    callback: Option<Py<PyAny>>,
    last: Instant,
    error: Option<PyErr>,
    cancel: Arc<AtomicBool>,
}

impl PyMonitor {
    pub(crate) fn new(callback: Option<Py<PyAny>>) -> Self {
        PyMonitor {
            callback,
            last: Instant::now(),
            error: None,
            cancel: Arc::new(AtomicBool::new(false)),
        }
    }

    /// Runs `f` with this monitor on a rayon worker, the GIL released, while the calling
    /// thread waits for it and checks for signals (Ctrl-C) every 50 ms; a signal stops `f` at
    /// its next progress report (on a worker already, `f` runs in place). Returns f's result,
    /// or the Python exception that stopped it.
    pub(crate) fn run<T: Send>(
        mut self,
        py: Python<'_>,
        f: impl FnOnce(&mut PyMonitor) -> crate::Result<T> + Send,
    ) -> PyResult<T> {
        if rayon::current_thread_index().is_some() {
            // Called from a worker (a progress callback that runs mdrvisc): run in place, as
            // waiting on this thread for a job of the same pool could deadlock.
            let r = py.detach(|| f(&mut self));
            return self.finish(py, r);
        }
        let pool = crate::pool::get().map_err(|e| to_pyerr(py, e))?;
        let cancel = Arc::clone(&self.cancel);
        let monitor = &mut self;
        let (r, signal) = py.detach(|| {
            let (tx, rx) = mpsc::channel();
            let mut signal = None;
            let r = pool.in_place_scope(|s| {
                s.spawn(move |_| {
                    // The receiver outlives the scope: the send cannot fail.
                    let _ = tx.send(f(monitor));
                });
                loop {
                    match rx.recv_timeout(Duration::from_millis(50)) {
                        Ok(r) => break r,
                        Err(RecvTimeoutError::Timeout) if signal.is_none() => {
                            if let Err(e) = Python::attach(|py| py.check_signals()) {
                                cancel.store(true, Ordering::Relaxed);
                                signal = Some(e);
                            }
                        }
                        Err(RecvTimeoutError::Timeout) => {}
                        // The job panicked: the scope re-raises the panic when it ends.
                        Err(RecvTimeoutError::Disconnected) => break Err(Error::Interrupted),
                    }
                }
            });
            (r, signal)
        });
        match signal {
            Some(e) => Err(e),
            None => self.finish(py, r),
        }
    }

    /// Converts the computation's result, preferring the Python exception that stopped it.
    fn finish<T>(self, py: Python<'_>, r: crate::Result<T>) -> PyResult<T> {
        match (r, self.error) {
            (Err(_), Some(e)) => Err(e),
            (r, _) => r.map_err(|e| to_pyerr(py, e)),
        }
    }
}

impl Monitor for PyMonitor {
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> crate::Result<()> {
        if self.cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        if done < total && self.last.elapsed() < Duration::from_millis(200) {
            return Ok(());
        }
        self.last = Instant::now();
        let outcome = Python::attach(|py| -> PyResult<()> {
            py.check_signals()?;
            if let Some(cb) = &self.callback {
                cb.call1(py, (stage, done, total))?;
            }
            Ok(())
        });
        outcome.map_err(|e| {
            self.error = Some(e);
            Error::Interrupted
        })
    }
}

/// Runs `f` on a worker of the crate's pool with the GIL released and waits for it: its
/// parallel loops then split among the workers without waking the calling thread each time
/// (for short computations that serve no progress callback; the others use
/// `PyMonitor::run`).
pub(crate) fn in_pool<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| crate::pool::run(f))
        .map_err(|e| to_pyerr(py, e))
}
